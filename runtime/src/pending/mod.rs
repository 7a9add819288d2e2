//! Pending pixels: the partly covered pixels of an anti-aliased frame, in caller memory, and
//! the sink that routes an anti-aliased polygon's samples through them (`sink.rs`).
//!
//! Front to back, each sample of a pixel ([`crate::fill::samples`]) belongs to the first
//! polygon that covers it, so a pixel's anti-aliased colour is the average of its samples'
//! first polygons, with no depth and no sorting. A pixel whose samples one polygon covers all
//! at once is finished at once, as without anti-aliasing. A partly covered pixel is *pending*:
//! a [`PendingPixel`] record holds its mask and the sums of its samples' colours, each later
//! polygon adds only the samples it newly covers, and the record is freed when its mask fills
//! up. At the end of the frame (or band) [`Pending::drain`] gives the background to the
//! samples still uncovered. A scan-order frame does not drain its pool: it reads each row's
//! pending pixels with their colours ([`Pending::row_pixels`], the colours the drain would
//! give) into the gaps of its scan memory as it is read out.
//!
//! A polygon's samples arrive as the fill's spans on the sample grid, one per sample row for a
//! convex polygon: a pixel row of them at a time, with their extent, from the fill by pixel
//! rows of a convex polygon, else one by one from the general fill, which [`Pending::gather`]
//! keeps. [`Pending::next_run`] turns them into masks only for the pixels at the spans' ends:
//! the pixels between, whose samples the polygon covers all, finish as one run.
//!
//! # Memory
//! Records come from the caller's slice; each row keeps its own list, sorted by column, so a
//! run of masks walks its row's list once. When the records run out, the row that needed one
//! *falls back*: until the frame ends, its pixels without a record are drawn as without
//! anti-aliasing, from their centre sample; those with one go on.
//! So every pixel is either its anti-aliased colour or exactly its colour without
//! anti-aliasing, never a mix.

#[cfg(test)]
mod tests;

mod finish;
mod pixel;
mod sink;

use finish::average;
pub use finish::PendingRow;
use pixel::SUM_BITS;
pub use pixel::{PendingPixel, SampleColour};
pub(crate) use sink::{drain, Antialiased};

use crate::display::{modulate, Colour, RowShade, RowTexture};
use crate::error::RenderError;
use crate::fill::samples::{
    row_extent, Mask, RowExtent, RowSpans, CENTRE_SAMPLE, FULL_MASK, NO_SPAN, SAMPLES,
    SAMPLE_COLUMNS, SAMPLE_ROWS,
};

/// No record (the end of a list).
const NONE: u16 = 0x7fff;
/// A row's head flag: the row ran out of records.
const FALLEN_BACK: u16 = 0x8000;

/// The pending pixels of a frame of `height` rows, and the spans of the pixel row the fill is
/// gathering, in caller memory (see the module docs).
#[derive(Debug)]
pub struct Pending<'m> {
    records: &'m mut [PendingPixel],
    /// Per row: the first record of its list (or [`NONE`]), and [`FALLEN_BACK`].
    heads: &'m mut [u16],
    /// The gathered pixel row's span per sample row (columns of the sample grid),
    /// [`NO_SPAN`] for a sample row without one, and whether it holds any.
    spans: RowSpans,
    holding: bool,
    /// The gathered row's extent, when it was gathered at once.
    extent: Option<RowExtent>,
    /// The pixel row gathered.
    gathered: u32,
    height: u32,
    /// First freed record ([`NONE`]: none), linked through `next`; then the records from
    /// `unused` on, never taken since the frame began.
    free: u16,
    unused: u16,
    in_use: usize,
    peak: usize,
}

/// A walk along a row's list of records, in column order.
#[derive(Debug)]
struct Cursor {
    row: usize,
    /// The link to `at`: the row's head (`None`) or a record's `next`.
    link: Option<u16>,
    at: u16,
    fallen: bool,
}

