//! Generated scenes for benchmarks and tests: closed meshes (sphere, torus, a grid of boxes) and
//! random triangle soups, deterministic for a given size and seed, and any of them textured.

use glam::{DVec2, DVec3};

use crate::load::texture::{CornerUvs, Texture};
use crate::load::{Mesh, SourceTriangle, DEFAULT_COLOUR};
pub use crate::random::SplitMix;

/// A mesh of `triangles` in the default colour.
pub fn mesh(triangles: Vec<[DVec3; 3]>) -> Mesh {
    Mesh {
        triangles: triangles
            .into_iter()
            .map(|vertices| SourceTriangle {
                vertices,
                colour: DEFAULT_COLOUR,
                normals: None,
                texture: None,
            })
            .collect(),
        ..Mesh::default()
    }
}

/// `mesh` with one texture on every triangle, its corners' coordinates `uv(corners)`: a
/// `2^log2 x 2^log2` checkerboard of red and white texels that repeats (`clamp` off).
pub fn textured(mut mesh: Mesh, log2: u8, uv: impl Fn([DVec3; 3]) -> [DVec2; 3]) -> Mesh {
    let side = 1u32 << log2;
    let texels = (0..side * side)
        .map(|i| {
            if (i % side + i / side).is_multiple_of(2) {
                0xF800
            } else {
                0xFFFF
            }
        })
        .collect();
    mesh.textures = vec![Texture {
        path: "checkerboard.png".into(),
        log2_width: log2,
        log2_height: log2,
        clamp: [false; 2],
        texels,
    }];
    for t in &mut mesh.triangles {
        t.texture = Some(CornerUvs {
            texture: 0,
            uv: uv(t.vertices),
        });
    }
    mesh
}

/// Add the quad `a b c d` (counter-clockwise seen from outside) as two triangles.
fn quad(out: &mut Vec<[DVec3; 3]>, a: DVec3, b: DVec3, c: DVec3, d: DVec3) {
    out.push([a, b, c]);
    out.push([a, c, d]);
}

/// Three triangles that pierce one another in a cycle: no order of them is right without a cut,
/// and every plane through three of their corners cuts one of them or leaves a side empty.
pub fn piercing_triangles() -> Vec<[DVec3; 3]> {
    vec![
        [
            DVec3::new(-1.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, -1.0),
            DVec3::new(0.0, 0.0, 1.0),
        ],
        [
            DVec3::new(0.0, -1.0, -0.9),
            DVec3::new(0.0, 1.0, -0.9),
            DVec3::new(0.1, 0.0, 0.9),
        ],
        [
            DVec3::new(-0.7, -0.5, 0.0),
            DVec3::new(0.6, 0.8, 0.1),
            DVec3::new(0.2, -0.9, 0.3),
        ],
    ]
}

/// A closed UV sphere of radius 1 with `rings` latitude bands and `segments` longitude bands
/// (`2 * segments * (rings - 1)` triangles), outward-facing.
pub fn sphere(rings: usize, segments: usize) -> Mesh {
    let rings = rings.max(2);
    let segments = segments.max(3);
    let point = |i: usize, j: usize| {
        let theta = std::f64::consts::PI * i as f64 / rings as f64;
        let phi = 2.0 * std::f64::consts::PI * (j % segments) as f64 / segments as f64;
        DVec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            theta.sin() * phi.sin(),
        )
    };
    let mut t = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            );
            if i == 0 {
                t.push([a, c, b]);
            } else if i == rings - 1 {
                t.push([a, d, b]);
            } else {
                t.push([a, d, c]);
                t.push([a, c, b]);
            }
        }
    }
    mesh(t)
}

/// A closed torus (major radius 1, minor radius 0.35) with `n * m * 2` triangles.
pub fn torus(n: usize, m: usize) -> Mesh {
    let (n, m) = (n.max(3), m.max(3));
    let point = |i: usize, j: usize| {
        let u = 2.0 * std::f64::consts::PI * (i % n) as f64 / n as f64;
        let v = 2.0 * std::f64::consts::PI * (j % m) as f64 / m as f64;
        let r = 1.0 + 0.35 * v.cos();
        DVec3::new(r * u.cos(), 0.35 * v.sin(), r * u.sin())
    };
    let mut t = Vec::new();
    for i in 0..n {
        for j in 0..m {
            quad(
                &mut t,
                point(i, j),
                point(i, j + 1),
                point(i + 1, j + 1),
                point(i + 1, j),
            );
        }
    }
    mesh(t)
}

