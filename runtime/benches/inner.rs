//! Criterion benchmarks of the runtime's inner loops (host, std):
//! - `fill/*`: the integer scanline fill of one polygon into a 640x480 XRGB8888 framebuffer,
//!   a small triangle (a few dozen pixels) and a large hexagon (most of the window);
//! - `clip/*`: near + window clipping (Sutherland–Hodgman) of a polygon in camera space, one
//!   crossing the near plane and two window edges, one inside (nothing clipped).
//!
//! Run with `cargo bench -p peel-runtime --bench inner`. Whole frames are measured in
//! `compiler/benches/frame.rs` (they need a compiled scene).

mod budget;

use std::hint::black_box;

use criterion::Criterion;
use glam::{DVec3, Vec3};
use peel_runtime::camera::{Camera, Pose};
use peel_runtime::clip::{clip_polygon, Frustum};
use peel_runtime::display::{Colour, Framebuffer, Xrgb8888};
use peel_runtime::fill::{fill_polygon, SubpixelPoint};

const W: u32 = 640;
const H: u32 = 480;

fn snap(points: &[(f32, f32)]) -> Vec<SubpixelPoint> {
    points
        .iter()
        .map(|&(x, y)| SubpixelPoint::snap(x, y))
        .collect()
}

fn fill(c: &mut Criterion) {
    let small = snap(&[(100.3, 100.7), (109.9, 103.2), (102.1, 111.6)]);
    let large = snap(&[
        (40.5, 240.2),
        (180.3, 20.7),
        (460.8, 25.1),
        (610.2, 238.9),
        (470.4, 455.3),
        (170.6, 460.9),
    ]);
    let mut pixels = vec![0u32; (W * H) as usize];
    let mut fb = Framebuffer::<Xrgb8888>::new(&mut pixels, W, H).expect("framebuffer");
    let colour = Colour::new(200, 120, 40);
    let mut g = c.benchmark_group("fill");
    for (name, poly) in [("small-triangle", &small), ("large-hexagon", &large)] {
        g.bench_function(name, |b| {
            b.iter(|| fill_polygon(black_box(poly), W, H, colour, &mut fb).expect("fill"))
        });
    }
    g.finish();
}

fn clip(c: &mut Criterion) {
    let camera = Camera::look_at(
        Pose::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO),
        60.0,
        W,
        H,
        0.01,
    )
    .expect("camera");
    let view = camera.view([0.0; 3]);
    let frustum = Frustum::new(&view);
    let to_camera = |p: Vec3| {
        let v = p - view.eye;
        Vec3::new(v.dot(view.right), v.dot(view.up), v.dot(view.forward))
    };
    // A large quad running from behind the eye to beyond the right and top edges.
    let crossing: Vec<Vec3> = [
        Vec3::new(-1.0, -1.0, 8.0),
        Vec3::new(9.0, -1.0, 8.0),
        Vec3::new(9.0, 9.0, -20.0),
        Vec3::new(-1.0, 9.0, -20.0),
    ]
    .map(to_camera)
    .to_vec();
    // A small triangle in the middle of the view.
    let inside: Vec<Vec3> = [
        Vec3::new(-0.3, -0.2, 0.0),
        Vec3::new(0.4, -0.1, 0.1),
        Vec3::new(0.0, 0.5, -0.1),
    ]
    .map(to_camera)
    .to_vec();
    let mut a = [Vec3::ZERO; 16];
    let mut b = [Vec3::ZERO; 16];
    // The crossing quad is cut by the near plane and two window edges, the triangle by none.
    for (poly, min_len) in [(&crossing, 5), (&inside, 3)] {
        a[..poly.len()].copy_from_slice(poly);
        let out = clip_polygon(frustum.planes(), poly.len(), &mut a, &mut b).expect("clip");
        assert!(out.len() >= min_len, "{} vertices", out.len());
    }
    let mut g = c.benchmark_group("clip");
    for (name, poly) in [("near-and-window", &crossing), ("inside", &inside)] {
        g.bench_function(name, |bench| {
            bench.iter(|| {
                a[..poly.len()].copy_from_slice(black_box(poly));
                clip_polygon(frustum.planes(), poly.len(), &mut a, &mut b)
                    .expect("clip")
                    .len()
            })
        });
    }
    g.finish();
}

budget::main!(fill, clip);