/// Adding a gathered pixel row ([`Pending::begin_add`], [`Pending::next_run`]): the polygon's
/// colour, the pixels with a sample (`x .. hi`, `x` the next one), those with all
/// (`inner_lo .. inner_hi`, from the pixel at or right of every span's start to the one left
/// of every span's end: not an interval when the spans are narrow), and the run of finished
/// pixels being extended.
#[derive(Debug)]
pub struct RowAdd<'t> {
    x: u32,
    hi: u32,
    inner_lo: u32,
    inner_hi: u32,
    colour: Colour,
    sample: u64,
    /// A smooth polygon's shade on the pixel row's middle sample row, in sample columns: a
    /// pixel takes its centre sample's colour.
    shade: Option<RowShade>,
    /// A textured polygon's row, in pixels: a pixel takes its centre's texel (times the
    /// shade at its centre sample, for a smooth polygon).
    texture: Option<RowTexture<'t>>,
    cursor: Cursor,
    run: Option<(u32, u32, Colour)>,
}

impl<'t> RowAdd<'t> {
    /// Pixel `x`'s colour and its packed samples: the polygon's one colour, or its shade at
    /// the pixel's centre sample, or its texel there.
    #[inline]
    fn colour_at(&self, x: u32) -> (Colour, u64) {
        let shade = |x: u32| {
            self.shade
                .as_ref()
                .map(|s| s.at(x * SAMPLE_COLUMNS + SAMPLE_COLUMNS / 2))
        };
        let c = match (&self.texture, shade(x)) {
            (None, None) => return (self.colour, self.sample),
            (None, Some(c)) => c,
            (Some(t), None) => t.at(x),
            (Some(t), Some(c)) => modulate(t.at(x), c),
        };
        (c, pixel::packed(c))
    }

    /// Texture the row: `row(first, end)` gives its texture's row for its pixels
    /// `first .. end`.
    pub(crate) fn texture(&mut self, row: impl FnOnce(u32, u32) -> RowTexture<'t>) {
        self.texture = Some(row(self.x, self.hi));
    }
}

impl<'m> Pending<'m> {
    /// Records in `records` (at most 32,767 are used) and a list head per row in `heads`, for
    /// frames (or bands) of up to `height` rows; needs `heads.len() >= height`, else
    /// [`RenderError::PendingMemory`].
    pub fn new(
        records: &'m mut [PendingPixel],
        heads: &'m mut [u16],
        height: u32,
    ) -> Result<Self, RenderError> {
        // A head per row of the frame, no more: a row's head is found by one check.
        let Some(heads) = usize::try_from(height)
            .ok()
            .and_then(|h| heads.get_mut(..h))
        else {
            return Err(RenderError::PendingMemory);
        };
        // Past `NONE` records, an index would be `NONE`: the slice ends there, so that an index
        // in it is a record.
        let used = records.len().min(usize::from(NONE));
        let mut p = Pending {
            records: records.get_mut(..used).unwrap_or_default(),
            heads,
            spans: [NO_SPAN; SAMPLE_ROWS as usize],
            holding: false,
            extent: None,
            gathered: 0,
            height,
            free: NONE,
            unused: 0,
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

    /// Forget every pending pixel and fallen-back row. (One copy for its three callers.)
    #[inline(never)]
    fn empty(&mut self) {
        for h in self.heads.iter_mut() {
            *h = NONE;
        }
        self.holding = false;
        // The records are left as they are: each is written whole when taken.
        self.free = NONE;
        self.unused = 0;
        self.in_use = 0;
    }

    /// Rows the memory holds.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Gather the fill's span `[x_start, x_end)` of sample row `sample_row` (of the grid of
    /// [`crate::fill::samples`]). The fill emits its rows top to bottom; a span of another
    /// pixel row than the one gathered, or a second span of a sample row (a polygon that is not
    /// convex), returns the gathered pixel row first, to be [added](Pending::begin_add)
    /// before this span is gathered again.
    pub fn gather(&mut self, sample_row: u32, x_start: u32, x_end: u32) -> Result<(), u32> {
        let (y, t) = (sample_row / SAMPLE_ROWS, sample_row % SAMPLE_ROWS);
        let taken = self.spans.get(t as usize).is_some_and(|s| *s != NO_SPAN);
        if self.holding && (y != self.gathered || taken) {
            return Err(self.gathered);
        }
        if x_start < x_end {
            if !self.holding {
                self.spans = [NO_SPAN; SAMPLE_ROWS as usize];
            }
            self.gathered = y;
            self.holding = true;
            if let Some(s) = self.spans.get_mut(t as usize) {
                *s = (x_start, x_end);
            }
        }
        Ok(())
    }

    /// Gather pixel row `y`'s spans at once ([`NO_SPAN`] for a sample row without one) with
    /// their extent, as [`Pending::gather`] would one by one; the row gathered before is
    /// forgotten.
    pub(crate) fn gather_row(&mut self, y: u32, spans: &RowSpans, extent: &RowExtent) {
        self.gathered = y;
        self.spans = *spans;
        self.extent = Some(*extent);
        self.holding = true;
    }

    /// The pixel row gathered, if it holds a span.
    pub fn gathered(&self) -> Option<u32> {
        self.holding.then_some(self.gathered)
    }

    /// Start adding the gathered row's samples in `colour` (and forget them), if it holds any:
    /// then call [`Pending::next_run`] until it returns `None`. With `shade` (a smooth
    /// polygon's, on the sample row through the pixel centres, in sample columns) each pixel
    /// takes the colour at its centre sample instead.
    pub fn begin_add<'t>(
        &mut self,
        colour: &SampleColour,
        shade: Option<RowShade>,
    ) -> Option<RowAdd<'t>> {
        if !core::mem::take(&mut self.holding) {
            return None;
        }
        let y = self.gathered;
        let row = y as usize;
        let head = *self.heads.get(row)?;
        // The pixels with a sample, and those with all.
        let [lo, hi, inner_lo, inner_hi] = self
            .extent
            .take()
            .unwrap_or_else(|| row_extent(&self.spans));
        Some(RowAdd {
            x: lo / SAMPLE_COLUMNS,
            hi: hi.div_ceil(SAMPLE_COLUMNS),
            inner_lo: inner_lo.div_ceil(SAMPLE_COLUMNS),
            inner_hi: inner_hi / SAMPLE_COLUMNS,
            colour: colour.colour,
            sample: colour.sample,
            shade,
            texture: None,
            cursor: Cursor {
                row,
                link: None,
                at: head & !FALLEN_BACK,
                fallen: head & FALLEN_BACK != 0,
            },
            run: None,
        })
    }

