//! Convex splitting: polygons with more vertices than the output allows (a fragment plus the
//! vertices the watertight pass inserted) are cut into convex pieces, without opening new
//! T-junctions.

use rayon::prelude::*;

use super::watertight::Boundary;

/// A polygon's convex pieces: index lists into its boundary.
pub(super) type Pieces = Vec<Vec<usize>>;

/// The pieces of each polygon with more than `max` (>= 3) vertices on its boundary; `None`
/// for the others (one piece: the polygon itself).
pub(super) fn split_large(boundaries: &[Boundary], max: usize) -> Vec<Option<Pieces>> {
    let max = max.max(3);
    boundaries
        .par_iter()
        .map(|boundary| {
            (boundary.len() > max).then(|| {
                let sides: Vec<Vec<u32>> = boundary
                    .iter()
                    .map(|&(_, [a, b])| if a == b { vec![a] } else { vec![a, b] })
                    .collect();
                convex_pieces(&sides, max)
            })
        })
        .collect()
}

/// Cut a convex polygon whose vertex `i` lies on the sides `sides[i]` (collinear runs of its
/// boundary) into convex pieces of at most `max` (>= 3) vertices: index lists into the
/// polygon, in its winding. Each cut is a chord between two vertices on no common side, so
/// every piece has positive area, chords carry no vertex, and every boundary vertex stays on
/// the boundary of a piece (no new T-junction).
fn convex_pieces(sides: &[Vec<u32>], max: usize) -> Pieces {
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

#[cfg(test)]
mod tests {
    use super::*;

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

    /// The sides of a polygon of `n` vertices with none inserted: vertex `k` is on sides
    /// `k − 1` and `k`.
    fn plain(n: usize) -> Vec<Vec<u32>> {
        (0..n)
            .map(|k| vec![((k + n - 1) % n) as u32, k as u32])
            .collect()
    }

    #[test]
    fn plain_polygons_are_cut_by_halving_chords() {
        assert_eq!(convex_pieces(&plain(5), 12), vec![vec![0, 1, 2, 3, 4]]);
        assert_eq!(
            convex_pieces(&plain(5), 3),
            vec![vec![0, 1, 2], vec![2, 3, 4], vec![4, 0, 2]]
        );
        assert_eq!(
            convex_pieces(&plain(7), 4),
            vec![vec![0, 1, 2, 3], vec![3, 4, 5], vec![5, 6, 0, 3]]
        );
    }
}
