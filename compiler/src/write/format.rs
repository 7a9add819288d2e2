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
use peel_runtime::read::layout::dequantise;
pub use peel_runtime::read::layout::{
    field_size, header_flags, node_kind, none_of_width, polygon_flags, FORMAT_VERSION, HEADER_SIZE,
    MAGIC, NONE, OPAQUE, TEXTURED_VERSION, TRANSPARENT_VERSION,
};
pub use peel_runtime::read::Header;

/// The bincode configuration, pinned here and nowhere else.
pub fn config() -> impl bincode::config::Config {
    bincode::config::standard()
        .with_little_endian()
        .with_fixed_int_encoding()
}

/// A vertex: steps on the header's bounds, or `f32` coordinates with
/// [`header_flags::WIDE_VERTICES`]. Its variant must match the header flags.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Vertex {
    /// Per axis, steps from the header's `bounds_min` to its `bounds_max`
    /// (`peel_runtime::read::layout::dequantise`).
    Grid([u16; 3]),
    /// Coordinates relative to `centre`.
    Wide([f32; 3]),
}

impl Vertex {
    /// The position the runtime reads, relative to the centre, on the header's bounds `lo`,
    /// `hi`.
    pub fn position(&self, lo: [f32; 3], hi: [f32; 3]) -> [f32; 3] {
        match *self {
            Vertex::Grid(q) => [0, 1, 2].map(|k| dequantise(lo[k], hi[k], q[k])),
            Vertex::Wide(v) => v,
        }
    }
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

/// A convex polygon (5 to 9 bytes, depending on the field width ([`header_flags::NARROW`],
/// [`header_flags::MEDIUM`]) and its colour field). Its support plane is the plane through its
/// first three vertices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Polygon {
    /// First of its `vertex_count` entries in `indices`.
    pub first_index: u32,
    /// Number of vertices (3 to 255).
    pub vertex_count: u8,
    /// [`polygon_flags`].
    pub flags: u8,
    /// Colour or palette index; its variant must match the header flags. With
    /// [`header_flags::TWO_COLOURS`] the interior side's, else both sides'.
    pub colour: ColourField,
    /// The exterior side's colour: present exactly with [`header_flags::TWO_COLOURS`].
    pub exterior: Option<ColourField>,
}

/// A node of the display tree (`1 + 3w` bytes, `1 + 4w` with [`header_flags::BOUNDS`], `w`
/// the field width: 2 with [`header_flags::NARROW`], 3 with [`header_flags::MEDIUM`], else 4).
/// `a`, `b`, `c` are a convex node's first polygon, count and child, a split's plane, + child
/// and - child. The first child (convex `c`, split `b`) must be [`NONE`] or the next node: it
/// is stored as the [`node_kind::FIRST_CHILD`] bit of the kind byte, not as a field.
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

/// A texture record (`TEXTURE_SIZE` = 8 bytes): its sides, flags and palette size, and where
/// its bytes start in [`PeelFile::texels`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct TextureRecord {
    /// `log2` of the width in texels.
    pub log2_width: u8,
    /// `log2` of the height in texels.
    pub log2_height: u8,
    /// `peel_runtime::read::layout::texture_flags`.
    pub flags: u8,
    /// The palette's colours less one with `texture_flags::PALETTE`, else 0.
    pub colours_minus_one: u8,
    /// The offset of its bytes in `texels`.
    pub offset: u32,
}

