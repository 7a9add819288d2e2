extern crate std;

use glam::Vec3;
use proptest::prelude::*;
use std::vec::Vec;

use super::testing::{box_faces, TestTree};
use super::*;
use crate::display::Colour;

fn order_of(tree: &TestTree, eye: Vec3, order: Order) -> Vec<u32> {
    let mut stack = [StackEntry::default(); 16];
    let mut t = Traversal::new(tree, eye, order, &mut stack).unwrap();
    t.skip_solids_from_behind();
    let out: Vec<u32> = t.by_ref().collect();
    assert_eq!(t.error(), None);
    out
}

fn btf(tree: &TestTree, eye: Vec3) -> Vec<u32> {
    order_of(tree, eye, Order::BackToFront)
}

fn convex(t: &mut TestTree, (first, count): (u32, u32), child: Option<u32>) -> u32 {
    t.add_node(Node::Convex {
        first,
        count,
        child,
    })
}

/// One convex node: the box [-1, 1]^3, faces -x, +x, -y, +y, -z, +z.
fn one_box() -> TestTree {
    let mut t = TestTree::default();
    let faces = box_faces(
        &mut t,
        Vec3::splat(-1.0),
        Vec3::splat(1.0),
        Colour::default(),
    );
    convex(&mut t, faces, None);
    t
}

#[test]
fn empty_tree_yields_nothing() {
    let t = TestTree::default();
    assert!(btf(&t, Vec3::ZERO).is_empty());
}

#[test]
fn convex_node_interior_first_then_exterior() {
    let t = one_box();
    // From +z the eye sees the inside of every face but +z.
    assert_eq!(btf(&t, Vec3::new(0.0, 0.0, 10.0)), [0, 1, 2, 3, 4, 5]);
    assert_eq!(btf(&t, Vec3::new(0.0, 0.0, -10.0)), [0, 1, 2, 3, 5, 4]);
    // From the (+x, +y) diagonal the +x and +y faces are seen from outside.
    assert_eq!(btf(&t, Vec3::new(10.0, 10.0, 0.0)), [0, 2, 4, 5, 1, 3]);
    // From inside the box, every face is seen from inside.
    assert_eq!(btf(&t, Vec3::new(0.2, -0.3, 0.1)), [0, 1, 2, 3, 4, 5]);
}

#[test]
fn each_polygon_comes_with_the_side_the_eye_sees() {
    let t = split_pair();
    let eyes = [
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::new(3.0, -2.0, 1.5),
        Vec3::new(0.1, 0.2, -1.5),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 5.0),
    ];
    for eye in eyes {
        for order in [Order::BackToFront, Order::FrontToBack] {
            let mut stack = [StackEntry::default(); 16];
            let mut walk = Traversal::new(&t, eye, order, &mut stack).unwrap();
            let (mut interior, mut exterior) = (0, 0);
            while let Some((index, polygon)) = walk.next_polygon_entering(|_| true) {
                let seen = walk.seen_interior();
                assert_eq!(polygon, t.polygon(index));
                let side = t.eye_side(&polygon, &t.side_eye(eye));
                assert_eq!(
                    seen,
                    sees_interior(&polygon, side),
                    "{eye} {order:?} {index}"
                );
                if seen {
                    interior += 1;
                } else {
                    exterior += 1;
                }
            }
            assert_eq!(interior + exterior, 12);
            // Outside both boxes some faces are seen from outside; inside one, none of its.
            assert!(exterior > 0, "{eye}");
        }
    }
}

#[test]
fn eye_on_a_polygon_plane() {
    let t = one_box();
    // Exactly on the +x face's plane: seen edge-on, counted with the interior pass.
    assert_eq!(btf(&t, Vec3::new(1.0, 0.0, 5.0)), [0, 1, 2, 3, 4, 5]);
    // Just outside it: the +x face moves to the exterior pass.
    assert_eq!(btf(&t, Vec3::new(1.001, 0.0, 5.0)), [0, 2, 3, 4, 1, 5]);
    // Both orders are valid paintings there; front to back stays the exact reverse.
    let mut rev = btf(&t, Vec3::new(1.0, 0.0, 5.0));
    rev.reverse();
    assert_eq!(
        order_of(&t, Vec3::new(1.0, 0.0, 5.0), Order::FrontToBack),
        rev
    );
}

