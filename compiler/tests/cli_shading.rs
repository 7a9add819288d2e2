//! `peel compile --shading smooth|faceted|unlit` and `--crease`: the files they write and the
//! combinations they refuse.

use std::path::{Path, PathBuf};

mod common;
use common::{fixture, peel, refused, s};

/// Compiles `scene` with `extra` into `dir/name`; returns its bytes and `--stats-json`.
fn compile(dir: &Path, scene: &str, name: &str, extra: &[&str]) -> (Vec<u8>, serde_json::Value) {
    let out: PathBuf = dir.join(name);
    let stats = dir.join(format!("{name}.json"));
    let mut args = vec!["compile", scene, "-o", s(&out), "--stats-json", s(&stats)];
    args.extend_from_slice(extra);
    let o = peel(&args);
    assert!(
        o.status.success(),
        "{extra:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let stats = std::fs::read_to_string(&stats).unwrap();
    (
        std::fs::read(&out).unwrap(),
        serde_json::from_str(&stats).unwrap(),
    )
}

/// A sphere of `rings` x `segments` quads on a square floor, as OBJ text.
fn sphere_obj(rings: usize, segments: usize) -> String {
    let mut text = String::new();
    for i in 0..=rings {
        let theta = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..segments {
            let phi = 2.0 * std::f64::consts::PI * j as f64 / segments as f64;
            let (x, y, z) = (
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            text += &format!("v {x} {} {z}\n", y + 1.5);
        }
    }
    let at = |i: usize, j: usize| i * segments + j % segments + 1;
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
            text += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
    }
    let n = (rings + 1) * segments;
    text += "v -3 0 -3\nv -3 0 3\nv 3 0 3\nv 3 0 -3\n";
    text += &format!(
        "f {} {} {}\nf {} {} {}\n",
        n + 1,
        n + 2,
        n + 3,
        n + 1,
        n + 3,
        n + 4
    );
    text
}

#[test]
fn shading_chooses_smooth_faceted_or_unlit() {
    let dir = tempfile::tempdir().unwrap();
    let demo = dir.path().join("ball.obj");
    std::fs::write(&demo, sphere_obj(8, 12)).unwrap();
    let demo = s(&demo).to_string();
    let (default, stats) = compile(dir.path(), &demo, "default.peel", &[]);
    assert!(stats["smooth_polygons"].as_u64().unwrap() > 0);
    let (faceted, stats) = compile(dir.path(), &demo, "faceted.peel", &["--shading", "faceted"]);
    assert_eq!(stats["smooth_polygons"], 0);
    assert!(faceted != default, "smooth is the default");
    let (unlit, _) = compile(dir.path(), &demo, "unlit.peel", &["--shading=unlit"]);
    let (flat, _) = compile(dir.path(), &demo, "flat.peel", &["--flat"]);
    assert!(unlit == flat, "--flat is --shading unlit");
    assert!(unlit != faceted);
    // The sphere is smooth; the floor stays flat.
    let (smooth, stats) = compile(dir.path(), &demo, "smooth.peel", &["--shading", "smooth"]);
    let count = stats["smooth_polygons"].as_u64().unwrap();
    let polygons = stats["output_polygons"].as_u64().unwrap();
    assert!(count > 0 && count < polygons, "{count} of {polygons}");
    assert!(smooth != faceted);
    assert!(smooth == default, "smooth is the default");
    let (creased, _) = compile(dir.path(), &demo, "creased.peel", &["--crease", "60"]);
    assert!(
        creased == default,
        "--crease alone: the default smooth shading"
    );
    let o = peel(&["inspect", s(&dir.path().join("smooth.peel"))]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains(&format!("smooth_polygons: {count}\n")),
        "{text}"
    );
    let o = peel(&["dump", s(&dir.path().join("smooth.peel"))]);
    let yaml = String::from_utf8_lossy(&o.stdout);
    assert!(
        yaml.contains("shades]") || yaml.contains(", shades"),
        "header flag"
    );
    assert!(
        yaml.contains("smooth") && yaml.contains("shades: [["),
        "polygon shades"
    );
    // A crease of 0: fewer faces join, other bytes; lights and shadows combine with smooth.
    let (sharp, _) = compile(
        dir.path(),
        &demo,
        "sharp.peel",
        &["--shading", "smooth", "--crease", "0"],
    );
    assert!(sharp != smooth);
    let (lit, stats) = compile(
        dir.path(),
        &demo,
        "lit.peel",
        &["--shading", "smooth", "--light=-1,1,0", "--shadows"],
    );
    assert!(lit != smooth && stats["smooth_polygons"].as_u64().unwrap() > 0);
    compile(
        dir.path(),
        &demo,
        "point.peel",
        &["--shading", "smooth", "--point-light=0,4,2"],
    );
}

#[test]
fn shading_flags_that_do_not_fit_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.peel");
    let cube = fixture("cube.obj");
    let base = ["compile", cube.as_str(), "-o", s(&out)];
    for (extra, says) in [
        (
            &["--shading", "faceted", "--crease=30"][..],
            &["--crease", "--shading smooth"][..],
        ),
        (&["--flat", "--crease=30"], &["--crease"]),
        (
            &["--shading", "smooth", "--crease=181"],
            &["--crease", "0 to 180"],
        ),
        (
            &["--shading", "smooth", "--crease=-1"],
            &["--crease", "0 to 180"],
        ),
        (
            &["--shading", "smooth", "--crease=nan"],
            &["--crease", "0 to 180"],
        ),
        (
            &["--shading", "smooth", "--crease=sharp"],
            &["--crease", "degrees"],
        ),
        (
            &["--shading", "shiny"],
            &["--shading", "smooth", "faceted", "unlit"],
        ),
        (
            &["--shading", "unlit", "--light=0,1,0"],
            &["--light", "unlit"],
        ),
        (
            &["--shading", "unlit", "--point-light=0,1,0"],
            &["--point-light", "unlit"],
        ),
        (
            &["--shading", "unlit", "--shadows"],
            &["--shadows", "unlit"],
        ),
        (&["--flat", "--shading", "smooth"], &["--flat", "--shading"]),
    ] {
        let args = [&base[..], extra].concat();
        refused(dir.path(), &args, says);
    }
    for edge in ["0", "180", "45.5"] {
        let o = peel(&[&base[..], &["--shading", "smooth", "--crease", edge]].concat());
        assert!(
            o.status.success(),
            "{edge}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}
