//! Fill: integer scanline fill of a polygon already clipped to the screen window
//! ([`fill_polygon`]).
//!
//! The classic scanline fill, in fixed point: every non-horizontal edge is walked down the
//! scanlines with an integer quotient-and-remainder walk (see `edge.rs`, no float and no
//! division per row); on each row the crossings of the active edges are sorted and paired,
//! and each pair `[x_left, x_right)` becomes one span. Sorting and pairing (even-odd) also
//! copes with polygons that snapping made slightly non-convex, self-touching or degenerate.
//!
//! # Ownership of boundary pixels (the top-left rule)
//! A pixel is drawn when its centre `(i + 1/2, j + 1/2)` is inside. A centre exactly on an
//! edge belongs to the polygon on the edge's right: spans are `[first centre >= x_left,
//! first centre >= x_right)`, so left edges are drawn and right edges not. An edge covers the
//! scanlines whose centre `y` satisfies `y_top <= y < y_bottom` and horizontal edges none, so
//! a vertex counts only for the edge it is the top of (with y down, as in Direct3D's
//! rasterization rules), and a horizontal top edge is drawn while a bottom one is not. Because
//! the crossing of a shared edge is computed exactly (rationals, not floats) and identically
//! from both sides, two polygons sharing an edge never both draw a pixel nor both skip one.

mod edge;
pub mod gradient;
pub mod samples;
mod small;
pub mod texture;

#[cfg(test)]
mod tests;

use core::fmt;

use crate::display::{Colour, SpanSink};
pub use edge::{Coord, EdgeWalk};
use gradient::Gradient;

/// Fractional bits of the renderer's fixed-point screen coordinates ([`SubpixelPoint`]).
pub const SUBPIXEL_BITS: u32 = 8;

/// Largest `SUB` the fill accepts (checked at compile time); keeps every edge walk within
/// `i64` for any `i32` coordinates.
pub const MAX_SUBPIXEL_BITS: u32 = 24;

/// Most vertices a polygon handed to [`fill_polygon`] may have.
pub const MAX_FILL_VERTICES: usize = 64;

/// Largest coordinate of a [`FixedPoint<SUB>`] the fill accepts: any `i32` with the
/// `wide-coordinates` feature (default), else `2^(29 - SUB) - 1` (8191 pixels at
/// [`SUBPIXEL_BITS`]), and then no negative coordinate either: the edge walk is then set up
/// in 32-bit arithmetic (see `edge.rs`). The renderer refuses a window beyond it up front
/// ([`crate::RenderError::ImageTooLarge`]) and clamps every point to its window, so its
/// polygons always fit.
pub const fn coordinate_limit<const SUB: u32>() -> i32 {
    if cfg!(feature = "wide-coordinates") {
        i32::MAX
    } else if SUB <= 29 {
        (1 << (29 - SUB)) - 1
    } else {
        0
    }
}

/// A screen point in fixed point, the format of every screen coordinate the fill and the
/// renderer use: each coordinate is an `i32` count of `2^-SUB` pixel, its value in pixels
/// times `2^SUB` (`SUB` fractional bits), x to the right and y down from the window's top-left
/// corner, so pixel `(i, j)` has its sample point (its centre) at
/// `((i + 1/2) 2^SUB, (j + 1/2) 2^SUB)`.
///
/// The precision is part of the type: the fill functions take `&[FixedPoint<SUB>]` and draw
/// at that `SUB`, so a point snapped at one precision cannot reach a fill at another. The
/// renderer's points are [`SubpixelPoint`]s.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FixedPoint<const SUB: u32> {
    /// x times `2^SUB`.
    pub x: i32,
    /// y times `2^SUB`.
    pub y: i32,
}

/// A point at the renderer's precision, [`SUBPIXEL_BITS`].
pub type SubpixelPoint = FixedPoint<SUBPIXEL_BITS>;

impl<const SUB: u32> FixedPoint<SUB> {
    /// A point from its raw fixed-point coordinates.
    pub const fn new(x: i32, y: i32) -> Self {
        FixedPoint { x, y }
    }

