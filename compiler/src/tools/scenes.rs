//! Generated scenes for benchmarks and tests: closed meshes (sphere, torus, a grid of boxes) and
//! random triangle soups, deterministic for a given size and seed; textures made in code (one
//! whose every texel has its own colour, a checkerboard), meshes textured with them, any generated mesh textured with a checkerboard, and the
//! pictures of the textured fixtures (`fixtures/textured-box/`, `fixtures/textured-floor/`);
//! scenes with transparent surfaces as OBJ and MTL text, and their fixtures
//! (`fixtures/crossing-panes/`, `fixtures/interpenetrating-boxes/`, `fixtures/glass-box/`).

use std::path::PathBuf;

use glam::{DVec2, DVec3};

use crate::load::texture::{CornerUvs, Texture};
use crate::load::{Mesh, SourceTriangle, DEFAULT_COLOUR};
pub use crate::random::SplitMix;

mod transparent;
pub use transparent::{
    crossing_panes, glass_box, glass_box_object, glass_box_teapot, interpenetrating_boxes,
    transparent_fixtures, transparent_scenes, Material, TransparentScene,
};

/// A mesh of `triangles` in the default colour.
pub fn mesh(triangles: Vec<[DVec3; 3]>) -> Mesh {
    Mesh {
        triangles: triangles
            .into_iter()
            .map(|vertices| SourceTriangle {
                opacity: u8::MAX,
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
    let (rings, segments) = (rings.max(2), segments.max(3));
    let points = sphere_points(rings, segments);
    let corners = sphere_corners(rings, segments);
    mesh(
        corners
            .into_iter()
            .map(|c| c.map(|(i, j)| points(i, j)))
            .collect(),
    )
}

/// The point of [`sphere`] on ring `i` (0 the north pole, `rings` the south one) and meridian
/// `j` (`segments` the same as 0).
fn sphere_points(rings: usize, segments: usize) -> impl Fn(usize, usize) -> DVec3 {
    move |i, j| {
        let theta = std::f64::consts::PI * i as f64 / rings as f64;
        let phi = 2.0 * std::f64::consts::PI * (j % segments) as f64 / segments as f64;
        DVec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            theta.sin() * phi.sin(),
        )
    }
}

/// [`sphere`]'s triangles by their corners' `(ring, meridian)` ([`sphere_points`]), the
/// meridians from 0 to `segments`.
fn sphere_corners(rings: usize, segments: usize) -> Vec<[(usize, usize); 3]> {
    let mut t = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = ((i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1));
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
    t
}

/// A closed torus (major radius 1, minor radius 0.35) with `n * m * 2` triangles.
pub fn torus(n: usize, m: usize) -> Mesh {
    let (n, m) = (n.max(3), m.max(3));
    let points = torus_points(n, m);
    let corners = torus_corners(n, m);
    mesh(
        corners
            .into_iter()
            .map(|c| c.map(|(i, j)| points(i, j)))
            .collect(),
    )
}

/// The point of [`torus`] at step `i` of `n` around its axis and `j` of `m` around its tube
/// (`n` and `m` the same as 0).
fn torus_points(n: usize, m: usize) -> impl Fn(usize, usize) -> DVec3 {
    move |i, j| {
        let u = 2.0 * std::f64::consts::PI * (i % n) as f64 / n as f64;
        let v = 2.0 * std::f64::consts::PI * (j % m) as f64 / m as f64;
        let r = 1.0 + 0.35 * v.cos();
        DVec3::new(r * u.cos(), 0.35 * v.sin(), r * u.sin())
    }
}

/// [`torus`]'s triangles by their corners' steps ([`torus_points`]), from 0 to `n` and `m`.
fn torus_corners(n: usize, m: usize) -> Vec<[(usize, usize); 3]> {
    let mut t = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (a, b, c, d) = ((i, j), (i, j + 1), (i + 1, j + 1), (i + 1, j));
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    t
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

/// The RGB565 colour of 5-bit red, 6-bit green and 5-bit blue (each taken modulo its range).
pub const fn rgb565(r: u16, g: u16, b: u16) -> u16 {
    (r & 31) << 11 | (g & 63) << 5 | (b & 31)
}

/// A material colour that shows the texels as they are.
pub const WHITE: [u8; 3] = [255; 3];

/// A repeating texture of `2^log2_width x 2^log2_height` texels, `texel(column, row)` each
/// (row 0 the top); `name` stands for its file in messages.
fn generated(
    name: &str,
    log2_width: u8,
    log2_height: u8,
    texel: impl Fn(u32, u32) -> u16,
) -> Texture {
    let (w, h) = (1u32 << log2_width, 1u32 << log2_height);
    Texture {
        path: PathBuf::from(format!("<generated {name} {w}x{h}>")),
        log2_width,
        log2_height,
        clamp: [false; 2],
        texels: (0..h)
            .flat_map(|r| (0..w).map(move |c| (c, r)))
            .map(|(c, r)| texel(c, r))
            .collect(),
    }
}

/// A repeating texture whose every texel has its own colour, so that a pixel's colour tells
/// which texel it shows (and how far that is from the right one): red is the column's low five
/// bits, blue its sixth (0 or 31), green the row. Sides up to 64 texels (`log2 <= 6`).
pub fn numbered_texture(log2_width: u8, log2_height: u8) -> Texture {
    assert!(
        log2_width <= 6 && log2_height <= 6,
        "a numbered texture has at most 64 x 64 texels"
    );
    generated("numbered", log2_width, log2_height, |c, r| {
        rgb565(c as u16, r as u16, if c >= 32 { 31 } else { 0 })
    })
}

/// The checkerboards' colours: a light sand and a dark blue.
pub const CHECKER_COLOURS: [u16; 2] = [rgb565(29, 56, 22), rgb565(4, 12, 18)];

/// A repeating checkerboard of `2^log2_width x 2^log2_height` texels in squares of
/// `2^log2_square`, in `colours` (the first at the top left).
pub fn checkerboard(
    log2_width: u8,
    log2_height: u8,
    log2_square: u8,
    colours: [u16; 2],
) -> Texture {
    generated("checkerboard", log2_width, log2_height, |c, r| {
        colours[(((c ^ r) >> log2_square) & 1) as usize]
    })
}

/// A white triangle under texture `texture`, its corners at `vertices` with coordinates `uv`.
fn textured_triangle(vertices: [DVec3; 3], uv: [DVec2; 3], texture: u32) -> SourceTriangle {
    SourceTriangle {
        opacity: u8::MAX,
        vertices,
        colour: WHITE,
        normals: None,
        texture: Some(CornerUvs { texture, uv }),
    }
}

/// Add the quad `p` (counter-clockwise seen from outside) with its corners' coordinates `uv`
/// as two triangles, split as [`quad`] splits one.
fn textured_quad(out: &mut Vec<SourceTriangle>, p: [DVec3; 4], uv: [DVec2; 4], texture: u32) {
    out.push(textured_triangle(
        [p[0], p[1], p[2]],
        [uv[0], uv[1], uv[2]],
        texture,
    ));
    out.push(textured_triangle(
        [p[0], p[2], p[3]],
        [uv[0], uv[2], uv[3]],
        texture,
    ));
}

/// [`sphere`] in white under a 64 x 64 [`checkerboard`] of 8 x 8 squares: `u` around, from 1
/// to 0 eastwards (so that seen from outside the picture is not mirrored), `v` from 1 at the
/// north pole to 0 at the south one. The seam's corners are duplicated (`u = 1` and `u = 0`),
/// and a triangle's pole corner takes the middle of its segment's `u`.
pub fn textured_sphere(rings: usize, segments: usize) -> Mesh {
    let (rings, segments) = (rings.max(2), segments.max(3));
    let points = sphere_points(rings, segments);
    let uv = |(i, j): (usize, usize), pole_j: usize| {
        let at_pole = i == 0 || i == rings;
        let u = if at_pole {
            (pole_j as f64 + 0.5) / segments as f64
        } else {
            j as f64 / segments as f64
        };
        DVec2::new(1.0 - u, 1.0 - i as f64 / rings as f64)
    };
    let triangles = sphere_corners(rings, segments)
        .into_iter()
        .map(|corners| {
            // A triangle's segment: the smallest `j` of its corners.
            let j = corners.iter().map(|c| c.1).min().unwrap_or(0);
            textured_triangle(
                corners.map(|c| points(c.0, c.1)),
                corners.map(|c| uv(c, j)),
                0,
            )
        })
        .collect();
    Mesh {
        triangles,
        textures: vec![checkerboard(6, 6, 3, CHECKER_COLOURS)],
        ..Mesh::default()
    }
}

/// [`torus`] in white under a 128 x 64 [`checkerboard`] of 8 x 8 squares: `u` around the
/// axis, from 1 to 0 (not mirrored, seen from outside), `v` from 0 to 1 around the tube,
/// upwards on its outside. The seams' corners are duplicated (`u = 1` and `u = 0`, `v = 0` and
/// `v = 1`).
pub fn textured_torus(n: usize, m: usize) -> Mesh {
    let (n, m) = (n.max(3), m.max(3));
    let points = torus_points(n, m);
    let uv = |(i, j): (usize, usize)| DVec2::new(1.0 - i as f64 / n as f64, j as f64 / m as f64);
    let triangles = torus_corners(n, m)
        .into_iter()
        .map(|c| textured_triangle(c.map(|(i, j)| points(i, j)), c.map(uv), 0))
        .collect();
    Mesh {
        triangles,
        textures: vec![checkerboard(7, 6, 3, CHECKER_COLOURS)],
        ..Mesh::default()
    }
}

/// A white square floor in the plane y = 0, from `-half` to `half` on x and z, facing up,
/// under a repeating 64 x 64 [`checkerboard`] of 8 x 8 squares: `(u, v)` is 0 at its corner
/// `(-half, 0, half)` and `repeats` at `(half, 0, -half)` (`u` along +x, `v` along -z: upright
/// seen from +z). The oblique views of the textured tests.
pub fn textured_floor(half: f64, repeats: f64) -> Mesh {
    let p = |x: f64, z: f64| DVec3::new(x * half, 0.0, z * half);
    let mut triangles = Vec::new();
    textured_quad(
        &mut triangles,
        [p(-1.0, 1.0), p(1.0, 1.0), p(1.0, -1.0), p(-1.0, -1.0)],
        [
            DVec2::ZERO,
            DVec2::new(repeats, 0.0),
            DVec2::splat(repeats),
            DVec2::new(0.0, repeats),
        ],
        0,
    );
    Mesh {
        triangles,
        textures: vec![checkerboard(6, 6, 3, CHECKER_COLOURS)],
        ..Mesh::default()
    }
}

/// The corners of the cube `[-1, 1]^3` in the order of `fixtures/textured-box/box.obj`'s `v`
/// lines.
const BOX_CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// The cube's faces as `box.obj` lists them (+z, +x, +y, -y, -x, -z: a die's 1 to 6), each by
/// its corners bottom left, bottom right, top right, top left seen from outside (the sides
/// upright; the top's up is -z, the bottom's +z): counter-clockwise, and the corners of OBJ
/// coordinates `(0, 0)`, `(1, 0)`, `(1, 1)`, `(0, 1)`.
const BOX_FACES: [[usize; 4]; 6] = [
    [4, 5, 6, 7],
    [5, 1, 2, 6],
    [7, 6, 2, 3],
    [0, 1, 5, 4],
    [0, 4, 7, 3],
    [1, 0, 3, 2],
];

/// The cube `[-1, 1]^3` in white with coordinates of its own under a 64 x 64
/// [`numbered_texture`], each face mapping it differently (in the order of
/// `fixtures/textured-box/box.obj`): +z as it is, +x turned a quarter, +y twice each way (repeating), -y from -0.5 to 1.5 each way under
/// the same texels clamped (texture 1), -x a quarter of it magnified (`u` 0.25 to 0.5, `v` 0.5
/// to 0.75), -z mirrored.
pub fn numbered_box() -> Mesh {
    let maps: [fn(DVec2) -> DVec2; 6] = [
        |p| p,
        |p| DVec2::new(p.y, 1.0 - p.x),
        |p| p * 2.0,
        |p| p * 2.0 - 0.5,
        |p| DVec2::new(0.25, 0.5) + p * 0.25,
        |p| DVec2::new(1.0 - p.x, p.y),
    ];
    let unit = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
    let mut triangles = Vec::new();
    for (face, (corners, map)) in BOX_FACES.iter().zip(maps).enumerate() {
        let texture = u32::from(face == 3);
        let p = corners.map(|c| DVec3::from_array(BOX_CORNERS[c]));
        textured_quad(&mut triangles, p, unit.map(map), texture);
    }
    let clamped = Texture {
        clamp: [true; 2],
        ..numbered_texture(6, 6)
    };
    Mesh {
        triangles,
        textures: vec![numbered_texture(6, 6), clamped],
        ..Mesh::default()
    }
}

/// Die digits 1 to 6, 5 x 7, a row a byte (bit 4 the left column).
const DIGITS: [[u8; 7]; 6] = [
    [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
    [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
    [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E],
    [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
    [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
    [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
];

/// The background of the die's faces 1 to 6: red, green, blue, yellow, purple, teal.
const FACE_COLOURS: [u16; 6] = [
    rgb565(26, 8, 4),
    rgb565(6, 44, 8),
    rgb565(4, 16, 26),
    rgb565(28, 52, 4),
    rgb565(22, 10, 24),
    rgb565(4, 44, 24),
];

/// Face `n` (1 to 6) of the textured box: 32 x 32 texels, the white digit `n` three texels a
/// dot, upright in the middle, on the face's colour in a black frame.
pub fn die_face(n: usize) -> Texture {
    assert!((1..=6).contains(&n), "a die's faces are 1 to 6");
    let (digit, colour) = (DIGITS[n - 1], FACE_COLOURS[n - 1]);
    let mut face = generated(&format!("face {n}"), 5, 5, |c, r| {
        let dot = |c: u32, r: u32| {
            // The digit's 15 x 21 texels from (8, 5).
            let (x, y) = (c.checked_sub(8)? / 3, r.checked_sub(5)? / 3);
            (x < 5 && y < 7).then(|| (digit[y as usize] >> (4 - x)) & 1 == 1)
        };
        if c == 0 || r == 0 || c == 31 || r == 31 {
            0
        } else if dot(c, r) == Some(true) {
            0xFFFF
        } else {
            colour
        }
    });
    face.path = PathBuf::from(format!("face{n}.png"));
    face
}

/// The textured floor's tile: 32 x 32 texels, four stones of 16 x 16 in two colours, a grey
/// joint on each one's top and left edge and a dark mark near its top left corner (so that
/// the tile's orientation shows).
pub fn floor_tile() -> Texture {
    let (light, dark) = (rgb565(27, 50, 20), rgb565(20, 34, 14));
    let (joint, mark) = (rgb565(12, 24, 12), rgb565(10, 18, 8));
    let mut tile = generated("tile", 5, 5, |c, r| {
        let (x, y) = (c % 16, r % 16);
        if x == 0 || y == 0 {
            joint
        } else if (3..5).contains(&x) && (3..5).contains(&y) {
            mark
        } else if (c / 16 + r / 16) % 2 == 0 {
            light
        } else {
            dark
        }
    });
    tile.path = PathBuf::from("tile.png");
    tile
}

/// The pictures of the textured fixtures by their paths under `fixtures/`: what the PNGs hold,
/// each texel's RGB565 colour expanded to 8 bits a channel
/// ([`rgb888`](super::reference::rgb888)), so that the loader reads them back exactly. A test
/// checks the files against these (and with `PEEL_WRITE_FIXTURES=1` writes them).
pub fn fixture_pictures() -> Vec<(String, Texture)> {
    let faces = (1..=6).map(|n| (format!("textured-box/face{n}.png"), die_face(n)));
    faces
        .chain([("textured-floor/tile.png".to_string(), floor_tile())])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::reference::rgb888;
    use std::collections::{HashMap, HashSet};

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

    /// Every texel of a numbered texture has its own colour, in RGB565 and expanded.
    #[test]
    fn numbered_texels_all_differ() {
        for (a, b) in [(6, 6), (5, 3), (0, 6)] {
            let t = numbered_texture(a, b);
            assert_eq!(t.texels.len(), (t.width() * t.height()) as usize);
            let colours: HashSet<[u8; 3]> = t.texels.iter().map(|&c| rgb888(c)).collect();
            assert_eq!(colours.len(), t.texels.len(), "{a} {b}");
        }
        let t = numbered_texture(6, 6);
        assert_eq!(t.texel(33, 2), rgb565(1, 2, 31));
        assert_eq!(t.texel(31, 63), rgb565(31, 63, 0));
    }

    #[test]
    fn checkerboard_squares_alternate() {
        let [a, b] = CHECKER_COLOURS;
        assert_ne!(a, b);
        let t = checkerboard(7, 6, 3, CHECKER_COLOURS);
        assert_eq!((t.width(), t.height()), (128, 64));
        let at = |c, r| t.texel(c, r);
        assert_eq!(
            [at(0, 0), at(7, 7), at(8, 0), at(0, 8), at(8, 8)],
            [a, a, b, b, a]
        );
        assert_eq!([at(127, 0), at(127, 63), at(120, 56)], [b, a, a]);
    }

    /// The textured sphere and torus are the plain ones with coordinates: no triangle's `u`
    /// goes the long way round a seam, and the pictures are not mirrored seen from outside
    /// (the coordinates turn as the corners do).
    #[test]
    fn textured_meshes_are_the_plain_ones_with_coordinates() {
        for (textured, plain, steps) in [
            (textured_sphere(8, 12), sphere(8, 12), 12.0),
            (textured_torus(10, 6), torus(10, 6), 10.0),
        ] {
            let positions = |m: &Mesh| m.triangles.iter().map(|t| t.vertices).collect::<Vec<_>>();
            assert_eq!(positions(&textured), positions(&plain));
            assert_eq!(textured.textures.len(), 1);
            for t in &textured.triangles {
                let uv = t.texture.expect("textured").uv;
                assert_eq!(t.texture.map(|c| c.texture), Some(0));
                assert!(uv
                    .iter()
                    .all(|p| (0.0..=1.0).contains(&p.x) && (0.0..=1.0).contains(&p.y)));
                let us = uv.map(|p| p.x);
                let span = us
                    .iter()
                    .fold(0.0f64, |m, &a| us.iter().fold(m, |m, &b| m.max(a - b)));
                assert!(span <= 1.0 / steps + 1e-12, "{uv:?}");
                let turn = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]);
                assert!(turn > 0.0, "mirrored: {uv:?}");
            }
        }
        // The seam: a corner at u = 1 and one at u = 0 share their positions.
        let t = textured_torus(10, 6);
        let at = |u: f64| {
            let mut p: Vec<[i64; 3]> = (t.triangles.iter())
                .flat_map(|t| (0..3).map(move |k| (t.vertices[k], t.texture.unwrap().uv[k])))
                .filter(|(_, uv)| uv.x == u)
                .map(|(p, _)| (p * 1e9).round().as_i64vec3().to_array())
                .collect();
            p.sort();
            p.dedup();
            p
        };
        assert_eq!(at(0.0), at(1.0));
        assert_eq!(at(0.0).len(), 6);
    }

    /// The floor faces up and repeats its texture `repeats` times each way, upright from +z.
    #[test]
    fn the_floor_faces_up_and_repeats() {
        let f = textured_floor(2.0, 4.0);
        assert_eq!(f.triangles.len(), 2);
        for t in &f.triangles {
            let [a, b, c] = t.vertices;
            assert!((b - a).cross(c - a).y > 0.0);
            let uv = t.texture.unwrap().uv;
            for (p, q) in t.vertices.iter().zip(uv) {
                assert_eq!(q, DVec2::new(p.x + 2.0, 2.0 - p.z));
            }
        }
    }

    /// The numbered box is closed, faces outwards, and maps the texture on each face as its
    /// documentation says: its bottom left corner's coordinates, and whether it is mirrored.
    #[test]
    fn the_numbered_box_maps_each_face_its_own_way() {
        let b = numbered_box();
        assert_eq!(b.triangles.len(), 12);
        assert_closed(&b);
        assert_eq!(b.textures.len(), 2);
        assert_eq!(
            (b.textures[0].clamp, b.textures[1].clamp),
            ([false; 2], [true; 2])
        );
        let bottom_left = [
            (0, DVec2::ZERO, false),
            (0, DVec2::Y, false),
            (0, DVec2::ZERO, false),
            (1, DVec2::splat(-0.5), false),
            (0, DVec2::new(0.25, 0.5), false),
            (0, DVec2::X, true),
        ];
        for (face, (texture, at, mirrored)) in bottom_left.into_iter().enumerate() {
            for t in &b.triangles[2 * face..2 * face + 2] {
                let [p, q, r] = t.vertices;
                assert!(
                    (q - p).cross(r - p).dot(p + q + r) > 0.0,
                    "face {face} inwards"
                );
                let c = t.texture.unwrap();
                assert_eq!(c.texture, texture);
                let turn = (c.uv[1] - c.uv[0]).perp_dot(c.uv[2] - c.uv[0]);
                assert_eq!(turn < 0.0, mirrored, "face {face}");
            }
            assert_eq!(
                b.triangles[2 * face].texture.unwrap().uv[0],
                at,
                "face {face}"
            );
        }
    }

    /// The die's faces: 32 x 32, framed in black, each its own colour with its digit in white
    /// (9 texels a dot).
    #[test]
    fn die_faces_show_their_digits() {
        let dots = [10, 14, 14, 14, 17, 15];
        let mut backgrounds = HashSet::new();
        for n in 1..=6 {
            let f = die_face(n);
            assert_eq!((f.width(), f.height()), (32, 32));
            assert!((0..32).all(|k| [(k, 0), (0, k), (k, 31), (31, k)]
                .iter()
                .all(|&(c, r)| f.texel(c, r) == 0)));
            let white = f.texels.iter().filter(|&&c| c == 0xFFFF).count();
            assert_eq!(white, 9 * dots[n - 1], "face {n}");
            backgrounds.insert(f.texel(2, 2));
        }
        assert_eq!(backgrounds.len(), 6);
    }

    /// The committed pictures of the textured fixtures are the generated ones
    /// ([`fixture_pictures`]); `PEEL_WRITE_FIXTURES=1` writes them first.
    #[cfg(feature = "png")]
    #[test]
    fn fixture_pictures_are_the_generated_ones() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
        for (path, texture) in fixture_pictures() {
            let (w, h) = (texture.width(), texture.height());
            let rgb: Vec<u8> = texture.texels.iter().flat_map(|&c| rgb888(c)).collect();
            let file = root.join(&path);
            if std::env::var_os("PEEL_WRITE_FIXTURES").is_some() {
                let image = image::RgbImage::from_raw(w, h, rgb.clone()).unwrap();
                image.save(&file).unwrap();
            }
            let read = image::open(&file)
                .unwrap_or_else(|e| panic!("{}: {e}", file.display()))
                .to_rgb8();
            assert_eq!(read.dimensions(), (w, h), "{path}");
            assert!(
                read.as_raw() == &rgb,
                "{path} differs from its generated picture"
            );
            let size = std::fs::metadata(&file).unwrap().len();
            assert!(size < 4096, "{path}: {size} bytes");
        }
    }

    /// The textured fixtures' OBJ files load (their `vt` and `map_Kd` aside), the box's faces
    /// as [`BOX_FACES`] list them.
    #[test]
    fn textured_fixtures_load() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
        let b = crate::load::load_obj(&root.join("textured-box/box.obj")).unwrap();
        assert_eq!((b.faces, b.triangles.len()), (6, 12));
        for (face, corners) in BOX_FACES.iter().enumerate() {
            let mut want: Vec<[i64; 3]> = corners
                .iter()
                .map(|&c| DVec3::from_array(BOX_CORNERS[c]).as_i64vec3().to_array())
                .collect();
            want.sort();
            let mut got: Vec<[i64; 3]> = (b.triangles[2 * face..2 * face + 2].iter())
                .flat_map(|t| t.vertices.map(|p| p.as_i64vec3().to_array()))
                .collect();
            got.sort();
            got.dedup();
            assert_eq!(got, want, "face {face}");
            for t in &b.triangles[2 * face..2 * face + 2] {
                let [p, q, r] = t.vertices;
                assert!(
                    (q - p).cross(r - p).dot(p + q + r) > 0.0,
                    "face {face} inwards"
                );
            }
        }
        let f = crate::load::load_obj(&root.join("textured-floor/floor.obj")).unwrap();
        assert_eq!(f.triangles.len(), 2);
        for t in &f.triangles {
            let [p, q, r] = t.vertices;
            assert!((q - p).cross(r - p).y > 0.0, "the floor faces up");
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
