//! Shared helpers of the end-to-end tests. The reference ray caster lives in the compiler crate
//! (`peel_compiler::reference`) because `peel bench` measures errors against it too.

pub use peel_compiler::reference::*;
