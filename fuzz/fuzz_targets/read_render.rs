//! Arbitrary bytes -> runtime reader -> render: never a panic, never a hang.
#![no_main]

use glam::DVec3;
use libfuzzer_sys::fuzz_target;
use peel_runtime::camera::{Camera, Pose};
use peel_runtime::display::{Colour, SpanSink};
use peel_runtime::read::Scene;
use peel_runtime::render::{Paint, Renderer, Workspace};

/// A `W x H` image's span sink that panics on what a frame must never send: a span outside
/// the image or an empty one (overdraw is allowed: back to front paints over).
struct CheckedSpans<const W: u32, const H: u32>;

impl<const W: u32, const H: u32> SpanSink for CheckedSpans<W, H> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, _: Colour) {
        assert!(
            y < H && x_end <= W,
            "span y={y} x={x_start}..{x_end} outside {W}x{H}"
        );
        assert!(x_start < x_end, "empty span y={y} x={x_start}..{x_end}");
    }
}

fuzz_target!(|data: &[u8]| {
    let Ok(scene) = Scene::parse(data) else {
        return;
    };
    let mut workspace: Box<Workspace<256, 64>> = Box::default();
    for (eye, paint) in [
        (DVec3::new(3.0, 2.0, 5.0), Paint::Colours),
        (DVec3::new(0.0, 0.0, 0.0), Paint::Ids),
        (DVec3::new(-1e3, 4.0, 0.5), Paint::Colours),
    ] {
        let Ok(camera) = Camera::look_at(
            Pose::new(eye, DVec3::new(0.1, 0.2, 0.3)),
            60.0,
            32,
            24,
            1e-3,
        ) else {
            continue;
        };
        let mut target = CheckedSpans::<32, 24>;
        let mut renderer = Renderer::new(&mut workspace);
        if paint == Paint::Ids {
            renderer = renderer.ids();
        }
        let _ = renderer.draw(&scene, &camera.view(scene.header().centre), &mut target);
    }
});
