//! Sample masks: which of a pixel's [`SAMPLES`] sample points a polygon covers, the mask an
//! anti-aliased frame averages (a pixel's share of a polygon; "coverage" is the span buffer).
//!
//! The samples form a grid of [`SAMPLE_COLUMNS`] x [`SAMPLE_ROWS`] per pixel, sample `(s, t)`
//! of pixel `(i, j)` at `(i + (s + 1/2) / 5, j + (t + 1/2) / 5)`. Scaling the polygon's points
//! exactly by `(5, 5)` puts every sample on a pixel centre of the scaled grid, so the masks
//! are the scanline fill of the scaled polygon, with its top-left rule and its exact shared
//! edges: each sample belongs to exactly one polygon of a closed mesh, as each pixel does.
//! The grid's middle sample `(2, 2)` is the pixel centre, so bit [`CENTRE_SAMPLE`] of a mask is
//! the pixel the ordinary fill draws, bit for bit.

use core::ops::Range;

use super::{Coord, EdgeWalk, FixedPoint};
use crate::display::{Colour, SpanSink};

/// Sample columns per pixel.
pub const SAMPLE_COLUMNS: u32 = 5;
/// Sample rows per pixel. Five rather than three: an edge's share of a pixel then errs by at
/// most a tenth of a pixel instead of a sixth (a largest error of about 26 instead of 43 in
/// 8-bit units, measured against a 16 x 16 supersampled reference in BENCHMARKS.md).
pub const SAMPLE_ROWS: u32 = 5;
/// Samples per pixel: bit `t * SAMPLE_COLUMNS + s` of a [`Mask`] is sample `(s, t)`.
pub const SAMPLES: u32 = SAMPLE_COLUMNS * SAMPLE_ROWS;
/// A pixel's samples, one bit each.
pub type Mask = u32;
/// The mask of a pixel whose samples are all covered.
pub const FULL_MASK: Mask = (1 << SAMPLES) - 1;
/// The bit of the sample at the pixel's centre.
pub const CENTRE_SAMPLE: u32 = SAMPLE_COLUMNS * (SAMPLE_ROWS / 2) + SAMPLE_COLUMNS / 2;

/// Set in `masks` (a pixel row's) the bits of the samples `[x_start, x_end)` (columns of the
/// sample grid) of sample row `sample_row`; returns the pixels touched, `lo .. hi`.
pub fn add_span_bits(
    masks: &mut [Mask],
    sample_row: u32,
    x_start: u32,
    x_end: u32,
) -> Option<(u32, u32)> {
    if x_start >= x_end {
        return None;
    }
    let base = (sample_row % SAMPLE_ROWS) * SAMPLE_COLUMNS;
    let (first, last) = (x_start / SAMPLE_COLUMNS, (x_end - 1) / SAMPLE_COLUMNS);
    for pixel in first..=last {
        let left = pixel * SAMPLE_COLUMNS;
        // The pixel's samples in the span: columns `s0 .. s1` of its grid row.
        let s0 = x_start.max(left) - left;
        let s1 = x_end.min(left + SAMPLE_COLUMNS) - left;
        if let Some(m) = masks.get_mut(pixel as usize) {
            *m |= ((1 << s1) - (1 << s0)) << base;
        }
    }
    Some((first, last + 1))
}

/// A pixel row's spans on the sample grid: sample row `t`'s is `[spans[t].0, spans[t].1)`, or
/// [`NO_SPAN`].
pub type RowSpans = [(u32, u32); SAMPLE_ROWS as usize];

/// The extent of a pixel row's spans, in columns of the sample grid: the least start and the
/// greatest end (`lo < hi` unless there is no span), then the greatest start and the least
/// end (the columns every sample row holds, when `inner_lo < inner_hi`; a [`NO_SPAN`] leaves
/// none).
pub type RowExtent = [u32; 4];

/// [`RowExtent`] of `spans`.
#[inline]
pub fn row_extent(spans: &RowSpans) -> RowExtent {
    let [(a0, b0), (a1, b1), (a2, b2), (a3, b3), (a4, b4)] = *spans;
    [
        a0.min(a1).min(a2).min(a3).min(a4),
        b0.max(b1).max(b2).max(b3).max(b4),
        a0.max(a1).max(a2).max(a3).max(a4),
        b0.min(b1).min(b2).min(b3).min(b4),
    ]
}

