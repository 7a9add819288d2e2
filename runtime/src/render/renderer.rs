//! The renderer: [`Renderer`], made once from a [`Workspace`] and optional span and vertex
//! memory, its switches ([`Paint`], back to front, background, culling), and a frame's
//! checks and passes. It exists apart from the per-polygon work ([`super::painter`]) so
//! that what a caller chooses and what is checked before the first pixel read in one
//! place; the painter only draws.

use glam::Vec3;

use super::painter::Painter;
#[cfg(feature = "antialias")]
use super::painter::Shifted;
use super::{FrameStats, Source, Workspace};
use crate::camera::LocalView;
use crate::clip::{self, Frustum};
use crate::coverage::{Coverage, Mode};
use crate::display::{Colour, SpanSink};
use crate::error::RenderError;
use crate::fill::{self, FixedPoint};
#[cfg(feature = "antialias")]
use crate::pending::Pending;
#[cfg(feature = "scan-order")]
use crate::scan::{Gaps, ScanFrame, ScanMemory};
use crate::traverse::{Order, StackEntry};
#[cfg(feature = "integer-vertices")]
use crate::vertices::IntegerView;
use crate::vertices::VertexCache;

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

/// The window in fixed point, or [`RenderError::ImageTooLarge`] (beyond `i32`, or beyond
/// [`fill::coordinate_limit`] without the `wide-coordinates` feature).
pub(super) fn window<const SUB: u32>(width: u32, height: u32) -> Result<(i32, i32), RenderError> {
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
/// use peel_runtime::display::{Framebuffer, Xrgb8888};
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
/// - culling on, which never changes a pixel ([`Renderer::without_culling`] to measure it;
///   [`Renderer::without_subtree_culling`] keeps all but the subtree box tests, for cores
///   where those cost more than they save).
///
/// `SUB` is the precision of its screen points ([`fill::FixedPoint<SUB>`]), that of its
/// [`Workspace`] and vertex memory: the default [`fill::SUBPIXEL_BITS`] with
/// [`Renderer::new`], another with [`Renderer::with_precision`].
#[derive(Debug)]
pub struct Renderer<'m, const SUB: u32 = { fill::SUBPIXEL_BITS }> {
    stack: &'m mut [StackEntry],
    clip_a: &'m mut [Vec3],
    clip_b: &'m mut [Vec3],
    points: &'m mut [FixedPoint<SUB>],
    edges: &'m mut [fill::EdgeWalk],
    coverage: Option<Coverage<'m>>,
    vertices: Option<VertexCache<'m, SUB>>,
    back_to_front: bool,
    paint: Paint,
    cull: bool,
    cull_subtrees: bool,
    integer_vertices: bool,
    background: Option<Colour>,
    #[cfg(feature = "antialias")]
    pending: Option<Pending<'m>>,
    /// Scan memory ([`Renderer::scan_memory`]).
    #[cfg(feature = "scan-order")]
    scan: Option<ScanMemory<'m>>,
    /// A scan-order frame is being drawn: its coverage is the scan memory, nothing is sent.
    #[cfg(feature = "scan-order")]
    scan_pass: bool,
}

/// A sink that draws nothing (scan order keeps its spans in the scan memory).
#[cfg(feature = "scan-order")]
struct Nowhere;

