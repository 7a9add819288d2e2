//! One frame of each variant, from the view to the last byte sent to the panel: what the
//! SysTick measurement covers. Memory comes from the pools, sized by the config block.

use core::ops::Range;

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::raw::RawU16;
use embedded_graphics_core::pixelcolor::Rgb565;
use embedded_graphics_core::primitives::Rectangle;

use crate::display::Panel;

#[cfg(not(feature = "zbuffer"))]
pub use peel::Method;
#[cfg(feature = "zbuffer")]
pub use zbuffer::Method;

/// Send `pixels`, frame rows `rows` of a `width`-pixel-wide image, to the panel in one
/// `fill_contiguous` (one address window and one burst).
#[allow(dead_code)] // Not every variant sends a buffer.
fn send(pixels: &[u16], width: u32, rows: Range<u32>, panel: &mut Panel) {
    let area = Rectangle::new(
        Point::new(0, rows.start as i32),
        Size::new(width, rows.end - rows.start),
    );
    let colours = pixels.iter().map(|&raw| Rgb565::from(RawU16::new(raw)));
    let Ok(()) = panel.fill_contiguous(&area, colours);
}

#[cfg(not(feature = "zbuffer"))]
mod peel {
    use peel_runtime::camera::View;
    use peel_runtime::coverage::Coverage;
    use peel_runtime::read::{Header, Scene};
    use peel_runtime::render::{Renderer, Workspace};
    use peel_runtime::target::{Colour, Rgb565Framebuffer};
    use peel_target_kit::config::Config;

    use crate::display::Panel;
    use crate::pool::Pool;
    use crate::{Failure, VARIANT};

    /// Traversal stack entries and clip-buffer vertices of the renderer's workspace: enough for
    /// the benchmark's scenes (the renderer refuses a scene that needs more before drawing).
    const STACK: usize = 128;
    const VERTS: usize = 24;

    /// A Peel variant's scene and memory.
    pub struct Method {
        scene: Scene<'static>,
        workspace: &'static mut Workspace<STACK, VERTS>,
        /// The framebuffer, or the band buffer; empty when streaming.
        pixels: &'static mut [u16],
        /// Span memory (front to back): intervals and per-row counts of one frame or band.
        spans: &'static mut [(u16, u16)],
        counts: &'static mut [u16],
        spans_per_row: usize,
        width: u32,
        height: u32,
        /// Rows per band (the height when not banded).
        band: u32,
        background: Colour,
    }

    impl Method {
        /// Validate the scene (once, at boot) and take the variant's memory.
        pub fn new(
            asset: &'static [u8],
            config: &Config,
            pixels: &mut Pool<u16>,
            spans: &mut Pool<(u16, u16)>,
        ) -> Result<Method, Failure> {
            let scene = Scene::parse(asset)?;
            let (width, height) = (config.width, config.height);
            let band = if VARIANT.banded() {
                config.band_rows
            } else {
                height
            };
            let buffered = !matches!(VARIANT, peel_target_kit::config::Variant::FtbStream);
            let pixel_count = if buffered {
                width as usize * band as usize
            } else {
                0
            };
            let spans_per_row = config.spans_per_row as usize;
            let (intervals, counts) = if VARIANT.front_to_back() {
                (spans_per_row * band as usize, band as usize)
            } else {
                (0, 0)
            };
            let workspace = cortex_m::singleton!(: Workspace<STACK, VERTS> = Workspace::new())
                .ok_or(Failure::Host("workspace taken twice"))?;
            Ok(Method {
                scene,
                workspace,
                pixels: pixels.take(pixel_count, "framebuffer")?,
                spans: spans.take(intervals, "span memory")?,
                counts: pixels.take(counts, "span memory row counts")?,
                spans_per_row,
                width,
                height,
                band,
                background: config.background_colour(),
            })
        }

        /// The scene's header (for the camera).
        pub fn header(&self) -> Header {
            self.scene.header()
        }

