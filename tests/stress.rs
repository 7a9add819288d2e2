//! Stress suite: hard inputs compiled, checked against the build's exact invariants
//! (`peel_compiler::tree::verify`), compiled again for determinism, and rendered against the
//! reference ray caster. Closed meshes must render without crack pixels.
//!
//! `cargo test --release --test stress` runs the fast subset (CI); `-- --ignored` adds the long
//! run (1000 random rotations, large sizes, more cameras). `-- --nocapture` prints a table.

use std::path::Path;
use std::time::Instant;

use glam::{DMat3, DVec3};
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::{load_obj, Mesh};
use peel_compiler::shadow::Light;
use peel_compiler::tools::raster::render_bytes;
use peel_compiler::tools::scenes::{self, SplitMix};
use peel_compiler::tools::shot::Shot;
use peel_compiler::tree::{verify, BuildOptions, DisplayTree, TreeNode};
use peel_e2e::polygons;
use peel_e2e::{bounds, reference};
use peel_runtime::read::Scene;

fn map(mesh: &Mesh, f: impl Fn(DVec3) -> DVec3) -> Mesh {
    scenes::mesh(mesh.triangles.iter().map(|t| t.vertices.map(&f)).collect())
}

/// How strictly a case's pixels are compared with the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Pixels {
    /// Robust pixels show the reference's triangle, and closed meshes have no crack.
    Closed,
    /// Robust pixels show the reference's triangle.
    Ids,
    /// Robust pixels are covered iff the reference covers them (which of near-coincident
    /// triangles wins is not decidable in f64).
    Coverage,
}

/// What one case measured.
#[derive(Debug, Clone)]
struct Outcome {
    name: String,
    kept: u64,
    polygons: u64,
    seconds: f64,
}

impl Outcome {
    fn growth(&self) -> f64 {
        self.polygons as f64 / self.kept.max(1) as f64
    }
}

fn same_tree(a: &DisplayTree, b: &DisplayTree) -> bool {
    a.centre == b.centre
        && a.vertices == b.vertices
        && a.planes == b.planes
        && a.polygons == b.polygons
        && a.nodes == b.nodes
        && a.stats == b.stats
}

/// `n` cameras outside the bounding sphere, spread over it (golden-angle spiral), with a
/// little distance and target jitter.
fn cameras(mesh: &Mesh, n: usize, size: (u32, u32), seed: u64) -> Vec<Shot> {
    let (lo, hi) = bounds(mesh);
    let c = (lo + hi) / 2.0;
    let r = ((hi - lo).length() / 2.0).max(f64::MIN_POSITIVE);
    let mut rng = SplitMix(seed);
    (0..n)
        .map(|k| {
            let y = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
            let a = k as f64 * 2.399_963_229_728_653;
            let s = (1.0 - y * y).sqrt();
            let dir = DVec3::new(s * a.cos(), y, s * a.sin());
            let dist = r * (2.2 + 1.5 * rng.unit());
            let jitter = (DVec3::new(rng.unit(), rng.unit(), rng.unit()) - 0.5) * 0.3 * r;
            Shot {
                up: if y.abs() > 0.9 { DVec3::X } else { DVec3::Y },
                fov_y_deg: 50.0,
                ..Shot::new(c + dir * dist, c + jitter, size.0, size.1)
            }
        })
        .collect()
}

/// Pixel differences of one view: robust id mismatches, robust coverage mismatches, cracks.
#[derive(Debug, Default, Clone, Copy)]
struct Diff {
    ids: usize,
    coverage: usize,
    cracks: usize,
}

