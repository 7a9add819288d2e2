//! Smooth shading of a whole mesh: each source triangle's [`CornerShades`] from its corner
//! normals ([`super::normals`]), and what the output needs of them: the intensities at every
//! vertex of every polygon the compiler cut from a triangle, each side, with a polygon in
//! shadow at the ambient intensity as faceted shading has it.

use glam::DVec3;
use rayon::prelude::*;

use super::corners::{quantise, CornerShades, Facing};
use super::normals::{corner_normals, Crease};
use super::Shading;
use crate::error::CompileError;
use crate::load::Mesh;
use crate::tree::{DisplayTree, TreePolygon};

/// Smooth shading: a light and a crease angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Smooth {
    /// The light ([`Shading::Flat`]: every corner at full intensity, as unlit).
    pub shading: Shading,
    /// Faces further apart meet at a sharp edge.
    pub crease: Crease,
}

impl Smooth {
    /// Smooth shading by `shading`'s light, with a crease of `crease_deg` degrees.
    ///
    /// # Errors
    /// A light that cannot shade ([`Shading::check`]), a crease that is not from 0 to 180
    /// degrees ([`CompileError::Crease`]).
    pub fn new(shading: Shading, crease_deg: f64) -> Result<Smooth, CompileError> {
        shading.check()?;
        Ok(Smooth {
            shading,
            crease: Crease::new(crease_deg)?,
        })
    }

    /// The corner shades of every triangle of `mesh`, in its order.
    pub fn shade(&self, mesh: &Mesh) -> SmoothShades {
        let normals = corner_normals(&mesh.triangles, self.crease);
        let triangles = mesh
            .triangles
            .par_iter()
            .zip(normals)
            .map(|(t, n)| CornerShades::new(&self.shading, t.vertices, n))
            .collect();
        SmoothShades {
            triangles,
            in_shadow: self.shading.intensity_in_shadow(),
        }
    }
}

/// A mesh smooth-shaded ([`Smooth::shade`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothShades {
    /// Per source triangle (the index is its id), its corner shades.
    pub triangles: Vec<CornerShades>,
    /// The intensity of a side in shadow.
    pub in_shadow: f64,
}

/// The intensities of one vertex of a polygon, each side, unrounded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexShade {
    /// Of the side seen from the polygon's convex set's interior.
    pub interior: f64,
    /// Of the other side.
    pub exterior: f64,
}

impl VertexShade {
    /// The 8-bit intensities ([`quantise`]), `[interior, exterior]`.
    pub fn quantised(self) -> [u8; 2] {
        [quantise(self.interior), quantise(self.exterior)]
    }
}

