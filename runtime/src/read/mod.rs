//! Read: a `.peel` file read in place from `&[u8]`, validated up front.
//!
//! After [`Scene::parse`] succeeded, every accessor is total (it never panics; an
//! out-of-range argument gives a default), so a corrupt file can never crash a frame.
//! The byte layout is specified in `formats/peel.md`; [`layout`] holds its constants.

pub mod layout;
mod validate;

use core::fmt;

use glam::Vec3;

use crate::display::Colour;
use crate::error::ReadError;
use layout::{
    element, header_flags, node_kind, u16_at, u32_at, u8_at, Record, BOUNDS_SIZE, ID_SIZE, NONE,
    PALETTE_SIZE, PLANE_SIZE,
};

/// The header, decoded. Its [`Default`] is all zero: with only `centre` and the bounds set, a
/// header frames a scene for the camera ([`crate::camera::Orbit::pose`],
/// [`crate::camera::Camera::default_near`]), which reads nothing else.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Header {
    /// Format version.
    pub version: u16,
    /// Header flags ([`layout::header_flags`]).
    pub flags: u16,
    /// Number of vertices.
    pub vertex_count: u32,
    /// Number of planes.
    pub plane_count: u32,
    /// Number of vertex indices.
    pub index_count: u32,
    /// Number of polygons.
    pub polygon_count: u32,
    /// Number of nodes.
    pub node_count: u32,
    /// Nodes on the longest root-to-leaf path.
    pub max_depth: u32,
    /// Largest polygon vertex count.
    pub max_polygon_vertices: u32,
    /// World position all coordinates are relative to.
    pub centre: [f64; 3],
    /// Scene bounds relative to `centre`.
    pub bounds_min: Vec3,
    /// Scene bounds relative to `centre`.
    pub bounds_max: Vec3,
    /// Number of palette colours (0 without [`header_flags::PALETTE`]).
    pub palette_count: u32,
    /// Number of node bounding boxes (0 without [`header_flags::BOUNDS`]).
    pub bounds_count: u32,
}

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

/// A polygon record. Its support plane is the plane through its first three vertices
/// ([`Scene::eye_side`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Polygon {
    /// First entry in the index array.
    pub first_index: u32,
    /// Number of vertices.
    pub vertex_count: u16,
    /// Polygon flags ([`layout::polygon_flags`]).
    pub flags: u8,
    /// Baked colour: of both sides, or with [`layout::header_flags::TWO_COLOURS`] of the
    /// interior side ([`Scene::colour_seen`]).
    pub colour: Colour,
}

/// A node record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Node {
    /// Convex set `first .. first + count`, then `child`.
    Convex {
        /// First polygon.
        first: u32,
        /// Number of polygons.
        count: u32,
        /// The node inside the set.
        child: Option<u32>,
    },
    /// Separating plane.
    Split {
        /// Plane index.
        plane: u32,
        /// Child on the + side.
        front: Option<u32>,
        /// Child on the - side.
        back: Option<u32>,
    },
}

impl Node {
    /// What [`Scene::node`] answers for an index out of range: an empty leaf, which draws nothing.
    pub const EMPTY: Node = Node::Convex {
        first: 0,
        count: 0,
        child: None,
    };
}

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
fn mul_wide_halves(a: i32, b: i32) -> i64 {
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

/// Whether record `i` of an array of `count` small records (16-bit steps or indices) can be
/// read at offset `i * size` with no overflow check, the slice's bounds check doing the rest:
/// below the count, or in a build without `large-scenes`, whose counts stay below 65,537,
/// below 2^24 (a compare with a constant).
#[inline]
fn readable(i: u32, count: u32) -> bool {
    i < if cfg!(feature = "large-scenes") {
        count
    } else {
        1 << 24
    }
}

/// A child or parent field: [`layout::NONE`] means "none".
fn link(value: u32) -> Option<u32> {
    (value != NONE).then_some(value)
}

/// A validated `.peel` file borrowed from its bytes.
#[derive(Clone, Copy)]
pub struct Scene<'a> {
    bytes: &'a [u8],
    header: Header,
    /// Byte offsets of the first record of each array (just after its length).
    vertices: usize,
    planes: usize,
    indices: usize,
    polygons: usize,
    ids: usize,
    palette: usize,
    bounds: usize,
    nodes: usize,
    /// The size of a step on each axis ([`layout::step`]).
    step: Vec3,
    /// Steps per unit of length on each axis ([`layout::per_step`]): brings the eye to steps.
    per_step: Vec3,
    /// The bounds as integers when they are an exact grid ([`layout::Grid`]), which ARMv6-M
    /// decodes with (the only core that has the field).
    #[cfg(all(target_arch = "arm", not(target_has_atomic = "32")))]
    grid: Option<[layout::Grid; 3]>,
    /// Record sizes, which the header flags choose.
    vertex_size: usize,
    index_size: usize,
    polygon_size: usize,
    node_size: usize,
    /// Bytes of a node field and a polygon's `plane` / `first_index` (2 or 4).
    field_size: usize,
    /// Where a polygon record's exterior colour field starts: its second colour field with
    /// [`header_flags::TWO_COLOURS`], else its one colour field.
    exterior: usize,
    /// The vertex array when its records are 16-bit steps and the index array when its
    /// entries are `u16` (else empty): the side test's fast path reads them with one bounds
    /// check per record.
    steps16: &'a [u8],
    indices16: &'a [u8],
}

