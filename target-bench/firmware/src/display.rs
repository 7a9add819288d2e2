//! The mock display: an ILI9341/ST7789 panel on an SPI bus. It counts the bytes a frame sends
//! and the driver's separate writes, and keeps the pixels it received in its panel memory (the
//! panel's GRAM, which the runner compares with the host's pixels).
//!
//! Such a panel takes pixels into an address window: CASET (1 command byte + 4 data bytes)
//! for its columns, RASET (1 + 4) for its rows, RAMWR (1), then 2 bytes per pixel, filled row
//! by row. Every method hands its pixels over as a firmware engineer would:
//!
//! * a buffer of whole rows (a framebuffer, a band): [`Panel::write_rows`], one window and one
//!   run of pixels, a DMA transfer of the buffer (a slice copy here);
//! * rows made one at a time, top to bottom, in a row buffer (scan order, the scanline
//!   z-buffer): [`Panel::open_rows`], one window for the frame, then [`Panel::send`] per row,
//!   a DMA transfer of the row buffer each, the panel's write position running on from row to
//!   row (a window per row would add 11 bytes and a chip-select cycle a row for nothing);
//! * spans streamed as drawn: `fill_solid` and `fill_contiguous` of the
//!   [`DrawTarget`] (as mipidsi 0.10 implements it: a window each, and a window per pixel of
//!   `draw_iter`). The builds that draw smooth files stream through [`PanelSink`]: a flat span
//!   is the same `fill_solid`, a shaded span one window and one burst of its pixels, each
//!   computed as it is sent and dithered to RGB565 as [`dither_rgb565`] does (what the
//!   runtime's RGB565 framebuffer stores), not a window per run of one colour; the build
//!   with textures sends a textured span the same way, each pixel its texel (times the
//!   polygon's colour) in RGB565.
//!
//! Every window set-up is charged in full (11 bytes: mipidsi 0.10 does not remember the
//! panel's window). `display_writes` counts the driver's separate writes, each its own
//! chip-select cycle or DMA transfer: a window set-up is one, a run of pixels one (a buffer,
//! or one `fill_*` call, is 2). Storing the pixels stands in for the transfer and is timed
//! with the frame, as the transfer would be: a run is one slice copy, as a DMA moves a block.

use core::convert::Infallible;

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{OriginDimensions, Size};
use embedded_graphics_core::pixelcolor::{IntoStorage, Rgb565};
use embedded_graphics_core::primitives::{PointsIter, Rectangle};
use embedded_graphics_core::Pixel;
use peel_runtime::display::Rgb565Framebuffer;
#[cfg(all(feature = "textures", feature = "smooth", not(feature = "scan")))]
use peel_runtime::display::RowTexture;
#[cfg(all(feature = "smooth", not(feature = "scan")))]
use peel_runtime::display::{dither_rgb565, Colour, RowShade, SpanSink};

/// Bytes of CASET (the window's columns): command and two 16-bit columns.
const CASET_BYTES: u64 = 5;
/// Bytes of RASET (the window's rows): command and two 16-bit rows.
const RASET_BYTES: u64 = 5;
/// Bytes of RAMWR (start writing at the window's first pixel).
const RAMWR_BYTES: u64 = 1;
/// Bytes of a window set-up.
const WINDOW_BYTES: u64 = CASET_BYTES + RASET_BYTES + RAMWR_BYTES;
/// Bytes per RGB565 pixel.
pub const PIXEL_BYTES: u64 = 2;
/// What the panel memory holds before each frame: a pixel the frame does not write keeps it,
/// and then differs from the host's pixel (unless the host's is this very colour).
pub const UNWRITTEN: u16 = 0xF81F;

