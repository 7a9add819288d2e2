//! The texel under each pixel centre, exactly: what a textured frame is checked against
//! ([`crate::tools::texture_check`]). The ray through the centre hits its nearest triangle at a
//! point whose barycentric weights interpolate the corners' OBJ `(u, v)` in f64, which is the
//! exact perspective-correct interpolation, and [`Texture::texel_of`] takes the texel there:
//! none of the file's 16-bit coordinates, the runtime's divisions or its 16-pixel steps.

use super::{ray_hit, screen_bbox, Lens, EDGE_MARGIN};
use crate::load::texture::Texture;
use crate::load::Mesh;
use crate::tools::shot::Shot;

/// A texel a point of the screen sees on a textured triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TexelHit {
    /// The source triangle: its index in [`Mesh::triangles`].
    pub id: u32,
    /// Its texture: an index into [`Mesh::textures`].
    pub texture: u32,
    /// The texel's column, 0 the image's left.
    pub column: u32,
    /// The texel's row, 0 the image's top.
    pub row: u32,
}

impl TexelHit {
    /// The texel `columns` and `rows` away on the same texture, repeated or clamped on each
    /// axis as `texture` says: a neighbour the renderer may show for it when the point is
    /// near their boundary.
    pub fn step(self, texture: &Texture, columns: i64, rows: i64) -> TexelHit {
        let place = |at: u32, by: i64, log2: u8, clamp: bool| {
            let n = 1i64 << log2;
            let k = i64::from(at) + by;
            (if clamp {
                k.clamp(0, n - 1)
            } else {
                k.rem_euclid(n)
            }) as u32
        };
        TexelHit {
            column: place(self.column, columns, texture.log2_width, texture.clamp[0]),
            row: place(self.row, rows, texture.log2_height, texture.clamp[1]),
            ..self
        }
    }

    /// The colour this texel shows, unlit: its RGB565 colour expanded ([`rgb888`]) times its
    /// triangle's colour ([`modulate`]). Panics if `mesh` lacks the triangle or the texture.
    pub fn colour(self, mesh: &Mesh) -> [u8; 3] {
        let texture = &mesh.textures[self.texture as usize];
        let kd = mesh.triangles[self.id as usize].colour;
        modulate(rgb888(texture.texel(self.column, self.row)), kd)
    }
}

/// An RGB565 colour (red in the high bits) in 8 bits a channel, as the renderer expands it:
/// `c5 * 255 / 31` and `c6 * 255 / 63`, rounded to nearest (never a tie).
pub fn rgb888(texel: u16) -> [u8; 3] {
    let expand = |c: u16, max: u32| ((u32::from(c) * 510 + max) / (2 * max)) as u8;
    [
        expand(texel >> 11, 31),
        expand((texel >> 5) & 63, 63),
        expand(texel & 31, 31),
    ]
}

/// Texel colour `x` on a surface of colour `k`: per channel `round(x * k / 255)` (never a tie:
/// 255 is odd), `peel_runtime::display::shaded`'s rounding; white leaves `x` as it is.
pub fn modulate(x: [u8; 3], k: [u8; 3]) -> [u8; 3] {
    std::array::from_fn(|c| ((2 * u32::from(x[c]) * u32::from(k[c]) + 255) / 510) as u8)
}

/// What [`texels()`] sees, per pixel (row-major).
#[derive(Debug, Clone)]
pub struct Texels {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// `id + 1` of the triangle the ray through the pixel centre hits first, 0 for none (as
    /// [`super::Reference::ids`]).
    pub ids: Vec<u32>,
    /// The texel under the pixel centre, where that triangle is textured.
    pub texels: Vec<Option<TexelHit>>,
    /// The centre and the four points [`EDGE_MARGIN`] (1/16 pixel) left, right, up and down of
    /// it see the same: the same triangle (or none) and the same texel. Elsewhere the
    /// compiler's quantisation and the runtime's rounding may fairly show a neighbour.
    pub robust: Vec<bool>,
}

impl Texels {
    /// The colour pixel `k` shows, unlit: its texel's ([`TexelHit::colour`]), or its
    /// triangle's colour when untextured; `None` for the background.
    pub fn colour(&self, mesh: &Mesh, k: usize) -> Option<[u8; 3]> {
        let id = self.ids[k].checked_sub(1)?;
        Some(match self.texels[k] {
            Some(hit) => hit.colour(mesh),
            None => mesh.triangles[id as usize].colour,
        })
    }

