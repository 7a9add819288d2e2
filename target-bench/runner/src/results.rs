//! The result records and their two files: `results.json` and the same records as a markdown
//! table, `results.md`.

use serde::Serialize;

/// One scene x method x core x size (x display path: records of one method differ by
/// `framebuffer_bytes`). The JSON keys are exactly these fields.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Record {
    /// Scene name (`(generated)` when a generated mesh stood in for a missing model).
    pub scene: String,
    /// `peel-front-to-back`, `peel-back-to-front` or `zbuffer-int`.
    pub method: String,
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
    /// Pixels differing from the host's, summed over the cameras.
    pub differing_pixels: u64,
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
        "| scene | method | core | width | height | triangles | instructions | ram_bytes | \
         framebuffer_bytes | flash_bytes | display_bytes | differing_pixels | deterministic |\n\
         |---|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|---|\n",
    );
    for r in records {
        s.push_str(&peel_compiler::tools::markdown_row([
            r.scene.clone(),
            r.method.clone(),
            r.core.clone(),
            r.width.to_string(),
            r.height.to_string(),
            grouped(r.triangles),
            grouped(r.instructions),
            grouped(r.ram_bytes),
            grouped(r.framebuffer_bytes),
            grouped(r.flash_bytes),
            grouped(r.display_bytes),
            r.differing_pixels.to_string(),
            (if r.deterministic { "yes" } else { "no" }).to_string(),
        ]));
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
            core: "cortex-m4f".into(),
            width: 320,
            height: 240,
            triangles: 38,
            instructions: 1_683_160,
            ram_bytes: 172_000,
            framebuffer_bytes: 153_600,
            flash_bytes: 63_302,
            display_bytes: 153_611,
            differing_pixels: 0,
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
                "core",
                "width",
                "height",
                "triangles",
                "instructions",
                "ram_bytes",
                "framebuffer_bytes",
                "flash_bytes",
                "display_bytes",
                "differing_pixels",
                "deterministic"
            ]
        );
    }

    #[test]
    fn table_rows() {
        let md = markdown(&[record()]);
        let lines: Vec<&str> = md.lines().collect();
        assert_eq!(lines.len(), 3);
        assert_eq!(
            lines[2],
            "| demo | peel-front-to-back | cortex-m4f | 320 | 240 | 38 | 1 683 160 | 172 000 | \
             153 600 | 63 302 | 153 611 | 0 | yes |"
        );
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1000), "1 000");
    }
}
