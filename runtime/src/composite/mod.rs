//! Composite: the transparent surfaces of a front-to-back frame, "under" compositing in caller
//! memory, with no framebuffer.
//!
//! Front to back, a pixel behind transparent surfaces keeps its colour sum `C` and its
//! transmittance `T` (what still shows through) until an opaque surface finishes it
//! (`C + T colour`) or the frame ends (`C + T background`). A transparent surface of colour
//! `c` and opacity `a` adds `T a c` to `C` and multiplies `T` by `1 - a`. Colour and opacity
//! are one a polygon, so `(C, T)` is one along runs of pixels: the memory keeps **runs**, per
//! row a list sorted by column ([`CompositeRun`], 12 bytes), never pixels. A run holds only
//! pixels the span memory does not cover: transparent spans are clipped against it and never
//! mark it ([`crate::coverage::Coverage::uncovered`]), so culling ignores them, and an opaque
//! span finishes the runs it meets as it marks its pixels covered.
//!
//! `C` is kept in quarters of a level and `T` in `2^-15`, so three panes stay within a
//! level of the exact composite.
//!
//! # Memory and the fallback
//! Before it changes a row, a span counts the records it needs (an opaque span at most one,
//! splitting a run); when the memory has fewer, that row **falls back**: its runs are
//! dropped, the rest of the walk skips it, and after the walk the renderer walks the tree
//! again for the rows that fell back, drawing them with screen-door transparency
//! ([`crate::display::screen_door`]), each pixel once, in a bitmap of the same memory
//! (`screen_door.rs`). A pixel sent before its row fell back has its exact colour, every other
//! pixel of the row its screen-door colour: never a mix. [`crate::render::FrameStats`] counts
//! the rows (`fallback_rows`); the builder's sizes file gives the runs an orbit needs.

mod screen_door;
mod sink;
#[cfg(test)]
mod tests;

#[cfg_attr(not(feature = "transparency"), allow(unused_imports))]
pub(crate) use sink::Composited;

use crate::coverage::Coverage;
use crate::display::{Colour, Shifted, SpanPaint, SpanSink};
use crate::error::RenderError;

/// Transmittance 1, in `2^-15`.
const ONE: u32 = 1 << 15;
/// Bits of a channel of a run's colour sum (quarters of a level: `1023` is `255.75`).
const SUM_BITS: u32 = 10;
const SUM_MASK: u32 = (1 << SUM_BITS) - 1;
/// No record (the end of a list).
const NONE: u16 = 0x7fff;
/// A row's head flag: the row fell back (its low bits then hold its screen-door slot).
const FALLEN: u16 = 0x8000;

/// The most records a [`Composite`] uses.
pub const MAX_RUNS: usize = NONE as usize;
/// Bytes of a [`CompositeRun`] record.
pub const RUN_BYTES: usize = core::mem::size_of::<CompositeRun>();

/// One run of pixels behind transparent surfaces, in caller memory: its columns, the next run
/// of its row, and its colour sum and transmittance (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CompositeRun {
    /// `start | end << 16`.
    span: u32,
    /// `next | transmittance << 16`.
    link: u32,
    /// The colour sum, [`SUM_BITS`] a channel (red the low bits).
    sum: u32,
}

/// A run's colour sum and transmittance: what its pixels show so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Under {
    sum: u32,
    transmittance: u32,
}

impl Under {
    /// Nothing in front yet: the background or the first surface shows as it is.
    const CLEAR: Under = Under {
        sum: 0,
        transmittance: ONE,
    };

