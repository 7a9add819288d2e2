//! The byte layout of a `.peel` file (specified in `formats/peel.md`): the constants the
//! compiler's writer shares with this reader, and little-endian field access that never panics.

/// First four bytes of every `.peel` file.
pub const MAGIC: [u8; 4] = *b"PEEL";
/// Bumped whenever the byte layout or the meaning of a field changes; readers refuse others.
pub const FORMAT_VERSION: u16 = 3;
/// "No node" in a child or parent field.
pub const NONE: u32 = u32::MAX;
/// "No node" (or "no box") in a `u16` field of a [`header_flags::NARROW`] file.
pub const NONE16: u16 = u16::MAX;
/// "No node" (or "no box") in a `u24` field of a [`header_flags::MEDIUM`] file.
pub const NONE24: u32 = (1 << 24) - 1;

/// Bits of the header's `flags`.
pub mod header_flags {
    /// The `ids` array holds one source triangle id per polygon.
    pub const IDS: u16 = 1 << 0;
    /// Indices are `u16` (else `u32`).
    pub const INDEX16: u16 = 1 << 1;
    /// Polygons name a colour of the `palette` array (else they hold their RGB colour).
    pub const PALETTE: u16 = 1 << 2;
    /// With [`PALETTE`]: the palette index is a `u16` (else a `u8`).
    pub const PALETTE16: u16 = 1 << 3;
    /// Node records end with an index into the `bounds` array (or `NONE`).
    pub const BOUNDS: u16 = 1 << 4;
    /// Node fields and a polygon's `first_index` are `u16` (else `u32`): every
    /// count they index is at most 65535.
    pub const NARROW: u16 = 1 << 5;
    /// Without [`NARROW`]: those fields are 3-byte little-endian integers (`u24`): every count
    /// they index is at most 2^24 - 1. Both flags at once are inconsistent.
    pub const MEDIUM: u16 = 1 << 6;
    /// Vertices are `[f32; 3]` (else `[u16; 3]`: steps on the header's bounds, decoded by
    /// [`super::dequantise`]).
    pub const WIDE_VERTICES: u16 = 1 << 7;
    /// Indices are 3-byte little-endian integers (`u24`, for up to 2^24 vertices); with
    /// [`INDEX16`] the flags are inconsistent.
    pub const INDEX24: u16 = 1 << 8;
    /// Each polygon record ends with a second colour field: the colour of its exterior side
    /// (the first is its interior side's). Without it both sides have the one colour.
    pub const TWO_COLOURS: u16 = 1 << 9;
    /// Every bit this version defines; a reader refuses others.
    pub const KNOWN: u16 = IDS
        | INDEX16
        | PALETTE
        | PALETTE16
        | BOUNDS
        | NARROW
        | MEDIUM
        | WIDE_VERTICES
        | INDEX24
        | TWO_COLOURS;
}

/// Bytes of an index under header `flags`.
pub const fn index_size(flags: u16) -> usize {
    if flags & header_flags::INDEX16 != 0 {
        2
    } else if flags & header_flags::INDEX24 != 0 {
        3
    } else {
        4
    }
}

/// Bytes of a vertex under header `flags`: `[f32; 3]` with [`header_flags::WIDE_VERTICES`],
/// else `[u16; 3]`.
pub const fn vertex_size(flags: u16) -> usize {
    if flags & header_flags::WIDE_VERTICES != 0 {
        12
    } else {
        6
    }
}

/// Bytes of a node field and a polygon's `first_index` under header `flags`.
pub const fn field_size(flags: u16) -> usize {
    if flags & header_flags::NARROW != 0 {
        2
    } else if flags & header_flags::MEDIUM != 0 {
        3
    } else {
        4
    }
}

/// "No node" in a field of `width` bytes: its largest value.
pub const fn none_of_width(width: usize) -> u32 {
    match width {
        2 => NONE16 as u32,
        3 => NONE24,
        _ => NONE,
    }
}

/// Bytes of a polygon's colour field under header `flags`: 3 bytes of RGB, or a 1- or 2-byte
/// palette index.
pub const fn colour_size(flags: u16) -> usize {
    if flags & header_flags::PALETTE == 0 {
        3
    } else if flags & header_flags::PALETTE16 != 0 {
        2
    } else {
        1
    }
}