/// A crack pixel: the reference covers it and all its neighbours with front faces, and the
/// render leaves it at the background or shows a back face there (on a closed, outward-facing
/// mesh a back face is only visible through a crack).
fn compare(mesh: &Mesh, bytes: &[u8], polys: &[Vec<DVec3>], shot: &Shot) -> Diff {
    let frame = render_bytes(bytes, shot, true, [0, 0, 0]).expect("render");
    let near = shot.near_over(&Scene::parse(bytes).unwrap().header());
    let tris: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
    let r = reference(&tris, polys, shot, near);
    let (w, h) = (shot.width as i64, shot.height as i64);
    let mut d = Diff::default();
    for (k, (&want, &ok)) in r.ids.iter().zip(&r.robust).enumerate() {
        let got = frame.pixels[k];
        if ok && got != want {
            d.ids += 1;
        }
        if ok && (got == 0) != (want == 0) {
            d.coverage += 1;
        }
        let (x, y) = (k as i64 % w, k as i64 / w);
        let covered =
            |i: i64, j: i64| i >= 0 && j >= 0 && i < w && j < h && r.ids[(j * w + i) as usize] != 0;
        let back = |id: u32| {
            id != 0
                && mesh.triangles.get(id as usize - 1).is_some_and(|t| {
                    let [a, b, c] = t.vertices;
                    (b - a).cross(c - a).dot(shot.eye - a) < 0.0
                })
        };
        let through = got == 0 || (back(got) && !back(want));
        if through && (-1..=1).all(|j| (-1..=1).all(|i| covered(x + i, y + j))) {
            d.cracks += 1;
        }
    }
    d
}

/// Verify, compile twice (determinism), render from `views` cameras; panics with the case name.
fn run(name: &str, mesh: &Mesh, pixels: Pixels, views: usize, size: (u32, u32)) -> Outcome {
    run_with(name, mesh, pixels, views, size, BuildOptions::default())
}

/// [`run`] with the build's `options`.
fn run_with(
    name: &str,
    mesh: &Mesh,
    pixels: Pixels,
    views: usize,
    size: (u32, u32),
    options: BuildOptions,
) -> Outcome {
    let start = Instant::now();
    let tree =
        verify(mesh, &options, 4).unwrap_or_else(|e| panic!("{name}: invariant broken: {e}"));
    let s = tree.stats;
    assert_eq!(s.input_triangles, mesh.triangles.len() as u64, "{name}");
    assert!(s.degenerate_dropped <= s.input_triangles, "{name}");
    let compile = CompileOptions {
        ids: true,
        build: options,
        ..CompileOptions::default()
    };
    let (again, bytes) =
        compile_mesh(mesh, &compile, &|_| {}).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(same_tree(&tree, &again), "{name}: two builds differ");
    let polys = polygons(&bytes);
    let mut total = Diff::default();
    for (k, view) in cameras(mesh, views, size, 11).iter().enumerate() {
        let d = compare(mesh, &bytes, &polys, view);
        if d.ids + d.coverage + d.cracks > 0 {
            eprintln!("{name}: camera {k}: {d:?}");
        }
        total.ids += d.ids;
        total.coverage += d.coverage;
        total.cracks += d.cracks;
    }
    match pixels {
        Pixels::Closed => {
            assert_eq!(total.cracks, 0, "{name}: crack pixels");
            assert_eq!(total.ids, 0, "{name}: robust pixels differ");
        }
        Pixels::Ids => assert_eq!(total.ids, 0, "{name}: robust pixels differ"),
        Pixels::Coverage => assert_eq!(total.coverage, 0, "{name}: robust coverage differs"),
    }
    Outcome {
        name: name.to_string(),
        kept: s.input_triangles - s.degenerate_dropped,
        polygons: s.output_polygons,
        seconds: start.elapsed().as_secs_f64(),
    }
}

fn report(title: &str, outcomes: &[Outcome]) {
    let growth = outcomes
        .iter()
        .max_by(|a, b| a.growth().total_cmp(&b.growth()));
    let slowest = outcomes
        .iter()
        .max_by(|a, b| a.seconds.total_cmp(&b.seconds));
    println!("{title}: {} cases", outcomes.len());
    if let (Some(g), Some(s)) = (growth, slowest) {
        println!(
            "  largest growth {:.2}x ({}: {} -> {} polygons); slowest {:.2}s ({})",
            g.growth(),
            g.name,
            g.kept,
            g.polygons,
            s.seconds,
            s.name
        );
    }
}

fn models() -> Option<std::path::PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models");
    if dir.is_dir() {
        Some(dir)
    } else {
        println!("skipping: shared models not found at ../shared/models");
        None
    }
}

// ---------------------------------------------------------------------------------------------
// Watertightness.

