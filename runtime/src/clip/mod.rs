//! Clip: Sutherland–Hodgman clipping of a convex polygon in camera space.
//!
//! A polygon is clipped first against the near plane `zc >= near` (so no point behind the eye
//! is ever projected), then against the four screen-window edges: the screen lines `sx = 0`,
//! `sx = W`, `sy = 0`, `sy = H`, lifted to planes through the eye (once `zc > 0`, `sx >= 0` is
//! `cx * zc + fx * xc >= 0`, and so on). Clipping against these planes before projecting gives
//! the same polygon as windowing the projected polygon (a central projection keeps lines and
//! sides for `zc > 0`), but the arithmetic only sees moderate camera-space coordinates: no
//! guard band, no huge projected values near the eye plane, no overflow to argue about.
//!
//! # Watertightness
//!
//! Two polygons sharing an edge must get bit-identical clipped points along it. Every step
//! here is a pure function of the edge's endpoints, independent of the direction the edge is
//! walked in: the inside test is per point, and an intersection is always computed from the
//! endpoint that is inside (`p_in + (p_out - p_in) * d_in / (d_in - d_out)`), so the two
//! polygons, which walk their shared edge in opposite directions, compute the same bits.
//!
//! # Memory
//!
//! The caller provides the buffers. Clipping a convex `n`-gon by one plane gives at most
//! `n + 1` vertices, so the [`CLIP_PLANES`] planes need buffers of `n + CLIP_PLANES`.

use glam::Vec3;

use crate::camera::{CameraBox, LocalView};
use crate::error::RenderError;

/// Number of planes a polygon is clipped against (near + four window edges).
pub const CLIP_PLANES: usize = 5;

/// A camera-space half-space `normal · p + offset >= 0` (points on the plane are inside).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClipPlane {
    /// Plane normal, pointing inside (not necessarily unit).
    pub normal: Vec3,
    /// Constant term.
    pub offset: f32,
}

impl ClipPlane {
    /// Whether every point of the camera-space box `b` fails this plane's `eval(p) >= 0` in
    /// `f32` as the clipper computes it: the margin covers `b`'s error and the rounding of
    /// the evaluation ([`Frustum::excludes_box`], a piece's cuts).
    pub fn excludes_box(&self, b: &CameraBox) -> bool {
        const ROUNDING: f32 = 1.0 / 262_144.0;
        let size = b.centre.abs() + b.extent + Vec3::splat(b.error);
        let n = self.normal.abs();
        let scale = n.element_sum();
        let margin =
            2.0 * scale * b.error + ROUNDING * (n.dot(size) + scale * b.error + self.offset.abs());
        self.eval(b.centre) + n.dot(b.extent) + margin < 0.0
    }

    /// Signed value at `p`: `>= 0` inside.
    pub fn eval(&self, p: Vec3) -> f32 {
        self.normal.dot(p) + self.offset
    }
}

/// The clip planes of a view, near plane first (the window planes are only valid once
/// `zc > 0`, which the near plane guarantees).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frustum {
    planes: [ClipPlane; CLIP_PLANES],
}

impl Frustum {
    /// The near plane and the four window planes of `view`.
    pub fn new(view: &LocalView) -> Frustum {
        let (w, h) = (view.width as f32, view.height as f32);
        let plane = |x: f32, y: f32, z: f32, offset: f32| ClipPlane {
            normal: Vec3::new(x, y, z),
            offset,
        };
        Frustum {
            planes: [
                plane(0.0, 0.0, 1.0, -view.near),       // zc >= near
                plane(view.fx, 0.0, view.cx, 0.0),      // sx >= 0
                plane(-view.fx, 0.0, w - view.cx, 0.0), // sx <= W
                plane(0.0, -view.fy, view.cy, 0.0),     // sy >= 0
                plane(0.0, view.fy, h - view.cy, 0.0),  // sy <= H
            ],
        }
    }

    /// All planes, near first.
    pub fn planes(&self) -> &[ClipPlane; CLIP_PLANES] {
        &self.planes
    }

    /// The near plane alone.
    pub fn near(&self) -> &ClipPlane {
        &self.planes[0]
    }

    /// The four window planes (only meaningful for points with `zc > 0`).
    pub fn window(&self) -> &[ClipPlane] {
        &self.planes[1..]
    }

