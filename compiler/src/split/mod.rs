//! Split: convex fragments, their exact cut by a plane, and the choice of the splitting plane.
//!
//! A fragment is a convex polygon stored as its support plane plus a cyclic list of bounding
//! planes; its vertices are kept alongside (grid points, or intersections of three table
//! planes). A cut adds one vertex on each cut edge — the intersection of the support plane,
//! the edge's plane and the split plane — and one edge (the split plane) to each piece, so
//! nothing is ever recomputed from rounded data.

use std::sync::Arc;

use rayon::prelude::*;

use std::sync::atomic::{AtomicU64, Ordering};

use crate::bvh::{box_of, max_f, min_f, Bvh};
use crate::planes::{
    intersect, l1_max, shared_filter_bound, PlaneEntry, PlaneId, PlaneTable, Side, Vertex,
};

pub mod lopsided;

/// A bounding edge of a fragment: the plane it lies on and the side the fragment is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    /// The bounding plane.
    pub plane: PlaneId,
    /// The side of `plane` the fragment lies on (`Front` or `Back`).
    pub inside: Side,
}

/// A convex fragment of one source triangle.
#[derive(Debug, Clone, PartialEq)]
pub struct Fragment {
    /// Source triangle id.
    pub source: u32,
    /// Support plane.
    pub support: PlaneId,
    /// True when the source triangle's normal is opposite to the support plane's normal.
    pub flipped: bool,
    /// Vertices, in the source triangle's winding order.
    pub vertices: Vec<Vertex>,
    /// `edges[i]` runs from `vertices[i]` to `vertices[i + 1]` (cyclically).
    pub edges: Vec<Edge>,
}

/// Where a fragment lies with respect to a plane.
#[derive(Debug, Clone, PartialEq)]
pub enum SplitResult {
    /// On the closed + side, not in the plane (the fragment, unchanged).
    Front(Fragment),
    /// On the closed − side, not in the plane.
    Back(Fragment),
    /// In the plane.
    On(Fragment),
    /// Cut in two: `(front piece, back piece)`.
    Cut(Fragment, Fragment),
}

/// How a fragment's vertices fall with respect to a plane, without cutting it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Placement {
    /// On the closed + side, not in the plane.
    Front,
    /// On the closed − side, not in the plane.
    Back,
    /// In the plane.
    On,
    /// Strictly on both sides.
    Straddle,
}

impl Placement {
    /// The placement of vertices on `sides` (stops at the first proof of a straddle).
    fn of_sides(sides: impl Iterator<Item = Side>) -> Placement {
        let (mut front, mut back) = (false, false);
        for side in sides {
            match side {
                Side::Front => front = true,
                Side::Back => back = true,
                Side::On => {}
            }
            if front && back {
                return Placement::Straddle;
            }
        }
        match (front, back) {
            (true, _) => Placement::Front,
            (false, true) => Placement::Back,
            // Every vertex on a plane other than its support: a degenerate fragment.
            (false, false) => Placement::On,
        }
    }
}

impl Fragment {
    /// Where the fragment lies with respect to `plane`.
    pub fn placement(&self, plane: PlaneId, table: &PlaneTable) -> Placement {
        if self.support == plane {
            return Placement::On;
        }
        let e = table.get(plane);
        Placement::of_sides(self.vertices.iter().map(|v| v.side(e)))
    }

