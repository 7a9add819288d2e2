//! Smooth shading through every path of a frame: the same pixels whichever way the spans go.

extern crate std;

use glam::{DVec3, Vec3};
use std::collections::BTreeSet;
use std::vec;
use std::vec::Vec;

use super::*;
use crate::camera::{Camera, Pose};
use crate::coverage::Coverage;
use crate::display::{Colour, Rgb565Framebuffer, SpanSink, Xrgb8888Framebuffer};
use crate::read::layout::polygon_flags::{INTERIOR_BACK, SMOOTH};
use crate::read::Node;
use crate::traverse::testing::{box_faces, TestTree};

const W: usize = 32;
const H: usize = 24;
const BACKGROUND: Colour = Colour::new(0, 0, 40);

/// The box [-1, 1]^3, one convex node, its faces smooth in `kd`: each corner's front
/// intensity a function of its position, its back's another, so every face varies.
fn smooth_box(kd: Colour) -> TestTree {
    let mut t = TestTree::default();
    let (first, count) = box_faces(&mut t, Vec3::splat(-1.0), Vec3::ONE, kd);
    t.nodes.push(Node::Convex {
        first,
        count,
        child: None,
    });
    for (k, p) in t.polygons.iter_mut().enumerate() {
        p.flags |= SMOOTH | if k % 2 == 0 { INTERIOR_BACK } else { 0 };
    }
    t.shades = t
        .vertices
        .iter()
        .map(|v| {
            let s = 30.0 + 45.0 * (v.x + 1.0) + 30.0 * (v.y + 1.0) + 20.0 * (v.z + 1.0);
            [s as u8, 255 - s as u8]
        })
        .collect();
    t
}

/// A display that takes every pixel once (a second write panics) and keeps its colour.
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

fn camera(eye: DVec3) -> Camera {
    Camera::look_at(Pose::new(eye, DVec3::ZERO), 60.0, W as u32, H as u32, 0.01).unwrap()
}

/// Front to back into an XRGB8888 framebuffer, in bands of `band` rows.
fn framebuffer(t: &TestTree, cam: &Camera, band: u32) -> Vec<u32> {
    let mut pixels = vec![0u32; W * H];
    let mut fb = Xrgb8888Framebuffer::new(&mut pixels, W as u32, H as u32).unwrap();
    let (mut intervals, mut counts) = (vec![(0u16, 0u16); 16 * H], vec![0u16; H]);
    let coverage = Coverage::new(&mut intervals, &mut counts, W as u32, band).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let mut renderer = Renderer::new(&mut ws)
        .span_memory(coverage)
        .background(BACKGROUND);
    let view = cam.view(t.centre());
    for first in (0..H as u32).step_by(band as usize) {
        let rows = first..(first + band).min(H as u32);
        let stats = renderer.draw_rows(t, &view, rows, &mut fb).unwrap();
        assert!(!stats.fallback);
    }
    pixels
}

/// One whole frame front to back into `sink`.
fn front_to_back<S: SpanSink>(t: &TestTree, cam: &Camera, sink: &mut S) {
    let (mut intervals, mut counts) = (vec![(0u16, 0u16); 16 * H], vec![0u16; H]);
    let coverage = Coverage::new(&mut intervals, &mut counts, W as u32, H as u32).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    Renderer::new(&mut ws)
        .span_memory(coverage)
        .background(BACKGROUND)
        .draw(t, &cam.view(t.centre()), sink)
        .unwrap();
}

/// Back to front, no span memory: every polygon painted over the last.
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

fn colours(pixels: &[u32]) -> Vec<Colour> {
    pixels
        .iter()
        .map(|&p| Colour::new((p >> 16) as u8, (p >> 8) as u8, p as u8))
        .collect()
}

fn views() -> [DVec3; 4] {
    [
        DVec3::new(1.8, 1.1, 2.6),
        DVec3::new(-2.2, -1.4, 1.6),
        DVec3::new(0.3, 2.9, -1.5),
        // Inside the box: its faces' other sides.
        DVec3::new(0.2, -0.3, 0.1),
    ]
}

