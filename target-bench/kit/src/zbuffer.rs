//! The z-buffer baseline as firmware would write it: the source triangles of a [`Mesh`], each
//! transformed, clipped, projected, snapped and filled exactly as Peel's renderer does its
//! polygons (the runtime's [`LocalView`], [`clip_polygon`], [`snap`] and
//! [`fill_polygon_rows`], top-left rule included), into an RGB565 framebuffer with a **16-bit depth buffer**: per pixel the
//! interpolated `1/z` wins when nearer (larger), ties going to the triangle drawn first.
//!
//! Depth is `1/z` mapped linearly onto `1..=65535` over the scene's depth range in this view
//! (its box in camera space, as a GPU's near and far planes would be fitted), 0 meaning empty.
//! Each triangle's depth is a plane `a x + b y + c` over the screen in fixed point
//! ([`FRACTION`] bits), set up once per triangle in `f32` and stepped with one integer add per
//! pixel, in 32 bits whenever a span's values allow (always, in practice).
//!
//! Everything is `f32`, integer or the runtime's code, so the host (the runner's reference
//! pixels) and both Cortex-M cores compute the same bits.

use glam::Vec3;
use peel_runtime::camera::LocalView;
use peel_runtime::clip::{clip_polygon, Frustum, CLIP_PLANES};
use peel_runtime::display::{Colour, SpanSink};
use peel_runtime::fill::{coordinate_limit, fill_polygon_rows, SubpixelPoint, SUBPIXEL_BITS};
use peel_runtime::render::snap;
use peel_runtime::RenderError;

use crate::mesh::Mesh;

/// Fractional bits of the depth planes: a depth of 65535 with one more bit for the doubled
/// coordinates fits in 30 bits.
pub const FRACTION: u32 = 13;
/// A clipped triangle's most vertices.
pub(crate) const CLIPPED: usize = 3 + CLIP_PLANES;
/// Bound on a plane coefficient in fixed point: only a triangle seen nearly edge-on comes
/// close, and every product below then still fits an `i64`.
const LIMIT: i64 = 1 << 40;

/// Why a frame was not drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ZError {
    /// The colour or depth buffer holds fewer than `needed` pixels.
    Buffer {
        /// Pixels of the image.
        needed: usize,
    },
    /// The view is unusable or the image too large (as the renderer would say).
    Render(RenderError),
    /// A list of the scanline z-buffer ([`crate::scanline::Lists`]) is too small.
    Full(crate::scanline::List),
}

impl From<RenderError> for ZError {
    fn from(e: RenderError) -> Self {
        ZError::Render(e)
    }
}

impl core::fmt::Display for ZError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ZError::Buffer { needed } => write!(f, "z-buffer memory under {needed} pixels"),
            ZError::Render(e) => write!(f, "{e}"),
            ZError::Full(list) => write!(f, "the {list} is full"),
        }
    }
}

/// The linear map from `1/z` to depth values for one view.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DepthRange {
    inv_far: f32,
    scale: f32,
}

impl DepthRange {
    /// The range of the box `lo..hi` (the scene's bounds) seen by `view`.
    pub(crate) fn new(view: &LocalView, lo: Vec3, hi: Vec3) -> DepthRange {
        let b = view.box_to_camera(lo, hi);
        let near = (b.centre.z - b.extent.z - b.error).max(view.near);
        let far = b.centre.z + b.extent.z + b.error;
        // A flat scene facing the eye, or NaN: any range that keeps the map finite.
        let far = if far > near { far } else { near * 2.0 };
        let inv_far = 1.0 / far;
        DepthRange {
            inv_far,
            scale: 65534.0 / (1.0 / near - inv_far),
        }
    }

    /// The depth plane of the camera-space polygon `camera` (`1 + (1/z - 1/far) * scale` at
    /// a screen point) in fixed point, or `None` when its plane passes through the eye.
    pub(crate) fn plane(&self, camera: &[Vec3], view: &LocalView) -> Option<[i64; 3]> {
        let p0 = *camera.first()?;
        let mut n = Vec3::ZERO;
        for w in camera.get(1..)?.windows(2) {
            n += (w[0] - p0).cross(w[1] - p0);
        }
        let d = n.dot(p0);
        if d == 0.0 || !d.is_finite() {
            return None;
        }
        // The ray through (x, y) is ((x - cx)/fx, -(y - cy)/fy, 1); it meets the plane at
        // zc = d / (n . ray), so 1/zc = (n . ray) / d, linear in x and y.
        let a = n.x / (view.fx * d);
        let b = -n.y / (view.fy * d);
        let c = (n.z - n.x * view.cx / view.fx + n.y * view.cy / view.fy) / d;
        let fixed = |v: f32| {
            let scaled = libm::roundf(v * (1u32 << FRACTION) as f32);
            // `as` saturates (NaN to 0).
            (scaled as i64).clamp(-LIMIT, LIMIT)
        };
        Some([
            fixed(a * self.scale),
            fixed(b * self.scale),
            fixed((c - self.inv_far) * self.scale + 1.0),
        ])
    }
}

