//! `peel`: compile OBJ scenes into `.peel` display trees, inspect, dump and render them.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use clap::{Args, Parser, Subcommand};
use glam::DVec3;
use indicatif::{ProgressBar, ProgressStyle};

use peel_compiler::compile::{compile_obj, compile_parts, CompileOptions, Compiled};
use peel_compiler::load::{LoadOptions, DEFAULT_MAX_TEXTURE};
use peel_compiler::shade::normals::Crease;
use peel_compiler::shade::{Shading, Surface, DEFAULT_LIGHT, DEFAULT_SURFACE};
use peel_compiler::tree::BuildOptions;

mod cli;

#[derive(Parser)]
#[command(
    name = "peel",
    version,
    about = "Exact display-tree compiler and renderer for triangle meshes"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Compile an OBJ scene into a .peel display tree.
    Compile(CompileArgs),
    /// Print what a .peel file holds, and the memory a frame of it needs (the sizes file's
    /// figures).
    Inspect {
        /// The .peel file.
        file: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
        /// Measure the span and scan memory at this image size WxH over an orbit of the
        /// scene, as `Builder::image_size` does (without it: the defaults).
        #[arg(long, value_parser = cli::parse_size, value_name = "WxH")]
        size: Option<(u32, u32)>,
    },
    /// Print the whole tree as YAML.
    Dump {
        /// The .peel file.
        file: PathBuf,
    },
    /// Render a .peel file to a PNG.
    Render(cli::RenderArgs),
    /// Benchmarks: frame time against pixel error for Peel and baselines (default), or the
    /// compiler against its baselines (`peel bench compile`).
    Bench(cli::BenchArgs),
    /// Compile and render the built-in demo scene.
    Demo {
        /// Where to write demo.obj, demo.peel and demo.png.
        #[arg(long, default_value = "peel-demo", value_name = "DIR")]
        out: PathBuf,
    },
}

#[derive(Args)]
struct CompileArgs {
    /// The OBJ file of the world (its MTL files are read too); optional when objects are
    /// given.
    #[arg(value_name = "WORLD.obj")]
    scene: Option<PathBuf>,
    /// An object NAME (1 to 64 bytes, distinct) compiled from FILE in its own frame, placed by
    /// the renderer: the output is a file of parts (format 5), the world first, then the
    /// objects in the order given. Repeatable.
    #[arg(long = "object", value_parser = cli::parse_object, value_name = "NAME=FILE")]
    objects: Vec<(String, PathBuf)>,
    /// Output .peel file (the name must end in .peel).
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Keep each polygon's source triangle id (needed for `render --ids`).
    #[arg(long)]
    ids: bool,
    /// Store vertices as f32 (12 bytes each) instead of 16-bit steps on the scene's bounds (6
    /// bytes, within 1/131070 of the scene's extent per axis): for views that close in on a
    /// detail.
    #[arg(long)]
    wide_vertices: bool,
    /// Mark the faces of closed parts that face out: while the eye is outside the scene's
    /// bounds the runtime skips those it sees from behind, before reading their vertices.
    /// Exact when no part passes through itself (not checked); open parts stay two-sided.
    #[arg(long)]
    solid: bool,
    /// Candidate planes costed per split node of more than 2048 fragments (sampled when there
    /// are more; smaller nodes cost every plane).
    #[arg(long, default_value_t = BuildOptions::default().candidates, value_name = "K")]
    candidates: usize,
    /// Seed of the candidate sampling.
    #[arg(long, default_value_t = 0, value_name = "N")]
    seed: u64,
    /// Larger output polygons are split into convex pieces.
    #[arg(long, default_value_t = BuildOptions::default().max_polygon_vertices, value_name = "N")]
    max_polygon_vertices: usize,
    /// Direction towards the light (a sun) for the baked Lambert shading, x,y,z not all zero
    /// (default: 0.4,0.8,0.45).
    #[arg(long, value_parser = cli::parse_direction, allow_hyphen_values = true, value_name = "X,Y,Z")]
    light: Option<DVec3>,
    /// A point light at this position instead of a sun (Lambert taken at each polygon's
    /// centroid).
    #[arg(long, value_parser = cli::parse_dvec3, allow_hyphen_values = true, conflicts_with = "light", value_name = "X,Y,Z")]
    point_light: Option<DVec3>,
    /// How the light colours the faces: smooth (interpolated over curved surfaces), faceted
    /// (one colour per face side) or unlit (the raw material colours). Default: faceted.
    #[arg(long, value_enum, value_name = "SHADING")]
    shading: Option<ShadingArg>,
    /// With --shading smooth: faces whose normals are further apart than this angle, in
    /// degrees from 0 to 180, meet at a sharp edge (default: 60).
    #[arg(long, value_parser = cli::parse_crease, allow_hyphen_values = true, value_name = "DEG")]
    crease: Option<Crease>,
    /// Keep the raw material colours (no shading): --shading unlit.
    #[arg(long, conflicts_with_all = ["light", "point_light", "shading"])]
    flat: bool,
    /// Cast shadows from the light: polygons are cut along them, their parts in shadow get
    /// the ambient colour.
    #[arg(long, conflicts_with = "flat")]
    shadows: bool,
    /// The colour R,G,B (0-255 each) of faces without a material, instead of the grey
    /// 200,200,200; the warning about such faces goes. (A file that names no material at all
    /// gets no warning.)
    #[arg(long, value_parser = cli::parse_rgb, value_name = "R,G,B", alias = "default-color")]
    default_colour: Option<[u8; 3]>,
    /// The largest side of a stored texture (MTL map_Kd), in texels: a power of two from 1
    /// to 1024. Larger images, and sides that are not powers of two, are resampled to the
    /// nearest power of two within it.
    #[arg(long, value_parser = cli::parse_max_texture, default_value_t = DEFAULT_MAX_TEXTURE, value_name = "N")]
    max_texture: u32,
    /// Refuse a texture whose sides are not powers of two of at most --max-texture instead of
    /// resampling it.
    #[arg(long)]
    no_resample: bool,
    /// Also write the statistics as JSON to this file.
    #[arg(long, value_name = "FILE")]
    stats_json: Option<PathBuf>,
}

