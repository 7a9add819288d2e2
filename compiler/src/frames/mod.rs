//! Frames: `peel bench` — frame time against pixel error, for Peel's two drawing orders and the
//! classic baselines, on the same scenes and cameras in one run.
//!
//! Every method draws source triangle ids (`id + 1`) into a `W x H` id image; the error of a
//! frame is the number of pixels whose id differs from the exact ray-casting reference
//! ([`crate::reference`]): `robust_errors` counts only pixels whose sample point is farther
//! than 1/16 pixel from every projected edge (of the source triangles and of Peel's compiled
//! polygons), `all_errors` counts them all. Times are medians over the cameras of each scene;
//! `pixels_written` is the mean per frame (overdraw included). The baselines share the
//! runtime's clip, projection, snapping and fill, so only the visibility method differs.

mod newell;
mod prepare;
mod zbuffer;

use std::time::Instant;

use glam::DVec3;
use peel_runtime::camera::{Camera, Pose};
use peel_runtime::coverage::Coverage;
use peel_runtime::read::Scene;
use peel_runtime::render::{Renderer, Workspace};
use peel_runtime::target::{Framebuffer, Xrgb8888};
use peel_runtime::traverse::Order;
use peel_runtime::vertices::{CachedVertex, VertexCache};
use serde::Serialize;

use crate::compile::{compile_mesh, CompileOptions};
use crate::load::Mesh;
use crate::raster::{HOST_SPANS_PER_ROW, HOST_STACK, HOST_VERTS};
use crate::reference::{reference, RefCamera, Reference};

/// One (scene, method) result; the JSON keys are exactly these fields.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrameRecord {
    /// Scene name.
    pub scene: String,
    /// Method name.
    pub method: String,
    /// Median frame time over the cameras, milliseconds.
    pub median_frame_ms: f64,
    /// Mean pixels written per frame (overdraw included).
    pub pixels_written: u64,
    /// Mismatched pixels whose sample point is farther than 1/16 pixel from every edge.
    pub robust_errors: u64,
    /// All mismatched pixels.
    pub all_errors: u64,
    /// Mean polygons handed to the fill per frame (Peel methods; 0 when not counted).
    #[serde(skip)]
    pub polygons_drawn: u64,
}

/// A frame: an id image and the pixels written.
struct Drawn {
    ids: Vec<u32>,
    written: u64,
    polygons: u64,
}

/// A camera of the benchmark.
#[derive(Debug, Clone, Copy)]
pub struct BenchCamera {
    /// Eye (world).
    pub eye: DVec3,
    /// Target (world).
    pub target: DVec3,
}

/// `n` cameras on a ring around the scene's bounding box, alternating above and below.
pub fn ring_cameras(mesh: &Mesh, n: usize) -> Vec<BenchCamera> {
    let (lo, hi) = mesh_bounds(mesh);
    let c = (lo + hi) / 2.0;
    let r = (hi - lo).length().max(1e-9) / 2.0;
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64 + 0.2;
            let up = if k % 2 == 0 { 0.55 } else { -0.35 };
            BenchCamera {
                eye: c + DVec3::new(a.cos() * 2.3 * r, up * r, a.sin() * 2.3 * r),
                target: c,
            }
        })
        .collect()
}

fn mesh_bounds(mesh: &Mesh) -> (DVec3, DVec3) {
    mesh.triangles.iter().flat_map(|t| t.vertices).fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), v| (lo.min(v), hi.max(v)),
    )
}

/// Method names, in table order.
pub const METHODS: [&str; 6] = [
    "peel-front-to-back",
    "peel-back-to-front",
    "zbuffer-int",
    "zbuffer-f32",
    "newell",
    "naive-bsp",
];

/// Everything a scene needs once: compiled bytes, source triangles, camera and reference per view.
struct Prepared {
    bytes: Vec<u8>,
    naive: Option<Vec<u8>>,
    /// The source triangles as the baselines draw them.
    triangles: prepare::Triangles,
    views: Vec<(Camera, Reference)>,
}

