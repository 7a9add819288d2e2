//! Small hand-made trees for the traversal and render tests (no file, no reader needed).

extern crate std;

use glam::Vec3;
use std::vec::Vec;

use super::{Tree, INTERIOR_FRONT};
use crate::display::Colour;
use crate::read::{Node, Plane, Polygon, Side, SideEye};
use crate::render::Source;

/// An in-memory display tree.
#[derive(Debug, Clone, Default)]
pub(crate) struct TestTree {
    pub nodes: Vec<Node>,
    pub planes: Vec<Plane>,
    pub polygons: Vec<Polygon>,
    pub vertices: Vec<Vec3>,
    pub indices: Vec<u32>,
    pub ids: Option<Vec<u32>>,
    pub centre: [f64; 3],
    /// Declared depth; `None` computes it.
    pub declared_depth: Option<u32>,
    /// Per node: its subtree's bounding box, if any (missing entries: none).
    pub bounds: Vec<Option<(Vec3, Vec3)>>,
    /// Per vertex its two intensities (front, back) for polygons flagged `SMOOTH`; empty:
    /// no polygon is smooth.
    pub shades: Vec<[u8; 2]>,
    /// What [`Tree::solid_sides`] answers.
    pub hidden: u8,
    /// The texture of every polygon, if any.
    pub texture: Option<crate::read::Texture<'static>>,
    /// Per vertex its texture coordinates `[s, t]` (with `texture`).
    pub uvs: Vec<[i32; 2]>,
    /// Per polygon its opacity; empty: every polygon is opaque.
    pub opacities: Vec<u8>,
}

impl TestTree {
    pub fn add_plane(&mut self, normal: Vec3, d: f32) -> u32 {
        self.planes.push(Plane { normal, d });
        (self.planes.len() - 1) as u32
    }

    /// A polygon on its own plane (through its first three vertices), with `INTERIOR_FRONT`
    /// set when `interior` lies on the plane's + side.
    pub fn add_polygon(&mut self, verts: &[Vec3], interior: Vec3, colour: Colour) -> u32 {
        let flags = if Plane::through(verts[0], verts[1], verts[2]).distance(interior) > 0.0 {
            INTERIOR_FRONT
        } else {
            0
        };
        let first_index = self.indices.len() as u32;
        for &v in verts {
            self.vertices.push(v);
            self.indices.push((self.vertices.len() - 1) as u32);
        }
        self.polygons.push(Polygon {
            first_index,
            vertex_count: verts.len() as u16,
            flags,
            colour,
        });
        (self.polygons.len() - 1) as u32
    }

    pub fn add_node(&mut self, node: Node) -> u32 {
        self.nodes.push(node);
        (self.nodes.len() - 1) as u32
    }

    fn depth_of(&self, i: Option<u32>, budget: u32) -> u32 {
        let Some(i) = i else { return 0 };
        if budget == 0 {
            return 0;
        }
        1 + match self.nodes[i as usize] {
            Node::Convex { child, .. } => self.depth_of(child, budget - 1),
            Node::Split { front, back, .. } => self
                .depth_of(front, budget - 1)
                .max(self.depth_of(back, budget - 1)),
        }
    }
}

impl Tree for TestTree {
    fn root(&self) -> Option<u32> {
        if self.nodes.is_empty() {
            None
        } else {
            Some(0)
        }
    }
    fn node(&self, i: u32) -> Node {
        self.nodes.get(i as usize).copied().unwrap_or(Node::Convex {
            first: 0,
            count: 0,
            child: None,
        })
    }
    fn plane(&self, i: u32) -> Plane {
        self.planes.get(i as usize).copied().unwrap_or_default()
    }
    fn polygon(&self, i: u32) -> Polygon {
        self.polygons.get(i as usize).copied().unwrap_or_default()
    }
    fn eye_side(&self, polygon: &Polygon, eye: &SideEye) -> Side {
        let v = |i| Source::polygon_vertex(self, polygon, i);
        Side::of(Plane::through(v(0), v(1), v(2)).distance(eye.at))
    }
    fn solid_sides(&self) -> u8 {
        self.hidden
    }
    fn node_count(&self) -> u32 {
        self.nodes.len() as u32
    }
    fn max_depth(&self) -> u32 {
        self.declared_depth
            .unwrap_or_else(|| self.depth_of(Tree::root(self), self.nodes.len() as u32))
    }
}

