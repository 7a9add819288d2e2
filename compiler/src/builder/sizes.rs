//! The sizes file: a small Rust file beside the `.peel` file with the constants firmware sizes
//! its buffers from (the traversal stack, the clip buffers, vertex and span memory), read from
//! the file's header, and `const fn` checks that make a buffer too small for the scene fail to
//! compile.

use std::fmt::Write as _;

use peel_runtime::clip;
use peel_runtime::composite::RUN_BYTES;
use peel_runtime::fill::MAX_FILL_VERTICES;
use peel_runtime::read::layout::{header_flags, PARTS_VERSION};
use peel_runtime::read::Header;
use peel_runtime::scan::SCAN_NODE_BYTES;
use peel_runtime::vertices::CachedVertex;

/// Span-memory intervals per image row the sizes file recommends for front-to-back rendering:
/// the host renderer's figure (`tools::raster::HOST_SPANS_PER_ROW`), capped by what can never
/// run out (see [`sizes_file`]). Running out is not an error: the rest of the frame is painted
/// back to front, with overdraw, and the same pixels.
pub const RECOMMENDED_SPANS_PER_ROW: usize = 64;

/// The span memory measured for an image size ([`super::spans::spans_per_row`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeasuredSpans {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The fewest intervals per row with which no frame of the orbit runs out.
    pub per_row: usize,
    /// The scan memory nodes with which no scan-order frame of the orbit runs out
    /// ([`super::spans::scan_nodes`]).
    pub scan_nodes: usize,
    /// The same for anti-aliased scan-order frames
    /// ([`super::spans::scan_nodes_antialiased`]).
    pub scan_nodes_antialiased: usize,
    /// The pending-pixel records with which no anti-aliased frame of the orbit has a row fall
    /// back to plain pixels ([`super::spans::pending_pixels`]).
    pub pending_pixels: usize,
    /// The composite-memory records with which no front-to-back frame of the orbit has a row
    /// fall back to screen-door transparency ([`super::spans::composite_runs`]; 0 for an
    /// opaque scene).
    pub composite_runs: usize,
}

impl MeasuredSpans {
    /// The largest of each figure of `self` and `other` (measured at the same size): memory
    /// with which no frame of either runs out.
    pub fn max(self, other: MeasuredSpans) -> MeasuredSpans {
        MeasuredSpans {
            per_row: self.per_row.max(other.per_row),
            scan_nodes: self.scan_nodes.max(other.scan_nodes),
            scan_nodes_antialiased: self
                .scan_nodes_antialiased
                .max(other.scan_nodes_antialiased),
            pending_pixels: self.pending_pixels.max(other.pending_pixels),
            composite_runs: self.composite_runs.max(other.composite_runs),
            ..self
        }
    }
}

/// The header the sizes file of a file of parts is written from: the first part's (the
/// world's) with the version [`PARTS_VERSION`] and the largest of each count over the parts,
/// so that memory sized from it draws every part. One header (a plain scene's) is itself.
pub fn largest(headers: &[Header]) -> Header {
    let [first, rest @ ..] = headers else {
        return Header::default();
    };
    if rest.is_empty() {
        return *first;
    }
    let max = |field: fn(&Header) -> u32| headers.iter().map(field).max().unwrap_or(0);
    Header {
        version: PARTS_VERSION,
        vertex_count: max(|h| h.vertex_count),
        plane_count: max(|h| h.plane_count),
        index_count: max(|h| h.index_count),
        polygon_count: max(|h| h.polygon_count),
        node_count: max(|h| h.node_count),
        max_depth: max(|h| h.max_depth),
        max_polygon_vertices: max(|h| h.max_polygon_vertices),
        palette_count: max(|h| h.palette_count),
        bounds_count: max(|h| h.bounds_count),
        ..*first
    }
}

/// Scan memory nodes the sizes file gives without a measurement (32 KiB).
pub const RECOMMENDED_SCAN_NODES: usize = 4096;

/// Scan memory nodes the sizes file gives anti-aliased scan-order frames without a
/// measurement (48 KiB: anti-aliased, the scenes measured need 25-66% more than plain).
pub const RECOMMENDED_SCAN_NODES_AA: usize = 6144;

/// Pending-pixel records the sizes file gives without a measurement (24 KiB).
pub const RECOMMENDED_PENDING_PIXELS: usize = 2048;

