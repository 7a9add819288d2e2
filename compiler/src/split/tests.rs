//! Exact cuts: pieces on their sides, sharing exactly the cut vertices.

use super::choose::{cost, Sample, SplitRule, Tally};
use super::triangle_fragment as triangle;
use super::*;
use crate::planes::Plane;
use proptest::prelude::*;

fn pt() -> impl Strategy<Value = [i32; 3]> {
    [-1000i32..1000, -1000i32..1000, -1000i32..1000]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn cuts_are_exact(t in [pt(), pt(), pt()], c in [pt(), pt(), pt()], d in [pt(), pt(), pt()]) {
        let mut table = PlaneTable::default();
        let Some(f) = triangle(&mut table, t) else { return Ok(()) };
        let Some((p, _)) = Plane::through(c[0], c[1], c[2]) else { return Ok(()) };
        let Some((p2, _)) = Plane::through(d[0], d[1], d[2]) else { return Ok(()) };
        let (pid, pid2) = (table.insert(p), table.insert(p2));
        let placement = f.placement(pid, &table);
        let r = f.clone().split(pid, &table).expect("consistent");
        let e = *table.get(pid);
        match r {
            SplitResult::Cut(a, b) => {
                prop_assert_eq!(placement, Placement::Straddle);
                prop_assert!(a.vertices.iter().all(|v| v.side(&e) != Side::Back));
                prop_assert!(b.vertices.iter().all(|v| v.side(&e) != Side::Front));
                // Each piece is bounded by P once; the new vertices are on P and shared.
                let on_a: Vec<_> = a.vertices.iter().filter(|v| v.side(&e) == Side::On).collect();
                let on_b: Vec<_> = b.vertices.iter().filter(|v| v.side(&e) == Side::On).collect();
                prop_assert_eq!(on_a.len(), 2);
                prop_assert_eq!(on_b.len(), 2);
                prop_assert!(on_a.iter().all(|v| on_b.contains(v)));
                prop_assert_eq!(a.edges.iter().filter(|x| x.plane == pid).count(), 1);
                prop_assert_eq!(b.edges.iter().filter(|x| x.plane == pid).count(), 1);
                // A second cut of a piece stays exact (cut vertices of cut vertices).
                if let Some(SplitResult::Cut(a2, b2)) = a.clone().split(pid2, &table) {
                    let e2 = *table.get(pid2);
                    prop_assert!(a2.vertices.iter().all(|v| v.side(&e2) != Side::Back && v.side(&e) != Side::Back));
                    prop_assert!(b2.vertices.iter().all(|v| v.side(&e2) != Side::Front && v.side(&e) != Side::Back));
                }
            }
            SplitResult::Front(_) => prop_assert_eq!(placement, Placement::Front),
            SplitResult::Back(_) => prop_assert_eq!(placement, Placement::Back),
            SplitResult::On(_) => prop_assert_eq!(placement, Placement::On),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The filtered count (one f64 bound per plane, exact predicate near the plane) is what
    /// the exact placement counts (and so is the cost): fragments cut by the plane and on each side, including
    /// fragments touching it, lying in it, and cut pieces (homogeneous vertices) near it.
    #[test]
    fn filtered_cost_equals_the_exact_count(
        tris in proptest::collection::vec([pt(), pt(), pt()], 2..12),
        scale in 0u32..12,
    ) {
        let s = 1i32 << scale;
        let mut table = PlaneTable::default();
        // Corners on a coarse lattice so that many planes pass through other corners.
        let frags: Vec<Fragment> = tris
            .iter()
            .filter_map(|t| triangle(&mut table, t.map(|p| p.map(|c| (c / 250) * s))))
            .collect();
        // Cut every fragment by the first support plane, so the list holds cut vertices too.
        let Some(first) = frags.first().map(|f| f.support) else { return Ok(()) };
        let mut list = Vec::new();
        for f in &frags {
            match f.clone().split(first, &table).expect("consistent") {
                SplitResult::Cut(a, b) => list.extend([a, b]),
                SplitResult::Front(f) | SplitResult::Back(f) | SplitResult::On(f) => list.push(f),
            }
        }
        let refs: Vec<&Fragment> = list.iter().collect();
        for plane in list.iter().map(|f| f.support) {
            // The oracle: the exact placement of every fragment, no filter.
            let mut exact = Tally::default();
            for f in &list {
                exact.add(f.placement(plane, &table));
            }
            let want = exact.cost(SplitRule::default(), 0);
            prop_assert_eq!(cost(&refs, plane, &table, u64::MAX), want);
            let sample = Sample::new(refs.iter().copied());
            prop_assert_eq!(sample.tally(plane, &table, |_, _| false), Some(exact));
        }
    }
}
