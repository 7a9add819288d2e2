//! Read: a `.peel` file read in place from `&[u8]`, validated up front.
//!
//! After [`Scene::parse`] succeeded, every accessor is total (it never panics; an
//! out-of-range argument gives a default), so a corrupt file can never crash a frame.
//! The byte layout is specified in `formats/peel.md`; [`layout`] holds its constants.
//!
//! One file per part of the scene, each with the accessors that read it: nodes (`node.rs`),
//! polygons (`polygon.rs`), vertices, boxes and planes (`geometry.rs`), the side of a
//! polygon the eye is on (`side.rs`), textures (`texture.rs`) and opacities
//! (`transparency.rs`); the checks of [`Scene::parse`] in `validate.rs`.

mod geometry;
pub mod layout;
mod node;
mod parts;
mod polygon;
mod side;
mod texture;
mod transparency;
mod validate;

use core::fmt;

use glam::Vec3;

use crate::error::ReadError;
pub use geometry::Plane;
pub use node::Node;
pub use parts::Parts;
pub use polygon::Polygon;
pub use side::{Side, SideEye};
pub(crate) use texture::rgb565_at;
pub use texture::Texture;

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
    /// Number of palette colours (0 without
    /// [`header_flags::PALETTE`](layout::header_flags::PALETTE)).
    pub palette_count: u32,
    /// Number of node bounding boxes (0 without
    /// [`header_flags::BOUNDS`](layout::header_flags::BOUNDS)).
    pub bounds_count: u32,
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
    /// The `shades` array (with [`layout::header_flags::SHADES`]; else it is empty).
    shades: usize,
    /// The texture arrays (with [`layout::header_flags::TEXTURES`]; else all zero). Only
    /// with the `textures` feature: zeroing it linked a `memclr` into the smallest build.
    #[cfg(feature = "textures")]
    textures: texture::TextureArrays,
    /// The `opacities` array (with [`layout::header_flags::TRANSPARENT`]; else 0). Only with
    /// the `transparency` feature.
    #[cfg(feature = "transparency")]
    opacities: usize,
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
    /// [`header_flags::TWO_COLOURS`](layout::header_flags::TWO_COLOURS), else its one colour
    /// field.
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
    /// validated by the firmware's build script (what `firmware/embedded-example` does), where
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
}

#[cfg(test)]
mod tests;
