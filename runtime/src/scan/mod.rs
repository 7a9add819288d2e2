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
//! [`ScanMemory`] is a pool of [`ScanNode`]s shared by every row (6 bytes each: where the
//! node starts, its colour in RGB565, the next node of its row) and one list head per row. A
//! row's list is sorted and partitions the row from its first node on: each node runs to the
//! next one's start, and a stretch of uncovered pixels between covered ones, or after them, is
//! a gap node, so that no node keeps its end. Touching intervals of the same RGB565 colour are
//! one node (the pieces of a split polygon, neighbours of one shade), so a frame needs far
//! fewer nodes than it draws spans: the teapot at 320x240 draws 3,200-5,100 pieces a frame and
//! keeps at most 2,878 nodes over an orbit, gap nodes included (17,268 bytes; 2,752 nodes of
//! 8 bytes when each kept its end). The builder's sizes file gives the nodes a scene needs
//! over an orbit at an image size (`SCAN_NODES`, `scan_memory(width, height)`).
//!
//! A smoothly shaded piece (feature `smooth`) of more than a few RGB565 colours is one shaded
//! interval of two nodes, its shade kept with it (58 bits: a shade steeper than 16 levels a
//! pixel goes as runs) and its colours computed as the frame is read out; one of fewer colours
//! is kept as its runs, which join flat neighbours of their colour, and a piece that continues
//! a shaded neighbour's shade grows it (`shaded.rs`). A frame keeps the shades of up to 16
//! materials so; further ones go as runs. Columns leave a node's top bit free to tag the nodes
//! whose colour field is no RGB565 colour (gaps, level runs, shaded intervals): scan memory
//! serves frames up to [`MAX_WIDTH`] (32,767) pixels wide.
//!
//! Shades are read out dithered to RGB565 by default, as a framebuffer stores them
//! ([`ScanMemory::set_dithering`]): the dither takes a pixel's 8-bit colour, so a dithered
//! frame keeps pieces of few colours as level runs (one node: a material and an 8-bit
//! level) rather than as runs of one RGB565 colour, and needs more nodes. The smooth cow at
//! 320x240 needs 5,314 over an orbit dithered (31,884 bytes). Beyond the 16 materials, shades
//! go as RGB565 runs, undithered.
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
//! background for those uncovered. Those pixels are gaps in the lists (a gap node each stretch
//! of them), and each splits the interval it would have joined, so an anti-aliased frame
//! mostly needs more nodes than the plain one (the teapot at 320x240: 3,601 over the orbit
//! against 2,878; the builder's
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

use crate::display::{Colour, Paint, RowShade, RowTexture, SpanPaint};
use crate::error::RenderError;
use shaded::Shading;

/// The end of a list.
const NIL: u16 = u16::MAX;

/// The bit of a node's `start` that marks a node whose colour field is no RGB565 colour: a
/// gap, a level run or a shaded interval, as the field's top two bits say ([`KIND`]). Columns
/// stay below it: a frame is at most [`MAX_WIDTH`] wide.
const TAGGED: u16 = 1 << 15;

/// The widest frame scan memory keeps: a column leaves the top bit of a node's first column
/// free, to mark a tagged node.
pub const MAX_WIDTH: u32 = (TAGGED - 1) as u32;

/// The top two bits of a tagged node's colour field: what the node is. Any other value (`00`,
/// `11`) is a gap.
const KIND: u16 = 0b11 << 14;

/// [`KIND`] of a level run: one node, pixels of one intensity level (bits 4..12) of a material
/// (bits 0..4), which a dithered frame ([`ScanMemory::set_dithering`]) keeps where an
/// undithered one keeps a run of one RGB565 colour.
const LEVEL: u16 = 0b01 << 14;

/// [`KIND`] of a shaded interval's first node: its material in bits 0..4, the top 10 bits of
/// its shade in bits 4..14, the other 48 in the next node of the pool ([`ScanNode::pair`]).
const PAIR: u16 = 0b10 << 14;

/// The colour field of a gap node.
const GAP: u16 = 0;

