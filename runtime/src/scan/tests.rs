//! Scan order: the memory against a pixel model, frames against the framebuffer's, rows in
//! order, running out as an error.

extern crate std;

use glam::{DVec3, Vec3};
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

use super::*;
use crate::camera::{Camera, Pose};
use crate::coverage::Coverage;
use crate::display::{
    dither_rgb565, Paint, Rgb565Framebuffer, RowShade, SpanSink, SHADE_FRACTION_BITS,
};
use crate::read::Node;
use crate::render::{Renderer, Source, Workspace};
use crate::traverse::testing::{box_faces, TestTree};

const W: u32 = 48;
const H: u32 = 36;
const BACKGROUND: Colour = Colour::new(0xab, 0xcd, 0xef);

/// The first colour written to each pixel (front to back: the one that shows), shaded pixels
/// dithered or not.
struct Model {
    width: usize,
    pixels: Vec<Option<u16>>,
    dither: bool,
}

impl Model {
    fn new(w: u32, h: u32) -> Self {
        Model {
            width: w as usize,
            pixels: vec![None; (w * h) as usize],
            dither: false,
        }
    }

    fn span(&mut self, y: u32, a: u32, b: u32, c: Colour) -> u64 {
        self.paint(y, a, b, |_| c.to_rgb565())
    }

    fn shaded_span(&mut self, y: u32, a: u32, b: u32, shade: &RowShade) -> u64 {
        if self.dither {
            self.paint(y, a, b, |x| dither_rgb565(x, y, shade.at(x)))
        } else {
            self.paint(y, a, b, |x| shade.at(x).to_rgb565())
        }
    }

    /// Paint the unpainted pixels of `a..b` in row `y`, pixel `x` in `colour(x)`.
    fn paint(&mut self, y: u32, a: u32, b: u32, colour: impl Fn(u32) -> u16) -> u64 {
        let mut n = 0;
        for x in a..b.min(self.width as u32) {
            let p = &mut self.pixels[y as usize * self.width + x as usize];
            if p.is_none() {
                *p = Some(colour(x));
                n += 1;
            }
        }
        n
    }

    fn image(&self, background: u16) -> Vec<u16> {
        self.pixels
            .iter()
            .map(|p| p.unwrap_or(background))
            .collect()
    }
}

/// Every row's list sorted, disjoint, and touching intervals of one colour merged.
fn well_formed(m: &ScanMemory<'_>) -> bool {
    (0..m.height()).all(|y| {
        let mut i = m.head(y);
        let mut last: Option<ScanNode> = None;
        let mut seen = 0;
        while i != NIL {
            let n = m.node(i);
            // Each node is some pixels wide, within the row; no list runs in a loop.
            seen += 1;
            if n.first() >= m.end(&n) || m.end(&n) > m.width || seen > m.capacity() {
                return false;
            }
            // A row never starts with a gap node (its first pixels are uncovered without
            // one), and never has two in a row.
            if n.is_gap() && last.is_none_or(|l| l.is_gap()) {
                return false;
            }
            // Neighbours of one RGB565 colour are one node.
            if let Some(l) = last {
                if !l.tagged() && !n.tagged() && l.colour == n.colour {
                    return false;
                }
            }
            last = Some(n);
            i = n.next;
        }
        true
    })
}

/// The nodes of row `y`'s list.
fn list_len(m: &ScanMemory<'_>, y: u32) -> usize {
    let mut i = m.head(y);
    let mut n = 0;
    while i != NIL && n <= m.capacity() {
        i = m.node(i).next;
        n += 1;
    }
    n
}

#[test]
fn intervals_merge_by_colour_and_answer_coverage() {
    let (mut nodes, mut heads) = ([ScanNode::EMPTY; 8], [0u16; 2]);
    let mut m = ScanMemory::new(&mut nodes, &mut heads, 10, 2).unwrap();
    let (red, blue) = (Colour::new(255, 0, 0), Colour::new(0, 0, 255));
    // Each interval with the gap node after it.
    assert_eq!(m.span(0, 2, 4, red), 2);
    assert_eq!(m.span(0, 6, 8, red), 2);
    assert_eq!((m.nodes_used(), list_len(&m, 0)), (4, 4));
    // Bridges the two red intervals: one node and its gap node, the others freed.
    assert_eq!(m.span(0, 3, 7, red), 2);
    assert_eq!(list_len(&m, 0), 2);
    assert!(well_formed(&m));
    assert!(m.covers(2, 0, 8, 1) && !m.covers(1, 0, 8, 1) && !m.covers(2, 0, 9, 1));
    // Another colour beside it: its own node, still one covered run.
    assert_eq!(m.span(0, 0, 10, blue), 4);
    assert_eq!(list_len(&m, 0), 3, "the gap node turned blue");
    assert!(m.covers(0, 0, 10, 1) && !m.covers(0, 0, 10, 2));
    assert!(m.is_full(1) && !m.is_full(2));
    let frame: Vec<u16> = m.pixels(7, Gaps::default()).collect();
    let (r, b) = (red.to_rgb565(), blue.to_rgb565());
    assert_eq!(frame[..10], [b, b, r, r, r, r, r, r, b, b]);
    assert!(frame[10..].iter().all(|&p| p == 7));
    assert_eq!(frame.len(), 20);
    // Spent: a span that needs a node is refused and the memory says so.
    let (mut nodes, mut heads) = ([ScanNode::EMPTY; 2], [0u16; 1]);
    let mut m = ScanMemory::new(&mut nodes, &mut heads, 10, 1).unwrap();
    assert_eq!(m.span(0, 0, 2, red), 2);
    assert_eq!(m.span(0, 2, 3, red), 1, "merged: no node needed");
    assert_eq!(m.span(0, 5, 6, red), 0);
    assert!(m.exhausted());
    assert!(ScanMemory::new(&mut [], &mut [0; 1], 10, 2).is_err());
}

