//! Newell, Newell and Sancha's depth-sort painter without the splitting step: sort by
//! farthest depth, then reorder pairs whose depth ranges overlap unless one of the classic
//! tests proves the order right; a pair already swapped once is left as it is (a cycle, which
//! only splitting could resolve, stays wrong — that is the baseline's error).

use glam::Vec3;
use peel_runtime::camera::LocalView;
use peel_runtime::display::Colour;
use peel_runtime::fill::fill_polygon;

use super::frame::{bytes, Frame, IdSink};
use super::prepare::{held_bytes, Prepared};

struct Item<'p, const SUB: u32> {
    t: &'p Prepared<SUB>,
    zmin: f32,
    zmax: f32,
    lo: (i32, i32),
    hi: (i32, i32),
    normal: Vec3,
    d: f32,
}

impl<'p, const SUB: u32> Item<'p, SUB> {
    fn new(t: &'p Prepared<SUB>) -> Self {
        let zmin = t.camera().iter().map(|p| p.z).fold(f32::INFINITY, f32::min);
        let zmax = t
            .camera()
            .iter()
            .map(|p| p.z)
            .fold(f32::NEG_INFINITY, f32::max);
        let lo = t
            .screen()
            .iter()
            .fold((i32::MAX, i32::MAX), |a, p| (a.0.min(p.x), a.1.min(p.y)));
        let hi = t
            .screen()
            .iter()
            .fold((i32::MIN, i32::MIN), |a, p| (a.0.max(p.x), a.1.max(p.y)));
        let p0 = t.camera()[0];
        let normal = (t.camera()[1] - p0).cross(t.camera()[2] - p0);
        Item {
            t,
            zmin,
            zmax,
            lo,
            hi,
            normal,
            d: normal.dot(p0),
        }
    }

    /// Every vertex of `other` on the side of this plane given by `sign` (the eye is at 0).
    fn all_on_side(&self, other: &Item<'_, SUB>, eye_side: bool) -> bool {
        let eye = -self.d; // plane value at the eye (origin)
        other.t.camera().iter().all(|p| {
            let v = self.normal.dot(*p) - self.d;
            if eye_side {
                v * eye >= 0.0
            } else {
                v * eye <= 0.0
            }
        })
    }
}

/// `p` may be drawn before `q` (p is not in front of q), by Newell's tests.
fn may_precede<const SUB: u32>(p: &Item<'_, SUB>, q: &Item<'_, SUB>) -> bool {
    p.zmax <= q.zmin
        || p.hi.0 <= q.lo.0
        || q.hi.0 <= p.lo.0
        || p.hi.1 <= q.lo.1
        || q.hi.1 <= p.lo.1
        || q.all_on_side(p, false)
        || p.all_on_side(q, true)
}

/// Sort and paint. Its memory: the clipped triangles, each with its sort record in the queue
/// and then in the order, and a flag per triangle.
pub fn draw<const SUB: u32>(tris: &[Prepared<SUB>], view: &LocalView, ids: &mut [u32]) -> Frame {
    let mut items: Vec<Item<'_, SUB>> = tris.iter().map(Item::new).collect();
    // Farthest first.
    items.sort_by(|a, b| b.zmax.total_cmp(&a.zmax).then(a.t.id.cmp(&b.t.id)));
    let mut order: Vec<Item<'_, SUB>> = Vec::with_capacity(items.len());
    let mut moved = vec![false; tris.iter().map(|t| t.id as usize + 1).max().unwrap_or(0)];
    let mut queue: std::collections::VecDeque<Item<'_, SUB>> = items.into();
    let memory_bytes =
        held_bytes(tris) + bytes::<Item<'_, SUB>>(2 * tris.len()) + bytes::<bool>(moved.len());
    while let Some(p) = queue.pop_front() {
        // Find a q (overlapping p in depth) that must come before p.
        let mut swap_at = None;
        for (k, q) in queue.iter().enumerate() {
            if q.zmax <= p.zmin {
                break; // sorted by zmax: no later item overlaps p in depth
            }
            if !may_precede(&p, q) && !moved[q.t.id as usize] {
                swap_at = Some(k);
                break;
            }
        }
        match swap_at {
            Some(k) => {
                let q = queue.remove(k).expect("index in range");
                moved[q.t.id as usize] = true;
                queue.push_front(p);
                queue.push_front(q);
            }
            None => order.push(p),
        }
    }
    let mut sink = IdSink::cleared(ids, view.width);
    for item in &order {
        sink.id = item.t.id;
        let _ = fill_polygon(
            item.t.screen(),
            view.width,
            view.height,
            Colour::default(),
            &mut sink,
        );
    }
    Frame {
        written: sink.written,
        memory_bytes,
    }
}
