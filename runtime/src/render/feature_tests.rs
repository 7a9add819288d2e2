//! What the cargo features change (run with `--no-default-features --features ...` too).

extern crate std;

use glam::{DVec3, Vec3};
use std::vec;
use std::vec::Vec;

use super::*;
use crate::camera::Pose;
use crate::read::Node;
use crate::traverse::testing::{box_faces, TestTree};

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
    let mut cov = Coverage::new(&mut intervals, &mut counts, w, h).unwrap();
    let mut sink = Pixels(w, vec![Colour::default(); (w * h) as usize]);
    let options = RenderOptions {
        order,
        paint,
        cull: true,
    };
    let stats = render_ordered(
        &cube(),
        &cam,
        &mut Workspace::<8, 16>::new(),
        options,
        Some(&mut cov),
        &mut sink,
    );
    (stats, sink.1)
}

#[test]
fn front_to_back_needs_its_feature_and_never_changes_the_image() {
    let (stats, image) = draw(Order::FrontToBack, Paint::Colours);
    let stats = stats.unwrap();
    let (b2f, reference) = draw(Order::BackToFront, Paint::Colours);
    assert!(b2f.unwrap().polygons_drawn > 0);
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
        assert!(stats.unwrap().polygons_drawn > 0);
        assert!(image
            .iter()
            .any(|&c| c == id_colour(100) || c == id_colour(105)));
    } else {
        assert_eq!(stats.unwrap_err(), RenderError::NoIds);
    }
}
