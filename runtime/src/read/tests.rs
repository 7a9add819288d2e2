//! Reader tests against a hand-written encoder that follows `formats/peel.md` byte by byte
//! (independent of the compiler's bincode writer, which has its own round-trip test).

extern crate std;

use std::vec::Vec;

use glam::Vec3;
use proptest::prelude::*;

use super::layout::*;
use super::side::mul_wide_halves;
use super::*;
use crate::display::Colour;

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
    /// first_index, vertex_count, flags, colour
    polygons: Vec<(u32, u16, u8, [u8; 3])>,
    /// With `TWO_COLOURS`: each polygon's exterior colour field.
    exterior: Vec<[u8; 3]>,
    ids: Vec<u32>,
    /// kind, a, b, c, parent (as [`RawNode`] before the first child becomes implicit: convex
    /// a = first polygon, b = count, c = child; split a = plane, b = + child, c = - child)
    nodes: Vec<(u8, u32, u32, u32, u32)>,
    /// Palette colours (with `PALETTE`, a polygon's colour field holds its index: byte 0, or
    /// bytes 0-1 with `PALETTE16`).
    palette: Vec<[u8; 3]>,
    /// Node boxes (quantised on the header's bounds).
    boxes: Vec<[u16; 6]>,
    /// Per node with `BOUNDS`: its box index or `NONE`.
    node_boxes: Vec<u32>,
    /// Header palette and bounds counts, when not the lengths.
    extra_counts: Option<[u32; 2]>,
    /// With `SHADES`: per vertex, `[front, back]` (written after the nodes, with its length).
    shades: Vec<[u8; 2]>,
}

/// Flags every [`Spec`] carries: none, or in a build without `large-scenes` (which reads only
/// those) 16-bit fields and indices.
const BASE_FLAGS: u16 = if cfg!(feature = "large-scenes") {
    0
} else {
    header_flags::NARROW | header_flags::INDEX16
};

