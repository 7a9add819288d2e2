//! Shadow: the input fragments cut exactly along the shadows the source triangles cast from a
//! sun or a point light, so that shading bakes every piece lit or in shadow (Chin and Feiner's
//! shadow volumes, resolved at compile time).
//!
//! A point `p` of a fragment is in shadow when the ray towards the sun (`p + t l`, `t > 0`), or
//! the segment to the point light `L`, meets another source triangle `T`: `p` lies in `T`'s
//! shadow volume, the intersection of four open half-spaces: the side of `T`'s support plane
//! away from the light and, for each edge `a b` of `T`, the side of the plane through the edge
//! and the light that holds `T`'s third vertex. The light is exact in the grid's integers: the
//! sun's direction `l` on an integer lattice ([`sun_direction`]), a point light at its nearest
//! grid point. Each of those planes is then an exact integer plane, of normal `(b − a) × l` or
//! `(b − a) × (L − a)`, below the plane table's bounds for grid points `a`, `b` (and `L` within
//! twice the grid's half-extent, which the compile checks). A fragment is cut by them with the
//! build's own exact cut, and the piece inside all four is in shadow. Points on a volume's
//! boundary count as lit, and so does a fragment lying in one of its planes (it is lit edge-on
//! or is the occluder's neighbour). Which side of a fragment faces the light is exact too: a
//! sign of `n · l`, or the side of its plane `L` is on, the same over the whole plane.
//!
//! A transparent source triangle (an MTL `d` below 1) casts no shadow: light passes through
//! it. It receives shadows as any other.
//!
//! Why the tree is unaffected: every piece lies in its fragment's support plane and shadow
//! planes are only ever edge planes of pieces, never support planes. The build's support
//! planes are thus the same, and so are its invariants and its termination argument (the
//! number of distinct support planes never grows from a node to its child and drops for every
//! child but one). The pieces of a triangle tile it, so the coverage check holds; the cuts open
//! T-junctions on neighbouring fragments, which the output's watertight pass closes as it does
//! for the build's own cuts. The extra pieces go into the tree with the others.

use glam::DVec3;
use rayon::prelude::*;

use crate::error::CompileError;
use crate::planes::{Plane, PlaneId, PlaneTable, Side, Vertex};
use crate::quantise::{IPoint, Quantiser};
use crate::split::{Fragment, Placement, SplitResult};

/// Where the light that casts shadows is (world coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// A sun: the direction towards it.
    Sun(DVec3),
    /// A point light: its position.
    Point(DVec3),
}

/// The light in the grid's integers.
#[derive(Clone, Copy)]
enum Caster {
    Sun([i64; 3]),
    Point(IPoint),
}

impl Caster {
    /// The side of `plane` the light is on (`On`: the plane is lit edge-on).
    fn side(&self, plane: &Plane) -> Side {
        match *self {
            Caster::Sun(l) => facing(plane, l),
            Caster::Point(p) => plane.side_of_point(p),
        }
    }

    /// The plane through `a`, `b` and the light (`None` when they are collinear).
    fn through(&self, a: IPoint, b: IPoint) -> Option<Plane> {
        let e = [0, 1, 2].map(|i| i64::from(b[i]) - i64::from(a[i]));
        let l = match *self {
            Caster::Sun(l) => l,
            Caster::Point(p) => [0, 1, 2].map(|i| i64::from(p[i]) - i64::from(a[i])),
        };
        let n = [
            e[1] * l[2] - e[2] * l[1],
            e[2] * l[0] - e[0] * l[2],
            e[0] * l[1] - e[1] * l[0],
        ];
        let d: i128 = (0..3).map(|i| i128::from(n[i]) * i128::from(a[i])).sum();
        Plane::canonical(n, d).map(|(plane, _)| plane)
    }
}

/// How far a point light may be from the grid's centre on each axis, in grid steps: twice the
/// grid's half-extent keeps the shadow planes' normals below 2^54 and offsets below 2^81.
const POINT_REACH: f64 = (1u64 << 26) as f64;

/// Lattice units of the sun's direction, per unit length: its direction is exact to about
/// 2^-20 radian, and the shadow planes' normals stay below 2^48.
const DIRECTION_UNITS: f64 = (1u64 << 20) as f64;

