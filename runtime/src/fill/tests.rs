//! Raster tests of the fill on the checking mock target: ASCII snapshots of small cases, and
//! property tests against tilings and a brute-force edge-function reference.

extern crate std;

use std::string::ToString;
use std::vec::Vec;

use proptest::prelude::*;

use super::*;
use crate::display::testing::MockTarget;

const A: Colour = Colour::new(255, 0, 0);
const B: Colour = Colour::new(0, 255, 0);
const C: Colour = Colour::new(0, 0, 255);

/// Points given by their raw fixed-point coordinates.
fn raw<const SUB: u32>(p: &[(i32, i32)]) -> Vec<FixedPoint<SUB>> {
    p.iter().map(|&(x, y)| FixedPoint::new(x, y)).collect()
}

/// Points given in pixels, snapped with `SUB` bits.
fn pts<const SUB: u32>(p: &[(f32, f32)]) -> Vec<FixedPoint<SUB>> {
    p.iter()
        .map(|&(x, y)| FixedPoint::<SUB>::snap(x, y))
        .collect()
}

/// Fill on the mock and check the returned count against what the mock received.
fn fill<const SUB: u32, const W: usize, const H: usize>(
    m: &mut MockTarget<W, H>,
    points: &[FixedPoint<SUB>],
    colour: Colour,
) -> u64 {
    let before = m.pixels();
    let n = fill_polygon(points, W as u32, H as u32, colour, m).unwrap();
    assert_eq!(
        n,
        m.pixels() - before,
        "returned count disagrees with the spans"
    );
    n
}

// ---------------------------------------------------------------- ASCII snapshots

#[test]
fn snapshot_triangle() {
    let mut m = MockTarget::<16, 10>::new();
    fill::<8, 16, 10>(&mut m, &pts::<8>(&[(1.0, 1.0), (14.3, 3.7), (4.2, 9.6)]), A);
    insta::assert_snapshot!("triangle", m.to_string());
}

/// A square whose diagonal runs through pixel centres: each centre on it goes to the
/// triangle on its right (B), none is drawn twice, none is left out.
#[test]
fn snapshot_square_split_on_pixel_centres() {
    let mut m = MockTarget::<10, 10>::new();
    let (p0, p1, p2, p3) = ((0.5, 0.5), (8.5, 0.5), (8.5, 8.5), (0.5, 8.5));
    fill::<1, 10, 10>(&mut m, &pts::<1>(&[p0, p2, p3]), A);
    fill::<1, 10, 10>(&mut m, &pts::<1>(&[p0, p1, p2]), B);
    // Centres with 0.5 <= x < 8.5 and 0.5 <= y < 8.5: columns and rows 0..8.
    assert_eq!(m.written_count(), 64);
    insta::assert_snapshot!("square_split_on_pixel_centres", m.to_string());
}

/// Six triangles around a vertex that sits exactly on a pixel centre (7.5, 5.5).
#[test]
fn snapshot_fan_around_a_pixel_centre() {
    let mut m = MockTarget::<16, 12>::new();
    let centre = (7.5, 5.5);
    let rim = [
        (13.0, 5.5),
        (10.25, 0.5),
        (4.75, 0.5),
        (2.0, 5.5),
        (4.75, 10.5),
        (10.25, 10.5),
    ];
    for (k, colour) in [A, B, C, A, B, C].into_iter().enumerate() {
        let tri = [centre, rim[k], rim[(k + 1) % 6]];
        fill::<4, 16, 12>(&mut m, &pts::<4>(&tri), colour);
    }
    assert!(
        m.written(7, 5),
        "the shared centre pixel is owned by someone"
    );
    insta::assert_snapshot!("fan_around_a_pixel_centre", m.to_string());
}

/// A sliver narrower than a pixel draws only the centres it really covers, and nothing
/// where it passes between them.
#[test]
fn snapshot_sliver() {
    let mut m = MockTarget::<16, 6>::new();
    fill::<8, 16, 6>(
        &mut m,
        &pts::<8>(&[(0.2, 0.3), (15.8, 4.6), (15.8, 5.2)]),
        A,
    );
    insta::assert_snapshot!("sliver", m.to_string());
}

