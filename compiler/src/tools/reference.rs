//! Reference: a brute-force f64 ray caster that follows the camera conventions of `docs/host.md`
//! ("Camera and pixels") to the letter, independent of the runtime's projection, clipping and
//! fill. The end-to-end tests and `peel bench` measure pixel errors against it. Per pixel it
//! also knows the side of the triangle seen, so the tests check the lighting
//! ([`Reference::seen_normal`], [`Reference::exclude_grazing_light`]), and the colour the
//! compiler's shading gives it there, faceted or smooth ([`Reference::colours`]). For textured
//! surfaces it gives the exact texel under each pixel centre ([`texels()`]). Transparent
//! surfaces it composites in exact depth order ([`composite()`]).

use crate::shade::corners::Facing;
use crate::shade::smooth::SmoothShades;
use crate::shade::{channel, Shading};
use crate::shadow::Light;

use glam::{DVec2, DVec3};

use super::shot::Shot;

mod composite;
mod texels;
pub use composite::{composite, composite_lit, Composited, OPAQUE};
pub use texels::{modulate, rgb888, texels, TexelHit, Texels};

/// A [`Shot`] as `docs/host.md` defines its camera: the basis `f`, `r`, `u`, the focal length
/// `fpx` in pixels, and the near distance resolved.
#[derive(Debug)]
struct Lens {
    eye: DVec3,
    /// Forward.
    f: DVec3,
    /// Right.
    r: DVec3,
    /// True up.
    u: DVec3,
    /// Focal length in pixels.
    fpx: f64,
    width: u32,
    height: u32,
    near: f64,
}

impl Lens {
    /// `f`, `r`, `u`, `fpx` of `shot` as `docs/host.md` defines them.
    fn new(shot: &Shot, near: f64) -> Lens {
        let f = (shot.target - shot.eye).normalize();
        let r = f.cross(shot.up).normalize();
        let u = r.cross(f);
        let fpx = (f64::from(shot.height) / 2.0) / (shot.fov_y_deg.to_radians() / 2.0).tan();
        Lens {
            eye: shot.eye,
            f,
            r,
            u,
            fpx,
            width: shot.width,
            height: shot.height,
            near,
        }
    }

    /// The ray through the centre of pixel `(i, j)` (its component along `f` is 1).
    fn ray(&self, i: usize, j: usize) -> DVec3 {
        self.ray_at(i as f64 + 0.5, j as f64 + 0.5)
    }

    /// The ray through the screen point `(x, y)`, in pixels from the top-left corner.
    fn ray_at(&self, x: f64, y: f64) -> DVec3 {
        self.f + ((x - f64::from(self.width) / 2.0) / self.fpx) * self.r
            - ((y - f64::from(self.height) / 2.0) / self.fpx) * self.u
    }

    /// Camera-space coordinates of a world point.
    fn to_camera(&self, p: DVec3) -> DVec3 {
        let d = p - self.eye;
        DVec3::new(d.dot(self.r), d.dot(self.u), d.dot(self.f))
    }

    /// Screen position of a camera-space point with `zc > 0`.
    fn project(&self, c: DVec3) -> DVec2 {
        DVec2::new(
            f64::from(self.width) / 2.0 + self.fpx * c.x / c.z,
            f64::from(self.height) / 2.0 - self.fpx * c.y / c.z,
        )
    }
}

/// What the reference sees: per pixel (row-major), `id + 1` of the nearest triangle hit by the
/// ray through the pixel centre at camera depth `>= near` (0: nothing), the side of it seen,
/// and whether the sample point is farther than 1/16 pixel from every projected edge.
#[derive(Debug, Clone)]
pub struct Reference {
    /// `id + 1` per pixel, 0 for background.
    pub ids: Vec<u32>,
    /// True where the pixel's ray sees the front of its triangle (the side from which its
    /// vertices wind counter-clockwise).
    pub front: Vec<bool>,
    /// True where the pixel's sample point is farther than 1/16 pixel from all edges.
    pub robust: Vec<bool>,
}

/// Distance from an edge below which a pixel is not "robust".
pub const EDGE_MARGIN: f64 = 1.0 / 16.0;

/// `|n · l|` below which a pixel is not robust for lighting: a side lit that nearly edge-on is
/// within rounding of the unlit colour, and the compiler lights the plane of the quantised
/// triangle, whose normal may differ from the source triangle's by about the grid's precision.
pub const LIGHT_MARGIN: f64 = 1.0 / 64.0;

/// How [`Reference::colours`] lights the side of a triangle a pixel sees.
#[derive(Debug, Clone, Copy)]
pub enum Lighting<'a> {
    /// One colour a side: [`Shading::shade_at`] the side's normal at the point the pixel's ray
    /// hits (faceted; unlit with [`Shading::Flat`]).
    Faceted(Shading),
    /// Smooth: the side's corner colours interpolated at the point the pixel's ray hits
    /// ([`crate::shade::corners::CornerShades::colour_at`]), of these shades of the triangles.
    Smooth(&'a SmoothShades),
}

