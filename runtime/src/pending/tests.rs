extern crate std;

use std::vec;
use std::vec::Vec;

use proptest::prelude::*;

use super::*;
use crate::display::SpanSink;
use crate::fill::samples::masks::{fill_polygon_masks, MaskSink};
use crate::fill::samples::{Mask, CENTRE_SAMPLE, SAMPLE_COLUMNS};
use crate::fill::{fill_polygon, FixedPoint};

const W: usize = 12;
const H: usize = 8;
const BACKGROUND: Colour = Colour::new(10, 20, 30);

/// A frame drawn front to back through a [`Pending`] pool: finished pixels are written once
/// (a second write panics), and a pixel of a fallen-back row without a record is drawn from
/// its centre sample, as the renderer will.
struct Frame<'p, 'm> {
    pending: &'p mut Pending<'m>,
    pixels: [[Option<Colour>; W]; H],
}

impl Frame<'_, '_> {
    fn write(&mut self, x: u32, y: u32, c: Colour) {
        let p = &mut self.pixels[y as usize][x as usize];
        assert!(p.is_none(), "pixel ({x}, {y}) written twice");
        *p = Some(c);
    }
}

impl Frame<'_, '_> {
    /// Add the gathered row, as the renderer does: finished pixels given as span memory's
    /// intervals, the runs of pixels that finish written where not yet written (as span memory
    /// does: a run of pixels covered whole may hold finished ones).
    fn add_gathered(&mut self, colour: Colour) {
        let Some(y) = self.pending.gathered() else {
            return;
        };
        let row = &self.pixels[y as usize];
        let mut finished = Vec::new();
        let mut x = 0;
        while x < W {
            if row[x].is_some() {
                let start = x;
                while x < W && row[x].is_some() {
                    x += 1;
                }
                finished.push((start as u16, x as u16));
            }
            x += 1;
        }
        let mut done = Vec::new();
        if let Some(mut add) = self.pending.begin_add(&SampleColour::new(colour), None) {
            while let Some((a, b, c)) = self.pending.next_run(&mut add, |x| {
                finished
                    .iter()
                    .any(|&(a, b)| (u32::from(a)..u32::from(b)).contains(&x))
            }) {
                done.extend((a..b).map(|x| (x, c)));
            }
        }
        for (x, c) in done {
            if self.pixels[y as usize][x as usize].is_none() {
                self.write(x, y, c);
            }
        }
    }
}

/// A polygon's fill on the sample grid into a [`Frame`], through [`Pending::gather`].
struct Gather<'f, 'p, 'm> {
    frame: &'f mut Frame<'p, 'm>,
    colour: Colour,
}

impl SpanSink for Gather<'_, '_, '_> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, _: Colour) {
        if self.frame.pending.gather(y, x_start, x_end).is_err() {
            self.frame.add_gathered(self.colour);
            assert!(self.frame.pending.gather(y, x_start, x_end).is_ok());
        }
    }
}

/// The picture, for [`Pending::drain`]: a pixel written twice panics.
struct Pixels([[Option<Colour>; W]; H]);

impl SpanSink for Pixels {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        for x in x_start..x_end {
            let p = &mut self.0[y as usize][x as usize];
            assert!(
                p.is_none(),
                "pixel ({x}, {y}) drained twice or after it finished"
            );
            *p = Some(colour);
        }
    }
}

type Triangle = ([FixedPoint<8>; 3], Colour);

/// Draw `polygons` front to back with `records` records; the picture and the peak.
fn draw(polygons: &[Triangle], records: usize) -> (Vec<Colour>, usize, Vec<bool>) {
    let mut pool = vec![PendingPixel::default(); records];
    let mut heads = [0u16; H];
    let mut pending = Pending::new(&mut pool, &mut heads, H as u32).unwrap();
    let mut frame = Frame {
        pending: &mut pending,
        pixels: [[None; W]; H],
    };
    for (tri, colour) in polygons {
        let (c, r) = (SAMPLE_COLUMNS, SAMPLE_ROWS);
        let scaled = tri.map(|p| FixedPoint::<8>::new(p.x * c as i32, p.y * r as i32));
        let mut gather = Gather {
            frame: &mut frame,
            colour: *colour,
        };
        fill_polygon(&scaled, c * W as u32, r * H as u32, *colour, &mut gather).unwrap();
        frame.add_gathered(*colour);
    }
    let fallen: Vec<bool> = (0..H as u32)
        .map(|y| frame.pending.fallen_back(y))
        .collect();
    let peak = frame.pending.peak();
    let mut pixels = Pixels(frame.pixels);
    frame.pending.drain(BACKGROUND, &mut pixels);
    assert_eq!(frame.pending.in_use(), 0);
    let picture = pixels
        .0
        .iter()
        .flatten()
        .map(|p| p.unwrap_or(BACKGROUND))
        .collect();
    (picture, peak, fallen)
}

