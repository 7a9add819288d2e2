//! The result records and what is made of them: `results.json`, the same records as a
//! markdown table (`results.md`), the anti-aliased frames' table and the README's table of the
//! alternatives. The docs' figures render these tables from the committed copy of
//! `results.json` (`results/target.json`) with the same functions.

use serde::{Deserialize, Serialize};

/// One scene x method x display path x shading x core x size ([`Record::identity`]). The JSON
/// keys are exactly these fields.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Record {
    /// Scene name (`(generated)` when a generated mesh stood in for a missing model).
    pub scene: String,
    /// `peel-front-to-back`, `peel-back-to-front`, `zbuffer-int`, `tiled-zbuffer`,
    /// `scanline-zbuffer` or `embedded-3dgfx`.
    pub method: String,
    /// How the frame reaches the display: `framebuffer` (one full-frame buffer, sent once),
    /// `stream` (each span sent as drawn, no pixel memory) or `bands-N` (a buffer of N rows,
    /// sent when drawn; the scanline z-buffer's is one row).
    pub path: String,
    /// `flat` (each polygon one colour: Peel's faceted or unlit files, the peers' per-face
    /// lighting) or `smooth` (colours interpolated across polygons: Peel's smooth files,
    /// embedded-3dgfx's Gouraud mode). Part of a record's identity: flat and smooth records of
    /// one scene, method, path, core and size stand side by side. Records written before it
    /// existed read as `flat`.
    #[serde(default = "flat")]
    pub shading: String,
    /// `cortex-m4f` or `cortex-m0plus`.
    pub core: String,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Source triangles of the scene.
    pub triangles: u64,
    /// Median instructions per frame over the camera path.
    pub instructions: u64,
    /// RAM a frame needs: statics, the stack's high-water mark, pixel, span and depth memory.
    pub ram_bytes: u64,
    /// The part of `ram_bytes` that holds pixels (0 when streaming).
    pub framebuffer_bytes: u64,
    /// Code, read-only data, initialised data and the scene.
    pub flash_bytes: u64,
    /// The firmware's `.text` (part of `flash_bytes`).
    pub text_bytes: u64,
    /// Median bytes a frame sends to the display.
    pub display_bytes: u64,
    /// Median separate writes a frame makes to the display driver: window set-ups and pixel
    /// runs (a buffer sent as one block, or a `fill_solid`, is one of each; rows sent one at a
    /// time into one window are one set-up and a run per row).
    pub display_writes: u64,
    /// Pixels differing from the host's run of the same code, summed over the cameras; `None`
    /// for a method whose code does not run on the host (embedded-3dgfx).
    pub differing_pixels: Option<u64>,
    /// Robust pixels (farther than 1/16 pixel from every projected edge) whose triangle is not
    /// the exact ray-casting reference's, summed over the cameras; for embedded-3dgfx, which
    /// draws no ids, robust pixels covered where the reference sees nothing or the reverse.
    /// `None` (not applicable) for anti-aliased frames, whose pixels are blends of triangles.
    pub robust_errors: Option<u64>,
    /// Anti-aliased frames: the most pending-pixel records a frame held at once, over the
    /// cameras (`None` for others).
    pub pending_peak: Option<u64>,
    /// Anti-aliased frames: the records the firmware has (the builder's `PENDING_PIXELS`).
    pub pending_records: Option<u64>,
    /// Anti-aliased frames: a row of some frame ran out of records and fell back to plain
    /// pixels, or a frame was not anti-aliased at all (either fails the run).
    pub pending_fallback: Option<bool>,
    /// Two runs gave the same instruction count for every frame (and the same pixels).
    pub deterministic: bool,
    /// Objects posed each frame (a file of parts, `peel_runtime::place`); 0, and absent from
    /// the JSON, for a plain scene (so records written before it read the same).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub objects: u64,
    /// A scene with transparent surfaces (`"transparent": true`, composited in exact order);
    /// `false`, and absent from the JSON, for an opaque one, such as the transparent scene's
    /// opaque baseline. Part of a record's identity: the two stand side by side.
    #[serde(default, skip_serializing_if = "is_false")]
    pub transparent: bool,
    /// Transparency (the build with composite memory): rows that fell back to screen-door
    /// transparency for want of composite runs, summed over the cameras (`None`, and absent,
    /// for other builds).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fallback_rows: Option<u64>,
    /// Transparency: the most composite runs a frame held at once, over the cameras.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub composite_peak: Option<u64>,
    /// Transparency: the composite runs the firmware has (12 bytes each; see
    /// `target-bench/runner/src/transparent.rs` for how they are sized).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub composite_runs: Option<u64>,
}

/// Whether `b` is false (a record's `transparent` is then left out of the JSON).
fn is_false(b: &bool) -> bool {
    !*b
}

