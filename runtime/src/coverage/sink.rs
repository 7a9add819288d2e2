//! The sinks that route a fill's spans through a [`Coverage`]: [`CoverageSink`], the public
//! one, and [`Clipped`], the renderer's, which also moves a band's rows and counts. Both carry
//! flat, shaded and textured spans alike ([`SpanPaint`]).

use super::Coverage;
use crate::display::{Colour, RowShade, RowTexture, Shifted, SpanPaint, SpanSink, Transparent};

/// A [`SpanSink`] that paints through a [`Coverage`] into another sink, counting pixels.
#[derive(Debug)]
pub struct CoverageSink<'c, 'm, S: SpanSink + ?Sized> {
    /// The coverage spans are clipped against.
    pub coverage: &'c mut Coverage<'m>,
    /// The real sink.
    pub sink: &'c mut S,
    /// Pixels forwarded to `sink`.
    pub pixels: u64,
}

impl<S: SpanSink + ?Sized> SpanSink for CoverageSink<'_, '_, S> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        self.pixels += self.coverage.span(y, x_start, x_end, &colour, self.sink);
    }

    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        self.pixels += self.coverage.span(y, x_start, x_end, shade, self.sink);
    }

    fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture<'_>) {
        self.pixels += self.coverage.span(y, x_start, x_end, texture, self.sink);
    }

    fn transparent_span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour, opacity: u8) {
        let paint = Transparent { colour, opacity };
        self.pixels += self.coverage.span(y, x_start, x_end, &paint, self.sink);
    }
}

/// The sink a polygon's fill draws into, in frame rows: through the band's coverage when
/// there is one (its row 0 being frame row `first_row`), else straight to `sink`; counts the
/// pixels forwarded (with the `stats` feature).
pub(crate) struct Clipped<'c, 'm, S: SpanSink + ?Sized> {
    pub(crate) coverage: Option<&'c mut Coverage<'m>>,
    pub(crate) sink: &'c mut S,
    pub(crate) first_row: u32,
    pub(crate) pixels: u64,
}

impl<S: SpanSink + ?Sized> Clipped<'_, '_, S> {
    #[inline]
    fn route<P: SpanPaint>(&mut self, y: u32, x_start: u32, x_end: u32, paint: &P) {
        let n = match self.coverage.as_deref_mut() {
            Some(c) => {
                let mut sink = Shifted {
                    sink: &mut *self.sink,
                    by: self.first_row,
                };
                let local = y.wrapping_sub(self.first_row);
                c.span(local, x_start, x_end, paint, &mut sink)
            }
            None => {
                paint.paint(self.sink, y, x_start, x_end);
                u64::from(x_end.saturating_sub(x_start))
            }
        };
        if cfg!(feature = "stats") {
            self.pixels = self.pixels.saturating_add(n);
        }
    }
}

impl<S: SpanSink + ?Sized> SpanSink for Clipped<'_, '_, S> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        self.route(y, x_start, x_end, &colour);
    }

    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        self.route(y, x_start, x_end, shade);
    }

    fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture<'_>) {
        self.route(y, x_start, x_end, texture);
    }

    /// Back to front (the only order that routes a transparent span here): blended over what
    /// the sink shows.
    fn transparent_span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour, opacity: u8) {
        self.route(y, x_start, x_end, &Transparent { colour, opacity });
    }
}