impl Source for TestTree {
    fn centre(&self) -> [f64; 3] {
        self.centre
    }
    fn max_polygon_vertices(&self) -> u32 {
        self.polygons
            .iter()
            .map(|p| u32::from(p.vertex_count))
            .max()
            .unwrap_or(0)
    }
    fn polygon_vertex(&self, polygon: &Polygon, i: u32) -> Vec3 {
        let k = polygon.first_index as usize + i as usize;
        self.indices
            .get(k)
            .and_then(|&v| self.vertices.get(v as usize))
            .copied()
            .unwrap_or_default()
    }
    fn has_ids(&self) -> bool {
        self.ids.is_some()
    }
    fn id(&self, i: u32) -> Option<u32> {
        self.ids
            .as_ref()
            .and_then(|ids| ids.get(i as usize))
            .copied()
    }
    fn node_bounds(&self, i: u32) -> Option<(Vec3, Vec3)> {
        self.bounds.get(i as usize).copied().flatten()
    }
    fn shade_side(&self, polygon: &Polygon, interior: bool) -> Option<usize> {
        if self.shades.is_empty() {
            return None;
        }
        crate::read::Scene::shade_side(polygon.flags, interior)
    }
    fn corner_shade(&self, polygon: &Polygon, i: u32, side: usize) -> u8 {
        let k = polygon.first_index as usize + i as usize;
        self.indices
            .get(k)
            .and_then(|&v| self.shades.get(v as usize))
            .map_or(0, |s| s[side & 1])
    }
    fn texture(&self, i: u32) -> Option<crate::read::Texture<'_>> {
        let _ = i;
        self.texture
    }
    fn corner_uv(&self, polygon: &Polygon, i: u32) -> [i32; 2] {
        let k = polygon.first_index as usize + i as usize;
        self.indices
            .get(k)
            .and_then(|&v| self.uvs.get(v as usize))
            .copied()
            .unwrap_or_default()
    }
    fn has_transparency(&self) -> bool {
        self.opacities.iter().any(|&a| a < u8::MAX)
    }
    fn opacity(&self, i: u32, _: &Polygon) -> u8 {
        self.opacities.get(i as usize).copied().unwrap_or(u8::MAX)
    }
}

/// The six faces of the axis-aligned box `[lo, hi]` as quads, interior towards the box.
pub(crate) fn box_faces(t: &mut TestTree, lo: Vec3, hi: Vec3, colour: Colour) -> (u32, u32) {
    let first = t.polygons.len() as u32;
    let c = (lo + hi) * 0.5;
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let faces = [
        // -x, +x, -y, +y, -z, +z
        [
            v(lo.x, lo.y, lo.z),
            v(lo.x, hi.y, lo.z),
            v(lo.x, hi.y, hi.z),
            v(lo.x, lo.y, hi.z),
        ],
        [
            v(hi.x, lo.y, lo.z),
            v(hi.x, hi.y, lo.z),
            v(hi.x, hi.y, hi.z),
            v(hi.x, lo.y, hi.z),
        ],
        [
            v(lo.x, lo.y, lo.z),
            v(hi.x, lo.y, lo.z),
            v(hi.x, lo.y, hi.z),
            v(lo.x, lo.y, hi.z),
        ],
        [
            v(lo.x, hi.y, lo.z),
            v(hi.x, hi.y, lo.z),
            v(hi.x, hi.y, hi.z),
            v(lo.x, hi.y, hi.z),
        ],
        [
            v(lo.x, lo.y, lo.z),
            v(hi.x, lo.y, lo.z),
            v(hi.x, hi.y, lo.z),
            v(lo.x, hi.y, lo.z),
        ],
        [
            v(lo.x, lo.y, hi.z),
            v(hi.x, lo.y, hi.z),
            v(hi.x, hi.y, hi.z),
            v(lo.x, hi.y, hi.z),
        ],
    ];
    for f in faces {
        t.add_polygon(&f, c, colour);
    }
    (first, 6)
}

