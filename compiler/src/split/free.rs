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

use super::choose::Sample;
use super::{Fragment, Placement};
use crate::hash::{FastMap, FastSet};
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
/// Ties go to the split whose smaller side holds the earliest fragment of the list. `whole`,
/// the list's sample when it holds every fragment, tests the candidates a box at a time.
pub fn best_free(
    frags: &[Fragment],
    supports: &[PlaneId],
    table: &PlaneTable,
    whole: Option<&Sample>,
) -> Option<Free> {
    if frags.len() > (u32::MAX / 16) as usize {
        return None;
    }
    // Each grid vertex with its first appearance (fragment position * 16 + corner): invariant
    // under axis swaps and mirrors, unlike its coordinates. Hashed, not sorted: only the
    // vertices tried need more.
    let mut first: FastMap<[i32; 3], u32> =
        FastMap::with_capacity_and_hasher(frags.len() * 2, Default::default());
    for (i, f) in frags.iter().enumerate() {
        for (k, v) in f.vertices.iter().enumerate() {
            if let Vertex::Int(p) = v {
                first.entry(*p).or_insert((i * 16 + k.min(15)) as u32);
            }
        }
    }
    if first.is_empty() {
        return None;
    }
    // Squared distances to the centroid, scaled by the count squared: exact integers.
    let n = first.len() as i128;
    let sum = first.keys().fold([0i128; 3], |s, v| {
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
        first.iter().map(|(v, &f)| (d2(v), f, *v)).collect();
    if order.len() > VERTICES {
        order.select_nth_unstable(VERTICES);
        order.truncate(VERTICES);
    }
    order.sort_unstable();
    let tried: FastSet<[i32; 3]> = order.iter().map(|o| o.2).collect();
    // The neighbours of the vertices tried along fragment edges, then the fragments around
    // every vertex a candidate goes through.
    let mut nbr: Vec<([i32; 3], [i32; 3])> = Vec::new();
    for f in frags {
        let m = f.vertices.len();
        for k in 0..m {
            if let (Vertex::Int(a), Vertex::Int(b)) = (&f.vertices[k], &f.vertices[(k + 1) % m]) {
                if tried.contains(a) {
                    nbr.push((*a, *b));
                }
                if tried.contains(b) {
                    nbr.push((*b, *a));
                }
            }
        }
    }
    nbr.sort_unstable();
    nbr.dedup();
    let needed: FastSet<[i32; 3]> = tried
        .iter()
        .copied()
        .chain(nbr.iter().map(|e| e.1))
        .collect();
    let mut inc: Vec<([i32; 3], u32)> = Vec::new();
    for (i, f) in frags.iter().enumerate() {
        for v in &f.vertices {
            if let Vertex::Int(p) = v {
                if needed.contains(p) {
                    inc.push((*p, i as u32));
                }
            }
        }
    }
    inc.sort_unstable();
    let range = |p: [i32; 3]| {
        let lo = inc.partition_point(|e| e.0 < p);
        lo..inc.partition_point(|e| e.0 <= p)
    };
    let first = |p: [i32; 3]| first.get(&p).copied().unwrap_or(u32::MAX);
    let mut supp: Vec<Plane> = supports.iter().map(|&p| table.get(p).plane).collect();
    supp.sort_unstable();
    let locally_free = |e: &PlaneEntry, pts: &[[i32; 3]]| {
        pts.iter().all(|&p| {
            inc[range(p)].iter().all(|&(_, i)| {
                let f = &frags[i as usize];
                matches!(place(f, e), Placement::Front | Placement::Back)
            })
        })
    };
    let mut seen: FastSet<Plane> = Default::default();
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
    // The survivors free on the whole list, with their smaller side.
    let n = frags.len();
    let mut free: Vec<(usize, Free)> = Vec::new();
    for e in survivors {
        let (front, back) = match whole {
            Some(sample) => match sample.tally_free(&e) {
                Some(t) if t.cuts == 0 && (t.front + t.back) as usize == n => {
                    (t.front as usize, t.back as usize)
                }
                _ => continue,
            },
            None => {
                let (mut front, mut back) = (0, 0);
                let all = frags.iter().all(|f| match place(f, &e) {
                    Placement::Front => {
                        front += 1;
                        true
                    }
                    Placement::Back => {
                        back += 1;
                        true
                    }
                    Placement::On | Placement::Straddle => false,
                });
                if !all {
                    continue;
                }
                (front, back)
            }
        };
        if front > 0 && back > 0 {
            free.push((
                front.min(back),
                Free {
                    entry: e,
                    front,
                    back,
                },
            ));
        }
    }
    let most = free.iter().map(|f| f.0).max()?;
    free.retain(|f| f.0 == most);
    // Ties: the smaller side holding the earliest fragment of the list (a position in the
    // list, not a coordinate).
    let small = |f: &Free| {
        let side = match f.front.cmp(&f.back) {
            std::cmp::Ordering::Less => Some(Placement::Front),
            std::cmp::Ordering::Greater => Some(Placement::Back),
            std::cmp::Ordering::Equal => None,
        };
        let first = |s: Placement| frags.iter().position(|g| place(g, &f.entry) == s);
        match side {
            Some(s) => first(s),
            None => first(Placement::Front).max(first(Placement::Back)),
        }
    };
    if free.len() == 1 {
        return free.pop().map(|f| f.1);
    }
    free.into_iter()
        .map(|(_, f)| (small(&f), f))
        .min_by_key(|(s, _)| *s)
        .map(|(_, f)| f)
}

#[cfg(test)]
mod tests;
