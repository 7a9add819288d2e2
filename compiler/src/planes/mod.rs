//! Planes: exact integer planes, exact vertices and the side predicate.
//!
//! Every decision of the compiler (which side of a plane a vertex lies on, whether two planes
//! are the same) is made here, exactly:
//! - a plane is `n · p = d` with `|n_k| < 2^55` (i64) and `|d| < 2^84` (i128), divided by the
//!   gcd and sign-normalised, so two planes are equal iff their integers are equal;
//! - a vertex is either an original grid point (i32, classified with i128, no filter needed) or
//!   the intersection of three table planes as homogeneous integers `(X, Y, Z, W)`, `W > 0`,
//!   `|W| < 2^168`, `|X|, |Y|, |Z| < 2^197` (Cramer). Classifying it needs `< 2^255`, so
//!   ethnum's I256 is exact; an f64 filter with a proven error bound decides first.
//!
//! A cut never builds a plane from rounded points: cut vertices are intersections of table
//! planes, so precision never drifts however deep the cut.

use crate::hash::{first_equal, mix, FastMap, ShardHash};
use std::sync::Arc;

use ethnum::I256;

use crate::quantise::IPoint;

mod gcd;
pub(crate) mod same;
pub(crate) use gcd::{div_exact, gcd_u128, gcd_u64, gcd_wide};

/// Index of a plane in the [`PlaneTable`].
pub type PlaneId = u32;

/// Which side of a plane a point lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Side {
    /// `n · p > d`.
    Front,
    /// `n · p < d`.
    Back,
    /// `n · p = d`.
    On,
}

impl Side {
    fn of_sign(positive: bool, negative: bool) -> Side {
        if positive {
            Side::Front
        } else if negative {
            Side::Back
        } else {
            Side::On
        }
    }

    /// The other side (`On` stays `On`).
    pub fn opposite(self) -> Side {
        match self {
            Side::Front => Side::Back,
            Side::Back => Side::Front,
            Side::On => Side::On,
        }
    }
}

/// A canonical integer plane `n · p = d`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Plane {
    /// Normal (not unit); the first non-zero component is positive.
    pub n: [i64; 3],
    /// Offset.
    pub d: i128,
}

impl Plane {
    /// Canonical form of `n · p = d`: divided by the gcd of all four, first non-zero of `n`
    /// positive. Returns the plane and whether it was negated. `None` when `n` is zero.
    pub fn canonical(n: [i64; 3], d: i128) -> Option<(Plane, bool)> {
        if n == [0, 0, 0] {
            return None;
        }
        // The normal's gcd first (64 bits, often 1 already), then the offset's remainder.
        let mut g = n.iter().fold(0, |g, c| {
            if g == 1 {
                1
            } else {
                gcd_u64(g, c.unsigned_abs())
            }
        });
        if g != 1 {
            g = gcd_u64(g, (d.unsigned_abs() % u128::from(g)) as u64);
        }
        let (mut n, mut d) = if g == 1 {
            (n, d)
        } else {
            (n.map(|c| c / g as i64), d / i128::from(g))
        };
        let first = n.iter().copied().find(|&c| c != 0).unwrap_or(0);
        let negated = first < 0;
        if negated {
            n = n.map(|c| -c);
            d = -d;
        }
        Some((Plane { n, d }, negated))
    }

    /// Support plane of the triangle `a b c` (normal `(b−a)×(c−a)`, so the triangle's winding
    /// is counter-clockwise seen from the + side unless the canonical form negated it).
    /// Returns the raw normal too. `None` for a zero-area triangle.
    pub fn through(a: IPoint, b: IPoint, c: IPoint) -> Option<(Plane, bool)> {
        let n = cross(sub(b, a), sub(c, a));
        let d = dot_i(n, a);
        Plane::canonical(n, d)
    }

    /// Exact side of a grid point.
    #[inline]
    pub fn side_of_point(&self, p: IPoint) -> Side {
        let s = self.n[0] as i128 * p[0] as i128
            + self.n[1] as i128 * p[1] as i128
            + self.n[2] as i128 * p[2] as i128
            - self.d;
        Side::of_sign(s > 0, s < 0)
    }
}

fn sub(a: IPoint, b: IPoint) -> [i64; 3] {
    [
        a[0] as i64 - b[0] as i64,
        a[1] as i64 - b[1] as i64,
        a[2] as i64 - b[2] as i64,
    ]
}

