//! Frames in scan order (feature `scan-order`): front to back, each covered interval kept with
//! its colour in caller memory during the walk, then the whole frame read out row by row, top
//! to bottom, the gaps in the background colour. A display gets one address window for the
//! frame and its pixels as one run ([`ScanFrame::pixels`], `ScanFrame::draw_to` with
//! `embedded-graphics`), or a row at a time into a row buffer ([`ScanFrame::row_into`]) for a
//! DMA; either way the panel never shows the old and the new frame mixed beyond the row being
//! written, and nothing is sent before the frame is complete.
//!
//! # Memory
//!
//! [`ScanMemory`] is a pool of [`ScanNode`]s shared by every row (8 bytes each: the interval,
//! its colour in RGB565, the next interval of its row) and one list head per row. A row's
//! list is sorted and holds its covered intervals; touching intervals of the same RGB565
//! colour are one node (the pieces of a split polygon, neighbours of one shade), so a frame
//! needs far fewer nodes than it draws spans: the teapot at 320x240 draws 3,200-5,100 pieces
//! a frame and keeps at most 2,751 nodes over an orbit. The builder's sizes file gives
//! the nodes a scene needs over an orbit at an image size (`SCAN_NODES`,
//! `scan_memory(width, height)`).
//!
//! A smoothly shaded piece (feature `smooth`) of more than a few RGB565 colours is one shaded
//! interval of two nodes, its shade kept with it and its colours computed as the frame is read
//! out; one of fewer colours is kept as its runs, which join flat neighbours of their colour,
//! and a piece that continues a shaded neighbour's shade grows it (`shaded.rs`). The smooth
//! cow at 320x240 needs 4,220 nodes over an orbit instead of 4,858 as runs of one colour. A
//! frame keeps the shades of up to 16 materials so; further ones go as runs. Columns leave a
//! node's top bit free to mark shaded intervals: scan memory serves frames up to
//! [`MAX_WIDTH`] (32,767) pixels wide.
//!
//! Shades are read out dithered to RGB565 by default, as a framebuffer stores them
//! ([`ScanMemory::set_dithering`]): the dither takes a pixel's 8-bit colour, so a dithered
//! frame keeps pieces of few colours as level runs (one node: a material and an 8-bit
//! level) rather than as runs of one RGB565 colour, and needs more nodes. The smooth cow at
//! 320x240 needs 5,163 over an orbit dithered, 4,220 undithered. Beyond the 16 materials,
//! shades go as RGB565 runs, undithered.
//!
//! The lists answer the walk's coverage queries (which subtrees and polygons are hidden) as
//! span memory does, so a scan-order frame culls and draws exactly what a streamed frame does.
//!
//! # Anti-aliased frames
//!
//! With [`Renderer::antialias`](crate::render::Renderer::antialias) the finished pixels go
//! into the lists with their colours and the partly covered ones stay in the pending pool
//! ([`crate::pending`]), which the frame borrows: the read-out merges each row's intervals
//! with its pending pixels, which lie in its gaps, each the average of its samples with the
//! background for those uncovered. Those pixels cost no node, but each splits the interval it
//! would have joined, so an anti-aliased frame mostly needs more nodes than the plain one
//! (the teapot at 320x240: 3,458 over the orbit against 2,751; the builder's
//! `spans::scan_nodes_antialiased`). A frame that runs out is drawn again without
//! anti-aliasing; only when the plain frame runs out too is it an error.
//!
//! # Running out
//!
//! A frame that needs more nodes than the pool holds is not drawn:
//! [`Renderer::draw_scan`](crate::render::Renderer::draw_scan) returns
//! [`RenderError::ScanMemoryFull`] and nothing has been sent, so the panel keeps the last
//! frame. There is no back-to-front fallback in scan order.
//!
//! [`RenderError::ScanMemoryFull`]: crate::error::RenderError::ScanMemoryFull

#[cfg(test)]
mod tests;

mod frame;
mod shaded;

pub(crate) use frame::Gaps;
pub use frame::{ScanFrame, ScanPixels};

use crate::display::{Colour, Paint, RowShade};
use crate::error::RenderError;
use shaded::Shading;

/// The end of a list.
const NIL: u16 = u16::MAX;

/// The bit of a node's `start` that marks a shaded interval (columns stay below it: a frame
/// is at most [`MAX_WIDTH`] wide).
const SHADED: u16 = 1 << 15;

