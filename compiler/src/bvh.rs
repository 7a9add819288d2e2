//! A bounding-volume hierarchy over f64 boxes, for the questions "which items lie strictly on
//! one side of this plane?" that the hull test (points) and the choice of the split plane
//! (fragments) ask many times of the same set. A box proven strictly on one side of a plane
//! (by [`Bvh::span`], with [`Bvh::margin`] far above the rounding of the approximate
//! coordinates) answers for every item in it at once; only the boxes the plane passes near
//! are opened.

use crate::planes::PlaneEntry;

/// Extra safety factor on the f64 box bounds, relative to the magnitudes involved (on top of
/// [`crate::planes::FILTER_BOUND`], which bounds the error of one approximate coordinate).
const BOX_MARGIN: f64 = 1.0 / (1u64 << 40) as f64;

/// Most levels of a hierarchy: a node this deep is a leaf, however many items it holds (only
/// inputs far beyond any real scene's size get there). A search's stack then fits a small
/// array: one entry per level plus one. (Zeroing a stack sized for any `u32` count at every
/// search cost a measurable part of a compile: BENCHMARKS.md, "Tuning constants".)
const MAX_LEVELS: u32 = 31;

/// Stack entries a depth-first search of any hierarchy needs.
pub(crate) const STACK: usize = MAX_LEVELS as usize + 1;

/// `acc.min(v)` for an accumulator that is never NaN: one `minsd`, where `f64::min`'s NaN
/// handling costs several instructions in the hottest loops. A NaN `v` is ignored, as there.
#[inline(always)]
pub(crate) fn min_f(acc: f64, v: f64) -> f64 {
    if v < acc {
        v
    } else {
        acc
    }
}

/// `acc.max(v)`, as [`min_f`].
#[inline(always)]
pub(crate) fn max_f(acc: f64, v: f64) -> f64 {
    if v > acc {
        v
    } else {
        acc
    }
}

/// The box `(min, max)` of `points` (infinite and empty when there are none).
pub(crate) fn box_of(points: impl Iterator<Item = [f64; 3]>) -> ([f64; 3], [f64; 3]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for c in points {
        for k in 0..3 {
            lo[k] = min_f(lo[k], c[k]);
            hi[k] = max_f(hi[k], c[k]);
        }
    }
    (lo, hi)
}

/// Reorder `centres` (at least 2) into two non-empty parts and return the length of the first:
/// split at the middle of the axis of widest spread, or at the median along it when that
/// leaves less than a quarter on one side.
fn split(centres: &mut [([f64; 3], u32)]) -> usize {
    let (lo, hi) = box_of(centres.iter().map(|&(c, _)| c));
    let axis = (0..3)
        .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
        .unwrap_or(0);
    let middle = 0.5 * (lo[axis] + hi[axis]);
    // Partition in place: items below the middle first.
    let mut below = 0;
    for i in 0..centres.len() {
        if centres[i].0[axis] < middle {
            centres.swap(i, below);
            below += 1;
        }
    }
    let n = centres.len();
    if below >= n.div_ceil(4) && n - below >= n.div_ceil(4) {
        return below;
    }
    let mid = n / 2;
    centres.select_nth_unstable_by(mid, |a, b| a.0[axis].total_cmp(&b.0[axis]));
    mid
}

/// A node: the box of its items, their range in the reordered item list, its children.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BvhNode {
    /// Box corners.
    pub min: [f64; 3],
    /// Box corners.
    pub max: [f64; 3],
    /// The node's items are `items[first..end]`.
    pub first: u32,
    /// See `first`.
    pub end: u32,
    /// Children (node indices), `None` for a leaf.
    pub children: Option<[u32; 2]>,
}

/// The hierarchy; node 0 is the root (none when there are no items).
#[derive(Debug, Clone, Default)]
pub(crate) struct Bvh {
    pub nodes: Vec<BvhNode>,
}

