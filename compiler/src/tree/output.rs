//! Exact tree -> [`DisplayTree`]: exact vertex dedupe, watertight boundaries (T-junctions
//! closed), f64 conversion relative to the centre, the output plane table (in order of first
//! use), large polygons cut into convex pieces, statistics.
//!
//! Watertightness: a cut adds a vertex on an edge that a neighbouring polygon also has. Once
//! rounded to f64 and projected, that vertex is no longer exactly on the neighbour's edge, and
//! the fill leaves cracks. So every vertex of an edge that lies exactly inside another polygon's
//! collinear edge is inserted into that polygon's vertex list. Edges are indexed by their exact
//! supporting line (canonical Plücker coordinates of the two planes that define it), so only
//! collinear edges are compared; every shared boundary segment lies on collinear edges of both
//! polygons. A vertex touching an edge transversally (no shared segment) cannot open a crack
//! and is not inserted.

use std::sync::Arc;

use crate::hash::{first_equal, mix, shard, FastMap, Hashed, ShardHash, SHARDS};

use ethnum::{I256, U256};
use glam::DVec3;
use rayon::iter::Either;
use rayon::prelude::*;

use super::build::{ExactNode, ExactTree};
use super::input::Input;
use super::{BuildOptions, DisplayTree, TreeNode, TreePlane, TreePolygon, TreeStats};
use crate::planes::same::{residues, same_point};
use crate::planes::{div_exact, gcd_u128, gcd_u64, gcd_wide, Plane, PlaneId, Vertex};
use crate::quantise::IPoint;
use crate::split::Fragment;

/// Exact identity of a line: the Plücker coordinates `(n1 × n2, d1 n2 − d2 n1)` of the two
/// planes meeting in it (the same up to a factor for any two planes of the pencil), divided by
/// their gcd, first non-zero direction component positive.
///
/// A key is stored narrow when all six integers fit in 64 bits (every line through two grid
/// points, so most edges), wide (boxed) otherwise: the form is a function of the key, so equal
/// keys have the same form, and the per-edge list is less than half the size.
#[derive(Debug, Clone, PartialEq, Eq)]
enum LineKey {
    Narrow { dir: [i64; 3], moment: [i64; 3] },
    Wide(Box<WideLineKey>),
}

/// A [`LineKey`] that does not fit in 64-bit integers.
#[derive(Debug, Clone, PartialEq, Eq)]
struct WideLineKey {
    dir: [i128; 3],
    moment: [I256; 3],
}

impl LineKey {
    /// The key of the reduced coordinates `dir`, `moment`, in its storage form.
    fn new(dir: [i128; 3], moment: [I256; 3]) -> LineKey {
        let small = |c: &I256| *c >= I256::from(i64::MIN) && *c <= I256::from(i64::MAX);
        if dir.iter().all(|&c| i64::try_from(c).is_ok()) && moment.iter().all(small) {
            LineKey::Narrow {
                dir: dir.map(|c| c as i64),
                moment: moment.map(|c| c.as_i64()),
            }
        } else {
            LineKey::Wide(Box::new(WideLineKey { dir, moment }))
        }
    }

    /// The direction (not normalised).
    fn dir(&self) -> [f64; 3] {
        match self {
            LineKey::Narrow { dir, .. } => dir.map(|c| c as f64),
            LineKey::Wide(w) => w.dir.map(|c| c as f64),
        }
    }
}

/// `None` when the planes are parallel (never for a support plane and one of its edge planes).
fn line_key(a: &Plane, b: &Plane) -> Option<LineKey> {
    let (u, v) = (a.n.map(i128::from), b.n.map(i128::from));
    let mut dir = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let mut g = dir.iter().fold(0u128, |g, c| gcd_u128(g, c.unsigned_abs()));
    if g == 0 {
        return None;
    }
    let sign = if dir.iter().copied().find(|&c| c != 0).unwrap_or(0) < 0 {
        -1
    } else {
        1
    };
    // The moment in 128 bits when it fits (an edge plane's small normal and offset keep it
    // near 2^107), else in 256; the same integers either way.
    let narrow = |k: usize| a.d.checked_mul(v[k])?.checked_sub(b.d.checked_mul(u[k])?);
    let moment = match [narrow(0), narrow(1), narrow(2)] {
        [Some(m0), Some(m1), Some(m2)] => {
            let m = [m0, m1, m2];
            for c in &m {
                g = gcd_u128(g, c.unsigned_abs());
            }
            let gi = g as i128 * sign;
            m.map(|c| I256::from(if gi == 1 { c } else { c / gi }))
        }
        _ => {
            let wide: [I256; 3] = std::array::from_fn(|k| {
                I256::from(a.d) * I256::from(b.n[k]) - I256::from(b.d) * I256::from(a.n[k])
            });
            let mut gw = U256::from(g);
            for m in &wide {
                gw = gcd_wide(gw, m.unsigned_abs());
            }
            g = gw.as_u128();
            wide.map(|c| div_exact(c, gw) * I256::from(sign))
        }
    };
    let gi = g as i128 * sign;
    if gi != 1 {
        dir = dir.map(|c| c / gi);
    }
    Some(LineKey::new(dir, moment))
}

