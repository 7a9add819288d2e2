extern crate std;

use std::vec::Vec;

use proptest::prelude::*;

use super::masks::{fill_polygon_masks, MaskSink};
use super::*;
use crate::fill::{fill_polygon, fill_polygon_rows, FillError};

const A: Colour = Colour::new(200, 100, 50);

/// The masks of a `W x H` window, each pixel's masks received at most once per polygon.
struct MaskImage<const W: usize, const H: usize> {
    masks: [[Mask; W]; H],
    seen: [[bool; W]; H],
    rows: Vec<u32>,
}

impl<const W: usize, const H: usize> MaskImage<W, H> {
    fn new() -> Self {
        MaskImage {
            masks: [[0; W]; H],
            seen: [[false; W]; H],
            rows: Vec::new(),
        }
    }

    /// Start another polygon: each pixel may get its masks once more.
    fn next_polygon(&mut self) {
        self.seen = [[false; W]; H];
        self.rows.clear();
    }
}

impl<const W: usize, const H: usize> MaskSink for MaskImage<W, H> {
    fn masks(&mut self, y: u32, x_start: u32, masks: &[Mask], colour: Colour) {
        assert_eq!(colour, A);
        assert!(!masks.is_empty() && masks[0] != 0 && masks[masks.len() - 1] != 0);
        assert!(self.rows.last().is_none_or(|&r| r < y), "rows out of order");
        self.rows.push(y);
        for (k, &m) in masks.iter().enumerate() {
            let (x, y) = (x_start as usize + k, y as usize);
            assert!(m & !FULL_MASK == 0, "bits beyond the grid");
            assert!(!self.seen[y][x], "pixel ({x}, {y}) received twice");
            self.seen[y][x] = true;
            assert!(
                self.masks[y][x] & m == 0,
                "sample of ({x}, {y}) covered twice"
            );
            self.masks[y][x] |= m;
        }
    }
}

/// The ordinary fill's pixels.
struct Pixels<const W: usize, const H: usize>([[bool; W]; H]);

impl<const W: usize, const H: usize> SpanSink for Pixels<W, H> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, _: Colour) {
        for x in x_start..x_end {
            self.0[y as usize][x as usize] = true;
        }
    }
}

/// Whether the even-odd fill with the top-left rule covers the point `(cx, cy)`, in doubled
/// units of `2^-SUB` pixel: the crossings at or left of it, of the edges whose rows
/// `[top, bottom)` hold it, are odd in number. Exact, in `i128`.
fn inside<const SUB: u32>(poly: &[FixedPoint<SUB>], cx: i128, cy: i128) -> bool {
    let n = poly.len();
    let mut odd = false;
    for k in 0..n {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        let (mut t, mut u) = (
            (2 * i128::from(a.x), 2 * i128::from(a.y)),
            (2 * i128::from(b.x), 2 * i128::from(b.y)),
        );
        if t.1 > u.1 {
            core::mem::swap(&mut t, &mut u);
        }
        if !(t.1 <= cy && cy < u.1) {
            continue;
        }
        // Crossing x_e = t.x + (cy - t.y) (u.x - t.x) / (u.y - t.y) <= cx.
        let dy = u.1 - t.1;
        if t.0 * dy + (cy - t.1) * (u.0 - t.0) <= cx * dy {
            odd = !odd;
        }
    }
    odd
}

/// The mask brute force gives pixel `(i, j)`: sample `(s, t)` at
/// `(i + (s + 1/2) / C, j + (t + 1/2) / R)`, tested on the polygon scaled by `(C, R)`, the
/// grid's columns and rows.
fn brute_mask<const SUB: u32>(poly: &[FixedPoint<SUB>], i: usize, j: usize) -> Mask {
    let scaled: Vec<FixedPoint<SUB>> = poly
        .iter()
        .map(|p| FixedPoint::new(p.x * C as i32, p.y * R as i32))
        .collect();
    let (c, r) = (C as usize, R as usize);
    let unit = 1i128 << SUB;
    let mut mask = 0;
    for t in 0..SAMPLE_ROWS as usize {
        for s in 0..SAMPLE_COLUMNS as usize {
            let cx = (2 * (c * i + s) as i128 + 1) * unit;
            let cy = (2 * (r * j + t) as i128 + 1) * unit;
            if inside(&scaled, cx, cy) {
                mask |= 1 << (t * SAMPLE_COLUMNS as usize + s);
            }
        }
    }
    mask
}