/// The widest frame scan memory keeps: a column leaves the top bit of a node's first column
/// free, to mark a shaded interval.
pub const MAX_WIDTH: u32 = (SHADED - 1) as u32;

/// The bit of a shaded node's colour field that makes it a level run: one node, pixels of one
/// intensity level (bits 4..12) of a material (bits 0..4), which a dithered frame
/// ([`ScanMemory::set_dithering`]) keeps where an undithered one keeps a run of one RGB565
/// colour.
const LEVEL: u16 = 1 << 15;

/// Material colours of shaded intervals a frame keeps (a shaded node names one by its index);
/// a frame with more keeps the further materials' shades as runs of one colour.
const MATERIALS: usize = 16;

/// One covered interval of a row in [`ScanMemory`]: columns `start..end`, its RGB565 colour,
/// the next interval of its row (a pool index, or none). A shaded interval (the top bit of
/// `start` set) takes two nodes in a row of the pool: the first holds its material's index for
/// a colour, the second its intensity at `start` and its step (a
/// [`RowShade`] from the
/// interval's first pixel on), so that a smooth span costs two nodes however many colours it
/// shows.
/// Four `u16`s in this order (`repr(C)`): any bit pattern is a node, so firmware may place
/// the pool in memory it hands out by size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(C)]
pub struct ScanNode {
    start: u16,
    end: u16,
    colour: u16,
    next: u16,
}

impl ScanNode {
    /// An unused node, for static arrays: all zeros, so that a `static` pool lands in `.bss`
    /// and costs no flash (a node's content matters only once the memory hands it out).
    pub const EMPTY: ScanNode = ScanNode {
        start: 0,
        end: 0,
        colour: 0,
        next: 0,
    };
}

impl ScanNode {
    /// The first column (without the shaded bit).
    #[inline]
    fn first(&self) -> u16 {
        self.start & !SHADED
    }

    /// Whether the interval is shaded: its shade in the next node of the pool, or a level
    /// run's in its colour field ([`ScanNode::is_level`]).
    #[inline]
    fn is_shaded(&self) -> bool {
        self.start & SHADED != 0
    }

    /// Whether the interval is a level run (one node, see [`LEVEL`]).
    #[inline]
    fn is_level(&self) -> bool {
        self.is_shaded() && self.colour & LEVEL != 0
    }

    /// A level run's colour field: `level` of material `material` (below [`MATERIALS`]).
    #[inline]
    fn level_field(level: u8, material: u8) -> u16 {
        LEVEL | u16::from(level) << 4 | u16::from(material)
    }

    /// A shaded node's material index, and a level run's level (else 0).
    #[inline]
    fn material_level(&self) -> (usize, u8) {
        (usize::from(self.colour & 0x0f), (self.colour >> 4) as u8)
    }

    /// A shaded interval's second node: `value` and `step` of a [`RowShade`], as four `u16`s.
    fn shade(value: i32, step: i32) -> Self {
        let (v, s) = (value as u32, step as u32);
        ScanNode {
            start: v as u16,
            end: (v >> 16) as u16,
            colour: s as u16,
            next: (s >> 16) as u16,
        }
    }

    /// The `value` and `step` of [`ScanNode::shade`].
    fn value_step(&self) -> (i32, i32) {
        let v = u32::from(self.start) | u32::from(self.end) << 16;
        let s = u32::from(self.colour) | u32::from(self.next) << 16;
        (v as i32, s as i32)
    }
}

impl Default for ScanNode {
    fn default() -> Self {
        ScanNode::EMPTY
    }
}

/// Bytes of one [`ScanNode`] (8).
pub const SCAN_NODE_BYTES: usize = core::mem::size_of::<ScanNode>();

/// The covered intervals of a `width x height` frame with their colours, in caller memory: a
/// pool of `nodes` shared by the rows (at most 65,535 are used) and a list head per row (see
/// the module docs).
#[derive(Debug)]
pub struct ScanMemory<'m> {
    nodes: &'m mut [ScanNode],
    heads: &'m mut [u16],
    width: u16,
    height: u32,
    /// Nodes never used this frame start here (freed ones are reused first).
    fresh: u16,
    /// Freed nodes, linked through `next`.
    free: u16,
    covered: u64,
    exhausted: bool,
    /// The last colour converted.
    last: Option<(Colour, u16)>,
    /// The material colours of the frame's shaded intervals, the first `materials` of them.
    palette: [Colour; MATERIALS],
    materials: u8,
    /// Whether shaded intervals are read out dithered ([`ScanMemory::set_dithering`]).
    dither: bool,
}

