//! `peel dump` and `peel inspect`: a `.peel` file read back through the runtime's reader (so
//! what is shown is what the runtime sees), as deterministic YAML or as a few counters.

use std::fmt::Write as _;

use peel_runtime::pending::PendingPixel;
use peel_runtime::read::layout::{header_flags, polygon_flags, texture_flags, TEXEL_SIZE};
use peel_runtime::read::{Node, Scene};
use peel_runtime::scan::ScanNode;
use peel_runtime::vertices::CachedVertex;
use peel_runtime::ReadError;
use serde::Serialize;

use crate::builder::sizes::FrameMemory;

/// Decimals of every float in the dump: fixed, so that snapshots are stable.
const DECIMALS: usize = 6;

/// One texture of a file, for `peel inspect`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct InspectTexture {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// The colours of its palette (0: RGB565 texels).
    pub palette_colours: u32,
    /// Columns past the edges take the edge column (else it repeats across `s`).
    pub clamp_s: bool,
    /// Rows past the edges take the edge row (else it repeats across `t`).
    pub clamp_t: bool,
    /// Its bytes in the file (palette and texels).
    pub bytes: u64,
}

/// Counters of `peel inspect`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Inspect {
    /// The file's format version.
    pub format_version: u16,
    /// Polygons.
    pub output_polygons: u64,
    /// Convex nodes.
    pub convex_nodes: u64,
    /// Split nodes.
    pub split_nodes: u64,
    /// Nodes on the longest root-to-leaf path (the header's value, checked by the reader).
    pub max_depth: u64,
    /// Largest polygon vertex count.
    pub max_polygon_vertices: u64,
    /// Split planes stored (a split node's plane; polygons' planes are not stored). The
    /// compile summary's "planes" are the distinct planes of the output, polygons' included.
    pub split_planes: u64,
    /// Distinct vertices.
    pub vertices: u64,
    /// Whether source triangle ids are present.
    pub ids: bool,
    /// Polygons smooth-shaded (their vertices' shades interpolated; 0 without shades).
    pub smooth_polygons: u64,
    /// Polygons that bound solids (`peel compile --solid`): skipped when seen from behind.
    pub solid_polygons: u64,
    /// Polygons drawn with a texture.
    pub textured_polygons: u64,
    /// The textures, in file order (none in a file without textures).
    pub textures: Vec<InspectTexture>,
    /// The textures' bytes together (their palettes and texels).
    pub texture_bytes: u64,
    /// World position of the centre of the scene's bounding box (what a framing camera looks
    /// at).
    pub centre: [f64; 3],
    /// World lower corner of the scene's bounding box.
    pub bounds_min: [f64; 3],
    /// World upper corner of the scene's bounding box.
    pub bounds_max: [f64; 3],
    /// Half the box diagonal: the radius of a sphere holding the whole scene.
    pub radius: f64,
    /// Palette colours (0 without a palette).
    pub palette_colours: u64,
    /// Distinct node bounding boxes stored.
    pub node_bounds: u64,
    /// File size.
    pub bytes: u64,
    /// The memory a frame needs, as the sizes file gives it (the defaults; [`inspect_at`]
    /// measures span and scan memory at an image size).
    pub frame_memory: FrameMemory,
}

/// The counters of a `.peel` file (validated first).
pub fn inspect(bytes: &[u8]) -> Result<Inspect, ReadError> {
    let scene = Scene::parse(bytes)?;
    let header = scene.header();
    let origin = glam::DVec3::from_array(header.centre);
    let (lo, hi) = (header.bounds_min.as_dvec3(), header.bounds_max.as_dvec3());
    let convex_nodes = (0..header.node_count)
        .filter(|&i| matches!(scene.node(i), Node::Convex { .. }))
        .count() as u64;
    let textures: Vec<InspectTexture> = (0..scene.texture_count())
        .filter_map(|k| inspect_texture(&scene, k))
        .collect();
    Ok(Inspect {
        format_version: header.version,
        output_polygons: header.polygon_count.into(),
        convex_nodes,
        split_nodes: u64::from(header.node_count) - convex_nodes,
        max_depth: header.max_depth.into(),
        max_polygon_vertices: header.max_polygon_vertices.into(),
        split_planes: header.plane_count.into(),
        vertices: header.vertex_count.into(),
        ids: header.flags & header_flags::IDS != 0,
        smooth_polygons: (0..header.polygon_count)
            .filter(|&p| scene.polygon(p).flags & polygon_flags::SMOOTH != 0)
            .count() as u64,
        solid_polygons: (0..header.polygon_count)
            .filter(|&p| {
                let inside = polygon_flags::INSIDE_INTERIOR | polygon_flags::INSIDE_EXTERIOR;
                scene.polygon(p).flags & inside != 0
            })
            .count() as u64,
        textured_polygons: (0..header.polygon_count)
            .filter(|&p| scene.polygon_texture(p).is_some())
            .count() as u64,
        texture_bytes: textures.iter().map(|t| t.bytes).sum(),
        textures,
        centre: (origin + (lo + hi) * 0.5).to_array(),
        bounds_min: (origin + lo).to_array(),
        bounds_max: (origin + hi).to_array(),
        radius: (hi - lo).length() * 0.5,
        palette_colours: header.palette_count.into(),
        node_bounds: header.bounds_count.into(),
        bytes: bytes.len() as u64,
        frame_memory: FrameMemory::of(&header, None),
    })
}

