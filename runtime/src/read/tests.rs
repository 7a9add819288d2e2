//! Reader tests against a hand-written encoder that follows `formats/peel.md` byte by byte
//! (independent of the compiler's bincode writer, which has its own round-trip test).

extern crate std;

use std::vec::Vec;

use glam::Vec3;
use proptest::prelude::*;

use super::layout::*;
use super::*;

/// A file as plain fields, encoded by [`Spec::encode`] exactly as the spec says.
#[derive(Clone)]
struct Spec {
    magic: [u8; 4],
    version: u16,
    flags: u16,
    counts: Option<[u32; 5]>,
    max_depth: u32,
    max_polygon_vertices: u32,
    centre: [f64; 3],
    bounds: [[f32; 3]; 2],
    vertices: Vec<[f32; 3]>,
    planes: Vec<[f32; 4]>,
    indices: Vec<u32>,
    /// plane, first_index, vertex_count, flags, colour
    polygons: Vec<(u32, u32, u16, u8, [u8; 3])>,
    ids: Vec<u32>,
    /// kind, a, b, c, parent
    nodes: Vec<(u8, u32, u32, u32, u32)>,
    /// Palette colours (with `PALETTE`, a polygon's colour field holds its index: byte 0, or
    /// bytes 0-1 with `PALETTE16`).
    palette: Vec<[u8; 3]>,
    /// Node boxes.
    boxes: Vec<[f32; 6]>,
    /// Per node with `BOUNDS`: its box index or `NONE`.
    node_boxes: Vec<u32>,
    /// Header palette and bounds counts, when not the lengths.
    extra_counts: Option<[u32; 2]>,
}

