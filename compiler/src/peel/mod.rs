//! Peel: which support planes of a fragment list lie on its convex hull (the planes of its
//! convex node, see [`crate::tree`]).
//!
//! A plane is on the hull iff no vertex of the list lies strictly on one of its sides. The
//! naive test scans every vertex for every plane (O(n²) per node). Instead the distinct
//! vertices go into a bounding-volume hierarchy with f64 boxes; a query "is some vertex
//! strictly on this side?" prunes a box only when an f64 bound *proves* it (the error bound
//! of [`crate::planes::FILTER_BOUND`] with a wide extra margin), accepts a box wholly and
//! strictly on the side the same way, and decides the remaining leaves with the exact
//! predicate. Nothing is approximate: f64 only chooses which exact tests to run.
//!
//! Cost: building is O(m log m) for m distinct vertices. A query for a plane that is not on
//! the hull usually stops at the first boxes it visits; a hull plane visits the boxes that
//! touch it within the rounding margin (those around its own vertices, plus box corners
//! poking through it). Worst case (every vertex within the margin of the plane, e.g. a
//! nearly flat or highly symmetric scene) it degrades to the exact scan, O(m) per plane.
//!
//! Witnesses: a plane found off the hull comes with its proof, a vertex strictly on each
//! side ([`Witness`]). A plane whose two witnesses are still vertices of a child's list is
//! still off the hull there and is not queried again; peeling one thin layer at a time would
//! otherwise query every remaining plane again per layer. After a split, the witness vertices
//! strictly on a child's side are proven vertices of that child (a cut keeps such vertices in
//! that side's piece): [`Known::Valid`], as [`Clue`]s, since a witness's two vertices often
//! fall on different sides; a plane with half a witness is searched on its other side only.
//! After a peel, each witness vertex is looked up among the child's vertices:
//! [`Known::Inherited`]. The few planes left to query are scanned; many, searched in the
//! hierarchy.

use rayon::prelude::*;

use crate::bvh::Bvh;
use crate::hash::FastSet;
use crate::planes::{l1_max, shared_filter_bound, PlaneEntry, PlaneId, PlaneTable, Side, Vertex};
use crate::split::Fragment;

/// Points per leaf of the hierarchy. Scanning a leaf is cheap next to building levels that
/// few queries reach: 64 gave the fewest instructions in total of the sizes tried, on the
/// teapot and the cow (BENCHMARKS.md, "Tuning constants").
const LEAF: usize = 64;

/// Why a plane is not on the hull of a list: a vertex of the list strictly on each side.
#[derive(Debug, Clone)]
pub struct Witness {
    /// The plane.
    pub plane: PlaneId,
    /// A vertex strictly on its + side.
    pub front: Vertex,
    /// A vertex strictly on its − side.
    pub back: Vertex,
}

/// What a list is known to hold for a plane: vertices of the list strictly on its sides (at
/// least one); both make a [`Witness`].
#[derive(Debug, Clone)]
pub struct Clue {
    /// The plane.
    pub plane: PlaneId,
    /// A vertex strictly on its + side, if one is known.
    pub front: Option<Vertex>,
    /// A vertex strictly on its − side, if one is known.
    pub back: Option<Vertex>,
}

/// The identity of a vertex: grid points by value, cut points by allocation. Two cut points
/// at the same place may have different keys, which only costs a query; equal keys are
/// always the same point (a witness holds its `Arc`, so its address is never reused).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Key {
    Int([i32; 3]),
    Hom(usize),
}

impl Key {
    fn of(v: &Vertex) -> Key {
        match v {
            Vertex::Int(p) => Key::Int(*p),
            Vertex::Hom(h) => Key::Hom(std::sync::Arc::as_ptr(h) as usize),
        }
    }
}

