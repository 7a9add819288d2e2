extern crate std;

use glam::{DVec3, Vec3};
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

use super::testing::*;
use super::*;
use crate::camera::{Camera, LocalView, Pose};
use crate::coverage::Coverage;
use crate::display::testing::MockTarget;
use crate::display::{Colour, SpanSink};
use crate::error::RenderError;
use crate::fill::{self, FixedPoint};
use crate::read::Node;
use crate::read::Scene;
use crate::traverse::testing::{box_faces, TestTree};
use crate::traverse::Order;

/// A framebuffer that also counts how often each pixel is written.
struct Frame {
    width: u32,
    pixels: Vec<Colour>,
    writes: Vec<u32>,
    spans: usize,
}

impl Frame {
    fn new(width: u32, height: u32) -> Self {
        let n = (width * height) as usize;
        Frame {
            width,
            pixels: vec![Colour::default(); n],
            writes: vec![0; n],
            spans: 0,
        }
    }
    fn at(&self, x: u32, y: u32) -> Colour {
        self.pixels[(y * self.width + x) as usize]
    }
}

impl SpanSink for Frame {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        self.spans += 1;
        for x in x_start..x_end {
            let i = (y * self.width + x) as usize;
            self.pixels[i] = colour;
            self.writes[i] += 1;
        }
    }
}

const FACE_COLOURS: [Colour; 6] = [
    Colour::new(255, 0, 0),
    Colour::new(0, 255, 0),
    Colour::new(0, 0, 255),
    Colour::new(255, 255, 0),
    Colour::new(0, 255, 255),
    Colour::new(255, 0, 255),
];

/// The box [-1, 1]^3 as one convex node, each face its own colour, ids 100.. per face.
fn coloured_box() -> TestTree {
    let mut t = TestTree::default();
    let (first, count) = box_faces(
        &mut t,
        Vec3::splat(-1.0),
        Vec3::splat(1.0),
        Colour::default(),
    );
    for (p, c) in t.polygons.iter_mut().zip(FACE_COLOURS) {
        p.colour = c;
    }
    t.nodes.push(Node::Convex {
        first,
        count,
        child: None,
    });
    t.ids = Some((100..106).collect());
    t
}

fn camera(eye: DVec3, w: u32, h: u32) -> Camera {
    Camera::look_at(Pose::new(eye, DVec3::ZERO), 60.0, w, h, 0.01).unwrap()
}

#[test]
fn the_nearest_face_wins() {
    let t = coloured_box();
    for (eye, face) in [
        (DVec3::new(0.0, 0.0, 6.0), 5),
        (DVec3::new(0.0, 0.0, -6.0), 4),
        (DVec3::new(6.0, 0.5, 0.3), 1),
        (DVec3::new(0.2, -6.0, 0.1), 2),
    ] {
        let mut ws = Workspace::<4, 16>::new();
        let mut frame = Frame::new(64, 48);
        let stats = draw_test_frame(
            &t,
            &camera(eye, 64, 48),
            &mut ws,
            Paint::Colours,
            &mut frame,
        )
        .unwrap();
        assert_eq!(frame.at(32, 24), FACE_COLOURS[face], "eye {eye}");
        if cfg!(feature = "stats") {
            assert_eq!(stats.polygons_visited, 6);
            assert_eq!(
                stats.pixels_written,
                frame.writes.iter().map(|&w| u64::from(w)).sum::<u64>()
            );
        }
        // Corners of the image see the background.
        assert_eq!(frame.at(0, 0), Colour::default());
    }
}

