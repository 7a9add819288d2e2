//! The on-target benchmark (`bash .ci/target [--quick]`, BENCHMARKS.md "On the target"): Peel's
//! renderer and the z-buffer baseline as Cortex-M4F and Cortex-M0+ firmware in QEMU, with
//! deterministic instruction counts, RAM and flash, bytes sent to a mock SPI display, and
//! every pixel checked against the host.
//!
//! Steps: build `peel` and one firmware per variant and core; compile the scenes with `peel
//! compile` and export the z-buffer's meshes; for each scene, core, size and variant write a
//! config block, run QEMU twice (instruction counts must agree), compare each frame the panel
//! received with the host's (`peel render` in the same order, the compiler's host renderer
//! anti-aliased, or the same z-buffer code run on the host) and write
//! `target/peel-target/results.json` and `results.md`. Any differing pixel or count fails the
//! run (after writing the results), as does any failed step. A full run with the streamed
//! build also measures the scene with moving objects against the same geometry as one static
//! file ([`objects`]).

mod accuracy;
mod elf;
mod measure;
mod objects;
mod pixels;
mod plan;
mod report;
mod scenes;
mod textured;
mod tools;
mod transparent;

use std::collections::hash_map::{Entry, HashMap};
use std::path::Path;
use std::process::ExitCode;
use std::rc::Rc;
use std::time::Instant;

use peel_runtime::display::Colour;
use peel_target_kit::config::{OrbitAngles, Variant};
use peel_target_kit::mesh::Mesh;
use peel_target_runner::{plot, results};

use accuracy::Truth;
use measure::{Expected, Measure, Robust};
use plan::{Args, Core, Setup, FOV_Y_DEG};
use scenes::Compiled;
use tools::Tools;

/// Background of every frame (`peel render --background`): not black, so that a pixel the
/// firmware leaves unpainted or paints in black shows.
const BACKGROUND: [u8; 3] = [24, 26, 32];