/// Texture `k` of `scene`, for `peel inspect` and `peel dump`.
fn inspect_texture(scene: &Scene<'_>, k: u32) -> Option<InspectTexture> {
    let t = scene.texture(k)?;
    Some(InspectTexture {
        width: 1 << t.log2_width,
        height: 1 << t.log2_height,
        palette_colours: (t.colours.len() / TEXEL_SIZE) as u32,
        clamp_s: t.flags & texture_flags::CLAMP_S != 0,
        clamp_t: t.flags & texture_flags::CLAMP_T != 0,
        bytes: (t.colours.len() + t.texels.len()) as u64,
    })
}

/// [`inspect`] with the span and scan memory measured at `width x height`
/// ([`FrameMemory::measured`], as `Builder::image_size` measures them).
///
/// # Errors
/// The reader's error or the measurement's, as text.
pub fn inspect_at(bytes: &[u8], width: u32, height: u32) -> Result<Inspect, String> {
    let mut info = inspect(bytes).map_err(|e| e.to_string())?;
    info.frame_memory = FrameMemory::measured(bytes, width, height)?;
    Ok(info)
}

/// The counters as `peel inspect` prints them: one `name: value` line each (the names of
/// `--json`), world coordinates with six decimals as in the dump, then the frame memory with
/// its bytes.
pub fn inspect_text(info: &Inspect) -> String {
    let mut out = String::new();
    let mut line = |name: &str, value: String| {
        let _ = writeln!(out, "{name}: {value}");
    };
    line("format_version", info.format_version.to_string());
    line("output_polygons", info.output_polygons.to_string());
    line("convex_nodes", info.convex_nodes.to_string());
    line("split_nodes", info.split_nodes.to_string());
    line("max_depth", info.max_depth.to_string());
    line(
        "max_polygon_vertices",
        info.max_polygon_vertices.to_string(),
    );
    line("split_planes", info.split_planes.to_string());
    line("vertices", info.vertices.to_string());
    line("ids", info.ids.to_string());
    line("smooth_polygons", info.smooth_polygons.to_string());
    line("solid_polygons", info.solid_polygons.to_string());
    line("textured_polygons", info.textured_polygons.to_string());
    line("centre", triple(info.centre));
    line("bounds_min", triple(info.bounds_min));
    line("bounds_max", triple(info.bounds_max));
    line("radius", fixed(info.radius));
    line("palette_colours", info.palette_colours.to_string());
    line("node_bounds", info.node_bounds.to_string());
    // The count, then a line per texture.
    let listed: String = (info.textures.iter())
        .map(|t| format!("\n  - {}", texture_text(t)))
        .collect();
    line("textures", format!("{}{listed}", info.textures.len()));
    line("texture_bytes", info.texture_bytes.to_string());
    line("bytes", info.bytes.to_string());
    frame_memory_lines(&mut out, &info.frame_memory, "");
    out
}

/// A texture in a line: `256x128, palette of 12 colours, clamp s and t, 32792 bytes`.
fn texture_text(t: &InspectTexture) -> String {
    let texels = match t.palette_colours {
        0 => "RGB565".to_string(),
        1 => "palette of 1 colour".to_string(),
        n => format!("palette of {n} colours"),
    };
    let wrap = match (t.clamp_s, t.clamp_t) {
        (false, false) => "repeats",
        (true, true) => "clamp s and t",
        (true, false) => "clamp s",
        (false, true) => "clamp t",
    };
    format!(
        "{}x{}, {texels}, {wrap}, {} bytes",
        t.width, t.height, t.bytes
    )
}

