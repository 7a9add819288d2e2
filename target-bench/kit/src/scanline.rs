//! The scanline z-buffer of the hidden-surface survey: one row of depth and colour, each row
//! sent to the display when done, so there is no framebuffer. Its memory is lists that grow
//! with the scene instead.
//!
//! A frame has two passes. The first transforms, clips, snaps and gives a depth plane to every
//! triangle exactly as the full-frame z-buffer does ([`crate::zbuffer`]), keeps each one that
//! covers a row centre in the polygon table, and buckets it by its first row (a linked list
//! per row). The second goes down the rows: a polygon's edges enter the active edge list at
//! its first row, as the fill's own edge walks ([`EdgeWalk`]); on each row every active
//! polygon's crossings are sorted and paired into spans, depth-tested into the row, and the
//! walks stepped; finished edges leave the list. The spans are the fill's spans and the depths
//! the z-buffer's, so a frame is the full-frame z-buffer's frame but where two triangles tie in
//! depth (the z-buffer keeps the one drawn first; here the order is the list's).
//!
//! Memory ([`Lists`], from the caller): the projected vertices (8 bytes each; a scene that
//! needs clipping keeps its clipped polygons' points apart, in `extra`), the polygon table
//! (one [`Polygon`] per triangle that covers a row), a list head per row, the active edges and
//! one row of colour and depth. [`ScanStats`] reports what a frame used, so firmware can be
//! sized for a camera path.

use peel_runtime::camera::LocalView;
use peel_runtime::display::{Colour, SpanSink};
use peel_runtime::fill::{Coord, EdgeWalk, SubpixelPoint, SUBPIXEL_BITS};

use crate::mesh::Mesh;
use crate::zbuffer::{Clipped, DepthSink, Prepared, Projected, ZError, CLIPPED};

/// "No polygon" in a list link.
const NONE: u32 = u32::MAX;

/// One triangle that covers a row centre: its depth plane (as [`crate::zbuffer`] computes
/// it), colour, points and the next polygon starting on the same row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Polygon {
    plane: [i64; 3],
    /// The triangle, whose corners index [`Lists::vertices`] (`count == 0`), or the first of
    /// its `count` points in [`Lists::extra`].
    first: u32,
    next: u32,
    rgb: u16,
    count: u8,
}

impl Polygon {
    /// An unused slot.
    pub const EMPTY: Polygon = Polygon {
        plane: [0; 3],
        first: 0,
        next: NONE,
        rgb: 0,
        count: 0,
    };
}

/// An edge in the active edge list: the fill's walk and its polygon.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ActiveEdge {
    walk: EdgeWalk,
    polygon: u32,
}

/// A list that ran out of room (see [`ZError::Full`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum List {
    /// [`Lists::polygons`].
    Polygons,
    /// [`Lists::vertices`]: fewer than the mesh's vertices.
    Vertices,
    /// [`Lists::extra`]: the clipped polygons' points.
    Extra,
    /// [`Lists::heads`]: fewer than the image's rows.
    Heads,
    /// [`Lists::active`].
    Active,
    /// [`Lists::colour`] or [`Lists::depth`]: shorter than a row.
    Row,
}

impl core::fmt::Display for List {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            List::Polygons => "polygon table",
            List::Vertices => "projected vertices",
            List::Extra => "clipped points",
            List::Heads => "row list heads",
            List::Active => "active edge list",
            List::Row => "row buffers",
        })
    }
}

/// The caller's memory for one frame.
pub struct Lists<'m> {
    /// The polygon table: at most one per triangle.
    pub polygons: &'m mut [Polygon],
    /// Each mesh vertex's screen point (frames without clipping).
    pub vertices: &'m mut [SubpixelPoint],
    /// The points of clipped polygons (frames with clipping).
    pub extra: &'m mut [SubpixelPoint],
    /// Per row, the first polygon starting on it.
    pub heads: &'m mut [u32],
    /// The active edge list.
    pub active: &'m mut [ActiveEdge],
    /// One row of RGB565 colour.
    pub colour: &'m mut [u16],
    /// One row of depth (0: empty).
    pub depth: &'m mut [u16],
}

