extern crate std;

use std::vec::Vec;

use super::*;
use crate::display::testing::MockTarget;
use crate::display::Colour;

const C: Colour = Colour::new(1, 2, 3);

/// Records forwarded spans.
#[derive(Default)]
struct Log(Vec<(u32, u32, u32)>);

impl SpanSink for Log {
    fn span(&mut self, y: u32, a: u32, b: u32, _: Colour) {
        self.0.push((y, a, b));
    }
}

#[test]
fn insertion_subtracts_and_merges() {
    let (mut iv, mut counts) = ([(0u16, 0u16); 8], [0u16; 2]);
    let mut cov = Coverage::new(&mut iv, &mut counts, 20, 2).unwrap();
    let mut log = Log::default();
    assert_eq!(cov.span(0, 2, 5, &C, &mut log), 3);
    assert_eq!(cov.span(0, 8, 10, &C, &mut log), 2);
    assert_eq!(cov.row(0), &[(2, 5), (8, 10)]);
    // Overlaps both and fills the gap: only the uncovered pieces go through.
    log.0.clear();
    assert_eq!(cov.span(0, 0, 12, &C, &mut log), 2 + 3 + 2);
    assert_eq!(log.0, [(0, 0, 2), (0, 5, 8), (0, 10, 12)]);
    assert_eq!(cov.row(0), &[(0, 12)]);
    // Adjacent spans merge into one interval.
    assert_eq!(cov.span(0, 12, 13, &C, &mut log), 1);
    assert_eq!(cov.row(0), &[(0, 13)]);
    // Fully covered: nothing forwarded.
    log.0.clear();
    assert_eq!(cov.span(0, 3, 9, &C, &mut log), 0);
    assert!(log.0.is_empty());
    assert_eq!(cov.covered(), 13);
    assert_eq!(cov.row(1), &[]);
    // Insertion in the middle keeps the order.
    cov.span(1, 15, 16, &C, &mut log);
    cov.span(1, 1, 2, &C, &mut log);
    cov.span(1, 8, 9, &C, &mut log);
    assert_eq!(cov.row(1), &[(1, 2), (8, 9), (15, 16)]);
    assert!(cov.covers(0, 0, 13, 1));
    assert!(!cov.covers(0, 0, 14, 1));
    assert!(!cov.covers(0, 0, 13, 2));
}

#[test]
fn full_rows_make_a_full_frame() {
    let (mut iv, mut counts) = ([(0u16, 0u16); 6], [0u16; 3]);
    let mut cov = Coverage::new(&mut iv, &mut counts, 10, 3).unwrap();
    let mut m = MockTarget::<10, 3>::new();
    for y in 0..3 {
        assert!(!cov.is_full());
        cov.span(y, 5, 10, &C, &mut m);
        cov.span(y, 0, 6, &C, &mut m);
        // A full row hit again does not count twice.
        cov.span(y, 0, 10, &C, &mut m);
    }
    assert!(cov.is_full());
    assert_eq!(m.written_count(), 30);
    assert_eq!(cov.covered(), 30);
    cov.clear();
    assert!(!cov.is_full());
    assert_eq!(cov.covered(), 0);
}

#[test]
fn exhaustion_drops_nothing_silently() {
    // Two slots per row.
    let (mut iv, mut counts) = ([(0u16, 0u16); 2], [0u16; 1]);
    let mut cov = Coverage::new(&mut iv, &mut counts, 20, 1).unwrap();
    let mut log = Log::default();
    cov.span(0, 0, 2, &C, &mut log);
    cov.span(0, 5, 6, &C, &mut log);
    assert!(!cov.exhausted());
    // A third disjoint interval does not fit: not drawn, flagged.
    assert_eq!(cov.span(0, 10, 12, &C, &mut log), 0);
    assert!(cov.exhausted());
    // Later spans are ignored too, even ones that would fit, so the list stays exact.
    assert_eq!(cov.span(0, 2, 5, &C, &mut log), 0);
    assert_eq!(cov.row(0), &[(0, 2), (5, 6)]);
    assert_eq!(log.0.len(), 2);
    // Frozen: clipped against the list, not merged.
    cov.freeze();
    log.0.clear();
    assert_eq!(cov.span(0, 0, 12, &C, &mut log), 3 + 6);
    assert_eq!(log.0, [(0, 2, 5), (0, 6, 12)]);
    assert_eq!(cov.row(0), &[(0, 2), (5, 6)]);
}