/// The direction towards the sun as the compiler casts shadows along it: `towards` normalised
/// and rounded onto an integer lattice (`None` when it is zero or not finite). The reference
/// casts its shadow rays along the same direction.
pub fn sun_direction(towards: DVec3) -> Option<[i64; 3]> {
    let l = towards.normalize_or_zero();
    let lattice = (l * DIRECTION_UNITS).round();
    let l = [lattice.x as i64, lattice.y as i64, lattice.z as i64];
    (l != [0; 3]).then_some(l)
}

/// A source triangle's shadow volume: four planes and the side of each that is inside.
struct Volume {
    source: u32,
    bounds: [(PlaneId, Side); 4],
    /// The triangle's corners projected across the sun's direction, for a quick rejection
    /// (none for a point light).
    shadow_box: Option<Box2>,
}

/// A box in the plane across the sun's direction (f64, widened by a bound on its rounding).
#[derive(Clone, Copy)]
struct Box2 {
    lo: [f64; 2],
    hi: [f64; 2],
}

impl Box2 {
    /// The box of `points` projected on `axes`, widened by `margin`.
    fn of(points: &[IPoint], axes: &[DVec3; 2], margin: f64) -> Box2 {
        let mut b = Box2 {
            lo: [f64::INFINITY; 2],
            hi: [f64::NEG_INFINITY; 2],
        };
        for p in points {
            let p = DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
            for (k, axis) in axes.iter().enumerate() {
                let v = p.dot(*axis);
                b.lo[k] = b.lo[k].min(v - margin);
                b.hi[k] = b.hi[k].max(v + margin);
            }
        }
        b
    }

    fn overlaps(&self, other: &Box2) -> bool {
        (0..2).all(|k| self.lo[k] <= other.hi[k] && other.lo[k] <= self.hi[k])
    }
}

/// The sun's volumes in a uniform grid of cells across its rays: a fragment can only be
/// shadowed by the volumes listed in the cells its box covers, so each fragment tests a few
/// volumes instead of all of them.
struct Buckets {
    lo: [f64; 2],
    cell: f64,
    side: usize,
    /// Per cell, the volumes whose box meets it, in increasing order.
    cells: Vec<Vec<u32>>,
}

impl Buckets {
    /// The buckets of `volumes` (`None` without boxes: a point light).
    fn new(volumes: &[Volume]) -> Option<Buckets> {
        let boxes: Vec<&Box2> = volumes
            .iter()
            .map(|v| v.shadow_box.as_ref())
            .collect::<Option<_>>()?;
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for b in &boxes {
            for k in 0..2 {
                lo[k] = lo[k].min(b.lo[k]);
                hi[k] = hi[k].max(b.hi[k]);
            }
        }
        let side = ((boxes.len() as f64).sqrt().ceil() as usize).clamp(1, 1024);
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let mut buckets = Buckets {
            lo,
            cell: (extent / side as f64).max(f64::MIN_POSITIVE),
            side,
            cells: vec![Vec::new(); side * side],
        };
        for (k, b) in boxes.iter().enumerate() {
            let ([x0, y0], [x1, y1]) = buckets.range(b);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    buckets.cells[y * side + x].push(k as u32);
                }
            }
        }
        Some(buckets)
    }

    /// The cells a box covers, first and last on each axis (clamped to the grid).
    fn range(&self, b: &Box2) -> ([usize; 2], [usize; 2]) {
        let at = |v: f64, k: usize| {
            let c = ((v - self.lo[k]) / self.cell).floor();
            (c.max(0.0) as usize).min(self.side - 1)
        };
        (
            [at(b.lo[0], 0), at(b.lo[1], 1)],
            [at(b.hi[0], 0), at(b.hi[1], 1)],
        )
    }

    /// The volumes whose cells `b` covers, in increasing order.
    fn meeting(&self, b: &Box2) -> Vec<u32> {
        let ([x0, y0], [x1, y1]) = self.range(b);
        let mut out: Vec<u32> = (y0..=y1)
            .flat_map(|y| (x0..=x1).flat_map(move |x| &self.cells[y * self.side + x]))
            .copied()
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }
}

