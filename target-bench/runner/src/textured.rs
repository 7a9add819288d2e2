//! The textured scenes (issue 47) and their untextured baselines: `textured-box` (the fixture
//! `fixtures/textured-box/`, a die: six quads, each its own 32 x 32 picture) and
//! `textured-mesh` (the UV sphere of [`SPHERE`] under a 64 x 64 checkerboard,
//! `tools::scenes::textured_sphere`, written as OBJ, MTL and PNG by [`write_textured_obj`]).
//! Each is compiled as it is (records with `"shading": "textured"`) and from the same OBJ
//! under a copy of its MTL without its `map_Kd` lines (the same geometry and materials,
//! untextured: `"flat"`), with the benchmark's options, and drawn at 320x240 on both cores
//! by the builds with textures (`--features ftb-stream,textures`, embedded-3dgfx's textured
//! mode with `--features embedded-3dgfx,textures`): the untextured frame by the same build as
//! the textured one, so the ratio is texturing's alone. Peel's frames are checked pixel for
//! pixel against `peel render` (integer vertices on the Cortex-M0+), as every scene's are.
//! The summary compares each camera's frames and, for the cost of the feature itself, the
//! untextured frame drawn by the plain streamed build.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use peel_compiler::load::Mesh;
use peel_runtime::display::rgb565_colour;
use peel_target_kit::config::{OrbitAngles, Variant};
use peel_target_runner::results::{Record, TEXTURE_GOALS};

use crate::accuracy::Truth;
use crate::measure::{Measure, INSTRUCTIONS_PER_TICK};
use crate::plan::{Core, Setup};
use crate::scenes::{self, SceneSpec};
use crate::tools::Tools;
use crate::{gfx3d_elf, mkdir, report, size_name, stem, write, Gfx3dBuilds, References};

/// The size the textured scenes are drawn at.
pub const SIZE: (u32, u32) = (320, 240);

/// The generated textured mesh: `textured_sphere(rings, segments)`, 960 triangles (about
/// suzanne's 968).
pub const SPHERE: (usize, usize) = (16, 32);

/// The textured scenes' names.
const NAMES: [&str; 2] = ["textured-box", "textured-mesh"];

/// What the textured runs need from the benchmark.
pub struct Textured<'a> {
    pub tools: &'a Tools,
    /// The repository's root (the fixture).
    pub root: &'a Path,
    pub firmware_dir: &'a Path,
    /// The plain builds ([`crate::run`]'s), for the untextured frame without textures.
    pub plain: &'a HashMap<(Core, Variant), PathBuf>,
    /// Those of Peel streamed and embedded-3dgfx that the run measures.
    pub setups: &'a [Setup],
    pub cameras: &'a [OrbitAngles],
    pub scene_dir: &'a Path,
    pub runs_dir: &'a Path,
    /// Where the host's frames go.
    pub references_dir: &'a Path,
    pub timeout_s: u32,
}

/// The records of the textured scenes and their baselines, the problems found, and the
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

/// The setups of [`Textured`] among `setups`: Peel streamed and embedded-3dgfx.
pub fn setups(setups: &[Setup]) -> Vec<Setup> {
    setups
        .iter()
        .filter(|s| matches!(s.variant, Variant::FtbStream | Variant::Gfx3d))
        .copied()
        .collect()
}

