//! Transparency: a file's transparent polygons and their opacities (format 7, see
//! `formats/peel.md`, "Transparency").

use super::layout::{self, polygon_flags};
use super::Scene;

impl Scene<'_> {
    /// Whether some polygon is transparent ([`layout::header_flags::TRANSPARENT`]); always
    /// `false` in a build without the `transparency` feature, which refuses such files.
    #[inline]
    pub fn has_transparency(&self) -> bool {
        cfg!(feature = "transparency") && self.header.flags & layout::header_flags::TRANSPARENT != 0
    }

    /// The opacity of polygon `i` (of 255; [`layout::OPAQUE`] for an opaque one, out of range
    /// or without transparency).
    #[inline]
    pub fn opacity(&self, i: u32) -> u8 {
        #[cfg(feature = "transparency")]
        if self.has_transparency() && i < self.header.polygon_count {
            return layout::u8_at(self.bytes, self.opacities + i as usize)
                .unwrap_or(layout::OPAQUE);
        }
        let _ = i;
        layout::OPAQUE
    }

    /// [`Scene::opacity`] of a polygon the walk read, by its flag first: an opaque polygon's
    /// costs one test.
    #[inline]
    pub(crate) fn opacity_of(&self, i: u32, flags: u8) -> u8 {
        if flags & polygon_flags::TRANSPARENT != 0 {
            self.opacity(i)
        } else {
            layout::OPAQUE
        }
    }
}
