//! Render: traverse, transform, clip, project, snap and fill, into a caller's [`SpanSink`].
//!
//! Everything a frame needs is checked before the first pixel ([`RenderError`]): the camera
//! fits the fixed-point range, the [`Workspace`] stack holds the tree's depth, its clip
//! buffers hold the largest polygon plus what clipping adds ([`clip::CLIP_PLANES`]), and id
//! rendering has ids to draw. A frame is then drawn completely or not at all.
//!
//! Snapping: a projected point `(sx, sy)` becomes the [`FixedPoint<SUB>`]
//! `(round(sx * 2^SUB), round(sy * 2^SUB))`, rounding to nearest (halves away from zero),
//! then clamped to the window `[0, W * 2^SUB] x [0, H * 2^SUB]` (clipped points may miss the
//! window by a rounding error). Snapping is a function of the point alone, so polygons sharing
//! an edge share its fixed-point ends bit for bit.
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
//!
//! The parts: what a scene offers the renderer ([`Source`]), the memory a frame uses
//! ([`Workspace`]), the renderer with its memory and switches ([`Renderer`]), a frame's checks
//! and passes as named steps (`frame.rs`), the per-polygon painter with snapping ([`snap`]),
//! what a polygon is painted with ([`Paint`]), and what a frame reports ([`FrameStats`], in
//! the leaf module [`crate::stats`]).
//!
//! [`RenderError`]: crate::error::RenderError
//! [`FixedPoint<SUB>`]: crate::fill::FixedPoint
//! [`SpanSink`]: crate::display::SpanSink
//! [`clip::CLIP_PLANES`]: crate::clip::CLIP_PLANES
//! [`Frustum::excludes_box`]: crate::clip::Frustum::excludes_box
//! [`Frustum::contains_box`]: crate::clip::Frustum::contains_box

mod content;
mod frame;
mod objects;
mod paint;
mod painter;
mod renderer;
mod shade;
mod source;
#[cfg(feature = "textures")]
mod texture;
mod workspace;

pub use crate::stats::FrameStats;
pub use content::{Content, Drawn};
pub use paint::{id_colour, Paint};
pub use painter::snap;
pub use renderer::Renderer;
pub use source::Source;
pub use workspace::Workspace;

#[cfg(test)]
pub(crate) mod testing;

#[cfg(test)]
mod tests;

#[cfg(test)]
mod order_tests;

#[cfg(test)]
mod feature_tests;

#[cfg(all(test, feature = "smooth"))]
mod smooth_tests;
#[cfg(all(test, feature = "textures"))]
mod texture_tests;
#[cfg(all(test, feature = "transparency", feature = "front-to-back"))]
mod transparency_tests;
