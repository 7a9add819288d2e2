//! The byte layout of a `.peel` file (specified in `formats/peel.md`): the constants the
//! compiler's writer shares with this reader, and little-endian field access that never panics.
//!
//! One file per part of the format, its items all re-exported here: the header (`header.rs`),
//! nodes (`node.rs`), polygons (`polygon.rs`), textures (`texture.rs`), transparency (`transparency.rs`), vertices and their grid (`vertex.rs`), and how
//! any field is read (`fields.rs`).

mod fields;
mod header;
mod node;
mod parts;
mod polygon;
mod texture;
mod transparency;
mod vertex;

pub(crate) use fields::{
    element, f32_at, f64_at, field_at, u16_at, u32_at, u64_at, u8_at, Record, ARMV6M,
};
pub use fields::{none_of_width, LENGTH_SIZE, NONE, NONE16, NONE24};
pub(crate) use header::header_offset;
pub use header::{header_flags, FORMAT_VERSION, HEADER_SIZE, MAGIC};
pub use node::{field_size, node_kind, node_size, BOUNDS_SIZE, NODE_SIZE, PLANE_SIZE};
pub use parts::{
    parts_offset, MAX_NAME, MAX_PARTS, PARTS_HEADER_SIZE, PARTS_VERSION, PART_ENTRY_SIZE,
};
pub use polygon::{
    colour_size, index_size, polygon_flags, polygon_size, ID_SIZE, INDEX_SIZE, PALETTE_SIZE,
    POLYGON_SIZE, SHADE_SIZE,
};
pub use texture::{
    texture_bytes, texture_flags, MAX_TEXTURES, MAX_TEXTURE_LOG2, NO_TEXTURE, TEXEL_SIZE,
    TEXTURED_VERSION, TEXTURE_SIZE, UV_FRACTION_BITS, UV_SIZE,
};
pub use transparency::{OPACITY_SIZE, OPAQUE, TRANSPARENT_VERSION};
pub use vertex::{dequantise, per_step, step, vertex_size, Grid};

// The core-specific paths the reader's tests check against the plain arithmetic.
#[cfg(test)]
pub(crate) use fields::element_narrow;
#[cfg(test)]
pub(crate) use vertex::scaled_by_exponent;
