//! Write: [`DisplayTree`] -> `format::PeelFile` -> bytes, and the atomic file write.
//!
//! The file is canonical whatever the order of the tree's nodes: nodes are renumbered in
//! pre-order (front before back), polygons follow the convex nodes that own them and their
//! vertex lists follow the polygons, so the reader can check ownership in one pass.
//!
//! It also carries only what the scene needs (`encoding`): `u16` indices when the vertex count
//! allows, a colour palette when it makes the file smaller, ids only when asked, and node
//! bounding boxes where they can let the runtime skip work.

mod atomic;
mod bounds;
pub(crate) mod encoding;
pub(crate) mod format;
pub(crate) mod grid;
pub mod parts;
pub(crate) mod shades;
pub(crate) mod textures;

use glam::{DVec3, Vec3};
use peel_runtime::read::Plane;

use crate::error::CompileError;
use crate::hash::FastMap;
use crate::tree::{DisplayTree, TreeNode};
use encoding::Encoding;
use format::{
    header_flags, node_kind, polygon_flags, ColourField, Header, Node, PeelFile, Polygon, Vertex,
    OPAQUE,
};

pub use atomic::{write_atomic, write_atomic_with};

fn invariant(message: impl Into<String>) -> CompileError {
    CompileError::Invariant(message.into())
}

/// `value` as a `u32` count, or an encode error naming `what`.
fn count(value: usize, what: &str) -> Result<u32, CompileError> {
    u32::try_from(value).map_err(|_| CompileError::Encode(format!("too many {what}: {value}")))
}

/// `v` rounded to `f32`, refusing values that are not finite there.
fn to_f32(v: DVec3, what: &str) -> Result<[f32; 3], CompileError> {
    let out = v.as_vec3().to_array();
    if out.iter().all(|c| c.is_finite()) {
        Ok(out)
    } else {
        Err(CompileError::Encode(format!(
            "{what} {v} is not finite in f32"
        )))
    }
}

/// What the writer stores besides the tree.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct WriteInput<'a> {
    /// Colour of each tree polygon: of both sides, or of its interior side when `exterior`
    /// is given.
    pub colours: &'a [[u8; 3]],
    /// Colour of each tree polygon's exterior side, or empty: both sides have `colours`.
    pub exterior: &'a [[u8; 3]],
    /// Keep source triangle ids.
    pub ids: bool,
    /// Added to every id kept: in a file of parts, a part's ids follow those of the parts
    /// before it.
    pub id_offset: u32,
    /// Store vertices as `f32` instead of 16-bit steps on the scene's bounds.
    pub wide_vertices: bool,
    /// Flags added to each tree polygon's ([`format::polygon_flags::SMOOTH`],
    /// [`format::polygon_flags::INTERIOR_BACK`], [`format::polygon_flags::INSIDE_INTERIOR`],
    /// [`format::polygon_flags::INSIDE_EXTERIOR`]), or empty: none.
    pub polygon_flags: &'a [u8],
    /// Per tree vertex, its `[front, back]` intensities (a smooth file, [`shades`]), or empty.
    pub shades: &'a [[u8; 2]],
    /// The textures `polygon_textures` name.
    pub textures: &'a [crate::load::texture::Texture],
    /// Per tree polygon, its index in `textures` or `NO_TEXTURE`; or empty: none is textured.
    /// When some polygon is textured the file is of version `TEXTURED_VERSION`, with the
    /// textures they use.
    pub polygon_textures: &'a [u8],
    /// Per tree vertex, its texture coordinates (`shades::uv_vertices`); empty when no
    /// polygon is textured.
    pub uvs: &'a [[i32; 2]],
    /// Per tree polygon, its opacity (`OPAQUE` for an opaque one); or empty: all are opaque.
    /// When some polygon is transparent the file is of version `TRANSPARENT_VERSION`, each
    /// such polygon flagged [`format::polygon_flags::TRANSPARENT`].
    pub opacities: &'a [u8],
}

/// The file for `tree`, `colours[i]` being the colour of `tree.polygons[i]`; source triangle
/// ids are kept when `ids` is set. Fails on a tree that breaks its invariants (a node reached
/// twice or never, an empty convex set, an index out of range).
#[cfg(test)]
pub(crate) fn peel_file(
    tree: &DisplayTree,
    colours: &[[u8; 3]],
    ids: bool,
) -> Result<PeelFile, CompileError> {
    peel_file_with(
        tree,
        &WriteInput {
            colours,
            ids,
            ..WriteInput::default()
        },
    )
}

