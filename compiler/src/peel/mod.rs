//! Peel: which support planes of a fragment list lie on its convex hull (seed 000's set E).
//!
//! A plane is on the hull iff no vertex of the list lies strictly on one of its sides. The
//! naive test scans every vertex for every plane (O(n²) per node). Instead the distinct
//! vertices go into a bounding-volume hierarchy with f64 boxes; a query "is some vertex
//! strictly on this side?" prunes a box only when an f64 bound *proves* it (the error bound
//! of [`crate::planes::FILTER_BOUND`] with a wide extra margin), accepts a box wholly and
//! strictly on the side the same way, and decides the remaining leaves with the exact
//! predicate. Nothing is approximate: f64 only chooses which exact tests to run.
//!
//! Cost: building is O(m log m) for m distinct vertices. A query for a plane that is not on
//! the hull usually stops at the first boxes it visits; a hull plane visits the boxes that
//! touch it within the rounding margin (those around its own vertices, plus box corners
//! poking through it). Worst case (every vertex within the margin of the plane, e.g. a
//! nearly flat or highly symmetric scene) it degrades to the exact scan, O(m) per plane.

use rayon::prelude::*;

use crate::planes::Vertex;
use crate::planes::{side_of_hom, HomPoint, PlaneEntry, PlaneId, PlaneTable, Side};
use crate::split::Fragment;

/// Points per leaf.
const LEAF: usize = 8;

/// Extra safety factor on the f64 box bounds (on top of the per-vertex filter bound).
const BOX_MARGIN: f64 = 1.0 / (1u64 << 40) as f64;

#[derive(Clone, Copy)]
enum Pt<'a> {
    Int([i32; 3]),
    Hom(&'a HomPoint),
}

impl Pt<'_> {
    fn side(&self, e: &PlaneEntry) -> Side {
        match self {
            Pt::Int(p) => e.plane.side_of_point(*p),
            Pt::Hom(h) => side_of_hom(h, e),
        }
    }
}

struct BvhNode {
    min: [f64; 3],
    max: [f64; 3],
    /// Leaf: `start..end` into the points. Inner: children at `start` and `end`.
    start: u32,
    end: u32,
    leaf: bool,
}

/// The vertices of a fragment list in a bounding-volume hierarchy.
pub struct VertexSet<'a> {
    pts: Vec<([f64; 3], Pt<'a>)>,
    nodes: Vec<BvhNode>,
}

