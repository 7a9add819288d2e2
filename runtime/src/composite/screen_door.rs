//! The screen-door pass: the rows that fell back (see the module docs of [`super`]) drawn
//! again front to back by the first pass's walk, a transparent surface as the pixels of its
//! screen door ([`crate::display::screen_door_shows`]), each pixel once (the pass's route is
//! [`super::Composited`]'s, in its door mode). Which pixels are drawn is a bitmap per row in
//! the composite memory, whose runs are spent by then; when it cannot hold every such row at
//! once the pass walks the tree once a group of them.

use super::{Composite, FALLEN};
use crate::coverage::Coverage;
use crate::display::{Colour, Nowhere, SpanPaint, SpanSink};

/// A row that fell back and waits for a later group (the low bits of its head).
const NO_SLOT: u16 = super::NONE;

/// The words of one row's bitmap.
fn words_per_row(width: u32) -> usize {
    width.div_ceil(32) as usize
}

impl Composite<'_> {
    fn word(&self, k: usize) -> u32 {
        let r = self.runs.get(k / 3).copied().unwrap_or_default();
        match k % 3 {
            0 => r.span,
            1 => r.link,
            _ => r.sum,
        }
    }

    fn set_word(&mut self, k: usize, v: u32) {
        if let Some(r) = self.runs.get_mut(k / 3) {
            match k % 3 {
                0 => r.span = v,
                1 => r.link = v,
                _ => r.sum = v,
            }
        }
    }

    /// Whether the memory holds the bitmap of one row `width` pixels wide.
    pub(crate) fn holds_a_row(&self, width: u32) -> bool {
        self.capacity() * 3 >= words_per_row(width)
    }

    /// The slot of row `y` in this group's bitmaps.
    fn slot(&self, y: u32) -> Option<usize> {
        let h = self.head(y);
        (h & FALLEN != 0 && h & NO_SLOT != NO_SLOT).then_some(usize::from(h & NO_SLOT))
    }

    /// Give the rows that fell back, from row `from` on (of `rows`), the next group's slots,
    /// each bitmap set where `coverage` covers; returns the row after the group's last, or
    /// `None` when no row is left.
    pub(crate) fn next_group(
        &mut self,
        from: u32,
        rows: u32,
        coverage: &Coverage<'_>,
    ) -> Option<u32> {
        let width = coverage.width();
        let per_row = words_per_row(width);
        let slots = (self.capacity() * 3).checked_div(per_row).unwrap_or(0);
        let slots = slots.min(usize::from(NO_SLOT));
        let (mut y, mut used) = (from, 0usize);
        while y < rows && used < slots {
            if self.fallen(y) {
                if let Some(h) = self.heads.get_mut(y as usize) {
                    *h = FALLEN | used as u16;
                }
                // Drawn: what the span memory (or scan memory) covers.
                let base = used * per_row;
                for k in 0..per_row {
                    self.set_word(base + k, u32::MAX);
                }
                coverage.uncovered(y, 0, width, |a, b| self.unmark(base, a, b));
                used += 1;
            }
            y += 1;
        }
        (used > 0).then_some(y)
    }

    /// Set the bits `a .. b` of the bitmap at word `base`.
    fn mark(&mut self, base: usize, a: u32, b: u32) {
        for x in a..b {
            let k = base + (x / 32) as usize;
            self.set_word(k, self.word(k) | 1 << (x % 32));
        }
    }

    /// Clear the bits `a .. b` of the bitmap at word `base`.
    fn unmark(&mut self, base: usize, a: u32, b: u32) {
        for x in a..b {
            let k = base + (x / 32) as usize;
            self.set_word(k, self.word(k) & !(1 << (x % 32)));
        }
    }

    fn drawn(&self, base: usize, x: u32) -> bool {
        self.word(base + (x / 32) as usize) & (1 << (x % 32)) != 0
    }

    /// The end of a group: its rows' pixels not drawn get `background` (when there is one),
    /// and the rows leave their slots. Returns the pixels sent.
    pub(crate) fn end_group<S: SpanSink + ?Sized>(
        &mut self,
        until: u32,
        width: u32,
        background: Option<Colour>,
        first_row: u32,
        sink: &mut S,
    ) -> u64 {
        let per_row = words_per_row(width);
        let mut sent = 0;
        for y in 0..until {
            let Some(slot) = self.slot(y) else {
                continue;
            };
            if let Some(bg) = background {
                let base = slot * per_row;
                let mut x = 0;
                while x < width {
                    if self.drawn(base, x) {
                        x += 1;
                        continue;
                    }
                    let start = x;
                    while x < width && !self.drawn(base, x) {
                        x += 1;
                    }
                    sink.span(first_row + y, start, x, bg);
                    sent += u64::from(x - start);
                }
            }
            if let Some(h) = self.heads.get_mut(y as usize) {
                *h = FALLEN | NO_SLOT;
            }
        }
        sent
    }
}

impl Composite<'_> {
    /// A span of the screen-door pass on frame row `y` (of a band whose row 0 is frame row
    /// `first_row`, `width` wide): of the rows in the group, the pixels of `x_start .. x_end`
    /// that `shows` and that are not drawn yet, drawn with `paint` into `sink`, or into
    /// `coverage` when it keeps colours (scan memory); every other span is dropped. Returns
    /// the pixels drawn.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn through_door<P: SpanPaint, S: SpanSink + ?Sized>(
        &mut self,
        coverage: &mut Coverage<'_>,
        sink: &mut S,
        (first_row, width): (u32, u32),
        y: u32,
        x_start: u32,
        x_end: u32,
        paint: &P,
        shows: impl Fn(u32) -> bool,
    ) -> u64 {
        let local = y.wrapping_sub(first_row);
        let Some(slot) = self.slot(local) else {
            return 0;
        };
        let base = slot * words_per_row(width);
        let x_end = x_end.min(width);
        let (mut x, mut drawn) = (x_start, 0);
        while x < x_end {
            if self.drawn(base, x) || !shows(x) {
                x += 1;
                continue;
            }
            let start = x;
            while x < x_end && !self.drawn(base, x) && shows(x) {
                x += 1;
            }
            self.mark(base, start, x);
            if coverage.keeps_colours() {
                coverage.span(local, start, x, paint, &mut Nowhere);
            } else {
                paint.paint(&mut *sink, y, start, x);
            }
            drawn += u64::from(x - start);
        }
        drawn
    }
}
