//! Shade: bake two-sided Lambert lighting into each polygon's colour, so a one-colour mesh
//! reads as 3D without any lighting work at run time.
//!
//! `colour = Kd * (AMBIENT + (1 - AMBIENT) * |n · l|)`, rounded, with `n` the polygon's unit
//! normal and `l` the unit direction towards the light ([`DEFAULT_LIGHT`] unless `--light`
//! gives another). Two-sided: a face lit from behind is as bright as from the front, since
//! faces are drawn from both sides.

use glam::DVec3;

/// Direction towards the default light: up, right and towards +z (before normalisation).
pub const DEFAULT_LIGHT: DVec3 = DVec3::new(0.4, 0.8, 0.45);

/// Fraction of the colour that every face gets whatever its orientation.
pub const AMBIENT: f64 = 0.3;

/// How colours are baked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shading {
    /// Keep the material colours as they are.
    Flat,
    /// Two-sided Lambert from a directional light (the direction towards the light).
    Lambert(DVec3),
}

impl Default for Shading {
    fn default() -> Self {
        Shading::Lambert(DEFAULT_LIGHT)
    }
}

impl Shading {
    /// The baked colour of a face of material colour `kd` and unit normal `normal`.
    pub fn shade(&self, kd: [u8; 3], normal: DVec3) -> [u8; 3] {
        match *self {
            Shading::Flat => kd,
            Shading::Lambert(light) => {
                let l = light.normalize_or_zero();
                let k = AMBIENT + (1.0 - AMBIENT) * normal.dot(l).abs().min(1.0);
                kd.map(|c| (f64::from(c) * k).round().clamp(0.0, 255.0) as u8)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_keeps_material_colour() {
        assert_eq!(Shading::Flat.shade([10, 20, 30], DVec3::X), [10, 20, 30]);
    }

    #[test]
    fn facing_the_light_is_full_colour_and_edge_on_is_ambient() {
        let s = Shading::Lambert(DVec3::Y);
        assert_eq!(s.shade([200, 100, 50], DVec3::Y), [200, 100, 50]);
        assert_eq!(
            s.shade([200, 100, 50], -DVec3::Y),
            [200, 100, 50],
            "two-sided"
        );
        assert_eq!(s.shade([200, 100, 50], DVec3::X), [60, 30, 15]);
    }

    #[test]
    fn default_light_orders_faces_by_angle() {
        let s = Shading::default();
        let top = s.shade([255, 255, 255], DVec3::Y)[0];
        let side = s.shade([255, 255, 255], DVec3::Z)[0];
        let other_side = s.shade([255, 255, 255], DVec3::X)[0];
        assert!(top > side && side > other_side, "{top} {side} {other_side}");
    }
}
