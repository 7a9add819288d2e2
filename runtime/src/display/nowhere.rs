//! [`Nowhere`]: a sink that drops every span. For frames whose pixels go elsewhere (a
//! scan-order frame keeps them in its scan memory) or are not wanted (measuring a frame's
//! span or record needs).

use super::{Colour, SpanSink};

/// Draws nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct Nowhere;

impl SpanSink for Nowhere {
    #[inline]
    fn span(&mut self, _: u32, _: u32, _: u32, _: Colour) {}
}
