//! The transparent scenes in `peel bench` ([`crate::tools::scenes::transparent_scenes`]):
//! Peel front to back (composite memory) and back to front (blended over the framebuffer),
//! and the z-buffer with the usual per-frame sort of the transparent triangles by their
//! centroid's depth ([`SORTED`]), each against the ray cast that composites every surface in
//! depth order. A pixel is wrong when a channel is more than [`TOLERANCE`] from it: the sorted
//! z-buffer is, wherever surfaces cross or overlap in depth; Peel's tree orders them exactly.

use std::time::Instant;

use glam::DVec3;

use super::{zbuffer, FrameRecord, Method};
use crate::compile::{compile_mesh, CompileOptions};
use crate::load::{Mesh, SourceTriangle};
use crate::shade::{Shading, Surface};
use crate::tools::raster::{render_bytes_with, Settings};
use crate::tools::reference::composite;
use crate::tools::scenes::TransparentScene;
use peel_runtime::read::Scene;
use peel_runtime::traverse::Order;

/// The sorted z-buffer's method name in the records.
pub const SORTED: &str = "zbuffer-sorted";

/// Channel difference (8-bit units) beyond which a pixel is wrong.
pub const TOLERANCE: f64 = 2.0;

/// The background of the transparent scenes' frames.
const BACKGROUND: [u8; 3] = [30, 40, 70];

/// `scene` as a loaded mesh: its triangles, colours and opacities.
fn mesh(scene: &TransparentScene) -> Mesh {
    let (colours, opacities) = (scene.colours(), scene.opacities());
    let triangles = (scene.corners().into_iter().enumerate())
        .map(|(k, vertices)| SourceTriangle {
            vertices,
            colour: colours[k],
            normals: None,
            texture: None,
            opacity: opacities[k],
        })
        .collect();
    Mesh {
        triangles,
        ..Mesh::default()
    }
}

/// The world-space polygons of a compiled file (their edges include every cut).
fn polygons(bytes: &[u8]) -> Result<Vec<Vec<DVec3>>, String> {
    let scene = Scene::parse(bytes).map_err(|e| e.to_string())?;
    let c = DVec3::from_array(scene.header().centre);
    Ok((0..scene.header().polygon_count)
        .map(|i| {
            let p = scene.polygon(i);
            (0..u32::from(p.vertex_count))
                .map(|k| c + scene.polygon_vertex(&p, k).as_dvec3())
                .collect()
        })
        .collect())
}

fn rgb(pixels: &[u32]) -> Vec<[u8; 3]> {
    pixels
        .iter()
        .map(|&p| [(p >> 16) as u8, (p >> 8) as u8, p as u8])
        .collect()
}

/// Per scene, the records of Peel in both orders and of the sorted z-buffer over the scene's
/// views, compiled unlit: the median frame time, the pixels written (Peel) and the wrong
/// pixels, robust ones (the reference's neighbourhood crosses one sequence of surfaces) and
/// all.
pub fn run_transparent(
    scenes: &[TransparentScene],
    log: &mut dyn FnMut(&str),
) -> Result<Vec<FrameRecord>, String> {
    let options = CompileOptions {
        shading: Shading::Flat,
        surface: Surface::Faceted,
        ..CompileOptions::default()
    };
    let mut out = Vec::new();
    for scene in scenes {
        let mesh = mesh(scene);
        let bytes = compile_mesh(&mesh, &options, &|_| {})
            .map_err(|e| e.to_string())?
            .1;
        let header = Scene::parse(&bytes).map_err(|e| e.to_string())?.header();
        let polys = polygons(&bytes)?;
        let triangles = scene.corners();
        let opacities = scene.opacities();
        let kd: Vec<[f64; 3]> = scene.colours().iter().map(|c| c.map(f64::from)).collect();
        let colour = |id: usize, _: bool| kd[id];
        let methods = [
            Method::PeelFrontToBack.name(),
            Method::PeelBackToFront.name(),
            SORTED,
        ];
        let mut rows: Vec<(Vec<f64>, u64, u64, u64, u64)> =
            methods.iter().map(|_| Default::default()).collect();
        for shot in &scene.shots {
            let near = shot.near_over(&header);
            let reference = composite(
                &triangles, &polys, shot, near, colour, &opacities, BACKGROUND,
            );
            let wrong = |picture: &[[u8; 3]]| {
                let all = (picture.iter().zip(&reference.colours))
                    .filter(|(p, c)| (0..3).any(|k| (f64::from(p[k]) - c[k]).abs() > TOLERANCE))
                    .count();
                (
                    reference.wrong_pixels(picture, TOLERANCE) as u64,
                    all as u64,
                )
            };
            for (k, row) in rows.iter_mut().enumerate() {
                let start = Instant::now();
                let (picture, written, drawn) = if k < 2 {
                    let settings = Settings {
                        order: [Order::FrontToBack, Order::BackToFront][k],
                        background: BACKGROUND,
                        ..Settings::default()
                    };
                    let frame = render_bytes_with(&bytes, shot, &settings)?;
                    let stats = frame.stats;
                    (
                        rgb(&frame.pixels),
                        stats.pixels_written,
                        stats.polygons_drawn,
                    )
                } else {
                    let picture = zbuffer::sorted_picture(
                        &triangles, colour, &opacities, BACKGROUND, shot, near,
                    )?;
                    (picture, 0, 0)
                };
                row.0.push(start.elapsed().as_secs_f64() * 1e3);
                let (robust, all) = wrong(&picture);
                row.1 += robust;
                row.2 += all;
                row.3 += written;
                row.4 += drawn;
            }
        }
        let views = scene.shots.len().max(1) as u64;
        for (method, (mut times, robust, all, written, drawn)) in methods.iter().zip(rows) {
            times.sort_by(f64::total_cmp);
            let record = FrameRecord {
                scene: scene.name.clone(),
                method: (*method).to_string(),
                median_frame_ms: times.get(times.len() / 2).copied().unwrap_or(0.0),
                pixels_written: written / views,
                robust_errors: robust,
                all_errors: all,
                memory_bytes: 0,
                polygons_drawn: drawn / views,
            };
            log(&format!(
                "  {} {}: {} wrong robust pixels over {} views",
                record.scene, record.method, record.robust_errors, views
            ));
            out.push(record);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::scenes::crossing_panes;

    /// Peel composites the crossing panes right in both orders; the sorted z-buffer does not.
    #[test]
    fn the_sorted_z_buffer_is_wrong_where_panes_cross() {
        let records = run_transparent(&[crossing_panes()], &mut |_| {}).unwrap();
        let get = |m: &str| records.iter().find(|r| r.method == m).unwrap();
        assert_eq!(get("peel-front-to-back").robust_errors, 0);
        assert_eq!(get("peel-back-to-front").robust_errors, 0);
        assert!(get(SORTED).robust_errors > 0);
        assert!(get("peel-front-to-back").pixels_written > 0);
    }
}
