//! Weiler and Atherton's polygonal windows, as the hidden-surface survey describes them: take
//! the nearest polygon (by its nearest depth) as the window, clip every other polygon against
//! its projection into an inside and an outside list, and test the inside list against the
//! window's depth: what lies behind it is hidden and dropped; a polygon nearer somewhere
//! becomes the new window over the old window's region (recursively); otherwise the window is
//! drawn, and the outside list goes on.
//!
//! Every polygon here is convex (a clipped triangle, or a piece of one), so clipping against
//! a window is a cut by each of its edge lines in turn: the part beyond an edge is an outside
//! piece, what remains after the last edge the inside piece. A cut's new vertices are rounded
//! to the fill's grid once and shared by both parts, which the runtime's fill then draws
//! without gap or overlap between them; a drawn window is never drawn over, so each pixel is
//! written once. Depth is `1/z`, linear on screen under perspective ([`inverse_depth_plane`]),
//! so a piece lies behind the window exactly when it does at each of its vertices; a piece
//! nearer at some vertices and farther at others crosses the window (they interpenetrate) and
//! is cut along the screen line where their depths are equal, its far part dropped. A
//! remaining pool is kept in a grid of screen tiles and a heap by nearest depth, so that a
//! window only meets the pieces near it.

use std::collections::BinaryHeap;
use std::ops::RangeInclusive;

use peel_runtime::camera::LocalView;
use peel_runtime::display::Colour;
use peel_runtime::fill::{fill_polygon, sample_rect, FixedPoint};

use super::frame::{bytes, Frame, IdSink, Peak};
use super::prepare::{inverse_depth_plane, Prepared};

/// Most vertices of a piece; a larger one is cut in two along a diagonal.
const CAP: usize = 12;
/// Room while a piece is cut by a window's edges (each cut adds at most one vertex).
const ROOM: usize = 2 * CAP + 8;
/// Nested windows beyond this draw the window as it is (only rounding can cause it).
const MAX_NESTING: u32 = 32;
/// Side of the pool's screen tiles, in pixels.
const TILE: u32 = 8;
/// A point closer than this to a line (in units of the fill's grid) lies on it: `f64`
/// rounding is some `1e-11` there, a real vertex off the line much farther.
const ON_LINE: f64 = 1e-6;

/// A clipped source triangle: its id and `1/z` plane.
#[derive(Debug, Clone, Copy)]
struct Source {
    id: u32,
    plane: [f64; 3],
}

/// A point in units of the fill's grid (`2^-SUB` pixel), kept in `f64` while pieces are cut
/// and rounded to the grid only when a window is filled: every cut is then exact up to `f64`
/// rounding, so a piece cut along a line that is not a source edge (a diagonal, a crossing)
/// leaves no sliver beside it, and both parts of a cut share the same points, which round
/// alike.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Point {
    x: f64,
    y: f64,
}

impl Point {
    fn of<const SUB: u32>(p: FixedPoint<SUB>) -> Point {
        Point {
            x: f64::from(p.x),
            y: f64::from(p.y),
        }
    }

    fn grid<const SUB: u32>(self) -> FixedPoint<SUB> {
        FixedPoint::new(self.x.round() as i32, self.y.round() as i32)
    }

    /// `(a - self) x (b - self)`.
    fn turn(self, a: Point, b: Point) -> f64 {
        (a.x - self.x) * (b.y - self.y) - (a.y - self.y) * (b.x - self.x)
    }
}

/// A convex piece of a source polygon, with its pixel box and nearest `1/z` (at a vertex).
#[derive(Debug, Clone, Copy)]
struct Piece {
    source: u32,
    len: u8,
    rect: [u32; 4],
    nearest: f64,
    points: [Point; CAP],
}

impl Piece {
    fn points(&self) -> &[Point] {
        &self.points[..usize::from(self.len)]
    }
}

/// Points while a piece is cut.
#[derive(Debug, Clone, Copy)]
struct Points {
    len: usize,
    points: [Point; ROOM],
}

impl Points {
    fn new() -> Self {
        Points {
            len: 0,
            points: [Point::default(); ROOM],
        }
    }

    fn of(points: &[Point]) -> Self {
        let mut p = Self::new();
        for &q in points {
            p.push(q);
        }
        p
    }

