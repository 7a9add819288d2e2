//! Z-buffer baselines (Catmull's depth buffer) over the source triangles, with the runtime's
//! fill and its top-left rule: per pixel, keep the nearest surface by interpolated `1/z`, in
//! `f32` or in fixed-point integers. One frame loop serves both; a [`Depth`] type says how a
//! triangle's `1/z` plane is stored and walked along a span.
//!
//! With transparent surfaces, the usual practice ([`draw_sorted`], [`sorted_picture`]): the
//! opaque triangles through the depth buffer first, then the transparent ones sorted by their
//! centroids' camera depth, far to near, each blended over the picture where it is nearer
//! than the opaque depth (without writing depth). Exact for surfaces apart in depth; wrong
//! where they cross or their centroids' order is not the pixels' order.

use peel_runtime::display::{Colour, SpanSink};
use peel_runtime::fill::fill_polygon;

use glam::DVec3;
use peel_runtime::camera::{Camera, LocalView, Pose};
use peel_runtime::fill::SUBPIXEL_BITS;

use super::frame::{bytes, Frame};
use super::prepare::{inverse_depth_plane, prepare, Prepared, Triangles};
use crate::shade::channel;
use crate::tools::reference::OPAQUE;
use crate::tools::shot::Shot;

/// Id image plus depth buffer of one frame.
pub struct ZFrame<'a, D> {
    /// `id + 1` per pixel, 0 for background.
    pub ids: &'a mut [u32],
    /// Depth per pixel (larger `1/z` is nearer; 0 is empty).
    pub depth: &'a mut [D],
    /// Image width.
    pub width: usize,
}

impl<D: Depth> ZFrame<'_, D> {
    /// The depth test at pixel `k`: keeps `z` and `id + 1` there when `z` is nearer; returns
    /// the pixels written (0 or 1).
    #[inline]
    fn keep(&mut self, k: usize, z: D, id: u32) -> u64 {
        if z > self.depth[k] {
            self.depth[k] = z;
            self.ids[k] = id + 1;
            1
        } else {
            0
        }
    }
}

/// A depth buffer's number format.
pub trait Depth: Copy + Default + PartialOrd {
    /// A triangle's `1/z` as a function of the pixel, in this format.
    type Plane: Copy;

    /// The format's plane for `1/z = a x + b y + c` (screen pixels).
    fn plane(abc: [f64; 3], view: &LocalView) -> Self::Plane;

    /// The plane's values at the pixel centres `x0, x0 + 1, ...` of row `y`.
    fn along(plane: &Self::Plane, x0: u32, y: u32) -> impl Iterator<Item = Self>;
}

impl Depth for f32 {
    type Plane = [f32; 3];

    fn plane(abc: [f64; 3], _: &LocalView) -> [f32; 3] {
        abc.map(|v| v as f32)
    }

    fn along(plane: &[f32; 3], x0: u32, y: u32) -> impl Iterator<Item = f32> {
        let [a, b, c] = *plane;
        let yc = y as f32 + 0.5;
        (x0..).map(move |x| a * (x as f32 + 0.5) + b * yc + c)
    }
}

/// Fractional bits of the integer depth plane's coefficients.
const DEPTH_FRACTION: u32 = 16;

/// The integer format: `1/z` scaled to `[0, 2^30]`, the plane `a x + b y + c` with
/// [`DEPTH_FRACTION`] fractional bits, stepped with integer adds along spans.
impl Depth for u32 {
    type Plane = [i64; 3];

    fn plane(abc: [f64; 3], view: &LocalView) -> [i64; 3] {
        let scale =
            f64::from(1u32 << 30) * f64::from(view.near) * f64::from(1u32 << DEPTH_FRACTION);
        abc.map(|v| (v * scale).round() as i64)
    }

    fn along(plane: &[i64; 3], x0: u32, y: u32) -> impl Iterator<Item = u32> {
        let [a, b, c] = *plane;
        // Doubled coordinates put pixel centres on integers: value(x) = (a(2x+1) + b(2y+1) + 2c) / 2.
        let mut v = a * (2 * i64::from(x0) + 1) + b * (2 * i64::from(y) + 1) + 2 * c;
        std::iter::from_fn(move || {
            let z = (v >> (DEPTH_FRACTION + 1)).clamp(0, i64::from(u32::MAX)) as u32;
            v += 2 * a;
            Some(z)
        })
    }
}

/// One triangle's spans, depth-tested into the frame.
struct Sink<'f, 'a, D: Depth> {
    frame: &'f mut ZFrame<'a, D>,
    plane: D::Plane,
    id: u32,
    written: u64,
}