/// [`line_key`] of the line through grid points `p` and `q` (`None` when they coincide),
/// without wide integers: the primitive direction `d` (first non-zero component positive) and
/// the moment `d × p`. This is the same key: the planes' `(L, M)` is `(λd, λ(d × p))` for an
/// integer `λ` (`M = L × p` for any point `p` of the line), and `gcd(d) = 1` makes `|λ|` the
/// gcd that [`line_key`] divides by.
fn line_through(p: [i32; 3], q: [i32; 3]) -> Option<LineKey> {
    let d: [i64; 3] = std::array::from_fn(|k| i64::from(q[k]) - i64::from(p[k]));
    let g = d.iter().fold(0, |g, c| gcd_u64(g, c.unsigned_abs()));
    if g == 0 {
        return None;
    }
    let first = d.iter().copied().find(|&c| c != 0).unwrap_or(0);
    let g = if first < 0 { -(g as i64) } else { g as i64 };
    // Most edge directions are primitive: no division.
    let d = if g == 1 { d } else { d.map(|c| c / g) };
    let p = p.map(i64::from);
    let moment = [
        d[1] * p[2] - d[2] * p[1],
        d[2] * p[0] - d[0] * p[2],
        d[0] * p[1] - d[1] * p[0],
    ];
    // |d| < 2^27 and |p| < 2^26: the moment is below 2^54, the key narrow.
    Some(LineKey::Narrow { dir: d, moment })
}

/// A line through more than two distinct vertices (edge endpoints): its unit direction and
/// the range of its points `(t, vertex id)` in the shared point list, sorted by their
/// approximate position `t` along it.
struct Line {
    dir: DVec3,
    points: std::ops::Range<usize>,
}

/// Slack of the approximate range search along a line, in grid units: vertex approximations
/// are within ~1e-7 of the exact point; the exact tests decide.
const LINE_SLACK: f64 = 1e-3;

/// The distinct vertices of the output (one id per exact point), with their approximate
/// coordinates (grid units).
struct Vertices {
    list: Vec<(Vertex, DVec3)>,
}

/// A vertex as [`first_equal`] matches it: hashed by its residues, equal when it is the same
/// point exactly (see [`crate::planes::same`]).
struct PointKey<'v> {
    residues: Option<[u64; 3]>,
    vertex: &'v Vertex,
}

impl PartialEq for PointKey<'_> {
    fn eq(&self, other: &Self) -> bool {
        self.residues == other.residues && same_point(self.vertex, other.vertex)
    }
}

impl Eq for PointKey<'_> {}

impl ShardHash for PointKey<'_> {
    fn shard_hash(&self) -> u64 {
        self.residues.map_or(0, mix)
    }
}

/// For each of `vertices`, the index of the first one at the same exact point (see
/// [`first_equal`]). The residues are computed in parallel chunks (each chunk shares one
/// inversion).
fn first_equal_points(vertices: &[&Vertex]) -> Vec<u32> {
    let residues: Vec<Option<[u64; 3]>> =
        vertices.par_chunks(4096).flat_map_iter(residues).collect();
    let keys: Vec<PointKey<'_>> = (residues.into_iter().zip(vertices))
        .map(|(residues, &vertex)| PointKey { residues, vertex })
        .collect();
    first_equal(&keys)
}

impl ShardHash for LineKey {
    fn shard_hash(&self) -> u64 {
        match self {
            LineKey::Narrow { dir, moment } => mix(dir.iter().chain(moment).map(|&c| c as u64)),
            LineKey::Wide(w) => {
                mix((w.dir.iter().map(|&c| c as u64)).chain(w.moment.iter().map(|m| m.as_u64())))
            }
        }
    }
}

impl Vertices {
    /// Ids of every vertex of every polygon (flat: polygon `p`'s are at
    /// `offsets[p]..offsets[p + 1]`), numbered in order of first use in polygon order:
    /// the same on any thread count. Points are hashed and matched in parallel. A cut point
    /// is one allocation shared by the pieces of its cut (and their later pieces), so it is
    /// matched once per allocation, not once per use.
    fn of(polys: &[&Fragment], offsets: &[usize]) -> (Vertices, Vec<u32>) {
        // Per use, an index into `distinct`: one entry per cut-point allocation and per grid
        // point, numbered in order of first use.
        let homs = (polys.iter().flat_map(|f| &f.vertices))
            .filter(|v| matches!(v, Vertex::Hom(_)))
            .count();
        let all = offsets.last().copied().unwrap_or(0);
        let mut seen: FastMap<usize, u32> = FastMap::default();
        seen.reserve(homs);
        // Grid points by value: a mesh vertex is a corner of several triangles.
        let mut grid: FastMap<[i32; 3], u32> = FastMap::default();
        grid.reserve((all - homs) / 4);
        let mut distinct: Vec<&Vertex> = Vec::new();
        let mut uses: Vec<u32> = Vec::with_capacity(all);
        for v in polys.iter().flat_map(|f| &f.vertices) {
            let next = distinct.len() as u32;
            let i = match v {
                Vertex::Int(p) => *grid.entry(*p).or_insert(next),
                Vertex::Hom(h) => *seen.entry(Arc::as_ptr(h) as usize).or_insert(next),
            };
            if i == next {
                distinct.push(v);
            }
            uses.push(i);
        }
        let first = first_equal_points(&distinct);
        // A point's first entry comes before its others, so it is numbered first.
        let mut list = Vec::new();
        let mut id_of = vec![0u32; distinct.len()];
        for (i, &f) in first.iter().enumerate() {
            if f as usize == i {
                id_of[i] = list.len() as u32;
                list.push((distinct[i].clone(), DVec3::from_array(distinct[i].approx())));
            } else {
                id_of[i] = id_of[f as usize];
            }
        }
        let ids = uses.par_iter().map(|&i| id_of[i as usize]).collect();
        (Vertices { list }, ids)
    }
}