impl Spec {
    /// A split at x = 0.5 with a convex set of two polygons in front and one behind.
    fn small() -> Spec {
        Spec {
            magic: MAGIC,
            version: FORMAT_VERSION,
            flags: header_flags::IDS,
            counts: None,
            max_depth: 2,
            max_polygon_vertices: 4,
            centre: [10.0, -20.0, 30.5],
            bounds: [[0.0; 3], [1.0; 3]],
            vertices: std::vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [0.0, 1.0, 1.0],
            ],
            planes: std::vec![
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0, 1.0],
                [1.0, 0.0, 0.0, 0.5]
            ],
            indices: std::vec![0, 1, 2, 3, 4, 5, 6, 4, 6, 5],
            polygons: std::vec![
                (0, 0, 4, polygon_flags::INTERIOR_FRONT, [10, 20, 30]),
                (1, 4, 3, polygon_flags::FLIPPED, [40, 50, 60]),
                (1, 7, 3, 0, [70, 80, 90]),
            ],
            ids: std::vec![7, 8, 9],
            nodes: std::vec![
                (node_kind::SPLIT, 2, 1, 2, NONE),
                (node_kind::CONVEX, 0, 2, NONE, 0),
                (node_kind::CONVEX, 2, 1, NONE, 0),
            ],
            palette: Vec::new(),
            boxes: Vec::new(),
            node_boxes: Vec::new(),
            extra_counts: None,
        }
    }

    /// [`Spec::small`] with every optional part: u16 indices, a u8 palette, node bounds.
    fn small_with_everything() -> Spec {
        let mut spec = Spec::small();
        spec.flags |= header_flags::INDEX16 | header_flags::PALETTE | header_flags::BOUNDS;
        spec.palette = std::vec![[10, 20, 30], [40, 50, 60]];
        for (k, p) in spec.polygons.iter_mut().enumerate() {
            p.4 = [(k % 2) as u8, 0, 0];
        }
        spec.boxes = std::vec![
            [0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            [0.0, 0.0, 1.0, 1.0, 1.0, 1.0]
        ];
        spec.node_boxes = std::vec![0, NONE, 1];
        spec
    }

    /// A chain of `n` convex nodes, one triangle each.
    fn chain(n: u32) -> Spec {
        let mut spec = Spec::small();
        spec.flags = 0;
        spec.ids.clear();
        spec.max_depth = n;
        spec.max_polygon_vertices = 3;
        spec.indices.clear();
        spec.polygons.clear();
        spec.nodes.clear();
        for i in 0..n {
            spec.indices.extend([0, 1, 2]);
            spec.polygons.push((0, 3 * i, 3, 0, [1, 2, 3]));
            let child = if i + 1 < n { i + 1 } else { NONE };
            let parent = if i == 0 { NONE } else { i - 1 };
            spec.nodes.push((node_kind::CONVEX, i, 1, child, parent));
        }
        spec
    }

    fn encode(&self) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend(self.magic);
        out.extend(self.version.to_le_bytes());
        out.extend(self.flags.to_le_bytes());
        let counts = self.counts.unwrap_or([
            self.vertices.len() as u32,
            self.planes.len() as u32,
            self.indices.len() as u32,
            self.polygons.len() as u32,
            self.nodes.len() as u32,
        ]);
        for v in counts
            .into_iter()
            .chain([self.max_depth, self.max_polygon_vertices])
        {
            out.extend(v.to_le_bytes());
        }
        for v in self.centre {
            out.extend(v.to_le_bytes());
        }
        for v in self.bounds.iter().flatten() {
            out.extend(v.to_le_bytes());
        }
        let extra = self
            .extra_counts
            .unwrap_or([self.palette.len() as u32, self.boxes.len() as u32]);
        for v in extra {
            out.extend(v.to_le_bytes());
        }
        assert_eq!(out.len(), HEADER_SIZE);
        let length = |out: &mut Vec<u8>, n: usize| out.extend((n as u64).to_le_bytes());
        length(&mut out, self.vertices.len());
        for v in self.vertices.iter().flatten() {
            out.extend(v.to_le_bytes());
        }
        length(&mut out, self.planes.len());
        for v in self.planes.iter().flatten() {
            out.extend(v.to_le_bytes());
        }
        length(&mut out, self.indices.len());
        for &v in &self.indices {
            if self.flags & header_flags::INDEX16 != 0 {
                out.extend((v as u16).to_le_bytes());
            } else {
                out.extend(v.to_le_bytes());
            }
        }
        length(&mut out, self.polygons.len());
        for &(plane, first, count, flags, colour) in &self.polygons {
            out.extend(plane.to_le_bytes());
            out.extend(first.to_le_bytes());
            out.extend(count.to_le_bytes());
            out.push(flags);
            let colour_size = polygon_size(self.flags) - 11;
            out.extend(&colour[..colour_size]);
        }
        length(&mut out, self.ids.len());
        for v in &self.ids {
            out.extend(v.to_le_bytes());
        }
        length(&mut out, self.palette.len());
        for c in &self.palette {
            out.extend(c);
        }
        length(&mut out, self.boxes.len());
        for v in self.boxes.iter().flatten() {
            out.extend(v.to_le_bytes());
        }
        length(&mut out, self.nodes.len());
        for (i, &(kind, a, b, c, parent)) in self.nodes.iter().enumerate() {
            out.push(kind);
            for v in [a, b, c, parent] {
                out.extend(v.to_le_bytes());
            }
            if self.flags & header_flags::BOUNDS != 0 {
                out.extend(
                    self.node_boxes
                        .get(i)
                        .copied()
                        .unwrap_or(NONE)
                        .to_le_bytes(),
                );
            }
        }
        out
    }

    /// Byte offset of node `i`'s record.
    fn node_offset(&self, i: usize) -> usize {
        self.encode().len() - (self.nodes.len() - i) * node_size(self.flags)
    }

    fn parse(&self) -> Result<(), ReadError> {
        Scene::parse(&self.encode()).map(|_| ())
    }
}

