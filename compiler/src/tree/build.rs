//! The exact build: convex nodes, else splits (see [`super`]), on exact fragments, with an
//! explicit work stack (deep trees cannot overflow the call stack) and rayon for large
//! independent subtrees.
//!
//! Rule for the fragments lying in a split's support plane P: they go to the side with fewer
//! fragments (ties: the side whose source ids come first), and that child is built directly
//! as a convex node holding exactly them, its interior being that side of P. Then no child
//! list has more distinct support planes than its parent, and every one but that convex node
//! has fewer. A free or edge split's children have no more support planes and fewer
//! fragments. So the pair (support planes, fragments) drops lexicographically and the build
//! ends (the argument in full: [`super`]); `Limit` checks it on every node
//! (`CompileError::Invariant`, never a hang).
//!
//! One file for one loop: the work stack, the split and convex steps it runs, and the subtrees
//! it hands to rayon share the job and slot types and the pre-order bookkeeping.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use rayon::prelude::*;

use super::input::Input;
use super::BuildOptions;
use crate::error::CompileError;
use crate::peel::{after_split, hull_planes, Known, Witness};
use crate::planes::{Plane, PlaneEntry, PlaneId, PlaneTable, Side};
use crate::split::choose::{choose_split_costed, content_hash, SplitRule, COST_ALL, CUT_WEIGHT};
use crate::split::edge::{divides, edge_planes};
use crate::split::free::{best_free, Free};
use crate::split::lopsided::{is_lopsided, lopsided_splits, Lopsided, CHAIN_AFTER};
use crate::split::{Fragment, Placement, SplitResult};

/// Subtrees are built in parallel when both sides of a split hold at least this many
/// fragments and at least an eighth of the node (which bounds the join recursion depth).
const PAR_MIN: usize = 2048;

/// Subtrees built in parallel so far (tests check that the parallel path is exercised).
#[cfg(test)]
pub(crate) static JOINS: AtomicU64 = AtomicU64::new(0);

/// Lopsided splits laid out from a batch so far (tests check that the path is exercised).
#[cfg(test)]
pub(crate) static CHAINED: AtomicU64 = AtomicU64::new(0);

/// A node of the exact tree (indices local to its [`ExactTree`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ExactNode {
    /// A convex set: polygons `first .. first + count`.
    Convex {
        first: u32,
        count: u32,
        child: Option<u32>,
        support_planes: u32,
    },
    /// A split.
    Split {
        plane: SplitPlane,
        front: Option<u32>,
        back: Option<u32>,
        support_planes: u32,
    },
}

/// The plane of a split node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SplitPlane {
    /// A support plane of the list (a table plane).
    Support(PlaneId),
    /// A plane through grid vertices of the list that cuts none of its fragments.
    Free(Plane),
    /// A table plane that is none of the list's support planes (the plane of one of its
    /// fragments' edges, [`crate::split::edge`]), with some fragment wholly on each side.
    Edge(PlaneId),
}

impl SplitPlane {
    /// The plane with its f64 approximation.
    pub(crate) fn entry(self, table: &PlaneTable) -> PlaneEntry {
        match self {
            SplitPlane::Support(p) | SplitPlane::Edge(p) => *table.get(p),
            SplitPlane::Free(p) => PlaneEntry::new(p),
        }
    }
}

/// A polygon of a convex node.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ExactPolygon {
    pub frag: Fragment,
    /// The rest of its convex set (and the node's subtree) lies on the + side of its plane.
    pub interior_front: bool,
}

/// The display tree with exact geometry; nodes in pre-order, root 0.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct ExactTree {
    pub nodes: Vec<ExactNode>,
    pub polygons: Vec<ExactPolygon>,
    pub cuts: u64,
}

/// Where a node goes: the root, or a child link of an earlier node.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Slot {
    Root,
    Child(u32),
    Front(u32),
    Back(u32),
}

/// Bound on a child list, lexicographic: `(support planes, fragments) < (max, fragments)`.
#[derive(Debug, Clone, Copy)]
struct Limit {
    max: u32,
    fragments: usize,
}

impl Limit {
    /// Fewer than `max` support planes.
    fn below(max: u32) -> Limit {
        Limit { max, fragments: 0 }
    }

    /// At most `max` support planes.
    fn at_most(max: u32) -> Limit {
        Limit {
            max,
            fragments: usize::MAX,
        }
    }