/// One shard's lines: their directions, the range of each one's points in the shard's point
/// list, that list (`(position along the line, vertex)`, sorted along each line), and the
/// edges as `(polygon, edge, line)`; line ids are within the shard.
type ShardLines = (
    Vec<DVec3>,
    Vec<std::ops::Range<usize>>,
    Vec<(f64, u32)>,
    Vec<(u32, u32, u32)>,
);

/// The sides (collinear runs of a polygon's boundary) a boundary vertex lies on: side `k` is
/// the polygon's edge `k`; a corner lies on two, a vertex inserted inside an edge on one
/// (stored twice).
type Sides = [u32; 2];

/// Every polygon's boundary with the collinear vertices of other polygons inserted: per
/// polygon, the vertices (as [`Vertices`] ids) and the sides each lies on.
type Boundary = Vec<(u32, Sides)>;

/// Each edge's line key and its hash, numbered as the vertices the edges start from (edge `k`
/// of polygon `p` is `offsets[p] + k`); `None` for an edge on no line (degenerate).
type EdgeKeys = Vec<Option<(u64, LineKey)>>;

/// The corners of the edge of source triangle `source` whose edge plane is `plane`, if one is.
fn source_edge(input: &Input, source: u32, plane: PlaneId) -> Option<(IPoint, IPoint)> {
    let at = (input.fragments)
        .binary_search_by_key(&source, |f| f.source)
        .ok()?;
    let t = &input.fragments[at];
    let k = t.edges.iter().position(|e| e.plane == plane)?;
    match (&t.vertices[k], &t.vertices[(k + 1) % t.vertices.len()]) {
        (Vertex::Int(p), Vertex::Int(q)) => Some((*p, *q)),
        _ => None,
    }
}

/// The [`EdgeKeys`] of `polys`, in parallel.
fn edge_keys(polys: &[&Fragment], input: &Input) -> EdgeKeys {
    let owner: Vec<(u32, u32)> = polys
        .iter()
        .enumerate()
        .flat_map(|(p, f)| (0..f.vertices.len() as u32).map(move |k| (p as u32, k)))
        .collect();
    owner
        .par_iter()
        .map(|&(p, k)| {
            let f = polys[p as usize];
            let n = f.vertices.len();
            let k = k as usize;
            let lk = match (&f.vertices[k], &f.vertices[(k + 1) % n]) {
                // An edge between two grid points (most edges) has the cheap key.
                (Vertex::Int(p), Vertex::Int(q)) => line_through(*p, *q),
                _ => {
                    let plane = f.edges.get(k)?.plane;
                    match source_edge(input, f.source, plane) {
                        // Part of a source triangle's edge: the line through its corners.
                        Some((p, q)) => line_through(p, q),
                        // A cut edge.
                        None => line_key(
                            &input.table.get(f.support).plane,
                            &input.table.get(plane).plane,
                        ),
                    }
                }
            }?;
            Some((lk.shard_hash(), lk))
        })
        .collect()
}

