//! Exact tree -> [`DisplayTree`]: the last step of the build. Each stage has its own module:
//!
//! 1. [`vertices`]: one id per exact point (merged), with its f64 approximation;
//! 2. [`line_keys`] and [`watertight`]: T-junctions closed, so the rounded output has no cracks;
//! 3. [`convex_split`]: polygons with too many vertices cut into convex pieces;
//! 4. [`numbering`]: planes, vertices and polygons numbered in order of first use (in f64,
//!    relative to the centre), and the statistics.

use super::build::ExactTree;
use super::input::Input;
use super::{BuildOptions, DisplayTree};
use crate::split::Fragment;

mod convex_split;
mod line_keys;
mod numbering;
mod vertices;
mod watertight;

/// The display tree of `exact` (built from `input` with `options`).
pub(crate) fn to_display(exact: &ExactTree, input: &Input, options: &BuildOptions) -> DisplayTree {
    let frags: Vec<&Fragment> = exact.polygons.iter().map(|p| &p.frag).collect();
    let mut offsets = Vec::with_capacity(frags.len() + 1);
    offsets.push(0usize);
    for f in &frags {
        offsets.push(offsets.last().copied().unwrap_or(0) + f.vertices.len());
    }
    // The edges' line keys do not depend on the vertex numbering: they are computed alongside
    // its sequential stretches.
    let ((vertices, ids), keys) = rayon::join(
        || vertices::Vertices::of(&frags, &offsets),
        || {
            if options.watertight {
                line_keys::edge_keys(&frags, input)
            } else {
                Vec::new()
            }
        },
    );
    let boundaries = if options.watertight {
        watertight::watertight(&frags, input, &vertices, &ids, &offsets, &keys)
    } else {
        (offsets.windows(2))
            .map(|w| watertight::plain_boundary(&ids[w[0]..w[1]]))
            .collect()
    };
    // The wide keys are boxed: freed on an idle worker.
    rayon::spawn(move || drop(keys));
    let pieces = convex_split::split_large(&boundaries, options.max_polygon_vertices);
    numbering::number(exact, input, &vertices, &boundaries, &pieces)
}
