use glam::{Mat3, Vec3};

use super::*;

#[test]
fn pose_angles_follow_the_command_line_convention() {
    // Yaw turns x towards -z (right-handed about y), pitch y towards z, roll x towards y.
    let yaw = Pose::from_degrees(Vec3::ZERO, 90.0, 0.0, 0.0);
    assert!((yaw.rotation * Vec3::X - Vec3::NEG_Z).length() < 1e-6);
    let pitch = Pose::from_degrees(Vec3::ZERO, 0.0, 90.0, 0.0);
    assert!((pitch.rotation * Vec3::Y - Vec3::Z).length() < 1e-6);
    let roll = Pose::from_degrees(Vec3::ZERO, 0.0, 0.0, 90.0);
    assert!((roll.rotation * Vec3::X - Vec3::Y).length() < 1e-6);
    // Roll first, then pitch, then yaw, then the translation.
    let all = Pose::from_degrees(Vec3::new(1.0, 2.0, 3.0), 90.0, 90.0, 90.0);
    let p = all.rotation * Vec3::X + all.translation;
    let want =
        yaw.rotation * (pitch.rotation * (roll.rotation * Vec3::X)) + Vec3::new(1.0, 2.0, 3.0);
    assert!((p - want).length() < 1e-6);
}

#[test]
fn the_object_view_sees_a_placed_point_where_the_world_view_sees_it() {
    let view = LocalView::look_at(
        Vec3::new(3.0, 2.0, 5.0),
        Vec3::ZERO,
        Vec3::Y,
        100.0,
        64,
        48,
        0.1,
    )
    .unwrap();
    let pose = Pose::from_degrees(Vec3::new(0.5, -1.0, 2.0), 30.0, -20.0, 75.0);
    let (rotation, offset) = placement(&pose, [1.0, 2.0, 3.0], [0.25, 0.5, 0.75]);
    let placed = Placement::new(rotation, offset, Vec3::splat(-1.0), Vec3::splat(1.0));
    let local = object_view(&view, &placed);
    let p = Vec3::new(0.3, -0.7, 0.2);
    // The point p of the object (relative to its centre (1, 2, 3)) is at T + R (c + p) in the
    // world, that is at that minus the world's centre in the world view's frame.
    let world = pose.translation + pose.rotation * (Vec3::new(1.0, 2.0, 3.0) + p)
        - Vec3::new(0.25, 0.5, 0.75);
    assert!((local.to_camera(p) - view.to_camera(world)).length() < 1e-5);
    assert_eq!(Mat3::IDENTITY, Pose::IDENTITY.rotation);
}

#[test]
fn a_step_of_object_memory_costs_what_the_docs_say() {
    // `ObjectMemory`'s docs and the firmware guide quote these.
    let per_step =
        core::mem::size_of::<ObjectMemory<0, 2>>() - core::mem::size_of::<ObjectMemory<0, 1>>();
    let per_object =
        core::mem::size_of::<ObjectMemory<2, 0>>() - core::mem::size_of::<ObjectMemory<1, 0>>();
    assert!(per_step <= 72, "{per_step} bytes a step");
    assert!(per_object <= 172, "{per_object} bytes an object");
}
