//! `peel compile` of textured scenes (MTL `map_Kd`, OBJ `vt`), `--max-texture` and
//! `--no-resample`, what `peel inspect` and `peel dump` say of the file, and the errors that
//! name the OBJ or MTL line.

use std::path::Path;

mod common;
use common::{peel, refused, s};

/// A quad of material `tex` with its corners' coordinates (`f` at line 11) and a triangle of
/// material `plain` without them.
const OBJ: &str = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                   vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl tex\nf 1/1 2/2 3/3 4/4\n\
                   usemtl plain\nf 1 3 2\n";

/// Writes `m.obj` (`obj`), `m.mtl` (`mtl`) and, with a size, `t.png` of `width x height`
/// pixels (red on the left half, blue on the right) into `dir`; returns the OBJ's path.
fn scene(dir: &Path, obj: &str, mtl: &str, image: Option<(u32, u32)>) -> String {
    std::fs::write(dir.join("m.obj"), obj).unwrap();
    std::fs::write(dir.join("m.mtl"), mtl).unwrap();
    if let Some((w, h)) = image {
        let png = image::RgbImage::from_fn(w, h, |x, _| {
            image::Rgb(if x < w / 2 { [255, 0, 0] } else { [0, 0, 255] })
        });
        png.save(dir.join("t.png")).unwrap();
    }
    dir.join("m.obj").to_string_lossy().into_owned()
}

const MTL: &str = "newmtl tex\nKd 1 1 1\nmap_Kd -clamp on t.png\nnewmtl plain\nKd 0 1 0\n";

#[test]
fn a_textured_scene_is_a_format_6_file_that_inspect_dump_and_render_read() {
    let src = tempfile::tempdir().unwrap();
    let obj = scene(src.path(), OBJ, MTL, Some((300, 100)));
    let out = tempfile::tempdir().unwrap();
    let file = out.path().join("t.peel");
    let o = peel(&["compile", &obj, "-o", s(&file)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(&file).unwrap();
    assert_eq!(u16::from_le_bytes([bytes[4], bytes[5]]), 6);

    let o = peel(&["inspect", s(&file)]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    // 300 x 100 resampled to 256 x 128; a few colours (the filter's ringing at the halves'
    // border adds some to red and blue): a palette.
    for line in [
        "format_version: 6\n",
        "textured_polygons: 2\n",
        "textures: 1\n  - 256x128, palette of ",
        " colours, clamp s and t, ",
    ] {
        assert!(text.contains(line), "no {line:?} in:\n{text}");
    }
    let o = peel(&["inspect", s(&file), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["textures"][0]["width"], 256);
    assert_eq!(v["textures"][0]["clamp_t"], true);
    assert_eq!(v["textured_polygons"], 2);
    let colours = v["textures"][0]["palette_colours"].as_u64().unwrap();
    assert!((2..=16).contains(&colours), "{colours}");
    assert_eq!(v["textures"][0]["bytes"], 2 * colours + 256 * 128);
    assert_eq!(v["texture_bytes"], v["textures"][0]["bytes"]);

    let o = peel(&["dump", s(&file)]);
    assert!(o.status.success());
    let yaml = String::from_utf8_lossy(&o.stdout);
    assert!(
        yaml.contains("  flags: [index16, narrow, two_colours, textures]\n"),
        "{yaml}"
    );
    assert!(
        yaml.contains("textures:\n  - 256x128, palette of ") && yaml.contains(" bytes  # 0\n"),
        "{yaml}"
    );
    assert_eq!(yaml.matches("texture: 0\n").count(), 2, "{yaml}");
    // The quad's corner `vt 1 1` is `[65536, 0]`: `t` runs down from the image's top.
    assert!(yaml.contains("[65536, 0]"), "{yaml}");

    let png = out.path().join("t.png");
    let o = peel(&["render", s(&file), "-o", s(&png), "--size", "64x48"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(png.exists());
}

#[test]
fn a_texture_coordinate_index_out_of_range_is_an_error_at_its_line() {
    let src = tempfile::tempdir().unwrap();
    let obj = scene(
        src.path(),
        &OBJ.replace("f 1/1 2/2 3/3 4/4", "f 1/1 2/2 3/3 4/5"),
        MTL,
        Some((4, 4)),
    );
    let out = tempfile::tempdir().unwrap();
    let file = out.path().join("t.peel");
    refused(
        out.path(),
        &["compile", &obj, "-o", s(&file)],
        &["m.obj:11: texture coordinate index 5 out of range (4 defined before this line)"],
    );
    let o = peel(&["compile", &obj, "-o", s(&file)]);
    assert_eq!(o.status.code(), Some(1));
}

#[test]
fn a_missing_texture_is_an_error_naming_it_and_the_mtl_line() {
    let src = tempfile::tempdir().unwrap();
    let obj = scene(src.path(), OBJ, MTL, None);
    let out = tempfile::tempdir().unwrap();
    let image = src.path().join("t.png");
    refused(
        out.path(),
        &["compile", &obj, "-o", s(&out.path().join("t.peel"))],
        &[&format!(
            "m.mtl:3: texture {}: cannot read",
            image.display()
        )],
    );
}

#[test]
fn without_resampling_a_texture_must_already_fit() {
    let src = tempfile::tempdir().unwrap();
    let obj = scene(src.path(), OBJ, MTL, Some((512, 64)));
    let out = tempfile::tempdir().unwrap();
    let file = out.path().join("t.peel");
    let compile = |extra: &[&str]| {
        let mut args = vec!["compile", obj.as_str(), "-o", s(&file)];
        args.extend_from_slice(extra);
        args.iter().map(|a| a.to_string()).collect::<Vec<String>>()
    };
    let args = compile(&["--no-resample"]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    refused(
        out.path(),
        &args,
        &[
            "m.mtl:3: texture ",
            "t.png is 512x64",
            "(--no-resample)",
            "at most 256 texels",
        ],
    );
    // Within a larger limit it is stored as it is; resampled, it is brought to the limit.
    for (extra, size) in [
        (&["--no-resample", "--max-texture", "512"][..], "512x64"),
        (&["--max-texture", "128"][..], "128x64"),
    ] {
        let args = compile(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = peel(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let o = peel(&["inspect", s(&file)]);
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains(&format!("  - {size}, ")), "{extra:?}: {text}");
    }
}

#[test]
fn a_texture_limit_that_is_no_power_of_two_is_refused() {
    let out = tempfile::tempdir().unwrap();
    for bad in ["100", "2048", "0", "many"] {
        let o = peel(&[
            "compile",
            &common::fixture("cube.obj"),
            "-o",
            s(&out.path().join("c.peel")),
            "--max-texture",
            bad,
        ]);
        assert_eq!(o.status.code(), Some(2), "{bad}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("--max-texture"), "{err}");
    }
    assert!(std::fs::read_dir(out.path()).unwrap().next().is_none());
}
