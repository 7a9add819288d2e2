//! The scene with moving objects (`objects`, issue 46) and its baseline (`objects-static`).
//!
//! `objects`: a world of a ground square and four boxes ([`peel_target_kit::objects::Layout`],
//! written as `objects-world.obj` with its MTL) and the teapot and the cow as objects (or
//! their generated stand-ins), compiled as one file of parts with the benchmark's options;
//! camera `k` poses them with [`peel_target_kit::objects::poses`], on the target as on the
//! host. `objects-static`: for each camera, the same posed geometry (the objects' triangles
//! moved by that camera's poses in `f64`) merged with the world's into one plain scene, drawn
//! by the same firmware for that camera alone; its record takes the median over the cameras.
//! Both are framed alike (the runner checks it), so each camera sees both from the same view.
//! Both are drawn by the streamed build with files of parts (`--features ftb-stream,objects`),
//! built here; the other records' builds hold none of its code.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::DVec3;
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::{load_obj, Mesh};
use peel_compiler::tools::raster::{posed_header, render_bytes_with, render_posed_with, Settings};
use peel_compiler::tools::scenes::boxed;
use peel_compiler::tools::shot::Shot;
use peel_runtime::camera::Orbit;
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Colour, SpanSink};
use peel_runtime::place::{Object, ObjectMemory, Pose};
use peel_runtime::read::{Header, Parts, Scene};
use peel_runtime::render::{Content, Renderer, Workspace};
use peel_target_kit::config::{OrbitAngles, Variant};
use peel_target_kit::objects::{self as kit, Layout, OBJECTS, STEPS};
use peel_target_runner::results::Record;

use crate::measure::{Expected, Measure, Robust, INSTRUCTIONS_PER_TICK};
use crate::plan::{Core, Setup, FOV_Y_DEG};
use crate::scenes::{self, Compiled, SceneSpec};
use crate::tools::Tools;
use crate::{report, size_name, write, BACKGROUND};

/// The objects, in the order of the file's parts and of the kit's poses.
const NAMES: [&str; OBJECTS] = ["teapot", "cow"];

/// Issue 46's goals for the posed frame: at most this multiple of the static file's
/// instructions (the median over the cameras of each camera's ratio), in at most this RAM.
const GOALS: (f64, u64) = (1.3, 40 * 1024);

/// The build that draws objects.
const SETUP: Setup = Setup {
    variant: Variant::FtbStream,
    band_rows: 0,
};

/// What the scene's runs need from the benchmark.
pub struct Objects<'a> {
    pub tools: &'a Tools,
    /// Where the firmware builds go.
    pub firmware_dir: &'a Path,
    pub cameras: &'a [OrbitAngles],
    /// Where the shared models are.
    pub models: &'a Path,
    pub scene_dir: &'a Path,
    pub runs_dir: &'a Path,
    pub timeout_s: u32,
}

/// The records of both scenes, the problems found, and the comparison as markdown.
pub struct Outcome {
    pub records: Vec<Record>,
    pub problems: Vec<String>,
    pub summary: String,
}

/// The compiled scenes and each camera's poses.
struct Prepared {
    posed: Compiled,
    /// Per camera: the poses, and the header that frames the posed scene.
    poses: Vec<([Pose; OBJECTS], Header)>,
    /// Per camera: the same geometry as one plain scene.
    statics: Vec<Compiled>,
}

