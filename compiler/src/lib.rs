//! Peel's offline scene compiler.
//!
//! Pipeline (one module per stage):
//! [`load`] (OBJ + MTL -> source triangles) -> [`quantise`] (power-of-two integer grid)
//! -> [`planes`] (exact integer planes and predicates) -> [`peel`] (convex-hull layers) /
//! [`split`] (exact cuts and the choice of the splitting plane) -> [`tree`] (the display
//! tree and its invariants) -> [`shade`] (baked Lambert colours) -> [`write`] (the `.peel` bytes, written atomically).
#![forbid(unsafe_code)]
#![warn(missing_docs)]

#[cfg(feature = "bench")]
pub mod bench;
pub mod builder;
pub(crate) mod bvh;
pub mod compile;
pub mod dump;
pub mod error;
#[cfg(feature = "bench")]
pub mod frames;
pub(crate) mod hash;
pub mod load;
pub mod peel;
pub mod planes;
pub mod quantise;
pub mod raster;
pub mod reference;
pub mod scenes;
pub mod shade;
pub mod split;
pub mod tree;
pub mod write;

pub use builder::Builder;
pub use error::CompileError;
