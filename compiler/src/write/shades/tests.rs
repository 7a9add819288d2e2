//! Smooth files: flat or smooth polygons, vertex copies, and what the reader sees of them.

use glam::DVec3;
use peel_runtime::display::Colour;
use peel_runtime::read::layout::header_flags;
use peel_runtime::read::Scene;

use super::*;
use crate::compile::{compile_mesh, polygon_shades, CompileOptions};
use crate::hash::FastMap;
use crate::load::{Mesh, SourceTriangle};
use crate::shade::smooth::Smooth;
use crate::shade::{Shading, Surface};
use crate::tools::scenes;
use crate::tree::BuildOptions;
use crate::write::{peel_file_with, tests::assert_reads_back, WriteInput};

/// Compile options with shadows from a sun.
fn options(shading: Shading, surface: Surface) -> CompileOptions {
    CompileOptions {
        build: BuildOptions {
            shadows: shading
                .light()
                .filter(|_| matches!(shading, Shading::Lambert(_))),
            ..BuildOptions::default()
        },
        shading,
        surface,
        ..CompileOptions::default()
    }
}

/// A curved scene: a sphere and a torus of two colours over a floor, so that polygons are cut
/// by each other and by shadows, and meet at creases.
fn curved() -> Mesh {
    let mut mesh = scenes::sphere(10, 16);
    let mut torus = scenes::torus(16, 8);
    for t in &mut torus.triangles {
        t.vertices = t.vertices.map(|v| v * 0.6 + DVec3::new(1.2, 0.3, 0.0));
        t.colour = [40, 180, 90];
    }
    mesh.triangles.extend(torus.triangles);
    let floor =
        [(-3.0, -3.0), (-3.0, 3.0), (3.0, 3.0), (3.0, -3.0)].map(|(x, z)| DVec3::new(x, -1.2, z));
    for t in [[0, 1, 2], [0, 2, 3]] {
        mesh.triangles.push(SourceTriangle {
            opacity: u8::MAX,
            vertices: t.map(|i| floor[i]),
            colour: [230, 120, 60],
            ..mesh.triangles[0]
        });
    }
    mesh
}

/// A box has sharp edges only: every polygon is flat, the file has no shades. Its colours are
/// the vertices' (`apply(kd, quantise(k))`), which faceted shading's `kd * k` rounded once
/// equals under the default light (the same bytes), and is within 1 of under any light.
#[test]
fn a_box_compiled_smooth_is_its_faceted_file() {
    let mesh = scenes::box_grid(2);
    for shading in [
        Shading::default(),
        Shading::Lambert(DVec3::new(-0.3, 0.9, 0.2)),
    ] {
        let compile = |surface| {
            compile_mesh(&mesh, &options(shading, surface), &|_| {})
                .unwrap()
                .1
        };
        let faceted = compile(Surface::Faceted);
        let smooth = compile(Surface::smooth(60.0).unwrap());
        let (faceted, smooth) = (
            Scene::parse(&faceted).unwrap(),
            Scene::parse(&smooth).unwrap(),
        );
        assert_eq!(smooth.header().flags & header_flags::SHADES, 0);
        if shading == Shading::default() {
            assert!(smooth.bytes() == faceted.bytes(), "the same bytes");
            continue;
        }
        assert_eq!(smooth.header(), faceted.header(), "{shading:?}");
        for p in 0..smooth.header().polygon_count {
            assert_eq!(smooth.polygon(p).flags, faceted.polygon(p).flags);
            for interior in [true, false] {
                let (a, b) = (
                    smooth.colour_seen(p, interior),
                    faceted.colour_seen(p, interior),
                );
                let near = |x: u8, y: u8| x.abs_diff(y) <= 1;
                assert!(near(a.r, b.r) && near(a.g, b.g) && near(a.b, b.b));
            }
        }
    }
}