/// The distinct vertices of a fragment list: hashed keys (to tell whether a vertex is one of
/// them; hashing, not sorting, since this set is rebuilt for every hull test) and, once
/// [`VertexSet::index`] is called, a bounding-volume hierarchy.
pub struct VertexSet<'a> {
    /// Each distinct vertex once, in order of first appearance, with its approximation.
    pts: Vec<([f64; 3], &'a Vertex)>,
    bvh: Bvh,
    /// The largest `|x| + |y| + |z|` of `pts` (set by [`VertexSet::index`]; see
    /// [`shared_filter_bound`]).
    l1_max: f64,
    /// Grid points.
    ints: FastSet<[i32; 3]>,
    /// Cut-point allocations (see [`Key`]).
    homs: FastSet<usize>,
}

impl<'a> VertexSet<'a> {
    /// The distinct grid vertices and cut-point allocations of `frags`, not yet indexed.
    pub fn new(frags: &'a [Fragment]) -> VertexSet<'a> {
        // A guess at the distinct counts: most vertices are shared by several fragments.
        let (uses, hom_uses) = frags
            .iter()
            .flat_map(|f| &f.vertices)
            .fold((0, 0), |(n, h), v| {
                (n + 1, h + usize::from(matches!(v, Vertex::Hom(_))))
            });
        let expected = uses / 2;
        let mut ints = FastSet::with_capacity_and_hasher(expected, Default::default());
        let mut homs = FastSet::with_capacity_and_hasher(hom_uses / 2, Default::default());
        let mut pts = Vec::with_capacity(expected);
        for f in frags {
            for v in &f.vertices {
                let new = match Key::of(v) {
                    Key::Int(p) => ints.insert(p),
                    Key::Hom(a) => homs.insert(a),
                };
                if new {
                    pts.push((v.approx(), v));
                }
            }
        }
        VertexSet {
            pts,
            bvh: Bvh::default(),
            l1_max: 0.0,
            ints,
            homs,
        }
    }

    /// True when `v` is one of the set's vertices (a cut point: the same allocation).
    pub fn contains(&self, v: &Vertex) -> bool {
        match Key::of(v) {
            Key::Int(p) => self.ints.contains(&p),
            Key::Hom(a) => self.homs.contains(&a),
        }
    }

    /// Build the hierarchy [`Self::any_strictly`] searches.
    pub fn index(&mut self) {
        if self.bvh.nodes.is_empty() {
            self.bvh = Bvh::build(&mut self.pts, |&(p, _)| (p, p), LEAF);
            self.l1_max = l1_max(self.pts.iter().map(|(p, _)| p));
        }
    }

    /// A vertex lying strictly on `side` (`Front` or `Back`) of `e`, if there is one.
    pub fn any_strictly(&self, e: &PlaneEntry, side: Side) -> Option<&'a Vertex> {
        let nodes = &self.bvh.nodes;
        debug_assert!(self.pts.is_empty() || !nodes.is_empty(), "not indexed");
        if nodes.is_empty() {
            return None;
        }
        let sign = if side == Side::Front { 1.0 } else { -1.0 };
        let m = self.bvh.margin(e);
        let bound = shared_filter_bound(e, self.l1_max);
        // Each level leaves at most one sibling on the stack (see `STACK`).
        let mut stack = [0u32; crate::bvh::STACK];
        let mut len = 1;
        while len > 0 {
            len -= 1;
            let node = &nodes[stack[len] as usize];
            let (lo, hi) = Bvh::span(node, e);
            let (lo, hi) = if sign > 0.0 { (lo, hi) } else { (-hi, -lo) };
            if hi < -m {
                continue; // every vertex strictly on the other side
            }
            let pts = &self.pts[node.first as usize..node.end as usize];
            if lo > m {
                return pts.first().map(|&(_, v)| v); // wholly, strictly on `side`
            }
            match node.children {
                None => {
                    // The first point exactly on `side`, most decided by the filter on the
                    // approximate coordinates at hand (the exact test reads the vertex).
                    for &(c, v) in pts {
                        let s = sign * (e.nf[0] * c[0] + e.nf[1] * c[1] + e.nf[2] * c[2] - e.df);
                        if s > bound || (s >= -bound && v.side(e) == side) {
                            return Some(v);
                        }
                    }
                }
                Some([l, r]) => {
                    // Visit the child reaching further to `side` first.
                    let reach_of = |c: u32| {
                        let (lo, hi) = Bvh::span(&nodes[c as usize], e);
                        if sign > 0.0 {
                            hi
                        } else {
                            -lo
                        }
                    };
                    let (first, second) = if reach_of(l) >= reach_of(r) {
                        (l, r)
                    } else {
                        (r, l)
                    };
                    stack[len] = second;
                    stack[len + 1] = first;
                    len += 2;
                }
            }
        }
        None
    }

