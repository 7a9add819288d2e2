//! Section sizes of a firmware ELF (32-bit, little-endian: both Cortex-M targets), read
//! directly so the runner needs no binutils.

/// A section's name and size in bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Section {
    /// Name, e.g. `.text`.
    pub name: String,
    /// Size in bytes.
    pub size: u64,
}

fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes(b.get(at..at + 2)?.try_into().ok()?))
}

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?))
}

/// The sections of an ELF32 little-endian file.
pub fn sections(bytes: &[u8]) -> Result<Vec<Section>, String> {
    if bytes.get(..6) != Some(&[0x7f, b'E', b'L', b'F', 1, 1][..]) {
        return Err("not a 32-bit little-endian ELF file".into());
    }
    let bad = || "truncated ELF section table".to_string();
    let table = u32_at(bytes, 0x20).ok_or_else(bad)? as usize;
    let entry = usize::from(u16_at(bytes, 0x2e).ok_or_else(bad)?);
    let count = usize::from(u16_at(bytes, 0x30).ok_or_else(bad)?);
    let names_index = usize::from(u16_at(bytes, 0x32).ok_or_else(bad)?);
    let header = |i: usize| -> Option<(u32, u32, u32)> {
        let at = table + i * entry;
        Some((
            u32_at(bytes, at)?,
            u32_at(bytes, at + 16)?,
            u32_at(bytes, at + 20)?,
        ))
    };
    let (_, names_at, names_len) = header(names_index).ok_or_else(bad)?;
    let names = bytes
        .get(names_at as usize..(names_at + names_len) as usize)
        .ok_or_else(bad)?;
    (0..count)
        .map(|i| {
            let (name, _, size) = header(i).ok_or_else(bad)?;
            let name = names.get(name as usize..).ok_or_else(bad)?;
            let end = name.iter().position(|&b| b == 0).unwrap_or(name.len());
            Ok(Section {
                name: String::from_utf8_lossy(&name[..end]).into_owned(),
                size: u64::from(size),
            })
        })
        .collect()
}

/// The size of section `name`, 0 when absent.
pub fn size(sections: &[Section], name: &str) -> u64 {
    sections
        .iter()
        .filter(|s| s.name == name)
        .map(|s| s.size)
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A minimal ELF32 with sections "", ".text" (0x1234 bytes) and ".shstrtab".
    fn tiny() -> Vec<u8> {
        let names = b"\0.text\0.shstrtab\0";
        let mut b = vec![0u8; 0x34];
        b[..6].copy_from_slice(&[0x7f, b'E', b'L', b'F', 1, 1]);
        let names_at = b.len() as u32;
        b.extend_from_slice(names);
        let table = b.len() as u32;
        b[0x20..0x24].copy_from_slice(&table.to_le_bytes());
        b[0x2e..0x30].copy_from_slice(&40u16.to_le_bytes());
        b[0x30..0x32].copy_from_slice(&3u16.to_le_bytes());
        b[0x32..0x34].copy_from_slice(&2u16.to_le_bytes());
        for (name, offset, size) in [
            (0u32, 0u32, 0u32),
            (1, 0, 0x1234),
            (7, names_at, names.len() as u32),
        ] {
            let mut h = [0u8; 40];
            h[..4].copy_from_slice(&name.to_le_bytes());
            h[16..20].copy_from_slice(&offset.to_le_bytes());
            h[20..24].copy_from_slice(&size.to_le_bytes());
            b.extend_from_slice(&h);
        }
        b
    }

    #[test]
    fn reads_names_and_sizes() {
        let s = sections(&tiny()).unwrap();
        assert_eq!(s.len(), 3);
        assert_eq!(size(&s, ".text"), 0x1234);
        assert_eq!(size(&s, ".shstrtab"), 17);
        assert_eq!(size(&s, ".data"), 0);
    }

    #[test]
    fn refuses_other_files() {
        assert!(sections(b"\x7fELF\x02\x01").is_err());
        let mut t = tiny();
        t.truncate(0x40);
        assert!(sections(&t).is_err());
    }
}
