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
//! A frame computes their coefficients once in `f64`, scaled by a power of two `2^e` chosen so
//! that every depth of the scene's box lies in `[2^41, 2^44)`, and rounded to `i64`; a vertex
//! then takes nine integer multiply-adds, one reciprocal of its depth and two multiplies, the
//! same bits on every core (no division: a core without a divide instruction pays dearly for
//! one). The point is the nearest integer to the quotient (halves up), clamped to the window
//! as [`crate::render::snap`] clamps.
//!
//! # The reciprocal
//! With the depth in `[2^41, 2^44)`, `d = ⌊Z / 2^13⌋` lies in `[2^28, 2^31)`, and
//! [`reciprocal`] gives `R ≈ 2^59 / d` in 32 bits: a seed from a table of the `2^22`-wide
//! intervals of `d` (`2^21 / (i + 1/2)`, within `1/129` of `2^43 / d`), one Newton step on the
//! top 17 bits of `d` (relative error `ε1 <= ε0² + 2^-14 + 2^-19 <= 2^-12.9`) and one on all of
//! them, its residual `(2^59 − d R1) / 2^17` taken modulo `2^32` (it lies within
//! `±2^42 ε1 < ±2^30`), every product of 16-bit limbs in 32 bits (ARMv6-M has no widening
//! multiply): `|1 − d R / 2^59| <= ε1² + 4 / 2^28 <= 2^-25`. A coordinate is then the high word
//! of `⌊N / 2^32⌋ R` (16-bit limbs again), which is `2^8 N / Z` within `2` (the dropped limb and
//! the floor) `+ 2^-25 2^26` (the reciprocal) `+ 2^40 / 2^41` (`N`'s low word) `+ 2^-2` (`Z`'s
//! low 13 bits) units of `2^-8`: `|q − N/Z| <= 2^-5` (with `N / Z < 2^18`: the window's side
//! in `2^-SUB` pixel is below [`REACH`]), so `⌊q + 1/2⌋` is within `1/2 + 2^-5` of `N/Z`.
//!
//! # Error bound
//! Over `q ∈ [0, 65535]^3` each integer form differs from `2^e` times the exact one by at most
//! `D`: each coefficient rounds by at most `1/2` plus its `f64` error (at most `2^-51` of its
//! terms' sizes), times `q <= 65535`, and the constant by at most `1/2` plus `2^-50` of its
//! terms' sizes (the frame computes `D` from them). With `Z*`, `X*` the exact depth and snapped
//! coordinate (in `2^-SUB` pixel), `|N/Z − X*| = |δN − X* δZ| / Z <= D (1 + |X*|) / (2^e Z* −
//! D)`. A frame takes this path only when that is at most an eighth of a unit for every vertex
//! of the scene's box (its least depth, and `|X*|` within the window, where every vertex of a
//! frame without clipping projects) and its integer depths lie in `[2^41, 2^44)`, else the
//! `f32` path. So the point is within half a unit (the rounding, as the `f32` path's snapping)
//! and `1/8 + 1/32 < 3/16` of the exact projection, inside the subtree test's slack (`1/64`
//! pixel beyond the snapping): culling stays exact. The forms of a vertex in the window stay
//! below `2^62` in magnitude (`2^18 · 2^44`), so nothing overflows; each is summed modulo
//! `2^64`, exact whatever its terms.

use glam::Vec3;

use crate::camera::LocalView;
use crate::fill::FixedPoint;

/// Integer depths lie below `2^DEPTH_BITS`...
const DEPTH_BITS: i32 = 44;
/// ... and at or above `2^LEAST_DEPTH_BITS` (so that `d` lies in `[2^28, 2^31)`).
const LEAST_DEPTH_BITS: i32 = 41;
/// `d = Z >> DEPTH_SHIFT`: the depth in 31 bits.
const DEPTH_SHIFT: u32 = 13;
/// The window's largest side in `2^-SUB` pixel, plus one, is at most this: keeps the forms
/// of a vertex in the window below `2^62` and the quotient's error below `2^-5`.
const REACH: f64 = 262_144.0;

