//! The transparent scene (issue "Transparent surfaces in exact order") and its baselines:
//! `glass-box`, the teapot of the shared models (or its generated stand-in) inside an
//! axis-aligned box of light-tinted glass a little larger than its bounds (12 triangles, `Kd`
//! a light tint, `d` [`GLASS_OPACITY`]; the teapot keeps the loader's default material,
//! opaque), written as OBJ and MTL by [`write_glass_box`]. It is compiled as it is (records
//! with `"transparent": true`) and from the same OBJ with the box opaque (`d 1`: the opaque
//! baseline, the same scene name, `transparent` absent), with the benchmark's options, and
//! drawn streamed at 320x240 on both cores by the build with transparency (`--features
//! ftb-stream,transparency`), the baseline by the same build, so the ratio is transparency's
//! alone. The teapot without a box is drawn by that build too (no record: the plain build's
//! teapot record is the benchmark's): front to back, the opaque box's front faces hide the
//! teapot, so the opaque baseline is cheaper than the teapot alone, and the summary gives the
//! ratio against both.
//!
//! Peel's frames are checked pixel for pixel against `peel render` (front to back, with
//! composite memory to spare; integer vertices on the Cortex-M0+), as every scene's are.
//!
//! Memory: the builder's span memory (`peel_compiler::spans::spans_per_row`) draws a
//! transparent file without composite memory, so it measures its bound; the glass box gets
//! instead the fewest intervals per row with which no camera's frame, composited, runs out
//! ([`spans_with_composite`]). Then for each core the host draws each camera's frame with
//! those intervals and every run a memory can address ([`composite_peak`], the same runtime
//! code and vertices as the firmware), then finds the fewest runs with which no row of any
//! camera's frame falls back ([`runs_needed`]: a little more than that peak, as a span checks
//! for the records it may need before it changes a row), which the firmware gets; the firmware reports each frame's peak and fallen rows, and
//! the records hold the peak (the most over the cameras), the runs given and the fallen rows
//! (**summed** over the cameras; the run fails on any). The composite memory is taken from
//! the firmware's pool and counted in the RAM figure with the rest.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use peel_runtime::display::Colour;
use peel_target_kit::config::{OrbitAngles, Variant};
use peel_target_runner::results::{Record, TRANSPARENCY_GOALS};

use crate::accuracy::Truth;
use crate::measure::Measure;
use crate::plan::{Core, Setup, FOV_Y_DEG};
use crate::scenes::{self, Compiled, SceneSpec};
use crate::textured::instructions;
use crate::tools::Tools;
use crate::{mkdir, size_name, stem, write, References, BACKGROUND};

/// The size the transparent scene is drawn at.
pub const SIZE: (u32, u32) = (320, 240);

/// The scene's name in the records.
pub const NAME: &str = "glass-box";

/// The glass's opacity (the MTL's `d`).
pub const GLASS_OPACITY: f64 = 0.4;

/// The glass's colour (the MTL's `Kd`): a light blue tint.
const GLASS_KD: [f64; 3] = [0.8, 0.9, 1.0];

/// The box's margin around the teapot's bounds, as a fraction of their largest side.
const MARGIN: f64 = 0.05;

/// What the transparent runs need from the benchmark.
pub struct Transparent<'a> {
    pub tools: &'a Tools,
    /// The shared models' folder (the teapot).
    pub models: &'a Path,
    pub firmware_dir: &'a Path,
    pub cameras: &'a [OrbitAngles],
    pub scene_dir: &'a Path,
    pub runs_dir: &'a Path,
    /// Where the host's frames go.
    pub references_dir: &'a Path,
    pub timeout_s: u32,
}

/// The records of the transparent scene and its opaque baseline, the problems found, and the
/// comparison as markdown.
pub struct Outcome {
    pub records: Vec<Record>,
    pub problems: Vec<String>,
    pub summary: String,
}

/// One measured configuration: its record and its instructions per camera.
struct Run {
    record: Record,
    counts: Vec<u64>,
}

