//! Render: traverse, transform, clip, project, snap and fill, into a caller's [`SpanSink`].
//!
//! Everything a frame needs is checked before the first pixel ([`RenderError`]): the camera
//! fits the fixed-point range, the [`Workspace`] stack holds the tree's depth, its clip
//! buffers hold the largest polygon plus what clipping adds ([`clip::CLIP_PLANES`]), and id
//! rendering has ids to draw. A frame is then drawn completely or not at all.
//!
//! Snapping: a projected point `(sx, sy)` becomes `FixedPoint { x: round(sx * 2^SUB),
//! y: round(sy * 2^SUB) }`, rounding to nearest (halves away from zero), then clamped to the
//! window `[0, W * 2^SUB] x [0, H * 2^SUB]` (clipped points may miss the window by a rounding
//! error). Snapping is a function of the point alone, so polygons sharing an edge share its
//! fixed-point ends bit for bit.

use glam::{Vec2, Vec3};

use crate::camera::{Camera, View};
use crate::clip::{self, Frustum};
use crate::coverage::{Coverage, CoverageSink, Mode};
use crate::error::RenderError;
use crate::fill::{self, FixedPoint};
use crate::read::layout::polygon_flags::{FLIPPED, ONE_SIDED};
use crate::read::{Polygon, Scene};
use crate::target::{Colour, SpanSink};
use crate::traverse::{DisplayTree, Order, StackEntry, Traversal};

/// Everything [`render`] reads from a scene; [`Scene`] implements it (tests use small
/// in-memory trees).
pub trait Source: DisplayTree {
    /// World position the scene's coordinates are relative to.
    fn centre(&self) -> [f64; 3];
    /// Largest polygon vertex count.
    fn max_polygon_vertices(&self) -> u32;
    /// Vertex `i` of `polygon`, relative to the centre.
    fn polygon_vertex(&self, polygon: &Polygon, i: u32) -> Vec3;
    /// Whether the scene holds triangle ids.
    fn has_ids(&self) -> bool;
    /// Source triangle id of polygon `i`.
    fn id(&self, i: u32) -> Option<u32>;
    /// Bounding box `(min, max)` of the polygons of node `i`'s subtree, relative to the
    /// centre, when the scene stores one (it is never required).
    fn node_bounds(&self, i: u32) -> Option<(Vec3, Vec3)> {
        let _ = i;
        None
    }
}

impl Source for Scene<'_> {
    fn centre(&self) -> [f64; 3] {
        self.header().centre
    }
    fn max_polygon_vertices(&self) -> u32 {
        self.header().max_polygon_vertices
    }
    fn polygon_vertex(&self, polygon: &Polygon, i: u32) -> Vec3 {
        Scene::polygon_vertex(self, polygon, i)
    }
    fn has_ids(&self) -> bool {
        self.header().flags & crate::read::layout::header_flags::IDS != 0
    }
    fn id(&self, i: u32) -> Option<u32> {
        Scene::id(self, i)
    }
    fn node_bounds(&self, i: u32) -> Option<(Vec3, Vec3)> {
        Scene::node_bounds(self, i)
    }
}

/// What a polygon is painted with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Paint {
    /// Its baked colour.
    #[default]
    Colours,
    /// Its source triangle id plus one, as 24 bits (red the high byte); needs a file with ids.
    Ids,
}

/// The colour of an id image pixel for triangle `id`: `id + 1` in 24 bits, red high
/// (ids past `2^24 - 2` wrap: the format's ids are far below that).
pub fn id_colour(id: u32) -> Colour {
    let v = id.wrapping_add(1);
    Colour::new((v >> 16) as u8, (v >> 8) as u8, v as u8)
}

