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

use crate::camera::{CameraBox, View};
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
    pub fn new(view: &View) -> Frustum {
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
    pub fn contains_box(&self, view: &View, lo: Vec3, hi: Vec3) -> bool {
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
        const ROUNDING: f32 = 1.0 / 262_144.0;
        let size = b.centre.abs() + b.extent + Vec3::splat(b.error);
        self.planes.iter().any(|plane| {
            let n = plane.normal.abs();
            let scale = n.element_sum();
            let margin = 2.0 * scale * b.error
                + ROUNDING * (n.dot(size) + scale * b.error + plane.offset.abs());
            plane.eval(b.centre) + n.dot(b.extent) + margin < 0.0
        })
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
mod tests {
    extern crate std;

    use super::*;
    use crate::camera::{Camera, Pose};
    use glam::DVec3;
    use proptest::prelude::*;
    use std::vec::Vec;

    /// Camera at the origin looking down -z, 100 x 100, fov 90 (fx = fy = 50), near 1.
    fn view() -> View {
        Camera::look_at(
            Pose::new(DVec3::ZERO, DVec3::new(0.0, 0.0, -1.0)),
            90.0,
            100,
            100,
            1.0,
        )
        .unwrap()
        .view([0.0; 3])
    }

    fn clip(planes: &[ClipPlane], poly: &[Vec3]) -> Vec<Vec3> {
        let mut a = [Vec3::ZERO; 16];
        let mut b = [Vec3::ZERO; 16];
        a[..poly.len()].copy_from_slice(poly);
        clip_polygon(planes, poly.len(), &mut a, &mut b)
            .unwrap()
            .to_vec()
    }

    /// A camera-space point (x right, y up, z forward) of the view above.
    fn c(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3::new(x, y, z)
    }

    #[test]
    fn fully_behind_the_near_plane_is_empty() {
        let f = Frustum::new(&view());
        let tri = [c(0.0, 0.0, 0.5), c(1.0, 0.0, -3.0), c(0.0, 1.0, 0.9)];
        assert!(clip(&[*f.near()], &tri).is_empty());
        assert!(clip(f.planes(), &tri).is_empty());
    }

    #[test]
    fn crossing_the_near_plane_is_cut_at_near() {
        let f = Frustum::new(&view());
        // One vertex in front (z = 3), two behind (z = -1): a triangle with two new points.
        let tri = [c(0.0, 0.0, 3.0), c(1.0, 0.0, -1.0), c(-1.0, 0.0, -1.0)];
        let out = clip(&[*f.near()], &tri);
        assert_eq!(out.len(), 3);
        assert!(out.iter().all(|p| p.z >= 1.0 - 1e-6));
        // Edge (0,0,3)-(1,0,-1) reaches z = 1 at half way: x = 0.5.
        assert!(out
            .iter()
            .any(|p| (p.x - 0.5).abs() < 1e-6 && (p.z - 1.0).abs() < 1e-6));
        assert!(out
            .iter()
            .any(|p| (p.x + 0.5).abs() < 1e-6 && (p.z - 1.0).abs() < 1e-6));
        // Two vertices in front: a quadrilateral.
        let tri = [c(0.0, 0.0, -1.0), c(1.0, 0.0, 3.0), c(-1.0, 0.0, 3.0)];
        assert_eq!(clip(&[*f.near()], &tri).len(), 4);
    }

    #[test]
    fn touching_the_near_plane() {
        let f = Frustum::new(&view());
        // In front, one vertex exactly on the plane: unchanged.
        let tri = [c(0.0, 0.0, 1.0), c(1.0, 0.0, 4.0), c(-1.0, 0.0, 4.0)];
        assert_eq!(clip(&[*f.near()], &tri), tri.to_vec());
        // Behind, one vertex exactly on the plane: only that point survives (nothing to draw).
        let tri = [c(0.0, 0.0, 1.0), c(1.0, 0.0, -4.0), c(-1.0, 0.0, -4.0)];
        let out = clip(&[*f.near()], &tri);
        assert!(out.len() < 3 || out.iter().all(|p| *p == c(0.0, 0.0, 1.0)));
    }

    fn screen(v: &View, poly: &[Vec3]) -> Vec<glam::Vec2> {
        poly.iter().map(|&p| v.project(p)).collect()
    }

    #[test]
    fn inside_the_window_is_unchanged() {
        let v = view();
        let f = Frustum::new(&v);
        // At z = 10 the window spans |x|, |y| <= 10.
        let tri = [c(-2.0, -2.0, 10.0), c(3.0, -1.0, 10.0), c(0.0, 4.0, 10.0)];
        assert_eq!(clip(f.planes(), &tri), tri.to_vec());
    }

    #[test]
    fn outside_the_window_is_empty() {
        let f = Frustum::new(&view());
        let right = [c(11.0, 0.0, 10.0), c(20.0, 1.0, 10.0), c(15.0, 5.0, 10.0)];
        assert!(clip(f.planes(), &right).is_empty());
        let above = [c(0.0, 11.0, 10.0), c(1.0, 20.0, 10.0), c(-3.0, 15.0, 10.0)];
        assert!(clip(f.planes(), &above).is_empty());
        // Outside the window across a corner without touching it (x + y > 25 at z = 10).
        let corner = [c(12.0, 14.0, 10.0), c(30.0, 0.0, 10.0), c(0.0, 30.0, 10.0)];
        assert!(clip(f.planes(), &corner).is_empty());
    }

    #[test]
    fn larger_than_the_screen_becomes_the_screen() {
        let v = view();
        let f = Frustum::new(&v);
        let big = [
            c(-1e4, -1e4, 10.0),
            c(1e4, -1e4, 10.0),
            c(1e4, 1e4, 10.0),
            c(-1e4, 1e4, 10.0),
        ];
        let out = screen(&v, &clip(f.planes(), &big));
        assert_eq!(out.len(), 4);
        for corner in [(0.0, 0.0), (100.0, 0.0), (100.0, 100.0), (0.0, 100.0)] {
            assert!(
                out.iter()
                    .any(|p| (p.x - corner.0).abs() < 1e-3 && (p.y - corner.1).abs() < 1e-3),
                "{corner:?} missing from {out:?}"
            );
        }
    }

    #[test]
    fn window_corner_cases() {
        let v = view();
        let f = Frustum::new(&v);
        // A triangle poking out of the top-left corner: the corner (0, 0) becomes a vertex.
        let tri = [c(-20.0, 5.0, 10.0), c(-5.0, 20.0, 10.0), c(0.0, 0.0, 10.0)];
        let out = screen(&v, &clip(f.planes(), &tri));
        assert!(
            out.iter().any(|p| p.x.abs() < 1e-3 && p.y.abs() < 1e-3),
            "{out:?}"
        );
        assert!(out
            .iter()
            .all(|p| p.x >= -1e-3 && p.x <= 100.001 && p.y >= -1e-3 && p.y <= 100.001));
        // An edge lying exactly on the window edge x = 0 (x = -10 at z = 10) is kept.
        let tri = [c(-10.0, 0.0, 10.0), c(-10.0, 5.0, 10.0), c(0.0, 0.0, 10.0)];
        assert_eq!(clip(f.planes(), &tri).len(), 3);
        // Touching the window at a single corner point: degenerate, fewer than 3 distinct points.
        let tri = [
            c(10.0, 10.0, 10.0),
            c(20.0, 10.0, 10.0),
            c(10.0, 20.0, 10.0),
        ];
        let out = clip(f.planes(), &tri);
        assert!(out.iter().all(|p| *p == c(10.0, 10.0, 10.0)), "{out:?}");
    }

    #[test]
    fn too_small_buffers_are_a_typed_error() {
        let f = Frustum::new(&view());
        // A diamond with a corner cut off by the window edge x = 0 (camera x = -10 at z = 10)
        // grows to 5 vertices: 4-vertex buffers cannot hold it.
        let sq = [
            c(-12.0, 0.0, 10.0),
            c(-8.0, -4.0, 10.0),
            c(-4.0, 0.0, 10.0),
            c(-8.0, 4.0, 10.0),
        ];
        let mut a = [Vec3::ZERO; 4];
        let mut b = [Vec3::ZERO; 4];
        a.copy_from_slice(&sq);
        let r = clip_polygon(f.planes(), 4, &mut a, &mut b);
        assert!(
            matches!(r, Err(RenderError::PolygonTooLarge { .. })),
            "{r:?}"
        );
    }

    /// The bit patterns of a clipped polygon's points.
    fn bits(out: &[Vec3]) -> Vec<[u32; 3]> {
        out.iter().map(|x| x.to_array().map(f32::to_bits)).collect()
    }

    fn coord() -> impl Strategy<Value = f32> {
        -30.0f32..30.0
    }

    fn point() -> impl Strategy<Value = Vec3> {
        (coord(), coord(), -5.0f32..30.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    proptest! {
        /// Two triangles sharing the edge `p q` (walked in opposite directions, as in a mesh)
        /// produce bit-identical clipped points along it.
        #[test]
        fn shared_edge_points_are_bit_identical(p in point(), q in point(), r in point(), s in point()) {
            let f = Frustum::new(&view());
            let one = clip(f.planes(), &[p, q, r]);
            let two = clip(f.planes(), &[q, p, s]);
            let (e1, e2) = (bits(&one), bits(&two));
            // Clip the bare segment in both directions: same end points, bit for bit, and
            // both clipped triangles hold exactly those points.
            let seg_a = clip_segment(&f, p, q);
            let seg_b = clip_segment(&f, q, p);
            match (seg_a, seg_b) {
                (Some((a0, a1)), Some((b0, b1))) => {
                    prop_assert_eq!(a0.to_array().map(f32::to_bits), b1.to_array().map(f32::to_bits));
                    prop_assert_eq!(a1.to_array().map(f32::to_bits), b0.to_array().map(f32::to_bits));
                    // And both clipped triangles contain those exact end points.
                    for x in [a0, a1] {
                        let b = x.to_array().map(f32::to_bits);
                        prop_assert!(e1.contains(&b), "{:?} not in first {:?}", x, one);
                        prop_assert!(e2.contains(&b), "{:?} not in second {:?}", x, two);
                    }
                }
                (None, None) => {}
                (a, b) => prop_assert!(false, "segment clipped differently: {:?} {:?}", a, b),
            }
        }
    }

    /// Points anywhere, or inside the frustum of [`view`] (so whole polygons often are).
    fn any_point() -> impl Strategy<Value = Vec3> {
        let inside = (-0.99f32..0.99, -0.99f32..0.99, 1.0f32..30.0)
            .prop_map(|(u, v, z)| Vec3::new(u * z, v * z, z));
        prop_oneof![point(), inside]
    }

    proptest! {
        /// Clipping by the whole frustum (ping-ponging between two buffers) returns what
        /// clipping plane by plane returns, bit for bit, for polygons inside, across and out.
        #[test]
        fn clip_polygon_equals_plane_by_plane(
            p in any_point(), q in any_point(), r in any_point(), s in any_point()
        ) {
            let f = Frustum::new(&view());
            let poly = [p, q, r, s];
            let mut expected: Vec<Vec3> = poly.to_vec();
            for plane in f.planes() {
                let mut out = [Vec3::ZERO; 16];
                let n = clip_against(plane, &expected, &mut out).expect("room");
                expected = out[..n].to_vec();
            }
            prop_assert_eq!(bits(&clip(f.planes(), &poly)), bits(&expected));
        }
    }

    proptest! {
        /// A box the frustum contains holds no point that the clipper's own test would cut.
        #[test]
        fn contained_boxes_need_no_clipping(
            c in (-3.0f32..3.0, -3.0f32..3.0, -30.0f32..-1.0),
            half in (0.01f32..4.0, 0.01f32..4.0, 0.01f32..4.0),
            t in proptest::collection::vec((0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0), 64),
        ) {
            let v = view();
            let f = Frustum::new(&v);
            let (c, h) = (Vec3::new(c.0, c.1, c.2), Vec3::new(half.0, half.1, half.2));
            let (lo, hi) = (c - h, c + h);
            if f.contains_box(&v, lo, hi) {
                for (a, b, z) in t {
                    let p = lo + (hi - lo) * Vec3::new(a, b, z);
                    let p = p.clamp(lo, hi);
                    let cam = v.to_camera(p);
                    for plane in f.planes() {
                        prop_assert!(plane.eval(cam) >= 0.0, "{:?} at {:?}", plane, p);
                    }
                }
            }
        }
    }

    #[test]
    fn contains_box_cases() {
        let v = view();
        let f = Frustum::new(&v);
        // Well inside: 10 in front, 1 wide (the window spans +-10 at that depth).
        assert!(f.contains_box(&v, Vec3::new(-0.5, -0.5, -10.5), Vec3::new(0.5, 0.5, -9.5)));
        // Crossing the near plane, the window's edge, or behind the eye: no.
        assert!(!f.contains_box(&v, Vec3::new(-0.5, -0.5, -10.0), Vec3::new(0.5, 0.5, -0.5)));
        assert!(!f.contains_box(&v, Vec3::new(9.0, -0.5, -10.5), Vec3::new(11.0, 0.5, -9.5)));
        assert!(!f.contains_box(&v, Vec3::new(-0.5, -0.5, 1.0), Vec3::new(0.5, 0.5, 2.0)));
        // Touching the window's edge exactly: the margin says no.
        assert!(!f.contains_box(&v, Vec3::new(0.0, -0.5, -10.0), Vec3::new(10.0, 0.5, -10.0)));
        assert!(!f.contains_box(&v, Vec3::splat(f32::NAN), Vec3::ONE));
    }

    /// Clip the segment `p -> q` by every plane with the same intersection rule.
    fn clip_segment(f: &Frustum, mut p: Vec3, mut q: Vec3) -> Option<(Vec3, Vec3)> {
        for plane in f.planes() {
            let (dp, dq) = (plane.eval(p), plane.eval(q));
            match (dp >= 0.0, dq >= 0.0) {
                (true, true) => {}
                (false, false) => return None,
                (true, false) => q = intersect(p, dp, q, dq),
                (false, true) => p = intersect(q, dq, p, dp),
            }
        }
        Some((p, q))
    }
}