    /// Adds `q` (dropped past [`ROOM`], which only a polygon bent by rounding could reach).
    fn push(&mut self, q: Point) {
        if let Some(slot) = self.points.get_mut(self.len) {
            *slot = q;
            self.len += 1;
        }
    }

    fn as_slice(&self) -> &[Point] {
        &self.points[..self.len]
    }
}

/// Cut `points` by a line given each point's signed `side` of it (0 on it): the parts on its
/// positive and its negative side. Points on the line go to both, and each crossing is
/// computed once and given to both.
fn cut(points: &[Point], side: &[f64], positive: &mut Points, negative: &mut Points) {
    *positive = Points::new();
    *negative = Points::new();
    for (i, (&p, &s)) in points.iter().zip(side).enumerate() {
        let j = (i + 1) % points.len();
        let (q, t) = (points[j], side[j]);
        if s >= 0.0 {
            positive.push(p);
        }
        if s <= 0.0 {
            negative.push(p);
        }
        if (s > 0.0 && t < 0.0) || (s < 0.0 && t > 0.0) {
            let f = s / (s - t);
            let x = Point {
                x: p.x + f * (q.x - p.x),
                y: p.y + f * (q.y - p.y),
            };
            positive.push(x);
            negative.push(x);
        }
    }
}

/// The convex hull of `points`, without points on its edges (empty when they are all on a
/// line): `f64` rounding can bend a piece by a hair, and a window must be convex for the
/// half-planes of its edges to be the window.
fn hull(points: &[Point]) -> Points {
    let mut sorted = [Point::default(); ROOM];
    let n = points.len().min(ROOM);
    sorted[..n].copy_from_slice(&points[..n]);
    let sorted = &mut sorted[..n];
    sorted.sort_unstable_by(|p, q| p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y)));
    // A turn within rounding of zero is no turn.
    let convex = |o: Point, a: Point, b: Point| {
        let (u, v) = ((a.x - o.x).hypot(a.y - o.y), (b.x - a.x).hypot(b.y - a.y));
        o.turn(a, b) > ON_LINE * (u + v)
    };
    // Andrew's monotone chain: the lower chain left to right, then the upper one back.
    let mut chain = [Point::default(); 2 * ROOM + 1];
    let mut k = 0;
    for &p in sorted.iter() {
        while k >= 2 && !convex(chain[k - 2], chain[k - 1], p) {
            k -= 1;
        }
        chain[k] = p;
        k += 1;
    }
    let lower = k + 1;
    for &p in sorted.iter().rev().skip(1) {
        while k >= lower && !convex(chain[k - 2], chain[k - 1], p) {
            k -= 1;
        }
        chain[k] = p;
        k += 1;
    }
    let k = k.saturating_sub(1); // the last point is the first
    if k < 3 {
        return Points::new();
    }
    Points::of(&chain[..k])
}

/// Twice the signed area of `points`.
fn area2(points: &[Point]) -> f64 {
    let mut a = 0.0;
    for (i, p) in points.iter().enumerate() {
        let q = points[(i + 1) % points.len()];
        a += p.x * q.y - q.x * p.y;
    }
    a
}

fn overlaps(a: [u32; 4], b: [u32; 4]) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

/// How an inside piece stands against its window.
enum Depth {
    /// Behind the window wherever it lies: hidden.
    Behind,
    /// Nearer than the window somewhere and never farther.
    Nearer,
    /// Nearer at some vertices, farther at others: the two cross along a screen line.
    Crossing,
}

/// The memory a frame used, at its peaks.
#[derive(Debug, Default)]
struct Usage {
    /// Pieces held outside the pool: nested windows' pools and their nearer pieces.
    held: usize,
    held_peak: Peak,
    /// One window's candidate handles.
    handles: Peak,
    /// One window's nearer pieces and one candidate's parts.
    parts: Peak,
    nesting: Peak,
}

/// What every window of a frame shares: the image, the sources, the memory figures.
struct Windows<'f, 'a, const SUB: u32> {
    sink: &'f mut IdSink<'a>,
    width: u32,
    height: u32,
    sources: &'f [Source],
    usage: Usage,
}

