//! Hull tests: the hierarchy's answers against an exact scan of every fragment, and witnesses
//! carried to a child list keeping the answers exact.

use super::*;
use crate::planes::Plane;
use crate::split::SplitResult;
use proptest::prelude::*;

fn naive(frags: &[Fragment], e: &PlaneEntry) -> Option<bool> {
    let sides: Vec<Side> = frags
        .iter()
        .flat_map(|f| f.vertices.iter().map(|v| v.side(e)))
        .collect();
    let (f, b) = (sides.contains(&Side::Front), sides.contains(&Side::Back));
    match (f, b) {
        (true, true) => None,
        (true, false) => Some(true),
        (false, true) => Some(false),
        (false, false) => Some(true),
    }
}

/// Triangles of `pts` (three points each) in a fresh table, then cut by the first one's
/// plane, so that the list also holds cut vertices.
fn soup(pts: &[[i32; 3]]) -> (PlaneTable, Vec<Fragment>) {
    let mut table = PlaneTable::default();
    let frags: Vec<Fragment> = pts
        .chunks_exact(3)
        .filter_map(|t| crate::split::triangle_fragment(&mut table, [t[0], t[1], t[2]]))
        .collect();
    let Some(cut) = frags.first().map(|f| f.support) else {
        return (table, frags);
    };
    let mut out = Vec::new();
    for f in frags {
        match f.split(cut, &table) {
            Some(crate::split::SplitResult::Cut(a, b)) => out.extend([a, b]),
            Some(
                crate::split::SplitResult::Front(f)
                | crate::split::SplitResult::Back(f)
                | crate::split::SplitResult::On(f),
            ) => out.push(f),
            None => {}
        }
    }
    (table, out)
}

/// `hull` answers like the exact scan on `frags`, with a witness for exactly the planes off
/// the hull.
fn check(frags: &[Fragment], table: &PlaneTable, hull: &Hull) -> Result<(), TestCaseError> {
    let planes = support_planes(frags);
    for (i, &p) in planes.iter().enumerate() {
        prop_assert_eq!(hull.sides[i], naive(frags, table.get(p)));
    }
    let off: Vec<PlaneId> = hull.witnesses.iter().map(|w| w.plane).collect();
    let want: Vec<PlaneId> = planes
        .iter()
        .zip(&hull.sides)
        .filter(|(_, s)| s.is_none())
        .map(|(&p, _)| p)
        .collect();
    prop_assert_eq!(off, want);
    // Each witness is a proof: its vertices lie strictly on the sides it claims.
    for w in &hull.witnesses {
        let e = table.get(w.plane);
        prop_assert_eq!((w.front.side(e), w.back.side(e)), (Side::Front, Side::Back));
    }
    Ok(())
}

fn support_planes(frags: &[Fragment]) -> Vec<PlaneId> {
    let mut p: Vec<PlaneId> = frags.iter().map(|f| f.support).collect();
    p.sort_unstable();
    p.dedup();
    p
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// The hierarchy answers exactly like the exact scan, on clustered and coplanar points.
    #[test]
    fn hierarchy_matches_the_exact_scan(
        pts in proptest::collection::vec([-40i32..40, -40i32..40, -3i32..3], 3..200),
        scale in 0u32..20,
    ) {
        let s = 1i32 << scale;
        let pts: Vec<[i32; 3]> = pts.iter().map(|p| [p[0] * s, p[1] * s, p[2]]).collect();
        let mut table = PlaneTable::default();
        let mut frags = Vec::new();
        for t in pts.chunks_exact(3) {
            if let Some((p, _)) = Plane::through(t[0], t[1], t[2]) {
                let id = table.insert(p);
                frags.push(Fragment {
                    source: 0,
                    support: id,
                    flipped: false,
                    vertices: t.iter().map(|&q| Vertex::Int(q)).collect(),
                    edges: Vec::new(),
                    shadowed: false,
                });
            }
        }
        let planes: Vec<PlaneId> = (0..table.len() as PlaneId).collect();
        let got = hull_planes(&frags, &planes, &table, &Known::default());
        for (i, &p) in planes.iter().enumerate() {
            prop_assert_eq!(got.sides[i], naive(&frags, table.get(p)));
        }
        // Lists this small are scanned (see `SCAN_WORK`): the hierarchy is asked directly.
        let mut set = VertexSet::new(&frags);
        set.index();
        for &p in &planes {
            let e = table.get(p);
            match set.hull_side(p, &table, None, None) {
                Ok(interior_front) => prop_assert_eq!(Some(interior_front), naive(&frags, e)),
                Err(w) => {
                    prop_assert_eq!(naive(&frags, e), None);
                    prop_assert_eq!((w.front.side(e), w.back.side(e)), (Side::Front, Side::Back));
                    // Half a witness known: the other side is searched, the known one kept.
                    for (f, b) in [(Some(&w.front), None), (None, Some(&w.back))] {
                        let Err(h) = set.hull_side(p, &table, f, b) else {
                            return Err(TestCaseError::fail("a known side was lost"));
                        };
                        prop_assert_eq!((h.front.side(e), h.back.side(e)), (Side::Front, Side::Back));
                    }
                }
            }
        }
    }

    /// A child list answers exactly like the exact scan when given its parent's
    /// witnesses: after peeling (any part of the parent, inherited witnesses checked for
    /// presence) and after a split (witnesses strictly on the child's side, used as they
    /// are: `hull_planes` asserts under test that they are vertices of the child). Lists
    /// of up to 50 planes take both the scan and the hierarchy.
    #[test]
    fn witnesses_carried_to_a_child_keep_answers_exact(
        pts in proptest::collection::vec([-30i32..30, -30i32..30, -4i32..4], 6..150),
        keep in proptest::collection::vec(proptest::bool::weighted(0.8), 100),
        cut in 0usize..1000,
    ) {
        let (table, frags) = soup(&pts);
        let planes = support_planes(&frags);
        let parent = hull_planes(&frags, &planes, &table, &Known::default());
        check(&frags, &table, &parent)?;
        for w in &parent.witnesses {
            let e = table.get(w.plane);
            prop_assert_eq!(w.front.side(e), Side::Front);
            prop_assert_eq!(w.back.side(e), Side::Back);
        }
        let child: Vec<Fragment> = frags
            .iter()
            .enumerate()
            .filter(|(i, _)| keep[i % keep.len()])
            .map(|(_, f)| f.clone())
            .collect();
        let planes = support_planes(&child);
        let got = hull_planes(&child, &planes, &table, &Known::Inherited(parent.witnesses.clone()));
        check(&child, &table, &got)?;
        let Some(&p) = planes.get(cut % planes.len().max(1)) else { return Ok(()) };
        let (known_front, known_back) = after_split(got.witnesses, table.get(p));
        for (side, known) in [(Side::Front, known_front), (Side::Back, known_back)] {
            let mut part = Vec::new();
            for f in child.iter().cloned() {
                match f.split(p, &table) {
                    Some(SplitResult::Cut(a, b)) => {
                        part.push(if side == Side::Front { a } else { b })
                    }
                    Some(SplitResult::Front(f)) if side == Side::Front => part.push(f),
                    Some(SplitResult::Back(f)) if side == Side::Back => part.push(f),
                    _ => {}
                }
            }
            let planes = support_planes(&part);
            check(&part, &table, &hull_planes(&part, &planes, &table, &known))?;
        }
    }
}
