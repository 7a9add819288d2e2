//! Build tests: invariants on random soups and closed meshes, determinism, output shape.

use glam::DVec3;
use proptest::prelude::*;

use super::build::{build_exact, ExactTree};
use super::input::{prepare, Input};
use super::*;
use crate::load::{Mesh, SourceTriangle};

pub(crate) fn mesh_of(tris: Vec<[DVec3; 3]>) -> Mesh {
    Mesh {
        triangles: tris
            .into_iter()
            .map(|vertices| SourceTriangle {
                opacity: u8::MAX,
                vertices,
                colour: [1, 2, 3],
                normals: None,
                texture: None,
            })
            .collect(),
        ..Mesh::default()
    }
}

/// A closed, star-shaped, generally non-convex mesh: a UV sphere with per-vertex radii.
pub(crate) fn bumpy_sphere(rings: usize, segments: usize, radii: &[f64]) -> Mesh {
    let r = |i: usize| 1.0 + radii[i % radii.len()];
    let mut pts = vec![DVec3::new(0.0, 0.0, r(0))];
    for i in 1..rings {
        let th = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..segments {
            let ph = std::f64::consts::TAU * j as f64 / segments as f64;
            let k = pts.len();
            pts.push(DVec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()) * r(k));
        }
    }
    pts.push(DVec3::new(0.0, 0.0, -r(pts.len())));
    let south = pts.len() - 1;
    let at = |i: usize, j: usize| 1 + (i - 1) * segments + j % segments;
    let mut tris = Vec::new();
    for j in 0..segments {
        tris.push([pts[0], pts[at(1, j)], pts[at(1, j + 1)]]);
        tris.push([pts[south], pts[at(rings - 1, j + 1)], pts[at(rings - 1, j)]]);
        for i in 1..rings - 1 {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1));
            tris.push([pts[a], pts[c], pts[d]]);
            tris.push([pts[a], pts[d], pts[b]]);
        }
    }
    mesh_of(tris)
}

fn exact(mesh: &Mesh, options: &BuildOptions) -> (Input, ExactTree) {
    let input = prepare(mesh, options.shadows).unwrap();
    let tree = build_exact(&input, options, &|_| {}).unwrap();
    (input, tree)
}

/// A thread pool of `threads` workers (to compare outputs across thread counts).
fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

/// Build and check every invariant; also compile twice to bytes and compare them.
fn checked(mesh: &Mesh) -> (Input, ExactTree) {
    let (input, tree) = exact(mesh, &BuildOptions::default());
    if let Err(e) = super::check::all(&tree, &input) {
        panic!("{e}");
    }
    assert_eq!(
        encoded(mesh),
        encoded(mesh),
        "two compiles give different bytes"
    );
    (input, tree)
}

/// The `.peel` bytes of `mesh` with default options and ids.
fn encoded(mesh: &Mesh) -> Vec<u8> {
    let options = crate::compile::CompileOptions {
        ids: true,
        ..Default::default()
    };
    crate::compile::compile_mesh(mesh, &options, &|_| {})
        .unwrap()
        .1
}

fn same(a: &DisplayTree, b: &DisplayTree) -> bool {
    a.centre == b.centre
        && a.vertices == b.vertices
        && a.planes == b.planes
        && a.polygons == b.polygons
        && a.nodes == b.nodes
        && a.stats == b.stats
}

fn small_coord() -> impl Strategy<Value = f64> {
    // Few distinct values: many coplanar triangles, shared edges, vertices on planes.
    (-3i32..=3).prop_map(f64::from)
}

fn tri() -> impl Strategy<Value = [DVec3; 3]> {
    let p =
        || (small_coord(), small_coord(), small_coord()).prop_map(|(x, y, z)| DVec3::new(x, y, z));
    [p(), p(), p()]
}

