//! What a baseline's frame writes and reports, the same for every baseline: spans of source
//! triangle ids into the id image ([`IdSink`]), and the pixels written with the bytes of
//! memory the frame needed besides the scene and the image ([`Frame`]), so that the table
//! compares what each method buys with its memory.

use peel_runtime::display::{Colour, SpanSink};

/// A baseline frame's figures.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Frame {
    /// Pixels written (overdraw included).
    pub written: u64,
    /// Bytes of the method's own memory at its peak in the frame: depth buffers, lists, work
    /// stacks (the scene and the id image are not counted).
    pub memory_bytes: u64,
}

/// The bytes of `n` values of `T`.
pub fn bytes<T>(n: usize) -> u64 {
    (n * std::mem::size_of::<T>()) as u64
}

/// Spans of one polygon into an id image of `width` columns: `id + 1` per pixel.
pub struct IdSink<'a> {
    /// The id image, row-major.
    pub ids: &'a mut [u32],
    /// Its width.
    pub width: usize,
    /// The source triangle whose spans come next.
    pub id: u32,
    /// Pixels written so far.
    pub written: u64,
}

impl<'a> IdSink<'a> {
    /// A sink over `ids` (`width` columns), cleared to 0 (background) first.
    pub fn cleared(ids: &'a mut [u32], width: u32) -> Self {
        ids.fill(0);
        IdSink {
            ids,
            width: width as usize,
            id: 0,
            written: 0,
        }
    }
}

impl SpanSink for IdSink<'_> {
    fn span(&mut self, y: u32, x0: u32, x1: u32, _: Colour) {
        let row = y as usize * self.width;
        self.ids[row + x0 as usize..row + x1 as usize].fill(self.id + 1);
        self.written += u64::from(x1 - x0);
    }
}

/// The largest value a count reached during a frame.
#[derive(Debug, Clone, Copy, Default)]
pub struct Peak(pub usize);

impl Peak {
    /// Note the current value `n`.
    #[inline]
    pub fn note(&mut self, n: usize) {
        self.0 = self.0.max(n);
    }
}
