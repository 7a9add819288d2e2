//! End to end: OBJ -> compiler -> `.peel` bytes -> no_std runtime -> pixels, compared with a
//! brute-force f64 ray caster that follows the camera conventions to the letter.
//!
//! Every pixel whose sample point lies farther than 1/16 pixel from all projected edges must
//! show exactly the reference's triangle id, with culling on (the default) or off, in both
//! orders, wherever the eye is: outside, inside a closed mesh, on its surface, or with the
//! near plane cutting it open.

use std::path::{Path, PathBuf};

use glam::DVec3;
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::{load_obj, Mesh};
use peel_compiler::tools::raster::{render_bytes_with, Settings};
use peel_compiler::tools::shot::Shot;
use peel_e2e::{bounds, closed_sphere, mesh_closed_outward, reference};
use peel_runtime::read::{Node, Scene};
use peel_runtime::traverse::Order;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name)
}

/// Compile `mesh` with ids.
fn compile(mesh: &Mesh) -> Vec<u8> {
    compile_vertices(mesh, false)
}

/// Compile `mesh` with ids, its vertices as `f32` when `wide`.
fn compile_vertices(mesh: &Mesh, wide_vertices: bool) -> Vec<u8> {
    let options = CompileOptions {
        ids: true,
        wide_vertices,
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

/// Render `bytes` and the reference as `shot` sees them and compare their robust pixels.
fn compare(
    mesh: &Mesh,
    bytes: &[u8],
    polys: &[Vec<DVec3>],
    shot: &Shot,
    settings: &Settings,
) -> Compared {
    let frame = render_bytes_with(
        bytes,
        shot,
        &Settings {
            ids: true,
            ..*settings
        },
    )
    .expect("render");
    let near = shot.near_over(&Scene::parse(bytes).unwrap().header());
    let tris: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
    let r = reference(&tris, polys, shot, near);
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
                        k % shot.width as usize,
                        k / shot.width as usize,
                        frame.pixels[k],
                        want
                    );
                }
            }
        }
    }
    c
}

/// Both drawing orders, with culling (the default) and without, and with integer vertices,
/// for every camera: no robust pixel differs from the reference, wherever the eye is: outside,
/// inside a closed mesh, on its surface, or with the near plane cutting it open.
fn all_settings() -> Vec<Settings> {
    let mut v = Vec::new();
    for cull in [true, false] {
        for order in [Order::FrontToBack, Order::BackToFront] {
            v.push(Settings {
                order,
                cull,
                ..Settings::default()
            });
        }
    }
    // Integer vertices (frames with culling and without clipping), in both orders.
    for order in [Order::FrontToBack, Order::BackToFront] {
        v.push(Settings {
            order,
            integer_vertices: true,
            ..Settings::default()
        });
    }
    v
}

/// Cameras around, inside and very close to the scene.
fn cameras(lo: DVec3, hi: DVec3) -> Vec<Shot> {
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
        v.push(Shot::new(e, c, 96, 72));
    }
    // Inside the scene, looking at a corner.
    v.push(Shot::new(c + DVec3::new(0.01, 0.02, 0.03) * r, hi, 96, 72));
    // Very close to the bounding box: polygons far larger than the screen.
    v.push(Shot::new(
        DVec3::new(c.x + 0.1 * r, c.y + 0.05 * r, hi.z + 0.02 * r),
        DVec3::new(c.x, c.y, lo.z),
        96,
        72,
    ));
    // One pixel.
    v.push(Shot::new(c + DVec3::new(1.7, 1.1, 2.3) * r, c, 1, 1));
    v
}

/// Whether a scene's tree must hold a split node (then a camera is put on its first split
/// plane), or must not.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Splits {
    Expected,
    None,
}