    /// [`Texels::colour`] of every pixel, row-major.
    pub fn colours(&self, mesh: &Mesh) -> Vec<Option<[u8; 3]>> {
        (0..self.ids.len()).map(|k| self.colour(mesh, k)).collect()
    }
}

/// The points a pixel's robustness is probed at, as offsets from its centre: the centre first.
const PROBES: [(f64, f64); 5] = [
    (0.0, 0.0),
    (-EDGE_MARGIN, 0.0),
    (EDGE_MARGIN, 0.0),
    (0.0, -EDGE_MARGIN),
    (0.0, EDGE_MARGIN),
];

/// Cast, for every pixel of `shot`, the ray through its centre and the four through the points
/// 1/16 pixel from it against `mesh`'s triangles (ids are indices), seeing from the near
/// distance `near` on as [`super::reference()`] does, and take the texel each nearest hit
/// falls in. Panics if a triangle names a texture `mesh` lacks.
pub fn texels(mesh: &Mesh, shot: &Shot, near: f64) -> Texels {
    let cam = &Lens::new(shot, near);
    let (w, h) = (cam.width as usize, cam.height as usize);
    let n = PROBES.len();
    // Per probe: the depth and the triangle with the hit's barycentric weights.
    let mut depth = vec![f64::INFINITY; w * h * n];
    let mut hits: Vec<Option<(u32, [f64; 3])>> = vec![None; w * h * n];
    for (id, tri) in mesh.triangles.iter().enumerate() {
        let t = &tri.vertices;
        let Some((x0, x1, y0, y1)) = screen_bbox(cam, &t.map(|p| cam.to_camera(p))) else {
            continue;
        };
        for j in y0..y1 {
            for i in x0..x1 {
                for (p, (dx, dy)) in PROBES.iter().enumerate() {
                    let dir = cam.ray_at(i as f64 + 0.5 + dx, j as f64 + 0.5 + dy);
                    let Some((tz, weights)) = ray_hit(cam.eye, dir, t) else {
                        continue;
                    };
                    // dir has unit component along f: the ray parameter is the camera depth.
                    let k = (j * w + i) * n + p;
                    if tz >= cam.near && tz < depth[k] {
                        depth[k] = tz;
                        hits[k] = Some((id as u32, weights));
                    }
                }
            }
        }
    }
    let seen = |hit: Option<(u32, [f64; 3])>| {
        let (id, w) = hit?;
        let Some(corners) = mesh.triangles[id as usize].texture else {
            return Some((id, None));
        };
        let texture = mesh
            .textures
            .get(corners.texture as usize)
            .expect("a triangle names a texture the mesh does not have");
        let uv = corners.uv[0] * w[0] + corners.uv[1] * w[1] + corners.uv[2] * w[2];
        let (column, row) = texture.texel_of(uv.x, uv.y);
        Some((
            id,
            Some(TexelHit {
                id,
                texture: corners.texture,
                column,
                row,
            }),
        ))
    };
    let mut out = Texels {
        width: cam.width,
        height: cam.height,
        ids: vec![0; w * h],
        texels: vec![None; w * h],
        robust: vec![true; w * h],
    };
    for k in 0..w * h {
        let probes: Vec<_> = (0..n).map(|p| seen(hits[k * n + p])).collect();
        if let Some((id, texel)) = probes[0] {
            out.ids[k] = id + 1;
            out.texels[k] = texel;
        }
        out.robust[k] = probes.iter().all(|&p| p == probes[0]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::texture::CornerUvs;
    use crate::load::SourceTriangle;
    use crate::tools::scenes::{numbered_texture, rgb565, textured_floor};
    use glam::{DVec2, DVec3};

    const SIDE: u32 = 64;

    fn shot() -> Shot {
        Shot::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, SIDE, SIDE)
    }

    /// A quad in the plane z = 0 facing [`shot`]'s eye, covering the screen square
    /// `[16, 48]^2` pixels exactly, with `(u, v)` from `lo` at its bottom left to `hi` at its
    /// top right: triangle 0 its bottom-right half, 1 its top-left one. At a pixel centre
    /// `(x, y)` it has `u = lo.x + (x - 16) / 32 * (hi.x - lo.x)` and
    /// `v = lo.y + (48 - y) / 32 * (hi.y - lo.y)`, for the quad faces the eye.
    fn facing_quad(lo: DVec2, hi: DVec2, texture: Texture) -> Mesh {
        let px = 5.0 / Lens::new(&shot(), 0.01).fpx; // world units a pixel at z = 0
        let at = |x: f64, y: f64| DVec3::new((x - 32.0) * px, (32.0 - y) * px, 0.0);
        let (a, b, c, d) = (
            at(16.0, 48.0),
            at(48.0, 48.0),
            at(48.0, 16.0),
            at(16.0, 16.0),
        );
        let (ua, ub, uc, ud) = (lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y));
        let triangle = |vertices, uv| SourceTriangle {
            opacity: u8::MAX,
            vertices,
            colour: [255; 3],
            normals: None,
            texture: Some(CornerUvs { texture: 0, uv }),
        };
        Mesh {
            triangles: vec![
                triangle([a, b, c], [ua, ub, uc]),
                triangle([a, c, d], [ua, uc, ud]),
            ],
            textures: vec![texture],
            ..Mesh::default()
        }
    }

    fn inside(i: u32, j: u32) -> bool {
        (16..48).contains(&i) && (16..48).contains(&j)
    }

    /// Whose centre lies on the quad's diagonal (from (16, 48) to (48, 16)).
    fn on_diagonal(i: u32, j: u32) -> bool {
        i + j == 63
    }

    /// 16 x 8 texels over 32 x 32 pixels: a texel is 2 pixels wide and 4 tall, and the pixel
    /// `(i, j)` of the quad shows texel `((i - 16) / 2, (j - 16) / 4)`. Every pixel but those
    /// on the diagonal is robust (texel boundaries fall on pixel edges).
    #[test]
    fn a_facing_quad_shows_the_texels_of_its_closed_form() {
        let mesh = facing_quad(DVec2::ZERO, DVec2::ONE, numbered_texture(4, 3));
        let seen = texels(&mesh, &shot(), 0.01);
        assert_eq!((seen.width, seen.height), (SIDE, SIDE));
        for j in 0..SIDE {
            for i in 0..SIDE {
                let k = (j * SIDE + i) as usize;
                if !inside(i, j) {
                    assert_eq!((seen.ids[k], seen.texels[k]), (0, None), "({i}, {j})");
                    assert!(seen.robust[k], "the background ({i}, {j})");
                    continue;
                }
                let texel = seen.texels[k].expect("textured");
                assert_eq!((texel.texture, texel.id + 1), (0, seen.ids[k]));
                assert_eq!((texel.column, texel.row), ((i - 16) / 2, (j - 16) / 4));
                assert_eq!(seen.robust[k], !on_diagonal(i, j), "({i}, {j})");
                if !on_diagonal(i, j) {
                    assert_eq!(texel.id, u32::from(i + j < 63), "({i}, {j})");
                }
            }
        }
    }

    /// `(u, v)` from -1 to 2 over the quad: three times the texture each way, each texel 4/3
    /// pixels; a repeating axis wraps, a clamping one keeps the edge texels beyond the edges.
    /// No pixel centre comes within 1/6 pixel of a texel boundary, so every pixel off the
    /// diagonal is robust.
    #[test]
    fn repeat_and_clamp_continue_past_the_edges() {
        for clamp in [[false, false], [true, false], [false, true], [true, true]] {
            let texture = Texture {
                clamp,
                ..numbered_texture(3, 3)
            };
            let mesh = facing_quad(DVec2::splat(-1.0), DVec2::splat(2.0), texture);
            let seen = texels(&mesh, &shot(), 0.01);
            let place = |x: f64, clamp: bool| {
                let k = x.floor() as i64;
                (if clamp {
                    k.clamp(0, 7)
                } else {
                    k.rem_euclid(8)
                }) as u32
            };
            let mut distinct = std::collections::HashSet::new();
            for j in 16..48 {
                for i in 16..48 {
                    let k = (j * SIDE + i) as usize;
                    let (x, y) = (f64::from(i) + 0.5, f64::from(j) + 0.5);
                    let u = -1.0 + 3.0 * (x - 16.0) / 32.0;
                    let v = -1.0 + 3.0 * (48.0 - y) / 32.0;
                    let want = (place(u * 8.0, clamp[0]), place((1.0 - v) * 8.0, clamp[1]));
                    let texel = seen.texels[k].expect("textured");
                    assert_eq!((texel.column, texel.row), want, "{clamp:?} ({i}, {j})");
                    assert_eq!(seen.robust[k], !on_diagonal(i, j), "{clamp:?} ({i}, {j})");
                    distinct.insert(want);
                }
            }
            // Every texel is seen; clamped, the corner texel covers a ninth of the quad or more.
            assert_eq!(distinct.len(), 64, "{clamp:?}");
        }
    }

    /// One texel a pixel, the texel boundaries `dx` (`dy`) right of (below) the pixel edges:
    /// a pixel is robust exactly when its centre is more than 1/16 pixel from both.
    #[test]
    fn robust_pixels_keep_a_sixteenth_of_a_pixel_from_texel_boundaries() {
        for (dx, dy) in [
            (0.4, 0.4),
            (0.47, 0.4),
            (0.4, 0.47),
            (0.55, 0.4),
            (0.57, 0.6),
            (0.4, 0.53),
        ] {
            // u * 32 = x - 16 - dx, (1 - v) * 32 = y - 16 - dy.
            let lo = DVec2::new(-dx / 32.0, dy / 32.0);
            let hi = DVec2::new((32.0 - dx) / 32.0, 1.0 + dy / 32.0);
            let mesh = facing_quad(lo, hi, numbered_texture(5, 5));
            let seen = texels(&mesh, &shot(), 0.01);
            let clear = |d: f64| (d - 0.5).abs() > EDGE_MARGIN;
            let want = clear(dx) && clear(dy);
            for j in 16..48 {
                for i in 16..48 {
                    let k = (j * SIDE + i) as usize;
                    let texel = seen.texels[k].expect("textured");
                    let column = (f64::from(i) + 0.5 - 16.0 - dx).floor() as i64;
                    let row = (f64::from(j) + 0.5 - 16.0 - dy).floor() as i64;
                    let at = (column.rem_euclid(32) as u32, row.rem_euclid(32) as u32);
                    assert_eq!((texel.column, texel.row), at, "{dx} {dy} ({i}, {j})");
                    if !on_diagonal(i, j) {
                        assert_eq!(seen.robust[k], want, "{dx} {dy} ({i}, {j})");
                    }
                }
            }
        }
    }

    /// A floor seen 84 degrees off its normal: twice a 64 x 64 texture across 2 world units,
    /// its texels from several pixels near the eye to a fraction of one far away. Each pixel's
    /// texel is that of the point where its ray meets the floor's plane, computed here
    /// independently (the ray from `docs/host.md`'s camera, the plane's own `(u, v)`).
    #[test]
    fn an_oblique_floor_shows_the_texels_of_its_plane() {
        let mesh = textured_floor(1.0, 2.0);
        let texture = &mesh.textures[0];
        assert_eq!((texture.width(), texture.height()), (64, 64));
        let s = Shot::new(
            DVec3::new(0.2, 0.15, 1.2),
            DVec3::new(0.0, 0.0, -0.3),
            96,
            64,
        );
        let forward = (s.target - s.eye).normalize();
        let angle = forward.dot(DVec3::Y).abs().acos().to_degrees();
        assert!(
            (70.0..85.0).contains(&angle),
            "{angle} degrees off the normal"
        );
        let right = forward.cross(s.up).normalize();
        let up = right.cross(forward);
        let fpx = 32.0 / (s.fov_y_deg.to_radians() / 2.0).tan();
        // The floor's texel coordinates (`u * 64`, `(1 - v) * 64`) where the ray through the
        // screen point `(x, y)` meets its plane: `(u, v)` is 0 at x = -1, z = 1, and 2 at
        // x = 1, z = -1.
        let texel_at = |x: f64, y: f64| {
            let d = forward + (x - 48.0) / fpx * right - (y - 32.0) / fpx * up;
            let p = s.eye + d * (-s.eye.y / d.y);
            let (u, v) = (p.x + 1.0, 1.0 - p.z);
            (DVec2::new(u * 64.0, (1.0 - v) * 64.0), p, d.y < 0.0)
        };
        let seen = texels(&mesh, &s, 0.01);
        let (mut robust, mut sizes) = (0, Vec::new());
        for j in 0..64 {
            for i in 0..96 {
                let k = j * 96 + i;
                let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
                let (t, p, below) = texel_at(x, y);
                if !(below && p.x.abs() < 1.0 && p.z.abs() < 1.0) {
                    let rim = (p.x.abs() - 1.0).abs() < 0.02 || (p.z.abs() - 1.0).abs() < 0.02;
                    assert!(below && rim || seen.texels[k].is_none(), "({i}, {j}) {p}");
                    continue;
                }
                let on_boundary = |c: f64| (c - c.round()).abs() < 1e-6;
                if on_boundary(t.x) || on_boundary(t.y) {
                    continue;
                }
                let want = t
                    .floor()
                    .as_i64vec2()
                    .to_array()
                    .map(|c| c.rem_euclid(64) as u32);
                let texel = seen.texels[k].expect("on the floor");
                assert_eq!([texel.column, texel.row], want, "({i}, {j})");
                if seen.robust[k] {
                    robust += 1;
                    let across = (texel_at(x + 1.0, y).0 - t).abs();
                    let down = (texel_at(x, y + 1.0).0 - t).abs();
                    sizes.push(across.max(down).max_element());
                }
            }
        }
        // Near the eye a texel spans pixels; far off, a pixel spans texels.
        assert!(robust > 500, "{robust} robust pixels");
        let (small, large) = (sizes.iter()).fold((f64::INFINITY, 0.0f64), |(lo, hi), &t| {
            (lo.min(t), hi.max(t))
        });
        assert!(
            small < 0.5 && large > 1.0,
            "{small} .. {large} texels a pixel"
        );
    }

    /// RGB565 expands by `c * 255 / 31` (`/ 63`) rounded; a texel's colour is that times its
    /// triangle's, rounded; an untextured triangle shows its own colour.
    #[test]
    fn texel_colours_are_expanded_and_multiplied_by_the_colour() {
        assert_eq!(rgb888(0xFFFF), [255; 3]);
        assert_eq!(rgb888(0), [0; 3]);
        // 16 * 255 / 31 = 131.6, 32 * 255 / 63 = 129.5 (up), 1 * 255 / 31 = 8.2.
        assert_eq!(rgb888(rgb565(16, 32, 1)), [132, 130, 8]);
        assert_eq!(rgb888(rgb565(15, 31, 30)), [123, 125, 247]);
        // 130 * 100 / 255 = 50.98, 8 * 40 / 255 = 1.25, 247 * 40 / 255 = 38.7.
        assert_eq!(modulate([255, 130, 8], [200, 100, 40]), [200, 51, 1]);
        assert_eq!(modulate([123, 125, 247], [255; 3]), [123, 125, 247]);
        let kd = [200, 100, 40];
        let mut mesh = facing_quad(DVec2::ZERO, DVec2::ONE, numbered_texture(4, 3));
        for t in &mut mesh.triangles {
            t.colour = kd;
        }
        mesh.triangles[1].texture = None;
        let seen = texels(&mesh, &shot(), 0.01);
        let colours = seen.colours(&mesh);
        let texture = &mesh.textures[0];
        // Pixel (40, 40) is on triangle 0, texel (12, 6); (20, 20) on the untextured one.
        let k = 40 * SIDE as usize + 40;
        assert_eq!(
            seen.texels[k].map(|t| (t.id, t.column, t.row)),
            Some((0, 12, 6))
        );
        assert_eq!(colours[k], Some(modulate(rgb888(texture.texel(12, 6)), kd)));
        let k = 20 * SIDE as usize + 20;
        assert_eq!(
            (seen.ids[k], seen.texels[k], colours[k]),
            (2, None, Some(kd))
        );
        assert_eq!(colours[0], None, "the background");
    }

    /// A step wraps on a repeating axis and stops at the edge on a clamping one.
    #[test]
    fn neighbours_wrap_or_clamp() {
        let hit = TexelHit {
            id: 0,
            texture: 0,
            column: 0,
            row: 7,
        };
        let repeat = numbered_texture(3, 3);
        let at = |t: &Texture, dc, dr| {
            let n = hit.step(t, dc, dr);
            (n.column, n.row)
        };
        assert_eq!(at(&repeat, -1, 1), (7, 0));
        assert_eq!(at(&repeat, 2, -3), (2, 4));
        let clamped = Texture {
            clamp: [true, false],
            ..repeat.clone()
        };
        assert_eq!(at(&clamped, -1, 1), (0, 0));
        let clamped = Texture {
            clamp: [false, true],
            ..repeat
        };
        assert_eq!(at(&clamped, -1, 1), (7, 7));
    }
}
