//! Numbering and statistics: planes, vertices and polygons get their output indices in order
//! of first use, node by node, so the output is the same on any thread count; the counters
//! reported by `peel compile` are taken on the way.

use glam::DVec3;
use rayon::iter::Either;
use rayon::prelude::*;

use super::convex_split::Pieces;
use super::vertices::Vertices;
use super::watertight::Boundary;
use crate::planes::{Plane, PlaneId};
use crate::tree::build::{ExactNode, ExactTree, SplitPlane};
use crate::tree::input::Input;
use crate::tree::{DisplayTree, TreeNode, TreePlane, TreePolygon, TreeStats};

/// The tree being numbered, with the output index of each input it has numbered so far.
struct Out<'a> {
    input: &'a Input,
    tree: DisplayTree,
    /// Output index of each [`Vertices`] id, in order of first use.
    vertex_ids: Vec<Option<u32>>,
    /// Output index of each table plane, in order of first use.
    plane_ids: Vec<Option<u32>>,
    /// Output index of each free split plane (not in the table), in order of first use.
    free_ids: crate::hash::FastMap<Plane, u32>,
}

impl Out<'_> {
    fn vertex(&mut self, vertices: &Vertices, id: u32) -> u32 {
        if let Some(i) = self.vertex_ids[id as usize] {
            return i;
        }
        // The approximation is the exact point rounded once per coordinate (see
        // `Vertex::approx`), in grid units.
        let p = vertices.list[id as usize].1 * self.input.quantiser.scale;
        let i = self.tree.vertices.len() as u32;
        self.tree.vertices.push(p);
        self.vertex_ids[id as usize] = Some(i);
        i
    }

    fn plane(&mut self, id: PlaneId) -> u32 {
        if let Some(i) = self.plane_ids[id as usize] {
            return i;
        }
        let i = self.push_plane(self.input.table.get(id).plane);
        self.plane_ids[id as usize] = Some(i);
        i
    }

    fn split_plane(&mut self, plane: SplitPlane) -> u32 {
        match plane {
            SplitPlane::Support(id) | SplitPlane::Edge(id) => self.plane(id),
            SplitPlane::Free(p) => {
                if let Some(&i) = self.free_ids.get(&p) {
                    return i;
                }
                let i = self.push_plane(p);
                self.free_ids.insert(p, i);
                i
            }
        }
    }

    fn push_plane(&mut self, p: Plane) -> u32 {
        let n = DVec3::new(p.n[0] as f64, p.n[1] as f64, p.n[2] as f64);
        let len = n.length();
        let i = self.tree.planes.len() as u32;
        self.tree.planes.push(TreePlane {
            normal: n / len,
            offset: p.d as f64 / len * self.input.quantiser.scale,
        });
        i
    }
}

/// The display tree of `exact`: its polygons' `boundaries` (as [`Vertices`] ids), each cut
/// into `pieces` when it has too many vertices.
pub(super) fn number(
    exact: &ExactTree,
    input: &Input,
    vertices: &Vertices,
    boundaries: &[Boundary],
    pieces: &[Option<Pieces>],
) -> DisplayTree {
    let mut out = Out {
        input,
        tree: DisplayTree {
            centre: input.quantiser.offset,
            ..DisplayTree::default()
        },
        vertex_ids: vec![None; vertices.list.len()],
        plane_ids: vec![None; input.table.len()],
        free_ids: Default::default(),
    };
    let mut stats = TreeStats {
        input_triangles: input.input_triangles,
        degenerate_dropped: input.degenerate_dropped,
        cuts: exact.cuts,
        ..TreeStats::default()
    };
    // Planes and vertices are numbered in order of first use, node by node (sequential and
    // cheap); the polygons are then built in parallel, in that order.
    let mut order: Vec<(usize, u32)> = Vec::with_capacity(exact.polygons.len());
    let mut emitted = 0u32;
    for node in &exact.nodes {
        let node = match *node {
            ExactNode::Convex {
                first,
                count,
                child,
                support_planes,
            } => {
                stats.convex_nodes += 1;
                let mut polygon_count = 0;
                for i in first as usize..(first + count) as usize {
                    let plane = out.plane(exact.polygons[i].frag.support);
                    let boundary = &boundaries[i];
                    match &pieces[i] {
                        None => {
                            for b in boundary {
                                out.vertex(vertices, b.0);
                            }
                            polygon_count += 1;
                        }
                        Some(pieces) => {
                            for piece in pieces {
                                for &k in piece {
                                    out.vertex(vertices, boundary[k].0);
                                }
                                polygon_count += 1;
                            }
                        }
                    }
                    order.push((i, plane));
                }
                let start = emitted;
                emitted += polygon_count;
                TreeNode::Convex {
                    first_polygon: start,
                    polygon_count,
                    child,
                    support_planes,
                }
            }
            ExactNode::Split {
                plane,
                front,
                back,
                support_planes,
            } => {
                stats.split_nodes += 1;
                TreeNode::Split {
                    plane: out.split_plane(plane),
                    front,
                    back,
                    support_planes,
                }
            }
        };
        out.tree.nodes.push(node);
    }
    // Every vertex was numbered above (`MAX` would fail the writer's checks).
    let vertex_ids = &out.vertex_ids;
    let id = move |v: u32| vertex_ids[v as usize].unwrap_or(u32::MAX);
    out.tree.polygons = order
        .par_iter()
        .flat_map_iter(|&(i, plane)| {
            let (poly, boundary) = (&exact.polygons[i], &boundaries[i]);
            let lists = match &pieces[i] {
                None => Either::Left(std::iter::once(
                    boundary.iter().map(|b| id(b.0)).collect::<Vec<u32>>(),
                )),
                Some(pieces) => Either::Right(
                    (pieces.iter())
                        .map(move |piece| piece.iter().map(|&k| id(boundary[k].0)).collect()),
                ),
            };
            lists.map(move |vertices| TreePolygon {
                plane,
                flipped: poly.frag.flipped,
                interior_front: poly.interior_front,
                vertices,
                source: poly.frag.source,
                shadowed: poly.frag.shadowed,
            })
        })
        .collect();
    // Children come after their parents: depths from the last node back.
    let mut depth = vec![0u64; out.tree.nodes.len()];
    for i in (0..depth.len()).rev() {
        let d = |c: Option<u32>| c.map_or(0, |c| depth[c as usize]);
        depth[i] = 1 + match out.tree.nodes[i] {
            TreeNode::Convex { child, .. } => d(child),
            TreeNode::Split { front, back, .. } => d(front).max(d(back)),
        };
    }
    stats.max_depth = depth.first().copied().unwrap_or(0);
    stats.output_polygons = out.tree.polygons.len() as u64;
    stats.planes = out.tree.planes.len() as u64;
    out.tree.stats = stats;
    out.tree
}