/// One frame's integer projection of 16-bit steps (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct IntegerView {
    /// `N_x`, `N_y` and `Z`: the coefficients of `q_0`, `q_1`, `q_2`, then the constant.
    forms: [[i64; 4]; 3],
    max_x: i32,
    max_y: i32,
}

/// An exponent `k` with `|x| < 2^k` (finite, non-zero `x`): from its exponent field.
fn exponent_above(x: f64) -> i32 {
    ((x.abs().to_bits() >> 52) & 0x7ff) as i32 - 1022
}

/// `2^e`, for `|e| <= 1000`.
fn power_of_two(e: i32) -> f64 {
    f64::from_bits(((e + 1023) as u64) << 52)
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
        let (min64, offset) = (min.as_dvec3(), min.as_dvec3() - eye);
        // The offset's own rounding is below 2^-53 of `|min| + |eye|`.
        let reach_of_offset = offset.abs() + min64.abs() + eye.abs();
        let (mut a, mut b) = (0.0f64, 0.0f64);
        for size in sizes {
            a = a.max((size * step.abs()).max_element());
            b = b.max(size.dot(reach_of_offset));
        }
        // The least and greatest depth over the box, each widened by a bound on its `f64`
        // error.
        let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
        let (mid, half) = ((lo + hi) * 0.5 - eye, (hi - lo) * 0.5);
        let (centre, spread) = (f.dot(mid), f.abs().dot(half));
        let size = ((f * mid).abs().element_sum() + spread) / 1_099_511_627_776.0;
        let (least, greatest) = (centre - spread - size, centre + spread + size);
        let finite = [a, b, least, greatest].iter().all(|v| v.is_finite());
        if !(finite && a > 0.0 && b > 0.0 && least > 0.0) {
            return None;
        }
        // The largest scale that keeps the greatest depth below 2^DEPTH_BITS, less one when
        // the rounding would reach it.
        let mut e = DEPTH_BITS - exponent_above(greatest);
        let rounding = |e: i32| {
            let scale = power_of_two(e);
            3.0 * 65535.0 * (0.5 + a * scale / 2_251_799_813_685_248.0)
                + 0.5
                + b * scale / 1_125_899_906_842_624.0
        };
        if !(-1000..=1000).contains(&e) {
            return None;
        }
        if greatest * power_of_two(e) + rounding(e) >= power_of_two(DEPTH_BITS) {
            e -= 1;
        }
        let (scale, rounding) = (power_of_two(e), rounding(e));
        let least = least * scale - rounding;
        let reach = f64::from(max_x.max(max_y).max(0)) + 1.0;
        let bounded = rounding * reach <= (least - rounding) * 0.125
            && least >= power_of_two(LEAST_DEPTH_BITS)
            && greatest * scale + rounding < power_of_two(DEPTH_BITS)
            && reach <= REACH
            // Every coefficient and constant fits an `i64`.
            && a * scale <= 4.0e18
            && b * scale <= 4.0e18;
        if !bounded {
            return None;
        }
        // Nearest, halves away from zero (`as` truncates; every value is below 2^62).
        let round = |x: f64| {
            let x = x * scale;
            (if x < 0.0 { x - 0.5 } else { x + 0.5 }) as i64
        };
        let form = |g: glam::DVec3| {
            let a = g * step;
            [round(a.x), round(a.y), round(a.z), round(g.dot(offset))]
        };
        Some(IntegerView {
            forms: [form(gains[0]), form(gains[1]), form(gains[2])],
            max_x: max_x.max(0),
            max_y: max_y.max(0),
        })
    }

    /// The snapped screen point of the vertex of steps `q`.
    #[inline]
    pub(crate) fn point<const SUB: u32>(&self, q: [u16; 3]) -> FixedPoint<SUB> {
        let [nx, ny, z] = self.forms.map(|form| value(form, q));
        // In `[2^28, 2^31)` by the frame's bound (the clamp only keeps that provable).
        let d = ((z as u64 >> DEPTH_SHIFT) as u32).clamp(1 << 28, (1 << 31) - 1);
        let r = reciprocal(d);
        FixedPoint::new(nearest(nx, r, self.max_x), nearest(ny, r, self.max_y))
    }
}

