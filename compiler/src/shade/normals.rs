//! Corner normals: the normal each corner of each source triangle is lit with in smooth
//! shading.
//!
//! A face that gives its corners' normals in the file (`vn`) keeps them. Elsewhere the corner
//! of face `f` at point `p` takes the sum of the unit normals of the faces around `p`, each
//! weighted by its angle at `p`, normalised: the weights do not depend on how a surface is cut
//! into triangles (a quad gives its corner's angle whichever diagonal splits it), where a plain
//! or area-weighted sum would. Faces are around `p` when a corner of theirs is at exactly `p`,
//! whichever vertex statement it comes from: meshes made of patches (the teapot) repeat the
//! vertices along their seams, which must not show. Only faces whose normal is within the
//! [`Crease`] angle of `f`'s count, so a box keeps its edges sharp while a curved surface is
//! smooth across its facets. A degenerate face (zero area, no normal) adds nothing; a corner
//! whose sum is zero takes its face's normal, and the corners of a degenerate face are zero.

use glam::DVec3;
use rayon::prelude::*;

use crate::error::CompileError;
use crate::hash::FastMap;
use crate::load::SourceTriangle;

/// The crease angle unless one is given, in degrees.
pub const DEFAULT_CREASE_DEG: f64 = 60.0;

/// The angle between two faces' normals above which they meet at a sharp edge: each lights
/// its corners there without the other.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crease {
    degrees: f64,
}

impl Default for Crease {
    fn default() -> Self {
        Crease::DEFAULT
    }
}

impl Crease {
    /// [`DEFAULT_CREASE_DEG`].
    pub const DEFAULT: Crease = Crease {
        degrees: DEFAULT_CREASE_DEG,
    };

    /// A crease of `degrees`, from 0 (only faces of the same normal are smooth across) to 180
    /// (every face around a point is).
    ///
    /// # Errors
    /// [`CompileError::Crease`] for any other value, NaN included.
    pub fn new(degrees: f64) -> Result<Crease, CompileError> {
        if (0.0..=180.0).contains(&degrees) {
            Ok(Crease { degrees })
        } else {
            Err(CompileError::Crease { degrees })
        }
    }

    /// The angle, in degrees.
    pub fn degrees(self) -> f64 {
        self.degrees
    }

    /// Whether the unit normals `a` and `b` are within the angle (measured with `atan2`, which
    /// is accurate near 0 and 180 degrees where `acos` is not).
    fn joins(self, a: DVec3, b: DVec3) -> bool {
        a.cross(b).length().atan2(a.dot(b)) <= self.degrees.to_radians()
    }
}

/// The unit normal of the triangle `v` (of its front, the side its corners wind
/// counter-clockwise seen from); `None` when it has no area.
pub fn face_normal(v: &[DVec3; 3]) -> Option<DVec3> {
    (v[1] - v[0]).cross(v[2] - v[0]).try_normalize()
}

/// The angle of the triangle `v` at its corner `k`, in radians.
fn corner_angle(v: &[DVec3; 3], k: usize) -> f64 {
    let (e1, e2) = (v[(k + 1) % 3] - v[k], v[(k + 2) % 3] - v[k]);
    e1.cross(e2).length().atan2(e1.dot(e2))
}

/// The exact bits of a point or normal (`-0.0` taken as `0.0`), a hash key.
fn key(p: DVec3) -> [u64; 3] {
    (p + DVec3::ZERO).to_array().map(f64::to_bits)
}

/// One face normal at one point: the faces of that normal there, their angles summed.
#[derive(Clone, Copy)]
struct Around {
    /// The point's group.
    point: u32,
    /// The normal's bits ([`key`]).
    key: [u64; 3],
    normal: DVec3,
    /// The sum of the faces' angles at the point.
    angle: f64,
}

