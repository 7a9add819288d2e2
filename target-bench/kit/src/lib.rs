//! What the on-target benchmark's firmware and its host runner share (`target-bench/`, see
//! BENCHMARKS.md, section "On the target"): where QEMU puts the data in code memory
//! ([`layout`]), the config block that tells the firmware what to draw ([`config`]), the
//! indexed mesh the z-buffer baseline draws ([`mesh`]) and that baseline itself
//! ([`zbuffer`]), and the poses of the scene with moving objects ([`objects`]). `no_std` and
//! allocation-free like the runtime, so the runner computes its reference pixels with the
//! very code the firmware runs; the writers need the `std` feature.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

#[cfg(any(feature = "std", test))]
extern crate std;

/// Traversal stack entries of the firmware's renderer workspace: the shared models need at most
/// about 100; the runner skips a scene deeper than this, with a notice, rather than fail on the
/// target (the renderer refuses it before drawing).
pub const STACK: usize = 128;
/// Clip-buffer vertices of the firmware's renderer workspace.
pub const VERTS: usize = 24;

pub mod config;
pub mod gfx3d;
pub mod mesh;
pub mod objects;
pub mod scanline;
pub mod zbuffer;

use peel_runtime::camera::{Camera, LocalView, Orbit};
use peel_runtime::read::Header;
use peel_runtime::RenderError;

/// The view of `peel render --orbit=AZ,EL --size=WxH --fov=FOV` over the scene whose header is
/// `header`: the CLI's default distance ([`Orbit::fitting_distance`]), near distance
/// ([`Camera::default_near`]) and up (`0,1,0`), computed by the same runtime code (`f64`,
/// `libm`) on the host and on the target, so both draw from bit-identical views.
///
/// # Errors
/// [`RenderError::BadCamera`] for a degenerate camera.
pub fn orbit_view(
    header: &Header,
    angles: config::OrbitAngles,
    fov_y_deg: f64,
    width: u32,
    height: u32,
) -> Result<LocalView, RenderError> {
    let orbit = Orbit {
        azimuth_deg: angles.azimuth_deg,
        elevation_deg: angles.elevation_deg,
        distance: Orbit::fitting_distance(fov_y_deg, width, height),
    };
    let near = Camera::default_near(header.bounds_min, header.bounds_max);
    let camera = Camera::look_at(orbit.pose(header), fov_y_deg, width, height, near)?;
    Ok(camera.view(header.centre))
}

/// Where QEMU's `-device loader` puts the data in the 4 MiB of code memory that the
/// `mps2-an385`/`mps2-an386` machines map at address 0: one firmware build then serves every
/// scene, size and camera path. The firmware itself links below [`layout::ASSET_ADDR`].
pub mod layout {
    /// The scene (`.peel` file) or the mesh ([`crate::mesh`]).
    pub const ASSET_ADDR: u32 = 0x0010_0000;
    /// The config block ([`crate::config`]).
    pub const CONFIG_ADDR: u32 = 0x003F_0000;
    /// The largest asset: up to the config block.
    pub const MAX_ASSET: u32 = CONFIG_ADDR - ASSET_ADDR;
    /// The code memory's end.
    pub const CODE_END: u32 = 0x0040_0000;
}

/// Little-endian field readers over a byte slice, `None` past its end.
pub(crate) mod bytes {
    pub fn u32_at(b: &[u8], at: usize) -> Option<u32> {
        Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?))
    }
    pub fn u16_at(b: &[u8], at: usize) -> Option<u16> {
        Some(u16::from_le_bytes(b.get(at..at + 2)?.try_into().ok()?))
    }
    pub fn f32_at(b: &[u8], at: usize) -> Option<f32> {
        u32_at(b, at).map(f32::from_bits)
    }
    pub fn f64_at(b: &[u8], at: usize) -> Option<f64> {
        Some(f64::from_le_bytes(b.get(at..at + 8)?.try_into().ok()?))
    }
}
