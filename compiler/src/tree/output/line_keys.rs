//! Exact identities of the lines edges lie on, so that only collinear edges are compared when
//! T-junctions are closed (see [`super::watertight`]).
//!
//! A line is keyed by the Plücker coordinates of two planes meeting in it, reduced to a
//! canonical form: equal keys mean the same line, whatever planes (or grid points) gave it.

use crate::hash::{mix, ShardHash};

use ethnum::{I256, U256};
use rayon::prelude::*;

use crate::planes::{div_exact, gcd_u128, gcd_u64, gcd_wide, Plane, PlaneId, Vertex};
use crate::quantise::IPoint;
use crate::split::Fragment;
use crate::tree::input::Input;

/// Exact identity of a line: the Plücker coordinates `(n1 × n2, d1 n2 − d2 n1)` of the two
/// planes meeting in it (the same up to a factor for any two planes of the pencil), divided by
/// their gcd, first non-zero direction component positive.
///
/// A key is stored narrow when all six integers fit in 64 bits (every line through two grid
/// points, so most edges), wide (boxed) otherwise: the form is a function of the key, so equal
/// keys have the same form, and the per-edge list is less than half the size.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum LineKey {
    Narrow { dir: [i64; 3], moment: [i64; 3] },
    Wide(Box<WideLineKey>),
}

/// A [`LineKey`] that does not fit in 64-bit integers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct WideLineKey {
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
    pub(super) fn dir(&self) -> [f64; 3] {
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

/// Each edge's line key and its hash, numbered as the vertices the edges start from (edge `k`
/// of polygon `p` is `offsets[p] + k`); `None` for an edge on no line (degenerate).
pub(super) type EdgeKeys = Vec<Option<(u64, LineKey)>>;

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
pub(super) fn edge_keys(polys: &[&Fragment], input: &Input) -> EdgeKeys {
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
