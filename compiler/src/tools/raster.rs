//! Raster: render `.peel` bytes into an image on the host (CLI `render`/`demo`, benchmarks,
//! end-to-end tests), through the no_std runtime exactly as firmware would.

use glam::DVec3;
use peel_runtime::camera::LocalView;
use peel_runtime::composite::{Composite, CompositeRun, MAX_RUNS};
use peel_runtime::coverage::Coverage;
use peel_runtime::display::Colour;
use peel_runtime::display::{Framebuffer, Xrgb8888};
use peel_runtime::error::RenderError;
use peel_runtime::pending::{Pending, PendingPixel};
use peel_runtime::place::{Object, ObjectMemory, Posed};
use peel_runtime::read::layout::MAX_PARTS;
use peel_runtime::read::{Header, Scene};
use peel_runtime::render::{Content, FrameStats, Renderer, Workspace};
use peel_runtime::traverse::Order;
use peel_runtime::vertices::{CachedVertex, VertexCache};

use super::shot::Shot;

/// Traversal stack entries of the host workspace (trees deeper than this are refused).
pub const HOST_STACK: usize = 1 << 14;
/// Clip buffer vertices of the host workspace.
pub const HOST_VERTS: usize = 96;

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
    /// Textures filtered bilinearly (`Renderer::bilinear`) instead of by nearest texel.
    pub bilinear: bool,
}

/// Composite-memory records given to front-to-back frames on the host: all a memory can use
/// (a scene without transparent surfaces uses none).
pub const HOST_COMPOSITE: usize = MAX_RUNS;

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
            bilinear: false,
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
    let scene = Scene::parse(bytes).map_err(|e| format!("invalid .peel file: {e}"))?;
    if scene.header().polygon_count == 0 {
        return Err(EMPTY_SCENE.to_string());
    }
    let camera = shot.camera(&scene.header())?;
    let view = camera.view(scene.header().centre);
    draw(
        &scene,
        &view,
        shot,
        settings,
        scene.header().vertex_count,
        None,
    )
    .map_err(|e| e.to_string())
}

/// Object memory of the host: every object a file can hold, and steps enough for any frame
/// the tests and the command line draw.
pub type HostObjectMemory = ObjectMemory<{ MAX_PARTS as usize }, 4096>;

/// The header that frames a world and posed objects for the camera ([`Shot::camera`],
/// [`Shot::near_over`]): the world's centre (or the origin) and the bounds of the world and of
/// every visible object's posed box.
pub fn posed_header(world: Option<&Scene<'_>>, objects: &[Object<'_>]) -> Header {
    let centre = Posed::new(world.copied(), objects).centre();
    let c = DVec3::from_array(centre);
    let (mut lo, mut hi) = match world {
        Some(w) => (
            w.header().bounds_min.as_dvec3(),
            w.header().bounds_max.as_dvec3(),
        ),
        None => (DVec3::INFINITY, DVec3::NEG_INFINITY),
    };
    for o in objects {
        let Some(pose) = o.pose else { continue };
        let h = o.scene.header();
        let r = pose.rotation.as_dmat3();
        let t = pose.translation.as_dvec3();
        let oc = DVec3::from_array(h.centre);
        for k in 0..8 {
            let (a, b) = (h.bounds_min.as_dvec3(), h.bounds_max.as_dvec3());
            let p = DVec3::new(
                if k & 1 == 0 { a.x } else { b.x },
                if k & 2 == 0 { a.y } else { b.y },
                if k & 4 == 0 { a.z } else { b.z },
            );
            let q = t + r * (oc + p) - c;
            lo = lo.min(q);
            hi = hi.max(q);
        }
    }
    if !lo.is_finite() {
        (lo, hi) = (DVec3::ZERO, DVec3::ZERO);
    }
    Header {
        centre,
        bounds_min: lo.as_vec3(),
        bounds_max: hi.as_vec3(),
        ..Header::default()
    }
}