/// Whether `n` is 0 (a record's `objects` is then left out of the JSON).
fn is_zero(n: &u64) -> bool {
    *n == 0
}

/// The shading of a record without one (written before smooth records existed).
fn flat() -> String {
    FLAT.into()
}

/// [`Record::shading`] of flat records.
pub const FLAT: &str = "flat";
/// [`Record::shading`] of smooth records.
pub const SMOOTH: &str = "smooth";
/// [`Record::shading`] of textured records.
pub const TEXTURED: &str = "textured";

impl Record {
    /// What tells a record apart from every other of a run: scene, method, path, shading,
    /// core, size and transparency (the key results are compared and looked up by).
    #[allow(clippy::type_complexity)]
    pub fn identity(&self) -> (&str, &str, &str, &str, &str, u32, u32, bool) {
        (
            &self.scene,
            &self.method,
            &self.path,
            &self.shading,
            &self.core,
            self.width,
            self.height,
            self.transparent,
        )
    }

    /// Whether the record is of flat shading.
    pub fn is_flat(&self) -> bool {
        self.shading == FLAT
    }
}

/// The records as pretty JSON.
pub fn json(records: &[Record]) -> Result<String, String> {
    serde_json::to_string_pretty(records).map_err(|e| e.to_string())
}

/// `n` with thin thousands separators (`1 234 567`), for the tables.
fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// A column of the records' tables: the record's JSON key, whether it is right-aligned, and
/// its cell.
#[derive(Debug)]
pub struct Column {
    /// The JSON key, also the header of `results.md`.
    pub key: &'static str,
    /// Right-aligned (a figure).
    pub figure: bool,
    /// The cell of a record.
    pub cell: fn(&Record) -> String,
}

/// `-` for a figure that does not apply.
fn or_dash(v: Option<u64>) -> String {
    v.map_or_else(|| "-".to_string(), grouped)
}

/// A column of words.
const fn words(key: &'static str, cell: fn(&Record) -> String) -> Column {
    Column {
        key,
        figure: false,
        cell,
    }
}

/// A column of figures.
const fn figures(key: &'static str, cell: fn(&Record) -> String) -> Column {
    Column {
        key,
        figure: true,
        cell,
    }
}

/// Every field of [`Record`] as a column, in the JSON's order.
pub const COLUMNS: [Column; 26] = [
    words("scene", |r| r.scene.clone()),
    words("method", |r| r.method.clone()),
    words("path", |r| r.path.clone()),
    words("shading", |r| r.shading.clone()),
    words("core", |r| r.core.clone()),
    figures("width", |r| r.width.to_string()),
    figures("height", |r| r.height.to_string()),
    figures("triangles", |r| grouped(r.triangles)),
    figures("instructions", |r| grouped(r.instructions)),
    figures("ram_bytes", |r| grouped(r.ram_bytes)),
    figures("framebuffer_bytes", |r| grouped(r.framebuffer_bytes)),
    figures("flash_bytes", |r| grouped(r.flash_bytes)),
    figures("text_bytes", |r| grouped(r.text_bytes)),
    figures("display_bytes", |r| grouped(r.display_bytes)),
    figures("display_writes", |r| grouped(r.display_writes)),
    figures("differing_pixels", |r| or_dash(r.differing_pixels)),
    figures("robust_errors", |r| or_dash(r.robust_errors)),
    figures("pending_peak", |r| or_dash(r.pending_peak)),
    figures("pending_records", |r| or_dash(r.pending_records)),
    words("pending_fallback", |r| {
        r.pending_fallback.map_or("-", yes_no).to_string()
    }),
    words("deterministic", |r| yes_no(r.deterministic).to_string()),
    figures("objects", |r| r.objects.to_string()),
    words("transparent", |r| yes_no(r.transparent).to_string()),
    figures("fallback_rows", |r| or_dash(r.fallback_rows)),
    figures("composite_peak", |r| or_dash(r.composite_peak)),
    figures("composite_runs", |r| or_dash(r.composite_runs)),
];

fn yes_no(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

/// The column of JSON key `key`.
pub fn column(key: &str) -> Option<&'static Column> {
    COLUMNS.iter().find(|c| c.key == key)
}

/// The columns of `results.md` (the anti-aliased frames' own figures are in their table).
pub const RESULTS_MD: [&str; 16] = [
    "scene",
    "method",
    "path",
    "core",
    "width",
    "height",
    "triangles",
    "instructions",
    "ram_bytes",
    "framebuffer_bytes",
    "flash_bytes",
    "display_bytes",
    "display_writes",
    "differing_pixels",
    "robust_errors",
    "deterministic",
];