impl Textured<'_> {
    /// Build, compile, measure on both cores and compare.
    pub fn run(&self, gfx3d_builds: &mut Gfx3dBuilds) -> Result<Outcome, String> {
        let mut firmware = HashMap::new();
        for core in [Core::M4f, Core::M0Plus] {
            for setup in self.setups {
                let variant = setup.variant;
                println!(
                    "== build: firmware {},textures for {}",
                    variant.name(),
                    core.name()
                );
                // embedded-3dgfx's first build only finds how many commands a scene needs.
                let commands = (variant == Variant::Gfx3d).then_some(crate::GFX3D_PROBE_COMMANDS);
                let elf = (self.tools).build_textures_firmware(
                    core,
                    variant,
                    commands,
                    self.firmware_dir,
                )?;
                if core == Core::M0Plus {
                    crate::tools::check_armv6m(&elf)?;
                }
                firmware.insert((core, variant), elf);
            }
        }
        let (mut records, mut problems) = (Vec::new(), Vec::new());
        let mut summary = String::from(
            "\n## Textured scenes: textured against untextured\n\n\
             Instructions per frame of each camera, 320x240, the builds with textures; ratio = \
             textured / untextured.\n",
        );
        for name in NAMES {
            let obj = self.textured_obj(name)?;
            println!("== scene {name} (textured and untextured)");
            let flat_dir = self.scene_dir.join(format!("{name}-untextured"));
            let flat_obj = untextured_copy(&obj, &flat_dir)?;
            let spec = |obj: &Path| SceneSpec {
                name: name.into(),
                obj: obj.to_path_buf(),
            };
            let dir = self.scene_dir.join(name);
            mkdir(&dir)?;
            let textured = scenes::compile(self.tools, &spec(&obj), false, None, &dir)?;
            let flat = scenes::compile(self.tools, &spec(&flat_obj), false, None, &flat_dir)?;
            if !textured.textured || flat.textured {
                return Err(format!(
                    "{name}: {} compiled {}textured, {} {}textured",
                    obj.display(),
                    if textured.textured { "" } else { "un" },
                    flat_obj.display(),
                    if flat.textured { "" } else { "un" },
                ));
            }
            for scene in [&textured, &flat] {
                let depth = peel_runtime::read::Scene::parse(&scene.peel_bytes)
                    .map_err(|e| format!("{}: {e}", scene.peel.display()))?
                    .header()
                    .max_depth;
                if depth as usize > peel_target_kit::STACK {
                    return Err(format!(
                        "{}: its tree is {depth} deep and the firmware's stack holds {}",
                        scene.peel.display(),
                        peel_target_kit::STACK
                    ));
                }
            }
            let mut runs: HashMap<(bool, Core, Variant), Run> = HashMap::new();
            let mut plain_counts: HashMap<Core, Vec<u64>> = HashMap::new();
            for (scene, label) in [(&textured, ""), (&flat, "-untextured")] {
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
                    let refs_dir = (self.references_dir)
                        .join(format!("{}{label}", stem(scene)))
                        .join(folder);
                    mkdir(&refs_dir)?;
                    let refs = References::new(
                        self.tools,
                        scene,
                        SIZE,
                        integer,
                        Rc::clone(&truth),
                        self.cameras,
                        self.setups,
                        &refs_dir,
                    )?;
                    let run_dir = |setup: &Setup, build: &str| {
                        (self.runs_dir)
                            .join(format!("{}{label}", stem(scene)))
                            .join(format!(
                                "{}-{}-{}{build}",
                                core.name(),
                                size_name(SIZE),
                                setup.label()
                            ))
                    };
                    for setup in self.setups {
                        let mut measure = Measure {
                            scene,
                            core,
                            size: SIZE,
                            setup: *setup,
                            cameras: self.cameras,
                            spans_per_row: refs.spans_per_row,
                            scan_nodes: 0,
                            pending_pixels: 0,
                            composite_runs: 0,
                            scanline_lists: (0, 0),
                            elf: firmware[&(core, setup.variant)].clone(),
                            timeout_s: self.timeout_s,
                        };
                        let dir = run_dir(setup, "-textures");
                        if setup.variant == Variant::Gfx3d {
                            measure.elf = gfx3d_elf(
                                self.tools,
                                &measure,
                                &dir,
                                gfx3d_builds,
                                self.firmware_dir,
                                true,
                            )?;
                        }
                        let (record, found) =
                            measure.measure(&dir, &refs.expected(setup.variant))?;
                        problems.extend(found);
                        let counts = instructions(&dir)?;
                        runs.insert(
                            (scene.textured, core, setup.variant),
                            Run {
                                record: record.clone(),
                                counts,
                            },
                        );
                        records.push(record);
                        // The untextured frame by the plain streamed build too: what compiling
                        // textures in costs a scene without them (not a record: the build
                        // with textures draws the baseline).
                        let plain = self.plain.get(&(core, Variant::FtbStream));
                        if let (false, Variant::FtbStream, Some(plain)) =
                            (scene.textured, setup.variant, plain)
                        {
                            measure.elf = plain.clone();
                            let dir = run_dir(setup, "-plain");
                            let (_, found) =
                                measure.measure(&dir, &refs.expected(setup.variant))?;
                            problems.extend(found);
                            plain_counts.insert(core, instructions(&dir)?);
                        }
                    }
                }
            }
            summary.push_str(&compare(name, &runs, &plain_counts));
        }
        Ok(Outcome {
            records,
            problems,
            summary,
        })
    }

    /// The textured OBJ file of scene `name` (one of [`NAMES`]): the fixture, or the generated
    /// sphere written into the scene folder.
    fn textured_obj(&self, name: &str) -> Result<PathBuf, String> {
        match name {
            "textured-box" => Ok(self.root.join("fixtures/textured-box/box.obj")),
            "textured-mesh" => {
                let dir = self.scene_dir.join("textured-mesh-source");
                mkdir(&dir)?;
                let (rings, segments) = SPHERE;
                let mesh = peel_compiler::tools::scenes::textured_sphere(rings, segments);
                write_textured_obj(&mesh, &dir, "sphere")
            }
            _ => Err(format!("{name}: not a textured scene")),
        }
    }
}

