//! Free splits: planes that are no support plane of a list and cut none of its fragments.
//!
//! A support plane through a closed surface cuts every fragment its line crosses. Yet many
//! lists hold loops of edges that lie in one plane (the rings of a surface of revolution, a
//! mirror plane's seam, the rims of the patches a model was tessellated from) or parts that a
//! plane through a vertex separates: such a plane divides the list without a cut. The
//! candidates are planes through grid vertices of the list, so they stay within the bounds of
//! [`crate::planes`] (those of a support plane) and cut points stay exact: for a vertex `b`,
//! the planes through `b` and two of its neighbours along fragment edges (a loop of edges in
//! one plane passes through such a triple at each of its vertices), and the three axis planes
//! through `b`. Vertices nearest the list's centre are tried first (their planes divide it
//! most evenly); a candidate is first tested on the fragments around its three vertices (where
//! a plane that cuts usually shows it), and only [`GLOBAL`] survivors are tested on the whole
//! list.
//!
//! Everything that orders or breaks ties is invariant under axis swaps and mirrors (exact
//! integer distances, fragment positions in the list), as the rest of the build is.

use super::{Fragment, Placement};
use crate::planes::{Plane, PlaneEntry, PlaneId, PlaneTable, Vertex};

/// Vertices whose planes are tried, nearest the list's centre first. All of them would find
/// a few more free splits (cow 1.718 polygons per triangle instead of 1.725) at a far higher
/// cost (BENCHMARKS.md, "Free splits").
const VERTICES: usize = 64;

/// Candidates that pass the local test and are tested on the whole list, at most.
const GLOBAL: usize = 16;

/// A free split of a list: no fragment cut, some on each side.
#[derive(Debug, Clone, Copy)]
pub struct Free {
    /// The plane (through grid vertices of the list, not a support plane of it).
    pub entry: PlaneEntry,
    /// Fragments on its closed + side.
    pub front: usize,
    /// Fragments on its closed − side.
    pub back: usize,
}

/// Where a fragment lies with respect to `e`.
fn place(f: &Fragment, e: &PlaneEntry) -> Placement {
    Placement::of_sides(f.vertices.iter().map(|v| v.side(e)))
}

