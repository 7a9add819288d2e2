//! The painter: snapping, and [`Painter`], the per-polygon work of a frame (the traversal
//! walk with node culling, then cull, clip, project, snap and fill each polygon). It walks
//! and fills: where a polygon's spans go is a sink's business, the plain route through the
//! span memory ([`crate::coverage::Clipped`]) or the anti-aliased one through the pending
//! pixels ([`crate::pending::Antialiased`]). It exists apart from the frame's passes
//! ([`super::frame`]) because it is the hot loop: one copy of it serves both passes of a
//! frame, and its rules (the module docs' "Culling", the snapping slack) are what keep culling
//! pixel-neutral.

use glam::{Vec2, Vec3};

use super::paint::{id_colour, Paint};
use super::shade::PlaneShade;
#[cfg(feature = "textures")]
use super::texture::{texture_map, Corners};
use super::Source;
use crate::camera::LocalView;
use crate::clip::{self, Frustum};
use crate::composite::Composite;
#[cfg(feature = "transparency")]
use crate::composite::Composited;
use crate::coverage::{Clipped, Coverage, Mode};
#[cfg(feature = "transparency")]
use crate::display::{Colour, Transparent};
use crate::display::{Filter, SpanSink};
use crate::error::RenderError;
use crate::fill::gradient::Gradient;
use crate::fill::samples::{SAMPLE_COLUMNS, SAMPLE_ROWS};
#[cfg(feature = "textures")]
use crate::fill::texture::{Lighting, TextureMap};
use crate::fill::{self, FixedPoint};
use crate::pending::{Antialiased, Pending, SampleColour};
use crate::read::Polygon;
use crate::stats::{Counter, Tally};
use crate::traverse::{Order, StackEntry, Start, Traversal};
use crate::vertices::{IntegerView, VertexCache};

/// Snap a screen point to a [`FixedPoint<SUB>`] in the window (see the module docs);
/// `max_x`, `max_y` are `W * 2^SUB`, `H * 2^SUB`. A NaN lands on 0.
pub fn snap<const SUB: u32>(p: Vec2, max_x: i32, max_y: i32) -> FixedPoint<SUB> {
    // Saturating and NaN-safe: no overflow, no panic.
    let q = FixedPoint::<SUB>::snap(p.x, p.y);
    FixedPoint {
        x: q.x.clamp(0, max_x.max(0)),
        y: q.y.clamp(0, max_y.max(0)),
    }
}

/// How far, in pixels, a snapped vertex of an image `size` pixels wide (its larger side) may
/// lie outside the screen rectangle of its node's box ([`LocalView::box_on_screen`], which already
/// holds every computed camera-space position): snapping moves it by at most `2^-(SUB+1)` of
/// a pixel, and the rectangle's and the vertex's screen values each round by a few units in
/// their last place, below `size` where it matters. `1/64` of a pixel plus `size · 2^-18` (64
/// such units) bounds that with room to spare: about 0.018 pixel at 640 pixels.
fn slack<const SUB: u32>(size: u32) -> f32 {
    0.5 / (1u32 << SUB.min(30)) as f32 + 1.0 / 64.0 + size as f32 / (1u32 << 18) as f32
}

/// `ceil(v)` as a pixel index: 0 below zero and for NaN, saturating above.
pub(super) fn ceil_pixel(v: f32) -> u32 {
    // `as` maps NaN and negatives to 0.
    let t = v as u32;
    if (t as f32) < v {
        t.saturating_add(1)
    } else {
        t
    }
}

/// `floor(v)` as a pixel index: 0 below zero and for NaN, saturating above.
pub(super) fn floor_pixel(v: f32) -> u32 {
    // `as` maps NaN and negatives to 0 and truncates the rest.
    v as u32
}

/// Where a frame of one scene starts its walk: the root, known at compile time.
#[derive(Debug, Clone, Copy)]
pub(super) struct Root;

impl From<Root> for Start {
    #[inline(always)]
    fn from(_: Root) -> Start {
        Start::Root
    }
}

/// The cuts a painter clips its polygons by: none (a scene, a world's step: [`NoCuts`], so
/// that a build without objects carries no cut code) or a piece's ([`PieceCuts`]).
pub(super) trait Cuts: Copy {
    /// The cuts, in camera space.
    fn list(&self) -> &[clip::Cut];
    /// Where `polygon` lies against the cuts, when its corners' steps tell
    /// ([`Crossing::Crossed`] when they do not).
    fn crossing<T: Source + ?Sized>(&self, scene: &T, polygon: &Polygon) -> Crossing {
        let _ = (scene, polygon);
        Crossing::Crossed
    }
    /// Whether a cut leaves nothing of the box of steps `lo..=hi`, when the cuts are known in
    /// steps (`None` otherwise).
    fn removes_steps(&self, lo: [u16; 3], hi: [u16; 3]) -> Option<bool> {
        let _ = (lo, hi);
        None
    }
}