/// A split on the plane z = 0 between a box at z in [1, 2] (+ side, polygons 0..6) and a box
/// at z in [-2, -1] (- side, polygons 6..12).
fn split_pair() -> TestTree {
    let mut t = TestTree::default();
    let p = t.add_plane(Vec3::Z, 0.0);
    let root = t.add_node(Node::Split {
        plane: p,
        front: None,
        back: None,
    });
    let front_faces = box_faces(
        &mut t,
        Vec3::new(-1.0, -1.0, 1.0),
        Vec3::new(1.0, 1.0, 2.0),
        Colour::default(),
    );
    let back_faces = box_faces(
        &mut t,
        Vec3::new(-1.0, -1.0, -2.0),
        Vec3::new(1.0, 1.0, -1.0),
        Colour::default(),
    );
    let front = convex(&mut t, front_faces, None);
    let back = convex(&mut t, back_faces, None);
    t.nodes[root as usize] = Node::Split {
        plane: p,
        front: Some(front),
        back: Some(back),
    };
    t
}

fn all_below(seq: &[u32], a: core::ops::Range<u32>, b: core::ops::Range<u32>) -> bool {
    let last_a = seq.iter().rposition(|i| a.contains(i)).unwrap();
    let first_b = seq.iter().position(|i| b.contains(i)).unwrap();
    last_a < first_b
}

#[test]
fn split_node_draws_the_far_side_first() {
    let t = split_pair();
    let plus = btf(&t, Vec3::new(0.3, 0.0, 5.0));
    assert_eq!(plus.len(), 12);
    assert!(all_below(&plus, 6..12, 0..6), "{plus:?}");
    let minus = btf(&t, Vec3::new(0.3, 0.0, -5.0));
    assert!(all_below(&minus, 0..6, 6..12), "{minus:?}");
}

#[test]
fn eye_exactly_on_a_split_plane() {
    let t = split_pair();
    let eye = Vec3::new(0.5, 0.25, 0.0);
    let seq = btf(&t, eye);
    // Every polygon exactly once.
    let mut sorted = seq.clone();
    sorted.sort();
    assert_eq!(sorted, (0..12).collect::<Vec<_>>());
    // The documented tie-break: distance 0 counts as the + side, so the - child first.
    assert!(all_below(&seq, 6..12, 0..6), "{seq:?}");
    // The + box: from z = 0 the -z face (z = 1) is seen from outside, the rest from inside.
    let front: Vec<u32> = seq.iter().copied().filter(|i| *i < 6).collect();
    assert_eq!(front, [0, 1, 2, 3, 5, 4]);
}

#[test]
fn nested_convex_nodes_draw_the_inner_set_between_the_passes() {
    let mut t = TestTree::default();
    let outer = box_faces(
        &mut t,
        Vec3::splat(-3.0),
        Vec3::splat(3.0),
        Colour::default(),
    );
    let inner = box_faces(
        &mut t,
        Vec3::splat(-1.0),
        Vec3::splat(1.0),
        Colour::default(),
    );
    let root = convex(&mut t, outer, None);
    let child = convex(&mut t, inner, None);
    t.nodes[root as usize] = Node::Convex {
        first: outer.0,
        count: outer.1,
        child: Some(child),
    };
    assert_eq!(
        btf(&t, Vec3::new(0.0, 0.0, 10.0)),
        [0, 1, 2, 3, 4, 6, 7, 8, 9, 10, 11, 5]
    );
}

