//! Compile the fixtures as docs/build-time.md says.

fn main() {
    // `$OUT_DIR/demo.peel` and its sizes, `$OUT_DIR/demo.rs`.
    peel_compiler::Builder::new("../../fixtures/demo.obj")
        .compile()
        .expect("compile demo.obj");
    // The cube has no materials: its colour is meant, so the loader does not warn.
    peel_compiler::Builder::new("../../fixtures/cube.obj")
        .default_colour([200, 120, 40])
        .compile()
        .expect("compile cube.obj");
}