    /// Snap a screen position in pixels to the nearest point of the `2^-SUB` grid (halves
    /// away from zero). Out-of-range values saturate and NaN becomes 0, so a bad vertex can
    /// misplace a polygon but never break the fill. The same input always gives the same
    /// point, which is what keeps vertices shared by two polygons shared after snapping.
    pub fn snap(x: f32, y: f32) -> Self {
        FixedPoint {
            x: round_scaled(x, SUB),
            y: round_scaled(y, SUB),
        }
    }

    /// [`Self::snap`] from `f64` coordinates.
    pub fn snap_f64(x: f64, y: f64) -> Self {
        let scale = f64::from(1u32 << SUB);
        FixedPoint {
            x: libm::round(x * scale) as i32,
            y: libm::round(y * scale) as i32,
        }
    }

    /// The point at whole pixel coordinates `(x, y)` (a pixel corner), saturating.
    pub const fn from_pixels(x: i32, y: i32) -> Self {
        FixedPoint {
            x: x.saturating_mul(1 << SUB),
            y: y.saturating_mul(1 << SUB),
        }
    }
}

/// A soft-float ABI: every `f32` operation is a library call, so rounding works on the bits.
const SOFT_FLOAT: bool = cfg!(all(target_arch = "arm", not(target_abi = "eabihf")));

/// `v * 2^k` (`k < 32`) rounded to the nearest integer, halves away from zero, saturating,
/// NaN to 0: the same as `libm::roundf(v * 2^k) as i32`, without its bit twiddling (it runs
/// for every snapped vertex). With hardware floats [`round_f32_float`] of the product; without
/// (a soft-float ABI, where each `f32` operation is a library call) [`round_bits_scaled`], on
/// the integer bits, where the exact scaling is an exponent rather than a multiply. The two
/// agree on every input (tested against `libm` and each other).
#[inline]
fn round_scaled(v: f32, k: u32) -> i32 {
    if SOFT_FLOAT {
        round_bits_scaled(v, k)
    } else {
        round_f32_float(v * (1u32 << k) as f32)
    }
}

/// `v` rounded as [`round_scaled`] rounds it (`k = 0`), in `f32` arithmetic. Below `2^23` in
/// magnitude the truncation and the fraction `v - t` are exact, so comparing the fraction with
/// one half decides exactly; above, every `f32` is already an integer.
#[inline]
fn round_f32_float(v: f32) -> i32 {
    const EXACT: f32 = 8_388_608.0; // 2^23
    if !(v > -EXACT && v < EXACT) {
        return v as i32;
    }
    let t = v as i32;
    let fraction = v - t as f32;
    if fraction >= 0.5 {
        t + 1
    } else if fraction <= -0.5 {
        t - 1
    } else {
        t
    }
}

/// [`round_scaled`] on the bits of `v * 2^k`: its significand `m` (with the hidden bit) times
/// `2^(e - 150)` (`e` the scaled exponent) is shifted right with half an output unit added
/// (halves away from zero in magnitude), or left when it is already an integer. The scaling
/// adds `k` to the exponent field of a finite, non-zero `v`: a product that would overflow to
/// infinity saturates as infinity does, a subnormal `v` gives 0 as its product (below
/// `2^-94`) does.
#[inline]
fn round_bits_scaled(v: f32, k: u32) -> i32 {
    let bits = v.to_bits();
    let field = (bits >> 23) & 0xff;
    if field == 0xff && bits & 0x007f_ffff != 0 {
        return 0; // NaN
    }
    let exponent = if field == 0 { 0 } else { field + k };
    let m = (bits & 0x007f_ffff) | 0x0080_0000;
    let negative = bits >> 31 != 0;
    let magnitude = if exponent < 126 {
        // |v| < 0.5 (zeros and subnormals too).
        0
    } else if exponent <= 150 {
        let shift = 150 - exponent; // 0..=24
        (m + ((1 << shift) >> 1)) >> shift
    } else if exponent < 158 {
        m << (exponent - 150) // below 2^31
    } else if negative {
        return i32::MIN; // at most -2^31, or -infinity
    } else {
        return i32::MAX;
    };
    // `magnitude < 2^31` here.
    let r = magnitude as i32;
    if negative {
        -r
    } else {
        r
    }
}

