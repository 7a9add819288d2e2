//! The orbit the boards draw: a camera circling the scene at a fixed elevation, a step per
//! frame.

use peel_runtime::camera::{Camera, LocalOrbit, LocalView, Orbit};
use peel_runtime::read::Header;
use peel_runtime::RenderError;

use crate::{HEIGHT, WIDTH};

/// Vertical field of view, degrees.
pub const FOV_Y_DEG: f32 = 60.0;
/// The orbit's elevation, degrees: one of those the build scripts measure the scan memory at.
pub const ELEVATION_DEG: f32 = 20.0;
/// The orbit's step per frame, degrees.
pub const STEP_DEG: f32 = 3.0;

/// The view of the orbit's frame at `azimuth_deg`: in `f32` alone ([`LocalOrbit`], no `f64`
/// and no libm linked). With the feature `f64-orbit`, the same orbit through the `f64`
/// [`Orbit`] and [`Camera`] instead: only to measure the flash the `f32` one saves
/// (BENCHMARKS.md, "The `f32` orbit").
pub fn orbit_view(header: &Header, azimuth_deg: f32) -> Result<LocalView, RenderError> {
    if cfg!(feature = "f64-orbit") {
        let fov = f64::from(FOV_Y_DEG);
        let orbit = Orbit {
            azimuth_deg: f64::from(azimuth_deg),
            elevation_deg: f64::from(ELEVATION_DEG),
            distance: Orbit::fitting_distance(fov, WIDTH, HEIGHT),
        };
        let near = Camera::default_near(header.bounds_min, header.bounds_max);
        let camera = Camera::look_at(orbit.pose(header), fov, WIDTH, HEIGHT, near)?;
        Ok(camera.view(header.centre))
    } else {
        let focal = LocalOrbit::focal(FOV_Y_DEG, HEIGHT);
        let orbit = LocalOrbit {
            azimuth_deg,
            elevation_deg: ELEVATION_DEG,
            distance: LocalOrbit::fitting_distance(focal, WIDTH, HEIGHT),
        };
        orbit.view(
            header,
            focal,
            WIDTH,
            HEIGHT,
            LocalOrbit::default_near(header),
        )
    }
}

/// The azimuth of the frame after the one at `azimuth_deg`, in `0..360`.
pub fn next_azimuth(azimuth_deg: f32) -> f32 {
    let next = azimuth_deg + STEP_DEG;
    if next >= 360.0 {
        next - 360.0
    } else {
        next
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_azimuth_wraps_at_a_full_turn() {
        assert_eq!(next_azimuth(0.0), STEP_DEG);
        assert_eq!(next_azimuth(360.0 - STEP_DEG), 0.0);
        let mut a = 0.0;
        for _ in 0..(360.0 / STEP_DEG) as usize * 3 {
            a = next_azimuth(a);
            assert!((0.0..360.0).contains(&a), "{a}");
        }
    }
}
