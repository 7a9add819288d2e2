extern crate std;

use std::vec;
use std::vec::Vec;

use proptest::prelude::*;

use super::*;
use crate::coverage::{Coverage, Mode};
use crate::display::{over, SpanSink};

const W: u32 = 24;
const H: u32 = 3;

/// Records every pixel once; panics on a pixel written twice (each pixel is sent once front
/// to back, transparent or not).
struct Once {
    pixels: Vec<Option<Colour>>,
}

impl Once {
    fn new() -> Once {
        Once {
            pixels: vec![None; (W * H) as usize],
        }
    }

    fn at(&self, x: u32, y: u32) -> Option<Colour> {
        self.pixels[(y * W + x) as usize]
    }
}

impl SpanSink for Once {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        for x in x_start..x_end {
            let p = &mut self.pixels[(y * W + x) as usize];
            assert!(p.is_none(), "pixel ({x}, {y}) written twice");
            *p = Some(colour);
        }
    }
}

/// One span of a test: opaque (`opacity` 255) or transparent.
#[derive(Debug, Clone, Copy)]
struct Span {
    y: u32,
    a: u32,
    b: u32,
    colour: Colour,
    opacity: u8,
}

/// The exact composite of each pixel: the spans front to back (in the order drawn) until an
/// opaque one, then the background; in 8-bit units, unrounded.
fn model(spans: &[Span], background: Colour) -> Vec<[f64; 3]> {
    let mut out = vec![[0.0; 3]; (W * H) as usize];
    for y in 0..H {
        for x in 0..W {
            let (mut sum, mut t) = ([0.0f64; 3], 1.0f64);
            let mut end = background;
            for s in spans.iter().filter(|s| s.y == y && s.a <= x && x < s.b) {
                if s.opacity == 255 {
                    end = s.colour;
                    break;
                }
                let a = f64::from(s.opacity) / 255.0;
                let c = [s.colour.r, s.colour.g, s.colour.b];
                for k in 0..3 {
                    sum[k] += t * a * f64::from(c[k]);
                }
                t *= 1.0 - a;
            }
            let e = [end.r, end.g, end.b];
            out[(y * W + x) as usize] = [0, 1, 2].map(|k| sum[k] + t * f64::from(e[k]));
        }
    }
    out
}

/// Draw `spans` front to back through a coverage and a composite of `records` runs, then the
/// end of the frame; returns the sink and the rows that fell back.
fn draw(spans: &[Span], records: usize, background: Colour) -> (Once, Composite<'static>) {
    let intervals = Vec::leak(vec![(0u16, 0u16); (W * H * 8) as usize]);
    let counts = Vec::leak(vec![0u16; H as usize]);
    let runs = Vec::leak(vec![CompositeRun::default(); records]);
    let heads = Vec::leak(vec![0u16; H as usize]);
    let mut coverage = Coverage::new(intervals, counts, W, H).unwrap();
    coverage.set_mode(Mode::Exclusive);
    let mut composite = Composite::new(runs, heads, H).unwrap();
    let mut sink = Once::new();
    for s in spans {
        let mut route = Composited {
            composite: &mut composite,
            coverage: &mut coverage,
            sink: &mut sink,
            first_row: 0,
            pixels: 0,
            door: None,
        };
        if s.opacity == 255 {
            route.span(s.y, s.a, s.b, s.colour);
        } else {
            route.transparent_span(s.y, s.a, s.b, s.colour, s.opacity);
        }
        check_invariants(&composite, &coverage);
    }
    composite.finish_rows(&mut coverage, Some(background), H, 0, &mut sink);
    (sink, composite)
}

/// The runs of each row are sorted, disjoint, non-empty, and cover no pixel the span memory
/// covers; the records in use are counted right.
fn check_invariants(c: &Composite<'_>, coverage: &Coverage<'_>) {
    let mut records = 0;
    for y in 0..H {
        if c.fallen(y) {
            continue;
        }
        let mut at = c.head(y);
        let mut last_end = 0;
        while at != NONE {
            let r = c.run(at);
            assert!(start(r) < end(r), "empty run {r:?}");
            assert!(
                start(r) >= last_end,
                "runs of row {y} overlap or are unsorted"
            );
            for x in start(r)..end(r) {
                assert!(
                    !coverage.covers_pixel(x, y),
                    "a run holds covered pixel {x}"
                );
            }
            last_end = end(r);
            records += 1;
            at = next(r);
        }
    }
    assert_eq!(records, c.in_use);
}

fn span(y: u32, a: u32, b: u32, colour: Colour, opacity: u8) -> Span {
    Span {
        y,
        a,
        b,
        colour,
        opacity,
    }
}