/// The file of `mesh` compiled smooth by `shading`, checked polygon by polygon against the
/// compiler's own shades; returns (file vertices, smooth polygons, polygons).
fn check_smooth(mesh: &Mesh, shading: Shading) -> (usize, usize, usize) {
    let surface = Surface::smooth(60.0).unwrap();
    let (tree, bytes) = compile_mesh(mesh, &options(shading, surface), &|_| {}).unwrap();
    let smooth = Smooth {
        shading,
        crease: crate::shade::normals::Crease::DEFAULT,
    };
    let shades = smooth.shade(mesh);
    let scene = Scene::parse(&bytes).unwrap();
    let header = scene.header();
    assert_ne!(header.flags & header_flags::SHADES, 0);
    // File indices are the shaded tree's vertices: a polygon is known by its vertices.
    let shaded = shade_vertices(&tree, &polygon_shades(&tree, mesh, &smooth), &[]).unwrap();
    let key = |vertices: &[u32]| {
        let mut v = vertices.to_vec();
        v.sort_unstable();
        v
    };
    let by_key: FastMap<Vec<u32>, usize> = shaded
        .tree
        .polygons
        .iter()
        .enumerate()
        .map(|(t, p)| (key(&p.vertices), t))
        .collect();
    assert_eq!(by_key.len(), tree.polygons.len());
    let mut smooth_polygons = 0;
    for p in 0..header.polygon_count {
        let polygon = scene.polygon(p);
        let list: Vec<u32> = (0..u32::from(polygon.vertex_count))
            .map(|k| scene.polygon_vertex_index(&polygon, k).unwrap())
            .collect();
        // A polygon whose corners round together is written with each once: it holds this
        // list, and its corners are read at this list's places.
        let t = by_key.get(&key(&list)).copied().unwrap_or_else(|| {
            let places = |vertices: &[u32]| {
                let mut at: Vec<[u32; 3]> = vertices
                    .iter()
                    .map(|&v| scene.vertex(v).to_array().map(f32::to_bits))
                    .collect();
                at.sort_unstable();
                at.dedup();
                at
            };
            let found: Vec<usize> = (0..shaded.tree.polygons.len())
                .filter(|&t| {
                    let all = &shaded.tree.polygons[t].vertices;
                    list.iter().all(|v| all.contains(v)) && places(all) == places(&list)
                })
                .collect();
            assert_eq!(found.len(), 1, "polygon {p}: {list:?}");
            found[0]
        });
        let (original, copy) = (&tree.polygons[t], &shaded.tree.polygons[t]);
        let want: Vec<[u8; 2]> = shades
            .polygon(&tree, original)
            .into_iter()
            .map(|s| s.quantised())
            .collect();
        let kd = mesh.triangles[original.source as usize].colour;
        let colour = |c: [u8; 3]| Colour::new(c[0], c[1], c[2]);
        for &v in &list {
            let j = copy.vertices.iter().position(|&w| w == v).unwrap();
            for (side, interior) in [(0, true), (1, false)] {
                match Scene::shade_side(polygon.flags, interior) {
                    Some(at) => {
                        assert_eq!(scene.vertex_shade(v, at), want[j][side], "polygon {p}");
                        assert_eq!(scene.colour_seen(p, interior), colour(kd));
                    }
                    None => assert_eq!(
                        scene.colour_seen(p, interior),
                        colour(apply(kd, want[j][side])),
                        "flat polygon {p}: one colour, every vertex's"
                    ),
                }
            }
        }
        if Scene::shade_side(polygon.flags, true).is_some() {
            smooth_polygons += 1;
            let colours = |side: usize| {
                let mut c: Vec<[u8; 3]> = want.iter().map(|s| apply(kd, s[side])).collect();
                c.dedup();
                c.len()
            };
            assert!(
                colours(0) > 1 || colours(1) > 1,
                "polygon {p} could be flat"
            );
        }
    }
    (
        header.vertex_count as usize,
        smooth_polygons,
        header.polygon_count as usize,
    )
}

#[test]
fn a_smooth_file_reads_back_each_vertex_shade_on_the_side_seen() {
    let mesh = curved();
    for shading in [
        Shading::default(),
        Shading::Point(DVec3::new(2.0, 4.0, 1.0)),
    ] {
        let (_, smooth, polygons) = check_smooth(&mesh, shading);
        // The floor, the parts in shadow and the sides facing away are flat.
        assert!(
            smooth > polygons / 8 && smooth < polygons,
            "{shading:?}: {smooth} of {polygons}"
        );
    }
}

