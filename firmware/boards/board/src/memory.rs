//! A board's frame memory and the renderer over it: the traversal stack and clip buffers, the
//! scan memory, the vertex memory and (feature `antialias`) the pending pixels' row heads,
//! each sized by a const parameter that the board takes from its scene's sizes file
//! ([`crate::include_scene!`]), so that another mesh needs no edit. One value, so that a
//! board keeps it in one static: all zeros, in `.bss`, no code to set it up.

#[cfg(feature = "antialias")]
use peel_runtime::pending::Pending;
use peel_runtime::pending::PendingPixel;
use peel_runtime::render::{Renderer, Workspace};
use peel_runtime::scan::{ScanMemory, ScanNode};
use peel_runtime::vertices::{CachedVertex, VertexCache};
use peel_runtime::RenderError;

use crate::{BACKGROUND, HEIGHT, WIDTH};

/// Vertex memory entries at most: every vertex of a small scene, 512 (4 KiB) of a larger one
/// (the vertices used close together in the walk, as in the target benchmark).
const MAX_VERTEX_MEMORY: usize = 512;

/// The vertex memory entries for a scene whose sizes file says `entries` (`VERTEX_MEMORY`).
pub const fn vertex_memory(entries: usize) -> usize {
    if entries < MAX_VERTEX_MEMORY {
        entries
    } else {
        MAX_VERTEX_MEMORY
    }
}

/// The scan memory nodes of the frames this build draws: the sizes file's `SCAN_NODES`, or
/// with the feature `antialias` its `SCAN_NODES_AA`.
pub const fn scan_nodes(plain: usize, antialiased: usize) -> usize {
    if cfg!(feature = "antialias") {
        antialiased
    } else {
        plain
    }
}

/// The pending-pixel records of the frames this build draws: with the feature `antialias`
/// the sizes file's `PENDING_PIXELS`, else none.
pub const fn pending_records(records: usize) -> usize {
    if cfg!(feature = "antialias") {
        records
    } else {
        0
    }
}

/// The core a board runs on, which decides two of the renderer's switches (the same pixels
/// either way but for integer vertices' last-place differences along edges).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Core {
    /// With an FPU (Cortex-M4F): vertices projected in `f32`, and subtrees outside the view
    /// or behind covered pixels skipped by their boxes.
    WithFpu,
    /// Without one (Cortex-M0+): vertices projected in integers (feature `integer-vertices`)
    /// and no subtree box tests, which cost more in software floats than the subtrees they
    /// skip (BENCHMARKS.md, "On the target").
    WithoutFpu,
}

impl Core {
    /// `renderer` with this core's switches.
    pub fn configure(self, renderer: Renderer<'_>) -> Renderer<'_> {
        match self {
            Core::WithFpu => renderer,
            Core::WithoutFpu => renderer.integer_vertices().without_subtree_culling(),
        }
    }
}

/// A board's frame memory: a [`Workspace<STACK, VERTS>`], `NODES` scan memory nodes and a list
/// head per row, `VERTICES` vertex memory entries and, anti-aliased, a pending list head per
/// row and `RECORDS` pending-pixel records (0: not anti-aliased).
#[derive(Debug)]
pub struct Memory<
    const STACK: usize,
    const VERTS: usize,
    const NODES: usize,
    const VERTICES: usize,
    const RECORDS: usize,
> {
    workspace: Workspace<STACK, VERTS>,
    nodes: [ScanNode; NODES],
    heads: [u16; HEIGHT as usize],
    vertices: [CachedVertex; VERTICES],
    #[cfg(feature = "antialias")]
    pending_heads: [u16; HEIGHT as usize],
    records: [PendingPixel; RECORDS],
}

impl<
        const STACK: usize,
        const VERTS: usize,
        const NODES: usize,
        const VERTICES: usize,
        const RECORDS: usize,
    > Memory<STACK, VERTS, NODES, VERTICES, RECORDS>
{
    /// All zeros: a static of it lands in `.bss`.
    pub const fn new() -> Self {
        Memory {
            workspace: Workspace::new(),
            nodes: [ScanNode::EMPTY; NODES],
            heads: [0; HEIGHT as usize],
            vertices: [CachedVertex::EMPTY; VERTICES],
            #[cfg(feature = "antialias")]
            pending_heads: [0; HEIGHT as usize],
            records: [PendingPixel::EMPTY; RECORDS],
        }
    }

    /// The renderer over this memory, made once: frames in scan order at [`WIDTH`] x
    /// [`HEIGHT`] on [`BACKGROUND`], with `core`'s switches, and anti-aliased when there are
    /// pending-pixel records (`RECORDS` > 0, feature `antialias`).
    pub fn renderer(&mut self, core: Core) -> Result<Renderer<'_>, RenderError> {
        let Memory {
            workspace,
            nodes,
            heads,
            vertices,
            #[cfg(feature = "antialias")]
            pending_heads,
            records,
        } = self;
        let scan = ScanMemory::new(nodes, heads, WIDTH, HEIGHT)?;
        let renderer = Renderer::new(workspace)
            .scan_memory(scan)
            .vertex_memory(VertexCache::new(vertices))
            .background(BACKGROUND);
        #[cfg(feature = "antialias")]
        let renderer = if records.is_empty() {
            renderer
        } else {
            renderer.antialias(Pending::new(records, pending_heads, HEIGHT)?)
        };
        #[cfg(not(feature = "antialias"))]
        let _ = records;
        Ok(core.configure(renderer))
    }
}

impl<
        const STACK: usize,
        const VERTS: usize,
        const NODES: usize,
        const VERTICES: usize,
        const RECORDS: usize,
    > Default for Memory<STACK, VERTS, NODES, VERTICES, RECORDS>
{
    fn default() -> Self {
        Memory::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_larger_than_the_vertex_memory_keeps_512_entries() {
        assert_eq!(vertex_memory(64), 64);
        assert_eq!(vertex_memory(4096), 512);
    }

    #[test]
    fn the_antialias_feature_picks_the_sizes_files_antialiased_figures() {
        let antialiased = cfg!(feature = "antialias");
        assert_eq!(scan_nodes(100, 150), if antialiased { 150 } else { 100 });
        assert_eq!(pending_records(80), if antialiased { 80 } else { 0 });
    }

    #[cfg(feature = "antialias")]
    #[test]
    fn the_renderer_is_antialiased_only_with_records() {
        let mut memory = Box::new(Memory::<64, 32, 64, 16, 0>::new());
        let renderer = memory.renderer(Core::WithFpu).unwrap();
        assert!(renderer.pending().is_none());
        let mut memory = Box::new(Memory::<64, 32, 64, 16, 8>::new());
        let renderer = memory.renderer(Core::WithFpu).unwrap();
        assert!(renderer.pending().is_some());
    }
}
