//! Accuracy against the exact ray-casting reference (`peel_compiler::tools::reference`), with
//! `peel bench`'s rule: a pixel counts only when its sample point lies farther than 1/16
//! pixel from every projected edge (of the source triangles and of the compiled polygons,
//! whose edges include the compiler's cuts), and it is an error when the method shows
//! another triangle there than the nearest one the ray hits. A method that draws ids is
//! compared id for id; embedded-3dgfx, which colours a mesh with its own lighting, by
//! coverage only (covered or not).
//!
//! The ids come from the host: Peel's renderer with ids from the same scene compiled with
//! ids, and the z-buffers' own code over the mesh with ids for colours. The target draws the
//! host's pixels (`differing_pixels`), so these are the target's errors.

use glam::DVec3;
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::load_obj;
use peel_compiler::tools::reference::{reference, Reference};
use peel_compiler::tools::shot::Shot;
use peel_runtime::camera::{Camera, Orbit};
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Framebuffer, Xrgb8888};
use peel_runtime::read::Scene;
use peel_runtime::render::{Renderer, Workspace};
use peel_target_kit::config::OrbitAngles;

use std::path::Path;

use crate::plan::FOV_Y_DEG;

/// The reference of every camera of a scene at one size.
pub struct Truth {
    references: Vec<Reference>,
    /// The scene compiled with ids (the same tree as the benchmark's file).
    ids_peel: Vec<u8>,
}

impl Truth {
    /// Ray-cast the scene of the OBJ file `obj` (compiled with `options`, ids added) from each
    /// of `cameras` at `width x height`.
    pub fn new(
        obj: &Path,
        options: &CompileOptions,
        cameras: &[OrbitAngles],
        (width, height): (u32, u32),
    ) -> Result<Truth, String> {
        let fail = |e: String| format!("{}: {e}", obj.display());
        let mesh = load_obj(obj).map_err(|e| fail(e.to_string()))?;
        let options = CompileOptions {
            ids: true,
            ..options.clone()
        };
        let (_, ids_peel) =
            compile_mesh(&mesh, &options, &|_| {}).map_err(|e| fail(e.to_string()))?;
        let parsed = Scene::parse(&ids_peel).map_err(|e| fail(e.to_string()))?;
        let header = parsed.header();
        let centre = DVec3::from_array(header.centre);
        let polygons: Vec<Vec<DVec3>> = (0..header.polygon_count)
            .map(|i| {
                let p = parsed.polygon(i);
                (0..u32::from(p.vertex_count))
                    .map(|k| centre + parsed.polygon_vertex(&p, k).as_dvec3())
                    .collect()
            })
            .collect();
        let triangles: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
        let references = cameras
            .iter()
            .map(|c| {
                let shot = shot(&header, *c, width, height);
                reference(&triangles, &polygons, &shot, shot.near_over(&header))
            })
            .collect();
        Ok(Truth {
            references,
            ids_peel,
        })
    }

    /// Robust pixels of camera `k` where `ids` (`id + 1` of the source triangle, 0 for none)
    /// is not the reference's.
    pub fn id_errors(&self, k: usize, ids: &[u32]) -> u64 {
        let r = &self.references[k];
        r.ids
            .iter()
            .zip(&r.robust)
            .zip(ids)
            .filter(|((want, &robust), got)| robust && want != got)
            .count() as u64
    }

    /// Robust pixels of camera `k` covered in `frame` (any colour but `background`) where the
    /// reference sees nothing, or the reverse.
    pub fn coverage_errors(&self, k: usize, frame: &[u16], background: u16) -> u64 {
        let r = &self.references[k];
        r.ids
            .iter()
            .zip(&r.robust)
            .zip(frame)
            .filter(|((&want, &robust), &got)| robust && (want != 0) != (got != background))
            .count() as u64
    }

    /// Peel's id image of camera `k`, front to back or back to front, with integer vertices
    /// or not (as the firmware of a core without an FPU draws).
    pub fn peel_ids(
        &self,
        angles: OrbitAngles,
        (width, height): (u32, u32),
        front_to_back: bool,
        integer_vertices: bool,
    ) -> Result<Vec<u32>, String> {
        let scene = Scene::parse(&self.ids_peel).map_err(|e| e.to_string())?;
        let header = scene.header();
        let view = peel_target_kit::orbit_view(&header, angles, FOV_Y_DEG, width, height)
            .map_err(|e| e.to_string())?;
        let mut workspace: Box<Workspace<{ 1 << 14 }, 64>> = Box::default();
        let (mut intervals, mut counts) = (
            vec![(0u16, 0u16); 64 * height as usize],
            vec![0u16; height as usize],
        );
        let mut ids = vec![0u32; width as usize * height as usize];
        let mut fb =
            Framebuffer::<Xrgb8888>::new(&mut ids, width, height).map_err(|e| e.to_string())?;
        let mut renderer = Renderer::new(&mut workspace).ids();
        if integer_vertices {
            renderer = renderer.integer_vertices();
        }
        renderer = if front_to_back {
            renderer.span_memory(
                Coverage::new(&mut intervals, &mut counts, width, height)
                    .map_err(|e| e.to_string())?,
            )
        } else {
            renderer.back_to_front()
        };
        renderer
            .draw(&scene, &view, &mut fb)
            .map_err(|e| e.to_string())?;
        Ok(ids)
    }
}

/// The shot of `peel render --orbit=AZ,EL` (the CLI's distance, field of view, up and near
/// distance), as the reference reads it.
fn shot(header: &peel_runtime::read::Header, angles: OrbitAngles, width: u32, height: u32) -> Shot {
    let orbit = Orbit {
        azimuth_deg: angles.azimuth_deg,
        elevation_deg: angles.elevation_deg,
        distance: Orbit::fitting_distance(FOV_Y_DEG, width, height),
    };
    let pose = orbit.pose(header);
    Shot {
        eye: pose.eye,
        target: pose.target,
        up: pose.up,
        fov_y_deg: FOV_Y_DEG,
        width,
        height,
        near: Some(Camera::default_near(header.bounds_min, header.bounds_max)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peel_has_no_robust_errors_and_wrong_images_have() {
        let demo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/demo.obj");
        let cameras = crate::plan::cameras(2);
        let size = (64, 48);
        let truth = Truth::new(&demo, &CompileOptions::default(), &cameras, size).unwrap();
        for (k, &c) in cameras.iter().enumerate() {
            for (front_to_back, integer) in [(true, false), (false, false), (true, true)] {
                let ids = truth.peel_ids(c, size, front_to_back, integer).unwrap();
                assert!(ids.iter().any(|&i| i != 0));
                assert_eq!(truth.id_errors(k, &ids), 0);
                // Coverage of the same image: none wrong either.
                let frame: Vec<u16> = ids.iter().map(|&i| u16::from(i != 0)).collect();
                assert_eq!(truth.coverage_errors(k, &frame, 0), 0);
                // An empty frame is wrong wherever the reference sees a robust triangle, and
                // ids shifted by one are wrong on every robust covered pixel.
                let covered = truth.references[k]
                    .ids
                    .iter()
                    .zip(&truth.references[k].robust)
                    .filter(|(&id, &robust)| robust && id != 0)
                    .count() as u64;
                assert!(covered > 100);
                assert_eq!(truth.coverage_errors(k, &vec![0; frame.len()], 0), covered);
                let shifted: Vec<u32> = ids
                    .iter()
                    .map(|&i| if i == 0 { 0 } else { i + 1 })
                    .collect();
                assert_eq!(truth.id_errors(k, &shifted), covered);
            }
        }
    }
}
