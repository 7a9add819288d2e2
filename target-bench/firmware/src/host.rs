//! What QEMU and the host provide: the config block and the asset in code memory (loaded by
//! `-device loader`, see [`peel_target_kit::layout`]) and host files through semihosting.

use core::fmt::Write;

use cortex_m_semihosting::nr::open::W_TRUNC_BINARY;
use cortex_m_semihosting::syscall;
use peel_target_kit::config;
use peel_target_kit::layout::{ASSET_ADDR, CONFIG_ADDR, MAX_ASSET};

use crate::Failure;

/// The config block's bytes.
pub fn config_block() -> &'static [u8] {
    // SAFETY: code memory the firmware does not link into (memory.x); QEMU loaded it before
    // reset and nothing writes it.
    unsafe { core::slice::from_raw_parts(CONFIG_ADDR as *const u8, config::SIZE) }
}

/// The asset: the first `len` bytes at [`ASSET_ADDR`] (at most [`MAX_ASSET`]).
pub fn asset(len: u32) -> &'static [u8] {
    let len = len.min(MAX_ASSET) as usize;
    // SAFETY: as for the config block.
    unsafe { core::slice::from_raw_parts(ASSET_ADDR as *const u8, len) }
}

/// A file name built without an allocator, nul-terminated as semihosting wants it.
struct Name {
    bytes: [u8; 32],
    len: usize,
}

impl Write for Name {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        let end = self.len + s.len();
        // Keep one byte for the nul.
        let slot = self.bytes.get_mut(self.len..end).filter(|_| end < 32);
        slot.ok_or(core::fmt::Error)?.copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

/// Write `pixels` (RGB565, little-endian) to the host file `frame-<k>.rgb565` in QEMU's
/// working directory.
pub fn write_frame(k: usize, pixels: &[u16]) -> Result<(), Failure> {
    let mut name = Name {
        bytes: [0; 32],
        len: 0,
    };
    write!(name, "frame-{k}.rgb565\0").map_err(|_| Failure::Host("file name"))?;
    let name =
        core::str::from_utf8(&name.bytes[..name.len]).map_err(|_| Failure::Host("file name"))?;
    // SAFETY: SYS_OPEN reads the nul-terminated name (length without the nul).
    let fd = unsafe { syscall!(OPEN, name.as_ptr(), W_TRUNC_BINARY, name.len() - 1) };
    if fd as isize == -1 {
        return Err(Failure::Host("open frame file"));
    }
    let mut chunk = [0u8; 512];
    for pixels in pixels.chunks(chunk.len() / 2) {
        for (bytes, p) in chunk.chunks_exact_mut(2).zip(pixels) {
            bytes.copy_from_slice(&p.to_le_bytes());
        }
        let bytes = &chunk[..2 * pixels.len()];
        // SAFETY: SYS_WRITE reads `bytes`; it returns the count not written (0: all).
        if unsafe { syscall!(WRITE, fd, bytes.as_ptr(), bytes.len()) } != 0 {
            return Err(Failure::Host("write frame file"));
        }
    }
    // SAFETY: SYS_CLOSE of the handle opened above.
    if unsafe { syscall!(CLOSE, fd) } != 0 {
        return Err(Failure::Host("close frame file"));
    }
    Ok(())
}