/// The vertices a smooth file needs, counted by brute force: per tree vertex, one per
/// distinct pair of shades the smooth polygons give it, or one if only flat polygons use it.
#[test]
fn vertices_are_copied_only_where_shades_differ() {
    let mesh = curved();
    let shading = Shading::default();
    let surface = Surface::smooth(60.0).unwrap();
    let (tree, _) = compile_mesh(&mesh, &options(shading, surface), &|_| {}).unwrap();
    let smooth = Smooth {
        shading,
        crease: crate::shade::normals::Crease::DEFAULT,
    };
    let polygons = polygon_shades(&tree, &mesh, &smooth);
    let shaded = shade_vertices(&tree, &polygons, &[]).unwrap();
    let mut pairs: Vec<Vec<[u8; 2]>> = vec![Vec::new(); tree.vertices.len()];
    let mut used = vec![false; tree.vertices.len()];
    for ((p, s), &flag) in tree.polygons.iter().zip(&polygons).zip(&shaded.flags) {
        for (&v, &pair) in p.vertices.iter().zip(&s.vertices) {
            used[v as usize] = true;
            if flag & polygon_flags::SMOOTH != 0 && !pairs[v as usize].contains(&pair) {
                pairs[v as usize].push(pair);
            }
        }
    }
    let want: usize = (0..tree.vertices.len())
        .filter(|&v| used[v])
        .map(|v| pairs[v].len().max(1))
        .sum();
    assert_eq!(shaded.tree.vertices.len(), want);
    assert!(
        want > tree.vertices.len(),
        "the crease at the floor copies some"
    );
    // Each copy has the position of its vertex, a smooth polygon's copy its own shades.
    for ((p, copy), (s, &flag)) in tree
        .polygons
        .iter()
        .zip(&shaded.tree.polygons)
        .zip(polygons.iter().zip(&shaded.flags))
    {
        for ((&v, &c), &pair) in p.vertices.iter().zip(&copy.vertices).zip(&s.vertices) {
            assert_eq!(shaded.tree.vertices[c as usize], tree.vertices[v as usize]);
            if flag != 0 {
                assert_eq!(shaded.shades[c as usize], pair);
            }
        }
    }
    // The file round-trips, shades included.
    let file = peel_file_with(
        &shaded.tree,
        &WriteInput {
            colours: &shaded.colours,
            exterior: &shaded.exterior,
            polygon_flags: &shaded.flags,
            shades: &shaded.shades,
            ..WriteInput::default()
        },
    )
    .unwrap();
    assert_eq!(file.shades.len(), file.vertices.len());
    assert_reads_back(&file);
}

#[test]
fn smooth_files_are_the_same_whatever_the_thread_count() {
    let mesh = curved();
    let options = options(Shading::default(), Surface::smooth(45.0).unwrap());
    let compile = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| compile_mesh(&mesh, &options, &|_| {}).unwrap().1)
    };
    let one = compile(1);
    assert!(one == compile(3));
    assert!(Scene::parse(&one).unwrap().header().flags & header_flags::SHADES != 0);
}

#[test]
fn faceted_and_unlit_files_have_no_shades() {
    let mesh = curved();
    for (shading, surface) in [
        (Shading::default(), Surface::Faceted),
        (Shading::Flat, Surface::Faceted),
        // Unlit and smooth: every corner at full intensity, every polygon flat.
        (Shading::Flat, Surface::smooth(60.0).unwrap()),
    ] {
        let bytes = compile_mesh(&mesh, &options(shading, surface), &|_| {})
            .unwrap()
            .1;
        let scene = Scene::parse(&bytes).unwrap();
        assert_eq!(
            scene.header().flags & header_flags::SHADES,
            0,
            "{shading:?}"
        );
        let (file, _): (crate::write::format::PeelFile, usize) =
            bincode::serde::decode_from_slice(&bytes, crate::write::format::config()).unwrap();
        assert!(file.shades.is_empty());
        assert!(file
            .polygons
            .iter()
            .all(|p| p.flags & polygon_flags::SMOOTH == 0));
        assert!(crate::write::to_bytes(&file).unwrap() == bytes);
    }
}

