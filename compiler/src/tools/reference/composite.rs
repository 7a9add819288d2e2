//! Transparent surfaces composited in exact depth order: along the ray through each pixel
//! centre, every surface hit at camera depth `>= near`, sorted front to back, `s_1, s_2, ...`,
//! each of colour `c_i` (that of the side seen, unrounded 8-bit units) and alpha
//! `a_i = opacity_i / 255` (1 for an opaque surface, opacity [`OPAQUE`]). A pixel is
//! `sum_i (prod_{j<i} (1 - a_j)) a_i c_i`, up to the first opaque surface; if the ray meets
//! none, plus `(prod_j (1 - a_j))` times the background. The runtime composites by this
//! definition; [`composite`] is its reference, as [`reference()`](super::reference) is for
//! opaque scenes.

use glam::DVec3;
use rayon::prelude::*;

use super::{mark_polygon_edges, ray_triangle, screen_bbox, Lens, Lighting, EDGE_MARGIN};
use crate::shade::channel;
use crate::shade::corners::Facing;
use crate::tools::shot::Shot;

/// The opacity of an opaque surface (alpha 1).
pub const OPAQUE: u8 = 255;

/// A pixel is not robust where two surfaces along its ray are this close in depth, relative
/// to the depth: their order is the rounding's.
const DEPTH_TIE: f64 = 1e-9;

/// What [`composite`] sees, per pixel (row-major).
#[derive(Debug, Clone)]
pub struct Composited {
    /// The composited colour in 8-bit units, unrounded.
    pub colours: Vec<[f64; 3]>,
    /// True where the pixel's centre and the four points 1/16 pixel from it (`x ± 1/16`,
    /// `y ± 1/16`) cross the same triangles in the same depth order (up to the first opaque
    /// one), no two of them at the same depth, and the centre is farther than [`EDGE_MARGIN`]
    /// from every projected edge of the triangles and of the extra polygons.
    pub robust: Vec<bool>,
    /// How many transparent surfaces the centre's ray crosses before its first opaque one
    /// (all it crosses when it meets none).
    pub transparent: Vec<u32>,
}

impl Composited {
    /// The colours rounded to 8 bits, as a picture shows them.
    pub fn pixels(&self) -> Vec<[u8; 3]> {
        self.colours.iter().map(|c| c.map(channel)).collect()
    }

    /// How many robust pixels of `picture` (row-major, the same size) differ from these
    /// colours by more than `tolerance` (8-bit units) in some channel.
    pub fn wrong_pixels(&self, picture: &[[u8; 3]], tolerance: f64) -> usize {
        assert_eq!(
            picture.len(),
            self.colours.len(),
            "a picture of the same size"
        );
        (picture.iter().zip(&self.colours).zip(&self.robust))
            .filter(|&((p, c), &robust)| {
                robust && (0..3).any(|k| (f64::from(p[k]) - c[k]).abs() > tolerance)
            })
            .count()
    }
}

/// One surface a ray crosses: the triangle, the side seen, the camera depth.
#[derive(Debug, Clone, Copy)]
struct Layer {
    id: usize,
    front: bool,
    depth: f64,
}

/// Composite, per pixel centre of `shot`, every one of `triangles` (the source triangles: ids
/// are indices) its ray crosses at camera depth `>= near`, front to back as the module says:
/// triangle `id` seen from its front (`front`, as [`Reference::front`](super::Reference::front))
/// has colour `colour(id, front)` (8-bit units, unrounded) and alpha `opacity[id] / 255`;
/// `background` shows through where the ray meets no opaque surface. Marks as not robust the
/// pixels whose neighbourhood crosses other surfaces or in another order, and those near the
/// projected edges of `triangles` and of `extra_polygons` (e.g. the compiled polygons), as
/// [`reference()`](super::reference) marks them.
///
/// # Panics
///
/// If `opacity` does not have one entry a triangle.
pub fn composite(
    triangles: &[[DVec3; 3]],
    extra_polygons: &[Vec<DVec3>],
    shot: &Shot,
    near: f64,
    colour: impl Fn(usize, bool) -> [f64; 3] + Sync,
    opacity: &[u8],
    background: [u8; 3],
) -> Composited {
    let colour = |id, front, _| colour(id, front);
    cast(
        triangles,
        extra_polygons,
        shot,
        near,
        colour,
        opacity,
        background,
    )
}

