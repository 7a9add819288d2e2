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
    /// default near distance); the error says why the camera is degenerate.
    pub fn camera(&self, header: &Header) -> Result<Camera, String> {
        Camera::look_at(
            Pose {
                eye: self.eye,
                target: self.target,
                up: self.up,
            },
            self.fov_y_deg,
            self.width,
            self.height,
            self.near_over(header),
        )
        .map_err(|e| e.to_string())
    }
}
