//! The gradient against `f64` evaluations of its plane, through the fill's own spans:
//! corners on pixel centres, random convex polygons, cuts, every precision, flat cases and
//! clamping.

extern crate std;

use std::collections::BTreeMap;
use std::vec::Vec;

use proptest::prelude::*;

use super::*;
use crate::display::SpanSink;
use crate::fill::fill_polygon;
use crate::fill::SUBPIXEL_BITS;

/// The renderer's precision.
const S: u32 = SUBPIXEL_BITS;

/// White: a pixel's colour is its intensity.
const WHITE: Colour = Colour::grey(255);

/// Each pixel of `points` filled, with the intensity `gradient` gives it.
fn levels<const SUB: u32>(
    points: &[FixedPoint<SUB>],
    gradient: &Gradient<SUB>,
) -> BTreeMap<(u32, u32), u8> {
    struct Levels<'g, const SUB: u32>(&'g Gradient<SUB>, BTreeMap<(u32, u32), u8>);
    impl<const SUB: u32> SpanSink for Levels<'_, SUB> {
        fn span(&mut self, y: u32, x_start: u32, x_end: u32, _: Colour) {
            let shade = self.0.row(y);
            for (x, c) in (x_start..x_end).zip(shade.colours(x_start)) {
                assert!(self.1.insert((x, y), c.r).is_none(), "({x}, {y}) twice");
            }
        }
    }
    let mut sink = Levels(gradient, BTreeMap::new());
    fill_polygon(
        points,
        GRADIENT_LIMIT,
        GRADIENT_LIMIT,
        Colour::default(),
        &mut sink,
    )
    .unwrap();
    sink.1
}

/// A point's raw coordinates.
fn xy<const SUB: u32>(p: FixedPoint<SUB>) -> (i64, i64) {
    (i64::from(p.x), i64::from(p.y))
}

/// The point at the centre of pixel `(x, y)`.
fn centre(x: i32, y: i32) -> FixedPoint<S> {
    let half = 1 << (S - 1);
    FixedPoint::new((x << S) + half, (y << S) + half)
}

/// The plane through three points and intensities, at pixel `(x, y)`'s centre, in `f64`.
fn plane(p: [FixedPoint<S>; 3], s: [u8; 3], x: u32, y: u32) -> f64 {
    let f = |v: i32| f64::from(v) / f64::from(1u32 << S);
    let (x0, y0) = (f(p[0].x), f(p[0].y));
    let (x1, y1) = (f(p[1].x) - x0, f(p[1].y) - y0);
    let (x2, y2) = (f(p[2].x) - x0, f(p[2].y) - y0);
    let (e1, e2) = (
        f64::from(s[1]) - f64::from(s[0]),
        f64::from(s[2]) - f64::from(s[0]),
    );
    let den = x1 * y2 - x2 * y1;
    let (nx, ny) = (e1 * y2 - e2 * y1, x1 * e2 - x2 * e1);
    let (dx, dy) = (f64::from(x) + 0.5 - x0, f64::from(y) + 0.5 - y0);
    f64::from(s[0]) + (nx * dx + ny * dy) / den
}

/// Whether `got` is `value` rounded (halves up) and clamped: equal, or one off where the
/// value lies within `1/64` of a half (the slopes' reciprocal and rounding err far less).
fn rounds(got: u8, value: f64) -> bool {
    let expected = libm::floor(value + 0.5).clamp(0.0, 255.0);
    let near_half = (value - libm::floor(value) - 0.5).abs() <= 1.0 / 64.0;
    let off = (f64::from(got) - expected).abs();
    off == 0.0 || (near_half && off <= 1.0)
}

/// Every triangle of largest area of `points` (by brute force).
fn largest_triangles(points: &[FixedPoint<S>]) -> (i64, Vec<[usize; 3]>) {
    let n = points.len();
    let mut best = (0, Vec::new());
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let a = doubled_area(xy(points[i]), xy(points[j]), xy(points[k])).abs();
                if a > best.0 {
                    best = (a, Vec::new());
                }
                if a == best.0 {
                    best.1.push([i, j, k]);
                }
            }
        }
    }
    best
}

