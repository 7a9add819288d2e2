//! Textures read in place (format [`TEXTURED_VERSION`](layout::TEXTURED_VERSION)): a polygon's
//! [`Texture`] and its vertices' coordinates.

use super::layout::{self, texture_flags, u32_at, u8_at, NO_TEXTURE, TEXEL_SIZE, UV_SIZE};
use super::Scene;

/// Where a textured file's texture arrays start (each just after its length).
#[derive(Debug, Clone, Copy, Default)]
#[cfg_attr(not(feature = "textures"), allow(dead_code))]
pub(crate) struct TextureArrays {
    pub(crate) uvs: usize,
    pub(crate) records: usize,
    pub(crate) count: u32,
    pub(crate) texels: usize,
    pub(crate) texel_bytes: usize,
    pub(crate) polygons: usize,
}

/// One texture of a file, borrowed from its bytes: `2^log2_width x 2^log2_height` RGB565
/// texels, row 0 the image's top, directly or through its own palette.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Texture<'a> {
    /// `log2` of the width.
    pub log2_width: u8,
    /// `log2` of the height.
    pub log2_height: u8,
    /// Record flags ([`texture_flags`]).
    pub flags: u8,
    /// The palette's RGB565 colours (2 bytes each; empty without
    /// [`texture_flags::PALETTE`]).
    pub colours: &'a [u8],
    /// The texels: 2 bytes each, or 1 (a palette index) with [`texture_flags::PALETTE`].
    pub texels: &'a [u8],
}

impl Texture<'_> {
    /// The RGB565 colour of texel `(column, row)`, both taken modulo the sides (0 for bytes
    /// the file does not have, which a parsed file always has).
    #[inline]
    pub fn texel(&self, column: u32, row: u32) -> u16 {
        let w = 1u32 << self.log2_width;
        let h = 1u32 << self.log2_height;
        self.texel_at((((row & (h - 1)) << self.log2_width) | (column & (w - 1))) as usize)
    }

    /// The RGB565 colour of texel `i` (row by row; 0 past the end).
    #[inline]
    pub fn texel_at(&self, i: usize) -> u16 {
        if self.flags & texture_flags::PALETTE != 0 {
            let k = self.texels.get(i).copied().unwrap_or(0);
            rgb565_at(self.colours, usize::from(k))
        } else {
            rgb565_at(self.texels, i)
        }
    }
}

/// RGB565 entry `i` of `bytes` (little endian), 0 past the end.
#[inline]
pub(crate) fn rgb565_at(bytes: &[u8], i: usize) -> u16 {
    // (One bounds check for both bytes.)
    match bytes.get(i * TEXEL_SIZE..i * TEXEL_SIZE + TEXEL_SIZE) {
        Some(&[lo, hi]) => u16::from_le_bytes([lo, hi]),
        _ => 0,
    }
}

impl<'a> Scene<'a> {
    /// Whether the file has textures ([`layout::header_flags::TEXTURES`]); always `false` in
    /// a build without the `textures` feature, which refuses such files.
    #[inline]
    pub fn has_textures(&self) -> bool {
        cfg!(feature = "textures") && self.header.flags & layout::header_flags::TEXTURES != 0
    }

    /// The texture arrays (all zero without textures).
    #[inline]
    fn texture_arrays(&self) -> TextureArrays {
        #[cfg(feature = "textures")]
        return self.textures;
        #[cfg(not(feature = "textures"))]
        TextureArrays::default()
    }

    /// The number of textures (0 without textures).
    pub fn texture_count(&self) -> u32 {
        if self.has_textures() {
            self.texture_arrays().count
        } else {
            0
        }
    }

    /// Texture `k`, if the file has it.
    pub fn texture(&self, k: u32) -> Option<Texture<'a>> {
        let arrays = self.texture_arrays();
        if !self.has_textures() || k >= arrays.count {
            return None;
        }
        let at = arrays.records + k as usize * layout::TEXTURE_SIZE;
        let b = self.bytes;
        let (log2_width, log2_height, flags) =
            (u8_at(b, at)?, u8_at(b, at + 1)?, u8_at(b, at + 2)?);
        let colours = if flags & texture_flags::PALETTE != 0 {
            u32::from(u8_at(b, at + 3)?) + 1
        } else {
            0
        };
        let start = arrays.texels + u32_at(b, at + 4)? as usize;
        let size = layout::texture_bytes(log2_width, log2_height, flags, colours);
        let bytes = b.get(start..start.checked_add(size)?)?;
        let (colours, texels) = bytes.split_at_checked(colours as usize * TEXEL_SIZE)?;
        Some(Texture {
            log2_width,
            log2_height,
            flags,
            colours,
            texels,
        })
    }

    /// The texture of polygon `i`, or `None` for an untextured one.
    #[inline]
    pub fn polygon_texture(&self, i: u32) -> Option<Texture<'a>> {
        if !self.has_textures() || i >= self.header.polygon_count {
            return None;
        }
        match u8_at(self.bytes, self.texture_arrays().polygons + i as usize)? {
            NO_TEXTURE => None,
            k => self.texture(u32::from(k)),
        }
    }

    /// The texture coordinates `[s, t]` of vertex `v` (`2^16` a whole side, see
    /// [`layout::UV_FRACTION_BITS`]); `[0, 0]` out of range or without textures.
    #[inline]
    pub fn vertex_uv(&self, v: u32) -> [i32; 2] {
        if !self.has_textures() || v >= self.header.vertex_count {
            return [0, 0];
        }
        let at = self.texture_arrays().uvs + v as usize * UV_SIZE;
        let s = u32_at(self.bytes, at).unwrap_or(0) as i32;
        let t = u32_at(self.bytes, at + 4).unwrap_or(0) as i32;
        [s, t]
    }
}