/// Render a world (if any) and posed objects as `shot` sees them, as `settings` say: the
/// frame firmware draws of a file of parts.
pub fn render_posed_with(
    world: Option<&Scene<'_>>,
    objects: &[Object<'_>],
    shot: &Shot,
    settings: &Settings,
) -> Result<Frame, String> {
    let numbers: Vec<String> = (0..objects.len()).map(|k| k.to_string()).collect();
    let names: Vec<&str> = numbers.iter().map(String::as_str).collect();
    render_posed_named(world, objects, &names, shot, settings)
}

/// [`render_posed_with`], its errors naming objects by `names` (one per object).
pub fn render_posed_named(
    world: Option<&Scene<'_>>,
    objects: &[Object<'_>],
    names: &[&str],
    shot: &Shot,
    settings: &Settings,
) -> Result<Frame, String> {
    let name = |k: u32| names.get(k as usize).copied().unwrap_or("?");
    let describe = |e: RenderError| match e {
        RenderError::ObjectsIntersect { first, second } => format!(
            "objects {} and {} intersect on the screen and no plane separates their boxes: \
             their order is not proven (move them apart)",
            name(first),
            name(second)
        ),
        RenderError::BadPose { object } => format!("the pose of {} is not finite", name(object)),
        e => e.to_string(),
    };
    let posed = Posed::new(world.copied(), objects);
    let parts = || world.into_iter().chain(objects.iter().map(|o| &o.scene));
    if parts().all(|s| s.header().polygon_count == 0) {
        return Err(EMPTY_SCENE.to_string());
    }
    let header = posed_header(world, objects);
    let camera = shot.camera(&header)?;
    let vertices = parts().map(|s| s.header().vertex_count).max().unwrap_or(0);
    let mut memory: Box<HostObjectMemory> = Box::default();
    let view = camera.view(header.centre);
    draw(&posed, &view, shot, settings, vertices, Some(&mut memory)).map_err(describe)
}

/// One frame of `content` through a host renderer set up as `settings` say.
fn draw<C: Content + ?Sized>(
    content: &C,
    view: &LocalView,
    shot: &Shot,
    settings: &Settings,
    vertex_count: u32,
    objects: Option<&mut HostObjectMemory>,
) -> Result<Frame, RenderError> {
    let (ids, background) = (settings.ids, settings.background);
    let mut pixels = vec![0u32; shot.width as usize * shot.height as usize];
    let mut fb =
        Framebuffer::<Xrgb8888>::new(&mut pixels, shot.width, shot.height).map_err(|_| {
            RenderError::ImageTooLarge {
                width: shot.width,
                height: shot.height,
            }
        })?;
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
    let coverage = Coverage::new(&mut intervals, &mut counts, shot.width, shot.height)?;
    let mut memory = vec![CachedVertex::EMPTY; vertex_count as usize];
    let mut renderer = Renderer::new(&mut workspace)
        .span_memory(coverage)
        .vertex_memory(VertexCache::new(&mut memory));
    if let Some(objects) = objects {
        renderer = renderer.object_memory(objects);
    }
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
    if settings.bilinear {
        renderer = renderer.bilinear();
    }
    // Transparent surfaces front to back: their runs in composite memory (all a memory can
    // use), finished by the background (an opaque scene never touches either).
    let mut runs = vec![CompositeRun::default(); HOST_COMPOSITE];
    let mut run_heads = vec![0u16; rows];
    renderer = renderer
        .composite_memory(Composite::new(&mut runs, &mut run_heads, shot.height)?)
        .background(bg);
    let mut records = vec![PendingPixel::default(); settings.antialias.unwrap_or(0)];
    let mut heads = vec![0u16; rows];
    if settings.antialias.is_some() {
        let pending = Pending::new(&mut records, &mut heads, shot.height)?;
        renderer = renderer.antialias(pending).background(bg);
    }
    let stats = renderer.draw(content, view, &mut fb)?;
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
