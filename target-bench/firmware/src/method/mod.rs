//! One frame of each variant, from the view to the last byte sent to the panel: what the
//! SysTick measurement covers. Memory comes from the pool, sized by the config block. Each
//! method is a `Method` with the same four functions (`new`, `header`, `framebuffer_bytes`,
//! `frame`); a build compiles only its variant's.

#[cfg(feature = "embedded-3dgfx")]
mod gfx3d;
#[cfg(peel_method)]
mod peel;
#[cfg(feature = "scanline-zbuffer")]
mod scanline;
#[cfg(any(feature = "zbuffer", feature = "tiled-zbuffer"))]
mod zbuffer;

#[cfg(feature = "embedded-3dgfx")]
pub use gfx3d::{Gfx3dFailure, Method};
#[cfg(peel_method)]
pub use peel::Method;
#[cfg(feature = "scanline-zbuffer")]
pub use scanline::Method;
#[cfg(any(feature = "zbuffer", feature = "tiled-zbuffer"))]
pub use zbuffer::Method;
