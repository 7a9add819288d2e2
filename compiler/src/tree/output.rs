//! Exact tree -> [`DisplayTree`]: exact vertex dedupe, f64 conversion relative to the centre,
//! the output plane table (in order of first use), large polygons cut into fans, statistics.

use std::collections::HashMap;

use ethnum::I256;
use glam::DVec3;

use super::build::{ExactNode, ExactTree};
use super::input::Input;
use super::{BuildOptions, DisplayTree, TreeNode, TreePlane, TreePolygon, TreeStats};
use crate::planes::{PlaneId, Vertex};

/// Exact identity of a vertex: grid point, or homogeneous coordinates in lowest terms.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
enum Key {
    Int([i32; 3]),
    Hom([I256; 3], I256),
}

fn key(v: &Vertex) -> Key {
    match v {
        Vertex::Int(p) => Key::Int(*p),
        Vertex::Hom(h) => {
            let (xyz, w) = h.reduced();
            let small = |c: &I256| *c >= I256::from(i32::MIN) && *c <= I256::from(i32::MAX);
            if w == I256::ONE && xyz.iter().all(small) {
                Key::Int(xyz.map(|c| c.as_i128() as i32))
            } else {
                Key::Hom(xyz, w)
            }
        }
    }
}

struct Out<'a> {
    input: &'a Input,
    tree: DisplayTree,
    vertex_ids: HashMap<Key, u32>,
    plane_ids: HashMap<PlaneId, u32>,
}

impl Out<'_> {
    fn vertex(&mut self, v: &Vertex) -> u32 {
        let k = key(v);
        if let Some(&i) = self.vertex_ids.get(&k) {
            return i;
        }
        let s = self.input.quantiser.scale;
        let p = match v {
            Vertex::Int(p) => self.input.quantiser.relative(*p),
            Vertex::Hom(h) => {
                let w = h.w.as_f64();
                DVec3::new(
                    h.xyz[0].as_f64() / w,
                    h.xyz[1].as_f64() / w,
                    h.xyz[2].as_f64() / w,
                ) * s
            }
        };
        let i = self.tree.vertices.len() as u32;
        self.tree.vertices.push(p);
        self.vertex_ids.insert(k, i);
        i
    }

    fn plane(&mut self, id: PlaneId) -> u32 {
        if let Some(&i) = self.plane_ids.get(&id) {
            return i;
        }
        let p = self.input.table.get(id).plane;
        let n = DVec3::new(p.n[0] as f64, p.n[1] as f64, p.n[2] as f64);
        let len = n.length();
        let i = self.tree.planes.len() as u32;
        self.tree.planes.push(TreePlane {
            normal: n / len,
            offset: p.d as f64 / len * self.input.quantiser.scale,
        });
        self.plane_ids.insert(id, i);
        i
    }
}

/// Cut a convex polygon of `n` vertices into fans of at most `max` (>= 3) vertices sharing
/// vertex 0: index lists into the polygon.
pub(crate) fn fan_pieces(n: usize, max: usize) -> Vec<Vec<usize>> {
    let max = max.max(3);
    if n <= max {
        return vec![(0..n).collect()];
    }
    let mut pieces = Vec::new();
    let mut s = 1;
    while s + 1 < n {
        let e = (s + max - 2).min(n - 1);
        let mut piece = vec![0];
        piece.extend(s..=e);
        pieces.push(piece);
        s = e;
    }
    pieces
}

pub(crate) fn to_display(exact: &ExactTree, input: &Input, options: &BuildOptions) -> DisplayTree {
    let mut out = Out {
        input,
        tree: DisplayTree {
            centre: input.quantiser.offset,
            ..DisplayTree::default()
        },
        vertex_ids: HashMap::new(),
        plane_ids: HashMap::new(),
    };
    let mut stats = TreeStats {
        input_triangles: input.input_triangles,
        degenerate_dropped: input.degenerate_dropped,
        cuts: exact.cuts,
        ..TreeStats::default()
    };
    for node in &exact.nodes {
        let node = match *node {
            ExactNode::Convex {
                first,
                count,
                child,
                support_planes,
            } => {
                stats.convex_nodes += 1;
                let start = out.tree.polygons.len() as u32;
                for poly in &exact.polygons[first as usize..(first + count) as usize] {
                    let f = &poly.frag;
                    let plane = out.plane(f.support);
                    for piece in fan_pieces(f.vertices.len(), options.max_polygon_vertices) {
                        let vertices = piece.iter().map(|&i| out.vertex(&f.vertices[i])).collect();
                        out.tree.polygons.push(TreePolygon {
                            plane,
                            flipped: f.flipped,
                            interior_front: poly.interior_front,
                            vertices,
                            source: f.source,
                        });
                    }
                }
                let polygon_count = out.tree.polygons.len() as u32 - start;
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
                    plane: out.plane(plane),
                    front,
                    back,
                    support_planes,
                }
            }
        };
        out.tree.nodes.push(node);
    }
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