/// Bytes of a polygon record under header `flags`: `first_index` ([`field_size`]),
/// `vertex_count` and `flags` (a byte each), the colour, and with
/// [`header_flags::TWO_COLOURS`] the exterior side's colour. A polygon's plane is not stored:
/// it is the plane through its first three vertices.
pub const fn polygon_size(flags: u16) -> usize {
    let colours = if flags & header_flags::TWO_COLOURS != 0 {
        2
    } else {
        1
    };
    field_size(flags) + 2 + colours * colour_size(flags)
}

/// Bytes of a node record under header `flags`: `kind`, then `a`, `b`, `parent` and with
/// [`header_flags::BOUNDS`] `bounds` ([`field_size`] each). A node's first child is implicit
/// (the next node, flagged by [`node_kind::FIRST_CHILD`]), so it takes no field.
pub const fn node_size(flags: u16) -> usize {
    let fields = if flags & header_flags::BOUNDS != 0 {
        4
    } else {
        3
    };
    1 + fields * field_size(flags)
}

/// A vertex or node box coordinate: step `q` of 65535 from the header's `min` to its `max`
/// along one axis, `min + q * step(min, max)`. It is monotone in `q`, so a box of steps contains
/// every vertex whose steps it contains; the writer rounds `f32` vertices' boxes outward
/// through this very function.
#[inline]
pub fn dequantise(min: f32, max: f32, q: u16) -> f32 {
    min + f32::from(q) * step(min, max)
}

/// The size of a step along an axis from `min` to `max` (`f32`, as [`dequantise`] uses it).
#[inline]
pub fn step(min: f32, max: f32) -> f32 {
    (max - min) / 65535.0
}

/// An axis whose bounds are an exact grid: step `q` lies at `(origin + q * stride) * 2^shift`
/// with every such integer below 2^24, so [`dequantise`] rounds nothing and a core without an
/// FPU gets its very bits from one integer multiply-add and one conversion ([`Grid::value`]).
/// The compiler writes such bounds; a file whose bounds are not one still decodes alike on
/// every core, through [`dequantise`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Grid {
    origin: i32,
    stride: i32,
    shift: i32,
}

impl Grid {
    /// The grid of the bounds `min ..= max`, if they are one.
    pub fn of(min: f32, max: f32) -> Option<Grid> {
        if !(min <= max && max - min <= f32::MAX) {
            return None;
        }
        let step = step(min, max);
        let (s, s_exp) = odd_times_power_of_two(step);
        let (m, m_exp) = odd_times_power_of_two(min);
        let shift = match (s, m) {
            (0, _) => m_exp,
            (_, 0) => s_exp,
            _ => s_exp.min(m_exp),
        };
        // A normal power of two, and every value `n * 2^shift` (|n| < 2^24) finite.
        if !(-126..=104).contains(&shift) {
            return None;
        }
        let widen = |n: i32, exp: i32| {
            if n == 0 {
                return Some(0);
            }
            let by = u32::try_from(exp - shift).ok().filter(|&by| by < 24)?;
            n.checked_mul(1 << by)
                .filter(|w| w.unsigned_abs() < 1 << 24)
        };
        let grid = Grid {
            origin: widen(m, m_exp)?,
            stride: widen(s, s_exp).filter(|&t| t <= 255)?,
            shift,
        };
        let last = grid.origin + 65535 * grid.stride;
        let exact = last.unsigned_abs() < 1 << 24
            && grid.value(0) == min
            && grid.value(u16::MAX) == max
            && step * 65535.0 == max - min;
        exact.then_some(grid)
    }

    /// Step `q`: [`dequantise`] on the grid's bounds, bit for bit, without a float operation
    /// but one conversion from `i32` (and on ARMv6-M, where every float multiply is a library
    /// call, the power of two added to the exponent).
    #[inline]
    pub fn value(self, q: u16) -> f32 {
        // Below 2^24 in magnitude (checked by `of`): exact in f32.
        let n = self.origin + i32::from(q) * self.stride;
        if ARMV6M {
            scaled_by_exponent(n, self.shift)
        } else {
            n as f32 * f32::from_bits(((self.shift + 127) as u32) << 23)
        }
    }
}

/// `n * 2^shift` for `|n| < 2^24` and `-126 <= shift <= 104` (a normal, finite result): the
/// conversion's exponent field moved by `shift`, where a multiply would be a library call.
#[inline]
pub(crate) fn scaled_by_exponent(n: i32, shift: i32) -> f32 {
    if n == 0 {
        return 0.0;
    }
    f32::from_bits(((n as f32).to_bits() as i32).wrapping_add(shift << 23) as u32)
}

