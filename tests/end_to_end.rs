//! End to end: OBJ -> compiler -> `.peel` bytes -> no_std runtime -> pixels, compared with a
//! brute-force f64 ray caster that follows the camera conventions to the letter.
//!
//! Every pixel whose sample point lies farther than 1/16 pixel from all projected edges must
//! show exactly the reference's triangle id, with culling on (the default) or off, in both
//! orders, wherever the eye is: outside, inside a closed mesh, on its surface, or with the
//! near plane cutting it open. Those of them not lit nearly edge-on must also show the colour
//! of the side of that triangle the reference sees: lit when it faces the light, `Kd * AMBIENT`
//! when it does not.

use std::path::{Path, PathBuf};

use glam::DVec3;
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::{load_obj, Mesh, SourceTriangle};
use peel_compiler::shade::{Shading, Surface, AMBIENT};
use peel_compiler::tools::raster::{render_bytes_with, Settings};
use peel_compiler::tools::shot::Shot;
use peel_e2e::polygons;
use peel_e2e::{bounds, closed_sphere, mesh_closed_outward, reference, shadowed};
use peel_runtime::read::layout::header_flags;
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
    compile_with(mesh, wide_vertices, false)
}

/// Compile `mesh` with ids, its vertices as `f32` when `wide`, its closed parts marked as
/// solids when `solid`.
fn compile_with(mesh: &Mesh, wide_vertices: bool, solid: bool) -> Vec<u8> {
    // Faceted: the colours are compared with the reference's faceted ones (smooth shading's
    // accuracy has its own test, `shading_gap::accuracy`).
    let options = CompileOptions {
        ids: true,
        wide_vertices,
        surface: Surface::Faceted,
        solid,
        ..CompileOptions::default()
    };
    compile_mesh(mesh, &options, &|_| {}).expect("compile").1
}

/// What [`compare`] counted.
#[derive(Debug, Clone, Copy, Default)]
struct Compared {
    /// Robust pixels whose rendered id differs from the reference's, or whose colour is not
    /// that of the side seen.
    bad: usize,
    /// Robust pixels whose colour was compared: their side seen faces the light (`lit`) or not,
    /// and of the latter, those whose side faces the sun but is in shadow.
    lit: usize,
    unlit: usize,
    shadowed: usize,
    /// Robust pixels (compared).
    robust: usize,
    /// Pixels where the reference sees a triangle.
    scene: usize,
    /// Robust pixels where the reference sees a triangle.
    robust_scene: usize,
}

impl Compared {
    /// Counts pixel `k` of `shot` as differing (`what`), printing the first few.
    fn differs(&mut self, shot: &Shot, k: usize, what: std::fmt::Arguments) {
        self.bad += 1;
        if self.bad <= 5 {
            let w = shot.width as usize;
            eprintln!("pixel ({}, {}): {what}", k % w, k / w);
        }
    }
}

/// Render `bytes` and the reference as `shot` sees them and compare their robust pixels: the
/// id, and away from grazing light the colour of the side seen (within 1 per channel: the
/// compiler lights the quantised triangle's plane, the reference the source triangle).
fn compare(
    mesh: &Mesh,
    bytes: &[u8],
    polys: &[Vec<DVec3>],
    shot: &Shot,
    settings: &Settings,
) -> Compared {
    compare_lit(mesh, bytes, polys, shot, settings, None)
}

