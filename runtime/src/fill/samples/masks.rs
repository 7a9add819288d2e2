//! Sample masks a polygon's samples make, for the tests: [`fill_polygon_masks`], the general
//! fill on the sample grid gathered into a pixel row's masks, which the tests compare with a
//! brute-force mask and with what the renderer's entry ([`super::fill_samples`]) hands over.

use core::ops::Range;

use super::{add_span_bits, Mask, SAMPLE_COLUMNS, SAMPLE_ROWS};
use crate::display::{Colour, SpanSink};
use crate::fill::{fill_polygon_rows, FillError, FixedPoint};

/// Receives a row's sample masks: pixels `x_start ..` of row `y`, one mask each, every one
/// non-zero at the run's ends (a run may hold zero masks between two covered pixels).
pub(crate) trait MaskSink {
    /// The masks of pixels `x_start .. x_start + masks.len()` of row `y`.
    fn masks(&mut self, y: u32, x_start: u32, masks: &[Mask], colour: Colour);
}

/// Fill `points` (as [`crate::fill::fill_polygon_rows`] takes them, in a `width`-pixel window)
/// on the sample grid of the pixel rows `rows`, and emit each row's masks, top to bottom;
/// returns the number of samples covered. `row_masks` is the caller's scratch row: at least
/// `width` masks, all zero, and left zero.
///
/// # Errors
/// The fill's, for the scaled points: [`FillError::TooManyVertices`], or
/// [`FillError::OutOfRange`] (naming the scaled point) when a scaled point leaves the fill's
/// range (only without the `wide-coordinates` feature, where five times the window's width
/// must be in range).
/// [`FillError::TooManyVertices`] with `max` the scratch row's length is also returned when
/// `row_masks` is shorter than `width`; nothing is drawn.
pub(crate) fn fill_polygon_masks<const SUB: u32, M: MaskSink + ?Sized>(
    points: &[FixedPoint<SUB>],
    width: u32,
    rows: Range<u32>,
    colour: Colour,
    row_masks: &mut [Mask],
    sink: &mut M,
) -> Result<u64, FillError<SUB>> {
    let mut scaled = [FixedPoint::<SUB>::default(); crate::fill::MAX_FILL_VERTICES];
    if points.len() > scaled.len() {
        return Err(FillError::TooManyVertices {
            count: points.len(),
            max: scaled.len(),
        });
    }
    if row_masks.len() < width as usize {
        return Err(FillError::TooManyVertices {
            count: width as usize,
            max: row_masks.len(),
        });
    }
    for (s, p) in scaled.iter_mut().zip(points) {
        // Saturated: a saturated point is out of the fill's range, or beyond any window.
        *s = FixedPoint::new(
            p.x.saturating_mul(SAMPLE_COLUMNS as i32),
            p.y.saturating_mul(SAMPLE_ROWS as i32),
        );
    }
    let mut rows_sink = MaskRows {
        masks: row_masks,
        y: u32::MAX,
        lo: u32::MAX,
        hi: 0,
        colour,
        sink,
    };
    let scaled_rows = rows.start.saturating_mul(SAMPLE_ROWS)..rows.end.saturating_mul(SAMPLE_ROWS);
    let covered = fill_polygon_rows(
        &scaled[..points.len()],
        width.saturating_mul(SAMPLE_COLUMNS),
        scaled_rows,
        colour,
        &mut rows_sink,
    )?;
    rows_sink.flush();
    Ok(covered)
}

/// The fill's spans on the sample grid, gathered into one pixel row's masks at a time (the
/// fill emits its rows top to bottom).
struct MaskRows<'a, M: MaskSink + ?Sized> {
    masks: &'a mut [Mask],
    /// The pixel row being gathered (`u32::MAX`: none yet).
    y: u32,
    /// Pixels `lo .. hi` of it hold bits.
    lo: u32,
    hi: u32,
    colour: Colour,
    sink: &'a mut M,
}

impl<M: MaskSink + ?Sized> MaskRows<'_, M> {
    /// Emit the gathered row and clear its masks.
    fn flush(&mut self) {
        if self.lo < self.hi {
            if let Some(run) = self.masks.get_mut(self.lo as usize..self.hi as usize) {
                self.sink.masks(self.y, self.lo, run, self.colour);
                run.fill(0);
            }
        }
        (self.lo, self.hi) = (u32::MAX, 0);
    }
}

impl<M: MaskSink + ?Sized> SpanSink for MaskRows<'_, M> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, _: Colour) {
        let row = y / SAMPLE_ROWS;
        if row != self.y {
            self.flush();
            self.y = row;
        }
        if let Some((lo, hi)) = add_span_bits(self.masks, y, x_start, x_end) {
            self.lo = self.lo.min(lo);
            self.hi = self.hi.max(hi);
        }
    }
}