/// [`composite`] with the colour of each surface the compiler's shading gives the side seen at
/// the point the ray crosses it, as [`Reference::colours_exact`](super::Reference::colours_exact)
/// lights an opaque one (no shadows): `kd[id]` times the intensity of `lighting`.
///
/// # Panics
///
/// If `opacity` or `kd` does not have one entry a triangle.
#[allow(clippy::too_many_arguments)]
pub fn composite_lit(
    triangles: &[[DVec3; 3]],
    extra_polygons: &[Vec<DVec3>],
    shot: &Shot,
    near: f64,
    kd: &[[u8; 3]],
    lighting: Lighting<'_>,
    opacity: &[u8],
    background: [u8; 3],
) -> Composited {
    assert_eq!(kd.len(), triangles.len(), "one colour a triangle");
    let colour = |id: usize, front: bool, p: DVec3| {
        let intensity = match lighting {
            Lighting::Faceted(shading) => {
                let [a, b, c] = triangles[id];
                let n = (b - a).cross(c - a).normalize_or_zero();
                shading.intensity_at(if front { n } else { -n }, p)
            }
            Lighting::Smooth(shades) => shades.triangles[id].intensity_at(Facing::of(front), p),
        };
        kd[id].map(|c| f64::from(c) * intensity)
    };
    cast(
        triangles,
        extra_polygons,
        shot,
        near,
        colour,
        opacity,
        background,
    )
}

