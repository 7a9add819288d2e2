//! The predicates against an exact rational oracle (num-bigint), on near-degenerate inputs.

use super::*;
use ethnum::U256;
use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use proptest::prelude::*;

fn big(x: I256) -> BigInt {
    x.to_string().parse().unwrap()
}

fn oracle_side(p: &Plane, xyz: [BigInt; 3], w: BigInt) -> Side {
    let mut s = -BigInt::from(p.d) * w;
    for (k, x) in xyz.into_iter().enumerate() {
        s += BigInt::from(p.n[k]) * x;
    }
    if s.is_positive() {
        Side::Front
    } else if s.is_negative() {
        Side::Back
    } else {
        Side::On
    }
}

fn oracle_hom(p: &Plane, h: &HomPoint) -> Side {
    oracle_side(p, h.xyz.map(big), big(h.w))
}

fn oracle_int(p: &Plane, q: IPoint) -> Side {
    oracle_side(p, q.map(BigInt::from), BigInt::from(1))
}

fn entry(p: Plane) -> PlaneEntry {
    let mut t = PlaneTable::default();
    let id = t.insert(p);
    *t.get(id)
}

const M: i32 = (1 << 26) - 1;

fn coord() -> impl Strategy<Value = i32> {
    prop_oneof![-M..=M, -8..=8i32, Just(M), Just(-M)]
}

fn point() -> impl Strategy<Value = IPoint> {
    [coord(), coord(), coord()]
}

fn plane_through(a: IPoint, b: IPoint, c: IPoint) -> Option<Plane> {
    Plane::through(a, b, c).map(|(p, _)| p)
}

#[test]
fn canonical_planes_are_equal_iff_the_same_plane() {
    let a = [0, 0, 0];
    let (p1, f1) = Plane::through(a, [2, 0, 0], [0, 2, 0]).unwrap();
    let (p2, f2) = Plane::through(a, [0, 4, 0], [6, 0, 0]).unwrap();
    assert_eq!(p1, p2);
    assert_ne!(f1, f2, "opposite windings are opposite orientations");
    assert_eq!(p1, Plane { n: [0, 0, 1], d: 0 });
    let (p3, _) = Plane::through([0, 0, 3], [2, 0, 3], [0, 2, 3]).unwrap();
    assert_ne!(p1, p3);
    assert!(Plane::through(a, [1, 1, 1], [2, 2, 2]).is_none());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn grid_points_match_the_oracle(a in point(), b in point(), c in point(), q in point()) {
        if let Some(p) = plane_through(a, b, c) {
            prop_assert!(p.n.iter().all(|c| c.unsigned_abs() < 1 << 55));
            prop_assert!(p.d.unsigned_abs() < 1 << 84);
            prop_assert_eq!(p.side_of_point(q), oracle_int(&p, q));
            for v in [a, b, c] {
                prop_assert_eq!(p.side_of_point(v), Side::On);
            }
            // The canonical normal is the raw one, negated exactly when `flipped`.
            let (_, flipped) = Plane::through(a, b, c).unwrap();
            let raw = cross(sub(b, a), sub(c, a));
            let first = raw.iter().copied().find(|&c| c != 0).unwrap();
            prop_assert_eq!(flipped, first < 0);
        }
    }

    #[test]
    fn intersections_lie_on_their_planes_and_classify_exactly(
        pts in proptest::collection::vec(point(), 12),
    ) {
        let planes: Vec<Plane> = pts.chunks(3).filter_map(|c| plane_through(c[0], c[1], c[2])).collect();
        prop_assume!(planes.len() == 4);
        if let Some(h) = intersect(&planes[0], &planes[1], &planes[2]) {
            prop_assert!(h.w > I256::ZERO);
            for p in &planes[..3] {
                prop_assert_eq!(side_of_hom(&h, &entry(*p)), Side::On);
                prop_assert_eq!(oracle_hom(p, &h), Side::On);
            }
            prop_assert_eq!(side_of_hom(&h, &entry(planes[3])), oracle_hom(&planes[3], &h));
            // Edge planes through the point's neighbourhood too.
            let e = edge_plane(pts[9], pts[10], planes[3].n);
            prop_assert_eq!(side_of_hom(&h, &entry(e)), oracle_hom(&e, &h));
        }
    }

    #[test]
    fn perturbations_of_2_pow_minus_40(pts in proptest::collection::vec(point(), 9), sx in -3i32..=3, sy in -3i32..=3) {
        let planes: Vec<Plane> = pts.chunks(3).filter_map(|c| plane_through(c[0], c[1], c[2])).collect();
        prop_assume!(planes.len() == 3);
        if let Some(h) = intersect(&planes[0], &planes[1], &planes[2]) {
            // Move the point by about 2^-40 of its size: the filter cannot decide, I256 must.
            let xyz = [
                h.xyz[0] + (h.xyz[0] >> 40) * I256::from(sx),
                h.xyz[1] + (h.xyz[1] >> 40) * I256::from(sy),
                h.xyz[2] + I256::from(sx * sy),
            ];
            let q = HomPoint::new(xyz, h.w).unwrap();
            for p in &planes {
                prop_assert_eq!(side_of_hom(&q, &entry(*p)), oracle_hom(p, &q));
            }
        }
    }
}

