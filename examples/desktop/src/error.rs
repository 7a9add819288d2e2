//! What stops the program, each with the file or frame it concerns.

use std::path::PathBuf;

use peel_runtime::{ReadError, RenderError};

/// Why the program stopped.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The file given with `--scene` cannot be read.
    #[error("{}: cannot read: {source}", path.display())]
    ReadFile {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The scene is not a valid `.peel` file.
    #[error("{scene}: not a valid .peel file: {source}")]
    Scene {
        /// The scene's name: its file, or the one build.rs compiled.
        scene: String,
        /// What is wrong with it.
        source: ReadError,
    },
    /// The frame memory does not suit the display.
    #[error("frame memory: {0}")]
    Memory(RenderError),
    /// A frame could not be drawn: memory too small for it, a workspace too small for the
    /// scene, a degenerate camera.
    #[error(
        "{scene}: frame {frame} (azimuth {azimuth_deg} degrees): {source}{}",
        hint(source)
    )]
    Frame {
        /// The scene's name.
        scene: String,
        /// The frame's number, from 0.
        frame: u64,
        /// Its azimuth.
        azimuth_deg: f64,
        /// The renderer's error.
        source: RenderError,
    },
    /// The PNG file cannot be written (nothing is left at its path).
    #[error("{}: cannot write the PNG: {message}", path.display())]
    Png {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// No `--png` and this build has no window.
    #[error(
        "this build has no window: run it with `--features window` (which needs SDL2's \
         development files, e.g. the Debian package libsdl2-dev), or write frames with \
         `--png OUT.png`"
    )]
    NoWindow,
}

/// What to try when a frame runs out of memory.
fn hint(error: &RenderError) -> &'static str {
    match error {
        RenderError::ScanMemoryFull { .. } => " (`--order stream` needs no scan memory)",
        _ => "",
    }
}