impl Objects<'_> {
    /// Compile, measure on both cores at each size, and compare.
    pub fn run(&self) -> Result<Outcome, String> {
        let mut firmware = HashMap::new();
        for core in [Core::M4f, Core::M0Plus] {
            println!("== build: firmware ftb-stream,objects for {}", core.name());
            let elf = self.tools.build_objects_firmware(core, self.firmware_dir)?;
            if core == Core::M0Plus {
                crate::tools::check_armv6m(&elf)?;
            }
            firmware.insert(core, elf);
        }
        println!("== scene objects");
        let prepared = self.prepare()?;
        let (mut records, mut problems) = (Vec::new(), Vec::new());
        let mut summary = String::from(
            "\n## Moving objects: posed against the same geometry as one static file\n\n\
             Instructions per frame of each camera (ftb-stream); ratio = posed / static.\n",
        );
        for core in [Core::M4f, Core::M0Plus] {
            for &size in core.sizes() {
                let elf = &firmware[&core];
                let (posed, found, posed_counts) =
                    self.measure_posed(&prepared, elf, core, size)?;
                problems.extend(found);
                let (statics, found, static_counts) =
                    self.measure_static(&prepared, elf, core, size)?;
                problems.extend(found);
                summary.push_str(&compare(
                    core,
                    size,
                    (&posed, &posed_counts),
                    (&statics, &static_counts),
                ));
                records.push(posed);
                records.push(statics);
            }
        }
        summary.push_str(&host_counts(&prepared, self.cameras)?);
        Ok(Outcome {
            records,
            problems,
            summary,
        })
    }

    /// The world, the file of parts, each camera's poses and static file, checked to frame
    /// alike.
    fn prepare(&self) -> Result<Prepared, String> {
        let options = scenes::options(false, None)?;
        let mut generated = false;
        let (mut paths, mut meshes, mut headers) = (Vec::new(), Vec::new(), Vec::new());
        for name in NAMES {
            let (obj, stand_in) = scenes::model(name, self.models, self.scene_dir)?;
            generated |= stand_in;
            let mesh = load(&obj)?;
            headers.push(header_of(&compile(&mesh, &options, &obj)?, &obj)?);
            meshes.push(mesh);
            paths.push(obj);
        }
        let headers: [Header; OBJECTS] = headers.try_into().map_err(|_| "two objects")?;
        let layout = Layout::new(&headers);
        let world_obj = self.scene_dir.join("objects-world.obj");
        write_world(&layout, &world_obj)?;
        let world_mesh = load(&world_obj)?;
        let suffix = if generated { " (generated)" } else { "" };
        let stem = if generated {
            "objects-generated"
        } else {
            "objects"
        };

        let peel = self.scene_dir.join(format!("{stem}.peel"));
        let object_args: Vec<String> = (NAMES.iter().zip(&paths))
            .map(|(n, p)| format!("{n}={}", p.display()))
            .collect();
        let mut args: Vec<&std::ffi::OsStr> = vec!["compile".as_ref(), world_obj.as_os_str()];
        for a in &object_args {
            args.extend::<[&std::ffi::OsStr; 2]>(["--object".as_ref(), a.as_ref()]);
        }
        args.extend::<[&std::ffi::OsStr; 5]>([
            "-o".as_ref(),
            peel.as_os_str(),
            "--solid".as_ref(),
            "--shading".as_ref(),
            "faceted".as_ref(),
        ]);
        self.tools.peel(&args)?;
        let bytes =
            std::fs::read(&peel).map_err(|e| format!("{}: cannot read: {e}", peel.display()))?;
        let fail = |e: String| format!("{}: {e}", peel.display());
        let parts = Parts::parse(&bytes).map_err(|e| fail(e.to_string()))?;
        let world = parts.world().ok_or_else(|| fail("no world".into()))?;
        let scenes = (0..OBJECTS)
            .map(|k| {
                let (name, scene) = (parts.object(k as u32))
                    .ok_or_else(|| fail(format!("no object {k}")))?;
                // The kit poses each object by the header it was laid out with.
                if name != NAMES[k] || framing(&scene.header()) != framing(&headers[k]) {
                    return Err(fail(format!(
                        "object {k} is {name:?} framed {:?}, not {:?} framed {:?} as compiled alone",
                        framing(&scene.header()),
                        NAMES[k],
                        framing(&headers[k])
                    )));
                }
                Ok(scene)
            })
            .collect::<Result<Vec<_>, _>>()?;
        for scene in scenes.iter().chain([&world]) {
            check_depth(&scene.header(), &peel)?;
        }
        let triangles = (world_mesh.triangles.len()
            + meshes.iter().map(|m| m.triangles.len()).sum::<usize>())
            as u64;
        let compiled =
            |name: String, obj: PathBuf, peel: PathBuf, peel_bytes: Vec<u8>, n| Compiled {
                spec: SceneSpec { name, obj },
                peel,
                peel_bytes,
                mesh: PathBuf::new(),
                mesh_bytes: Vec::new(),
                ids_mesh_bytes: Vec::new(),
                gfx3d: PathBuf::new(),
                gfx3d_bytes: Vec::new(),
                triangles,
                shadows: false,
                smooth: false,
                textured: false,
                objects: n,
                transparent: false,
            };

        let (mut poses, mut statics) = (Vec::new(), Vec::new());
        for k in 0..self.cameras.len() {
            let pose = kit::poses(k, &headers);
            let header = kit::posed_header(&world.header(), &headers, &pose);
            let objects = posed(&scenes, &pose);
            let host = posed_header(Some(&world), &objects);
            if framing(&header) != framing(&host) {
                return Err(fail(format!(
                    "camera {k}: the kit frames the posed scene {:?}, the host {:?}",
                    framing(&header),
                    framing(&host)
                )));
            }
            let merged = merge(&world_mesh, &meshes, &pose);
            let path = self.scene_dir.join(format!("{stem}-static-{k}.peel"));
            let static_bytes = compile(&merged, &options, &path)?;
            let static_header = header_of(&static_bytes, &path)?;
            check_depth(&static_header, &path)?;
            // The orbit camera is the header's: the same view only if framed alike.
            if framing(&static_header) != framing(&header) {
                return Err(format!(
                    "{}: framed {:?}, the posed scene of camera {k} {:?}: their views would differ",
                    path.display(),
                    framing(&static_header),
                    framing(&header)
                ));
            }
            write(&path, &static_bytes)?;
            statics.push(compiled(
                format!("objects-static{suffix}"),
                world_obj.clone(),
                path,
                static_bytes,
                0,
            ));
            poses.push((pose, header));
        }
        Ok(Prepared {
            posed: compiled(
                format!("objects{suffix}"),
                world_obj,
                peel,
                bytes,
                OBJECTS as u64,
            ),
            poses,
            statics,
        })
    }

    /// The posed scene on `core` at `size`: its record, problems and instructions per camera.
    fn measure_posed(
        &self,
        prepared: &Prepared,
        elf: &Path,
        core: Core,
        size: (u32, u32),
    ) -> Result<(Record, Vec<String>, Vec<u64>), String> {
        let integer = core.integer_vertices();
        let bytes = &prepared.posed.peel_bytes;
        let parts = Parts::parse(bytes).map_err(|e| e.to_string())?;
        let world = parts.world().ok_or("no world")?;
        let scenes: Vec<Scene<'_>> = (0..OBJECTS as u32)
            .filter_map(|k| parts.object(k).map(|(_, s)| s))
            .collect();
        let (mut frames, mut views) = (Vec::new(), Vec::new());
        for (&angles, (pose, header)) in self.cameras.iter().zip(&prepared.poses) {
            let objects = posed(&scenes, pose);
            let frame = render_posed_with(
                Some(&world),
                &objects,
                &shot(header, angles, size),
                &settings(integer),
            )
            .map_err(|e| format!("{}: host frame: {e}", prepared.posed.peel.display()))?;
            frames.push(rgb565(&frame.pixels));
            views.push(
                peel_target_kit::orbit_view(header, angles, FOV_Y_DEG, size.0, size.1)
                    .map_err(|e| e.to_string())?,
            );
        }
        let spans = spans_per_row(size, integer, |renderer| {
            let mut fallback = false;
            for (view, (pose, _)) in views.iter().zip(&prepared.poses) {
                let objects = posed(&scenes, pose);
                let posed = peel_runtime::place::Posed::new(Some(world), &objects);
                fallback |= draw(renderer, &posed, view)?;
            }
            Ok(fallback)
        })?;
        let dir = self.runs_dir.join("objects").join(format!(
            "{}-{}-{}",
            core.name(),
            size_name(size),
            SETUP.label()
        ));
        let measure = self.measure(&prepared.posed, elf, core, size, self.cameras, spans);
        let (record, found) = measure.measure(&dir, &expected(&frames))?;
        let counts = instructions(&dir)?;
        Ok((record, found, counts))
    }

    /// The static files, each for its camera, on `core` at `size`: one record (medians over
    /// the cameras, the most RAM and flash), problems and instructions per camera.
    fn measure_static(
        &self,
        prepared: &Prepared,
        elf: &Path,
        core: Core,
        size: (u32, u32),
    ) -> Result<(Record, Vec<String>, Vec<u64>), String> {
        let integer = core.integer_vertices();
        let mut views = Vec::new();
        for (&angles, scene) in self.cameras.iter().zip(&prepared.statics) {
            let header = header_of(&scene.peel_bytes, &scene.peel)?;
            views.push(
                peel_target_kit::orbit_view(&header, angles, FOV_Y_DEG, size.0, size.1)
                    .map_err(|e| e.to_string())?,
            );
        }
        // Span memory for every camera's frame of its file, as the posed scene's.
        let spans = spans_per_row(size, integer, |renderer| {
            let mut fallback = false;
            for (view, scene) in views.iter().zip(&prepared.statics) {
                let parsed = Scene::parse(&scene.peel_bytes).map_err(|e| e.to_string())?;
                fallback |= draw(renderer, &parsed, view)?;
            }
            Ok(fallback)
        })?;
        let (mut records, mut problems, mut counts) = (Vec::new(), Vec::new(), Vec::new());
        for (k, scene) in prepared.statics.iter().enumerate() {
            let header = header_of(&scene.peel_bytes, &scene.peel)?;
            let frame = render_bytes_with(
                &scene.peel_bytes,
                &shot(&header, self.cameras[k], size),
                &settings(integer),
            )
            .map_err(|e| format!("{}: host frame: {e}", scene.peel.display()))?;
            let frames = [rgb565(&frame.pixels)];
            let dir = self.runs_dir.join("objects-static").join(format!(
                "{}-{}-{}-camera-{k}",
                core.name(),
                size_name(size),
                SETUP.label()
            ));
            let cameras = &self.cameras[k..=k];
            let measure = self.measure(scene, elf, core, size, cameras, spans);
            let (record, found) = measure.measure(&dir, &expected(&frames))?;
            counts.extend(instructions(&dir)?);
            records.push(record);
            problems.extend(found.into_iter().map(|p| format!("camera {k}: {p}")));
        }
        Ok((combine(&records)?, problems, counts))
    }

    #[allow(clippy::too_many_arguments)]
    fn measure<'m>(
        &'m self,
        scene: &'m Compiled,
        elf: &Path,
        core: Core,
        size: (u32, u32),
        cameras: &'m [OrbitAngles],
        spans_per_row: u32,
    ) -> Measure<'m> {
        Measure {
            scene,
            core,
            size,
            setup: SETUP,
            cameras,
            spans_per_row,
            scan_nodes: 0,
            pending_pixels: 0,
            composite_runs: 0,
            scanline_lists: (0, 0),
            elf: elf.to_path_buf(),
            timeout_s: self.timeout_s,
        }
    }
}