/// `a ∘ q + b` for a form `[a_0, a_1, a_2, b]`, modulo `2^64` (exact when the value fits an
/// `i64`): each coefficient in 16-bit limbs, so that a core without a widening multiply
/// (ARMv6-M) takes 32-bit multiplies (every low limb times a step fits 32 bits) rather than a
/// 64-bit multiply's library call.
#[inline]
fn value([a0, a1, a2, b]: [i64; 4], q: [u16; 3]) -> i64 {
    let (mut high, mut middle, mut low) = (0i32, 0u64, 0u64);
    for (a, q) in [a0, a1, a2].into_iter().zip(q) {
        let q = u32::from(q);
        // `a = high 2^32 + middle 2^16 + low` (only `high`'s low 32 bits count below 2^64).
        high = high.wrapping_add(((a >> 32) as i32).wrapping_mul(q as i32));
        middle += u64::from(((a >> 16) as u32 & 0xffff) * q);
        low += u64::from((a as u32 & 0xffff) * q);
    }
    (i64::from(high) << 32)
        .wrapping_add((middle << 16) as i64)
        .wrapping_add(low as i64)
        .wrapping_add(b)
}

/// Seeds of [`reciprocal`]: entry `i − 64` is `2^21 / (i + 1/2)` rounded, for the interval
/// `[i 2^22, (i + 1) 2^22)` of `d` (within `1 / (2i + 1)` of `2^43 / d` there).
const SEEDS: [u16; 448] = {
    let mut seeds = [0u16; 448];
    let mut k = 0;
    while k < 448 {
        let i = k as u32 + 64;
        seeds[k] = ((1u32 << 23) / (2 * i + 1)).div_ceil(2) as u16;
        k += 1;
    }
    seeds
};

/// `R ≈ 2^59 / d` for `d` in `[2^28, 2^31)`, within `2^-25` of it relatively (module docs):
/// a seed, then two Newton steps in 32-bit arithmetic with 16-bit limbs. Any other `d` gives
/// some value, without panicking.
#[inline]
fn reciprocal(d: u32) -> u32 {
    let seed = SEEDS
        .get((d >> 22).wrapping_sub(64) as usize)
        .copied()
        .unwrap_or(1);
    let y0 = u32::from(seed);
    // Step 1, on the top 17 bits: `2^29 (1 − (d >> 14) y0 / 2^29)`, within ±2^22.
    let e1 = (1u32 << 29).wrapping_sub((d >> 14).wrapping_mul(y0)) as i32;
    let r1 = (y0 << 16).wrapping_add(((y0 as i32).wrapping_mul(e1 >> 7) >> 6) as u32);
    // Step 2, on all of `d`: `(2^59 − d r1) / 2^17` modulo 2^32, within ±2^30.
    let (dh, dl) = (d >> 16, d & 0xffff);
    let (rh, rl) = (r1 >> 16, r1 & 0xffff);
    let product = (dh.wrapping_mul(rh) << 15)
        .wrapping_add(dh.wrapping_mul(rl) >> 1)
        .wrapping_add(dl.wrapping_mul(rh) >> 1)
        .wrapping_add(dl.wrapping_mul(rl) >> 17);
    let e2 = 0u32.wrapping_sub(product) as i32;
    // `r1 e2 / 2^42`.
    let (eh, el) = (e2 >> 16, (e2 as u32) & 0xffff);
    let correction = ((rh as i32).wrapping_mul(eh) >> 10)
        .wrapping_add((rh.wrapping_mul(el) >> 26) as i32)
        .wrapping_add((rl as i32).wrapping_mul(eh) >> 26);
    r1.wrapping_add(correction as u32)
}

