//! `peel bench`: frame time against pixel error, for Peel's two drawing orders and the
//! classic baselines, on the same scenes and cameras in one run.
//!
//! Every method draws source triangle ids (`id + 1`) into a `W x H` id image; the error of a
//! frame is the number of pixels whose id differs from the exact ray-casting reference
//! ([`crate::tools::reference`]): `robust_errors` counts only pixels whose sample point is farther
//! than 1/16 pixel from every projected edge (of the source triangles and of Peel's compiled
//! polygons), `all_errors` counts them all. Times are medians over the cameras of each scene;
//! `pixels_written` is the mean per frame (overdraw included), `memory_bytes` the most any
//! camera's frame needed besides the scene and the image. The baselines share the runtime's
//! clip, projection, snapping and fill, so only the visibility method differs.
//!
//! Timing is in `measure`, the reports in `report` (table, JSON) and `plot`, the
//! `--candidates` knob in `candidates`; the baselines are `zbuffer`, `newell`, `watkins`,
//! `warnock` and `weiler_atherton` over the front end `prepare`, writing and reporting
//! through `frame`; this module holds the scenes, cameras and the run.

mod candidates;
mod frame;
mod measure;
mod newell;
mod plot;
mod prepare;
mod report;
#[cfg(test)]
mod testing;
mod transparency;
mod warnock;
mod watkins;
mod weiler_atherton;
mod zbuffer;

use std::time::Instant;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::compile::CompileOptions;
use crate::load::Mesh;
use crate::tools::raster::HOST_STACK;
use crate::tools::shot::Shot;
use measure::{measure_scene, prepare_scene, Variant, Work};

pub use candidates::candidates_knob;
pub use plot::{bitmap_png, plot};
pub use report::{from_json, json, markdown, markdown_of};
pub use transparency::{run_transparent, SORTED, TOLERANCE};
pub use zbuffer::sorted_picture;

/// A visibility method of the benchmark: Peel's two drawing orders and the baselines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Peel, front to back with span memory (no overdraw).
    PeelFrontToBack,
    /// Peel, back to front (painter's order, overdraw allowed).
    PeelBackToFront,
    /// Z-buffer with fixed-point integer depth.
    ZbufferInt,
    /// Z-buffer with `f32` depth.
    ZbufferF32,
    /// Newell, Newell and Sancha's depth sort, without splitting.
    Newell,
    /// A naive BSP of the source triangles, drawn back to front.
    NaiveBsp,
    /// Watkins' scanline method: per row, zones between segment ends, each the nearest
    /// segment's.
    Watkins,
    /// Warnock's area subdivision into quadrants.
    WarnockQuadrants,
    /// Warnock's area subdivision at the box of a polygon (the later variant).
    WarnockEnclosing,
    /// Weiler and Atherton's polygonal windows.
    WeilerAtherton,
}

impl Method {
    /// Every method, in table order.
    pub const ALL: [Method; 10] = [
        Method::PeelFrontToBack,
        Method::PeelBackToFront,
        Method::ZbufferInt,
        Method::ZbufferF32,
        Method::Newell,
        Method::NaiveBsp,
        Method::Watkins,
        Method::WarnockQuadrants,
        Method::WarnockEnclosing,
        Method::WeilerAtherton,
    ];

    /// The name in tables, plots and JSON records.
    pub const fn name(self) -> &'static str {
        match self {
            Method::PeelFrontToBack => "peel-front-to-back",
            Method::PeelBackToFront => "peel-back-to-front",
            Method::ZbufferInt => "zbuffer-int",
            Method::ZbufferF32 => "zbuffer-f32",
            Method::Newell => "newell",
            Method::NaiveBsp => "naive-bsp",
            Method::Watkins => "watkins",
            Method::WarnockQuadrants => "warnock-quadrants",
            Method::WarnockEnclosing => "warnock-enclosing",
            Method::WeilerAtherton => "weiler-atherton",
        }
    }

    /// The method named `name` (`None` for the extra precision rows, `…/sub0` etc.).
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }
}