    /// The next run of pixels of `add`'s row that its samples finish, in column order, in one
    /// colour: draw it and count it covered. Each pixel gets the samples not yet covered, but
    /// those of the pixels `finished` says are (their samples belong to nearer polygons); a run
    /// of pixels the polygon covers whole can hold finished pixels, to be skipped. In a
    /// fallen-back row, a pixel without a record is drawn when the polygon covers its centre
    /// sample, as without anti-aliasing.
    pub fn next_run(
        &mut self,
        add: &mut RowAdd<'_>,
        finished: impl Fn(u32) -> bool,
    ) -> Option<(u32, u32, Colour)> {
        while add.x < add.hi {
            let x = add.x;
            let (x0, x1, c) = if add.inner_lo <= x && x < add.inner_hi {
                // Covered whole: every pixel finishes, a pending one in its average.
                self.walk_to(&mut add.cursor, x);
                let (colour, sample) = add.colour_at(x);
                // A shaded run is one pixel long (runs of one colour join below).
                let end = |e: u32| {
                    if add.shade.is_some() || add.texture.is_some() {
                        x + 1
                    } else {
                        e
                    }
                };
                match self.record(add.cursor.at).map(|r| u32::from(r.x)) {
                    Some(rx) if rx == x => {
                        (x, x + 1, self.finish(&mut add.cursor, FULL_MASK, sample))
                    }
                    Some(rx) if rx < add.inner_hi => (x, end(rx), colour),
                    _ => (x, end(add.inner_hi), colour),
                }
            } else {
                add.x += 1;
                // A pixel with a record is not finished: only one without is tested.
                self.walk_to(&mut add.cursor, x);
                let pending = self
                    .record(add.cursor.at)
                    .is_some_and(|r| u32::from(r.x) == x);
                if !pending && finished(x) {
                    continue;
                }
                // Left of `inner_lo` the spans' starts cut the pixel, right of `inner_hi` their
                // ends (a missing sample row leaves both: `inner_lo` past every pixel).
                let mask = self.mask_of(x, x < add.inner_lo, x >= add.inner_hi);
                if mask == 0 {
                    continue;
                }
                let (colour, sample) = add.colour_at(x);
                match self.add_pixel(&mut add.cursor, x, mask, sample, colour) {
                    Some(c) => (x, x + 1, c),
                    None => continue,
                }
            };
            add.x = x1;
            match &mut add.run {
                Some((_, end, rc)) if *end == x0 && *rc == c => *end = x1,
                run => {
                    if let Some(done) = run.replace((x0, x1, c)) {
                        return Some(done);
                    }
                }
            }
        }
        add.run.take()
    }