impl Reference {
    /// The colour of each pixel (row-major; `None` for the background) in 8-bit units,
    /// unrounded: that of the side of its triangle seen, lit by `lighting`, for the material
    /// colours `kd` (one a triangle), or `Kd * AMBIENT` where `shadowed` (per pixel, as
    /// [`shadowed`] gives it) is set. `triangles`, `shot` and `near` are what the reference
    /// was cast with.
    pub fn colours_exact(
        &self,
        triangles: &[[DVec3; 3]],
        kd: &[[u8; 3]],
        shot: &Shot,
        near: f64,
        lighting: Lighting<'_>,
        shadowed: Option<&[bool]>,
    ) -> Vec<Option<[f64; 3]>> {
        let cam = &Lens::new(shot, near);
        (0..self.ids.len())
            .map(|k| {
                let id = self.ids[k].checked_sub(1)? as usize;
                let p = self.hit(cam, triangles, k)?;
                let kd = kd[id].map(f64::from);
                let in_shadow = shadowed.is_some_and(|s| s[k]);
                let intensity = match lighting {
                    Lighting::Faceted(shading) if in_shadow => shading.intensity_in_shadow(),
                    Lighting::Faceted(shading) => {
                        shading.intensity_at(self.seen_normal(triangles, k)?, p)
                    }
                    Lighting::Smooth(shades) if in_shadow => shades.in_shadow,
                    Lighting::Smooth(shades) => {
                        shades.triangles[id].intensity_at(Facing::of(self.front[k]), p)
                    }
                };
                Some(kd.map(|c| c * intensity))
            })
            .collect()
    }

    /// [`Reference::colours_exact`] rounded to 8 bits, as a picture shows them.
    pub fn colours(
        &self,
        triangles: &[[DVec3; 3]],
        kd: &[[u8; 3]],
        shot: &Shot,
        near: f64,
        lighting: Lighting<'_>,
        shadowed: Option<&[bool]>,
    ) -> Vec<Option<[u8; 3]>> {
        self.colours_exact(triangles, kd, shot, near, lighting, shadowed)
            .into_iter()
            .map(|c| c.map(|c| c.map(channel)))
            .collect()
    }

    /// The unit normal of the side of its triangle that pixel `k` sees (pointing to the eye),
    /// `triangles` being those the reference was cast against; `None` for the background.
    pub fn seen_normal(&self, triangles: &[[DVec3; 3]], k: usize) -> Option<DVec3> {
        let id = self.ids.get(k)?.checked_sub(1)?;
        let [a, b, c] = triangles.get(id as usize)?;
        let n = (*b - *a).cross(*c - *a).normalize_or_zero();
        Some(if self.front[k] { n } else { -n })
    }

    /// Marks as not robust the pixels whose side seen is lit within [`LIGHT_MARGIN`] of edge-on
    /// by `shading`'s light (none for [`Shading::Flat`]), `triangles`, `shot` and `near` being
    /// what the reference was cast with.
    pub fn exclude_grazing_light(
        &mut self,
        triangles: &[[DVec3; 3]],
        shot: &Shot,
        near: f64,
        shading: &Shading,
    ) {
        let cam = &Lens::new(shot, near);
        for k in 0..self.ids.len() {
            let (Some(n), Some(p)) = (self.seen_normal(triangles, k), self.hit(cam, triangles, k))
            else {
                continue;
            };
            let towards = match *shading {
                Shading::Flat => return,
                Shading::Lambert(towards) => towards,
                Shading::Point(at) => at - p,
            };
            if n.dot(towards.normalize_or_zero()).abs() < LIGHT_MARGIN {
                self.robust[k] = false;
            }
        }
    }

    /// The point pixel `k`'s ray hits (`None` for the background), `triangles`, `shot` and
    /// `near` being what the reference was cast with.
    pub fn hit_point(
        &self,
        triangles: &[[DVec3; 3]],
        shot: &Shot,
        near: f64,
        k: usize,
    ) -> Option<DVec3> {
        self.hit(&Lens::new(shot, near), triangles, k)
    }

    /// The point pixel `k`'s ray hits.
    fn hit(&self, cam: &Lens, triangles: &[[DVec3; 3]], k: usize) -> Option<DVec3> {
        let id = self.ids.get(k)?.checked_sub(1)? as usize;
        let w = cam.width as usize;
        let dir = cam.ray(k % w, k / w);
        ray_triangle(cam.eye, dir, triangles.get(id)?).map(|t| cam.eye + dir * t)
    }
}

/// Cast one ray per pixel of `shot` against `triangles` (the source triangles: ids are
/// indices), seeing from the near distance `near` on (the shot's own resolved over the
/// scene, [`Shot::near_over`]), and mark the pixels near the projected edges of `triangles`
/// and of `extra_polygons` (e.g. the compiled polygons, whose edges include the cuts).
pub fn reference(
    triangles: &[[DVec3; 3]],
    extra_polygons: &[Vec<DVec3>],
    shot: &Shot,
    near: f64,
) -> Reference {
    let cam = &Lens::new(shot, near);
    let (w, h) = (cam.width as usize, cam.height as usize);
    let mut depth = vec![f64::INFINITY; w * h];
    let mut ids = vec![0u32; w * h];
    let mut front = vec![false; w * h];
    let mut robust = vec![true; w * h];
    for (id, t) in triangles.iter().enumerate() {
        let normal = (t[1] - t[0]).cross(t[2] - t[0]);
        let c = t.map(|p| cam.to_camera(p));
        let Some((x0, x1, y0, y1)) = screen_bbox(cam, &c) else {
            continue;
        };
        for j in y0..y1 {
            for i in x0..x1 {
                let dir = cam.ray(i, j);
                if let Some(tz) = ray_triangle(cam.eye, dir, t) {
                    // dir has unit component along f, so the ray parameter is the camera depth.
                    let k = j * w + i;
                    if tz >= cam.near && tz < depth[k] {
                        depth[k] = tz;
                        ids[k] = id as u32 + 1;
                        front[k] = dir.dot(normal) < 0.0;
                    }
                }
            }
        }
        mark_polygon_edges(cam, &c, &mut robust);
    }
    for p in extra_polygons {
        let c: Vec<DVec3> = p.iter().map(|&q| cam.to_camera(q)).collect();
        mark_polygon_edges(cam, &c, &mut robust);
    }
    Reference { ids, front, robust }
}

