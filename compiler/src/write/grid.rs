//! Vertices as 16-bit steps on the scene's bounds (6 bytes instead of 12 of `f32`).
//!
//! Each axis of the header's bounds is cut into 65535 steps; a vertex is stored as the step
//! nearest to its exact position, so it moves by at most half a step (1/131070 of the scene's
//! extent on that axis) plus the `f32` rounding of the decoded value. The runtime decodes with
//! `peel_runtime::read::layout::dequantise`, the same function as for node boxes, so a box of
//! steps contains its vertices exactly.

use glam::DVec3;
use peel_runtime::read::layout::dequantise;

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
