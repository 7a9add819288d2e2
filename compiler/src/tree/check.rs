//! Invariant checks of the build, independent of the code they check: exact ones on the
//! exact tree (structure, support-plane counts, sides, convexity, area partition), and a
//! brute-force f64 search for T-junctions in the output. [`verify`] runs the exact ones for the
//! stress suite, which cannot see the crate's tests.

use std::collections::BTreeSet;

use ethnum::I256;

use super::build::{build_exact, ExactNode, ExactTree, SplitPlane};
use super::input::{prepare, Input};
use super::output::to_display;
use super::{BuildOptions, DisplayTree};
use crate::planes::{side_of_hom_exact, HomPoint, PlaneEntry, PlaneId, PlaneTable, Side};
use crate::split::{Fragment, SplitResult};

type Check = Result<(), String>;

/// Build `mesh` and check the exact tree against every invariant of the build (structure,
/// strictly decreasing support-plane counts, sides of every split, convex nodes convex, exact
/// area partition with `samples` rational points per source triangle); then convert it as
/// [`build`](fn@super::build) does. For the stress suite: slow on large inputs.
#[doc(hidden)]
pub fn verify(
    mesh: &crate::load::Mesh,
    options: &BuildOptions,
    samples: usize,
) -> Result<DisplayTree, String> {
    let input = prepare(mesh, options.shadows).map_err(|e| e.to_string())?;
    let exact = build_exact(&input, options, &|_| {}).map_err(|e| e.to_string())?;
    structure(&exact)?;
    support_planes(&exact, &input.table)?;
    fragments(&exact, &input)?;
    ancestor_sides(&exact, &input)?;
    convex_sets(&exact, &input)?;
    area_partition(&exact, &input, samples, 7)?;
    Ok(to_display(&exact, &input, options))
}

fn children(n: &ExactNode) -> Vec<u32> {
    match *n {
        ExactNode::Convex { child, .. } => child.into_iter().collect(),
        ExactNode::Split { front, back, .. } => front.into_iter().chain(back).collect(),
    }
}

/// Every node reachable exactly once, in pre-order (a split's children in either order),
/// children after parents.
pub(crate) fn structure(t: &ExactTree) -> Check {
    if t.nodes.is_empty() {
        return if t.polygons.is_empty() {
            Ok(())
        } else {
            Err("polygons without nodes".into())
        };
    }
    let mut order = Vec::new();
    let mut stack = vec![0u32];
    while let Some(i) = stack.pop() {
        order.push(i);
        let mut c = children(&t.nodes[i as usize]);
        c.sort_unstable_by(|a, b| b.cmp(a));
        stack.extend(c);
    }
    if order != (0..t.nodes.len() as u32).collect::<Vec<_>>() {
        return Err("nodes are not in pre-order".into());
    }
    let mut next = 0;
    for n in &t.nodes {
        if let ExactNode::Convex { first, count, .. } = *n {
            if first != next || count == 0 {
                return Err(format!(
                    "polygon range {first}+{count}, expected start {next}"
                ));
            }
            next += count;
        }
    }
    if next as usize != t.polygons.len() {
        return Err("polygons not owned by convex nodes".into());
    }
    Ok(())
}

/// The fragments of each node's subtree (= the list the node was built from).
fn subtree_polys(t: &ExactTree) -> Vec<Vec<u32>> {
    let mut sets: Vec<Vec<u32>> = vec![Vec::new(); t.nodes.len()];
    for i in (0..t.nodes.len()).rev() {
        let mut s: Vec<u32> = Vec::new();
        if let ExactNode::Convex { first, count, .. } = t.nodes[i] {
            s.extend(first..first + count);
        }
        for c in children(&t.nodes[i]) {
            s.extend(sets[c as usize].iter().copied());
        }
        sets[i] = s;
    }
    sets
}