/// Per pixel, each sample's first polygon: the anti-aliased picture and the one without
/// anti-aliasing (the centre sample's), by brute force over the polygons' masks.
fn expected(polygons: &[Triangle]) -> (Vec<Colour>, Vec<Colour>) {
    struct All(Vec<Mask>);
    impl MaskSink for All {
        fn masks(&mut self, y: u32, x_start: u32, masks: &[Mask], _: Colour) {
            for (k, &m) in masks.iter().enumerate() {
                self.0[y as usize * W + x_start as usize + k] |= m;
            }
        }
    }
    let mut owner = vec![[None::<Colour>; SAMPLES as usize]; W * H];
    let mut scratch = [0 as Mask; W];
    for (tri, colour) in polygons {
        let mut all = All(vec![0; W * H]);
        fill_polygon_masks(tri, W as u32, 0..H as u32, *colour, &mut scratch, &mut all).unwrap();
        for (samples, m) in owner.iter_mut().zip(all.0) {
            for (s, o) in samples.iter_mut().enumerate() {
                if m >> s & 1 == 1 && o.is_none() {
                    *o = Some(*colour);
                }
            }
        }
    }
    let aa = owner
        .iter()
        .map(|samples| {
            let sum = |f: fn(Colour) -> u8| {
                let t: u32 = samples
                    .iter()
                    .map(|o| u32::from(f(o.unwrap_or(BACKGROUND))))
                    .sum();
                ((2 * t + SAMPLES) / (2 * SAMPLES)) as u8
            };
            Colour::new(sum(|c| c.r), sum(|c| c.g), sum(|c| c.b))
        })
        .collect();
    let plain = owner
        .iter()
        .map(|s| s[CENTRE_SAMPLE as usize].unwrap_or(BACKGROUND))
        .collect();
    (aa, plain)
}

fn triangles() -> impl Strategy<Value = Vec<Triangle>> {
    let point = (0..=(W as i32 + 1) * 256, 0..=(H as i32 + 1) * 256)
        .prop_map(|(x, y)| FixedPoint::new(x, y));
    let colour = (any::<u8>(), any::<u8>(), any::<u8>()).prop_map(|(r, g, b)| Colour::new(r, g, b));
    proptest::collection::vec(([point.clone(), point.clone(), point], colour), 1..12)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// With records enough, every pixel is the average of its samples' first polygons (the
    /// background for the others), and no row falls back.
    #[test]
    fn enough_records_give_the_exact_average(polygons in triangles()) {
        let (picture, peak, fallen) = draw(&polygons, W * H);
        prop_assert!(peak <= W * H);
        prop_assert!(!fallen.contains(&true));
        prop_assert_eq!(picture, expected(&polygons).0);
    }

    /// With few records (or none), every pixel is either its anti-aliased colour or its
    /// colour without anti-aliasing, and rows that never ran out are all anti-aliased.
    #[test]
    fn running_out_never_mixes(polygons in triangles(), records in 0..6usize) {
        let (picture, peak, fallen) = draw(&polygons, records);
        prop_assert!(peak <= records);
        let (aa, plain) = expected(&polygons);
        for k in 0..W * H {
            let (x, y) = (k % W, k / W);
            prop_assert!(
                picture[k] == aa[k] || picture[k] == plain[k],
                "pixel ({}, {}): {:?}, not {:?} nor {:?}", x, y, picture[k], aa[k], plain[k]
            );
            if !fallen[y] {
                prop_assert_eq!(picture[k], aa[k], "pixel ({}, {}) of a row that did not fall back", x, y);
            }
        }
        if records == 0 {
            prop_assert_eq!(picture, plain);
        }
    }
}

/// Gather the spans `(sample row, start, end)` and add them in `colour`: the runs that finish.
fn add(p: &mut Pending<'_>, spans: &[(u32, u32, u32)], colour: Colour) -> Vec<(u32, u32, Colour)> {
    let mut runs = Vec::new();
    let mut add_gathered = |p: &mut Pending<'_>| {
        if let Some(mut add) = p.begin_add(&SampleColour::new(colour), None) {
            while let Some(run) = p.next_run(&mut add, |_| false) {
                runs.push(run);
            }
        }
    };
    for &(row, a, b) in spans {
        if p.gather(row, a, b).is_err() {
            add_gathered(p);
            assert!(p.gather(row, a, b).is_ok());
        }
    }
    add_gathered(p);
    runs
}