fn float_tri() -> impl Strategy<Value = [DVec3; 3]> {
    let c = || -1e3..1e3f64;
    let p = move || (c(), c(), c()).prop_map(|(x, y, z)| DVec3::new(x, y, z));
    [p(), p(), p()]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn random_soups_on_a_coarse_grid(tris in proptest::collection::vec(tri(), 1..40)) {
        let mesh = mesh_of(tris);
        let (input, _) = checked(&mesh);
        let kept = input.fragments.len() as u64;
        prop_assert_eq!(kept + input.degenerate_dropped, mesh.triangles.len() as u64);
    }

    #[test]
    fn random_float_soups(tris in proptest::collection::vec(float_tri(), 1..30)) {
        checked(&mesh_of(tris));
    }

    #[test]
    fn random_closed_meshes(
        rings in 3usize..8,
        segments in 3usize..9,
        radii in proptest::collection::vec(-0.6..0.6f64, 1..20),
    ) {
        let mesh = bumpy_sphere(rings, segments, &radii);
        let (_, tree) = checked(&mesh);
        prop_assert!(!tree.nodes.is_empty());
    }
}

/// A cube whose faces are `n × n` grids of coplanar triangles, wound outwards.
fn tessellated_cube(n: usize) -> Mesh {
    let mut tris = Vec::new();
    for axis in 0..3 {
        for side in [-1.0, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let at = |i: usize, j: usize| {
                let mut p = DVec3::ZERO;
                p[axis] = side;
                p[u] = -1.0 + 2.0 * i as f64 / n as f64;
                p[v] = -1.0 + 2.0 * j as f64 / n as f64;
                p
            };
            for i in 0..n {
                for j in 0..n {
                    let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                    if side > 0.0 {
                        tris.push([a, b, c]);
                        tris.push([a, c, d]);
                    } else {
                        tris.push([a, c, b]);
                        tris.push([a, d, c]);
                    }
                }
            }
        }
    }
    mesh_of(tris)
}

#[test]
fn a_convex_mesh_is_one_convex_node() {
    let mesh = tessellated_cube(4);
    let (_, tree) = checked(&mesh);
    assert_eq!(tree.nodes.len(), 1);
    assert_eq!(tree.polygons.len(), mesh.triangles.len());
    // A consistently wound closed surface: the interior is on the same side of every source
    // normal, so `interior_front` follows `flipped` one way for every polygon.
    let same = tree
        .polygons
        .iter()
        .filter(|p| p.interior_front == p.frag.flipped)
        .count();
    assert!(
        same == 0 || same == tree.polygons.len(),
        "{same} of {}",
        tree.polygons.len()
    );
}

#[test]
fn nested_cubes_are_two_convex_nodes() {
    let outer = tessellated_cube(2);
    let inner = outer.triangles.iter().map(|t| t.vertices.map(|p| p * 0.5));
    let mesh = mesh_of(
        outer
            .triangles
            .iter()
            .map(|t| t.vertices)
            .chain(inner)
            .collect(),
    );
    let (_, tree) = checked(&mesh);
    assert_eq!(tree.nodes.len(), 2);
    assert_eq!(tree.cuts, 0);
}

#[test]
fn a_staircase_needs_no_split() {
    // Complexity zero: a staircase of n steps needs no split, only n convex nodes.
    let mut tris = Vec::new();
    for s in 0..4 {
        let (y, z) = (s as f64, s as f64);
        let step = [
            DVec3::new(0.0, y, z + 1.0),
            DVec3::new(1.0, y, z + 1.0),
            DVec3::new(1.0, y + 1.0, z + 1.0),
            DVec3::new(0.0, y + 1.0, z + 1.0),
        ];
        tris.push([step[0], step[1], step[2]]);
        tris.push([step[0], step[2], step[3]]);
        let riser = [
            DVec3::new(0.0, y, z),
            DVec3::new(1.0, y, z),
            DVec3::new(1.0, y, z + 1.0),
            DVec3::new(0.0, y, z + 1.0),
        ];
        tris.push([riser[0], riser[1], riser[2]]);
        tris.push([riser[0], riser[2], riser[3]]);
    }
    let (_, tree) = checked(&mesh_of(tris));
    assert!(tree
        .nodes
        .iter()
        .all(|n| matches!(n, super::build::ExactNode::Convex { .. })));
    assert_eq!(tree.cuts, 0);
}

/// A torus's rings of edges lie in planes no triangle crosses: the build splits along them
/// (free splits, no support planes) and cuts nothing, keeping every invariant.
#[test]
fn a_torus_is_split_along_its_rings_without_a_cut() {
    let (_, tree) = checked(&crate::tools::scenes::torus(24, 12));
    let free = (tree.nodes.iter())
        .filter(|n| {
            matches!(
                n,
                super::build::ExactNode::Split {
                    plane: super::build::SplitPlane::Free(_),
                    ..
                }
            )
        })
        .count();
    assert!(free > 0, "no free split");
    assert_eq!(tree.cuts, 0);
}

