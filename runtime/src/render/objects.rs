//! A frame with objects, before its walk: the checks of its parts, each object's placement
//! and the frame's order ([`crate::place`]), and the cuts of a piece in camera space.

use glam::{Vec2, Vec3};

use super::Source;
use crate::camera::LocalView;
use crate::clip::{self, ClipPlane, Keep};
use crate::error::RenderError;
use crate::place::{self, Cut, Placement, Posed, Step, NO_CUT};
use crate::read::layout::MAX_PARTS;
use crate::traverse::Tree;

/// Most cuts a piece may have (each clips every polygon of the piece once more).
pub(super) const MAX_CUTS: usize = 32;

/// An unused entry of a piece's cuts.
pub(super) const NO_CLIP_CUT: clip::Cut = clip::Cut {
    plane: ClipPlane {
        normal: Vec3::ZERO,
        offset: 0.0,
    },
    keep: Keep::Both,
};

/// Whether every part holds ids, and the largest polygon of any; every part's depth checked
/// against the traversal stack's `stack` entries.
pub(super) fn parts_summary(
    posed: &Posed<'_, '_>,
    stack: usize,
) -> Result<(bool, u32), RenderError> {
    let mut ids = true;
    let mut largest = 0;
    let parts = posed
        .world
        .iter()
        .chain(posed.objects.iter().map(|o| &o.scene));
    for scene in parts {
        ids &= scene.has_ids();
        largest = largest.max(scene.max_polygon_vertices());
        let needed = scene.max_depth();
        if needed as usize > stack {
            return Err(RenderError::StackTooSmall {
                needed,
                available: u32::try_from(stack).unwrap_or(u32::MAX),
            });
        }
    }
    Ok((ids, largest))
}

/// The placements of `posed`'s objects and the frame's order for `view`, into `memory`;
/// the number of steps, and the most planes that cut one object. Refuses a frame whose pieces have more cuts than the clip buffers
/// (`available` vertices, polygons of up to `max_vertices`) can take.
pub(super) fn prepare(
    posed: &Posed<'_, '_>,
    view: &LocalView,
    max_vertices: u32,
    available: u32,
    memory: &mut place::Memory<'_>,
) -> Result<(usize, usize), RenderError> {
    let count = posed.objects.len();
    if memory.placements.len() < count || count > MAX_PARTS as usize {
        return Err(RenderError::ObjectMemory);
    }
    let centre = posed.centre();
    let mut scale = view.eye.abs().element_sum();
    if let Some(h) = posed.world.map(|w| w.header()) {
        scale = scale
            .max(h.bounds_min.abs().element_sum())
            .max(h.bounds_max.abs().element_sum());
    }
    // Each object's screen rectangle (`None`: it reaches behind the near plane).
    let mut rects = [None::<(Vec2, Vec2)>; MAX_PARTS as usize];
    for (k, (object, slot)) in posed
        .objects
        .iter()
        .zip(memory.placements.iter_mut())
        .enumerate()
    {
        let h = object.scene.header();
        *slot = match object.pose {
            None => Placement::HIDDEN,
            Some(pose) if !pose.is_finite() => {
                return Err(RenderError::BadPose { object: k as u32 });
            }
            Some(pose) => {
                let (rotation, offset) = place::placement(&pose, h.centre, centre);
                let (lo, hi) = object.bounds();
                Placement::new(rotation, offset, lo, hi)
            }
        };
        for c in &slot.corners {
            scale = scale.max(c.abs().element_sum());
        }
        if slot.visible {
            let local = place::object_view(view, slot);
            let (lo, hi) = object.bounds();
            let b = local.box_to_camera(lo, hi);
            rects[k] = local.box_on_screen(&b);
        }
    }
    let overlap = |a: u16, b: u16| match (rects[usize::from(a)], rects[usize::from(b)]) {
        (Some((a0, a1)), Some((b0, b1))) => {
            // A pixel of slack for rounding and snapping.
            a0.x <= b1.x + 1.0 && b0.x <= a1.x + 1.0 && a0.y <= b1.y + 1.0 && b0.y <= a1.y + 1.0
        }
        _ => true,
    };
    let side_eye = posed
        .world
        .map(|w| w.side_eye(view.eye))
        .unwrap_or_default();
    let world = posed.world.as_ref();
    let steps = place::plan(world, view.eye, &side_eye, count, scale, &overlap, memory)?;
    // Each object is cut by at most `MAX_CUTS` planes, each of which may add two vertices
    // to a polygon (its own pieces' a vertex, the others' a crossing each way).
    let planned = memory.steps.get(..steps).unwrap_or(&[]);
    let mut most = 0;
    for k in 0..count {
        let mut firsts = [u16::MAX; MAX_CUTS];
        let object = k as u16;
        let planes = object_planes(planned, &memory.cuts[..], object, &mut firsts).ok_or(
            RenderError::TooManyCuts {
                object: u32::from(object),
            },
        )?;
        most = most.max(planes);
    }
    let needed = clip::buffer_len_for(max_vertices).saturating_add(2 * most as u32);
    if needed > available {
        return Err(RenderError::PolygonTooLarge { needed, available });
    }
    Ok((steps, most))
}