/// A gradient along a row, `from` at column 0 (8-bit levels) and `per_pixel` more a column.
fn gradient(colour: Colour, from: f64, per_pixel: f64) -> RowShade {
    let unit = f64::from(1u32 << SHADE_FRACTION_BITS);
    RowShade {
        base: (from * unit) as i32,
        step: (per_pixel * unit) as i32,
        colour,
    }
}

/// Every pixel of row `y` of `m` read out, by the iterator and into a row.
#[cfg(feature = "smooth")]
fn row_of(m: &ScanMemory<'_>, y: u32) -> Vec<u16> {
    let w = m.width() as usize;
    let mut row = vec![0u16; w];
    m.row_into(y, 0, Gaps::default(), &mut row);
    let all: Vec<u16> = m.pixels(0, Gaps::default()).collect();
    assert_eq!(row[..], all[y as usize * w..][..w]);
    row
}

/// A shaded span of many colours takes two nodes, its pixels next to a flat neighbour of their
/// colour join it, pieces that continue a shade extend it (forward and back), and the pixels
/// are the shade's.
#[cfg(feature = "smooth")]
#[test]
fn a_shade_takes_two_nodes_whatever_its_colours() {
    let (mut nodes, mut heads) = ([ScanNode::EMPTY; 16], [0u16; 3]);
    let mut m = ScanMemory::new(&mut nodes, &mut heads, 200, 3).unwrap();
    m.set_dithering(false);
    let white = Colour::grey(255);
    let ramp = gradient(white, 10.0, 1.2);
    assert_eq!(m.paint(0, 0, 200, Paint::Shade(&ramp)), 200);
    assert_eq!(
        m.nodes_used(),
        2,
        "{} colours in two nodes",
        200 * 6 / 5 / 4
    );
    let want: Vec<u16> = (0..200).map(|x| ramp.at(x).to_rgb565()).collect();
    assert_eq!(row_of(&m, 0), want);
    // The same shade in pieces, right half first: one shaded interval, extended back.
    assert_eq!(m.paint(1, 100, 200, Paint::Shade(&ramp)), 100);
    assert_eq!(m.paint(1, 0, 100, Paint::Shade(&ramp)), 100);
    assert_eq!(m.nodes_used(), 4);
    assert_eq!(row_of(&m, 1), want);
    assert!(well_formed(&m));
    // A flat interval, then a shade of two colours beside it, the first the interval's: as runs,
    // the first joining the interval (one node more); then a shade of many colours each side
    // of those: shaded (two nodes each).
    let gentle = gradient(white, 100.0, 0.5);
    let runs = |a: u32, b: u32| {
        1 + (a + 1..b)
            .filter(|&x| gentle.at(x).to_rgb565() != gentle.at(x - 1).to_rgb565())
            .count()
    };
    let split = 50;
    // Up to the third run's first pixel.
    let end = (split + 1..200).find(|&x| runs(split, x + 1) == 3).unwrap();
    assert_eq!(runs(split, end), 2);
    let level = gentle.at(split);
    assert_eq!(m.span(2, 40, split, level), 10);
    assert_eq!(m.nodes_used(), 6, "the interval and the gap node after it");
    assert_eq!(
        m.paint(2, split, end, Paint::Shade(&gentle)),
        u64::from(end - split)
    );
    assert_eq!(m.nodes_used(), 7, "the second run's node");
    assert!(runs(0, 40) > 4 && runs(end, 190) > 4);
    assert_eq!(
        m.paint(2, 0, 190, Paint::Shade(&gentle)),
        u64::from(190 - end + 40)
    );
    assert_eq!(
        m.nodes_used(),
        11,
        "a pair each side, the gap node after the second"
    );
    assert_eq!(list_len(&m, 2), 5, "pair, interval, run, pair, gap");
    let row = row_of(&m, 2);
    assert!(row[40..split as usize]
        .iter()
        .all(|&p| p == level.to_rgb565()));
    let gentle_row: Vec<u16> = (0..190).map(|x| gentle.at(x).to_rgb565()).collect();
    assert_eq!(row[..40], gentle_row[..40]);
    assert_eq!(row[split as usize..190], gentle_row[split as usize..]);
    assert!(end - split > 4, "two runs of {}", end - split);
    assert!(well_formed(&m) && m.covers(0, 2, 190, 3) && !m.covers(0, 2, 191, 3));
}

/// A shaded interval's shade survives its packing into 58 bits: every value, and every step
/// within [`STEP_BITS`], of either sign, beside any material and first column.
#[test]
fn a_pair_keeps_its_shade() {
    let limit = 1i32 << (STEP_BITS - 1);
    for (value, step) in [
        (0, 0),
        (i32::MAX, limit - 1),
        (i32::MIN, -limit),
        (-1, -1),
        (
            200 << SHADE_FRACTION_BITS,
            -(3 << SHADE_FRACTION_BITS) + 12_345,
        ),
    ] {
        assert!(ScanNode::step_fits(step));
        let (first, second) = ScanNode::pair(MAX_WIDTH as u16, 7, 15, value, step);
        assert!(first.is_pair() && first.is_shaded() && !first.is_level() && !first.is_gap());
        assert_eq!(
            (first.first(), first.next, first.material_level()),
            (MAX_WIDTH as u16, 7, (15, 0))
        );
        assert_eq!(first.value_step(&second), (value, step));
    }
    assert!(!ScanNode::step_fits(limit) && !ScanNode::step_fits(-limit - 1));
}

