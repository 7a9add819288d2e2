//! Shot: the host's one description of a camera, in the terms of `docs/host.md` ("Camera and pixels"):
//! where the eye is, what it looks at, the field of view, the image size and the near
//! distance. The CLI, the raster, the reference ray caster, the benchmark and the tests all
//! describe their cameras with it; [`Shot::camera`] makes the runtime's validated
//! [`Camera`] of it, and the reference reads it directly (independently of the runtime).

use glam::DVec3;
use peel_runtime::camera::{Camera, Pose, DEFAULT_FOV_Y_DEG, DEFAULT_UP};
use peel_runtime::read::Header;

/// A camera in the terms of `docs/host.md`; `near: None` is the default near distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shot {
    /// Eye position (world).
    pub eye: DVec3,
    /// Point looked at (world).
    pub target: DVec3,
    /// Up hint.
    pub up: DVec3,
    /// Vertical field of view in degrees.
    pub fov_y_deg: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Near distance, or the default (1e-3 x the scene's bounding-box diagonal).
    pub near: Option<f64>,
}

impl Shot {
    /// A `width x height` shot from `eye` at `target` with the defaults: up `0,1,0`, a 60°
    /// vertical field of view, the default near distance.
    pub const fn new(eye: DVec3, target: DVec3, width: u32, height: u32) -> Shot {
        Shot {
            eye,
            target,
            up: DEFAULT_UP,
            fov_y_deg: DEFAULT_FOV_Y_DEG,
            width,
            height,
            near: None,
        }
    }

    /// The near distance over the scene with header `header`: the shot's own, or the default
    /// ([`Camera::default_near`]).
    pub fn near_over(&self, header: &Header) -> f64 {
        self.near
            .unwrap_or_else(|| Camera::default_near(header.bounds_min, header.bounds_max))
    }

    /// The runtime camera of this shot over the scene with header `header` (resolving the
    /// default near distance); the error says which value makes the camera degenerate.
    pub fn camera(&self, header: &Header) -> Result<Camera, String> {
        let near = self.near_over(header);
        Camera::look_at(
            Pose {
                eye: self.eye,
                target: self.target,
                up: self.up,
            },
            self.fov_y_deg,
            self.width,
            self.height,
            near,
        )
        .map_err(|e| match self.why_degenerate(near) {
            Some(why) => format!("{e}: {why}"),
            None => e.to_string(),
        })
    }

    /// Which value of this shot (with near distance `near`) the runtime's camera refuses, in
    /// the order [`Camera::look_at`] checks them.
    fn why_degenerate(&self, near: f64) -> Option<String> {
        let fov = self.fov_y_deg;
        if !(fov > 0.0 && fov < 180.0) {
            return Some(format!(
                "the vertical field of view {fov} is not strictly between 0 and 180 degrees"
            ));
        }
        if self.width == 0 || self.height == 0 {
            return Some(format!(
                "the image size {}x{} is empty",
                self.width, self.height
            ));
        }
        if !(self.eye.is_finite() && self.target.is_finite() && self.up.is_finite()) {
            return Some("the eye, the target or the up direction is not finite".into());
        }
        if !(near.is_finite() && near > 0.0) {
            return Some(match self.near {
                Some(_) => format!("the near distance {near} is not a positive number"),
                None => "the scene has no extent to take the default near distance from".into(),
            });
        }
        if self.up.try_normalize().is_none() {
            return Some("the up direction has no length".into());
        }
        let forward = (self.target - self.eye).try_normalize();
        match forward {
            None => Some("the eye and the target are the same point".into()),
            Some(f) if f.cross(self.up).try_normalize().is_none() => {
                Some("the view direction is parallel to the up direction".into())
            }
            Some(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use peel_runtime::read::Header;

    #[test]
    fn a_degenerate_shot_says_which_value_is_wrong() {
        let header = Header {
            bounds_max: glam::Vec3::ONE,
            ..Header::default()
        };
        let good = Shot::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, 64, 48);
        assert!(good.camera(&header).is_ok());
        let cases = [
            (
                Shot {
                    fov_y_deg: 180.0,
                    ..good
                },
                "field of view 180 is not strictly between 0 and 180",
            ),
            (
                Shot {
                    fov_y_deg: 0.0,
                    ..good
                },
                "field of view 0 is not",
            ),
            (Shot { width: 0, ..good }, "image size 0x48 is empty"),
            (
                Shot {
                    near: Some(-1.0),
                    ..good
                },
                "near distance -1 is not a positive number",
            ),
            (
                Shot {
                    target: good.eye,
                    ..good
                },
                "the eye and the target are the same point",
            ),
            (
                Shot {
                    up: DVec3::Z,
                    ..good
                },
                "parallel to the up direction",
            ),
            (
                Shot {
                    up: DVec3::ZERO,
                    ..good
                },
                "the up direction has no length",
            ),
            (
                Shot {
                    eye: DVec3::NAN,
                    ..good
                },
                "not finite",
            ),
        ];
        for (shot, says) in cases {
            let e = shot.camera(&header).unwrap_err();
            assert!(e.contains(says), "{shot:?}: {e}");
        }
        // No extent: no default near distance.
        let e = good.camera(&Header::default()).unwrap_err();
        assert!(e.contains("the scene has no extent"), "{e}");
    }
}