const C: u32 = SAMPLE_COLUMNS;
const R: u32 = SAMPLE_ROWS;
const W: usize = 14;
const H: usize = 10;

fn check<const SUB: u32>(raw: &[(i32, i32)]) -> Result<(), TestCaseError> {
    let poly: Vec<FixedPoint<SUB>> = raw.iter().map(|&(x, y)| FixedPoint::new(x, y)).collect();
    let mut image = MaskImage::<W, H>::new();
    let mut scratch = [0 as Mask; W];
    let covered =
        fill_polygon_masks(&poly, W as u32, 0..H as u32, A, &mut scratch, &mut image).unwrap();
    prop_assert!(scratch.iter().all(|&m| m == 0), "scratch row left dirty");
    let mut pixels = Pixels([[false; W]; H]);
    fill_polygon(&poly, W as u32, H as u32, A, &mut pixels).unwrap();
    let mut count = 0;
    for j in 0..H {
        for i in 0..W {
            let m = image.masks[j][i];
            prop_assert_eq!(
                m,
                brute_mask(&poly, i, j),
                "pixel ({}, {}) of {:?}",
                i,
                j,
                poly
            );
            prop_assert_eq!(
                m >> CENTRE_SAMPLE & 1 == 1,
                pixels.0[j][i],
                "centre of ({}, {}) of {:?}",
                i,
                j,
                poly
            );
            count += u64::from(m.count_ones());
        }
    }
    prop_assert_eq!(covered, count);
    Ok(())
}

/// Up to 8 points within a pixel of the window, often on multiples of a fifteenth of a pixel
/// (where samples and edges meet and the tie rule decides) or of half a pixel.
fn points(sub: u32) -> impl Strategy<Value = Vec<(i32, i32)>> {
    let unit = 1i32 << sub;
    let coord = move |hi: i32| {
        (0..=hi * unit, 0..3).prop_map(move |(v, snap)| match snap {
            0 => v,
            1 => v / (unit / 2).max(1) * (unit / 2).max(1),
            // The nearest multiple of unit / 15 that the precision holds exactly.
            _ => v / (unit / 16).max(1) * (unit / 16).max(1),
        })
    };
    proptest::collection::vec((coord(W as i32 + 1), coord(H as i32 + 1)), 3..=8)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// Any polygon (non-convex, self-intersecting, degenerate): every mask is the brute-force
    /// even-odd test with the top-left rule at its samples, each pixel is sent once, and the
    /// centre sample is the ordinary fill's pixel.
    #[test]
    fn masks_match_brute_force_sub8(p in points(8)) {
        check::<8>(&p)?;
    }

    #[test]
    fn masks_match_brute_force_sub4(p in points(4)) {
        check::<4>(&p)?;
    }

    /// A fan of triangles around a point of a rectangle tiles its samples: each one inside is
    /// covered exactly once (the image panics on a second cover), and none outside.
    #[test]
    fn a_fan_tiles_the_samples(
        (x0, y0, x1, y1) in (0..3 * 256i32, 0..2 * 256i32, 8 * 256..12 * 256i32, 5 * 256..9 * 256i32),
        (px, py) in (0..1000i32, 0..1000i32),
        cuts in proptest::collection::vec(0..1000i32, 4),
    ) {
        let centre = FixedPoint::<8>::new(x0 + 1 + px * (x1 - x0 - 2) / 1000, y0 + 1 + py * (y1 - y0 - 2) / 1000);
        // The rectangle's outline with one extra point on each side, clockwise in y down.
        let along = |a: i32, b: i32, c: i32| a + (b - a) * c / 1000;
        let outline: [FixedPoint<8>; 8] = [
            FixedPoint::new(x0, y0),
            FixedPoint::new(along(x0, x1, cuts[0]), y0),
            FixedPoint::new(x1, y0),
            FixedPoint::new(x1, along(y0, y1, cuts[1])),
            FixedPoint::new(x1, y1),
            FixedPoint::new(along(x0, x1, cuts[2]), y1),
            FixedPoint::new(x0, y1),
            FixedPoint::new(x0, along(y0, y1, cuts[3])),
        ];
        let mut image = MaskImage::<W, H>::new();
        let mut scratch = [0 as Mask; W];
        for k in 0..outline.len() {
            image.next_polygon();
            let tri = [centre, outline[k], outline[(k + 1) % outline.len()]];
            fill_polygon_masks(&tri, W as u32, 0..H as u32, A, &mut scratch, &mut image).unwrap();
        }
        let rect: [FixedPoint<8>; 4] = [FixedPoint::new(x0, y0), FixedPoint::new(x1, y0), FixedPoint::new(x1, y1), FixedPoint::new(x0, y1)];
        for j in 0..H {
            for i in 0..W {
                prop_assert_eq!(image.masks[j][i], brute_mask(&rect, i, j), "pixel ({}, {})", i, j);
            }
        }
    }
}

