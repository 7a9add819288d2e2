//! The header: its magic, version and flags, its fields' offsets, and its bytes both ways
//! ([`Header::to_bytes`], [`Header::from_bytes`]), the one description of them that the
//! compiler's writer uses too.

use super::fields::Record;
use crate::read::Header;

/// First four bytes of every `.peel` file.
pub const MAGIC: [u8; 4] = *b"PEEL";
/// Bumped whenever the byte layout or the meaning of a field changes; readers refuse others.
pub const FORMAT_VERSION: u16 = 4;

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
    /// [`dequantise`](super::super::dequantise)).
    pub const WIDE_VERTICES: u16 = 1 << 7;
    /// Indices are 3-byte little-endian integers (`u24`, for up to 2^24 vertices); with
    /// [`INDEX16`] the flags are inconsistent.
    pub const INDEX24: u16 = 1 << 8;
    /// Each polygon record ends with a second colour field: the colour of its exterior side
    /// (the first is its interior side's). Without it both sides have the one colour.
    pub const TWO_COLOURS: u16 = 1 << 9;
    /// The file ends with the `shades` array: per vertex, two 8-bit intensities (of the
    /// source triangle's front side, then of its back side; 255 is the material's full
    /// colour), which the vertices of [`polygon_flags::SMOOTH`](super::super::polygon_flags::SMOOTH)
    /// polygons are shaded with. Without it no polygon is smooth.
    pub const SHADES: u16 = 1 << 10;
    /// Some polygons bound solids ([`polygon_flags::INSIDE_INTERIOR`](super::super::polygon_flags::INSIDE_INTERIOR),
    /// [`polygon_flags::INSIDE_EXTERIOR`](super::super::polygon_flags::INSIDE_EXTERIOR)):
    /// seen from behind from outside their solid, they are hidden.
    pub const SOLID: u16 = 1 << 11;
    /// Only in a file of version [`TEXTURED_VERSION`](super::super::TEXTURED_VERSION), and
    /// always there: the file ends with the texture arrays (`uvs`, `textures`, `texels`,
    /// `polygon_textures`), and polygons may be textured.
    pub const TEXTURES: u16 = 1 << 12;
    /// Only in a file of version [`TRANSPARENT_VERSION`](super::super::TRANSPARENT_VERSION),
    /// and always there: the file ends with the `opacities` array (a `u8` per polygon), and
    /// polygons may be [`polygon_flags::TRANSPARENT`](super::super::polygon_flags::TRANSPARENT).
    pub const TRANSPARENT: u16 = 1 << 13;
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
        | TWO_COLOURS
        | SHADES
        | SOLID
        | TEXTURES
        | TRANSPARENT;
}

/// Bytes of the header.
pub const HEADER_SIZE: usize = 92;

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

impl Header {
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
    /// [`Scene::parse`]: crate::read::Scene::parse
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