/// Where a polygon lies against a piece's cuts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Crossing {
    /// Wholly on the side each cut keeps, and crossing no plane: drawn as if uncut.
    Clear,
    /// Wholly on the side a cut removes: nothing of it is drawn.
    Removed,
    /// Crossing a plane (or not known): cut.
    Crossed,
}

/// A cut in a piece's vertex steps, in integers: `a · q + k` for the steps `q` of a vertex,
/// within `err` of the camera-space cut's value scaled (see [`StepCut::new`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct StepCut {
    a: [i32; 3],
    k: i32,
    err: i32,
    keep: clip::Keep,
}

impl StepCut {
    /// An unused entry.
    pub(super) const NONE: StepCut = StepCut {
        a: [0; 3],
        k: 0,
        err: 0,
        keep: clip::Keep::Both,
    };

    /// `cut` (camera space) for the vertices `min + q ∘ step` of an object seen by `view`
    /// (its local view): `cut(c) = m · (p - eye) + offset` with `m = n_x right + n_y up +
    /// n_z forward`, so `a = m ∘ step` and `k = m · (min - eye) + offset`, scaled so that
    /// `|a_i| <= 2^12` (`|a · q| < 2^30` for 16-bit steps) and `|k| <= 2^30`, in `i32`. `err`
    /// bounds the rounding of `a` and `k` to integers (half a unit each, times the steps)
    /// and of their `f32` sums, so a sign beyond `err` is the sign of the `f32` cut the
    /// clipper computes, whose error is far smaller.
    pub(super) fn new(cut: &clip::Cut, view: &LocalView, (min, step): (Vec3, Vec3)) -> StepCut {
        let n = cut.plane.normal;
        let m = view.right * n.x + view.up * n.y + view.forward * n.z;
        let a = m * step;
        let k = m.dot(min - view.eye) + cut.plane.offset;
        let largest = a.abs().max_element();
        let scale = if largest > 0.0 { 4096.0 / largest } else { 1.0 };
        let size = a.abs().element_sum() * 65_535.0
            + m.abs().dot((min - view.eye).abs())
            + cut.plane.offset.abs();
        let limit = (1u32 << 30) as f32;
        let k_scaled = (k * scale).clamp(-limit, limit);
        let a = [a.x, a.y, a.z].map(|v| libm::roundf(v * scale) as i32);
        // Rounding a: half a unit a step on each axis; k: one unit; the f32 sums: 2^-16 of
        // the magnitudes (generously).
        let err = 3 * 32_768 + 2 + (size * scale / 65_536.0).min(limit) as i32;
        StepCut {
            a,
            k: k_scaled as i32,
            err,
            keep: cut.keep,
        }
    }

    #[inline]
    fn value(&self, q: [u16; 3]) -> i32 {
        let [a0, a1, a2] = self.a;
        a0 * i32::from(q[0]) + a1 * i32::from(q[1]) + a2 * i32::from(q[2]) + self.k
    }
}

/// A piece's cuts: in camera space, and in its vertex steps when the object has them.
#[derive(Debug, Clone, Copy)]
pub(super) struct PieceCuts<'s> {
    pub(super) cuts: &'s [clip::Cut],
    pub(super) steps: Option<&'s [StepCut]>,
}

impl Cuts for PieceCuts<'_> {
    #[inline(always)]
    fn list(&self) -> &[clip::Cut] {
        self.cuts
    }

    fn removes_steps(&self, lo: [u16; 3], hi: [u16; 3]) -> Option<bool> {
        self.removes_box_steps(lo, hi)
    }

    fn crossing<T: Source + ?Sized>(&self, scene: &T, polygon: &Polygon) -> Crossing {
        let Some(steps) = self.steps.filter(|s| s.len() <= MAX_STEP_CUTS) else {
            return Crossing::Crossed;
        };
        // Per cut: every corner strictly above (`above`), strictly below (`below`).
        let (mut above, mut below) = ([true; MAX_STEP_CUTS], [true; MAX_STEP_CUTS]);
        for i in 0..u32::from(polygon.vertex_count) {
            let q = scene
                .vertex_index(polygon, i)
                .and_then(|v| scene.vertex_steps(v));
            let Some(q) = q else {
                return Crossing::Crossed;
            };
            for (j, s) in steps.iter().enumerate() {
                let e = s.value(q);
                above[j] &= e > s.err;
                below[j] &= e < -s.err;
            }
        }
        let mut clear = true;
        for (j, s) in steps.iter().enumerate() {
            let removed = match s.keep {
                clip::Keep::Plus => below[j],
                clip::Keep::Minus => above[j],
                clip::Keep::Both => false,
            };
            if removed {
                return Crossing::Removed;
            }
            clear &= above[j] || below[j];
        }
        if clear {
            Crossing::Clear
        } else {
            Crossing::Crossed
        }
    }
}