    /// At most `max` support planes, and fewer than `fragments` fragments with `max`.
    fn fewer(max: u32, fragments: usize) -> Limit {
        Limit { max, fragments }
    }

    fn check(self, k: u32, n: usize, what: &str) -> Result<(), CompileError> {
        if (k, n) >= (self.max, self.fragments) {
            return Err(CompileError::Invariant(format!(
                "{what}: {k} support planes and {n} fragments, parent allows fewer than ({}, {})",
                self.max, self.fragments
            )));
        }
        Ok(())
    }
}

enum Job {
    /// `compile(L)`. `known`: witnesses found for an ancestor's list. `lopsided`: how many
    /// lopsided splits in a row left this list; from [`CHAIN_AFTER`] on, more are looked for
    /// in one pass before one is chosen alone (see [`crate::split::lopsided`]).
    Compile {
        frags: Vec<Fragment>,
        known: Known,
        slot: Slot,
        limit: Limit,
        lopsided: u32,
    },
    /// A chain of lopsided splits decided ahead (`steps`, the next one last), then
    /// `compile(rest)`, which looks for the next batch at once when `again` (removing these
    /// fragments frees more such splits: the ones they crossed).
    Chain {
        steps: Vec<ChainStep>,
        rest: Vec<Fragment>,
        again: bool,
        /// Witnesses for the list the chain starts from (checked against `rest`).
        known: Vec<Witness>,
        slot: Slot,
        limit: Limit,
    },
    /// The child of a split holding the split plane's fragments `on`: a convex node of
    /// exactly them, then `compile(rest)`.
    InPlane {
        on: Vec<Fragment>,
        rest: Vec<Fragment>,
        /// Witnesses for `rest`.
        known: Known,
        interior_front: bool,
        slot: Slot,
        limit: Limit,
    },
}

/// One split of a chain of lopsided splits, decided ahead.
struct ChainStep {
    plane: PlaneId,
    /// The fragments in the plane.
    on: Vec<Fragment>,
    /// The small side's fragments.
    small: Vec<Fragment>,
    /// The small side is the + side.
    small_front: bool,
    /// Distinct support planes of the list the split divides.
    support_planes: u32,
}

impl Job {
    /// Where the job's node goes.
    fn slot(&self) -> Slot {
        match self {
            Job::Compile { slot, .. } | Job::InPlane { slot, .. } | Job::Chain { slot, .. } => {
                *slot
            }
        }
    }

    /// Fragments the job starts from.
    fn len(&self) -> usize {
        match self {
            Job::Compile { frags, .. } => frags.len(),
            Job::InPlane { on, rest, .. } => on.len() + rest.len(),
            Job::Chain { steps, rest, .. } => {
                rest.len()
                    + steps
                        .iter()
                        .map(|s| s.on.len() + s.small.len())
                        .sum::<usize>()
            }
        }
    }

    /// The same job as the root of a separately built subtree.
    fn rooted(mut self) -> Job {
        match &mut self {
            Job::Compile { slot, .. } | Job::InPlane { slot, .. } | Job::Chain { slot, .. } => {
                *slot = Slot::Root
            }
        }
        self
    }
}

struct Ctx<'a> {
    table: &'a PlaneTable,
    options: &'a BuildOptions,
    progress: &'a (dyn Fn(u64) + Sync),
    placed: AtomicU64,
    /// How this build weighs its split planes.
    rule: Rule,
    /// Small lists are built once per rule of [`RULES`], the best kept ([`best_of`]); off
    /// in those builds themselves.
    best_of: bool,
    /// In those builds: the free splits found so far (see [`free_of`]).
    frees: Option<&'a Mutex<FreeMemo>>,
}

/// Free splits found for lists, by [`content_hash`]: a list's free split does not depend on
/// the rule, and the builds of one list by each rule meet the same lists again (the list
/// itself first, and every list below the splits the rules agree on).
type FreeMemo = Vec<(u64, Vec<Fragment>, Option<Free>)>;

/// `find()`, the free split of `frags`, or the one found before for the same list (compared
/// whole, not only by hash) in another rule's build of the same small list.
fn free_of(ctx: &Ctx, frags: &[Fragment], find: impl FnOnce() -> Option<Free>) -> Option<Free> {
    let Some(memo) = ctx.frees else {
        return find();
    };
    let h = content_hash(frags);
    let known = |memo: &FreeMemo| {
        (memo.iter())
            .find(|(k, list, _)| *k == h && list.as_slice() == frags)
            .map(|e| e.2)
    };
    if let Some(free) = known(&memo.lock().expect("free memo")) {
        return free;
    }
    let free = find();
    memo.lock()
        .expect("free memo")
        .push((h, frags.to_vec(), free));
    free
}

