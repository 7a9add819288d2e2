//! The greedy baseline with triangle output (fewest cuts, no balance) on one OBJ file, with a
//! chosen number of candidate planes per split: `all` is the exhaustive search (every support
//! plane of the list is costed), a number samples that many, as `peel bench compile` does
//! with 64.
//!
//! `cargo run --release -p peel-compiler --example greedy -- scene.obj [all | K]`

use std::process::ExitCode;

use peel_compiler::load::load_obj;
use peel_compiler::tools::bench_compile::baselines::greedy_triangles;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(path), candidates) = (args.first(), args.get(1).map(String::as_str)) else {
        eprintln!("usage: greedy <scene.obj> [all | K]");
        return ExitCode::FAILURE;
    };
    let candidates = match candidates {
        None => 64,
        Some("all") => usize::MAX,
        Some(k) => match k.parse() {
            Ok(k) => k,
            Err(e) => {
                eprintln!("{k}: not a number of candidates ({e})");
                return ExitCode::FAILURE;
            }
        },
    };
    let stats = load_obj(std::path::Path::new(path))
        .map_err(|e| e.to_string())
        .and_then(|mesh| greedy_triangles(&mesh, candidates, 0).map_err(|e| e.to_string()));
    match stats {
        Ok(s) => {
            let ratio = s.output_polygons as f64 / s.input_triangles as f64;
            println!(
                "{path}: {} triangles -> {} triangles (ratio {ratio:.3}), {} split nodes, depth {}",
                s.input_triangles, s.output_polygons, s.split_nodes, s.max_depth
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}
