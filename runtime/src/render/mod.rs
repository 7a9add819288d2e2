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

use crate::camera::Camera;
use crate::clip::{self, Frustum};
use crate::error::RenderError;
use crate::fill::{self, FixedPoint};
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

/// Counters of one frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameStats {
    /// Polygons the traversal yielded.
    pub polygons_visited: u64,
    /// Polygons left with at least 3 vertices after clipping (handed to the fill).
    pub polygons_drawn: u64,
    /// Pixels the fill emitted (overdraw counted).
    pub pixels_written: u64,
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
/// bits. Checks everything up front (see the module docs) and never panics.
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
    let (width, height) = (camera.width(), camera.height());
    let (max_x, max_y) = window::<SUB>(width, height)?;
    if paint == Paint::Ids && !scene.has_ids() {
        return Err(RenderError::NoIds);
    }
    let needed = clip::buffer_len_for(scene.max_polygon_vertices());
    let available = u32::try_from(VERTS.min(fill::MAX_FILL_VERTICES)).unwrap_or(u32::MAX);
    if needed > available {
        return Err(RenderError::PolygonTooLarge { needed, available });
    }
    let view = camera.view(scene.centre());
    let frustum = Frustum::new(&view);
    let Workspace {
        stack,
        clip_a,
        clip_b,
        points,
    } = workspace;
    let mut traversal = Traversal::new(scene, view.eye, Order::BackToFront, stack)?;
    let mut stats = FrameStats::default();
    for index in traversal.by_ref() {
        stats.polygons_visited = stats.polygons_visited.saturating_add(1);
        let polygon = scene.polygon(index);
        let n = u32::from(polygon.vertex_count);
        if clip::buffer_len_for(n) > available {
            // Only a source contradicting its own maximum gets here.
            return Err(RenderError::PolygonTooLarge {
                needed: clip::buffer_len_for(n),
                available,
            });
        }
        for (i, slot) in (0..n).zip(clip_a.iter_mut()) {
            *slot = view.to_camera(scene.polygon_vertex(&polygon, i));
        }
        let clipped = clip::clip_polygon(frustum.planes(), n as usize, clip_a, clip_b)?;
        if clipped.len() < 3 {
            continue;
        }
        let mut count = 0usize;
        for (slot, &c) in points.iter_mut().zip(clipped) {
            *slot = snap::<SUB>(view.project(c), max_x, max_y);
            count += 1;
        }
        let colour = match paint {
            Paint::Colours => polygon.colour,
            Paint::Ids => id_colour(scene.id(index).unwrap_or(u32::MAX)),
        };
        stats.polygons_drawn = stats.polygons_drawn.saturating_add(1);
        let pts = points.get(..count).unwrap_or(&[]);
        let pixels = fill::fill_polygon::<SUB, S>(pts, width, height, colour, sink).map_err(
            |fill::FillError::TooManyVertices { count, max }| RenderError::PolygonTooLarge {
                needed: u32::try_from(count).unwrap_or(u32::MAX),
                available: u32::try_from(max).unwrap_or(u32::MAX),
            },
        )?;
        stats.pixels_written = stats.pixels_written.saturating_add(pixels);
    }
    match traversal.error() {
        Some(e) => Err(e),
        None => Ok(stats),
    }
}

#[cfg(test)]
mod tests;