/// Per pixel of `seen` (the [`reference()`] of `triangles` for `shot` and `near`): whether the
/// point its ray hits is in shadow from `light`, the side seen facing the light: the ray from
/// that point towards the sun (along [`crate::shadow::sun_direction`], as the compiler casts
/// it), or the segment to the point light, meets another triangle. A pixel near a shadow's
/// boundary is one near a compiled polygon's edge (the compiler cuts polygons there), which
/// `seen` marks.
pub fn shadowed(
    seen: &Reference,
    triangles: &[[DVec3; 3]],
    shot: &Shot,
    near: f64,
    light: Light,
) -> Vec<bool> {
    let cam = &Lens::new(shot, near);
    let sun = match light {
        Light::Sun(towards) => match crate::shadow::sun_direction(towards) {
            Some(l) => Some(DVec3::new(l[0] as f64, l[1] as f64, l[2] as f64).normalize()),
            None => return vec![false; seen.ids.len()],
        },
        Light::Point(_) => None,
    };
    (0..seen.ids.len())
        .map(|k| {
            let (Some(n), Some(p)) = (seen.seen_normal(triangles, k), seen.hit(cam, triangles, k))
            else {
                return false;
            };
            // Towards the light, and how far along it the light is.
            let (l, reach) = match (sun, light) {
                (Some(l), _) => (l, f64::INFINITY),
                (None, Light::Point(at) | Light::Sun(at)) => (at - p, 1.0),
            };
            if n.dot(l) <= 0.0 {
                return false; // turned away from the light: unlit anyway
            }
            let id = seen.ids[k] as usize - 1;
            // Hits at the point itself (a neighbour sharing its edge) are not shadows.
            let from = 1e-9 * p.abs().max_element().max(1.0) / l.length();
            (triangles.iter().enumerate()).any(|(other, tri)| {
                other != id && ray_triangle(p, l, tri).is_some_and(|s| s > from && s < reach)
            })
        })
        .collect()
}

/// The colour `n x n` samples per pixel (a box filter) see, per pixel (row-major) and channel,
/// in 8-bit units: each sample's ray, at `(i + (a + 1/2) / n, j + (b + 1/2) / n)`, takes
/// `colour(id, front)` of the nearest of `triangles` it hits at camera depth `>= near` (the
/// triangle's index, and whether the front is seen, as in [`Reference`]), `background` where
/// it hits none. The reference an anti-aliased frame is measured against. [`sampled`] on an
/// `n x n` grid, its means as `f32`.
pub fn supersampled(
    triangles: &[[DVec3; 3]],
    shot: &Shot,
    near: f64,
    n: u32,
    colour: impl Fn(usize, bool) -> [u8; 3],
    background: [u8; 3],
) -> Vec<[f32; 3]> {
    let n = n.max(1);
    let grid = Grid {
        columns: n,
        rows: n,
    };
    let seen = cast_samples(triangles, None, shot, near, grid, colour, background);
    seen.colours.iter().map(|c| c.map(|v| v as f32)).collect()
}

/// A grid of sample points per pixel: sample `(s, t)` of pixel `(i, j)` at
/// `(i + (s + 1/2) / columns, j + (t + 1/2) / rows)`, as the runtime's anti-aliased frames
/// place theirs (`peel_runtime::fill::samples`, whose `SAMPLE_COLUMNS` and `SAMPLE_ROWS` give
/// its grid).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Grid {
    /// Samples per pixel across.
    pub columns: u32,
    /// Samples per pixel down.
    pub rows: u32,
}

impl Grid {
    /// The runtime's grid (`peel_runtime::fill::samples`).
    pub const RUNTIME: Grid = Grid {
        columns: peel_runtime::fill::samples::SAMPLE_COLUMNS,
        rows: peel_runtime::fill::samples::SAMPLE_ROWS,
    };

    /// Samples per pixel.
    pub fn samples(self) -> u32 {
        self.columns * self.rows
    }
}

/// What [`sampled`] sees, per pixel (row-major).
#[derive(Debug, Clone)]
pub struct Sampled {
    /// The grid sampled.
    pub grid: Grid,
    /// Per pixel and channel, in 8-bit units: the exact mean of its samples' colours (a sum of
    /// integers over the sample count, correctly rounded to `f64`).
    pub colours: Vec<[f64; 3]>,
    /// Per pixel: how many of its samples are within [`EDGE_MARGIN`] (1/16 pixel, Euclidean,
    /// in screen pixels) of a projected edge: see [`sampled`].
    pub near_edge: Vec<u32>,
}