/// A torus turned off its axis has no ring left in one plane, and its support planes cut it
/// wherever its surface comes back: the build splits it by its edges' planes instead (which
/// may cut, and are no support planes), keeping every invariant.
#[test]
fn a_turned_torus_is_split_by_edge_planes() {
    let (_, tree) = checked(&turned(&crate::tools::scenes::torus(24, 12)));
    let edge = (tree.nodes.iter())
        .filter(|n| {
            matches!(
                n,
                super::build::ExactNode::Split {
                    plane: super::build::SplitPlane::Edge(_),
                    ..
                }
            )
        })
        .count();
    assert!(edge > 0, "no edge split");
}

#[test]
fn crossing_triangles_are_cut_exactly() {
    let (input, tree) = checked(&mesh_of(crate::tools::scenes::piercing_triangles()));
    assert!(tree.cuts > 0);
    assert!(super::check::area_partition(&tree, &input, 400, 3).unwrap() > 1000);
}

#[test]
fn degenerate_triangles_are_dropped_and_counted() {
    let tris = vec![
        [DVec3::ZERO, DVec3::X, DVec3::Y],
        [DVec3::ZERO, DVec3::X, DVec3::X * 2.0],
        [DVec3::ZERO, DVec3::ZERO, DVec3::Y],
        // Zero area only after quantisation: the third corner is far below one grid step.
        [DVec3::ZERO, DVec3::X, DVec3::new(0.5, 1e-12, 0.0)],
    ];
    let tree = build(&mesh_of(tris), &BuildOptions::default(), &|_| {}).unwrap();
    assert_eq!(tree.stats.degenerate_dropped, 3);
    assert_eq!(tree.stats.input_triangles, 4);
    assert_eq!(tree.stats.output_polygons, 1);
}

#[test]
fn empty_mesh_gives_an_empty_tree() {
    let tree = build(&Mesh::default(), &BuildOptions::default(), &|_| {}).unwrap();
    assert!(tree.nodes.is_empty() && tree.polygons.is_empty());
}

#[test]
fn building_twice_and_on_any_thread_count_gives_identical_output() {
    // Large enough for the parallel paths (sampled costs, parallel hull, joined subtrees).
    let radii: Vec<f64> = (0..97)
        .map(|i| ((i * 37 % 97) as f64 / 97.0 - 0.5) * 0.5)
        .collect();
    let mesh = bumpy_sphere(60, 80, &radii);
    let options = BuildOptions::default();
    let run = |threads: usize| pool(threads).install(|| build(&mesh, &options, &|_| {}).unwrap());
    let joins = super::build::JOINS.load(std::sync::atomic::Ordering::Relaxed);
    let a = run(1);
    let b = run(2);
    let c = run(3);
    assert!(same(&a, &b) && same(&a, &c));
    assert!(
        super::build::JOINS.load(std::sync::atomic::Ordering::Relaxed) > joins,
        "the mesh is too small to build subtrees in parallel"
    );
    // The file too, byte for byte.
    let bytes = |threads: usize| pool(threads).install(|| encoded(&mesh));
    assert_eq!(bytes(1), bytes(2));
    assert!(a.stats.split_nodes > 0);
    let (input, tree) = exact(&mesh, &options);
    super::check::structure(&tree).unwrap();
    super::check::support_planes(&tree, &input.table).unwrap();
    super::check::ancestor_sides(&tree, &input).unwrap();
    super::check::fragments(&tree, &input).unwrap();
    super::check::area_partition(&tree, &input, 2, 1).unwrap();
}

/// A mesh turned about an axis that no grid plane holds, so that no loop of its edges stays
/// in one plane once quantised (no free split along it).
pub(crate) fn turned(mesh: &Mesh) -> Mesh {
    let r = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.3, 0.7, 1.1);
    mesh_of(
        (mesh.triangles.iter())
            .map(|t| t.vertices.map(|p| r * p))
            .collect(),
    )
}

