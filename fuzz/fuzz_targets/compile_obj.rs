//! OBJ bytes -> load -> compile: never a panic; errors are fine. Inputs are small (the runner
//! caps them), so time and memory stay bounded; the loader rejects absurd sizes itself.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::load_obj_text;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // No mtllib is resolved: the fuzz file lives in a directory that does not exist.
    let Ok(mesh) = load_obj_text(Path::new("/nonexistent-fuzz-dir/fuzz.obj"), text) else {
        return;
    };
    let options = CompileOptions {
        ids: true,
        ..CompileOptions::default()
    };
    if let Ok((_, bytes)) = compile_mesh(&mesh, &options, &|_| {}) {
        // Whatever the compiler writes, the runtime must accept.
        assert!(peel_runtime::read::Scene::parse(&bytes).is_ok());
    }
});