/// One (scene, method) result; the JSON keys are exactly these fields.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameRecord {
    /// Scene name.
    pub scene: String,
    /// The [`Method`]'s name; `peel-front-to-back/sub0` etc. for the extra precision rows.
    pub method: String,
    /// Median frame time over the cameras, milliseconds.
    pub median_frame_ms: f64,
    /// Mean pixels written per frame (overdraw included).
    pub pixels_written: u64,
    /// Mismatched pixels whose sample point is farther than 1/16 pixel from every edge.
    pub robust_errors: u64,
    /// All mismatched pixels.
    pub all_errors: u64,
    /// The most bytes a frame of the method needed besides the scene and the image (the
    /// largest over the cameras): depth buffer, span and vertex memory, lists, work stacks.
    pub memory_bytes: u64,
    /// Mean polygons handed to the fill per frame (Peel methods; 0 when not counted).
    pub polygons_drawn: u64,
}

/// `n` shots of `width x height` pixels from a ring around the scene's bounding box,
/// alternating above and below, looking at its centre (the other settings the defaults).
pub fn ring_shots(mesh: &Mesh, n: usize, width: u32, height: u32) -> Vec<Shot> {
    let (lo, hi) = mesh_bounds(mesh);
    let c = (lo + hi) / 2.0;
    let r = (hi - lo).length().max(1e-9) / 2.0;
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64 + 0.2;
            let up = if k % 2 == 0 { 0.55 } else { -0.35 };
            let eye = c + DVec3::new(a.cos() * 2.3 * r, up * r, a.sin() * 2.3 * r);
            Shot::new(eye, c, width, height)
        })
        .collect()
}

fn mesh_bounds(mesh: &Mesh) -> (DVec3, DVec3) {
    mesh.triangles.iter().flat_map(|t| t.vertices).fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), v| (lo.min(v), hi.max(v)),
    )
}

/// One scene of the benchmark: its mesh and, when available, the naive BSP baseline's bytes.
pub struct BenchScene {
    /// Name in the table.
    pub name: String,
    /// Source triangles.
    pub mesh: Mesh,
    /// The naive BSP of the mesh (Fuchs, Kedem and Naylor's), as a `.peel` file with ids.
    pub naive_bsp: Option<Vec<u8>>,
}

/// The naive BSP baseline is abandoned on a scene once it holds more than this many polygons
/// per input triangle (the scene then has no `naive-bsp` row, and a notice says so).
pub const NAIVE_BSP_MAX_RATIO: u64 = 20;