/// The grid corners of an input fragment (a source triangle).
fn corners(f: &Fragment) -> Vec<IPoint> {
    f.vertices
        .iter()
        .filter_map(|v| match v {
            Vertex::Int(p) => Some(*p),
            Vertex::Hom(_) => None,
        })
        .collect()
}

/// The sign of `n · l` for a plane's normal `n`.
fn facing(plane: &Plane, l: [i64; 3]) -> Side {
    let s: i128 = (0..3)
        .map(|k| i128::from(plane.n[k]) * i128::from(l[k]))
        .sum();
    if s > 0 {
        Side::Front
    } else if s < 0 {
        Side::Back
    } else {
        Side::On
    }
}

/// Each fragment of `fragments` (the source triangles, as the input stage makes them) cut
/// along the shadows the others cast from `light` (those whose source triangle `casts`, by
/// source id: a transparent triangle casts none; a source beyond `casts` does), each piece marked in shadow or not
/// ([`Fragment::shadowed`]); the planes of the cuts are added to `table`. Deterministic: the
/// planes are added in source order, the pieces come in source order. Fails on a point light
/// too far from the scene for exact planes (a sun then does the same job).
pub(crate) fn cast(
    fragments: &[Fragment],
    casts: &[bool],
    table: &mut PlaneTable,
    light: Light,
    grid: &Quantiser,
) -> Result<Vec<Fragment>, CompileError> {
    let caster = match light {
        Light::Sun(towards) => match sun_direction(towards) {
            Some(l) => Caster::Sun(l),
            None => return Ok(fragments.to_vec()),
        },
        Light::Point(at) => {
            let q = (at - grid.offset) / grid.scale;
            // NaN fails as well.
            let within = q.abs().max_element() <= POINT_REACH;
            if !within {
                return Err(CompileError::Light(format!(
                    "the point light {at} is too far from the scene for exact shadows (at most \
                     twice the scene's half-extent from its centre on each axis): use a sun"
                )));
            }
            Caster::Point(grid.quantise(at))
        }
    };
    // The sun's rays across: a box of a triangle there holds the shadow it casts.
    let axes = match caster {
        Caster::Sun(l) => {
            let lf = DVec3::new(l[0] as f64, l[1] as f64, l[2] as f64).normalize();
            let u = lf.any_orthogonal_vector().normalize();
            Some([u, lf.cross(u).normalize()])
        }
        Caster::Point(_) => None,
    };
    // Grid coordinates are below 2^26 in magnitude: a projection on a unit axis rounds by far
    // less than this.
    let margin = 1e-6 * f64::from(1u32 << 26);
    let mut volumes = Vec::new();
    for f in fragments {
        let q = corners(f);
        let support = table.get(f.support).plane;
        let light_side = caster.side(&support);
        let caster_at_all = casts.get(f.source as usize).copied().unwrap_or(true);
        if q.len() != 3 || light_side == Side::On || !caster_at_all {
            continue; // lit edge-on (or transparent): no shadow
        }
        let mut bounds = [(f.support, light_side.opposite()); 4];
        for k in 0..3 {
            let (a, b, c) = (q[k], q[(k + 1) % 3], q[(k + 2) % 3]);
            // Never `None`: the light off the triangle's plane is off every edge's line.
            let Some(plane) = caster.through(a, b) else {
                continue;
            };
            bounds[k + 1] = (table.insert(plane), plane.side_of_point(c));
        }
        volumes.push(Volume {
            source: f.source,
            bounds,
            shadow_box: axes.map(|axes| Box2::of(&q, &axes, margin)),
        });
    }
    let table = &*table;
    let buckets = Buckets::new(&volumes);
    let pieces: Vec<Vec<Fragment>> = fragments
        .par_iter()
        .map(|f| {
            let support = table.get(f.support).plane;
            if caster.side(&support) == Side::On {
                return Ok(vec![f.clone()]); // lit edge-on: ambient on both sides anyway
            }
            let reach = axes.map(|axes| Box2::of(&corners(f), &axes, margin));
            let mut lit = vec![f.clone()];
            let mut dark = Vec::new();
            // In source order, whatever the buckets: the same pieces every time.
            let candidates = match (&buckets, &reach) {
                (Some(buckets), Some(reach)) => buckets.meeting(reach),
                _ => (0..volumes.len() as u32).collect(),
            };
            for v in candidates.iter().map(|&k| &volumes[k as usize]) {
                let apart = matches!((&v.shadow_box, &reach), (Some(a), Some(b)) if !a.overlaps(b));
                if v.source == f.source || apart {
                    continue;
                }
                let mut still = Vec::with_capacity(lit.len());
                for piece in lit {
                    let (inside, outside) = clip(piece, &v.bounds, table)?;
                    dark.extend(inside);
                    still.extend(outside);
                }
                lit = still;
                if lit.is_empty() {
                    break;
                }
            }
            if lit.is_empty() {
                // All in shadow: the fragment whole, uncut.
                return Ok(vec![Fragment {
                    shadowed: true,
                    ..f.clone()
                }]);
            }
            for piece in &mut dark {
                piece.shadowed = true;
            }
            lit.extend(dark);
            Ok(lit)
        })
        .collect::<Result<_, CompileError>>()?;
    Ok(pieces.into_iter().flatten().collect())
}