#[test]
fn polygons_drawn_counts_only_what_survives_clipping() {
    let t = coloured_box();
    let mut ws = Workspace::<4, 16>::new();
    // Eye at the box centre looking at +z with a 60 degree cone: the +z face fills the
    // image, the side faces lie outside the cone (they would need z >= tan(60) = 1.73) and
    // the -z face is behind the eye.
    let cam = Camera::look_at(
        Pose::new(DVec3::ZERO, DVec3::new(0.0, 0.0, 1.0)),
        60.0,
        32,
        32,
        0.01,
    )
    .unwrap();
    let mut frame = Frame::new(32, 32);
    let stats = draw_test_frame(&t, &cam, &mut ws, Paint::Colours, &mut frame).unwrap();
    // The whole image is the +z face.
    assert!(frame.pixels.iter().all(|&c| c == FACE_COLOURS[5]));
    // Without the `stats` feature the counters read 0.
    let counted = |n: u64| if cfg!(feature = "stats") { n } else { 0 };
    assert_eq!(stats.polygons_visited, counted(6));
    assert_eq!(stats.polygons_drawn, counted(1));
    assert_eq!(stats.pixels_written, counted(32 * 32));
}

#[cfg(feature = "ids")]
#[test]
fn id_images_hold_id_plus_one() {
    let t = coloured_box();
    let mut ws = Workspace::<4, 16>::new();
    let mut frame = Frame::new(40, 40);
    draw_test_frame(
        &t,
        &camera(DVec3::new(0.0, 0.0, 6.0), 40, 40),
        &mut ws,
        Paint::Ids,
        &mut frame,
    )
    .unwrap();
    assert_eq!(frame.at(20, 20), Colour::new(0, 0, 106));
    assert_eq!(id_colour(0x01_02_03 - 1), Colour::new(1, 2, 3));
    assert_eq!(id_colour(0), Colour::new(0, 0, 1));
}

#[test]
fn refusals_happen_before_any_pixel() {
    let mut t = coloured_box();
    let cam = camera(DVec3::new(0.0, 0.0, 6.0), 16, 16);
    let mut frame = Frame::new(16, 16);
    // Stack too small for the depth-1 tree.
    let r = draw_test_frame(
        &t,
        &cam,
        &mut Workspace::<0, 16>::new(),
        Paint::Colours,
        &mut frame,
    );
    assert_eq!(
        r,
        Err(RenderError::StackTooSmall {
            needed: 1,
            available: 0
        })
    );
    // Quads need 4 + 5 clip vertices.
    let r = draw_test_frame(
        &t,
        &cam,
        &mut Workspace::<1, 8>::new(),
        Paint::Colours,
        &mut frame,
    );
    assert_eq!(
        r,
        Err(RenderError::PolygonTooLarge {
            needed: 9,
            available: 8
        })
    );
    assert!(draw_test_frame(
        &t,
        &cam,
        &mut Workspace::<1, 9>::new(),
        Paint::Colours,
        &mut frame
    )
    .is_ok());
    // Larger buffers than the fill takes are capped at its maximum.
    t.polygons[0].vertex_count = 62;
    let r = draw_test_frame(
        &t,
        &cam,
        &mut Workspace::<1, 100>::new(),
        Paint::Colours,
        &mut frame,
    );
    assert_eq!(
        r,
        Err(RenderError::PolygonTooLarge {
            needed: 67,
            available: 64
        })
    );
    t.polygons[0].vertex_count = 4;
    // Ids asked of a file without ids.
    t.ids = None;
    let r = draw_test_frame(
        &t,
        &cam,
        &mut Workspace::<1, 9>::new(),
        Paint::Ids,
        &mut frame,
    );
    assert_eq!(r, Err(RenderError::NoIds));
    // An image too wide for 8 fractional bits in an i32.
    let wide = camera(DVec3::new(0.0, 0.0, 6.0), 1 << 23, 1);
    let r = draw_test_frame(
        &t,
        &wide,
        &mut Workspace::<1, 9>::new(),
        Paint::Colours,
        &mut frame,
    );
    assert_eq!(
        r,
        Err(RenderError::ImageTooLarge {
            width: 1 << 23,
            height: 1
        })
    );
    // The one successful render above drew; count the spans it wrote and check no refusal
    // added any.
    let spans = frame.spans;
    let mut fresh = Frame::new(16, 16);
    let _ = draw_test_frame(
        &t,
        &cam,
        &mut Workspace::<0, 16>::new(),
        Paint::Colours,
        &mut fresh,
    );
    let _ = draw_test_frame(
        &t,
        &cam,
        &mut Workspace::<1, 8>::new(),
        Paint::Colours,
        &mut fresh,
    );
    assert_eq!(fresh.spans, 0);
    assert!(spans > 0);
}

