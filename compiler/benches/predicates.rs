//! Criterion benchmarks of the exact side-of-plane predicate (`planes::side_of_hom`): a cut
//! vertex (the intersection of three integer planes, homogeneous I256 coordinates) against a
//! plane,
//! - `filter-decides`: the vertex is well off the plane, so the f64 filter answers;
//! - `exact-fallback`: the vertex lies on the plane, so the filter cannot decide and the I256
//!   evaluation runs;
//! - `exact-only`: the I256 evaluation alone (`side_of_hom_exact`) on the off-plane vertex,
//!   what every test would cost without the filter;
//! - `grid-point`: an input corner (`Plane::side_of_point`, i128), for scale.
//!
//! Run with `cargo bench -p peel-compiler --bench predicates`.

#[path = "../../runtime/benches/budget/mod.rs"]
mod budget;

use std::hint::black_box;

use criterion::Criterion;
use peel_compiler::predicates::{
    intersect, side_of_hom, side_of_hom_exact, Plane, PlaneTable, Side,
};

/// A plane through three grid points (coordinates `|q| < 2^26` like the compiler's grid).
fn plane(a: [i32; 3], b: [i32; 3], c: [i32; 3]) -> Plane {
    Plane::through(a, b, c).expect("non-degenerate").0
}

fn predicates(c: &mut Criterion) {
    let p1 = plane(
        [1_000_003, -2_000_011, 3_000_017],
        [-5_000_023, 7_000_001, 1_100_009],
        [13_000_027, 2_000_029, -17_000_033],
    );
    let p2 = plane(
        [-9_000_001, 4_000_037, -6_000_041],
        [8_000_053, -3_000_059, 12_000_061],
        [2_000_063, 19_000_067, 5_000_071],
    );
    let p3 = plane(
        [7_000_079, 7_000_083, -7_000_087],
        [-11_000_093, 3_000_097, 9_000_101],
        [4_000_103, -15_000_107, -2_000_111],
    );
    let off = plane(
        [30_000_001, 1, 2],
        [30_000_003, 20_000_000, 5],
        [29_999_999, 7, 20_000_000],
    );
    let vertex = intersect(&p1, &p2, &p3).expect("three independent planes");
    let mut table = PlaneTable::default();
    let on_id = table.insert(p1);
    let off_id = table.insert(off);
    let (on_entry, off_entry) = (*table.get(on_id), *table.get(off_id));
    assert_eq!(side_of_hom(&vertex, &on_entry), Side::On);
    let off_side = side_of_hom(&vertex, &off_entry);
    assert_ne!(off_side, Side::On);
    assert_eq!(side_of_hom_exact(&vertex, &off), off_side);

    let mut g = c.benchmark_group("side-of-plane");
    g.bench_function("filter-decides", |b| {
        b.iter(|| side_of_hom(black_box(&vertex), black_box(&off_entry)))
    });
    g.bench_function("exact-fallback", |b| {
        b.iter(|| side_of_hom(black_box(&vertex), black_box(&on_entry)))
    });
    g.bench_function("exact-only", |b| {
        b.iter(|| side_of_hom_exact(black_box(&vertex), black_box(&off)))
    });
    let corner = [1_000_003, -2_000_011, 3_000_017];
    g.bench_function("grid-point", |b| {
        b.iter(|| black_box(&off).side_of_point(black_box(corner)))
    });
    g.finish();
}

budget::main!(predicates);
