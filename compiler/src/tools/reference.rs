//! Reference: a brute-force f64 ray caster that follows the camera conventions of the README
//! ("Camera and pixels") to the letter, independent of the runtime's projection, clipping and
//! fill. The end-to-end tests and `peel bench` measure pixel errors against it.

use glam::{DVec2, DVec3};

/// A camera in the README's terms, in f64.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefCamera {
    /// Eye position (world).
    pub eye: DVec3,
    /// Point looked at (world).
    pub target: DVec3,
    /// Up hint.
    pub up: DVec3,
    /// Vertical field of view in degrees.
    pub fov_y_deg: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Near distance.
    pub near: f64,
}

/// The camera basis of the README.
#[derive(Debug, Clone, Copy)]
pub struct Basis {
    /// Forward.
    pub f: DVec3,
    /// Right.
    pub r: DVec3,
    /// True up.
    pub u: DVec3,
    /// Focal length in pixels.
    pub fpx: f64,
}

impl RefCamera {
    /// `f`, `r`, `u`, `fpx` as the README defines them.
    pub fn basis(&self) -> Basis {
        let f = (self.target - self.eye).normalize();
        let r = f.cross(self.up).normalize();
        let u = r.cross(f);
        let fpx = (f64::from(self.height) / 2.0) / (self.fov_y_deg.to_radians() / 2.0).tan();
        Basis { f, r, u, fpx }
    }

    /// Camera-space coordinates of a world point.
    pub fn to_camera(&self, b: &Basis, p: DVec3) -> DVec3 {
        let d = p - self.eye;
        DVec3::new(d.dot(b.r), d.dot(b.u), d.dot(b.f))
    }

    /// Screen position of a camera-space point with `zc > 0`.
    pub fn project(&self, b: &Basis, c: DVec3) -> DVec2 {
        DVec2::new(
            f64::from(self.width) / 2.0 + b.fpx * c.x / c.z,
            f64::from(self.height) / 2.0 - b.fpx * c.y / c.z,
        )
    }
}

/// What the reference sees: per pixel (row-major), `id + 1` of the nearest triangle hit by the
/// ray through the pixel centre at camera depth `>= near` (0: nothing), and whether the sample
/// point is farther than 1/16 pixel from every projected edge.
#[derive(Debug, Clone)]
pub struct Reference {
    /// `id + 1` per pixel, 0 for background.
    pub ids: Vec<u32>,
    /// True where the pixel's sample point is farther than 1/16 pixel from all edges.
    pub robust: Vec<bool>,
}

/// Distance from an edge below which a pixel is not "robust".
pub const EDGE_MARGIN: f64 = 1.0 / 16.0;

/// Cast one ray per pixel against `triangles` (the source triangles: ids are indices) and mark
/// the pixels near the projected edges of `triangles` and of `extra_edges` (e.g. the edges of
/// the compiled polygons, which include the cuts).
pub fn reference(
    triangles: &[[DVec3; 3]],
    extra_polygons: &[Vec<DVec3>],
    cam: &RefCamera,
) -> Reference {
    let b = cam.basis();
    let (w, h) = (cam.width as usize, cam.height as usize);
    let mut depth = vec![f64::INFINITY; w * h];
    let mut ids = vec![0u32; w * h];
    let mut robust = vec![true; w * h];
    for (id, t) in triangles.iter().enumerate() {
        let c = t.map(|p| cam.to_camera(&b, p));
        let Some((x0, x1, y0, y1)) = screen_bbox(cam, &b, &c) else {
            continue;
        };
        for j in y0..y1 {
            for i in x0..x1 {
                let dir = b.f + ((i as f64 + 0.5 - f64::from(cam.width) / 2.0) / b.fpx) * b.r
                    - ((j as f64 + 0.5 - f64::from(cam.height) / 2.0) / b.fpx) * b.u;
                if let Some(tz) = ray_triangle(cam.eye, dir, t) {
                    // dir has unit component along f, so the ray parameter is the camera depth.
                    let k = j * w + i;
                    if tz >= cam.near && tz < depth[k] {
                        depth[k] = tz;
                        ids[k] = id as u32 + 1;
                    }
                }
            }
        }
        mark_polygon_edges(cam, &b, &c, &mut robust);
    }
    for p in extra_polygons {
        let c: Vec<DVec3> = p.iter().map(|&q| cam.to_camera(&b, q)).collect();
        mark_polygon_edges(cam, &b, &c, &mut robust);
    }
    Reference { ids, robust }
}

/// Pixel range (`x0..x1`, `y0..y1`) that may see the camera-space polygon `c`.
fn screen_bbox(cam: &RefCamera, b: &Basis, c: &[DVec3]) -> Option<(usize, usize, usize, usize)> {
    if c.iter().all(|p| p.z < cam.near) {
        return None;
    }
    let (w, h) = (cam.width as usize, cam.height as usize);
    if c.iter().any(|p| p.z < cam.near) {
        return Some((0, w, 0, h)); // crosses the near plane: test every pixel
    }
    let s: Vec<DVec2> = c.iter().map(|&p| cam.project(b, p)).collect();
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
    Some(e2.dot(q) * inv)
}

/// Mark pixels near the projected edges of the camera-space polygon `c`, after clipping it to
/// the near plane (the clip adds the near-plane edge, which the renderer also draws).
fn mark_polygon_edges(cam: &RefCamera, b: &Basis, c: &[DVec3], robust: &mut [bool]) {
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
    let s: Vec<DVec2> = clipped.iter().map(|&p| cam.project(b, p)).collect();
    for k in 0..s.len() {
        mark_segment(cam, s[k], s[(k + 1) % s.len()], robust);
    }
}

/// Mark every pixel whose centre is within [`EDGE_MARGIN`] of the segment `a`-`b`.
fn mark_segment(cam: &RefCamera, a: DVec2, b: DVec2, robust: &mut [bool]) {
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

    fn cam(w: u32, h: u32) -> RefCamera {
        RefCamera {
            eye: DVec3::new(0.0, 0.0, 5.0),
            target: DVec3::ZERO,
            up: DVec3::Y,
            fov_y_deg: 60.0,
            width: w,
            height: h,
            near: 0.01,
        }
    }

    #[test]
    fn centre_pixel_sees_the_facing_triangle_and_corners_see_nothing() {
        let t = [[
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ]];
        let r = reference(&t, &[], &cam(33, 33));
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
        let r = reference(&[far, near], &[], &cam(64, 64));
        assert_eq!(r.ids[32 * 64 + 32], 2);
        // A pixel column crossing the near triangle's left edge has a non-robust pixel.
        assert!(r.robust.iter().any(|&x| !x));
        assert!(r.robust.iter().filter(|&&x| x).count() > 64 * 64 / 2);
    }

    #[test]
    fn triangle_behind_the_eye_is_invisible() {
        let t = [[
            DVec3::new(-1.0, -1.0, 6.0),
            DVec3::new(1.0, -1.0, 6.0),
            DVec3::new(0.0, 1.0, 6.0),
        ]];
        let r = reference(&t, &[], &cam(16, 16));
        assert!(r.ids.iter().all(|&i| i == 0));
    }
}