fn main() -> ExitCode {
    let args = match plan::parse_args(std::env::args().skip(1)) {
        Ok(Some(args)) => args,
        Ok(None) => {
            println!("{}", plan::USAGE);
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            eprintln!("target: {e}");
            return ExitCode::from(2);
        }
    };
    let start = Instant::now();
    let outcome = run(&args);
    let seconds = start.elapsed().as_secs_f64();
    match outcome {
        Ok(problems) if problems.is_empty() => {
            println!("target: every pixel as on the host, every count repeated ({seconds:.0} s)");
            ExitCode::SUCCESS
        }
        Ok(problems) => {
            for p in &problems {
                eprintln!("target: FAILED: {p}");
            }
            eprintln!("target: {} problems ({seconds:.0} s)", problems.len());
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("target: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Create `dir` (and its parents).
fn mkdir(dir: &Path) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: cannot create: {e}", dir.display()))
}

/// Write `bytes` to `path`.
fn write(path: &Path, bytes: &[u8]) -> Result<(), String> {
    std::fs::write(path, bytes).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// The whole benchmark; the problems found (differing pixels, counts that did not repeat).
fn run(args: &Args) -> Result<Vec<String>, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .map_err(|e| format!("the repository root: {e}"))?;
    tools::check_qemu()?;
    let mut tools = Tools::find(&root)?;
    let out = tools.target_dir.join("peel-target");
    let firmware_dir = out.join("firmware");
    let scene_dir = out.join("scenes");
    for dir in [&firmware_dir, &scene_dir] {
        mkdir(dir)?;
    }
    // Runs of an earlier invocation would mix with these.
    let runs_dir = out.join("runs");
    if runs_dir.exists() {
        std::fs::remove_dir_all(&runs_dir)
            .map_err(|e| format!("{}: cannot remove: {e}", runs_dir.display()))?;
    }

    println!("== build: peel");
    tools.build_peel()?;
    let setups = plan::setups(args.only.as_deref());
    let smooth_setups = plan::smooth_setups(args.only.as_deref(), args.quick);
    let mut variants: Vec<Variant> = setups.iter().map(|s| s.variant).collect();
    variants.extend(smooth_setups.iter().map(|s| s.variant));
    let mut seen = Vec::new();
    variants.retain(|v| {
        let new = !seen.contains(v);
        seen.push(*v);
        new
    });
    let cores = [Core::M4f, Core::M0Plus];
    let mut firmware = HashMap::new();
    for core in cores {
        for &variant in &variants {
            println!("== build: firmware {} for {}", variant.name(), core.name());
            // embedded-3dgfx's first build only finds how many commands a scene needs.
            let commands = (variant == Variant::Gfx3d).then_some(GFX3D_PROBE_COMMANDS);
            let elf = tools.build_firmware(core, variant, commands, &firmware_dir)?;
            if core == Core::M0Plus {
                tools::check_armv6m(&elf)?;
            }
            firmware.insert((core, variant), elf);
        }
    }

    let models = args
        .models
        .clone()
        .unwrap_or_else(|| root.join("../shared/models"));
    let scenes = scenes::list(&root, &models, args.quick, &scene_dir)?;
    let cameras = plan::cameras(if args.quick { 2 } else { 8 });
    let (mut records, mut problems, mut skipped) = (Vec::new(), Vec::new(), Vec::new());
    let mut gfx3d_builds: Gfx3dBuilds = HashMap::new();
    for spec in &scenes {
        println!("== scene {}", spec.name);
        let scene = scenes::compile(&tools, spec, args.shadows, None, &scene_dir)?;
        let depth = peel_runtime::read::Scene::parse(&scene.peel_bytes)
            .map_err(|e| format!("{}: {e}", scene.peel.display()))?
            .header()
            .max_depth;
        if depth as usize > peel_target_kit::STACK {
            let notice = format!(
                "{}: skipped, its tree is {depth} deep and the firmware's stack holds {}",
                spec.name,
                peel_target_kit::STACK
            );
            println!("   {notice}");
            skipped.push(notice);
            continue;
        }
        // A core without an FPU draws with integer vertices: its references do too.
        let mut references: HashMap<((u32, u32), bool), References> = HashMap::new();
        // The reference of each size, shared by the cores that draw at it.
        let mut truths: HashMap<(u32, u32), Rc<Truth>> = HashMap::new();
        for core in cores {
            let sizes = if args.quick {
                &core.sizes()[..1]
            } else {
                core.sizes()
            };
            for &size in sizes {
                let integer = core.integer_vertices();
                let refs = match references.entry((size, integer)) {
                    Entry::Occupied(e) => e.into_mut(),
                    Entry::Vacant(e) => {
                        let mut folder = size_name(size);
                        if integer {
                            folder.push_str("-integer");
                        }
                        let dir = out.join("references").join(stem(&scene)).join(folder);
                        mkdir(&dir)?;
                        let truth = match truths.entry(size) {
                            Entry::Occupied(t) => Rc::clone(t.get()),
                            Entry::Vacant(t) => Rc::clone(t.insert(Rc::new(Truth::new(
                                &scene.spec.obj,
                                &scenes::options(scene.shadows, None)?,
                                &cameras,
                                size,
                            )?))),
                        };
                        e.insert(References::new(
                            &tools, &scene, size, integer, truth, &cameras, &setups, &dir,
                        )?)
                    }
                };
                let start = records.len();
                for setup in &setups {
                    let mut elf = firmware[&(core, setup.variant)].clone();
                    let dir = |setup: &plan::Setup| {
                        runs_dir.join(stem(&scene)).join(format!(
                            "{}-{}-{}",
                            core.name(),
                            size_name(size),
                            setup.label()
                        ))
                    };
                    let measure = |setup: plan::Setup, elf: &Path| Measure {
                        scene: &scene,
                        core,
                        size,
                        setup,
                        cameras: &cameras,
                        spans_per_row: refs.spans_per_row,
                        // The builder's `SCAN_NODES`, or `SCAN_NODES_AA` anti-aliased.
                        scan_nodes: if setup.variant == Variant::ScanAa {
                            refs.scan_nodes.1
                        } else {
                            refs.scan_nodes.0
                        },
                        pending_pixels: refs.pending_pixels,
                        composite_runs: 0,
                        scanline_lists: refs.scanline_lists,
                        elf: elf.to_path_buf(),
                        timeout_s: if args.quick { 120 } else { 900 },
                    };
                    if setup.variant == Variant::Gfx3d {
                        elf = gfx3d_elf(
                            &tools,
                            &measure(*setup, &elf),
                            &dir(setup),
                            &mut gfx3d_builds,
                            &firmware_dir,
                            false,
                        )?;
                    }
                    let run = |setup: plan::Setup| {
                        measure(setup, &elf).measure(&dir(&setup), &refs.expected(setup.variant))
                    };
                    let (record, found) = if setup.variant == Variant::TiledZbuffer {
                        // Bands as tall as RAM no more than Peel's streamed frame allows.
                        let peel = records[start..].iter().find(|r: &&results::Record| {
                            r.method == Variant::FtbStream.method() && r.path == "stream"
                        });
                        let budget = peel.map_or(TILED_BUDGET, |r| r.ram_bytes);
                        tiled(size, budget, run)?
                    } else {
                        run(*setup)?
                    };
                    records.push(record);
                    problems.extend(found);
                }
            }
        }
        if plan::smooth_scene(&spec.name, args.quick) && !smooth_setups.is_empty() {
            let size = plan::SMOOTH_SIZE;
            let truth = match truths.get(&size) {
                Some(t) => Rc::clone(t),
                None => Rc::new(Truth::new(
                    &spec.obj,
                    &scenes::options(args.shadows, None)?,
                    &cameras,
                    size,
                )?),
            };
            let smooth = Smooth {
                tools: &tools,
                firmware: &firmware,
                setups: &smooth_setups,
                cameras: &cameras,
                truth: &truth,
                runs_dir: &runs_dir,
                firmware_dir: &firmware_dir,
                timeout_s: if args.quick { 120 } else { 900 },
                crease: plan::smooth_crease_deg(args.quick),
            };
            let (found_records, found) =
                smooth.run(spec, args.shadows, &scene_dir, &mut gfx3d_builds)?;
            records.extend(found_records);
            problems.extend(found);
        }
    }
    // The scene with moving objects and its static baseline: the streamed build only, in
    // full runs (the quick run stays as it was).
    let mut objects_summary = String::new();
    if !args.quick {
        let streamed = setups.iter().any(|s| s.variant == Variant::FtbStream);
        if streamed && !args.shadows {
            let outcome = objects::Objects {
                tools: &tools,
                firmware_dir: &firmware_dir,
                cameras: &cameras,
                models: &models,
                scene_dir: &scene_dir,
                runs_dir: &runs_dir,
                timeout_s: 900,
            }
            .run()?;
            records.extend(outcome.records);
            problems.extend(outcome.problems);
            objects_summary = outcome.summary;
        } else {
            let notice = "objects: skipped, only ftb-stream draws a scene with objects, and                           without --shadows"
                .to_string();
            println!("   {notice}");
            skipped.push(notice);
        }
    }
    // The textured scenes and their untextured baselines: Peel streamed and embedded-3dgfx,
    // by the builds with textures, in full runs.
    let mut textured_summary = String::new();
    if !args.quick {
        let textured_setups = textured::setups(&setups);
        if !textured_setups.is_empty() && !args.shadows {
            let outcome = textured::Textured {
                tools: &tools,
                root: &root,
                firmware_dir: &firmware_dir,
                plain: &firmware,
                setups: &textured_setups,
                cameras: &cameras,
                scene_dir: &scene_dir,
                runs_dir: &runs_dir,
                references_dir: &out.join("references"),
                timeout_s: 900,
            }
            .run(&mut gfx3d_builds)?;
            records.extend(outcome.records);
            problems.extend(outcome.problems);
            textured_summary = outcome.summary;
        } else {
            let notice = "textured scenes: skipped, only ftb-stream and embedded-3dgfx draw them, \
                          without --shadows"
                .to_string();
            println!("   {notice}");
            skipped.push(notice);
        }
    }
    // The transparent glass box, its opaque baseline and the teapot alone: the streamed build
    // with transparency, in full runs.
    let mut transparent_summary = String::new();
    if !args.quick {
        let streamed = setups.iter().any(|s| s.variant == Variant::FtbStream);
        if streamed && !args.shadows {
            let outcome = transparent::Transparent {
                tools: &tools,
                models: &models,
                firmware_dir: &firmware_dir,
                cameras: &cameras,
                scene_dir: &scene_dir,
                runs_dir: &runs_dir,
                references_dir: &out.join("references"),
                timeout_s: 900,
            }
            .run()?;
            records.extend(outcome.records);
            problems.extend(outcome.problems);
            transparent_summary = outcome.summary;
        } else {
            let notice = "transparent scene: skipped, only ftb-stream draws it, without --shadows"
                .to_string();
            println!("   {notice}");
            skipped.push(notice);
        }
    }
    let json = results::json(&records)?;
    write(&out.join("results.json"), json.as_bytes())?;
    write(
        &out.join("results.md"),
        (results::markdown(&records)
            + &results::antialiased(&records)
            + &results::smooth(&records)
            + &results::textured(&records)
            + &objects_summary
            + &textured_summary
            + &transparent_summary
            + &skipped
                .iter()
                .map(|n| format!("\n{n}\n"))
                .collect::<String>())
            .as_bytes(),
    )?;
    // The plot a user decides from: the teapot's (or the first scene's); a full run with the
    // real teapot keeps it in the repository (README, "Peel and the alternatives").
    let pick = ["teapot", "teapot (generated)"]
        .into_iter()
        .find(|s| records.iter().any(|r| r.scene == *s))
        .or(records.first().map(|r| r.scene.as_str()));
    if let Some(png) = pick.map(|s| plot::plot(&records, s)).transpose()?.flatten() {
        write(&out.join("alternatives.png"), &png)?;
        let scenes = results::alternatives_scenes(&records);
        write(
            &out.join("alternatives.md"),
            results::alternatives(&records, &scenes).as_bytes(),
        )?;
        if !args.quick && args.only.is_none() && !args.shadows && pick == Some("teapot") {
            write(&root.join("target-bench/alternatives.png"), &png)?;
        }
    }
    println!(
        "\n{}{}{}{}{objects_summary}{textured_summary}{transparent_summary}",
        results::markdown(&records),
        results::antialiased(&records),
        results::smooth(&records),
        results::textured(&records)
    );
    println!(
        "written: {} and results.md",
        out.join("results.json").display()
    );
    Ok(problems)
}

/// embedded-3dgfx's builds made so far, by core, command buffer and whether with textures.
type Gfx3dBuilds = HashMap<(Core, u64, bool), std::path::PathBuf>;

/// embedded-3dgfx's build for `measure`'s scene on its core: a run of the probe build
/// (`measure.elf`, in `dir`) finds the smallest command buffer that fits the scene over the
/// cameras, and the build with it is made once per core and size of buffer (with textures as
/// `textures` says, as the probe build was).
fn gfx3d_elf(
    tools: &Tools,
    measure: &Measure<'_>,
    dir: &Path,
    builds: &mut Gfx3dBuilds,
    firmware_dir: &Path,
    textures: bool,
) -> Result<std::path::PathBuf, String> {
    let probe = measure.probe(dir)?;
    let commands = probe
        .gfx3d_commands
        .ok_or("embedded-3dgfx: no command count")?;
    let core = measure.core;
    Ok(match builds.entry((core, commands, textures)) {
        Entry::Occupied(e) => e.get().clone(),
        Entry::Vacant(e) => {
            println!(
                "== build: firmware embedded-3dgfx{} for {} with {commands} commands",
                if textures { ",textures" } else { "" },
                core.name()
            );
            let elf = if textures {
                tools.build_textures_firmware(core, Variant::Gfx3d, Some(commands), firmware_dir)?
            } else {
                tools.build_firmware(core, Variant::Gfx3d, Some(commands), firmware_dir)?
            };
            e.insert(elf).clone()
        }
    })
}

/// The smooth runs of a scene ([`plan::smooth_setups`]): its smooth file (`peel compile
/// --shading smooth --crease DEG`, otherwise the flat file's options) on both cores at
/// [`plan::SMOOTH_SIZE`], each checked against the host's frames of the same file drawn as
/// the firmware draws it ([`smooth_frame`]), the robust errors counted from the frames.
struct Smooth<'a> {
    tools: &'a Tools,
    firmware: &'a HashMap<(Core, Variant), std::path::PathBuf>,
    setups: &'a [Setup],
    cameras: &'a [OrbitAngles],
    /// The reference at [`plan::SMOOTH_SIZE`] (the OBJ's, as the flat file's).
    truth: &'a Truth,
    runs_dir: &'a Path,
    firmware_dir: &'a Path,
    timeout_s: u32,
    /// The smooth files' crease in degrees ([`plan::smooth_crease_deg`]).
    crease: f64,
}

impl Smooth<'_> {
    fn run(
        &self,
        spec: &scenes::SceneSpec,
        shadows: bool,
        scene_dir: &Path,
        gfx3d_builds: &mut Gfx3dBuilds,
    ) -> Result<(Vec<results::Record>, Vec<String>), String> {
        println!("== scene {} smooth", spec.name);
        let scene = scenes::compile(self.tools, spec, shadows, Some(self.crease), scene_dir)?;
        let depth = peel_runtime::read::Scene::parse(&scene.peel_bytes)
            .map_err(|e| format!("{}: {e}", scene.peel.display()))?
            .header()
            .max_depth;
        if depth as usize > peel_target_kit::STACK {
            return Err(format!(
                "{}: its smooth tree is {depth} deep and the firmware's stack holds {}",
                spec.name,
                peel_target_kit::STACK
            ));
        }
        let (width, height) = plan::SMOOTH_SIZE;
        let fail = |e: String| format!("{}: {e}", scene.peel.display());
        let spans_per_row =
            peel_compiler::spans::spans_per_row(&scene.peel_bytes, width, height).map_err(fail)?;
        let needs = |v: Variant| self.setups.iter().any(|s| s.variant == v);
        let scan_nodes = if needs(Variant::ScanOrder) {
            peel_compiler::spans::scan_nodes(&scene.peel_bytes, width, height).map_err(fail)?
        } else {
            0
        };
        let (mut records, mut problems) = (Vec::new(), Vec::new());
        for core in [Core::M4f, Core::M0Plus] {
            let integer = core.integer_vertices();
            // Dithered, as the panel's sink sends shaded spans and scan memory reads them out
            // by default.
            let frames = if needs(Variant::FtbStream) || needs(Variant::ScanOrder) {
                (self.cameras.iter())
                    .map(|&c| smooth_frame(&scene, c, (width, height), integer))
                    .collect::<Result<Vec<_>, _>>()?
            } else {
                Vec::new()
            };
            for setup in self.setups {
                let dir = self
                    .runs_dir
                    .join(format!("{}-smooth", stem(&scene)))
                    .join(format!(
                        "{}-{}-{}",
                        core.name(),
                        size_name((width, height)),
                        setup.label()
                    ));
                let mut measure = Measure {
                    scene: &scene,
                    core,
                    size: (width, height),
                    setup: *setup,
                    cameras: self.cameras,
                    spans_per_row: spans_per_row as u32,
                    scan_nodes: scan_nodes as u32,
                    pending_pixels: 0,
                    composite_runs: 0,
                    scanline_lists: (0, 0),
                    elf: self.firmware[&(core, setup.variant)].clone(),
                    timeout_s: self.timeout_s,
                };
                if setup.variant == Variant::Gfx3d {
                    measure.elf = gfx3d_elf(
                        self.tools,
                        &measure,
                        &dir,
                        gfx3d_builds,
                        self.firmware_dir,
                        false,
                    )?;
                }
                let expected = Expected {
                    frames: match setup.variant {
                        Variant::FtbStream | Variant::ScanOrder => Some(&frames[..]),
                        _ => None,
                    },
                    robust_errors: Robust::FromFrames,
                    truth: Some(self.truth),
                    pending_peaks: None,
                };
                let (record, found) = measure.measure(&dir, &expected)?;
                records.push(record);
                problems.extend(found);
            }
        }
        Ok((records, problems))
    }
}

/// The frame of the smooth `scene` from the orbit camera `angles` at `size` as the streamed
/// and scan-order firmware draws it: Peel's renderer front to back with span memory (integer
/// vertices or not), the firmware's view and background, into an RGB565 framebuffer whose
/// shaded spans are dithered ([`peel_runtime::display::dither_rgb565`], as the panel's sink
/// sends them and scan memory reads them out), flat spans rounded.
fn smooth_frame(
    scene: &Compiled,
    angles: OrbitAngles,
    (w, h): (u32, u32),
    integer: bool,
) -> Result<Vec<u16>, String> {
    use peel_runtime::coverage::Coverage;
    use peel_runtime::display::Rgb565Framebuffer;
    use peel_runtime::render::{Renderer, Workspace};
    let fail = |e: String| format!("{}: host smooth frame: {e}", scene.peel.display());
    let parsed =
        peel_runtime::read::Scene::parse(&scene.peel_bytes).map_err(|e| fail(e.to_string()))?;
    let view = peel_target_kit::orbit_view(&parsed.header(), angles, FOV_Y_DEG, w, h)
        .map_err(|e| fail(e.to_string()))?;
    let rows = h as usize;
    let mut workspace: Box<Workspace<{ 1 << 14 }, 64>> = Box::default();
    let mut intervals = vec![(0u16, 0u16); (w as usize).div_ceil(2) * rows];
    let mut counts = vec![0u16; rows];
    let coverage =
        Coverage::new(&mut intervals, &mut counts, w, h).map_err(|e| fail(e.to_string()))?;
    let [r, g, b] = BACKGROUND;
    let mut renderer = Renderer::new(&mut workspace)
        .span_memory(coverage)
        .background(Colour::new(r, g, b));
    if integer {
        renderer = renderer.integer_vertices();
    }
    let mut pixels = vec![0u16; w as usize * rows];
    let mut fb = Rgb565Framebuffer::new(&mut pixels, w, h).map_err(|e| fail(e.to_string()))?;
    renderer
        .draw(&parsed, &view, &mut fb)
        .map_err(|e| fail(e.to_string()))?;
    Ok(pixels)
}

/// A scene's name for paths.
fn stem(scene: &Compiled) -> String {
    scene.spec.name.replace(" (generated)", "-generated")
}

fn size_name((w, h): (u32, u32)) -> String {
    format!("{w}x{h}")
}

/// embedded-3dgfx's command buffer in the build that finds how many a scene needs (more than
/// the largest scene's triangles: one command per face drawn and one for the depth clear).
const GFX3D_PROBE_COMMANDS: u64 = 16 * 1024;

/// RAM for the tiled z-buffer when Peel's streamed frame was not measured (`--only`).
const TILED_BUDGET: u64 = 32 * 1024;

/// The tiled z-buffer measured with the tallest bands whose RAM is at most `budget` bytes: a
/// first guess beside 3 kB of statics and stack, then the height that the run's own statics
/// and stack leave room for (a few runs at most: only the band buffers change with it).
fn tiled(
    (width, height): (u32, u32),
    budget: u64,
    run: impl Fn(plan::Setup) -> Result<(results::Record, Vec<String>), String>,
) -> Result<(results::Record, Vec<String>), String> {
    let row_bytes = 4 * u64::from(width);
    let mut rows = plan::tiled_band_rows(budget, 3 * 1024, width, height);
    let mut best = None;
    for _ in 0..4 {
        let setup = plan::Setup {
            variant: Variant::TiledZbuffer,
            band_rows: rows,
        };
        let (record, found) = run(setup)?;
        let other = record.ram_bytes.saturating_sub(row_bytes * u64::from(rows));
        let fits = record.ram_bytes <= budget;
        let next = plan::tiled_band_rows(budget, other, width, height);
        if fits || rows == 1 {
            best = Some((record, found));
        }
        if next == rows && (fits || rows == 1) {
            break;
        }
        rows = if fits { next } else { next.min(rows - 1) };
    }
    best.ok_or_else(|| format!("tiled z-buffer: no band height fits {budget} bytes"))
}

/// The host's frames of one scene and size, for each camera: `peel render` in each order, the
/// anti-aliased frames of the compiler's host renderer, and the z-buffers run on the host; the
/// reference and each method's robust errors; and the memory the firmware gets (span memory,
/// scan memory, pending pixels, the scanline z-buffer's lists).
struct References {
    front_to_back: Vec<Vec<u16>>,
    /// Anti-aliased, with the firmware's pending-pixel records.
    antialiased: Vec<Vec<u16>>,
    /// Anti-aliased: the most pending pixels each frame holds at once with records to spare.
    pending_peaks: Vec<u64>,
    pending_pixels: u32,
    back_to_front: Vec<Vec<u16>>,
    zbuffer: Vec<Vec<u16>>,
    scanline: Vec<Vec<u16>>,
    spans_per_row: u32,
    /// Scan memory nodes, plain and anti-aliased.
    scan_nodes: (u32, u32),
    scanline_lists: (u32, u32),
    truth: Rc<Truth>,
    /// Robust errors per method that draws ids, summed over the cameras.
    robust: HashMap<&'static str, u64>,
}

impl References {
    /// Render what `setups` need into `dir` (Peel's frames with integer vertices or not), and
    /// count the robust errors against `truth`, the reference of this size.
    #[allow(clippy::too_many_arguments)]
    fn new(
        tools: &Tools,
        scene: &Compiled,
        (width, height): (u32, u32),
        integer: bool,
        truth: Rc<Truth>,
        cameras: &[OrbitAngles],
        setups: &[Setup],
        dir: &Path,
    ) -> Result<References, String> {
        let needs = |v: Variant| setups.iter().any(|s| s.variant.method() == v.method());
        let peel = |order: &str, variant: Variant| -> Result<Vec<Vec<u16>>, String> {
            if !needs(variant) {
                return Ok(Vec::new());
            }
            let [r, g, b] = BACKGROUND;
            cameras
                .iter()
                .enumerate()
                .map(|(k, c)| {
                    let png = dir.join(format!("{order}-{k}.png"));
                    let orbit = format!("--orbit={},{}", c.azimuth_deg, c.elevation_deg);
                    let size = format!("--size={width}x{height}");
                    let order_arg = format!("--order={order}");
                    let background = format!("--background={r},{g},{b}");
                    let mut args: Vec<&std::ffi::OsStr> = vec![
                        "render".as_ref(),
                        scene.peel.as_os_str(),
                        orbit.as_ref(),
                        size.as_ref(),
                        order_arg.as_ref(),
                        background.as_ref(),
                    ];
                    if integer {
                        args.push("--integer-vertices".as_ref());
                    }
                    args.extend(["-o".as_ref(), png.as_os_str()]);
                    tools.peel(&args)?;
                    pixels::png_rgb565(&png, width, height)
                })
                .collect()
        };
        let fail = |e: String| format!("{}: {e}", scene.mesh.display());
        let mesh = Mesh::parse(&scene.mesh_bytes).map_err(|e| fail(e.to_string()))?;
        let ids_mesh = Mesh::parse(&scene.ids_mesh_bytes).map_err(|e| fail(e.to_string()))?;
        let background = Colour::new(BACKGROUND[0], BACKGROUND[1], BACKGROUND[2]).to_rgb565();
        let views = cameras
            .iter()
            .map(|&c| {
                peel_target_kit::orbit_view(&mesh.header(), c, FOV_Y_DEG, width, height)
                    .map_err(|e| e.to_string())
            })
            .collect::<Result<Vec<_>, String>>()?;
        let mut robust = HashMap::new();
        let zbuffers = needs(Variant::Zbuffer) || needs(Variant::TiledZbuffer);
        let zbuffer = if zbuffers {
            let draw = |mesh: &Mesh, view, background| {
                let n = width as usize * height as usize;
                let (mut colour, mut depth) = (vec![0u16; n], vec![0u16; n]);
                peel_target_kit::zbuffer::draw(mesh, view, background, &mut colour, &mut depth)
                    .map_err(|e| fail(format!("host z-buffer: {e}")))?;
                Ok::<_, String>(colour)
            };
            let mut errors = 0;
            for (k, view) in views.iter().enumerate() {
                let ids = draw(&ids_mesh, view, 0)?;
                errors +=
                    truth.id_errors(k, &ids.iter().map(|&i| u32::from(i)).collect::<Vec<_>>());
            }
            // Bands are the frame's rows (the same triangles, order, spans and depths).
            robust.insert(Variant::Zbuffer.method(), errors);
            robust.insert(Variant::TiledZbuffer.method(), errors);
            views
                .iter()
                .map(|view| draw(&mesh, view, background))
                .collect::<Result<_, String>>()?
        } else {
            Vec::new()
        };
        let (scanline, scanline_lists) = if needs(Variant::ScanlineZbuffer) {
            let (mut frames, mut errors, mut lists) = (Vec::new(), 0, (0, 0));
            for (k, view) in views.iter().enumerate() {
                let (ids, _) = scanline_frame(&ids_mesh, view, 0)?;
                errors +=
                    truth.id_errors(k, &ids.iter().map(|&i| u32::from(i)).collect::<Vec<_>>());
                let (frame, stats) = scanline_frame(&mesh, view, background)?;
                frames.push(frame);
                lists.0 = lists.0.max(stats.peak_active as u32);
                lists.1 = lists.1.max(stats.extra_points as u32);
            }
            robust.insert(Variant::ScanlineZbuffer.method(), errors);
            (frames, lists)
        } else {
            (Vec::new(), (0, 0))
        };
        for (variant, front_to_back) in
            [(Variant::FtbStream, true), (Variant::B2fFramebuffer, false)]
        {
            if needs(variant) {
                let mut errors = 0;
                for (k, &c) in cameras.iter().enumerate() {
                    let ids = truth.peel_ids(c, (width, height), front_to_back, integer)?;
                    errors += truth.id_errors(k, &ids);
                }
                robust.insert(variant.method(), errors);
            }
        }
        // What the builder's sizes file gives firmware for this image size: an orbit that
        // includes these cameras never falls back.
        let spans_per_row = peel_compiler::spans::spans_per_row(&scene.peel_bytes, width, height)
            .map_err(|e| format!("{}: {e}", scene.peel.display()))?
            as u32;
        let scan_nodes = |nodes: fn(&[u8], u32, u32) -> Result<usize, String>| {
            nodes(&scene.peel_bytes, width, height)
                .map(|n| n as u32)
                .map_err(|e| format!("{}: {e}", scene.peel.display()))
        };
        // Only for the builds that take it (not every build of the method: a transparent
        // scene, streamed with composite memory, has no scan-order frame).
        let scan_nodes = (
            if setups.iter().any(|s| s.variant == Variant::ScanOrder) {
                scan_nodes(peel_compiler::spans::scan_nodes)?
            } else {
                0
            },
            if setups.iter().any(|s| s.variant == Variant::ScanAa) {
                scan_nodes(peel_compiler::spans::scan_nodes_antialiased)?
            } else {
                0
            },
        );
        // Anti-aliased: the records the builder's sizes file gives (`PENDING_PIXELS`), and the
        // frames of the compiler's host renderer with as many.
        let (antialiased, pending_peaks, pending_pixels) =
            if setups.iter().any(|s| s.variant.antialiased()) {
                let records =
                    peel_compiler::spans::pending_pixels(&scene.peel_bytes, width, height)
                        .map_err(|e| format!("{}: {e}", scene.peel.display()))?;
                let (mut frames, mut peaks) = (Vec::new(), Vec::new());
                for &c in cameras {
                    let size = (width, height);
                    frames.push(antialiased_frame(scene, c, size, integer, records)?);
                    peaks.push(pending_peak(scene, c, size, integer)?);
                }
                (frames, peaks, records as u32)
            } else {
                (Vec::new(), Vec::new(), 0)
            };
        Ok(References {
            front_to_back: peel("front-to-back", Variant::FtbStream)?,
            antialiased,
            pending_peaks,
            pending_pixels,
            back_to_front: peel("back-to-front", Variant::B2fFramebuffer)?,
            zbuffer,
            scanline,
            spans_per_row,
            scan_nodes,
            scanline_lists,
            truth,
            robust,
        })
    }

    /// What a variant's frames are checked against.
    fn expected(&self, variant: Variant) -> Expected<'_> {
        let frames = match variant {
            Variant::FtbFramebuffer
            | Variant::FtbStream
            | Variant::FtbBands
            | Variant::ScanOrder => Some(&self.front_to_back[..]),
            Variant::B2fFramebuffer | Variant::B2fBands => Some(&self.back_to_front[..]),
            // The tiled z-buffer's bands are the whole frame's rows.
            Variant::Zbuffer | Variant::TiledZbuffer => Some(&self.zbuffer[..]),
            Variant::ScanlineZbuffer => Some(&self.scanline[..]),
            Variant::StreamAa | Variant::ScanAa => Some(&self.antialiased[..]),
            Variant::Gfx3d => None,
        };
        let robust_errors = if variant.antialiased() {
            Robust::NotApplicable
        } else {
            self.robust
                .get(variant.method())
                .map_or(Robust::FromFrames, |&n| Robust::Known(n))
        };
        Expected {
            frames,
            robust_errors,
            truth: Some(&self.truth),
            pending_peaks: variant.antialiased().then_some(&self.pending_peaks[..]),
        }
    }
}

