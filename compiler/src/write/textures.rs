//! Textures as a file stores them (`formats/peel.md`, "Textures"): the textures the written
//! polygons use, renumbered in order of first use, each as RGB565 texels or, when it has at
//! most 256 colours and that is smaller, as its own palette and a `u8` index per texel.

use peel_runtime::read::layout::{texture_flags, NO_TEXTURE, TEXEL_SIZE};

use crate::error::CompileError;
use crate::hash::FastMap;
use crate::load::texture::Texture;

use super::format::TextureRecord;

/// Textures renumbered for a file: the polygons' texture bytes, the records and the texels.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Stored {
    /// Per polygon (in the order given), its texture in the file, or [`NO_TEXTURE`].
    pub polygons: Vec<u8>,
    /// The texture records, in order of first use.
    pub records: Vec<TextureRecord>,
    /// Every texture's bytes, in record order.
    pub texels: Vec<u8>,
}

/// The textures of `textures` that `polygons` (each an index into `textures` or
/// [`NO_TEXTURE`]) use, in order of first use; `None` when no polygon is textured.
///
/// # Errors
/// [`CompileError::Invariant`] for an index past `textures`, [`CompileError::Encode`] when
/// the texels pass 4 GiB (an offset is a `u32`).
pub(crate) fn store(textures: &[Texture], polygons: &[u8]) -> Result<Option<Stored>, CompileError> {
    if polygons.iter().all(|&k| k == NO_TEXTURE) {
        return Ok(None);
    }
    let mut order: FastMap<u8, u8> = FastMap::default();
    let mut out = Stored {
        polygons: Vec::with_capacity(polygons.len()),
        records: Vec::new(),
        texels: Vec::new(),
    };
    for &k in polygons {
        if k == NO_TEXTURE {
            out.polygons.push(NO_TEXTURE);
            continue;
        }
        let next = order.len() as u8;
        let new = *order.entry(k).or_insert(next);
        if new == next {
            let texture = textures.get(usize::from(k)).ok_or_else(|| {
                CompileError::Invariant(format!(
                    "polygon texture {k} of {} textures",
                    textures.len()
                ))
            })?;
            let offset = u32::try_from(out.texels.len())
                .map_err(|_| CompileError::Encode("the textures' texels pass 4 GiB".into()))?;
            let (flags, colours) = encode(texture, &mut out.texels);
            out.records.push(TextureRecord {
                log2_width: texture.log2_width,
                log2_height: texture.log2_height,
                flags,
                colours_minus_one: colours.saturating_sub(1) as u8,
                offset,
            });
        }
        out.polygons.push(new);
    }
    u32::try_from(out.texels.len())
        .map_err(|_| CompileError::Encode("the textures' texels pass 4 GiB".into()))?;
    Ok(Some(out))
}