#[cfg(feature = "scan-order")]
impl SpanSink for Nowhere {
    #[inline]
    fn span(&mut self, _: u32, _: u32, _: u32, _: Colour) {}
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
    /// [`Renderer::new`] at `SUB` fractional bits, over a workspace of that precision:
    /// `Renderer::with_precision(&mut ws)` with `ws: Workspace<STACK, VERTS, 4>`.
    #[inline(always)]
    pub fn with_precision<const STACK: usize, const VERTS: usize>(
        workspace: &'m mut Workspace<STACK, VERTS, SUB>,
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
            cull_subtrees: true,
            integer_vertices: false,
            background: None,
            #[cfg(feature = "antialias")]
            pending: None,
            #[cfg(feature = "scan-order")]
            scan: None,
            #[cfg(feature = "scan-order")]
            scan_pass: false,
        }
    }

    /// Scan memory for frames in scan order ([`Renderer::draw_scan`]; feature `scan-order`):
    /// each covered interval kept with its colour, the frame then read out row by row.
    #[cfg(feature = "scan-order")]
    #[inline(always)]
    pub fn scan_memory(mut self, memory: ScanMemory<'m>) -> Self {
        self.scan = Some(memory);
        self
    }

    /// Draw `scene` seen by `view` front to back into the scan memory ([`Renderer::scan_memory`])
    /// and return the frame, to be sent to a display in scan order: every row top to bottom,
    /// the pixels no polygon covers in the background colour ([`Renderer::background`], black
    /// without one), in one address window ([`ScanFrame::pixels`], `ScanFrame::draw_to` with
    /// `embedded-graphics`) or a row at a time ([`ScanFrame::row_into`]). Nothing reaches a
    /// display during the walk.
    ///
    /// Anti-aliased ([`Renderer::antialias`]): the finished pixels go into the scan memory
    /// with their colours, the partly covered ones stay in the pending pool (not drained
    /// into the scan memory, where each would cost a node), and the read-out merges each
    /// row's pending pixels into its gaps, their uncovered samples in the background colour:
    /// the anti-aliased frame [`Renderer::draw`] gives. The frame borrows the pool until it
    /// is dropped. It mostly needs more nodes than the plain frame (a pending pixel splits
    /// the interval it would have joined); when the memory runs out, the frame is drawn again
    /// without anti-aliasing (nothing was sent yet), so every pixel is the anti-aliased or
    /// exactly the plain one ([`FrameStats::antialiased`] says which).
    ///
    /// Never back to front: [`RenderError::NotFrontToBack`] without scan memory or with
    /// [`Renderer::back_to_front`], and [`RenderError::ScanMemoryFull`] when the frame needs
    /// more nodes than the memory holds, without anti-aliasing too (nothing was sent: the
    /// panel keeps its last frame). The other errors are [`Renderer::draw`]'s.
    #[cfg(feature = "scan-order")]
    pub fn draw_scan<T: Source + ?Sized>(
        &mut self,
        scene: &T,
        view: &LocalView,
    ) -> Result<ScanFrame<'_>, RenderError> {
        if self.back_to_front {
            return Err(RenderError::NotFrontToBack);
        }
        let memory = self.scan.take().ok_or(RenderError::NotFrontToBack)?;
        let nodes = u32::try_from(memory.capacity()).unwrap_or(u32::MAX);
        let saved = self.coverage.replace(Coverage::from_scan(memory));
        self.scan_pass = true;
        let result = self.draw_rows(scene, view, 0..view.height, &mut Nowhere);
        self.scan_pass = false;
        let used = core::mem::replace(&mut self.coverage, saved);
        self.scan = used.and_then(Coverage::into_scan);
        let stats = match result {
            Err(RenderError::SpanMemoryFull) => return Err(RenderError::ScanMemoryFull { nodes }),
            r => r?,
        };
        let memory = self.scan.as_ref().ok_or(RenderError::NotFrontToBack)?;
        let background = self.background.unwrap_or_default();
        // An anti-aliased frame's pending pixels stay in the pool until the read-out.
        #[cfg(feature = "antialias")]
        let gaps = Gaps::pending(
            self.pending.as_ref().filter(|_| stats.antialiased),
            background,
        );
        #[cfg(not(feature = "antialias"))]
        let gaps = Gaps::default();
        Ok(ScanFrame {
            memory,
            background: background.to_rgb565(),
            gaps,
            stats,
        })
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
    pub fn vertex_memory(mut self, vertices: VertexCache<'m, SUB>) -> Self {
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

    /// Walk every subtree without testing its box (culling polygons and clipping as before):
    /// the same pixels. On a core without an FPU a box test (some forty `f32` operations in
    /// software) costs more than the subtrees it skips save; with one it pays (see
    /// BENCHMARKS.md, "On the target"). The scene's box is still tested once per frame, to
    /// skip clipping when the scene is inside the view.
    #[inline(always)]
    pub fn without_subtree_culling(mut self) -> Self {
        self.cull_subtrees = false;
        self
    }

    /// Project and snap the vertices in integer arithmetic in frames without clipping, for
    /// scenes of 16-bit vertices on an exact grid (the compiler's), when the frame's error
    /// bound holds (see [`crate::vertices`], "Integer vertices": among others, the depths of
    /// the scene's box within a factor of about 4 of each other, as in an orbit from 1.7
    /// bounding radii or farther, and a window side below `2^18` subpixel units, 1,023 pixels
    /// at 8 bits; other frames take the `f32` path). Points then differ from the `f32` path's
    /// by a unit in their last place now and then, so pixels can differ along edges; the same
    /// bits on every core, and culling stays exact. On a core without an FPU it saves most of
    /// a vertex's cost (thousands of instructions in software floats); with one it costs more
    /// than the `f32` path. With the `integer-vertices` feature; without it the option is
    /// ignored.
    #[inline(always)]
    pub fn integer_vertices(mut self) -> Self {
        self.integer_vertices = true;
        self
    }

    /// Anti-aliased frames (with the `antialias` feature): each pixel the average of its
    /// [`SAMPLES`](crate::fill::samples::SAMPLES) samples' colours, each sample taking the
    /// nearest polygon covering it (front to back, the first) and the background colour
    /// (black without [`Renderer::background`]) where none does; partly covered pixels wait
    /// in `pending` (see [`crate::pending`]). Only frames drawn front to back in colours are
    /// anti-aliased: when the span memory runs out the frame is drawn again without
    /// anti-aliasing (a display sink, whose [`SpanSink::write_once`] holds, gets
    /// [`RenderError::SpanMemoryFull`] instead), and back-to-front and id frames are drawn
    /// without it ([`FrameStats::antialiased`] says which). Scan-order frames
    /// ([`Renderer::draw_scan`]) are anti-aliased too: their pending pixels stay in `pending`
    /// until the [`ScanFrame`] is read out, and a frame whose scan memory runs out is drawn
    /// again without anti-aliasing.
    #[cfg(feature = "antialias")]
    #[inline(always)]
    pub fn antialias(mut self, pending: Pending<'m>) -> Self {
        self.pending = Some(pending);
        self
    }

    /// The pending pixels' memory, if any (after a frame: its peak).
    #[cfg(feature = "antialias")]
    pub fn pending(&self) -> Option<&Pending<'m>> {
        self.pending.as_ref()
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
    /// for a view that is degenerate ([`LocalView::check`]), an image too large for the
    /// fixed-point range, a stack or clip buffers too small for the scene, span memory of
    /// another size than the view's image, or ids asked of a scene without them. Never panics.
    pub fn draw<T, S>(
        &mut self,
        scene: &T,
        view: &LocalView,
        target: &mut S,
    ) -> Result<FrameStats, RenderError>
    where
        T: Source + ?Sized,
        S: SpanSink + ?Sized,
    {
        self.draw_rows(scene, view, 0..view.height, target)
    }

    /// [`Renderer::draw`] of frame rows `rows` only: a band, for firmware that sends a frame
    /// to its display band by band instead of keeping a framebuffer. The target gets the same
    /// spans as in the whole frame's draw, with frame row numbers (a [`Framebuffer::band`]
    /// takes them), and subtrees whose screen box misses the band are skipped. Span memory,
    /// if given, is for the band: a [`Coverage`] `view.width` wide and at least `rows.len()`
    /// high (its first rows are used, so one serves every band, the shorter last one too).
    /// Also an error: rows outside the image ([`RenderError::RowsOutsideImage`]).
    ///
    /// [`Framebuffer::band`]: crate::display::Framebuffer::band
    pub fn draw_rows<T, S>(
        &mut self,
        scene: &T,
        view: &LocalView,
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
        let order = self.order();
        // A display streamed span by span, or a scan-order frame: front to back or nothing.
        #[cfg(feature = "scan-order")]
        let scan_pass = self.scan_pass;
        #[cfg(not(feature = "scan-order"))]
        let scan_pass = false;
        let once = scan_pass || target.write_once();
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
        // Through `black_box`: knowing the order past this check, LLVM specialised the walk of
        // a streamed frame for it and laid it out 2% slower (the teapot on both cores).
        if once && core::hint::black_box(order) != Order::FrontToBack {
            return Err(RenderError::NotFrontToBack);
        }
        let frustum = Frustum::new(view);
        // The whole scene inside the frustum (the usual case for an object in view): no
        // subtree needs the frustum test and no polygon needs clipping. Bounds are only trusted
        // when culling is on, as for every other use of them.
        let scene_box = || scene.root().and_then(|root| scene.node_bounds(root));
        let all_inside = cull
            && cfg!(feature = "bounds-culling")
            && scene_box().is_some_and(|(lo, hi)| frustum.contains_box(view, lo, hi));
        #[cfg(feature = "integer-vertices")]
        let integer = if self.integer_vertices && all_inside {
            scene_box()
                .zip(scene.step_grid())
                .and_then(|(bounds, grid)| {
                    IntegerView::new::<SUB>(view, grid, bounds, max_x, max_y)
                })
        } else {
            None
        };
        // Only frames without clipping use it (see `crate::vertices`).
        let mut vertices = vertices.filter(|_| all_inside);
        if let Some(v) = vertices.as_deref_mut() {
            v.next_frame();
        }
        // Anti-aliased: front to back in colours, with the sample grid in the fill's range.
        #[cfg(feature = "antialias")]
        let mut pending = self.pending.as_mut().filter(|_| {
            order == Order::FrontToBack
                && paint == Paint::Colours
                && coverage.is_some()
                && window::<SUB>(
                    width.saturating_mul(fill::samples::SAMPLE_COLUMNS),
                    height.saturating_mul(fill::samples::SAMPLE_ROWS),
                )
                .is_ok()
        });
        #[cfg(feature = "antialias")]
        if let Some(p) = pending.as_deref_mut() {
            if p.height() < rows.end - rows.start {
                return Err(RenderError::PendingMemory);
            }
            p.clear();
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
            cull_subtrees: self.cull_subtrees,
            all_inside,
            clip_a: &mut self.clip_a[..],
            clip_b: &mut self.clip_b[..],
            points: &mut self.points[..],
            edges: &mut self.edges[..],
            vertices,
            #[cfg(feature = "integer-vertices")]
            integer,
            #[cfg(feature = "antialias")]
            antialias: pending,
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
        // Scan order paints its gaps when the frame is read out.
        let background = if scan_pass { None } else { self.background };
        // Back to front: the background first, then every polygon over it.
        if let (Some(colour), Order::BackToFront) = (background, order) {
            paint_uncovered(None, width, first_row..end_row, colour, target);
        }

        // Pixels left pending for a scan-order frame's read-out.
        #[cfg(feature = "antialias")]
        let mut kept = 0u64;
        #[cfg(not(feature = "antialias"))]
        let kept = 0u64;
        // Pass 1: the frame's order; anti-aliased, again without if its span (or scan) memory
        // runs out (a display, which must not be drawn over, gets the error below instead; a
        // scan-order frame has sent nothing yet).
        #[cfg_attr(not(feature = "antialias"), allow(clippy::never_loop))]
        let overflow = loop {
            let overflow = painter.walk(
                scene,
                order,
                &mut self.stack[..],
                coverage.as_deref_mut(),
                target,
                &mut stats,
                None,
            )?;
            #[cfg(feature = "antialias")]
            if let (Some(p), Some(c)) = (painter.antialias.take(), coverage.as_deref_mut()) {
                if overflow.is_none() && scan_pass {
                    // Kept: the read-out puts them into the scan memory's gaps (each drained
                    // into it would cost a node).
                    kept = p.in_use() as u64;
                    stats.pixels_written += kept;
                    stats.antialiased = true;
                } else if overflow.is_none() {
                    // The pending pixels take the background for their uncovered samples.
                    let mut sink = Shifted {
                        sink: &mut *target,
                        by: first_row,
                    };
                    let mut through = crate::coverage::CoverageSink {
                        coverage: c,
                        sink: &mut sink,
                        pixels: 0,
                    };
                    p.drain(background.unwrap_or_default(), &mut through);
                    stats.pixels_written += through.pixels;
                    stats.antialiased = true;
                } else if !once || scan_pass {
                    p.clear();
                    c.clear();
                    c.use_rows(end_row - first_row);
                    c.set_mode(Mode::Exclusive);
                    continue;
                }
            }
            break overflow;
        };

        // Pass 2 (span memory exhausted at polygon `last`): the polygons from the farthest up
        // to `last`, back to front, clipped against the frozen coverage.
        if overflow.is_some() && once {
            // No overdraw on a display: the frame stops here.
            return Err(RenderError::SpanMemoryFull);
        }
        if let (Some(last), Some(c)) = (overflow, coverage.as_deref_mut()) {
            stats.fallback = true;
            c.freeze();
            // What pass 2 draws, it draws over this (it paints back to front).
            if let Some(colour) = background {
                paint_uncovered(Some(c), width, first_row..end_row, colour, target);
            }
            painter.walk(
                scene,
                Order::BackToFront,
                &mut self.stack[..],
                coverage.as_deref_mut(),
                target,
                &mut stats,
                Some(last),
            )?;
        }
        if let (Some(colour), Order::FrontToBack, None) = (background, order, overflow) {
            if let Some(c) = coverage.as_deref() {
                paint_uncovered(Some(c), width, first_row..end_row, colour, target);
            }
        }
        stats.distinct_pixels = match coverage.as_deref() {
            Some(c) if !c.exhausted() && !stats.fallback => Some(c.covered() + kept),
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
