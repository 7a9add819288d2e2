//! Reports of the measurements: the JSON records of `peel bench --json` and the markdown
//! table.

use super::{FrameRecord, Method};

/// The JSON of `peel bench --json`: every record of the tables, one per (scene, method), the
/// `SUBPIXEL_BITS` rows (`peel-front-to-back/sub0`, ...) included, so that the tables can be
/// made again from it ([`from_json`], [`markdown_of`]).
pub fn json(records: &[FrameRecord]) -> Result<String, String> {
    serde_json::to_string_pretty(records).map_err(|e| e.to_string())
}

/// The records of a `peel bench --json` file.
pub fn from_json(text: &str) -> Result<Vec<FrameRecord>, String> {
    serde_json::from_str(text).map_err(|e| e.to_string())
}

/// The records as a markdown table, with each method's time relative to the integer z-buffer
/// of the same scene (the baseline measured in the same run).
pub fn markdown(records: &[FrameRecord]) -> String {
    markdown_of(records, records)
}

/// `rows` (some of `records`) as a markdown table, each time relative to the integer z-buffer
/// of its scene in `records`.
pub fn markdown_of<'r>(
    rows: impl IntoIterator<Item = &'r FrameRecord>,
    records: &[FrameRecord],
) -> String {
    let mut s = String::from(
        "| scene | method | median frame (ms) | speed vs zbuffer-int | memory (bytes) | polygons drawn | pixels written | robust errors | all errors |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        // (A transparent scene's baseline is the sorted z-buffer.)
        let base = records
            .iter()
            .find(|b| b.scene == r.scene && b.method == Method::ZbufferInt.name())
            .or_else(|| (records.iter()).find(|b| b.scene == r.scene && b.method == super::SORTED))
            .map(|b| b.median_frame_ms)
            .unwrap_or(f64::NAN);
        s += &crate::tools::markdown_row([
            r.scene.clone(),
            r.method.clone(),
            format!("{:.3}", r.median_frame_ms),
            format!("{:.2}x", base / r.median_frame_ms),
            r.memory_bytes.to_string(),
            if r.polygons_drawn > 0 {
                r.polygons_drawn.to_string()
            } else {
                "-".into()
            },
            r.pixels_written.to_string(),
            r.robust_errors.to_string(),
            r.all_errors.to_string(),
        ]);
    }
    s
}
