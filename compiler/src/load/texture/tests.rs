//! Textured materials: `vt` per corner, `map_Kd` read once per image with its options, images
//! decoded and brought to power-of-two sides, and the errors that name the MTL line.

use std::fs;
#[cfg(feature = "textures")]
use std::path::Path;

#[cfg(feature = "textures")]
use glam::DVec2;

use crate::error::CompileError;
use crate::load::{load_obj, load_obj_with, LoadOptions};

/// Writes `files` (name, content) into a fresh temporary directory.
fn write_files(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, content) in files {
        fs::write(dir.path().join(name), content).unwrap();
    }
    dir
}

/// A square with corner texture coordinates, as one quad of material `tex` (lines 1 to 10),
/// and a triangle of material `plain` without them (line 12).
const QUAD: &str = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                    vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl tex\nf 1/1 2/2 3/3 4/4\n\
                    usemtl plain\nf 1 2 3\n";

/// Writes a `width x height` PNG whose pixel `(x, y)` is `colour(x, y)`.
#[cfg(feature = "textures")]
fn png(path: &Path, width: u32, height: u32, colour: impl Fn(u32, u32) -> [u8; 3]) {
    image::RgbImage::from_fn(width, height, |x, y| image::Rgb(colour(x, y)))
        .save(path)
        .unwrap();
}

#[cfg(feature = "textures")]
#[test]
fn a_textured_face_keeps_its_corners_coordinates_and_the_image_is_read_once() {
    let dir = write_files(&[
        ("m.obj", &format!("{QUAD}usemtl again\nf 1/1 2/2 3/3\n")),
        (
            "m.mtl",
            "newmtl tex\nKd 1 1 1\nmap_Kd -clamp on wall.png\nnewmtl plain\nKd 1 0 0\n\
             newmtl again\nmap_Kd wall.png\n",
        ),
    ]);
    // Row 0 is the image's top: red on top, blue below; left half dark.
    png(&dir.path().join("wall.png"), 2, 2, |x, y| match (x, y) {
        (0, 0) => [0, 0, 0],
        (1, 0) => [255, 0, 0],
        (0, 1) => [0, 0, 0],
        _ => [0, 0, 255],
    });
    let mesh = load_obj(&dir.path().join("m.obj")).unwrap();
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
    // The quad's two triangles, each corner its own `vt`; the plain triangle none.
    let uv = |k: usize| [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y][k];
    for t in &mesh.triangles[..2] {
        let got = t.texture.unwrap();
        assert_eq!(got.texture, 0);
        for (corner, uv_got) in t.vertices.iter().zip(got.uv) {
            let k = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
                .iter()
                .position(|&(x, y)| corner.x == x && corner.y == y)
                .unwrap();
            assert_eq!(uv_got, uv(k));
        }
    }
    assert_eq!(mesh.triangles[2].texture, None);
    // The same image without `-clamp`: a texture of its own, from the image read once. Its
    // material has no `Kd`: the texture shows as it is, without a warning.
    assert_eq!(mesh.triangles[3].texture.unwrap().texture, 1);
    assert_eq!(mesh.triangles[3].colour, [255; 3]);
    assert_eq!(mesh.textures.len(), 2);
    let (clamped, repeated) = (&mesh.textures[0], &mesh.textures[1]);
    assert_eq!((clamped.clamp, repeated.clamp), ([true; 2], [false; 2]));
    assert_eq!(clamped.texels, [0x0000, 0xF800, 0x0000, 0x001F]);
    assert_eq!(clamped.texels, repeated.texels);
    assert_eq!((clamped.width(), clamped.height()), (2, 2));
    // `vt 1 1` (u = 1, v = 1) is the top right texel, clamped; repeated, it wraps to the left.
    assert_eq!(clamped.texel_of(1.0, 1.0), (1, 0));
    assert_eq!(repeated.texel_of(1.0, 1.0), (0, 0));
    assert_eq!(clamped.texel(1, 1), 0x001F);
    // The image is a file of the build, once, with its bytes.
    let image = dir.path().join("wall.png");
    assert_eq!(mesh.files.iter().filter(|f| **f == image).count(), 1);
    let bytes = fs::read(&image).unwrap();
    assert!(mesh.mtl_bytes.contains(&(image, bytes)));
}

#[cfg(feature = "textures")]
#[test]
fn a_polygon_face_gives_each_triangle_its_corners_coordinates() {
    let dir = write_files(&[
        (
            "m.obj",
            "mtllib m.mtl\nv 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\n\
             vt 0 0\nvt 0.5 0\nvt 0.5 0.25\nvt 0.25 0.5\nvt 0 0.25\nusemtl tex\n\
             f 1/1 2/2 3/3 4/4 5/5\n",
        ),
        ("m.mtl", "newmtl tex\nmap_Kd t.png\n"),
    ]);
    png(&dir.path().join("t.png"), 4, 4, |_, _| [255, 255, 255]);
    let mesh = load_obj(&dir.path().join("m.obj")).unwrap();
    assert_eq!(mesh.triangles.len(), 3);
    for t in &mesh.triangles {
        let uvs = t.texture.unwrap().uv;
        for (corner, uv) in t.vertices.iter().zip(uvs) {
            // Each corner's `vt` is its position over 4.
            assert_eq!(uv, corner.truncate() / 4.0, "{t:?}");
        }
    }
}