/// Appends `texture`'s bytes to `out`: its palette and indices when it has at most 256
/// colours and they take fewer bytes than RGB565 texels, else the texels. Returns its record's
/// flags and the palette's colours (0 without).
fn encode(texture: &Texture, out: &mut Vec<u8>) -> (u8, u32) {
    let mut flags = 0;
    if texture.clamp[0] {
        flags |= texture_flags::CLAMP_S;
    }
    if texture.clamp[1] {
        flags |= texture_flags::CLAMP_T;
    }
    let texels = &texture.texels;
    // The colours in order of first use, while there are at most 256.
    let mut palette: Vec<u16> = Vec::new();
    let mut index: FastMap<u16, u8> = FastMap::default();
    let mut fits = true;
    for &c in texels {
        if let std::collections::hash_map::Entry::Vacant(slot) = index.entry(c) {
            if palette.len() == 256 {
                fits = false;
                break;
            }
            slot.insert(palette.len() as u8);
            palette.push(c);
        }
    }
    let smaller = palette.len() * TEXEL_SIZE + texels.len() < texels.len() * TEXEL_SIZE;
    if fits && smaller {
        for c in &palette {
            out.extend_from_slice(&c.to_le_bytes());
        }
        out.extend(texels.iter().map(|c| index[c]));
        (flags | texture_flags::PALETTE, palette.len() as u32)
    } else {
        for c in texels {
            out.extend_from_slice(&c.to_le_bytes());
        }
        (flags, 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use peel_runtime::read::layout::texture_bytes;
    use std::path::PathBuf;

    fn texture(log2: [u8; 2], clamp: [bool; 2], texels: Vec<u16>) -> Texture {
        Texture {
            path: PathBuf::from("t.png"),
            log2_width: log2[0],
            log2_height: log2[1],
            clamp,
            texels,
        }
    }

    /// A texture of few colours is a palette in order of first use and one byte a texel; one
    /// too small for a palette to pay, or of more than 256 colours, is RGB565 texels.
    #[test]
    fn a_palette_is_used_when_it_fits_and_is_smaller() {
        let two = texture([2, 1], [false; 2], [7, 7, 3, 7, 3, 3, 9, 9].to_vec());
        let mut bytes = Vec::new();
        assert_eq!(encode(&two, &mut bytes), (texture_flags::PALETTE, 3));
        assert_eq!(bytes, [7, 0, 3, 0, 9, 0, 0, 0, 1, 0, 1, 1, 2, 2]);
        assert_eq!(bytes.len(), texture_bytes(2, 1, texture_flags::PALETTE, 3));
        // 2 texels of 2 colours: a palette would take 6 bytes, the texels 4.
        let tiny = texture([1, 0], [true, false], vec![0xF800, 0x001F]);
        let mut bytes = Vec::new();
        assert_eq!(encode(&tiny, &mut bytes), (texture_flags::CLAMP_S, 0));
        assert_eq!(bytes, [0x00, 0xF8, 0x1F, 0x00]);
        // 4 texels of 2 colours: 8 bytes either way, so the texels.
        let even = texture([1, 1], [false, true], vec![1, 2, 2, 1]);
        let mut bytes = Vec::new();
        assert_eq!(encode(&even, &mut bytes), (texture_flags::CLAMP_T, 0));
        assert_eq!(bytes.len(), 8);
        // 1024 texels: 256 colours fit a palette, 257 do not; 512 texels of 256 colours take
        // 1024 bytes either way, so the texels.
        for (log2, colours, palette) in [(10, 256u16, true), (10, 257, false), (9, 256, false)] {
            let texels = (0..1 << log2).map(|i| i % colours).collect();
            let t = texture([log2, 0], [true; 2], texels);
            let mut bytes = Vec::new();
            let (flags, n) = encode(&t, &mut bytes);
            assert_eq!(
                flags & texture_flags::PALETTE != 0,
                palette,
                "{log2} {colours}"
            );
            assert_eq!(flags & texture_flags::CLAMP_S, texture_flags::CLAMP_S);
            assert_eq!(bytes.len(), texture_bytes(log2, 0, flags, n));
        }
    }

    /// Only the textures polygons use are stored, in order of first use, each at the end of
    /// the one before.
    #[test]
    fn textures_are_renumbered_in_order_of_first_use() {
        let textures = [
            texture([0, 0], [false; 2], vec![1]),
            texture([1, 1], [false; 2], vec![1, 2, 3, 4]),
            texture([2, 2], [false; 2], vec![5; 16]),
        ];
        assert_eq!(store(&textures, &[NO_TEXTURE; 3]).unwrap(), None);
        let stored = store(&textures, &[NO_TEXTURE, 2, 1, 2, NO_TEXTURE])
            .unwrap()
            .unwrap();
        assert_eq!(stored.polygons, [NO_TEXTURE, 0, 1, 0, NO_TEXTURE]);
        let records: Vec<(u8, u8, u32)> = (stored.records.iter())
            .map(|r| (r.log2_width, r.colours_minus_one, r.offset))
            .collect();
        // Texture 2: one colour, palette (2 + 16 bytes); texture 1: texels (8 bytes).
        assert_eq!(records, [(2, 0, 0), (1, 0, 18)]);
        assert_eq!(stored.texels.len(), 26);
        let e = store(&textures, &[3]).unwrap_err();
        assert!(matches!(e, CompileError::Invariant(_)), "{e:?}");
    }
}
