//! The `.peel` file as Rust types. `formats/peel.md` specifies the same bytes; bincode 2 with
//! [`config`] (fixed-width little-endian integers, `u64` sequence lengths) writes them.
//!
//! Layout rule: every record type has a fixed size within one file, so the runtime reads any
//! element in place. The header flags choose some sizes (index width, colour field, node
//! bounds), so [`PeelFile`] is (de)serialised by hand: the flags read first decide how the
//! arrays that follow are encoded.

use serde::de::{self, DeserializeSeed, SeqAccess, Visitor};
use serde::ser::{self, SerializeSeq, SerializeTuple};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

// The constants and the header live in the runtime's reader so that writer and reader cannot
// disagree: the header is written as the bytes of `Header::to_bytes`.
pub use peel_runtime::read::layout::{
    header_flags, node_kind, polygon_flags, FORMAT_VERSION, HEADER_SIZE, MAGIC, NONE,
};
pub use peel_runtime::read::Header;

/// The bincode configuration, pinned here and nowhere else.
pub fn config() -> impl bincode::config::Config {
    bincode::config::standard()
        .with_little_endian()
        .with_fixed_int_encoding()
}

/// A polygon's colour field: RGB, or an index into the palette (`u8` or `u16`), as the header
/// flags [`header_flags::PALETTE`] and [`header_flags::PALETTE16`] say.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColourField {
    /// Baked RGB888 colour (no palette).
    Rgb([u8; 3]),
    /// Palette index, `PALETTE` alone.
    Index8(u8),
    /// Palette index, `PALETTE | PALETTE16`.
    Index16(u16),
}

/// A convex polygon (14, 13 or 12 bytes, depending on its colour field).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Polygon {
    /// Index into `planes` of its support plane.
    pub plane: u32,
    /// First of its `vertex_count` entries in `indices`.
    pub first_index: u32,
    /// Number of vertices (>= 3).
    pub vertex_count: u16,
    /// [`polygon_flags`].
    pub flags: u8,
    /// Colour or palette index; its variant must match the header flags.
    pub colour: ColourField,
}

/// A node of the display tree (17 bytes, 21 with [`header_flags::BOUNDS`]); see [`node_kind`]
/// for the meaning of `a`, `b`, `c`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Node {
    /// [`node_kind`].
    pub kind: u8,
    /// First field.
    pub a: u32,
    /// Second field.
    pub b: u32,
    /// Third field.
    pub c: u32,
    /// The node whose child this is ([`NONE`] for the root). Lets the reader check that the
    /// links form a tree, and measure its depth, without memory of its own.
    pub parent: u32,
    /// Index into `bounds` of the subtree's box, or [`NONE`]. Written only with
    /// [`header_flags::BOUNDS`] (and must then be [`NONE`] without it).
    pub bounds: u32,
}

/// A whole `.peel` file: the header, then flat arrays (each a `u64` length then its records).
#[derive(Debug, Clone, PartialEq)]
pub struct PeelFile {
    /// Header.
    pub header: Header,
    /// Vertex positions relative to `header.centre`.
    pub vertices: Vec<[f32; 3]>,
    /// Planes `n · p = d` as `[nx, ny, nz, d]`, unit normal, relative to `header.centre`.
    pub planes: Vec<[f32; 4]>,
    /// Polygon vertex lists, concatenated; written as `u16` with [`header_flags::INDEX16`].
    pub indices: Vec<u32>,
    /// Polygons, in the order of the convex nodes that own them; their vertex lists are
    /// consecutive in `indices`.
    pub polygons: Vec<Polygon>,
    /// Source triangle id per polygon when `header_flags::IDS` is set, else empty.
    pub ids: Vec<u32>,
    /// Palette colours when `header_flags::PALETTE` is set, else empty.
    pub palette: Vec<[u8; 3]>,
    /// Node bounding boxes `[min, max]` when `header_flags::BOUNDS` is set, else empty.
    pub bounds: Vec<[f32; 6]>,
    /// Nodes in pre-order (front before back): the root is node 0 and children come after
    /// their parents. Convex nodes own the polygons in node order.
    pub nodes: Vec<Node>,
}

/// Fields of [`PeelFile`] in file order.
const FILE_FIELDS: usize = 10;

impl Serialize for PeelFile {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let flags = self.header.flags;
        let mut t = s.serialize_tuple(FILE_FIELDS)?;
        t.serialize_element(&header_words(&self.header))?;
        t.serialize_element(&self.vertices)?;
        t.serialize_element(&self.planes)?;
        t.serialize_element(&Records(&self.indices, flags))?;
        t.serialize_element(&Records(&self.polygons, flags))?;
        t.serialize_element(&self.ids)?;
        t.serialize_element(&self.palette)?;
        t.serialize_element(&self.bounds)?;
        t.serialize_element(&Records(&self.nodes, flags))?;
        t.end()
    }
}

