//! End to end: OBJ -> compiler -> `.peel` bytes -> no_std runtime -> pixels, compared with a
//! brute-force f64 ray caster that follows the camera conventions to the letter.
//!
//! Every pixel whose sample point lies farther than 1/16 pixel from all projected edges must
//! show exactly the reference's triangle id.

use std::path::{Path, PathBuf};

use glam::DVec3;
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::{load_obj, Mesh};
use peel_compiler::raster::{render_bytes_with, Settings, View};
use peel_e2e::{reference, RefCamera};
use peel_runtime::read::{Node, Scene};
use peel_runtime::traverse::Order;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name)
}

/// Compile `mesh` with ids.
fn compile(mesh: &Mesh) -> Vec<u8> {
    let options = CompileOptions {
        ids: true,
        ..CompileOptions::default()
    };
    compile_mesh(mesh, &options, &|_| {}).expect("compile").1
}

/// World-space polygons of a compiled file (their edges include every cut).
fn polygons(bytes: &[u8]) -> Vec<Vec<DVec3>> {
    let scene = Scene::parse(bytes).expect("valid file");
    let c = DVec3::from_array(scene.header().centre);
    (0..scene.header().polygon_count)
        .map(|i| {
            let p = scene.polygon(i);
            (0..u32::from(p.vertex_count))
                .map(|k| c + scene.polygon_vertex(&p, k).as_dvec3())
                .collect()
        })
        .collect()
}

/// Scene bounds of the source triangles.
fn bounds(mesh: &Mesh) -> (DVec3, DVec3) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for t in &mesh.triangles {
        for v in t.vertices {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    (lo, hi)
}

/// What [`compare`] counted.
#[derive(Debug, Clone, Copy, Default)]
struct Compared {
    /// Robust pixels whose rendered id differs from the reference's.
    bad: usize,
    /// Robust pixels (compared).
    robust: usize,
    /// Pixels where the reference sees a triangle.
    scene: usize,
    /// Robust pixels where the reference sees a triangle.
    robust_scene: usize,
}

/// Render `bytes` and the reference with `view` and compare their robust pixels.
fn compare(
    mesh: &Mesh,
    bytes: &[u8],
    polys: &[Vec<DVec3>],
    view: &View,
    settings: &Settings,
) -> Compared {
    let frame = render_bytes_with(
        bytes,
        view,
        &Settings {
            ids: true,
            ..*settings
        },
    )
    .expect("render");
    let scene = Scene::parse(bytes).unwrap();
    let camera = peel_compiler::raster::camera(&scene, view).unwrap();
    let cam = RefCamera {
        eye: view.eye,
        target: view.target,
        up: view.up,
        fov_y_deg: view.fov_y_deg,
        width: view.width,
        height: view.height,
        near: camera.near(),
    };
    let tris: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
    let r = reference(&tris, polys, &cam);
    let mut c = Compared::default();
    for (k, (&want, &ok)) in r.ids.iter().zip(&r.robust).enumerate() {
        if want != 0 {
            c.scene += 1;
        }
        if ok {
            c.robust += 1;
            if want != 0 {
                c.robust_scene += 1;
            }
            if frame.pixels[k] != want {
                c.bad += 1;
                if c.bad <= 5 {
                    eprintln!(
                        "pixel ({}, {}): rendered id+1 {} reference {}",
                        k % view.width as usize,
                        k / view.width as usize,
                        frame.pixels[k],
                        want
                    );
                }
            }
        }
    }
    c
}

/// Both drawing orders without culling, and front to back with culling when the eye is known
/// to be outside every closed mesh.
fn all_settings(outside: bool) -> Vec<Settings> {
    let mut v = vec![
        Settings {
            order: Order::FrontToBack,
            cull: false,
            ..Settings::default()
        },
        Settings {
            order: Order::BackToFront,
            cull: false,
            ..Settings::default()
        },
    ];
    if outside {
        v.push(Settings {
            order: Order::FrontToBack,
            cull: true,
            ..Settings::default()
        });
    }
    v
}

fn view(eye: DVec3, target: DVec3, width: u32, height: u32) -> View {
    View {
        eye,
        target,
        up: DVec3::Y,
        fov_y_deg: 60.0,
        width,
        height,
        near: None,
    }
}

/// Cameras around, inside and very close to the scene.
fn cameras(lo: DVec3, hi: DVec3) -> Vec<View> {
    let c = (lo + hi) / 2.0;
    let r = (hi - lo).length().max(1e-9) / 2.0;
    let mut v = Vec::new();
    for k in 0..8 {
        let a = k as f64 * 0.785 + 0.3;
        let e = c + DVec3::new(
            a.cos() * 2.6 * r,
            (k as f64 - 3.5) * 0.45 * r,
            a.sin() * 2.6 * r,
        );
        v.push(view(e, c, 96, 72));
    }
    // Inside the scene, looking at a corner.
    v.push(view(c + DVec3::new(0.01, 0.02, 0.03) * r, hi, 96, 72));
    // Very close to the bounding box: polygons far larger than the screen.
    v.push(view(
        DVec3::new(c.x + 0.1 * r, c.y + 0.05 * r, hi.z + 0.02 * r),
        DVec3::new(c.x, c.y, lo.z),
        96,
        72,
    ));
    // One pixel.
    v.push(view(c + DVec3::new(1.7, 1.1, 2.3) * r, c, 1, 1));
    v
}

/// Whether a scene's tree must hold a split node (then a camera is put on its first split
/// plane), or must not.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Splits {
    Expected,
    None,
}

