//! The two baselines `peel bench compile` measures Peel against, built from the core's own
//! exact predicates and cuts (no geometry written twice):
//! - the naive BSP tree of Fuchs, Kedem and Naylor: the first polygon of a list is the node,
//!   its plane splits the rest exactly, polygons in that plane join the node; every polygon
//!   list gives a node. `peel bench` also draws it: [`naive_bsp_file`] encodes it as a display
//!   tree through the same writer as Peel's output;
//! - the greedy rule with triangle output: convex peeling, else the support plane cutting the
//!   fewest fragments (no balance term). Kept as triangles, a cut triangle becomes a triangle
//!   and a quad split in two (3 triangles). Here the pieces are kept as convex polygons and
//!   counted as `vertices − 2` triangles at the end: identical while a triangle is cut once,
//!   and never more than the triangle count later (cutting a polygon adds 2 triangles;
//!   cutting its triangles separately adds 2 per triangle cut), so the baseline is, if
//!   anything, favourable to the greedy rule.

use crate::error::CompileError;
use crate::load::Mesh;
use crate::peel::{after_split, hull_planes, Known};
use crate::planes::PlaneId;
use crate::shade::Shading;
use crate::split::choose::{choose_split_with, SplitRule};
use crate::split::{Fragment, SplitResult};
use crate::tree::build::{attach, ExactNode, ExactPolygon, ExactTree, Slot, SplitPlane};
use crate::tree::input::{prepare, Input};
use crate::tree::output::to_display;
use crate::tree::{BuildOptions, DisplayTree};
use crate::write::{encode_with, WriteInput};

/// What a baseline produced.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BaselineStats {
    /// Triangles read.
    pub input_triangles: u64,
    /// Output polygons (naive BSP) or triangles (greedy-triangles).
    pub output_polygons: u64,
    /// Nodes of the tree (naive BSP: one per polygon list; greedy: convex + split nodes).
    pub nodes: u64,
    /// Split nodes (naive BSP: nodes with polygons on both sides of their plane).
    pub split_nodes: u64,
    /// Nodes on the longest root-to-leaf path.
    pub max_depth: u64,
}

fn inconsistent() -> CompileError {
    CompileError::Invariant("a cut found no intersection point".into())
}

/// The fragments of a list split by a plane: `(front, back, on, cuts)`.
type Sides = (Vec<Fragment>, Vec<Fragment>, Vec<Fragment>, u64);

/// Split `frags` by `plane`.
fn split_all(
    frags: impl IntoIterator<Item = Fragment>,
    plane: PlaneId,
    table: &crate::planes::PlaneTable,
) -> Result<Sides, CompileError> {
    let (mut front, mut back, mut on, mut cuts) = (Vec::new(), Vec::new(), Vec::new(), 0);
    for f in frags {
        match f.split(plane, table).ok_or_else(inconsistent)? {
            SplitResult::Front(f) => front.push(f),
            SplitResult::Back(f) => back.push(f),
            SplitResult::On(f) => on.push(f),
            SplitResult::Cut(a, b) => {
                cuts += 1;
                front.push(a);
                back.push(b);
            }
        }
    }
    Ok((front, back, on, cuts))
}

/// The naive BSP of `mesh`.
pub fn naive_bsp(mesh: &Mesh) -> Result<BaselineStats, CompileError> {
    match naive_walk(&prepare(mesh, None)?, u64::MAX, None)? {
        Walk::Done(stats) | Walk::OverBudget(stats) => Ok(stats),
    }
}

/// The naive BSP as a `.peel` file (see [`naive_bsp_file`]).
#[derive(Debug, Clone)]
pub struct NaiveBspFile {
    /// The BSP's figures (nodes and depth of the BSP itself, not of its encoding).
    pub stats: BaselineStats,
    /// The display tree encoding it.
    pub tree: DisplayTree,
    /// The `.peel` bytes (checked by the runtime's reader).
    pub bytes: Vec<u8>,
}

/// What [`naive_bsp_file`] made.
#[derive(Debug, Clone)]
pub enum NaiveBsp {
    /// The BSP fits the budget.
    Built(Box<NaiveBspFile>),
    /// The BSP was abandoned as soon as it held more than `limit` polygons.
    OverBudget {
        /// Polygons (placed or still to place) when it stopped.
        polygons: u64,
        /// The budget.
        limit: u64,
    },
}