impl<'m> ScanMemory<'m> {
    /// Scan memory for `width x height` frames. Needs `heads.len() >= height` and
    /// `width <= MAX_WIDTH`, else [`RenderError::SpanMemory`].
    pub fn new(
        nodes: &'m mut [ScanNode],
        heads: &'m mut [u16],
        width: u32,
        height: u32,
    ) -> Result<Self, RenderError> {
        let w = u16::try_from(width).map_err(|_| RenderError::SpanMemory)?;
        let rows = usize::try_from(height).map_err(|_| RenderError::SpanMemory)?;
        if heads.len() < rows || width > MAX_WIDTH {
            return Err(RenderError::SpanMemory);
        }
        let mut m = ScanMemory {
            nodes,
            heads,
            width: w,
            height,
            fresh: 0,
            free: NIL,
            covered: 0,
            exhausted: false,
            last: None,
            palette: [Colour::grey(0); MATERIALS],
            materials: 0,
            dither: true,
        };
        m.clear();
        Ok(m)
    }

    /// Forget the frame.
    pub fn clear(&mut self) {
        for h in self.heads.iter_mut() {
            *h = NIL;
        }
        self.fresh = 0;
        self.free = NIL;
        self.covered = 0;
        self.exhausted = false;
        self.materials = 0;
    }

    /// Whether smooth shades are read out dithered to RGB565 ([`dither_rgb565`], on by
    /// default) or rounded, as a framebuffer's ([`Framebuffer::set_dithering`]). Dithered, a
    /// shade's pixels are kept to the 8-bit colour the dither takes rather than to RGB565, so
    /// a smooth frame needs more nodes (see the module docs). Flat spans are never dithered.
    /// Set before the memory goes to the renderer ([`Renderer::scan_memory`]).
    ///
    /// [`Renderer::scan_memory`]: crate::render::Renderer::scan_memory
    ///
    /// [`dither_rgb565`]: crate::display::dither_rgb565
    /// [`Framebuffer::set_dithering`]: crate::display::Framebuffer::set_dithering
    pub fn set_dithering(&mut self, on: bool) {
        self.dither = on;
    }

    /// Whether smooth shades are dithered ([`Self::set_dithering`]).
    pub fn dithering(&self) -> bool {
        self.dither
    }

    /// Frame width.
    pub fn width(&self) -> u32 {
        u32::from(self.width)
    }

    /// Frame height.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Nodes in the pool (at most 65,535 of them are used).
    pub fn capacity(&self) -> usize {
        self.nodes.len().min(usize::from(NIL))
    }

    /// The most nodes the frame held at once (its need: a pool of this many would not have
    /// run out).
    pub fn nodes_used(&self) -> usize {
        usize::from(self.fresh)
    }

    /// Whether an interval found no free node (the frame is then incomplete).
    pub fn exhausted(&self) -> bool {
        self.exhausted
    }

    /// Distinct pixels covered.
    pub fn covered(&self) -> u64 {
        self.covered
    }

    /// Whether every pixel of the first `rows` rows is covered.
    pub(crate) fn is_full(&self, rows: u32) -> bool {
        self.covered == u64::from(self.width) * u64::from(rows)
    }

    fn head(&self, y: u32) -> u16 {
        usize::try_from(y)
            .ok()
            .and_then(|y| self.heads.get(y))
            .copied()
            .unwrap_or(NIL)
    }

    /// Node `i`; beyond the pool (never, by construction) an empty one ending its list.
    fn node(&self, i: u16) -> ScanNode {
        self.nodes.get(usize::from(i)).copied().unwrap_or(ScanNode {
            next: NIL,
            ..ScanNode::EMPTY
        })
    }

    fn node_mut(&mut self, i: u16) -> Option<&mut ScanNode> {
        self.nodes.get_mut(usize::from(i))
    }