/// `piece` cut by the half-spaces `bounds`: the part inside all of them (if any) and the
/// parts outside (`piece` itself, uncut, when no part is inside).
#[allow(clippy::type_complexity)]
fn clip(
    piece: Fragment,
    bounds: &[(PlaneId, Side); 4],
    table: &PlaneTable,
) -> Result<(Option<Fragment>, Vec<Fragment>), CompileError> {
    let outside_of = |&(plane, inside): &(PlaneId, Side)| match piece.placement(plane, table) {
        Placement::Front => inside != Side::Front,
        Placement::Back => inside != Side::Back,
        Placement::On => true,
        Placement::Straddle => false,
    };
    if bounds.iter().any(outside_of) {
        return Ok((None, vec![piece]));
    }
    let original = piece.clone();
    let mut outside = Vec::new();
    let mut rest = piece;
    for &(plane, inside) in bounds {
        let result = rest.split(plane, table).ok_or_else(|| {
            CompileError::Invariant("a shadow cut whose planes do not meet in a point".into())
        })?;
        rest = match result {
            SplitResult::Front(p) if inside == Side::Front => p,
            SplitResult::Back(p) if inside == Side::Back => p,
            // Outside after all: the piece stays whole.
            SplitResult::Front(_) | SplitResult::Back(_) | SplitResult::On(_) => {
                return Ok((None, vec![original]));
            }
            SplitResult::Cut(front, back) => {
                let (kept, other) = if inside == Side::Front {
                    (front, back)
                } else {
                    (back, front)
                };
                outside.push(other);
                kept
            }
        };
    }
    Ok((Some(rest), outside))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::scenes::mesh;
    use crate::tree::input::prepare;

    /// Area of a fragment in grid units, from its vertices.
    fn area(f: &Fragment) -> f64 {
        let p: Vec<DVec3> = f.vertices.iter().map(|v| DVec3::from(v.approx())).collect();
        let twice =
            (1..p.len() - 1).fold(DVec3::ZERO, |s, k| s + (p[k] - p[0]).cross(p[k + 1] - p[0]));
        twice.length() / 2.0
    }

    /// A square ground at z = 0 (two triangles, sources 0 and 1) and a triangle above it
    /// (source 2).
    fn ground_and_roof(height: f64) -> crate::load::Mesh {
        let v = DVec3::new;
        mesh(vec![
            [v(-4.0, -4.0, 0.0), v(4.0, -4.0, 0.0), v(4.0, 4.0, 0.0)],
            [v(-4.0, -4.0, 0.0), v(4.0, 4.0, 0.0), v(-4.0, 4.0, 0.0)],
            [
                v(-1.0, -1.0, height),
                v(1.5, -0.5, height),
                v(0.0, 1.0, height),
            ],
        ])
    }

    #[test]
    fn the_sun_is_a_lattice_direction() {
        assert_eq!(sun_direction(DVec3::ZERO), None);
        assert_eq!(sun_direction(DVec3::new(f64::NAN, 0.0, 1.0)), None);
        assert_eq!(
            sun_direction(DVec3::new(0.0, 0.0, 3.0)),
            Some([0, 0, 1 << 20])
        );
        let l = sun_direction(DVec3::new(3.0, -4.0, 0.0)).unwrap();
        assert_eq!(l, [629_146, -838_861, 0]);
    }

    #[test]
    fn a_triangle_shades_exactly_its_projection_on_the_ground() {
        let roof = ground_and_roof(2.0);
        let input = prepare(&roof, Some(Light::Sun(DVec3::new(0.3, 0.2, 1.0)))).unwrap();
        let pieces = input.build_fragments();
        let of = |source: u32, dark: bool| {
            (pieces.iter()).filter(move |f| f.source == source && f.shadowed == dark)
        };
        // Nothing is above the roof: one piece, lit.
        assert_eq!(of(2, false).count(), 1);
        assert_eq!(of(2, true).count(), 0);
        let roof_area = area(&input.fragments[2]);
        let ground_area = area(&input.fragments[0]) + area(&input.fragments[1]);
        let dark: f64 = (0..2).flat_map(|s| of(s, true)).map(area).sum();
        let lit: f64 = (0..2).flat_map(|s| of(s, false)).map(area).sum();
        // Parallel planes: the shadow has the roof's area, and the pieces tile the ground.
        assert!(
            (dark - roof_area).abs() <= 1e-9 * roof_area,
            "{dark} {roof_area}"
        );
        assert!((dark + lit - ground_area).abs() <= 1e-9 * ground_area);
        // The shadow is where the roof falls along the sun: every dark vertex, moved up along
        // it to the roof's height, lies inside the roof (to the grid's rounding of its corners).
        let q = &input.quantiser;
        for f in (0..2).flat_map(|s| of(s, true)) {
            for v in &f.vertices {
                let p = q.offset + DVec3::from(v.approx()) * q.scale + DVec3::new(0.6, 0.4, 2.0);
                let r = roof.triangles[2].vertices;
                let inside = (0..3).all(|k| {
                    let (a, b) = (r[k], r[(k + 1) % 3]);
                    (b - a).cross(p - a).z >= -1e-4
                });
                assert!(inside, "{p} is outside the roof");
            }
        }
    }

    #[test]
    fn a_point_light_casts_the_roof_enlarged_by_its_distance() {
        let roof = ground_and_roof(1.0);
        // Straight above the roof at height 3: the shadow is the roof scaled by 3 / (3 - 1).
        let light = Light::Point(DVec3::new(0.2, 0.1, 3.0));
        let input = prepare(&roof, Some(light)).unwrap();
        let pieces = input.build_fragments();
        let dark: f64 = pieces.iter().filter(|f| f.shadowed).map(area).sum();
        let want = area(&input.fragments[2]) * 1.5 * 1.5;
        assert!((dark - want).abs() <= 1e-6 * want, "{dark} {want}");
        // Too far from the scene for exact planes: a clear error.
        let far = Light::Point(DVec3::new(0.0, 0.0, 1e6));
        let err = prepare(&roof, Some(far)).err().expect("refused");
        assert!(err.to_string().contains("use a sun"), "{err}");
    }

    #[test]
    fn a_sun_along_a_face_casts_and_receives_nothing() {
        let roof = ground_and_roof(2.0);
        let input = prepare(&roof, Some(Light::Sun(DVec3::new(1.0, 0.5, 0.0)))).unwrap();
        let pieces = input.build_fragments();
        assert_eq!(pieces, input.fragments.as_slice(), "nothing cut");
        assert!(pieces.iter().all(|f| !f.shadowed));
    }

    #[test]
    fn the_same_input_gives_the_same_pieces() {
        let roof = ground_and_roof(1.0);
        let sun = Some(Light::Sun(DVec3::new(-0.2, 0.4, 1.0)));
        let a = prepare(&roof, sun).unwrap();
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let b = one.install(|| prepare(&roof, sun).unwrap());
        assert_eq!(a.build_fragments(), b.build_fragments());
        assert_eq!(a.table.len(), b.table.len());
        assert!(a.build_fragments().len() > a.fragments.len());
    }
}