/// A sample row without a span: the start past every end, so that the least start and the
/// greatest end of a row's spans, and the samples of a pixel in them, need no test for it.
pub const NO_SPAN: (u32, u32) = (u32::MAX, 0);

/// Receives a polygon's samples: its spans on the sample grid one by one, top to bottom
/// ([`SpanSink`], from the general fill), or a pixel row of them at a time
/// ([`SampleSink::sample_rows`]), then [`SampleSink::end`].
pub(crate) trait SampleSink: SpanSink {
    /// The spans of pixel row `y`'s sample rows, at least one of them not empty, and their
    /// extent.
    fn sample_rows(&mut self, y: u32, spans: &RowSpans, extent: &RowExtent);

    /// The polygon's last span was given.
    fn end(&mut self);
}

/// The fill of a polygon on the sample grid, the one entry for anti-aliased polygons:
/// `points` (already scaled to the grid, within `rect`, its samples' rectangle, in a window
/// `width` columns wide) over the sample rows `rows` (whole pixel rows) into `sink`, a pixel
/// row at a time when [`fill_sample_rows`] can walk it, else span by span by the general fill.
/// Out of line: inlined into the painter's walk, its loop shared the walk's registers and
/// kept its rows' extent on the stack (2% of the anti-aliased frame on the Cortex-M4F).
#[inline(never)]
pub(crate) fn fill_samples<const SUB: u32, S: SampleSink + ?Sized>(
    points: &[FixedPoint<SUB>],
    rect: [u32; 4],
    edges: &mut [EdgeWalk],
    width: u32,
    rows: Range<u32>,
    sink: &mut S,
) {
    if fill_sample_rows(points, edges, width, rows.clone(), sink) {
        return;
    }
    fill_span_by_span(points, rect, edges, width, rows, sink);
}

/// [`fill_samples`] by the general fill, span by span: the rare polygon (clipped at the
/// window's sides, or not convex). Out of line: inlined beside the pixel-row walk, the
/// general fill's second copy in the painter's walk cost the anti-aliased frame 2% on the
/// Cortex-M4F.
#[inline(never)]
fn fill_span_by_span<const SUB: u32, S: SampleSink + ?Sized>(
    points: &[FixedPoint<SUB>],
    rect: [u32; 4],
    edges: &mut [EdgeWalk],
    width: u32,
    rows: Range<u32>,
    sink: &mut S,
) {
    super::fill_in_rect(
        points,
        rect,
        edges,
        width,
        rows,
        &mut Colour::default(),
        sink,
    );
    sink.end();
}

