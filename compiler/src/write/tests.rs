//! Writer tests: hand-built trees, the round trip through the runtime's reader field by field,
//! and the writer's own invariant checks.

use glam::{DVec3, Vec3};
use peel_runtime::display::Colour;
use peel_runtime::read::{self, layout, Scene};

use super::encoding::{Encoding, PaletteWidth};
use super::format::{self, header_flags, node_kind, polygon_flags, ColourField, PeelFile, NONE};
use super::*;
use crate::tree::{TreePlane, TreePolygon};

fn polygon(
    plane: u32,
    vertices: &[u32],
    flipped: bool,
    interior_front: bool,
    source: u32,
) -> TreePolygon {
    TreePolygon {
        plane,
        flipped,
        interior_front,
        vertices: vertices.to_vec(),
        source,
        shadowed: false,
    }
}

fn convex(first_polygon: u32, polygon_count: u32, child: Option<u32>) -> TreeNode {
    TreeNode::Convex {
        first_polygon,
        polygon_count,
        child,
        support_planes: 0,
    }
}

/// A split at x = 0.5 whose front is a chain of two convex sets and whose back is one; the
/// node and polygon order is deliberately not the file's (the writer renumbers).
pub(crate) fn small_tree() -> (DisplayTree, Vec<[u8; 3]>) {
    let v = |x, y, z| DVec3::new(x, y, z);
    let plane = |normal, offset| TreePlane { normal, offset };
    let tree = DisplayTree {
        centre: v(100.0, 200.0, 300.0),
        vertices: vec![
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(1.0, 1.0, 0.0),
            v(0.0, 1.0, 0.0),
            v(0.0, 0.0, 1.0),
            v(1.0, 0.0, 1.0),
            v(-0.25, 1.0, 1.0),
        ],
        planes: vec![
            plane(DVec3::Z, 0.0),
            plane(DVec3::Z, 1.0),
            plane(DVec3::X, 0.5),
        ],
        polygons: vec![
            polygon(1, &[4, 5, 6], true, false, 11),
            polygon(0, &[0, 1, 2, 3], false, true, 10),
            polygon(1, &[4, 6, 5], false, false, 12),
        ],
        nodes: vec![
            TreeNode::Split {
                plane: 2,
                front: Some(2),
                back: Some(1),
                support_planes: 0,
            },
            convex(0, 1, None),
            convex(1, 1, Some(3)),
            convex(2, 1, None),
        ],
        stats: Default::default(),
    };
    (tree, vec![[255, 0, 0], [0, 255, 0], [0, 0, 255]])
}

/// A chain of `depth` convex sets, one triangle each.
pub(crate) fn chain_tree(depth: u32) -> (DisplayTree, Vec<[u8; 3]>) {
    let tree = DisplayTree {
        vertices: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
        planes: vec![TreePlane {
            normal: DVec3::Z,
            offset: 0.0,
        }],
        polygons: (0..depth)
            .map(|i| polygon(0, &[0, 1, 2], false, true, i))
            .collect(),
        nodes: (0..depth)
            .map(|i| convex(i, 1, (i + 1 < depth).then_some(i + 1)))
            .collect(),
        ..Default::default()
    };
    (tree, vec![[1, 2, 3]; depth as usize])
}

fn colour(c: [u8; 3]) -> Colour {
    Colour::new(c[0], c[1], c[2])
}

fn link(v: u32) -> Option<u32> {
    (v != NONE).then_some(v)
}

