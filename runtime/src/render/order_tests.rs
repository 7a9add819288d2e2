//! Front to back against back to front: same image, each pixel once, culling and fallback.

extern crate std;

use glam::{DVec3, Vec3};
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

#[cfg(feature = "front-to-back")]
use super::painter::{NoCuts, Painter};
use super::testing::*;
use super::*;
use crate::camera::{Camera, Pose};
use crate::clip::Frustum;
use crate::coverage::Coverage;
use crate::display::testing::MockTarget;
use crate::display::Colour;
#[cfg(feature = "front-to-back")]
use crate::display::SpanSink;
#[cfg(feature = "front-to-back")]
use crate::fill::FixedPoint;
use crate::read::Node;
#[cfg(feature = "front-to-back")]
use crate::stats::Tally;
use crate::traverse::testing::{box_faces, TestTree};
use crate::traverse::Order;

const W: usize = 48;
const H: usize = 36;

/// Boxes `k = 0..n` of side `size[k]` at `centre[k]`, separated by split planes `x = ...`
/// (sorted by x so the planes really separate them), each box one convex node, colour per
/// face. Every node gets its bounding box.
fn boxes(centres: &[(Vec3, f32)]) -> TestTree {
    let mut sorted = centres.to_vec();
    sorted.sort_by(|a, b| a.0.x.total_cmp(&b.0.x));
    let mut t = TestTree::default();
    // Node layout: split_0 -> (+: split_1 ..., -: box_0). Build recursively as a chain.
    fn build(t: &mut TestTree, items: &[(Vec3, f32)], colour_base: u8) -> (u32, Vec3, Vec3) {
        let (c, r) = items[0];
        let (lo, hi) = (c - Vec3::splat(r), c + Vec3::splat(r));
        if items.len() == 1 {
            let (first, count) = box_faces(t, lo, hi, Colour::default());
            for (k, p) in t.polygons[first as usize..].iter_mut().enumerate() {
                p.colour = Colour::new(colour_base, 40 * k as u8, 255 - colour_base);
            }
            let i = t.add_node(Node::Convex {
                first,
                count,
                child: None,
            });
            t.bounds.resize(t.nodes.len(), None);
            t.bounds[i as usize] = Some((lo, hi));
            return (i, lo, hi);
        }
        let x = (hi.x + (items[1].0.x - items[1].1)) * 0.5;
        let plane = t.add_plane(Vec3::X, x);
        let i = t.add_node(Node::Convex {
            first: 0,
            count: 0,
            child: None,
        });
        let (back, blo, bhi) = build(t, &items[..1], colour_base);
        let (front, flo, fhi) = build(t, &items[1..], colour_base.wrapping_add(30));
        t.nodes[i as usize] = Node::Split {
            plane,
            front: Some(front),
            back: Some(back),
        };
        t.bounds.resize(t.nodes.len(), None);
        let (lo, hi) = (blo.min(flo), bhi.max(fhi));
        t.bounds[i as usize] = Some((lo, hi));
        (i, lo, hi)
    }
    // Keep boxes disjoint along x.
    let mut x = -6.0f32;
    for item in &mut sorted {
        item.0.x = x + item.1;
        x += 2.0 * item.1 + 0.3;
    }
    build(&mut t, &sorted, 20);
    t
}

fn camera(eye: DVec3, target: DVec3) -> Camera {
    Camera::look_at(Pose::new(eye, target), 70.0, W as u32, H as u32, 0.05).unwrap()
}

fn back_to_front(t: &TestTree, cam: &Camera, cull: bool) -> (MockTarget<W, H>, FrameStats) {
    let mut m = MockTarget::allowing_overdraw();
    let options = Options {
        order: Order::BackToFront,
        paint: Paint::Colours,
        cull,
    };
    let stats = draw_test_frame_with(
        t,
        cam,
        &mut Workspace::<16, 12>::new(),
        options,
        Memory::default(),
        &mut m,
    )
    .unwrap();
    (m, stats)
}

fn front_to_back<const SLOTS: usize>(
    t: &TestTree,
    cam: &Camera,
    mut target: MockTarget<W, H>,
) -> (MockTarget<W, H>, FrameStats) {
    let mut intervals = vec![(0u16, 0u16); SLOTS * H];
    let mut counts = [0u16; H];
    let cov = Coverage::new(&mut intervals, &mut counts, W as u32, H as u32).unwrap();
    let stats = draw_test_frame_with(
        t,
        cam,
        &mut Workspace::<16, 12>::new(),
        Options::default(),
        Memory::from(cov),
        &mut target,
    )
    .unwrap();
    (target, stats)
}

fn same_image(a: &MockTarget<W, H>, b: &MockTarget<W, H>) -> bool {
    (0..H).all(|y| (0..W).all(|x| a.get(x, y) == b.get(x, y)))
}

