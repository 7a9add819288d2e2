//! Loader tests: bad inputs (fixtures under `fixtures/bad/`), materials, order, polygons.

use super::*;
use std::fs;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/bad")
        .join(name)
}

/// Writes `files` (name, content) into a fresh temporary directory.
fn write_files(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, content) in files {
        fs::write(dir.path().join(name), content).unwrap();
    }
    dir
}

fn load_text(obj: &str) -> Mesh {
    let dir = write_files(&[("m.obj", obj)]);
    load_obj(&dir.path().join("m.obj")).unwrap()
}

fn line_of(e: &CompileError) -> Option<usize> {
    match e {
        CompileError::Parse { line, .. }
        | CompileError::NonFinite { line, .. }
        | CompileError::IndexOutOfRange { line, .. } => Some(*line),
        _ => None,
    }
}

#[test]
fn bad_fixtures_give_their_documented_error_and_line() {
    let cases: &[(&str, &str, Option<usize>)] = &[
        ("nan_coordinate.obj", "NonFinite", Some(4)),
        ("inf_coordinate.obj", "NonFinite", Some(3)),
        ("index_out_of_range.obj", "IndexOutOfRange", Some(6)),
        ("negative_index.obj", "IndexOutOfRange", Some(5)),
        ("zero_index.obj", "IndexOutOfRange", Some(5)),
        ("forward_reference.obj", "IndexOutOfRange", Some(5)),
        ("no_faces.obj", "NoFaces", None),
        ("bad_number.obj", "Parse", Some(3)),
        ("bad_face.obj", "Parse", Some(5)),
        ("cut_off_face.obj", "Parse", Some(8)),
    ];
    for &(name, kind, line) in cases {
        let path = fixture(name);
        let e = load_obj(&path).expect_err(name);
        let debug = format!("{e:?}");
        assert!(
            debug.starts_with(kind),
            "{name}: expected {kind}, got {debug}"
        );
        assert_eq!(line_of(&e), line, "{name}: {e}");
        let shown = e.to_string();
        assert!(
            shown.contains(name),
            "{name}: message must name the file: {shown}"
        );
        if let Some(line) = line {
            assert!(shown.contains(&format!("{name}:{line}:")), "{shown}");
        }
    }
}