/// What a frame used of its [`Lists`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ScanStats {
    /// Polygons in the table.
    pub polygons: usize,
    /// Points in [`Lists::extra`].
    pub extra_points: usize,
    /// The most edges active at once.
    pub peak_active: usize,
}

/// Where finished rows go.
pub trait RowSink {
    /// Row `y`, left to right, RGB565.
    fn row(&mut self, y: u32, pixels: &[u16]);
}

/// The first row whose centre is at or below the fixed-point `y >= 0` (the fill's rule).
fn first_row(y: i32) -> i32 {
    let s = 1i32 << SUBPIXEL_BITS;
    (2 * y + s - 1) >> (SUBPIXEL_BITS + 1)
}

/// Draw `mesh` seen by `view` row by row into `sink`, uncovered pixels in `background`.
///
/// # Errors
/// [`ZError::Full`] when a list of `lists` is too small (rows already sent stay sent), or as
/// [`crate::zbuffer::draw`] for an unusable view or an image too large for the fill.
pub fn draw<S: RowSink + ?Sized>(
    mesh: &Mesh<'_>,
    view: &LocalView,
    background: u16,
    lists: &mut Lists<'_>,
    sink: &mut S,
) -> Result<ScanStats, ZError> {
    let prepared = Prepared::new(mesh, view)?;
    let (width, height) = (view.width, view.height);
    let w = width as usize;
    let full = |list| ZError::Full(list);
    let heads = lists
        .heads
        .get_mut(..height as usize)
        .ok_or(full(List::Heads))?;
    let (Some(colour), Some(depth)) = (lists.colour.get_mut(..w), lists.depth.get_mut(..w)) else {
        return Err(full(List::Row));
    };
    heads.fill(NONE);
    let mut stats = ScanStats::default();

    // Pass 1: the polygon table, bucketed by first row.
    let mut work = Clipped::default();
    for t in 0..mesh.triangle_count() {
        let Some(Projected { points, plane, rgb }) =
            prepared.triangle(mesh, view, t, None, &mut work)?
        else {
            continue;
        };
        let (lo, hi) = points.iter().fold((i32::MAX, i32::MIN), |(lo, hi), p| {
            (lo.min(p.y), hi.max(p.y))
        });
        let (first, end) = (first_row(lo), first_row(hi).min(height as i32));
        if first >= end {
            continue;
        }
        let (index, count) = if prepared.inside() {
            let (corners, _) = mesh.triangle(t);
            for (&c, &p) in corners.iter().zip(points) {
                *lists
                    .vertices
                    .get_mut(usize::from(c))
                    .ok_or(full(List::Vertices))? = p;
            }
            (t, 0)
        } else {
            let at = stats.extra_points;
            lists
                .extra
                .get_mut(at..at + points.len())
                .ok_or(full(List::Extra))?
                .copy_from_slice(points);
            stats.extra_points += points.len();
            (at as u32, points.len() as u8)
        };
        let head = heads.get_mut(first as usize).ok_or(full(List::Heads))?;
        let id = stats.polygons;
        *lists.polygons.get_mut(id).ok_or(full(List::Polygons))? = Polygon {
            plane,
            first: index,
            next: *head,
            rgb,
            count,
        };
        *head = id as u32;
        stats.polygons += 1;
    }

    // Pass 2: the rows.
    let mut n_active = 0;
    for y in 0..height {
        colour.fill(background);
        depth.fill(0);
        let row = y as Coord;
        // The polygons starting on this row bring their edges.
        let mut p = heads.get(y as usize).copied().unwrap_or(NONE);
        while let Some(polygon) = lists.polygons.get(p as usize).copied() {
            let mut triangle = [SubpixelPoint::default(); 3];
            let points: &[SubpixelPoint] = if polygon.count == 0 {
                let (corners, _) = mesh.triangle(polygon.first);
                for (slot, &c) in triangle.iter_mut().zip(&corners) {
                    *slot = lists
                        .vertices
                        .get(usize::from(c))
                        .copied()
                        .unwrap_or_default();
                }
                &triangle
            } else {
                let at = polygon.first as usize;
                lists
                    .extra
                    .get(at..at + usize::from(polygon.count))
                    .unwrap_or(&[])
            };
            for (i, &a) in points.iter().enumerate() {
                let b = points.get(i + 1).or(points.first()).copied().unwrap_or(a);
                if let Some(walk) = EdgeWalk::new(a, b, height) {
                    *lists.active.get_mut(n_active).ok_or(full(List::Active))? =
                        ActiveEdge { walk, polygon: p };
                    n_active += 1;
                }
            }
            p = polygon.next;
        }
        stats.peak_active = stats.peak_active.max(n_active);

        // Each active polygon's crossings on this row (its edges are consecutive), paired.
        let active = lists.active.get_mut(..n_active).unwrap_or(&mut []);
        let mut i = 0;
        while let Some(head) = active.get(i) {
            let id = head.polygon;
            let mut xs = [0 as Coord; CLIPPED];
            let mut n = 0;
            while let Some(e) = active.get(i).filter(|e| e.polygon == id) {
                if e.walk.row() == row {
                    if let Some(slot) = xs.get_mut(n) {
                        *slot = e.walk.x();
                        n += 1;
                    }
                }
                i += 1;
            }
            let xs = &mut xs[..n.min(CLIPPED)];
            xs.sort_unstable();
            let Some(polygon) = lists.polygons.get(id as usize) else {
                continue;
            };
            let mut sink = DepthSink {
                colour: &mut *colour,
                depth: &mut *depth,
                width: w,
                first_row: y,
                plane: polygon.plane,
                rgb: polygon.rgb,
            };
            for pair in xs.chunks_exact(2) {
                let clamp = |x: Coord| x.clamp(0, width as Coord) as u32;
                let (start, end) = (clamp(pair[0]), clamp(pair[1]));
                if start < end {
                    sink.span(y, start, end, Colour::default());
                }
            }
        }

        // Step the edges on this row; drop the finished ones, keeping the order.
        let mut kept = 0;
        for k in 0..active.len() {
            let mut e = active[k];
            if e.walk.row() == row {
                if e.walk.row_end() <= row + 1 {
                    continue;
                }
                e.walk.step();
            }
            active[kept] = e;
            kept += 1;
        }
        n_active = kept;
        sink.row(y, colour);
    }
    Ok(stats)
}