/// [`compare`] for a file compiled with the default shading (`shadows` `None`), or with
/// `shadows`, the shading whose light cast its shadows: a side facing it in shadow is
/// `Kd * AMBIENT`. A point light's colours are baked at each polygon's centroid, so there only
/// lit or not (`Kd * AMBIENT`) is compared.
fn compare_lit(
    mesh: &Mesh,
    bytes: &[u8],
    polys: &[Vec<DVec3>],
    shot: &Shot,
    settings: &Settings,
    shadows: Option<Shading>,
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
    let shading = shadows.unwrap_or(CompileOptions::default().shading);
    let shadowed = match shading.light().filter(|_| shadows.is_some()) {
        Some(light) => shadowed(&r, &tris, shot, near, light),
        None => vec![false; r.ids.len()],
    };
    let exact = !matches!(shading, Shading::Point(_));
    let mut lighting = r.clone();
    lighting.exclude_grazing_light(&tris, shot, near, &shading);
    let colours = render_bytes_with(bytes, shot, settings).expect("render");
    let mut c = Compared::default();
    for k in (0..r.ids.len()).filter(|&k| lighting.robust[k]) {
        let Some(normal) = r.seen_normal(&tris, k) else {
            continue;
        };
        let kd = mesh.triangles[r.ids[k] as usize - 1].colour;
        let ambient = kd.map(|v| (f64::from(v) * AMBIENT).round() as u8);
        let want = if shadowed[k] {
            c.shadowed += 1;
            ambient
        } else {
            let at = r
                .hit_point(&tris, shot, near, k)
                .expect("a pixel on a triangle");
            shading.shade_at(kd, normal, at)
        };
        let p = colours.pixels[k];
        let got = [(p >> 16) as u8, (p >> 8) as u8, p as u8];
        if want == ambient {
            c.unlit += 1;
        } else {
            c.lit += 1;
        }
        let wrong = if exact {
            (0..3).any(|i| got[i].abs_diff(want[i]) > 1)
        } else {
            (got == ambient) != (want == ambient)
        };
        if wrong {
            c.differs(
                shot,
                k,
                format_args!("rendered colour {got:?}, the side seen is {want:?}"),
            );
        }
    }
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
                let got = frame.pixels[k];
                c.differs(
                    shot,
                    k,
                    format_args!("rendered id+1 {got} reference {want}"),
                );
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

/// Checks `mesh` from [`cameras`], `extra` and a camera on its first split plane in every
/// setting; returns the robust pixels whose colour was compared, lit and unlit.
fn check_scene(name: &str, mesh: &Mesh, extra: &[Shot], splits: Splits) -> (usize, usize) {
    check_compiled(name, mesh, &compile(mesh), extra, splits)
}

/// [`check_scene`] of `bytes`, compiled from `mesh`.
fn check_compiled(
    name: &str,
    mesh: &Mesh,
    bytes: &[u8],
    extra: &[Shot],
    splits: Splits,
) -> (usize, usize) {
    let bytes = bytes.to_vec();
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
    let mut lighting = (0, 0);
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
            lighting = (lighting.0 + c.lit, lighting.1 + c.unlit);
        }
    }
    assert_eq!(
        total_bad, 0,
        "{name}: robust pixels differ from the reference"
    );
    lighting
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
        let (lit, unlit) = check_scene(name, &mesh, &[], splits);
        // Not vacuous: the cameras see sides facing the light and sides turned away.
        assert!(lit > 100 && unlit > 100, "{name}: {lit} lit, {unlit} unlit");
    }
}

/// Compiles `mesh` with ids, lit by `shading` and with its light's shadows, and compares it with
/// the reference from each of `shots` in every setting; every robust pixel must match.
/// Returns the robust pixels in shadow compared.
fn check_shadows(name: &str, mesh: &Mesh, shading: Shading, shots: &[Shot]) -> usize {
    let options = CompileOptions {
        ids: true,
        shading,
        surface: Surface::Faceted,
        build: peel_compiler::tree::BuildOptions {
            shadows: shading.light(),
            ..Default::default()
        },
        ..CompileOptions::default()
    };
    let bytes = compile_mesh(mesh, &options, &|_| {}).expect("compile").1;
    let polys = polygons(&bytes);
    let mut in_shadow = 0;
    for (k, shot) in shots.iter().enumerate() {
        for settings in all_settings() {
            let c = compare_lit(mesh, &bytes, &polys, shot, &settings, Some(shading));
            assert_eq!(
                c.bad, 0,
                "{name}, {shading:?}, camera {k} ({shot:?}), {settings:?}: {c:?}"
            );
            in_shadow += c.shadowed;
        }
    }
    in_shadow
}

/// Shadows from a sun: every robust pixel shows its side seen lit, turned away or in shadow
/// as the reference's rays say, in both orders and with culling on and off, from cameras
/// around, inside and close to the scene: a box above a plane, a box sunk into it, boxes
/// that interpenetrate, and the demo scene, under suns from several directions.
#[test]
fn shadows_match_the_ray_caster() {
    use peel_compiler::tools::scenes;
    let ground = |t: &mut Vec<[DVec3; 3]>, y: f64| {
        let c =
            [(-2.0, -2.0), (2.0, -2.0), (2.0, 2.0), (-2.0, 2.0)].map(|(x, z)| DVec3::new(x, y, z));
        t.push([c[0], c[2], c[1]]);
        t.push([c[0], c[3], c[2]]);
    };
    let mut above = Vec::new();
    ground(&mut above, 0.0);
    scenes::boxed(
        &mut above,
        DVec3::new(-0.5, 0.3, -0.4),
        DVec3::new(0.4, 1.2, 0.5),
    );
    let mut sunk = Vec::new();
    ground(&mut sunk, 0.0);
    scenes::boxed(
        &mut sunk,
        DVec3::new(-0.3, -0.4, -0.6),
        DVec3::new(0.6, 0.8, 0.2),
    );
    let meshes = [
        ("box above a plane", scenes::mesh(above)),
        ("box sunk into a plane", scenes::mesh(sunk)),
        (
            "interpenetrating_boxes.obj",
            load_obj(&fixture("interpenetrating_boxes.obj")).unwrap(),
        ),
        ("demo.obj", load_obj(&fixture("demo.obj")).unwrap()),
    ];
    let suns = [
        DVec3::new(0.4, 0.8, 0.45),
        DVec3::new(-0.9, 0.5, 0.2),
        DVec3::new(0.1, 0.6, -0.8),
    ];
    for (name, mesh) in &meshes {
        let (lo, hi) = bounds(mesh);
        let mut in_shadow = 0;
        for sun in suns {
            in_shadow += check_shadows(name, mesh, Shading::Lambert(sun), &cameras(lo, hi));
        }
        // Not vacuous: every scene casts shadows the cameras see.
        assert!(
            in_shadow > 100,
            "{name}: {in_shadow} pixels in shadow compared"
        );
    }
}

