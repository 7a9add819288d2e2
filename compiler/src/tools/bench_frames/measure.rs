//! Measurement: each method draws every camera of a scene into an id image, timed, and the
//! image is compared with the exact reference. Kept apart from the reports so that what is
//! timed is easy to see.

use std::time::Instant;

use glam::DVec3;
use peel_runtime::camera::Camera;
use peel_runtime::clip;
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Framebuffer, Xrgb8888};
use peel_runtime::fill::{EdgeWalk, FixedPoint, SUBPIXEL_BITS};
use peel_runtime::read::Scene;
use peel_runtime::render::{Renderer, Workspace};
use peel_runtime::traverse::{Order, StackEntry};
use peel_runtime::vertices::{CachedVertex, VertexCache};

use super::frame::bytes;
use super::warnock::Split;
use super::{newell, prepare, warnock, watkins, weiler_atherton, zbuffer, FrameRecord, Method};
use crate::compile::{compile_mesh, CompileOptions};
use crate::load::Mesh;
use crate::tools::median;
use crate::tools::raster::{HOST_SPANS_PER_ROW, HOST_STACK, HOST_VERTS};
use crate::tools::reference::{reference, Reference};
use crate::tools::shot::Shot;

/// A frame: an id image, the pixels written, the polygons drawn and the memory it needed.
struct Drawn {
    ids: Vec<u32>,
    written: u64,
    polygons: u64,
    memory_bytes: u64,
}

/// The memory a frame of the display tree `scene` needs besides the scene: a workspace with
/// the stack its depth needs and clip buffers for its largest polygon, vertex memory keeping
/// every vertex, and front to back the span memory the sizes file recommends (the host's 64
/// intervals per row, or fewer where fewer can never run out: a row holds at most one interval
/// per polygon and `(width + 1) / 2` in all).
fn tree_memory<const SUB: u32>(scene: &Scene<'_>, front_to_back: bool, camera: &Camera) -> u64 {
    let h = scene.header();
    let verts = clip::buffer_len_for(h.max_polygon_vertices) as usize;
    let workspace = bytes::<StackEntry>(h.max_depth as usize)
        + bytes::<glam::Vec3>(2 * verts)
        + bytes::<FixedPoint<SUB>>(verts)
        + bytes::<EdgeWalk>(verts);
    let vertices = bytes::<CachedVertex>((h.vertex_count as usize).next_power_of_two());
    let spans = if front_to_back {
        let per_row = HOST_SPANS_PER_ROW
            .min((camera.width() as usize).div_ceil(2))
            .min(h.polygon_count as usize);
        let rows = camera.height() as usize;
        bytes::<(u16, u16)>(per_row * rows) + bytes::<u16>(rows)
    } else {
        0
    };
    workspace + vertices + spans
}

/// Everything a scene needs once: compiled bytes, source triangles, camera and reference per view.
pub(super) struct Prepared {
    bytes: Vec<u8>,
    /// The naive BSP baseline's bytes, when the scene has them.
    pub(super) naive: Option<Vec<u8>>,
    /// The source triangles as the baselines draw them.
    triangles: prepare::Triangles,
    views: Vec<(Camera, Reference)>,
}

pub(super) fn prepare_scene(
    mesh: &Mesh,
    naive: Option<Vec<u8>>,
    shots: &[Shot],
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
    for shot in shots {
        let camera = shot.camera(&h)?;
        views.push((camera, reference(&triangles, &polys, shot, camera.near())));
    }
    Ok(Prepared {
        bytes,
        naive,
        triangles: prepare::Triangles::new(&triangles, centre),
        views,
    })
}

