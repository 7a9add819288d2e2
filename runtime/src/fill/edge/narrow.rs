//! The narrow walk (without `wide-coordinates`): the same walk as the wide one, set up in
//! 32-bit arithmetic, for coordinates in `0..=`[`crate::fill::coordinate_limit`].

use super::{top_bottom, EdgeWalk, FixedPoint};

/// The integer type of the narrow walk.
#[allow(dead_code)]
pub(super) type Coord = i32;

/// The first pixel whose centre is at or right of `v` (`first_centre_at_or_after`) in 32-bit arithmetic, for `0 <= v <=`
/// [`crate::fill::coordinate_limit`] (beyond it the result is wrong, never a panic).
#[inline]
pub(crate) fn first_centre_narrow<const SUB: u32>(v: i32) -> i32 {
    // ceil((2v - S) / 2S) = floor((2v + S - 1) / 2S): an arithmetic shift.
    let s = 1i32 << SUB;
    v.wrapping_mul(2).wrapping_add(s - 1) >> (SUB + 1)
}

/// [`first_centre_narrow`], the build's [`super::first_centre`].
#[allow(dead_code)]
#[inline]
pub(super) fn first_centre<const SUB: u32>(v: i32) -> Coord {
    first_centre_narrow::<SUB>(v)
}

/// [`EdgeWalk::for_edge_narrow`], the build's [`EdgeWalk::for_edge`].
#[allow(dead_code)]
#[inline]
pub(super) fn walk<const SUB: u32>(
    a: FixedPoint<SUB>,
    b: FixedPoint<SUB>,
    height: u32,
) -> Option<EdgeWalk> {
    EdgeWalk::for_edge_narrow::<SUB>(a, b, height)
}

/// An `i32` as a [`Coord`] (the identity without `wide-coordinates`).
#[allow(clippy::useless_conversion)]
#[inline]
fn coord(v: i32) -> super::Coord {
    super::Coord::from(v)
}

impl EdgeWalk {
    /// [`Self::for_edge`] in 32-bit arithmetic, for points whose coordinates all lie in
    /// `0..=L` with `L = `[`super::coordinate_limit`]`::<SUB>() = 2^(29 - SUB) - 1` (the
    /// caller guarantees it): the same walk, field for field.
    ///
    /// With `S = 2^SUB`, `e = (2 first + 1) S - 2 y_top` (`0 <= e < 2S`: `y_top >= 0`, so no
    /// row is clamped away) and `dx e = q1 dy + r1` (`0 <= r1 < dy`), the start numerator is
    /// `num = (2 x_top - S) dy + dx e = M dy + r1` with `M = 2 x_top - S + q1`. Splitting
    /// `M = 2S k + m` (`0 <= m < 2S`: a shift and a mask) gives `num = den k + (dy m + r1)`
    /// with `0 <= dy m + r1 < den = 2S dy`, so `ceil(num / den)` is `k` or `k + 1` and the
    /// classic walk's `N` follows without dividing by `den`. Ranges: `den <= 2S L < 2^30`,
    /// `|dx e| < 2S L`, `|M| <= (2S + 1) L + S < 2^31`, and the walk keeps
    /// `rem + step_r < 2 den < 2^31`: nothing overflows an `i32`.
    pub(crate) fn for_edge_narrow<const SUB: u32>(
        a: FixedPoint<SUB>,
        b: FixedPoint<SUB>,
        height: u32,
    ) -> Option<Self> {
        let (top, bottom) = top_bottom(a, b)?;
        let s = 1i32 << SUB;
        let first = first_centre_narrow::<SUB>(top.y).max(0);
        let end =
            first_centre_narrow::<SUB>(bottom.y).min(i32::try_from(height).unwrap_or(i32::MAX));
        if first >= end {
            return None;
        }
        // `max(1)`: `dy > 0` already; it only makes the divisions provably panic-free.
        let dy = (bottom.y - top.y).max(1);
        let dx = bottom.x - top.x;
        let den = 2 * s * dy;
        let e = (2 * first + 1) * s - 2 * top.y;
        let p = dx * e;
        let (q1, r1) = (p.div_euclid(dy), p.rem_euclid(dy));
        let m_all = 2 * top.x - s + q1;
        let (k, m) = (m_all >> (SUB + 1), m_all & (2 * s - 1));
        let t = dy * m + r1 + den - 1;
        let (x, rem) = if t >= den { (k + 1, t - den) } else { (k, t) };
        Some(EdgeWalk {
            x: coord(x),
            rem: coord(rem),
            den: coord(den),
            step_q: coord(dx.div_euclid(dy)),
            step_r: coord(2 * s * dx.rem_euclid(dy)),
            row: coord(first),
            row_end: coord(end),
        })
    }
}
