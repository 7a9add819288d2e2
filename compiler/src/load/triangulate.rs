//! Polygon faces -> triangles, in the polygon's own plane.
//!
//! tobj's fan triangulation is wrong for concave faces, so a face with more than three corners
//! goes through `spade`'s constrained Delaunay triangulation (CDT):
//!
//! 1. consecutive corners at the same 3D position are merged (they only add zero-area
//!    triangles);
//! 2. the polygon is projected onto the plane of its Newell normal by dropping the normal's
//!    dominant axis;
//! 3. the boundary edges are inserted as constraint edges and only the triangles inside the
//!    polygon (odd crossing parity from the outside) are kept;
//! 4. each triangle is oriented with the winding of the face.
//!
//! Output order (independent of spade's internal face order): every triangle is written as
//! three corner indices of the face, starting at its smallest index and keeping the face's
//! winding; the triangles are then sorted by these index triples (smallest corner, then the
//! next corner in winding order, then the last).
//!
//! A polygon that is not simple (two corners at the same projected point, crossing or touching
//! edges) or that has zero area cannot be triangulated this way: [`triangulate_polygon`]
//! reports why, and the caller falls back to [`fan`], which is already in the documented order.

use glam::{DVec2, DVec3};
use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

/// Why a polygon could not be triangulated in its plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NotSimple {
    /// All corners are collinear or coincident: the polygon has no area.
    ZeroArea,
    /// Two non-consecutive corners project to the same point (a repeated vertex).
    RepeatedVertex,
    /// Two edges cross or touch, or a corner lies on another edge.
    SelfIntersecting,
    /// A coordinate is outside the range spade accepts.
    OutOfRange,
}

impl std::fmt::Display for NotSimple {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            NotSimple::ZeroArea => "it has zero area",
            NotSimple::RepeatedVertex => "it visits the same point twice",
            NotSimple::SelfIntersecting => "its edges cross or touch",
            NotSimple::OutOfRange => "its coordinates are out of the triangulator's range",
        })
    }
}

/// The fan from corner 0: `[0, i, i + 1]` for `i` in `1..n - 1` (already in the documented
/// order). Used for triangles and as the fallback for polygons that are not simple.
pub fn fan(n: usize) -> Vec<[usize; 3]> {
    (1..n.saturating_sub(1)).map(|i| [0, i, i + 1]).collect()
}

/// Triangulates a polygon face given its corners in file order.
///
/// Returns triangles as corner indices into `corners`, oriented like the face and in the
/// documented order (see the module docs). Merged consecutive duplicates mean a face may yield
/// fewer than `n - 2` triangles; every returned triangle has a non-zero projected area.
pub fn triangulate_polygon(corners: &[DVec3]) -> Result<Vec<[usize; 3]>, NotSimple> {
    if corners.len() == 3 {
        return Ok(fan(3));
    }
    let kept = merge_consecutive_duplicates(corners);
    if kept.len() < 3 {
        return Err(NotSimple::ZeroArea);
    }
    let points: Vec<DVec3> = kept.iter().map(|&i| corners[i]).collect();
    let normal = plane_normal(&points).ok_or(NotSimple::ZeroArea)?;
    let flat = project(&points, normal);
    let local = cdt_inside(&flat)?;
    let area2 = shoelace2(&flat);
    if area2 == 0.0 || !area2.is_finite() {
        return Err(NotSimple::ZeroArea);
    }

    let mut triangles: Vec<[usize; 3]> = local
        .into_iter()
        .map(|[a, b, c]| {
            // Give each triangle the polygon's orientation in the projection plane.
            let t = if (orient(flat[a], flat[b], flat[c]) > 0.0) == (area2 > 0.0) {
                [kept[a], kept[b], kept[c]]
            } else {
                [kept[a], kept[c], kept[b]]
            };
            canonical(t)
        })
        .collect();
    triangles.sort_unstable();
    Ok(triangles)
}