/// Everything the reader sees equals what bincode wrote.
pub(crate) fn assert_reads_back(file: &PeelFile) {
    let bytes = to_bytes(file).unwrap();
    let (decoded, used): (PeelFile, usize) =
        bincode::serde::decode_from_slice(&bytes, format::config()).unwrap();
    assert_eq!((&decoded, used), (file, bytes.len()));

    let scene = Scene::parse(&bytes).unwrap();
    assert_eq!(scene.header(), file.header);
    let fh = &file.header;
    let position = |v: &format::Vertex| {
        Vec3::from(v.position(fh.bounds_min.to_array(), fh.bounds_max.to_array()))
    };
    for (i, v) in file.vertices.iter().enumerate() {
        assert_eq!(scene.vertex(i as u32), position(v));
    }
    for (i, p) in file.planes.iter().enumerate() {
        let plane = scene.plane(i as u32);
        assert_eq!((plane.normal, plane.d), (Vec3::new(p[0], p[1], p[2]), p[3]));
    }
    for (i, p) in file.polygons.iter().enumerate() {
        let read = scene.polygon(i as u32);
        let expected = read::Polygon {
            first_index: p.first_index,
            vertex_count: u16::from(p.vertex_count),
            flags: p.flags,
            colour: match p.colour {
                ColourField::Rgb(c) => colour(c),
                ColourField::Index8(k) => colour(file.palette[usize::from(k)]),
                ColourField::Index16(k) => colour(file.palette[usize::from(k)]),
            },
        };
        assert_eq!(read, expected);
        let exterior = match p.exterior {
            None => expected.colour,
            Some(ColourField::Rgb(c)) => colour(c),
            Some(ColourField::Index8(k)) => colour(file.palette[usize::from(k)]),
            Some(ColourField::Index16(k)) => colour(file.palette[usize::from(k)]),
        };
        assert_eq!(scene.colour_seen(i as u32, false), exterior);
        assert_eq!(scene.colour_seen(i as u32, true), expected.colour);
        for k in 0..u32::from(p.vertex_count) {
            let index = file.indices[(p.first_index + k) as usize];
            assert_eq!(
                scene.polygon_vertex(&read, k),
                position(&file.vertices[index as usize])
            );
        }
        assert_eq!(scene.id(i as u32), file.ids.get(i).copied());
    }
    for (i, n) in file.nodes.iter().enumerate() {
        let expected = match n.kind {
            node_kind::CONVEX => read::Node::Convex {
                first: n.a,
                count: n.b,
                child: link(n.c),
            },
            _ => read::Node::Split {
                plane: n.a,
                front: link(n.b),
                back: link(n.c),
            },
        };
        assert_eq!(scene.node(i as u32), expected);
        assert_eq!(scene.parent(i as u32), link(n.parent));
        let stored = link(n.bounds).map(|k| decoded_box(file, file.bounds[k as usize]));
        assert_eq!(scene.node_bounds(i as u32), stored);
    }
    for (v, pair) in file.shades.iter().enumerate() {
        assert_eq!([0, 1].map(|k| scene.vertex_shade(v as u32, k)), *pair);
    }
    // Textures: each vertex's coordinates, each record's bytes, each polygon's texture.
    assert_eq!(scene.has_textures(), !file.textures.is_empty());
    for (v, uv) in file.uvs.iter().enumerate() {
        assert_eq!(scene.vertex_uv(v as u32), *uv);
    }
    assert_eq!(scene.texture_count() as usize, file.textures.len());
    for (k, record) in file.textures.iter().enumerate() {
        let texture = scene.texture(k as u32).unwrap();
        let colours = if record.flags & layout::texture_flags::PALETTE != 0 {
            u32::from(record.colours_minus_one) + 1
        } else {
            0
        };
        let start = record.offset as usize;
        let size =
            layout::texture_bytes(record.log2_width, record.log2_height, record.flags, colours);
        let (palette, texels) =
            file.texels[start..start + size].split_at(colours as usize * layout::TEXEL_SIZE);
        let stored = peel_runtime::read::Texture {
            log2_width: record.log2_width,
            log2_height: record.log2_height,
            flags: record.flags,
            colours: palette,
            texels,
        };
        assert_eq!(texture, stored);
    }
    for (i, &k) in file.polygon_textures.iter().enumerate() {
        assert_eq!(
            scene.polygon_texture(i as u32),
            (k != layout::NO_TEXTURE).then(|| scene.texture(u32::from(k)).unwrap())
        );
    }
    assert_eq!(file.header.palette_count as usize, file.palette.len());
    assert_eq!(file.header.bounds_count as usize, file.bounds.len());
    assert_eq!(scene.root(), (!file.nodes.is_empty()).then_some(0));
}