/// Draw one frame with `method`; `SUB` is the fixed-point precision, that of `at`.
fn draw<const SUB: u32>(
    scenes: &mut Scenes<'_>,
    method: Method,
    camera: &Camera,
    work: &mut Buffers,
    at: &mut AtPrecision<SUB>,
) -> Result<Drawn, String> {
    let (w, h) = (camera.width(), camera.height());
    let n = (w * h) as usize;
    match method {
        Method::PeelFrontToBack | Method::PeelBackToFront | Method::NaiveBsp => {
            let (scene, memory) = if method == Method::NaiveBsp {
                let scene = scenes.naive.as_ref().ok_or("no naive BSP")?;
                (scene, &mut scenes.naive_memory)
            } else {
                (&scenes.peel, &mut scenes.peel_memory)
            };
            let order = if method == Method::PeelFrontToBack {
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
            let mut renderer = Renderer::with_precision(&mut at.workspace)
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
                memory_bytes: tree_memory::<SUB>(scene, order == Order::FrontToBack, camera),
            })
        }
        Method::ZbufferInt
        | Method::ZbufferF32
        | Method::Newell
        | Method::Watkins
        | Method::WarnockQuadrants
        | Method::WarnockEnclosing
        | Method::WeilerAtherton => {
            let view = camera.view(scenes.peel.header().centre);
            let tris = &mut at.triangles;
            let projected = prepare::prepare(scenes.triangles, &view, &mut at.projected, tris);
            let mut ids = vec![0u32; n];
            let frame = match method {
                Method::ZbufferInt => {
                    zbuffer::draw_ids::<SUB, u32>(tris, &view, &mut ids, &mut work.depth_u32)
                }
                Method::ZbufferF32 => {
                    zbuffer::draw_ids::<SUB, f32>(tris, &view, &mut ids, &mut work.depth_f32)
                }
                Method::Newell => newell::draw::<SUB>(tris, &view, &mut ids),
                Method::Watkins => watkins::draw::<SUB>(tris, &view, &mut ids),
                Method::WarnockQuadrants => {
                    warnock::draw::<SUB>(tris, &view, &mut ids, Split::Quadrants)
                }
                Method::WarnockEnclosing => {
                    warnock::draw::<SUB>(tris, &view, &mut ids, Split::Enclosing)
                }
                _ => weiler_atherton::draw::<SUB>(tris, &view, &mut ids),
            };
            Ok(Drawn {
                ids,
                written: frame.written,
                polygons: 0,
                memory_bytes: projected + frame.memory_bytes,
            })
        }
    }
}

/// Reused buffers: those any precision uses, and those holding snapped points, one set per
/// precision timed.
pub(super) struct Work {
    buffers: Buffers,
    sub0: AtPrecision<0>,
    sub4: AtPrecision<4>,
    sub8: AtPrecision<SUBPIXEL_BITS>,
}

/// The buffers of every precision.
struct Buffers {
    intervals: Vec<(u16, u16)>,
    counts: Vec<u16>,
    depth_u32: Vec<u32>,
    depth_f32: Vec<f32>,
}

/// The buffers holding points snapped at `SUB` fractional bits: the renderer's workspace, the
/// baselines' triangles and projected vertices.
struct AtPrecision<const SUB: u32> {
    workspace: Box<Workspace<HOST_STACK, HOST_VERTS, SUB>>,
    triangles: Vec<prepare::Prepared<SUB>>,
    projected: Vec<(glam::Vec3, FixedPoint<SUB>)>,
}

impl<const SUB: u32> AtPrecision<SUB> {
    fn new() -> Self {
        AtPrecision {
            workspace: Box::default(),
            triangles: Vec::new(),
            projected: Vec::new(),
        }
    }
}

/// A scene's files, validated once before any frame is timed (firmware parses a file once,
/// then draws many frames from it), the memory of their projected vertices, and the source
/// triangles the baselines draw.
struct Scenes<'b> {
    peel: Scene<'b>,
    naive: Option<Scene<'b>>,
    peel_memory: Vec<CachedVertex>,
    naive_memory: Vec<CachedVertex>,
    triangles: &'b prepare::Triangles,
}

impl Scenes<'_> {
    /// One frame of `v` seen by `camera`: [`draw`] at the variant's precision (0, 4, or else
    /// the default [`SUBPIXEL_BITS`]).
    ///
    /// [`SUBPIXEL_BITS`]: peel_runtime::fill::SUBPIXEL_BITS
    fn draw(&mut self, v: &Variant, camera: &Camera, work: &mut Work) -> Result<Drawn, String> {
        let Work {
            buffers,
            sub0,
            sub4,
            sub8,
        } = work;
        match v.sub {
            0 => draw(self, v.method, camera, buffers, sub0),
            4 => draw(self, v.method, camera, buffers, sub4),
            _ => draw(self, v.method, camera, buffers, sub8),
        }
    }
}

