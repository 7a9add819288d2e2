//! Frames without a framebuffer: a frame streamed with its background (every pixel written,
//! the uncovered ones in the background colour) and a frame drawn in bands of rows equal the
//! framebuffer frame pixel for pixel, in both orders, at every precision, for cameras inside,
//! cutting and outside closed solids and an open soup; front to back every pixel is written
//! exactly once, also across bands, and when the span memory runs out (the fallback) the image
//! is still the same. A frame in scan order (scan memory, read out row by row) is the
//! framebuffer frame in RGB565, and scan memory one node short of its need is a typed error.

use std::sync::OnceLock;

use glam::DVec3;
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::tools::raster::{
    posed_header, HostObjectMemory, HOST_SPANS_PER_ROW, HOST_STACK, HOST_VERTS,
};
use peel_compiler::tools::scenes;
use peel_e2e::closed_sphere;
use peel_runtime::camera::{Camera, LocalView, Pose};
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Colour, Framebuffer, SpanSink, Xrgb8888};
use peel_runtime::error::RenderError;
use peel_runtime::place::{Object, Posed};
use peel_runtime::read::Scene;
use peel_runtime::render::{Content, FrameStats, Renderer, Workspace};
use peel_runtime::scan::{ScanMemory, ScanNode};
use peel_runtime::traverse::Order;
use proptest::prelude::*;

/// The background: no id of these small scenes has this colour.
const BACKGROUND: Colour = Colour::new(0xab, 0xcd, 0xef);

/// The scenes, compiled once with ids: a closed sphere and torus side by side with loose
/// triangles through them, and a dense open soup.
fn scenes() -> &'static [Vec<u8>] {
    static SCENES: OnceLock<Vec<Vec<u8>>> = OnceLock::new();
    SCENES.get_or_init(|| {
        let mut solids = closed_sphere(8, 16);
        let torus = scenes::torus(16, 8);
        solids.triangles.extend(torus.triangles.iter().map(|t| {
            let mut t = *t;
            t.vertices = t.vertices.map(|v| v * 0.8 + DVec3::new(1.2, 0.1, 0.0));
            t
        }));
        solids
            .triangles
            .extend(scenes::soup(40, 0.5, 3).triangles.iter().copied());
        let options = CompileOptions {
            ids: true,
            ..CompileOptions::default()
        };
        [solids, scenes::soup(400, 0.25, 9)]
            .iter()
            .map(|mesh| compile_mesh(mesh, &options, &|_| {}).expect("compile").1)
            .collect()
    })
}

/// A full-size image and how often each pixel was written.
struct Counted {
    width: u32,
    colours: Vec<u32>,
    writes: Vec<u32>,
}

impl Counted {
    fn new(width: u32, height: u32) -> Self {
        let n = (width * height) as usize;
        Counted {
            width,
            colours: vec![u32::MAX; n],
            writes: vec![0; n],
        }
    }
}

impl SpanSink for Counted {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        for x in x_start..x_end {
            let k = (y * self.width + x) as usize;
            self.colours[k] = colour.to_xrgb8888();
            self.writes[k] += 1;
        }
    }
}

/// Sends every span to two sinks, and panics on a span outside the rows drawn.
struct Both<'a, A, B>(&'a mut A, &'a mut B, std::ops::Range<u32>);

impl<A: SpanSink, B: SpanSink> SpanSink for Both<'_, A, B> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        assert!(
            self.2.contains(&y),
            "a span on row {y}, outside the band {:?}",
            self.2
        );
        self.0.span(y, x_start, x_end, colour);
        self.1.span(y, x_start, x_end, colour);
    }
}

/// How a frame is drawn.
#[derive(Debug, Clone, Copy)]
struct Way {
    order: Order,
    /// Span memory slots per row (front to back): few enough forces the fallback.
    slots: usize,
    /// Stream with the background instead of clearing a framebuffer first.
    stream: bool,
}

/// Draw rows `rows` of `view` as `way` says into `sink`, with span memory of `memory_rows`.
fn draw_rows<const SUB: u32, S: SpanSink, C: Content + ?Sized>(
    scene: &C,
    view: &LocalView,
    way: Way,
    rows: std::ops::Range<u32>,
    memory_rows: u32,
    sink: &mut S,
) -> FrameStats {
    let mut intervals = vec![(0u16, 0u16); way.slots * memory_rows as usize];
    let mut counts = vec![0u16; memory_rows as usize];
    let coverage = Coverage::new(&mut intervals, &mut counts, view.width, memory_rows).unwrap();
    let mut workspace: Box<Workspace<HOST_STACK, HOST_VERTS, SUB>> = Box::default();
    let mut objects: Box<HostObjectMemory> = Box::default();
    let mut renderer = Renderer::<SUB>::with_precision(&mut workspace)
        .ids()
        .object_memory(&mut objects);
    if way.order == Order::FrontToBack {
        renderer = renderer.span_memory(coverage);
    }
    if way.stream {
        renderer = renderer.background(BACKGROUND);
    }
    renderer.draw_rows(scene, view, rows, sink).expect("frame")
}

