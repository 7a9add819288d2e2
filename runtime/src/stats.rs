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
