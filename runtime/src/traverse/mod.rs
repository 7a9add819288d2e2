//! Traverse: the display tree's polygons in painter order for one eye position.
//!
//! Display order (back to front; a split node as in Fuchs, Kedem and Naylor's BSP trees):
//! - split node with plane `P`: eye on the + side (`distance >= 0`) -> the − child, then the
//!   + child; otherwise the + child, then the − child;
//! - convex node: first its polygons whose interior the eye sees (the eye is on the
//!   polygon plane's interior side: the + side when [`INTERIOR_FRONT`] is set), then the
//!   child, then its polygons whose exterior the eye sees.
//!
//! An eye exactly on a plane is legal: a split plane through the eye separates nothing the
//! eye can see overlapping, and a polygon whose plane holds the eye is seen edge-on, so
//! either order is right. The tie is broken the same way everywhere (`distance == 0` counts
//! as the + side), which makes the order deterministic.
//!
//! A polygon that bounds a solid and that the eye sees from behind, with the whole scene in
//! front of the near plane, is hidden by the solid's own surface: asked to
//! ([`Traversal::skip_solids_from_behind`]), the walk skips it in both orders, right after its
//! side test, before anything reads its vertices.
//!
//! The walk is iterative with an explicit, caller-provided stack: one pending entry per node
//! on the current root-to-node path, so the header's `max_depth` entries always suffice.
//! [`Order::FrontToBack`] walks the exact reverse sequence (for front-to-back renderers).

use glam::Vec3;

use crate::error::RenderError;
use crate::read::{Node, Plane, Polygon, Scene, Side, SideEye};

/// Bit of [`Polygon::flags`]: the rest of the polygon's convex set lies on the + side of its
/// plane.
pub const INTERIOR_FRONT: u8 = 1 << 1;
pub use crate::read::layout::polygon_flags::{INSIDE_EXTERIOR, INSIDE_INTERIOR};

/// The tree as the traversal sees it. [`Scene`] implements it; tests implement it on small
/// hand-made trees. Accessors must be total (any default for an out-of-range index).
pub trait Tree {
    /// Root node, if the tree is not empty.
    fn root(&self) -> Option<u32>;
    /// Node `i`.
    fn node(&self, i: u32) -> Node;
    /// Plane `i` (a split node's).
    fn plane(&self, i: u32) -> Plane;
    /// Polygon `i`.
    fn polygon(&self, i: u32) -> Polygon;
    /// The eye as [`Tree::eye_side`] takes it, from the eye in the tree's coordinates; called
    /// once per walk. The default: the eye as it is ([`SideEye::world`]).
    fn side_eye(&self, eye: Vec3) -> SideEye {
        SideEye::world(eye)
    }
    /// Which side of `polygon`'s support plane the eye (as [`Tree::side_eye`] gave it) is on;
    /// [`Side::Front`] is the + side, which [`INTERIOR_FRONT`] refers to.
    fn eye_side(&self, polygon: &Polygon, side_eye: &SideEye) -> Side;
    /// The polygon flags ([`INSIDE_INTERIOR`], [`INSIDE_EXTERIOR`]) the tree's faces of
    /// solids carry, 0 when it has none ([`Traversal::skip_solids_from_behind`]). The
    /// default: none.
    fn solid_sides(&self) -> u8 {
        0
    }
    /// Number of nodes (bounds the walk even if the tree were malformed).
    fn node_count(&self) -> u32;
    /// Nodes on the longest root-to-leaf path (the stack the walk needs).
    fn max_depth(&self) -> u32;
    /// Number of polygons: the walk never scans a convex node's polygons beyond it, which
    /// bounds its work even on a tree whose nodes were not validated (see
    /// [`Scene::parse_trusted`]). The default trusts the nodes.
    fn polygon_count(&self) -> u32 {
        u32::MAX
    }
}

impl Tree for Scene<'_> {
    fn root(&self) -> Option<u32> {
        Scene::root(self)
    }
    fn node(&self, i: u32) -> Node {
        Scene::node(self, i)
    }
    fn plane(&self, i: u32) -> Plane {
        Scene::plane(self, i)
    }
    /// Without its colour: the walk needs none ([`Scene::polygon_shape`]).
    fn polygon(&self, i: u32) -> Polygon {
        Scene::polygon_shape(self, i)
    }
    fn side_eye(&self, eye: Vec3) -> SideEye {
        Scene::side_eye(self, eye)
    }
    fn eye_side(&self, polygon: &Polygon, side_eye: &SideEye) -> Side {
        Scene::eye_side(self, polygon, side_eye)
    }
    fn solid_sides(&self) -> u8 {
        if self.header().flags & crate::read::layout::header_flags::SOLID != 0 {
            INSIDE_INTERIOR | INSIDE_EXTERIOR
        } else {
            0
        }
    }
    fn node_count(&self) -> u32 {
        self.header().node_count
    }
    fn max_depth(&self) -> u32 {
        self.header().max_depth
    }
    fn polygon_count(&self) -> u32 {
        self.header().polygon_count
    }
}