/// How a build weighs its split planes: the cost of a support or edge plane, and what an edge
/// split must save over the best support split.
#[derive(Debug, Clone, Copy)]
struct Rule {
    split: SplitRule,
    edge_penalty: u64,
}

/// The rules a small list is built with, the build's own first: the cut weight and the edge
/// penalty each move the cow's and suzanne's polygons by a percent or two either way, list by
/// list, so the best of a few builds of a list beats any one rule (BENCHMARKS.md, "Edge
/// splits").
const RULES: [Rule; 4] = [
    Rule::new(CUT_WEIGHT, EDGE_PENALTY),
    Rule::new(CUT_WEIGHT, 0),
    Rule::new(10, EDGE_PENALTY),
    Rule::new(6, EDGE_PENALTY),
];

impl Rule {
    const fn new(cut_weight: u64, edge_penalty: u64) -> Rule {
        Rule {
            split: SplitRule {
                cut_weight,
                balance_weight: 1,
            },
            edge_penalty,
        }
    }
}

/// Lists of at most this many fragments, and at least [`BEST_OF_MIN`], are built with each
/// rule of [`RULES`]. 64: cow 1.517 and suzanne 1.518 polygons per triangle, for 1.5 times
/// the instructions of the build by one rule; 256: 1.515 and 1.519 for 1.6 times 64's
/// compile time (wall clock); 32: 1.524 and 1.519.
const BEST_OF_MAX: usize = 64;

/// Smaller lists are built once: they rarely cut.
const BEST_OF_MIN: usize = 8;

pub(crate) fn build_exact(
    input: &Input,
    options: &BuildOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ExactTree, CompileError> {
    let ctx = Ctx {
        table: &input.table,
        options,
        progress,
        placed: AtomicU64::new(0),
        rule: RULES[0],
        best_of: true,
        frees: None,
    };
    let root = Job::Compile {
        frags: input.build_fragments().to_vec(),
        known: Known::default(),
        slot: Slot::Root,
        limit: Limit::at_most(u32::MAX),
        lopsided: 0,
    };
    let tree = run(&ctx, root)?;
    (ctx.progress)(ctx.placed.load(Ordering::Relaxed));
    Ok(tree)
}

/// Sorted distinct support planes of a list.
fn distinct_planes<'a>(frags: impl Iterator<Item = &'a Fragment>) -> Vec<PlaneId> {
    let mut p: Vec<PlaneId> = frags.map(|f| f.support).collect();
    p.sort_unstable();
    p.dedup();
    p
}

/// Point the link `slot` of an earlier node at node `idx`.
pub(crate) fn attach(tree: &mut ExactTree, slot: Slot, idx: u32) {
    let field = match slot {
        Slot::Root => return,
        Slot::Child(n) => match &mut tree.nodes[n as usize] {
            ExactNode::Convex { child, .. } => child,
            ExactNode::Split { .. } => unreachable!("convex child of a split"),
        },
        Slot::Front(n) | Slot::Back(n) => match &mut tree.nodes[n as usize] {
            ExactNode::Split { front, back, .. } => {
                if matches!(slot, Slot::Front(_)) {
                    front
                } else {
                    back
                }
            }
            ExactNode::Convex { .. } => unreachable!("split child of a convex node"),
        },
    };
    *field = Some(idx);
}

/// Append a subtree built separately, in pre-order position (everything still on the work
/// stack comes after it in pre-order).
fn append(tree: &mut ExactTree, sub: ExactTree, slot: Slot) {
    tree.cuts += sub.cuts;
    if sub.nodes.is_empty() {
        return;
    }
    let no = tree.nodes.len() as u32;
    let po = tree.polygons.len() as u32;
    let off = |c: &mut Option<u32>| *c = c.map(|c| c + no);
    tree.nodes.extend(sub.nodes.into_iter().map(|mut n| {
        match &mut n {
            ExactNode::Convex { first, child, .. } => {
                *first += po;
                off(child);
            }
            ExactNode::Split { front, back, .. } => {
                off(front);
                off(back);
            }
        }
        n
    }));
    tree.polygons.extend(sub.polygons);
    attach(tree, slot, no);
}

