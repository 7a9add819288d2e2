//! Shared helpers of the end-to-end tests. The reference ray caster lives in the compiler crate
//! (`peel_compiler::tools::reference`) because `peel bench` measures errors against it too.

pub use peel_compiler::tools::reference::*;

/// Bounds of a mesh's source triangles.
pub fn bounds(mesh: &Mesh) -> (DVec3, DVec3) {
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

use std::collections::HashMap;

use glam::DVec3;
use peel_compiler::load::Mesh;

/// `peel_compiler::tools::scenes::sphere(rings, segments)` made exactly closed. The generator puts
/// the south pole of segment `j` at `(sin(pi) cos(phi_j), -1, sin(pi) sin(phi_j))`, and
/// `sin(pi)` is about 1.2e-16 in `f64`: one point per segment, so the pole's triangles share
/// no edge exactly and the mesh has a hole there. Here every vertex within 1e-9 of the y axis
/// is put on it exactly.
pub fn closed_sphere(rings: usize, segments: usize) -> Mesh {
    let mut mesh = peel_compiler::tools::scenes::sphere(rings, segments);
    for t in &mut mesh.triangles {
        for v in &mut t.vertices {
            if v.x.abs() < 1e-9 && v.z.abs() < 1e-9 {
                *v = DVec3::new(0.0, v.y.signum(), 0.0);
            }
        }
    }
    mesh
}

/// Whether `triangles` form a closed surface oriented outwards, exactly: every directed edge
/// (between corners with identical coordinates) is used once and its reverse once, and the
/// signed volume is positive (counter-clockwise seen from outside). Seen from inside such a
/// surface, or through a near plane that cuts it open, every face that shows is a back face.
pub fn closed_outward(triangles: &[[DVec3; 3]]) -> bool {
    let key = |v: DVec3| (v + DVec3::ZERO).to_array().map(f64::to_bits);
    let mut edges: HashMap<([u64; 3], [u64; 3]), u32> = HashMap::new();
    let mut volume = 0.0;
    for &[a, b, c] in triangles {
        for (p, q) in [(a, b), (b, c), (c, a)] {
            *edges.entry((key(p), key(q))).or_default() += 1;
        }
        volume += a.dot(b.cross(c));
    }
    volume > 0.0
        && edges
            .iter()
            .all(|(&(p, q), &n)| n == 1 && edges.get(&(q, p)) == Some(&1))
}

/// [`closed_outward`] for a whole mesh.
pub fn mesh_closed_outward(mesh: &Mesh) -> bool {
    let triangles: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
    closed_outward(&triangles)
}

/// World-space polygons of a compiled file (their edges include every cut).
pub fn polygons(bytes: &[u8]) -> Vec<Vec<DVec3>> {
    let scene = peel_runtime::read::Scene::parse(bytes).expect("valid file");
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
