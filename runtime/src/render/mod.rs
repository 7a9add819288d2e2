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
//!
//! # Culling
//!
//! With culling on (the default; [`Renderer::without_culling`] turns it off) a frame skips
//! work that cannot change a pixel,
//! for every camera the renderer accepts, inside or outside the scene, at every `SUB` and
//! image size:
//! - a subtree whose box lies outside one frustum plane ([`Frustum::excludes_box`]): with
//!   that test's margin every vertex of the subtree fails the clipper's own `f32` test for
//!   that plane, so clipping would leave nothing of its polygons;
//! - front to back, a subtree whose screen box widened by the projection and snapping error
//!   (`slack`) holds no uncovered pixel centre, and a polygon whose snapped points' sample
//!   rectangle is all covered: in front-to-back order a covered pixel is never written again,
//!   so these could only have written nothing;
//! - clipping, when the whole scene passes every plane with margin
//!   ([`Frustum::contains_box`]): clipping would return every polygon unchanged.
//!
//! There is deliberately no back-face culling. It is not pixel-neutral with snapped
//! coordinates even for an eye outside a closed, outward-oriented mesh wholly in front of the
//! near plane (where it is exact in real numbers): snapping can turn a tiny face near a
//! silhouette over, and a pixel centre in the gap it leaves is covered by far-side faces
//! only (the snapped images of a closed surface cover every point with orientations summing
//! to zero, so there they come in pairs, one of them turned over). The display order decides
//! which one shows, and a rule that judges one polygon at a time cannot tell it from the one
//! it hides. Front to back, a closed mesh's far side comes after its near side has covered
//! its pixels, and the coverage tests above, which are exact, skip it.

use glam::{Vec2, Vec3};

use crate::camera::View;
use crate::clip::{self, Frustum};
use crate::coverage::{Coverage, Mode};
use crate::error::RenderError;
use crate::fill::{self, FixedPoint};
use crate::read::{Polygon, Scene};
use crate::target::{Colour, SpanSink};
use crate::traverse::{DisplayTree, Order, StackEntry, Traversal};
use crate::vertices::VertexCache;

