//! Pending pixels: the partly covered pixels of an anti-aliased frame, in caller memory.
//!
//! Front to back, each sample of a pixel ([`crate::fill::samples`]) belongs to the first
//! polygon that covers it, so a pixel's anti-aliased colour is the average of its samples'
//! first polygons, with no depth and no sorting. A pixel whose samples one polygon covers all
//! at once is finished at once, as without anti-aliasing. A partly covered pixel is *pending*:
//! a [`PendingPixel`] record holds its mask and the sums of its samples' colours, each later
//! polygon adds only the samples it newly covers, and the record is freed when its mask fills
//! up ([`Outcome::Finished`]). At the end of the frame (or band) [`Pending::drain`] gives the
//! background to the samples still uncovered.
//!
//! # Memory
//! Records come from the caller's slice; each row keeps its own list, sorted by column, so a
//! run of masks walks its row's list once. When the records run out, the row that needed one
//! *falls back*: until the frame ends, its pixels without a record are drawn as without
//! anti-aliasing, from their centre sample ([`Outcome::Unrecorded`]); those with one go on.
//! So every pixel is either its anti-aliased colour or exactly its colour without
//! anti-aliasing, never a mix.

#[cfg(test)]
mod tests;

use crate::display::{Colour, SpanSink};
use crate::error::RenderError;
use crate::fill::samples::{add_span_bits, Mask, CENTRE_SAMPLE, FULL_MASK, SAMPLES, SAMPLE_ROWS};

/// No record (the end of a list).
const NONE: u16 = 0x7fff;
/// A row's head flag: the row ran out of records.
const FALLEN_BACK: u16 = 0x8000;

/// One pending pixel: its column, its row list's next record, its covered samples and the sums
/// of their colours. 12 bytes: the mask and the sums share one 64-bit accumulator
/// ([`SAMPLES`] bits of mask, then [`SUM_BITS`] per channel, red lowest), kept as two words so
/// that the record stays 4-byte aligned. Adding a polygon's new samples is then one addition.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PendingPixel {
    x: u16,
    next: u16,
    acc: [u32; 2],
}

/// Bits of a colour sum: at most [`SAMPLES`] x 255 per channel.
const SUM_BITS: u32 = 13;
const _: () = assert!(SAMPLES * 255 < 1 << SUM_BITS && SAMPLES + 3 * SUM_BITS <= 64);

impl Default for PendingPixel {
    fn default() -> Self {
        PendingPixel {
            x: 0,
            next: NONE,
            acc: [0; 2],
        }
    }
}

impl PendingPixel {
    fn acc(&self) -> u64 {
        u64::from(self.acc[0]) | u64::from(self.acc[1]) << 32
    }

    fn set_acc(&mut self, acc: u64) {
        self.acc = [acc as u32, (acc >> 32) as u32];
    }

    fn mask(&self) -> Mask {
        self.acc[0] & FULL_MASK
    }
}

/// `colour`'s channels placed as a [`PendingPixel`]'s sums: the accumulator's increment for one
/// sample.
fn packed(colour: Colour) -> u64 {
    (u64::from(colour.r) | u64::from(colour.g) << SUM_BITS | u64::from(colour.b) << (2 * SUM_BITS))
        << SAMPLES
}

/// What [`Pending::add_run`] says of a pixel of the run whose mask was not zero.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// The pixel's samples are all covered now: draw it in this colour and count it covered.
    Finished(Colour),
    /// The pixel is pending (or the run added no new sample to it): nothing to draw yet.
    Pending,
    /// The pixel's row fell back and the pixel has no record: draw it as without
    /// anti-aliasing, in the run's colour if `centre` (its mask holds the centre sample).
    Unrecorded {
        /// The run covers the pixel's centre sample.
        centre: bool,
    },
}

/// The pending pixels of a frame of `height` rows, and the row of masks the fill gathers a
/// polygon's samples into, in caller memory (see the module docs).
#[derive(Debug)]
pub struct Pending<'m> {
    records: &'m mut [PendingPixel],
    /// Per row: the first record of its list (or [`NONE`]), and [`FALLEN_BACK`].
    heads: &'m mut [u16],
    /// A polygon's masks of one pixel row (`gathered`), zero outside `lo .. hi`.
    row: &'m mut [Mask],
    /// The pixel row gathered in `row`, and its columns holding bits.
    gathered: u32,
    lo: u32,
    hi: u32,
    height: u32,
    /// First free record ([`NONE`]: none), linked through `next`.
    free: u16,
    in_use: usize,
    peak: usize,
}

