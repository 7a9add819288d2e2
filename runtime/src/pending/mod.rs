//! Pending pixels: the partly covered pixels of an anti-aliased frame, in caller memory.
//!
//! Front to back, each sample of a pixel ([`crate::fill::samples`]) belongs to the first
//! polygon that covers it, so a pixel's anti-aliased colour is the average of its samples'
//! first polygons, with no depth and no sorting. A pixel whose samples one polygon covers all
//! at once is finished at once, as without anti-aliasing. A partly covered pixel is *pending*:
//! a [`PendingPixel`] record holds its mask and the sums of its samples' colours, each later
//! polygon adds only the samples it newly covers, and the record is freed when its mask fills
//! up ([`Outcome::Finished`]). At the end of the frame (or band) [`Pending::drain`] gives the
//! background to the samples still uncovered. A scan-order frame does not drain its pool: it
//! reads each row's pending pixels with their colours ([`Pending::row_pixels`], the colours
//! the drain would give) into the gaps of its scan memory as it is read out.
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
use crate::fill::samples::{add_span_bits, CENTRE_SAMPLE, FULL_MASK, SAMPLES, SAMPLE_ROWS};

/// No record (the end of a list).
const NONE: u16 = 0x7fff;
/// A row's head flag: the row ran out of records.
const FALLEN_BACK: u16 = 0x8000;

/// One pending pixel: its column, its row list's next record, its covered samples and the sums
/// of their colours (at most [`SAMPLES`] x 255 per channel). 12 bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PendingPixel {
    x: u16,
    next: u16,
    mask: u16,
    sums: [u16; 3],
}

impl Default for PendingPixel {
    fn default() -> Self {
        PendingPixel {
            x: 0,
            next: NONE,
            mask: 0,
            sums: [0; 3],
        }
    }
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
    row: &'m mut [u16],
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
        row: &'m mut [u16],
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
        masks: &[u16],
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
        let channels = [colour.r, colour.g, colour.b].map(u16::from);
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
                let new = mask & !r.mask;
                if new == 0 {
                    out(x, Outcome::Pending);
                    continue;
                }
                let n = new.count_ones() as u16;
                let (next, mut r) = (r.next, *r);
                r.mask |= new;
                for (s, c) in r.sums.iter_mut().zip(channels) {
                    *s += n * c;
                }
                if r.mask == FULL_MASK {
                    self.unlink(row, link, at, next);
                    at = next;
                    out(x, Outcome::Finished(average(r.sums, [0; 3], 0)));
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
            let n = mask.count_ones() as u16;
            if let Some(slot) = self.records.get_mut(usize::from(new)) {
                *slot = PendingPixel {
                    x: x as u16,
                    next: at,
                    mask,
                    sums: channels.map(|c| n * c),
                };
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
        let bg = [background.r, background.g, background.b].map(u16::from);
        let mut painted = 0;
        for y in 0..self.height {
            let mut at = self.head(y) & !FALLEN_BACK;
            while let Some(r) = self.record(at) {
                let missing = (FULL_MASK & !r.mask).count_ones() as u16;
                let x = u32::from(r.x);
                sink.span(y, x, x + 1, average(r.sums, bg, missing));
                painted += 1;
                at = r.next;
            }
        }
        self.empty();
        painted
    }
}

impl Pending<'_> {
    /// Row `y`'s pending pixels in column order, each with the colour [`Pending::drain`] would
    /// paint it (`background` for its uncovered samples), leaving them pending: for a frame
    /// read out after the walk ([`crate::scan::ScanFrame`], which merges them into its gaps).
    pub fn row_pixels(&self, y: u32, background: Colour) -> PendingRow<'_> {
        PendingRow {
            records: &*self.records,
            at: self.head(y) & !FALLEN_BACK,
            fill: [background.r, background.g, background.b].map(u16::from),
        }
    }
}

/// The pending pixels of a row with their colours, column by column: [`Pending::row_pixels`].
#[derive(Debug, Clone)]
pub struct PendingRow<'a> {
    records: &'a [PendingPixel],
    at: u16,
    fill: [u16; 3],
}

impl Iterator for PendingRow<'_> {
    /// A pixel's column and colour.
    type Item = (u32, Colour);

    fn next(&mut self) -> Option<(u32, Colour)> {
        let r = self
            .records
            .get(usize::from(self.at))
            .filter(|_| self.at < NONE)?;
        self.at = r.next;
        let missing = (FULL_MASK & !r.mask).count_ones() as u16;
        Some((u32::from(r.x), average(r.sums, self.fill, missing)))
    }
}

/// The average of [`SAMPLES`] samples: `sums` plus `missing` samples of `fill`, rounded to
/// nearest.
fn average(sums: [u16; 3], fill: [u16; 3], missing: u16) -> Colour {
    let channel = |sum: u16, fill: u16| {
        let total = u32::from(sum) + u32::from(missing) * u32::from(fill);
        ((2 * total + SAMPLES) / (2 * SAMPLES)) as u8
    };
    let ([r, g, b], [fr, fg, fb]) = (sums, fill);
    Colour::new(channel(r, fr), channel(g, fg), channel(b, fb))
}