/// Where a walk starts ([`Traversal::starting`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Start {
    /// The whole tree.
    #[default]
    Root,
    /// The subtree under a node.
    Subtree(u32),
    /// The polygons of a convex node whose interior side (`interior`) or exterior side the
    /// eye sees; nothing for a split node.
    Hull {
        /// The node.
        node: u32,
        /// Which side seen.
        interior: bool,
    },
}

/// Which way the polygons come out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Order {
    /// Farthest first: the painter's algorithm (later polygons overwrite earlier ones).
    #[default]
    BackToFront,
    /// Nearest first: the exact reverse of [`Order::BackToFront`].
    FrontToBack,
}

/// `x >= 0.0`, exactly (false for NaN, true for -0.0). On a core without an FPU the
/// comparison is a library call, which LLVM repeated for each of its uses in the walk (the
/// Cortex-M0+'s teapot frame called it four times per split node); its bits answer in a few
/// integer instructions.
#[inline(always)]
fn non_negative(x: f32) -> bool {
    if cfg!(all(target_arch = "arm", not(target_abi = "eabihf"))) {
        non_negative_bits(x)
    } else {
        x >= 0.0
    }
}

/// [`non_negative`] from the bits: zero of either sign, or a clear sign bit on a number up
/// to infinity (above it: NaN).
#[inline(always)]
fn non_negative_bits(x: f32) -> bool {
    let bits = x.to_bits();
    let magnitude = bits & 0x7fff_ffff;
    magnitude == 0 || (bits >> 31 == 0 && magnitude <= 0x7f80_0000)
}

/// Whether the eye sees the interior side of `polygon`, the eye being on `side` of its
/// plane ([`Tree::eye_side`]; on the plane counts as yes).
pub fn sees_interior(polygon: &Polygon, side: Side) -> bool {
    let interior = if polygon.flags & INTERIOR_FRONT != 0 {
        Side::Front
    } else {
        Side::Back
    };
    side == interior || side == Side::On
}

/// Whether the eye, seeing `polygon`'s interior side or not, sees it from behind (the inside
/// of the solid it bounds) while `hidden` ([`Traversal::skip_solids_from_behind`]) says such
/// faces are hidden. An eye on the plane counts as seeing the interior side
/// ([`sees_interior`]): the polygon is edge-on and covers nothing, either way.
#[inline]
fn seen_from_behind(polygon: &Polygon, seen_interior: bool, hidden: u8) -> bool {
    let inside = if seen_interior {
        INSIDE_INTERIOR
    } else {
        INSIDE_EXTERIOR
    };
    polygon.flags & hidden & inside != 0
}

/// One entry of the traversal stack (opaque; `Copy` so stacks are plain arrays).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StackEntry(Task);

impl StackEntry {
    /// An unused entry (the [`Default`]).
    pub const IDLE: StackEntry = StackEntry(Task::Idle);
}

// `repr(u8)` with `Idle = 0`: an idle stack is zero bytes, so a workspace in a `static` lands
// in `.bss` (no flash for its initial value).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(u8)]
enum Task {
    #[default]
    Idle = 0,
    /// Visit a node.
    Node(u32) = 1,
    /// Scan polygons `first .. first + count`, `done` of them already looked at, yielding
    /// those with `sees_interior == interior`, then visit `then`. A node's first scan sets
    /// bit `k` of `yielded` for each polygon `k < 32` it yields or skips as seen from behind,
    /// and hands the mask to the second scan (`known`), which then yields the others without
    /// testing their planes again.
    Scan {
        first: u32,
        count: u32,
        done: u32,
        interior: bool,
        then: Option<u32>,
        yielded: u32,
        known: bool,
    } = 2,
}

/// The polygon indices of a tree in display order, as an iterator.
///
/// Created by [`Traversal::new`], which refuses a stack smaller than the tree's depth. If a
/// (malformed) tree turned out deeper than it declares, or had more visits than nodes, the
/// walk stops early and [`Traversal::error`] says why; a validated [`Scene`] never does.
#[derive(Debug)]
pub struct Traversal<'t, 's, T: Tree + ?Sized> {
    tree: &'t T,
    eye: Vec3,
    /// `eye` as the tree's polygon side test takes it ([`Tree::side_eye`]).
    side_eye: SideEye,
    /// Flags of the polygons skipped when seen from behind
    /// ([`Traversal::skip_solids_from_behind`]).
    hidden: u8,
    order: Order,
    stack: &'s mut [StackEntry],
    len: usize,
    active: Task,
    visits: u32,
    error: Option<RenderError>,
}