#[test]
fn zero_memory_exhausts_at_once_and_bad_sizes_are_refused() {
    let mut counts = [0u16; 4];
    let mut cov = Coverage::new(&mut [], &mut counts, 8, 4).unwrap();
    assert_eq!(cov.span(0, 0, 1, &C, &mut Log::default()), 0);
    assert!(cov.exhausted());
    assert_eq!(
        Coverage::new(&mut [], &mut [0u16; 3], 8, 4).err(),
        Some(RenderError::SpanMemory)
    );
    assert_eq!(
        Coverage::new(&mut [], &mut [0u16; 3], 70_000, 3).err(),
        Some(RenderError::SpanMemory)
    );
}

#[test]
fn measure_forwards_everything_and_counts_distinct_pixels() {
    let (mut iv, mut counts) = ([(0u16, 0u16); 4], [0u16; 1]);
    let mut cov = Coverage::new(&mut iv, &mut counts, 10, 1).unwrap();
    cov.set_mode(Mode::Measure);
    let mut log = Log::default();
    assert_eq!(cov.span(0, 0, 5, &C, &mut log), 5);
    assert_eq!(cov.span(0, 3, 8, &C, &mut log), 5);
    assert_eq!(cov.covered(), 8);
    assert_eq!(log.0, [(0, 0, 5), (0, 3, 8)]);
}

/// Naive model: a bool per pixel.
fn check_against_model(spans: &[(u32, u32, u32)], per_row: usize) {
    const W: u32 = 40;
    const H: u32 = 3;
    let mut iv = std::vec![(0u16, 0u16); per_row * H as usize];
    let mut counts = [0u16; H as usize];
    let mut cov = Coverage::new(&mut iv, &mut counts, W, H).unwrap();
    let mut model = [[false; W as usize]; H as usize];
    let mut target = MockTarget::<40, 3>::new();
    for &(y, a, b) in spans {
        let (y, a, b) = (y % H, a % W, b % (W + 1));
        let before: Vec<(u16, u16)> = cov.row(y).to_vec();
        let sent = cov.span(y, a, b, &C, &mut target);
        if cov.exhausted() {
            assert_eq!(sent, 0);
            assert_eq!(cov.row(y), &before[..]);
            break;
        }
        let mut expect = 0;
        for x in a..b {
            if !model[y as usize][x as usize] {
                expect += 1;
                model[y as usize][x as usize] = true;
            }
        }
        assert_eq!(sent, expect);
        // The list is sorted, disjoint, not touching, and equals the model.
        let row = cov.row(y);
        assert!(row.windows(2).all(|w| w[0].1 < w[1].0));
        for x in 0..W {
            let in_list = row
                .iter()
                .any(|&(s, e)| u32::from(s) <= x && x < u32::from(e));
            assert_eq!(in_list, model[y as usize][x as usize]);
            assert_eq!(target.written(x as usize, y as usize), in_list);
        }
        // `covers` agrees with the model on every rectangle of this row (and of it with the
        // next row).
        for x0 in 0..=W {
            for x1 in x0..=W {
                let rows = |y0: u32, y1: u32| {
                    (y0..y1.min(H)).all(|r| (x0..x1).all(|x| model[r as usize][x as usize]))
                };
                assert_eq!(cov.covers(x0, y, x1, y + 1), rows(y, y + 1));
                assert_eq!(cov.covers(x0, y, x1, y + 2), rows(y, y + 2));
            }
        }
    }
}

proptest::proptest! {
    #[test]
    fn matches_a_pixel_model(
        spans in proptest::collection::vec((0u32..3, 0u32..40, 0u32..41), 0..60),
        per_row in 1usize..8,
    ) {
        check_against_model(&spans, per_row);
    }
}