/// Counters of one frame (what `peel render --stats` prints).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameStats {
    /// Polygons the traversal yielded.
    pub polygons_visited: u64,
    /// Polygons left with at least 3 vertices after clipping (handed to the fill).
    pub polygons_drawn: u64,
    /// Pixels the fill emitted (overdraw counted).
    pub pixels_written: u64,
    /// Subtrees skipped because their bounds lie outside the view frustum.
    pub nodes_culled_frustum: u64,
    /// Subtrees skipped because their screen rectangle was already covered (front to back).
    pub nodes_culled_covered: u64,
    /// One-sided polygons skipped because the eye is behind them.
    pub polygons_culled_back_face: u64,
    /// Distinct pixels written, when known: always in front-to-back mode (without fallback),
    /// and in back-to-front mode when span memory was given and sufficed.
    pub distinct_pixels: Option<u64>,
    /// Front to back stopped early because every pixel was covered.
    pub stopped_full: bool,
    /// Front to back ran out of span memory (or had none) and painted the rest back to front.
    pub fallback: bool,
}

impl FrameStats {
    /// Pixels written per distinct pixel covered (exactly 1 in front-to-back mode; 1 for an
    /// empty frame), when the distinct count is known.
    pub fn overdraw(&self) -> Option<f64> {
        let distinct = self.distinct_pixels?;
        Some(if distinct == 0 {
            1.0
        } else {
            self.pixels_written as f64 / distinct as f64
        })
    }
}

/// How a frame is drawn. The default is what the CLI's default is: front to back with all
/// culling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderOptions {
    /// Back to front (painter's algorithm, overdraw) or front to back (each pixel once,
    /// needs span memory: see [`Coverage`]).
    pub order: Order,
    /// Colours or ids.
    pub paint: Paint,
    /// Skip subtrees outside the frustum or (front to back) already covered, and one-sided
    /// polygons seen from behind. Changes the image only where back faces of a closed mesh
    /// are visible: with the eye inside it, or its inside opened by the near plane; turn it
    /// off to look inside closed meshes (see `formats/peel.md`, `ONE_SIDED`).
    pub cull: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            order: Order::FrontToBack,
            paint: Paint::Colours,
            cull: true,
        }
    }
}

/// The memory of a frame, fixed-size: a traversal stack of `STACK` entries (at least the
/// tree's `max_depth`) and clip buffers of `VERTS` vertices (at least the largest polygon
/// plus [`clip::CLIP_PLANES`], and at most [`fill::MAX_FILL_VERTICES`] are used).
#[derive(Debug, Clone)]
pub struct Workspace<const STACK: usize, const VERTS: usize> {
    stack: [StackEntry; STACK],
    clip_a: [Vec3; VERTS],
    clip_b: [Vec3; VERTS],
    points: [FixedPoint; VERTS],
}

impl<const STACK: usize, const VERTS: usize> Workspace<STACK, VERTS> {
    /// A zeroed workspace (large `STACK`/`VERTS` belong in a `static` or on the heap).
    pub fn new() -> Self {
        Workspace {
            stack: [StackEntry::default(); STACK],
            clip_a: [Vec3::ZERO; VERTS],
            clip_b: [Vec3::ZERO; VERTS],
            points: [FixedPoint::default(); VERTS],
        }
    }
}

impl<const STACK: usize, const VERTS: usize> Default for Workspace<STACK, VERTS> {
    fn default() -> Self {
        Self::new()
    }
}

/// Snap a screen point to fixed point with `SUB` fractional bits (see the module docs);
/// `max_x`, `max_y` are `W * 2^SUB`, `H * 2^SUB`. A NaN lands on 0.
pub fn snap<const SUB: u32>(p: Vec2, max_x: i32, max_y: i32) -> FixedPoint {
    // Saturating and NaN-safe: no overflow, no panic.
    let q = FixedPoint::snap::<SUB>(p.x, p.y);
    FixedPoint {
        x: q.x.clamp(0, max_x.max(0)),
        y: q.y.clamp(0, max_y.max(0)),
    }
}

/// The window in fixed point, or [`RenderError::ImageTooLarge`].
fn window<const SUB: u32>(width: u32, height: u32) -> Result<(i32, i32), RenderError> {
    let scaled = |v: u32| {
        i32::try_from(v)
            .ok()
            .and_then(|v| v.checked_mul(1i32.checked_shl(SUB)?))
            .filter(|_| SUB <= 30)
    };
    match (scaled(width), scaled(height)) {
        (Some(x), Some(y)) => Ok((x, y)),
        _ => Err(RenderError::ImageTooLarge { width, height }),
    }
}