impl SmoothShades {
    /// The intensities at each vertex of `polygon` of `tree` (a piece of source triangle
    /// `polygon.source` of the mesh these shades are of), in the order of its vertices: its
    /// triangle's interpolated at the vertex, or [`SmoothShades::in_shadow`] on both sides for
    /// a polygon in shadow.
    pub fn polygon(&self, tree: &DisplayTree, polygon: &TreePolygon) -> Vec<VertexShade> {
        let vertices = polygon.vertices.iter();
        if polygon.shadowed {
            let k = self.in_shadow;
            return vertices
                .map(|_| VertexShade {
                    interior: k,
                    exterior: k,
                })
                .collect();
        }
        let shades = &self.triangles[polygon.source as usize];
        // The interior side's normal is the plane's when `interior_front`, the triangle's front
        // is when not `flipped`.
        let interior = Facing::of(polygon.interior_front != polygon.flipped);
        let exterior = Facing::of(polygon.interior_front == polygon.flipped);
        vertices
            .map(|&v| {
                let at: DVec3 = tree.centre + tree.vertices[v as usize];
                VertexShade {
                    interior: shades.intensity_at(interior, at),
                    exterior: shades.intensity_at(exterior, at),
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::super::AMBIENT;
    use super::*;
    use crate::compile::{compile_mesh, CompileOptions};
    use crate::shadow::Light;
    use crate::tools::scenes;
    use crate::tree::BuildOptions;

    #[test]
    fn a_light_or_crease_that_cannot_shade_is_refused() {
        let e = Smooth::new(Shading::Lambert(DVec3::ZERO), 60.0).unwrap_err();
        assert!(matches!(e, CompileError::Light(_)), "{e:?}");
        let e = Smooth::new(Shading::default(), 181.0).unwrap_err();
        assert!(
            e.to_string()
                .contains("invalid crease angle 181 (--crease)"),
            "{e}"
        );
        let s = Smooth::new(Shading::Flat, 30.0).unwrap();
        assert_eq!(s.crease.degrees(), 30.0);
    }

    /// A sphere over a floor in the sun, compiled with shadows: every polygon's vertices get
    /// their triangle's interpolated intensities on the side the compiler's interior is (as
    /// faceted shading's sides follow it), the polygons in the sphere's shadow the ambient one,
    /// and a polygon vertex at a source corner that corner's intensity.
    #[test]
    fn polygons_get_their_triangles_intensities_and_shadows_the_ambient() {
        let mut mesh = scenes::sphere(6, 8);
        let floor = [
            DVec3::new(-4.0, -1.5, -4.0),
            DVec3::new(-4.0, -1.5, 4.0),
            DVec3::new(4.0, -1.5, 4.0),
            DVec3::new(4.0, -1.5, -4.0),
        ];
        for t in [[0, 1, 2], [0, 2, 3]] {
            mesh.triangles.push(crate::load::SourceTriangle {
                opacity: u8::MAX,
                vertices: t.map(|i| floor[i]),
                ..mesh.triangles[0]
            });
        }
        let sun = DVec3::new(0.2, 1.0, 0.1);
        let options = CompileOptions {
            build: BuildOptions {
                shadows: Some(Light::Sun(sun)),
                ..BuildOptions::default()
            },
            shading: Shading::Lambert(sun),
            ..CompileOptions::default()
        };
        let (tree, _) = compile_mesh(&mesh, &options, &|_| {}).unwrap();
        let smooth = Smooth::new(Shading::Lambert(sun), 60.0).unwrap();
        let shades = smooth.shade(&mesh);
        let (mut shadowed, mut at_corners) = (0, 0);
        for p in &tree.polygons {
            let got = shades.polygon(&tree, p);
            assert_eq!(got.len(), p.vertices.len());
            if p.shadowed {
                shadowed += 1;
                assert!(got
                    .iter()
                    .all(|v| v.interior == AMBIENT && v.exterior == AMBIENT));
                continue;
            }
            let t = &shades.triangles[p.source as usize];
            let plane = tree.planes[p.plane as usize].normal;
            let inward = if p.interior_front { plane } else { -plane };
            let source_front = crate::shade::normals::face_normal(&t.corners).unwrap();
            let interior = Facing::of(inward.dot(source_front) > 0.0);
            for (&v, shade) in p.vertices.iter().zip(&got) {
                let at = tree.centre + tree.vertices[v as usize];
                assert_eq!(shade.interior, t.intensity_at(interior, at));
                let exterior = if interior == Facing::Front {
                    Facing::Back
                } else {
                    Facing::Front
                };
                assert_eq!(shade.exterior, t.intensity_at(exterior, at));
                if let Some(k) = t.corners.iter().position(|&c| (c - at).length() < 1e-6) {
                    at_corners += 1;
                    let want = t.of(interior)[k];
                    assert!(
                        (shade.interior - want).abs() < 1e-5,
                        "{} {want}",
                        shade.interior
                    );
                }
            }
        }
        assert!(shadowed > 0, "the sphere shadows the floor");
        assert!(at_corners > 0);
        // The 8-bit form of a lit vertex and of a shadowed one.
        let lit = VertexShade {
            interior: 1.0,
            exterior: AMBIENT,
        };
        assert_eq!(lit.quantised(), [255, 77]);
    }
}
