//! Gouraud shading in integers: a polygon's intensity at each pixel centre, the affine
//! function of screen position through its corners' 8-bit intensities ([`Gradient`]), handed
//! to a sink one row at a time ([`RowShade`]) with the material colour it multiplies, so that
//! each written pixel costs one add and a multiply a channel.
//!
//! # The plane
//! The intensity is the plane through three of the polygon's corners `(x, y, intensity)`: the
//! three that span the largest area (a convex polygon's largest inscribed triangle, found in
//! `O(n^2)`), so that a sliver's first three points, nearly collinear, cannot blow the slopes
//! up. Every point of a convex polygon then has barycentric coordinates in `[-1, 1]` with
//! respect to that triangle, so the plane stays within the corners' range widened by that
//! range once more on each side (`-255..=510`), which [`SHADE_FRACTION_BITS`] leaves room for
//! in an `i32`. A polygon of more than three corners whose intensities are not coplanar is
//! shaded by that one plane, its other corners' intensities only approximated.
//!
//! # One division a polygon
//! The slopes are the plane's divided by the triangle's doubled area. The gradient divides
//! once, for a reciprocal of the area with 30 significant bits, and multiplies by it: a slope
//! errs by less than `2^-28` of itself and half a unit of `2^-F` (`F` =
//! [`SHADE_FRACTION_BITS`]), so pixel `x` errs by at most `(x + 1) / 2^F` of a level beyond
//! that, at most `1/256` across a row of [`GRADIENT_LIMIT`] pixels. A row's base is the value
//! at pixel 0 of row 0 plus `y` row steps: a multiply, no walk. Setting a polygon up on a core
//! without a divide instruction costs one software 64-bit division, where rounding each slope
//! exactly took a dozen.
//!
//! # Domain
//! Points within `0..=`[`GRADIENT_LIMIT`] pixels on both axes, taken at
//! [`GRADIENT_SUBPIXEL_BITS`] fractional bits: every intermediate value then fits an `i64`.
//! Points of more bits are rounded to it for the plane (only for their shading: the fill keeps
//! its own), points of none gain one, which pixel centres need. The renderer clamps its points
//! to its window, so any window within the limit (every window of the narrow fill) is inside;
//! a polygon with a point outside is shaded flat, at its first corner's intensity.

use super::{FixedPoint, MAX_SUBPIXEL_BITS};
use crate::display::{shaded, Colour, RowShade, SHADE_FRACTION_BITS};

/// The gradient's extent in pixels: points in `0..=GRADIENT_LIMIT` on both axes, rows and
/// columns in `0..GRADIENT_LIMIT`. A polygon with a point outside is shaded flat.
pub const GRADIENT_LIMIT: u32 = 8192;

/// Fractional bits of the points a [`Gradient`]'s plane goes through, at most: a point of more
/// is rounded to them (halves up), a point of none gains one.
pub const GRADIENT_SUBPIXEL_BITS: u32 = 8;

/// Fraction bits of the values a gradient hands out.
const F: u32 = SHADE_FRACTION_BITS;

/// A polygon's intensity plane over the pixel grid ([`Gradient::of`]) and its material colour:
/// [`Gradient::row`] gives each row's [`RowShade`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Gradient<const SUB: u32> {
    /// The intensity at the centre of pixel `(0, 0)`, times `2^F`, modulo `2^32`.
    origin: i32,
    /// Per pixel to the right and per row down, on the same scale, modulo `2^32`.
    step: i32,
    row_step: i32,
    /// The material colour.
    colour: Colour,
    /// The intensity everywhere when the plane is flat.
    flat: Option<u8>,
}

impl<const SUB: u32> Gradient<SUB> {
    /// `colour` times intensity `level` everywhere.
    pub const fn flat(colour: Colour, level: u8) -> Self {
        Gradient {
            origin: (level as i32) << F,
            step: 0,
            row_step: 0,
            colour,
            flat: Some(level),
        }
    }

    /// Fractional bits of the points the plane goes through: `SUB`, within `1..=`
    /// [`GRADIENT_SUBPIXEL_BITS`].
    const BITS: u32 = if SUB == 0 {
        1
    } else if SUB > GRADIENT_SUBPIXEL_BITS {
        GRADIENT_SUBPIXEL_BITS
    } else {
        SUB
    };

    /// A coordinate at [`Self::BITS`]: shifted up, or rounded down (halves up).
    #[inline]
    fn at_bits(v: i32) -> i64 {
        let v = i64::from(v);
        if SUB < Self::BITS {
            v << (Self::BITS - SUB)
        } else {
            let drop = SUB - Self::BITS;
            (v + ((1 << drop) >> 1)) >> drop
        }
    }

    /// A point at [`Self::BITS`].
    #[inline]
    fn point(p: FixedPoint<SUB>) -> (i64, i64) {
        (Self::at_bits(p.x), Self::at_bits(p.y))
    }