    /// Cut the fragment exactly by `plane`. `None` only if the geometry is inconsistent (three
    /// planes that should meet in a point do not): a bug, reported by the caller.
    pub fn split(self, plane: PlaneId, table: &PlaneTable) -> Option<SplitResult> {
        if self.support == plane {
            return Some(SplitResult::On(self));
        }
        let e = table.get(plane);
        // Most fragments are not cut: place them without collecting their sides.
        match Placement::of_sides(self.vertices.iter().map(|v| v.side(e))) {
            Placement::Front => return Some(SplitResult::Front(self)),
            Placement::Back => return Some(SplitResult::Back(self)),
            Placement::On => return Some(SplitResult::On(self)),
            Placement::Straddle => {}
        }
        let sides: Vec<Side> = self.vertices.iter().map(|v| v.side(e)).collect();
        let n = self.vertices.len();
        let cap = n + 2;
        let (mut fv, mut fe) = (Vec::with_capacity(cap), Vec::with_capacity(cap));
        let (mut bv, mut be) = (Vec::with_capacity(cap), Vec::with_capacity(cap));
        let cut_front = Edge {
            plane,
            inside: Side::Front,
        };
        let cut_back = Edge {
            plane,
            inside: Side::Back,
        };
        let support = &table.get(self.support).plane;
        for i in 0..n {
            let j = (i + 1) % n;
            let (si, sj) = (sides[i], sides[j]);
            let v = &self.vertices[i];
            let edge = self.edges[i];
            if si != Side::Back {
                fv.push(v.clone());
                fe.push(if si == Side::On && sj == Side::Back {
                    cut_front
                } else {
                    edge
                });
            }
            if si != Side::Front {
                bv.push(v.clone());
                be.push(if si == Side::On && sj == Side::Front {
                    cut_back
                } else {
                    edge
                });
            }
            if (si == Side::Front && sj == Side::Back) || (si == Side::Back && sj == Side::Front) {
                let h = intersect(support, &table.get(edge.plane).plane, &e.plane)?;
                let c = Vertex::Hom(Arc::new(h));
                if si == Side::Front {
                    fv.push(c.clone());
                    fe.push(cut_front);
                    bv.push(c);
                    be.push(edge);
                } else {
                    bv.push(c.clone());
                    be.push(cut_back);
                    fv.push(c);
                    fe.push(edge);
                }
            }
        }
        if fv.len() < 3 || bv.len() < 3 {
            return None;
        }
        let piece = |vertices, edges| Fragment {
            source: self.source,
            support: self.support,
            flipped: self.flipped,
            vertices,
            edges,
        };
        Some(SplitResult::Cut(piece(fv, fe), piece(bv, be)))
    }
}

/// Small deterministic generator (SplitMix64) for the candidate and fragment samples.
#[derive(Debug, Clone)]
pub struct SplitMix(u64);

impl SplitMix {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> SplitMix {
        SplitMix(seed)
    }

    /// Next value.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform-ish value in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_u64() as u128 * n as u128) >> 64) as usize
    }
}

/// A deterministic hash of a fragment list (sources and supports), to seed its samples from
/// the node's content rather than from shared state: the result is the same on any thread.
pub fn content_hash(frags: &[Fragment]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64 ^ frags.len() as u64;
    for f in frags {
        h = (h ^ ((f.source as u64) << 32 | f.support as u64)).wrapping_mul(0x0000_0100_0000_01B3);
        h = h.rotate_left(5) ^ f.vertices.len() as u64;
    }
    h
}

/// Fragments per leaf of a sample's hierarchy. A hierarchy is built per split node and
/// queried by every candidate, so smaller leaves cost more levels to build and larger ones
/// more fragments placed per query: 16 gave the fewest instructions in total of the sizes tried
/// (BENCHMARKS.md, "Tuning constants").
const LEAF: usize = 16;

/// Fragments costed per candidate at most; bigger nodes are sampled.
pub const COST_SAMPLE: usize = 2000;

/// Weight of one cut against one fragment of imbalance.
pub const CUT_WEIGHT: u64 = 8;

/// The cost of `plane` on `frags`: `8·cuts + |front − back|` (a cut piece counts on both
/// sides, fragments in the plane on neither). Returns `u64::MAX` as soon as the cost is
/// proven to exceed `limit` (the cuts so far plus the imbalance the remaining fragments
/// cannot undo), which never changes which plane is cheapest.
#[cfg(test)]
pub fn cost(frags: &[&Fragment], plane: PlaneId, table: &PlaneTable, limit: u64) -> u64 {
    Sample::new(frags.iter().copied()).cost(plane, table, limit)
}