/// What a frame is framed by: the centre and the bounds.
fn framing(h: &Header) -> ([f64; 3], [f32; 3], [f32; 3]) {
    (h.centre, h.bounds_min.to_array(), h.bounds_max.to_array())
}

fn load(obj: &Path) -> Result<Mesh, String> {
    load_obj(obj).map_err(|e| format!("{}: {e}", obj.display()))
}

/// `mesh` compiled with `options` (`path` names it in errors).
fn compile(mesh: &Mesh, options: &CompileOptions, path: &Path) -> Result<Vec<u8>, String> {
    let (_, bytes) =
        compile_mesh(mesh, options, &|_| {}).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(bytes)
}

fn header_of(bytes: &[u8], path: &Path) -> Result<Header, String> {
    Ok(Scene::parse(bytes)
        .map_err(|e| format!("{}: {e}", path.display()))?
        .header())
}

/// Refuse a tree deeper than the firmware's traversal stack.
fn check_depth(header: &Header, path: &Path) -> Result<(), String> {
    if header.max_depth as usize > peel_target_kit::STACK {
        return Err(format!(
            "{}: a tree {} deep, the firmware's stack holds {}",
            path.display(),
            header.max_depth,
            peel_target_kit::STACK
        ));
    }
    Ok(())
}

/// The objects `scenes` posed by `poses`.
fn posed<'a>(scenes: &[Scene<'a>], poses: &[Pose; OBJECTS]) -> Vec<Object<'a>> {
    scenes
        .iter()
        .zip(poses)
        .map(|(&scene, &pose)| Object::new(scene, Some(pose)))
        .collect()
}

