//! Tests of the camera: the specification's formulas by hand, the focal/pixel-ratio model,
//! orbits, refusals, and the `f32` view against the `f64` camera.

use super::*;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
}

proptest::proptest! {
    /// Every corner of a world box, transformed and projected, lies in the screen
    /// rectangle of its camera-space box, to within the renderer's allowance for the
    /// rounding of screen values (`render::slack` without its snapping term: 1/64 pixel
    /// plus 2^-18 of the image's larger side, what culling relies on), and closer for a
    /// value smaller than that side (2^-18 of the value). In practice the box's error
    /// bound keeps every corner inside.
    #[test]
    fn box_rectangle_holds_every_projected_corner(
        eye in proptest::array::uniform3(-50.0f64..50.0),
        target in proptest::array::uniform3(-5.0f64..5.0),
        lo in proptest::array::uniform3(-10.0f32..10.0),
        size in proptest::array::uniform3(0.0f32..8.0),
    ) {
        let pose = Pose::new(DVec3::from_array(eye), DVec3::from_array(target));
        let Ok(cam) = Camera::look_at(pose, 60.0, 640, 480, 0.01) else { return Ok(()) };
        let view = cam.view([0.0; 3]);
        let lo = Vec3::from_array(lo);
        let hi = lo + Vec3::from_array(size);
        let b = view.box_to_camera(lo, hi);
        let Some((min, max)) = view.box_on_screen(&b) else { return Ok(()) };
        for k in 0..8 {
            let p = Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            let q = view.project(view.to_camera(p));
            let tol = 1.0 / 64.0 + q.x.abs().max(q.y.abs()).min(640.0) / 262_144.0;
            proptest::prop_assert!(q.x >= min.x - tol && q.x <= max.x + tol, "{q} {min} {max}");
            proptest::prop_assert!(q.y >= min.y - tol && q.y <= max.y + tol, "{q} {min} {max}");
        }
    }
}

fn simple() -> Camera {
    // fov 90 -> fpx = (H/2) / tan(45) = 50.
    Camera::look_at(
        Pose::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO),
        90.0,
        200,
        100,
        0.01,
    )
    .unwrap()
}

#[test]
fn look_at_matches_the_spec_formulas() {
    let cam = simple();
    let (r, u, f) = cam.basis();
    assert!(close(r.x, 1.0) && close(r.y, 0.0) && close(r.z, 0.0));
    assert!(close(u.x, 0.0) && close(u.y, 1.0) && close(u.z, 0.0));
    assert!(close(f.x, 0.0) && close(f.y, 0.0) && close(f.z, -1.0));
    // xc = 1, yc = 0.5, zc = 5: sx = 100 + 50 * 1 / 5, sy = 50 - 50 * 0.5 / 5.
    let (sx, sy) = cam.project(DVec3::new(1.0, 0.5, 0.0)).unwrap();
    assert!(close(sx, 110.0), "{sx}");
    assert!(close(sy, 45.0), "{sy}");
    // The target projects to the image centre.
    let (sx, sy) = cam.project(DVec3::ZERO).unwrap();
    assert!(close(sx, 100.0) && close(sy, 50.0));
}

#[test]
fn oblique_camera_hand_computed() {
    // Eye on the +x axis looking at the origin: forward -x, right = cross(-x, y) = -z.
    // fov 60, H = 120 -> fpx = 60 / tan(30 deg) = 60 * sqrt(3).
    let cam = Camera::look_at(
        Pose::new(DVec3::new(10.0, 0.0, 0.0), DVec3::ZERO),
        60.0,
        160,
        120,
        0.1,
    )
    .unwrap();
    let p = DVec3::new(0.0, 2.0, -3.0); // xc = 3, yc = 2, zc = 10
    let c = cam.to_camera(p);
    assert!(close(c.x, 3.0) && close(c.y, 2.0) && close(c.z, 10.0));
    let fpx = 60.0 * 3f64.sqrt();
    let (sx, sy) = cam.project(p).unwrap();
    assert!(close(sx, 80.0 + fpx * 0.3));
    assert!(close(sy, 60.0 - fpx * 0.2));
}

