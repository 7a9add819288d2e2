//! Polygons: their records decoded (vertex range, flags, the colour each side shows), and the
//! scene's accessors for them, their vertex indices and their ids.

use glam::Vec3;

use super::layout::{
    self, element, header_flags, u16_at, u32_at, u8_at, Record, ID_SIZE, PALETTE_SIZE,
};
use super::{readable, Scene};
use crate::display::Colour;

/// A polygon record. Its support plane is the plane through its first three vertices
/// ([`Scene::eye_side`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Polygon {
    /// First entry in the index array.
    pub first_index: u32,
    /// Number of vertices.
    pub vertex_count: u16,
    /// Polygon flags ([`layout::polygon_flags`]).
    pub flags: u8,
    /// Baked colour: of both sides, or with [`layout::header_flags::TWO_COLOURS`] of the
    /// interior side ([`Scene::colour_seen`]).
    pub colour: Colour,
}

impl Scene<'_> {
    /// Polygon `i` (all zero when out of range).
    #[inline]
    pub fn polygon(&self, i: u32) -> Polygon {
        let polygon = self.polygon_shape(i);
        Polygon {
            colour: self.colour_seen(i, true),
            ..polygon
        }
    }

    /// Polygon `i` without its colour (left at its default): what the traversal needs, which
    /// leaves the colour to [`Scene::colour_seen`] for the polygons drawn.
    #[inline]
    pub fn polygon_shape(&self, i: u32) -> Polygon {
        if i >= self.header.polygon_count {
            return Polygon::default();
        }
        let Some(at) = element(self.polygons, self.polygon_size, i) else {
            return Polygon::default();
        };
        // One bounds check per record, fields at constant offsets.
        let w = self.field_size();
        let fields = if w == 2 {
            Record::<4>::at(self.bytes, at).map(|r| (r.narrow(0, false), r.u8(2), r.u8(3)))
        } else if w == 3 {
            Record::<5>::at(self.bytes, at).map(|r| (r.medium(0, false), r.u8(3), r.u8(4)))
        } else {
            Record::<6>::at(self.bytes, at).map(|r| (r.u32(0), r.u8(4), r.u8(5)))
        };
        let Some((first_index, vertex_count, flags)) = fields else {
            return Polygon::default();
        };
        Polygon {
            first_index,
            vertex_count: u16::from(vertex_count),
            flags,
            colour: Colour::default(),
        }
    }

    /// The colour polygon `i` shows an eye on its interior side (`interior`, as the
    /// traversal yields it) or on its exterior side: the record's colour field, or with
    /// [`header_flags::TWO_COLOURS`] its second one for the exterior side (black when out of
    /// range).
    #[inline]
    pub fn colour_seen(&self, i: u32, interior: bool) -> Colour {
        if i >= self.header.polygon_count {
            return Colour::default();
        }
        let field = if interior {
            self.field_size() + 2
        } else {
            self.exterior
        };
        // Within the polygon array (checked by the parse): no overflow.
        self.colour_at(self.polygons + i as usize * self.polygon_size + field)
    }

    /// Which of each vertex's two intensities ([`Scene::vertex_shade`]) shade the side of a
    /// polygon with `flags` that an eye on its `interior` side sees: 0 (its source triangle's
    /// front) or 1 (its back), or `None` for a polygon that is not
    /// [`SMOOTH`](layout::polygon_flags::SMOOTH) (its colour field is then the side's colour).
    #[inline]
    pub fn shade_side(flags: u8, interior: bool) -> Option<usize> {
        use layout::polygon_flags::{INTERIOR_BACK, SMOOTH};
        if flags & SMOOTH == 0 {
            return None;
        }
        Some(usize::from(interior == (flags & INTERIOR_BACK != 0)))
    }

    /// Intensity `side` (0 or 1, [`Scene::shade_side`]) of vertex `v`, 255 the material's full
    /// colour: 0 out of range or in a file without
    /// [`SHADES`](layout::header_flags::SHADES).
    #[inline]
    pub fn vertex_shade(&self, v: u32, side: usize) -> u8 {
        if self.header.flags & header_flags::SHADES == 0 || v >= self.header.vertex_count {
            return 0;
        }
        // Within the shades array (checked by the parse): no overflow.
        let at = self.shades + v as usize * layout::SHADE_SIZE + (side & 1);
        u8_at(self.bytes, at).unwrap_or(0)
    }

    /// The colour field at `at`: RGB, or a palette index (see [`layout::polygon_size`]).
    #[inline(never)]
    fn colour_at(&self, at: usize) -> Colour {
        let b = self.bytes;
        let flags = self.header.flags;
        // One bounds check for the three bytes.
        let rgb = |at: usize| match b.get(at..at.wrapping_add(3)) {
            Some(&[r, g, b]) => Colour::new(r, g, b),
            _ => Colour::default(),
        };
        if flags & header_flags::PALETTE == 0 {
            return rgb(at);
        }
        let index = if flags & header_flags::PALETTE16 != 0 {
            u16_at(b, at).map(u32::from)
        } else {
            u8_at(b, at).map(u32::from)
        };
        match index {
            // Below 2^16 entries inside the file (checked by the parse): no overflow.
            Some(k) if k < self.header.palette_count => {
                rgb(self.palette + k as usize * PALETTE_SIZE)
            }
            _ => Colour::default(),
        }
    }

    /// Entry `i` of the index array (`u16`, `u24` or `u32` as the header says), if in range.
    #[inline]
    pub(super) fn index(&self, i: u32) -> Option<u32> {
        if self.index_size() == 2 {
            if !readable(i, self.header.index_count) {
                return None;
            }
            let at = i as usize * 2;
            let entry: &[u8; 2] = self.indices16.get(at..at + 2)?.try_into().ok()?;
            return Some(u32::from(u16::from_le_bytes(*entry)));
        }
        if i >= self.header.index_count {
            return None;
        }
        let at = element(self.indices, self.index_size(), i)?;
        match self.index_size() {
            2 => u16_at(self.bytes, at).map(u32::from),
            3 => layout::field_at(self.bytes, at, 3, false),
            _ => u32_at(self.bytes, at),
        }
    }

    /// Vertex `i` of polygon `polygon` (`i < vertex_count`), relative to the centre
    /// (zero when out of range).
    pub fn polygon_vertex(&self, polygon: &Polygon, i: u32) -> Vec3 {
        self.polygon_vertex_index(polygon, i)
            .map_or(Vec3::ZERO, |v| self.vertex(v))
    }

    /// The index in the vertex list of vertex `i` of `polygon` (`None` when out of range).
    #[inline]
    pub fn polygon_vertex_index(&self, polygon: &Polygon, i: u32) -> Option<u32> {
        if i >= u32::from(polygon.vertex_count) {
            return None;
        }
        polygon
            .first_index
            .checked_add(i)
            .and_then(|slot| self.index(slot))
    }

    /// Source triangle id of polygon `i`, when the file has ids.
    pub fn id(&self, i: u32) -> Option<u32> {
        if self.header.flags & header_flags::IDS == 0 || i >= self.header.polygon_count {
            return None;
        }
        u32_at(self.bytes, element(self.ids, ID_SIZE, i)?)
    }
}
