//! Shade: bake Lambert lighting into each polygon's colours, so a mesh reads as 3D without any
//! lighting work at run time.
//!
//! Each side of a face is lit on its own, as the side a viewer sees: with `n` the unit normal
//! of the side (pointing to the eyes that see it) and `l` the unit direction towards the light
//! (a sun, [`DEFAULT_LIGHT`] unless `--light` gives another, or a point light), the side gets
//! `Kd * (AMBIENT + (1 - AMBIENT) * max(n · l, 0))`, rounded: the side facing the light is
//! lit, the other gets `Kd * AMBIENT`. Faces are drawn from both sides, so a polygon carries
//! both colours ([`Sides`]) and the runtime shows the one of the side the eye is on. A point
//! light's direction varies across a polygon: it is taken at the polygon's centroid, so every
//! polygon keeps one colour per side (which side faces a point light is the same over a whole
//! plane).
//!
//! That is *faceted* shading ([`Shading`]; *unlit* is [`Shading::Flat`]). *Smooth* shading
//! ([`smooth::Smooth`]) lights each corner of a source triangle with a normal of the surface
//! around it instead ([`normals`]), by the same rule, and interpolates the corners' colours
//! over the triangle ([`corners`]), so a curved mesh does not show its facets.

pub mod corners;
pub mod normals;
pub mod smooth;

use glam::DVec3;

/// Direction towards the default light: up, right and towards +z (before normalisation).
pub const DEFAULT_LIGHT: DVec3 = DVec3::new(0.4, 0.8, 0.45);

/// Fraction of the colour that every face gets whatever its orientation.
pub const AMBIENT: f64 = 0.3;

/// How colours are baked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shading {
    /// Keep the material colours as they are, on both sides.
    Flat,
    /// Lambert from a directional light (the direction towards the light), each side on its own.
    Lambert(DVec3),
    /// Lambert from a point light (its position), each side on its own, at the centroid.
    Point(DVec3),
}

impl Default for Shading {
    fn default() -> Self {
        Shading::Lambert(DEFAULT_LIGHT)
    }
}

/// How a polygon's colour varies over it; [`Shading`] is the light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Surface {
    /// One colour per side of each polygon (`peel compile --shading faceted`, or `unlit`
    /// with [`Shading::Flat`]).
    Faceted,
    /// Corner colours interpolated over each triangle ([`smooth::Smooth`]), faces further
    /// apart than the crease meeting at a sharp edge (`--shading smooth --crease DEG`).
    Smooth(normals::Crease),
}

/// The surface unless one is asked: smooth, with the default crease, so that a curved mesh
/// shows no facets; a polygon whose corners agree (a box's faces, any face without light) is
/// stored and drawn as a faceted one.
pub const DEFAULT_SURFACE: Surface = Surface::Smooth(normals::Crease::DEFAULT);

impl Default for Surface {
    fn default() -> Self {
        DEFAULT_SURFACE
    }
}

impl Surface {
    /// Smooth, with a crease of `degrees`.
    ///
    /// # Errors
    /// [`crate::error::CompileError::Crease`] for an angle not from 0 to 180 degrees.
    pub fn smooth(degrees: f64) -> Result<Surface, crate::error::CompileError> {
        Ok(Surface::Smooth(normals::Crease::new(degrees)?))
    }
}

/// The colours of a polygon's two sides.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sides {
    /// Seen from its convex set's interior side.
    pub interior: [u8; 3],
    /// Seen from the other side.
    pub exterior: [u8; 3],
}

