//! Solids: the parts of a quantised mesh that enclose a volume, facing out (`peel compile
//! --solid`).
//!
//! A face of such a part seen from behind, from an eye outside the part, is hidden: the
//! segment from any of its points to the eye starts inside the part and ends outside, so it
//! crosses the part's surface in between. The runtime skips those faces, before any vertex
//! work, in frames that need no clipping: the whole scene in front of the near plane, so the
//! eye is outside every part and no near plane cuts the surface in between away. The argument
//! needs the part's inside to be the back of every face, which holds for a closed surface that
//! faces out and does not pass through itself. Closed and facing out is checked here, exactly
//! on the grid; a surface passing through itself is not detected, which is why the option is
//! the user's to give.

use crate::hash::FastMap;
use crate::load::Mesh;
use crate::planes::Plane;

use super::{IPoint, Quantiser};

/// Per triangle of `mesh`, whether it bounds a solid: its connected part (triangles sharing
/// grid vertices, degenerate ones left out as the build leaves them out) is closed, every
/// directed edge met once and its reverse once, and encloses a positive volume (its faces
/// wound counter-clockwise seen from outside, as OBJ's fronts are), and none of its triangles
/// is transparent (its inside shows through). Exact and deterministic.
pub fn solid_triangles(mesh: &Mesh, quantiser: &Quantiser) -> Vec<bool> {
    let corners: Vec<Option<[IPoint; 3]>> = mesh
        .triangles
        .iter()
        .map(|t| {
            let q = t.vertices.map(|p| quantiser.quantise(p));
            Plane::through(q[0], q[1], q[2]).map(|_| q)
        })
        .collect();
    let mut ids: FastMap<IPoint, u32> = FastMap::default();
    let mut points: Vec<IPoint> = Vec::new();
    let mut kept: Vec<(usize, [u32; 3])> = Vec::new();
    for (i, q) in corners.iter().enumerate() {
        if let Some(q) = q {
            let v = q.map(|p| {
                *ids.entry(p).or_insert_with(|| {
                    points.push(p);
                    points.len() as u32 - 1
                })
            });
            kept.push((i, v));
        }
    }
    let mut parts = Parts::new(points.len());
    for &(_, [a, b, c]) in &kept {
        parts.join(a, b);
        parts.join(b, c);
    }
    let mut edges: FastMap<(u32, u32), u32> = FastMap::default();
    for &(_, [a, b, c]) in &kept {
        for e in [(a, b), (b, c), (c, a)] {
            *edges.entry(e).or_insert(0) += 1;
        }
    }
    // Per part (its root vertex): open, and six times its signed volume.
    let mut open: FastMap<u32, bool> = FastMap::default();
    let mut volume: FastMap<u32, i128> = FastMap::default();
    for &(i, [a, b, c]) in &kept {
        let root = parts.root(a);
        let closed = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(x, y)| edges.get(&(x, y)) == Some(&1) && edges.get(&(y, x)) == Some(&1));
        // A part with a transparent face shows its inside: it hides nothing, as an open one.
        let see_through = mesh.triangles[i].opacity < crate::load::OPAQUE;
        *open.entry(root).or_insert(false) |= !closed || see_through;
        let [p, q, r] = [a, b, c].map(|v| points[v as usize]);
        *volume.entry(root).or_insert(0) += det(p, q, r);
    }
    let mut solid = vec![false; mesh.triangles.len()];
    for &(i, [a, _, _]) in &kept {
        let root = parts.root(a);
        solid[i] = !open[&root] && volume[&root] > 0;
    }
    solid
}

/// `p . (q x r)`, exact: each coordinate below 2^26, so each term below 2^79.
fn det(p: IPoint, q: IPoint, r: IPoint) -> i128 {
    let [p, q, r] = [p, q, r].map(|v| v.map(i128::from));
    p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0])
        + p[2] * (q[0] * r[1] - q[1] * r[0])
}

/// Union-find over vertex ids: the connected parts.
struct Parts(Vec<u32>);

impl Parts {
    fn new(n: usize) -> Parts {
        Parts((0..n as u32).collect())
    }

