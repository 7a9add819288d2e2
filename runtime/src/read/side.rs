//! Which side of a polygon's support plane the eye is on, the one question the traversal asks
//! of every polygon: exact in integers with 16-bit vertices (the common case, and all that a
//! core without an FPU can afford), else in `f32`.

use glam::Vec3;

use super::geometry::Plane;
use super::layout;
use super::polygon::Polygon;
use super::Scene;

/// Which side of a polygon's support plane the eye is on ([`Scene::eye_side`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// The side the plane's normal points to, which [`layout::polygon_flags::INTERIOR_FRONT`]
    /// refers to.
    Front,
    /// On the plane.
    On,
    /// The other side.
    Back,
}

impl Side {
    /// The side of a signed distance (NaN counts as [`Side::On`]).
    #[inline]
    pub fn of(distance: f32) -> Side {
        if distance > 0.0 {
            Side::Front
        } else if distance < 0.0 {
            Side::Back
        } else {
            Side::On
        }
    }
}

/// The eye as [`Scene::eye_side`] takes it, computed once per frame by [`Scene::side_eye`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SideEye {
    /// In the vertices' units: steps from `bounds_min` with 16-bit vertices, else the eye
    /// relative to the centre.
    pub at: Vec3,
    /// `at` in 1/[`SideEye::UNIT`] steps, truncated, when 16-bit vertices and every
    /// coordinate within [`SideEye::REACH`] steps: the integer side test's eye.
    pub fixed: Option<[i32; 3]>,
}

impl SideEye {
    /// Fixed-point units per step of [`SideEye::fixed`].
    pub const UNIT: i32 = 256;
    /// How far (in steps, 32 times a scene's extent) [`SideEye::fixed`] reaches: an eye offset
    /// stays below 2^30 units.
    pub const REACH: i32 = 1 << 21;

    /// An eye in the tree's own coordinates, for trees without 16-bit vertices.
    pub fn world(eye: Vec3) -> SideEye {
        SideEye {
            at: eye,
            fixed: None,
        }
    }
}

/// `a * b`, exact. ARMv6-M ([`layout::ARMV6M`]) has no long multiply, so the 64-bit product
/// would be a library call: there it is four 16-bit products instead ([`mul_wide_halves`]).
#[inline]
fn mul_wide(a: i32, b: i32) -> i64 {
    if layout::ARMV6M {
        mul_wide_halves(a, b)
    } else {
        i64::from(a) * i64::from(b)
    }
}

/// [`mul_wide`] from 16-bit halves of the magnitudes, each partial product exact in `u32`.
#[inline]
pub(super) fn mul_wide_halves(a: i32, b: i32) -> i64 {
    let (x, y) = (a.unsigned_abs(), b.unsigned_abs());
    let (xh, xl, yh, yl) = (x >> 16, x & 0xffff, y >> 16, y & 0xffff);
    let middle = u64::from(xh * yl) + u64::from(xl * yh);
    let magnitude = (u64::from(xh * yh) << 32) + (middle << 16) + u64::from(xl * yl);
    if (a < 0) != (b < 0) {
        (magnitude as i64).wrapping_neg()
    } else {
        magnitude as i64
    }
}

/// The side given by the sign of `(q - p) x (r - p) . (e / UNIT - p)`, for steps `p`,
/// `q`, `r` and an eye `e` in 1/[`SideEye::UNIT`] steps within [`SideEye::REACH`]; `None` unless
/// `q - p` and `r - p` lie within 2^15 per axis. Then every product is exact: the cross product's
/// below 2^30, its components below 2^31, the eye offsets below 2^30, each term below 2^61.
#[inline]
fn integer_sign(p: [i32; 3], q: [i32; 3], r: [i32; 3], e: [i32; 3]) -> Option<Side> {
    let a = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
    let b = [r[0] - p[0], r[1] - p[1], r[2] - p[2]];
    // Each of a and b in -2^15 ..< 2^15, tested at once.
    let spread = |c: i32| (c + (1 << 15)) as u32;
    let wide =
        (spread(a[0]) | spread(a[1]) | spread(a[2]) | spread(b[0]) | spread(b[1]) | spread(b[2]))
            >> 16;
    if wide != 0 {
        return None;
    }
    let n = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let unit = SideEye::UNIT;
    let d = [e[0] - p[0] * unit, e[1] - p[1] * unit, e[2] - p[2] * unit];
    let side = mul_wide(n[0], d[0]) + mul_wide(n[1], d[1]) + mul_wide(n[2], d[2]);
    Some(if side > 0 {
        Side::Front
    } else if side < 0 {
        Side::Back
    } else {
        Side::On
    })
}

/// [`float_side`] of the steps `p`, `q`, `r` (out of line: the rare case needs no room in the
/// walk).
#[inline(never)]
fn far_side(steps: [[i32; 3]; 3], at: Vec3) -> Side {
    let v = |s: [i32; 3]| Vec3::new(s[0] as f32, s[1] as f32, s[2] as f32);
    float_side(v(steps[0]), v(steps[1]), v(steps[2]), at)
}