/// A scene of the benchmark, with its naive BSP compiled to `.peel` bytes (ids on,
/// two-sided) unless it exceeds [`NAIVE_BSP_MAX_RATIO`] or is deeper than the host renderer's
/// stack; `log` gets a notice when it is skipped, and the build's figures otherwise.
pub fn frame_scene(
    name: &str,
    mesh: Mesh,
    log: &mut dyn FnMut(&str),
) -> Result<BenchScene, String> {
    use crate::tools::baselines::{naive_bsp_file, NaiveBsp};
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

/// Run every [`Method`] on every scene (16 cameras each unless `cameras` says otherwise); also the
/// `SUBPIXEL_BITS` knob (0, 4, 8) for front to back, reported as extra rows named
/// `peel-front-to-back/sub0` etc. (not part of the methods).
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
        let shots = ring_shots(&s.mesh, cameras, width, height);
        let p = prepare_scene(
            &s.mesh,
            s.naive_bsp.clone(),
            &shots,
            &CompileOptions::default(),
        )?;
        let mut work = Work::new(height);
        let mut variants: Vec<Variant> = Method::ALL
            .into_iter()
            .filter(|&m| m != Method::NaiveBsp || p.naive.is_some())
            .map(Variant::new)
            .collect();
        for sub in [0, 4] {
            variants.push(Variant::at(Method::PeelFrontToBack, sub));
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

#[cfg(test)]
mod tests {
    use super::*;
    use peel_runtime::read::Scene;

    /// On a small closed scene, Peel (both orders) and the z-buffers have no robust errors, and
    /// front to back writes fewer pixels than back to front.
    #[test]
    fn methods_agree_with_the_reference_on_a_box_grid() {
        let scene = BenchScene {
            name: "grid".into(),
            mesh: crate::tools::scenes::box_grid(2),
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

    /// The whole bench on a small soup (cycles, so the naive BSP cuts): every method has a
    /// record with exactly the JSON keys, and the naive BSP, an exact BSP drawn back to front,
    /// matches the reference on every robust pixel.
    #[test]
    fn bench_json_has_every_method_and_the_naive_bsp_is_exact() {
        let mesh = crate::tools::scenes::soup(40, 0.5, 3);
        let triangles = mesh.triangles.len();
        let mut notes = Vec::new();
        let scene = frame_scene("soup-40", mesh, &mut |m| notes.push(m.to_string())).unwrap();
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
        // Every record, the `SUBPIXEL_BITS` rows too, and back to the same records and table.
        assert_eq!(from_json(&text).unwrap(), records);
        assert_eq!(markdown(&from_json(&text).unwrap()), markdown(&records));
        let rows = value.as_array().unwrap();
        assert_eq!(rows.len(), Method::ALL.len() + 2);
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
                    "memory_bytes",
                    "method",
                    "pixels_written",
                    "polygons_drawn",
                    "robust_errors",
                    "scene"
                ]
            );
        }
        let methods: Vec<&str> = rows.iter().map(|r| r["method"].as_str().unwrap()).collect();
        assert_eq!(methods[..Method::ALL.len()], Method::ALL.map(Method::name));
        assert_eq!(
            methods[Method::ALL.len()..],
            ["peel-front-to-back/sub0", "peel-front-to-back/sub4"]
        );
        assert!(rows.iter().all(|r| r["memory_bytes"].as_u64().unwrap() > 0));
        let naive = rows.iter().find(|r| r["method"] == "naive-bsp").unwrap();
        assert_eq!(naive["robust_errors"], 0);
        assert!(naive["pixels_written"].as_u64().unwrap() > 0);
        // Zero subpixel bits err by design; the methods do not, but for Newell's sort.
        for r in rows[..Method::ALL.len()]
            .iter()
            .filter(|r| r["method"] != "newell")
        {
            assert_eq!(r["robust_errors"], 0, "{r}");
        }
    }

    /// The survey's methods (Watkins, Warnock's two subdivisions, Weiler and Atherton) on two
    /// generated scenes of convex solids that do not interpenetrate, a sphere and a grid of
    /// boxes: no robust error, as each is exact in principle there. The demo's solids and a
    /// triangle soup interpenetrate: their errors are counted, not asserted zero (Weiler and
    /// Atherton's rounded cuts leave a pixel on the demo at 640x480), only bounded.
    #[test]
    fn survey_methods_on_the_demo_and_generated_scenes() {
        let demo = crate::load::load_obj(
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/demo.obj"),
        )
        .unwrap();
        let scenes = [
            ("demo", demo),
            ("sphere", crate::tools::scenes::sphere(12, 24)),
            ("grid", crate::tools::scenes::box_grid(2)),
            ("soup", crate::tools::scenes::soup(60, 0.4, 5)),
        ]
        .map(|(name, mesh)| BenchScene {
            name: name.into(),
            mesh,
            naive_bsp: None,
        });
        let (w, h, cameras) = (160, 120, 4);
        let records = run(&scenes, w, h, cameras, &mut |_| {}).unwrap();
        for m in [
            Method::Watkins,
            Method::WarnockQuadrants,
            Method::WarnockEnclosing,
            Method::WeilerAtherton,
        ] {
            for s in ["demo", "sphere", "grid", "soup"] {
                let r = records
                    .iter()
                    .find(|r| r.scene == s && r.method == m.name())
                    .unwrap();
                eprintln!(
                    "{s} {}: {} robust, {} all errors, {} bytes",
                    r.method, r.robust_errors, r.all_errors, r.memory_bytes
                );
                assert!(r.pixels_written > 0 && r.memory_bytes > 0, "{r:?}");
                if s == "soup" || s == "demo" {
                    assert!(
                        r.robust_errors * 100 < u64::from(w * h) * cameras as u64,
                        "{r:?}"
                    );
                } else {
                    assert_eq!(r.robust_errors, 0, "{r:?}");
                }
            }
        }
    }

    /// The naive BSP stops as soon as it exceeds its polygon budget.
    #[test]
    fn a_naive_bsp_over_budget_stops() {
        use crate::tools::baselines::{naive_bsp_file, NaiveBsp};
        let mesh = crate::tools::scenes::soup(40, 0.5, 3);
        let shading = CompileOptions::default().shading;
        match naive_bsp_file(&mesh, 45, true, &shading).unwrap() {
            NaiveBsp::OverBudget { polygons, limit } => assert!(polygons > limit && limit == 45),
            NaiveBsp::Built(_) => panic!("40 crossing triangles fit in 45 polygons"),
        }
    }
}