/// Bits of a shaded interval's step ([`ScanNode::pair`]): a shade steeper than 16 levels a
/// pixel is kept as runs.
const STEP_BITS: u32 = 26;

/// Material colours of shaded intervals a frame keeps (a shaded node names one by its index);
/// a frame with more keeps the further materials' shades as runs of one colour.
const MATERIALS: usize = 16;

/// One node of a row in [`ScanMemory`]: the column where it starts, its colour, the next node of
/// its row (a pool index, or none). A node runs to the start of the next (the last to the end
/// of the row), so that a node costs three `u16`s: a stretch of uncovered pixels after a
/// covered one is a gap node, and the pixels before a row's first node are uncovered. A
/// covered node's colour is an RGB565 colour, or (tagged, the top bit of `start`) a level run
/// or the first node of a shaded interval, which takes two nodes in a row of the pool: its
/// material's index for a colour, and its intensity at `start` and its step (a [`RowShade`]
/// from the interval's first pixel on), so that a smooth span costs two nodes however many
/// colours it shows. Three `u16`s in this order (`repr(C)`): any bit pattern is a node, so
/// firmware may place the pool in memory it hands out by size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(C)]
pub struct ScanNode {
    start: u16,
    colour: u16,
    next: u16,
}

impl ScanNode {
    /// An unused node, for static arrays: all zeros, so that a `static` pool lands in `.bss`
    /// and costs no flash (a node's content matters only once the memory hands it out).
    pub const EMPTY: ScanNode = ScanNode {
        start: 0,
        colour: 0,
        next: 0,
    };

    /// The first column (without the tag bit).
    #[inline]
    fn first(&self) -> u16 {
        self.start & !TAGGED
    }

    /// Whether the colour field is no RGB565 colour (a gap, a level run, a shaded interval).
    #[inline]
    fn tagged(&self) -> bool {
        self.start & TAGGED != 0
    }

    /// Whether the node is a gap: uncovered pixels.
    #[inline]
    fn is_gap(&self) -> bool {
        self.tagged() && !matches!(self.colour & KIND, LEVEL | PAIR)
    }

    /// Whether the node is shaded: a level run or a shaded interval (whose shade is in the
    /// next node of the pool, [`ScanNode::is_pair`]).
    #[inline]
    fn is_shaded(&self) -> bool {
        self.tagged() && matches!(self.colour & KIND, LEVEL | PAIR)
    }

    /// Whether the interval is a level run (one node, see [`LEVEL`]).
    #[inline]
    fn is_level(&self) -> bool {
        self.tagged() && self.colour & KIND == LEVEL
    }

    /// Whether the node is a shaded interval's first (see [`PAIR`]).
    #[inline]
    fn is_pair(&self) -> bool {
        self.tagged() && self.colour & KIND == PAIR
    }

    /// A level run's colour field: `level` of material index `material`.
    #[inline]
    fn level_field(level: u8, material: u8) -> u16 {
        LEVEL | u16::from(level) << 4 | u16::from(material & 0x0f)
    }

    /// A shaded node's material index, and a level run's level (else 0).
    #[inline]
    fn material_level(&self) -> (usize, u8) {
        let level = if self.is_level() {
            (self.colour >> 4) as u8
        } else {
            0
        };
        (usize::from(self.colour & 0x0f), level)
    }

    /// Whether a shade of `step` fits a shaded interval ([`STEP_BITS`]).
    #[inline]
    fn step_fits(step: i32) -> bool {
        let limit = 1i32 << (STEP_BITS - 1);
        (-limit..limit).contains(&step)
    }

    /// A shaded interval's two nodes from `start` on, followed by `next`: material index
    /// `material`, `value` and `step` of a [`RowShade`] (`step` as [`ScanNode::step_fits`]
    /// allows: its top bits are dropped), packed into 58 bits: 10 in the first node's colour
    /// field, 48 in the second node.
    fn pair(start: u16, next: u16, material: u8, value: i32, step: i32) -> (Self, Self) {
        let mask = (1u64 << STEP_BITS) - 1;
        let bits = u64::from(value as u32) | ((step as u64) & mask) << 32;
        let first = ScanNode {
            start: start | TAGGED,
            colour: PAIR | ((bits >> 48) as u16 & 0x3ff) << 4 | u16::from(material & 0x0f),
            next,
        };
        let second = ScanNode {
            start: bits as u16,
            colour: (bits >> 16) as u16,
            next: (bits >> 32) as u16,
        };
        (first, second)
    }

