//! The mock display: an embedded-graphics `DrawTarget<Color = Rgb565>` that counts the bytes
//! a frame would send to an ILI9341/ST7789 panel over SPI and keeps the pixels it received in
//! its panel memory (the panel's GRAM, which the runner compares with the host's pixels).
//!
//! Such a panel takes a write as an address window, CASET (1 command byte + 4 data bytes) for
//! the columns and RASET (1 + 4) for the rows, then RAMWR (1) and 2 bytes per pixel, for each
//! `fill_solid` or `fill_contiguous` call and for each pixel of `draw_iter`. The mock charges
//! the whole window set-up (11 bytes) on every write, as mipidsi 0.10 sends it (it does not
//! remember the panel's window), and counts the driver's separate writes: a window set-up and
//! a run of pixels per call (`display_writes`; each is its own chip-select cycle or DMA
//! transfer). Storing the pixels is the stand-in for the transfer and is timed with the frame,
//! as the transfer would be.

use core::convert::Infallible;

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{OriginDimensions, Size};
use embedded_graphics_core::pixelcolor::{IntoStorage, Rgb565};
use embedded_graphics_core::primitives::{PointsIter, Rectangle};
use embedded_graphics_core::Pixel;

/// Bytes of CASET (the window's columns): command and two 16-bit columns.
const CASET_BYTES: u64 = 5;
/// Bytes of RASET (the window's rows): command and two 16-bit rows.
const RASET_BYTES: u64 = 5;
/// Bytes of RAMWR (start writing at the window's first pixel).
const RAMWR_BYTES: u64 = 1;
/// Bytes per RGB565 pixel.
pub const PIXEL_BYTES: u64 = 2;
/// What the panel memory holds before each frame: a pixel the frame does not write keeps it,
/// and then differs from the host's pixel (unless the host's is this very colour).
pub const UNWRITTEN: u16 = 0xF81F;

/// The panel: its memory and the bytes sent to it this frame.
pub struct Panel {
    memory: &'static mut [u16],
    width: u32,
    height: u32,
    bytes: u64,
    /// Separate writes: window set-ups and pixel runs.
    writes: u64,
}

impl Panel {
    /// A `width x height` panel over `memory` (exactly its pixels).
    pub fn new(memory: &'static mut [u16], width: u32, height: u32) -> Panel {
        Panel {
            memory,
            width,
            height,
            bytes: 0,
            writes: 0,
        }
    }

    /// Forget the last frame: memory to [`UNWRITTEN`], byte count to 0.
    pub fn start_frame(&mut self) {
        self.memory.fill(UNWRITTEN);
        self.bytes = 0;
        self.writes = 0;
    }

    /// Bytes sent since [`Panel::start_frame`].
    pub fn bytes(&self) -> u64 {
        self.bytes
    }

    /// Separate writes since [`Panel::start_frame`]: a window set-up and a pixel run per call.
    pub fn writes(&self) -> u64 {
        self.writes
    }

    /// What the panel holds, row by row.
    pub fn pixels(&self) -> &[u16] {
        self.memory
    }

    /// The rows of `area` inside the panel, as `(first index, row length, rows)`; `None`
    /// when it misses the panel.
    fn clipped(&self, area: &Rectangle) -> Option<(usize, usize, usize)> {
        let screen = Rectangle::new(Default::default(), Size::new(self.width, self.height));
        let a = area.intersection(&screen);
        if a.size.width == 0 || a.size.height == 0 {
            return None;
        }
        let first = a.top_left.y as usize * self.width as usize + a.top_left.x as usize;
        Some((first, a.size.width as usize, a.size.height as usize))
    }

    /// Count a write of `pixels` pixels: the window set-up (CASET, RASET, RAMWR) and the
    /// pixels, two writes.
    fn count(&mut self, pixels: u64) {
        self.bytes += CASET_BYTES + RASET_BYTES + RAMWR_BYTES + PIXEL_BYTES * pixels;
        self.writes += 2;
    }
}

impl OriginDimensions for Panel {
    fn size(&self) -> Size {
        Size::new(self.width, self.height)
    }
}

impl DrawTarget for Panel {
    type Color = Rgb565;
    type Error = Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Pixel<Rgb565>>,
    {
        for Pixel(p, colour) in pixels {
            self.count(1);
            let (Ok(x), Ok(y)) = (u32::try_from(p.x), u32::try_from(p.y)) else {
                continue;
            };
            if x < self.width && y < self.height {
                self.memory[(y * self.width + x) as usize] = colour.into_storage();
            }
        }
        Ok(())
    }

    fn fill_contiguous<I>(&mut self, area: &Rectangle, colours: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Rgb565>,
    {
        let Some((first, w, h)) = self.clipped(area) else {
            return Ok(());
        };
        self.count((w * h) as u64);
        if (w, h) == (area.size.width as usize, area.size.height as usize) {
            // Wholly on the panel (the usual case): row by row, no per-pixel checks.
            let stride = self.width as usize;
            let mut colours = colours.into_iter();
            for row in 0..h {
                let at = first + row * stride;
                for (slot, c) in self.memory[at..at + w].iter_mut().zip(&mut colours) {
                    *slot = c.into_storage();
                }
            }
            return Ok(());
        }
        for (p, c) in area.points().zip(colours) {
            let (Ok(x), Ok(y)) = (u32::try_from(p.x), u32::try_from(p.y)) else {
                continue;
            };
            if x < self.width && y < self.height {
                self.memory[(y * self.width + x) as usize] = c.into_storage();
            }
        }
        Ok(())
    }

    fn fill_solid(&mut self, area: &Rectangle, colour: Rgb565) -> Result<(), Infallible> {
        let Some((first, w, h)) = self.clipped(area) else {
            return Ok(());
        };
        self.count((w * h) as u64);
        let raw = colour.into_storage();
        let stride = self.width as usize;
        for row in 0..h {
            let at = first + row * stride;
            self.memory[at..at + w].fill(raw);
        }
        Ok(())
    }
}
