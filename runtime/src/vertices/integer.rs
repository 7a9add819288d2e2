//! Integer vertices ([`crate::render::Renderer::integer_vertices`]): a frame's vertices
//! projected and snapped in integer arithmetic, for cores without an FPU, where the `f32` path
//! (transform, projection, snapping in software floats) costs thousands of instructions a
//! vertex.
//!
//! A scene whose vertices are 16-bit steps `q` on an exact grid has them at
//! `p = min + q ∘ step` exactly. With `d = p − eye` and the view's basis `r`, `u`, `f`, the
//! snapped point of the `f32` path is `S (c_x + f_x (r·d) / (f·d))` across (and likewise down),
//! `S = 2^SUB`: the quotient of two forms affine in `q`,
//! `N_x = S (f_x r + c_x f)·d`, `N_y = S (c_y f − f_y u)·d` over the depth `Z = f·d`.
//! A frame computes their coefficients once in `f64`, scaled by a power of two `2^e` and
//! rounded to `i64`; a vertex then takes nine integer multiply-adds and two divisions, the
//! same bits on every core. The point is `⌊(2N + Z) / 2Z⌋` (the nearest), clamped to the
//! window as [`crate::render::snap`] clamps.
//!
//! # Error bound
//! Over `q ∈ [0, 65535]^3` each integer form differs from `2^e` times the exact one by at most
//! `D = 2^17`: each coefficient rounds by at most `1/2` plus its `f64` error (a few units of
//! `2^-53` of its terms' sizes, which `2^e` keeps at most `2^44`), times `q <= 65535`, and the
//! constant by at most `1` plus a few units of `2^-53` of at most `2^60`. With `Z*`, `X*` the exact
//! depth and snapped coordinate (in `2^-SUB` pixel), `|N/Z − X*| = |δN − X* δZ| / Z <=
//! D (1 + |X*|) / (2^e Z* − D)`. A frame takes this path only when that is at most an eighth
//! of a unit for every vertex of the scene's box (its least depth, and `|X*|` within the
//! window, where every vertex of a frame without clipping projects), else the `f32` path.
//! The division drops the `t` low bits of `N` and `Z` that leave `Z` 31 bits (`>= 2^30` when
//! any are dropped), which moves the quotient by at most `(1 + X*) / 2^30 < 2^-4`. So the
//! point is within half a unit (the rounding, as the `f32` path's snapping) and `3/16` of the
//! exact projection, inside the subtree test's slack (`1/64` pixel beyond the snapping): culling
//! stays exact. The forms stay below `2^62` in magnitude (`3 · 2^44 · 65535 + 2^60`), so
//! nothing overflows.

use glam::Vec3;

use crate::camera::LocalView;
use crate::fill::FixedPoint;

/// Coefficients of a step are at most `2^COEFFICIENT_BITS` in magnitude.
const COEFFICIENT_BITS: i32 = 44;
/// Constants are at most `2^CONSTANT_BITS` in magnitude.
const CONSTANT_BITS: i32 = 60;
/// `D`: how far an integer form may lie from `2^e` times the exact one (module docs).
const ROUNDING: f64 = 131_072.0;
/// Largest window side, in `2^-SUB` pixel, plus one: keeps the division's truncation below
/// `2^-4` of a unit.
const REACH: f64 = 67_108_864.0;

/// One frame's integer projection of 16-bit steps (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct IntegerView {
    /// `N_x`, `N_y` and `Z`: the coefficients of `q_0`, `q_1`, `q_2`, then the constant.
    forms: [[i64; 4]; 3],
    max_x: i32,
    max_y: i32,
    /// Bits of `max_x` and `max_y`: the quotient bits the divisions find.
    bits_x: u32,
    bits_y: u32,
}

/// An exponent `k` with `|x| < 2^k` (finite, non-zero `x`): from its exponent field.
fn exponent_above(x: f64) -> i32 {
    ((x.abs().to_bits() >> 52) & 0x7ff) as i32 - 1022
}