#[test]
fn shades_that_do_not_match_the_polygons_are_refused() {
    let mesh = scenes::box_grid(1);
    let (tree, _) = compile_mesh(&mesh, &CompileOptions::default(), &|_| {}).unwrap();
    let e = shade_vertices(&tree, &[], &[]).unwrap_err();
    assert!(matches!(e, CompileError::Invariant(_)), "{e:?}");
    // A smooth flag without shades is refused by the writer.
    let colours = vec![[1, 2, 3]; tree.polygons.len()];
    let flags = vec![polygon_flags::SMOOTH; tree.polygons.len()];
    let input = WriteInput {
        colours: &colours,
        polygon_flags: &flags,
        ..WriteInput::default()
    };
    assert!(peel_file_with(&tree, &input).is_err());
}

/// `mesh` textured: spherical coordinates around the vertical axis, the seam where `u` wraps
/// from 1 to 0 (a triangle across it takes `u + 1` at the corners before it), and every third
/// triangle left untextured.
fn textured(mesh: Mesh) -> Mesh {
    let mut mesh = scenes::textured(mesh, 2, |t| {
        let turn = std::f64::consts::TAU;
        let mut uv = t.map(|p| glam::DVec2::new(p.z.atan2(p.x) / turn + 0.5, p.y));
        let right = uv.iter().map(|uv| uv.x).fold(0.0, f64::max);
        for uv in &mut uv {
            if right - uv.x > 0.5 {
                uv.x += 1.0;
            }
        }
        uv
    });
    for t in mesh.triangles.iter_mut().step_by(3) {
        t.texture = None;
    }
    mesh
}

/// Each copy has the position of its vertex, a smooth polygon's copy its shades (swapped with
/// the polygon's interior index, when it was), a textured polygon's copy its coordinates; no
/// vertex has two copies of the same shades and coordinates.
fn check_copies(
    tree: &DisplayTree,
    copied: &DisplayTree,
    shades: &[PolygonShades],
    flags: &[u8],
    uvs: &[PolygonUvs],
    vertex_shades: &[[u8; 2]],
    vertex_uvs: &[[i32; 2]],
) {
    let mut seen: FastMap<(u32, [u8; 2], [i32; 2]), u32> = FastMap::default();
    let mut origin = vec![None; copied.vertices.len()];
    for (i, (p, copy)) in tree.polygons.iter().zip(&copied.polygons).enumerate() {
        for (k, (&v, &c)) in p.vertices.iter().zip(&copy.vertices).enumerate() {
            assert_eq!(copied.vertices[c as usize], tree.vertices[v as usize]);
            assert_eq!(*origin[c as usize].get_or_insert(v), v);
            if flags[i] & polygon_flags::SMOOTH != 0 {
                let [f, b] = shades[i].vertices[k];
                // Stored swapped exactly when the interior index no longer says the interior.
                let swapped =
                    (flags[i] & polygon_flags::INTERIOR_BACK != 0) != p.interior_is_back();
                let want = if swapped { [b, f] } else { [f, b] };
                assert_eq!(vertex_shades[c as usize], want);
            }
            if let Some(uv) = &uvs[i] {
                assert_eq!(vertex_uvs[c as usize], uv[k]);
            }
        }
    }
    for (c, v) in origin.iter().enumerate() {
        let v = v.expect("every copy is used");
        let shade = vertex_shades.get(c).copied().unwrap_or_default();
        let uv = vertex_uvs.get(c).copied().unwrap_or_default();
        if let Some(other) = seen.insert((v, shade, uv), c as u32) {
            panic!("copies {other} and {c} of vertex {v} are alike");
        }
    }
}