fn prepare_scene(
    mesh: &Mesh,
    naive: Option<Vec<u8>>,
    cams: &[BenchCamera],
    width: u32,
    height: u32,
    compile: &CompileOptions,
) -> Result<Prepared, String> {
    let options = CompileOptions {
        ids: true,
        ..compile.clone()
    };
    let (_, bytes) = compile_mesh(mesh, &options, &|_| {}).map_err(|e| e.to_string())?;
    let scene = Scene::parse(&bytes).map_err(|e| e.to_string())?;
    let h = scene.header();
    let centre = DVec3::from_array(h.centre);
    let near = Camera::default_near(h.bounds_min, h.bounds_max);
    let polys: Vec<Vec<DVec3>> = (0..h.polygon_count)
        .map(|i| {
            let p = scene.polygon(i);
            (0..u32::from(p.vertex_count))
                .map(|k| centre + scene.polygon_vertex(&p, k).as_dvec3())
                .collect()
        })
        .collect();
    let triangles: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
    let mut views = Vec::new();
    for c in cams {
        let camera = Camera::look_at(Pose::new(c.eye, c.target), 60.0, width, height, near)
            .map_err(|e| e.to_string())?;
        let rc = RefCamera {
            eye: c.eye,
            target: c.target,
            up: DVec3::Y,
            fov_y_deg: 60.0,
            width,
            height,
            near,
        };
        views.push((camera, reference(&triangles, &polys, &rc)));
    }
    Ok(Prepared {
        bytes,
        naive,
        triangles: prepare::Triangles::new(&triangles, centre),
        views,
    })
}

/// Draw one frame with `method`; `SUB` is the fixed-point precision.
fn draw<const SUB: u32>(
    p: &Prepared,
    scenes: &mut Scenes<'_>,
    method: &str,
    camera: &Camera,
    work: &mut Work,
) -> Result<Drawn, String> {
    let (w, h) = (camera.width(), camera.height());
    let n = (w * h) as usize;
    match method {
        "peel-front-to-back" | "peel-back-to-front" | "naive-bsp" => {
            let (scene, memory) = if method == "naive-bsp" {
                let scene = scenes.naive.as_ref().ok_or("no naive BSP")?;
                (scene, &mut scenes.naive_memory)
            } else {
                (&scenes.peel, &mut scenes.peel_memory)
            };
            let order = if method == "peel-front-to-back" {
                Order::FrontToBack
            } else {
                Order::BackToFront
            };
            let mut ids = vec![0u32; n];
            let mut fb = Framebuffer::<Xrgb8888>::new(&mut ids, w, h).map_err(|e| e.to_string())?;
            let coverage = Coverage::new(&mut work.intervals, &mut work.counts, w, h)
                .map_err(|e| e.to_string())?;
            // A renderer per frame, as the method and precision change from frame to frame;
            // its vertex memory is cleared here, which the timed frame pays for.
            let mut renderer = Renderer::<SUB>::with_precision(&mut work.workspace)
                .span_memory(coverage)
                .vertex_memory(VertexCache::new(memory))
                .ids();
            if order == Order::BackToFront {
                renderer = renderer.back_to_front();
            }
            let view = camera.view(scene.header().centre);
            let stats = renderer
                .draw(scene, &view, &mut fb)
                .map_err(|e| e.to_string())?;
            Ok(Drawn {
                ids,
                written: stats.pixels_written,
                polygons: stats.polygons_drawn,
            })
        }
        "zbuffer-int" | "zbuffer-f32" | "newell" => {
            let view = camera.view(scenes.peel.header().centre);
            let tris = &mut work.triangles;
            prepare::prepare::<SUB>(&p.triangles, &view, &mut work.projected, tris);
            let mut ids = vec![0u32; n];
            let written = match method {
                "zbuffer-int" => {
                    work.depth_u32.resize(n, 0);
                    let mut f = zbuffer::ZFrame {
                        ids: &mut ids,
                        depth: &mut work.depth_u32,
                        width: w as usize,
                    };
                    zbuffer::render::<SUB, u32>(tris, &view, &mut f)
                }
                "zbuffer-f32" => {
                    work.depth_f32.resize(n, 0.0);
                    let mut f = zbuffer::ZFrame {
                        ids: &mut ids,
                        depth: &mut work.depth_f32,
                        width: w as usize,
                    };
                    zbuffer::render::<SUB, f32>(tris, &view, &mut f)
                }
                _ => newell::render::<SUB>(tris, &view, &mut ids),
            };
            Ok(Drawn {
                ids,
                written,
                polygons: 0,
            })
        }
        other => Err(format!("unknown method {other}")),
    }
}

