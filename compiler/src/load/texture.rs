//! Textures: a material's `map_Kd` image as the file will store it (power-of-two sides, RGB565
//! texels, row 0 the image's top), and a triangle's texture coordinates.

use std::path::PathBuf;

use glam::DVec2;

use crate::error::CompileError;
use crate::hash::FastMap;

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

/// The textures of one load, read as faces use them: each material's `map_Kd` read at its
/// first use, each image file decoded once.
#[derive(Debug)]
pub(super) struct Table {
    /// Per tobj material (the index is its id), its `map_Kd` statement.
    materials: Vec<Option<super::mtl::MapKd>>,
    /// The largest side and whether larger or other than power-of-two sides are resampled.
    max: u32,
    resample: bool,
    /// Material id -> index in `textures`.
    by_material: FastMap<usize, u32>,
    /// Image path and clamping -> index in `textures`.
    by_image: FastMap<(PathBuf, bool), u32>,
    /// The textures, in order of first use.
    pub textures: Vec<Texture>,
    /// Every image file read and its bytes, in order.
    pub files: Vec<(PathBuf, Vec<u8>)>,
    /// Worded warnings (options that change nothing).
    pub warnings: Vec<String>,
}

impl Table {
    /// The table of materials whose `map_Kd` statements are `materials` (one per tobj
    /// material, in order), sides limited to `max` and resampled when `resample`.
    pub(super) fn new(materials: Vec<Option<super::mtl::MapKd>>, max: u32, resample: bool) -> Self {
        Table {
            materials,
            max,
            resample,
            by_material: FastMap::default(),
            by_image: FastMap::default(),
            textures: Vec::new(),
            files: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// Whether material `material` has a `map_Kd`.
    pub(super) fn textured(&self, material: usize) -> bool {
        matches!(self.materials.get(material), Some(Some(_)))
    }

    /// The index of material `material`'s texture, read now if it is its first use; `None`
    /// when it has none.
    ///
    /// # Errors
    /// A malformed statement ([`CompileError::Mtl`]), an image that cannot be read, decoded
    /// or, without resampling, stored as it is, a build without the `textures` feature.
    pub(super) fn texture(&mut self, material: usize) -> Result<Option<u32>, CompileError> {
        if let Some(&k) = self.by_material.get(&material) {
            return Ok(Some(k));
        }
        let Some(Some(map_kd)) = self.materials.get(material) else {
            return Ok(None);
        };
        let options = super::mtl::options(&map_kd.text).map_err(|message| CompileError::Mtl {
            path: map_kd.mtl.clone(),
            line: map_kd.line,
            message,
        })?;
        let image = match map_kd.mtl.parent() {
            Some(dir) => dir.join(&options.image),
            None => PathBuf::from(&options.image),
        };
        let site = |image| super::decode::Site {
            image,
            mtl: &map_kd.mtl,
            line: map_kd.line,
        };
        if !options.ignored.is_empty() {
            self.warnings.push(format!(
                "{}:{}: `map_Kd` option{} {} ignored (only `-clamp` is read)",
                map_kd.mtl.display(),
                map_kd.line,
                if options.ignored.len() == 1 { "" } else { "s" },
                options.ignored.join(", "),
            ));
        }
        let key = (image.clone(), options.clamp);
        let k = match self.by_image.get(&key) {
            Some(&k) => k,
            None => {
                let read = self.textures.iter().find(|t| t.path == image);
                let texels = match read {
                    Some(t) => super::decode::Texels {
                        log2_width: t.log2_width,
                        log2_height: t.log2_height,
                        texels: t.texels.clone(),
                    },
                    None => {
                        let (bytes, texels) =
                            super::decode::read(site(&image), self.max, self.resample)?;
                        self.files.push((image.clone(), bytes));
                        texels
                    }
                };
                let k = self.textures.len() as u32;
                self.textures.push(Texture {
                    path: image,
                    log2_width: texels.log2_width,
                    log2_height: texels.log2_height,
                    clamp: [options.clamp; 2],
                    texels: texels.texels,
                });
                self.by_image.insert(key, k);
                k
            }
        };
        self.by_material.insert(material, k);
        Ok(Some(k))
    }
}

#[cfg(test)]
mod tests;