    fn root(&mut self, mut v: u32) -> u32 {
        while self.0[v as usize] != v {
            let up = self.0[self.0[v as usize] as usize];
            self.0[v as usize] = up;
            v = up;
        }
        v
    }

    /// The smaller root becomes the parent: the roots do not depend on the order of joins.
    fn join(&mut self, a: u32, b: u32) {
        let (a, b) = (self.root(a), self.root(b));
        let (low, high) = (a.min(b), a.max(b));
        self.0[high as usize] = low;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::{Mesh, SourceTriangle};
    use glam::DVec3;

    /// A unit cube's 12 triangles, fronts facing out.
    fn cube(at: DVec3) -> Vec<[DVec3; 3]> {
        let c = |x: f64, y: f64, z: f64| at + DVec3::new(x, y, z);
        let quads = [
            [c(0., 0., 0.), c(0., 1., 0.), c(1., 1., 0.), c(1., 0., 0.)], // z = 0, facing -z
            [c(0., 0., 1.), c(1., 0., 1.), c(1., 1., 1.), c(0., 1., 1.)], // z = 1, facing +z
            [c(0., 0., 0.), c(1., 0., 0.), c(1., 0., 1.), c(0., 0., 1.)], // y = 0, facing -y
            [c(0., 1., 0.), c(0., 1., 1.), c(1., 1., 1.), c(1., 1., 0.)], // y = 1, facing +y
            [c(0., 0., 0.), c(0., 0., 1.), c(0., 1., 1.), c(0., 1., 0.)], // x = 0, facing -x
            [c(1., 0., 0.), c(1., 1., 0.), c(1., 1., 1.), c(1., 0., 1.)], // x = 1, facing +x
        ];
        quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect()
    }

    fn mesh(triangles: &[[DVec3; 3]]) -> Mesh {
        Mesh {
            triangles: triangles
                .iter()
                .map(|&vertices| SourceTriangle {
                    opacity: u8::MAX,
                    vertices,
                    colour: [200; 3],
                    normals: None,
                    texture: None,
                })
                .collect(),
            ..Mesh::default()
        }
    }

    fn solid(triangles: &[[DVec3; 3]]) -> Vec<bool> {
        let m = mesh(triangles);
        solid_triangles(&m, &Quantiser::fit(&m))
    }

    #[test]
    fn a_closed_cube_facing_out_is_solid() {
        assert_eq!(solid(&cube(DVec3::ZERO)), vec![true; 12]);
    }

    #[test]
    fn a_cube_facing_in_is_not() {
        let inward: Vec<_> = cube(DVec3::ZERO)
            .into_iter()
            .map(|[a, b, c]| [a, c, b])
            .collect();
        assert_eq!(solid(&inward), vec![false; 12]);
    }

    #[test]
    fn an_open_cube_is_not_and_a_closed_one_beside_it_is() {
        let mut triangles = cube(DVec3::ZERO);
        triangles.pop(); // one face's half gone
        triangles.extend(cube(DVec3::new(3.0, 0.0, 0.0)));
        let s = solid(&triangles);
        assert_eq!(s[..11], [false; 11]);
        assert_eq!(s[11..], [true; 12]);
    }

    #[test]
    fn a_face_wound_against_its_neighbours_opens_the_part() {
        let mut triangles = cube(DVec3::ZERO);
        let [a, b, c] = triangles[4];
        triangles[4] = [a, c, b];
        assert_eq!(solid(&triangles), vec![false; 12]);
    }

    #[test]
    fn a_doubled_face_opens_the_part_and_a_degenerate_triangle_is_not_solid() {
        let mut triangles = cube(DVec3::ZERO);
        triangles.push(triangles[0]);
        assert_eq!(solid(&triangles), vec![false; 13]);
        let mut triangles = cube(DVec3::ZERO);
        triangles.push([DVec3::ZERO, DVec3::X, DVec3::X * 2.0]);
        let s = solid(&triangles);
        assert_eq!(s[..12], [true; 12]);
        assert!(!s[12]);
    }
}
