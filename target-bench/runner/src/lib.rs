//! The on-target benchmark's records and what is made of them (its tables and the plot of the
//! alternatives): a library, so that the runner, which writes them, and the docs' figures
//! (`peel-doc-check figures`), which render them from the committed `results/target.json`,
//! share one rendering.

pub mod plot;
pub mod results;