#[test]
fn out_of_range_reports_index_and_count() {
    match load_obj(&fixture("index_out_of_range.obj")) {
        Err(CompileError::IndexOutOfRange { index, count, .. }) => {
            assert_eq!((index, count), (5, 3));
        }
        other => panic!("{other:?}"),
    }
    match load_obj(&fixture("nan_coordinate.obj")) {
        Err(CompileError::NonFinite { value, .. }) => assert_eq!(value, "NaN"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn unreadable_file_is_io() {
    let dir = tempfile::tempdir().unwrap();
    let e = load_obj(&dir.path().join("absent.obj")).unwrap_err();
    assert!(matches!(e, CompileError::Io { .. }), "{e:?}");
}

#[test]
fn invalid_utf8_is_a_parse_error_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.obj");
    fs::write(&path, b"v 0 0 0\nv 1 0 0\n# caf\xe9\nv 0 1 0\nf 1 2 3\n").unwrap();
    let e = load_obj(&path).unwrap_err();
    assert!(matches!(e, CompileError::Parse { line: 3, .. }), "{e:?}");
}

#[test]
fn mtl_colours_are_rounded_and_clamped() {
    let dir = write_files(&[
        (
            "m.obj",
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl half\nf 1 2 3\nusemtl wild\nf 1 2 3\n",
        ),
        (
            "m.mtl",
            "newmtl half\nKd 0.5 0.25 0.002\nnewmtl wild\nKd -0.2 1.5 0.998\n",
        ),
    ]);
    let obj = dir.path().join("m.obj");
    let mesh = load_obj(&obj).unwrap();
    let colours: Vec<_> = mesh.triangles.iter().map(|t| t.colour).collect();
    // 127.5 -> 128, 63.75 -> 64, 0.51 -> 1; clamped -> 0 and 255, 254.49 -> 254.
    assert_eq!(colours, [[128, 64, 1], [0, 255, 254]]);
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
    assert_eq!(mesh.files, [obj, dir.path().join("m.mtl")]);
}

#[test]
fn missing_mtl_gives_default_colour_and_a_warning() {
    let dir = write_files(&[(
        "m.obj",
        "v 0 0 0\nv 1 0 0\nmtllib gone.mtl\nv 0 1 0\nusemtl red\nf 1 2 3\n",
    )]);
    let obj = dir.path().join("m.obj");
    let mesh = load_obj(&obj).unwrap();
    assert_eq!(mesh.triangles[0].colour, DEFAULT_COLOUR);
    assert_eq!(mesh.files, [obj]);
    let text = mesh.warnings.join("\n");
    assert!(text.contains("m.obj:3:"), "{text}");
    assert!(
        text.contains("gone.mtl") && text.contains("not found"),
        "{text}"
    );
    assert!(text.contains("`red` is not defined"), "{text}");
}

#[test]
fn faces_without_material_or_kd_warn() {
    let dir = write_files(&[
        (
            "m.obj",
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 3\nusemtl plain\nf 1 2 3\n",
        ),
        ("m.mtl", "newmtl plain\nNs 10\n"),
    ]);
    let mesh = load_obj(&dir.path().join("m.obj")).unwrap();
    assert!(mesh.triangles.iter().all(|t| t.colour == DEFAULT_COLOUR));
    let text = mesh.warnings.join("\n");
    assert!(text.contains("2 faces have no material"), "{text}");
    assert!(text.contains("first at line 5"), "{text}");
    // The warning says how to choose their colour.
    assert!(
        text.contains("default colour 200,200,200") && text.contains("--default-colour R,G,B"),
        "{text}"
    );
    assert!(
        text.contains("`plain` has no usable diffuse colour"),
        "{text}"
    );
}

#[test]
fn a_file_that_names_no_material_gets_the_default_colour_without_a_warning() {
    // A plain mesh: no `mtllib`, no `usemtl`.
    let mesh = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 1 2 4 3\n");
    assert_eq!((mesh.faces, mesh.triangles.len()), (2, 3));
    assert!(mesh.triangles.iter().all(|t| t.colour == DEFAULT_COLOUR));
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
    // Naming a material anywhere makes faces without one a mistake again.
    for named in ["usemtl red\n", "mtllib m.mtl\n"] {
        let dir = write_files(&[
            (
                "m.obj",
                &format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n{named}f 1 2 3\n"),
            ),
            ("m.mtl", "newmtl red\nKd 1 0 0\n"),
        ]);
        let mesh = load_obj(&dir.path().join("m.obj")).unwrap();
        let text = mesh.warnings.join("\n");
        assert!(text.contains("no material"), "{named}: {text}");
    }
}

#[test]
fn a_chosen_default_colour_is_meant_for_faces_without_material_and_silences_their_warning() {
    let dir = write_files(&[
        (
            "m.obj",
            "mtllib m.mtl\nmtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n\
             usemtl plain\nf 1 2 3\nusemtl undefined\nf 1 2 3\nusemtl red\nf 1 2 3\n",
        ),
        ("m.mtl", "newmtl plain\nNs 10\nnewmtl red\nKd 1 0 0\n"),
    ]);
    let obj = dir.path().join("m.obj");
    let options = LoadOptions {
        default_colour: Some([1, 2, 3]),
        ..LoadOptions::default()
    };
    let mesh = load_obj_with(&obj, &options).unwrap();
    let colours: Vec<_> = mesh.triangles.iter().map(|t| t.colour).collect();
    assert_eq!(colours, [[1, 2, 3], [1, 2, 3], [1, 2, 3], [255, 0, 0]]);
    // No warning for the face without material; the mistakes in the files still warn.
    let text = mesh.warnings.join("\n");
    assert!(!text.contains("no material"), "{text}");
    assert!(
        text.contains("`plain` has no usable diffuse colour"),
        "{text}"
    );
    assert!(text.contains("`undefined` is not defined"), "{text}");
    assert!(
        text.contains("gone.mtl") && text.contains("not found"),
        "{text}"
    );
    assert_eq!(mesh.warnings.len(), 3, "{text}");
    // Without the option: the grey, and the warning.
    let plain = load_obj(&obj).unwrap();
    assert_eq!(plain.triangles[0].colour, DEFAULT_COLOUR);
    assert_eq!(plain.warnings.len(), 4);
    // The MTL bytes parsed are kept, for a build cache.
    assert_eq!(
        mesh.mtl_bytes,
        [(
            dir.path().join("m.mtl"),
            b"newmtl plain\nNs 10\nnewmtl red\nKd 1 0 0\n".to_vec()
        )]
    );
}

#[test]
fn ids_follow_f_lines_across_material_and_group_changes() {
    // Materials switch back and forth, with objects and groups in between: tobj makes a model
    // per switch, and the ids must still follow the `f` lines.
    let obj = "\
mtllib m.mtl
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
usemtl a
f 1 2 3
o second
usemtl b
f 1 2 4
f 1 3 4
usemtl a
g half
f 2 3 4
usemtl b
o third
f 4 3 2
g
usemtl a
f 1 4 2 3
";
    let dir = write_files(&[
        ("m.obj", obj),
        ("m.mtl", "newmtl a\nKd 1 0 0\nnewmtl b\nKd 0 0 1\n"),
    ]);
    let mesh = load_obj(&dir.path().join("m.obj")).unwrap();
    let v = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(0.0, 0.0, 1.0),
    ];
    let (a, b) = ([255, 0, 0], [0, 0, 255]);
    let expected_first = [
        ([1, 2, 3], a),
        ([1, 2, 4], b),
        ([1, 3, 4], b),
        ([2, 3, 4], a),
        ([4, 3, 2], b),
    ];
    for (i, (corners, colour)) in expected_first.iter().enumerate() {
        let t = &mesh.triangles[i];
        assert_eq!(t.vertices, corners.map(|c| v[c - 1]), "triangle {i}");
        assert_eq!(t.colour, *colour, "triangle {i}");
    }
    // The last face is a (non-planar) quad: two triangles in colour a.
    assert_eq!(mesh.triangles.len(), 7);
    assert!(mesh.triangles[5..].iter().all(|t| t.colour == a));
}

#[test]
fn concave_polygon_covers_its_exact_area() {
    // An L-shape in the plane y = 2, winding so the normal points to -y.
    let mesh = load_text("v 0 2 0\nv 2 2 0\nv 2 2 1\nv 1 2 1\nv 1 2 2\nv 0 2 2\nf 1 2 3 4 5 6\n");
    assert_eq!(mesh.triangles.len(), 4);
    let mut total = DVec3::ZERO;
    for t in &mesh.triangles {
        let [p, q, r] = t.vertices;
        let n = (q - p).cross(r - p);
        assert!(
            n.y < 0.0 && n.x == 0.0 && n.z == 0.0,
            "winding must match the face: {n}"
        );
        total += n / 2.0;
        // The notch [1, 2] x [1, 2] (in x, z) is outside the L: no centroid may fall in it.
        let c = (p + q + r) / 3.0;
        assert!(
            !(c.x > 1.0 && c.z > 1.0),
            "triangle outside the polygon: {t:?}"
        );
    }
    assert_eq!(total, DVec3::new(0.0, -3.0, 0.0));
}

#[test]
fn quad_splits_into_two_triangles_in_documented_order() {
    let mesh = load_text("v 0 0 0\nv 4 0 0\nv 4 1 0\nv 0 3 0\nf 1 2 3 4\n");
    let v = |i: usize| mesh.triangles.iter().map(move |t| t.vertices[i]);
    assert_eq!(mesh.triangles.len(), 2);
    let p = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(4.0, 0.0, 0.0),
        DVec3::new(4.0, 1.0, 0.0),
        DVec3::new(0.0, 3.0, 0.0),
    ];
    // Each triangle starts at its smallest corner and the pair is sorted.
    let corners: Vec<[usize; 3]> = mesh
        .triangles
        .iter()
        .map(|t| t.vertices.map(|x| p.iter().position(|&y| y == x).unwrap()))
        .collect();
    assert!(corners.windows(2).all(|w| w[0] < w[1]), "{corners:?}");
    assert!(
        corners.iter().all(|c| c[0] < c[1] && c[0] < c[2]),
        "{corners:?}"
    );
    let area: f64 = mesh
        .triangles
        .iter()
        .map(|t| {
            (t.vertices[1] - t.vertices[0])
                .cross(t.vertices[2] - t.vertices[0])
                .z
                / 2.0
        })
        .inspect(|&a| assert!(a > 0.0))
        .sum();
    assert_eq!(area, 8.0);
    assert_eq!(v(0).count(), 2);
}

