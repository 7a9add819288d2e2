//! A frame, step by step: the checks before the first pixel ([`check`]), then the passes,
//! each a named step of [`Frame`]: the background first (back to front), the first pass in
//! the frame's order (anti-aliased: again without anti-aliasing when its memory runs out),
//! the fallback pass (span memory exhausted: the rest back to front), the background last
//! (front to back). Where the pixels go is passed in ([`Output`]): a sink, or the scan
//! memory, which a scan-order frame reads out afterwards. The renderer only picks the memory
//! and the output; the painter only walks and fills.

use core::ops::Range;

use glam::Vec3;

use super::content::{Content, Drawn};
use super::objects::{self, MAX_CUTS};
use super::paint::Paint;
use super::painter::{NoCuts, Painter, PieceCuts, Root, StepCut};
use super::{FrameStats, Source};
use crate::camera::LocalView;
use crate::clip::{self, Frustum};
use crate::composite::Composite;
use crate::coverage::{Coverage, Mode};
use crate::display::{Colour, Filter, SpanSink};
use crate::error::RenderError;
use crate::fill::{self, FixedPoint};
use crate::pending::{self, Pending};
use crate::place::{self, Posed, Step};
use crate::stats::{Counter, Tally};
use crate::traverse::{Order, StackEntry, Start};
#[cfg(feature = "integer-vertices")]
use crate::vertices::IntegerView;
use crate::vertices::VertexCache;

/// Where a frame's pixels go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Output {
    /// Into the target sink; `once`: each pixel at most once (a display streamed span by
    /// span, [`SpanSink::write_once`]), so front to back or nothing.
    Sink {
        /// The sink takes each pixel once.
        once: bool,
    },
    /// Into the scan memory, which is the frame's coverage: front to back or nothing, no
    /// background (the read-out paints the gaps), pending pixels left for the read-out.
    Scan,
}

/// The renderer's switches a frame reads.
#[derive(Debug, Clone, Copy)]
pub(super) struct Settings {
    pub(super) back_to_front: bool,
    pub(super) paint: Paint,
    pub(super) cull: bool,
    pub(super) cull_subtrees: bool,
    pub(super) integer_vertices: bool,
    pub(super) background: Option<Colour>,
    pub(super) filter: Filter,
}

/// The memory a frame draws with, borrowed from the renderer (the coverage from the scan
/// memory in scan order).
pub(super) struct Memory<'a, 'm, const SUB: u32> {
    pub(super) stack: &'a mut [StackEntry],
    pub(super) clip_a: &'a mut [Vec3],
    pub(super) clip_b: &'a mut [Vec3],
    pub(super) points: &'a mut [FixedPoint<SUB>],
    pub(super) edges: &'a mut [fill::EdgeWalk],
    pub(super) coverage: Option<&'a mut Coverage<'m>>,
    pub(super) vertices: Option<&'a mut VertexCache<'m, SUB>>,
    pub(super) pending: Option<&'a mut Pending<'m>>,
    /// Composite memory, for a front-to-back frame with transparent surfaces.
    pub(super) composite: Option<&'a mut Composite<'m>>,
    /// Object memory, for a frame with objects.
    pub(super) objects: Option<&'a mut place::Memory<'m>>,
}

/// Where a walk stopped: the step of a frame with objects (0 for a frame of one scene) and
/// the polygon there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Mark {
    step: usize,
    polygon: u32,
}

