//! [`Antialiased`]: the sink an anti-aliased polygon's fill draws into, wrapping the frame's
//! real sink as tiny-skia's `SuperBlitter` wraps its blitter. It gathers the polygon's spans
//! on the sample grid into pixel rows, adds each row to the pending pixels and sends the runs
//! of pixels that row finishes through the span memory (or scan memory) to the sink; at the
//! end of a frame [`drain`] gives the pixels still pending their background. The painter
//! only fills: every step of an anti-aliased span after the fill is here.

use super::{Pending, SampleColour};
use crate::coverage::{Coverage, CoverageSink};
use crate::display::{Colour, Shifted, SpanSink};
use crate::fill::gradient::Gradient;
use crate::fill::samples::{RowExtent, RowSpans, SampleSink, SAMPLE_ROWS};
use crate::fill::texture::TextureMap;

/// An anti-aliased polygon's route from the fill to `sink`: its colour (or a smooth polygon's
/// gradient on the sample grid), the pending pixels, the band's coverage (its row 0 being
/// frame row `first_row`) and the pixels sent.
pub(crate) struct Antialiased<'c, 'p, 'm, 't, S: SpanSink + ?Sized, const SUB: u32> {
    pub(crate) pending: &'c mut Pending<'p>,
    pub(crate) colour: SampleColour,
    /// A smooth polygon's gradient over the sample grid: each pixel takes its centre
    /// sample's colour.
    pub(crate) gradient: Option<Gradient<SUB>>,
    /// A textured polygon's map over the pixel grid: each pixel takes its centre's texel.
    pub(crate) texture: Option<TextureMap<'t, SUB>>,
    pub(crate) coverage: &'c mut Coverage<'m>,
    pub(crate) sink: &'c mut S,
    pub(crate) first_row: u32,
    pub(crate) pixels: u64,
}

impl<S: SpanSink + ?Sized, const SUB: u32> Antialiased<'_, '_, '_, '_, S, SUB> {
    /// Gather a span of sample row `y` (the band starts on a pixel row, so a sample row keeps
    /// its place in it); a span of the next pixel row first adds the gathered one.
    #[inline(never)]
    fn sample_span(&mut self, y: u32, x_start: u32, x_end: u32) {
        let local = y.wrapping_sub(self.first_row * SAMPLE_ROWS);
        if self.pending.gather(local, x_start, x_end).is_err() {
            self.add_gathered();
            let _ = self.pending.gather(local, x_start, x_end);
        }
    }

    /// Add the gathered row to the pending pixels, sending the runs of pixels it finishes.
    fn add_gathered(&mut self) {
        let Some(y) = self.pending.gathered() else {
            return;
        };
        // The sample row through the pixel centres, in frame rows.
        let centre_row = (y + self.first_row) * SAMPLE_ROWS + SAMPLE_ROWS / 2;
        let shade = self.gradient.as_mut().map(|g| g.row(centre_row));
        let Some(mut add) = self.pending.begin_add(&self.colour, shade) else {
            return;
        };
        if let Some(map) = &self.texture {
            add.texture(|first, end| map.row(y + self.first_row, first, end));
        }
        let coverage = &mut *self.coverage;
        // (A test per pixel, as scan memory, whose rows are lists, answers it too.)
        while let Some((x0, x1, c)) = self
            .pending
            .next_run(&mut add, |x| coverage.covers_pixel(x, y))
        {
            let mut sink = Shifted {
                sink: &mut *self.sink,
                by: self.first_row,
            };
            self.pixels += coverage.span(y, x0, x1, &c, &mut sink);
        }
    }
}

impl<S: SpanSink + ?Sized, const SUB: u32> SpanSink for Antialiased<'_, '_, '_, '_, S, SUB> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, _: Colour) {
        self.sample_span(y, x_start, x_end);
    }
}

impl<S: SpanSink + ?Sized, const SUB: u32> SampleSink for Antialiased<'_, '_, '_, '_, S, SUB> {
    fn sample_rows(&mut self, y: u32, spans: &RowSpans, extent: &RowExtent) {
        self.pending
            .gather_row(y.wrapping_sub(self.first_row), spans, extent);
        self.add_gathered();
    }

    fn end(&mut self) {
        self.add_gathered();
    }
}

/// End an anti-aliased frame (or band) drawn into `sink` through `coverage` (its row 0 being
/// frame row `first_row`): every pixel still pending takes `background` for its uncovered
/// samples. Returns the pixels sent.
pub(crate) fn drain<S: SpanSink + ?Sized>(
    pending: &mut Pending<'_>,
    coverage: &mut Coverage<'_>,
    sink: &mut S,
    first_row: u32,
    background: Colour,
) -> u64 {
    let mut sink = Shifted {
        sink,
        by: first_row,
    };
    let mut through = CoverageSink {
        coverage,
        sink: &mut sink,
        pixels: 0,
    };
    pending.drain(background, &mut through);
    through.pixels
}
