//! Texturing in a frame: a textured polygon's [`TextureMap`], set up in `f32` from its plane in
//! camera space, so that a polygon the window or a cut clipped maps as the whole does, and
//! pieces of one source triangle map alike.
//!
//! On the polygon's plane `n · p = d` (camera space, through its first three corners), the
//! texture coordinate `s` is affine, `s = g · p + h` (`g` in the plane, from the corners'
//! coordinates). The pixel centre `(X, Y)` sees the point `z r` of the ray
//! `r = ((X - cx) / fx, -(Y - cy) / fy, 1)`, and on the plane `1/z = n · r / d` and
//! `s/z = (d g + h n) · r / d`: both affine in `(X, Y)`, as `r` is.

use glam::Vec3;

use crate::camera::LocalView;
use crate::display::Filter;
use crate::fill::texture::{Lighting, TextureMap};
use crate::fill::FixedPoint;
use crate::read::Texture;

/// `w = 1/z` is scaled to at most this on the polygon.
const W_SCALE: f32 = (1u32 << 30) as f32;

/// A textured polygon's corners as the map needs them.
pub(super) struct Corners {
    /// The first three, in camera space.
    pub(super) at: [Vec3; 3],
    /// Their file coordinates.
    pub(super) uvs: [[i32; 2]; 3],
    /// The largest magnitude of `s` and of `t` over all the polygon's corners.
    pub(super) reach: [u32; 2],
}

/// The map of a polygon with `corners`,
/// drawn as the screen polygon `points` (at `SUB` fractional bits, `grid` points a pixel:
/// the anti-aliased fill's samples are 5 x 5).
/// `None` for a polygon seen edge-on or degenerate (it draws nothing, or a sliver; the
/// renderer then draws it in its colour).
pub(super) fn texture_map<'a, const SUB: u32>(
    view: &LocalView,
    texture: Texture<'a>,
    corners: Corners,
    points: &[FixedPoint<SUB>],
    grid: (u32, u32),
    lighting: Lighting<SUB>,
    filter: Filter,
) -> Option<TextureMap<'a, SUB>> {
    let Corners { at, uvs, reach } = corners;
    let [p0, p1, p2] = at;
    let (e1, e2) = (p1 - p0, p2 - p0);
    let n = e1.cross(e2);
    let area = n.length_squared();
    let d = n.dot(p0);
    if !(area > 0.0 && area.is_finite() && d != 0.0 && d.is_finite()) {
        return None;
    }
    // The gradient of each coordinate along the plane, and its value at the camera's origin.
    let (u, v) = (e2.cross(n) / area, n.cross(e1) / area);
    let axis = |k: usize| {
        let (c0, c1, c2) = (uvs[0][k] as f32, uvs[1][k] as f32, uvs[2][k] as f32);
        let g = u * (c1 - c0) + v * (c2 - c0);
        let h = c0 - g.dot(p0);
        // `s/z = a · r` with `a = (d g + h n) / d`.
        g + n * (h / d)
    };
    let inverse_z = n / d;
    // A plane `c · r` over the pixel centres: per column, per row, at pixel centre (X, Y).
    let (fx, fy, cx, cy) = (view.fx, view.fy, view.cx, view.cy);
    let plane = |c: Vec3, x: f32, y: f32| {
        let (dx, dy) = (c.x / fx, -c.y / fy);
        [dx, dy, c.z + dx * (x - cx) + dy * (y - cy)]
    };
    // The polygon's nearest point: the largest `1/z` over its corners (affine on it).
    let unit = (1u32 << SUB) as f32;
    let (sx, sy) = (1.0 / (unit * grid.0 as f32), 1.0 / (unit * grid.1 as f32));
    let nearest = points
        .iter()
        .map(|p| {
            let [_, _, w] = plane(inverse_z, p.x as f32 * sx, p.y as f32 * sy);
            w
        })
        .fold(0.0f32, f32::max);
    if !(nearest > 0.0 && nearest.is_finite()) {
        return None;
    }
    let first = points.first()?;
    let pixel = |v: i32, n: u32| (v >> SUB).max(0) as u32 / n;
    let anchor = (pixel(first.x, grid.0), pixel(first.y, grid.1));
    let (x, y) = (anchor.0 as f32 + 0.5, anchor.1 as f32 + 0.5);
    // `s` below `2^shift`: `s w / 2^shift` stays below `w`'s `2^30`.
    let shift = reach.map(|r| (32 - r.leading_zeros()) as u8);
    let k = W_SCALE / nearest;
    // (`2^-shift` from its exponent bits: exact, no integer conversion.)
    let power = |shift: u8| f32::from_bits((127 - u32::from(shift).min(126)) << 23);
    let scaled = |c: Vec3, shift: u8| plane(c * (k * power(shift)), x, y);
    TextureMap::new(
        texture,
        [
            scaled(inverse_z, 0),
            scaled(axis(0), shift[0]),
            scaled(axis(1), shift[1]),
        ],
        anchor,
        shift,
        lighting,
        filter,
    )
}
