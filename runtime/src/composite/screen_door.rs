//! The screen-door pass: the rows that fell back (see the module docs of [`super`]) drawn
//! again front to back, a transparent surface as the pixels of its screen door
//! ([`screen_door_shows`]), each pixel once. Which pixels are drawn is a bitmap per row in
//! the composite memory, whose runs are spent by then; when it cannot hold every such row at
//! once the pass walks the tree once a group of them.

use super::{Composite, FALLEN};
use crate::coverage::Coverage;
use crate::display::{
    screen_door_shows, Colour, Nowhere, RowShade, RowTexture, SpanPaint, SpanSink,
};

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

/// The screen-door pass's sink (the renderer's spans, in frame rows): of the rows in the
/// group, the pixels not drawn yet, each drawn once; every other span is dropped.
pub(crate) struct ScreenDoor<'c, 'm, 'v, S: SpanSink + ?Sized> {
    pub(crate) composite: &'c mut Composite<'m>,
    pub(crate) sink: &'c mut S,
    /// Scan memory, which takes the pixels instead of `sink` (a scan-order frame).
    pub(crate) scan: Option<&'c mut Coverage<'v>>,
    pub(crate) first_row: u32,
    pub(crate) width: u32,
    pub(crate) pixels: u64,
}

impl<S: SpanSink + ?Sized> ScreenDoor<'_, '_, '_, S> {
    /// Draw the pixels of `x_start .. x_end` on frame row `y` that `shows` and that are not
    /// drawn yet, with `paint`.
    fn route<P: SpanPaint>(
        &mut self,
        y: u32,
        x_start: u32,
        x_end: u32,
        paint: &P,
        shows: impl Fn(u32) -> bool,
    ) {
        let local = y.wrapping_sub(self.first_row);
        let Some(slot) = self.composite.slot(local) else {
            return;
        };
        let base = slot * words_per_row(self.width);
        let x_end = x_end.min(self.width);
        let mut x = x_start;
        while x < x_end {
            if self.composite.drawn(base, x) || !shows(x) {
                x += 1;
                continue;
            }
            let start = x;
            while x < x_end && !self.composite.drawn(base, x) && shows(x) {
                x += 1;
            }
            self.composite.mark(base, start, x);
            match self.scan.as_deref_mut() {
                Some(scan) => {
                    scan.span(local, start, x, paint, &mut Nowhere);
                }
                None => paint.paint(&mut *self.sink, y, start, x),
            }
            self.pixels += u64::from(x - start);
        }
    }
}

impl<S: SpanSink + ?Sized> SpanSink for ScreenDoor<'_, '_, '_, S> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        self.route(y, x_start, x_end, &colour, |_| true);
    }

    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        self.route(y, x_start, x_end, shade, |_| true);
    }

    fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture<'_>) {
        self.route(y, x_start, x_end, texture, |_| true);
    }

    fn transparent_span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour, opacity: u8) {
        self.route(y, x_start, x_end, &colour, |x| {
            screen_door_shows(x, y, opacity)
        });
    }
}
