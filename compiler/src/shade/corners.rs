//! Corner shades: the light at each corner of a source triangle, each side on its own, and in
//! between.
//!
//! A side is lit at a corner as [`Shading::intensity_at`] lights a face, with the corner normal
//! turned to that side: the corner normal `n` is turned to the front (`n` if `n · f >= 0`,
//! else `-n`, `f` the triangle's face normal) and negated for the back. A side facing away
//! from the light thus gets the ambient part at every corner, so the far side of a model stays
//! dark without a special case, while normals from a file that disagree with the winding are
//! still lit on the side they belong to. A point light's direction is taken from each
//! corner's own position.
//!
//! Inside the triangle, and at any point of its plane (the vertices of the pieces the compiler
//! cuts it into), a side's intensity is the barycentric interpolation of its corners'; points
//! off the plane are projected onto it. The material colour times the intensity is the
//! colour, unrounded; [`quantise`] gives the 8-bit intensity a file stores and [`apply`] the
//! colour it gives.

use glam::DVec3;

use super::{channel, Shading};

/// A side of a source triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Facing {
    /// The side its corners wind counter-clockwise seen from: its normal is
    /// `(b - a) × (c - a)`.
    Front,
    /// The other side.
    Back,
}

impl Facing {
    /// The side whose normal points to the eyes that see it: the front when `front` is set.
    pub fn of(front: bool) -> Facing {
        if front {
            Facing::Front
        } else {
            Facing::Back
        }
    }
}

/// The intensity at each corner of one source triangle, each side on its own: the factor the
/// material colour is multiplied by, from [`super::AMBIENT`] to 1, unrounded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerShades {
    /// The triangle's corners (world coordinates).
    pub corners: [DVec3; 3],
    /// The intensity of the front at each corner.
    pub front: [f64; 3],
    /// The intensity of the back at each corner.
    pub back: [f64; 3],
}

impl CornerShades {
    /// The triangle `corners`, of corner normals `normals` (unit, or zero for no normal),
    /// lit by `shading`.
    pub fn new(shading: &Shading, corners: [DVec3; 3], normals: [DVec3; 3]) -> CornerShades {
        let face = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let front: [DVec3; 3] = normals.map(|n| if n.dot(face) >= 0.0 { n } else { -n });
        CornerShades {
            corners,
            front: [0, 1, 2].map(|k| shading.intensity_at(front[k], corners[k])),
            back: [0, 1, 2].map(|k| shading.intensity_at(-front[k], corners[k])),
        }
    }

    /// The intensities of `side` at the corners.
    pub fn of(&self, side: Facing) -> [f64; 3] {
        match side {
            Facing::Front => self.front,
            Facing::Back => self.back,
        }
    }

    /// The barycentric coordinates of `p` projected onto the triangle's plane (they sum to 1;
    /// a corner's are exactly 1 there and 0 elsewhere); a third each for a triangle of no
    /// area.
    pub fn weights(&self, p: DVec3) -> [f64; 3] {
        weights(self.corners, p)
    }

    /// The intensity of `side` at the point `p` of the triangle's plane: its corners'
    /// interpolated, kept within their range (a point a rounding error outside the triangle
    /// is not extrapolated past them).
    pub fn intensity_at(&self, side: Facing, p: DVec3) -> f64 {
        let values = self.of(side);
        let w = self.weights(p);
        let value = w[0] * values[0] + w[1] * values[1] + w[2] * values[2];
        let lo = values[0].min(values[1]).min(values[2]);
        let hi = values[0].max(values[1]).max(values[2]);
        value.clamp(lo, hi)
    }

    /// The colour of `side` at `p` for the material colour `kd`, in 8-bit units, unrounded.
    pub fn colour_at(&self, kd: [u8; 3], side: Facing, p: DVec3) -> [f64; 3] {
        let k = self.intensity_at(side, p);
        kd.map(|c| f64::from(c) * k)
    }
}

/// The barycentric coordinates of `p` projected onto the plane of the triangle `corners` (they
/// sum to 1; a corner's are exactly 1 there and 0 elsewhere); a third each for a triangle of
/// no area.
pub fn weights(corners: [DVec3; 3], p: DVec3) -> [f64; 3] {
    let [a, b, c] = corners;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let n = ab.cross(ac);
    let area = n.length_squared();
    if !(area > 0.0 && area.is_finite()) {
        return [1.0 / 3.0; 3];
    }
    // `ap = s ab + t ac + h n`: crossing with `ac` or `ab` and dotting with `n` drops `h`.
    let s = ap.cross(ac).dot(n) / area;
    let t = ab.cross(ap).dot(n) / area;
    [1.0 - s - t, s, t]
}

/// An intensity in 8 bits, as a file stores it: `round(255 * intensity)`.
pub fn quantise(intensity: f64) -> u8 {
    channel(255.0 * intensity)
}

/// The colour the 8-bit intensity `intensity` ([`quantise`]) gives the material colour `kd`:
/// `kd * intensity / 255`, rounded.
pub fn apply(kd: [u8; 3], intensity: u8) -> [u8; 3] {
    kd.map(|c| channel(f64::from(c) * f64::from(intensity) / 255.0))
}

#[cfg(test)]
mod tests {
    use super::super::AMBIENT;
    use super::*;

    fn triangle() -> [DVec3; 3] {
        [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
        ]
    }

