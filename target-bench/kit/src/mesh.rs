//! The z-buffer baseline's scene: a plain indexed triangle mesh, read in place like a `.peel`
//! file. Vertices are relative to the `.peel` scene's centre and carry its header's centre and
//! bounds, so the firmware frames it with the very same [`peel_runtime::camera::Orbit`] pose;
//! each triangle has the RGB565 value of the colour the compiler baked into its polygons.
//!
//! | offset | field |
//! |---|---|
//! | 0 | magic `PTBM` |
//! | 4 | [`VERSION`] (u32) |
//! | 8, 12 | vertex count, triangle count (u32) |
//! | 16 | centre (3 x f64) |
//! | 40, 52 | bounds min, max relative to the centre (3 x f32 each) |
//! | 64 | vertices (3 x f32 each) |
//! | then | triangles: three u16 vertex indices and an RGB565 colour (u16) each |

use glam::Vec3;
use peel_runtime::read::Header;

use crate::bytes::{f32_at, f64_at, u16_at, u32_at};

/// Format version.
pub const VERSION: u32 = 1;
/// The file's first bytes.
pub const MAGIC: [u8; 4] = *b"PTBM";
/// Header size.
pub const HEADER: usize = 64;
/// Bytes per vertex.
pub const VERTEX: usize = 12;
/// Bytes per triangle.
pub const TRIANGLE: usize = 8;

/// Why mesh bytes were refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshError {
    /// Not a mesh of this version.
    Magic,
    /// Fewer bytes than the counts need.
    Truncated,
    /// Triangle `0` names a vertex past the vertex count.
    Index(u32),
}

impl core::fmt::Display for MeshError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            MeshError::Magic => write!(f, "not a mesh (magic PTBM, version {VERSION})"),
            MeshError::Truncated => write!(f, "mesh shorter than its counts say"),
            MeshError::Index(t) => write!(f, "mesh triangle {t} names a missing vertex"),
        }
    }
}

/// A validated mesh over borrowed bytes.
#[derive(Debug, Clone, Copy)]
pub struct Mesh<'a> {
    vertices: &'a [u8],
    triangles: &'a [u8],
    centre: [f64; 3],
    bounds_min: Vec3,
    bounds_max: Vec3,
}

