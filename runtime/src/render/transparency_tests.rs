//! Transparent surfaces through every path of a frame: back to front blended "over" the
//! framebuffer, front to back composited "under" in composite memory (whole, in bands,
//! streamed once per pixel), the screen-door fallback, and the refusals.

extern crate std;

use glam::{DVec3, Vec3};
use std::vec;
use std::vec::Vec;

use super::*;
use crate::camera::{Camera, Pose};
use crate::composite::{Composite, CompositeRun};
use crate::coverage::Coverage;
use crate::display::{Colour, SpanSink, Xrgb8888Framebuffer};
use crate::read::Node;
use crate::traverse::testing::{box_faces, TestTree};
use crate::RenderError;

const W: usize = 40;
const H: usize = 30;
const BACKGROUND: Colour = Colour::new(20, 30, 60);

/// A glass box `[-1, 1]^3` (each face its own tint and opacity) around an opaque box
/// `[-0.4, 0.4]^3`: the glass's convex node, the opaque box its child.
fn glass_box() -> TestTree {
    let mut t = TestTree::default();
    let (first, count) = box_faces(&mut t, Vec3::splat(-1.0), Vec3::ONE, Colour::grey(0));
    let tints = [
        Colour::new(255, 80, 80),
        Colour::new(80, 255, 80),
        Colour::new(80, 80, 255),
        Colour::new(255, 255, 80),
        Colour::new(80, 255, 255),
        Colour::new(255, 80, 255),
    ];
    for (p, c) in t.polygons.iter_mut().zip(tints) {
        p.colour = c;
    }
    t.opacities = vec![90, 120, 150, 60, 200, 30];
    let (inner, inner_count) =
        box_faces(&mut t, Vec3::splat(-0.4), Vec3::splat(0.4), Colour::grey(0));
    for (k, p) in t.polygons.iter_mut().enumerate().skip(inner as usize) {
        let k = (k % 6) as u8;
        p.colour = Colour::new(40 * k, 200, 255 - 30 * k);
    }
    t.opacities.resize(t.polygons.len(), u8::MAX);
    t.nodes.push(Node::Convex {
        first,
        count,
        child: Some(1),
    });
    t.nodes.push(Node::Convex {
        first: inner,
        count: inner_count,
        child: None,
    });
    t
}

fn camera(eye: DVec3) -> Camera {
    Camera::look_at(Pose::new(eye, DVec3::ZERO), 60.0, W as u32, H as u32, 0.01).unwrap()
}

fn views() -> [DVec3; 4] {
    [
        DVec3::new(2.1, 1.3, 3.0),
        DVec3::new(-2.6, -1.5, 1.8),
        DVec3::new(0.4, 3.2, -1.7),
        // Inside the glass, outside the opaque box.
        DVec3::new(0.7, -0.6, 0.75),
    ]
}

/// The memory of a front-to-back frame: span memory, and composite memory of `runs` records.
struct Memory {
    intervals: Vec<(u16, u16)>,
    counts: Vec<u16>,
    runs: Vec<CompositeRun>,
    heads: Vec<u16>,
}

impl Memory {
    fn new(runs: usize) -> Memory {
        Memory {
            intervals: vec![(0, 0); 16 * H],
            counts: vec![0; H],
            runs: vec![CompositeRun::default(); runs],
            heads: vec![0; H],
        }
    }

    fn renderer<'m>(&'m mut self, ws: &'m mut Workspace<16, 12>, band: u32) -> Renderer<'m> {
        let coverage = Coverage::new(&mut self.intervals, &mut self.counts, W as u32, band);
        let composite = Composite::new(&mut self.runs, &mut self.heads, band);
        Renderer::new(ws)
            .span_memory(coverage.unwrap())
            .composite_memory(composite.unwrap())
            .background(BACKGROUND)
    }
}

/// Front to back into an XRGB8888 framebuffer, in bands of `band` rows; the frames' stats.
fn front_to_back(t: &TestTree, cam: &Camera, band: u32, runs: usize) -> (Vec<u32>, FrameStats) {
    let mut pixels = vec![0u32; W * H];
    let mut fb = Xrgb8888Framebuffer::new(&mut pixels, W as u32, H as u32).unwrap();
    let (mut memory, mut ws) = (Memory::new(runs), Workspace::<16, 12>::new());
    let mut renderer = memory.renderer(&mut ws, band);
    let view = cam.view(t.centre());
    let mut total = FrameStats::default();
    for first in (0..H as u32).step_by(band as usize) {
        let rows = first..(first + band).min(H as u32);
        let stats = renderer.draw_rows(t, &view, rows, &mut fb).unwrap();
        total.fallback_rows += stats.fallback_rows;
        total.fallback |= stats.fallback;
    }
    (pixels, total)
}

/// Back to front into an XRGB8888 framebuffer: every polygon blended over the last.
fn back_to_front(t: &TestTree, cam: &Camera) -> Vec<u32> {
    let mut pixels = vec![0u32; W * H];
    let mut fb = Xrgb8888Framebuffer::new(&mut pixels, W as u32, H as u32).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    Renderer::new(&mut ws)
        .background(BACKGROUND)
        .draw(t, &cam.view(t.centre()), &mut fb)
        .unwrap();
    pixels
}