impl Shading {
    /// Refuses a light that cannot shade: a sun's direction of no length or not finite (every
    /// face would get only its ambient colour), a point light's position that is not finite.
    pub fn check(&self) -> Result<(), crate::error::CompileError> {
        let text = |v: DVec3| format!("{},{},{}", v.x, v.y, v.z);
        let why = match *self {
            Shading::Flat => None,
            Shading::Lambert(towards) if !towards.is_finite() => Some(format!(
                "the light direction {} is not finite",
                text(towards)
            )),
            Shading::Lambert(towards) if towards.try_normalize().is_none() => Some(format!(
                "the light direction {} has no length: it points from the scene towards the \
                 light, e.g. {}",
                text(towards),
                text(DEFAULT_LIGHT)
            )),
            Shading::Point(at) if !at.is_finite() => Some(format!(
                "the point light position {} is not finite",
                text(at)
            )),
            Shading::Lambert(_) | Shading::Point(_) => None,
        };
        why.map_or(Ok(()), |m| Err(crate::error::CompileError::Light(m)))
    }

    /// The light that casts shadows (`None` without lighting).
    pub fn light(&self) -> Option<crate::shadow::Light> {
        match *self {
            Shading::Flat => None,
            Shading::Lambert(towards) => Some(crate::shadow::Light::Sun(towards)),
            Shading::Point(at) => Some(crate::shadow::Light::Point(at)),
        }
    }

    /// The baked colour of the side of a face of material colour `kd` whose unit normal,
    /// pointing to the eyes that see the side, is `normal`, at the point `at` (world
    /// coordinates; only a point light depends on it).
    pub fn shade_at(&self, kd: [u8; 3], normal: DVec3, at: DVec3) -> [u8; 3] {
        let k = self.intensity_at(normal, at);
        kd.map(|c| channel(f64::from(c) * k))
    }

    /// The factor [`Shading::shade_at`] multiplies the material colour by, unrounded:
    /// `AMBIENT + (1 - AMBIENT) * max(n · l, 0)` for the side of unit normal `normal` at the
    /// point `at`, 1 when [`Shading::Flat`]. Smooth shading takes it at each corner.
    pub fn intensity_at(&self, normal: DVec3, at: DVec3) -> f64 {
        let towards = match *self {
            Shading::Flat => return 1.0,
            Shading::Lambert(towards) => towards,
            Shading::Point(light) => light - at,
        };
        let l = towards.normalize_or_zero();
        AMBIENT + (1.0 - AMBIENT) * normal.dot(l).clamp(0.0, 1.0)
    }

    /// The factor of a side in shadow: [`AMBIENT`] (1 when [`Shading::Flat`], which casts none).
    pub fn intensity_in_shadow(&self) -> f64 {
        self.intensity_at(DVec3::ZERO, DVec3::ZERO)
    }

    /// [`Shading::shade_at`] the origin: a sun lights every point alike.
    pub fn shade(&self, kd: [u8; 3], normal: DVec3) -> [u8; 3] {
        self.shade_at(kd, normal, DVec3::ZERO)
    }

    /// Both sides of a face of material colour `kd` in shadow: the ambient part of `kd` (or
    /// `kd` itself when [`Shading::Flat`]).
    pub fn in_shadow(&self, kd: [u8; 3]) -> Sides {
        let ambient = self.shade(kd, DVec3::ZERO);
        Sides {
            interior: ambient,
            exterior: ambient,
        }
    }

    /// Both sides of a face of material colour `kd` and unit normal `normal`, its interior on
    /// the side `normal` points to when `interior_front` is set, lit as at its point `at`.
    pub fn sides(&self, kd: [u8; 3], normal: DVec3, interior_front: bool, at: DVec3) -> Sides {
        let inward = if interior_front { normal } else { -normal };
        Sides {
            interior: self.shade_at(kd, inward, at),
            exterior: self.shade_at(kd, -inward, at),
        }
    }
}