/// A UV sphere is convex, but once quantised many of its quads fold very slightly inward, and
/// each fold is split off alone (turned, its rings are no longer planes that divide it without
/// a cut): a chain as deep as there are folds. The build takes most of those splits in
/// batches (once a few come in a row), and the tree keeps every invariant, cuts next to
/// nothing, and is the same on any thread count.
#[test]
fn a_nearly_convex_sphere_is_split_off_fold_by_fold_in_batches() {
    let mesh = turned(&crate::tools::scenes::sphere(32, 64));
    let chained = super::build::CHAINED.load(std::sync::atomic::Ordering::Relaxed);
    let (_, tree) = checked(&mesh);
    let batched = super::build::CHAINED.load(std::sync::atomic::Ordering::Relaxed) - chained;
    let splits = tree
        .nodes
        .iter()
        .filter(|n| matches!(n, super::build::ExactNode::Split { .. }))
        .count() as u64;
    assert!(splits > 500, "only {splits} splits: the folds are gone");
    assert!(
        batched * 2 > splits,
        "{batched} of {splits} splits came from batches"
    );
    // Batches take only free splits; the few splits chosen alone between them may cut.
    assert!(tree.cuts < 10, "{} cuts", tree.cuts);
    let bytes = |threads: usize| pool(threads).install(|| encoded(&mesh));
    assert_eq!(bytes(1), bytes(2));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(6))]
    /// Spheres of other sizes, turned and moved (so other quads fold once quantised; turned
    /// off their axis first, so no ring stays a plane that splits them without a cut): the
    /// batched chains keep every invariant.
    #[test]
    fn nearly_convex_spheres_keep_every_invariant(
        rings in 24usize..34,
        segments in 40usize..64,
        turn in 0.0..std::f64::consts::PI,
        offset in -1e3..1e3f64,
    ) {
        let mut mesh = turned(&crate::tools::scenes::sphere(rings, segments));
        let (sin, cos) = turn.sin_cos();
        for t in &mut mesh.triangles {
            for p in &mut t.vertices {
                *p = DVec3::new(cos * p.x - sin * p.z, p.y, sin * p.x + cos * p.z) + offset;
            }
        }
        let chained = super::build::CHAINED.load(std::sync::atomic::Ordering::Relaxed);
        checked(&mesh);
        prop_assert!(super::build::CHAINED.load(std::sync::atomic::Ordering::Relaxed) > chained);
    }
}

#[test]
fn output_is_consistent_and_relative_to_the_centre() {
    let offset = DVec3::new(1e6, -2e6, 3e5);
    let base = bumpy_sphere(10, 14, &[0.3, -0.2, 0.1, 0.25, -0.4]);
    let mesh = mesh_of(
        base.triangles
            .iter()
            .map(|t| t.vertices.map(|p| p * 1e-3 + offset))
            .collect(),
    );
    let options = BuildOptions {
        max_polygon_vertices: 3,
        ..BuildOptions::default()
    };
    let tree = build(&mesh, &options, &|_| {}).unwrap();
    let q = quantisation(&mesh);
    assert_eq!(tree.centre, q.offset);
    assert!((tree.centre - offset).length() < 1e-2);
    let s = tree.stats;
    assert_eq!(s.output_polygons as usize, tree.polygons.len());
    assert_eq!((s.convex_nodes + s.split_nodes) as usize, tree.nodes.len());
    assert_eq!(s.planes as usize, tree.planes.len());
    assert!(s.max_depth >= 1 && s.max_depth as usize <= tree.nodes.len());
    for p in &tree.planes {
        assert!((p.normal.length() - 1.0).abs() < 1e-12);
    }
    for v in &tree.vertices {
        assert!(v.length() < 2e-3, "vertex {v} not relative to the centre");
    }
    for poly in &tree.polygons {
        assert_eq!(poly.vertices.len(), 3, "max_polygon_vertices = 3");
        let plane = tree.planes[poly.plane as usize];
        for &v in &poly.vertices {
            let d = plane.normal.dot(tree.vertices[v as usize]) - plane.offset;
            assert!(d.abs() < 1e-9, "vertex off its polygon's plane by {d}");
        }
        // The winding follows the source triangle: its normal agrees with the source's.
        let src = mesh.triangles[poly.source as usize].vertices;
        let sn = (src[1] - src[0]).cross(src[2] - src[0]);
        let [a, b, c] = [0, 1, 2].map(|i| tree.vertices[poly.vertices[i] as usize]);
        let pn = (b - a).cross(c - a);
        assert!(pn.dot(sn) > 0.0, "winding lost");
        assert_eq!(poly.flipped, plane.normal.dot(sn) < 0.0);
    }
    for (i, n) in tree.nodes.iter().enumerate() {
        let kids = match *n {
            TreeNode::Convex {
                child,
                polygon_count,
                ..
            } => {
                assert!(polygon_count >= 1);
                vec![child]
            }
            TreeNode::Split { front, back, .. } => vec![front, back],
        };
        assert!(kids.into_iter().flatten().all(|c| c as usize > i));
    }
}

