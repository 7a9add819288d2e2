//! The scene with moving objects (`objects`, issue 46): a world of a ground square and four
//! tall boxes, and two objects (the teapot and the cow) that stand on the ground and move
//! with the camera: camera `k` sees each object at its own place and turn ([`poses`]). Defined
//! once here, so that the firmware and the runner pose them with the same `f32` values (the
//! sines and cosines from `libm`, not the host's), and the runner builds the world from the
//! same [`Layout`].
//!
//! The world is sized from the objects' boxes: [`Layout::unit`] is the largest horizontal
//! half-diagonal of an object's box, so an object turned any way stays within `unit` of
//! where it stands. Object 0 walks the lane `x = -2 unit`, object 1 the lane `x = +2 unit`
//! (the plane `x = 0` between them, through the middle box); the boxes stand beside the
//! lanes, so their faces' planes cut the objects at some cameras, and the world's bounds hold
//! every posed object, so the posed scene and the same geometry as one file are framed alike.

use glam::{DVec3, Mat3, Vec3};
use peel_runtime::place::Pose;
use peel_runtime::read::Header;

/// The objects the scene poses.
pub const OBJECTS: usize = 2;
/// Clip-buffer vertices of the firmware's workspace for a posed frame: the renderer asks
/// for the largest polygon's buffer and two vertices for each plane that cuts an object in
/// the frame (the poses here need at most 46).
pub const VERTS: usize = 48;
/// Steps of the frame's order the firmware's object memory holds
/// (`peel_runtime::place::ObjectMemory<OBJECTS, STEPS>`, about 72 bytes a step with its piece,
/// cut and task): the runner's host frames find the span memory with as many, so a frame that
/// needs more fails on the host first.
pub const STEPS: usize = 64;

/// The world's size, from the objects' boxes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layout {
    /// The largest horizontal half-diagonal of an object's box.
    pub unit: f32,
    /// The boxes' height: taller than any object, so the world's bounds hold them.
    pub height: f32,
}

impl Layout {
    /// The layout for objects whose headers are `objects`.
    pub fn new(objects: &[Header; OBJECTS]) -> Layout {
        let (mut unit, mut tallest) = (0.0f32, 0.0f32);
        for h in objects {
            let half = (h.bounds_max - h.bounds_min) * 0.5;
            unit = unit.max(libm::sqrtf(half.x * half.x + half.z * half.z));
            tallest = tallest.max(h.bounds_max.y - h.bounds_min.y);
        }
        Layout {
            unit,
            height: tallest * 1.25,
        }
    }

    /// Half the ground square's side (the ground is at `y = 0`, centred on the origin).
    pub fn ground(&self) -> f32 {
        4.0 * self.unit
    }

    /// The world's boxes, each `(x range, z range)` from `y = 0` to [`Layout::height`]: one
    /// between the lanes, one beyond each lane, one at the far end of the middle.
    pub fn boxes(&self) -> [([f32; 2], [f32; 2]); 4] {
        let u = self.unit;
        [
            ([-0.6 * u, 0.6 * u], [-0.6 * u, 0.6 * u]),
            ([-3.9 * u, -3.1 * u], [-0.4 * u, 0.4 * u]),
            ([-0.6 * u, 0.6 * u], [2.2 * u, 3.4 * u]),
            ([3.1 * u, 3.9 * u], [-2.1 * u, -0.9 * u]),
        ]
    }

    /// Where each object's box centre stands (x, z) for camera `k`, and its turn in degrees:
    /// object 0 walks its lane forwards and turns 45 degrees a camera, object 1 walks the
    /// other lane backwards and turns -30 degrees a camera.
    pub fn places(&self, k: usize) -> [(f32, f32, f32); OBJECTS] {
        let u = self.unit;
        let t = (k % 8) as f32 / 7.0;
        [
            (-2.0 * u, (-2.5 + 5.0 * t) * u, 45.0 * (k % 8) as f32),
            (2.0 * u, (2.5 - 5.0 * t) * u, 90.0 - 30.0 * (k % 8) as f32),
        ]
    }
}

/// The poses of camera `k` for objects whose headers are `objects`: each turned about the
/// vertical by its angle ([`Layout::places`]), its box's centre over its place and its lowest
/// point a hair (`2^-10` of the boxes' height) above the ground, so that the same geometry as
/// one file has the ground's bounds.
pub fn poses(k: usize, objects: &[Header; OBJECTS]) -> [Pose; OBJECTS] {
    let layout = Layout::new(objects);
    let places = layout.places(k);
    let lift = f64::from(layout.height) / 1024.0;
    core::array::from_fn(|i| {
        let (x, z, yaw) = places[i];
        let (s, c) = (
            libm::sinf(yaw * (core::f32::consts::PI / 180.0)),
            libm::cosf(yaw * (core::f32::consts::PI / 180.0)),
        );
        // A right-handed turn about y, as `Mat3::from_rotation_y`.
        let rotation = Mat3::from_cols(
            Vec3::new(c, 0.0, -s),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(s, 0.0, c),
        );
        let h = &objects[i];
        let mid = DVec3::from_array(h.centre) + (h.bounds_min + h.bounds_max).as_dvec3() * 0.5;
        let turned = rotation.as_dmat3() * mid;
        let lowest = h.centre[1] + f64::from(h.bounds_min.y);
        let translation = DVec3::new(
            f64::from(x) - turned.x,
            lift - lowest,
            f64::from(z) - turned.z,
        );
        Pose {
            rotation,
            translation: translation.as_vec3(),
        }
    })
}