/// The world's triangles and each object's moved by its pose (`T + R p` in `f64`), as one
/// mesh: the posed geometry as a static scene.
fn merge(world: &Mesh, objects: &[Mesh], poses: &[Pose; OBJECTS]) -> Mesh {
    let mut merged = world.clone();
    for (mesh, pose) in objects.iter().zip(poses) {
        let (r, t) = (pose.rotation.as_dmat3(), pose.translation.as_dvec3());
        merged.triangles.extend(mesh.triangles.iter().map(|tri| {
            let mut moved = *tri;
            moved.vertices = tri.vertices.map(|p| t + r * p);
            moved.normals = tri.normals.map(|n| n.map(|n| r * n));
            moved
        }));
    }
    merged
}

/// The world of `layout` as an OBJ file at `path` with its MTL beside it: the ground square
/// and the boxes, each in its own colour.
fn write_world(layout: &Layout, path: &Path) -> Result<(), String> {
    let mtl = path.with_extension("mtl");
    let colours = [
        ("ground", [0.35, 0.55, 0.30]),
        ("red", [0.85, 0.20, 0.15]),
        ("blue", [0.20, 0.35, 0.85]),
        ("gold", [0.90, 0.75, 0.20]),
        ("white", [0.90, 0.90, 0.88]),
    ];
    let mut m = String::from("# Materials of the benchmark's world with moving objects.\n");
    for (name, [r, g, b]) in colours {
        let _ = writeln!(m, "newmtl {name}\nKd {r} {g} {b}");
    }
    write(&mtl, m.as_bytes())?;
    let g = f64::from(layout.ground());
    let ground = [
        DVec3::new(-g, 0.0, -g),
        DVec3::new(-g, 0.0, g),
        DVec3::new(g, 0.0, g),
        DVec3::new(g, 0.0, -g),
    ];
    let mut groups = vec![(
        "ground",
        vec![
            [ground[0], ground[1], ground[2]],
            [ground[0], ground[2], ground[3]],
        ],
    )];
    let height = f64::from(layout.height);
    for ((x, z), (name, _)) in layout.boxes().into_iter().zip(&colours[1..]) {
        let mut t = Vec::new();
        boxed(
            &mut t,
            DVec3::new(f64::from(x[0]), 0.0, f64::from(z[0])),
            DVec3::new(f64::from(x[1]), height, f64::from(z[1])),
        );
        groups.push((name, t));
    }
    let name = mtl.file_name().map(|n| n.to_string_lossy().into_owned());
    let mut obj = format!(
        "# The benchmark's world with moving objects (target-bench/runner/src/objects.rs).\n\
         mtllib {}\n",
        name.unwrap_or_default()
    );
    let mut index: HashMap<[u64; 3], usize> = HashMap::new();
    let mut faces = String::new();
    for (material, triangles) in groups {
        let _ = writeln!(faces, "usemtl {material}");
        for t in triangles {
            let ids = t.map(|v| {
                let n = index.len() + 1;
                *index
                    .entry(v.to_array().map(f64::to_bits))
                    .or_insert_with(|| {
                        let _ = writeln!(obj, "v {} {} {}", v.x, v.y, v.z);
                        n
                    })
            });
            let _ = writeln!(faces, "f {} {} {}", ids[0], ids[1], ids[2]);
        }
    }
    write(path, (obj + &faces).as_bytes())
}

