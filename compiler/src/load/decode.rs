//! Texture images decoded (PNG and JPEG, with the `textures` feature) and brought to the sides a
//! file stores: powers of two, at most the limit, resampled when they are not (or refused,
//! without resampling).

use std::path::Path;

use crate::error::CompileError;

/// Where a texture is named: its image and the `map_Kd` statement, for messages.
#[derive(Debug, Clone, Copy)]
pub(super) struct Site<'a> {
    /// The image file.
    pub image: &'a Path,
    /// The MTL file.
    pub mtl: &'a Path,
    /// 1-based line of the `map_Kd` statement.
    pub line: usize,
}

/// An image as a file stores it: `2^log2_width x 2^log2_height` RGB565 texels, row 0 the top.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Texels {
    pub log2_width: u8,
    pub log2_height: u8,
    pub texels: Vec<u16>,
}

/// The side a texture of `n` texels gets: `n` when it is a power of two of at most `max`, else
/// the power of two nearest to it in ratio (of the two around it, the one `n` is fewer times
/// off), at most `max`.
#[cfg(feature = "textures")]
fn side(n: u32, max: u32) -> u32 {
    if n.is_power_of_two() && n <= max {
        return n;
    }
    let below = 1u64 << (31 - n.max(1).leading_zeros());
    // `n` is nearer `2 below` than `below` in ratio when `n / below > 2 below / n`.
    let n = u64::from(n);
    let nearest = if n * n > 2 * below * below {
        2 * below
    } else {
        below
    };
    nearest.min(u64::from(max)) as u32
}

/// The image file at `site`: its bytes (for the build's cache) and its texels, sides at most
/// `max` (a power of two): resampled to [`side`]s when `resample`, else refused unless its
/// sides are already such.
#[cfg(feature = "textures")]
pub(super) fn read(
    site: Site<'_>,
    max: u32,
    resample: bool,
) -> Result<(Vec<u8>, Texels), CompileError> {
    use image::imageops::{resize, FilterType};
    use peel_runtime::display::Colour;

    let bytes = read_file(site)?;
    let failed = |message: String| CompileError::TextureImage {
        image: site.image.to_path_buf(),
        mtl: site.mtl.to_path_buf(),
        line: site.line,
        message,
    };
    let decoded = image::ImageReader::new(std::io::Cursor::new(&bytes))
        .with_guessed_format()
        .map_err(|e| failed(e.to_string()))?
        .decode()
        .map_err(|e| failed(e.to_string()))?;
    let (width, height) = (decoded.width(), decoded.height());
    let (w, h) = (side(width, max), side(height, max));
    if (w, h) != (width, height) && !resample {
        return Err(CompileError::TextureSize {
            image: site.image.to_path_buf(),
            mtl: site.mtl.to_path_buf(),
            line: site.line,
            width,
            height,
            max,
        });
    }
    let mut rgb = decoded.into_rgb8();
    if (w, h) != (width, height) {
        rgb = resize(&rgb, w, h, FilterType::Lanczos3);
    }
    let texels = rgb
        .pixels()
        .map(|p| Colour::new(p[0], p[1], p[2]).to_rgb565())
        .collect();
    let texels = Texels {
        log2_width: w.trailing_zeros() as u8,
        log2_height: h.trailing_zeros() as u8,
        texels,
    };
    Ok((bytes, texels))
}

/// The bytes of the image file at `site`, refusing one over [`super::MAX_INPUT_BYTES`].
#[cfg(feature = "textures")]
fn read_file(site: Site<'_>) -> Result<Vec<u8>, CompileError> {
    let io = |source| CompileError::TextureFile {
        image: site.image.to_path_buf(),
        mtl: site.mtl.to_path_buf(),
        line: site.line,
        source,
    };
    let size = std::fs::metadata(site.image).map_err(io)?.len();
    super::check_size(site.image, size)?;
    let bytes = std::fs::read(site.image).map_err(io)?;
    super::check_size(site.image, bytes.len() as u64)?;
    Ok(bytes)
}

/// Without the `textures` feature no image is read: a textured face is an error.
#[cfg(not(feature = "textures"))]
pub(super) fn read(
    site: Site<'_>,
    _max: u32,
    _resample: bool,
) -> Result<(Vec<u8>, Texels), CompileError> {
    Err(CompileError::TexturesOff {
        image: site.image.to_path_buf(),
        mtl: site.mtl.to_path_buf(),
        line: site.line,
    })
}

#[cfg(all(test, feature = "textures"))]
mod tests {
    use super::*;

    #[test]
    fn a_side_is_kept_when_it_may_be_stored_else_the_nearest_power_of_two() {
        assert_eq!(side(64, 256), 64);
        assert_eq!(side(1, 256), 1);
        assert_eq!(side(512, 256), 256);
        // 300 is 1.17 times 256 and 1.71 times short of 512; 384 is nearer 512 (1.33 against
        // 1.5).
        assert_eq!(side(300, 1024), 256);
        assert_eq!(side(362, 1024), 256);
        assert_eq!(side(363, 1024), 512);
        assert_eq!(side(384, 1024), 512);
        assert_eq!(side(3, 1024), 4);
        assert_eq!(side(5, 1024), 4);
        assert_eq!(side(1000, 256), 256);
        assert_eq!(side(u32::MAX, 1024), 1024);
    }
}