/// The side of `at` of the plane through `a`, `b`, `c` ([`Plane::through`]), in `f32`: what
/// [`Scene::eye_side`] does with `f32` vertices, and with steps beyond [`integer_sign`]'s reach
/// (steps far apart, or the eye far away), where a wrong side by rounding puts the eye next to
/// the plane, which it then sees edge-on.
#[inline]
fn float_side(a: Vec3, b: Vec3, c: Vec3, at: Vec3) -> Side {
    Side::of(Plane::through(a, b, c).distance(at))
}

impl Scene<'_> {
    /// `eye` (relative to the centre) as [`Scene::eye_side`] takes it, once per frame: in
    /// steps from `bounds_min` with 16-bit vertices (a positive scale per axis, which keeps
    /// every side's sign), unchanged with `f32` vertices. A NaN coordinate, which the renderer
    /// refuses up front, counts as 0.
    #[inline]
    pub fn side_eye(&self, eye: Vec3) -> SideEye {
        if self.vertex_size() != 6 {
            return SideEye {
                at: eye,
                fixed: None,
            };
        }
        let at = (eye - self.header.bounds_min) * self.per_step;
        // Saturating conversions: beyond reach the test below fails. (A NaN coordinate, which
        // the renderer refuses up front, converts to 0.)
        let fixed = at * SideEye::UNIT as f32;
        let fixed = [fixed.x as i32, fixed.y as i32, fixed.z as i32];
        let limit = (SideEye::REACH * SideEye::UNIT) as u32;
        let within = fixed.iter().all(|c| c.unsigned_abs() < limit);
        SideEye {
            at,
            fixed: within.then_some(fixed),
        }
    }

    /// Which side of `polygon`'s support plane the eye (from [`Scene::side_eye`]) is on:
    /// [`Side::Front`] where `(v1 - v0) x (v2 - v0)` points to. The plane is the one through the
    /// polygon's first three vertices as read: the writer rotates each vertex list so that these
    /// three are far from collinear, and sets [`layout::polygon_flags::INTERIOR_FRONT`] for
    /// this normal.
    ///
    /// With 16-bit vertices no vertex is decoded. When the three are within 2^15 steps of each
    /// other and the eye within [`SideEye::REACH`], the test is integer, and exact: the cross
    /// product of the steps in `i32`, its dot product with the eye in 1/256 steps in `i64`
    /// (the common case, and what a core without an FPU can afford). Otherwise it is
    /// [`Plane::through`] the steps in `f32`; with `f32` vertices, through them.
    #[inline]
    pub fn eye_side(&self, polygon: &Polygon, eye: &SideEye) -> Side {
        if self.vertex_size() != 6 {
            return self.wide_side(polygon, eye);
        }
        self.steps_side(polygon, eye)
    }

    /// [`Scene::eye_side`] with 16-bit vertices.
    #[inline]
    fn steps_side(&self, polygon: &Polygon, eye: &SideEye) -> Side {
        let [p, q, r] = self.three_steps(polygon);
        match eye.fixed.and_then(|e| integer_sign(p, q, r, e)) {
            Some(side) => side,
            None => far_side([p, q, r], eye.at),
        }
    }

    /// The steps of `polygon`'s first three vertices (zero for one out of range). With `u16`
    /// indices the three are read with one bounds check.
    #[inline]
    fn three_steps(&self, polygon: &Polygon) -> [[i32; 3]; 3] {
        // A wrapped offset (only in a file that `parse` refuses) reads nothing.
        let at = (polygon.first_index as usize).wrapping_mul(2);
        let fast = self
            .indices16
            .get(at..at.wrapping_add(6))
            .and_then(|t| <&[u8; 6]>::try_from(t).ok())
            .filter(|_| polygon.vertex_count >= 3);
        let indices = match fast {
            Some(t) => [
                u32::from(u16::from_le_bytes([t[0], t[1]])),
                u32::from(u16::from_le_bytes([t[2], t[3]])),
                u32::from(u16::from_le_bytes([t[4], t[5]])),
            ],
            // Wider indices; without `large-scenes` only a polygon that validation refuses.
            None if cfg!(feature = "large-scenes") => self.slow_indices(polygon),
            None => [u32::MAX; 3],
        };
        let mut steps = [[0; 3]; 3];
        for (s, &v) in steps.iter_mut().zip(&indices) {
            if let Some(q) = self.steps_of(v) {
                *s = [i32::from(q[0]), i32::from(q[1]), i32::from(q[2])];
            }
        }
        steps
    }

    /// The indices of `polygon`'s first three vertices through [`Scene::polygon_vertex_index`]
    /// (`u32::MAX` for one out of range), out of line: wider indices are rare enough.
    #[inline(never)]
    fn slow_indices(&self, polygon: &Polygon) -> [u32; 3] {
        let mut indices = [u32::MAX; 3];
        for (i, slot) in (0..3).zip(&mut indices) {
            *slot = self.polygon_vertex_index(polygon, i).unwrap_or(u32::MAX);
        }
        indices
    }

    /// [`Scene::eye_side`] with `f32` vertices.
    #[inline(never)]
    fn wide_side(&self, polygon: &Polygon, eye: &SideEye) -> Side {
        let v = |i| self.polygon_vertex(polygon, i);
        float_side(v(0), v(1), v(2), eye.at)
    }
}