/// The colour the samples of `grid` see, per pixel of `shot`: each sample's ray takes
/// `colour(id, front)` of the nearest of `triangles` it hits at camera depth `>= near` (the
/// triangle's index, and whether the front is seen, as in [`Reference`]), `background` where
/// it hits none; a pixel's colour is their exact mean, not rounded. On the runtime's grid
/// ([`Grid::RUNTIME`]) these are the very points an anti-aliased frame samples, so its pixels
/// are these means rounded, but for samples so near an edge that snapping and the compiler's
/// quantisation may move them to the other side.
///
/// Those are counted per pixel ([`Sampled::near_edge`]), conservatively: a sample is near an
/// edge when it lies within [`EDGE_MARGIN`] (Euclidean distance in screen pixels) of a
/// projected edge of any of `triangles` (seen or hidden) or of `extra_polygons` (e.g. the
/// compiled polygons, whose edges include the cuts: where interpenetrating triangles meet),
/// each clipped to the near plane first (the clip adds the near-plane edge, which the
/// renderer also draws), as [`reference()`] marks pixel centres.
pub fn sampled(
    triangles: &[[DVec3; 3]],
    extra_polygons: &[Vec<DVec3>],
    shot: &Shot,
    near: f64,
    grid: Grid,
    colour: impl Fn(usize, bool) -> [u8; 3],
    background: [u8; 3],
) -> Sampled {
    let grid = Grid {
        columns: grid.columns.max(1),
        rows: grid.rows.max(1),
    };
    cast_samples(
        triangles,
        Some(extra_polygons),
        shot,
        near,
        grid,
        colour,
        background,
    )
}

/// [`sampled`], counting the samples near edges only given `extra_polygons` (else
/// [`Sampled::near_edge`] is all zero); `grid` has no zero side.
fn cast_samples(
    triangles: &[[DVec3; 3]],
    extra_polygons: Option<&[Vec<DVec3>]>,
    shot: &Shot,
    near: f64,
    grid: Grid,
    colour: impl Fn(usize, bool) -> [u8; 3],
    background: [u8; 3],
) -> Sampled {
    let cam = &Lens::new(shot, near);
    let (w, h) = (cam.width as usize, cam.height as usize);
    let (nx, ny) = (grid.columns as usize, grid.rows as usize);
    let boxes: Vec<Option<(usize, usize, usize, usize)>> = triangles
        .iter()
        .map(|t| screen_bbox(cam, &t.map(|p| cam.to_camera(p))))
        .collect();
    // The projected edges, when counting the samples near them.
    let mut edges: Vec<(DVec2, DVec2)> = Vec::new();
    if let Some(extra) = extra_polygons {
        let camera_space = |p: &[DVec3]| p.iter().map(|&q| cam.to_camera(q)).collect::<Vec<_>>();
        let outlines = (triangles.iter().map(|t| camera_space(t)))
            .chain(extra.iter().map(|p| camera_space(p)));
        for c in outlines {
            let s = screen_outline(cam, &c);
            edges.extend((0..s.len()).map(|k| (s[k], s[(k + 1) % s.len()])));
        }
    }
    let mut out = Sampled {
        grid,
        colours: vec![[0.0; 3]; w * h],
        near_edge: vec![0; w * h],
    };
    // A band of 8 pixel rows at a time keeps the samples' depths small.
    const BAND: usize = 8;
    let per_row = w * nx;
    let mut depth = vec![f64::INFINITY; per_row * BAND * ny];
    let mut seen = vec![None::<(usize, bool)>; per_row * BAND * ny];
    let mut near_edge = vec![false; if edges.is_empty() { 0 } else { seen.len() }];
    for band in (0..h).step_by(BAND) {
        let rows = band..(band + BAND).min(h);
        depth.fill(f64::INFINITY);
        seen.fill(None);
        near_edge.fill(false);
        for (id, t) in triangles.iter().enumerate() {
            let Some((x0, x1, y0, y1)) = boxes[id] else {
                continue;
            };
            let normal = (t[1] - t[0]).cross(t[2] - t[0]);
            for j in y0.max(rows.start)..y1.min(rows.end) {
                for sj in 0..ny {
                    let y = j as f64 + (sj as f64 + 0.5) / ny as f64;
                    let row = ((j - rows.start) * ny + sj) * per_row;
                    for i in x0..x1 {
                        for si in 0..nx {
                            let x = i as f64 + (si as f64 + 0.5) / nx as f64;
                            let dir = cam.ray_at(x, y);
                            if let Some(tz) = ray_triangle(cam.eye, dir, t) {
                                let k = row + i * nx + si;
                                if tz >= cam.near && tz < depth[k] {
                                    depth[k] = tz;
                                    seen[k] = Some((id, dir.dot(normal) < 0.0));
                                }
                            }
                        }
                    }
                }
            }
        }
        for &(a, b) in &edges {
            mark_samples(a, b, w, grid, rows.clone(), &mut near_edge);
        }
        for j in rows.clone() {
            for i in 0..w {
                let (mut sum, mut near) = ([0u64; 3], 0);
                for sj in 0..ny {
                    let row = ((j - rows.start) * ny + sj) * per_row;
                    for si in 0..nx {
                        let k = row + i * nx + si;
                        let c = seen[k].map_or(background, |(id, front)| colour(id, front));
                        for (s, v) in sum.iter_mut().zip(c) {
                            *s += u64::from(v);
                        }
                        near += u32::from(near_edge.get(k).copied().unwrap_or(false));
                    }
                }
                out.colours[j * w + i] = sum.map(|s| s as f64 / (nx * ny) as f64);
                out.near_edge[j * w + i] = near;
            }
        }
    }
    out
}