/// The scanline z-buffer's frame of `mesh` seen by `view` on the host, with lists as long as
/// anything can need, and what it used of them.
fn scanline_frame(
    mesh: &Mesh,
    view: &peel_runtime::camera::LocalView,
    background: u16,
) -> Result<(Vec<u16>, peel_target_kit::scanline::ScanStats), String> {
    use peel_target_kit::scanline::{draw, FrameRows, OwnedLists};
    let mut owned = OwnedLists::for_mesh(mesh, view.width, view.height);
    let mut rows = FrameRows::new(view.width, view.height, 0);
    let stats = draw(mesh, view, background, &mut owned.lists(), &mut rows)
        .map_err(|e| format!("host scanline z-buffer: {e}"))?;
    Ok((rows.pixels, stats))
}

/// The anti-aliased frame of `scene` from the orbit camera `angles` at `size` as the compiler's
/// host renderer draws it (`peel_compiler::tools::raster`, `Settings::antialias`) with
/// `records` pending-pixel records, the background of every frame and the firmware's vertices,
/// as RGB565 (as `pixels::png_rgb565` converts the other frames).
fn antialiased_frame(
    scene: &Compiled,
    angles: OrbitAngles,
    (width, height): (u32, u32),
    integer: bool,
    records: usize,
) -> Result<Vec<u16>, String> {
    use peel_compiler::tools::raster::{render_bytes_with, Settings};
    use peel_compiler::tools::shot::Shot;
    use peel_runtime::camera::Orbit;
    let header = peel_runtime::read::Scene::parse(&scene.peel_bytes)
        .map_err(|e| format!("{}: {e}", scene.peel.display()))?
        .header();
    let pose = Orbit {
        azimuth_deg: angles.azimuth_deg,
        elevation_deg: angles.elevation_deg,
        distance: Orbit::fitting_distance(FOV_Y_DEG, width, height),
    }
    .pose(&header);
    let shot = Shot {
        fov_y_deg: FOV_Y_DEG,
        ..Shot::new(pose.eye, pose.target, width, height)
    };
    let settings = Settings {
        background: BACKGROUND,
        integer_vertices: integer,
        antialias: Some(records),
        ..Settings::default()
    };
    let frame = render_bytes_with(&scene.peel_bytes, &shot, &settings)
        .map_err(|e| format!("{}: host anti-aliased frame: {e}", scene.peel.display()))?;
    if !frame.stats.antialiased {
        return Err(format!(
            "{}: the host's frame at {} deg is not anti-aliased",
            scene.peel.display(),
            angles.azimuth_deg
        ));
    }
    Ok(frame
        .pixels
        .iter()
        .map(|&p| Colour::new((p >> 16) as u8, (p >> 8) as u8, p as u8).to_rgb565())
        .collect())
}