impl<const SUB: u32> Windows<'_, '_, SUB> {
    /// The `1/z` of `source` at the point `p`.
    fn depth(&self, source: u32, p: Point) -> f64 {
        let [a, b, c] = self.sources[source as usize].plane;
        let scale = 1.0 / f64::from(1u32 << SUB);
        (a * p.x + b * p.y) * scale + c
    }

    /// The pieces of the hull of `points` (of `source`) into `out`: none without area or pixel
    /// centre (it can neither show nor hide one), two or more when it has too many vertices.
    fn make(&self, source: u32, points: &[Point], out: &mut Vec<Piece>) {
        if points.len() < 3 {
            return;
        }
        let hull = hull(points);
        self.make_convex(source, hull.as_slice(), out);
    }

    /// [`Self::make`] of a convex polygon.
    fn make_convex(&self, source: u32, points: &[Point], out: &mut Vec<Piece>) {
        if points.len() < 3 {
            return;
        }
        if points.len() > CAP {
            let half = points.len() / 2;
            self.make_convex(source, &points[..=half], out);
            let mut rest = Points::of(&points[half..]);
            rest.push(points[0]);
            self.make_convex(source, rest.as_slice(), out);
            return;
        }
        let mut grid = [FixedPoint::<SUB>::default(); CAP];
        for (g, p) in grid.iter_mut().zip(points) {
            *g = p.grid();
        }
        let Some(rect) = sample_rect(&grid[..points.len()], self.width, self.height) else {
            return;
        };
        let mut piece = Piece {
            source,
            len: points.len() as u8,
            rect,
            nearest: f64::NEG_INFINITY,
            points: [Point::default(); CAP],
        };
        piece.points[..points.len()].copy_from_slice(points);
        piece.nearest = points
            .iter()
            .map(|&p| self.depth(source, p))
            .fold(f64::NEG_INFINITY, f64::max);
        out.push(piece);
    }

    /// Clip `piece` against `window` (orientation `turn`): `false` when they are disjoint,
    /// else its pieces inside and outside the window, added to `inside` and `outside`.
    fn clip(
        &self,
        piece: &Piece,
        window: &Piece,
        turn: f64,
        inside: &mut Vec<Piece>,
        outside: &mut Vec<Piece>,
    ) -> bool {
        let mut rest = Points::of(piece.points());
        let (mut positive, mut negative) = (Points::new(), Points::new());
        let mut side = [0.0; ROOM];
        let mut cut_any = false;
        let w = window.points();
        for (k, &a) in w.iter().enumerate() {
            let b = w[(k + 1) % w.len()];
            let tolerance = ON_LINE * (b.x - a.x).hypot(b.y - a.y);
            let points = rest.as_slice();
            let (mut any_in, mut any_out) = (false, false);
            for (s, &p) in side.iter_mut().zip(points) {
                let v = turn * a.turn(b, p);
                *s = if v.abs() <= tolerance { 0.0 } else { v };
                any_in |= *s > 0.0;
                any_out |= *s < 0.0;
            }
            if !any_out {
                continue;
            }
            if !any_in {
                // Wholly beyond this edge: disjoint, or the last outside piece.
                if !cut_any {
                    return false;
                }
                self.make(piece.source, points, outside);
                return true;
            }
            cut(points, &side[..points.len()], &mut positive, &mut negative);
            self.make(piece.source, negative.as_slice(), outside);
            rest = positive;
            cut_any = true;
        }
        if cut_any {
            self.make(piece.source, rest.as_slice(), inside);
        } else {
            inside.push(*piece);
        }
        true
    }

    /// How `piece` (inside `window`) stands against it in depth; fills `side` (per vertex,
    /// positive where the piece is nearer) for a crossing.
    fn compare(&self, piece: &Piece, window: &Piece, side: &mut [f64]) -> Depth {
        let (mut nearer, mut farther) = (false, false);
        for (s, &p) in side.iter_mut().zip(piece.points()) {
            let (dp, dw) = (self.depth(piece.source, p), self.depth(window.source, p));
            let tolerance = 1e-12 * dw.abs();
            *s = dp - dw;
            nearer |= *s > tolerance;
            farther |= *s < -tolerance;
        }
        match (nearer, farther) {
            (false, _) => Depth::Behind,
            (true, false) => Depth::Nearer,
            (true, true) => Depth::Crossing,
        }
    }