/// Rectangles with all edges on pixel centres: the top and left edges are drawn, the bottom
/// and right ones are not, so the three tiles neither overlap nor leave gaps; plus a
/// trapezoid with horizontal top and bottom edges.
#[test]
fn snapshot_horizontal_edges() {
    let mut m = MockTarget::<16, 12>::new();
    let rect =
        |x0: f32, y0: f32, x1: f32, y1: f32| pts::<1>(&[(x0, y0), (x1, y0), (x1, y1), (x0, y1)]);
    assert_eq!(
        fill::<1, 16, 12>(&mut m, &rect(2.5, 1.5, 6.5, 4.5), A),
        4 * 3
    );
    assert_eq!(
        fill::<1, 16, 12>(&mut m, &rect(6.5, 1.5, 10.5, 4.5), B),
        4 * 3
    );
    assert_eq!(
        fill::<1, 16, 12>(&mut m, &rect(2.5, 4.5, 10.5, 6.5), C),
        8 * 2
    );
    let trapezoid = pts::<1>(&[(4.0, 7.5), (10.0, 7.5), (14.0, 11.5), (1.0, 11.5)]);
    fill::<1, 16, 12>(&mut m, &trapezoid, A);
    insta::assert_snapshot!("horizontal_edges", m.to_string());
}

/// Non-convex and self-intersecting outlines are filled even-odd: an L shape, and a
/// pentagram whose centre is outside.
#[test]
fn snapshot_non_convex() {
    let mut m = MockTarget::<24, 12>::new();
    let l = pts::<4>(&[
        (1.0, 1.0),
        (4.0, 1.0),
        (4.0, 8.0),
        (9.0, 8.0),
        (9.0, 11.0),
        (1.0, 11.0),
    ]);
    fill::<4, 24, 12>(&mut m, &l, A);
    let star = pts::<4>(&[
        (16.5, 0.5),
        (20.3, 11.2),
        (10.5, 4.5),
        (22.5, 4.5),
        (12.7, 11.2),
    ]);
    fill::<4, 24, 12>(&mut m, &star, B);
    assert!(
        !m.written(16, 6),
        "the pentagram's centre has winding 2: outside"
    );
    insta::assert_snapshot!("non_convex", m.to_string());
}

// ---------------------------------------------------------------- unit tests

#[test]
fn degenerate_polygons_draw_nothing_and_do_not_panic() {
    let mut m = MockTarget::<8, 8>::new();
    let p = |x, y| FixedPoint::<4>::from_pixels(x, y);
    let cases: [&[FixedPoint<4>]; 7] = [
        &[],
        &[p(1, 1)],
        &[p(1, 1), p(5, 6)],
        &[p(1, 1), p(1, 1), p(1, 1)],
        &[p(1, 1), p(3, 3), p(6, 6)],
        &[p(1, 1), p(6, 1), p(3, 1)],
        &[p(1, 1), p(6, 6), p(1, 1), p(6, 6)],
    ];
    for points in cases {
        assert_eq!(fill::<4, 8, 8>(&mut m, points, A), 0, "{points:?}");
    }
    assert_eq!(m.spans(), 0);
}

#[test]
fn repeated_and_collinear_points_change_nothing() {
    let p = |x, y| FixedPoint::<0>::from_pixels(x, y);
    let mut plain = MockTarget::<8, 8>::new();
    assert!(fill::<0, 8, 8>(&mut plain, &[p(1, 1), p(7, 3), p(3, 7)], A) > 10);
    // (4, 2), (5, 5) and (2, 4) lie on the three edges; (1, 1), (7, 3) are repeated.
    let noisy = [
        p(1, 1),
        p(1, 1),
        p(4, 2),
        p(7, 3),
        p(7, 3),
        p(5, 5),
        p(3, 7),
        p(2, 4),
        p(1, 1),
    ];
    let mut m = MockTarget::<8, 8>::new();
    fill::<0, 8, 8>(&mut m, &noisy, A);
    assert_eq!(m.to_string(), plain.to_string());
}

#[test]
fn winding_does_not_matter() {
    let points = pts::<8>(&[(0.7, 0.2), (7.9, 3.3), (5.1, 7.8), (1.2, 6.0)]);
    let mut reversed = points.clone();
    reversed.reverse();
    let mut a = MockTarget::<8, 8>::new();
    let mut b = MockTarget::<8, 8>::new();
    let na = fill::<8, 8, 8>(&mut a, &points, A);
    let nb = fill::<8, 8, 8>(&mut b, &reversed, A);
    assert!(na > 20);
    assert_eq!((na, a.to_string()), (nb, b.to_string()));
}