/// Recorded support-plane counts are right, and obey the termination argument.
pub(crate) fn support_planes(t: &ExactTree, table: &PlaneTable) -> Check {
    let sets = subtree_polys(t);
    let count = |i: usize| {
        sets[i]
            .iter()
            .map(|&p| t.polygons[p as usize].frag.support)
            .collect::<BTreeSet<_>>()
            .len() as u32
    };
    let recorded = |i: u32| match t.nodes[i as usize] {
        ExactNode::Convex { support_planes, .. } | ExactNode::Split { support_planes, .. } => {
            support_planes
        }
    };
    let has_plane = |i: u32, p: PlaneId| {
        sets[i as usize]
            .iter()
            .any(|&q| t.polygons[q as usize].frag.support == p)
    };
    for (i, n) in t.nodes.iter().enumerate() {
        let k = recorded(i as u32);
        if k != count(i) {
            return Err(format!(
                "node {i} records {k} support planes, has {}",
                count(i)
            ));
        }
        match *n {
            ExactNode::Convex { child: Some(c), .. } if recorded(c) >= k => {
                return Err(format!(
                    "convex node {i} -> child {c}: {} >= {k}",
                    recorded(c)
                ));
            }
            ExactNode::Split {
                plane: SplitPlane::Free(plane),
                front,
                back,
                ..
            } => {
                // A free plane is no support plane of the list and cuts nothing: the children
                // have no more support planes (and fewer fragments, which the build checks).
                let in_plane = sets[i]
                    .iter()
                    .any(|&q| table.get(t.polygons[q as usize].frag.support).plane == plane);
                if in_plane {
                    return Err(format!("free split {i}: a polygon lies in its plane"));
                }
                for c in [front, back].into_iter().flatten() {
                    let kc = recorded(c);
                    if kc > k {
                        return Err(format!("free split {i} -> child {c} grows: {kc} > {k}"));
                    }
                }
            }
            ExactNode::Split {
                plane: SplitPlane::Edge(plane),
                front,
                back,
                ..
            } => {
                // An edge plane is no support plane of the list: the children have no more
                // support planes (and fewer fragments, which the build checks).
                if has_plane(i as u32, plane) {
                    return Err(format!("edge split {i}: its plane is a support plane"));
                }
                for c in [front, back].into_iter().flatten() {
                    let kc = recorded(c);
                    if kc > k {
                        return Err(format!("edge split {i} -> child {c} grows: {kc} > {k}"));
                    }
                }
            }
            ExactNode::Split {
                plane: SplitPlane::Support(plane),
                front,
                back,
                ..
            } => {
                for c in [front, back].into_iter().flatten() {
                    let kc = recorded(c);
                    if kc > k {
                        return Err(format!("split {i} -> child {c} grows: {kc} > {k}"));
                    }
                    if has_plane(c, plane) {
                        // The child holding P is a convex node of P's fragments only.
                        let ExactNode::Convex {
                            first,
                            count,
                            child,
                            ..
                        } = t.nodes[c as usize]
                        else {
                            return Err(format!("split {i}: child {c} holding P is not convex"));
                        };
                        let polys = &t.polygons[first as usize..(first + count) as usize];
                        if polys.iter().any(|p| p.frag.support != plane) {
                            return Err(format!("split {i}: child {c} holds more than P"));
                        }
                        if let Some(g) = child {
                            if recorded(g) >= k {
                                return Err(format!("split {i}: grandchild {g} does not drop"));
                            }
                        }
                    } else if kc >= k {
                        return Err(format!("split {i} -> child {c} without P: {kc} >= {k}"));
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// Each fragment is a consistent convex polygon: every vertex on its support plane and on its
/// two edges' planes, every vertex on the inside of every edge.
pub(crate) fn fragments(t: &ExactTree, input: &Input) -> Check {
    for (i, p) in t.polygons.iter().enumerate() {
        let f = &p.frag;
        let n = f.vertices.len();
        if n < 3 || f.edges.len() != n {
            return Err(format!(
                "polygon {i}: {n} vertices, {} edges",
                f.edges.len()
            ));
        }
        let support = input.table.get(f.support);
        for (j, v) in f.vertices.iter().enumerate() {
            if v.side(support) != Side::On {
                return Err(format!("polygon {i}: vertex {j} off its support plane"));
            }
            for (k, e) in f.edges.iter().enumerate() {
                let s = v.side(input.table.get(e.plane));
                let on_edge = k == j || (k + 1) % n == j;
                if on_edge && s != Side::On {
                    return Err(format!("polygon {i}: vertex {j} not on its edge {k}"));
                }
                if !on_edge && s != e.inside {
                    return Err(format!(
                        "polygon {i}: vertex {j} outside edge {k} (not strictly convex)"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Every fragment lies on the correct closed side of every ancestor split plane.
pub(crate) fn ancestor_sides(t: &ExactTree, input: &Input) -> Check {
    if t.nodes.is_empty() {
        return Ok(());
    }
    let mut stack: Vec<(u32, Vec<(PlaneEntry, Side)>)> = vec![(0, Vec::new())];
    while let Some((i, anc)) = stack.pop() {
        match t.nodes[i as usize] {
            ExactNode::Convex {
                first,
                count,
                child,
                ..
            } => {
                for p in &t.polygons[first as usize..(first + count) as usize] {
                    for (e, side) in &anc {
                        if p.frag.vertices.iter().any(|v| v.side(e) == side.opposite()) {
                            return Err(format!(
                                "node {i}: a polygon on the wrong side of plane {:?}",
                                e.plane
                            ));
                        }
                    }
                }
                if let Some(c) = child {
                    stack.push((c, anc));
                }
            }
            ExactNode::Split {
                plane, front, back, ..
            } => {
                for (c, side) in [(front, Side::Front), (back, Side::Back)] {
                    if let Some(c) = c {
                        let mut a = anc.clone();
                        a.push((plane.entry(&input.table), side));
                        stack.push((c, a));
                    }
                }
            }
        }
    }
    Ok(())
}

/// Each convex node's polygons are exactly a convex set, and everything under the node lies
/// on the interior side of each of them, as `interior_front` says.
pub(crate) fn convex_sets(t: &ExactTree, input: &Input) -> Check {
    let sets = subtree_polys(t);
    for (i, n) in t.nodes.iter().enumerate() {
        let ExactNode::Convex { first, count, .. } = *n else {
            continue;
        };
        for q in &t.polygons[first as usize..(first + count) as usize] {
            let e = input.table.get(q.frag.support);
            let outside = if q.interior_front {
                Side::Back
            } else {
                Side::Front
            };
            for &o in &sets[i] {
                if t.polygons[o as usize]
                    .frag
                    .vertices
                    .iter()
                    .any(|v| v.side(e) == outside)
                {
                    return Err(format!("convex node {i}: polygon {o} outside the set"));
                }
            }
        }
    }
    Ok(())
}

/// `Some(true)` strictly inside, `Some(false)` strictly outside, `None` on the boundary.
fn contains(f: &Fragment, p: &HomPoint, input: &Input) -> Option<bool> {
    let mut boundary = false;
    for e in &f.edges {
        let s = side_of_hom_exact(p, &input.table.get(e.plane).plane);
        if s == Side::On {
            boundary = true;
        } else if s != e.inside {
            return Some(false);
        }
    }
    if boundary {
        None
    } else {
        Some(true)
    }
}

/// The fragments of each source triangle cover it exactly once: exact rational sample points
/// `a + (i (b − a) + j (c − a)) / N` strictly inside the triangle each lie in exactly one
/// fragment (points on a fragment boundary are skipped). Returns the number of points tested.
pub(crate) fn area_partition(
    t: &ExactTree,
    input: &Input,
    samples: usize,
    seed: u64,
) -> Result<usize, String> {
    let mut by_source: Vec<Vec<&Fragment>> = vec![Vec::new(); input.input_triangles as usize];
    for p in &t.polygons {
        by_source[p.frag.source as usize].push(&p.frag);
    }
    let mut rng = crate::random::SplitMix::new(seed);
    let mut tested = 0;
    const N: i64 = 1_000_003;
    for f in &input.fragments {
        let frags = &by_source[f.source as usize];
        if frags.is_empty() {
            return Err(format!("source {} has no output fragment", f.source));
        }
        let q: Vec<[i64; 3]> = f
            .vertices
            .iter()
            .map(|v| match v {
                crate::planes::Vertex::Int(p) => p.map(i64::from),
                crate::planes::Vertex::Hom(_) => unreachable!("input corners are grid points"),
            })
            .collect();
        for _ in 0..samples {
            let i = 1 + rng.below(N as usize - 2) as i64;
            let j = 1 + rng.below((N - i - 1) as usize) as i64;
            if i + j >= N {
                continue;
            }
            let xyz: [I256; 3] = std::array::from_fn(|k| {
                I256::from(N * q[0][k])
                    + I256::from(i * (q[1][k] - q[0][k]))
                    + I256::from(j * (q[2][k] - q[0][k]))
            });
            let p = HomPoint::new(xyz, I256::from(N)).unwrap();
            let mut inside = 0;
            let mut on_boundary = false;
            for g in frags {
                match contains(g, &p, input) {
                    Some(true) => inside += 1,
                    Some(false) => {}
                    None => on_boundary = true,
                }
            }
            if on_boundary {
                continue;
            }
            if inside != 1 {
                return Err(format!(
                    "source {}: a point lies in {inside} fragments",
                    f.source
                ));
            }
            tested += 1;
        }
    }
    Ok(tested)
}

/// All of the above.
#[cfg(test)]
pub(crate) fn all(t: &ExactTree, input: &Input) -> Check {
    structure(t)?;
    support_planes(t, &input.table)?;
    fragments(t, input)?;
    ancestor_sides(t, input)?;
    convex_sets(t, input)?;
    area_partition(t, input, 16, 7)?;
    Ok(())
}

/// Fragments of one split, re-checked: both pieces exactly on their sides.
#[allow(dead_code)]
pub(crate) fn split_sides(r: &SplitResult, plane: PlaneId, input: &Input) -> Check {
    let e = input.table.get(plane);
    let bad = |f: &Fragment, s: Side| f.vertices.iter().any(|v| v.side(e) == s);
    match r {
        SplitResult::Front(f) if bad(f, Side::Back) => Err("front has a back vertex".into()),
        SplitResult::Back(f) if bad(f, Side::Front) => Err("back has a front vertex".into()),
        SplitResult::Cut(f, b) if bad(f, Side::Back) || bad(b, Side::Front) => {
            Err("a piece crosses".into())
        }
        _ => Ok(()),
    }
}

/// Polygon edges with another polygon's vertex inside them (closer than `off` to the edge's
/// line, farther than `end` from both ends, and with one of its own edges along that line:
/// a transversal touch opens no crack), found by brute force in f64: an independent check
/// of the watertight pass. Exactly collinear vertices round to within ~1e-16 of the line; `off`
/// must stay far below the distance of the nearest distinct non-collinear vertex.
#[cfg(test)]
pub(crate) fn t_junctions(polys: &[Vec<glam::DVec3>], off: f64, end: f64) -> usize {
    let mut found = 0;
    for (p, poly) in polys.iter().enumerate() {
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let d = b - a;
            let len2 = d.length_squared();
            if len2 == 0.0 {
                continue;
            }
            let near_line = |w: glam::DVec3| {
                let t = (w - a).dot(d) / len2;
                (a + d * t - w).length() < off
            };
            for (q, other) in polys.iter().enumerate() {
                if q == p {
                    continue;
                }
                for (j, &w) in other.iter().enumerate() {
                    let t = (w - a).dot(d) / len2;
                    let away = (w - a).length() > end && (w - b).length() > end;
                    // Only a vertex of an edge along the same line can open a crack.
                    let m = other.len();
                    let along = near_line(other[(j + 1) % m]) || near_line(other[(j + m - 1) % m]);
                    if t > 0.0 && t < 1.0 && away && near_line(w) && along && !poly.contains(&w) {
                        found += 1;
                    }
                }
            }
        }
    }
    found
}