    /// Behind one more surface of `colour` at `opacity`: in multiplies and shifts (no
    /// division, which a Cortex-M0+ does in software).
    #[inline]
    fn behind(self, colour: Colour, opacity: u8) -> Under {
        // `alpha = opacity / 255` in `2^-15`, rounded: `255` is exactly `ONE`.
        let alpha = (u32::from(opacity) * 8_421_505 + (1 << 15)) >> 16;
        // `T alpha`, what this surface shows, in `2^-15`.
        let shown = (self.transmittance * alpha + (1 << 14)) >> 15;
        // `T alpha c` in quarters of a level: `shown c 4 / 2^15`, rounded.
        let add = |shift: u32, c: u8| {
            let old = (self.sum >> shift) & SUM_MASK;
            let more = (shown * u32::from(c) + (1 << 12)) >> 13;
            (old + more).min(SUM_MASK) << shift
        };
        Under {
            sum: add(0, colour.r) | add(SUM_BITS, colour.g) | add(2 * SUM_BITS, colour.b),
            transmittance: self.transmittance - shown.min(self.transmittance),
        }
    }

    /// Finished by an opaque `colour` (or the background): `C + T colour`, rounded.
    #[inline]
    fn over(self, colour: Colour) -> Colour {
        let t = self.transmittance;
        let channel = |shift: u32, c: u8| {
            let sum = (self.sum >> shift) & SUM_MASK;
            ((sum * 8192 + t * u32::from(c) + (1 << 14)) >> 15).min(255) as u8
        };
        Colour::new(
            channel(0, colour.r),
            channel(SUM_BITS, colour.g),
            channel(2 * SUM_BITS, colour.b),
        )
    }
}

/// The runs of a frame of `height` rows in caller memory (see the module docs).
#[derive(Debug)]
pub struct Composite<'m> {
    runs: &'m mut [CompositeRun],
    /// Per row: its first run (or [`NONE`]), and [`FALLEN`].
    heads: &'m mut [u16],
    height: u32,
    /// First freed record ([`NONE`]: none), linked through `next`; then the records from
    /// `unused` on, never taken since the frame began.
    free: u16,
    unused: u16,
    in_use: usize,
    peak: usize,
    fallen: u32,
}

impl<'m> Composite<'m> {
    /// Runs in `runs` (at most [`MAX_RUNS`] are used) and a list head per row in `heads`, for
    /// frames (or bands) of up to `height` rows; needs `heads.len() >= height`, else
    /// [`RenderError::CompositeMemory`].
    pub fn new(
        runs: &'m mut [CompositeRun],
        heads: &'m mut [u16],
        height: u32,
    ) -> Result<Self, RenderError> {
        if (heads.len() as u64) < u64::from(height) {
            return Err(RenderError::CompositeMemory);
        }
        let mut c = Composite {
            runs,
            heads,
            height,
            free: NONE,
            unused: 0,
            in_use: 0,
            peak: 0,
            fallen: 0,
        };
        c.clear();
        Ok(c)
    }

    /// Forget every run (a new frame or band).
    pub fn clear(&mut self) {
        self.heads.fill(NONE);
        self.free = NONE;
        self.unused = 0;
        self.in_use = 0;
        self.peak = 0;
        self.fallen = 0;
    }

    /// Rows the memory serves.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Records it can hold.
    pub fn capacity(&self) -> usize {
        self.runs.len().min(MAX_RUNS)
    }

    /// The records the frame asked for at once, at most, since it began: in use, and what a
    /// span counted it might need before it changed a row (a little more than the most in
    /// use). A memory of this many records draws the same frame with no row falling back.
    pub fn peak(&self) -> usize {
        self.peak
    }

    /// Rows that fell back to screen-door transparency this frame.
    pub fn fallen_rows(&self) -> u32 {
        self.fallen
    }

    fn head(&self, y: u32) -> u16 {
        self.heads.get(y as usize).copied().unwrap_or(FALLEN)
    }

    /// Whether row `y` fell back (rows beyond the memory count as fallen: nothing is kept for
    /// them).
    #[inline]
    pub(crate) fn fallen(&self, y: u32) -> bool {
        self.head(y) & FALLEN != 0
    }

    /// Whether row `y` has runs.
    #[inline]
    pub(crate) fn has_runs(&self, y: u32) -> bool {
        self.head(y) != NONE
    }

    fn free_records(&self) -> usize {
        self.capacity() - self.in_use
    }

