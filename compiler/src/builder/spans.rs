//! The span memory a scene needs: the fewest intervals per row with which no frame of an
//! orbit around the scene, at the image size firmware draws, runs out of span memory front to
//! back. Running out is not an error, but the rest of that frame is painted back to front:
//! with overdraw, which a panel streamed span by span shows as flicker, and more display
//! writes. Firmware sized by this figure keeps every frame of the orbit front to back.

use peel_runtime::camera::{Camera, Orbit, DEFAULT_FOV_Y_DEG};
use peel_runtime::composite::{Composite, CompositeRun, MAX_RUNS};
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Colour, SpanSink};
use peel_runtime::pending::{Pending, PendingPixel};
use peel_runtime::read::Scene;
use peel_runtime::render::{Renderer, Workspace};
use peel_runtime::scan::{ScanMemory, ScanNode};

use super::sizes::MeasuredSpans;

/// Everything the sizes file measures at `width x height` ([`crate::Builder::image_size`],
/// `peel inspect --size`): [`spans_per_row`], [`scan_nodes`], [`scan_nodes_antialiased`] and
/// [`pending_pixels`].
///
/// # Errors
/// Theirs, saying which measurement failed.
pub fn measure(bytes: &[u8], width: u32, height: u32) -> Result<MeasuredSpans, String> {
    let at = |what: &'static str| move |e| format!("measuring {what} at {width}x{height}: {e}");
    Ok(MeasuredSpans {
        width,
        height,
        per_row: spans_per_row(bytes, width, height).map_err(at("span memory"))?,
        scan_nodes: scan_nodes(bytes, width, height).map_err(at("scan memory"))?,
        scan_nodes_antialiased: scan_nodes_antialiased(bytes, width, height)
            .map_err(at("anti-aliased scan memory"))?,
        pending_pixels: pending_pixels(bytes, width, height).map_err(at("pending pixels"))?,
        composite_runs: composite_runs(bytes, width, height).map_err(at("composite memory"))?,
    })
}

/// Cameras of the orbit measured: azimuths 0, 15, ..., 345 degrees.
pub const ORBIT_CAMERAS: u32 = 24;
/// Their elevations, in degrees: the CLI's default view and a view from higher up.
pub const ORBIT_ELEVATIONS: [f64; 2] = [20.0, 45.0];

/// The orbit's views of `scene` at `width x height` (see [`spans_per_row`]).
fn orbit_views(
    scene: &Scene<'_>,
    width: u32,
    height: u32,
) -> Result<Vec<peel_runtime::camera::LocalView>, String> {
    let header = scene.header();
    let near = Camera::default_near(header.bounds_min, header.bounds_max);
    ORBIT_ELEVATIONS
        .iter()
        .flat_map(|&elevation_deg| {
            (0..ORBIT_CAMERAS).map(move |k| Orbit {
                azimuth_deg: 360.0 * f64::from(k) / f64::from(ORBIT_CAMERAS),
                elevation_deg,
                distance: Orbit::fitting_distance(DEFAULT_FOV_Y_DEG, width, height),
            })
        })
        .map(|orbit| {
            Camera::look_at(orbit.pose(&header), DEFAULT_FOV_Y_DEG, width, height, near)
                .map(|c| c.view(header.centre))
                .map_err(|e| e.to_string())
        })
        .collect()
}

/// The scan memory nodes (`peel_runtime::scan::ScanNode`, 6 bytes each) with which no
/// scan-order frame of the orbit of [`spans_per_row`] runs out: the most any of its frames
/// holds at once.
///
/// # Errors
/// As [`spans_per_row`]'s, and a frame that needs more than the 65,535 nodes scan memory can
/// address.
pub fn scan_nodes(bytes: &[u8], width: u32, height: u32) -> Result<usize, String> {
    scan_nodes_with(bytes, width, height, false)
}

/// [`scan_nodes`] for anti-aliased scan-order frames (`Renderer::antialias`, with records to
/// spare): more than the plain frames need, as each pending pixel splits an interval. With
/// fewer nodes (but at least [`scan_nodes`]) a frame that runs out is drawn plain.
///
/// # Errors
/// As [`scan_nodes`]'.
pub fn scan_nodes_antialiased(bytes: &[u8], width: u32, height: u32) -> Result<usize, String> {
    scan_nodes_with(bytes, width, height, true)
}

