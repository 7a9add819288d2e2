//! Gouraud shading in integers: a polygon's colour at each pixel centre, the affine function
//! of screen position through its vertices' colours ([`Gradient`]), handed to a sink one row
//! at a time ([`RowShade`]) so that each written pixel costs one add a channel.
//!
//! # The plane
//! Each channel is the plane through three of the polygon's vertices `(x, y, colour)`: the
//! three that span the largest area (a convex polygon's largest inscribed triangle, found in
//! `O(n^2)`), so that a sliver's first three points, nearly collinear, cannot blow the slopes
//! up. Every point of a convex polygon then has barycentric coordinates in `[-1, 1]` with
//! respect to that triangle, so the plane stays within the vertices' colour range widened by
//! that range once more on each side (`-255..=510`), which [`SHADE_FRACTION_BITS`] leaves room
//! for in an `i32`. A polygon of more than three vertices whose colours are not coplanar is
//! shaded by that one plane, its other vertices' colours only approximated.
//!
//! # Exact rounding, so that cuts do not show
//! The step per pixel is the plane's x slope rounded to nearest at [`SHADE_FRACTION_BITS`],
//! and the row base the plane's value at pixel `x = 0`'s centre rounded the same way, both
//! computed exactly in `i64` from the triangle: two 64-bit divisions a varying channel to set
//! up, two more for the first row asked for and for any row not a few below the last (the
//! next row is an add and a compare). Rounding exactly makes both functions of the plane
//! alone, whichever triangle gave it: a polygon cut into pieces whose vertices lie on the
//! plane shades each of its pixels exactly as the whole does.
//!
//! Error: the base and the step each err by at most half a unit of `2^-F` of a level (`F` =
//! [`SHADE_FRACTION_BITS`]), so pixel `x` errs by at most `(x + 1) / 2^(F + 1)` of a level:
//! at most `1/512` across a row of [`GRADIENT_LIMIT`] pixels. A rounded channel is therefore
//! the plane's exactly rounded value, or one off where the plane lies that close to a half.
//!
//! # Domain
//! Points within `0..=`[`GRADIENT_LIMIT`] pixels on both axes, taken at
//! [`GRADIENT_SUBPIXEL_BITS`] fractional bits: every intermediate value then fits an `i64`.
//! Points of more bits are rounded to it for the plane (only for their shading: the fill keeps
//! its own), points of none gain one, which pixel centres need. The renderer clamps its points
//! to its window, so any window within the limit (every window of the narrow fill) is inside;
//! a polygon with a point outside is shaded flat.

use super::{FixedPoint, MAX_SUBPIXEL_BITS, SUBPIXEL_BITS};
use crate::display::{Colour, RowShade, SHADE_FRACTION_BITS};

/// The gradient's extent in pixels: points in `0..=GRADIENT_LIMIT` on both axes, rows and
/// columns in `0..GRADIENT_LIMIT`. A polygon with a point outside is shaded flat.
pub const GRADIENT_LIMIT: u32 = 8192;

/// Fractional bits of the points a [`Gradient`]'s planes go through, at most: a point of more
/// is rounded to them (halves up), a point of none gains one.
pub const GRADIENT_SUBPIXEL_BITS: u32 = 8;

/// Fraction bits of the values a gradient hands out.
const F: u32 = SHADE_FRACTION_BITS;

/// Rows [`Gradient::row`] walks down rather than computing the row afresh (an add and a
/// compare a channel a row, against two 64-bit divisions a channel).
const WALK_ROWS: u32 = 16;

/// One channel's plane, and where its walk down the rows stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct Channel {
    /// The channel at the anchor vertex.
    colour: i32,
    /// The plane's slopes per unit of `2^-BITS` pixel, over the gradient's `den`.
    nx: i64,
    ny: i64,
    /// Per pixel to the right, rounded, modulo `2^32`.
    step: i32,
    /// Per row down: `row_q + row_r / (2 den)`, the quotient modulo `2^32`.
    row_q: i32,
    row_r: i64,
    /// The current row's base: `q + r / (2 den)` is the value at pixel `0`'s centre plus one
    /// half, so `q` is the value rounded (modulo `2^32`) and `0 <= r < 2 den`.
    q: i32,
    r: i64,
}