/// A markdown table of `records`, one row each in their order, with these headers and columns.
pub fn table<'r>(
    records: impl IntoIterator<Item = &'r Record>,
    columns: &[(&str, &Column)],
) -> String {
    let mut s = peel_compiler::tools::markdown_row(columns.iter().map(|(header, _)| header));
    s.push('|');
    for (_, c) in columns {
        s.push_str(if c.figure { "--:|" } else { "---|" });
    }
    s.push('\n');
    for r in records {
        s.push_str(&peel_compiler::tools::markdown_row(
            columns.iter().map(|(_, c)| (c.cell)(r)),
        ));
    }
    s
}

/// The columns of these JSON keys, each headed by its key; an unknown key is an error naming
/// it and the keys there are.
pub fn columns_of<'k>(keys: &[&'k str]) -> Result<Vec<(&'k str, &'static Column)>, String> {
    keys.iter()
        .map(|&k| {
            column(k).map(|c| (k, c)).ok_or_else(|| {
                let known: Vec<&str> = COLUMNS.iter().map(|c| c.key).collect();
                format!("no column {k:?} (the records' keys: {})", known.join(", "))
            })
        })
        .collect()
}

/// The records as a markdown table (`results.md`): the columns of [`RESULTS_MD`] and the
/// shading after the path, in the JSON's order. (The docs' default table keeps
/// [`RESULTS_MD`]: their committed records predate the shading.)
pub fn markdown(records: &[Record]) -> String {
    let columns: Vec<(&str, &Column)> = COLUMNS
        .iter()
        .filter(|c| c.key == "shading" || RESULTS_MD.contains(&c.key))
        .map(|c| (c.key, c))
        .collect();
    table(records, &columns)
}

/// Goals for the anti-aliased streamed frame of the teapot on the Cortex-M4F at 320x240: RAM
/// (bytes), instructions against the streamed frame's, display bytes against a full frame's
/// pixels (153,600), `.text` growth against the streamed build's (bytes).
pub const AA_GOALS: (u64, f64, f64, i64) = (49_152, 1.8, 1.4, 3_000);

/// Whether `r` is Peel's streamed frame of the scene, shading, core and size of `aa`.
fn stream_of(r: &Record, aa: &Record) -> bool {
    r.method == "peel-front-to-back"
        && r.path == "stream"
        && r.shading == aa.shading
        && (r.scene.as_str(), r.core.as_str(), r.width, r.height)
            == (aa.scene.as_str(), aa.core.as_str(), aa.width, aa.height)
}

/// The anti-aliased frames' section of `results.md`: a heading, [`antialiased_table`] and
/// [`antialiased_goals`]. Empty without anti-aliased records.
pub fn antialiased(records: &[Record]) -> String {
    let table = antialiased_table(records);
    if table.is_empty() {
        return table;
    }
    format!(
        "\n## Anti-aliased frames (stream-aa, scan-aa)\n\n{table}{}",
        antialiased_goals(records)
    )
}

/// The anti-aliased records (`stream-aa`).
fn antialiased_records(records: &[Record]) -> Vec<&Record> {
    records
        .iter()
        .filter(|r| r.method == "peel-front-to-back-aa")
        .collect()
}

/// The anti-aliased frames (`stream-aa`), each under Peel's streamed frame of the same scene,
/// core and size: instructions and their ratio to the streamed frame's, RAM, display bytes and
/// writes, `.text` against the streamed build's, pending records and differing pixels. Empty
/// without anti-aliased records.
pub fn antialiased_table(records: &[Record]) -> String {
    let aa = antialiased_records(records);
    if aa.is_empty() {
        return String::new();
    }
    let mut s = String::from(
        "| scene | core | size | path | instructions | x stream | ram_bytes | display_bytes | \
         display_writes | .text delta | pending peak / records | fallback | differing_pixels |\n\
         |---|---|---|---|--:|--:|--:|--:|--:|--:|--:|---|--:|\n",
    );
    let dash = || "-".to_string();
    for a in &aa {
        let stream = records.iter().find(|r| stream_of(r, a));
        let ratio = |r: &Record| {
            stream.map_or_else(dash, |s| {
                format!(
                    "{:.2}x",
                    r.instructions as f64 / s.instructions.max(1) as f64
                )
            })
        };
        let row = |r: &Record, path: &str, text: String, pending: String, fallback: String| {
            peel_compiler::tools::markdown_row([
                r.scene.clone(),
                r.core.clone(),
                format!("{}x{}", r.width, r.height),
                path.to_string(),
                grouped(r.instructions),
                ratio(r),
                grouped(r.ram_bytes),
                grouped(r.display_bytes),
                grouped(r.display_writes),
                text,
                pending,
                fallback,
                r.differing_pixels.map_or_else(dash, |d| d.to_string()),
            ])
        };
        if let Some(st) = stream {
            s.push_str(&row(st, "stream", dash(), dash(), dash()));
        }
        let text = stream.map_or_else(dash, |st| {
            format!("{:+}", a.text_bytes as i64 - st.text_bytes as i64)
        });
        let pending = match (a.pending_peak, a.pending_records) {
            (Some(p), Some(n)) => format!("{} / {}", grouped(p), grouped(n)),
            _ => dash(),
        };
        let fallback = match a.pending_fallback {
            Some(true) => "YES".to_string(),
            Some(false) => "no".to_string(),
            None => dash(),
        };
        let path = if a.path == "scan-order" {
            "scan-aa"
        } else {
            "stream-aa"
        };
        s.push_str(&row(a, path, text, pending, fallback));
    }
    s
}