#[test]
fn small_file_reads_back_every_field() {
    let bytes = Spec::small().encode();
    let scene = Scene::parse(&bytes).unwrap();
    let header = scene.header();
    assert_eq!(header.version, FORMAT_VERSION);
    assert_eq!(header.flags, header_flags::IDS);
    assert_eq!(
        [
            header.vertex_count,
            header.plane_count,
            header.index_count,
            header.polygon_count
        ],
        [7, 3, 10, 3]
    );
    assert_eq!(
        (
            header.node_count,
            header.max_depth,
            header.max_polygon_vertices
        ),
        (3, 2, 4)
    );
    assert_eq!(header.centre, [10.0, -20.0, 30.5]);
    assert_eq!(
        (header.bounds_min, header.bounds_max),
        (Vec3::ZERO, Vec3::ONE)
    );
    assert_eq!(scene.root(), Some(0));
    assert_eq!(
        scene.node(0),
        Node::Split {
            plane: 2,
            front: Some(1),
            back: Some(2)
        }
    );
    assert_eq!(
        scene.node(1),
        Node::Convex {
            first: 0,
            count: 2,
            child: None
        }
    );
    assert_eq!(scene.parent(2), Some(0));
    assert_eq!(scene.parent(0), None);
    let p1 = scene.polygon(1);
    let expected = Polygon {
        plane: 1,
        first_index: 4,
        vertex_count: 3,
        flags: polygon_flags::FLIPPED,
        colour: Colour::new(40, 50, 60),
    };
    assert_eq!(p1, expected);
    assert_eq!(scene.polygon_vertex(&p1, 1), Vec3::new(1.0, 0.0, 1.0));
    assert_eq!(
        scene.polygon_vertex(&scene.polygon(2), 2),
        Vec3::new(1.0, 0.0, 1.0)
    );
    assert_eq!(scene.vertex(2), Vec3::new(1.0, 1.0, 0.0));
    assert_eq!(
        scene.plane(2),
        Plane {
            normal: Vec3::X,
            d: 0.5
        }
    );
    assert_eq!(scene.plane(2).distance(Vec3::new(2.0, 5.0, 5.0)), 1.5);
    assert_eq!([scene.id(0), scene.id(2)], [Some(7), Some(9)]);
}

#[test]
fn accessors_are_total_out_of_range() {
    let bytes = Spec::small().encode();
    let scene = Scene::parse(&bytes).unwrap();
    for i in [3, 1000, u32::MAX] {
        assert_eq!(scene.node(i), Node::EMPTY);
        assert_eq!(scene.parent(i), None);
        assert_eq!(scene.polygon(i), Polygon::default());
        assert_eq!(scene.vertex(i.saturating_add(4)), Vec3::ZERO);
        assert_eq!(scene.plane(i), Plane::default());
        assert_eq!(scene.id(i), None);
        assert_eq!(
            scene.polygon_vertex(&scene.polygon(0), i.saturating_add(1)),
            Vec3::ZERO
        );
    }
    let forged = Polygon {
        first_index: u32::MAX,
        vertex_count: 9,
        ..Polygon::default()
    };
    assert_eq!(scene.polygon_vertex(&forged, 3), Vec3::ZERO);
}

#[test]
fn ids_absent_without_the_flag() {
    let mut spec = Spec::small();
    spec.flags = 0;
    spec.ids.clear();
    let bytes = spec.encode();
    assert_eq!(Scene::parse(&bytes).unwrap().id(0), None);
    // Ids present but the flag clear: the ids length disagrees with the header.
    spec.ids = std::vec![1, 2, 3];
    assert!(matches!(spec.parse(), Err(ReadError::CountMismatch { .. })));
}

#[test]
fn empty_tree_is_valid() {
    let mut spec = Spec::small();
    spec.flags = 0;
    spec.ids.clear();
    spec.indices.clear();
    spec.polygons.clear();
    spec.nodes.clear();
    spec.max_depth = 0;
    let bytes = spec.encode();
    let scene = Scene::parse(&bytes).unwrap();
    assert_eq!(scene.root(), None);
    assert_eq!(scene.node(0), Node::EMPTY);
}

