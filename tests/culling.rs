//! Culling and the vertex memory never change a frame. Dense generated scenes drawn so small
//! that most polygons cover no pixel centre, where subtree culling (outside the frustum, no
//! pixel centre near the subtree's screen box, or every such pixel already covered) does the
//! most: the image with culling equals the image without, pixel for pixel, and culling did skip
//! subtrees; the image drawn with projected vertices kept from frame to frame (one memory for
//! every camera of a scene) equals the image drawn without. And random scenes of closed solids
//! (convex and not, interpenetrating, with loose triangles inside) seen from inside a solid,
//! through a near plane that cuts one open, and from outside: culling is pixel-neutral for
//! every camera, in both orders and at every precision.

use glam::{DMat3, DVec3};
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::Mesh;
use peel_compiler::tools::raster::{HOST_SPANS_PER_ROW, HOST_STACK, HOST_VERTS};
use peel_compiler::tools::scenes;
use peel_compiler::tools::shot::Shot as ViewShot;
use peel_e2e::{bounds, closed_outward, closed_sphere, mesh_closed_outward, polygons, reference};
use peel_runtime::camera::{Camera, Pose};
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Framebuffer, Xrgb8888};
use peel_runtime::read::Scene;
use peel_runtime::render::{Renderer, Workspace};
use peel_runtime::traverse::Order;
use peel_runtime::vertices::{CachedVertex, VertexCache};
use proptest::prelude::*;
use proptest::test_runner::{TestCaseError, TestRunner};
use std::cell::Cell;

/// The id image of one frame drawn by `renderer` (made for the camera's image size), and the
/// subtrees culled.
fn draw<const SUB: u32>(
    renderer: &mut Renderer<'_, SUB>,
    scene: &Scene<'_>,
    camera: &Camera,
) -> (Vec<u32>, u64) {
    let (w, h) = (camera.width(), camera.height());
    let mut ids = vec![0u32; (w * h) as usize];
    let mut fb = Framebuffer::<Xrgb8888>::new(&mut ids, w, h).expect("framebuffer");
    let stats = renderer
        .draw(scene, &camera.view(scene.header().centre), &mut fb)
        .expect("render");
    (ids, stats.nodes_culled_covered + stats.nodes_culled_frustum)
}

/// How much of the culling a frame does.
#[derive(Clone, Copy, PartialEq)]
enum Culling {
    /// All of it (the default).
    All,
    /// All but the subtree box tests (`Renderer::without_subtree_culling`).
    NoSubtrees,
    /// None (`Renderer::without_culling`).
    Off,
}