/// The goals for the teapot's anti-aliased frame on the Cortex-M4F at 320x240 ([`AA_GOALS`])
/// and whether each is met; empty when that frame was not measured.
pub fn antialiased_goals(records: &[Record]) -> String {
    let dash = || "-".to_string();
    let mut s = String::new();
    let goal = antialiased_records(records).into_iter().find(|r| {
        r.scene.starts_with("teapot") && r.core == "cortex-m4f" && (r.width, r.height) == (320, 240)
    });
    if let Some(a) = goal {
        let (ram, ratio, display, text) = AA_GOALS;
        let stream = records.iter().find(|r| stream_of(r, a));
        let yes = |ok: bool| (if ok { "yes" } else { "NO" }).to_string();
        s.push_str(&format!(
            "\nGoals ({}, cortex-m4f, 320x240):\n\n| goal | measured | limit | met |\n|---|--:|--:|---|\n",
            a.scene
        ));
        s.push_str(&peel_compiler::tools::markdown_row([
            "ram_bytes".into(),
            grouped(a.ram_bytes),
            grouped(ram),
            yes(a.ram_bytes <= ram),
        ]));
        let fallback = a.pending_fallback.unwrap_or(true);
        s.push_str(&peel_compiler::tools::markdown_row([
            "no row falling back".into(),
            (if fallback { "a row fell back" } else { "none" }).into(),
            "none".into(),
            yes(!fallback),
        ]));
        if let Some(st) = stream {
            let x = a.instructions as f64 / st.instructions.max(1) as f64;
            s.push_str(&peel_compiler::tools::markdown_row([
                "instructions / streamed frame's".into(),
                format!("{x:.2}x"),
                format!("{ratio:.1}x"),
                yes(x <= ratio),
            ]));
        }
        let full = 153_600.0;
        let x = a.display_bytes as f64 / full;
        s.push_str(&peel_compiler::tools::markdown_row([
            "display_bytes / 153,600".into(),
            format!("{x:.3}x ({})", grouped(a.display_bytes)),
            format!("{display:.1}x ({})", grouped((display * full) as u64)),
            yes(x <= display),
        ]));
        if let Some(st) = stream {
            let d = a.text_bytes as i64 - st.text_bytes as i64;
            s.push_str(&peel_compiler::tools::markdown_row([
                ".text growth (bytes)".into(),
                format!("{d:+}"),
                format!("{text}"),
                yes(d <= text),
            ]));
        }
        s.push_str(&peel_compiler::tools::markdown_row([
            "differing pixels".into(),
            a.differing_pixels.map_or_else(dash, |d| d.to_string()),
            "0".into(),
            yes(a.differing_pixels == Some(0)),
        ]));
    }
    s
}

/// Goals for smooth frames against their flat twins: instructions of the streamed frame (at
/// most this multiple of the flat one's), RAM of the streamed frame and RAM of the scan-order
/// frame on the Cortex-M4F (bytes).
pub const SMOOTH_GOALS: (f64, u64, u64) = (1.3, 32_768, 49_152);

/// The flat record of `smooth`'s scene, method, path, core and size.
fn flat_twin<'r>(records: &'r [Record], smooth: &Record) -> Option<&'r Record> {
    records.iter().find(|r| {
        r.is_flat() && {
            let (a, b) = (r.identity(), smooth.identity());
            (a.0, a.1, a.2, a.4, a.5, a.6, a.7) == (b.0, b.1, b.2, b.4, b.5, b.6, b.7)
        }
    })
}