#[test]
fn points_closer_than_near_do_not_project() {
    let cam = simple();
    assert!(cam.project(DVec3::new(0.0, 0.0, 5.0)).is_none()); // the eye itself
    assert!(cam.project(DVec3::new(0.0, 0.0, 6.0)).is_none()); // behind
    assert!(cam.project(DVec3::new(0.0, 0.0, 4.995)).is_none()); // zc = 0.005 < near
    assert!(cam.project(DVec3::new(0.0, 0.0, 4.98)).is_some()); // zc = 2 * near
}

fn header(centre: [f64; 3], lo: [f32; 3], hi: [f32; 3]) -> Header {
    Header {
        centre,
        bounds_min: Vec3::from_array(lo),
        bounds_max: Vec3::from_array(hi),
        ..Header::default()
    }
}

proptest::proptest! {
    /// An orbit at the fitting distance sees every corner of the scene's box inside the
    /// image, whatever the scene's position, size and aspect and the orbit's angles.
    #[test]
    fn an_orbit_at_the_fitting_distance_frames_the_whole_box(
        centre in proptest::array::uniform3(-1e6f64..1e6),
        lo in proptest::array::uniform3(-50.0f32..0.0),
        size in proptest::array::uniform3(0.01f32..100.0),
        azimuth in -360.0f64..360.0,
        elevation in -85.0f64..85.0,
        fov in 10.0f64..120.0,
        width in 1u32..2000,
        height in 1u32..2000,
    ) {
        let lo = Vec3::from_array(lo);
        let hi = lo + Vec3::from_array(size);
        let h = header(centre, lo.to_array(), hi.to_array());
        let orbit = Orbit {
            azimuth_deg: azimuth,
            elevation_deg: elevation,
            distance: Orbit::fitting_distance(fov, width, height),
        };
        let cam = Camera::look_at(orbit.pose(&h), fov, width, height, 1e-6).unwrap();
        let (c, r) = Orbit::bounding_sphere(&h);
        proptest::prop_assert!((cam.eye().distance(c) / r - orbit.distance).abs() < 1e-6);
        for k in 0..8 {
            let p = DVec3::new(
                f64::from(if k & 1 == 0 { lo.x } else { hi.x }),
                f64::from(if k & 2 == 0 { lo.y } else { hi.y }),
                f64::from(if k & 4 == 0 { lo.z } else { hi.z }),
            ) + DVec3::from_array(centre);
            let (sx, sy) = cam.project(p).unwrap();
            let (w, ht) = (f64::from(width), f64::from(height));
            proptest::prop_assert!(
                (0.0..=w).contains(&sx) && (0.0..=ht).contains(&sy),
                "corner {k} at ({sx}, {sy}) outside {width}x{height}"
            );
        }
    }
}

#[test]
fn the_default_orbit_looks_at_the_box_centre_from_the_front_right_and_above() {
    let h = header([10.0, 0.0, 0.0], [-1.0, -2.0, -3.0], [1.0, 2.0, 3.0]);
    let pose = Orbit::default().pose(&h);
    assert_eq!(pose.target, DVec3::new(10.0, 0.0, 0.0));
    let d = pose.eye - pose.target;
    assert!(d.x > 0.0 && d.y > 0.0 && d.z > 0.0, "{d}");
    assert!((d.length() - 2.5 * 14f64.sqrt()).abs() < 1e-9);
    // A scene without extent still gets a pose one unit per radius away.
    let point = header([1.0, 2.0, 3.0], [0.0; 3], [0.0; 3]);
    assert!(
        (Orbit::default()
            .pose(&point)
            .eye
            .distance(DVec3::new(1.0, 2.0, 3.0))
            - 2.5)
            .abs()
            < 1e-9
    );
}

#[test]
fn intrinsics_equal_look_at_when_parameters_agree() {
    let pose = Pose {
        eye: DVec3::new(1.0, 2.0, 3.0),
        target: DVec3::new(-2.0, 0.5, -4.0),
        up: DVec3::new(0.1, 1.0, 0.0),
    };
    let (w, h) = (320, 240);
    let a = Camera::look_at(pose, 50.0, w, h, 0.05).unwrap();
    let fpx = 120.0 / (25f64).to_radians().tan();
    let rx = 0.002;
    let intr = Intrinsics {
        f: fpx * rx,
        rx,
        ry: rx,
        i0: 160.0,
        j0: 120.0,
    };
    let b = Camera::from_intrinsics(pose, intr, w, h, 0.05).unwrap();
    for p in [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(-1.5, 0.7, -2.0),
        DVec3::new(3.0, -1.0, -9.0),
    ] {
        let (ax, ay) = a.project(p).unwrap();
        let (bx, by) = b.project(p).unwrap();
        assert!(close(ax, bx) && close(ay, by), "{ax},{ay} vs {bx},{by}");
    }
}

