//! Peel's runtime: reads a compiled `.peel` display tree in place and paints it.
//!
//! `#![no_std]`, no allocator, no `unsafe`: every buffer is provided by the caller or has a
//! fixed size. Pipeline: [`read`] -> [`traverse`] -> [`camera`] (project) -> [`clip`] ->
//! [`fill`] -> [`display`]; [`render`] ties them together.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

pub mod camera;
pub mod clip;
// (Without the feature nothing draws through it; its types stay for the renderer's API.)
#[cfg_attr(not(feature = "transparency"), allow(dead_code))]
pub mod composite;
pub mod coverage;
pub mod display;
pub mod error;
pub mod fill;
pub mod pending;
pub mod place;
pub mod read;
pub mod render;
#[cfg(feature = "scan-order")]
pub mod scan;
pub mod stats;
pub mod traverse;
pub mod vertices;

pub use error::{ReadError, RenderError};
/// The vector types of the API (a [`place::Pose`]'s rotation and translation), at the version
/// the runtime uses.
pub use glam;
