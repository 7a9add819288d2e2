//! The two baselines `peel bench compile` measures Peel against, built from the core's own
//! exact predicates and cuts (no geometry written twice):
//! - seed 004's naive BSP: the first polygon of a list is the node, its plane splits the rest
//!   exactly, polygons in that plane join the node; every polygon list gives a node;
//! - seed 000's greedy rule with triangle output: convex peeling, else the support plane
//!   cutting the fewest fragments (no balance term). The seed keeps triangles, so a cut
//!   triangle becomes a triangle and a quad split in two (3 triangles). Here the pieces are
//!   kept as convex polygons and counted as `vertices − 2` triangles at the end: identical
//!   while a triangle is cut once, and never more than the seed's count later (cutting a
//!   polygon adds 2 triangles; cutting its triangles separately adds 2 per triangle cut), so
//!   the baseline is, if anything, favourable to the greedy rule.

use crate::error::CompileError;
use crate::load::Mesh;
use crate::peel::hull_planes;
use crate::planes::PlaneId;
use crate::split::{choose_split_with, Fragment, SplitResult, SplitRule};
use crate::tree::input::prepare;

/// What a baseline produced.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BaselineStats {
    /// Triangles read.
    pub input_triangles: u64,
    /// Output polygons (naive BSP) or triangles (greedy-triangles).
    pub output_polygons: u64,
    /// Nodes of the tree (naive BSP: one per polygon list; greedy: convex + split nodes).
    pub nodes: u64,
    /// Split nodes (greedy only; 0 for the naive BSP, whose every node splits).
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
    frags: Vec<Fragment>,
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

/// Seed 004's naive BSP of `mesh`.
pub fn naive_bsp(mesh: &Mesh) -> Result<BaselineStats, CompileError> {
    let input = prepare(mesh)?;
    let mut stats = BaselineStats {
        input_triangles: input.input_triangles,
        ..BaselineStats::default()
    };
    let mut stack = vec![(input.fragments, 1u64)];
    while let Some((mut frags, depth)) = stack.pop() {
        if frags.is_empty() {
            continue;
        }
        let first = frags.remove(0);
        let plane = first.support;
        let (front, back, on, _) = split_all(frags, plane, &input.table)?;
        stats.nodes += 1;
        stats.output_polygons += 1 + on.len() as u64;
        stats.max_depth = stats.max_depth.max(depth);
        stack.push((back, depth + 1));
        stack.push((front, depth + 1));
    }
    Ok(stats)
}

fn triangles(frags: &[Fragment]) -> u64 {
    frags.iter().map(|f| f.vertices.len() as u64 - 2).sum()
}

/// Seed 000's greedy rule with triangle output. `candidates` and `seed` sample the planes
/// costed per split exactly as the build does (pass `usize::MAX` for the seed's exhaustive
/// search).
pub fn greedy_triangles(
    mesh: &Mesh,
    candidates: usize,
    seed: u64,
) -> Result<BaselineStats, CompileError> {
    let input = prepare(mesh)?;
    let table = &input.table;
    let mut stats = BaselineStats {
        input_triangles: input.input_triangles,
        ..BaselineStats::default()
    };
    let mut stack = vec![(input.fragments, 1u64)];
    while let Some((frags, depth)) = stack.pop() {
        if frags.is_empty() {
            continue;
        }
        stats.nodes += 1;
        stats.max_depth = stats.max_depth.max(depth);
        let mut planes: Vec<PlaneId> = frags.iter().map(|f| f.support).collect();
        planes.sort_unstable();
        planes.dedup();
        let hull = hull_planes(&frags, &planes, table);
        if hull.iter().any(Option::is_some) {
            let (e, rest): (Vec<Fragment>, Vec<Fragment>) = frags.into_iter().partition(|f| {
                hull[planes.binary_search(&f.support).expect("own plane")].is_some()
            });
            stats.output_polygons += triangles(&e);
            stack.push((rest, depth + 1));
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
        stack.push((back, depth + 1));
        stack.push((front, depth + 1));
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
        crate::scenes::boxed(&mut t, DVec3::splat(-1.0), DVec3::splat(1.0));
        Mesh {
            triangles: t
                .into_iter()
                .map(|vertices| crate::load::SourceTriangle {
                    vertices,
                    colour: crate::load::DEFAULT_COLOUR,
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