/// A deeper tree mixing splits and nested convex sets, for the order properties.
fn mixed() -> TestTree {
    let mut t = split_pair();
    // Give the + box a nested child and hang a second split under the - box.
    let inner = box_faces(
        &mut t,
        Vec3::new(-0.5, -0.5, 1.2),
        Vec3::new(0.5, 0.5, 1.8),
        Colour::default(),
    );
    let inner_node = convex(&mut t, inner, None);
    if let Node::Convex { first, count, .. } = t.nodes[1] {
        t.nodes[1] = Node::Convex {
            first,
            count,
            child: Some(inner_node),
        };
    }
    let px = t.add_plane(Vec3::X, 0.0);
    let a = box_faces(
        &mut t,
        Vec3::new(0.1, -0.5, -1.8),
        Vec3::new(0.5, 0.5, -1.2),
        Colour::default(),
    );
    let b = box_faces(
        &mut t,
        Vec3::new(-0.5, -0.5, -1.8),
        Vec3::new(-0.1, 0.5, -1.2),
        Colour::default(),
    );
    let na = convex(&mut t, a, None);
    let nb = convex(&mut t, b, None);
    let split = t.add_node(Node::Split {
        plane: px,
        front: Some(na),
        back: Some(nb),
    });
    if let Node::Convex { first, count, .. } = t.nodes[2] {
        t.nodes[2] = Node::Convex {
            first,
            count,
            child: Some(split),
        };
    }
    t
}

#[test]
fn stack_of_exactly_the_depth_suffices() {
    let t = mixed();
    assert_eq!(t.max_depth(), 4);
    let mut stack = [StackEntry::default(); 4];
    let mut tr =
        Traversal::new(&t, Vec3::new(0.2, 0.1, 3.0), Order::BackToFront, &mut stack).unwrap();
    assert_eq!(tr.by_ref().count(), t.polygons.len());
    assert_eq!(tr.error(), None);
}

#[test]
fn stack_smaller_than_the_depth_is_refused_up_front() {
    let t = mixed();
    let mut stack = [StackEntry::default(); 3];
    let r = Traversal::new(&t, Vec3::ZERO, Order::BackToFront, &mut stack);
    assert_eq!(
        r.err(),
        Some(RenderError::StackTooSmall {
            needed: 4,
            available: 3
        })
    );
}

#[test]
fn a_tree_deeper_than_declared_stops_with_an_error() {
    let mut t = mixed();
    t.declared_depth = Some(2);
    let mut stack = [StackEntry::default(); 2];
    let mut tr =
        Traversal::new(&t, Vec3::new(0.2, 0.1, 3.0), Order::BackToFront, &mut stack).unwrap();
    let n = tr.by_ref().count();
    assert!(n < t.polygons.len());
    assert!(matches!(
        tr.error(),
        Some(RenderError::StackTooSmall { .. })
    ));
}

#[test]
fn a_cycle_stops_with_an_error() {
    let mut t = one_box();
    t.nodes[0] = Node::Convex {
        first: 0,
        count: 6,
        child: Some(0),
    };
    t.declared_depth = Some(1);
    let mut stack = [StackEntry::default(); 8];
    let mut tr = Traversal::new(
        &t,
        Vec3::new(0.0, 0.0, 10.0),
        Order::BackToFront,
        &mut stack,
    )
    .unwrap();
    let n = tr.by_ref().count();
    assert!(n <= 12);
    assert_eq!(tr.error(), Some(RenderError::MalformedTree));
}

fn eye_coord() -> impl Strategy<Value = f32> {
    prop_oneof![
        (-6.0f32..6.0),
        // Values that put the eye exactly on planes of the trees above.
        prop::sample::select(std::vec![
            -2.0f32, -1.8, -1.0, -0.5, 0.0, 0.1, 0.5, 1.0, 1.2, 2.0
        ]),
    ]
}