/// The most pending pixels the anti-aliased frame of `scene` from the orbit camera `angles`
/// at `size` (the firmware's view) holds at once with records to spare (all a pool can
/// address) and span memory that never runs out: with at least as many, no row of the frame
/// falls back.
fn pending_peak(
    scene: &Compiled,
    angles: OrbitAngles,
    (w, h): (u32, u32),
    integer: bool,
) -> Result<u64, String> {
    use peel_runtime::coverage::Coverage;
    use peel_runtime::display::SpanSink;
    use peel_runtime::pending::{Pending, PendingPixel};
    use peel_runtime::render::{Renderer, Workspace};
    struct Nowhere;
    impl SpanSink for Nowhere {
        fn span(&mut self, _: u32, _: u32, _: u32, _: Colour) {}
    }
    let fail = |e: String| format!("{}: pending pixels: {e}", scene.peel.display());
    let parsed =
        peel_runtime::read::Scene::parse(&scene.peel_bytes).map_err(|e| fail(e.to_string()))?;
    let view = peel_target_kit::orbit_view(&parsed.header(), angles, FOV_Y_DEG, w, h)
        .map_err(|e| fail(e.to_string()))?;
    let rows = h as usize;
    let mut workspace: Box<Workspace<{ 1 << 14 }, 64>> = Box::default();
    let mut intervals = vec![(0u16, 0u16); (w as usize).div_ceil(2) * rows];
    let mut counts = vec![0u16; rows];
    let mut records = vec![PendingPixel::default(); peel_compiler::tools::raster::HOST_PENDING];
    let mut heads = vec![Default::default(); rows];
    let coverage =
        Coverage::new(&mut intervals, &mut counts, w, h).map_err(|e| fail(e.to_string()))?;
    let pending = Pending::new(&mut records, &mut heads, h).map_err(|e| fail(e.to_string()))?;
    let [r, g, b] = BACKGROUND;
    let mut renderer = Renderer::new(&mut workspace)
        .span_memory(coverage)
        .antialias(pending)
        .background(Colour::new(r, g, b));
    if integer {
        renderer = renderer.integer_vertices();
    }
    let stats = renderer
        .draw(&parsed, &view, &mut Nowhere)
        .map_err(|e| fail(e.to_string()))?;
    let peak = renderer.pending().map_or(0, |p| p.peak());
    if !stats.antialiased || peak >= peel_compiler::tools::raster::HOST_PENDING {
        return Err(fail(
            "the frame is not anti-aliased with every record a pool can address".into(),
        ));
    }
    Ok(peak as u64)
}