impl PieceCuts<'_> {
    /// [`Cuts::removes_steps`] for a piece.
    fn removes_box_steps(&self, lo: [u16; 3], hi: [u16; 3]) -> Option<bool> {
        let steps = self.steps?;
        Some(steps.iter().any(|s| {
            // The largest and smallest of `a · q + k` over the box, axis by axis.
            let (mut most, mut least) = (s.k, s.k);
            for i in 0..3 {
                let (x, y) = (s.a[i] * i32::from(lo[i]), s.a[i] * i32::from(hi[i]));
                most += x.max(y);
                least += x.min(y);
            }
            match s.keep {
                clip::Keep::Plus => most < -s.err,
                clip::Keep::Minus => least > s.err,
                clip::Keep::Both => false,
            }
        }))
    }
}

/// Most cuts [`PieceCuts::crossing`] tells polygons apart by (more: every polygon is cut).
pub(super) const MAX_STEP_CUTS: usize = 32;

/// Polygons of at most this many corners keep their corners' shared projections through a
/// cut (more: every point of theirs is projected from the cut's `f32`).
const KEPT_CORNERS: usize = 16;

/// No cuts: the painter of a frame of one scene.
#[derive(Debug, Clone, Copy)]
pub(super) struct NoCuts;

impl Cuts for NoCuts {
    #[inline(always)]
    fn list(&self) -> &[clip::Cut] {
        &[]
    }
}

/// The per-polygon work of a frame, with its buffers.
pub(super) struct Painter<'w, 'v, const SUB: u32, K: Cuts = NoCuts> {
    pub(super) view: &'w LocalView,
    /// The frame rows drawn (all of them, or a band).
    pub(super) rows: core::ops::Range<u32>,
    pub(super) frustum: Frustum,
    pub(super) max_x: i32,
    pub(super) max_y: i32,
    pub(super) available: u32,
    pub(super) paint: Paint,
    pub(super) cull: bool,
    /// Subtrees are tested against their boxes (see [`super::Renderer::without_subtree_culling`]).
    pub(super) cull_subtrees: bool,
    /// How textured polygons' pixels take their texels ([`super::Renderer::bilinear`]).
    #[cfg_attr(not(feature = "textures"), allow(dead_code))]
    pub(super) filter: Filter,
    /// Every polygon of the scene is inside the frustum (see [`Frustum::contains_box`]).
    pub(super) all_inside: bool,
    pub(super) clip_a: &'w mut [Vec3],
    pub(super) clip_b: &'w mut [Vec3],
    pub(super) points: &'w mut [FixedPoint<SUB>],
    pub(super) edges: &'w mut [fill::EdgeWalk],
    /// Projected vertices, in frames without clipping.
    pub(super) vertices: Option<&'w mut VertexCache<'v, SUB>>,
    /// The integer projection of the scene's steps, in frames without clipping that asked
    /// for it ([`super::Renderer::integer_vertices`]).
    #[cfg(feature = "integer-vertices")]
    pub(super) integer: Option<IntegerView>,
    /// Pending pixels, in an anti-aliased frame ([`super::Renderer::antialias`]).
    pub(super) antialias: Option<&'w mut Pending<'v>>,
    /// The runs behind transparent surfaces, in a front-to-back frame of a scene that has
    /// them ([`super::Renderer::composite_memory`]).
    pub(super) composite: Option<&'w mut Composite<'v>>,
    /// The screen-door pass of the rows that fell back ([`crate::composite`]): the fills go
    /// through the screen door, each pixel once.
    #[cfg_attr(not(feature = "transparency"), allow(dead_code))]
    pub(super) door: bool,
    /// The half-spaces, in camera space, a piece of a posed object is clipped to (none
    /// otherwise; see [`crate::place`]).
    pub(super) cuts: K,
}