/// The id image of one front-to-back frame at `SUB` fractional bits, with integer vertices or
/// not, and the subtrees culled.
fn frame<const SUB: u32>(
    scene: &Scene<'_>,
    camera: &Camera,
    culling: Culling,
    integer: bool,
) -> (Vec<u32>, u64) {
    let h = camera.height();
    let mut intervals = vec![(0u16, 0u16); HOST_SPANS_PER_ROW * h as usize];
    let mut counts = vec![0u16; h as usize];
    let coverage = Coverage::new(&mut intervals, &mut counts, camera.width(), h).expect("spans");
    let mut workspace: Box<Workspace<HOST_STACK, HOST_VERTS, SUB>> = Box::default();
    let mut renderer = Renderer::<SUB>::with_precision(&mut workspace)
        .span_memory(coverage)
        .ids();
    renderer = match culling {
        Culling::All => renderer,
        Culling::NoSubtrees => renderer.without_subtree_culling(),
        Culling::Off => renderer.without_culling(),
    };
    if integer {
        renderer = renderer.integer_vertices();
    }
    draw(&mut renderer, scene, camera)
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
    let mut memory = vec![CachedVertex::EMPTY; (h.vertex_count as usize).next_power_of_two()];
    let mut integer_memory = memory.clone();
    // Direct-mapped memory far smaller than the scene: vertices keep replacing each other.
    let mut small_memory = [CachedVertex::EMPTY; 16];
    for (k, (w, ht)) in [(24, 18), (64, 48), (160, 120), (1920, 1080)]
        .into_iter()
        .enumerate()
    {
        // One renderer with vertex memory for every camera of this size, as firmware keeps it.
        let mut intervals = vec![(0u16, 0u16); HOST_SPANS_PER_ROW * ht as usize];
        let mut counts = vec![0u16; ht as usize];
        let coverage = Coverage::new(&mut intervals, &mut counts, w, ht).expect("spans");
        let mut workspace: Box<Workspace<HOST_STACK, HOST_VERTS, SUB>> = Box::default();
        let mut cached = Renderer::<SUB>::with_precision(&mut workspace)
            .span_memory(coverage)
            .vertex_memory(VertexCache::new(&mut memory))
            .ids();
        let mut integer_intervals = vec![(0u16, 0u16); HOST_SPANS_PER_ROW * ht as usize];
        let mut integer_counts = vec![0u16; ht as usize];
        let integer_coverage =
            Coverage::new(&mut integer_intervals, &mut integer_counts, w, ht).expect("spans");
        let mut integer_workspace: Box<Workspace<HOST_STACK, HOST_VERTS, SUB>> = Box::default();
        let mut cached_integer = Renderer::<SUB>::with_precision(&mut integer_workspace)
            .span_memory(integer_coverage)
            .vertex_memory(VertexCache::new(&mut integer_memory))
            .integer_vertices()
            .ids();
        let mut small_intervals = vec![(0u16, 0u16); HOST_SPANS_PER_ROW * ht as usize];
        let mut small_counts = vec![0u16; ht as usize];
        let small_coverage =
            Coverage::new(&mut small_intervals, &mut small_counts, w, ht).expect("spans");
        let mut small_workspace: Box<Workspace<HOST_STACK, HOST_VERTS, SUB>> = Box::default();
        let mut small = Renderer::<SUB>::with_precision(&mut small_workspace)
            .span_memory(small_coverage)
            .vertex_memory(VertexCache::new(&mut small_memory))
            .ids();
        for step in 0..6 {
            let a = 0.4 + step as f64 * 1.1 + k as f64 * 0.3;
            let dist = if step % 2 == 0 { 2.2 } else { 1.3 };
            let eye = c + DVec3::new(a.cos() * dist * r, 0.4 * r, a.sin() * dist * r);
            // Slightly off centre, so the scene's box is cut by the frame's edge in some views.
            let target = c + DVec3::new(0.3 * r * (step as f64 - 2.5) / 2.5, 0.0, 0.0);
            let near = Camera::default_near(h.bounds_min, h.bounds_max);
            let camera = Camera::look_at(Pose::new(eye, target), 60.0, w, ht, near).expect("cam");
            let (with, n) = frame::<SUB>(&scene, &camera, Culling::All, false);
            let (integer, _) = frame::<SUB>(&scene, &camera, Culling::All, true);
            for (with, integer) in [(&with, false), (&integer, true)] {
                let (without, _) = frame::<SUB>(&scene, &camera, Culling::Off, integer);
                let (no_subtrees, none) =
                    frame::<SUB>(&scene, &camera, Culling::NoSubtrees, integer);
                assert_eq!(none, 0, "{name}: subtrees culled without subtree culling");
                // Without culling no frame skips clipping, so none takes integer vertices.
                let others = [
                    (&no_subtrees, "without subtree culling"),
                    (&without, "without culling"),
                ];
                for (other, what) in others.into_iter().take(if integer { 1 } else { 2 }) {
                    let differ = with.iter().zip(other).filter(|(a, b)| a != b).count();
                    assert_eq!(
                        differ, 0,
                        "{name}, SUB = {SUB}, {w}x{ht}, camera {step}, integer vertices {integer}: \
                         {differ} pixels change {what}"
                    );
                }
            }
            let (cached, _) = draw(&mut cached, &scene, &camera);
            let (small, _) = draw(&mut small, &scene, &camera);
            let (cached_integer, _) = draw(&mut cached_integer, &scene, &camera);
            for (images, reference, what) in [
                (&cached, &with, "the vertex memory"),
                (&small, &with, "a small vertex memory"),
                (
                    &cached_integer,
                    &integer,
                    "the vertex memory and integer vertices",
                ),
            ] {
                let stale = reference.iter().zip(images).filter(|(a, b)| a != b).count();
                assert_eq!(
                    stale, 0,
                    "{name}, SUB = {SUB}, {w}x{ht}, camera {step}: {stale} pixels change with {what}"
                );
            }
            culled += n;
        }
    }
    culled
}

/// At every precision (the soups are open meshes).
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