impl<'a> Mesh<'a> {
    /// Check `bytes` once (header, lengths, every index); the accessors cannot fail after.
    ///
    /// # Errors
    /// [`MeshError`] for anything else than a mesh of this version.
    pub fn parse(bytes: &'a [u8]) -> Result<Mesh<'a>, MeshError> {
        if bytes.get(..4) != Some(&MAGIC[..]) || u32_at(bytes, 4) != Some(VERSION) {
            return Err(MeshError::Magic);
        }
        let count = |at| {
            u32_at(bytes, at)
                .map(|n| n as usize)
                .ok_or(MeshError::Truncated)
        };
        let (nv, nt) = (count(8)?, count(12)?);
        let v_end = nv
            .checked_mul(VERTEX)
            .and_then(|n| n.checked_add(HEADER))
            .ok_or(MeshError::Truncated)?;
        let t_end = nt
            .checked_mul(TRIANGLE)
            .and_then(|n| n.checked_add(v_end))
            .ok_or(MeshError::Truncated)?;
        let vertices = bytes.get(HEADER..v_end).ok_or(MeshError::Truncated)?;
        let triangles = bytes.get(v_end..t_end).ok_or(MeshError::Truncated)?;
        let f = |at| f64_at(bytes, at).unwrap_or(0.0);
        let v = |at: usize| {
            let g = |k: usize| f32_at(bytes, at + 4 * k).unwrap_or(0.0);
            Vec3::new(g(0), g(1), g(2))
        };
        let mesh = Mesh {
            vertices,
            triangles,
            centre: [f(16), f(24), f(32)],
            bounds_min: v(40),
            bounds_max: v(52),
        };
        for t in 0..mesh.triangle_count() {
            let (corners, _) = mesh.triangle(t);
            if corners.iter().any(|&i| usize::from(i) >= nv) {
                return Err(MeshError::Index(t));
            }
        }
        Ok(mesh)
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> u32 {
        (self.triangles.len() / TRIANGLE) as u32
    }

    /// Vertex `i`, relative to the centre (the origin for an index out of range).
    #[inline]
    pub fn vertex(&self, i: u16) -> Vec3 {
        let at = usize::from(i) * VERTEX;
        let g = |k: usize| f32_at(self.vertices, at + 4 * k).unwrap_or(0.0);
        Vec3::new(g(0), g(1), g(2))
    }

    /// Triangle `t`: its corners' vertex indices and its RGB565 colour.
    #[inline]
    pub fn triangle(&self, t: u32) -> ([u16; 3], u16) {
        let at = t as usize * TRIANGLE;
        let g = |k: usize| u16_at(self.triangles, at + 2 * k).unwrap_or(0);
        ([g(0), g(1), g(2)], g(3))
    }

    /// Bounds of the scene (relative to the centre), as the `.peel` header has them.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        (self.bounds_min, self.bounds_max)
    }

    /// A header with the `.peel` scene's centre and bounds (the rest zero): what
    /// [`peel_runtime::camera::Orbit::pose`] and [`peel_runtime::camera::Camera::default_near`]
    /// read, so the mesh is seen from exactly the scene's cameras.
    pub fn header(&self) -> Header {
        Header {
            vertex_count: (self.vertices.len() / VERTEX) as u32,
            polygon_count: self.triangle_count(),
            max_polygon_vertices: 3,
            centre: self.centre,
            bounds_min: self.bounds_min,
            bounds_max: self.bounds_max,
            ..Header::default()
        }
    }
}

/// The bytes of a mesh: `vertices` relative to `header.centre`, `triangles` as vertex indices
/// and RGB565 colour, framed by `header`'s centre and bounds. `None` with more than 65536
/// vertices (the indices are 16-bit).
#[cfg(any(feature = "std", test))]
pub fn encode(
    header: &Header,
    vertices: &[Vec3],
    triangles: &[([u32; 3], u16)],
) -> Option<std::vec::Vec<u8>> {
    if vertices.len() > 1 << 16 {
        return None;
    }
    let mut b =
        std::vec::Vec::with_capacity(HEADER + VERTEX * vertices.len() + TRIANGLE * triangles.len());
    b.extend_from_slice(&MAGIC);
    b.extend_from_slice(&VERSION.to_le_bytes());
    b.extend_from_slice(&(vertices.len() as u32).to_le_bytes());
    b.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for c in header.centre {
        b.extend_from_slice(&c.to_le_bytes());
    }
    for v in [header.bounds_min, header.bounds_max]
        .iter()
        .chain(vertices)
    {
        for c in v.to_array() {
            b.extend_from_slice(&c.to_le_bytes());
        }
    }
    for (corners, colour) in triangles {
        for &i in corners {
            b.extend_from_slice(&u16::try_from(i).ok()?.to_le_bytes());
        }
        b.extend_from_slice(&colour.to_le_bytes());
    }
    Some(b)
}

/// The mesh `bytes` with each triangle's colour replaced by its index plus one: drawn with
/// background 0, its frame is an id image (the triangle seen at each pixel, 0 for none).
/// `None` for bytes that are not a mesh or with 65,535 triangles or more.
#[cfg(any(feature = "std", test))]
pub fn with_ids(bytes: &[u8]) -> Option<std::vec::Vec<u8>> {
    let mesh = Mesh::parse(bytes).ok()?;
    let count = u16::try_from(mesh.triangle_count())
        .ok()
        .filter(|&n| n < u16::MAX)?;
    let first = HEADER + mesh.vertices.len();
    let mut out = bytes.get(..first + TRIANGLE * usize::from(count))?.to_vec();
    for t in 0..count {
        let at = first + TRIANGLE * usize::from(t) + 6;
        out[at..at + 2].copy_from_slice(&(t + 1).to_le_bytes());
    }
    Some(out)
}

/// A header with only a centre and bounds, for tests.
#[cfg(test)]
pub(crate) fn test_header(centre: [f64; 3], lo: Vec3, hi: Vec3) -> Header {
    Header {
        centre,
        bounds_min: lo,
        bounds_max: hi,
        ..Header::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> Header {
        test_header([1.0, 2.0, 3.0], Vec3::splat(-1.0), Vec3::splat(1.0))
    }

    #[test]
    fn round_trip() {
        let vertices = [Vec3::new(0.5, -1.0, 0.25), Vec3::X, Vec3::Y];
        let bytes = encode(&header(), &vertices, &[([0, 1, 2], 0xf800)]).unwrap();
        let mesh = Mesh::parse(&bytes).unwrap();
        assert_eq!(mesh.triangle_count(), 1);
        assert_eq!(mesh.triangle(0), ([0, 1, 2], 0xf800));
        assert_eq!(mesh.vertex(0), vertices[0]);
        assert_eq!(mesh.header().centre, [1.0, 2.0, 3.0]);
        assert_eq!(mesh.bounds(), (Vec3::splat(-1.0), Vec3::splat(1.0)));
    }

    #[test]
    fn id_meshes() {
        let vertices = [Vec3::new(0.5, -1.0, 0.25), Vec3::X, Vec3::Y];
        let tris = [([0, 1, 2], 0xf800), ([2, 1, 0], 0x001f)];
        let bytes = encode(&header(), &vertices, &tris).unwrap();
        let ids = with_ids(&bytes).unwrap();
        let mesh = Mesh::parse(&ids).unwrap();
        assert_eq!(mesh.triangle(0), ([0, 1, 2], 1));
        assert_eq!(mesh.triangle(1), ([2, 1, 0], 2));
        assert_eq!(mesh.vertex(0), vertices[0]);
        assert!(with_ids(&bytes[1..]).is_none());
    }

    #[test]
    fn refusals() {
        let bytes = encode(&header(), &[Vec3::X; 3], &[([0, 1, 2], 0)]).unwrap();
        assert_eq!(
            Mesh::parse(&bytes[..bytes.len() - 1]).err(),
            Some(MeshError::Truncated)
        );
        assert_eq!(Mesh::parse(&bytes[1..]).err(), Some(MeshError::Magic));
        let bad = encode(&header(), &[Vec3::X; 3], &[([0, 1, 3], 0)]).unwrap();
        assert_eq!(Mesh::parse(&bad).err(), Some(MeshError::Index(0)));
        let many = std::vec![Vec3::X; (1 << 16) + 1];
        assert!(encode(&header(), &many, &[]).is_none());
    }
}