/// The smooth frames' section of `results.md`: each smooth record beside its flat twin (the
/// same scene, method, path, core and size), their instructions and RAM and the ratios, and
/// whether each meets [`SMOOTH_GOALS`] where one applies. Empty without smooth records.
pub fn smooth(records: &[Record]) -> String {
    let smooth: Vec<&Record> = records.iter().filter(|r| r.shading == SMOOTH).collect();
    if smooth.is_empty() {
        return String::new();
    }
    let (ratio_goal, stream_ram, scan_ram) = SMOOTH_GOALS;
    let mut s = String::from(
        "\n## Smooth frames against flat\n\n\
         | scene | method | path | core | size | instructions | flat | x flat | ram_bytes | flat | \
         display_bytes | display_writes | differing_pixels | goals |\n\
         |---|---|---|---|---|--:|--:|--:|--:|--:|--:|--:|--:|---|\n",
    );
    let dash = || "-".to_string();
    for r in smooth {
        let flat = flat_twin(records, r);
        let x = flat.map(|f| r.instructions as f64 / f.instructions.max(1) as f64);
        let peel = r.method == "peel-front-to-back";
        let mut goals = Vec::new();
        if peel && r.path == "stream" {
            if let Some(x) = x {
                goals.push(format!(
                    "x flat <= {ratio_goal}: {}",
                    if x <= ratio_goal { "yes" } else { "NO" }
                ));
            }
            goals.push(format!(
                "RAM <= {}: {}",
                grouped(stream_ram),
                if r.ram_bytes <= stream_ram {
                    "yes"
                } else {
                    "NO"
                }
            ));
        }
        if peel && r.path == "scan-order" && r.core == "cortex-m4f" {
            goals.push(format!(
                "RAM <= {}: {}",
                grouped(scan_ram),
                if r.ram_bytes <= scan_ram { "yes" } else { "NO" }
            ));
        }
        s.push_str(&peel_compiler::tools::markdown_row([
            r.scene.clone(),
            r.method.clone(),
            r.path.clone(),
            r.core.clone(),
            format!("{}x{}", r.width, r.height),
            grouped(r.instructions),
            flat.map_or_else(dash, |f| grouped(f.instructions)),
            x.map_or_else(dash, |x| format!("{x:.2}x")),
            grouped(r.ram_bytes),
            flat.map_or_else(dash, |f| grouped(f.ram_bytes)),
            grouped(r.display_bytes),
            grouped(r.display_writes),
            or_dash(r.differing_pixels),
            if goals.is_empty() {
                dash()
            } else {
                goals.join("; ")
            },
        ]));
    }
    s
}

/// Goals for textured frames against their untextured twins (issue 47): Peel's streamed frame
/// at most this multiple of the untextured frame's instructions on the Cortex-M4F and on the
/// Cortex-M0+, in at most this RAM (bytes).
pub const TEXTURE_GOALS: (f64, f64, u64) = (1.5, 2.0, 32_768);

/// The textured frames' section of `results.md`: each textured record beside its untextured
/// twin (the `flat` record of the same scene, method, path, core and size), their instructions,
/// RAM and flash and the ratios, and whether Peel's streamed frames meet [`TEXTURE_GOALS`].
/// Empty without textured records.
pub fn textured(records: &[Record]) -> String {
    let textured: Vec<&Record> = records.iter().filter(|r| r.shading == TEXTURED).collect();
    if textured.is_empty() {
        return String::new();
    }
    let (m4f, m0plus, ram) = TEXTURE_GOALS;
    let mut s = String::from(
        "\n## Textured frames against untextured\n\n\
         | scene | method | path | core | size | instructions | untextured | x untextured | \
         ram_bytes | untextured | flash_bytes | untextured | differing_pixels | goals |\n\
         |---|---|---|---|---|--:|--:|--:|--:|--:|--:|--:|--:|---|\n",
    );
    let dash = || "-".to_string();
    let yes = |ok: bool| if ok { "yes" } else { "NO" };
    for r in textured {
        let flat = flat_twin(records, r);
        let x = flat.map(|f| r.instructions as f64 / f.instructions.max(1) as f64);
        let mut goals = Vec::new();
        if r.method == "peel-front-to-back" && r.path == "stream" {
            let limit = if r.core == "cortex-m4f" { m4f } else { m0plus };
            if let Some(x) = x {
                goals.push(format!("x untextured <= {limit}: {}", yes(x <= limit)));
            }
            goals.push(format!(
                "RAM <= {}: {}",
                grouped(ram),
                yes(r.ram_bytes <= ram)
            ));
        }
        s.push_str(&peel_compiler::tools::markdown_row([
            r.scene.clone(),
            r.method.clone(),
            r.path.clone(),
            r.core.clone(),
            format!("{}x{}", r.width, r.height),
            grouped(r.instructions),
            flat.map_or_else(dash, |f| grouped(f.instructions)),
            x.map_or_else(dash, |x| format!("{x:.2}x")),
            grouped(r.ram_bytes),
            flat.map_or_else(dash, |f| grouped(f.ram_bytes)),
            grouped(r.flash_bytes),
            flat.map_or_else(dash, |f| grouped(f.flash_bytes)),
            or_dash(r.differing_pixels),
            if goals.is_empty() {
                dash()
            } else {
                goals.join("; ")
            },
        ]));
    }
    s
}

/// Goals for the transparent scene (the glass box around the teapot) streamed at 320x240 on
/// both cores: instructions at most this multiple of the opaque box's, in at most this RAM
/// (bytes), with no row falling back.
pub const TRANSPARENCY_GOALS: (f64, u64) = (1.5, 40_960);

