//! The wide walk (feature `wide-coordinates`): kept in `i64`, set up with a 128-bit
//! numerator, for any `i32` coordinates.

use super::{top_bottom, EdgeWalk, FixedPoint};

/// The integer type of the wide walk.
pub(super) type Coord = i64;

/// Pixel index `ceil((2v - S) / (2S))` of a fixed-point coordinate `v` with `S = 2^SUB`: the
/// first pixel whose centre `(k + 1/2) * S` is `>= v`. Used for rows and columns alike.
#[inline]
pub(crate) fn first_centre_at_or_after<const SUB: u32>(v: i32) -> i64 {
    let s = 1i64 << SUB;
    (2 * i64::from(v) + s - 1).div_euclid(2 * s)
}

/// [`first_centre_at_or_after`], the build's [`super::first_centre`].
#[inline]
pub(super) fn first_centre<const SUB: u32>(v: i32) -> Coord {
    first_centre_at_or_after::<SUB>(v)
}

/// [`EdgeWalk::for_edge_wide`], the build's [`EdgeWalk::for_edge`].
#[inline]
pub(super) fn walk<const SUB: u32>(
    a: FixedPoint<SUB>,
    b: FixedPoint<SUB>,
    height: u32,
) -> Option<EdgeWalk> {
    EdgeWalk::for_edge_wide::<SUB>(a, b, height)
}

impl EdgeWalk {
    /// The walk of `x_k = ceil((num + k * step) / den)` from `k = 0` on row `row`, `den > 0`.
    /// The caller guarantees every value of the walk fits an `i64` (see [`Self::for_edge_wide`]).
    pub(crate) fn from_ratio(num: i128, den: i64, step: i64, row: i64, row_end: i64) -> Self {
        debug_assert!(den > 0);
        // Guaranteed by the caller; clamping makes the divisions provably panic-free.
        let den = den.max(1);
        // ceil(num / den) = floor((num + den - 1) / den); the remainder is the walk's N.
        let shifted = num + i128::from(den) - 1;
        // Inside a window of up to 2^15 pixels at SUB = 8 the numerator is below 2^50, so the
        // 128-bit division (slow, in software on small cores) is only a fallback.
        let (x, rem) = match i64::try_from(shifted) {
            Ok(a) => (a.div_euclid(den), a.rem_euclid(den)),
            Err(_) => {
                let d = i128::from(den);
                (shifted.div_euclid(d) as i64, shifted.rem_euclid(d) as i64)
            }
        };
        EdgeWalk {
            x,
            rem,
            den,
            step_q: step.div_euclid(den),
            step_r: step.rem_euclid(den),
            row,
            row_end,
        }
    }

    /// The walk of the edge `a`-`b` (either direction) over the scanlines whose centre `y`
    /// satisfies `y_top <= y < y_bottom`, restricted to rows `0..height`. `None` for a horizontal edge or one that crosses no such row.
    ///
    /// Arithmetic range: with `S = 2^SUB` (`SUB <= 24`), `dy = y_bottom - y_top < 2^32` and
    /// `|dx| < 2^32` for any `i32` input, so `den = 2S*dy < 2^57` and `|step| = 2S*|dx| <
    /// 2^57`; the walk keeps `rem + step_r < 2*den < 2^58`, and `x` stays within a pixel of the
    /// edge's own x range, `|x| < 2^32`. Only the start numerator needs 128 bits (once per
    /// edge). So any `i32` coordinates are safe, not only those inside the window.
    pub(crate) fn for_edge_wide<const SUB: u32>(
        a: FixedPoint<SUB>,
        b: FixedPoint<SUB>,
        height: u32,
    ) -> Option<Self> {
        let (top, bottom) = top_bottom(a, b)?;
        let first = first_centre_at_or_after::<SUB>(top.y).max(0);
        let end = first_centre_at_or_after::<SUB>(bottom.y).min(i64::from(height));
        if first >= end {
            return None;
        }
        let s = 1i64 << SUB;
        let dy = i64::from(bottom.y) - i64::from(top.y);
        let dx = i64::from(bottom.x) - i64::from(top.x);
        // Crossing at row j (centre y_c, 2*y_c = (2j+1)S): x = x_t + dx*(y_c - y_t)/dy, and the
        // pixel is ceil((2x - S) / 2S) = ceil(num_j / den) with
        //   num_j = (2 x_t - S) dy + dx ((2j+1)S - 2 y_t),   den = 2S dy,   num_{j+1} = num_j + 2S dx.
        let centre2 = i128::from((2 * first + 1) * s);
        let num = i128::from(2 * i64::from(top.x) - s) * i128::from(dy)
            + i128::from(dx) * (centre2 - 2 * i128::from(top.y));
        Some(Self::from_ratio(num, 2 * s * dy, 2 * s * dx, first, end))
    }

    /// The classic walk's `N` after the division of the current row.
    #[cfg(test)]
    pub(crate) fn rem(&self) -> Coord {
        self.rem
    }
}
