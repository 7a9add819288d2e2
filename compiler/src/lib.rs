//! Peel's offline scene compiler.
//!
//! Pipeline (one module per stage, see ARCHITECTURE.md): `load` (OBJ + MTL -> source
//! triangles) -> `quantise` (power-of-two integer grid) -> `planes` (exact integer planes and
//! predicates) -> `peel` (convex-hull layers) / `split` (exact cuts and the choice of the
//! splitting plane) -> `tree` (the display tree and its invariants) -> `shade` (baked Lambert
//! colours) and `texture` (texture coordinates) -> `write` (the `.peel` bytes, written
//! atomically).
//!
//! The public API is what a build script or a tool needs: [`Builder`] (compile an OBJ from
//! `build.rs`), [`compile`] and [`load`] (the whole compile in one call, of a file or of a
//! mesh), the [`tree`] and [`shade`] types those take and return, [`write`](mod@write) (the
//! atomic file write), [`dump`] (a `.peel` file as YAML or counters). Apart from the pipeline,
//! [`tools`] holds the host tools and the test and benchmark support: `raster`, `reference`,
//! `scenes`, `shading_gap`, `texture_check`, and with the `bench` feature `bench_frames`
//! (`peel bench`) and `bench_compile` (`peel bench compile`); the `png` feature adds
//! `tools::raster::png`. The other stages are private.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod builder;
mod bvh;
pub mod compile;
pub mod dump;
mod error;
mod hash;
pub mod load;
mod peel;
mod planes;
mod quantise;
mod random;
pub mod shade;
pub mod shadow;
mod split;
mod texture;
pub mod tools;
pub mod tree;
pub mod write;

pub use builder::sizes::{FrameMemory, MeasuredSpans};
pub use builder::{spans, Builder, Output};
pub use error::CompileError;

/// The exact side-of-plane predicates, for the criterion benchmark (`benches/predicates.rs`).
/// Not part of the supported API.
#[doc(hidden)]
pub mod predicates {
    pub use crate::planes::{intersect, side_of_hom, side_of_hom_exact, Plane, PlaneTable, Side};
}
