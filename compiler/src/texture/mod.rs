//! Texture coordinates of the output: each vertex of each polygon gets the coordinates of its
//! position on its source triangle, the corners' `vt` interpolated (barycentric, as smooth
//! shading's intensities), in the file's fixed point.
//!
//! The interpolation is on the triangle as the build saw it, its corners on the grid: a vertex
//! at a corner has that corner's weights exactly (so its corner's coordinates, bit for bit),
//! and a vertex a cut made gets the coordinates of its exact position on the same plane of
//! coordinates, so cutting a polygon never changes its picture.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::load::texture::CornerUvs;
use crate::load::Mesh;
use crate::quantise::Quantiser;
use crate::shade::corners::weights;
use crate::tree::{DisplayTree, TreePolygon};
use peel_runtime::read::layout::UV_FRACTION_BITS;

/// `(u, v)` as OBJ gives them -> the file's `[s, t]`: `s = round(u 2^16)`,
/// `t = round((1 - v) 2^16)` (`t = 0` is the image's top row), saturating at the ends of `i32`.
pub(crate) fn fixed(uv: DVec2) -> [i32; 2] {
    let one = f64::from(1u32 << UV_FRACTION_BITS);
    // `as` saturates (and takes NaN to 0).
    [
        (uv.x * one).round() as i32,
        ((1.0 - uv.y) * one).round() as i32,
    ]
}

/// The coordinates at `p` (relative to the grid's origin) of a triangle whose corners are
/// `corners` (the same frame) with coordinates `uvs`: interpolated, each kept within its
/// corners' range (a point a rounding error outside is not extrapolated past them).
pub(crate) fn uv_at(corners: [DVec3; 3], uvs: [DVec2; 3], p: DVec3) -> DVec2 {
    let w = weights(corners, p);
    let value = uvs[0] * w[0] + uvs[1] * w[1] + uvs[2] * w[2];
    let lo = uvs[0].min(uvs[1]).min(uvs[2]);
    let hi = uvs[0].max(uvs[1]).max(uvs[2]);
    value.clamp(lo, hi)
}

/// Per polygon of `tree` (from `mesh`'s triangles), its vertices' texture coordinates in the
/// order of its list, or `None` for a polygon whose source triangle has no texture; empty when
/// the mesh has no textured triangle.
pub(crate) fn polygon_uvs(tree: &DisplayTree, mesh: &Mesh) -> Vec<Option<Vec<[i32; 2]>>> {
    if mesh.triangles.iter().all(|t| t.texture.is_none()) {
        return Vec::new();
    }
    let quantiser = Quantiser::fit(mesh);
    tree.polygons
        .par_iter()
        .map(|p| polygon(tree, p, mesh, &quantiser))
        .collect()
}

/// One polygon's coordinates ([`polygon_uvs`]).
fn polygon(
    tree: &DisplayTree,
    polygon: &TreePolygon,
    mesh: &Mesh,
    quantiser: &Quantiser,
) -> Option<Vec<[i32; 2]>> {
    let triangle = &mesh.triangles[polygon.source as usize];
    let CornerUvs { uv, .. } = triangle.texture?;
    // The corners as the build has them: grid points, in the tree's frame (exact: the grid's
    // step is a power of two).
    let corners = triangle.vertices.map(|c| {
        let q = quantiser.quantise(c);
        DVec3::new(f64::from(q[0]), f64::from(q[1]), f64::from(q[2])) * quantiser.scale
    });
    Some(
        (polygon.vertices.iter())
            .map(|&v| fixed(uv_at(corners, uv, tree.vertices[v as usize])))
            .collect(),
    )
}

#[cfg(test)]
mod tests;