    /// `Ok(interior_front)` when plane `p` is on the hull of the set: `interior_front` is true
    /// when the rest lies on the + side (also when every vertex is in the plane); otherwise
    /// `Err` with the witnesses that it is not. `front` and `back` are vertices of the set
    /// already known strictly on a side (that side is not searched).
    pub fn hull_side<'v>(
        &'v self,
        p: PlaneId,
        table: &PlaneTable,
        front: Option<&'v Vertex>,
        back: Option<&'v Vertex>,
    ) -> Result<bool, Witness> {
        let e = table.get(p);
        verdict(
            p,
            front.or_else(|| self.any_strictly(e, Side::Front)),
            back.or_else(|| self.any_strictly(e, Side::Back)),
        )
    }
}

/// The hull answer for plane `p` from a vertex strictly on each side, if any (see
/// [`VertexSet::hull_side`]).
fn verdict(p: PlaneId, front: Option<&Vertex>, back: Option<&Vertex>) -> Result<bool, Witness> {
    match (front, back) {
        (Some(f), Some(b)) => Err(Witness {
            plane: p,
            front: f.clone(),
            back: b.clone(),
        }),
        (f, b) => Ok(f.is_some() || b.is_none()),
    }
}

/// [`VertexSet::hull_side`] by a scan of every vertex of `frags` (no set to build: for a few
/// planes).
fn scan<'v>(
    frags: &'v [Fragment],
    p: PlaneId,
    table: &PlaneTable,
    mut front: Option<&'v Vertex>,
    mut back: Option<&'v Vertex>,
) -> Result<bool, Witness> {
    let e = table.get(p);
    for v in frags.iter().flat_map(|f| &f.vertices) {
        if front.is_some() && back.is_some() {
            break;
        }
        match v.side(e) {
            Side::Front => front = front.or(Some(v)),
            Side::Back => back = back.or(Some(v)),
            Side::On => {}
        }
    }
    verdict(p, front, back)
}

/// The support planes of a fragment list on its convex hull, and why the others are not.
#[derive(Debug, Clone, Default)]
pub struct Hull {
    /// Per plane of `planes` (the list's distinct support planes): `Some(interior_front)` when
    /// it is on the convex hull, else `None`.
    pub sides: Vec<Option<bool>>,
    /// A witness for every plane off the hull, sorted by plane (to pass to a child list).
    pub witnesses: Vec<Witness>,
}

/// What a child list is handed of its planes (sorted by plane).
#[derive(Debug, Clone)]
pub enum Known {
    /// Vertices proven to be in the list by the caller (see [`after_split`]): used as they
    /// are.
    Valid(Vec<Clue>),
    /// Witnesses found for a list this one came from: each vertex is used where it is still
    /// in the list.
    Inherited(Vec<Witness>),
}

impl Default for Known {
    /// None.
    fn default() -> Known {
        Known::Valid(Vec::new())
    }
}

/// What the witnesses of a list tell the children of a split of it by `plane`, as
/// `(front, back)`: the witness vertices strictly on a child's side (a cut keeps such a vertex
/// in that side's piece, and no fragment in the plane has one). Sorted as given; each
/// vertex's side is computed once.
pub fn after_split(witnesses: Vec<Witness>, plane: &PlaneEntry) -> (Known, Known) {
    // Sized for the most each side can get: growing them by pushes cost instructions
    // (reallocations and copies; BENCHMARKS.md, "Tuning constants").
    let n = witnesses.len();
    let (mut front, mut back) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for w in witnesses {
        let (f, b) = (w.front.side(plane), w.back.side(plane));
        let empty = || Clue {
            plane: w.plane,
            front: None,
            back: None,
        };
        // Each vertex goes to the clue of the child it is in (moved, not cloned).
        let (mut to_front, mut to_back) = (empty(), empty());
        match f {
            Side::Front => to_front.front = Some(w.front),
            Side::Back => to_back.front = Some(w.front),
            Side::On => {}
        }
        match b {
            Side::Front => to_front.back = Some(w.back),
            Side::Back => to_back.back = Some(w.back),
            Side::On => {}
        }
        if to_front.front.is_some() || to_front.back.is_some() {
            front.push(to_front);
        }
        if to_back.front.is_some() || to_back.back.is_some() {
            back.push(to_back);
        }
    }
    (Known::Valid(front), Known::Valid(back))
}