/// How far a picture (RGB bytes, row-major) is from a [`supersampled`] reference, per channel in
/// 8-bit units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImageError {
    /// The largest difference.
    pub max: f32,
    /// The 99.9th percentile of the differences.
    pub p999: f32,
    /// The mean difference.
    pub mean: f32,
}

impl ImageError {
    /// `picture` (3 bytes a pixel) against `reference`.
    pub fn of(picture: &[u8], reference: &[[f32; 3]]) -> ImageError {
        let mut d: Vec<f32> = picture
            .chunks_exact(3)
            .zip(reference)
            .flat_map(|(p, r)| (0..3).map(move |c| (f32::from(p[c]) - r[c]).abs()))
            .collect();
        if d.is_empty() {
            return ImageError {
                max: 0.0,
                p999: 0.0,
                mean: 0.0,
            };
        }
        d.sort_by(f32::total_cmp);
        let at = ((d.len() as f64 * 0.999).ceil() as usize).clamp(1, d.len()) - 1;
        ImageError {
            max: d[d.len() - 1],
            p999: d[at],
            mean: (d.iter().map(|&v| f64::from(v)).sum::<f64>() / d.len() as f64) as f32,
        }
    }
}

/// Pixel range (`x0..x1`, `y0..y1`) that may see the camera-space polygon `c`.
fn screen_bbox(cam: &Lens, c: &[DVec3]) -> Option<(usize, usize, usize, usize)> {
    if c.iter().all(|p| p.z < cam.near) {
        return None;
    }
    let (w, h) = (cam.width as usize, cam.height as usize);
    if c.iter().any(|p| p.z < cam.near) {
        return Some((0, w, 0, h)); // crosses the near plane: test every pixel
    }
    let s: Vec<DVec2> = c.iter().map(|&p| cam.project(p)).collect();
    let lo = s.iter().fold(DVec2::splat(f64::INFINITY), |a, &p| a.min(p));
    let hi = s
        .iter()
        .fold(DVec2::splat(f64::NEG_INFINITY), |a, &p| a.max(p));
    let clamp = |v: f64, n: usize| v.max(0.0).min(n as f64) as usize;
    let (x0, x1) = (clamp(lo.x - 1.0, w), clamp(hi.x + 2.0, w));
    let (y0, y1) = (clamp(lo.y - 1.0, h), clamp(hi.y + 2.0, h));
    (x0 < x1 && y0 < y1).then_some((x0, x1, y0, y1))
}

/// Möller–Trumbore; returns the ray parameter of the hit (both faces count).
fn ray_triangle(o: DVec3, d: DVec3, t: &[DVec3; 3]) -> Option<f64> {
    ray_hit(o, d, t).map(|(s, _)| s)
}

/// [`ray_triangle`] with the hit point's barycentric weights of `t`'s corners (the point is
/// `w[0] t[0] + w[1] t[1] + w[2] t[2]`), which interpolate anything given per corner exactly
/// as it varies over the triangle in space: the perspective-correct interpolation.
fn ray_hit(o: DVec3, d: DVec3, t: &[DVec3; 3]) -> Option<(f64, [f64; 3])> {
    let e1 = t[1] - t[0];
    let e2 = t[2] - t[0];
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - t[0];
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some((e2.dot(q) * inv, [1.0 - u - v, u, v]))
}

/// Mark pixels near the projected edges of the camera-space polygon `c`, after clipping it to
/// the near plane (the clip adds the near-plane edge, which the renderer also draws).
fn mark_polygon_edges(cam: &Lens, c: &[DVec3], robust: &mut [bool]) {
    let s = screen_outline(cam, c);
    for k in 0..s.len() {
        mark_segment(cam, s[k], s[(k + 1) % s.len()], robust);
    }
}

/// The camera-space polygon `c` clipped to the near plane (the clip adds the near-plane edge,
/// which the renderer also draws) and projected: its screen outline.
fn screen_outline(cam: &Lens, c: &[DVec3]) -> Vec<DVec2> {
    let mut clipped = Vec::with_capacity(c.len() + 1);
    for k in 0..c.len() {
        let (p, q) = (c[k], c[(k + 1) % c.len()]);
        if p.z >= cam.near {
            clipped.push(p);
        }
        if (p.z >= cam.near) != (q.z >= cam.near) {
            let t = (cam.near - p.z) / (q.z - p.z);
            clipped.push(p + (q - p) * t);
        }
    }
    clipped.iter().map(|&p| cam.project(p)).collect()
}

