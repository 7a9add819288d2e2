//! How pending pixels leave the pool: each its average colour ([`average`]), the uncovered
//! samples in the background, drained into a sink at the end of a frame or band
//! ([`Pending::drain`]) or read a row at a time by a scan-order frame's read-out
//! ([`Pending::row_pixels`]), which leaves them pending.

use super::{Pending, PendingPixel, FALLEN_BACK, NONE, SAMPLES, SUM_BITS};
use crate::display::{Colour, SpanSink};

impl Pending<'_> {
    /// End the frame (or band): every pending pixel takes `background` for its uncovered
    /// samples and is painted into `sink`, row by row, in column order; then the pool is
    /// empty again ([`Pending::peak`] stays until [`Pending::clear`]). Returns the pixels
    /// painted.
    pub fn drain<S: SpanSink + ?Sized>(&mut self, background: Colour, sink: &mut S) -> u64 {
        let fill = [background.r, background.g, background.b].map(u32::from);
        let mut painted = 0;
        for y in 0..self.height {
            let mut at = self.head(y) & !FALLEN_BACK;
            while let Some(r) = self.record(at) {
                let x = u32::from(r.x);
                sink.span(y, x, x + 1, average(r, fill));
                painted += 1;
                at = r.next;
            }
        }
        self.empty();
        painted
    }
}

impl Pending<'_> {
    /// Row `y`'s pending pixels in column order, each with the colour [`Pending::drain`] would
    /// paint it (`background` for its uncovered samples), leaving them pending: for a frame
    /// read out after the walk ([`crate::scan::ScanFrame`], which merges them into its gaps).
    pub fn row_pixels(&self, y: u32, background: Colour) -> PendingRow<'_> {
        PendingRow {
            records: &*self.records,
            at: self.head(y) & !FALLEN_BACK,
            fill: [background.r, background.g, background.b].map(u32::from),
        }
    }
}

/// The pending pixels of a row with their colours, column by column: [`Pending::row_pixels`].
#[derive(Debug, Clone)]
pub struct PendingRow<'a> {
    records: &'a [PendingPixel],
    at: u16,
    fill: [u32; 3],
}

impl Iterator for PendingRow<'_> {
    /// A pixel's column and colour.
    type Item = (u32, Colour);

    fn next(&mut self) -> Option<(u32, Colour)> {
        let r = self
            .records
            .get(usize::from(self.at))
            .filter(|_| self.at < NONE)?;
        self.at = r.next;
        Some((u32::from(r.x), average(r, self.fill)))
    }
}

/// The average of [`SAMPLES`] samples: `r`'s, plus its missing samples in `fill`, rounded to
/// nearest.
pub(super) fn average(r: &PendingPixel, fill: [u32; 3]) -> Colour {
    let acc = r.acc();
    let missing = SAMPLES - r.mask().count_ones();
    let channel = |k: u32| {
        let sum = (acc >> (SAMPLES + k * SUM_BITS)) as u32 & ((1 << SUM_BITS) - 1);
        let total = sum + missing * fill[k as usize];
        ((2 * total + SAMPLES) / (2 * SAMPLES)) as u8
    };
    Colour::new(channel(0), channel(1), channel(2))
}