/// Faceted and textured: a vertex is copied once per distinct coordinates of the textured
/// polygons that use it (the untextured ones take one of those copies), once if only
/// untextured polygons use it.
#[test]
fn textured_vertices_are_copied_once_per_distinct_coordinates() {
    let mesh = textured(curved());
    let options = options(Shading::default(), Surface::Faceted);
    let (tree, _) = compile_mesh(&mesh, &options, &|_| {}).unwrap();
    let uvs = crate::texture::polygon_uvs(&tree, &mesh);
    let copied = uv_vertices(&tree, &uvs).unwrap();
    let mut distinct: Vec<Vec<[i32; 2]>> = vec![Vec::new(); tree.vertices.len()];
    let mut used = vec![false; tree.vertices.len()];
    for (p, uvs) in tree.polygons.iter().zip(&uvs) {
        for (k, &v) in p.vertices.iter().enumerate() {
            used[v as usize] = true;
            if let Some(uv) = uvs.as_ref().map(|uvs| uvs[k]) {
                if !distinct[v as usize].contains(&uv) {
                    distinct[v as usize].push(uv);
                }
            }
        }
    }
    let want: usize = (0..tree.vertices.len())
        .filter(|&v| used[v])
        .map(|v| distinct[v].len().max(1))
        .sum();
    assert_eq!(copied.tree.vertices.len(), want);
    assert!(want > tree.vertices.len(), "the seam copies some");
    assert_eq!(copied.uvs.len(), want);
    assert!(copied.shades.is_empty());
    let flat = vec![0; tree.polygons.len()];
    check_copies(&tree, &copied.tree, &[], &flat, &uvs, &[], &copied.uvs);
    // Without textured polygons, nothing is copied.
    let untextured = uv_vertices(&tree, &[]).unwrap();
    assert!(matches!(untextured.tree, Cow::Borrowed(_)) && untextured.uvs.is_empty());
}

/// Smooth and textured: every copy as its polygons need it, and none twice; the file reads
/// back, shades and coordinates included.
#[test]
fn smooth_textured_vertices_carry_their_shades_and_coordinates() {
    let mesh = textured(curved());
    let shading = Shading::default();
    let (tree, _) = compile_mesh(
        &mesh,
        &options(shading, Surface::smooth(60.0).unwrap()),
        &|_| {},
    )
    .unwrap();
    let smooth = Smooth {
        shading,
        crease: crate::shade::normals::Crease::DEFAULT,
    };
    let polygons = polygon_shades(&tree, &mesh, &smooth);
    let uvs = crate::texture::polygon_uvs(&tree, &mesh);
    let shaded = shade_vertices(&tree, &polygons, &uvs).unwrap();
    assert!(shaded.flags.iter().any(|&f| f & polygon_flags::SMOOTH != 0));
    assert_eq!(shaded.shades.len(), shaded.tree.vertices.len());
    assert_eq!(shaded.uvs.len(), shaded.tree.vertices.len());
    check_copies(
        &tree,
        &shaded.tree,
        &polygons,
        &shaded.flags,
        &uvs,
        &shaded.shades,
        &shaded.uvs,
    );
    // The seam copies more than the shades alone.
    let plain = shade_vertices(&tree, &polygons, &[]).unwrap();
    assert!(shaded.tree.vertices.len() > plain.tree.vertices.len());
    let textures: Vec<u8> = (tree.polygons.iter())
        .map(|p| {
            mesh.triangles[p.source as usize]
                .texture
                .map_or(peel_runtime::read::layout::NO_TEXTURE, |t| t.texture as u8)
        })
        .collect();
    let file = peel_file_with(
        &shaded.tree,
        &WriteInput {
            colours: &shaded.colours,
            exterior: &shaded.exterior,
            polygon_flags: &shaded.flags,
            shades: &shaded.shades,
            textures: &mesh.textures,
            polygon_textures: &textures,
            uvs: &shaded.uvs,
            ..WriteInput::default()
        },
    )
    .unwrap();
    assert_eq!(
        file.header.version,
        peel_runtime::read::layout::TEXTURED_VERSION
    );
    assert_eq!(file.uvs.len(), file.vertices.len());
    assert_reads_back(&file);
}

#[test]
fn coordinates_that_do_not_match_the_polygons_are_refused() {
    let mesh = scenes::box_grid(1);
    let (tree, _) = compile_mesh(&mesh, &CompileOptions::default(), &|_| {}).unwrap();
    let e = uv_vertices(&tree, &[None]).unwrap_err();
    assert!(matches!(e, CompileError::Invariant(_)), "{e:?}");
    let mut uvs: Vec<PolygonUvs> = vec![None; tree.polygons.len()];
    uvs[0] = Some(vec![[0, 0]]);
    let e = uv_vertices(&tree, &uvs).unwrap_err();
    assert!(matches!(e, CompileError::Invariant(_)), "{e:?}");
}