/// A shade steeper than a pair keeps goes as runs, with the same pixels.
#[cfg(feature = "smooth")]
#[test]
fn a_steep_shade_goes_as_runs() {
    let (mut nodes, mut heads) = ([ScanNode::EMPTY; 64], [0u16; 1]);
    let mut m = ScanMemory::new(&mut nodes, &mut heads, 40, 1).unwrap();
    m.set_dithering(false);
    let steep = gradient(Colour::grey(255), 0.0, 17.0);
    assert!(!ScanNode::step_fits(steep.step));
    assert_eq!(m.paint(0, 5, 20, Paint::Shade(&steep)), 15);
    let want: Vec<u16> = (0..40)
        .map(|x| {
            if (5..20).contains(&x) {
                steep.at(x).to_rgb565()
            } else {
                0
            }
        })
        .collect();
    assert_eq!(row_of(&m, 0), want);
    assert!(m.nodes_used() > 4 && well_formed(&m));
}

/// Dithered (the default), a shade is kept to its 8-bit colours: a piece of few levels as
/// level runs, one node each, that join their neighbours of the same level and material (not a
/// flat interval of that colour, which is not dithered); one of many as a shaded interval; the
/// pixels read out dithered on the frame's rows.
#[cfg(feature = "smooth")]
#[test]
fn a_dithered_shade_keeps_its_levels() {
    let (mut nodes, mut heads) = ([ScanNode::EMPTY; 16], [0u16; 2]);
    let mut m = ScanMemory::new(&mut nodes, &mut heads, 64, 2).unwrap();
    assert!(m.dithering());
    let colour = Colour::new(250, 180, 90);
    // Two levels, 0..10 and 10..20: two level runs.
    let two = gradient(colour, 99.55, 0.1);
    let level = |x: u32| two.colours(x).level();
    assert_eq!(
        (level(0), level(9), level(10), level(19)),
        (100, 100, 101, 101)
    );
    assert_eq!(m.paint(0, 0, 20, Paint::Shade(&two)), 20);
    assert_eq!(
        m.nodes_used(),
        3,
        "two level runs and the gap node after them"
    );
    // The same shade on both sides: each piece joins the run of its level.
    assert_eq!(
        m.paint(0, 20, 24, Paint::Shade(&gradient(colour, 101.0, 0.0))),
        4
    );
    assert_eq!(m.nodes_used(), 3, "joined the second run");
    // A flat interval of the level's colour is not a level run: no join.
    let flat = two.at(0);
    assert_eq!(m.span(1, 0, 5, flat), 5);
    assert_eq!(m.paint(1, 5, 10, Paint::Shade(&two)), 5);
    assert_eq!(
        m.nodes_used(),
        6,
        "each with a gap node after it, the first turned level run"
    );
    // Many levels: one shaded interval, in the gap node's place.
    let ramp = gradient(colour, 20.0, 3.0);
    assert_eq!(m.paint(1, 10, 64, Paint::Shade(&ramp)), 54);
    assert_eq!(
        (m.nodes_used(), list_len(&m, 1)),
        (8, 3),
        "the gap node freed"
    );
    let want = |y: u32, x: u32| match (y, x) {
        (0, 0..20) => dither_rgb565(x, 0, two.at(x)),
        (0, _) => dither_rgb565(x, 0, two.at(19)),
        (1, 0..5) => flat.to_rgb565(),
        (1, 5..10) => dither_rgb565(x, 1, two.at(x)),
        (1, _) => dither_rgb565(x, 1, ramp.at(x)),
        _ => unreachable!(),
    };
    assert_eq!(
        row_of(&m, 0)[..24],
        (0..24).map(|x| want(0, x)).collect::<Vec<_>>()
    );
    assert_eq!(
        row_of(&m, 1),
        (0..64).map(|x| want(1, x)).collect::<Vec<_>>()
    );
    // The dither shows: a level between two RGB565 colours takes both.
    assert!(row_of(&m, 1)[5..10]
        .iter()
        .any(|&p| p != two.at(5).to_rgb565()));
    let pixels: Vec<u16> = m.pixels(3, Gaps::default()).collect();
    assert_eq!(pixels[64..], row_of(&m, 1)[..]);
    assert!(well_formed(&m));
}

/// More materials in a frame than scan memory names: the further ones are kept as runs of
/// one colour, with the same pixels.
#[cfg(feature = "smooth")]
#[test]
fn materials_beyond_the_palette_are_kept_as_runs() {
    let n = MATERIALS as u32 + 2;
    let mut nodes = vec![ScanNode::EMPTY; 400];
    let mut heads = vec![0u16; n as usize];
    let mut m = ScanMemory::new(&mut nodes, &mut heads, 64, n).unwrap();
    m.set_dithering(false);
    let shades: Vec<RowShade> = (0..n)
        .map(|k| gradient(Colour::new(255, 8 * k as u8, 100), 0.0, 4.0))
        .collect();
    for (y, shade) in shades.iter().enumerate() {
        assert_eq!(m.paint(y as u32, 0, 64, Paint::Shade(shade)), 64);
    }
    for (y, shade) in shades.iter().enumerate() {
        let want: Vec<u16> = (0..64).map(|x| shade.at(x).to_rgb565()).collect();
        assert_eq!(row_of(&m, y as u32), want, "row {y}");
        let nodes = (0..).scan(m.head(y as u32), |i, _| {
            (*i != NIL).then(|| {
                let n = m.node(*i);
                *i = n.next;
                n
            })
        });
        let (shaded, flat) = nodes.fold((0, 0), |(s, f), n| {
            if n.is_shaded() {
                (s + 1, f)
            } else {
                (s, f + 1)
            }
        });
        if y < MATERIALS {
            assert_eq!((shaded, flat), (1, 0), "row {y}");
        } else {
            assert_eq!(shaded, 0, "row {y}");
            assert!(flat > 8, "row {y}: {flat} runs");
        }
    }
    assert!(ScanMemory::new(&mut [], &mut [0; 1], MAX_WIDTH + 1, 1).is_err());
}

