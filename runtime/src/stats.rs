//! What a frame reports: [`FrameStats`], the counters of one frame and how it ended (full,
//! or fallen back to back-to-front). A leaf module: the renderer fills it in, the scan-order
//! frame carries it, the CLI (`peel render --stats`), the benches and the tests read it, and
//! none of them reaches into another's module for it. Most of it compiles away without the
//! `stats` feature.

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
    /// The frame was anti-aliased ([`Renderer::antialias`](crate::render::Renderer::antialias); not when the span or scan
    /// memory ran out, which draws the frame without).
    pub antialiased: bool,
    /// A frame with objects: the steps of its order (world subtrees and hulls, and pieces of
    /// objects), which the object memory's `STEPS` must hold; 0 otherwise.
    pub object_steps: u32,
    /// A frame with objects: the most world planes that cut one object (each may add two
    /// vertices to a polygon: the clip buffers' `VERTS`); 0 otherwise.
    pub object_planes: u32,
    /// Front to back with transparent surfaces: the rows whose composite memory ran out, drawn
    /// with screen-door transparency instead ([`crate::composite`]); 0 otherwise.
    pub fallback_rows: u32,
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

/// A counter of [`Tally`], named after its [`FrameStats`] field.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Counter {
    PolygonsVisited,
    PolygonsDrawn,
    PixelsWritten,
    NodesCulledFrustum,
    NodesCulledCovered,
    PolygonsCulledCovered,
}

/// What a frame's walks count as they go: [`FrameStats`]'s counters with the `stats`
/// feature, and whether the walk stopped full. Without the feature it holds no counters, so
/// that a frame sets none up (their clear was most of a small build's frame set-up).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Tally {
    #[cfg(feature = "stats")]
    counts: [u64; 6],
    /// Front to back stopped early because every pixel was covered.
    pub(crate) stopped_full: bool,
    /// The frame fell back to back to front ([`FrameStats::fallback`]).
    pub(crate) fallback: bool,
    /// The frame was anti-aliased ([`FrameStats::antialiased`]).
    pub(crate) antialiased: bool,
    pub(crate) object_steps: u32,
    pub(crate) object_planes: u32,
    /// Rows fallen back to screen-door transparency ([`FrameStats::fallback_rows`]).
    pub(crate) fallback_rows: u32,
}

impl Tally {
    /// No counts yet, for a frame that `fallback`s from its start or not.
    pub(crate) fn new(fallback: bool) -> Self {
        Tally {
            fallback,
            ..Tally::default()
        }
    }

    /// `counter += n` (saturating) with the `stats` feature; nothing without it.
    /// A frame with objects: its steps and the most planes that cut one object.
    pub(crate) fn with_objects(self, steps: u32, planes: u32) -> Self {
        Tally {
            object_steps: steps,
            object_planes: planes,
            ..self
        }
    }

    #[inline(always)]
    pub(crate) fn add(&mut self, counter: Counter, n: u64) {
        #[cfg(feature = "stats")]
        {
            let c = &mut self.counts[counter as usize];
            *c = c.saturating_add(n);
        }
        #[cfg(not(feature = "stats"))]
        let _ = (counter, n);
    }

    /// The counter's value (0 without the `stats` feature).
    #[inline(always)]
    fn get(&self, counter: Counter) -> u64 {
        #[cfg(feature = "stats")]
        return self.counts[counter as usize];
        #[cfg(not(feature = "stats"))]
        {
            let _ = counter;
            0
        }
    }

    /// The frame's report: these counts and how the frame ended.
    pub(crate) fn report(&self, distinct_pixels: Option<u64>) -> FrameStats {
        FrameStats {
            polygons_visited: self.get(Counter::PolygonsVisited),
            polygons_drawn: self.get(Counter::PolygonsDrawn),
            pixels_written: self.get(Counter::PixelsWritten),
            nodes_culled_frustum: self.get(Counter::NodesCulledFrustum),
            nodes_culled_covered: self.get(Counter::NodesCulledCovered),
            polygons_culled_covered: self.get(Counter::PolygonsCulledCovered),
            distinct_pixels,
            stopped_full: self.stopped_full,
            fallback: self.fallback,
            antialiased: self.antialiased,
            object_steps: self.object_steps,
            object_planes: self.object_planes,
            fallback_rows: self.fallback_rows,
        }
    }
}