#[test]
fn intrinsics_use_the_pixel_ratios_and_principal_point() {
    // i = i0 + f xc / (rx zc), j = j0 - f yc / (ry zc), with xc = 1, yc = 0.5, zc = 5.
    let intr = Intrinsics {
        f: 2.0,
        rx: 0.01,
        ry: 0.02,
        i0: 30.0,
        j0: 40.0,
    };
    let cam = Camera::from_intrinsics(
        Pose::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO),
        intr,
        64,
        64,
        0.01,
    )
    .unwrap();
    let (i, j) = cam.project(DVec3::new(1.0, 0.5, 0.0)).unwrap();
    assert!(close(i, 30.0 + 200.0 / 5.0), "{i}");
    assert!(close(j, 40.0 - 100.0 * 0.5 / 5.0), "{j}");
}

#[test]
fn degenerate_cameras_are_refused() {
    let ok = Pose::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO);
    let bad = |r: Result<Camera, RenderError>| r == Err(RenderError::BadCamera);
    assert!(bad(Camera::look_at(ok, 60.0, 0, 10, 0.1)));
    assert!(bad(Camera::look_at(ok, 60.0, 10, 0, 0.1)));
    assert!(bad(Camera::look_at(ok, 0.0, 10, 10, 0.1)));
    assert!(bad(Camera::look_at(ok, 180.0, 10, 10, 0.1)));
    assert!(bad(Camera::look_at(ok, f64::NAN, 10, 10, 0.1)));
    assert!(bad(Camera::look_at(ok, 60.0, 10, 10, 0.0)));
    assert!(bad(Camera::look_at(ok, 60.0, 10, 10, f64::INFINITY)));
    let same = Pose::new(DVec3::ONE, DVec3::ONE);
    assert!(bad(Camera::look_at(same, 60.0, 10, 10, 0.1)));
    let parallel = Pose {
        eye: DVec3::new(0.0, 5.0, 0.0),
        target: DVec3::ZERO,
        up: DVec3::Y,
    };
    assert!(bad(Camera::look_at(parallel, 60.0, 10, 10, 0.1)));
    let nan = Pose::new(DVec3::new(f64::NAN, 0.0, 0.0), DVec3::ZERO);
    assert!(bad(Camera::look_at(nan, 60.0, 10, 10, 0.1)));
    let intr = Intrinsics {
        f: 1.0,
        rx: 0.0,
        ry: 1.0,
        i0: 0.0,
        j0: 0.0,
    };
    assert!(bad(Camera::from_intrinsics(ok, intr, 10, 10, 0.1)));
}

#[test]
fn view_is_relative_to_the_centre_and_agrees_with_f64() {
    let centre = [1.0e6, -2.0e6, 3.0e6];
    let eye = DVec3::new(1.0e6 + 0.25, -2.0e6 + 1.5, 3.0e6 + 7.0);
    let cam = Camera::look_at(
        Pose::new(eye, DVec3::from_array(centre)),
        60.0,
        100,
        100,
        0.01,
    )
    .unwrap();
    let view = cam.view(centre);
    assert_eq!(view.eye, Vec3::new(0.25, 1.5, 7.0));
    let local = Vec3::new(0.5, -0.25, 1.0);
    let world = DVec3::from_array(centre) + local.as_dvec3();
    let (sx, sy) = cam.project(world).unwrap();
    let s = view.project(view.to_camera(local));
    assert!((f64::from(s.x) - sx).abs() < 1e-3 && (f64::from(s.y) - sy).abs() < 1e-3);
}