    /// The `value` and `step` of the shaded interval whose nodes are `self` and `second`
    /// ([`ScanNode::pair`]).
    fn value_step(&self, second: &ScanNode) -> (i32, i32) {
        let bits = u64::from(second.start)
            | u64::from(second.colour) << 16
            | u64::from(second.next) << 32
            | u64::from((self.colour >> 4) & 0x3ff) << 48;
        let value = bits as u32 as i32;
        // Sign-extend the step's STEP_BITS.
        let step = ((bits >> 32) as i32) << (32 - STEP_BITS) >> (32 - STEP_BITS);
        (value, step)
    }
}

impl Default for ScanNode {
    fn default() -> Self {
        ScanNode::EMPTY
    }
}

/// Bytes of one [`ScanNode`] (6).
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

    /// The column where node `n` ends: the next node's start, or the row's end.
    #[inline]
    fn end(&self, n: &ScanNode) -> u16 {
        if n.next == NIL {
            self.width
        } else {
            self.node(n.next).first()
        }
    }

    /// Row `y`'s nodes in order, each with its index and its end (each node read once).
    #[inline]
    fn row_nodes(&self, y: u32) -> RowNodes<'_, 'm> {
        let i = self.head(y);
        RowNodes {
            memory: self,
            i,
            n: self.node(i),
        }
    }

    /// Whether every pixel `x0 <= x < x1`, `y0 <= y < y1` is covered (an empty rectangle is).
    pub fn covers(&self, x0: u32, y0: u32, x1: u32, y1: u32) -> bool {
        if x0 >= x1 {
            return true;
        }
        (y0..y1.min(self.height)).all(|y| {
            // A column past the row's end is held by no node.
            let x = u16::try_from(x0).unwrap_or(u16::MAX);
            let Spot {
                mut held,
                after: mut i,
                after_start: mut after,
                ..
            } = self.spot(self.head(y), x);
            if held == NIL {
                return false;
            }
            // Then node by node up to `x1`, each covered.
            loop {
                if self.node(held).is_gap() {
                    return false;
                }
                if u32::from(after) >= x1 {
                    return true;
                }
                if i == NIL {
                    return false;
                }
                held = i;
                i = self.node(held).next;
                after = if i == NIL {
                    self.width
                } else {
                    self.node(i).first()
                };
            }
        })
    }

    /// Each uncovered piece of `[x_start, x_end)` on row `y`, left to right, as
    /// `piece(start, end)`: the pixels before the row's first node and its gap nodes.
    pub(crate) fn uncovered(
        &self,
        y: u32,
        x_start: u32,
        x_end: u32,
        mut piece: impl FnMut(u32, u32),
    ) {
        let x_end = x_end.min(u32::from(self.width));
        let mut clipped = |a: u32, b: u32| {
            let (a, b) = (a.max(x_start), b.min(x_end));
            if a < b {
                piece(a, b);
            }
        };
        let head = self.head(y);
        let first = if head == NIL {
            u32::from(self.width)
        } else {
            u32::from(self.node(head).first())
        };
        clipped(0, first);
        for (_, n, end) in self.row_nodes(y) {
            if u32::from(n.first()) >= x_end {
                break;
            }
            if n.is_gap() {
                clipped(u32::from(n.first()), u32::from(end));
            }
        }
    }

    /// Where column `x` is in a row, searched from node `from` (a row's first, or a node that
    /// starts at or before `x`) by the starts alone: a node ends where the next starts.
    #[inline]
    fn spot(&self, from: u16, x: u16) -> Spot {
        let mut spot = Spot {
            before: NIL,
            held: NIL,
            after: from,
            after_start: self.width,
        };
        while spot.after != NIL {
            let Some(n) = self.nodes.get(usize::from(spot.after)) else {
                spot.after = NIL;
                break;
            };
            let start = n.first();
            if start > x {
                spot.after_start = start;
                break;
            }
            (spot.before, spot.held, spot.after) = (spot.held, spot.after, n.next);
        }
        spot
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
            Paint::Texture(texture) => self.textured_span(y, x_start, x_end, texture),
        }
    }

    /// [`ScanMemory::span`] with a texture's row: kept as its runs of one colour.
    #[inline(never)]
    fn textured_span(&mut self, y: u32, x_start: u32, x_end: u32, texture: &RowTexture) -> u64 {
        let mut covered = 0;
        let x_end = x_end.min(u32::from(self.width));
        texture.runs(x_start, x_end, |a, b, colour| {
            covered += self.span(y, a, b, colour);
        });
        covered
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
        // A covered node that starts at or before `at`, where the search resumes (none: the
        // row's first node).
        let mut from = NIL;
        let mut covered = 0u64;
        while at < b {
            let Spot {
                before,
                held: cur,
                after: i,
                after_start: after,
            } = self.spot(if from == NIL { self.head(y) } else { from }, at);
            let found = (cur != NIL).then(|| self.node(cur));
            if found.is_some_and(|n| !n.is_gap()) {
                // (Past `at` in a well-formed list; never stalls in any other.)
                at = after.max(at + 1);
                from = cur;
                continue;
            }
            // `at` is uncovered: in gap node `gap`, or before the row's first node (no gap
            // node), between covered nodes `left` and `right` (or none), which starts at
            // `right_start`.
            let (left, gap, right, right_start) = (before, cur, i, after);
            let gap_start = found.map_or(0, |g| g.first());
            let gap_end = right_start.min(b);
            // The neighbours the piece touches.
            let prev = if at == gap_start { left } else { NIL };
            let next = if gap_end == right_start { right } else { NIL };
            let (end, c) = match pieces.piece(self, (at, gap_end), prev, next) {
                Piece::Left(end) => {
                    covered += u64::from(end - at);
                    self.left_grows(left, gap, end, right_start);
                    (at, from) = (end, left);
                    continue;
                }
                Piece::Right(start) => {
                    covered += u64::from(gap_end - start);
                    self.right_grows(row, (left, gap, right), start, gap_start);
                    if start == at {
                        (at, from) = (gap_end, right);
                    }
                    continue;
                }
                Piece::Flat(end, c) => (end, Some((c, false))),
                Piece::Level(end, c) => (end, Some((c, true))),
                Piece::Shaded(end) => (end, None),
            };
            let same = |m: &ScanNode| Some((m.colour, m.tagged())) == c;
            let left_same = prev != NIL && same(&self.node(prev));
            let right_same = end == gap_end && next != NIL && same(&self.node(next));
            covered += u64::from(end - at);
            match (left_same, right_same) {
                (true, true) => {
                    // The gap joins two intervals of its colour: one node.
                    let beyond = self.node(right).next;
                    if let Some(l) = self.node_mut(left) {
                        l.next = beyond;
                    }
                    self.release(gap);
                    self.release(right);
                    at = if beyond == NIL {
                        self.width
                    } else {
                        self.node(beyond).first()
                    };
                    from = left;
                    continue;
                }
                (true, false) => {
                    self.left_grows(left, gap, end, right_start);
                    (at, from) = (end, left);
                    continue;
                }
                (false, true) => {
                    self.right_grows(row, (left, gap, right), at, gap_start);
                    (at, from) = (end, right);
                    continue;
                }
                (false, false) => {}
            }
            // A new node, and a gap node after it when uncovered pixels follow: the gap node
            // the new node starts, moved after it when the new node is a pair, which cannot
            // take its place.
            let in_place = gap != NIL && at == gap_start;
            let tail = if end >= right_start {
                right
            } else if in_place && c.is_none() {
                gap
            } else {
                let g = ScanNode {
                    start: end | TAGGED,
                    colour: GAP,
                    next: right,
                };
                match self.alloc(g) {
                    Some(g) => g,
                    None => return self.run_out(covered - u64::from(end - at)),
                }
            };
            let node = |(colour, level): (u16, bool)| ScanNode {
                start: if level { at | TAGGED } else { at },
                colour,
                next: tail,
            };
            let linked = match c {
                Some(c) if in_place => {
                    if let Some(g) = self.node_mut(gap) {
                        *g = node(c);
                    }
                    Some(gap)
                }
                Some(c) => self.alloc(node(c)),
                None => {
                    let (first, shade) = pieces.shaded(at, end, tail);
                    self.alloc_pair(first, shade)
                }
            };
            let Some(i) = linked else {
                if tail != right && tail != gap {
                    self.release(tail);
                }
                return self.run_out(covered - u64::from(end - at));
            };
            if i != gap {
                if in_place {
                    // A pair where the gap started: the gap node after it, or gone.
                    self.link(row, left, i);
                    if tail == gap {
                        if let Some(g) = self.node_mut(gap) {
                            g.start = end | TAGGED;
                        }
                    } else {
                        self.release(gap);
                    }
                } else {
                    self.link(row, gap, i);
                }
            }
            (at, from) = (end, i);
        }
        self.covered += covered;
        covered
    }

    /// The pool is spent: the frame stops covering, with `covered` pixels of this span.
    #[cold]
    fn run_out(&mut self, covered: u64) -> u64 {
        self.exhausted = true;
        self.covered += covered;
        covered
    }

    /// Covered node `left`, which gap node `gap` follows, now runs to `end` (at most
    /// `right_start`, where the gap ends): the gap starts there, or is gone.
    fn left_grows(&mut self, left: u16, gap: u16, end: u16, right_start: u16) {
        if end >= right_start {
            let after = self.node(gap).next;
            if let Some(l) = self.node_mut(left) {
                l.next = after;
            }
            self.release(gap);
        } else if let Some(g) = self.node_mut(gap) {
            g.start = end | TAGGED;
        }
    }

    /// Covered node `right` now starts at `start` (the gap before it, `gap` after `left`,
    /// or the row's first pixels when `gap` is none, starting at `gap_start`, ends there, or
    /// is gone).
    fn right_grows(
        &mut self,
        row: usize,
        (left, gap, right): (u16, u16, u16),
        start: u16,
        gap_start: u16,
    ) {
        if let Some(r) = self.node_mut(right) {
            r.start = start | (r.start & TAGGED);
        }
        if gap != NIL && start <= gap_start {
            self.link(row, left, right);
            self.release(gap);
        }
    }
}