/// The most even free split found for `frags` (distinct support planes `supports`), if any.
/// Ties go to the split whose smaller side holds the earliest fragment of the list.
pub fn best_free(frags: &[Fragment], supports: &[PlaneId], table: &PlaneTable) -> Option<Free> {
    // Each grid vertex with the fragments it is a corner of, and with its neighbours along
    // fragment edges; keyed for order by where it first appears in the list.
    let mut inc: Vec<([i32; 3], u32)> = Vec::with_capacity(frags.len() * 3);
    let mut nbr: Vec<([i32; 3], [i32; 3])> = Vec::with_capacity(frags.len() * 6);
    for (i, f) in frags.iter().enumerate() {
        let n = f.vertices.len();
        for k in 0..n {
            if let Vertex::Int(a) = f.vertices[k] {
                inc.push((a, (i * 16 + k.min(15)) as u32));
                if let Vertex::Int(b) = f.vertices[(k + 1) % n] {
                    nbr.push((a, b));
                    nbr.push((b, a));
                }
            }
        }
    }
    if inc.is_empty() || frags.len() > (u32::MAX / 16) as usize {
        return None;
    }
    inc.sort_unstable();
    nbr.sort_unstable();
    nbr.dedup();
    let range = |p: [i32; 3]| {
        let lo = inc.partition_point(|e| e.0 < p);
        lo..inc.partition_point(|e| e.0 <= p)
    };
    // The first appearance of a vertex (fragment position * 16 + corner): invariant under
    // axis swaps and mirrors, unlike its coordinates.
    let first = |p: [i32; 3]| inc[range(p).start..].first().map_or(u32::MAX, |e| e.1);
    let mut verts: Vec<([i32; 3], u32)> = Vec::new();
    for e in &inc {
        match verts.last_mut() {
            Some(v) if v.0 == e.0 => v.1 = v.1.min(e.1),
            _ => verts.push(*e),
        }
    }
    // Squared distances to the centroid, scaled by the count squared: exact integers.
    let n = verts.len() as i128;
    let sum = verts.iter().fold([0i128; 3], |s, (v, _)| {
        [
            s[0] + v[0] as i128,
            s[1] + v[1] as i128,
            s[2] + v[2] as i128,
        ]
    });
    let d2 = |v: &[i32; 3]| -> u128 {
        (0..3)
            .map(|k| (v[k] as i128 * n - sum[k]).unsigned_abs().pow(2))
            .fold(0u128, u128::saturating_add)
    };
    let mut order: Vec<(u128, u32, [i32; 3])> =
        verts.iter().map(|(v, f)| (d2(v), *f, *v)).collect();
    order.sort_unstable();
    order.truncate(VERTICES);
    let mut supp: Vec<Plane> = supports.iter().map(|&p| table.get(p).plane).collect();
    supp.sort_unstable();
    let locally_free = |e: &PlaneEntry, pts: &[[i32; 3]]| {
        pts.iter().all(|&p| {
            inc[range(p)].iter().all(|&(_, i)| {
                let f = &frags[(i / 16) as usize];
                matches!(place(f, e), Placement::Front | Placement::Back)
            })
        })
    };
    let mut seen: crate::hash::FastSet<Plane> = Default::default();
    let mut survivors: Vec<PlaneEntry> = Vec::new();
    // Whole vertices at a time, so that which planes survive does not depend on the order of
    // the candidates of one vertex.
    for &(_, _, b) in &order {
        if survivors.len() >= GLOBAL {
            break;
        }
        let lo = nbr.partition_point(|e| e.0 < b);
        let hi = nbr.partition_point(|e| e.0 <= b);
        let mut ns: Vec<(u32, [i32; 3])> = nbr[lo..hi].iter().map(|e| (first(e.1), e.1)).collect();
        ns.sort_unstable();
        let mut cands: Vec<(Plane, [[i32; 3]; 3])> = Vec::new();
        for i in 0..ns.len() {
            for j in i + 1..ns.len() {
                let (a, c) = (ns[i].1, ns[j].1);
                if let Some((p, _)) = Plane::through(a, b, c) {
                    cands.push((p, [a, b, c]));
                }
            }
        }
        for k in 0..3 {
            let mut normal = [0i64; 3];
            normal[k] = 1;
            let d = i128::from(b[k]);
            cands.push((Plane { n: normal, d }, [b, b, b]));
        }
        for (p, pts) in cands {
            if supp.binary_search(&p).is_ok() || !seen.insert(p) {
                continue;
            }
            let e = PlaneEntry::new(p);
            if locally_free(&e, &pts) {
                survivors.push(e);
            }
        }
    }
    let mut best: Option<(usize, usize, Free)> = None;
    for e in survivors {
        let (mut front, mut back) = (0, 0);
        // The earliest fragment on each side.
        let (mut first_front, mut first_back) = (usize::MAX, usize::MAX);
        let mut cut = false;
        for (i, f) in frags.iter().enumerate() {
            match place(f, &e) {
                Placement::Front => {
                    front += 1;
                    first_front = first_front.min(i);
                }
                Placement::Back => {
                    back += 1;
                    first_back = first_back.min(i);
                }
                Placement::On | Placement::Straddle => {
                    cut = true;
                    break;
                }
            }
        }
        if cut || front == 0 || back == 0 {
            continue;
        }
        let small = if front < back {
            first_front
        } else if back < front {
            first_back
        } else {
            first_front.max(first_back)
        };
        let better = match &best {
            None => true,
            Some((m, s, _)) => {
                (front.min(back), std::cmp::Reverse(small)) > (*m, std::cmp::Reverse(*s))
            }
        };
        if better {
            best = Some((
                front.min(back),
                small,
                Free {
                    entry: e,
                    front,
                    back,
                },
            ));
        }
    }
    best.map(|b| b.2)
}

#[cfg(test)]
mod tests;