/// A minimal OBJ reader for the shared models (`v` and polygon `f` lines only).
fn read_obj(path: &std::path::Path) -> Option<Mesh> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut v = Vec::new();
    let mut tris = Vec::new();
    for line in text.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f64> = it.take(3).map(|x| x.parse().unwrap()).collect();
                v.push(DVec3::new(c[0], c[1], c[2]));
            }
            Some("f") => {
                let idx: Vec<usize> = it
                    .map(|t| {
                        let i: i64 = t.split('/').next().unwrap().parse().unwrap();
                        if i < 0 {
                            (v.len() as i64 + i) as usize
                        } else {
                            i as usize - 1
                        }
                    })
                    .collect();
                for k in 1..idx.len() - 1 {
                    tris.push([v[idx[0]], v[idx[k]], v[idx[k + 1]]]);
                }
            }
            _ => {}
        }
    }
    Some(mesh_of(tris))
}

/// Ratio and time on the shared models (run with `--ignored --nocapture`, release).
#[test]
#[ignore]
fn shared_models_speed_and_ratio() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/models");
    for name in ["cow", "teapot", "suzanne", "stanford-bunny"] {
        let path = root.join(format!("{name}.obj"));
        let Some(mesh) = read_obj(&path) else {
            println!("skipped: {} not found", path.display());
            continue;
        };
        let options = BuildOptions::default();
        let t = std::time::Instant::now();
        let tree = build(&mesh, &options, &|_| {}).unwrap();
        let s = tree.stats;
        println!(
            "{name}: {} tris -> {} polys (ratio {:.3}), {} cuts, {} convex + {} split nodes, depth {}, {:.3} s",
            s.input_triangles,
            s.output_polygons,
            s.output_polygons as f64 / s.input_triangles as f64,
            s.cuts,
            s.convex_nodes,
            s.split_nodes,
            s.max_depth,
            t.elapsed().as_secs_f64()
        );
    }
}

/// With shadows (a bumpy sphere shadows itself) the file is the same on any thread count,
/// and the tree keeps every invariant.
#[test]
fn shadows_give_identical_output_on_any_thread_count_and_keep_every_invariant() {
    let radii: Vec<f64> = (0..31)
        .map(|i| ((i * 13 % 31) as f64 / 31.0 - 0.5) * 0.6)
        .collect();
    let mesh = bumpy_sphere(20, 30, &radii);
    let options = crate::compile::CompileOptions {
        ids: true,
        build: BuildOptions {
            shadows: Some(crate::shadow::Light::Sun(glam::DVec3::new(0.3, 0.9, -0.4))),
            ..BuildOptions::default()
        },
        ..Default::default()
    };
    let compile = |threads: usize| {
        pool(threads).install(|| crate::compile::compile_mesh(&mesh, &options, &|_| {}).unwrap())
    };
    let (a, bytes) = compile(1);
    assert_eq!(bytes, compile(3).1);
    assert!(a.polygons.iter().any(|p| p.shadowed), "no shadow");
    let (input, tree) = exact(&mesh, &options.build);
    assert!(
        input.build_fragments().len() > input.fragments.len(),
        "no cut"
    );
    super::check::structure(&tree).unwrap();
    super::check::support_planes(&tree, &input.table).unwrap();
    super::check::ancestor_sides(&tree, &input).unwrap();
    super::check::fragments(&tree, &input).unwrap();
    super::check::convex_sets(&tree, &input).unwrap();
    super::check::area_partition(&tree, &input, 2, 1).unwrap();
}