/// The integer nearest `n / z` (halves up) clamped to `0..=max`, from `n` and `r` the
/// [`reciprocal`] of `z >> 13`, for `z` in `[2^41, 2^44)`: the high word of `⌊n / 2^32⌋ r` is
/// `2^8 n / z` (module docs).
#[inline]
fn nearest(n: i64, r: u32, max: i32) -> i32 {
    let high = (n >> 32) as i32;
    if high < 0 || max <= 0 {
        return 0;
    }
    // `n < 2^62` in the window: beyond it the quotient is over `2^62 / 2^44 > max`.
    if high >= 1 << 30 {
        return max;
    }
    let high = high as u32;
    let (nh, nl) = (high >> 16, high & 0xffff);
    let (rh, rl) = (r >> 16, r & 0xffff);
    // Each product below 2^31, their sum below 2^32 (`nh < 2^14`, `rh <= 2^15 + 1`).
    let fraction = nh
        .wrapping_mul(rh)
        .wrapping_add(nh.wrapping_mul(rl).wrapping_add(nl.wrapping_mul(rh)) >> 16);
    ((fraction.wrapping_add(128) >> 8) as i32).min(max)
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

    /// `|1 − d R / 2^59| <= 2^-25`, as exact rationals: `2^25 |2^59 − d R| <= 2^59`.
    fn reciprocal_holds(d: u32) -> Result<(), TestCaseError> {
        let r = reciprocal(d);
        let residual = (1i128 << 59) - i128::from(d) * i128::from(r);
        prop_assert!(
            residual.abs() << 25 <= 1i128 << 59,
            "d {} r {} residual {}",
            d,
            r,
            residual
        );
        Ok(())
    }

    /// Every seed's interval at its ends, and a sweep of the whole range.
    #[test]
    fn reciprocals_are_within_the_bound() {
        for i in 64u32..512 {
            for d in [
                i << 22,
                (i << 22) + 1,
                (i << 22) + (1 << 21),
                ((i + 1) << 22) - 1,
            ] {
                reciprocal_holds(d).unwrap();
            }
        }
        let mut d = 1u32 << 28;
        while d < 1 << 31 {
            reciprocal_holds(d).unwrap();
            d += 4099;
        }
    }

    proptest! {
        #[test]
        fn reciprocal_within_the_bound(d in (1u32 << 28)..(1 << 31)) {
            reciprocal_holds(d)?;
        }

        /// The rounded quotient is within `1/2 + 1/32` of `n / z` clamped to the window, for a
        /// depth in `[2^41, 2^44)` and a quotient below `2^18`, or anything clamped.
        #[test]
        fn nearest_is_within_the_bound(
            z in (1i64 << 41)..(1 << 44),
            x in prop_oneof![0.0f64..262_144.0, -10.0f64..10.0, 0.0f64..1_000.0],
            max in prop_oneof![0i32..262_144, Just(81_920), Just(61_440)],
            noise in any::<i32>(),
        ) {
            let n = (x * z as f64) as i64 + i64::from(noise);
            let r = reciprocal((z >> 13) as u32);
            let q = nearest(n, r, max);
            let target = i128::from(n).clamp(0, i128::from(max) * i128::from(z));
            let off = (i128::from(q) * i128::from(z) - target).abs();
            prop_assert!(32 * off <= 17 * i128::from(z), "n {} z {} max {} q {}", n, z, max, q);
            prop_assert!((0..=max.max(0)).contains(&q));
        }

        /// The limbs' sum is the form's value modulo 2^64, whatever the coefficients.
        #[test]
        fn limbs_add_up(
            a in prop_oneof![
                proptest::array::uniform3(-(1i64 << 46)..=1 << 46),
                any::<[i64; 3]>()
            ],
            b in any::<i64>(),
            q in any::<[u16; 3]>(),
        ) {
            let expected: i128 = (0..3).map(|j| i128::from(a[j]) * i128::from(q[j])).sum::<i128>() + i128::from(b);
            prop_assert_eq!(value([a[0], a[1], a[2], b], q), expected as i64);
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