#[test]
fn snapping_rounds_to_nearest_and_clamps() {
    let p = snap::<8>(
        glam::Vec2::new(1.5 + 0.6 / 256.0, 2.0 - 0.4 / 256.0),
        10 << 8,
        10 << 8,
    );
    assert_eq!(p, FixedPoint::new(385, 512));
    let p = snap::<8>(glam::Vec2::new(-0.01, 10.01), 10 << 8, 10 << 8);
    assert_eq!(p, FixedPoint::new(0, 10 << 8));
    let p = snap::<8>(glam::Vec2::new(f32::NAN, f32::INFINITY), 10 << 8, 10 << 8);
    assert_eq!(p, FixedPoint::new(0, 10 << 8));
}

/// Two triangles `a b c` and `c d a` of a planar convex quad, in one convex node (ids 1, 2).
fn quad_pair(q: [Vec3; 4]) -> TestTree {
    let mut t = TestTree::default();
    let inside = q[0] + (q[1] - q[0]).cross(q[2] - q[0]);
    t.add_polygon(&[q[0], q[1], q[2]], inside, Colour::new(0, 0, 1));
    t.add_polygon(&[q[2], q[3], q[0]], inside, Colour::new(0, 0, 2));
    t.nodes.push(Node::Convex {
        first: 0,
        count: 2,
        child: None,
    });
    t
}

