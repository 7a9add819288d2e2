//! A scan-order frame read out: [`ScanFrame`], its pixels row by row ([`ScanPixels`], or a row
//! into a buffer), the gaps between the scan memory's intervals in the background colour but
//! for an anti-aliased frame's pending pixels ([`Gaps`]).

use super::{ScanMemory, NIL};
use crate::display::{dither_rgb565, Colour, PixelFormat, Rgb565, RowColours};
use crate::pending::Pending;
#[cfg(feature = "antialias")]
use crate::pending::PendingRow;

impl ScanMemory<'_> {
    /// The frame as pixels, row by row, gaps in `background` (RGB565) but for the pending
    /// pixels of `gaps`.
    pub(super) fn pixels<'a>(&'a self, background: u16, gaps: Gaps<'a>) -> ScanPixels<'a> {
        let mut row = gaps.row(0);
        ScanPixels {
            memory: self,
            background,
            y: 0,
            x: 0,
            node: self.head(0),
            run: 0,
            colour: background,
            shade: None,
            gaps,
            next_gap: row.next(),
            row,
        }
    }

    /// Row `y` into `out` (its first `width` pixels), gaps in `background` but for the
    /// pending pixels of `gaps`.
    pub(super) fn row_into(&self, y: u32, background: u16, gaps: Gaps<'_>, out: &mut [u16]) {
        // A frame without shaded intervals (no material named) is read out without a test for
        // them: one instance each.
        if cfg!(feature = "smooth") && self.materials > 0 {
            self.row_into_with::<true>(y, background, gaps, out);
        } else {
            self.row_into_with::<false>(y, background, gaps, out);
        }
    }

    /// [`Self::row_into`], shaded intervals possible or not (`SHADES`).
    #[inline(always)]
    fn row_into_with<const SHADES: bool>(
        &self,
        y: u32,
        background: u16,
        gaps: Gaps<'_>,
        out: &mut [u16],
    ) {
        let w = usize::from(self.width).min(out.len());
        let Some(out) = out.get_mut(..w) else { return };
        let mut pending = gaps.row(y);
        let mut next = pending.next();
        // Gap `at..end`: the background, then its pending pixels (any left of it lie under an
        // interval, which wins: never, by construction).
        let mut gap = |at: usize, end: usize, out: &mut [u16]| {
            if let Some(gap) = out.get_mut(at..end) {
                gap.fill(background);
            }
            while let Some((x, c)) = next.filter(|&(x, _)| usize::from(x) < end) {
                if usize::from(x) >= at {
                    if let Some(p) = out.get_mut(usize::from(x)) {
                        *p = c;
                    }
                }
                next = pending.next();
            }
        };
        let mut at = 0usize;
        for (i, n, end) in self.row_nodes(y) {
            let (s, e) = (usize::from(n.first()).min(w), usize::from(end).min(w));
            gap(at, s, out);
            if n.is_gap() {
                gap(s, e, out);
            } else if let Some(run) = out.get_mut(s..e) {
                if SHADES && n.is_shaded() {
                    // As an RGB565 framebuffer stores a shaded span.
                    let shade = self.row_shade(i, &n);
                    Rgb565::encode_shaded(run, s as u32, y, &shade, self.dither);
                } else {
                    run.fill(n.colour);
                }
            }
            at = at.max(e);
        }
        gap(at, w, out);
    }
}

/// The pending pixels of an anti-aliased frame, which the read-out puts into its gaps (with
/// the `antialias` feature; none without it, and then no room in the read-out's iterator,
/// whose state a pixel loop keeps in registers).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Gaps<'a> {
    #[cfg(feature = "antialias")]
    pending: Option<(&'a Pending<'a>, Colour)>,
    _frame: core::marker::PhantomData<&'a ()>,
}

