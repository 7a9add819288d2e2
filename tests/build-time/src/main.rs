//! Draw a frame of each scene build.rs compiled, with the traversal stack, the clip buffers,
//! the span memory and the vertex memory sized from the generated sizes files, as firmware
//! would (see docs/build-time.md).

use glam::DVec3;
use peel_runtime::camera::{Camera, Pose};
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Colour, Rgb565Framebuffer};
use peel_runtime::read::Scene;
use peel_runtime::render::{FrameStats, Renderer, Workspace};
use peel_runtime::vertices::{CachedVertex, VertexCache};

mod demo {
    include!(concat!(env!("OUT_DIR"), "/demo.rs"));
}
mod cube {
    include!(concat!(env!("OUT_DIR"), "/cube.rs"));
}

static DEMO: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/demo.peel"));
static CUBE: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/cube.peel"));

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

const fn max(a: usize, b: usize) -> usize {
    if a > b {
        a
    } else {
        b
    }
}

/// One workspace for both scenes, sized for the larger of each figure.
const STACK: usize = max(demo::STACK, cube::STACK);
const VERTS: usize = max(demo::VERTS, cube::VERTS);
const _: () = demo::check_workspace(STACK, VERTS);
const _: () = cube::check_workspace(STACK, VERTS);

/// Span memory and vertex memory for both.
const SPANS: usize = max(
    demo::span_memory(WIDTH, HEIGHT),
    cube::span_memory(WIDTH, HEIGHT),
);
const VERTICES: usize = max(demo::VERTEX_MEMORY, cube::VERTEX_MEMORY);
const _: () = demo::check_vertex_memory(VERTICES);

// The compile-time check: this workspace is too small for the demo scene.
#[cfg(feature = "too-small")]
const _: () = demo::check_workspace(1, VERTS);

/// Draw `bytes` from a point on a diagonal at `distance` times the scene's size.
fn draw(bytes: &[u8], workspace: &mut Workspace<STACK, VERTS>) -> FrameStats {
    let scene = Scene::parse(bytes).expect("a valid scene");
    let h = scene.header();
    let centre = DVec3::from_array(h.centre);
    let size = (h.bounds_max - h.bounds_min).length() as f64;
    let eye = centre + DVec3::new(1.0, 0.8, 1.2) * size;
    let camera = Camera::look_at(Pose::new(eye, centre), 50.0, WIDTH, HEIGHT, 1e-3 * size)
        .expect("a camera");
    let mut intervals = vec![(0u16, 0u16); SPANS];
    let mut counts = [0u16; HEIGHT as usize];
    let coverage = Coverage::new(&mut intervals, &mut counts, WIDTH, HEIGHT).expect("span memory");
    let mut memory = vec![CachedVertex::EMPTY; VERTICES];
    let mut pixels = vec![0u16; (WIDTH * HEIGHT) as usize];
    let mut fb = Rgb565Framebuffer::new(&mut pixels, WIDTH, HEIGHT).expect("a framebuffer");
    fb.clear(Colour::new(0, 0, 0));
    let mut renderer = Renderer::new(workspace)
        .span_memory(coverage)
        .vertex_memory(VertexCache::new(&mut memory));
    renderer
        .draw(&scene, &camera.view(h.centre), &mut fb)
        .expect("the frame fits the memory sized from the sizes file")
}

fn main() {
    let mut workspace = Workspace::<STACK, VERTS>::new();
    for (name, bytes) in [("demo", DEMO), ("cube", CUBE)] {
        let stats = draw(bytes, &mut workspace);
        println!(
            "{name}: {} polygons drawn, {} pixels, fallback {}",
            stats.polygons_drawn, stats.pixels_written, stats.fallback
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sizes files say what the headers say.
    #[test]
    fn the_sizes_are_the_headers() {
        let h = Scene::parse(DEMO).unwrap().header();
        assert_eq!(demo::BYTES, DEMO.len());
        assert_eq!(demo::STACK, h.max_depth as usize);
        assert_eq!(demo::MAX_DEPTH, h.max_depth as usize);
        assert_eq!(
            demo::VERTS,
            peel_runtime::clip::buffer_len_for(h.max_polygon_vertices) as usize
        );
        assert_eq!(demo::VERTICES, h.vertex_count as usize);
        assert_eq!(demo::POLYGONS, h.polygon_count as usize);
        assert_eq!(demo::NODES, h.node_count as usize);
        assert_eq!(demo::CENTRE, h.centre);
        assert_eq!(demo::BOUNDS_MIN, h.bounds_min.to_array());
        assert_eq!(demo::BOUNDS_MAX, h.bounds_max.to_array());
        let h = Scene::parse(CUBE).unwrap().header();
        assert_eq!(cube::STACK, h.max_depth as usize);
        assert_eq!(cube::VERTICES, h.vertex_count as usize);
    }

    /// Frames drawn with memory of exactly those sizes succeed, each pixel written once.
    #[test]
    fn frames_fit_the_memory_sized_from_the_sizes_files() {
        let mut workspace = Workspace::<STACK, VERTS>::new();
        for bytes in [DEMO, CUBE] {
            let stats = draw(bytes, &mut workspace);
            assert!(stats.polygons_drawn > 0);
            assert!(!stats.fallback, "the span memory sufficed");
        }
    }

    /// The cube's faces have the colour build.rs chose (shaded from it).
    #[test]
    fn the_default_colour_reaches_the_file() {
        let scene = Scene::parse(CUBE).unwrap();
        let c = scene.polygon(0).colour;
        assert!(c.r > c.g && c.g > c.b && c.b > 0, "{c:?}");
    }
}