/// The three scenes drawn: the glass box, the same box opaque, the teapot alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Kind {
    Glass,
    Opaque,
    Teapot,
}

impl Kind {
    fn label(self) -> &'static str {
        match self {
            Kind::Glass => "",
            Kind::Opaque => "-opaque",
            Kind::Teapot => "-teapot-alone",
        }
    }
}

impl Transparent<'_> {
    /// Build, compile, size the composite memory, measure on both cores and compare.
    pub fn run(&self) -> Result<Outcome, String> {
        let setup = Setup {
            variant: Variant::FtbStream,
            band_rows: 0,
        };
        let mut firmware = HashMap::new();
        for core in [Core::M4f, Core::M0Plus] {
            println!(
                "== build: firmware ftb-stream,transparency for {}",
                core.name()
            );
            let elf = self
                .tools
                .build_transparency_firmware(core, self.firmware_dir)?;
            if core == Core::M0Plus {
                crate::tools::check_armv6m(&elf)?;
            }
            firmware.insert(core, elf);
        }
        println!("== scene {NAME} (transparent, opaque, the teapot alone)");
        let source = self.scene_dir.join(format!("{NAME}-source"));
        mkdir(&source)?;
        let (teapot, _) = scenes::model("teapot", self.models, &source)?;
        let mut compiled = Vec::new();
        for kind in [Kind::Glass, Kind::Opaque, Kind::Teapot] {
            let obj = match kind {
                Kind::Glass => write_glass_box(&teapot, &source, NAME, GLASS_OPACITY)?,
                Kind::Opaque => write_glass_box(&teapot, &source, &format!("{NAME}-opaque"), 1.0)?,
                Kind::Teapot => teapot.clone(),
            };
            let spec = SceneSpec {
                name: if kind == Kind::Teapot {
                    "teapot".into()
                } else {
                    NAME.into()
                },
                obj,
            };
            let dir = self.scene_dir.join(format!("{NAME}{}", kind.label()));
            mkdir(&dir)?;
            let mut scene = scenes::compile(self.tools, &spec, false, None, &dir)?;
            let parsed = peel_runtime::read::Scene::parse(&scene.peel_bytes)
                .map_err(|e| format!("{}: {e}", scene.peel.display()))?;
            if parsed.header().max_depth as usize > peel_target_kit::STACK {
                return Err(format!(
                    "{}: its tree is {} deep and the firmware's stack holds {}",
                    scene.peel.display(),
                    parsed.header().max_depth,
                    peel_target_kit::STACK
                ));
            }
            let has_transparency = parsed.has_transparency();
            scene.transparent = kind == Kind::Glass;
            compiled.push((kind, scene, has_transparency));
        }
        let mut problems = Vec::new();
        for (kind, scene, transparent) in &compiled {
            if *transparent != (*kind == Kind::Glass) {
                problems.push(format!(
                    "{}: compiled {}, expected {} (does the compiler read the MTL's `d`, and \
                     the runtime's Scene give its opacities?)",
                    scene.peel.display(),
                    if *transparent {
                        "transparent"
                    } else {
                        "opaque"
                    },
                    if *kind == Kind::Glass {
                        "transparent"
                    } else {
                        "opaque"
                    },
                ));
            }
        }
        let (mut records, mut runs) = (Vec::new(), HashMap::new());
        for (kind, scene, _) in &compiled {
            let truth = Rc::new(Truth::new(
                &scene.spec.obj,
                &scenes::options(false, None)?,
                self.cameras,
                SIZE,
            )?);
            for core in [Core::M4f, Core::M0Plus] {
                let integer = core.integer_vertices();
                let mut folder = size_name(SIZE);
                if integer {
                    folder.push_str("-integer");
                }
                let name = format!("{}{}", stem(scene), kind.label());
                let refs_dir = self.references_dir.join(&name).join(folder);
                mkdir(&refs_dir)?;
                let refs = References::new(
                    self.tools,
                    scene,
                    SIZE,
                    integer,
                    Rc::clone(&truth),
                    self.cameras,
                    &[setup],
                    &refs_dir,
                )?;
                // The builder's span memory (`spans::spans_per_row`) is measured without
                // composite memory, which a transparent file's frame then needs all of: the
                // glass box gets the fewest intervals per row with which no camera's frame,
                // drawn with its composite runs, runs out.
                let spans_per_row = if *kind == Kind::Glass {
                    spans_with_composite(scene, self.cameras, SIZE, integer)?
                } else {
                    refs.spans_per_row
                };
                // The most runs a frame of the orbit holds, with every run there is.
                let peaks = (self.cameras.iter())
                    .map(|&c| composite_peak(scene, c, SIZE, integer, spans_per_row))
                    .collect::<Result<Vec<u64>, String>>()?;
                let peak = peaks.iter().copied().max().unwrap_or(0);
                println!(
                    "   {name} {}: composite peak on the host {peak} runs (per camera {peaks:?}); \
                     span memory {} intervals per row (the builder's {})",
                    core.name(),
                    spans_per_row,
                    refs.spans_per_row
                );
                // The transparent scene gets the orbit's need (at least one run, so that its
                // build always reports); the opaque ones none, as they need none.
                let composite_runs = match kind {
                    Kind::Glass => {
                        let n =
                            runs_needed(scene, self.cameras, SIZE, integer, spans_per_row, peak)?;
                        println!(
                            "   {name} {}: {n} composite runs, none falling back",
                            core.name()
                        );
                        n.max(1) as u32
                    }
                    _ if peak > 0 => {
                        return Err(format!("{name}: an opaque scene holds {peak} runs"))
                    }
                    _ => 0,
                };
                let measure = Measure {
                    scene,
                    core,
                    size: SIZE,
                    setup,
                    cameras: self.cameras,
                    spans_per_row,
                    scan_nodes: 0,
                    pending_pixels: 0,
                    composite_runs,
                    scanline_lists: (0, 0),
                    elf: firmware[&core].clone(),
                    timeout_s: self.timeout_s,
                };
                let dir = (self.runs_dir.join(&name)).join(format!(
                    "{}-{}-{}-transparency",
                    core.name(),
                    size_name(SIZE),
                    setup.label()
                ));
                let (record, found) = measure.measure(&dir, &refs.expected(setup.variant))?;
                problems.extend(found);
                let counts = instructions(&dir)?;
                if *kind != Kind::Teapot {
                    records.push(record.clone());
                }
                runs.insert((*kind, core), Run { record, counts });
            }
        }
        Ok(Outcome {
            records,
            problems,
            summary: compare(&runs),
        })
    }
}