impl Channel {
    /// A constant channel.
    const fn flat(level: u8) -> Self {
        Channel {
            colour: level as i32,
            nx: 0,
            ny: 0,
            step: 0,
            row_q: 0,
            row_r: 0,
            q: (level as i32) << F,
            r: 0,
        }
    }

    /// Whether the channel is the same everywhere.
    const fn is_flat(&self) -> bool {
        self.nx == 0 && self.ny == 0
    }
}

/// The Gouraud shading of one polygon: set up once from its points and their colours, then
/// asked for each row's [`RowShade`] ([`Self::row`]). See the [module docs](self) for the plane
/// chosen, its rounding and its domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Gradient<const SUB: u32 = SUBPIXEL_BITS> {
    /// Red, green, blue.
    channels: [Channel; 3],
    /// The vertex the planes are written from, at [`Self::BITS`].
    anchor: (i64, i64),
    /// Twice the largest triangle's area in units of `2^-2 BITS` pixel, `> 0`.
    den: i64,
    /// The row the channels' bases are at; `u32::MAX` before the first.
    row: u32,
}

impl<const SUB: u32> Gradient<SUB> {
    /// `colour` everywhere.
    pub const fn flat(colour: Colour) -> Self {
        Gradient {
            channels: [
                Channel::flat(colour.r),
                Channel::flat(colour.g),
                Channel::flat(colour.b),
            ],
            anchor: (0, 0),
            den: 1,
            row: u32::MAX,
        }
    }

    /// Fractional bits of the points the planes go through: `SUB`, within `1..=`
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

    /// The gradient of the polygon `points` (at least three, convex, in the fill's order,
    /// either winding) whose vertex `i` has colour `colours[i]` (extra entries of either slice
    /// are ignored). Flat, of the first colour, for fewer than three, when all the colours are
    /// equal, when the polygon has no area (it draws nothing), and for a point outside
    /// `0..=`[`GRADIENT_LIMIT`] pixels.
    pub fn new(points: &[FixedPoint<SUB>], colours: &[Colour]) -> Self {
        let n = points.len().min(colours.len());
        let points = points.get(..n).unwrap_or(&[]);
        Self::of(points, |i| colours.get(i).copied().unwrap_or_default())
    }

    /// [`Self::new`] with vertex `i`'s colour `colour(i)`, asked only for the vertices the
    /// planes go through (and each vertex once to see whether all are equal): the renderer
    /// computes a clipped point's colour only when it is needed.
    pub fn of(points: &[FixedPoint<SUB>], colour: impl Fn(usize) -> Colour) -> Self {
        const {
            assert!(
                SUB <= MAX_SUBPIXEL_BITS,
                "SUB must be at most MAX_SUBPIXEL_BITS"
            );
        }
        let n = points.len();
        let first = colour(0);
        if n < 3 {
            return Self::flat(first);
        }
        let limit = i64::from(GRADIENT_LIMIT) << Self::BITS;
        let inside = |&p: &FixedPoint<SUB>| {
            let (x, y) = Self::point(p);
            (0..=limit).contains(&x) && (0..=limit).contains(&y)
        };
        if (1..n).all(|i| colour(i) == first) || !points.iter().all(inside) {
            return Self::flat(first);
        }
        let point = |i: usize| points.get(i).map_or((0, 0), |&p| Self::point(p));
        let Some(([i, mut j, mut k], area)) = largest_triangle(n, point) else {
            return Self::flat(first);
        };
        if area < 0 {
            core::mem::swap(&mut j, &mut k);
        }
        let den = area.abs();
        let (p0, p1, p2) = (point(i), point(j), point(k));
        let (c0, c1, c2) = (colour(i), colour(j), colour(k));
        let d1 = (p1.0 - p0.0, p1.1 - p0.1);
        let d2 = (p2.0 - p0.0, p2.1 - p0.1);
        let scale = 1 << (Self::BITS + F);
        let plane = |a: u8, b: u8, c: u8| channel(scale, a, b, c, d1, d2, den);
        Gradient {
            channels: [
                plane(c0.r, c1.r, c2.r),
                plane(c0.g, c1.g, c2.g),
                plane(c0.b, c1.b, c2.b),
            ],
            anchor: p0,
            den,
            row: u32::MAX,
        }
    }

    /// The colour when every channel is constant (then a flat span draws the polygon).
    pub fn flat_colour(&self) -> Option<Colour> {
        let [r, g, b] = &self.channels;
        let level = |c: &Channel| c.colour as u8;
        (r.is_flat() && g.is_flat() && b.is_flat())
            .then(|| Colour::new(level(r), level(g), level(b)))
    }

