//! The small-polygon fill: most polygons of a mesh frame cover a few pixel centres, where the
//! scanline fill's set-up (a walk per edge, with its divisions, then crossings sorted and
//! paired) costs more than testing the centres of the sample rectangle against each edge.
//!
//! It gives exactly [`super::fill_in`]'s spans. On a row the scanline fill's crossing of edge
//! `e` is `x_e`, the first pixel whose centre is at or right of the edge; pixel `i` is drawn
//! when an odd number of the `x_e` are `<= i`, and two drawn neighbours `i - 1`, `i` lie in one
//! span unless some `x_e` is `i` (the sorted crossings pair into spans, so a span ends exactly
//! where a count changes). With the edge's top `t`, `dy > 0`, "the centre `(c_x, c_y)` is at or
//! right of the edge" is the integer edge function `(2 c_x - 2 t_x) dy - dx (2 c_y - 2 t_y)
//! >= 0`, increasing along the row, so `x_e` is the number of the rectangle's centres where it
//! is negative; an edge counts on the rows whose centre `y` is in `[t_y, b_y)`, as its walk
//! does. The rectangle's pixels are the bits of two words: their parity, and the `x_e`s.

use super::{edge::Coord, FixedPoint, Shader};
use crate::display::SpanSink;

/// Sample rectangles of at most this many pixels are filled by testing their centres (at
/// most 32: a bit of a word each).
pub(crate) const SMALL_AREA: u32 = 32;

/// Fill `points` as [`super::fill_in`] would (with room for every edge), when `rect` is
/// [`super::sample_rect`]`(points, width, height)` cut to the rows drawn and holds at most
/// [`SMALL_AREA`] pixels; `None`, with nothing drawn, for a larger rectangle, a point farther
/// than a pixel outside it (a polygon clamped to the window) or more than 8 subpixel bits.
pub(crate) fn fill_small<const SUB: u32, S: SpanSink + ?Sized, P: Shader>(
    points: &[FixedPoint<SUB>],
    rect: [u32; 4],
    shader: &mut P,
    sink: &mut S,
) -> Option<u64> {
    const { assert!(SMALL_AREA <= 32) };
    if SUB > 8 {
        return None;
    }
    let [x0, y0, x1, y1] = rect;
    let (w, h) = (x1.checked_sub(x0)?, y1.checked_sub(y0)?);
    if w.checked_mul(h)? > SMALL_AREA {
        return None;
    }
    let s = 1i32 << SUB;
    // Points relative to the rectangle's corner `(x0, y0) S`, within `limit` of it. With
    // `w, h <= 32` and `S <= 2^8` every edge function below is at most
    // `2 (4 * 32 + 5) S (2 * 32 + 4) S < 2^31` in magnitude (doubled centres within
    // `(2 * 32 + 1) S`, doubled points within `2 limit`, `|dx|, |dy| <= 2 limit`).
    let limit = Coord::from((SMALL_AREA as i32 + 2) * s);
    #[allow(clippy::unnecessary_fallible_conversions)]
    let (ox, oy) = (
        Coord::try_from(x0).ok()? * Coord::from(s),
        Coord::try_from(y0).ok()? * Coord::from(s),
    );
    let relative = |p: FixedPoint<SUB>| -> Option<(i32, i32)> {
        let (u, v) = (Coord::from(p.x) - ox, Coord::from(p.y) - oy);
        let inside = |d: Coord| -limit <= d && d <= limit;
        // `Coord` is `i64` with `wide-coordinates`, `i32` without.
        #[allow(clippy::unnecessary_cast)]
        let relative = (u as i32, v as i32);
        (inside(u) && inside(v)).then_some(relative)
    };
    let (w, h) = (w as i32, h as i32);
    let row_bits = if w >= 32 { u32::MAX } else { (1u32 << w) - 1 };
    // Per pixel `r * w + i`: the parity of the crossings at or left of it, and whether one is
    // at it.
    let (mut parity, mut crossing) = (0u32, 0u32);
    let mut a = relative(*points.first()?)?;
    for k in 0..points.len() {
        let next = points.get(k + 1).or(points.first()).copied()?;
        let b = relative(next)?;
        let (top, bottom) = match a.1.cmp(&b.1) {
            core::cmp::Ordering::Less => (a, b),
            core::cmp::Ordering::Greater => (b, a),
            core::cmp::Ordering::Equal => {
                a = b;
                continue;
            }
        };
        a = b;
        // The edge's rows of the rectangle: centres `(2r + 1) S` in `[2 t_y, 2 b_y)`.
        let row = |v: i32| ((2 * v + s - 1) >> (SUB + 1)).max(0).min(h);
        let (r0, r1) = (row(top.1), row(bottom.1));
        let (dx, dy) = (bottom.0 - top.0, bottom.1 - top.1);
        let (step_x, step_y) = (2 * s * dy, 2 * s * dx);
        let mut f_row = (s - 2 * top.0) * dy - dx * ((2 * r0 + 1) * s - 2 * top.1);
        for r in r0..r1 {
            let (mut f, mut x_e) = (f_row, 0);
            while x_e < w && f < 0 {
                f += step_x;
                x_e += 1;
            }
            if x_e < w {
                let at = r * w + x_e;
                parity ^= (row_bits << at) & (row_bits << (r * w));
                crossing |= 1 << at;
            }
            f_row -= step_y;
        }
    }
    let mut pixels = 0u64;
    for r in 0..h {
        let (p, c) = (parity >> (r * w), crossing >> (r * w));
        let mut i = 0;
        while i < w {
            if (p >> i) & 1 == 0 {
                i += 1;
                continue;
            }
            let start = i;
            i += 1;
            while i < w && (p >> i) & 1 == 1 && (c >> i) & 1 == 0 {
                i += 1;
            }
            let (y, xs, xe) = (y0 + r as u32, x0 + start as u32, x0 + i as u32);
            shader.span(sink, y, xs, xe);
            pixels += u64::from(xe - xs);
        }
    }
    Some(pixels)
}
