//! Fill: integer scanline fill of a polygon already clipped to the screen window.
//! CONTRACT (owned by the fill helper): [`fill_polygon`] below.

use crate::target::{Colour, SpanSink};

/// Fractional bits of the fixed-point screen coordinates used by the renderer.
pub const SUBPIXEL_BITS: u32 = 8;

/// Most vertices a polygon handed to [`fill_polygon`] may have.
pub const MAX_FILL_VERTICES: usize = 64;

/// A screen point in fixed point with `SUB` fractional bits (x right, y down; pixel `(i, j)`
/// has its sample point at `(i + 0.5, j + 0.5)`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FixedPoint {
    /// x times `2^SUB`.
    pub x: i32,
    /// y times `2^SUB`.
    pub y: i32,
}

/// Fill the polygon `points` (either winding, inside the window `[0, width] x [0, height]`)
/// with the top-left rule and emit its spans; returns the number of pixels emitted.
pub fn fill_polygon<const SUB: u32, S: SpanSink + ?Sized>(
    points: &[FixedPoint],
    width: u32,
    height: u32,
    colour: Colour,
    sink: &mut S,
) -> u64 {
    let _ = (points, width, height, colour, sink);
    todo!("fill helper")
}