fn check_scene(name: &str, mesh: &Mesh, extra: &[View], splits: Splits) {
    let bytes = compile(mesh);
    let polys = polygons(&bytes);
    let (lo, hi) = bounds(mesh);
    let mut views = cameras(lo, hi);
    views.extend_from_slice(extra);
    // A camera exactly on the first split plane of the tree (either order is right there).
    let scene = Scene::parse(&bytes).unwrap();
    let split = (0..scene.header().node_count)
        .map(|i| scene.node(i))
        .find(|n| matches!(n, Node::Split { .. }));
    match (split, splits) {
        (Some(Node::Split { plane, .. }), Splits::Expected) => {
            let p = scene.plane(plane);
            let centre = DVec3::from_array(scene.header().centre);
            let n = p.normal.as_dvec3();
            let c = (lo + hi) / 2.0 - centre;
            // The stored normal is unit length only to f32 precision: divide by |n|^2 so the
            // eye lies on the plane to f64 precision (the orthogonal offset keeps n . x).
            let on = c - n * ((n.dot(c) - f64::from(p.d)) / n.length_squared())
                + n.any_orthogonal_vector() * (hi - lo).length();
            let size = (hi - lo).length();
            let off = n.dot(on) - f64::from(p.d);
            assert!(
                off.abs() <= 1e-9 * size.max(1.0),
                "{name}: the split-plane camera is {off} off its plane"
            );
            views.push(view(on + centre, (lo + hi) / 2.0, 96, 72));
        }
        (None, Splits::None) => {}
        (found, _) => {
            panic!("{name}: expected split nodes: {splits:?}, first split found: {found:?}")
        }
    }
    let mut total_bad = 0;
    for (k, v) in views.iter().enumerate() {
        // Back-face culling assumes the eye is outside closed meshes: only the orbit cameras
        // (outside the bounding box) keep it on.
        let outside = k < 8;
        for settings in all_settings(outside) {
            let c = compare(mesh, &bytes, &polys, v, &settings);
            if c.bad > 0 {
                eprintln!(
                    "{name}: camera {k} ({v:?}) {settings:?}: {} of {} robust pixels differ",
                    c.bad, c.robust
                );
            }
            // A camera that sees the scene must compare some of its pixels: the test must not
            // pass by marking everything non-robust. (The one-pixel camera is exempt: it looks
            // at the bounding-box centre, which often lies on an edge, e.g. a face diagonal.)
            let tiny = v.width * v.height < 64;
            assert!(
                tiny || c.scene == 0 || c.robust_scene > 0,
                "{name}: camera {k} ({v:?}) sees {} scene pixels, none of them robust",
                c.scene
            );
            // The orbit cameras look at the scene's centre from outside: they all see it.
            assert!(
                !outside || c.scene > 0,
                "{name}: orbit camera {k} ({v:?}) sees nothing"
            );
            total_bad += c.bad;
        }
    }
    assert_eq!(
        total_bad, 0,
        "{name}: robust pixels differ from the reference"
    );
}

#[test]
fn fixtures_match_the_ray_caster() {
    for (name, splits) in [
        ("triangle.obj", Splits::None),
        ("cube.obj", Splits::None),
        ("nested_cubes.obj", Splits::None),
        ("staircase.obj", Splits::None),
        ("cyclic_triangles.obj", Splits::Expected),
        ("interpenetrating_boxes.obj", Splits::Expected),
        ("demo.obj", Splits::Expected),
    ] {
        let mesh = load_obj(&fixture(name)).expect("load fixture");
        check_scene(name, &mesh, &[], splits);
    }
}

#[test]
fn near_plane_cuts_polygons() {
    let mesh = load_obj(&fixture("cube.obj")).unwrap();
    let bytes = compile(&mesh);
    let polys = polygons(&bytes);
    // Eye just outside the +z face, looking along it: the near plane slices the face.
    let mut v = view(
        DVec3::new(0.2, 0.1, 1.02),
        DVec3::new(-1.0, -0.2, 0.6),
        120,
        90,
    );
    v.near = Some(0.08);
    for settings in all_settings(false) {
        let c = compare(&mesh, &bytes, &polys, &v, &settings);
        assert!(c.robust_scene > 1000, "{c:?}");
        assert_eq!(c.bad, 0, "{settings:?}");
    }
}

#[test]
fn large_image() {
    let mesh = load_obj(&fixture("nested_cubes.obj")).unwrap();
    let bytes = compile(&mesh);
    let polys = polygons(&bytes);
    let v = view(DVec3::new(5.0, 3.5, 6.0), DVec3::ZERO, 4096, 4096);
    for settings in all_settings(true) {
        let c = compare(&mesh, &bytes, &polys, &v, &settings);
        assert!(c.robust_scene > 1_000_000, "{c:?}");
        assert_eq!(c.bad, 0, "{settings:?}");
    }
}

#[test]
fn generated_closed_meshes_match() {
    let sphere = peel_compiler::scenes::sphere(10, 16);
    check_scene("sphere", &sphere, &[], Splits::Expected);
    let torus = peel_compiler::scenes::torus(16, 8);
    check_scene("torus", &torus, &[], Splits::Expected);
    let soup = peel_compiler::scenes::soup(60, 0.4, 3);
    check_scene("soup", &soup, &[], Splits::Expected);
}