impl<'a> Gaps<'a> {
    /// The pending pixels of `pending`, their uncovered samples in `background` (none
    /// without the `antialias` feature).
    #[cfg_attr(not(feature = "antialias"), allow(unused_variables))]
    pub(crate) fn pending(pending: Option<&'a Pending<'a>>, background: Colour) -> Self {
        Gaps {
            #[cfg(feature = "antialias")]
            pending: pending.map(|p| (p, background)),
            _frame: core::marker::PhantomData,
        }
    }

    /// Row `y`'s pending pixels.
    #[cfg_attr(not(feature = "antialias"), allow(unused_variables))]
    fn row(&self, y: u32) -> GapRow<'a> {
        GapRow {
            #[cfg(feature = "antialias")]
            pending: self
                .pending
                .map(|(p, background)| p.row_pixels(y, background)),
            _frame: core::marker::PhantomData,
        }
    }
}

/// A row's pending pixels, column by column: column and RGB565 colour.
#[derive(Debug, Clone)]
struct GapRow<'a> {
    #[cfg(feature = "antialias")]
    pending: Option<PendingRow<'a>>,
    _frame: core::marker::PhantomData<&'a ()>,
}

impl GapRow<'_> {
    #[inline]
    fn next(&mut self) -> Option<(u16, u16)> {
        #[cfg(feature = "antialias")]
        if let Some((x, c)) = self.pending.as_mut().and_then(Iterator::next) {
            return Some((x as u16, c.to_rgb565()));
        }
        None
    }
}

/// The pixels of a frame in scan order (RGB565), `width x height` of them: see
/// [`ScanFrame::pixels`].
#[derive(Debug, Clone)]
pub struct ScanPixels<'a> {
    memory: &'a ScanMemory<'a>,
    background: u16,
    y: u32,
    x: u16,
    node: u16,
    /// Pixels left of the current run, all `colour` or, in a shaded interval, `shade`'s.
    run: u16,
    colour: u16,
    shade: Option<RowColours>,
    gaps: Gaps<'a>,
    /// Row `y`'s pending pixels, and the next of them (column, colour).
    row: GapRow<'a>,
    next_gap: Option<(u16, u16)>,
}

impl ScanPixels<'_> {
    /// Start the next run: the rest of the gap before the next interval, or that interval.
    #[inline(never)]
    fn refill(&mut self) -> bool {
        let m = self.memory;
        loop {
            if self.y >= m.height {
                return false;
            }
            if self.x >= m.width {
                self.y += 1;
                self.x = 0;
                self.node = m.head(self.y);
                self.row = self.gaps.row(self.y);
                self.next_gap = self.row.next();
                continue;
            }
            let n = (self.node != NIL).then(|| m.node(self.node));
            self.shade = None;
            let gap_end = match n {
                Some(n) if m.end(&n) <= self.x => {
                    self.node = n.next;
                    continue;
                }
                Some(n) if n.first() > self.x => Some(n.first().min(m.width)),
                // A gap node: left in place, since pending pixels may cut its gap.
                Some(n) if n.is_gap() => Some(m.end(&n).min(m.width)),
                Some(n) => {
                    self.colour = n.colour;
                    if cfg!(feature = "smooth") && n.is_shaded() {
                        let shade = m.row_shade(self.node, &n);
                        self.shade = Some(shade.colours(u32::from(self.x)));
                    }
                    self.run = m.end(&n).min(m.width) - self.x;
                    self.node = n.next;
                    None
                }
                None => Some(m.width),
            };
            if let Some(end) = gap_end {
                // A gap: the background up to its next pending pixel, or that pixel (those
                // left of it lie under an interval, which wins: never, by construction).
                while self.next_gap.is_some_and(|(x, _)| x < self.x) {
                    self.next_gap = self.row.next();
                }
                self.colour = self.background;
                self.run = end - self.x;
                match self.next_gap {
                    Some((x, c)) if x == self.x => {
                        self.colour = c;
                        self.run = 1;
                        self.next_gap = self.row.next();
                    }
                    Some((x, _)) if x < end => self.run = x - self.x,
                    _ => {}
                }
            }
            if self.run == 0 {
                self.node = NIL;
                self.x = m.width;
                continue;
            }
            self.x += self.run;
            return true;
        }
    }
}