/// `k x k x k` disjoint axis-aligned boxes (12 triangles each) on a grid.
pub fn box_grid(k: usize) -> Mesh {
    let mut t = Vec::new();
    for x in 0..k {
        for y in 0..k {
            for z in 0..k {
                let lo = DVec3::new(x as f64, y as f64, z as f64) * 2.0;
                boxed(&mut t, lo, lo + DVec3::splat(1.2));
            }
        }
    }
    mesh(t)
}

/// The 12 outward triangles of the box `lo..hi`.
pub fn boxed(t: &mut Vec<[DVec3; 3]>, lo: DVec3, hi: DVec3) {
    let v = |x: bool, y: bool, z: bool| {
        DVec3::new(
            if x { hi.x } else { lo.x },
            if y { hi.y } else { lo.y },
            if z { hi.z } else { lo.z },
        )
    };
    let (f, t_) = (false, true);
    quad(t, v(f, f, f), v(f, t_, f), v(t_, t_, f), v(t_, f, f)); // -z
    quad(t, v(f, f, t_), v(t_, f, t_), v(t_, t_, t_), v(f, t_, t_)); // +z
    quad(t, v(f, f, f), v(t_, f, f), v(t_, f, t_), v(f, f, t_)); // -y
    quad(t, v(f, t_, f), v(f, t_, t_), v(t_, t_, t_), v(t_, t_, f)); // +y
    quad(t, v(f, f, f), v(f, f, t_), v(f, t_, t_), v(f, t_, f)); // -x
    quad(t, v(t_, f, f), v(t_, t_, f), v(t_, t_, t_), v(t_, f, t_)); // +x
}

/// `n` random triangles in the unit cube, each of size about `size`: many intersections,
/// the worst case for cuts.
pub fn soup(n: usize, size: f64, seed: u64) -> Mesh {
    let mut rng = SplitMix(seed);
    let mut t = Vec::with_capacity(n);
    for _ in 0..n {
        let c = DVec3::new(rng.unit(), rng.unit(), rng.unit());
        let mut corner = || c + (DVec3::new(rng.unit(), rng.unit(), rng.unit()) - 0.5) * size;
        t.push([corner(), corner(), corner()]);
    }
    mesh(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Every undirected edge of a closed, consistently oriented mesh appears once in each
    /// direction.
    fn assert_closed(m: &Mesh) {
        let key = |p: DVec3| (p * 1e9).round().as_i64vec3().to_array();
        let mut edges: HashMap<([i64; 3], [i64; 3]), i32> = HashMap::new();
        for t in &m.triangles {
            for k in 0..3 {
                let (a, b) = (key(t.vertices[k]), key(t.vertices[(k + 1) % 3]));
                *edges.entry((a, b)).or_default() += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "directed edge used {n} times");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge without its twin");
        }
    }

    #[test]
    fn generated_meshes_are_closed_and_sized() {
        let s = sphere(8, 12);
        assert_eq!(s.triangles.len(), 2 * 12 * 7);
        assert_closed(&s);
        let t = torus(10, 6);
        assert_eq!(t.triangles.len(), 120);
        assert_closed(&t);
        let g = box_grid(2);
        assert_eq!(g.triangles.len(), 8 * 12);
        assert_closed(&g);
    }

    #[test]
    fn sphere_faces_outwards() {
        for t in &sphere(6, 8).triangles {
            let [a, b, c] = t.vertices;
            let n = (b - a).cross(c - a);
            assert!(n.dot((a + b + c) / 3.0) > 0.0);
        }
    }

    #[test]
    fn soup_is_deterministic() {
        let a = soup(50, 0.3, 7);
        let b = soup(50, 0.3, 7);
        assert_eq!(a.triangles, b.triangles);
        assert_ne!(a.triangles, soup(50, 0.3, 8).triangles);
    }
}