/// A smooth face is a gradient: more colours than faces, each pixel within its corners'
/// range, and not the flat picture of the same box.
#[test]
fn smooth_faces_are_gradients_within_their_corners() {
    let t = smooth_box(Colour::grey(255));
    let mut flat = t.clone();
    flat.shades.clear();
    for eye in views() {
        let cam = camera(eye);
        let pixels = colours(&framebuffer(&t, &cam, H as u32));
        let faces: Vec<Colour> = pixels
            .iter()
            .copied()
            .filter(|&c| c != BACKGROUND)
            .collect();
        assert!(faces.len() > W * H / 3, "the box fills the view from {eye}");
        let distinct: BTreeSet<u8> = faces.iter().map(|c| c.r).collect();
        assert!(distinct.len() > 12, "{} levels from {eye}", distinct.len());
        let (lo, hi) = t
            .shades
            .iter()
            .flatten()
            .fold((255, 0), |(lo, hi), &s| (u8::min(lo, s), u8::max(hi, s)));
        for c in &faces {
            assert!(
                c.r == c.g && c.g == c.b,
                "a grey material stays grey: {c:?}"
            );
            assert!((lo..=hi).contains(&c.r), "{} outside {lo}..={hi}", c.r);
        }
        assert_ne!(pixels, colours(&framebuffer(&flat, &cam, H as u32)));
    }
}

/// Whole frame, bands, back to front, streamed once per pixel into a display, and scan
/// order: one picture.
#[test]
fn every_path_draws_the_same_smooth_pixels() {
    let t = smooth_box(Colour::new(250, 180, 90));
    for eye in views() {
        let cam = camera(eye);
        let whole = framebuffer(&t, &cam, H as u32);
        assert_eq!(framebuffer(&t, &cam, 5), whole, "bands of 5 from {eye}");
        assert_eq!(framebuffer(&t, &cam, 1), whole, "bands of 1 from {eye}");
        assert_eq!(back_to_front(&t, &cam), whole, "back to front from {eye}");

        // Streamed: a pixel written twice panics.
        let mut target = Once(vec![None; W * H]);
        front_to_back(&t, &cam, &mut target);
        let streamed: Vec<Colour> = target.0.iter().map(|c| c.unwrap()).collect();
        assert_eq!(streamed, colours(&whole), "streamed from {eye}");

        // Scan order, dithered (the default) or not, as the RGB565 framebuffer.
        #[cfg(feature = "scan-order")]
        for dither in [true, false] {
            use crate::scan::{ScanMemory, ScanNode};
            let mut expected = vec![0u16; W * H];
            let mut fb = Rgb565Framebuffer::new(&mut expected, W as u32, H as u32).unwrap();
            fb.set_dithering(dither);
            front_to_back(&t, &cam, &mut fb);
            let mut nodes = vec![ScanNode::EMPTY; 4096];
            let mut heads = vec![0u16; H];
            let mut memory = ScanMemory::new(&mut nodes, &mut heads, W as u32, H as u32).unwrap();
            assert!(memory.dithering());
            memory.set_dithering(dither);
            let mut ws = Workspace::<16, 12>::new();
            let mut renderer = Renderer::new(&mut ws)
                .scan_memory(memory)
                .background(BACKGROUND);
            let frame = renderer.draw_scan(&t, &cam.view(t.centre())).unwrap();
            let scan: Vec<u16> = frame.pixels().collect();
            assert_eq!(scan, expected, "scan order (dither {dither}) from {eye}");
            let mut row = vec![0u16; W];
            for y in 0..H {
                frame.row_into(y as u32, &mut row);
                assert_eq!(row, expected[y * W..(y + 1) * W], "row {y} from {eye}");
            }
        }
    }
}

/// RGB565 framebuffers dither shaded spans unless told not to, and leave flat ones alone.
#[test]
fn rgb565_dithers_shaded_spans_only() {
    let cam = camera(views()[0]);
    let draw = |t: &TestTree, dither: bool| {
        let mut pixels = vec![0u16; W * H];
        let mut fb = Rgb565Framebuffer::new(&mut pixels, W as u32, H as u32).unwrap();
        fb.set_dithering(dither);
        let mut ws = Workspace::<16, 12>::new();
        Renderer::new(&mut ws)
            .background(BACKGROUND)
            .draw(t, &cam.view(t.centre()), &mut fb)
            .unwrap();
        pixels
    };
    let smooth = smooth_box(Colour::new(250, 180, 90));
    assert_ne!(draw(&smooth, true), draw(&smooth, false));
    let mut flat = smooth.clone();
    flat.shades.clear();
    assert_eq!(draw(&flat, true), draw(&flat, false));
}