/// Append a split node by `plane` (its children linked later) at `slot`; returns its index.
fn push_split(tree: &mut ExactTree, plane: SplitPlane, support_planes: u32, slot: Slot) -> u32 {
    let idx = tree.nodes.len() as u32;
    tree.nodes.push(ExactNode::Split {
        plane,
        front: None,
        back: None,
        support_planes,
    });
    attach(tree, slot, idx);
    idx
}

fn push_convex(
    ctx: &Ctx,
    tree: &mut ExactTree,
    polys: Vec<ExactPolygon>,
    support_planes: u32,
    slot: Slot,
) -> u32 {
    let idx = tree.nodes.len() as u32;
    tree.nodes.push(ExactNode::Convex {
        first: tree.polygons.len() as u32,
        count: polys.len() as u32,
        child: None,
        support_planes,
    });
    attach(tree, slot, idx);
    placed(ctx, polys.len() as u64);
    tree.polygons.extend(polys);
    idx
}

/// Count `n` more polygons placed, reporting progress every 4,096.
fn placed(ctx: &Ctx, n: u64) {
    let before = ctx.placed.fetch_add(n, Ordering::Relaxed);
    if before >> 12 != (before + n) >> 12 {
        (ctx.progress)(before + n);
    }
}

/// The subtree of `job` (a small list's) built with each rule of [`RULES`]: the one with the
/// fewest polygons, then nodes (ties: the earlier rule). Each build is the ordinary one, so
/// the kept subtree holds every invariant; the choice depends on the list alone, so the
/// output is the same on any thread count.
fn best_of(ctx: &Ctx, job: &Job) -> Result<ExactTree, CompileError> {
    let Job::Compile {
        frags,
        known,
        limit,
        lopsided,
        ..
    } = job
    else {
        unreachable!("only a list is built with each rule")
    };
    let mut best: Option<ExactTree> = None;
    let frees = Mutex::new(FreeMemo::new());
    for rule in RULES {
        let sub = Ctx {
            table: ctx.table,
            options: ctx.options,
            progress: &|_| {},
            placed: AtomicU64::new(0),
            rule,
            best_of: false,
            frees: Some(&frees),
        };
        let tree = run(
            &sub,
            Job::Compile {
                frags: frags.clone(),
                known: known.clone(),
                slot: Slot::Root,
                limit: *limit,
                lopsided: *lopsided,
            },
        )?;
        let key = |t: &ExactTree| (t.polygons.len(), t.nodes.len());
        if best.as_ref().is_none_or(|b| key(&tree) < key(b)) {
            best = Some(tree);
        }
    }
    let best = best.expect("a rule");
    placed(ctx, best.polygons.len() as u64);
    Ok(best)
}