    /// Whether every pixel `x0 <= x < x1`, `y0 <= y < y1` is covered (an empty rectangle is).
    pub fn covers(&self, x0: u32, y0: u32, x1: u32, y1: u32) -> bool {
        if x0 >= x1 {
            return true;
        }
        (y0..y1.min(self.height)).all(|y| {
            let mut at = x0;
            let mut i = self.head(y);
            while i != NIL {
                let n = self.node(i);
                if u32::from(n.end) <= at {
                    i = n.next;
                    continue;
                }
                if u32::from(n.first()) > at {
                    return false;
                }
                at = u32::from(n.end);
                if at >= x1 {
                    return true;
                }
                i = n.next;
            }
            false
        })
    }

    /// A node for `n`, from the free list or the fresh ones; `None` when the pool is spent.
    fn alloc(&mut self, n: ScanNode) -> Option<u16> {
        let i = if self.free != NIL {
            let i = self.free;
            self.free = self.node(i).next;
            i
        } else if usize::from(self.fresh) < self.capacity() {
            self.fresh += 1;
            self.fresh - 1
        } else {
            return None;
        };
        *self.node_mut(i)? = n;
        Some(i)
    }

    fn release(&mut self, i: u16) {
        let free = self.free;
        if let Some(n) = self.node_mut(i) {
            n.next = free;
            self.free = i;
        }
    }

    /// Link `i` after `prev` (or first in row `y`).
    fn link(&mut self, y: usize, prev: u16, i: u16) {
        if prev == NIL {
            if let Some(h) = self.heads.get_mut(y) {
                *h = i;
            }
        } else if let Some(p) = self.node_mut(prev) {
            p.next = i;
        }
    }

    /// The RGB565 form of `colour` (the last one is kept: spans come in runs of one colour).
    #[inline]
    fn rgb565(&mut self, colour: Colour) -> u16 {
        match self.last {
            Some((k, c)) if k == colour => c,
            _ => {
                let c = colour.to_rgb565();
                self.last = Some((colour, c));
                c
            }
        }
    }

