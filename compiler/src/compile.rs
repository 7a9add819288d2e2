//! The whole compile in one call: load -> build -> shade -> encode. Used by the CLI, the
//! [`crate::Builder`] for build scripts, the benchmark and the tests.

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::DVec3;
use rayon::prelude::*;

use crate::error::CompileError;
use crate::load::{load_obj_bytes, read_obj, LoadOptions, Mesh};
use crate::quantise::Quantiser;
use crate::shade::smooth::Smooth;
use crate::shade::{Shading, Surface};
use crate::tree::{build, BuildOptions, DisplayTree, TreeStats};
use crate::write::format::polygon_flags;
use peel_runtime::read::layout::{MAX_TEXTURES, NO_TEXTURE};

/// Everything a compile can be asked.
#[derive(Debug, Clone, Default)]
pub struct CompileOptions {
    /// How the OBJ is read (the default colour).
    pub load: LoadOptions,
    /// Tree-building knobs.
    pub build: BuildOptions,
    /// Store each polygon's source triangle id (for id images).
    pub ids: bool,
    /// Added to every id stored: a part of a scene of parts numbers its triangles after
    /// those of the parts before it ([`compile_parts`]), so that one id image tells them
    /// apart.
    pub id_offset: u32,
    /// Store vertices as `f32` (12 bytes) instead of 16-bit steps on the scene's bounds (6
    /// bytes, within 1/131070 of the scene's extent per axis): for views so close that such a
    /// step spans more than 1/16 pixel.
    pub wide_vertices: bool,
    /// The light colours are baked with ([`Shading::Flat`]: none).
    pub shading: Shading,
    /// One colour per polygon side, or smooth shading ([`crate::shade::DEFAULT_SURFACE`]).
    pub surface: Surface,
    /// Mark the faces of closed parts that face out (see `quantise::solid`), so that the
    /// runtime skips those seen from behind while a frame needs no clipping (the whole scene
    /// in front of the near plane). The user's word that no part passes through itself, which
    /// the compiler does not check.
    pub solid: bool,
}

/// The result of a compile.
#[derive(Debug, Clone)]
pub struct Compiled {
    /// The `.peel` bytes.
    pub bytes: Vec<u8>,
    /// The tree's counters.
    pub stats: TreeStats,
    /// Wall time of load + build + encode, in seconds.
    pub seconds: f64,
    /// Loader warnings.
    pub warnings: Vec<String>,
    /// Files read (OBJ and MTL).
    pub files: Vec<PathBuf>,
    /// MTL files named but absent (see [`Mesh::missing`]).
    pub missing: Vec<PathBuf>,
    /// The bytes of the MTL files read (see [`Mesh::mtl_bytes`]).
    pub mtl_bytes: Vec<(PathBuf, Vec<u8>)>,
}