/// Reused buffers.
struct Work {
    workspace: Box<Workspace<HOST_STACK, HOST_VERTS>>,
    intervals: Vec<(u16, u16)>,
    counts: Vec<u16>,
    depth_u32: Vec<u32>,
    depth_f32: Vec<f32>,
    triangles: Vec<prepare::Prepared>,
    projected: Vec<(glam::Vec3, peel_runtime::fill::FixedPoint)>,
}

/// A scene's files, validated once before any frame is timed (firmware parses a file once,
/// then draws many frames from it), and the memory of their projected vertices.
struct Scenes<'b> {
    peel: Scene<'b>,
    naive: Option<Scene<'b>>,
    peel_memory: Vec<CachedVertex>,
    naive_memory: Vec<CachedVertex>,
}

impl Work {
    fn new(height: u32) -> Self {
        Work {
            workspace: Box::default(),
            intervals: vec![(0, 0); HOST_SPANS_PER_ROW * height as usize],
            counts: vec![0; height as usize],
            depth_u32: Vec::new(),
            depth_f32: Vec::new(),
            triangles: Vec::new(),
            projected: Vec::new(),
        }
    }
}

fn errors(r: &Reference, ids: &[u32]) -> (u64, u64) {
    let mut robust = 0;
    let mut all = 0;
    for ((&want, &ok), &got) in r.ids.iter().zip(&r.robust).zip(ids) {
        if want != got {
            all += 1;
            robust += u64::from(ok);
        }
    }
    (robust, all)
}

/// The median of `v` (the mean of the middle two for an even count; 0 when empty).
pub(crate) fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return 0.0;
    }
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        (v[m - 1] + v[m]) / 2.0
    }
}

/// One timed row of a scene: a method at a fixed-point precision.
struct Variant {
    label: String,
    method: &'static str,
    sub: u32,
}

/// [`draw`] at the precision `sub` (0, 4, or else the default [`SUBPIXEL_BITS`]).
///
/// [`SUBPIXEL_BITS`]: peel_runtime::fill::SUBPIXEL_BITS
fn draw_at(
    sub: u32,
    p: &Prepared,
    scenes: &mut Scenes<'_>,
    method: &str,
    camera: &Camera,
    work: &mut Work,
) -> Result<Drawn, String> {
    match sub {
        0 => draw::<0>(p, scenes, method, camera, work),
        4 => draw::<4>(p, scenes, method, camera, work),
        _ => draw::<{ peel_runtime::fill::SUBPIXEL_BITS }>(p, scenes, method, camera, work),
    }
}