#[test]
fn f32_look_at_agrees_with_the_f64_camera() {
    let centre = [3.0, -1.0, 2.0];
    let c = DVec3::from_array(centre);
    let (eye, target, up) = (
        DVec3::new(2.0, 3.0, 9.0),
        DVec3::new(-1.0, 0.5, 0.25),
        DVec3::new(0.1, 1.0, 0.0),
    );
    let (w, h) = (160, 120);
    let camera = Camera::look_at(Pose { eye, target, up }, 50.0, w, h, 0.01).unwrap();
    let focal = (60.0 / (25f64).to_radians().tan()) as f32;
    let view = LocalView::look_at(
        (eye - c).as_vec3(),
        (target - c).as_vec3(),
        up.as_vec3(),
        focal,
        w,
        h,
        0.01,
    )
    .unwrap();
    let reference = camera.view(centre);
    assert_eq!(
        (view.width, view.height, view.cx, view.cy),
        (160, 120, 80.0, 60.0)
    );
    assert!((view.fx - reference.fx).abs() < 1e-4 && view.fx == view.fy);
    assert!((view.near - reference.near).abs() < 1e-9);
    for (a, b) in [
        (view.eye, reference.eye),
        (view.right, reference.right),
        (view.up, reference.up),
        (view.forward, reference.forward),
    ] {
        assert!((a - b).abs().max_element() < 1e-6, "{a} vs {b}");
    }
    for p in [
        Vec3::ZERO,
        Vec3::new(-1.5, 0.7, -2.0),
        Vec3::new(3.0, -1.0, -4.0),
    ] {
        let (s, r) = (
            view.project(view.to_camera(p)),
            reference.project(reference.to_camera(p)),
        );
        assert!((s - r).abs().max_element() < 1e-3, "{s} vs {r}");
    }
}

#[test]
fn degenerate_f32_views_are_refused() {
    let (eye, target) = (Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO);
    let look = |eye: Vec3, target: Vec3, up: Vec3, focal: f32, w: u32, h: u32, near: f32| {
        LocalView::look_at(eye, target, up, focal, w, h, near)
    };
    assert!(look(eye, target, Vec3::Y, 100.0, 10, 10, 0.1).is_ok());
    let bad = |r: Result<LocalView, RenderError>| r == Err(RenderError::BadCamera);
    assert!(bad(look(eye, target, Vec3::Y, 100.0, 0, 10, 0.1)));
    assert!(bad(look(eye, target, Vec3::Y, 100.0, 10, 0, 0.1)));
    assert!(bad(look(eye, target, Vec3::Y, 0.0, 10, 10, 0.1)));
    assert!(bad(look(eye, target, Vec3::Y, f32::NAN, 10, 10, 0.1)));
    assert!(bad(look(eye, target, Vec3::Y, f32::INFINITY, 10, 10, 0.1)));
    assert!(bad(look(eye, target, Vec3::Y, 100.0, 10, 10, 0.0)));
    assert!(bad(look(eye, target, Vec3::Y, 100.0, 10, 10, f32::NAN)));
    assert!(bad(look(eye, eye, Vec3::Y, 100.0, 10, 10, 0.1)));
    assert!(bad(look(eye, target, Vec3::Z, 100.0, 10, 10, 0.1)));
    assert!(bad(look(eye, target, Vec3::NAN, 100.0, 10, 10, 0.1)));
    assert!(bad(look(
        Vec3::INFINITY,
        target,
        Vec3::Y,
        100.0,
        10,
        10,
        0.1
    )));
    assert!(bad(look(eye, Vec3::NAN, Vec3::Y, 100.0, 10, 10, 0.1)));
    let mut view = look(eye, target, Vec3::Y, 100.0, 10, 10, 0.1).unwrap();
    view.right.x = f32::NAN;
    assert_eq!(view.check(), Err(RenderError::BadCamera));
}

#[test]
fn from_basis_is_look_at_without_the_normalising() {
    let (eye, target) = (Vec3::new(1.0, 2.0, 6.0), Vec3::new(-0.5, 0.0, 0.25));
    let view = LocalView::look_at(eye, target, Vec3::Y, 90.0, 64, 48, 0.01).unwrap();
    let same = LocalView::from_basis(eye, view.right, view.forward, 90.0, 64, 48, 0.01);
    assert_eq!(same, view);
}

#[test]
fn default_near_is_a_thousandth_of_the_diagonal() {
    let n = Camera::default_near(Vec3::ZERO, Vec3::new(3.0, 4.0, 12.0));
    assert!(close(n, 0.013));
}