/// The pixels `[x0, x1) x [y0, y1)` whose sample points lie in the half-open box
/// `[min, max)` of `points`, within a `width x height` window, or
/// `None` when there is none. Every pixel the fill draws for `points` is in it (a span
/// `[x_left, x_right)` and an edge's rows `[y_top, y_bottom)` are half-open the same way), so
/// `None` means the fill would draw nothing, and a rectangle already covered means the
/// polygon cannot show. Points must be in the fill's range ([`coordinate_limit`]).
pub fn sample_rect<const SUB: u32>(
    points: &[FixedPoint<SUB>],
    width: u32,
    height: u32,
) -> Option<[u32; 4]> {
    let first = points.first()?;
    let (mut lo, mut hi) = (*first, *first);
    for p in points {
        lo = FixedPoint::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = FixedPoint::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    let pixel = |v: i32, limit: u32| -> u32 {
        #[allow(clippy::unnecessary_fallible_conversions)]
        let limit = Coord::try_from(limit).unwrap_or(Coord::MAX);
        edge::first_centre::<SUB>(v).clamp(0, limit) as u32
    };
    let (x0, x1) = (pixel(lo.x, width), pixel(hi.x, width));
    let (y0, y1) = (pixel(lo.y, height), pixel(hi.y, height));
    (x0 < x1 && y0 < y1).then_some([x0, y0, x1, y1])
}

/// Why [`fill_polygon`] drew nothing (a polygon of [`FixedPoint<SUB>`]s).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FillError<const SUB: u32 = SUBPIXEL_BITS> {
    /// The polygon has more vertices than [`MAX_FILL_VERTICES`].
    TooManyVertices {
        /// Vertices given.
        count: usize,
        /// Vertices the fill holds.
        max: usize,
    },
    /// A point lies outside `0..=limit` ([`coordinate_limit`]; only without the
    /// `wide-coordinates` feature).
    OutOfRange {
        /// The point.
        point: FixedPoint<SUB>,
        /// The largest coordinate accepted.
        limit: i32,
    },
}

impl<const SUB: u32> fmt::Display for FillError<SUB> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            FillError::TooManyVertices { count, max } => {
                write!(
                    f,
                    "polygon of {count} vertices, the fill holds at most {max}"
                )
            }
            FillError::OutOfRange { point, limit } => write!(
                f,
                "point ({}, {}) outside the fill's range 0..={limit} \
                 (enable the `wide-coordinates` feature)",
                point.x, point.y
            ),
        }
    }
}

#[cfg(feature = "std")]
impl<const SUB: u32> std::error::Error for FillError<SUB> {}

/// Fill the polygon `points` (either winding, inside the window `[0, width] x [0, height]`)
/// with the top-left rule and emit its spans; returns the number of pixels emitted.
///
/// The points' precision `SUB` is at most [`MAX_SUBPIXEL_BITS`] (checked at compile time; the
/// renderer's is [`SUBPIXEL_BITS`]). The polygon is filled with the
/// even-odd rule, so any closed point list is accepted: non-convex, self-intersecting, with
/// repeated or collinear points, or of zero area (which draws nothing). Points outside the
/// window are fine (any `i32`, or any coordinate in `0..=`[`coordinate_limit`] without the
/// `wide-coordinates` feature): spans are clipped to it, so the sink only ever receives
/// `x_start < x_end <= width`, `y < height`; a convex polygon gives at most one span per row.
///
/// # Errors
/// [`FillError::TooManyVertices`] when `points.len() > MAX_FILL_VERTICES`,
/// [`FillError::OutOfRange`] for a point beyond [`coordinate_limit`]; nothing is drawn.
pub fn fill_polygon<const SUB: u32, S: SpanSink + ?Sized>(
    points: &[FixedPoint<SUB>],
    width: u32,
    height: u32,
    colour: Colour,
    sink: &mut S,
) -> Result<u64, FillError<SUB>> {
    fill_polygon_rows(points, width, 0..height, colour, sink)
}

