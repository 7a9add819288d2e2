//! The `.peel` file as Rust types. `formats/peel.md` specifies the same bytes; bincode 2 with
//! [`config`] (fixed-width little-endian integers, `u64` sequence lengths) writes them.
//!
//! Layout rule: every record type has a fixed size, so the runtime reads any element in place.

use serde::{Deserialize, Serialize};

// The constants live in the runtime's reader so that writer and reader cannot disagree.
pub use peel_runtime::read::layout::{
    header_flags, node_kind, polygon_flags, FORMAT_VERSION, MAGIC, NONE,
};

/// The bincode configuration, pinned here and nowhere else.
pub fn config() -> impl bincode::config::Config {
    bincode::config::standard()
        .with_little_endian()
        .with_fixed_int_encoding()
}

/// Fixed-size header (92 bytes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// [`MAGIC`].
    pub magic: [u8; 4],
    /// [`FORMAT_VERSION`].
    pub version: u16,
    /// [`header_flags`].
    pub flags: u16,
    /// Length of `vertices`.
    pub vertex_count: u32,
    /// Length of `planes`.
    pub plane_count: u32,
    /// Length of `indices`.
    pub index_count: u32,
    /// Length of `polygons`.
    pub polygon_count: u32,
    /// Length of `nodes`.
    pub node_count: u32,
    /// Nodes on the longest root-to-leaf path (bounds the traversal stack).
    pub max_depth: u32,
    /// Largest `vertex_count` of any polygon (bounds the clip buffers).
    pub max_polygon_vertices: u32,
    /// World position every coordinate of the file is relative to.
    pub centre: [f64; 3],
    /// Lower corner of the scene's bounding box, relative to `centre`.
    pub bounds_min: [f32; 3],
    /// Upper corner of the scene's bounding box, relative to `centre`.
    pub bounds_max: [f32; 3],
    /// Length of `palette` (0 without `header_flags::PALETTE`).
    pub palette_count: u32,
    /// Length of `bounds` (0 without `header_flags::BOUNDS`).
    pub bounds_count: u32,
}

/// A convex polygon (14 bytes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Polygon {
    /// Index into `planes` of its support plane.
    pub plane: u32,
    /// First of its `vertex_count` entries in `indices`.
    pub first_index: u32,
    /// Number of vertices (>= 3).
    pub vertex_count: u16,
    /// [`polygon_flags`].
    pub flags: u8,
    /// Baked RGB888 colour.
    pub colour: [u8; 3],
}

/// A node of the display tree (17 bytes); see [`node_kind`] for the meaning of `a`, `b`, `c`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Node {
    /// [`node_kind`].
    pub kind: u8,
    /// First field.
    pub a: u32,
    /// Second field.
    pub b: u32,
    /// Third field.
    pub c: u32,
    /// The node whose child this is ([`NONE`] for the root). Lets the reader check that the
    /// links form a tree, and measure its depth, without memory of its own.
    pub parent: u32,
}

/// A whole `.peel` file: the header, then flat arrays (each a `u64` length then its records).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PeelFile {
    /// Header.
    pub header: Header,
    /// Vertex positions relative to `header.centre`.
    pub vertices: Vec<[f32; 3]>,
    /// Planes `n · p = d` as `[nx, ny, nz, d]`, unit normal, relative to `header.centre`.
    pub planes: Vec<[f32; 4]>,
    /// Polygon vertex lists, concatenated.
    pub indices: Vec<u32>,
    /// Polygons, in the order of the convex nodes that own them; their vertex lists are
    /// consecutive in `indices`.
    pub polygons: Vec<Polygon>,
    /// Source triangle id per polygon when `header_flags::IDS` is set, else empty.
    pub ids: Vec<u32>,
    /// Palette colours when `header_flags::PALETTE` is set, else empty (this writer does not
    /// emit a palette yet).
    pub palette: Vec<[u8; 3]>,
    /// Node bounding boxes `[min, max]` when `header_flags::BOUNDS` is set, else empty (this
    /// writer does not emit bounds yet).
    pub bounds: Vec<[f32; 6]>,
    /// Nodes in pre-order (front before back): the root is node 0 and children come after
    /// their parents. Convex nodes own the polygons in node order.
    pub nodes: Vec<Node>,
}
