//! The renderer: [`Renderer`], made once from a [`Workspace`] and optional span, vertex,
//! pending and scan memory, and its switches ([`Paint`], back to front, background, culling).
//! It exists apart from a frame's steps ([`super::frame`]) and the per-polygon work
//! ([`super::painter`]) so that what a caller chooses reads in one place; a frame borrows its
//! memory and runs its passes.

use glam::Vec3;

use super::frame::{self, Memory, Output, Settings};
use super::paint::Paint;
use super::{Content, FrameStats, Workspace};
use crate::camera::LocalView;
use crate::composite::Composite;
use crate::coverage::Coverage;
#[cfg(feature = "scan-order")]
use crate::display::Nowhere;
use crate::display::{Colour, Filter, SpanSink};
use crate::error::RenderError;
use crate::fill::{self, FixedPoint};
use crate::pending::Pending;
use crate::place::{self, ObjectMemory};
#[cfg(feature = "scan-order")]
use crate::scan::{Gaps, ScanFrame, ScanMemory};
use crate::traverse::{Order, StackEntry};
use crate::vertices::VertexCache;

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
    settings: Settings,
    /// Pending memory ([`Renderer::antialias`]).
    #[cfg(feature = "antialias")]
    pending: Option<Pending<'m>>,
    /// Scan memory ([`Renderer::scan_memory`]).
    #[cfg(feature = "scan-order")]
    scan: Option<ScanMemory<'m>>,
    /// Object memory ([`Renderer::object_memory`]).
    objects: Option<place::Memory<'m>>,
    /// Composite memory ([`Renderer::composite_memory`]).
    #[cfg(feature = "transparency")]
    composite: Option<Composite<'m>>,
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
            settings: Settings {
                back_to_front: false,
                paint: Paint::Colours,
                cull: true,
                cull_subtrees: true,
                integer_vertices: false,
                background: None,
                filter: Filter::Nearest,
            },
            #[cfg(feature = "antialias")]
            pending: None,
            #[cfg(feature = "scan-order")]
            scan: None,
            objects: None,
            #[cfg(feature = "transparency")]
            composite: None,
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
    pub fn draw_scan<C: Content + ?Sized>(
        &mut self,
        scene: &C,
        view: &LocalView,
    ) -> Result<ScanFrame<'_>, RenderError> {
        if self.settings.back_to_front {
            return Err(RenderError::NotFrontToBack);
        }
        let memory = self.scan.take().ok_or(RenderError::NotFrontToBack)?;
        let nodes = u32::try_from(memory.capacity()).unwrap_or(u32::MAX);
        // The scan memory is the frame's coverage while it is drawn.
        let mut coverage = Coverage::from_scan(memory);
        let rows = 0..view.height;
        let result = self.frame(
            scene,
            view,
            rows,
            &mut Nowhere,
            Some(&mut coverage),
            Output::Scan,
        );
        self.scan = coverage.into_scan();
        let stats = match result {
            Err(RenderError::SpanMemoryFull) => return Err(RenderError::ScanMemoryFull { nodes }),
            r => r?,
        };
        let memory = self.scan.as_ref().ok_or(RenderError::NotFrontToBack)?;
        let background = self.settings.background.unwrap_or_default();
        // An anti-aliased frame's pending pixels stay in the pool until the read-out.
        let pending = self.pending().filter(|_| stats.antialiased);
        Ok(ScanFrame {
            memory,
            background: background.to_rgb565(),
            gaps: Gaps::pending(pending, background),
            stats,
        })
    }

    /// Memory for frames with objects ([`crate::place::Posed`]): each object's placement and
    /// the frame's order. A frame of one scene never uses it.
    #[inline(always)]
    pub fn object_memory<const OBJECTS: usize, const STEPS: usize>(
        mut self,
        memory: &'m mut ObjectMemory<OBJECTS, STEPS>,
    ) -> Self {
        self.objects = Some(memory.into());
        self
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

    /// Paint source triangle ids (`id + 1` as 24-bit RGB, see [`id_colour`](super::id_colour)) instead of
    /// colours; a scene without ids then fails with [`RenderError::NoIds`].
    #[inline(always)]
    pub fn ids(mut self) -> Self {
        self.settings.paint = Paint::Ids;
        self
    }

    /// Paint back to front even with span memory (which then only counts distinct pixels).
    #[inline(always)]
    pub fn back_to_front(mut self) -> Self {
        self.settings.back_to_front = true;
        self
    }

    /// Write every pixel of every frame, those no polygon covers in `colour`: front to back
    /// each exactly once (the uncovered spans are emitted last, or before the fallback pass,
    /// from the span memory), back to front with the rows painted first. A display then needs
    /// no clear and no framebuffer: spans can go straight to it.
    #[inline(always)]
    pub fn background(mut self, colour: Colour) -> Self {
        self.settings.background = Some(colour);
        self
    }

    /// Draw without culling (see the module docs, "Culling"): the same pixels, more work;
    /// only to measure what culling saves.
    #[inline(always)]
    pub fn without_culling(mut self) -> Self {
        self.settings.cull = false;
        self
    }

    /// Walk every subtree without testing its box (culling polygons and clipping as before):
    /// the same pixels. On a core without an FPU a box test (some forty `f32` operations in
    /// software) costs more than the subtrees it skips save; with one it pays (see
    /// BENCHMARKS.md, "On the target"). The scene's box is still tested once per frame, to
    /// skip clipping when the scene is inside the view.
    #[inline(always)]
    pub fn without_subtree_culling(mut self) -> Self {
        self.settings.cull_subtrees = false;
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
        self.settings.integer_vertices = true;
        self
    }

    /// Textured polygons filtered bilinearly: each pixel the four texels around its centre's
    /// coordinates, weighted, instead of the one it falls in ([`Filter`]). Smoother where a
    /// texel spans several pixels; four loads and a blend a pixel.
    #[inline(always)]
    pub fn bilinear(mut self) -> Self {
        self.settings.filter = Filter::Bilinear;
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

    /// Composite memory for front-to-back frames of scenes with transparent surfaces (with the
    /// `transparency` feature; see [`crate::composite`]): per row, the runs of pixels behind
    /// them, each finished when an opaque surface or the background shows through. Without
    /// it such a frame is drawn back to front into a framebuffer (exact as well, with
    /// overdraw) and refused for a display ([`RenderError::CompositeMemory`]). Opaque scenes
    /// never use it.
    #[cfg(feature = "transparency")]
    #[inline(always)]
    pub fn composite_memory(mut self, composite: Composite<'m>) -> Self {
        self.composite = Some(composite);
        self
    }

    /// The composite memory, if any (after a frame: its peak); never without the
    /// `transparency` feature.
    pub fn composite(&self) -> Option<&Composite<'m>> {
        #[cfg(feature = "transparency")]
        return self.composite.as_ref();
        #[cfg(not(feature = "transparency"))]
        None
    }

    /// The pending pixels' memory, if any (after a frame: its peak); never without the
    /// `antialias` feature.
    pub fn pending(&self) -> Option<&Pending<'m>> {
        #[cfg(feature = "antialias")]
        return self.pending.as_ref();
        #[cfg(not(feature = "antialias"))]
        None
    }

    /// The order frames are drawn in: front to back exactly when span memory was given and
    /// back to front was not asked for.
    pub fn order(&self) -> Order {
        if self.coverage.is_some()
            && !self.settings.back_to_front
            && cfg!(feature = "front-to-back")
        {
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
    pub fn draw<C, S>(
        &mut self,
        scene: &C,
        view: &LocalView,
        target: &mut S,
    ) -> Result<FrameStats, RenderError>
    where
        C: Content + ?Sized,
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
    pub fn draw_rows<C, S>(
        &mut self,
        scene: &C,
        view: &LocalView,
        rows: core::ops::Range<u32>,
        target: &mut S,
    ) -> Result<FrameStats, RenderError>
    where
        C: Content + ?Sized,
        S: SpanSink + ?Sized,
    {
        let mut coverage = self.coverage.take();
        let once = target.write_once();
        let result = self.frame(
            scene,
            view,
            rows,
            target,
            coverage.as_mut(),
            Output::Sink { once },
        );
        self.coverage = coverage;
        result
    }

    /// A frame of rows `rows` into `target` through `coverage` (the span memory, or the scan
    /// memory), with the renderer's other memory: checked, then its passes.
    fn frame<C, S>(
        &mut self,
        scene: &C,
        view: &LocalView,
        rows: core::ops::Range<u32>,
        target: &mut S,
        coverage: Option<&mut Coverage<'m>>,
        output: Output,
    ) -> Result<FrameStats, RenderError>
    where
        C: Content + ?Sized,
        S: SpanSink + ?Sized,
    {
        #[cfg(feature = "antialias")]
        let pending = self.pending.as_mut();
        #[cfg(not(feature = "antialias"))]
        let pending = None;
        #[cfg(feature = "transparency")]
        let composite = self.composite.as_mut();
        #[cfg(not(feature = "transparency"))]
        let composite = None;
        let memory = Memory {
            stack: &mut self.stack[..],
            clip_a: &mut self.clip_a[..],
            clip_b: &mut self.clip_b[..],
            points: &mut self.points[..],
            edges: &mut self.edges[..],
            coverage,
            vertices: self.vertices.as_mut(),
            pending,
            composite,
            objects: self.objects.as_mut(),
        };
        // Scan order paints its gaps when the frame is read out.
        let background = self.settings.background.filter(|_| output != Output::Scan);
        frame::check(scene, view, rows, output, self.settings, memory)?
            .draw(scene, target, background)
    }
}
