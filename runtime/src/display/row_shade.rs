//! [`RowShade`]: one row of a smoothly shaded polygon, what a sink receives with a shaded span
//! ([`SpanSink::shaded_span`](super::SpanSink::shaded_span)). The fill's
//! [`Gradient`](crate::fill::gradient::Gradient) makes one per row; it lives here, beside the
//! sinks that take it, so that the display module needs nothing of the fill.

use super::Colour;

/// Fraction bits of a [`RowShade`]'s intensity: a value `v` is the 8-bit intensity
/// `v / 2^SHADE_FRACTION_BITS` (255: the material's full colour). Enough that a step rounded
/// to it drifts by less than 1/256 of a level across the widest row the gradient serves, and
/// few enough that every intensity a polygon can reach (its corners' range widened by that
/// range once more on each side, see the gradient) fits an `i32`.
pub const SHADE_FRACTION_BITS: u32 = 21;

/// Half a level: the bias that turns the floor of a shift into rounding to nearest.
const HALF: i32 = 1 << (SHADE_FRACTION_BITS - 1);

/// The shading of one pixel row: a material colour times an intensity affine in x. Pixel
/// `x`'s intensity is `base + x * step` in units of `2^-SHADE_FRACTION_BITS` of a level,
/// whatever the span, rounded to 8 bits, and its colour the material's times it, as a file's
/// corner colours are. A span cut into pieces (the span buffer's uncovered parts of it)
/// therefore passes the same `RowShade` with every piece.
///
/// Both are kept modulo `2^32` (wrapping): `base` extrapolates the polygon's plane to column
/// 0, far outside the polygon it may be, but the sum at a pixel of the polygon is a true
/// intensity within `i32`, and wrapping arithmetic is exact modulo `2^32`. Only pixels of the
/// polygon are meaningful.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RowShade {
    /// The intensity at the centre of pixel `x = 0` of the row, times
    /// `2^SHADE_FRACTION_BITS`, modulo `2^32`.
    pub base: i32,
    /// Its change from a pixel to the next on the right, on the same scale, modulo `2^32`.
    pub step: i32,
    /// The material colour (intensity 255).
    pub colour: Colour,
}

impl RowShade {
    /// `colour` at every pixel.
    pub const fn flat(colour: Colour) -> Self {
        RowShade {
            base: 255 << SHADE_FRACTION_BITS,
            step: 0,
            colour,
        }
    }

    /// The colour of pixel `x`: the intensity rounded to nearest (halves up) and clamped to
    /// `0..=255`, times the material colour ([`shaded`]). The clamp matters on a polygon's
    /// edge, where rounding, or a corner off the plane of a polygon of more than three, can
    /// take the plane just past its corners' intensities.
    #[inline]
    pub fn at(&self, x: u32) -> Colour {
        self.colours(x).colour()
    }

    /// The colours of pixels `x, x + 1, ...`, each as [`Self::at`] gives it, by one add and a
    /// multiply a channel a pixel. The iterator never ends: zip it with the pixels of a span.
    #[inline]
    pub fn colours(&self, x: u32) -> RowColours {
        RowColours {
            value: self
                .base
                .wrapping_add(self.step.wrapping_mul(x as i32))
                .wrapping_add(HALF),
            step: self.step,
            colour: self.colour,
        }
    }
}

/// The colour that intensity `level` (255: full) gives `colour`, each channel
/// `round(c * level / 255)` (never a tie: 255 is odd), as the compiler rounds a corner's.
#[inline]
pub const fn shaded(colour: Colour, level: u8) -> Colour {
    const fn channel(c: u8, level: u8) -> u8 {
        let t = c as u32 * level as u32 + 128;
        ((t + (t >> 8)) >> 8) as u8
    }
    Colour::new(
        channel(colour.r, level),
        channel(colour.g, level),
        channel(colour.b, level),
    )
}

/// The colours of a row's pixels from one on, left to right ([`RowShade::colours`]).
#[derive(Debug, Clone)]
pub struct RowColours {
    /// The next pixel's intensity plus [`HALF`], so that a shift rounds it.
    value: i32,
    step: i32,
    colour: Colour,
}

impl RowColours {
    /// The next pixel's colour, without advancing.
    #[inline]
    fn colour(&self) -> Colour {
        shaded(self.colour, self.level())
    }

    /// The next pixel's 8-bit intensity.
    #[inline]
    pub fn level(&self) -> u8 {
        (self.value >> SHADE_FRACTION_BITS).clamp(0, 255) as u8
    }
}

impl Iterator for RowColours {
    type Item = Colour;

    #[inline]
    fn next(&mut self) -> Option<Colour> {
        let colour = self.colour();
        self.value = self.value.wrapping_add(self.step);
        Some(colour)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;

    /// `shaded` is `round(c * level / 255)` for every channel value and level.
    #[test]
    fn shaded_rounds_exactly() {
        for c in 0..=255u8 {
            for level in 0..=255u8 {
                let exact = (f64::from(c) * f64::from(level) / 255.0).round() as u8;
                assert_eq!(shaded(Colour::grey(c), level).r, exact, "{c} {level}");
            }
        }
    }

    /// Pixel by pixel: the affine intensity rounded, clamped, times the colour; wrapping
    /// bases far outside the range still give the right pixels; a flat shade is its colour.
    #[test]
    fn pixels_are_the_rounded_intensity_times_the_colour() {
        let f = SHADE_FRACTION_BITS;
        let kd = Colour::new(200, 100, 50);
        let shade = RowShade {
            base: (10 << f) + (1 << (f - 1)) - 1,
            step: (3 << f) / 2,
            colour: kd,
        };
        for x in 0..200u32 {
            let v = 10.0 + 0.5 + 1.5 * f64::from(x) - 1.0 / f64::from(1 << f);
            let level = v.round().clamp(0.0, 255.0) as u8;
            assert_eq!(shade.at(x), shaded(kd, level), "pixel {x}");
        }
        let colours: std::vec::Vec<Colour> = shade.colours(7).take(50).collect();
        assert!(colours.iter().zip(7..).all(|(&c, x)| c == shade.at(x)));
        // A base extrapolated far past i32, wrapped: pixel 1000 is at 100.
        let far = RowShade {
            base: (100i32 << f).wrapping_sub((1i32 << f).wrapping_mul(1000).wrapping_mul(3)),
            step: 3 << f,
            colour: Colour::grey(255),
        };
        assert_eq!(far.at(1000), Colour::grey(100));
        assert_eq!(RowShade::flat(kd).at(123), kd);
    }
}