/// The convex hull of `points` (Andrew's monotone chain), counter-clockwise in screen axes,
/// without collinear points.
fn hull<T: Copy>(mut points: Vec<((i64, i64), T)>) -> Vec<((i64, i64), T)> {
    points.sort_by_key(|p| p.0);
    points.dedup_by_key(|p| p.0);
    if points.len() < 3 {
        return points;
    }
    let cross = |o: (i64, i64), a: (i64, i64), b: (i64, i64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut h: Vec<((i64, i64), T)> = Vec::new();
    for pass in 0..2 {
        let start = h.len();
        let iter: Vec<_> = if pass == 0 {
            points.clone()
        } else {
            points.iter().rev().copied().collect()
        };
        for p in iter {
            while h.len() >= start + 2 && cross(h[h.len() - 2].0, h[h.len() - 1].0, p.0) <= 0 {
                h.pop();
            }
            h.push(p);
        }
        h.pop();
    }
    h
}

/// A convex polygon of up to `n` points in a box of `extent` pixels placed anywhere in the
/// gradient's extent, with an intensity each.
fn convex_polygon(n: usize, extent: i32) -> impl Strategy<Value = (Vec<FixedPoint<S>>, Vec<u8>)> {
    // Below the narrow fill's limit, so that the test runs in every build.
    let limit = ((GRADIENT_LIMIT as i32 - extent) << S) - 1;
    (
        (0..=limit, 0..=limit),
        proptest::collection::vec(((0..=extent << S, 0..=extent << S), any::<u8>()), 3..=n),
    )
        .prop_map(|((ox, oy), points)| {
            let points = points
                .into_iter()
                .map(|((x, y), s)| ((i64::from(x + ox), i64::from(y + oy)), s))
                .collect();
            hull(points)
                .into_iter()
                .map(|((x, y), s)| (FixedPoint::new(x as i32, y as i32), s))
                .unzip()
        })
}

/// A triangle whose corners lie on pixel centres has their intensities there, however far
/// from column 0 and row 0, and a colour is the material's times its intensity.
#[test]
fn a_corner_on_a_pixel_centre_has_its_intensity() {
    let cases = [
        ([(2, 3), (20, 9), (7, 30)], [255, 0, 128]),
        ([(8000, 8100), (8150, 8010), (8020, 8180)], [3, 250, 77]),
        ([(100, 7000), (101, 7000), (100, 7001)], [0, 255, 9]),
    ];
    for (corners, s) in cases {
        let points = corners.map(|(x, y)| centre(x, y));
        let kd = Colour::new(200, 120, 40);
        let gradient = Gradient::of(&points, kd, |i| s[i]);
        for ((x, y), level) in corners.into_iter().zip(s) {
            assert_eq!(
                gradient.row(y as u32).at(x as u32),
                shaded(kd, level),
                "{corners:?}"
            );
        }
        assert_eq!(gradient.flat_colour(), None);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Every pixel of a random convex polygon is its plane's intensity rounded (the plane
    /// through the polygon's largest triangle), anywhere in the gradient's extent.
    #[test]
    fn every_pixel_against_the_plane((points, s) in convex_polygon(8, 40)) {
        let gradient = Gradient::of(&points, WHITE, |i| s[i]);
        let Some(([i, j, k], _)) = largest_triangle(points.len(), |i| xy(points[i])) else {
            return Ok(());
        };
        let corners = [points[i], points[j], points[k]];
        let levels_at = [s[i], s[j], s[k]];
        if gradient.flat_colour().is_some() {
            // Flat: one intensity, or a sliver steeper than 2^12 levels a pixel.
            let at = |x, y| plane(corners, levels_at, x, y);
            let steepest = (at(1, 0) - at(0, 0)).abs().max((at(0, 1) - at(0, 0)).abs());
            prop_assert!(
                s.iter().all(|&v| v == s[0])
                    || levels_at.iter().all(|&v| v == s[0])
                    || steepest > 4095.0,
                "flat at {steepest} levels a pixel"
            );
            return Ok(());
        }
        for ((x, y), got) in levels(&points, &gradient) {
            let value = plane(corners, levels_at, x, y);
            prop_assert!(rounds(got, value), "({x}, {y}): {got} for {value}");
        }
    }

    /// The largest triangle search against brute force, on convex polygons of many points,
    /// some repeated (as clipping and snapping can leave them).
    #[test]
    fn the_largest_triangle(
        (points, _) in convex_polygon(24, 300),
        repeats in proptest::collection::vec(any::<prop::sample::Index>(), 0..6),
    ) {
        let mut points = points;
        for at in repeats {
            let i = at.index(points.len());
            points.insert(i, points[i]);
        }
        let (area, _) = largest_triangles(&points);
        match largest_triangle(points.len(), |i| xy(points[i])) {
            Some(([i, j, k], signed)) => {
                prop_assert!(i < j && j < k && k < points.len());
                prop_assert_eq!(signed, doubled_area(xy(points[i]), xy(points[j]), xy(points[k])));
                prop_assert_eq!(signed.abs(), area);
            }
            None => prop_assert_eq!(area, 0),
        }
    }

}

/// A triangle cut in two along a line through a corner: each piece's new corner takes the
/// whole's intensity there, rounded, and every pixel is within a level of the whole's.
#[test]
fn a_triangle_cut_in_two() {
    let (a, b, c) = (centre(10, 10), centre(90, 20), centre(30, 70));
    let s = [8u8, 248, 100];
    let whole = levels(&[a, b, c], &Gradient::of(&[a, b, c], WHITE, |i| s[i]));
    let m = FixedPoint::<S>::new((b.x + c.x) / 2, (b.y + c.y) / 2);
    let sm = (u16::from(s[1]) + u16::from(s[2])).div_ceil(2) as u8;
    let mut pieces = levels(
        &[a, b, m],
        &Gradient::of(&[a, b, m], WHITE, |i| [s[0], s[1], sm][i]),
    );
    pieces.extend(levels(
        &[a, m, c],
        &Gradient::of(&[a, m, c], WHITE, |i| [s[0], sm, s[2]][i]),
    ));
    assert_eq!(pieces.len(), whole.len());
    for (at, level) in &whole {
        assert!(
            pieces[at].abs_diff(*level) <= 1,
            "{at:?}: {} against {level}",
            pieces[at]
        );
    }
}

/// The same triangle at every precision the fill takes shades within a level alike.
#[test]
fn every_precision_shades_alike() {
    fn at<const SUB: u32>(corners: &[(i32, i32); 3]) -> [FixedPoint<SUB>; 3] {
        corners.map(|(x, y)| FixedPoint::new(x << SUB, y << SUB))
    }
    let corners = [(3, 2), (60, 11), (17, 44)];
    let s = [30u8, 220, 140];
    let reference = levels(
        &at::<S>(&corners),
        &Gradient::of(&at::<S>(&corners), WHITE, |i| s[i]),
    );
    fn check<const SUB: u32>(
        corners: &[(i32, i32); 3],
        s: [u8; 3],
        reference: &BTreeMap<(u32, u32), u8>,
    ) {
        let points = at::<SUB>(corners);
        let got = levels(&points, &Gradient::of(&points, WHITE, |i| s[i]));
        assert_eq!(got.len(), reference.len(), "SUB {SUB}");
        for (p, level) in got {
            assert!(level.abs_diff(reference[&p]) <= 1, "SUB {SUB} {p:?}");
        }
    }
    check::<0>(&corners, s, &reference);
    check::<2>(&corners, s, &reference);
    check::<4>(&corners, s, &reference);
    check::<8>(&corners, s, &reference);
}

/// Flat: equal intensities, fewer than three points, no area, a point outside the extent,
/// a sliver steeper than 2^12 levels a pixel; each at its first corner's intensity.
#[test]
fn flat_cases() {
    let kd = Colour::new(10, 200, 90);
    let flat = |g: Gradient<S>| g.flat_colour();
    let triangle = [centre(1, 1), centre(30, 2), centre(5, 40)];
    assert_eq!(
        flat(Gradient::of(&triangle, kd, |_| 77)),
        Some(shaded(kd, 77))
    );
    assert_eq!(
        flat(Gradient::of(&triangle[..2], kd, |i| [9, 200][i])),
        Some(shaded(kd, 9))
    );
    let line = [centre(1, 1), centre(2, 2), centre(3, 3)];
    assert_eq!(
        flat(Gradient::of(&line, kd, |i| [9, 200, 3][i])),
        Some(shaded(kd, 9))
    );
    let outside = [
        centre(1, 1),
        FixedPoint::new(((GRADIENT_LIMIT as i32) + 1) << S, 0),
        centre(5, 40),
    ];
    assert_eq!(
        flat(Gradient::of(&outside, kd, |i| [9, 200, 3][i])),
        Some(shaded(kd, 9))
    );
    let sliver = [
        FixedPoint::new(0, 0),
        FixedPoint::new(8000 << S, 1),
        FixedPoint::new(8000 << S, 2),
    ];
    assert_eq!(
        flat(Gradient::of(&sliver, kd, |i| [0, 255, 0][i])),
        Some(shaded(kd, 0))
    );
    // A steep plane that is not a sliver stays a gradient, and a flat one fills flat.
    assert_eq!(flat(Gradient::of(&triangle, kd, |i| [0, 255, 0][i])), None);
    assert_eq!(Gradient::<S>::flat(kd, 255).row(5).at(9), kd);
}

/// Where a polygon of four corners is shaded by the plane of three (here corners 0, 1 and
/// 3), the fourth corner's neighbourhood takes the plane beyond `0..=255`: the pixels there
/// clamp instead of wrapping.
#[test]
fn past_the_range_clamps() {
    let points = [centre(0, 0), centre(40, 0), centre(40, 40), centre(0, 40)];
    for (s, far) in [([0u8, 200, 0, 200], 255u8), ([255, 55, 255, 55], 0)] {
        let gradient = Gradient::of(&points, WHITE, |i| s[i]);
        let got = levels(&points, &gradient);
        assert_eq!(got[&(39, 39)], far, "{s:?}");
        assert_eq!(got[&(0, 0)], s[0], "{s:?}");
    }
}