/// Everything a [`Renderer`] reads from a scene; [`Scene`] implements it (tests use small
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
    /// The index of vertex `i` of `polygon` in the scene's shared vertex list, when it has one:
    /// a frame then projects each shared vertex once, the first time its index comes, from the
    /// position [`Source::polygon_vertex`] gives (see [`crate::vertices`]). Equal indices must
    /// therefore mean equal positions.
    fn vertex_index(&self, polygon: &Polygon, i: u32) -> Option<u32> {
        let _ = (polygon, i);
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
    fn vertex_index(&self, polygon: &Polygon, i: u32) -> Option<u32> {
        Scene::polygon_vertex_index(self, polygon, i)
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

/// Counters of one frame (what `peel render --stats` prints). The counters are kept with the
/// `stats` feature (default); without it they read 0, and only `distinct_pixels`,
/// `stopped_full` and `fallback` are reported.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameStats {
    /// Polygons the traversal yielded.
    pub polygons_visited: u64,
    /// Polygons handed to the fill: left with at least 3 vertices after clipping, with a pixel
    /// centre inside their box, and not culled as covered.
    pub polygons_drawn: u64,
    /// Pixels the fill emitted (overdraw counted).
    pub pixels_written: u64,
    /// Subtrees skipped because their bounds lie outside the view frustum (0 without the
    /// `bounds-culling` feature).
    pub nodes_culled_frustum: u64,
    /// Subtrees skipped because their screen rectangle was already covered (front to back;
    /// 0 without the `bounds-culling` feature).
    pub nodes_culled_covered: u64,
    /// Polygons skipped because every pixel they could draw was already covered (front to
    /// back; tested on the rectangle of their sample points, before the fill).
    pub polygons_culled_covered: u64,
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
    /// empty frame), when the distinct count is known (and pixels are counted: never without
    /// the `stats` feature).
    pub fn overdraw(&self) -> Option<f64> {
        if !cfg!(feature = "stats") {
            return None;
        }
        let distinct = self.distinct_pixels?;
        Some(if distinct == 0 {
            1.0
        } else {
            self.pixels_written as f64 / distinct as f64
        })
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
    /// The fill's edge memory, reused by every polygon.
    edges: [fill::EdgeWalk; VERTS],
}

impl<const STACK: usize, const VERTS: usize> Workspace<STACK, VERTS> {
    /// A zeroed workspace (large `STACK`/`VERTS` belong in a `static` or on the heap). A
    /// `const fn`: firmware can keep it in a `static`, which costs no code (all zero bytes,
    /// it lands in `.bss`).
    pub const fn new() -> Self {
        Workspace {
            stack: [StackEntry::IDLE; STACK],
            clip_a: [Vec3::ZERO; VERTS],
            clip_b: [Vec3::ZERO; VERTS],
            points: [FixedPoint::new(0, 0); VERTS],
            edges: [fill::EdgeWalk::ZERO; VERTS],
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

/// The window in fixed point, or [`RenderError::ImageTooLarge`] (beyond `i32`, or beyond
/// [`fill::coordinate_limit`] without the `wide-coordinates` feature).
fn window<const SUB: u32>(width: u32, height: u32) -> Result<(i32, i32), RenderError> {
    let scaled = |v: u32| {
        i32::try_from(v)
            .ok()
            .and_then(|v| v.checked_mul(1i32.checked_shl(SUB)?))
            .filter(|&v| SUB <= 30 && v <= fill::coordinate_limit::<SUB>())
    };
    match (scaled(width), scaled(height)) {
        (Some(x), Some(y)) => Ok((x, y)),
        _ => Err(RenderError::ImageTooLarge { width, height }),
    }
}

/// Draws frames: made once from caller memory, reused for every frame, never allocating.
///
/// ```no_run
/// use peel_runtime::camera::{Camera, Orbit};
/// use peel_runtime::coverage::Coverage;
/// use peel_runtime::read::Scene;
/// use peel_runtime::render::{Renderer, Workspace};
/// use peel_runtime::target::{Framebuffer, Xrgb8888};
/// # let bytes: &[u8] = &[];
/// let scene = Scene::parse(bytes).expect("a valid .peel file");
/// let header = scene.header();
/// let near = Camera::default_near(header.bounds_min, header.bounds_max);
/// let pose = Orbit::default().pose(&header);
/// let camera = Camera::look_at(pose, 60.0, 320, 240, near).expect("a camera");
/// // Stack for the tree's depth, clip buffers for its largest polygon (see `Workspace`).
/// let mut workspace = Box::new(Workspace::<512, 32>::new());
/// // Span memory: front to back, every pixel written once (see `Coverage`).
/// let (mut spans, mut rows) = (vec![(0, 0); 64 * 240], vec![0; 240]);
/// let coverage = Coverage::new(&mut spans, &mut rows, 320, 240).expect("span memory");
/// let mut renderer = Renderer::new(&mut workspace).span_memory(coverage);
/// let mut pixels = vec![0u32; 320 * 240];
/// let mut target = Framebuffer::<Xrgb8888>::new(&mut pixels, 320, 240).expect("a target");
/// let stats = renderer
///     .draw(&scene, &camera.view(header.centre), &mut target)
///     .expect("a frame");
/// assert!(!stats.fallback);
/// ```
///
/// What is drawn follows from the memory given and a few switches, and the result says what
/// happened:
/// - with span memory ([`Renderer::span_memory`]) front to back: each pixel is written once
///   and the walk stops when the frame is full; if the span memory runs out mid-frame, the
///   rest is painted back to front, clipped against what is covered: the same image with
///   some overdraw, reported as [`FrameStats::fallback`];
/// - without it (or with [`Renderer::back_to_front`]) back to front, the painter's algorithm
///   (span memory, if given, then only counts distinct pixels);
/// - vertex memory ([`Renderer::vertex_memory`]) saves work and changes no pixel;
/// - colours, or ids with [`Renderer::ids`] (a scene without ids is an error, not a blank);
/// - culling on, which never changes a pixel ([`Renderer::without_culling`] to measure it).
///
/// `SUB` is the fixed-point precision of screen coordinates (fractional bits): the default
/// [`fill::SUBPIXEL_BITS`] with [`Renderer::new`], another with [`Renderer::with_precision`].
#[derive(Debug)]
pub struct Renderer<'m, const SUB: u32 = { fill::SUBPIXEL_BITS }> {
    stack: &'m mut [StackEntry],
    clip_a: &'m mut [Vec3],
    clip_b: &'m mut [Vec3],
    points: &'m mut [FixedPoint],
    edges: &'m mut [fill::EdgeWalk],
    coverage: Option<Coverage<'m>>,
    vertices: Option<VertexCache<'m>>,
    back_to_front: bool,
    paint: Paint,
    cull: bool,
    background: Option<Colour>,
}

impl<'m> Renderer<'m> {
    /// A renderer at the default precision [`fill::SUBPIXEL_BITS`] using `workspace`'s stack
    /// and clip buffers: back to front, colours, culling on.
    #[inline(always)]
    pub fn new<const STACK: usize, const VERTS: usize>(
        workspace: &'m mut Workspace<STACK, VERTS>,
    ) -> Self {
        Renderer::with_precision(workspace)
    }
}

impl<'m, const SUB: u32> Renderer<'m, SUB> {
    /// [`Renderer::new`] at `SUB` fractional bits: `Renderer::<4>::with_precision(&mut ws)`.
    #[inline(always)]
    pub fn with_precision<const STACK: usize, const VERTS: usize>(
        workspace: &'m mut Workspace<STACK, VERTS>,
    ) -> Self {
        let Workspace {
            stack,
            clip_a,
            clip_b,
            points,
            edges,
        } = workspace;
        Renderer {
            stack,
            clip_a,
            clip_b,
            points,
            edges,
            coverage: None,
            vertices: None,
            back_to_front: false,
            paint: Paint::Colours,
            cull: true,
            background: None,
        }
    }

    /// Span memory for images of the coverage's size: frames are then drawn front to back,
    /// each pixel written once (with the `front-to-back` feature; without it the memory is
    /// unused and every frame reports [`FrameStats::fallback`]).
    #[inline(always)]
    pub fn span_memory(mut self, coverage: Coverage<'m>) -> Self {
        self.coverage = Some(coverage);
        self
    }

    /// Screen positions of the scene's vertices, kept from frame to frame (with the
    /// `vertex-cache` feature; see [`crate::vertices`]): the same pixels for less work.
    #[inline(always)]
    pub fn vertex_memory(mut self, vertices: VertexCache<'m>) -> Self {
        self.vertices = Some(vertices);
        self
    }

    /// Paint source triangle ids (`id + 1` as 24-bit RGB, see [`id_colour`]) instead of
    /// colours; a scene without ids then fails with [`RenderError::NoIds`].
    #[inline(always)]
    pub fn ids(mut self) -> Self {
        self.paint = Paint::Ids;
        self
    }

    /// Paint back to front even with span memory (which then only counts distinct pixels).
    #[inline(always)]
    pub fn back_to_front(mut self) -> Self {
        self.back_to_front = true;
        self
    }

    /// Write every pixel of every frame, those no polygon covers in `colour`: front to back
    /// each exactly once (the uncovered spans are emitted last, or before the fallback pass,
    /// from the span memory), back to front with the rows painted first. A display then needs
    /// no clear and no framebuffer: spans can go straight to it.
    #[inline(always)]
    pub fn background(mut self, colour: Colour) -> Self {
        self.background = Some(colour);
        self
    }

    /// Draw without culling (see the module docs, "Culling"): the same pixels, more work;
    /// only to measure what culling saves.
    #[inline(always)]
    pub fn without_culling(mut self) -> Self {
        self.cull = false;
        self
    }

    /// The order frames are drawn in: front to back exactly when span memory was given and
    /// back to front was not asked for.
    pub fn order(&self) -> Order {
        if self.coverage.is_some() && !self.back_to_front && cfg!(feature = "front-to-back") {
            Order::FrontToBack
        } else {
            Order::BackToFront
        }
    }

    /// The span memory, if any (after a frame: what it covered).
    pub fn coverage(&self) -> Option<&Coverage<'m>> {
        self.coverage.as_ref()
    }

    /// Draw `scene` seen by `view` into `target`. Everything is checked before the first
    /// pixel (see the module docs) and the frame is drawn completely or not at all: an error
    /// for a view that is degenerate ([`View::check`]), an image too large for the
    /// fixed-point range, a stack or clip buffers too small for the scene, span memory of
    /// another size than the view's image, or ids asked of a scene without them. Never panics.
    pub fn draw<T, S>(
        &mut self,
        scene: &T,
        view: &View,
        target: &mut S,
    ) -> Result<FrameStats, RenderError>
    where
        T: Source + ?Sized,
        S: SpanSink + ?Sized,
    {
        view.check()?;
        self.frame(scene, view, 0..view.height, target)
    }

    /// [`Renderer::draw`] of frame rows `rows` only: a band, for firmware that sends a frame
    /// to its display band by band instead of keeping a framebuffer. The target gets the same
    /// spans as in the whole frame's draw, with frame row numbers (a [`Framebuffer::band`]
    /// takes them), and subtrees whose screen box misses the band are skipped. Span memory,
    /// if given, is for the band: a [`Coverage`] `view.width` wide and at least `rows.len()`
    /// high (its first rows are used, so one serves every band, the shorter last one too).
    /// Also an error: rows outside the image ([`RenderError::RowsOutsideImage`]).
    ///
    /// [`Framebuffer::band`]: crate::target::Framebuffer::band
    pub fn draw_rows<T, S>(
        &mut self,
        scene: &T,
        view: &View,
        rows: core::ops::Range<u32>,
        target: &mut S,
    ) -> Result<FrameStats, RenderError>
    where
        T: Source + ?Sized,
        S: SpanSink + ?Sized,
    {
        view.check()?;
        if rows.start > rows.end || rows.end > view.height {
            return Err(RenderError::RowsOutsideImage {
                start: rows.start,
                end: rows.end,
                height: view.height,
            });
        }
        self.frame(scene, view, rows, target)
    }

    fn frame<T, S>(
        &mut self,
        scene: &T,
        view: &View,
        rows: core::ops::Range<u32>,
        sink: &mut S,
    ) -> Result<FrameStats, RenderError>
    where
        T: Source + ?Sized,
        S: SpanSink + ?Sized,
    {
        let order = self.order();
        let paint = self.paint;
        let cull = self.cull;
        // Without the features the memory is never used: the optimiser drops that code.
        let asked_front_to_back = self.coverage.is_some() && !self.back_to_front;
        let mut coverage = if cfg!(feature = "front-to-back") {
            self.coverage.as_mut()
        } else {
            None
        };
        let vertices = if cfg!(feature = "vertex-cache") {
            self.vertices.as_mut()
        } else {
            None
        };
        let (width, height) = (view.width, view.height);
        let (max_x, max_y) = window::<SUB>(width, height)?;
        if paint == Paint::Ids && !(cfg!(feature = "ids") && scene.has_ids()) {
            return Err(RenderError::NoIds);
        }
        let needed = clip::buffer_len_for(scene.max_polygon_vertices());
        let buffers = [
            self.clip_a.len(),
            self.clip_b.len(),
            self.points.len(),
            self.edges.len(),
            fill::MAX_FILL_VERTICES,
        ];
        let shortest = buffers.into_iter().min().unwrap_or(0);
        let available = u32::try_from(shortest).unwrap_or(u32::MAX);
        if needed > available {
            return Err(RenderError::PolygonTooLarge { needed, available });
        }
        if let Some(c) = coverage.as_deref_mut() {
            if c.width() != width || c.height() < rows.end - rows.start {
                return Err(RenderError::SpanMemory);
            }
            c.clear();
            c.use_rows(rows.end - rows.start);
        }
        let frustum = Frustum::new(view);
        // The whole scene inside the frustum (the usual case for an object in view): no
        // subtree needs the frustum test and no polygon needs clipping. Bounds are only trusted
        // when culling is on, as for every other use of them.
        let all_inside = cull
            && cfg!(feature = "bounds-culling")
            && scene
                .root()
                .and_then(|root| scene.node_bounds(root))
                .is_some_and(|(lo, hi)| frustum.contains_box(view, lo, hi));
        // Only frames without clipping use it (see `crate::vertices`).
        let mut vertices = vertices.filter(|_| all_inside);
        if let Some(v) = vertices.as_deref_mut() {
            v.next_frame();
        }
        let (first_row, end_row) = (rows.start, rows.end);
        let mut painter = Painter::<SUB> {
            view,
            rows,
            frustum,
            max_x,
            max_y,
            available,
            paint,
            cull,
            all_inside,
            clip_a: &mut self.clip_a[..],
            clip_b: &mut self.clip_b[..],
            points: &mut self.points[..],
            edges: &mut self.edges[..],
            vertices,
        };
        let mut stats = FrameStats {
            // Front to back was asked for, but the feature is off: painted back to front.
            fallback: asked_front_to_back && order == Order::BackToFront,
            ..FrameStats::default()
        };
        if let Some(c) = coverage.as_deref_mut() {
            c.set_mode(if order == Order::FrontToBack {
                Mode::Exclusive
            } else {
                Mode::Measure
            });
        }
        let background = self.background;
        // Back to front: the background first, then every polygon over it.
        if let (Some(colour), Order::BackToFront) = (background, order) {
            paint_uncovered(None, width, first_row..end_row, colour, sink);
        }

        // Pass 1: the frame's order.
        let overflow = painter.walk(
            scene,
            order,
            &mut self.stack[..],
            coverage.as_deref_mut(),
            sink,
            &mut stats,
            None,
        )?;

        // Pass 2 (span memory exhausted at polygon `last`): the polygons from the farthest up
        // to `last`, back to front, clipped against the frozen coverage.
        if let (Some(last), Some(c)) = (overflow, coverage.as_deref_mut()) {
            stats.fallback = true;
            c.freeze();
            // What pass 2 draws, it draws over this (it paints back to front).
            if let Some(colour) = background {
                paint_uncovered(Some(c), width, first_row..end_row, colour, sink);
            }
            painter.walk(
                scene,
                Order::BackToFront,
                &mut self.stack[..],
                coverage.as_deref_mut(),
                sink,
                &mut stats,
                Some(last),
            )?;
        }
        if let (Some(colour), Order::FrontToBack, None) = (background, order, overflow) {
            if let Some(c) = coverage.as_deref() {
                paint_uncovered(Some(c), width, first_row..end_row, colour, sink);
            }
        }
        stats.distinct_pixels = match coverage.as_deref() {
            Some(c) if !c.exhausted() && !stats.fallback => Some(c.covered()),
            _ => None,
        };
        Ok(stats)
    }
}

/// Paint in `colour` the pixels of frame rows `rows`, `width` wide, that `coverage` does not
/// cover (its row `y` being frame row `rows.start + y`): all of them without one. (One copy
/// for its three callers.)
#[inline(never)]
fn paint_uncovered<S: SpanSink + ?Sized>(
    coverage: Option<&Coverage<'_>>,
    width: u32,
    rows: core::ops::Range<u32>,
    colour: Colour,
    sink: &mut S,
) {
    let first_row = rows.start;
    for y in 0..rows.end - rows.start {
        let mut at = 0;
        for &(a, b) in coverage.map_or(&[][..], |c| c.row(y)) {
            if at < u32::from(a) {
                sink.span(first_row + y, at, u32::from(a), colour);
            }
            at = u32::from(b);
        }
        if at < width {
            sink.span(first_row + y, at, width, colour);
        }
    }
}

/// How far, in pixels, a snapped vertex of an image `size` pixels wide (its larger side) may
/// lie outside the screen rectangle of its node's box ([`View::box_on_screen`], which already
/// holds every computed camera-space position): snapping moves it by at most `2^-(SUB+1)` of
/// a pixel, and the rectangle's and the vertex's screen values each round by a few units in
/// their last place, below `size` where it matters. `1/64` of a pixel plus `size · 2^-18` (64
/// such units) bounds that with room to spare: about 0.018 pixel at 640 pixels.
fn slack<const SUB: u32>(size: u32) -> f32 {
    0.5 / (1u32 << SUB.min(30)) as f32 + 1.0 / 64.0 + size as f32 / (1u32 << 18) as f32
}

/// `ceil(v)` as a pixel index: 0 below zero and for NaN, saturating above.
fn ceil_pixel(v: f32) -> u32 {
    // `as` maps NaN and negatives to 0.
    let t = v as u32;
    if (t as f32) < v {
        t.saturating_add(1)
    } else {
        t
    }
}

/// `floor(v)` as a pixel index: 0 below zero and for NaN, saturating above.
fn floor_pixel(v: f32) -> u32 {
    v.max(0.0) as u32
}

/// `*counter += n` (saturating) with the `stats` feature; nothing without it.
#[inline(always)]
fn tally(counter: &mut u64, n: u64) {
    if cfg!(feature = "stats") {
        *counter = counter.saturating_add(n);
    }
}

/// The per-polygon work of a frame, with its buffers.
struct Painter<'w, 'v, const SUB: u32> {
    view: &'w View,
    /// The frame rows drawn (all of them, or a band).
    rows: core::ops::Range<u32>,
    frustum: Frustum,
    max_x: i32,
    max_y: i32,
    available: u32,
    paint: Paint,
    cull: bool,
    /// Every polygon of the scene is inside the frustum (see [`Frustum::contains_box`]).
    all_inside: bool,
    clip_a: &'w mut [Vec3],
    clip_b: &'w mut [Vec3],
    points: &'w mut [FixedPoint],
    edges: &'w mut [fill::EdgeWalk],
    /// Projected vertices, in frames without clipping.
    vertices: Option<&'w mut VertexCache<'v>>,
}

impl<const SUB: u32> Painter<'_, '_, SUB> {
    /// One walk of the tree in `order`, drawing every polygon it yields. In front-to-back
    /// mode ([`Mode::Exclusive`] coverage) it stops when the frame is full, or after the
    /// polygon whose span did not fit the span memory, which it returns. With `last` (the
    /// fallback pass) it stops after polygon `last`, which the first pass already counted.
    /// One function for both passes keeps one copy of the loop in the binary.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn walk<T: Source + ?Sized, S: SpanSink + ?Sized>(
        &mut self,
        scene: &T,
        order: Order,
        stack: &mut [StackEntry],
        mut coverage: Option<&mut Coverage<'_>>,
        sink: &mut S,
        stats: &mut FrameStats,
        last: Option<u32>,
    ) -> Result<Option<u32>, RenderError> {
        let exclusive = coverage
            .as_deref()
            .is_some_and(|c| c.mode() == Mode::Exclusive);
        let mut overflow = None;
        let mut traversal = Traversal::new(scene, self.view.eye, order, stack)?;
        loop {
            if exclusive && coverage.as_deref().is_some_and(|c| c.is_full()) {
                stats.stopped_full = true;
                break;
            }
            let cov = coverage.as_deref();
            let next = traversal.next_polygon_entering(|node| self.enter(scene, node, cov, stats));
            let Some((index, polygon)) = next else { break };
            if last != Some(index) {
                tally(&mut stats.polygons_visited, 1);
            }
            self.draw(scene, index, &polygon, coverage.as_deref_mut(), sink, stats)?;
            if last == Some(index) {
                break;
            }
            if exclusive && coverage.as_deref().is_some_and(|c| c.exhausted()) {
                overflow = Some(index);
                break;
            }
        }
        match traversal.error() {
            Some(e) => Err(e),
            None => Ok(overflow),
        }
    }

    /// Whether the walk enters `node`: not when culling proves its subtree draws nothing (see
    /// the module docs). Always, without the `bounds-culling` feature.
    fn enter<T: Source + ?Sized>(
        &self,
        scene: &T,
        node: u32,
        coverage: Option<&Coverage<'_>>,
        stats: &mut FrameStats,
    ) -> bool {
        if !(self.cull && cfg!(feature = "bounds-culling")) {
            return true;
        }
        let coverage = coverage.filter(|c| c.mode() != Mode::Measure);
        let (w, h) = (self.view.width, self.view.height);
        let (r0, r1) = (self.rows.start, self.rows.end);
        let banded = r0 != 0 || r1 != h;
        if self.all_inside && coverage.is_none() && !banded {
            return true; // nothing to test
        }
        let Some((lo, hi)) = scene.node_bounds(node) else {
            return true;
        };
        let b = self.view.box_to_camera(lo, hi);
        if !self.all_inside && self.frustum.excludes_box(&b) {
            tally(&mut stats.nodes_culled_frustum, 1);
            return false;
        }
        if coverage.is_none() && !banded {
            return true;
        }
        // Doom's bbox check in 3D: only when the whole box is in front of the near plane.
        let Some((min, max)) = self.view.box_on_screen(&b) else {
            return true;
        };
        // The pixels of the rows drawn whose sample point `(x + 0.5, y + 0.5)` is within
        // `slack` of the box's screen rectangle: the only ones its polygons can draw. None:
        // nothing to draw; all covered: nothing shows.
        let slack = slack::<SUB>(w.max(h));
        let first = |v: f32, limit: u32| ceil_pixel(v - slack - 0.5).min(limit);
        let past = |v: f32, limit: u32| floor_pixel(v + slack + 0.5).min(limit);
        let (x0, y0) = (first(min.x, w), first(min.y, h).max(r0));
        let (x1, y1) = (past(max.x, w), past(max.y, h).min(r1));
        let covered = |c: &Coverage<'_>| c.covers(x0, y0 - r0, x1, y1 - r0);
        if x0 >= x1 || y0 >= y1 || coverage.is_some_and(covered) {
            tally(&mut stats.nodes_culled_covered, 1);
            return false;
        }
        true
    }

    /// Cull, clip, project, snap and fill polygon `index`, through `coverage` when given.
    fn draw<T: Source + ?Sized, S: SpanSink + ?Sized>(
        &mut self,
        scene: &T,
        index: u32,
        polygon: &Polygon,
        coverage: Option<&mut Coverage<'_>>,
        sink: &mut S,
        stats: &mut FrameStats,
    ) -> Result<(), RenderError> {
        let n = u32::from(polygon.vertex_count);
        if clip::buffer_len_for(n) > self.available {
            // Only a source contradicting its own maximum gets here.
            return Err(RenderError::PolygonTooLarge {
                needed: clip::buffer_len_for(n),
                available: self.available,
            });
        }
        let (view, max_x, max_y) = (self.view, self.max_x, self.max_y);
        let screen = |c: Vec3| snap::<SUB>(view.project(c), max_x, max_y);
        // Without the feature there is never a cache: the test keeps that path out of the
        // binary (the optimiser cannot see through the painter's field).
        let cache = self
            .vertices
            .as_deref_mut()
            .filter(|_| cfg!(feature = "vertex-cache"));
        let count = if let Some(cache) = cache {
            // No clipping in this frame: each corner is its vertex's snapped projection,
            // computed once per frame.
            let corner = |v: Vec3| screen(view.to_camera(v));
            let mut count = 0usize;
            for (i, slot) in (0..n).zip(self.points.iter_mut()) {
                let position = || scene.polygon_vertex(polygon, i);
                *slot = match scene.vertex_index(polygon, i) {
                    Some(v) => cache.get(v, || corner(position())),
                    None => corner(position()),
                };
                count += 1;
            }
            count
        } else {
            for (i, slot) in (0..n).zip(self.clip_a.iter_mut()) {
                *slot = view.to_camera(scene.polygon_vertex(polygon, i));
            }
            let clipped = if self.all_inside {
                self.clip_a.get(..n as usize).unwrap_or(&[])
            } else {
                clip::clip_polygon(self.frustum.planes(), n as usize, self.clip_a, self.clip_b)?
            };
            let mut count = 0usize;
            for (slot, &c) in self.points.iter_mut().zip(clipped) {
                *slot = screen(c);
                count += 1;
            }
            count
        };
        if count < 3 {
            return Ok(());
        }
        let pts = self.points.get(..count).unwrap_or(&[]);
        let (width, height) = (self.view.width, self.view.height);
        // No pixel centre inside: the fill would draw nothing. All covered: nothing shows.
        let Some([x0, y0, x1, y1]) = fill::sample_rect::<SUB>(pts, width, height) else {
            return Ok(());
        };
        let (r0, r1) = (self.rows.start, self.rows.end);
        let (y0, y1) = (y0.max(r0), y1.min(r1));
        if y0 >= y1 {
            return Ok(());
        }
        if let Some(c) = coverage.as_deref() {
            if c.mode() != Mode::Measure && c.covers(x0, y0 - r0, x1, y1 - r0) {
                tally(&mut stats.polygons_culled_covered, 1);
                return Ok(());
            }
        }
        let colour = match self.paint {
            Paint::Colours => polygon.colour,
            Paint::Ids if cfg!(feature = "ids") => id_colour(scene.id(index).unwrap_or(u32::MAX)),
            Paint::Ids => polygon.colour,
        };
        tally(&mut stats.polygons_drawn, 1);
        // One fill for both cases (with and without span memory): one copy in the binary.
        // Its checks hold: `count <= available <= min(VERTS, MAX_FILL_VERTICES)` edges, and
        // `snap` keeps every point in the window, which `window` kept within
        // `fill::coordinate_limit`.
        let mut through = Through {
            coverage,
            sink,
            first_row: r0,
            pixels: 0,
        };
        let rows = self.rows.clone();
        fill::fill_in::<SUB, _>(pts, self.edges, width, rows, colour, &mut through);
        tally(&mut stats.pixels_written, through.pixels);
        Ok(())
    }
}

/// The sink the fill draws into: through the coverage when there is one (see
/// [`crate::coverage::CoverageSink`]; its row 0 is frame row `first_row`), else straight to
/// `sink`; counts the pixels forwarded.
struct Through<'c, 'm, S: SpanSink + ?Sized> {
    coverage: Option<&'c mut Coverage<'m>>,
    sink: &'c mut S,
    first_row: u32,
    pixels: u64,
}

impl<S: SpanSink + ?Sized> SpanSink for Through<'_, '_, S> {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        match self.coverage.as_deref_mut() {
            Some(c) => {
                let mut sink = Shifted {
                    sink: &mut *self.sink,
                    by: self.first_row,
                };
                let local = y.wrapping_sub(self.first_row);
                let n = c.span(local, x_start, x_end, colour, &mut sink);
                tally(&mut self.pixels, n);
            }
            None => {
                self.sink.span(y, x_start, x_end, colour);
                tally(&mut self.pixels, u64::from(x_end.saturating_sub(x_start)));
            }
        }
    }
}

/// A sink whose rows are `by` below the rows it is given: from a band's coverage rows back
/// to frame rows.
struct Shifted<'s, S: SpanSink + ?Sized> {
    sink: &'s mut S,
    by: u32,
}

impl<S: SpanSink + ?Sized> SpanSink for Shifted<'_, S> {
    #[inline]
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        self.sink
            .span(y.wrapping_add(self.by), x_start, x_end, colour);
    }
}

#[cfg(test)]
pub(crate) mod testing;

#[cfg(test)]
mod tests;

#[cfg(test)]
mod order_tests;

#[cfg(test)]
mod feature_tests;