impl<'m> Pending<'m> {
    /// Records in `records` (at most 32,767 are used), a list head per row in `heads` and a
    /// mask per column in `row`, for frames (or bands) of up to `width x height` pixels; needs
    /// `heads.len() >= height` and `row.len() >= width`, else [`RenderError::PendingMemory`].
    pub fn new(
        records: &'m mut [PendingPixel],
        heads: &'m mut [u16],
        row: &'m mut [Mask],
        width: u32,
        height: u32,
    ) -> Result<Self, RenderError> {
        let short = |len: usize, n: u32| usize::try_from(n).map_or(true, |n| len < n);
        if short(heads.len(), height) || short(row.len(), width) {
            return Err(RenderError::PendingMemory);
        }
        let mut p = Pending {
            records,
            heads,
            row,
            gathered: 0,
            lo: u32::MAX,
            hi: 0,
            height,
            free: NONE,
            in_use: 0,
            peak: 0,
        };
        p.clear();
        Ok(p)
    }

    /// Forget every pending pixel and fallen-back row, and the peak (a new frame or band).
    pub fn clear(&mut self) {
        self.empty();
        self.peak = 0;
    }

    /// Forget every pending pixel and fallen-back row.
    fn empty(&mut self) {
        for h in self.heads.iter_mut() {
            *h = NONE;
        }
        for m in self.row.iter_mut() {
            *m = 0;
        }
        (self.lo, self.hi) = (u32::MAX, 0);
        let n = self.records.len().min(usize::from(NONE));
        for (i, r) in self.records.iter_mut().take(n).enumerate() {
            *r = PendingPixel {
                next: if i + 1 < n { (i + 1) as u16 } else { NONE },
                ..PendingPixel::default()
            };
        }
        self.free = if n > 0 { 0 } else { NONE };
        self.in_use = 0;
    }

    /// Rows the memory holds.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Columns the mask row holds.
    pub fn width(&self) -> usize {
        self.row.len()
    }

    /// Gather the fill's span `[x_start, x_end)` of sample row `sample_row` (of the grid of
    /// [`crate::fill::samples`]) into the mask row. The fill emits its rows top to bottom; a
    /// span of another pixel row than the one gathered returns that row first, to be
    /// [added](Pending::add_gathered) before this span is gathered again.
    pub fn gather(&mut self, sample_row: u32, x_start: u32, x_end: u32) -> Result<(), u32> {
        let y = sample_row / SAMPLE_ROWS;
        if self.lo < self.hi && y != self.gathered {
            return Err(self.gathered);
        }
        self.gathered = y;
        if let Some((lo, hi)) = add_span_bits(self.row, sample_row, x_start, x_end) {
            self.lo = self.lo.min(lo);
            self.hi = self.hi.max(hi);
        }
        Ok(())
    }

    /// The pixel row gathered, and whether it holds bits.
    pub fn gathered(&self) -> Option<u32> {
        (self.lo < self.hi).then_some(self.gathered)
    }

    /// Clear the gathered masks of the pixels in `intervals` (the finished pixels of the row
    /// gathered: their samples all belong to nearer polygons).
    pub fn skip_finished(&mut self, intervals: &[(u16, u16)]) {
        for &(a, b) in intervals {
            let (a, b) = (u32::from(a).max(self.lo), u32::from(b).min(self.hi));
            if let Some(run) = self.row.get_mut(a as usize..b as usize) {
                run.fill(0);
            }
        }
    }

    /// [`Pending::add_run`] the gathered row's masks, in `colour`, and clear them.
    pub fn add_gathered<F: FnMut(u32, Outcome)>(&mut self, colour: Colour, out: F) {
        if self.lo >= self.hi {
            return;
        }
        let (lo, hi) = (self.lo as usize, self.hi as usize);
        let row = core::mem::take(&mut self.row);
        if let Some(run) = row.get_mut(lo..hi) {
            self.add_run(self.gathered, lo as u32, run, colour, out);
            run.fill(0);
        }
        self.row = row;
        (self.lo, self.hi) = (u32::MAX, 0);
    }

    /// Records in use now.
    pub fn in_use(&self) -> usize {
        self.in_use
    }

    /// Most records in use at once since the last [`Pending::clear`].
    pub fn peak(&self) -> usize {
        self.peak
    }

    /// Whether row `y` ran out of records in this frame.
    pub fn fallen_back(&self, y: u32) -> bool {
        self.head(y) & FALLEN_BACK != 0
    }

    fn head(&self, y: u32) -> u16 {
        usize::try_from(y)
            .ok()
            .and_then(|y| self.heads.get(y))
            .copied()
            .unwrap_or(NONE)
    }

    fn record(&self, i: u16) -> Option<&PendingPixel> {
        self.records.get(usize::from(i))
    }

