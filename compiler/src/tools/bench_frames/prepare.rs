//! The per-triangle front end shared by the baseline renderers: world -> camera (the runtime's
//! `LocalView`), near and window clipping (the runtime's `clip`), projection and snapping (the
//! runtime's `snap`), so every method sees bit-identical screen polygons. The triangles share
//! a vertex list, so a frame that needs no clipping projects each vertex once, as Peel does
//! with its vertex memory.

use glam::{DVec3, Vec3};
use peel_runtime::camera::LocalView;
use peel_runtime::clip::{clip_polygon, Frustum, CLIP_PLANES};
use peel_runtime::fill::FixedPoint;
use peel_runtime::render::snap;

use crate::hash::FastMap;

/// Most vertices of a clipped triangle: one more per clip plane.
const MAX_CLIPPED: usize = 3 + CLIP_PLANES;

/// One source triangle after clipping: camera-space and fixed-point screen polygons (`SUB`
/// fractional bits), in fixed arrays (no allocation per triangle).
#[derive(Debug, Clone, Copy)]
pub struct Prepared<const SUB: u32> {
    /// Source triangle id.
    pub id: u32,
    len: usize,
    camera: [Vec3; MAX_CLIPPED],
    screen: [FixedPoint<SUB>; MAX_CLIPPED],
}

impl<const SUB: u32> Prepared<SUB> {
    /// The clipped polygon in camera space.
    pub fn camera(&self) -> &[Vec3] {
        &self.camera[..self.len]
    }
    /// The same polygon on screen.
    pub fn screen(&self) -> &[FixedPoint<SUB>] {
        &self.screen[..self.len]
    }
}

/// The memory a method keeps when it holds every clipped polygon of a frame at once: an id
/// and its screen points each. The front end's own records are the benchmark's, not the
/// method's: fixed-size, with room for clipping's extra vertices and the camera-space points
/// the depth planes are made from.
pub fn held_bytes<const SUB: u32>(tris: &[Prepared<SUB>]) -> u64 {
    tris.iter()
        .map(|t| super::frame::bytes::<u32>(1) + super::frame::bytes::<FixedPoint<SUB>>(t.len))
        .sum()
}

/// Source triangles as the baselines draw them, built once per scene: their distinct corners
/// relative to the scene centre in `f32` (as the runtime's scene stores vertices), each
/// triangle's three corner indices, and the box of the corners, which lets a frame that sees
/// the whole scene skip clipping, as Peel does.
pub struct Triangles {
    vertices: Vec<Vec3>,
    corners: Vec<[u32; 3]>,
    bounds: (Vec3, Vec3),
}

impl Triangles {
    /// `triangles` (world coordinates) relative to `centre`.
    pub fn new(triangles: &[[DVec3; 3]], centre: DVec3) -> Self {
        let mut index: FastMap<[u32; 3], u32> = FastMap::default();
        let mut vertices = Vec::new();
        let corners = triangles
            .iter()
            .map(|t| {
                t.map(|p| {
                    let q = (p - centre).as_vec3();
                    *index
                        .entry(q.to_array().map(f32::to_bits))
                        .or_insert_with(|| {
                            vertices.push(q);
                            (vertices.len() - 1) as u32
                        })
                })
            })
            .collect();
        let bounds = vertices.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), &q| (lo.min(q), hi.max(q)),
        );
        Triangles {
            vertices,
            corners,
            bounds,
        }
    }
}

/// Clip and project `triangles` for `view` (built for their centre) into `out` (cleared
/// first; its memory, and that of `projected`, is reused from frame to frame). When the
/// frustum contains their box nothing is clipped, and each vertex is projected once, into
/// `projected`. Returns the bytes of projected vertices the frame used (0 when it clipped:
/// each triangle is then projected alone), which every baseline's memory includes, as Peel's
/// includes its vertex memory.
pub fn prepare<const SUB: u32>(
    triangles: &Triangles,
    view: &LocalView,
    projected: &mut Vec<(Vec3, FixedPoint<SUB>)>,
    out: &mut Vec<Prepared<SUB>>,
) -> u64 {
    out.clear();
    let frustum = Frustum::new(view);
    let (lo, hi) = triangles.bounds;
    let inside = frustum.contains_box(view, lo, hi);
    let (max_x, max_y) = ((view.width << SUB) as i32, (view.height << SUB) as i32);
    let screen = |c: Vec3| snap::<SUB>(view.project(c), max_x, max_y);
    if inside {
        projected.clear();
        projected.extend(triangles.vertices.iter().map(|&v| {
            let c = view.to_camera(v);
            (c, screen(c))
        }));
        out.extend(triangles.corners.iter().enumerate().map(|(id, t)| {
            let mut p = Prepared {
                id: id as u32,
                len: 3,
                camera: [Vec3::ZERO; MAX_CLIPPED],
                screen: [FixedPoint::default(); MAX_CLIPPED],
            };
            for (k, &i) in t.iter().enumerate() {
                (p.camera[k], p.screen[k]) = projected[i as usize];
            }
            p
        }));
        return super::frame::bytes::<(Vec3, FixedPoint<SUB>)>(projected.len());
    }
    let mut a = [Vec3::ZERO; 16];
    let mut b = [Vec3::ZERO; 16];
    for (id, t) in triangles.corners.iter().enumerate() {
        for (slot, &i) in a.iter_mut().zip(t) {
            *slot = view.to_camera(triangles.vertices[i as usize]);
        }
        let Ok(clipped) = clip_polygon(frustum.planes(), 3, &mut a, &mut b) else {
            continue;
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
            t.screen[k] = screen(c);
        }
        out.push(t);
    }
    0
}

/// `1/zc` at a screen point as `A x + B y + C` for the plane of a camera-space polygon, or
/// `None` when the plane passes through the eye (seen edge-on).
pub fn inverse_depth_plane(camera: &[Vec3], view: &LocalView) -> Option<[f64; 3]> {
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