/// The framebuffer frame: cleared to the background, then drawn.
fn reference<const SUB: u32, C: Content + ?Sized>(
    scene: &C,
    view: &LocalView,
    order: Order,
) -> Vec<u32> {
    let (w, h) = (view.width, view.height);
    let mut pixels = vec![0u32; (w * h) as usize];
    let mut fb = Framebuffer::<Xrgb8888>::new(&mut pixels, w, h).unwrap();
    fb.clear(BACKGROUND);
    let way = Way {
        order,
        slots: HOST_SPANS_PER_ROW,
        stream: false,
    };
    draw_rows::<SUB, _, _>(scene, view, way, 0..h, h, &mut fb);
    pixels
}

/// The scan-order frame of `view` against `expected` (the front-to-back framebuffer frame),
/// in RGB565, read as one run and row by row; one node less than it used is an error.
fn check_scan<const SUB: u32, C: Content + ?Sized>(
    scene: &C,
    view: &LocalView,
    expected: &[u32],
) -> Result<(), TestCaseError> {
    let (w, h) = (view.width, view.height);
    let want: Vec<u16> = expected
        .iter()
        .map(|&p| Colour::new((p >> 16) as u8, (p >> 8) as u8, p as u8).to_rgb565())
        .collect();
    let draw = |nodes: usize| -> Result<(Vec<u16>, Vec<u16>, usize), RenderError> {
        let mut pool = vec![ScanNode::EMPTY; nodes];
        let mut heads = vec![0u16; h as usize];
        let mut memory = ScanMemory::new(&mut pool, &mut heads, w, h).unwrap();
        // Against a frame rounded to RGB565: undithered (the dithered read-out is the RGB565
        // framebuffer's, `runtime/src/render/smooth_tests.rs`).
        memory.set_dithering(false);
        let mut workspace: Box<Workspace<HOST_STACK, HOST_VERTS, SUB>> = Box::default();
        let mut objects: Box<HostObjectMemory> = Box::default();
        let mut renderer = Renderer::<SUB>::with_precision(&mut workspace)
            .ids()
            .object_memory(&mut objects)
            .scan_memory(memory)
            .background(BACKGROUND);
        let frame = renderer.draw_scan(scene, view)?;
        let mut rows = Vec::new();
        let mut row = vec![0u16; w as usize];
        for y in 0..h {
            frame.row_into(y, &mut row);
            rows.extend_from_slice(&row);
        }
        Ok((frame.pixels().collect(), rows, frame.nodes_used()))
    };
    let (pixels, rows, used) = draw(4096).expect("a scan-order frame");
    prop_assert!(
        pixels == want,
        "scan order differs from the framebuffer frame"
    );
    prop_assert!(
        rows == want,
        "scan-order rows differ from the framebuffer frame"
    );
    prop_assert!(draw(used).is_ok());
    if used > 0 {
        prop_assert_eq!(
            draw(used - 1).err(),
            Some(RenderError::ScanMemoryFull {
                nodes: used as u32 - 1
            })
        );
    }
    Ok(())
}

