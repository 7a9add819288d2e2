//! Node bounding boxes: the box of every vertex of a subtree's polygons, which lets the runtime
//! skip a subtree outside the view frustum or (front to back) already covered on screen.
//!
//! Which nodes get a box (the others store `NONE`, and the runtime simply enters them):
//! - none at all in a tree of a single node: its box is the header's scene bounds;
//! - the root always (a frame that sees none of the scene then draws nothing);
//! - not a leaf convex node with fewer than [`MIN_LEAF_POLYGONS`] polygons: testing 8 box
//!   corners costs about as much as rejecting that few polygons in the clipper;
//! - not a node whose box equals its parent's: the parent's test already gave the answer.
//!
//! A stored box is quantised outward to 65535 steps per axis of the scene's bounds (12 bytes
//! instead of 24 of `f32`): [`quantise`] rounds each corner through the runtime's own decoder,
//! so the box the runtime reads still contains every vertex of the subtree as the runtime reads
//! it (for vertices stored as steps, the box is exactly their steps' box). Equal
//! (quantised) boxes are stored once.

use rayon::prelude::*;

use crate::hash::FastMap;

use peel_runtime::read::layout::dequantise;

use super::format::{node_kind, Node, Polygon, NONE};

/// Leaf convex nodes with fewer polygons than this get no box.
pub const MIN_LEAF_POLYGONS: u32 = 4;

/// `[min xyz, max xyz]`.
type Box3 = [f32; 6];

fn union(a: Option<Box3>, b: Option<Box3>) -> Option<Box3> {
    match (a, b) {
        (Some(a), Some(b)) => Some([
            a[0].min(b[0]),
            a[1].min(b[1]),
            a[2].min(b[2]),
            a[3].max(b[3]),
            a[4].max(b[4]),
            a[5].max(b[5]),
        ]),
        (a, None) => a,
        (None, b) => b,
    }
}

fn point(v: [f32; 3]) -> Box3 {
    [v[0], v[1], v[2], v[0], v[1], v[2]]
}

/// The box of each node's subtree (`None` for a subtree without polygons). `nodes` must be in
/// pre-order (children after their parent) and its links in range, as the writer emits them.
pub fn node_bounds(
    vertices: &[[f32; 3]],
    indices: &[u32],
    polygons: &[Polygon],
    nodes: &[Node],
) -> Vec<Option<Box3>> {
    // Each convex node's own polygons (independent: in parallel), then the subtrees from the
    // last node back.
    let own: Vec<Option<Box3>> = nodes
        .par_iter()
        .map(|n| {
            let mut b = None;
            if n.kind == node_kind::CONVEX {
                let owned = polygons.iter().skip(n.a as usize).take(n.b as usize);
                for p in owned {
                    let first = p.first_index as usize;
                    for &v in indices.iter().skip(first).take(usize::from(p.vertex_count)) {
                        b = union(b, vertices.get(v as usize).map(|&v| point(v)));
                    }
                }
            }
            b
        })
        .collect();
    let mut boxes: Vec<Option<Box3>> = vec![None; nodes.len()];
    let child_box = |boxes: &[Option<Box3>], c: u32| {
        if c == NONE {
            None
        } else {
            boxes.get(c as usize).copied().flatten()
        }
    };
    for i in (0..nodes.len()).rev() {
        let n = nodes[i];
        let b = if n.kind == node_kind::CONVEX {
            own[i]
        } else {
            child_box(&boxes, n.b)
        };
        boxes[i] = union(b, child_box(&boxes, n.c));
    }
    boxes
}

/// A quantised box: per axis, steps from the scene's lower to its upper bound.
pub type QuantisedBox = [u16; 6];

/// The smallest quantised box whose decoded corners (`dequantise` on `lo`, `hi`) contain `b`.
/// `b` must lie inside `lo ..= hi` (the scene's bounds), whose ends decode exactly.
pub fn quantise(b: Box3, lo: [f32; 3], hi: [f32; 3]) -> QuantisedBox {
    let mut q = [0u16; 6];
    for k in 0..3 {
        let (l, h) = (lo[k], hi[k]);
        let step = |v: f32| {
            let t = if h > l {
                f64::from(v - l) / f64::from(h - l)
            } else {
                0.0
            };
            (t * 65535.0).clamp(0.0, 65535.0)
        };
        // A first guess, then outward until the decoded value contains the coordinate, and
        // inward while it still does (a vertex on a step gets that very step).
        let mut min = step(b[k]).floor() as u16;
        while min > 0 && dequantise(l, h, min) > b[k] {
            min -= 1;
        }
        while min < u16::MAX && dequantise(l, h, min + 1) <= b[k] {
            min += 1;
        }
        let mut max = step(b[k + 3]).ceil() as u16;
        while max < u16::MAX && dequantise(l, h, max) < b[k + 3] {
            max += 1;
        }
        while max > 0 && dequantise(l, h, max - 1) >= b[k + 3] {
            max -= 1;
        }
        q[k] = min;
        q[k + 3] = max;
    }
    q
}

/// Sets each node's `bounds` field by the rule of the module docs and returns the boxes to
/// store (quantised on the scene's bounds `lo`, `hi`), or `None` when the file stores none (a
/// single node).
pub fn assign(
    nodes: &mut [Node],
    boxes: &[Option<Box3>],
    lo: [f32; 3],
    hi: [f32; 3],
) -> Option<Vec<QuantisedBox>> {
    if nodes.len() < 2 {
        return None;
    }
    let boxes: Vec<Option<QuantisedBox>> = boxes
        .iter()
        .map(|b| b.map(|b| quantise(b, lo, hi)))
        .collect();
    let mut stored = Vec::new();
    let mut slots: FastMap<QuantisedBox, u32> = FastMap::default();
    for (i, node) in nodes.iter_mut().enumerate() {
        let n = *node;
        let Some(b) = boxes.get(i).copied().flatten() else {
            continue;
        };
        let small_leaf = n.kind == node_kind::CONVEX && n.c == NONE && n.b < MIN_LEAF_POLYGONS;
        let parent_box = boxes.get(n.parent as usize).copied().flatten();
        let keep = i == 0 || !(small_leaf || parent_box == Some(b));
        if keep {
            let slot = *slots.entry(b).or_insert_with(|| {
                stored.push(b);
                (stored.len() - 1) as u32
            });
            node.bounds = slot;
        }
    }
    Some(stored)
}
