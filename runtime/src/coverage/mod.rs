//! Coverage: which pixels of the frame are already drawn, as a span buffer in caller memory.
//!
//! Front-to-back rendering (the reverse painter's algorithm: draw a pixel only if it has not
//! been drawn yet, as in Quake's span buffer described by Abrash) keeps,
//! per scanline, the sorted list of covered intervals. Every span the fill emits goes through
//! [`Coverage::span`]: the covered parts are subtracted, only the uncovered pieces reach the
//! real sink, and the span is merged into the row's list. So each pixel is written at most
//! once, and the frame is done when every row is one interval `[0, W)`.
//!
//! # Memory and the exhaustion policy
//!
//! The caller gives `H` row counters and a slice of `(u16, u16)` intervals, split evenly into
//! `H` rows of `intervals.len() / H` slots. A span whose merge would need one more slot than
//! its row has is **not drawn**: the coverage becomes [`Coverage::exhausted`] and ignores every
//! later span, so the list still describes exactly the pixels that were written. The renderer
//! then [freezes](Coverage::freeze) it and paints the polygons that are left (the one that
//! overflowed and all farther ones) back to front, each span still clipped against the frozen
//! list: nearer polygons are never overwritten and no polygon is dropped; only the rest of the
//! frame has overdraw. Merging adjacent intervals keeps the lists short: a row needs one slot
//! per visible "hole" boundary, not per polygon.
//!
//! # Stores
//!
//! The intervals live in one of two stores (`store.rs`): rows of slots as above, or (a
//! scan-order frame, feature `scan-order`) the scan memory's coloured lists
//! ([`crate::scan::ScanMemory`]), which answer the same queries and keep every span instead
//! of forwarding it. The sinks that route a fill's spans through a coverage are in `sink.rs`.

#[cfg(test)]
mod tests;

mod sink;
mod store;

pub(crate) use sink::Clipped;
pub use sink::CoverageSink;

use crate::display::{SpanPaint, SpanSink};
use crate::error::RenderError;
use store::{Rows, ScanStore, Store};

/// What [`Coverage::span`] does with the list.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Subtract, forward the uncovered pieces, merge (front-to-back rendering).
    Exclusive,
    /// Subtract and forward, but do not merge: the list is frozen (the exhaustion fallback).
    Frozen,
    /// Forward the whole span and merge it: only measures the distinct pixels covered
    /// (back-to-front rendering with statistics).
    Measure,
}

/// Per-row covered intervals of a `width x height` frame, in caller memory (see the module
/// docs). Intervals are half-open `[start, end)`, sorted, disjoint and not touching.
#[derive(Debug)]
pub struct Coverage<'m> {
    store: Store<'m>,
    width: u16,
    height: u32,
    /// Rows of the frame or band being drawn (`<= height`): full when all of them are.
    in_use: u32,
    mode: Mode,
}

impl<'m> Coverage<'m> {
    /// An empty coverage of a `width x height` frame. Needs `counts.len() >= height` and
    /// `width <= u16::MAX`, else [`RenderError::SpanMemory`]; any `intervals` length works
    /// (even 0: then the first span exhausts it, and the renderer falls back at once).
    pub fn new(
        intervals: &'m mut [(u16, u16)],
        counts: &'m mut [u16],
        width: u32,
        height: u32,
    ) -> Result<Self, RenderError> {
        let w = u16::try_from(width).map_err(|_| RenderError::SpanMemory)?;
        let rows = usize::try_from(height).map_err(|_| RenderError::SpanMemory)?;
        if counts.len() < rows {
            return Err(RenderError::SpanMemory);
        }
        let per_row = intervals
            .len()
            .checked_div(rows)
            .unwrap_or(0)
            .min(usize::from(u16::MAX));
        let mut c = Coverage {
            store: Store::Rows(Rows {
                intervals,
                counts,
                per_row,
                full_rows: 0,
                covered: 0,
                exhausted: false,
            }),
            width: w,
            height,
            in_use: height,
            mode: Mode::Exclusive,
        };
        c.clear();
        Ok(c)
    }