impl Spec {
    /// A split at x = 0.5 with a convex set of two polygons in front and one behind.
    fn small() -> Spec {
        Spec {
            magic: MAGIC,
            version: FORMAT_VERSION,
            flags: header_flags::IDS | BASE_FLAGS,
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
                (0, 4, polygon_flags::INTERIOR_FRONT, [10, 20, 30]),
                (4, 3, 0, [40, 50, 60]),
                (7, 3, 0, [70, 80, 90]),
            ],
            ids: std::vec![7, 8, 9],
            exterior: std::vec![[11, 21, 31], [41, 51, 61], [71, 81, 91]],
            nodes: std::vec![
                (node_kind::SPLIT, 2, 1, 2, NONE),
                (node_kind::CONVEX, 0, 2, NONE, 0),
                (node_kind::CONVEX, 2, 1, NONE, 0),
            ],
            palette: Vec::new(),
            boxes: Vec::new(),
            node_boxes: Vec::new(),
            extra_counts: None,
            shades: Vec::new(),
        }
    }

    /// [`Spec::small`] with every optional part: u16 indices, a u8 palette, node bounds, u16
    /// node and polygon fields.
    fn small_with_everything() -> Spec {
        let mut spec = Spec::small();
        spec.flags |= header_flags::INDEX16
            | header_flags::PALETTE
            | header_flags::BOUNDS
            | header_flags::NARROW;
        spec.palette = std::vec![[10, 20, 30], [40, 50, 60]];
        for (k, p) in spec.polygons.iter_mut().enumerate() {
            p.3 = [(k % 2) as u8, 0, 0];
        }
        let top = u16::MAX;
        spec.boxes = std::vec![[0, 0, 0, top, top, top], [0, 0, top, top, top, top]];
        spec.node_boxes = std::vec![0, NONE, 1];
        spec
    }

    /// A chain of `n` convex nodes, one triangle each.
    fn chain(n: u32) -> Spec {
        let mut spec = Spec::small();
        spec.flags = BASE_FLAGS;
        spec.ids.clear();
        spec.max_depth = n;
        spec.max_polygon_vertices = 3;
        spec.indices.clear();
        spec.polygons.clear();
        spec.nodes.clear();
        for i in 0..n {
            spec.indices.extend([0, 1, 2]);
            spec.polygons.push((3 * i, 3, 0, [1, 2, 3]));
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
        for v in &self.vertices {
            for (k, c) in v.iter().enumerate() {
                if self.flags & header_flags::WIDE_VERTICES != 0 {
                    out.extend(c.to_le_bytes());
                } else {
                    // The nearest step on the bounds (exact for the corners used here).
                    let (lo, hi) = (self.bounds[0][k], self.bounds[1][k]);
                    let t = if hi > lo { (c - lo) / (hi - lo) } else { 0.0 };
                    let q = (t * 65535.0).round().clamp(0.0, 65535.0) as u16;
                    out.extend(q.to_le_bytes());
                }
            }
        }
        length(&mut out, self.planes.len());
        for v in self.planes.iter().flatten() {
            out.extend(v.to_le_bytes());
        }
        length(&mut out, self.indices.len());
        for &v in &self.indices {
            let width = index_size(self.flags);
            out.extend(&v.to_le_bytes()[..width]);
        }
        let width = field_size(self.flags);
        let field = |out: &mut Vec<u8>, v: u32| {
            let v = if v == NONE { none_of_width(width) } else { v };
            out.extend(&v.to_le_bytes()[..width]);
        };
        length(&mut out, self.polygons.len());
        for (k, &(first, count, flags, colour)) in self.polygons.iter().enumerate() {
            field(&mut out, first);
            out.push(count as u8);
            out.push(flags);
            out.extend(&colour[..colour_size(self.flags)]);
            if self.flags & header_flags::TWO_COLOURS != 0 {
                out.extend(&self.exterior[k][..colour_size(self.flags)]);
            }
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
            // The first child is implicit: the next node, flagged in the kind byte.
            let (first, second) = if kind == node_kind::CONVEX {
                (c, b)
            } else {
                (b, c)
            };
            if first == NONE {
                out.push(kind);
            } else {
                assert_eq!(
                    first as usize,
                    i + 1,
                    "node {i}: a first child is the next node"
                );
                out.push(kind | node_kind::FIRST_CHILD);
            }
            for v in [a, second, parent] {
                field(&mut out, v);
            }
            if self.flags & header_flags::BOUNDS != 0 {
                field(&mut out, self.node_boxes.get(i).copied().unwrap_or(NONE));
            }
        }
        if self.flags & header_flags::SHADES != 0 {
            length(&mut out, self.shades.len());
            for s in &self.shades {
                out.extend(s);
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
    assert_eq!(header.flags, header_flags::IDS | BASE_FLAGS);
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
        first_index: 4,
        vertex_count: 3,
        flags: 0,
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
    spec.flags = BASE_FLAGS;
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
    spec.flags = BASE_FLAGS;
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
    // Versions 1 and 2 (the previous layouts) and a later one.
    for version in [1, 2, FORMAT_VERSION + 1, TRANSPARENT_VERSION + 1] {
        let mut spec = Spec::small();
        spec.version = version;
        assert_eq!(spec.parse(), Err(ReadError::UnsupportedVersion { version }));
        assert_eq!(
            Scene::parse(&spec.encode()[..6]).unwrap_err(),
            ReadError::UnsupportedVersion { version }
        );
    }
    let mut spec = Spec::small();
    spec.flags = 1 << 14;
    assert_eq!(
        spec.parse(),
        Err(ReadError::UnknownFlags { flags: 1 << 14 })
    );
    for both in [
        header_flags::NARROW | header_flags::MEDIUM,
        header_flags::INDEX16 | header_flags::INDEX24,
    ] {
        spec.flags = both;
        assert_eq!(
            spec.parse(),
            Err(ReadError::InconsistentFlags { flags: spec.flags })
        );
    }
    // Wider fields, indices or vertices are refused by a build without their feature, with
    // what is missing; the rest of this test reads them.
    for (flags, feature) in [
        (0, cfg!(feature = "large-scenes")),
        (header_flags::NARROW, cfg!(feature = "large-scenes")),
        (header_flags::INDEX16, cfg!(feature = "large-scenes")),
        (
            header_flags::NARROW | header_flags::INDEX16 | header_flags::WIDE_VERTICES,
            cfg!(feature = "wide-vertices"),
        ),
    ] {
        let mut spec = Spec::small();
        spec.flags = flags;
        let unsupported = Err(ReadError::UnsupportedFlags { flags });
        assert_eq!(spec.parse() == unsupported, !feature, "{flags:#x}");
    }
    if !cfg!(feature = "large-scenes") {
        return;
    }
    // u24 indices read the same vertices as u32 ones, a byte shorter each.
    let mut narrow = Spec::small();
    narrow.flags |= header_flags::INDEX24;
    let (plain, narrow) = (Spec::small().encode(), narrow.encode());
    assert_eq!(narrow.len() + Spec::small().indices.len(), plain.len());
    let (plain, narrow) = (
        Scene::parse(&plain).unwrap(),
        Scene::parse(&narrow).unwrap(),
    );
    for p in 0..3 {
        let (a, b) = (plain.polygon(p), narrow.polygon(p));
        for k in 0..u32::from(a.vertex_count) {
            assert_eq!(plain.polygon_vertex(&a, k), narrow.polygon_vertex(&b, k));
        }
    }
}

/// Against `u32` fields and indices.
#[test]
#[cfg_attr(not(feature = "large-scenes"), ignore = "u32 fields need large-scenes")]
fn optional_parts_read_back() {
    let spec = Spec::small_with_everything();
    let bytes = spec.encode();
    let plain = Spec::small().encode();
    // u16 indices (-20), 5-byte polygons for 9 (-12), 9-byte nodes for 13 (-12), palette (+6),
    // boxes (+24).
    assert_eq!(bytes.len(), plain.len() - 20 - 12 - 12 + 6 + 24);
    let scene = Scene::parse(&bytes).unwrap();
    let plain = Scene::parse(&plain).unwrap();
    for i in 0..3 {
        let (p, q) = (scene.polygon(i), plain.polygon(i));
        assert_eq!(
            (p.first_index, p.vertex_count, p.flags),
            (q.first_index, q.vertex_count, q.flags)
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
    // u24 fields read the same records.
    let mut medium = Spec::small_with_everything();
    medium.flags = medium.flags & !header_flags::NARROW | header_flags::MEDIUM;
    let medium_bytes = medium.encode();
    // A byte more per polygon field (1) and node field (4 with bounds), 3 of each.
    assert_eq!(medium_bytes.len(), bytes.len() + 3 + 3 * 4);
    let medium = Scene::parse(&medium_bytes).unwrap();
    for i in 0..3 {
        assert_eq!(medium.node(i), scene.node(i));
        assert_eq!(medium.parent(i), scene.parent(i));
        assert_eq!(medium.node_bounds(i), scene.node_bounds(i));
        assert_eq!(medium.polygon(i), scene.polygon(i));
    }
    // A u16 palette index.
    let mut spec = Spec::small_with_everything();
    spec.flags |= header_flags::PALETTE16;
    spec.polygons[2].3 = [1, 0, 0];
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
    let cases: [fn(&mut Spec); 10] = [
        // A palette without its flag, and the flag without a palette.
        |s| s.palette.push([1, 2, 3]),
        |s| {
            s.flags |= header_flags::PALETTE;
            s.extra_counts = Some([0, 0]);
        },
        // Boxes without the flag.
        |s| s.boxes.push([0; 6]),
        // A palette index out of range.
        |s| {
            *s = Spec::small_with_everything();
            s.polygons[1].3 = [2, 0, 0];
        },
        // A box index out of range.
        |s| {
            *s = Spec::small_with_everything();
            s.node_boxes[1] = 2;
        },
        // A box with min > max, and one whose decoded corner overflows.
        |s| {
            *s = Spec::small_with_everything();
            s.boxes[1][5] = 0;
        },
        |s| {
            *s = Spec::small_with_everything();
            s.bounds = [[-3e38; 3], [3e38; 3]];
            s.boxes[0][4] = 1;
        },
        // A palette count beyond what a u8 index can name.
        |s| {
            *s = Spec::small_with_everything();
            s.palette = std::vec![[0; 3]; 257];
        },
        // u16 fields with more than 65535 planes.
        |s| {
            *s = Spec::small_with_everything();
            s.planes = std::vec![[0.0; 4]; 1 << 16];
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
    let ids_end = spec.encode().len() - 3 * node_size(spec.flags) - LENGTH_SIZE;
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

/// Vertices stored as steps decode with [`dequantise`], as node boxes do, and wide ones are
/// read as they are.
#[test]
fn vertices_are_steps_on_the_bounds_or_f32() {
    let mut spec = Spec::small();
    spec.bounds = [[-2.0, 0.0, 0.0], [2.0, 3.0, 1.0]];
    spec.vertices[5] = [0.5, 1.0, 1.0];
    spec.vertices[1] = [2.0, 0.0, 0.0];
    spec.vertices[2] = [-2.0, 3.0, 1.0];
    let scene_bytes = spec.encode();
    let scene = Scene::parse(&scene_bytes).unwrap();
    // 0.5 is step 40959.375 of 65535 on [-2, 2]: step 40959 is read.
    let expected = Vec3::new(
        dequantise(-2.0, 2.0, 40959),
        dequantise(0.0, 3.0, 21845),
        1.0,
    );
    assert_eq!(scene.vertex(5), expected);
    assert!(
        (scene.vertex(5) - Vec3::new(0.5, 1.0, 1.0))
            .abs()
            .max_element()
            < 4.0 / 65535.0
    );
    // The ends are exact.
    assert_eq!(scene.vertex(1), Vec3::new(2.0, 0.0, 0.0));
    assert_eq!(scene.vertex(2), Vec3::new(-2.0, 3.0, 1.0));
    if !cfg!(feature = "wide-vertices") {
        return;
    }
    spec.flags |= header_flags::WIDE_VERTICES;
    let wide_bytes = spec.encode();
    assert_eq!(
        wide_bytes.len(),
        scene_bytes.len() + 6 * spec.vertices.len()
    );
    let wide = Scene::parse(&wide_bytes).unwrap();
    assert_eq!(wide.vertex(5), Vec3::new(0.5, 1.0, 1.0));
}

/// With `f32` vertices.
#[test]
#[cfg_attr(
    not(feature = "wide-vertices"),
    ignore = "f32 vertices need wide-vertices"
)]
fn non_finite_or_out_of_bounds_floats_are_refused() {
    let cases: [fn(&mut Spec); 7] = [
        |s| s.centre[1] = f64::NAN,
        |s| s.bounds[0][2] = f32::NEG_INFINITY,
        |s| s.bounds = [[1.0; 3], [0.0; 3]],
        // Finite bounds whose extent is not: a step would decode to infinity.
        |s| s.bounds = [[-3e38; 3], [3e38; 3]],
        |s| s.vertices[3][0] = f32::NAN,
        |s| s.vertices[3][0] = 1.5,
        |s| s.planes[1][3] = f32::INFINITY,
    ];
    for case in cases {
        // Vertices as f32, so that they can be out of bounds or not finite.
        let mut spec = Spec::small();
        spec.flags |= header_flags::WIDE_VERTICES;
        case(&mut spec);
        assert!(matches!(spec.parse(), Err(ReadError::BadRecord { .. })));
    }
}

/// A polygon's plane is the plane through its first three vertices, oriented by their order:
/// the + side that `INTERIOR_FRONT` names is where `(v1 - v0) x (v2 - v0)` points. Steps and
/// `f32` vertices give the same sides.
#[test]
fn a_polygon_plane_is_through_its_first_three_vertices() {
    let mut spec = Spec::small();
    spec.bounds = [[0.0, 0.0, -2.0], [1.0, 1.0, 1.0]];
    for wide in [false, true] {
        if wide && !cfg!(feature = "wide-vertices") {
            continue;
        }
        if wide {
            spec.flags |= header_flags::WIDE_VERTICES;
        }
        let bytes = spec.encode();
        let scene = Scene::parse(&bytes).unwrap();
        let side = |p, eye| scene.eye_side(&scene.polygon(p), &scene.side_eye(eye));
        // Polygon 0: (0,0,0), (1,0,0), (1,1,0), (0,1,0): normal +z.
        assert_eq!(side(0, Vec3::new(0.3, 0.3, 0.5)), Side::Front);
        assert_eq!(side(0, Vec3::new(5.0, -3.0, -0.001)), Side::Back);
        assert_eq!(side(0, Vec3::new(7.0, 3.0, 0.0)), Side::On);
        // Polygon 2: (0,0,1), (0,1,1), (1,0,1): normal -z, through z = 1.
        assert_eq!(side(2, Vec3::new(0.3, 0.3, 0.5)), Side::Front);
        assert_eq!(side(2, Vec3::new(0.3, 0.3, 1.5)), Side::Back);
    }
    // Collinear first vertices give a zero normal: every point is on the plane.
    assert_eq!(
        Plane::through(Vec3::ZERO, Vec3::X, Vec3::X * 2.0),
        Plane::default()
    );
}

proptest! {
    /// ARMv6-M's decoding scales by moving the exponent: the product, for every `n` and
    /// power of two a grid allows.
    #[test]
    fn scaling_by_the_exponent_is_the_product(
        n in -(1i32 << 24) + 1..1 << 24,
        shift in -126i32..=104,
    ) {
        let product = (f64::from(n) * 2f64.powi(shift)) as f32;
        prop_assert_eq!(scaled_by_exponent(n, shift).to_bits(), product.to_bits());
    }

    /// Bounds built as a grid are one, and every step decodes to `dequantise`'s bits.
    #[test]
    fn a_grid_decodes_as_dequantise(
        origin in -(1i32 << 23)..1 << 23,
        stride in 0i32..=255,
        shift in -100i32..80,
        q in any::<u16>(),
    ) {
        let last = origin + 65535 * stride;
        prop_assume!(last.unsigned_abs() < 1 << 24);
        let at = |n: i32| (f64::from(n) * 2f64.powi(shift)) as f32;
        let (min, max) = (at(origin), at(last));
        let grid = Grid::of(min, max).expect("an exact grid");
        prop_assert_eq!(grid.value(q).to_bits(), dequantise(min, max, q).to_bits());
        prop_assert_eq!(grid.value(q), at(origin + i32::from(q) * stride));
    }
}

/// Bounds whose steps `dequantise` must round are not a grid; neither is a step beyond 255
/// units or a value beyond 2^24 of them.
#[test]
fn bounds_off_a_grid_are_not_one() {
    assert!(Grid::of(-1.0, 3.0).is_none());
    assert!(Grid::of(0.0, 65535.0 * 256.0).is_some());
    assert!(Grid::of(0.0, 65535.0 * 257.0).is_none());
    assert!(Grid::of(-16_777_216.0, 0.0).is_none());
    assert!(Grid::of(f32::NAN, 1.0).is_none());
    assert!(Grid::of(1.0, 0.0).is_none());
    assert_eq!(Grid::of(0.5, 0.5).map(|g| g.value(9)), Some(0.5));
}

proptest! {
    /// A record's offset is the checked product and sum, on every core's path.
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

    /// The 64-bit product from 16-bit halves (the Cortex-M0+ path) is the product.
    #[test]
    fn products_from_halves_are_exact(a in any::<i32>(), b in any::<i32>()) {
        prop_assert_eq!(mul_wide_halves(a, b), i64::from(a) * i64::from(b));
    }

    /// Vertices within 2^15 steps of each other and an eye within reach take the integer test:
    /// its sign is the exact one (i128 arithmetic on the steps and the fixed-point eye).
    #[test]
    fn the_integer_side_is_exact(
        base in proptest::array::uniform3(0i32..=65535),
        offsets in proptest::array::uniform2(proptest::array::uniform3(-32767i32..32767)),
        eye in proptest::array::uniform3(-3.0f32..3.0),
    ) {
        let mut spec = Spec::small();
        let (lo, hi) = ([-1.0f32, -2.0, 0.5], [3.0f32, 1.0, 0.75]);
        spec.bounds = [lo, hi];
        let q = [
            base,
            [0, 1, 2].map(|k| (base[k] + offsets[0][k]).clamp(0, 65535)),
            [0, 1, 2].map(|k| (base[k] + offsets[1][k]).clamp(0, 65535)),
        ];
        for (i, v) in q.iter().enumerate() {
            spec.vertices[i] = [0, 1, 2].map(|k| {
                (f64::from(lo[k]) + f64::from(v[k]) * (f64::from(hi[k]) - f64::from(lo[k])) / 65535.0)
                    as f32
            });
        }
        let bytes = spec.encode();
        let scene = Scene::parse(&bytes).unwrap();
        let side_eye = scene.side_eye(Vec3::from(eye));
        let e = side_eye.fixed.expect("an eye this close is within reach");
        // The steps as stored.
        let stored = [0u32, 1, 2].map(|i| {
            let at = element(scene.vertices, 6, i).unwrap();
            [0, 2, 4].map(|k| i128::from(u16_at(&bytes, at + k).unwrap()))
        });
        let [p, q, r] = stored;
        let (a, b) = ([0, 1, 2].map(|k| q[k] - p[k]), [0, 1, 2].map(|k| r[k] - p[k]));
        let n = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
        let exact: i128 = (0..3).map(|k| n[k] * (i128::from(e[k]) - 256 * p[k])).sum();
        let side = scene.eye_side(&scene.polygon(0), &side_eye);
        prop_assert_eq!(side, Side::of(exact.signum() as f32));
    }
}

/// On a flat axis (every vertex at the same height) a step is 0 and no eye can be brought to
/// steps on it; the side must still follow the eye across the plane.
#[test]
fn a_flat_scene_still_has_two_sides() {
    let mut spec = Spec::small();
    spec.bounds = [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
    let bytes = spec.encode();
    let scene = Scene::parse(&bytes).unwrap();
    // Polygon 0: (0,0,0), (1,0,0), (1,1,0), (0,1,0): normal +z.
    let side = |eye| scene.eye_side(&scene.polygon(0), &scene.side_eye(eye));
    assert_eq!(side(Vec3::new(0.3, 0.3, 0.5)), Side::Front);
    assert_eq!(side(Vec3::new(-4.0, 9.0, -1e-3)), Side::Back);
    assert_eq!(side(Vec3::new(4.0, -2.0, 0.0)), Side::On);
}

proptest! {
    /// With 16-bit vertices the side comes from the steps' integer cross product and the eye
    /// in steps: the sign is the exact one (real arithmetic on the vertices' positions) for
    /// every eye not within a thousandth of the plane.
    #[test]
    fn the_side_in_steps_is_the_exact_side(
        q in proptest::array::uniform3(proptest::array::uniform3(0u16..=65535)),
        eye in proptest::array::uniform3(-10.0f32..10.0),
    ) {
        let mut spec = Spec::small();
        let (lo, hi) = ([-1.0f32, -2.0, 0.5], [3.0f32, 1.0, 0.75]);
        spec.bounds = [lo, hi];
        let position = |q: [u16; 3]| {
            [0, 1, 2].map(|k| {
                f64::from(lo[k]) + f64::from(q[k]) * (f64::from(hi[k]) - f64::from(lo[k])) / 65535.0
            })
        };
        for (i, &v) in q.iter().enumerate() {
            spec.vertices[i] = position(v).map(|c| c as f32);
        }
        let bytes = spec.encode();
        let scene = Scene::parse(&bytes).unwrap();
        // The steps as stored: the encoder's nearest step of each f32 position.
        let stored = [0u32, 1, 2].map(|i| {
            let v = scene.vertex(i);
            [0, 1, 2].map(|k| ((v[k] - lo[k]) / (hi[k] - lo[k]) * 65535.0).round() as u16)
        });
        let [a, b, c] = stored.map(|s| glam::DVec3::from(position(s)));
        let normal = (b - a).cross(c - a);
        let eye_d = glam::DVec3::new(f64::from(eye[0]), f64::from(eye[1]), f64::from(eye[2]));
        let exact = normal.dot(eye_d - a);
        prop_assume!(normal.length() > 1e-9 && exact.abs() > 1e-3 * normal.length());
        let side = scene.eye_side(&scene.polygon(0), &scene.side_eye(Vec3::from(eye)));
        prop_assert_eq!(side, Side::of(exact as f32), "exact {}", exact);
    }
}

#[test]
fn out_of_range_records_are_refused_at_their_offset() {
    let node_cases: [fn(&mut Spec); 10] = [
        |s| s.nodes[0].0 = 7,    // unknown kind
        |s| s.nodes[1].0 = 0x40, // unknown bit of the kind byte
        |s| s.nodes[0].1 = 3,    // split plane out of range
        |s| s.nodes[0].3 = 1,    // front == back
        |s| s.nodes[2].2 = 0,    // empty convex set
        |s| s.nodes[2].1 = 1,    // polygons owned twice
        |s| s.nodes[1].3 = 2,    // 2 would have two parents
        |s| s.nodes[2].4 = 1,    // parent that does not name it
        |s| s.nodes[0].4 = 1,    // the root has a parent
        |s| s.nodes[2].3 = 3,    // child beyond the array
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
        |s| s.polygons[1].2 = 0b1,      // unknown flag (version 1's FLIPPED)
        |s| s.polygons[1].2 = 0b100,    // unknown flag (version 1's one-sided bit)
        |s| s.polygons[1].0 = 3,        // not right after the previous polygon
        |s| s.max_polygon_vertices = 3, // polygon 0 has 4 vertices
        |s| s.indices[3] = 7,           // vertex out of range
        |s| {
            s.polygons[2].1 = 2;
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
    // 2's - child is 1, which comes before it.
    let mut spec = Spec::small();
    spec.nodes[0] = (node_kind::SPLIT, 2, NONE, 2, NONE);
    spec.nodes[1] = (node_kind::CONVEX, 0, 2, NONE, 2);
    spec.nodes[2] = (node_kind::SPLIT, 2, NONE, 1, 0);
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
    spec.nodes[2] = (node_kind::SPLIT, 2, NONE, 1, 1);
    assert!(matches!(spec.parse(), Err(ReadError::BadRecord { .. })));
    // A self loop (a first child is always the next node, so only a split's - child can try).
    let mut spec = Spec::small();
    spec.nodes[0].3 = 0;
    assert!(matches!(spec.parse(), Err(ReadError::BadRecord { .. })));
}

/// 200,000 nodes: `u32` fields.
#[test]
#[cfg_attr(not(feature = "large-scenes"), ignore = "u32 fields need large-scenes")]
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
    spec.nodes[0].1 = 99; // split plane index
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
    use crate::display::SpanSink;
    use crate::render::{Renderer, Workspace};
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
        let _ = (scene.eye_side(&p, &scene.side_eye(Vec3::ONE)), scene.id(i));
    }
    let _ = scene.vertex(h.vertex_count);
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
            (layout.vertices, h.vertex_count as usize * layout.vertex_size),
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

#[test]
fn two_colours_give_each_side_its_own() {
    let polygon = |scene: &Scene<'_>, k: u32| {
        // The record's colour is the interior side's; its shape has none.
        assert_eq!(scene.polygon(k).colour, scene.colour_seen(k, true));
        assert_eq!(scene.polygon_shape(k).colour, Colour::default());
        (scene.colour_seen(k, true), scene.colour_seen(k, false))
    };
    let one = Spec::small().encode();
    let one = Scene::parse(&one).unwrap();
    assert_eq!(
        polygon(&one, 1),
        (Colour::new(40, 50, 60), Colour::new(40, 50, 60))
    );
    let mut spec = Spec::small();
    spec.flags |= header_flags::TWO_COLOURS;
    let bytes = spec.encode();
    assert_eq!(
        bytes.len(),
        Spec::small().encode().len() + 3 * 3,
        "one more colour field per polygon"
    );
    let two = Scene::parse(&bytes).unwrap();
    for k in 0..3u32 {
        let (c, e) = (spec.polygons[k as usize].3, spec.exterior[k as usize]);
        assert_eq!(
            polygon(&two, k),
            (Colour::new(c[0], c[1], c[2]), Colour::new(e[0], e[1], e[2]))
        );
        assert_eq!(two.polygon(k).first_index, spec.polygons[k as usize].0);
    }
    // Out of range: the record's colour (here the default), no panic.
    assert_eq!(polygon(&two, 3), (Colour::default(), Colour::default()));
}

#[test]
fn an_exterior_palette_index_out_of_range_is_refused() {
    let mut spec = Spec::small_with_everything();
    spec.flags |= header_flags::TWO_COLOURS;
    spec.exterior = std::vec![[1, 0, 0], [0, 0, 0], [1, 0, 0]];
    let scene = spec.encode();
    let scene = Scene::parse(&scene).unwrap();
    assert_eq!(scene.colour_seen(0, false), Colour::new(40, 50, 60));
    spec.exterior[1] = [2, 0, 0];
    assert_eq!(
        spec.parse(),
        Err(ReadError::BadRecord {
            offset: polygon_at(&spec, 1)
        })
    );
}

/// [`Spec::small`] with shades: polygon 1 smooth (its interior the source triangle's front),
/// polygon 2 smooth with `INTERIOR_BACK`, polygon 0 flat.
fn smooth_spec() -> Spec {
    let mut spec = Spec::small();
    spec.flags |= header_flags::SHADES;
    spec.shades = (0..spec.vertices.len() as u8)
        .map(|v| [200 + v, 70 + v])
        .collect();
    spec.polygons[1].2 |= polygon_flags::SMOOTH;
    spec.polygons[2].2 |= polygon_flags::SMOOTH | polygon_flags::INTERIOR_BACK;
    spec
}

#[test]
fn shades_read_back_on_the_side_seen() {
    let spec = smooth_spec();
    let bytes = spec.encode();
    assert_eq!(
        bytes.len(),
        Spec::small().encode().len() + 8 + SHADE_SIZE * spec.vertices.len(),
        "a length, then two bytes per vertex"
    );
    let scene = Scene::parse(&bytes).unwrap();
    for v in 0..spec.vertices.len() as u32 {
        for side in 0..2 {
            assert_eq!(scene.vertex_shade(v, side), spec.shades[v as usize][side]);
        }
    }
    assert_eq!(scene.vertex_shade(99, 0), 0, "out of range");
    // Polygon 0 is flat: no shade side. Polygon 1 shades its interior with the fronts,
    // polygon 2 with the backs.
    let side = |p: u32, interior| Scene::shade_side(scene.polygon(p).flags, interior);
    assert_eq!((side(0, true), side(0, false)), (None, None));
    assert_eq!((side(1, true), side(1, false)), (Some(0), Some(1)));
    assert_eq!((side(2, true), side(2, false)), (Some(1), Some(0)));
    // Without the flag there are no shades, and no bytes for them.
    let plain = Spec::small().encode();
    let plain = Scene::parse(&plain).unwrap();
    assert_eq!(plain.vertex_shade(0, 0), 0);
}

/// Offset of polygon `k`'s record in `spec`'s file.
fn polygon_at(spec: &Spec, k: usize) -> usize {
    let bytes = spec.encode();
    let shades = if spec.flags & header_flags::SHADES != 0 {
        8 + SHADE_SIZE * spec.shades.len()
    } else {
        0
    };
    bytes.len()
        - shades
        - spec.nodes.len() * node_size(spec.flags)
        - 8
        - spec.boxes.len() * BOUNDS_SIZE
        - 8
        - spec.palette.len() * PALETTE_SIZE
        - 8
        - spec.ids.len() * ID_SIZE
        - 8
        - (spec.polygons.len() - k) * polygon_size(spec.flags)
}

#[test]
fn smooth_polygons_need_shades_and_interior_back_needs_smooth() {
    assert_eq!(smooth_spec().parse(), Ok(()));
    // SMOOTH without SHADES.
    let mut spec = Spec::small();
    spec.polygons[1].2 |= polygon_flags::SMOOTH;
    assert_eq!(
        spec.parse(),
        Err(ReadError::BadRecord {
            offset: polygon_at(&spec, 1)
        })
    );
    // INTERIOR_BACK without SMOOTH, with or without SHADES.
    for shades in [false, true] {
        let mut spec = if shades { smooth_spec() } else { Spec::small() };
        spec.polygons[0].2 |= polygon_flags::INTERIOR_BACK;
        assert_eq!(
            spec.parse(),
            Err(ReadError::BadRecord {
                offset: polygon_at(&spec, 0)
            }),
            "shades: {shades}"
        );
    }
}

#[test]
fn solid_marks_need_the_header_flag_and_one_side() {
    use polygon_flags::{INSIDE_EXTERIOR, INSIDE_INTERIOR};
    let mut spec = Spec::small();
    spec.flags |= header_flags::SOLID;
    spec.polygons[0].2 |= INSIDE_INTERIOR;
    spec.polygons[1].2 |= INSIDE_EXTERIOR;
    let bytes = spec.encode();
    let scene = Scene::parse(&bytes).unwrap();
    assert_eq!(scene.polygon(0).flags & INSIDE_INTERIOR, INSIDE_INTERIOR);
    assert_eq!(scene.polygon(1).flags & INSIDE_EXTERIOR, INSIDE_EXTERIOR);
    // A mark without the header flag, and both marks at once.
    let mut unflagged = spec.clone();
    unflagged.flags &= !header_flags::SOLID;
    let mut both = spec.clone();
    both.polygons[2].2 |= INSIDE_INTERIOR | INSIDE_EXTERIOR;
    for (bad, polygon) in [(unflagged, 0), (both, 2)] {
        assert_eq!(
            bad.parse(),
            Err(ReadError::BadRecord {
                offset: polygon_at(&bad, polygon)
            })
        );
    }
}

#[test]
fn a_short_or_miscounted_shades_array_is_refused() {
    let spec = smooth_spec();
    let bytes = spec.encode();
    let length_at = bytes.len() - 8 - SHADE_SIZE * spec.shades.len();
    // Every strict prefix, inside the shades array too, is truncated.
    for cut in [bytes.len() - 1, length_at + 8, length_at + 3] {
        assert!(
            matches!(
                Scene::parse(&bytes[..cut]),
                Err(ReadError::Truncated { .. })
            ),
            "{cut}"
        );
    }
    assert_eq!(
        Scene::parse(&bytes[..bytes.len() - 1]).unwrap_err(),
        ReadError::Truncated {
            offset: length_at + 8
        }
    );
    // A length other than vertex_count.
    let mut short = spec.clone();
    short.shades.pop();
    assert_eq!(
        short.parse(),
        Err(ReadError::CountMismatch { offset: length_at })
    );
    // The flag set without the array.
    let mut absent = spec.encode();
    absent.truncate(length_at);
    assert_eq!(
        Scene::parse(&absent).unwrap_err(),
        ReadError::Truncated { offset: length_at }
    );
    // Bytes after it.
    let mut longer = bytes.clone();
    longer.push(0);
    assert_eq!(
        Scene::parse(&longer).unwrap_err(),
        ReadError::TrailingBytes {
            offset: bytes.len()
        }
    );
}

/// The texture arrays of a version 6 file, appended to a [`Spec`]'s bytes.
#[derive(Clone)]
struct TextureSpec {
    uvs: Vec<[i32; 2]>,
    /// `log2_width, log2_height, flags, colours - 1, offset`.
    records: Vec<(u8, u8, u8, u8, u32)>,
    texels: Vec<u8>,
    polygons: Vec<u8>,
}

impl TextureSpec {
    /// Two textures on [`Spec::small`]: texture 0 a 2 x 2 of RGB565 texels, clamped across
    /// `s`; texture 1 a 4 x 2 of three palette colours. Polygon 0 takes texture 1, polygon 1
    /// none, polygon 2 texture 0.
    fn small(spec: &Spec) -> TextureSpec {
        let direct: [u16; 4] = [0xF800, 0x07E0, 0x001F, 0xFFFF];
        let palette: [u16; 3] = [0x1234, 0xABCD, 0x0F0F];
        let indices: [u8; 8] = [0, 1, 2, 1, 0, 0, 2, 2];
        let mut texels: Vec<u8> = direct.iter().flat_map(|t| t.to_le_bytes()).collect();
        texels.extend(palette.iter().flat_map(|t| t.to_le_bytes()));
        texels.extend(indices);
        TextureSpec {
            uvs: (0..spec.vertices.len() as i32)
                .map(|v| [v * 1000 - 2000, -v * 77])
                .collect(),
            records: std::vec![
                (1, 1, texture_flags::CLAMP_S, 0, 0),
                (2, 1, texture_flags::PALETTE, 2, 8)
            ],
            texels,
            polygons: std::vec![1, NO_TEXTURE, 0],
        }
    }

    /// `spec` as version 6 with these arrays.
    fn encode(&self, spec: &Spec) -> Vec<u8> {
        let mut spec = spec.clone();
        spec.version = TEXTURED_VERSION;
        spec.flags |= header_flags::TEXTURES;
        let mut out = spec.encode();
        let length = |out: &mut Vec<u8>, n: usize| out.extend((n as u64).to_le_bytes());
        length(&mut out, self.uvs.len());
        for [s, t] in &self.uvs {
            out.extend(s.to_le_bytes());
            out.extend(t.to_le_bytes());
        }
        length(&mut out, self.records.len());
        for &(w, h, flags, colours, offset) in &self.records {
            out.extend([w, h, flags, colours]);
            out.extend(offset.to_le_bytes());
        }
        length(&mut out, self.texels.len());
        out.extend(&self.texels);
        length(&mut out, self.polygons.len());
        out.extend(&self.polygons);
        out
    }

    /// Offsets of the `uvs`, `textures`, `texels` and `polygon_textures` lengths.
    #[cfg(feature = "textures")]
    fn lengths(&self, spec: &Spec) -> [usize; 4] {
        let end = self.encode(spec).len();
        let polygons = end - 8 - self.polygons.len();
        let texels = polygons - 8 - self.texels.len();
        let records = texels - 8 - TEXTURE_SIZE * self.records.len();
        let uvs = records - 8 - UV_SIZE * self.uvs.len();
        [uvs, records, texels, polygons]
    }
}

#[cfg(feature = "textures")]
#[test]
fn textures_read_back() {
    let spec = Spec::small();
    let textures = TextureSpec::small(&spec);
    let bytes = textures.encode(&spec);
    let scene = Scene::parse(&bytes).unwrap();
    assert!(scene.has_textures());
    assert_eq!(scene.texture_count(), 2);
    for (v, &uv) in textures.uvs.iter().enumerate() {
        assert_eq!(scene.vertex_uv(v as u32), uv);
    }
    assert_eq!(scene.vertex_uv(99), [0, 0], "out of range");
    let t0 = scene.polygon_texture(2).unwrap();
    assert_eq!((t0.log2_width, t0.log2_height), (1, 1));
    assert_eq!(t0.flags, texture_flags::CLAMP_S);
    assert_eq!(
        [
            t0.texel(0, 0),
            t0.texel(1, 0),
            t0.texel(0, 1),
            t0.texel(1, 1)
        ],
        [0xF800, 0x07E0, 0x001F, 0xFFFF]
    );
    // Coordinates wrap modulo the sides.
    assert_eq!(t0.texel(3, 2), 0x07E0);
    let t1 = scene.polygon_texture(0).unwrap();
    assert_eq!((t1.log2_width, t1.log2_height), (2, 1));
    let row = |r: u32| (0..4).map(|c| t1.texel(c, r)).collect::<Vec<_>>();
    assert_eq!(row(0), [0x1234, 0xABCD, 0x0F0F, 0xABCD]);
    assert_eq!(row(1), [0x1234, 0x1234, 0x0F0F, 0x0F0F]);
    assert_eq!(scene.polygon_texture(1), None, "untextured");
    assert_eq!(scene.polygon_texture(3), None, "out of range");
    assert_eq!(scene.texture(2), None);
    // An untextured file has none of it.
    let plain = Spec::small().encode();
    let plain = Scene::parse(&plain).unwrap();
    assert!(!plain.has_textures());
    assert_eq!(
        (plain.polygon_texture(0), plain.vertex_uv(0)),
        (None, [0, 0])
    );
}

#[cfg(feature = "textures")]
#[test]
fn textures_belong_to_version_6_and_version_6_to_textures() {
    let spec = Spec::small();
    let bytes = TextureSpec::small(&spec).encode(&spec);
    let flags = u16::from_le_bytes([bytes[6], bytes[7]]);
    // Version 4 with the flag.
    let mut four = bytes.clone();
    four[4..6].copy_from_slice(&FORMAT_VERSION.to_le_bytes());
    assert_eq!(
        Scene::parse(&four).unwrap_err(),
        ReadError::InconsistentFlags { flags }
    );
    // Version 6 without it.
    let mut six = spec.encode();
    six[4..6].copy_from_slice(&TEXTURED_VERSION.to_le_bytes());
    assert_eq!(
        Scene::parse(&six).unwrap_err(),
        ReadError::InconsistentFlags { flags: spec.flags }
    );
}

#[cfg(feature = "textures")]
#[test]
fn every_prefix_of_a_textured_file_is_truncated_and_more_bytes_trail() {
    let spec = Spec::small();
    let bytes = TextureSpec::small(&spec).encode(&spec);
    let start = spec.encode().len();
    for end in start..bytes.len() {
        assert!(
            matches!(
                Scene::parse(&bytes[..end]),
                Err(ReadError::Truncated { .. })
            ),
            "{end}"
        );
    }
    let mut longer = bytes.clone();
    longer.push(0);
    assert_eq!(
        Scene::parse(&longer).unwrap_err(),
        ReadError::TrailingBytes {
            offset: bytes.len()
        }
    );
}

#[cfg(feature = "textures")]
#[test]
fn bad_texture_records_are_refused_where_they_are() {
    let spec = Spec::small();
    let good = TextureSpec::small(&spec);
    let [uvs, records, texels, polygons] = good.lengths(&spec);
    let record = |k: usize| records + 8 + TEXTURE_SIZE * k;
    let check = |t: &TextureSpec, expected: ReadError, what: &str| {
        assert_eq!(
            Scene::parse(&t.encode(&spec)).unwrap_err(),
            expected,
            "{what}"
        );
    };
    let mut t = good.clone();
    t.uvs.pop();
    check(&t, ReadError::CountMismatch { offset: uvs }, "uvs count");
    let mut t = good.clone();
    t.polygons.push(0);
    check(
        &t,
        ReadError::CountMismatch { offset: polygons },
        "polygon count",
    );
    let mut t = good.clone();
    t.records.clear();
    t.texels.clear();
    check(&t, ReadError::BadRecord { offset: records }, "no texture");
    let mut t = good.clone();
    t.records[0].0 = MAX_TEXTURE_LOG2 + 1;
    check(&t, ReadError::BadRecord { offset: record(0) }, "too wide");
    let mut t = good.clone();
    t.records[1].2 |= 1 << 7;
    check(
        &t,
        ReadError::BadRecord { offset: record(1) },
        "unknown flag",
    );
    let mut t = good.clone();
    t.records[0].3 = 1;
    check(
        &t,
        ReadError::BadRecord { offset: record(0) },
        "colours without palette",
    );
    let mut t = good.clone();
    t.records[1].4 = 9;
    check(&t, ReadError::BadRecord { offset: record(1) }, "offset");
    let mut t = good.clone();
    t.texels.push(0);
    check(
        &t,
        ReadError::BadRecord { offset: texels },
        "texels past the last",
    );
    let mut t = good.clone();
    t.texels.pop();
    check(&t, ReadError::BadRecord { offset: texels }, "texels short");
    // Palette index 3 of three colours: the seventh index byte.
    let mut t = good.clone();
    let last = t.texels.len() - 2;
    t.texels[last] = 3;
    check(
        &t,
        ReadError::BadRecord {
            offset: texels + 8 + last,
        },
        "palette index",
    );
    let mut t = good.clone();
    t.polygons[1] = 2;
    check(
        &t,
        ReadError::BadRecord {
            offset: polygons + 8 + 1,
        },
        "polygon texture",
    );
}

/// A build without textures refuses a textured file as it refuses other parts it left out.
#[cfg(not(feature = "textures"))]
#[test]
fn a_build_without_textures_refuses_them() {
    let spec = Spec::small();
    let bytes = TextureSpec::small(&spec).encode(&spec);
    assert_eq!(
        Scene::parse(&bytes).unwrap_err(),
        ReadError::UnsupportedFlags {
            flags: spec.flags | header_flags::TEXTURES
        }
    );
}

/// `spec` as a version 7 file: the `TRANSPARENT` flag and `opacities` (one a polygon) after
/// everything else, the polygons whose opacity is below 255 flagged.
#[cfg(feature = "transparency")]
fn transparent_file(spec: &Spec, opacities: &[u8]) -> Vec<u8> {
    let mut spec = spec.clone();
    spec.version = TRANSPARENT_VERSION;
    spec.flags |= header_flags::TRANSPARENT;
    for (p, &a) in spec.polygons.iter_mut().zip(opacities) {
        if a < OPAQUE {
            p.2 |= polygon_flags::TRANSPARENT;
        }
    }
    let mut out = spec.encode();
    out.extend((opacities.len() as u64).to_le_bytes());
    out.extend(opacities);
    out
}

#[cfg(feature = "transparency")]
#[test]
fn opacities_read_back_and_belong_to_version_7() {
    let spec = Spec::small();
    let n = spec.polygons.len();
    let mut opacities = std::vec![OPAQUE; n];
    opacities[1] = 90;
    let bytes = transparent_file(&spec, &opacities);
    let scene = Scene::parse(&bytes).unwrap();
    assert!(scene.has_transparency());
    assert_eq!(scene.opacity(1), 90);
    assert_eq!(scene.opacity(0), OPAQUE);
    assert_eq!(scene.opacity(99), OPAQUE, "out of range");
    assert_ne!(scene.polygon(1).flags & polygon_flags::TRANSPARENT, 0);
    assert!(!Scene::parse(&spec.encode()).unwrap().has_transparency());
    // Version 4 with the flag, version 7 without it.
    let flags = u16::from_le_bytes([bytes[6], bytes[7]]);
    let mut four = bytes.clone();
    four[4..6].copy_from_slice(&FORMAT_VERSION.to_le_bytes());
    assert_eq!(
        Scene::parse(&four).unwrap_err(),
        ReadError::InconsistentFlags { flags }
    );
    let mut seven = spec.encode();
    seven[4..6].copy_from_slice(&TRANSPARENT_VERSION.to_le_bytes());
    assert_eq!(
        Scene::parse(&seven).unwrap_err(),
        ReadError::InconsistentFlags { flags: spec.flags }
    );
    // A short array, or bytes after it.
    for end in bytes.len() - n..bytes.len() {
        assert!(matches!(
            Scene::parse(&bytes[..end]),
            Err(ReadError::Truncated { .. })
        ));
    }
    let mut longer = bytes.clone();
    longer.push(0);
    assert!(matches!(
        Scene::parse(&longer),
        Err(ReadError::TrailingBytes { .. })
    ));
}

#[cfg(feature = "transparency")]
#[test]
fn an_opacity_must_agree_with_its_polygon() {
    let spec = Spec::small();
    let n = spec.polygons.len();
    let opacity_at = |bytes: &[u8], k: usize| bytes.len() - n + k;
    // Flagged and opaque.
    let mut opacities = std::vec![OPAQUE; n];
    opacities[0] = 100;
    let mut bytes = transparent_file(&spec, &opacities);
    let at = opacity_at(&bytes, 0);
    bytes[at] = OPAQUE;
    assert_eq!(
        Scene::parse(&bytes).unwrap_err(),
        ReadError::BadRecord { offset: at }
    );
    // Unflagged and transparent.
    let mut bytes = transparent_file(&spec, &opacities);
    let at = opacity_at(&bytes, 1);
    bytes[at] = 10;
    assert_eq!(
        Scene::parse(&bytes).unwrap_err(),
        ReadError::BadRecord { offset: at }
    );
    // Transparent and part of a solid.
    let mut solid = spec.clone();
    solid.flags |= header_flags::SOLID;
    solid.polygons[0].2 |= polygon_flags::INSIDE_INTERIOR;
    let bytes = transparent_file(&solid, &opacities);
    assert_eq!(
        Scene::parse(&bytes).unwrap_err(),
        ReadError::BadRecord {
            offset: opacity_at(&bytes, 0)
        }
    );
    // The polygon flag without the header's.
    let mut flagged = spec.clone();
    flagged.polygons[2].2 |= polygon_flags::TRANSPARENT;
    assert_eq!(
        flagged.parse(),
        Err(ReadError::BadRecord {
            offset: polygon_at(&flagged, 2)
        })
    );
}