/// `x` as `m * 2^e` with `m` odd and `|m| < 2^24`, or `(0, 0)` for zero (and for a value
/// that is not finite, which no grid accepts: its `e` is out of range).
fn odd_times_power_of_two(x: f32) -> (i32, i32) {
    let bits = x.to_bits();
    let field = ((bits >> 23) & 0xff) as i32;
    let fraction = (bits & 0x7f_ffff) as i32;
    let (m, e) = match field {
        0 if fraction == 0 => return (0, 0),
        0 => (fraction, -149),
        0xff => return (1, i32::MAX / 2),
        _ => (fraction | 0x80_0000, field - 150),
    };
    let zeros = m.trailing_zeros() as i32;
    let m = m >> zeros;
    (if bits >> 31 != 0 { -m } else { m }, e + zeros)
}

/// ARMv6-M (Cortex-M0+ class: no FPU, no long multiply, no divide), told apart by its lack of
/// compare-and-swap.
pub(crate) const ARMV6M: bool = cfg!(all(target_arch = "arm", not(target_has_atomic = "32")));

/// Steps per unit of length along an axis from `min` to `max` (1 on a flat axis, where every
/// step is 0): what brings a point to steps for a polygon's side ([`crate::read::Scene::side_eye`]).
#[inline]
pub fn per_step(min: f32, max: f32) -> f32 {
    let extent = max - min;
    if extent > 0.0 {
        65535.0 / extent
    } else {
        1.0
    }
}

/// Bits of a polygon's `flags`.
pub mod polygon_flags {
    /// The rest of the polygon's convex set lies on the + side of its plane (the plane through
    /// its first three vertices, its normal `(v1 - v0) x (v2 - v0)`).
    pub const INTERIOR_FRONT: u8 = 1 << 1;
    /// Every bit this version defines; a reader refuses others.
    pub const KNOWN: u8 = INTERIOR_FRONT;
}

/// Values of a node's `kind` byte.
pub mod node_kind {
    /// `a` = first polygon, `b` = polygon count; the child (what lies inside the set) is the
    /// next node when [`FIRST_CHILD`] is set, else there is none.
    pub const CONVEX: u8 = 0;
    /// `a` = plane, `b` = child on the - side (or [`super::NONE`]); the child on the + side is
    /// the next node when [`FIRST_CHILD`] is set, else there is none.
    pub const SPLIT: u8 = 1;
    /// Bit of the `kind` byte: the node's first child (a convex node's child, a split's + child)
    /// exists and is the next node, `i + 1` (the nodes are in pre-order, front before back).
    pub const FIRST_CHILD: u8 = 1 << 7;
}

/// Bytes of the header.
pub const HEADER_SIZE: usize = 92;
/// Bytes of an array length (`u64`).
pub const LENGTH_SIZE: usize = 8;
/// Bytes of a plane (`[f32; 4]`).
pub const PLANE_SIZE: usize = 16;
/// Bytes of an index (`u32`; `u16` with [`header_flags::INDEX16`], see [`index_size`]).
pub const INDEX_SIZE: usize = 4;
/// Bytes of the widest polygon record (`u32` field, RGB colour; see [`polygon_size`]).
pub const POLYGON_SIZE: usize = 11;
/// Bytes of a palette entry (RGB888).
pub const PALETTE_SIZE: usize = 3;
/// Bytes of a node's bounds (`[u16; 6]`: min then max, see [`dequantise`]).
pub const BOUNDS_SIZE: usize = 12;
/// Bytes of an id (`u32`).
pub const ID_SIZE: usize = 4;
/// Bytes of the widest node record (`u32` fields and bounds; see [`node_size`]).
pub const NODE_SIZE: usize = 17;

/// Byte offsets of the header fields.
pub(crate) mod header_offset {
    pub const VERSION: usize = 4;
    pub const FLAGS: usize = 6;
    pub const VERTEX_COUNT: usize = 8;
    pub const PLANE_COUNT: usize = 12;
    pub const INDEX_COUNT: usize = 16;
    pub const POLYGON_COUNT: usize = 20;
    pub const NODE_COUNT: usize = 24;
    pub const MAX_DEPTH: usize = 28;
    pub const MAX_POLYGON_VERTICES: usize = 32;
    pub const CENTRE: usize = 36;
    pub const BOUNDS_MIN: usize = 60;
    pub const BOUNDS_MAX: usize = 72;
    pub const PALETTE_COUNT: usize = 84;
    pub const BOUNDS_COUNT: usize = 88;
}

