//! A file of parts ([`layout::PARTS_VERSION`]): a world and named objects, each its own tree
//! ([`Scene`]), read in place and validated up front; a plain tree file reads as a world with
//! no objects, so one reader serves both.

use super::layout::{self, parts_offset, u16_at, u32_at, MAGIC, PART_ENTRY_SIZE};
use super::Scene;
use crate::error::ReadError;

/// A validated file of parts borrowed from its bytes (or a plain tree: a world alone).
#[derive(Debug, Clone, Copy)]
pub struct Parts<'a> {
    bytes: &'a [u8],
    /// Entries of the part table; 0 for a plain tree file.
    count: u32,
    /// Part 0 is the world (always, for a plain tree file).
    world: bool,
}

/// One entry of the part table: the tree's and the name's byte ranges.
#[derive(Debug, Clone, Copy)]
struct Entry {
    tree: (usize, usize),
    name: (usize, usize),
}

impl<'a> Parts<'a> {
    /// Read a file of parts, checking its table, its names and every part's tree as
    /// [`Scene::parse`] does; a plain tree file is a world with no objects.
    pub fn parse(bytes: &'a [u8]) -> Result<Parts<'a>, ReadError> {
        Self::read(bytes, Scene::parse)
    }

    /// [`Parts::parse`] with each tree read by [`Scene::parse_trusted`]: for a file that
    /// [`Parts::parse`] accepted elsewhere (a build script).
    pub fn parse_trusted(bytes: &'a [u8]) -> Result<Parts<'a>, ReadError> {
        Self::read(bytes, Scene::parse_trusted)
    }

    fn read(
        bytes: &'a [u8],
        tree: fn(&'a [u8]) -> Result<Scene<'a>, ReadError>,
    ) -> Result<Parts<'a>, ReadError> {
        if bytes.get(..4) != Some(&MAGIC[..]) {
            return Err(ReadError::BadMagic);
        }
        let version = u16_at(bytes, 4).ok_or(ReadError::Truncated { offset: 4 })?;
        if version != layout::PARTS_VERSION {
            tree(bytes)?;
            return Ok(Parts {
                bytes,
                count: 0,
                world: true,
            });
        }
        let field = |offset: usize| u32_at(bytes, offset).ok_or(ReadError::Truncated { offset });
        let flags = u16_at(bytes, parts_offset::FLAGS).ok_or(ReadError::Truncated {
            offset: parts_offset::FLAGS,
        })?;
        if flags != 0 {
            return Err(ReadError::UnknownFlags { flags });
        }
        let count = field(parts_offset::COUNT)?;
        let world = field(parts_offset::WORLD)?;
        if count == 0 || count > layout::MAX_PARTS {
            return Err(ReadError::BadRecord {
                offset: parts_offset::COUNT,
            });
        }
        if world > 1 {
            return Err(ReadError::BadRecord {
                offset: parts_offset::WORLD,
            });
        }
        let parts = Parts {
            bytes,
            count,
            world: world == 1,
        };
        for k in 0..count {
            let at = parts_offset::TABLE + k as usize * PART_ENTRY_SIZE;
            let entry = parts.entry(k).ok_or(ReadError::Truncated { offset: at })?;
            let (start, len) = entry.tree;
            let slice = bytes
                .get(start..start.saturating_add(len))
                .filter(|_| start % 4 == 0)
                .ok_or(ReadError::BadRecord { offset: at })?;
            tree(slice).map_err(|e| e.in_part(k, start))?;
            let is_world = parts.world && k == 0;
            let name = parts
                .name_of(&entry)
                .ok_or(ReadError::BadName { offset: at })?;
            let fits = name.len() <= layout::MAX_NAME as usize;
            if is_world != name.is_empty() || !fits {
                return Err(ReadError::BadName { offset: at });
            }
            let repeated = (0..k).any(|j| {
                let other = parts.entry(j).and_then(|e| parts.name_of(&e));
                !name.is_empty() && other == Some(name)
            });
            if repeated {
                return Err(ReadError::BadName { offset: at });
            }
        }
        Ok(parts)
    }

    fn entry(&self, k: u32) -> Option<Entry> {
        if k >= self.count {
            return None;
        }
        let at = parts_offset::TABLE + k as usize * PART_ENTRY_SIZE;
        let field = |i: usize| u32_at(self.bytes, at + 4 * i).map(|v| v as usize);
        Some(Entry {
            tree: (field(0)?, field(1)?),
            name: (field(2)?, field(3)?),
        })
    }

    fn name_of(&self, entry: &Entry) -> Option<&'a str> {
        let (start, len) = entry.name;
        let bytes = self.bytes.get(start..start.checked_add(len)?)?;
        core::str::from_utf8(bytes).ok()
    }

    /// The tree of table entry `k`, trusted: [`Parts::parse`] checked it.
    fn tree(&self, k: u32) -> Option<Scene<'a>> {
        let (start, len) = self.entry(k)?.tree;
        Scene::parse_trusted(self.bytes.get(start..start.checked_add(len)?)?).ok()
    }

    /// Whether the file is a file of parts (else a plain tree: a world alone).
    pub fn has_table(&self) -> bool {
        self.count > 0
    }

    /// The world's tree, if the file has one.
    pub fn world(&self) -> Option<Scene<'a>> {
        match (self.count, self.world) {
            (0, _) => Scene::parse_trusted(self.bytes).ok(),
            (_, true) => self.tree(0),
            _ => None,
        }
    }

    /// Number of objects.
    pub fn object_count(&self) -> u32 {
        self.count
            .saturating_sub(u32::from(self.world && self.count > 0))
    }

    /// Object `k` (in the order the compiler was given them): its name and its tree.
    pub fn object(&self, k: u32) -> Option<(&'a str, Scene<'a>)> {
        if k >= self.object_count() {
            return None;
        }
        let entry = k + u32::from(self.world);
        let name = self.entry(entry).and_then(|e| self.name_of(&e))?;
        Some((name, self.tree(entry)?))
    }

    /// The object named `name`, with its index.
    pub fn find(&self, name: &str) -> Option<(u32, Scene<'a>)> {
        (0..self.object_count()).find_map(|k| {
            let (n, scene) = self.object(k)?;
            (n == name).then_some((k, scene))
        })
    }
}