#[cfg(feature = "textures")]
#[test]
fn faces_without_coordinates_at_every_corner_show_the_colour_with_a_warning() {
    let dir = write_files(&[
        (
            "m.obj",
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl tex\n\
             f 1 2 3\nf 1/1 2 3/1\nf 1/1 2/1 3/1\n",
        ),
        (
            "m.mtl",
            "newmtl tex\nKd 1 1 1\nmap_Kd -bm 0.5 -s 2 2 t.png\n",
        ),
    ]);
    png(&dir.path().join("t.png"), 1, 1, |_, _| [9, 9, 9]);
    let mesh = load_obj(&dir.path().join("m.obj")).unwrap();
    let textured: Vec<bool> = mesh.triangles.iter().map(|t| t.texture.is_some()).collect();
    assert_eq!(textured, [false, false, true]);
    let text = mesh.warnings.join("\n");
    assert!(
        text.contains("material `tex` has a texture (`map_Kd`), but 2 faces give (first at line 7) no texture coordinates"),
        "{text}"
    );
    assert!(
        text.contains("m.mtl:3: `map_Kd` options -bm 0.5, -s 2 2 ignored"),
        "{text}"
    );
}

#[cfg(feature = "textures")]
#[test]
fn a_missing_or_undecodable_image_is_an_error_naming_it_and_the_mtl_line() {
    let dir = write_files(&[
        (
            "m.obj",
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl tex\nf 1/1 2/1 3/1\n",
        ),
        ("m.mtl", "# wall\nnewmtl tex\nKd 1 1 1\nmap_Kd gone.png\n"),
    ]);
    let e = load_obj(&dir.path().join("m.obj")).unwrap_err();
    assert!(
        matches!(e, CompileError::TextureFile { line: 4, .. }),
        "{e:?}"
    );
    let shown = e.to_string();
    assert!(
        shown.contains("m.mtl:4: texture ") && shown.contains("gone.png: cannot read"),
        "{shown}"
    );
    fs::write(dir.path().join("gone.png"), "not an image").unwrap();
    let e = load_obj(&dir.path().join("m.obj")).unwrap_err();
    assert!(
        matches!(e, CompileError::TextureImage { line: 4, .. }),
        "{e:?}"
    );
    assert!(e.to_string().contains("gone.png: cannot decode"), "{e}");
    // An image no face uses is not read: the plain faces compile.
    let dir = write_files(&[
        (
            "m.obj",
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl tex\nf 1 2 3\n",
        ),
        ("m.mtl", "newmtl tex\nKd 1 1 1\nmap_Kd gone.png\n"),
    ]);
    let mesh = load_obj(&dir.path().join("m.obj")).unwrap();
    assert!(mesh.textures.is_empty());
}

#[cfg(feature = "textures")]
#[test]
fn a_bad_map_kd_option_is_an_error_at_its_line() {
    let dir = write_files(&[
        ("m.obj", QUAD),
        (
            "m.mtl",
            "newmtl tex\nmap_Kd -clamp sometimes t.png\nnewmtl plain\n",
        ),
    ]);
    let e = load_obj(&dir.path().join("m.obj")).unwrap_err();
    assert!(matches!(e, CompileError::Mtl { line: 2, .. }), "{e:?}");
    assert!(
        e.to_string()
            .contains("m.mtl:2: `map_Kd`: `-clamp sometimes`: the value is `on` or `off`"),
        "{e}"
    );
}

