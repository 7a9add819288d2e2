//! The choice of the splitting plane: candidates costed (cuts weighed with balance) on a sample
//! of the node's fragments, whose bounding-volume hierarchy places most of them a box at a time.

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use super::{Fragment, Placement};
use crate::bvh::{box_of, max_f, min_f, Bvh};
use crate::planes::{l1_max, shared_filter_bound, PlaneEntry, PlaneId, PlaneTable, Side, Vertex};
use crate::random::SplitMix;

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

/// Lists of at most this many fragments cost every candidate plane rather than a sample of
/// [`crate::tree::BuildOptions::candidates`]: most cuts are made in small lists (two thirds
/// of the cow's in lists of at most 256 fragments), and there a sample often misses the best
/// support or edge plane (cow 1.540 and suzanne 1.536 polygons per triangle against 1.581 and
/// 1.653; BENCHMARKS.md, "Edge splits"). The bound keeps a node's costing bounded, so a large
/// mesh pays it per node as a small one does.
pub const COST_ALL: usize = 2048;

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
        self.tally_entry(plane, table.get(plane), stop)
    }

    /// The sample counted against a plane that is no support plane of it (a free split's
    /// candidate, [`super::free`]); `None` as soon as it cuts a fragment.
    pub(crate) fn tally_free(&self, e: &PlaneEntry) -> Option<Tally> {
        // No fragment's support has the id `PlaneId::MAX` (the table holds fewer planes).
        self.tally_entry(PlaneId::MAX, e, |t, _| t.cuts > 0)
    }

    /// [`Self::tally`] of the plane `e` (whose id is `plane`).
    fn tally_entry(
        &self,
        plane: PlaneId,
        e: &PlaneEntry,
        stop: impl Fn(&Tally, u64) -> bool,
    ) -> Option<Tally> {
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
    pub(super) cuts: u64,
    pub(super) front: u64,
    pub(super) back: u64,
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

/// The support plane [`choose_split_costed`] chooses with the cost weights of `rule`.
#[cfg(feature = "bench")]
pub fn choose_split_with(
    rule: SplitRule,
    frags: &[Fragment],
    planes: &[PlaneId],
    table: &PlaneTable,
    candidates: usize,
    seed: u64,
) -> PlaneId {
    choose_split_costed(rule, frags, planes, table, candidates, seed).plane
}

/// The plane [`choose_split_costed`] chose, with its cost on the sample.
pub struct Choice<'a> {
    /// The plane.
    pub plane: PlaneId,
    /// Its cost on the sample (`u64::MAX` when no candidate was costed).
    pub cost: u64,
    /// The sample's fragments it cuts.
    pub cuts: u64,
    /// Fragments in the sample.
    pub sampled: usize,
    /// The sample it was costed on.
    pub(crate) sample: Sample<'a>,
    /// The sample is the whole list (at most [`COST_SAMPLE`] fragments).
    pub(crate) whole: bool,
    /// The list's [`content_hash`].
    hash: u64,
}

/// Choose the splitting plane among `planes` (the distinct support planes of `frags`, sorted)
/// by `rule`: the build's is the greedy rule (fewest cuts) weighed with balance, see [`cost`].
/// A plane that cuts nothing (a free split: it adds no polygon) costs only its imbalance, so
/// it wins whenever that imbalance is below what the cheapest cutting plane costs; candidates
/// are support planes, so every split by one also takes its plane's fragments out of both
/// children (the termination argument). The build weighs the result against a free split by a
/// plane that is not a support plane ([`super::free`]) and against the edge plane this same
/// choice finds among `planes` = the list's edge planes ([`super::edge`]), hence the cost and
/// the cuts. At most `candidates` planes are costed (a deterministic sample seeded from `seed`
/// and the node's content when there are more), each on at most [`COST_SAMPLE`] fragments.
/// Ties go to the smaller id.
///
/// Candidates are costed in parallel for large nodes, with the same answer on any thread count
/// (see [`cheapest`]).
pub fn choose_split_costed<'a>(
    rule: SplitRule,
    frags: &'a [Fragment],
    planes: &[PlaneId],
    table: &PlaneTable,
    candidates: usize,
    seed: u64,
) -> Choice<'a> {
    let hash = content_hash(frags);
    let mut rng = SplitMix::new(seed ^ hash);
    let cands = pick(planes, candidates, &mut rng);
    let sample = if frags.len() > COST_SAMPLE {
        Sample::new((0..COST_SAMPLE).map(|_| &frags[rng.below(frags.len())]))
    } else {
        Sample::new(frags.iter())
    };
    let (cost, plane) =
        cheapest(&sample, rule, &cands, table, u64::MAX).unwrap_or((u64::MAX, planes[0]));
    let cuts = sample
        .tally(plane, table, |_, _| false)
        .map_or(0, |t| t.cuts);
    Choice {
        plane,
        cost,
        cuts,
        sampled: sample.frags.len(),
        whole: frags.len() <= COST_SAMPLE,
        sample,
        hash,
    }
}

impl Choice<'_> {
    /// The plane of least cost among `planes` (none of them need be a support plane), costed
    /// by `rule` on this choice's sample, if that cost is at most `limit`: as
    /// [`choose_split_costed`] (at most `candidates` of them, sampled from `seed` and the
    /// list's content), but every candidate is dropped as soon as it is proven above `limit`,
    /// which changes no answer below it.
    pub fn cheapest_below(
        &self,
        rule: SplitRule,
        planes: &[PlaneId],
        table: &PlaneTable,
        candidates: usize,
        seed: u64,
        limit: u64,
    ) -> Option<(PlaneId, u64)> {
        let mut rng = SplitMix::new(seed ^ self.hash);
        let cands = pick(planes, candidates, &mut rng);
        cheapest(&self.sample, rule, &cands, table, limit).map(|(c, p)| (p, c))
    }
}

/// At most `candidates` of `planes` (all when there are no more), a deterministic sample drawn
/// from `rng`, sorted.
fn pick(planes: &[PlaneId], candidates: usize, rng: &mut SplitMix) -> Vec<PlaneId> {
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
    cands
}

/// The least `(cost, plane)` of `cands` on `sample` by `rule`, if one costs at most `limit`.
/// Candidates are costed in parallel for large samples; a shared best-so-far only stops
/// candidates proven worse, so the answer is the same on any thread count.
fn cheapest(
    sample: &Sample,
    rule: SplitRule,
    cands: &[PlaneId],
    table: &PlaneTable,
    limit: u64,
) -> Option<(u64, PlaneId)> {
    let best_so_far = AtomicU64::new(limit);
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
    best.filter(|&(c, _)| c != u64::MAX)
}
