//! Write: `DisplayTree` -> [`format::PeelFile`] -> bytes, and the atomic file write.

pub mod format;
