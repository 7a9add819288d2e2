//! The `peel` binary as a user runs it: exit codes, messages, files written (or not).

use std::path::Path;

mod common;
use common::{fixture, fixtures, peel, refused, s};

fn json_keys(text: &str) -> Vec<String> {
    let v: serde_json::Value = serde_json::from_str(text).expect("valid JSON");
    let mut keys: Vec<String> = v.as_object().expect("an object").keys().cloned().collect();
    keys.sort();
    keys
}

#[test]
fn compile_writes_the_file_and_exact_stats_keys() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cube.peel");
    let stats = dir.path().join("stats.json");
    let o = peel(&[
        "compile",
        &fixture("cube.obj"),
        "-o",
        s(&out),
        "--stats-json",
        s(&stats),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.exists());
    let mut want = [
        "input_triangles",
        "degenerate_dropped",
        "output_polygons",
        "convex_nodes",
        "split_nodes",
        "cuts",
        "max_depth",
        "planes",
        "smooth_polygons",
        "solid_polygons",
        "bytes",
        "compile_seconds",
    ]
    .map(String::from)
    .to_vec();
    want.sort();
    let text = std::fs::read_to_string(&stats).unwrap();
    assert_eq!(json_keys(&text), want);
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["input_triangles"], 12);
    assert_eq!(v["bytes"], std::fs::metadata(&out).unwrap().len());

    let o = peel(&["inspect", s(&out), "--json"]);
    assert!(o.status.success());
    let keys = json_keys(&String::from_utf8_lossy(&o.stdout));
    for k in [
        "format_version",
        "output_polygons",
        "convex_nodes",
        "split_nodes",
        "max_depth",
        "split_planes",
        "vertices",
        "bytes",
        "frame_memory",
    ] {
        assert!(
            keys.contains(&k.to_string()),
            "inspect --json lacks {k}: {keys:?}"
        );
    }

    let o = peel(&["dump", s(&out)]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stdout).contains("convex"));
}

#[test]
fn solid_marks_a_closed_cube_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let solid_polygons = |solid: bool| {
        let out = dir.path().join("cube.peel");
        let stats = dir.path().join("stats.json");
        let cube = fixture("cube.obj");
        let mut args = vec!["compile", &cube, "-o", s(&out)];
        args.extend(["--stats-json", s(&stats)]);
        if solid {
            args.push("--solid");
        }
        let o = peel(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
        let o = peel(&["inspect", s(&out), "--json"]);
        let shown: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(shown["solid_polygons"], v["solid_polygons"]);
        (v["solid_polygons"].clone(), v["output_polygons"].clone())
    };
    let (solid, all) = solid_polygons(true);
    assert_eq!(solid, all);
    assert_ne!(solid, 0);
    assert_eq!(solid_polygons(false).0, 0);
}

#[test]
fn bad_inputs_fail_with_file_and_line_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    for (name, line) in [
        ("bad/nan_coordinate.obj", 4),
        ("bad/inf_coordinate.obj", 3),
        ("bad/index_out_of_range.obj", 6),
        ("bad/bad_number.obj", 3),
        ("bad/cut_off_face.obj", 8),
    ] {
        let out = dir.path().join("out.peel");
        let o = peel(&["compile", &fixture(name), "-o", s(&out)]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{name} compiled");
        let file = Path::new(name).file_name().unwrap().to_str().unwrap();
        assert!(err.contains(&format!("{file}:{line}:")), "{name}: {err}");
        assert!(!out.exists(), "{name}: partial output left behind");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            0,
            "temp file left behind"
        );
    }
    let out = dir.path().join("out.peel");
    let o = peel(&["compile", &fixture("bad/no_faces.obj"), "-o", s(&out)]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("no faces"));
    let o = peel(&["compile", &fixture("does_not_exist.obj"), "-o", s(&out)]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("does_not_exist.obj"));
    assert!(!out.exists());
}

#[test]
fn corrupt_peel_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.peel");
    std::fs::write(&bad, b"PEEL\x01\x00garbage").unwrap();
    for args in [vec!["inspect", s(&bad)], vec!["dump", s(&bad)]] {
        let o = peel(&args);
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("bad.peel") && err.contains("byte"), "{err}");
    }
}

