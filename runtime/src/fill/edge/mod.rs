//! The edge walk: the pixel where an edge crosses each scanline, by integer stepping only (an
//! incremental walk in the manner of Bresenham's, exact for any rational slope).
//!
//! The classic integer walk goes up an edge from its low end `(xbas, ybas)` to its high end
//! `(xhaut, yhaut)` keeping `x` and the numerator `N` of its fractional part over `Δy`; each
//! row does `(Q, N) <- div_euclid(N, Δy); x += Q; N += Δx`, with `N` started at `Δy - 1` on a
//! left edge so the rounding is a ceiling. Here the same walk is written for any rational
//! sequence `x_k = ceil((num + k * step) / den)`: the division of the step by `den` is done
//! once up front (`step = q * den + r`), so a row costs an add and a compare instead of a
//! division, and the state `(x, rem)` after each row is exactly that walk's `(x, N)` after its
//! division.
//!
//! For the fill, `x_k` is the first pixel whose centre is at or right of the crossing at row
//! `j0 + k` (see [`EdgeWalk::for_edge`]). Using that one rounding for left *and* right edges
//! (a span is `[x_left, x_right)`) is what makes two polygons sharing an edge split its pixels
//! exactly: the one on the right owns a centre lying on the edge, the one on the left does not.

//!
//! # Two widths
//!
//! With the `wide-coordinates` feature (default) the walk is kept in `i64` and set up with a
//! 128-bit numerator, so any `i32` coordinates work ([`EdgeWalk::for_edge`]). Without it,
//! `EdgeWalk::for_edge_narrow` sets up the same walk, bit for bit, with 32-bit arithmetic
//! only (a core's hardware divide instead of software 64-bit division), for coordinates in
//! `0..=`[`super::coordinate_limit`]: those of the renderer, which clamps every point to
//! its window and refuses a window beyond that limit. Each width is a file (`wide.rs`,
//! `narrow.rs`) setting up the same [`EdgeWalk`]; the build picks one, and the tests build
//! both to compare them.

use super::FixedPoint;

#[cfg(any(test, not(feature = "wide-coordinates")))]
mod narrow;
#[cfg(feature = "wide-coordinates")]
mod wide;

#[cfg(not(feature = "wide-coordinates"))]
use narrow as width;
#[cfg(feature = "wide-coordinates")]
use wide as width;

/// The integer type of a walk: `i64` with `wide-coordinates`, `i32` without.
pub type Coord = width::Coord;

/// One non-horizontal edge being walked down the scanlines: the fill's own walk, public so
/// that other scanline methods (an active edge list over many polygons) cross each row exactly
/// where the fill does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct EdgeWalk {
    /// First pixel (column) whose centre is at or right of the crossing on row `row`.
    pub(crate) x: Coord,
    /// Numerator of the fractional remainder, `0 <= rem < den`.
    rem: Coord,
    /// Denominator, `> 0`.
    den: Coord,
    /// Whole pixels added per row.
    step_q: Coord,
    /// Remainder added per row, `0 <= step_r < den`.
    step_r: Coord,
    /// The row `x` belongs to.
    pub(crate) row: Coord,
    /// First row past the edge.
    pub(crate) row_end: Coord,
}

/// The first pixel whose centre is at or right of fixed-point coordinate `v`, as a [`Coord`]
/// in the build's width (the renderer's points are within the narrow walk's range).
#[inline]
pub(crate) fn first_centre<const SUB: u32>(v: i32) -> Coord {
    width::first_centre::<SUB>(v)
}

/// The edge's ends, top first; `None` for a horizontal edge (it bounds no span).
fn top_bottom<const SUB: u32>(
    a: FixedPoint<SUB>,
    b: FixedPoint<SUB>,
) -> Option<(FixedPoint<SUB>, FixedPoint<SUB>)> {
    match a.y.cmp(&b.y) {
        core::cmp::Ordering::Less => Some((a, b)),
        core::cmp::Ordering::Greater => Some((b, a)),
        core::cmp::Ordering::Equal => None,
    }
}

impl EdgeWalk {
    /// All zero: an unused slot (the [`Default`], usable in `const` context).
    pub(crate) const ZERO: EdgeWalk = EdgeWalk {
        x: 0,
        rem: 0,
        den: 0,
        step_q: 0,
        step_r: 0,
        row: 0,
        row_end: 0,
    };