#[test]
fn two_panes_over_an_opaque_span_and_the_background() {
    let red = Colour::new(255, 0, 0);
    let blue = Colour::new(0, 0, 255);
    let green = Colour::new(0, 200, 0);
    let bg = Colour::new(10, 20, 30);
    let spans = [
        span(1, 2, 12, red, 128),
        span(1, 6, 20, blue, 64),
        span(1, 4, 9, green, 255),
    ];
    let (sink, composite) = draw(&spans, 16, bg);
    let exact = model(&spans, bg);
    for y in 0..H {
        for x in 0..W {
            let got = sink.at(x, y).expect("every pixel is written");
            let want = exact[(y * W + x) as usize];
            for (g, w) in [got.r, got.g, got.b].into_iter().zip(want) {
                assert!(
                    (f64::from(g) - w).abs() <= 1.0,
                    "({x}, {y}): {got:?} vs {want:?}"
                );
            }
        }
    }
    // Red over green where only red is in front, as the framebuffer's blend gives it.
    assert_eq!(sink.at(5, 1), Some(over(red, 128, green)));
    assert_eq!(composite.fallen_rows(), 0);
    assert!(composite.peak() >= 3);
}

#[test]
fn fragments_of_one_face_make_one_run() {
    let glass = Colour::new(200, 220, 255);
    let spans = [span(0, 0, 5, glass, 90), span(0, 5, 11, glass, 90)];
    let intervals = Vec::leak(vec![(0u16, 0u16); 64]);
    let counts = Vec::leak(vec![0u16; H as usize]);
    let runs = Vec::leak(vec![CompositeRun::default(); 8]);
    let heads = Vec::leak(vec![0u16; H as usize]);
    let mut coverage = Coverage::new(intervals, counts, W, H).unwrap();
    let mut composite = Composite::new(runs, heads, H).unwrap();
    let mut sink = Once::new();
    for s in spans {
        Composited {
            composite: &mut composite,
            coverage: &mut coverage,
            sink: &mut sink,
            first_row: 0,
            pixels: 0,
            door: None,
        }
        .transparent_span(s.y, s.a, s.b, s.colour, s.opacity);
    }
    assert_eq!(composite.in_use, 1);
    assert_eq!(start(composite.run(composite.head(0))), 0);
    assert_eq!(end(composite.run(composite.head(0))), 11);
}

#[test]
fn a_row_out_of_records_falls_back_and_keeps_nothing() {
    let glass = Colour::new(100, 100, 255);
    // Three separate runs on row 0 need three records; there are two.
    let spans = [
        span(0, 0, 2, glass, 100),
        span(0, 4, 6, glass, 100),
        span(0, 8, 10, glass, 100),
        span(2, 0, 4, glass, 100),
    ];
    let (sink, composite) = draw(&spans, 2, Colour::grey(0));
    assert_eq!(composite.fallen_rows(), 1);
    assert!(composite.fallen(0));
    assert!(!composite.fallen(2));
    // A row that fell back is left to the screen-door pass: nothing of it was sent.
    assert!((0..W).all(|x| sink.at(x, 0).is_none()));
    assert!(sink.at(1, 2).is_some());
}

#[test]
fn an_opaque_span_inside_a_run_needs_a_record() {
    let glass = Colour::new(100, 100, 255);
    let wall = Colour::new(9, 9, 9);
    // One record: the pane's run; the wall inside it would split it.
    let spans = [span(0, 0, 20, glass, 100), span(0, 5, 8, wall, 255)];
    let (_, composite) = draw(&spans, 1, Colour::grey(0));
    assert_eq!(composite.fallen_rows(), 1);
    let (sink, composite) = draw(&spans, 2, Colour::grey(0));
    assert_eq!(composite.fallen_rows(), 0);
    assert_eq!(sink.at(6, 0), Some(over(glass, 100, wall)));
    // The peak counts the record the wall asked for.
    assert_eq!(composite.peak(), 2);
}

fn arb_span() -> impl Strategy<Value = Span> {
    (
        0..H,
        0..W,
        1..W,
        any::<[u8; 3]>(),
        prop_oneof![Just(255u8), 1u8..255],
    )
        .prop_map(|(y, a, len, c, opacity)| Span {
            y,
            a,
            b: (a + len).min(W),
            colour: Colour::new(c[0], c[1], c[2]),
            opacity,
        })
}

proptest! {
    /// Any spans front to back: each pixel sent once, the runs' invariants hold after every
    /// span, and every pixel is within a level of the exact composite (up to three panes).
    #[test]
    fn composites_like_the_exact_model(spans in proptest::collection::vec(arb_span(), 1..24)) {
        let bg = Colour::new(40, 80, 120);
        let depth = (0..H).flat_map(|y| (0..W).map(move |x| (x, y))).map(|(x, y)| {
            spans.iter().filter(|s| s.y == y && s.a <= x && x < s.b && s.opacity < 255).count()
        }).max().unwrap_or(0);
        prop_assume!(depth <= 3);
        let (sink, composite) = draw(&spans, 256, bg);
        prop_assert_eq!(composite.fallen_rows(), 0);
        // Memory of the peak draws it with no row falling back, the same pixels.
        let (again, exactly) = draw(&spans, composite.peak(), bg);
        prop_assert_eq!(exactly.fallen_rows(), 0);
        prop_assert_eq!(&again.pixels, &sink.pixels);
        let exact = model(&spans, bg);
        for y in 0..H {
            for x in 0..W {
                let got = sink.at(x, y).expect("every pixel is written");
                let want = exact[(y * W + x) as usize];
                for (g, w) in [got.r, got.g, got.b].into_iter().zip(want) {
                    prop_assert!((f64::from(g) - w).abs() <= 1.0, "({}, {}): {:?} vs {:?}", x, y, got, want);
                }
            }
        }
    }
}
