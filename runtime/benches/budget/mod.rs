//! The measurement budget of every criterion benchmark in the workspace: this crate's
//! `inner.rs` and the compiler's `frame.rs` and `predicates.rs` (which include this file by
//! path), so that a `cargo bench` stays short on a small machine and their figures are taken
//! alike.

use std::time::Duration;

use criterion::Criterion;

/// A benchmark file's `main`: its `targets` under the [`budget`] (this file must be its
/// module `budget`).
macro_rules! main {
    ($($target:path),+ $(,)?) => {
        criterion::criterion_group! {
            name = benches;
            config = budget::budget();
            targets = $($target),+
        }
        criterion::criterion_main!(benches);
    };
}
pub(crate) use main;

/// 20 samples, after 0.3 s of warm-up, in 1 s of measurement.
pub fn budget() -> Criterion {
    Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
}
