//! Compile the scene at build time, sized for the panel, and put `memory.x` where the linker
//! finds it.
//!
//! The scene is the repository's demo (`fixtures/demo.obj`) unless `PEEL_BOARD_MESH` names
//! another OBJ (a path relative to this folder, or absolute): for example
//! `PEEL_BOARD_MESH=models/teapot.obj cargo build --release`.

use std::path::PathBuf;

/// The panel, in landscape: the size the span memory is measured at.
const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;

fn main() {
    println!("cargo:rerun-if-env-changed=PEEL_BOARD_MESH");
    let mesh = std::env::var_os("PEEL_BOARD_MESH")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("../../../fixtures/demo.obj"));
    // Writes `$OUT_DIR/scene.peel` and its sizes, `$OUT_DIR/scene.rs` (`STACK`, `VERTS`,
    // `SPANS_PER_ROW` measured over an orbit at 320x240, ...), whatever the OBJ's name.
    peel_compiler::Builder::new(&mesh)
        .out_name("scene.peel")
        .image_size(WIDTH, HEIGHT)
        .compile()
        .unwrap_or_else(|e| panic!("compile {}: {e}", mesh.display()));
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("OUT_DIR"));
    std::fs::copy("memory.x", out.join("memory.x")).expect("copy memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
}
