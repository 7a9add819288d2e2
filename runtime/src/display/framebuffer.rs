//! Framebuffers over caller-owned slices: the runtime allocates nothing, so the caller hands
//! in the pixel memory (a display's buffer, a static array, a `Vec` on a host).

use core::fmt;
use core::marker::PhantomData;

use super::dither::{dithered, row_thresholds};
use super::{over, rgb565_colour, Colour, RowShade, RowTexture, SpanSink};

/// How a [`Colour`] is stored in one pixel of a [`Framebuffer`].
pub trait PixelFormat {
    /// One stored pixel.
    type Raw: Copy + fmt::Debug + PartialEq;
    /// The stored value of `colour` (computed once per span, not per pixel).
    fn encode(colour: Colour) -> Self::Raw;

    /// The colour a stored pixel shows (what a transparent span is blended over).
    fn decode(raw: Self::Raw) -> Colour;

    /// Store a shaded span: `run[i]` is pixel `(x_start + i, y)` (`y` a frame row), of colour
    /// `shade.at(x_start + i)`; `dither` is the framebuffer's switch, for a format with fewer
    /// bits a channel than a [`Colour`]. By default each colour is [`Self::encode`]d, which is
    /// all a format of 8 bits a channel needs.
    #[inline]
    fn encode_shaded(run: &mut [Self::Raw], x_start: u32, y: u32, shade: &RowShade, dither: bool) {
        let _ = (y, dither);
        for (pixel, colour) in run.iter_mut().zip(shade.colours(x_start)) {
            *pixel = Self::encode(colour);
        }
    }

    /// Store a textured span: `run[i]` is pixel `(x_start + i, y)`, of colour
    /// `texture.at(x_start + i)`. By default each colour is [`Self::encode`]d.
    #[inline]
    fn encode_textured(run: &mut [Self::Raw], x_start: u32, texture: &RowTexture<'_>) {
        for (pixel, colour) in run.iter_mut().zip(texture.colours(x_start)) {
            *pixel = Self::encode(colour);
        }
    }
}

/// 256 grey levels, one byte per pixel: [`Colour::luma`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Gray8;

impl PixelFormat for Gray8 {
    type Raw = u8;
    #[inline]
    fn encode(colour: Colour) -> u8 {
        colour.luma()
    }

    #[inline]
    fn decode(raw: u8) -> Colour {
        Colour::grey(raw)
    }
}

/// 16-bit RGB565: [`Colour::to_rgb565`], and shaded spans [`dither_rgb565`] unless the
/// framebuffer's dithering is off ([`Framebuffer::set_dithering`]).
///
/// [`dither_rgb565`]: super::dither_rgb565
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Rgb565;

impl PixelFormat for Rgb565 {
    type Raw = u16;
    #[inline]
    fn encode(colour: Colour) -> u16 {
        colour.to_rgb565()
    }

    #[inline]
    fn decode(raw: u16) -> Colour {
        rgb565_colour(raw)
    }

    /// Texels unlit are stored as they are (the file's texels are RGB565 already), lit ones
    /// multiplied once a run of equal texels ([`RowTexture::rgb565_into`]).
    #[inline]
    fn encode_textured(run: &mut [u16], x_start: u32, texture: &RowTexture<'_>) {
        texture.rgb565_into(x_start, run);
    }

    #[inline]
    fn encode_shaded(run: &mut [u16], x_start: u32, y: u32, shade: &RowShade, dither: bool) {
        let colours = run.iter_mut().zip(shade.colours(x_start));
        if dither {
            let thresholds = row_thresholds(y);
            for (x, (pixel, colour)) in (x_start..).zip(colours) {
                *pixel = dithered(colour, thresholds[(x & 3) as usize]);
            }
        } else {
            for (pixel, colour) in colours {
                *pixel = colour.to_rgb565();
            }
        }
    }
}

/// 32-bit `0x00RRGGBB`: [`Colour::to_xrgb8888`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Xrgb8888;

impl PixelFormat for Xrgb8888 {
    type Raw = u32;
    #[inline]
    fn encode(colour: Colour) -> u32 {
        colour.to_xrgb8888()
    }

    #[inline]
    fn decode(raw: u32) -> Colour {
        Colour::new((raw >> 16) as u8, (raw >> 8) as u8, raw as u8)
    }
}

/// Why a slice cannot back a framebuffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FramebufferError {
    /// The slice holds fewer pixels than `stride * (height - 1) + width`.
    BufferTooSmall {
        /// Pixels needed.
        needed: usize,
        /// Pixels in the slice.
        len: usize,
    },
    /// The row stride is shorter than a row.
    StrideTooSmall {
        /// The stride given, in pixels.
        stride: usize,
        /// The width.
        width: u32,
    },
    /// `stride * height` does not fit a `usize`.
    TooLarge,
}

