//! Watkins' scanline method, as the hidden-surface survey describes it: per row, each
//! polygon's intersection with the scan plane is a segment; the segment ends cut the row into
//! zones, and each zone takes the id of its nearest segment, with depth compared at the zone's
//! end (where two segments touch there, at its middle). Where the nearest segment differs
//! between a zone's two ends, the segments cross in depth (the polygons interpenetrate): the
//! zone is cut at the crossing and each part resolved alike, down to single pixels.
//!
//! The segments are the fill's spans: each polygon's edges are the fill's own walks
//! ([`EdgeWalk`]), entering an active edge list at the polygon's first row (a list per row,
//! as in the scanline z-buffer). Depth is `1/z`, linear along a row under perspective, taken
//! from each polygon's plane ([`inverse_depth_plane`]), so comparing it at pixel centres is
//! exact up to rounding, and a zone whose two ends agree has one nearest segment throughout.

use peel_runtime::camera::LocalView;
use peel_runtime::display::{Colour, SpanSink};
use peel_runtime::fill::{Coord, EdgeWalk};

use super::frame::{bytes, Frame, IdSink, Peak};
use super::prepare::{held_bytes, inverse_depth_plane, Prepared};

/// "No polygon" in a row list.
const NONE: u32 = u32::MAX;
/// An event that ends a segment (the other events start one).
const END: u32 = 1 << 31;
/// Most crossings of one polygon on a row: one per edge of a clipped triangle.
const MAX_CROSSINGS: usize = 16;

/// A polygon of the table: its triangle, `1/z` plane and the next polygon starting on the same
/// row.
#[derive(Debug, Clone, Copy)]
struct Polygon {
    triangle: u32,
    plane: [f64; 3],
    next: u32,
}

/// An edge in the active edge list: the fill's walk and its polygon.
#[derive(Debug, Clone, Copy)]
struct ActiveEdge {
    walk: EdgeWalk,
    polygon: u32,
}

/// A polygon's span on the current row, `[x0, x1)`, with its depth along the row,
/// `1/z = slope x + offset`.
#[derive(Debug, Clone, Copy)]
struct Segment {
    x0: u32,
    x1: u32,
    polygon: u32,
    slope: f64,
    offset: f64,
}

impl Segment {
    fn depth(&self, x: f64) -> f64 {
        self.slope * x + self.offset
    }
}

/// The first row whose centre is at or below the fixed-point `y >= 0` (the fill's rule).
fn first_row<const SUB: u32>(y: i32) -> i64 {
    let s = 1i64 << SUB;
    (2 * i64::from(y) + s - 1) >> (SUB + 1)
}

/// The peaks of the lists a frame used.
#[derive(Debug, Default)]
struct Peaks {
    active: Peak,
    segments: Peak,
    covering: Peak,
}

/// Draw `tris` into `ids` (`view.width` x `view.height`). Its memory: the clipped triangles,
/// the polygon table with a list head per row, and at their peaks the active edges, one row's
/// segments, their start and end events, and the segments covering the current zone.
pub fn draw<const SUB: u32>(tris: &[Prepared<SUB>], view: &LocalView, ids: &mut [u32]) -> Frame {
    let (width, height) = (view.width, view.height);
    let mut heads = vec![NONE; height as usize];
    let mut polygons: Vec<Polygon> = Vec::with_capacity(tris.len());
    for (k, t) in tris.iter().enumerate() {
        let Some(plane) = inverse_depth_plane(t.camera(), view) else {
            continue;
        };
        let (lo, hi) = t.screen().iter().fold((i32::MAX, i32::MIN), |(lo, hi), p| {
            (lo.min(p.y), hi.max(p.y))
        });
        let (first, end) = (first_row::<SUB>(lo), first_row::<SUB>(hi));
        if first >= end.min(i64::from(height)) {
            continue; // crosses no row centre
        }
        let head = &mut heads[first as usize];
        polygons.push(Polygon {
            triangle: k as u32,
            plane,
            next: *head,
        });
        *head = (polygons.len() - 1) as u32;
    }

    let mut sink = IdSink::cleared(ids, width);
    let mut active: Vec<ActiveEdge> = Vec::new();
    let mut segments: Vec<Segment> = Vec::new();
    let mut events: Vec<(u32, u32)> = Vec::new();
    let mut covering: Vec<u32> = Vec::new();
    let mut position: Vec<u32> = Vec::new();
    let mut peaks = Peaks::default();
    for y in 0..height {
        let row = y as Coord;
        let yc = f64::from(y) + 0.5;
        // The polygons starting on this row bring their edges.
        let mut p = heads[y as usize];
        while p != NONE {
            let polygon = &polygons[p as usize];
            let points = tris[polygon.triangle as usize].screen();
            for (i, &a) in points.iter().enumerate() {
                let b = points[(i + 1) % points.len()];
                if let Some(walk) = EdgeWalk::new::<SUB>(a, b, height) {
                    active.push(ActiveEdge { walk, polygon: p });
                }
            }
            p = polygon.next;
        }
        peaks.active.note(active.len());

        // Each active polygon's crossings (its edges are consecutive), paired into segments.
        segments.clear();
        let mut i = 0;
        while i < active.len() {
            let polygon = active[i].polygon;
            let mut xs = [0 as Coord; MAX_CROSSINGS];
            let mut n = 0;
            while i < active.len() && active[i].polygon == polygon {
                if active[i].walk.row() == row && n < MAX_CROSSINGS {
                    xs[n] = active[i].walk.x();
                    n += 1;
                }
                i += 1;
            }
            let xs = &mut xs[..n];
            xs.sort_unstable();
            let [a, b, c] = polygons[polygon as usize].plane;
            for pair in xs.chunks_exact(2) {
                let clamp = |x: Coord| x.clamp(0, Coord::from(width)) as u32;
                let (x0, x1) = (clamp(pair[0]), clamp(pair[1]));
                if x0 < x1 {
                    segments.push(Segment {
                        x0,
                        x1,
                        polygon,
                        slope: a,
                        offset: b * yc + c,
                    });
                }
            }
        }
        peaks.segments.note(segments.len());

        // The zones between consecutive segment ends, left to right.
        events.clear();
        for (k, s) in segments.iter().enumerate() {
            events.push((s.x0, k as u32));
            events.push((s.x1, k as u32 | END));
        }
        events.sort_unstable_by_key(|e| e.0);
        position.resize(segments.len(), 0);
        covering.clear();
        let mut out = Spans {
            sink: &mut sink,
            y,
            pending: None,
        };
        let mut previous = 0;
        let mut k = 0;
        while k < events.len() {
            let x = events[k].0;
            if x > previous && !covering.is_empty() {
                let zone = Zone {
                    segments: &segments,
                    covering: &covering,
                };
                zone.resolve(previous, x, &polygons, tris, &mut out);
            }
            while let Some(&(_, e)) = events.get(k).filter(|e| e.0 == x) {
                let s = (e & !END) as usize;
                if e & END == 0 {
                    position[s] = covering.len() as u32;
                    covering.push(s as u32);
                } else {
                    let at = position[s] as usize;
                    covering.swap_remove(at);
                    if let Some(&moved) = covering.get(at) {
                        position[moved as usize] = at as u32;
                    }
                }
                peaks.covering.note(covering.len());
                k += 1;
            }
            previous = x;
        }
        out.flush();

        // Step the edges on this row; drop the finished ones, keeping the order.
        active.retain_mut(|e| {
            if e.walk.row() != row {
                return true;
            }
            if e.walk.row_end() <= row + 1 {
                return false;
            }
            e.walk.step();
            true
        });
    }
    let memory_bytes = held_bytes(tris)
        + bytes::<Polygon>(polygons.len())
        + bytes::<u32>(heads.len())
        + bytes::<ActiveEdge>(peaks.active.0)
        + bytes::<Segment>(peaks.segments.0)
        + bytes::<(u32, u32)>(2 * peaks.segments.0)
        + bytes::<u32>(peaks.segments.0 + peaks.covering.0);
    Frame {
        written: sink.written,
        memory_bytes,
    }
}

