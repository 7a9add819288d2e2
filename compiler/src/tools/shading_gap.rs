//! The shading gap: how far a mesh's faceted picture is from its smooth one, both the exact
//! reference's ([`Reference::colours`](super::reference::Reference::colours)), on the robust
//! pixels of each view (those whose centre lies farther than
//! [`EDGE_MARGIN`](super::reference::EDGE_MARGIN) from every projected edge): what smooth
//! shading changes, and what a file's smooth colours will be measured against.

use glam::DVec3;
use peel_runtime::camera::{Orbit, DEFAULT_FOV_Y_DEG};
use peel_runtime::read::Header;

use super::raster::render_bytes;
use super::reference::{reference, Lighting};
use super::shot::Shot;
use crate::load::Mesh;
use crate::shade::smooth::Smooth;

/// The views measured: the orbit of the target benchmark's camera path, azimuths 0, 45, ...,
/// 315 degrees at an elevation of 20, each at the distance at which the mesh fits the image.
pub const VIEW_AZIMUTHS_DEG: [f64; 8] = [0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0];
/// The elevation of those views, in degrees (`peel render`'s default).
pub const VIEW_ELEVATION_DEG: f64 = 20.0;

/// A difference of more than this many 8-bit units is one a viewer sees.
pub const VISIBLE: f64 = 8.0;

/// The header a file of `mesh` has as far as the camera is concerned: its bounding box about
/// the box's centre.
fn bounds(mesh: &Mesh) -> Header {
    let points = mesh.triangles.iter().flat_map(|t| t.vertices);
    let (lo, hi) = points.fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    let centre = (lo + hi) * 0.5;
    Header {
        centre: centre.to_array(),
        bounds_min: (lo - centre).as_vec3(),
        bounds_max: (hi - centre).as_vec3(),
        ..Header::default()
    }
}

/// The views of `mesh` ([`VIEW_AZIMUTHS_DEG`]) at `width x height`.
pub fn views(mesh: &Mesh, width: u32, height: u32) -> Vec<Shot> {
    (VIEW_AZIMUTHS_DEG.iter())
        .map(|&azimuth| view(mesh, azimuth, VIEW_ELEVATION_DEG, width, height))
        .collect()
}

/// The view of `mesh` from `azimuth_deg`, `elevation_deg` at `width x height`, around its
/// bounding box as `peel render --orbit` frames a compiled scene.
pub fn view(mesh: &Mesh, azimuth_deg: f64, elevation_deg: f64, width: u32, height: u32) -> Shot {
    let orbit = Orbit {
        azimuth_deg,
        elevation_deg,
        distance: Orbit::fitting_distance(DEFAULT_FOV_Y_DEG, width, height),
    };
    let pose = orbit.pose(&bounds(mesh));
    Shot::new(pose.eye, pose.target, width, height)
}

/// The differences of one or more views, per robust pixel that sees the mesh: the largest over
/// its channels, in 8-bit units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gap {
    /// Robust pixels that see the mesh.
    pub pixels: usize,
    /// Their mean difference.
    pub mean: f64,
    /// The 99th percentile (nearest rank).
    pub p99: f64,
    /// The largest.
    pub max: f64,
    /// How many differ by more than [`VISIBLE`].
    pub visible: usize,
}

impl Gap {
    /// The figures of `differences`.
    pub fn of(mut differences: Vec<f64>) -> Gap {
        differences.sort_by(f64::total_cmp);
        let n = differences.len();
        if n == 0 {
            return Gap {
                pixels: 0,
                mean: 0.0,
                p99: 0.0,
                max: 0.0,
                visible: 0,
            };
        }
        let rank = ((n as f64 * 0.99).ceil() as usize).clamp(1, n) - 1;
        Gap {
            pixels: n,
            mean: differences.iter().sum::<f64>() / n as f64,
            p99: differences[rank],
            max: differences[n - 1],
            visible: differences.iter().filter(|&&d| d > VISIBLE).count(),
        }
    }
}