impl<'a> VertexSet<'a> {
    /// The distinct grid vertices and all cut vertices of `frags`.
    pub fn new(frags: &'a [Fragment]) -> VertexSet<'a> {
        let mut ints: Vec<[i32; 3]> = Vec::new();
        let mut pts: Vec<([f64; 3], Pt<'a>)> = Vec::new();
        for f in frags {
            for v in &f.vertices {
                match v {
                    Vertex::Int(p) => ints.push(*p),
                    Vertex::Hom(h) => pts.push((h.approx, Pt::Hom(h))),
                }
            }
        }
        ints.sort_unstable();
        ints.dedup();
        pts.extend(ints.into_iter().map(|p| (p.map(|c| c as f64), Pt::Int(p))));
        let mut set = VertexSet {
            pts,
            nodes: Vec::new(),
        };
        if !set.pts.is_empty() {
            let n = set.pts.len();
            set.build(0, n);
        }
        set
    }

    fn build(&mut self, start: usize, end: usize) -> u32 {
        let mut min = [f64::INFINITY; 3];
        let mut max = [f64::NEG_INFINITY; 3];
        for (p, _) in &self.pts[start..end] {
            for k in 0..3 {
                min[k] = min[k].min(p[k]);
                max[k] = max[k].max(p[k]);
            }
        }
        let id = self.nodes.len() as u32;
        self.nodes.push(BvhNode {
            min,
            max,
            start: start as u32,
            end: end as u32,
            leaf: true,
        });
        if end - start > LEAF {
            let axis = (0..3)
                .max_by(|&a, &b| (max[a] - min[a]).total_cmp(&(max[b] - min[b])))
                .unwrap_or(0);
            let mid = (start + end) / 2;
            self.pts[start..end]
                .select_nth_unstable_by(mid - start, |a, b| a.0[axis].total_cmp(&b.0[axis]));
            let l = self.build(start, mid);
            let r = self.build(mid, end);
            let node = &mut self.nodes[id as usize];
            node.leaf = false;
            node.start = l;
            node.end = r;
        }
        id
    }

    /// Proven range of `n·p − d` over a box: `(lo, hi, margin)`.
    fn range(node: &BvhNode, e: &PlaneEntry) -> (f64, f64, f64) {
        let (mut lo, mut hi, mut m) = (-e.df, -e.df, e.df.abs());
        for k in 0..3 {
            let (a, b) = (e.nf[k] * node.min[k], e.nf[k] * node.max[k]);
            lo += a.min(b);
            hi += a.max(b);
            m += a.abs().max(b.abs());
        }
        (lo, hi, m * BOX_MARGIN)
    }

    /// True when some vertex lies strictly on `side` (`Front` or `Back`) of `e`.
    pub fn any_strictly(&self, e: &PlaneEntry, side: Side) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let sign = if side == Side::Front { 1.0 } else { -1.0 };
        // The median split keeps the hierarchy's depth below 33 for any `u32` point count;
        // each level leaves at most one sibling on the stack.
        let mut stack = [0u32; 80];
        let mut len = 1;
        while len > 0 {
            len -= 1;
            let i = stack[len];
            let node = &self.nodes[i as usize];
            let (lo, hi, m) = Self::range(node, e);
            let (lo, hi) = if sign > 0.0 { (lo, hi) } else { (-hi, -lo) };
            if hi < -m {
                continue; // every vertex strictly on the other side
            }
            if lo > m {
                return true; // a non-empty box wholly, strictly on `side`
            }
            if node.leaf {
                if self.pts[node.start as usize..node.end as usize]
                    .iter()
                    .any(|(_, p)| p.side(e) == side)
                {
                    return true;
                }
            } else {
                // Visit the child reaching further to `side` first.
                let (l, r) = (node.start, node.end);
                let reach_of = |c: u32| {
                    let (lo, hi, _) = Self::range(&self.nodes[c as usize], e);
                    if sign > 0.0 {
                        hi
                    } else {
                        -lo
                    }
                };
                let (rl, rr) = (reach_of(l), reach_of(r));
                let (first, second) = if rl >= rr { (l, r) } else { (r, l) };
                stack[len] = second;
                stack[len + 1] = first;
                len += 2;
            }
        }
        false
    }

    /// `Some(interior_front)` when `e` is on the hull of the set: `interior_front` is true when
    /// the rest lies on the + side (also when every vertex is in the plane); `None` otherwise.
    pub fn hull_side(&self, e: &PlaneEntry) -> Option<bool> {
        let front = self.any_strictly(e, Side::Front);
        if front && self.any_strictly(e, Side::Back) {
            None
        } else {
            Some(front || !self.any_strictly(e, Side::Back))
        }
    }
}

/// For each plane of `planes` (the distinct support planes of `frags`): `Some(interior_front)`
/// when it is on the convex hull of `frags`, else `None`.
pub fn hull_planes(
    frags: &[Fragment],
    planes: &[PlaneId],
    table: &PlaneTable,
) -> Vec<Option<bool>> {
    let set = VertexSet::new(frags);
    let test = |&p: &PlaneId| set.hull_side(table.get(p));
    if planes.len() > 64 && frags.len() > 512 {
        planes.par_iter().map(test).collect()
    } else {
        planes.iter().map(test).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planes::Plane;
    use proptest::prelude::*;

    fn naive(frags: &[Fragment], e: &PlaneEntry) -> Option<bool> {
        let sides: Vec<Side> = frags
            .iter()
            .flat_map(|f| f.vertices.iter().map(|v| v.side(e)))
            .collect();
        let (f, b) = (sides.contains(&Side::Front), sides.contains(&Side::Back));
        match (f, b) {
            (true, true) => None,
            (true, false) => Some(true),
            (false, true) => Some(false),
            (false, false) => Some(true),
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// The hierarchy answers exactly like the exact scan, on clustered and coplanar points.
        #[test]
        fn hierarchy_matches_the_exact_scan(
            pts in proptest::collection::vec([-40i32..40, -40i32..40, -3i32..3], 3..200),
            scale in 0u32..20,
        ) {
            let s = 1i32 << scale;
            let pts: Vec<[i32; 3]> = pts.iter().map(|p| [p[0] * s, p[1] * s, p[2]]).collect();
            let mut table = PlaneTable::default();
            let mut frags = Vec::new();
            for t in pts.chunks_exact(3) {
                if let Some((p, _)) = Plane::through(t[0], t[1], t[2]) {
                    let id = table.insert(p);
                    frags.push(Fragment {
                        source: 0,
                        support: id,
                        flipped: false,
                        vertices: t.iter().map(|&q| Vertex::Int(q)).collect(),
                        edges: Vec::new(),
                    });
                }
            }
            let planes: Vec<PlaneId> = (0..table.len() as PlaneId).collect();
            let got = hull_planes(&frags, &planes, &table);
            for (i, &p) in planes.iter().enumerate() {
                prop_assert_eq!(got[i], naive(&frags, table.get(p)));
            }
        }
    }
}
