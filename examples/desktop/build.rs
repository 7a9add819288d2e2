//! Compile the scene at build time, as firmware does, with its memory measured for the
//! display the program draws into.
//!
//! The scene is the repository's demo (`fixtures/demo.obj`) unless `PEEL_DESKTOP_MESH` names
//! another OBJ (a path relative to this folder, or absolute).

use std::path::PathBuf;

/// The simulated display: the size of the boards' panels. The program takes it from the sizes
/// file (`SPANS_MEASURED_AT`), so it is set here alone.
const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;

fn main() {
    println!("cargo:rerun-if-env-changed=PEEL_DESKTOP_MESH");
    let mesh = std::env::var_os("PEEL_DESKTOP_MESH")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("../../fixtures/demo.obj"));
    // Writes `$OUT_DIR/scene.peel` and its sizes, `$OUT_DIR/scene.rs` (`STACK`, `VERTS`,
    // `SCAN_NODES` and `SPANS_PER_ROW` measured over an orbit at this size, ...).
    peel_compiler::Builder::new(&mesh)
        .out_name("scene.peel")
        .image_size(WIDTH, HEIGHT)
        .compile()
        .unwrap_or_else(|e| panic!("compile {}: {e}", mesh.display()));
    // The scene's name in the program's messages and window title.
    let name = mesh
        .file_name()
        .unwrap_or(mesh.as_os_str())
        .to_string_lossy();
    println!("cargo:rustc-env=PEEL_DESKTOP_SCENE_NAME={name}");
}
