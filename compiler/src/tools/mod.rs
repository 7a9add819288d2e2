//! Tools and test/benchmark support, not the compile pipeline: nothing in `load` -> `quantise`
//! -> `planes` -> `peel`/`split` -> `tree` -> `shade` -> `write` depends on these modules.
//!
//! - [`shot`]: the host's camera description (eye, target, up, field of view, image size,
//!   near distance), shared by everything below.
//! - [`raster`]: render `.peel` bytes into an image on the host, through the no_std runtime
//!   (`peel render`/`peel demo`, benchmarks, end-to-end tests).
//! - [`reference`](mod@reference): the brute-force f64 ray caster the tests and `peel bench`
//!   measure pixel errors against, the exact texel under each pixel of textured surfaces, and
//!   transparent surfaces composited in exact depth order.
//! - [`texture_check`]: a textured frame's pixels against those texels.
//! - [`scenes`]: generated meshes (sphere, torus, box grid, triangle soup) for benchmarks and
//!   tests, generated textures and textured meshes, the textured fixtures' pictures, and
//!   scenes with transparent surfaces (OBJ and MTL text) and their fixtures.
//! - [`shading_gap`]: how far a mesh's faceted picture is from its smooth one, on the
//!   reference's robust pixels.
//! - `bench_frames` (`peel bench`, feature `bench`): frame time against pixel error, Peel
//!   against the classic visibility methods.
//! - `bench_compile` (`peel bench compile`, feature `bench`): Peel's build against two
//!   baselines.
//! - `baselines` (feature `bench`): those baselines, a naive BSP tree and the greedy rule with
//!   triangle output, which `peel bench` draws too. The two benchmarks share it and
//!   [`median`], and depend on nothing else of each other.

#[cfg(feature = "bench")]
pub mod baselines;
#[cfg(feature = "bench")]
pub mod bench_compile;
#[cfg(feature = "bench")]
pub mod bench_frames;
pub mod raster;
pub mod reference;
pub mod scenes;
pub mod shading_gap;
pub mod shot;
pub mod texture_check;

/// One row of a markdown table, `| a | b | ... |` and a newline: the benchmarks' tables (frames,
/// compile, target) build their rows from cells rather than hand-counted format strings.
pub fn markdown_row<I>(cells: I) -> String
where
    I: IntoIterator,
    I::Item: std::fmt::Display,
{
    let mut row = String::from("|");
    for cell in cells {
        row.push_str(&format!(" {cell} |"));
    }
    row.push('\n');
    row
}

/// The median of `v` (the mean of the middle two for an even count; 0 when empty).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return 0.0;
    }
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        (v[m - 1] + v[m]) / 2.0
    }
}