/// The root box of a scene, when it stores one.
fn root_box<T: Source + ?Sized>(scene: &T) -> Option<(Vec3, Vec3)> {
    scene.root().and_then(|root| scene.node_bounds(root))
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

/// The frame of rows `rows` of `view`, checked (see the module docs of [`super`]) and ready
/// for its passes; the memory is cleared for it.
#[allow(clippy::too_many_arguments)]
pub(super) fn check<'a, 'm, C, const SUB: u32>(
    content: &C,
    view: &'a LocalView,
    rows: Range<u32>,
    output: Output,
    settings: Settings,
    memory: Memory<'a, 'm, SUB>,
) -> Result<Frame<'a, 'm, SUB>, RenderError>
where
    C: Content + ?Sized,
{
    view.check()?;
    let drawn = content.drawn();
    if rows.start > rows.end || rows.end > view.height {
        return Err(RenderError::RowsOutsideImage {
            start: rows.start,
            end: rows.end,
            height: view.height,
        });
    }
    let Memory {
        stack,
        clip_a,
        clip_b,
        points,
        edges,
        coverage,
        vertices,
        pending,
        composite,
        objects,
    } = memory;
    let paint = settings.paint;
    // Transparent surfaces in a frame of colours: front to back through the composite
    // memory; without it, into a sink that takes overdraw, back to front (exact too).
    let transparent = cfg!(feature = "transparency")
        && paint == Paint::Colours
        && match drawn {
            Drawn::One(scene) => scene.has_transparency(),
            Drawn::Posed(posed) => {
                posed.world.is_some_and(|w| w.has_transparency())
                    || posed.objects.iter().any(|o| o.scene.has_transparency())
            }
        };
    let composite = composite.filter(|_| transparent);
    let asked_front_to_back = coverage.is_some() && !settings.back_to_front;
    let once_sink = matches!(output, Output::Sink { once: true } | Output::Scan);
    if transparent && composite.is_none() && asked_front_to_back && once_sink {
        return Err(RenderError::CompositeMemory);
    }
    let composed = !transparent || composite.is_some();
    let order = if asked_front_to_back && cfg!(feature = "front-to-back") && composed {
        Order::FrontToBack
    } else {
        Order::BackToFront
    };
    let once = match output {
        Output::Sink { once } => once,
        Output::Scan => true,
    };
    // Without the features the memory is never used: the optimiser drops that code.
    let mut coverage = coverage.filter(|_| cfg!(feature = "front-to-back"));
    let vertices = vertices.filter(|_| cfg!(feature = "vertex-cache"));
    let (width, height) = (view.width, view.height);
    let (max_x, max_y) = window::<SUB>(width, height)?;
    let (has_ids, max_vertices) = match drawn {
        Drawn::One(scene) => (scene.has_ids(), scene.max_polygon_vertices()),
        Drawn::Posed(posed) => objects::parts_summary(posed, stack.len())?,
    };
    if paint == Paint::Ids && !(cfg!(feature = "ids") && has_ids) {
        return Err(RenderError::NoIds);
    }
    let needed = clip::buffer_len_for(max_vertices);
    let buffers = [
        clip_a.len(),
        clip_b.len(),
        points.len(),
        edges.len(),
        fill::MAX_FILL_VERTICES,
    ];
    let shortest = buffers.into_iter().min().unwrap_or(0);
    let available = u32::try_from(shortest).unwrap_or(u32::MAX);
    if needed > available {
        return Err(RenderError::PolygonTooLarge { needed, available });
    }
    let band = rows.end - rows.start;
    if let Some(c) = coverage.as_deref_mut() {
        if c.width() != width || c.height() < band {
            return Err(RenderError::SpanMemory);
        }
        c.clear();
        c.use_rows(band);
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
    let cull = settings.cull;
    let scene_box = || match drawn {
        Drawn::One(scene) => root_box(scene),
        Drawn::Posed(posed) => posed.world.and_then(|w| root_box(&w)),
    };
    let all_inside = cull
        && cfg!(feature = "bounds-culling")
        && scene_box().is_some_and(|(lo, hi)| frustum.contains_box(view, lo, hi));
    #[cfg(feature = "integer-vertices")]
    let integer = if settings.integer_vertices && all_inside {
        let grid = match drawn {
            Drawn::One(scene) => scene.step_grid(),
            Drawn::Posed(posed) => posed.world.and_then(|w| w.step_grid()),
        };
        scene_box()
            .zip(grid)
            .and_then(|(bounds, grid)| IntegerView::new::<SUB>(view, grid, bounds, max_x, max_y))
    } else {
        None
    };
    // Only frames without clipping use it (see `crate::vertices`); with objects, each part
    // that needs none.
    let posed = matches!(drawn, Drawn::Posed(_));
    let mut vertices = vertices.filter(|_| all_inside || posed);
    if let Some(v) = vertices.as_deref_mut() {
        v.next_frame();
    }
    // Anti-aliased: front to back in colours, with the sample grid in the fill's range.
    let mut pending = pending.filter(|_| {
        cfg!(feature = "antialias")
            && order == Order::FrontToBack
            && paint == Paint::Colours
            && coverage.is_some()
            && window::<SUB>(
                width.saturating_mul(fill::samples::SAMPLE_COLUMNS),
                height.saturating_mul(fill::samples::SAMPLE_ROWS),
            )
            .is_ok()
    });
    if let Some(p) = pending.as_deref_mut() {
        if transparent {
            return Err(RenderError::AntialiasedTransparency);
        }
        if p.height() < band {
            return Err(RenderError::PendingMemory);
        }
        p.clear();
    }
    let mut composite = composite.filter(|_| order == Order::FrontToBack);
    if let Some(c) = composite.as_deref_mut() {
        if c.height() < band || !c.holds_a_row(width) {
            return Err(RenderError::CompositeMemory);
        }
        c.clear();
    }
    if let Some(c) = coverage.as_deref_mut() {
        c.set_mode(if order == Order::FrontToBack {
            Mode::Exclusive
        } else {
            Mode::Measure
        });
    }
    // A frame with objects: their placements and the frame's order.
    let (objects, steps, planes) = match drawn {
        Drawn::One(_) => (None, 0, 0),
        Drawn::Posed(posed) => {
            let memory = objects.ok_or(RenderError::ObjectMemory)?;
            let (steps, planes) = objects::prepare(posed, view, max_vertices, available, memory)?;
            (Some(memory), steps, planes)
        }
    };
    let painter = Painter::<SUB> {
        view,
        rows: rows.clone(),
        frustum,
        max_x,
        max_y,
        available,
        paint,
        cull,
        cull_subtrees: settings.cull_subtrees,
        filter: settings.filter,
        all_inside,
        clip_a,
        clip_b,
        points,
        edges,
        vertices,
        #[cfg(feature = "integer-vertices")]
        integer,
        antialias: pending,
        composite,
        door: false,
        cuts: NoCuts,
    };
    Ok(Frame {
        painter,
        stack,
        coverage,
        order,
        once,
        output,
        width,
        rows,
        objects,
        steps,
        integer_vertices: settings.integer_vertices,
        backdrop: settings.background,
        // Front to back was asked for, but the feature is off: painted back to front.
        tally: Tally::new(asked_front_to_back && order == Order::BackToFront)
            .with_objects(steps as u32, planes as u32),
    })
}

/// A checked frame and its passes.
pub(super) struct Frame<'a, 'm, const SUB: u32> {
    painter: Painter<'a, 'm, SUB>,
    stack: &'a mut [StackEntry],
    coverage: Option<&'a mut Coverage<'m>>,
    order: Order,
    once: bool,
    output: Output,
    width: u32,
    rows: Range<u32>,
    /// A frame with objects: its memory, holding `steps` steps of its order.
    objects: Option<&'a mut place::Memory<'m>>,
    steps: usize,
    integer_vertices: bool,
    /// The renderer's background, which finishes the runs behind transparent surfaces (a
    /// scan-order frame's too, whose gaps the read-out paints).
    #[cfg_attr(not(feature = "transparency"), allow(dead_code))]
    backdrop: Option<Colour>,
    tally: Tally,
}

impl<const SUB: u32> Frame<'_, '_, SUB> {
    /// Every pass in turn, into `target`, over `background` where it has one (the caller's
    /// setting: held in the frame, LLVM did not prove it unchanged by the walks and kept the
    /// background's code in builds that never set one).
    pub(super) fn draw<C, S>(
        mut self,
        scene: &C,
        target: &mut S,
        background: Option<Colour>,
    ) -> Result<FrameStats, RenderError>
    where
        C: Content + ?Sized,
        S: SpanSink + ?Sized,
    {
        // Read once, before the walks, for the same reason.
        let (order, once) = (self.order, self.once);
        let (width, rows) = (self.width, self.rows.clone());
        // Back to front: the background first, then every polygon over it.
        if order == Order::BackToFront {
            paint_background(background, None, width, &rows, target);
        }
        let (overflow, kept) = self.first_pass(scene, target, background)?;
        if overflow.is_some() && once {
            // No overdraw on a display (nor in scan memory): the frame stops here.
            return Err(RenderError::SpanMemoryFull);
        }
        // (Only a build with transparency has composite memory in a frame, or this code.)
        let composited = cfg!(feature = "transparency") && self.painter.composite.is_some();
        if overflow.is_some() && composited {
            // Runs cannot be drawn over: the whole frame again, back to front.
            self.again_back_to_front(scene, target, background)?;
        } else if let Some(last) = overflow {
            self.fallback(scene, target, last, background)?;
        } else if order == Order::FrontToBack {
            #[cfg(feature = "transparency")]
            if composited {
                return self.finish_composited(scene, target, background, kept);
            }
            let coverage = self.coverage.as_deref();
            if coverage.is_some() {
                paint_background(background, coverage, width, &rows, target);
            }
        }
        let distinct = match self.coverage.as_deref() {
            Some(c) if !c.exhausted() && !self.tally.fallback => Some(c.covered() + kept),
            _ => None,
        };
        Ok(self.tally.report(distinct))
    }

    /// Pass 1, in the frame's order. Anti-aliased, its pending pixels end the pass: drained
    /// into `target` with the background for their uncovered samples, or (scan order) kept
    /// for the read-out; and when its span (or scan) memory runs out, the pass runs again
    /// without anti-aliasing, unless the sink is a display, which must not be drawn over (it
    /// gets the error instead; a scan-order frame has sent nothing yet). Returns the polygon
    /// whose span did not fit, if any, and the pixels kept pending.
    fn first_pass<C, S>(
        &mut self,
        scene: &C,
        target: &mut S,
        background: Option<Colour>,
    ) -> Result<(Option<Mark>, u64), RenderError>
    where
        C: Content + ?Sized,
        S: SpanSink + ?Sized,
    {
        loop {
            let overflow = self.walk(scene, target, None)?;
            // (Never without the feature: the optimiser drops the drain.)
            let antialiased = self.painter.antialias.take();
            let antialiased = antialiased.filter(|_| cfg!(feature = "antialias"));
            let (Some(p), Some(c)) = (antialiased, self.coverage.as_deref_mut()) else {
                return Ok((overflow, 0));
            };
            match (overflow, self.output) {
                (None, Output::Scan) => {
                    // Kept: the read-out puts them into the scan memory's gaps (each drained
                    // into it would cost a node).
                    let kept = p.in_use() as u64;
                    self.tally.add(Counter::PixelsWritten, kept);
                    self.tally.antialiased = true;
                    return Ok((None, kept));
                }
                (None, Output::Sink { .. }) => {
                    let first_row = self.rows.start;
                    let background = background.unwrap_or_default();
                    let sent = pending::drain(p, c, target, first_row, background);
                    self.tally.add(Counter::PixelsWritten, sent);
                    self.tally.antialiased = true;
                    return Ok((None, 0));
                }
                (Some(_), Output::Sink { once: true }) => return Ok((overflow, 0)),
                (Some(_), _) => {
                    p.clear();
                    c.clear();
                    c.use_rows(self.rows.end - self.rows.start);
                    c.set_mode(Mode::Exclusive);
                }
            }
        }
    }

    /// A front-to-back frame with transparent surfaces whose span memory ran out: its runs
    /// cannot be drawn over, so the whole frame is painted again back to front, the
    /// background first (a sink that takes overdraw: a display's frame stopped instead).
    fn again_back_to_front<C, S>(
        &mut self,
        scene: &C,
        target: &mut S,
        background: Option<Colour>,
    ) -> Result<(), RenderError>
    where
        C: Content + ?Sized,
        S: SpanSink + ?Sized,
    {
        self.tally.fallback = true;
        self.painter.composite = None;
        let coverage = self.coverage.take();
        paint_background(background, None, self.width, &self.rows, target);
        self.order = Order::BackToFront;
        let walked = self.walk(scene, target, None);
        self.coverage = coverage;
        walked.map(|_| ())
    }

    /// The end of a front-to-back frame with transparent surfaces: the runs finished with the
    /// background (in scan memory, kept there), then the rows that fell back drawn again.
    #[cfg(feature = "transparency")]
    fn finish_composited<C, S>(
        mut self,
        scene: &C,
        target: &mut S,
        background: Option<Colour>,
        kept: u64,
    ) -> Result<FrameStats, RenderError>
    where
        C: Content + ?Sized,
        S: SpanSink + ?Sized,
    {
        let rows = self.rows.clone();
        let backdrop = self.backdrop;
        if let (Some(composite), Some(coverage)) = (
            self.painter.composite.as_deref_mut(),
            self.coverage.as_deref_mut(),
        ) {
            let band = rows.end - rows.start;
            composite.finish_rows(coverage, backdrop, band, rows.start, target);
            self.tally.fallback_rows = composite.fallen_rows();
        }
        if self.tally.fallback_rows > 0 {
            self.screen_door_pass(scene, target, background)?;
        }
        let distinct = match self.coverage.as_deref() {
            // (Scan memory, which the runs went into.)
            Some(c) if c.exhausted() => return Err(RenderError::SpanMemoryFull),
            Some(c) if self.tally.fallback_rows == 0 => Some(c.covered() + kept),
            _ => None,
        };
        Ok(self.tally.report(distinct))
    }

    /// The rows that fell back to screen-door transparency, drawn again front to back (see
    /// [`crate::composite`]): a walk a group of them, then the group's background.
    #[cfg(feature = "transparency")]
    fn screen_door_pass<C, S>(
        &mut self,
        scene: &C,
        target: &mut S,
        background: Option<Colour>,
    ) -> Result<(), RenderError>
    where
        C: Content + ?Sized,
        S: SpanSink + ?Sized,
    {
        let (band, first_row, width) =
            (self.rows.end - self.rows.start, self.rows.start, self.width);
        // (Scan order: the read-out paints the gaps.)
        let background = background.filter(|_| self.output != Output::Scan);
        let mut from = 0;
        loop {
            let (Some(composite), Some(coverage)) = (
                self.painter.composite.as_deref_mut(),
                self.coverage.as_deref(),
            ) else {
                return Ok(());
            };
            let Some(until) = composite.next_group(from, band, coverage) else {
                return Ok(());
            };
            // The same walk as the first pass's, its fills through the screen door.
            self.painter.door = true;
            let walked = self.walk(scene, target, None);
            self.painter.door = false;
            walked?;
            if let Some(composite) = self.painter.composite.as_deref_mut() {
                composite.end_group(until, width, background, first_row, target);
            }
            from = until;
        }
    }

    /// Pass 2 (span memory exhausted at polygon `last`): the polygons from the farthest up to
    /// `last`, back to front, clipped against the frozen coverage, over the background.
    fn fallback<C, S>(
        &mut self,
        scene: &C,
        target: &mut S,
        last: Mark,
        background: Option<Colour>,
    ) -> Result<(), RenderError>
    where
        C: Content + ?Sized,
        S: SpanSink + ?Sized,
    {
        let Some(c) = self.coverage.as_deref_mut() else {
            return Ok(());
        };
        self.tally.fallback = true;
        c.freeze();
        // What pass 2 draws, it draws over this (it paints back to front).
        let coverage = self.coverage.as_deref();
        paint_background(background, coverage, self.width, &self.rows, target);
        self.order = Order::BackToFront;
        self.walk(scene, target, Some(last))?;
        Ok(())
    }

    /// One walk of the tree in the frame's order (see [`Painter::walk`]); with objects, of
    /// the frame's steps.
    #[inline(always)]
    fn walk<C, S>(
        &mut self,
        scene: &C,
        target: &mut S,
        last: Option<Mark>,
    ) -> Result<Option<Mark>, RenderError>
    where
        C: Content + ?Sized,
        S: SpanSink + ?Sized,
    {
        match scene.drawn() {
            Drawn::One(scene) => {
                let overflow = self.painter.walk(
                    scene,
                    self.order,
                    &mut self.stack[..],
                    self.coverage.as_deref_mut(),
                    target,
                    &mut self.tally,
                    last.map(|m| m.polygon),
                    Root,
                )?;
                Ok(overflow.map(|polygon| Mark { step: 0, polygon }))
            }
            Drawn::Posed(posed) => self.walk_steps(posed, target, last),
        }
    }

    /// The steps of a frame with objects in the frame's order (back to front as planned,
    /// front to back reversed), each part with its view, its clipping and its cuts; with
    /// `last`, up to that polygon of that step.
    fn walk_steps<S>(
        &mut self,
        posed: &Posed<'_, '_>,
        target: &mut S,
        last: Option<Mark>,
    ) -> Result<Option<Mark>, RenderError>
    where
        S: SpanSink + ?Sized,
    {
        let Frame {
            painter,
            stack,
            coverage,
            order,
            objects,
            steps,
            integer_vertices,
            tally,
            ..
        } = self;
        let Some(memory) = objects.as_deref() else {
            return Ok(None);
        };
        let (order, n) = (*order, *steps);
        let view = painter.view;
        let world_inside = painter.all_inside;
        #[cfg(feature = "integer-vertices")]
        let world_integer = painter.integer;
        let cull = painter.cull && cfg!(feature = "bounds-culling");
        // Which part the vertex memory holds (`u32::MAX`: the world's).
        let mut cached = None;
        for i in 0..n {
            let at = if order == Order::BackToFront {
                i
            } else {
                n - 1 - i
            };
            let Some(&step) = memory.steps.get(at) else {
                break;
            };
            let last_here = last.filter(|m| m.step == at).map(|m| m.polygon);
            let overflow = match step {
                Step::Subtree(_) | Step::Hull { .. } => {
                    let Some(world) = posed.world.as_ref() else {
                        continue;
                    };
                    let start = match step {
                        Step::Hull { node, interior } => Start::Hull { node, interior },
                        Step::Subtree(node) => Start::Subtree(node),
                        Step::Piece { .. } => Start::Root,
                    };
                    if world_inside && cached != Some(u32::MAX) {
                        if let Some(v) = painter.vertices.as_deref_mut() {
                            v.next_frame();
                        }
                        cached = Some(u32::MAX);
                    }
                    let mut part = painter.part(
                        view,
                        world_inside,
                        #[cfg(feature = "integer-vertices")]
                        world_integer,
                        NoCuts,
                    );
                    part.walk(
                        world,
                        order,
                        &mut stack[..],
                        coverage.as_deref_mut(),
                        target,
                        tally,
                        last_here,
                        start,
                    )?
                }
                Step::Piece { object, cut } => {
                    let k = usize::from(object);
                    let (Some(o), Some(placement)) =
                        (posed.objects.get(k), memory.placements.get(k))
                    else {
                        continue;
                    };
                    let local = place::object_view(view, placement);
                    let bounds = root_box(&o.scene);
                    let inside = cull
                        && bounds
                            .is_some_and(|(lo, hi)| painter.frustum.contains_box(&local, lo, hi));
                    let mut cuts = [objects::NO_CLIP_CUT; MAX_CUTS];
                    let planned = memory.steps.get(..n).unwrap_or(&[]);
                    let count = objects::camera_cuts(
                        planned,
                        &memory.cuts[..],
                        object,
                        cut,
                        view,
                        &mut cuts,
                    );
                    // The cuts in the object's vertex steps, which tell the polygons no cut
                    // crosses (drawn as if uncut) and those cut away.
                    let mut step_cuts = [StepCut::NONE; MAX_CUTS];
                    let grid = o.scene.step_grid();
                    if let Some(grid) = grid {
                        for (s, c) in step_cuts.iter_mut().zip(&cuts[..count]) {
                            *s = StepCut::new(c, &local, grid);
                        }
                    }
                    let piece = PieceCuts {
                        cuts: &cuts[..count],
                        steps: grid.map(|_| &step_cuts[..count]),
                    };
                    #[cfg(feature = "integer-vertices")]
                    let integer = if *integer_vertices && inside {
                        bounds.zip(o.scene.step_grid()).and_then(|(b, grid)| {
                            IntegerView::new::<SUB>(&local, grid, b, painter.max_x, painter.max_y)
                        })
                    } else {
                        None
                    };
                    #[cfg(not(feature = "integer-vertices"))]
                    let _ = integer_vertices;
                    let part_id = u32::from(object);
                    if inside && cached != Some(part_id) {
                        if let Some(v) = painter.vertices.as_deref_mut() {
                            v.next_frame();
                        }
                        cached = Some(part_id);
                    }
                    let mut part = painter.part(
                        &local,
                        inside,
                        #[cfg(feature = "integer-vertices")]
                        integer,
                        piece,
                    );
                    part.walk(
                        &o.scene,
                        order,
                        &mut stack[..],
                        coverage.as_deref_mut(),
                        target,
                        tally,
                        last_here,
                        Start::Root,
                    )?
                }
            };
            if let Some(polygon) = overflow {
                return Ok(Some(Mark { step: at, polygon }));
            }
            if last_here.is_some() {
                break;
            }
        }
        Ok(None)
    }
}

/// The background, if the frame has one, where `coverage` does not cover.
fn paint_background<S: SpanSink + ?Sized>(
    background: Option<Colour>,
    coverage: Option<&Coverage<'_>>,
    width: u32,
    rows: &Range<u32>,
    target: &mut S,
) {
    if let Some(colour) = background {
        paint_uncovered(coverage, width, rows.clone(), colour, target);
    }
}

/// Paint in `colour` the pixels of frame rows `rows`, `width` wide, that `coverage` does not
/// cover (its row `y` being frame row `rows.start + y`): all of them without one. (One copy
/// for its three callers.)
#[inline(never)]
fn paint_uncovered<S: SpanSink + ?Sized>(
    coverage: Option<&Coverage<'_>>,
    width: u32,
    rows: Range<u32>,
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