/// A streamed frame of `scene` from the orbit camera `angles` at `size` with `spans` span-memory
/// intervals per row and every composite run a memory can address, drawn as the firmware draws
/// it (`integer` vertices or not): its stats and composite peak.
fn composited_frame(
    scene: &Compiled,
    angles: OrbitAngles,
    (w, h): (u32, u32),
    integer: bool,
    spans: usize,
    runs: usize,
) -> Result<(peel_runtime::render::FrameStats, usize), String> {
    use peel_runtime::composite::{Composite, CompositeRun, MAX_RUNS};
    use peel_runtime::coverage::Coverage;
    use peel_runtime::display::SpanSink;
    use peel_runtime::render::{Renderer, Workspace};
    struct Nowhere;
    impl SpanSink for Nowhere {
        fn span(&mut self, _: u32, _: u32, _: u32, _: Colour) {}
    }
    let fail = |e: String| format!("{}: composite runs: {e}", scene.peel.display());
    let parsed =
        peel_runtime::read::Scene::parse(&scene.peel_bytes).map_err(|e| fail(e.to_string()))?;
    let view = peel_target_kit::orbit_view(&parsed.header(), angles, FOV_Y_DEG, w, h)
        .map_err(|e| fail(e.to_string()))?;
    let rows = h as usize;
    let mut workspace: Box<Workspace<{ 1 << 14 }, 64>> = Box::default();
    let mut intervals = vec![(0u16, 0u16); spans * rows];
    let mut counts = vec![0u16; rows];
    let mut runs = vec![CompositeRun::default(); runs.min(MAX_RUNS)];
    let mut heads = vec![0u16; rows];
    let coverage =
        Coverage::new(&mut intervals, &mut counts, w, h).map_err(|e| fail(e.to_string()))?;
    let composite = Composite::new(&mut runs, &mut heads, h).map_err(|e| fail(e.to_string()))?;
    let [r, g, b] = BACKGROUND;
    let mut renderer = Renderer::new(&mut workspace)
        .span_memory(coverage)
        .composite_memory(composite)
        .background(Colour::new(r, g, b));
    if integer {
        renderer = renderer.integer_vertices();
    }
    let stats = renderer
        .draw(&parsed, &view, &mut Nowhere)
        .map_err(|e| fail(e.to_string()))?;
    let peak = renderer.composite().map_or(0, |c| c.peak());
    Ok((stats, peak))
}