/// `tree` as `.peel` bytes, following the format's layout record by record (children must
/// come after their parents, as in a file).
pub(crate) fn encode(tree: &TestTree) -> Vec<u8> {
    use crate::read::layout::{header_flags, node_kind, FORMAT_VERSION, HEADER_SIZE, MAGIC, NONE};
    let mut parents = std::vec![NONE; tree.nodes.len()];
    for (i, n) in tree.nodes.iter().enumerate() {
        let children = match *n {
            Node::Convex { child, .. } => [child, None],
            Node::Split { front, back, .. } => [front, back],
        };
        for c in children.into_iter().flatten() {
            parents[c as usize] = i as u32;
        }
    }
    let (mut lo, mut hi) = (Vec3::ZERO, Vec3::ZERO);
    for &v in &tree.vertices {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    let mut out = Vec::new();
    out.extend(MAGIC);
    out.extend(FORMAT_VERSION.to_le_bytes());
    // f32 vertices: the file reads back exactly what the tree holds.
    let flags = if tree.ids.is_some() {
        header_flags::IDS | header_flags::WIDE_VERTICES
    } else {
        header_flags::WIDE_VERTICES
    };
    out.extend(flags.to_le_bytes());
    for v in [
        tree.vertices.len() as u32,
        tree.planes.len() as u32,
        tree.indices.len() as u32,
        tree.polygons.len() as u32,
        tree.nodes.len() as u32,
        Tree::max_depth(tree),
        Source::max_polygon_vertices(tree),
    ] {
        out.extend(v.to_le_bytes());
    }
    for v in tree.centre {
        out.extend(v.to_le_bytes());
    }
    for v in lo.to_array().into_iter().chain(hi.to_array()) {
        out.extend(v.to_le_bytes());
    }
    // No palette, no bounds.
    out.extend([0u8; 8]);
    assert_eq!(out.len(), HEADER_SIZE);
    let length = |out: &mut Vec<u8>, n: usize| out.extend((n as u64).to_le_bytes());
    length(&mut out, tree.vertices.len());
    for v in tree.vertices.iter().flat_map(|v| v.to_array()) {
        out.extend(v.to_le_bytes());
    }
    length(&mut out, tree.planes.len());
    for p in &tree.planes {
        for v in p.normal.to_array().into_iter().chain([p.d]) {
            out.extend(v.to_le_bytes());
        }
    }
    length(&mut out, tree.indices.len());
    for v in &tree.indices {
        out.extend(v.to_le_bytes());
    }
    length(&mut out, tree.polygons.len());
    for p in &tree.polygons {
        out.extend(p.first_index.to_le_bytes());
        out.push(p.vertex_count as u8);
        out.push(p.flags);
        out.extend([p.colour.r, p.colour.g, p.colour.b]);
    }
    let ids = tree.ids.clone().unwrap_or_default();
    length(&mut out, ids.len());
    for v in ids {
        out.extend(v.to_le_bytes());
    }
    length(&mut out, 0);
    length(&mut out, 0);
    length(&mut out, tree.nodes.len());
    let opt = |c: Option<u32>| c.unwrap_or(NONE);
    for (i, (n, parent)) in tree.nodes.iter().zip(parents).enumerate() {
        // The first child (convex child, split + child) is implicit: the next node.
        let (kind, a, first, second) = match *n {
            Node::Convex {
                first,
                count,
                child,
            } => (node_kind::CONVEX, first, child, count),
            Node::Split { plane, front, back } => (node_kind::SPLIT, plane, front, opt(back)),
        };
        match first {
            None => out.push(kind),
            Some(child) => {
                assert_eq!(child as usize, i + 1, "a first child is the next node");
                out.push(kind | node_kind::FIRST_CHILD);
            }
        }
        for v in [a, second, parent] {
            out.extend(v.to_le_bytes());
        }
    }
    out
}
