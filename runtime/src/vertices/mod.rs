//! Vertices: the screen position of each of a scene's vertices, projected and snapped once per
//! frame, in caller memory.
//!
//! A compiled scene shares its vertices between polygons (a vertex of a closed mesh is in about
//! six). Without this memory every polygon transforms, projects and snaps its own corners; with
//! it, the first polygon that uses a vertex in a frame does, and the others read the result.
//! Snapping is a function of the vertex alone, so the pixels are the same bit for bit.
//!
//! It is used only in frames that need no clipping (the scene's box inside the view frustum,
//! the usual case of an object in view): a clipped polygon's corners are new points.
//!
//! Each entry carries the number of the frame that wrote it, so a new frame starts without
//! clearing the memory: entries of older frames are simply stale.

#[cfg(test)]
mod tests;

use crate::fill::{FixedPoint, SUBPIXEL_BITS};

/// One vertex's snapped screen position (the coordinates of a [`FixedPoint`], at the
/// precision of the [`VertexCache`] that wrote it) and the frame that computed it (0: none
/// yet). Memory of any precision: the cache over it gives it one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CachedVertex {
    frame: u32,
    x: i32,
    y: i32,
}

impl CachedVertex {
    /// An empty entry (the [`Default`]); `const`, for memory in a `static`.
    pub const EMPTY: CachedVertex = CachedVertex {
        frame: 0,
        x: 0,
        y: 0,
    };
}

/// Screen positions, [`FixedPoint<SUB>`]s, of vertices `0 .. entries.len()` of a scene (see
/// the module docs); vertices past the end are computed every time, as without the cache.
/// Keep it from frame to frame: [`VertexCache::new`] clears the memory, a new frame does not.
/// Every entry it reads was written by itself in the same frame, so at its own `SUB`.
#[derive(Debug)]
pub struct VertexCache<'m, const SUB: u32 = SUBPIXEL_BITS> {
    entries: &'m mut [CachedVertex],
    frame: u32,
}

impl<'m, const SUB: u32> VertexCache<'m, SUB> {
    /// A cache over `entries` (cleared here), ideally one per vertex of the scene
    /// ([`crate::read::Header::vertex_count`]).
    pub fn new(entries: &'m mut [CachedVertex]) -> Self {
        entries.fill(CachedVertex::EMPTY);
        VertexCache { entries, frame: 0 }
    }

    /// Number of vertices it holds.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether it holds no vertex.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Start a frame: every entry is stale. The frame number wraps after `2^32 - 1` frames;
    /// the memory is then cleared once.
    pub(crate) fn next_frame(&mut self) {
        self.frame = self.frame.wrapping_add(1);
        if self.frame == 0 {
            self.entries.fill(CachedVertex::EMPTY);
            self.frame = 1;
        }
    }

    /// The position of vertex `index` in this frame: computed by `compute` the first time and
    /// kept (when `index` is in range).
    #[inline]
    pub(crate) fn get(
        &mut self,
        index: u32,
        compute: impl FnOnce() -> FixedPoint<SUB>,
    ) -> FixedPoint<SUB> {
        let frame = self.frame;
        match self.entries.get_mut(index as usize) {
            Some(e) if e.frame == frame => FixedPoint::new(e.x, e.y),
            Some(e) => {
                let point = compute();
                *e = CachedVertex {
                    frame,
                    x: point.x,
                    y: point.y,
                };
                point
            }
            None => compute(),
        }
    }

    #[cfg(test)]
    fn set_frame(&mut self, frame: u32) {
        self.frame = frame;
    }
}
