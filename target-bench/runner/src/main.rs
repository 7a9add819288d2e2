//! The on-target benchmark (`bash .ci/target [--quick]`, BENCHMARKS.md "On the target"): Peel's
//! renderer and the z-buffer baseline as Cortex-M4F and Cortex-M0+ firmware in QEMU, with
//! deterministic instruction counts, RAM and flash, bytes sent to a mock SPI display, and
//! every pixel checked against the host.
//!
//! Steps: build `peel` and one firmware per variant and core; compile the scenes with `peel
//! compile` and export the z-buffer's meshes; for each scene, core, size and variant write a
//! config block, run QEMU twice (instruction counts must agree), compare each frame the panel
//! received with the host's (`peel render` in the same order, or the same z-buffer code run
//! on the host) and write `target/peel-target/results.json` and `results.md`. Any differing
//! pixel or count fails the run (after writing the results), as does any failed step.

mod elf;
mod measure;
mod pixels;
mod plan;
mod report;
mod results;
mod scenes;
mod tools;

use std::collections::hash_map::{Entry, HashMap};
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use peel_runtime::target::Colour;
use peel_target_kit::config::{OrbitAngles, Variant};
use peel_target_kit::mesh::Mesh;

use measure::Measure;
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
    let mut variants: Vec<Variant> = setups.iter().map(|s| s.variant).collect();
    variants.dedup();
    let cores = [Core::M4f, Core::M0Plus];
    let mut firmware = HashMap::new();
    for core in cores {
        for &variant in &variants {
            println!("== build: firmware {} for {}", variant.name(), core.name());
            let elf = tools.build_firmware(core, variant, &firmware_dir)?;
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
    for spec in &scenes {
        println!("== scene {}", spec.name);
        let scene = scenes::compile(&tools, spec, &scene_dir)?;
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
                        e.insert(References::new(
                            &tools, &scene, size, integer, &cameras, &setups, &dir,
                        )?)
                    }
                };
                for setup in &setups {
                    let run = Measure {
                        scene: &scene,
                        core,
                        size,
                        setup: *setup,
                        cameras: &cameras,
                        spans_per_row: refs.spans_per_row,
                        elf: &firmware[&(core, setup.variant)],
                        timeout_s: if args.quick { 120 } else { 900 },
                    };
                    let dir = runs_dir.join(stem(&scene)).join(format!(
                        "{}-{}-{}",
                        core.name(),
                        size_name(size),
                        setup.label()
                    ));
                    let (record, found) = run.measure(&dir, refs.for_variant(setup.variant))?;
                    records.push(record);
                    problems.extend(found);
                }
            }
        }
    }
    let json = results::json(&records)?;
    write(&out.join("results.json"), json.as_bytes())?;
    write(
        &out.join("results.md"),
        (results::markdown(&records)
            + &skipped
                .iter()
                .map(|n| format!("\n{n}\n"))
                .collect::<String>())
            .as_bytes(),
    )?;
    println!("\n{}", results::markdown(&records));
    println!(
        "written: {} and results.md",
        out.join("results.json").display()
    );
    Ok(problems)
}

/// A scene's name for paths.
fn stem(scene: &Compiled) -> String {
    scene.spec.name.replace(" (generated)", "-generated")
}

fn size_name((w, h): (u32, u32)) -> String {
    format!("{w}x{h}")
}

/// The host's frames of one scene and size, for each camera: `peel render` in each order,
/// and the z-buffer run on the host; and the span memory the firmware gets.
struct References {
    front_to_back: Vec<Vec<u16>>,
    back_to_front: Vec<Vec<u16>>,
    zbuffer: Vec<Vec<u16>>,
    spans_per_row: u32,
}

impl References {
    /// Render what `setups` need into `dir` (Peel's frames with integer vertices or not).
    #[allow(clippy::too_many_arguments)]
    fn new(
        tools: &Tools,
        scene: &Compiled,
        (width, height): (u32, u32),
        integer: bool,
        cameras: &[OrbitAngles],
        setups: &[Setup],
        dir: &Path,
    ) -> Result<References, String> {
        let needs = |method: &str| setups.iter().any(|s| s.variant.method() == method);
        let peel = |order: &str| -> Result<Vec<Vec<u16>>, String> {
            if !needs(&format!("peel-{order}")) {
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
        let zbuffer = if needs(Variant::Zbuffer.method()) {
            let mesh = Mesh::parse(&scene.mesh_bytes)
                .map_err(|e| format!("{}: {e}", scene.mesh.display()))?;
            let n = width as usize * height as usize;
            let background = Colour::new(BACKGROUND[0], BACKGROUND[1], BACKGROUND[2]).to_rgb565();
            cameras
                .iter()
                .map(|&c| {
                    let view =
                        peel_target_kit::orbit_view(&mesh.header(), c, FOV_Y_DEG, width, height)
                            .map_err(|e| e.to_string())?;
                    let (mut colour, mut depth) = (vec![0u16; n], vec![0u16; n]);
                    peel_target_kit::zbuffer::draw(
                        &mesh,
                        &view,
                        background,
                        &mut colour,
                        &mut depth,
                    )
                    .map_err(|e| format!("{}: host z-buffer: {e}", scene.mesh.display()))?;
                    Ok(colour)
                })
                .collect::<Result<_, String>>()?
        } else {
            Vec::new()
        };
        let spans_per_row =
            scenes::spans_per_row(&scene.peel_bytes, cameras, FOV_Y_DEG, (width, height))
                .map_err(|e| format!("{}: {e}", scene.peel.display()))?;
        Ok(References {
            front_to_back: peel("front-to-back")?,
            back_to_front: peel("back-to-front")?,
            zbuffer,
            spans_per_row,
        })
    }

    /// The frames a variant's pixels must equal.
    fn for_variant(&self, variant: Variant) -> &[Vec<u16>] {
        match variant.method() {
            "peel-front-to-back" => &self.front_to_back,
            "peel-back-to-front" => &self.back_to_front,
            _ => &self.zbuffer,
        }
    }
}