/// A view from close by, where the window clips the faces: the clipped points take the
/// plane's intensities, so the picture stays a gradient within the corners' range, and the
/// streamed frame is the framebuffer's.
#[test]
fn clipped_smooth_faces_stay_within_their_corners() {
    let t = smooth_box(Colour::grey(255));
    let cam = camera(DVec3::new(0.5, 0.4, 1.8));
    let pixels = colours(&framebuffer(&t, &cam, H as u32));
    assert!(
        pixels.iter().all(|&c| c != BACKGROUND),
        "the box fills the view"
    );
    let (lo, hi) = t
        .shades
        .iter()
        .flatten()
        .fold((255, 0), |(lo, hi), &s| (u8::min(lo, s), u8::max(hi, s)));
    assert!(pixels.iter().all(|c| (lo..=hi).contains(&c.r)));
    let distinct: BTreeSet<u8> = pixels.iter().map(|c| c.r).collect();
    assert!(distinct.len() > 8);
    assert_eq!(back_to_front(&t, &cam), framebuffer(&t, &cam, 3));
}

/// Anti-aliased, a pixel inside one face takes its centre's shade: within one level of the
/// plain frame's (the two gradients are the same plane, rounded on different grids).
#[cfg(feature = "antialias")]
#[test]
fn antialiased_smooth_pixels_inside_a_face_are_the_plain_ones() {
    use crate::pending::{Pending, PendingPixel};
    let t = smooth_box(Colour::grey(255));
    for eye in views().into_iter().take(3) {
        let cam = camera(eye);
        let plain = colours(&framebuffer(&t, &cam, H as u32));
        let mut ids = vec![0u32; W * H];
        {
            let mut fb = Xrgb8888Framebuffer::new(&mut ids, W as u32, H as u32).unwrap();
            let mut with_ids = t.clone();
            with_ids.ids = Some((0..6).collect());
            let mut ws = Workspace::<16, 12>::new();
            Renderer::new(&mut ws)
                .ids()
                .draw(&with_ids, &cam.view(t.centre()), &mut fb)
                .unwrap();
        }
        let mut pixels = vec![0u32; W * H];
        let mut fb = Xrgb8888Framebuffer::new(&mut pixels, W as u32, H as u32).unwrap();
        let (mut intervals, mut counts) = (vec![(0u16, 0u16); 32 * H], vec![0u16; H]);
        let mut pool = vec![PendingPixel::default(); 2048];
        let mut heads = vec![0u16; H];
        let mut ws = Workspace::<16, 12>::new();
        let coverage = Coverage::new(&mut intervals, &mut counts, W as u32, H as u32).unwrap();
        let pending = Pending::new(&mut pool, &mut heads, H as u32).unwrap();
        let stats = Renderer::new(&mut ws)
            .span_memory(coverage)
            .antialias(pending)
            .background(BACKGROUND)
            .draw(&t, &cam.view(t.centre()), &mut fb)
            .unwrap();
        assert!(stats.antialiased);
        let aa = colours(&pixels);
        let mut inside = 0;
        for y in 1..H - 1 {
            for x in 1..W - 1 {
                let id = ids[y * W + x];
                let same = (y - 1..=y + 1).all(|v| (x - 1..=x + 1).all(|u| ids[v * W + u] == id));
                if id == 0 || !same {
                    continue;
                }
                inside += 1;
                let (a, p) = (aa[y * W + x], plain[y * W + x]);
                assert!(a.r.abs_diff(p.r) <= 1, "({x}, {y}) from {eye}: {a:?} {p:?}");
            }
        }
        assert!(
            inside > W * H / 8,
            "{inside} pixels inside faces from {eye}"
        );
    }
}