fn cross(u: [i64; 3], v: [i64; 3]) -> [i64; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

fn dot_i(n: [i64; 3], p: IPoint) -> i128 {
    n[0] as i128 * p[0] as i128 + n[1] as i128 * p[1] as i128 + n[2] as i128 * p[2] as i128
}

/// The plane through edge `a -> b` of a triangle with support normal `support`, containing the
/// axis direction along which `support` is largest (never parallel to the support plane), so
/// adjacent triangles in the same plane share their edge planes.
pub fn edge_plane(a: IPoint, b: IPoint, support: [i64; 3]) -> Plane {
    let k = (0..3)
        .max_by_key(|&k| (support[k].unsigned_abs(), std::cmp::Reverse(k)))
        .unwrap_or(0);
    let mut e = [0i64; 3];
    e[k] = 1;
    let n = cross(sub(b, a), e);
    let d = dot_i(n, a);
    Plane::canonical(n, d)
        .expect("an edge of a non-degenerate triangle")
        .0
}

/// A table plane with its f64 approximation cached for the filters.
#[derive(Debug, Clone, Copy)]
pub struct PlaneEntry {
    /// The exact plane.
    pub plane: Plane,
    /// `n` rounded to f64.
    pub nf: [f64; 3],
    /// `d` rounded to f64.
    pub df: f64,
}

/// The canonical plane table: each distinct plane gets one id, in order of first insertion.
#[derive(Debug, Clone, Default)]
pub struct PlaneTable {
    entries: Vec<PlaneEntry>,
    ids: FastMap<Plane, PlaneId>,
}

impl ShardHash for Plane {
    fn shard_hash(&self) -> u64 {
        let [a, b, c] = self.n.map(|x| x as u64);
        mix([a, b, c, self.d as u64, (self.d >> 64) as u64])
    }
}

impl PlaneEntry {
    pub(crate) fn new(plane: Plane) -> PlaneEntry {
        PlaneEntry {
            plane,
            nf: plane.n.map(|c| c as f64),
            df: plane.d as f64,
        }
    }
}

impl PlaneTable {
    /// Id of `plane`, inserting it when new.
    pub fn insert(&mut self, plane: Plane) -> PlaneId {
        if self.ids.len() < self.entries.len() {
            // Filled by `insert_all`, which leaves the map to the first `insert`.
            self.ids = (self.entries.iter().enumerate())
                .map(|(i, e)| (e.plane, i as PlaneId))
                .collect();
        }
        let next = self.entries.len() as PlaneId;
        let id = *self.ids.entry(plane).or_insert(next);
        if id == next {
            self.entries.push(PlaneEntry::new(plane));
        }
        id
    }

    /// The ids [`PlaneTable::insert`] would give `planes` one after the other, with the
    /// planes matched in parallel (the same ids on any thread count).
    pub fn insert_all(&mut self, planes: &[Plane]) -> Vec<PlaneId> {
        if !self.is_empty() {
            return planes.iter().map(|&p| self.insert(p)).collect();
        }
        let first = first_equal(planes);
        let mut ids: Vec<PlaneId> = Vec::with_capacity(planes.len());
        for (i, &f) in first.iter().enumerate() {
            let id = if f as usize == i {
                self.entries.push(PlaneEntry::new(planes[i]));
                (self.entries.len() - 1) as PlaneId
            } else {
                ids[f as usize]
            };
            ids.push(id);
        }
        ids
    }

    /// The entry of `id`.
    #[inline]
    pub fn get(&self, id: PlaneId) -> &PlaneEntry {
        &self.entries[id as usize]
    }

    /// Number of distinct planes.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when the table holds no plane.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

/// A vertex given as homogeneous integers, `W > 0`.
#[derive(Debug, Clone, PartialEq)]
pub struct HomPoint {
    /// `(X, Y, Z)`; the point is `(X, Y, Z) / W`.
    pub xyz: [I256; 3],
    /// `W > 0`.
    pub w: I256,
    /// `(X, Y, Z) / W` rounded (relative error below `2^-49`).
    pub approx: [f64; 3],
}

impl HomPoint {
    /// A point from homogeneous coordinates (sign-normalised so that `W > 0`); `None` if `W = 0`.
    pub fn new(xyz: [I256; 3], w: I256) -> Option<HomPoint> {
        if w == I256::ZERO {
            return None;
        }
        let (xyz, w) = if w < I256::ZERO {
            (xyz.map(|c| -c), -w)
        } else {
            (xyz, w)
        };
        let wf = w.as_f64();
        let approx = xyz.map(|c| c.as_f64() / wf);
        Some(HomPoint { xyz, w, approx })
    }

    /// Lowest terms (divide by the gcd of all four). Only the tests use it: the output
    /// matches equal points without gcds ([`same`]).
    #[cfg(test)]
    pub fn reduced(&self) -> ([I256; 3], I256) {
        let mut g = self.w.unsigned_abs();
        for c in self.xyz {
            g = gcd_wide(g, c.unsigned_abs());
        }
        (self.xyz.map(|c| div_exact(c, g)), div_exact(self.w, g))
    }
}

/// A fragment vertex: an original grid point, or a cut point.
#[derive(Debug, Clone, PartialEq)]
pub enum Vertex {
    /// A quantised input corner.
    Int(IPoint),
    /// The intersection of three table planes.
    Hom(Arc<HomPoint>),
}

/// The f64 filter's bound, relative to `Σ|n_k x_k| + |d|`. The inputs carry relative errors
/// below 8u (u = 2^-53: `n`, `d` rounded once; `X`, `W` rounded by ethnum's `as_f64` (<= 3u
/// each) then divided), the three products and three sums add below 6u more: the true value
/// is within ~16u of the computed one; 2^-45 = 256u leaves a wide margin.
pub const FILTER_BOUND: f64 = 1.0 / (1u64 << 45) as f64;

/// One f64 filter bound for `e` and every point whose approximate coordinates have
/// `|x| + |y| + |z| <= l1_max`: [`FILTER_BOUND`] is relative to `Σ|n_k x_k| + |d|`, which is at
/// most `max|n_k| * (|x| + |y| + |z|) + |d|`; twice that covers the rounding of these sums.
/// Looser than the per-point bound only by what sends a point within ~2^-44 of the plane's
/// scale to the exact predicate, which nearly only points on the plane are.
#[inline]
pub fn shared_filter_bound(e: &PlaneEntry, l1_max: f64) -> f64 {
    let n = e.nf[0].abs().max(e.nf[1].abs()).max(e.nf[2].abs());
    2.0 * (n * l1_max + e.df.abs()) * FILTER_BOUND
}

/// The largest `|x| + |y| + |z|` of `points` (see [`shared_filter_bound`]).
pub fn l1_max<'p>(points: impl Iterator<Item = &'p [f64; 3]>) -> f64 {
    points
        .map(|c| c[0].abs() + c[1].abs() + c[2].abs())
        .fold(0.0, f64::max)
}

impl Vertex {
    /// Approximate coordinates (exact for grid points).
    #[inline]
    pub fn approx(&self) -> [f64; 3] {
        match self {
            Vertex::Int(p) => p.map(|c| c as f64),
            Vertex::Hom(h) => h.approx,
        }
    }

    /// Exact side of this vertex with respect to `e`.
    #[inline]
    pub fn side(&self, e: &PlaneEntry) -> Side {
        match self {
            Vertex::Int(p) => e.plane.side_of_point(*p),
            Vertex::Hom(h) => side_of_hom(h, e),
        }
    }
}

/// Exact side of a homogeneous point: the f64 filter, then I256 when it cannot decide.
#[inline]
pub fn side_of_hom(h: &HomPoint, e: &PlaneEntry) -> Side {
    let t = [
        e.nf[0] * h.approx[0],
        e.nf[1] * h.approx[1],
        e.nf[2] * h.approx[2],
    ];
    let s = t[0] + t[1] + t[2] - e.df;
    let m = t[0].abs() + t[1].abs() + t[2].abs() + e.df.abs();
    let bound = m * FILTER_BOUND;
    if s > bound {
        return Side::Front;
    }
    if s < -bound {
        return Side::Back;
    }
    side_of_hom_exact(h, &e.plane)
}

/// Exact side of a homogeneous point with I256 only (`|n·X − d·W| < 2^255`, see module docs).
pub fn side_of_hom_exact(h: &HomPoint, p: &Plane) -> Side {
    let mut s = I256::ZERO;
    for k in 0..3 {
        s += I256::from(p.n[k]) * h.xyz[k];
    }
    s -= I256::from(p.d) * h.w;
    Side::of_sign(s > I256::ZERO, s < I256::ZERO)
}

fn cross_wide(u: [i64; 3], v: [i64; 3]) -> [i128; 3] {
    let (u, v) = (u.map(|c| c as i128), v.map(|c| c as i128));
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

/// The common point of three planes (Cramer), or `None` when they do not meet in one point.
pub fn intersect(a: &Plane, b: &Plane, c: &Plane) -> Option<HomPoint> {
    let bc = cross_wide(b.n, c.n);
    let ca = cross_wide(c.n, a.n);
    let ab = cross_wide(a.n, b.n);
    let w = (0..3).fold(I256::ZERO, |w, k| {
        w + I256::from(a.n[k]) * I256::from(bc[k])
    });
    let (da, db, dc) = (I256::from(a.d), I256::from(b.d), I256::from(c.d));
    let xyz: [I256; 3] = std::array::from_fn(|k| {
        da * I256::from(bc[k]) + db * I256::from(ca[k]) + dc * I256::from(ab[k])
    });
    HomPoint::new(xyz, w)
}

#[cfg(test)]
mod tests;