/// The naive BSP of `mesh` as a display tree, encoded like Peel's own output
/// (`write::encode_with`), so the runtime draws it: two-sided polygons (no culling
/// flags), colours baked with `shading`, source ids kept when `ids` is set. The build stops
/// (without running out of memory) once the polygons exceed `max_polygons`.
///
/// Encoding: a BSP node with plane `P`, the polygons `S` lying in `P`, the + subtree `F` and
/// the − subtree `B` must be drawn `B, S, F` from an eye on the + side and `F, S, B` from the
/// − side. The runtime draws a convex node as: the polygons whose interior side the eye sees,
/// then the child, then the others; a split node as: the far side's child, then the near
/// side's. So the node becomes
/// - `Split(P, + = Convex(S, interior +, child F), − = B)` when both sides are non-empty;
/// - `Convex(S, interior +, child F)` when `B` is empty;
/// - `Convex(S, interior −, child B)` when `F` is empty (eye on +: `B`, then `S`; eye on −:
///   `S`, then `B`),
///
/// which keeps chains (a convex object gives one) one tree node per BSP node deep.
pub fn naive_bsp_file(
    mesh: &Mesh,
    max_polygons: u64,
    ids: bool,
    shading: &Shading,
) -> Result<NaiveBsp, CompileError> {
    let input = prepare(mesh, None)?;
    let mut exact = ExactTree::default();
    let stats = match naive_walk(&input, max_polygons, Some(&mut exact))? {
        Walk::Done(stats) => stats,
        Walk::OverBudget(stats) => {
            return Ok(NaiveBsp::OverBudget {
                polygons: stats.output_polygons,
                limit: max_polygons,
            })
        }
    };
    // The same output pass as Peel's own trees: exact vertex sharing, T-junctions closed,
    // large polygons cut into convex pieces.
    let tree = to_display(&exact, &input, &BuildOptions::default());
    let (colours, exterior) = crate::compile::bake(&tree, mesh, shading);
    let input = WriteInput {
        colours: &colours,
        exterior: &exterior,
        ids,
        ..WriteInput::default()
    };
    let bytes = encode_with(&tree, &input)?;
    Ok(NaiveBsp::Built(Box::new(NaiveBspFile {
        stats,
        tree,
        bytes,
    })))
}

/// How [`naive_walk`] ended (the figures so far).
enum Walk {
    Done(BaselineStats),
    OverBudget(BaselineStats),
}

/// Append `node` to `tree` and point the parent's `slot` at it.
fn emit(tree: &mut ExactTree, slot: Slot, node: ExactNode) -> u32 {
    let idx = tree.nodes.len() as u32;
    tree.nodes.push(node);
    attach(tree, slot, idx);
    idx
}

/// A convex node holding `set` (all in one plane), its interior on the + side or not.
fn emit_convex(tree: &mut ExactTree, slot: Slot, set: Vec<Fragment>, interior_front: bool) -> u32 {
    let node = ExactNode::Convex {
        first: tree.polygons.len() as u32,
        count: set.len() as u32,
        child: None,
        // Only Peel's build uses these counts (for its termination check).
        support_planes: 0,
    };
    tree.polygons
        .extend(set.into_iter().map(|frag| ExactPolygon {
            frag,
            interior_front,
        }));
    emit(tree, slot, node)
}