#[test]
fn a_256_by_256_scan_of_adjacent_points_around_a_plane() {
    // A steep plane with large coefficients and a point on it given with a huge W: the scan
    // steps by 1/W, far below what f64 can see.
    let p = plane_through([M, -M + 17, 3], [-M + 5, M, -1234567], [12345, 678, M]).unwrap();
    let a = plane_through([M, -M + 17, 3], [-M, 3, 5], [1, 2, M - 3]).unwrap();
    let b = plane_through([-M + 5, M, -1234567], [7, -M, 99], [M, M, -M]).unwrap();
    let on = intersect(&p, &a, &b).unwrap();
    assert!(
        on.w.unsigned_abs() > U256::ONE << 100,
        "the scan needs a big W"
    );
    let e = entry(p);
    let mut counts = [0usize; 3];
    for i in -128..128i32 {
        for j in -128..128i32 {
            let xyz = [
                on.xyz[0] + I256::from(i),
                on.xyz[1] + I256::from(j),
                on.xyz[2],
            ];
            let q = HomPoint::new(xyz, on.w).unwrap();
            let got = side_of_hom(&q, &e);
            assert_eq!(got, oracle_hom(&p, &q), "at ({i}, {j})");
            counts[got as usize] += 1;
        }
    }
    assert!(
        counts[0] > 0 && counts[1] > 0 && counts[2] > 0,
        "{counts:?}"
    );
}

#[test]
fn points_coplanar_up_to_rounding() {
    // Points of the real plane x + 2y + 3z = 1, rounded to the grid: classify exactly.
    let p = Plane {
        n: [1, 2, 3],
        d: 1 << 20,
    };
    let e = entry(p);
    let mut on = 0;
    for i in 0..2000i64 {
        let x = (i * 7919) % 100_000 - 50_000;
        let y = (i * 104_729) % 100_000 - 50_000;
        let zr = ((1i64 << 20) - x - 2 * y) as f64 / 3.0;
        let q = [x as i32, y as i32, zr.round() as i32];
        let got = Vertex::Int(q).side(&e);
        assert_eq!(got, oracle_int(&p, q));
        on += (got == Side::On) as usize;
    }
    assert!(on > 0);
}

#[test]
fn reduced_is_canonical() {
    let h = HomPoint::new(
        [I256::from(6), I256::from(-9), I256::from(12)],
        I256::from(-3),
    )
    .unwrap();
    assert_eq!(
        h.reduced(),
        ([I256::from(-2), I256::from(3), I256::from(-4)], I256::ONE)
    );
    assert!(big(h.w).is_positive() && !big(h.w).is_zero());
}

proptest! {
    /// Matching a batch in parallel gives the ids one-by-one insertion gives, in a fresh table
    /// and after it (where the batch falls back to single inserts), and later single inserts
    /// still find the batch's planes.
    #[test]
    fn insert_all_numbers_planes_as_insert_does(
        picks in proptest::collection::vec(0usize..12, 0..200),
        split in 0usize..200,
    ) {
        let pool: Vec<Plane> = (0..12)
            .map(|i| Plane::canonical([1 + i % 3, i / 3, 2], i128::from(i) - 5).unwrap().0)
            .collect();
        let planes: Vec<Plane> = picks.iter().map(|&i| pool[i]).collect();
        let mut one = PlaneTable::default();
        let want: Vec<PlaneId> = planes.iter().map(|&p| one.insert(p)).collect();
        let split = split.min(planes.len());
        let mut batch = PlaneTable::default();
        let mut got = batch.insert_all(&planes[..split]);
        got.extend(batch.insert_all(&planes[split..]));
        prop_assert_eq!(&got, &want);
        prop_assert_eq!(batch.len(), one.len());
        for (&p, &id) in planes.iter().zip(&want) {
            prop_assert_eq!(batch.insert(p), id);
            prop_assert_eq!(batch.get(id).plane, p);
        }
    }
}
