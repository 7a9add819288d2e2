//! One configuration measured: its config block written, QEMU run twice (the counts must
//! agree), each frame compared with the host's, and its record of instructions, RAM, flash and
//! display bytes.

use std::path::Path;

use peel_target_kit::config::{Config, OrbitAngles, Variant, MAX_CAMERAS, WRITE_FRAMES};

use crate::accuracy::Truth;
use crate::plan::{Core, Setup, FOV_Y_DEG};
use crate::results::Record;
use crate::scenes::Compiled;
use crate::tools::{self, QemuRun};
use crate::{elf, mkdir, pixels, report, size_name, write, BACKGROUND};

/// Instructions per SysTick tick under `-icount shift=0` (25 MHz core clock, 1 ns per
/// instruction).
pub(crate) const INSTRUCTIONS_PER_TICK: u64 = 40;

/// One configuration: a scene, core, size and display path.
pub struct Measure<'a> {
    pub scene: &'a Compiled,
    pub core: Core,
    pub size: (u32, u32),
    pub setup: Setup,
    pub cameras: &'a [OrbitAngles],
    pub spans_per_row: u32,
    /// Scan memory nodes (scan order).
    pub scan_nodes: u32,
    /// Pending-pixel records (anti-aliased).
    pub pending_pixels: u32,
    /// Composite runs (the streamed build with transparency; 0: no composite memory).
    pub composite_runs: u32,
    /// The scanline z-buffer's active edges and clipped points (the most over the cameras).
    pub scanline_lists: (u32, u32),
    pub elf: std::path::PathBuf,
    pub timeout_s: u32,
}

/// What a configuration's frames are checked against.
pub struct Expected<'a> {
    /// The host's frames of the same code, when it runs on the host.
    pub frames: Option<&'a [Vec<u16>]>,
    /// How the robust errors are known.
    pub robust_errors: Robust,
    /// The reference (needed by [`Robust::FromFrames`]).
    pub truth: Option<&'a Truth>,
    /// Anti-aliased: the most pending pixels each frame holds at once on the host with records
    /// to spare (the same code, so the target's peak when none of its rows fell back).
    pub pending_peaks: Option<&'a [u64]>,
}

/// How a configuration's robust errors are known.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Robust {
    /// From the host's id images of the same code.
    Known(u64),
    /// Counted from the target's frames by coverage against the reference.
    FromFrames,
    /// Not measured: no ray-casting reference of the scene (the scene with objects, whose
    /// frames are the host's to the pixel all the same).
    Unmeasured,
    /// Not applicable: an anti-aliased pixel blends the triangles it sees, so it is no one
    /// triangle's (its accuracy is measured against a supersampled reference instead,
    /// BENCHMARKS.md "Anti-aliased frames").
    NotApplicable,
}

/// One QEMU run's report and frames.
struct RunResult {
    report: report::Report,
    frames: Vec<Vec<u16>>,
}