/// One polygon's spans, depth-tested into the rows `first_row..` held by `colour` and
/// `depth` (`width` pixels a row).
pub(crate) struct DepthSink<'f> {
    pub(crate) colour: &'f mut [u16],
    pub(crate) depth: &'f mut [u16],
    pub(crate) width: usize,
    pub(crate) first_row: u32,
    pub(crate) plane: [i64; 3],
    pub(crate) rgb: u16,
}

impl SpanSink for DepthSink<'_> {
    #[inline]
    fn span(&mut self, y: u32, x0: u32, x1: u32, _: Colour) {
        let [a, b, c] = self.plane;
        let row = y.wrapping_sub(self.first_row) as usize * self.width;
        let (first, past) = (row + x0 as usize, row + x1 as usize);
        let (Some(colours), Some(depths)) = (
            self.colour.get_mut(first..past),
            self.depth.get_mut(first..past),
        ) else {
            return;
        };
        // Doubled coordinates put pixel centres on integers: the value at pixel x is
        // (a (2x + 1) + b (2y + 1) + 2c) / 2, with FRACTION fractional bits.
        let start = a * i64::from(2 * x0 + 1) + b * i64::from(2 * y + 1) + 2 * c;
        let step = 2 * a;
        let end = start + step * i64::from(x1 - x0 - 1);
        let rgb = self.rgb;
        let cells = colours.iter_mut().zip(depths.iter_mut());
        const FAST: i64 = 1 << 30;
        if start.abs() < FAST && end.abs() < FAST {
            // Every value lies between the ends; `step` fits whenever there are two pixels.
            let (mut v, step) = (start as i32, step as i32);
            for (c, d) in cells {
                let z = (v >> (FRACTION + 1)).clamp(1, 65535) as u16;
                if z > *d {
                    *d = z;
                    *c = rgb;
                }
                v = v.wrapping_add(step);
            }
        } else {
            let mut v = start;
            for (c, d) in cells {
                let z = (v >> (FRACTION + 1)).clamp(1, 65535) as u16;
                if z > *d {
                    *d = z;
                    *c = rgb;
                }
                v += step;
            }
        }
    }
}

/// Draw `mesh` seen by `view` into `colour` (RGB565, cleared to `background` first) with the
/// depth buffer `depth` (cleared to empty first), both `view.width x view.height`, packed.
///
/// # Errors
/// [`ZError`] for a buffer too small, an unusable view or an image too large for the fill;
/// nothing is drawn then.
pub fn draw(
    mesh: &Mesh<'_>,
    view: &LocalView,
    background: u16,
    colour: &mut [u16],
    depth: &mut [u16],
) -> Result<(), ZError> {
    draw_rows(mesh, view, background, 0..view.height, colour, depth)
}

/// [`draw`] of the rows `rows` only (a band: the tiled z-buffer submits the whole mesh once per
/// band), into `colour` and `depth` of `view.width x rows.len()` pixels: the band's pixels of
/// the whole frame, bit for bit (the same triangles in the same order, the fill's own spans on
/// those rows, the same depths).
///
/// # Errors
/// As [`draw`]; also [`ZError::Buffer`] for rows outside the image.
pub fn draw_rows(
    mesh: &Mesh<'_>,
    view: &LocalView,
    background: u16,
    rows: core::ops::Range<u32>,
    colour: &mut [u16],
    depth: &mut [u16],
) -> Result<(), ZError> {
    const SUB: u32 = SUBPIXEL_BITS;
    let prepared = Prepared::new(mesh, view)?;
    let width = view.width;
    let band_rows = rows.end.saturating_sub(rows.start);
    let needed = width as usize * band_rows as usize;
    let (Some(colour), Some(depth)) = (colour.get_mut(..needed), depth.get_mut(..needed)) else {
        return Err(ZError::Buffer { needed });
    };
    if rows.end > view.height || band_rows == 0 {
        return Err(ZError::Buffer { needed });
    }
    colour.fill(background);
    depth.fill(0);
    let whole = rows.start == 0 && rows.end == view.height;
    // The band in fixed point.
    let band = (!whole).then_some(((rows.start as i32) << SUB, (rows.end as i32) << SUB));
    let mut work = Clipped::default();
    for t in 0..mesh.triangle_count() {
        let Some(Projected { points, plane, rgb }) =
            prepared.triangle(mesh, view, t, band, &mut work)?
        else {
            continue;
        };
        let mut sink = DepthSink {
            colour: &mut *colour,
            depth: &mut *depth,
            width: width as usize,
            first_row: rows.start,
            plane,
            rgb,
        };
        // At most CLIPPED points, all snapped into the window checked above: cannot fail.
        let _ = fill_polygon_rows(points, width, rows.clone(), Colour::default(), &mut sink);
    }
    Ok(())
}

