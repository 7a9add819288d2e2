//! [`SpanPaint`]: what a span is painted with, one colour or one row of a smooth shade or of a
//! texture, so
//! that the adapters between the fill and the sink (the span memory, a band's shift) forward
//! the pieces of either kind with one code path.

use super::{Colour, RowShade, RowTexture, SpanSink};

/// A [`SpanPaint`] by kind, for a store that keeps the kinds apart (scan memory).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Paint<'a> {
    /// One colour.
    Colour(Colour),
    /// A smooth shade's row.
    Shade(&'a RowShade),
    /// A textured polygon's row.
    Texture(&'a RowTexture<'a>),
}

/// What a span is painted with: a [`Colour`], or a [`RowShade`] (a piece of a span takes the
/// whole row's shade, so pieces cut by the span memory keep their pixels' colours).
pub trait SpanPaint {
    /// The paint by kind.
    fn kind(&self) -> Paint<'_>;

    /// Paint `x_start .. x_end` of row `y` into `sink`: [`SpanSink::span`] or
    /// [`SpanSink::shaded_span`].
    fn paint<S: SpanSink + ?Sized>(&self, sink: &mut S, y: u32, x_start: u32, x_end: u32);

    /// Each run of pixels of one colour in `x_start .. x_end`, left to right, as
    /// `run(start, end, colour)`: for a store that keeps one colour an interval.
    fn runs(&self, x_start: u32, x_end: u32, run: impl FnMut(u32, u32, Colour));
}

impl SpanPaint for Colour {
    #[inline]
    fn kind(&self) -> Paint<'_> {
        Paint::Colour(*self)
    }

    #[inline]
    fn paint<S: SpanSink + ?Sized>(&self, sink: &mut S, y: u32, x_start: u32, x_end: u32) {
        sink.span(y, x_start, x_end, *self);
    }

    #[inline]
    fn runs(&self, x_start: u32, x_end: u32, mut run: impl FnMut(u32, u32, Colour)) {
        if x_start < x_end {
            run(x_start, x_end, *self);
        }
    }
}

impl SpanPaint for RowShade {
    #[inline]
    fn kind(&self) -> Paint<'_> {
        Paint::Shade(self)
    }

    #[inline]
    fn paint<S: SpanSink + ?Sized>(&self, sink: &mut S, y: u32, x_start: u32, x_end: u32) {
        sink.shaded_span(y, x_start, x_end, self);
    }

    fn runs(&self, x_start: u32, x_end: u32, run: impl FnMut(u32, u32, Colour)) {
        runs_of(self.colours(x_start), x_start, x_end, run);
    }
}

impl SpanPaint for RowTexture<'_> {
    #[inline]
    fn kind(&self) -> Paint<'_> {
        Paint::Texture(self)
    }

    #[inline]
    fn paint<S: SpanSink + ?Sized>(&self, sink: &mut S, y: u32, x_start: u32, x_end: u32) {
        sink.textured_span(y, x_start, x_end, self);
    }

    fn runs(&self, x_start: u32, x_end: u32, run: impl FnMut(u32, u32, Colour)) {
        runs_of(self.colours(x_start), x_start, x_end, run);
    }
}

/// Each run of one colour of `colours` (pixels `x_start ..`) within `x_start .. x_end`.
fn runs_of(
    mut colours: impl Iterator<Item = Colour>,
    x_start: u32,
    x_end: u32,
    mut run: impl FnMut(u32, u32, Colour),
) {
    if x_start >= x_end {
        return;
    }
    let mut current = (x_start, colours.next().unwrap_or_default());
    for (x, colour) in (x_start + 1..x_end).zip(colours) {
        if colour != current.1 {
            run(current.0, x, current.1);
            current = (x, colour);
        }
    }
    run(current.0, x_end, current.1);
}