/// The frame memory lines of `peel inspect` (the heading, then the figures with their bytes),
/// the heading saying `whose` figures they are.
fn frame_memory_lines(out: &mut String, m: &FrameMemory, whose: &str) {
    let _ = match m.measured_at {
        Some((w, h)) => writeln!(
            out,
            "frame_memory (the sizes file's{whose}, measured at {w}x{h} over an orbit of the \
             scene):"
        ),
        None => writeln!(
            out,
            "frame_memory (the sizes file's{whose}; span and scan memory are the defaults, \
             `--size WxH` measures them):"
        ),
    };
    let mut line = |name: &str, value: String| {
        let _ = writeln!(out, "  {name}: {value}");
    };
    let bytes = |count: usize, each: usize| format!("{count} ({} bytes)", count * each);
    line("stack", m.stack.to_string());
    line("verts", m.verts.to_string());
    line(
        "vertex_memory",
        bytes(m.vertex_memory, size_of::<CachedVertex>()),
    );
    line(
        "spans_per_row",
        match m.measured_at {
            Some((_, h)) => format!(
                "{} ({} bytes at {h} rows)",
                m.spans_per_row,
                m.spans_per_row * h as usize * size_of::<(u16, u16)>()
            ),
            None => m.spans_per_row.to_string(),
        },
    );
    line("scan_nodes", bytes(m.scan_nodes, size_of::<ScanNode>()));
    line(
        "scan_nodes_aa",
        bytes(m.scan_nodes_aa, size_of::<ScanNode>()),
    );
    line(
        "pending_pixels",
        bytes(m.pending_pixels, size_of::<PendingPixel>()),
    );
    if m.composite_runs > 0 {
        line(
            "composite_runs",
            bytes(m.composite_runs, peel_runtime::composite::RUN_BYTES),
        );
    }
}

/// One part of a file of parts, for `peel inspect`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InspectPart {
    /// The object's name; empty for the world.
    pub name: String,
    /// The part's tree's counters.
    #[serde(flatten)]
    pub counters: Inspect,
}

/// Counters of `peel inspect` for a file of parts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InspectParts {
    /// The file's format version (`PARTS_VERSION`).
    pub format_version: u16,
    /// Whether part 0 is the world.
    pub world: bool,
    /// File size.
    pub bytes: u64,
    /// Each part, in file order.
    pub parts: Vec<InspectPart>,
    /// The largest of each figure over the parts: one workspace that draws every part.
    pub frame_memory: FrameMemory,
}

/// The counters of a file of parts and of each of its parts (each tree validated), the
/// frame memory measured at `size` if given.
///
/// # Errors
/// What is wrong with the file, or the measurement's error.
pub fn inspect_parts(bytes: &[u8], size: Option<(u32, u32)>) -> Result<InspectParts, String> {
    let read = crate::write::parts::read_parts(bytes)?;
    let mut parts = Vec::with_capacity(read.len());
    for part in &read {
        let mut counters = inspect(part.tree).map_err(|e| e.to_string())?;
        if let Some((width, height)) = size {
            counters.frame_memory = FrameMemory::measured(part.tree, width, height)?;
        }
        parts.push(InspectPart {
            name: part.name.to_string(),
            counters,
        });
    }
    let frame_memory = (parts.iter().map(|p| p.counters.frame_memory))
        .reduce(FrameMemory::max)
        .ok_or("a file of parts without parts")?;
    Ok(InspectParts {
        format_version: peel_runtime::read::layout::PARTS_VERSION,
        world: read.first().is_some_and(|p| p.name.is_empty()),
        bytes: bytes.len() as u64,
        parts,
        frame_memory,
    })
}