/// An anti-aliased frame's read-out: each row merges the scan memory's intervals (`a`, `b`)
/// with the pool's pending pixels (`p`, `q`: partly covered, their other samples the
/// background), the rest background (`.`); one run, row by row, and the colours the pool's
/// drain gives.
#[cfg(feature = "antialias")]
#[test]
fn pending_pixels_fill_their_gaps_in_the_read_out() {
    use crate::fill::samples::{SAMPLES, SAMPLE_COLUMNS, SAMPLE_ROWS};
    use crate::pending::{Pending, PendingPixel};
    let picture = ["aa.p.bbbp..q", "p...........", "qaaaaaaaaaap"];
    let (w, h) = (12u32, 3u32);
    let (a, b) = (Colour::new(200, 10, 10), Colour::new(10, 10, 200));
    let (p, q) = (Colour::new(250, 250, 0), Colour::new(0, 250, 250));
    // Nine samples of `p`, four of `q`: the first `k` of pixel `(x, y)`, row by row.
    let pend = |pool: &mut Pending<'_>, x: u32, y: u32, k: u32, c: Colour| {
        let (cols, rows) = (SAMPLE_COLUMNS, SAMPLE_ROWS);
        for t in 0..k.div_ceil(cols) {
            let n = (k - t * cols).min(cols);
            pool.gather(y * rows + t, x * cols, x * cols + n).unwrap();
        }
        let mut add = pool
            .begin_add(&crate::pending::SampleColour::new(c), None)
            .unwrap();
        assert_eq!(pool.next_run(&mut add, |_| false), None);
    };
    let (mut nodes, mut heads) = ([ScanNode::EMPTY; 16], [0u16; 3]);
    let mut m = ScanMemory::new(&mut nodes, &mut heads, w, h).unwrap();
    let mut records = [PendingPixel::default(); 16];
    let mut pending_heads = [0u16; 3];
    let mut pool = Pending::new(&mut records, &mut pending_heads, h).unwrap();
    for (y, line) in picture.iter().enumerate() {
        for (x, c) in line.bytes().enumerate() {
            let (x, y) = (x as u32, y as u32);
            match c {
                b'a' => {
                    m.span(y, x, x + 1, a);
                }
                b'b' => {
                    m.span(y, x, x + 1, b);
                }
                b'p' => pend(&mut pool, x, y, 9, p),
                b'q' => pend(&mut pool, x, y, 4, q),
                _ => {}
            }
        }
    }
    assert_eq!(
        m.nodes_used(),
        6,
        "a, b and a's run of the last row, each with the gap node after it"
    );
    assert_eq!(pool.in_use(), 6);
    // `k` of the samples in `c`, the rest `BACKGROUND`, rounded to nearest.
    let blend = |c: Colour, k: u32| {
        let ch = |v: u8, bg: u8| {
            let total = k * u32::from(v) + (SAMPLES - k) * u32::from(bg);
            ((2 * total + SAMPLES) / (2 * SAMPLES)) as u8
        };
        let (r, g, b) = (
            ch(c.r, BACKGROUND.r),
            ch(c.g, BACKGROUND.g),
            ch(c.b, BACKGROUND.b),
        );
        Colour::new(r, g, b).to_rgb565()
    };
    let bg = BACKGROUND.to_rgb565();
    let expected: Vec<u16> = picture
        .iter()
        .flat_map(|line| line.bytes())
        .map(|c| match c {
            b'a' => a.to_rgb565(),
            b'b' => b.to_rgb565(),
            b'p' => blend(p, 9),
            b'q' => blend(q, 4),
            _ => bg,
        })
        .collect();
    assert!(expected.iter().all(|&c| c != 0));
    let gaps = Gaps::pending(Some(&pool), BACKGROUND);
    assert_eq!(m.pixels(bg, gaps).collect::<Vec<_>>(), expected);
    let mut row = [0u16; 12];
    for y in 0..h {
        m.row_into(y, bg, gaps, &mut row);
        assert_eq!(
            row[..],
            expected[(y * w) as usize..][..w as usize],
            "row {y}"
        );
    }
    // Without the pool: the plain gaps.
    let plain: Vec<u16> = m.pixels(bg, Gaps::default()).collect();
    assert!(plain
        .iter()
        .zip(&expected)
        .all(|(&g, &e)| g == e || g == bg));
    // The colours the drain paints.
    let mut drained = Model::new(w, h);
    struct Into<'a>(&'a mut Model);
    impl SpanSink for Into<'_> {
        fn span(&mut self, y: u32, a: u32, b: u32, c: Colour) {
            self.0.span(y, a, b, c);
        }
    }
    assert_eq!(pool.drain(BACKGROUND, &mut Into(&mut drained)), 6);
    for (k, d) in drained.pixels.iter().enumerate() {
        if let Some(d) = d {
            assert_eq!(*d, expected[k], "pixel {k}");
        }
    }
}

