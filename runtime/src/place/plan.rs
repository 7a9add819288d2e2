//! The frame's order with objects: the world's tree walked node by node with the pieces of
//! the objects that lie in each node's region, into a list of [`Step`]s, back to front (see
//! the module docs of [`super`]).

use glam::{Mat3, Vec3};

use crate::error::RenderError;
use crate::read::{Node, Plane, Scene, SideEye};
use crate::traverse::{sees_interior, Tree, INTERIOR_FRONT};

/// "No cut" / "no piece" in a link field.
pub(crate) const NO_CUT: u16 = u16::MAX;
const NONE: u16 = u16::MAX;

/// One step of a frame with objects, in back-to-front order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Step {
    /// The world's subtree under this node, walked as usual.
    Subtree(u32),
    /// The polygons of this world convex node whose interior side (`true`) or exterior side
    /// the eye sees.
    Hull { node: u32, interior: bool },
    /// An object's piece: the object clipped to the half-spaces of the cut chain `cut`.
    Piece { object: u16, cut: u16 },
}

/// A half-space a piece is clipped to: the side of `plane` (world coordinates relative to
/// the world's centre) where `distance >= 0` (`keep_plus`) or `<= 0`; `prev` the cut before
/// it in the piece's chain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Cut {
    pub(crate) plane: Plane,
    pub(crate) keep_plus: bool,
    pub(crate) prev: u16,
}

impl Cut {
    pub(crate) const EMPTY: Cut = Cut {
        plane: Plane {
            normal: Vec3::ZERO,
            d: 0.0,
        },
        keep_plus: true,
        prev: NO_CUT,
    };
}

/// A piece: an object and its cut chain, linked into the set of pieces of one region.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Piece {
    object: u16,
    cut: u16,
    next: u16,
    /// A box in the object's coordinates that holds the piece: the object's box, shrunk at
    /// each cut to hold what is left of it.
    lo: Vec3,
    hi: Vec3,
}

impl Piece {
    pub(crate) const EMPTY: Piece = Piece {
        object: 0,
        cut: NO_CUT,
        next: NONE,
        lo: Vec3::ZERO,
        hi: Vec3::ZERO,
    };
}

/// What is left to do: a world node with the set of pieces in its region (linked from
/// `set`), a set of pieces to order and emit, or a step to emit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Task {
    Idle,
    Node { node: u32, set: u16 },
    Group(u16),
    Emit(Step),
}

/// An object this frame: visible or not, its rotation and offset into the world's
/// coordinates, and its posed box's corners there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Placement {
    pub(crate) visible: bool,
    pub(crate) rotation: Mat3,
    pub(crate) offset: Vec3,
    pub(crate) corners: [Vec3; 8],
    /// The object's box in its own coordinates.
    pub(crate) lo: Vec3,
    pub(crate) hi: Vec3,
}

impl Placement {
    pub(crate) const HIDDEN: Placement = Placement {
        visible: false,
        rotation: Mat3::IDENTITY,
        offset: Vec3::ZERO,
        corners: [Vec3::ZERO; 8],
        lo: Vec3::ZERO,
        hi: Vec3::ZERO,
    };

    /// The object of box `lo..=hi` (its coordinates) placed by `rotation` and `offset`.
    pub(crate) fn new(rotation: Mat3, offset: Vec3, lo: Vec3, hi: Vec3) -> Placement {
        Placement {
            visible: true,
            rotation,
            offset,
            corners: box_corners(lo, hi).map(|p| rotation * p + offset),
            lo,
            hi,
        }
    }
}

