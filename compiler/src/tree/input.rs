//! The build's input: quantised triangles as fragments, and the (then frozen) plane table.
//!
//! Every plane the build will ever use is created here: split planes are support planes and
//! cuts only intersect existing planes, so the table is read-only (and shared by all threads)
//! during the build, and plane ids do not depend on scheduling.

use rayon::prelude::*;

use crate::error::CompileError;
use crate::load::Mesh;
use crate::planes::{edge_plane, Plane, PlaneTable, Side, Vertex};
use crate::quantise::Quantiser;
use crate::split::{Edge, Fragment};

/// Quantised triangles ready to build.
pub(crate) struct Input {
    /// The grid.
    pub quantiser: Quantiser,
    /// Every plane of the build.
    pub table: PlaneTable,
    /// One fragment per kept triangle, in source order.
    pub fragments: Vec<Fragment>,
    /// Triangles read.
    pub input_triangles: u64,
    /// Triangles of zero area after quantisation.
    pub degenerate_dropped: u64,
}

pub(crate) fn prepare(mesh: &Mesh) -> Result<Input, CompileError> {
    if mesh.triangles.len() > u32::MAX as usize / 4 {
        return Err(CompileError::TooLarge {
            path: mesh.files.first().cloned().unwrap_or_default(),
            message: format!(
                "{} triangles (at most {})",
                mesh.triangles.len(),
                u32::MAX / 4
            ),
        });
    }
    let quantiser = Quantiser::fit(mesh);
    let mut table = PlaneTable::default();
    let mut fragments = Vec::with_capacity(mesh.triangles.len());
    let mut dropped = 0;
    // Support planes take the first ids, in source order, and edge planes come after: the
    // build breaks ties by plane id, and this numbering does not depend on the coordinate
    // axes (an edge plane's axis direction does), so axis swaps and mirrors give the same
    // tree up to the transform.
    // The planes are computed in parallel (the gcds are the costly part), then numbered in
    // order: the same ids on any thread count.
    let supports: Vec<_> = mesh
        .triangles
        .par_iter()
        .map(|t| {
            let q = t.vertices.map(|p| quantiser.quantise(p));
            Plane::through(q[0], q[1], q[2]).map(|(plane, flipped)| (q, plane, flipped))
        })
        .collect();
    let mut kept = Vec::with_capacity(mesh.triangles.len());
    for (i, s) in supports.into_iter().enumerate() {
        let Some((q, plane, flipped)) = s else {
            dropped += 1;
            continue;
        };
        kept.push((i, q, flipped, table.insert(plane)));
    }
    let edge_planes: Vec<[(Plane, Side); 3]> = kept
        .par_iter()
        .map(|&(_, q, _, support)| {
            let n = table.get(support).plane.n;
            [0, 1, 2].map(|k| {
                let e = edge_plane(q[k], q[(k + 1) % 3], n);
                (e, e.side_of_point(q[(k + 2) % 3]))
            })
        })
        .collect();
    for ((i, q, flipped, support), edges) in kept.into_iter().zip(edge_planes) {
        let edges = edges
            .into_iter()
            .map(|(e, inside)| {
                debug_assert_ne!(inside, Side::On);
                Edge {
                    plane: table.insert(e),
                    inside,
                }
            })
            .collect();
        fragments.push(Fragment {
            source: i as u32,
            support,
            flipped,
            vertices: q.iter().map(|&p| Vertex::Int(p)).collect(),
            edges,
        });
    }
    Ok(Input {
        quantiser,
        table,
        fragments,
        input_triangles: mesh.triangles.len() as u64,
        degenerate_dropped: dropped,
    })
}