/// The unit normal of every corner of `triangles`, in the order of their vertices (see the
/// module doc): the file's where a triangle has them, else the angle-weighted normal of the
/// faces around the corner within `crease`. Faces of one normal at a point count once, so a
/// point costs the square of its distinct normals: a flat fan of any size is cheap, the apex
/// of a cone of many faces is not.
pub fn corner_normals(triangles: &[SourceTriangle], crease: Crease) -> Vec<[DVec3; 3]> {
    let faces: Vec<Option<DVec3>> = triangles
        .par_iter()
        .map(|t| face_normal(&t.vertices))
        .collect();
    // One group per exact point.
    let mut groups: FastMap<[u64; 3], u32> = FastMap::default();
    let corner_group: Vec<[u32; 3]> = triangles
        .iter()
        .map(|t| {
            t.vertices.map(|p| {
                let next = groups.len() as u32;
                *groups.entry(key(p)).or_insert(next)
            })
        })
        .collect();
    // Every face's normal at each of its points, sorted by point and normal (stably, so the
    // sums are the same on every run): a point's faces are a run, equal normals one entry.
    let mut each: Vec<Around> = triangles
        .par_iter()
        .zip(&faces)
        .zip(&corner_group)
        .flat_map_iter(|((t, face), group)| {
            face.iter().flat_map(move |&normal| {
                (0..3).map(move |k| Around {
                    point: group[k],
                    key: key(normal),
                    normal,
                    angle: corner_angle(&t.vertices, k),
                })
            })
        })
        .collect();
    each.par_sort_by(|a, b| (a.point, a.key).cmp(&(b.point, b.key)));
    let mut around: Vec<Around> = Vec::with_capacity(each.len());
    for e in each {
        match around.last_mut() {
            Some(last) if (last.point, last.key) == (e.point, e.key) => last.angle += e.angle,
            _ => around.push(e),
        }
    }
    // Where each point's run starts (a point with no face of area has an empty one).
    let mut starts = vec![around.len(); groups.len() + 1];
    for (i, e) in around.iter().enumerate().rev() {
        starts[e.point as usize] = i;
    }
    for g in (0..groups.len()).rev() {
        starts[g] = starts[g].min(starts[g + 1]);
    }
    let run = |g: u32| starts[g as usize]..starts[g as usize + 1];
    // The smooth normal of each entry: of the faces at its point within the crease of it.
    let smooth: Vec<DVec3> = around
        .par_iter()
        .map(|e| {
            let sum: DVec3 = around[run(e.point)]
                .iter()
                .filter(|other| other.key == e.key || crease.joins(e.normal, other.normal))
                .map(|other| other.normal * other.angle)
                .sum();
            sum.try_normalize().unwrap_or(e.normal)
        })
        .collect();
    triangles
        .par_iter()
        .zip(&faces)
        .zip(&corner_group)
        .map(|((t, face), group)| match (t.normals, face) {
            (Some(file), _) => file,
            (None, None) => [DVec3::ZERO; 3],
            (None, Some(n)) => group.map(|g| {
                let (range, k) = (run(g), key(*n));
                let at = range.start + around[range].partition_point(|e| e.key < k);
                smooth[at]
            }),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::DEFAULT_COLOUR;
    use crate::tools::scenes;

    fn triangles(v: &[[DVec3; 3]]) -> Vec<SourceTriangle> {
        v.iter()
            .map(|&vertices| SourceTriangle {
                opacity: u8::MAX,
                vertices,
                colour: DEFAULT_COLOUR,
                normals: None,
                texture: None,
            })
            .collect()
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-12
    }

    /// Two faces at the origin, the first flat with a right angle there, the second tilted by
    /// 40 degrees about the x axis with a 30-degree angle there: the corner normal at the
    /// origin is their normals weighted 3 to 1, not 1 to 1.
    #[test]
    fn faces_weigh_by_their_angle_at_the_point() {
        let tilt = 40f64.to_radians();
        let flat = [DVec3::ZERO, DVec3::X, DVec3::Y];
        // In the plane through the x axis tilted by 40 degrees, 30 degrees from -x.
        let (u, w) = (-DVec3::X, DVec3::new(0.0, -tilt.cos(), tilt.sin()));
        let thirty = 30f64.to_radians();
        let tilted = [DVec3::ZERO, u, u * thirty.cos() + w * thirty.sin()];
        let mesh = triangles(&[flat, tilted]);
        let (a, b) = (face_normal(&flat).unwrap(), face_normal(&tilted).unwrap());
        assert!((a.dot(b) - tilt.cos()).abs() < 1e-12, "40 degrees apart");
        assert!((corner_angle(&tilted, 0) - thirty).abs() < 1e-12);
        let want = (a * 90f64.to_radians() + b * thirty).normalize();
        let got = corner_normals(&mesh, Crease::default());
        assert!(close(got[0][0], want), "{} {want}", got[0][0]);
        assert!(close(got[1][0], want), "the same point, the same normal");
        let unweighted = (a + b).normalize();
        assert!((got[0][0] - unweighted).length() > 0.05);
        // Their other corners are theirs alone.
        assert!(close(got[0][1], a) && close(got[0][2], a));
        assert!(close(got[1][1], b) && close(got[1][2], b));
    }

    /// A box keeps its edges sharp: every corner normal is its face's. With every face joined
    /// (180 degrees), a box's corner is its diagonal: each side has a right angle there
    /// whichever diagonal splits it into triangles.
    #[test]
    fn a_box_keeps_its_edges_sharp() {
        let mut t = Vec::new();
        scenes::boxed(
            &mut t,
            DVec3::new(-1.0, -2.0, -3.0),
            DVec3::new(2.0, 1.0, 0.5),
        );
        let mesh = triangles(&t);
        for (tri, corners) in mesh.iter().zip(corner_normals(&mesh, Crease::default())) {
            let face = face_normal(&tri.vertices).unwrap();
            assert!(corners.iter().all(|&n| n == face), "{corners:?} {face}");
        }
        let round = corner_normals(&mesh, Crease::new(180.0).unwrap());
        for (tri, corners) in mesh.iter().zip(round) {
            for (p, n) in tri.vertices.iter().zip(corners) {
                let diagonal = DVec3::new(
                    if p.x > 0.0 { 1.0 } else { -1.0 },
                    if p.y > 0.0 { 1.0 } else { -1.0 },
                    if p.z > 0.0 { 1.0 } else { -1.0 },
                )
                .normalize();
                assert!(close(n, diagonal), "at {p}: {n}");
            }
        }
    }

    /// Corners at the same point join whichever triangle and vertex they come from: two
    /// halves of a ridge, each with its own copies of the shared points (a seam), and `-0.0`
    /// is `0.0`.
    #[test]
    fn points_group_by_position_across_duplicated_vertices() {
        let slope = |s: f64| {
            [
                DVec3::new(0.0, 0.0, -0.0),
                DVec3::new(s, -0.5, 0.0),
                DVec3::new(0.0, 0.0, 1.0),
            ]
        };
        // Reflected in x = 0 (with its winding reversed): the normals are 53.1 degrees apart,
        // within the crease, and the two angles at each shared point are equal.
        let left = slope(-1.0);
        let right = {
            let r = slope(1.0);
            [r[0], r[2], r[1]]
        };
        let right_copy = [DVec3::new(-0.0, 0.0, 0.0), right[1], right[2]];
        let mesh = triangles(&[left, right_copy]);
        let n = corner_normals(&mesh, Crease::default());
        let up = (face_normal(&left).unwrap() + face_normal(&right).unwrap()).normalize();
        assert!(close(n[0][0], up), "{}", n[0][0]);
        assert!(close(n[1][0], up), "{}", n[1][0]);
        assert!(
            close(n[0][2], up) && close(n[1][1], up),
            "the other shared point"
        );
        assert!(close(n[0][1], face_normal(&left).unwrap()), "its own");
    }

    /// Two faces whose normals are 0.1 degree under the crease apart join; 0.1 degree over,
    /// they do not.
    #[test]
    fn the_crease_decides_just_under_and_just_over() {
        let hinge = |degrees: f64| {
            let a = degrees.to_radians();
            let flat = [DVec3::ZERO, DVec3::X, DVec3::Y];
            // Turned by `a` about the x axis: its normal `a` from +z.
            let turned = [DVec3::ZERO, DVec3::new(0.0, -a.cos(), a.sin()), DVec3::X];
            triangles(&[flat, turned])
        };
        let crease = Crease::new(DEFAULT_CREASE_DEG).unwrap();
        for (degrees, joined) in [(59.9, true), (60.1, false), (10.0, true), (120.0, false)] {
            let mesh = hinge(degrees);
            let (a, b) = (
                face_normal(&mesh[0].vertices).unwrap(),
                face_normal(&mesh[1].vertices).unwrap(),
            );
            assert!((a.dot(b).acos().to_degrees() - degrees).abs() < 1e-9);
            let n = corner_normals(&mesh, crease)[0][0];
            assert_eq!(!close(n, a), joined, "{degrees} degrees: {n}");
        }
        // The crease is a checked number of degrees.
        assert_eq!(Crease::new(45.0).unwrap().degrees(), 45.0);
        for bad in [-1.0, 180.5, f64::NAN, f64::INFINITY] {
            let e = Crease::new(bad).unwrap_err();
            assert!(matches!(e, CompileError::Crease { .. }), "{e:?}");
            let says = e.to_string();
            assert!(
                says.contains("--crease") && says.contains(&format!("{bad}")),
                "{says}"
            );
        }
        // At 0 degrees only faces of the same normal join: a flat fan is flat.
        let fan = triangles(&[
            [DVec3::ZERO, DVec3::X, DVec3::Y],
            [DVec3::ZERO, DVec3::Y, DVec3::new(-1.0, 1.0, 0.0)],
        ]);
        for corners in corner_normals(&fan, Crease::new(0.0).unwrap()) {
            assert!(corners.iter().all(|&n| n == DVec3::Z));
        }
    }

    /// The file's normals are kept; a degenerate face adds nothing to its neighbours and its
    /// own corners have no normal.
    #[test]
    fn file_normals_are_kept_and_degenerate_faces_add_nothing() {
        let flat = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let sliver = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        let mut mesh = triangles(&[flat, sliver]);
        let n = corner_normals(&mesh, Crease::new(180.0).unwrap());
        assert_eq!(n[0], [DVec3::Z; 3]);
        assert_eq!(n[1], [DVec3::ZERO; 3]);
        let given = [DVec3::X, DVec3::Y, DVec3::new(0.6, 0.0, 0.8)];
        mesh[0].normals = Some(given);
        assert_eq!(corner_normals(&mesh, Crease::default())[0], given);
    }

    /// The teapot repeats its vertices along its patches' seams; corners at one point whose
    /// faces are all within the crease of one another share one normal, seam or not.
    #[test]
    fn the_teapot_has_no_seams() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/models/teapot.obj");
        if !path.is_file() {
            println!("skipping: shared models not found at ../shared/models");
            return;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let statements = text.lines().filter(|l| l.starts_with("v ")).count();
        let mesh = crate::load::load_obj(&path).unwrap();
        let normals = corner_normals(&mesh.triangles, Crease::default());
        let mut at: FastMap<[u64; 3], Vec<(DVec3, DVec3)>> = FastMap::default();
        for (t, corners) in mesh.triangles.iter().zip(&normals) {
            let Some(face) = face_normal(&t.vertices) else {
                continue;
            };
            for (p, n) in t.vertices.iter().zip(corners) {
                at.entry(key(*p)).or_default().push((face, *n));
            }
        }
        assert!(
            at.len() < statements,
            "{} points of {statements} vertices",
            at.len()
        );
        let crease = Crease::default();
        let mut smooth = 0;
        for corners in at.values() {
            let joined = corners
                .iter()
                .all(|a| corners.iter().all(|b| crease.joins(a.0, b.0)));
            if joined {
                smooth += 1;
                assert!(corners.iter().all(|c| c.1 == corners[0].1), "{corners:?}");
            }
        }
        assert!(
            smooth * 10 > at.len() * 9,
            "{smooth} of {} points",
            at.len()
        );
    }

    /// On a UV sphere the corner normals are the radial ones, within a fraction of a degree,
    /// where the faces' are off by several degrees.
    #[test]
    fn a_sphere_is_smooth() {
        let sphere = scenes::sphere(24, 48);
        let normals = corner_normals(&sphere.triangles, Crease::default());
        let (mut smooth, mut faceted) = (0f64, 0f64);
        for (t, corners) in sphere.triangles.iter().zip(&normals) {
            let face = face_normal(&t.vertices).unwrap();
            for (p, n) in t.vertices.iter().zip(corners) {
                // The generator's south pole is no one point (`sin π` is not 0): its copies
                // differ in their last bits and do not join.
                if p.y < -0.999 {
                    continue;
                }
                let radial = p.normalize();
                smooth = smooth.max(n.angle_between(radial).to_degrees());
                faceted = faceted.max(face.angle_between(radial).to_degrees());
            }
        }
        assert!(
            smooth < 0.25,
            "smooth: {smooth} degrees off the radial normal"
        );
        assert!(faceted > 20.0 * smooth, "faceted: {faceted} degrees");
    }
}
