//! Memory handed out by size at boot: one build serves every image size and band height, and
//! what a run takes from the pool is exactly what a firmware sized for that run would hold in
//! statics (the runner counts the pool's used part as RAM, not its capacity). One pool of
//! words for every buffer, so that every build links all of it and the runner can subtract
//! its whole capacity from the statics.

use crate::Failure;

/// What a buffer is for (named when the pool is too small).
#[derive(Debug, Clone, Copy)]
pub enum Use {
    /// A framebuffer or band buffer.
    Framebuffer,
    /// The z-buffer's depth buffer.
    DepthBuffer,
    /// Span-memory intervals.
    SpanMemory,
    /// Span memory's per-row counts.
    RowCounts,
    /// Scan memory's nodes.
    ScanNodes,
    /// Scan memory's row heads.
    ScanHeads,
    /// The mock display's panel memory (not from the pool).
    PanelMemory,
    /// A list of the scanline z-buffer (polygon table, vertices, heads, active edges).
    ScanlineList,
    /// Object memory (the streamed build's scene with objects).
    #[cfg(feature = "objects")]
    ObjectMemory,
    /// The renderer's workspace (the streamed build's, which draws objects too).
    #[cfg(feature = "objects")]
    Workspace,
    /// embedded-3dgfx's meshes of a textured scene (one a group), in the build with textures.
    #[cfg(all(feature = "textures", feature = "embedded-3dgfx"))]
    Meshes,
    /// embedded-3dgfx's texture manager, in the build with textures.
    #[cfg(all(feature = "textures", feature = "embedded-3dgfx"))]
    Textures,
    /// Composite runs (transparent surfaces streamed; in that build only).
    #[cfg(feature = "transparency")]
    CompositeRuns,
    /// The composite runs' row heads.
    #[cfg(feature = "transparency")]
    CompositeHeads,
    /// Pending-pixel records (anti-aliased frames; in that build only, like their names).
    #[cfg(feature = "aa")]
    PendingRecords,
    /// The pending pixels' row heads.
    #[cfg(feature = "aa")]
    PendingHeads,
}

impl core::fmt::Display for Use {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Use::Framebuffer => "framebuffer",
            Use::DepthBuffer => "depth buffer",
            Use::SpanMemory => "span memory",
            Use::RowCounts => "span memory row counts",
            Use::ScanNodes => "scan memory nodes",
            Use::ScanHeads => "scan memory row heads",
            Use::PanelMemory => "panel memory",
            Use::ScanlineList => "scanline z-buffer list",
            #[cfg(feature = "objects")]
            Use::ObjectMemory => "object memory",
            #[cfg(feature = "objects")]
            Use::Workspace => "renderer workspace",
            #[cfg(all(feature = "textures", feature = "embedded-3dgfx"))]
            Use::Meshes => "embedded-3dgfx meshes",
            #[cfg(all(feature = "textures", feature = "embedded-3dgfx"))]
            Use::Textures => "embedded-3dgfx texture manager",
            #[cfg(feature = "transparency")]
            Use::CompositeRuns => "composite runs",
            #[cfg(feature = "transparency")]
            Use::CompositeHeads => "composite row heads",
            #[cfg(feature = "aa")]
            Use::PendingRecords => "pending-pixel records",
            #[cfg(feature = "aa")]
            Use::PendingHeads => "pending-pixel row heads",
        })
    }
}

/// A `'static` word slice from which buffers are taken, front first, never given back.
pub struct Pool {
    free: &'static mut [u32],
    capacity: usize,
}

// Span memory is handed out as words: a pair of `u16` must be one word, with no padding.
const _: () =
    assert!(core::mem::size_of::<(u16, u16)>() == 4 && core::mem::align_of::<(u16, u16)>() <= 4);

impl Pool {
    /// A pool over `all`.
    pub fn new(all: &'static mut [u32]) -> Self {
        let capacity = all.len();
        Pool {
            free: all,
            capacity,
        }
    }

