//! Textures through every path of a frame, and against an exact ray cast: the same pixels
//! whichever way the spans go, each the texel under its centre or, by the runs' chords, one
//! next to it.

extern crate std;

use glam::{DVec3, Vec3};
use std::boxed::Box;
use std::vec;
use std::vec::Vec;

use super::*;
use crate::camera::{Camera, LocalView, Pose};
use crate::coverage::Coverage;
use crate::display::{rgb565_colour, Colour, Rgb565Framebuffer, SpanSink, Xrgb8888Framebuffer};
use crate::read::{Node, Texture};
use crate::traverse::testing::{box_faces, TestTree};

const W: usize = 96;
const H: usize = 72;
const BACKGROUND: Colour = Colour::new(0, 0, 40);
/// The texture's sides: `2^LOG2` texels.
const LOG2: u8 = 4;

/// The texel `(c, r)`'s RGB565 colour: red `2c`, green `4r`, blue `c + r`, all distinct, so
/// a pixel's colour names its texel.
fn texel(c: u32, r: u32) -> u16 {
    ((c * 2) << 11 | (r * 4) << 5 | (c + r)) as u16
}

/// The texel a colour names.
fn texel_of(colour: Colour) -> (u32, u32) {
    let c = colour.to_rgb565();
    (u32::from(c >> 12), u32::from((c >> 7) & 15))
}

/// How many textures face `k` of the box spans across its `s` and `t`.
fn repeats(k: usize) -> (f64, f64) {
    (1.0 + (k % 3) as f64, 1.0 + (k % 2) as f64)
}

/// The box [-1, 1]^3, one convex node, its faces textured (white, unlit): face `k` spans
/// [`repeats`] textures, its corners `0, 1, 2, 3` at `(0, 0)`, `(S, 0)`, `(S, T)`, `(0, T)`.
fn textured_box() -> TestTree {
    let mut t = TestTree::default();
    let (first, count) = box_faces(&mut t, Vec3::splat(-1.0), Vec3::ONE, Colour::grey(255));
    t.nodes.push(Node::Convex {
        first,
        count,
        child: None,
    });
    let side = 1u32 << LOG2;
    let bytes: Vec<u8> = (0..side * side)
        .flat_map(|i| texel(i % side, i / side).to_le_bytes())
        .collect();
    t.texture = Some(Texture {
        log2_width: LOG2,
        log2_height: LOG2,
        flags: 0,
        colours: &[],
        texels: Box::leak(bytes.into_boxed_slice()),
    });
    t.uvs = (0..6)
        .flat_map(|k| {
            let (s, t) = repeats(k);
            let (s, t) = ((s * 65536.0) as i32, (t * 65536.0) as i32);
            [[0, 0], [s, 0], [s, t], [0, t]]
        })
        .collect();
    t
}

fn camera(eye: DVec3) -> Camera {
    Camera::look_at(Pose::new(eye, DVec3::ZERO), 60.0, W as u32, H as u32, 0.01).unwrap()
}