impl Work {
    pub(super) fn new(height: u32) -> Self {
        Work {
            buffers: Buffers {
                intervals: vec![(0, 0); HOST_SPANS_PER_ROW * height as usize],
                counts: vec![0; height as usize],
                depth_u32: Vec::new(),
                depth_f32: Vec::new(),
            },
            sub0: AtPrecision::new(),
            sub4: AtPrecision::new(),
            sub8: AtPrecision::new(),
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

/// One timed row of a scene: a method at a fixed-point precision.
pub(super) struct Variant {
    label: String,
    method: Method,
    sub: u32,
}

impl Variant {
    /// `method` at the default precision, named as the method.
    pub(super) fn new(method: Method) -> Variant {
        Variant {
            label: method.name().to_string(),
            method,
            sub: SUBPIXEL_BITS,
        }
    }

    /// `method` at `sub` bits of fixed-point precision, named `<method>/sub<sub>`.
    pub(super) fn at(method: Method, sub: u32) -> Variant {
        Variant {
            label: format!("{}/sub{sub}", method.name()),
            method,
            sub,
        }
    }
}

/// Every variant on every camera of a scene. Per camera, each variant in turn: one untimed
/// frame (for its pixels and errors, and to warm the caches with its own data, as a renderer
/// drawing frame after frame has them), then the fastest of three timed frames. Taking the
/// cameras in the outer loop spreads a busy moment of this shared machine over every method
/// rather than one; the minimum filters out the machine's other work, and the median over
/// cameras is taken next.
pub(super) fn measure_scene(
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
    // One entry per vertex (rounded up to the power of two the memory uses): every vertex kept.
    let vertex_count = |s: &Scene<'_>| (s.header().vertex_count as usize).next_power_of_two();
    let peel_memory = vec![CachedVertex::EMPTY; vertex_count(&peel)];
    let naive_memory = vec![CachedVertex::EMPTY; naive.as_ref().map_or(0, vertex_count)];
    let mut scenes = Scenes {
        peel,
        naive,
        peel_memory,
        naive_memory,
        triangles: &p.triangles,
    };
    let n = variants.len();
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); n];
    let mut totals = vec![(0u64, 0u64, 0u64, 0u64, 0u64); n];
    for (camera, r) in &p.views {
        for ((v, total), t) in variants.iter().zip(&mut totals).zip(&mut times) {
            let d = scenes.draw(v, camera, work)?;
            let (rb, al) = errors(r, &d.ids);
            total.0 += d.written;
            total.1 += d.polygons;
            total.2 += rb;
            total.3 += al;
            total.4 = total.4.max(d.memory_bytes);
            let mut best = f64::INFINITY;
            for _ in 0..3 {
                let start = Instant::now();
                scenes.draw(v, camera, work)?;
                best = best.min(start.elapsed().as_secs_f64() * 1e3);
            }
            t.push(best);
        }
    }
    let views = p.views.len().max(1) as u64;
    Ok(variants
        .iter()
        .zip(times.into_iter().zip(totals))
        .map(
            |(v, (t, (written, polygons, robust, all, memory)))| FrameRecord {
                scene: scene.into(),
                method: v.label.clone(),
                median_frame_ms: median(t),
                pixels_written: written / views,
                robust_errors: robust,
                all_errors: all,
                memory_bytes: memory,
                polygons_drawn: polygons / views,
            },
        )
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::bench_frames::BenchScene;

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
        let shots = [Shot::new(DVec3::new(0.0, 0.0, 6.0), DVec3::ZERO, 64, 64)];
        let p = prepare_scene(&scene.mesh, None, &shots, &CompileOptions::default()).unwrap();
        let mut work = Work::new(64);
        let rows = measure_scene(
            "c",
            &[
                Variant::new(Method::PeelFrontToBack),
                Variant::new(Method::Newell),
            ],
            &p,
            &mut work,
        )
        .unwrap();
        let (peel, newell) = (&rows[0], &rows[1]);
        assert_eq!(peel.method, "peel-front-to-back");
        assert_eq!(peel.robust_errors, 0);
        assert!(newell.robust_errors > 0, "a cycle cannot be sorted");
    }
}