    /// A coverage kept in scan memory (scan order: each interval with its colour). Only
    /// [`Mode::Exclusive`] applies to it: spans are merged into the memory, none is forwarded.
    #[cfg_attr(not(feature = "scan-order"), allow(dead_code))]
    pub(crate) fn from_scan(scan: ScanStore<'m>) -> Self {
        let (width, height) = (scan.width() as u16, scan.height());
        let mut c = Coverage {
            store: Store::Scan(scan),
            width,
            height,
            in_use: height,
            mode: Mode::Exclusive,
        };
        c.clear();
        c
    }

    /// The scan memory of [`Coverage::from_scan`].
    #[cfg_attr(not(feature = "scan-order"), allow(dead_code))]
    pub(crate) fn into_scan(self) -> Option<ScanStore<'m>> {
        match self.store {
            Store::Scan(s) => Some(s),
            Store::Rows(_) => None,
        }
    }

    /// Forget everything (a new frame), back to [`Mode::Exclusive`].
    pub fn clear(&mut self) {
        match &mut self.store {
            Store::Rows(r) => r.clear(),
            Store::Scan(s) => s.clear(),
        }
        self.in_use = self.height;
        self.mode = Mode::Exclusive;
    }

    /// Frame width.
    pub fn width(&self) -> u32 {
        u32::from(self.width)
    }

    /// Frame height.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Interval slots per row (0 in scan memory, whose rows share one pool).
    pub fn per_row(&self) -> usize {
        match &self.store {
            Store::Rows(r) => r.per_row,
            Store::Scan(_) => 0,
        }
    }

    /// The current mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Set the mode (clears nothing).
    pub fn set_mode(&mut self, mode: Mode) {
        self.mode = mode;
    }

    /// Stop merging: later spans are clipped against the list as it is now.
    pub fn freeze(&mut self) {
        self.mode = Mode::Frozen;
    }

    /// Whether a span could not be merged for lack of slots (it and every later span were
    /// dropped until [`Coverage::freeze`] or [`Coverage::clear`]).
    pub fn exhausted(&self) -> bool {
        match &self.store {
            Store::Rows(r) => r.exhausted,
            Store::Scan(s) => s.exhausted(),
        }
    }

    /// Distinct pixels covered (exact while not exhausted).
    pub fn covered(&self) -> u64 {
        match &self.store {
            Store::Rows(r) => r.covered,
            Store::Scan(s) => s.covered(),
        }
    }

    /// Whether every pixel of the frame is covered (of its first `rows` rows after
    /// [`Coverage::use_rows`]).
    pub fn is_full(&self) -> bool {
        match &self.store {
            Store::Rows(r) => r.full_rows == self.in_use || self.width == 0,
            Store::Scan(s) => s.is_full(self.in_use),
        }
    }

    /// Draw only the first `rows` rows until the next [`Coverage::clear`] (a band shorter than
    /// the memory): the frame is full when they are.
    pub fn use_rows(&mut self, rows: u32) {
        self.in_use = rows.min(self.height);
    }

    /// The covered intervals of row `y` (empty outside the frame, and for a coverage in scan
    /// memory).
    pub fn row(&self, y: u32) -> &[(u16, u16)] {
        match &self.store {
            Store::Rows(r) if y < self.height => r.row(y),
            _ => &[],
        }
    }

    /// Whether pixel `(x, y)` is covered: [`Coverage::covers`] of one pixel, inlined for the
    /// anti-aliased fill's test of each pixel at a polygon's edges.
    #[inline]
    pub fn covers_pixel(&self, x: u32, y: u32) -> bool {
        let row = match &self.store {
            Store::Rows(_) => self.row(y),
            Store::Scan(s) => return s.covers(x, y, x + 1, y + 1),
        };
        let i = row.partition_point(|&(_, b)| u32::from(b) <= x);
        row.get(i).is_some_and(|&(a, _)| u32::from(a) <= x)
    }

    /// Whether every pixel `x0 <= x < x1`, `y0 <= y < y1` is covered (an empty rectangle is).
    pub fn covers(&self, x0: u32, y0: u32, x1: u32, y1: u32) -> bool {
        if let Store::Scan(s) = &self.store {
            return s.covers(x0, y0, x1, y1);
        }
        (y0..y1.min(self.height)).all(|y| {
            // The intervals are sorted and disjoint: only the first one ending past `x0` can
            // hold `[x0, x1)` (a binary search; rows of a dense mesh hold dozens).
            let row = self.row(y);
            let i = row.partition_point(|&(_, b)| u32::from(b) <= x0);
            x0 >= x1
                || row
                    .get(i)
                    .is_some_and(|&(a, b)| u32::from(a) <= x0 && x1 <= u32::from(b))
        })
    }

    /// Whether the store keeps each interval's colour (scan memory): it forwards no span, so
    /// a span's pieces are painted into it.
    #[inline]
    pub(crate) fn keeps_colours(&self) -> bool {
        matches!(self.store, Store::Scan(_))
    }

    /// Each uncovered piece of `[x_start, x_end)` on row `y`, left to right, as
    /// `piece(start, end)`, merging nothing: where a transparent span may show (it covers
    /// nothing).
    #[inline]
    pub fn uncovered(&self, y: u32, x_start: u32, x_end: u32, mut piece: impl FnMut(u32, u32)) {
        if let Store::Scan(s) = &self.store {
            return s.uncovered(y, x_start, x_end, piece);
        }
        let x_end = x_end.min(u32::from(self.width));
        if x_start >= x_end {
            return;
        }
        let row = self.row(y);
        let first = row.partition_point(|&(_, e)| u32::from(e) <= x_start);
        let mut at = x_start;
        for &(s, e) in row.get(first..).unwrap_or(&[]) {
            let (s, e) = (u32::from(s), u32::from(e));
            if s >= x_end {
                break;
            }
            if s > at {
                piece(at, s);
            }
            at = at.max(e);
        }
        if at < x_end {
            piece(at, x_end);
        }
    }

    /// Paint `[x_start, x_end)` of row `y` into `sink` as the mode says; returns the pixels
    /// forwarded (in scan memory: covered, as it forwards nothing). Out-of-frame or empty
    /// spans, and every span once exhausted (in the merging modes), forward nothing.
    ///
    /// With scan memory built in, a call here is a dispatch between two stores, kept out of
    /// the walk (inlined, it cost the scan-order frame 2-4% of its instructions on the
    /// Cortex-M4F); with one store it is inlined where it has one caller, as before.
    #[cfg_attr(feature = "scan-order", inline(never))]
    pub fn span<S: SpanSink + ?Sized, P: SpanPaint>(
        &mut self,
        y: u32,
        x_start: u32,
        x_end: u32,
        paint: &P,
        sink: &mut S,
    ) -> u64 {
        let (mode, width, height) = (self.mode, self.width, self.height);
        let rows = match &mut self.store {
            Store::Rows(r) => r,
            Store::Scan(s) => return s.paint(y, x_start, x_end, paint.kind()),
        };
        let x_end = x_end.min(u32::from(width));
        if x_start >= x_end || y >= height || (rows.exhausted && mode == Mode::Exclusive) {
            return 0;
        }
        // In range: both fit u16 since x_end <= width <= u16::MAX.
        let (a, b) = (x_start as u16, x_end as u16);
        // Intervals touching [a, b] (overlapping or adjacent) are merged with it.
        let (first, last, n) = {
            let row = rows.row(y);
            let first = row.partition_point(|&(_, e)| e < a);
            (first, row.partition_point(|&(s, _)| s <= b), row.len())
        };
        let mut merging = mode != Mode::Frozen && !rows.exhausted;
        if merging && n + 1 - (last - first) > rows.per_row {
            rows.exhausted = true;
            if mode == Mode::Exclusive {
                return 0;
            }
            // Measuring: keep painting, stop counting.
            merging = false;
        }
        let row = rows.row(y);
        let mut forwarded = 0u64;
        if mode == Mode::Measure {
            paint.paint(sink, y, x_start, x_end);
            forwarded = u64::from(b - a);
        } else {
            let mut at = a;
            for &(s, e) in row.get(first..last).unwrap_or(&[]) {
                if s > at {
                    paint.paint(sink, y, u32::from(at), u32::from(s));
                    forwarded += u64::from(s - at);
                }
                at = at.max(e);
            }
            if at < b {
                paint.paint(sink, y, u32::from(at), u32::from(b));
                forwarded += u64::from(b - at);
            }
        }
        if merging {
            rows.merge(y as usize, first, last, a, b, width);
        }
        forwarded
    }
}
