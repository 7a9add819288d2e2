use glam::DVec3;

use super::one_sided_triangles;
use crate::load::SourceTriangle;

/// The 12 triangles of the axis box `lo..hi`, counter-clockwise seen from outside.
fn cube(lo: DVec3, hi: DVec3) -> Vec<SourceTriangle> {
    let p = |i: usize| {
        DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    // Faces as corner indices (bit 0 = x, 1 = y, 2 = z), counter-clockwise from outside.
    let faces = [
        [0, 2, 3, 1], // z = lo
        [4, 5, 7, 6], // z = hi
        [0, 1, 5, 4], // y = lo
        [2, 6, 7, 3], // y = hi
        [0, 4, 6, 2], // x = lo
        [1, 3, 7, 5], // x = hi
    ];
    faces
        .iter()
        .flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]])
        .map(|t| SourceTriangle {
            vertices: t.map(p),
            colour: [200, 200, 200],
        })
        .collect()
}

fn unit_cube() -> Vec<SourceTriangle> {
    cube(DVec3::ZERO, DVec3::ONE)
}

#[test]
fn a_cube_is_closed() {
    assert_eq!(one_sided_triangles(&unit_cube()), vec![true; 12]);
}

#[test]
fn a_cube_with_a_face_removed_is_open() {
    let mut t = unit_cube();
    t.drain(0..2);
    assert_eq!(one_sided_triangles(&t), vec![false; 10]);
    // Half a face missing is as open.
    let mut t = unit_cube();
    t.remove(5);
    assert_eq!(one_sided_triangles(&t), vec![false; 11]);
}

#[test]
fn two_cubes_are_decided_separately() {
    let mut t = unit_cube();
    let mut open = cube(DVec3::splat(3.0), DVec3::splat(4.0));
    open.truncate(10);
    t.extend(open);
    let flags = one_sided_triangles(&t);
    assert_eq!(&flags[..12], &[true; 12]);
    assert_eq!(&flags[12..], &[false; 10]);
}

#[test]
fn an_inconsistently_wound_cube_is_open() {
    let mut t = unit_cube();
    t[3].vertices.swap(1, 2);
    assert_eq!(one_sided_triangles(&t), vec![false; 12]);
    // A whole face flipped: every edge still used twice, but two in the same direction.
    let mut t = unit_cube();
    for tri in &mut t[..2] {
        tri.vertices.swap(1, 2);
    }
    assert_eq!(one_sided_triangles(&t), vec![false; 12]);
}

#[test]
fn an_inside_out_cube_is_two_sided() {
    let mut t = unit_cube();
    for tri in &mut t {
        tri.vertices.swap(1, 2);
    }
    assert_eq!(one_sided_triangles(&t), vec![false; 12]);
}

#[test]
fn cubes_sharing_an_edge_are_non_manifold() {
    // Two cubes touching along the edge x = 1, y = 1: that edge is used four times.
    let mut t = unit_cube();
    t.extend(cube(DVec3::new(1.0, 1.0, 0.0), DVec3::new(2.0, 2.0, 1.0)));
    assert_eq!(one_sided_triangles(&t), vec![false; 24]);
}

#[test]
fn matching_is_exact() {
    let mut t = unit_cube();
    // One corner of one triangle moved by one ulp: the seams there no longer weld.
    let tri = t
        .iter_mut()
        .find(|tri| tri.vertices.contains(&DVec3::ONE))
        .unwrap();
    for v in &mut tri.vertices {
        if *v == DVec3::ONE {
            v.x = 1.0 + f64::EPSILON;
        }
    }
    assert_eq!(one_sided_triangles(&t), vec![false; 12]);
    // Signed zero is the same point.
    let mut t = unit_cube();
    for v in &mut t[0].vertices {
        if v.x == 0.0 {
            v.x = -0.0;
        }
    }
    assert!(t[0].vertices.iter().any(|v| v.x.is_sign_negative()));
    assert_eq!(one_sided_triangles(&t), vec![true; 12]);
}

#[test]
fn degenerate_triangles_are_two_sided_and_ignored() {
    let mut t = unit_cube();
    t.push(SourceTriangle {
        vertices: [DVec3::ZERO, DVec3::ZERO, DVec3::X],
        colour: [0; 3],
    });
    let mut expected = vec![true; 12];
    expected.push(false);
    assert_eq!(one_sided_triangles(&t), expected);
    assert_eq!(one_sided_triangles(&[]), Vec::<bool>::new());
}

#[test]
fn a_closed_surface_that_crosses_itself_is_two_sided() {
    // Pull the corner (1, 1, 1) down through the bottom face: still closed, consistently
    // wound and of positive volume, but the faces around that corner cross the bottom face,
    // so from below their back sides show.
    let pulled = DVec3::new(0.6, 0.6, -0.5);
    let t: Vec<SourceTriangle> = unit_cube()
        .into_iter()
        .map(|mut t| {
            for v in &mut t.vertices {
                if *v == DVec3::ONE {
                    *v = pulled;
                }
            }
            t
        })
        .collect();
    assert_eq!(one_sided_triangles(&t), vec![false; 12]);
    // The same surface beside an untouched cube: only the crossing one is two-sided.
    let mut both = t;
    both.extend(cube(DVec3::splat(3.0), DVec3::splat(4.0)));
    let sides = one_sided_triangles(&both);
    assert_eq!(sides[..12], [false; 12]);
    assert_eq!(sides[12..], [true; 12]);
}
