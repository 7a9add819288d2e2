//! Vertex merging: one id per exact point. Cuts compute the same point from different planes
//! (as different homogeneous coordinates); merged, neighbours share the vertex and its
//! rounding, so no crack opens between them.

use std::sync::Arc;

use glam::DVec3;
use rayon::prelude::*;

use crate::hash::{first_equal, mix, FastMap, ShardHash};
use crate::planes::same::{residues, same_point};
use crate::planes::Vertex;
use crate::split::Fragment;

/// The distinct vertices of the output (one id per exact point), with their approximate
/// coordinates (grid units).
pub(super) struct Vertices {
    pub(super) list: Vec<(Vertex, DVec3)>,
}

/// A vertex as [`first_equal`] matches it: hashed by its residues, equal when it is the same
/// point exactly (see [`crate::planes::same`]).
struct PointKey<'v> {
    residues: Option<[u64; 3]>,
    vertex: &'v Vertex,
}

impl PartialEq for PointKey<'_> {
    fn eq(&self, other: &Self) -> bool {
        self.residues == other.residues && same_point(self.vertex, other.vertex)
    }
}

impl Eq for PointKey<'_> {}

impl ShardHash for PointKey<'_> {
    fn shard_hash(&self) -> u64 {
        self.residues.map_or(0, mix)
    }
}

/// For each of `vertices`, the index of the first one at the same exact point (see
/// [`first_equal`]). The residues are computed in parallel chunks (each chunk shares one
/// inversion).
fn first_equal_points(vertices: &[&Vertex]) -> Vec<u32> {
    let residues: Vec<Option<[u64; 3]>> =
        vertices.par_chunks(4096).flat_map_iter(residues).collect();
    let keys: Vec<PointKey<'_>> = (residues.into_iter().zip(vertices))
        .map(|(residues, &vertex)| PointKey { residues, vertex })
        .collect();
    first_equal(&keys)
}

impl Vertices {
    /// Ids of every vertex of every polygon (flat: polygon `p`'s are at
    /// `offsets[p]..offsets[p + 1]`), numbered in order of first use in polygon order:
    /// the same on any thread count. Points are hashed and matched in parallel. A cut point
    /// is one allocation shared by the pieces of its cut (and their later pieces), so it is
    /// matched once per allocation, not once per use.
    pub(super) fn of(polys: &[&Fragment], offsets: &[usize]) -> (Vertices, Vec<u32>) {
        // Per use, an index into `distinct`: one entry per cut-point allocation and per grid
        // point, numbered in order of first use.
        let homs = (polys.iter().flat_map(|f| &f.vertices))
            .filter(|v| matches!(v, Vertex::Hom(_)))
            .count();
        let all = offsets.last().copied().unwrap_or(0);
        let mut seen: FastMap<usize, u32> = FastMap::default();
        seen.reserve(homs);
        // Grid points by value: a mesh vertex is a corner of several triangles.
        let mut grid: FastMap<[i32; 3], u32> = FastMap::default();
        grid.reserve((all - homs) / 4);
        let mut distinct: Vec<&Vertex> = Vec::new();
        let mut uses: Vec<u32> = Vec::with_capacity(all);
        for v in polys.iter().flat_map(|f| &f.vertices) {
            let next = distinct.len() as u32;
            let i = match v {
                Vertex::Int(p) => *grid.entry(*p).or_insert(next),
                Vertex::Hom(h) => *seen.entry(Arc::as_ptr(h) as usize).or_insert(next),
            };
            if i == next {
                distinct.push(v);
            }
            uses.push(i);
        }
        let first = first_equal_points(&distinct);
        // A point's first entry comes before its others, so it is numbered first.
        let mut list = Vec::new();
        let mut id_of = vec![0u32; distinct.len()];
        for (i, &f) in first.iter().enumerate() {
            if f as usize == i {
                id_of[i] = list.len() as u32;
                list.push((distinct[i].clone(), DVec3::from_array(distinct[i].approx())));
            } else {
                id_of[i] = id_of[f as usize];
            }
        }
        let ids = uses.par_iter().map(|&i| id_of[i as usize]).collect();
        (Vertices { list }, ids)
    }
}