/// A colour channel in 8-bit units, rounded to the nearest and kept in `0..=255`.
pub fn channel(value: f64) -> u8 {
    value.round().clamp(0.0, 255.0) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_light_without_direction_or_position_is_refused() {
        for (shading, says) in [
            (
                Shading::Lambert(DVec3::ZERO),
                "the light direction 0,0,0 has no length",
            ),
            (Shading::Lambert(DVec3::splat(1e-320)), "has no length"),
            (
                Shading::Lambert(DVec3::new(f64::NAN, 1.0, 0.0)),
                "is not finite",
            ),
            (
                Shading::Point(DVec3::new(0.0, f64::INFINITY, 0.0)),
                "position 0,inf,0 is not finite",
            ),
        ] {
            let e = shading.check().unwrap_err().to_string();
            assert!(e.contains(says), "{shading:?}: {e}");
        }
        for fine in [
            Shading::Flat,
            Shading::default(),
            Shading::Lambert(DVec3::new(0.0, -1e-3, 0.0)),
            Shading::Point(DVec3::ZERO),
        ] {
            assert!(fine.check().is_ok(), "{fine:?}");
        }
    }

    #[test]
    fn flat_keeps_material_colour_on_both_sides() {
        assert_eq!(Shading::Flat.shade([10, 20, 30], DVec3::X), [10, 20, 30]);
        let sides = Shading::Flat.sides([10, 20, 30], DVec3::Y, true, DVec3::ZERO);
        assert_eq!(sides.interior, [10, 20, 30]);
        assert_eq!(sides.exterior, [10, 20, 30]);
    }

    #[test]
    fn the_side_facing_the_light_is_lit_and_the_other_is_ambient() {
        let s = Shading::Lambert(DVec3::Y);
        assert_eq!(s.shade([200, 100, 50], DVec3::Y), [200, 100, 50]);
        assert_eq!(s.shade([200, 100, 50], -DVec3::Y), [60, 30, 15]);
        assert_eq!(s.shade([200, 100, 50], DVec3::X), [60, 30, 15], "edge-on");
        let slanted = s.shade([200, 100, 50], DVec3::new(0.0, 0.6, 0.8));
        assert_eq!(slanted, [144, 72, 36], "Kd * (0.3 + 0.7 * 0.6)");
    }

    #[test]
    fn sides_follow_the_interior() {
        let s = Shading::Lambert(DVec3::Y);
        let lit = [200, 100, 50];
        let ambient = [60, 30, 15];
        let at = DVec3::new(5.0, -3.0, 2.0);
        let up = s.sides(lit, DVec3::Y, true, at);
        assert_eq!((up.interior, up.exterior), (lit, ambient));
        let down = s.sides(lit, DVec3::Y, false, at);
        assert_eq!((down.interior, down.exterior), (ambient, lit));
        let flipped = s.sides(lit, -DVec3::Y, false, at);
        assert_eq!(flipped, up, "the same face named by the opposite normal");
    }

    #[test]
    fn a_point_light_lights_by_its_direction_from_the_point() {
        let s = Shading::Point(DVec3::new(0.0, 2.0, 0.0));
        let kd = [200, 100, 50];
        // Straight below the light: full colour; beside it at 45 degrees: 0.3 + 0.7 / sqrt 2.
        assert_eq!(s.shade_at(kd, DVec3::Y, DVec3::ZERO), kd);
        assert_eq!(
            s.shade_at(kd, DVec3::Y, DVec3::new(2.0, 0.0, 0.0)),
            [159, 79, 40]
        );
        assert_eq!(
            s.shade_at(kd, -DVec3::Y, DVec3::ZERO),
            [60, 30, 15],
            "turned away"
        );
        // Above the light, the face's top is turned away from it.
        assert_eq!(
            s.shade_at(kd, DVec3::Y, DVec3::new(0.0, 3.0, 0.0)),
            [60, 30, 15]
        );
    }

    #[test]
    fn default_light_orders_faces_by_angle() {
        let s = Shading::default();
        let top = s.shade([255, 255, 255], DVec3::Y)[0];
        let side = s.shade([255, 255, 255], DVec3::Z)[0];
        let other_side = s.shade([255, 255, 255], DVec3::X)[0];
        let bottom = s.shade([255, 255, 255], -DVec3::Y)[0];
        assert!(
            top > side && side > other_side && other_side > bottom,
            "{top} {side} {other_side} {bottom}"
        );
        assert_eq!(bottom, (255.0 * AMBIENT).round() as u8);
    }
}