/// A whole `.peel` file: the header, then flat arrays (each a `u64` length then its records).
#[derive(Debug, Clone, PartialEq)]
pub struct PeelFile {
    /// Header.
    pub header: Header,
    /// Vertex positions (steps on the header's bounds, or `f32` relative to `header.centre`).
    pub vertices: Vec<Vertex>,
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
    /// Node bounding boxes `[min, max]` when `header_flags::BOUNDS` is set, else empty: per
    /// axis, steps from the header's `bounds_min` to its `bounds_max`
    /// (`peel_runtime::read::layout::dequantise`).
    pub bounds: Vec<[u16; 6]>,
    /// Nodes in pre-order (front before back): the root is node 0 and children come after
    /// their parents. Convex nodes own the polygons in node order.
    pub nodes: Vec<Node>,
    /// Per vertex, the intensities `[front, back]` of its source triangle's sides (255: the
    /// material's colour) when `header_flags::SHADES` is set, else empty and not written.
    pub shades: Vec<[u8; 2]>,
    /// Per vertex, its texture coordinates `[s, t]` when `header_flags::TEXTURES` is set (a
    /// file of version `TEXTURED_VERSION`), else empty and not written; so are the three
    /// arrays below.
    pub uvs: Vec<[i32; 2]>,
    /// The texture records (1 to `MAX_TEXTURES`).
    pub textures: Vec<TextureRecord>,
    /// Every texture's bytes, in record order.
    pub texels: Vec<u8>,
    /// Per polygon, its texture or `NO_TEXTURE`.
    pub polygon_textures: Vec<u8>,
    /// Per polygon, its opacity when `header_flags::TRANSPARENT` is set (a file of version
    /// `TRANSPARENT_VERSION`), else empty and not written.
    pub opacities: Vec<u8>,
}

/// Fields of [`PeelFile`] in file order (`shades` only with its flag, the four texture arrays
/// only with `TEXTURES`, `opacities` only with `TRANSPARENT`).
const FILE_FIELDS: usize = 15;

impl Serialize for PeelFile {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let flags = self.header.flags;
        let shades = flags & header_flags::SHADES != 0;
        if !shades && !self.shades.is_empty() {
            return Err(ser::Error::custom("shades without the SHADES flag"));
        }
        let textures = flags & header_flags::TEXTURES != 0;
        let texture_arrays =
            self.uvs.len() + self.textures.len() + self.texels.len() + self.polygon_textures.len();
        if !textures && texture_arrays != 0 {
            return Err(ser::Error::custom("textures without the TEXTURES flag"));
        }
        let transparent = flags & header_flags::TRANSPARENT != 0;
        if !transparent && !self.opacities.is_empty() {
            return Err(ser::Error::custom("opacities without the TRANSPARENT flag"));
        }
        let fields = FILE_FIELDS
            - usize::from(!shades)
            - 4 * usize::from(!textures)
            - usize::from(!transparent);
        let mut t = s.serialize_tuple(fields)?;
        t.serialize_element(&header_words(&self.header))?;
        t.serialize_element(&Records(&self.vertices, flags))?;
        t.serialize_element(&self.planes)?;
        t.serialize_element(&Records(&self.indices, flags))?;
        t.serialize_element(&Records(&self.polygons, flags))?;
        t.serialize_element(&self.ids)?;
        t.serialize_element(&self.palette)?;
        t.serialize_element(&self.bounds)?;
        t.serialize_element(&Records(&self.nodes, flags))?;
        if shades {
            t.serialize_element(&self.shades)?;
        }
        if textures {
            t.serialize_element(&self.uvs)?;
            t.serialize_element(&self.textures)?;
            t.serialize_element(&self.texels)?;
            t.serialize_element(&self.polygon_textures)?;
        }
        if transparent {
            t.serialize_element(&self.opacities)?;
        }
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
    /// Writes the record at position `index` of its array.
    fn write<S: Serializer>(&self, flags: u16, index: u32, s: S) -> Result<S::Ok, S::Error>;
    /// Reads the record at position `index` of its array.
    fn read<'de, A: SeqAccess<'de>>(
        flags: u16,
        index: u32,
        seq: &mut A,
    ) -> Result<Option<Self>, A::Error>;
}

/// An array of flag-dependent records, with its `u64` length.
struct Records<'a, T>(&'a [T], u16);

/// One flag-dependent record and its position in its array.
struct Record<'a, T>(&'a T, u16, u32);