    /// The walk of the edge `a`-`b` (either direction) over the scanlines whose centre `y`
    /// satisfies `y_top <= y < y_bottom`, restricted to rows `0..height`, in the build's
    /// width. `None` for a horizontal edge or one that crosses no such row.
    #[inline]
    pub(crate) fn for_edge<const SUB: u32>(
        a: FixedPoint<SUB>,
        b: FixedPoint<SUB>,
        height: u32,
    ) -> Option<Self> {
        width::walk::<SUB>(a, b, height)
    }

    /// The walk of the edge `a`-`b` (either direction, points in the fill's range, see
    /// [`super::coordinate_limit`]) over the rows `0..height` whose centre it crosses by the
    /// fill's rule; `None` for a horizontal edge or one that crosses none.
    #[inline]
    pub fn new<const SUB: u32>(
        a: FixedPoint<SUB>,
        b: FixedPoint<SUB>,
        height: u32,
    ) -> Option<Self> {
        Self::for_edge::<SUB>(a, b, height)
    }

    /// The first pixel whose centre is at or right of the crossing with row [`Self::row`]
    /// (a span is `[left.x(), right.x())`).
    #[inline]
    pub fn x(&self) -> Coord {
        self.x
    }

    /// The row the walk is on.
    #[inline]
    pub fn row(&self) -> Coord {
        self.row
    }

    /// The first row past the edge.
    #[inline]
    pub fn row_end(&self) -> Coord {
        self.row_end
    }

    /// Move to the next row.
    #[inline]
    pub fn step(&mut self) {
        self.step_x();
        self.row += 1;
    }