/// Lists as long as any frame of a mesh can need, owned (the host's runs).
#[cfg(any(feature = "std", test))]
pub struct OwnedLists {
    polygons: std::vec::Vec<Polygon>,
    vertices: std::vec::Vec<SubpixelPoint>,
    extra: std::vec::Vec<SubpixelPoint>,
    heads: std::vec::Vec<u32>,
    active: std::vec::Vec<ActiveEdge>,
    colour: std::vec::Vec<u16>,
    depth: std::vec::Vec<u16>,
}

#[cfg(any(feature = "std", test))]
impl OwnedLists {
    /// For frames of `mesh` of `width x height` pixels: a table entry per triangle, a point per
    /// vertex, and room for every triangle clipped to its most points and all its edges active.
    pub fn for_mesh(mesh: &Mesh<'_>, width: u32, height: u32) -> OwnedLists {
        use std::vec;
        let n = mesh.triangle_count() as usize;
        OwnedLists {
            polygons: vec![Polygon::EMPTY; n],
            vertices: vec![SubpixelPoint::default(); mesh.header().vertex_count as usize],
            extra: vec![SubpixelPoint::default(); n * CLIPPED],
            heads: vec![0; height as usize],
            active: vec![ActiveEdge::default(); n * CLIPPED],
            colour: vec![0; width as usize],
            depth: vec![0; width as usize],
        }
    }

    /// The lists, borrowed for a frame.
    pub fn lists(&mut self) -> Lists<'_> {
        Lists {
            polygons: &mut self.polygons,
            vertices: &mut self.vertices,
            extra: &mut self.extra,
            heads: &mut self.heads,
            active: &mut self.active,
            colour: &mut self.colour,
            depth: &mut self.depth,
        }
    }
}