/// [`peel_file`] with every input, in the smallest encoding ([`Encoding::smallest`]).
pub(crate) fn peel_file_with(
    tree: &DisplayTree,
    input: &WriteInput<'_>,
) -> Result<PeelFile, CompileError> {
    peel_file_encoded(tree, input, None)
}

/// [`peel_file_with`] in `encoding` (`None`: the smallest). Fails when `encoding` cannot hold
/// the scene (too many vertices for `u16` indices, colours for the palette width).
pub(crate) fn peel_file_encoded(
    tree: &DisplayTree,
    input: &WriteInput<'_>,
    encoding: Option<Encoding>,
) -> Result<PeelFile, CompileError> {
    let WriteInput {
        colours,
        exterior,
        ids,
        id_offset,
        wide_vertices,
        polygon_flags: extra_flags,
        shades,
        textures,
        polygon_textures,
        uvs,
        opacities,
    } = *input;
    let exterior = if exterior.is_empty() {
        colours
    } else {
        exterior
    };
    if colours.len() != tree.polygons.len() || exterior.len() != tree.polygons.len() {
        return Err(invariant(format!(
            "{} and {} colours for {} polygons",
            colours.len(),
            exterior.len(),
            tree.polygons.len()
        )));
    }
    let smooth_polygons = extra_flags
        .iter()
        .filter(|&&f| f & polygon_flags::SMOOTH != 0)
        .count();
    let shades_ok = if shades.is_empty() {
        smooth_polygons == 0
    } else {
        shades.len() == tree.vertices.len()
    };
    if !(extra_flags.is_empty() || extra_flags.len() == tree.polygons.len()) || !shades_ok {
        return Err(invariant(format!(
            "{} polygon flags ({smooth_polygons} smooth) and {} shades for {} polygons and {} \
             vertices",
            extra_flags.len(),
            shades.len(),
            tree.polygons.len(),
            tree.vertices.len()
        )));
    }
    let textured = polygon_textures
        .iter()
        .any(|&k| k != peel_runtime::read::layout::NO_TEXTURE);
    let textures_ok = if textured {
        polygon_textures.len() == tree.polygons.len() && uvs.len() == tree.vertices.len()
    } else {
        uvs.is_empty()
    };
    if !textures_ok {
        return Err(invariant(format!(
            "{} polygon textures and {} texture coordinates for {} polygons and {} vertices",
            polygon_textures.len(),
            uvs.len(),
            tree.polygons.len(),
            tree.vertices.len()
        )));
    }
    let transparent = opacities.iter().any(|&a| a < OPAQUE);
    if transparent && opacities.len() != tree.polygons.len() {
        return Err(invariant(format!(
            "{} opacities for {} polygons",
            opacities.len(),
            tree.polygons.len()
        )));
    }
    let wide = tree
        .vertices
        .iter()
        .map(|&v| to_f32(v, "vertex"))
        .collect::<Result<Vec<_>, _>>()?;
    let (bounds_min, bounds_max) = {
        let (lo, hi) = bounds(&wide);
        grid::covering(lo, hi)
    };
    // What the runtime will read: the f32 vertices, or their nearest steps decoded.
    let (vertices, decoded): (Vec<Vertex>, Vec<[f32; 3]>) = if wide_vertices {
        (wide.iter().map(|&v| Vertex::Wide(v)).collect(), wide)
    } else {
        tree.vertices
            .iter()
            .map(|&v| {
                let q = Vertex::Grid(grid::nearest(v, bounds_min, bounds_max));
                (q, q.position(bounds_min, bounds_max))
            })
            .unzip()
    };

    let per_step = DVec3::from([0, 1, 2].map(|k| {
        f64::from(peel_runtime::read::layout::per_step(
            bounds_min[k],
            bounds_max[k],
        ))
    }));
    let mut out = Emitter {
        tree,
        vertices: &vertices,
        per_step,
        ids,
        id_offset,
        extra_flags,
        polygon_textures,
        opacities: if transparent { opacities } else { &[] },
        opacities_out: Vec::new(),
        planes: Vec::new(),
        plane_slots: FastMap::default(),
        file_nodes: Vec::new(),
        polygons: Vec::new(),
        rgb: Vec::new(),
        rgb_exterior: Vec::new(),
        indices: Vec::new(),
        ids_out: Vec::new(),
        textures_out: Vec::new(),
        max_depth: 0,
        emitted: vec![false; tree.polygons.len()],
    };
    out.emit_nodes(&[colours, exterior])?;
    if let Some(unowned) = out.unowned_polygon() {
        return Err(invariant(format!(
            "polygon {unowned} belongs to no convex node"
        )));
    }
    let max_polygon_vertices = out
        .polygons
        .iter()
        .map(|p| u32::from(p.vertex_count))
        .max()
        .unwrap_or(0);

    // A second colour field per polygon only when some polygon's sides differ.
    let two_colours = out.rgb != out.rgb_exterior;
    let mut rgb = out.rgb.clone();
    if two_colours {
        rgb.extend_from_slice(&out.rgb_exterior);
    }
    let colours = encoding::distinct_colours(&rgb).len();
    let encoding = encoding.unwrap_or_else(|| {
        Encoding::smallest(
            vertices.len(),
            out.indices.len(),
            out.polygons.len(),
            colours,
            two_colours,
        )
    });
    let mut flags = encoding.flags(vertices.len(), colours)?;
    if two_colours {
        flags |= header_flags::TWO_COLOURS;
    }
    let (fields, palette) = encoding::colour_fields(flags, &rgb)?;
    let (interior, exterior) = fields.split_at(out.polygons.len());
    for (k, polygon) in out.polygons.iter_mut().enumerate() {
        polygon.colour = interior[k];
        polygon.exterior = exterior.get(k).copied();
    }
    let node_bounds = bounds::node_bounds(&decoded, &out.indices, &out.polygons, &out.file_nodes);
    let boxes = bounds::assign(&mut out.file_nodes, &node_bounds, bounds_min, bounds_max);
    if boxes.is_some() {
        flags |= header_flags::BOUNDS;
    }
    if wide_vertices {
        flags |= header_flags::WIDE_VERTICES;
    }
    if !shades.is_empty() {
        flags |= header_flags::SHADES;
    }
    let inside = polygon_flags::INSIDE_INTERIOR | polygon_flags::INSIDE_EXTERIOR;
    if extra_flags.iter().any(|&f| f & inside != 0) {
        flags |= header_flags::SOLID;
    }
    let stored = textures::store(textures, &out.textures_out)?;
    if stored.is_some() {
        flags |= header_flags::TEXTURES;
    }
    if transparent {
        flags |= header_flags::TRANSPARENT;
    }
    let version = if transparent {
        format::TRANSPARENT_VERSION
    } else if stored.is_some() {
        format::TEXTURED_VERSION
    } else {
        format::FORMAT_VERSION
    };
    let (uvs, texture_records, texels, polygon_textures) = match stored {
        Some(s) => (uvs.to_vec(), s.records, s.texels, s.polygons),
        None => Default::default(),
    };
    let boxes = boxes.unwrap_or_default();
    // The narrowest node and polygon fields that every count they index fits (the width's
    // largest value is NONE).
    let planes = out.planes;
    let largest = [
        planes.len(),
        out.indices.len(),
        out.polygons.len(),
        out.file_nodes.len(),
        boxes.len(),
    ]
    .into_iter()
    .max()
    .unwrap_or(0);
    if largest <= format::none_of_width(2) as usize {
        flags |= header_flags::NARROW;
    } else if largest <= format::none_of_width(3) as usize {
        flags |= header_flags::MEDIUM;
    }
    let header = Header {
        version,
        flags: if ids {
            flags | header_flags::IDS
        } else {
            flags
        },
        vertex_count: count(vertices.len(), "vertices")?,
        plane_count: count(planes.len(), "planes")?,
        index_count: count(out.indices.len(), "polygon vertices")?,
        polygon_count: count(out.polygons.len(), "polygons")?,
        node_count: count(out.file_nodes.len(), "nodes")?,
        max_depth: out.max_depth,
        max_polygon_vertices,
        centre: tree.centre.to_array(),
        bounds_min: bounds_min.into(),
        bounds_max: bounds_max.into(),
        palette_count: count(palette.len(), "palette colours")?,
        bounds_count: count(boxes.len(), "node bounds")?,
    };
    let Emitter {
        indices,
        polygons,
        ids_out,
        file_nodes,
        opacities_out,
        ..
    } = out;
    Ok(PeelFile {
        header,
        vertices,
        planes,
        indices,
        polygons,
        ids: ids_out,
        palette,
        bounds: boxes,
        nodes: file_nodes,
        shades: shades.to_vec(),
        uvs,
        textures: texture_records,
        texels,
        polygon_textures,
        opacities: opacities_out,
    })
}