/// Rotates a triangle so its smallest corner index comes first (the winding is unchanged).
fn canonical(t: [usize; 3]) -> [usize; 3] {
    let m = (0..3).min_by_key(|&i| t[i]).unwrap_or(0);
    [t[m], t[(m + 1) % 3], t[(m + 2) % 3]]
}

/// Indices of the corners left after merging runs of equal consecutive corners (cyclically).
fn merge_consecutive_duplicates(corners: &[DVec3]) -> Vec<usize> {
    let mut kept: Vec<usize> = Vec::with_capacity(corners.len());
    for (i, c) in corners.iter().enumerate() {
        match kept.last() {
            Some(&j) if corners[j] == *c => {}
            _ => kept.push(i),
        }
    }
    while kept.len() > 1 && corners[kept[0]] == corners[kept[kept.len() - 1]] {
        kept.pop();
    }
    kept
}

/// The normal of the plane to project onto: Newell's normal (robust for non-planar and concave
/// polygons), or for a self-intersecting polygon whose Newell normal cancels out (a symmetric
/// bow tie), the largest cross product from the first corner. `None` if all corners are
/// collinear (no plane at all).
fn plane_normal(points: &[DVec3]) -> Option<DVec3> {
    let n = points.len();
    let mut newell = DVec3::ZERO;
    for i in 0..n {
        let (p, q) = (points[i], points[(i + 1) % n]);
        newell.x += (p.y - q.y) * (p.z + q.z);
        newell.y += (p.z - q.z) * (p.x + q.x);
        newell.z += (p.x - q.x) * (p.y + q.y);
    }
    if newell.abs().max_element() > 0.0 {
        return Some(newell);
    }
    let p0 = points[0];
    let far = points.iter().copied().max_by(|a, b| {
        (*a - p0)
            .length_squared()
            .total_cmp(&(*b - p0).length_squared())
    })?;
    points
        .iter()
        .map(|&p| (far - p0).cross(p - p0))
        .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))
        .filter(|c| c.abs().max_element() > 0.0)
}

/// Drops the dominant axis of `normal` (which must not be zero).
fn project(points: &[DVec3], normal: DVec3) -> Vec<DVec2> {
    let a = normal.abs();
    let keep: fn(DVec3) -> DVec2 = if a.x >= a.y && a.x >= a.z {
        |p| DVec2::new(p.y, p.z)
    } else if a.y >= a.z {
        |p| DVec2::new(p.z, p.x)
    } else {
        |p| DVec2::new(p.x, p.y)
    };
    points.iter().map(|&p| keep(p)).collect()
}

/// Twice the signed area (positive = counter-clockwise).
fn shoelace2(points: &[DVec2]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| points[i].perp_dot(points[(i + 1) % n]))
        .sum()
}

fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Constrained Delaunay triangulation of a simple polygon; returns the inside triangles as
/// indices into `flat` (in spade's orientation; the caller fixes winding and order).
fn cdt_inside(flat: &[DVec2]) -> Result<Vec<[usize; 3]>, NotSimple> {
    let n = flat.len();
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::new();
    let mut handles: Vec<FixedVertexHandle> = Vec::with_capacity(n);
    for p in flat {
        let h = cdt
            .insert(Point2::new(p.x, p.y))
            .map_err(|_| NotSimple::OutOfRange)?;
        handles.push(h);
    }
    if cdt.num_vertices() != n {
        return Err(NotSimple::RepeatedVertex);
    }
    let mut corner_of = vec![usize::MAX; n];
    for (i, h) in handles.iter().enumerate() {
        corner_of[h.index()] = i;
    }
    for i in 0..n {
        let (from, to) = (handles[i], handles[(i + 1) % n]);
        // `try_add_constraint` refuses crossings; a corner lying on the edge splits it, which
        // `exists_constraint` then reveals. Either way the polygon is not simple.
        if cdt.exists_constraint(from, to)
            || cdt.try_add_constraint(from, to).is_empty()
            || !cdt.exists_constraint(from, to)
        {
            return Err(NotSimple::SelfIntersecting);
        }
    }

    // Flood fill from the outer face; crossing a constraint (boundary) edge flips inside/outside.
    let mut inside: Vec<Option<bool>> = vec![None; cdt.num_all_faces()];
    let outer = cdt.outer_face();
    inside[outer.fix().index()] = Some(false);
    let mut stack: Vec<(spade::handles::FixedDirectedEdgeHandle, bool)> = cdt
        .directed_edges()
        .filter(|e| e.face().is_outer())
        .map(|e| (e.fix(), false))
        .collect();
    while let Some((edge, side)) = stack.pop() {
        let e = cdt.directed_edge(edge);
        let next = e.rev().face();
        let next_side = side ^ e.is_constraint_edge();
        let slot = &mut inside[next.fix().index()];
        if slot.is_some() {
            continue;
        }
        *slot = Some(next_side);
        if let Some(face) = next.as_inner() {
            for adj in face.adjacent_edges() {
                stack.push((adj.fix(), next_side));
            }
        }
    }

    let triangles: Vec<[usize; 3]> = cdt
        .inner_faces()
        .filter(|f| inside[f.fix().index()] == Some(true))
        .map(|f| f.vertices().map(|v| corner_of[v.fix().index()]))
        .collect();
    if triangles.len() != n - 2 {
        // A simple polygon always has exactly n - 2 triangles; anything else is a defect.
        return Err(NotSimple::SelfIntersecting);
    }
    Ok(triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(points: &[(f64, f64)]) -> Vec<DVec3> {
        points.iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect()
    }

    fn area(p: &[DVec3], t: [usize; 3]) -> f64 {
        (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).z / 2.0
    }

    /// Point strictly inside the polygon (even-odd rule), for sampling triangle centroids.
    fn inside_polygon(p: &[DVec3], q: DVec2) -> bool {
        let mut inside = false;
        for i in 0..p.len() {
            let (a, b) = (p[i].truncate(), p[(i + 1) % p.len()].truncate());
            if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y) {
                inside = !inside;
            }
        }
        inside
    }

    fn check_exact_cover(p: &[DVec3], tris: &[[usize; 3]], polygon_area: f64) {
        let total: f64 = tris.iter().map(|&t| area(p, t)).sum();
        assert_eq!(
            total, polygon_area,
            "triangles must cover the polygon exactly"
        );
        for &t in tris {
            assert!(area(p, t) > 0.0, "triangle {t:?} has the wrong winding");
            let c = (p[t[0]] + p[t[1]] + p[t[2]]).truncate() / 3.0;
            assert!(
                inside_polygon(p, c),
                "triangle {t:?} lies outside the polygon"
            );
        }
        let mut sorted = tris.to_vec();
        sorted.sort();
        assert_eq!(sorted, tris, "triangles must come sorted");
        for t in tris {
            assert!(
                t[0] < t[1] && t[0] < t[2],
                "{t:?} must start at its smallest corner"
            );
        }
    }

    #[test]
    fn l_shape_counter_clockwise() {
        // Concave at corner 3: a fan from corner 0 would put a triangle outside.
        let p = flat(&[(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]);
        let tris = triangulate_polygon(&p).unwrap();
        assert_eq!(tris.len(), 4);
        check_exact_cover(&p, &tris, 3.0);
    }

    #[test]
    fn star_clockwise_keeps_clockwise_winding() {
        // A five-pointed star given clockwise: every triangle must stay clockwise.
        let mut pts = Vec::new();
        for k in 0..10 {
            let r = if k % 2 == 0 { 4.0 } else { 1.5 };
            let a = -(k as f64) * std::f64::consts::PI / 5.0;
            // Round to a grid so the area sum is exact in f64.
            pts.push(((r * a.cos() * 64.0).round(), (r * a.sin() * 64.0).round()));
        }
        let p = flat(&pts);
        let tris = triangulate_polygon(&p).unwrap();
        assert_eq!(tris.len(), 8);
        let mirrored: Vec<DVec3> = p.iter().map(|v| DVec3::new(v.x, -v.y, 0.0)).collect();
        let polygon_area = -shoelace2(&project(&p, DVec3::Z)) / 2.0;
        assert!(polygon_area > 0.0);
        for &t in &tris {
            assert!(
                area(&p, t) < 0.0,
                "triangle {t:?} must be clockwise like the face"
            );
        }
        // Mirroring y makes the star counter-clockwise; the same triangles must then cover it.
        check_exact_cover(&mirrored, &tris, polygon_area);
    }

    #[test]
    fn quad_splits_in_two_in_documented_order() {
        let p = flat(&[(0., 0.), (3., 0.), (3., 1.), (0., 2.)]);
        let tris = triangulate_polygon(&p).unwrap();
        assert_eq!(tris.len(), 2);
        check_exact_cover(&p, &tris, 4.5);
    }

    #[test]
    fn tilted_non_axis_plane() {
        // An L-shape in the plane x + y + z = 0 seen from its normal side; winding preserved.
        let u = DVec3::new(1.0, -1.0, 0.0);
        let v = DVec3::new(1.0, 1.0, -2.0);
        let l2 = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)];
        let p: Vec<DVec3> = l2.iter().map(|&(a, b)| u * a + v * b).collect();
        let normal = u.cross(v);
        let tris = triangulate_polygon(&p).unwrap();
        assert_eq!(tris.len(), 4);
        let total: f64 = tris
            .iter()
            .map(|t| (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).dot(normal))
            .inspect(|&a| assert!(a > 0.0))
            .sum();
        let expected = 2.0 * 3.0 * normal.length_squared();
        assert!((total - expected).abs() < 1e-9 * expected);
    }

    #[test]
    fn consecutive_duplicates_are_merged() {
        let p = flat(&[(0., 0.), (1., 0.), (1., 0.), (1., 1.), (0., 1.), (0., 0.)]);
        let tris = triangulate_polygon(&p).unwrap();
        assert_eq!(tris.len(), 2);
        check_exact_cover(&p, &tris, 1.0);
        assert!(tris.iter().all(|t| !t.contains(&2) && !t.contains(&5)));
    }

    #[test]
    fn bow_tie_is_not_simple() {
        let p = flat(&[(0., 0.), (1., 1.), (1., 0.), (0., 1.)]);
        assert_eq!(triangulate_polygon(&p), Err(NotSimple::SelfIntersecting));
    }

    #[test]
    fn repeated_vertex_is_not_simple() {
        // Two squares sharing corner (1, 1) visited twice.
        let p = flat(&[
            (0., 0.),
            (1., 0.),
            (1., 1.),
            (2., 1.),
            (2., 2.),
            (1., 2.),
            (1., 1.),
            (0., 1.),
        ]);
        assert_eq!(triangulate_polygon(&p), Err(NotSimple::RepeatedVertex));
    }

    #[test]
    fn corner_on_another_edge_is_not_simple() {
        let p = flat(&[(0., 0.), (2., 0.), (2., 2.), (1., 0.), (0., 2.)]);
        assert_eq!(triangulate_polygon(&p), Err(NotSimple::SelfIntersecting));
    }

    #[test]
    fn bow_tie_with_unequal_lobes_is_not_simple() {
        let p = flat(&[(0., 0.), (2., 2.), (2., 0.), (0., 1.)]);
        assert_eq!(triangulate_polygon(&p), Err(NotSimple::SelfIntersecting));
    }

    #[test]
    fn collinear_polygon_has_zero_area() {
        let p = flat(&[(0., 0.), (1., 0.), (2., 0.), (3., 0.)]);
        assert_eq!(triangulate_polygon(&p), Err(NotSimple::ZeroArea));
    }

    #[test]
    fn fan_is_in_documented_order() {
        assert_eq!(fan(5), vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
        assert!(fan(2).is_empty());
    }
}
