//! Textures (format [`TEXTURED_VERSION`]): the constants of the four arrays a textured file
//! ends with, after the nodes (and the shades): `uvs`, `textures`, `texels` and
//! `polygon_textures` (see `formats/peel.md`, "Textures").

/// The format version of a file with textures ([`TEXTURES`](super::header_flags::TEXTURES)):
/// the tree format of [`FORMAT_VERSION`](super::FORMAT_VERSION) with the texture arrays. A file
/// without textures keeps version 4, byte for byte.
pub const TEXTURED_VERSION: u16 = 6;

/// Bytes of a vertex's texture coordinates: `[i32; 2]`, `s` then `t`.
pub const UV_SIZE: usize = 8;

/// Fraction bits of a texture coordinate: `2^UV_FRACTION_BITS` is the texture's whole width
/// (`s`) or height (`t`). `t = 0` is the image's top edge (an OBJ's `v = 1`), so that a texel's
/// row is its row in the stored image.
pub const UV_FRACTION_BITS: u32 = 16;

/// Bytes of a texture record: `log2_width`, `log2_height`, `flags`, `colours - 1` (a byte
/// each; the last only with [`texture_flags::PALETTE`], else 0), then the `u32` byte offset of
/// its texels in the `texels` array.
pub const TEXTURE_SIZE: usize = 8;

/// Largest `log2` of a texture's side: 1024 texels.
pub const MAX_TEXTURE_LOG2: u8 = 10;

/// Most textures in a file: a polygon names one with a byte, [`NO_TEXTURE`] excepted.
pub const MAX_TEXTURES: u32 = 255;

/// A polygon's texture byte when it has no texture.
pub const NO_TEXTURE: u8 = 0xFF;

/// Bytes of a texel: an RGB565 colour (`u16`, little endian), or with
/// [`texture_flags::PALETTE`] a `u8` index into the texture's colours, which precede its
/// texels (each an RGB565 `u16`).
pub const TEXEL_SIZE: usize = 2;

/// Bits of a texture record's `flags`.
pub mod texture_flags {
    /// Columns past the edges take the edge column (else the texture repeats across `s`).
    pub const CLAMP_S: u8 = 1 << 0;
    /// Rows past the edges take the edge row (else the texture repeats across `t`).
    pub const CLAMP_T: u8 = 1 << 1;
    /// The texels are `u8` indices into the texture's own colours (`colours - 1` in the
    /// record), stored first.
    pub const PALETTE: u8 = 1 << 2;
    /// Every bit this version defines; a reader refuses others.
    pub const KNOWN: u8 = CLAMP_S | CLAMP_T | PALETTE;
}

/// The bytes of a texture of `2^log2_width x 2^log2_height` texels with record `flags` and
/// `colours` palette entries (ignored without [`texture_flags::PALETTE`]).
pub const fn texture_bytes(log2_width: u8, log2_height: u8, flags: u8, colours: u32) -> usize {
    let texels = 1usize << (log2_width as u32 + log2_height as u32);
    if flags & texture_flags::PALETTE != 0 {
        colours as usize * TEXEL_SIZE + texels
    } else {
        texels * TEXEL_SIZE
    }
}