/// The header's bytes as serde sees them: [`HEADER_SIZE`] / 4 arrays of 4 bytes (serde's
/// arrays stop at 32 elements). Bincode writes an array as its elements alone, so these are the
/// bytes of [`Header::to_bytes`].
type HeaderWords = [[u8; 4]; HEADER_SIZE / 4];

const _: () = assert!(
    HEADER_SIZE / 4 * 4 == HEADER_SIZE,
    "the header is whole words"
);

fn header_words(header: &Header) -> HeaderWords {
    let bytes = header.to_bytes();
    std::array::from_fn(|k| {
        [
            bytes[4 * k],
            bytes[4 * k + 1],
            bytes[4 * k + 2],
            bytes[4 * k + 3],
        ]
    })
}

/// The header of `words`, when they start with [`MAGIC`].
fn header_of<E: de::Error>(words: HeaderWords) -> Result<Header, E> {
    let bytes: [u8; HEADER_SIZE] = words.as_flattened().try_into().map_err(E::custom)?;
    if !bytes.starts_with(&MAGIC) {
        return Err(E::custom("not a .peel file (magic)"));
    }
    Ok(Header::from_bytes(&bytes))
}

/// A record whose encoding depends on the header flags.
trait Flagged: Sized {
    fn write<S: Serializer>(&self, flags: u16, s: S) -> Result<S::Ok, S::Error>;
    fn read<'de, A: SeqAccess<'de>>(flags: u16, seq: &mut A) -> Result<Option<Self>, A::Error>;
}

/// An array of flag-dependent records, with its `u64` length.
struct Records<'a, T>(&'a [T], u16);

/// One flag-dependent record.
struct Record<'a, T>(&'a T, u16);

impl<T: Flagged> Serialize for Records<'_, T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.0.len()))?;
        for item in self.0 {
            seq.serialize_element(&Record(item, self.1))?;
        }
        seq.end()
    }
}

impl<T: Flagged> Serialize for Record<'_, T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.write(self.1, s)
    }
}

impl Flagged for u32 {
    fn write<S: Serializer>(&self, flags: u16, s: S) -> Result<S::Ok, S::Error> {
        if flags & header_flags::INDEX16 == 0 {
            return s.serialize_u32(*self);
        }
        let narrow = u16::try_from(*self)
            .map_err(|_| ser::Error::custom(format!("index {self} does not fit INDEX16")))?;
        s.serialize_u16(narrow)
    }
    fn read<'de, A: SeqAccess<'de>>(flags: u16, seq: &mut A) -> Result<Option<Self>, A::Error> {
        if flags & header_flags::INDEX16 == 0 {
            seq.next_element::<u32>()
        } else {
            Ok(seq.next_element::<u16>()?.map(u32::from))
        }
    }
}

/// The colour field the header flags call for.
fn colour_kind(flags: u16) -> fn(ColourField) -> bool {
    if flags & header_flags::PALETTE == 0 {
        |c| matches!(c, ColourField::Rgb(_))
    } else if flags & header_flags::PALETTE16 == 0 {
        |c| matches!(c, ColourField::Index8(_))
    } else {
        |c| matches!(c, ColourField::Index16(_))
    }
}

impl Flagged for Polygon {
    fn write<S: Serializer>(&self, flags: u16, s: S) -> Result<S::Ok, S::Error> {
        if !colour_kind(flags)(self.colour) {
            return Err(ser::Error::custom(format!(
                "colour field {:?} disagrees with header flags {flags:#x}",
                self.colour
            )));
        }
        let mut t = s.serialize_tuple(5)?;
        t.serialize_element(&self.plane)?;
        t.serialize_element(&self.first_index)?;
        t.serialize_element(&self.vertex_count)?;
        t.serialize_element(&self.flags)?;
        match self.colour {
            ColourField::Rgb(rgb) => t.serialize_element(&rgb)?,
            ColourField::Index8(k) => t.serialize_element(&k)?,
            ColourField::Index16(k) => t.serialize_element(&k)?,
        }
        t.end()
    }
    fn read<'de, A: SeqAccess<'de>>(flags: u16, seq: &mut A) -> Result<Option<Self>, A::Error> {
        let Some(plane) = seq.next_element::<u32>()? else {
            return Ok(None);
        };
        let first_index = required(seq.next_element()?)?;
        let vertex_count = required(seq.next_element()?)?;
        let polygon_flags = required(seq.next_element()?)?;
        let colour = if flags & header_flags::PALETTE == 0 {
            ColourField::Rgb(required(seq.next_element()?)?)
        } else if flags & header_flags::PALETTE16 == 0 {
            ColourField::Index8(required(seq.next_element()?)?)
        } else {
            ColourField::Index16(required(seq.next_element()?)?)
        };
        Ok(Some(Polygon {
            plane,
            first_index,
            vertex_count,
            flags: polygon_flags,
            colour,
        }))
    }
}