fn watertight(
    polys: &[&Fragment],
    input: &Input,
    vertices: &Vertices,
    ids: &[u32],
    offsets: &[usize],
    keys: &EdgeKeys,
) -> Vec<Boundary> {
    // Lines are numbered per shard (by the hash of their key), shards in parallel: every edge
    // of a line falls in one shard and is taken in polygon order there, and a line's points
    // are sorted along it (ties by vertex id), so nothing depends on the thread count; line
    // ids are internal only.
    let key_of = |p: usize, k: usize| keys[offsets[p] + k].as_ref();
    let mut buckets: Vec<Vec<(u32, u32)>> = vec![Vec::new(); SHARDS];
    for (p, f) in polys.iter().enumerate() {
        for k in 0..f.vertices.len() {
            if let Some((hash, _)) = key_of(p, k) {
                buckets[shard(*hash)].push((p as u32, k as u32));
            }
        }
    }
    let shards: Vec<ShardLines> = buckets
        .into_par_iter()
        .map(|bucket| {
            let mut line_ids: FastMap<Hashed<'_, LineKey>, u32> = FastMap::default();
            let mut dirs: Vec<DVec3> = Vec::new();
            let mut points: Vec<(u32, f64, u32)> = Vec::with_capacity(2 * bucket.len());
            let mut edges = Vec::with_capacity(bucket.len());
            for (p, k) in bucket {
                let Some((hash, key)) = key_of(p as usize, k as usize) else {
                    continue;
                };
                let next_id = dirs.len() as u32;
                let id = *line_ids
                    .entry(Hashed { hash: *hash, key })
                    .or_insert(next_id);
                if id == next_id {
                    dirs.push(DVec3::from_array(key.dir()).normalize());
                }
                let own = &ids[offsets[p as usize]..offsets[p as usize + 1]];
                let n = own.len();
                for j in [k as usize, (k as usize + 1) % n] {
                    let v = own[j];
                    let t = vertices.list[v as usize].1.dot(dirs[id as usize]);
                    points.push((id, t, v));
                }
                edges.push((p, k, id));
            }
            // Grouped by line (a counting sort: a line holds a few points), then sorted along
            // it; a vertex has one position along a line, so its repeats are adjacent and are
            // dropped.
            let mut start = vec![0usize; dirs.len() + 1];
            for &(id, _, _) in &points {
                start[id as usize + 1] += 1;
            }
            for i in 0..dirs.len() {
                start[i + 1] += start[i];
            }
            let mut fill = start.clone();
            let mut grouped = vec![(0.0, 0u32); points.len()];
            for &(id, t, v) in &points {
                grouped[fill[id as usize]] = (t, v);
                fill[id as usize] += 1;
            }
            let mut runs = Vec::with_capacity(dirs.len());
            let mut out = 0;
            for w in start.windows(2) {
                grouped[w[0]..w[1]]
                    .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                let first = out;
                for i in w[0]..w[1] {
                    if out == first || grouped[out - 1].1 != grouped[i].1 {
                        grouped[out] = grouped[i];
                        out += 1;
                    }
                }
                runs.push(first..out);
            }
            grouped.truncate(out);
            (dirs, runs, grouped, edges)
        })
        .collect();
    // Only lines with more than two points are kept: a line with two holds just the endpoints
    // of each of its edges, so nothing is inserted there (most lines).
    let mut edge_lines: Vec<Option<u32>> = vec![None; offsets.last().copied().unwrap_or(0)];
    let mut lines: Vec<Line> = Vec::new();
    let mut points: Vec<(f64, u32)> = Vec::new();
    for (dirs, runs, shard_points, edges) in shards {
        let mut kept: Vec<Option<u32>> = vec![None; dirs.len()];
        for (id, run) in runs.into_iter().enumerate() {
            if run.len() > 2 {
                kept[id] = Some(lines.len() as u32);
                let start = points.len();
                points.extend_from_slice(&shard_points[run]);
                lines.push(Line {
                    dir: dirs[id],
                    points: start..points.len(),
                });
            }
        }
        for (p, k, id) in edges {
            edge_lines[offsets[p as usize] + k as usize] = kept[id as usize];
        }
    }
    let boundary = |(p, f): (usize, &&Fragment)| {
        let n = f.vertices.len();
        let own = &ids[offsets[p]..offsets[p + 1]];
        let mut boundary: Boundary = Vec::with_capacity(n);
        let mut inserted: Vec<&(f64, u32)> = Vec::new();
        for k in 0..n {
            let prev = (k + n - 1) % n;
            boundary.push((own[k], [prev as u32, k as u32]));
            let Some(id) = edge_lines[offsets[p] + k] else {
                continue;
            };
            if n < 3 || f.edges.len() != n {
                continue;
            }
            let line = &lines[id as usize];
            let on_line = &points[line.points.clone()];
            let next = (k + 1) % n;
            let along = |v: u32| vertices.list[v as usize].1.dot(line.dir);
            let (ta, tb) = (along(own[k]), along(own[next]));
            let slack = LINE_SLACK + 1e-12 * (ta.abs() + tb.abs());
            let (lo, hi) = (ta.min(tb) - slack, ta.max(tb) + slack);
            let start = on_line.partition_point(|q| q.0 < lo);
            let (e_prev, e_next) = (&f.edges[prev], &f.edges[next]);
            let (pl_prev, pl_next) = (input.table.get(e_prev.plane), input.table.get(e_next.plane));
            inserted.clear();
            inserted.extend(
                on_line[start..]
                    .iter()
                    .take_while(|q| q.0 <= hi)
                    .filter(|q| q.1 != own[k] && q.1 != own[next])
                    // On the line, strictly inside both neighbouring edges = strictly between
                    // the endpoints (the polygon is strictly convex).
                    .filter(|q| {
                        let v = &vertices.list[q.1 as usize].0;
                        v.side(pl_prev) == e_prev.inside && v.side(pl_next) == e_next.inside
                    }),
            );
            inserted.sort_by(|a, b| (a.0 - ta).abs().total_cmp(&(b.0 - ta).abs()));
            boundary.extend(inserted.iter().map(|q| (q.1, [k as u32; 2])));
        }
        boundary
    };
    polys.par_iter().enumerate().map(boundary).collect()
}

