//! A frame of the orbit, drawn as firmware draws it: front to back in RGB565 into an
//! embedded-graphics `DrawTarget`, with memory sized for the scene. Nothing here knows it runs
//! on a PC but the heap the memory lives on: firmware keeps the same buffers in statics.

use std::convert::Infallible;

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::pixelcolor::Rgb565;
use peel_runtime::camera::{Camera, LocalView, Orbit, DEFAULT_FOV_Y_DEG};
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Colour, DrawTargetSink};
use peel_runtime::read::{Header, Scene};
use peel_runtime::render::{FrameStats, Renderer, Workspace};
use peel_runtime::scan::{ScanMemory, ScanNode};
use peel_runtime::vertices::{CachedVertex, VertexCache};
use peel_runtime::RenderError;

use crate::scene;

/// What no polygon covers (the boards' background).
pub const BACKGROUND: Colour = Colour::new(24, 26, 32);
/// The orbit's elevation, degrees: one of the two the build script measured the memory at.
pub const ELEVATION_DEG: f64 = 20.0;
/// Traversal stack and clip buffers for a file read at run time, whose depth and largest
/// polygon are not known when this program compiles: the host renderer's.
const ANY_STACK: usize = 1 << 14;
const ANY_VERTS: usize = 64;

/// How a frame reaches the display.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Order {
    /// Front to back into scan memory, then the whole frame row by row in one address window
    /// (`ScanFrame::draw_to`: one `fill_contiguous`), as the boards send it.
    Scan,
    /// Each span to the display as it is drawn (`DrawTargetSink`: one `fill_solid` a span),
    /// the uncovered pixels last in the background colour: no frame memory at all.
    Stream,
}

/// The traversal stack and clip buffers of [`Memory`]: a `Workspace`'s sizes are constants.
enum Stack {
    /// The built-in scene's, from its sizes file.
    Sized(Box<Workspace<{ scene::STACK }, { scene::VERTS }>>),
    /// Any scene's (up to the runtime's limits; a deeper tree is a frame error).
    Any(Box<Workspace<ANY_STACK, ANY_VERTS>>),
}

/// The memory of the frames of one scene in one [`Order`]: what a firmware's statics hold.
pub struct Memory {
    stack: Stack,
    /// Scan memory ([`Order::Scan`]).
    nodes: Vec<ScanNode>,
    heads: Vec<u16>,
    /// Span memory ([`Order::Stream`]).
    intervals: Vec<(u16, u16)>,
    counts: Vec<u16>,
    vertices: Vec<CachedVertex>,
    width: u32,
    height: u32,
}

impl Memory {
    /// The built-in scene's memory at the size its sizes file was measured at, as firmware
    /// sizes its statics: `STACK`, `VERTS`, `SCAN_NODES` or `span_memory(W, H)`,
    /// `VERTEX_MEMORY`.
    pub fn built_in(order: Order) -> Memory {
        let (width, height) = scene::SPANS_MEASURED_AT;
        let (nodes, intervals) = match order {
            Order::Scan => (scene::SCAN_NODES, 0),
            Order::Stream => (0, scene::span_memory(width, height)),
        };
        Memory::new(
            Stack::Sized(Box::default()),
            order,
            nodes,
            intervals,
            scene::VERTEX_MEMORY,
        )
    }

    /// Memory for a scene read at run time, whose orbit nobody measured: all the scan memory
    /// the runtime can address, span memory that can never run out (a row holds at most
    /// `(width + 1) / 2` intervals) and a vertex entry per vertex, at the built-in scene's
    /// display size.
    pub fn any(header: &Header, order: Order) -> Memory {
        let (width, height) = scene::SPANS_MEASURED_AT;
        let (nodes, intervals) = match order {
            Order::Scan => (usize::from(u16::MAX), 0),
            Order::Stream => (0, (width as usize).div_ceil(2) * height as usize),
        };
        let vertices = (header.vertex_count as usize).next_power_of_two();
        Memory::new(
            Stack::Any(Box::default()),
            order,
            nodes,
            intervals,
            vertices,
        )
    }