/// Instructions of each frame of the first run in `dir` (its QEMU log).
pub(crate) fn instructions(dir: &Path) -> Result<Vec<u64>, String> {
    let log = dir.join("run-1/qemu.out");
    let text = std::fs::read_to_string(&log)
        .map_err(|e| format!("{}: cannot read: {e}", log.display()))?;
    let report = report::parse(&text).map_err(|e| format!("{}: {e}", log.display()))?;
    Ok(report
        .frames
        .iter()
        .map(|f| f.ticks * INSTRUCTIONS_PER_TICK)
        .collect())
}

/// The comparison of scene `name` on each core: Peel's streamed frames per camera, textured
/// and untextured, and their ratios; the medians' ratio against [`TEXTURE_GOALS`], RAM and
/// flash; embedded-3dgfx's medians; the untextured frame of the plain build.
fn compare(
    name: &str,
    runs: &HashMap<(bool, Core, Variant), Run>,
    plain: &HashMap<Core, Vec<u64>>,
) -> String {
    let mut s = String::new();
    let (m4f_goal, m0_goal, ram_goal) = TEXTURE_GOALS;
    let met = |ok: bool| if ok { "met" } else { "not met" };
    for core in [Core::M4f, Core::M0Plus] {
        let goal = if core == Core::M4f { m4f_goal } else { m0_goal };
        let _ = writeln!(s, "\n### {name}, {}\n", core.name());
        let peel = (
            runs.get(&(true, core, Variant::FtbStream)),
            runs.get(&(false, core, Variant::FtbStream)),
        );
        if let (Some(t), Some(f)) = peel {
            s.push_str("| camera | textured | untextured | ratio |\n|--:|--:|--:|--:|\n");
            let mut ratios = Vec::new();
            for (k, (&a, &b)) in t.counts.iter().zip(&f.counts).enumerate() {
                let ratio = a as f64 / b.max(1) as f64;
                ratios.push(ratio);
                let _ = writeln!(s, "| {k} | {a} | {b} | {ratio:.3} |");
            }
            let x = t.record.instructions as f64 / f.record.instructions.max(1) as f64;
            ratios.sort_by(f64::total_cmp);
            let n = ratios.len();
            let median_ratio = match n {
                0 => f64::NAN,
                n if n % 2 == 1 => ratios[n / 2],
                n => (ratios[n / 2 - 1] + ratios[n / 2]) / 2.0,
            };
            let _ = writeln!(
                s,
                "\nPeel streamed: median {} textured, {} untextured, ratio {x:.3} (goal at most \
                 {goal}: {}; the cameras' ratios' median {median_ratio:.3}); RAM {} B textured \
                 (goal at most {ram_goal}: {}), {} B untextured; flash {} B textured, {} B \
                 untextured; differing pixels {} and {}.",
                t.record.instructions,
                f.record.instructions,
                met(x <= goal),
                t.record.ram_bytes,
                met(t.record.ram_bytes <= ram_goal),
                f.record.ram_bytes,
                t.record.flash_bytes,
                f.record.flash_bytes,
                or_dash(t.record.differing_pixels),
                or_dash(f.record.differing_pixels),
            );
            if let Some(p) = plain.get(&core) {
                let m = report::median(p);
                let _ = writeln!(
                    s,
                    "The untextured frame by the plain streamed build (no textures compiled \
                     in): median {m} ({:.3}x that build's, textured {:.3}x).",
                    f.record.instructions as f64 / m.max(1) as f64,
                    t.record.instructions as f64 / m.max(1) as f64,
                );
            }
            println!("   {name} {}: textured / untextured {x:.3}", core.name());
        }
        let gfx3d = (
            runs.get(&(true, core, Variant::Gfx3d)),
            runs.get(&(false, core, Variant::Gfx3d)),
        );
        if let (Some(t), Some(f)) = gfx3d {
            let _ = writeln!(
                s,
                "\nembedded-3dgfx: median {} textured, {} untextured ({:.3}x); RAM {} B and {} B; \
                 flash {} B and {} B; robust errors {} and {}.",
                t.record.instructions,
                f.record.instructions,
                t.record.instructions as f64 / f.record.instructions.max(1) as f64,
                t.record.ram_bytes,
                f.record.ram_bytes,
                t.record.flash_bytes,
                f.record.flash_bytes,
                or_dash(t.record.robust_errors),
                or_dash(f.record.robust_errors),
            );
        }
    }
    s
}