#[cfg(feature = "front-to-back")]
#[test]
fn front_to_back_draws_each_pixel_once_and_matches() {
    let t = boxes(&[(Vec3::ZERO, 1.0), (Vec3::ZERO, 1.5), (Vec3::ZERO, 0.7)]);
    for eye in [
        DVec3::new(0.5, 2.0, 9.0),
        DVec3::new(-7.0, 1.0, 3.0),
        DVec3::new(6.0, -3.0, -5.0),
    ] {
        let cam = camera(eye, DVec3::ZERO);
        let (reference, b2f) = back_to_front(&t, &cam, false);
        // `MockTarget::new()` panics on any pixel written twice.
        let (image, f2b) = front_to_back::<8>(&t, &cam, MockTarget::new());
        assert!(same_image(&reference, &image), "{reference}\n{image}");
        assert!(reference.written_count() > 50);
        assert_eq!(f2b.distinct_pixels, Some(image.written_count() as u64));
        assert!(!f2b.fallback);
        if cfg!(feature = "stats") {
            assert_eq!(f2b.pixels_written, image.written_count() as u64);
            assert_eq!(f2b.overdraw(), Some(1.0));
            // The painter overdraws (several boxes overlap on screen from these eyes).
            assert!(b2f.pixels_written > f2b.pixels_written, "{b2f:?} {f2b:?}");
        }
    }
}

#[cfg(feature = "front-to-back")]
#[test]
fn polygons_behind_covered_pixels_skip_the_fill() {
    // One box seen straight from the front: its front face hides the five others, whose
    // sample rectangles lie inside the front face's square.
    let t = boxes(&[(Vec3::ZERO, 1.0)]);
    let cam = camera(DVec3::new(-5.0, 0.0, 6.0), DVec3::new(-5.0, 0.0, 0.0));
    let (reference, _) = back_to_front(&t, &cam, false);
    let (image, f2b) = front_to_back::<8>(&t, &cam, MockTarget::new());
    assert!(same_image(&reference, &image), "{reference}\n{image}");
    assert!(image.written_count() > 50);
    if cfg!(feature = "stats") {
        assert_eq!(f2b.polygons_visited, 6, "{f2b:?}");
        assert_eq!(f2b.polygons_drawn, 1, "{f2b:?}");
        assert_eq!(f2b.polygons_culled_covered, 5, "{f2b:?}");
    }
}

