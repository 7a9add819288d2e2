//! Camera: where the eye is, where it looks, and how camera space maps to pixels.
//!
//! The world camera [`Camera`] with the ways to pose it ([`Pose`], [`Orbit`]) and its
//! [`Intrinsics`] are here; the same camera in a scene's local `f32` frame ([`LocalView`], the
//! per-vertex work) and a node box carried into that frame ([`CameraBox`]) in `local_view.rs`;
//! [`LocalOrbit`], an orbit made in `f32` alone, in `local_orbit.rs`.
//!
//! # Conventions (the project's camera specification, restated)
//!
//! World coordinates are right-handed. A camera is an `eye`, a `target`, an `up` vector
//! (default `0,1,0`), a vertical field of view `fov_y` in degrees (default 60), an image of
//! `W x H` pixels and a `near` distance (default: `1e-3` times the scene's bounding-box
//! diagonal, see [`Camera::default_near`]).
//!
//! ```text
//! f   = normalize(target - eye)      forward
//! r   = normalize(cross(f, up))      right
//! u   = cross(r, f)                  true up
//! fpx = (H / 2) / tan(fov_y / 2)     focal length in pixels (square pixels)
//!
//! xc = dot(P - eye, r)   yc = dot(P - eye, u)   zc = dot(P - eye, f)    camera space
//! sx = W / 2 + fpx * xc / zc          screen x, to the right
//! sy = H / 2 - fpx * yc / zc          screen y, downwards
//! ```
//!
//! Only points with `zc >= near` are visible; the rest is clipped away (see [`crate::clip`]),
//! never wrapped around. Pixel `(i, j)` is column `i` from the left, row `j` from the top, and
//! its sample point is its centre `(i + 0.5, j + 0.5)`.
//!
//! # The focal/pixel-ratio parametrisation
//!
//! [`Camera::from_intrinsics`] takes the classic pinhole model instead: a focal distance `f`,
//! the width `rx` and height `ry` of a pixel (same unit as `f`), and the principal point
//! `(i0, j0)` in pixels. A camera-space point then lands at
//! `i = i0 + f * xc / (rx * zc)`, `j = j0 - f * yc / (ry * zc)` (the image `j` axis points
//! against the true up). With `f / rx = f / ry = fpx` and `(i0, j0) = (W / 2, H / 2)` it is
//! exactly the look-at camera above.
//!
//! # Precision
//!
//! The camera is kept in `f64`. A `.peel` file stores `f32` coordinates relative to a `centre`
//! given in `f64`; [`Camera::view`] subtracts that centre from the eye in `f64` and only then
//! rounds to `f32`, so a scene far from the world origin keeps its precision.
//!
//! # An `f32` camera for small cores
//!
//! A core without `f64` hardware (Cortex-M4F) pays for the `f64` camera in software floating
//! point. [`LocalView::look_at`] builds the renderer's [`LocalView`] directly in `f32`, in the
//! scene's local frame (coordinates relative to the header's `centre`), from a focal length
//! in pixels (no `tan`); [`crate::render::Renderer::draw`] takes it. It is the look-at camera
//! above with `fpx = focal` and the principal point at the image centre, rounded to `f32`
//! one step earlier (the basis is normalised in `f32`): fine for a scene near its centre,
//! which is where the compiler puts it. Firmware that never calls [`Camera`] links no `f64`
//! arithmetic at all.
//!
//! [`LocalOrbit`] is [`Orbit`] the same way: the view of an orbit around a scene, made in
//! `f32` alone, with no libm either (polynomial sines and cosines, a Newton square root, the
//! basis written out); see its module for how close it stays to the `f64` path.

use glam::{DVec3, Vec3};

use crate::error::RenderError;
use crate::read::Header;

mod local_orbit;
mod local_view;
pub use local_orbit::{sin_cos_deg, LocalOrbit};
pub use local_view::{CameraBox, LocalView};

/// Field of view used when the caller has no preference, in degrees.
pub const DEFAULT_FOV_Y_DEG: f64 = 60.0;
/// Up vector used when the caller has no preference.
pub const DEFAULT_UP: DVec3 = DVec3::Y;
/// Default near distance as a fraction of the scene's bounding-box diagonal.
pub const DEFAULT_NEAR_FRACTION: f64 = 1e-3;