/// [`render_with`] with the default fixed-point precision [`fill::SUBPIXEL_BITS`].
pub fn render<T, S, const STACK: usize, const VERTS: usize>(
    scene: &T,
    camera: &Camera,
    workspace: &mut Workspace<STACK, VERTS>,
    paint: Paint,
    sink: &mut S,
) -> Result<FrameStats, RenderError>
where
    T: Source + ?Sized,
    S: SpanSink + ?Sized,
{
    render_with::<{ fill::SUBPIXEL_BITS }, T, S, STACK, VERTS>(
        scene, camera, workspace, paint, sink,
    )
}

/// Draw `scene` seen by `camera` back to front into `sink`, snapping to `SUB` fractional
/// bits, with culling. Checks everything up front (see the module docs) and never panics.
pub fn render_with<const SUB: u32, T, S, const STACK: usize, const VERTS: usize>(
    scene: &T,
    camera: &Camera,
    workspace: &mut Workspace<STACK, VERTS>,
    paint: Paint,
    sink: &mut S,
) -> Result<FrameStats, RenderError>
where
    T: Source + ?Sized,
    S: SpanSink + ?Sized,
{
    let options = RenderOptions {
        order: Order::BackToFront,
        paint,
        cull: true,
    };
    render_with_options::<SUB, T, S, STACK, VERTS>(scene, camera, workspace, options, None, sink)
}

/// [`render_with_options`] with the default fixed-point precision [`fill::SUBPIXEL_BITS`].
pub fn render_ordered<T, S, const STACK: usize, const VERTS: usize>(
    scene: &T,
    camera: &Camera,
    workspace: &mut Workspace<STACK, VERTS>,
    options: RenderOptions,
    coverage: Option<&mut Coverage<'_>>,
    sink: &mut S,
) -> Result<FrameStats, RenderError>
where
    T: Source + ?Sized,
    S: SpanSink + ?Sized,
{
    render_with_options::<{ fill::SUBPIXEL_BITS }, T, S, STACK, VERTS>(
        scene, camera, workspace, options, coverage, sink,
    )
}