/// `--shading` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum ShadingArg {
    /// Each vertex lit with the surface's normal there, colours interpolated in between.
    Smooth,
    /// One colour per side of each face.
    Faceted,
    /// The material colours as they are (as --flat).
    Unlit,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Compile(args) => compile(&args),
        Command::Inspect { file, json, size } => cli::inspect(&file, json, size),
        Command::Dump { file } => cli::dump(&file),
        Command::Render(args) => cli::render(&args),
        Command::Demo { out } => cli::demo(&out),
        Command::Bench(args) => cli::bench(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn compile(args: &CompileArgs) -> Result<(), String> {
    let peel_name = args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("peel"));
    if !peel_name {
        return Err(format!(
            "-o/--output {}: peel compile writes .peel files: give the output a .peel name",
            args.output.display()
        ));
    }
    let asked = match (args.flat, args.shading) {
        (true, _) => Some(ShadingArg::Unlit),
        (false, asked) => asked,
    };
    let surface = match asked {
        Some(ShadingArg::Smooth) => Surface::Smooth(args.crease.unwrap_or_default()),
        Some(ShadingArg::Faceted | ShadingArg::Unlit) => Surface::Faceted,
        None => match DEFAULT_SURFACE {
            Surface::Smooth(default) => Surface::Smooth(args.crease.unwrap_or(default)),
            Surface::Faceted => Surface::Faceted,
        },
    };
    if args.crease.is_some() && surface == Surface::Faceted {
        return Err(
            "--crease applies to smooth shading only: add --shading smooth, or drop --crease"
                .into(),
        );
    }
    let unlit = asked == Some(ShadingArg::Unlit);
    if unlit && !args.flat {
        let lit = [
            (args.light.is_some(), "--light"),
            (args.point_light.is_some(), "--point-light"),
            (args.shadows, "--shadows"),
        ];
        if let Some((_, flag)) = lit.iter().find(|(on, _)| *on) {
            return Err(format!(
                "{flag} needs a light: --shading unlit has none (use --shading faceted or \
                 smooth)"
            ));
        }
    }
    let shading = match (unlit, args.point_light) {
        (true, _) => Shading::Flat,
        (false, Some(at)) => Shading::Point(at),
        (false, None) => Shading::Lambert(args.light.unwrap_or(DEFAULT_LIGHT)),
    };
    let options = CompileOptions {
        build: BuildOptions {
            candidates: args.candidates,
            seed: args.seed,
            max_polygon_vertices: args.max_polygon_vertices,
            shadows: shading.light().filter(|_| args.shadows),
            ..BuildOptions::default()
        },
        load: LoadOptions {
            default_colour: args.default_colour,
            max_texture: args.max_texture,
            resample: !args.no_resample,
        },
        ids: args.ids,
        id_offset: 0,
        wide_vertices: args.wide_vertices,
        shading,
        surface,
        solid: args.solid,
    };
    match (&args.scene, args.objects.is_empty()) {
        (Some(scene), true) => {
            compile_to(scene, &args.output, &options, args.stats_json.as_deref()).map(|_| ())
        }
        (None, true) => Err(
            "nothing to compile: give the world's OBJ file, or objects with --object NAME=FILE"
                .into(),
        ),
        (world, false) => compile_parts_to(
            world.as_deref(),
            &args.objects,
            &args.output,
            &options,
            args.stats_json.as_deref(),
        ),
    }
}

/// How many polygons of a compiled file are smooth-shaded, and how many bound solids.
fn marked_polygons(bytes: &[u8]) -> (u64, u64) {
    peel_compiler::dump::inspect(bytes).map_or((0, 0), |i| (i.smooth_polygons, i.solid_polygons))
}