/// Planes queried by a scan of the list's vertices at most, whatever the list's size; more
/// build the hierarchy, unless [`SCAN_WORK`] allows scans.
const SCAN_MAX: usize = 8;

/// More planes than [`SCAN_MAX`] are still scanned when `planes × fragments` is at most this:
/// in small lists a scan (which stops at the first vertex found on each side searched) is
/// cheaper than building the hierarchy. This value gave the fewest instructions on the cow
/// and the bunny of those tried, and fewer than scanning only up to [`SCAN_MAX`] planes
/// (BENCHMARKS.md, "Tuning constants").
const SCAN_WORK: usize = 8192;

/// For each plane of `planes` (the distinct support planes of `frags`, sorted): is it on the
/// convex hull of `frags`? A plane with both vertices of a witness known in `known` is off the
/// hull without a query; with one, only the other side is searched.
pub fn hull_planes(
    frags: &[Fragment],
    planes: &[PlaneId],
    table: &PlaneTable,
    known: &Known,
) -> Hull {
    // What is known of each plane: vertices of `frags` strictly on its sides.
    let mut parts: Vec<(Option<&Vertex>, Option<&Vertex>)> = vec![(None, None); planes.len()];
    let set = match known {
        Known::Valid(clues) => {
            #[cfg(test)]
            {
                let set = VertexSet::new(frags);
                let parts = clues.iter().flat_map(|c| c.front.iter().chain(&c.back));
                for v in parts {
                    assert!(set.contains(v), "invalid clue");
                }
            }
            fill_parts(
                planes,
                clues,
                |c| c.plane,
                &mut parts,
                |c| (c.front.as_ref(), c.back.as_ref()),
            );
            None
        }
        // Witnesses are checked against the list's vertices.
        Known::Inherited(witnesses) if !witnesses.is_empty() => {
            let set = VertexSet::new(frags);
            fill_parts(
                planes,
                witnesses,
                |w| w.plane,
                &mut parts,
                |w| {
                    (
                        set.contains(&w.front).then_some(&w.front),
                        set.contains(&w.back).then_some(&w.back),
                    )
                },
            );
            Some(set)
        }
        Known::Inherited(_) => None,
    };
    // Planes to search (both sides, or the one not known).
    let queried = parts
        .iter()
        .filter(|(f, b)| f.is_none() || b.is_none())
        .count();
    let set = if queried > SCAN_MAX && queried * frags.len() > SCAN_WORK {
        let mut set = set.unwrap_or_else(|| VertexSet::new(frags));
        set.index();
        Some(set)
    } else {
        None
    };
    // A whole witness needs no search (going through the searches for it costs instructions:
    // BENCHMARKS.md, "Tuning constants"); the searches skip a side already known.
    let test = |(&p, &(f, b)): (&PlaneId, &(Option<&Vertex>, Option<&Vertex>))| match &set {
        _ if f.is_some() && b.is_some() => verdict(p, f, b),
        Some(set) => set.hull_side(p, table, f, b),
        None => scan(frags, p, table, f, b),
    };
    let results: Vec<Result<bool, Witness>> = if queried > 64 && frags.len() > 512 {
        planes.par_iter().zip(&parts).map(test).collect()
    } else {
        planes.iter().zip(&parts).map(test).collect()
    };
    let mut hull = Hull {
        sides: Vec::with_capacity(planes.len()),
        witnesses: Vec::with_capacity(planes.len()),
    };
    for r in results {
        match r {
            Ok(interior_front) => hull.sides.push(Some(interior_front)),
            Err(w) => {
                hull.sides.push(None);
                hull.witnesses.push(w);
            }
        }
    }
    hull
}

