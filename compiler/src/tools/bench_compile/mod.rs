//! `peel bench compile`: Peel's build against two baselines, on the shared models and on
//! generated scenes, in one process (so the timings are comparable).
//!
//! For each scene: build time (the tree alone, as the baselines are timed) and whole compile
//! time (reading the OBJ, build, closed-mesh test, shading, encoding), `output polygons /
//! input triangles`, split nodes and depth of Peel's tree, next to a naive BSP and the greedy
//! rule with triangle output (see [`crate::tools::baselines`]). The baselines are quadratic on
//! unfavourable inputs, so they are run only on scenes of at most [`BASELINE_MAX_TRIANGLES`]
//! triangles.

use std::path::Path;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::compile::{compile_mesh, CompileOptions};
use crate::error::CompileError;
use crate::load::{load_obj, Mesh};
use crate::tools::baselines::{greedy_triangles, naive_bsp, BaselineStats};
use crate::tools::median;
use crate::tree::{build, BuildOptions};

/// The shared models looked for in the models directory (absent ones are skipped).
pub const MODELS: [&str; 4] = ["cow", "teapot", "suzanne", "stanford-bunny"];

/// Scenes with more triangles skip the baselines.
pub const BASELINE_MAX_TRIANGLES: usize = 100_000;

/// One baseline's figures on one scene.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BaselineRow {
    /// Output polygons (greedy: triangles).
    pub polygons: u64,
    /// `polygons / triangles`.
    pub ratio: f64,
    /// Nodes on the longest path.
    pub depth: u64,
    /// Split nodes (naive BSP: every node with both sides non-empty counts as one).
    pub split_nodes: u64,
    /// Wall time.
    pub seconds: f64,
}

/// One scene's figures; the JSON keys of `peel bench compile --json` are exactly these fields.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BenchRow {
    /// Scene name.
    pub scene: String,
    /// Input triangles.
    pub triangles: u64,
    /// Peel's output polygons.
    pub polygons: u64,
    /// `polygons / triangles`.
    pub ratio: f64,
    /// Peel's split nodes.
    pub split_nodes: u64,
    /// Peel's depth.
    pub depth: u64,
    /// Peel's build time (wall, median of [`PEEL_RUNS`]): the tree alone, as the baselines are
    /// timed.
    pub seconds: f64,
    /// Peel's whole compile (wall, median of [`PEEL_RUNS`]): reading the OBJ (shared models; generated scenes have no
    /// file), the build, the closed-mesh test, shading and encoding: all `peel compile` does
    /// but write the file.
    pub compile_seconds: f64,
    /// The naive BSP (absent above [`BASELINE_MAX_TRIANGLES`]).
    pub naive_bsp: Option<BaselineRow>,
    /// The greedy rule with triangles (absent above [`BASELINE_MAX_TRIANGLES`]).
    pub greedy_triangles: Option<BaselineRow>,
}

/// Timed runs of Peel per scene (see [`compile_scene_timed`]).
pub const PEEL_RUNS: usize = 3;

fn ratio(polygons: u64, triangles: u64) -> f64 {
    polygons as f64 / triangles.max(1) as f64
}

fn baseline(
    run: impl FnOnce() -> Result<BaselineStats, CompileError>,
) -> Result<BaselineRow, CompileError> {
    let t = Instant::now();
    let s = run()?;
    Ok(BaselineRow {
        polygons: s.output_polygons,
        ratio: ratio(s.output_polygons, s.input_triangles),
        depth: s.max_depth,
        split_nodes: s.split_nodes,
        seconds: t.elapsed().as_secs_f64(),
    })
}

/// Measure one scene with Peel's default options and both baselines; `load_seconds` is the
/// time its OBJ took to read (0 for a generated scene).
pub fn compile_scene_timed(
    name: &str,
    mesh: &Mesh,
    load_seconds: f64,
) -> Result<BenchRow, CompileError> {
    let options = BuildOptions::default();
    // Peel's times are medians of PEEL_RUNS, build and compile alternating (the machine's
    // speed drifts, and the first run of a process warms its allocator).
    let (mut builds, mut compiles) = (Vec::new(), Vec::new());
    let mut stats = None;
    for _ in 0..PEEL_RUNS {
        let t = Instant::now();
        let tree = build(mesh, &options, &|_| {})?;
        builds.push(t.elapsed().as_secs_f64());
        stats = Some(tree.stats);
        let t = Instant::now();
        compile_mesh(mesh, &CompileOptions::default(), &|_| {})?;
        compiles.push(load_seconds + t.elapsed().as_secs_f64());
    }
    let (seconds, compile_seconds) = (median(builds), median(compiles));
    let s = stats.unwrap_or_default();
    let small = mesh.triangles.len() <= BASELINE_MAX_TRIANGLES;
    Ok(BenchRow {
        scene: name.to_string(),
        triangles: s.input_triangles,
        polygons: s.output_polygons,
        ratio: ratio(s.output_polygons, s.input_triangles),
        split_nodes: s.split_nodes,
        depth: s.max_depth,
        seconds,
        compile_seconds,
        naive_bsp: if small {
            Some(baseline(|| naive_bsp(mesh))?)
        } else {
            None
        },
        greedy_triangles: if small {
            Some(baseline(|| {
                greedy_triangles(mesh, options.candidates, options.seed)
            })?)
        } else {
            None
        },
    })
}