#[test]
fn every_strict_prefix_is_truncated() {
    let bytes = Spec::small().encode();
    for len in 0..bytes.len() {
        let err = Scene::parse(&bytes[..len]).unwrap_err();
        assert!(
            matches!(err, ReadError::Truncated { offset } if offset <= len),
            "{len}: {err:?}"
        );
    }
}

#[test]
fn trailing_bytes_are_refused() {
    let mut bytes = Spec::small().encode();
    let len = bytes.len();
    bytes.push(0);
    assert_eq!(
        Scene::parse(&bytes).unwrap_err(),
        ReadError::TrailingBytes { offset: len }
    );
}

#[test]
fn header_identity_is_checked_first() {
    let mut spec = Spec::small();
    spec.magic = *b"PEEK";
    assert_eq!(spec.parse(), Err(ReadError::BadMagic));
    assert_eq!(Scene::parse(b"PNG").unwrap_err(), ReadError::BadMagic);
    let mut spec = Spec::small();
    spec.version = 2;
    assert_eq!(
        spec.parse(),
        Err(ReadError::UnsupportedVersion { version: 2 })
    );
    assert_eq!(
        Scene::parse(&spec.encode()[..6]).unwrap_err(),
        ReadError::UnsupportedVersion { version: 2 }
    );
    let mut spec = Spec::small();
    spec.flags = 0b10_0000;
    assert_eq!(
        spec.parse(),
        Err(ReadError::UnknownFlags { flags: 0b10_0000 })
    );
}

#[test]
fn optional_parts_read_back() {
    let spec = Spec::small_with_everything();
    let bytes = spec.encode();
    let plain = Spec::small().encode();
    // u16 indices (-20), 12-byte polygons (-6), 21-byte nodes (+12), palette (+6), boxes (+48).
    assert_eq!(bytes.len(), plain.len() - 20 - 6 + 12 + 6 + 48);
    let scene = Scene::parse(&bytes).unwrap();
    let plain = Scene::parse(&plain).unwrap();
    for i in 0..3 {
        let (p, q) = (scene.polygon(i), plain.polygon(i));
        assert_eq!(
            (p.plane, p.first_index, p.vertex_count, p.flags),
            (q.plane, q.first_index, q.vertex_count, q.flags)
        );
        for k in 0..u32::from(p.vertex_count) {
            assert_eq!(scene.polygon_vertex(&p, k), plain.polygon_vertex(&q, k));
        }
        assert_eq!(scene.node(i), plain.node(i));
    }
    assert_eq!(scene.polygon(0).colour, Colour::new(10, 20, 30));
    assert_eq!(scene.polygon(1).colour, Colour::new(40, 50, 60));
    assert_eq!(scene.polygon(2).colour, Colour::new(10, 20, 30));
    assert_eq!(scene.node_bounds(0), Some((Vec3::ZERO, Vec3::ONE)));
    assert_eq!(scene.node_bounds(1), None);
    assert_eq!(
        scene.node_bounds(2),
        Some((Vec3::new(0.0, 0.0, 1.0), Vec3::ONE))
    );
    assert_eq!(plain.node_bounds(0), None);
    assert_eq!(scene.node_bounds(3), None);
    // A u16 palette index.
    let mut spec = Spec::small_with_everything();
    spec.flags |= header_flags::PALETTE16;
    spec.polygons[2].4 = [1, 0, 0];
    let scene_bytes = spec.encode();
    let scene = Scene::parse(&scene_bytes).unwrap();
    assert_eq!(scene.polygon(2).colour, Colour::new(40, 50, 60));
}

