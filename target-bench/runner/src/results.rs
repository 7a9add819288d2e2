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
    pub robust_errors: u64,
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
            r.robust_errors.to_string(),
            (if r.deterministic { "yes" } else { "no" }).to_string(),
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
                    grouped(r.robust_errors),
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
            display_bytes: 153_611,
            display_writes: 2,
            differing_pixels: Some(0),
            robust_errors: 3,
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
                "display_bytes",
                "display_writes",
                "differing_pixels",
                "robust_errors",
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
