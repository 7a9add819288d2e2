//! Typed errors: `Copy`, `Display`, never a panic.

use core::fmt;

/// Why a byte slice is not a valid `.peel` file. `offset` is the byte offset of the problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadError {
    /// Fewer bytes than the structure needs.
    Truncated {
        /// Where the missing data starts.
        offset: usize,
    },
    /// The first four bytes are not `PEEL`.
    BadMagic,
    /// A format version this reader does not know.
    UnsupportedVersion {
        /// The version in the file.
        version: u16,
    },
    /// Flag bits this reader does not know.
    UnknownFlags {
        /// The flags in the file.
        flags: u16,
    },
    /// Flags of widths this build was compiled without: `u24` or `u32` fields or indices
    /// (feature `large-scenes`), `f32` vertices (feature `wide-vertices`).
    UnsupportedFlags {
        /// The flags in the file.
        flags: u16,
    },
    /// Header flags that contradict each other (a `u16` palette index without a palette).
    InconsistentFlags {
        /// The flags in the file.
        flags: u16,
    },
    /// An array length disagrees with the header count.
    CountMismatch {
        /// Byte offset of the array length.
        offset: usize,
    },
    /// A record holds an index beyond its array, a child that does not come after its parent,
    /// an unknown kind, or a value out of its documented range.
    BadRecord {
        /// Byte offset of the record.
        offset: usize,
    },
    /// The tree is deeper than the header says.
    TooDeep {
        /// The header's `max_depth`.
        max_depth: u32,
    },
    /// Bytes remain after the last array.
    TrailingBytes {
        /// Where they start.
        offset: usize,
    },
    /// A part of a file of parts ([`crate::read::Parts`]) is not a tree this reader accepts
    /// (its header's magic, version, flags or depth).
    BadPart {
        /// The part's index.
        part: u32,
        /// Byte offset of the part's tree.
        offset: usize,
    },
    /// An object's name in a file of parts is empty, too long, not UTF-8, or a repeat.
    BadName {
        /// Byte offset of the name's table entry.
        offset: usize,
    },
}