/// The distinct planes that cut pieces of `object` in `steps`, each as the index of the first
/// cut made by it, in that order, into `firsts`; how many, or `None` past [`MAX_CUTS`].
fn object_planes(
    steps: &[Step],
    cuts: &[Cut],
    object: u16,
    firsts: &mut [u16; MAX_CUTS],
) -> Option<usize> {
    let mut count = 0;
    for step in steps {
        let Step::Piece {
            object: o,
            cut: mut at,
        } = *step
        else {
            continue;
        };
        if o != object {
            continue;
        }
        let mut guard = 0;
        while let Some(c) = cuts.get(usize::from(at)).filter(|_| at != NO_CUT) {
            let known = firsts[..count]
                .iter()
                .position(|&f| cuts.get(usize::from(f)).is_some_and(|k| k.plane == c.plane));
            match known {
                Some(k) if firsts[k] > at => firsts[k] = at,
                Some(_) => {}
                None => {
                    *firsts.get_mut(count)? = at;
                    count += 1;
                }
            }
            guard += 1;
            if guard > cuts.len() {
                break;
            }
            at = c.prev;
        }
    }
    firsts[..count].sort_unstable();
    Some(count)
}

/// The cuts of a piece of `object` in camera space (`view`: the world's), into `out`: every
/// distinct plane that cuts any piece of the object in this frame's `steps`, in the order the
/// plan first cut by it, each keeping the side the piece's own chain (ending at `cut`) keeps,
/// or both. How many. A world plane `n · p = d` is `(n · right, n · up, n · forward) · c +
/// (n · eye - d)` for the camera point `c`: the same values for every piece it cuts.
pub(super) fn camera_cuts(
    steps: &[Step],
    cuts: &[Cut],
    object: u16,
    cut: u16,
    view: &LocalView,
    out: &mut [clip::Cut; MAX_CUTS],
) -> usize {
    let mut firsts = [u16::MAX; MAX_CUTS];
    let count = object_planes(steps, cuts, object, &mut firsts).unwrap_or(0);
    for (slot, &first) in out.iter_mut().zip(&firsts[..count]) {
        let Some(c) = cuts.get(usize::from(first)) else {
            continue;
        };
        // The side this piece keeps, if its chain cuts by this plane.
        let mut keep = Keep::Both;
        let mut at = cut;
        let mut guard = 0;
        while let Some(k) = cuts.get(usize::from(at)).filter(|_| at != NO_CUT) {
            if k.plane == c.plane {
                keep = if k.keep_plus { Keep::Plus } else { Keep::Minus };
                break;
            }
            guard += 1;
            if guard > cuts.len() {
                break;
            }
            at = k.prev;
        }
        let normal = c.plane.normal;
        *slot = clip::Cut {
            plane: ClipPlane {
                normal: Vec3::new(
                    normal.dot(view.right),
                    normal.dot(view.up),
                    normal.dot(view.forward),
                ),
                offset: normal.dot(view.eye) - c.plane.d,
            },
            keep,
        };
    }
    count
}