    /// Add a polygon's masks of row `y`, pixels `x_start ..` (none of them finished), in
    /// `colour`: each pixel gets the samples of its mask not yet covered. `out` hears of every
    /// pixel whose mask is not zero, with its column, in column order.
    pub fn add_run<F: FnMut(u32, Outcome)>(
        &mut self,
        y: u32,
        x_start: u32,
        masks: &[Mask],
        colour: Colour,
        mut out: F,
    ) {
        let Some(row) = usize::try_from(y).ok().filter(|_| y < self.height) else {
            return;
        };
        let Some(&head) = self.heads.get(row) else {
            return;
        };
        let mut fallen = head & FALLEN_BACK != 0;
        // The link to the current record: the row's head (`None`) or a record's `next`.
        let mut link: Option<u16> = None;
        let mut at = head & !FALLEN_BACK;
        let sample = packed(colour);
        for (k, &mask) in masks.iter().enumerate() {
            let mask = mask & FULL_MASK;
            if mask == 0 {
                continue;
            }
            let x = x_start.saturating_add(k as u32);
            // Walk the sorted list to the first record at or right of `x`.
            while let Some(r) = self.record(at).filter(|r| u32::from(r.x) < x) {
                link = Some(at);
                at = r.next;
            }
            if let Some(r) = self.record(at).filter(|r| u32::from(r.x) == x) {
                let new = mask & !r.mask();
                if new == 0 {
                    out(x, Outcome::Pending);
                    continue;
                }
                let (next, mut r) = (r.next, *r);
                // The new samples' bits and colours: no carry crosses a field.
                r.set_acc(r.acc() + u64::from(new) + u64::from(new.count_ones()) * sample);
                if r.mask() == FULL_MASK {
                    self.unlink(row, link, at, next);
                    at = next;
                    out(x, Outcome::Finished(average(&r, [0; 3])));
                } else {
                    if let Some(slot) = self.records.get_mut(usize::from(at)) {
                        *slot = r;
                    }
                    out(x, Outcome::Pending);
                }
                continue;
            }
            if mask == FULL_MASK {
                out(x, Outcome::Finished(colour));
                continue;
            }
            let centre = mask >> CENTRE_SAMPLE & 1 == 1;
            if fallen {
                out(x, Outcome::Unrecorded { centre });
                continue;
            }
            let Some(new) = self.take_free() else {
                fallen = true;
                if let Some(h) = self.heads.get_mut(row) {
                    *h |= FALLEN_BACK;
                }
                out(x, Outcome::Unrecorded { centre });
                continue;
            };
            if let Some(slot) = self.records.get_mut(usize::from(new)) {
                *slot = PendingPixel {
                    x: x as u16,
                    next: at,
                    ..PendingPixel::default()
                };
                slot.set_acc(u64::from(mask) + u64::from(mask.count_ones()) * sample);
            }
            self.set_link(row, link, new);
            link = Some(new);
            out(x, Outcome::Pending);
        }
    }

    /// The first free record, taken off the free list.
    fn take_free(&mut self) -> Option<u16> {
        let i = self.free;
        let next = self.record(i)?.next;
        self.free = next;
        self.in_use += 1;
        self.peak = self.peak.max(self.in_use);
        Some(i)
    }

    /// Point `link` (the head of `row`, or record `link`'s `next`) at `to`.
    fn set_link(&mut self, row: usize, link: Option<u16>, to: u16) {
        match link {
            None => {
                if let Some(h) = self.heads.get_mut(row) {
                    *h = (*h & FALLEN_BACK) | to;
                }
            }
            Some(l) => {
                if let Some(r) = self.records.get_mut(usize::from(l)) {
                    r.next = to;
                }
            }
        }
    }

    /// Remove record `at` (reached through `link`, followed by `next`) and free it.
    fn unlink(&mut self, row: usize, link: Option<u16>, at: u16, next: u16) {
        self.set_link(row, link, next);
        let free = self.free;
        if let Some(r) = self.records.get_mut(usize::from(at)) {
            *r = PendingPixel {
                next: free,
                ..PendingPixel::default()
            };
            self.free = at;
            self.in_use = self.in_use.saturating_sub(1);
        }
    }

    /// End the frame (or band): every pending pixel takes `background` for its uncovered
    /// samples and is painted into `sink`, row by row, in column order; then the pool is
    /// empty again ([`Pending::peak`] stays until [`Pending::clear`]). Returns the pixels
    /// painted.
    pub fn drain<S: SpanSink + ?Sized>(&mut self, background: Colour, sink: &mut S) -> u64 {
        let fill = [background.r, background.g, background.b].map(u32::from);
        let mut painted = 0;
        for y in 0..self.height {
            let mut at = self.head(y) & !FALLEN_BACK;
            while let Some(r) = self.record(at) {
                let x = u32::from(r.x);
                sink.span(y, x, x + 1, average(r, fill));
                painted += 1;
                at = r.next;
            }
        }
        self.empty();
        painted
    }
}

/// The average of [`SAMPLES`] samples: `r`'s, plus its missing samples in `fill`, rounded to
/// nearest.
fn average(r: &PendingPixel, fill: [u32; 3]) -> Colour {
    let acc = r.acc();
    let missing = SAMPLES - r.mask().count_ones();
    let channel = |k: u32| {
        let sum = (acc >> (SAMPLES + k * SUM_BITS)) as u32 & ((1 << SUM_BITS) - 1);
        let total = sum + missing * fill[k as usize];
        ((2 * total + SAMPLES) / (2 * SAMPLES)) as u8
    };
    Colour::new(channel(0), channel(1), channel(2))
}
