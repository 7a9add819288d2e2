//! Culling and the vertex memory never change a front-to-back frame. Dense generated scenes
//! drawn so small that most polygons cover no pixel centre, where subtree culling (outside the
//! frustum, no pixel centre near the subtree's screen box, or every such pixel already covered)
//! does the most: the image with culling equals the image without, pixel for pixel, and
//! culling did skip subtrees; the image drawn with projected vertices kept from frame to frame
//! (one memory for every camera of a scene) equals the image drawn without.

use glam::DVec3;
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::Mesh;
use peel_compiler::raster::{HOST_SPANS_PER_ROW, HOST_STACK, HOST_VERTS};
use peel_compiler::scenes;
use peel_runtime::camera::{Camera, Pose};
use peel_runtime::coverage::Coverage;
use peel_runtime::read::Scene;
use peel_runtime::render::{render_with_options, FrameMemory, Paint, RenderOptions, Workspace};
use peel_runtime::target::{Framebuffer, Xrgb8888};
use peel_runtime::traverse::Order;
use peel_runtime::vertices::{CachedVertex, VertexCache};

/// The id image of one front-to-back frame at `SUB` fractional bits, and the subtrees culled.
fn frame<const SUB: u32>(
    scene: &Scene<'_>,
    camera: &Camera,
    cull: bool,
    vertices: Option<&mut VertexCache<'_>>,
) -> (Vec<u32>, u64) {
    let (w, h) = (camera.width(), camera.height());
    let mut ids = vec![0u32; (w * h) as usize];
    let mut fb = Framebuffer::<Xrgb8888>::new(&mut ids, w, h).expect("framebuffer");
    let mut intervals = vec![(0u16, 0u16); HOST_SPANS_PER_ROW * h as usize];
    let mut counts = vec![0u16; h as usize];
    let mut coverage = Coverage::new(&mut intervals, &mut counts, w, h).expect("coverage");
    let mut workspace: Box<Workspace<HOST_STACK, HOST_VERTS>> = Box::default();
    let options = RenderOptions {
        order: Order::FrontToBack,
        paint: Paint::Ids,
        cull,
    };
    let stats = render_with_options::<SUB, _, _, HOST_STACK, HOST_VERTS>(
        scene,
        camera,
        &mut workspace,
        options,
        FrameMemory {
            coverage: Some(&mut coverage),
            vertices,
        },
        &mut fb,
    )
    .expect("render");
    (ids, stats.nodes_culled_covered + stats.nodes_culled_frustum)
}

/// Frames of `mesh` from a ring of cameras at two distances and three image sizes, with and
/// without culling, at `SUB` bits; returns the subtrees culled in all.
fn same_with_and_without<const SUB: u32>(name: &str, mesh: &Mesh) -> u64 {
    let options = CompileOptions {
        ids: true,
        ..CompileOptions::default()
    };
    let bytes = compile_mesh(mesh, &options, &|_| {}).expect("compile").1;
    let scene = Scene::parse(&bytes).expect("valid file");
    let h = scene.header();
    let (lo, hi) = (h.bounds_min.as_dvec3(), h.bounds_max.as_dvec3());
    let c = DVec3::from_array(h.centre) + (lo + hi) / 2.0;
    let r = (hi - lo).length() / 2.0;
    let mut culled = 0;
    let mut memory = vec![CachedVertex::EMPTY; h.vertex_count as usize];
    let mut vertices = VertexCache::new(&mut memory);
    for (k, (w, ht)) in [(24, 18), (64, 48), (160, 120), (1920, 1080)]
        .into_iter()
        .enumerate()
    {
        for step in 0..6 {
            let a = 0.4 + step as f64 * 1.1 + k as f64 * 0.3;
            let dist = if step % 2 == 0 { 2.2 } else { 1.3 };
            let eye = c + DVec3::new(a.cos() * dist * r, 0.4 * r, a.sin() * dist * r);
            // Slightly off centre, so the scene's box is cut by the frame's edge in some views.
            let target = c + DVec3::new(0.3 * r * (step as f64 - 2.5) / 2.5, 0.0, 0.0);
            let near = Camera::default_near(h.bounds_min, h.bounds_max);
            let camera = Camera::look_at(Pose::new(eye, target), 60.0, w, ht, near).expect("cam");
            let (with, n) = frame::<SUB>(&scene, &camera, true, None);
            let (without, _) = frame::<SUB>(&scene, &camera, false, None);
            let (cached, _) = frame::<SUB>(&scene, &camera, true, Some(&mut vertices));
            let stale = with.iter().zip(&cached).filter(|(a, b)| a != b).count();
            assert_eq!(
                stale, 0,
                "{name}, SUB = {SUB}, {w}x{ht}, camera {step}: {stale} pixels change with the \
                 vertex memory"
            );
            let differ = with.iter().zip(&without).filter(|(a, b)| a != b).count();
            assert_eq!(
                differ, 0,
                "{name}, SUB = {SUB}, {w}x{ht}, camera {step}: {differ} pixels change with culling"
            );
            culled += n;
        }
    }
    culled
}

/// At every precision (subtree culling only: the meshes are open, no polygon is one-sided).
fn check_open(name: &str, mesh: &Mesh) {
    let culled = [
        same_with_and_without::<0>(name, mesh),
        same_with_and_without::<4>(name, mesh),
        same_with_and_without::<{ peel_runtime::fill::SUBPIXEL_BITS }>(name, mesh),
    ];
    assert!(
        culled.iter().all(|&n| n > 0),
        "{name}: culling skipped no subtree at some precision: {culled:?}"
    );
}

#[test]
fn culling_keeps_dense_open_soups_pixel_exact() {
    check_open("soup 1500", &scenes::soup(1500, 0.08, 11));
    check_open("soup 400, large", &scenes::soup(400, 0.3, 5));
}

/// Closed meshes add back-face culling (the eyes are all outside), at the default precision
/// only: with 0 or 4 fractional bits, snapping can fold a sliver of a tiny front face over at
/// a silhouette, and a pixel centre in the gap then shows the back face behind it without
/// culling and the background with it (the torus below does, at a few pixels per frame).
#[test]
fn culling_keeps_dense_closed_meshes_pixel_exact() {
    for (name, mesh) in [
        ("sphere 24x48", scenes::sphere(24, 48)),
        ("torus 24x24", scenes::torus(24, 24)),
    ] {
        let culled = same_with_and_without::<{ peel_runtime::fill::SUBPIXEL_BITS }>(name, &mesh);
        assert!(culled > 0, "{name}: culling skipped no subtree");
    }
}