/// The spans [`super::fill_in`] gives `points` (on the sample grid, `width` columns) over the
/// sample rows `rows` (whole pixel rows), handed to `sink` a pixel row at a time, top to
/// bottom, when every sample row crosses at most two of its edges: one going down and one going
/// up in the order of `points`, as in any convex polygon. Each row's span is then the one
/// the general fill pairs from the same two crossings, without its sorting and pairing per
/// sample row, nor a call per sample row. Returns `false`, having drawn nothing, for any other
/// polygon, one with a point left or right of the window (whose spans the general fill clips)
/// or more edges than `edges` holds: the caller fills it with the general fill.
fn fill_sample_rows<const SUB: u32, S: SampleSink + ?Sized>(
    points: &[FixedPoint<SUB>],
    edges: &mut [EdgeWalk],
    width: u32,
    rows: Range<u32>,
    sink: &mut S,
) -> bool {
    #[allow(clippy::unnecessary_fallible_conversions)]
    let first_row = Coord::try_from(rows.start).unwrap_or(Coord::MAX);
    let room = edges.len().min(super::MAX_FILL_VERTICES);
    // Edges going down at `edges[..down]`, going up at `edges[room - up..room]`, each sorted
    // by first row.
    let (mut down, mut up) = (0, 0);
    // Within the window's columns, every crossing is a column `0..=width`: no span to clip.
    let right = i64::from(width) << SUB;
    for (i, &a) in points.iter().enumerate() {
        if !(0..=right).contains(&i64::from(a.x)) {
            return false;
        }
        let b = points.get(i + 1).or(points.first()).copied().unwrap_or(a);
        let Some(mut walk) = EdgeWalk::for_edge::<SUB>(a, b, rows.end) else {
            continue;
        };
        while walk.row < first_row.min(walk.row_end) {
            walk.step();
        }
        if walk.row >= walk.row_end {
            continue;
        }
        if down + up >= room {
            return false;
        }
        let (lo, at) = if a.y < b.y {
            down += 1;
            (0, down - 1)
        } else {
            up += 1;
            (room - up, room - up)
        };
        if let Some(slot) = edges.get_mut(at) {
            *slot = walk;
        }
        // Insertion, as the general fill keeps its edges: the down chain grows to the right,
        // the up chain to the left.
        let (mut k, last) = (at, if lo == 0 { 0 } else { room - 1 });
        if lo == 0 {
            while let Some([prev, this]) = k.checked_sub(1).and_then(|j| edges.get_mut(j..=k)) {
                if prev.row <= this.row {
                    break;
                }
                core::mem::swap(prev, this);
                k -= 1;
            }
        } else {
            while k < last {
                let Some([this, next]) = edges.get_mut(k..=k + 1) else {
                    break;
                };
                if this.row <= next.row {
                    break;
                }
                core::mem::swap(this, next);
                k += 1;
            }
        }
    }
    if down == 0 && up == 0 {
        return true;
    }
    // Each chain's edges must follow one another down the rows.
    // (`room - up` is within `edges`: the `min` only makes it provably so.)
    let (downs, ups) = edges.split_at_mut((room - up).min(edges.len()));
    let (Some(downs), Some(ups)) = (downs.get_mut(..down), ups.get_mut(..up)) else {
        return false;
    };
    let disjoint = |chain: &[EdgeWalk]| chain.windows(2).all(|w| w[0].row_end <= w[1].row);
    if downs.is_empty() || ups.is_empty() || !disjoint(downs) || !disjoint(ups) {
        return false;
    }
    // The chains' current edges, walked in registers.
    let (mut d, mut u) = (0, 0);
    let (mut a, mut b) = (downs[0], ups[0]);
    let mut row = a.row.min(b.row);
    let group = SAMPLE_ROWS as Coord;
    let (mut pixel_row, mut t) = (row.div_euclid(group), row.rem_euclid(group) as usize);
    let mut spans: RowSpans = [NO_SPAN; SAMPLE_ROWS as usize];
    loop {
        if row >= a.row_end {
            d += 1;
            let Some(&next) = downs.get(d) else { break };
            a = next;
        }
        if row >= b.row_end {
            u += 1;
            let Some(&next) = ups.get(u) else { break };
            b = next;
        }
        if a.row == row && b.row == row {
            // The rows both edges cross: a span each (the walks' own rows are set past them at
            // once, so that the loop keeps less in registers).
            let n = a.row_end.min(b.row_end) - row;
            (a.row, b.row, row) = (a.row + n, b.row + n, row + n);
            for _ in 0..n {
                let (l, r) = if a.x <= b.x { (a.x, b.x) } else { (b.x, a.x) };
                if l < r {
                    if let Some(span) = spans.get_mut(t) {
                        *span = (l as u32, r as u32);
                    }
                }
                a.step_x();
                b.step_x();
                t += 1;
                if t == SAMPLE_ROWS as usize {
                    send_row(sink, pixel_row as u32, &mut spans);
                    (pixel_row, t) = (pixel_row + 1, 0);
                }
            }
        } else {
            // A row that at most one crosses: no span (the general fill ignores an odd
            // crossing).
            for e in [&mut a, &mut b] {
                if e.row == row {
                    e.step();
                }
            }
            row += 1;
            t += 1;
            if t == SAMPLE_ROWS as usize {
                send_row(sink, pixel_row as u32, &mut spans);
                (pixel_row, t) = (pixel_row + 1, 0);
            }
        }
    }
    send_row(sink, pixel_row as u32, &mut spans);
    true
}

/// Hand pixel row `y`'s spans to `sink` if it holds any, and empty them.
#[inline]
fn send_row<S: SampleSink + ?Sized>(sink: &mut S, y: u32, spans: &mut RowSpans) {
    let extent = row_extent(spans);
    if extent[0] < extent[1] {
        sink.sample_rows(y, spans, &extent);
        *spans = [NO_SPAN; SAMPLE_ROWS as usize];
    }
}

#[cfg(test)]
pub(crate) mod masks;
#[cfg(test)]
mod tests;