    /// Under a sun straight above, the front's corners are lit by how far their normals lean
    /// from it and the back is ambient at every corner: the far side stays dark. A normal
    /// against the winding is lit on the front all the same.
    #[test]
    fn each_side_is_lit_with_the_corner_normal_turned_to_it() {
        let sun = Shading::Lambert(DVec3::Z);
        let lean = DVec3::new(0.6, 0.0, 0.8);
        let normals = [DVec3::Z, lean, -lean];
        let s = CornerShades::new(&sun, triangle(), normals);
        let lit = AMBIENT + (1.0 - AMBIENT) * 0.8;
        assert_eq!(s.front, [1.0, lit, lit]);
        assert_eq!(s.back, [AMBIENT; 3]);
        // Seen from below, the same triangle is the other way round.
        let below = CornerShades::new(&Shading::Lambert(-DVec3::Z), triangle(), normals);
        assert_eq!(below.front, [AMBIENT; 3]);
        assert_eq!(below.back, [1.0, lit, lit]);
        // Grazing: a corner normal square to the light is ambient on both sides.
        let grazing = CornerShades::new(&Shading::Lambert(DVec3::X), triangle(), [DVec3::Z; 3]);
        assert_eq!((grazing.front, grazing.back), ([AMBIENT; 3], [AMBIENT; 3]));
        // Unlit: full intensity everywhere.
        let flat = CornerShades::new(&Shading::Flat, triangle(), normals);
        assert_eq!((flat.front, flat.back), ([1.0; 3], [1.0; 3]));
    }

    /// A point light is seen from each corner in its own direction: right above corner 0 it
    /// lights that corner fully and the others by the cosine of their angle to it.
    #[test]
    fn a_point_light_lights_each_corner_from_its_own_direction() {
        let light = DVec3::new(0.0, 0.0, 2.0);
        let s = CornerShades::new(&Shading::Point(light), triangle(), [DVec3::Z; 3]);
        let slanted = AMBIENT + (1.0 - AMBIENT) * (2.0 / 8f64.sqrt());
        assert_eq!(s.front[0], 1.0);
        assert!((s.front[1] - slanted).abs() < 1e-15 && (s.front[2] - slanted).abs() < 1e-15);
        assert_eq!(s.back, [AMBIENT; 3]);
        // Not the centroid's direction, which faceted shading takes for the whole face.
        let centroid =
            Shading::Point(light).intensity_at(DVec3::Z, DVec3::new(2.0, 2.0, 0.0) / 3.0);
        assert!(s.front.iter().all(|&k| (k - centroid).abs() > 0.01));
    }

    #[test]
    fn inside_the_intensity_is_the_corners_interpolated() {
        let sun = Shading::Lambert(DVec3::new(1.0, 0.0, 1.0));
        let normals = [
            DVec3::Z,
            DVec3::new(0.6, 0.0, 0.8),
            DVec3::new(-0.6, 0.0, 0.8),
        ];
        let s = CornerShades::new(&sun, triangle(), normals);
        let f = s.front;
        assert!(f[0] != f[1] && f[1] != f[2] && f[0] != f[2], "{f:?}");
        // Exact at the corners.
        for (k, &corner) in triangle().iter().enumerate() {
            assert_eq!(s.intensity_at(Facing::Front, corner), f[k]);
            assert_eq!(
                s.colour_at([200, 100, 0], Facing::Front, corner),
                [200.0 * f[k], 100.0 * f[k], 0.0]
            );
        }
        // A cut vertex on an edge: between its two corners.
        let cut = DVec3::new(0.5, 1.5, 0.0);
        let want = 0.25 * f[1] + 0.75 * f[2];
        assert!((s.intensity_at(Facing::Front, cut) - want).abs() < 1e-15);
        // Inside, and off the plane by a rounding error: projected.
        let inside = DVec3::new(0.5, 0.25, 1e-9);
        let want = 0.625 * f[0] + 0.25 * f[1] + 0.125 * f[2];
        assert!((s.intensity_at(Facing::Front, inside) - want).abs() < 1e-15);
        let centroid = triangle().iter().sum::<DVec3>() / 3.0;
        let mean = (s.back[0] + s.back[1] + s.back[2]) / 3.0;
        assert!((s.intensity_at(Facing::Back, centroid) - mean).abs() < 1e-15);
        // Outside by a little, not past the corners' range.
        let beyond = DVec3::new(-1e-3, 2.0 + 1e-3, 0.0);
        let (lo, hi) = (
            f.iter().cloned().fold(1.0, f64::min),
            f.iter().cloned().fold(0.0, f64::max),
        );
        assert!((lo..=hi).contains(&s.intensity_at(Facing::Front, beyond)));
    }

    #[test]
    fn intensities_take_eight_bits_and_colour_the_material() {
        assert_eq!(quantise(1.0), 255);
        assert_eq!(quantise(AMBIENT), 77, "76.5 rounds up");
        assert_eq!(quantise(AMBIENT + (1.0 - AMBIENT) * 0.6), 184, "183.6");
        assert_eq!(quantise(0.5), 128, "127.5 rounds up");
        assert_eq!(quantise(100.49 / 255.0), 100);
        assert_eq!(quantise(0.0), 0);
        assert_eq!(apply([200, 100, 50], 184), [144, 72, 36]);
        assert_eq!(apply([255, 255, 255], 77), [77; 3]);
        assert_eq!(apply([200, 100, 50], 255), [200, 100, 50]);
        // Faceted shading's colour of the same side, where rounding twice does not differ.
        let k = AMBIENT + (1.0 - AMBIENT) * 0.6;
        let faceted = Shading::Lambert(DVec3::Y).shade([200, 100, 50], DVec3::new(0.0, 0.6, 0.8));
        assert_eq!(apply([200, 100, 50], quantise(k)), faceted);
    }
}
