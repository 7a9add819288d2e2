//! The encoding of the variable-size parts of a file: index width and colour palette.
//!
//! Rule: the writer picks, among the encodings that can hold the scene, the one whose file is
//! smallest ([`Encoding::smallest`]); on a tie the earlier of [`Encoding::ALL`] wins (`u16`
//! indices, then no palette), so the file stays a canonical function of the tree. `u16`
//! indices fit when the vertex count is at most 65536 and are never larger; a palette costs
//! 3 bytes per distinct colour and saves 2 (`u8` index) or 1 (`u16` index) byte per colour
//! field (one per polygon, two when its sides differ), so it pays when colours repeat.

use crate::hash::FastMap;

use super::format::{header_flags, ColourField};
use crate::error::CompileError;
use peel_runtime::read::layout::{index_size, polygon_size, PALETTE_SIZE};

/// Width of a palette index.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PaletteWidth {
    /// Up to 256 colours.
    U8,
    /// Up to 65536 colours.
    U16,
}

/// Index width and colour representation of one file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Encoding {
    /// Indices are `u16` ([`header_flags::INDEX16`]).
    pub index16: bool,
    /// Polygons name a palette colour ([`header_flags::PALETTE`]) of this width.
    pub palette: Option<PaletteWidth>,
}

impl Encoding {
    /// Every encoding, in order of preference on a tie.
    pub const ALL: [Encoding; 6] = {
        const fn e(index16: bool, palette: Option<PaletteWidth>) -> Encoding {
            Encoding { index16, palette }
        }
        [
            e(true, None),
            e(true, Some(PaletteWidth::U8)),
            e(true, Some(PaletteWidth::U16)),
            e(false, None),
            e(false, Some(PaletteWidth::U8)),
            e(false, Some(PaletteWidth::U16)),
        ]
    };

    /// Header flags of this encoding, or an error when it cannot hold `vertices` vertices and
    /// `colours` distinct colours.
    pub fn flags(self, vertices: usize, colours: usize) -> Result<u16, CompileError> {
        let mut flags = 0;
        if self.index16 {
            if vertices > 1 << 16 {
                return Err(CompileError::Encode(format!(
                    "{vertices} vertices do not fit u16 indices"
                )));
            }
            flags |= header_flags::INDEX16;
        } else if vertices <= 1 << 24 {
            // Wider than u16 but not u32: three bytes an index.
            flags |= header_flags::INDEX24;
        }
        if let Some(width) = self.palette {
            let max = match width {
                PaletteWidth::U8 => 1 << 8,
                PaletteWidth::U16 => 1 << 16,
            };
            if colours == 0 || colours > max {
                return Err(CompileError::Encode(format!(
                    "{colours} colours do not fit a {width:?} palette"
                )));
            }
            flags |= header_flags::PALETTE;
            if width == PaletteWidth::U16 {
                flags |= header_flags::PALETTE16;
            }
        }
        Ok(flags)
    }

    /// Bytes of the parts this encoding changes: indices, polygons (with two colour fields
    /// each when `two_colours`) and palette.
    pub fn size(self, indices: usize, polygons: usize, colours: usize, two_colours: bool) -> usize {
        let mut flags = self.flags(0, 1).unwrap_or(0);
        if two_colours {
            flags |= header_flags::TWO_COLOURS;
        }
        let palette = if self.palette.is_some() { colours } else { 0 };
        indices * index_size(flags) + polygons * polygon_size(flags) + palette * PALETTE_SIZE
    }

    /// The encoding of the smallest file that can hold the scene.
    pub fn smallest(
        vertices: usize,
        indices: usize,
        polygons: usize,
        colours: usize,
        two_colours: bool,
    ) -> Encoding {
        Encoding::ALL
            .into_iter()
            .filter(|e| e.flags(vertices, colours).is_ok())
            .min_by_key(|e| e.size(indices, polygons, colours, two_colours))
            // Unreachable: `u32` indices and RGB colours hold any scene.
            .unwrap_or(Encoding {
                index16: false,
                palette: None,
            })
    }
}

/// The distinct colours of `rgb`, in order of first use.
pub fn distinct_colours(rgb: &[[u8; 3]]) -> Vec<[u8; 3]> {
    let mut seen = FastMap::default();
    let mut out = Vec::new();
    for &c in rgb {
        seen.entry(c).or_insert_with(|| {
            out.push(c);
        });
    }
    out
}

/// The colour field of each of `rgb` under header `flags`, with the palette they index
/// (empty without [`header_flags::PALETTE`]).
pub fn colour_fields(
    flags: u16,
    rgb: &[[u8; 3]],
) -> Result<(Vec<ColourField>, Vec<[u8; 3]>), CompileError> {
    if flags & header_flags::PALETTE == 0 {
        return Ok((
            rgb.iter().map(|&c| ColourField::Rgb(c)).collect(),
            Vec::new(),
        ));
    }
    let palette = distinct_colours(rgb);
    let index: FastMap<[u8; 3], usize> = palette.iter().enumerate().map(|(k, &c)| (c, k)).collect();
    let wide = flags & header_flags::PALETTE16 != 0;
    let fields = rgb
        .iter()
        .map(|c| {
            let k = index[c];
            let field = if wide {
                u16::try_from(k).ok().map(ColourField::Index16)
            } else {
                u8::try_from(k).ok().map(ColourField::Index8)
            };
            field.ok_or_else(|| CompileError::Encode(format!("palette index {k} too wide")))
        })
        .collect::<Result<_, _>>()?;
    Ok((fields, palette))
}
