//! The mock display: an embedded-graphics `DrawTarget<Color = Rgb565>` that counts the bytes
//! a frame would send to an ILI9341/ST7789 panel over SPI and keeps the pixels it received in
//! its panel memory (the panel's GRAM, which the runner compares with the host's pixels).
//!
//! Such a panel takes a write as an address window, CASET (1 command byte + 4 data bytes) for
//! the columns and RASET (1 + 4) for the rows, then RAMWR (1) and 2 bytes per pixel, for each
//! `fill_solid` or `fill_contiguous` call and for each pixel of `draw_iter`. The panel keeps
//! its window between writes, so the driver sends CASET only when the columns change and RASET
//! only when the rows do (a span on the same row as the last write needs no RASET): at most
//! 11 bytes of set-up per write. Storing the pixels is the stand-in for the transfer and is
//! timed with the frame, as the transfer would be.

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
    /// The panel's window (first and last column, first and last row), once set.
    window: Option<[u32; 4]>,
}

impl Panel {
    /// A `width x height` panel over `memory` (exactly its pixels).
    pub fn new(memory: &'static mut [u16], width: u32, height: u32) -> Panel {
        Panel {
            memory,
            width,
            height,
            bytes: 0,
            window: None,
        }
    }

    /// Forget the last frame: memory to [`UNWRITTEN`], byte count to 0.
    pub fn start_frame(&mut self) {
        self.memory.fill(UNWRITTEN);
        self.bytes = 0;
        self.window = None;
    }

    /// Bytes sent since [`Panel::start_frame`].
    pub fn bytes(&self) -> u64 {
        self.bytes
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

    /// Count a write of `area` (its pixels on the panel: `pixels`): the window commands that
    /// change it, RAMWR, the pixels.
    fn count(&mut self, area: &Rectangle, pixels: u64) {
        let (x, y) = (area.top_left.x as u32, area.top_left.y as u32);
        let (w, h) = (area.size.width.max(1), area.size.height.max(1));
        let window = [x, x + w - 1, y, y + h - 1];
        let last = self.window.replace(window);
        let columns = last.map(|l| [l[0], l[1]]) != Some([window[0], window[1]]);
        let rows = last.map(|l| [l[2], l[3]]) != Some([window[2], window[3]]);
        self.bytes += RAMWR_BYTES
            + if columns { CASET_BYTES } else { 0 }
            + if rows { RASET_BYTES } else { 0 }
            + PIXEL_BYTES * pixels;
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
            self.count(&Rectangle::new(p, Size::new(1, 1)), 1);
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
        self.count(area, (w * h) as u64);
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
        self.count(area, (w * h) as u64);
        let raw = colour.into_storage();
        let stride = self.width as usize;
        for row in 0..h {
            let at = first + row * stride;
            self.memory[at..at + w].fill(raw);
        }
        Ok(())
    }
}
