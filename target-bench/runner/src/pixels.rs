//! Pixels to compare: the host's PNG frames as RGB565 ([`Colour::to_rgb565`], exactly what the
//! target's framebuffers and display adapter store) and the panel memory the firmware wrote.

use std::path::Path;

use peel_runtime::display::Colour;

/// A PNG file's pixels as RGB565, checked to be `width x height`.
pub fn png_rgb565(path: &Path, width: u32, height: u32) -> Result<Vec<u16>, String> {
    let image = image::open(path)
        .map_err(|e| format!("{}: cannot decode: {e}", path.display()))?
        .to_rgb8();
    if image.dimensions() != (width, height) {
        return Err(format!(
            "{}: {}x{} pixels, {width}x{height} expected",
            path.display(),
            image.width(),
            image.height()
        ));
    }
    Ok(image
        .pixels()
        .map(|p| Colour::new(p[0], p[1], p[2]).to_rgb565())
        .collect())
}

/// A frame file of the firmware: `pixels` little-endian RGB565 values.
pub fn frame_file(path: &Path, pixels: usize) -> Result<Vec<u16>, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    decode_frame(&bytes, pixels).map_err(|e| format!("{}: {e}", path.display()))
}

fn decode_frame(bytes: &[u8], pixels: usize) -> Result<Vec<u16>, String> {
    if bytes.len() != 2 * pixels {
        return Err(format!(
            "{} bytes, {} expected ({pixels} RGB565 pixels)",
            bytes.len(),
            2 * pixels
        ));
    }
    Ok(bytes
        .chunks_exact(2)
        .map(|b| u16::from_le_bytes([b[0], b[1]]))
        .collect())
}

/// Pixels whose values differ (the frames being the same size).
pub fn differing(a: &[u16], b: &[u16]) -> u64 {
    let unequal = a.iter().zip(b).filter(|(x, y)| x != y).count();
    (unequal + a.len().abs_diff(b.len())) as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_decode_little_endian() {
        assert_eq!(
            decode_frame(&[0x1f, 0xf8, 0, 0], 2).unwrap(),
            vec![0xf81f, 0]
        );
        assert!(decode_frame(&[0; 3], 2).unwrap_err().contains("3 bytes"));
    }

    #[test]
    fn counts_differences_bit_for_bit() {
        assert_eq!(differing(&[1, 2, 3], &[1, 2, 3]), 0);
        assert_eq!(differing(&[1, 2, 3], &[1, 0, 4]), 2);
        // A missing pixel differs too.
        assert_eq!(differing(&[1, 2, 3], &[1, 2]), 1);
    }

    #[test]
    fn png_round_trip_as_rgb565() {
        let dir = std::env::temp_dir().join(format!("peel-target-pixels-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("two.png");
        let rgb = [255, 0, 0, 24, 26, 32];
        image::save_buffer(&path, &rgb, 2, 1, image::ExtendedColorType::Rgb8).unwrap();
        let pixels = png_rgb565(&path, 2, 1).unwrap();
        assert_eq!(pixels, vec![0xf800, Colour::new(24, 26, 32).to_rgb565()]);
        assert!(png_rgb565(&path, 1, 2).unwrap_err().contains("2x1 pixels"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
