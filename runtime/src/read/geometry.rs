//! Geometry: planes, and the points the file stores decoded (vertices and node boxes: 16-bit
//! steps on the header's bounds, or `f32` as stored).

use glam::Vec3;

use super::layout::{self, element, Record, BOUNDS_SIZE, PLANE_SIZE};
use super::{readable, Scene};

/// A plane `normal · p = d` (relative to the scene centre). Only the sign of
/// [`Plane::distance`] is used (which side of the plane the eye is on), so the normal need not
/// be of unit length.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Plane {
    /// Normal (of unit length for a split node's plane).
    pub normal: Vec3,
    /// Offset.
    pub d: f32,
}

impl Plane {
    /// The plane through `a`, `b`, `c`, its normal `(b - a) x (c - a)` (zero when they are
    /// collinear: then every point is on it).
    #[inline]
    pub fn through(a: Vec3, b: Vec3, c: Vec3) -> Plane {
        let normal = (b - a).cross(c - a);
        Plane {
            normal,
            d: normal.dot(a),
        }
    }

    /// Signed distance of `p` (positive on the + side).
    pub fn distance(&self, p: Vec3) -> f32 {
        self.normal.dot(p) - self.d
    }
}

impl Scene<'_> {
    /// The steps of vertex `v` of a file with 16-bit vertices, with one bounds check.
    #[inline]
    pub(super) fn steps_of(&self, v: u32) -> Option<[u16; 3]> {
        if !readable(v, self.header.vertex_count) {
            return None;
        }
        let at = v as usize * 6;
        let r: &[u8; 6] = self.steps16.get(at..at + 6)?.try_into().ok()?;
        Some([
            u16::from_le_bytes([r[0], r[1]]),
            u16::from_le_bytes([r[2], r[3]]),
            u16::from_le_bytes([r[4], r[5]]),
        ])
    }

    /// The quantised box at `at`, decoded on the header's bounds: [`layout::dequantise`]
    /// lane by lane (the same operations in the same order, so the same bits), without its
    /// branches.
    pub(super) fn box_at(&self, at: usize) -> (Vec3, Vec3) {
        let lo = self.header.bounds_min;
        let Some(r) = Record::<BOUNDS_SIZE>::at(self.bytes, at) else {
            return (lo, lo);
        };
        (self.decode(&r, 0), self.decode(&r, 6))
    }

    /// The point of three `u16` steps at byte `first` of `r` on the header's bounds:
    /// [`layout::dequantise`] lane by lane (the same operations, so the same bits). Vertices
    /// and boxes decode alike, so a box of steps contains the vertices whose steps it contains.
    #[inline]
    fn decode<const N: usize>(&self, r: &Record<N>, first: usize) -> Vec3 {
        self.point([r.u16(first), r.u16(first + 2), r.u16(first + 4)])
    }

    /// The point of steps `q` ([`Scene::decode`]).
    #[inline]
    fn point(&self, q: [u16; 3]) -> Vec3 {
        #[cfg(all(target_arch = "arm", not(target_has_atomic = "32")))]
        if let Some([x, y, z]) = self.grid {
            return Vec3::new(x.value(q[0]), y.value(q[1]), z.value(q[2]));
        }
        let q = Vec3::new(f32::from(q[0]), f32::from(q[1]), f32::from(q[2]));
        self.header.bounds_min + q * self.step
    }

    /// `(min, step)` of the vertices' 16-bit steps when the bounds are an exact grid on every
    /// axis ([`layout::Grid`]): vertex `v` is then exactly `min + q ∘ step` for its steps `q`
    /// ([`Scene::vertex_steps`]). `None` for `f32` vertices.
    pub fn step_grid(&self) -> Option<(Vec3, Vec3)> {
        let (lo, hi) = (self.header.bounds_min, self.header.bounds_max);
        let exact = (0..3).all(|j| layout::Grid::of(lo[j], hi[j]).is_some());
        (self.vertex_size() == 6 && exact).then_some((lo, self.step))
    }

    /// The 16-bit steps of vertex `v` (`None` for `f32` vertices or out of range).
    #[inline]
    pub fn vertex_steps(&self, v: u32) -> Option<[u16; 3]> {
        if self.vertex_size() != 6 {
            return None;
        }
        self.steps_of(v)
    }

    /// Vertex `i`, relative to the centre (zero when out of range).
    #[inline]
    pub fn vertex(&self, i: u32) -> Vec3 {
        if self.vertex_size() == 6 {
            return self.steps_of(i).map_or(Vec3::ZERO, |q| self.point(q));
        }
        // `f32` vertices (or none at all).
        if i >= self.header.vertex_count {
            return Vec3::ZERO;
        }
        element(self.vertices, self.vertex_size(), i).map_or(Vec3::ZERO, |at| self.vec3_at(at))
    }

    /// Plane `i` (all zero when out of range).
    pub fn plane(&self, i: u32) -> Plane {
        if i >= self.header.plane_count {
            return Plane::default();
        }
        element(self.planes, PLANE_SIZE, i)
            .and_then(|at| Record::<PLANE_SIZE>::at(self.bytes, at))
            .map_or(Plane::default(), |r| Plane {
                normal: Vec3::new(r.f32(0), r.f32(4), r.f32(8)),
                d: r.f32(12),
            })
    }

    fn vec3_at(&self, at: usize) -> Vec3 {
        Record::<12>::at(self.bytes, at)
            .map_or(Vec3::ZERO, |r| Vec3::new(r.f32(0), r.f32(4), r.f32(8)))
    }
}