impl fmt::Display for FramebufferError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            FramebufferError::BufferTooSmall { needed, len } => write!(
                f,
                "framebuffer slice holds {len} pixels, the image needs {needed}"
            ),
            FramebufferError::StrideTooSmall { stride, width } => {
                write!(f, "row stride {stride} is shorter than the width {width}")
            }
            FramebufferError::TooLarge => write!(f, "framebuffer size overflows usize"),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for FramebufferError {}

/// A `width x height` image in a caller's slice, row `y` starting at `y * stride`; or a band
/// of a larger frame's rows ([`Framebuffer::band`]).
#[derive(Debug)]
pub struct Framebuffer<'a, P: PixelFormat> {
    buf: &'a mut [P::Raw],
    width: u32,
    height: u32,
    stride: usize,
    /// The frame row stored first: spans and [`Framebuffer::pixel`] use frame rows.
    first_row: u32,
    /// Whether shaded spans are dithered where the format drops bits (only RGB565 does, and
    /// only its framebuffer can turn it off: [`Framebuffer::set_dithering`]).
    dither: bool,
    format: PhantomData<P>,
}

/// One byte of grey per pixel.
pub type Gray8Framebuffer<'a> = Framebuffer<'a, Gray8>;
/// One `u16` RGB565 per pixel.
pub type Rgb565Framebuffer<'a> = Framebuffer<'a, Rgb565>;
/// One `u32` `0x00RRGGBB` per pixel.
pub type Xrgb8888Framebuffer<'a> = Framebuffer<'a, Xrgb8888>;

impl<'a, P: PixelFormat> Framebuffer<'a, P> {
    /// A framebuffer whose rows are packed (`stride = width`).
    ///
    /// # Errors
    /// [`FramebufferError`] if `buf` is too small.
    pub fn new(buf: &'a mut [P::Raw], width: u32, height: u32) -> Result<Self, FramebufferError> {
        Self::with_stride(buf, width, height, width as usize)
    }

    /// A framebuffer whose rows are `stride` pixels apart (padding is never written).
    ///
    /// # Errors
    /// [`FramebufferError`] if `stride < width` or `buf` is too small.
    pub fn with_stride(
        buf: &'a mut [P::Raw],
        width: u32,
        height: u32,
        stride: usize,
    ) -> Result<Self, FramebufferError> {
        if stride < width as usize {
            return Err(FramebufferError::StrideTooSmall { stride, width });
        }
        let needed = match height {
            0 => 0,
            h => stride
                .checked_mul(h as usize - 1)
                .and_then(|n| n.checked_add(width as usize))
                .ok_or(FramebufferError::TooLarge)?,
        };
        if buf.len() < needed {
            return Err(FramebufferError::BufferTooSmall {
                needed,
                len: buf.len(),
            });
        }
        Ok(Framebuffer {
            buf,
            width,
            height,
            stride,
            first_row: 0,
            dither: true,
            format: PhantomData,
        })
    }

    /// A band: rows `rows` of a `width`-pixel-wide frame, packed. Spans and
    /// [`Framebuffer::pixel`] take frame rows, so a renderer drawing those rows
    /// ([`crate::render::Renderer::draw_rows`]) draws into it unchanged, and a frame needs one
    /// band of memory instead of a whole image.
    ///
    /// # Errors
    /// [`FramebufferError`] if `buf` is too small.
    pub fn band(
        buf: &'a mut [P::Raw],
        width: u32,
        rows: core::ops::Range<u32>,
    ) -> Result<Self, FramebufferError> {
        let mut band = Self::new(buf, width, rows.end.saturating_sub(rows.start))?;
        band.first_row = rows.start;
        Ok(band)
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels (rows held).
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The frame rows held: `0..height`, or a band's rows.
    pub fn rows(&self) -> core::ops::Range<u32> {
        self.first_row..self.first_row.saturating_add(self.height)
    }

    /// Distance between rows, in pixels.
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// Paint every pixel of the image (not the stride padding).
    pub fn clear(&mut self, colour: Colour) {
        let raw = P::encode(colour);
        let w = self.width as usize;
        if self.stride == w {
            let n = w * self.height as usize;
            self.buf[..n].fill(raw);
        } else {
            for y in 0..self.height as usize {
                let row = y * self.stride;
                self.buf[row..row + w].fill(raw);
            }
        }
    }

    /// The stored value of pixel `(x, y)` (`y` a frame row), `None` outside the rows held.
    pub fn pixel(&self, x: u32, y: u32) -> Option<P::Raw> {
        let y = y.checked_sub(self.first_row).filter(|&y| y < self.height)?;
        if x < self.width {
            self.buf.get(y as usize * self.stride + x as usize).copied()
        } else {
            None
        }
    }

    /// The whole backing slice.
    pub fn as_slice(&self) -> &[P::Raw] {
        self.buf
    }
}

impl Framebuffer<'_, Rgb565> {
    /// Whether shaded spans are stored dithered ([`dither_rgb565`]) or rounded
    /// ([`Colour::to_rgb565`]). On by default: 5 and 6 bits a channel show a smooth gradient
    /// as visible bands, which the dither turns into a fine pattern of the right mean. Flat
    /// spans are one colour and always stored rounded, so turning it on changes nothing
    /// drawn without shading.
    ///
    /// [`dither_rgb565`]: super::dither_rgb565
    pub fn set_dithering(&mut self, on: bool) {
        self.dither = on;
    }

