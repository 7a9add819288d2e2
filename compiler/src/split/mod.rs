//! Split: convex fragments, their exact cut by a plane, and the choice of the splitting plane
//! (`choose.rs`; besides support planes, free planes `free.rs` and edge planes `edge.rs`).
//!
//! A fragment is a convex polygon stored as its support plane plus a cyclic list of bounding
//! planes; its vertices are kept alongside (grid points, or intersections of three table
//! planes). A cut adds one vertex on each cut edge — the intersection of the support plane,
//! the edge's plane and the split plane — and one edge (the split plane) to each piece, so
//! nothing is ever recomputed from rounded data.

use std::sync::Arc;

use crate::planes::{intersect, PlaneId, PlaneTable, Side, Vertex};

pub mod choose;
pub mod edge;
pub mod free;
pub mod lopsided;

/// A bounding edge of a fragment: the plane it lies on and the side the fragment is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    /// The bounding plane.
    pub plane: PlaneId,
    /// The side of `plane` the fragment lies on (`Front` or `Back`).
    pub inside: Side,
}

/// A convex fragment of one source triangle.
#[derive(Debug, Clone, PartialEq)]
pub struct Fragment {
    /// Source triangle id.
    pub source: u32,
    /// Support plane.
    pub support: PlaneId,
    /// True when the source triangle's normal is opposite to the support plane's normal.
    pub flipped: bool,
    /// Vertices, in the source triangle's winding order.
    pub vertices: Vec<Vertex>,
    /// `edges[i]` runs from `vertices[i]` to `vertices[i + 1]` (cyclically).
    pub edges: Vec<Edge>,
    /// In the shadow of another source triangle (see [`crate::shadow`]).
    pub shadowed: bool,
}

/// Where a fragment lies with respect to a plane.
#[derive(Debug, Clone, PartialEq)]
pub enum SplitResult {
    /// On the closed + side, not in the plane (the fragment, unchanged).
    Front(Fragment),
    /// On the closed − side, not in the plane.
    Back(Fragment),
    /// In the plane.
    On(Fragment),
    /// Cut in two: `(front piece, back piece)`.
    Cut(Fragment, Fragment),
}

/// How a fragment's vertices fall with respect to a plane, without cutting it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Placement {
    /// On the closed + side, not in the plane.
    Front,
    /// On the closed − side, not in the plane.
    Back,
    /// In the plane.
    On,
    /// Strictly on both sides.
    Straddle,
}

impl Placement {
    /// The placement of vertices on `sides` (stops at the first proof of a straddle).
    pub(crate) fn of_sides(sides: impl Iterator<Item = Side>) -> Placement {
        let (mut front, mut back) = (false, false);
        for side in sides {
            match side {
                Side::Front => front = true,
                Side::Back => back = true,
                Side::On => {}
            }
            if front && back {
                return Placement::Straddle;
            }
        }
        match (front, back) {
            (true, _) => Placement::Front,
            (false, true) => Placement::Back,
            // Every vertex on a plane other than its support: a degenerate fragment.
            (false, false) => Placement::On,
        }
    }
}

impl Fragment {
    /// Where the fragment lies with respect to `plane`.
    pub fn placement(&self, plane: PlaneId, table: &PlaneTable) -> Placement {
        if self.support == plane {
            return Placement::On;
        }
        let e = table.get(plane);
        Placement::of_sides(self.vertices.iter().map(|v| v.side(e)))
    }

