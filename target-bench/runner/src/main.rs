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
use peel_target_kit::config::{Config, OrbitAngles, Variant, MAX_CAMERAS, WRITE_FRAMES};
use peel_target_kit::mesh::Mesh;

use plan::{Args, Core, Setup, FOV_Y_DEG};
use results::Record;
use scenes::Compiled;
use tools::{QemuRun, Tools};

/// Background of every frame (`peel render --background`): not black, so that a pixel the
/// firmware leaves unpainted or paints in black shows.
const BACKGROUND: [u8; 3] = [24, 26, 32];
/// Instructions per SysTick tick under `-icount shift=0` (25 MHz core clock, 1 ns per
/// instruction).
const INSTRUCTIONS_PER_TICK: u64 = 40;

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
        let mut references: HashMap<(u32, u32), References> = HashMap::new();
        for core in cores {
            let sizes = if args.quick {
                &core.sizes()[..1]
            } else {
                core.sizes()
            };
            for &size in sizes {
                let refs = match references.entry(size) {
                    Entry::Occupied(e) => e.into_mut(),
                    Entry::Vacant(e) => {
                        let dir = out
                            .join("references")
                            .join(stem(&scene))
                            .join(size_name(size));
                        mkdir(&dir)?;
                        e.insert(References::new(
                            &tools, &scene, size, &cameras, &setups, &dir,
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
    /// Render what `setups` need into `dir`.
    fn new(
        tools: &Tools,
        scene: &Compiled,
        (width, height): (u32, u32),
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
                    tools.peel(&[
                        "render".as_ref(),
                        scene.peel.as_os_str(),
                        format!("--orbit={},{}", c.azimuth_deg, c.elevation_deg).as_ref(),
                        format!("--size={width}x{height}").as_ref(),
                        format!("--order={order}").as_ref(),
                        format!("--background={r},{g},{b}").as_ref(),
                        "-o".as_ref(),
                        png.as_os_str(),
                    ])?;
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

/// One configuration: a scene, core, size and display path.
struct Measure<'a> {
    scene: &'a Compiled,
    core: Core,
    size: (u32, u32),
    setup: Setup,
    cameras: &'a [OrbitAngles],
    spans_per_row: u32,
    elf: &'a Path,
    timeout_s: u32,
}

/// One QEMU run's report and frames.
struct RunResult {
    report: report::Report,
    frames: Vec<Vec<u16>>,
}

impl Measure<'_> {
    /// Run the configuration twice in `dir`; its record and the problems found.
    fn measure(&self, dir: &Path, expected: &[Vec<u16>]) -> Result<(Record, Vec<String>), String> {
        mkdir(dir)?;
        let (width, height) = self.size;
        let zbuffer = self.setup.variant == Variant::Zbuffer;
        let (asset, asset_len) = if zbuffer {
            (&self.scene.mesh, self.scene.mesh_bytes.len())
        } else {
            (&self.scene.peel, self.scene.peel_bytes.len())
        };
        let mut cameras = [OrbitAngles::default(); MAX_CAMERAS];
        cameras[..self.cameras.len()].copy_from_slice(self.cameras);
        let [r, g, b] = BACKGROUND;
        let config = Config {
            variant: self.setup.variant,
            width,
            height,
            band_rows: self.setup.band_rows,
            spans_per_row: self.spans_per_row,
            asset_len: u32::try_from(asset_len).map_err(|_| "asset too large".to_string())?,
            background: u32::from_be_bytes([0, r, g, b]),
            flags: WRITE_FRAMES,
            fov_y_deg: FOV_Y_DEG,
            camera_count: self.cameras.len() as u32,
            cameras,
        };
        let config_path = dir.join("config.bin");
        write(&config_path, &config.encode())?;
        let runs = [1, 2]
            .map(|k| self.run_once(&dir.join(format!("run-{k}")), asset, &config_path))
            .into_iter()
            .collect::<Result<Vec<_>, _>>()?;
        let (first, second) = (&runs[0], &runs[1]);

        let name = format!(
            "{} {} {} {}",
            self.scene.spec.name,
            self.core.name(),
            size_name(self.size),
            self.setup.label()
        );
        let mut problems = Vec::new();
        let ticks = |r: &RunResult| r.report.frames.iter().map(|f| f.ticks).collect::<Vec<_>>();
        let deterministic = ticks(first) == ticks(second) && first.frames == second.frames;
        if !deterministic {
            problems.push(format!(
                "{name}: two runs differ (ticks {:?} and {:?}{})",
                ticks(first),
                ticks(second),
                if first.frames == second.frames {
                    ""
                } else {
                    ", and their pixels"
                }
            ));
        }
        if expected.len() != first.frames.len() {
            return Err(format!(
                "{name}: {} reference frames for {} cameras",
                expected.len(),
                first.frames.len()
            ));
        }
        let mut differing = 0;
        for (k, (got, want)) in first.frames.iter().zip(expected).enumerate() {
            let d = pixels::differing(got, want);
            if d > 0 {
                problems.push(format!(
                    "{name}: camera {k} ({} deg): {d} pixels differ from the host's (see {})",
                    self.cameras[k].azimuth_deg,
                    dir.join("run-1")
                        .join(format!("frame-{k}.rgb565"))
                        .display()
                ));
            }
            differing += d;
        }
        if first.report.frames.iter().any(|f| f.fallback) {
            println!("   note: {name}: span memory ran out (finished back to front: same pixels)");
        }
        if differing == 0 {
            // Keep the logs; the frames (150 kB each) only when they are needed.
            for k in 0..self.cameras.len() {
                for run in ["run-1", "run-2"] {
                    let _ = std::fs::remove_file(dir.join(run).join(format!("frame-{k}.rgb565")));
                }
            }
        }

        let elf_bytes = std::fs::read(self.elf)
            .map_err(|e| format!("{}: cannot read: {e}", self.elf.display()))?;
        let sections =
            elf::sections(&elf_bytes).map_err(|e| format!("{}: {e}", self.elf.display()))?;
        let size = |name| elf::size(&sections, name);
        let statics = size(".data") + size(".bss") + size(".uninit");
        let report = &first.report;
        // The pool is all in the statics; only what the run took from it counts.
        let ram = statics.checked_sub(report.pool_capacity).ok_or_else(|| {
            format!(
                "{}: statics smaller than the pool reported",
                self.elf.display()
            )
        })? + report.pool_used
            + report.stack_peak;
        let flash = size(".vector_table")
            + size(".text")
            + size(".rodata")
            + size(".data")
            + asset_len as u64;
        let median = |f: fn(&report::Frame) -> u64| {
            report::median(&report.frames.iter().map(f).collect::<Vec<_>>())
        };
        let record = Record {
            scene: self.scene.spec.name.clone(),
            method: self.setup.variant.method().into(),
            core: self.core.name().into(),
            width,
            height,
            triangles: self.scene.triangles,
            instructions: median(|f| f.ticks) * INSTRUCTIONS_PER_TICK,
            ram_bytes: ram,
            framebuffer_bytes: report.framebuffer,
            flash_bytes: flash,
            display_bytes: median(|f| f.display_bytes),
            differing_pixels: differing,
            deterministic,
        };
        println!(
            "   {name}: {} instructions, {} B RAM, {} differing pixels",
            record.instructions, record.ram_bytes, record.differing_pixels
        );
        Ok((record, problems))
    }

    /// One QEMU run in `dir`, checked to be of the right build, with its frames read.
    fn run_once(&self, dir: &Path, asset: &Path, config: &Path) -> Result<RunResult, String> {
        mkdir(dir)?;
        let output = tools::qemu(&QemuRun {
            core: self.core,
            elf: self.elf,
            asset,
            config,
            dir,
            timeout_s: self.timeout_s,
        })?;
        let log = dir.join("qemu.out");
        let report = report::parse(&output).map_err(|e| format!("{}: {e}", log.display()))?;
        if report.variant != self.setup.variant.name() || report.target != self.core.triple() {
            return Err(format!(
                "{}: a build of {} for {} answered, not {} for {}",
                log.display(),
                report.variant,
                report.target,
                self.setup.variant.name(),
                self.core.triple()
            ));
        }
        if report.frames.len() != self.cameras.len() {
            return Err(format!(
                "{}: {} frames for {} cameras",
                log.display(),
                report.frames.len(),
                self.cameras.len()
            ));
        }
        let pixels = self.size.0 as usize * self.size.1 as usize;
        let frames = (0..self.cameras.len())
            .map(|k| pixels::frame_file(&dir.join(format!("frame-{k}.rgb565")), pixels))
            .collect::<Result<_, _>>()?;
        Ok(RunResult { report, frames })
    }
}