/// A triangle ready to fill: its screen points, depth plane and colour.
pub(crate) struct Projected<'w> {
    pub(crate) points: &'w [SubpixelPoint],
    pub(crate) plane: [i64; 3],
    pub(crate) rgb: u16,
}

/// A triangle's working memory: camera-space corners and their clipped polygon, and its
/// snapped screen points.
#[derive(Default)]
pub(crate) struct Clipped {
    a: [Vec3; CLIPPED],
    b: [Vec3; CLIPPED],
    points: [SubpixelPoint; CLIPPED],
}

/// What every triangle of one frame shares: the view's frustum, whether the scene needs
/// clipping, its depth range and the window in fixed point.
pub(crate) struct Prepared {
    frustum: Frustum,
    inside: bool,
    range: DepthRange,
    max_x: i32,
    max_y: i32,
}

impl Prepared {
    /// Check `view` and set up its frame over `mesh`.
    pub(crate) fn new(mesh: &Mesh<'_>, view: &LocalView) -> Result<Prepared, ZError> {
        const SUB: u32 = SUBPIXEL_BITS;
        view.check()?;
        let (width, height) = (view.width, view.height);
        let too_large = RenderError::ImageTooLarge { width, height };
        let fixed = |v: u32| {
            i32::try_from(v)
                .ok()
                .and_then(|v| v.checked_mul(1 << SUB))
                .filter(|&v| v <= coordinate_limit::<SUB>())
                .ok_or(too_large)
        };
        let (max_x, max_y) = (fixed(width)?, fixed(height)?);
        let frustum = Frustum::new(view);
        let (lo, hi) = mesh.bounds();
        Ok(Prepared {
            // As the renderer does: a scene wholly inside the frustum needs no clipping.
            inside: frustum.contains_box(view, lo, hi),
            frustum,
            range: DepthRange::new(view, lo, hi),
            max_x,
            max_y,
        })
    }

    /// Whether no triangle needs clipping in this view.
    pub(crate) fn inside(&self) -> bool {
        self.inside
    }