    fn fill(&mut self, piece: &Piece) {
        self.sink.id = self.sources[piece.source as usize].id;
        let mut grid = [FixedPoint::<SUB>::default(); CAP];
        for (g, p) in grid.iter_mut().zip(piece.points()) {
            *g = p.grid();
        }
        let _ = fill_polygon(
            &grid[..piece.points().len()],
            self.width,
            self.height,
            Colour::default(),
            self.sink,
        );
    }

    /// Draw the pieces of `pool`, the window `first` first (when given), at nesting `level`.
    fn draw_pool<P: Pool>(&mut self, pool: &mut P, first: Option<Piece>, level: u32) {
        self.usage.nesting.note(level as usize + 1);
        let mut next = first;
        let (mut handles, mut inside, mut outside, mut nearer) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut side = [0.0; CAP];
        while let Some(window) = next.take().or_else(|| pool.pop_nearest()) {
            let turn = area2(window.points()).signum();
            handles.clear();
            pool.overlapping(window.rect, &mut handles);
            nearer.clear();
            for &h in &handles {
                let piece = *pool.piece(h);
                inside.clear();
                outside.clear();
                if !self.clip(&piece, &window, turn, &mut inside, &mut outside) {
                    continue;
                }
                self.usage
                    .parts
                    .note(nearer.len() + inside.len() + outside.len());
                pool.remove(h);
                for o in outside.drain(..) {
                    pool.put(o, &mut self.usage);
                }
                for q in &inside {
                    match self.compare(q, &window, &mut side) {
                        Depth::Behind => {}
                        Depth::Nearer => nearer.push(*q),
                        Depth::Crossing => {
                            let (mut front, mut back) = (Points::new(), Points::new());
                            cut(q.points(), &side[..q.points().len()], &mut front, &mut back);
                            self.make(q.source, front.as_slice(), &mut nearer);
                        }
                    }
                }
            }
            self.usage.handles.note(handles.len());
            self.usage.held_peak.note(self.usage.held + nearer.len());
            if nearer.is_empty() || level >= MAX_NESTING {
                self.fill(&window);
                continue;
            }
            // The window's region holds nearer pieces: the nearest becomes the window there.
            let k = (0..nearer.len())
                .max_by(|&i, &j| nearer[i].nearest.total_cmp(&nearer[j].nearest))
                .unwrap_or(0);
            let q = nearer.swap_remove(k);
            let mut region = Local::default();
            for p in nearer.drain(..).chain(std::iter::once(window)) {
                region.put(p, &mut self.usage);
            }
            self.draw_pool(&mut region, Some(q), level + 1);
            self.usage.held -= region.items.len();
        }
    }
}

/// What a nesting level of windows holds besides its pieces: its lists and a side per vertex.
type Level = ([Vec<u32>; 4], [f64; CAP], Points);

/// The pieces still to draw.
trait Pool {
    /// Take out the piece with the nearest `1/z`.
    fn pop_nearest(&mut self) -> Option<Piece>;
    /// Handles of the pieces whose boxes overlap `rect`.
    fn overlapping(&mut self, rect: [u32; 4], out: &mut Vec<u32>);
    fn piece(&self, handle: u32) -> &Piece;
    fn remove(&mut self, handle: u32);
    fn put(&mut self, piece: Piece, usage: &mut Usage);
}

/// A nested window's pool: a few pieces, searched in full.
#[derive(Default)]
struct Local {
    items: Vec<Option<Piece>>,
}

impl Pool for Local {
    fn pop_nearest(&mut self) -> Option<Piece> {
        let k = (0..self.items.len())
            .filter(|&k| self.items[k].is_some())
            .max_by(|&i, &j| {
                let near = |k: usize| self.items[k].map_or(f64::NEG_INFINITY, |p| p.nearest);
                near(i).total_cmp(&near(j))
            })?;
        self.items[k].take()
    }

    fn overlapping(&mut self, rect: [u32; 4], out: &mut Vec<u32>) {
        for (k, p) in self.items.iter().enumerate() {
            if p.is_some_and(|p| overlaps(p.rect, rect)) {
                out.push(k as u32);
            }
        }
    }

    fn piece(&self, handle: u32) -> &Piece {
        self.items[handle as usize]
            .as_ref()
            .expect("a handle of a live piece")
    }

