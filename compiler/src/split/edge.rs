//! Edge splits: a list split by the plane of one of its fragments' edges, a table plane that
//! is none of its support planes.
//!
//! A support plane through a curved surface cuts it wherever the surface comes back to the
//! plane; the plane of an edge (through the edge and the axis nearest the fragment's normal,
//! see [`crate::planes::edge_plane`]) stands across the surface, cuts nothing along its own
//! edge and follows the surface's mesh lines as far as they run straight. Around a neck (a leg,
//! an ear, a handle) it often cuts fewer fragments than any support plane, and leaves two
//! parts that peel. Such a plane may cut, so it is taken only when some fragment lies wholly
//! on each side: then each child has fewer fragments than the list and no more support planes
//! (the termination argument, [`crate::tree`]). Its cut points are intersections of table
//! planes, exact as any other.
//!
//! Not with shadows ([`crate::shadow`]): there one pixel of one of the stress suite's views
//! (a turned torus in a sun, `tests/stress.rs`) showed a crack; no exact T-junction was left
//! open, and declining edge planes that pass within four of the file's vertex steps of a vertex,
//! or those of shadow edges, did not remove it. The cause is not found yet.

use super::{Fragment, Placement};
use crate::planes::{PlaneEntry, PlaneId};

/// The distinct planes of the edges of `frags` that are none of `supports` (sorted), the
/// candidates of an edge split.
pub fn edge_planes(frags: &[Fragment], supports: &[PlaneId]) -> Vec<PlaneId> {
    let mut planes: Vec<PlaneId> = frags
        .iter()
        .flat_map(|f| f.edges.iter().map(|e| e.plane))
        .filter(|p| supports.binary_search(p).is_err())
        .collect();
    planes.sort_unstable();
    planes.dedup();
    planes
}

/// True when some fragment of `frags` lies wholly on each side of `e` (strictly, none in it):
/// splitting by `e` leaves each side fewer fragments than the list.
pub fn divides(frags: &[Fragment], e: &PlaneEntry) -> bool {
    let (mut front, mut back) = (false, false);
    for f in frags {
        match Placement::of_sides(f.vertices.iter().map(|v| v.side(e))) {
            Placement::Front => front = true,
            Placement::Back => back = true,
            Placement::On | Placement::Straddle => {}
        }
        if front && back {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planes::PlaneTable;
    use crate::split::triangle_fragment;

    /// Two triangles side by side in the plane z = 0: the plane of the edge between them is
    /// no support plane and has one triangle wholly on each side; the plane of an outer edge
    /// has both on one side.
    #[test]
    fn the_shared_edge_divides_and_an_outer_edge_does_not() {
        let mut table = PlaneTable::default();
        let a = triangle_fragment(&mut table, [[0, 0, 0], [4, 0, 0], [0, 4, 0]]).unwrap();
        let b = triangle_fragment(&mut table, [[4, 0, 0], [4, 4, 0], [0, 4, 0]]).unwrap();
        let frags = vec![a, b];
        let supports = vec![frags[0].support];
        assert_eq!(frags[1].support, frags[0].support);
        let planes = edge_planes(&frags, &supports);
        // Five distinct edges: three of each triangle, one shared.
        assert_eq!(planes.len(), 5);
        assert!(!planes.contains(&frags[0].support));
        let shared = frags[0].edges[1].plane;
        assert_eq!(frags[1].edges[2].plane, shared);
        assert!(divides(&frags, table.get(shared)));
        let outer = frags[0].edges[0].plane;
        assert!(!divides(&frags, table.get(outer)));
    }
}