/// A display: takes every pixel once (a second write panics) and keeps its colour; a
/// transparent span is never sent to it front to back.
struct Once(Vec<Option<Colour>>);

impl SpanSink for Once {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        for x in x_start..x_end {
            let old = self.0[y as usize * W + x as usize].replace(colour);
            assert!(old.is_none(), "({x}, {y}) written twice");
        }
    }

    fn write_once(&self) -> bool {
        true
    }
}

/// A painter's canvas that cannot read its pixels: back to front it draws a transparent
/// surface as its screen door (the sink's default), the last write showing.
struct Canvas(Vec<Option<Colour>>);

impl SpanSink for Canvas {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        for x in x_start..x_end {
            self.0[y as usize * W + x as usize] = Some(colour);
        }
    }
}

fn colours(pixels: &[u32]) -> Vec<Colour> {
    pixels
        .iter()
        .map(|&p| Colour::new((p >> 16) as u8, (p >> 8) as u8, p as u8))
        .collect()
}

fn max_difference(a: &[Colour], b: &[Colour]) -> u8 {
    a.iter()
        .zip(b)
        .map(|(p, q)| {
            p.r.abs_diff(q.r)
                .max(p.g.abs_diff(q.g))
                .max(p.b.abs_diff(q.b))
        })
        .max()
        .unwrap_or(0)
}

/// Front to back (whole, in bands, streamed) and back to front: the same composite within
/// a level a pane (each order rounds its own way), and the glass shows (it is not the
/// picture of the opaque box alone).
#[test]
fn every_path_composites_the_same_picture() {
    let t = glass_box();
    let mut opaque = t.clone();
    opaque.opacities.clear();
    for eye in views() {
        let cam = camera(eye);
        let (whole, stats) = front_to_back(&t, &cam, H as u32, 512);
        assert_eq!(stats.fallback_rows, 0);
        assert!(!stats.fallback);
        for band in [7, 1] {
            let (banded, _) = front_to_back(&t, &cam, band, 512);
            assert_eq!(banded, whole, "bands of {band} from {eye}");
        }
        let painted = back_to_front(&t, &cam);
        let d = max_difference(&colours(&painted), &colours(&whole));
        assert!(d <= 2, "back to front differs by {d} from {eye}");

        let mut display = Once(vec![None; W * H]);
        let (mut memory, mut ws) = (Memory::new(512), Workspace::<16, 12>::new());
        let stats = memory
            .renderer(&mut ws, H as u32)
            .draw(&t, &cam.view(t.centre()), &mut display)
            .unwrap();
        assert_eq!(stats.fallback_rows, 0);
        let streamed: Vec<Colour> = display.0.iter().map(|c| c.unwrap()).collect();
        assert_eq!(streamed, colours(&whole), "streamed from {eye}");

        let (solid, _) = front_to_back(&opaque, &cam, H as u32, 512);
        assert_ne!(solid, whole, "the glass shows from {eye}");
    }
}

/// An opaque scene draws the same pixels with composite memory as without, which it does
/// not touch.
#[test]
fn an_opaque_scene_ignores_the_composite_memory() {
    let mut t = glass_box();
    t.opacities.clear();
    for eye in views() {
        let cam = camera(eye);
        let (with, stats) = front_to_back(&t, &cam, H as u32, 64);
        assert_eq!(stats.fallback_rows, 0);
        let mut pixels = vec![0u32; W * H];
        let mut fb = Xrgb8888Framebuffer::new(&mut pixels, W as u32, H as u32).unwrap();
        let (mut intervals, mut counts) = (vec![(0u16, 0u16); 16 * H], vec![0u16; H]);
        let coverage = Coverage::new(&mut intervals, &mut counts, W as u32, H as u32).unwrap();
        let mut ws = Workspace::<16, 12>::new();
        let mut renderer = Renderer::new(&mut ws)
            .span_memory(coverage)
            .background(BACKGROUND);
        renderer.draw(&t, &cam.view(t.centre()), &mut fb).unwrap();
        assert_eq!(pixels, with, "from {eye}");
    }
}

/// With too little composite memory, rows fall back to screen-door transparency: every pixel
/// is sent once, each is the exact composite or the screen-door picture's (never a mix), and
/// some are the screen door's.
#[test]
fn rows_out_of_memory_fall_back_to_the_screen_door() {
    let t = glass_box();
    for eye in views() {
        let cam = camera(eye);
        let (exact, _) = front_to_back(&t, &cam, H as u32, 512);
        let exact = colours(&exact);
        let mut door = Canvas(vec![Some(BACKGROUND); W * H]);
        let mut ws = Workspace::<16, 12>::new();
        Renderer::new(&mut ws)
            .draw(&t, &cam.view(t.centre()), &mut door)
            .unwrap();
        let door: Vec<Colour> = door.0.iter().map(|c| c.unwrap()).collect();

        let mut display = Once(vec![None; W * H]);
        let (mut memory, mut ws) = (Memory::new(12), Workspace::<16, 12>::new());
        let stats = memory
            .renderer(&mut ws, H as u32)
            .draw(&t, &cam.view(t.centre()), &mut display)
            .unwrap();
        assert!(stats.fallback_rows > 0, "from {eye}");
        let mut screen_door = 0;
        for (k, c) in display.0.iter().enumerate() {
            let c = c.expect("every pixel is sent");
            assert!(
                c == exact[k] || c == door[k],
                "pixel {k} from {eye}: {c:?}, exact {:?}, screen door {:?}",
                exact[k],
                door[k]
            );
            screen_door += usize::from(c != exact[k]);
        }
        assert!(screen_door > 0, "from {eye}");
    }
}