/// [`fill_polygon`] of the rows `rows` only: the spans the whole polygon's fill has on those
/// rows, for a frame drawn in bands of rows (an edge starting above the band is walked down to
/// it, so the crossings are the same).
///
/// # Errors
/// As [`fill_polygon`].
pub fn fill_polygon_rows<const SUB: u32, S: SpanSink + ?Sized>(
    points: &[FixedPoint<SUB>],
    width: u32,
    rows: core::ops::Range<u32>,
    colour: Colour,
    sink: &mut S,
) -> Result<u64, FillError<SUB>> {
    const {
        assert!(
            SUB <= MAX_SUBPIXEL_BITS,
            "SUB must be at most MAX_SUBPIXEL_BITS"
        );
    }
    if points.len() > MAX_FILL_VERTICES {
        return Err(FillError::TooManyVertices {
            count: points.len(),
            max: MAX_FILL_VERTICES,
        });
    }
    if !cfg!(feature = "wide-coordinates") {
        let limit = coordinate_limit::<SUB>();
        let inside = |v: i32| (0..=limit).contains(&v);
        if let Some(&point) = points.iter().find(|p| !(inside(p.x) && inside(p.y))) {
            return Err(FillError::OutOfRange { point, limit });
        }
    }

    // Typical polygons (clipped triangles and quads) get small arrays: initialising the
    // full-size ones would cost more than filling a small polygon.
    Ok(if points.len() <= SMALL_POLYGON {
        let mut edges = [EdgeWalk::default(); SMALL_POLYGON];
        fill_in(points, &mut edges, width, rows, &mut { colour }, sink)
    } else {
        let mut edges = [EdgeWalk::default(); MAX_FILL_VERTICES];
        fill_in(points, &mut edges, width, rows, &mut { colour }, sink)
    })
}

/// [`fill_in`] of a polygon whose [`sample_rect`] cut to `rows` is `rect`. On a soft-float
/// ARM core (ARMv6-M: no divide instruction either) a small rectangle's centres are tested
/// one by one (`small.rs`: the same spans without the walks' divisions), which saves 2.5-3% of a
/// mesh frame there; with a divide instruction the scanline set-up is the cheaper one (the
/// Cortex-M4F's frame took 1-2% more), and elsewhere the scanline fill draws all.
#[allow(clippy::too_many_arguments)]
pub(crate) fn fill_in_rect<const SUB: u32, S: SpanSink + ?Sized, P: Shader>(
    points: &[FixedPoint<SUB>],
    rect: [u32; 4],
    edges: &mut [EdgeWalk],
    width: u32,
    rows: core::ops::Range<u32>,
    shader: &mut P,
    sink: &mut S,
) -> u64 {
    if SOFT_FLOAT && points.len() <= edges.len().min(MAX_FILL_VERTICES) {
        if let Some(pixels) = small::fill_small(points, rect, shader, sink) {
            return pixels;
        }
    }
    fill_in(points, edges, width, rows, shader, sink)
}

/// What a fill paints its spans with: one [`Colour`], or a polygon's [`Gradient`], which
/// hands each row its [`RowShade`](crate::display::RowShade). The fill is generic over it, so a
/// flat polygon's fill is the plain one, with no test per span.
pub(crate) trait Shader {
    /// Paint `x_start .. x_end` of row `y` into `sink`.
    fn span<S: SpanSink + ?Sized>(&mut self, sink: &mut S, y: u32, x_start: u32, x_end: u32);
}

impl Shader for Colour {
    #[inline]
    fn span<S: SpanSink + ?Sized>(&mut self, sink: &mut S, y: u32, x_start: u32, x_end: u32) {
        sink.span(y, x_start, x_end, *self);
    }
}

impl Shader for crate::display::Transparent {
    #[inline]
    fn span<S: SpanSink + ?Sized>(&mut self, sink: &mut S, y: u32, x_start: u32, x_end: u32) {
        sink.transparent_span(y, x_start, x_end, self.colour, self.opacity);
    }
}

impl<const SUB: u32> Shader for Gradient<SUB> {
    #[inline]
    fn span<S: SpanSink + ?Sized>(&mut self, sink: &mut S, y: u32, x_start: u32, x_end: u32) {
        let shade = self.row(y);
        sink.shaded_span(y, x_start, x_end, &shade);
    }
}

/// Vertex count up to which [`fill_polygon`] uses its small arrays.
const SMALL_POLYGON: usize = 16;