fn closed_meshes() -> Vec<(String, Mesh)> {
    // Turned off its axis, the torus's rings of edges no longer lie in planes, so the build
    // cuts it (upright, it splits along them without a cut).
    let turn = DMat3::from_euler(glam::EulerRot::XYZ, 0.3, 0.7, 1.1);
    vec![
        ("sphere".into(), scenes::sphere(12, 18)),
        ("torus".into(), scenes::torus(18, 10)),
        (
            "turned torus".into(),
            map(&scenes::torus(18, 10), |p| turn * p),
        ),
        ("box grid".into(), scenes::box_grid(3)),
    ]
}

/// Shadows from random suns and point lights cut polygons without opening cracks or breaking
/// the tree's invariants (checked on every node, with the area partition of each source
/// triangle): the closed meshes from 100 cameras each, and random soups.
#[test]
fn shadows_keep_meshes_watertight_and_trees_valid() {
    let mut rng = SplitMix(77);
    let sun = |rng: &mut SplitMix| {
        let mut c = || rng.unit() * 2.0 - 1.0;
        DVec3::new(c(), c().abs() + 0.2, c())
    };
    let mut out = Vec::new();
    for (name, mesh) in closed_meshes() {
        let sun = sun(&mut rng);
        let options = BuildOptions {
            shadows: Some(Light::Sun(sun)),
            ..BuildOptions::default()
        };
        let o = run_with(
            &format!("{name}, sun {sun}"),
            &mesh,
            Pixels::Closed,
            100,
            (160, 120),
            options,
        );
        // A convex mesh shadows only whole faces (those turned away); the others cast
        // shadows on themselves, along which their faces are cut.
        assert!(
            name == "sphere" || o.polygons > o.kept,
            "{}: no shadow was cut",
            o.name
        );
        out.push(o);
    }
    for (name, mesh) in closed_meshes() {
        // A point light around the mesh, within one and a half times its half-extent.
        let (lo, hi) = bounds(&mesh);
        let mut c = || rng.unit() * 3.0 - 1.5;
        let at = (lo + hi) / 2.0 + DVec3::new(c(), c(), c()) * (hi - lo) / 2.0;
        let options = BuildOptions {
            shadows: Some(Light::Point(at)),
            ..BuildOptions::default()
        };
        let name = format!("{name}, point light {at}");
        out.push(run_with(
            &name,
            &mesh,
            Pixels::Closed,
            100,
            (160, 120),
            options,
        ));
    }
    for seed in 0..4 {
        let sun = sun(&mut rng);
        let options = BuildOptions {
            shadows: Some(Light::Sun(sun)),
            ..BuildOptions::default()
        };
        let soup = scenes::soup(60, 0.5, seed);
        out.push(run_with(
            &format!("soup {seed}, sun {sun}"),
            &soup,
            Pixels::Ids,
            4,
            (48, 36),
            options,
        ));
    }
    report("shadows", &out);
}

#[test]
fn closed_meshes_have_no_cracks_from_100_cameras() {
    let mut out = Vec::new();
    for (name, mesh) in closed_meshes() {
        out.push(run(&name, &mesh, Pixels::Closed, 100, (160, 120)));
    }
    report("watertight", &out);
}

#[test]
fn the_cow_has_no_cracks_from_100_cameras() {
    let Some(dir) = models() else { return };
    let mesh = load_obj(&dir.join("cow.obj")).expect("cow.obj");
    let out = run("cow", &mesh, Pixels::Closed, 100, (160, 120));
    report("cow", &[out]);
}

/// A turned torus where the writer's rounding brings the ends of short cut edges together: a
/// polygon whose vertices then coincide in pairs had no three that defined its plane, was
/// drawn on the wrong side of its node's child, and showed hundreds of wrong robust pixels
/// from some of these cameras.
#[test]
fn a_turned_torus_whose_short_cut_edges_round_to_points() {
    let turn = DMat3::from_euler(
        glam::EulerRot::ZYX,
        4.8679949541599505,
        2.917536956792414,
        6.07573107951825,
    );
    let mesh = map(&scenes::torus(18, 10), |p| turn * p);
    let out = run("turned torus", &mesh, Pixels::Closed, 100, (160, 120));
    report("turned torus", &[out]);
}

// ---------------------------------------------------------------------------------------------
// Transforms.

