//! The per-triangle front end shared by the baseline renderers: world -> camera (the runtime's
//! `View`), near and window clipping (the runtime's `clip`), projection and snapping (the
//! runtime's `snap`), so every method sees bit-identical screen polygons.

use glam::{DVec3, Vec3};
use peel_runtime::camera::View;
use peel_runtime::clip::{clip_polygon, Frustum, CLIP_PLANES};
use peel_runtime::fill::FixedPoint;
use peel_runtime::render::snap;

/// Most vertices of a clipped triangle: one more per clip plane.
const MAX_CLIPPED: usize = 3 + CLIP_PLANES;

/// One source triangle after clipping: camera-space and fixed-point screen polygons, in
/// fixed arrays (no allocation per triangle).
#[derive(Debug, Clone, Copy)]
pub struct Prepared {
    /// Source triangle id.
    pub id: u32,
    len: usize,
    camera: [Vec3; MAX_CLIPPED],
    screen: [FixedPoint; MAX_CLIPPED],
}

impl Prepared {
    /// The clipped polygon in camera space.
    pub fn camera(&self) -> &[Vec3] {
        &self.camera[..self.len]
    }
    /// The same polygon on screen, `SUB` fractional bits.
    pub fn screen(&self) -> &[FixedPoint] {
        &self.screen[..self.len]
    }
}

/// The box of `triangles` as [`prepare`] sees them (relative to `centre`, in `f32`): computed
/// once per scene, it lets a frame that sees the whole scene skip clipping, as Peel does.
pub fn scene_box(triangles: &[[DVec3; 3]], centre: DVec3) -> (Vec3, Vec3) {
    triangles.iter().flatten().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| {
            let q = (*p - centre).as_vec3();
            (lo.min(q), hi.max(q))
        },
    )
}

/// Clip and project `triangles` (world coordinates) for `view` (built for `centre`) into
/// `out` (cleared first; its memory is reused from frame to frame). `bounds` is their
/// [`scene_box`]: when the frustum contains it, nothing is clipped.
pub fn prepare<const SUB: u32>(
    triangles: &[[DVec3; 3]],
    centre: DVec3,
    bounds: (Vec3, Vec3),
    view: &View,
    out: &mut Vec<Prepared>,
) {
    out.clear();
    let frustum = Frustum::new(view);
    let inside = frustum.contains_box(view, bounds.0, bounds.1);
    let (max_x, max_y) = ((view.width << SUB) as i32, (view.height << SUB) as i32);
    let mut a = [Vec3::ZERO; 16];
    let mut b = [Vec3::ZERO; 16];
    for (id, t) in triangles.iter().enumerate() {
        for (slot, p) in a.iter_mut().zip(t) {
            *slot = view.to_camera((*p - centre).as_vec3());
        }
        let clipped = if inside {
            &a[..3]
        } else {
            let Ok(clipped) = clip_polygon(frustum.planes(), 3, &mut a, &mut b) else {
                continue;
            };
            clipped
        };
        if clipped.len() < 3 || clipped.len() > MAX_CLIPPED {
            continue;
        }
        let mut t = Prepared {
            id: id as u32,
            len: clipped.len(),
            camera: [Vec3::ZERO; MAX_CLIPPED],
            screen: [FixedPoint::default(); MAX_CLIPPED],
        };
        for (k, &c) in clipped.iter().enumerate() {
            t.camera[k] = c;
            t.screen[k] = snap::<SUB>(view.project(c), max_x, max_y);
        }
        out.push(t);
    }
}

/// `1/zc` at a screen point as `A x + B y + C` for the plane of a camera-space polygon, or
/// `None` when the plane passes through the eye (seen edge-on).
pub fn inverse_depth_plane(camera: &[Vec3], view: &View) -> Option<[f64; 3]> {
    let p0 = camera.first()?.as_dvec3();
    let mut n = DVec3::ZERO;
    for w in camera.windows(2).skip(1) {
        n += (w[0].as_dvec3() - p0).cross(w[1].as_dvec3() - p0);
    }
    let d = n.dot(p0);
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    let (fx, fy, cx, cy) = (
        f64::from(view.fx),
        f64::from(view.fy),
        f64::from(view.cx),
        f64::from(view.cy),
    );
    // dir(x, y) = ((x - cx)/fx, -(y - cy)/fy, 1); t = d / (n . dir) = zc, so 1/zc = n . dir / d.
    Some([
        n.x / (fx * d),
        -n.y / (fy * d),
        (n.z - n.x * cx / fx + n.y * cy / fy) / d,
    ])
}