fn or_dash(n: Option<u64>) -> String {
    n.map_or_else(|| "-".to_string(), |n| n.to_string())
}

/// A copy of `obj` in `dir` under copies of its MTL files (its `mtllib` lines, beside it)
/// without their `map_Kd` lines: the same geometry and materials, untextured. The copy's path.
fn untextured_copy(obj: &Path, dir: &Path) -> Result<PathBuf, String> {
    mkdir(dir)?;
    let read = |p: &Path| {
        std::fs::read_to_string(p).map_err(|e| format!("{}: cannot read: {e}", p.display()))
    };
    let text = read(obj)?;
    let from = obj.parent().unwrap_or(Path::new("."));
    for line in text.lines() {
        let Some(names) = line.trim().strip_prefix("mtllib") else {
            continue;
        };
        for mtl in names.split_whitespace() {
            let kept: String = read(&from.join(mtl))?
                .lines()
                .filter(|l| !l.trim_start().starts_with("map_Kd"))
                .map(|l| format!("{l}\n"))
                .collect();
            write(&dir.join(mtl), kept.as_bytes())?;
        }
    }
    let copy = dir.join(obj.file_name().ok_or("an OBJ path without a file name")?);
    write(&copy, text.as_bytes())?;
    Ok(copy)
}

/// `mesh` with its textures as `STEM.obj` in `dir`, with `STEM.mtl` (a material per texture
/// and colour: `Kd`, `map_Kd` of `STEM-K.png`, `-clamp on` where the texture clamps) and a
/// PNG per texture (its RGB565 texels expanded to 8 bits, which the loader reads back
/// exactly): shared points and coordinates merged, printed exactly. The OBJ's path.
pub fn write_textured_obj(mesh: &Mesh, dir: &Path, stem: &str) -> Result<PathBuf, String> {
    let mut mtl = format!("# Materials of {stem}.obj, written by the target benchmark.\n");
    for (k, t) in mesh.textures.iter().enumerate() {
        let png = format!("{stem}-{k}.png");
        let (w, h) = (t.width(), t.height());
        let image = image::RgbImage::from_fn(w, h, |c, r| {
            let colour = rgb565_colour(t.texel(c, r));
            image::Rgb([colour.r, colour.g, colour.b])
        });
        let path = dir.join(&png);
        image
            .save(&path)
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
        if t.clamp[0] != t.clamp[1] {
            return Err(format!("{png}: an MTL clamps both axes or neither"));
        }
    }
    let mut materials: Vec<(Option<u32>, [u8; 3])> = Vec::new();
    let (mut points, mut uvs): (HashMap<[u64; 3], usize>, HashMap<[u64; 2], usize>) =
        Default::default();
    let (mut head, mut faces) = (String::new(), String::new());
    let mut current = None;
    for t in &mesh.triangles {
        let key = (t.texture.map(|c| c.texture), t.colour);
        let m = match materials.iter().position(|&k| k == key) {
            Some(m) => m,
            None => {
                materials.push(key);
                let [r, g, b] = t.colour.map(|c| f64::from(c) / 255.0);
                let _ = writeln!(mtl, "newmtl m{}\nKd {r} {g} {b}", materials.len() - 1);
                if let Some(k) = key.0 {
                    let clamp = mesh.textures.get(k as usize).is_some_and(|t| t.clamp[0]);
                    let clamp = if clamp { "-clamp on " } else { "" };
                    let _ = writeln!(mtl, "map_Kd {clamp}{stem}-{k}.png");
                }
                materials.len() - 1
            }
        };
        if current != Some(m) {
            let _ = writeln!(faces, "usemtl m{m}");
            current = Some(m);
        }
        let mut corner = |k: usize| {
            let v = t.vertices[k];
            let n = points.len();
            let p = *points
                .entry(v.to_array().map(f64::to_bits))
                .or_insert_with(|| {
                    let _ = writeln!(head, "v {} {} {}", v.x, v.y, v.z);
                    n
                })
                + 1;
            match t.texture {
                Some(c) => {
                    let uv = c.uv[k];
                    let n = uvs.len();
                    let q = *uvs
                        .entry(uv.to_array().map(f64::to_bits))
                        .or_insert_with(|| {
                            let _ = writeln!(head, "vt {} {}", uv.x, uv.y);
                            n
                        })
                        + 1;
                    format!("{p}/{q}")
                }
                None => p.to_string(),
            }
        };
        let (a, b, c) = (corner(0), corner(1), corner(2));
        let _ = writeln!(faces, "f {a} {b} {c}");
    }
    let mtl_path = dir.join(format!("{stem}.mtl"));
    write(&mtl_path, mtl.as_bytes())?;
    let obj = dir.join(format!("{stem}.obj"));
    let text = format!(
        "# A generated textured mesh, written by the target benchmark.\nmtllib {stem}.mtl\n{head}{faces}"
    );
    write(&obj, text.as_bytes())?;
    Ok(obj)
}

