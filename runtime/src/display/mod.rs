//! Display: where spans land. The fill produces spans ([`SpanSink`], in [`Colour`]); the
//! framebuffers, a display or a test's mock consume them.
//!
//! [`Framebuffer`] writes into a caller's slice in one of three pixel formats ([`Gray8`],
//! [`Rgb565`], [`Xrgb8888`]); with the `embedded-graphics` feature, `DrawTargetSink` forwards
//! spans to any `embedded_graphics_core` draw target. The crate's own tests draw into a mock
//! that checks and prints what a fill drew (`testing::MockTarget`, built only for them).
//!
//! A smoothly shaded span comes with its row's [`RowShade`] ([`SpanSink::shaded_span`]); the
//! framebuffers store it pixel by pixel, RGB565 dithered ([`dither_rgb565`]) unless switched
//! off.
//!
//! Adapters between sinks, one a file: [`Nowhere`] drops every span, `Shifted` moves a band's
//! rows to frame rows. The adapters of the other concepts live with them: the span memory's
//! clipping sink in [`crate::coverage`], the anti-aliasing sink in [`crate::pending`].

mod dither;
mod framebuffer;
mod nowhere;
mod row_shade;
mod row_texture;
mod shifted;
mod span_paint;
#[cfg(test)]
pub(crate) mod testing;
mod transparent;

#[cfg(feature = "embedded-graphics")]
mod embedded;

pub use dither::{dither_rgb565, BAYER_4X4};
#[cfg(feature = "embedded-graphics")]
pub use embedded::{DisplayFormat, DrawTargetSink};
pub use framebuffer::{
    Framebuffer, FramebufferError, Gray8, Gray8Framebuffer, PixelFormat, Rgb565, Rgb565Framebuffer,
    Xrgb8888, Xrgb8888Framebuffer,
};
pub use nowhere::Nowhere;
pub use row_shade::{shaded, RowColours, RowShade, SHADE_FRACTION_BITS};
pub use row_texture::{
    modulate, rgb565_colour, Filter, Modulation, RowTexture, TexelColours, TexelWalk, RUN,
};
pub(crate) use shifted::Shifted;
pub use span_paint::{Paint, SpanPaint};
pub use transparent::{over, screen_door, screen_door_shows, Transparent};

/// An RGB888 colour. Id images use it too: `id + 1` as 24 bits, red the high byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Colour {
    /// Red.
    pub r: u8,
    /// Green.
    pub g: u8,
    /// Blue.
    pub b: u8,
}

impl Colour {
    /// A colour from its three channels.
    pub const fn new(r: u8, g: u8, b: u8) -> Self {
        Colour { r, g, b }
    }

    /// A grey level (of 256), as a colour.
    pub const fn grey(level: u8) -> Self {
        Colour::new(level, level, level)
    }

    /// Luma, ITU-R BT.601 in 8-bit fixed point (`(77 R + 150 G + 29 B + 128) / 256`), the same
    /// formula as embedded-graphics' RGB to grey conversion, so both paths agree.
    pub const fn luma(self) -> u8 {
        ((self.r as u32 * 77 + self.g as u32 * 150 + self.b as u32 * 29 + 128) >> 8) as u8
    }

    /// RGB565 (red in the high bits), each channel rounded to nearest like embedded-graphics.
    pub const fn to_rgb565(self) -> u16 {
        let r = (self.r as u32 * 31 + 127) / 255;
        let g = (self.g as u32 * 63 + 127) / 255;
        let b = (self.b as u32 * 31 + 127) / 255;
        ((r << 11) | (g << 5) | b) as u16
    }

    /// `0x00RRGGBB`.
    pub const fn to_xrgb8888(self) -> u32 {
        ((self.r as u32) << 16) | ((self.g as u32) << 8) | self.b as u32
    }
}

/// Receives horizontal runs of pixels: row `y`, columns `x_start .. x_end` (exclusive end,
/// `x_start < x_end <= width`, `y < height`).
pub trait SpanSink {
    /// Paint one span.
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour);

    /// Whether every pixel must be written at most once (a display streamed span by span,
    /// where overdraw shows as flicker): the renderer then draws front to back or not at all
    /// ([`RenderError::NotFrontToBack`] before the first pixel, [`RenderError::SpanMemoryFull`]
    /// where the span memory runs out, instead of finishing the frame back to front).
    /// `false` unless a sink says otherwise (`DrawTargetSink`, with `embedded-graphics`, says
    /// `true`).
    ///
    /// [`RenderError::NotFrontToBack`]: crate::error::RenderError::NotFrontToBack
    /// [`RenderError::SpanMemoryFull`]: crate::error::RenderError::SpanMemoryFull
    fn write_once(&self) -> bool {
        false
    }

    /// Paint one span of a smoothly shaded polygon: pixel `x` takes
    /// [`shade.at(x)`](RowShade::at), `shade` being its row's whole (a piece of a span takes
    /// the span's). By default each run of pixels of one colour goes to [`Self::span`], so
    /// every sink draws shaded spans; a sink that stores pixels overrides it with a direct
    /// loop (the framebuffers do).
    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        shade.runs(x_start, x_end, |a, b, colour| self.span(y, a, b, colour));
    }

    /// Paint one span of a textured polygon: pixel `x` takes
    /// [`texture.at(x)`](RowTexture::at), `texture` being its row's whole. By default each
    /// run of pixels of one colour goes to [`Self::span`]; the framebuffers override it with
    /// a direct loop.
    fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture<'_>) {
        texture.runs(x_start, x_end, |a, b, colour| self.span(y, a, b, colour));
    }

    /// Paint one span of a transparent polygon, back to front: `colour` at `opacity` (of 255)
    /// over what the pixels show. By default the sink cannot read its pixels, so it draws
    /// the polygon's [`screen_door`] in `colour`; the framebuffers override it with the exact
    /// blend ([`over`]).
    fn transparent_span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour, opacity: u8) {
        screen_door(y, x_start, x_end, opacity, |a, b| {
            self.span(y, a, b, colour)
        });
    }
}