/// The panel: its memory, the bytes sent to it this frame and the open window.
pub struct Panel {
    memory: &'static mut [u16],
    width: u32,
    height: u32,
    bytes: u64,
    /// Separate writes: window set-ups and pixel runs.
    writes: u64,
    /// The window of [`Panel::open_rows`]: its next pixel and its end, in `memory`.
    next: usize,
    end: usize,
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
            next: 0,
            end: 0,
        }
    }

    /// Forget the last frame: memory to [`UNWRITTEN`], counts to 0, no window.
    pub fn start_frame(&mut self) {
        self.memory.fill(UNWRITTEN);
        self.bytes = 0;
        self.writes = 0;
        (self.next, self.end) = (0, 0);
    }

    /// Bytes sent since [`Panel::start_frame`].
    pub fn bytes(&self) -> u64 {
        self.bytes
    }

    /// Separate writes since [`Panel::start_frame`]: window set-ups and pixel runs.
    pub fn writes(&self) -> u64 {
        self.writes
    }

    /// What the panel holds, row by row.
    pub fn pixels(&self) -> &[u16] {
        self.memory
    }

    /// Set the address window to the whole rows `rows` (those on the panel): CASET, RASET
    /// and RAMWR, one write. [`Panel::send`] then fills it.
    #[inline(never)]
    pub fn open_rows(&mut self, rows: core::ops::Range<u32>) {
        self.bytes += WINDOW_BYTES;
        self.writes += 1;
        let w = self.width as usize;
        let row = |y: u32| (y.min(self.height) as usize) * w;
        (self.next, self.end) = (row(rows.start), row(rows.end).max(row(rows.start)));
    }

    /// One run of pixels into the open window from its next pixel on: a DMA transfer of a
    /// buffer, here one slice copy; 2 bytes a pixel, one write. Pixels past the window's end
    /// are sent but not stored (a panel would wrap to the window's start; the benchmark never
    /// sends them, and the runner's pixel check would see it). Never inlined, like
    /// [`Panel::open_rows`]: every method's transfer is the same code.
    #[inline(never)]
    pub fn send(&mut self, pixels: &[u16]) {
        self.bytes += PIXEL_BYTES * pixels.len() as u64;
        self.writes += 1;
        let n = pixels.len().min(self.end - self.next);
        if let (Some(to), Some(from)) = (
            self.memory.get_mut(self.next..self.next + n),
            pixels.get(..n),
        ) {
            to.copy_from_slice(from);
        }
        self.next += n;
    }

    /// A buffer of whole rows, the first of them frame row `first_row`: one window and one
    /// run, two writes.
    // (Not used by the builds that send rows one at a time.)
    #[cfg_attr(any(feature = "scan", feature = "scanline-zbuffer"), allow(dead_code))]
    pub fn write_rows(&mut self, first_row: u32, pixels: &[u16]) {
        let rows = pixels.len().div_ceil(self.width.max(1) as usize);
        let rows = u32::try_from(rows).unwrap_or(u32::MAX);
        self.open_rows(first_row..first_row.saturating_add(rows));
        self.send(pixels);
    }

    /// A framebuffer or a band at its frame rows, as [`Panel::write_rows`] sends it (its rows
    /// one run when packed, a run per row otherwise).
    // (Not used by the builds that send rows one at a time.)
    #[cfg_attr(any(feature = "scan", feature = "scanline-zbuffer"), allow(dead_code))]
    pub fn write_framebuffer(&mut self, framebuffer: &Rgb565Framebuffer<'_>) {
        let (w, rows) = (framebuffer.width() as usize, framebuffer.rows());
        let stride = framebuffer.stride();
        let n = rows.len() * w;
        let all = framebuffer.as_slice();
        if stride == w {
            // `Framebuffer::new` checked that the buffer holds every row.
            self.write_rows(rows.start, all.get(..n).unwrap_or(all));
            return;
        }
        self.open_rows(rows.clone());
        for row in all.chunks(stride.max(1)).take(rows.len()) {
            self.send(row.get(..w).unwrap_or(row));
        }
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

    /// The panel's pixels of row `y`, columns `x_start..x_end` clipped to it, counted as one
    /// window and one burst; `None` when nothing is left.
    #[cfg(all(feature = "smooth", not(feature = "scan")))]
    fn burst(&mut self, y: u32, x_start: u32, x_end: u32) -> Option<&mut [u16]> {
        let x_end = x_end.min(self.width);
        if y >= self.height || x_start >= x_end {
            return None;
        }
        let n = (x_end - x_start) as usize;
        self.count(n as u64);
        let at = (y * self.width + x_start) as usize;
        self.memory.get_mut(at..at + n)
    }

    /// One shaded span of row `y`, columns `x_start..x_end` (clipped to the panel): one window
    /// and one burst of its pixels, two writes, as a flat span's `fill_solid`. Pixel `x` is
    /// `shade.at(x)` dithered ([`dither_rgb565`]), computed as it is sent (a driver feeding
    /// the SPI FIFO from the gradient, or filling a line buffer for a DMA).
    #[cfg(all(feature = "smooth", not(feature = "scan")))]
    #[inline(never)]
    pub fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        let Some(run) = self.burst(y, x_start, x_end) else {
            return;
        };
        for ((slot, colour), x) in run.iter_mut().zip(shade.colours(x_start)).zip(x_start..) {
            *slot = dither_rgb565(x, y, colour);
        }
    }

    /// One textured span of row `y`, columns `x_start..x_end` (clipped to the panel): one
    /// window and one burst of its pixels, two writes, as [`Panel::shaded_span`]. Pixel `x` is
    /// `texture.at(x)` in RGB565 as the runtime's RGB565 framebuffer stores it
    /// (`RowTexture::rgb565_into`: the texels a run at a time, lit ones multiplied once a run
    /// of equal texels), computed as it is sent.
    #[cfg(all(feature = "textures", feature = "smooth", not(feature = "scan")))]
    #[inline(never)]
    pub fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture<'_>) {
        if let Some(run) = self.burst(y, x_start, x_end) {
            texture.rgb565_into(x_start, run);
        }
    }

    /// Count a `DrawTarget` write of `pixels` pixels: the window set-up and the pixels, two
    /// writes.
    fn count(&mut self, pixels: u64) {
        self.bytes += WINDOW_BYTES + PIXEL_BYTES * pixels;
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

/// The streamed builds' sink when they draw smooth files: a flat span as
/// `DrawTargetSink` sends it (one `fill_solid`, its colour converted once per polygon), a
/// shaded span as one window and one burst of dithered pixels ([`Panel::shaded_span`]), and
/// in the build with textures a textured span likewise ([`Panel::textured_span`]).
#[cfg(all(feature = "smooth", not(feature = "scan")))]
pub struct PanelSink<'a> {
    panel: &'a mut Panel,
    /// The last colour converted, and its RGB565.
    last: Option<(Colour, Rgb565)>,
}

