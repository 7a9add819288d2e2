//! Nodes: their kinds, the width of their fields (which a polygon's `first_index` shares), their
//! records' sizes, and the sizes of the planes and boxes they refer to.

use super::header::header_flags;

/// Bytes of a node field and a polygon's `first_index` under header `flags`.
pub const fn field_size(flags: u16) -> usize {
    if flags & header_flags::NARROW != 0 {
        2
    } else if flags & header_flags::MEDIUM != 0 {
        3
    } else {
        4
    }
}

/// Bytes of a node record under header `flags`: `kind`, then `a`, `b`, `parent` and with
/// [`header_flags::BOUNDS`] `bounds` ([`field_size`] each). A node's first child is implicit
/// (the next node, flagged by [`node_kind::FIRST_CHILD`]), so it takes no field.
pub const fn node_size(flags: u16) -> usize {
    let fields = if flags & header_flags::BOUNDS != 0 {
        4
    } else {
        3
    };
    1 + fields * field_size(flags)
}

/// Values of a node's `kind` byte.
pub mod node_kind {
    /// `a` = first polygon, `b` = polygon count; the child (what lies inside the set) is the
    /// next node when [`FIRST_CHILD`] is set, else there is none.
    pub const CONVEX: u8 = 0;
    /// `a` = plane, `b` = child on the - side (or [`NONE`](super::super::NONE)); the child on
    /// the + side is the next node when [`FIRST_CHILD`] is set, else there is none.
    pub const SPLIT: u8 = 1;
    /// Bit of the `kind` byte: the node's first child (a convex node's child, a split's + child)
    /// exists and is the next node, `i + 1` (the nodes are in pre-order, front before back).
    pub const FIRST_CHILD: u8 = 1 << 7;
}

/// Bytes of a plane (`[f32; 4]`).
pub const PLANE_SIZE: usize = 16;
/// Bytes of a node's bounds (`[u16; 6]`: min then max, see [`dequantise`](super::dequantise)).
pub const BOUNDS_SIZE: usize = 12;
/// Bytes of the widest node record (`u32` fields and bounds; see [`node_size`]).
pub const NODE_SIZE: usize = 17;