impl<'t, 's, T: Tree + ?Sized> Traversal<'t, 's, T> {
    /// Walk `tree` for an eye at `eye` (in the tree's coordinates: relative to the scene
    /// centre). Fails with [`RenderError::StackTooSmall`] if `stack` is shorter than the
    /// tree's `max_depth`.
    pub fn new(
        tree: &'t T,
        eye: Vec3,
        order: Order,
        stack: &'s mut [StackEntry],
    ) -> Result<Self, RenderError> {
        let needed = tree.max_depth();
        if needed as usize > stack.len() {
            return Err(RenderError::StackTooSmall {
                needed,
                available: u32::try_from(stack.len()).unwrap_or(u32::MAX),
            });
        }
        Ok(Traversal {
            tree,
            eye,
            side_eye: tree.side_eye(eye),
            hidden: 0,
            order,
            stack,
            len: 0,
            active: tree.root().map_or(Task::Idle, Task::Node),
            visits: 0,
            error: None,
        })
    }

    /// [`Traversal::new`] walking only part of the tree: a subtree, or the polygons of a
    /// convex node whose interior (or exterior) side the eye sees, in `order`. A frame with
    /// objects walks the world in such parts, its objects' pieces between them.
    #[inline(always)]
    pub fn starting(
        tree: &'t T,
        eye: Vec3,
        order: Order,
        stack: &'s mut [StackEntry],
        start: Start,
    ) -> Result<Self, RenderError> {
        let mut walk = Self::new(tree, eye, order, stack)?;
        walk.active = match start {
            Start::Root => walk.active,
            Start::Subtree(node) => Task::Node(node),
            Start::Hull { node, interior } => match tree.node(node) {
                Node::Convex { first, count, .. } => Task::Scan {
                    first,
                    count: count.min(tree.polygon_count().saturating_sub(first)),
                    done: 0,
                    interior,
                    then: None,
                    yielded: 0,
                    known: false,
                },
                Node::Split { .. } => Task::Idle,
            },
        };
        Ok(walk)
    }

    /// From now on, skip the faces of solids ([`Tree::solid_sides`]) the eye sees from
    /// behind, before anything reads their vertices. For a caller whose view has the whole
    /// scene in front of its near plane: then the eye is outside every solid, and the segment
    /// from such a face to the eye leaves the solid through its surface, which is drawn
    /// unclipped and hides the face. (Were the near plane to cut the scene, it could cut that
    /// surface away and show the inside.)
    pub fn skip_solids_from_behind(&mut self) {
        self.hidden = self.tree.solid_sides();
    }

    /// Why the walk stopped early, if it did (see the type docs).
    pub fn error(&self) -> Option<RenderError> {
        self.error
    }

    fn push(&mut self, task: Task) -> bool {
        match self.stack.get_mut(self.len) {
            Some(slot) => {
                *slot = StackEntry(task);
                self.len += 1;
                true
            }
            None => {
                self.error = Some(RenderError::StackTooSmall {
                    needed: self.tree.max_depth().saturating_add(1),
                    available: u32::try_from(self.stack.len()).unwrap_or(u32::MAX),
                });
                false
            }
        }
    }

    fn pop(&mut self) -> Task {
        if self.len == 0 {
            return Task::Idle;
        }
        self.len -= 1;
        self.stack.get(self.len).map_or(Task::Idle, |e| e.0)
    }

    fn stop<R>(&mut self) -> Option<R> {
        self.active = Task::Idle;
        self.len = 0;
        None
    }

    /// A node's first scan is over: give the polygons it yielded to the node's second scan,
    /// pushed just before the first scan started and so still on top of the stack.
    fn hand_over(&mut self, first_polygon: u32, mask: u32) {
        let top = self.len.checked_sub(1).and_then(|i| self.stack.get_mut(i));
        if let Some(StackEntry(Task::Scan {
            first,
            yielded,
            known,
            ..
        })) = top
        {
            if *first == first_polygon && !*known {
                *yielded = mask;
                *known = true;
            }
        }
    }
}

impl<T: Tree + ?Sized> Iterator for Traversal<'_, '_, T> {
    type Item = u32;

    fn next(&mut self) -> Option<u32> {
        self.next_entering(|_| true)
    }
}

