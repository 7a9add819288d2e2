//! Texture coordinates of the output: the fixed point, and every vertex of every polygon at
//! its position on its source triangle, cut or not.

use glam::{DVec2, DVec3};

use super::*;
use crate::compile::{compile_mesh, CompileOptions};
use crate::load::SourceTriangle;
use crate::shade::{Shading, Surface};
use crate::shadow::Light;
use crate::tools::scenes;
use crate::tree::BuildOptions;

#[test]
fn coordinates_are_sixteen_fraction_bits_with_t_down_from_the_top() {
    assert_eq!(fixed(DVec2::new(0.0, 1.0)), [0, 0]);
    assert_eq!(fixed(DVec2::new(1.0, 0.0)), [65536, 65536]);
    assert_eq!(fixed(DVec2::new(0.5, 0.25)), [32768, 49152]);
    assert_eq!(fixed(DVec2::new(-2.5, 3.0)), [-163840, -131072]);
    // Rounded to nearest (half away from zero), saturating.
    assert_eq!(fixed(DVec2::new(1.0 / 131072.0, 1.0)), [1, 0]);
    assert_eq!(fixed(DVec2::new(0.4 / 65536.0, 1.0)), [0, 0]);
    assert_eq!(fixed(DVec2::new(1e9, -1e9)), [i32::MAX, i32::MAX]);
    assert_eq!(fixed(DVec2::new(-1e9, 1e9)), [i32::MIN, i32::MIN]);
}

#[test]
fn inside_the_coordinates_are_the_corners_interpolated() {
    let corners = [
        DVec3::ZERO,
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.0, 2.0, 0.0),
    ];
    let uvs = [
        DVec2::new(0.0, 0.0),
        DVec2::new(4.0, 1.0),
        DVec2::new(-1.0, 3.0),
    ];
    for (c, uv) in corners.iter().zip(uvs) {
        assert_eq!(uv_at(corners, uvs, *c), uv);
    }
    // Half way along the second edge, and off the plane a little: projected.
    let got = uv_at(corners, uvs, DVec3::new(1.0, 1.0, 1e-9));
    assert!((got - DVec2::new(1.5, 2.0)).length() < 1e-12, "{got}");
    // A point a rounding error outside is kept within the corners' range.
    let got = uv_at(corners, uvs, DVec3::new(-1e-9, 0.0, 0.0));
    assert!(got.x >= -1.0 && got.y >= 0.0, "{got}");
}

/// A sphere over a floor in the sun, compiled with shadows: the floor's triangles are cut
/// along the sphere's shadow, the sphere's by the floor's plane nowhere. Every vertex of every
/// polygon has the coordinates of its position: on the floor, planar ones (`u = x / 2`,
/// `v = z / 2`: linear in the position, so the expected value needs no triangle), on the
/// sphere, its triangle's corners' interpolated; a vertex at a source corner has that corner's
/// coordinates exactly.
#[test]
fn every_vertex_takes_the_coordinates_of_its_position_cut_or_not() {
    let mut mesh = scenes::sphere(8, 12);
    let floor =
        [(-3.0, -3.0), (-3.0, 3.0), (3.0, 3.0), (3.0, -3.0)].map(|(x, z)| DVec3::new(x, -1.2, z));
    let sphere = mesh.triangles.len();
    for t in [[0, 1, 2], [0, 2, 3]] {
        mesh.triangles.push(SourceTriangle {
            opacity: u8::MAX,
            vertices: t.map(|i| floor[i]),
            ..mesh.triangles[0]
        });
    }
    let planar = |p: DVec3| DVec2::new(p.x / 2.0, p.z / 2.0);
    let mut mesh = scenes::textured(mesh, 3, |t| t.map(|p| DVec2::new(p.x.atan2(p.z), p.y)));
    for t in &mut mesh.triangles[sphere..] {
        t.texture = t.texture.map(|uvs| CornerUvs {
            uv: t.vertices.map(planar),
            ..uvs
        });
    }
    let sun = DVec3::new(0.3, 1.0, 0.2);
    let options = CompileOptions {
        build: BuildOptions {
            shadows: Some(Light::Sun(sun)),
            ..BuildOptions::default()
        },
        shading: Shading::Lambert(sun),
        surface: Surface::Faceted,
        ..CompileOptions::default()
    };
    let (tree, _) = compile_mesh(&mesh, &options, &|_| {}).unwrap();
    let uvs = polygon_uvs(&tree, &mesh);
    assert_eq!(uvs.len(), tree.polygons.len());
    let (mut cut, mut at_corners) = (0, 0);
    for (p, uvs) in tree.polygons.iter().zip(&uvs) {
        let t = &mesh.triangles[p.source as usize];
        let corner_uvs = t.texture.unwrap().uv;
        let uvs = uvs.as_ref().unwrap();
        assert_eq!(uvs.len(), p.vertices.len());
        for (&v, &got) in p.vertices.iter().zip(uvs) {
            let at = tree.centre + tree.vertices[v as usize];
            if let Some(k) = t.vertices.iter().position(|&c| (c - at).length() < 1e-6) {
                at_corners += 1;
                assert_eq!(got, fixed(corner_uvs[k]));
                continue;
            }
            cut += 1;
            let want = if (p.source as usize) < sphere {
                // The exact barycentric interpolation on the triangle as the file gives it.
                let w = crate::shade::corners::weights(t.vertices, at);
                corner_uvs[0] * w[0] + corner_uvs[1] * w[1] + corner_uvs[2] * w[2]
            } else {
                planar(at)
            };
            let want = fixed(want);
            // Within one step of 2^-16: the corners the compiler takes are on its grid.
            for k in 0..2 {
                assert!(
                    (got[k] - want[k]).abs() <= 1,
                    "polygon of triangle {}: {got:?} against {want:?}",
                    p.source
                );
            }
        }
    }
    assert!(cut > 8, "the shadow cuts the floor: {cut} cut vertices");
    assert!(at_corners > 100);
}

#[test]
fn an_untextured_mesh_has_no_coordinates() {
    let mesh = scenes::sphere(4, 6);
    let (tree, _) = compile_mesh(&mesh, &CompileOptions::default(), &|_| {}).unwrap();
    assert!(polygon_uvs(&tree, &mesh).is_empty());
    // One textured triangle: the others' polygons have none.
    let mut mesh = scenes::textured(mesh, 0, |_| [DVec2::ZERO; 3]);
    for t in &mut mesh.triangles[1..] {
        t.texture = None;
    }
    let (tree, _) = compile_mesh(&mesh, &CompileOptions::default(), &|_| {}).unwrap();
    let uvs = polygon_uvs(&tree, &mesh);
    for (p, uvs) in tree.polygons.iter().zip(&uvs) {
        assert_eq!(uvs.is_some(), p.source == 0);
    }
}
