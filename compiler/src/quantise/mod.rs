//! Quantise: fit a power-of-two grid to the scene's bounding box so that every coordinate
//! becomes an integer with `|q| < 2^26`.
//!
//! After this step every decision of the compiler is exact integer arithmetic; a power-of-two
//! scale makes a scene at ±1e6 and a scene of 1e-6 the same problem, and maps back exactly
//! (`world = offset + q * scale`, the product being exact in f64).

use glam::DVec3;

use crate::load::Mesh;

/// Largest `|q|` the grid is fitted to (before rounding), so that `|q| <= 2^25 + 1 < 2^26`.
pub const GRID_HALF_EXTENT: f64 = (1u64 << 25) as f64;

/// A quantised point: integer grid coordinates, each `|q| < 2^26`.
pub type IPoint = [i32; 3];

/// The world <-> grid transform: `world = offset + q * scale`, `scale` a power of two.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantiser {
    /// World position of grid point 0 (the centre of the bounding box); becomes
    /// `DisplayTree::centre`.
    pub offset: DVec3,
    /// Size of one grid step in world units (a power of two).
    pub scale: f64,
}

impl Quantiser {
    /// Fit the grid to the bounding box of all the mesh's triangle corners.
    pub fn fit(mesh: &Mesh) -> Quantiser {
        Quantiser::fit_points(mesh.triangles.iter().flat_map(|t| t.vertices))
    }

    /// Fit the grid to the bounding box of `points` (an empty set gives the identity).
    pub fn fit_points(points: impl IntoIterator<Item = DVec3>) -> Quantiser {
        let mut min = DVec3::splat(f64::INFINITY);
        let mut max = DVec3::splat(f64::NEG_INFINITY);
        for p in points {
            min = min.min(p);
            max = max.max(p);
        }
        if !(min.is_finite() && max.is_finite()) {
            return Quantiser {
                offset: DVec3::ZERO,
                scale: 1.0,
            };
        }
        let offset = (min + max) * 0.5;
        let half = (max - offset).max(offset - min).max_element();
        if half.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Quantiser { offset, scale: 1.0 };
        }
        // Smallest power of two with half / scale <= 2^25.
        let mut scale = 2f64.powi(half.log2().ceil() as i32 - 25);
        while half / scale > GRID_HALF_EXTENT {
            scale *= 2.0;
        }
        while scale > f64::MIN_POSITIVE && half / (scale * 0.5) <= GRID_HALF_EXTENT {
            scale *= 0.5;
        }
        Quantiser { offset, scale }
    }

    /// World point -> nearest grid point.
    pub fn quantise(&self, p: DVec3) -> IPoint {
        let q = ((p - self.offset) / self.scale).round();
        [q.x as i32, q.y as i32, q.z as i32]
    }

    /// Grid point -> world point relative to `offset` (exact: a power-of-two scale).
    #[cfg(test)]
    pub fn relative(&self, q: IPoint) -> DVec3 {
        DVec3::new(q[0] as f64, q[1] as f64, q[2] as f64) * self.scale
    }
}

pub mod solid;

#[cfg(test)]
mod tests {
    use super::*;

    fn check(points: &[DVec3]) {
        let qz = Quantiser::fit_points(points.iter().copied());
        assert_eq!(qz.scale.log2().fract(), 0.0, "scale must be a power of two");
        let mut biggest = 0i32;
        for &p in points {
            let q = qz.quantise(p);
            for c in q {
                assert!(c.unsigned_abs() < 1 << 26);
                biggest = biggest.max(c.abs());
            }
            let back = qz.offset + qz.relative(q);
            assert!((back - p).abs().max_element() <= qz.scale * 0.5 * (1.0 + 1e-9));
        }
        // The grid is as fine as allowed: the extreme coordinate uses more than half the range.
        assert!(biggest > 1 << 24, "grid too coarse: {biggest}");
    }

    #[test]
    fn far_offsets_and_tiny_scales_are_the_same_problem() {
        let unit = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.5, 0.25),
            DVec3::new(-0.3, 1.0, 0.0),
        ];
        check(&unit);
        check(&unit.map(|p| p + DVec3::splat(1e6)));
        check(&unit.map(|p| p * 1e-6));
        check(&unit.map(|p| p * 1e-6 - DVec3::new(1e6, 0.0, 3.0)));
        let a = Quantiser::fit_points(unit);
        let b = Quantiser::fit_points(unit.map(|p| p * 0.5f64.powi(20)));
        for p in unit {
            assert_eq!(a.quantise(p), b.quantise(p * 0.5f64.powi(20)));
        }
    }

    #[test]
    fn degenerate_boxes() {
        let one = Quantiser::fit_points([DVec3::new(3.0, 4.0, 5.0)]);
        assert_eq!(one.quantise(DVec3::new(3.0, 4.0, 5.0)), [0, 0, 0]);
        let none = Quantiser::fit_points([]);
        assert_eq!(none.scale, 1.0);
    }
}
