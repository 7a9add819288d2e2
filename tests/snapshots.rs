//! Snapshots of compiled fixtures (`peel dump` YAML), reviewed before they were accepted, and the
//! byte-exact format sample of `formats/samples/`.

use std::path::Path;

use peel_compiler::compile::{compile_obj, CompileOptions};
use peel_compiler::dump::{dump_yaml, inspect};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn compiled(name: &str, ids: bool) -> Vec<u8> {
    let options = CompileOptions {
        ids,
        ..CompileOptions::default()
    };
    compile_obj(&root().join("fixtures").join(name), &options, &|_| {})
        .expect("compile")
        .bytes
}

fn snapshot(name: &str) -> (String, peel_compiler::dump::Inspect) {
    let bytes = compiled(name, true);
    (
        dump_yaml(&bytes).expect("dump"),
        inspect(&bytes).expect("inspect"),
    )
}

#[test]
fn one_triangle() {
    let (yaml, info) = snapshot("triangle.obj");
    assert_eq!(
        (info.convex_nodes, info.split_nodes, info.output_polygons),
        (1, 0, 1)
    );
    insta::assert_snapshot!(yaml);
}

#[test]
fn cube_is_one_convex_node() {
    let (yaml, info) = snapshot("cube.obj");
    assert_eq!(
        (info.convex_nodes, info.split_nodes, info.output_polygons),
        (1, 0, 12)
    );
    insta::assert_snapshot!(yaml);
}

#[test]
fn staircase_has_complexity_zero() {
    let (yaml, info) = snapshot("staircase.obj");
    assert_eq!(
        info.split_nodes, 0,
        "complexity zero: the staircase needs no split"
    );
    assert_eq!(info.output_polygons, 16);
    insta::assert_snapshot!(yaml);
}

#[test]
fn nested_cubes_are_two_convex_layers() {
    let (yaml, info) = snapshot("nested_cubes.obj");
    assert_eq!(
        (info.convex_nodes, info.split_nodes, info.output_polygons),
        (2, 0, 24)
    );
    insta::assert_snapshot!(yaml);
}

#[test]
fn cyclic_overlap_must_cut() {
    let (yaml, info) = snapshot("cyclic_triangles.obj");
    assert!(info.split_nodes >= 1);
    assert!(
        info.output_polygons > 3,
        "a cyclic overlap cannot be drawn without a cut"
    );
    insta::assert_snapshot!(yaml);
}

#[test]
fn interpenetrating_boxes() {
    let (yaml, info) = snapshot("interpenetrating_boxes.obj");
    assert!(info.split_nodes >= 1);
    insta::assert_snapshot!(yaml);
}

/// Format stability: compiling the sample's source again gives the stored bytes exactly.
/// After a deliberate format change (and version bump), rewrite the sample with
/// `PEEL_BLESS=1 cargo test --release --test snapshots`.
#[test]
fn format_sample_is_byte_stable() {
    let sample = root().join("formats/samples/cube_ids.peel");
    let bytes = compiled("cube.obj", true);
    if std::env::var_os("PEEL_BLESS").is_some() {
        std::fs::write(&sample, &bytes).unwrap();
    }
    let stored = std::fs::read(&sample).unwrap_or_else(|e| panic!("{}: {e}", sample.display()));
    assert_eq!(stored.len(), bytes.len(), "sample size changed");
    assert!(
        stored == bytes,
        "sample bytes changed: the format or the compiler output drifted"
    );
}