/// A polygon's own boundary, T-junctions left open (vertex `k` lies on sides `k − 1` and `k`).
fn plain_boundary(own: &[u32]) -> Boundary {
    let n = own.len();
    own.iter()
        .enumerate()
        .map(|(k, &v)| (v, [((k + n - 1) % n) as u32, k as u32]))
        .collect()
}

/// Cut a convex polygon whose vertex `i` lies on the sides `sides[i]` (collinear runs of its
/// boundary) into convex pieces of at most `max` (>= 3) vertices: index lists into the
/// polygon, in its winding. Each cut is a chord between two vertices on no common side, so
/// every piece has positive area, chords carry no vertex, and every boundary vertex stays on
/// the boundary of a piece (no new T-junction).
pub(crate) fn convex_pieces(sides: &[Vec<u32>], max: usize) -> Vec<Vec<usize>> {
    let max = max.max(3);
    let mut next_side = sides.iter().flatten().copied().max().map_or(0, |m| m + 1);
    let mut pieces = Vec::new();
    let mut todo: Vec<Vec<(usize, Vec<u32>)>> = vec![sides.iter().cloned().enumerate().collect()];
    while let Some(piece) = todo.pop() {
        let n = piece.len();
        if n <= max {
            pieces.push(piece.into_iter().map(|(i, _)| i).collect());
            continue;
        }
        let disjoint = |i: usize, j: usize| !piece[i].1.iter().any(|s| piece[j].1.contains(s));
        let chord = (2..=n / 2).rev().find_map(|d| {
            (0..n)
                .map(|i| (i, (i + d) % n))
                .find(|&(i, j)| disjoint(i, j))
        });
        let Some((i, j)) = chord else {
            // Unreachable for a polygon of positive area (n >= 4 always has such a chord).
            pieces.push(piece.into_iter().map(|(i, _)| i).collect());
            continue;
        };
        let c = next_side;
        next_side += 1;
        let run = |from: usize, to: usize| {
            let mut r = Vec::new();
            let mut k = from;
            loop {
                let (v, mut s) = piece[k].clone();
                if k == from || k == to {
                    s.push(c);
                }
                r.push((v, s));
                if k == to {
                    return r;
                }
                k = (k + 1) % n;
            }
        };
        let (a, b) = (run(i, j), run(j, i));
        // Popped last-in first-out: `a` (which holds the start of the list) comes out first.
        todo.push(b);
        todo.push(a);
    }
    pieces
}

struct Out<'a> {
    input: &'a Input,
    tree: DisplayTree,
    /// Output index of each [`Vertices`] id, in order of first use.
    vertex_ids: Vec<Option<u32>>,
    /// Output index of each table plane, in order of first use.
    plane_ids: Vec<Option<u32>>,
}

impl Out<'_> {
    fn vertex(&mut self, vertices: &Vertices, id: u32) -> u32 {
        if let Some(i) = self.vertex_ids[id as usize] {
            return i;
        }
        // The approximation is the exact point rounded once per coordinate (see
        // `Vertex::approx`), in grid units.
        let p = vertices.list[id as usize].1 * self.input.quantiser.scale;
        let i = self.tree.vertices.len() as u32;
        self.tree.vertices.push(p);
        self.vertex_ids[id as usize] = Some(i);
        i
    }

    fn plane(&mut self, id: PlaneId) -> u32 {
        if let Some(i) = self.plane_ids[id as usize] {
            return i;
        }
        let p = self.input.table.get(id).plane;
        let n = DVec3::new(p.n[0] as f64, p.n[1] as f64, p.n[2] as f64);
        let len = n.length();
        let i = self.tree.planes.len() as u32;
        self.tree.planes.push(TreePlane {
            normal: n / len,
            offset: p.d as f64 / len * self.input.quantiser.scale,
        });
        self.plane_ids[id as usize] = Some(i);
        i
    }
}

/// Cut a convex polygon of `n` vertices into fans of at most `max` (>= 3) vertices sharing
/// vertex 0: index lists into the polygon. (Superseded by [`convex_pieces`], which keeps
/// inserted collinear vertices on piece boundaries.)
#[cfg(test)]
pub(crate) fn fan_pieces(n: usize, max: usize) -> Vec<Vec<usize>> {
    let max = max.max(3);
    if n <= max {
        return vec![(0..n).collect()];
    }
    let mut pieces = Vec::new();
    let mut s = 1;
    while s + 1 < n {
        let e = (s + max - 2).min(n - 1);
        let mut piece = vec![0];
        piece.extend(s..=e);
        pieces.push(piece);
        s = e;
    }
    pieces
}

