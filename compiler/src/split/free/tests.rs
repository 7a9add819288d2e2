//! Free splits: found where a loop of edges lies in a plane, never a cut, none where every
//! plane through the list's vertices cuts.

use glam::DVec3;

use super::*;
use crate::tools::scenes::{mesh, piercing_triangles, torus};
use crate::tree::input::prepare;

/// The support planes of `frags`, sorted and distinct.
fn supports(frags: &[Fragment]) -> Vec<PlaneId> {
    let mut p: Vec<PlaneId> = frags.iter().map(|f| f.support).collect();
    p.sort_unstable();
    p.dedup();
    p
}

/// A torus's horizontal rings of edges each lie in a plane `y = c` (the same float for every
/// vertex of a ring), which no triangle crosses: a free split, checked fragment by fragment.
#[test]
fn a_torus_has_a_free_split_through_a_ring_of_edges() {
    let input = prepare(&torus(12, 8), None).unwrap();
    let frags = &input.fragments;
    let planes = supports(frags);
    let free = best_free(frags, &planes, &input.table, None).expect("a free split");
    let (mut front, mut back) = (0, 0);
    for f in frags {
        match place(f, &free.entry) {
            Placement::Front => front += 1,
            Placement::Back => back += 1,
            other => panic!("a fragment is {other:?}"),
        }
    }
    assert_eq!((front, back), (free.front, free.back));
    assert!(front > 0 && back > 0);
    let own = |p: &Plane| planes.iter().any(|&q| input.table.get(q).plane == *p);
    assert!(!own(&free.entry.plane), "a support plane");
}

/// Three triangles that pierce one another in a cycle: every plane through three of their
/// corners cuts one of them or leaves a side empty.
#[test]
fn piercing_triangles_have_no_free_split() {
    let input = prepare(&mesh(piercing_triangles()), None).unwrap();
    let frags = &input.fragments;
    assert!(best_free(frags, &supports(frags), &input.table, None).is_none());
}

/// Two far-apart triangles are separated by an axis plane through a corner.
#[test]
fn apart_triangles_are_separated_without_a_cut() {
    let t = |x: f64| {
        [
            DVec3::new(x, 0.0, 0.0),
            DVec3::new(x + 1.0, 0.2, 0.1),
            DVec3::new(x, 1.0, 0.7),
        ]
    };
    let input = prepare(&mesh(vec![t(0.0), t(5.0)]), None).unwrap();
    let frags = &input.fragments;
    let free = best_free(frags, &supports(frags), &input.table, None).expect("a free split");
    assert_eq!((free.front, free.back), (1, 1));
}
