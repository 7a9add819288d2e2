//! What the cargo features change (run with `--no-default-features --features ...` too).

extern crate std;

use glam::{DVec3, Vec3};
use std::vec;
use std::vec::Vec;

use super::frame::window;
use super::painter::{NoCuts, Painter};
use super::testing::*;
use super::*;
use crate::camera::{Camera, Pose};
use crate::clip::Frustum;
use crate::coverage::Coverage;
use crate::display::{Colour, SpanSink};
use crate::error::RenderError;
use crate::fill::{self, FixedPoint};
use crate::read::Node;
use crate::stats::Tally;
use crate::traverse::testing::{box_faces, TestTree};
use crate::traverse::Order;

struct Pixels(u32, Vec<Colour>);

impl SpanSink for Pixels {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        for x in x_start..x_end {
            self.1[(y * self.0 + x) as usize] = colour;
        }
    }
}

fn cube() -> TestTree {
    let mut t = TestTree::default();
    let (first, count) = box_faces(&mut t, Vec3::splat(-1.0), Vec3::ONE, Colour::default());
    for (k, p) in t.polygons.iter_mut().enumerate() {
        p.colour = Colour::new(40 * k as u8, 255 - 40 * k as u8, 7);
    }
    t.nodes.push(Node::Convex {
        first,
        count,
        child: None,
    });
    t.ids = Some((100..106).collect());
    t
}

fn draw(order: Order, paint: Paint) -> (Result<FrameStats, RenderError>, Vec<Colour>) {
    let (w, h) = (24u32, 18u32);
    let cam = Camera::look_at(
        Pose::new(DVec3::new(2.5, 1.5, 4.0), DVec3::ZERO),
        60.0,
        w,
        h,
        0.01,
    )
    .unwrap();
    let mut intervals = vec![(0u16, 0u16); 8 * h as usize];
    let mut counts = vec![0u16; h as usize];
    let cov = Coverage::new(&mut intervals, &mut counts, w, h).unwrap();
    let mut sink = Pixels(w, vec![Colour::default(); (w * h) as usize]);
    let options = Options {
        order,
        paint,
        cull: true,
    };
    let stats = draw_test_frame_with(
        &cube(),
        &cam,
        &mut Workspace::<8, 16>::new(),
        options,
        Memory::from(cov),
        &mut sink,
    );
    (stats, sink.1)
}

#[test]
fn front_to_back_needs_its_feature_and_never_changes_the_image() {
    let (stats, image) = draw(Order::FrontToBack, Paint::Colours);
    let stats = stats.unwrap();
    let (b2f, reference) = draw(Order::BackToFront, Paint::Colours);
    b2f.unwrap();
    assert!(
        reference
            .iter()
            .filter(|&&c| c != Colour::default())
            .count()
            > 50
    );
    assert_eq!(image, reference);
    // With the feature the span memory is used (no fallback, each pixel once); without it the
    // frame is painted back to front.
    assert_eq!(stats.fallback, !cfg!(feature = "front-to-back"));
    assert_eq!(
        stats.distinct_pixels.is_some(),
        cfg!(feature = "front-to-back")
    );
}

#[test]
fn id_images_need_their_feature() {
    let (stats, image) = draw(Order::BackToFront, Paint::Ids);
    if cfg!(feature = "ids") {
        stats.unwrap();
        assert!(image
            .iter()
            .any(|&c| c == id_colour(100) || c == id_colour(105)));
    } else {
        assert_eq!(stats.unwrap_err(), RenderError::NoIds);
    }
}

#[test]
fn counters_need_their_feature() {
    let (stats, image) = draw(Order::BackToFront, Paint::Colours);
    let stats = stats.unwrap();
    let drawn = image.iter().filter(|&&c| c != Colour::default()).count() as u64;
    // Span memory measures distinct pixels whatever `stats` says.
    let measured = cfg!(feature = "front-to-back").then_some(drawn);
    assert_eq!(stats.distinct_pixels, measured);
    if cfg!(feature = "stats") {
        // Three faces are seen, six visited; the painter overdraws the far ones.
        assert_eq!(stats.polygons_visited, 6);
        assert_eq!(stats.polygons_drawn, 6);
        assert!(stats.pixels_written > drawn, "{stats:?}");
        assert_eq!(stats.overdraw().is_some(), cfg!(feature = "front-to-back"));
    } else {
        let zero = FrameStats {
            distinct_pixels: measured,
            ..FrameStats::default()
        };
        assert_eq!(stats, zero);
        assert_eq!(stats.overdraw(), None);
    }
}

