//! The `--candidates` knob: how the number of candidate split planes costed per node trades
//! compile time against output size and frame time.

use std::time::Instant;

use super::measure::{measure_scene, prepare_scene, Variant, Work};
use super::{ring_cameras, Method};
use crate::compile::{compile_mesh, CompileOptions};
use crate::load::Mesh;

/// The `--candidates` knob on one mesh: compile time, output polygons and median
/// front-to-back frame time for each `K`, as a markdown table.
pub fn candidates_knob(
    name: &str,
    mesh: &Mesh,
    ks: &[usize],
    width: u32,
    height: u32,
    cameras: usize,
) -> Result<String, String> {
    let mut s = String::from(
        "| scene | candidates | compile (s) | output polygons | polygons / triangles | median frame (ms) |\n|---|---:|---:|---:|---:|---:|\n",
    );
    let cams = ring_cameras(mesh, cameras);
    for &k in ks {
        let mut options = CompileOptions::default();
        options.build.candidates = k;
        let start = Instant::now();
        let (tree, _) = compile_mesh(mesh, &options, &|_| {}).map_err(|e| e.to_string())?;
        let seconds = start.elapsed().as_secs_f64();
        let p = prepare_scene(mesh, None, &cams, width, height, &options)?;
        let mut work = Work::new(height);
        let front_to_back = Variant::new(Method::PeelFrontToBack);
        let r = measure_scene(name, &[front_to_back], &p, &mut work)?
            .pop()
            .ok_or("no frame")?;
        s += &format!(
            "| {name} | {k} | {seconds:.3} | {} | {:.3} | {:.3} |\n",
            tree.stats.output_polygons,
            tree.stats.output_polygons as f64 / mesh.triangles.len().max(1) as f64,
            r.median_frame_ms
        );
    }
    Ok(s)
}
