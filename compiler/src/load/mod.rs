//! Load: OBJ + MTL -> source triangles, with validation.
//!
//! CONTRACT (owned by the load helper): `load_obj(path)` returns a [`Mesh`] whose triangle `i`
//! is source triangle id `i` (ids follow the order of the `f` lines; a polygon face contributes
//! its triangles in the documented order).

use glam::DVec3;
use std::path::{Path, PathBuf};

use crate::error::CompileError;

/// Colour used for faces without a material (or when the MTL file is missing): mid grey.
pub const DEFAULT_COLOUR: [u8; 3] = [200, 200, 200];

/// One input triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SourceTriangle {
    /// Corners in file order (the winding gives the front side).
    pub vertices: [DVec3; 3],
    /// Material diffuse colour (`Kd`), RGB888.
    pub colour: [u8; 3],
}

/// A loaded scene.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Triangles; the index is the source triangle id.
    pub triangles: Vec<SourceTriangle>,
    /// Non-fatal problems (missing MTL, face without material, ...), already worded for people.
    pub warnings: Vec<String>,
    /// Every file read (the OBJ and its MTL files), for `cargo:rerun-if-changed`.
    pub files: Vec<PathBuf>,
}

/// Load an OBJ file (and its MTL files).
pub fn load_obj(path: &Path) -> Result<Mesh, CompileError> {
    let _ = path;
    todo!("load helper")
}