    /// The shading of row `y` (rows past [`GRADIENT_LIMIT`] as its last). The next row, or one
    /// a few below, is walked to with an add and a compare a channel and row, any other
    /// computed afresh; the result is the same either way.
    pub fn row(&mut self, y: u32) -> RowShade {
        let y = y.min(GRADIENT_LIMIT - 1);
        match y.checked_sub(self.row) {
            Some(0) => {}
            Some(rows) if rows <= WALK_ROWS => {
                for _ in 0..rows {
                    self.walk();
                }
            }
            _ => self.seek(y),
        }
        self.row = y;
        RowShade {
            base: self.channels.map(|c| c.q),
            step: self.channels.map(|c| c.step),
        }
    }

    /// One row down.
    #[inline]
    fn walk(&mut self) {
        let e = 2 * self.den;
        for c in &mut self.channels {
            c.q = c.q.wrapping_add(c.row_q);
            c.r += c.row_r;
            if c.r >= e {
                c.r -= e;
                c.q = c.q.wrapping_add(1);
            }
        }
    }

    /// The bases of row `y` (at most [`GRADIENT_LIMIT`]` - 1`) from the planes: the value at
    /// `(1/2, y + 1/2)` pixels is `colour + m / den` with `m` below `2^52` in magnitude, and
    /// `floor((m 2^F + den / 2) / den)` is taken in two divisions of `i64`s.
    fn seek(&mut self, y: u32) {
        let half = 1i64 << (Self::BITS - 1);
        let dx = half - self.anchor.0;
        let dy = (2 * i64::from(y) + 1) * half - self.anchor.1;
        let den = self.den;
        for c in &mut self.channels {
            if c.is_flat() {
                continue;
            }
            let (qm, rm) = floor_div_rem(c.nx * dx + c.ny * dy, den);
            // `0 <= rm < den <= 2^42`: the product is below `2^63`.
            let (q2, rho) = floor_div_rem(rm * (1 << F), den);
            // `m 2^F + den / 2 = (qm 2^F + q2) den + rho + den / 2`, over `den`, doubled to
            // stay in integers.
            let q = (c.colour << F)
                .wrapping_add((qm as i32) << F)
                .wrapping_add(q2 as i32);
            (c.q, c.r) = if 2 * rho < den {
                (q, 2 * rho + den)
            } else {
                (q.wrapping_add(1), 2 * rho - den)
            };
        }
    }
}

/// One channel's plane through colours `a`, `b`, `c` at the anchor and at offsets `d1`, `d2`
/// from it (counter-clockwise in screen axes: `den = d1 x d2 > 0`), points of `BITS`
/// fractional bits and `scale = 2^(BITS + F)` (a constant of the caller's, where a shift by
/// a variable would be a library call on a 32-bit core).
fn channel(
    scale: i64,
    a: u8,
    b: u8,
    c: u8,
    (x1, y1): (i64, i64),
    (x2, y2): (i64, i64),
    den: i64,
) -> Channel {
    let (e1, e2) = (i64::from(b) - i64::from(a), i64::from(c) - i64::from(a));
    // The colour at `p` is `a + (nx (p.x - x0) + ny (p.y - y0)) / den`; each below `2^30`.
    let nx = e1 * y2 - e2 * y1;
    let ny = x1 * e2 - x2 * e1;
    if nx == 0 && ny == 0 {
        return Channel::flat(a);
    }
    // Per pixel: `nx 2^BITS / den`, at `F` fraction bits, rounded (halves up).
    let (step, _) = floor_div_rem(2 * nx * scale + den, 2 * den);
    let (row_q, row_rho) = floor_div_rem(ny * scale, den);
    Channel {
        colour: i32::from(a),
        nx,
        ny,
        step: step as i32,
        row_q: row_q as i32,
        row_r: 2 * row_rho,
        q: 0,
        r: 0,
    }
}

/// `(floor(a / b), a - b floor(a / b))` for `b > 0` (a `b` below 1 is taken as 1, which only
/// makes the division provably panic-free).
#[inline]
fn floor_div_rem(a: i64, b: i64) -> (i64, i64) {
    let b = b.max(1);
    let (q, r) = (a / b, a % b);
    if r < 0 {
        (q - 1, r + b)
    } else {
        (q, r)
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