/// The same meshes translated by 0, ±1e6 and scaled by 1e-6, 1, 1e6.
#[test]
fn translated_and_scaled_meshes() {
    let mut out = Vec::new();
    for (name, mesh) in [
        ("torus", scenes::torus(10, 6)),
        ("soup", scenes::soup(40, 0.4, 5)),
    ] {
        for shift in [0.0, 1e6, -1e6] {
            for scale in [1e-6, 1.0, 1e6] {
                let m = map(&mesh, |p| p * scale + DVec3::splat(shift * scale.max(1.0)));
                let pixels = if name == "torus" {
                    Pixels::Closed
                } else {
                    Pixels::Ids
                };
                out.push(run(
                    &format!("{name} x{scale:e} +{shift:e}"),
                    &m,
                    pixels,
                    6,
                    (48, 36),
                ));
            }
        }
    }
    report("translated/scaled", &out);
}

/// A random rotation (uniform enough: three random angles).
fn rotation(rng: &mut SplitMix) -> DMat3 {
    let mut a = || rng.unit() * std::f64::consts::TAU;
    DMat3::from_euler(glam::EulerRot::ZYX, a(), a(), a())
}

fn rotations(n: usize, views: usize) -> Vec<Outcome> {
    let base = [scenes::torus(8, 6), scenes::soup(20, 0.5, 9)];
    let mut rng = SplitMix(1234);
    (0..n)
        .map(|k| {
            let r = rotation(&mut rng);
            let mesh = map(&base[k % 2], |p| r * p);
            let pixels = if k % 2 == 0 {
                Pixels::Closed
            } else {
                Pixels::Ids
            };
            run(&format!("rotation {k}"), &mesh, pixels, views, (40, 30))
        })
        .collect()
}

#[test]
fn random_rotations() {
    report("rotations", &rotations(12, 2));
}

#[test]
#[ignore = "long run: cargo test --release --test stress -- --ignored"]
fn random_rotations_1000() {
    report("rotations (long)", &rotations(1000, 2));
}

