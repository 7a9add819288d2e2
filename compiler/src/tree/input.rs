//! The build's input: quantised triangles as fragments, and the (then frozen) plane table.
//!
//! Every plane the build will ever use is created here: split planes are support planes and
//! cuts only intersect existing planes, so the table is read-only (and shared by all threads)
//! during the build, and plane ids do not depend on scheduling.

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
    let mut kept = Vec::with_capacity(mesh.triangles.len());
    for (i, t) in mesh.triangles.iter().enumerate() {
        let q = t.vertices.map(|p| quantiser.quantise(p));
        let Some((plane, flipped)) = Plane::through(q[0], q[1], q[2]) else {
            dropped += 1;
            continue;
        };
        kept.push((i, q, plane, flipped, table.insert(plane)));
    }
    for (i, q, plane, flipped, support) in kept {
        let edges = (0..3)
            .map(|k| {
                let e = edge_plane(q[k], q[(k + 1) % 3], plane.n);
                let inside = e.side_of_point(q[(k + 2) % 3]);
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