proptest! {
    #[test]
    fn front_to_back_is_the_exact_reverse(x in eye_coord(), y in eye_coord(), z in eye_coord()) {
        let t = mixed();
        let eye = Vec3::new(x, y, z);
        let mut seq = btf(&t, eye);
        let mut sorted = seq.clone();
        sorted.sort();
        prop_assert_eq!(sorted, (0..t.polygons.len() as u32).collect::<Vec<_>>());
        seq.reverse();
        prop_assert_eq!(order_of(&t, eye, Order::FrontToBack), seq);
    }

    /// Between the two children of a split, the child on the eye's side comes last.
    #[test]
    fn split_children_are_never_interleaved(x in eye_coord(), y in eye_coord(), z in eye_coord()) {
        let t = mixed();
        let seq = btf(&t, Vec3::new(x, y, z));
        // Root split: + side polygons 0..6 and 12..18, - side 6..12 and 18..30.
        let plus = |i: &u32| *i < 6 || (12..18).contains(i);
        let first_is_plus = plus(&seq[0]);
        let switch = seq.iter().position(|i| plus(i) != first_is_plus).unwrap();
        prop_assert!(seq[switch..].iter().all(|i| plus(i) != first_is_plus));
        prop_assert_eq!(first_is_plus, z < 0.0);
    }
}

