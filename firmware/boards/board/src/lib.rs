//! What Peel's board crates share: everything but the hardware. A board's `main.rs` sets up
//! its clocks, pins and SPI, describes its panel with [`panel`], and hands the panel, its static
//! [`Memory`] and the scene its build script compiled to [`Firmware::start`], which sets the panel up and
//! [`run`]s an orbit around the scene frame after frame in scan order (no framebuffer: 150 KiB
//! at 320x240).
//!
//! ```ignore
//! peel_board::main!(rp_pico::entry, hardware); // the scene, its sizes, `Memory` and `main`
//!
//! fn hardware(firmware: Firmware, buffer: &'static mut [u8; 512]) -> ! {
//!     // ... clocks, pins, SPI ...
//!     let panel = peel_board::panel::st7789(spi, dc, buffer);
//!     firmware.start(panel, reset, backlight, &mut delay, Core::WithoutFpu)
//! }
//! ```
//!
//! Generic over the panel (an embedded-graphics `DrawTarget` of `Rgb565`) and the scene's
//! sizes, so it builds for the host too, where its tests send frames through `mipidsi` to a
//! recorded SPI bus and decode them as the panel would show them.
#![cfg_attr(not(test), no_std)]
#![forbid(unsafe_code)]

mod failure;
mod frame;
mod memory;
mod orbit;
pub mod panel;
mod run;
mod scene;

#[cfg(test)]
mod dcs;
#[cfg(test)]
mod on_panel;
#[cfg(test)]
mod recorder;

pub use failure::{fail, Failure};
pub use frame::draw_frame;
pub use memory::{pending_records, scan_nodes, vertex_memory, Core, Memory};
pub use orbit::{next_azimuth, orbit_view, ELEVATION_DEG, FOV_Y_DEG, STEP_DEG};
pub use run::{run, Firmware};

use peel_runtime::display::Colour;

/// The panel in landscape: the size the build scripts measure the scan memory at.
pub const WIDTH: u32 = 320;
/// See [`WIDTH`].
pub const HEIGHT: u32 = 240;
/// What no polygon covers.
pub const BACKGROUND: Colour = Colour::new(24, 26, 32);