impl<D: Depth> SpanSink for Sink<'_, '_, D> {
    fn span(&mut self, y: u32, x0: u32, x1: u32, _: Colour) {
        let row = y as usize * self.frame.width;
        for (x, z) in (x0..x1).zip(D::along(&self.plane, x0, y)) {
            self.written += self.frame.keep(row + x as usize, z, self.id);
        }
    }
}

/// [`draw`] into `ids` (`view.width` x `view.height`), with `depth` (reused from frame to
/// frame) sized to match. Its memory is the depth buffer: the triangles are drawn one at a
/// time, so a z-buffer needs no list of them (the benchmark's front end keeps one, which is
/// not counted here).
pub fn draw_ids<const SUB: u32, D: Depth>(
    tris: &[Prepared<SUB>],
    view: &LocalView,
    ids: &mut [u32],
    depth: &mut Vec<D>,
) -> Frame {
    depth.resize(ids.len(), D::default());
    let memory_bytes = bytes::<D>(depth.len());
    let mut frame = ZFrame {
        ids,
        depth,
        width: view.width as usize,
    };
    Frame {
        written: draw::<SUB, D>(tris, view, &mut frame),
        memory_bytes,
    }
}

/// The z-buffer in format `D` (`f32` or `u32`): returns the pixels written.
pub fn draw<const SUB: u32, D: Depth>(
    tris: &[Prepared<SUB>],
    view: &LocalView,
    frame: &mut ZFrame<'_, D>,
) -> u64 {
    frame.ids.fill(0);
    frame.depth.fill(D::default());
    let mut written = 0;
    for t in tris {
        let Some(abc) = inverse_depth_plane(t.camera(), view) else {
            continue;
        };
        let mut sink = Sink {
            frame,
            plane: D::plane(abc, view),
            id: t.id,
            written: 0,
        };
        let _ = fill_polygon(
            t.screen(),
            view.width,
            view.height,
            Colour::default(),
            &mut sink,
        );
        written += sink.written;
    }
    written
}

/// One source triangle as [`draw_sorted`] paints it in a frame: the colour of its side seen
/// (8-bit units, unrounded), its opacity ([`OPAQUE`] for an opaque one; alpha
/// `opacity / 255`) and the camera depth of its centroid, which orders the transparent ones.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// The colour of the side seen.
    pub colour: [f64; 3],
    /// Its opacity.
    pub opacity: u8,
    /// Its centroid's camera depth.
    pub depth: f64,
}

/// One triangle's spans painted into a colour picture with an `f32` depth buffer: an opaque
/// one depth-tested and written, a transparent one depth-tested against the opaque depth and
/// blended over the picture ("over", in 8 bits as a framebuffer holds it), depth unwritten.
struct Paint<'f> {
    pixels: &'f mut [[u8; 3]],
    depth: &'f mut [f32],
    width: usize,
    plane: [f32; 3],
    surface: Surface,
    written: u64,
}

impl SpanSink for Paint<'_> {
    fn span(&mut self, y: u32, x0: u32, x1: u32, _: Colour) {
        let row = y as usize * self.width;
        let Surface {
            colour, opacity, ..
        } = self.surface;
        let a = f64::from(opacity) / 255.0;
        for (x, z) in (x0..x1).zip(f32::along(&self.plane, x0, y)) {
            let k = row + x as usize;
            if z <= self.depth[k] {
                continue;
            }
            self.written += 1;
            if opacity == OPAQUE {
                self.depth[k] = z;
                self.pixels[k] = colour.map(channel);
            } else {
                let under = self.pixels[k];
                self.pixels[k] = std::array::from_fn(|c| {
                    channel(a * colour[c] + (1.0 - a) * f64::from(under[c]))
                });
            }
        }
    }
}

