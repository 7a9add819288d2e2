//! Closed meshes: which source triangles may be drawn one-sided (back-face culled).
//!
//! A triangle is **one-sided** when the connected component it belongs to is a closed,
//! consistently and outward oriented surface:
//! - components: triangles are connected when they share an edge (two corners with equal
//!   coordinates, exactly: no tolerance, so a mesh whose seams do not weld exactly is open);
//! - closed and consistent: every edge of the component is used by exactly two triangles, once
//!   in each direction (a→b and b→a). One edge used once (a hole), three or more times
//!   (non-manifold) or twice in the same direction (inconsistent winding) makes the **whole
//!   component** two-sided: the decision is per component,
//!   since orientation only means something for a surface as a whole;
//! - a triangle with two equal corners (no area, nothing to draw) is two-sided and ignored;
//! - outward: the component's signed volume is positive (counter-clockwise seen from outside).
//!   An inside-out closed mesh is consistent but shows its back faces from outside: two-sided;
//! - embedded: no two of its triangles cross (exact test in [`intersect`]). A surface that
//!   folds through itself, as scanned meshes sometimes do, shows back faces from outside too.
//!
//! Why this is safe for an eye **outside** every closed component: a point seen from behind on
//! an outward closed surface is reached through the solid, so a front face of the same surface
//! lies between it and the eye and hides it; skipping it does not change the image. That holds
//! for the polygons the compiler cuts from those triangles (same plane, same side) and whatever
//! other meshes interpenetrate. It fails when the eye is **inside** a closed mesh, or when the
//! near plane cuts one open (the hiding front face is clipped away): then back faces are
//! visible and culling shows what is behind them instead. The compiler cannot know the camera,
//! so the file marks the polygons and the runtime's `RenderOptions::cull` (on by default, off
//! with `peel render --no-cull`) decides.

use crate::hash::FastMap;

use glam::DVec3;

use crate::load::SourceTriangle;

/// Exact identity of a coordinate triple (`-0.0` and `0.0` are the same point).
fn key(v: DVec3) -> [u64; 3] {
    (v + DVec3::ZERO).to_array().map(f64::to_bits)
}

/// Union-find over triangles, path halving.
struct Components(Vec<u32>);

impl Components {
    fn find(&mut self, mut i: u32) -> u32 {
        while self.0[i as usize] != i {
            let up = self.0[self.0[i as usize] as usize];
            self.0[i as usize] = up;
            i = up;
        }
        i
    }

    fn union(&mut self, a: u32, b: u32) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.0[a.max(b) as usize] = a.min(b);
        }
    }
}

/// The uses of one undirected edge: the first two `(triangle, runs low -> high)`, and how many.
#[derive(Default)]
struct EdgeUses {
    uses: [(u32, bool); 2],
    count: u32,
}

/// Per source triangle: whether it belongs to a closed, consistently and outward oriented
/// component (see the module docs), hence may be drawn one-sided.
pub fn one_sided_triangles(triangles: &[SourceTriangle]) -> Vec<bool> {
    let n = triangles.len();
    let mut ids: FastMap<[u64; 3], u32> = FastMap::default();
    let corners: Vec<[u32; 3]> = triangles
        .iter()
        .map(|t| {
            t.vertices.map(|v| {
                let next = ids.len() as u32;
                *ids.entry(key(v)).or_insert(next)
            })
        })
        .collect();

    // Undirected edge (low, high) -> its first two uses (triangle, runs low -> high) and how
    // many there are. All the triangles of an edge join one component, and one bad triangle
    // spoils its component, so marking one of them bad is enough (no list per edge).
    let mut edges: FastMap<(u32, u32), EdgeUses> = FastMap::default();
    let mut components = Components((0..n as u32).collect());
    let mut bad = vec![false; n];
    for (t, c) in corners.iter().enumerate() {
        if c[0] == c[1] || c[1] == c[2] || c[2] == c[0] {
            bad[t] = true; // alone in its component: it spoils nothing else
            continue;
        }
        for k in 0..3 {
            let (a, b) = (c[k], c[(k + 1) % 3]);
            let e = edges.entry((a.min(b), a.max(b))).or_default();
            match e.count {
                0 => e.uses[0] = (t as u32, a < b),
                1 => e.uses[1] = (t as u32, a < b),
                _ => bad[t] = true, // a third use: not a manifold edge
            }
            if e.count > 0 {
                components.union(t as u32, e.uses[0].0);
            }
            e.count = e.count.saturating_add(1);
        }
    }
    for e in edges.values() {
        // Open (one use), or two uses in the same direction.
        if e.count == 1 || (e.count == 2 && e.uses[0].1 == e.uses[1].1) {
            bad[e.uses[0].0 as usize] = true;
        }
    }

    // Per component root: spoiled, and the signed volume (times 6) about a local origin.
    let mut spoiled = vec![false; n];
    let mut origin: Vec<Option<DVec3>> = vec![None; n];
    let mut volume = vec![0.0f64; n];
    for t in 0..n {
        let root = components.find(t as u32) as usize;
        spoiled[root] |= bad[t];
        let [a, b, c] = triangles[t].vertices;
        let o = *origin[root].get_or_insert(a);
        volume[root] += (a - o).dot((b - o).cross(c - o));
    }
    // A surface that crosses itself shows back faces from outside: two-sided.
    let mut members: FastMap<usize, Vec<[DVec3; 3]>> = FastMap::default();
    for (t, tri) in triangles.iter().enumerate() {
        let root = components.find(t as u32) as usize;
        if !spoiled[root] && volume[root] > 0.0 {
            members.entry(root).or_default().push(tri.vertices);
        }
    }
    let crossing: Vec<usize> = members
        .into_iter()
        .filter(|(_, tris)| intersect::self_intersecting(tris))
        .map(|(root, _)| root)
        .collect();
    for root in crossing {
        spoiled[root] = true;
    }
    (0..n)
        .map(|t| {
            let root = components.find(t as u32) as usize;
            !spoiled[root] && volume[root] > 0.0
        })
        .collect()
}

mod intersect;

#[cfg(test)]
mod tests;
