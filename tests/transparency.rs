//! Transparent surfaces against the exact ray cast that composites every surface along each
//! pixel's ray in depth order (`tools::reference::composite`): the crossing panes, the glass
//! box around an object (and the teapot, when the shared models are there), the
//! interpenetrating boxes, each from views through two or three surfaces at once. Compiled
//! from their OBJ and MTL text, unlit, drawn front to back (composite memory) and back to
//! front (blended over the framebuffer): on robust pixels every channel within 2 of the
//! reference. The sorted z-buffer's picture of the same views is wrong on some of them.

use std::path::Path;

use glam::DVec3;
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::{load_obj, Mesh};
use peel_compiler::shade::{Shading, Surface};
use peel_compiler::tools::bench_frames::sorted_picture;
use peel_compiler::tools::raster::{render_bytes_with, Settings};
use peel_compiler::tools::reference::composite;
use peel_compiler::tools::scenes::{transparent_scenes, TransparentScene};
use peel_e2e::polygons;
use peel_runtime::read::Scene;
use peel_runtime::traverse::Order;

const BACKGROUND: [u8; 3] = [30, 40, 70];

/// The scene written as OBJ and MTL into a folder of its own, and loaded.
fn load(scene: &TransparentScene) -> Mesh {
    let dir = std::env::temp_dir().join(format!(
        "peel-transparency-{}-{}",
        std::process::id(),
        scene.name
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let mtl = format!("{}.mtl", scene.name);
    std::fs::write(dir.join(&mtl), scene.mtl()).unwrap();
    let obj = dir.join(format!("{}.obj", scene.name));
    std::fs::write(&obj, scene.obj(&mtl)).unwrap();
    let mesh = load_obj(&obj).expect("load");
    std::fs::remove_dir_all(&dir).ok();
    mesh
}

fn rgb(pixels: &[u32]) -> Vec<[u8; 3]> {
    pixels
        .iter()
        .map(|&p| [(p >> 16) as u8, (p >> 8) as u8, p as u8])
        .collect()
}

#[test]
fn transparent_scenes_composite_within_two_of_the_reference_in_both_orders() {
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models");
    let models = models.is_dir().then_some(models.as_path());
    if models.is_none() {
        println!("notice: the shared models are absent: the teapot in its glass box is skipped");
    }
    let scenes = transparent_scenes(models, &mut |m| println!("{m}")).expect("scenes");
    let options = CompileOptions {
        shading: Shading::Flat,
        surface: Surface::Faceted,
        ..CompileOptions::default()
    };
    let mut sorted_wrong = 0;
    for scene in &scenes {
        let mesh = load(scene);
        let opacities: Vec<u8> = mesh.triangles.iter().map(|t| t.opacity).collect();
        assert_eq!(opacities, scene.opacities(), "{}: the MTL's d", scene.name);
        let bytes = compile_mesh(&mesh, &options, &|_| {}).expect("compile").1;
        let header = Scene::parse(&bytes).expect("parse").header();
        let transparent = opacities.iter().any(|&a| a < 255);
        assert_eq!(header.version == 7, transparent, "{}", scene.name);
        let polys = polygons(&bytes);
        let tris: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
        let kd: Vec<[f64; 3]> = (mesh.triangles.iter())
            .map(|t| t.colour.map(f64::from))
            .collect();
        for shot in &scene.shots {
            let near = shot.near_over(&header);
            let reference = composite(
                &tris,
                &polys,
                shot,
                near,
                |id, _| kd[id],
                &opacities,
                BACKGROUND,
            );
            let robust = reference.robust.iter().filter(|&&r| r).count();
            assert!(
                robust * 2 > reference.robust.len(),
                "{}: robust pixels",
                scene.name
            );
            for order in [Order::FrontToBack, Order::BackToFront] {
                let settings = Settings {
                    order,
                    background: BACKGROUND,
                    ..Settings::default()
                };
                let frame = render_bytes_with(&bytes, shot, &settings).expect("render");
                assert_eq!(frame.stats.fallback_rows, 0);
                let wrong = reference.wrong_pixels(&rgb(&frame.pixels), 2.0);
                assert_eq!(wrong, 0, "{} {order:?} from {}", scene.name, shot.eye);
            }
            let colour = |id: usize, _| kd[id];
            let sorted = sorted_picture(&tris, colour, &opacities, BACKGROUND, shot, near)
                .expect("sorted z-buffer");
            sorted_wrong += reference.wrong_pixels(&sorted, 2.0);
        }
    }
    assert!(
        sorted_wrong > 0,
        "the sorted z-buffer gets some crossing right by luck only"
    );
}