/// Per view of `shots`, the differences between `mesh` shaded faceted by `smooth`'s light
/// and shaded `smooth`, then all of them together: `(per view, overall)`. A shot without a
/// near distance takes the default over the mesh's bounding box.
pub fn faceted_against_smooth(mesh: &Mesh, smooth: &Smooth, shots: &[Shot]) -> (Vec<Gap>, Gap) {
    let header = bounds(mesh);
    let triangles: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
    let kd: Vec<[u8; 3]> = mesh.triangles.iter().map(|t| t.colour).collect();
    let shades = smooth.shade(mesh);
    let per_view: Vec<Vec<f64>> = shots
        .iter()
        .map(|shot| {
            let near = shot.near_over(&header);
            let seen = reference(&triangles, &[], shot, near);
            let paint = |lighting| seen.colours(&triangles, &kd, shot, near, lighting, None);
            let faceted = paint(Lighting::Faceted(smooth.shading));
            let smooth = paint(Lighting::Smooth(&shades));
            (faceted.iter().zip(&smooth).zip(&seen.robust))
                .filter_map(|((a, b), &robust)| match (a, b) {
                    (Some(a), Some(b)) if robust => Some(
                        (0..3)
                            .map(|c| f64::from(a[c].abs_diff(b[c])))
                            .fold(0.0, f64::max),
                    ),
                    _ => None,
                })
                .collect()
        })
        .collect();
    let gaps = per_view.iter().map(|d| Gap::of(d.clone())).collect();
    (gaps, Gap::of(per_view.concat()))
}