/// The corners of the box `lo..=hi`, corner `k` taking `hi` on the axes of the bits of `k`.
fn box_corners(lo: Vec3, hi: Vec3) -> [Vec3; 8] {
    core::array::from_fn(|k| {
        Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The box (in the object's coordinates) that holds what is left of the box `lo..=hi` of an
/// object placed by `p` on the side of `plane` where its distance is `>= 0` (`keep_plus`) or
/// `<= 0`: that of its corners on that side and of the points where its edges cross the plane.
fn shrunk(p: &Placement, lo: Vec3, hi: Vec3, plane: &Plane, keep_plus: bool) -> (Vec3, Vec3) {
    let local = box_corners(lo, hi);
    let d = local.map(|c| {
        let d = plane.distance(p.rotation * c + p.offset);
        if keep_plus {
            d
        } else {
            -d
        }
    });
    let (mut a, mut b) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let mut take = |q: Vec3| {
        a = a.min(q);
        b = b.max(q);
    };
    for k in 0..8 {
        if d[k] >= 0.0 {
            take(local[k]);
        }
        // The edges from corner k along each axis it does not take `hi` on.
        for bit in [1, 2, 4] {
            let j = k | bit;
            if j != k && (d[k] < 0.0) != (d[j] < 0.0) {
                let t = d[k] / (d[k] - d[j]);
                take(local[k] + (local[j] - local[k]) * t);
            }
        }
    }
    // Rounding may leave the points a hair outside: never grow, and an empty set (a piece
    // the plane barely touches) keeps its old box.
    if a.cmple(b).all() {
        (a.max(lo), b.min(hi))
    } else {
        (lo, hi)
    }
}

/// Where a posed box lies against a plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Class {
    Plus,
    Minus,
    Both,
}

/// Relative width of the band around a plane inside which a box counts as on its side.
const HAIR: f32 = 1.0 / (1u32 << 20) as f32;

fn classify(corners: &[Vec3; 8], plane: &Plane, scale: f32) -> Class {
    let margin = plane.normal.abs().element_sum() * scale * HAIR;
    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
    for c in corners {
        let d = plane.distance(*c);
        lo = lo.min(d);
        hi = hi.max(d);
    }
    if lo >= -margin {
        Class::Plus
    } else if hi <= margin {
        Class::Minus
    } else {
        Class::Both
    }
}

/// The frame's pieces, cuts and steps being built.
struct Builder<'m, 'p> {
    placements: &'p [Placement],
    steps: &'m mut [Step],
    pieces: &'m mut [Piece],
    cuts: &'m mut [Cut],
    step_count: usize,
    piece_count: usize,
    cut_count: usize,
    scale: f32,
    eye: Vec3,
    /// For the pieces' order: the view's screen test (see [`plan`]).
    overlap: &'p dyn Fn(u16, u16) -> bool,
}

impl Builder<'_, '_> {
    fn emit(&mut self, step: Step) -> Result<(), RenderError> {
        let slot = self.steps.get_mut(self.step_count).ok_or(full())?;
        *slot = step;
        self.step_count += 1;
        Ok(())
    }

    fn piece(
        &mut self,
        object: u16,
        cut: u16,
        next: u16,
        bounds: (Vec3, Vec3),
    ) -> Result<u16, RenderError> {
        let at = self.piece_count;
        let slot = self.pieces.get_mut(at).ok_or(full())?;
        let (lo, hi) = (bounds.0, bounds.1);
        *slot = Piece {
            object,
            cut,
            next,
            lo,
            hi,
        };
        self.piece_count += 1;
        u16::try_from(at).map_err(|_| full())
    }

    fn cut(&mut self, plane: Plane, keep_plus: bool, prev: u16) -> Result<u16, RenderError> {
        // One value per plane: a plane met again (through another polygon on it) takes the
        // value of its first cut, so that every piece computes the same crossings.
        let (plane, keep_plus) = self.canonical(plane, keep_plus);
        let at = self.cut_count;
        let slot = self.cuts.get_mut(at).ok_or(full())?;
        *slot = Cut {
            plane,
            keep_plus,
            prev,
        };
        self.cut_count += 1;
        u16::try_from(at).map_err(|_| full())
    }

    /// `plane` as the first cut made by the same plane (within [`HAIR`]) holds it, with the
    /// side kept turned accordingly; `plane` itself when it is new.
    fn canonical(&self, plane: Plane, keep_plus: bool) -> (Plane, bool) {
        let length = plane.normal.length();
        if length.is_nan() || length <= 0.0 {
            return (plane, keep_plus);
        }
        let (n, d) = (plane.normal / length, plane.d / length);
        for c in self.cuts.get(..self.cut_count).unwrap_or(&[]) {
            let l = c.plane.normal.length();
            if l.is_nan() || l <= 0.0 {
                continue;
            }
            let (m, e) = (c.plane.normal / l, c.plane.d / l);
            let close = |sign: f32| {
                (n - m * sign).abs().element_sum() <= 4.0 * HAIR
                    && (d - e * sign).abs() <= self.scale * HAIR
            };
            if close(1.0) {
                return (c.plane, keep_plus);
            }
            if close(-1.0) {
                return (c.plane, !keep_plus);
            }
        }
        (plane, keep_plus)
    }

    fn get(&self, piece: u16) -> Piece {
        self.pieces
            .get(usize::from(piece))
            .copied()
            .unwrap_or(Piece::EMPTY)
    }

    fn placement(&self, object: u16) -> &Placement {
        self.placements
            .get(usize::from(object))
            .unwrap_or(&Placement::HIDDEN)
    }

    /// Splits `set` by `plane` into the pieces on its + side and on its − side, cutting
    /// those that cross it; returns the two sets' heads.
    fn split(&mut self, mut set: u16, plane: &Plane) -> Result<(u16, u16), RenderError> {
        let (mut plus, mut minus) = (NONE, NONE);
        while set != NONE {
            let p = self.get(set);
            let next = p.next;
            let class = match self.known_side(p.cut, plane) {
                Some(class) => class,
                None => {
                    let at = self.placement(p.object);
                    let corners = box_corners(p.lo, p.hi).map(|c| at.rotation * c + at.offset);
                    classify(&corners, plane, self.scale)
                }
            };
            match class {
                Class::Plus => {
                    self.relink(set, plus);
                    plus = set;
                }
                Class::Minus => {
                    self.relink(set, minus);
                    minus = set;
                }
                Class::Both => {
                    let at = *self.placement(p.object);
                    let c = self.cut(*plane, true, p.cut)?;
                    let bounds = shrunk(&at, p.lo, p.hi, plane, true);
                    plus = self.piece(p.object, c, plus, bounds)?;
                    let c = self.cut(*plane, false, p.cut)?;
                    let bounds = shrunk(&at, p.lo, p.hi, plane, false);
                    minus = self.piece(p.object, c, minus, bounds)?;
                }
            }
            set = next;
        }
        Ok((plus, minus))
    }

    /// The side of `plane` a piece with the cut chain `cut` lies on, when the chain already
    /// cut it by the same plane (within [`HAIR`]): the polygons of a world plane are many, and
    /// each would cut the piece again.
    fn known_side(&self, mut cut: u16, plane: &Plane) -> Option<Class> {
        // Every cut holds its plane's canonical value (`Self::cut`): the same plane is the
        // same bits; `same` says whether it faces the way `plane` does.
        let (canonical, same) = self.canonical(*plane, true);
        let mut steps = 0;
        while let Some(c) = self.cuts.get(usize::from(cut)).filter(|_| cut != NO_CUT) {
            if c.plane == canonical {
                return Some(if c.keep_plus == same {
                    Class::Plus
                } else {
                    Class::Minus
                });
            }
            steps += 1;
            if steps > self.cut_count {
                break;
            }
            cut = c.prev;
        }
        None
    }

    fn relink(&mut self, piece: u16, next: u16) {
        if let Some(p) = self.pieces.get_mut(usize::from(piece)) {
            p.next = next;
        }
    }

    /// Emits the pieces of `set` (of distinct objects, in one region of the world) back to
    /// front: each after every piece its object may hide.
    fn group(&mut self, set: u16) -> Result<(), RenderError> {
        const MAX: usize = crate::read::layout::MAX_PARTS as usize;
        let mut pending = [(0u16, 0u16); MAX];
        let mut n = 0;
        let mut at = set;
        while at != NONE {
            let p = self.get(at);
            let slot = pending.get_mut(n).ok_or(full())?;
            *slot = (p.object, p.cut);
            n += 1;
            at = p.next;
        }
        while n > 0 {
            // The first piece no other pending piece must precede.
            let mut chosen = None;
            'candidates: for i in 0..n {
                for j in 0..n {
                    if i != j && self.precedes(pending[j].0, pending[i].0)? {
                        continue 'candidates;
                    }
                }
                chosen = Some(i);
                break;
            }
            let i = match chosen {
                Some(i) => i,
                None => {
                    let (a, b) = (pending[0].0, pending[1 % n].0);
                    return Err(RenderError::ObjectsIntersect {
                        first: u32::from(a.min(b)),
                        second: u32::from(a.max(b)),
                    });
                }
            };
            let (object, cut) = pending[i];
            self.emit(Step::Piece { object, cut })?;
            pending.copy_within(i + 1..n, i);
            n -= 1;
        }
        Ok(())
    }

    /// Whether object `a` must be drawn before object `b` (back to front), asked of each pair
    /// the same way round (by [`Self::first_of`]), so that the answers agree.
    fn precedes(&self, a: u16, b: u16) -> Result<bool, RenderError> {
        Ok(if a < b {
            self.first_of(a, b)? == Some(true)
        } else {
            self.first_of(b, a)? == Some(false)
        })
    }

    /// Which of objects `a` and `b` comes first back to front: `a` (`Some(true)`) when a plane
    /// separates their boxes with the eye on `b`'s side, `b` when on `a`'s, either (`None`)
    /// when no plane separates them but they do not overlap on the screen. (Two separating
    /// planes may disagree: then neither object can hide the other.) Boxes that no plane
    /// separates and that overlap on the screen cannot be ordered: an error naming them.
    fn first_of(&self, a: u16, b: u16) -> Result<Option<bool>, RenderError> {
        let (pa, pb) = match (
            self.placements.get(usize::from(a)),
            self.placements.get(usize::from(b)),
        ) {
            (Some(pa), Some(pb)) => (pa, pb),
            _ => return Ok(None),
        };
        let axes_a = [pa.rotation.x_axis, pa.rotation.y_axis, pa.rotation.z_axis];
        let axes_b = [pb.rotation.x_axis, pb.rotation.y_axis, pb.rotation.z_axis];
        let mut axes = [Vec3::ZERO; 15];
        axes[..3].copy_from_slice(&axes_a);
        axes[3..6].copy_from_slice(&axes_b);
        for (k, axis) in axes[6..].iter_mut().enumerate() {
            *axis = axes_a[k / 3].cross(axes_b[k % 3]);
        }
        for n in axes {
            let length = n.abs().element_sum();
            if length < 1e-6 {
                continue;
            }
            let span = |corners: &[Vec3; 8]| {
                corners
                    .iter()
                    .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), c| {
                        let d = n.dot(*c);
                        (lo.min(d), hi.max(d))
                    })
            };
            let (a_lo, a_hi) = span(&pa.corners);
            let (b_lo, b_hi) = span(&pb.corners);
            let margin = length * self.scale * HAIR;
            let e = n.dot(self.eye);
            if a_hi <= b_lo + margin {
                // a below, b above: the eye above the middle sees b in front.
                return Ok(Some(e >= (a_hi + b_lo) * 0.5));
            }
            if b_hi <= a_lo + margin {
                return Ok(Some(e < (b_hi + a_lo) * 0.5));
            }
        }
        if (self.overlap)(a, b) {
            Err(RenderError::ObjectsIntersect {
                first: u32::from(a.min(b)),
                second: u32::from(a.max(b)),
            })
        } else {
            Ok(None)
        }
    }
}