impl<T: Flagged> Serialize for Records<'_, T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.0.len()))?;
        for (index, item) in self.0.iter().enumerate() {
            let index = u32::try_from(index)
                .map_err(|_| ser::Error::custom("more than u32::MAX records"))?;
            seq.serialize_element(&Record(item, self.1, index))?;
        }
        seq.end()
    }
}

impl<T: Flagged> Serialize for Record<'_, T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.write(self.1, self.2, s)
    }
}

impl Flagged for u32 {
    fn write<S: Serializer>(&self, flags: u16, _: u32, s: S) -> Result<S::Ok, S::Error> {
        if flags & header_flags::INDEX16 != 0 {
            let narrow = u16::try_from(*self)
                .map_err(|_| ser::Error::custom(format!("index {self} does not fit INDEX16")))?;
            return s.serialize_u16(narrow);
        }
        if flags & header_flags::INDEX24 != 0 {
            if *self >= 1 << 24 {
                return Err(ser::Error::custom(format!(
                    "index {self} does not fit INDEX24"
                )));
            }
            let le = self.to_le_bytes();
            return [le[0], le[1], le[2]].serialize(s);
        }
        s.serialize_u32(*self)
    }
    fn read<'de, A: SeqAccess<'de>>(
        flags: u16,
        _: u32,
        seq: &mut A,
    ) -> Result<Option<Self>, A::Error> {
        if flags & header_flags::INDEX16 != 0 {
            Ok(seq.next_element::<u16>()?.map(u32::from))
        } else if flags & header_flags::INDEX24 != 0 {
            Ok(seq
                .next_element::<[u8; 3]>()?
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], 0])))
        } else {
            seq.next_element::<u32>()
        }
    }
}

impl Flagged for Vertex {
    fn write<S: Serializer>(&self, flags: u16, _: u32, s: S) -> Result<S::Ok, S::Error> {
        let wide = flags & header_flags::WIDE_VERTICES != 0;
        match (self, wide) {
            (Vertex::Grid(q), false) => q.serialize(s),
            (Vertex::Wide(v), true) => v.serialize(s),
            _ => Err(ser::Error::custom(format!(
                "vertex {self:?} disagrees with header flags {flags:#x}"
            ))),
        }
    }
    fn read<'de, A: SeqAccess<'de>>(
        flags: u16,
        _: u32,
        seq: &mut A,
    ) -> Result<Option<Self>, A::Error> {
        if flags & header_flags::WIDE_VERTICES != 0 {
            let Some(x) = seq.next_element::<f32>()? else {
                return Ok(None);
            };
            let (y, z) = (
                required(seq.next_element()?)?,
                required(seq.next_element()?)?,
            );
            Ok(Some(Vertex::Wide([x, y, z])))
        } else {
            let Some(x) = seq.next_element::<u16>()? else {
                return Ok(None);
            };
            let (y, z) = (
                required(seq.next_element()?)?,
                required(seq.next_element()?)?,
            );
            Ok(Some(Vertex::Grid([x, y, z])))
        }
    }
}

/// A node field or a polygon's `plane` / `first_index`: `u16` with [`header_flags::NARROW`],
/// `u24` with [`header_flags::MEDIUM`], else `u32`; [`NONE`] is written as the width's largest
/// value, which no other value may take.
fn field<T: SerializeTuple>(t: &mut T, flags: u16, value: u32) -> Result<(), T::Error> {
    let width = field_size(flags);
    if width == 4 {
        return t.serialize_element(&value);
    }
    let none = none_of_width(width);
    let stored = if value == NONE {
        none
    } else if value < none {
        value
    } else {
        return Err(ser::Error::custom(format!(
            "field {value} does not fit {width} bytes"
        )));
    };
    let le = stored.to_le_bytes();
    if width == 2 {
        t.serialize_element(&[le[0], le[1]])
    } else {
        t.serialize_element(&[le[0], le[1], le[2]])
    }
}