fn quad_strategy() -> impl Strategy<Value = [Vec3; 4]> {
    // Four points on an ellipse (sorted angles: convex) in a random plane.
    (
        (-3.0f32..3.0, -3.0f32..3.0, -3.0f32..3.0),
        (
            0.0f32..core::f32::consts::TAU,
            0.0f32..core::f32::consts::PI,
        ),
        (0.5f32..8.0, 0.5f32..8.0),
        [0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0],
    )
        .prop_map(|((cx, cy, cz), (yaw, pitch), (ra, rb), mut t)| {
            t.sort_by(f32::total_cmp);
            let (sy, cyaw) = (libm::sinf(yaw), libm::cosf(yaw));
            let (sp, cp) = (libm::sinf(pitch), libm::cosf(pitch));
            let u = Vec3::new(cyaw, 0.0, sy);
            let v = Vec3::new(-sy * cp, sp, cyaw * cp);
            let c = Vec3::new(cx, cy, cz);
            let step = [0.0f32, 0.25, 0.5, 0.75];
            let mut q = [Vec3::ZERO; 4];
            for k in 0..4 {
                // Spread the four angles over the quarters so the quad is not degenerate.
                let a = (step[k] + t[k] * 0.2) * core::f32::consts::TAU;
                q[k] = c + u * (ra * libm::cosf(a)) + v * (rb * libm::sinf(a));
            }
            q
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Two polygons sharing an edge: no pixel painted twice, and (when the quad is fully in
    /// front of the eye) no pixel well inside the quad left unpainted, whatever the clipping.
    #[test]
    fn shared_edges_are_watertight(q in quad_strategy(), ex in -2.0f64..2.0, ey in -2.0f64..2.0) {
        let t = quad_pair(q);
        let (w, h) = (48u32, 36u32);
        let eye = DVec3::new(ex, ey, 4.0);
        let cam = Camera::look_at(Pose::new(eye, DVec3::new(0.0, 0.0, 0.0)), 70.0, w, h, 0.05).unwrap();
        let mut ws = Workspace::<2, 8>::new();
        let mut frame = Frame::new(w, h);
        let stats = draw_test_frame(&t, &cam, &mut ws, Paint::Colours, &mut frame).unwrap();
        prop_assert!(frame.writes.iter().all(|&n| n <= 1), "a pixel painted twice");
        if cfg!(feature = "stats") {
            prop_assert_eq!(stats.pixels_written, frame.writes.iter().map(|&n| u64::from(n)).sum::<u64>());
        }
        // Gap check against the f64 reference projection of the whole quad.
        let proj: Option<Vec<(f64, f64)>> = q.iter().map(|p| {
            let c = cam.to_camera(p.as_dvec3());
            if c.z > 0.1 { cam.project(p.as_dvec3()) } else { None }
        }).collect();
        if let Some(s) = proj {
            let area2: f64 = (0..4).map(|k| {
                let (a, b) = (s[k], s[(k + 1) % 4]);
                a.0 * b.1 - a.1 * b.0
            }).sum();
            prop_assume!(area2.abs() > 1e-6);
            for y in 0..h {
                for x in 0..w {
                    let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
                    let deep = (0..4).all(|k| {
                        let (a, b) = (s[k], s[(k + 1) % 4]);
                        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                        let len = (dx * dx + dy * dy).sqrt();
                        let cross = dx * (py - a.1) - dy * (px - a.0);
                        len > 0.0 && cross * area2.signum() / len > 0.75
                    });
                    if deep {
                        prop_assert_eq!(frame.writes[(y * w + x) as usize], 1, "gap at {},{}", x, y);
                    }
                }
            }
        }
    }
}

/// Rendering from `.peel` bytes through [`Scene`] gives the in-memory tree's image, with the
/// scene centre honoured.
#[test]
#[cfg_attr(
    not(all(feature = "large-scenes", feature = "wide-vertices")),
    ignore = "the test encoder writes f32 vertices and u32 fields"
)]
fn scene_renders_like_the_in_memory_tree() {
    let mut t = coloured_box();
    t.centre = [1000.0, -50.0, 20.0];
    let bytes = crate::traverse::testing::encode(&t);
    let scene = Scene::parse(&bytes).unwrap();
    let eye = DVec3::new(1003.0, -48.0, 25.0);
    let cam = Camera::look_at(
        Pose::new(eye, DVec3::from_array(t.centre)),
        50.0,
        40,
        30,
        0.01,
    )
    .unwrap();
    let paints: &[Paint] = if cfg!(feature = "ids") {
        &[Paint::Colours, Paint::Ids]
    } else {
        &[Paint::Colours]
    };
    for &paint in paints {
        let (mut a, mut b) = (Frame::new(40, 30), Frame::new(40, 30));
        let sa = draw_test_frame(&t, &cam, &mut Workspace::<2, 9>::new(), paint, &mut a).unwrap();
        let sb =
            draw_test_frame(&scene, &cam, &mut Workspace::<2, 9>::new(), paint, &mut b).unwrap();
        assert_eq!(sa, sb);
        assert_eq!(a.pixels, b.pixels);
        assert!(sa.polygons_drawn >= 3 || !cfg!(feature = "stats"), "{sa:?}");
    }
    // The box is centred on the scene centre, so the image centre shows it.
    let mut f = Frame::new(40, 30);
    draw_test_frame(
        &scene,
        &cam,
        &mut Workspace::<2, 9>::new(),
        Paint::Colours,
        &mut f,
    )
    .unwrap();
    assert_ne!(f.at(20, 15), Colour::default());
}

/// [`render_view`] with the view of a camera draws exactly what the camera draws; the `f32`
/// [`LocalView::look_at`] draws the same picture up to pixels along edges; a bad view is refused
/// before any pixel.
#[test]
#[cfg_attr(
    not(all(feature = "large-scenes", feature = "wide-vertices")),
    ignore = "the test encoder writes f32 vertices and u32 fields"
)]
fn a_view_draws_what_its_camera_draws() {
    let mut t = coloured_box();
    t.centre = [1000.0, -50.0, 20.0];
    let bytes = crate::traverse::testing::encode(&t);
    let scene = Scene::parse(&bytes).unwrap();
    let (w, h) = (40u32, 30u32);
    let eye = DVec3::new(1003.0, -48.0, 25.0);
    let centre = DVec3::from_array(t.centre);
    let cam = Camera::look_at(Pose::new(eye, centre), 50.0, w, h, 0.01).unwrap();
    let draw = |view: Option<&LocalView>, order: Order| {
        let mut frame = Frame::new(w, h);
        let mut intervals = vec![(0u16, 0u16); 8 * h as usize];
        let mut counts = vec![0u16; h as usize];
        let cov = Coverage::new(&mut intervals, &mut counts, w, h).unwrap();
        let options = Options {
            order,
            ..Options::default()
        };
        let mut ws = Workspace::<2, 9>::new();
        let stats = match view {
            Some(v) => draw::<{ fill::SUBPIXEL_BITS }, _, _, 2, 9>(
                &scene,
                v,
                &mut ws,
                options,
                Memory::from(cov),
                &mut frame,
            ),
            None => draw_test_frame_with(
                &scene,
                &cam,
                &mut ws,
                options,
                Memory::from(cov),
                &mut frame,
            ),
        };
        (stats, frame.pixels)
    };
    for order in [Order::BackToFront, Order::FrontToBack] {
        let (sa, a) = draw(None, order);
        let (sb, b) = draw(Some(&cam.view(t.centre)), order);
        assert!(sa.is_ok() && a.iter().filter(|&&c| c != Colour::default()).count() > 100);
        assert_eq!((sa, a), (sb, b));
    }
    let focal = (f64::from(h) * 0.5 / (25f64).to_radians().tan()) as f32;
    let view = LocalView::look_at(
        (eye - centre).as_vec3(),
        Vec3::ZERO,
        Vec3::Y,
        focal,
        w,
        h,
        0.01,
    )
    .unwrap();
    let (_, reference) = draw(None, Order::FrontToBack);
    let (stats, image) = draw(Some(&view), Order::FrontToBack);
    assert!(stats.is_ok());
    let differ = image.iter().zip(&reference).filter(|(a, b)| a != b).count();
    assert!(differ <= 12, "{differ} pixels differ");
    let mut bad = view;
    bad.fx = 0.0;
    let (stats, image) = draw(Some(&bad), Order::FrontToBack);
    assert_eq!(stats, Err(RenderError::BadCamera));
    assert!(image.iter().all(|&c| c == Colour::default()));
}