#[test]
fn convex_polygon_gives_one_span_per_row() {
    let mut m = MockTarget::<16, 16>::new();
    let hexagon = pts::<8>(&[
        (8.0, 0.3),
        (15.0, 4.0),
        (15.0, 12.0),
        (8.0, 15.7),
        (1.0, 12.0),
        (1.0, 4.0),
    ]);
    fill::<8, 16, 16>(&mut m, &hexagon, A);
    // Rows 0 and 15 pass between the pixel centres near the pointed top and bottom.
    assert!(!m.written(7, 0) && !m.written(8, 0) && !m.written(7, 15) && !m.written(8, 15));
    assert_eq!(m.spans(), 14);
}

#[test]
fn outside_the_window_is_clipped() {
    let mut m = MockTarget::<8, 6>::new();
    let big = pts::<8>(&[(0.0, 0.0), (300.0, 0.0), (20.0, 400.0)]);
    assert_eq!(fill::<8, 8, 6>(&mut m, &big, A), 48);
    let mut m = MockTarget::<8, 6>::new();
    let beyond = pts::<8>(&[(9.0, 1.0), (20.0, 1.0), (20.0, 5.0)]);
    assert_eq!(fill::<8, 8, 6>(&mut m, &beyond, A), 0);
    // At the edge of the narrow range (any i32 is in range with `wide-coordinates`).
    let l = coordinate_limit::<8>().min((1 << 21) - 1);
    let far = [
        FixedPoint::new(0, 0),
        FixedPoint::new(l, 0),
        FixedPoint::new(0, l),
    ];
    let mut m = MockTarget::<8, 6>::new();
    assert_eq!(fill::<8, 8, 6>(&mut m, &far, A), 48);
}

#[cfg(feature = "wide-coordinates")]
#[test]
fn any_i32_coordinates_are_clipped() {
    assert_eq!(coordinate_limit::<8>(), i32::MAX);
    let mut m = MockTarget::<8, 6>::new();
    let big = pts::<8>(&[(-100.0, -50.0), (300.0, -40.0), (20.0, 400.0)]);
    assert_eq!(fill::<8, 8, 6>(&mut m, &big, A), 48);
    let extreme = [(i32::MIN, i32::MIN), (i32::MAX, 0), (0, i32::MAX)];
    let mut m = MockTarget::<8, 6>::new();
    assert_eq!(fill::<8, 8, 6>(&mut m, &raw(&extreme), A), 48);
    let mut m = MockTarget::<8, 6>::new();
    fill::<0, 8, 6>(&mut m, &raw(&extreme), A);
}

#[cfg(not(feature = "wide-coordinates"))]
#[test]
fn without_wide_coordinates_out_of_range_points_are_refused() {
    assert_eq!(coordinate_limit::<8>(), (1 << 21) - 1);
    assert_eq!(coordinate_limit::<0>(), (1 << 29) - 1);
    assert_eq!(coordinate_limit::<24>(), 31);
    let mut m = MockTarget::<8, 6>::new();
    for bad in [
        FixedPoint::<8>::new(-1, 0),
        FixedPoint::new(0, -1),
        FixedPoint::new(1 << 21, 5),
        FixedPoint::new(5, i32::MAX),
    ] {
        let tri = [FixedPoint::new(0, 0), bad, FixedPoint::new(300, 400)];
        assert_eq!(
            fill_polygon(&tri, 8, 6, A, &mut m),
            Err(FillError::OutOfRange {
                point: bad,
                limit: (1 << 21) - 1
            })
        );
    }
    assert_eq!(m.spans(), 0);
    let e = FillError::OutOfRange {
        point: FixedPoint::<24>::new(-1, 2),
        limit: 31,
    };
    assert_eq!(
        e.to_string(),
        "point (-1, 2) outside the fill's range 0..=31 (enable the `wide-coordinates` feature)"
    );
}

#[test]
fn too_many_vertices_is_an_error_and_draws_nothing() {
    let mut m = MockTarget::<8, 8>::new();
    let ring: Vec<FixedPoint<8>> = (0..MAX_FILL_VERTICES + 1)
        .map(|k| {
            let a = k as f32 / (MAX_FILL_VERTICES + 1) as f32 * core::f32::consts::TAU;
            FixedPoint::<8>::snap(4.0 + 3.5 * libm::cosf(a), 4.0 + 3.5 * libm::sinf(a))
        })
        .collect();
    assert_eq!(
        fill_polygon(&ring, 8, 8, A, &mut m),
        Err(FillError::TooManyVertices { count: 65, max: 64 })
    );
    assert_eq!(m.spans(), 0);
    assert!(fill::<8, 8, 8>(&mut m, &ring[..MAX_FILL_VERTICES], A) > 30);
}