/// The naive BSP, with an explicit stack (the tree can be as deep as the input is
/// long); builds the exact display tree (see [`naive_bsp_file`]) when `tree` is given. Stops
/// once the polygons placed or still to place exceed `max_polygons`.
fn naive_walk(
    input: &Input,
    max_polygons: u64,
    mut tree: Option<&mut ExactTree>,
) -> Result<Walk, CompileError> {
    let mut stats = BaselineStats {
        input_triangles: input.input_triangles,
        ..BaselineStats::default()
    };
    // Fragments placed or still to place.
    let mut live = input.fragments.len() as u64;
    let mut stack = vec![(input.fragments.clone(), 1u64, Slot::Root)];
    while let Some((frags, depth, slot)) = stack.pop() {
        let mut frags = frags.into_iter();
        let Some(first) = frags.next() else {
            continue;
        };
        let plane = first.support;
        let (front, back, on, c) = split_all(frags, plane, &input.table)?;
        live += c;
        stats.nodes += 1;
        stats.output_polygons += 1 + on.len() as u64;
        stats.max_depth = stats.max_depth.max(depth);
        if !front.is_empty() && !back.is_empty() {
            stats.split_nodes += 1;
        }
        if live > max_polygons {
            stats.output_polygons = live;
            return Ok(Walk::OverBudget(stats));
        }
        let Some(tree) = tree.as_deref_mut() else {
            stack.push((back, depth + 1, slot));
            stack.push((front, depth + 1, slot));
            continue;
        };
        tree.cuts += c;
        let mut set = on;
        set.insert(0, first);
        if front.is_empty() {
            // Convex(S, interior −, child B).
            let node = emit_convex(tree, slot, set, false);
            stack.push((back, depth + 1, Slot::Child(node)));
        } else if back.is_empty() {
            // Convex(S, interior +, child F).
            let node = emit_convex(tree, slot, set, true);
            stack.push((front, depth + 1, Slot::Child(node)));
        } else {
            // Split(P, + = Convex(S, interior +, child F), − = B).
            let split = ExactNode::Split {
                plane: SplitPlane::Support(plane),
                front: None,
                back: None,
                support_planes: 0,
            };
            let split = emit(tree, slot, split);
            let node = emit_convex(tree, Slot::Front(split), set, true);
            stack.push((back, depth + 1, Slot::Back(split)));
            stack.push((front, depth + 1, Slot::Child(node)));
        }
    }
    Ok(Walk::Done(stats))
}

fn triangles(frags: &[Fragment]) -> u64 {
    frags.iter().map(|f| f.vertices.len() as u64 - 2).sum()
}