#[test]
fn inconsistent_optional_parts_are_refused() {
    let mut spec = Spec::small();
    spec.flags |= header_flags::PALETTE16;
    assert_eq!(
        spec.parse(),
        Err(ReadError::InconsistentFlags { flags: spec.flags })
    );
    let cases: [fn(&mut Spec); 9] = [
        // A palette without its flag, and the flag without a palette.
        |s| s.palette.push([1, 2, 3]),
        |s| {
            s.flags |= header_flags::PALETTE;
            s.extra_counts = Some([0, 0]);
        },
        // Boxes without the flag.
        |s| s.boxes.push([0.0; 6]),
        // A palette index out of range.
        |s| {
            *s = Spec::small_with_everything();
            s.polygons[1].4 = [2, 0, 0];
        },
        // A box index out of range.
        |s| {
            *s = Spec::small_with_everything();
            s.node_boxes[1] = 2;
        },
        // A box with min > max, and a non-finite one.
        |s| {
            *s = Spec::small_with_everything();
            s.boxes[1][2] = 2.0;
        },
        |s| {
            *s = Spec::small_with_everything();
            s.boxes[0][4] = f32::NAN;
        },
        // A palette count beyond what a u8 index can name.
        |s| {
            *s = Spec::small_with_everything();
            s.palette = std::vec![[0; 3]; 257];
        },
        // u16 indices with more than 2^16 vertices.
        |s| {
            *s = Spec::small_with_everything();
            s.vertices = std::vec![[0.0; 3]; (1 << 16) + 1];
        },
    ];
    for (k, case) in cases.into_iter().enumerate() {
        let mut spec = Spec::small();
        case(&mut spec);
        assert!(
            matches!(
                spec.parse(),
                Err(ReadError::BadRecord { .. } | ReadError::CountMismatch { .. })
            ),
            "case {k}: {:?}",
            spec.parse()
        );
    }
    // The header counts must match the arrays.
    let mut spec = Spec::small_with_everything();
    spec.extra_counts = Some([2, 1]);
    assert!(matches!(spec.parse(), Err(ReadError::CountMismatch { .. })));
}

#[test]
fn counts_must_match_array_lengths() {
    let mut spec = Spec::small();
    spec.counts = Some([7, 3, 10, 3, 4]);
    // The node array length field follows the ids: 4 node records would be needed.
    let ids_end = spec.encode().len() - 3 * NODE_SIZE - LENGTH_SIZE;
    assert_eq!(
        spec.parse(),
        Err(ReadError::CountMismatch { offset: ids_end })
    );
    spec.counts = Some([8, 3, 10, 3, 3]);
    assert_eq!(
        spec.parse(),
        Err(ReadError::CountMismatch {
            offset: HEADER_SIZE
        })
    );
}

#[test]
fn non_finite_or_out_of_bounds_floats_are_refused() {
    let cases: [fn(&mut Spec); 6] = [
        |s| s.centre[1] = f64::NAN,
        |s| s.bounds[0][2] = f32::NEG_INFINITY,
        |s| s.bounds = [[1.0; 3], [0.0; 3]],
        |s| s.vertices[3][0] = f32::NAN,
        |s| s.vertices[3][0] = 1.5,
        |s| s.planes[1][3] = f32::INFINITY,
    ];
    for case in cases {
        let mut spec = Spec::small();
        case(&mut spec);
        assert!(matches!(spec.parse(), Err(ReadError::BadRecord { .. })));
    }
}

/// Files from earlier compilers flag the polygons of closed meshes one-sided: they still read,
/// and the flag is no more than a bit the renderer ignores.
#[test]
fn the_legacy_one_sided_flag_is_accepted() {
    let mut spec = Spec::small();
    for p in &mut spec.polygons {
        p.3 |= polygon_flags::LEGACY_ONE_SIDED;
    }
    let bytes = spec.encode();
    let scene = Scene::parse(&bytes).expect("a legacy flag is valid");
    assert_ne!(scene.polygon(0).flags & polygon_flags::LEGACY_ONE_SIDED, 0);
}