impl<'v, const SUB: u32, K: Cuts> Painter<'_, 'v, SUB, K> {
    /// This painter for one part of a frame with objects: the part's `view` (the camera in its
    /// frame), whether it lies wholly inside the frustum, its integer projection, and the cuts
    /// of its piece. Vertex memory serves only a part that needs no clipping.
    pub(super) fn part<'s, C: Cuts>(
        &'s mut self,
        view: &'s LocalView,
        all_inside: bool,
        #[cfg(feature = "integer-vertices")] integer: Option<IntegerView>,
        cuts: C,
    ) -> Painter<'s, 'v, SUB, C> {
        // A piece's polygons that no cut crosses draw as if uncut (see `draw`).
        let unclipped = all_inside;
        Painter {
            view,
            rows: self.rows.clone(),
            frustum: self.frustum,
            max_x: self.max_x,
            max_y: self.max_y,
            available: self.available,
            paint: self.paint,
            cull: self.cull,
            cull_subtrees: self.cull_subtrees,
            filter: self.filter,
            all_inside,
            clip_a: &mut *self.clip_a,
            clip_b: &mut *self.clip_b,
            points: &mut *self.points,
            edges: &mut *self.edges,
            vertices: self.vertices.as_deref_mut().filter(|_| unclipped),
            #[cfg(feature = "integer-vertices")]
            integer: integer.filter(|_| unclipped),
            antialias: self.antialias.as_deref_mut(),
            composite: self.composite.as_deref_mut(),
            door: self.door,
            cuts,
        }
    }

    /// One walk of the tree in `order`, drawing every polygon it yields. In front-to-back
    /// mode ([`Mode::Exclusive`] coverage) it stops when the frame is full, or after the
    /// polygon whose span did not fit the span memory, which it returns. With `last` (the
    /// fallback pass) it stops after polygon `last`, which the first pass already counted.
    /// One function for both passes keeps one copy of the loop in the binary.
    /// `start` says where in the tree: the root ([`Root`], a frame of one scene, whose walk
    /// then has no code for the others) or a part of it (a frame with objects walks the world
    /// in parts).
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    pub(super) fn walk<T: Source + ?Sized, S: SpanSink + ?Sized, St: Into<Start>>(
        &mut self,
        scene: &T,
        order: Order,
        stack: &mut [StackEntry],
        mut coverage: Option<&mut Coverage<'_>>,
        sink: &mut S,
        stats: &mut Tally,
        last: Option<u32>,
        start: St,
    ) -> Result<Option<u32>, RenderError> {
        let mut traversal = Traversal::starting(scene, self.view.eye, order, stack, start.into())?;
        let exclusive = coverage
            .as_deref()
            .is_some_and(|c| c.mode() == Mode::Exclusive);
        let mut overflow = None;
        if self.all_inside {
            traversal.skip_solids_from_behind();
        }
        loop {
            if exclusive && coverage.as_deref().is_some_and(|c| c.is_full()) {
                stats.stopped_full = true;
                break;
            }
            let cov = coverage.as_deref();
            let next = traversal.next_polygon_entering(|node| self.enter(scene, node, cov, stats));
            let Some((index, polygon)) = next else { break };
            let interior = traversal.seen_interior();
            if last != Some(index) {
                stats.add(Counter::PolygonsVisited, 1);
            }
            let cov = coverage.as_deref_mut();
            self.draw(scene, index, &polygon, interior, cov, sink, stats)?;
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
    pub(super) fn enter<T: Source + ?Sized>(
        &self,
        scene: &T,
        node: u32,
        coverage: Option<&Coverage<'_>>,
        stats: &mut Tally,
    ) -> bool {
        // A piece of a posed object skips what its cuts leave nothing of, with or without the
        // other subtree tests: each piece would otherwise walk its object's whole tree.
        if !self.cuts.list().is_empty()
            && cfg!(feature = "bounds-culling")
            && self.cut_away(scene, node)
        {
            stats.add(Counter::NodesCulledFrustum, 1);
            return false;
        }
        if !(self.cull && self.cull_subtrees && cfg!(feature = "bounds-culling")) {
            return true;
        }
        self.test_subtree(scene, node, coverage, stats)
    }

    /// Whether a cut of this piece leaves nothing of node `node`'s subtree: in integers on the
    /// box's steps when the cuts are known in steps, else in `f32` on its camera box.
    #[inline(never)]
    fn cut_away<T: Source + ?Sized>(&self, scene: &T, node: u32) -> bool {
        let steps = scene.node_box_steps(node);
        if let Some(away) = steps.and_then(|(lo, hi)| self.cuts.removes_steps(lo, hi)) {
            return away;
        }
        let Some((lo, hi)) = scene.node_bounds(node) else {
            return false;
        };
        let b = self.view.box_to_camera(lo, hi);
        self.cuts.list().iter().any(|cut| cut.removes_box(&b))
    }

    /// [`Self::enter`]'s tests. Out of line on a soft-float ARM core: inlined into the walk,
    /// LLVM may compute some of its `f32` sums before the branch that skips them, each a
    /// library call there, for every node of a frame without subtree tests (the teapot's
    /// frame on the Cortex-M0+ took 2.4 times its instructions so when the painter borrowed
    /// the frame's integer view rather than copying it).
    #[cfg_attr(all(target_arch = "arm", not(target_abi = "eabihf")), inline(never))]
    fn test_subtree<T: Source + ?Sized>(
        &self,
        scene: &T,
        node: u32,
        coverage: Option<&Coverage<'_>>,
        stats: &mut Tally,
    ) -> bool {
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
            stats.add(Counter::NodesCulledFrustum, 1);
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
        // Anti-aliased, a pixel's samples lie within 0.4 pixel of its centre.
        let slack = slack::<SUB>(w.max(h)) + if self.antialiased() { 0.4 } else { 0.0 };
        let first = |v: f32, limit: u32| ceil_pixel(v - slack - 0.5).min(limit);
        let past = |v: f32, limit: u32| floor_pixel(v + slack + 0.5).min(limit);
        let (x0, y0) = (first(min.x, w), first(min.y, h).max(r0));
        let (x1, y1) = (past(max.x, w), past(max.y, h).min(r1));
        let covered = |c: &Coverage<'_>| c.covers(x0, y0 - r0, x1, y1 - r0);
        if x0 >= x1 || y0 >= y1 || coverage.is_some_and(covered) {
            stats.add(Counter::NodesCulledCovered, 1);
            return false;
        }
        true
    }

    /// Whether the frame is anti-aliased (never without the `antialias` feature: the
    /// optimiser then drops every anti-aliased path).
    #[inline(always)]
    fn antialiased(&self) -> bool {
        cfg!(feature = "antialias") && self.antialias.is_some()
    }

    /// Cull, clip, project, snap and fill polygon `index`, in the colour of its side the eye
    /// sees (its interior side when `interior`), through `coverage` when given.
    #[allow(clippy::too_many_arguments)]
    fn draw<T: Source + ?Sized, S: SpanSink + ?Sized>(
        &mut self,
        scene: &T,
        index: u32,
        polygon: &Polygon,
        interior: bool,
        coverage: Option<&mut Coverage<'_>>,
        sink: &mut S,
        stats: &mut Tally,
    ) -> Result<(), RenderError> {
        let n = u32::from(polygon.vertex_count);
        // (Each cut of a posed object's piece may add a vertex.)
        let needed = clip::buffer_len_for(n).saturating_add(self.cuts.list().len() as u32);
        if needed > self.available {
            // Only a source contradicting its own maximum gets here, or a piece with more
            // cuts than the buffers have room for.
            return Err(RenderError::PolygonTooLarge {
                needed,
                available: self.available,
            });
        }
        let (view, max_x, max_y) = (self.view, self.max_x, self.max_y);
        // Anti-aliased, the points are scaled to the sample grid (exact: the renderer checked
        // that the scaled window is in the fill's range), once per vertex with vertex memory.
        let antialiased = self.antialiased();
        let (c, r) = (SAMPLE_COLUMNS, SAMPLE_ROWS);
        // (`cfg!` inside: the closures below are not inlined, and a captured flag would be
        // tested per vertex in builds without anti-aliasing.)
        let grid = |p: FixedPoint<SUB>| {
            if cfg!(feature = "antialias") && antialiased {
                let (c, r) = (SAMPLE_COLUMNS as i32, SAMPLE_ROWS as i32);
                FixedPoint::new(p.x.wrapping_mul(c), p.y.wrapping_mul(r))
            } else {
                p
            }
        };
        let screen = |c: Vec3| grid(snap::<SUB>(view.project(c), max_x, max_y));
        // Without the feature there is never a cache: the test keeps that path out of the
        // binary (the optimiser cannot see through the painter's field).
        let cache = self
            .vertices
            .as_deref_mut()
            .filter(|_| cfg!(feature = "vertex-cache"));
        // Without the feature there are never integer vertices (nor the field).
        // Borrowed: a copy of the view (112 bytes) per polygon took a `memcpy` on ARMv6-M.
        #[cfg(feature = "integer-vertices")]
        let integer = self.integer.as_ref();
        #[cfg(not(feature = "integer-vertices"))]
        let integer: Option<&IntegerView> = None;
        // Smooth shading: which of the corners' intensities the side seen takes (`None`: the
        // polygon has one colour a side, or the frame paints ids).
        let side = match self.paint {
            Paint::Colours if cfg!(feature = "smooth") => scene.shade_side(polygon, interior),
            _ => None,
        };
        // The gradient of a smooth polygon that clipping gave new points, built while they are
        // at hand (the others' is built just before the fill).
        let mut clipped_gradient: Option<Gradient<SUB>> = None;
        // A piece's polygon: wholly cut away, wholly kept, or crossed by a cut.
        let mut crossed = !self.cuts.list().is_empty();
        let shared_corners = cache.is_some() || integer.is_some();
        if crossed && shared_corners {
            match self.cuts.crossing(scene, polygon) {
                Crossing::Clear => crossed = false,
                Crossing::Removed => return Ok(()),
                Crossing::Crossed => {}
            }
        }
        let count = if shared_corners && !crossed {
            // No clipping in this frame: each corner is its vertex's snapped projection,
            // computed once per frame when there is vertex memory.
            let corner = |v: Vec3| screen(view.to_camera(v));
            let shared = |v: u32| {
                let steps = integer.and_then(|g| scene.vertex_steps(v).map(|q| (g, q)));
                match steps {
                    Some((g, q)) => grid(g.point::<SUB>(q)),
                    None => corner(scene.vertex(v)),
                }
            };
            let mut cache = cache;
            let mut count = 0usize;
            for (i, slot) in (0..n).zip(self.points.iter_mut()) {
                *slot = match (scene.vertex_index(polygon, i), cache.as_deref_mut()) {
                    (Some(v), Some(c)) => c.get(v, || shared(v)),
                    (Some(v), None) => shared(v),
                    (None, _) => corner(scene.polygon_vertex(polygon, i)),
                };
                count += 1;
            }
            count
        } else {
            for (i, slot) in (0..n).zip(self.clip_a.iter_mut()) {
                *slot = view.to_camera(scene.polygon_vertex(polygon, i));
            }
            // A crossed polygon of a piece that needs no clipping otherwise: its corners that
            // the cuts keep take their shared projections (integer or cached), as its
            // neighbours that no cut crosses have them, so that no crack opens between them.
            let mut kept = [(Vec3::ZERO, FixedPoint::<SUB>::new(0, 0)); KEPT_CORNERS];
            let kept_count = if crossed && shared_corners && n as usize <= KEPT_CORNERS {
                let mut cache = self
                    .vertices
                    .as_deref_mut()
                    .filter(|_| cfg!(feature = "vertex-cache"));
                for (i, slot) in (0..n).zip(kept.iter_mut()) {
                    let c = self.clip_a.get(i as usize).copied().unwrap_or_default();
                    let corner = |v: Vec3| screen(view.to_camera(v));
                    let shared = |v: u32| {
                        let steps = integer.and_then(|g| scene.vertex_steps(v).map(|q| (g, q)));
                        match steps {
                            Some((g, q)) => grid(g.point::<SUB>(q)),
                            None => corner(scene.vertex(v)),
                        }
                    };
                    let p = match (scene.vertex_index(polygon, i), cache.as_deref_mut()) {
                        (Some(v), Some(cache)) => cache.get(v, || shared(v)),
                        (Some(v), None) => shared(v),
                        (None, _) => screen(c),
                    };
                    *slot = (c, p);
                }
                n as usize
            } else {
                0
            };
            // A smooth polygon about to be clipped: its plane's intensities, from its first
            // three corners (the compiler starts a list with its best-shaped three).
            let cut = crossed;
            let plane = match side {
                Some(side) if !self.all_inside || cut => {
                    let at = |k: usize| self.clip_a.get(k).copied().unwrap_or_default();
                    let shade = |k: u32| scene.corner_shade(polygon, k, side);
                    Some(PlaneShade::new(
                        [at(0), at(1), at(2)],
                        [shade(0), shade(1), shade(2)],
                    ))
                }
                _ => None,
            };
            let clipped = if cut {
                let planes = if self.all_inside {
                    &[][..]
                } else {
                    &self.frustum.planes()[..]
                };
                let cuts = self.cuts.list();
                clip::cut_polygon(cuts, planes, n as usize, self.clip_a, self.clip_b)?
            } else if self.all_inside {
                self.clip_a.get(..n as usize).unwrap_or(&[])
            } else {
                clip::clip_polygon(self.frustum.planes(), n as usize, self.clip_a, self.clip_b)?
            };
            let mut count = 0usize;
            let kept = kept.get(..kept_count).unwrap_or(&[]);
            for (slot, &c) in self.points.iter_mut().zip(clipped) {
                // (A corner the cuts kept is the very point given them, bit for bit.)
                let corner = kept.iter().find(|(k, _)| k.to_array() == c.to_array());
                *slot = match corner {
                    Some(&(_, p)) => p,
                    None => screen(c),
                };
                count += 1;
            }
            if let Some(plane) = plane {
                let kd = scene.colour_seen(index, polygon, interior);
                let pts = self.points.get(..count).unwrap_or(&[]);
                let at = |i: usize| clipped.get(i).copied().unwrap_or_default();
                clipped_gradient = Some(Gradient::of(pts, kd, |i| {
                    PlaneShade::level(plane.at(at(i)))
                }));
            }
            count
        };
        if count < 3 {
            return Ok(());
        }
        let (width, height) = (self.view.width, self.view.height);
        let pts = self.points.get(..count).unwrap_or(&[]);
        // No pixel centre (sample) inside: the fill would draw nothing. All covered: nothing
        // shows. Anti-aliased, `grid` is the samples' rectangle and `x0 .. y1` their pixels'.
        let (w, h) = if antialiased {
            // (In range: the renderer checked the scaled window.)
            (width.wrapping_mul(c), height.wrapping_mul(r))
        } else {
            (width, height)
        };
        let Some(grid) = fill::sample_rect(pts, w, h) else {
            return Ok(());
        };
        let [x0, y0, x1, y1] = if antialiased {
            let [x0, y0, x1, y1] = grid;
            [x0 / c, y0 / r, x1.div_ceil(c), y1.div_ceil(r)]
        } else {
            grid
        };
        let (r0, r1) = (self.rows.start, self.rows.end);
        let (y0, y1) = (y0.max(r0), y1.min(r1));
        if y0 >= y1 {
            return Ok(());
        }
        if let Some(c) = coverage.as_deref() {
            if c.mode() != Mode::Measure && c.covers(x0, y0 - r0, x1, y1 - r0) {
                stats.add(Counter::PolygonsCulledCovered, 1);
                return Ok(());
            }
            // (Anti-aliased, a polygon is not also tested at the samples of the pending pixels in
            // its box: drawing those that add none costs less than testing every polygon.)
        }
        let mut colour = match self.paint {
            Paint::Ids if cfg!(feature = "ids") => id_colour(scene.id(index).unwrap_or(u32::MAX)),
            Paint::Colours | Paint::Ids => scene.colour_seen(index, polygon, interior),
        };
        // A transparent polygon's opacity (opaque in an id image, whose pixels name the
        // nearest surface).
        #[cfg(feature = "transparency")]
        let opacity = match self.paint {
            Paint::Colours if cfg!(feature = "transparency") => scene.opacity(index, polygon),
            _ => u8::MAX,
        };
        stats.add(Counter::PolygonsDrawn, 1);
        // A smooth polygon's gradient (`colour` is then its material's), or its one colour
        // where the gradient is flat.
        let gradient = side.and_then(|side| {
            let g = clipped_gradient.unwrap_or_else(|| {
                Gradient::of(pts, colour, |i| scene.corner_shade(polygon, i as u32, side))
            });
            match g.flat_colour() {
                Some(flat) => {
                    colour = flat;
                    None
                }
                None => Some(g),
            }
        });
        // Checks the fills rely on: `count <= available <= min(VERTS, MAX_FILL_VERTICES)`
        // edges, and `snap` keeps every point in the window, which `window` kept within
        // `fill::coordinate_limit` (anti-aliased: the sample grid's window).
        // (`cfg!` here too: without it the optimiser kept the anti-aliased fill in builds
        // without the feature at `opt-level = "s"`.)
        // An anti-aliased textured polygon's map, on the pixel grid; a smooth one's texels
        // are lit by the pending pixels' shade.
        #[cfg(feature = "textures")]
        let antialiased_texture = if cfg!(feature = "antialias") && antialiased {
            let white = crate::display::Colour::grey(255);
            let lit = if gradient.is_some() { white } else { colour };
            let grid = (SAMPLE_COLUMNS, SAMPLE_ROWS);
            self.texture_map(scene, index, polygon, pts, grid, Lighting::Colour(lit))
        } else {
            None
        };
        #[cfg(not(feature = "textures"))]
        let antialiased_texture = None;
        let pending = match self.antialias.as_deref_mut() {
            Some(p) if cfg!(feature = "antialias") && antialiased => Some(p),
            _ => None,
        };
        let pixels = match (pending, coverage) {
            (Some(pending), Some(coverage)) => {
                // The sample rows of the pixel rows `y0 .. y1`, all in the band.
                let rect = [grid[0], grid[1].max(y0 * r), grid[2], grid[3].min(y1 * r)];
                let mut sink = Antialiased {
                    pending,
                    colour: SampleColour::new(colour),
                    gradient,
                    texture: antialiased_texture,
                    coverage,
                    sink,
                    first_row: r0,
                    pixels: 0,
                };
                let rows = y0 * r..y1 * r;
                fill::samples::fill_samples(pts, rect, self.edges, width * c, rows, &mut sink);
                sink.pixels
            }
            (_, coverage) => {
                let rect = [x0, y0, x1, y1];
                // Transparent surfaces front to back: through the composite memory (only in a
                // build with the feature: without it, this path is not compiled at all).
                #[cfg(feature = "transparency")]
                let coverage = match (self.composite.take(), coverage) {
                    (Some(composite), Some(coverage)) => {
                        // (Out of the painter while it fills: `fill_into` borrows it whole.)
                        let points = core::mem::take(&mut self.points);
                        let pts = points.get(..count).unwrap_or(&[]);
                        let mut sink = Composited {
                            composite: &mut *composite,
                            coverage,
                            sink,
                            first_row: r0,
                            pixels: 0,
                            door: self.door.then_some(width),
                        };
                        let filled = self.fill_into(
                            scene, index, polygon, pts, rect, gradient, colour, opacity, &mut sink,
                        );
                        let counted = sink.pixels;
                        self.composite = Some(composite);
                        self.points = points;
                        stats.add(Counter::PixelsWritten, filled.unwrap_or(counted));
                        return Ok(());
                    }
                    (composite, coverage) => {
                        self.composite = composite;
                        coverage
                    }
                };
                let mut sink = Clipped {
                    coverage,
                    sink,
                    first_row: r0,
                    pixels: 0,
                };
                let rows = self.rows.clone();
                // A textured polygon: its texels through its perspective map, lit by its
                // colour or its gradient.
                #[cfg(feature = "textures")]
                {
                    let lighting = match gradient {
                        Some(g) => Lighting::Smooth(g),
                        None => Lighting::Colour(colour),
                    };
                    let map = self.texture_map(scene, index, polygon, pts, (1, 1), lighting);
                    if let Some(mut map) = map {
                        let (edges, rows) = (&mut *self.edges, rows.clone());
                        let pixels =
                            fill::fill_in_rect(pts, rect, edges, width, rows, &mut map, &mut sink);
                        stats.add(Counter::PixelsWritten, pixels);
                        return Ok(());
                    }
                }
                match gradient {
                    Some(mut g) => {
                        fill::fill_in_rect(pts, rect, self.edges, width, rows, &mut g, &mut sink)
                    }
                    #[cfg(feature = "transparency")]
                    None if opacity < u8::MAX => {
                        let mut paint = Transparent { colour, opacity };
                        fill::fill_in_rect(
                            pts, rect, self.edges, width, rows, &mut paint, &mut sink,
                        )
                    }
                    None => fill::fill_in_rect(
                        pts,
                        rect,
                        self.edges,
                        width,
                        rows,
                        &mut { colour },
                        &mut sink,
                    ),
                };
                sink.pixels
            }
        };
        stats.add(Counter::PixelsWritten, pixels);
        Ok(())
    }

    /// Fill polygon `index` (its screen polygon `pts`, within `rect`) into `sink`: its texels
    /// through its perspective map (returning the pixels the fill drew), else its gradient,
    /// its colour at its `opacity`, or its one colour (returning `None`: the sink counts).
    #[cfg(feature = "transparency")]
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn fill_into<T: Source + ?Sized, S: SpanSink + ?Sized>(
        &mut self,
        scene: &T,
        index: u32,
        polygon: &Polygon,
        pts: &[FixedPoint<SUB>],
        rect: [u32; 4],
        gradient: Option<Gradient<SUB>>,
        colour: Colour,
        opacity: u8,
        sink: &mut S,
    ) -> Option<u64> {
        let (width, rows) = (self.view.width, self.rows.clone());
        // A textured polygon: its texels through its perspective map, lit by its colour or
        // its gradient.
        #[cfg(feature = "textures")]
        {
            let lighting = match gradient {
                Some(g) => Lighting::Smooth(g),
                None => Lighting::Colour(colour),
            };
            let map = self.texture_map(scene, index, polygon, pts, (1, 1), lighting);
            if let Some(mut map) = map {
                let (edges, rows) = (&mut *self.edges, rows.clone());
                return Some(fill::fill_in_rect(
                    pts, rect, edges, width, rows, &mut map, sink,
                ));
            }
        }
        #[cfg(not(feature = "textures"))]
        let _ = (scene, index, polygon);
        match gradient {
            Some(mut g) => fill::fill_in_rect(pts, rect, self.edges, width, rows, &mut g, sink),
            None if opacity < u8::MAX && cfg!(feature = "transparency") => {
                let mut paint = Transparent { colour, opacity };
                fill::fill_in_rect(pts, rect, self.edges, width, rows, &mut paint, sink)
            }
            None => fill::fill_in_rect(pts, rect, self.edges, width, rows, &mut { colour }, sink),
        };
        None
    }

    /// The perspective map of polygon `index` (whose screen polygon is `points`, on a grid of
    /// `grid` points a pixel) when the frame paints colours and the polygon is textured: its
    /// texels times `lighting`.
    #[cfg(feature = "textures")]
    fn texture_map<'t, T: Source + ?Sized>(
        &self,
        scene: &'t T,
        index: u32,
        polygon: &Polygon,
        points: &[FixedPoint<SUB>],
        grid: (u32, u32),
        lighting: Lighting<SUB>,
    ) -> Option<TextureMap<'t, SUB>> {
        if !matches!(self.paint, Paint::Colours) {
            return None;
        }
        let texture = scene.texture(index)?;
        let view = &self.view;
        let corners = [0, 1, 2].map(|i| view.to_camera(scene.polygon_vertex(polygon, i)));
        let uvs = [0, 1, 2].map(|i| scene.corner_uv(polygon, i));
        let mut reach = [0u32; 2];
        for i in 0..u32::from(polygon.vertex_count) {
            let uv = scene.corner_uv(polygon, i);
            reach = [
                reach[0].max(uv[0].unsigned_abs()),
                reach[1].max(uv[1].unsigned_abs()),
            ];
        }
        let corners = Corners {
            at: corners,
            uvs,
            reach,
        };
        texture_map(view, texture, corners, points, grid, lighting, self.filter)
    }
}