/// Where the camera is and where it looks (world coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Eye position.
    pub eye: DVec3,
    /// A point the optical axis goes through.
    pub target: DVec3,
    /// Approximate up direction (need not be orthogonal to the view direction).
    pub up: DVec3,
}

impl Pose {
    /// A pose with the default up vector `0,1,0`.
    pub fn new(eye: DVec3, target: DVec3) -> Self {
        Pose {
            eye,
            target,
            up: DEFAULT_UP,
        }
    }
}

/// A camera position that needs no knowledge of a scene's coordinates: on a sphere around the
/// centre of the scene's bounding box (from its header), looking at that centre, up `0,1,0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// Degrees around the vertical (`y`) axis, from `+z` towards `+x`.
    pub azimuth_deg: f64,
    /// Degrees above the horizontal plane, strictly between -90 and 90 (straight up or down
    /// the view direction would be parallel to `up`).
    pub elevation_deg: f64,
    /// Distance of the eye from the box centre, in bounding radii (half the box diagonal):
    /// above 1 the eye is outside the whole scene.
    pub distance: f64,
}

impl Default for Orbit {
    /// A three-quarter view from slightly above, at 2.5 bounding radii: the whole scene fits
    /// a 60° field of view with room to spare.
    fn default() -> Self {
        Orbit {
            azimuth_deg: 30.0,
            elevation_deg: 20.0,
            distance: 2.5,
        }
    }
}

impl Orbit {
    /// The smallest distance, in bounding radii, at which the bounding sphere fits a
    /// `width x height` image with a vertical field of view `fov_y_deg`, plus 5% of margin.
    pub fn fitting_distance(fov_y_deg: f64, width: u32, height: u32) -> f64 {
        let half_y = (fov_y_deg * 0.5).to_radians();
        let aspect = f64::from(width.max(1)) / f64::from(height.max(1));
        let half_x = libm::atan(libm::tan(half_y) * aspect);
        1.05 / libm::sin(half_y.min(half_x))
    }

    /// The world-space bounding sphere of a scene: its box's centre and half diagonal (1 for
    /// a scene without extent, so that a pose can still be made).
    pub fn bounding_sphere(header: &Header) -> (DVec3, f64) {
        let (lo, hi) = (header.bounds_min.as_dvec3(), header.bounds_max.as_dvec3());
        let centre = DVec3::from_array(header.centre) + (lo + hi) * 0.5;
        let radius = (hi - lo).length() * 0.5;
        (centre, if radius > 0.0 { radius } else { 1.0 })
    }

    /// The pose of this orbit around the scene whose header is `header`.
    pub fn pose(&self, header: &Header) -> Pose {
        let (centre, radius) = Orbit::bounding_sphere(header);
        let (az, el) = (
            self.azimuth_deg.to_radians(),
            self.elevation_deg.to_radians(),
        );
        let dir = DVec3::new(
            libm::cos(el) * libm::sin(az),
            libm::sin(el),
            libm::cos(el) * libm::cos(az),
        );
        Pose::new(centre + dir * (self.distance * radius), centre)
    }
}

/// The pinhole parameters of the focal/pixel-ratio model (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Intrinsics {
    /// Distance from the optical centre to the image plane.
    pub f: f64,
    /// Width of a pixel, in the unit of `f`.
    pub rx: f64,
    /// Height of a pixel, in the unit of `f`.
    pub ry: f64,
    /// Principal point, column (continuous pixel coordinates).
    pub i0: f64,
    /// Principal point, row (continuous pixel coordinates, downwards).
    pub j0: f64,
}

/// A validated camera (world coordinates, `f64`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    eye: DVec3,
    right: DVec3,
    up: DVec3,
    forward: DVec3,
    /// Focal lengths in pixels, horizontal and vertical.
    fx: f64,
    fy: f64,
    /// Principal point in pixels.
    cx: f64,
    cy: f64,
    width: u32,
    height: u32,
    near: f64,
}