#[test]
fn render_accepts_negative_numbers_in_both_forms_and_checks_ids() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain.peel");
    assert!(peel(&["compile", &fixture("cube.obj"), "-o", s(&plain)])
        .status
        .success());
    let a = dir.path().join("a.png");
    let o = peel(&[
        "render",
        s(&plain),
        "--eye=-3,2.5,4",
        "--target=0,0,0",
        "--size=64x48",
        "-o",
        s(&a),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let b = dir.path().join("b.png");
    let o = peel(&[
        "render",
        s(&plain),
        "--eye",
        "-3,2.5,4",
        "--target",
        "-0,0,0",
        "--size",
        "64x48",
        "-o",
        s(&b),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());

    let c = dir.path().join("c.png");
    let o = peel(&[
        "render",
        s(&plain),
        "--eye=-3,2.5,4",
        "--target=0,0,0",
        "--size=64x48",
        "--ids",
        "-o",
        s(&c),
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--ids"));
    assert!(!c.exists());

    let with_ids = dir.path().join("ids.peel");
    assert!(
        peel(&["compile", &fixture("cube.obj"), "-o", s(&with_ids), "--ids"])
            .status
            .success()
    );
    let o = peel(&[
        "render",
        s(&with_ids),
        "--eye=-3,2.5,4",
        "--target=0,0,0",
        "--size=64x48",
        "--ids",
        "-o",
        s(&c),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&c).unwrap().to_rgb8();
    let centre = img.get_pixel(32, 24).0;
    let id = (u32::from(centre[0]) << 16) | (u32::from(centre[1]) << 8) | u32::from(centre[2]);
    assert!((1..=12).contains(&id), "centre pixel shows id+1 = {id}");
    assert_eq!(img.get_pixel(0, 0).0, [0, 0, 0], "background is 0");
}

#[test]
fn demo_writes_a_picture() {
    let dir = tempfile::tempdir().unwrap();
    let o = peel(&["demo", "--out", s(dir.path())]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(dir.path().join("demo.png")).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (800, 600));
    let distinct: std::collections::HashSet<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    assert!(distinct.len() > 8, "the demo shows several shaded objects");
}

#[test]
fn render_orders_give_the_same_picture_and_stats_report_overdraw() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("demo.peel");
    assert!(peel(&["compile", &fixture("demo.obj"), "-o", s(&file)])
        .status
        .success());
    let mut pictures = Vec::new();
    let mut overdraws = Vec::new();
    for order in ["front-to-back", "back-to-front"] {
        let png = dir.path().join(format!("{order}.png"));
        let o = peel(&[
            "render",
            s(&file),
            "--eye=5,4,7",
            "--target=0,0.8,0",
            "--size=160x120",
            &format!("--order={order}"),
            "--stats",
            "-o",
            s(&png),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        let line = out
            .lines()
            .find(|l| l.starts_with("overdraw: "))
            .expect("overdraw line")
            .to_owned();
        overdraws.push(line);
        let covered: u64 = out
            .lines()
            .find_map(|l| l.strip_prefix("polygons culled (covered): "))
            .expect("covered line")
            .parse()
            .unwrap();
        // Only front to back knows what is covered: hidden faces skip the fill.
        assert_eq!(covered > 0, order == "front-to-back", "{out}");
        pictures.push(std::fs::read(&png).unwrap());
    }
    assert_eq!(
        pictures[0], pictures[1],
        "both orders draw the same picture"
    );
    assert_eq!(
        overdraws[0], "overdraw: 1.00",
        "front to back writes each pixel once"
    );
    assert_ne!(
        overdraws[1], "overdraw: 1.00",
        "the painter's algorithm overdraws this scene"
    );
    let o = peel(&[
        "render",
        s(&file),
        "--eye=5,4,7",
        "--target=0,0,0",
        "--size=8x8",
        "--order=sideways",
        "-o",
        "x.png",
    ]);
    assert!(!o.status.success());
}

/// The colours of each polygon of a `.peel` file, its interior side's then its exterior
/// side's, in the order `peel dump` lists the polygons.
fn dumped_colours(file: &Path) -> Vec<[[u8; 3]; 2]> {
    let o = peel(&["dump", s(file)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let parse = |rest: &str| -> [u8; 3] {
        let v: Vec<u8> = rest
            .trim_end_matches(']')
            .split(',')
            .map(|c| c.trim().parse().expect("a colour channel"))
            .collect();
        [v[0], v[1], v[2]]
    };
    let mut out: Vec<[[u8; 3]; 2]> = Vec::new();
    for line in String::from_utf8_lossy(&o.stdout).lines() {
        if let Some(rest) = line.trim().strip_prefix("colour: [") {
            let c = parse(rest);
            out.push([c, c]);
        } else if let Some(rest) = line.trim().strip_prefix("exterior_colour: [") {
            out.last_mut().expect("a polygon's colour first")[1] = parse(rest);
        }
    }
    out
}

/// The `Kd` colours of an MTL file as the loader rounds them (clamped, x 255, rounded).
fn kd_colours(mtl: &str) -> Vec<[u8; 3]> {
    std::fs::read_to_string(fixtures().join(mtl))
        .unwrap()
        .lines()
        .filter_map(|l| l.trim().strip_prefix("Kd "))
        .map(|rest| {
            let v: Vec<f64> = rest
                .split_whitespace()
                .map(|c| c.parse().unwrap())
                .collect();
            [v[0], v[1], v[2]].map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)
        })
        .collect()
}

fn compile_demo(dir: &Path, name: &str, extra: &[&str]) -> Vec<[[u8; 3]; 2]> {
    let out = dir.join(name);
    let mut args = vec!["compile", &fixture("demo.obj"), "-o", s(&out)]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>();
    args.extend(extra.iter().map(|a| a.to_string()));
    // Faceted unless asked otherwise: the callers check each polygon's baked colours.
    if !extra
        .iter()
        .any(|a| a.starts_with("--flat") || a.starts_with("--shading"))
    {
        args.extend(["--shading".to_string(), "faceted".to_string()]);
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = peel(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    dumped_colours(&out)
}

#[test]
fn compile_bakes_shading_unless_flat_and_light_moves_it() {
    let dir = tempfile::tempdir().unwrap();
    let kd = kd_colours("demo.mtl");
    let ground = kd[0];
    assert_eq!(
        ground,
        [89, 140, 77],
        "demo.mtl's first material is the ground"
    );

    // --flat: exactly the materials' Kd on both sides, every material present.
    let flat_sides = compile_demo(dir.path(), "flat.peel", &["--flat"]);
    assert!(flat_sides.len() > 20);
    assert!(
        flat_sides.iter().all(|[a, b]| a == b),
        "--flat: one colour for both sides"
    );
    let flat: Vec<[u8; 3]> = flat_sides.iter().map(|[a, _]| *a).collect();
    let mut flat_set: Vec<[u8; 3]> = flat.clone();
    flat_set.sort();
    flat_set.dedup();
    let mut kd_set = kd.clone();
    kd_set.sort();
    kd_set.dedup();
    assert_eq!(flat_set, kd_set, "--flat keeps the raw Kd colours");

    // Default: per polygon, the side facing the light Kd scaled by AMBIENT + (1 - AMBIENT) n.l
    // in [0.3, 1], the other side Kd * AMBIENT.
    let ambient = |kd: [u8; 3]| kd.map(|c| (f64::from(c) * 0.3).round() as u8);
    let shaded = compile_demo(dir.path(), "shaded.peel", &[]);
    assert_eq!(shaded.len(), flat.len(), "shading does not change the tree");
    let within = |baked: &[[[u8; 3]; 2]], what: &str| {
        for (i, (sides, f)) in baked.iter().zip(&flat).enumerate() {
            assert!(
                sides.contains(&ambient(*f)),
                "{what}: polygon {i} baked {sides:?} from Kd {f:?}: no side is Kd * 0.3"
            );
            for b in sides {
                for c in 0..3 {
                    let lo = (f64::from(f[c]) * 0.3).floor() as u8;
                    assert!(
                        b[c] <= f[c] && b[c] >= lo.saturating_sub(1),
                        "{what}: polygon {i} baked {b:?} from Kd {f:?}"
                    );
                }
            }
        }
    };
    within(&shaded, "default light");
    let two_sided = shaded.iter().filter(|[a, b]| a != b).count();
    assert!(
        two_sided * 2 > flat.len(),
        "default compile shades: only {two_sided} of {} polygons have two colours",
        flat.len()
    );
    // The ground (normal +y) under the default light (0.4, 0.8, 0.45): k = 0.3 + 0.7 * 0.799
    // on top, 0.3 below.
    let grounds: Vec<usize> = (0..flat.len()).filter(|&i| flat[i] == ground).collect();
    assert!(!grounds.is_empty());
    let sorted = |mut sides: [[u8; 3]; 2]| {
        sides.sort();
        sides
    };
    for &i in &grounds {
        assert_eq!(
            sorted(shaded[i]),
            [[27, 42, 23], [76, 120, 66]],
            "ground under the default light"
        );
    }

    // --light straight up: the ground's top gets its full Kd; from the side: only the ambient
    // part on both sides.
    let up = compile_demo(dir.path(), "up.peel", &["--light", "0,1,0"]);
    within(&up, "--light 0,1,0");
    let side = compile_demo(dir.path(), "side.peel", &["--light=-1,0,0"]);
    within(&side, "--light -1,0,0");
    for &i in &grounds {
        assert_eq!(
            sorted(up[i]),
            sorted([ground, [27, 42, 23]]),
            "ground lit from straight above"
        );
        assert_eq!(side[i], [[27, 42, 23]; 2], "ground lit edge-on: 0.3 x Kd");
    }
    assert_ne!(up, shaded, "--light changes the baked colours");
    assert_ne!(side, shaded, "--light changes the baked colours");
    assert_ne!(up, side);
}

#[test]
fn compile_casts_shadows_from_the_light() {
    let dir = tempfile::tempdir().unwrap();
    let one_colour = |polygons: &[[[u8; 3]; 2]]| polygons.iter().filter(|[a, b]| a == b).count();
    for light in [
        None,
        Some("--light=-0.9,0.5,0.2"),
        Some("--point-light=0.5,2.5,0.5"),
    ] {
        let extra: Vec<&str> = light.into_iter().collect();
        let lit = compile_demo(dir.path(), "lit.peel", &extra);
        let with = [extra.clone(), vec!["--shadows"]].concat();
        let shadows = compile_demo(dir.path(), "shadows.peel", &with);
        // Cut along the shadows; the parts in shadow have one colour, the ambient one.
        assert!(
            shadows.len() > lit.len(),
            "{light:?}: {} polygons",
            shadows.len()
        );
        assert!(
            one_colour(&shadows) > one_colour(&lit),
            "{light:?}: no polygon in shadow"
        );
    }
    // Refused, with a message naming what to change.
    for (light, says) in [("--flat", "--flat"), ("--point-light=0,1e6,0", "use a sun")] {
        let x = dir.path().join("x.peel");
        let o = peel(&[
            "compile",
            &fixture("demo.obj"),
            "-o",
            s(&x),
            "--shadows",
            light,
        ]);
        assert!(!o.status.success(), "{light}");
        assert!(String::from_utf8_lossy(&o.stderr).contains(says), "{light}");
    }
}

#[test]
fn the_demo_scene_needs_split_nodes() {
    let dir = tempfile::tempdir().unwrap();
    // `peel demo` compiles the copy of fixtures/demo.obj built into the binary.
    let o = peel(&["demo", "--out", s(dir.path())]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let demo_obj = dir.path().join("demo.obj");
    let fixture_text = |name: &str| std::fs::read_to_string(fixtures().join(name)).unwrap();
    assert_eq!(
        std::fs::read_to_string(&demo_obj).unwrap(),
        format!(
            "{}\n{}",
            fixture_text("demo.obj"),
            fixture_text("demo-torus.obj")
        ),
        "peel demo uses fixtures/demo.obj and the torus of fixtures/demo-torus.obj"
    );
    let out = dir.path().join("again.peel");
    let stats = dir.path().join("stats.json");
    // `peel demo` casts the default sun's shadows.
    let o = peel(&[
        "compile",
        s(&demo_obj),
        "-o",
        s(&out),
        "--shadows",
        "--stats-json",
        s(&stats),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    let splits = v["split_nodes"].as_u64().expect("split_nodes is a number");
    assert!(splits > 0, "the demo scene compiles without a split: {v}");
    assert!(v["cuts"].as_u64().unwrap() > 0, "{v}");
    // The file says the same.
    let o = peel(&["inspect", s(&out), "--json"]);
    assert!(o.status.success());
    let inspect: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(inspect["split_nodes"].as_u64(), Some(splits));
    // And so does the file `peel demo` wrote itself.
    let o = peel(&["inspect", s(&dir.path().join("demo.peel")), "--json"]);
    assert!(o.status.success());
    let inspect: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(inspect["split_nodes"].as_u64(), Some(splits));
    assert_eq!(
        std::fs::read(dir.path().join("demo.peel")).unwrap(),
        std::fs::read(&out).unwrap(),
        "peel demo is peel compile --shadows (smooth, the default)"
    );
    let o = peel(&["inspect", s(&out), "--json"]);
    let inspect: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(
        inspect["smooth_polygons"].as_u64().unwrap() > 200,
        "the torus is smooth: {inspect}"
    );
}

/// The decoded RGB bytes of a PNG.
fn rgb(png: &Path) -> Vec<u8> {
    image::open(png).unwrap().to_rgb8().into_raw()
}

/// The value of the `--stats` line `name: value`.
fn stat(stdout: &[u8], name: &str) -> u64 {
    let out = String::from_utf8_lossy(stdout);
    out.lines()
        .find_map(|l| l.strip_prefix(name)?.strip_prefix(": "))
        .unwrap_or_else(|| panic!("no '{name}' line in:\n{out}"))
        .parse()
        .unwrap()
}

#[test]
fn render_from_inside_a_closed_mesh_is_the_same_with_and_without_culling() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("cube.peel");
    let o = peel(&["compile", &fixture("cube.obj"), "-o", s(&file)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The eye inside the cube [-1, 1]^3: every pixel sees one of its faces from behind.
    let render = |name: &str, extra: &[&str]| {
        let png = dir.path().join(name);
        let mut args = vec![
            "render",
            s(&file),
            "--eye=0.2,0.1,0.3",
            "--target=1,0.2,0.5",
            "--size=64x48",
            "--stats",
            "-o",
            s(&png),
        ];
        args.extend_from_slice(extra);
        let o = peel(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        (rgb(&png), o.stdout)
    };
    let (culled, stats) = render("culled.png", &[]);
    let (all, all_stats) = render("all.png", &["--no-cull"]);
    let differ = culled
        .chunks(3)
        .zip(all.chunks(3))
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(
        differ,
        0,
        "{differ} of {} pixels change with culling",
        64 * 48
    );
    assert_eq!(stat(&all_stats, "pixels written"), 64 * 48);
    assert_eq!(
        stat(&stats, "pixels written"),
        64 * 48,
        "the default render (culling on) from inside the cube writes every pixel once"
    );
}

/// The pixels written, from `render --stats` output.
fn pixels_written(stdout: &[u8]) -> u64 {
    let text = String::from_utf8_lossy(stdout);
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix("pixels written: "))
        .unwrap_or_else(|| panic!("no 'pixels written' line in: {text}"));
    line.trim().parse().unwrap()
}

#[test]
fn render_frames_the_scene_by_itself_and_inspect_prints_where_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("demo.peel");
    assert!(peel(&["compile", &fixture("demo.obj"), "-o", s(&scene)])
        .status
        .success());
    // No --eye/--target: an orbit around the scene's box, at the distance that fits it.
    let framed = dir.path().join("framed.png");
    let o = peel(&[
        "render",
        s(&scene),
        "--size=96x72",
        "--stats",
        "-o",
        s(&framed),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let seen = pixels_written(&o.stdout);
    assert!(seen > 96 * 72 / 10, "only {seen} pixels of the scene");
    // The scene fits: no pixel of its border row or column is covered (background is black).
    let img = image::load_from_memory(&std::fs::read(&framed).unwrap())
        .unwrap()
        .to_rgb8();
    let border = (0..96)
        .flat_map(|x| [(x, 0), (x, 71)])
        .chain((0..72).flat_map(|y| [(0, y), (95, y)]));
    assert!(border
        .into_iter()
        .all(|(x, y)| img.get_pixel(x, y).0 == [0, 0, 0]));
    // Other angles and distances; the orbit equals the camera it describes.
    let side = dir.path().join("side.png");
    let o = peel(&[
        "render",
        s(&scene),
        "--orbit=90,0",
        "--distance=3",
        "--size=96x72",
        "-o",
        s(&side),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = peel(&["inspect", s(&scene), "--json"]);
    assert!(o.status.success());
    let info: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let v = |k: &str| -> Vec<f64> {
        let a = info[k]
            .as_array()
            .unwrap_or_else(|| panic!("inspect lacks {k}"));
        a.iter().map(|x| x.as_f64().unwrap()).collect()
    };
    let (c, r) = (v("centre"), info["radius"].as_f64().unwrap());
    let (lo, hi) = (v("bounds_min"), v("bounds_max"));
    for k in 0..3 {
        assert!(lo[k] < hi[k] && ((lo[k] + hi[k]) / 2.0 - c[k]).abs() < 1e-9);
    }
    let eye = format!("--eye={},{},{}", c[0] + 3.0 * r, c[1], c[2]);
    let target = format!("--target={},{},{}", c[0], c[1], c[2]);
    let explicit = dir.path().join("explicit.png");
    let o = peel(&[
        "render",
        s(&scene),
        &eye,
        &target,
        "--size=96x72",
        "-o",
        s(&explicit),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(&side).unwrap(),
        std::fs::read(&explicit).unwrap()
    );
}

#[test]
fn render_explains_what_it_cannot_do() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("cube.peel");
    assert!(peel(&["compile", &fixture("cube.obj"), "-o", s(&scene)])
        .status
        .success());
    let fails = |args: &[&str], says: &str| {
        let o = peel(args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?} succeeded");
        assert!(err.contains(says), "{args:?}: {err}");
    };
    // An extension it does not write: refused before anything is written.
    let ppm = dir.path().join("x.ppm");
    fails(&["render", s(&scene), "--size=8x8", "-o", s(&ppm)], ".png");
    assert!(!ppm.exists());
    // Looking straight down with the default up: the error says which flag fixes it.
    let down = dir.path().join("down.png");
    fails(
        &[
            "render",
            s(&scene),
            "--eye=0,5,0",
            "--target=0,0,0",
            "--size=8x8",
            "-o",
            s(&down),
        ],
        "--up",
    );
    assert!(!down.exists());
    let o = peel(&[
        "render",
        s(&scene),
        "--eye=0,5,0",
        "--target=0,0,0",
        "--up=0,0,-1",
        "--size=8x8",
        "-o",
        s(&down),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // Half a camera, or a camera and an orbit, or an orbit straight down.
    let out = dir.path().join("y.png");
    fails(
        &[
            "render",
            s(&scene),
            "--eye=0,0,5",
            "--size=8x8",
            "-o",
            s(&out),
        ],
        "--target",
    );
    fails(
        &[
            "render",
            s(&scene),
            "--eye=0,0,5",
            "--target=0,0,0",
            "--orbit=0,0",
            "--size=8x8",
            "-o",
            s(&out),
        ],
        "--orbit",
    );
    fails(
        &[
            "render",
            s(&scene),
            "--orbit=0,90",
            "--size=8x8",
            "-o",
            s(&out),
        ],
        "elevation",
    );
    // A camera looking away: the image is written, with a warning.
    let away = dir.path().join("away.png");
    let o = peel(&[
        "render",
        s(&scene),
        "--eye=0,0,5",
        "--target=0,0,10",
        "--size=8x8",
        "-o",
        s(&away),
    ]);
    assert!(o.status.success());
    assert!(away.exists());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("warning") && err.contains("no pixel"), "{err}");
}

/// `peel bench --quick` (what CI runs, here on small images from one camera) runs every
/// method on every scene: one JSON record each, with its memory, and the table and the plot.
#[test]
fn bench_quick_runs_every_method_on_every_scene() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("frames.json");
    let o = peel(&[
        "bench",
        "--quick",
        "--size",
        "64x48",
        "--cameras",
        "1",
        "--out",
        s(dir.path()),
        "--json",
        s(&json),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&json).unwrap();
    let records: Vec<serde_json::Value> = serde_json::from_str(&text).unwrap();
    let scenes = ["demo", "sphere-9k", "torus-4k", "box-grid-768", "soup-1k"];
    let methods = [
        "peel-front-to-back",
        "peel-back-to-front",
        "zbuffer-int",
        "zbuffer-f32",
        "newell",
        "naive-bsp",
        "watkins",
        "warnock-quadrants",
        "warnock-enclosing",
        "weiler-atherton",
    ];
    // Each scene's methods, and front to back at 0 and 4 subpixel bits (the table's
    // `SUBPIXEL_BITS` rows).
    let subpixel = ["peel-front-to-back/sub0", "peel-front-to-back/sub4"];
    // Then the transparent scenes (the teapot's only with the shared models): Peel in both
    // orders and the z-buffer that sorts transparent triangles, against the composited cast.
    let transparent = [
        "crossing-panes",
        "glass-box",
        "glass-box-opaque",
        "interpenetrating-boxes",
    ];
    let composited = ["peel-front-to-back", "peel-back-to-front", "zbuffer-sorted"];
    let teapot = records
        .iter()
        .filter(|r| r["scene"] == "glass-box-teapot")
        .count();
    assert!(teapot == 0 || teapot == composited.len());
    let teapots = usize::from(teapot > 0) * 2 * composited.len();
    assert_eq!(
        records.len(),
        scenes.len() * (methods.len() + subpixel.len())
            + transparent.len() * composited.len()
            + teapots
    );
    for scene in transparent {
        for method in composited {
            let r = records
                .iter()
                .find(|r| r["scene"] == scene && r["method"] == method)
                .unwrap_or_else(|| panic!("{scene} {method}"));
            let robust = r["robust_errors"].as_u64().unwrap();
            if method.starts_with("peel") {
                assert_eq!(robust, 0, "{r}");
            } else if scene == "crossing-panes" {
                assert!(robust > 0, "the sorted z-buffer where panes cross: {r}");
            }
        }
    }
    for scene in scenes {
        for method in methods.iter().chain(&subpixel) {
            let r = records
                .iter()
                .find(|r| r["scene"] == scene && r["method"] == *method)
                .unwrap_or_else(|| panic!("{scene} {method}"));
            assert!(r["memory_bytes"].as_u64().unwrap() > 0, "{r}");
            assert!(r["pixels_written"].as_u64().unwrap() > 0, "{r}");
            if method.starts_with("peel") {
                assert!(r["polygons_drawn"].as_u64().unwrap() > 0, "{r}");
            }
        }
    }
    let table = std::fs::read_to_string(dir.path().join("frames.md")).unwrap();
    assert!(table.contains("| demo | weiler-atherton |"), "{table}");
    assert!(dir.path().join("frames.png").exists());
}

#[test]
fn render_names_the_flag_and_its_range_for_a_bad_camera_value() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("cube.peel");
    assert!(peel(&["compile", &fixture("cube.obj"), "-o", s(&scene)])
        .status
        .success());
    let out_dir = tempfile::tempdir().unwrap();
    let png = out_dir.path().join("x.png");
    let fov = "strictly between 0 and 180 degrees";
    for (flag, says) in [
        (&["--fov=180"][..], ["--fov", fov]),
        (&["--fov", "0"], ["--fov", fov]),
        (&["--fov", "-30"], ["--fov", fov]),
        (&["--fov=nan"], ["--fov", "not a finite number"]),
        (&["--near=-1"], ["--near", "must be a positive number"]),
        (&["--near", "-1"], ["--near", "must be a positive number"]),
        (&["--near=0"], ["--near", "must be a positive number"]),
        (
            &["--distance=-2"],
            ["--distance", "must be a positive number"],
        ),
        (&["--up=0,0,0"], ["--up", "has no length"]),
    ] {
        let mut args = vec!["render", s(&scene), "-o", s(&png)];
        args.extend_from_slice(flag);
        refused(out_dir.path(), &args, &says);
    }
}

#[test]
fn compile_refuses_a_light_without_direction() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.peel");
    for light in ["--light=0,0,0", "--light=-0,0,0"] {
        refused(
            dir.path(),
            &["compile", &fixture("cube.obj"), "-o", s(&out), light],
            &["--light", "has no length"],
        );
    }
    let o = peel(&[
        "compile",
        &fixture("cube.obj"),
        "-o",
        s(&out),
        "--light=0,-1e-3,0",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn compile_output_must_be_a_peel_file() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["out.txt", "out", "out.peel.png"] {
        let out = dir.path().join(name);
        refused(
            dir.path(),
            &["compile", &fixture("cube.obj"), "-o", s(&out)],
            &["-o/--output", name, ".peel"],
        );
    }
    let out = dir.path().join("OUT.PEEL");
    let o = peel(&["compile", &fixture("cube.obj"), "-o", s(&out)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn a_file_of_degenerate_faces_is_an_error_and_an_empty_scene_does_not_blame_the_camera() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.peel");
    refused(
        dir.path(),
        &["compile", &fixture("bad/all_degenerate.obj"), "-o", s(&out)],
        &[
            "all_degenerate.obj: all 3 faces are degenerate",
            "nothing to draw",
        ],
    );
    // An empty scene is a valid file (the library still makes one of an empty mesh): render
    // says it is empty, whatever the camera.
    let (_, bytes) = peel_compiler::compile::compile_mesh(
        &peel_compiler::load::Mesh::default(),
        &peel_compiler::compile::CompileOptions::default(),
        &|_| {},
    )
    .unwrap();
    let files = tempfile::tempdir().unwrap();
    let empty = files.path().join("empty.peel");
    std::fs::write(&empty, bytes).unwrap();
    let png = dir.path().join("x.png");
    for camera in [&[][..], &["--eye=0,0,5", "--target=0,0,0"]] {
        let mut args = vec!["render", s(&empty), "-o", s(&png)];
        args.extend_from_slice(camera);
        refused(dir.path(), &args, &["empty.peel: the scene is empty"]);
        let err = String::from_utf8_lossy(&peel(&args).stderr).into_owned();
        assert!(!err.contains("camera"), "{err}");
    }
}

#[test]
fn a_file_cut_off_in_a_face_is_an_error_naming_its_last_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.peel");
    refused(
        dir.path(),
        &["compile", &fixture("bad/cut_off_face.obj"), "-o", s(&out)],
        &[
            "cut_off_face.obj:8: the file ends in the middle of a face",
            "`f 2 3` has 2 corners",
            "cut off",
        ],
    );
}

/// The standard error of `peel compile` of `obj` with `extra`, which must succeed, into `out`.
fn compile_warnings(obj: &Path, out: &Path, extra: &[&str]) -> String {
    let mut args = vec!["compile", s(obj), "-o", s(out)];
    args.extend_from_slice(extra);
    let o = peel(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn default_colour_colours_faces_without_material_and_a_plain_mesh_does_not_warn() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.peel");
    // A plain mesh (no `mtllib`, no `usemtl`): the default grey, no warning.
    let err = compile_warnings(&fixtures().join("cube.obj"), &out, &["--flat"]);
    assert!(err.is_empty(), "{err}");
    assert!(dumped_colours(&out)
        .iter()
        .all(|c| *c == [[200, 200, 200]; 2]));
    // Materials, but faces before any `usemtl`: the warning says how to choose their colour.
    let obj = dir.path().join("m.obj");
    std::fs::write(dir.path().join("m.mtl"), "newmtl red\nKd 1 0 0\n").unwrap();
    std::fs::write(
        &obj,
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nusemtl red\nf 1 3 4\n",
    )
    .unwrap();
    let err = compile_warnings(&obj, &out, &["--flat"]);
    assert!(
        err.contains("m.obj: 2 faces have no material")
            && err.contains("first at line 6")
            && err.contains("200,200,200")
            && err.contains("--default-colour R,G,B"),
        "{err}"
    );
    let mut colours = dumped_colours(&out);
    colours.sort();
    assert_eq!(
        colours,
        [[[200, 200, 200]; 2], [[200, 200, 200]; 2], [[255, 0, 0]; 2]]
    );
    // --default-colour: those faces get it, and the warning goes.
    let err = compile_warnings(&obj, &out, &["--flat", "--default-colour", "10,20,30"]);
    assert!(err.is_empty(), "{err}");
    let mut colours = dumped_colours(&out);
    colours.sort();
    assert_eq!(
        colours,
        [[[10, 20, 30]; 2], [[10, 20, 30]; 2], [[255, 0, 0]; 2]]
    );
    let bad = tempfile::tempdir().unwrap();
    refused(
        bad.path(),
        &[
            "compile",
            s(&obj),
            "-o",
            s(&bad.path().join("x.peel")),
            "--default-colour=300,0,0",
        ],
        &["--default-colour", "0..=255"],
    );
}

#[test]
fn render_has_a_default_size() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("cube.peel");
    assert!(peel(&["compile", &fixture("cube.obj"), "-o", s(&scene)])
        .status
        .success());
    let png = dir.path().join("x.png");
    let o = peel(&["render", s(&scene), "-o", s(&png)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        image::open(&png).unwrap().to_rgb8().dimensions(),
        (640, 480)
    );
    let help = String::from_utf8_lossy(&peel(&["render", "--help"]).stdout).into_owned();
    assert!(help.contains("[default: 640x480]"), "{help}");
}

/// The value of the line `name: value` of `text`.
fn line_value<'a>(text: &'a str, name: &str) -> &'a str {
    text.lines()
        .find_map(|l| l.strip_prefix(name)?.strip_prefix(": "))
        .unwrap_or_else(|| panic!("no '{name}' line in:\n{text}"))
}

#[test]
fn planes_and_split_planes_and_the_centre_read_alike_in_every_output() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("demo.peel");
    let o = peel(&["compile", &fixture("demo.obj"), "-o", s(&scene)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(summary.contains(" planes, "), "{summary}");
    let inspect = String::from_utf8_lossy(&peel(&["inspect", s(&scene)]).stdout).into_owned();
    let dump = String::from_utf8_lossy(&peel(&["dump", s(&scene)]).stdout).into_owned();
    // "planes" is the summary's distinct planes; what the file stores are split planes.
    let split_planes: usize = line_value(&inspect, "split_planes").parse().unwrap();
    assert_eq!(
        line_value(&dump, "  split_planes"),
        split_planes.to_string()
    );
    assert!(split_planes > 0);
    assert!(
        !inspect
            .lines()
            .chain(dump.lines())
            .any(|l| l.trim_start().starts_with("planes")),
        "{inspect}\n{dump}"
    );
    let json: serde_json::Value =
        serde_json::from_slice(&peel(&["inspect", s(&scene), "--json"]).stdout).unwrap();
    assert_eq!(json["split_planes"], split_planes);
    assert!(json.get("planes").is_none());
    // The centres (inspect's in world coordinates, the dump's the file's origin) with one
    // formatting: three numbers of six decimals.
    let six = |v: &str| {
        let v = v.split("  #").next().unwrap();
        let parts: Vec<&str> = v.trim_matches(['[', ']']).split(", ").collect();
        parts.len() == 3
            && parts
                .iter()
                .all(|p| p.parse::<f64>().is_ok() && p.split_once('.').unwrap().1.len() == 6)
    };
    for (what, v) in [
        ("inspect centre", line_value(&inspect, "centre")),
        ("inspect bounds_min", line_value(&inspect, "bounds_min")),
        ("dump centre", line_value(&dump, "  centre")),
        ("dump bounds_min", line_value(&dump, "  bounds_min")),
    ] {
        assert!(six(v), "{what}: {v}");
    }
    let c = json["centre"].as_array().unwrap();
    assert_eq!(
        line_value(&inspect, "centre"),
        format!(
            "[{:.6}, {:.6}, {:.6}]",
            c[0].as_f64().unwrap(),
            c[1].as_f64().unwrap(),
            c[2].as_f64().unwrap()
        )
    );
}

#[test]
fn inspect_prints_the_memory_a_frame_needs_and_measures_it_at_a_size() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("demo.peel");
    assert!(peel(&["compile", &fixture("demo.obj"), "-o", s(&scene)])
        .status
        .success());
    let json = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["inspect", s(&scene), "--json"];
        args.extend_from_slice(extra);
        let o = peel(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let plain = json(&[]);
    let m = &plain["frame_memory"];
    assert_eq!(m["stack"], plain["max_depth"]);
    assert_eq!(
        m["verts"].as_u64().unwrap(),
        plain["max_polygon_vertices"].as_u64().unwrap() + 5
    );
    let vertices = plain["vertices"].as_u64().unwrap();
    assert_eq!(
        m["vertex_memory"].as_u64(),
        Some(vertices.next_power_of_two())
    );
    assert_eq!(
        (m["spans_per_row"].as_u64(), m["scan_nodes"].as_u64()),
        (Some(64), Some(4096))
    );
    assert!(m["measured_at"].is_null());
    let measured = json(&["--size", "96x64"]);
    let n = &measured["frame_memory"];
    assert_eq!(n["measured_at"], serde_json::json!([96, 64]));
    assert_eq!((&n["stack"], &n["verts"]), (&m["stack"], &m["verts"]));
    let per_row = n["spans_per_row"].as_u64().unwrap();
    assert!((1..=48).contains(&per_row), "{n}");
    assert!(n["scan_nodes"].as_u64().unwrap() > 0);
    // The text: every figure, with its bytes, and whether it was measured.
    let o = peel(&["inspect", s(&scene), "--size=96x64"]);
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        text.contains("frame_memory (the sizes file's, measured at 96x64"),
        "{text}"
    );
    assert_eq!(
        line_value(&text, "  spans_per_row"),
        format!("{per_row} ({} bytes at 64 rows)", per_row * 64 * 4)
    );
    for name in [
        "stack",
        "verts",
        "vertex_memory",
        "scan_nodes",
        "scan_nodes_aa",
        "pending_pixels",
    ] {
        assert!(
            line_value(&text, &format!("  {name}"))
                .starts_with(&n[name].as_u64().unwrap().to_string()),
            "{name}: {text}"
        );
    }
    let text = String::from_utf8_lossy(&peel(&["inspect", s(&scene)]).stdout).into_owned();
    assert!(text.contains("`--size WxH` measures them"), "{text}");
    // A bad size names the flag.
    let o = peel(&["inspect", s(&scene), "--size=0x5"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--size"));
}

/// The long flags (`--name`) in `text`.
fn long_flags(text: &str) -> std::collections::BTreeSet<String> {
    let mut out = std::collections::BTreeSet::new();
    let bytes = text.as_bytes();
    let mut i = 0;
    while let Some(at) = text[i..].find("--") {
        let start = i + at;
        let mut end = start + 2;
        while end < bytes.len() && (bytes[end].is_ascii_alphanumeric() || bytes[end] == b'-') {
            end += 1;
        }
        let before = start.checked_sub(1).map(|b| bytes[b]);
        let word_start = !matches!(before, Some(b) if b.is_ascii_alphanumeric() || b == b'-');
        if word_start && end > start + 2 && bytes[start + 2].is_ascii_lowercase() {
            out.insert(text[start..end].to_string());
        }
        i = end;
    }
    out
}

/// `docs/command-line.md` cannot drift from the binary: for every subcommand, its synopsis
/// names exactly the long flags `peel <sub> --help` prints (and the page mentions them all).
#[test]
fn the_command_line_page_has_every_flag_of_every_subcommand() {
    let page_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/command-line.md");
    let page = std::fs::read_to_string(&page_path).unwrap();
    let synopsis = page
        .split("## Synopsis")
        .nth(1)
        .and_then(|rest| rest.split("```text\n").nth(1))
        .and_then(|rest| rest.split("```").next())
        .expect("a ```text block under ## Synopsis");
    // Each entry: a line starting with `peel `, with the indented lines that continue it.
    let mut entries: Vec<String> = Vec::new();
    for line in synopsis.lines() {
        if line.starts_with("peel ") {
            entries.push(line.to_string());
        } else if let Some(last) = entries.last_mut() {
            last.push('\n');
            last.push_str(line);
        }
    }
    for sub in ["compile", "inspect", "dump", "render", "demo", "bench"] {
        let o = peel(&[sub, "--help"]);
        assert!(o.status.success());
        let mut help = long_flags(&String::from_utf8_lossy(&o.stdout));
        help.remove("--help");
        let documented: std::collections::BTreeSet<String> = entries
            .iter()
            .filter(|e| e.starts_with(&format!("peel {sub} ")) || *e == &format!("peel {sub}"))
            .flat_map(|e| long_flags(e))
            .collect();
        assert_eq!(
            documented, help,
            "the synopsis of `peel {sub}` in docs/command-line.md against `peel {sub} --help`"
        );
        for flag in &help {
            assert!(page.contains(flag.as_str()), "{flag} of peel {sub}");
        }
    }
}

/// The `u32` at `at`.
fn u32_at(bytes: &[u8], at: usize) -> usize {
    u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize
}

/// The parts of a file of parts as its table gives them: name and tree bytes each.
fn table(bytes: &[u8]) -> Vec<(String, &[u8])> {
    use peel_runtime::read::layout::{parts_offset, PART_ENTRY_SIZE};
    (0..u32_at(bytes, parts_offset::COUNT))
        .map(|k| {
            let entry = parts_offset::TABLE + k * PART_ENTRY_SIZE;
            let [tree, tree_len, name, name_len] = [0, 4, 8, 12].map(|f| u32_at(bytes, entry + f));
            assert_eq!(tree % 4, 0, "part {k}");
            let name = std::str::from_utf8(&bytes[name..name + name_len]).unwrap();
            (name.to_string(), &bytes[tree..tree + tree_len])
        })
        .collect()
}

/// A world and two objects: a file of parts (version 5) of the three trees, each the tree its
/// OBJ compiles to alone but for its ids, which follow the triangles of the parts before it.
#[test]
fn a_world_and_objects_compile_to_a_file_of_parts() {
    use peel_runtime::read::layout::{parts_offset, MAGIC, PARTS_VERSION};
    use peel_runtime::read::Scene;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("scene.peel");
    let stats = dir.path().join("stats.json");
    let files = ["cube.obj", "staircase.obj", "triangle.obj"];
    let stairs = format!("stairs={}", fixture(files[1]));
    let tri = format!("tri={}", fixture(files[2]));
    let o = peel(&[
        "compile",
        &fixture(files[0]),
        "--object",
        &stairs,
        "--object",
        &tri,
        "--ids",
        "-o",
        s(&out),
        "--stats-json",
        s(&stats),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("(world)") && stdout.contains("(stairs)") && stdout.contains("3 parts"),
        "{stdout}"
    );
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(bytes[..4], MAGIC);
    assert_eq!(u16::from_le_bytes([bytes[4], bytes[5]]), PARTS_VERSION);
    assert_eq!(u32_at(&bytes, parts_offset::WORLD), 1);
    let parts = table(&bytes);
    let names: Vec<&str> = parts.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["", "stairs", "tri"]);

    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    assert_eq!(v["bytes"], bytes.len());
    let records = v["parts"].as_array().unwrap();
    assert_eq!(records.len(), 3);
    let mut before = 0;
    for (k, ((name, tree), file)) in parts.iter().zip(files).enumerate() {
        assert_eq!(records[k]["name"], name.as_str());
        assert_eq!(records[k]["bytes"], tree.len());
        let alone = dir.path().join(format!("alone{k}.peel"));
        let o = peel(&["compile", &fixture(file), "--ids", "-o", s(&alone)]);
        assert!(o.status.success());
        let alone = std::fs::read(&alone).unwrap();
        let (mine, theirs) = (Scene::parse(tree).unwrap(), Scene::parse(&alone).unwrap());
        assert_eq!(mine.header(), theirs.header(), "{file}");
        assert!(mine.header().polygon_count > 0);
        for i in 0..mine.header().polygon_count {
            assert_eq!(mine.id(i), theirs.id(i).map(|id| id + before), "{file}");
        }
        before += records[k]["input_triangles"].as_u64().unwrap() as u32;
    }

    let o = peel(&["inspect", s(&out)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    for line in [
        "format_version: 5",
        "parts: 3",
        "part 0 (world):",
        "part 2 (tri):",
    ] {
        assert!(text.contains(line), "no `{line}` in {text}");
    }
    let o = peel(&["inspect", s(&out), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let polygons: Vec<u64> = (v["parts"].as_array().unwrap().iter())
        .map(|p| p["output_polygons"].as_u64().unwrap())
        .collect();
    let most = polygons.iter().max().copied().unwrap();
    assert_eq!(polygons.len(), 3);
    assert!(v["frame_memory"]["stack"].as_u64().unwrap() > 0 && most > 0);
    let o = peel(&["dump", s(&out)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("a file of parts") && err.contains("stairs"));

    // Objects alone: no world.
    let o = peel(&["compile", "--object", &tri, "-o", s(&out)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(u32_at(&bytes, parts_offset::WORLD), 0);
    assert_eq!(table(&bytes).len(), 1);
}

/// A name the table cannot hold, a missing `=`, too many parts, no part, a missing or bad OBJ:
/// refused, with a message naming the problem, and no file written.
#[test]
fn bad_objects_are_refused_and_nothing_is_written() {
    use peel_runtime::read::layout::{MAX_NAME, MAX_PARTS};
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("scene.peel");
    let (cube, tri) = (fixture("cube.obj"), fixture("triangle.obj"));
    let long = format!("{}={tri}", "n".repeat(MAX_NAME as usize + 1));
    let empty = format!("={tri}");
    let a = format!("a={tri}");
    let absent = dir.path().join("absent.obj");
    let absent_arg = format!("b={}", s(&absent));
    let bad = format!("b={}", fixture("bad/bad_number.obj"));
    let cases: [(Vec<&str>, Vec<&str>); 7] = [
        (vec!["--object", &empty], vec!["--object", "no name"]),
        (vec!["--object", &long], vec!["--object", "at most"]),
        (vec!["--object", &tri], vec!["--object", "NAME=FILE"]),
        (
            vec!["--object", &a, "--object", &a],
            vec!["--object", "`a`", "given twice"],
        ),
        (
            vec!["--object", &a, "--object", &absent_arg],
            vec!["absent.obj"],
        ),
        (vec!["--object", &bad], vec!["bad_number.obj:"]),
        (vec![], vec!["nothing to compile", "--object"]),
    ];
    for (objects, says) in cases {
        let mut args = vec!["compile"];
        if !objects.is_empty() {
            args.push(&cube);
        }
        args.extend(&objects);
        args.extend(["-o", s(&out)]);
        refused(dir.path(), &args, &says);
    }
    let many: Vec<String> = (0..MAX_PARTS).map(|k| format!("o{k}={tri}")).collect();
    let mut args = vec!["compile", cube.as_str()];
    for m in &many {
        args.extend(["--object", m.as_str()]);
    }
    args.extend(["-o", s(&out)]);
    let max = format!("1 to {MAX_PARTS}");
    refused(dir.path(), &args, &["--object", &max]);
}

/// `peel render` of a file of parts: objects stay where their files put them or go where
/// `--pose` says, `--hide` leaves one out; an unknown name, a bad pose and objects whose
/// order cannot be proven are errors that name them, with no image written.
#[test]
fn render_poses_the_objects_of_a_file_of_parts() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.peel");
    let a = format!("a={}", fixture("cube.obj"));
    let b = format!("b={}", fixture("cube.obj"));
    let o = peel(&[
        "compile",
        &fixture("staircase.obj"),
        "--object",
        &a,
        "--object",
        &b,
        "--ids",
        "-o",
        s(&scene),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let render = |name: &str, extra: &[&str]| {
        let png = dir.path().join(name);
        let mut args = vec![
            "render",
            s(&scene),
            "--ids",
            "--size",
            "64x48",
            "-o",
            s(&png),
        ];
        args.extend_from_slice(extra);
        (peel(&args), png)
    };
    // Both cubes at their file's place: the same box, which no plane separates.
    let (o, png) = render("same.png", &[]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("objects a and b intersect"), "{err}");
    assert!(!png.exists());
    // Apart: drawn; the ids of both cubes show (ids follow the world's, then a's, then b's).
    let (o, png) = render(
        "apart.png",
        &["--pose", "a=-4,0,0", "--pose=b=4,0,0,45,0,0"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ids = |png: &std::path::Path| -> std::collections::BTreeSet<u32> {
        let img = image::open(png).unwrap().to_rgb8();
        img.pixels()
            .map(|p| u32::from(p[0]) << 16 | u32::from(p[1]) << 8 | u32::from(p[2]))
            .collect()
    };
    // Each cube's ids (+ 1, as the image holds them), from its tree.
    let bytes = std::fs::read(&scene).unwrap();
    let parts = peel_runtime::read::Parts::parse(&bytes).unwrap();
    let range = |k: u32| {
        let (_, tree) = parts.object(k).unwrap();
        let ids: Vec<u32> = (0..tree.header().polygon_count)
            .filter_map(|i| tree.id(i))
            .collect();
        (ids.iter().min().unwrap() + 1)..=(ids.iter().max().unwrap() + 1)
    };
    let (ids_a, ids_b) = (range(0), range(1));
    assert!(ids_a.end() < ids_b.start());
    let seen = ids(&png);
    assert!(seen.iter().any(|id| ids_a.contains(id)), "a: {seen:?}");
    assert!(seen.iter().any(|id| ids_b.contains(id)), "b: {seen:?}");
    // b hidden: its ids are gone, a's stay.
    let (o, png) = render("hidden.png", &["--pose", "a=-4,0,0", "--hide", "b"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let seen = ids(&png);
    assert!(!seen.iter().any(|id| ids_b.contains(id)), "b still shows");
    assert!(seen.iter().any(|id| ids_a.contains(id)), "a is gone");
    // Errors.
    let (o, png) = render("unknown.png", &["--pose", "kettle=0,0,0"]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("kettle") && err.contains("a, b"), "{err}");
    assert!(!png.exists());
    let (o, png) = render("bad.png", &["--pose", "a=1,2"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--pose"));
    assert!(!png.exists());
}
