//! Ordered dithering to RGB565 ([`dither_rgb565`]): a smooth gradient reduced to 5 or 6 bits
//! a channel shows bands a level wide; a 4 x 4 Bayer matrix trades them for a fine, fixed
//! pattern whose average is the 8-bit colour.

use super::Colour;

/// The 4 x 4 Bayer matrix, row `y % 4`, column `x % 4`: each of `0..16` once, neighbours far
/// apart in value, so any constant level spreads its pixels evenly over the block.
pub const BAYER_4X4: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// `colour` at pixel `(x, y)` in RGB565, dithered: channel `c` on the `max`-level scale
/// (`max` = 31 for red and blue, 63 for green) is `s = round(16 max c / 255)` sixteenths of a
/// level, and the pixel stores `floor((s + t) / 16)`, `t` the pixel's entry of [`BAYER_4X4`].
///
/// Over any 4 x 4 block of pixels (aligned on multiples of 4) each `t` occurs once, and the sum
/// of `floor((s + t) / 16)` over `t = 0..16` is exactly `s`, so the block's mean is `s / 16`
/// levels: within 1/32 of a level of the colour's exact value `max c / 255`, the finest a
/// block of 16 pixels can express. A channel within 1/32 of a level (`s` a multiple of 16:
/// always `0` and `255`, so black, white and the primaries) is that level at every pixel,
/// which is the plain conversion [`Colour::to_rgb565`]. The result never exceeds `max`.
pub const fn dither_rgb565(x: u32, y: u32, colour: Colour) -> u16 {
    dithered(
        colour,
        (BAYER_4X4[(y & 3) as usize][(x & 3) as usize] as u32) << 12,
    )
}

/// `round(16 * 31 c / 255) = (c R_MUL + R_ADD) >> 12` for red and blue.
const R_MUL: u32 = 7967;
/// See [`R_MUL`].
const R_ADD: u32 = 2063;
/// `round(16 * 63 c / 255) = (c G_MUL + G_ADD) >> 12` for green.
const G_MUL: u32 = 16191;
/// See [`G_MUL`].
const G_ADD: u32 = 2079;

/// The thresholds of row `y`'s columns `x % 4`, each already shifted into place for
/// [`dithered`]: a shaded span's loop takes one per pixel instead of indexing the matrix.
#[inline]
pub(super) fn row_thresholds(y: u32) -> [u32; 4] {
    BAYER_4X4[(y & 3) as usize].map(|t| u32::from(t) << 12)
}

/// [`dither_rgb565`] of `colour` with the threshold `t` (a [`BAYER_4X4`] entry times `2^12`):
/// each channel's sixteenths `(c mul + add) >> 12` plus the threshold, over 16, in one shift.
#[inline]
pub(super) const fn dithered(colour: Colour, t: u32) -> u16 {
    let r = (colour.r as u32 * R_MUL + R_ADD + t) >> 16;
    let g = (colour.g as u32 * G_MUL + G_ADD + t) >> 16;
    let b = (colour.b as u32 * R_MUL + R_ADD + t) >> 16;
    ((r << 11) | (g << 5) | b) as u16
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A channel's value in sixteenths of a level, exactly: `round(16 max c / 255)`.
    fn exact_sixteenths(c: u8, max: u32) -> u32 {
        (2 * 16 * max * u32::from(c) + 255) / 510
    }

    /// The channel of every pixel of the block at `(x0, y0)`: red, green or blue by `shift` and
    /// `mask` of the RGB565 word.
    fn block(x0: u32, y0: u32, colour: Colour, shift: u32, mask: u16) -> [u16; 16] {
        core::array::from_fn(|i| {
            let (x, y) = (x0 + i as u32 % 4, y0 + i as u32 / 4);
            (dither_rgb565(x, y, colour) >> shift) & mask
        })
    }

    #[test]
    fn the_constants_are_the_exact_sixteenths() {
        for c in 0..=255u8 {
            assert_eq!(
                (u32::from(c) * R_MUL + R_ADD) >> 12,
                exact_sixteenths(c, 31)
            );
            assert_eq!(
                (u32::from(c) * G_MUL + G_ADD) >> 12,
                exact_sixteenths(c, 63)
            );
        }
    }

    #[test]
    fn every_grey_level_averages_to_its_value_over_a_block() {
        for c in 0..=255u8 {
            let grey = Colour::grey(c);
            for (shift, mask, max) in [(11, 0x1f, 31u32), (5, 0x3f, 63), (0, 0x1f, 31)] {
                // Any aligned block: the pattern repeats every 4 pixels both ways.
                for (x0, y0) in [(0, 0), (4, 8), (1000, 4)] {
                    let levels = block(x0, y0, grey, shift, mask);
                    let sum: u32 = levels.iter().map(|&v| u32::from(v)).sum();
                    assert_eq!(sum, exact_sixteenths(c, max), "grey {c}, max {max}");
                    // Within 1/32 of a level: |sum / 16 - max c / 255| <= 1/32.
                    let error = (i64::from(sum) * 255 * 2 - i64::from(max) * i64::from(c) * 32)
                        .unsigned_abs();
                    assert!(error <= 255, "grey {c}, max {max}: off by {error}/510");
                    assert!(levels.iter().all(|&v| u32::from(v) <= max));
                }
            }
        }
    }

    #[test]
    fn a_representable_colour_is_the_plain_conversion() {
        for c in 0..=255u8 {
            for (colour, shift, mask, max) in [
                (Colour::new(c, 0, 0), 11, 0x1f, 31),
                (Colour::new(0, c, 0), 5, 0x3f, 63),
                (Colour::new(0, 0, c), 0, 0x1f, 31),
            ] {
                let levels = block(8, 12, colour, shift, mask);
                let constant = levels.iter().all(|&v| v == levels[0]);
                // Constant exactly when the channel is within 1/32 of a level, and then it is
                // the rounded level.
                assert_eq!(
                    constant,
                    exact_sixteenths(c, max).is_multiple_of(16),
                    "{colour:?}"
                );
                if constant {
                    assert!(levels
                        .iter()
                        .all(|&v| v == (colour.to_rgb565() >> shift) & mask));
                }
            }
        }
        for colour in [
            Colour::new(0, 0, 0),
            Colour::new(255, 255, 255),
            Colour::new(255, 0, 0),
            Colour::new(0, 255, 255),
        ] {
            for (x, y) in [(0, 0), (1, 2), (3, 3), (6, 5)] {
                assert_eq!(dither_rgb565(x, y, colour), colour.to_rgb565());
            }
        }
    }
}