/// Composite-memory records the sizes file gives a scene with transparent surfaces without a
/// measurement (12 KiB).
pub const RECOMMENDED_COMPOSITE_RUNS: usize = 1024;

/// The memory a frame of a scene needs, as its sizes file gives it: the figures firmware sizes
/// its buffers from (`peel inspect` prints them). Each field is the sizes file's constant of
/// the same name in capitals.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct FrameMemory {
    /// Traversal stack entries (the tree's depth): the `STACK` of `Workspace<STACK, VERTS>`.
    pub stack: usize,
    /// Clip-buffer vertices (the largest polygon plus one per clip plane): the `VERTS` of
    /// `Workspace<STACK, VERTS>`.
    pub verts: usize,
    /// Vertex memory entries that keep every vertex (the vertex count rounded up to a power of
    /// two).
    pub vertex_memory: usize,
    /// Span-memory intervals per row for front-to-back frames.
    pub spans_per_row: usize,
    /// Scan memory nodes for frames in scan order.
    pub scan_nodes: usize,
    /// Scan memory nodes for anti-aliased frames in scan order.
    pub scan_nodes_aa: usize,
    /// Pending-pixel records for anti-aliased frames.
    pub pending_pixels: usize,
    /// Composite-memory records for front-to-back frames with transparent surfaces (0 for an
    /// opaque scene, whose JSON leaves it out).
    #[serde(skip_serializing_if = "is_zero")]
    pub composite_runs: usize,
    /// The image size the last four were measured at (`SPANS_MEASURED_AT`); `None` where they
    /// are the sizes file's defaults.
    pub measured_at: Option<(u32, u32)>,
}

impl FrameMemory {
    /// The figures of the scene with header `header`, the span and scan memory measured if
    /// `spans`, else the defaults.
    pub fn of(header: &Header, spans: Option<MeasuredSpans>) -> FrameMemory {
        let defaults = FrameMemory {
            stack: header.max_depth as usize,
            verts: clip::buffer_len_for(header.max_polygon_vertices) as usize,
            // The vertex memory is direct-mapped over a power of two of entries.
            vertex_memory: (header.vertex_count as usize).next_power_of_two(),
            spans_per_row: RECOMMENDED_SPANS_PER_ROW,
            scan_nodes: RECOMMENDED_SCAN_NODES,
            scan_nodes_aa: RECOMMENDED_SCAN_NODES_AA,
            pending_pixels: RECOMMENDED_PENDING_PIXELS,
            composite_runs: if header.flags & header_flags::TRANSPARENT != 0 {
                RECOMMENDED_COMPOSITE_RUNS
            } else {
                0
            },
            measured_at: None,
        };
        match spans {
            None => defaults,
            Some(m) => FrameMemory {
                spans_per_row: m.per_row,
                scan_nodes: m.scan_nodes,
                scan_nodes_aa: m.scan_nodes_antialiased,
                pending_pixels: m.pending_pixels,
                composite_runs: m.composite_runs,
                measured_at: Some((m.width, m.height)),
                ..defaults
            },
        }
    }

    /// The largest of each figure of `self` and `other`: memory that draws either scene (the
    /// parts of a file of parts share one workspace). The measured size is kept where both
    /// were measured at it.
    pub fn max(self, other: FrameMemory) -> FrameMemory {
        FrameMemory {
            stack: self.stack.max(other.stack),
            verts: self.verts.max(other.verts),
            vertex_memory: self.vertex_memory.max(other.vertex_memory),
            spans_per_row: self.spans_per_row.max(other.spans_per_row),
            scan_nodes: self.scan_nodes.max(other.scan_nodes),
            scan_nodes_aa: self.scan_nodes_aa.max(other.scan_nodes_aa),
            pending_pixels: self.pending_pixels.max(other.pending_pixels),
            composite_runs: self.composite_runs.max(other.composite_runs),
            measured_at: self
                .measured_at
                .filter(|_| self.measured_at == other.measured_at),
        }
    }