    fn run(&self, i: u16) -> CompositeRun {
        self.runs.get(usize::from(i)).copied().unwrap_or_default()
    }

    fn set(&mut self, i: u16, r: CompositeRun) {
        if let Some(slot) = self.runs.get_mut(usize::from(i)) {
            *slot = r;
        }
    }

    /// A record, from the freed ones first.
    fn take(&mut self) -> Option<u16> {
        let i = if self.free != NONE {
            let i = self.free;
            self.free = next(self.run(i));
            i
        } else if usize::from(self.unused) < self.capacity() {
            self.unused += 1;
            self.unused - 1
        } else {
            return None;
        };
        self.in_use += 1;
        self.peak = self.peak.max(self.in_use);
        Some(i)
    }

    fn release(&mut self, i: u16) {
        let mut r = self.run(i);
        set_next(&mut r, self.free);
        self.set(i, r);
        self.free = i;
        self.in_use -= 1;
    }

    /// Row `y` falls back: its runs are dropped and the rest of the walk skips it.
    pub(crate) fn fall_back(&mut self, y: u32) {
        let mut at = self.head(y);
        if at & FALLEN != 0 {
            return;
        }
        while at != NONE {
            let n = next(self.run(at));
            self.release(at);
            at = n;
        }
        if let Some(h) = self.heads.get_mut(y as usize) {
            // (No screen-door slot yet: `screen_door.rs` gives it one.)
            *h = FALLEN | NONE;
        }
        self.fallen += 1;
    }

    /// The link to the first run of row `y`, or after run `prev`.
    fn link_after(&self, y: u32, prev: Option<u16>) -> u16 {
        match prev {
            None => self.head(y),
            Some(p) => next(self.run(p)),
        }
    }

    fn set_link_after(&mut self, y: u32, prev: Option<u16>, to: u16) {
        match prev {
            None => {
                if let Some(h) = self.heads.get_mut(y as usize) {
                    *h = to;
                }
            }
            Some(p) => {
                let mut r = self.run(p);
                set_next(&mut r, to);
                self.set(p, r);
            }
        }
    }

    /// A new run `[start, end)` showing `under`, after `prev` in row `y`'s list (the caller
    /// counted it: there is a record).
    fn insert(&mut self, y: u32, prev: Option<u16>, start: u32, end: u32, under: Under) -> u16 {
        let Some(i) = self.take() else {
            return NONE;
        };
        let after = self.link_after(y, prev);
        let mut r = CompositeRun::default();
        set_span(&mut r, start, end);
        set_under(&mut r, under);
        set_next(&mut r, after);
        self.set(i, r);
        self.set_link_after(y, prev, i);
        i
    }

    /// Run `i` cut at `x` (inside it): `i` keeps `[start, x)`, a new run after it `[x, end)`.
    fn split(&mut self, y: u32, i: u16, x: u32) -> u16 {
        let r = self.run(i);
        let n = self.insert(y, Some(i), x, end(r), under(r));
        let mut r = self.run(i);
        let s = start(r);
        set_span(&mut r, s, x);
        self.set(i, r);
        n
    }

    /// Records adding `[a, b)` of row `y` needs at most: one per gap between its runs there,
    /// one per run it cuts.
    fn needed(&self, y: u32, a: u32, b: u32) -> usize {
        let (mut n, mut x) = (0, a);
        let mut at = self.head(y);
        while at != NONE && x < b {
            let r = self.run(at);
            let (s, e) = (start(r), end(r));
            if e > x {
                if s >= b {
                    break;
                }
                if s > x {
                    n += 1;
                }
                n += usize::from(s < x && x < e) + usize::from(s < b && b < e);
                x = e;
            }
            at = next(r);
        }
        n + usize::from(x < b)
    }

