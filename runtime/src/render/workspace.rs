//! The memory of a frame: [`Workspace`], fixed-size buffers the caller owns (the traversal
//! stack, clip buffers, snapped points, edge walks). It exists apart because it is the one
//! thing a caller must size (from the tree's depth and largest polygon) and place (on the
//! heap, or in a `static` on firmware); a [`Renderer`](super::Renderer) borrows it.

use glam::Vec3;

use crate::fill::{self, FixedPoint};
use crate::traverse::StackEntry;

/// The memory of a frame, fixed-size: a traversal stack of `STACK` entries (at least the
/// tree's `max_depth`) and clip buffers of `VERTS` vertices (at least the largest polygon
/// plus [`clip::CLIP_PLANES`], and at most [`fill::MAX_FILL_VERTICES`] are used), whose
/// snapped points are [`FixedPoint<SUB>`]s: a [`Renderer`](super::Renderer) of the same
/// precision borrows it (the default, [`fill::SUBPIXEL_BITS`], is [`Renderer::new`]'s).
///
/// [`clip::CLIP_PLANES`]: crate::clip::CLIP_PLANES
/// [`Renderer::new`]: super::Renderer::new
#[derive(Debug, Clone)]
pub struct Workspace<
    const STACK: usize,
    const VERTS: usize,
    const SUB: u32 = { fill::SUBPIXEL_BITS },
> {
    pub(super) stack: [StackEntry; STACK],
    pub(super) clip_a: [Vec3; VERTS],
    pub(super) clip_b: [Vec3; VERTS],
    pub(super) points: [FixedPoint<SUB>; VERTS],
    /// The fill's edge memory, reused by every polygon.
    pub(super) edges: [fill::EdgeWalk; VERTS],
}

impl<const STACK: usize, const VERTS: usize, const SUB: u32> Workspace<STACK, VERTS, SUB> {
    /// A zeroed workspace (large `STACK`/`VERTS` belong in a `static` or on the heap). A
    /// `const fn`: firmware can keep it in a `static`, which costs no code (all zero bytes,
    /// it lands in `.bss`).
    pub const fn new() -> Self {
        Workspace {
            stack: [StackEntry::IDLE; STACK],
            clip_a: [Vec3::ZERO; VERTS],
            clip_b: [Vec3::ZERO; VERTS],
            points: [FixedPoint::new(0, 0); VERTS],
            edges: [fill::EdgeWalk::ZERO; VERTS],
        }
    }
}

impl<const STACK: usize, const VERTS: usize, const SUB: u32> Default
    for Workspace<STACK, VERTS, SUB>
{
    fn default() -> Self {
        Self::new()
    }
}