/// The shot of the orbit camera `angles` over the scene framed by `header`, as the firmware's
/// view ([`peel_target_kit::orbit_view`]) sees it.
fn shot(header: &Header, angles: OrbitAngles, (width, height): (u32, u32)) -> Shot {
    let pose = Orbit {
        azimuth_deg: angles.azimuth_deg,
        elevation_deg: angles.elevation_deg,
        distance: Orbit::fitting_distance(FOV_Y_DEG, width, height),
    }
    .pose(header);
    Shot {
        fov_y_deg: FOV_Y_DEG,
        ..Shot::new(pose.eye, pose.target, width, height)
    }
}

/// The host renderer as the streamed firmware draws (integer vertices or not).
fn settings(integer_vertices: bool) -> Settings {
    Settings {
        background: BACKGROUND,
        integer_vertices,
        ..Settings::default()
    }
}

fn rgb565(pixels: &[u32]) -> Vec<u16> {
    pixels
        .iter()
        .map(|&p| Colour::new((p >> 16) as u8, (p >> 8) as u8, p as u8).to_rgb565())
        .collect()
}

/// Frames checked pixel for pixel; no ray-casting reference of these scenes.
fn expected(frames: &[Vec<u16>]) -> Expected<'_> {
    Expected {
        frames: Some(frames),
        robust_errors: Robust::Unmeasured,
        truth: None,
        pending_peaks: None,
    }
}

