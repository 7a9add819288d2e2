//! A scene without textures is written byte for byte as before textures existed (format 4):
//! each case's file hashed and compared with the hash of the file the compiler wrote before
//! textures were added (the hashes below were taken from that compiler, on the same
//! fixtures and options).

use std::path::Path;

use glam::DVec3;
use peel_compiler::compile::{compile_mesh, compile_obj, CompileOptions};
use peel_compiler::shade::{Shading, Surface};
use peel_compiler::shadow::Light;
use peel_compiler::tools::scenes;
use peel_compiler::tree::BuildOptions;

/// FNV-1a, 64 bits: a change anywhere in the bytes changes it (with overwhelming likelihood).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The option sets every case is compiled with: the default (smooth), faceted with ids and
/// solids, unlit, and smooth with shadows from a sun.
fn option_sets() -> Vec<(&'static str, CompileOptions)> {
    let sun = DVec3::new(0.3, 1.0, 0.2);
    vec![
        ("default", CompileOptions::default()),
        (
            "faceted-ids-solid",
            CompileOptions {
                surface: Surface::Faceted,
                ids: true,
                solid: true,
                ..CompileOptions::default()
            },
        ),
        (
            "unlit",
            CompileOptions {
                surface: Surface::Faceted,
                shading: Shading::Flat,
                ..CompileOptions::default()
            },
        ),
        (
            "smooth-shadows",
            CompileOptions {
                shading: Shading::Lambert(sun),
                build: BuildOptions {
                    shadows: Some(Light::Sun(sun)),
                    ..BuildOptions::default()
                },
                ..CompileOptions::default()
            },
        ),
    ]
}

/// Every case's name and the hash of its file.
fn hashes() -> Vec<(String, u64)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let mut out = Vec::new();
    for (set, options) in option_sets() {
        for name in [
            "cube.obj",
            "cyclic_triangles.obj",
            "demo.obj",
            "interpenetrating_boxes.obj",
        ] {
            let bytes = compile_obj(&root.join(name), &options, &|_| {})
                .expect(name)
                .bytes;
            out.push((format!("{name} {set}"), fnv1a(&bytes)));
        }
        for (name, mesh) in [
            ("sphere", scenes::sphere(8, 12)),
            ("torus", scenes::torus(12, 8)),
        ] {
            let bytes = compile_mesh(&mesh, &options, &|_| {}).expect(name).1;
            out.push((format!("{name} {set}"), fnv1a(&bytes)));
        }
    }
    out
}

#[test]
fn untextured_files_are_byte_for_byte_as_before_textures() {
    let expected: &[(&str, u64)] = &[
        ("cube.obj default", 0x610befb22b70e07b),
        ("cyclic_triangles.obj default", 0x7f60084e7150ee52),
        ("demo.obj default", 0x64f8134ae61210f2),
        ("interpenetrating_boxes.obj default", 0x285cd1dd9b81bdf7),
        ("sphere default", 0x28e8df204ab146ec),
        ("torus default", 0x48b75346f06349ab),
        ("cube.obj faceted-ids-solid", 0x7c5c5d703b977204),
        ("cyclic_triangles.obj faceted-ids-solid", 0x53b874248aa73ab6),
        ("demo.obj faceted-ids-solid", 0xdfc6da27f70d9355),
        (
            "interpenetrating_boxes.obj faceted-ids-solid",
            0xfbe26e50ab927486,
        ),
        ("sphere faceted-ids-solid", 0xf82e16416cb010f3),
        ("torus faceted-ids-solid", 0x4b86a6ff149d95af),
        ("cube.obj unlit", 0x4fecb4918f57d784),
        ("cyclic_triangles.obj unlit", 0xbe2640085d54f7e5),
        ("demo.obj unlit", 0x17d481376d9855e6),
        ("interpenetrating_boxes.obj unlit", 0x6857f72bbaf2c0c8),
        ("sphere unlit", 0xdaba172c486eeb0b),
        ("torus unlit", 0x128d85f671d73a1f),
        ("cube.obj smooth-shadows", 0xb6fdeadcbfa04fa5),
        ("cyclic_triangles.obj smooth-shadows", 0x78d9090efa47b450),
        ("demo.obj smooth-shadows", 0x0a1321c807aa9cdb),
        (
            "interpenetrating_boxes.obj smooth-shadows",
            0x3fe740602abd8d58,
        ),
        ("sphere smooth-shadows", 0x140126256809653a),
        ("torus smooth-shadows", 0xae4ad498414e356f),
    ];
    let got = hashes();
    let shown: Vec<String> = got
        .iter()
        .map(|(name, h)| format!("(\"{name}\", {h:#018x}),"))
        .collect();
    assert_eq!(
        got.len(),
        expected.len(),
        "hashes now:\n{}",
        shown.join("\n")
    );
    for ((name, h), (want_name, want)) in got.iter().zip(expected) {
        assert_eq!((name.as_str(), *h), (*want_name, *want), "{name}");
    }
}
