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

// The `f32` orbit (`LocalOrbit`) against the `f64` one.

use super::local_orbit::sqrt;

#[test]
fn f32_sines_and_cosines_are_within_4e7() {
    let mut worst = 0.0f64;
    // Every hundredth of a degree over two turns each way, and the exact quarter turns.
    for k in -72_000..=72_000 {
        let deg = k as f32 * 0.01;
        let (s, c) = sin_cos_deg(deg);
        let r = f64::from(deg).to_radians();
        worst = worst
            .max((f64::from(s) - libm::sin(r)).abs())
            .max((f64::from(c) - libm::cos(r)).abs());
    }
    assert!(worst < 4e-7, "worst error {worst:e}");
    for (deg, want) in [
        (0.0f32, (0.0f32, 1.0f32)),
        (90.0, (1.0, 0.0)),
        (180.0, (0.0, -1.0)),
        (-90.0, (-1.0, 0.0)),
        (270.0, (-1.0, 0.0)),
        (3600.0, (0.0, 1.0)),
    ] {
        // Exact (a zero may come with either sign).
        assert_eq!(sin_cos_deg(deg), want, "{deg}");
    }
    assert!(sin_cos_deg(f32::NAN).0.is_nan() && sin_cos_deg(f32::INFINITY).1.is_nan());
}

proptest::proptest! {
    /// Far from zero too, up to the documented 16,000,000 degrees.
    #[test]
    fn f32_sines_and_cosines_hold_for_large_angles(deg in -1.6e7f32..1.6e7) {
        let (s, c) = sin_cos_deg(deg);
        let r = f64::from(deg).to_radians();
        proptest::prop_assert!((f64::from(s) - libm::sin(r)).abs() < 4e-7, "{deg}");
        proptest::prop_assert!((f64::from(c) - libm::cos(r)).abs() < 4e-7, "{deg}");
    }

    /// The Newton square root, over the whole positive range, subnormals included.
    #[test]
    fn f32_square_root_is_within_2_pow_22(bits in 1u32..0x7f80_0000) {
        let x = f32::from_bits(bits);
        let want = f64::from(x).sqrt();
        let got = f64::from(sqrt(x));
        proptest::prop_assert!(((got - want) / want).abs() <= 1.0 / 4_194_304.0, "{x:e}: {got} vs {want}");
    }

    /// The `f32` orbit's view against the `f64` path (`Orbit::pose`, `Camera::look_at`,
    /// `Camera::view`) for the same angles, distance and field of view: the bounds of the
    /// module docs.
    #[test]
    fn the_f32_orbit_agrees_with_the_f64_one(
        centre in proptest::array::uniform3(-1e6f64..1e6),
        lo in proptest::array::uniform3(-50.0f32..0.0),
        size in proptest::array::uniform3(0.01f32..100.0),
        azimuth in -720.0f32..720.0,
        elevation in -89.0f32..89.0,
        distance in 1.0f32..10.0,
        fov in 10.0f32..120.0,
        width in 1u32..2000,
        height in 1u32..2000,
    ) {
        let lo = Vec3::from_array(lo);
        let hi = lo + Vec3::from_array(size);
        let h = header(centre, lo.to_array(), hi.to_array());
        let orbit = LocalOrbit { azimuth_deg: azimuth, elevation_deg: elevation, distance };
        let focal = LocalOrbit::focal(fov, height);
        let near = LocalOrbit::default_near(&h);
        let view = orbit.view(&h, focal, width, height, near).unwrap();
        let wide = Orbit {
            azimuth_deg: f64::from(azimuth),
            elevation_deg: f64::from(elevation),
            distance: f64::from(distance),
        };
        let near64 = Camera::default_near(h.bounds_min, h.bounds_max);
        let reference = Camera::look_at(wide.pose(&h), f64::from(fov), width, height, near64)
            .unwrap()
            .view(centre);
        for (a, b) in [
            (view.right, reference.right),
            (view.up, reference.up),
            (view.forward, reference.forward),
        ] {
            proptest::prop_assert!((a - b).abs().max_element() <= 2e-6, "{a} vs {b}");
        }
        let (_, radius) = LocalOrbit::bounding_sphere(&h);
        let reach = lo.abs().max(hi.abs()).max_element() + distance * radius;
        proptest::prop_assert!(
            (view.eye - reference.eye).abs().max_element() <= 2e-6 * reach,
            "{} vs {}", view.eye, reference.eye
        );
        proptest::prop_assert!((view.fx - reference.fx).abs() <= 1e-5 * reference.fx);
        proptest::prop_assert_eq!(view.fx, view.fy);
        proptest::prop_assert_eq!((view.cx, view.cy), (reference.cx, reference.cy));
        proptest::prop_assert!((view.near - reference.near).abs() <= 1e-6 * reference.near);
        let fitting = LocalOrbit::fitting_distance(focal, width, height);
        let fitting64 = Orbit::fitting_distance(f64::from(fov), width, height);
        proptest::prop_assert!((f64::from(fitting) - fitting64).abs() <= 1e-5 * fitting64);
    }
}