/// Every variant on every camera of a scene. Per camera, each variant in turn: one untimed
/// frame (for its pixels and errors, and to warm the caches with its own data, as a renderer
/// drawing frame after frame has them), then the fastest of three timed frames. Taking the
/// cameras in the outer loop spreads a busy moment of this shared machine over every method
/// rather than one; the minimum filters out the machine's other work, and the median over
/// cameras is taken next.
fn measure_scene(
    scene: &str,
    variants: &[Variant],
    p: &Prepared,
    work: &mut Work,
) -> Result<Vec<FrameRecord>, String> {
    let peel = Scene::parse(&p.bytes).map_err(|e| e.to_string())?;
    let naive = match &p.naive {
        Some(bytes) => Some(Scene::parse(bytes).map_err(|e| e.to_string())?),
        None => None,
    };
    let vertex_count = |s: &Scene<'_>| s.header().vertex_count as usize;
    let peel_memory = vec![CachedVertex::EMPTY; vertex_count(&peel)];
    let naive_memory = vec![CachedVertex::EMPTY; naive.as_ref().map_or(0, vertex_count)];
    let mut scenes = Scenes {
        peel,
        naive,
        peel_memory,
        naive_memory,
    };
    let n = variants.len();
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); n];
    let mut totals = vec![(0u64, 0u64, 0u64, 0u64); n];
    for (camera, r) in &p.views {
        for ((v, total), t) in variants.iter().zip(&mut totals).zip(&mut times) {
            let d = draw_at(v.sub, p, &mut scenes, v.method, camera, work)?;
            let (rb, al) = errors(r, &d.ids);
            total.0 += d.written;
            total.1 += d.polygons;
            total.2 += rb;
            total.3 += al;
            let mut best = f64::INFINITY;
            for _ in 0..3 {
                let start = Instant::now();
                draw_at(v.sub, p, &mut scenes, v.method, camera, work)?;
                best = best.min(start.elapsed().as_secs_f64() * 1e3);
            }
            t.push(best);
        }
    }
    let views = p.views.len().max(1) as u64;
    Ok(variants
        .iter()
        .zip(times.into_iter().zip(totals))
        .map(|(v, (t, (written, polygons, robust, all)))| FrameRecord {
            scene: scene.into(),
            method: v.label.clone(),
            median_frame_ms: median(t),
            pixels_written: written / views,
            robust_errors: robust,
            all_errors: all,
            polygons_drawn: polygons / views,
        })
        .collect())
}

/// One scene of the benchmark: its mesh and, when available, the naive BSP baseline's bytes.
pub struct BenchScene {
    /// Name in the table.
    pub name: String,
    /// Source triangles.
    pub mesh: Mesh,
    /// Seed 004's naive BSP of the mesh, as a `.peel` file with ids.
    pub naive_bsp: Option<Vec<u8>>,
}

/// The naive BSP baseline is abandoned on a scene once it holds more than this many polygons
/// per input triangle (the scene then has no `naive-bsp` row, and a notice says so).
pub const NAIVE_BSP_MAX_RATIO: u64 = 20;

/// A scene of the benchmark, with seed 004's naive BSP compiled to `.peel` bytes (ids on,
/// two-sided) unless it exceeds [`NAIVE_BSP_MAX_RATIO`] or is deeper than the host renderer's
/// stack; `log` gets a notice when it is skipped, and the build's figures otherwise.
pub fn bench_scene(
    name: &str,
    mesh: Mesh,
    log: &mut dyn FnMut(&str),
) -> Result<BenchScene, String> {
    use crate::bench::baselines::{naive_bsp_file, NaiveBsp};
    let limit = (mesh.triangles.len() as u64)
        .saturating_mul(NAIVE_BSP_MAX_RATIO)
        .max(1);
    let start = Instant::now();
    let built = naive_bsp_file(&mesh, limit, true, &CompileOptions::default().shading)
        .map_err(|e| format!("{name}: naive BSP: {e}"))?;
    let naive_bsp = match built {
        NaiveBsp::OverBudget { polygons, limit } => {
            log(&format!(
                "notice: {name}: naive BSP skipped, over {polygons} polygons (budget {limit} = \
                 {NAIVE_BSP_MAX_RATIO} x {} triangles)",
                mesh.triangles.len()
            ));
            None
        }
        NaiveBsp::Built(f) if f.tree.stats.max_depth > HOST_STACK as u64 => {
            log(&format!(
                "notice: {name}: naive BSP skipped, {} nodes deep (the host renderer's stack \
                 holds {HOST_STACK})",
                f.tree.stats.max_depth
            ));
            None
        }
        NaiveBsp::Built(f) => {
            log(&format!(
                "{name}: naive BSP: {} polygons ({:.2} x {} triangles), {} nodes, depth {}, \
                 {} cuts, {} bytes, {:.2} s",
                f.stats.output_polygons,
                f.stats.output_polygons as f64 / mesh.triangles.len().max(1) as f64,
                mesh.triangles.len(),
                f.stats.nodes,
                f.stats.max_depth,
                f.tree.stats.cuts,
                f.bytes.len(),
                start.elapsed().as_secs_f64()
            ));
            Some(f.bytes)
        }
    };
    Ok(BenchScene {
        name: name.to_string(),
        mesh,
        naive_bsp,
    })
}