fn scan_nodes_with(bytes: &[u8], width: u32, height: u32, aa: bool) -> Result<usize, String> {
    let scene = Scene::parse(bytes).map_err(|e| e.to_string())?;
    // Transparent surfaces are never anti-aliased (`RenderError::AntialiasedTransparency`).
    if aa && scene.has_transparency() {
        return Ok(0);
    }
    let views = orbit_views(&scene, width, height)?;
    let mut workspace: Box<Workspace<{ 1 << 14 }, 64>> = Box::default();
    let mut nodes = vec![ScanNode::EMPTY; usize::from(u16::MAX)];
    let mut heads = vec![0u16; height as usize];
    let memory =
        ScanMemory::new(&mut nodes, &mut heads, width, height).map_err(|e| e.to_string())?;
    let mut records = vec![PendingPixel::default(); if aa { MOST_PENDING } else { 0 }];
    let mut pending_heads = vec![0u16; height as usize];
    let mut runs = vec![CompositeRun::default(); MAX_RUNS];
    let mut run_heads = vec![0u16; height as usize];
    let composite = Composite::new(&mut runs, &mut run_heads, height).map_err(|e| e.to_string())?;
    let mut renderer = Renderer::new(&mut workspace)
        .scan_memory(memory)
        .composite_memory(composite);
    if aa {
        let pending =
            Pending::new(&mut records, &mut pending_heads, height).map_err(|e| e.to_string())?;
        renderer = renderer.antialias(pending);
    }
    let mut most = 0;
    for view in &views {
        let frame = renderer
            .draw_scan(&scene, view)
            .map_err(|e| e.to_string())?;
        if aa && !frame.stats().antialiased {
            return Err("an anti-aliased frame needs more than 65,535 nodes".to_string());
        }
        most = most.max(frame.nodes_used());
    }
    Ok(most)
}

/// Records an anti-aliased pool can address (`peel_runtime::pending`).
const MOST_PENDING: usize = 32_767;

/// The pending-pixel records (`peel_runtime::pending::PendingPixel`, 12 bytes each) with
/// which no anti-aliased frame of the orbit of [`spans_per_row`] has a row fall back to
/// plain pixels: the most any of its frames keeps pending at once (with span memory enough,
/// `spans_per_row_bound`).
///
/// # Errors
/// As [`spans_per_row`]'s, and a frame that keeps more pixels pending than a pool can address.
pub fn pending_pixels(bytes: &[u8], width: u32, height: u32) -> Result<usize, String> {
    let scene = Scene::parse(bytes).map_err(|e| e.to_string())?;
    // Transparent surfaces are never anti-aliased (`RenderError::AntialiasedTransparency`).
    if scene.has_transparency() {
        return Ok(0);
    }
    let views = orbit_views(&scene, width, height)?;
    let per_row = (width as usize).div_ceil(2).max(1);
    let mut workspace: Box<Workspace<{ 1 << 14 }, 64>> = Box::default();
    let mut intervals = vec![(0u16, 0u16); per_row * height as usize];
    let mut counts = vec![0u16; height as usize];
    let mut records = vec![PendingPixel::default(); MOST_PENDING];
    let mut heads = vec![0u16; height as usize];
    let coverage =
        Coverage::new(&mut intervals, &mut counts, width, height).map_err(|e| e.to_string())?;
    let pending = Pending::new(&mut records, &mut heads, height).map_err(|e| e.to_string())?;
    let mut renderer = Renderer::new(&mut workspace)
        .span_memory(coverage)
        .antialias(pending);
    let mut most = 0;
    for view in &views {
        renderer
            .draw(&scene, view, &mut Nowhere)
            .map_err(|e| e.to_string())?;
        most = most.max(renderer.pending().map_or(0, |p| p.peak()));
    }
    if most >= MOST_PENDING {
        return Err(format!(
            "a frame keeps more than {MOST_PENDING} pixels pending"
        ));
    }
    Ok(most)
}