/// Faces that name a normal at every corner keep them (normalised) on their triangles'
/// corners, a pentagon's triangles those of their own corners, whichever `v/vt/vn` form and
/// whatever material or group comes between; the others keep none.
#[test]
fn normals_from_the_file_follow_their_corners() {
    let mesh = load_text(
        "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 3 0\nv -1 1 0\nvt 0 0\n\
         vn 0 0 2\nvn 1 0 1\nvn 0 1 1\nvn -1 0 1\nvn 0 -1 1\nvn 0 0 0\n\
         f 1//1 2//2 3//3 4//4 5//5\n\
         g other\nf 1/1/5 3/1/3 4/1/4\n\
         f 1 2 3\n\
         f 1//1 2 3//3\n\
         f 1//6 2//2 3//3\n",
    );
    let normal = |i: usize| {
        [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.0, 1.0, 1.0),
            DVec3::new(-1.0, 0.0, 1.0),
            DVec3::new(0.0, -1.0, 1.0),
        ][i]
            .normalize()
    };
    let corners = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(3.0, 1.0, 0.0),
        DVec3::new(1.0, 3.0, 0.0),
        DVec3::new(-1.0, 1.0, 0.0),
    ];
    assert_eq!(mesh.triangles.len(), 3 + 1 + 3);
    // The pentagon: every triangle corner has the normal of the face corner it is.
    for t in &mesh.triangles[..3] {
        let normals = t.normals.expect("the pentagon's normals");
        for (v, n) in t.vertices.iter().zip(normals) {
            let corner = corners.iter().position(|c| c == v).unwrap();
            assert_eq!(n, normal(corner), "at {v}");
        }
    }
    let tri = &mesh.triangles[3];
    assert_eq!(tri.vertices, [corners[0], corners[2], corners[3]]);
    assert_eq!(tri.normals, Some([normal(4), normal(2), normal(3)]));
    // No normals, some corners only, one of no length: none.
    assert!(mesh.triangles[4..].iter().all(|t| t.normals.is_none()));
}