#[test]
fn snap_rounds_and_saturates() {
    assert_eq!(FixedPoint::<8>::snap(1.5, -0.25), FixedPoint::new(384, -64));
    assert_eq!(FixedPoint::<0>::snap(2.5, 2.49), FixedPoint::new(3, 2));
    assert_eq!(
        FixedPoint::<8>::snap(f32::NAN, 1e30),
        FixedPoint::new(0, i32::MAX)
    );
    assert_eq!(
        FixedPoint::<4>::snap_f64(0.03125, -1e300),
        FixedPoint::new(1, i32::MIN)
    );
    assert_eq!(
        FixedPoint::<8>::from_pixels(3, -2),
        FixedPoint::new(768, -512)
    );
}

#[test]
fn error_display() {
    let e: FillError = FillError::TooManyVertices { count: 70, max: 64 };
    assert_eq!(
        e.to_string(),
        "polygon of 70 vertices, the fill holds at most 64"
    );
}

// ---------------------------------------------------------------- references

/// Brute-force coverage of a convex polygon (any winding, non-zero area, no collinear
/// points): exact edge functions at doubled-unit pixel centres `((2i+1)S, (2j+1)S)`, with
/// the top-left tie rule (a centre on an edge is inside iff the edge is a left edge, or a
/// horizontal edge with the inside below it).
fn brute_force<const SUB: u32, const W: usize, const H: usize>(
    poly: &[FixedPoint<SUB>],
) -> [[bool; W]; H] {
    let s = 1i128 << SUB;
    let n = poly.len();
    let area2: i128 = (0..n)
        .map(|k| {
            let (a, b) = (poly[k], poly[(k + 1) % n]);
            i128::from(a.x) * i128::from(b.y) - i128::from(b.x) * i128::from(a.y)
        })
        .sum();
    assert_ne!(area2, 0);
    let sign = area2.signum();
    let mut out = [[false; W]; H];
    for (j, row) in out.iter_mut().enumerate() {
        for (i, cell) in row.iter_mut().enumerate() {
            let (cx, cy) = ((2 * i as i128 + 1) * s, (2 * j as i128 + 1) * s);
            *cell = (0..n).all(|k| {
                let (a, b) = (poly[k], poly[(k + 1) % n]);
                let (ax, ay) = (2 * i128::from(a.x), 2 * i128::from(a.y));
                let (dx, dy) = (2 * i128::from(b.x) - ax, 2 * i128::from(b.y) - ay);
                let e = sign * (dx * (cy - ay) - dy * (cx - ax));
                // Inward normal (gradient of e): (-dy, dx) * sign.
                let (nx, ny) = (-dy * sign, dx * sign);
                e > 0 || (e == 0 && (nx > 0 || (nx == 0 && ny > 0)))
            });
        }
    }
    out
}

/// Strictly convex hull (Andrew's monotone chain, collinear points dropped); also for
/// `fill::samples`' tests.
pub(super) fn hull<const SUB: u32>(mut p: Vec<FixedPoint<SUB>>) -> Vec<FixedPoint<SUB>> {
    p.sort_by_key(|q| (q.x, q.y));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: FixedPoint<SUB>, a: FixedPoint<SUB>, b: FixedPoint<SUB>| {
        (i128::from(a.x) - i128::from(o.x)) * (i128::from(b.y) - i128::from(o.y))
            - (i128::from(a.y) - i128::from(o.y)) * (i128::from(b.x) - i128::from(o.x))
    };
    let mut h: Vec<FixedPoint<SUB>> = Vec::new();
    for pass in 0..2 {
        let start = h.len();
        let iter: Vec<FixedPoint<SUB>> = if pass == 0 {
            p.clone()
        } else {
            p.iter().rev().copied().collect()
        };
        for q in iter {
            while h.len() >= start + 2 && cross(h[h.len() - 2], h[h.len() - 1], q) <= 0 {
                h.pop();
            }
            h.push(q);
        }
        h.pop();
    }
    h
}

fn check_convex<const SUB: u32>(raw: Vec<(i32, i32)>, reverse: bool) -> Result<(), TestCaseError> {
    const W: usize = 24;
    const H: usize = 20;
    let mut poly = hull(
        raw.into_iter()
            .map(|(x, y)| FixedPoint::new(x, y))
            .collect(),
    );
    if poly.len() < 3 {
        return Ok(());
    }
    if reverse {
        poly.reverse();
    }
    let expected = brute_force::<SUB, W, H>(&poly);
    let mut m = MockTarget::<W, H>::new();
    fill::<SUB, W, H>(&mut m, &poly, A);
    for (j, row) in expected.iter().enumerate() {
        for (i, &inside) in row.iter().enumerate() {
            prop_assert_eq!(
                m.written(i, j),
                inside,
                "pixel ({}, {}) of {:?}\n{}",
                i,
                j,
                poly,
                m
            );
        }
    }
    Ok(())
}