    /// A transparent span of row `y`: `colour` at `opacity` over its `pieces` (the parts the
    /// span memory does not cover, left to right, given twice: counted, then added). Falls the
    /// row back when the memory lacks the records.
    pub(crate) fn add<F>(&mut self, y: u32, pieces: F, colour: Colour, opacity: u8)
    where
        F: Fn(&mut dyn FnMut(u32, u32)),
    {
        if self.fallen(y) {
            return;
        }
        let mut need = 0;
        pieces(&mut |a, b| need += self.needed(y, a, b));
        self.peak = self.peak.max(self.in_use + need);
        if need > self.free_records() {
            self.fall_back(y);
            return;
        }
        pieces(&mut |a, b| self.add_piece(y, a, b, colour, opacity));
        self.coalesce(y);
    }

    fn add_piece(&mut self, y: u32, a: u32, b: u32, colour: Colour, opacity: u8) {
        let fresh = Under::CLEAR.behind(colour, opacity);
        let (mut prev, mut x) = (None, a);
        while x < b {
            let mut at = self.link_after(y, prev);
            while at != NONE && end(self.run(at)) <= x {
                prev = Some(at);
                at = next(self.run(at));
            }
            if at == NONE || start(self.run(at)) >= b {
                self.insert(y, prev, x, b, fresh);
                return;
            }
            let s = start(self.run(at));
            if s > x {
                prev = Some(self.insert(y, prev, x, s, fresh));
                x = s;
                continue;
            }
            if s < x {
                prev = Some(at);
                at = self.split(y, at, x);
            }
            if end(self.run(at)) > b {
                self.split(y, at, b);
            }
            let mut r = self.run(at);
            let u = under(r).behind(colour, opacity);
            set_under(&mut r, u);
            self.set(at, r);
            x = end(r);
        }
    }

    /// Merge the runs of row `y` that touch and show the same.
    fn coalesce(&mut self, y: u32) {
        let mut at = self.head(y);
        while at != NONE {
            let r = self.run(at);
            let n = next(r);
            if n == NONE {
                break;
            }
            let m = self.run(n);
            if end(r) == start(m) && under(r) == under(m) {
                let mut r = r;
                let s = start(r);
                set_span(&mut r, s, end(m));
                set_next(&mut r, next(m));
                self.set(at, r);
                self.release(n);
            } else {
                at = n;
            }
        }
    }

    /// Whether an opaque span of row `y` may go on: it may split a run, which needs a record;
    /// without one the row falls back (and the span is dropped).
    #[inline]
    pub(crate) fn opaque_fits(&mut self, y: u32) -> bool {
        if self.fallen(y) {
            return false;
        }
        if self.has_runs(y) {
            self.peak = self.peak.max(self.in_use + 1);
            if self.free_records() == 0 {
                self.fall_back(y);
                return false;
            }
        }
        true
    }

    /// An opaque piece `[a, b)` of row `y` (uncovered, now covered): painted into `sink`, as
    /// it is where no run is, finishing the runs it meets, which give up those pixels.
    pub(crate) fn finish<P, S>(&mut self, y: u32, a: u32, b: u32, paint: &P, sink: &mut S)
    where
        P: SpanPaint,
        S: SpanSink + ?Sized,
    {
        let (mut prev, mut x) = (None, a);
        while x < b {
            let mut at = self.link_after(y, prev);
            while at != NONE && end(self.run(at)) <= x {
                prev = Some(at);
                at = next(self.run(at));
            }
            if at == NONE || start(self.run(at)) >= b {
                paint.paint(sink, y, x, b);
                return;
            }
            let r = self.run(at);
            let (s, e) = (start(r), end(r));
            if s > x {
                paint.paint(sink, y, x, s);
                x = s;
            }
            let stop = e.min(b);
            let u = under(r);
            paint.runs(x, stop, |p, q, c| sink.span(y, p, q, u.over(c)));
            match (s < x, e > stop) {
                (true, true) => {
                    // (The one split an opaque span can make: `opaque_fits` kept a record.)
                    let n = self.split(y, at, stop);
                    let mut r = self.run(at);
                    set_span(&mut r, s, x);
                    self.set(at, r);
                    let _ = n;
                    return;
                }
                (true, false) => {
                    let mut r = r;
                    set_span(&mut r, s, x);
                    self.set(at, r);
                    prev = Some(at);
                }
                (false, true) => {
                    let mut r = r;
                    set_span(&mut r, stop, e);
                    self.set(at, r);
                }
                (false, false) => {
                    let after = next(r);
                    self.set_link_after(y, prev, after);
                    self.release(at);
                }
            }
            x = stop;
        }
    }