fn run(ctx: &Ctx, job: Job) -> Result<ExactTree, CompileError> {
    let mut tree = ExactTree::default();
    let mut stack = vec![job];
    while let Some(job) = stack.pop() {
        match job {
            Job::InPlane {
                on,
                rest,
                known,
                interior_front,
                slot,
                limit,
            } => {
                let k = distinct_planes(on.iter().chain(&rest)).len() as u32;
                limit.check(k, on.len() + rest.len(), "in-plane child of a split")?;
                let polys = on
                    .into_iter()
                    .map(|frag| ExactPolygon {
                        frag,
                        interior_front,
                    })
                    .collect();
                let idx = push_convex(ctx, &mut tree, polys, k, slot);
                stack.extend(convex_child(idx, k, rest, known));
            }
            Job::Chain {
                mut steps,
                rest,
                again,
                known,
                slot,
                limit,
            } => {
                let Some(step) = steps.pop() else {
                    stack.push(Job::Compile {
                        frags: rest,
                        known: Known::Inherited(known),
                        slot,
                        limit,
                        lopsided: if again { CHAIN_AFTER } else { 0 },
                    });
                    continue;
                };
                let k = step.support_planes;
                limit.check(k, 0, "lopsided split")?;
                #[cfg(test)]
                CHAINED.fetch_add(1, Ordering::Relaxed);
                let idx = push_split(&mut tree, SplitPlane::Support(step.plane), k, slot);
                let (small_slot, big_slot) = if step.small_front {
                    (Slot::Front(idx), Slot::Back(idx))
                } else {
                    (Slot::Back(idx), Slot::Front(idx))
                };
                stack.push(Job::Chain {
                    steps,
                    rest,
                    again,
                    known,
                    slot: big_slot,
                    limit: Limit::below(k),
                });
                stack.push(Job::InPlane {
                    on: step.on,
                    rest: step.small,
                    known: Known::default(),
                    interior_front: step.small_front,
                    slot: small_slot,
                    limit: Limit::at_most(k),
                });
            }
            Job::Compile {
                ref frags, slot, ..
            } if ctx.best_of && (BEST_OF_MIN..=BEST_OF_MAX).contains(&frags.len()) => {
                let sub = best_of(ctx, &job)?;
                append(&mut tree, sub, slot);
            }
            Job::Compile {
                frags,
                known,
                slot,
                limit,
                lopsided,
            } => {
                if frags.is_empty() {
                    continue;
                }
                let planes = distinct_planes(frags.iter());
                let k = planes.len() as u32;
                limit.check(k, frags.len(), "node")?;
                let hull = hull_planes(&frags, &planes, ctx.table, &known);
                drop(known);
                if hull.sides.iter().any(Option::is_some) {
                    let (mut e, mut rest) = (Vec::new(), Vec::with_capacity(frags.len()));
                    for frag in frags {
                        let i = planes.binary_search(&frag.support).expect("own plane");
                        match hull.sides[i] {
                            Some(interior_front) => e.push(ExactPolygon {
                                frag,
                                interior_front,
                            }),
                            None => rest.push(frag),
                        }
                    }
                    let idx = push_convex(ctx, &mut tree, e, k, slot);
                    let known = Known::Inherited(hull.witnesses);
                    stack.extend(convex_child(idx, k, rest, known));
                    continue;
                }
                if lopsided >= CHAIN_AFTER {
                    let splits = lopsided_splits(&frags, &planes, ctx.table);
                    if !splits.is_empty() {
                        let (mut steps, rest) = chain(frags, &planes, splits, ctx.table)?;
                        steps.reverse();
                        stack.push(Job::Chain {
                            again: steps.len() >= CHAIN_AFTER as usize,
                            steps,
                            rest,
                            known: hull.witnesses,
                            slot,
                            limit,
                        });
                        continue;
                    }
                }
                // The child holding the split plane's fragments is laid out first: the
                // order does not depend on the plane's sign, so mirrored scenes give the same
                // tree up to the transform.
                let (first, second) = split_node(
                    ctx,
                    &mut tree,
                    frags,
                    &planes,
                    hull.witnesses,
                    slot,
                    lopsided,
                )?;
                let (n1, n2) = (first.len(), second.len());
                if n1.min(n2) >= PAR_MIN && n1.min(n2) * 8 >= n1 + n2 {
                    let (s1, s2) = (first.slot(), second.slot());
                    #[cfg(test)]
                    JOINS.fetch_add(1, Ordering::Relaxed);
                    let (a, b) =
                        rayon::join(|| run(ctx, first.rooted()), || run(ctx, second.rooted()));
                    append(&mut tree, a?, s1);
                    append(&mut tree, b?, s2);
                } else {
                    stack.push(second);
                    stack.push(first);
                }
            }
        }
    }
    Ok(tree)
}

/// The job of convex node `idx`'s child, when some of its list (`rest`, with witnesses
/// `known`) is left: the node took every fragment of at least one of its `k` support planes,
/// so the child has fewer.
fn convex_child(idx: u32, k: u32, rest: Vec<Fragment>, known: Known) -> Option<Job> {
    (!rest.is_empty()).then(|| Job::Compile {
        frags: rest,
        known,
        slot: Slot::Child(idx),
        limit: Limit::below(k),
        lopsided: 0,
    })
}

