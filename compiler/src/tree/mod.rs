//! Tree: the display-tree build, its statistics and invariants.
//!
//! A fragment list becomes a convex node when some of its support planes lie on its convex
//! hull: the fragments on them enclose the rest, and are drawn before or after it depending on
//! which side of each the eye is. Otherwise the list is split by one of its support planes, as
//! in Fuchs, Kedem and Naylor's BSP trees, by a *free* plane: a plane through grid vertices
//! of the list that is none of its support planes and cuts none of its fragments
//! (`split::free`), or by an *edge* plane: the table plane of one of its fragments' edges, none
//! of its support planes, which may cut but has some fragment wholly on each side
//! (`split::edge`). What remains is built the same way.
//!
//! Why the build ends: take the pair (distinct support planes, fragments) of a list, ordered
//! lexicographically. A convex node's child has fewer support planes (the node took every
//! fragment of at least one). A split by a support plane P gives P's fragments to a convex
//! node of them alone, and no other child holds one, so the other lists have fewer support
//! planes (cuts add fragments, never planes); the convex node's own child has fewer too. A free
//! or an edge split is by a plane that holds no fragment, so it adds no support plane (cuts add
//! fragments, never planes); each side lacks the fragments lying wholly on the other, of which
//! there is at least one, so each child has no more support planes and fewer fragments. Every
//! step drops the pair, which cannot drop forever. The build checks the drop on every node
//! (`CompileError::Invariant`, never a hang).
//!
//! `build` turns a [`Mesh`] into a [`DisplayTree`]. Everything in the `DisplayTree` is
//! relative to `centre` (the quantisation offset), in world units, f64.

use glam::DVec3;

use crate::error::CompileError;
use crate::load::Mesh;

pub(crate) mod build;
mod check;
pub(crate) mod input;
pub(crate) mod output;
#[doc(hidden)]
pub use check::verify;
#[cfg(test)]
mod tests;

/// Knobs of the build.
#[derive(Debug, Clone)]
pub struct BuildOptions {
    /// At most this many candidate planes are costed per split node of more than 2,048
    /// fragments (sampled deterministically from `seed` when there are more); smaller nodes
    /// cost every plane.
    pub candidates: usize,
    /// Seed of the candidate sampling.
    pub seed: u64,
    /// Output polygons with more vertices are split into convex pieces.
    pub max_polygon_vertices: usize,
    /// Close T-junctions (see the watertight pass of the output). Always on in the CLI; off
    /// only to show the cracks it prevents (the stress suite's control test). Hidden from the
    /// docs, not private: that test is in another crate (`tests/stress.rs`), and a file built
    /// without it may show cracks, so no user should turn it off.
    #[doc(hidden)]
    pub watertight: bool,
    /// Cut polygons along the shadows the mesh casts from this light; each piece is then lit
    /// or in shadow ([`TreePolygon::shadowed`]). `None`: no shadows.
    pub shadows: Option<crate::shadow::Light>,
}

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions {
            candidates: 64,
            seed: 0,
            max_polygon_vertices: 12,
            watertight: true,
            shadows: None,
        }
    }
}

/// A plane `normal · p = offset` relative to [`DisplayTree::centre`]; `normal` has unit length
/// and the sign of the canonical integer plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreePlane {
    /// Unit normal.
    pub normal: DVec3,
    /// Offset along the normal.
    pub offset: f64,
}

/// One output polygon (a convex fragment of one source triangle).
#[derive(Debug, Clone, PartialEq)]
pub struct TreePolygon {
    /// Index into [`DisplayTree::planes`] of its support plane.
    pub plane: u32,
    /// True when the source triangle's front normal is opposite to the plane's normal.
    pub flipped: bool,
    /// True when the rest of its convex set lies on the + side of the plane (the "inside").
    pub interior_front: bool,
    /// Indices into [`DisplayTree::vertices`], in the source triangle's winding order.
    pub vertices: Vec<u32>,
    /// Source triangle id.
    pub source: u32,
    /// In the shadow of another source triangle: both sides get the ambient colour.
    pub shadowed: bool,
}

impl TreePolygon {
    /// Whether its interior side (the side of the rest of its convex set) is its source
    /// triangle's back.
    pub fn interior_is_back(&self) -> bool {
        self.interior_front == self.flipped
    }
}

/// A node of the display tree. Children always have larger indices than their parent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TreeNode {
    /// A convex set: polygons `first_polygon .. first_polygon + polygon_count`, then a child.
    Convex {
        /// First polygon of the set.
        first_polygon: u32,
        /// Number of polygons of the set (>= 1).
        polygon_count: u32,
        /// What lies inside the set.
        child: Option<u32>,
        /// Distinct support planes of the list this node was built from.
        support_planes: u32,
    },
    /// A separating plane.
    Split {
        /// Index into [`DisplayTree::planes`].
        plane: u32,
        /// Subtree on the + side.
        front: Option<u32>,
        /// Subtree on the - side.
        back: Option<u32>,
        /// Distinct support planes of the list this node was built from.
        support_planes: u32,
    },
}

/// Counters reported by `peel compile`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TreeStats {
    /// Triangles read.
    pub input_triangles: u64,
    /// Triangles of zero area after quantisation, dropped.
    pub degenerate_dropped: u64,
    /// Polygons in the output.
    pub output_polygons: u64,
    /// Convex nodes.
    pub convex_nodes: u64,
    /// Split nodes.
    pub split_nodes: u64,
    /// Fragments cut in two.
    pub cuts: u64,
    /// Nodes on the longest root-to-leaf path.
    pub max_depth: u64,
    /// Distinct planes in the output.
    pub planes: u64,
}

/// The compiled display tree, before serialisation.
#[derive(Debug, Clone, Default)]
pub struct DisplayTree {
    /// World position of the origin of every coordinate below.
    pub centre: DVec3,
    /// Distinct vertices, relative to `centre`.
    pub vertices: Vec<DVec3>,
    /// Distinct planes used by polygons and splits.
    pub planes: Vec<TreePlane>,
    /// Polygons; each convex node owns a contiguous range.
    pub polygons: Vec<TreePolygon>,
    /// Nodes in pre-order; the root is node 0 (absent when the tree is empty).
    pub nodes: Vec<TreeNode>,
    /// Counters.
    pub stats: TreeStats,
}

/// Build the display tree of `mesh`. `progress` is called from time to time with the number
/// of fragments placed in convex nodes so far (for a progress bar).
///
/// Deterministic: the same mesh and options give the same tree, whatever the thread count.
pub(crate) fn build(
    mesh: &Mesh,
    options: &BuildOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<DisplayTree, CompileError> {
    let input = input::prepare(mesh, options.shadows)?;
    let exact = build::build_exact(&input, options, progress)?;
    let tree = output::to_display(&exact, &input, options);
    // Freeing the exact tree (millions of small allocations) overlaps the caller's next steps
    // on an idle worker.
    rayon::spawn(move || drop((exact, input)));
    Ok(tree)
}

/// The quantisation transform [`build`] uses for `mesh` (`centre` is its `offset`).
#[cfg(test)]
pub(crate) fn quantisation(mesh: &Mesh) -> crate::quantise::Quantiser {
    crate::quantise::Quantiser::fit(mesh)
}