/// [`fill_polygon`] (without its checks) of rows `rows` only, with room for `edges.len()`
/// edges, at most [`MAX_FILL_VERTICES`]; edges past that are ignored. The renderer passes the
/// edge memory of its workspace, so nothing is initialised per polygon and the binary holds
/// one fill. An edge starting above `rows` is walked down to it row by row: the same crossings
/// as the whole polygon's fill, so a frame drawn in bands has the same pixels.
pub(crate) fn fill_in<const SUB: u32, S: SpanSink + ?Sized, P: Shader>(
    points: &[FixedPoint<SUB>],
    edges: &mut [EdgeWalk],
    width: u32,
    rows: core::ops::Range<u32>,
    shader: &mut P,
    sink: &mut S,
) -> u64 {
    #[allow(clippy::unnecessary_fallible_conversions)]
    let first_row = Coord::try_from(rows.start).unwrap_or(Coord::MAX);
    const N: usize = MAX_FILL_VERTICES;
    let room = edges.len().min(N);
    // Edges that cross at least one row centre of the window, sorted by first row.
    let mut count = 0;
    for (i, &a) in points.iter().enumerate() {
        // Every index below is in range (`count < room <= edges.len()`); `get` keeps the
        // fill panic-free.
        let b = points.get(i + 1).or(points.first()).copied().unwrap_or(a);
        if let Some(mut walk) = EdgeWalk::for_edge::<SUB>(a, b, rows.end) {
            while walk.row < first_row.min(walk.row_end) {
                walk.step();
            }
            if walk.row >= walk.row_end {
                continue;
            }
            if count >= room {
                break;
            }
            // Insertion keeps `edges[..count]` sorted by `row`. (Swapping neighbours rather
            // than shifting keeps the optimiser from calling a `memmove` it must then link.)
            if let Some(slot) = edges.get_mut(count) {
                *slot = walk;
            }
            let mut k = count;
            while let Some([prev, this]) = k.checked_sub(1).and_then(|j| edges.get_mut(j..=k)) {
                if prev.row <= this.row {
                    break;
                }
                core::mem::swap(prev, this);
                k -= 1;
            }
            count += 1;
        }
    }
    let Some(first) = edges.first().filter(|_| count > 0) else {
        return 0;
    };

    // Infallible with `wide-coordinates` (`i64`), saturating without (`i32`).
    #[allow(clippy::unnecessary_fallible_conversions)]
    let width = Coord::try_from(width).unwrap_or(Coord::MAX);
    // Indices into `edges` of the edges crossing the current row, in x order.
    let mut active = [0u8; N];
    let mut n_active = 0;
    let mut next = 0;
    let mut row = first.row;
    let mut pixels = 0u64;
    loop {
        while next < count && edges.get(next).is_some_and(|e| e.row == row) {
            active[n_active.min(N - 1)] = next as u8;
            n_active += 1;
            next += 1;
        }
        // Sort by crossing; the order barely changes between rows, so insertion sort is
        // linear in practice (and trivial for the two edges of a convex polygon).
        // (`x_of` and the `min`s only make the bounds provable: indices are always in range.)
        let x_of = |a: u8| edges.get(usize::from(a)).map_or(0, |e| e.x);
        let n_active_max = n_active.min(N);
        for i in 1..n_active_max {
            let e = active[i];
            let x = x_of(e);
            let mut k = i;
            while k > 0 && x_of(active[k - 1]) > x {
                active[k] = active[k - 1];
                k -= 1;
            }
            active[k] = e;
        }
        // Pair the crossings. Every edge covers the same half-open rows, so a closed polygon
        // always has an even count; an odd last one could only come from a bug and is ignored.
        let mut p = 0;
        while p + 1 < n_active_max {
            let start = x_of(active[p]).clamp(0, width);
            let end = x_of(active[p + 1]).clamp(0, width);
            if start < end {
                // In range: 0 <= row < height and 0 <= start < end <= width, all u32.
                shader.span(sink, row as u32, start as u32, end as u32);
                pixels += (end - start) as u64;
            }
            p += 2;
        }
        // Step the active edges and drop the finished ones, keeping the x order.
        let mut kept = 0;
        for i in 0..n_active_max {
            let Some(e) = edges.get_mut(usize::from(active[i])) else {
                continue;
            };
            if e.row_end > row + 1 {
                e.step();
                let a = active[i];
                if let Some(slot) = active.get_mut(kept) {
                    *slot = a;
                }
                kept += 1;
            }
        }
        n_active = kept;
        row += 1;
        if n_active == 0 {
            match edges.get(next) {
                Some(e) if next < count => row = e.row,
                _ => break,
            }
        }
    }
    pixels
}