/// Run every method on every scene (16 cameras each unless `cameras` says otherwise); also the
/// `SUBPIXEL_BITS` knob (0, 4, 8) for front to back, reported as extra rows named
/// `peel-front-to-back/sub0` etc. (not part of the six methods).
pub fn run(
    scenes: &[BenchScene],
    width: u32,
    height: u32,
    cameras: usize,
    log: &mut dyn FnMut(&str),
) -> Result<Vec<FrameRecord>, String> {
    let mut out = Vec::new();
    for s in scenes {
        log(&format!(
            "{}: {} triangles, preparing references",
            s.name,
            s.mesh.triangles.len()
        ));
        let cams = ring_cameras(&s.mesh, cameras);
        let p = prepare_scene(
            &s.mesh,
            s.naive_bsp.clone(),
            &cams,
            width,
            height,
            &CompileOptions::default(),
        )?;
        let mut work = Work::new(height);
        let mut variants: Vec<Variant> = METHODS
            .iter()
            .filter(|&&m| m != "naive-bsp" || p.naive.is_some())
            .map(|&m| Variant {
                label: m.to_string(),
                method: m,
                sub: peel_runtime::fill::SUBPIXEL_BITS,
            })
            .collect();
        for sub in [0, 4] {
            variants.push(Variant {
                label: format!("peel-front-to-back/sub{sub}"),
                method: "peel-front-to-back",
                sub,
            });
        }
        for r in measure_scene(&s.name, &variants, &p, &mut work)? {
            log(&format!(
                "  {}: {:.3} ms, {} robust errors",
                r.method, r.median_frame_ms, r.robust_errors
            ));
            out.push(r);
        }
    }
    Ok(out)
}

/// The JSON of `peel bench --json`: one record per (scene, method) of the six [`METHODS`]
/// (the `SUBPIXEL_BITS` rows are left out).
pub fn json(records: &[FrameRecord]) -> Result<String, String> {
    let main: Vec<&FrameRecord> = records
        .iter()
        .filter(|r| METHODS.contains(&r.method.as_str()))
        .collect();
    serde_json::to_string_pretty(&main).map_err(|e| e.to_string())
}

/// The records as a markdown table, with each method's time relative to the integer z-buffer
/// of the same scene (the baseline measured in the same run).
pub fn markdown(records: &[FrameRecord]) -> String {
    let mut s = String::from(
        "| scene | method | median frame (ms) | speed vs zbuffer-int | polygons drawn | pixels written | robust errors | all errors |\n|---|---|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in records {
        let base = records
            .iter()
            .find(|b| b.scene == r.scene && b.method == "zbuffer-int")
            .map(|b| b.median_frame_ms)
            .unwrap_or(f64::NAN);
        s += &format!(
            "| {} | {} | {:.3} | {:.2}x | {} | {} | {} | {} |\n",
            r.scene,
            r.method,
            r.median_frame_ms,
            base / r.median_frame_ms,
            if r.polygons_drawn > 0 {
                r.polygons_drawn.to_string()
            } else {
                "-".into()
            },
            r.pixels_written,
            r.robust_errors,
            r.all_errors
        );
    }
    s
}