/// Bounding box of `vertices` (all zero when there are none).
fn bounds(vertices: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    let Some(first) = vertices.first() else {
        return ([0.0; 3], [0.0; 3]);
    };
    vertices
        .iter()
        .fold((*first, *first), |(mut lo, mut hi), v| {
            for k in 0..3 {
                lo[k] = lo[k].min(v[k]);
                hi[k] = hi[k].max(v[k]);
            }
            (lo, hi)
        })
}

/// Builds the node, plane, polygon, index and id arrays in file order.
struct Emitter<'t> {
    tree: &'t DisplayTree,
    /// The vertices as the runtime reads them.
    vertices: &'t [Vertex],
    /// Steps per unit of length on each axis, as the runtime brings the eye to steps.
    per_step: DVec3,
    ids: bool,
    /// Added to every id.
    id_offset: u32,
    /// Flags added per tree polygon (or empty).
    extra_flags: &'t [u8],
    /// Per tree polygon, its texture (or empty).
    polygon_textures: &'t [u8],
    /// Per tree polygon, its opacity (or empty: an opaque scene).
    opacities: &'t [u8],
    /// Per file polygon, its opacity (empty for an opaque scene).
    opacities_out: Vec<u8>,
    /// The split nodes' planes, in order of first use.
    planes: Vec<[f32; 4]>,
    /// Tree plane -> index in `planes`.
    plane_slots: FastMap<u32, u32>,
    file_nodes: Vec<Node>,
    /// Polygons in file order, their colour field still RGB.
    polygons: Vec<Polygon>,
    /// RGB colour of each file polygon (of its interior side).
    rgb: Vec<[u8; 3]>,
    /// RGB colour of each file polygon's exterior side.
    rgb_exterior: Vec<[u8; 3]>,
    indices: Vec<u32>,
    ids_out: Vec<u32>,
    /// Per file polygon, its texture in `polygon_textures` (`NO_TEXTURE` without).
    textures_out: Vec<u8>,
    max_depth: u32,
    /// Per tree polygon: already written (a polygon is owned by exactly one convex node).
    emitted: Vec<bool>,
}

