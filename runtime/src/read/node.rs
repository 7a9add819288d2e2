//! Nodes: the tree's records decoded (a convex set or a split, and the links between them),
//! and the scene's accessors for them.

use glam::Vec3;

use super::layout::{element, header_flags, node_kind, Record, BOUNDS_SIZE, NONE};
use super::Scene;

/// A node record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Node {
    /// Convex set `first .. first + count`, then `child`.
    Convex {
        /// First polygon.
        first: u32,
        /// Number of polygons.
        count: u32,
        /// The node inside the set.
        child: Option<u32>,
    },
    /// Separating plane.
    Split {
        /// Plane index.
        plane: u32,
        /// Child on the + side.
        front: Option<u32>,
        /// Child on the - side.
        back: Option<u32>,
    },
}

impl Node {
    /// What [`Scene::node`] answers for an index out of range: an empty leaf, which draws nothing.
    pub const EMPTY: Node = Node::Convex {
        first: 0,
        count: 0,
        child: None,
    };
}

/// A child or parent field: [`layout::NONE`](NONE) means "none".
pub(super) fn link(value: u32) -> Option<u32> {
    (value != NONE).then_some(value)
}

impl Scene<'_> {
    /// Root node, if the tree is not empty.
    pub fn root(&self) -> Option<u32> {
        (self.header.node_count > 0).then_some(0)
    }

    /// Node `i` ([`Node::EMPTY`] when out of range).
    #[inline]
    pub fn node(&self, i: u32) -> Node {
        match self.raw_node(i) {
            Some(raw) if i < self.header.node_count => raw.node(),
            _ => Node::EMPTY,
        }
    }

    /// Parent of node `i` (`None` for the root and out of range).
    pub fn parent(&self, i: u32) -> Option<u32> {
        if i >= self.header.node_count {
            return None;
        }
        self.raw_node(i).and_then(|raw| link(raw.parent))
    }

    /// Bounding box `(min, max)` of node `i`'s subtree, relative to the centre, if the file
    /// stores one for it.
    #[inline]
    pub fn node_bounds(&self, i: u32) -> Option<(Vec3, Vec3)> {
        let at = self.node_box_at(i)?;
        Some(self.box_at(at))
    }

    /// Node `i`'s box as the file stores it: the 16-bit steps of its corners (`(min, max)`),
    /// which hold the steps of every vertex of its subtree ([`Scene::vertex_steps`]); `None`
    /// without a box or with `f32` vertices.
    #[inline]
    pub fn node_box_steps(&self, i: u32) -> Option<([u16; 3], [u16; 3])> {
        if self.vertex_size() != 6 {
            return None;
        }
        let r = Record::<BOUNDS_SIZE>::at(self.bytes, self.node_box_at(i)?)?;
        let q = |k: usize| [r.u16(k), r.u16(k + 2), r.u16(k + 4)];
        Some((q(0), q(6)))
    }

    /// The byte offset of node `i`'s box, if it has one.
    #[inline]
    fn node_box_at(&self, i: u32) -> Option<usize> {
        if self.header.flags & header_flags::BOUNDS == 0 || i >= self.header.node_count {
            return None;
        }
        let w = self.field_size();
        let at = element(self.nodes, self.node_size, i)?.checked_add(1 + 3 * w)?;
        let k = match w {
            2 => Record::<2>::at(self.bytes, at)?.narrow(0, true),
            3 => Record::<3>::at(self.bytes, at)?.medium(0, true),
            _ => Record::<4>::at(self.bytes, at)?.u32(0),
        };
        let k = link(k)?;
        if k >= self.header.bounds_count {
            return None;
        }
        element(self.bounds, BOUNDS_SIZE, k)
    }

    #[inline]
    pub(super) fn raw_node(&self, i: u32) -> Option<RawNode> {
        RawNode::at(
            self.bytes,
            element(self.nodes, self.node_size, i)?,
            self.field_size(),
            i,
        )
    }
}

/// A node record as stored, before its kind is interpreted.
#[derive(Debug, Clone, Copy)]
pub(super) struct RawNode {
    /// The kind, without [`node_kind::FIRST_CHILD`].
    pub(super) kind: u8,
    pub(super) a: u32,
    /// Convex: the child; split: the child on the + side (the implicit first child, the next
    /// node, when [`node_kind::FIRST_CHILD`] is set).
    b: u32,
    /// Convex: the polygon count; split: the child on the - side.
    pub(super) c: u32,
    pub(super) parent: u32,
}

impl RawNode {
    /// Node `i` at byte `at`: one bounds check per record, fields at constant offsets (`w`:
    /// the field width).
    #[inline]
    fn at(bytes: &[u8], at: usize, w: usize, i: u32) -> Option<RawNode> {
        let (byte, a, c, parent) = if w == 2 {
            let r = Record::<7>::at(bytes, at)?;
            let byte = r.u8(0);
            // A convex node's second field is a count, a split's a link.
            let convex = byte & !node_kind::FIRST_CHILD == node_kind::CONVEX;
            (
                byte,
                r.narrow(1, false),
                r.narrow(3, !convex),
                r.narrow(5, true),
            )
        } else if w == 3 {
            let r = Record::<10>::at(bytes, at)?;
            let byte = r.u8(0);
            let convex = byte & !node_kind::FIRST_CHILD == node_kind::CONVEX;
            (
                byte,
                r.medium(1, false),
                r.medium(4, !convex),
                r.medium(7, true),
            )
        } else {
            let r = Record::<13>::at(bytes, at)?;
            (r.u8(0), r.u32(1), r.u32(5), r.u32(9))
        };
        let b = if byte & node_kind::FIRST_CHILD != 0 {
            i.wrapping_add(1)
        } else {
            NONE
        };
        Some(RawNode {
            kind: byte & !node_kind::FIRST_CHILD,
            a,
            b,
            c,
            parent,
        })
    }

    /// The decoded node; an unknown kind (rejected by `parse`) reads as [`Node::EMPTY`].
    fn node(self) -> Node {
        match self.kind {
            node_kind::CONVEX => Node::Convex {
                first: self.a,
                count: self.c,
                child: link(self.b),
            },
            node_kind::SPLIT => Node::Split {
                plane: self.a,
                front: link(self.b),
                back: link(self.c),
            },
            _ => Node::EMPTY,
        }
    }

    /// Children in drawing-independent order: the convex child, or front then back.
    pub(super) fn children(self) -> [Option<u32>; 2] {
        match self.node() {
            Node::Convex { child, .. } => [child, None],
            Node::Split { front, back, .. } => [front, back],
        }
    }
}
