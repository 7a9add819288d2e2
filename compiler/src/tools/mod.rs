//! Tools and test/benchmark support, not the compile pipeline: nothing in `load` -> `quantise`
//! -> `planes` -> `peel`/`split` -> `tree` -> `shade` -> `write` depends on these modules.
//!
//! - [`raster`]: render `.peel` bytes into an image on the host, through the no_std runtime
//!   (`peel render`/`peel demo`, benchmarks, end-to-end tests).
//! - [`reference`](mod@reference): the brute-force f64 ray caster the tests and `peel bench`
//!   measure pixel errors against.
//! - [`scenes`]: generated meshes (sphere, torus, box grid, triangle soup) for benchmarks and
//!   tests.
//! - `bench_frames` (`peel bench`, feature `bench`): frame time against pixel error, Peel
//!   against the classic visibility methods.
//! - `bench_compile` (`peel bench compile`, feature `bench`): Peel's build against two
//!   baselines.

#[cfg(feature = "bench")]
pub mod bench_compile;
#[cfg(feature = "bench")]
pub mod bench_frames;
pub mod raster;
pub mod reference;
pub mod scenes;
