//! [`LocalView`]: the camera as the renderer takes it, in a scene's local `f32` frame, with the
//! per-vertex work (camera space, projection) and the culling's boxes ([`CameraBox`]). Made
//! from a [`Camera`](super::Camera), or in `f32` alone for cores without `f64`
//! ([`LocalView::look_at`]).

use glam::{Vec2, Vec3};

use crate::error::RenderError;

/// A world box in camera space ([`LocalView::box_to_camera`]): the exact camera-space image of
/// every point of the box lies within `centre ± extent`, and the `f32` camera-space position
/// the renderer computes for any of them (a vertex's [`LocalView::to_camera`], or a point clipped
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

/// A [`Camera`](super::Camera) in a scene's local `f32` frame: the per-vertex work of the renderer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalView {
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

impl LocalView {
    /// The look-at camera of [the module docs](super), computed in `f32` in the scene's local
    /// frame: `eye`, `target` and `up` relative to the scene's `centre`, `focal` the focal
    /// length in pixels (`(H / 2) / tan(fov_y / 2)` for a vertical field of view `fov_y`), the
    /// principal point at the image centre. Refuses ([`RenderError::BadCamera`]) what
    /// [`Camera::look_at`](super::Camera::look_at) refuses: a zero-size image,
    /// `eye == target`, an `up` parallel to the view direction, a focal length or near
    /// distance that is not positive, any non-finite value.
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        focal: f32,
        width: u32,
        height: u32,
        near: f32,
    ) -> Result<LocalView, RenderError> {
        // Non-finite `eye`, `target` or `up` make a direction that does not normalise.
        let forward = (target - eye)
            .try_normalize()
            .ok_or(RenderError::BadCamera)?;
        let right = forward
            .cross(up)
            .try_normalize()
            .ok_or(RenderError::BadCamera)?;
        let view = LocalView::from_basis(eye, right, forward, focal, width, height, near);
        view.check()?;
        Ok(view)
    }

    /// The look-at view of [`LocalView::look_at`] from its basis already computed: `right` and
    /// `forward` unit and orthogonal (the true up is their cross product), square pixels of
    /// focal length `focal`, the principal point at the image centre. For firmware whose
    /// orbit fixes the basis, so that it needs no square root. Not checked: as for a view
    /// written field by field, [`crate::render::Renderer::draw`] checks it ([`LocalView::check`]).
    pub fn from_basis(
        eye: Vec3,
        right: Vec3,
        forward: Vec3,
        focal: f32,
        width: u32,
        height: u32,
        near: f32,
    ) -> LocalView {
        LocalView {
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
        }
    }

    /// Whether the view is usable: every value finite, a non-empty image, positive focal
    /// lengths and near distance ([`RenderError::BadCamera`] otherwise). The fields are
    /// public, so [`crate::render::Renderer::draw`] checks this before drawing; a view from
    /// [`LocalView::look_at`] always passes. The basis is not checked for orthonormality: a skewed
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

    /// A screen rectangle `(min, max)` holding [`LocalView::project`] of the computed camera-space
    /// position of every point of `b` (a vertex's [`LocalView::to_camera`], or a point clipped from
    /// a polygon inside the box), up to the rounding of the screen values themselves (a few
    /// units in their last place); `None` unless all of them are at least `near` away (also
    /// for NaN), where projecting is monotonic.
    pub fn box_on_screen(&self, b: &CameraBox) -> Option<(Vec2, Vec2)> {
        let grow = Vec3::splat(b.error);
        let (a, b) = (b.centre - b.extent - grow, b.centre + b.extent + grow);
        if a.z.is_nan() || a.z < self.near {
            return None;
        }
        // `x / z` over the box is extreme at its corners (monotonic in each). `min` and `max`
        // as `f32::min` and `f32::max` (a NaN gives the other) without their library call on
        // cores without a minimum instruction.
        let least = |x: f32| {
            let (p, q) = (x / a.z, x / b.z);
            if p < q || q.is_nan() {
                p
            } else {
                q
            }
        };
        let most = |x: f32| {
            let (p, q) = (x / a.z, x / b.z);
            if p > q || q.is_nan() {
                p
            } else {
                q
            }
        };
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
        // `c.z.max(self.near)` (NaN gives `near`) without a library call.
        let z = if c.z >= self.near { c.z } else { self.near };
        Vec2::new(self.cx + self.fx * (c.x / z), self.cy - self.fy * (c.y / z))
    }
}