/// The fewest span-memory intervals per row (at least 1, at most half the width) with which
/// no frame of `cameras` of `scene` at `size`, with composite runs to spare, runs out.
fn spans_with_composite(
    scene: &Compiled,
    cameras: &[OrbitAngles],
    size: (u32, u32),
    integer: bool,
) -> Result<u32, String> {
    let enough = |spans: usize| -> Result<bool, String> {
        for &c in cameras {
            let all = peel_runtime::composite::MAX_RUNS;
            if composited_frame(scene, c, size, integer, spans, all)?
                .0
                .fallback
            {
                return Ok(false);
            }
        }
        Ok(true)
    };
    let (mut lo, mut hi) = (1, (size.0 as usize).div_ceil(2));
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if enough(mid)? {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    Ok(lo as u32)
}

/// The most composite runs the streamed frame of `scene` from the orbit camera `angles` at
/// `size` (the firmware's view) holds at once with every run a memory can address and the
/// firmware's `spans` intervals per row, drawn as the firmware draws it (`integer` vertices or
/// not; the peak depends on the span memory too):
/// with at least as many, no row of the frame falls back. 0 for an opaque scene.
pub fn composite_peak(
    scene: &Compiled,
    angles: OrbitAngles,
    (w, h): (u32, u32),
    integer: bool,
    spans: u32,
) -> Result<u64, String> {
    let all = peel_runtime::composite::MAX_RUNS;
    let (stats, peak) = composited_frame(scene, angles, (w, h), integer, spans as usize, all)?;
    if stats.fallback_rows > 0 || peak >= peel_runtime::composite::MAX_RUNS {
        return Err(format!(
            "{}: {} rows fall back with every run a memory can address",
            scene.peel.display(),
            stats.fallback_rows
        ));
    }
    Ok(peak as u64)
}

/// The fewest composite runs (at least `peak`, the most the frames hold at once) with which
/// no row of any frame of `cameras` of `scene` at `size` with `spans` intervals per row falls
/// back: a span checks that the records it may need are free before it changes a row, so the
/// memory needs some runs beyond the peak.
fn runs_needed(
    scene: &Compiled,
    cameras: &[OrbitAngles],
    size: (u32, u32),
    integer: bool,
    spans: u32,
    peak: u64,
) -> Result<u64, String> {
    let enough = |runs: u64| -> Result<bool, String> {
        for &c in cameras {
            let (stats, _) =
                composited_frame(scene, c, size, integer, spans as usize, runs as usize)?;
            if stats.fallback_rows > 0 {
                return Ok(false);
            }
        }
        Ok(true)
    };
    let (mut lo, mut hi) = (peak, peak.max(1) * 2);
    while !enough(hi)? {
        if hi >= peel_runtime::composite::MAX_RUNS as u64 {
            return Err(format!(
                "{}: rows fall back with every run a memory can address",
                scene.peel.display()
            ));
        }
        (lo, hi) = (hi, (hi * 2).min(peel_runtime::composite::MAX_RUNS as u64));
    }
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if enough(mid)? {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    Ok(lo)
}

/// The comparison on each core: each camera's instructions of the glass box, the opaque box
/// and the teapot alone, the ratios, and the medians' ratios against [`TRANSPARENCY_GOALS`];
/// RAM, composite memory and fallen rows.
fn compare(runs: &HashMap<(Kind, Core), Run>) -> String {
    let (ratio_goal, ram_goal) = TRANSPARENCY_GOALS;
    let met = |ok: bool| if ok { "met" } else { "NOT met" };
    let mut s = format!(
        "\n## Transparent surfaces: the glass box against the opaque box\n\n\
         Instructions per frame of each camera, {}x{}, streamed, the build with transparency \
         (`ftb-stream,transparency`); the teapot alone by the same build.\n",
        SIZE.0, SIZE.1
    );
    for core in [Core::M4f, Core::M0Plus] {
        let get = |kind| runs.get(&(kind, core));
        let (Some(g), Some(o), Some(t)) = (get(Kind::Glass), get(Kind::Opaque), get(Kind::Teapot))
        else {
            continue;
        };
        let _ = writeln!(
            s,
            "\n### {NAME}, {}\n\n| camera | glass box | opaque box | teapot alone | x opaque | x teapot |\n\
             |--:|--:|--:|--:|--:|--:|",
            core.name()
        );
        for (k, ((&a, &b), &c)) in g.counts.iter().zip(&o.counts).zip(&t.counts).enumerate() {
            let _ = writeln!(
                s,
                "| {k} | {a} | {b} | {c} | {:.3} | {:.3} |",
                a as f64 / b.max(1) as f64,
                a as f64 / c.max(1) as f64
            );
        }
        let (gi, oi, ti) = (
            g.record.instructions,
            o.record.instructions,
            t.record.instructions,
        );
        let x = gi as f64 / oi.max(1) as f64;
        let xt = gi as f64 / ti.max(1) as f64;
        let fallen = g.record.fallback_rows;
        let dash = |n: Option<u64>| n.map_or_else(|| "-".to_string(), |n| n.to_string());
        let _ =
            writeln!(
            s,
            "\nMedians: glass box {gi}, opaque box {oi}, teapot alone {ti}; ratio {x:.3} against \
             the opaque box (goal at most {ratio_goal}: {}), {xt:.3} against the teapot alone. \
             RAM {} B (goal at most {ram_goal}: {}), opaque box {} B, teapot alone {} B; \
             composite peak {} of {} runs ({} B); rows fallen back {} (summed over the \
             cameras; goal none: {}); differing pixels {}, {} and {}.",
            met(x <= ratio_goal),
            g.record.ram_bytes,
            met(g.record.ram_bytes <= ram_goal),
            o.record.ram_bytes,
            t.record.ram_bytes,
            dash(g.record.composite_peak),
            dash(g.record.composite_runs),
            g.record.composite_runs.map_or(0, |n| n as usize * peel_runtime::composite::RUN_BYTES),
            dash(fallen),
            met(fallen == Some(0)),
            dash(g.record.differing_pixels),
            dash(o.record.differing_pixels),
            dash(t.record.differing_pixels),
        );
        println!(
            "   {NAME} {}: glass / opaque box {x:.3}, glass / teapot alone {xt:.3}, RAM {} B",
            core.name(),
            g.record.ram_bytes
        );
    }
    s
}

/// The OBJ file `STEM.obj` in `dir` of the teapot `teapot` (its lines as they are: its
/// vertices and faces, the loader's default material) inside an axis-aligned box
/// ([`MARGIN`] larger than its bounds on every side, 12 triangles facing out) of the material
/// `glass` (`Kd` [`GLASS_KD`], `d` `opacity`), with `STEM.mtl`. The OBJ's path.
pub fn write_glass_box(
    teapot: &Path,
    dir: &Path,
    stem: &str,
    opacity: f64,
) -> Result<PathBuf, String> {
    let text = std::fs::read_to_string(teapot)
        .map_err(|e| format!("{}: cannot read: {e}", teapot.display()))?;
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    let mut vertices = 0usize;
    for line in text.lines() {
        let mut words = line.split_whitespace();
        if words.next() != Some("v") {
            continue;
        }
        vertices += 1;
        for (k, w) in words.take(3).enumerate() {
            let c: f64 = w
                .parse()
                .map_err(|e| format!("{}: {line:?}: {e}", teapot.display()))?;
            lo[k] = lo[k].min(c);
            hi[k] = hi[k].max(c);
        }
    }
    if vertices == 0 {
        return Err(format!("{}: no vertices", teapot.display()));
    }
    let side = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    let margin = side * MARGIN;
    let (lo, hi) = (lo.map(|c| c - margin), hi.map(|c| c + margin));
    let mut obj = format!(
        "# The teapot ({}) in a box of glass (d {opacity}), written by the target benchmark.\n",
        teapot.file_name().unwrap_or_default().to_string_lossy()
    );
    let _ = writeln!(obj, "mtllib {stem}.mtl");
    for line in text.lines() {
        // The teapot's own material lines, if any, would look for its MTL beside this file.
        if !line.trim_start().starts_with("mtllib") {
            obj.push_str(line);
            obj.push('\n');
        }
    }
    // Corner k: x from bit 0, y from bit 1, z from bit 2.
    for k in 0..8 {
        let pick = |axis: usize| {
            if k >> axis & 1 == 0 {
                lo[axis]
            } else {
                hi[axis]
            }
        };
        let _ = writeln!(obj, "v {} {} {}", pick(0), pick(1), pick(2));
    }
    obj.push_str("o glass\nusemtl glass\n");
    // Each face's corners counter-clockwise seen from outside.
    const QUADS: [[usize; 4]; 6] = [
        [0, 4, 6, 2], // x low
        [1, 3, 7, 5], // x high
        [0, 1, 5, 4], // y low
        [2, 6, 7, 3], // y high
        [0, 2, 3, 1], // z low
        [4, 5, 7, 6], // z high
    ];
    for [a, b, c, d] in QUADS {
        let v = |k: usize| vertices + k + 1;
        let _ = writeln!(obj, "f {} {} {}", v(a), v(b), v(c));
        let _ = writeln!(obj, "f {} {} {}", v(a), v(c), v(d));
    }
    let [r, g, b] = GLASS_KD;
    let mtl = format!(
        "# The glass of {stem}.obj, written by the target benchmark.\nnewmtl glass\nKd {r} {g} \
         {b}\nd {opacity}\n"
    );
    write(&dir.join(format!("{stem}.mtl")), mtl.as_bytes())?;
    let path = dir.join(format!("{stem}.obj"));
    write(&path, obj.as_bytes())?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use peel_compiler::load::load_obj;

    #[test]
    fn the_glass_box_holds_the_teapot_and_faces_out() {
        let dir = std::env::temp_dir().join(format!("peel-target-glass-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let teapot = dir.join("pot.obj");
        std::fs::write(&teapot, "v 0 0 0\nv 1 0 0\nv 0 2 0\nf 1 2 3\n").unwrap();
        let obj = write_glass_box(&teapot, &dir, "glass", 0.4).unwrap();
        let mesh = load_obj(&obj).unwrap();
        assert_eq!(mesh.triangles.len(), 13);
        assert_eq!(
            mesh.triangles[0].colour,
            peel_compiler::load::DEFAULT_COLOUR
        );
        let centre = glam::DVec3::new(0.5, 1.0, 0.0);
        for t in &mesh.triangles[1..] {
            let [a, b, c] = t.vertices;
            let normal = (b - a).cross(c - a);
            assert!(normal.dot(a - centre) > 0.0, "{t:?} faces in");
            // The margin: 5% of the largest side (2) beyond the bounds.
            assert!(t
                .vertices
                .iter()
                .all(|p| p.y >= -0.1 - 1e-12 && p.y <= 2.1 + 1e-12));
            assert_eq!(t.colour, mesh.triangles[1].colour);
            assert_ne!(t.colour, peel_compiler::load::DEFAULT_COLOUR);
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