/// Which field of the parent record receives a child's new index.
#[derive(Clone, Copy)]
enum Slot {
    Root,
    B(u32),
    C(u32),
}

impl Emitter<'_> {
    /// Pre-order walk with an explicit stack (deep trees must not overflow the call stack).
    fn emit_nodes(&mut self, colours: &[&[[u8; 3]]; 2]) -> Result<(), CompileError> {
        let tree = self.tree;
        if tree.nodes.is_empty() {
            return Ok(());
        }
        let mut seen = vec![false; tree.nodes.len()];
        let mut stack = vec![(0u32, Slot::Root, 1u32)];
        while let Some((old, slot, depth)) = stack.pop() {
            let seen_before = seen
                .get_mut(old as usize)
                .map(|s| std::mem::replace(s, true))
                .ok_or_else(|| invariant(format!("child {old} out of range")))?;
            if seen_before {
                return Err(invariant(format!("node {old} is reached twice")));
            }
            let new = count(self.file_nodes.len(), "nodes")?;
            let parent = match slot {
                Slot::Root => format::NONE,
                Slot::B(p) => {
                    self.file_nodes[p as usize].b = new;
                    p
                }
                Slot::C(p) => {
                    self.file_nodes[p as usize].c = new;
                    p
                }
            };
            self.max_depth = self.max_depth.max(depth);
            // Child links are set as the children are written, boxes by `bounds::assign`.
            let record = |kind, a, b| Node {
                kind,
                a,
                b,
                c: format::NONE,
                parent,
                bounds: format::NONE,
            };
            match tree.nodes[old as usize] {
                TreeNode::Convex {
                    first_polygon,
                    polygon_count,
                    child,
                    ..
                } => {
                    if polygon_count == 0 {
                        return Err(invariant(format!("convex node {old} has no polygon")));
                    }
                    let first = count(self.polygons.len(), "polygons")?;
                    for p in first_polygon..first_polygon.saturating_add(polygon_count) {
                        self.emit_polygon(p, colours)?;
                    }
                    self.file_nodes
                        .push(record(node_kind::CONVEX, first, polygon_count));
                    if let Some(child) = child {
                        stack.push((child, Slot::C(new), depth + 1));
                    }
                }
                TreeNode::Split {
                    plane, front, back, ..
                } => {
                    let plane = self.split_plane(old, plane)?;
                    self.file_nodes
                        .push(record(node_kind::SPLIT, plane, format::NONE));
                    // Back first on the stack so that the front subtree comes first in the file.
                    if let Some(back) = back {
                        stack.push((back, Slot::C(new), depth + 1));
                    }
                    if let Some(front) = front {
                        stack.push((front, Slot::B(new), depth + 1));
                    }
                }
            }
        }
        match seen.iter().position(|s| !s) {
            Some(unreached) => Err(invariant(format!(
                "node {unreached} is not reachable from the root"
            ))),
            None => Ok(()),
        }
    }

    /// The file index of split node `node`'s tree plane `plane`, stored at its first use.
    fn split_plane(&mut self, node: u32, plane: u32) -> Result<u32, CompileError> {
        if let Some(&slot) = self.plane_slots.get(&plane) {
            return Ok(slot);
        }
        let p =
            self.tree.planes.get(plane as usize).ok_or_else(|| {
                invariant(format!("split node {node}: plane {plane} out of range"))
            })?;
        let [x, y, z] = to_f32(p.normal, "plane normal")?;
        let d = p.offset as f32;
        if !d.is_finite() {
            return Err(CompileError::Encode(format!(
                "plane offset {} is not finite in f32",
                p.offset
            )));
        }
        let slot = count(self.planes.len(), "planes")?;
        self.planes.push([x, y, z, d]);
        self.plane_slots.insert(plane, slot);
        Ok(slot)
    }

    /// Polygon `p`, its colours `colours[0][p]` (interior side) and `colours[1][p]`.
    fn emit_polygon(&mut self, p: u32, colours: &[&[[u8; 3]]; 2]) -> Result<(), CompileError> {
        let tree = self.tree;
        let polygon = tree
            .polygons
            .get(p as usize)
            .ok_or_else(|| invariant(format!("polygon {p} out of range")))?;
        if std::mem::replace(&mut self.emitted[p as usize], true) {
            return Err(invariant(format!(
                "polygon {p} belongs to two convex nodes"
            )));
        }
        if polygon.plane as usize >= tree.planes.len() {
            return Err(invariant(format!(
                "polygon {p}: plane {} out of range",
                polygon.plane
            )));
        }
        if polygon.vertices.len() < 3 {
            return Err(invariant(format!(
                "polygon {p} has {} vertices",
                polygon.vertices.len()
            )));
        }
        if let Some(v) = polygon
            .vertices
            .iter()
            .find(|&&v| v as usize >= tree.vertices.len())
        {
            return Err(invariant(format!("polygon {p}: vertex {v} out of range")));
        }
        let list = distinct_corners(self.vertices, &polygon.vertices);
        let n = list.len();
        let vertex_count = u8::try_from(n).map_err(|_| {
            CompileError::Encode(format!(
                "a polygon of {n} vertices: the format holds at most 255 per polygon \
                 (a smaller --max-polygon-vertices)"
            ))
        })?;
        // The runtime takes the plane through the first three vertices: start the list (in
        // its winding order) where they are farthest from collinear, and name the interior's
        // side for that plane's normal.
        let (start, normal) = plane_start(self.vertices, self.per_step, &list);
        let exact = self.tree.planes[polygon.plane as usize].normal;
        let agrees = normal.dot(exact) >= 0.0;
        let opacity = self.opacities.get(p as usize).copied();
        let see_through = opacity.is_some_and(|a| a < OPAQUE);
        let flags = if polygon.interior_front == agrees {
            polygon_flags::INTERIOR_FRONT
        } else {
            0
        } | self.extra_flags.get(p as usize).copied().unwrap_or(0)
            | if see_through {
                polygon_flags::TRANSPARENT
            } else {
                0
            };
        if let Some(a) = opacity {
            self.opacities_out.push(a);
        }
        self.polygons.push(Polygon {
            first_index: count(self.indices.len(), "polygon vertices")?,
            vertex_count,
            flags,
            colour: ColourField::Rgb(colours[0][p as usize]),
            exterior: None,
        });
        self.rgb.push(colours[0][p as usize]);
        self.rgb_exterior.push(colours[1][p as usize]);
        self.textures_out.push(
            (self.polygon_textures.get(p as usize).copied())
                .unwrap_or(peel_runtime::read::layout::NO_TEXTURE),
        );
        let (head, tail) = list.split_at(start);
        self.indices.extend_from_slice(tail);
        self.indices.extend_from_slice(head);
        if self.ids {
            let id = polygon.source.checked_add(self.id_offset).ok_or_else(|| {
                CompileError::Encode(format!(
                    "source triangle {} after {} of the parts before it: ids are 32-bit",
                    polygon.source, self.id_offset
                ))
            })?;
            self.ids_out.push(id);
        }
        Ok(())
    }

    /// A polygon of the tree that no convex node emitted.
    fn unowned_polygon(&self) -> Option<usize> {
        self.emitted.iter().position(|e| !e)
    }
}