/// [`InspectParts`] as `peel inspect` prints it: the file's lines, each part's
/// ([`inspect_text`], indented under `part K (NAME):`), then the frame memory every part fits.
pub fn inspect_parts_text(info: &InspectParts) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "format_version: {}", info.format_version);
    let _ = writeln!(out, "world: {}", info.world);
    let _ = writeln!(out, "parts: {}", info.parts.len());
    let _ = writeln!(out, "bytes: {}", info.bytes);
    for (k, part) in info.parts.iter().enumerate() {
        let label = if part.name.is_empty() {
            "world"
        } else {
            &part.name
        };
        let _ = writeln!(out, "part {k} ({label}):");
        for line in inspect_text(&part.counters).lines() {
            let _ = writeln!(out, "  {line}");
        }
    }
    frame_memory_lines(&mut out, &info.frame_memory, ", the largest over the parts");
    out
}

/// `v` with [`DECIMALS`] decimals, without the sign of a value that rounds to zero.
fn fixed(v: f64) -> String {
    let s = format!("{v:.DECIMALS$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_string(),
        _ => s,
    }
}

fn triple(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", fixed(v[0]), fixed(v[1]), fixed(v[2]))
}

fn f32_triple(v: glam::Vec3) -> String {
    triple(v.as_dvec3().to_array())
}

/// Names of the set bits, as a YAML flow sequence.
fn flag_names(names: &[(bool, &str)]) -> String {
    let set: Vec<&str> = names
        .iter()
        .filter(|(on, _)| *on)
        .map(|(_, name)| *name)
        .collect();
    format!("[{}]", set.join(", "))
}

/// Deepest indentation of the nested tree: a child that would be indented further is written
/// as `name: {subtree: N}` and node `N` is printed, nested again from the left, as an entry of
/// the top-level `subtrees` list. Nearly convex meshes give trees tens of thousands of nodes
/// deep, where nesting all the way makes the output quadratic in the depth (gigabytes of
/// spaces) and overflows the formatter's width.
const MAX_INDENT: usize = 256;