#[test]
fn the_grid_has_the_centre_in_the_middle() {
    assert_eq!(SAMPLES, 25);
    assert_eq!(CENTRE_SAMPLE, 12);
    assert_eq!(FULL_MASK, 0x1ff_ffff);
    // A pixel-sized square on pixel boundaries covers all of its pixel's samples.
    let square = [(1, 1), (2, 1), (2, 2), (1, 2)].map(|(x, y)| FixedPoint::<8>::from_pixels(x, y));
    let mut image = MaskImage::<W, H>::new();
    let mut scratch = [0 as Mask; W];
    let covered =
        fill_polygon_masks(&square, W as u32, 0..H as u32, A, &mut scratch, &mut image).unwrap();
    assert_eq!((covered, image.masks[1][1]), (25, FULL_MASK));
    // Half of it, x in [1, 1.5): the samples at x = 1.1 and 1.3 of each row; the one at 1.5
    // lies on its right edge, which the top-left rule gives to the polygon right of it.
    let half =
        [(256, 256), (384, 256), (384, 512), (256, 512)].map(|(x, y)| FixedPoint::<8>::new(x, y));
    let mut image = MaskImage::<W, H>::new();
    fill_polygon_masks(&half, W as u32, 0..H as u32, A, &mut scratch, &mut image).unwrap();
    assert_eq!(image.masks[1][1], 0b00011_00011_00011_00011_00011);
}

#[test]
fn rows_limit_the_masks_and_a_short_scratch_row_is_refused() {
    let tri = [(0, 0), (12, 1), (3, 9)].map(|(x, y)| FixedPoint::<8>::from_pixels(x, y));
    let mut image = MaskImage::<W, H>::new();
    let mut scratch = [0 as Mask; W];
    fill_polygon_masks(&tri, W as u32, 3..5, A, &mut scratch, &mut image).unwrap();
    assert_eq!(image.rows, [3, 4]);
    for j in 0..H {
        for i in 0..W {
            let want = if (3..5).contains(&j) {
                brute_mask(&tri, i, j)
            } else {
                0
            };
            assert_eq!(image.masks[j][i], want, "pixel ({i}, {j})");
        }
    }
    let mut short = [0 as Mask; W - 1];
    let mut image = MaskImage::<W, H>::new();
    let refused = fill_polygon_masks(&tri, W as u32, 0..H as u32, A, &mut short, &mut image);
    assert_eq!(
        refused,
        Err(FillError::TooManyVertices {
            count: W,
            max: W - 1
        })
    );
    assert!(image.rows.is_empty());
}

// `fill_sample_rows`: the spans of a polygon on the sample grid, a pixel row at a time, against
// the general fill's.

use crate::fill::tests::hull;
use crate::fill::{MAX_FILL_VERTICES, SUBPIXEL_BITS};

/// A point on the sample grid at the renderer's precision.
type Point = FixedPoint<SUBPIXEL_BITS>;

/// `2^-SUBPIXEL_BITS` units per sample.
const UNIT: i32 = 1 << SUBPIXEL_BITS;
/// The window of the `fill_sample_rows` tests, in pixels.
const PIXELS_W: u32 = 40;
const PIXELS_H: u32 = 30;

/// What `fill_sample_rows` hands over: each pixel row's sample-row spans, in order.
#[derive(Default)]
struct SampleRows(Vec<(u32, RowSpans)>);

impl SampleSink for SampleRows {
    fn sample_rows(&mut self, y: u32, spans: &RowSpans, extent: &RowExtent) {
        assert_eq!(*extent, row_extent(spans), "pixel row {y}");
        self.0.push((y, *spans));
    }

    fn end(&mut self) {}
}