/// [`composite`] with `colour(id, front, point hit)`.
fn cast(
    triangles: &[[DVec3; 3]],
    extra_polygons: &[Vec<DVec3>],
    shot: &Shot,
    near: f64,
    colour: impl Fn(usize, bool, DVec3) -> [f64; 3] + Sync,
    opacity: &[u8],
    background: [u8; 3],
) -> Composited {
    assert_eq!(opacity.len(), triangles.len(), "one opacity a triangle");
    let cam = &Lens::new(shot, near);
    let (w, h) = (cam.width as usize, cam.height as usize);
    let boxes: Vec<Option<(usize, usize, usize, usize)>> = triangles
        .iter()
        .map(|t| screen_bbox(cam, &t.map(|p| cam.to_camera(p))))
        .collect();
    let normals: Vec<DVec3> = (triangles.iter())
        .map(|t| (t[1] - t[0]).cross(t[2] - t[0]))
        .collect();
    let crossings = |candidates: &[usize], x: f64, y: f64| {
        let dir = cam.ray_at(x, y);
        let mut hits: Vec<Layer> = (candidates.iter())
            .filter_map(|&id| {
                // dir has unit component along f, so the ray parameter is the camera depth.
                let depth = ray_triangle(cam.eye, dir, &triangles[id])?;
                (depth >= cam.near).then(|| Layer {
                    id,
                    front: dir.dot(normals[id]) < 0.0,
                    depth,
                })
            })
            .collect();
        hits.sort_by(|a, b| a.depth.total_cmp(&b.depth).then(a.id.cmp(&b.id)));
        if let Some(k) = hits.iter().position(|l| opacity[l.id] == OPAQUE) {
            hits.truncate(k + 1);
        }
        (dir, hits)
    };
    let background = background.map(f64::from);
    let offsets = [
        (EDGE_MARGIN, 0.0),
        (-EDGE_MARGIN, 0.0),
        (0.0, EDGE_MARGIN),
        (0.0, -EDGE_MARGIN),
    ];
    let rows: Vec<Vec<([f64; 3], bool, u32)>> = (0..h)
        .into_par_iter()
        .map(|j| {
            let in_row: Vec<usize> = (boxes.iter().enumerate())
                .filter(|(_, b)| b.is_some_and(|b| (b.2..b.3).contains(&j)))
                .map(|(id, _)| id)
                .collect();
            let mut here = Vec::new();
            (0..w)
                .map(|i| {
                    here.clear();
                    here.extend(
                        in_row
                            .iter()
                            .copied()
                            .filter(|&id| boxes[id].is_some_and(|b| (b.0..b.1).contains(&i))),
                    );
                    let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
                    let (dir, layers) = crossings(&here, x, y);
                    let tie = layers
                        .windows(2)
                        .any(|p| p[1].depth - p[0].depth <= DEPTH_TIE * p[1].depth);
                    let same = |(dx, dy): (f64, f64)| {
                        let (_, other) = crossings(&here, x + dx, y + dy);
                        other.iter().map(|l| l.id).eq(layers.iter().map(|l| l.id))
                    };
                    let robust = !tie && offsets.into_iter().all(same);
                    let (mut sum, mut through) = ([0.0; 3], 1.0);
                    let mut transparent = 0;
                    for l in &layers {
                        let a = f64::from(opacity[l.id]) / 255.0;
                        let c = colour(l.id, l.front, cam.eye + dir * l.depth);
                        for (s, c) in sum.iter_mut().zip(c) {
                            *s += through * a * c;
                        }
                        through *= 1.0 - a;
                        transparent += u32::from(opacity[l.id] != OPAQUE);
                    }
                    if layers.last().is_none_or(|l| opacity[l.id] != OPAQUE) {
                        for (s, b) in sum.iter_mut().zip(background) {
                            *s += through * b;
                        }
                    }
                    (sum, robust, transparent)
                })
                .collect()
        })
        .collect();
    let mut out = Composited {
        colours: Vec::with_capacity(w * h),
        robust: Vec::with_capacity(w * h),
        transparent: Vec::with_capacity(w * h),
    };
    for (c, robust, transparent) in rows.into_iter().flatten() {
        out.colours.push(c);
        out.robust.push(robust);
        out.transparent.push(transparent);
    }
    let outlines = (triangles.iter().map(|t| t.to_vec())).chain(extra_polygons.iter().cloned());
    for p in outlines {
        let c: Vec<DVec3> = p.iter().map(|&q| cam.to_camera(q)).collect();
        mark_polygon_edges(cam, &c, &mut out.robust);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shade::Shading;

    const NEAR: f64 = 0.01;
    const W: u32 = 33;

    fn shot() -> Shot {
        Shot::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, W, W)
    }

    /// The square `[x0, x1] x [y0, y1]` at depth `z(x, y)`, counter-clockwise seen from +z.
    fn pane(x0: f64, y0: f64, x1: f64, y1: f64, z: impl Fn(f64, f64) -> f64) -> [[DVec3; 3]; 2] {
        let p = |x: f64, y: f64| DVec3::new(x, y, z(x, y));
        [
            [p(x0, y0), p(x1, y0), p(x1, y1)],
            [p(x0, y0), p(x1, y1), p(x0, y1)],
        ]
    }

    /// The pixel `(i, j)`'s index.
    fn at(i: u32, j: u32) -> usize {
        (j * W + i) as usize
    }

    /// `over` composited over `under`, each `(colour, opacity)`, over `background`.
    fn over(layers: &[([f64; 3], u8)], background: [u8; 3]) -> [f64; 3] {
        let (mut sum, mut through) = ([0.0; 3], 1.0);
        for &(c, o) in layers {
            let a = f64::from(o) / 255.0;
            for k in 0..3 {
                sum[k] += through * a * c[k];
            }
            through *= 1.0 - a;
        }
        for k in 0..3 {
            sum[k] += through * f64::from(background[k]);
        }
        sum
    }

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() < 1e-9)
    }

    const RED: [f64; 3] = [200.0, 30.0, 10.0];
    const BLUE: [f64; 3] = [20.0, 60.0, 220.0];
    const BACK: [u8; 3] = [10, 20, 30];

    /// Two overlapping panes, squares 0 (left, lower) and 1 (right, upper), at depths `z0` and
    /// `z1`: red at opacity 102 and blue at 153.
    fn two_panes(z0: f64, z1: f64) -> (Vec<[DVec3; 3]>, [u8; 4]) {
        let a = pane(-1.2, -1.2, 0.4, 0.4, |_, _| z0);
        let b = pane(-0.4, -0.4, 1.2, 1.2, |_, _| z1);
        ([a, b].as_flattened().to_vec(), [102, 102, 153, 153])
    }

    fn colours(id: usize, _: bool) -> [f64; 3] {
        if id < 2 {
            RED
        } else {
            BLUE
        }
    }

    /// Pixels in the overlap, in the red square alone, in the blue alone, and outside both
    /// (all away from edges).
    const OVERLAP: (u32, u32) = (17, 17);
    const RED_ONLY: (u32, u32) = (10, 20);
    const BLUE_ONLY: (u32, u32) = (22, 12);
    const OUTSIDE: (u32, u32) = (1, 1);

    #[test]
    fn two_overlapping_panes_composite_analytically() {
        let (t, opacity) = two_panes(1.0, 0.0);
        let c = composite(&t, &[], &shot(), NEAR, colours, &opacity, BACK);
        let (red, blue) = ((RED, opacity[0]), (BLUE, opacity[2]));
        for ((i, j), layers) in [
            (OVERLAP, vec![red, blue]),
            (RED_ONLY, vec![red]),
            (BLUE_ONLY, vec![blue]),
            (OUTSIDE, vec![]),
        ] {
            let k = at(i, j);
            assert!(c.robust[k], "({i}, {j})");
            assert_eq!(c.transparent[k] as usize, layers.len(), "({i}, {j})");
            let want = over(&layers, BACK);
            assert!(
                close(c.colours[k], want),
                "({i}, {j}): {:?} {want:?}",
                c.colours[k]
            );
        }
        let pixels = c.pixels();
        assert_eq!(pixels[at(OUTSIDE.0, OUTSIDE.1)], BACK);
    }

    #[test]
    fn the_order_in_depth_matters() {
        let (front_red, opacity) = two_panes(1.0, 0.0);
        let (front_blue, _) = two_panes(0.0, 1.0);
        let s = shot();
        let a = composite(&front_red, &[], &s, NEAR, colours, &opacity, BACK);
        let b = composite(&front_blue, &[], &s, NEAR, colours, &opacity, BACK);
        let k = at(OVERLAP.0, OVERLAP.1);
        let (red, blue) = ((RED, opacity[0]), (BLUE, opacity[2]));
        assert!(a.robust[k] && b.robust[k]);
        assert!(close(a.colours[k], over(&[red, blue], BACK)));
        assert!(close(b.colours[k], over(&[blue, red], BACK)));
        assert!((0..3).any(|c| (a.colours[k][c] - b.colours[k][c]).abs() > 10.0));
    }

    #[test]
    fn an_opaque_triangle_in_front_hides_everything() {
        let (mut t, opacity) = two_panes(1.0, 0.0);
        t.extend(pane(-2.0, -2.0, 2.0, 2.0, |_, _| 2.0));
        let mut opacity = opacity.to_vec();
        opacity.extend([OPAQUE; 2]);
        let green = [30.0, 180.0, 40.0];
        let colour = |id: usize, front: bool| if id >= 4 { green } else { colours(id, front) };
        let c = composite(&t, &[], &shot(), NEAR, colour, &opacity, BACK);
        for (i, j) in [OVERLAP, RED_ONLY, BLUE_ONLY] {
            let k = at(i, j);
            assert_eq!(c.colours[k], green, "({i}, {j})");
            assert_eq!(c.transparent[k], 0);
            assert!(c.robust[k]);
        }
        // An opaque pane behind the others shows through them, the background not at all.
        let mut t = two_panes(1.0, 0.0).0;
        t.extend(pane(-2.0, -2.0, 2.0, 2.0, |_, _| -1.0));
        let c = composite(&t, &[], &shot(), NEAR, colour, &opacity, [255; 3]);
        let k = at(OVERLAP.0, OVERLAP.1);
        let want = over(&[(RED, 102), (BLUE, 153), (green, OPAQUE)], [0; 3]);
        assert!(close(c.colours[k], want), "{:?} {want:?}", c.colours[k]);
        assert_eq!(c.transparent[k], 2);
    }

    /// Two panes crossing along `x = 0`, which projects onto the middle of pixel column 16:
    /// there the order changes within 1/16 pixel, so that column is not robust; a few columns
    /// away it is, and each side has its own order.
    #[test]
    fn a_crossing_of_two_panes_is_not_robust() {
        let flat = pane(-1.0, -1.0, 1.0, 1.0, |_, _| 0.0);
        let tilted = pane(-1.0, -1.0, 1.0, 1.0, |x, _| 0.6 * x);
        let t = [flat, tilted].as_flattened().to_vec();
        let opacity = [120; 4];
        let c = composite(&t, &[], &shot(), NEAR, colours, &opacity, BACK);
        // Rows 12 and 20 avoid the squares' diagonals near the columns looked at.
        for j in [12, 20] {
            assert!(!c.robust[at(16, j)], "row {j}");
            let (left, right) = (at(13, j), at(19, j));
            assert!(c.robust[left] && c.robust[right], "row {j}");
            let (red, blue) = ((RED, 120), (BLUE, 120));
            assert!(close(c.colours[left], over(&[red, blue], BACK)));
            assert!(close(c.colours[right], over(&[blue, red], BACK)));
        }
    }

    /// Lit: each surface takes the colour the shading gives its side at the point crossed.
    #[test]
    fn lit_surfaces_take_their_shading() {
        let (t, opacity) = two_panes(1.0, 0.0);
        let kd = [[200, 30, 10], [200, 30, 10], [20, 60, 220], [20, 60, 220]];
        let sun = Shading::Lambert(DVec3::new(0.0, 0.6, 0.8));
        let s = shot();
        let c = composite_lit(
            &t,
            &[],
            &s,
            NEAR,
            &kd,
            Lighting::Faceted(sun),
            &opacity,
            BACK,
        );
        let lit = |kd: [u8; 3]| kd.map(|v| f64::from(v) * sun.intensity_at(DVec3::Z, DVec3::ZERO));
        let k = at(OVERLAP.0, OVERLAP.1);
        let want = over(&[(lit(kd[0]), 102), (lit(kd[2]), 153)], BACK);
        assert!(close(c.colours[k], want), "{:?} {want:?}", c.colours[k]);
        let flat = composite(&t, &[], &s, NEAR, colours, &opacity, BACK);
        assert!(!close(c.colours[k], flat.colours[k]));
    }
}