/// Draw `scene` seen by `camera` into `sink` as `options` say.
///
/// Front to back needs `coverage` (span memory for the camera's `W x H`, cleared here): every
/// pixel is then written exactly once and the walk stops when the frame is full. When the span
/// memory runs out, or there is none, the polygons not drawn yet are painted back to front,
/// clipped against what is covered (see [`crate::coverage`]): the image is the same, only
/// with overdraw in that part ([`FrameStats::fallback`]). Back to front uses `coverage`, if
/// given, only to count distinct pixels. Fails with [`RenderError::SpanMemory`] when the
/// coverage's size is not the camera's.
pub fn render_with_options<const SUB: u32, T, S, const STACK: usize, const VERTS: usize>(
    scene: &T,
    camera: &Camera,
    workspace: &mut Workspace<STACK, VERTS>,
    options: RenderOptions,
    coverage: Option<&mut Coverage<'_>>,
    sink: &mut S,
) -> Result<FrameStats, RenderError>
where
    T: Source + ?Sized,
    S: SpanSink + ?Sized,
{
    // Without the feature the span memory is never used: the optimiser drops that code.
    let mut coverage = if cfg!(feature = "front-to-back") {
        coverage
    } else {
        None
    };
    let (width, height) = (camera.width(), camera.height());
    let (max_x, max_y) = window::<SUB>(width, height)?;
    if options.paint == Paint::Ids && !(cfg!(feature = "ids") && scene.has_ids()) {
        return Err(RenderError::NoIds);
    }
    let needed = clip::buffer_len_for(scene.max_polygon_vertices());
    let available = u32::try_from(VERTS.min(fill::MAX_FILL_VERTICES)).unwrap_or(u32::MAX);
    if needed > available {
        return Err(RenderError::PolygonTooLarge { needed, available });
    }
    if let Some(c) = coverage.as_deref_mut() {
        if c.width() != width || c.height() != height {
            return Err(RenderError::SpanMemory);
        }
        c.clear();
    }
    let view = camera.view(scene.centre());
    let frustum = Frustum::new(&view);
    let Workspace {
        stack,
        clip_a,
        clip_b,
        points,
    } = workspace;
    let mut painter = Painter::<SUB> {
        view,
        frustum,
        max_x,
        max_y,
        available,
        paint: options.paint,
        cull: options.cull,
        clip_a,
        clip_b,
        points,
    };
    let mut stats = FrameStats::default();
    let front_to_back = options.order == Order::FrontToBack;
    if let Some(c) = coverage.as_deref_mut() {
        c.set_mode(if front_to_back {
            Mode::Exclusive
        } else {
            Mode::Measure
        });
    }
    let first_order = if front_to_back && coverage.is_none() {
        stats.fallback = true;
        Order::BackToFront
    } else {
        options.order
    };

    // Pass 1: the requested order (or back to front when there is no span memory).
    let mut overflow = None;
    {
        let mut traversal = Traversal::new(scene, view.eye, first_order, &mut stack[..])?;
        loop {
            if front_to_back && coverage.as_deref().is_some_and(|c| c.is_full()) {
                stats.stopped_full = true;
                break;
            }
            let cov = coverage.as_deref();
            let next = traversal.next_entering(|node| painter.enter(scene, node, cov, &mut stats));
            let Some(index) = next else { break };
            stats.polygons_visited = stats.polygons_visited.saturating_add(1);
            painter.draw(scene, index, coverage.as_deref_mut(), sink, &mut stats)?;
            if front_to_back && coverage.as_deref().is_some_and(|c| c.exhausted()) {
                overflow = Some(index);
                break;
            }
        }
        if let Some(e) = traversal.error() {
            return Err(e);
        }
    }

    // Pass 2 (span memory exhausted at polygon `last`): the polygons from the farthest up to
    // `last`, back to front, clipped against the frozen coverage.
    if let (Some(last), Some(c)) = (overflow, coverage.as_deref_mut()) {
        stats.fallback = true;
        c.freeze();
        let mut traversal = Traversal::new(scene, view.eye, Order::BackToFront, &mut stack[..])?;
        loop {
            let cov = coverage.as_deref();
            let next = traversal.next_entering(|node| painter.enter(scene, node, cov, &mut stats));
            let Some(index) = next else { break };
            if index != last {
                stats.polygons_visited = stats.polygons_visited.saturating_add(1);
            }
            painter.draw(scene, index, coverage.as_deref_mut(), sink, &mut stats)?;
            if index == last {
                break;
            }
        }
        if let Some(e) = traversal.error() {
            return Err(e);
        }
    }
    stats.distinct_pixels = match coverage.as_deref() {
        Some(c) if !c.exhausted() && !stats.fallback => Some(c.covered()),
        _ => None,
    };
    Ok(stats)
}

/// The per-polygon work of a frame, with its buffers.
struct Painter<'w, const SUB: u32> {
    view: View,
    frustum: Frustum,
    max_x: i32,
    max_y: i32,
    available: u32,
    paint: Paint,
    cull: bool,
    clip_a: &'w mut [Vec3],
    clip_b: &'w mut [Vec3],
    points: &'w mut [FixedPoint],
}