#[test]
fn a_record_fills_up_and_is_freed() {
    let mut pool = [PendingPixel::default(); 2];
    let mut heads = [0u16; 2];
    let mut p = Pending::new(&mut pool, &mut heads, 2).unwrap();
    let red = Colour::new(255, 0, 0);
    let blue = Colour::new(0, 0, 255);
    // The left two sample columns of pixel (3, 1), then pixels 3 and 4 whole: only the other
    // 15 samples of pixel 3 are blue, and pixel 4 finishes at once.
    let rows = |a, b| (5..10).map(move |t| (t, a, b)).collect::<Vec<_>>();
    assert_eq!(add(&mut p, &rows(15, 17), red), []);
    assert_eq!(p.in_use(), 1);
    // 10 red and 15 blue samples: 10 * 255 / 25 = 102, 15 * 255 / 25 = 153.
    let mixed = Colour::new(102, 0, 153);
    assert_eq!(
        add(&mut p, &rows(15, 25), blue),
        [(3, 4, mixed), (4, 5, blue)]
    );
    assert_eq!((p.in_use(), p.peak()), (0, 1));
    // Records are reused: three pending pixels (one sample each, not the centre) in a
    // two-record pool make row 0 fall back, and the third is not drawn.
    assert_eq!(add(&mut p, &[(0, 0, 1), (0, 10, 11), (0, 15, 16)], red), []);
    assert_eq!(p.in_use(), 2);
    assert!(p.fallen_back(0) && !p.fallen_back(1));
    // A fallen-back row draws a pixel without a record from its centre sample.
    assert_eq!(add(&mut p, &[(2, 22, 23)], blue), [(4, 5, blue)]);
    let mut drained = Vec::new();
    struct Spans<'a>(&'a mut Vec<(u32, u32, Colour)>);
    impl SpanSink for Spans<'_> {
        fn span(&mut self, y: u32, x: u32, end: u32, c: Colour) {
            assert_eq!(end, x + 1);
            self.0.push((y, x, c));
        }
    }
    // One red sample of 25 over a white background: (255 + 24 * 255) / 25 and 24 * 255 / 25.
    assert_eq!(p.drain(Colour::grey(255), &mut Spans(&mut drained)), 2);
    let pink = Colour::new(255, 245, 245);
    assert_eq!(drained, [(0, 0, pink), (0, 2, pink)]);
    assert!(!p.fallen_back(0));
    assert_eq!(p.in_use(), 0);
}

#[test]
fn a_row_without_every_sample_row_has_no_pixel_covered_whole() {
    let mut pool = [PendingPixel::default(); 8];
    let mut heads = [0u16; 1];
    let mut p = Pending::new(&mut pool, &mut heads, 1).unwrap();
    let red = Colour::new(255, 0, 0);
    // Four of five sample rows over pixels 0..4: nothing finishes, four pixels wait.
    let spans: Vec<_> = (0..4).map(|t| (t, 0, 20)).collect();
    assert_eq!(add(&mut p, &spans, red), []);
    assert_eq!(p.in_use(), 4);
    // The fifth row finishes them, in one run.
    assert_eq!(add(&mut p, &[(4, 0, 20)], red), [(0, 4, red)]);
    assert_eq!(p.in_use(), 0);
}

/// A pool past the lists' end marker (32,767) uses the records below it, and its lists end.
#[test]
fn a_larger_pool_than_the_records_used_ends_its_lists() {
    let mut pool = vec![PendingPixel::default(); 40_000];
    let mut heads = [0u16; 1];
    let mut p = Pending::new(&mut pool, &mut heads, 1).unwrap();
    let red = Colour::new(255, 0, 0);
    assert_eq!(add(&mut p, &[(0, 0, 1), (0, 10, 11)], red), []);
    assert_eq!(p.in_use(), 2);
    let mut pixels = Pixels([[None; W]; H]);
    assert_eq!(p.drain(Colour::grey(0), &mut pixels), 2);
}

#[test]
fn too_few_heads_are_refused() {
    let mut heads = [0u16; 3];
    assert!(matches!(
        Pending::new(&mut [], &mut heads, 4),
        Err(RenderError::PendingMemory)
    ));
    assert!(Pending::new(&mut [], &mut heads, 3).is_ok());
}