impl Bvh {
    /// Build over `items`, reordering them so that every node's items are contiguous; `bounds`
    /// gives an item's box (asked once per item), `leaf` the most items a leaf holds. Each
    /// node splits its items' box centres at the middle of the axis they spread most on (one
    /// pass), or at their median along it when the middle leaves less than a quarter on one
    /// side, so the depth grows as the logarithm of the count (and stops at [`MAX_LEVELS`]).
    /// Boxes are merged bottom-up. (Hierarchies are built for most nodes of the tree, so their
    /// build cost counts.)
    pub fn build<T: Clone>(
        items: &mut [T],
        bounds: impl Fn(&T) -> ([f64; 3], [f64; 3]),
        leaf: usize,
    ) -> Bvh {
        let leaf = leaf.max(1);
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * items.len() / leaf + 1),
        };
        if items.is_empty() {
            return bvh;
        }
        let boxes: Vec<([f64; 3], [f64; 3])> = items.iter().map(&bounds).collect();
        let mut centres: Vec<([f64; 3], u32)> = boxes
            .iter()
            .enumerate()
            .map(|(i, (a, b))| ([a[0] + b[0], a[1] + b[1], a[2] + b[2]], i as u32))
            .collect();
        bvh.node(&mut centres, 0, &boxes, leaf, 1);
        let sorted: Vec<T> = centres
            .iter()
            .map(|&(_, i)| items[i as usize].clone())
            .collect();
        items.clone_from_slice(&sorted);
        bvh
    }

    /// The node over `centres` (items `first..` of the final order; `boxes` by item index)
    /// and its subtree, reordering `centres`; returns its index.
    fn node(
        &mut self,
        centres: &mut [([f64; 3], u32)],
        first: usize,
        boxes: &[([f64; 3], [f64; 3])],
        leaf: usize,
        level: u32,
    ) -> u32 {
        let id = self.nodes.len();
        let n = centres.len();
        self.nodes.push(BvhNode {
            min: [f64::INFINITY; 3],
            max: [f64::NEG_INFINITY; 3],
            first: first as u32,
            end: (first + n) as u32,
            children: None,
        });
        let (mut min, mut max) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let mut add = |lo: &[f64; 3], hi: &[f64; 3]| {
            for k in 0..3 {
                min[k] = min_f(min[k], lo[k]);
                max[k] = max_f(max[k], hi[k]);
            }
        };
        if n > leaf && level < MAX_LEVELS {
            let mid = split(centres);
            let (left, right) = centres.split_at_mut(mid);
            let l = self.node(left, first, boxes, leaf, level + 1);
            let r = self.node(right, first + mid, boxes, leaf, level + 1);
            for c in [l, r] {
                let c = self.nodes[c as usize];
                add(&c.min, &c.max);
            }
            self.nodes[id].children = Some([l, r]);
        } else {
            for &(_, i) in centres.iter() {
                let (lo, hi) = &boxes[i as usize];
                add(lo, hi);
            }
        }
        self.nodes[id].min = min;
        self.nodes[id].max = max;
        id as u32
    }

    /// The margin of every [`Bvh::span`] of this hierarchy for plane `e`: every point of a
    /// node's box (and every item whose approximate coordinates are in it) has its exact
    /// value of `n·p − d` in `lo − margin ..= hi + margin`. It is relative to the largest
    /// magnitudes of the whole hierarchy (the root's box), which bound each node's own, so one
    /// margin per query serves every node (a node's own magnitudes would prune the same boxes
    /// but for a 2^-40 sliver, at several more operations per box).
    pub fn margin(&self, e: &PlaneEntry) -> f64 {
        let Some(root) = self.nodes.first() else {
            return 0.0;
        };
        let mut m = e.df.abs();
        for k in 0..3 {
            m += e.nf[k].abs() * max_f(root.min[k].abs(), root.max[k].abs());
        }
        m * BOX_MARGIN
    }

    /// Range `(lo, hi)` of `n·p − d` over `node`'s box, up to [`Bvh::margin`].
    #[inline]
    pub fn span(node: &BvhNode, e: &PlaneEntry) -> (f64, f64) {
        let (mut lo, mut hi) = (-e.df, -e.df);
        for k in 0..3 {
            let (a, b) = (e.nf[k] * node.min[k], e.nf[k] * node.max[k]);
            lo += min_f(a, b);
            hi += max_f(a, b);
        }
        (lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Every node's box holds its items; leaves hold at most `leaf`; children split the
        /// parent's range in two, each with at least a quarter of it.
        #[test]
        fn boxes_hold_their_items(
            pts in proptest::collection::vec([-1e3f64..1e3, -1e3f64..1e3, -1e3f64..1e3], 0..300),
            leaf in 1usize..10,
            skew in any::<bool>(),
        ) {
            // Skewed points crowd near 0 with a few far out: the middle split is lopsided there.
            let pts: Vec<[f64; 3]> = if skew {
                pts.iter().map(|p| p.map(|c| c.powi(9) * 1e-24)).collect()
            } else {
                pts
            };
            let mut items = pts.clone();
            let bvh = Bvh::build(&mut items, |p| (*p, *p), leaf);
            prop_assert_eq!(bvh.nodes.is_empty(), pts.is_empty());
            for node in &bvh.nodes {
                for p in &items[node.first as usize..node.end as usize] {
                    for (k, &c) in p.iter().enumerate() {
                        prop_assert!(node.min[k] <= c && c <= node.max[k]);
                    }
                }
                match node.children {
                    None => prop_assert!((node.end - node.first) as usize <= leaf),
                    Some([l, r]) => {
                        let (l, r) = (bvh.nodes[l as usize], bvh.nodes[r as usize]);
                        prop_assert_eq!((l.first, l.end, r.end), (node.first, r.first, node.end));
                        // At least a quarter on each side: the depth grows as the log of the count.
                        let n = node.end - node.first;
                        prop_assert!(4 * (l.end - l.first) >= n && 4 * (r.end - r.first) >= n);
                    }
                }
            }
            let mut sorted = items.clone();
            let mut want = pts.clone();
            sorted.sort_by(|a, b| a.partial_cmp(b).unwrap());
            want.sort_by(|a, b| a.partial_cmp(b).unwrap());
            prop_assert_eq!(sorted, want);
        }

        /// What a span proves with the hierarchy's margin holds exactly: a box proven strictly
        /// on one side holds only grid points strictly on that side, for planes through three
        /// of the points (so that some points lie exactly on them), up to the grid's 2^26.
        #[test]
        fn spans_prove_exact_sides(
            pts in proptest::collection::vec(
                proptest::array::uniform3(-(1i32 << 26) + 1..1i32 << 26),
                3..200,
            ),
            small in any::<bool>(),
            leaf in 1usize..8,
            picks in proptest::collection::vec((0usize..200, 0usize..200, 0usize..200), 1..8),
        ) {
            use crate::planes::{Plane, PlaneTable, Side};
            // Small coordinates crowd the points near the planes.
            let pts: Vec<[i32; 3]> = if small {
                pts.iter().map(|p| p.map(|c| c >> 20)).collect()
            } else {
                pts
            };
            let mut items: Vec<([f64; 3], [i32; 3])> =
                pts.iter().map(|p| (p.map(f64::from), *p)).collect();
            let bvh = Bvh::build(&mut items, |&(c, _)| (c, c), leaf);
            for (a, b, c) in picks {
                let mut table = PlaneTable::default();
                let n = pts.len();
                let Some((plane, _)) = Plane::through(pts[a % n], pts[b % n], pts[c % n]) else {
                    continue;
                };
                let id = table.insert(plane);
                let e = table.get(id);
                let m = bvh.margin(e);
                for node in &bvh.nodes {
                    let (lo, hi) = Bvh::span(node, e);
                    for &(_, p) in &items[node.first as usize..node.end as usize] {
                        let side = e.plane.side_of_point(p);
                        if lo > m {
                            prop_assert_eq!(side, Side::Front);
                        }
                        if hi < -m {
                            prop_assert_eq!(side, Side::Back);
                        }
                    }
                }
            }
        }
    }
}