/// An exact transform of a mesh on a dyadic grid: the map, and its linear part (what it does
/// to positions relative to the centre).
type Exact = (&'static str, fn(DVec3) -> DVec3, fn(DVec3) -> DVec3);

const TRANSLATE: Exact = ("translate", |p| p + DVec3::new(3.0, -5.0, 1024.0), |p| p);
const SWAPS_AND_MIRRORS: [Exact; 5] = [
    (
        "swap xy",
        |p| DVec3::new(p.y, p.x, p.z),
        |p| DVec3::new(p.y, p.x, p.z),
    ),
    (
        "swap yz",
        |p| DVec3::new(p.x, p.z, p.y),
        |p| DVec3::new(p.x, p.z, p.y),
    ),
    (
        "cycle",
        |p| DVec3::new(p.z, p.x, p.y),
        |p| DVec3::new(p.z, p.x, p.y),
    ),
    (
        "mirror x",
        |p| DVec3::new(-p.x, p.y, p.z),
        |p| DVec3::new(-p.x, p.y, p.z),
    ),
    (
        "mirror z",
        |p| DVec3::new(p.x, p.y, -p.z),
        |p| DVec3::new(p.x, p.y, -p.z),
    ),
];

/// Differences between the tree of `base` and the tree of its transform (empty: the same
/// tree up to the transform, polygon order inside convex nodes aside).
fn transform_differences(name: &str, base: &Mesh, (what, f, linear): Exact) -> Vec<String> {
    let options = BuildOptions::default();
    let t0 = verify(base, &options, 2).unwrap();
    let t = verify(&map(base, f), &options, 2).unwrap_or_else(|e| panic!("{name} {what}: {e}"));
    let mut out = Vec::new();
    if t.stats != t0.stats {
        out.push(format!("{name} {what}: statistics differ"));
    }
    let shape = |t: &DisplayTree| -> Vec<(bool, u32)> {
        t.nodes
            .iter()
            .map(|n| match *n {
                TreeNode::Convex { polygon_count, .. } => (true, polygon_count),
                TreeNode::Split { .. } => (false, 0),
            })
            .collect()
    };
    if shape(&t) != shape(&t0) {
        out.push(format!("{name} {what}: tree shapes differ"));
    }
    // `+ 0.0` folds -0 into 0.
    let key = |v: DVec3| (v + DVec3::ZERO).to_array().map(f64::to_bits);
    let polys = |t: &DisplayTree, g: fn(DVec3) -> DVec3| {
        let mut out: Vec<(u32, Vec<[u64; 3]>)> = t
            .polygons
            .iter()
            .map(|p| {
                let mut v: Vec<[u64; 3]> = p
                    .vertices
                    .iter()
                    .map(|&i| key(g(t.vertices[i as usize])))
                    .collect();
                v.sort_unstable();
                (p.source, v)
            })
            .collect();
        out.sort_unstable();
        out
    };
    if polys(&t0, linear) != polys(&t, |p| p) {
        out.push(format!("{name} {what}: polygons differ"));
    }
    out
}

fn dyadic_meshes() -> Vec<(&'static str, Mesh)> {
    let snap = |p: DVec3| (p * 1024.0).round() / 1024.0;
    vec![
        ("torus", map(&scenes::torus(10, 6), snap)),
        ("soup", map(&scenes::soup(30, 0.5, 2), snap)),
    ]
}

/// A whole-grid translation gives exactly the same tree.
#[test]
fn grid_translations_give_the_same_tree() {
    for (name, base) in dyadic_meshes() {
        let d = transform_differences(name, &base, TRANSLATE);
        assert!(d.is_empty(), "{d:?}");
    }
}

/// Axis swaps and mirrors give the same tree up to the transform: the build breaks ties by
/// plane ids numbered in source order and never by axis order or plane sign.
#[test]
fn swaps_and_mirrors_give_the_same_tree() {
    let mut all = Vec::new();
    for (name, base) in dyadic_meshes() {
        for t in SWAPS_AND_MIRRORS {
            all.extend(transform_differences(name, &base, t));
        }
    }
    assert!(all.is_empty(), "{all:#?}");
}

// ---------------------------------------------------------------------------------------------
// Degenerate and adversarial inputs.

/// Triangles sharing the edge (0,0,0)-(1,0,0), consecutive ones `angle` radians apart.
fn fan(count: usize, angle: f64) -> Mesh {
    scenes::mesh(
        (0..count)
            .map(|i| {
                let a = 0.4 + i as f64 * angle;
                [DVec3::ZERO, DVec3::X, DVec3::new(0.5, a.cos(), a.sin())]
            })
            .collect(),
    )
}

#[test]
fn near_coplanar_fans() {
    let mut out = Vec::new();
    for e in 3..=9 {
        let angle = 10f64.powi(-e);
        out.push(run(
            &format!("fan 1e-{e}"),
            &fan(12, angle),
            Pixels::Coverage,
            4,
            (48, 36),
        ));
    }
    report("fans", &out);
}

/// `n` pages around the x axis, all sharing the segment (0,0,0)-(1,0,0).
fn book(n: usize) -> Mesh {
    fan(n, std::f64::consts::TAU / n as f64)
}

/// `n` random triangles sharing the origin as a corner.
fn star(n: usize, seed: u64) -> Mesh {
    let mut rng = SplitMix(seed);
    let mut dir =
        || DVec3::new(rng.unit() - 0.5, rng.unit() - 0.5, rng.unit() - 0.5).normalize_or(DVec3::X);
    scenes::mesh((0..n).map(|_| [DVec3::ZERO, dir(), dir()]).collect())
}

#[test]
fn book_pages_and_a_star() {
    let out = vec![
        run("book 1000", &book(1000), Pixels::Coverage, 3, (48, 36)),
        run("star 1000", &star(1000, 4), Pixels::Coverage, 3, (48, 36)),
    ];
    report("book/star", &out);
}

#[test]
fn duplicate_and_opposite_duplicate_triangles() {
    let base = scenes::sphere(6, 8);
    let mut tris: Vec<[DVec3; 3]> = base.triangles.iter().map(|t| t.vertices).collect();
    let n = tris.len();
    for k in 0..n {
        let t = tris[k];
        tris.push(t);
        tris.push([t[0], t[2], t[1]]);
    }
    let out = run(
        "duplicates",
        &scenes::mesh(tris),
        Pixels::Coverage,
        8,
        (48, 36),
    );
    report("duplicates", &[out]);
}

#[test]
fn slivers_and_zero_area_triangles() {
    let mut out = Vec::new();
    for e in 3..=9 {
        let aspect = 10f64.powi(e);
        let mut tris = vec![
            [
                DVec3::ZERO,
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(0.5, 1.0 / aspect, 0.0),
            ],
            [
                DVec3::new(0.3, -0.5, -0.2),
                DVec3::new(0.4, 0.5, -0.2),
                DVec3::new(0.35, 0.0, 0.6),
            ],
            [
                DVec3::new(-0.2, 0.3, 0.3),
                DVec3::new(1.2, 0.3, 0.3),
                DVec3::new(0.5, -0.4, -0.3),
            ],
        ];
        // Exactly zero area: a repeated corner and collinear corners.
        tris.push([DVec3::ONE, DVec3::ONE, DVec3::ZERO]);
        tris.push([DVec3::ZERO, DVec3::splat(0.5), DVec3::ONE]);
        let o = run(
            &format!("sliver 1e{e}"),
            &scenes::mesh(tris.clone()),
            Pixels::Coverage,
            4,
            (48, 36),
        );
        let tree = verify(&scenes::mesh(tris), &BuildOptions::default(), 1).unwrap();
        assert!(
            tree.stats.degenerate_dropped >= 2,
            "zero-area triangles are counted"
        );
        out.push(o);
    }
    report("slivers", &out);
}

#[test]
fn random_soups() {
    let out: Vec<Outcome> = (0..6)
        .map(|seed| {
            run(
                &format!("soup {seed}"),
                &scenes::soup(60, 0.5, seed),
                Pixels::Ids,
                4,
                (48, 36),
            )
        })
        .collect();
    report("soups", &out);
}

#[test]
#[ignore = "long run: cargo test --release --test stress -- --ignored"]
fn large_inputs() {
    let mut out = vec![
        run(
            "sphere 40x60",
            &scenes::sphere(40, 60),
            Pixels::Closed,
            20,
            (96, 72),
        ),
        run(
            "torus 60x30",
            &scenes::torus(60, 30),
            Pixels::Closed,
            20,
            (96, 72),
        ),
        run(
            "box grid 6",
            &scenes::box_grid(6),
            Pixels::Closed,
            20,
            (96, 72),
        ),
        run("book 5000", &book(5000), Pixels::Coverage, 4, (64, 48)),
        run("star 5000", &star(5000, 8), Pixels::Coverage, 4, (64, 48)),
    ];
    for seed in 0..20 {
        out.push(run(
            &format!("soup 300 {seed}"),
            &scenes::soup(300, 0.4, seed),
            Pixels::Ids,
            4,
            (64, 48),
        ));
    }
    if let Some(dir) = models() {
        for name in ["suzanne.obj", "teapot.obj", "stanford-bunny.obj"] {
            if let Ok(mesh) = load_obj(&dir.join(name)) {
                out.push(run(name, &mesh, Pixels::Ids, 10, (96, 72)));
            }
        }
    }
    report("large", &out);
}

// ---------------------------------------------------------------------------------------------
// Fuzz regressions: the bodies of the `fuzz/` targets, run on every input kept in
// `fuzz/regressions/<target>/` (crashes found by `cargo fuzz`, named after what they broke).

/// `compile_obj`: OBJ bytes -> load -> compile: never a panic; whatever is written is readable.
fn fuzz_compile_obj(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(mesh) =
        peel_compiler::load::load_obj_text(Path::new("/nonexistent-fuzz-dir/fuzz.obj"), text)
    else {
        return;
    };
    let options = CompileOptions {
        ids: true,
        ..CompileOptions::default()
    };
    if let Ok((_, bytes)) = compile_mesh(&mesh, &options, &|_| {}) {
        assert!(Scene::parse(&bytes).is_ok());
    }
}

/// A `W x H` image's span sink that panics on what a frame must never send: a span outside
/// the image or an empty one (overdraw is allowed: back to front paints over).
struct CheckedSpans<const W: u32, const H: u32>;

impl<const W: u32, const H: u32> peel_runtime::display::SpanSink for CheckedSpans<W, H> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, _: peel_runtime::display::Colour) {
        assert!(
            y < H && x_end <= W,
            "span y={y} x={x_start}..{x_end} outside {W}x{H}"
        );
        assert!(x_start < x_end, "empty span y={y} x={x_start}..{x_end}");
    }
}