impl Camera {
    /// The camera of the project's specification: `fov_y_deg` is the vertical field of view.
    ///
    /// Refuses ([`RenderError::BadCamera`]) a zero-size image, `eye == target`, an `up`
    /// parallel to the view direction, a field of view outside `(0, 180)`, a near distance
    /// that is not positive, or any non-finite value.
    pub fn look_at(
        pose: Pose,
        fov_y_deg: f64,
        width: u32,
        height: u32,
        near: f64,
    ) -> Result<Camera, RenderError> {
        if !(fov_y_deg > 0.0 && fov_y_deg < 180.0) {
            return Err(RenderError::BadCamera);
        }
        let half = (fov_y_deg * 0.5).to_radians();
        let fpx = (f64::from(height) * 0.5) / libm::tan(half);
        // Square pixels of unit size: `f / rx = f / ry = fpx` exactly.
        let intrinsics = Intrinsics {
            f: fpx,
            rx: 1.0,
            ry: 1.0,
            i0: f64::from(width) * 0.5,
            j0: f64::from(height) * 0.5,
        };
        Camera::from_intrinsics(pose, intrinsics, width, height, near)
    }

    /// The focal/pixel-ratio camera (see the module docs), oriented by `pose` like
    /// [`Camera::look_at`]. Same refusals, plus `f`, `rx` or `ry` not positive.
    pub fn from_intrinsics(
        pose: Pose,
        intrinsics: Intrinsics,
        width: u32,
        height: u32,
        near: f64,
    ) -> Result<Camera, RenderError> {
        let Intrinsics { f, rx, ry, i0, j0 } = intrinsics;
        let (fx, fy) = (f / rx, f / ry);
        let finite = pose.eye.is_finite()
            && pose.target.is_finite()
            && pose.up.is_finite()
            && fx.is_finite()
            && fy.is_finite()
            && i0.is_finite()
            && j0.is_finite()
            && near.is_finite();
        let positive = f > 0.0 && rx > 0.0 && ry > 0.0 && fx > 0.0 && fy > 0.0 && near > 0.0;
        if !(finite && positive) || width == 0 || height == 0 {
            return Err(RenderError::BadCamera);
        }
        let forward = (pose.target - pose.eye)
            .try_normalize()
            .ok_or(RenderError::BadCamera)?;
        let right = forward
            .cross(pose.up)
            .try_normalize()
            .ok_or(RenderError::BadCamera)?;
        let up = right.cross(forward);
        Ok(Camera {
            eye: pose.eye,
            right,
            up,
            forward,
            fx,
            fy,
            cx: i0,
            cy: j0,
            width,
            height,
            near,
        })
    }

    /// The specification's default near distance: `1e-3` times the diagonal of the scene's
    /// bounding box (a `.peel` header gives `bounds_min`, `bounds_max`).
    pub fn default_near(bounds_min: Vec3, bounds_max: Vec3) -> f64 {
        (bounds_max.as_dvec3() - bounds_min.as_dvec3()).length() * DEFAULT_NEAR_FRACTION
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Near distance.
    pub fn near(&self) -> f64 {
        self.near
    }

    /// Eye position (world).
    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// The orthonormal camera basis `(right, true up, forward)`.
    pub fn basis(&self) -> (DVec3, DVec3, DVec3) {
        (self.right, self.up, self.forward)
    }

    /// Camera-space coordinates `(xc, yc, zc)` of a world point, in `f64`.
    pub fn to_camera(&self, p: DVec3) -> DVec3 {
        let v = p - self.eye;
        DVec3::new(v.dot(self.right), v.dot(self.up), v.dot(self.forward))
    }

    /// Screen position `(sx, sy)` of a world point, in `f64`; `None` when it is closer than
    /// the near distance. A reference for tests and tools; the renderer uses [`LocalView`].
    pub fn project(&self, p: DVec3) -> Option<(f64, f64)> {
        let c = self.to_camera(p);
        if c.z.is_nan() || c.z < self.near {
            return None;
        }
        Some((self.cx + self.fx * c.x / c.z, self.cy - self.fy * c.y / c.z))
    }

    /// The camera as seen from a scene whose coordinates are relative to `centre`, in `f32`.
    pub fn view(&self, centre: [f64; 3]) -> LocalView {
        let eye = self.eye - DVec3::from_array(centre);
        LocalView {
            eye: eye.as_vec3(),
            right: self.right.as_vec3(),
            up: self.up.as_vec3(),
            forward: self.forward.as_vec3(),
            fx: self.fx as f32,
            fy: self.fy as f32,
            cx: self.cx as f32,
            cy: self.cy as f32,
            width: self.width,
            height: self.height,
            near: self.near as f32,
        }
    }
}

#[cfg(test)]
mod tests;