#[test]
fn self_intersecting_polygon_falls_back_to_a_fan_with_a_warning() {
    let mesh = load_text("v 0 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 4\n");
    assert_eq!(mesh.triangles.len(), 2);
    assert_eq!(mesh.triangles[0].vertices[0], DVec3::ZERO);
    assert_eq!(mesh.triangles[1].vertices[0], DVec3::ZERO);
    let text = mesh.warnings.join("\n");
    assert!(
        text.contains("1 face is not a simple polygon") && text.contains("line 5"),
        "{text}"
    );
}

#[test]
fn short_faces_and_polylines_are_skipped_with_warnings() {
    let mesh = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nl 1 2 3\nf 3 2 1\n");
    assert_eq!(mesh.triangles.len(), 1);
    assert_eq!(mesh.triangles[0].vertices[0], DVec3::new(0.0, 1.0, 0.0));
    let text = mesh.warnings.join("\n");
    assert!(text.contains("fewer than three corners (line 4)"), "{text}");
    assert!(text.contains("1 polyline"), "{text}");
}

#[test]
fn degenerate_triangles_are_kept() {
    let mesh = load_text("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\nf 1 2 3 2\n");
    // One collinear triangle, one with a repeated corner, and a collinear quad as a fan.
    assert_eq!(mesh.triangles.len(), 4);
}

#[test]
fn weight_and_relative_indices() {
    let mesh = load_text("v 2 4 6 2\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n");
    assert_eq!(mesh.triangles[0].vertices[0], DVec3::new(1.0, 2.0, 3.0));
}

#[test]
fn oversized_file_is_too_large() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.obj");
    let file = fs::File::create(&path).unwrap();
    file.set_len(MAX_INPUT_BYTES + 1).unwrap(); // sparse: no real disk use
    let e = load_obj(&path).unwrap_err();
    assert!(matches!(e, CompileError::TooLarge { .. }), "{e:?}");
}

#[test]
fn shared_models_load() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/models");
    if !dir.is_dir() {
        println!("skipping: shared models not found at ../shared/models");
        return;
    }
    for name in ["suzanne.obj", "teapot.obj", "cow.obj", "stanford-bunny.obj"] {
        let path = dir.join(name);
        if !path.is_file() {
            println!("skipping {name}: not present");
            continue;
        }
        let mesh = load_obj(&path).unwrap_or_else(|e| panic!("{e}"));
        let text = fs::read_to_string(&path).unwrap();
        let expected: usize = text
            .lines()
            .filter(|l| l.starts_with("f "))
            .map(|l| l.split_whitespace().count() - 3)
            .sum();
        // These models have no repeated corners, so every n-gon gives n - 2 triangles.
        assert_eq!(mesh.triangles.len(), expected, "{name}");
        assert!(
            mesh.warnings
                .iter()
                .all(|w| !w.contains("not a simple polygon")),
            "{name}: {:?}",
            mesh.warnings
        );
        assert!(mesh
            .triangles
            .iter()
            .all(|t| t.vertices.iter().all(|v| v.is_finite())));
        // Suzanne gives a normal at every corner, the others none.
        let with_normals = mesh
            .triangles
            .iter()
            .filter(|t| t.normals.is_some())
            .count();
        let given = if name == "suzanne.obj" {
            mesh.triangles.len()
        } else {
            0
        };
        assert_eq!(with_normals, given, "{name}");
    }
}