/// The sorted z-buffer with transparency into `pixels` (`view.width` x `view.height`, cleared
/// to `background` first), with `depth` (reused from frame to frame) sized to match:
/// `surfaces` (one a source triangle, by id) say how each of `tris` is painted. The opaque
/// triangles through the depth buffer, then the transparent ones by their centroids' depth,
/// far to near (ties by id), each blended over the picture where it is nearer than the opaque
/// depth. Its memory: the depth buffer and the sorted list of transparent triangles.
pub fn draw_sorted<const SUB: u32>(
    tris: &[Prepared<SUB>],
    view: &LocalView,
    surfaces: &[Surface],
    background: [u8; 3],
    pixels: &mut [[u8; 3]],
    depth: &mut Vec<f32>,
) -> Frame {
    pixels.fill(background);
    depth.clear();
    depth.resize(pixels.len(), 0.0);
    let surface = |t: &Prepared<SUB>| surfaces[t.id as usize];
    let (opaque, mut transparent): (Vec<&Prepared<SUB>>, Vec<&Prepared<SUB>>) =
        tris.iter().partition(|t| surface(t).opacity == OPAQUE);
    transparent
        .sort_by(|a, b| (surface(b).depth.total_cmp(&surface(a).depth)).then(a.id.cmp(&b.id)));
    let mut written = 0;
    for t in opaque.into_iter().chain(transparent.iter().copied()) {
        let Some(abc) = inverse_depth_plane(t.camera(), view) else {
            continue;
        };
        let mut sink = Paint {
            pixels: &mut *pixels,
            depth: &mut depth[..],
            width: view.width as usize,
            plane: f32::plane(abc, view),
            surface: surface(t),
            written: 0,
        };
        let _ = fill_polygon(
            t.screen(),
            view.width,
            view.height,
            Colour::default(),
            &mut sink,
        );
        written += sink.written;
    }
    Frame {
        written,
        memory_bytes: bytes::<f32>(depth.len()) + bytes::<u32>(transparent.len()),
    }
}

/// The [`Surface`]s of `triangles` seen from `eye` looking along the unit `forward`: the colour
/// `colour(id, front)` of the side seen (`front` as the reference's
/// [`Reference::front`](crate::tools::reference::Reference::front)), `opacity[id]`, the
/// centroid's camera depth.
pub fn surfaces(
    triangles: &[[DVec3; 3]],
    eye: DVec3,
    forward: DVec3,
    colour: impl Fn(usize, bool) -> [f64; 3],
    opacity: &[u8],
) -> Vec<Surface> {
    assert_eq!(opacity.len(), triangles.len(), "one opacity a triangle");
    (triangles.iter().enumerate())
        .map(|(id, &[a, b, c])| Surface {
            colour: colour(id, (eye - a).dot((b - a).cross(c - a)) > 0.0),
            opacity: opacity[id],
            depth: ((a + b + c) / 3.0 - eye).dot(forward),
        })
        .collect()
}