/// A `cols x rows` grid of jittered cells, each split into two triangles along a random
/// diagonal, tiling the rectangle `[ox, ox + cols*cw] x [oy, oy + rows*ch]` exactly (boundary
/// vertices only slide along the boundary, interior jitter stays below a quarter cell so no
/// triangle flips). Every pixel whose centre is in the half-open rectangle must be drawn
/// exactly once (the mock panics on a second write) and no other.
#[allow(clippy::too_many_arguments)]
fn check_grid<const SUB: u32>(
    origin: (i32, i32),
    cell: (i32, i32),
    size: (usize, usize),
    jitter: &[(i32, i32)],
    diagonals: &[bool],
) -> Result<(), TestCaseError> {
    const W: usize = 48;
    const H: usize = 48;
    let s = 1i32 << SUB;
    let (ox, oy) = (origin.0 * s / 16, origin.1 * s / 16);
    let (cw, ch) = (cell.0 * s / 16, cell.1 * s / 16);
    let (cols, rows) = size;
    let jmax = (cw.min(ch) - 1) / 4;
    let vertex = |c: usize, r: usize| {
        let (jx, jy) = jitter[r * (cols + 1) + c];
        let (jx, jy) = (
            jx.rem_euclid(2 * jmax + 1) - jmax,
            jy.rem_euclid(2 * jmax + 1) - jmax,
        );
        let inner_x = c > 0 && c < cols;
        let inner_y = r > 0 && r < rows;
        FixedPoint::new(
            ox + c as i32 * cw + if inner_x { jx } else { 0 },
            oy + r as i32 * ch + if inner_y { jy } else { 0 },
        )
    };
    let mut m = MockTarget::<W, H>::new();
    let mut total = 0;
    for r in 0..rows {
        for c in 0..cols {
            let (p00, p10, p01, p11) = (
                vertex(c, r),
                vertex(c + 1, r),
                vertex(c, r + 1),
                vertex(c + 1, r + 1),
            );
            let tris = if diagonals[r * cols + c] {
                [[p00, p10, p01], [p10, p11, p01]]
            } else {
                [[p00, p10, p11], [p00, p11, p01]]
            };
            for (k, t) in tris.iter().enumerate() {
                total += fill::<SUB, W, H>(&mut m, t, if (r + c + k) % 2 == 0 { A } else { B });
            }
        }
    }
    let (x0, x1) = (2 * i64::from(ox), 2 * i64::from(ox + cols as i32 * cw));
    let (y0, y1) = (2 * i64::from(oy), 2 * i64::from(oy + rows as i32 * ch));
    let mut inside = 0;
    for j in 0..H {
        for i in 0..W {
            let (cx, cy) = (
                (2 * i as i64 + 1) * i64::from(s),
                (2 * j as i64 + 1) * i64::from(s),
            );
            let want = x0 <= cx && cx < x1 && y0 <= cy && cy < y1;
            inside += u64::from(want);
            prop_assert_eq!(m.written(i, j), want, "pixel ({}, {})\n{}", i, j, m);
        }
    }
    prop_assert_eq!(total, inside);
    Ok(())
}

/// Origin, cell size, cell counts, jitter per vertex, diagonal per cell.
type GridCase = (
    (i32, i32),
    (i32, i32),
    (usize, usize),
    Vec<(i32, i32)>,
    Vec<bool>,
);

/// Grid parameters in sixteenths of a pixel (scaled to each SUB, so SUB = 0 gets whole
/// pixels): origin 0..4 px, cells 4..8 px, up to 5 x 5 cells (at most 44 px, inside 48).
fn grid_strategy() -> impl Strategy<Value = GridCase> {
    (
        0..64i32,
        0..64i32,
        64..=128i32,
        64..=128i32,
        1..=5usize,
        1..=5usize,
    )
        .prop_flat_map(|(ox, oy, cw, ch, cols, rows)| {
            (
                Just((ox, oy)),
                Just((cw, ch)),
                Just((cols, rows)),
                proptest::collection::vec((0..1 << 20, 0..1 << 20), (cols + 1) * (rows + 1)),
                proptest::collection::vec(any::<bool>(), cols * rows),
            )
        })
}

