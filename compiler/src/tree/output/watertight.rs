//! Watertight boundaries: T-junctions closed.
//!
//! A cut adds a vertex on an edge that a neighbouring polygon also has. Once rounded to f64
//! and projected, that vertex is no longer exactly on the neighbour's edge, and the fill
//! leaves cracks. So every vertex of an edge that lies exactly inside another polygon's
//! collinear edge is inserted into that polygon's vertex list. Edges are indexed by their
//! exact supporting line (see [`super::line_keys`]), so only collinear edges are compared;
//! every shared boundary segment lies on collinear edges of both polygons. A vertex touching
//! an edge transversally (no shared segment) cannot open a crack and is not inserted.

use glam::DVec3;
use rayon::prelude::*;

use super::line_keys::{EdgeKeys, LineKey};
use super::vertices::Vertices;
use crate::hash::{shard, FastMap, Hashed, SHARDS};
use crate::split::Fragment;
use crate::tree::input::Input;

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
pub(super) type Sides = [u32; 2];

/// Every polygon's boundary with the collinear vertices of other polygons inserted: per
/// polygon, the vertices (as [`Vertices`] ids) and the sides each lies on.
pub(super) type Boundary = Vec<(u32, Sides)>;

pub(super) fn watertight(
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
pub(super) fn plain_boundary(own: &[u32]) -> Boundary {
    let n = own.len();
    own.iter()
        .enumerate()
        .map(|(k, &v)| (v, [((k + n - 1) % n) as u32, k as u32]))
        .collect()
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use crate::tools::scenes;
    use crate::tree::build::build_exact;
    use crate::tree::check::t_junctions;
    use crate::tree::input::prepare;
    use crate::tree::output::to_display;
    use crate::tree::{BuildOptions, DisplayTree};

    fn world_polygons(t: &DisplayTree) -> Vec<Vec<DVec3>> {
        t.polygons
            .iter()
            .map(|p| p.vertices.iter().map(|&i| t.vertices[i as usize]).collect())
            .collect()
    }

    #[test]
    fn cut_meshes_come_out_without_t_junctions() {
        for (name, mesh) in [
            ("torus", crate::tree::tests::turned(&scenes::torus(12, 8))),
            ("soup", scenes::soup(40, 0.5, 3)),
            (
                "bumpy",
                crate::tree::tests::bumpy_sphere(6, 9, &[0.3, -0.2, 0.1, 0.25, -0.3]),
            ),
        ] {
            let options = BuildOptions::default();
            let input = prepare(&mesh, None).unwrap();
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