    /// The figures of the scene `bytes`, the span and scan memory measured at
    /// `width x height` as [`crate::Builder::image_size`] measures them (an orbit of frames
    /// each: far slower than reading the header).
    ///
    /// # Errors
    /// A message for a scene that does not parse or a measurement that fails
    /// ([`super::spans::measure`]).
    pub fn measured(bytes: &[u8], width: u32, height: u32) -> Result<FrameMemory, String> {
        let scene = peel_runtime::read::Scene::parse(bytes).map_err(|e| e.to_string())?;
        let spans = super::spans::measure(bytes, width, height)?;
        Ok(FrameMemory::of(&scene.header(), Some(spans)))
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// World planes a posed object may be cut by in a frame that the `VERTS` of a file of parts
/// has room for: each may add two vertices to a polygon (`peel_runtime::place`). A frame
/// that needs more is refused with `RenderError::PolygonTooLarge`.
pub const OBJECT_PLANES: usize = 8;

/// Steps of a frame's order per object that the `OBJECT_STEPS` of a file of parts allows
/// (a piece of an object and the world's subtrees and hulls around it; cuts and pieces take
/// as many entries as steps).
pub const STEPS_PER_OBJECT: usize = 48;

/// The text of the sizes file of `header` (a `.peel` file of `bytes` bytes named `peel_name`,
/// compiled from `source`), with the span memory measured for an image size if `spans`.
/// For a file of parts with `objects` objects (0 for a plain scene): `VERTS` with room for
/// [`OBJECT_PLANES`] cuts, and the object memory (`OBJECTS`, `OBJECT_STEPS`).
pub fn sizes_file(
    header: &Header,
    bytes: usize,
    peel_name: &str,
    source: &str,
    spans: Option<MeasuredSpans>,
    objects: usize,
) -> String {
    // The names go into comments and string literals.
    let peel_name = &peel_name.escape_default().to_string();
    let source = &source.escape_default().to_string();
    let memory = FrameMemory::of(header, spans);
    let (stack, mut verts, vertex_memory) = (memory.stack, memory.verts, memory.vertex_memory);
    if objects > 0 {
        verts = (verts + 2 * OBJECT_PLANES).min(MAX_FILL_VERTICES);
    }
    let vertices = header.vertex_count as usize;
    let entry = std::mem::size_of::<CachedVertex>();
    let mut s = String::new();
    let mut line = |text: &str| {
        s.push_str(text);
        s.push('\n');
    };
    line(&format!(
        "// The sizes of `{peel_name}`, compiled from `{source}` by peel-compiler {}.",
        env!("CARGO_PKG_VERSION")
    ));
    line("// Generated by `peel_compiler::Builder` (do not edit). Include it in a module of its own:");
    line(&format!(
        "//     mod scene {{ include!(concat!(env!(\"OUT_DIR\"), \"/{}\")); }}",
        sizes_name(peel_name)
    ));
    line("// then size the frame's memory from it, e.g. `Workspace<{ scene::STACK }, { scene::VERTS }>`,");
    line("// or check memory sized otherwise at compile time: `const _: () = scene::check_workspace(64, 24);`.");
    let mut item = |doc: &str, decl: String| item_into(&mut line, doc, "dead_code", &decl);
    item(
        "Format version of the file.",
        format!("pub const FORMAT_VERSION: u16 = {};", header.version),
    );
    item(
        "Size of the file in bytes.",
        format!("pub const BYTES: usize = {bytes};"),
    );
    item(
        "Vertices (shared between polygons).",
        format!("pub const VERTICES: usize = {vertices};"),
    );
    item(
        "Polygons.",
        format!("pub const POLYGONS: usize = {};", header.polygon_count),
    );
    item(
        "Nodes of the display tree.",
        format!("pub const NODES: usize = {};", header.node_count),
    );
    item(
        "Nodes on the tree's longest root-to-leaf path (the header's `max_depth`).",
        format!("pub const MAX_DEPTH: usize = {};", header.max_depth),
    );
    item(
        "Traversal stack entries a frame needs: `MAX_DEPTH`. The `STACK` of\n\
         `Workspace<STACK, VERTS>`.",
        format!("pub const STACK: usize = {stack};"),
    );
    item(
        "Vertices of the largest polygon (the header's `max_polygon_vertices`).",
        format!(
            "pub const MAX_POLYGON_VERTICES: usize = {};",
            header.max_polygon_vertices
        ),
    );
    item(
        &format!(
            "Clip-buffer vertices a frame needs: the largest polygon plus one per clip plane\n\
             (`clip::buffer_len_for(MAX_POLYGON_VERTICES)`, {} planes). The `VERTS` of\n\
             `Workspace<STACK, VERTS>`.",
            clip::CLIP_PLANES
        ),
        format!("pub const VERTS: usize = {verts};"),
    );
    if objects > 0 {
        item(
            "Objects of the file of parts: the `OBJECTS` of `place::ObjectMemory<OBJECTS, STEPS>`.",
            format!("pub const OBJECTS: usize = {objects};"),
        );
        item(
            &format!(
                "Steps of a frame's order: an allowance of {STEPS_PER_OBJECT} per object, plus as many for the\n\
                 world (poses are the firmware's, so nothing can be measured here; a frame that\n\
                 needs more is refused with `RenderError::ObjectMemory`). The `STEPS` of\n\
                 `place::ObjectMemory<OBJECTS, STEPS>`."
            ),
            format!(
                "pub const OBJECT_STEPS: usize = {};",
                STEPS_PER_OBJECT * (objects + 1)
            ),
        );
    }
    // Values of a scene can look like mathematical constants to clippy.
    let float = "dead_code, clippy::approx_constant, clippy::excessive_precision";
    item_into(
        &mut line,
        "World position the file's coordinates are relative to.",
        float,
        &format!("pub const CENTRE: [f64; 3] = {};", floats(&header.centre)),
    );
    item_into(
        &mut line,
        "Scene bounds, relative to `CENTRE`.",
        float,
        &format!(
            "pub const BOUNDS_MIN: [f32; 3] = {};",
            floats(&header.bounds_min.to_array())
        ),
    );
    item_into(
        &mut line,
        "Scene bounds, relative to `CENTRE`.",
        float,
        &format!(
            "pub const BOUNDS_MAX: [f32; 3] = {};",
            floats(&header.bounds_max.to_array())
        ),
    );
    let mut item = |doc: &str, decl: String| item_into(&mut line, doc, "dead_code", &decl);
    item(
        &format!(
            "Vertex memory entries (`vertices::CachedVertex`, {entry} bytes each: {} bytes): one\n\
             per vertex, rounded up to a power of two, keeps every vertex (fewer keep those used\n\
             close together).",
            vertex_memory * entry
        ),
        format!("pub const VERTEX_MEMORY: usize = {vertex_memory};"),
    );
    match spans {
        None => item(
            "Span-memory intervals per row recommended for front-to-back rendering (the host's\n\
             figure; `Builder::image_size` measures what the scene needs). Running out is not an\n\
             error: the rest of the frame is painted back to front, with overdraw and the same\n\
             pixels.",
            format!("pub const SPANS_PER_ROW: usize = {};", memory.spans_per_row),
        ),
        Some(MeasuredSpans {
            width,
            height,
            per_row,
            ..
        }) => {
            item(
                &format!(
                    "Span-memory intervals per row this scene needs at {width}x{height}: the fewest\n\
                     with which no frame of an orbit around it ({} cameras at elevations {:?}\n\
                     degrees, the CLI's distance and field of view) runs out. A frame that runs\n\
                     out is finished back to front: the same pixels, with overdraw (flicker on a\n\
                     streamed panel) and more display writes.",
                    super::spans::ORBIT_CAMERAS as usize * super::spans::ORBIT_ELEVATIONS.len(),
                    super::spans::ORBIT_ELEVATIONS
                ),
                format!("pub const SPANS_PER_ROW: usize = {per_row};"),
            );
            item(
                "The image size `SPANS_PER_ROW` was measured at.",
                format!("pub const SPANS_MEASURED_AT: (u32, u32) = ({width}, {height});"),
            );
        }
    }
    match spans {
        None => item(
            &format!(
                "Scan memory nodes (`scan::ScanNode`, {SCAN_NODE_BYTES} bytes each) for frames in scan\n\
                 order (`Renderer::draw_scan`): a guess (`Builder::image_size` measures what the\n\
                 scene needs). Running out is an error (`RenderError::ScanMemoryFull`): nothing is\n\
                 sent."
            ),
            format!("pub const SCAN_NODES: usize = {};", memory.scan_nodes),
        ),
        Some(MeasuredSpans {
            width,
            height,
            scan_nodes,
            ..
        }) => item(
            &format!(
                "Scan memory nodes (`scan::ScanNode`, {SCAN_NODE_BYTES} bytes each: {} bytes) this scene needs\n\
                 at {width}x{height} for frames in scan order (`Renderer::draw_scan`): the most\n\
                 any frame of the orbit of `SPANS_PER_ROW` holds. Running out is an error\n\
                 (`RenderError::ScanMemoryFull`): nothing is sent.",
                scan_nodes * SCAN_NODE_BYTES
            ),
            format!("pub const SCAN_NODES: usize = {scan_nodes};"),
        ),
    }
    match spans {
        None => item(
            "Scan memory nodes for anti-aliased frames in scan order (`Renderer::draw_scan` with\n\
             `Renderer::antialias`): a guess (`Builder::image_size` measures what the scene\n\
             needs). A frame that runs out is drawn without anti-aliasing (with at least\n\
             `SCAN_NODES`; with fewer, `RenderError::ScanMemoryFull`).",
            format!("pub const SCAN_NODES_AA: usize = {};", memory.scan_nodes_aa),
        ),
        Some(MeasuredSpans {
            width,
            height,
            scan_nodes_antialiased,
            ..
        }) => item(
            &format!(
                "Scan memory nodes ({SCAN_NODE_BYTES} bytes each: {} bytes) this scene needs at {width}x{height}\n\
                 for anti-aliased frames in scan order (`Renderer::draw_scan` with\n\
                 `Renderer::antialias`): the most any frame of the orbit of `SPANS_PER_ROW`\n\
                 holds. A frame that runs out is drawn without anti-aliasing (with at least\n\
                 `SCAN_NODES`; with fewer, `RenderError::ScanMemoryFull`).",
                scan_nodes_antialiased * SCAN_NODE_BYTES
            ),
            format!("pub const SCAN_NODES_AA: usize = {scan_nodes_antialiased};"),
        ),
    }
    match spans {
        None => item(
            "Pending-pixel records (`pending::PendingPixel`, 12 bytes each) for anti-aliased\n\
             frames (`Renderer::antialias`): a guess (`Builder::image_size` measures what the\n\
             scene needs). Running out draws a row's remaining edge pixels without anti-aliasing.",
            format!(
                "pub const PENDING_PIXELS: usize = {};",
                memory.pending_pixels
            ),
        ),
        Some(MeasuredSpans {
            width,
            height,
            pending_pixels,
            ..
        }) => item(
            &format!(
                "Pending-pixel records (`pending::PendingPixel`, 12 bytes each: {} bytes) this\n\
                 scene needs at {width}x{height} for anti-aliased frames (`Renderer::antialias`):\n\
                 the most any frame of the orbit of `SPANS_PER_ROW` keeps pending. Running out\n\
                 draws a row's remaining edge pixels without anti-aliasing.",
                pending_pixels * 12
            ),
            format!("pub const PENDING_PIXELS: usize = {pending_pixels};"),
        ),
    }
    // Only a scene with transparent surfaces needs composite memory.
    if header.flags & header_flags::TRANSPARENT != 0 {
        let runs = memory.composite_runs;
        let doc = match spans {
            None => format!(
                "Composite-memory records (`composite::CompositeRun`, {RUN_BYTES} bytes each: {}\n\
                 bytes) for front-to-back frames of this scene's transparent surfaces\n\
                 (`Renderer::composite_memory`, with a `u16` head per row): a guess\n\
                 (`Builder::image_size` measures what the scene needs). A row that runs out is\n\
                 drawn with screen-door transparency (`FrameStats::fallback_rows`).",
                runs * RUN_BYTES
            ),
            Some(MeasuredSpans { width, height, .. }) => format!(
                "Composite-memory records (`composite::CompositeRun`, {RUN_BYTES} bytes each: {}\n\
                 bytes) this scene needs at {width}x{height} for front-to-back frames of its\n\
                 transparent surfaces (`Renderer::composite_memory`, with a `u16` head per row):\n\
                 the most any frame of the orbit of `SPANS_PER_ROW` holds. A row that runs out\n\
                 is drawn with screen-door transparency (`FrameStats::fallback_rows`).",
                runs * RUN_BYTES
            ),
        };
        item(&doc, format!("pub const COMPOSITE_RUNS: usize = {runs};"));
    }
    item(
        &format!(
            "Bytes of caller memory an anti-aliased frame in scan order takes at `height` rows\n\
             (`Renderer::draw_scan` with `Renderer::antialias`): `SCAN_NODES_AA` scan memory\n\
             nodes ({SCAN_NODE_BYTES} bytes each) and `PENDING_PIXELS` pending-pixel records (12\n\
             bytes each), and a list head (2 bytes) per row for each."
        ),
        format!(
            "pub const fn scan_antialiased_bytes(height: u32) -> usize {{\n    \
             SCAN_NODES_AA * {SCAN_NODE_BYTES} + PENDING_PIXELS * 12 + 4 * height as usize\n\
             }}"
        ),
    );
    item(
        "Intervals per row that can never run out at `width`: each polygon covers one span of\n\
         a row, and a row holds at most `(width + 1) / 2` disjoint intervals.",
        "pub const fn spans_per_row_bound(width: u32) -> usize {\n    \
             let half = (width as usize).div_ceil(2);\n    \
             if POLYGONS < half { POLYGONS } else { half }\n\
         }"
        .to_string(),
    );
    item(
        "Span memory for a `width x height` frame: the intervals (`SPANS_PER_ROW` per row, or\n\
         fewer where `spans_per_row_bound` is smaller); `Coverage::new` also takes `height`\n\
         row counters.",
        "pub const fn span_memory(width: u32, height: u32) -> usize {\n    \
             let bound = spans_per_row_bound(width);\n    \
             let per_row = if SPANS_PER_ROW < bound { SPANS_PER_ROW } else { bound };\n    \
             per_row * height as usize\n\
         }"
        .to_string(),
    );
    item(
        "Whether a `Workspace<stack, verts>` holds this scene's frames.",
        "pub const fn workspace_fits(stack: usize, verts: usize) -> bool {\n    \
             stack >= STACK && verts >= VERTS\n\
         }"
        .to_string(),
    );
    item(
        "Fails to compile when used in a constant with a `Workspace<stack, verts>` too small for\n\
         this scene: `const _: () = scene::check_workspace(64, 24);`.",
        format!(
            "pub const fn check_workspace(stack: usize, verts: usize) {{\n    \
                 assert!(stack >= STACK, \"the Workspace's STACK is smaller than {peel_name}'s depth, STACK = {stack}\");\n    \
                 assert!(verts >= VERTS, \"the Workspace's VERTS is smaller than {peel_name}'s clip buffers, VERTS = {verts}\");\n\
             }}"
        ),
    );
    item(
        "Fails to compile when used in a constant with vertex memory too small for this scene:\n\
         `const _: () = scene::check_vertex_memory(1024);` (smaller memory works, but projects\n\
         some vertices once per polygon).",
        format!(
            "pub const fn check_vertex_memory(entries: usize) {{\n    \
                 assert!(entries >= VERTEX_MEMORY, \"the vertex memory cannot keep every vertex of {peel_name}, VERTEX_MEMORY = {vertex_memory}\");\n\
             }}"
        ),
    );
    line("");
    let _ = writeln!(
        s,
        "// The runtime fills polygons of at most {MAX_FILL_VERTICES} vertices, clip vertices included."
    );
    let _ = writeln!(
        s,
        "const _: () = assert!(VERTS <= {MAX_FILL_VERTICES}, \"{peel_name} has polygons too large for the runtime's fill: compile it with a smaller max_polygon_vertices\");"
    );
    s
}

/// One documented item: its doc lines, `#[allow(allow)]` and the declaration.
fn item_into(line: &mut impl FnMut(&str), doc: &str, allow: &str, decl: &str) {
    line("");
    for d in doc.lines() {
        line(&format!("/// {d}"));
    }
    line(&format!("#[allow({allow})]"));
    line(decl);
}

/// The sizes file's name for a `.peel` file named `peel_name`: its stem + `.rs`.
pub fn sizes_name(peel_name: &str) -> String {
    let stem = std::path::Path::new(peel_name).file_stem().map_or_else(
        || peel_name.to_string(),
        |s| s.to_string_lossy().into_owned(),
    );
    format!("{stem}.rs")
}

/// `[a, b, c]` with each value in the shortest form that reads back exactly.
fn floats<T: std::fmt::Debug>(v: &[T; 3]) -> String {
    format!("[{:?}, {:?}, {:?}]", v[0], v[1], v[2])
}
