//! Place: objects compiled apart, posed each frame, and their exact order among the world's
//! polygons.
//!
//! A file of parts ([`crate::read::Parts`]) holds a world and objects, each a tree compiled in
//! its own frame. A frame gives each object a [`Pose`] (or hides it). The renderer then draws
//! the world's tree and each object's tree, each in its own exact order, and orders them
//! among themselves with planes (`plan.rs`):
//! - an object goes down the world's tree as a polygon would: a split plane with the object
//!   on one side sends it to that child; a convex node whose polygons' planes all have the
//!   object on their interior side takes it between its polygons seen from inside and those
//!   seen from outside, and passes it to its child;
//! - where a world plane passes through the object, the object is cut by it: each side is a
//!   *piece*, the object drawn with its polygons clipped to that side, placed on its own.
//!   Both pieces compute the points on the cut from the same plane values, so they share
//!   them bit for bit and leave no crack;
//! - pieces of several objects in one region of the world are ordered by a plane that
//!   separates the objects' posed boxes, found each frame; where none exists and their boxes
//!   overlap on the screen, the frame is refused with
//!   [`RenderError::ObjectsIntersect`](crate::error::RenderError::ObjectsIntersect), never
//!   drawn wrong.
//!
//! An object is placed by its box (the header's bounds), posed: a conservative hull. A box
//! within a hair of a plane (`2^-20` of the scene's size) counts as on its side, so that an
//! object resting on the floor is not cut by it.

mod plan;
mod pose;

use glam::{Mat3, Vec3};

use crate::camera::LocalView;
use crate::read::Scene;
pub(crate) use plan::{plan, Cut, Placement, Step, NO_CUT};
pub use pose::Pose;

/// An object of a frame: its tree and where it stands (`None`: hidden). Made once
/// ([`Object::new`] reads its vertices' box), posed each frame through [`Object::pose`].
#[derive(Debug, Clone, Copy)]
pub struct Object<'a> {
    /// The object's tree, compiled in its own frame.
    pub scene: Scene<'a>,
    /// Its pose this frame; `None` hides it.
    pub pose: Option<Pose>,
    /// The box of its vertices (relative to its centre): tighter than the header's bounds,
    /// which are the vertex grid's, so that objects that touch are told apart.
    bounds: (Vec3, Vec3),
}

impl<'a> Object<'a> {
    /// The object of `scene`, placed by `pose` (`None`: hidden). Reads every vertex once.
    pub fn new(scene: Scene<'a>, pose: Option<Pose>) -> Self {
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for v in 0..scene.header().vertex_count {
            let p = scene.vertex(v);
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let h = scene.header();
        let bounds = if lo.cmple(hi).all() {
            (lo, hi)
        } else {
            (h.bounds_min, h.bounds_max)
        };
        Object {
            scene,
            pose,
            bounds,
        }
    }

    /// The box of its vertices, relative to its centre.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.bounds
    }
}

/// What a frame with objects draws: the world (if any) and the objects with their poses.
/// [`crate::render::Renderer::draw`] takes it as it takes a [`Scene`], with object memory
/// ([`crate::render::Renderer::object_memory`]).
#[derive(Debug, Clone, Copy)]
pub struct Posed<'s, 'a> {
    /// The world, drawn where its file puts it.
    pub world: Option<Scene<'a>>,
    /// The objects; errors name them by their index here.
    pub objects: &'s [Object<'a>],
}

impl<'s, 'a> Posed<'s, 'a> {
    /// The world and the objects of a frame.
    pub fn new(world: Option<Scene<'a>>, objects: &'s [Object<'a>]) -> Self {
        Posed { world, objects }
    }

    /// The world position a frame's view is relative to ([`crate::camera::Camera::view`]):
    /// the world's centre, or the origin without a world.
    pub fn centre(&self) -> [f64; 3] {
        self.world.map_or([0.0; 3], |w| w.header().centre)
    }
}

/// The memory a frame with objects orders them in: per object its placement, and the
/// frame's order as steps, with the pieces and cuts it is made of. `OBJECTS` objects at
/// most, `STEPS` steps, pieces, cuts and pending tasks each: 172 bytes an object, 72 a step.
#[derive(Debug)]
pub struct ObjectMemory<const OBJECTS: usize, const STEPS: usize> {
    pub(crate) placements: [Placement; OBJECTS],
    pub(crate) steps: [Step; STEPS],
    pub(crate) pieces: [plan::Piece; STEPS],
    pub(crate) cuts: [Cut; STEPS],
    pub(crate) tasks: [plan::Task; STEPS],
}

impl<const OBJECTS: usize, const STEPS: usize> ObjectMemory<OBJECTS, STEPS> {
    /// Memory for up to `OBJECTS` objects and `STEPS` steps.
    pub const fn new() -> Self {
        ObjectMemory {
            placements: [Placement::HIDDEN; OBJECTS],
            steps: [Step::Subtree(0); STEPS],
            pieces: [plan::Piece::EMPTY; STEPS],
            cuts: [Cut::EMPTY; STEPS],
            tasks: [plan::Task::Idle; STEPS],
        }
    }
}

impl<const OBJECTS: usize, const STEPS: usize> Default for ObjectMemory<OBJECTS, STEPS> {
    fn default() -> Self {
        Self::new()
    }
}

/// [`ObjectMemory`] borrowed as slices (what the renderer keeps).
#[derive(Debug)]
pub(crate) struct Memory<'m> {
    pub(crate) placements: &'m mut [Placement],
    pub(crate) steps: &'m mut [Step],
    pub(crate) pieces: &'m mut [plan::Piece],
    pub(crate) cuts: &'m mut [Cut],
    pub(crate) tasks: &'m mut [plan::Task],
}

impl<'m, const OBJECTS: usize, const STEPS: usize> From<&'m mut ObjectMemory<OBJECTS, STEPS>>
    for Memory<'m>
{
    fn from(m: &'m mut ObjectMemory<OBJECTS, STEPS>) -> Self {
        Memory {
            placements: &mut m.placements,
            steps: &mut m.steps,
            pieces: &mut m.pieces,
            cuts: &mut m.cuts,
            tasks: &mut m.tasks,
        }
    }
}

/// The rotation and the offset that take an object's coordinates (relative to its centre)
/// to the world's (relative to `world_centre`): `p -> rotation * p + offset`.
pub(crate) fn placement(
    pose: &Pose,
    object_centre: [f64; 3],
    world_centre: [f64; 3],
) -> (Mat3, Vec3) {
    let r = pose.rotation;
    let c = object_centre;
    // In f64: the centres may be far from the origin.
    let rotated =
        |row: Vec3| f64::from(row.x) * c[0] + f64::from(row.y) * c[1] + f64::from(row.z) * c[2];
    let rows = r.transpose();
    let t = pose.translation;
    let offset = Vec3::new(
        (f64::from(t.x) + rotated(rows.x_axis) - world_centre[0]) as f32,
        (f64::from(t.y) + rotated(rows.y_axis) - world_centre[1]) as f32,
        (f64::from(t.z) + rotated(rows.z_axis) - world_centre[2]) as f32,
    );
    (r, offset)
}

/// The camera in an object's frame: the view moved by the inverse of its placement (its
/// rotation's transpose), so that `to_camera` of an object's point is that of the placed
/// point.
pub(crate) fn object_view(view: &LocalView, placement: &Placement) -> LocalView {
    let back = placement.rotation.transpose();
    LocalView {
        eye: back * (view.eye - placement.offset),
        right: back * view.right,
        up: back * view.up,
        forward: back * view.forward,
        ..*view
    }
}

#[cfg(test)]
mod tests;