pub(crate) fn to_display(exact: &ExactTree, input: &Input, options: &BuildOptions) -> DisplayTree {
    let mut out = Out {
        input,
        tree: DisplayTree {
            centre: input.quantiser.offset,
            ..DisplayTree::default()
        },
        vertex_ids: Vec::new(),
        plane_ids: vec![None; input.table.len()],
    };
    let mut stats = TreeStats {
        input_triangles: input.input_triangles,
        degenerate_dropped: input.degenerate_dropped,
        cuts: exact.cuts,
        ..TreeStats::default()
    };
    let frags: Vec<&Fragment> = exact.polygons.iter().map(|p| &p.frag).collect();
    let mut offsets = Vec::with_capacity(frags.len() + 1);
    offsets.push(0usize);
    for f in &frags {
        offsets.push(offsets.last().copied().unwrap_or(0) + f.vertices.len());
    }
    // The edges' line keys do not depend on the vertex numbering: they are computed alongside
    // its sequential stretches.
    let ((vertices, ids), keys) = rayon::join(
        || Vertices::of(&frags, &offsets),
        || {
            if options.watertight {
                edge_keys(&frags, input)
            } else {
                Vec::new()
            }
        },
    );
    out.vertex_ids = vec![None; vertices.list.len()];
    let boundaries = if options.watertight {
        watertight(&frags, input, &vertices, &ids, &offsets, &keys)
    } else {
        (offsets.windows(2))
            .map(|w| plain_boundary(&ids[w[0]..w[1]]))
            .collect()
    };
    // The wide keys are boxed: freed on an idle worker.
    rayon::spawn(move || drop(keys));
    // Polygons with more vertices than allowed are cut into convex pieces (index lists into
    // their boundary); the others are one piece.
    let max = options.max_polygon_vertices.max(3);
    let pieces: Vec<Option<Vec<Vec<usize>>>> = boundaries
        .par_iter()
        .map(|boundary| {
            (boundary.len() > max).then(|| {
                let sides: Vec<Vec<u32>> = boundary
                    .iter()
                    .map(|&(_, [a, b])| if a == b { vec![a] } else { vec![a, b] })
                    .collect();
                convex_pieces(&sides, options.max_polygon_vertices)
            })
        })
        .collect();
    // Planes and vertices are numbered in order of first use, node by node (sequential and
    // cheap); the polygons are then built in parallel, in that order.
    let mut order: Vec<(usize, u32)> = Vec::with_capacity(exact.polygons.len());
    let mut emitted = 0u32;
    for node in &exact.nodes {
        let node = match *node {
            ExactNode::Convex {
                first,
                count,
                child,
                support_planes,
            } => {
                stats.convex_nodes += 1;
                let mut polygon_count = 0;
                for i in first as usize..(first + count) as usize {
                    let plane = out.plane(exact.polygons[i].frag.support);
                    let boundary = &boundaries[i];
                    match &pieces[i] {
                        None => {
                            for b in boundary {
                                out.vertex(&vertices, b.0);
                            }
                            polygon_count += 1;
                        }
                        Some(pieces) => {
                            for piece in pieces {
                                for &k in piece {
                                    out.vertex(&vertices, boundary[k].0);
                                }
                                polygon_count += 1;
                            }
                        }
                    }
                    order.push((i, plane));
                }
                let start = emitted;
                emitted += polygon_count;
                TreeNode::Convex {
                    first_polygon: start,
                    polygon_count,
                    child,
                    support_planes,
                }
            }
            ExactNode::Split {
                plane,
                front,
                back,
                support_planes,
            } => {
                stats.split_nodes += 1;
                TreeNode::Split {
                    plane: out.plane(plane),
                    front,
                    back,
                    support_planes,
                }
            }
        };
        out.tree.nodes.push(node);
    }
    // Every vertex was numbered above (`MAX` would fail the writer's checks).
    let vertex_ids = &out.vertex_ids;
    let id = move |v: u32| vertex_ids[v as usize].unwrap_or(u32::MAX);
    out.tree.polygons = order
        .par_iter()
        .flat_map_iter(|&(i, plane)| {
            let (poly, boundary) = (&exact.polygons[i], &boundaries[i]);
            let lists = match &pieces[i] {
                None => Either::Left(std::iter::once(
                    boundary.iter().map(|b| id(b.0)).collect::<Vec<u32>>(),
                )),
                Some(pieces) => Either::Right(
                    (pieces.iter())
                        .map(move |piece| piece.iter().map(|&k| id(boundary[k].0)).collect()),
                ),
            };
            lists.map(move |vertices| TreePolygon {
                plane,
                flipped: poly.frag.flipped,
                interior_front: poly.interior_front,
                vertices,
                source: poly.frag.source,
            })
        })
        .collect();
    // Children come after their parents: depths from the last node back.
    let mut depth = vec![0u64; out.tree.nodes.len()];
    for i in (0..depth.len()).rev() {
        let d = |c: Option<u32>| c.map_or(0, |c| depth[c as usize]);
        depth[i] = 1 + match out.tree.nodes[i] {
            TreeNode::Convex { child, .. } => d(child),
            TreeNode::Split { front, back, .. } => d(front).max(d(back)),
        };
    }
    stats.max_depth = depth.first().copied().unwrap_or(0);
    stats.output_polygons = out.tree.polygons.len() as u64;
    stats.planes = out.tree.planes.len() as u64;
    out.tree.stats = stats;
    out.tree
}