/// Sets `parts[i]` to `known(item)` for each of `items` (sorted by plane, as `planes` is) whose
/// plane is `planes[i]`.
fn fill_parts<'k, T>(
    planes: &[PlaneId],
    items: &'k [T],
    plane_of: impl Fn(&T) -> PlaneId,
    parts: &mut [(Option<&'k Vertex>, Option<&'k Vertex>)],
    known: impl Fn(&'k T) -> (Option<&'k Vertex>, Option<&'k Vertex>),
) {
    let mut k = 0;
    for (i, &p) in planes.iter().enumerate() {
        while k < items.len() && plane_of(&items[k]) < p {
            k += 1;
        }
        if let Some(item) = items.get(k).filter(|item| plane_of(item) == p) {
            parts[i] = known(item);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planes::Plane;
    use crate::split::SplitResult;
    use proptest::prelude::*;

    fn naive(frags: &[Fragment], e: &PlaneEntry) -> Option<bool> {
        let sides: Vec<Side> = frags
            .iter()
            .flat_map(|f| f.vertices.iter().map(|v| v.side(e)))
            .collect();
        let (f, b) = (sides.contains(&Side::Front), sides.contains(&Side::Back));
        match (f, b) {
            (true, true) => None,
            (true, false) => Some(true),
            (false, true) => Some(false),
            (false, false) => Some(true),
        }
    }

    /// Triangles of `pts` (three points each) in a fresh table, then cut by the first one's
    /// plane, so that the list also holds cut vertices.
    fn soup(pts: &[[i32; 3]]) -> (PlaneTable, Vec<Fragment>) {
        let mut table = PlaneTable::default();
        let frags: Vec<Fragment> = pts
            .chunks_exact(3)
            .filter_map(|t| crate::split::triangle_fragment(&mut table, [t[0], t[1], t[2]]))
            .collect();
        let Some(cut) = frags.first().map(|f| f.support) else {
            return (table, frags);
        };
        let mut out = Vec::new();
        for f in frags {
            match f.split(cut, &table) {
                Some(crate::split::SplitResult::Cut(a, b)) => out.extend([a, b]),
                Some(
                    crate::split::SplitResult::Front(f)
                    | crate::split::SplitResult::Back(f)
                    | crate::split::SplitResult::On(f),
                ) => out.push(f),
                None => {}
            }
        }
        (table, out)
    }

    /// `hull` answers like the exact scan on `frags`, with a witness for exactly the planes off
    /// the hull.
    fn check(frags: &[Fragment], table: &PlaneTable, hull: &Hull) -> Result<(), TestCaseError> {
        let planes = support_planes(frags);
        for (i, &p) in planes.iter().enumerate() {
            prop_assert_eq!(hull.sides[i], naive(frags, table.get(p)));
        }
        let off: Vec<PlaneId> = hull.witnesses.iter().map(|w| w.plane).collect();
        let want: Vec<PlaneId> = planes
            .iter()
            .zip(&hull.sides)
            .filter(|(_, s)| s.is_none())
            .map(|(&p, _)| p)
            .collect();
        prop_assert_eq!(off, want);
        // Each witness is a proof: its vertices lie strictly on the sides it claims.
        for w in &hull.witnesses {
            let e = table.get(w.plane);
            prop_assert_eq!((w.front.side(e), w.back.side(e)), (Side::Front, Side::Back));
        }
        Ok(())
    }

    fn support_planes(frags: &[Fragment]) -> Vec<PlaneId> {
        let mut p: Vec<PlaneId> = frags.iter().map(|f| f.support).collect();
        p.sort_unstable();
        p.dedup();
        p
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// The hierarchy answers exactly like the exact scan, on clustered and coplanar points.
        #[test]
        fn hierarchy_matches_the_exact_scan(
            pts in proptest::collection::vec([-40i32..40, -40i32..40, -3i32..3], 3..200),
            scale in 0u32..20,
        ) {
            let s = 1i32 << scale;
            let pts: Vec<[i32; 3]> = pts.iter().map(|p| [p[0] * s, p[1] * s, p[2]]).collect();
            let mut table = PlaneTable::default();
            let mut frags = Vec::new();
            for t in pts.chunks_exact(3) {
                if let Some((p, _)) = Plane::through(t[0], t[1], t[2]) {
                    let id = table.insert(p);
                    frags.push(Fragment {
                        source: 0,
                        support: id,
                        flipped: false,
                        vertices: t.iter().map(|&q| Vertex::Int(q)).collect(),
                        edges: Vec::new(),
                    });
                }
            }
            let planes: Vec<PlaneId> = (0..table.len() as PlaneId).collect();
            let got = hull_planes(&frags, &planes, &table, &Known::default());
            for (i, &p) in planes.iter().enumerate() {
                prop_assert_eq!(got.sides[i], naive(&frags, table.get(p)));
            }
            // Lists this small are scanned (see `SCAN_WORK`): the hierarchy is asked directly.
            let mut set = VertexSet::new(&frags);
            set.index();
            for &p in &planes {
                let e = table.get(p);
                match set.hull_side(p, &table, None, None) {
                    Ok(interior_front) => prop_assert_eq!(Some(interior_front), naive(&frags, e)),
                    Err(w) => {
                        prop_assert_eq!(naive(&frags, e), None);
                        prop_assert_eq!((w.front.side(e), w.back.side(e)), (Side::Front, Side::Back));
                        // Half a witness known: the other side is searched, the known one kept.
                        for (f, b) in [(Some(&w.front), None), (None, Some(&w.back))] {
                            let Err(h) = set.hull_side(p, &table, f, b) else {
                                return Err(TestCaseError::fail("a known side was lost"));
                            };
                            prop_assert_eq!((h.front.side(e), h.back.side(e)), (Side::Front, Side::Back));
                        }
                    }
                }
            }
        }

        /// A child list answers exactly like the exact scan when given its parent's
        /// witnesses: after peeling (any part of the parent, inherited witnesses checked for
        /// presence) and after a split (witnesses strictly on the child's side, used as they
        /// are: `hull_planes` asserts under test that they are vertices of the child). Lists
        /// of up to 50 planes take both the scan and the hierarchy.
        #[test]
        fn witnesses_carried_to_a_child_keep_answers_exact(
            pts in proptest::collection::vec([-30i32..30, -30i32..30, -4i32..4], 6..150),
            keep in proptest::collection::vec(proptest::bool::weighted(0.8), 100),
            cut in 0usize..1000,
        ) {
            let (table, frags) = soup(&pts);
            let planes = support_planes(&frags);
            let parent = hull_planes(&frags, &planes, &table, &Known::default());
            check(&frags, &table, &parent)?;
            for w in &parent.witnesses {
                let e = table.get(w.plane);
                prop_assert_eq!(w.front.side(e), Side::Front);
                prop_assert_eq!(w.back.side(e), Side::Back);
            }
            let child: Vec<Fragment> = frags
                .iter()
                .enumerate()
                .filter(|(i, _)| keep[i % keep.len()])
                .map(|(_, f)| f.clone())
                .collect();
            let planes = support_planes(&child);
            let got = hull_planes(&child, &planes, &table, &Known::Inherited(parent.witnesses.clone()));
            check(&child, &table, &got)?;
            let Some(&p) = planes.get(cut % planes.len().max(1)) else { return Ok(()) };
            let (known_front, known_back) = after_split(got.witnesses, table.get(p));
            for (side, known) in [(Side::Front, known_front), (Side::Back, known_back)] {
                let mut part = Vec::new();
                for f in child.iter().cloned() {
                    match f.split(p, &table) {
                        Some(SplitResult::Cut(a, b)) => {
                            part.push(if side == Side::Front { a } else { b })
                        }
                        Some(SplitResult::Front(f)) if side == Side::Front => part.push(f),
                        Some(SplitResult::Back(f)) if side == Side::Back => part.push(f),
                        _ => {}
                    }
                }
                let planes = support_planes(&part);
                check(&part, &table, &hull_planes(&part, &planes, &table, &known))?;
            }
        }
    }
}