/// The fragments a node's candidates are costed on, with their vertices' f64 coordinates
/// flattened so that most sides are decided by one filtered dot product (the exact
/// predicate runs only when the filter cannot decide).
pub(crate) struct Sample<'a> {
    /// The fragments, in the order of `bvh`'s leaves (a node holds `first..end`).
    frags: Vec<&'a Fragment>,
    /// Vertex coordinates of all fragments, in order.
    coords: Vec<[f64; 3]>,
    /// `coords[ends[i - 1]..ends[i]]` are fragment `i`'s vertices.
    ends: Vec<u32>,
    /// Per fragment, its first four vertices as `[xs, ys, zs]` (a triangle repeats its last
    /// vertex), so that one branch-free pass places most fragments (see [`Sample::place`]);
    /// `None` for fragments with more vertices.
    quads: Vec<Option<[[f64; 4]; 3]>>,
    /// The fragments' boxes in a hierarchy: a plane counts a whole box at once on the side
    /// it proves the box on, and opens only the boxes it passes near (see [`Sample::tally`]).
    bvh: Bvh,
    /// The largest `|x| + |y| + |z|` of `coords`: with it one filter bound per plane holds for
    /// every vertex (see [`Sample::filter_bound`]).
    l1_max: f64,
}

impl<'a> Sample<'a> {
    pub(crate) fn new(frags: impl Iterator<Item = &'a Fragment>) -> Sample<'a> {
        let mut frags: Vec<&Fragment> = frags.collect();
        let bounds = |f: &&Fragment| box_of(f.vertices.iter().map(Vertex::approx));
        // The hierarchy puts the fragments in leaf order; the flat arrays follow it, so a leaf
        // reads one contiguous run of them.
        let bvh = Bvh::build(&mut frags, bounds, LEAF);
        let mut coords = Vec::with_capacity(frags.len() * 4);
        let mut ends = Vec::with_capacity(frags.len());
        let mut quads = Vec::with_capacity(frags.len());
        for f in &frags {
            let lo = coords.len();
            coords.extend(f.vertices.iter().map(Vertex::approx));
            ends.push(coords.len() as u32);
            quads.push(quad(&coords[lo..]));
        }
        let l1_max = l1_max(coords.iter());
        Sample {
            frags,
            coords,
            ends,
            quads,
            bvh,
            l1_max,
        }
    }

    /// Approximate coordinates of fragment `i`'s vertices.
    fn vertices(&self, i: usize) -> &[[f64; 3]] {
        let lo = if i == 0 { 0 } else { self.ends[i - 1] as usize };
        self.coords.get(lo..self.ends[i] as usize).unwrap_or(&[])
    }

    /// One f64 filter bound for `e` and every vertex of the sample (see
    /// [`shared_filter_bound`]).
    fn filter_bound(&self, e: &PlaneEntry) -> f64 {
        shared_filter_bound(e, self.l1_max)
    }

    /// [`Fragment::placement`] of fragment `i`, filtered with `bound` ([`Self::filter_bound`]):
    /// its first four vertices' filtered values place it when each is past `bound` (or two are
    /// past it on opposite sides); otherwise (a vertex within `bound` of the plane, or more
    /// than four vertices) the vertex loop decides with the exact predicate.
    ///
    /// `CALLER` only tells the callers apart: each gets its own copy, so the costing loop,
    /// the hottest of the build, keeps this inlined into it as when it was the only caller
    /// (a shared copy cost it instructions: BENCHMARKS.md, "Tuning constants").
    #[inline]
    fn place<const CALLER: u8>(
        &self,
        i: usize,
        plane: PlaneId,
        e: &PlaneEntry,
        bound: f64,
    ) -> Placement {
        if let Some([xs, ys, zs]) = &self.quads[i] {
            // Lane-wise over the four vertices, paired, so the compiler can use packed
            // arithmetic.
            let s: [f64; 4] =
                std::array::from_fn(|k| e.nf[0] * xs[k] + e.nf[1] * ys[k] + e.nf[2] * zs[k] - e.df);
            let lo = min_f(min_f(s[0], s[2]), min_f(s[1], s[3]));
            let hi = max_f(max_f(s[0], s[2]), max_f(s[1], s[3]));
            if hi > bound && lo < -bound {
                return Placement::Straddle;
            }
            if lo > bound {
                return Placement::Front;
            }
            if hi < -bound {
                return Placement::Back;
            }
        }
        // The vertex loop.
        let f = self.frags[i];
        if f.support == plane {
            return Placement::On;
        }
        Placement::of_sides(self.vertices(i).iter().zip(&f.vertices).map(|(c, v)| {
            let s = e.nf[0] * c[0] + e.nf[1] * c[1] + e.nf[2] * c[2] - e.df;
            if s > bound {
                Side::Front
            } else if s < -bound {
                Side::Back
            } else {
                v.side(e)
            }
        }))
    }

    /// See [`cost`].
    #[cfg(test)]
    pub(crate) fn cost(&self, plane: PlaneId, table: &PlaneTable, limit: u64) -> u64 {
        self.cost_with(SplitRule::default(), plane, table, limit)
    }

    /// `rule.cut_weight·cuts + rule.balance_weight·|front − back|`, `u64::MAX` once proven
    /// above `limit`.
    pub(crate) fn cost_with(
        &self,
        rule: SplitRule,
        plane: PlaneId,
        table: &PlaneTable,
        limit: u64,
    ) -> u64 {
        let over =
            |t: &Tally, left: u64| t.cuts * rule.cut_weight > limit || t.cost(rule, left) > limit;
        match self.tally(plane, table, over) {
            Some(t) if t.cost(rule, 0) <= limit => t.cost(rule, 0),
            _ => u64::MAX,
        }
    }

    /// The sample counted against `plane`; `None` as soon as `stop(count so far, fragments
    /// left)` holds (it is asked after each box counted whole and each leaf opened).
    pub(crate) fn tally(
        &self,
        plane: PlaneId,
        table: &PlaneTable,
        stop: impl Fn(&Tally, u64) -> bool,
    ) -> Option<Tally> {
        let e = table.get(plane);
        let bound = self.filter_bound(e);
        let m = self.bvh.margin(e);
        let nodes = &self.bvh.nodes;
        let mut tally = Tally::default();
        let mut left = self.frags.len() as u64;
        // Each level leaves at most one sibling on the stack.
        let mut stack = [0u32; crate::bvh::STACK];
        let mut len = usize::from(!nodes.is_empty());
        while len > 0 {
            len -= 1;
            let node = &nodes[stack[len] as usize];
            let (lo, hi) = Bvh::span(node, e);
            let k = u64::from(node.end - node.first);
            if lo > m {
                tally.front += k; // every vertex strictly in front: every fragment Front
            } else if hi < -m {
                tally.back += k;
            } else if let Some([l, r]) = node.children {
                stack[len] = l;
                stack[len + 1] = r;
                len += 2;
                continue;
            } else {
                for i in node.first as usize..node.end as usize {
                    tally.add(self.place::<COSTING>(i, plane, e, bound));
                }
            }
            left -= k;
            if stop(&tally, left) {
                return None;
            }
        }
        Some(tally)
    }

    /// The fragments in the order the searches number them.
    pub(crate) fn leaf_order(&self) -> &[&'a Fragment] {
        &self.frags
    }

    /// The fragments not wholly on the closed side opposite `small` of `plane` (as positions
    /// in [`Self::leaf_order`]), into `out` (cleared first), counted (no
    /// cuts); `None` as soon as there are more than `max` or one is cut. Boxes proven strictly
    /// on the far side are skipped whole; a box proven strictly on `small`'s side with too
    /// many fragments ends the search before any is placed (the usual answer when `small` is
    /// the side most fragments are on).
    ///
    /// The walk is written out as in [`Self::tally`] rather than shared: a shared walk made
    /// the compiler inline the costing loop worse (more of its instructions: BENCHMARKS.md,
    /// "Tuning constants"), and this search runs far less often.
    pub(crate) fn touched(
        &self,
        plane: PlaneId,
        small: Side,
        table: &PlaneTable,
        max: usize,
        out: &mut Vec<u32>,
    ) -> Option<Tally> {
        out.clear();
        let e = table.get(plane);
        let bound = self.filter_bound(e);
        let m = self.bvh.margin(e);
        let nodes = &self.bvh.nodes;
        let mut tally = Tally::default();
        let mut stack = [0u32; crate::bvh::STACK];
        let mut len = usize::from(!nodes.is_empty());
        while len > 0 {
            len -= 1;
            let node = &nodes[stack[len] as usize];
            let (lo, hi) = Bvh::span(node, e);
            let (beyond, near) = match small {
                Side::Front => (hi < -m, lo > m),
                _ => (lo > m, hi < -m),
            };
            if beyond {
                continue;
            }
            if near && out.len() + (node.end - node.first) as usize > max {
                return None;
            }
            if let Some([l, r]) = node.children {
                stack[len] = l;
                stack[len + 1] = r;
                len += 2;
                continue;
            }
            for i in node.first as usize..node.end as usize {
                let placement = self.place::<LOPSIDED>(i, plane, e, bound);
                match (placement, small) {
                    (Placement::Straddle, _) => return None,
                    (Placement::Front, Side::Back) | (Placement::Back, Side::Front) => continue,
                    _ => tally.add(placement),
                }
                out.push(i as u32);
                if out.len() > max {
                    return None;
                }
            }
        }
        Some(tally)
    }
}

/// [`Sample::place`] called from [`Sample::tally`].
const COSTING: u8 = 0;
/// [`Sample::place`] called from [`Sample::touched`].
const LOPSIDED: u8 = 1;

/// The first four of `coords` as `[xs, ys, zs]`, the last repeated when there are three (a
/// repeated vertex changes no placement); `None` beyond four.
fn quad(coords: &[[f64; 3]]) -> Option<[[f64; 4]; 3]> {
    if coords.is_empty() || coords.len() > 4 {
        return None;
    }
    let at = |k: usize| coords[k.min(coords.len() - 1)];
    Some([0, 1, 2].map(|c| [at(0)[c], at(1)[c], at(2)[c], at(3)[c]]))
}

/// Fragments counted against a plane: cut, and on each side (a cut piece counts on both
/// sides, a fragment in the plane on neither).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct Tally {
    cuts: u64,
    front: u64,
    back: u64,
}

