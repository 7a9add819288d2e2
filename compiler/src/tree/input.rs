//! The build's input: quantised triangles as fragments, and the (then frozen) plane table.
//!
//! Every plane a fragment will ever be bounded by is created here: cuts are made only by
//! table planes (support planes, and edge planes in edge splits, `split::edge`) and only
//! intersect existing planes, so the table is read-only (and shared by
//! all threads) during the build, and plane ids do not depend on scheduling. Free split planes
//! (`split::free`) cut nothing: their split nodes hold them by value.

use rayon::prelude::*;

use crate::error::CompileError;
use crate::load::Mesh;
use crate::planes::{edge_plane, Plane, PlaneTable, Side, Vertex};
use crate::quantise::{IPoint, Quantiser};
use crate::shadow::Light;
use crate::split::{Edge, Fragment};

/// Quantised triangles ready to build.
pub(crate) struct Input {
    /// The grid.
    pub quantiser: Quantiser,
    /// Every plane of the build.
    pub table: PlaneTable,
    /// One fragment per kept triangle, in source order.
    pub fragments: Vec<Fragment>,
    /// What the build starts from when it differs from `fragments`: their pieces lit and in
    /// shadow ([`crate::shadow`]), in source order.
    pub shadowed: Option<Vec<Fragment>>,
    /// Triangles read.
    pub input_triangles: u64,
    /// Triangles of zero area after quantisation.
    pub degenerate_dropped: u64,
}

/// The fragments the build starts from.
impl Input {
    pub(crate) fn build_fragments(&self) -> &[Fragment] {
        self.shadowed.as_deref().unwrap_or(&self.fragments)
    }
}

/// The build's input for `mesh`, its fragments cut along the shadows `light` casts when given.
pub(crate) fn prepare(mesh: &Mesh, light: Option<Light>) -> Result<Input, CompileError> {
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
    // Support planes take the first ids, in source order, and edge planes come after: the
    // build breaks ties by plane id, and this numbering does not depend on the coordinate
    // axes (an edge plane's axis direction does), so axis swaps and mirrors give the same
    // tree up to the transform.
    // Planes are computed and matched in parallel (the gcds and the hashing are the costly
    // part) and numbered in order: the same ids on any thread count.
    let supports: Vec<_> = mesh
        .triangles
        .par_iter()
        .map(|t| {
            let q = t.vertices.map(|p| quantiser.quantise(p));
            Plane::through(q[0], q[1], q[2]).map(|(plane, flipped)| (q, plane, flipped))
        })
        .collect();
    let kept: Vec<(usize, [IPoint; 3], bool, Plane)> = (supports.into_iter().enumerate())
        .filter_map(|(i, s)| s.map(|(q, plane, flipped)| (i, q, flipped, plane)))
        .collect();
    let dropped = (mesh.triangles.len() - kept.len()) as u64;
    let edges: Vec<[(Plane, Side); 3]> = kept
        .par_iter()
        .map(|&(_, q, _, support)| {
            [0, 1, 2].map(|k| {
                let e = edge_plane(q[k], q[(k + 1) % 3], support.n);
                (e, e.side_of_point(q[(k + 2) % 3]))
            })
        })
        .collect();
    let planes: Vec<Plane> = (kept.iter().map(|k| k.3))
        .chain(edges.iter().flat_map(|e| e.iter().map(|&(plane, _)| plane)))
        .collect();
    let mut table = PlaneTable::default();
    let ids = table.insert_all(&planes);
    let (support_ids, edge_ids) = ids.split_at(kept.len());
    let fragments: Vec<Fragment> = (kept.par_iter().zip(&edges).enumerate())
        .map(|(j, (&(i, q, flipped, _), edges))| {
            let edges = (0..3)
                .map(|k| {
                    debug_assert_ne!(edges[k].1, Side::On);
                    Edge {
                        plane: edge_ids[3 * j + k],
                        inside: edges[k].1,
                    }
                })
                .collect();
            Fragment {
                source: i as u32,
                support: support_ids[j],
                flipped,
                vertices: q.iter().map(|&p| Vertex::Int(p)).collect(),
                edges,
                shadowed: false,
            }
        })
        .collect();
    let shadowed = match light {
        Some(light) => {
            // A transparent triangle casts no shadow (it receives them).
            let casts: Vec<bool> = (mesh.triangles.iter())
                .map(|t| t.opacity == crate::load::OPAQUE)
                .collect();
            Some(crate::shadow::cast(
                &fragments, &casts, &mut table, light, &quantiser,
            )?)
        }
        None => None,
    };
    Ok(Input {
        quantiser,
        table,
        fragments,
        shadowed,
        input_triangles: mesh.triangles.len() as u64,
        degenerate_dropped: dropped,
    })
}
