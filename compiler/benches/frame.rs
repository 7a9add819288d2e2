//! Criterion benchmark of a whole frame: the demo scene (`fixtures/demo.obj`, compiled with
//! the default options) drawn by the runtime at 640x480, front to back (span buffer, each pixel
//! written once, covered subtrees skipped) against back to front (painter's algorithm), each
//! iteration clearing the framebuffer first.
//!
//! Run with `cargo bench -p peel-compiler --bench frame`. The runtime's inner loops (fill,
//! clip) are in `runtime/benches/inner.rs`.

#[path = "../../runtime/benches/budget/mod.rs"]
mod budget;

use std::hint::black_box;
use std::path::Path;

use criterion::Criterion;
use glam::DVec3;
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::tools::raster::{HOST_SPANS_PER_ROW, HOST_STACK, HOST_VERTS};
use peel_runtime::camera::{Camera, Pose};
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Colour, Framebuffer, Xrgb8888};
use peel_runtime::read::Scene;
use peel_runtime::render::{Renderer, Workspace};
use peel_runtime::traverse::Order;

const W: u32 = 640;
const H: u32 = 480;

fn frame(c: &mut Criterion) {
    let obj = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/demo.obj");
    let mesh = peel_compiler::load::load_obj(&obj).expect("demo fixture");
    let (_, bytes) = compile_mesh(&mesh, &CompileOptions::default(), &|_| {}).expect("compile");
    let scene = Scene::parse(&bytes).expect("valid scene");
    let h = scene.header();
    // The demo's camera (`peel demo`), at 640x480.
    let camera = Camera::look_at(
        Pose::new(DVec3::new(5.5, 4.5, 7.5), DVec3::new(0.0, 0.8, 0.0)),
        50.0,
        W,
        H,
        Camera::default_near(h.bounds_min, h.bounds_max),
    )
    .expect("camera");
    let view = camera.view(scene.header().centre);
    let mut pixels = vec![0u32; (W * H) as usize];
    let mut workspace: Box<Workspace<HOST_STACK, HOST_VERTS>> = Box::default();
    let mut intervals = vec![(0u16, 0u16); HOST_SPANS_PER_ROW * H as usize];
    let mut counts = vec![0u16; H as usize];
    let mut g = c.benchmark_group("demo-frame-640x480");
    for (name, order) in [
        ("front-to-back", Order::FrontToBack),
        ("back-to-front", Order::BackToFront),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| {
                let mut fb = Framebuffer::<Xrgb8888>::new(&mut pixels, W, H).expect("fb");
                fb.clear(Colour::new(24, 26, 32));
                let coverage = Coverage::new(&mut intervals, &mut counts, W, H).expect("coverage");
                let mut renderer = Renderer::new(&mut workspace).span_memory(coverage);
                if order == Order::BackToFront {
                    renderer = renderer.back_to_front();
                }
                renderer
                    .draw(black_box(&scene), &view, &mut fb)
                    .expect("render")
                    .pixels_written
            })
        });
    }
    g.finish();
}

budget::main!(frame);