/// The header that frames the world `world` and the objects `objects` posed by `poses` for
/// the camera: the world's centre, and the bounds of the world and of each object's posed
/// box. The same values as the compiler's `tools::raster::posed_header`, which frames the
/// host's frames (the runner checks that they agree).
pub fn posed_header(world: &Header, objects: &[Header], poses: &[Pose]) -> Header {
    let c = DVec3::from_array(world.centre);
    let (mut lo, mut hi) = (world.bounds_min.as_dvec3(), world.bounds_max.as_dvec3());
    for (h, pose) in objects.iter().zip(poses) {
        let r = pose.rotation.as_dmat3();
        let t = pose.translation.as_dvec3();
        let oc = DVec3::from_array(h.centre);
        let (a, b) = (h.bounds_min.as_dvec3(), h.bounds_max.as_dvec3());
        for k in 0..8 {
            let p = DVec3::new(
                if k & 1 == 0 { a.x } else { b.x },
                if k & 2 == 0 { a.y } else { b.y },
                if k & 4 == 0 { a.z } else { b.z },
            );
            let q = t + r * (oc + p) - c;
            lo = lo.min(q);
            hi = hi.max(q);
        }
    }
    Header {
        centre: world.centre,
        bounds_min: lo.as_vec3(),
        bounds_max: hi.as_vec3(),
        ..Header::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(centre: [f64; 3], lo: [f32; 3], hi: [f32; 3]) -> Header {
        Header {
            centre,
            bounds_min: Vec3::from_array(lo),
            bounds_max: Vec3::from_array(hi),
            ..Header::default()
        }
    }

    #[test]
    fn objects_stand_on_the_ground_in_their_lanes_apart_from_the_boxes() {
        let objects = [
            header([0.2, 1.5, 0.0], [-3.2, -1.5, -2.0], [3.2, 1.5, 2.0]),
            header([0.8, -0.4, 0.0], [-5.2, -3.2, -1.7], [5.2, 3.2, 1.7]),
        ];
        let layout = Layout::new(&objects);
        let u = layout.unit;
        let world = header(
            [0.0, f64::from(layout.height) / 2.0, 0.0],
            [-layout.ground(), -layout.height / 2.0, -layout.ground()],
            [layout.ground(), layout.height / 2.0, layout.ground()],
        );
        for k in 0..8 {
            let poses = poses(k, &objects);
            for (i, (h, pose)) in objects.iter().zip(&poses).enumerate() {
                let one = posed_header(&world, &[*h], &[*pose]);
                // Within the world's bounds: the framing is the world's.
                assert_eq!(
                    (one.bounds_min, one.bounds_max),
                    (world.bounds_min, world.bounds_max)
                );
                // The posed box's own extent.
                let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
                for c in 0..8 {
                    let pick = |bit, a: f32, b: f32| f64::from(if c & bit == 0 { a } else { b });
                    let p = DVec3::new(
                        pick(1, h.bounds_min.x, h.bounds_max.x),
                        pick(2, h.bounds_min.y, h.bounds_max.y),
                        pick(4, h.bounds_min.z, h.bounds_max.z),
                    ) + DVec3::from_array(h.centre);
                    let q = pose.translation.as_dvec3() + pose.rotation.as_dmat3() * p;
                    lo = lo.min(q);
                    hi = hi.max(q);
                }
                assert!(
                    lo.y > 0.0 && lo.y < f64::from(layout.height) / 500.0,
                    "{k} {i}: {lo}"
                );
                assert!(hi.y < f64::from(layout.height));
                // In its lane, clear of the other lane and of every box.
                let (near, far) = if i == 0 { (-hi.x, -lo.x) } else { (lo.x, hi.x) };
                assert!(
                    near > 0.9 * f64::from(u) && far < 3.05 * f64::from(u),
                    "{k} {i}"
                );
                for (bx, bz) in layout.boxes() {
                    let apart = hi.x <= f64::from(bx[0])
                        || lo.x >= f64::from(bx[1])
                        || hi.z <= f64::from(bz[0])
                        || lo.z >= f64::from(bz[1]);
                    assert!(apart, "camera {k}, object {i} meets the box {bx:?} {bz:?}");
                }
            }
        }
    }
}
