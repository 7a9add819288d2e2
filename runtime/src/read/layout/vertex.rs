//! Vertices: their record's size and the grid their 16-bit steps (and node boxes) decode on,
//! which the writer quantises with too, so that both sides agree bit for bit.

use super::fields::ARMV6M;
use super::header::header_flags;

/// Bytes of a vertex under header `flags`: `[f32; 3]` with [`header_flags::WIDE_VERTICES`],
/// else `[u16; 3]`.
pub const fn vertex_size(flags: u16) -> usize {
    if flags & header_flags::WIDE_VERTICES != 0 {
        12
    } else {
        6
    }
}

/// A vertex or node box coordinate: step `q` of 65535 from the header's `min` to its `max`
/// along one axis, `min + q * step(min, max)`. It is monotone in `q`, so a box of steps contains
/// every vertex whose steps it contains; the writer rounds `f32` vertices' boxes outward
/// through this very function.
#[inline]
pub fn dequantise(min: f32, max: f32, q: u16) -> f32 {
    min + f32::from(q) * step(min, max)
}

/// The size of a step along an axis from `min` to `max` (`f32`, as [`dequantise`] uses it).
#[inline]
pub fn step(min: f32, max: f32) -> f32 {
    (max - min) / 65535.0
}

/// An axis whose bounds are an exact grid: step `q` lies at `(origin + q * stride) * 2^shift`
/// with every such integer below 2^24, so [`dequantise`] rounds nothing and a core without an
/// FPU gets its very bits from one integer multiply-add and one conversion ([`Grid::value`]).
/// The compiler writes such bounds; a file whose bounds are not one still decodes alike on
/// every core, through [`dequantise`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Grid {
    origin: i32,
    stride: i32,
    shift: i32,
}

impl Grid {
    /// The grid of the bounds `min ..= max`, if they are one.
    pub fn of(min: f32, max: f32) -> Option<Grid> {
        if !(min <= max && max - min <= f32::MAX) {
            return None;
        }
        let step = step(min, max);
        let (s, s_exp) = odd_times_power_of_two(step);
        let (m, m_exp) = odd_times_power_of_two(min);
        let shift = match (s, m) {
            (0, _) => m_exp,
            (_, 0) => s_exp,
            _ => s_exp.min(m_exp),
        };
        // A normal power of two, and every value `n * 2^shift` (|n| < 2^24) finite.
        if !(-126..=104).contains(&shift) {
            return None;
        }
        let widen = |n: i32, exp: i32| {
            if n == 0 {
                return Some(0);
            }
            let by = u32::try_from(exp - shift).ok().filter(|&by| by < 24)?;
            n.checked_mul(1 << by)
                .filter(|w| w.unsigned_abs() < 1 << 24)
        };
        let grid = Grid {
            origin: widen(m, m_exp)?,
            stride: widen(s, s_exp).filter(|&t| t <= 255)?,
            shift,
        };
        let last = grid.origin + 65535 * grid.stride;
        let exact = last.unsigned_abs() < 1 << 24
            && grid.value(0) == min
            && grid.value(u16::MAX) == max
            && step * 65535.0 == max - min;
        exact.then_some(grid)
    }

    /// Step `q`: [`dequantise`] on the grid's bounds, bit for bit, without a float operation
    /// but one conversion from `i32` (and on ARMv6-M, where every float multiply is a library
    /// call, the power of two added to the exponent).
    #[inline]
    pub fn value(self, q: u16) -> f32 {
        // Below 2^24 in magnitude (checked by `of`): exact in f32.
        let n = self.origin + i32::from(q) * self.stride;
        if ARMV6M {
            scaled_by_exponent(n, self.shift)
        } else {
            n as f32 * f32::from_bits(((self.shift + 127) as u32) << 23)
        }
    }
}

/// `n * 2^shift` for `|n| < 2^24` and `-126 <= shift <= 104` (a normal, finite result): the
/// conversion's exponent field moved by `shift`, where a multiply would be a library call.
#[inline]
pub(crate) fn scaled_by_exponent(n: i32, shift: i32) -> f32 {
    if n == 0 {
        return 0.0;
    }
    f32::from_bits(((n as f32).to_bits() as i32).wrapping_add(shift << 23) as u32)
}

/// `x` as `m * 2^e` with `m` odd and `|m| < 2^24`, or `(0, 0)` for zero (and for a value
/// that is not finite, which no grid accepts: its `e` is out of range).
fn odd_times_power_of_two(x: f32) -> (i32, i32) {
    let bits = x.to_bits();
    let field = ((bits >> 23) & 0xff) as i32;
    let fraction = (bits & 0x7f_ffff) as i32;
    let (m, e) = match field {
        0 if fraction == 0 => return (0, 0),
        0 => (fraction, -149),
        0xff => return (1, i32::MAX / 2),
        _ => (fraction | 0x80_0000, field - 150),
    };
    let zeros = m.trailing_zeros() as i32;
    let m = m >> zeros;
    (if bits >> 31 != 0 { -m } else { m }, e + zeros)
}

/// Steps per unit of length along an axis from `min` to `max` (1 on a flat axis, where every
/// step is 0): what brings a point to steps for a polygon's side ([`crate::read::Scene::side_eye`]).
#[inline]
pub fn per_step(min: f32, max: f32) -> f32 {
    let extent = max - min;
    if extent > 0.0 {
        65535.0 / extent
    } else {
        1.0
    }
}
