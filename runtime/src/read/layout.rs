//! The byte layout of a `.peel` file (specified in `formats/peel.md`): the constants the
//! compiler's writer shares with this reader, and little-endian field access that never panics.

/// First four bytes of every `.peel` file.
pub const MAGIC: [u8; 4] = *b"PEEL";
/// Bumped whenever the byte layout or the meaning of a field changes; readers refuse others.
pub const FORMAT_VERSION: u16 = 1;
/// "No node" in a child or parent field.
pub const NONE: u32 = u32::MAX;

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
    /// Node records end with a `u32` index into the `bounds` array (or `NONE`).
    pub const BOUNDS: u16 = 1 << 4;
    /// Every bit this version defines; a reader refuses others.
    pub const KNOWN: u16 = IDS | INDEX16 | PALETTE | PALETTE16 | BOUNDS;
}

/// Bytes of an index under header `flags`.
pub const fn index_size(flags: u16) -> usize {
    if flags & header_flags::INDEX16 != 0 {
        2
    } else {
        4
    }
}

/// Bytes of a polygon record under header `flags`: 11 + the colour (3 bytes of RGB, or a
/// 1- or 2-byte palette index).
pub const fn polygon_size(flags: u16) -> usize {
    if flags & header_flags::PALETTE == 0 {
        POLYGON_SIZE
    } else if flags & header_flags::PALETTE16 != 0 {
        POLYGON_SIZE - 1
    } else {
        POLYGON_SIZE - 2
    }
}

/// Bytes of a node record under header `flags`.
pub const fn node_size(flags: u16) -> usize {
    if flags & header_flags::BOUNDS != 0 {
        NODE_SIZE + 4
    } else {
        NODE_SIZE
    }
}

/// Bits of a polygon's `flags`.
pub mod polygon_flags {
    /// The polygon's front (counter-clockwise) side faces away from its plane's normal.
    pub const FLIPPED: u8 = 1 << 0;
    /// The rest of the polygon's convex set lies on the + side of its plane.
    pub const INTERIOR_FRONT: u8 = 1 << 1;
    /// Set by earlier compilers on polygons of closed meshes, for a back-face culling that
    /// could change pixels; readers accept and ignore it, writers leave it 0.
    pub const LEGACY_ONE_SIDED: u8 = 1 << 2;
    /// Every bit this version defines; a reader refuses others.
    pub const KNOWN: u8 = FLIPPED | INTERIOR_FRONT | LEGACY_ONE_SIDED;
}

/// Values of a node's `kind`.
pub mod node_kind {
    /// `a` = first polygon, `b` = polygon count, `c` = child (or [`super::NONE`]).
    pub const CONVEX: u8 = 0;
    /// `a` = plane, `b` = child on the + side, `c` = child on the - side (or [`super::NONE`]).
    pub const SPLIT: u8 = 1;
}

/// Bytes of the header.
pub const HEADER_SIZE: usize = 92;
/// Bytes of an array length (`u64`).
pub const LENGTH_SIZE: usize = 8;
/// Bytes of a vertex (`[f32; 3]`).
pub const VERTEX_SIZE: usize = 12;
/// Bytes of a plane (`[f32; 4]`).
pub const PLANE_SIZE: usize = 16;
/// Bytes of an index (`u32`; `u16` with [`header_flags::INDEX16`], see [`index_size`]).
pub const INDEX_SIZE: usize = 4;
/// Bytes of a polygon record with an RGB colour (see [`polygon_size`]).
pub const POLYGON_SIZE: usize = 14;
/// Bytes of a palette entry (RGB888).
pub const PALETTE_SIZE: usize = 3;
/// Bytes of a node's bounds (`[f32; 6]`: min then max).
pub const BOUNDS_SIZE: usize = 24;
/// Bytes of an id (`u32`).
pub const ID_SIZE: usize = 4;
/// Bytes of a node record without bounds (see [`node_size`]).
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
    pub(crate) fn u8(&self, offset: usize) -> u8 {
        self.0.get(offset).copied().unwrap_or(0)
    }

    #[inline]
    pub(crate) fn u16(&self, offset: usize) -> u16 {
        u16::from_le_bytes(self.bytes(offset))
    }

    #[inline]
    pub(crate) fn u32(&self, offset: usize) -> u32 {
        u32::from_le_bytes(self.bytes(offset))
    }

    #[inline]
    pub(crate) fn f32(&self, offset: usize) -> f32 {
        f32::from_le_bytes(self.bytes(offset))
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
    if cfg!(all(target_arch = "arm", not(target_has_atomic = "32"))) {
        element_narrow(start, size, index)
    } else {
        usize::try_from(index)
            .ok()?
            .checked_mul(size)?
            .checked_add(start)
    }
}

/// [`element`] for ARMv6-M (no compare-and-swap, the cfg that tells it apart), which has no
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