/// The segments covering one zone of a row.
struct Zone<'z> {
    segments: &'z [Segment],
    covering: &'z [u32],
}

impl Zone<'_> {
    /// The nearest segment at the pixel centre `x`; two that touch there (equal depth, up to
    /// rounding) are compared at `middle` instead.
    fn nearest(&self, x: f64, middle: f64) -> &Segment {
        let mut best = &self.segments[self.covering[0] as usize];
        for &k in &self.covering[1..] {
            let s = &self.segments[k as usize];
            let (ds, db) = (s.depth(x), best.depth(x));
            let touch = 1e-9 * ds.abs().max(db.abs());
            if ds > db + touch || (ds >= db - touch && s.depth(middle) > best.depth(middle)) {
                best = s;
            }
        }
        best
    }

    /// Give the pixels `[a, b)` of the zone their nearest segment: the one nearest at both
    /// ends, or else each side of the two ends' segments' crossing, resolved alike.
    fn resolve<const SUB: u32>(
        &self,
        a: u32,
        b: u32,
        polygons: &[Polygon],
        tris: &[Prepared<SUB>],
        out: &mut Spans<'_, '_>,
    ) {
        let middle = (f64::from(a) + f64::from(b)) / 2.0;
        let left = self.nearest(f64::from(a) + 0.5, middle);
        let right = self.nearest(f64::from(b) - 0.5, middle);
        if left.polygon == right.polygon || b - a == 1 {
            let id = tris[polygons[left.polygon as usize].triangle as usize].id;
            out.push(a, b, id);
            return;
        }
        // The first pixel whose centre is at or right of the crossing, strictly inside.
        let crossing = (right.offset - left.offset) / (left.slope - right.slope);
        let m = if crossing.is_finite() {
            ((crossing - 0.5).ceil() as i64).clamp(i64::from(a) + 1, i64::from(b) - 1) as u32
        } else {
            a + (b - a) / 2
        };
        self.resolve(a, m, polygons, tris, out);
        self.resolve(m, b, polygons, tris, out);
    }
}

/// A row's spans into the id image, neighbours of the same id merged.
struct Spans<'s, 'a> {
    sink: &'s mut IdSink<'a>,
    y: u32,
    pending: Option<(u32, u32, u32)>,
}

impl Spans<'_, '_> {
    fn push(&mut self, x0: u32, x1: u32, id: u32) {
        match &mut self.pending {
            Some((_, end, pending)) if *end == x0 && *pending == id => *end = x1,
            _ => {
                self.flush();
                self.pending = Some((x0, x1, id));
            }
        }
    }

    fn flush(&mut self) {
        if let Some((x0, x1, id)) = self.pending.take() {
            self.sink.id = id;
            self.sink.span(self.y, x0, x1, Colour::default());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing;
    use super::*;

    /// Two overlapping squares, a square behind a larger nearer one, and two squares crossing
    /// in depth (their shared zones are cut at the crossing), in both orders: the reference's
    /// pixels, the nearer square in front.
    #[test]
    fn hand_made_scenes() {
        testing::check_hand_made_scenes(&draw::<8>);
    }
}
