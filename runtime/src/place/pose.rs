//! [`Pose`]: where an object stands in the world this frame.

use glam::{Mat3, Vec3};

/// A rigid placement of an object: the point `p` of the object's file goes to
/// `translation + rotation * p` in the world's coordinates. The rotation must be a rotation
/// (orthonormal, determinant 1): the renderer moves the camera into the object's frame with
/// its transpose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// The rotation.
    pub rotation: Mat3,
    /// The translation, in the world's coordinates.
    pub translation: Vec3,
}

impl Pose {
    /// The object where its file puts it.
    pub const IDENTITY: Pose = Pose {
        rotation: Mat3::IDENTITY,
        translation: Vec3::ZERO,
    };

    /// `translation + Ry(yaw) Rx(pitch) Rz(roll) p`, angles in degrees, each a right-handed
    /// rotation about its axis (the command line's `--pose`).
    pub fn from_degrees(translation: Vec3, yaw: f32, pitch: f32, roll: f32) -> Pose {
        let rotation = Mat3::from_rotation_y(yaw.to_radians())
            * Mat3::from_rotation_x(pitch.to_radians())
            * Mat3::from_rotation_z(roll.to_radians());
        Pose {
            rotation,
            translation,
        }
    }

    /// Whether every value is finite (the renderer refuses others).
    pub fn is_finite(&self) -> bool {
        self.rotation.is_finite() && self.translation.is_finite()
    }
}

impl Default for Pose {
    fn default() -> Self {
        Pose::IDENTITY
    }
}