/// The generated scenes of the bench.
pub fn generated_scenes() -> Vec<(String, Mesh)> {
    use crate::tools::scenes::{box_grid, soup, sphere, torus};
    vec![
        ("sphere 32x64".into(), sphere(32, 64)),
        ("torus 48x24".into(), torus(48, 24)),
        ("box grid 6^3".into(), box_grid(6)),
        ("soup 2000".into(), soup(2000, 0.1, 1)),
    ]
}

/// The rows as a markdown table.
pub fn markdown(rows: &[BenchRow]) -> String {
    let mut out = String::from(
        "| scene | triangles | peel polygons | peel ratio | peel splits | peel depth | peel s \
         | peel compile s | naive BSP polygons | naive BSP ratio | naive BSP splits | naive BSP depth | naive BSP s \
         | greedy-triangles triangles | greedy-triangles ratio | greedy splits | greedy depth \
         | greedy-triangles s |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let base = |b: &Option<BaselineRow>| match b {
        Some(b) => format!(
            "{} | {:.3} | {} | {} | {:.3}",
            b.polygons, b.ratio, b.split_nodes, b.depth, b.seconds
        ),
        None => "— | — | — | — | —".to_string(),
    };
    for r in rows {
        out.push_str(&super::markdown_row([
            r.scene.clone(),
            r.triangles.to_string(),
            r.polygons.to_string(),
            format!("{:.3}", r.ratio),
            r.split_nodes.to_string(),
            r.depth.to_string(),
            format!("{:.3}", r.seconds),
            format!("{:.3}", r.compile_seconds),
            base(&r.naive_bsp),
            base(&r.greedy_triangles),
        ]));
    }
    out
}

/// The rows of a `peel bench compile --json` file.
pub fn from_json(text: &str) -> Result<Vec<BenchRow>, String> {
    serde_json::from_str(text).map_err(|e| e.to_string())
}

/// Run the bench on the shared models found in `models_dir` (a notice is printed for each
/// one absent) and on the generated scenes; write the rows as JSON to `json` when given;
/// return the markdown table.
pub fn bench_compile(models_dir: &Path, json: Option<&Path>) -> Result<String, CompileError> {
    // The generated scenes run first, though listed last: a build frees its tree on an idle
    // worker, and the bunny's (the largest) would otherwise overlap the next scene's timing.
    let generated = generated_scenes()
        .into_iter()
        .map(|(name, mesh)| compile_scene_timed(&name, &mesh, 0.0))
        .collect::<Result<Vec<_>, _>>()?;
    let mut rows = Vec::new();
    for name in MODELS {
        let path = models_dir.join(format!("{name}.obj"));
        if !path.is_file() {
            println!("skipped: {} not found", path.display());
            continue;
        }
        let t = Instant::now();
        let mesh = load_obj(&path)?;
        let load_seconds = t.elapsed().as_secs_f64();
        rows.push(compile_scene_timed(name, &mesh, load_seconds)?);
    }
    rows.extend(generated);
    if let Some(path) = json {
        let text =
            serde_json::to_string_pretty(&rows).map_err(|e| CompileError::Encode(e.to_string()))?;
        std::fs::write(path, text).map_err(|source| CompileError::Write {
            path: path.to_path_buf(),
            source,
        })?;
    }
    Ok(markdown(&rows))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_row_and_its_table() {
        let row =
            compile_scene_timed("box grid 2^3", &crate::tools::scenes::box_grid(2), 0.0).unwrap();
        assert_eq!(row.triangles, 96);
        // Disjoint boxes are never cut by Peel nor by the greedy rule.
        assert_eq!(row.polygons, 96);
        assert_eq!(row.greedy_triangles.unwrap().polygons, 96);
        assert!(row.naive_bsp.unwrap().polygons >= 96);
        assert!(row.compile_seconds >= 0.0 && row.compile_seconds.is_finite());
        let table = markdown(std::slice::from_ref(&row));
        assert_eq!(table.lines().count(), 3);
        // Header, rule and row have the same number of cells.
        let cells: Vec<usize> = table.lines().map(|l| l.matches('|').count()).collect();
        assert_eq!(cells, vec![cells[0]; 3]);
        assert!(table
            .lines()
            .nth(2)
            .unwrap()
            .starts_with("| box grid 2^3 | 96 | 96 | 1.000 |"));
        // The JSON gives the same rows, so the table can be made again from it.
        let json = serde_json::to_string_pretty(std::slice::from_ref(&row)).unwrap();
        assert_eq!(from_json(&json).unwrap(), std::slice::from_ref(&row));
        assert_eq!(markdown(&from_json(&json).unwrap()), table);
    }

    /// The full bench on the shared models (run with `--ignored --nocapture`, release).
    #[test]
    #[ignore]
    fn shared_models_bench() {
        let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/models");
        println!("{}", bench_compile(&models, None).unwrap());
    }

    #[test]
    fn missing_models_are_skipped_and_json_is_written() {
        let dir = tempfile::tempdir().unwrap();
        let json = dir.path().join("bench.json");
        let table = bench_compile(dir.path(), Some(&json)).unwrap();
        // Only the generated scenes: header, rule and one line each.
        assert_eq!(table.lines().count(), 2 + generated_scenes().len());
        let rows: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        assert_eq!(rows.as_array().unwrap().len(), generated_scenes().len());
    }
}
