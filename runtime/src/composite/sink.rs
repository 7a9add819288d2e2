//! [`Composited`]: the sink a polygon's fill draws into in a front-to-back frame with
//! transparent surfaces, wrapping the span memory and the real sink: a transparent span
//! becomes runs of the composite memory, an opaque one is clipped by the span memory and
//! finishes the runs it meets on its way to the sink.

use super::Composite;
use crate::coverage::Coverage;
use crate::display::{
    screen_door_shows, Colour, Nowhere, RowShade, RowTexture, Shifted, SpanPaint, SpanSink,
};

/// A polygon's route from the fill to `sink` through `coverage` and `composite` (their row 0
/// being frame row `first_row`), counting the pixels sent.
pub(crate) struct Composited<'c, 'm, 'n, S: SpanSink + ?Sized> {
    pub(crate) composite: &'c mut Composite<'n>,
    pub(crate) coverage: &'c mut Coverage<'m>,
    pub(crate) sink: &'c mut S,
    pub(crate) first_row: u32,
    pub(crate) pixels: u64,
    /// The screen-door pass (`screen_door.rs`), of a frame `width` wide: the spans go through
    /// the screen door of the rows that fell back, each pixel once.
    pub(crate) door: Option<u32>,
}

/// The pieces the span memory forwards of an opaque span, on their way to the sink: each
/// finishes the runs it meets.
struct Finishing<'c, 'n, S: SpanSink + ?Sized> {
    composite: &'c mut Composite<'n>,
    sink: Shifted<'c, S>,
}

impl<S: SpanSink + ?Sized> SpanSink for Finishing<'_, '_, S> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        self.composite
            .finish(y, x_start, x_end, &colour, &mut self.sink);
    }

    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        self.composite
            .finish(y, x_start, x_end, shade, &mut self.sink);
    }

    fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture<'_>) {
        self.composite
            .finish(y, x_start, x_end, texture, &mut self.sink);
    }
}

/// Pieces painted into a coverage that keeps colours (scan memory), which clips them.
struct IntoScan<'c, 'm> {
    coverage: &'c mut Coverage<'m>,
    pixels: u64,
}

impl SpanSink for IntoScan<'_, '_> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        self.pixels += self.coverage.span(y, x_start, x_end, &colour, &mut Nowhere);
    }

    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        self.pixels += self.coverage.span(y, x_start, x_end, shade, &mut Nowhere);
    }

    fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture<'_>) {
        self.pixels += self.coverage.span(y, x_start, x_end, texture, &mut Nowhere);
    }
}

/// A finished run's pixels in scan memory: `colour` on `[x_start, x_end)` of row `y`.
pub(super) fn into_scan(
    coverage: &mut Coverage<'_>,
    y: u32,
    x_start: u32,
    x_end: u32,
    colour: Colour,
) {
    coverage.span(y, x_start, x_end, &colour, &mut Nowhere);
}

impl<S: SpanSink + ?Sized> Composited<'_, '_, '_, S> {
    fn opaque<P: SpanPaint>(&mut self, y: u32, x_start: u32, x_end: u32, paint: &P) {
        let local = y.wrapping_sub(self.first_row);
        if !self.composite.opaque_fits(local) {
            return;
        }
        if self.coverage.keeps_colours() {
            // Scan memory forwards nothing: the runs are finished into it first, and it clips
            // the rest of the span.
            let mut scan = IntoScan {
                coverage: &mut *self.coverage,
                pixels: 0,
            };
            self.composite
                .finish(local, x_start, x_end, paint, &mut scan);
            self.pixels = self.pixels.saturating_add(scan.pixels);
            return;
        }
        let sink = Shifted {
            sink: &mut *self.sink,
            by: self.first_row,
        };
        let n = if self.composite.has_runs(local) {
            let mut finishing = Finishing {
                composite: &mut *self.composite,
                sink,
            };
            self.coverage
                .span(local, x_start, x_end, paint, &mut finishing)
        } else {
            let mut sink = sink;
            self.coverage.span(local, x_start, x_end, paint, &mut sink)
        };
        self.pixels = self.pixels.saturating_add(n);
    }
}

impl<S: SpanSink + ?Sized> Composited<'_, '_, '_, S> {
    /// A span of the screen-door pass: `paint` where `shows`.
    fn door<P: SpanPaint>(
        &mut self,
        width: u32,
        (y, x_start, x_end): (u32, u32, u32),
        paint: &P,
        shows: impl Fn(u32) -> bool,
    ) {
        let at = (self.first_row, width);
        let (coverage, sink) = (&mut *self.coverage, &mut *self.sink);
        let n = (self.composite).through_door(coverage, sink, at, y, x_start, x_end, paint, shows);
        self.pixels = self.pixels.saturating_add(n);
    }
}

impl<S: SpanSink + ?Sized> SpanSink for Composited<'_, '_, '_, S> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        match self.door {
            Some(width) => self.door(width, (y, x_start, x_end), &colour, |_| true),
            None => self.opaque(y, x_start, x_end, &colour),
        }
    }

    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        match self.door {
            Some(width) => self.door(width, (y, x_start, x_end), shade, |_| true),
            None => self.opaque(y, x_start, x_end, shade),
        }
    }

    fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture<'_>) {
        match self.door {
            Some(width) => self.door(width, (y, x_start, x_end), texture, |_| true),
            None => self.opaque(y, x_start, x_end, texture),
        }
    }

    fn transparent_span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour, opacity: u8) {
        if let Some(width) = self.door {
            let shows = |x| screen_door_shows(x, y, opacity);
            return self.door(width, (y, x_start, x_end), &colour, shows);
        }
        let local = y.wrapping_sub(self.first_row);
        let coverage = &*self.coverage;
        let pieces = |piece: &mut dyn FnMut(u32, u32)| {
            coverage.uncovered(local, x_start, x_end, &mut *piece);
        };
        self.composite.add(local, pieces, colour, opacity);
    }
}