impl super::Header {
    /// The header as a file holds it: its [`HEADER_SIZE`] bytes, [`MAGIC`] first. The one
    /// description of the header's bytes, which the compiler's writer uses too.
    pub fn to_bytes(&self) -> [u8; HEADER_SIZE] {
        use header_offset as h;
        let mut out = [0u8; HEADER_SIZE];
        let mut put = |offset: usize, field: &[u8]| {
            for (o, b) in out.iter_mut().skip(offset).zip(field) {
                *o = *b;
            }
        };
        put(0, &MAGIC);
        put(h::VERSION, &self.version.to_le_bytes());
        put(h::FLAGS, &self.flags.to_le_bytes());
        put(h::VERTEX_COUNT, &self.vertex_count.to_le_bytes());
        put(h::PLANE_COUNT, &self.plane_count.to_le_bytes());
        put(h::INDEX_COUNT, &self.index_count.to_le_bytes());
        put(h::POLYGON_COUNT, &self.polygon_count.to_le_bytes());
        put(h::NODE_COUNT, &self.node_count.to_le_bytes());
        put(h::MAX_DEPTH, &self.max_depth.to_le_bytes());
        put(
            h::MAX_POLYGON_VERTICES,
            &self.max_polygon_vertices.to_le_bytes(),
        );
        for (k, c) in self.centre.iter().enumerate() {
            put(h::CENTRE + 8 * k, &c.to_le_bytes());
        }
        for (k, (lo, hi)) in self
            .bounds_min
            .to_array()
            .iter()
            .zip(self.bounds_max.to_array())
            .enumerate()
        {
            put(h::BOUNDS_MIN + 4 * k, &lo.to_le_bytes());
            put(h::BOUNDS_MAX + 4 * k, &hi.to_le_bytes());
        }
        put(h::PALETTE_COUNT, &self.palette_count.to_le_bytes());
        put(h::BOUNDS_COUNT, &self.bounds_count.to_le_bytes());
        out
    }

    /// The header of [`HEADER_SIZE`] bytes, field by field, with no check: [`Scene::parse`]
    /// checks the magic, version and flags first (and [`Self::to_bytes`] undoes this).
    ///
    /// [`Scene::parse`]: super::Scene::parse
    pub fn from_bytes(bytes: &[u8; HEADER_SIZE]) -> Self {
        use header_offset as h;
        let r = Record(*bytes);
        let f64_field = |offset: usize| f64::from_le_bytes(r.bytes(offset));
        let vec3 =
            |offset: usize| glam::Vec3::new(r.f32(offset), r.f32(offset + 4), r.f32(offset + 8));
        Self {
            version: r.u16(h::VERSION),
            flags: r.u16(h::FLAGS),
            vertex_count: r.u32(h::VERTEX_COUNT),
            plane_count: r.u32(h::PLANE_COUNT),
            index_count: r.u32(h::INDEX_COUNT),
            polygon_count: r.u32(h::POLYGON_COUNT),
            node_count: r.u32(h::NODE_COUNT),
            max_depth: r.u32(h::MAX_DEPTH),
            max_polygon_vertices: r.u32(h::MAX_POLYGON_VERTICES),
            centre: [
                f64_field(h::CENTRE),
                f64_field(h::CENTRE + 8),
                f64_field(h::CENTRE + 16),
            ],
            bounds_min: vec3(h::BOUNDS_MIN),
            bounds_max: vec3(h::BOUNDS_MAX),
            palette_count: r.u32(h::PALETTE_COUNT),
            bounds_count: r.u32(h::BOUNDS_COUNT),
        }
    }
}

/// A fixed-size record read once (one bounds check), whose fields are then decoded at constant
/// offsets with no further check: the hot accessors read nodes, planes and polygons this way.
#[derive(Clone, Copy)]
pub(crate) struct Record<const N: usize>([u8; N]);

impl<const N: usize> Record<N> {
    /// The `N` bytes at `offset`, or `None` past the end (or on overflow).
    #[inline]
    pub(crate) fn at(bytes: &[u8], offset: usize) -> Option<Self> {
        array_at(bytes, offset).map(Record)
    }