impl IntegerView {
    /// The projection of the points `min + q ∘ step` (exact: the scene's grid) for `view`,
    /// snapped at `SUB` bits into `[0, max_x] x [0, max_y]`, when its error bound holds for
    /// every point of the box `lo..=hi` (holding every vertex, each in front of the eye);
    /// `None` otherwise, and for any non-finite or degenerate value.
    pub(crate) fn new<const SUB: u32>(
        view: &LocalView,
        (min, step): (Vec3, Vec3),
        (lo, hi): (Vec3, Vec3),
        max_x: i32,
        max_y: i32,
    ) -> Option<Self> {
        let s = f64::from(1u32 << SUB.min(24));
        let (r, u, f) = (
            view.right.as_dvec3(),
            view.up.as_dvec3(),
            view.forward.as_dvec3(),
        );
        let (fx, fy) = (f64::from(view.fx), f64::from(view.fy));
        let (cx, cy) = (f64::from(view.cx), f64::from(view.cy));
        let gains = [r * (s * fx) + f * (s * cx), f * (s * cy) - u * (s * fy), f];
        // Bounds on the terms of each sum, which bound its `f64` error whatever cancels.
        let sizes = [
            r.abs() * (s * fx.abs()) + f.abs() * (s * cx.abs()),
            f.abs() * (s * cy.abs()) + u.abs() * (s * fy.abs()),
            f.abs(),
        ];
        let (step, eye) = (step.as_dvec3(), view.eye.as_dvec3());
        let offset = min.as_dvec3() - eye;
        let (mut a, mut b) = (0.0f64, 0.0f64);
        for size in sizes {
            a = a.max((size * step.abs()).max_element());
            b = b.max(size.dot(offset.abs()));
        }
        if !(a.is_finite() && b.is_finite() && a > 0.0 && b > 0.0) {
            return None;
        }
        let e = (COEFFICIENT_BITS - exponent_above(a)).min(CONSTANT_BITS - exponent_above(b));
        if !(-1000..=1000).contains(&e) {
            return None;
        }
        let scale = f64::from_bits(((e + 1023) as u64) << 52); // 2^e
                                                               // The least depth over the box, less a bound on its own `f64` error.
        let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
        let (mid, half) = ((lo + hi) * 0.5 - eye, (hi - lo) * 0.5);
        let depth = f.dot(mid) - f.abs().dot(half);
        let size = (f * mid).abs().element_sum() + f.abs().dot(half);
        let least = (depth - size / 1_099_511_627_776.0) * scale - ROUNDING;
        let reach = f64::from(max_x.max(max_y).max(0)) + 1.0;
        if !(least.is_finite() && ROUNDING * reach <= least * 0.125 && reach <= REACH) {
            return None;
        }
        // Nearest, halves away from zero (`as` truncates; every value is below 2^61).
        let round = |x: f64| {
            let x = x * scale;
            (if x < 0.0 { x - 0.5 } else { x + 0.5 }) as i64
        };
        let form = |g: glam::DVec3| {
            let a = g * step;
            [round(a.x), round(a.y), round(a.z), round(g.dot(offset))]
        };
        let (max_x, max_y) = (max_x.max(0), max_y.max(0));
        Some(IntegerView {
            forms: [form(gains[0]), form(gains[1]), form(gains[2])],
            max_x,
            max_y,
            bits_x: 32 - (max_x as u32).leading_zeros(),
            bits_y: 32 - (max_y as u32).leading_zeros(),
        })
    }

    /// The snapped screen point of the vertex of steps `q`.
    #[inline]
    pub(crate) fn point<const SUB: u32>(&self, q: [u16; 3]) -> FixedPoint<SUB> {
        let [nx, ny, z] = self.forms.map(|form| value(form, q));
        // Positive and below 2^62 by the frame's bound (the clamp only keeps that provable).
        let z = z.clamp(1, 1 << 62) as u64;
        // The divisor in 31 bits: `t` low bits off both terms.
        let t = (64 - z.leading_zeros()).saturating_sub(31);
        let d = (z >> t) as u32;
        FixedPoint::new(
            nearest(nx, t, d, self.max_x, self.bits_x),
            nearest(ny, t, d, self.max_y, self.bits_y),
        )
    }
}

