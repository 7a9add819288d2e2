//! Textured scenes end to end, as files: OBJ `vt` and MTL `map_Kd` -> compiler -> a format 6
//! file the runtime reads -> pixels. The texels show the right way up, a polygon cut by the compiler
//! keeps the coordinates of its positions, and textures are stored as the format says (a
//! palette or RGB565, their clamp flags, only those drawn).

use std::path::Path;

use glam::{DVec2, DVec3};
use peel_compiler::compile::{compile_mesh, compile_obj, CompileOptions};
use peel_compiler::load::{load_obj, SourceTriangle};
use peel_compiler::shade::{Shading, Surface};
use peel_compiler::tools::raster::{render_bytes_with, Settings};
use peel_compiler::tools::scenes;
use peel_compiler::tools::shot::Shot;
use peel_runtime::read::layout::{header_flags, texture_flags, TEXTURED_VERSION};
use peel_runtime::read::Scene;

/// Writes `files` (name, text) into `dir`.
fn write(dir: &Path, files: &[(&str, &str)]) {
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
}

/// Writes the PNG `name` of `width x height` pixels, pixel `(x, y)` `colour(x, y)`.
fn png(dir: &Path, name: &str, width: u32, height: u32, colour: impl Fn(u32, u32) -> [u8; 3]) {
    image::RgbImage::from_fn(width, height, |x, y| image::Rgb(colour(x, y)))
        .save(dir.join(name))
        .unwrap();
}

/// Unlit, faceted: a white material shows its texels as they are.
fn unlit() -> CompileOptions {
    CompileOptions {
        shading: Shading::Flat,
        surface: Surface::Faceted,
        ..CompileOptions::default()
    }
}

/// A unit square facing +z, its corners' `vt` its `(x, y)`, textured with a 2 x 2 image: red
/// and green on top, blue and white below. Seen from +z (x to the right, y up), each quarter of
/// the square shows its texel: `vt 0 1` is the image's top left.
#[test]
fn a_textured_square_shows_its_texels_the_right_way_up() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        &[
            (
                "square.obj",
                "mtllib square.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                 vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl picture\nf 1/1 2/2 3/3 4/4\n",
            ),
            ("square.mtl", "newmtl picture\nKd 1 1 1\nmap_Kd four.png\n"),
        ],
    );
    let texels = [[[255, 0, 0], [0, 255, 0]], [[0, 0, 255], [255, 255, 255]]];
    png(dir.path(), "four.png", 2, 2, |x, y| {
        texels[y as usize][x as usize]
    });
    let compiled = compile_obj(&dir.path().join("square.obj"), &unlit(), &|_| {}).unwrap();
    let scene = Scene::parse(&compiled.bytes).unwrap();
    let header = scene.header();
    assert_eq!(header.version, TEXTURED_VERSION);
    assert_ne!(header.flags & header_flags::TEXTURES, 0);
    assert_eq!(scene.texture_count(), 1);
    assert!((0..header.polygon_count).all(|p| scene.polygon_texture(p).is_some()));

    let shot = Shot::new(DVec3::new(0.5, 0.5, 1.2), DVec3::new(0.5, 0.5, 0.0), 64, 64);
    let frame = render_bytes_with(&compiled.bytes, &shot, &Settings::default()).unwrap();
    let pixel = |x: u32, y: u32| frame.pixels[(y * frame.width + x) as usize];
    // The square spans about pixels 5 to 58; each quarter's middle.
    for (x, y, want) in [
        (18, 18, 0xFF0000),
        (45, 18, 0x00FF00),
        (18, 45, 0x0000FF),
        (45, 45, 0xFFFFFF),
    ] {
        assert_eq!(pixel(x, y), want, "pixel {x}, {y}");
    }
}

/// Three triangles that pierce one another in a cycle, textured by a linear map of their
/// positions: the compiler must cut them. Every vertex of every polygon the file holds has the
/// coordinates of its position (within what rounding the position to the file's 16-bit
/// steps changes), corners and cuts alike.
#[test]
fn cut_polygons_keep_the_coordinates_of_their_positions() {
    let map = |p: DVec3| DVec2::new(p.x + 0.3 * p.z, p.y - 0.2 * p.z);
    let mesh = scenes::textured(scenes::mesh(scenes::piercing_triangles()), 3, |t| {
        t.map(map)
    });
    let options = CompileOptions {
        ids: true,
        ..unlit()
    };
    let (tree, bytes) = compile_mesh(&mesh, &options, &|_| {}).unwrap();
    assert!(tree.stats.cuts > 0, "the cycle needs a cut");
    let scene = Scene::parse(&bytes).unwrap();
    let header = scene.header();
    let centre = DVec3::from_array(header.centre);
    // Half a step on each axis moves the coordinates by at most |grad| times half the step's
    // diagonal, here under 2 units of 2^-16.
    let step = (header.bounds_max - header.bounds_min).as_dvec3() / 65535.0;
    let slack = 65536.0 * 1.1 * (step.length() / 2.0) + 1.0;
    assert!(slack < 4.0, "{slack}");
    let mut checked = 0;
    for i in 0..header.polygon_count {
        let polygon = scene.polygon(i);
        assert!(scene.polygon_texture(i).is_some());
        for k in 0..u32::from(polygon.vertex_count) {
            let v = scene.polygon_vertex_index(&polygon, k).unwrap();
            let at = centre + scene.vertex(v).as_dvec3();
            let want = map(at);
            let want = [want.x * 65536.0, (1.0 - want.y) * 65536.0];
            let got = scene.vertex_uv(v);
            for axis in 0..2 {
                assert!(
                    (f64::from(got[axis]) - want[axis]).abs() <= slack,
                    "polygon {i} (triangle {:?}) vertex {k}: {got:?} against {want:?}",
                    scene.id(i)
                );
            }
            checked += 1;
        }
    }
    assert!(
        checked > 9,
        "more vertices than the three triangles' corners"
    );
}