    /// `W` bytes at `offset` (zero past the end: offsets are constants within `N`).
    #[inline]
    fn bytes<const W: usize>(&self, offset: usize) -> [u8; W] {
        let mut out = [0u8; W];
        for (o, b) in out.iter_mut().zip(self.0.iter().skip(offset)) {
            *o = *b;
        }
        out
    }

    #[inline]
    pub(crate) fn u16(&self, offset: usize) -> u16 {
        u16::from_le_bytes(self.bytes(offset))
    }

    #[inline]
    pub(crate) fn f32(&self, offset: usize) -> f32 {
        f32::from_le_bytes(self.bytes(offset))
    }

    #[inline]
    pub(crate) fn u8(&self, offset: usize) -> u8 {
        self.0.get(offset).copied().unwrap_or(0)
    }

    #[inline]
    pub(crate) fn u32(&self, offset: usize) -> u32 {
        u32::from_le_bytes(self.bytes(offset))
    }

    /// A `u16` field, its [`NONE16`] read as [`NONE`] when `link`.
    #[inline]
    pub(crate) fn narrow(&self, offset: usize, link: bool) -> u32 {
        let v = self.u16(offset);
        if link && v == NONE16 {
            NONE
        } else {
            u32::from(v)
        }
    }

    /// A `u24` field, its [`NONE24`] read as [`NONE`] when `link`.
    #[inline]
    pub(crate) fn medium(&self, offset: usize, link: bool) -> u32 {
        let [a, b, c] = self.bytes::<3>(offset);
        let v = u32::from_le_bytes([a, b, c, 0]);
        if link && v == NONE24 {
            NONE
        } else {
            v
        }
    }
}

/// `N` bytes at `offset`, or `None` past the end (or on overflow).
fn array_at<const N: usize>(bytes: &[u8], offset: usize) -> Option<[u8; N]> {
    bytes.get(offset..offset.checked_add(N)?)?.try_into().ok()
}

pub(crate) fn u8_at(bytes: &[u8], offset: usize) -> Option<u8> {
    bytes.get(offset).copied()
}

pub(crate) fn u16_at(bytes: &[u8], offset: usize) -> Option<u16> {
    array_at(bytes, offset).map(u16::from_le_bytes)
}

/// A node field or a polygon's `first_index` of `width` bytes (2, 3 or 4), its
/// largest value read as [`NONE`] when `link`.
#[inline]
pub(crate) fn field_at(bytes: &[u8], offset: usize, width: usize, link: bool) -> Option<u32> {
    let mut le = [0u8; 4];
    let end = offset.checked_add(width.min(4))?;
    for (o, b) in le.iter_mut().zip(bytes.get(offset..end)?) {
        *o = *b;
    }
    let v = u32::from_le_bytes(le);
    Some(if link && v == none_of_width(width) {
        NONE
    } else {
        v
    })
}

pub(crate) fn u32_at(bytes: &[u8], offset: usize) -> Option<u32> {
    array_at(bytes, offset).map(u32::from_le_bytes)
}

pub(crate) fn u64_at(bytes: &[u8], offset: usize) -> Option<u64> {
    array_at(bytes, offset).map(u64::from_le_bytes)
}

pub(crate) fn f32_at(bytes: &[u8], offset: usize) -> Option<f32> {
    array_at(bytes, offset).map(f32::from_le_bytes)
}

pub(crate) fn f64_at(bytes: &[u8], offset: usize) -> Option<f64> {
    array_at(bytes, offset).map(f64::from_le_bytes)
}

/// Byte offset of element `index` of an array of `size`-byte records starting at `start`.
#[inline]
pub(crate) fn element(start: usize, size: usize, index: u32) -> Option<usize> {
    if ARMV6M {
        element_narrow(start, size, index)
    } else {
        usize::try_from(index)
            .ok()?
            .checked_mul(size)?
            .checked_add(start)
    }
}

/// [`element`] for ARMv6-M ([`ARMV6M`]), which has no
/// widening multiply: there `checked_mul` is a 64-bit library call on every record read.
/// Below 2^24 records of under 256 bytes the product fits 32 bits and needs no check.
#[inline]
pub(crate) fn element_narrow(start: usize, size: usize, index: u32) -> Option<usize> {
    let index = usize::try_from(index).ok()?;
    let offset = if index < 1 << 24 && size < 256 {
        index * size
    } else {
        index.checked_mul(size)?
    };
    offset.checked_add(start)
}