    /// Whether every point of the box `[lo, hi]` (in the view's scene frame) passes every
    /// plane in [`clip_polygon`]'s own `f32` test, so that clipping its polygons changes
    /// nothing and can be skipped.
    ///
    /// Why a margin makes this exact: `to_camera` then `eval` is affine, so over the box its
    /// exact value is at least its smallest value at a corner. Each `f32` evaluation (a
    /// subtraction, three-term dot products) is within `8 * 2^-24 * S` of the exact value,
    /// with `S = |n|_1 * 3 * |p - eye|_1 + |offset|` bounding the magnitudes involved (each
    /// row of the rotation has length 1). Asking every corner for `2 * 2^-16 * S`, far more
    /// than twice that error, leaves every point of the box at least `2^-16 * S` above zero
    /// in exact arithmetic, hence `>= 0` once evaluated in `f32`.
    pub fn contains_box(&self, view: &LocalView, lo: Vec3, hi: Vec3) -> bool {
        const MARGIN: f32 = 2.0 / 65_536.0;
        let finite = lo.is_finite() && hi.is_finite();
        finite
            && (0..8).all(|k| {
                let p = Vec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                );
                let c = view.to_camera(p);
                let reach = 3.0 * (p - view.eye).abs().element_sum();
                self.planes.iter().all(|plane| {
                    let scale = plane.normal.abs().element_sum() * reach + plane.offset.abs();
                    plane.eval(c) >= MARGIN * scale
                })
            })
    }

    /// Whether every point of `b` fails one plane in [`clip_polygon`]'s own `f32` test, so
    /// that clipping leaves nothing of any polygon inside the box.
    ///
    /// Why the margin makes this exact: over the exact camera-space box, `eval` is at most
    /// `eval(centre) + |normal|·extent`; the computed positions of the box's points (vertices
    /// and points clipped from them by earlier planes) are within `error` of it per axis
    /// ([`CameraBox`]), which moves `eval` by at most `|normal|₁ · error`; and `eval` itself
    /// rounds by a few units of `2^-24` of `|normal|₁ · |p|₁ + |offset|`. Asking for twice
    /// the first plus `2^-18` of the second leaves every such point below zero.
    pub fn excludes_box(&self, b: &CameraBox) -> bool {
        self.planes.iter().any(|plane| plane.excludes_box(b))
    }
}

/// Vertices a polygon of `vertex_count` vertices needs in each clip buffer.
pub const fn buffer_len_for(vertex_count: u32) -> u32 {
    vertex_count.saturating_add(CLIP_PLANES as u32)
}

/// Clip the convex polygon `input` against one plane into `out`; returns the vertex count
/// written. Fails (writing a prefix only) if `out` is shorter than `input.len() + 1` would
/// need.
pub fn clip_against(
    plane: &ClipPlane,
    input: &[Vec3],
    out: &mut [Vec3],
) -> Result<usize, RenderError> {
    let mut len = 0usize;
    let mut emit = |p: Vec3, len: &mut usize| -> Result<(), RenderError> {
        match out.get_mut(*len) {
            Some(slot) => {
                *slot = p;
                *len += 1;
                Ok(())
            }
            None => Err(RenderError::PolygonTooLarge {
                needed: (input.len() as u32).saturating_add(1),
                available: out.len() as u32,
            }),
        }
    };
    let Some(&last) = input.last() else {
        return Ok(0);
    };
    let mut prev = last;
    let mut d_prev = plane.eval(prev);
    for &cur in input {
        let d_cur = plane.eval(cur);
        let prev_in = d_prev >= 0.0;
        let cur_in = d_cur >= 0.0;
        if prev_in != cur_in {
            let p = if prev_in {
                intersect(prev, d_prev, cur, d_cur)
            } else {
                intersect(cur, d_cur, prev, d_prev)
            };
            emit(p, &mut len)?;
        }
        if cur_in {
            emit(cur, &mut len)?;
        }
        prev = cur;
        d_prev = d_cur;
    }
    Ok(len)
}

/// The point where segment `[inside, outside]` crosses the plane, computed from the inside
/// endpoint (`d_in >= 0 > d_out`, so the denominator is positive and `t` is in `[0, 1]`).
fn intersect(inside: Vec3, d_in: f32, outside: Vec3, d_out: f32) -> Vec3 {
    let t = d_in / (d_in - d_out);
    inside + (outside - inside) * t
}