/// Build, shade and encode an already loaded mesh (a mesh without faces, or whose faces are
/// all degenerate, gives an empty tree). Refuses a light that cannot shade
/// ([`Shading::check`]).
pub fn compile_mesh(
    mesh: &Mesh,
    options: &CompileOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<(DisplayTree, Vec<u8>), CompileError> {
    options.shading.check()?;
    if mesh.textures.len() > MAX_TEXTURES as usize {
        return Err(CompileError::TooManyTextures {
            path: mesh.files.first().cloned().unwrap_or_default(),
            count: mesh.textures.len(),
            max: MAX_TEXTURES,
        });
    }
    let tree = build(mesh, &options.build, progress)?;
    let input = crate::write::WriteInput {
        ids: options.ids,
        id_offset: options.id_offset,
        wide_vertices: options.wide_vertices,
        ..crate::write::WriteInput::default()
    };
    let solid = solid_flags(&tree, mesh, options.solid);
    // Textured polygons: their vertices' coordinates, and each one's texture.
    let uvs = crate::texture::polygon_uvs(&tree, mesh);
    let polygon_textures: Vec<u8> = if uvs.is_empty() {
        Vec::new()
    } else {
        (tree.polygons.iter())
            .map(|p| match mesh.triangles[p.source as usize].texture {
                // At most `MAX_TEXTURES` (checked above): below `NO_TEXTURE`.
                Some(t) => t.texture as u8,
                None => NO_TEXTURE,
            })
            .collect()
    };
    // Transparent polygons: each one's opacity (empty for an opaque scene).
    let opacities: Vec<u8> = (tree.polygons.iter())
        .map(|p| mesh.triangles[p.source as usize].opacity)
        .collect();
    let transparent = opacities.iter().any(|&a| a < crate::load::OPAQUE);
    let input = crate::write::WriteInput {
        textures: &mesh.textures,
        polygon_textures: &polygon_textures,
        opacities: if transparent { &opacities } else { &[] },
        ..input
    };
    let bytes = match options.surface {
        Surface::Faceted => {
            let (colours, exterior) = bake(&tree, mesh, &options.shading);
            let copied = crate::write::shades::uv_vertices(&tree, &uvs)?;
            let input = crate::write::WriteInput {
                colours: &colours,
                exterior: &exterior,
                polygon_flags: &solid,
                uvs: &copied.uvs,
                ..input
            };
            crate::write::encode_with(&copied.tree, &input)?
        }
        Surface::Smooth(crease) => {
            let smooth = Smooth {
                shading: options.shading,
                crease,
            };
            let shades = polygon_shades(&tree, mesh, &smooth);
            let mut shaded = crate::write::shades::shade_vertices(&tree, &shades, &uvs)?;
            if transparent {
                // A transparent polygon has one colour a side (composited in runs of one
                // colour): faceted, lit as a faceted file lights it.
                let (interior, exterior) = bake(&tree, mesh, &options.shading);
                let smooth = polygon_flags::SMOOTH | polygon_flags::INTERIOR_BACK;
                for (k, &a) in opacities.iter().enumerate() {
                    if a < crate::load::OPAQUE {
                        shaded.colours[k] = interior[k];
                        shaded.exterior[k] = exterior[k];
                        shaded.flags[k] &= !smooth;
                    }
                }
            }
            let merged: Vec<u8>;
            let flags = if solid.is_empty() {
                &shaded.flags
            } else {
                merged = (shaded.flags.iter().zip(&solid))
                    .map(|(a, b)| a | b)
                    .collect();
                &merged
            };
            let input = crate::write::WriteInput {
                colours: &shaded.colours,
                exterior: &shaded.exterior,
                polygon_flags: flags,
                shades: &shaded.shades,
                uvs: &shaded.uvs,
                ..input
            };
            crate::write::encode_with(&shaded.tree, &input)?
        }
    };
    Ok((tree, bytes))
}

/// Per polygon of `tree` (from `mesh`'s triangles), the side its solid's inside lies on
/// ([`polygon_flags::INSIDE_INTERIOR`] or [`polygon_flags::INSIDE_EXTERIOR`]: its source
/// triangle's back), or 0 when its source triangle bounds no solid; empty unless `solid`.
fn solid_flags(tree: &DisplayTree, mesh: &Mesh, solid: bool) -> Vec<u8> {
    if !solid {
        return Vec::new();
    }
    let solids = crate::quantise::solid::solid_triangles(mesh, &Quantiser::fit(mesh));
    tree.polygons
        .iter()
        .map(|p| {
            if !solids.get(p.source as usize).copied().unwrap_or(false) {
                0
            } else if p.interior_is_back() {
                polygon_flags::INSIDE_INTERIOR
            } else {
                polygon_flags::INSIDE_EXTERIOR
            }
        })
        .collect()
}

/// Each polygon of `tree` (from `mesh`'s triangles) smooth-shaded: its material colour and its
/// vertices' 8-bit intensities, `[front, back]` of its source triangle.
pub(crate) fn polygon_shades(
    tree: &DisplayTree,
    mesh: &Mesh,
    smooth: &Smooth,
) -> Vec<crate::write::shades::PolygonShades> {
    let shades = smooth.shade(mesh);
    tree.polygons
        .par_iter()
        .map(|p| {
            // The interior side is the triangle's front when `interior_front != flipped`.
            let front_inside = p.interior_front != p.flipped;
            crate::write::shades::PolygonShades {
                kd: mesh.triangles[p.source as usize].colour,
                vertices: shades
                    .polygon(tree, p)
                    .into_iter()
                    .map(|v| {
                        let [inside, outside] = v.quantised();
                        if front_inside {
                            [inside, outside]
                        } else {
                            [outside, inside]
                        }
                    })
                    .collect(),
            }
        })
        .collect()
}

/// The colours of each polygon of `tree` (from `mesh`'s triangles): of its interior side and
/// of its exterior side ([`Shading::sides`], or [`Shading::in_shadow`] for a polygon in
/// shadow).
pub(crate) fn bake(
    tree: &DisplayTree,
    mesh: &Mesh,
    shading: &Shading,
) -> (Vec<[u8; 3]>, Vec<[u8; 3]>) {
    tree.polygons
        .par_iter()
        .map(|p| {
            let kd = mesh.triangles[p.source as usize].colour;
            let normal = tree.planes[p.plane as usize].normal;
            let sides = if p.shadowed {
                shading.in_shadow(kd)
            } else {
                let sum: DVec3 = p.vertices.iter().map(|&v| tree.vertices[v as usize]).sum();
                let centroid = tree.centre + sum / p.vertices.len().max(1) as f64;
                shading.sides(kd, normal, p.interior_front, centroid)
            };
            (sides.interior, sides.exterior)
        })
        .unzip()
}

/// Load and compile an OBJ file (nothing is written).
pub fn compile_obj(
    path: &Path,
    options: &CompileOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Compiled, CompileError> {
    let start = Instant::now();
    compile_obj_bytes(path, read_obj(path)?, options, progress, start)
}

/// [`compile_obj`] for OBJ bytes read already ([`read_obj`]); `path` names the file and
/// locates its MTL files. `start` is when the compile began (for [`Compiled::seconds`]).
///
/// A file whose faces are all degenerate is an error ([`CompileError::AllDegenerate`]): its
/// scene would be empty.
pub fn compile_obj_bytes(
    path: &Path,
    bytes: Vec<u8>,
    options: &CompileOptions,
    progress: &(dyn Fn(u64) + Sync),
    start: Instant,
) -> Result<Compiled, CompileError> {
    // Before the load: a light that cannot shade is refused at once.
    options.shading.check()?;
    let mesh = load_obj_bytes(path, bytes, &options.load)?;
    // On a pool thread, the encoding reuses the memory the build's threads have freed (each
    // thread allocates from its own arena): fewer fresh pages, so fewer page faults
    // (BENCHMARKS.md, "Tuning constants").
    let (tree, bytes) = rayon::scope(|_| compile_mesh(&mesh, options, progress))?;
    if tree.polygons.is_empty() {
        return Err(CompileError::AllDegenerate {
            path: path.to_path_buf(),
            faces: mesh.faces,
        });
    }
    Ok(Compiled {
        bytes,
        stats: tree.stats,
        seconds: start.elapsed().as_secs_f64(),
        warnings: mesh.warnings,
        files: mesh.files,
        missing: mesh.missing,
        mtl_bytes: mesh.mtl_bytes,
    })
}

/// A scene of parts compiled ([`compile_parts`]).
#[derive(Debug, Clone)]
pub struct CompiledParts {
    /// The file: a file of parts ([`crate::write::parts`]), or the world's tree file alone,
    /// byte for byte what [`compile_obj`] gives, when there is no object.
    pub bytes: Vec<u8>,
    /// Each part's name (empty for the world) and compile, in file order: the world first.
    pub parts: Vec<(String, Compiled)>,
    /// Wall time of the whole compile, in seconds.
    pub seconds: f64,
}

/// Load and compile a scene of parts: `world` (optional) and `objects` (name and OBJ file
/// each), every part in its own frame with `options`. With [`CompileOptions::ids`] the ids
/// number the world's source triangles first, then each object's in the order given
/// (offset by the source triangles of the parts before it). The names are checked
/// ([`crate::write::parts::check_parts`]) before any file is read.
pub fn compile_parts(
    world: Option<&Path>,
    objects: &[(String, PathBuf)],
    options: &CompileOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<CompiledParts, CompileError> {
    let start = Instant::now();
    let names: Vec<&str> = objects.iter().map(|(n, _)| n.as_str()).collect();
    crate::write::parts::check_parts(world.is_some(), &names)?;
    let world = world
        .map(|w| Ok::<_, CompileError>((w, read_obj(w)?)))
        .transpose()?;
    let objects = (objects.iter())
        .map(|(name, path)| Ok((name.clone(), path.as_path(), read_obj(path)?)))
        .collect::<Result<Vec<_>, CompileError>>()?;
    compile_parts_bytes(world, objects, options, progress, start)
}

/// [`compile_parts`] for OBJ bytes read already ([`read_obj`]): the world's path and bytes,
/// and each object's name, path and bytes. `start` is when the compile began.
pub fn compile_parts_bytes(
    world: Option<(&Path, Vec<u8>)>,
    objects: Vec<(String, &Path, Vec<u8>)>,
    options: &CompileOptions,
    progress: &(dyn Fn(u64) + Sync),
    start: Instant,
) -> Result<CompiledParts, CompileError> {
    let names: Vec<&str> = objects.iter().map(|(n, _, _)| n.as_str()).collect();
    crate::write::parts::check_parts(world.is_some(), &names)?;
    let has_objects = !objects.is_empty();
    let sources = (world
        .map(|(path, bytes)| (String::new(), path, bytes))
        .into_iter())
    .chain(objects);
    let mut parts: Vec<(String, Compiled)> = Vec::new();
    let mut part_options = options.clone();
    for (name, path, bytes) in sources {
        let compiled = compile_obj_bytes(path, bytes, &part_options, progress, Instant::now())?;
        part_options.id_offset = u32::try_from(compiled.stats.input_triangles)
            .ok()
            .and_then(|n| part_options.id_offset.checked_add(n))
            .ok_or_else(|| CompileError::TooLarge {
                path: path.to_path_buf(),
                message: "the parts hold more source triangles than 32-bit ids number".into(),
            })?;
        parts.push((name, compiled));
    }
    let bytes = match (has_objects, parts.first()) {
        (false, Some((_, world))) => world.bytes.clone(),
        _ => {
            let world = parts.first().filter(|(n, _)| n.is_empty());
            let objects: Vec<(String, Vec<u8>)> = (parts.iter())
                .skip(usize::from(world.is_some()))
                .map(|(n, c)| (n.clone(), c.bytes.clone()))
                .collect();
            crate::write::parts::parts_file(world.map(|(_, c)| c.bytes.as_slice()), &objects)?
        }
    };
    Ok(CompiledParts {
        bytes,
        parts,
        seconds: start.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixture(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../fixtures")
            .join(name)
    }

    #[test]
    fn a_file_whose_faces_are_all_degenerate_is_an_error_naming_it() {
        let path = fixture("bad/all_degenerate.obj");
        let e = compile_obj(&path, &CompileOptions::default(), &|_| {}).unwrap_err();
        assert!(
            matches!(e, CompileError::AllDegenerate { faces: 3, .. }),
            "{e:?}"
        );
        let shown = e.to_string();
        assert!(
            shown.contains("all_degenerate.obj: all 3 faces are degenerate")
                && shown.contains("nothing to draw"),
            "{shown}"
        );
        // One face left with an area: it compiles, the others dropped.
        let text = std::fs::read_to_string(&path).unwrap() + "f 1 2 4\n";
        let compiled = compile_obj_bytes(
            &path,
            text.into_bytes(),
            &CompileOptions::default(),
            &|_| {},
            Instant::now(),
        )
        .unwrap();
        assert_eq!(compiled.stats.output_polygons, 1);
        assert_eq!(compiled.stats.degenerate_dropped, 3);
    }

    /// A torus and a box beside a loose soup: with `solid` the torus's and the box's polygons
    /// carry the side their solid's inside is on (its source triangle's back), the soup's
    /// none; without it, or with no closed part, the file is what it was.
    #[test]
    fn solid_marks_the_faces_of_closed_parts_only() {
        use crate::tools::scenes;
        use peel_runtime::read::layout::header_flags::SOLID;
        use peel_runtime::read::Scene;
        let mut triangles: Vec<[DVec3; 3]> = (scenes::torus(12, 6).triangles.iter())
            .map(|t| t.vertices)
            .collect();
        let closed = triangles.len() + 12;
        scenes::boxed(&mut triangles, DVec3::splat(1.5), DVec3::splat(2.0));
        triangles.extend(
            scenes::soup(20, 0.3, 7)
                .triangles
                .iter()
                .map(|t| t.vertices),
        );
        let mesh = scenes::mesh(triangles);
        let compile = |solid: bool, mesh: &Mesh| {
            let options = CompileOptions {
                ids: true,
                solid,
                ..CompileOptions::default()
            };
            compile_mesh(mesh, &options, &|_| {}).unwrap().1
        };
        let bytes = compile(true, &mesh);
        let scene = Scene::parse(&bytes).unwrap();
        assert_ne!(scene.header().flags & SOLID, 0);
        let inside = polygon_flags::INSIDE_INTERIOR | polygon_flags::INSIDE_EXTERIOR;
        for i in 0..scene.header().polygon_count {
            let p = scene.polygon(i);
            let source = scene.id(i).unwrap() as usize;
            let mark = p.flags & inside;
            assert_eq!(
                mark != 0,
                source < closed,
                "polygon {i} of triangle {source}"
            );
            if mark != 0 {
                // The source triangle's front faces out: seen from the side of its normal, the
                // eye sees the side the mark does not name.
                let t = mesh.triangles[source].vertices;
                let normal = (t[1] - t[0]).cross(t[2] - t[0]);
                let centre = DVec3::from_array(scene.header().centre);
                let outside = (t[0] + t[1] + t[2]) / 3.0 + normal - centre;
                let side = scene.eye_side(&p, &scene.side_eye(outside.as_vec3()));
                let seen_interior = peel_runtime::traverse::sees_interior(&p, side);
                let hidden = if seen_interior {
                    polygon_flags::INSIDE_INTERIOR
                } else {
                    polygon_flags::INSIDE_EXTERIOR
                };
                assert_eq!(mark & hidden, 0, "polygon {i} of triangle {source}");
            }
        }
        assert_ne!(bytes, compile(false, &mesh));
        let soup = scenes::soup(40, 0.3, 3);
        assert_eq!(compile(true, &soup), compile(false, &soup));
    }

    /// Without objects the file is the world's tree, byte for byte; with them, each part is
    /// that file compiled alone, the objects' ids following the triangles before them.
    #[test]
    fn parts_are_their_files_compiled_alone_with_ids_following_on() {
        use crate::write::parts::read_parts;
        use peel_runtime::read::Scene;
        let options = CompileOptions {
            ids: true,
            solid: true,
            ..CompileOptions::default()
        };
        let alone = |name: &str| compile_obj(&fixture(name), &options, &|_| {}).unwrap();
        let world = fixture("cube.obj");
        let plain = compile_parts(Some(&world), &[], &options, &|_| {}).unwrap();
        assert_eq!(plain.bytes, alone("cube.obj").bytes);
        assert_eq!(plain.parts.len(), 1);

        let objects = [
            ("stairs".to_string(), fixture("staircase.obj")),
            ("nest".to_string(), fixture("nested_cubes.obj")),
        ];
        let scene = compile_parts(Some(&world), &objects, &options, &|_| {}).unwrap();
        let parts = read_parts(&scene.bytes).unwrap();
        let names: Vec<&str> = parts.iter().map(|p| p.name).collect();
        assert_eq!(names, ["", "stairs", "nest"]);
        let mut before = 0u32;
        for (part, file) in parts
            .iter()
            .zip(["cube.obj", "staircase.obj", "nested_cubes.obj"])
        {
            let own = alone(file);
            let (mine, theirs) = (
                Scene::parse(part.tree).unwrap(),
                Scene::parse(&own.bytes).unwrap(),
            );
            assert_eq!(mine.header(), theirs.header(), "{file}");
            let count = mine.header().polygon_count;
            assert!(count > 0);
            for i in 0..count {
                assert_eq!(
                    mine.id(i).unwrap(),
                    theirs.id(i).unwrap() + before,
                    "{file}"
                );
            }
            before += own.stats.input_triangles as u32;
        }
        // The offset is the ids' only change.
        let no_ids = CompileOptions {
            ids: false,
            ..options.clone()
        };
        let scene = compile_parts(None, &objects[..1], &no_ids, &|_| {}).unwrap();
        let part = read_parts(&scene.bytes).unwrap()[0].tree;
        assert_eq!(
            part,
            compile_obj(&fixture("staircase.obj"), &no_ids, &|_| {})
                .unwrap()
                .bytes
        );
    }

    #[test]
    fn a_bad_name_is_refused_before_any_file_is_read() {
        let absent = fixture("absent.obj");
        let objects = [("a".to_string(), absent.clone()), ("a".to_string(), absent)];
        let e = compile_parts(None, &objects, &CompileOptions::default(), &|_| {}).unwrap_err();
        assert!(matches!(e, CompileError::PartName { .. }), "{e:?}");
        let e = compile_parts(None, &[], &CompileOptions::default(), &|_| {}).unwrap_err();
        assert!(
            matches!(e, CompileError::PartCount { parts: 0, .. }),
            "{e:?}"
        );
    }

    /// A mesh made in code is held to the file's limit too: texture indices are bytes.
    #[test]
    fn a_mesh_of_more_textures_than_a_file_holds_is_refused() {
        let mut mesh = crate::tools::scenes::textured(crate::tools::scenes::box_grid(1), 0, |_| {
            [glam::DVec2::ZERO; 3]
        });
        let one = mesh.textures[0].clone();
        mesh.textures = vec![one; MAX_TEXTURES as usize + 1];
        let e = compile_mesh(&mesh, &CompileOptions::default(), &|_| {}).unwrap_err();
        assert!(
            matches!(e, CompileError::TooManyTextures { count: 256, .. }),
            "{e:?}"
        );
        mesh.textures.pop();
        assert!(compile_mesh(&mesh, &CompileOptions::default(), &|_| {}).is_ok());
    }

    #[test]
    fn a_light_without_direction_is_refused_before_the_load() {
        let options = CompileOptions {
            shading: Shading::Lambert(DVec3::ZERO),
            ..CompileOptions::default()
        };
        // No bytes would be `NoFaces`: the light is refused first.
        let e = compile_obj_bytes(
            &fixture("absent.obj"),
            Vec::new(),
            &options,
            &|_| {},
            Instant::now(),
        )
        .unwrap_err();
        assert!(matches!(e, CompileError::Light(_)), "{e:?}");
        let mesh = crate::tools::scenes::box_grid(1);
        let e = compile_mesh(&mesh, &options, &|_| {}).unwrap_err();
        assert!(e.to_string().contains("has no length"), "{e}");
    }
}