impl<S: SpanSink + ?Sized> SpanSink for &mut S {
    #[inline]
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        (**self).span(y, x_start, x_end, colour);
    }

    #[inline]
    fn write_once(&self) -> bool {
        (**self).write_once()
    }

    #[inline]
    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        (**self).shaded_span(y, x_start, x_end, shade);
    }

    #[inline]
    fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture<'_>) {
        (**self).textured_span(y, x_start, x_end, texture);
    }

    #[inline]
    fn transparent_span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour, opacity: u8) {
        (**self).transparent_span(y, x_start, x_end, colour, opacity);
    }
}

#[cfg(test)]
mod tests {
    use super::testing::MockTarget;
    use super::*;

    #[test]
    fn encodings() {
        let white = Colour::new(255, 255, 255);
        let black = Colour::default();
        assert_eq!((white.luma(), black.luma()), (255, 0));
        assert_eq!(Colour::grey(100).luma(), 100);
        // Green weighs most, blue least.
        assert_eq!(Colour::new(255, 0, 0).luma(), 77);
        assert_eq!(Colour::new(0, 255, 0).luma(), 149);
        assert_eq!(Colour::new(0, 0, 255).luma(), 29);
        assert_eq!(white.to_rgb565(), 0xffff);
        assert_eq!(black.to_rgb565(), 0);
        assert_eq!(Colour::new(255, 0, 0).to_rgb565(), 0xf800);
        assert_eq!(Colour::new(0, 255, 0).to_rgb565(), 0x07e0);
        assert_eq!(Colour::new(0, 0, 255).to_rgb565(), 0x001f);
        // Rounded, not truncated: 4/255*31 = 0.49 -> 0, 5/255*31 = 0.61 -> 1.
        assert_eq!(Colour::new(0, 0, 4).to_rgb565(), 0);
        assert_eq!(Colour::new(0, 0, 5).to_rgb565(), 1);
        assert_eq!(Colour::new(0x12, 0x34, 0x56).to_xrgb8888(), 0x0012_3456);
    }

    #[test]
    fn the_default_shaded_span_sends_runs_of_one_colour() {
        let f = SHADE_FRACTION_BITS;
        // The intensity climbs a level every four pixels.
        let shade = RowShade {
            base: (10 << f) + (1 << (f - 3)),
            step: 1 << (f - 2),
            colour: Colour::new(255, 30, 128),
        };
        let mut mock = MockTarget::<16, 2>::new();
        mock.shaded_span(1, 3, 16, &shade);
        mock.shaded_span(0, 5, 5, &shade);
        for x in 0..16 {
            assert_eq!(mock.get(x, 1), (x >= 3).then(|| shade.at(x as u32)), "{x}");
            assert!(!mock.written(x, 0));
        }
        // One span a run of one colour: intensity 11 from 3, 12 from 6, 13 from 10, 14 from 14.
        assert_eq!(mock.spans(), 4);
        assert_eq!(mock.get(9, 1), Some(shaded(Colour::new(255, 30, 128), 12)));
        // `at` and the colours iterator agree, far along a row too.
        let mut colours = shade.colours(1000);
        assert!((1000..1100).all(|x| colours.next() == Some(shade.at(x))));
    }

    #[test]
    fn shifted_forwards_shaded_spans() {
        let shade = RowShade {
            base: 0,
            step: 9 << SHADE_FRACTION_BITS,
            colour: Colour::new(255, 100, 30),
        };
        let mut buf = [0u16; 8 * 6];
        let mut fb = Rgb565Framebuffer::new(&mut buf, 8, 6).unwrap();
        Shifted {
            sink: &mut fb,
            by: 4,
        }
        .shaded_span(1, 0, 8, &shade);
        // On frame row 5, dithered there: the framebuffer's own loop.
        for x in 0..8 {
            assert_eq!(fb.pixel(x, 5), Some(dither_rgb565(x, 5, shade.at(x))));
        }
        assert!((0..8).all(|x| fb.pixel(x, 1) == Some(0)));
    }
}
