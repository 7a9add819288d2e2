//! Field access: every read of the file's bytes goes through here, so none can panic. Little-
//! endian fields, a fixed-size record read with one bounds check ([`Record`]), the offsets of
//! array elements, and the values a link field holds for "no node".

/// "No node" in a child or parent field.
pub const NONE: u32 = u32::MAX;
/// "No node" (or "no box") in a `u16` field of a
/// [`header_flags::NARROW`](super::header_flags::NARROW) file.
pub const NONE16: u16 = u16::MAX;
/// "No node" (or "no box") in a `u24` field of a
/// [`header_flags::MEDIUM`](super::header_flags::MEDIUM) file.
pub const NONE24: u32 = (1 << 24) - 1;

/// "No node" in a field of `width` bytes: its largest value.
pub const fn none_of_width(width: usize) -> u32 {
    match width {
        2 => NONE16 as u32,
        3 => NONE24,
        _ => NONE,
    }
}

/// Bytes of an array length (`u64`).
pub const LENGTH_SIZE: usize = 8;

/// ARMv6-M (Cortex-M0+ class: no FPU, no long multiply, no divide), told apart by its lack of
/// compare-and-swap.
pub(crate) const ARMV6M: bool = cfg!(all(target_arch = "arm", not(target_has_atomic = "32")));

/// A fixed-size record read once (one bounds check), whose fields are then decoded at constant
/// offsets with no further check: the hot accessors read nodes, planes and polygons this way.
#[derive(Clone, Copy)]
pub(crate) struct Record<const N: usize>(pub(super) [u8; N]);

impl<const N: usize> Record<N> {
    /// The `N` bytes at `offset`, or `None` past the end (or on overflow).
    #[inline]
    pub(crate) fn at(bytes: &[u8], offset: usize) -> Option<Self> {
        array_at(bytes, offset).map(Record)
    }

    /// `W` bytes at `offset` (zero past the end: offsets are constants within `N`).
    #[inline]
    pub(super) fn bytes<const W: usize>(&self, offset: usize) -> [u8; W] {
        let mut out = [0u8; W];
        for (o, b) in out.iter_mut().zip(self.0.iter().skip(offset)) {
            *o = *b;
        }
        out
    }

    #[inline]
    pub(crate) fn u16(&self, offset: usize) -> u16 {
        u16::from_le_bytes(self.bytes(offset))
    }

    #[inline]
    pub(crate) fn f32(&self, offset: usize) -> f32 {
        f32::from_le_bytes(self.bytes(offset))
    }

    #[inline]
    pub(crate) fn u8(&self, offset: usize) -> u8 {
        self.0.get(offset).copied().unwrap_or(0)
    }

    #[inline]
    pub(crate) fn u32(&self, offset: usize) -> u32 {
        u32::from_le_bytes(self.bytes(offset))
    }

    /// A `u16` field, its [`NONE16`] read as [`NONE`] when `link`.
    #[inline]
    pub(crate) fn narrow(&self, offset: usize, link: bool) -> u32 {
        let v = self.u16(offset);
        if link && v == NONE16 {
            NONE
        } else {
            u32::from(v)
        }
    }

    /// A `u24` field, its [`NONE24`] read as [`NONE`] when `link`.
    #[inline]
    pub(crate) fn medium(&self, offset: usize, link: bool) -> u32 {
        let [a, b, c] = self.bytes::<3>(offset);
        let v = u32::from_le_bytes([a, b, c, 0]);
        if link && v == NONE24 {
            NONE
        } else {
            v
        }
    }
}

/// `N` bytes at `offset`, or `None` past the end (or on overflow).
fn array_at<const N: usize>(bytes: &[u8], offset: usize) -> Option<[u8; N]> {
    bytes.get(offset..offset.checked_add(N)?)?.try_into().ok()
}

pub(crate) fn u8_at(bytes: &[u8], offset: usize) -> Option<u8> {
    bytes.get(offset).copied()
}

pub(crate) fn u16_at(bytes: &[u8], offset: usize) -> Option<u16> {
    array_at(bytes, offset).map(u16::from_le_bytes)
}

/// A node field or a polygon's `first_index` of `width` bytes (2, 3 or 4), its
/// largest value read as [`NONE`] when `link`.
#[inline]
pub(crate) fn field_at(bytes: &[u8], offset: usize, width: usize, link: bool) -> Option<u32> {
    let mut le = [0u8; 4];
    let end = offset.checked_add(width.min(4))?;
    for (o, b) in le.iter_mut().zip(bytes.get(offset..end)?) {
        *o = *b;
    }
    let v = u32::from_le_bytes(le);
    Some(if link && v == none_of_width(width) {
        NONE
    } else {
        v
    })
}

pub(crate) fn u32_at(bytes: &[u8], offset: usize) -> Option<u32> {
    array_at(bytes, offset).map(u32::from_le_bytes)
}

pub(crate) fn u64_at(bytes: &[u8], offset: usize) -> Option<u64> {
    array_at(bytes, offset).map(u64::from_le_bytes)
}

pub(crate) fn f32_at(bytes: &[u8], offset: usize) -> Option<f32> {
    array_at(bytes, offset).map(f32::from_le_bytes)
}

pub(crate) fn f64_at(bytes: &[u8], offset: usize) -> Option<f64> {
    array_at(bytes, offset).map(f64::from_le_bytes)
}

/// Byte offset of element `index` of an array of `size`-byte records starting at `start`.
#[inline]
pub(crate) fn element(start: usize, size: usize, index: u32) -> Option<usize> {
    if ARMV6M {
        element_narrow(start, size, index)
    } else {
        usize::try_from(index)
            .ok()?
            .checked_mul(size)?
            .checked_add(start)
    }
}

/// [`element`] for ARMv6-M ([`ARMV6M`]), which has no
/// widening multiply: there `checked_mul` is a 64-bit library call on every record read.
/// Below 2^24 records of under 256 bytes the product fits 32 bits and needs no check.
#[inline]
pub(crate) fn element_narrow(start: usize, size: usize, index: u32) -> Option<usize> {
    let index = usize::try_from(index).ok()?;
    let offset = if index < 1 << 24 && size < 256 {
        index * size
    } else {
        index.checked_mul(size)?
    };
    offset.checked_add(start)
}