/// Emit a split node for `frags` (no plane of which is on the hull) and return the jobs of
/// its two children, the one laid out first first. The plane is the support plane of least
/// cost ([`choose_split_costed`]), unless that one cuts and a free split ([`best_free`]) has
/// less imbalance than its cost (a free split costs no polygon), or else that one cuts and
/// the edge plane of least cost costs less than it by more than [`EDGE_PENALTY`] and divides
/// the list.
fn split_node(
    ctx: &Ctx,
    tree: &mut ExactTree,
    frags: Vec<Fragment>,
    planes: &[PlaneId],
    known: Vec<Witness>,
    slot: Slot,
    lopsided: u32,
) -> Result<(Job, Job), CompileError> {
    let candidates = if frags.len() <= COST_ALL {
        usize::MAX
    } else {
        ctx.options.candidates
    };
    let k = planes.len() as u32;
    // The free or edge split's plane when one wins (the choice borrows the list).
    let (plane, free, edge) = {
        let choice = choose_split_costed(
            ctx.rule.split,
            &frags,
            planes,
            ctx.table,
            candidates,
            ctx.options.seed,
        );
        let cuts = choice.cost >= ctx.rule.split.cut_weight;
        let free = cuts
            .then(|| {
                free_of(ctx, &frags, || {
                    best_free(
                        &frags,
                        planes,
                        ctx.table,
                        choice.whole.then_some(&choice.sample),
                    )
                })
            })
            .flatten()
            .filter(|free| {
                // Its imbalance on the list, scaled to the sample the support plane was
                // costed on.
                let imbalance = free.front.abs_diff(free.back) as u128 * choice.sampled as u128
                    / frags.len() as u128;
                imbalance < u128::from(choice.cost)
            });
        // Only against a support plane that cuts: one that cuts nothing (splitting off a fold
        // of a nearly convex mesh, however lopsided) adds no polygon, an edge plane would.
        // Not with shadows: there the stress suite's turned torus showed a crack pixel (see
        // `split::edge`).
        let edge = (choice.cuts > 0 && free.is_none() && ctx.options.shadows.is_none())
            .then(|| {
                let edges = edge_planes(&frags, planes);
                if edges.is_empty() {
                    return None;
                }
                // Costed on the support planes' sample, with its own candidates (the seed told
                // apart); only a cost below the support plane's less the penalty matters.
                let limit = choice.cost.checked_sub(ctx.rule.edge_penalty + 1)?;
                let (e, _) = choice.cheapest_below(
                    ctx.rule.split,
                    &edges,
                    ctx.table,
                    candidates,
                    ctx.options.seed ^ EDGE_SEED,
                    limit,
                )?;
                divides(&frags, ctx.table.get(e)).then_some(e)
            })
            .flatten();
        (choice.plane, free, edge)
    };
    if let Some(free) = free {
        return free_split(tree, frags, free.entry, k, known, slot, lopsided);
    }
    if let Some(e) = edge {
        return edge_split(ctx, tree, frags, e, k, known, slot);
    }
    support_split(ctx, tree, frags, planes, known, slot, lopsided, plane)
}

/// What an edge split must save over the best support split: one cut. A support split also
/// takes its plane's fragments out of the list; with no penalty, or a bonus instead, the cow
/// and suzanne get about as many polygons or more (BENCHMARKS.md, "Edge splits").
const EDGE_PENALTY: u64 = CUT_WEIGHT;

/// Mixed into the seed of the edge planes' sample, so that it is not the support planes'.
const EDGE_SEED: u64 = 0x5eed_ed6e;

