//! [`Shifted`]: a sink whose rows lie a fixed count below the rows it is given. The span
//! memory of a band counts its rows from the band's first; what it forwards goes back to
//! frame rows through this adapter, as embedded-graphics' `Translated` moves a draw target.

use super::{Colour, RowShade, RowTexture, SpanSink};

/// Forwards every span `by` rows down: from a band's rows back to frame rows.
#[derive(Debug)]
pub(crate) struct Shifted<'s, S: SpanSink + ?Sized> {
    /// The sink in frame rows.
    pub(crate) sink: &'s mut S,
    /// The frame row of row 0.
    pub(crate) by: u32,
}

impl<S: SpanSink + ?Sized> SpanSink for Shifted<'_, S> {
    #[inline]
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        self.sink
            .span(y.wrapping_add(self.by), x_start, x_end, colour);
    }

    /// The same shade on the frame row: it depends on the column only, and a frame's dither
    /// on frame rows.
    #[inline]
    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        self.sink
            .shaded_span(y.wrapping_add(self.by), x_start, x_end, shade);
    }

    /// The same texture row on the frame row: it depends on the column only.
    #[inline]
    fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture<'_>) {
        self.sink
            .textured_span(y.wrapping_add(self.by), x_start, x_end, texture);
    }

    /// The same blend on the frame row.
    #[inline]
    fn transparent_span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour, opacity: u8) {
        self.sink
            .transparent_span(y.wrapping_add(self.by), x_start, x_end, colour, opacity);
    }
}
