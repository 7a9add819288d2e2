//! [`RowShade`]: one row of a smoothly shaded polygon, what a sink receives with a shaded span
//! ([`SpanSink::shaded_span`](super::SpanSink::shaded_span)). The fill's
//! [`Gradient`](crate::fill::gradient::Gradient) makes one per row; it lives here, beside the
//! sinks that take it, so that the display module needs nothing of the fill.

use super::Colour;

/// Fraction bits of a [`RowShade`]'s channels: a channel value `v` is the 8-bit level
/// `v / 2^SHADE_FRACTION_BITS`. Enough that a step rounded to it drifts by less than 1/256 of
/// a level across the widest row the gradient serves, and few enough that every colour a
/// polygon can reach (its vertices' range widened by that range once more on each side, see
/// the gradient) fits an `i32`.
pub const SHADE_FRACTION_BITS: u32 = 21;

/// Half a level: the bias that turns the floor of a shift into rounding to nearest.
const HALF: i32 = 1 << (SHADE_FRACTION_BITS - 1);

/// The shading of one pixel row, affine in x: channel `i` of pixel `x` is
/// `base[i] + x * step[i]` in units of `2^-SHADE_FRACTION_BITS` of a level, whatever the
/// span. A span cut into pieces (the span buffer's uncovered parts of it) therefore passes the
/// same `RowShade` with every piece.
///
/// Both are kept modulo `2^32` (wrapping): `base` extrapolates the polygon's plane to column
/// 0, far outside the polygon it may be, but the sum at a pixel of the polygon is a true
/// colour within `i32`, and wrapping arithmetic is exact modulo `2^32`. Only pixels of the
/// polygon are meaningful.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RowShade {
    /// Red, green and blue at the centre of pixel `x = 0` of the row, times
    /// `2^SHADE_FRACTION_BITS`, modulo `2^32`.
    pub base: [i32; 3],
    /// Their change from a pixel to the next on the right, on the same scale, modulo `2^32`.
    pub step: [i32; 3],
}

impl RowShade {
    /// `colour` at every pixel.
    pub const fn flat(colour: Colour) -> Self {
        RowShade {
            base: [
                (colour.r as i32) << SHADE_FRACTION_BITS,
                (colour.g as i32) << SHADE_FRACTION_BITS,
                (colour.b as i32) << SHADE_FRACTION_BITS,
            ],
            step: [0; 3],
        }
    }

    /// The colour of pixel `x`: each channel rounded to nearest (halves up) and clamped to
    /// `0..=255`. The clamp matters on a polygon's edge, where rounding, or a vertex off the
    /// plane of a polygon of more than three, can take the plane just past its colours.
    #[inline]
    pub fn at(&self, x: u32) -> Colour {
        self.colours(x).colour()
    }

    /// The colours of pixels `x, x + 1, ...`, each as [`Self::at`] gives it, by one add per
    /// channel and pixel. The iterator never ends: zip it with the pixels of a span.
    #[inline]
    pub fn colours(&self, x: u32) -> RowColours {
        let x = x as i32;
        let value = [0, 1, 2].map(|i| {
            self.base[i]
                .wrapping_add(self.step[i].wrapping_mul(x))
                .wrapping_add(HALF)
        });
        RowColours {
            value,
            step: self.step,
        }
    }
}

/// The colours of a row's pixels from one on, left to right ([`RowShade::colours`]).
#[derive(Debug, Clone)]
pub struct RowColours {
    /// Each channel of the next pixel plus [`HALF`], so that a shift rounds it.
    value: [i32; 3],
    step: [i32; 3],
}

impl RowColours {
    /// The next pixel's colour, without advancing.
    #[inline]
    fn colour(&self) -> Colour {
        let [r, g, b] = self.value.map(level);
        Colour::new(r, g, b)
    }
}

/// A channel value plus [`HALF`] as its 8-bit level: rounded, then clamped.
#[inline]
fn level(v: i32) -> u8 {
    (v >> SHADE_FRACTION_BITS).clamp(0, 255) as u8
}

impl Iterator for RowColours {
    type Item = Colour;

    #[inline]
    fn next(&mut self) -> Option<Colour> {
        let colour = self.colour();
        for (v, s) in self.value.iter_mut().zip(self.step) {
            *v = v.wrapping_add(s);
        }
        Some(colour)
    }
}