    /// Pixel `x`'s mask from the gathered spans (a [`NO_SPAN`] gives no bit: no test), from
    /// their `starts`, their `ends`, or both (the others lie outside the pixel).
    fn mask_of(&self, x: u32, starts: bool, ends: bool) -> Mask {
        // A row's samples at or right of column `s` of the pixel, and left of it, for `s`
        // clamped to `0..=7` (one saturation on ARMv7-M).
        const FROM: [u8; 8] = [31, 30, 28, 24, 16, 0, 0, 0];
        const BELOW: [u8; 8] = [0, 1, 3, 7, 15, 31, 31, 31];
        const _: () = assert!(SAMPLE_COLUMNS == 5);
        let left = x * SAMPLE_COLUMNS;
        let column = |v: u32| (v.wrapping_sub(left) as i32).clamp(0, 7) as usize & 7;
        let mut mask = 0;
        for (t, &(a, b)) in self.spans.iter().enumerate() {
            let from = if starts { FROM[column(a)] } else { 31 };
            let below = if ends { BELOW[column(b)] } else { 31 };
            let bits = from & below;
            mask |= Mask::from(bits) << (t as u32 * SAMPLE_COLUMNS);
        }
        mask
    }

    /// Move `cursor` to the first record at or right of column `x`.
    fn walk_to(&self, cursor: &mut Cursor, x: u32) {
        while let Some(r) = self.record(cursor.at).filter(|r| u32::from(r.x) < x) {
            cursor.link = Some(cursor.at);
            cursor.at = r.next;
        }
    }

    /// Add samples `mask` (not zero, none of them finished) of pixel `x` in `colour`
    /// (`sample`: its [`packed`] channels); the pixel's colour if it finishes.
    fn add_pixel(
        &mut self,
        cursor: &mut Cursor,
        x: u32,
        mask: Mask,
        sample: u64,
        colour: Colour,
    ) -> Option<Colour> {
        self.walk_to(cursor, x);
        if let Some(r) = self.record(cursor.at).filter(|r| u32::from(r.x) == x) {
            if mask & !r.mask() == 0 {
                return None;
            }
            if (r.mask() | mask) == FULL_MASK {
                return Some(self.finish(cursor, mask, sample));
            }
            self.records
                .get_mut(usize::from(cursor.at))?
                .add(mask, sample);
            return None;
        }
        if mask == FULL_MASK {
            return Some(colour);
        }
        let centre = (mask >> CENTRE_SAMPLE & 1 == 1).then_some(colour);
        if cursor.fallen {
            return centre;
        }
        let Some(new) = self.take_free() else {
            cursor.fallen = true;
            if let Some(h) = self.heads.get_mut(cursor.row) {
                *h |= FALLEN_BACK;
            }
            return centre;
        };
        if let Some(slot) = self.records.get_mut(usize::from(new)) {
            *slot = PendingPixel {
                x: x as u16,
                next: cursor.at,
                ..PendingPixel::default()
            };
            slot.add(mask, sample);
        }
        self.set_link(cursor.row, cursor.link, new);
        cursor.link = Some(new);
        None
    }

    /// Give the record at `cursor` the samples of `mask` it lacks (which fills it), free it,
    /// and return its average.
    fn finish(&mut self, cursor: &mut Cursor, mask: Mask, sample: u64) -> Colour {
        let at = cursor.at;
        let Some(mut r) = self.record(at).copied() else {
            return Colour::default();
        };
        r.add(mask, sample);
        self.unlink(cursor.row, cursor.link, at, r.next);
        cursor.at = r.next;
        average(&r, [0; 3])
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

    /// Record `i`, if it is one: never [`NONE`] (the pool ends before it).
    fn record(&self, i: u16) -> Option<&PendingPixel> {
        self.records.get(usize::from(i))
    }

    /// The first free record, taken off the free list.
    fn take_free(&mut self) -> Option<u16> {
        let i = match self.record(self.free).map(|r| r.next) {
            Some(next) => core::mem::replace(&mut self.free, next),
            // Then those never used in this frame, in order.
            None if usize::from(self.unused) < self.records.len() => {
                self.unused += 1;
                self.unused - 1
            }
            None => return None,
        };
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
}