/// A scatter plot (PNG bytes) of median frame time against all errors, one colour per method.
pub fn plot(records: &[FrameRecord]) -> Result<Vec<u8>, String> {
    use plotters::prelude::*;
    static FONT: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    FONT.get_or_init(|| {
        // plotters draws text with ab_glyph from a font we ship: no system font is needed.
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .map_err(|_| "cannot load the plot font".to_string())
    })
    .clone()?;
    let (w, h) = (900u32, 600u32);
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let max_t = records
            .iter()
            .map(|r| r.median_frame_ms)
            .fold(1e-3, f64::max)
            * 2.0;
        let min_t = records
            .iter()
            .map(|r| r.median_frame_ms)
            .fold(max_t, f64::min)
            .max(1e-4)
            / 2.0;
        let max_e = records
            .iter()
            .map(|r| r.all_errors)
            .max()
            .unwrap_or(1)
            .max(1) as f64
            * 2.0;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "frame time vs pixel errors (16 cameras per scene)",
                ("sans-serif", 22),
            )
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d((min_t..max_t).log_scale(), (0.5f64..max_e).log_scale())
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc("median frame time (ms)")
            .y_desc("mismatched pixels + 1 (all)")
            .draw()
            .map_err(|e| e.to_string())?;
        let palette = [RED, BLUE, GREEN, MAGENTA, CYAN, BLACK];
        for (k, m) in METHODS.iter().enumerate() {
            let colour = palette[k % palette.len()];
            let pts: Vec<(f64, f64)> = records
                .iter()
                .filter(|r| r.method == *m)
                .map(|r| (r.median_frame_ms, r.all_errors as f64 + 1.0))
                .collect();
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 5, colour.filled())))
                .map_err(|e| e.to_string())?
                .label(*m)
                .legend(move |(x, y)| Circle::new((x, y), 5, colour.filled()));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    let frame = crate::raster::Frame {
        width: w,
        height: h,
        pixels: rgb
            .chunks(3)
            .map(|c| (u32::from(c[0]) << 16) | (u32::from(c[1]) << 8) | u32::from(c[2]))
            .collect(),
        stats: Default::default(),
    };
    crate::raster::png(&frame)
}

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
        let front_to_back = Variant {
            label: "peel-front-to-back".into(),
            method: "peel-front-to-back",
            sub: peel_runtime::fill::SUBPIXEL_BITS,
        };
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

#[cfg(test)]
mod tests {
    use super::*;

    /// On a small closed scene, Peel (both orders) and the z-buffers have no robust errors, and
    /// front to back writes fewer pixels than back to front.
    #[test]
    fn methods_agree_with_the_reference_on_a_box_grid() {
        let scene = BenchScene {
            name: "grid".into(),
            mesh: crate::scenes::box_grid(2),
            naive_bsp: None,
        };
        let records = run(&[scene], 64, 48, 4, &mut |_| {}).unwrap();
        let get = |m: &str| records.iter().find(|r| r.method == m).unwrap();
        for m in [
            "peel-front-to-back",
            "peel-back-to-front",
            "zbuffer-int",
            "zbuffer-f32",
        ] {
            assert_eq!(get(m).robust_errors, 0, "{m}");
        }
        assert!(
            get("peel-front-to-back").pixels_written < get("peel-back-to-front").pixels_written
        );
        assert!(markdown(&records).contains("| grid | zbuffer-int |"));
    }