/// The composite-memory records (`peel_runtime::composite::CompositeRun`, 12 bytes each)
/// with which no front-to-back frame of the orbit of [`spans_per_row`] has a row fall back to
/// screen-door transparency: the most any of its frames holds at once (with span memory
/// enough, `spans_per_row_bound`); 0 for a scene without transparent surfaces.
///
/// # Errors
/// As [`spans_per_row`]'s, and a frame that needs more records than a memory can address.
pub fn composite_runs(bytes: &[u8], width: u32, height: u32) -> Result<usize, String> {
    let scene = Scene::parse(bytes).map_err(|e| e.to_string())?;
    if !scene.has_transparency() {
        return Ok(0);
    }
    let views = orbit_views(&scene, width, height)?;
    let per_row = (width as usize).div_ceil(2).max(1);
    let mut workspace: Box<Workspace<{ 1 << 14 }, 64>> = Box::default();
    let mut intervals = vec![(0u16, 0u16); per_row * height as usize];
    let mut counts = vec![0u16; height as usize];
    let mut runs = vec![CompositeRun::default(); MAX_RUNS];
    let mut heads = vec![0u16; height as usize];
    let coverage =
        Coverage::new(&mut intervals, &mut counts, width, height).map_err(|e| e.to_string())?;
    let composite = Composite::new(&mut runs, &mut heads, height).map_err(|e| e.to_string())?;
    let mut renderer = Renderer::new(&mut workspace)
        .span_memory(coverage)
        .composite_memory(composite);
    let mut most = 0;
    for view in &views {
        let stats = renderer
            .draw(&scene, view, &mut Nowhere)
            .map_err(|e| e.to_string())?;
        if stats.fallback_rows > 0 {
            return Err(format!(
                "a frame needs more than {MAX_RUNS} composite records"
            ));
        }
        most = most.max(renderer.composite().map_or(0, |c| c.peak()));
    }
    Ok(most)
}

/// A sink that draws nothing.
struct Nowhere;

impl SpanSink for Nowhere {
    fn span(&mut self, _: u32, _: u32, _: u32, _: Colour) {}
}