/// A sink that draws nothing.
struct Nowhere;

impl SpanSink for Nowhere {
    fn span(&mut self, _: u32, _: u32, _: u32, _: Colour) {}
}

/// One frame of `content` with `renderer`; whether span memory ran out.
fn draw<C: Content + ?Sized>(
    renderer: &mut Renderer<'_>,
    content: &C,
    view: &peel_runtime::camera::LocalView,
) -> Result<bool, String> {
    Ok(renderer
        .draw(content, view, &mut Nowhere)
        .map_err(|e| e.to_string())?
        .fallback)
}

/// The fewest span-memory intervals per row with which no frame `frames` draws runs out
/// (`frames` draws them all with the renderer it is given and says whether any ran out):
/// what the firmware gets, as the builder's sizes file gives a plain scene over an orbit.
fn spans_per_row(
    (width, height): (u32, u32),
    integer: bool,
    mut frames: impl FnMut(&mut Renderer<'_>) -> Result<bool, String>,
) -> Result<u32, String> {
    let rows = height as usize;
    let most = (width as usize).div_ceil(2);
    // The firmware's workspace for a posed frame and its object memory: a frame that needs
    // more fails here first.
    let mut workspace: Box<Workspace<{ peel_target_kit::STACK }, { kit::VERTS }>> = Box::default();
    let mut intervals = vec![(0u16, 0u16); most * rows];
    let mut counts = vec![0u16; rows];
    let mut memory: Box<ObjectMemory<OBJECTS, STEPS>> = Box::default();
    let mut enough = |per_row: usize| -> Result<bool, String> {
        let coverage = Coverage::new(&mut intervals[..per_row * rows], &mut counts, width, height)
            .map_err(|e| e.to_string())?;
        let mut renderer = Renderer::new(&mut workspace)
            .span_memory(coverage)
            .object_memory(&mut memory);
        if integer {
            renderer = renderer.integer_vertices();
        }
        Ok(!frames(&mut renderer)?)
    };
    if !enough(most)? {
        return Err(format!(
            "the frames run out of span memory at {most} intervals a row"
        ));
    }
    let (mut lo, mut hi) = (1, most);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if enough(mid)? {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    Ok(lo as u32)
}

/// Instructions of each frame of the first run in `dir` (its QEMU log).
fn instructions(dir: &Path) -> Result<Vec<u64>, String> {
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

/// One record of the static files' per-camera records: medians of the per-frame figures, the
/// most RAM and flash, the differing pixels summed.
fn combine(records: &[Record]) -> Result<Record, String> {
    let first = records.first().ok_or("no static records")?;
    let median = |f: fn(&Record) -> u64| report::median(&records.iter().map(f).collect::<Vec<_>>());
    let most = |f: fn(&Record) -> u64| records.iter().map(f).max().unwrap_or(0);
    Ok(Record {
        instructions: median(|r| r.instructions),
        display_bytes: median(|r| r.display_bytes),
        display_writes: median(|r| r.display_writes),
        ram_bytes: most(|r| r.ram_bytes),
        framebuffer_bytes: most(|r| r.framebuffer_bytes),
        flash_bytes: most(|r| r.flash_bytes),
        differing_pixels: records
            .iter()
            .map(|r| r.differing_pixels)
            .sum::<Option<u64>>(),
        deterministic: records.iter().all(|r| r.deterministic),
        ..first.clone()
    })
}

/// The comparison on one core and size: each camera's instructions and their ratio, the
/// median ratio, and RAM.
fn compare(
    core: Core,
    (w, h): (u32, u32),
    (posed, posed_counts): (&Record, &[u64]),
    (statics, static_counts): (&Record, &[u64]),
) -> String {
    let mut s = format!(
        "\n### {} {w}x{h}\n\n| camera | posed | static | ratio |\n|--:|--:|--:|--:|\n",
        core.name()
    );
    let mut ratios = Vec::new();
    for (k, (&p, &q)) in posed_counts.iter().zip(static_counts).enumerate() {
        let ratio = p as f64 / q as f64;
        ratios.push(ratio);
        let _ = writeln!(s, "| {k} | {p} | {q} | {ratio:.3} |");
    }
    ratios.sort_by(f64::total_cmp);
    let n = ratios.len();
    let median = if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        ratios[n / 2]
    } else {
        (ratios[n / 2 - 1] + ratios[n / 2]) / 2.0
    };
    let (ratio_goal, ram_goal) = GOALS;
    let met = |ok: bool| if ok { "met" } else { "not met" };
    let _ = writeln!(
        s,
        "\nMedian ratio {median:.3} (goal at most {ratio_goal}: {}); RAM posed {} B (goal at \
         most {ram_goal}: {}), static {} B (the most over the cameras).",
        met(median <= ratio_goal),
        posed.ram_bytes,
        met(posed.ram_bytes <= ram_goal),
        statics.ram_bytes
    );
    println!(
        "   {} {} {w}x{h}: median ratio posed / static {median:.3}",
        posed.scene,
        core.name()
    );
    s
}

/// The host's counts of each camera's frame at 320x240 (`f32` vertices): polygons visited and
/// drawn, posed and static; where the posed frame's work goes.
fn host_counts(prepared: &Prepared, cameras: &[OrbitAngles]) -> Result<String, String> {
    let size = (320, 240);
    let parts = Parts::parse(&prepared.posed.peel_bytes).map_err(|e| e.to_string())?;
    let world = parts.world().ok_or("no world")?;
    let scenes: Vec<Scene<'_>> = (0..OBJECTS as u32)
        .filter_map(|k| parts.object(k).map(|(_, s)| s))
        .collect();
    let mut s = String::from(
        "\n### Host counts, 320x240\n\n| camera | posed visited | static visited | posed drawn \
         | static drawn |\n|--:|--:|--:|--:|--:|\n",
    );
    for (k, ((&angles, (pose, header)), scene)) in cameras
        .iter()
        .zip(&prepared.poses)
        .zip(&prepared.statics)
        .enumerate()
    {
        let objects = posed(&scenes, pose);
        let p = render_posed_with(
            Some(&world),
            &objects,
            &shot(header, angles, size),
            &settings(false),
        )?
        .stats;
        let static_header = header_of(&scene.peel_bytes, &scene.peel)?;
        let q = render_bytes_with(
            &scene.peel_bytes,
            &shot(&static_header, angles, size),
            &settings(false),
        )?
        .stats;
        let _ = writeln!(
            s,
            "| {k} | {} | {} | {} | {} |",
            p.polygons_visited, q.polygons_visited, p.polygons_drawn, q.polygons_drawn
        );
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_world_is_the_layouts_and_the_static_geometry_is_posed() {
        let dir = std::env::temp_dir().join(format!("peel-target-objects-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let layout = Layout {
            unit: 2.5,
            height: 4.0,
        };
        let path = dir.join("objects-world.obj");
        write_world(&layout, &path).unwrap();
        let world = load(&path).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        // The ground's two triangles and twelve a box, each group in its own colour.
        assert_eq!(world.triangles.len(), 2 + 12 * 4);
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for t in &world.triangles {
            for v in t.vertices {
                (lo, hi) = (lo.min(v), hi.max(v));
            }
        }
        assert_eq!(
            (lo, hi),
            (DVec3::new(-10.0, 0.0, -10.0), DVec3::new(10.0, 4.0, 10.0))
        );
        let colours: std::collections::HashSet<[u8; 3]> =
            world.triangles.iter().map(|t| t.colour).collect();
        assert_eq!(colours.len(), 5);

        // An object turned a quarter about y and moved: each corner at T + R p.
        let object = peel_compiler::tools::scenes::mesh(vec![[
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.0, 0.0, 1.0),
        ]]);
        let quarter = Pose {
            rotation: glam::Mat3::from_cols(glam::Vec3::Z * -1.0, glam::Vec3::Y, glam::Vec3::X),
            translation: glam::Vec3::new(3.0, 0.5, -2.0),
        };
        let merged = merge(
            &world,
            &[object.clone(), object],
            &[quarter, Pose::IDENTITY],
        );
        assert_eq!(merged.triangles.len(), world.triangles.len() + 2);
        let moved = merged.triangles[world.triangles.len()].vertices;
        assert_eq!(
            moved,
            [
                DVec3::new(3.0, 0.5, -3.0),
                DVec3::new(3.0, 1.5, -2.0),
                DVec3::new(4.0, 0.5, -2.0)
            ]
        );
        assert_eq!(
            merged.triangles[world.triangles.len() + 1].vertices[0],
            DVec3::X
        );
    }

    #[test]
    fn the_static_record_takes_medians_and_the_most_memory() {
        let record = |instructions, ram_bytes, differing| Record {
            scene: "objects-static".into(),
            method: "peel-front-to-back".into(),
            path: "stream".into(),
            shading: "flat".into(),
            core: "cortex-m4f".into(),
            width: 320,
            height: 240,
            triangles: 100,
            instructions,
            ram_bytes,
            framebuffer_bytes: 0,
            flash_bytes: ram_bytes * 10,
            text_bytes: 1,
            display_bytes: instructions / 10,
            display_writes: 2,
            differing_pixels: Some(differing),
            robust_errors: None,
            pending_peak: None,
            pending_records: None,
            pending_fallback: None,
            deterministic: true,
            objects: 0,
            transparent: false,
            fallback_rows: None,
            composite_peak: None,
            composite_runs: None,
        };
        let combined = combine(&[record(30, 5, 0), record(10, 7, 1), record(20, 6, 2)]).unwrap();
        assert_eq!(
            (
                combined.instructions,
                combined.ram_bytes,
                combined.flash_bytes
            ),
            (20, 7, 70)
        );
        assert_eq!(
            (combined.display_bytes, combined.differing_pixels),
            (2, Some(3))
        );
        assert!(combine(&[]).is_err());
    }
}