/// The greedy rule with triangle output. `candidates` and `seed` sample the planes costed per
/// split exactly as the build does (pass `usize::MAX` to cost every support plane).
pub fn greedy_triangles(
    mesh: &Mesh,
    candidates: usize,
    seed: u64,
) -> Result<BaselineStats, CompileError> {
    let input = prepare(mesh, None)?;
    let table = &input.table;
    let mut stats = BaselineStats {
        input_triangles: input.input_triangles,
        ..BaselineStats::default()
    };
    let mut stack = vec![(input.fragments, 1u64, Known::default())];
    while let Some((frags, depth, known)) = stack.pop() {
        if frags.is_empty() {
            continue;
        }
        stats.nodes += 1;
        stats.max_depth = stats.max_depth.max(depth);
        let mut planes: Vec<PlaneId> = frags.iter().map(|f| f.support).collect();
        planes.sort_unstable();
        planes.dedup();
        let hull = hull_planes(&frags, &planes, table, &known);
        if hull.sides.iter().any(Option::is_some) {
            let (e, rest): (Vec<Fragment>, Vec<Fragment>) = frags.into_iter().partition(|f| {
                hull.sides[planes.binary_search(&f.support).expect("own plane")].is_some()
            });
            stats.output_polygons += triangles(&e);
            stack.push((rest, depth + 1, Known::Inherited(hull.witnesses)));
            continue;
        }
        stats.split_nodes += 1;
        let p = choose_split_with(
            SplitRule::FEWEST_CUTS,
            &frags,
            &planes,
            table,
            candidates,
            seed,
        );
        let (mut front, mut back, on, _) = split_all(frags, p, table)?;
        // The plane's own fragments go with the smaller side, where they are on the hull
        // and are peeled next (so that side has fewer planes than this node).
        if front.len() <= back.len() {
            front.extend(on);
        } else {
            back.extend(on);
        }
        let (known_front, known_back) = after_split(hull.witnesses, table.get(p));
        stack.push((back, depth + 1, known_back));
        stack.push((front, depth + 1, known_front));
    }
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::load_obj_text;
    use glam::DVec3;

    fn cube() -> Mesh {
        let mut t = Vec::new();
        crate::tools::scenes::boxed(&mut t, DVec3::splat(-1.0), DVec3::splat(1.0));
        Mesh {
            triangles: t
                .into_iter()
                .map(|vertices| crate::load::SourceTriangle {
                    opacity: u8::MAX,
                    vertices,
                    colour: crate::load::DEFAULT_COLOUR,
                    normals: None,
                    texture: None,
                })
                .collect(),
            ..Mesh::default()
        }
    }

    fn cyclic() -> Mesh {
        let text = include_str!("../../../fixtures/cyclic_triangles.obj");
        load_obj_text(std::path::Path::new("cyclic_triangles.obj"), text).unwrap()
    }

    /// Corners of the fixture, to check by hand which plane cuts which triangle.
    fn signs(mesh: &Mesh, plane_of: usize, tri: usize) -> [f64; 3] {
        let [a, b, c] = mesh.triangles[plane_of].vertices;
        let n = (b - a).cross(c - a);
        mesh.triangles[tri].vertices.map(|p| n.dot(p - a))
    }

    #[test]
    fn a_cube_is_not_cut() {
        let naive = naive_bsp(&cube()).unwrap();
        // 6 faces: each node holds a face's first triangle and its coplanar twin; every other
        // face is behind it, so the tree is a chain of 6 nodes.
        assert_eq!(naive.output_polygons, 12);
        assert_eq!(naive.nodes, 6);
        assert_eq!(naive.max_depth, 6);
        let greedy = greedy_triangles(&cube(), 64, 0).unwrap();
        // Convex: one peel takes all 12 triangles.
        assert_eq!(greedy.output_polygons, 12);
        assert_eq!(greedy.nodes, 1);
        assert_eq!(greedy.split_nodes, 0);
    }

    /// The encoded naive BSP is the counted one: a cube is a chain of 6 convex nodes (every
    /// other face on one side of each face: no split node), the cyclic triangles need
    /// split nodes; the runtime reads both files.
    #[test]
    fn the_naive_bsp_file_encodes_the_counted_tree() {
        let shading = Shading::default();
        for (mesh, splits) in [(cube(), 0), (cyclic(), 2)] {
            let NaiveBsp::Built(f) = naive_bsp_file(&mesh, u64::MAX, true, &shading).unwrap()
            else {
                panic!("no budget, no skip");
            };
            assert_eq!(f.stats, naive_bsp(&mesh).unwrap());
            assert_eq!(f.tree.stats.convex_nodes, f.stats.nodes);
            assert_eq!(f.tree.stats.split_nodes, splits);
            assert!(f.tree.stats.output_polygons >= f.stats.output_polygons);
            let scene = peel_runtime::read::Scene::parse(&f.bytes).unwrap();
            assert_eq!(u64::from(scene.header().node_count), f.stats.nodes + splits);
        }
        let NaiveBsp::Built(cube) = naive_bsp_file(&cube(), 100, false, &shading).unwrap() else {
            panic!("12 polygons fit in 100");
        };
        assert_eq!(cube.tree.stats.max_depth, 6);
        assert!(cube.tree.polygons.iter().all(|p| p.vertices.len() == 3));
    }

    #[test]
    fn cyclic_triangles_are_cut() {
        let mesh = cyclic();
        assert_eq!(mesh.triangles.len(), 3);
        // Each triangle's plane crosses both others (corners strictly on both sides).
        for p in 0..3 {
            for t in (0..3).filter(|&t| t != p) {
                let s = signs(&mesh, p, t);
                assert!(s.iter().any(|&x| x > 0.0) && s.iter().any(|&x| x < 0.0));
            }
        }
        // Naive BSP: triangle 0 is the root, its plane cuts 1 and 2 (2 cuts, 5 polygons);
        // each side holds a piece of 1 then a piece of 2, and the piece of 1's plane cuts the
        // piece of 2 on exactly one side (1 more cut): 6 polygons in 6 nodes, depth 3.
        let naive = naive_bsp(&mesh).unwrap();
        assert_eq!(
            (naive.output_polygons, naive.nodes, naive.max_depth),
            (6, 6, 3)
        );
        // Greedy: no plane is on the hull (each is crossed by the others) and every plane
        // cuts two triangles, so one split makes 2 x 3 + 1 = 7 triangles; then every list is
        // peelable (no second split).
        let greedy = greedy_triangles(&mesh, 64, 0).unwrap();
        assert_eq!((greedy.output_polygons, greedy.split_nodes), (7, 1));
    }
}