/// The fewest span-memory intervals per row (at least 1) with which no frame of the orbit
/// ([`ORBIT_CAMERAS`] azimuths at each of [`ORBIT_ELEVATIONS`], the CLI's distance and field
/// of view) of the scene `bytes` at `width x height` runs out; never more than the bound that
/// can never run out (one interval per polygon, `(width + 1) / 2` in all).
///
/// # Errors
/// A message for a scene that does not parse, an image size the renderer refuses, or a scene
/// too deep for the measuring stack.
pub fn spans_per_row(bytes: &[u8], width: u32, height: u32) -> Result<usize, String> {
    let scene = Scene::parse(bytes).map_err(|e| e.to_string())?;
    let header = scene.header();
    let bound = (header.polygon_count as usize)
        .min((width as usize).div_ceil(2))
        .max(1);
    let views = orbit_views(&scene, width, height)?;
    let mut workspace: Box<Workspace<{ 1 << 14 }, 64>> = Box::default();
    let mut intervals = vec![(0u16, 0u16); bound * height as usize];
    let mut counts = vec![0u16; height as usize];
    // (A scene with transparent surfaces is drawn front to back with composite memory.)
    let transparent = scene.has_transparency();
    let mut runs = vec![CompositeRun::default(); if transparent { MAX_RUNS } else { 0 }];
    let mut run_heads = vec![0u16; height as usize];
    let mut enough = |per_row: usize| -> Result<bool, String> {
        for view in &views {
            let coverage = Coverage::new(
                &mut intervals[..per_row * height as usize],
                &mut counts,
                width,
                height,
            )
            .map_err(|e| e.to_string())?;
            let mut renderer = Renderer::new(&mut workspace).span_memory(coverage);
            if transparent {
                let composite =
                    Composite::new(&mut runs, &mut run_heads, height).map_err(|e| e.to_string())?;
                renderer = renderer.composite_memory(composite);
            }
            let stats = renderer
                .draw(&scene, view, &mut Nowhere)
                .map_err(|e| e.to_string())?;
            if stats.fallback {
                return Ok(false);
            }
        }
        Ok(true)
    };
    // Whether a frame runs out only shrinks as memory grows: bisect between 1 and the bound.
    let (mut lo, mut hi) = (1, bound);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compile::{compile_mesh, CompileOptions};
    use crate::tools::scenes;

    #[test]
    fn the_fewest_that_never_run_out_over_the_orbit() {
        let mesh = scenes::box_grid(3);
        let (_, bytes) = compile_mesh(&mesh, &CompileOptions::default(), &|_| {}).unwrap();
        let (w, h) = (96, 64);
        let n = spans_per_row(&bytes, w, h).unwrap();
        assert!(n >= 2, "a grid of boxes has rows of several intervals: {n}");
        // With n no frame of the orbit falls back, with n - 1 one does.
        let scene = Scene::parse(&bytes).unwrap();
        let header = scene.header();
        let near = Camera::default_near(header.bounds_min, header.bounds_max);
        let mut workspace: Box<Workspace<{ 1 << 14 }, 64>> = Box::default();
        let mut fallbacks = |per_row: usize| {
            let mut intervals = vec![(0u16, 0u16); per_row * h as usize];
            let mut counts = vec![0u16; h as usize];
            let mut any = false;
            for &elevation_deg in &ORBIT_ELEVATIONS {
                for k in 0..ORBIT_CAMERAS {
                    let orbit = Orbit {
                        azimuth_deg: 360.0 * f64::from(k) / f64::from(ORBIT_CAMERAS),
                        elevation_deg,
                        distance: Orbit::fitting_distance(DEFAULT_FOV_Y_DEG, w, h),
                    };
                    let camera =
                        Camera::look_at(orbit.pose(&header), DEFAULT_FOV_Y_DEG, w, h, near)
                            .unwrap();
                    let coverage = Coverage::new(&mut intervals, &mut counts, w, h).unwrap();
                    any |= Renderer::new(&mut workspace)
                        .span_memory(coverage)
                        .draw(&scene, &camera.view(header.centre), &mut Nowhere)
                        .unwrap()
                        .fallback;
                }
            }
            any
        };
        assert!(!fallbacks(n));
        assert!(fallbacks(n - 1));
        assert!(spans_per_row(&bytes[1..], w, h).is_err());
        // Scan memory of the measured nodes draws every frame of the orbit; one node less
        // fails one of them, with the typed error.
        let nodes = scan_nodes(&bytes, w, h).unwrap();
        assert!(nodes > 0);
        let views = orbit_views(&scene, w, h).unwrap();
        let mut fails = |n: usize| {
            let mut pool = vec![ScanNode::EMPTY; n];
            let mut heads = vec![0u16; h as usize];
            let memory = ScanMemory::new(&mut pool, &mut heads, w, h).unwrap();
            let mut renderer = Renderer::new(&mut workspace).scan_memory(memory);
            views.iter().any(|v| renderer.draw_scan(&scene, v).is_err())
        };
        assert!(!fails(nodes));
        assert!(fails(nodes - 1));
        // Anti-aliased: with the measured nodes every frame of the orbit is anti-aliased; with
        // one less, one is drawn plain (or not at all).
        let aa_nodes = scan_nodes_antialiased(&bytes, w, h).unwrap();
        let mut all_antialiased = |n: usize| {
            let mut pool = vec![ScanNode::EMPTY; n];
            let mut heads = vec![0u16; h as usize];
            let memory = ScanMemory::new(&mut pool, &mut heads, w, h).unwrap();
            let mut records = vec![PendingPixel::default(); MOST_PENDING];
            let mut pending_heads = vec![0u16; h as usize];
            let pending = Pending::new(&mut records, &mut pending_heads, h).unwrap();
            let mut renderer = Renderer::new(&mut workspace)
                .scan_memory(memory)
                .antialias(pending);
            views.iter().all(|v| {
                renderer
                    .draw_scan(&scene, v)
                    .is_ok_and(|f| f.stats().antialiased)
            })
        };
        assert!(all_antialiased(aa_nodes));
        assert!(!all_antialiased(aa_nodes - 1));
        // Pending pixels: with the measured records every anti-aliased frame of the orbit is
        // the one with records to spare; with one less, a row falls back and a frame differs.
        let pending = pending_pixels(&bytes, w, h).unwrap();
        assert!(pending > 0);
        let mut frames = |records: usize| -> Vec<Vec<u32>> {
            views
                .iter()
                .map(|view| {
                    let per_row = (w as usize).div_ceil(2);
                    let mut intervals = vec![(0u16, 0u16); per_row * h as usize];
                    let mut counts = vec![0u16; h as usize];
                    let mut pool = vec![PendingPixel::default(); records];
                    let mut heads = vec![0u16; h as usize];
                    let mut pixels = vec![0u32; (w * h) as usize];
                    let mut fb = peel_runtime::display::Framebuffer::<
                        peel_runtime::display::Xrgb8888,
                    >::new(&mut pixels, w, h)
                    .unwrap();
                    let coverage = Coverage::new(&mut intervals, &mut counts, w, h).unwrap();
                    let pending = Pending::new(&mut pool, &mut heads, h).unwrap();
                    Renderer::new(&mut workspace)
                        .span_memory(coverage)
                        .antialias(pending)
                        .draw(&scene, view, &mut fb)
                        .unwrap();
                    pixels
                })
                .collect()
        };
        let spare = frames(MOST_PENDING);
        assert!(frames(pending) == spare);
        assert!(frames(pending - 1) != spare);
    }
}
