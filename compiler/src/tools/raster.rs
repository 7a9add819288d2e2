//! Raster: render `.peel` bytes into an image on the host (CLI `render`/`demo`, benchmarks,
//! end-to-end tests), through the no_std runtime exactly as firmware would.

use peel_runtime::coverage::Coverage;
use peel_runtime::display::Colour;
use peel_runtime::display::{Framebuffer, Xrgb8888};
use peel_runtime::pending::{Pending, PendingPixel};
use peel_runtime::read::Scene;
use peel_runtime::render::{FrameStats, Renderer, Workspace};
use peel_runtime::traverse::Order;
use peel_runtime::vertices::{CachedVertex, VertexCache};

use super::shot::Shot;

/// Traversal stack entries of the host workspace (trees deeper than this are refused).
pub const HOST_STACK: usize = 1 << 14;
/// Clip buffer vertices of the host workspace.
pub const HOST_VERTS: usize = 64;

/// A rendered frame: `0x00RRGGBB` per pixel, row-major.
#[derive(Debug, Clone)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels.
    pub pixels: Vec<u32>,
    /// What the runtime counted.
    pub stats: FrameStats,
}

impl Frame {
    /// The frame as RGB bytes.
    pub fn to_rgb(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| [(p >> 16) as u8, (p >> 8) as u8, *p as u8])
            .collect()
    }
}

/// Why an empty scene is not rendered.
pub const EMPTY_SCENE: &str = "the scene is empty (it has no polygons): there is nothing to draw";

/// Span-buffer intervals per image row given to front-to-back rendering on the host.
pub const HOST_SPANS_PER_ROW: usize = 64;

/// How a frame is drawn on the host.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Settings {
    /// Front to back (each pixel written once) or back to front (painter's algorithm).
    pub order: Order,
    /// Culling that provably changes no pixel: frustum and covered subtrees, covered polygons.
    pub cull: bool,
    /// The id image (`id + 1`, background 0) instead of colours.
    pub ids: bool,
    /// Background colour (ignored for id images, whose background is 0).
    pub background: [u8; 3],
    /// Vertices projected in integers, as a core without an FPU draws them
    /// (`Renderer::integer_vertices`).
    pub integer_vertices: bool,
    /// Anti-aliased (`Renderer::antialias`) with this many pending-pixel records (the CLI
    /// gives [`HOST_PENDING`]), blending edges with the background.
    pub antialias: Option<usize>,
}

/// Pending-pixel records given to anti-aliased frames on the host: all a pool can use.
pub const HOST_PENDING: usize = 32_767;

impl Default for Settings {
    fn default() -> Self {
        Settings {
            order: Order::FrontToBack,
            cull: true,
            ids: false,
            background: [0, 0, 0],
            integer_vertices: false,
            antialias: None,
        }
    }
}

/// Render `bytes` as `shot` sees them: colours, or the id image (`id + 1`, background 0), front
/// to back with culling.
pub fn render_bytes(
    bytes: &[u8],
    shot: &Shot,
    ids: bool,
    background: [u8; 3],
) -> Result<Frame, String> {
    render_bytes_with(
        bytes,
        shot,
        &Settings {
            ids,
            background,
            ..Settings::default()
        },
    )
}

/// Render `bytes` as `shot` sees them, as `settings` say. An empty scene (no polygons) is an
/// error: there is nothing to draw, and no extent to frame or to take a near distance from.
pub fn render_bytes_with(bytes: &[u8], shot: &Shot, settings: &Settings) -> Result<Frame, String> {
    let (ids, background) = (settings.ids, settings.background);
    let scene = Scene::parse(bytes).map_err(|e| format!("invalid .peel file: {e}"))?;
    if scene.header().polygon_count == 0 {
        return Err(EMPTY_SCENE.to_string());
    }
    let camera = shot.camera(&scene.header())?;
    let mut pixels = vec![0u32; shot.width as usize * shot.height as usize];
    let mut fb = Framebuffer::<Xrgb8888>::new(&mut pixels, shot.width, shot.height)
        .map_err(|e| e.to_string())?;
    let bg = if ids {
        Colour::new(0, 0, 0)
    } else {
        Colour::new(background[0], background[1], background[2])
    };
    fb.clear(bg);
    let mut workspace: Box<Workspace<HOST_STACK, HOST_VERTS>> = Box::default();
    let rows = shot.height as usize;
    let mut intervals = vec![(0u16, 0u16); HOST_SPANS_PER_ROW * rows];
    let mut counts = vec![0u16; rows];
    let coverage = Coverage::new(&mut intervals, &mut counts, shot.width, shot.height)
        .map_err(|e| e.to_string())?;
    let mut memory = vec![CachedVertex::EMPTY; scene.header().vertex_count as usize];
    let mut renderer = Renderer::new(&mut workspace)
        .span_memory(coverage)
        .vertex_memory(VertexCache::new(&mut memory));
    if ids {
        renderer = renderer.ids();
    }
    if settings.order == Order::BackToFront {
        renderer = renderer.back_to_front();
    }
    if !settings.cull {
        renderer = renderer.without_culling();
    }
    if settings.integer_vertices {
        renderer = renderer.integer_vertices();
    }
    let mut records = vec![PendingPixel::default(); settings.antialias.unwrap_or(0)];
    let mut heads = vec![0u16; rows];
    if settings.antialias.is_some() {
        let pending =
            Pending::new(&mut records, &mut heads, shot.height).map_err(|e| e.to_string())?;
        renderer = renderer.antialias(pending).background(bg);
    }
    let stats = renderer
        .draw(&scene, &camera.view(scene.header().centre), &mut fb)
        .map_err(|e| e.to_string())?;
    Ok(Frame {
        width: shot.width,
        height: shot.height,
        pixels,
        stats,
    })
}

/// Encode a frame as PNG bytes.
#[cfg(feature = "png")]
pub fn png(frame: &Frame) -> Result<Vec<u8>, String> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(
            &frame.to_rgb(),
            frame.width,
            frame.height,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| e.to_string())?;
    Ok(out)
}