/// The nodes of a row with their ends ([`ScanMemory::row_nodes`]): each node read once, as
/// the one before it ends where it starts.
struct RowNodes<'a, 'm> {
    memory: &'a ScanMemory<'m>,
    /// The next node's index (NIL at the end) and the node.
    i: u16,
    n: ScanNode,
}

impl Iterator for RowNodes<'_, '_> {
    type Item = (u16, ScanNode, u16);

    #[inline]
    fn next(&mut self) -> Option<(u16, ScanNode, u16)> {
        if self.i == NIL {
            return None;
        }
        let (i, n) = (self.i, self.n);
        let end = if n.next == NIL {
            self.memory.width
        } else {
            self.n = self.memory.node(n.next);
            self.n.first()
        };
        self.i = n.next;
        Some((i, n, end))
    }
}

/// Where a column is in a row ([`ScanMemory::spot`]).
struct Spot {
    /// The node before `held` (none when `held` is the first searched).
    before: u16,
    /// The node holding the column (none before the row's first node).
    held: u16,
    /// The node after it (none at the row's end), and where it starts (the row's width).
    after: u16,
    after_start: u16,
}

/// What the next piece of a gap becomes.
enum Piece {
    /// Pixels up to `.0` joined the covered node before the gap (which touches it).
    Left(u16),
    /// Pixels from `.0` to the gap's end joined the covered node after it (which touches it).
    Right(u16),
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
