//! Z-buffer baselines (seeds 001 and 003) over the source triangles, with the runtime's fill and
//! its top-left rule: per pixel, keep the nearest surface by interpolated `1/z`, in `f32` or in
//! fixed-point integers.

use peel_runtime::fill::fill_polygon;
use peel_runtime::target::{Colour, SpanSink};

use super::prepare::{inverse_depth_plane, Prepared};
use peel_runtime::camera::View;

/// Id image plus depth buffer of one frame.
pub struct ZFrame<'a, D> {
    /// `id + 1` per pixel, 0 for background.
    pub ids: &'a mut [u32],
    /// Depth per pixel (larger `1/z` is nearer; 0 is empty).
    pub depth: &'a mut [D],
    /// Image width.
    pub width: usize,
}

struct F32Sink<'f, 'a> {
    frame: &'f mut ZFrame<'a, f32>,
    plane: [f32; 3],
    id: u32,
    written: u64,
}

impl SpanSink for F32Sink<'_, '_> {
    fn span(&mut self, y: u32, x0: u32, x1: u32, _: Colour) {
        let [a, b, c] = self.plane;
        let row = y as usize * self.frame.width;
        let yc = y as f32 + 0.5;
        for x in x0..x1 {
            let z = a * (x as f32 + 0.5) + b * yc + c;
            let k = row + x as usize;
            if z > self.frame.depth[k] {
                self.frame.depth[k] = z;
                self.frame.ids[k] = self.id + 1;
                self.written += 1;
            }
        }
    }
}

/// The f32 z-buffer: returns the pixels written.
pub fn render_f32<const SUB: u32>(
    tris: &[Prepared],
    view: &View,
    frame: &mut ZFrame<'_, f32>,
) -> u64 {
    frame.ids.fill(0);
    frame.depth.fill(0.0);
    let mut written = 0;
    for t in tris {
        let Some(p) = inverse_depth_plane(t.camera(), view) else {
            continue;
        };
        let mut sink = F32Sink {
            frame,
            plane: p.map(|v| v as f32),
            id: t.id,
            written: 0,
        };
        let _ = fill_polygon::<SUB, _>(
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

/// Fractional bits of the integer depth plane's coefficients.
const DEPTH_FRACTION: u32 = 16;

struct IntSink<'f, 'a> {
    frame: &'f mut ZFrame<'a, u32>,
    /// `1/z` scaled to `[0, 2^30]`, as `a x + b y + c` with `DEPTH_FRACTION` fractional bits.
    plane: [i64; 3],
    id: u32,
    written: u64,
}

impl SpanSink for IntSink<'_, '_> {
    fn span(&mut self, y: u32, x0: u32, x1: u32, _: Colour) {
        let [a, b, c] = self.plane;
        let row = y as usize * self.frame.width;
        // Doubled coordinates put pixel centres on integers: value(x) = (a(2x+1) + b(2y+1) + 2c) / 2.
        let mut v = a * (2 * i64::from(x0) + 1) + b * (2 * i64::from(y) + 1) + 2 * c;
        for x in x0..x1 {
            let z = (v >> (DEPTH_FRACTION + 1)).clamp(0, i64::from(u32::MAX)) as u32;
            let k = row + x as usize;
            if z > self.frame.depth[k] {
                self.frame.depth[k] = z;
                self.frame.ids[k] = self.id + 1;
                self.written += 1;
            }
            v += 2 * a;
        }
    }
}

/// The integer z-buffer (`1/z` in 30-bit fixed point, stepped with integer adds along spans).
pub fn render_int<const SUB: u32>(
    tris: &[Prepared],
    view: &View,
    frame: &mut ZFrame<'_, u32>,
) -> u64 {
    frame.ids.fill(0);
    frame.depth.fill(0);
    let scale = f64::from(1u32 << 30) * f64::from(view.near) * f64::from(1u32 << DEPTH_FRACTION);
    let mut written = 0;
    for t in tris {
        let Some(p) = inverse_depth_plane(t.camera(), view) else {
            continue;
        };
        let plane = p.map(|v| (v * scale).round() as i64);
        let mut sink = IntSink {
            frame,
            plane,
            id: t.id,
            written: 0,
        };
        let _ = fill_polygon::<SUB, _>(
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
