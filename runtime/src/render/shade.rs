//! Smooth shading in a frame: the intensity at a point that clipping makes on a smooth
//! polygon, which its [`Gradient`](crate::fill::gradient::Gradient) interpolates with the
//! corners' stored ones: the polygon's plane's at it ([`PlaneShade`]), so that a polygon cut
//! by the window shades as the whole does.

use glam::Vec3;

/// A polygon's intensity as an affine function of camera-space position on its plane,
/// through three of its corners: what a point clipping makes takes. Clamped to the three
/// corners' range, as the compiler's interpolation is.
pub(super) struct PlaneShade {
    p0: Vec3,
    e1: Vec3,
    e2: Vec3,
    /// `(e1 x e2) / |e1 x e2|^2`: a point's barycentric weights are dot products with it.
    n: Vec3,
    s: [f32; 3],
}

impl PlaneShade {
    /// The plane through `corners` (camera space) with intensities `shades`; a degenerate
    /// triangle gives the first corner's intensity everywhere.
    pub(super) fn new(corners: [Vec3; 3], shades: [u8; 3]) -> Self {
        let (e1, e2) = (corners[1] - corners[0], corners[2] - corners[0]);
        let normal = e1.cross(e2);
        let area = normal.length_squared();
        PlaneShade {
            p0: corners[0],
            e1,
            e2,
            n: if area > 0.0 && area.is_finite() {
                normal / area
            } else {
                Vec3::ZERO
            },
            s: shades.map(f32::from),
        }
    }

    /// The intensity at `c` (a point of the plane).
    pub(super) fn at(&self, c: Vec3) -> f32 {
        let d = c - self.p0;
        let w1 = d.cross(self.e2).dot(self.n);
        let w2 = self.e1.cross(d).dot(self.n);
        let [s0, s1, s2] = self.s;
        let s = s0 + w1 * (s1 - s0) + w2 * (s2 - s0);
        let (lo, hi) = (s0.min(s1).min(s2), s0.max(s1).max(s2));
        // (NaN from a degenerate point lands on `lo`.)
        if s >= lo {
            s.min(hi)
        } else {
            lo
        }
    }

    /// Intensity `s` (0 to 255) rounded to 8 bits.
    pub(super) fn level(s: f32) -> u8 {
        (s + 0.5) as u8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plane_gives_the_corners_and_interpolates_between() {
        let corners = [
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::new(2.0, 0.0, 6.0),
            Vec3::new(0.0, 2.0, 5.0),
        ];
        let plane = PlaneShade::new(corners, [40, 240, 100]);
        assert_eq!(plane.at(corners[0]), 40.0);
        assert_eq!(plane.at(corners[1]), 240.0);
        assert_eq!(plane.at(corners[2]), 100.0);
        let mid = (corners[1] + corners[2]) * 0.5;
        assert!((plane.at(mid) - 170.0).abs() < 1e-3);
        // Outside the triangle: clamped to the corners' range.
        assert_eq!(plane.at(corners[1] * 3.0 - corners[0] * 2.0), 240.0);
        assert_eq!(PlaneShade::level(170.4), 170);
        assert_eq!(PlaneShade::level(170.5), 171);
        // Degenerate: the first corner's intensity.
        let flat = PlaneShade::new([corners[0]; 3], [9, 200, 30]);
        assert_eq!(flat.at(corners[1]), 9.0);
    }
}
