//! Transparency (format [`TRANSPARENT_VERSION`]): the constants of the `opacities` array a
//! file with transparent surfaces ends with.

/// The format version of a file with transparent surfaces
/// ([`TRANSPARENT`](super::header_flags::TRANSPARENT)): version 4's layout, or version 6's
/// with [`TEXTURES`](super::header_flags::TEXTURES), and the `opacities` array at the end.
pub const TRANSPARENT_VERSION: u16 = 7;

/// Bytes of a polygon's opacity (a `u8`: `alpha = opacity / 255`).
pub const OPACITY_SIZE: usize = 1;

/// The opacity of an opaque polygon; a polygon below it carries
/// [`polygon_flags::TRANSPARENT`](super::polygon_flags::TRANSPARENT).
pub const OPAQUE: u8 = u8::MAX;