impl Iterator for ScanPixels<'_> {
    type Item = u16;

    #[inline]
    fn next(&mut self) -> Option<u16> {
        if self.run == 0 && !self.refill() {
            return None;
        }
        self.run -= 1;
        if let Some(shade) = &mut self.shade {
            let colour = shade.next()?;
            if self.memory.dither {
                let x = u32::from(self.x - self.run - 1);
                return Some(dither_rgb565(x, self.y, colour));
            }
            return Some(colour.to_rgb565());
        }
        Some(self.colour)
    }
}

/// A frame drawn in scan order ([`Renderer::draw_scan`]), ready to go to a display: its
/// pixels row by row, top to bottom, in RGB565.
///
/// [`Renderer::draw_scan`]: crate::render::Renderer::draw_scan
#[derive(Debug)]
pub struct ScanFrame<'a> {
    pub(crate) memory: &'a ScanMemory<'a>,
    pub(crate) background: u16,
    /// An anti-aliased frame's pending pixels, read out in its gaps.
    pub(crate) gaps: Gaps<'a>,
    pub(crate) stats: crate::stats::FrameStats,
}

impl<'a> ScanFrame<'a> {
    /// Frame width.
    pub fn width(&self) -> u32 {
        self.memory.width()
    }

    /// Frame height.
    pub fn height(&self) -> u32 {
        self.memory.height()
    }

    /// What the walk did.
    pub fn stats(&self) -> crate::stats::FrameStats {
        self.stats
    }

    /// The most scan-memory nodes the frame held.
    pub fn nodes_used(&self) -> usize {
        self.memory.nodes_used()
    }

    /// Every pixel of the frame in scan order, RGB565: what a display's one window
    /// (`0, 0` to `width - 1, height - 1`) takes, e.g. mipidsi's
    /// `set_pixels(0, 0, w - 1, h - 1, frame.pixels().map(RawU16::new).map(Rgb565::from))`.
    pub fn pixels(&self) -> ScanPixels<'a> {
        self.memory.pixels(self.background, self.gaps)
    }

    /// Row `y` into `row` (its first `width` pixels), RGB565: for a row buffer sent by DMA
    /// while the next row is filled. Nothing for a row outside the frame.
    pub fn row_into(&self, y: u32, row: &mut [u16]) {
        if y < self.height() {
            self.memory.row_into(y, self.background, self.gaps, row);
        }
    }
}

#[cfg(feature = "embedded-graphics")]
mod embedded {
    use embedded_graphics_core::draw_target::DrawTarget;
    use embedded_graphics_core::geometry::{Point, Size};
    use embedded_graphics_core::pixelcolor::raw::RawU16;
    use embedded_graphics_core::pixelcolor::Rgb565;
    use embedded_graphics_core::primitives::Rectangle;

    use super::ScanFrame;

    impl ScanFrame<'_> {
        /// The pixels as embedded-graphics colours.
        pub fn colours(&self) -> impl Iterator<Item = Rgb565> + '_ {
            self.pixels().map(|p| Rgb565::from(RawU16::new(p)))
        }

        /// Send the frame to `display` as one `fill_contiguous` over the whole screen: display
        /// drivers (mipidsi among them) turn it into one address window and one run of
        /// pixels, in scan order.
        ///
        /// # Errors
        /// The display's.
        pub fn draw_to<D: DrawTarget<Color = Rgb565>>(
            &self,
            display: &mut D,
        ) -> Result<(), D::Error> {
            let area = Rectangle::new(Point::zero(), Size::new(self.width(), self.height()));
            display.fill_contiguous(&area, self.colours())
        }
    }
}