    /// Cut the fragment exactly by `plane`. `None` only if the geometry is inconsistent (three
    /// planes that should meet in a point do not): a bug, reported by the caller.
    pub fn split(self, plane: PlaneId, table: &PlaneTable) -> Option<SplitResult> {
        if self.support == plane {
            return Some(SplitResult::On(self));
        }
        let e = table.get(plane);
        // Most fragments are not cut: place them without collecting their sides.
        match Placement::of_sides(self.vertices.iter().map(|v| v.side(e))) {
            Placement::Front => return Some(SplitResult::Front(self)),
            Placement::Back => return Some(SplitResult::Back(self)),
            Placement::On => return Some(SplitResult::On(self)),
            Placement::Straddle => {}
        }
        let sides: Vec<Side> = self.vertices.iter().map(|v| v.side(e)).collect();
        let n = self.vertices.len();
        let mut front = Piece::new(Side::Front, plane, n + 2);
        let mut back = Piece::new(Side::Back, plane, n + 2);
        let support = &table.get(self.support).plane;
        for i in 0..n {
            let (si, sj) = (sides[i], sides[(i + 1) % n]);
            let v = &self.vertices[i];
            let edge = self.edges[i];
            front.corner(v, edge, si, sj);
            back.corner(v, edge, si, sj);
            if si != Side::On && sj == si.opposite() {
                let h = intersect(support, &table.get(edge.plane).plane, &e.plane)?;
                let c = Vertex::Hom(Arc::new(h));
                let (from, to) = if si == Side::Front {
                    (&mut front, &mut back)
                } else {
                    (&mut back, &mut front)
                };
                // The crossing leaves `from` along the cut and enters `to` along the edge.
                from.push(c.clone(), from.cut);
                to.push(c, edge);
            }
        }
        if front.vertices.len() < 3 || back.vertices.len() < 3 {
            return None;
        }
        let piece = |p: Piece| Fragment {
            source: self.source,
            support: self.support,
            flipped: self.flipped,
            vertices: p.vertices,
            edges: p.edges,
            shadowed: self.shadowed,
        };
        Some(SplitResult::Cut(piece(front), piece(back)))
    }
}

/// One side's piece of a fragment being cut: the same walk of the fragment's corners builds
/// the front and the back piece, each keeping what lies on its closed side.
struct Piece {
    /// `Front` or `Back`.
    side: Side,
    /// The cut plane, as this piece's bounding edge.
    cut: Edge,
    vertices: Vec<Vertex>,
    edges: Vec<Edge>,
}

impl Piece {
    fn new(side: Side, plane: PlaneId, capacity: usize) -> Piece {
        Piece {
            side,
            cut: Edge {
                plane,
                inside: side,
            },
            vertices: Vec::with_capacity(capacity),
            edges: Vec::with_capacity(capacity),
        }
    }

    /// Corner `v` (on side `si` of the cut plane) and its outgoing `edge` (to a corner on side
    /// `sj`): kept unless the corner lies on the other side. A corner in the plane whose next
    /// corner lies on the other side leaves this piece along the cut.
    fn corner(&mut self, v: &Vertex, edge: Edge, si: Side, sj: Side) {
        let other = self.side.opposite();
        if si != other {
            let out = if si == Side::On && sj == other {
                self.cut
            } else {
                edge
            };
            self.push(v.clone(), out);
        }
    }

    fn push(&mut self, v: Vertex, edge: Edge) {
        self.vertices.push(v);
        self.edges.push(edge);
    }
}

/// The fragment of triangle `q` (its edge planes through the support's normal direction), as
/// the input stage makes it; `None` when degenerate. For tests of the modules that cut and peel.
#[cfg(test)]
pub(crate) fn triangle_fragment(table: &mut PlaneTable, q: [[i32; 3]; 3]) -> Option<Fragment> {
    let (plane, flipped) = crate::planes::Plane::through(q[0], q[1], q[2])?;
    let support = table.insert(plane);
    let edges = (0..3)
        .map(|k| {
            let e = crate::planes::edge_plane(q[k], q[(k + 1) % 3], plane.n);
            Edge {
                plane: table.insert(e),
                inside: e.side_of_point(q[(k + 2) % 3]),
            }
        })
        .collect();
    Some(Fragment {
        source: 0,
        support,
        flipped,
        vertices: q.map(Vertex::Int).to_vec(),
        edges,
        shadowed: false,
    })
}

#[cfg(test)]
mod tests;