        /// Bytes of pixel memory: the framebuffer or band buffer (0 when streaming).
        pub fn framebuffer_bytes(&self) -> usize {
            core::mem::size_of_val(self.pixels)
        }

        /// Draw the frame seen by `view` and send it to `panel`; returns whether front to
        /// back ran out of span memory (the frame is then finished back to front: the same
        /// pixels, with overdraw).
        pub fn frame(&mut self, view: &View, panel: &mut Panel) -> Result<bool, Failure> {
            self.draw(view, panel)
        }

        /// Span memory for `rows` rows.
        #[allow(dead_code)]
        fn coverage(&mut self, rows: u32) -> Result<Coverage<'_>, Failure> {
            let n = rows as usize;
            Ok(Coverage::new(
                &mut self.spans[..self.spans_per_row * n],
                &mut self.counts[..n],
                self.width,
                rows,
            )?)
        }

        #[cfg(feature = "ftb-framebuffer")]
        fn draw(&mut self, view: &View, panel: &mut Panel) -> Result<bool, Failure> {
            let (w, h) = (self.width, self.height);
            let coverage = Coverage::new(&mut self.spans[..], &mut self.counts[..], w, h)?;
            let mut fb = Rgb565Framebuffer::new(&mut self.pixels[..], w, h)?;
            fb.clear(self.background);
            let stats = Renderer::new(&mut *self.workspace)
                .span_memory(coverage)
                .draw(&self.scene, view, &mut fb)?;
            super::send(self.pixels, w, 0..h, panel);
            Ok(stats.fallback)
        }

        #[cfg(feature = "b2f-framebuffer")]
        fn draw(&mut self, view: &View, panel: &mut Panel) -> Result<bool, Failure> {
            let (w, h) = (self.width, self.height);
            let mut fb = Rgb565Framebuffer::new(&mut self.pixels[..], w, h)?;
            fb.clear(self.background);
            Renderer::new(&mut *self.workspace).draw(&self.scene, view, &mut fb)?;
            super::send(self.pixels, w, 0..h, panel);
            Ok(false)
        }
    }
}

#[cfg(feature = "zbuffer")]
mod zbuffer {
    use peel_runtime::camera::View;
    use peel_runtime::read::Header;
    use peel_target_kit::config::Config;
    use peel_target_kit::mesh::Mesh;

    use crate::display::Panel;
    use crate::pool::Pool;
    use crate::Failure;

    /// The mesh, the framebuffer and the depth buffer.
    pub struct Method {
        mesh: Mesh<'static>,
        colour: &'static mut [u16],
        depth: &'static mut [u16],
        width: u32,
        height: u32,
        background: u16,
    }

    impl Method {
        /// Validate the mesh (once, at boot) and take the buffers.
        pub fn new(
            asset: &'static [u8],
            config: &Config,
            pixels: &mut Pool<u16>,
            _: &mut Pool<(u16, u16)>,
        ) -> Result<Method, Failure> {
            let n = config.width as usize * config.height as usize;
            Ok(Method {
                mesh: Mesh::parse(asset)?,
                colour: pixels.take(n, "framebuffer")?,
                depth: pixels.take(n, "depth buffer")?,
                width: config.width,
                height: config.height,
                background: config.background_colour().to_rgb565(),
            })
        }

        /// The scene's header (for the camera).
        pub fn header(&self) -> Header {
            self.mesh.header()
        }

        /// Bytes of pixel memory: the framebuffer (the depth buffer is not pixels).
        pub fn framebuffer_bytes(&self) -> usize {
            core::mem::size_of_val(self.colour)
        }

        /// Draw the frame seen by `view` and send it to `panel` (never a fallback).
        pub fn frame(&mut self, view: &View, panel: &mut Panel) -> Result<bool, Failure> {
            peel_target_kit::zbuffer::draw(
                &self.mesh,
                view,
                self.background,
                self.colour,
                self.depth,
            )?;
            super::send(self.colour, self.width, 0..self.height, panel);
            Ok(false)
        }
    }
}