#[test]
fn the_f32_orbit_is_defined_at_the_poles_and_refuses_bad_views() {
    let h = header([0.0; 3], [-1.0; 3], [1.0; 3]);
    let focal = LocalOrbit::focal(60.0, 48);
    for elevation_deg in [90.0, -90.0] {
        let orbit = LocalOrbit {
            elevation_deg,
            ..LocalOrbit::default()
        };
        let view = orbit.view(&h, focal, 64, 48, 0.01).unwrap();
        assert!((view.forward.y + elevation_deg / 90.0).abs() < 1e-6);
        assert!(view.right.dot(view.forward).abs() < 1e-6);
        assert!((view.up.length() - 1.0).abs() < 1e-6);
    }
    let orbit = LocalOrbit::default();
    assert_eq!(
        orbit.view(&h, focal, 0, 48, 0.01),
        Err(RenderError::BadCamera)
    );
    assert_eq!(
        orbit.view(&h, 0.0, 64, 48, 0.01),
        Err(RenderError::BadCamera)
    );
    assert_eq!(
        orbit.view(&h, focal, 64, 48, 0.0),
        Err(RenderError::BadCamera)
    );
    let nan = LocalOrbit {
        azimuth_deg: f32::NAN,
        ..orbit
    };
    assert_eq!(
        nan.view(&h, focal, 64, 48, 0.01),
        Err(RenderError::BadCamera)
    );
    // A scene without extent: one unit per radius, as the `f64` orbit.
    let point = header([0.0; 3], [0.5; 3], [0.5; 3]);
    assert_eq!(LocalOrbit::bounding_sphere(&point), (Vec3::splat(0.5), 1.0));
}

/// The pixels of the `f32` orbit against the `f64` one's, over an orbit of the render tests'
/// kind of scene (two boxes on either side of a split plane, each face its own colour), at
/// two image sizes and three elevations: the views differ by rounding (a few millionths),
/// which moves an edge by thousandths of a pixel, so a pixel differs only where an edge passes
/// that close to its centre: each differing pixel has the other image's colour next to it. On
/// these 144 frames, 2 of 1.6 million pixels differ.
#[test]
fn the_f32_orbit_draws_the_f64_orbits_pixels() {
    extern crate std;
    use crate::display::{Colour, SpanSink};
    use crate::read::Node;
    use crate::render::{Renderer, Workspace};
    use crate::traverse::testing::{box_faces, TestTree};
    use std::vec;
    use std::vec::Vec;

    struct Image {
        width: u32,
        pixels: Vec<Colour>,
    }
    impl SpanSink for Image {
        fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
            let row = (y * self.width) as usize;
            self.pixels[row + x_start as usize..row + x_end as usize].fill(colour);
        }
    }

    let mut t = TestTree::default();
    let plane = t.add_plane(Vec3::X, 0.0);
    let root = t.add_node(Node::EMPTY);
    let mut colours = 0u8;
    let mut boxed = |t: &mut TestTree, lo: Vec3, hi: Vec3| {
        let (first, count) = box_faces(t, lo, hi, Colour::default());
        for p in &mut t.polygons[first as usize..] {
            colours += 1;
            p.colour = Colour::new(colours.wrapping_mul(40), 255 - colours * 20, colours);
        }
        t.add_node(Node::Convex {
            first,
            count,
            child: None,
        })
    };
    let front = boxed(&mut t, Vec3::new(0.5, -1.0, -0.7), Vec3::new(2.0, 0.6, 1.3));
    let back = boxed(
        &mut t,
        Vec3::new(-2.2, -0.4, -1.0),
        Vec3::new(-0.3, 1.1, 0.2),
    );
    t.nodes[root as usize] = Node::Split {
        plane,
        front: Some(front),
        back: Some(back),
    };
    t.centre = [100.0, -20.0, 3.5];
    let h = header(t.centre, [-2.2, -1.0, -1.0], [2.0, 1.1, 1.3]);

    let (mut frames, mut pixels, mut differing) = (0, 0, 0);
    for (width, height) in [(64u32, 48u32), (160, 120)] {
        let focal = LocalOrbit::focal(60.0, height);
        let distance = LocalOrbit::fitting_distance(focal, width, height);
        let near = LocalOrbit::default_near(&h);
        let near64 = Camera::default_near(h.bounds_min, h.bounds_max);
        for elevation in [-30.0f32, 20.0, 45.0] {
            for k in 0..24 {
                let orbit = LocalOrbit {
                    azimuth_deg: 15.0 * k as f32 + 0.3,
                    elevation_deg: elevation,
                    distance,
                };
                let wide = Orbit {
                    azimuth_deg: f64::from(orbit.azimuth_deg),
                    elevation_deg: f64::from(elevation),
                    distance: f64::from(distance),
                };
                let views = [
                    orbit.view(&h, focal, width, height, near).unwrap(),
                    Camera::look_at(wide.pose(&h), 60.0, width, height, near64)
                        .unwrap()
                        .view(t.centre),
                ];
                let images = views.map(|view| {
                    let mut image = Image {
                        width,
                        pixels: vec![Colour::new(1, 2, 3); (width * height) as usize],
                    };
                    let mut ws = Workspace::<8, 16>::new();
                    Renderer::new(&mut ws).draw(&t, &view, &mut image).unwrap();
                    image.pixels
                });
                frames += 1;
                pixels += images[0].len();
                let (w, h) = (width as usize, height as usize);
                for (i, (a, b)) in images[0].iter().zip(&images[1]).enumerate() {
                    if a == b {
                        continue;
                    }
                    differing += 1;
                    // An edge's tie: a neighbour in the `f64` image has the `f32` colour.
                    let (x, y) = (i % w, i / w);
                    let neighbours = [
                        (x > 0).then(|| i - 1),
                        (x + 1 < w).then(|| i + 1),
                        (y > 0).then(|| i - w),
                        (y + 1 < h).then(|| i + w),
                    ];
                    assert!(
                        neighbours.iter().flatten().any(|&j| images[1][j] == *a),
                        "pixel ({x}, {y}) of {width}x{height} at azimuth {} elevation \
                         {elevation}: not on an edge",
                        orbit.azimuth_deg
                    );
                }
            }
        }
    }
    assert_eq!(frames, 144);
    // Measured: 2 of 1,603,584 pixels.
    assert!(
        differing * 100_000 <= pixels,
        "{differing} of {pixels} pixels differ over {frames} frames"
    );
}