#[test]
fn out_of_range_records_are_refused_at_their_offset() {
    let node_cases: [fn(&mut Spec); 9] = [
        |s| s.nodes[0].0 = 7, // unknown kind
        |s| s.nodes[0].1 = 3, // split plane out of range
        |s| s.nodes[0].3 = 1, // front == back
        |s| s.nodes[2].2 = 0, // empty convex set
        |s| s.nodes[2].1 = 1, // polygons owned twice
        |s| s.nodes[1].3 = 2, // 2 would have two parents
        |s| s.nodes[2].4 = 1, // parent that does not name it
        |s| s.nodes[0].4 = 1, // the root has a parent
        |s| s.nodes[1].3 = 7, // child beyond the array
    ];
    for (k, case) in node_cases.into_iter().enumerate() {
        let mut spec = Spec::small();
        case(&mut spec);
        let err = spec.parse().unwrap_err();
        assert!(
            matches!(err, ReadError::BadRecord { offset } if offset >= spec.node_offset(0)),
            "case {k}: {err:?}"
        );
    }
    let polygon_cases: [fn(&mut Spec); 6] = [
        |s| s.polygons[1].0 = 3,        // plane out of range
        |s| s.polygons[1].3 = 0b1000,   // unknown flag
        |s| s.polygons[1].1 = 3,        // not right after the previous polygon
        |s| s.max_polygon_vertices = 3, // polygon 0 has 4 vertices
        |s| s.indices[3] = 7,           // vertex out of range
        |s| {
            s.polygons[2].2 = 2;
            s.indices.pop();
        }, // fewer than 3 vertices
    ];
    for (k, case) in polygon_cases.into_iter().enumerate() {
        let mut spec = Spec::small();
        case(&mut spec);
        assert!(
            matches!(spec.parse(), Err(ReadError::BadRecord { .. })),
            "case {k}"
        );
    }
    // An index that belongs to no polygon.
    let mut spec = Spec::small();
    spec.indices.push(0);
    assert!(matches!(spec.parse(), Err(ReadError::BadRecord { .. })));
}

#[test]
fn child_before_parent_and_cycles_are_refused() {
    // Node 1 and 2 swap roles: 2's child is 1, which comes before it.
    let mut spec = Spec::small();
    spec.nodes[0] = (node_kind::SPLIT, 2, 2, NONE, NONE);
    spec.nodes[1] = (node_kind::CONVEX, 0, 2, NONE, 2);
    spec.nodes[2] = (node_kind::CONVEX, 2, 1, 1, 0);
    assert_eq!(
        spec.parse(),
        Err(ReadError::BadRecord {
            offset: spec.node_offset(1)
        })
    );
    // A cycle 1 -> 2 -> 1 under the root.
    let mut spec = Spec::small();
    spec.nodes[0] = (node_kind::SPLIT, 2, 1, NONE, NONE);
    spec.nodes[1] = (node_kind::CONVEX, 0, 2, 2, 2);
    spec.nodes[2] = (node_kind::CONVEX, 2, 1, 1, 1);
    assert!(matches!(spec.parse(), Err(ReadError::BadRecord { .. })));
    // A self loop.
    let mut spec = Spec::small();
    spec.nodes[2].3 = 2;
    assert!(matches!(spec.parse(), Err(ReadError::BadRecord { .. })));
}

#[test]
fn depth_is_checked_without_recursion() {
    let deep = 200_000;
    let mut spec = Spec::chain(deep);
    let bytes = spec.encode();
    let scene = Scene::parse(&bytes).unwrap();
    assert_eq!(
        scene.node(deep - 1),
        Node::Convex {
            first: deep - 1,
            count: 1,
            child: None
        }
    );
    spec.max_depth = deep - 1;
    assert_eq!(
        spec.parse(),
        Err(ReadError::TooDeep {
            max_depth: deep - 1
        })
    );
    // A header bound above the real depth is allowed.
    let mut spec = Spec::small();
    spec.max_depth = 3;
    assert_eq!(spec.parse(), Ok(()));
    spec.max_depth = 1;
    assert_eq!(spec.parse(), Err(ReadError::TooDeep { max_depth: 1 }));
}