/// The picture (row-major) the sorted z-buffer draws of `triangles` (world coordinates; ids
/// are indices) for `shot` with near distance `near`: the opaque ones through an `f32` depth
/// buffer, then the transparent ones sorted by their centroids' camera depth, far to near,
/// each blended over the picture (in 8 bits) where it is nearer than the opaque depth, without
/// writing depth. Through the runtime's clip, projection, snapping and fill at its precision,
/// as `peel bench`'s baselines draw: triangle `id` seen from its front (`front`) has colour
/// `colour(id, front)` and opacity `opacity[id]`; `background` where nothing opaque covers a
/// pixel. The error says why the shot makes no camera.
pub fn sorted_picture(
    triangles: &[[DVec3; 3]],
    colour: impl Fn(usize, bool) -> [f64; 3],
    opacity: &[u8],
    background: [u8; 3],
    shot: &Shot,
    near: f64,
) -> Result<Vec<[u8; 3]>, String> {
    let pose = Pose {
        eye: shot.eye,
        target: shot.target,
        up: shot.up,
    };
    let camera = Camera::look_at(pose, shot.fov_y_deg, shot.width, shot.height, near)
        .map_err(|e| e.to_string())?;
    let (lo, hi) = (triangles.iter().flatten()).fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let centre = if lo.is_finite() {
        (lo + hi) / 2.0
    } else {
        DVec3::ZERO
    };
    let view = camera.view(centre.to_array());
    let (mut projected, mut tris) = (Vec::new(), Vec::new());
    prepare::<SUBPIXEL_BITS>(
        &Triangles::new(triangles, centre),
        &view,
        &mut projected,
        &mut tris,
    );
    let forward = (shot.target - shot.eye).normalize();
    let surfaces = surfaces(triangles, shot.eye, forward, colour, opacity);
    let mut pixels = vec![[0; 3]; (shot.width * shot.height) as usize];
    draw_sorted(
        &tris,
        &view,
        &surfaces,
        background,
        &mut pixels,
        &mut Vec::new(),
    );
    Ok(pixels)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::reference::{composite, Composited};

    const NEAR: f64 = 0.01;
    /// The tolerance, per channel in 8-bit units: a few roundings in the framebuffer.
    const TOLERANCE: f64 = 2.0;

    fn shot() -> Shot {
        Shot::new(DVec3::new(0.3, 0.2, 5.0), DVec3::ZERO, 96, 72)
    }

    /// The square `[x0, x1] x [y0, y1]` at depth `z(x, y)`, counter-clockwise seen from +z.
    fn pane(x0: f64, y0: f64, x1: f64, y1: f64, z: impl Fn(f64, f64) -> f64) -> [[DVec3; 3]; 2] {
        let p = |x: f64, y: f64| DVec3::new(x, y, z(x, y));
        [
            [p(x0, y0), p(x1, y0), p(x1, y1)],
            [p(x0, y0), p(x1, y1), p(x0, y1)],
        ]
    }

    /// Pane `k`'s colour (its triangles `2k` and `2k + 1`), a different one each side.
    fn colour(id: usize, front: bool) -> [f64; 3] {
        let c = [
            [210.0, 40.0, 30.0],
            [30.0, 70.0, 220.0],
            [40.0, 200.0, 60.0],
            [120.0, 120.0, 120.0],
        ][id / 2 % 4];
        if front {
            c
        } else {
            c.map(|v| v * 0.5)
        }
    }

    const BACK: [u8; 3] = [15, 25, 35];

    /// The sorted z-buffer's picture and the composited reference of `panes`.
    fn both(panes: &[[[DVec3; 3]; 2]], opacity: &[u8]) -> (Vec<[u8; 3]>, Composited) {
        let t = panes.as_flattened();
        let s = shot();
        let got = sorted_picture(t, colour, opacity, BACK, &s, NEAR).unwrap();
        let want = composite(t, &[], &s, NEAR, colour, opacity, BACK);
        (got, want)
    }

    /// Two transparent panes crossing along `x = 0`: each is drawn whole before or after the
    /// other, so on one side of the crossing their order is wrong.
    #[test]
    fn crossing_panes_are_wrong_on_robust_pixels() {
        let flat = pane(-1.0, -1.0, 1.0, 1.0, |_, _| 0.0);
        let tilted = pane(-1.0, -1.0, 1.0, 1.0, |x, _| 0.7 * x);
        let (got, want) = both(&[flat, tilted], &[140; 4]);
        let robust_both = (want.robust.iter().zip(&want.transparent))
            .filter(|&(&r, &n)| r && n == 2)
            .count();
        let wrong = want.wrong_pixels(&got, TOLERANCE);
        assert!(robust_both > 500, "{robust_both} robust pixels see both");
        assert!(wrong > 0, "no pixel is wrong");
        assert!(wrong < robust_both, "{wrong} wrong of {robust_both}");
    }

    /// Panes apart in depth, one of them opaque between two transparent ones, over an opaque
    /// backdrop: the sorted z-buffer is right on every robust pixel.
    #[test]
    fn panes_apart_in_depth_are_right() {
        let backdrop = pane(-3.0, -3.0, 3.0, 3.0, |_, _| -1.0);
        let far = pane(-1.2, -1.0, 0.5, 0.6, |_, _| 0.0);
        let opaque = pane(-0.3, -0.4, 0.4, 0.3, |_, _| 0.3);
        let near = pane(-0.5, -0.8, 1.0, 1.0, |x, y| 0.6 + 0.05 * x + 0.02 * y);
        let opacity = [OPAQUE, OPAQUE, 110, 110, OPAQUE, OPAQUE, 160, 160];
        let (got, want) = both(&[backdrop, far, opaque, near], &opacity);
        let robust = want.robust.iter().filter(|&&r| r).count();
        assert!(robust > 96 * 72 / 2, "{robust} robust pixels");
        assert!(want.transparent.contains(&2));
        assert_eq!(want.wrong_pixels(&got, TOLERANCE), 0);
        // The transparent panes listed first are drawn in the same order.
        let (got, want) = both(&[near, backdrop, opaque, far], &opacity);
        assert_eq!(want.wrong_pixels(&got, TOLERANCE), 0);
    }

    /// Without transparent triangles it is the plain z-buffer: each pixel the colour of the
    /// side seen of the nearest.
    #[test]
    fn opaque_panes_are_the_plain_z_buffer() {
        let flat = pane(-1.0, -1.0, 1.0, 1.0, |_, _| 0.0);
        let tilted = pane(-1.0, -1.0, 1.0, 1.0, |x, _| 0.7 * x);
        let (got, want) = both(&[flat, tilted], &[OPAQUE; 4]);
        assert!(want.robust.iter().filter(|&&r| r).count() > 96 * 72 / 2);
        assert_eq!(want.wrong_pixels(&got, 0.5), 0);
    }
}