impl ReadError {
    /// The error of a tree that starts `start` bytes into the file, in the file's offsets
    /// (part `part` of a file of parts).
    pub(crate) fn in_part(self, part: u32, start: usize) -> ReadError {
        let at = |offset: usize| offset.saturating_add(start);
        match self {
            ReadError::Truncated { offset } => ReadError::Truncated { offset: at(offset) },
            ReadError::CountMismatch { offset } => ReadError::CountMismatch { offset: at(offset) },
            ReadError::BadRecord { offset } => ReadError::BadRecord { offset: at(offset) },
            ReadError::TrailingBytes { offset } => ReadError::TrailingBytes { offset: at(offset) },
            _ => ReadError::BadPart {
                part,
                offset: start,
            },
        }
    }
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ReadError::Truncated { offset } => write!(f, "truncated at byte {offset}"),
            ReadError::BadMagic => write!(f, "not a .peel file (bad magic at byte 0)"),
            ReadError::UnsupportedVersion { version } => {
                write!(f, "unsupported format version {version} (byte 4)")
            }
            ReadError::UnknownFlags { flags } => {
                write!(f, "unknown header flags {flags:#06x} (byte 6)")
            }
            ReadError::UnsupportedFlags { flags } => write!(
                f,
                "header flags {flags:#06x} (byte 6) need a feature this build lacks \
                 (large-scenes or wide-vertices)"
            ),
            ReadError::InconsistentFlags { flags } => {
                write!(f, "inconsistent header flags {flags:#06x} (byte 6)")
            }
            ReadError::CountMismatch { offset } => {
                write!(f, "array length at byte {offset} disagrees with the header")
            }
            ReadError::BadRecord { offset } => write!(f, "invalid record at byte {offset}"),
            ReadError::TooDeep { max_depth } => {
                write!(f, "tree deeper than the header's max_depth {max_depth}")
            }
            ReadError::TrailingBytes { offset } => {
                write!(f, "unexpected bytes after the end, at byte {offset}")
            }
            ReadError::BadPart { part, offset } => write!(
                f,
                "part {part}, at byte {offset}, is not a tree this reader accepts \
                 (magic, version, flags or depth)"
            ),
            ReadError::BadName { offset } => write!(
                f,
                "the object name of the part table entry at byte {offset} is empty, too long, \
                 not UTF-8 or repeated"
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for ReadError {}

/// Why a frame cannot be drawn (decided up front, before any pixel is written).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RenderError {
    /// The tree is deeper than the caller's traversal stack.
    StackTooSmall {
        /// Entries needed (the header's `max_depth`).
        needed: u32,
        /// Entries provided.
        available: u32,
    },
    /// A polygon has more vertices than the clip buffers hold.
    PolygonTooLarge {
        /// Vertices needed (the header's `max_polygon_vertices` plus what clipping adds).
        needed: u32,
        /// Vertices the buffers hold.
        available: u32,
    },
    /// Id rendering was asked of a file compiled without `--ids`.
    NoIds,
    /// The camera is not usable (zero-size image, degenerate basis, non-finite values).
    BadCamera,
    /// The image is too large for the fixed-point screen coordinates (`W * 2^SUB` and
    /// `H * 2^SUB` must fit in an `i32`, and without the `wide-coordinates` feature be at most
    /// [`crate::fill::coordinate_limit`]).
    ImageTooLarge {
        /// Image width in pixels.
        width: u32,
        /// Image height in pixels.
        height: u32,
    },
    /// The tree visits more nodes than it has (a cycle): only a tree that did not come
    /// from a validated file can do that.
    MalformedTree,
    /// The span memory does not match the frame: fewer row counters than rows, or a width
    /// beyond `u16`.
    SpanMemory,
    /// The memory for pending pixels ([`crate::render::Renderer::antialias`]) does not match
    /// the frame: fewer row heads than rows.
    PendingMemory,
    /// A frame that must be drawn front to back (a scan-order frame, or spans streamed to a
    /// display, whose sink says [`crate::display::SpanSink::write_once`]) would be painted
    /// back to front: there is no span or scan memory, [`crate::render::Renderer::back_to_front`]
    /// was asked for, or the runtime lacks its `front-to-back` feature. Refused before the
    /// first pixel.
    NotFrontToBack,
    /// A streamed frame ran out of span memory: it stops there, with what was sent so far,
    /// rather than finishing back to front with overdraw. Give the memory the sizes file
    /// measures (`SPANS_PER_ROW`).
    SpanMemoryFull,
    /// A scan-order frame needs more scan memory nodes than the memory holds; nothing was
    /// sent. Give the memory the sizes file measures (`SCAN_NODES`).
    ScanMemoryFull {
        /// Nodes in the memory.
        nodes: u32,
    },
    /// A frame with objects ([`crate::place::Posed`]) needs more object memory than the
    /// renderer has ([`crate::render::Renderer::object_memory`]): none, fewer placements than
    /// objects, or fewer steps, pieces or cuts than this frame's order.
    ObjectMemory,
    /// Two objects whose posed boxes no plane separates overlap on the screen: their order is
    /// not proven, and the frame is refused rather than drawn wrong.
    ObjectsIntersect {
        /// Index of the first object ([`crate::place::Posed::objects`]).
        first: u32,
        /// Index of the second.
        second: u32,
    },
    /// More world planes cut an object this frame than a piece can be clipped by (32): a
    /// world of many planes through the object's place.
    TooManyCuts {
        /// Index of the object.
        object: u32,
    },
    /// An object's pose is not finite.
    BadPose {
        /// Index of the object.
        object: u32,
    },
    /// A front-to-back frame of a scene with transparent surfaces into a sink that takes each
    /// pixel once (a display, or scan memory) has no composite memory
    /// ([`crate::render::Renderer::composite_memory`]), or that memory has fewer row heads
    /// than the frame has rows. (Into a framebuffer, such a frame is drawn back to front.)
    CompositeMemory,
    /// Transparent surfaces in an anti-aliased frame: a pending pixel's samples would each
    /// need their own transmittance. Refused before the first pixel; draw the scene without
    /// [`crate::render::Renderer::antialias`].
    AntialiasedTransparency,
    /// [`crate::render::Renderer::draw_rows`] was given rows that are not a range of the
    /// image's rows.
    RowsOutsideImage {
        /// First row asked for.
        start: u32,
        /// Row past the last asked for.
        end: u32,
        /// Image height.
        height: u32,
    },
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            RenderError::StackTooSmall { needed, available } => write!(
                f,
                "the tree needs a traversal stack of {needed} entries, the caller gave {available}"
            ),
            RenderError::PolygonTooLarge { needed, available } => write!(
                f,
                "polygons need clip buffers of {needed} vertices, the caller gave {available}"
            ),
            RenderError::NoIds => {
                write!(f, "the file holds no triangle ids (compile it with --ids)")
            }
            RenderError::BadCamera => write!(f, "the camera is degenerate or not finite"),
            RenderError::ImageTooLarge { width, height } => write!(
                f,
                "a {width} x {height} image is too large for the fixed-point screen coordinates"
            ),
            RenderError::MalformedTree => {
                write!(f, "the display tree is malformed (a node is reached twice)")
            }
            RenderError::SpanMemory => write!(
                f,
                "the span memory needs one counter per row and a width of at most 65535"
            ),
            RenderError::PendingMemory => {
                write!(f, "the pending-pixel memory needs one list head per row")
            }
            RenderError::NotFrontToBack => write!(
                f,
                "this frame must be drawn front to back (span or scan memory, the front-to-back \
                 feature, no back_to_front)"
            ),
            RenderError::SpanMemoryFull => write!(
                f,
                "the streamed frame ran out of span memory (stopped; give SPANS_PER_ROW per row)"
            ),
            RenderError::ScanMemoryFull { nodes } => write!(
                f,
                "the frame needs more than the {nodes} nodes of scan memory (nothing sent; give \
                 SCAN_NODES)"
            ),
            RenderError::ObjectMemory => write!(
                f,
                "the frame's objects need more object memory (placements, steps, pieces or cuts)"
            ),
            RenderError::ObjectsIntersect { first, second } => write!(
                f,
                "objects {first} and {second} intersect on the screen and no plane separates \
                 their boxes: their order is not proven"
            ),
            RenderError::TooManyCuts { object } => write!(
                f,
                "more than 32 world planes cut object {object} this frame"
            ),
            RenderError::BadPose { object } => {
                write!(f, "the pose of object {object} is not finite")
            }
            RenderError::CompositeMemory => write!(
                f,
                "transparent surfaces front to back need composite memory with a head per row"
            ),
            RenderError::AntialiasedTransparency => write!(
                f,
                "transparent surfaces cannot be anti-aliased (draw without antialias)"
            ),
            RenderError::RowsOutsideImage { start, end, height } => write!(
                f,
                "rows {start}..{end} are not rows of an image {height} rows high"
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for RenderError {}