impl Tally {
    /// Count one fragment.
    pub(crate) fn add(&mut self, placement: Placement) {
        match placement {
            Placement::Front => self.front += 1,
            Placement::Back => self.back += 1,
            Placement::On => {}
            Placement::Straddle => {
                self.cuts += 1;
                self.front += 1;
                self.back += 1;
            }
        }
    }

    /// `rule`'s cost of the count; with `left` fragments still to count, the least the final
    /// cost can be (they can only make up that much imbalance).
    pub(crate) fn cost(&self, rule: SplitRule, left: u64) -> u64 {
        self.cuts * rule.cut_weight
            + self.front.abs_diff(self.back).saturating_sub(left) * rule.balance_weight
    }
}

/// The weights of a split plane's cost.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SplitRule {
    /// Weight of one cut fragment.
    pub cut_weight: u64,
    /// Weight of one fragment of imbalance between the sides.
    pub balance_weight: u64,
}

impl Default for SplitRule {
    /// The build's rule: `8·cuts + |front − back|`.
    fn default() -> Self {
        SplitRule {
            cut_weight: CUT_WEIGHT,
            balance_weight: 1,
        }
    }
}

impl SplitRule {
    /// The greedy rule: the fewest cuts, balance ignored (ties to the smaller plane id).
    #[cfg(feature = "bench")]
    pub const FEWEST_CUTS: SplitRule = SplitRule {
        cut_weight: 1,
        balance_weight: 0,
    };
}