/// `read_render`: arbitrary bytes -> reader -> render: never a panic.
fn fuzz_read_render(data: &[u8]) {
    use peel_runtime::camera::{Camera, Pose};
    use peel_runtime::render::{Paint, Renderer, Workspace};
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
}

/// Runs one kept input, by target; the named tests below call it once per file.
fn replay(target: &str, file: &str) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/regressions")
        .join(target)
        .join(file);
    let bytes =
        std::fs::read(&path).unwrap_or_else(|e| panic!("fuzz regression {}: {e}", path.display()));
    match target {
        "compile_obj" => fuzz_compile_obj(&bytes),
        "read_render" => fuzz_read_render(&bytes),
        _ => panic!("unknown fuzz target {target}"),
    }
}

/// One `#[test]` per kept input, so a regression fails under its own name; `FUZZ_REGRESSIONS`
/// lists them all, and `fuzz_regressions_all_named` fails when a file in
/// `fuzz/regressions/` has no test here (add a line) or a line names a missing file.
macro_rules! fuzz_regressions {
    ($($target:ident { $($test:ident => $file:literal,)* })*) => {
        $($(
            #[test]
            fn $test() {
                replay(stringify!($target), $file);
            }
        )*)*
        const FUZZ_REGRESSIONS: &[(&str, &str)] = &[$($((stringify!($target), $file),)*)*];
    };
}