impl SpanSink for SampleRows {
    fn span(&mut self, y: u32, _: u32, _: u32, _: Colour) {
        panic!("fill_sample_rows handed over sample row {y} alone");
    }
}

/// Every span of a fill, in the order received.
#[derive(Default)]
struct AllSpans(Vec<(u32, u32, u32)>);

impl SpanSink for AllSpans {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        assert_eq!(colour, A);
        self.0.push((y, x_start, x_end));
    }
}

/// The general fill's spans of `points` over the sample rows `rows`.
fn general_spans(points: &[Point], width: u32, rows: Range<u32>) -> Vec<(u32, u32, u32)> {
    let mut all = AllSpans::default();
    fill_polygon_rows(points, width, rows, A, &mut all).unwrap();
    all.0
}

/// [`general_spans`] grouped as `fill_sample_rows` hands them over: a pixel row per entry, in
/// the order the general fill reaches them, each sample row's span or [`NO_SPAN`]; `None` when
/// some sample row has more than one span (no single span per sample row can match it).
fn general_rows(points: &[Point], width: u32, rows: Range<u32>) -> Option<Vec<(u32, RowSpans)>> {
    let mut grouped: Vec<(u32, RowSpans)> = Vec::new();
    for (y, x_start, x_end) in general_spans(points, width, rows) {
        let pixel_row = y / SAMPLE_ROWS;
        if grouped.last().is_none_or(|&(r, _)| r != pixel_row) {
            grouped.push((pixel_row, [NO_SPAN; SAMPLE_ROWS as usize]));
        }
        let slot = &mut grouped.last_mut()?.1[(y % SAMPLE_ROWS) as usize];
        if *slot != NO_SPAN {
            return None;
        }
        *slot = (x_start, x_end);
    }
    Some(grouped)
}

/// Run `fill_sample_rows` on `points` and check it against the general fill: when it accepts
/// the polygon, the same spans grouped the same way; when it refuses, nothing drawn. Returns
/// whether it accepted.
fn check_sample_rows(
    points: &[Point],
    width: u32,
    rows: Range<u32>,
) -> Result<bool, TestCaseError> {
    let mut edges = [EdgeWalk::default(); MAX_FILL_VERTICES];
    let mut fast = SampleRows::default();
    let accepted = fill_sample_rows(points, &mut edges, width, rows.clone(), &mut fast);
    if accepted {
        let general = general_rows(points, width, rows.clone());
        prop_assert_eq!(
            Some(fast.0),
            general,
            "{:?}, width {}, rows {:?}",
            points,
            width,
            rows
        );
    } else {
        prop_assert!(
            fast.0.is_empty(),
            "refused {:?} but drew {:?}",
            points,
            fast.0
        );
    }
    Ok(accepted)
}

/// A coordinate in `0..=samples` samples: anywhere, on a sample centre or boundary (multiples
/// of half a sample), on a pixel boundary, or on the window's border.
fn sample_coord(samples: i32) -> impl Strategy<Value = i32> {
    let hi = samples * UNIT;
    prop_oneof![
        3 => 0..=hi,
        2 => (0..=2 * samples).prop_map(|k| k * UNIT / 2),
        1 => (0..=samples / 5).prop_map(|k| k * 5 * UNIT),
        1 => prop_oneof![Just(0), Just(hi)],
    ]
}

/// A point of the sample grid of the `PIXELS_W x PIXELS_H` window, border included.
fn sample_point() -> impl Strategy<Value = Point> {
    (
        sample_coord((PIXELS_W * SAMPLE_COLUMNS) as i32),
        sample_coord((PIXELS_H * SAMPLE_ROWS) as i32),
    )
        .prop_map(|(x, y)| Point::new(x, y))
}

/// The hull of `p` in either winding, starting at any of its vertices.
fn convex_polygon(p: Vec<Point>, reverse: bool, rotate: usize) -> Vec<Point> {
    let mut h = hull(p);
    if reverse {
        h.reverse();
    }
    if !h.is_empty() {
        let k = rotate % h.len();
        h.rotate_left(k);
    }
    h
}

/// An axis-aligned rectangle with corners `a` and `b`, in either winding.
fn rectangle(a: Point, b: Point, reverse: bool) -> Vec<Point> {
    let mut r = std::vec![a, Point::new(b.x, a.y), b, Point::new(a.x, b.y)];
    if reverse {
        r.reverse();
    }
    r
}