/// The proptests' checks: `m`'s rows well formed and not exhausted, its frame read out (as
/// pixels and row by row) `model`'s image, and the coverage of rectangle `query` (`x0, y0, x1,
/// y1`) the model's.
fn agrees_with(
    m: &ScanMemory<'_>,
    model: &Model,
    query: (u32, u32, u32, u32),
) -> Result<(), TestCaseError> {
    let (w, h) = (m.width(), m.height());
    prop_assert!(well_formed(m));
    prop_assert!(!m.exhausted());
    prop_assert_eq!(
        m.pixels(3, Gaps::default()).collect::<Vec<_>>(),
        model.image(3)
    );
    let mut row = vec![0u16; w as usize];
    for y in 0..h {
        m.row_into(y, 3, Gaps::default(), &mut row);
        prop_assert_eq!(
            &row[..],
            &model.image(3)[(y * w) as usize..((y + 1) * w) as usize]
        );
    }
    let (x0, y0, x1, y1) = query;
    let covered = (y0..y1.min(h))
        .all(|y| (x0..x1.min(w)).all(|x| model.pixels[(y * w + x) as usize].is_some()) && x1 <= w)
        || x0 >= x1;
    prop_assert_eq!(m.covers(x0, y0, x1, y1), covered);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Random spans in random colours: the frame read out is the first colour written to
    /// each pixel, rows are well formed, coverage answers as the pixels do.
    #[test]
    fn spans_match_a_pixel_model(
        spans in proptest::collection::vec((0u32..6, 0u32..20, 0u32..22, 0u8..3), 0..80),
        query in (0u32..20, 0u32..6, 0u32..22, 0u32..7),
    ) {
        let (w, h) = (20, 6);
        let mut nodes = vec![ScanNode::EMPTY; 200];
        let mut heads = vec![0u16; h as usize];
        let mut m = ScanMemory::new(&mut nodes, &mut heads, w, h).unwrap();
        let mut model = Model::new(w, h);
        for &(y, a, b, c) in &spans {
            let colour = Colour::grey(c * 100);
            let want = if a < b { model.span(y, a, b, colour) } else { 0 };
            prop_assert_eq!(m.span(y, a, b, colour), want);
        }
        agrees_with(&m, &model, query)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Random flat and shaded spans (a few shades, shared by several spans, so that pieces
    /// continue each other): the frame read out is the first colour each pixel was painted,
    /// rows are well formed, coverage answers as the pixels do.
    #[test]
    fn shades_match_a_pixel_model(
        shades in proptest::collection::vec((0u8..4, 0.0f64..255.0, -6.0f64..6.0), 1..4),
        spans in proptest::collection::vec((0u32..4, 0u32..64, 0u32..66, 0usize..6), 0..60),
        query in (0u32..64, 0u32..4, 0u32..66, 0u32..5),
        dither in any::<bool>(),
    ) {
        let (w, h) = (64, 4);
        let shades: Vec<RowShade> = shades
            .iter()
            .map(|&(c, from, step)| gradient(Colour::new(255, 60 * c, 200), from, step))
            .collect();
        let mut nodes = vec![ScanNode::EMPTY; 600];
        let mut heads = vec![0u16; h as usize];
        let mut m = ScanMemory::new(&mut nodes, &mut heads, w, h).unwrap();
        m.set_dithering(dither);
        // (Without the `smooth` feature, shades are kept as RGB565 runs.)
        let mut model = Model { dither: dither && cfg!(feature = "smooth"), ..Model::new(w, h) };
        for &(y, a, b, k) in &spans {
            let (got, want) = match shades.get(k) {
                Some(shade) => (
                    m.paint(y, a, b, Paint::Shade(shade)),
                    if a < b { model.shaded_span(y, a, b, shade) } else { 0 },
                ),
                None => {
                    // A flat colour, some of them those of a shade's pixels.
                    let colour = shades[k % shades.len()].at(a % w);
                    (m.span(y, a, b, colour), if a < b { model.span(y, a, b, colour) } else { 0 })
                }
            };
            prop_assert_eq!(got, want);
        }
        agrees_with(&m, &model, query)?;
    }
}

/// The proptests' scene and camera: [`boxes`] of `(size, y, z)` along x, seen from `eye`.
fn boxes_seen(sizes: &[(f32, f32, f32)], eye: (f64, f64, f64)) -> (TestTree, Camera) {
    let items: Vec<(Vec3, f32)> = sizes
        .iter()
        .map(|&(r, y, z)| (Vec3::new(0.0, y, z), r))
        .collect();
    (boxes(&items), camera(DVec3::new(eye.0, eye.1, eye.2)))
}

/// Boxes along x, each a convex node, split planes between them, a colour per face.
fn boxes(items: &[(Vec3, f32)]) -> TestTree {
    let mut t = TestTree::default();
    fn build(t: &mut TestTree, items: &[(Vec3, f32)], base: u8) -> u32 {
        let (c, r) = items[0];
        let (lo, hi) = (c - Vec3::splat(r), c + Vec3::splat(r));
        if items.len() == 1 {
            let (first, count) = box_faces(t, lo, hi, Colour::default());
            for (k, p) in t.polygons[first as usize..].iter_mut().enumerate() {
                p.colour = Colour::new(base, 40 * k as u8, 255 - base);
            }
            return t.add_node(Node::Convex {
                first,
                count,
                child: None,
            });
        }
        let x = (hi.x + (items[1].0.x - items[1].1)) * 0.5;
        let plane = t.add_plane(Vec3::X, x);
        let i = t.add_node(Node::Convex {
            first: 0,
            count: 0,
            child: None,
        });
        let back = build(t, &items[..1], base);
        let front = build(t, &items[1..], base.wrapping_add(30));
        t.nodes[i as usize] = Node::Split {
            plane,
            front: Some(front),
            back: Some(back),
        };
        i
    }
    let mut sorted = items.to_vec();
    let mut x = -6.0f32;
    for item in &mut sorted {
        item.0.x = x + item.1;
        x += 2.0 * item.1 + 0.3;
    }
    build(&mut t, &sorted, 20);
    t
}

fn camera(eye: DVec3) -> Camera {
    Camera::look_at(Pose::new(eye, DVec3::ZERO), 70.0, W, H, 0.05).unwrap()
}

/// The front-to-back frame into an RGB565 framebuffer with the background.
fn framebuffer_frame(t: &TestTree, cam: &Camera) -> Vec<u16> {
    let mut pixels = vec![0u16; (W * H) as usize];
    let mut fb = Rgb565Framebuffer::new(&mut pixels, W, H).unwrap();
    let (mut intervals, mut counts) = (vec![(0u16, 0u16); 32 * H as usize], vec![0u16; H as usize]);
    let mut ws = Workspace::<16, 12>::new();
    let coverage = Coverage::new(&mut intervals, &mut counts, W, H).unwrap();
    let stats = Renderer::new(&mut ws)
        .span_memory(coverage)
        .background(BACKGROUND)
        .draw(t, &cam.view(t.centre()), &mut fb)
        .unwrap();
    assert!(!stats.fallback);
    pixels
}

/// Rows in order, each once, each `W` pixels: panics otherwise.
struct Rows {
    next: u32,
    image: Vec<u16>,
}

impl Rows {
    fn row(&mut self, y: u32, pixels: &[u16]) {
        assert_eq!(y, self.next, "rows out of order");
        assert_eq!(pixels.len(), W as usize);
        self.image.extend_from_slice(pixels);
        self.next += 1;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    /// Random boxes and eyes: the scan-order frame is the framebuffer's, pixel for pixel,
    /// read as one run or row by row.
    #[test]
    fn scan_order_is_the_framebuffer_frame(
        sizes in proptest::collection::vec((0.3f32..2.0, -2.0f32..2.0, -2.0f32..2.0), 1..5),
        eye in (-9.0f64..9.0, -6.0f64..6.0, 3.0f64..12.0),
    ) {
        let (t, cam) = boxes_seen(&sizes, eye);
        let reference = framebuffer_frame(&t, &cam);
        let mut nodes = vec![ScanNode::EMPTY; 2048];
        let mut heads = vec![0u16; H as usize];
        let memory = ScanMemory::new(&mut nodes, &mut heads, W, H).unwrap();
        let mut ws = Workspace::<16, 12>::new();
        let mut renderer = Renderer::new(&mut ws).scan_memory(memory).background(BACKGROUND);
        for _ in 0..2 {
            // Twice: the memory is cleared between frames.
            let frame = renderer.draw_scan(&t, &cam.view(t.centre())).unwrap();
            prop_assert!(!frame.stats().fallback);
            prop_assert_eq!(frame.pixels().collect::<Vec<_>>(), reference.clone());
            let mut rows = Rows { next: 0, image: Vec::new() };
            let mut buffer = [0u16; W as usize];
            for y in 0..frame.height() {
                frame.row_into(y, &mut buffer);
                rows.row(y, &buffer);
            }
            prop_assert_eq!(&rows.image, &reference);
            let used = frame.nodes_used();
            // Exactly that much memory is enough; one node less is an error.
            let mut nodes = vec![ScanNode::EMPTY; used];
            let mut heads = vec![0u16; H as usize];
            let memory = ScanMemory::new(&mut nodes, &mut heads, W, H).unwrap();
            let mut ws = Workspace::<16, 12>::new();
            let mut exact = Renderer::new(&mut ws).scan_memory(memory).background(BACKGROUND);
            let pixels: Vec<u16> = exact.draw_scan(&t, &cam.view(t.centre())).unwrap().pixels().collect();
            prop_assert_eq!(pixels, reference.clone());
            if used > 0 {
                let mut nodes = vec![ScanNode::EMPTY; used - 1];
                let mut heads = vec![0u16; H as usize];
                let memory = ScanMemory::new(&mut nodes, &mut heads, W, H).unwrap();
                let mut ws = Workspace::<16, 12>::new();
                let mut short = Renderer::new(&mut ws).scan_memory(memory);
                prop_assert_eq!(
                    short.draw_scan(&t, &cam.view(t.centre())).err(),
                    Some(RenderError::ScanMemoryFull { nodes: used as u32 - 1 })
                );
            }
        }
    }
}

/// The anti-aliased front-to-back frame into an RGB565 framebuffer with the background, and
/// whether it was anti-aliased.
#[cfg(feature = "antialias")]
fn antialiased_framebuffer_frame(t: &TestTree, cam: &Camera, records: usize) -> (Vec<u16>, bool) {
    use crate::pending::{Pending, PendingPixel};
    let mut pixels = vec![0u16; (W * H) as usize];
    let mut fb = Rgb565Framebuffer::new(&mut pixels, W, H).unwrap();
    let (mut intervals, mut counts) = (vec![(0u16, 0u16); 32 * H as usize], vec![0u16; H as usize]);
    let mut pool = vec![PendingPixel::default(); records];
    let mut heads = vec![0u16; H as usize];
    let mut ws = Workspace::<16, 12>::new();
    let coverage = Coverage::new(&mut intervals, &mut counts, W, H).unwrap();
    let pending = Pending::new(&mut pool, &mut heads, H).unwrap();
    let stats = Renderer::new(&mut ws)
        .span_memory(coverage)
        .antialias(pending)
        .background(BACKGROUND)
        .draw(t, &cam.view(t.centre()), &mut fb)
        .unwrap();
    assert!(!stats.fallback);
    (pixels, stats.antialiased)
}

/// The scan-order frame with `nodes` nodes, anti-aliased with `records` records (read as one
/// run and row by row, which must agree), its stats and nodes used.
#[cfg(feature = "antialias")]
fn antialiased_scan_frame(
    t: &TestTree,
    cam: &Camera,
    nodes: usize,
    records: usize,
) -> Result<(Vec<u16>, crate::render::FrameStats, usize), RenderError> {
    use crate::pending::{Pending, PendingPixel};
    let mut pool = vec![ScanNode::EMPTY; nodes];
    let mut heads = vec![0u16; H as usize];
    let memory = ScanMemory::new(&mut pool, &mut heads, W, H).unwrap();
    let mut records = vec![PendingPixel::default(); records];
    let mut pending_heads = vec![0u16; H as usize];
    let pending = Pending::new(&mut records, &mut pending_heads, H).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let mut renderer = Renderer::new(&mut ws)
        .scan_memory(memory)
        .antialias(pending)
        .background(BACKGROUND);
    let frame = renderer.draw_scan(t, &cam.view(t.centre()))?;
    let pixels: Vec<u16> = frame.pixels().collect();
    let mut rows = Rows {
        next: 0,
        image: Vec::new(),
    };
    let mut buffer = [0u16; W as usize];
    for y in 0..frame.height() {
        frame.row_into(y, &mut buffer);
        rows.row(y, &buffer);
    }
    assert_eq!(rows.image, pixels, "row by row as in one run");
    Ok((pixels, frame.stats(), frame.nodes_used()))
}

#[cfg(feature = "antialias")]
proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    /// Random boxes and eyes, anti-aliased: the scan-order frame is the framebuffer's; with
    /// a pool of 0 or 8 records each pixel is the anti-aliased or the plain one (all plain
    /// with none), as streamed; scan memory enough for the plain frame but not for the
    /// anti-aliased one draws the plain frame; less than both is an error.
    #[test]
    fn antialiased_scan_order_is_the_framebuffer_frame(
        sizes in proptest::collection::vec((0.3f32..2.0, -2.0f32..2.0, -2.0f32..2.0), 1..5),
        eye in (-9.0f64..9.0, -6.0f64..6.0, 3.0f64..12.0),
    ) {
        let (t, cam) = boxes_seen(&sizes, eye);
        let (reference, antialiased) = antialiased_framebuffer_frame(&t, &cam, 4096);
        prop_assert!(antialiased);
        let plain = framebuffer_frame(&t, &cam);
        let (pixels, stats, aa_nodes) = antialiased_scan_frame(&t, &cam, 2048, 4096).unwrap();
        prop_assert!(stats.antialiased);
        prop_assert_eq!(&pixels, &reference);
        for records in [0, 8] {
            let (few, stats, _) = antialiased_scan_frame(&t, &cam, 2048, records).unwrap();
            prop_assert!(stats.antialiased);
            for k in 0..few.len() {
                prop_assert!(few[k] == reference[k] || few[k] == plain[k], "pixel {}", k);
            }
            if records == 0 {
                prop_assert_eq!(&few, &plain);
            }
            let (streamed, _) = antialiased_framebuffer_frame(&t, &cam, records);
            prop_assert_eq!(&few, &streamed);
        }
        // The plain frame's need (more or less than the anti-aliased one's), then memory
        // between the two.
        let plain_nodes = {
            let mut nodes = vec![ScanNode::EMPTY; 2048];
            let mut heads = vec![0u16; H as usize];
            let memory = ScanMemory::new(&mut nodes, &mut heads, W, H).unwrap();
            let mut ws = Workspace::<16, 12>::new();
            let mut renderer = Renderer::new(&mut ws).scan_memory(memory);
            renderer.draw_scan(&t, &cam.view(t.centre())).unwrap().nodes_used()
        };
        let (exact, stats, _) = antialiased_scan_frame(&t, &cam, aa_nodes, 4096).unwrap();
        prop_assert!(stats.antialiased);
        prop_assert_eq!(&exact, &reference);
        for nodes in [plain_nodes, aa_nodes.saturating_sub(1)] {
            if nodes < aa_nodes && nodes >= plain_nodes {
                let (short, stats, _) = antialiased_scan_frame(&t, &cam, nodes, 4096).unwrap();
                prop_assert!(!stats.antialiased && !stats.fallback);
                prop_assert_eq!(&short, &plain);
            }
        }
        // Less than both: nothing.
        let fewest = plain_nodes.min(aa_nodes);
        if fewest > 0 {
            prop_assert_eq!(
                antialiased_scan_frame(&t, &cam, fewest - 1, 4096).err(),
                Some(RenderError::ScanMemoryFull { nodes: fewest as u32 - 1 })
            );
        }
    }
}

#[test]
fn never_back_to_front() {
    let t = boxes(&[(Vec3::ZERO, 1.0), (Vec3::ZERO, 1.5)]);
    let view = camera(DVec3::new(0.5, 2.0, 9.0)).view(t.centre());
    let mut ws = Workspace::<16, 12>::new();
    // No scan memory.
    let mut r = Renderer::new(&mut ws);
    assert_eq!(
        r.draw_scan(&t, &view).err(),
        Some(RenderError::NotFrontToBack)
    );
    // Back to front asked for.
    let (mut nodes, mut heads) = (vec![ScanNode::EMPTY; 512], vec![0u16; H as usize]);
    let memory = ScanMemory::new(&mut nodes, &mut heads, W, H).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let mut r = Renderer::new(&mut ws).scan_memory(memory).back_to_front();
    assert_eq!(
        r.draw_scan(&t, &view).err(),
        Some(RenderError::NotFrontToBack)
    );
    // Memory of another size.
    let (mut nodes, mut heads) = (vec![ScanNode::EMPTY; 512], vec![0u16; H as usize]);
    let memory = ScanMemory::new(&mut nodes, &mut heads, W - 1, H).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let mut r = Renderer::new(&mut ws).scan_memory(memory);
    assert_eq!(r.draw_scan(&t, &view).err(), Some(RenderError::SpanMemory));
    // No nodes at all.
    let mut heads = vec![0u16; H as usize];
    let memory = ScanMemory::new(&mut [], &mut heads, W, H).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let mut r = Renderer::new(&mut ws).scan_memory(memory);
    assert_eq!(
        r.draw_scan(&t, &view).err(),
        Some(RenderError::ScanMemoryFull { nodes: 0 })
    );
}

/// A sink that must be written once per pixel, streamed.
struct Display {
    written: Vec<bool>,
}

impl SpanSink for Display {
    fn span(&mut self, y: u32, a: u32, b: u32, _: Colour) {
        for x in a..b {
            let p = &mut self.written[(y * W + x) as usize];
            assert!(!*p, "overdraw at ({x}, {y})");
            *p = true;
        }
    }

    fn write_once(&self) -> bool {
        true
    }
}

#[test]
fn a_streamed_display_is_never_painted_back_to_front() {
    let t = boxes(&[(Vec3::ZERO, 1.0), (Vec3::ZERO, 1.5), (Vec3::ZERO, 0.7)]);
    let view = camera(DVec3::new(0.5, 2.0, 9.0)).view(t.centre());
    let mut display = Display {
        written: vec![false; (W * H) as usize],
    };
    let mut ws = Workspace::<16, 12>::new();
    let mut r = Renderer::new(&mut ws).background(BACKGROUND);
    assert_eq!(
        r.draw(&t, &view, &mut display).err(),
        Some(RenderError::NotFrontToBack)
    );
    assert!(
        display.written.iter().all(|&w| !w),
        "refused before any pixel"
    );
    // Too little span memory: it stops where it ran out, with no overdraw.
    let (mut intervals, mut counts) = (vec![(0u16, 0u16); H as usize], vec![0u16; H as usize]);
    let coverage = Coverage::new(&mut intervals, &mut counts, W, H).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let mut r = Renderer::new(&mut ws)
        .span_memory(coverage)
        .background(BACKGROUND);
    assert_eq!(
        r.draw(&t, &view, &mut display).err(),
        Some(RenderError::SpanMemoryFull)
    );
    // Enough: every pixel once.
    display.written.fill(false);
    let (mut intervals, mut counts) = (vec![(0u16, 0u16); 16 * H as usize], vec![0u16; H as usize]);
    let coverage = Coverage::new(&mut intervals, &mut counts, W, H).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let mut r = Renderer::new(&mut ws)
        .span_memory(coverage)
        .background(BACKGROUND);
    r.draw(&t, &view, &mut display).unwrap();
    assert!(display.written.iter().all(|&w| w));
}

#[cfg(feature = "embedded-graphics")]
mod embedded {
    use super::*;
    use embedded_graphics_core::draw_target::DrawTarget;
    use embedded_graphics_core::geometry::{OriginDimensions, Size};
    use embedded_graphics_core::pixelcolor::{IntoStorage, Rgb565};
    use embedded_graphics_core::primitives::Rectangle;
    use embedded_graphics_core::Pixel;

    /// A panel that takes exactly one window, the whole screen, and panics on anything else.
    struct Panel {
        windows: usize,
        pixels: Vec<u16>,
    }

    impl OriginDimensions for Panel {
        fn size(&self) -> Size {
            Size::new(W, H)
        }
    }

    impl DrawTarget for Panel {
        type Color = Rgb565;
        type Error = core::convert::Infallible;

        fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(
            &mut self,
            _: I,
        ) -> Result<(), Self::Error> {
            panic!("a scan-order frame is one window, not pixels");
        }

        fn fill_contiguous<I: IntoIterator<Item = Rgb565>>(
            &mut self,
            area: &Rectangle,
            colours: I,
        ) -> Result<(), Self::Error> {
            self.windows += 1;
            assert_eq!(self.windows, 1, "one window a frame");
            assert_eq!(*area, self.bounding_box_of());
            self.pixels
                .extend(colours.into_iter().map(|c| c.into_storage()));
            Ok(())
        }
    }

    impl Panel {
        fn bounding_box_of(&self) -> Rectangle {
            Rectangle::new(Default::default(), self.size())
        }
    }

    #[test]
    fn one_window_in_scan_order() {
        let t = boxes(&[(Vec3::ZERO, 1.0), (Vec3::ZERO, 1.5)]);
        let cam = camera(DVec3::new(-7.0, 1.0, 3.0));
        let reference = framebuffer_frame(&t, &cam);
        let (mut nodes, mut heads) = (vec![ScanNode::EMPTY; 512], vec![0u16; H as usize]);
        let memory = ScanMemory::new(&mut nodes, &mut heads, W, H).unwrap();
        let mut ws = Workspace::<16, 12>::new();
        let mut r = Renderer::new(&mut ws)
            .scan_memory(memory)
            .background(BACKGROUND);
        let frame = r.draw_scan(&t, &cam.view(t.centre())).unwrap();
        let mut panel = Panel {
            windows: 0,
            pixels: Vec::new(),
        };
        frame.draw_to(&mut panel).unwrap();
        assert_eq!(panel.pixels, reference);
    }

    /// Anti-aliased: still one window, the merged frame.
    #[cfg(feature = "antialias")]
    #[test]
    fn one_window_for_an_antialiased_frame() {
        use crate::pending::{Pending, PendingPixel};
        let t = boxes(&[(Vec3::ZERO, 1.0), (Vec3::ZERO, 1.5)]);
        let cam = camera(DVec3::new(-7.0, 1.0, 3.0));
        let (reference, _) = antialiased_framebuffer_frame(&t, &cam, 4096);
        assert_ne!(reference, framebuffer_frame(&t, &cam), "edges blended");
        let (mut nodes, mut heads) = (vec![ScanNode::EMPTY; 512], vec![0u16; H as usize]);
        let memory = ScanMemory::new(&mut nodes, &mut heads, W, H).unwrap();
        let mut records = vec![PendingPixel::default(); 4096];
        let mut pending_heads = vec![0u16; H as usize];
        let pending = Pending::new(&mut records, &mut pending_heads, H).unwrap();
        let mut ws = Workspace::<16, 12>::new();
        let mut r = Renderer::new(&mut ws)
            .scan_memory(memory)
            .antialias(pending)
            .background(BACKGROUND);
        let frame = r.draw_scan(&t, &cam.view(t.centre())).unwrap();
        assert!(frame.stats().antialiased);
        let mut panel = Panel {
            windows: 0,
            pixels: Vec::new(),
        };
        frame.draw_to(&mut panel).unwrap();
        assert_eq!(panel.pixels, reference);
        let colours: Vec<u16> = frame.colours().map(|c| c.into_storage()).collect();
        assert_eq!(colours, reference);
    }
}