#[cfg(feature = "front-to-back")]
#[test]
fn a_full_screen_stops_the_walk_and_culls_covered_subtrees() {
    // A big box right in front of the eye hides two boxes behind it.
    let mut t = TestTree::default();
    let (first, count) = box_faces(
        &mut t,
        Vec3::new(-20.0, -20.0, -1.0),
        Vec3::new(20.0, 20.0, 1.0),
        Colour::new(9, 9, 9),
    );
    let far = boxes(&[(Vec3::ZERO, 1.0), (Vec3::ZERO, 1.0)]);
    // Split z = -2: + side (the eye's) holds the wall, - side the far boxes.
    let plane = t.add_plane(Vec3::Z, -2.0);
    t.add_node(Node::Split {
        plane,
        front: Some(1),
        back: Some(2),
    });
    t.add_node(Node::Convex {
        first,
        count,
        child: None,
    });
    // Append `far` shifted to z = -6, its nodes renumbered after ours.
    let base_node = t.nodes.len() as u32;
    let base_poly = t.polygons.len() as u32;
    let base_plane = t.planes.len() as u32;
    let base_vertex = t.vertices.len() as u32;
    let shift = Vec3::new(0.0, 0.0, -6.0);
    t.vertices.extend(far.vertices.iter().map(|&v| v + shift));
    t.indices
        .extend(far.indices.iter().map(|&i| i + base_vertex));
    for p in &far.planes {
        t.planes.push(crate::read::Plane {
            normal: p.normal,
            d: p.d + p.normal.dot(shift),
        });
    }
    for p in &far.polygons {
        let mut p = *p;
        p.first_index += t.indices.len() as u32 - far.indices.len() as u32;
        t.polygons.push(p);
    }
    for n in &far.nodes {
        t.nodes.push(match *n {
            Node::Convex {
                first,
                count,
                child,
            } => Node::Convex {
                first: first + base_poly,
                count,
                child: child.map(|c| c + base_node),
            },
            Node::Split { plane, front, back } => Node::Split {
                plane: plane + base_plane,
                front: front.map(|c| c + base_node),
                back: back.map(|c| c + base_node),
            },
        });
    }
    t.bounds = vec![None; base_node as usize];
    t.bounds.extend(
        far.bounds
            .iter()
            .map(|b| b.map(|(lo, hi)| (lo + shift, hi + shift))),
    );
    let cam = camera(DVec3::new(0.0, 0.0, 5.0), DVec3::new(0.0, 0.0, -5.0));
    let (reference, _) = back_to_front(&t, &cam, false);
    let (image, stats) = front_to_back::<4>(&t, &cam, MockTarget::new());
    assert!(same_image(&reference, &image));
    assert_eq!(image.written_count(), W * H);
    assert!(stats.stopped_full, "{stats:?}");
    // The wall's back faces come after the front one in front-to-back order; the walk
    // stops before them and before the far boxes.
    assert!(stats.polygons_visited < 6, "{stats:?}");

    // Without the front face stopping everything (a wall with a hole would do the same):
    // check the covered-subtree test directly by letting the walk continue.
    let mut intervals = vec![(0u16, 0u16); 4 * H];
    let mut counts = [0u16; H];
    let mut cov = Coverage::new(&mut intervals, &mut counts, W as u32, H as u32).unwrap();
    let mut sink = MockTarget::<W, H>::new();
    // Pre-cover the frame except one pixel: the far boxes project into the middle.
    let stats = {
        let mut pre = crate::coverage::CoverageSink {
            coverage: &mut cov,
            sink: &mut sink,
            pixels: 0,
        };
        for y in 0..H as u32 {
            pre.span(y, 0, W as u32, Colour::new(1, 1, 1));
        }
        let _ = pre.pixels;
        // The render clears the coverage, so test the culling decision through `enter`.
        let view = cam.view(t.centre);
        let painter_frustum = Frustum::new(&view);
        let mut a = [Vec3::ZERO; 12];
        let mut b = [Vec3::ZERO; 12];
        let mut pts = [FixedPoint::default(); 12];
        let mut edges = [crate::fill::EdgeWalk::default(); 12];
        let painter = Painter::<8> {
            view: &view,
            rows: 0..view.height,
            frustum: painter_frustum,
            max_x: 0,
            max_y: 0,
            available: 12,
            paint: Paint::Colours,
            cull: true,
            cull_subtrees: true,
            filter: crate::display::Filter::Nearest,
            all_inside: false,
            clip_a: &mut a,
            clip_b: &mut b,
            points: &mut pts,
            edges: &mut edges,
            vertices: None,
            #[cfg(feature = "integer-vertices")]
            integer: None,
            antialias: None,
            composite: None,
            door: false,
            cuts: NoCuts,
        };
        let mut tally = Tally::default();
        // Without `bounds-culling` every subtree is entered.
        let culled = !painter.enter(&t, base_node, Some(&cov), &mut tally);
        assert_eq!(culled, cfg!(feature = "bounds-culling"));
        tally.report(None)
    };
    let counted = cfg!(all(feature = "stats", feature = "bounds-culling"));
    assert_eq!(stats.nodes_culled_covered, u64::from(counted));
}

#[test]
fn a_scene_wholly_in_view_is_drawn_unclipped_with_the_same_image() {
    let t = boxes(&[(Vec3::ZERO, 1.0), (Vec3::ZERO, 1.5), (Vec3::ZERO, 0.7)]);
    let cam = camera(DVec3::new(1.0, 3.0, 14.0), DVec3::new(-1.0, 0.0, 0.0));
    let view = cam.view(t.centre);
    let (lo, hi) = t.node_bounds(0).unwrap();
    // The precondition of the unclipped path holds (with `bounds-culling`, the path is taken).
    assert!(Frustum::new(&view).contains_box(&view, lo, hi));
    let (clipped, _) = back_to_front(&t, &cam, false);
    let (unclipped, _) = back_to_front(&t, &cam, true);
    assert!(same_image(&clipped, &unclipped), "{clipped}\n{unclipped}");
    assert!(clipped.written_count() > 50, "{}", clipped.written_count());
}

#[test]
fn frustum_culling_skips_subtrees_without_changing_the_image() {
    let t = boxes(&[(Vec3::ZERO, 1.0), (Vec3::ZERO, 1.0), (Vec3::ZERO, 1.0)]);
    // Look at the leftmost box from close: the others are out of view.
    let target = DVec3::new(-5.0, 0.0, 0.0);
    let cam = Camera::look_at(
        Pose::new(DVec3::new(-5.0, 0.0, 4.0), target),
        30.0,
        W as u32,
        H as u32,
        0.05,
    )
    .unwrap();
    let (plain, s0) = back_to_front(&t, &cam, false);
    let (culled, s1) = back_to_front(&t, &cam, true);
    assert!(same_image(&plain, &culled));
    assert!(plain.written_count() > 0);
    assert_eq!(s0.nodes_culled_frustum, 0);
    let (f2b, s2) = front_to_back::<8>(&t, &cam, MockTarget::allowing_overdraw());
    assert!(same_image(&plain, &f2b));
    if cfg!(all(feature = "stats", feature = "bounds-culling")) {
        assert!(s1.nodes_culled_frustum >= 1, "{s1:?}");
        assert!(s1.polygons_visited < s0.polygons_visited);
        assert!(s2.nodes_culled_frustum >= 1);
    } else {
        // Without the feature the subtrees are walked (and their polygons clipped away);
        // without `stats` nothing is counted.
        assert_eq!((s1.nodes_culled_frustum, s2.nodes_culled_frustum), (0, 0));
    }
}