/// Polygons of 3 to 8 points: arbitrary point lists (non-convex, self-intersecting,
/// degenerate), and convex ones in either winding.
fn sample_polygon() -> impl Strategy<Value = Vec<Point>> {
    prop_oneof![
        proptest::collection::vec(sample_point(), 3..=8),
        (
            proptest::collection::vec(sample_point(), 3..=8),
            any::<bool>(),
            any::<usize>()
        )
            .prop_map(|(p, reverse, rotate)| {
                let h = convex_polygon(p.clone(), reverse, rotate);
                if h.len() >= 3 {
                    h
                } else {
                    p
                }
            }),
    ]
}

/// A band of whole pixel rows of the window, as sample rows (possibly empty).
fn sample_band() -> impl Strategy<Value = Range<u32>> {
    (0..=PIXELS_H, 0..=PIXELS_H).prop_map(|(a, b)| a.min(b) * SAMPLE_ROWS..a.max(b) * SAMPLE_ROWS)
}

/// The window's width in samples, sometimes narrower than the polygons (spans clipped).
fn sample_width() -> impl Strategy<Value = u32> {
    prop_oneof![Just(PIXELS_W), 1..=PIXELS_W].prop_map(|w| w * SAMPLE_COLUMNS)
}

/// Three points: anywhere, collinear (a zero-area triangle), or with two equal.
fn triangle() -> impl Strategy<Value = Vec<Point>> {
    prop_oneof![
        2 => proptest::collection::vec(sample_point(), 3),
        1 => (sample_point(), sample_point(), 0..=4i32, any::<usize>()).prop_map(
            |(a, b, k, rotate)| {
                // a, its midpoint with b (exact: even coordinates), b, and k/4 of the way.
                let (ax, ay, bx, by) = (a.x & !3, a.y & !3, b.x & !3, b.y & !3);
                let along = Point::new(ax + (bx - ax) / 4 * k, ay + (by - ay) / 4 * k);
                let mut t = std::vec![Point::new(ax, ay), Point::new(bx, by), along];
                t.rotate_left(rotate % 3);
                t
            }
        ),
        1 => (sample_point(), sample_point(), any::<usize>()).prop_map(|(a, b, rotate)| {
            let mut t = std::vec![a, a, b];
            t.rotate_left(rotate % 3);
            t
        }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    /// Whenever `fill_sample_rows` accepts a polygon (arbitrary or convex, points on the
    /// window's border too) over a band of pixel rows, it hands over the general fill's spans,
    /// sample row for sample row, grouped into the pixel rows that have any, top to bottom,
    /// the others [`NO_SPAN`]; when it refuses one it draws nothing. A polygon with a point
    /// right of a narrower window (whose spans the general fill clips) is refused.
    #[test]
    fn sample_rows_match_the_general_fill(
        points in sample_polygon(),
        width in sample_width(),
        rows in sample_band(),
    ) {
        let outside = points.iter().any(|p| i64::from(p.x) > i64::from(width) * i64::from(UNIT));
        let accepted = check_sample_rows(&points, width, rows)?;
        prop_assert!(!(outside && accepted), "accepted {:?} in width {}", points, width);
    }

    /// Every triangle in the window, degenerate ones included, is accepted, over any band,
    /// with the general fill's spans.
    #[test]
    fn sample_rows_accept_every_triangle(points in triangle(), rows in sample_band()) {
        let width = PIXELS_W * SAMPLE_COLUMNS;
        prop_assert!(check_sample_rows(&points, width, rows)?, "refused {:?}", points);
    }

    /// Every strictly convex polygon in the window (the hull of exact grid points, so nothing
    /// is snapped), and every rectangle, in either winding and from any first vertex, is
    /// accepted, over any band, with the general fill's spans.
    #[test]
    fn sample_rows_accept_every_convex_polygon(
        p in proptest::collection::vec(sample_point(), 3..=12),
        (a, b) in (sample_point(), sample_point()),
        reverse in any::<bool>(),
        rotate in any::<usize>(),
        rows in sample_band(),
    ) {
        let width = PIXELS_W * SAMPLE_COLUMNS;
        let convex = convex_polygon(p, reverse, rotate);
        if convex.len() >= 3 {
            prop_assert!(check_sample_rows(&convex, width, rows.clone())?, "refused {:?}", convex);
        }
        let rect = rectangle(a, b, reverse);
        prop_assert!(check_sample_rows(&rect, width, rows)?, "refused {:?}", rect);
    }
}

/// Samples as points of the sample grid.
fn sample_points(p: &[(i32, i32)]) -> Vec<Point> {
    p.iter()
        .map(|&(x, y)| Point::new(x * UNIT, y * UNIT))
        .collect()
}

/// A "W" (three teeth hanging from a bar): the sample rows through the teeth cross three
/// edges going down and three going up, so it is refused and nothing is drawn, though the
/// general fill draws three spans on those rows; below the teeth, where only the bar's two
/// sides cross, a band of it is accepted with the general fill's spans.
#[test]
fn sample_rows_refuse_a_comb_but_accept_its_convex_band() {
    let comb = sample_points(&[
        (0, 0),
        (50, 100),
        (100, 0),
        (150, 100),
        (200, 0),
        (200, 150),
        (0, 150),
    ]);
    let (width, all) = (PIXELS_W * SAMPLE_COLUMNS, 0..PIXELS_H * SAMPLE_ROWS);
    let mut edges = [EdgeWalk::default(); MAX_FILL_VERTICES];
    let mut fast = SampleRows::default();
    assert!(!fill_sample_rows(
        &comb,
        &mut edges,
        width,
        all.clone(),
        &mut fast
    ));
    assert!(fast.0.is_empty());
    let general = general_spans(&comb, width, all.clone());
    assert_eq!(general.iter().filter(|s| s.0 == 50).count(), 3);
    assert!(general.iter().any(|s| s.0 == 149));
    assert_eq!(general_rows(&comb, width, all), None);
    // Pixel rows 21 .. 30: sample rows 105 .. 150, below the teeth.
    let below = 21 * SAMPLE_ROWS..30 * SAMPLE_ROWS;
    let accepted = check_sample_rows(&comb, width, below).unwrap();
    assert!(accepted);
    // A band reaching into the teeth is refused again.
    assert!(!check_sample_rows(&comb, width, 19 * SAMPLE_ROWS..30 * SAMPLE_ROWS).unwrap());
}

/// A band starting below the polygon's top vertex (a y-monotone, non-convex hexagon), with
/// vertices inside it on both sides (each chain moves to its next edge mid-band) and edges
/// crossing the band's top: the general fill's spans, on every sample row of every pixel row
/// of the band, and the same as the whole polygon's fill on those rows.
#[test]
fn sample_rows_of_a_band_starting_inside_the_polygon() {
    // In samples: top (100, 12.6), right (150, 36) (138, 104), bottom (200, 144), left
    // (60, 88) (30, 52); band: sample rows 25 .. 75 (pixel rows 5 .. 15).
    let pentagon: Vec<Point> = [
        (1000, 315),
        (1500, 900),
        (1380, 2600),
        (2000, 3600),
        (600, 2200),
        (300, 1300),
    ]
    .iter()
    .map(|&(x, y)| Point::new(x * UNIT / 10, y * UNIT / 25))
    .collect();
    let (width, band) = (PIXELS_W * SAMPLE_COLUMNS, 5 * SAMPLE_ROWS..15 * SAMPLE_ROWS);
    let mut edges = [EdgeWalk::default(); MAX_FILL_VERTICES];
    let mut fast = SampleRows::default();
    assert!(fill_sample_rows(
        &pentagon,
        &mut edges,
        width,
        band.clone(),
        &mut fast
    ));
    assert_eq!(
        Some(fast.0.clone()),
        general_rows(&pentagon, width, band.clone())
    );
    let pixel_rows: Vec<u32> = fast.0.iter().map(|r| r.0).collect();
    assert_eq!(pixel_rows, (5..15).collect::<Vec<u32>>());
    assert!(fast
        .0
        .iter()
        .all(|(_, spans)| spans.iter().all(|&(l, r)| l < r && r <= width)));
    // The band's spans are the whole polygon's on those rows.
    let whole = general_spans(&pentagon, width, 0..PIXELS_H * SAMPLE_ROWS);
    let in_band: Vec<(u32, u32, u32)> = whole.into_iter().filter(|s| band.contains(&s.0)).collect();
    assert_eq!(in_band, general_spans(&pentagon, width, band));
}
