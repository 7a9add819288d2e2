//! Textured surfaces against the exact ray cast (`tools::reference::texels`): on the project's
//! textured box from views where its faces are oblique, on a generated mesh under a
//! checkerboard, and on a mesh with its own coordinates under a texture whose neighbouring
//! texels all differ. On robust pixels (the centre and four points 1/16 pixel away in one
//! texel of one triangle), at least 99% take the cast's texel and none a texel farther than
//! next to it; every path of a frame draws the same pixels.

use glam::DVec3;
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::{load_obj, Mesh};
use peel_compiler::shade::{Shading, Surface};
use peel_compiler::tools::raster::{render_bytes_with, Settings};
use peel_compiler::tools::reference::texels;
use peel_compiler::tools::scenes;
use peel_compiler::tools::shot::Shot;
use peel_compiler::tools::texture_check::{check, TextureCheck};
use peel_runtime::traverse::Order;

/// `mesh` compiled unlit (the texels as they are).
fn compile(mesh: &Mesh) -> Vec<u8> {
    let options = CompileOptions {
        shading: Shading::Flat,
        surface: Surface::Faceted,
        ..CompileOptions::default()
    };
    compile_mesh(mesh, &options, &|_| {}).expect("compile").1
}

/// A 320 x 240 shot from `eye` at `target`.
fn shot(eye: DVec3, target: DVec3) -> Shot {
    Shot {
        near: Some(0.01),
        ..Shot::new(eye, target, 320, 240)
    }
}

/// The check of `bytes` (compiled from `mesh`) drawn as `shot` sees it, front to back, after
/// asserting that back to front draws the same picture and that the frame in integer
/// vertices is as accurate.
fn checked(mesh: &Mesh, bytes: &[u8], shot: &Shot) -> TextureCheck {
    let front = render_bytes_with(bytes, shot, &Settings::default()).expect("render");
    let back = render_bytes_with(
        bytes,
        shot,
        &Settings {
            order: Order::BackToFront,
            ..Settings::default()
        },
    )
    .expect("render");
    assert_eq!(front.pixels, back.pixels, "both orders, one picture");
    let reference = texels(mesh, shot, shot.near.unwrap_or(0.01));
    // In integer vertices, as a core without an FPU draws: edges may move by a subpixel
    // unit, never a texel.
    let integer = render_bytes_with(
        bytes,
        shot,
        &Settings {
            integer_vertices: true,
            ..Settings::default()
        },
    )
    .expect("render");
    let c = check(&reference, mesh, &integer.pixels);
    assert_eq!(
        c.wrong,
        0,
        "integer vertices from {}: {}",
        shot.eye,
        c.summary()
    );
    assert!(
        c.exact * 100 >= c.pixels * 99,
        "integer vertices: {}",
        c.summary()
    );
    check(&reference, mesh, &front.pixels)
}

/// Sums the checks of `shots`, asserting each: no robust pixel beyond a neighbouring texel,
/// and at least 99% of them exact over all.
fn assert_accurate(mesh: &Mesh, shots: &[Shot], what: &str) -> TextureCheck {
    let bytes = compile(mesh);
    let mut all = TextureCheck::default();
    for s in shots {
        let c = checked(mesh, &bytes, s);
        assert_eq!(c.wrong, 0, "{what} from {}: {}", s.eye, c.summary());
        assert!(
            c.pixels > 2000,
            "{what} from {}: {} robust pixels",
            s.eye,
            c.pixels
        );
        println!("{what} from {}: {}", s.eye, c.summary());
        all.pixels += c.pixels;
        all.exact += c.exact;
        all.adjacent += c.adjacent;
    }
    assert!(
        all.exact * 100 >= all.pixels * 99,
        "{what}: {} of {} robust pixels exact",
        all.exact,
        all.pixels
    );
    all
}

/// The largest angle, in degrees, between the view axis and a face of the box [-1, 1]^3 the
/// eye sees.
fn most_oblique_face(eye: DVec3, target: DVec3) -> f64 {
    let axis = (target - eye).normalize();
    let normals = [DVec3::X, DVec3::Y, DVec3::Z];
    normals
        .iter()
        .flat_map(|&n| [n, -n])
        .filter(|&n| (eye - n).dot(n) > 0.0)
        .map(|n| 180.0 - n.dot(axis).acos().to_degrees())
        .fold(0.0, f64::max)
}

#[test]
fn the_textured_box_shows_its_texels_from_oblique_views() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/textured-box/box.obj");
    let mesh = load_obj(path.as_ref()).expect("the fixture loads");
    assert_eq!(mesh.textures.len(), 6, "a picture per face");
    let target = DVec3::ZERO;
    let eyes = [
        DVec3::new(4.5, 1.5, 0.4),
        DVec3::new(-0.5, 4.2, 1.2),
        DVec3::new(1.1, -0.6, -4.4),
        DVec3::new(3.0, 2.0, 2.5),
    ];
    for &eye in &eyes[..3] {
        assert!(
            most_oblique_face(eye, target) >= 70.0,
            "{eye}: a face at {:.0} degrees",
            most_oblique_face(eye, target)
        );
    }
    let shots: Vec<Shot> = eyes.iter().map(|&e| shot(e, target)).collect();
    assert_accurate(&mesh, &shots, "box");
}

#[test]
fn a_generated_sphere_under_a_checkerboard_shows_its_texels() {
    let mesh = scenes::textured_sphere(12, 24);
    let shots: Vec<Shot> = [
        DVec3::new(0.0, 0.3, 3.0),
        DVec3::new(2.2, 1.6, -1.4),
        DVec3::new(-0.4, -2.6, 1.0),
    ]
    .iter()
    .map(|&e| shot(e, DVec3::ZERO))
    .collect();
    assert_accurate(&mesh, &shots, "sphere");
}

#[test]
fn a_mesh_with_its_own_coordinates_shows_each_texel() {
    let mesh = scenes::numbered_box();
    let shots: Vec<Shot> = [
        DVec3::new(3.0, 2.1, 2.6),
        DVec3::new(-3.4, 0.4, -1.2),
        DVec3::new(0.6, -3.8, 0.9),
        DVec3::new(4.2, 0.25, 0.3),
    ]
    .iter()
    .map(|&e| shot(e, DVec3::ZERO))
    .collect();
    assert_accurate(&mesh, &shots, "numbered box");
}