    /// Triangle `t` transformed, clipped, snapped and given its depth plane (in `work`): its
    /// screen points, depth plane and colour, or `None` when it draws nothing, or nothing in
    /// the band `band` (rows `top..bottom` in fixed point; the plane is then not computed).
    #[inline]
    pub(crate) fn triangle<'w>(
        &self,
        mesh: &Mesh<'_>,
        view: &LocalView,
        t: u32,
        band: Option<(i32, i32)>,
        work: &'w mut Clipped,
    ) -> Result<Option<Projected<'w>>, ZError> {
        let (corners, rgb) = mesh.triangle(t);
        for (slot, &i) in work.a.iter_mut().zip(&corners) {
            *slot = view.to_camera(mesh.vertex(i));
        }
        let clipped: &[Vec3] = if self.inside {
            &work.a[..3]
        } else {
            clip_polygon(self.frustum.planes(), 3, &mut work.a, &mut work.b)?
        };
        if clipped.len() < 3 {
            return Ok(None);
        }
        let mut count = 0;
        for (slot, &c) in work.points.iter_mut().zip(clipped) {
            *slot = snap::<SUBPIXEL_BITS>(view.project(c), self.max_x, self.max_y);
            count += 1;
        }
        if let Some((top, bottom)) = band {
            // Wholly above or below the band: no row centre of it inside.
            let (lo, hi) = work.points[..count]
                .iter()
                .fold((i32::MAX, i32::MIN), |(lo, hi), p| {
                    (lo.min(p.y), hi.max(p.y))
                });
            if hi < top || lo > bottom {
                return Ok(None);
            }
        }
        let Some(plane) = self.range.plane(clipped, view) else {
            return Ok(None);
        };
        Ok(Some(Projected {
            points: &work.points[..count],
            plane,
            rgb,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::encode;
    use peel_runtime::camera::{Camera, Orbit};
    use std::vec;

    /// Two overlapping squares facing +z, the front one (z = 0.5) red and drawn second, the
    /// back one (z = -0.5) blue; the bounds are the unit cube.
    fn two_squares(front_first: bool) -> std::vec::Vec<u8> {
        let mut vertices = vec![];
        let mut tris = vec![];
        let mut square = |z: f32, size: f32, rgb: u16| {
            let base = vertices.len() as u32;
            for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                vertices.push(Vec3::new(x * size, y * size, z));
            }
            tris.push(([base, base + 1, base + 2], rgb));
            tris.push(([base, base + 2, base + 3], rgb));
        };
        if front_first {
            square(0.5, 0.5, 0xf800);
            square(-0.5, 1.0, 0x001f);
        } else {
            square(-0.5, 1.0, 0x001f);
            square(0.5, 0.5, 0xf800);
        }
        let header = crate::mesh::test_header([0.0; 3], Vec3::splat(-1.0), Vec3::splat(1.0));
        encode(&header, &vertices, &tris).unwrap()
    }

    /// The 32x24 view of `mesh` from `azimuth` degrees, level.
    fn view(mesh: &Mesh<'_>, azimuth: f64) -> LocalView {
        let angles = crate::config::OrbitAngles {
            azimuth_deg: azimuth,
            elevation_deg: 0.0,
        };
        crate::orbit_view(&mesh.header(), angles, 60.0, 32, 24).unwrap()
    }

    fn frame(bytes: &[u8], azimuth: f64) -> std::vec::Vec<u16> {
        let mesh = Mesh::parse(bytes).unwrap();
        let (mut colour, mut depth) = (vec![0u16; 32 * 24], vec![0u16; 32 * 24]);
        draw(&mesh, &view(&mesh, azimuth), 7, &mut colour, &mut depth).unwrap();
        assert!(colour
            .iter()
            .zip(&depth)
            .all(|(&c, &d)| (c == 7) == (d == 0)));
        colour
    }

    #[test]
    fn nearest_wins_whatever_the_order() {
        let (a, b) = (
            frame(&two_squares(true), 0.0),
            frame(&two_squares(false), 0.0),
        );
        assert_eq!(a, b);
        // The centre shows the front square, a corner region the back one, and the border
        // the background.
        assert_eq!(a[12 * 32 + 16], 0xf800);
        assert!(a.contains(&0x001f));
        assert_eq!(a[0], 7);
        // Seen from behind, the blue square hides the red one.
        let back = frame(&two_squares(true), 180.0);
        assert!(!back.contains(&0xf800) && back.contains(&0x001f));
    }

    #[test]
    fn bands_are_the_frames_rows() {
        let bytes = two_squares(true);
        let mesh = Mesh::parse(&bytes).unwrap();
        for azimuth in [0.0, 30.0, 200.0] {
            let whole = frame(&bytes, azimuth);
            let view = view(&mesh, azimuth);
            for band in [1, 5, 7, 24] {
                let mut banded = vec![];
                let (mut colour, mut depth) = (vec![0u16; 32 * band], vec![0u16; 32 * band]);
                let mut first = 0;
                while first < 24 {
                    let rows = first..(first + band as u32).min(24);
                    draw_rows(&mesh, &view, 7, rows.clone(), &mut colour, &mut depth).unwrap();
                    banded.extend_from_slice(&colour[..32 * rows.len()]);
                    first = rows.end;
                }
                assert_eq!(banded, whole, "azimuth {azimuth}, bands of {band}");
            }
            let (mut colour, mut depth) = (vec![0u16; 64], vec![0u16; 64]);
            assert_eq!(
                draw_rows(&mesh, &view, 7, 20..25, &mut colour, &mut depth),
                Err(ZError::Buffer { needed: 160 })
            );
        }
    }

    #[test]
    fn refuses_small_buffers_and_large_images() {
        let bytes = two_squares(true);
        let mesh = Mesh::parse(&bytes).unwrap();
        let h = mesh.header();
        let pose = Orbit::default().pose(&h);
        let camera = Camera::look_at(pose, 60.0, 32, 24, 0.01).unwrap();
        let view = camera.view(h.centre);
        let mut small = vec![0u16; 10];
        let mut depth = vec![0u16; 32 * 24];
        assert_eq!(
            draw(&mesh, &view, 0, &mut small, &mut depth),
            Err(ZError::Buffer { needed: 32 * 24 })
        );
        let huge = LocalView {
            width: 1 << 24,
            ..view
        };
        assert!(matches!(
            draw(&mesh, &huge, 0, &mut small, &mut depth),
            Err(ZError::Render(RenderError::ImageTooLarge { .. }))
        ));
    }
}