/// `list` without the vertices that the runtime reads at the same place as the one before
/// (cyclically): a polygon the same shape, whose every three consecutive vertices can define its
/// plane. Rounding brings the ends of a short cut edge together, and a list whose vertices
/// coincide in pairs had no three that did, so its plane was nil and its side wrong. A polygon
/// with fewer than three distinct vertices, which covers nothing, keeps its list.
fn distinct_corners(vertices: &[Vertex], list: &[u32]) -> Vec<u32> {
    let at = |v: u32| vertices[v as usize];
    let mut out: Vec<u32> = Vec::with_capacity(list.len());
    for &v in list {
        if out.last().is_none_or(|&u| at(u) != at(v)) {
            out.push(v);
        }
    }
    while out.len() > 1 && at(out[0]) == at(out[out.len() - 1]) {
        out.pop();
    }
    if out.len() < 3 {
        return list.to_vec();
    }
    out
}

/// Where a polygon's vertex list should start so that the runtime's plane through its first
/// three vertices is best defined: the rotation with the longest normal (the first on ties),
/// and that normal, in the runtime's arithmetic (`peel_runtime::read::Scene::eye_side`): the
/// exact cross product of 16-bit steps, brought to world units by the steps per unit length
/// (`per_step`), or `Plane::through` on `f32` vertices.
fn plane_start(vertices: &[Vertex], per_step: DVec3, list: &[u32]) -> (usize, DVec3) {
    let n = list.len();
    let normal = |start: usize| {
        let at = |k: usize| vertices[list[(start + k) % n] as usize];
        match (at(0), at(1), at(2)) {
            (Vertex::Grid(p), Vertex::Grid(q), Vertex::Grid(r)) => {
                // Steps < 2^16: the products and their differences are exact in f64.
                let steps = |v: [u16; 3]| DVec3::from(v.map(f64::from));
                let (p, q, r) = (steps(p), steps(q), steps(r));
                (q - p).cross(r - p) * per_step
            }
            (p, q, r) => {
                let wide = |v: Vertex| match v {
                    Vertex::Wide(v) => Vec3::from(v),
                    Vertex::Grid(_) => Vec3::ZERO, // never mixed: one encoding per file
                };
                Plane::through(wide(p), wide(q), wide(r)).normal.as_dvec3()
            }
        }
    };
    let mut best = (0, DVec3::ZERO);
    for start in 0..n {
        let candidate = normal(start);
        if candidate.length_squared() > best.1.length_squared() {
            best = (start, candidate);
        }
    }
    best
}

