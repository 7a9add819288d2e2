//! Exact self-intersection test of a triangle set: a closed, outward oriented surface that
//! crosses itself (a fold of a scanned mesh, say) shows back faces from outside, so such a
//! component must stay two-sided.
//!
//! Decisions use Shewchuk's exact `orient3d` / `orient2d` on the input's f64 coordinates (the
//! `robust` crate): no tolerance. Candidate pairs come from a sweep over the triangles' x
//! extents. Touching counts as crossing wherever that is cheaper to decide (a triangle's
//! corner exactly on another triangle that shares no corner with it, an edge lying in
//! another triangle's plane): the test may call a surface self-intersecting that only
//! touches itself, which costs some culling, never a wrong pixel. Two triangles sharing an
//! edge or a corner touch there by construction and are only reported when they really
//! overlap beyond it.

use glam::DVec3;
use robust::{orient2d, orient3d, Coord, Coord3D};

fn c3(p: DVec3) -> Coord3D<f64> {
    Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    }
}

/// Sign of the volume of `(a, b, c, d)`: which side of plane `abc` the point `d` is on.
fn o3(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> i8 {
    let v = orient3d(c3(a), c3(b), c3(c), c3(d));
    (v > 0.0) as i8 - (v < 0.0) as i8
}

/// The projection of a triangle onto a coordinate plane where it keeps a non-zero area (an
/// axis is dropped), so that in-plane questions become exact 2D orientations.
#[derive(Clone, Copy)]
struct Drop(usize);

impl Drop {
    fn of(t: &[DVec3; 3]) -> Option<Drop> {
        (0..3).rev().map(Drop).find(|d| d.o2(t[0], t[1], t[2]) != 0)
    }

    fn p(self, v: DVec3) -> Coord<f64> {
        let a = v.to_array();
        let (i, j) = match self.0 {
            0 => (1, 2),
            1 => (2, 0),
            _ => (0, 1),
        };
        Coord { x: a[i], y: a[j] }
    }

    fn o2(self, a: DVec3, b: DVec3, c: DVec3) -> i8 {
        let v = orient2d(self.p(a), self.p(b), self.p(c));
        (v > 0.0) as i8 - (v < 0.0) as i8
    }

    /// True when no edge line of `a` or `b` (convex, in one plane, 2 or 3 points each)
    /// separates them. `strict`: only interiors count (touching is not overlapping).
    fn overlap(self, a: &[DVec3], b: &[DVec3], strict: bool) -> bool {
        !(self.separates(a, b, strict) || self.separates(b, a, strict))
    }

    fn separates(self, a: &[DVec3], b: &[DVec3], strict: bool) -> bool {
        let n = a.len();
        (0..n).any(|i| {
            let (e0, e1) = (a[i], a[(i + 1) % n]);
            // The side of the edge line the polygon `a` is on (any vertex off the line).
            let inside = a
                .iter()
                .map(|&v| self.o2(e0, e1, v))
                .find(|&s| s != 0)
                .unwrap_or(0);
            if inside == 0 {
                // `a` is a segment: its line separates `b` when `b` is strictly on one side.
                let sides: Vec<i8> = b.iter().map(|&v| self.o2(e0, e1, v)).collect();
                return sides.iter().all(|&s| s > 0) || sides.iter().all(|&s| s < 0);
            }
            let outside = |v: &DVec3| {
                let s = self.o2(e0, e1, *v);
                if strict {
                    s != inside
                } else {
                    s == -inside
                }
            };
            b.iter().all(outside)
        })
    }
}

/// Whether the closed segment `ab` meets the closed triangle `t` (not coplanar with it).
fn segment_meets(a: DVec3, b: DVec3, t: &[DVec3; 3], drop: Drop) -> bool {
    let (sa, sb) = (o3(t[0], t[1], t[2], a), o3(t[0], t[1], t[2], b));
    if sa * sb > 0 {
        return false;
    }
    if sa == 0 && sb == 0 {
        return drop.overlap(&[a, b], t, false);
    }
    let s: [i8; 3] = std::array::from_fn(|k| o3(a, b, t[k], t[(k + 1) % 3]));
    s.iter().all(|&x| x >= 0) || s.iter().all(|&x| x <= 0)
}

/// Whether two non-degenerate triangles cross beyond the corners and edge they share.
fn cross(t1: &[DVec3; 3], d1: Drop, t2: &[DVec3; 3], d2: Drop) -> bool {
    let s: [i8; 3] = std::array::from_fn(|k| o3(t1[0], t1[1], t1[2], t2[k]));
    if s == [0, 0, 0] {
        // Coplanar: only overlapping interiors matter (a shared edge or corner is no overlap).
        return d1.overlap(t1, t2, true);
    }
    let r: [i8; 3] = std::array::from_fn(|k| o3(t2[0], t2[1], t2[2], t1[k]));
    let one_side = |v: &[i8; 3]| v.iter().all(|&x| x > 0) || v.iter().all(|&x| x < 0);
    if one_side(&s) || one_side(&r) {
        return false;
    }
    let shared = |v: DVec3| t1.contains(&v) && t2.contains(&v);
    match t1.iter().filter(|&&v| shared(v)).count() {
        // Not coplanar and sharing an edge: they meet on that edge only.
        2.. => false,
        // Their planes cross on a line through every shared corner; the intersection, if it
        // goes beyond, ends on an edge of one of them that avoids the shared corner.
        _ => {
            let edges = |t: &[DVec3; 3]| {
                (0..3)
                    .map(|k| (t[k], t[(k + 1) % 3]))
                    .filter(|&(a, b)| !shared(a) && !shared(b))
                    .collect::<Vec<_>>()
            };
            edges(t1).iter().any(|&(a, b)| segment_meets(a, b, t2, d2))
                || edges(t2).iter().any(|&(a, b)| segment_meets(a, b, t1, d1))
        }
    }
}

/// Whether some two of `triangles` cross (see the module docs). Degenerate triangles
/// (collinear corners) draw nothing and are ignored.
pub(crate) fn self_intersecting(triangles: &[[DVec3; 3]]) -> bool {
    let mut items: Vec<([DVec3; 3], Drop, DVec3, DVec3)> = triangles
        .iter()
        .filter_map(|t| {
            let d = Drop::of(t)?;
            let lo = t[0].min(t[1]).min(t[2]);
            let hi = t[0].max(t[1]).max(t[2]);
            Some((*t, d, lo, hi))
        })
        .collect();
    items.sort_by(|a, b| a.2.x.total_cmp(&b.2.x));
    for (i, (t1, d1, lo1, hi1)) in items.iter().enumerate() {
        for (t2, d2, lo2, hi2) in &items[i + 1..] {
            if lo2.x > hi1.x {
                break;
            }
            let apart = (0..3).any(|k| lo2[k] > hi1[k] || lo1[k] > hi2[k]);
            if !apart && cross(t1, *d1, t2, *d2) {
                return true;
            }
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn crossing_triangles_are_found() {
        let a = [v(0.0, 0.0, 0.0), v(2.0, 0.0, 0.0), v(0.0, 2.0, 0.0)];
        let b = [v(0.5, 0.5, -1.0), v(0.5, 0.5, 1.0), v(3.0, 3.0, 0.5)];
        assert!(self_intersecting(&[a, b]));
        // The same, moved clear.
        let far = b.map(|p| p + v(10.0, 0.0, 0.0));
        assert!(!self_intersecting(&[a, far]));
    }

    #[test]
    fn neighbours_sharing_an_edge_or_a_corner_do_not_cross() {
        let a = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)];
        let flat = [v(1.0, 0.0, 0.0), v(1.0, 1.0, 0.0), v(0.0, 1.0, 0.0)];
        let bent = [v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(0.0, 0.0, 1.0)];
        let corner = [v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0), v(2.0, 1.0, 1.0)];
        for other in [flat, bent, corner] {
            assert!(!self_intersecting(&[a, other]));
        }
        // A coplanar neighbour folded back over `a` overlaps it.
        let folded = [v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(0.2, 0.2, 0.0)];
        assert!(self_intersecting(&[a, folded]));
        // A neighbour through a shared corner that cuts into `a`.
        let through = [v(0.0, 0.0, 0.0), v(0.5, 0.2, -1.0), v(0.2, 0.5, 1.0)];
        assert!(self_intersecting(&[a, through]));
    }

    #[test]
    fn a_closed_box_does_not_cross_itself() {
        let c = |i: usize| v((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64);
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let tris: Vec<[DVec3; 3]> = quads
            .iter()
            .flat_map(|q| [[c(q[0]), c(q[1]), c(q[2])], [c(q[0]), c(q[2]), c(q[3])]])
            .collect();
        assert!(!self_intersecting(&tris));
    }
}
