//! The orbit in a window (feature `window`): the simulator's SDL2 window shows each frame as
//! the display holds it, until the window is closed.

use embedded_graphics_core::pixelcolor::Rgb565;
use embedded_graphics_simulator::{
    OutputSettingsBuilder, SimulatorDisplay, SimulatorEvent, Window,
};

use crate::error::Error;
use crate::Orbiter;

/// Show `orbit`'s frames in a window titled `title`, `scale` window pixels a display pixel,
/// until it is closed (the simulator holds the pace at 60 frames a second at most).
///
/// # Errors
/// The first frame that cannot be drawn.
pub fn run(
    orbit: &mut Orbiter<'_, '_>,
    display: &mut SimulatorDisplay<Rgb565>,
    title: &str,
    scale: u32,
) -> Result<(), Error> {
    let settings = OutputSettingsBuilder::new().scale(scale).build();
    let mut window = Window::new(title, &settings);
    loop {
        orbit.next_frame(display)?;
        window.update(display);
        if window.events().any(|e| e == SimulatorEvent::Quit) {
            return Ok(());
        }
    }
}