/// Up to 10 points within a margin of two pixels around the 24 x 20 window; each coordinate
/// is often snapped to a multiple of half a pixel so that vertices and edges land exactly on
/// pixel centres, where the tie rule matters.
fn points_strategy(sub: u32) -> impl Strategy<Value = Vec<(i32, i32)>> {
    let s = 1i32 << sub;
    let half = (s / 2).max(1);
    let coord = move |lo: i32, hi: i32| {
        (lo * s..=hi * s, any::<bool>())
            .prop_map(move |(v, snap)| if snap { v.div_euclid(half) * half } else { v })
    };
    // Without `wide-coordinates` the fill takes no negative coordinate.
    let lo = if cfg!(feature = "wide-coordinates") {
        -2
    } else {
        0
    };
    proptest::collection::vec((coord(lo, 26), coord(lo, 22)), 3..=10)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn grid_tiles_exactly_sub0((o, c, n, j, d) in grid_strategy()) {
        check_grid::<0>(o, c, n, &j, &d)?;
    }

    #[test]
    fn grid_tiles_exactly_sub4((o, c, n, j, d) in grid_strategy()) {
        check_grid::<4>(o, c, n, &j, &d)?;
    }

    #[test]
    fn grid_tiles_exactly_sub8((o, c, n, j, d) in grid_strategy()) {
        check_grid::<8>(o, c, n, &j, &d)?;
    }

    #[test]
    fn convex_matches_brute_force_sub0(p in points_strategy(0), rev in any::<bool>()) {
        check_convex::<0>(p, rev)?;
    }

    #[test]
    fn convex_matches_brute_force_sub4(p in points_strategy(4), rev in any::<bool>()) {
        check_convex::<4>(p, rev)?;
    }

    #[test]
    fn convex_matches_brute_force_sub8(p in points_strategy(8), rev in any::<bool>()) {
        check_convex::<8>(p, rev)?;
    }

    /// Any point list, anywhere in i32: no panic, no span outside the window, no pixel
    /// drawn twice (spans of one polygon are disjoint), and the count is right. Without
    /// `wide-coordinates`: refused when out of range, and the same checks once wrapped into it.
    #[test]
    fn arbitrary_polygons_are_safe(
        p in proptest::collection::vec(
            prop_oneof![
                (-300i32..9000, -300i32..7000),
                (any::<i32>(), any::<i32>()),
            ],
            0..=MAX_FILL_VERTICES,
        )
    ) {
        arbitrary::<8>(&raw(&p))?;
        arbitrary::<0>(&raw(&p))?;
    }
}

fn arbitrary<const SUB: u32>(poly: &[FixedPoint<SUB>]) -> Result<(), TestCaseError> {
    let limit = coordinate_limit::<SUB>();
    let wide = cfg!(feature = "wide-coordinates");
    let inside = |v: i32| wide || (0..=limit).contains(&v);
    let mut m = MockTarget::<32, 24>::new();
    if poly.iter().all(|p| inside(p.x) && inside(p.y)) {
        fill::<SUB, 32, 24>(&mut m, poly, A);
        return Ok(());
    }
    let refused = fill_polygon(poly, 32, 24, A, &mut m);
    let out_of_range = matches!(refused, Err(FillError::OutOfRange { .. }));
    prop_assert!(out_of_range, "{:?}", refused);
    prop_assert_eq!(m.spans(), 0);
    let wrapped: Vec<FixedPoint<SUB>> = poly
        .iter()
        .map(|p| FixedPoint::new(p.x.rem_euclid(limit + 1), p.y.rem_euclid(limit + 1)))
        .collect();
    fill::<SUB, 32, 24>(&mut m, &wrapped, A);
    Ok(())
}

#[test]
fn round_f32_matches_libm_on_halves_and_limits() {
    let cases = [
        0.0f32,
        -0.0,
        0.5,
        -0.5,
        1.5,
        -1.5,
        2.5,
        0.49999997,
        -0.49999997,
        8_388_607.5,
        -8_388_607.5,
        8_388_608.0,
        16_777_215.0,
        3.0e9,
        -3.0e9,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        f32::MIN_POSITIVE,
    ];
    for v in cases {
        assert_eq!(round_f32_float(v), libm::roundf(v) as i32, "{v}");
        assert_eq!(round_bits_scaled(v, 0), libm::roundf(v) as i32, "{v}");
    }
}