fn full() -> RenderError {
    RenderError::ObjectMemory
}

/// Pushes a task onto `tasks` (of which `len` are in use).
fn push(tasks: &mut [Task], len: &mut usize, task: Task) -> Result<(), RenderError> {
    let slot = tasks.get_mut(*len).ok_or(full())?;
    *slot = task;
    *len += 1;
    Ok(())
}

/// The frame's order, back to front, into `steps`: the world (if any) walked for the eye at
/// `eye` (relative to its centre; `side_eye` as its polygon side test takes it) with the
/// visible objects of the first `count` placements placed in it. `scale` bounds the magnitude of the
/// coordinates compared (for the margin of [`classify`]); `overlap(a, b)` says whether two
/// objects' boxes may overlap on the screen. Returns the number of steps.
#[allow(clippy::too_many_arguments)]
pub(crate) fn plan(
    world: Option<&Scene<'_>>,
    eye: Vec3,
    side_eye: &SideEye,
    count: usize,
    scale: f32,
    overlap: &dyn Fn(u16, u16) -> bool,
    memory: &mut super::Memory<'_>,
) -> Result<usize, RenderError> {
    let placements = memory.placements.get(..count).unwrap_or(&[]);
    let mut b = Builder {
        placements,
        steps: &mut *memory.steps,
        pieces: &mut *memory.pieces,
        cuts: &mut *memory.cuts,
        step_count: 0,
        piece_count: 0,
        cut_count: 0,
        scale,
        eye,
        overlap,
    };
    let tasks = &mut *memory.tasks;
    let mut set = NONE;
    for (k, p) in placements.iter().enumerate().rev() {
        if p.visible {
            let k = u16::try_from(k).map_err(|_| full())?;
            set = b.piece(k, NO_CUT, set, (p.lo, p.hi))?;
        }
    }
    let mut len = 0usize;
    let root = world.and_then(Tree::root);
    match root {
        Some(root) => push(tasks, &mut len, Task::Node { node: root, set })?,
        None if set != NONE => push(tasks, &mut len, Task::Group(set))?,
        None => {}
    }
    let visits_limit = world.map_or(0, |w| w.header().node_count);
    let mut visits = 0u32;
    while len > 0 {
        len -= 1;
        let task = tasks.get(len).copied().unwrap_or(Task::Idle);
        match task {
            Task::Idle => {}
            Task::Emit(step) => b.emit(step)?,
            Task::Group(set) => b.group(set)?,
            Task::Node { node, set } if set == NONE => b.emit(Step::Subtree(node))?,
            Task::Node { node, set } => {
                let Some(world) = world else { break };
                visits += 1;
                if visits > visits_limit {
                    return Err(RenderError::MalformedTree);
                }
                let child = |c: Option<u32>, set: u16| match c {
                    Some(node) => Some(Task::Node { node, set }),
                    None if set != NONE => Some(Task::Group(set)),
                    None => None,
                };
                match Tree::node(world, node) {
                    Node::Split { plane, front, back } => {
                        let plane = Tree::plane(world, plane);
                        let (plus, minus) = b.split(set, &plane)?;
                        // As the traversal: the eye on the + side draws the − child first.
                        let eye_plus = plane.distance(eye) >= 0.0;
                        let (first, second) = if eye_plus {
                            ((back, minus), (front, plus))
                        } else {
                            ((front, plus), (back, minus))
                        };
                        for (c, s) in [second, first] {
                            if let Some(t) = child(c, s) {
                                push(tasks, &mut len, t)?;
                            }
                        }
                    }
                    Node::Convex {
                        first,
                        count,
                        child: inner,
                    } => {
                        let count = count.min(world.header().polygon_count.saturating_sub(first));
                        let mut inside = set;
                        for k in first..first + count {
                            if inside == NONE {
                                break;
                            }
                            let polygon = world.polygon_shape(k);
                            let v = |i| world.polygon_vertex(&polygon, i);
                            let plane = Plane::through(v(0), v(1), v(2));
                            let (plus, minus) = b.split(inside, &plane)?;
                            let interior_plus = polygon.flags & INTERIOR_FRONT != 0;
                            let (interior, exterior) = if interior_plus {
                                (plus, minus)
                            } else {
                                (minus, plus)
                            };
                            inside = interior;
                            if exterior == NONE {
                                continue;
                            }
                            // The pieces outside this polygon's plane are apart from the
                            // whole node: behind it when the eye is on its interior side.
                            let side = world.eye_side(&polygon, side_eye);
                            if sees_interior(&polygon, side) {
                                b.group(exterior)?;
                            } else {
                                push(tasks, &mut len, Task::Group(exterior))?;
                            }
                        }
                        let hull = |interior| Step::Hull { node, interior };
                        push(tasks, &mut len, Task::Emit(hull(false)))?;
                        if let Some(t) = child(inner, inside) {
                            push(tasks, &mut len, t)?;
                        }
                        b.emit(hull(true))?;
                    }
                }
            }
        }
    }
    Ok(b.step_count)
}