impl<const SUB: u32> Painter<'_, SUB> {
    /// Whether the walk enters `node`: not when culling proves its subtree draws nothing.
    fn enter<T: Source + ?Sized>(
        &self,
        scene: &T,
        node: u32,
        coverage: Option<&Coverage<'_>>,
        stats: &mut FrameStats,
    ) -> bool {
        if !self.cull {
            return true;
        }
        let Some((lo, hi)) = scene.node_bounds(node) else {
            return true;
        };
        let mut corners = [Vec3::ZERO; 8];
        for (k, c) in corners.iter_mut().enumerate() {
            let p = Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            *c = self.view.to_camera(p);
        }
        // Outside one half-space of the (convex) frustum: outside the frustum.
        let outside = self
            .frustum
            .planes()
            .iter()
            .any(|plane| corners.iter().all(|&c| plane.eval(c) < 0.0));
        if outside {
            stats.nodes_culled_frustum = stats.nodes_culled_frustum.saturating_add(1);
            return false;
        }
        let Some(coverage) = coverage.filter(|c| c.mode() != Mode::Measure) else {
            return true;
        };
        // Doom's bbox check in 3D: only when the whole box is in front of the near plane.
        if corners.iter().any(|c| c.z < self.view.near) {
            return true;
        }
        let (mut min, mut max) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
        for &c in &corners {
            let p = self.view.project(c);
            min = min.min(p);
            max = max.max(p);
        }
        // One pixel of margin covers snapping; clamped to the frame.
        let pixel = |v: f32, limit: u32| libm::floorf(v).clamp(0.0, limit as f32) as u32;
        let (w, h) = (coverage.width(), coverage.height());
        let (x0, y0) = (pixel(min.x - 1.0, w), pixel(min.y - 1.0, h));
        let (x1, y1) = (pixel(max.x + 2.0, w), pixel(max.y + 2.0, h));
        if coverage.covers(x0, y0, x1, y1) {
            stats.nodes_culled_covered = stats.nodes_culled_covered.saturating_add(1);
            return false;
        }
        true
    }

    /// Cull, clip, project, snap and fill polygon `index`, through `coverage` when given.
    fn draw<T: Source + ?Sized, S: SpanSink + ?Sized>(
        &mut self,
        scene: &T,
        index: u32,
        coverage: Option<&mut Coverage<'_>>,
        sink: &mut S,
        stats: &mut FrameStats,
    ) -> Result<(), RenderError> {
        let polygon = scene.polygon(index);
        if self.cull && polygon.flags & ONE_SIDED != 0 {
            let plane = scene.plane(polygon.plane);
            let d = plane.distance(self.view.eye);
            let front = if polygon.flags & FLIPPED != 0 { -d } else { d };
            if front < 0.0 {
                stats.polygons_culled_back_face = stats.polygons_culled_back_face.saturating_add(1);
                return Ok(());
            }
        }
        let n = u32::from(polygon.vertex_count);
        if clip::buffer_len_for(n) > self.available {
            // Only a source contradicting its own maximum gets here.
            return Err(RenderError::PolygonTooLarge {
                needed: clip::buffer_len_for(n),
                available: self.available,
            });
        }
        for (i, slot) in (0..n).zip(self.clip_a.iter_mut()) {
            *slot = self.view.to_camera(scene.polygon_vertex(&polygon, i));
        }
        let clipped =
            clip::clip_polygon(self.frustum.planes(), n as usize, self.clip_a, self.clip_b)?;
        if clipped.len() < 3 {
            return Ok(());
        }
        let mut count = 0usize;
        for (slot, &c) in self.points.iter_mut().zip(clipped) {
            *slot = snap::<SUB>(self.view.project(c), self.max_x, self.max_y);
            count += 1;
        }
        let colour = match self.paint {
            Paint::Colours => polygon.colour,
            Paint::Ids if cfg!(feature = "ids") => id_colour(scene.id(index).unwrap_or(u32::MAX)),
            Paint::Ids => polygon.colour,
        };
        stats.polygons_drawn = stats.polygons_drawn.saturating_add(1);
        let pts = self.points.get(..count).unwrap_or(&[]);
        let (width, height) = (self.view.width, self.view.height);
        let too_large =
            |fill::FillError::TooManyVertices { count, max }| RenderError::PolygonTooLarge {
                needed: u32::try_from(count).unwrap_or(u32::MAX),
                available: u32::try_from(max).unwrap_or(u32::MAX),
            };
        let pixels = match coverage {
            Some(coverage) => {
                let mut through = CoverageSink {
                    coverage,
                    sink,
                    pixels: 0,
                };
                fill::fill_polygon::<SUB, _>(pts, width, height, colour, &mut through)
                    .map_err(too_large)?;
                through.pixels
            }
            None => {
                fill::fill_polygon::<SUB, S>(pts, width, height, colour, sink).map_err(too_large)?
            }
        };
        stats.pixels_written = stats.pixels_written.saturating_add(pixels);
        Ok(())
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod order_tests;

#[cfg(test)]
mod feature_tests;
