extern crate std;

use std::vec::Vec;

use proptest::prelude::*;

use super::*;
use crate::fill::fill_polygon;

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