/// What cannot be composited is refused before the first pixel.
#[test]
fn transparency_refusals() {
    let t = glass_box();
    let cam = camera(views()[0]);
    let view = cam.view(t.centre());
    // A display without composite memory.
    let mut display = Once(vec![None; W * H]);
    let (mut intervals, mut counts) = (vec![(0u16, 0u16); 16 * H], vec![0u16; H]);
    let coverage = Coverage::new(&mut intervals, &mut counts, W as u32, H as u32).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let result = Renderer::new(&mut ws)
        .span_memory(coverage)
        .draw(&t, &view, &mut display);
    assert_eq!(result, Err(RenderError::CompositeMemory));
    assert!(display.0.iter().all(Option::is_none));
    // A framebuffer without it: back to front, the same composite.
    let mut pixels = vec![0u32; W * H];
    let mut fb = Xrgb8888Framebuffer::new(&mut pixels, W as u32, H as u32).unwrap();
    let (mut intervals, mut counts) = (vec![(0u16, 0u16); 16 * H], vec![0u16; H]);
    let coverage = Coverage::new(&mut intervals, &mut counts, W as u32, H as u32).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    Renderer::new(&mut ws)
        .span_memory(coverage)
        .background(BACKGROUND)
        .draw(&t, &view, &mut fb)
        .unwrap();
    assert_eq!(pixels, back_to_front(&t, &cam));
    // Composite memory with fewer heads than rows.
    let (mut memory, mut ws) = (Memory::new(64), Workspace::<16, 12>::new());
    memory.heads.truncate(H - 1);
    let composite = Composite::new(&mut memory.runs, &mut memory.heads, H as u32);
    assert_eq!(composite.err(), Some(RenderError::CompositeMemory));
    let _ = &mut ws;
    // Anti-aliased.
    #[cfg(feature = "antialias")]
    {
        use crate::pending::{Pending, PendingPixel};
        let mut records = vec![PendingPixel::default(); 256];
        let mut heads = vec![0u16; H];
        let pending = Pending::new(&mut records, &mut heads, H as u32).unwrap();
        let (mut memory, mut ws) = (Memory::new(64), Workspace::<16, 12>::new());
        let mut display = Once(vec![None; W * H]);
        let result =
            memory
                .renderer(&mut ws, H as u32)
                .antialias(pending)
                .draw(&t, &view, &mut display);
        assert_eq!(result, Err(RenderError::AntialiasedTransparency));
    }
}

/// Scan order keeps the composite in its memory: the frame read out is the streamed frame's
/// in RGB565, with enough composite memory and with too little (the screen door's rows).
#[cfg(feature = "scan-order")]
#[test]
fn scan_order_reads_out_the_streamed_composite() {
    use crate::display::Rgb565Framebuffer;
    use crate::scan::{ScanMemory, ScanNode};
    let t = glass_box();
    for eye in views() {
        let cam = camera(eye);
        let view = cam.view(t.centre());
        for runs in [512, 12] {
            let mut expected = vec![0u16; W * H];
            let mut fb = Rgb565Framebuffer::new(&mut expected, W as u32, H as u32).unwrap();
            let (mut memory, mut ws) = (Memory::new(runs), Workspace::<16, 12>::new());
            let streamed = memory
                .renderer(&mut ws, H as u32)
                .draw(&t, &view, &mut fb)
                .unwrap();
            assert_eq!(streamed.fallback_rows > 0, runs == 12, "from {eye}");

            let mut nodes = vec![ScanNode::EMPTY; 4096];
            let mut heads = vec![0u16; H];
            let scan = ScanMemory::new(&mut nodes, &mut heads, W as u32, H as u32).unwrap();
            let (mut composite_runs, mut composite_heads) =
                (vec![CompositeRun::default(); runs], vec![0u16; H]);
            let composite =
                Composite::new(&mut composite_runs, &mut composite_heads, H as u32).unwrap();
            let mut ws = Workspace::<16, 12>::new();
            let mut renderer = Renderer::new(&mut ws)
                .scan_memory(scan)
                .composite_memory(composite)
                .background(BACKGROUND);
            let frame = renderer.draw_scan(&t, &view).unwrap();
            assert_eq!(frame.stats().fallback_rows, streamed.fallback_rows);
            let pixels: Vec<u16> = frame.pixels().collect();
            assert_eq!(pixels, expected, "scan order with {runs} runs from {eye}");
        }
    }
}
