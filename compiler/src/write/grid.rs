//! Vertices as 16-bit steps on the scene's bounds (6 bytes instead of 12 of `f32`).
//!
//! Each axis of the header's bounds is cut into 65535 steps; a vertex is stored as the step
//! nearest to its exact position, so it moves by at most half a step (1/131070 of the scene's
//! extent on that axis) plus the `f32` rounding of the decoded value. The runtime decodes with
//! `peel_runtime::read::layout::dequantise`, the same function as for node boxes, so a box of
//! steps contains its vertices exactly.

use glam::DVec3;
use peel_runtime::read::layout::{dequantise, Grid};

/// The header's bounds for vertices within `lo ..= hi`: per axis the smallest exact grid
/// ([`Grid`]) found that contains them, its step at most about 1/64 above the least possible
/// (`(hi - lo) / 65535`). On such bounds every decoded step is exact, which lets a core without
/// an FPU decode in integers. An axis with no such grid (a flat one at a subnormal height) keeps
/// its bounds.
pub fn covering(lo: [f32; 3], hi: [f32; 3]) -> ([f32; 3], [f32; 3]) {
    let mut out = (lo, hi);
    for k in 0..3 {
        (out.0[k], out.1[k]) = covering_axis(lo[k], hi[k]);
    }
    out
}

fn covering_axis(lo: f32, hi: f32) -> (f32, f32) {
    if Grid::of(lo, hi).is_some() || hi <= lo {
        return (lo, hi);
    }
    let (l, h) = (f64::from(lo), f64::from(hi));
    const LIMIT: f64 = (1 << 24) as f64;
    // The finest unit first: strides of about 256 units, then 128, 64...
    let mut shift = ((h - l) / 65535.0 / 256.0).log2().floor() as i32;
    while shift <= 104 {
        let unit = 2f64.powi(shift);
        let origin = (l / unit).floor();
        let stride = ((h / unit - origin) / 65535.0).ceil().max(1.0);
        let last = origin + 65535.0 * stride;
        if stride <= 255.0 && origin.abs() < LIMIT && last.abs() < LIMIT {
            let (min, max) = ((origin * unit) as f32, (last * unit) as f32);
            if Grid::of(min, max).is_some() {
                return (min, max);
            }
        }
        shift += 1;
    }
    (lo, hi)
}

/// The step of `v` (exact, relative to the centre) nearest to it on each axis of `lo ..= hi`.
pub fn nearest(v: DVec3, lo: [f32; 3], hi: [f32; 3]) -> [u16; 3] {
    let mut q = [0u16; 3];
    for k in 0..3 {
        let (l, h) = (lo[k], hi[k]);
        if h <= l {
            continue;
        }
        let t = (v[k] - f64::from(l)) / (f64::from(h) - f64::from(l));
        let guess = (t * 65535.0).round().clamp(0.0, 65535.0) as u16;
        // The decoded value is rounded to f32: the best step may be a neighbour of the guess.
        let error = |s: u16| (f64::from(dequantise(l, h, s)) - v[k]).abs();
        q[k] = [guess.saturating_sub(1), guess, guess.saturating_add(1)]
            .into_iter()
            .min_by(|&a, &b| error(a).total_cmp(&error(b)).then(a.cmp(&b)))
            .unwrap_or(guess);
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::write::format::Vertex;
    use proptest::prelude::*;

    proptest! {
        /// Around the centre (vertices are relative to it) the grid contains the bounds, is
        /// exact, and its step is within 1/32 of the least.
        #[test]
        fn the_covering_grid_is_exact_and_fine(
            below in 0.0f32..=1.0,
            extent in prop_oneof![1e-4f32..10.0, 1.0f32..1e6],
            q in any::<u16>(),
        ) {
            let lo = -extent * below;
            let hi = lo + extent;
            prop_assume!(hi > lo);
            let (min, max) = covering([lo; 3], [hi; 3]);
            let (min, max) = (min[0], max[0]);
            prop_assert!(min <= lo && max >= hi, "{min} {max}");
            let grid = Grid::of(min, max);
            prop_assert!(grid.is_some(), "{min} {max}");
            let least = (f64::from(hi) - f64::from(lo)) / 65535.0;
            let step = f64::from(max - min) / 65535.0;
            prop_assert!(step <= least * (1.0 + 1.0 / 32.0), "{step} {least}");
            let value = grid.unwrap().value(q);
            prop_assert_eq!(value.to_bits(), dequantise(min, max, q).to_bits());
            let exact = f64::from(min) + f64::from(q) * step;
            prop_assert_eq!(f64::from(value), exact);
        }
    }

    #[test]
    fn a_flat_axis_keeps_its_height() {
        assert_eq!(covering([0.5; 3], [0.5; 3]), ([0.5; 3], [0.5; 3]));
        assert_eq!(covering([0.0; 3], [0.0; 3]), ([0.0; 3], [0.0; 3]));
    }

    fn decode(q: [u16; 3], lo: [f32; 3], hi: [f32; 3]) -> [f32; 3] {
        Vertex::Grid(q).position(lo, hi)
    }

    #[test]
    fn the_nearest_step_is_within_half_a_step_and_the_ends_are_exact() {
        let (lo, hi) = ([-1.0, 0.0, 2.0], [1.0, 0.0, 2.5]);
        assert_eq!(nearest(DVec3::new(-1.0, 0.0, 2.5), lo, hi), [0, 0, 65535]);
        assert_eq!(decode([0, 0, 65535], lo, hi), [-1.0, 0.0, 2.5]);
        for i in 0..1000 {
            let x = -1.0 + 2.0 * f64::from(i) / 999.0 + 1e-7;
            let v = DVec3::new(x.min(1.0), 0.0, 2.25);
            let d = decode(nearest(v, lo, hi), lo, hi);
            let half_step = 2.0 / 65535.0 / 2.0;
            // Half a step, plus the f32 rounding of the decoded value.
            assert!(
                (f64::from(d[0]) - v.x).abs() <= half_step + 1e-7,
                "{x}: {d:?}"
            );
            assert!((f64::from(d[2]) - 2.25).abs() <= 0.5 / 65535.0 / 2.0 + 1e-7);
        }
    }
}
