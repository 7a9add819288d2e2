//! Z-buffer baselines (Catmull's depth buffer) over the source triangles, with the runtime's
//! fill and its top-left rule: per pixel, keep the nearest surface by interpolated `1/z`, in
//! `f32` or in fixed-point integers. One frame loop serves both; a [`Depth`] type says how a
//! triangle's `1/z` plane is stored and walked along a span.

use peel_runtime::display::{Colour, SpanSink};
use peel_runtime::fill::fill_polygon;

use super::frame::{bytes, Frame};
use super::prepare::{inverse_depth_plane, Prepared};
use peel_runtime::camera::LocalView;

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