/// Three materials: a texture of three colours clamped on both axes (a palette), one of 256
/// colours in 256 texels (RGB565: a palette would be larger) that repeats, and one whose only
/// face has no area (read, but drawn by no polygon: not stored).
#[test]
fn textures_are_stored_as_a_palette_or_rgb565_with_their_clamp_flags() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        &[
            (
                "m.obj",
                "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 2 0 0\n\
                 vt 0 0\nvt 1 0\nvt 0 1\n\
                 usemtl unused\nf 1/1 2/2 5/3\n\
                 usemtl few\nf 1/1 2/2 3/3\nusemtl many\nf 1/1 4/2 3/3\n",
            ),
            (
                "m.mtl",
                "newmtl few\nmap_Kd -clamp on few.png\nnewmtl many\nmap_Kd many.png\n\
                 newmtl unused\nmap_Kd unused.png\n",
            ),
        ],
    );
    png(dir.path(), "few.png", 8, 4, |x, _| {
        [(x % 3 * 100) as u8, 30, 0]
    });
    png(dir.path(), "many.png", 16, 16, |x, y| {
        [x as u8 * 16, y as u8 * 16, 128]
    });
    png(dir.path(), "unused.png", 4, 4, |_, _| [1, 2, 3]);
    let path = dir.path().join("m.obj");
    assert_eq!(load_obj(&path).unwrap().textures.len(), 3);
    let compiled = compile_obj(&path, &unlit(), &|_| {}).unwrap();
    assert_eq!(compiled.stats.degenerate_dropped, 1);
    let scene = Scene::parse(&compiled.bytes).unwrap();
    assert_eq!(scene.texture_count(), 2);
    let few = scene.texture(0).unwrap();
    assert_eq!((few.log2_width, few.log2_height), (3, 2));
    let clamp = texture_flags::CLAMP_S | texture_flags::CLAMP_T;
    assert_eq!(few.flags, clamp | texture_flags::PALETTE);
    // Three colours, then one byte a texel.
    assert_eq!(few.colours.len(), 2 * 3);
    assert_eq!(few.texels.len(), 32);
    let many = scene.texture(1).unwrap();
    assert_eq!(
        (many.flags, many.colours.len(), many.texels.len()),
        (0, 0, 512)
    );
    let rgb565 = |r, g, b| peel_runtime::display::Colour::new(r, g, b).to_rgb565();
    assert_eq!(many.texel(5, 9), rgb565(80, 144, 128));
    assert_eq!(few.texel(4, 3), rgb565(100, 30, 0));
    // Each face's polygon has its material's texture.
    let textures: Vec<u8> = (0..scene.header().polygon_count)
        .map(|p| scene.polygon_texture(p).unwrap().log2_width)
        .collect();
    assert_eq!(textures.len(), 2);
    assert!(
        textures.contains(&3) && textures.contains(&4),
        "{textures:?}"
    );
}

/// A textured triangle of no area is dropped: no polygon is textured, and the file is of
/// version 4, without the texture arrays.
#[test]
fn a_file_whose_textured_faces_are_all_dropped_is_version_4() {
    let mut mesh = scenes::box_grid(1);
    let flat = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
    mesh.triangles.push(SourceTriangle {
        opacity: u8::MAX,
        vertices: flat,
        ..mesh.triangles[0]
    });
    let mut mesh = scenes::textured(mesh, 1, |_| [DVec2::ZERO, DVec2::X, DVec2::Y]);
    let last = mesh.triangles.len() - 1;
    for t in &mut mesh.triangles[..last] {
        t.texture = None;
    }
    let (_, bytes) = compile_mesh(&mesh, &CompileOptions::default(), &|_| {}).unwrap();
    let scene = Scene::parse(&bytes).unwrap();
    assert_eq!(scene.header().version, 4);
    assert_eq!(scene.header().flags & header_flags::TEXTURES, 0);
}
