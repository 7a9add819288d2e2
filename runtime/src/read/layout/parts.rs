//! A file of parts (format [`PARTS_VERSION`]): a world and named objects, each a complete
//! tree file of [`FORMAT_VERSION`](super::FORMAT_VERSION) compiled in its own frame, which the
//! renderer places by a pose per frame. A scene with no object is written as its tree alone.
//!
//! ```text
//! 0   magic "PEEL"
//! 4   u16 version (PARTS_VERSION)
//! 6   u16 flags (none defined: 0)
//! 8   u32 part count (1 ..= MAX_PARTS)
//! 12  u32 world: 1 when part 0 is the world, else 0
//! 16  part table, PART_ENTRY_SIZE bytes each:
//!       u32 tree offset, u32 tree length   (from the file's start)
//!       u32 name offset, u32 name length   (UTF-8; empty for the world, 1 ..= MAX_NAME
//!                                            bytes for an object, names distinct)
//! ... names, then trees (each at an offset that is a multiple of 4)
//! ```

/// The version of a file of parts.
pub const PARTS_VERSION: u16 = 5;
/// Bytes before the part table.
pub const PARTS_HEADER_SIZE: usize = 16;
/// Bytes of one entry of the part table.
pub const PART_ENTRY_SIZE: usize = 16;
/// Most parts a file holds (the world and the objects).
pub const MAX_PARTS: u32 = 32;
/// Longest object name, in bytes.
pub const MAX_NAME: u32 = 64;

/// Byte offsets of the fields of a file of parts.
pub mod parts_offset {
    /// `u16` flags.
    pub const FLAGS: usize = 6;
    /// `u32` part count.
    pub const COUNT: usize = 8;
    /// `u32` 1 when part 0 is the world.
    pub const WORLD: usize = 12;
    /// The part table.
    pub const TABLE: usize = super::PARTS_HEADER_SIZE;
}