/// Screen segments of every polygon edge of `t` (its centre is the origin), projected in
/// `f64`; `None` when a vertex is behind the near plane.
fn projected_edges(t: &TestTree, cam: &Camera) -> Option<Vec<[(f64, f64); 2]>> {
    let mut out = Vec::new();
    for p in &t.polygons {
        let n = u32::from(p.vertex_count);
        for i in 0..n {
            let a = cam.project(t.polygon_vertex(p, i).as_dvec3())?;
            let b = cam.project(t.polygon_vertex(p, (i + 1) % n).as_dvec3())?;
            out.push([a, b]);
        }
    }
    Some(out)
}

/// Distance from the centre of pixel `(x, y)` to the nearest segment of `edges`.
fn distance_to_edges(x: usize, y: usize, edges: &[[(f64, f64); 2]]) -> f64 {
    let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
    edges
        .iter()
        .map(|&[(ax, ay), (bx, by)]| {
            let (dx, dy) = (bx - ax, by - ay);
            let len2 = dx * dx + dy * dy;
            let s = if len2 > 0.0 {
                (((px - ax) * dx + (py - ay) * dy) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let (qx, qy) = (ax + s * dx - px, ay + s * dy - py);
            (qx * qx + qy * qy).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Pixels where `a` and `b` differ (in coverage or colour) must lie within `tolerance` pixels
/// of a projected edge; returns how many differ.
fn differences_near_edges<const W: usize, const H: usize>(
    a: &MockTarget<W, H>,
    b: &MockTarget<W, H>,
    edges: &[[(f64, f64); 2]],
    tolerance: f64,
) -> usize {
    let mut differ = 0;
    for y in 0..H {
        for x in 0..W {
            if a.get(x, y) != b.get(x, y) {
                differ += 1;
                let d = distance_to_edges(x, y, edges);
                assert!(
                    d <= tolerance,
                    "pixel ({x}, {y}) differs {d} px away from every edge\n{a}\n{b}"
                );
            }
        }
    }
    differ
}

/// The whole render path (traverse, clip, project, snap, fill) at `SUB = 0`: snapping to
/// whole pixels moves each vertex by at most half a pixel per axis, so the image equals the
/// `SUB = 8` one except within `sqrt(2) / 2` pixel of a projected edge; a shared edge is still
/// written exactly once, and front to back still writes every pixel once (`MockTarget::new()`
/// panics on overdraw).
#[test]
fn whole_pixel_precision_renders_the_same_scene_up_to_edges() {
    const W: usize = 48;
    const H: usize = 36;
    let tolerance = core::f64::consts::FRAC_1_SQRT_2 + 1e-3;

    // Two triangles sharing a diagonal, back to front, no overdraw allowed.
    let plane_z = |x: f32, y: f32| Vec3::new(x, y, 0.3 * x - 0.2 * y);
    let quads = [
        [
            Vec3::new(-2.3, -1.6, 0.0),
            Vec3::new(2.1, -1.2, 0.0),
            Vec3::new(1.7, 1.9, 0.0),
            Vec3::new(-1.9, 1.4, 0.0),
        ],
        [
            plane_z(-2.6, -0.4),
            plane_z(0.3, -2.2),
            plane_z(2.4, 0.9),
            plane_z(-0.8, 2.0),
        ],
    ];
    for q in quads {
        let t = quad_pair(q);
        for eye in [DVec3::new(0.4, 0.3, 5.0), DVec3::new(-3.0, 1.2, 4.1)] {
            let cam = camera(eye, W as u32, H as u32);
            let mut coarse = MockTarget::<W, H>::new();
            let stats = draw_test_frame_at::<0, TestTree, MockTarget<W, H>, 2, 8>(
                &t,
                &cam,
                &mut Workspace::new(),
                Paint::Colours,
                &mut coarse,
            )
            .unwrap();
            let mut fine = MockTarget::<W, H>::new();
            draw_test_frame_at::<8, TestTree, MockTarget<W, H>, 2, 8>(
                &t,
                &cam,
                &mut Workspace::new(),
                Paint::Colours,
                &mut fine,
            )
            .unwrap();
            if cfg!(feature = "stats") {
                assert_eq!(stats.polygons_drawn, 2, "{stats:?}");
                assert_eq!(stats.pixels_written, coarse.written_count() as u64);
            }
            assert!(coarse.written_count() > 300, "{coarse}");
            // Both triangles show.
            let colours = [Colour::new(0, 0, 1), Colour::new(0, 0, 2)];
            for c in colours {
                let n = (0..H)
                    .flat_map(|y| (0..W).map(move |x| (x, y)))
                    .filter(|&(x, y)| coarse.get(x, y) == Some(c))
                    .count();
                assert!(n > 50, "{c:?}: {n} pixels\n{coarse}");
            }
            let edges = projected_edges(&t, &cam).unwrap();
            let differ = differences_near_edges(&coarse, &fine, &edges, tolerance);
            assert!(
                differ < coarse.written_count() / 4,
                "{differ} pixels differ"
            );
        }
    }

    // A closed box, front to back with span memory: each pixel once, same picture as SUB = 8.
    let t = coloured_box();
    for eye in [
        DVec3::new(2.0, 1.4, 2.7),
        DVec3::new(-2.6, -1.0, 1.6),
        DVec3::new(0.5, 3.0, -1.8),
    ] {
        let cam = camera(eye, W as u32, H as u32);
        // Without `front-to-back` the frame is painted back to front (overdraw allowed).
        let target = || {
            if cfg!(feature = "front-to-back") {
                MockTarget::<W, H>::new()
            } else {
                MockTarget::<W, H>::allowing_overdraw()
            }
        };
        let mut frames = [target(), target()];
        let mut all_stats = [FrameStats::default(); 2];
        for (k, (frame, stats)) in frames.iter_mut().zip(&mut all_stats).enumerate() {
            let mut intervals = vec![(0u16, 0u16); 8 * H];
            let mut counts = [0u16; H];
            let cov = Coverage::new(&mut intervals, &mut counts, W as u32, H as u32).unwrap();
            let options = Options::default();
            *stats = if k == 0 {
                draw_test_frame_with_at::<0, _, _, 4, 16>(
                    &t,
                    &cam,
                    &mut Workspace::new(),
                    options,
                    Memory::from(cov),
                    frame,
                )
            } else {
                draw_test_frame_with_at::<8, _, _, 4, 16>(
                    &t,
                    &cam,
                    &mut Workspace::new(),
                    options,
                    Memory::from(cov),
                    frame,
                )
            }
            .unwrap();
        }
        let [coarse, fine] = &frames;
        let stats = all_stats[0];
        if cfg!(feature = "front-to-back") {
            assert!(!stats.fallback, "{stats:?}");
            assert_eq!(stats.distinct_pixels, Some(coarse.written_count() as u64));
        }
        if cfg!(all(feature = "stats", feature = "front-to-back")) {
            assert_eq!(stats.pixels_written, coarse.written_count() as u64);
            // Three faces are visible from each of these eyes.
            assert!(stats.polygons_drawn >= 3, "{stats:?}");
        }
        assert!(coarse.written_count() > 300, "{coarse}");
        let edges = projected_edges(&t, &cam).unwrap();
        let differ = differences_near_edges(coarse, fine, &edges, tolerance);
        assert!(
            differ < coarse.written_count() / 4,
            "{differ} pixels differ"
        );
        // Back to front at SUB = 0 paints the same picture (with overdraw).
        let mut painter = MockTarget::<W, H>::allowing_overdraw();
        draw_test_frame_at::<0, TestTree, MockTarget<W, H>, 4, 16>(
            &t,
            &cam,
            &mut Workspace::new(),
            Paint::Colours,
            &mut painter,
        )
        .unwrap();
        for y in 0..H {
            for x in 0..W {
                assert_eq!(coarse.get(x, y), painter.get(x, y), "({x}, {y})");
            }
        }
    }
}

#[test]
fn pixel_bounds_of_a_screen_box_round_outwards_and_saturate() {
    use super::painter::{ceil_pixel, floor_pixel};
    assert_eq!(ceil_pixel(0.3), 1);
    assert_eq!(ceil_pixel(2.0), 2);
    assert_eq!(ceil_pixel(-1.5), 0);
    assert_eq!(ceil_pixel(f32::NAN), 0);
    assert_eq!(ceil_pixel(1e20), u32::MAX);
    assert_eq!(floor_pixel(2.7), 2);
    assert_eq!(floor_pixel(-0.5), 0);
    assert_eq!(floor_pixel(f32::NAN), 0);
}

/// The box seen from a corner, 24 x 12, front to back with the background: a mock target that
/// panics on overdraw gets every pixel once, the background (`D`, drawn last) around the three
/// faces; drawn in bands of 5 rows (the last one of 2), or of 1, the same picture.
#[test]
fn a_streamed_frame_writes_every_pixel_once_whole_or_in_bands() {
    const W: usize = 24;
    const H: usize = 12;
    let t = coloured_box();
    let view = camera(DVec3::new(1.5, 1.2, 2.0), W as u32, H as u32).view([0.0; 3]);
    let background = Colour::new(1, 2, 3);
    // Without the `front-to-back` feature the frame is painted back to front: overdraw.
    let once = cfg!(feature = "front-to-back");
    let picture = |band: u32| {
        let mut target = if once {
            MockTarget::<W, H>::new()
        } else {
            MockTarget::<W, H>::allowing_overdraw()
        };
        let (mut intervals, mut counts) = ([(0u16, 0u16); 8 * H], [0u16; H]);
        let coverage = Coverage::new(&mut intervals, &mut counts, W as u32, band).unwrap();
        let mut ws = Workspace::<4, 16>::new();
        let mut renderer = Renderer::new(&mut ws)
            .span_memory(coverage)
            .background(background);
        for first in (0..H as u32).step_by(band as usize) {
            let rows = first..(first + band).min(H as u32);
            let stats = renderer.draw_rows(&t, &view, rows, &mut target).unwrap();
            assert_eq!(stats.fallback, !once);
        }
        assert_eq!(target.written_count(), W * H);
        let colours: Vec<_> = (0..H * W).map(|k| target.get(k % W, k / W)).collect();
        (std::format!("{target}"), colours)
    };
    let (whole, colours) = picture(H as u32);
    // (Back to front the letters differ: the background is drawn first.)
    if once {
        insta::assert_snapshot!(whole, @r"
    DDDDDDDDDDDDDDDDDDDDDDDD
    DDDDDDDDDDDDDDDDDDDDDDDD
    DDDDDAAAABBBBBBBCCDDDDDD
    DDDDDDAAAAAAAACCCDDDDDDD
    DDDDDDAAAAAAAACCCDDDDDDD
    DDDDDDAAAAAAAACCCDDDDDDD
    DDDDDDAAAAAAAACCCDDDDDDD
    DDDDDDDAAAAAAACCCDDDDDDD
    DDDDDDDAAAAAAACCDDDDDDDD
    DDDDDDDAAAAAACCCDDDDDDDD
    DDDDDDDDDAAAACCDDDDDDDDD
    DDDDDDDDDDAAACCDDDDDDDDD
        ");
    }
    // (Compared by colour: the letters follow the order colours are first drawn.)
    assert_eq!(picture(5).1, colours);
    assert_eq!(picture(1).1, colours);
}

#[test]
fn rows_outside_the_image_or_span_memory_shorter_than_the_band_are_errors() {
    let t = coloured_box();
    let view = camera(DVec3::new(3.0, 2.5, 4.0), 16, 8).view([0.0; 3]);
    let mut target = MockTarget::<16, 8>::allowing_overdraw();
    let mut ws = Workspace::<4, 16>::new();
    let mut renderer = Renderer::new(&mut ws);
    assert_eq!(
        renderer.draw_rows(&t, &view, 4..9, &mut target),
        Err(RenderError::RowsOutsideImage {
            start: 4,
            end: 9,
            height: 8
        })
    );
    #[allow(clippy::reversed_empty_ranges)]
    let backwards = 5..4;
    assert!(renderer
        .draw_rows(&t, &view, backwards, &mut target)
        .is_err());
    // No rows: nothing drawn, not an error.
    assert!(renderer.draw_rows(&t, &view, 3..3, &mut target).is_ok());
    assert_eq!(target.written_count(), 0);
    let (mut intervals, mut counts) = ([(0u16, 0u16); 8 * 4], [0u16; 4]);
    let coverage = Coverage::new(&mut intervals, &mut counts, 16, 4).unwrap();
    let mut renderer = Renderer::new(&mut ws).span_memory(coverage);
    // (Without the `front-to-back` feature span memory is never used, so never checked.)
    if cfg!(feature = "front-to-back") {
        assert_eq!(
            renderer.draw_rows(&t, &view, 0..5, &mut target),
            Err(RenderError::SpanMemory)
        );
    }
    assert!(renderer.draw_rows(&t, &view, 4..8, &mut target).is_ok());
    assert!(target.written_count() > 0);
}
