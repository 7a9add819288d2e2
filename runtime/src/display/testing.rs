//! A checking span sink for the crate's unit tests (fill, coverage and render). It panics by
//! design, so it is built only for them and is no part of the public API.
//!
//! [`MockTarget`] panics on what a fill must never do: a span outside the image or empty, and
//! (unless allowed, as painter's-algorithm renders need) a pixel written twice. It prints as
//! ASCII art for snapshot tests: `.` for an unwritten pixel, and `A`, `B`, ... for colours in
//! the order they were first drawn. It has a fixed size and no allocation, like the crate.

use core::fmt;

use super::{Colour, SpanSink};

/// Symbols of the colours, in order of first use.
const SYMBOLS: &[u8; 62] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";

/// A `W x H` image that records which colour wrote each pixel. Panics on misuse (by design:
/// it is a test helper).
#[derive(Debug, Clone)]
pub struct MockTarget<const W: usize, const H: usize> {
    /// 0 = unwritten, else 1 + index into `palette`.
    cells: [[u8; W]; H],
    palette: [Colour; 62],
    palette_len: usize,
    allow_overdraw: bool,
    spans: usize,
    pixels: u64,
}

impl<const W: usize, const H: usize> Default for MockTarget<W, H> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const W: usize, const H: usize> MockTarget<W, H> {
    /// An empty image that panics when a pixel is written twice.
    pub const fn new() -> Self {
        MockTarget {
            cells: [[0; W]; H],
            palette: [Colour::new(0, 0, 0); 62],
            palette_len: 0,
            allow_overdraw: false,
            spans: 0,
            pixels: 0,
        }
    }

    /// An empty image where a later span may paint over an earlier one (painter's algorithm).
    pub const fn allowing_overdraw() -> Self {
        let mut m = Self::new();
        m.allow_overdraw = true;
        m
    }

    /// The colour of pixel `(x, y)`, `None` if unwritten or outside.
    pub fn get(&self, x: usize, y: usize) -> Option<Colour> {
        match self.cells.get(y)?.get(x)? {
            0 => None,
            &c => Some(self.palette[usize::from(c) - 1]),
        }
    }

    /// Whether pixel `(x, y)` was written.
    pub fn written(&self, x: usize, y: usize) -> bool {
        self.get(x, y).is_some()
    }

    /// Spans received.
    pub fn spans(&self) -> usize {
        self.spans
    }

    /// Pixels written, counting overdraw.
    pub fn pixels(&self) -> u64 {
        self.pixels
    }

    /// Pixels currently written.
    pub fn written_count(&self) -> usize {
        self.cells.iter().flatten().filter(|&&c| c != 0).count()
    }

    fn symbol_index(&mut self, colour: Colour) -> u8 {
        if let Some(i) = self.palette[..self.palette_len]
            .iter()
            .position(|&c| c == colour)
        {
            return i as u8 + 1;
        }
        assert!(
            self.palette_len < SYMBOLS.len(),
            "MockTarget: more than 62 colours"
        );
        self.palette[self.palette_len] = colour;
        self.palette_len += 1;
        self.palette_len as u8
    }
}

impl<const W: usize, const H: usize> SpanSink for MockTarget<W, H> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        assert!(
            (y as usize) < H && (x_end as usize) <= W,
            "MockTarget: span y={y} x={x_start}..{x_end} outside {W}x{H}"
        );
        assert!(
            x_start < x_end,
            "MockTarget: empty span y={y} x={x_start}..{x_end}"
        );
        let c = self.symbol_index(colour);
        let allow = self.allow_overdraw;
        for (x, cell) in self.cells[y as usize][x_start as usize..x_end as usize]
            .iter_mut()
            .enumerate()
        {
            assert!(
                allow || *cell == 0,
                "MockTarget: overdraw at ({}, {y})",
                x_start as usize + x
            );
            *cell = c;
        }
        self.spans += 1;
        self.pixels += u64::from(x_end - x_start);
    }
}

impl<const W: usize, const H: usize> fmt::Display for MockTarget<W, H> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use fmt::Write;
        for row in &self.cells {
            for &c in row {
                f.write_char(match c {
                    0 => '.',
                    c => char::from(SYMBOLS[usize::from(c) - 1]),
                })?;
            }
            f.write_char('\n')?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::ToString;

    #[test]
    fn records_and_prints() {
        let mut m = MockTarget::<4, 2>::new();
        m.span(0, 1, 3, Colour::new(1, 2, 3));
        m.span(1, 0, 1, Colour::new(9, 9, 9));
        m.span(1, 3, 4, Colour::new(1, 2, 3));
        assert_eq!(m.to_string(), ".AA.\nB..A\n");
        assert_eq!(m.get(1, 0), Some(Colour::new(1, 2, 3)));
        assert_eq!(m.get(0, 0), None);
        assert_eq!((m.spans(), m.pixels(), m.written_count()), (3, 4, 4));
    }

    #[test]
    #[should_panic(expected = "overdraw at (2, 0)")]
    fn panics_on_overdraw() {
        let mut m = MockTarget::<4, 2>::new();
        m.span(0, 0, 3, Colour::default());
        m.span(0, 2, 4, Colour::default());
    }

    #[test]
    fn overdraw_can_be_allowed() {
        let mut m = MockTarget::<4, 1>::allowing_overdraw();
        m.span(0, 0, 3, Colour::new(1, 1, 1));
        m.span(0, 2, 4, Colour::new(2, 2, 2));
        assert_eq!(m.to_string(), "AABB\n");
    }

    #[test]
    #[should_panic(expected = "outside")]
    fn panics_out_of_bounds() {
        MockTarget::<4, 2>::new().span(0, 2, 5, Colour::default());
    }

    #[test]
    #[should_panic(expected = "outside")]
    fn panics_on_row_out_of_bounds() {
        MockTarget::<4, 2>::new().span(2, 0, 1, Colour::default());
    }

    #[test]
    #[should_panic(expected = "empty span")]
    fn panics_on_empty_span() {
        MockTarget::<4, 2>::new().span(0, 2, 2, Colour::default());
    }
}