/// The bincode bytes of `file`, with [`format::config`].
pub(crate) fn to_bytes(file: &PeelFile) -> Result<Vec<u8>, CompileError> {
    bincode::serde::encode_to_vec(file, format::config())
        .map_err(|e| CompileError::Encode(e.to_string()))
}

/// The `.peel` bytes of `tree` (see [`peel_file`]), checked by the runtime's own reader before
/// they are returned, so a file this returns is one the runtime accepts.
#[cfg(test)]
pub(crate) fn encode(
    tree: &DisplayTree,
    colours: &[[u8; 3]],
    ids: bool,
) -> Result<Vec<u8>, CompileError> {
    encode_with(
        tree,
        &WriteInput {
            colours,
            ids,
            ..WriteInput::default()
        },
    )
}

/// [`encode`] with every input (see [`peel_file_with`]).
pub(crate) fn encode_with(
    tree: &DisplayTree,
    input: &WriteInput<'_>,
) -> Result<Vec<u8>, CompileError> {
    let bytes = to_bytes(&peel_file_with(tree, input)?)?;
    peel_runtime::read::Scene::parse(&bytes)
        .map_err(|e| invariant(format!("the runtime refuses the encoded file: {e}")))?;
    Ok(bytes)
}

#[cfg(test)]
pub(crate) mod tests;