fuzz_regressions! {
    compile_obj {
        fuzz_regressions_compile_obj_seed_collinear_and_repeated_corners =>
            "seed_collinear_and_repeated_corners.obj",
    }
    read_render {
        fuzz_regressions_read_render_seed_truncated_header => "seed_truncated_header.bin",
    }
}

#[test]
fn fuzz_regressions_all_named() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/regressions");
    let mut on_disk = Vec::new();
    for target in ["compile_obj", "read_render"] {
        let dir = root.join(target);
        let entries = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("fuzz regressions {}: {e}", dir.display()));
        for entry in entries {
            let name = entry.expect("readable directory entry").file_name();
            on_disk.push((target.to_string(), name.to_string_lossy().into_owned()));
        }
    }
    on_disk.sort();
    let mut named: Vec<(String, String)> = FUZZ_REGRESSIONS
        .iter()
        .map(|&(t, f)| (t.to_string(), f.to_string()))
        .collect();
    named.sort();
    let unnamed: Vec<_> = on_disk.iter().filter(|c| !named.contains(c)).collect();
    let missing: Vec<_> = named.iter().filter(|c| !on_disk.contains(c)).collect();
    assert!(
        unnamed.is_empty() && missing.is_empty(),
        "fuzz/regressions out of step with the fuzz_regressions! list in tests/stress.rs: \
         files without a test {unnamed:?}, tests without a file {missing:?}"
    );
}

/// The crack counter's control: the same closed meshes compiled with T-junctions left open do
/// show cracks from the same cameras (so the test above can fail), and closing them removes
/// every one.
#[test]
fn open_t_junctions_show_cracks() {
    let mut open_total = 0;
    for (name, mesh) in closed_meshes() {
        for watertight in [false, true] {
            let options = CompileOptions {
                build: BuildOptions {
                    watertight,
                    ..BuildOptions::default()
                },
                ids: true,
                ..CompileOptions::default()
            };
            let (_, bytes) = compile_mesh(&mesh, &options, &|_| {}).expect("compile");
            let polys = polygons(&bytes);
            let cracks: usize = cameras(&mesh, 100, (160, 120), 11)
                .iter()
                .map(|view| compare(&mesh, &bytes, &polys, view).cracks)
                .sum();
            println!("{name}: watertight {watertight}: {cracks} crack pixels");
            if watertight {
                assert_eq!(cracks, 0, "{name}");
            } else {
                open_total += cracks;
            }
        }
    }
    assert!(open_total > 0, "no crack with T-junctions left open");
}