fn views() -> [DVec3; 5] {
    [
        DVec3::new(1.8, 1.1, 2.6),
        DVec3::new(-2.2, -1.4, 1.6),
        // Grazing: the +y face at about 80 degrees from the view axis.
        DVec3::new(3.2, 1.25, 0.4),
        DVec3::new(0.3, 2.9, -1.5),
        // Inside the box: its faces' other sides, clipped by the window.
        DVec3::new(0.2, -0.3, 0.1),
    ]
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

/// Back to front, no span memory, into `sink`.
fn back_to_front<S: SpanSink>(t: &TestTree, cam: &Camera, sink: &mut S) {
    let mut ws = Workspace::<16, 12>::new();
    Renderer::new(&mut ws)
        .background(BACKGROUND)
        .draw(t, &cam.view(t.centre()), sink)
        .unwrap();
}

fn colours(pixels: &[u32]) -> Vec<Colour> {
    pixels
        .iter()
        .map(|&p| Colour::new((p >> 16) as u8, (p >> 8) as u8, p as u8))
        .collect()
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

/// The exact face and texel under screen point `(x, y)` (pixels, `f64`): the ray cast from
/// the eye through it onto the box, the face's coordinates at the hit.
fn cast(view: &LocalView, x: f64, y: f64) -> Option<(usize, (u32, u32))> {
    let v = |a: Vec3| a.as_dvec3();
    let d = v(view.right) * ((x - f64::from(view.cx)) / f64::from(view.fx))
        - v(view.up) * ((y - f64::from(view.cy)) / f64::from(view.fy))
        + v(view.forward);
    let o = v(view.eye);
    let t = textured_box();
    let mut best: Option<(f64, usize, DVec3)> = None;
    for k in 0..6 {
        let corner = |i: usize| v(t.vertices[k * 4 + i]);
        let (p0, p1, p3) = (corner(0), corner(1), corner(3));
        let n = (p1 - p0).cross(p3 - p0);
        let along = d.dot(n);
        if along == 0.0 {
            continue;
        }
        let hit = (p0 - o).dot(n) / along;
        let p = o + d * hit;
        let (a, b) = ((p - p0).dot(p1 - p0) / 4.0, (p - p0).dot(p3 - p0) / 4.0);
        let inside = (0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b);
        if hit > 0.0 && inside && best.is_none_or(|(h, _, _)| hit < h) {
            best = Some((hit, k, DVec3::new(a, b, 0.0)));
        }
    }
    let (_, k, ab) = best?;
    let (s, t) = repeats(k);
    let side = f64::from(1u32 << LOG2);
    let place = |u: f64| (u * side).floor().rem_euclid(side) as u32;
    Some((k, (place(ab.x * s), place(ab.y * t))))
}

/// Robust pixels (their centre and four points 1/16 pixel away on one face and one texel)
/// counted: `(robust, exact)`; every robust pixel is its texel or one next to it.
fn check_against_the_cast(pixels: &[Colour], view: &LocalView, what: &str) -> (usize, usize) {
    let side = 1u32 << LOG2;
    let (mut robust, mut exact) = (0, 0);
    for y in 0..H {
        for x in 0..W {
            let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
            let Some(centre) = cast(view, cx, cy) else {
                continue;
            };
            let e = 1.0 / 16.0;
            let around = [(e, 0.0), (-e, 0.0), (0.0, e), (0.0, -e)];
            if !around
                .iter()
                .all(|&(dx, dy)| cast(view, cx + dx, cy + dy) == Some(centre))
            {
                continue;
            }
            robust += 1;
            let got = texel_of(pixels[y * W + x]);
            let (c, r) = centre.1;
            if got == (c, r) {
                exact += 1;
                continue;
            }
            let near = |a: u32, b: u32| (a + side - b) % side <= 1 || (b + side - a) % side <= 1;
            assert!(
                near(got.0, c) && near(got.1, r),
                "{what}: pixel ({x}, {y}) shows texel {got:?}, the cast {:?}",
                (c, r)
            );
        }
    }
    (robust, exact)
}

/// Each robust pixel is the cast's texel, or one next to it; at least 99% are the cast's.
#[test]
fn textured_pixels_are_the_texels_under_their_centres() {
    let t = textured_box();
    let (mut robust, mut exact) = (0, 0);
    for eye in views() {
        let cam = camera(eye);
        let view = cam.view(t.centre());
        let pixels = colours(&framebuffer(&t, &cam, H as u32));
        let (r, e) = check_against_the_cast(&pixels, &view, &std::format!("from {eye}"));
        assert!(r > W * H / 8, "{r} robust pixels from {eye}");
        std::println!("{eye}: {e} of {r} robust pixels exact");
        (robust, exact) = (robust + r, exact + e);
    }
    assert!(
        exact * 100 >= robust * 99,
        "{exact} of {robust} robust pixels take the cast's texel"
    );
}

/// Whole frame, bands, back to front, streamed once per pixel, RGB565 (the texels stored as
/// they are) and scan order: one picture.
#[test]
fn every_path_draws_the_same_textured_pixels() {
    let t = textured_box();
    for eye in views() {
        let cam = camera(eye);
        let whole = framebuffer(&t, &cam, H as u32);
        assert_eq!(framebuffer(&t, &cam, 5), whole, "bands of 5 from {eye}");
        assert_eq!(framebuffer(&t, &cam, 1), whole, "bands of 1 from {eye}");
        let mut painted = vec![0u32; W * H];
        let mut fb = Xrgb8888Framebuffer::new(&mut painted, W as u32, H as u32).unwrap();
        back_to_front(&t, &cam, &mut fb);
        assert_eq!(painted, whole, "back to front from {eye}");

        let mut target = Once(vec![None; W * H]);
        let (mut intervals, mut counts) = (vec![(0u16, 0u16); 16 * H], vec![0u16; H]);
        let coverage = Coverage::new(&mut intervals, &mut counts, W as u32, H as u32).unwrap();
        let mut ws = Workspace::<16, 12>::new();
        Renderer::new(&mut ws)
            .span_memory(coverage)
            .background(BACKGROUND)
            .draw(&t, &cam.view(t.centre()), &mut target)
            .unwrap();
        let streamed: Vec<Colour> = target.0.iter().map(|c| c.unwrap()).collect();
        assert_eq!(streamed, colours(&whole), "streamed from {eye}");

        let mut rgb565 = vec![0u16; W * H];
        let mut fb = Rgb565Framebuffer::new(&mut rgb565, W as u32, H as u32).unwrap();
        back_to_front(&t, &cam, &mut fb);
        let expected: Vec<u16> = colours(&whole).iter().map(|c| c.to_rgb565()).collect();
        assert_eq!(rgb565, expected, "RGB565 from {eye}");
        assert!(rgb565.iter().all(|&c| rgb565_colour(c).to_rgb565() == c));

        #[cfg(feature = "scan-order")]
        {
            use crate::scan::{ScanMemory, ScanNode};
            let mut nodes = vec![ScanNode::EMPTY; 8192];
            let mut heads = vec![0u16; H];
            let memory = ScanMemory::new(&mut nodes, &mut heads, W as u32, H as u32).unwrap();
            let mut ws = Workspace::<16, 12>::new();
            let mut renderer = Renderer::new(&mut ws)
                .scan_memory(memory)
                .background(BACKGROUND);
            let frame = renderer.draw_scan(&t, &cam.view(t.centre())).unwrap();
            let scan: Vec<u16> = frame.pixels().collect();
            assert_eq!(scan, expected, "scan order from {eye}");
        }
    }
}

/// A lit textured face: each pixel the unlit texel times the polygon's colour.
#[test]
fn lighting_multiplies_the_texels() {
    let t = textured_box();
    let mut lit = t.clone();
    let kd = Colour::new(200, 120, 255);
    for p in &mut lit.polygons {
        p.colour = kd;
    }
    let cam = camera(views()[0]);
    let plain = colours(&framebuffer(&t, &cam, H as u32));
    let shaded = colours(&framebuffer(&lit, &cam, H as u32));
    for (p, s) in plain.iter().zip(&shaded) {
        if *p != BACKGROUND {
            assert_eq!(*s, crate::display::modulate(*p, kd));
        }
    }
}

/// Anti-aliased, a pixel inside a face takes its centre's texel: the plain frame's, or one
/// next to it (the chords run over the samples' span).
#[cfg(feature = "antialias")]
#[test]
fn antialiased_textured_pixels_inside_a_face_are_the_plain_ones() {
    use crate::pending::{Pending, PendingPixel};
    let t = textured_box();
    for eye in views().into_iter().take(3) {
        let cam = camera(eye);
        let view = cam.view(t.centre());
        let plain = colours(&framebuffer(&t, &cam, H as u32));
        let mut pixels = vec![0u32; W * H];
        let mut fb = Xrgb8888Framebuffer::new(&mut pixels, W as u32, H as u32).unwrap();
        let (mut intervals, mut counts) = (vec![(0u16, 0u16); 32 * H], vec![0u16; H]);
        let mut pool = vec![PendingPixel::default(); 4096];
        let mut heads = vec![0u16; H];
        let mut ws = Workspace::<16, 12>::new();
        let coverage = Coverage::new(&mut intervals, &mut counts, W as u32, H as u32).unwrap();
        let pending = Pending::new(&mut pool, &mut heads, H as u32).unwrap();
        let stats = Renderer::new(&mut ws)
            .span_memory(coverage)
            .antialias(pending)
            .background(BACKGROUND)
            .draw(&t, &view, &mut fb)
            .unwrap();
        assert!(stats.antialiased);
        let aa = colours(&pixels);
        let (mut inside, mut same) = (0, 0);
        for y in 1..H - 1 {
            for x in 1..W - 1 {
                let face = |u: usize, v: usize| cast(&view, u as f64 + 0.5, v as f64 + 0.5);
                let Some((k, _)) = face(x, y) else { continue };
                let whole = (y - 1..=y + 1)
                    .all(|v| (x - 1..=x + 1).all(|u| face(u, v).is_some_and(|f| f.0 == k)));
                if !whole {
                    continue;
                }
                inside += 1;
                let (a, p) = (texel_of(aa[y * W + x]), texel_of(plain[y * W + x]));
                same += usize::from(a == p);
                let near = |a: u32, b: u32| a.abs_diff(b) <= 1 || a.abs_diff(b) == 15;
                assert!(near(a.0, p.0) && near(a.1, p.1), "({x}, {y}) from {eye}");
            }
        }
        assert!(
            inside > W * H / 8,
            "{inside} pixels inside faces from {eye}"
        );
        assert!(same * 100 >= inside * 95, "{same} of {inside} from {eye}");
    }
}

/// Bilinear, switched on: another picture than the nearest texels', the same through the
/// framebuffer and streamed.
#[test]
fn bilinear_frames_blend_and_stream_alike() {
    let t = textured_box();
    let cam = camera(views()[0]);
    let draw = |bilinear: bool, sink: &mut dyn SpanSink| {
        let (mut intervals, mut counts) = (vec![(0u16, 0u16); 16 * H], vec![0u16; H]);
        let coverage = Coverage::new(&mut intervals, &mut counts, W as u32, H as u32).unwrap();
        let mut ws = Workspace::<16, 12>::new();
        let renderer = Renderer::new(&mut ws)
            .span_memory(coverage)
            .background(BACKGROUND);
        let mut renderer = if bilinear {
            renderer.bilinear()
        } else {
            renderer
        };
        renderer.draw(&t, &cam.view(t.centre()), sink).unwrap();
    };
    let mut nearest = vec![0u32; W * H];
    draw(
        false,
        &mut Xrgb8888Framebuffer::new(&mut nearest, W as u32, H as u32).unwrap(),
    );
    let mut blended = vec![0u32; W * H];
    draw(
        true,
        &mut Xrgb8888Framebuffer::new(&mut blended, W as u32, H as u32).unwrap(),
    );
    let differ = nearest.iter().zip(&blended).filter(|(a, b)| a != b).count();
    assert!(differ > W * H / 10, "{differ} pixels blended");
    let mut target = Once(vec![None; W * H]);
    draw(true, &mut target);
    let streamed: Vec<Colour> = target.0.iter().map(|c| c.unwrap()).collect();
    assert_eq!(streamed, colours(&blended));
}