#[test]
fn depth_walk_visits_both_sides_of_splits() {
    // root split: front = convex leaf, back = convex -> convex -> convex (depth 4).
    let mut spec = Spec::chain(4);
    spec.polygons.pop();
    spec.indices.truncate(9);
    spec.nodes = std::vec![
        (node_kind::SPLIT, 2, 1, 2, NONE),
        (node_kind::CONVEX, 0, 1, NONE, 0),
        (node_kind::CONVEX, 1, 1, 3, 0),
        (node_kind::CONVEX, 2, 1, NONE, 2),
    ];
    spec.max_depth = 3;
    assert_eq!(spec.parse(), Ok(()));
    spec.max_depth = 2;
    assert_eq!(spec.parse(), Err(ReadError::TooDeep { max_depth: 2 }));
}

#[test]
fn trusted_parse_reads_a_valid_file_like_parse() {
    for spec in [Spec::small(), Spec::small_with_everything()] {
        let bytes = spec.encode();
        let (a, b) = (
            Scene::parse(&bytes).unwrap(),
            Scene::parse_trusted(&bytes).unwrap(),
        );
        assert_eq!(a.header(), b.header());
        let h = a.header();
        for i in 0..h.node_count + 1 {
            assert_eq!((a.node(i), a.parent(i)), (b.node(i), b.parent(i)));
            assert_eq!(a.node_bounds(i), b.node_bounds(i));
        }
        for i in 0..h.polygon_count + 1 {
            let (p, q) = (a.polygon(i), b.polygon(i));
            assert_eq!((p, a.id(i)), (q, b.id(i)));
            for k in 0..u32::from(p.vertex_count) {
                assert_eq!(a.polygon_vertex(&p, k), b.polygon_vertex(&q, k));
            }
        }
    }
}

#[test]
fn trusted_parse_checks_header_and_layout_only() {
    let bytes = Spec::small().encode();
    // Header and layout errors: the same verdict as `parse`.
    for len in 0..bytes.len() {
        assert_eq!(
            Scene::parse_trusted(&bytes[..len]).unwrap_err(),
            Scene::parse(&bytes[..len]).unwrap_err()
        );
    }
    let mut trailing = bytes.clone();
    trailing.push(0);
    assert!(matches!(
        Scene::parse_trusted(&trailing),
        Err(ReadError::TrailingBytes { .. })
    ));
    let mut foreign = bytes.clone();
    foreign[0] = b'X';
    assert_eq!(
        Scene::parse_trusted(&foreign).unwrap_err(),
        ReadError::BadMagic
    );
    // A record out of range passes: that is `parse`'s linear-time work.
    let mut spec = Spec::small();
    spec.polygons[0].0 = 99; // plane index
    let bytes = spec.encode();
    assert!(matches!(
        Scene::parse(&bytes),
        Err(ReadError::BadRecord { .. })
    ));
    let scene = Scene::parse_trusted(&bytes).unwrap();
    assert_eq!(scene.plane(99), Plane::default());
    render_untrusted(&scene);
}

/// Render what `parse_trusted` accepted, front to back and back to front, through the `f32`
/// view: it must end (an image or a typed error), never panic or hang.
fn render_untrusted(scene: &Scene<'_>) {
    use crate::coverage::Coverage;
    use crate::render::{Renderer, Workspace};
    use crate::target::SpanSink;
    use crate::traverse::Order;
    struct Count(u64);
    impl SpanSink for Count {
        fn span(&mut self, _: u32, x_start: u32, x_end: u32, _: Colour) {
            self.0 += u64::from(x_end - x_start);
        }
    }
    let view = crate::camera::LocalView::look_at(
        Vec3::new(2.0, 1.5, 3.0),
        Vec3::splat(0.5),
        Vec3::Y,
        20.0,
        16,
        12,
        0.01,
    )
    .unwrap();
    for order in [Order::BackToFront, Order::FrontToBack] {
        let mut intervals = [(0u16, 0u16); 2 * 12];
        let mut counts = [0u16; 12];
        let cov = Coverage::new(&mut intervals, &mut counts, 16, 12).unwrap();
        let mut sink = Count(0);
        let mut ws = Workspace::<8, 16>::new();
        let mut renderer = Renderer::new(&mut ws).span_memory(cov);
        if order == Order::BackToFront {
            renderer = renderer.back_to_front();
        }
        let _ = renderer.draw(scene, &view, &mut sink);
    }
}