/// Polygons per convex node whose side the first scan remembers for the second (one bit each).
const MASK_BITS: u32 = u32::BITS;

impl<T: Tree + ?Sized> Traversal<'_, '_, T> {
    /// The next polygon, asking `enter(node)` before walking into each node: `false` skips
    /// the node's whole subtree (the renderer's frustum and coverage culling). Asked once per
    /// node reached, in walk order, so the answer may depend on what was drawn so far.
    pub fn next_entering<F: FnMut(u32) -> bool>(&mut self, enter: F) -> Option<u32> {
        self.next_polygon_entering(enter).map(|(index, _)| index)
    }

    /// Whether the eye sees the interior side ([`sees_interior`]) of the polygon the walk
    /// yielded last, which the walk knows anyway: the side whose colour shows
    /// ([`crate::read::Scene::colour_seen`]). Only meaningful right after a polygon came.
    #[inline]
    pub fn seen_interior(&self) -> bool {
        matches!(self.active, Task::Scan { interior: true, .. })
    }

    /// [`Self::next_entering`] with the polygon's record, which the walk has read anyway (the
    /// side seen: [`Self::seen_interior`]).
    pub fn next_polygon_entering<F: FnMut(u32) -> bool>(
        &mut self,
        mut enter: F,
    ) -> Option<(u32, Polygon)> {
        let back_to_front = self.order == Order::BackToFront;
        loop {
            if self.error.is_some() {
                return self.stop();
            }
            let task = match self.active {
                Task::Idle => {
                    if self.len == 0 {
                        return None;
                    }
                    self.pop()
                }
                t => t,
            };
            self.active = Task::Idle;
            match task {
                Task::Idle => {}
                Task::Node(i) => {
                    self.visits = self.visits.saturating_add(1);
                    if self.visits > self.tree.node_count() {
                        self.error = Some(RenderError::MalformedTree);
                        return self.stop();
                    }
                    if !enter(i) {
                        continue;
                    }
                    match self.tree.node(i) {
                        Node::Split { plane, front, back } => {
                            let plus = non_negative(self.tree.plane(plane).distance(self.eye));
                            let (first, second) = if plus == back_to_front {
                                (back, front)
                            } else {
                                (front, back)
                            };
                            if let Some(s) = second {
                                if !self.push(Task::Node(s)) {
                                    return self.stop();
                                }
                            }
                            self.active = first.map_or(Task::Idle, Task::Node);
                        }
                        Node::Convex {
                            first,
                            count,
                            child,
                        } => {
                            // A no-op on a validated tree.
                            let count = count.min(self.tree.polygon_count().saturating_sub(first));
                            // Second pass: pending below the child.
                            let later = Task::Scan {
                                first,
                                count,
                                done: 0,
                                interior: !back_to_front,
                                then: None,
                                yielded: 0,
                                known: false,
                            };
                            if !self.push(later) {
                                return self.stop();
                            }
                            self.active = Task::Scan {
                                first,
                                count,
                                done: 0,
                                interior: back_to_front,
                                then: child,
                                yielded: 0,
                                known: false,
                            };
                        }
                    }
                }
                Task::Scan {
                    first,
                    count,
                    mut done,
                    interior,
                    then,
                    mut yielded,
                    known,
                } => {
                    while done < count {
                        // Back to front scans forwards, front to back backwards: exact reverse.
                        let k = if back_to_front {
                            done
                        } else {
                            count - 1 - done
                        };
                        done += 1;
                        let index = first.saturating_add(k);
                        let bit = if k < MASK_BITS { 1u32 << k } else { 0 };
                        if known && yielded & bit != 0 {
                            continue; // the first scan yielded it
                        }
                        let polygon = self.tree.polygon(index);
                        let wanted = (known && bit != 0) || {
                            let seen = sees_interior(
                                &polygon,
                                self.tree.eye_side(&polygon, &self.side_eye),
                            );
                            if polygon.flags & self.hidden != 0
                                && seen_from_behind(&polygon, seen, self.hidden)
                            {
                                // Neither scan yields it; the second skips it by its bit.
                                yielded |= bit;
                                continue;
                            }
                            seen == interior
                        };
                        if wanted {
                            self.active = Task::Scan {
                                first,
                                count,
                                done,
                                interior,
                                then,
                                yielded: yielded | bit,
                                known,
                            };
                            return Some((index, polygon));
                        }
                    }
                    // The first scan of a node (its `interior` is `back_to_front`).
                    if interior == back_to_front {
                        self.hand_over(first, yielded);
                    }
                    self.active = then.map_or(Task::Idle, Task::Node);
                }
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod testing;

#[cfg(test)]
mod tests;