    /// The end of a frame (or band) whose row 0 is frame row `first_row`: every row that did
    /// not fall back gets `background`, where `coverage` does not cover it, through the runs
    /// still open there (`C + T background`; black without a background) or as it is (left
    /// alone without one). Returns the pixels sent. In scan memory, which keeps colours, the
    /// runs go into it and its gaps are left to the read-out.
    pub(crate) fn finish_rows<S: SpanSink + ?Sized>(
        &mut self,
        coverage: &mut Coverage<'_>,
        background: Option<Colour>,
        rows: u32,
        first_row: u32,
        sink: &mut S,
    ) -> u64 {
        let bg = background.unwrap_or_default();
        if coverage.keeps_colours() {
            // Scan memory: the runs go into it, its gaps are the read-out's.
            for y in 0..rows {
                let mut at = self.head(y);
                while !self.fallen(y) && at != NONE {
                    let r = self.run(at);
                    sink::into_scan(coverage, y, start(r), end(r), under(r).over(bg));
                    at = next(r);
                }
            }
            self.spend_runs(rows);
            return 0;
        }
        let mut sink = Shifted {
            sink,
            by: first_row,
        };
        let width = coverage.width();
        let mut sent = 0u64;
        for y in 0..rows {
            if self.fallen(y) {
                continue;
            }
            let mut at = self.head(y);
            let mut gap = |a: u32, b: u32, sink: &mut Shifted<'_, S>, at: &mut u16| {
                let mut x = a;
                while *at != NONE && x < b {
                    let r = self.run(*at);
                    let (s, e) = (start(r), end(r));
                    if s >= b {
                        break;
                    }
                    if s > x && background.is_some() {
                        sink.span(y, x, s, bg);
                        sent += u64::from(s - x);
                    }
                    sink.span(y, s, e, under(r).over(bg));
                    sent += u64::from(e - s);
                    x = e;
                    *at = next(r);
                }
                if x < b && background.is_some() {
                    sink.span(y, x, b, bg);
                    sent += u64::from(b - x);
                }
            };
            let mut x = 0;
            for &(a, b) in coverage.row(y) {
                if x < u32::from(a) {
                    gap(x, u32::from(a), &mut sink, &mut at);
                }
                x = u32::from(b);
            }
            if x < width {
                gap(x, width, &mut sink, &mut at);
            }
        }
        self.spend_runs(rows);
        sent
    }

    /// The runs of the first `rows` rows are finished: their memory is free (a bitmap of
    /// the screen-door pass may take it); the rows that fell back stay marked.
    fn spend_runs(&mut self, rows: u32) {
        self.heads.iter_mut().take(rows as usize).for_each(|h| {
            if *h & FALLEN == 0 {
                *h = NONE;
            }
        });
        self.free = NONE;
        self.unused = 0;
        self.in_use = 0;
    }
}

fn start(r: CompositeRun) -> u32 {
    r.span & 0xffff
}

fn end(r: CompositeRun) -> u32 {
    r.span >> 16
}

fn next(r: CompositeRun) -> u16 {
    (r.link & 0xffff) as u16
}

fn under(r: CompositeRun) -> Under {
    Under {
        sum: r.sum,
        transmittance: r.link >> 16,
    }
}

fn set_span(r: &mut CompositeRun, start: u32, end: u32) {
    r.span = (start & 0xffff) | end << 16;
}

fn set_next(r: &mut CompositeRun, next: u16) {
    r.link = (r.link & !0xffff) | u32::from(next);
}

fn set_under(r: &mut CompositeRun, u: Under) {
    r.sum = u.sum;
    r.link = (r.link & 0xffff) | u.transmittance.min(ONE) << 16;
}
