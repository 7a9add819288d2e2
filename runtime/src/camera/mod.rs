//! Camera: where the eye is, where it looks, and how camera space maps to pixels.
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
//! point. [`View::look_at`] builds the renderer's [`View`] directly in `f32`, in the scene's
//! local frame (coordinates relative to the header's `centre`), from a focal length in
//! pixels (no `tan`); [`crate::render::Renderer::draw`] takes it. It is the look-at camera
//! above with `fpx = focal` and the principal point at the image centre, rounded to `f32`
//! one step earlier (the basis is normalised in `f32`): fine for a scene near its centre,
//! which is where the compiler puts it. Firmware that never calls [`Camera`] links no `f64`
//! arithmetic at all.

use glam::{DVec3, Vec2, Vec3};

use crate::error::RenderError;
use crate::read::Header;

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
        Camera::build(
            pose,
            fpx,
            fpx,
            f64::from(width) * 0.5,
            f64::from(height) * 0.5,
            width,
            height,
            near,
        )
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
        if !(f > 0.0 && rx > 0.0 && ry > 0.0) {
            return Err(RenderError::BadCamera);
        }
        Camera::build(pose, f / rx, f / ry, i0, j0, width, height, near)
    }

    #[allow(clippy::too_many_arguments)]
    fn build(
        pose: Pose,
        fx: f64,
        fy: f64,
        cx: f64,
        cy: f64,
        width: u32,
        height: u32,
        near: f64,
    ) -> Result<Camera, RenderError> {
        let finite = pose.eye.is_finite()
            && pose.target.is_finite()
            && pose.up.is_finite()
            && fx.is_finite()
            && fy.is_finite()
            && cx.is_finite()
            && cy.is_finite()
            && near.is_finite();
        if !finite || width == 0 || height == 0 || near <= 0.0 || fx <= 0.0 || fy <= 0.0 {
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
            cx,
            cy,
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
    /// the near distance. A reference for tests and tools; the renderer uses [`View`].
    pub fn project(&self, p: DVec3) -> Option<(f64, f64)> {
        let c = self.to_camera(p);
        if c.z.is_nan() || c.z < self.near {
            return None;
        }
        Some((self.cx + self.fx * c.x / c.z, self.cy - self.fy * c.y / c.z))
    }

    /// The camera as seen from a scene whose coordinates are relative to `centre`, in `f32`.
    pub fn view(&self, centre: [f64; 3]) -> View {
        let eye = self.eye - DVec3::from_array(centre);
        View {
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

/// A world box in camera space ([`View::box_to_camera`]): the exact camera-space image of
/// every point of the box lies within `centre ± extent`, and the `f32` camera-space position
/// the renderer computes for any of them (a vertex's [`View::to_camera`], or a point clipped
/// from a polygon inside the box) within `error` more on each axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraBox {
    /// Camera-space centre.
    pub centre: Vec3,
    /// Half extents along the camera axes (each axis gets `|axis|·h`).
    pub extent: Vec3,
    /// Bound on the `f32` error of any computed camera-space position in the box, per axis.
    pub error: f32,
}

impl CameraBox {
    /// `error` per unit of the box's reach `|mid − eye|₁ + |mid|₁ + |h|₁` (midpoint `mid`, half
    /// size `h`, in the scene frame). Each `f32` operation rounds by at most `2^-24` of its
    /// result: a point's `p − eye` and its three-term dot products with the unit axes stay
    /// within `5 · 2^-24 · |p − eye|₁` of the exact camera position, the box's midpoint, half
    /// size and extents within `4 · 2^-24` of the reach, and a clipped point (a convex
    /// combination of such points) adds a few more units; `2^-18` is more than four times
    /// their sum.
    pub const ERROR: f32 = 1.0 / 262_144.0;
}

/// A [`Camera`] in a scene's local `f32` frame: the per-vertex work of the renderer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Eye position relative to the scene centre.
    pub eye: Vec3,
    /// Right vector.
    pub right: Vec3,
    /// True up vector.
    pub up: Vec3,
    /// Forward vector.
    pub forward: Vec3,
    /// Horizontal focal length in pixels.
    pub fx: f32,
    /// Vertical focal length in pixels.
    pub fy: f32,
    /// Principal point, column.
    pub cx: f32,
    /// Principal point, row.
    pub cy: f32,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Near distance (camera-space `zc` of the near plane).
    pub near: f32,
}

impl View {
    /// The look-at camera of the module docs, computed in `f32` in the scene's local frame:
    /// `eye`, `target` and `up` relative to the scene's `centre`, `focal` the focal length in
    /// pixels (`(H / 2) / tan(fov_y / 2)` for a vertical field of view `fov_y`), the principal
    /// point at the image centre. Refuses ([`RenderError::BadCamera`]) what
    /// [`Camera::look_at`] refuses: a zero-size image, `eye == target`, an `up` parallel to the
    /// view direction, a focal length or near distance that is not positive, any non-finite
    /// value.
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        focal: f32,
        width: u32,
        height: u32,
        near: f32,
    ) -> Result<View, RenderError> {
        // Non-finite `eye`, `target` or `up` make a direction that does not normalise.
        let forward = (target - eye)
            .try_normalize()
            .ok_or(RenderError::BadCamera)?;
        let right = forward
            .cross(up)
            .try_normalize()
            .ok_or(RenderError::BadCamera)?;
        let view = View {
            eye,
            right,
            up: right.cross(forward),
            forward,
            fx: focal,
            fy: focal,
            cx: width as f32 * 0.5,
            cy: height as f32 * 0.5,
            width,
            height,
            near,
        };
        view.check()?;
        Ok(view)
    }

    /// Whether the view is usable: every value finite, a non-empty image, positive focal
    /// lengths and near distance ([`RenderError::BadCamera`] otherwise). The fields are
    /// public, so [`crate::render::Renderer::draw`] checks this before drawing; a view from
    /// [`View::look_at`] always passes. The basis is not checked for orthonormality: a skewed
    /// one draws a skewed image, nothing worse.
    pub fn check(&self) -> Result<(), RenderError> {
        let (e, r, u, f) = (self.eye, self.right, self.up, self.forward);
        let values = [
            e.x, e.y, e.z, r.x, r.y, r.z, u.x, u.y, u.z, f.x, f.y, f.z, self.fx, self.fy, self.cx,
            self.cy, self.near,
        ];
        // One loop rather than seventeen inlined tests: this runs once per frame.
        let finite = values.iter().all(|v| v.is_finite());
        let positive = self.near > 0.0 && self.fx > 0.0 && self.fy > 0.0;
        if finite && positive && self.width != 0 && self.height != 0 {
            Ok(())
        } else {
            Err(RenderError::BadCamera)
        }
    }

    /// Camera-space coordinates of a scene point. A pure function of `p`: a vertex shared by
    /// two polygons gets bit-identical camera coordinates in both.
    pub fn to_camera(&self, p: Vec3) -> Vec3 {
        let v = p - self.eye;
        Vec3::new(v.dot(self.right), v.dot(self.up), v.dot(self.forward))
    }

    /// The camera-space box around the world box `lo..=hi` (see [`CameraBox`]). One transform
    /// instead of eight.
    pub fn box_to_camera(&self, lo: Vec3, hi: Vec3) -> CameraBox {
        let mid = (lo + hi) * 0.5;
        let h = (hi - lo) * 0.5;
        let extent = Vec3::new(
            self.right.abs().dot(h),
            self.up.abs().dot(h),
            self.forward.abs().dot(h),
        );
        let reach =
            (mid - self.eye).abs().element_sum() + mid.abs().element_sum() + h.abs().element_sum();
        CameraBox {
            centre: self.to_camera(mid),
            extent,
            error: CameraBox::ERROR * reach,
        }
    }

    /// A screen rectangle `(min, max)` holding [`View::project`] of the computed camera-space
    /// position of every point of `b` (a vertex's [`View::to_camera`], or a point clipped from
    /// a polygon inside the box), up to the rounding of the screen values themselves (a few
    /// units in their last place); `None` unless all of them are at least `near` away (also
    /// for NaN), where projecting is monotonic.
    pub fn box_on_screen(&self, b: &CameraBox) -> Option<(Vec2, Vec2)> {
        let grow = Vec3::splat(b.error);
        let (a, b) = (b.centre - b.extent - grow, b.centre + b.extent + grow);
        if a.z.is_nan() || a.z < self.near {
            return None;
        }
        // `x / z` over the box is extreme at its corners (monotonic in each).
        let least = |x: f32| (x / a.z).min(x / b.z);
        let most = |x: f32| (x / a.z).max(x / b.z);
        Some((
            Vec2::new(
                self.cx + self.fx * least(a.x),
                self.cy - self.fy * most(b.y),
            ),
            Vec2::new(
                self.cx + self.fx * most(b.x),
                self.cy - self.fy * least(a.y),
            ),
        ))
    }

    /// Screen position of a camera-space point that survived near clipping. `zc` is first
    /// raised to `near`: clipped points can land a rounding error short of the near plane and
    /// must never be projected from behind it.
    pub fn project(&self, c: Vec3) -> Vec2 {
        let z = c.z.max(self.near);
        Vec2::new(self.cx + self.fx * (c.x / z), self.cy - self.fy * (c.y / z))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
    }

    proptest::proptest! {
        /// Every corner of a world box, transformed and projected, lies in the screen
        /// rectangle of its camera-space box, to within the renderer's allowance for the
        /// rounding of screen values (`render::slack` without its snapping term: 1/64 pixel
        /// plus 2^-18 of the image's larger side, what culling relies on), and closer for a
        /// value smaller than that side (2^-18 of the value). In practice the box's error
        /// bound keeps every corner inside.
        #[test]
        fn box_rectangle_holds_every_projected_corner(
            eye in proptest::array::uniform3(-50.0f64..50.0),
            target in proptest::array::uniform3(-5.0f64..5.0),
            lo in proptest::array::uniform3(-10.0f32..10.0),
            size in proptest::array::uniform3(0.0f32..8.0),
        ) {
            let pose = Pose::new(DVec3::from_array(eye), DVec3::from_array(target));
            let Ok(cam) = Camera::look_at(pose, 60.0, 640, 480, 0.01) else { return Ok(()) };
            let view = cam.view([0.0; 3]);
            let lo = Vec3::from_array(lo);
            let hi = lo + Vec3::from_array(size);
            let b = view.box_to_camera(lo, hi);
            let Some((min, max)) = view.box_on_screen(&b) else { return Ok(()) };
            for k in 0..8 {
                let p = Vec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                );
                let q = view.project(view.to_camera(p));
                let tol = 1.0 / 64.0 + q.x.abs().max(q.y.abs()).min(640.0) / 262_144.0;
                proptest::prop_assert!(q.x >= min.x - tol && q.x <= max.x + tol, "{q} {min} {max}");
                proptest::prop_assert!(q.y >= min.y - tol && q.y <= max.y + tol, "{q} {min} {max}");
            }
        }
    }

    fn simple() -> Camera {
        // fov 90 -> fpx = (H/2) / tan(45) = 50.
        Camera::look_at(
            Pose::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO),
            90.0,
            200,
            100,
            0.01,
        )
        .unwrap()
    }

    #[test]
    fn look_at_matches_the_spec_formulas() {
        let cam = simple();
        let (r, u, f) = cam.basis();
        assert!(close(r.x, 1.0) && close(r.y, 0.0) && close(r.z, 0.0));
        assert!(close(u.x, 0.0) && close(u.y, 1.0) && close(u.z, 0.0));
        assert!(close(f.x, 0.0) && close(f.y, 0.0) && close(f.z, -1.0));
        // xc = 1, yc = 0.5, zc = 5: sx = 100 + 50 * 1 / 5, sy = 50 - 50 * 0.5 / 5.
        let (sx, sy) = cam.project(DVec3::new(1.0, 0.5, 0.0)).unwrap();
        assert!(close(sx, 110.0), "{sx}");
        assert!(close(sy, 45.0), "{sy}");
        // The target projects to the image centre.
        let (sx, sy) = cam.project(DVec3::ZERO).unwrap();
        assert!(close(sx, 100.0) && close(sy, 50.0));
    }

    #[test]
    fn oblique_camera_hand_computed() {
        // Eye on the +x axis looking at the origin: forward -x, right = cross(-x, y) = -z.
        // fov 60, H = 120 -> fpx = 60 / tan(30 deg) = 60 * sqrt(3).
        let cam = Camera::look_at(
            Pose::new(DVec3::new(10.0, 0.0, 0.0), DVec3::ZERO),
            60.0,
            160,
            120,
            0.1,
        )
        .unwrap();
        let p = DVec3::new(0.0, 2.0, -3.0); // xc = 3, yc = 2, zc = 10
        let c = cam.to_camera(p);
        assert!(close(c.x, 3.0) && close(c.y, 2.0) && close(c.z, 10.0));
        let fpx = 60.0 * 3f64.sqrt();
        let (sx, sy) = cam.project(p).unwrap();
        assert!(close(sx, 80.0 + fpx * 0.3));
        assert!(close(sy, 60.0 - fpx * 0.2));
    }

    #[test]
    fn points_closer_than_near_do_not_project() {
        let cam = simple();
        assert!(cam.project(DVec3::new(0.0, 0.0, 5.0)).is_none()); // the eye itself
        assert!(cam.project(DVec3::new(0.0, 0.0, 6.0)).is_none()); // behind
        assert!(cam.project(DVec3::new(0.0, 0.0, 4.995)).is_none()); // zc = 0.005 < near
        assert!(cam.project(DVec3::new(0.0, 0.0, 4.98)).is_some()); // zc = 2 * near
    }

    fn header(centre: [f64; 3], lo: [f32; 3], hi: [f32; 3]) -> Header {
        Header {
            version: 1,
            flags: 0,
            vertex_count: 0,
            plane_count: 0,
            index_count: 0,
            polygon_count: 0,
            node_count: 0,
            max_depth: 0,
            max_polygon_vertices: 0,
            centre,
            bounds_min: Vec3::from_array(lo),
            bounds_max: Vec3::from_array(hi),
            palette_count: 0,
            bounds_count: 0,
        }
    }

    proptest::proptest! {
        /// An orbit at the fitting distance sees every corner of the scene's box inside the
        /// image, whatever the scene's position, size and aspect and the orbit's angles.
        #[test]
        fn an_orbit_at_the_fitting_distance_frames_the_whole_box(
            centre in proptest::array::uniform3(-1e6f64..1e6),
            lo in proptest::array::uniform3(-50.0f32..0.0),
            size in proptest::array::uniform3(0.01f32..100.0),
            azimuth in -360.0f64..360.0,
            elevation in -85.0f64..85.0,
            fov in 10.0f64..120.0,
            width in 1u32..2000,
            height in 1u32..2000,
        ) {
            let lo = Vec3::from_array(lo);
            let hi = lo + Vec3::from_array(size);
            let h = header(centre, lo.to_array(), hi.to_array());
            let orbit = Orbit {
                azimuth_deg: azimuth,
                elevation_deg: elevation,
                distance: Orbit::fitting_distance(fov, width, height),
            };
            let cam = Camera::look_at(orbit.pose(&h), fov, width, height, 1e-6).unwrap();
            let (c, r) = Orbit::bounding_sphere(&h);
            proptest::prop_assert!((cam.eye().distance(c) / r - orbit.distance).abs() < 1e-6);
            for k in 0..8 {
                let p = DVec3::new(
                    f64::from(if k & 1 == 0 { lo.x } else { hi.x }),
                    f64::from(if k & 2 == 0 { lo.y } else { hi.y }),
                    f64::from(if k & 4 == 0 { lo.z } else { hi.z }),
                ) + DVec3::from_array(centre);
                let (sx, sy) = cam.project(p).unwrap();
                let (w, ht) = (f64::from(width), f64::from(height));
                proptest::prop_assert!(
                    (0.0..=w).contains(&sx) && (0.0..=ht).contains(&sy),
                    "corner {k} at ({sx}, {sy}) outside {width}x{height}"
                );
            }
        }
    }

    #[test]
    fn the_default_orbit_looks_at_the_box_centre_from_the_front_right_and_above() {
        let h = header([10.0, 0.0, 0.0], [-1.0, -2.0, -3.0], [1.0, 2.0, 3.0]);
        let pose = Orbit::default().pose(&h);
        assert_eq!(pose.target, DVec3::new(10.0, 0.0, 0.0));
        let d = pose.eye - pose.target;
        assert!(d.x > 0.0 && d.y > 0.0 && d.z > 0.0, "{d}");
        assert!((d.length() - 2.5 * 14f64.sqrt()).abs() < 1e-9);
        // A scene without extent still gets a pose one unit per radius away.
        let point = header([1.0, 2.0, 3.0], [0.0; 3], [0.0; 3]);
        assert!(
            (Orbit::default()
                .pose(&point)
                .eye
                .distance(DVec3::new(1.0, 2.0, 3.0))
                - 2.5)
                .abs()
                < 1e-9
        );
    }

    #[test]
    fn intrinsics_equal_look_at_when_parameters_agree() {
        let pose = Pose {
            eye: DVec3::new(1.0, 2.0, 3.0),
            target: DVec3::new(-2.0, 0.5, -4.0),
            up: DVec3::new(0.1, 1.0, 0.0),
        };
        let (w, h) = (320, 240);
        let a = Camera::look_at(pose, 50.0, w, h, 0.05).unwrap();
        let fpx = 120.0 / (25f64).to_radians().tan();
        let rx = 0.002;
        let intr = Intrinsics {
            f: fpx * rx,
            rx,
            ry: rx,
            i0: 160.0,
            j0: 120.0,
        };
        let b = Camera::from_intrinsics(pose, intr, w, h, 0.05).unwrap();
        for p in [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(-1.5, 0.7, -2.0),
            DVec3::new(3.0, -1.0, -9.0),
        ] {
            let (ax, ay) = a.project(p).unwrap();
            let (bx, by) = b.project(p).unwrap();
            assert!(close(ax, bx) && close(ay, by), "{ax},{ay} vs {bx},{by}");
        }
    }

    #[test]
    fn intrinsics_use_the_pixel_ratios_and_principal_point() {
        // i = i0 + f xc / (rx zc), j = j0 - f yc / (ry zc), with xc = 1, yc = 0.5, zc = 5.
        let intr = Intrinsics {
            f: 2.0,
            rx: 0.01,
            ry: 0.02,
            i0: 30.0,
            j0: 40.0,
        };
        let cam = Camera::from_intrinsics(
            Pose::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO),
            intr,
            64,
            64,
            0.01,
        )
        .unwrap();
        let (i, j) = cam.project(DVec3::new(1.0, 0.5, 0.0)).unwrap();
        assert!(close(i, 30.0 + 200.0 / 5.0), "{i}");
        assert!(close(j, 40.0 - 100.0 * 0.5 / 5.0), "{j}");
    }

    #[test]
    fn degenerate_cameras_are_refused() {
        let ok = Pose::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO);
        let bad = |r: Result<Camera, RenderError>| r == Err(RenderError::BadCamera);
        assert!(bad(Camera::look_at(ok, 60.0, 0, 10, 0.1)));
        assert!(bad(Camera::look_at(ok, 60.0, 10, 0, 0.1)));
        assert!(bad(Camera::look_at(ok, 0.0, 10, 10, 0.1)));
        assert!(bad(Camera::look_at(ok, 180.0, 10, 10, 0.1)));
        assert!(bad(Camera::look_at(ok, f64::NAN, 10, 10, 0.1)));
        assert!(bad(Camera::look_at(ok, 60.0, 10, 10, 0.0)));
        assert!(bad(Camera::look_at(ok, 60.0, 10, 10, f64::INFINITY)));
        let same = Pose::new(DVec3::ONE, DVec3::ONE);
        assert!(bad(Camera::look_at(same, 60.0, 10, 10, 0.1)));
        let parallel = Pose {
            eye: DVec3::new(0.0, 5.0, 0.0),
            target: DVec3::ZERO,
            up: DVec3::Y,
        };
        assert!(bad(Camera::look_at(parallel, 60.0, 10, 10, 0.1)));
        let nan = Pose::new(DVec3::new(f64::NAN, 0.0, 0.0), DVec3::ZERO);
        assert!(bad(Camera::look_at(nan, 60.0, 10, 10, 0.1)));
        let intr = Intrinsics {
            f: 1.0,
            rx: 0.0,
            ry: 1.0,
            i0: 0.0,
            j0: 0.0,
        };
        assert!(bad(Camera::from_intrinsics(ok, intr, 10, 10, 0.1)));
    }

    #[test]
    fn view_is_relative_to_the_centre_and_agrees_with_f64() {
        let centre = [1.0e6, -2.0e6, 3.0e6];
        let eye = DVec3::new(1.0e6 + 0.25, -2.0e6 + 1.5, 3.0e6 + 7.0);
        let cam = Camera::look_at(
            Pose::new(eye, DVec3::from_array(centre)),
            60.0,
            100,
            100,
            0.01,
        )
        .unwrap();
        let view = cam.view(centre);
        assert_eq!(view.eye, Vec3::new(0.25, 1.5, 7.0));
        let local = Vec3::new(0.5, -0.25, 1.0);
        let world = DVec3::from_array(centre) + local.as_dvec3();
        let (sx, sy) = cam.project(world).unwrap();
        let s = view.project(view.to_camera(local));
        assert!((f64::from(s.x) - sx).abs() < 1e-3 && (f64::from(s.y) - sy).abs() < 1e-3);
    }

    #[test]
    fn f32_look_at_agrees_with_the_f64_camera() {
        let centre = [3.0, -1.0, 2.0];
        let c = DVec3::from_array(centre);
        let (eye, target, up) = (
            DVec3::new(2.0, 3.0, 9.0),
            DVec3::new(-1.0, 0.5, 0.25),
            DVec3::new(0.1, 1.0, 0.0),
        );
        let (w, h) = (160, 120);
        let camera = Camera::look_at(Pose { eye, target, up }, 50.0, w, h, 0.01).unwrap();
        let focal = (60.0 / (25f64).to_radians().tan()) as f32;
        let view = View::look_at(
            (eye - c).as_vec3(),
            (target - c).as_vec3(),
            up.as_vec3(),
            focal,
            w,
            h,
            0.01,
        )
        .unwrap();
        let reference = camera.view(centre);
        assert_eq!(
            (view.width, view.height, view.cx, view.cy),
            (160, 120, 80.0, 60.0)
        );
        assert!((view.fx - reference.fx).abs() < 1e-4 && view.fx == view.fy);
        assert!((view.near - reference.near).abs() < 1e-9);
        for (a, b) in [
            (view.eye, reference.eye),
            (view.right, reference.right),
            (view.up, reference.up),
            (view.forward, reference.forward),
        ] {
            assert!((a - b).abs().max_element() < 1e-6, "{a} vs {b}");
        }
        for p in [
            Vec3::ZERO,
            Vec3::new(-1.5, 0.7, -2.0),
            Vec3::new(3.0, -1.0, -4.0),
        ] {
            let (s, r) = (
                view.project(view.to_camera(p)),
                reference.project(reference.to_camera(p)),
            );
            assert!((s - r).abs().max_element() < 1e-3, "{s} vs {r}");
        }
    }

    #[test]
    fn degenerate_f32_views_are_refused() {
        let (eye, target) = (Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO);
        let look = |eye: Vec3, target: Vec3, up: Vec3, focal: f32, w: u32, h: u32, near: f32| {
            View::look_at(eye, target, up, focal, w, h, near)
        };
        assert!(look(eye, target, Vec3::Y, 100.0, 10, 10, 0.1).is_ok());
        let bad = |r: Result<View, RenderError>| r == Err(RenderError::BadCamera);
        assert!(bad(look(eye, target, Vec3::Y, 100.0, 0, 10, 0.1)));
        assert!(bad(look(eye, target, Vec3::Y, 100.0, 10, 0, 0.1)));
        assert!(bad(look(eye, target, Vec3::Y, 0.0, 10, 10, 0.1)));
        assert!(bad(look(eye, target, Vec3::Y, f32::NAN, 10, 10, 0.1)));
        assert!(bad(look(eye, target, Vec3::Y, f32::INFINITY, 10, 10, 0.1)));
        assert!(bad(look(eye, target, Vec3::Y, 100.0, 10, 10, 0.0)));
        assert!(bad(look(eye, target, Vec3::Y, 100.0, 10, 10, f32::NAN)));
        assert!(bad(look(eye, eye, Vec3::Y, 100.0, 10, 10, 0.1)));
        assert!(bad(look(eye, target, Vec3::Z, 100.0, 10, 10, 0.1)));
        assert!(bad(look(eye, target, Vec3::NAN, 100.0, 10, 10, 0.1)));
        assert!(bad(look(
            Vec3::INFINITY,
            target,
            Vec3::Y,
            100.0,
            10,
            10,
            0.1
        )));
        assert!(bad(look(eye, Vec3::NAN, Vec3::Y, 100.0, 10, 10, 0.1)));
        let mut view = look(eye, target, Vec3::Y, 100.0, 10, 10, 0.1).unwrap();
        view.right.x = f32::NAN;
        assert_eq!(view.check(), Err(RenderError::BadCamera));
    }

    #[test]
    fn default_near_is_a_thousandth_of_the_diagonal() {
        let n = Camera::default_near(Vec3::ZERO, Vec3::new(3.0, 4.0, 12.0));
        assert!(close(n, 0.013));
    }
}
