//! Read: a `.peel` file read in place from `&[u8]`, validated up front.
//! CONTRACT (owned by the format helper): the API below. After [`Scene::parse`] succeeded,
//! every accessor is total (it never panics; an out-of-range argument gives a default).

use glam::Vec3;

use crate::error::ReadError;
use crate::target::Colour;

/// The header, decoded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Header {
    /// Format version.
    pub version: u16,
    /// Header flags (bit 0: ids present).
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
}

/// A plane `normal · p = d` (relative to the scene centre).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Plane {
    /// Unit normal.
    pub normal: Vec3,
    /// Offset.
    pub d: f32,
}

impl Plane {
    /// Signed distance of `p` (positive on the + side).
    pub fn distance(&self, p: Vec3) -> f32 {
        self.normal.dot(p) - self.d
    }
}

/// A polygon record.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Polygon {
    /// Support plane index.
    pub plane: u32,
    /// First entry in the index array.
    pub first_index: u32,
    /// Number of vertices.
    pub vertex_count: u16,
    /// Polygon flags (bit 0 flipped, bit 1 interior on the + side).
    pub flags: u8,
    /// Baked colour.
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

/// A validated `.peel` file borrowed from its bytes.
#[derive(Debug, Clone, Copy)]
pub struct Scene<'a> {
    bytes: &'a [u8],
}

impl<'a> Scene<'a> {
    /// Check everything up front (magic, version, sizes, every index in range, children after
    /// parents, depth <= header depth).
    pub fn parse(bytes: &'a [u8]) -> Result<Scene<'a>, ReadError> {
        let _ = bytes;
        todo!("format helper")
    }
    /// The header.
    pub fn header(&self) -> Header {
        todo!()
    }
    /// Root node, if the tree is not empty.
    pub fn root(&self) -> Option<u32> {
        todo!()
    }
    /// Node `i`.
    pub fn node(&self, i: u32) -> Node {
        let _ = i;
        todo!()
    }
    /// Polygon `i`.
    pub fn polygon(&self, i: u32) -> Polygon {
        let _ = i;
        todo!()
    }
    /// Vertex `i` of polygon `polygon` (`i < vertex_count`), relative to the centre.
    pub fn polygon_vertex(&self, polygon: &Polygon, i: u32) -> Vec3 {
        let _ = (polygon, i);
        todo!()
    }
    /// Vertex `i`, relative to the centre.
    pub fn vertex(&self, i: u32) -> Vec3 {
        let _ = i;
        todo!()
    }
    /// Plane `i`.
    pub fn plane(&self, i: u32) -> Plane {
        let _ = i;
        todo!()
    }
    /// Source triangle id of polygon `i`, when the file has ids.
    pub fn id(&self, i: u32) -> Option<u32> {
        let _ = (i, self.bytes);
        todo!()
    }
}