/// Reads a field written by [`field`]; `link` fields read the width's largest value as
/// [`NONE`].
fn read_field<'de, A: SeqAccess<'de>>(
    flags: u16,
    seq: &mut A,
    link: bool,
) -> Result<Option<u32>, A::Error> {
    let width = field_size(flags);
    let value = match width {
        2 => seq
            .next_element::<[u8; 2]>()?
            .map(|b| u32::from_le_bytes([b[0], b[1], 0, 0])),
        3 => seq
            .next_element::<[u8; 3]>()?
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], 0])),
        _ => return seq.next_element::<u32>(),
    };
    Ok(value.map(|v| {
        if link && v == none_of_width(width) {
            NONE
        } else {
            v
        }
    }))
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
    fn write<S: Serializer>(&self, flags: u16, _: u32, s: S) -> Result<S::Ok, S::Error> {
        let two = flags & header_flags::TWO_COLOURS != 0;
        let kind = colour_kind(flags);
        if !kind(self.colour) || self.exterior.is_some() != two || !self.exterior.is_none_or(kind) {
            return Err(ser::Error::custom(format!(
                "colour fields {:?}, {:?} disagree with header flags {flags:#x}",
                self.colour, self.exterior
            )));
        }
        let mut t = s.serialize_tuple(if two { 5 } else { 4 })?;
        field(&mut t, flags, self.first_index)?;
        t.serialize_element(&self.vertex_count)?;
        t.serialize_element(&self.flags)?;
        for colour in std::iter::once(self.colour).chain(self.exterior) {
            match colour {
                ColourField::Rgb(rgb) => t.serialize_element(&rgb)?,
                ColourField::Index8(k) => t.serialize_element(&k)?,
                ColourField::Index16(k) => t.serialize_element(&k)?,
            }
        }
        t.end()
    }
    fn read<'de, A: SeqAccess<'de>>(
        flags: u16,
        _: u32,
        seq: &mut A,
    ) -> Result<Option<Self>, A::Error> {
        let Some(first_index) = read_field(flags, seq, false)? else {
            return Ok(None);
        };
        let vertex_count = required(seq.next_element()?)?;
        let polygon_flags = required(seq.next_element()?)?;
        let mut colour = || -> Result<ColourField, A::Error> {
            Ok(if flags & header_flags::PALETTE == 0 {
                ColourField::Rgb(required(seq.next_element()?)?)
            } else if flags & header_flags::PALETTE16 == 0 {
                ColourField::Index8(required(seq.next_element()?)?)
            } else {
                ColourField::Index16(required(seq.next_element()?)?)
            })
        };
        let interior = colour()?;
        let exterior = if flags & header_flags::TWO_COLOURS != 0 {
            Some(colour()?)
        } else {
            None
        };
        Ok(Some(Polygon {
            first_index,
            vertex_count,
            flags: polygon_flags,
            colour: interior,
            exterior,
        }))
    }
}

impl Node {
    /// The first child (a convex node's child, a split's + child): written as
    /// [`node_kind::FIRST_CHILD`], since it can only be the next node.
    fn first_child(&self) -> u32 {
        if self.kind == node_kind::CONVEX {
            self.c
        } else {
            self.b
        }
    }

    /// The field stored after `a`: a convex node's count, a split's - child.
    fn second_field(&self) -> u32 {
        if self.kind == node_kind::CONVEX {
            self.b
        } else {
            self.c
        }
    }
}

