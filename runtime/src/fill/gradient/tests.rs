//! The gradient against exact and `f64` evaluations of its plane, through the fill's own
//! spans: vertices, random convex polygons, cuts, flat cases, the row walk and the drift
//! across the widest row.

extern crate std;

use std::collections::BTreeMap;
use std::vec;
use std::vec::Vec;

use proptest::prelude::*;

use super::*;
use crate::display::SpanSink;
use crate::fill::fill_polygon;

/// The renderer's precision.
const S: u32 = SUBPIXEL_BITS;

/// The pixels a fill draws, in order: `(x, y)`.
#[derive(Default)]
struct Pixels(Vec<(u32, u32)>);

impl SpanSink for Pixels {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, _: Colour) {
        self.0.extend((x_start..x_end).map(|x| (x, y)));
    }
}

/// The pixels of `points` by the fill, within the gradient's whole extent.
fn pixels(points: &[FixedPoint<S>]) -> Vec<(u32, u32)> {
    let mut sink = Pixels::default();
    fill_polygon(
        points,
        GRADIENT_LIMIT,
        GRADIENT_LIMIT,
        Colour::default(),
        &mut sink,
    )
    .unwrap();
    sink.0
}

/// What the next stage does with a shaded polygon: each span of the fill handed on with its
/// row's shade. Collects the pixels' colours.
struct Shaded<'g> {
    gradient: &'g mut Gradient<S>,
    image: BTreeMap<(u32, u32), Colour>,
}

impl SpanSink for Shaded<'_> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, _: Colour) {
        let shade = self.gradient.row(y);
        for (x, colour) in (x_start..x_end).zip(shade.colours(x_start)) {
            assert!(
                self.image.insert((x, y), colour).is_none(),
                "({x}, {y}) twice"
            );
        }
    }
}

/// The shaded image of each polygon in turn, into one map (pieces of a cut must not overlap).
fn shade_all(polygons: &[(Vec<FixedPoint<S>>, Vec<Colour>)]) -> BTreeMap<(u32, u32), Colour> {
    let mut image = BTreeMap::new();
    for (points, colours) in polygons {
        let mut gradient = Gradient::new(points, colours);
        let mut sink = Shaded {
            gradient: &mut gradient,
            image: core::mem::take(&mut image),
        };
        fill_polygon(
            points,
            GRADIENT_LIMIT,
            GRADIENT_LIMIT,
            Colour::default(),
            &mut sink,
        )
        .unwrap();
        image = sink.image;
    }
    image
}

/// A point's raw coordinates.
fn xy<const SUB: u32>(p: FixedPoint<SUB>) -> (i64, i64) {
    (i64::from(p.x), i64::from(p.y))
}

/// Whether three points span an area.
fn has_area(p: &[FixedPoint<S>; 3]) -> bool {
    doubled_area(xy(p[0]), xy(p[1]), xy(p[2])) != 0
}

fn channels(c: Colour) -> [u8; 3] {
    [c.r, c.g, c.b]
}

/// The point at the centre of pixel `(x, y)`.
fn centre(x: i32, y: i32) -> FixedPoint<S> {
    let half = 1 << (S - 1);
    FixedPoint::new((x << S) + half, (y << S) + half)
}

/// A plane of the test, exact: the value at `p` is
/// `colour + (nx (p.x - x0) + ny (p.y - y0)) / den`, from three points and colours.
#[derive(Debug, Clone, Copy)]
struct Plane {
    anchor: (i128, i128),
    colour: [i128; 3],
    nx: [i128; 3],
    ny: [i128; 3],
    den: i128,
}

