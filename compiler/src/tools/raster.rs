//! Raster: render `.peel` bytes into an image on the host (CLI `render`/`demo`, benchmarks,
//! end-to-end tests), through the no_std runtime exactly as firmware would.

use glam::DVec3;
use peel_runtime::camera::{Camera, Pose};
use peel_runtime::coverage::Coverage;
use peel_runtime::read::Scene;
use peel_runtime::render::{FrameStats, Renderer, Workspace};
use peel_runtime::target::Colour;
use peel_runtime::target::{Framebuffer, Xrgb8888};
use peel_runtime::traverse::Order;
use peel_runtime::vertices::{CachedVertex, VertexCache};

/// Traversal stack entries of the host workspace (trees deeper than this are refused).
pub const HOST_STACK: usize = 1 << 14;
/// Clip buffer vertices of the host workspace.
pub const HOST_VERTS: usize = 64;

/// A camera in the README's terms; `near: None` is the default near distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Eye position (world).
    pub eye: DVec3,
    /// Point looked at (world).
    pub target: DVec3,
    /// Up hint.
    pub up: DVec3,
    /// Vertical field of view in degrees.
    pub fov_y_deg: f64,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Near distance, or the default (1e-3 x the scene's bounding-box diagonal).
    pub near: Option<f64>,
}

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

/// The runtime camera for `view` over `scene` (resolving the default near distance).
pub fn camera(scene: &Scene<'_>, view: &View) -> Result<Camera, String> {
    let h = scene.header();
    let near = view
        .near
        .unwrap_or_else(|| Camera::default_near(h.bounds_min, h.bounds_max));
    Camera::look_at(
        Pose {
            eye: view.eye,
            target: view.target,
            up: view.up,
        },
        view.fov_y_deg,
        view.width,
        view.height,
        near,
    )
    .map_err(|e| e.to_string())
}

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
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            order: Order::FrontToBack,
            cull: true,
            ids: false,
            background: [0, 0, 0],
        }
    }
}

/// Render `bytes` seen from `view`: colours, or the id image (`id + 1`, background 0), front
/// to back with culling.
pub fn render_bytes(
    bytes: &[u8],
    view: &View,
    ids: bool,
    background: [u8; 3],
) -> Result<Frame, String> {
    render_bytes_with(
        bytes,
        view,
        &Settings {
            ids,
            background,
            ..Settings::default()
        },
    )
}

/// Render `bytes` seen from `view` as `settings` say.
pub fn render_bytes_with(bytes: &[u8], view: &View, settings: &Settings) -> Result<Frame, String> {
    let (ids, background) = (settings.ids, settings.background);
    let scene = Scene::parse(bytes).map_err(|e| format!("invalid .peel file: {e}"))?;
    let camera = camera(&scene, view)?;
    let mut pixels = vec![0u32; view.width as usize * view.height as usize];
    let mut fb = Framebuffer::<Xrgb8888>::new(&mut pixels, view.width, view.height)
        .map_err(|e| e.to_string())?;
    let bg = if ids {
        Colour::new(0, 0, 0)
    } else {
        Colour::new(background[0], background[1], background[2])
    };
    fb.clear(bg);
    let mut workspace: Box<Workspace<HOST_STACK, HOST_VERTS>> = Box::default();
    let rows = view.height as usize;
    let mut intervals = vec![(0u16, 0u16); HOST_SPANS_PER_ROW * rows];
    let mut counts = vec![0u16; rows];
    let coverage = Coverage::new(&mut intervals, &mut counts, view.width, view.height)
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
    let stats = renderer
        .draw(&scene, &camera.view(scene.header().centre), &mut fb)
        .map_err(|e| e.to_string())?;
    Ok(Frame {
        width: view.width,
        height: view.height,
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