impl Flagged for Node {
    fn write<S: Serializer>(&self, flags: u16, s: S) -> Result<S::Ok, S::Error> {
        let with_bounds = flags & header_flags::BOUNDS != 0;
        if !with_bounds && self.bounds != NONE {
            return Err(ser::Error::custom("node bounds without the BOUNDS flag"));
        }
        let mut t = s.serialize_tuple(if with_bounds { 6 } else { 5 })?;
        t.serialize_element(&self.kind)?;
        t.serialize_element(&self.a)?;
        t.serialize_element(&self.b)?;
        t.serialize_element(&self.c)?;
        t.serialize_element(&self.parent)?;
        if with_bounds {
            t.serialize_element(&self.bounds)?;
        }
        t.end()
    }
    fn read<'de, A: SeqAccess<'de>>(flags: u16, seq: &mut A) -> Result<Option<Self>, A::Error> {
        let Some(kind) = seq.next_element::<u8>()? else {
            return Ok(None);
        };
        Ok(Some(Node {
            kind,
            a: required(seq.next_element()?)?,
            b: required(seq.next_element()?)?,
            c: required(seq.next_element()?)?,
            parent: required(seq.next_element()?)?,
            bounds: if flags & header_flags::BOUNDS != 0 {
                required(seq.next_element()?)?
            } else {
                NONE
            },
        }))
    }
}

/// A field that must follow the first one of its record.
fn required<T, E: de::Error>(value: Option<T>) -> Result<T, E> {
    value.ok_or_else(|| E::custom("record ends early"))
}

/// Reads one flag-dependent record, as a tuple of its fields (records have no length prefix).
struct RecordSeed<T>(u16, std::marker::PhantomData<T>);

/// Reads an array of flag-dependent records.
struct RecordsSeed<T>(u16, std::marker::PhantomData<T>);

/// Fields of the widest record ([`Node`] with bounds); bincode reads a tuple field by field, so
/// the exact count is not needed, only an upper bound.
const MAX_RECORD_FIELDS: usize = 6;

impl<'de, T: Flagged> DeserializeSeed<'de> for RecordSeed<T> {
    type Value = T;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<T, D::Error> {
        struct V<T>(u16, std::marker::PhantomData<T>);
        impl<'de, T: Flagged> Visitor<'de> for V<T> {
            type Value = T;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a record")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<T, A::Error> {
                T::read(self.0, &mut seq)?.ok_or_else(|| de::Error::custom("empty record"))
            }
        }
        d.deserialize_tuple(MAX_RECORD_FIELDS, V(self.0, self.1))
    }
}

impl<'de, T: Flagged> DeserializeSeed<'de> for RecordsSeed<T> {
    type Value = Vec<T>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Vec<T>, D::Error> {
        struct V<T>(u16, std::marker::PhantomData<T>);
        impl<'de, T: Flagged> Visitor<'de> for V<T> {
            type Value = Vec<T>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an array of records")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
                let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 16));
                while let Some(item) =
                    seq.next_element_seed(RecordSeed::<T>(self.0, std::marker::PhantomData))?
                {
                    out.push(item);
                }
                Ok(out)
            }
        }
        d.deserialize_seq(V(self.0, self.1))
    }
}

impl<'de> Deserialize<'de> for PeelFile {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<PeelFile, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = PeelFile;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a .peel file")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<PeelFile, A::Error> {
                let header = header_of(required(seq.next_element()?)?)?;
                let flags = header.flags;
                Ok(PeelFile {
                    header,
                    vertices: required(seq.next_element()?)?,
                    planes: required(seq.next_element()?)?,
                    indices: required(
                        seq.next_element_seed(RecordsSeed(flags, std::marker::PhantomData))?,
                    )?,
                    polygons: required(
                        seq.next_element_seed(RecordsSeed(flags, std::marker::PhantomData))?,
                    )?,
                    ids: required(seq.next_element()?)?,
                    palette: required(seq.next_element()?)?,
                    bounds: required(seq.next_element()?)?,
                    nodes: required(
                        seq.next_element_seed(RecordsSeed(flags, std::marker::PhantomData))?,
                    )?,
                })
            }
        }
        d.deserialize_tuple(FILE_FIELDS, V)
    }
}