/// Compile `scene` into `output` with a progress bar on a terminal, print the summary, and
/// return the bytes written.
pub(crate) fn compile_to(
    scene: &Path,
    output: &Path,
    options: &CompileOptions,
    stats_json: Option<&Path>,
) -> Result<Vec<u8>, String> {
    let bar = ProgressBar::new_spinner();
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{elapsed}]").map_err(|e| e.to_string())?,
    );
    bar.set_message(format!("compiling {}", scene.display()));
    bar.enable_steady_tick(Duration::from_millis(120));
    let progress = |placed: u64| {
        bar.set_message(format!(
            "compiling {}: {placed} polygons placed",
            scene.display()
        ))
    };
    let compiled = compile_obj(scene, options, &progress);
    bar.finish_and_clear();
    let compiled = compiled.map_err(|e| e.to_string())?;
    for w in &compiled.warnings {
        eprintln!("warning: {w}");
    }
    peel_compiler::write::write_atomic(output, &compiled.bytes).map_err(|e| e.to_string())?;
    write_stats(stats_json, &part_stats(&compiled))?;
    println!(
        "{} -> {}: {}",
        scene.display(),
        output.display(),
        summary(&compiled)
    );
    Ok(compiled.bytes)
}

/// The statistics of one compiled tree, as `--stats-json` writes them.
fn part_stats(compiled: &Compiled) -> serde_json::Value {
    let s = compiled.stats;
    let (smooth, solid) = marked_polygons(&compiled.bytes);
    serde_json::json!({
        "input_triangles": s.input_triangles,
        "degenerate_dropped": s.degenerate_dropped,
        "output_polygons": s.output_polygons,
        "convex_nodes": s.convex_nodes,
        "split_nodes": s.split_nodes,
        "cuts": s.cuts,
        "max_depth": s.max_depth,
        "planes": s.planes,
        "smooth_polygons": smooth,
        "solid_polygons": solid,
        "bytes": compiled.bytes.len(),
        "compile_seconds": compiled.seconds,
    })
}

/// The summary line's counters of one compiled tree.
fn summary(compiled: &Compiled) -> String {
    let s = compiled.stats;
    format!(
        "{} triangles ({} degenerate dropped) -> {} polygons, {} convex + {} split nodes, {} cuts, depth {}, {} planes, {} bytes, {:.3} s",
        s.input_triangles,
        s.degenerate_dropped,
        s.output_polygons,
        s.convex_nodes,
        s.split_nodes,
        s.cuts,
        s.max_depth,
        s.planes,
        compiled.bytes.len(),
        compiled.seconds
    )
}

/// Write `stats` as JSON to `path`, if given.
fn write_stats(path: Option<&Path>, stats: &serde_json::Value) -> Result<(), String> {
    if let Some(path) = path {
        let text = serde_json::to_string_pretty(stats).map_err(|e| e.to_string())?;
        peel_compiler::write::write_atomic(path, text.as_bytes()).map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Compile a scene of parts into `output` (a file of parts): print one summary line per part
/// and one for the file; `--stats-json` holds `parts`, one record per part (a plain scene's
/// keys with its `name`, empty for the world, and `obj`), and the file's `bytes` and
/// `compile_seconds`.
fn compile_parts_to(
    world: Option<&Path>,
    objects: &[(String, PathBuf)],
    output: &Path,
    options: &CompileOptions,
    stats_json: Option<&Path>,
) -> Result<(), String> {
    let names: Vec<&str> = objects.iter().map(|(n, _)| n.as_str()).collect();
    peel_compiler::write::parts::check_parts(world.is_some(), &names)
        .map_err(|e| format!("--object: {e}"))?;
    let bar = ProgressBar::new_spinner();
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{elapsed}]").map_err(|e| e.to_string())?,
    );
    let parts = objects.len() + usize::from(world.is_some());
    bar.set_message(format!("compiling {parts} parts"));
    bar.enable_steady_tick(Duration::from_millis(120));
    let progress =
        |placed: u64| bar.set_message(format!("compiling {parts} parts: {placed} polygons placed"));
    let compiled = compile_parts(world, objects, options, &progress);
    bar.finish_and_clear();
    let compiled = compiled.map_err(|e| e.to_string())?;
    for (_, part) in &compiled.parts {
        for w in &part.warnings {
            eprintln!("warning: {w}");
        }
    }
    peel_compiler::write::write_atomic(output, &compiled.bytes).map_err(|e| e.to_string())?;
    let paths = world
        .into_iter()
        .chain(objects.iter().map(|(_, p)| p.as_path()));
    let mut records = Vec::new();
    for ((name, part), path) in compiled.parts.iter().zip(paths) {
        let mut record = part_stats(part);
        record["name"] = name.as_str().into();
        record["obj"] = path.display().to_string().into();
        records.push(record);
        let label = if name.is_empty() { "world" } else { name };
        println!("{} ({label}): {}", path.display(), summary(part));
    }
    write_stats(
        stats_json,
        &serde_json::json!({
            "parts": records,
            "bytes": compiled.bytes.len(),
            "compile_seconds": compiled.seconds,
        }),
    )?;
    println!(
        "-> {}: {} parts ({}{} objects), {} bytes, {:.3} s",
        output.display(),
        compiled.parts.len(),
        if world.is_some() {
            "the world and "
        } else {
            ""
        },
        objects.len(),
        compiled.bytes.len(),
        compiled.seconds
    );
    Ok(())
}