impl Measure<'_> {
    /// The asset the variant draws, and its length.
    fn asset(&self) -> (&Path, usize) {
        let variant = self.setup.variant;
        if variant == Variant::Gfx3d {
            (&self.scene.gfx3d, self.scene.gfx3d_bytes.len())
        } else if variant.draws_mesh() {
            (&self.scene.mesh, self.scene.mesh_bytes.len())
        } else {
            (&self.scene.peel, self.scene.peel_bytes.len())
        }
    }

    /// One run in `dir`, not measured: what the firmware reports (embedded-3dgfx's command
    /// count, to size its buffer).
    pub fn probe(&self, dir: &Path) -> Result<report::Report, String> {
        let config = self.config(dir)?;
        let (asset, _) = self.asset();
        Ok(self.run_once(&dir.join("probe"), asset, &config)?.report)
    }

    /// Write the configuration's block into `dir`; its path.
    fn config(&self, dir: &Path) -> Result<std::path::PathBuf, String> {
        mkdir(dir)?;
        let (width, height) = self.size;
        let (_, asset_len) = self.asset();
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
            active_edges: self.scanline_lists.0,
            clipped_points: self.scanline_lists.1,
            scan_nodes: self.scan_nodes,
            pending_pixels: self.pending_pixels,
            composite_runs: self.composite_runs,
        };
        let config_path = dir.join("config.bin");
        write(&config_path, &config.encode())?;
        Ok(config_path)
    }

    /// Run the configuration twice in `dir`; its record and the problems found.
    pub fn measure(
        &self,
        dir: &Path,
        expected: &Expected<'_>,
    ) -> Result<(Record, Vec<String>), String> {
        let config_path = self.config(dir)?;
        let (asset, asset_len) = self.asset();
        let (width, height) = self.size;
        let [r, g, b] = BACKGROUND;
        let runs = [1, 2]
            .map(|k| self.run_once(&dir.join(format!("run-{k}")), asset, &config_path))
            .into_iter()
            .collect::<Result<Vec<_>, _>>()?;
        let (first, second) = (&runs[0], &runs[1]);

        let name = format!(
            "{}{} {} {} {}",
            self.scene.spec.name,
            match self.scene.shading() {
                peel_target_runner::results::FLAT => String::new(),
                shading => format!(" {shading}"),
            } + if self.scene.transparent {
                " transparent"
            } else {
                ""
            },
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
        let mut differing = None;
        if let Some(frames) = expected.frames {
            if frames.len() != first.frames.len() {
                return Err(format!(
                    "{name}: {} reference frames for {} cameras",
                    frames.len(),
                    first.frames.len()
                ));
            }
            let mut total = 0;
            for (k, (got, want)) in first.frames.iter().zip(frames).enumerate() {
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
                total += d;
            }
            differing = Some(total);
        }
        let background = peel_runtime::display::Colour::new(r, g, b).to_rgb565();
        let robust_errors = match expected.robust_errors {
            Robust::Known(n) => Some(n),
            Robust::FromFrames => {
                let truth = expected
                    .truth
                    .ok_or_else(|| format!("{name}: robust errors without a reference"))?;
                Some(
                    (first.frames.iter().enumerate())
                        .map(|(k, frame)| truth.coverage_errors(k, frame, background))
                        .sum(),
                )
            }
            Robust::NotApplicable | Robust::Unmeasured => None,
        };
        // Anti-aliased: every frame must be, with no row fallen back to plain pixels. A row
        // falls back only when a pixel finds every record in use, so a peak below the records
        // means none did; a peak at the records is an exact fit when the host, with records
        // to spare, needs no more.
        let (mut pending_peak, mut pending_fallback) = (None, None);
        if self.setup.variant.antialiased() {
            let aa = &first.report.antialiasing;
            let host = expected.pending_peaks.unwrap_or(&[]);
            if aa.len() != self.cameras.len() || host.len() != self.cameras.len() {
                return Err(format!(
                    "{name}: {} anti-aliasing reports and {} host peaks for {} cameras",
                    aa.len(),
                    host.len(),
                    self.cameras.len()
                ));
            }
            let mut fell_back = false;
            for (k, (a, &spare)) in aa.iter().zip(host).enumerate() {
                let full = spare > a.pending_records || a.pending_peak != spare;
                if !a.antialiased || full {
                    fell_back = true;
                    problems.push(format!(
                        "{name}: camera {k}: {} (pending peak {} of {} records; the host's with \
                         records to spare: {spare})",
                        if a.antialiased {
                            "a row fell back to plain pixels"
                        } else {
                            "the frame is not anti-aliased"
                        },
                        a.pending_peak,
                        a.pending_records,
                    ));
                }
            }
            pending_peak = aa.iter().map(|a| a.pending_peak).max();
            pending_fallback = Some(fell_back);
        }
        // Transparency: every row of every frame composited exactly, none fallen back to
        // screen-door transparency (the host's frames, with runs to spare, have none either,
        // so a fallen row would show as differing pixels too).
        let composite = &first.report.composite;
        let (mut fallback_rows, mut composite_peak) = (None, None);
        if !composite.is_empty() {
            if composite.len() != self.cameras.len() {
                return Err(format!(
                    "{name}: {} composite reports for {} cameras",
                    composite.len(),
                    self.cameras.len()
                ));
            }
            for (k, c) in composite.iter().enumerate() {
                if c.fallback_rows > 0 {
                    problems.push(format!(
                        "{name}: camera {k}: {} rows fell back to screen-door transparency \
                         (composite peak {} of {} runs)",
                        c.fallback_rows, c.composite_peak, c.composite_runs
                    ));
                }
            }
            fallback_rows = Some(composite.iter().map(|c| c.fallback_rows).sum());
            composite_peak = composite.iter().map(|c| c.composite_peak).max();
        }
        if first.report.frames.iter().any(|f| f.fallback) {
            println!("   note: {name}: span memory ran out (finished back to front: same pixels)");
        }
        if differing == Some(0) {
            // Keep the logs; the frames (150 kB each) only when they are needed.
            for k in 0..self.cameras.len() {
                for run in ["run-1", "run-2"] {
                    let _ = std::fs::remove_file(dir.join(run).join(format!("frame-{k}.rgb565")));
                }
            }
        }

        let elf_bytes = std::fs::read(&self.elf)
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
            path: self.setup.path(),
            shading: self.scene.shading().into(),
            core: self.core.name().into(),
            width,
            height,
            triangles: self.scene.triangles,
            instructions: median(|f| f.ticks) * INSTRUCTIONS_PER_TICK,
            ram_bytes: ram,
            framebuffer_bytes: report.framebuffer,
            flash_bytes: flash,
            text_bytes: size(".text"),
            display_bytes: median(|f| f.display_bytes),
            display_writes: median(|f| f.display_writes),
            differing_pixels: differing,
            robust_errors,
            pending_peak,
            pending_records: self
                .setup
                .variant
                .antialiased()
                .then_some(u64::from(self.pending_pixels)),
            pending_fallback,
            deterministic,
            objects: self.scene.objects,
            transparent: self.scene.transparent,
            fallback_rows,
            composite_peak,
            composite_runs: (self.composite_runs > 0).then_some(u64::from(self.composite_runs)),
        };
        let dash = |n: Option<u64>| n.map_or_else(|| "-".to_string(), |d| d.to_string());
        println!(
            "   {name}: {} instructions, {} B RAM, {} differing pixels, {} robust errors",
            record.instructions,
            record.ram_bytes,
            dash(differing),
            dash(record.robust_errors)
        );
        Ok((record, problems))
    }

    /// One QEMU run in `dir`, checked to be of the right build, with its frames read.
    fn run_once(&self, dir: &Path, asset: &Path, config: &Path) -> Result<RunResult, String> {
        mkdir(dir)?;
        let output = tools::qemu(&QemuRun {
            core: self.core,
            elf: &self.elf,
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
