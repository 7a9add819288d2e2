//! Measurement: each method draws every camera of a scene into an id image, timed, and the
//! image is compared with the exact reference. Kept apart from the reports so that what is
//! timed is easy to see.

use std::time::Instant;

use glam::DVec3;
use peel_runtime::camera::{Camera, Pose};
use peel_runtime::coverage::Coverage;
use peel_runtime::read::Scene;
use peel_runtime::render::{Renderer, Workspace};
use peel_runtime::target::{Framebuffer, Xrgb8888};
use peel_runtime::traverse::Order;
use peel_runtime::vertices::{CachedVertex, VertexCache};

use super::{newell, prepare, zbuffer, BenchCamera, FrameRecord, Method};
use crate::compile::{compile_mesh, CompileOptions};
use crate::load::Mesh;
use crate::tools::raster::{HOST_SPANS_PER_ROW, HOST_STACK, HOST_VERTS};
use crate::tools::reference::{reference, RefCamera, Reference};

/// A frame: an id image and the pixels written.
struct Drawn {
    ids: Vec<u32>,
    written: u64,
    polygons: u64,
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
    method: Method,
    camera: &Camera,
    work: &mut Work,
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
        Method::ZbufferInt | Method::ZbufferF32 | Method::Newell => {
            let view = camera.view(scenes.peel.header().centre);
            let tris = &mut work.triangles;
            prepare::prepare::<SUB>(&p.triangles, &view, &mut work.projected, tris);
            let mut ids = vec![0u32; n];
            let written = match method {
                Method::ZbufferInt => {
                    work.depth_u32.resize(n, 0);
                    let mut f = zbuffer::ZFrame {
                        ids: &mut ids,
                        depth: &mut work.depth_u32,
                        width: w as usize,
                    };
                    zbuffer::render::<SUB, u32>(tris, &view, &mut f)
                }
                Method::ZbufferF32 => {
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
    }
}

/// Reused buffers.
pub(super) struct Work {
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
    pub(super) fn new(height: u32) -> Self {
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
            sub: peel_runtime::fill::SUBPIXEL_BITS,
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

/// [`draw`] at the precision `sub` (0, 4, or else the default [`SUBPIXEL_BITS`]).
///
/// [`SUBPIXEL_BITS`]: peel_runtime::fill::SUBPIXEL_BITS
fn draw_at(
    sub: u32,
    p: &Prepared,
    scenes: &mut Scenes<'_>,
    method: Method,
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
        let cams = [BenchCamera {
            eye: DVec3::new(0.0, 0.0, 6.0),
            target: DVec3::ZERO,
        }];
        let p =
            prepare_scene(&scene.mesh, None, &cams, 64, 64, &CompileOptions::default()).unwrap();
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