/// The teapot of the shared models (skipped when they are absent) shadows itself: the spout,
/// the handle and the lid cast shadows on the body. Every robust pixel shows its side seen
/// lit, turned away or in shadow, in both orders, with culling on and off.
#[test]
fn the_teapot_shadows_itself() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models/teapot.obj");
    if !path.is_file() {
        println!("skipping: the shared models are absent");
        return;
    }
    let mesh = load_obj(&path).expect("the teapot loads");
    let sun = Shading::Lambert(DVec3::new(0.4, 0.8, 0.45));
    let (lo, hi) = bounds(&mesh);
    // Large enough images for pixels away from the small triangles' edges.
    let shots: Vec<Shot> = cameras(lo, hi)
        .into_iter()
        .take(8)
        .step_by(3)
        .map(|s| Shot {
            width: 320,
            height: 240,
            ..s
        })
        .collect();
    let in_shadow = check_shadows("teapot", &mesh, sun, &shots);
    assert!(in_shadow > 100, "{in_shadow} pixels in shadow compared");
}

/// A point light inside a room-like open box (a floor and four walls, no ceiling) with a
/// floating box and a pillar: every robust pixel is lit or not (`Kd * AMBIENT`) as the
/// reference's segments to the light say, in both orders, with culling on and off, from
/// cameras around, inside and close to it.
#[test]
fn a_point_light_in_a_room_matches_the_ray_caster() {
    use peel_compiler::tools::scenes;
    let v = DVec3::new;
    let quad = |t: &mut Vec<[DVec3; 3]>, c: [DVec3; 4]| {
        t.push([c[0], c[1], c[2]]);
        t.push([c[0], c[2], c[3]]);
    };
    let mut room = Vec::new();
    let (s, h) = (2.0, 2.0);
    quad(
        &mut room,
        [v(-s, 0.0, -s), v(-s, 0.0, s), v(s, 0.0, s), v(s, 0.0, -s)],
    );
    quad(
        &mut room,
        [v(-s, 0.0, -s), v(s, 0.0, -s), v(s, h, -s), v(-s, h, -s)],
    );
    quad(
        &mut room,
        [v(-s, 0.0, s), v(-s, h, s), v(s, h, s), v(s, 0.0, s)],
    );
    quad(
        &mut room,
        [v(-s, 0.0, -s), v(-s, h, -s), v(-s, h, s), v(-s, 0.0, s)],
    );
    quad(
        &mut room,
        [v(s, 0.0, -s), v(s, 0.0, s), v(s, h, s), v(s, h, -s)],
    );
    scenes::boxed(&mut room, v(-0.9, 0.3, -0.5), v(0.2, 0.9, 0.6));
    scenes::boxed(&mut room, v(0.7, -0.2, 0.6), v(1.0, 1.4, 0.9));
    let mesh = scenes::mesh(room);
    let (lo, hi) = bounds(&mesh);
    let mut in_shadow = 0;
    let mut shots = cameras(lo, hi);
    shots.push(Shot::new(v(-1.2, 1.5, -1.3), v(0.5, 0.0, 0.8), 96, 72));
    for light in [v(0.6, 1.8, -0.7), v(-1.5, 1.2, 1.4)] {
        in_shadow += check_shadows("room", &mesh, Shading::Point(light), &shots);
    }
    assert!(in_shadow > 100, "{in_shadow} pixels in shadow compared");
}

/// The colour at the centre of a 9x9 image of `bytes` seen from `eye` towards `target`.
fn centre_colour(bytes: &[u8], eye: DVec3, target: DVec3, settings: &Settings) -> [u8; 3] {
    let frame = render_bytes_with(bytes, &Shot::new(eye, target, 9, 9), settings).expect("render");
    let p = frame.pixels[4 * 9 + 4];
    [(p >> 16) as u8, (p >> 8) as u8, p as u8]
}