/// Emit a split node of `frags` by their support plane `p` and return the jobs of its two
/// children: the one holding the split plane's fragments first.
#[allow(clippy::too_many_arguments)]
fn support_split(
    ctx: &Ctx,
    tree: &mut ExactTree,
    frags: Vec<Fragment>,
    planes: &[PlaneId],
    known: Vec<Witness>,
    slot: Slot,
    lopsided: u32,
    p: PlaneId,
) -> Result<(Job, Job), CompileError> {
    let k = planes.len() as u32;
    let results: Vec<Option<SplitResult>> = if frags.len() >= PAR_MIN {
        frags
            .into_par_iter()
            .map(|f| f.split(p, ctx.table))
            .collect()
    } else {
        frags.into_iter().map(|f| f.split(p, ctx.table)).collect()
    };
    let n = results.len();
    let (mut front, mut back, mut on) = (Vec::with_capacity(n), Vec::with_capacity(n), Vec::new());
    let mut cuts = 0u64;
    for r in results {
        match r {
            Some(SplitResult::Front(f)) => front.push(f),
            Some(SplitResult::Back(f)) => back.push(f),
            Some(SplitResult::On(f)) => on.push(f),
            Some(SplitResult::Cut(f, b)) => {
                cuts += 1;
                front.push(f);
                back.push(b);
            }
            None => {
                return Err(CompileError::Invariant(
                    "a cut found no intersection point".into(),
                ))
            }
        }
    }
    tree.cuts += cuts;
    if on.iter().any(|f| f.support != p) {
        return Err(CompileError::Invariant(
            "a fragment lies in a plane that is not its support".into(),
        ));
    }
    if on.is_empty() || front.is_empty() || back.is_empty() {
        return Err(CompileError::Invariant(format!(
            "split plane {p} is not a proper split: {} front, {} back, {} in the plane",
            front.len(),
            back.len(),
            on.len()
        )));
    }
    let idx = push_split(tree, SplitPlane::Support(p), k, slot);
    let (strict, loose) = (Limit::below(k), Limit::at_most(k));
    // The split plane's fragments join the smaller side; a tie goes to the side whose
    // source ids come first (not to "front", which depends on the plane's sign).
    let (known_front, known_back) = after_split(known, ctx.table.get(p));
    let lopsided = if is_lopsided(n, front.len().min(back.len()), on.len(), cuts as usize) {
        lopsided + 1
    } else {
        0
    };
    let on_front = match front.len().cmp(&back.len()) {
        std::cmp::Ordering::Less => true,
        std::cmp::Ordering::Greater => false,
        std::cmp::Ordering::Equal => front
            .iter()
            .map(|f| f.source)
            .le(back.iter().map(|f| f.source)),
    };
    Ok(if on_front {
        (
            Job::InPlane {
                on,
                rest: front,
                known: known_front,
                interior_front: true,
                slot: Slot::Front(idx),
                limit: loose,
            },
            Job::Compile {
                frags: back,
                known: known_back,
                slot: Slot::Back(idx),
                limit: strict,
                lopsided,
            },
        )
    } else {
        (
            Job::InPlane {
                on,
                rest: back,
                known: known_back,
                interior_front: false,
                slot: Slot::Back(idx),
                limit: loose,
            },
            Job::Compile {
                frags: front,
                known: known_front,
                slot: Slot::Front(idx),
                limit: strict,
                lopsided,
            },
        )
    })
}

/// Emit a split node of `frags` (`k` distinct support planes) by the table plane `p`, none of
/// their support planes, with some fragment wholly on each side ([`divides`]), and return the
/// jobs of its two children: the side holding the list's first fragment wholly first. Cuts add
/// fragments but no support plane, and each side lacks the fragments wholly on the other, so
/// each child has at most `k` support planes and fewer fragments than the list (the
/// termination argument, [`super`]).
fn edge_split(
    ctx: &Ctx,
    tree: &mut ExactTree,
    frags: Vec<Fragment>,
    p: PlaneId,
    k: u32,
    known: Vec<Witness>,
    slot: Slot,
) -> Result<(Job, Job), CompileError> {
    let n = frags.len();
    let (mut front, mut back) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let mut first_front = None;
    for f in frags {
        match f.split(p, ctx.table) {
            Some(SplitResult::Front(f)) => {
                first_front.get_or_insert(true);
                front.push(f);
            }
            Some(SplitResult::Back(f)) => {
                first_front.get_or_insert(false);
                back.push(f);
            }
            Some(SplitResult::Cut(f, b)) => {
                tree.cuts += 1;
                front.push(f);
                back.push(b);
            }
            Some(SplitResult::On(_)) => {
                return Err(CompileError::Invariant(format!(
                    "a fragment lies in edge split plane {p}, not its support"
                )))
            }
            None => {
                return Err(CompileError::Invariant(
                    "a cut found no intersection point".into(),
                ))
            }
        }
    }
    if front.len() >= n || back.len() >= n {
        return Err(CompileError::Invariant(format!(
            "edge split plane {p} does not divide: {} front, {} back of {n}",
            front.len(),
            back.len()
        )));
    }
    let split = (SplitPlane::Edge(p), ctx.table.get(p));
    let sides = (front, back, first_front == Some(true));
    Ok(split_children(tree, split, k, n, sides, known, slot, 0))
}

/// Emit the split node of a list of `n` fragments (`k` distinct support planes) by `plane`
/// (`entry`), sorted into `front` and `back`, and return its children's jobs, the side
/// holding the list's first fragment first (`first_front`), each `lopsided` as given.
#[allow(clippy::too_many_arguments)]
fn split_children(
    tree: &mut ExactTree,
    (plane, entry): (SplitPlane, &PlaneEntry),
    k: u32,
    n: usize,
    (front, back, first_front): (Vec<Fragment>, Vec<Fragment>, bool),
    known: Vec<Witness>,
    slot: Slot,
    lopsided: u32,
) -> (Job, Job) {
    let idx = push_split(tree, plane, k, slot);
    let (known_front, known_back) = after_split(known, entry);
    let limit = Limit::fewer(k, n);
    let job = |frags, known, slot| Job::Compile {
        frags,
        known,
        slot,
        limit,
        lopsided,
    };
    let front = job(front, known_front, Slot::Front(idx));
    let back = job(back, known_back, Slot::Back(idx));
    if first_front {
        (front, back)
    } else {
        (back, front)
    }
}

