//! Framebuffers over caller-owned slices: the runtime allocates nothing, so the caller hands
//! in the pixel memory (a display's buffer, a static array, a `Vec` on a host).

use core::fmt;
use core::marker::PhantomData;

use super::{Colour, SpanSink};

/// How a [`Colour`] is stored in one pixel of a [`Framebuffer`].
pub trait PixelFormat {
    /// One stored pixel.
    type Raw: Copy + fmt::Debug + PartialEq;
    /// The stored value of `colour` (computed once per span, not per pixel).
    fn encode(colour: Colour) -> Self::Raw;
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
}

/// 16-bit RGB565: [`Colour::to_rgb565`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Rgb565;

impl PixelFormat for Rgb565 {
    type Raw = u16;
    #[inline]
    fn encode(colour: Colour) -> u16 {
        colour.to_rgb565()
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

impl<P: PixelFormat> SpanSink for Framebuffer<'_, P> {
    /// One slice fill per span. A span that breaks the [`SpanSink`] contract is clipped to
    /// the image rather than allowed to panic or spill into the next row.
    #[inline]
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        let x_end = x_end.min(self.width);
        let Some(y) = y.checked_sub(self.first_row).filter(|&y| y < self.height) else {
            return;
        };
        if x_start >= x_end {
            return;
        }
        let row = y as usize * self.stride;
        // `new` checked the buffer holds every row: `get_mut` never fails, and cannot panic.
        if let Some(run) = self
            .buf
            .get_mut(row + x_start as usize..row + x_end as usize)
        {
            run.fill(P::encode(colour));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