/// The scenes of the README's table of Peel and the alternatives that `records` has: the
/// teapot and the cow, or the generated meshes that stood in for them.
pub fn alternatives_scenes(records: &[Record]) -> Vec<&'static str> {
    ["teapot", "cow", "teapot (generated)", "cow (generated)"]
        .into_iter()
        .filter(|s| records.iter().any(|r| r.scene == *s))
        .collect()
}

/// The README's table of Peel and the alternatives: for each of `scenes` at 320x240, each
/// plotted method ([`crate::plot::METHODS`]) on each core, its instructions, RAM, flash and
/// robust errors, then its instructions and RAM as multiples of Peel's streamed frame of the
/// same scene and core (the first plotted method), so that the text needs to quote no ratio.
pub fn alternatives(records: &[Record], scenes: &[&str]) -> String {
    let mut rows: Vec<(&Record, Option<&Record>)> = Vec::new();
    for scene in scenes {
        for core in ["cortex-m4f", "cortex-m0plus"] {
            let mut mine: Vec<(usize, &Record)> = records
                .iter()
                .filter(|r| r.core == core)
                .filter_map(|r| Some((crate::plot::plotted(r, scene)?, r)))
                .collect();
            mine.sort_by_key(|(k, _)| *k);
            let peel = mine.first().filter(|(k, _)| *k == 0).map(|(_, r)| *r);
            rows.extend(mine.into_iter().map(|(_, r)| (r, peel)));
        }
    }
    let columns: Vec<(&str, &Column)> = [
        ("scene", "scene"),
        ("core", "core"),
        ("method", "method"),
        ("path", "path"),
        ("instructions", "instructions"),
        ("RAM (bytes)", "ram_bytes"),
        ("flash (bytes)", "flash_bytes"),
        ("robust errors", "robust_errors"),
    ]
    .into_iter()
    .filter_map(|(header, key)| Some((header, column(key)?)))
    .collect();
    let headers = columns
        .iter()
        .map(|(h, _)| *h)
        .chain(["x Peel's instructions", "x Peel's RAM"]);
    let mut s = peel_compiler::tools::markdown_row(headers);
    s.push('|');
    for (_, c) in &columns {
        s.push_str(if c.figure { "--:|" } else { "---|" });
    }
    s.push_str("--:|--:|\n");
    let times = |a: u64, b: Option<u64>| match b {
        Some(b) if b > 0 => format!("{:.2}", a as f64 / b as f64),
        _ => "-".to_string(),
    };
    for (r, peel) in rows {
        let cells = columns.iter().map(|(_, c)| (c.cell)(r)).chain([
            times(r.instructions, peel.map(|p| p.instructions)),
            times(r.ram_bytes, peel.map(|p| p.ram_bytes)),
        ]);
        s.push_str(&peel_compiler::tools::markdown_row(cells));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record() -> Record {
        Record {
            scene: "demo".into(),
            method: "peel-front-to-back".into(),
            path: "framebuffer".into(),
            shading: "flat".into(),
            core: "cortex-m4f".into(),
            width: 320,
            height: 240,
            triangles: 38,
            instructions: 1_683_160,
            ram_bytes: 172_000,
            framebuffer_bytes: 153_600,
            flash_bytes: 63_302,
            text_bytes: 40_000,
            display_bytes: 153_611,
            display_writes: 2,
            differing_pixels: Some(0),
            robust_errors: Some(3),
            pending_peak: None,
            pending_records: None,
            pending_fallback: None,
            deterministic: true,
            objects: 0,
            transparent: false,
            fallback_rows: None,
            composite_peak: None,
            composite_runs: None,
        }
    }

    #[test]
    fn json_keys_are_the_fields_in_order() {
        let j = json(&[record()]).unwrap();
        let keys: Vec<&str> = j
            .lines()
            .filter_map(|l| l.trim().strip_prefix('"')?.split('"').next())
            .collect();
        assert_eq!(
            keys,
            [
                "scene",
                "method",
                "path",
                "shading",
                "core",
                "width",
                "height",
                "triangles",
                "instructions",
                "ram_bytes",
                "framebuffer_bytes",
                "flash_bytes",
                "text_bytes",
                "display_bytes",
                "display_writes",
                "differing_pixels",
                "robust_errors",
                "pending_peak",
                "pending_records",
                "pending_fallback",
                "deterministic"
            ]
        );
        // A table's columns are named by the same keys, and `objects`, which only records of
        // a scene with objects hold.
        assert_eq!(
            COLUMNS[..21].iter().map(|c| c.key).collect::<Vec<_>>(),
            keys
        );
        assert_eq!(COLUMNS[21].key, "objects");
        assert_eq!(
            COLUMNS[22..].iter().map(|c| c.key).collect::<Vec<_>>(),
            [
                "transparent",
                "fallback_rows",
                "composite_peak",
                "composite_runs"
            ]
        );
        let glass = Record {
            transparent: true,
            fallback_rows: Some(0),
            composite_peak: Some(310),
            composite_runs: Some(320),
            ..record()
        };
        let j = json(std::slice::from_ref(&glass)).unwrap();
        assert!(
            j.contains(
                "\"deterministic\": true,\n    \"transparent\": true,\n    \"fallback_rows\": 0,\n    \
                 \"composite_peak\": 310,\n    \"composite_runs\": 320\n"
            ),
            "{j}"
        );
        let back: Vec<Record> = serde_json::from_str(&j).unwrap();
        assert_eq!(back, std::slice::from_ref(&glass));
        // The transparent record and its opaque baseline are told apart.
        assert_ne!(glass.identity(), record().identity());
        let posed = Record {
            objects: 2,
            ..record()
        };
        let j = json(std::slice::from_ref(&posed)).unwrap();
        assert!(
            j.contains("\"deterministic\": true,\n    \"objects\": 2\n"),
            "{j}"
        );
        let back: Vec<Record> = serde_json::from_str(&j).unwrap();
        assert_eq!(back, [posed]);
        let back: Vec<Record> = serde_json::from_str(&json(&[record()]).unwrap()).unwrap();
        assert_eq!(back[0].objects, 0);
        let picked = table(&[record()], &columns_of(&["method", "ram_bytes"]).unwrap());
        assert_eq!(
            picked,
            "| method | ram_bytes |\n|---|--:|\n| peel-front-to-back | 172 000 |\n"
        );
        let e = columns_of(&["ram"]).unwrap_err();
        assert!(
            e.starts_with("no column \"ram\" (the records' keys: scene, method,"),
            "{e}"
        );
    }

    #[test]
    fn alternatives_table() {
        let mut gfx = record();
        (gfx.method, gfx.path, gfx.differing_pixels) =
            ("embedded-3dgfx".into(), "framebuffer".into(), None);
        (gfx.instructions, gfx.ram_bytes) = (2 * gfx.instructions, gfx.ram_bytes / 4);
        let mut stream = record();
        stream.path = "stream".into();
        let mut small = record();
        (small.width, small.height) = (160, 120);
        let md = alternatives(&[gfx.clone(), record(), stream, small], &["demo"]);
        let lines: Vec<&str> = md.lines().collect();
        // Peel's streamed frame first, then the peers; the framebuffer path and other sizes
        // are not in it.
        assert_eq!(lines.len(), 4, "{md}");
        assert!(lines[2].contains("| peel-front-to-back | stream |"));
        assert!(lines[3].contains("| embedded-3dgfx | framebuffer | 3 366 320 |"));
        // Each row's instructions and RAM against Peel's streamed frame on its core.
        assert!(lines[2].ends_with("| 1.00 | 1.00 |"), "{md}");
        assert!(lines[3].ends_with("| 2.00 | 0.25 |"), "{md}");
        assert!(markdown(&[gfx]).contains("| - | 3 | yes |"));
    }

    #[test]
    fn antialiased_table_and_goals() {
        assert_eq!(antialiased(&[record()]), "");
        let (mut stream, mut aa) = (record(), record());
        (stream.scene, stream.path, stream.ram_bytes) = ("teapot".into(), "stream".into(), 24_000);
        (aa.scene, aa.method, aa.path) = (
            "teapot".into(),
            "peel-front-to-back-aa".into(),
            "stream".into(),
        );
        (aa.instructions, aa.ram_bytes, aa.display_bytes) = (2_000_000, 45_000, 230_000);
        (aa.text_bytes, aa.robust_errors) = (42_500, None);
        (aa.pending_peak, aa.pending_records, aa.pending_fallback) =
            (Some(1_700), Some(1_714), Some(false));
        let md = antialiased(&[stream, aa.clone()]);
        assert!(
            md.contains("| stream | 1 683 160 | 1.00x | 24 000 |"),
            "{md}"
        );
        assert!(
            md.contains("| stream-aa | 2 000 000 | 1.19x | 45 000 | 230 000 | 2 | +2500 | 1 700 / 1 714 | no | 0 |"),
            "{md}"
        );
        assert!(md.contains("| ram_bytes | 45 000 | 49 152 | yes |"), "{md}");
        assert!(
            md.contains("| no row falling back | none | none | yes |"),
            "{md}"
        );
        assert!(
            md.contains("| 1.497x (230 000) | 1.4x (215 040) | NO |"),
            "{md}"
        );
        assert!(
            md.contains("| .text growth (bytes) | +2500 | 3000 | yes |"),
            "{md}"
        );
        assert!(markdown(&[aa]).contains("| 0 | - | yes |"));
    }

    #[test]
    fn records_without_a_shading_read_as_flat() {
        let j = json(&[record()])
            .unwrap()
            .replace("\"shading\": \"flat\",", "");
        assert!(!j.contains("shading"));
        let back: Vec<Record> = serde_json::from_str(&j).unwrap();
        assert_eq!(back, [record()]);
        assert!(back[0].is_flat());
    }

    #[test]
    fn textured_records_stand_beside_their_untextured_twins() {
        let mut textured_stream = record();
        (textured_stream.path, textured_stream.shading) = ("stream".into(), TEXTURED.into());
        (textured_stream.instructions, textured_stream.ram_bytes) = (1_400_000, 30_000);
        let mut flat_stream = textured_stream.clone();
        (flat_stream.shading, flat_stream.instructions) = (FLAT.into(), 1_000_000);
        let mut m0 = textured_stream.clone();
        (m0.core, m0.instructions, m0.ram_bytes) = ("cortex-m0plus".into(), 2_100_000, 40_000);
        let mut m0_flat = flat_stream.clone();
        m0_flat.core = "cortex-m0plus".into();
        let mut smooth_stream = flat_stream.clone();
        smooth_stream.shading = SMOOTH.into();
        let records = [flat_stream, textured_stream, m0_flat, m0, smooth_stream];
        let md = textured(&records);
        let lines: Vec<&str> = md.lines().filter(|l| l.starts_with("| demo")).collect();
        assert_eq!(lines.len(), 2, "{md}");
        assert!(
            lines[0].contains("| cortex-m4f | 320x240 | 1 400 000 | 1 000 000 | 1.40x | 30 000 |"),
            "{md}"
        );
        assert!(
            lines[0].ends_with("| x untextured <= 1.5: yes; RAM <= 32 768: yes |"),
            "{md}"
        );
        assert!(
            lines[1].ends_with("| x untextured <= 2: NO; RAM <= 32 768: NO |"),
            "{md}"
        );
        // Neither the smooth section nor this one shows the other's records.
        assert!(!smooth(&records).contains("textured"));
        assert_eq!(
            smooth(&records)
                .lines()
                .filter(|l| l.starts_with("| demo"))
                .count(),
            1
        );
        assert!(textured(&records[..1]).is_empty());
    }

    #[test]
    fn flat_and_smooth_records_are_told_apart() {
        let mut smooth_stream = record();
        (smooth_stream.path, smooth_stream.shading) = ("stream".into(), SMOOTH.into());
        (smooth_stream.instructions, smooth_stream.ram_bytes) = (2_000_000, 30_000);
        let mut flat_stream = smooth_stream.clone();
        (flat_stream.shading, flat_stream.instructions) = (FLAT.into(), 1_600_000);
        assert_ne!(smooth_stream.identity(), flat_stream.identity());
        let mut scan = smooth_stream.clone();
        (scan.path, scan.ram_bytes) = ("scan-order".into(), 50_000);
        let records = [record(), flat_stream.clone(), smooth_stream.clone(), scan];
        assert_eq!(flat_twin(&records, &smooth_stream), Some(&flat_stream));
        let md = smooth(&records);
        let lines: Vec<&str> = md.lines().filter(|l| l.starts_with("| demo")).collect();
        assert_eq!(lines.len(), 2, "{md}");
        assert!(
            lines[0].contains(
                "| stream | cortex-m4f | 320x240 | 2 000 000 | 1 600 000 | 1.25x | 30 000 | 30 000 |"
            ),
            "{md}"
        );
        assert!(
            lines[0].ends_with("| x flat <= 1.3: yes; RAM <= 32 768: yes |"),
            "{md}"
        );
        // No flat scan-order twin: no ratio; over the scan-order RAM goal.
        assert!(
            lines[1].contains("| 2 000 000 | - | - | 50 000 | - |"),
            "{md}"
        );
        assert!(lines[1].ends_with("| RAM <= 49 152: NO |"), "{md}");
        assert_eq!(smooth(&[record()]), "");
        // The anti-aliased table and the alternatives compare flat records only.
        let mut aa = smooth_stream.clone();
        aa.method = "peel-front-to-back-aa".into();
        aa.shading = FLAT.into();
        assert!(stream_of(&flat_stream, &aa) && !stream_of(&smooth_stream, &aa));
    }

    #[test]
    fn table_rows() {
        let md = markdown(&[record()]);
        let lines: Vec<&str> = md.lines().collect();
        assert_eq!(lines.len(), 3);
        assert_eq!(
            lines[2],
            "| demo | peel-front-to-back | framebuffer | flat | cortex-m4f | 320 | 240 | 38 | \
             1 683 160 | 172 000 | 153 600 | 63 302 | 153 611 | 2 | 0 | 3 | yes |"
        );
        // The docs' default columns are without the shading.
        assert!(!RESULTS_MD.contains(&"shading"));
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1000), "1 000");
    }
}