/// Streamed and banded frames of `scene` against the framebuffer frame.
fn check<const SUB: u32, C: Content + ?Sized>(
    scene: &C,
    view: &LocalView,
    band: u32,
    slots: usize,
) -> Result<(), TestCaseError> {
    let (w, h) = (view.width, view.height);
    for order in [Order::FrontToBack, Order::BackToFront] {
        let expected = reference::<SUB, _>(scene, view, order);
        if order == Order::FrontToBack {
            check_scan::<SUB, _>(scene, view, &expected)?;
        }
        let way = Way {
            order,
            slots,
            stream: true,
        };
        // Streamed: no clear, every pixel written by the frame itself.
        let mut streamed = Counted::new(w, h);
        let stats = draw_rows::<SUB, _, _>(scene, view, way, 0..h, h, &mut streamed);
        let differ = streamed
            .colours
            .iter()
            .zip(&expected)
            .filter(|(a, b)| a != b)
            .count();
        prop_assert_eq!(differ, 0, "{:?}, streamed: {} pixels differ", order, differ);
        let once = order == Order::FrontToBack && !stats.fallback;
        prop_assert!(streamed.writes.iter().all(|&n| n >= 1));
        if once {
            prop_assert!(
                streamed.writes.iter().all(|&n| n == 1),
                "{:?}: overdraw",
                order
            );
        }
        // Banded: each band drawn into a band buffer (and counted), then put in place. One
        // span memory of `band` rows serves every band, the shorter last one too.
        let mut banded = vec![0u32; (w * h) as usize];
        let mut counted = Counted::new(w, h);
        let mut fallback = false;
        for first in (0..h).step_by(band as usize) {
            let rows = first..(first + band).min(h);
            let mut buffer = vec![0u32; (w * (rows.end - first)) as usize];
            let mut fb = Framebuffer::<Xrgb8888>::band(&mut buffer, w, rows.clone()).unwrap();
            let mut both = Both(&mut fb, &mut counted, rows.clone());
            fallback |= draw_rows::<SUB, _, _>(scene, view, way, rows, band, &mut both).fallback;
            banded[(first * w) as usize..][..buffer.len()].copy_from_slice(&buffer);
        }
        let differ = banded.iter().zip(&expected).filter(|(a, b)| a != b).count();
        prop_assert_eq!(
            differ,
            0,
            "{:?}, bands of {}: {} pixels differ",
            order,
            band,
            differ
        );
        prop_assert!(counted.writes.iter().all(|&n| n >= 1));
        if order == Order::FrontToBack && !fallback {
            prop_assert!(
                counted.writes.iter().all(|&n| n == 1),
                "{:?}, bands of {}: overdraw",
                order,
                band
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, failure_persistence: None, ..ProptestConfig::default() })]

    /// Eyes anywhere from inside the solids to well outside, looking anywhere near the scene;
    /// small images (so bands are few rows), every band height, and span memory from ample
    /// down to one slot per row (the fallback).
    #[test]
    fn streamed_and_banded_frames_equal_the_framebuffer_frame(
        which in 0usize..2,
        eye in prop::array::uniform3(-1.6f64..1.6),
        target in prop::array::uniform3(-0.5f64..0.5),
        width in 8u32..48,
        height in 6u32..36,
        band in 1u32..40,
        slots in prop::sample::select(vec![1usize, 2, HOST_SPANS_PER_ROW]),
        sub in prop::sample::select(vec![0u32, 4, 8]),
    ) {
        let bytes = &scenes()[which];
        let scene = Scene::parse(bytes).unwrap();
        let h = scene.header();
        let mesh_box = (h.bounds_min.as_dvec3(), h.bounds_max.as_dvec3());
        let centre = DVec3::from_array(h.centre) + (mesh_box.0 + mesh_box.1) / 2.0;
        let reach = (mesh_box.1 - mesh_box.0) / 2.0;
        let eye = centre + DVec3::from_array(eye) * reach;
        let target = centre + DVec3::from_array(target) * reach;
        prop_assume!((eye - target).length() > 1e-3 * reach.length());
        let near = Camera::default_near(h.bounds_min, h.bounds_max);
        let camera = Camera::look_at(Pose::new(eye, target), 60.0, width, height, near);
        prop_assume!(camera.is_ok());
        let view = camera.unwrap().view(h.centre);
        let band = band.min(height);
        match sub {
            0 => check::<0, _>(&scene, &view, band, slots)?,
            4 => check::<4, _>(&scene, &view, band, slots)?,
            _ => check::<8, _>(&scene, &view, band, slots)?,
        }
    }
}