/// The cube with its node bounds, seen with its box out of view.
fn culled_cube(order: Order) -> (FrameStats, bool) {
    let mut t = cube();
    t.bounds = vec![Some((Vec3::splat(-1.0), Vec3::ONE))];
    let cam = Camera::look_at(
        Pose::new(DVec3::new(0.0, 0.0, 5.0), DVec3::new(0.0, 0.0, 10.0)),
        60.0,
        16,
        12,
        0.01,
    )
    .unwrap();
    let mut intervals = vec![(0u16, 0u16); 4 * 12];
    let mut counts = vec![0u16; 12];
    let cov = Coverage::new(&mut intervals, &mut counts, 16, 12).unwrap();
    let mut sink = Pixels(16, vec![Colour::default(); 16 * 12]);
    let options = Options {
        order,
        ..Options::default()
    };
    let mut ws = Workspace::<8, 16>::new();
    let stats =
        draw_test_frame_with(&t, &cam, &mut ws, options, Memory::from(cov), &mut sink).unwrap();
    // Whether the walk enters the node, asked directly.
    let view = cam.view(t.centre);
    let (mut a, mut b) = ([Vec3::ZERO; 16], [Vec3::ZERO; 16]);
    let mut points = [FixedPoint::default(); 16];
    let mut edges = [fill::EdgeWalk::default(); 16];
    let painter = Painter::<8> {
        view: &view,
        rows: 0..view.height,
        frustum: Frustum::new(&view),
        max_x: 16 << 8,
        max_y: 12 << 8,
        available: 16,
        paint: Paint::Colours,
        cull: true,
        cull_subtrees: true,
        filter: crate::display::Filter::Nearest,
        all_inside: false,
        clip_a: &mut a,
        clip_b: &mut b,
        points: &mut points,
        edges: &mut edges,
        vertices: None,
        #[cfg(feature = "integer-vertices")]
        integer: None,
        antialias: None,
        composite: None,
        door: false,
        cuts: NoCuts,
    };
    let entered = painter.enter(&t, 0, None, &mut Tally::default());
    assert!(sink.1.iter().all(|&c| c == Colour::default()));
    (stats, entered)
}

#[test]
fn subtree_culling_needs_its_feature_and_never_changes_the_image() {
    for order in [Order::BackToFront, Order::FrontToBack] {
        let (stats, entered) = culled_cube(order);
        let culled = cfg!(feature = "bounds-culling");
        assert_eq!(entered, !culled);
        if cfg!(feature = "stats") {
            // Culled: the node and its six polygons are skipped; else all six are visited
            // and clipped away.
            assert_eq!(stats.nodes_culled_frustum, u64::from(culled));
            assert_eq!(stats.polygons_visited, if culled { 0 } else { 6 });
            assert_eq!(stats.polygons_drawn, 0);
        } else {
            assert_eq!((stats.nodes_culled_frustum, stats.polygons_visited), (0, 0));
        }
    }
}

#[test]
fn image_size_limit_follows_wide_coordinates() {
    // At 8 subpixel bits: 8191 pixels fit both widths; 8192 need `wide-coordinates`, which
    // allows up to 2^23 - 1.
    assert!(window::<8>(8191, 8191).is_ok());
    let wide = window::<8>(8192, 10);
    let too_large = Err(RenderError::ImageTooLarge {
        width: 8192,
        height: 10,
    });
    if cfg!(feature = "wide-coordinates") {
        assert_eq!(wide, Ok((8192 << 8, 10 << 8)));
        assert!(window::<8>((1 << 23) - 1, 1).is_ok());
        assert!(window::<8>(1 << 23, 1).is_err());
    } else {
        assert_eq!(wide, too_large);
        assert!(window::<0>((1 << 29) - 1, 1).is_ok());
        assert!(window::<0>(1 << 29, 1).is_err());
    }
    // Through the renderer, refused before any pixel (a 8192 x 2 frame of the cube).
    let cam = Camera::look_at(
        Pose::new(DVec3::new(0.0, 0.0, 3.0), DVec3::ZERO),
        60.0,
        8192,
        2,
        0.01,
    )
    .unwrap();
    let mut sink = Pixels(8192, vec![Colour::default(); 8192 * 2]);
    let r = draw_test_frame(
        &cube(),
        &cam,
        &mut Workspace::<8, 16>::new(),
        Paint::Colours,
        &mut sink,
    );
    if cfg!(feature = "wide-coordinates") {
        r.unwrap();
        assert!(sink.1.iter().any(|&c| c != Colour::default()));
    } else {
        assert_eq!(
            r,
            Err(RenderError::ImageTooLarge {
                width: 8192,
                height: 2
            })
        );
        assert!(sink.1.iter().all(|&c| c == Colour::default()));
    }
}
