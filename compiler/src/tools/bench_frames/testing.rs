//! Hand-made scenes whose answer is known, for the baselines' unit tests: two overlapping
//! squares, a square behind a larger nearer one, two squares crossing in depth. A method
//! draws each through the shared front end; its robust pixels must be the exact reference's,
//! and a few pixels whose answer is plain must show it.

use glam::DVec3;
use peel_runtime::camera::{Camera, LocalView, Pose};

use super::frame::Frame;
use super::prepare::{prepare, Prepared, Triangles};
use crate::tools::reference::reference;
use crate::tools::shot::Shot;

/// A baseline's frame at the renderer's precision.
pub type Draw<'d> = dyn Fn(&[Prepared<8>], &LocalView, &mut [u32]) -> Frame + 'd;

const W: u32 = 96;
const H: u32 = 72;

/// The square `[x0, x1] x [y0, y1]` at depth `z(x, y)` as two triangles.
fn square(x0: f64, y0: f64, x1: f64, y1: f64, z: impl Fn(f64, f64) -> f64) -> [[DVec3; 3]; 2] {
    let p = |x: f64, y: f64| DVec3::new(x, y, z(x, y));
    [
        [p(x0, y0), p(x1, y0), p(x1, y1)],
        [p(x0, y0), p(x1, y1), p(x0, y1)],
    ]
}

/// `draw`'s id image of `triangles` seen from `z = 5` looking down `-z`, after checking that
/// every robust pixel is the reference's; also the frame's figures.
fn frame(draw: &Draw<'_>, triangles: &[[DVec3; 3]]) -> (Vec<u32>, Frame) {
    let shot = Shot {
        near: Some(0.01),
        ..Shot::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, W, H)
    };
    let pose = Pose {
        eye: shot.eye,
        target: shot.target,
        up: shot.up,
    };
    let camera = Camera::look_at(pose, shot.fov_y_deg, W, H, 0.01).expect("a camera");
    let view = camera.view([0.0; 3]);
    let source = Triangles::new(triangles, DVec3::ZERO);
    let (mut projected, mut tris) = (Vec::new(), Vec::new());
    prepare::<8>(&source, &view, &mut projected, &mut tris);
    let mut ids = vec![u32::MAX; (W * H) as usize];
    let f = draw(&tris, &view, &mut ids);
    let exact = reference(triangles, &[], &shot, 0.01);
    for (k, (&got, &want)) in ids.iter().zip(&exact.ids).enumerate() {
        if exact.robust[k] {
            assert_eq!(got, want, "pixel ({}, {})", k as u32 % W, k as u32 / W);
        }
    }
    assert!(f.memory_bytes > 0);
    (ids, f)
}

/// The id (`+ 1`) at pixel `(x, y)`, as the source square it belongs to (triangles `2k` and
/// `2k + 1` are square `k`; `None` for the background).
fn square_at(ids: &[u32], x: u32, y: u32) -> Option<u32> {
    ids[(y * W + x) as usize].checked_sub(1).map(|id| id / 2)
}

/// The three scenes, each in both orders: [`overlapping_and_hidden`], [`crossing`].
pub fn check_hand_made_scenes(draw: &Draw<'_>) {
    overlapping_and_hidden(draw);
    crossing(draw);
}

/// Two overlapping squares, the far one listed first and then last; and a small square behind
/// a larger nearer one, which hides it entirely, in both orders.
fn overlapping_and_hidden(draw: &Draw<'_>) {
    let far = square(-1.0, -1.0, 0.4, 0.4, |_, _| 0.0);
    let near = square(-0.4, -0.4, 1.0, 1.0, |_, _| 0.5);
    for (scene, near_square) in [([far, near], 1), ([near, far], 0)] {
        let (ids, f) = frame(draw, scene.as_flattened());
        // The overlap, the far square alone, the near square alone, and the background.
        assert_eq!(square_at(&ids, W / 2 + 1, H / 2 - 1), Some(near_square));
        assert_eq!(square_at(&ids, W / 2 - 8, H / 2 + 8), Some(1 - near_square));
        assert_eq!(square_at(&ids, W / 2 + 8, H / 2 - 8), Some(near_square));
        assert_eq!(square_at(&ids, 1, 1), None);
        assert!(f.written > 0);
    }
    let small = square(-0.5, -0.5, 0.5, 0.5, |_, _| 0.0);
    let large = square(-2.0, -2.0, 2.0, 2.0, |_, _| 1.0);
    for (scene, large_square) in [([small, large], 1), ([large, small], 0)] {
        let (ids, _) = frame(draw, scene.as_flattened());
        assert!(
            (0..H).all(|y| (0..W).all(|x| square_at(&ids, x, y) != Some(1 - large_square))),
            "the small square is hidden"
        );
        assert_eq!(square_at(&ids, W / 2, H / 2), Some(large_square));
    }
}

/// Two squares crossing in depth along `x = 0`: the tilted one is nearer on the right.
fn crossing(draw: &Draw<'_>) {
    let flat = square(-1.0, -1.0, 1.0, 1.0, |_, _| 0.0);
    let tilted = square(-1.0, -1.0, 1.0, 1.0, |x, _| 0.6 * x);
    for (scene, tilted_square) in [([flat, tilted], 1), ([tilted, flat], 0)] {
        let (ids, _) = frame(draw, scene.as_flattened());
        for y in [H / 2 - 10, H / 2 + 3, H / 2 + 10] {
            assert_eq!(square_at(&ids, W / 2 + 8, y), Some(tilted_square));
            assert_eq!(square_at(&ids, W / 2 - 8, y), Some(1 - tilted_square));
        }
    }
}