#[cfg(test)]
mod tests {
    use super::*;
    use peel_compiler::load::load_obj;

    fn temp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("peel-target-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn the_generated_textured_mesh_loads_back_exactly() {
        let dir = temp("textured");
        let mesh = peel_compiler::tools::scenes::textured_sphere(4, 6);
        let obj = write_textured_obj(&mesh, &dir, "sphere").unwrap();
        let back = load_obj(&obj).unwrap();
        let corners = |m: &Mesh| {
            (m.triangles.iter())
                .map(|t| (t.vertices, t.colour, t.texture))
                .collect::<Vec<_>>()
        };
        assert_eq!(corners(&back), corners(&mesh));
        let texels = |m: &Mesh| {
            (m.textures.iter())
                .map(|t| (t.log2_width, t.log2_height, t.clamp, t.texels.clone()))
                .collect::<Vec<_>>()
        };
        assert_eq!(texels(&back), texels(&mesh));
        // Its untextured copy: the same triangles and colours, no texture.
        let flat = untextured_copy(&obj, &dir.join("untextured")).unwrap();
        let flat = load_obj(&flat).unwrap();
        assert!(flat.textures.is_empty());
        assert!(flat.triangles.iter().all(|t| t.texture.is_none()));
        let geometry = |m: &Mesh| {
            (m.triangles.iter())
                .map(|t| (t.vertices, t.colour))
                .collect::<Vec<_>>()
        };
        assert_eq!(geometry(&flat), geometry(&mesh));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