    fn remove(&mut self, handle: u32) {
        self.items[handle as usize] = None;
    }

    fn put(&mut self, piece: Piece, usage: &mut Usage) {
        self.items.push(Some(piece));
        usage.held += 1;
        usage.held_peak.note(usage.held);
    }
}

/// A slot of the frame's pool; its generation tells its current piece from earlier ones in
/// the heap and the tiles, which keep stale entries until they meet them.
#[derive(Debug, Clone, Copy)]
struct Slot {
    piece: Piece,
    generation: u32,
    alive: bool,
    stamp: u32,
}

/// The frame's pool: pieces in slots (reused), a heap by nearest depth, and per screen tile
/// the pieces whose boxes meet it.
struct Grid {
    slots: Vec<Slot>,
    free: Vec<u32>,
    heap: BinaryHeap<(u64, u32, u32)>,
    tiles: Vec<Vec<(u32, u32)>>,
    columns: u32,
    stamp: u32,
    entries: usize,
    heap_peak: Peak,
    entries_peak: Peak,
}

/// `v`'s bits, ordered as `v` is.
fn ordered(v: f64) -> u64 {
    let b = v.to_bits();
    if b >> 63 == 1 {
        !b
    } else {
        b | 1 << 63
    }
}

impl Grid {
    fn new(width: u32, height: u32) -> Self {
        let columns = width.div_ceil(TILE);
        Grid {
            slots: Vec::new(),
            free: Vec::new(),
            heap: BinaryHeap::new(),
            tiles: vec![Vec::new(); (columns * height.div_ceil(TILE)) as usize],
            columns,
            stamp: 0,
            entries: 0,
            heap_peak: Peak::default(),
            entries_peak: Peak::default(),
        }
    }

    /// The tiles `rect` meets: a range of columns and of rows.
    fn tiles_of(rect: [u32; 4]) -> (RangeInclusive<u32>, RangeInclusive<u32>) {
        let [x0, y0, x1, y1] = rect;
        (x0 / TILE..=(x1 - 1) / TILE, y0 / TILE..=(y1 - 1) / TILE)
    }

    fn memory_bytes(&self) -> u64 {
        bytes::<Slot>(self.slots.len())
            + bytes::<u32>(self.slots.len())
            + bytes::<(u64, u32, u32)>(self.heap_peak.0)
            + bytes::<Vec<(u32, u32)>>(self.tiles.len())
            + bytes::<(u32, u32)>(self.entries_peak.0)
    }
}

impl Pool for Grid {
    fn pop_nearest(&mut self) -> Option<Piece> {
        while let Some((_, s, generation)) = self.heap.pop() {
            let slot = &mut self.slots[s as usize];
            if slot.alive && slot.generation == generation {
                slot.alive = false;
                self.free.push(s);
                return Some(slot.piece);
            }
        }
        None
    }

    fn overlapping(&mut self, rect: [u32; 4], out: &mut Vec<u32>) {
        self.stamp = self.stamp.wrapping_add(1);
        let (columns, rows) = Self::tiles_of(rect);
        for t in rows.flat_map(|y| columns.clone().map(move |x| (x, y))) {
            let t = (t.1 * self.columns + t.0) as usize;
            let slots = &mut self.slots;
            let tile = &mut self.tiles[t];
            let before = tile.len();
            tile.retain(|&(s, g)| {
                let slot = &slots[s as usize];
                slot.alive && slot.generation == g
            });
            self.entries -= before - tile.len();
            for &(s, _) in tile.iter() {
                let slot = &mut slots[s as usize];
                if slot.stamp != self.stamp && overlaps(slot.piece.rect, rect) {
                    slot.stamp = self.stamp;
                    out.push(s);
                }
            }
        }
    }

    fn piece(&self, handle: u32) -> &Piece {
        &self.slots[handle as usize].piece
    }

    fn remove(&mut self, handle: u32) {
        self.slots[handle as usize].alive = false;
        self.free.push(handle);
    }