impl Flagged for Node {
    fn write<S: Serializer>(&self, flags: u16, index: u32, s: S) -> Result<S::Ok, S::Error> {
        let with_bounds = flags & header_flags::BOUNDS != 0;
        if !with_bounds && self.bounds != NONE {
            return Err(ser::Error::custom("node bounds without the BOUNDS flag"));
        }
        if self.kind & node_kind::FIRST_CHILD != 0 {
            return Err(ser::Error::custom("node kind with the FIRST_CHILD bit"));
        }
        let kind = match self.first_child() {
            NONE => self.kind,
            child if Some(child) == index.checked_add(1) => self.kind | node_kind::FIRST_CHILD,
            child => {
                return Err(ser::Error::custom(format!(
                    "node {index}: first child {child} is not the next node"
                )))
            }
        };
        let mut t = s.serialize_tuple(if with_bounds { 5 } else { 4 })?;
        t.serialize_element(&kind)?;
        field(&mut t, flags, self.a)?;
        field(&mut t, flags, self.second_field())?;
        field(&mut t, flags, self.parent)?;
        if with_bounds {
            field(&mut t, flags, self.bounds)?;
        }
        t.end()
    }
    fn read<'de, A: SeqAccess<'de>>(
        flags: u16,
        index: u32,
        seq: &mut A,
    ) -> Result<Option<Self>, A::Error> {
        let Some(byte) = seq.next_element::<u8>()? else {
            return Ok(None);
        };
        let kind = byte & !node_kind::FIRST_CHILD;
        let first_child = if byte & node_kind::FIRST_CHILD != 0 {
            index.wrapping_add(1)
        } else {
            NONE
        };
        let a = required(read_field(flags, seq, false)?)?;
        let second = required(read_field(flags, seq, kind != node_kind::CONVEX)?)?;
        let (b, c) = if kind == node_kind::CONVEX {
            (second, first_child)
        } else {
            (first_child, second)
        };
        Ok(Some(Node {
            kind,
            a,
            b,
            c,
            parent: required(read_field(flags, seq, true)?)?,
            bounds: if flags & header_flags::BOUNDS != 0 {
                required(read_field(flags, seq, true)?)?
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

/// Reads one flag-dependent record (at the given position of its array), as a tuple of its
/// fields (records have no length prefix).
struct RecordSeed<T>(u16, u32, std::marker::PhantomData<T>);

/// Reads an array of flag-dependent records.
struct RecordsSeed<T>(u16, std::marker::PhantomData<T>);

/// An upper bound on the fields of a record ([`Node`] with bounds has 5); bincode reads a tuple field by field, so
/// the exact count is not needed, only an upper bound.
const MAX_RECORD_FIELDS: usize = 6;

impl<'de, T: Flagged> DeserializeSeed<'de> for RecordSeed<T> {
    type Value = T;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<T, D::Error> {
        struct V<T>(u16, u32, std::marker::PhantomData<T>);
        impl<'de, T: Flagged> Visitor<'de> for V<T> {
            type Value = T;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a record")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<T, A::Error> {
                T::read(self.0, self.1, &mut seq)?.ok_or_else(|| de::Error::custom("empty record"))
            }
        }
        d.deserialize_tuple(MAX_RECORD_FIELDS, V(self.0, self.1, self.2))
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
                loop {
                    let index = u32::try_from(out.len())
                        .map_err(|_| de::Error::custom("more than u32::MAX records"))?;
                    let seed = RecordSeed::<T>(self.0, index, std::marker::PhantomData);
                    let Some(item) = seq.next_element_seed(seed)? else {
                        break;
                    };
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
                let mut file = PeelFile {
                    header,
                    vertices: required(
                        seq.next_element_seed(RecordsSeed(flags, std::marker::PhantomData))?,
                    )?,
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
                    shades: Vec::new(),
                    uvs: Vec::new(),
                    textures: Vec::new(),
                    texels: Vec::new(),
                    polygon_textures: Vec::new(),
                    opacities: Vec::new(),
                };
                if flags & header_flags::SHADES != 0 {
                    file.shades = required(seq.next_element()?)?;
                }
                if flags & header_flags::TEXTURES != 0 {
                    file.uvs = required(seq.next_element()?)?;
                    file.textures = required(seq.next_element()?)?;
                    file.texels = required(seq.next_element()?)?;
                    file.polygon_textures = required(seq.next_element()?)?;
                }
                if flags & header_flags::TRANSPARENT != 0 {
                    file.opacities = required(seq.next_element()?)?;
                }
                Ok(file)
            }
        }
        d.deserialize_tuple(FILE_FIELDS, V)
    }
}