/// A stored box decoded as the runtime reads it.
fn decoded_box(file: &PeelFile, b: [u16; 6]) -> (Vec3, Vec3) {
    let (lo, hi) = (file.header.bounds_min, file.header.bounds_max);
    let axis = |k: usize, q: u16| layout::dequantise(lo[k], hi[k], q);
    (
        Vec3::new(axis(0, b[0]), axis(1, b[1]), axis(2, b[2])),
        Vec3::new(axis(0, b[3]), axis(1, b[4]), axis(2, b[5])),
    )
}

#[test]
fn quantised_boxes_contain_their_coordinates() {
    // Awkward scene bounds and coordinates: every decoded box still contains its corners.
    let (lo, hi) = (
        [-4.445_835_f32, -3.637_036, 1e-3],
        [5.998_088_f32, 2.759_72, 7e4],
    );
    let mut seed = 1u64;
    let mut next = || {
        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    for _ in 0..20_000 {
        let mut b = [0f32; 6];
        for k in 0..3 {
            let (x, y) = (next(), next());
            let at = |t: f32| (lo[k] + (hi[k] - lo[k]) * t).clamp(lo[k], hi[k]);
            b[k] = at(x.min(y));
            b[k + 3] = at(x.max(y));
        }
        let q = bounds::quantise(b, lo, hi);
        for k in 0..3 {
            assert!(
                layout::dequantise(lo[k], hi[k], q[k]) <= b[k],
                "{b:?} {q:?}"
            );
            assert!(
                layout::dequantise(lo[k], hi[k], q[k + 3]) >= b[k + 3],
                "{b:?} {q:?}"
            );
        }
    }
}

#[test]
fn record_sizes_match_the_spec() {
    let (tree, colours) = small_tree();
    let size = |bytes: Vec<u8>| bytes.len();
    let enc = |v: &dyn erased::Encode| v.encode();
    // The exterior sides in other colours: a second colour field per polygon.
    let exterior: Vec<[u8; 3]> = colours.iter().map(|c| c.map(|v| !v)).collect();
    let inputs =
        [(false, false), (true, false), (false, true)].map(|(wide_vertices, two)| WriteInput {
            colours: &colours,
            exterior: if two { &exterior } else { &[] },
            ids: true,
            wide_vertices,
            ..WriteInput::default()
        });
    for (input, encoding) in inputs.iter().flat_map(|i| Encoding::ALL.map(|e| (i, e))) {
        let file = peel_file_encoded(&tree, input, Some(encoding)).unwrap();
        let bytes = to_bytes(&file).unwrap();
        assert_eq!(bytes[..layout::HEADER_SIZE], file.header.to_bytes());
        let wide_vertices = file.header.flags & header_flags::WIDE_VERTICES != 0;
        assert_eq!(wide_vertices, input.wide_vertices);
        assert_eq!(
            layout::vertex_size(file.header.flags),
            if wide_vertices { 12 } else { 6 }
        );
        assert_eq!(size(enc(&file.planes[0])), layout::PLANE_SIZE);
        let h = &file.header;
        let total = layout::HEADER_SIZE
            + 8 * layout::LENGTH_SIZE
            + h.vertex_count as usize * layout::vertex_size(h.flags)
            + h.plane_count as usize * layout::PLANE_SIZE
            + h.index_count as usize * layout::index_size(h.flags)
            + h.polygon_count as usize * (layout::polygon_size(h.flags) + layout::ID_SIZE)
            + h.palette_count as usize * layout::PALETTE_SIZE
            + h.bounds_count as usize * layout::BOUNDS_SIZE
            + h.node_count as usize * layout::node_size(h.flags);
        assert_eq!(bytes.len(), total, "{encoding:?}");
        // Without u16 indices, small_tree's 7 vertices take u24 ones (INDEX24).
        let expected_index = if encoding.index16 { 2 } else { 3 };
        assert_eq!(h.flags & header_flags::INDEX24 != 0, !encoding.index16);
        let no_narrow_index = h.flags & !(header_flags::INDEX16 | header_flags::INDEX24);
        assert_eq!(layout::index_size(no_narrow_index), 4);
        // small_tree's counts all fit NARROW's u16 fields: 2 + 1 + 1 + the colour.
        assert_ne!(h.flags & header_flags::NARROW, 0);
        let colour_field = match encoding.palette {
            None => 3,
            Some(PaletteWidth::U8) => 1,
            Some(PaletteWidth::U16) => 2,
        };
        let two = h.flags & header_flags::TWO_COLOURS != 0;
        assert_eq!(two, !input.exterior.is_empty());
        let expected_polygon = 4 + colour_field * if two { 2 } else { 1 };
        assert_eq!(
            (layout::index_size(h.flags), layout::polygon_size(h.flags)),
            (expected_index, expected_polygon)
        );
        assert_eq!(layout::node_size(h.flags), 9, "small_tree has bounds");
        let wide = h.flags & !header_flags::NARROW;
        assert_eq!(layout::polygon_size(wide), expected_polygon + 2);
        assert_eq!(layout::node_size(wide), 17);
        let medium = wide | header_flags::MEDIUM;
        assert_eq!(layout::polygon_size(medium), expected_polygon + 1);
        assert_eq!(layout::node_size(medium), 13);
        // The same records in u24 and u32 fields read back alike.
        for flags in [medium, wide] {
            let mut other = file.clone();
            other.header.flags = flags;
            assert_reads_back(&other);
        }
    }
    let file = peel_file(&tree, &colours, true).unwrap();
    // Spot checks of the header's byte offsets.
    let bytes = to_bytes(&file).unwrap();
    assert_eq!(&bytes[..4], b"PEEL");
    assert_eq!(
        u32::from_le_bytes(bytes[24..28].try_into().unwrap()),
        4,
        "node_count at 24"
    );
    assert_eq!(
        f64::from_le_bytes(bytes[36..44].try_into().unwrap()),
        100.0,
        "centre at 36"
    );
    assert_eq!(
        f32::from_le_bytes(bytes[60..64].try_into().unwrap()),
        -0.25,
        "bounds_min at 60"
    );
}

/// Encoding of single records, to measure them.
mod erased {
    pub trait Encode {
        fn encode(&self) -> Vec<u8>;
    }
    impl<T: serde::Serialize> Encode for T {
        fn encode(&self) -> Vec<u8> {
            bincode::serde::encode_to_vec(self, super::format::config()).unwrap()
        }
    }
}

#[test]
fn round_trip_field_by_field() {
    let (tree, colours) = small_tree();
    for ids in [true, false] {
        assert_reads_back(&peel_file(&tree, &colours, ids).unwrap());
    }
    let (tree, colours) = chain_tree(1000);
    assert_reads_back(&peel_file(&tree, &colours, true).unwrap());
    assert_reads_back(&peel_file(&DisplayTree::default(), &[], false).unwrap());
}

#[test]
fn the_file_is_the_tree_in_pre_order() {
    let (tree, colours) = small_tree();
    let file = peel_file(&tree, &colours, true).unwrap();
    let h = &file.header;
    assert_eq!(
        (h.version, h.flags),
        (
            4,
            header_flags::IDS | header_flags::INDEX16 | header_flags::BOUNDS | header_flags::NARROW
        )
    );
    assert_eq!((h.max_depth, h.max_polygon_vertices), (3, 4));
    // The grid that covers the vertices, (-0.25, 0, 0)..(1, 1, 1).
    assert_eq!(
        (h.bounds_min.to_array(), h.bounds_max.to_array()),
        grid::covering([-0.25, 0.0, 0.0], [1.0; 3])
    );
    assert_eq!(h.centre, [100.0, 200.0, 300.0]);
    let node = |kind, a, b, c, parent, bounds| format::Node {
        kind,
        a,
        b,
        c,
        parent,
        bounds,
    };
    // Bounds: the root's; node 1's box equals the root's; the two leaves hold one polygon
    // each: none.
    assert_eq!(
        file.nodes,
        [
            // Only split planes are stored: the root's is plane 0.
            node(node_kind::SPLIT, 0, 1, 3, NONE, 0),
            node(node_kind::CONVEX, 0, 1, 2, 0, NONE),
            node(node_kind::CONVEX, 1, 1, NONE, 1, NONE),
            node(node_kind::CONVEX, 2, 1, NONE, 0, NONE),
        ]
    );
    // The root's box is the box of the vertices as stored: from the grid's first step (on
    // -0.25, 0, 0) to the steps nearest (1, 1, 1).
    let (lo, hi) = (h.bounds_min.to_array(), h.bounds_max.to_array());
    let top = grid::nearest(DVec3::ONE, lo, hi);
    assert!(top.iter().all(|&q| q > 64_000 && q < u16::MAX), "{top:?}");
    assert_eq!(file.bounds, [[0, 0, 0, top[0], top[1], top[2]]]);
    // Old polygons 1, 2, 0, in the order of the convex nodes that own them.
    assert_eq!(file.ids, [10, 12, 11]);
    assert_eq!(file.indices, [0, 1, 2, 3, 4, 6, 5, 4, 5, 6]);
    let firsts: Vec<u32> = file.polygons.iter().map(|p| p.first_index).collect();
    assert_eq!(firsts, [0, 4, 7]);
    // INTERIOR_FRONT is relative to the normal of the first three vertices: polygon 1's
    // winding turns against its plane's normal (+z), so its interior (-z side, not the
    // plane's + side) is on that normal's + side.
    let interior: Vec<u8> = file.polygons.iter().map(|p| p.flags).collect();
    assert_eq!(
        interior,
        [
            polygon_flags::INTERIOR_FRONT,
            polygon_flags::INTERIOR_FRONT,
            0
        ]
    );
    assert_eq!(file.polygons[1].colour, ColourField::Rgb([0, 0, 255]));
    assert_eq!(file.planes, [[1.0, 0.0, 0.0, 0.5]]);
    // Vertices are steps on the scene's bounds: (-0.25, 1, 1) is the grid's first step on x,
    // within half a step of 1 on y and z.
    assert_eq!(file.vertices[6], format::Vertex::Grid([0, top[1], top[2]]));
    let at = file.vertices[6].position(lo, hi);
    assert_eq!(at[0], -0.25);
    for k in [1, 2] {
        let step = (hi[k] - lo[k]) / 65535.0;
        assert!((at[k] - 1.0).abs() <= step / 2.0, "{at:?}");
    }
    let without_ids = peel_file(&tree, &colours, false).unwrap();
    assert_eq!(without_ids.header.flags & header_flags::IDS, 0);
    assert!(without_ids.ids.is_empty());
}

/// A first child takes no field: it must be the next node, or the serialiser refuses the file.
#[test]
fn a_first_child_is_the_next_node() {
    let (tree, colours) = small_tree();
    let file = peel_file(&tree, &colours, false).unwrap();
    let encode = |file: &PeelFile| bincode::serde::encode_to_vec(file, format::config());
    let bytes = encode(&file).unwrap();
    let back: PeelFile = bincode::serde::decode_from_slice(&bytes, format::config())
        .unwrap()
        .0;
    assert_eq!(back, file);
    let mut broken = file.clone();
    // The root split's + child becomes node 3, not the next node.
    assert_eq!(
        (broken.nodes[0].kind, broken.nodes[0].b),
        (node_kind::SPLIT, 1)
    );
    broken.nodes[0].b = 3;
    assert!(encode(&broken).is_err());
    let mut broken = file;
    broken.nodes[1].kind |= node_kind::FIRST_CHILD;
    assert!(encode(&broken).is_err());
}

#[test]
fn encode_checks_with_the_reader() {
    let (tree, colours) = chain_tree(300);
    let bytes = encode(&tree, &colours, false).unwrap();
    let scene = Scene::parse(&bytes).unwrap();
    assert_eq!(scene.header().max_depth, 300);
}

/// Breaks a tree or its colours.
type Breakage = fn(&mut DisplayTree, &mut Vec<[u8; 3]>);

#[test]
fn broken_trees_are_refused() {
    let cases: [(&str, Breakage); 9] = [
        ("reached twice", |t, _| {
            t.nodes[0] = TreeNode::Split {
                plane: 2,
                front: Some(2),
                back: Some(2),
                support_planes: 0,
            }
        }),
        ("not reachable", |t, _| t.nodes[2] = convex(1, 1, None)),
        ("no polygon", |t, _| t.nodes[1] = convex(0, 0, None)),
        ("out of range", |t, _| t.nodes[3] = convex(2, 2, None)),
        ("two convex", |t, _| t.nodes[3] = convex(1, 1, Some(1))),
        ("colours", |_, c| {
            c.pop();
        }),
        ("vertices", |t, _| t.polygons[0].vertices.truncate(2)),
        ("vertex 9", |t, _| t.polygons[0].vertices[0] = 9),
        ("plane 3", |t, _| t.polygons[0].plane = 3),
    ];
    for (needle, break_it) in cases {
        let (mut tree, mut colours) = small_tree();
        break_it(&mut tree, &mut colours);
        let err = encode(&tree, &colours, true).unwrap_err();
        assert!(
            matches!(err, CompileError::Invariant(ref m) if m.contains(needle)),
            "{needle}: {err}"
        );
    }
    let (mut tree, colours) = small_tree();
    tree.nodes[3] = convex(0, 1, None);
    // Polygon 0 owned twice (and polygon 2 by nobody: the counts agree) is caught.
    assert!(encode(&tree, &colours, true)
        .unwrap_err()
        .to_string()
        .contains("two convex"));
    let (mut tree, colours) = small_tree();
    tree.nodes[3] = convex(1, 1, None);
    tree.nodes[2] = convex(0, 1, Some(3));
    tree.nodes[1] = convex(2, 1, None);
    assert!(
        encode(&tree, &colours, true).is_ok(),
        "a permutation of ownership is fine"
    );
}

#[test]
fn values_beyond_f32_are_refused() {
    let (mut tree, colours) = small_tree();
    tree.vertices[0].x = 1e39;
    assert!(matches!(
        encode(&tree, &colours, false),
        Err(CompileError::Encode(_))
    ));
    let (mut tree, colours) = small_tree();
    tree.planes[2].offset = f64::NAN; // the split's: only split planes are stored
    assert!(matches!(
        encode(&tree, &colours, false),
        Err(CompileError::Encode(_))
    ));
}

#[test]
fn unowned_polygons_are_refused() {
    let (mut tree, mut colours) = small_tree();
    tree.polygons.push(polygon(0, &[0, 1, 2], false, false, 13));
    colours.push([9, 9, 9]);
    let err = encode(&tree, &colours, false).unwrap_err();
    assert!(
        err.to_string()
            .contains("polygon 3 belongs to no convex node"),
        "{err}"
    );
}

/// A split at x = 0 between two stacks of `per_side` unit squares (each its own leaf convex
/// node of 4 polygons... as triangles fans): the front at x in 1..2, the back at x in -2..-1.
/// Polygon `k` has colour `colour(k)`.
fn two_sided_tree(per_side: u32, colour: impl Fn(u32) -> [u8; 3]) -> (DisplayTree, Vec<[u8; 3]>) {
    let mut vertices = Vec::new();
    let mut polygons = Vec::new();
    let mut nodes = vec![TreeNode::Split {
        plane: 0,
        front: Some(1),
        back: Some(2),
        support_planes: 0,
    }];
    for (side, x) in [(0u32, 1.0), (1, -2.0)] {
        let first = polygons.len() as u32;
        for k in 0..per_side {
            let v = vertices.len() as u32;
            let z = f64::from(k);
            vertices.extend([
                DVec3::new(x, 0.0, z),
                DVec3::new(x + 1.0, 0.0, z),
                DVec3::new(x + 1.0, 1.0, z),
            ]);
            polygons.push(polygon(1, &[v, v + 1, v + 2], false, true, first + k));
        }
        nodes.push(convex(first, per_side, None));
        let _ = side;
    }
    let colours = (0..polygons.len() as u32).map(colour).collect();
    let tree = DisplayTree {
        vertices,
        planes: vec![
            TreePlane {
                normal: DVec3::X,
                offset: 0.0,
            },
            TreePlane {
                normal: DVec3::Z,
                offset: 0.0,
            },
        ],
        polygons,
        nodes,
        ..Default::default()
    };
    (tree, colours)
}

fn input(colours: &[[u8; 3]], ids: bool) -> WriteInput<'_> {
    WriteInput {
        colours,
        ids,
        ..WriteInput::default()
    }
}