/// Per view of `shots`, the differences between the runtime's picture of `bytes` (the file
/// compiled from `mesh` with `smooth`'s light and crease, drawn on the host as firmware draws
/// it, undithered) and the reference's exact smooth colours, then all of them together:
/// `(per view, overall)`.
///
/// # Errors
/// A file the runtime cannot draw.
pub fn runtime_against_smooth(
    mesh: &Mesh,
    bytes: &[u8],
    smooth: &Smooth,
    shots: &[Shot],
) -> Result<(Vec<Gap>, Gap), String> {
    let header = bounds(mesh);
    let triangles: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
    let kd: Vec<[u8; 3]> = mesh.triangles.iter().map(|t| t.colour).collect();
    let shades = smooth.shade(mesh);
    let mut per_view = Vec::new();
    for shot in shots {
        let near = shot.near_over(&header);
        let seen = reference(&triangles, &[], shot, near);
        let exact =
            seen.colours_exact(&triangles, &kd, shot, near, Lighting::Smooth(&shades), None);
        let frame = render_bytes(bytes, shot, false, [0; 3])?;
        let differences: Vec<f64> = (exact.iter().zip(&frame.pixels).zip(&seen.robust))
            .filter_map(|((e, &p), &robust)| {
                let e = e.filter(|_| robust)?;
                let drawn = [(p >> 16) as u8, (p >> 8) as u8, p as u8];
                Some(
                    (0..3)
                        .map(|c| (f64::from(drawn[c]) - e[c]).abs())
                        .fold(0.0, f64::max),
                )
            })
            .collect();
        per_view.push(differences);
    }
    let gaps = per_view.iter().map(|d| Gap::of(d.clone())).collect();
    Ok((gaps, Gap::of(per_view.concat())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::load_obj;
    use crate::shade::normals::DEFAULT_CREASE_DEG;
    use crate::shade::Shading;
    use crate::tools::scenes;
    use std::path::Path;

    /// 320x240, as the target benchmark draws.
    const SIZE: (u32, u32) = (320, 240);

    fn smooth() -> Smooth {
        Smooth::new(Shading::default(), DEFAULT_CREASE_DEG).unwrap()
    }

    #[test]
    fn gap_figures() {
        let g = Gap::of((1..=200).map(f64::from).rev().collect());
        assert_eq!((g.pixels, g.mean, g.p99, g.max), (200, 100.5, 198.0, 200.0));
        assert_eq!(g.visible, 192);
        assert_eq!(Gap::of(Vec::new()).pixels, 0);
    }

    /// A box is the same faceted and smooth: its edges are creases.
    #[test]
    fn a_box_looks_the_same_smooth() {
        let mut t = Vec::new();
        scenes::boxed(
            &mut t,
            DVec3::new(-1.0, -0.5, -2.0),
            DVec3::new(1.0, 0.7, 0.3),
        );
        let mesh = scenes::mesh(t);
        let (views, all) = faceted_against_smooth(&mesh, &smooth(), &views(&mesh, 160, 120));
        assert!(views.iter().all(|g| g.pixels > 1000), "{views:?}");
        assert_eq!(all.max, 0.0, "{all:?}");
    }

    /// A sphere is smooth where its faceted picture shows steps: seen from the views, smooth
    /// shading is nearer the sphere's true shading (Lambert at the radial normal) on every
    /// view, and far nearer on the whole.
    #[test]
    fn a_sphere_is_nearer_its_true_shading_smooth() {
        let mesh = scenes::sphere(12, 24);
        let shading = Shading::default();
        let shades = smooth().shade(&mesh);
        let triangles: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
        let kd: Vec<[u8; 3]> = mesh.triangles.iter().map(|t| t.colour).collect();
        let (mut faceted_off, mut smooth_off) = (0.0, 0.0);
        let header = bounds(&mesh);
        for shot in views(&mesh, 160, 120) {
            let near = shot.near_over(&header);
            let seen = reference(&triangles, &[], &shot, near);
            let paint = |lighting| seen.colours_exact(&triangles, &kd, &shot, near, lighting, None);
            let faceted = paint(Lighting::Faceted(shading));
            let smooth = paint(Lighting::Smooth(&shades));
            let (mut f, mut s) = (0.0, 0.0);
            for k in (0..seen.ids.len()).filter(|&k| seen.robust[k] && seen.ids[k] > 0) {
                let p = seen.hit_point(&triangles, &shot, near, k).unwrap();
                let front = seen.seen_normal(&triangles, k).unwrap().dot(p) > 0.0;
                let radial = if front { p.normalize() } else { -p.normalize() };
                let truth = 200.0 * shading.intensity_at(radial, p);
                f += (faceted[k].unwrap()[0] - truth).abs();
                s += (smooth[k].unwrap()[0] - truth).abs();
            }
            assert!(s < f, "{shot:?}: smooth {s} against faceted {f}");
            faceted_off += f;
            smooth_off += s;
        }
        assert!(smooth_off * 3.0 < faceted_off, "{smooth_off} {faceted_off}");
    }

    /// The white teapot (every face's `Kd` 1,1,1) from the views at 320x240 in the default
    /// light: what smooth shading changes. Prints the figures; `--nocapture` shows them.
    #[test]
    fn the_white_teapot_faceted_against_smooth() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/models/teapot.obj");
        if !path.is_file() {
            println!("skipping: shared models not found at ../shared/models");
            return;
        }
        let mut mesh = load_obj(&path).unwrap();
        for t in &mut mesh.triangles {
            t.colour = [255; 3];
        }
        let (w, h) = SIZE;
        let (views, all) = faceted_against_smooth(&mesh, &smooth(), &views(&mesh, w, h));
        // `peel render`'s default view, apart.
        let default = Orbit::default();
        let one = view(&mesh, default.azimuth_deg, default.elevation_deg, w, h);
        let (_, alone) = faceted_against_smooth(&mesh, &smooth(), &[one]);
        println!(
            "the white teapot at {w}x{h}, default light, crease {DEFAULT_CREASE_DEG} degrees: \
             faceted against smooth on the robust pixels, 8-bit units"
        );
        println!("| view (azimuth, elevation) | pixels | mean | p99 | max | > {VISIBLE} |");
        println!("|---|--:|--:|--:|--:|--:|");
        let name = |a: f64, e: f64| format!("{a}, {e}");
        let rows = (VIEW_AZIMUTHS_DEG.iter())
            .map(|&a| name(a, VIEW_ELEVATION_DEG))
            .zip(&views)
            .chain([("all eight".to_string(), &all)])
            .chain([(name(default.azimuth_deg, default.elevation_deg), &alone)]);
        for (name, g) in rows {
            println!(
                "| {name} | {} | {:.2} | {} | {} | {} |",
                g.pixels, g.mean, g.p99, g.max, g.visible
            );
        }
        assert!(views.iter().all(|g| g.pixels > 3000), "{views:?}");
        // Facets show: every view has visible steps, which smooth shading removes.
        assert!(
            views.iter().all(|g| g.visible > 0 && g.max > 2.0 * VISIBLE),
            "{views:?}"
        );
        assert!(all.mean > 1.0, "{all:?}");
    }
}

/// The runtime's smooth pictures against the reference's: the accuracy goal of smooth shading.
#[cfg(test)]
mod accuracy {
    use super::*;
    use crate::compile::{compile_mesh, CompileOptions};
    use crate::load::load_obj;
    use crate::shade::normals::{Crease, DEFAULT_CREASE_DEG};
    use crate::shade::{Shading, Surface};
    use crate::tools::scenes;
    use std::path::Path;

    /// Mean, 99th percentile and largest difference allowed, in 8-bit units.
    const GOAL: (f64, f64, f64) = (1.0, 3.0, 12.0);

    fn white(mut mesh: Mesh) -> Mesh {
        for t in &mut mesh.triangles {
            t.colour = [255; 3];
        }
        mesh
    }

    /// The gap of `mesh` compiled smooth (default light, no shadows) from the eight views and
    /// three more at other elevations, 320x240; printed, and checked against [`GOAL`].
    fn check(name: &str, mesh: &Mesh) -> Gap {
        let smooth = Smooth::new(Shading::default(), DEFAULT_CREASE_DEG).unwrap();
        let options = CompileOptions {
            surface: Surface::Smooth(Crease::new(DEFAULT_CREASE_DEG).unwrap()),
            ..CompileOptions::default()
        };
        let (_, bytes) = compile_mesh(mesh, &options, &|_| {}).unwrap();
        let mut shots = views(mesh, 320, 240);
        shots.extend(
            [(30.0, -25.0), (200.0, 60.0), (290.0, 5.0)].map(|(a, e)| view(mesh, a, e, 320, 240)),
        );
        let (per_view, all) = runtime_against_smooth(mesh, &bytes, &smooth, &shots).unwrap();
        println!(
            "{name}: {} robust pixels, mean {:.3}, p99 {}, max {:.2}, worst view max {:.2}",
            all.pixels,
            all.mean,
            all.p99,
            all.max,
            per_view.iter().map(|g| g.max).fold(0.0, f64::max)
        );
        assert!(
            per_view.iter().all(|g| g.pixels > 500),
            "{name}: {per_view:?}"
        );
        let (mean, p99, max) = GOAL;
        assert!(
            all.mean <= mean && all.p99 <= p99 && all.max <= max,
            "{name}: {all:?} against mean {mean}, p99 {p99}, max {max}"
        );
        all
    }

    #[test]
    fn generated_scenes_shade_as_the_reference() {
        check("sphere 24 x 48", &white(scenes::sphere(24, 48)));
        check("torus 24 x 48", &white(scenes::torus(24, 48)));
        check("sphere 8 x 12", &white(scenes::sphere(8, 12)));
    }

    #[test]
    fn the_models_shade_as_the_reference() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/models");
        for name in ["teapot", "cow", "suzanne"] {
            let path = dir.join(format!("{name}.obj"));
            if !path.is_file() {
                println!("skipping {name}: shared models not found at ../shared/models");
                continue;
            }
            check(name, &white(load_obj(&path).unwrap()));
        }
    }
}