/// Emit a split node of `frags` (`k` distinct support planes) by the free plane `e`, which
/// cuts none of them, and return the jobs of its two children: the side holding the list's
/// first fragment first (not the + side, which depends on the plane's sign). Each child has
/// at most `k` support planes and fewer fragments than the list, so the pair drops
/// lexicographically (the termination argument, [`super`]).
fn free_split(
    tree: &mut ExactTree,
    frags: Vec<Fragment>,
    e: PlaneEntry,
    k: u32,
    known: Vec<Witness>,
    slot: Slot,
    lopsided: u32,
) -> Result<(Job, Job), CompileError> {
    let n = frags.len();
    let (mut front, mut back) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let mut first_front = None;
    for f in frags {
        let placement = Placement::of_sides(f.vertices.iter().map(|v| v.side(&e)));
        first_front.get_or_insert(placement == Placement::Front);
        match placement {
            Placement::Front => front.push(f),
            Placement::Back => back.push(f),
            Placement::On | Placement::Straddle => {
                return Err(CompileError::Invariant(format!(
                    "free split plane {:?} cuts a fragment or holds one",
                    e.plane
                )))
            }
        }
    }
    if front.is_empty() || back.is_empty() {
        return Err(CompileError::Invariant(format!(
            "free split plane {:?} is not a proper split: {} front, {} back",
            e.plane,
            front.len(),
            back.len()
        )));
    }
    let lopsided = if is_lopsided(n, front.len().min(back.len()), 0, 0) {
        lopsided + 1
    } else {
        0
    };
    let split = (SplitPlane::Free(e.plane), &e);
    let sides = (front, back, first_front == Some(true));
    Ok(split_children(
        tree, split, k, n, sides, known, slot, lopsided,
    ))
}

/// The chain of `splits` ([`lopsided_splits`] of `frags`, whose distinct support planes are
/// `planes`): each split's fragments sorted, and what is left after the last one (the
/// untouched fragments, in their order). A split only touches fragments no earlier one
/// touched, so each is a proper split of what the earlier ones leave: its plane's fragments
/// are all still there (and leave with it, so the count of support planes strictly drops
/// along the chain).
fn chain(
    frags: Vec<Fragment>,
    planes: &[PlaneId],
    splits: Vec<Lopsided>,
    table: &PlaneTable,
) -> Result<(Vec<ChainStep>, Vec<Fragment>), CompileError> {
    let pos = |p: PlaneId| planes.binary_search(&p).expect("own plane");
    let mut count = vec![0u32; planes.len()];
    for f in &frags {
        count[pos(f.support)] += 1;
    }
    let mut k = planes.len() as u32;
    let mut slots: Vec<Option<Fragment>> = frags.into_iter().map(Some).collect();
    let mut steps = Vec::with_capacity(splits.len());
    let bad = |what: &str| CompileError::Invariant(format!("lopsided split: {what}"));
    for s in splits {
        let support_planes = k;
        let small_front = s.small == Side::Front;
        let (mut on, mut small) = (Vec::new(), Vec::new());
        for &i in &s.touched {
            let f = slots[i as usize]
                .take()
                .ok_or_else(|| bad("a fragment touched twice"))?;
            let support = pos(f.support);
            match f.placement(s.plane, table) {
                Placement::On => on.push(f),
                Placement::Front if small_front => small.push(f),
                Placement::Back if !small_front => small.push(f),
                _ => return Err(bad("a touched fragment is cut or on the far side")),
            }
            count[support] -= 1;
            if count[support] == 0 {
                k -= 1;
            }
        }
        if on.is_empty() || small.is_empty() {
            return Err(bad("not a proper split"));
        }
        steps.push(ChainStep {
            plane: s.plane,
            on,
            small,
            small_front,
            support_planes,
        });
    }
    let rest: Vec<Fragment> = slots.into_iter().flatten().collect();
    if rest.is_empty() {
        return Err(bad("nothing left on the far side"));
    }
    Ok((steps, rest))
}