/// The same trees read from `.peel` bytes through [`Scene`] walk in the same order.
#[test]
#[cfg_attr(
    not(all(feature = "large-scenes", feature = "wide-vertices")),
    ignore = "the test encoder writes f32 vertices and u32 fields"
)]
fn scene_walks_like_the_in_memory_tree() {
    for t in [one_box(), split_pair()] {
        let bytes = super::testing::encode(&t);
        let scene = Scene::parse(&bytes).unwrap();
        for eye in [
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::new(0.3, -0.2, -4.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(5.0, 7.0, 1.5),
        ] {
            let mut stack = [StackEntry::default(); 4];
            let from_scene: Vec<u32> = Traversal::new(&scene, eye, Order::BackToFront, &mut stack)
                .unwrap()
                .collect();
            assert_eq!(from_scene, btf(&t, eye));
        }
    }
}

/// The display order written the obvious recursive way, as an oracle for the
/// iterative walk (which remembers a node's first scan in a bit mask for the second).
fn recursive_btf(t: &TestTree, node: Option<u32>, eye: Vec3, out: &mut Vec<u32>) {
    let Some(i) = node else { return };
    match t.node(i) {
        Node::Split { plane, front, back } => {
            let (first, second) = if t.plane(plane).distance(eye) >= 0.0 {
                (back, front)
            } else {
                (front, back)
            };
            recursive_btf(t, first, eye, out);
            recursive_btf(t, second, eye, out);
        }
        Node::Convex {
            first,
            count,
            child,
        } => {
            let seen =
                |p: u32| sees_interior(&t.polygon(p), t.eye_side(&t.polygon(p), &t.side_eye(eye)));
            let shown = |p: u32| !seen_from_behind(&t.polygon(p), seen(p), t.hidden);
            out.extend((first..first + count).filter(|&p| seen(p) && shown(p)));
            recursive_btf(t, child, eye, out);
            out.extend((first..first + count).filter(|&p| !seen(p) && shown(p)));
        }
    }
}

/// Convex nodes of `n` triangles tangent to a sphere of radius `r` (Fibonacci directions),
/// nested: `sizes[0]` outermost.
fn nested_spheres(sizes: &[(u32, f32)]) -> TestTree {
    let mut t = TestTree::default();
    let mut ranges = Vec::new();
    for &(n, r) in sizes {
        let first = t.polygons.len() as u32;
        for k in 0..n {
            let z = 1.0 - 2.0 * (k as f32 + 0.5) / n as f32;
            let phi = k as f32 * 2.399_963;
            let d = Vec3::new(
                (1.0 - z * z).sqrt() * phi.cos(),
                (1.0 - z * z).sqrt() * phi.sin(),
                z,
            );
            let u = d.any_orthonormal_vector();
            let v = d.cross(u);
            let c = d * r;
            let s = 0.2 * r;
            t.add_polygon(
                &[c + u * s, c + v * s, c - u * s - v * s],
                Vec3::ZERO,
                Colour::default(),
            );
        }
        ranges.push((first, n));
    }
    // Node `k` holds layer `k` (the root, node 0, the outermost); its child is node `k + 1`.
    for (k, &range) in ranges.iter().enumerate() {
        let child = (k + 1 < ranges.len()).then_some(k as u32 + 1);
        convex(&mut t, range, child);
    }
    t
}

proptest! {
    /// Convex nodes below, at and above the 32 polygons the first scan remembers: the walk
    /// matches the recursive definition, front to back is its reverse.
    #[test]
    fn large_convex_nodes_match_the_recursive_order(
        x in eye_coord(), y in eye_coord(), z in eye_coord(),
        outer in 1u32..140, inner in 1u32..80,
    ) {
        let t = nested_spheres(&[(outer, 2.0), (inner, 1.0)]);
        let eye = Vec3::new(x, y, z) * 1.5;
        let mut want = Vec::new();
        recursive_btf(&t, t.root(), eye, &mut want);
        prop_assert_eq!(want.len(), t.polygons.len());
        prop_assert_eq!(btf(&t, eye), want.clone());
        want.reverse();
        prop_assert_eq!(order_of(&t, eye, Order::FrontToBack), want);
    }
}

proptest! {
    /// Polygons marked as bounding a solid (inside on their interior or exterior side, or
    /// neither), with those seen from behind hidden: both orders skip exactly them, keep the
    /// others in the recursive order, and stay each other's reverse, below, at and above the 32
    /// polygons the first scan remembers. Without `hidden` every polygon comes.
    #[test]
    fn polygons_seen_from_behind_are_skipped_in_both_orders(
        x in eye_coord(), y in eye_coord(), z in eye_coord(),
        outer in 1u32..140, inner in 1u32..80, marks in any::<u64>(),
    ) {
        let mut t = nested_spheres(&[(outer, 2.0), (inner, 1.0)]);
        for (k, p) in t.polygons.iter_mut().enumerate() {
            p.flags |= [0, INSIDE_INTERIOR, INSIDE_EXTERIOR, INSIDE_INTERIOR][(marks >> (k % 32 * 2)) as usize & 3];
        }
        let eye = Vec3::new(x, y, z) * 1.5;
        let everything = btf(&t, eye);
        prop_assert_eq!(everything.len(), t.polygons.len());
        t.hidden = INSIDE_INTERIOR | INSIDE_EXTERIOR;
        let mut want = Vec::new();
        recursive_btf(&t, t.root(), eye, &mut want);
        let side_eye = t.side_eye(eye);
        let behind = |p: u32| {
            let polygon = t.polygon(p);
            let seen = sees_interior(&polygon, t.eye_side(&polygon, &side_eye));
            let inside = if seen { INSIDE_INTERIOR } else { INSIDE_EXTERIOR };
            polygon.flags & inside != 0
        };
        let kept: Vec<u32> = everything.iter().copied().filter(|&p| !behind(p)).collect();
        prop_assert_eq!(&want, &kept);
        prop_assert_eq!(btf(&t, eye), want.clone());
        want.reverse();
        prop_assert_eq!(order_of(&t, eye, Order::FrontToBack), want);
    }
}

#[test]
fn non_negative_bits_is_the_comparison_at_the_edges() {
    let edges = [
        0.0f32,
        -0.0,
        f32::MIN_POSITIVE,
        -f32::MIN_POSITIVE,
        f32::from_bits(1),
        f32::from_bits(0x8000_0001),
        1.0,
        -1.0,
        f32::MAX,
        f32::MIN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        -f32::NAN,
        f32::from_bits(0x7f80_0001),
        f32::from_bits(0xff80_0001),
    ];
    for x in edges {
        assert_eq!(
            non_negative_bits(x),
            x >= 0.0,
            "{x:?} ({:#010x})",
            x.to_bits()
        );
        assert_eq!(non_negative(x), x >= 0.0, "{x:?}");
    }
}

proptest! {
    #[test]
    fn non_negative_bits_is_the_comparison(bits in any::<u32>()) {
        let x = f32::from_bits(bits);
        prop_assert_eq!(non_negative_bits(x), x >= 0.0);
    }
}