#[cfg(all(feature = "smooth", not(feature = "scan")))]
impl<'a> PanelSink<'a> {
    /// A sink streaming into `panel`.
    pub fn new(panel: &'a mut Panel) -> Self {
        PanelSink { panel, last: None }
    }
}

#[cfg(all(feature = "smooth", not(feature = "scan")))]
impl SpanSink for PanelSink<'_> {
    fn write_once(&self) -> bool {
        true
    }

    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        if x_start >= x_end {
            return;
        }
        let (Ok(x), Ok(y)) = (i32::try_from(x_start), i32::try_from(y)) else {
            return;
        };
        let c = match self.last {
            Some((k, c)) if k == colour => c,
            _ => {
                let c = Rgb565::from(embedded_graphics_core::pixelcolor::Rgb888::new(
                    colour.r, colour.g, colour.b,
                ));
                self.last = Some((colour, c));
                c
            }
        };
        let area = Rectangle::new(
            embedded_graphics_core::geometry::Point::new(x, y),
            Size::new(x_end - x_start, 1),
        );
        let Ok(()) = self.panel.fill_solid(&area, c);
    }

    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        self.panel.shaded_span(y, x_start, x_end, shade);
    }

    #[cfg(feature = "textures")]
    fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture<'_>) {
        self.panel.textured_span(y, x_start, x_end, texture);
    }
}
