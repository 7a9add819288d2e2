//! What stops a board's firmware: there is nowhere to print, so the reason is kept where a
//! debugger finds it.

use peel_runtime::{ReadError, RenderError};

/// What stopped the firmware, kept where a debugger finds it.
#[derive(Debug)]
pub enum Failure {
    /// The scene in flash does not parse.
    Read(ReadError),
    /// A frame could not be drawn (its memory, its camera, or scan memory that ran out).
    Render(RenderError),
    /// The hardware: the clocks did not start, a peripheral was taken twice, or the panel
    /// refused its set-up or a write (SPI or a pin).
    Hardware,
}

impl From<RenderError> for Failure {
    fn from(e: RenderError) -> Self {
        Failure::Render(e)
    }
}

impl From<ReadError> for Failure {
    fn from(e: ReadError) -> Self {
        Failure::Read(e)
    }
}

/// Stop with `failure` (a real device might blink it, or reset).
pub fn fail(failure: Failure) -> ! {
    loop {
        core::hint::black_box(&failure);
    }
}