/// Rows into a whole frame, and the order they came in (the host's runs).
#[cfg(any(feature = "std", test))]
pub struct FrameRows {
    /// The frame, row by row.
    pub pixels: std::vec::Vec<u16>,
    /// The rows received, in order.
    pub rows: std::vec::Vec<u32>,
    width: usize,
}

#[cfg(any(feature = "std", test))]
impl FrameRows {
    /// A `width x height` frame of `fill`.
    pub fn new(width: u32, height: u32, fill: u16) -> FrameRows {
        FrameRows {
            pixels: std::vec![fill; width as usize * height as usize],
            rows: std::vec::Vec::new(),
            width: width as usize,
        }
    }
}

#[cfg(any(feature = "std", test))]
impl RowSink for FrameRows {
    fn row(&mut self, y: u32, pixels: &[u16]) {
        let at = y as usize * self.width;
        if let Some(row) = self.pixels.get_mut(at..at + self.width) {
            row.copy_from_slice(pixels);
        }
        self.rows.push(y);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{encode, test_header};
    use crate::zbuffer;
    use glam::Vec3;
    use peel_runtime::camera::{Camera, Orbit};
    use std::vec;
    use std::vec::Vec;

    /// Closed boxes at distinct depths and sizes, some overlapping on screen, each face its
    /// own colour.
    fn boxes() -> Vec<u8> {
        let mut vertices = vec![];
        let mut tris = vec![];
        let mut cube = |c: Vec3, r: f32| {
            let base = vertices.len() as u32;
            for k in 0..8 {
                let s = |bit: u32| if k & bit != 0 { r } else { -r };
                vertices.push(c + Vec3::new(s(1), s(2), s(4)));
            }
            let faces = [
                [0, 1, 3, 2],
                [4, 6, 7, 5],
                [0, 4, 5, 1],
                [2, 3, 7, 6],
                [0, 2, 6, 4],
                [1, 5, 7, 3],
            ];
            for f in faces {
                let colour = (tris.len() as u16 + 1) * 997;
                tris.push(([base + f[0], base + f[1], base + f[2]], colour));
                tris.push(([base + f[0], base + f[2], base + f[3]], colour ^ 0x0421));
            }
        };
        cube(Vec3::new(-0.4, 0.1, 0.2), 0.35);
        cube(Vec3::new(0.3, -0.2, -0.3), 0.5);
        cube(Vec3::new(0.1, 0.5, 0.6), 0.2);
        let header = test_header([0.0; 3], Vec3::splat(-1.0), Vec3::splat(1.0));
        encode(&header, &vertices, &tris).unwrap()
    }

    fn view(bytes: &[u8], azimuth: f64, distance_scale: f64) -> LocalView {
        let mesh = Mesh::parse(bytes).unwrap();
        let h = mesh.header();
        let orbit = Orbit {
            azimuth_deg: azimuth,
            elevation_deg: 25.0,
            distance: Orbit::fitting_distance(60.0, 64, 48) * distance_scale,
        };
        let near = Camera::default_near(h.bounds_min, h.bounds_max);
        let camera = Camera::look_at(orbit.pose(&h), 60.0, 64, 48, near).unwrap();
        camera.view(h.centre)
    }

    fn scanline(bytes: &[u8], view: &LocalView) -> (Vec<u16>, ScanStats) {
        let mesh = Mesh::parse(bytes).unwrap();
        let h = view.height as usize;
        let mut owned = OwnedLists::for_mesh(&mesh, view.width, view.height);
        let mut lists = owned.lists();
        let mut frame = FrameRows::new(view.width, view.height, 0xdead);
        let stats = draw(&mesh, view, 7, &mut lists, &mut frame).unwrap();
        assert_eq!(
            frame.rows,
            (0..h as u32).collect::<Vec<_>>(),
            "rows in order"
        );
        (frame.pixels, stats)
    }

    fn zbuffer(bytes: &[u8], view: &LocalView) -> Vec<u16> {
        let mesh = Mesh::parse(bytes).unwrap();
        let n = (view.width * view.height) as usize;
        let (mut colour, mut depth) = (vec![0u16; n], vec![0u16; n]);
        zbuffer::draw(&mesh, view, 7, &mut colour, &mut depth).unwrap();
        colour
    }

    /// [`boxes`] with its triangles in reverse order.
    fn reversed(bytes: &[u8]) -> Vec<u8> {
        let mesh = Mesh::parse(bytes).unwrap();
        let h = mesh.header();
        let vertices: Vec<Vec3> = (0..h.vertex_count as u16).map(|i| mesh.vertex(i)).collect();
        let tris: Vec<([u32; 3], u16)> = (0..mesh.triangle_count())
            .rev()
            .map(|t| {
                let (c, rgb) = mesh.triangle(t);
                (c.map(u32::from), rgb)
            })
            .collect();
        encode(&h, &vertices, &tris).unwrap()
    }

    #[test]
    fn the_full_frame_z_buffers_pixels_row_by_row() {
        let bytes = boxes();
        let back = reversed(&bytes);
        let mut clipped = false;
        // From afar (no clipping) and from close up (clipped by the window and the near plane).
        for scale in [1.0, 0.45, 0.2] {
            for azimuth in [0.0, 40.0, 135.0, 250.0] {
                let v = view(&bytes, azimuth, scale);
                let (pixels, stats) = scanline(&bytes, &v);
                // Where two triangles tie in depth, the z-buffer keeps the one drawn first, so
                // its frames in both triangle orders differ there and only there; elsewhere
                // every pixel is the z-buffer's.
                let (first, last) = (zbuffer(&bytes, &v), zbuffer(&back, &v));
                let mut ties = 0;
                for k in 0..pixels.len() {
                    if first[k] == last[k] {
                        assert_eq!(
                            pixels[k], first[k],
                            "azimuth {azimuth}, scale {scale}, pixel {k}"
                        );
                    } else {
                        ties += 1;
                        assert!(pixels[k] == first[k] || pixels[k] == last[k]);
                    }
                }
                assert!(ties * 100 < pixels.len(), "{ties} ties");
                assert!(stats.polygons > 0 && stats.peak_active >= 2);
                assert!(pixels.iter().any(|&p| p != 7), "something is drawn");
                clipped |= stats.extra_points > 0;
            }
        }
        assert!(clipped, "some views clip");
    }

    #[test]
    fn lists_too_small_are_named() {
        let bytes = boxes();
        let mesh = Mesh::parse(&bytes).unwrap();
        let v = view(&bytes, 30.0, 1.0);
        let (_, stats) = scanline(&bytes, &v);
        let mut polygons = vec![Polygon::EMPTY; stats.polygons - 1];
        let mut vertices = vec![SubpixelPoint::default(); 24];
        let mut heads = vec![0; 48];
        let mut active = vec![ActiveEdge::default(); stats.peak_active];
        let (mut colour, mut depth) = (vec![0; 64], vec![0; 64]);
        let mut lists = Lists {
            polygons: &mut polygons,
            vertices: &mut vertices,
            extra: &mut [],
            heads: &mut heads,
            active: &mut active,
            colour: &mut colour,
            depth: &mut depth,
        };
        let mut frame = FrameRows::new(64, 48, 0);
        let err = draw(&mesh, &v, 0, &mut lists, &mut frame);
        assert_eq!(err, Err(ZError::Full(List::Polygons)));
        // The table that fits, and exactly the peak of active edges, suffice.
        let mut polygons = vec![Polygon::EMPTY; stats.polygons];
        lists.polygons = &mut polygons;
        assert_eq!(draw(&mesh, &v, 0, &mut lists, &mut frame), Ok(stats));
        let mut active = vec![ActiveEdge::default(); stats.peak_active - 1];
        lists.active = &mut active;
        assert_eq!(
            draw(&mesh, &v, 0, &mut lists, &mut frame),
            Err(ZError::Full(List::Active))
        );
    }
}