/// A plane in camera space that a piece of a posed object is cut by (see [`crate::place`]):
/// its polygons keep the side where `plane.eval(p) >= 0` ([`Keep::Plus`]) or `<= 0`
/// ([`Keep::Minus`]), or keep both sides with a vertex where an edge crosses it
/// ([`Keep::Both`]): a plane that cuts another piece of the object, so that each piece has a
/// vertex wherever its neighbours have one and no crack opens between them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cut {
    /// The plane.
    pub plane: ClipPlane,
    /// What is kept.
    pub keep: Keep,
}

impl Cut {
    /// Whether the cut leaves nothing of the camera-space box `b`: every point of it on the
    /// side not kept, as [`ClipPlane::excludes_box`] proves it ([`Keep::Both`] keeps all).
    pub fn removes_box(&self, b: &CameraBox) -> bool {
        match self.keep {
            Keep::Plus => self.plane.excludes_box(b),
            Keep::Minus => ClipPlane {
                normal: -self.plane.normal,
                offset: -self.plane.offset,
            }
            .excludes_box(b),
            Keep::Both => false,
        }
    }
}

/// What a [`Cut`] keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Keep {
    /// The + side.
    Plus,
    /// The − side.
    Minus,
    /// Both, with the crossings as vertices.
    Both,
}

/// Sutherland–Hodgman against `cut`. The two pieces of an object on either side of one plane
/// get the same point on every edge it crosses, bit for bit: the plane's values are the same
/// for both, and the point is always computed from the edge's end on the + side.
pub fn cut_against(cut: &Cut, input: &[Vec3], out: &mut [Vec3]) -> Result<usize, RenderError> {
    let kept = |d: f32| match cut.keep {
        Keep::Plus => d >= 0.0,
        Keep::Minus => d <= 0.0,
        Keep::Both => true,
    };
    let too_large = RenderError::PolygonTooLarge {
        needed: (input.len() as u32).saturating_add(1),
        available: out.len() as u32,
    };
    let mut len = 0usize;
    let mut emit = |p: Vec3, len: &mut usize| -> Result<(), RenderError> {
        let slot = out.get_mut(*len).ok_or(too_large)?;
        *slot = p;
        *len += 1;
        Ok(())
    };
    let Some(&last) = input.last() else {
        return Ok(0);
    };
    let (mut prev, mut d_prev) = (last, cut.plane.eval(last));
    for &cur in input {
        let d_cur = cut.plane.eval(cur);
        if d_prev > 0.0 && d_cur < 0.0 {
            emit(intersect(prev, d_prev, cur, d_cur), &mut len)?;
        } else if d_prev < 0.0 && d_cur > 0.0 {
            emit(intersect(cur, d_cur, prev, d_prev), &mut len)?;
        }
        if kept(d_cur) {
            emit(cur, &mut len)?;
        }
        prev = cur;
        d_prev = d_cur;
    }
    Ok(len)
}

/// The polygon `a[..len]` cut by every one of `cuts`, then clipped by `planes` (see
/// [`clip_polygon`]).
pub fn cut_polygon<'b>(
    cuts: &[Cut],
    planes: &[ClipPlane],
    len: usize,
    a: &'b mut [Vec3],
    b: &'b mut [Vec3],
) -> Result<&'b [Vec3], RenderError> {
    let mut len = len.min(a.len());
    let (mut src, mut dst) = (a, b);
    for cut in cuts {
        if len == 0 {
            break;
        }
        let input = src.get(..len).unwrap_or(&[]);
        len = cut_against(cut, input, dst)?;
        core::mem::swap(&mut src, &mut dst);
    }
    clip_polygon(planes, len, src, dst)
}

/// Clip the convex polygon held in `a[..len]` against every plane of `planes`, ping-ponging
/// between `a` and `b`; returns the clipped polygon (a slice of one of them, possibly with
/// fewer than 3 vertices when nothing is left). (A renderer that knows the whole scene is
/// inside, by [`Frustum::contains_box`], skips clipping altogether.)
pub fn clip_polygon<'b>(
    planes: &[ClipPlane],
    len: usize,
    a: &'b mut [Vec3],
    b: &'b mut [Vec3],
) -> Result<&'b [Vec3], RenderError> {
    let mut len = len.min(a.len());
    let (mut src, mut dst) = (a, b);
    for plane in planes {
        if len == 0 {
            break;
        }
        let input = src.get(..len).unwrap_or(&[]);
        len = clip_against(plane, input, dst)?;
        core::mem::swap(&mut src, &mut dst);
    }
    let src: &'b [Vec3] = src;
    Ok(src.get(..len).unwrap_or(&[]))
}

#[cfg(test)]
mod tests;
