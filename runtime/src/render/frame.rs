//! A frame, step by step: the checks before the first pixel ([`check`]), then the passes,
//! each a named step of [`Frame`]: the background first (back to front), the first pass in
//! the frame's order (anti-aliased: again without anti-aliasing when its memory runs out),
//! the fallback pass (span memory exhausted: the rest back to front), the background last
//! (front to back). Where the pixels go is passed in ([`Output`]): a sink, or the scan
//! memory, which a scan-order frame reads out afterwards. The renderer only picks the memory
//! and the output; the painter only walks and fills.

use core::ops::Range;

use glam::Vec3;

use super::paint::Paint;
use super::painter::Painter;
use super::{FrameStats, Source};
use crate::camera::LocalView;
use crate::clip::{self, Frustum};
use crate::coverage::{Coverage, Mode};
use crate::display::{Colour, SpanSink};
use crate::error::RenderError;
use crate::fill::{self, FixedPoint};
use crate::pending::{self, Pending};
use crate::stats::{Counter, Tally};
use crate::traverse::{Order, StackEntry};
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
pub(super) fn check<'a, 'm, T, const SUB: u32>(
    scene: &T,
    view: &'a LocalView,
    rows: Range<u32>,
    output: Output,
    settings: Settings,
    memory: Memory<'a, 'm, SUB>,
) -> Result<Frame<'a, 'm, SUB>, RenderError>
where
    T: Source + ?Sized,
{
    view.check()?;
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
    } = memory;
    let asked_front_to_back = coverage.is_some() && !settings.back_to_front;
    let order = if asked_front_to_back && cfg!(feature = "front-to-back") {
        Order::FrontToBack
    } else {
        Order::BackToFront
    };
    let once = match output {
        Output::Sink { once } => once,
        Output::Scan => true,
    };
    let paint = settings.paint;
    // Without the features the memory is never used: the optimiser drops that code.
    let mut coverage = coverage.filter(|_| cfg!(feature = "front-to-back"));
    let vertices = vertices.filter(|_| cfg!(feature = "vertex-cache"));
    let (width, height) = (view.width, view.height);
    let (max_x, max_y) = window::<SUB>(width, height)?;
    if paint == Paint::Ids && !(cfg!(feature = "ids") && scene.has_ids()) {
        return Err(RenderError::NoIds);
    }
    let needed = clip::buffer_len_for(scene.max_polygon_vertices());
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
    let scene_box = || scene.root().and_then(|root| scene.node_bounds(root));
    let all_inside = cull
        && cfg!(feature = "bounds-culling")
        && scene_box().is_some_and(|(lo, hi)| frustum.contains_box(view, lo, hi));
    #[cfg(feature = "integer-vertices")]
    let integer = if settings.integer_vertices && all_inside {
        scene_box()
            .zip(scene.step_grid())
            .and_then(|(bounds, grid)| IntegerView::new::<SUB>(view, grid, bounds, max_x, max_y))
    } else {
        None
    };
    // Only frames without clipping use it (see `crate::vertices`).
    let mut vertices = vertices.filter(|_| all_inside);
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
        if p.height() < band {
            return Err(RenderError::PendingMemory);
        }
        p.clear();
    }
    if let Some(c) = coverage.as_deref_mut() {
        c.set_mode(if order == Order::FrontToBack {
            Mode::Exclusive
        } else {
            Mode::Measure
        });
    }
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
        all_inside,
        clip_a,
        clip_b,
        points,
        edges,
        vertices,
        #[cfg(feature = "integer-vertices")]
        integer,
        antialias: pending,
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
        // Front to back was asked for, but the feature is off: painted back to front.
        tally: Tally::new(asked_front_to_back && order == Order::BackToFront),
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
    tally: Tally,
}

impl<const SUB: u32> Frame<'_, '_, SUB> {
    /// Every pass in turn, into `target`, over `background` where it has one (the caller's
    /// setting: held in the frame, LLVM did not prove it unchanged by the walks and kept the
    /// background's code in builds that never set one).
    pub(super) fn draw<T, S>(
        mut self,
        scene: &T,
        target: &mut S,
        background: Option<Colour>,
    ) -> Result<FrameStats, RenderError>
    where
        T: Source + ?Sized,
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
        if let Some(last) = overflow {
            self.fallback(scene, target, last, background)?;
        } else if order == Order::FrontToBack {
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
    fn first_pass<T, S>(
        &mut self,
        scene: &T,
        target: &mut S,
        background: Option<Colour>,
    ) -> Result<(Option<u32>, u64), RenderError>
    where
        T: Source + ?Sized,
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

    /// Pass 2 (span memory exhausted at polygon `last`): the polygons from the farthest up to
    /// `last`, back to front, clipped against the frozen coverage, over the background.
    fn fallback<T, S>(
        &mut self,
        scene: &T,
        target: &mut S,
        last: u32,
        background: Option<Colour>,
    ) -> Result<(), RenderError>
    where
        T: Source + ?Sized,
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

    /// One walk of the tree in the frame's order (see [`Painter::walk`]).
    fn walk<T, S>(
        &mut self,
        scene: &T,
        target: &mut S,
        last: Option<u32>,
    ) -> Result<Option<u32>, RenderError>
    where
        T: Source + ?Sized,
        S: SpanSink + ?Sized,
    {
        self.painter.walk(
            scene,
            self.order,
            &mut self.stack[..],
            self.coverage.as_deref_mut(),
            target,
            &mut self.tally,
            last,
        )
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