    /// The gradient of the polygon `points` (convex, in the fill's order, either winding) in
    /// the material colour `colour`, whose corner `i` has intensity `level(i)` (255: full),
    /// asked only for the corners the plane goes through (and each once to see whether all are
    /// equal): the renderer computes a clipped point's intensity only when it is needed. Flat,
    /// at the first corner's intensity, for fewer than three points, when all are equal, when
    /// the polygon has no area (it draws nothing), and for a point outside
    /// `0..=`[`GRADIENT_LIMIT`] pixels.
    pub fn of(points: &[FixedPoint<SUB>], colour: Colour, level: impl Fn(usize) -> u8) -> Self {
        const {
            assert!(
                SUB <= MAX_SUBPIXEL_BITS,
                "SUB must be at most MAX_SUBPIXEL_BITS"
            );
        }
        let n = points.len();
        let first = level(0);
        if n < 3 || (1..n).all(|i| level(i) == first) {
            return Self::flat(colour, first);
        }
        let limit = i64::from(GRADIENT_LIMIT) << Self::BITS;
        let inside = |&p: &FixedPoint<SUB>| {
            let (x, y) = Self::point(p);
            (0..=limit).contains(&x) && (0..=limit).contains(&y)
        };
        if !points.iter().all(inside) {
            return Self::flat(colour, first);
        }
        let point = |i: usize| points.get(i).map_or((0, 0), |&p| Self::point(p));
        let Some(([i, mut j, mut k], area)) = largest_triangle(n, point) else {
            return Self::flat(colour, first);
        };
        if area < 0 {
            core::mem::swap(&mut j, &mut k);
        }
        // `0 < den < 2^44`: twice the area in units of `2^-2 BITS` pixel.
        let den = area.abs();
        let (p0, p1, p2) = (point(i), point(j), point(k));
        let (s0, s1, s2) = (level(i), level(j), level(k));
        let (x1, y1) = (p1.0 - p0.0, p1.1 - p0.1);
        let (x2, y2) = (p2.0 - p0.0, p2.1 - p0.1);
        let (e1, e2) = (i64::from(s1) - i64::from(s0), i64::from(s2) - i64::from(s0));
        // The intensity at `p` is `s0 + (nx (p.x - x0) + ny (p.y - y0)) / den`, in levels and
        // units of `2^-BITS` pixel; `|nx|, |ny| < 2^31`.
        let nx = e1 * y2 - e2 * y1;
        let ny = x1 * e2 - x2 * e1;
        // `r = 2^(30 + L) / den` with `2^(L - 1) <= den < 2^L`, in `(2^30, 2^31]`: past 32
        // bits, `den` loses its low bits first (a relative error below `2^-31`).
        let l = 64 - den.leading_zeros();
        let drop = l.saturating_sub(32);
        let r = (1i64 << (30 + l - drop)) / (den >> drop).max(1);
        // A slope per pixel at `F` fraction bits: `n 2^(BITS + F) / den = n r / 2^(30 + L -
        // BITS - F)`, rounded; `|n r| < 2^62`, and the shift is at least `1 + L`.
        let shift = 30 + l - (Self::BITS + F);
        let slope = |n: i64| -> i64 { (n * r + (1 << (shift - 1))) >> shift };
        let (step, row_step) = (slope(nx), slope(ny));
        // A sliver steeper than 2^12 levels a pixel covers at most a pixel centre or two: flat
        // (which also keeps the products below in range).
        let steep = 1i64 << (F + 12);
        if step.abs() > steep || row_step.abs() > steep {
            return Self::flat(colour, first);
        }
        // Pixel (0, 0)'s centre is `half - p0` away from the anchor, at `BITS`.
        let half = 1i64 << (Self::BITS - 1);
        let (dx, dy) = (half - p0.0, half - p0.1);
        // `|step dx| < 2^(F + 12 + 22)`: exact in i64; the result wraps, as `RowShade` may.
        let origin = (i64::from(s0) << F) + ((step * dx + row_step * dy) >> Self::BITS);
        Gradient {
            origin: origin as i32,
            step: step as i32,
            row_step: row_step as i32,
            colour,
            flat: None,
        }
    }

    /// The colour when the intensity is constant (then a flat span draws the polygon).
    pub fn flat_colour(&self) -> Option<Colour> {
        self.flat.map(|level| shaded(self.colour, level))
    }

    /// The shading of row `y` (rows past [`GRADIENT_LIMIT`] as its last).
    #[inline]
    pub fn row(&self, y: u32) -> RowShade {
        let y = y.min(GRADIENT_LIMIT - 1);
        RowShade {
            base: self
                .origin
                .wrapping_add(self.row_step.wrapping_mul(y as i32)),
            step: self.step,
            colour: self.colour,
        }
    }
}

/// Twice the signed area of the triangle `a`, `b`, `c` (positive counter-clockwise in screen
/// axes, y down), exact: below `2^43` in magnitude within the gradient's domain.
#[inline]
fn doubled_area(a: (i64, i64), b: (i64, i64), c: (i64, i64)) -> i64 {
    (b.0 - a.0) * (c.1 - a.1) - (c.0 - a.0) * (b.1 - a.1)
}

/// The indices `i < j < k` of the largest triangle on the `n` points `point(0..n)` of a
/// convex polygon, and its signed doubled area; `None` when every triangle is flat. For each
/// `i`, the best `k` for `j` never lies before the best for `j - 1` along a convex chain, so
/// one pointer serves all `j`: `O(n^2)` triangles rather than `O(n^3)`. (On a polygon that
/// snapping left slightly non-convex it may miss the largest by a little; any triangle with
/// area gives a plane.)
fn largest_triangle(n: usize, point: impl Fn(usize) -> (i64, i64)) -> Option<([usize; 3], i64)> {
    let area = |i: usize, j: usize, k: usize| doubled_area(point(i), point(j), point(k));
    let mut best = ([0, 1, 2], 0i64);
    for i in 0..n {
        let mut k = i + 2;
        for j in i + 1..n {
            k = k.max(j + 1);
            if k >= n {
                break;
            }
            let mut here = area(i, j, k).abs();
            while k + 1 < n {
                let next = area(i, j, k + 1).abs();
                if next < here {
                    break;
                }
                (k, here) = (k + 1, next);
            }
            if here > best.1.abs() {
                best = ([i, j, k], area(i, j, k));
            }
        }
    }
    (best.1 != 0).then_some(best)
}

#[cfg(test)]
mod tests;