#[test]
fn node_bounds_follow_the_rule() {
    // Front leaf: 4 polygons (gets a box); back leaf: 4 too; root: always.
    let (tree, colours) = two_sided_tree(4, |_| [1, 2, 3]);
    let file = peel_file(&tree, &colours, false).unwrap();
    assert_ne!(file.header.flags & header_flags::BOUNDS, 0);
    let boxes: Vec<_> = file
        .nodes
        .iter()
        .map(|n| link(n.bounds).map(|k| file.bounds[k as usize]))
        .collect();
    let exact = [
        [-2.0, 0.0, 0.0, 2.0, 1.0, 3.0],
        [1.0, 0.0, 0.0, 2.0, 1.0, 3.0],
        [-2.0, 0.0, 0.0, -1.0, 1.0, 3.0],
    ];
    for (b, e) in boxes.iter().zip(exact) {
        // The box of the vertices as stored (each within half a step of its exact position),
        // quantised outward by at most one step per side.
        let (lo, hi) = decoded_box(&file, b.unwrap());
        let e: [f32; 6] = e;
        for k in 0..3 {
            let step = (file.header.bounds_max[k] - file.header.bounds_min[k]) / 65535.0;
            let (below, above) = (e[k] - lo[k], hi[k] - e[k + 3]);
            assert!(
                below >= -step / 2.0 && below <= 1.5 * step,
                "{k}: {lo} {e:?}"
            );
            assert!(
                above >= -step / 2.0 && above <= 1.5 * step,
                "{k}: {hi} {e:?}"
            );
        }
    }
    assert_reads_back(&file);
    // Leaves of fewer than MIN_LEAF_POLYGONS polygons get none.
    let (tree, colours) = two_sided_tree(bounds::MIN_LEAF_POLYGONS - 1, |_| [1, 2, 3]);
    let file = peel_file(&tree, &colours, false).unwrap();
    let kept: Vec<u32> = file.nodes.iter().map(|n| n.bounds).collect();
    assert_eq!(kept, [0, NONE, NONE]);
    // A single node stores no bounds at all.
    let (tree, colours) = chain_tree(1);
    let file = peel_file(&tree, &colours, false).unwrap();
    assert_eq!(file.header.flags & header_flags::BOUNDS, 0);
    assert!(file.bounds.is_empty() && file.nodes[0].bounds == NONE);
    // A chain: every box equals its parent's (same triangle): only the root's.
    let (tree, colours) = chain_tree(10);
    let file = peel_file(&tree, &colours, false).unwrap();
    assert_eq!(file.bounds.len(), 1);
    assert!(file.nodes[1..].iter().all(|n| n.bounds == NONE));
}