impl Plane {
    fn new(p: [FixedPoint<S>; 3], c: [Colour; 3]) -> Self {
        let (x1, y1) = (i128::from(p[1].x - p[0].x), i128::from(p[1].y - p[0].y));
        let (x2, y2) = (i128::from(p[2].x - p[0].x), i128::from(p[2].y - p[0].y));
        let den = x1 * y2 - x2 * y1;
        // `den > 0`: the other winding flips the signs of all three.
        let sign = den.signum();
        let [c0, c1, c2] = c.map(|c| channels(c).map(i128::from));
        let e1: [i128; 3] = core::array::from_fn(|i| c1[i] - c0[i]);
        let e2: [i128; 3] = core::array::from_fn(|i| c2[i] - c0[i]);
        Plane {
            anchor: (i128::from(p[0].x), i128::from(p[0].y)),
            colour: c0,
            nx: core::array::from_fn(|i| sign * (e1[i] * y2 - e2[i] * y1)),
            ny: core::array::from_fn(|i| sign * (x1 * e2[i] - x2 * e1[i])),
            den: den.abs(),
        }
    }

    /// The value at pixel `(x, y)`'s centre times `den 2^F` (`den > 0`), exactly.
    fn scaled(&self, x: u32, y: u32, i: usize) -> i128 {
        let half = 1i128 << (S - 1);
        let (px, py) = ((i128::from(x) << S) + half, (i128::from(y) << S) + half);
        (self.colour[i] * self.den
            + self.nx[i] * (px - self.anchor.0)
            + self.ny[i] * (py - self.anchor.1))
            << F
    }

    /// The value at pixel `(x, y)`'s centre in `f64`.
    fn f64(&self, x: u32, y: u32, i: usize) -> f64 {
        let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
        let scale = f64::from(1u32 << S);
        let (dx, dy) = (
            px * scale - self.anchor.0 as f64,
            py * scale - self.anchor.1 as f64,
        );
        self.colour[i] as f64 + (self.nx[i] as f64 * dx + self.ny[i] as f64 * dy) / self.den as f64
    }
}

/// Whether `got` is the exact `value` rounded (halves up) and clamped, as documented: equal,
/// or one off where the value lies within `1/512` of a half.
fn rounds(got: u8, value: f64) -> bool {
    let expected = libm::floor(value + 0.5).clamp(0.0, 255.0);
    let near_half = (value - libm::floor(value) - 0.5).abs() <= 1.0 / 512.0;
    let off = (f64::from(got) - expected).abs();
    off == 0.0 || (near_half && off <= 1.0)
}