/// Mark in `near` every sample of `grid` within [`EDGE_MARGIN`] of the screen segment `a`-`b`
/// in the pixel rows `rows` of a `width`-pixel image, `near` holding those rows' samples as
/// [`cast_samples`] lays them out (row-major, sample rows of pixel row `rows.start` first).
fn mark_samples(
    a: DVec2,
    b: DVec2,
    width: usize,
    grid: Grid,
    rows: std::ops::Range<usize>,
    near: &mut [bool],
) {
    let (nx, ny) = (f64::from(grid.columns), f64::from(grid.rows));
    let per_row = width * grid.columns as usize;
    let m = EDGE_MARGIN;
    // The candidates are found with a little slack; the distance alone decides.
    let slack = 1e-9;
    // Sample index `g` (of the image's sample columns or rows, `n` a pixel) of the samples
    // whose coordinates `(g + 1/2) / n` lie in `[lo, hi]`: `first .. end`, within `limit`.
    let span = |lo: f64, hi: f64, n: f64, limit: std::ops::Range<usize>| {
        let first = ((lo - slack) * n - 0.5).ceil();
        let end = ((hi + slack) * n - 0.5).floor() + 1.0;
        let clamp = |v: f64| v.clamp(limit.start as f64, limit.end as f64) as usize;
        clamp(first)..clamp(end)
    };
    let d = b - a;
    let sample_rows = rows.start * grid.rows as usize..rows.end * grid.rows as usize;
    let ys = span(a.y.min(b.y) - m, a.y.max(b.y) + m, ny, sample_rows.clone());
    for g in ys {
        let y = (g as f64 + 0.5) / ny;
        // The part of the segment within `m` of the sample row, vertically, grown by `m`.
        let (t0, t1) = if d.y == 0.0 {
            (0.0, 1.0)
        } else {
            let (u, v) = ((y - m - a.y) / d.y, (y + m - a.y) / d.y);
            (u.min(v).max(0.0), u.max(v).min(1.0))
        };
        let (xa, xb) = (a.x + d.x * t0, a.x + d.x * t1);
        let xs = span(xa.min(xb) - m, xa.max(xb) + m, nx, 0..per_row);
        let row = (g - sample_rows.start) * per_row;
        for s in xs {
            let p = DVec2::new((s as f64 + 0.5) / nx, y);
            if segment_distance(p, a, b) <= m {
                near[row + s] = true;
            }
        }
    }
}

/// Mark every pixel whose centre is within [`EDGE_MARGIN`] of the segment `a`-`b`.
fn mark_segment(cam: &Lens, a: DVec2, b: DVec2, robust: &mut [bool]) {
    let (w, h) = (f64::from(cam.width), f64::from(cam.height));
    // Clip to the screen grown by two pixels (Liang–Barsky), so long edges cost their on-screen length.
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, a.x + 2.0),
        (d.x, w + 2.0 - a.x),
        (-d.y, a.y + 2.0),
        (d.y, h + 2.0 - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0 > t1 {
        return;
    }
    let (ca, cb) = (a + d * t0, a + d * t1);
    let steps = ((cb - ca).length() * 2.0).ceil().max(1.0) as usize;
    for s in 0..=steps {
        let p = ca + (cb - ca) * (s as f64 / steps as f64);
        let (pi, pj) = (p.x.floor() as i64, p.y.floor() as i64);
        for j in pj - 1..=pj + 1 {
            for i in pi - 1..=pi + 1 {
                if i < 0 || j < 0 || i >= i64::from(cam.width) || j >= i64::from(cam.height) {
                    continue;
                }
                let centre = DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
                if segment_distance(centre, a, b) <= EDGE_MARGIN {
                    robust[j as usize * cam.width as usize + i as usize] = false;
                }
            }
        }
    }
}

fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let len2 = d.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + d * t - p).length()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square of world size 2 seen head-on covering exactly the left half of the middle
    /// pixel column's pixels: they are half white, and whole pixels are exact.
    #[test]
    fn supersampling_averages_the_samples() {
        // 9 x 9 pixels; at distance 5 with the shot's field of view, find the world width of a
        // pixel and put the square's right edge through the middle of pixel column 4.
        let s = shot(9, 9);
        let lens = Lens::new(&s, 0.01);
        let px = 5.0 / lens.fpx;
        let right = 0.0; // the image centre, x = 4.5 pixels
        let quad = |x0: f64, x1: f64| {
            [
                [
                    DVec3::new(x0, -10.0, 0.0),
                    DVec3::new(x1, -10.0, 0.0),
                    DVec3::new(x1, 10.0, 0.0),
                ],
                [
                    DVec3::new(x0, -10.0, 0.0),
                    DVec3::new(x1, 10.0, 0.0),
                    DVec3::new(x0, 10.0, 0.0),
                ],
            ]
        };
        let tris = quad(-20.0 * px, right);
        let white = |_: usize, _: bool| [255, 255, 255];
        let img = supersampled(&tris, &s, 0.01, 16, white, [0, 0, 0]);
        for j in 0..9 {
            assert_eq!(img[j * 9 + 3], [255.0; 3], "left of the edge");
            assert_eq!(img[j * 9 + 4], [127.5; 3], "half covered");
            assert_eq!(img[j * 9 + 5], [0.0; 3], "right of it");
        }
        // The picture without anti-aliasing (column 4's centre is on the edge: say it is white)
        // is 127.5 off on column 4's 27 channels, exact elsewhere.
        let plain: Vec<u8> = (0..81)
            .flat_map(|k| [if k % 9 <= 4 { 255 } else { 0 }; 3])
            .collect();
        let e = ImageError::of(&plain, &img);
        assert_eq!(e.max, 127.5);
        assert_eq!(e.p999, 127.5);
        assert!((e.mean - 127.5 * 27.0 / 243.0).abs() < 1e-4, "{e:?}");
        // Sides: the square seen from its back gets the back's colour.
        let sides = supersampled(
            &tris,
            &s,
            0.01,
            2,
            |_, front| if front { [9, 9, 9] } else { [7, 7, 7] },
            [0, 0, 0],
        );
        let facing = tris[0];
        let front = (facing[1] - facing[0]).cross(facing[2] - facing[0]).z > 0.0;
        assert_eq!(sides[4 * 9 + 2], [if front { 9.0 } else { 7.0 }; 3]);
    }

    /// One big white triangle on black whose only edge on screen is vertical, through pixel
    /// column 4 just right of a sample column: on every grid (the runtime's too), that column's
    /// pixels see the samples left of the edge, and count the samples within 1/16 pixel of it
    /// (of it alone: the others are off screen); an extra polygon's edge counts too.
    #[test]
    fn samples_see_the_triangle_and_count_those_near_its_edges() {
        let s = shot(9, 9);
        let px = 5.0 / Lens::new(&s, 0.01).fpx; // world units a pixel, at the triangle's depth
        let world_x = |x: f64| (x - 4.5) * px;
        let world_y = |y: f64| (4.5 - y) * px;
        for grid in [
            Grid::RUNTIME,
            Grid {
                columns: 4,
                rows: 2,
            },
            Grid {
                columns: 16,
                rows: 16,
            },
        ] {
            let (nx, ny) = (f64::from(grid.columns), f64::from(grid.rows));
            let k = f64::from(grid.samples());
            // The edge 0.03 pixel right of the middle sample column of pixel column 4.
            let edge = 4.0 + (f64::from(grid.columns / 2) + 0.5) / nx + 0.03;
            let e = world_x(edge);
            let tri = [[
                DVec3::new(e, -10.0, 0.0),
                DVec3::new(e, 10.0, 0.0),
                DVec3::new(-30.0, 0.0, 0.0),
            ]];
            let xs = (0..grid.columns).map(|c| 4.0 + (f64::from(c) + 0.5) / nx);
            let inside = xs.clone().filter(|&x| x < edge).count() as f64 * ny;
            let near = xs.filter(|&x| (x - edge).abs() <= EDGE_MARGIN).count() as u32;
            let near = near * grid.rows;
            assert!(
                near >= grid.rows,
                "{grid:?}: the middle sample column is near"
            );
            let white = |_: usize, _: bool| [255, 255, 255];
            let seen = sampled(&tri, &[], &s, 0.01, grid, white, [0, 0, 0]);
            assert_eq!(seen.grid, grid);
            for j in 0..9 {
                let at = |i: usize| (seen.colours[j * 9 + i], seen.near_edge[j * 9 + i]);
                assert_eq!(at(3), ([255.0; 3], 0), "{grid:?}: left of the edge");
                assert_eq!(at(4), ([255.0 * inside / k; 3], near), "{grid:?}: on it");
                assert_eq!(at(5), ([0.0; 3], 0), "{grid:?}: right of it");
            }
            // The same means as `supersampled`'s on square grids.
            if nx == ny {
                let square = supersampled(&tri, &s, 0.01, grid.columns, white, [0, 0, 0]);
                let means: Vec<[f32; 3]> =
                    seen.colours.iter().map(|c| c.map(|v| v as f32)).collect();
                assert_eq!(square, means);
            }
            // A polygon whose one edge on screen is horizontal, 0.02 pixel below the first
            // sample row of pixel row 2: those samples are near it, the rest of the row's not
            // (but column 4's near the triangle).
            let y = 2.0 + 0.5 / ny + 0.02;
            let below = world_y(y);
            let quad = vec![
                DVec3::new(-30.0, below, 0.0),
                DVec3::new(30.0, below, 0.0),
                DVec3::new(30.0, 30.0, 0.0),
                DVec3::new(-30.0, 30.0, 0.0),
            ];
            let cut = sampled(&tri, &[quad], &s, 0.01, grid, white, [0, 0, 0]);
            assert_eq!(
                cut.colours, seen.colours,
                "{grid:?}: extra polygons are not seen"
            );
            let rows_near = (0..grid.rows)
                .filter(|&t| (2.0 + (f64::from(t) + 0.5) / ny - y).abs() <= EDGE_MARGIN)
                .count() as u32;
            assert!(rows_near >= 1);
            for j in 0..9 {
                let want = if j == 2 { rows_near * grid.columns } else { 0 };
                assert_eq!(cut.near_edge[j * 9], want, "{grid:?}: pixel (0, {j})");
            }
            let both = near + rows_near * grid.columns - near / grid.rows * rows_near;
            assert_eq!(cut.near_edge[2 * 9 + 4], both, "{grid:?}: near both edges");
        }
    }

    fn shot(w: u32, h: u32) -> Shot {
        Shot::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, w, h)
    }

    /// A triangle in the plane z = 0, counter-clockwise seen from [`shot`]'s eye (its front),
    /// around the origin, which the centre pixel's ray hits.
    fn facing() -> [[DVec3; 3]; 1] {
        [[
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ]]
    }

    #[test]
    fn centre_pixel_sees_the_facing_triangle_and_corners_see_nothing() {
        let t = facing();
        let r = reference(&t, &[], &shot(33, 33), 0.01);
        assert_eq!(r.ids[16 * 33 + 16], 1);
        assert_eq!(r.ids[0], 0);
        assert!(r.robust[16 * 33 + 16]);
    }

    #[test]
    fn nearer_triangle_wins_and_edges_are_not_robust() {
        let far = [
            DVec3::new(-3.0, -3.0, -1.0),
            DVec3::new(3.0, -3.0, -1.0),
            DVec3::new(0.0, 3.0, -1.0),
        ];
        let near = [
            DVec3::new(-1.0, -0.9, 1.0),
            DVec3::new(1.1, -1.0, 1.0),
            DVec3::new(0.1, 1.0, 1.0),
        ];
        let r = reference(&[far, near], &[], &shot(64, 64), 0.01);
        assert_eq!(r.ids[32 * 64 + 32], 2);
        // A pixel column crossing the near triangle's left edge has a non-robust pixel.
        assert!(r.robust.iter().any(|&x| !x));
        assert!(r.robust.iter().filter(|&&x| x).count() > 64 * 64 / 2);
    }

    #[test]
    fn each_pixel_knows_the_side_it_sees_and_grazing_light_is_not_robust() {
        // Counter-clockwise seen from +z (the eye): its front.
        let t = facing();
        let centre = 16 * 33 + 16;
        let r = reference(&t, &[], &shot(33, 33), 0.01);
        assert!(r.front[centre]);
        assert_eq!(r.seen_normal(&t, centre), Some(DVec3::Z));
        assert_eq!(r.seen_normal(&t, 0), None, "background");
        let back = [[t[0][0], t[0][2], t[0][1]]];
        let r = reference(&back, &[], &shot(33, 33), 0.01);
        assert!(!r.front[centre]);
        assert_eq!(r.seen_normal(&back, centre), Some(DVec3::Z));
        let robust = r.robust.iter().filter(|&&x| x).count();
        let s = shot(33, 33);
        let mut lit = r.clone();
        lit.exclude_grazing_light(
            &back,
            &s,
            0.01,
            &Shading::Lambert(DVec3::new(0.0, 1.0, 0.1)),
        );
        assert_eq!(
            lit.robust.iter().filter(|&&x| x).count(),
            robust,
            "n.l = 0.0995"
        );
        let mut grazing = r.clone();
        let sun = Shading::Lambert(DVec3::new(0.0, 1.0, -0.01));
        grazing.exclude_grazing_light(&back, &s, 0.01, &sun);
        assert!(!grazing.robust[centre], "|n.l| = 0.01");
        assert!(grazing.robust[0], "the background keeps its verdict");
    }

    /// The colour of a pixel: faceted, as `Shading::shade_at` the side seen; smooth, its
    /// corners' intensities interpolated at the point hit; in shadow, the ambient part.
    #[test]
    fn colours_follow_the_lighting() {
        use crate::shade::corners::CornerShades;
        use crate::shade::AMBIENT;
        // The centre pixel's ray hits the origin, a quarter of the way from each of the first
        // two corners to the third.
        let t = facing();
        let (s, centre, kd) = (shot(33, 33), 16 * 33 + 16, [[200, 100, 40]]);
        let r = reference(&t, &[], &s, 0.01);
        let sun = Shading::Lambert(DVec3::new(0.0, 0.6, 0.8));
        let faceted = r.colours(&t, &kd, &s, 0.01, Lighting::Faceted(sun), None);
        assert_eq!(faceted[centre], Some(sun.shade(kd[0], DVec3::Z)));
        assert_eq!(faceted[0], None, "the background");
        let unlit = r.colours(&t, &kd, &s, 0.01, Lighting::Faceted(Shading::Flat), None);
        assert_eq!(unlit[centre], Some(kd[0]));
        let shades = SmoothShades {
            triangles: vec![CornerShades {
                corners: t[0],
                front: [1.0, AMBIENT, 0.65],
                back: [AMBIENT; 3],
            }],
            in_shadow: AMBIENT,
        };
        let smooth = r.colours_exact(&t, &kd, &s, 0.01, Lighting::Smooth(&shades), None);
        let k = 0.25 * 1.0 + 0.25 * AMBIENT + 0.5 * 0.65;
        let want = kd[0].map(|c| f64::from(c) * k);
        let got = smooth[centre].unwrap();
        assert!(
            (0..3).all(|c| (got[c] - want[c]).abs() < 1e-9),
            "{got:?} {want:?}"
        );
        // From behind, the back's.
        let behind = Shot::new(DVec3::new(0.0, 0.0, -5.0), DVec3::ZERO, 33, 33);
        let r_behind = reference(&t, &[], &behind, 0.01);
        let back = r_behind.colours(&t, &kd, &behind, 0.01, Lighting::Smooth(&shades), None);
        assert_eq!(back[centre], Some([60, 30, 12]));
        // In shadow, both ambient.
        let mut shadowed = vec![false; r.ids.len()];
        shadowed[centre] = true;
        for lighting in [Lighting::Faceted(sun), Lighting::Smooth(&shades)] {
            let c = r.colours(&t, &kd, &s, 0.01, lighting, Some(&shadowed));
            assert_eq!(c[centre], Some([60, 30, 12]));
            assert_ne!(c[centre + 1], Some([60, 30, 12]));
        }
    }

    #[test]
    fn triangle_behind_the_eye_is_invisible() {
        let t = [[
            DVec3::new(-1.0, -1.0, 6.0),
            DVec3::new(1.0, -1.0, 6.0),
            DVec3::new(0.0, 1.0, 6.0),
        ]];
        let r = reference(&t, &[], &shot(16, 16), 0.01);
        assert!(r.ids.iter().all(|&i| i == 0));
    }
}
