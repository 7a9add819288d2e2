//! Textures: a material's `map_Kd` image as the file will store it (power-of-two sides, RGB565
//! texels, row 0 the image's top), and a triangle's texture coordinates.

use std::path::PathBuf;

use glam::DVec2;

/// A triangle's texture: which of the mesh's [`Texture`]s, and its corners' coordinates as the
/// OBJ gives them (`vt u v`: `v = 0` is the image's bottom row), in the order of the
/// triangle's vertices.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerUvs {
    /// Index into [`super::Mesh::textures`].
    pub texture: u32,
    /// `(u, v)` per corner.
    pub uv: [DVec2; 3],
}

/// A texture ready to store: `2^log2_width x 2^log2_height` RGB565 texels, row by row from the
/// top, left to right.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Texture {
    /// The image file it was read from (for messages and the build's file list).
    pub path: PathBuf,
    /// `log2` of the width in texels.
    pub log2_width: u8,
    /// `log2` of the height in texels.
    pub log2_height: u8,
    /// `[s, t]`: the edge texels continue past the edges on that axis (MTL `-clamp on`),
    /// else the texture repeats.
    pub clamp: [bool; 2],
    /// RGB565 texels (red in the high bits), `width * height` of them.
    pub texels: Vec<u16>,
}

impl Texture {
    /// Width in texels.
    pub fn width(&self) -> u32 {
        1 << self.log2_width
    }

    /// Height in texels.
    pub fn height(&self) -> u32 {
        1 << self.log2_height
    }

    /// The texel `(column, row)` that OBJ coordinates `(u, v)` fall in: column
    /// `floor(u * width)`, row `floor((1 - v) * height)`, each repeated or clamped as the
    /// texture says (the exact mapping, which the runtime's file coordinates round to
    /// `2^-16` of the texture).
    pub fn texel_of(&self, u: f64, v: f64) -> (u32, u32) {
        let place = |x: f64, log2: u8, clamp: bool| -> u32 {
            let n = 1i64 << log2;
            let k = (x * n as f64).floor() as i64;
            if clamp {
                k.clamp(0, n - 1) as u32
            } else {
                k.rem_euclid(n) as u32
            }
        };
        (
            place(u, self.log2_width, self.clamp[0]),
            place(1.0 - v, self.log2_height, self.clamp[1]),
        )
    }

    /// The RGB565 texel at `(column, row)` (taken modulo the sides).
    pub fn texel(&self, column: u32, row: u32) -> u16 {
        let (c, r) = (column & (self.width() - 1), row & (self.height() - 1));
        self.texels
            .get((r as usize) << self.log2_width | c as usize)
            .copied()
            .unwrap_or(0)
    }
}