/// The posed frames' world, a grid of eight boxes, then two small objects: a closed sphere
/// and a torus, each 0.6 across, with ids after the world's.
fn posed_scene() -> &'static [Vec<u8>] {
    static PARTS: OnceLock<Vec<Vec<u8>>> = OnceLock::new();
    PARTS.get_or_init(|| {
        let world = scenes::box_grid(2);
        let mut sphere = closed_sphere(6, 10);
        let mut torus = scenes::torus(10, 6);
        for mesh in [&mut sphere, &mut torus] {
            for t in &mut mesh.triangles {
                t.vertices = t.vertices.map(|v| v * 0.3);
            }
        }
        let mut first = 0;
        [world, sphere, torus]
            .iter()
            .map(|mesh| {
                let options = CompileOptions {
                    ids: true,
                    id_offset: first,
                    ..CompileOptions::default()
                };
                first += mesh.triangles.len() as u32;
                compile_mesh(mesh, &options, &|_| {}).expect("compile").1
            })
            .collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    /// The same with objects posed in the solids' scene (apart from each other, through the
    /// world's solids and planes): streamed, banded and scan-order frames equal the
    /// framebuffer frame, in both orders, with the fallback.
    #[test]
    fn posed_frames_are_the_same_on_every_path(
        a in prop::array::uniform3(-1.0f32..1.0),
        b in prop::array::uniform3(-1.0f32..1.0),
        turn in prop::array::uniform3(-180.0f32..180.0),
        eye in prop::array::uniform3(-1.6f64..1.6),
        width in 8u32..48,
        height in 6u32..36,
        band in 1u32..40,
        slots in prop::sample::select(vec![1usize, 2, HOST_SPANS_PER_ROW]),
    ) {
        let [world, sphere, torus] = [0, 1, 2].map(|k| Scene::parse(&posed_scene()[k]).unwrap());
        // Among the boxes (0 to 3.2 on each axis), the sphere left of x = 1.6 and the torus
        // right of it: a plane between them always.
        let at = |p: [f32; 3], x: f32| glam::Vec3::new(x + 0.5 * p[0], 1.6 + 1.5 * p[1], 1.6 + 1.5 * p[2]);
        let objects = [
            Object::new(sphere, Some(peel_runtime::place::Pose::from_degrees(at(a, 0.75), turn[0], 0.0, 0.0))),
            Object::new(torus, Some(peel_runtime::place::Pose::from_degrees(
                    at(b, 2.45),
                    turn[0],
                    turn[1],
                    turn[2],
                ))),
        ];
        let posed = Posed::new(Some(world), &objects);
        let h = posed_header(Some(&world), &objects);
        let mesh_box = (h.bounds_min.as_dvec3(), h.bounds_max.as_dvec3());
        let centre = DVec3::from_array(h.centre) + (mesh_box.0 + mesh_box.1) / 2.0;
        let reach = (mesh_box.1 - mesh_box.0) / 2.0;
        let eye = centre + DVec3::from_array(eye) * reach;
        prop_assume!((eye - centre).length() > 1e-3 * reach.length());
        let near = Camera::default_near(h.bounds_min, h.bounds_max);
        let camera = Camera::look_at(Pose::new(eye, centre), 60.0, width, height, near);
        prop_assume!(camera.is_ok());
        let view = camera.unwrap().view(h.centre);
        check::<8, _>(&posed, &view, band.min(height), slots)?;
    }
}

/// The test scenes do what the property needs: the eye can be inside a closed solid (then no
/// background shows), and one slot per row makes front to back fall back while enough slots
/// do not.
#[test]
fn the_scenes_exercise_inside_views_and_the_fallback() {
    let scene = Scene::parse(&scenes()[0]).unwrap();
    let h = scene.header();
    // From the sphere's centre, looking at the torus: front to back with one slot per row
    // falls back, with plenty of slots it does not.
    let camera = Camera::look_at(
        Pose::new(DVec3::ZERO, DVec3::new(1.2, 0.1, 0.0)),
        60.0,
        32,
        24,
        Camera::default_near(h.bounds_min, h.bounds_max),
    )
    .unwrap();
    let view = camera.view(h.centre);
    let mut sink = Counted::new(32, 24);
    let way = |slots| Way {
        order: Order::FrontToBack,
        slots,
        stream: true,
    };
    assert!(draw_rows::<8, _, _>(&scene, &view, way(1), 0..24, 24, &mut sink).fallback);
    let mut sink = Counted::new(32, 24);
    let stats = draw_rows::<8, _, _>(&scene, &view, way(HOST_SPANS_PER_ROW), 0..24, 24, &mut sink);
    assert!(!stats.fallback);
    // Inside the sphere every pixel shows some polygon: no background.
    let bg = BACKGROUND.to_xrgb8888();
    assert!(sink.colours.iter().all(|&c| c != bg));
    // Back to front in bands (no span memory), subtrees whose screen box misses the band are
    // skipped: from outside, the soup's bands skip some.
    let soup = Scene::parse(&scenes()[1]).unwrap();
    let h = soup.header();
    let eye = DVec3::from_array(h.centre) + DVec3::new(0.0, 0.5, 3.0);
    let camera = Camera::look_at(
        Pose::new(eye, DVec3::from_array(h.centre)),
        60.0,
        64,
        48,
        Camera::default_near(h.bounds_min, h.bounds_max),
    )
    .unwrap();
    let view = camera.view(h.centre);
    let way = Way {
        order: Order::BackToFront,
        slots: 0,
        stream: true,
    };
    let mut sink = Counted::new(64, 48);
    let skipped: u64 = (0..48)
        .step_by(8)
        .map(|y| {
            draw_rows::<8, _, _>(&soup, &view, way, y..y + 8, 8, &mut sink).nodes_culled_covered
        })
        .sum();
    assert!(skipped > 0, "no subtree skipped outside its band");
}
