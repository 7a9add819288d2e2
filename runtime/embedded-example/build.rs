//! Compile the scene at build time and put `memory.x` where the linker finds it.

use std::path::PathBuf;

fn main() {
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("OUT_DIR"));
    peel_compiler::Builder::new("../../fixtures/demo.obj")
        .out_name("scene.peel")
        .compile()
        .expect("compile the demo scene");
    std::fs::copy("memory.x", out.join("memory.x")).expect("copy memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
}