    fn put(&mut self, piece: Piece, _: &mut Usage) {
        let s = match self.free.pop() {
            Some(s) => s,
            None => {
                self.slots.push(Slot {
                    piece,
                    generation: 0,
                    alive: false,
                    stamp: 0,
                });
                (self.slots.len() - 1) as u32
            }
        };
        let slot = &mut self.slots[s as usize];
        slot.piece = piece;
        slot.generation = slot.generation.wrapping_add(1);
        slot.alive = true;
        let generation = slot.generation;
        self.heap.push((ordered(piece.nearest), s, generation));
        self.heap_peak.note(self.heap.len());
        let (columns, rows) = Self::tiles_of(piece.rect);
        for y in rows {
            for x in columns.clone() {
                self.tiles[(y * self.columns + x) as usize].push((s, generation));
                self.entries += 1;
            }
        }
        self.entries_peak.note(self.entries);
    }
}

/// Draw `tris` into `ids` (`view.width` x `view.height`). Its memory: the sources (id and
/// plane), and at their peaks the pool (its slots, heap and tiles), the pieces held by nested
/// windows, and one window's candidates and parts.
pub fn draw<const SUB: u32>(tris: &[Prepared<SUB>], view: &LocalView, ids: &mut [u32]) -> Frame {
    let (mut sources, mut polygons) = (Vec::new(), Vec::new());
    for t in tris {
        if let Some(plane) = inverse_depth_plane(t.camera(), view) {
            sources.push(Source { id: t.id, plane });
            polygons.push(t.screen());
        }
    }
    let mut sink = IdSink::cleared(ids, view.width);
    let mut frame = Windows::<SUB> {
        sink: &mut sink,
        width: view.width,
        height: view.height,
        sources: &sources,
        usage: Usage::default(),
    };
    // The pool takes the clipped triangles' points; their list goes.
    let mut grid = Grid::new(view.width, view.height);
    let mut pieces = Vec::new();
    for (s, points) in polygons.into_iter().enumerate() {
        let mut corners = Points::new();
        for &p in points {
            corners.push(Point::of(p));
        }
        frame.make(s as u32, corners.as_slice(), &mut pieces);
        for p in pieces.drain(..) {
            grid.put(p, &mut frame.usage);
        }
    }
    frame.draw_pool(&mut grid, None, 0);
    let usage = &frame.usage;
    let memory_bytes = bytes::<Source>(sources.len())
        + grid.memory_bytes()
        + bytes::<Option<Piece>>(usage.held_peak.0)
        + bytes::<u32>(usage.handles.0)
        + bytes::<Piece>(usage.parts.0)
        + bytes::<Level>(usage.nesting.0);
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
    /// in depth (the nearer part of the one that is not the first window is cut out along the
    /// crossing and drawn over its half), in both orders: the reference's pixels, the nearer
    /// square in front.
    #[test]
    fn hand_made_scenes() {
        testing::check_hand_made_scenes(&draw::<8>);
    }

    /// A cut shares its crossings between both parts, and the parts keep the piece's area.
    #[test]
    fn a_cut_shares_its_crossings() {
        let square =
            [(0.0, 0.0), (64.0, 0.0), (64.0, 64.0), (0.0, 64.0)].map(|(x, y)| Point { x, y });
        let side: Vec<f64> = square.iter().map(|p| p.x - 21.3).collect();
        let (mut left, mut right) = (Points::new(), Points::new());
        cut(&square, &side, &mut right, &mut left);
        assert_eq!((left.len, right.len), (4, 4));
        let on_line = |p: &Points| -> Vec<Point> {
            p.as_slice()
                .iter()
                .copied()
                .filter(|q| (q.x - 21.3).abs() < 1e-9)
                .collect()
        };
        let shared = on_line(&left);
        assert_eq!(shared.len(), 2);
        assert!(shared.iter().all(|p| on_line(&right).contains(p)));
        let total = area2(left.as_slice()) + area2(right.as_slice());
        assert!((total - area2(&square)).abs() < 1e-9);
    }

    /// The hull of a piece bent by rounding drops the bent vertex and the points on its edges.
    #[test]
    fn the_hull_straightens_a_bent_piece() {
        let bent = [
            (0.0, 0.0),
            (10.0, 0.0),
            (20.0, 0.0),
            (20.0, 10.0),
            (10.0, 9.0),
            (10.0, 10.0),
            (0.0, 10.0),
        ]
        .map(|(x, y)| Point { x, y });
        let h = hull(&bent);
        assert_eq!(h.len, 4);
        assert_eq!(area2(h.as_slice()).abs(), 400.0);
    }
}