/// Choose the splitting plane among `planes` (the distinct support planes of `frags`, sorted):
/// the greedy rule (fewest cuts) weighed with balance, see [`cost`]. A plane that cuts nothing
/// (a free split: it adds no polygon) costs only its imbalance, so it wins whenever that
/// imbalance is below what the cheapest cutting plane costs; candidates are support planes
/// only, so every split also takes its plane's fragments out of both children (the
/// termination argument), and no plane is ever made up. At most `candidates`
/// planes are costed (a deterministic sample seeded from `seed` and the node's content when
/// there are more), each on at most [`COST_SAMPLE`] fragments. Ties go to the smaller id.
///
/// Candidates are costed in parallel for large nodes; a shared best-so-far only stops
/// candidates proven worse, so the minimum by `(cost, plane)` is the same on any thread count.
pub fn choose_split(
    frags: &[Fragment],
    planes: &[PlaneId],
    table: &PlaneTable,
    candidates: usize,
    seed: u64,
) -> PlaneId {
    choose_split_with(SplitRule::default(), frags, planes, table, candidates, seed)
}

/// [`choose_split`] with the cost weights of `rule`.
pub fn choose_split_with(
    rule: SplitRule,
    frags: &[Fragment],
    planes: &[PlaneId],
    table: &PlaneTable,
    candidates: usize,
    seed: u64,
) -> PlaneId {
    let mut rng = SplitMix::new(seed ^ content_hash(frags));
    let mut cands: Vec<PlaneId> = planes.to_vec();
    let k = candidates.max(1);
    if cands.len() > k {
        for i in 0..k {
            let j = i + rng.below(cands.len() - i);
            cands.swap(i, j);
        }
        cands.truncate(k);
        cands.sort_unstable();
    }
    let sample = if frags.len() > COST_SAMPLE {
        Sample::new((0..COST_SAMPLE).map(|_| &frags[rng.below(frags.len())]))
    } else {
        Sample::new(frags.iter())
    };
    let best_so_far = AtomicU64::new(u64::MAX);
    let costed = |&p: &PlaneId| {
        let c = sample.cost_with(rule, p, table, best_so_far.load(Ordering::Relaxed));
        best_so_far.fetch_min(c, Ordering::Relaxed);
        (c, p)
    };
    let best = if sample.frags.len() * cands.len() > 20_000 {
        cands.par_iter().map(costed).min()
    } else {
        cands.iter().map(costed).min()
    };
    best.map(|(_, p)| p).unwrap_or(planes[0])
}

/// The fragment of triangle `q` (its edge planes through the support's normal direction), as
/// the input stage makes it; `None` when degenerate. For tests of the modules that cut and peel.
#[cfg(test)]
pub(crate) fn triangle_fragment(table: &mut PlaneTable, q: [[i32; 3]; 3]) -> Option<Fragment> {
    let (plane, flipped) = crate::planes::Plane::through(q[0], q[1], q[2])?;
    let support = table.insert(plane);
    let edges = (0..3)
        .map(|k| {
            let e = crate::planes::edge_plane(q[k], q[(k + 1) % 3], plane.n);
            Edge {
                plane: table.insert(e),
                inside: e.side_of_point(q[(k + 2) % 3]),
            }
        })
        .collect();
    Some(Fragment {
        source: 0,
        support,
        flipped,
        vertices: q.map(Vertex::Int).to_vec(),
        edges,
    })
}

#[cfg(test)]
mod tests;
