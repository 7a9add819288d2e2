//! Compile the scene at build time, validate it with the runtime's full check, and put
//! `memory.x` where the linker finds it.

use std::path::PathBuf;

fn main() {
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("OUT_DIR"));
    // The `full` configuration can paint ids: its scene keeps them.
    let full = std::env::var_os("CARGO_FEATURE_FULL").is_some();
    // The smallest configuration leaves the runtime's `smooth` feature out, which would draw
    // a smooth polygon in its full material colour: its scene is faceted.
    let surface = if full {
        peel_compiler::shade::DEFAULT_SURFACE
    } else {
        peel_compiler::shade::Surface::Faceted
    };
    let scene = peel_compiler::Builder::new("../../fixtures/demo.obj")
        .out_name("scene.peel")
        .ids(full)
        .surface(surface)
        .compile()
        .expect("compile the demo scene");
    // The firmware embeds exactly these bytes and, in its smallest configuration, reads them
    // with `Scene::parse_trusted` (header and layout only): the linear-time validation runs
    // here, once, instead of at every boot on the device.
    let bytes = std::fs::read(&scene).expect("read the compiled scene");
    peel_runtime::read::Scene::parse(&bytes).expect("the compiled scene fails validation");
    std::fs::copy("memory.x", out.join("memory.x")).expect("copy memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
}