#[cfg(feature = "textures")]
#[test]
fn sides_that_cannot_be_stored_are_resampled_or_refused() {
    let dir = write_files(&[
        ("m.obj", QUAD),
        ("m.mtl", "newmtl tex\nmap_Kd t.png\nnewmtl plain\n"),
    ]);
    let obj = dir.path().join("m.obj");
    let image = dir.path().join("t.png");
    // 300 x 100: 256 x 128 (the nearest powers of two); 600 x 3 with the limit at 256: 256 x 4.
    for ((w, h), max, want) in [((300, 100), 256, (256, 128)), ((600, 3), 256, (256, 4))] {
        png(&image, w, h, |x, _| {
            if x < w / 2 {
                [255, 0, 0]
            } else {
                [0, 0, 255]
            }
        });
        let options = LoadOptions {
            max_texture: max,
            ..LoadOptions::default()
        };
        let mesh = load_obj_with(&obj, &options).unwrap();
        let t = &mesh.textures[0];
        assert_eq!((t.width(), t.height()), want);
        assert_eq!(t.texels.len(), (want.0 * want.1) as usize);
        // Far from the middle the halves keep their colours.
        assert_eq!(t.texel(0, 0), 0xF800);
        assert_eq!(t.texel(want.0 - 1, want.1 - 1), 0x001F);
        // Without resampling: refused, naming the image, its size, the MTL line and the limit.
        let options = LoadOptions {
            resample: false,
            ..options
        };
        let e = load_obj_with(&obj, &options).unwrap_err();
        assert!(
            matches!(e, CompileError::TextureSize { line: 2, width, height, .. } if (width, height) == (w, h)),
            "{e:?}"
        );
        let shown = e.to_string();
        assert!(
            shown.contains("m.mtl:2: texture ")
                && shown.contains(&format!("t.png is {w}x{h}"))
                && shown.contains(&format!("at most {max} texels")),
            "{shown}"
        );
    }
    // Powers of two within the limit are stored as they are, with or without resampling.
    png(&image, 16, 2, |x, y| [x as u8 * 16, y as u8 * 100, 7]);
    for resample in [true, false] {
        let options = LoadOptions {
            max_texture: 16,
            resample,
            ..LoadOptions::default()
        };
        let t = &load_obj_with(&obj, &options).unwrap().textures[0];
        assert_eq!((t.log2_width, t.log2_height), (4, 1));
        let want = peel_runtime::display::Colour::new(5 * 16, 100, 7).to_rgb565();
        assert_eq!(t.texel(5, 1), want);
    }
}

/// 256 materials, each with its own image and a face: one texture more than a file holds.
#[cfg(feature = "textures")]
#[test]
fn more_textures_than_a_file_holds_are_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let (mut obj, mut mtl) = (
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n".to_string(),
        String::new(),
    );
    for k in 0..256 {
        obj += &format!("usemtl m{k}\nf 1/1 2/1 3/1\n");
        mtl += &format!("newmtl m{k}\nmap_Kd t{k}.png\n");
        png(&dir.path().join(format!("t{k}.png")), 1, 1, |_, _| {
            [k as u8, 0, 0]
        });
    }
    fs::write(dir.path().join("m.obj"), &obj).unwrap();
    fs::write(dir.path().join("m.mtl"), &mtl).unwrap();
    let e = load_obj(&dir.path().join("m.obj")).unwrap_err();
    assert!(
        matches!(
            e,
            CompileError::TooManyTextures {
                count: 256,
                max: 255,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(
        e.to_string()
            .contains("m.obj: the faces use 256 textures: a file holds at most 255"),
        "{e}"
    );
    // 255 of them fit.
    let obj = obj.replace("usemtl m255\nf 1/1 2/1 3/1\n", "");
    fs::write(dir.path().join("m.obj"), &obj).unwrap();
    assert_eq!(
        load_obj(&dir.path().join("m.obj")).unwrap().textures.len(),
        255
    );
}

#[cfg(feature = "textures")]
#[test]
fn a_jpeg_is_decoded_too() {
    let dir = write_files(&[
        ("m.obj", QUAD),
        ("m.mtl", "newmtl tex\nmap_Kd t.jpg\nnewmtl plain\n"),
    ]);
    let grey = image::RgbImage::from_pixel(8, 8, image::Rgb([128, 128, 128]));
    grey.save(dir.path().join("t.jpg")).unwrap();
    let t = &load_obj(&dir.path().join("m.obj")).unwrap().textures[0];
    assert_eq!((t.width(), t.height()), (8, 8));
    // JPEG is lossy: about mid grey.
    let g = (t.texel(3, 3) >> 5) & 63;
    assert!((30..=34).contains(&g), "{g}");
}

#[test]
fn a_texture_size_limit_must_be_a_power_of_two_up_to_1024() {
    let dir = write_files(&[("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")]);
    let obj = dir.path().join("m.obj");
    for bad in [0, 3, 100, 2048] {
        let options = LoadOptions {
            max_texture: bad,
            ..LoadOptions::default()
        };
        let e = load_obj_with(&obj, &options).unwrap_err();
        assert!(
            matches!(e, CompileError::MaxTexture { max, largest: 1024 } if max == bad),
            "{e:?}"
        );
    }
    for good in [1, 64, 1024] {
        let options = LoadOptions {
            max_texture: good,
            ..LoadOptions::default()
        };
        assert!(load_obj_with(&obj, &options).is_ok());
    }
}

#[cfg(not(feature = "textures"))]
#[test]
fn without_the_feature_a_used_texture_is_an_error_saying_so() {
    let dir = write_files(&[
        ("m.obj", QUAD),
        ("m.mtl", "newmtl tex\nmap_Kd t.png\nnewmtl plain\n"),
    ]);
    let e = load_obj(&dir.path().join("m.obj")).unwrap_err();
    assert!(
        matches!(e, CompileError::TexturesOff { line: 2, .. }),
        "{e:?}"
    );
    assert!(
        e.to_string()
            .contains("built without the `textures` feature"),
        "{e}"
    );
}
