//! Warnock's area subdivision, as the hidden-surface survey describes it: a window (a
//! rectangle of pixels) with no polygon, with one polygon, or covered by one polygon nearer
//! than all others is filled directly; any other window is subdivided, into its quadrants or,
//! in the later variant, at the smallest rectangle enclosing a polygon ([`Split`]). Polygons
//! are classified against a window as disjoint, intersecting or contained, or surrounding, and
//! those behind the farthest depth of a surrounding polygon are eliminated. A window of one
//! pixel takes the polygon nearest at its centre.
//!
//! Everything is decided at pixel centres, with the fill's rule: a polygon surrounds a window
//! when it covers the centres of its corners (and so, being convex, every centre in it), is
//! disjoint when its pixel box misses the window or one of its edges has every centre outside,
//! and a polygon alone in a window is drawn by the runtime's fill restricted to the window.
//! Depth is `1/z`, linear on screen under perspective ([`inverse_depth_plane`]): over a window
//! it ranges between its values at the corner centres, so the elimination is exact up to
//! rounding.

use peel_runtime::camera::LocalView;
use peel_runtime::display::{Colour, SpanSink};
use peel_runtime::fill::{fill_polygon_rows, sample_rect, FixedPoint};

use super::frame::{bytes, Frame, IdSink, Peak};
use super::prepare::{held_bytes, inverse_depth_plane, Prepared};

/// How a window that is not simple is subdivided.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Split {
    /// Into its four quadrants (Warnock's original rule).
    Quadrants,
    /// At the pixel box of the window's nearest polygon whose box is smaller than the window:
    /// the box and the up to four rectangles around it (quadrants when there is none).
    Enclosing,
}

/// A polygon index in a window's list, flagged when it surrounds the window (and so every
/// window inside it).
const SURROUNDS: u32 = 1 << 31;

/// A polygon of the frame: its points, id, `1/z` plane, pixel box, whether it is convex, and
/// its nearest `1/z` (at a vertex).
struct Polygon<'p, const SUB: u32> {
    points: &'p [FixedPoint<SUB>],
    id: u32,
    plane: [f64; 3],
    rect: [u32; 4],
    /// Orientation sign (`1` or `-1`) when convex; `0` when not (snapping can bend a clipped
    /// polygon), which is then only ever tested by its box and at single pixels.
    convex: i64,
    nearest: f64,
}

impl<const SUB: u32> Polygon<'_, SUB> {
    fn depth(&self, x: f64, y: f64) -> f64 {
        let [a, b, c] = self.plane;
        a * x + b * y + c
    }

    /// Whether the fill covers the centre of pixel `(i, j)`: an odd number of the edges that
    /// cross its row (by the fill's half-open rule) cross it at or left of the centre, in
    /// exact integers (doubled coordinates put the centre on the grid).
    fn covers(&self, i: u32, j: u32) -> bool {
        let s = 1i64 << SUB;
        let (xc, yc) = ((2 * i64::from(i) + 1) * s, (2 * i64::from(j) + 1) * s);
        let mut inside = false;
        for (k, a) in self.points.iter().enumerate() {
            let b = self.points[(k + 1) % self.points.len()];
            let (top, bottom) = if a.y < b.y { (*a, b) } else { (b, *a) };
            let (ty, by) = (2 * i64::from(top.y), 2 * i64::from(bottom.y));
            if ty == by || yc < ty || yc >= by {
                continue;
            }
            let (dx, dy) = (
                i64::from(bottom.x) - i64::from(top.x),
                i64::from(bottom.y) - i64::from(top.y),
            );
            if dx * (yc - ty) <= (xc - 2 * i64::from(top.x)) * dy {
                inside = !inside;
            }
        }
        inside
    }

    /// The centres of the window's corners, doubled fixed point.
    fn corners(rect: [u32; 4]) -> [(i64, i64); 4] {
        let s = 1i64 << SUB;
        let c = |v: u32| (2 * i64::from(v) + 1) * s;
        let [x0, y0, x1, y1] = rect;
        let (l, t, r, b) = (c(x0), c(y0), c(x1 - 1), c(y1 - 1));
        [(l, t), (r, t), (l, b), (r, b)]
    }

    /// One of the (convex) polygon's edges has every centre of the window strictly outside.
    fn separated(&self, rect: [u32; 4]) -> bool {
        let corners = Self::corners(rect);
        self.points.iter().enumerate().any(|(k, a)| {
            let b = self.points[(k + 1) % self.points.len()];
            let (ax, ay) = (2 * i64::from(a.x), 2 * i64::from(a.y));
            let (ex, ey) = (2 * i64::from(b.x) - ax, 2 * i64::from(b.y) - ay);
            corners
                .iter()
                .all(|&(x, y)| self.convex * (ex * (y - ay) - ey * (x - ax)) < 0)
        })
    }
}