/// After a successful parse, read everything (and a little beyond) through the accessors.
fn exercise(scene: &Scene<'_>) {
    let h = scene.header();
    for i in 0..h.node_count.saturating_add(2) {
        let _ = (scene.node(i), scene.parent(i));
    }
    for i in 0..h.polygon_count.saturating_add(2) {
        let p = scene.polygon(i);
        for k in 0..u32::from(p.vertex_count) + 1 {
            let _ = scene.polygon_vertex(&p, k);
        }
        let _ = (scene.plane(p.plane), scene.id(i));
    }
    let _ = scene.vertex(h.vertex_count);
}

proptest! {
    /// A record's offset is the checked product and sum, on every core's path (ARMv6-M's
    /// without a 64-bit multiply, the others').
    #[test]
    fn element_offsets_are_checked_arithmetic(
        start in any::<usize>(),
        size in prop_oneof![0usize..300, any::<usize>()],
        index in prop_oneof![0u32..(1 << 24) + 10, any::<u32>()],
    ) {
        let want = (index as usize).checked_mul(size).and_then(|o| o.checked_add(start));
        prop_assert_eq!(element(start, size, index), want);
        prop_assert_eq!(element_narrow(start, size, index), want);
    }
}

proptest! {
    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
        if let Ok(scene) = Scene::parse(&bytes) {
            exercise(&scene);
        }
    }

    #[test]
    fn random_bytes_behind_a_valid_header_never_panic(
        tail in proptest::collection::vec(any::<u8>(), 0..600)
    ) {
        let mut bytes = Spec::small().encode();
        bytes.truncate(HEADER_SIZE);
        bytes.extend(tail);
        if let Ok(scene) = Scene::parse(&bytes) {
            exercise(&scene);
        }
    }

    #[test]
    fn mutations_never_panic(
        edits in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>(), 0u8..3), 1..6)
    ) {
        let mut bytes = Spec::small().encode();
        for (at, value, how) in edits {
            let i = at.index(bytes.len());
            match how {
                0 => bytes[i] = value,
                1 => bytes[i] ^= 1 << (value % 8),
                _ => bytes[i] = if value % 2 == 0 { 0 } else { 0xff },
            }
        }
        if let Ok(scene) = Scene::parse(&bytes) {
            exercise(&scene);
        }
        // The trusted reader accepts more of these; they still read and render safely.
        if let Ok(scene) = Scene::parse_trusted(&bytes) {
            exercise(&scene);
            render_untrusted(&scene);
        }
    }

    #[test]
    fn trusted_random_bytes_behind_a_valid_layout_never_panic_or_hang(
        records in proptest::collection::vec(any::<u8>(), 0..400),
        which in any::<bool>(),
    ) {
        // The layout of a valid file (header and array lengths) with random records.
        let spec = if which { Spec::small() } else { Spec::small_with_everything() };
        let mut bytes = spec.encode();
        let layout = Scene::parse_trusted(&bytes).unwrap();
        let h = layout.header;
        let arrays = [
            (layout.vertices, h.vertex_count as usize * VERTEX_SIZE),
            (layout.planes, h.plane_count as usize * PLANE_SIZE),
            (layout.indices, h.index_count as usize * layout.index_size),
            (layout.polygons, h.polygon_count as usize * layout.polygon_size),
            (layout.palette, h.palette_count as usize * PALETTE_SIZE),
            (layout.bounds, h.bounds_count as usize * BOUNDS_SIZE),
            (layout.nodes, h.node_count as usize * layout.node_size),
        ];
        let slots = arrays.iter().flat_map(|&(start, len)| start..start + len);
        for (at, r) in slots.zip(records) {
            bytes[at] = r;
        }
        if let Ok(scene) = Scene::parse_trusted(&bytes) {
            exercise(&scene);
            render_untrusted(&scene);
        }
    }
}