/// The channel values of `shade` at `x`, unrounded (true values when the pixel is the
/// polygon's: they fit an `i32`).
fn raw(shade: &RowShade, x: u32) -> [i32; 3] {
    core::array::from_fn(|i| shade.base[i].wrapping_add(shade.step[i].wrapping_mul(x as i32)))
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

fn colour() -> impl Strategy<Value = Colour> {
    any::<[u8; 3]>().prop_map(|[r, g, b]| Colour::new(r, g, b))
}

/// A convex polygon of up to `n` points in a box of `extent` pixels placed anywhere in the
/// gradient's extent, with a colour each.
fn convex_polygon(
    n: usize,
    extent: i32,
) -> impl Strategy<Value = (Vec<FixedPoint<S>>, Vec<Colour>)> {
    // Below the narrow fill's limit, so that the test runs in every build.
    let limit = ((GRADIENT_LIMIT as i32 - extent) << S) - 1;
    (
        (0..=limit, 0..=limit),
        proptest::collection::vec(((0..=extent << S, 0..=extent << S), colour()), 3..=n),
    )
        .prop_map(|((ox, oy), points)| {
            let points = points
                .into_iter()
                .map(|((x, y), c)| ((i64::from(x + ox), i64::from(y + oy)), c))
                .collect();
            hull(points)
                .into_iter()
                .map(|((x, y), c)| (FixedPoint::new(x as i32, y as i32), c))
                .unzip()
        })
}

// ------------------------------------------------------------------------------ vertices

/// A triangle whose vertices lie on pixel centres has their colours there, exactly, however
/// far from column 0 and from the first row asked for.
#[test]
fn a_vertex_on_a_pixel_centre_has_its_colour() {
    let cases = [
        (
            [(2, 3), (20, 9), (7, 30)],
            [(255, 0, 0), (0, 255, 0), (0, 0, 255)],
        ),
        (
            [(8000, 10), (8191, 400), (7950, 8191)],
            [(1, 2, 3), (254, 128, 7), (90, 91, 92)],
        ),
        (
            [(0, 0), (1, 0), (0, 1)],
            [(0, 0, 0), (255, 255, 255), (17, 200, 255)],
        ),
    ];
    for (at, colours) in cases {
        let points = at.map(|(x, y)| centre(x, y));
        let colours = colours.map(|(r, g, b)| Colour::new(r, g, b));
        let mut gradient = Gradient::new(&points, &colours);
        // Rows out of order: each is walked to or computed afresh.
        for (&(x, y), &c) in at.iter().zip(&colours).rev() {
            assert_eq!(
                gradient.row(y as u32).at(x as u32),
                c,
                "{at:?} at ({x}, {y})"
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]

    #[test]
    fn random_vertices_on_pixel_centres(
        at in proptest::array::uniform3((0..GRADIENT_LIMIT as i32, 0..GRADIENT_LIMIT as i32)),
        colours in proptest::array::uniform3(colour()),
    ) {
        let points = at.map(|(x, y)| centre(x, y));
        prop_assume!(has_area(&points));
        let mut gradient = Gradient::new(&points, &colours);
        for (&(x, y), &c) in at.iter().zip(&colours) {
            prop_assert_eq!(gradient.row(y as u32).at(x as u32), c);
        }
    }
}

// ------------------------------------------------------------------ against the plane

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    /// On every pixel of a random convex polygon, anywhere in the extent: the rounded colour
    /// is the `f64` plane's through a largest triangle, rounded and clamped, or one off where
    /// the plane is within `1/512` of a half (so never more than one off); and
    /// the unrounded value errs by at most `(x + 1) / 2` units of `2^-F`, as documented.
    #[test]
    fn every_pixel_against_the_plane((points, colours) in convex_polygon(8, 40)) {
        let (area, triangles) = largest_triangles(&points);
        prop_assume!(area > 0);
        let pixels = pixels(&points);
        let mut gradient = Gradient::new(&points, &colours);
        let shades: Vec<RowShade> = pixels.iter().map(|&(_, y)| gradient.row(y)).collect();
        // Ties between triangles of equal area: the gradient took one of them.
        let fits = |[i, j, k]: [usize; 3]| {
            let plane = Plane::new([points[i], points[j], points[k]], [colours[i], colours[j], colours[k]]);
            pixels.iter().zip(&shades).all(|(&(x, y), shade)| {
                let got = shade.at(x);
                let value = raw(shade, x);
                (0..3).all(|c| {
                    let close = rounds(channels(got)[c], plane.f64(x, y, c));
                    // |value - exact| <= (x + 1) / 2, scaled by the plane's signed `den`.
                    let error = (i128::from(value[c]) * plane.den - plane.scaled(x, y, c)).abs();
                    close && 2 * error <= (i128::from(x) + 1) * plane.den
                })
            })
        };
        prop_assert!(triangles.into_iter().any(fits), "{points:?} {colours:?}");
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

/// Where a polygon of four vertices is shaded by the plane of three, the fourth's corner
/// takes the plane beyond `0..=255`: the pixels there clamp, including those just past the
/// range, where rounding alone would give `-1` or `256`.
#[test]
fn past_the_range_clamps() {
    // The largest triangle is the first three (uniquely), whose plane is `7 (x - y) / 40`
    // (red) and `255 - 7 (x - y) / 40` (green): at the fourth corner `-3.15` and `258.15`,
    // whatever colour it has.
    let corners = [(0, 0), (40, 0), (40, 40), (2, 20)];
    let points = corners.map(|(x, y)| centre(x, y));
    let colours = [(0, 255), (7, 248), (0, 255), (0, 255)].map(|(r, g)| Colour::new(r, g, 0));
    let plane = Plane::new(
        [points[0], points[1], points[2]],
        [colours[0], colours[1], colours[2]],
    );
    let mut gradient = Gradient::new(&points, &colours);
    let half = 1 << (F - 1);
    let (mut below, mut just_below, mut above, mut just_above) = (0, 0, 0, 0);
    for (x, y) in pixels(&points) {
        let shade = gradient.row(y);
        let got = shade.at(x);
        let value = raw(&shade, x);
        for (c, (&level, &value)) in channels(got).iter().zip(&value).take(2).enumerate() {
            let exact = plane.f64(x, y, c);
            assert!(rounds(level, exact), "({x}, {y}): {got:?}, {exact}");
            if value < -half {
                assert_eq!(level, 0);
                below += 1;
                just_below += usize::from(exact > -1.5);
            }
            if value >= (255 << F) + half {
                assert_eq!(level, 255);
                above += 1;
                just_above += usize::from(exact < 256.5);
            }
        }
    }
    assert!(
        below > 0 && just_below > 0 && above > 0 && just_above > 0,
        "{below} {just_below} {above} {just_above}"
    );
}

// ---------------------------------------------------------------------------- cutting

/// A polygon on the lattice `a + u du + v dv` (colours `c + u cu + v cv`): convex, its colours
/// on one plane, and so are those of any polygon of its lattice points.
fn lattice_polygon() -> impl Strategy<Value = (Vec<FixedPoint<S>>, Vec<Colour>)> {
    let step = || (-(6 << S)..=6 << S, -(6 << S)..=6 << S);
    let slope = || proptest::array::uniform3(-24i32..=24);
    (
        (
            64 << S..=(GRADIENT_LIMIT as i32 - 64) << S,
            64 << S..=(GRADIENT_LIMIT as i32 - 64) << S,
        ),
        step(),
        step(),
        colour(),
        slope(),
        slope(),
        proptest::collection::vec((-4i32..=4, -4i32..=4), 3..12),
    )
        .prop_map(|(a, du, dv, c, cu, cv, uv)| {
            let points = uv
                .into_iter()
                .filter_map(|(u, v)| {
                    let x = a.0 + u * du.0 + v * dv.0;
                    let y = a.1 + u * du.1 + v * dv.1;
                    let level = |i: usize| {
                        u8::try_from(i32::from(channels(c)[i]) + u * cu[i] + v * cv[i]).ok()
                    };
                    let colour = Colour::new(level(0)?, level(1)?, level(2)?);
                    Some(((i64::from(x), i64::from(y)), colour))
                })
                .collect();
            hull(points)
                .into_iter()
                .map(|((x, y), c)| (FixedPoint::new(x as i32, y as i32), c))
                .unzip()
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]

    /// Cut along a diagonal, the two pieces (each its own largest triangle, its own anchor)
    /// shade every pixel exactly as the whole: the rounding depends on the plane alone.
    #[test]
    fn cutting_never_changes_the_shading(
        (points, colours) in lattice_polygon(),
        from in any::<prop::sample::Index>(),
        across in any::<prop::sample::Index>(),
    ) {
        let n = points.len();
        prop_assume!(n >= 4);
        let i = from.index(n);
        let j = (i + 2 + across.index(n - 3)) % n;
        let piece = |from: usize, to: usize| {
            let mut k = from;
            let mut piece = (Vec::new(), Vec::new());
            loop {
                piece.0.push(points[k]);
                piece.1.push(colours[k]);
                if k == to {
                    return piece;
                }
                k = (k + 1) % n;
            }
        };
        let whole = shade_all(&[(points.clone(), colours.clone())]);
        prop_assume!(!whole.is_empty());
        let cut = shade_all(&[piece(i, j), piece(j, i)]);
        prop_assert_eq!(whole, cut);
    }
}

/// A triangle cut from a vertex to the middle of the opposite side, and across two sides at
/// a quarter and three quarters, the cut points' colours interpolated.
#[test]
fn a_triangle_cut_in_two() {
    let points =
        [(8000, 5600), (20800, 10560), (12352, 32000)].map(|(x, y)| FixedPoint::<S>::new(x, y));
    let colours =
        [(8, 200, 40), (248, 0, 120), (100, 100, 4)].map(|(r, g, b)| Colour::new(r, g, b));
    let between = |a: usize, b: usize, quarters: i32| {
        let (p, q) = (points[a], points[b]);
        let point = FixedPoint::new(
            p.x + (q.x - p.x) * quarters / 4,
            p.y + (q.y - p.y) * quarters / 4,
        );
        let mix =
            |u: u8, v: u8| (i32::from(u) + (i32::from(v) - i32::from(u)) * quarters / 4) as u8;
        let (u, v) = (colours[a], colours[b]);
        (
            point,
            Colour::new(mix(u.r, v.r), mix(u.g, v.g), mix(u.b, v.b)),
        )
    };
    let whole = shade_all(&[(points.to_vec(), colours.to_vec())]);
    assert!(whole.len() > 100);
    let (m, cm) = between(0, 1, 2);
    let halves = [
        (
            vec![points[0], m, points[2]],
            vec![colours[0], cm, colours[2]],
        ),
        (
            vec![m, points[1], points[2]],
            vec![cm, colours[1], colours[2]],
        ),
    ];
    assert_eq!(shade_all(&halves), whole);
    let ((p, cp), (q, cq)) = (between(0, 1, 1), between(0, 2, 3));
    let pieces = [
        (vec![points[0], p, q], vec![colours[0], cp, cq]),
        (
            vec![p, points[1], points[2], q],
            vec![cp, colours[1], colours[2], cq],
        ),
    ];
    assert_eq!(shade_all(&pieces), whole);
}

// -------------------------------------------------------------------------- precisions

/// The rows `0..40` of the gradient of `points`.
fn rows<const SUB: u32>(points: &[FixedPoint<SUB>], colours: &[Colour]) -> Vec<RowShade> {
    let mut gradient = Gradient::new(points, colours);
    (0..40).map(|y| gradient.row(y)).collect()
}

/// The same polygon given at any precision the fill takes is shaded alike (exact rounding:
/// the plane alone decides), and points finer than the gradient's bits are rounded to them.
#[test]
fn every_precision_shades_alike() {
    let corners = [(3, 2), (40, 9), (17, 33), (5, 20)];
    let colours = [(0, 50, 255), (255, 0, 90), (30, 200, 7), (128, 128, 250)]
        .map(|(r, g, b)| Colour::new(r, g, b));
    fn at<const SUB: u32>(corners: &[(i32, i32); 4]) -> [FixedPoint<SUB>; 4] {
        corners.map(|(x, y)| FixedPoint::from_pixels(x, y))
    }
    let expected = rows(&at::<8>(&corners), &colours);
    assert_eq!(rows(&at::<0>(&corners), &colours), expected);
    assert_eq!(rows(&at::<1>(&corners), &colours), expected);
    assert_eq!(rows(&at::<4>(&corners), &colours), expected);
    assert_eq!(rows(&at::<12>(&corners), &colours), expected);
    assert_eq!(rows(&at::<24>(&corners), &colours), expected);
    // Twelve bits, rounded to eight for the plane (halves up).
    let fine = [
        (13000, 8200),
        (163_850, 36_871),
        (69_640, 135_176),
        (20_488, 81_928),
    ]
    .map(|(x, y)| FixedPoint::<12>::new(x, y));
    let rounded = fine.map(|p| FixedPoint::<8>::new((p.x + 8) >> 4, (p.y + 8) >> 4));
    assert_ne!(rounded.map(|p| p.x << 4), fine.map(|p| p.x));
    assert_eq!(rows(&fine, &colours), rows(&rounded, &colours));
}

// ------------------------------------------------------------------------- flat cases

#[test]
fn flat_cases() {
    let c = Colour::new(10, 20, 30);
    let other = Colour::new(200, 100, 0);
    let triangle = [centre(1, 1), centre(30, 4), centre(9, 25)];
    let flat = |g: Gradient<S>| {
        let mut g = g;
        let shade = g.row(12);
        (g.flat_colour(), shade.step, shade.at(0), shade.at(17))
    };
    let expect = (Some(c), [0; 3], c, c);
    // All colours equal.
    assert_eq!(flat(Gradient::new(&triangle, &[c; 3])), expect);
    // No area: collinear points, or repeated ones; the first colour.
    let line = [centre(1, 1), centre(5, 3), centre(9, 5), centre(3, 2)];
    assert!(pixels(&line).is_empty());
    assert_eq!(
        flat(Gradient::new(&line, &[c, other, other, other])),
        expect
    );
    let point = [centre(4, 4); 3];
    assert_eq!(flat(Gradient::new(&point, &[c, other, other])), expect);
    // Fewer than three (colours or points).
    assert_eq!(flat(Gradient::new(&triangle, &[c, other])), expect);
    assert_eq!(
        flat(Gradient::new(&triangle[..2], &[c, other, other])),
        expect
    );
    assert_eq!(
        flat(Gradient::<S>::new(&[], &[])).0,
        Some(Colour::default())
    );
    // A point outside the extent, on either side.
    let outside = [
        centre(1, 1),
        centre(GRADIENT_LIMIT as i32, 4),
        centre(9, 25),
    ];
    assert_eq!(flat(Gradient::new(&outside, &[c, other, other])), expect);
    let negative = [centre(1, 1), FixedPoint::new(-1, 4), centre(9, 25)];
    assert_eq!(flat(Gradient::new(&negative, &[c, other, other])), expect);
    assert_eq!(flat(Gradient::flat(c)), expect);
    assert_eq!(RowShade::flat(c), Gradient::<S>::flat(c).row(3));
    // One channel varying is not flat, the others keep their level.
    let mut red = Gradient::new(&triangle, &[c, Colour::new(250, 20, 30), c]);
    assert_eq!(red.flat_colour(), None);
    let shade = red.row(1);
    assert_eq!((shade.step[1], shade.step[2]), (0, 0));
    assert_eq!(shade.at(1), c);
    assert_eq!(red.row(4).at(30), Colour::new(250, 20, 30));
}

// --------------------------------------------------------------------- rows and drift

/// The row's base and step of a triangle's gradient against the plane's exactly rounded
/// values (halves up), modulo `2^32`.
fn check_rounding(
    points: [FixedPoint<S>; 3],
    colours: [Colour; 3],
    y: u32,
) -> Result<(), TestCaseError> {
    let plane = Plane::new(points, colours);
    let shade = Gradient::new(&points, &colours).row(y);
    let round = |scaled: i128| (2 * scaled + plane.den).div_euclid(2 * plane.den) as i32;
    for c in 0..3 {
        let at0 = plane.scaled(0, y, c);
        prop_assert_eq!(shade.base[c], round(at0), "base, channel {}", c);
        prop_assert_eq!(
            shade.step[c],
            round(plane.scaled(1, y, c) - at0),
            "step, channel {}",
            c
        );
    }
    Ok(())
}

/// A plane whose value at every row's pixel `0` is an odd number of `2^-(F + 1)`: exactly
/// half a unit, which rounds up.
#[test]
fn a_tie_rounds_up() {
    let points = [(1, 0), (2049, 1), (2049, 2049)].map(|(x, y)| FixedPoint::<S>::new(x, y));
    let colours = [
        Colour::new(10, 20, 30),
        Colour::new(11, 20, 30),
        Colour::new(10, 20, 30),
    ];
    let plane = Plane::new(points, colours);
    for y in [0, 1, 5, 30, 31, 8191] {
        // Odd: `2 scaled / den` is, so `scaled / den` is a half.
        assert_eq!(
            (2 * plane.scaled(0, y, 0)).rem_euclid(2 * plane.den),
            plane.den
        );
        check_rounding(points, colours, y).unwrap();
    }
    // Walked to, the same.
    let mut gradient = Gradient::new(&points, &colours);
    let first = gradient.row(3);
    assert_eq!(first, Gradient::new(&points, &colours).row(3));
    for y in 4..40 {
        assert_eq!(gradient.row(y), Gradient::new(&points, &colours).row(y));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// A triangle's base and step are its plane's, exactly rounded, at any row.
    #[test]
    fn base_and_step_are_exactly_rounded(
        corners in proptest::array::uniform3((0..=(GRADIENT_LIMIT << S) as i32, 0..=(GRADIENT_LIMIT << S) as i32)),
        colours in proptest::array::uniform3(colour()),
        y in 0..GRADIENT_LIMIT,
    ) {
        let points = corners.map(|(x, y)| FixedPoint::<S>::new(x, y));
        prop_assume!(has_area(&points));
        check_rounding(points, colours, y)?;
    }

    /// Rows walked to one after another, in small jumps or computed afresh are the same.
    #[test]
    fn walking_equals_seeking(
        (points, colours) in convex_polygon(6, 8000),
        start in 0..GRADIENT_LIMIT,
        jumps in proptest::collection::vec(0..40u32, 1..40),
    ) {
        let mut walked = Gradient::new(&points, &colours);
        let mut y = start;
        for jump in jumps {
            y = (y + jump).min(GRADIENT_LIMIT - 1);
            let fresh = Gradient::new(&points, &colours).row(y);
            prop_assert_eq!(walked.row(y), fresh, "row {}", y);
        }
        // Back up: computed afresh.
        let fresh = Gradient::new(&points, &colours).row(start);
        prop_assert_eq!(walked.row(start), fresh);
    }

    /// Stepping across the widest row drifts by less than `1/256` of a level (in fact at most
    /// `1/512`), for any plane of the extent, slivers included: the step times `8191` against
    /// the exact change, and the value at the last column against the exact plane, both
    /// modulo `2^32` as the shade keeps them.
    #[test]
    fn the_widest_row_drifts_below_a_256th(
        corners in proptest::array::uniform3((0..=(GRADIENT_LIMIT << S) as i32, 0..=(GRADIENT_LIMIT << S) as i32)),
        sliver in any::<bool>(),
        colours in proptest::array::uniform3(colour()),
        y in 0..GRADIENT_LIMIT,
    ) {
        let mut points = corners.map(|(x, y)| FixedPoint::<S>::new(x, y));
        if sliver {
            // The third point a subpixel off the line of the first two.
            let (a, b) = (points[0], points[1]);
            points[2] = FixedPoint::new((a.x + b.x) / 2, (a.y + b.y) / 2 + 1);
        }
        prop_assume!(has_area(&points));
        prop_assume!(colours.iter().any(|&c| c != colours[0]));
        let plane = Plane::new(points, colours);
        let shade = Gradient::new(&points, &colours).row(y);
        let last = GRADIENT_LIMIT - 1;
        for c in 0..3 {
            // Modulo 2^32 in units of 2^-F, and the difference's magnitude times `den`.
            let off = |value: i32, exact_scaled: i128| {
                let exact = exact_scaled.div_euclid(plane.den);
                let diff = i128::from(value.wrapping_sub(exact as i32));
                (diff * plane.den - exact_scaled.rem_euclid(plane.den)).abs()
            };
            let change = plane.scaled(last, y, c) - plane.scaled(0, y, c);
            let drift = off(shade.step[c].wrapping_mul(last as i32), change);
            prop_assert!(drift * 256 < plane.den << F, "step drift {}/{}", drift, plane.den);
            let error = off(raw(&shade, last)[c], plane.scaled(last, y, c));
            prop_assert!(error * 512 <= plane.den << F, "error {}/{}", error, plane.den);
        }
    }
}