#[test]
fn every_optional_part_round_trips() {
    let trees = [
        small_tree(),
        two_sided_tree(5, |k| [k as u8, 0, 0]),
        two_sided_tree(200, |k| [(k % 7) as u8, 1, 2]),
        two_sided_tree(200, |k| [(k % 256) as u8, (k / 256) as u8, 9]),
        chain_tree(50),
    ];
    for (tree, colours) in &trees {
        for ids in [false, true] {
            let distinct = encoding::distinct_colours(colours).len();
            for e in Encoding::ALL {
                if e.flags(tree.vertices.len(), distinct).is_err() {
                    continue;
                }
                let file = peel_file_encoded(tree, &input(colours, ids), Some(e)).unwrap();
                assert_reads_back(&file);
            }
        }
    }
}

#[test]
fn the_chosen_encoding_is_the_smallest() {
    let many_vertices = {
        let (mut tree, colours) = two_sided_tree(4, |_| [5, 5, 5]);
        tree.vertices
            .extend((0..70_000).map(|k| DVec3::new(0.0, 0.0, f64::from(k % 3))));
        (tree, colours)
    };
    let cases = [
        ("distinct colours", small_tree()),
        ("one colour", chain_tree(40)),
        ("7 colours", two_sided_tree(200, |k| [(k % 7) as u8, 1, 2])),
        (
            "300 colours",
            two_sided_tree(600, |k| [(k % 300) as u8, (k % 300 / 256) as u8, 3]),
        ),
        (
            "all distinct",
            two_sided_tree(300, |k| [k as u8, (k >> 8) as u8, 0]),
        ),
        ("70000 vertices", many_vertices),
    ];
    let mut chosen_palettes = Vec::new();
    for (name, (tree, colours)) in &cases {
        let input = input(colours, false);
        let chosen = to_bytes(&peel_file_with(tree, &input).unwrap()).unwrap();
        let sizes: Vec<(Encoding, usize)> = Encoding::ALL
            .into_iter()
            .filter_map(|e| {
                let file = peel_file_encoded(tree, &input, Some(e)).ok()?;
                Some((e, to_bytes(&file).unwrap().len()))
            })
            .collect();
        let best = sizes.iter().map(|s| s.1).min().unwrap();
        assert_eq!(chosen.len(), best, "{name}: {sizes:?}");
        chosen_palettes.push(Scene::parse(&chosen).unwrap().header().flags);
    }
    let has = |k: usize, flag: u16| chosen_palettes[k] & flag != 0;
    assert!(
        !has(0, header_flags::PALETTE),
        "3 distinct colours in 3 polygons"
    );
    assert!(has(1, header_flags::PALETTE) && !has(1, header_flags::PALETTE16));
    assert!(
        has(3, header_flags::PALETTE16),
        "300 colours need u16 indices"
    );
    assert!(!has(4, header_flags::PALETTE), "nothing repeats");
    assert!(has(0, header_flags::INDEX16) && !has(5, header_flags::INDEX16));
    // An encoding that cannot hold the scene is refused, not truncated.
    let (tree, colours) = &cases[5].1;
    let u16_indices = Encoding {
        index16: true,
        palette: None,
    };
    assert!(peel_file_encoded(tree, &input(colours, false), Some(u16_indices)).is_err());
}

#[test]
fn corners_that_round_together_are_written_once() {
    let grid = |v: [u16; 3]| Vertex::Grid(v);
    let (a, b, c) = (grid([0, 0, 0]), grid([900, 0, 0]), grid([0, 700, 0]));
    // Each corner twice, as a triangle cut near its corners rounds: every three consecutive
    // corners hold a pair, and their plane is nil.
    let vertices = [a, a, b, b, c, c];
    let list = [1, 2, 3, 4, 5, 0];
    assert_eq!(plane_start(&vertices, DVec3::ONE, &list).1, DVec3::ZERO);
    let kept = distinct_corners(&vertices, &list);
    assert_eq!(kept, [1, 2, 4]);
    assert_eq!(
        plane_start(&vertices, DVec3::ONE, &kept).1,
        DVec3::new(0.0, 0.0, 900.0 * 700.0)
    );
    // A polygon that rounds to a segment covers nothing and keeps its list.
    let segment = [a, a, b];
    assert_eq!(distinct_corners(&segment, &[0, 1, 2]), [0, 1, 2]);
    // Distinct corners are kept in order.
    assert_eq!(distinct_corners(&[a, b, c], &[2, 0, 1]), [2, 0, 1]);
}