/// Closed meshes (the eyes are all outside), at every precision: at 0 and 4 fractional bits
/// too, where snapping can turn a sliver of a tiny front face over at a silhouette (a pixel
/// centre in the gap shows the back face behind it), culling must not change a pixel.
#[test]
fn culling_keeps_dense_closed_meshes_pixel_exact() {
    for (name, mesh) in [
        ("sphere 24x48", closed_sphere(24, 48)),
        ("torus 24x24", scenes::torus(24, 24)),
    ] {
        assert!(mesh_closed_outward(&mesh), "{name} is not closed");
        let culled = [
            same_with_and_without::<0>(name, &mesh),
            same_with_and_without::<4>(name, &mesh),
            same_with_and_without::<{ peel_runtime::fill::SUBPIXEL_BITS }>(name, &mesh),
        ];
        assert!(
            culled.iter().all(|&n| n > 0),
            "{name}: culling skipped no subtree at some precision: {culled:?}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Culling is pixel-neutral for every camera: inside closed meshes, with the near plane cutting
// them open, and outside them, in both orders and at every precision.
// ---------------------------------------------------------------------------------------------

/// The id image of one frame in `order` at `SUB` fractional bits (front to back with span
/// memory sized as in [`frame`], back to front without), and the polygons the walk yielded.
fn ids_image<const SUB: u32>(
    scene: &Scene<'_>,
    camera: &Camera,
    order: Order,
    cull: bool,
) -> (Vec<u32>, u64) {
    let (w, h) = (camera.width(), camera.height());
    let mut ids = vec![0u32; (w * h) as usize];
    let mut fb = Framebuffer::<Xrgb8888>::new(&mut ids, w, h).expect("framebuffer");
    let mut intervals = vec![(0u16, 0u16); HOST_SPANS_PER_ROW * h as usize];
    let mut counts = vec![0u16; h as usize];
    let coverage = Coverage::new(&mut intervals, &mut counts, w, h).expect("coverage");
    let mut workspace: Box<Workspace<HOST_STACK, HOST_VERTS, SUB>> = Box::default();
    let mut renderer = Renderer::<SUB>::with_precision(&mut workspace).ids();
    if order == Order::FrontToBack {
        renderer = renderer.span_memory(coverage);
    }
    if !cull {
        renderer = renderer.without_culling();
    }
    let stats = renderer
        .draw(scene, &camera.view(scene.header().centre), &mut fb)
        .expect("render");
    (ids, stats.polygons_visited)
}

/// [`ids_image`] at `sub` fractional bits (0, 4 or 8), and the polygons the walk yielded.
fn ids_image_at(
    sub: u32,
    scene: &Scene<'_>,
    camera: &Camera,
    order: Order,
    cull: bool,
) -> (Vec<u32>, u64) {
    match sub {
        0 => ids_image::<0>(scene, camera, order, cull),
        4 => ids_image::<4>(scene, camera, order, cull),
        8 => ids_image::<8>(scene, camera, order, cull),
        _ => unreachable!("untested precision {sub}"),
    }
}

/// A closed solid, counter-clockwise seen from outside, with an exact vertex for every corner
/// it shares (each corner is computed once, so its copies weld bit for bit).
#[derive(Debug, Clone)]
enum Solid {
    /// An axis-aligned box (convex).
    Box { centre: [f64; 3], half: [f64; 3] },
    /// A closed UV sphere (`scenes::sphere(rings, segments)`, its pole welded) scaled per axis
    /// and moved (convex).
    Ellipsoid {
        centre: [f64; 3],
        radii: [f64; 3],
        rings: usize,
        segments: usize,
    },
    /// An octahedron subdivided once, each of its 18 vertices pushed radially by its factor:
    /// star-shaped around its centre (convex or not).
    Gem {
        centre: [f64; 3],
        radius: f64,
        bumps: Vec<f64>,
    },
    /// `scenes::torus(n, m)` scaled, its axis turned to x, y or z, and moved (non-convex).
    Torus {
        centre: [f64; 3],
        scale: f64,
        n: usize,
        m: usize,
        axis: usize,
    },
    /// An L-shaped prism (outline `(0,0) (a,0) (a,b) (c,b) (c,d) (0,d)`, height `h`), turned by
    /// `yaw` and `pitch` and moved (non-convex).
    Ell {
        centre: [f64; 3],
        a: f64,
        b: f64,
        c: f64,
        d: f64,
        h: f64,
        yaw: f64,
        pitch: f64,
    },
}

/// Add the quad `a b c d` (counter-clockwise seen from outside) as two triangles.
fn quad(out: &mut Vec<[DVec3; 3]>, a: DVec3, b: DVec3, c: DVec3, d: DVec3) {
    out.push([a, b, c]);
    out.push([a, c, d]);
}

impl Solid {
    /// The solid's triangles.
    fn triangles(&self) -> Vec<[DVec3; 3]> {
        match self {
            Solid::Box { centre, half } => {
                let (c, e) = (DVec3::from_array(*centre), DVec3::from_array(*half));
                let mut t = Vec::new();
                scenes::boxed(&mut t, c - e, c + e);
                t
            }
            Solid::Ellipsoid {
                centre,
                radii,
                rings,
                segments,
            } => {
                let (c, r) = (DVec3::from_array(*centre), DVec3::from_array(*radii));
                closed_sphere(*rings, *segments)
                    .triangles
                    .iter()
                    .map(|t| t.vertices.map(|v| c + v * r))
                    .collect()
            }
            Solid::Gem {
                centre,
                radius,
                bumps,
            } => {
                let c = DVec3::from_array(*centre);
                let (mut dirs, faces) = subdivided_octahedron();
                for (d, bump) in dirs.iter_mut().zip(bumps) {
                    *d = c + *d * (radius * bump);
                }
                faces.iter().map(|f| f.map(|i| dirs[i])).collect()
            }
            Solid::Torus {
                centre,
                scale,
                n,
                m,
                axis,
            } => {
                let c = DVec3::from_array(*centre);
                scenes::torus(*n, *m)
                    .triangles
                    .iter()
                    .map(|t| t.vertices.map(|v| c + turn(v, *axis) * *scale))
                    .collect()
            }
            Solid::Ell { .. } => {
                let v = |x: f64, y: f64, z: f64| self.ell_point(DVec3::new(x, y, z));
                let (a, b, c, d, h) = self.ell_sizes();
                let outline = [(0.0, 0.0), (a, 0.0), (a, b), (c, b), (c, d), (0.0, d)];
                let low: Vec<DVec3> = outline.iter().map(|&(x, y)| v(x, y, 0.0)).collect();
                let high: Vec<DVec3> = outline.iter().map(|&(x, y)| v(x, y, h)).collect();
                let mut t = Vec::new();
                // The caps: fans from the reflex corner 3 (the outline is star-shaped from it),
                // counter-clockwise seen from +z on top, reversed below.
                for k in [4, 5, 0, 1] {
                    let next = (k + 1) % 6;
                    t.push([high[3], high[k], high[next]]);
                    t.push([low[3], low[next], low[k]]);
                }
                for k in 0..6 {
                    let next = (k + 1) % 6;
                    quad(&mut t, low[k], low[next], high[next], high[k]);
                }
                t
            }
        }
    }

    /// The L prism's outline and height.
    fn ell_sizes(&self) -> (f64, f64, f64, f64, f64) {
        match *self {
            Solid::Ell { a, b, c, d, h, .. } => (a, b, c, d, h),
            _ => unreachable!(),
        }
    }

    /// A point of the L prism's own frame placed in the world.
    fn ell_point(&self, p: DVec3) -> DVec3 {
        let Solid::Ell {
            centre,
            a,
            d,
            h,
            yaw,
            pitch,
            ..
        } = *self
        else {
            unreachable!()
        };
        let q = p - DVec3::new(a, d, h) / 2.0;
        let r = DMat3::from_rotation_y(yaw) * DMat3::from_rotation_x(pitch);
        DVec3::from_array(centre) + r * q
    }

    /// A point well inside the solid, and the radius of a ball around it inside the solid.
    /// `t` in `[0, 1)` picks where along the torus's tube.
    fn interior(&self, t: f64) -> (DVec3, f64) {
        match self {
            Solid::Box { centre, half } => (
                DVec3::from_array(*centre),
                half.iter().copied().fold(f64::INFINITY, f64::min),
            ),
            // The coarsest sphere (3 rings, 4 segments) holds the ball of half its radius.
            Solid::Ellipsoid { centre, radii, .. } => (
                DVec3::from_array(*centre),
                0.5 * radii.iter().copied().fold(f64::INFINITY, f64::min),
            ),
            Solid::Gem {
                centre,
                radius,
                bumps,
            } => (
                DVec3::from_array(*centre),
                0.45 * radius * bumps.iter().copied().fold(f64::INFINITY, f64::min),
            ),
            // The centre of the tube's cross-section at one ring of vertices (the polygon there
            // holds the disc of radius 0.35 cos(pi / m) >= 0.24).
            Solid::Torus {
                centre,
                scale,
                n,
                axis,
                ..
            } => {
                let i = ((t * *n as f64) as usize).min(n - 1);
                let u = 2.0 * std::f64::consts::PI * i as f64 / *n as f64;
                let p = DVec3::new(u.cos(), 0.0, u.sin());
                (
                    DVec3::from_array(*centre) + turn(p, *axis) * *scale,
                    0.24 * scale,
                )
            }
            Solid::Ell { .. } => {
                let (_, b, c, _, h) = self.ell_sizes();
                (
                    self.ell_point(DVec3::new(c, b, h) / 2.0),
                    0.5 * b.min(c).min(h),
                )
            }
        }
    }
}

/// `p` with the torus's axis (y) turned to x (`axis` 0), kept (1) or turned to z (2): cyclic
/// permutations of the coordinates, which keep the orientation.
fn turn(p: DVec3, axis: usize) -> DVec3 {
    match axis {
        0 => DVec3::new(p.y, p.z, p.x),
        1 => p,
        _ => DVec3::new(p.z, p.x, p.y),
    }
}

/// The unit directions of an octahedron subdivided once (18) and its 32 outward triangles.
fn subdivided_octahedron() -> (Vec<DVec3>, Vec<[usize; 3]>) {
    let mut dirs = vec![
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];
    let mut middle = std::collections::BTreeMap::new();
    let mut mid = |a: usize, b: usize, dirs: &mut Vec<DVec3>| {
        *middle.entry((a.min(b), a.max(b))).or_insert_with(|| {
            dirs.push((dirs[a] + dirs[b]).normalize());
            dirs.len() - 1
        })
    };
    let mut faces = Vec::new();
    for (x, y, z) in [
        (0, 2, 4),
        (1, 2, 4),
        (0, 3, 4),
        (1, 3, 4),
        (0, 2, 5),
        (1, 2, 5),
        (0, 3, 5),
        (1, 3, 5),
    ] {
        // (x, y, z) is counter-clockwise seen from outside when an even number of its axes
        // are negative.
        let [a, b, c] = if (x + y + z) % 2 == 0 {
            [x, y, z]
        } else {
            [x, z, y]
        };
        let (ab, bc, ca) = (
            mid(a, b, &mut dirs),
            mid(b, c, &mut dirs),
            mid(c, a, &mut dirs),
        );
        faces.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    (dirs, faces)
}

/// A generated scene: one to three closed solids placed close together (they often
/// interpenetrate), and maybe a few loose (open, two-sided) triangles inside the first one.
#[derive(Debug, Clone)]
struct Solids {
    solids: Vec<Solid>,
    /// Loose triangles inside solid 0, their corners as offsets from its interior point in
    /// units of its interior ball's radius.
    loose: Vec<[[f64; 3]; 3]>,
}

impl Solids {
    /// The mesh and, per source triangle, whether it belongs to a closed solid.
    fn mesh(&self) -> (Mesh, Vec<bool>) {
        let mut tris = Vec::new();
        for s in &self.solids {
            tris.extend(s.triangles());
        }
        let closed = tris.len();
        let (p, r) = self.solids[0].interior(0.0);
        for t in &self.loose {
            tris.push(t.map(|o| p + DVec3::from_array(o) * r));
        }
        let solid = (0..tris.len()).map(|i| i < closed).collect();
        (scenes::mesh(tris), solid)
    }
}

fn point(lo: f64, hi: f64) -> impl Strategy<Value = [f64; 3]> + Clone {
    [lo..hi, lo..hi, lo..hi]
}

fn solid() -> impl Strategy<Value = Solid> {
    let place = point(-0.7, 0.7);
    prop_oneof![
        (place.clone(), point(0.25, 0.9)).prop_map(|(centre, half)| Solid::Box { centre, half }),
        (place.clone(), point(0.4, 1.0), 3usize..8, 4usize..13).prop_map(
            |(centre, radii, rings, segments)| Solid::Ellipsoid {
                centre,
                radii,
                rings,
                segments
            }
        ),
        (
            place.clone(),
            0.5..1.0f64,
            proptest::collection::vec(0.8..1.25f64, 18)
        )
            .prop_map(|(centre, radius, bumps)| Solid::Gem {
                centre,
                radius,
                bumps
            }),
        (place.clone(), 0.6..1.0f64, 6usize..13, 4usize..9, 0usize..3).prop_map(
            |(centre, scale, n, m, axis)| Solid::Torus {
                centre,
                scale,
                n,
                m,
                axis
            }
        ),
        (
            place,
            (
                0.8..1.6f64,
                0.3..0.7f64,
                0.3..0.7f64,
                0.8..1.6f64,
                0.4..1.2f64
            ),
            (-3.2..3.2f64, -1.5..1.5f64)
        )
            .prop_map(|(centre, (a, fc, fb, d, h), (yaw, pitch))| Solid::Ell {
                centre,
                a,
                b: fb * d,
                c: fc * a,
                d,
                h,
                yaw,
                pitch
            }),
    ]
}

fn solids() -> impl Strategy<Value = Solids> {
    (
        proptest::collection::vec(solid(), 1..4),
        prop_oneof![
            Just(Vec::new()),
            proptest::collection::vec(
                [point(-0.55, 0.55), point(-0.55, 0.55), point(-0.55, 0.55)],
                1..5
            ),
        ],
    )
        .prop_map(|(solids, loose)| Solids { solids, loose })
}

/// Where a camera is put; indices of solids and triangles are taken modulo their counts.
#[derive(Debug, Clone)]
enum Shot {
    /// The eye inside a solid (near its interior point), looking along `look`.
    Inside {
        solid: usize,
        along: f64,
        offset: [f64; 3],
        look: [f64; 3],
    },
    /// The eye `lift` (in units of the triangle's size) outside a point of one of a solid's
    /// triangles, looking into the solid (tilted by `tilt`), with a near distance `near`
    /// times the eye's distance to the triangle's plane: the near plane cuts the solid open.
    NearCut {
        solid: usize,
        triangle: usize,
        weights: [f64; 3],
        lift: f64,
        tilt: [f64; 2],
        near: f64,
    },
    /// The eye `distance` times the scene's radius from its centre, aiming near the centre.
    Outside {
        direction: [f64; 3],
        distance: f64,
        aim: [f64; 3],
    },
}

/// Two shots of each kind: inside, near cut, outside.
fn shots() -> impl Strategy<Value = [Shot; 6]> {
    let inside = (
        0usize..3,
        0.0..1.0f64,
        point(-0.3, 0.3),
        point(-1.0, 1.0).prop_filter("a direction", |v| DVec3::from_array(*v).length() > 0.2),
    )
        .prop_map(|(solid, along, offset, look)| Shot::Inside {
            solid,
            along,
            offset,
            look,
        });
    let near_cut = (
        (0usize..3, 0usize..1000),
        point(0.2, 1.0),
        0.01..0.05f64,
        [-0.6..0.6f64, -0.6..0.6f64],
        2.0..4.0f64,
    )
        .prop_map(
            |((solid, triangle), weights, lift, tilt, near)| Shot::NearCut {
                solid,
                triangle,
                weights,
                lift,
                tilt,
                near,
            },
        );
    let outside = (
        point(-1.0, 1.0).prop_filter("a direction", |v| DVec3::from_array(*v).length() > 0.2),
        1.3..3.0f64,
        point(-0.3, 0.3),
    )
        .prop_map(|(direction, distance, aim)| Shot::Outside {
            direction,
            distance,
            aim,
        });
    (
        inside.clone(),
        inside,
        near_cut.clone(),
        near_cut,
        outside.clone(),
        outside,
    )
        .prop_map(|(a, b, c, d, e, f)| [a, b, c, d, e, f])
}

/// An up hint for a view from `eye` towards `target`, not parallel to it.
fn up_towards(eye: DVec3, target: DVec3) -> DVec3 {
    if (target - eye).normalize().y.abs() > 0.9 {
        DVec3::X
    } else {
        DVec3::Y
    }
}

/// A camera looking from `eye` towards `target`, with an up hint not parallel to the view.
fn camera_towards(eye: DVec3, target: DVec3, w: u32, h: u32, near: f64) -> Camera {
    let up = up_towards(eye, target);
    Camera::look_at(Pose { eye, target, up }, 60.0, w, h, near).expect("camera")
}

/// Of the pixels where `a` and `b` differ, those robust for the exact ray-casting reference of
/// `mesh` (compiled into `bytes`) seen as [`camera_towards`] sees it: farther than 1/16 pixel
/// from every projected edge.
fn robust_differences(
    mesh: &Mesh,
    bytes: &[u8],
    (eye, target, near): (DVec3, DVec3, f64),
    (w, h): (u32, u32),
    a: &[u32],
    b: &[u32],
) -> usize {
    let shot = ViewShot {
        eye,
        target,
        up: up_towards(eye, target),
        fov_y_deg: 60.0,
        width: w,
        height: h,
        near: Some(near),
    };
    let triangles: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
    let seen = reference(&triangles, &polygons(bytes), &shot, near);
    (a.iter().zip(b).zip(&seen.robust))
        .filter(|&((x, y), &robust)| x != y && robust)
        .count()
}

impl Shot {
    /// Eye, target and near distance for `scene` (`default_near` unless the shot cuts).
    fn place(&self, scene: &Solids, default_near: f64) -> (DVec3, DVec3, f64) {
        let pick = |i: usize| &scene.solids[i % scene.solids.len()];
        match self {
            Shot::Inside {
                solid,
                along,
                offset,
                look,
            } => {
                let (p, r) = pick(*solid).interior(*along);
                let eye = p + DVec3::from_array(*offset) * r;
                (eye, eye + DVec3::from_array(*look), default_near)
            }
            Shot::NearCut {
                solid,
                triangle,
                weights,
                lift,
                tilt,
                near,
            } => {
                let tris = pick(*solid).triangles();
                let [a, b, c] = tris[triangle % tris.len()];
                let w = DVec3::from_array(*weights);
                let w = w / (w.x + w.y + w.z);
                let p = a * w.x + b * w.y + c * w.z;
                let cross = (b - a).cross(c - a);
                let n = cross.normalize();
                let size = (cross.length() / 2.0).sqrt();
                let eye = p + n * (lift * size);
                let (u, v) = n.any_orthonormal_pair();
                let forward = -n + u * tilt[0] + v * tilt[1];
                (eye, eye + forward, near * lift * size)
            }
            Shot::Outside {
                direction,
                distance,
                aim,
            } => {
                let (lo, hi) = bounds(&scene.mesh().0);
                let c = (lo + hi) / 2.0;
                let r = (hi - lo).length() / 2.0;
                let eye = c + DVec3::from_array(*direction).normalize() * (distance * r);
                (eye, c + DVec3::from_array(*aim) * r, default_near)
            }
        }
    }
}

/// What one case of [`culling_is_pixel_neutral_for_every_camera`] saw: cameras inside a solid
/// or cutting one open, and how many of them see mostly closed meshes from behind.
#[derive(Debug, Clone, Copy, Default)]
struct Seen {
    cameras: usize,
    from_behind: usize,
    /// Polygons the walk yielded from outside, compiled without `solid` and with it.
    outside_visited: [u64; 2],
}

/// One case: `scene` from each of `shots`, every image with culling equal to the image
/// without; counts what the inside and near-cut cameras see.
fn neutral_for(scene: &Solids, shots: &[Shot]) -> Result<Seen, TestCaseError> {
    let (mesh, solid) = scene.mesh();
    // Not vacuous: every solid is closed and oriented outwards (seen from inside, or through
    // the near plane's cut, it shows back faces).
    for (i, s) in scene.solids.iter().enumerate() {
        prop_assert!(
            closed_outward(&s.triangles()),
            "scene {:?}: solid {} is not closed",
            scene,
            i
        );
    }
    let options = CompileOptions {
        ids: true,
        ..CompileOptions::default()
    };
    let bytes = compile_mesh(&mesh, &options, &|_| {}).expect("compile").1;
    let file = Scene::parse(&bytes).expect("valid file");
    let solid_options = CompileOptions {
        solid: true,
        ..options
    };
    let solid_bytes = compile_mesh(&mesh, &solid_options, &|_| {})
        .expect("compile")
        .1;
    let solid_file = Scene::parse(&solid_bytes).expect("valid file");
    prop_assert!(
        solid_file.header().flags & peel_runtime::read::layout::header_flags::SOLID != 0,
        "scene {:?}: no solid marked",
        scene
    );
    let h = file.header();
    let default_near = Camera::default_near(h.bounds_min, h.bounds_max);
    let mut seen = Seen::default();
    for (k, shot) in shots.iter().enumerate() {
        let (eye, target, near) = shot.place(scene, default_near);
        for (w, ht) in [(24, 18), (57, 43), (96, 72)] {
            let camera = camera_towards(eye, target, w, ht, near);
            for sub in [0, 4, 8] {
                for order in [Order::FrontToBack, Order::BackToFront] {
                    let (with, visited) = ids_image_at(sub, &file, &camera, order, true);
                    let (without, _) = ids_image_at(sub, &file, &camera, order, false);
                    let (with_solids, solid_visited) =
                        ids_image_at(sub, &solid_file, &camera, order, true);
                    let differ = with.iter().zip(&without).filter(|(a, b)| a != b).count();
                    // Faces of the solids seen from behind skipped: at the renderer's 8
                    // fractional bits no robust pixel changes. Snapping can turn a sliver of a
                    // face over at a silhouette (a face seen from behind then covers a pixel
                    // centre that no face seen from the front covers): within a few hundredths
                    // of a pixel of its edges at 8 bits, more at 0 and 4.
                    let differ_at = |a: &[u32], b: &[u32]| a.iter().zip(b).any(|(x, y)| x != y);
                    let solid_differ = if sub == 8 && differ_at(&with_solids, &without) {
                        robust_differences(
                            &mesh,
                            &solid_bytes,
                            (eye, target, near),
                            (w, ht),
                            &with_solids,
                            &without,
                        )
                    } else {
                        0
                    };
                    // The frame, for the messages below.
                    let frame = || {
                        format!(
                            "scene {scene:?}, camera {k} {shot:?} (eye {eye}, target {target}, \
                             near {near}), {order:?}, SUB = {sub}, {w}x{ht}"
                        )
                    };
                    prop_assert!(
                        solid_differ == 0,
                        "{}: {} of {} robust pixels change with solids",
                        frame(),
                        solid_differ,
                        w * ht
                    );
                    if matches!(shot, Shot::Outside { .. }) {
                        seen.outside_visited[0] += visited;
                        seen.outside_visited[1] += solid_visited;
                    }
                    prop_assert_eq!(
                        differ,
                        0,
                        "{}: {} of {} pixels change with culling",
                        frame(),
                        differ,
                        w * ht
                    );
                    if matches!(shot, Shot::Outside { .. })
                        || (w, sub, order) != (96, 8, Order::FrontToBack)
                    {
                        continue;
                    }
                    // Not vacuous: from inside a solid, or through the near plane's cut, the
                    // camera sees the scene everywhere or nearly...
                    let covered = without.iter().filter(|&&id| id > 0).count();
                    prop_assert!(
                        covered * 2 >= without.len(),
                        "scene {:?}, camera {} {:?}: only {} of {} pixels show the scene",
                        scene,
                        k,
                        shot,
                        covered,
                        without.len()
                    );
                    // ...and, mostly, closed meshes from behind (unless something else inside
                    // the solid hides them): what culling back faces would remove.
                    let behind = without
                        .iter()
                        .filter(|&&id| {
                            let i = id as usize;
                            i > 0 && solid[i - 1] && {
                                let [a, b, c] = mesh.triangles[i - 1].vertices;
                                (b - a).cross(c - a).dot(eye - a) < 0.0
                            }
                        })
                        .count();
                    seen.cameras += 1;
                    if behind * 4 >= without.len() {
                        seen.from_behind += 1;
                    }
                }
            }
        }
    }
    Ok(seen)
}

/// Random scenes of closed solids (see [`solids`]) from two cameras inside a solid, two with
/// the near plane cutting a solid open and two outside everything: the image with culling
/// equals the image without, pixel for pixel, in both orders, at 0, 4 and 8 fractional bits
/// and at three image sizes; the image of the scene compiled with `solid`, whose walk skips the
/// faces seen from behind from outside, differs from it on no robust pixel.
#[test]
fn culling_is_pixel_neutral_for_every_camera() {
    let config = ProptestConfig {
        max_shrink_iters: 64,
        source_file: Some(file!()),
        ..ProptestConfig::with_cases(96)
    };
    let mut runner = TestRunner::new(config);
    let total = Cell::new(Seen::default());
    let result = runner.run(&(solids(), shots()), |(scene, shots)| {
        let seen = neutral_for(&scene, &shots)?;
        let t = total.get();
        total.set(Seen {
            cameras: t.cameras + seen.cameras,
            from_behind: t.from_behind + seen.from_behind,
            outside_visited: [0, 1].map(|k| t.outside_visited[k] + seen.outside_visited[k]),
        });
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    // Most inside and near-cut cameras see closed meshes from behind on a quarter of their
    // pixels or more (a few see mostly loose triangles or another solid inside the solid).
    let t = total.get();
    assert!(
        t.cameras > 0 && t.from_behind * 10 >= t.cameras * 6,
        "only {} of {} inside and near-cut cameras see closed meshes from behind",
        t.from_behind,
        t.cameras
    );
    // From outside, the walk skips the solids' faces seen from behind in the frames that need
    // no clipping (about 0.7 of the polygons visited remain over a run; views that cut the
    // scene's box skip none).
    let [plain, solid] = t.outside_visited;
    assert!(
        solid * 100 <= plain * 85,
        "from outside, {solid} polygons visited with solids against {plain} without"
    );
}