/// What is left to print, innermost last (an explicit stack: deep trees must not overflow).
enum Item {
    /// A node's fields at this indentation.
    Node(u32, usize),
    /// `name: null`, or `name:` followed by the child node, indented once more.
    Child(&'static str, Option<u32>, usize),
}

/// The whole file as a YAML document: the header (its `centre` is the world origin of every
/// coordinate that follows, where `peel inspect`'s is the box's centre in world coordinates;
/// both with six decimals), the split planes, then the tree as nested nodes
/// with their polygons (flags, colour, the exterior side's colour where it differs, id if
/// present, vertices, a smooth polygon's vertices' shades `[front, back]`, a textured
/// polygon's texture and its vertices' coordinates `[s, t]`; the textures themselves are
/// listed after the header, one line each); subtrees nested deeper
/// than `MAX_INDENT` (256 spaces) follow in a `subtrees` list, in the order they are referred to.
pub fn dump_yaml(bytes: &[u8]) -> Result<String, ReadError> {
    let scene = Scene::parse(bytes)?;
    let h = scene.header();
    let mut out = String::new();
    let ids = flag_names(&[
        (h.flags & header_flags::IDS != 0, "ids"),
        (h.flags & header_flags::INDEX16 != 0, "index16"),
        (h.flags & header_flags::PALETTE != 0, "palette"),
        (h.flags & header_flags::PALETTE16 != 0, "palette16"),
        (h.flags & header_flags::BOUNDS != 0, "bounds"),
        (h.flags & header_flags::NARROW != 0, "narrow"),
        (h.flags & header_flags::MEDIUM != 0, "medium"),
        (h.flags & header_flags::TWO_COLOURS != 0, "two_colours"),
        (h.flags & header_flags::SHADES != 0, "shades"),
        (h.flags & header_flags::TEXTURES != 0, "textures"),
    ]);
    // Writing into a String cannot fail.
    let _ = writeln!(
        out,
        "header:\n  version: {}\n  flags: {ids}\n  vertices: {}\n  split_planes: {}\n  indices: {}\n  \
         polygons: {}\n  nodes: {}\n  max_depth: {}\n  max_polygon_vertices: {}\n  \
         centre: {}  # world origin of the coordinates below\n  \
         bounds_min: {}  # relative to centre\n  bounds_max: {}  # relative to centre\n  palette: {}\n  node_bounds: {}",
        h.version,
        h.vertex_count,
        h.plane_count,
        h.index_count,
        h.polygon_count,
        h.node_count,
        h.max_depth,
        h.max_polygon_vertices,
        triple(h.centre),
        f32_triple(h.bounds_min),
        f32_triple(h.bounds_max),
        h.palette_count,
        h.bounds_count,
    );
    if scene.texture_count() > 0 {
        out.push_str("textures:\n");
        for k in 0..scene.texture_count() {
            if let Some(t) = inspect_texture(&scene, k) {
                let _ = writeln!(out, "  - {}  # {k}", texture_text(&t));
            }
        }
    }
    if h.plane_count == 0 {
        out.push_str("split_planes: []\n");
    } else {
        out.push_str("split_planes:\n");
        for i in 0..h.plane_count {
            let p = scene.plane(i);
            let n = p.normal.as_dvec3();
            let d = fixed(p.d.into());
            let _ = writeln!(
                out,
                "  - [{}, {}, {}, {d}]",
                fixed(n.x),
                fixed(n.y),
                fixed(n.z)
            );
        }
    }
    let mut stack = vec![Item::Child("tree", scene.root(), 0)];
    // Subtrees moved to the `subtrees` list, and how many of them are printed.
    let (mut moved, mut printed) = (Vec::new(), 0);
    loop {
        let Some(item) = stack.pop() else {
            let Some(&node) = moved.get(printed) else {
                break;
            };
            if printed == 0 {
                out.push_str("subtrees:\n");
            }
            printed += 1;
            out.push_str("  -\n");
            stack.push(Item::Node(node, 4));
            continue;
        };
        match item {
            Item::Child(name, None, indent) => {
                let _ = writeln!(out, "{:indent$}{name}: null", "");
            }
            Item::Child(name, Some(node), indent) if indent >= MAX_INDENT => {
                let _ = writeln!(out, "{:indent$}{name}: {{subtree: {node}}}", "");
                moved.push(node);
            }
            Item::Child(name, Some(node), indent) => {
                let _ = writeln!(out, "{:indent$}{name}:", "");
                stack.push(Item::Node(node, indent + 2));
            }
            Item::Node(i, indent) => {
                if let Some((lo, hi)) = scene.node_bounds(i) {
                    let (lo, hi) = (f32_triple(lo), f32_triple(hi));
                    let _ = writeln!(out, "{:indent$}bounds: [{lo}, {hi}]", "");
                }
                match scene.node(i) {
                    Node::Convex {
                        first,
                        count,
                        child,
                    } => {
                        let _ =
                            writeln!(out, "{:indent$}kind: convex\n{:indent$}node: {i}", "", "");
                        let _ = writeln!(out, "{:indent$}polygons:", "");
                        for p in first..first.saturating_add(count) {
                            write_polygon(&mut out, &scene, p, indent + 2);
                        }
                        stack.push(Item::Child("child", child, indent));
                    }
                    Node::Split { plane, front, back } => {
                        let _ = writeln!(
                            out,
                            "{:indent$}kind: split\n{:indent$}node: {i}\n{:indent$}plane: {plane}",
                            "", "", ""
                        );
                        stack.push(Item::Child("back", back, indent));
                        stack.push(Item::Child("front", front, indent));
                    }
                }
            }
        }
    }
    Ok(out)
}

/// One polygon as a sequence entry at `indent`.
fn write_polygon(out: &mut String, scene: &Scene<'_>, p: u32, indent: usize) {
    let polygon = scene.polygon(p);
    let flags = flag_names(&[
        (
            polygon.flags & polygon_flags::INTERIOR_FRONT != 0,
            "interior_front",
        ),
        (polygon.flags & polygon_flags::SMOOTH != 0, "smooth"),
        (
            polygon.flags & polygon_flags::INTERIOR_BACK != 0,
            "interior_back",
        ),
    ]);
    let c = polygon.colour;
    let _ = writeln!(out, "{:indent$}- index: {p}", "");
    let inner = indent + 2;
    let _ = writeln!(
        out,
        "{:inner$}flags: {flags}\n{:inner$}colour: [{}, {}, {}]",
        "", "", c.r, c.g, c.b
    );
    let e = scene.colour_seen(p, false);
    if e != c {
        let _ = writeln!(
            out,
            "{:inner$}exterior_colour: [{}, {}, {}]",
            "", e.r, e.g, e.b
        );
    }
    if let Some(id) = scene.id(p) {
        let _ = writeln!(out, "{:inner$}id: {id}", "");
    }
    let _ = writeln!(out, "{:inner$}vertices:", "");
    for k in 0..u32::from(polygon.vertex_count) {
        let _ = writeln!(
            out,
            "{:inner$}  - {}",
            "",
            f32_triple(scene.polygon_vertex(&polygon, k))
        );
    }
    if let Some(texture) = scene.polygon_texture(p) {
        // The texture's index: the one whose texels these are.
        let k = (0..scene.texture_count()).find(|&k| {
            scene
                .texture(k)
                .is_some_and(|t| t.texels.as_ptr() == texture.texels.as_ptr())
        });
        let uvs: Vec<String> = (0..u32::from(polygon.vertex_count))
            .map(|k| {
                let v = scene.polygon_vertex_index(&polygon, k).unwrap_or(u32::MAX);
                let [s, t] = scene.vertex_uv(v);
                format!("[{s}, {t}]")
            })
            .collect();
        let k = k.map_or_else(|| "null".to_string(), |k| k.to_string());
        let _ = writeln!(out, "{:inner$}texture: {k}", "");
        let _ = writeln!(out, "{:inner$}uvs: [{}]", "", uvs.join(", "));
    }
    if polygon.flags & polygon_flags::SMOOTH != 0 {
        // Each vertex's intensities, [front, back] of the source triangle.
        let shades: Vec<String> = (0..u32::from(polygon.vertex_count))
            .map(|k| {
                let v = scene.polygon_vertex_index(&polygon, k).unwrap_or(u32::MAX);
                format!(
                    "[{}, {}]",
                    scene.vertex_shade(v, 0),
                    scene.vertex_shade(v, 1)
                )
            })
            .collect();
        let _ = writeln!(out, "{:inner$}shades: [{}]", "", shades.join(", "));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builder::sizes::{
        RECOMMENDED_PENDING_PIXELS, RECOMMENDED_SCAN_NODES, RECOMMENDED_SCAN_NODES_AA,
        RECOMMENDED_SPANS_PER_ROW,
    };
    use crate::write::tests::{chain_tree, small_tree};
    use peel_runtime::clip;

    #[test]
    fn dump_of_a_small_tree() {
        let (tree, colours) = small_tree();
        let bytes = crate::write::encode(&tree, &colours, true).unwrap();
        insta::assert_snapshot!(dump_yaml(&bytes).unwrap());
    }

    #[test]
    fn dump_without_ids_has_no_id_lines() {
        let (tree, colours) = small_tree();
        let bytes = crate::write::encode(&tree, &colours, false).unwrap();
        let yaml = dump_yaml(&bytes).unwrap();
        assert!(
            yaml.contains("flags: [index16, bounds, narrow]\n") && !yaml.contains("id:"),
            "{yaml}"
        );
    }

    #[test]
    fn dump_of_a_deep_tree_does_not_recurse_and_stays_linear() {
        // Run on a stack far too small for one frame per level, and deeper than the
        // formatter's widest indentation (65,535) if it were nested all the way.
        let depth = 40_000;
        let (tree, colours) = chain_tree(depth);
        let bytes = crate::write::encode(&tree, &colours, false).unwrap();
        let nodes = Scene::parse(&bytes).unwrap().header().node_count as usize;
        let yaml = std::thread::Builder::new()
            .stack_size(48 * 1024)
            .spawn(move || dump_yaml(&bytes).unwrap())
            .unwrap()
            .join()
            .unwrap();
        assert_eq!(yaml.matches("kind: convex").count(), depth as usize);
        // Every node exactly once, every moved subtree referred to once and printed once.
        let mut seen = vec![0u32; nodes];
        for line in yaml.lines() {
            if let Some(i) = line.trim_start().strip_prefix("node: ") {
                seen[i.parse::<usize>().unwrap()] += 1;
            }
        }
        assert!(seen.iter().all(|&k| k == 1));
        let refs = yaml.matches("{subtree: ").count();
        assert!(refs > 0);
        assert_eq!(yaml.matches("\n  -\n").count(), refs);
        // Linear in the depth: no line indented past the limit (plus a polygon's own levels).
        let widest = yaml.lines().map(|l| l.len() - l.trim_start().len()).max();
        assert!(widest.unwrap() <= MAX_INDENT + 8, "{widest:?}");
        assert!(yaml.len() < 4096 * depth as usize, "{} bytes", yaml.len());
    }

    #[test]
    fn dump_refuses_invalid_bytes() {
        assert_eq!(dump_yaml(b"nope").unwrap_err(), ReadError::BadMagic);
        assert_eq!(
            inspect(b"PEE").unwrap_err(),
            ReadError::Truncated { offset: 0 }
        );
    }

    #[test]
    fn inspect_counts() {
        let (tree, colours) = small_tree();
        let bytes = crate::write::encode(&tree, &colours, true).unwrap();
        let info = inspect(&bytes).unwrap();
        // The tree's vertices span (-0.25, 0, 0)..(1, 1, 1) around (100, 200, 300); the header
        // holds the grid that covers them.
        let (lo, hi) = crate::write::grid::covering([-0.25, 0.0, 0.0], [1.0; 3]);
        let (lo, hi) = (
            glam::Vec3::from(lo).as_dvec3(),
            glam::Vec3::from(hi).as_dvec3(),
        );
        let origin = glam::DVec3::new(100.0, 200.0, 300.0);
        let expected = Inspect {
            format_version: 4,
            output_polygons: 3,
            convex_nodes: 3,
            split_nodes: 1,
            max_depth: 3,
            max_polygon_vertices: 4,
            split_planes: 1, // the split's; polygons' planes are not stored
            vertices: 7,
            ids: true,
            smooth_polygons: 0,
            solid_polygons: 0,
            textured_polygons: 0,
            textures: Vec::new(),
            texture_bytes: 0,
            centre: (origin + (lo + hi) * 0.5).to_array(),
            bounds_min: (origin + lo).to_array(),
            bounds_max: (origin + hi).to_array(),
            radius: (hi - lo).length() * 0.5,
            palette_colours: 0,
            node_bounds: 1,
            bytes: bytes.len() as u64,
            frame_memory: FrameMemory {
                stack: 3,
                verts: clip::buffer_len_for(4) as usize,
                vertex_memory: 8,
                spans_per_row: RECOMMENDED_SPANS_PER_ROW,
                scan_nodes: RECOMMENDED_SCAN_NODES,
                scan_nodes_aa: RECOMMENDED_SCAN_NODES_AA,
                pending_pixels: RECOMMENDED_PENDING_PIXELS,
                composite_runs: 0,
                measured_at: None,
            },
        };
        assert_eq!(info, expected);
    }

    /// A box whose faces are textured but one: the texture listed once, the textured polygons
    /// counted, each with its texture and its vertices' coordinates in the dump.
    #[test]
    fn a_textured_file_lists_its_textures() {
        use crate::compile::{compile_mesh, CompileOptions};
        use crate::tools::scenes;
        let mut mesh = scenes::textured(scenes::box_grid(1), 2, |t| {
            t.map(|p| glam::DVec2::new(p.x + p.z, p.y))
        });
        mesh.triangles[0].texture = None;
        let bytes = compile_mesh(&mesh, &CompileOptions::default(), &|_| {})
            .unwrap()
            .1;
        let info = inspect(&bytes).unwrap();
        assert_eq!(info.format_version, 6);
        assert_eq!(info.textured_polygons, info.output_polygons - 1);
        let checkerboard = InspectTexture {
            width: 4,
            height: 4,
            palette_colours: 2,
            clamp_s: false,
            clamp_t: false,
            bytes: 4 + 16,
        };
        assert_eq!(
            (info.textures.as_slice(), info.texture_bytes),
            (&[checkerboard][..], 20)
        );
        let text = inspect_text(&info);
        assert!(
            text.contains("textures: 1\n  - 4x4, palette of 2 colours, repeats, 20 bytes\n"),
            "{text}"
        );
        let yaml = dump_yaml(&bytes).unwrap();
        assert!(
            yaml.contains("\ntextures:\n  - 4x4, palette of 2 colours, repeats, 20 bytes  # 0\n"),
            "{yaml}"
        );
        assert_eq!(
            yaml.matches("texture: 0\n").count() as u64,
            info.textured_polygons,
            "{yaml}"
        );
        assert_eq!(
            yaml.matches("uvs: [[").count() as u64,
            info.textured_polygons
        );
    }

    #[test]
    fn fixed_drops_the_sign_of_zero() {
        assert_eq!(fixed(-0.0), "0.000000");
        assert_eq!(fixed(-1e-9), "0.000000");
        assert_eq!(fixed(-0.5), "-0.500000");
    }
}
