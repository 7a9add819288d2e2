//! The result records and their two files: `results.json` and the same records as a markdown
//! table, `results.md`.

use serde::Serialize;

/// One scene x method x core x size x display path. The JSON keys are exactly these fields.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
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
    /// runs (a `fill_solid` or `fill_contiguous` is one of each, as mipidsi sends them).
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
}

/// The records as pretty JSON.
pub fn json(records: &[Record]) -> Result<String, String> {
    serde_json::to_string_pretty(records).map_err(|e| e.to_string())
}

/// `n` with thin thousands separators (`1 234 567`), for the table.
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

/// The records as a markdown table, same columns and order as the JSON.
pub fn markdown(records: &[Record]) -> String {
    let mut s = String::from(
        "| scene | method | path | core | width | height | triangles | instructions | ram_bytes | \
         framebuffer_bytes | flash_bytes | display_bytes | display_writes | differing_pixels | robust_errors | \
         deterministic |\n\
         |---|---|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|---|\n",
    );
    for r in records {
        s.push_str(&peel_compiler::tools::markdown_row([
            r.scene.clone(),
            r.method.clone(),
            r.path.clone(),
            r.core.clone(),
            r.width.to_string(),
            r.height.to_string(),
            grouped(r.triangles),
            grouped(r.instructions),
            grouped(r.ram_bytes),
            grouped(r.framebuffer_bytes),
            grouped(r.flash_bytes),
            grouped(r.display_bytes),
            grouped(r.display_writes),
            r.differing_pixels
                .map_or_else(|| "-".to_string(), |d| d.to_string()),
            r.robust_errors
                .map_or_else(|| "-".to_string(), |d| d.to_string()),
            (if r.deterministic { "yes" } else { "no" }).to_string(),
        ]));
    }
    s
}

/// Goals for the anti-aliased streamed frame of the teapot on the Cortex-M4F at 320x240: RAM
/// (bytes), instructions against the streamed frame's, display bytes against a full frame's
/// pixels (153,600), `.text` growth against the streamed build's (bytes).
pub const AA_GOALS: (u64, f64, f64, i64) = (49_152, 1.8, 1.4, 3_000);

/// Whether `r` is Peel's streamed frame of the scene, core and size of `aa`.
fn stream_of(r: &Record, aa: &Record) -> bool {
    r.method == "peel-front-to-back"
        && r.path == "stream"
        && (r.scene.as_str(), r.core.as_str(), r.width, r.height)
            == (aa.scene.as_str(), aa.core.as_str(), aa.width, aa.height)
}

/// The anti-aliased frames (`stream-aa`), each under Peel's streamed frame of the same scene,
/// core and size: instructions and their ratio to the streamed frame's, RAM, display bytes and
/// writes, `.text` against the streamed build's, pending records and differing pixels; then
/// the goals for the teapot on the Cortex-M4F at 320x240 when it was measured. Empty without
/// anti-aliased records.
pub fn antialiased(records: &[Record]) -> String {
    let aa: Vec<&Record> = records
        .iter()
        .filter(|r| r.method == "peel-front-to-back-aa")
        .collect();
    if aa.is_empty() {
        return String::new();
    }
    let mut s = String::from(
        "\n## Anti-aliased frames (stream-aa, scan-aa)\n\n\
         | scene | core | size | path | instructions | x stream | ram_bytes | display_bytes | \
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
    let goal = aa.iter().find(|r| {
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

/// The README's table of Peel and the alternatives: for each of `scenes` at 320x240, each
/// plotted method ([`crate::plot::METHODS`]) on each core, its instructions, RAM, flash and
/// robust errors.
pub fn alternatives(records: &[Record], scenes: &[&str]) -> String {
    let mut s = String::from(
        "| scene | core | method | path | instructions | RAM (bytes) | flash (bytes) | \
         robust errors |\n|---|---|---|---|--:|--:|--:|--:|\n",
    );
    for scene in scenes {
        for core in ["cortex-m4f", "cortex-m0plus"] {
            let mut rows: Vec<(usize, &Record)> = records
                .iter()
                .filter(|r| r.core == core)
                .filter_map(|r| Some((crate::plot::plotted(r, scene)?, r)))
                .collect();
            rows.sort_by_key(|(k, _)| *k);
            for (_, r) in rows {
                s.push_str(&peel_compiler::tools::markdown_row([
                    r.scene.clone(),
                    r.core.clone(),
                    r.method.clone(),
                    r.path.clone(),
                    grouped(r.instructions),
                    grouped(r.ram_bytes),
                    grouped(r.flash_bytes),
                    r.robust_errors.map_or_else(|| "-".to_string(), grouped),
                ]));
            }
        }
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
    }

    #[test]
    fn alternatives_table() {
        let mut gfx = record();
        (gfx.method, gfx.path, gfx.differing_pixels) =
            ("embedded-3dgfx".into(), "framebuffer".into(), None);
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
        assert!(lines[3].contains("| embedded-3dgfx | framebuffer | 1 683 160 |"));
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
    fn table_rows() {
        let md = markdown(&[record()]);
        let lines: Vec<&str> = md.lines().collect();
        assert_eq!(lines.len(), 3);
        assert_eq!(
            lines[2],
            "| demo | peel-front-to-back | framebuffer | cortex-m4f | 320 | 240 | 38 | 1 683 160 | \
             172 000 | 153 600 | 63 302 | 153 611 | 2 | 0 | 3 | yes |"
        );
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1000), "1 000");
    }
}