    /// The next `n` words, for `what` (named in the error).
    fn words(&mut self, n: usize, what: Use) -> Result<&'static mut [u32], Failure> {
        let free = core::mem::take(&mut self.free);
        if n > free.len() {
            let left = free.len();
            self.free = free;
            return Err(Failure::OutOfMemory {
                what,
                needed: n,
                free: left,
            });
        }
        let (taken, rest) = free.split_at_mut(n);
        self.free = rest;
        Ok(taken)
    }

    /// `n` halfwords (pixels, depths, row counts).
    pub fn u16s(&mut self, n: usize, what: Use) -> Result<&'static mut [u16], Failure> {
        let words = self.words(n.div_ceil(2), what)?;
        // SAFETY: the words are ours for good, aligned for `u16`, hold at least `n` of them,
        // and every bit pattern is a `u16`.
        Ok(unsafe { core::slice::from_raw_parts_mut(words.as_mut_ptr().cast::<u16>(), n) })
    }

    /// `n` pairs of halfwords (span-memory intervals).
    #[cfg(peel_method)]
    pub fn pairs(&mut self, n: usize, what: Use) -> Result<&'static mut [(u16, u16)], Failure> {
        let words = self.words(n, what)?;
        // SAFETY: as for `u16s`; a pair is one word without padding (checked above), so every
        // bit pattern is a pair.
        Ok(unsafe { core::slice::from_raw_parts_mut(words.as_mut_ptr().cast(), n) })
    }

    /// `n` scan memory nodes.
    #[cfg(feature = "scan")]
    pub fn scan_nodes(
        &mut self,
        n: usize,
    ) -> Result<&'static mut [peel_runtime::scan::ScanNode], Failure> {
        use peel_runtime::scan::{ScanNode, SCAN_NODE_BYTES};
        const { assert!(core::mem::align_of::<ScanNode>() <= 4) };
        let words = self.words((n * SCAN_NODE_BYTES).div_ceil(4), Use::ScanNodes)?;
        let first = words.as_mut_ptr().cast::<ScanNode>();
        for k in 0..n {
            // SAFETY: the words are ours for good, 4-aligned, and hold `n` nodes.
            unsafe { first.add(k).write(ScanNode::EMPTY) };
        }
        // SAFETY: as above, and every node was just written.
        Ok(unsafe { core::slice::from_raw_parts_mut(first, n) })
    }

    /// `n` copies of `value`, aligned for `T` (a word skipped when `T` needs 8 bytes and the
    /// next word is not), for lists of plain records.
    #[cfg(any(feature = "scanline-zbuffer", feature = "aa", feature = "transparency"))]
    pub fn filled<T: Copy>(
        &mut self,
        n: usize,
        value: T,
        what: Use,
    ) -> Result<&'static mut [T], Failure> {
        const { assert!(core::mem::align_of::<T>() <= 8 && core::mem::size_of::<T>() > 0) };
        let misaligned = !(self.free.as_ptr() as usize).is_multiple_of(core::mem::align_of::<T>());
        if misaligned {
            self.words(1, what)?;
        }
        let words = self.words((n * core::mem::size_of::<T>()).div_ceil(4), what)?;
        let first = words.as_mut_ptr().cast::<T>();
        for k in 0..n {
            // SAFETY: the words are ours for good and hold `n` values of `T` from `first`,
            // which is aligned for `T` (checked above; the pool's words are 4-aligned).
            unsafe { first.add(k).write(value) };
        }
        // SAFETY: as above, and every element was just written.
        Ok(unsafe { core::slice::from_raw_parts_mut(first, n) })
    }

    /// `value` moved into the pool (object memory, a workspace, embedded-3dgfx's texture
    /// manager), aligned for `T` as [`Pool::filled`] is.
    #[cfg(any(
        feature = "objects",
        all(feature = "textures", feature = "embedded-3dgfx")
    ))]
    pub fn value<T>(&mut self, value: T, what: Use) -> Result<&'static mut T, Failure> {
        const { assert!(core::mem::align_of::<T>() <= 8 && core::mem::size_of::<T>() > 0) };
        let misaligned = !(self.free.as_ptr() as usize).is_multiple_of(core::mem::align_of::<T>());
        if misaligned {
            self.words(1, what)?;
        }
        let words = self.words(core::mem::size_of::<T>().div_ceil(4), what)?;
        let at = words.as_mut_ptr().cast::<T>();
        // SAFETY: the words are ours for good, hold a `T` and are aligned for it (checked
        // above; the pool's words are 4-aligned); it is written before the reference is made.
        unsafe {
            at.write(value);
            Ok(&mut *at)
        }
    }

    /// `n` values, the `k`-th `make(k)` (embedded-3dgfx's meshes), aligned for `T` as
    /// [`Pool::filled`] is; `make`'s error, if any, after the values before it were made.
    #[cfg(all(feature = "textures", feature = "embedded-3dgfx"))]
    pub fn made<T>(
        &mut self,
        n: usize,
        mut make: impl FnMut(usize) -> Result<T, Failure>,
        what: Use,
    ) -> Result<&'static mut [T], Failure> {
        const { assert!(core::mem::align_of::<T>() <= 8 && core::mem::size_of::<T>() > 0) };
        let misaligned = !(self.free.as_ptr() as usize).is_multiple_of(core::mem::align_of::<T>());
        if misaligned {
            self.words(1, what)?;
        }
        let words = self.words((n * core::mem::size_of::<T>()).div_ceil(4), what)?;
        let first = words.as_mut_ptr().cast::<T>();
        for k in 0..n {
            // SAFETY: the words are ours for good and hold `n` values of `T` from `first`,
            // which is aligned for `T` (checked above; the pool's words are 4-aligned). On an
            // error the values made are never read (nor dropped: the words stay taken).
            unsafe { first.add(k).write(make(k)?) };
        }
        // SAFETY: as above, and every element was just written.
        Ok(unsafe { core::slice::from_raw_parts_mut(first, n) })
    }

    /// Bytes handed out.
    pub fn used_bytes(&self) -> usize {
        (self.capacity - self.free.len()) * 4
    }

    /// Bytes of the whole pool.
    pub fn capacity_bytes(&self) -> usize {
        self.capacity * 4
    }
}