    fn new(stack: Stack, order: Order, nodes: usize, intervals: usize, vertices: usize) -> Memory {
        let (width, height) = scene::SPANS_MEASURED_AT;
        let rows = |used: bool| vec![0u16; if used { height as usize } else { 0 }];
        Memory {
            stack,
            nodes: vec![ScanNode::EMPTY; nodes],
            heads: rows(order == Order::Scan),
            intervals: vec![(0, 0); intervals],
            counts: rows(order == Order::Stream),
            vertices: vec![CachedVertex::EMPTY; vertices],
            width,
            height,
        }
    }

    /// The display size.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The renderer of every frame over this memory, made once: front to back into scan
    /// memory or span memory as `order` says, vertices kept in vertex memory, the uncovered
    /// pixels in [`BACKGROUND`].
    ///
    /// # Errors
    /// [`RenderError::SpanMemory`] for a display too wide for the memory's rows.
    pub fn renderer(&mut self, order: Order) -> Result<Renderer<'_>, RenderError> {
        let renderer = match &mut self.stack {
            Stack::Sized(w) => Renderer::new(&mut **w),
            Stack::Any(w) => Renderer::new(&mut **w),
        };
        let renderer = renderer
            .vertex_memory(VertexCache::new(&mut self.vertices))
            .background(BACKGROUND);
        let (width, height) = (self.width, self.height);
        Ok(match order {
            Order::Scan => renderer.scan_memory(ScanMemory::new(
                &mut self.nodes,
                &mut self.heads,
                width,
                height,
            )?),
            Order::Stream => renderer.span_memory(Coverage::new(
                &mut self.intervals,
                &mut self.counts,
                width,
                height,
            )?),
        })
    }
}

/// The view of the orbit's frame at `azimuth_deg` on a `width x height` display: the `f64`
/// [`Orbit`] and [`Camera`] the build script measured the memory with (the default field of
/// view, the fitting distance). It is also the host renderer's camera: a frame here is
/// `peel render --orbit <azimuth>,20`'s in RGB565. (Firmware on a core without `f64` takes
/// `LocalOrbit`, the same orbit in `f32`, as the boards do.)
///
/// # Errors
/// [`RenderError::BadCamera`] for an azimuth that is not finite.
pub fn orbit_view(
    header: &Header,
    azimuth_deg: f64,
    width: u32,
    height: u32,
) -> Result<LocalView, RenderError> {
    let orbit = Orbit {
        azimuth_deg,
        elevation_deg: ELEVATION_DEG,
        distance: Orbit::fitting_distance(DEFAULT_FOV_Y_DEG, width, height),
    };
    let near = Camera::default_near(header.bounds_min, header.bounds_max);
    let camera = Camera::look_at(orbit.pose(header), DEFAULT_FOV_Y_DEG, width, height, near)?;
    Ok(camera.view(header.centre))
}

/// Draw the frame `view` sees and send it to `display` in `order`: the one place that decides
/// how a frame reaches the display, as a firmware's `draw_frame`. Every pixel is written, so
/// the display needs no clearing between frames.
///
/// # Errors
/// The renderer's: scan memory too small for the frame ([`RenderError::ScanMemoryFull`],
/// nothing sent) or span memory ([`RenderError::SpanMemoryFull`], the frame stopped), a
/// workspace too small for the scene, a degenerate view.
pub fn draw_frame<D>(
    renderer: &mut Renderer<'_>,
    scene: &Scene<'_>,
    view: &LocalView,
    order: Order,
    display: &mut D,
) -> Result<FrameStats, RenderError>
where
    D: DrawTarget<Color = Rgb565, Error = Infallible>,
{
    match order {
        Order::Scan => {
            let frame = renderer.draw_scan(scene, view)?;
            frame
                .draw_to(display)
                .unwrap_or_else(|never| match never {});
            Ok(frame.stats())
        }
        Order::Stream => {
            let mut sink = DrawTargetSink::new(display);
            let stats = renderer.draw(scene, view, &mut sink)?;
            sink.finish().unwrap_or_else(|never| match never {});
            Ok(stats)
        }
    }
}