    /// Cover the uncovered pixels of `[x_start, x_end)` in row `y` with `colour`; returns the
    /// pixels newly covered. Out-of-frame or empty spans cover nothing; so does every span
    /// once the pool ran out ([`ScanMemory::exhausted`]).
    pub fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) -> u64 {
        let c = self.rgb565(colour);
        self.cover(y, x_start, x_end, OneColour(c))
    }

    /// Cover the uncovered pixels of `[x_start, x_end)` in row `y` with `paint`, as
    /// [`ScanMemory::span`] does with a colour.
    #[inline]
    pub(crate) fn paint(&mut self, y: u32, x_start: u32, x_end: u32, paint: Paint<'_>) -> u64 {
        match paint {
            Paint::Colour(colour) => self.span(y, x_start, x_end, colour),
            Paint::Shade(shade) => self.shaded_span(y, x_start, x_end, shade),
        }
    }

    /// [`ScanMemory::span`] with a shade. A piece of it is kept as its runs of one RGB565
    /// colour where they cost fewer nodes (their first and last join flat neighbours of their
    /// colour), and otherwise as a shaded interval, two nodes; where a shaded neighbour's shade
    /// continues over its pixels to RGB565 precision, that neighbour grows instead. A frame's
    /// further materials beyond [`MATERIALS`] keep their shades as runs. Out of line: one
    /// instance for the flat and the shaded paths' callers.
    #[inline(never)]
    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) -> u64 {
        match self
            .material(shade.colour)
            .filter(|_| cfg!(feature = "smooth"))
        {
            Some(material) => self.cover(y, x_start, x_end, Shading::new(shade, material)),
            None => self.runs(y, x_start, x_end, shade),
        }
    }

    /// Cover the uncovered pixels of `[x_start, x_end)` in row `y`, piece by piece as `pieces`
    /// says (one loop for both kinds, compiled for each).
    #[inline]
    fn cover<P: Pieces>(&mut self, y: u32, x_start: u32, x_end: u32, mut pieces: P) -> u64 {
        let x_end = x_end.min(u32::from(self.width));
        if x_start >= x_end || y >= self.height || self.exhausted {
            return 0;
        }
        let row = y as usize;
        // In range: both fit u16 since x_end <= width <= MAX_WIDTH.
        let (mut at, b) = (x_start as u16, x_end as u16);
        let mut prev = NIL;
        let mut cur = self.head(y);
        // Skip the intervals that end before `at` (not touching it).
        while cur != NIL {
            let n = self.node(cur);
            if n.end >= at {
                break;
            }
            prev = cur;
            cur = n.next;
        }
        let mut covered = 0u64;
        while at < b {
            let n = (cur != NIL).then(|| self.node(cur));
            if let Some(n) = n.filter(|n| n.first() <= at) {
                // Covered up to its end (or touching at `at`).
                at = at.max(n.end);
                prev = cur;
                cur = n.next;
                continue;
            }
            let gap_end = n.map_or(b, |n| n.first().min(b));
            let (end, c) = match pieces.piece(self, (at, gap_end), prev, cur) {
                Piece::Joined(from, to) => {
                    covered += u64::from(to - from);
                    if from == at {
                        at = to;
                    }
                    continue;
                }
                Piece::Flat(end, c) => (end, Some((c, false))),
                Piece::Level(end, c) => (end, Some((c, true))),
                Piece::Shaded(end) => (end, None),
            };
            let same = |m: &ScanNode| Some((m.colour, m.is_shaded())) == c;
            let left = prev != NIL && {
                let p = self.node(prev);
                p.end == at && same(&p)
            };
            let right = end == gap_end && n.is_some_and(|n| n.first() == gap_end && same(&n));
            covered += u64::from(end - at);
            let linked = match (left, right, n) {
                (true, true, Some(n)) => {
                    // The gap joins two intervals of its colour: one node.
                    if let Some(p) = self.node_mut(prev) {
                        p.end = n.end;
                        p.next = n.next;
                    }
                    self.release(cur);
                    at = n.end;
                    cur = n.next;
                    continue;
                }
                (true, _, _) => {
                    if let Some(p) = self.node_mut(prev) {
                        p.end = end;
                    }
                    at = end;
                    continue;
                }
                (false, true, Some(_)) => {
                    if let Some(r) = self.node_mut(cur) {
                        r.start = at | (r.start & SHADED);
                    }
                    at = end;
                    continue;
                }
                _ => match c {
                    Some((colour, level)) => self.alloc(ScanNode {
                        start: if level { at | SHADED } else { at },
                        end,
                        colour,
                        next: cur,
                    }),
                    None => {
                        let (first, shade) = pieces.shaded(at, end, cur);
                        self.alloc_pair(first, shade)
                    }
                },
            };
            let Some(i) = linked else {
                self.exhausted = true;
                let covered = covered - u64::from(end - at);
                self.covered += covered;
                return covered;
            };
            self.link(row, prev, i);
            prev = i;
            at = end;
        }
        self.covered += covered;
        covered
    }
}

/// What the next piece of a gap becomes.
enum Piece {
    /// Pixels `from..to` joined a shaded neighbour (`from` is the gap's start, or `to` its
    /// end).
    Joined(u16, u16),
    /// Pixels up to `.0` in one RGB565 colour.
    Flat(u16, u16),
    /// Pixels up to `.0`, a level run of colour field `.1` ([`LEVEL`]).
    Level(u16, u16),
    /// Pixels up to `.0`, a shaded interval.
    Shaded(u16),
}

/// A span's paint as scan memory cuts a gap into pieces: one colour ([`OneColour`]) or a
/// shade ([`Shading`]).
trait Pieces {
    /// The next piece of gap `at..gap_end`, between interval `prev` (ending at or before `at`,
    /// or none) and interval `next` (starting at or after `gap_end`, or none).
    fn piece(&mut self, m: &mut ScanMemory<'_>, gap: (u16, u16), prev: u16, next: u16) -> Piece;

    /// A shaded interval's two nodes, `at..end` followed by `next` (never asked of one
    /// colour).
    fn shaded(&self, at: u16, end: u16, next: u16) -> (ScanNode, ScanNode);
}

/// A flat span: one colour, RGB565.
struct OneColour(u16);

impl Pieces for OneColour {
    #[inline]
    fn piece(&mut self, _: &mut ScanMemory<'_>, gap: (u16, u16), _: u16, _: u16) -> Piece {
        Piece::Flat(gap.1, self.0)
    }

    fn shaded(&self, _: u16, _: u16, _: u16) -> (ScanNode, ScanNode) {
        (ScanNode::EMPTY, ScanNode::EMPTY)
    }
}