    /// [`Self::step`] of the crossing alone, for a caller counting the rows itself.
    #[inline]
    pub(crate) fn step_x(&mut self) {
        self.x += self.step_q;
        self.rem += self.step_r;
        if self.rem >= self.den {
            self.rem -= self.den;
            self.x += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    #[allow(unused_imports)]
    use super::narrow::first_centre_narrow;
    #[cfg(feature = "wide-coordinates")]
    #[allow(unused_imports)]
    use super::wide::first_centre_at_or_after;
    use super::*;

    use proptest::prelude::*;

    fn xs(mut walk: EdgeWalk) -> ([Coord; 16], usize) {
        let mut out = [0; 16];
        let mut n = 0;
        while walk.row < walk.row_end {
            out[n] = walk.x;
            n += 1;
            walk.step();
        }
        (out, n)
    }

    /// A worked example of the classic walk: left edge (3, 0)-(7, 10) with pixels on integer
    /// points: x = 3 + 0.4 y is displayed as 3,4,4,5,5,5,6,6,7,7, with N = 9,3,7,1,5,9 after
    /// each division (worked by hand).
    #[cfg(feature = "wide-coordinates")]
    #[test]
    fn classic_walk_worked_example() {
        let (xbas, ybas, xhaut, yhaut) = (3i64, 0i64, 7i64, 10i64);
        let (dx, dy) = (xhaut - xbas, yhaut - ybas);
        let mut walk = EdgeWalk::from_ratio(i128::from(xbas * dy), dy, dx, ybas, yhaut);
        let mut n = [0; 10];
        let mut x = [0; 10];
        for k in 0..10 {
            x[k] = walk.x;
            n[k] = walk.rem();
            walk.step();
        }
        assert_eq!(x, [3, 4, 4, 5, 5, 5, 6, 6, 7, 7]);
        assert_eq!(n[..6], [9, 3, 7, 1, 5, 9]);
    }

    /// The fill's walk at SUB = 0 on the same edge (3, 0)-(7, 10), whose vertices are now
    /// pixel *corners*: the crossings at y = j + 1/2 are x = 3.2, 3.6, 4.0, 4.4, ..., 6.8, and
    /// the first pixel with centre i + 1/2 >= x is ceil(x - 1/2) = 3,4,4,4,5,5,6,6,6,7 (4.0
    /// lies on the centre 3.5 + 1/2, so pixel 4 is the first one: a left edge is drawn).
    #[test]
    fn fill_walk_sub0_same_edge() {
        let a = FixedPoint { x: 3, y: 0 };
        let b = FixedPoint { x: 7, y: 10 };
        let (got, n) = xs(EdgeWalk::for_edge::<0>(a, b, 100).unwrap());
        assert_eq!(got[..n], [3, 4, 4, 4, 5, 5, 6, 6, 6, 7]);
        // Either direction gives the same walk (shared edges must agree).
        assert_eq!(
            EdgeWalk::for_edge::<0>(b, a, 100),
            EdgeWalk::for_edge::<0>(a, b, 100)
        );
    }

    /// The classic walk's lattice (pixels on integer points) is the pixel-centre lattice
    /// shifted by half a pixel: at SUB = 1 the edge (3.5, 0.5)-(7.5, 10.5) reproduces the
    /// worked example's sequence exactly.
    #[test]
    fn fill_walk_is_the_classic_walk_shifted_by_half_a_pixel() {
        let a = FixedPoint { x: 7, y: 1 };
        let b = FixedPoint { x: 15, y: 21 };
        let (got, n) = xs(EdgeWalk::for_edge::<1>(a, b, 100).unwrap());
        assert_eq!(got[..n], [3, 4, 4, 5, 5, 5, 6, 6, 7, 7]);
    }

    #[test]
    fn negative_slope_and_rows() {
        // (10, 0) -> (0, 5) at SUB = 0: x = 10 - 2 (j + 1/2) = 9, 7, 5, 3, 1 -> ceil(x - 1/2).
        let (got, n) =
            xs(
                EdgeWalk::for_edge::<0>(FixedPoint { x: 10, y: 0 }, FixedPoint { x: 0, y: 5 }, 100)
                    .unwrap(),
            );
        assert_eq!(got[..n], [9, 7, 5, 3, 1]);
    }

    #[test]
    fn rows_are_half_open_and_clamped() {
        // SUB = 2 (S = 4): y from 2 (0.5, row 0's centre, included) to 10 (2.5, row 2's
        // centre, excluded) -> rows 0 and 1.
        let w = EdgeWalk::for_edge::<2>(FixedPoint { x: 0, y: 2 }, FixedPoint { x: 0, y: 10 }, 100)
            .unwrap();
        assert_eq!((w.row, w.row_end), (0, 2));
        // Just below a centre: y from 3 -> row 1 first.
        let w = EdgeWalk::for_edge::<2>(FixedPoint { x: 0, y: 3 }, FixedPoint { x: 0, y: 11 }, 100)
            .unwrap();
        assert_eq!((w.row, w.row_end), (1, 3));
        // Clamped to the window, and the start x is that of the clamped row.
        #[cfg(feature = "wide-coordinates")]
        {
            let (a, b) = (FixedPoint { x: 0, y: -10 }, FixedPoint { x: 20, y: 10 });
            let w = EdgeWalk::for_edge::<0>(a, b, 5).unwrap();
            assert_eq!((w.row, w.row_end, w.x), (0, 5, 10));
        }
        let (a, b) = (FixedPoint { x: 0, y: 0 }, FixedPoint { x: 20, y: 20 });
        let w = EdgeWalk::for_edge::<0>(a, b, 5).unwrap();
        assert_eq!((w.row, w.row_end, w.x), (0, 5, 0));
        // Between two centres, and horizontal: nothing.
        assert!(
            EdgeWalk::for_edge::<2>(FixedPoint { x: 0, y: 3 }, FixedPoint { x: 9, y: 5 }, 9)
                .is_none()
        );
        assert!(
            EdgeWalk::for_edge::<0>(FixedPoint { x: 0, y: 3 }, FixedPoint { x: 9, y: 3 }, 9)
                .is_none()
        );
    }

    #[cfg(feature = "wide-coordinates")]
    #[test]
    fn extreme_coordinates_do_not_overflow() {
        let a = FixedPoint {
            x: i32::MIN,
            y: i32::MIN,
        };
        let b = FixedPoint {
            x: i32::MAX,
            y: i32::MAX,
        };
        let mut w = EdgeWalk::for_edge::<24>(a, b, 1 << 15).unwrap();
        while w.row < w.row_end {
            w.step();
        }
        let (b, c) = (FixedPoint::new(b.x, b.y), FixedPoint { x: i32::MIN, y: 0 });
        let mut w = EdgeWalk::for_edge::<0>(b, c, 1 << 15).unwrap();
        assert!(w.x < -(1 << 30));
        while w.row < w.row_end {
            w.step();
        }
    }

    /// The pixel of row `j` straight from the definition (see [`EdgeWalk::for_edge`]), in
    /// 128-bit arithmetic: `ceil(num_j / den)`.
    fn reference_x<const SUB: u32>(a: FixedPoint<SUB>, b: FixedPoint<SUB>, j: i128) -> i128 {
        let (top, bottom) = if a.y < b.y { (a, b) } else { (b, a) };
        let s = 1i128 << SUB;
        let (ty, tx) = (i128::from(top.y), i128::from(top.x));
        let dy = i128::from(bottom.y) - ty;
        let dx = i128::from(bottom.x) - tx;
        let num = (2 * tx - s) * dy + dx * ((2 * j + 1) * s - 2 * ty);
        let den = 2 * s * dy;
        num.div_euclid(den) + i128::from(num.rem_euclid(den) != 0)
    }

    /// The narrow walk against the definition, row by row, and (when both exist) field for
    /// field against the wide walk.
    fn check_narrow<const SUB: u32>(a: FixedPoint<SUB>, b: FixedPoint<SUB>, height: u32) {
        let narrow = EdgeWalk::for_edge_narrow::<SUB>(a, b, height);
        #[cfg(feature = "wide-coordinates")]
        assert_eq!(
            narrow,
            EdgeWalk::for_edge::<SUB>(a, b, height),
            "{a:?} {b:?}"
        );
        let s = 1i128 << SUB;
        let centre = |v: i32| (2 * i128::from(v) + s - 1).div_euclid(2 * s);
        let first = centre(a.y.min(b.y)).max(0);
        let end = centre(a.y.max(b.y)).min(i128::from(height));
        let Some(mut walk) = narrow else {
            assert!(first >= end, "{a:?} {b:?}: no walk for rows {first}..{end}");
            return;
        };
        assert_eq!(
            (i128::from(walk.row), i128::from(walk.row_end)),
            (first, end)
        );
        // The first rows (up to 2048): the set-up is what the narrow range is about; a step
        // is the same add-and-compare in both widths.
        let mut j = first;
        while j < end.min(first + 2048) {
            assert_eq!(
                i128::from(walk.x),
                reference_x::<SUB>(a, b, j),
                "{a:?} {b:?} row {j}"
            );
            assert!(0 <= walk.rem && walk.rem < walk.den);
            walk.step();
            j += 1;
        }
    }

    fn coordinates_within(limit: i32) -> impl Strategy<Value = (i32, i32)> {
        let c = move || prop_oneof![0..=limit, 0..=limit.min(4096), Just(0), Just(limit)];
        (c(), c())
    }

    /// `(x, y)` reduced modulo `l + 1`, as a point.
    fn wrapped<const SUB: u32>((x, y): (i32, i32), l: i32) -> FixedPoint<SUB> {
        FixedPoint::new(x % (l + 1), y % (l + 1))
    }

    proptest! {
        #[test]
        fn narrow_walk_is_exact_sub8(
            a in coordinates_within(crate::fill::coordinate_limit::<8>().min((1 << 21) - 1)),
            b in coordinates_within((1 << 21) - 1),
            height in 1u32..3000,
        ) {
            let (a, b) = (FixedPoint::new(a.0, a.1), FixedPoint::new(b.0, b.1));
            check_narrow::<8>(a, b, height);
        }

        #[test]
        fn narrow_walk_is_exact_other_precisions(
            a in coordinates_within((1 << 29) - 1),
            b in coordinates_within((1 << 29) - 1),
            height in 1u32..3000,
        ) {
            let (l4, l0, l24) = ((1 << 25) - 1, (1 << 29) - 1, (1 << 5) - 1);
            check_narrow::<4>(wrapped(a, l4), wrapped(b, l4), height);
            check_narrow::<0>(wrapped(a, l0), wrapped(b, l0), height);
            check_narrow::<24>(wrapped(a, l24), wrapped(b, l24), height);
        }
    }

    /// The corners of the narrow range, where the arithmetic is tightest.
    #[test]
    fn narrow_walk_at_the_limits() {
        fn corners<const SUB: u32>() {
            let l = (1i32 << (29 - SUB)) - 1;
            let vals = [0, 1, l / 2, l - 1, l];
            for &ax in &vals {
                for &ay in &vals {
                    for &bx in &vals {
                        for &by in &vals {
                            let (a, b) = (FixedPoint { x: ax, y: ay }, FixedPoint { x: bx, y: by });
                            check_narrow::<SUB>(a, b, 40);
                            check_narrow::<SUB>(a, b, u32::MAX);
                        }
                    }
                }
            }
        }
        corners::<0>();
        corners::<8>();
        corners::<24>();
    }
}