/// One triangle in the plane z = 0: the side facing the light is lit, the other side is
/// `Kd * AMBIENT`, whichever way the light comes and whatever the order and culling; `--flat`
/// shows `Kd` on both sides and stores one colour per polygon.
#[test]
fn a_face_is_lit_on_the_side_facing_the_light_only() {
    let mesh = load_obj(&fixture("triangle.obj")).unwrap();
    let kd = mesh.triangles[0].colour;
    let ambient = kd.map(|c| (f64::from(c) * AMBIENT).round() as u8);
    let centroid = DVec3::new(1.0, 1.0, 0.0) / 3.0;
    let above = centroid + DVec3::new(0.1, 0.2, 3.0);
    let below = centroid + DVec3::new(-0.2, 0.1, -3.0);
    let two_colours = |bytes: &[u8]| {
        let flags = Scene::parse(bytes).unwrap().header().flags;
        flags & peel_runtime::read::layout::header_flags::TWO_COLOURS != 0
    };
    for light in [DVec3::new(0.3, -0.2, 1.0), DVec3::new(-0.5, 0.4, -0.7)] {
        let shading = Shading::Lambert(light);
        let options = CompileOptions {
            shading,
            surface: Surface::Faceted,
            ..CompileOptions::default()
        };
        let bytes = compile_mesh(&mesh, &options, &|_| {}).unwrap().1;
        assert!(two_colours(&bytes));
        let (lit_eye, dark_eye) = if light.z > 0.0 {
            (above, below)
        } else {
            (below, above)
        };
        let lit = shading.shade(kd, (lit_eye - centroid).normalize().z.signum() * DVec3::Z);
        assert_ne!(lit, ambient, "{light}");
        for settings in all_settings() {
            let seen = |eye| centre_colour(&bytes, eye, centroid, &settings);
            assert_eq!(seen(lit_eye), lit, "{light}, {settings:?}: the lit side");
            assert_eq!(
                seen(dark_eye),
                ambient,
                "{light}, {settings:?}: the side away"
            );
        }
    }
    let flat = CompileOptions {
        shading: Shading::Flat,
        ..CompileOptions::default()
    };
    let bytes = compile_mesh(&mesh, &flat, &|_| {}).unwrap().1;
    assert!(!two_colours(&bytes), "--flat: one colour per polygon");
    for settings in all_settings() {
        for eye in [above, below] {
            assert_eq!(centre_colour(&bytes, eye, centroid, &settings), kd);
        }
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
    let torus = peel_compiler::tools::scenes::torus(16, 8);
    assert!(mesh_closed_outward(&torus));
    let soup = peel_compiler::tools::scenes::soup(60, 0.4, 3);
    for (name, mesh) in [("sphere", sphere), ("torus", torus), ("soup", soup)] {
        let (lit, unlit) = check_scene(name, &mesh, &[], Splits::Expected);
        assert!(lit > 100 && unlit > 100, "{name}: {lit} lit, {unlit} unlit");
    }
}

/// The same meshes, two tori crossing each other and the cow (when present), compiled with
/// their closed parts as solids: the walk skips the faces seen from behind when the whole
/// scene is in front of the near plane (the orbit cameras), and no robust pixel differs from
/// the reference from any camera.
#[test]
fn generated_solids_match() {
    let sphere = closed_sphere(10, 16);
    let torus = peel_compiler::tools::scenes::torus(16, 8);
    let mut crossed = torus.clone();
    let turned: Vec<_> = (torus.triangles.iter())
        .map(|t| SourceTriangle {
            opacity: u8::MAX,
            // A mirror (y and z swapped) keeps the faces outward once the corners swap too.
            vertices: [t.vertices[0], t.vertices[2], t.vertices[1]]
                .map(|v| DVec3::new(v.x + 0.7, v.z, v.y)),
            ..*t
        })
        .collect();
    crossed.triangles.extend(turned);
    assert!(mesh_closed_outward(&crossed));
    let mut meshes = vec![
        ("sphere", sphere),
        ("torus", torus),
        ("crossed tori", crossed),
    ];
    let cow = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models/cow.obj");
    if cow.is_file() {
        meshes.push(("cow", load_obj(&cow).expect("the cow loads")));
    } else {
        println!("skipping the cow: the shared models are absent");
    }
    for (name, mesh) in meshes {
        let bytes = compile_with(&mesh, false, true);
        let scene = Scene::parse(&bytes).unwrap();
        assert!(
            scene.header().flags & header_flags::SOLID != 0,
            "{name}: no solid"
        );
        let (lit, unlit) = check_compiled(name, &mesh, &bytes, &[], Splits::Expected);
        assert!(lit > 100 && unlit > 100, "{name}: {lit} lit, {unlit} unlit");
    }
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