    /// Newell's sort without splitting cannot draw a cyclic overlap right: it must show errors
    /// where Peel shows none.
    #[test]
    fn newell_fails_on_a_cycle_peel_does_not() {
        let mesh = crate::load::load_obj(
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../fixtures/cyclic_triangles.obj"),
        )
        .unwrap();
        let scene = BenchScene {
            name: "cyclic".into(),
            mesh,
            naive_bsp: None,
        };
        let cams = [BenchCamera {
            eye: DVec3::new(0.0, 0.0, 6.0),
            target: DVec3::ZERO,
        }];
        let p =
            prepare_scene(&scene.mesh, None, &cams, 64, 64, &CompileOptions::default()).unwrap();
        let mut work = Work::new(64);
        let variant = |m: &'static str| Variant {
            label: m.into(),
            method: m,
            sub: 8,
        };
        let rows = measure_scene(
            "c",
            &[variant("peel-front-to-back"), variant("newell")],
            &p,
            &mut work,
        )
        .unwrap();
        let (peel, newell) = (&rows[0], &rows[1]);
        assert_eq!(peel.method, "peel-front-to-back");
        assert_eq!(peel.robust_errors, 0);
        assert!(newell.robust_errors > 0, "a cycle cannot be sorted");
    }

    /// The whole bench on a small soup (cycles, so the naive BSP cuts): every method has a
    /// record with exactly the JSON keys, and the naive BSP, an exact BSP drawn back to front,
    /// matches the reference on every robust pixel.
    #[test]
    fn bench_json_has_all_six_methods_and_the_naive_bsp_is_exact() {
        let mesh = crate::scenes::soup(40, 0.5, 3);
        let triangles = mesh.triangles.len();
        let mut notes = Vec::new();
        let scene = bench_scene("soup-40", mesh, &mut |m| notes.push(m.to_string())).unwrap();
        let naive = scene
            .naive_bsp
            .as_deref()
            .expect("the naive BSP fits its budget");
        let header = Scene::parse(naive).unwrap().header();
        assert!(
            header.polygon_count as usize > triangles,
            "{notes:?}: no cut"
        );
        let records = run(&[scene], 64, 48, 4, &mut |_| {}).unwrap();
        let text = json(&records).unwrap();
        let value: serde_json::Value = serde_json::from_str(&text).unwrap();
        let rows = value.as_array().unwrap();
        assert_eq!(rows.len(), METHODS.len());
        for row in rows {
            let mut keys: Vec<&str> = row
                .as_object()
                .unwrap()
                .keys()
                .map(|k| k.as_str())
                .collect();
            keys.sort_unstable();
            assert_eq!(
                keys,
                [
                    "all_errors",
                    "median_frame_ms",
                    "method",
                    "pixels_written",
                    "robust_errors",
                    "scene"
                ]
            );
        }
        let methods: Vec<&str> = rows.iter().map(|r| r["method"].as_str().unwrap()).collect();
        assert_eq!(methods, METHODS);
        let naive = rows.iter().find(|r| r["method"] == "naive-bsp").unwrap();
        assert_eq!(naive["robust_errors"], 0);
        assert!(naive["pixels_written"].as_u64().unwrap() > 0);
        for r in rows.iter().filter(|r| r["method"] != "newell") {
            assert_eq!(r["robust_errors"], 0, "{r}");
        }
    }

    /// The naive BSP stops as soon as it exceeds its polygon budget.
    #[test]
    fn a_naive_bsp_over_budget_stops() {
        use crate::bench::baselines::{naive_bsp_file, NaiveBsp};
        let mesh = crate::scenes::soup(40, 0.5, 3);
        let shading = CompileOptions::default().shading;
        match naive_bsp_file(&mesh, 45, true, &shading).unwrap() {
            NaiveBsp::OverBudget { polygons, limit } => assert!(polygons > limit && limit == 45),
            NaiveBsp::Built(_) => panic!("40 crossing triangles fit in 45 polygons"),
        }
    }

    #[test]
    fn plot_is_a_png() {
        let r = FrameRecord {
            scene: "s".into(),
            method: "zbuffer-int".into(),
            median_frame_ms: 1.0,
            pixels_written: 10,
            robust_errors: 0,
            all_errors: 3,
            polygons_drawn: 0,
        };
        let png = plot(&[r]).unwrap();
        assert_eq!(&png[1..4], b"PNG");
    }
}