fn overlaps(a: [u32; 4], b: [u32; 4]) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

/// A window waiting to be drawn: its rectangle, its parent's list in the arena, and the
/// arena's length when it was pushed (what lies above belongs to finished siblings).
#[derive(Debug, Clone, Copy)]
struct Task {
    rect: [u32; 4],
    parent: (u32, u32),
    top: u32,
}

/// The spans of a polygon within a window's columns.
struct ClipSink<'s, 'a> {
    sink: &'s mut IdSink<'a>,
    x0: u32,
    x1: u32,
}

impl SpanSink for ClipSink<'_, '_> {
    fn span(&mut self, y: u32, x0: u32, x1: u32, colour: Colour) {
        let (a, b) = (x0.max(self.x0), x1.min(self.x1));
        if a < b {
            self.sink.span(y, a, b, colour);
        }
    }
}

/// Draw `tris` into `ids` (`view.width` x `view.height`), subdividing by `split`. Its memory:
/// the clipped triangles, the polygon table, and at their peaks the windows waiting and the
/// arena of their polygon lists (an index each, and a depth while a list is built).
pub fn draw<const SUB: u32>(
    tris: &[Prepared<SUB>],
    view: &LocalView,
    ids: &mut [u32],
    split: Split,
) -> Frame {
    let (width, height) = (view.width, view.height);
    let scale = 1.0 / f64::from(1u32 << SUB);
    let polygons: Vec<Polygon<'_, SUB>> = tris
        .iter()
        .filter_map(|t| {
            let plane = inverse_depth_plane(t.camera(), view)?;
            let points = t.screen();
            let rect = sample_rect(points, width, height)?;
            let turns: Vec<i64> = (0..points.len())
                .map(|k| {
                    let (a, b, c) = (
                        points[k],
                        points[(k + 1) % points.len()],
                        points[(k + 2) % points.len()],
                    );
                    let (ux, uy) = (i64::from(b.x - a.x), i64::from(b.y - a.y));
                    let (vx, vy) = (i64::from(c.x - b.x), i64::from(c.y - b.y));
                    ux * vy - uy * vx
                })
                .collect();
            let convex = if turns.iter().all(|&t| t >= 0) {
                1
            } else if turns.iter().all(|&t| t <= 0) {
                -1
            } else {
                0
            };
            if turns.iter().all(|&t| t == 0) {
                return None; // no area: the fill draws nothing
            }
            let nearest = points
                .iter()
                .map(|p| {
                    let [a, b, c] = plane;
                    a * f64::from(p.x) * scale + b * f64::from(p.y) * scale + c
                })
                .fold(f64::NEG_INFINITY, f64::max);
            Some(Polygon {
                points,
                id: t.id,
                plane,
                rect,
                convex,
                nearest,
            })
        })
        .collect();

    let mut sink = IdSink::cleared(ids, width);
    let mut arena: Vec<u32> = (0..polygons.len() as u32).collect();
    let mut depths: Vec<f64> = Vec::new();
    let mut tasks = vec![Task {
        rect: [0, 0, width, height],
        parent: (0, arena.len() as u32),
        top: arena.len() as u32,
    }];
    let (mut peak_arena, mut peak_depths, mut peak_tasks) = (Peak(arena.len()), Peak(0), Peak(1));
    while let Some(task) = tasks.pop() {
        arena.truncate(task.top as usize);
        let rect = task.rect;
        let [x0, y0, x1, y1] = rect;
        let (l, t, r, b) = (
            f64::from(x0) + 0.5,
            f64::from(y0) + 0.5,
            f64::from(x1) - 0.5,
            f64::from(y1) - 0.5,
        );
        // Classify the parent's polygons; note the nearest depth each can have in the window
        // and the farthest depth of the nearest surrounding polygon.
        let start = arena.len();
        depths.clear();
        let mut farthest = f64::NEG_INFINITY;
        for k in task.parent.0..task.parent.1 {
            let entry = arena[k as usize];
            let p = &polygons[(entry & !SURROUNDS) as usize];
            let surrounds = if entry & SURROUNDS != 0 {
                true
            } else {
                if !overlaps(p.rect, rect) || (p.convex != 0 && p.separated(rect)) {
                    continue;
                }
                p.convex != 0
                    && p.covers(x0, y0)
                    && p.covers(x1 - 1, y0)
                    && p.covers(x0, y1 - 1)
                    && p.covers(x1 - 1, y1 - 1)
            };
            let d = [p.depth(l, t), p.depth(r, t), p.depth(l, b), p.depth(r, b)];
            let (lo, hi) = d
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            if surrounds {
                farthest = farthest.max(lo);
                depths.push(hi);
            } else {
                depths.push(hi.min(p.nearest));
            }
            arena.push(entry | if surrounds { SURROUNDS } else { 0 });
        }
        peak_depths.note(depths.len());
        // Eliminate the polygons behind the nearest surrounding polygon's farthest depth.
        let mut end = start;
        for k in start..arena.len() {
            if depths[k - start] >= farthest {
                arena[end] = arena[k];
                end += 1;
            }
        }
        arena.truncate(end);
        peak_arena.note(arena.len());
        let list = &arena[start..end];
        match list {
            [] => {}
            [one] if one & SURROUNDS != 0 => {
                sink.id = polygons[(one & !SURROUNDS) as usize].id;
                for y in y0..y1 {
                    sink.span(y, x0, x1, Colour::default());
                }
            }
            [one] => {
                let p = &polygons[*one as usize];
                sink.id = p.id;
                let mut clip = ClipSink {
                    sink: &mut sink,
                    x0,
                    x1,
                };
                let _ = fill_polygon_rows(p.points, width, y0..y1, Colour::default(), &mut clip);
            }
            _ if x1 - x0 == 1 && y1 - y0 == 1 => {
                let nearest = list
                    .iter()
                    .map(|&e| (e, &polygons[(e & !SURROUNDS) as usize]))
                    .filter(|(e, p)| e & SURROUNDS != 0 || p.covers(x0, y0))
                    .map(|(_, p)| p)
                    .max_by(|p, q| p.depth(l, t).total_cmp(&q.depth(l, t)));
                if let Some(p) = nearest {
                    sink.id = p.id;
                    sink.span(y0, x0, x1, Colour::default());
                }
            }
            _ => {
                let parent = (start as u32, end as u32);
                let top = end as u32;
                let box_of = |e: u32| polygons[(e & !SURROUNDS) as usize].rect;
                let enclosing = match split {
                    Split::Quadrants => None,
                    Split::Enclosing => list
                        .iter()
                        .filter(|&&e| e & SURROUNDS == 0)
                        .map(|&e| {
                            let [a, b, c, d] = box_of(e);
                            (e, [a.max(x0), b.max(y0), c.min(x1), d.min(y1)])
                        })
                        .filter(|&(_, inner)| inner != rect)
                        .max_by(|(e, _), (f, _)| {
                            let near = |e: u32| polygons[(e & !SURROUNDS) as usize].nearest;
                            near(*e).total_cmp(&near(*f))
                        })
                        .map(|(_, inner)| inner),
                };
                let children = match enclosing {
                    Some([a, b, c, d]) => [
                        [a, b, c, d],
                        [x0, y0, x1, b],
                        [x0, d, x1, y1],
                        [x0, b, a, d],
                        [c, b, x1, d],
                    ],
                    None => {
                        let (mx, my) = (x0 + (x1 - x0) / 2, y0 + (y1 - y0) / 2);
                        [
                            [x0, y0, mx, my],
                            [mx, y0, x1, my],
                            [x0, my, mx, y1],
                            [mx, my, x1, y1],
                            [0; 4],
                        ]
                    }
                };
                for child in children {
                    if child[0] < child[2] && child[1] < child[3] {
                        tasks.push(Task {
                            rect: child,
                            parent,
                            top,
                        });
                    }
                }
                peak_tasks.note(tasks.len());
            }
        }
    }
    let memory_bytes = held_bytes(tris)
        + bytes::<Polygon<'_, SUB>>(polygons.len())
        + bytes::<u32>(peak_arena.0)
        + bytes::<f64>(peak_depths.0)
        + bytes::<Task>(peak_tasks.0);
    Frame {
        written: sink.written,
        memory_bytes,
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing;
    use super::*;

    /// Two overlapping squares, a square behind a larger nearer one, and two squares crossing
    /// in depth (they surround the windows along their crossing without either being
    /// eliminated, so those are subdivided down to pixels), in both orders and both
    /// subdivisions: the reference's pixels, the nearer square in front.
    #[test]
    fn hand_made_scenes() {
        for split in [Split::Quadrants, Split::Enclosing] {
            testing::check_hand_made_scenes(&|t, v, i| draw::<8>(t, v, i, split));
        }
    }
}