    /// Whether shaded spans are dithered ([`Self::set_dithering`]).
    pub fn dithering(&self) -> bool {
        self.dither
    }
}

impl<P: PixelFormat> Framebuffer<'_, P> {
    /// The pixels `x_start .. x_end` of frame row `y` and the row within the buffer, clipped
    /// to the image: a span that breaks the [`SpanSink`] contract is clipped rather than
    /// allowed to panic or spill into the next row.
    #[inline]
    fn run(&mut self, y: u32, x_start: u32, x_end: u32) -> Option<&mut [P::Raw]> {
        let x_end = x_end.min(self.width);
        let y = y.checked_sub(self.first_row).filter(|&y| y < self.height)?;
        if x_start >= x_end {
            return None;
        }
        let row = y as usize * self.stride;
        // `new` checked the buffer holds every row: `get_mut` never fails, and cannot panic.
        self.buf
            .get_mut(row + x_start as usize..row + x_end as usize)
    }
}

impl<P: PixelFormat> SpanSink for Framebuffer<'_, P> {
    /// One slice fill per span. A span that breaks the [`SpanSink`] contract is clipped to
    /// the image rather than allowed to panic or spill into the next row.
    #[inline]
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        if let Some(run) = self.run(y, x_start, x_end) {
            run.fill(P::encode(colour));
        }
    }

    /// One loop over the span's pixels, each encoded by the format
    /// ([`PixelFormat::encode_shaded`]: RGB565 dithers unless switched off), clipped as
    /// [`Self::span`] is.
    #[inline]
    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        let dither = self.dither;
        if let Some(run) = self.run(y, x_start, x_end) {
            P::encode_shaded(run, x_start, y, shade, dither);
        }
    }

    /// A textured span stored pixel by pixel ([`PixelFormat::encode_textured`]), clipped as
    /// [`Self::span`] is.
    #[inline]
    fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture<'_>) {
        if let Some(run) = self.run(y, x_start, x_end) {
            P::encode_textured(run, x_start, texture);
        }
    }

    /// `colour` at `opacity` blended [`over`] each pixel, exactly (back to front), clipped
    /// as [`Self::span`] is.
    fn transparent_span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour, opacity: u8) {
        if let Some(run) = self.run(y, x_start, x_end) {
            let mut last = None;
            for pixel in run {
                // (Runs of one colour below blend once.)
                let below = *pixel;
                let blended = match last {
                    Some((b, v)) if b == below => v,
                    _ => P::encode(over(colour, opacity, P::decode(below))),
                };
                last = Some((below, blended));
                *pixel = blended;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::display::{dither_rgb565, SHADE_FRACTION_BITS};

    #[test]
    fn new_checks_the_slice() {
        let mut buf = [0u8; 12];
        assert!(Gray8Framebuffer::new(&mut buf, 4, 3).is_ok());
        assert_eq!(
            Gray8Framebuffer::new(&mut buf, 4, 4).unwrap_err(),
            FramebufferError::BufferTooSmall {
                needed: 16,
                len: 12
            }
        );
        // The last row needs no padding: 5 * 2 + 2 = 12.
        assert!(Gray8Framebuffer::with_stride(&mut buf, 2, 3, 5).is_ok());
        assert_eq!(
            Gray8Framebuffer::with_stride(&mut buf, 4, 1, 3).unwrap_err(),
            FramebufferError::StrideTooSmall {
                stride: 3,
                width: 4
            }
        );
        assert_eq!(
            Gray8Framebuffer::with_stride(&mut buf, 4, u32::MAX, usize::MAX).unwrap_err(),
            FramebufferError::TooLarge
        );
        assert!(Gray8Framebuffer::new(&mut [], 0, 0).is_ok());
    }

    #[test]
    fn spans_clear_and_getter() {
        let mut buf = [0xaaaa_u16; 4 * 6];
        let mut fb = Rgb565Framebuffer::with_stride(&mut buf, 4, 4, 6).unwrap();
        fb.clear(Colour::new(0, 0, 255));
        fb.span(1, 1, 3, Colour::new(255, 0, 0));
        fb.span(3, 0, 4, Colour::new(0, 255, 0));
        // Contract breaches are clipped, not panics.
        fb.span(2, 3, 99, Colour::new(255, 255, 255));
        fb.span(9, 0, 1, Colour::new(255, 255, 255));
        fb.span(0, 2, 2, Colour::new(255, 255, 255));
        assert_eq!(fb.pixel(0, 1), Some(0x001f));
        assert_eq!(fb.pixel(1, 1), Some(0xf800));
        assert_eq!(fb.pixel(2, 1), Some(0xf800));
        assert_eq!(fb.pixel(3, 1), Some(0x001f));
        assert_eq!(fb.pixel(3, 2), Some(0xffff));
        assert_eq!(fb.pixel(2, 0), Some(0x001f));
        assert!((0..4).all(|x| fb.pixel(x, 3) == Some(0x07e0)));
        assert_eq!(fb.pixel(4, 0), None);
        assert_eq!(fb.pixel(0, 4), None);
        // The stride padding (columns 4 and 5) is untouched.
        let raw = fb.as_slice();
        for y in 0..3 {
            assert_eq!(&raw[y * 6 + 4..y * 6 + 6], &[0xaaaa, 0xaaaa]);
        }
    }

    #[test]
    fn a_band_takes_frame_rows() {
        let mut buf = [0u16; 3 * 2];
        let mut band = Rgb565Framebuffer::band(&mut buf, 3, 4..6).unwrap();
        assert_eq!((band.rows(), band.height()), (4..6, 2));
        band.span(4, 0, 2, Colour::new(255, 0, 0));
        band.span(5, 1, 3, Colour::new(0, 0, 255));
        // Rows outside the band are not the band's: ignored, not wrapped or panicking.
        band.span(3, 0, 3, Colour::new(255, 255, 255));
        band.span(6, 0, 3, Colour::new(255, 255, 255));
        assert_eq!(
            (band.pixel(0, 4), band.pixel(2, 4)),
            (Some(0xf800), Some(0))
        );
        assert_eq!(
            (band.pixel(0, 5), band.pixel(2, 5)),
            (Some(0), Some(0x001f))
        );
        assert_eq!((band.pixel(0, 3), band.pixel(0, 6)), (None, None));
        assert_eq!(buf, [0xf800, 0xf800, 0, 0, 0x001f, 0x001f]);
        assert_eq!(
            Rgb565Framebuffer::band(&mut [0; 5], 3, 4..6).unwrap_err(),
            FramebufferError::BufferTooSmall { needed: 6, len: 5 }
        );
    }

    #[test]
    fn gray_and_xrgb_store_their_encoding() {
        let c = Colour::new(10, 200, 30);
        let mut g = [0u8; 4];
        let mut fb = Gray8Framebuffer::new(&mut g, 2, 2).unwrap();
        fb.span(1, 0, 2, c);
        assert_eq!(g, [0, 0, c.luma(), c.luma()]);
        let mut x = [0u32; 4];
        let mut fb = Xrgb8888Framebuffer::new(&mut x, 2, 2).unwrap();
        fb.clear(c);
        assert_eq!(x, [0x000a_c81e; 4]);
    }

    /// A sink of the default shaded span: only `span` is its own.
    struct ByPixel<'f, 'a, P: PixelFormat>(&'f mut Framebuffer<'a, P>);

    impl<P: PixelFormat> SpanSink for ByPixel<'_, '_, P> {
        fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
            self.0.span(y, x_start, x_end, colour);
        }
    }

    /// Shades with every feature: steep and gentle channels, a base far outside the range
    /// (wrapping), values past `0..=255` (clamping), and a flat one.
    fn shades() -> [RowShade; 4] {
        let f = SHADE_FRACTION_BITS;
        [
            RowShade {
                base: 3 << f,
                step: (7 << f) / 5,
                colour: Colour::new(255, 120, 9),
            },
            RowShade {
                base: i32::MAX - 5,
                step: 1 << (f - 4),
                colour: Colour::new(40, 255, 200),
            },
            RowShade {
                base: (1000i32 << f).wrapping_mul(9),
                step: -(3 << f),
                colour: Colour::grey(255),
            },
            RowShade::flat(Colour::new(9, 99, 199)),
        ]
    }

    /// Spans of each shade on rows 0..6, clipped at the right edge, into a `7 x 6` image.
    fn draw<S: SpanSink>(sink: &mut S) {
        for (y, shade) in (0..6).zip(shades().iter().cycle()) {
            sink.shaded_span(y, y % 3, 5 + y % 3, shade);
        }
        // A span past the image and one off it: clipped, not panicking.
        sink.shaded_span(5, 4, 99, &shades()[0]);
        sink.shaded_span(7, 0, 3, &shades()[1]);
        sink.shaded_span(2, 4, 4, &shades()[1]);
    }

    /// The framebuffer's loop against the default path, pixel for pixel.
    fn same_as_by_pixel<P: PixelFormat>(blank: P::Raw)
    where
        P::Raw: Default,
    {
        let mut direct = [blank; 7 * 6];
        let mut by_pixel = [blank; 7 * 6];
        draw(&mut Framebuffer::<P>::new(&mut direct, 7, 6).unwrap());
        draw(&mut ByPixel(
            &mut Framebuffer::<P>::new(&mut by_pixel, 7, 6).unwrap(),
        ));
        assert_eq!(direct, by_pixel);
        assert!(direct.iter().filter(|&&p| p != blank).count() > 20);
    }

    #[test]
    fn a_shaded_span_is_its_pixels_colours() {
        same_as_by_pixel::<Gray8>(0xaa);
        same_as_by_pixel::<Xrgb8888>(0xaaaa_aaaa);
        // RGB565 rounded, with the dither off.
        let mut direct = [0xaaaa_u16; 7 * 6];
        let mut by_pixel = [0xaaaa_u16; 7 * 6];
        let mut fb = Rgb565Framebuffer::new(&mut direct, 7, 6).unwrap();
        assert!(fb.dithering());
        fb.set_dithering(false);
        assert!(!fb.dithering());
        draw(&mut fb);
        draw(&mut ByPixel(
            &mut Rgb565Framebuffer::new(&mut by_pixel, 7, 6).unwrap(),
        ));
        assert_eq!(direct, by_pixel);
        // And each pixel is the shade's colour there.
        let shade = shades()[0];
        let fb = Rgb565Framebuffer::new(&mut direct, 7, 6).unwrap();
        for x in 0..5 {
            assert_eq!(fb.pixel(x, 0), Some(shade.at(x).to_rgb565()));
        }
        assert_eq!(fb.pixel(5, 0), Some(0xaaaa));
    }

    #[test]
    fn rgb565_dithers_shaded_spans() {
        let mut buf = [0xaaaa_u16; 7 * 6];
        let mut fb = Rgb565Framebuffer::new(&mut buf, 7, 6).unwrap();
        draw(&mut fb);
        // Through `&mut`: the framebuffer's own loop, not the default (which stores rounded
        // colours).
        draw(&mut &mut fb);
        let mut dithered = 0;
        for (y, shade) in (0..6).zip(shades().iter().cycle()) {
            let last = if y == 5 { 7 } else { 5 + y % 3 };
            for x in y % 3..last {
                // Row 5's second span, from x = 4, is the first shade's.
                let shade = if y == 5 && x >= 4 {
                    &shades()[0]
                } else {
                    shade
                };
                let colour = shade.at(x);
                assert_eq!(
                    fb.pixel(x, y),
                    Some(dither_rgb565(x, y, colour)),
                    "({x}, {y})"
                );
                dithered += usize::from(dither_rgb565(x, y, colour) != colour.to_rgb565());
            }
        }
        assert!(dithered > 5);
        // Flat spans are not dithered.
        let grey = Colour::grey(100);
        fb.span(0, 0, 4, grey);
        assert!((0..4).all(|x| fb.pixel(x, 0) == Some(grey.to_rgb565())));
        assert!((0..4).any(|x| dither_rgb565(x, 0, grey) != grey.to_rgb565()));
    }

    #[test]
    fn a_band_dithers_on_frame_rows() {
        let mut frame = [0u16; 7 * 6];
        draw(&mut Rgb565Framebuffer::new(&mut frame, 7, 6).unwrap());
        let mut band = [0u16; 7 * 3];
        draw(&mut Rgb565Framebuffer::band(&mut band, 7, 2..5).unwrap());
        assert_eq!(band[..], frame[2 * 7..5 * 7]);
    }
}
