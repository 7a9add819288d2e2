//! Vertices: the screen positions of a scene's vertices, projected and snapped once per frame,
//! in caller memory.
//!
//! A compiled scene shares its vertices between polygons (a vertex of a closed mesh is in about
//! six). Without this memory every polygon transforms, projects and snaps its own corners; with
//! it, the first polygon that uses a vertex in a frame does, and the others read the result.
//! Snapping is a function of the vertex alone, so the pixels are the same bit for bit.
//!
//! It is used only in frames that need no clipping (the scene's box inside the view frustum,
//! the usual case of an object in view): a clipped polygon's corners are new points.
//!
//! The memory is direct-mapped: vertex `v` has the one entry `v mod n` (`n` the largest power
//! of two the memory holds), which remembers which vertex it holds. One entry per vertex of
//! the scene keeps every vertex; fewer (firmware with a few kilobytes to spare) keep the
//! vertices used close together in the walk, which the compiler numbers in the order of first
//! use. A frame starts by clearing the entries it will use.

// Without the feature the renderer never asks for it.
#[cfg_attr(not(feature = "integer-vertices"), allow(dead_code))]
mod integer;
#[cfg(test)]
mod tests;

pub(crate) use integer::IntegerView;

use crate::fill::{FixedPoint, SUBPIXEL_BITS};

/// One vertex's snapped screen position (the coordinates of a [`FixedPoint`], at the
/// precision of the [`VertexCache`] that wrote it), and which vertex it is: 8 bytes, so that
/// small memories hold more vertices. Memory of any precision: the cache over it gives it one.
///
/// The first word holds `x` in its low 24 bits (a snapped point lies in the window, so `x` is
/// at least 0 and, at the renderer's precision, below `2^24` for images up to 65535 pixels;
/// a point that does not fit is not kept) and the vertex's tag in its high 8: one more than
/// the vertex index over the number of entries (its entry is the index modulo that number),
/// 0 for none, so that [`CachedVertex::EMPTY`] is all zeros (memory in `.bss`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CachedVertex {
    x_and_tag: u32,
    y: i32,
}

/// The bits of `x` in [`CachedVertex::x_and_tag`].
const X_BITS: u32 = 0x00ff_ffff;
/// The largest tag: vertices whose index over the number of entries is 255 or more are not
/// kept.
const MAX_TAG: u32 = 0xff;

impl CachedVertex {
    /// An empty entry (the [`Default`]); `const`, for memory in a `static`.
    pub const EMPTY: CachedVertex = CachedVertex { x_and_tag: 0, y: 0 };
}

impl Default for CachedVertex {
    fn default() -> Self {
        CachedVertex::EMPTY
    }
}

/// Screen positions, [`FixedPoint<SUB>`]s, of a scene's vertices (see the module docs), in the
/// first power-of-two entries of the memory given. Keep it from frame to frame: it is made
/// once. Every entry it reads was written by itself in the same frame, so at its own `SUB`.
#[derive(Debug)]
pub struct VertexCache<'m, const SUB: u32 = SUBPIXEL_BITS> {
    entries: &'m mut [CachedVertex],
    /// `entries.len() - 1` (0 without entries): the entry of vertex `v` is `v & mask`.
    mask: u32,
    /// `log2(entries.len())`: the tag of vertex `v` is `(v >> shift) + 1`.
    shift: u32,
}

impl<'m, const SUB: u32> VertexCache<'m, SUB> {
    /// A cache over the largest power-of-two prefix of `entries` (up to `2^31` entries); one
    /// per vertex of the scene ([`crate::read::Header::vertex_count`], rounded up to a power of
    /// two) keeps every vertex, fewer keep those used close together. Nothing is read before
    /// a frame clears it, so whatever the memory held does not matter.
    pub fn new(entries: &'m mut [CachedVertex]) -> Self {
        let len = entries.len().min(1 << 31);
        let shift = if len == 0 { 0 } else { len.ilog2() };
        let used = if len == 0 { 0 } else { 1 << shift };
        let entries = match entries.get_mut(..used) {
            Some(e) => e,
            None => &mut [],
        };
        let mask = (used as u32).saturating_sub(1);
        VertexCache {
            entries,
            mask,
            shift,
        }
    }

    /// Number of entries in use (a power of two, or 0).
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether it holds no entry.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Start a frame: the camera may have moved, so every entry is cleared.
    pub(crate) fn next_frame(&mut self) {
        self.entries.fill(CachedVertex::EMPTY);
    }

    /// The position of vertex `index` in this frame: kept from an earlier call of the frame, or
    /// computed by `compute` and kept (replacing the vertex that shared its entry). A vertex
    /// whose tag would not fit in 8 bits, or a point with `x` outside `0..2^24`, is computed
    /// each time.
    #[inline]
    pub(crate) fn get(
        &mut self,
        index: u32,
        compute: impl FnOnce() -> FixedPoint<SUB>,
    ) -> FixedPoint<SUB> {
        let above = index >> self.shift;
        match self.entries.get_mut((index & self.mask) as usize) {
            Some(e) if above < MAX_TAG => {
                let tag = above + 1;
                if e.x_and_tag >> 24 == tag {
                    return FixedPoint::new((e.x_and_tag & X_BITS) as i32, e.y);
                }
                let point = compute();
                // A negative `x` has its high bits set.
                if point.x as u32 <= X_BITS {
                    *e = CachedVertex {
                        x_and_tag: point.x as u32 | tag << 24,
                        y: point.y,
                    };
                }
                point
            }
            _ => compute(),
        }
    }
}