/// `a ∘ q + b` for a form `[a_0, a_1, a_2, b]` with `|a_j| <= 2^44`: each coefficient in 16-bit
/// limbs, so that a core without a widening multiply (ARMv6-M) takes 32-bit multiplies
/// (every limb times a step fits 32 bits) rather than a 64-bit multiply's library call.
#[inline]
fn value([a0, a1, a2, b]: [i64; 4], q: [u16; 3]) -> i64 {
    let (mut high, mut middle, mut low) = (0i32, 0u64, 0u64);
    for (a, q) in [a0, a1, a2].into_iter().zip(q) {
        let q = u32::from(q);
        // `a = high 2^32 + middle 2^16 + low`, `|high| < 2^13`.
        high = high.wrapping_add(((a >> 32) as i32).wrapping_mul(q as i32));
        middle += u64::from(((a >> 16) as u32 & 0xffff) * q);
        low += u64::from((a as u32 & 0xffff) * q);
    }
    (i64::from(high) << 32)
        .wrapping_add((middle << 16) as i64)
        .wrapping_add(low as i64)
        .wrapping_add(b)
}

/// The integer nearest `n / z` (halves up) clamped to `0..=max`, from `n` without its `t` low
/// bits and `d = z >> t` (`2^30 <= d < 2^31` when `t > 0`): a 64-by-32-bit long division of
/// as many quotient bits as `max` has (`bits`, at most 31), in 32-bit registers.
#[inline]
fn nearest(n: i64, t: u32, d: u32, max: i32, bits: u32) -> i32 {
    if n <= 0 || bits == 0 || bits > 31 || d == 0 || max < 0 {
        return 0;
    }
    let n = (n as u64) >> t;
    // The quotient is below `2^bits` unless this first remainder is `>= d`.
    let top = n >> bits;
    if top >= u64::from(d) {
        return max;
    }
    let (mut remainder, mut rest, mut quotient) = (top as u32, (n as u32) << (32 - bits), 0u32);
    for _ in 0..bits {
        // `remainder < d < 2^31`: the shift keeps every bit.
        remainder = remainder << 1 | rest >> 31;
        rest <<= 1;
        quotient <<= 1;
        if remainder >= d {
            remainder -= d;
            quotient |= 1;
        }
    }
    // `2 remainder < 2d < 2^32`.
    if remainder.wrapping_mul(2) >= d {
        quotient += 1;
    }
    quotient.min(max as u32) as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    use proptest::prelude::*;

    /// A view of the box `min ..= min + 65535 step` from `distance` box radii away, and the
    /// window's limits at 8 bits.
    fn case(
        min: Vec3,
        step: Vec3,
        (azimuth, elevation, distance): (f32, f32, f32),
        (width, height): (u32, u32),
    ) -> Option<(LocalView, i32, i32)> {
        let max = min + step * 65535.0;
        let centre = (min + max) * 0.5;
        let radius = (max - min).length() * 0.5;
        let dir = Vec3::new(
            elevation.cos() * azimuth.sin(),
            elevation.sin(),
            elevation.cos() * azimuth.cos(),
        );
        let eye = centre + dir * radius * distance;
        let focal = height as f32 * 0.5 / (30f32.to_radians()).tan();
        let view =
            LocalView::look_at(eye, centre, Vec3::Y, focal, width, height, radius * 1e-3).ok()?;
        Some((view, (width << 8) as i32, (height << 8) as i32))
    }

    /// The exact snapped coordinates (before rounding) of `min + q ∘ step`, in `f64`, and
    /// whether the point is in front and within the window.
    fn exact(view: &LocalView, min: Vec3, step: Vec3, q: [u16; 3]) -> (f64, f64, bool) {
        let d = |v: Vec3| [f64::from(v.x), f64::from(v.y), f64::from(v.z)];
        let (m, t, e) = (d(min), d(step), d(view.eye));
        let p = [0, 1, 2].map(|j| m[j] + f64::from(q[j]) * t[j] - e[j]);
        let dot = |a: [f64; 3]| a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
        let (x, y, z) = (dot(d(view.right)), dot(d(view.up)), dot(d(view.forward)));
        let sx = 256.0 * (f64::from(view.cx) + f64::from(view.fx) * x / z);
        let sy = 256.0 * (f64::from(view.cy) - f64::from(view.fy) * y / z);
        let inside = z > 0.0
            && (0.0..=f64::from(view.width) * 256.0).contains(&sx)
            && (0.0..=f64::from(view.height) * 256.0).contains(&sy);
        (sx, sy, inside)
    }

    /// Orbit views of boxes of many sizes and places: where the frame takes the integer path,
    /// every vertex in the window lies within half a unit (the rounding) and a quarter (the
    /// bound) of its exact snapped position.
    fn check(
        min: Vec3,
        step: Vec3,
        angles: (f32, f32, f32),
        qs: &[[u16; 3]],
    ) -> Result<bool, TestCaseError> {
        let Some((view, max_x, max_y)) = case(min, step, angles, (320, 240)) else {
            return Ok(false);
        };
        let max = min + step * 65535.0;
        let Some(integer) = IntegerView::new::<8>(&view, (min, step), (min, max), max_x, max_y)
        else {
            return Ok(false);
        };
        for &q in qs {
            let (sx, sy, inside) = exact(&view, min, step, q);
            if !inside {
                continue;
            }
            let p = integer.point::<8>(q);
            let tolerance = 0.75 + 1e-6 * (sx.abs() + sy.abs());
            prop_assert!(
                (f64::from(p.x) - sx).abs() <= tolerance,
                "{} vs {} at {:?}",
                p.x,
                sx,
                q
            );
            prop_assert!(
                (f64::from(p.y) - sy).abs() <= tolerance,
                "{} vs {} at {:?}",
                p.y,
                sy,
                q
            );
        }
        Ok(true)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

        #[test]
        fn integer_points_are_within_the_bound(
            min in (-1e3f32..1e3, -1e3f32..1e3, -1e3f32..1e3),
            step in (1e-6f32..1e-1, 1e-6f32..1e-1, 1e-6f32..1e-1),
            angles in (-3.2f32..3.2, -1.5f32..1.5, 1.5f32..6.0),
            qs in proptest::collection::vec(any::<[u16; 3]>(), 16),
        ) {
            let (min, step) = (Vec3::new(min.0, min.1, min.2), Vec3::new(step.0, step.1, step.2));
            check(min, step, angles, &qs)?;
        }
    }

    proptest! {
        /// The long division is the nearest quotient of the truncated terms, clamped.
        #[test]
        fn nearest_divides_exactly(
            n in prop_oneof![any::<i64>(), 0i64..1 << 40],
            z in prop_oneof![1u64..1 << 62, 1u64..1 << 31],
            max in prop_oneof![any::<i32>(), 0i32..100_000],
        ) {
            let t = (64 - z.leading_zeros()).saturating_sub(31);
            let d = (z >> t) as u32;
            let n = n.min(1 << 62);
            let truncated = if n <= 0 { 0 } else { i128::from((n as u64) >> t) };
            let expected = ((2 * truncated + i128::from(d)) / (2 * i128::from(d)))
                .clamp(0, i128::from(max.max(0)));
            let bits = 32 - (max.max(0) as u32).leading_zeros();
            prop_assert_eq!(i128::from(nearest(n, t, d, max, bits)), expected);
        }

        /// The limbs' sum is the form's value.
        #[test]
        fn limbs_add_up(a in proptest::array::uniform3(-(1i64 << 44)..=1 << 44), b in -(1i64 << 60)..=1 << 60, q in any::<[u16; 3]>()) {
            let expected: i128 = (0..3).map(|j| i128::from(a[j]) * i128::from(q[j])).sum::<i128>() + i128::from(b);
            prop_assert_eq!(i128::from(value([a[0], a[1], a[2], b], q)), expected);
        }
    }

    /// The integer path is taken for the orbit views firmware draws, and refused where the
    /// bound fails (the eye inside the box).
    #[test]
    fn orbit_views_take_the_integer_path() {
        let (min, step) = (Vec3::splat(-1.0), Vec3::splat(2.0 / 65535.0));
        for k in 0..8 {
            let azimuth = k as f32 * core::f32::consts::FRAC_PI_4;
            assert!(check(min, step, (azimuth, 0.35, 2.5), &[[0; 3], [65535; 3]]).unwrap());
        }
        assert!(!check(min, step, (0.0, 0.0, 0.5), &[]).unwrap());
    }
}
