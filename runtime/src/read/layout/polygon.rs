//! Polygons: their flags, their records' sizes (colour fields included), and the sizes of the
//! arrays they refer to (indices, palette, ids).

use super::header::header_flags;
use super::node::field_size;

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

/// Bits of a polygon's `flags`.
pub mod polygon_flags {
    /// The rest of the polygon's convex set lies on the + side of its plane (the plane through
    /// its first three vertices, its normal `(v1 - v0) x (v2 - v0)`).
    pub const INTERIOR_FRONT: u8 = 1 << 1;
    /// Smooth shading (only with [`SHADES`](super::header_flags::SHADES)): the colour varies over the
    /// polygon. Its colour fields hold the material's colour, and the colour at each vertex
    /// is that colour times the vertex's intensity on the side seen (the `shades` array,
    /// `round(c * intensity / 255)` a channel: `display::shaded`),
    /// interpolated in between. Without it the colour field is the side's colour, as in a
    /// faceted file: a polygon whose vertices' colours are all equal costs nothing more.
    pub const SMOOTH: u8 = 1 << 2;
    /// With [`SMOOTH`]: the polygon's interior side is its source triangle's back, so an eye
    /// on the interior side takes the second of each vertex's two intensities (else the
    /// first), an eye on the exterior side the other.
    pub const INTERIOR_BACK: u8 = 1 << 3;
    /// Only with [`SOLID`](super::header_flags::SOLID): the polygon bounds a solid whose
    /// inside lies on the polygon's interior side, so an eye outside the solid that sees that
    /// side sees it from behind, and the solid's surface hides it (in a frame with the whole
    /// scene in front of the near plane: `Traversal::skip_solids_from_behind`).
    pub const INSIDE_INTERIOR: u8 = 1 << 4;
    /// As [`INSIDE_INTERIOR`], the solid's inside on the polygon's exterior side.
    pub const INSIDE_EXTERIOR: u8 = 1 << 5;
    /// Only with [`TRANSPARENT`](super::header_flags::TRANSPARENT), exactly when the
    /// polygon's opacity (the `opacities` array) is below 255: it shows what lies behind it.
    /// Never with [`SMOOTH`], [`INSIDE_INTERIOR`] or [`INSIDE_EXTERIOR`], nor textured.
    pub const TRANSPARENT: u8 = 1 << 6;
    /// Every bit this version defines; a reader refuses others.
    pub const KNOWN: u8 =
        INTERIOR_FRONT | SMOOTH | INTERIOR_BACK | INSIDE_INTERIOR | INSIDE_EXTERIOR | TRANSPARENT;
}

/// Bytes of a vertex's shades (with [`header_flags::SHADES`]): two intensities.
pub const SHADE_SIZE: usize = 2;

/// Bytes of an index (`u32`; `u16` with [`header_flags::INDEX16`], see [`index_size`]).
pub const INDEX_SIZE: usize = 4;
/// Bytes of the widest polygon record (`u32` field, RGB colour; see [`polygon_size`]).
pub const POLYGON_SIZE: usize = 11;
/// Bytes of a palette entry (RGB888).
pub const PALETTE_SIZE: usize = 3;
/// Bytes of an id (`u32`).
pub const ID_SIZE: usize = 4;