#[test]
fn exhausted_span_memory_falls_back_without_losing_polygons() {
    let t = boxes(&[(Vec3::ZERO, 1.0), (Vec3::ZERO, 1.5), (Vec3::ZERO, 0.7)]);
    let cam = camera(DVec3::new(0.5, 2.0, 9.0), DVec3::ZERO);
    let (reference, _) = back_to_front(&t, &cam, false);
    // One slot per row: the second disjoint span on a row overflows.
    let (image, stats) = front_to_back::<1>(&t, &cam, MockTarget::allowing_overdraw());
    assert!(same_image(&reference, &image), "{reference}\n{image}");
    assert!(stats.fallback, "{stats:?}");
    assert_eq!(stats.distinct_pixels, None);
    // No span memory at all: the whole frame back to front.
    let (image, stats) = front_to_back::<0>(&t, &cam, MockTarget::allowing_overdraw());
    assert!(same_image(&reference, &image));
    assert!(stats.fallback);
    // A renderer without span memory draws back to front by design: not a fallback.
    let mut ws = Workspace::<16, 12>::new();
    let mut renderer = Renderer::new(&mut ws);
    assert_eq!(renderer.order(), Order::BackToFront);
    let mut none = MockTarget::<W, H>::allowing_overdraw();
    let stats = renderer.draw(&t, &cam.view(t.centre), &mut none).unwrap();
    assert!(!stats.fallback);
    assert!(same_image(&reference, &none));
}

/// A closed box, each face of its own colour.
fn closed_cube() -> TestTree {
    let mut t = TestTree::default();
    let (first, count) = box_faces(
        &mut t,
        Vec3::splat(-1.0),
        Vec3::splat(1.0),
        Colour::default(),
    );
    for k in 0..count as usize {
        let p = &mut t.polygons[first as usize + k];
        p.colour = Colour::new(50 + 30 * k as u8, 0, 0);
    }
    t.nodes.push(Node::Convex {
        first,
        count,
        child: None,
    });
    t
}

/// Culling never empties a closed mesh seen from inside (it used to skip every face there as
/// a back face), in either order.
#[test]
fn a_closed_cube_seen_from_inside_is_drawn_with_culling() {
    let t = closed_cube();
    let inside = camera(DVec3::new(0.1, 0.2, 0.3), DVec3::new(0.0, 0.0, -1.0));
    let (all, _) = back_to_front(&t, &inside, false);
    let (culled, _) = back_to_front(&t, &inside, true);
    assert_eq!(all.written_count(), W * H);
    assert!(same_image(&all, &culled), "{all}\n{culled}");
    let (image, _) = front_to_back::<8>(&t, &inside, MockTarget::new());
    assert!(same_image(&all, &image), "{all}\n{image}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    /// Random boxes and eyes: front to back (each pixel once) is the painter's image, with
    /// or without enough span memory.
    #[test]
    fn random_scenes_agree(
        sizes in proptest::collection::vec((0.3f32..2.0, -2.0f32..2.0, -2.0f32..2.0), 1..5),
        eye in (-9.0f64..9.0, -6.0f64..6.0, 3.0f64..12.0),
    ) {
        let items: Vec<(Vec3, f32)> =
            sizes.iter().map(|&(r, y, z)| (Vec3::new(0.0, y, z), r)).collect();
        let t = boxes(&items);
        let cam = camera(DVec3::new(eye.0, eye.1, eye.2), DVec3::ZERO);
        let (reference, _) = back_to_front(&t, &cam, false);
        // Without `front-to-back` the frame is painted back to front: overdraw is allowed.
        let target = if cfg!(feature = "front-to-back") {
            MockTarget::new()
        } else {
            MockTarget::allowing_overdraw()
        };
        let (image, stats) = front_to_back::<16>(&t, &cam, target);
        prop_assert!(same_image(&reference, &image));
        if cfg!(all(feature = "stats", feature = "front-to-back")) {
            prop_assert_eq!(stats.overdraw(), Some(1.0));
        }
        let (image, _) = front_to_back::<2>(&t, &cam, MockTarget::allowing_overdraw());
        prop_assert!(same_image(&reference, &image));
    }
}