impl fmt::Debug for Scene<'_> {
    /// The header and the size, not the (possibly megabytes of) bytes.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Scene")
            .field("bytes", &self.bytes.len())
            .field("header", &self.header)
            .finish()
    }
}

impl<'a> Scene<'a> {
    /// Check everything up front (magic, version, flags, sizes, finite floats, every index in
    /// range, the node tree, depth <= header depth); see `formats/peel.md`, "Validation".
    /// Runs in time linear in the file size and allocates nothing.
    pub fn parse(bytes: &'a [u8]) -> Result<Scene<'a>, ReadError> {
        validate::parse(bytes)
    }

    /// [`Scene::parse`] without the record checks, for bytes that [`Scene::parse`] already
    /// accepted elsewhere: typically a file embedded in firmware with `include_bytes!` and
    /// validated by the firmware's build script (what `runtime/embedded-example` does), where
    /// the linear-time checks would only repeat the build's verdict at every boot and cost
    /// flash. Checks the header (magic, version, flags) and that every array lies inside
    /// `bytes` and the file ends with the last one, in constant time.
    ///
    /// On a file that [`Scene::parse`] would refuse, nothing unsafe happens: every accessor is
    /// total, the traversal stops with a [`crate::RenderError`] on a malformed tree and walks no
    /// polygon range beyond the polygon array, so a frame never panics and always ends, but it
    /// may draw a wrong image or stop part way with an error. Anything read at run time (a
    /// file from storage or a radio) belongs to [`Scene::parse`].
    pub fn parse_trusted(bytes: &'a [u8]) -> Result<Scene<'a>, ReadError> {
        validate::parse_layout(bytes)
    }

    /// Bytes of a node field and a polygon's `first_index`: 2 in a build without
    /// `large-scenes`, which refuses other files (a constant, so the other widths' code goes).
    #[inline]
    fn field_size(&self) -> usize {
        if cfg!(feature = "large-scenes") {
            self.field_size
        } else {
            2
        }
    }

    /// Bytes of an index: 2 in a build without `large-scenes`.
    #[inline]
    fn index_size(&self) -> usize {
        if cfg!(feature = "large-scenes") {
            self.index_size
        } else {
            2
        }
    }

    /// Bytes of a vertex: 6 in a build without `wide-vertices`.
    #[inline]
    fn vertex_size(&self) -> usize {
        if cfg!(feature = "wide-vertices") {
            self.vertex_size
        } else {
            6
        }
    }

    /// The header.
    pub fn header(&self) -> Header {
        self.header
    }

    /// The bytes the scene was parsed from.
    pub fn bytes(&self) -> &'a [u8] {
        self.bytes
    }

    /// Root node, if the tree is not empty.
    pub fn root(&self) -> Option<u32> {
        (self.header.node_count > 0).then_some(0)
    }

    /// Node `i` ([`Node::EMPTY`] when out of range).
    #[inline]
    pub fn node(&self, i: u32) -> Node {
        match self.raw_node(i) {
            Some(raw) if i < self.header.node_count => raw.node(),
            _ => Node::EMPTY,
        }
    }

    /// Parent of node `i` (`None` for the root and out of range).
    pub fn parent(&self, i: u32) -> Option<u32> {
        if i >= self.header.node_count {
            return None;
        }
        self.raw_node(i).and_then(|raw| link(raw.parent))
    }

    /// Polygon `i` (all zero when out of range).
    #[inline]
    pub fn polygon(&self, i: u32) -> Polygon {
        let polygon = self.polygon_shape(i);
        Polygon {
            colour: self.colour_seen(i, true),
            ..polygon
        }
    }

    /// Polygon `i` without its colour (left at its default): what the traversal needs, which
    /// leaves the colour to [`Scene::colour_seen`] for the polygons drawn.
    #[inline]
    pub fn polygon_shape(&self, i: u32) -> Polygon {
        if i >= self.header.polygon_count {
            return Polygon::default();
        }
        let Some(at) = element(self.polygons, self.polygon_size, i) else {
            return Polygon::default();
        };
        // One bounds check per record, fields at constant offsets.
        let w = self.field_size();
        let fields = if w == 2 {
            Record::<4>::at(self.bytes, at).map(|r| (r.narrow(0, false), r.u8(2), r.u8(3)))
        } else if w == 3 {
            Record::<5>::at(self.bytes, at).map(|r| (r.medium(0, false), r.u8(3), r.u8(4)))
        } else {
            Record::<6>::at(self.bytes, at).map(|r| (r.u32(0), r.u8(4), r.u8(5)))
        };
        let Some((first_index, vertex_count, flags)) = fields else {
            return Polygon::default();
        };
        Polygon {
            first_index,
            vertex_count: u16::from(vertex_count),
            flags,
            colour: Colour::default(),
        }
    }

    /// The colour polygon `i` shows an eye on its interior side (`interior`, as the
    /// traversal yields it) or on its exterior side: the record's colour field, or with
    /// [`header_flags::TWO_COLOURS`] its second one for the exterior side (black when out of
    /// range).
    #[inline]
    pub fn colour_seen(&self, i: u32, interior: bool) -> Colour {
        if i >= self.header.polygon_count {
            return Colour::default();
        }
        let field = if interior {
            self.field_size() + 2
        } else {
            self.exterior
        };
        // Within the polygon array (checked by the parse): no overflow.
        self.colour_at(self.polygons + i as usize * self.polygon_size + field)
    }

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

    /// The steps of vertex `v` of a file with 16-bit vertices, with one bounds check.
    #[inline]
    fn steps_of(&self, v: u32) -> Option<[u16; 3]> {
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

    /// [`Scene::eye_side`] with `f32` vertices.
    #[inline(never)]
    fn wide_side(&self, polygon: &Polygon, eye: &SideEye) -> Side {
        let v = |i| self.polygon_vertex(polygon, i);
        float_side(v(0), v(1), v(2), eye.at)
    }

    /// The colour field at `at`: RGB, or a palette index (see [`layout::polygon_size`]).
    #[inline(never)]
    fn colour_at(&self, at: usize) -> Colour {
        let b = self.bytes;
        let flags = self.header.flags;
        // One bounds check for the three bytes.
        let rgb = |at: usize| match b.get(at..at.wrapping_add(3)) {
            Some(&[r, g, b]) => Colour::new(r, g, b),
            _ => Colour::default(),
        };
        if flags & header_flags::PALETTE == 0 {
            return rgb(at);
        }
        let index = if flags & header_flags::PALETTE16 != 0 {
            u16_at(b, at).map(u32::from)
        } else {
            u8_at(b, at).map(u32::from)
        };
        match index {
            // Below 2^16 entries inside the file (checked by the parse): no overflow.
            Some(k) if k < self.header.palette_count => {
                rgb(self.palette + k as usize * PALETTE_SIZE)
            }
            _ => Colour::default(),
        }
    }

    /// Entry `i` of the index array (`u16`, `u24` or `u32` as the header says), if in range.
    #[inline]
    fn index(&self, i: u32) -> Option<u32> {
        if self.index_size() == 2 {
            if !readable(i, self.header.index_count) {
                return None;
            }
            let at = i as usize * 2;
            let entry: &[u8; 2] = self.indices16.get(at..at + 2)?.try_into().ok()?;
            return Some(u32::from(u16::from_le_bytes(*entry)));
        }
        if i >= self.header.index_count {
            return None;
        }
        let at = element(self.indices, self.index_size(), i)?;
        match self.index_size() {
            2 => u16_at(self.bytes, at).map(u32::from),
            3 => layout::field_at(self.bytes, at, 3, false),
            _ => u32_at(self.bytes, at),
        }
    }

    /// Bounding box `(min, max)` of node `i`'s subtree, relative to the centre, if the file
    /// stores one for it.
    #[inline]
    pub fn node_bounds(&self, i: u32) -> Option<(Vec3, Vec3)> {
        if self.header.flags & header_flags::BOUNDS == 0 || i >= self.header.node_count {
            return None;
        }
        let w = self.field_size();
        let at = element(self.nodes, self.node_size, i)?.checked_add(1 + 3 * w)?;
        let k = match w {
            2 => Record::<2>::at(self.bytes, at)?.narrow(0, true),
            3 => Record::<3>::at(self.bytes, at)?.medium(0, true),
            _ => Record::<4>::at(self.bytes, at)?.u32(0),
        };
        let k = link(k)?;
        if k >= self.header.bounds_count {
            return None;
        }
        let at = element(self.bounds, BOUNDS_SIZE, k)?;
        Some(self.box_at(at))
    }

    /// The quantised box at `at`, decoded on the header's bounds: [`layout::dequantise`]
    /// lane by lane (the same operations in the same order, so the same bits), without its
    /// branches.
    fn box_at(&self, at: usize) -> (Vec3, Vec3) {
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

    /// Vertex `i` of polygon `polygon` (`i < vertex_count`), relative to the centre
    /// (zero when out of range).
    pub fn polygon_vertex(&self, polygon: &Polygon, i: u32) -> Vec3 {
        self.polygon_vertex_index(polygon, i)
            .map_or(Vec3::ZERO, |v| self.vertex(v))
    }

    /// The index in the vertex list of vertex `i` of `polygon` (`None` when out of range).
    #[inline]
    pub fn polygon_vertex_index(&self, polygon: &Polygon, i: u32) -> Option<u32> {
        if i >= u32::from(polygon.vertex_count) {
            return None;
        }
        polygon
            .first_index
            .checked_add(i)
            .and_then(|slot| self.index(slot))
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

    /// Source triangle id of polygon `i`, when the file has ids.
    pub fn id(&self, i: u32) -> Option<u32> {
        if self.header.flags & header_flags::IDS == 0 || i >= self.header.polygon_count {
            return None;
        }
        u32_at(self.bytes, element(self.ids, ID_SIZE, i)?)
    }

    fn vec3_at(&self, at: usize) -> Vec3 {
        Record::<12>::at(self.bytes, at)
            .map_or(Vec3::ZERO, |r| Vec3::new(r.f32(0), r.f32(4), r.f32(8)))
    }

    #[inline]
    fn raw_node(&self, i: u32) -> Option<RawNode> {
        RawNode::at(
            self.bytes,
            element(self.nodes, self.node_size, i)?,
            self.field_size(),
            i,
        )
    }
}

/// A node record as stored, before its kind is interpreted.
#[derive(Debug, Clone, Copy)]
struct RawNode {
    /// The kind, without [`node_kind::FIRST_CHILD`].
    kind: u8,
    a: u32,
    /// Convex: the child; split: the child on the + side (the implicit first child, the next
    /// node, when [`node_kind::FIRST_CHILD`] is set).
    b: u32,
    /// Convex: the polygon count; split: the child on the - side.
    c: u32,
    parent: u32,
}

impl RawNode {
    /// Node `i` at byte `at`: one bounds check per record, fields at constant offsets (`w`:
    /// the field width).
    #[inline]
    fn at(bytes: &[u8], at: usize, w: usize, i: u32) -> Option<RawNode> {
        let (byte, a, c, parent) = if w == 2 {
            let r = Record::<7>::at(bytes, at)?;
            let byte = r.u8(0);
            // A convex node's second field is a count, a split's a link.
            let convex = byte & !node_kind::FIRST_CHILD == node_kind::CONVEX;
            (
                byte,
                r.narrow(1, false),
                r.narrow(3, !convex),
                r.narrow(5, true),
            )
        } else if w == 3 {
            let r = Record::<10>::at(bytes, at)?;
            let byte = r.u8(0);
            let convex = byte & !node_kind::FIRST_CHILD == node_kind::CONVEX;
            (
                byte,
                r.medium(1, false),
                r.medium(4, !convex),
                r.medium(7, true),
            )
        } else {
            let r = Record::<13>::at(bytes, at)?;
            (r.u8(0), r.u32(1), r.u32(5), r.u32(9))
        };
        let b = if byte & node_kind::FIRST_CHILD != 0 {
            i.wrapping_add(1)
        } else {
            NONE
        };
        Some(RawNode {
            kind: byte & !node_kind::FIRST_CHILD,
            a,
            b,
            c,
            parent,
        })
    }

    /// The decoded node; an unknown kind (rejected by `parse`) reads as [`Node::EMPTY`].
    fn node(self) -> Node {
        match self.kind {
            node_kind::CONVEX => Node::Convex {
                first: self.a,
                count: self.c,
                child: link(self.b),
            },
            node_kind::SPLIT => Node::Split {
                plane: self.a,
                front: link(self.b),
                back: link(self.c),
            },
            _ => Node::EMPTY,
        }
    }

    /// Children in drawing-independent order: the convex child, or front then back.
    fn children(self) -> [Option<u32>; 2] {
        match self.node() {
            Node::Convex { child, .. } => [child, None],
            Node::Split { front, back, .. } => [front, back],
        }
    }
}

#[cfg(test)]
mod tests;