/// The two roundings agree on a sweep of about a million bit patterns (every exponent, both
/// signs, NaNs and infinities included).
#[test]
fn round_bits_and_float_agree_on_a_sweep() {
    let mut bits = 0u32;
    loop {
        let v = f32::from_bits(bits);
        assert_eq!(
            round_bits_scaled(v, 0),
            round_f32_float(v),
            "{v} ({bits:#x})"
        );
        match bits.checked_add(4099) {
            Some(b) => bits = b,
            None => break,
        }
    }
}

/// Rounding `v * 2^k` on the bits is rounding the product, on a sweep of bit patterns (every
/// exponent, both signs, subnormals, NaNs, infinities, products that overflow) for every scale
/// up to 31.
#[test]
fn scaled_rounding_is_rounding_the_product() {
    for k in 0..32 {
        let scale = (1u64 << k) as f32;
        let mut bits = 0u32;
        loop {
            let v = f32::from_bits(bits);
            assert_eq!(
                round_bits_scaled(v, k),
                round_bits_scaled(v * scale, 0),
                "{v} ({bits:#x}) * 2^{k}"
            );
            match bits.checked_add(65_537) {
                Some(b) => bits = b,
                None => break,
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn scaled_rounding_matches_the_product(bits in any::<u32>(), k in 0u32..32) {
        let v = f32::from_bits(bits);
        let product = v * (1u64 << k) as f32;
        prop_assert_eq!(round_bits_scaled(v, k), round_f32_float(product), "{} * 2^{}", v, k);
    }

    #[test]
    fn round_f32_matches_libm(bits in any::<u32>()) {
        let v = f32::from_bits(bits);
        prop_assert_eq!(round_f32_float(v), libm::roundf(v) as i32, "{}", v);
        prop_assert_eq!(round_bits_scaled(v, 0), libm::roundf(v) as i32, "{}", v);
    }

    #[test]
    fn round_f32_matches_libm_near_halves(k in -20_000_000i32..20_000_000, ulps in -3i32..=3) {
        let half = k as f32 + 0.5;
        let v = f32::from_bits((half.to_bits() as i32 + ulps) as u32);
        prop_assert_eq!(round_f32_float(v), libm::roundf(v) as i32, "{}", v);
        prop_assert_eq!(round_bits_scaled(v, 0), libm::roundf(v) as i32, "{}", v);
    }
}

/// The pixels a fill draws, as a set.
fn drawn_pixels<const SUB: u32>(points: &[FixedPoint<SUB>], w: u32, h: u32) -> Vec<(u32, u32)> {
    struct Collect(Vec<(u32, u32)>);
    impl SpanSink for Collect {
        fn span(&mut self, y: u32, x0: u32, x1: u32, _: Colour) {
            self.0.extend((x0..x1).map(|x| (x, y)));
        }
    }
    let mut c = Collect(Vec::new());
    fill_polygon(points, w, h, Colour::default(), &mut c).unwrap();
    c.0
}

#[test]
fn sample_rect_edges() {
    // SUB = 4: pixel 0's sample is at 8, pixel 1's at 24.
    // A box from 8 (on pixel 0's sample) to 24 (on pixel 1's): only pixel 0 on each axis.
    assert_eq!(
        sample_rect(&raw::<4>(&[(8, 8), (24, 8), (24, 24), (8, 24)]), 10, 10),
        Some([0, 0, 1, 1])
    );
    // Just after the sample: nothing.
    assert_eq!(
        sample_rect(&raw::<4>(&[(9, 9), (24, 9), (24, 24)]), 10, 10),
        None
    );
    // SUB = 0: samples at i + 1/2, so [0, 1) holds pixel 0.
    assert_eq!(
        sample_rect(&raw::<0>(&[(0, 0), (1, 0), (0, 1)]), 4, 4),
        Some([0, 0, 1, 1])
    );
    // Clamped to the window; empty input.
    assert_eq!(
        sample_rect(&raw::<0>(&[(-5, -5), (50, -5), (50, 50)]), 4, 3),
        Some([0, 0, 4, 3])
    );
    assert_eq!(sample_rect::<0>(&[], 4, 4), None);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]

    /// Every pixel the fill draws lies in the sample rectangle, and `None` means none is
    /// drawn.
    #[test]
    fn sample_rect_holds_every_drawn_pixel(
        pts in proptest::collection::vec((-40i32..400, -40i32..400), 3..7)
    ) {
        // Without `wide-coordinates` the fill takes no negative coordinate.
        let shift = if cfg!(feature = "wide-coordinates") { 0 } else { 40 };
        let points: Vec<FixedPoint<4>> =
            pts.iter().map(|&(x, y)| FixedPoint::new(x + shift, y + shift)).collect();
        let drawn = drawn_pixels::<4>(&points, 20, 16);
        match sample_rect(&points, 20, 16) {
            None => prop_assert!(drawn.is_empty(), "{:?}", drawn),
            Some([x0, y0, x1, y1]) => {
                for (x, y) in drawn {
                    prop_assert!(x0 <= x && x < x1 && y0 <= y && y < y1, "({}, {})", x, y);
                }
            }
        }
    }
}

// ---------------------------------------------------------------- the small-polygon fill

/// Every span a fill emits, in order.
#[derive(Default)]
struct Spans(Vec<(u32, u32, u32)>);

impl SpanSink for Spans {
    fn span(&mut self, y: u32, x0: u32, x1: u32, _: Colour) {
        self.0.push((y, x0, x1));
    }
}

/// The small-polygon fill of `points` on rows `rows` of a `w x h` window against the
/// scanline fill: the same spans in the same order, the same count. Returns whether the
/// small fill took the polygon.
fn small_matches_scanline<const SUB: u32>(
    points: &[FixedPoint<SUB>],
    w: u32,
    h: u32,
    rows: core::ops::Range<u32>,
) -> Result<bool, TestCaseError> {
    let Some([x0, y0, x1, y1]) = sample_rect(points, w, h) else {
        return Ok(false);
    };
    let (y0, y1) = (y0.max(rows.start), y1.min(rows.end));
    if y0 >= y1 {
        return Ok(false);
    }
    let mut small = Spans::default();
    let Some(n) = small::fill_small(points, [x0, y0, x1, y1], &mut { A }, &mut small) else {
        return Ok(false);
    };
    let mut scan = Spans::default();
    let mut edges = [EdgeWalk::default(); MAX_FILL_VERTICES];
    let m = fill_in(points, &mut edges, w, rows, &mut { A }, &mut scan);
    prop_assert_eq!(&small.0, &scan.0, "{:?}", points);
    prop_assert_eq!(n, m);
    Ok(true)
}

/// Points within a few pixels of each other (so their sample rectangle is often small),
/// anywhere in and around a 24 x 20 window; coordinates often on half pixels, where the tie
/// rules decide, and often repeated (collinear and degenerate polygons).
fn small_polygon_strategy(sub: u32) -> impl Strategy<Value = Vec<(i32, i32)>> {
    let s = 1i32 << sub;
    let half = (s / 2).max(1);
    let lo = if cfg!(feature = "wide-coordinates") {
        -3 * s
    } else {
        4 * s
    };
    let offset = move || {
        (-3 * s..=3 * s, any::<bool>())
            .prop_map(move |(v, snap)| if snap { v.div_euclid(half) * half } else { v })
    };
    (lo..=26 * s, lo..=22 * s).prop_flat_map(move |(cx, cy)| {
        proptest::collection::vec(
            (offset(), offset()).prop_map(move |(dx, dy)| (cx + dx, cy + dy)),
            3..=8,
        )
    })
}

#[test]
fn small_fill_takes_small_polygons_only() {
    // A triangle over 2 x 2 centres at SUB = 4, and one over 7 x 7.
    let small = raw::<4>(&[(8, 8), (40, 8), (8, 40)]);
    assert_eq!(sample_rect(&small, 10, 10), Some([0, 0, 2, 2]));
    assert!(small_matches_scanline(&small, 10, 10, 0..10).unwrap());
    let large = raw::<4>(&[(8, 8), (120, 8), (8, 120)]);
    assert_eq!(sample_rect(&large, 10, 10), Some([0, 0, 7, 7]));
    assert!(!small_matches_scanline(&large, 10, 10, 0..10).unwrap());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    /// Any small point list (convex or not, self-intersecting, degenerate), whole or in a
    /// band of rows: exactly the scanline fill's spans.
    #[test]
    fn small_fill_gives_the_scanline_spans(
        p0 in small_polygon_strategy(0),
        p4 in small_polygon_strategy(4),
        p8 in small_polygon_strategy(8),
        r0 in 0u32..20,
        len in 0u32..21,
    ) {
        let rows = r0..(r0 + len).min(20);
        small_matches_scanline::<0>(&raw(&p0), 24, 20, rows.clone())?;
        small_matches_scanline::<4>(&raw(&p4), 24, 20, rows.clone())?;
        small_matches_scanline::<8>(&raw(&p8), 24, 20, rows.clone())?;
        small_matches_scanline::<8>(&raw(&p8), 24, 20, 0..20)?;
    }
}