/// Build `mesh` and check the exact tree against every invariant of the build (structure,
/// strictly decreasing support-plane counts, sides of every split, convex nodes convex, exact
/// area partition with `samples` rational points per source triangle); then convert it as
/// [`super::build`] does. For the stress suite and the fuzzers: slow on large inputs.
#[doc(hidden)]
pub fn verify(
    mesh: &crate::load::Mesh,
    options: &BuildOptions,
    samples: usize,
) -> Result<DisplayTree, String> {
    let input = super::input::prepare(mesh).map_err(|e| e.to_string())?;
    let exact = super::build::build_exact(&input, options, &|_| {}).map_err(|e| e.to_string())?;
    super::check::structure(&exact)?;
    super::check::support_planes(&exact)?;
    super::check::fragments(&exact, &input)?;
    super::check::ancestor_sides(&exact, &input)?;
    super::check::convex_sets(&exact, &input)?;
    super::check::area_partition(&exact, &input, samples, 7)?;
    Ok(to_display(&exact, &input, options))
}

/// Polygon edges with another polygon's vertex inside them (closer than `off` to the edge's
/// line, farther than `end` from both ends, and with one of its own edges along that line:
/// a transversal touch opens no crack), found by brute force in f64: an independent check
/// of [`watertight`]. Exactly collinear vertices round to within ~1e-16 of the line; `off`
/// must stay far below the distance of the nearest distinct non-collinear vertex.
#[cfg(test)]
pub(crate) fn t_junctions(polys: &[Vec<DVec3>], off: f64, end: f64) -> usize {
    let mut found = 0;
    for (p, poly) in polys.iter().enumerate() {
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let d = b - a;
            let len2 = d.length_squared();
            if len2 == 0.0 {
                continue;
            }
            let near_line = |w: DVec3| {
                let t = (w - a).dot(d) / len2;
                (a + d * t - w).length() < off
            };
            for (q, other) in polys.iter().enumerate() {
                if q == p {
                    continue;
                }
                for (j, &w) in other.iter().enumerate() {
                    let t = (w - a).dot(d) / len2;
                    let away = (w - a).length() > end && (w - b).length() > end;
                    // Only a vertex of an edge along the same line can open a crack.
                    let m = other.len();
                    let along = near_line(other[(j + 1) % m]) || near_line(other[(j + m - 1) % m]);
                    if t > 0.0 && t < 1.0 && away && near_line(w) && along && !poly.contains(&w) {
                        found += 1;
                    }
                }
            }
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes;
    use crate::tree::build::build_exact;
    use crate::tree::input::prepare;

    fn area2(pts: &[[f64; 2]]) -> f64 {
        (0..pts.len())
            .map(|k| {
                let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
                a[0] * b[1] - a[1] * b[0]
            })
            .sum()
    }

    /// A convex polygon (regular `m`-gon) with `extra[k]` collinear points inserted on edge `k`.
    fn polygon(m: usize, extra: &[usize]) -> (Vec<[f64; 2]>, Vec<Vec<u32>>) {
        let corner = |k: usize| {
            let a = std::f64::consts::TAU * k as f64 / m as f64;
            [a.cos(), a.sin()]
        };
        let (mut pts, mut sides) = (Vec::new(), Vec::new());
        for k in 0..m {
            pts.push(corner(k));
            sides.push(vec![((k + m - 1) % m) as u32, k as u32]);
            let (a, b) = (corner(k), corner((k + 1) % m));
            let e = extra.get(k).copied().unwrap_or(0);
            for i in 1..=e {
                let t = i as f64 / (e + 1) as f64;
                pts.push([a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t]);
                sides.push(vec![k as u32]);
            }
        }
        (pts, sides)
    }

    #[test]
    fn pieces_are_convex_non_degenerate_and_cover_the_polygon() {
        for (m, extra, max) in [
            (3, vec![10], 4),
            (3, vec![10], 3),
            (3, vec![0, 0, 30], 12),
            (4, vec![1, 2, 3, 4], 5),
            (12, vec![], 12),
            (12, vec![], 4),
            (5, vec![7, 0, 7, 0, 7], 6),
            (3, vec![2, 2, 2], 3),
        ] {
            let (pts, sides) = polygon(m, &extra);
            let pieces = convex_pieces(&sides, max);
            let total = area2(&pts);
            let mut sum = 0.0;
            let mut used = vec![false; pts.len()];
            for piece in &pieces {
                assert!(piece.len() >= 3 && piece.len() <= max.max(3), "{piece:?}");
                let q: Vec<[f64; 2]> = piece.iter().map(|&i| pts[i]).collect();
                let a = area2(&q);
                assert!(
                    a > 1e-9,
                    "degenerate piece {piece:?} of {m}/{extra:?}/{max}"
                );
                for k in 0..q.len() {
                    let (a, b, c) = (q[k], q[(k + 1) % q.len()], q[(k + 2) % q.len()]);
                    let turn = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
                    assert!(turn > -1e-12, "piece {piece:?} not convex");
                }
                sum += a;
                piece.iter().for_each(|&i| used[i] = true);
            }
            assert!(
                (sum - total).abs() < 1e-9 * total,
                "pieces do not tile the polygon"
            );
            assert!(used.iter().all(|&u| u), "a boundary vertex is on no piece");
            if pts.len() <= max {
                assert_eq!(pieces.len(), 1);
            }
        }
    }

    #[test]
    fn line_keys_identify_lines_whatever_the_planes() {
        // The line through (1, 2, 3) with direction (2, -1, 5), as the meet of different planes.
        let through = |n: [i64; 3]| {
            let d = n[0] as i128 + 2 * n[1] as i128 + 3 * n[2] as i128;
            Plane::canonical(n, d).unwrap().0
        };
        // Normals orthogonal to (2, -1, 5).
        let normals = [[1, 2, 0], [5, 0, -2], [0, 5, 1], [6, 2, -2], [-7, 6, 4]];
        let key0 = line_key(&through(normals[0]), &through(normals[1])).unwrap();
        for a in normals {
            for b in normals {
                let k = line_key(&through(a), &through(b));
                if a == b {
                    assert!(k.is_none());
                } else {
                    assert_eq!(k.unwrap(), key0);
                }
            }
        }
        // A parallel line and a line through the same point with another direction differ.
        let shifted = |n: [i64; 3]| {
            let d = n[0] as i128 + 2 * n[1] as i128 + 4 * n[2] as i128;
            Plane::canonical(n, d).unwrap().0
        };
        assert_ne!(
            line_key(&shifted(normals[0]), &shifted(normals[1])).unwrap(),
            key0
        );
        assert_ne!(
            line_key(&through([1, 0, 0]), &through([0, 1, 0])).unwrap(),
            key0
        );
    }

    proptest::proptest! {
        /// The key of an edge between grid points, from the points, is the key its support and
        /// edge planes give, in either direction (the quantised range, and small coordinates
        /// where gcds are large).
        #[test]
        fn grid_edge_keys_match_plane_keys(
            tri in proptest::prop_oneof![
                proptest::array::uniform3(proptest::array::uniform3(-(1i32 << 25)..(1 << 25))),
                proptest::array::uniform3(proptest::array::uniform3(-6i32..6)),
            ],
        ) {
            let Some((support, _)) = Plane::through(tri[0], tri[1], tri[2]) else {
                return Ok(());
            };
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let edge = crate::planes::edge_plane(a, b, support.n);
                let want = line_key(&support, &edge);
                proptest::prop_assert!(want.is_some());
                proptest::prop_assert_eq!(line_through(a, b), want.clone());
                proptest::prop_assert_eq!(line_through(b, a), want);
            }
        }
    }

    fn world_polygons(t: &DisplayTree) -> Vec<Vec<DVec3>> {
        t.polygons
            .iter()
            .map(|p| p.vertices.iter().map(|&i| t.vertices[i as usize]).collect())
            .collect()
    }

    #[test]
    fn cut_meshes_come_out_without_t_junctions() {
        for (name, mesh) in [
            ("torus", scenes::torus(12, 8)),
            ("soup", scenes::soup(40, 0.5, 3)),
            (
                "bumpy",
                crate::tree::tests::bumpy_sphere(6, 9, &[0.3, -0.2, 0.1, 0.25, -0.3]),
            ),
        ] {
            let options = BuildOptions::default();
            let input = prepare(&mesh).unwrap();
            let exact = build_exact(&input, &options, &|_| {}).unwrap();
            // The exact fragments as they were, without the insertions.
            let s = input.quantiser.scale;
            let raw: Vec<Vec<DVec3>> = exact
                .polygons
                .iter()
                .map(|p| {
                    p.frag
                        .vertices
                        .iter()
                        .map(|v| DVec3::from_array(v.approx()) * s)
                        .collect()
                })
                .collect();
            let before = t_junctions(&raw, 1e-12, 1e-9);
            let tree = to_display(&exact, &input, &options);
            let after = t_junctions(&world_polygons(&tree), 1e-12, 1e-9);
            assert!(exact.cuts > 0, "{name}: no cut, nothing to test");
            assert!(before > 0, "{name}: the build made no T-junction to close");
            assert_eq!(
                after, 0,
                "{name}: {after} T-junctions left ({before} before)"
            );
            assert!(tree
                .polygons
                .iter()
                .all(|p| p.vertices.len() <= options.max_polygon_vertices));
        }
    }

    #[test]
    fn small_vertex_limits_still_close_t_junctions() {
        let mesh = scenes::torus(10, 6);
        for max in [3, 4, 5] {
            let options = BuildOptions {
                max_polygon_vertices: max,
                ..BuildOptions::default()
            };
            let tree = crate::tree::build(&mesh, &options, &|_| {}).unwrap();
            assert!(tree.polygons.iter().all(|p| p.vertices.len() <= max));
            assert_eq!(
                t_junctions(&world_polygons(&tree), 1e-12, 1e-9),
                0,
                "max {max}"
            );
        }
    }
}