fn check_scene(name: &str, mesh: &Mesh, extra: &[Shot], splits: Splits) {
    let bytes = compile(mesh);
    let polys = polygons(&bytes);
    let (lo, hi) = bounds(mesh);
    let mut shots = cameras(lo, hi);
    shots.extend_from_slice(extra);
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
            shots.push(Shot::new(on + centre, (lo + hi) / 2.0, 96, 72));
        }
        (None, Splits::None) => {}
        (found, _) => {
            panic!("{name}: expected split nodes: {splits:?}, first split found: {found:?}")
        }
    }
    let mut total_bad = 0;
    for (k, v) in shots.iter().enumerate() {
        // The orbit cameras are outside the bounding box; the others are inside or very close.
        let outside = k < 8;
        for settings in all_settings() {
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
    let mut v = Shot::new(
        DVec3::new(0.2, 0.1, 1.02),
        DVec3::new(-1.0, -0.2, 0.6),
        120,
        90,
    );
    v.near = Some(0.08);
    for settings in all_settings() {
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
    let v = Shot::new(DVec3::new(5.0, 3.5, 6.0), DVec3::ZERO, 4096, 4096);
    for settings in all_settings() {
        let c = compare(&mesh, &bytes, &polys, &v, &settings);
        assert!(c.robust_scene > 1_000_000, "{c:?}");
        assert_eq!(c.bad, 0, "{settings:?}");
    }
}

#[test]
fn generated_closed_meshes_match() {
    let sphere = closed_sphere(10, 16);
    assert!(mesh_closed_outward(&sphere));
    check_scene("sphere", &sphere, &[], Splits::Expected);
    let torus = peel_compiler::tools::scenes::torus(16, 8);
    assert!(mesh_closed_outward(&torus));
    check_scene("torus", &torus, &[], Splits::Expected);
    let soup = peel_compiler::tools::scenes::soup(60, 0.4, 3);
    check_scene("soup", &soup, &[], Splits::Expected);
}

/// A camera of [`culling_matches_inside_on_and_through_closed_meshes`]: a name, the shot,
/// and the least number of robust pixels showing the scene it must compare.
struct NamedShot {
    name: String,
    shot: Shot,
    min_robust_scene: usize,
    /// The eye lies on a face: the nearest points seen are at depth ~0, so no fixed step
    /// bounds their error in pixels. Checked with `f32` vertices only.
    eye_on_surface: bool,
}

fn shot(
    name: &str,
    eye: DVec3,
    target: DVec3,
    near: Option<f64>,
    min_robust_scene: usize,
) -> NamedShot {
    NamedShot {
        name: name.to_string(),
        shot: Shot {
            near,
            ..Shot::new(eye, target, 96, 72)
        },
        min_robust_scene,
        eye_on_surface: false,
    }
}

/// A [`shot`] whose eye lies on a face of the mesh.
fn shot_on_surface(name: &str, eye: DVec3, target: DVec3, min_robust_scene: usize) -> NamedShot {
    NamedShot {
        eye_on_surface: true,
        ..shot(name, eye, target, None, min_robust_scene)
    }
}

/// Render `shots` of `mesh` in both orders with culling (the default) and without, from files
/// with 16-bit and with `f32` vertices, and compare every robust pixel with the ray caster;
/// each shot must compare enough scene pixels. Returns a line per shot and setting whose robust
/// pixels differ.
fn check_shots(scene: &str, mesh: &Mesh, shots: &[NamedShot]) -> Vec<String> {
    // Not vacuous: the mesh is closed, so the cameras inside it or cutting it see back faces.
    assert!(mesh_closed_outward(mesh), "{scene}: the mesh is not closed");
    let files = [false, true].map(|wide| {
        let bytes = compile_vertices(mesh, wide);
        let polys = polygons(&bytes);
        (wide, bytes, polys)
    });
    let mut failures = Vec::new();
    for s in shots {
        let checked = files.iter().filter(|(wide, ..)| *wide || !s.eye_on_surface);
        for ((wide, bytes, polys), settings) in
            checked.flat_map(|f| all_settings().into_iter().map(move |s| (f, s)))
        {
            let c = compare(mesh, bytes, polys, &s.shot, &settings);
            assert!(
                c.robust_scene >= s.min_robust_scene,
                "{scene}, {}: only {} robust scene pixels compared ({c:?}, {:?})",
                s.name,
                c.robust_scene,
                s.shot
            );
            if c.bad > 0 {
                failures.push(format!(
                    "{scene}, {} ({:?}, cull {}, wide vertices {wide}): {} of {} robust pixels \
                     ({} showing the scene) differ",
                    s.name, settings.order, settings.cull, c.bad, c.robust, c.robust_scene
                ));
            }
        }
    }
    failures
}

/// A point on triangle `i` of `mesh` (its centroid, to f64 rounding) and the triangle's unit
/// outward normal.
fn on_triangle(mesh: &Mesh, i: usize) -> (DVec3, DVec3) {
    let [a, b, c] = mesh.triangles[i].vertices;
    ((a + b + c) / 3.0, (b - a).cross(c - a).normalize())
}

/// With culling on (the default) in both orders, cameras inside closed meshes, exactly on
/// their surface and with the near plane cutting them open see what the ray caster sees:
/// the back faces of the mesh's inside where it shows.
#[test]
fn culling_matches_inside_on_and_through_closed_meshes() {
    // The cube [-1, 1]^3.
    let cube = load_obj(&fixture("cube.obj")).unwrap();
    let v = DVec3::new;
    let mut failures = check_shots(
        "cube.obj",
        &cube,
        &[
            shot("inside", v(0.2, 0.1, 0.3), v(1.0, 0.2, 0.5), None, 5000),
            shot(
                "inside, down",
                v(-0.5, 0.4, -0.3),
                v(0.3, -0.9, 0.8),
                None,
                5000,
            ),
            shot(
                "on z = 1, inwards",
                v(0.2, 0.1, 1.0),
                v(0.1, 0.0, -1.0),
                None,
                5000,
            ),
            shot(
                "on z = 1, along it",
                v(0.2, 0.1, 1.0),
                v(-1.0, -0.2, 1.0),
                None,
                2000,
            ),
            shot(
                "on z = 1, grazing in",
                v(0.2, 0.1, 1.0),
                v(-1.0, -0.2, 0.6),
                None,
                3000,
            ),
            shot(
                "on z = 1, outwards",
                v(0.2, 0.1, 1.0),
                v(1.2, 0.3, 1.6),
                None,
                500,
            ),
            shot(
                "on x = -1, inwards",
                v(-1.0, 0.3, -0.2),
                v(0.5, -0.4, 0.1),
                None,
                5000,
            ),
            shot(
                "near cuts z = 1",
                v(0.2, 0.1, 1.02),
                v(0.1, 0.0, -1.0),
                Some(0.08),
                5000,
            ),
            shot(
                "near cuts x = 1",
                v(1.03, 0.3, -0.2),
                v(-1.0, 0.1, 0.1),
                Some(0.1),
                5000,
            ),
        ],
    );

    // The unit sphere (10 rings, 16 segments): (0, 0, 1) is one of its vertices.
    let sphere = closed_sphere(10, 16);
    let (p, n) = on_triangle(&sphere, 70);
    let tangent = n.any_orthogonal_vector();
    failures.extend(check_shots(
        "sphere",
        &sphere,
        &[
            shot("inside", v(0.1, -0.2, 0.15), v(1.0, 0.3, 0.2), None, 5000),
            shot(
                "inside, down",
                v(-0.3, 0.3, -0.2),
                v(0.5, -1.0, 0.4),
                None,
                5000,
            ),
            shot_on_surface("on a face, inwards", p, p - n, 5000),
            shot_on_surface("on a face, grazing in", p, p + tangent - 0.3 * n, 3000),
            shot(
                "near cuts",
                v(0.05, 0.02, 1.03),
                DVec3::ZERO,
                Some(0.1),
                5000,
            ),
        ],
    ));

    // The torus (major radius 1, tube radius 0.35, 16 x 8): the centre of the tube's cross
    // section at a ring of vertices, and the outer equator's vertex (1.35, 0, 0).
    let torus = peel_compiler::tools::scenes::torus(16, 8);
    let u = 2.0 * std::f64::consts::PI * 3.0 / 16.0;
    let ring = v(u.cos(), 0.0, u.sin());
    let along = v(-u.sin(), 0.0, u.cos());
    let (p, n) = on_triangle(&torus, 50);
    failures.extend(check_shots(
        "torus",
        &torus,
        &[
            shot(
                "inside the tube, along it",
                ring * 1.02 + v(0.0, 0.05, 0.0),
                ring + along,
                None,
                5000,
            ),
            shot(
                "inside the tube, across it",
                ring * 0.98,
                ring * 1.5 + v(0.0, 0.6, 0.0),
                None,
                5000,
            ),
            shot_on_surface("on a face, inwards", p, p - n, 5000),
            shot(
                "near cuts the outside",
                v(1.38, 0.03, 0.02),
                DVec3::ZERO,
                Some(0.1),
                3000,
            ),
        ],
    ));
    assert!(
        failures.is_empty(),
        "robust pixels differ from the reference:\n{}",
        failures.join("\n")
    );
}
