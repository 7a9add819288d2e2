//! The benchmark's scenes: which OBJ files (the demo, the shared models or generated stand-ins
//! of similar size), compiled with `peel compile` at its default settings, and for the z-buffer
//! the same source triangles as an indexed mesh with the colours the compiler baked.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::{load_obj, Mesh};
use peel_compiler::shade::normals::{corner_normals, Crease};
use peel_compiler::shade::Surface;
use peel_compiler::tools::scenes;
use peel_runtime::display::Colour;
use peel_runtime::read::Scene;

use crate::tools::Tools;

/// A scene to benchmark.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneSpec {
    /// The name in the records.
    pub name: String,
    /// Its OBJ file.
    pub obj: PathBuf,
}

/// The shared models, and the generated mesh standing in for each when it is absent: grids
/// of closed boxes with about as many triangles (suzanne 968: 768; teapot 6,320 and cow
/// 5,804: 6,144). Spheres and tori of those sizes compile to trees 151 to 1,346 deep, more
/// than the firmware's traversal stack ([`peel_target_kit::STACK`]); these are about 20.
type Generator = fn() -> Mesh;
const MODELS: [(&str, Generator); 3] = [
    ("suzanne", || scenes::box_grid(4)),
    ("teapot", || scenes::box_grid(8)),
    ("cow", || scenes::box_grid(8)),
];

/// The scenes: the demo, then (unless `quick`) each model from `models`, or its generated
/// stand-in written as an OBJ file into `dir`.
pub fn list(root: &Path, models: &Path, quick: bool, dir: &Path) -> Result<Vec<SceneSpec>, String> {
    let mut list = vec![SceneSpec {
        name: "demo".into(),
        obj: root.join("fixtures/demo.obj"),
    }];
    if quick {
        return Ok(list);
    }
    for (name, _) in MODELS {
        let (obj, generated) = model(name, models, dir)?;
        list.push(SceneSpec {
            name: if generated {
                format!("{name} (generated)")
            } else {
                name.into()
            },
            obj,
        });
    }
    Ok(list)
}

/// The OBJ file of the shared model `name` (one of [`MODELS`]) from `models`, or when it is
/// absent its generated stand-in written into `dir` (`true`: generated).
pub fn model(name: &str, models: &Path, dir: &Path) -> Result<(PathBuf, bool), String> {
    let model = models.join(format!("{name}.obj"));
    if model.is_file() {
        return Ok((model, false));
    }
    let (_, generate) = MODELS
        .iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| format!("{name}: not a shared model"))?;
    println!(
        "{}: absent, a generated mesh of similar size stands in",
        model.display()
    );
    let obj = dir.join(format!("{name}-generated.obj"));
    write_obj(&generate(), &obj)?;
    Ok((obj, true))
}

/// `mesh` as an OBJ file (shared corners merged; coordinates printed exactly).
fn write_obj(mesh: &Mesh, path: &Path) -> Result<(), String> {
    let mut index: HashMap<[u64; 3], usize> = HashMap::new();
    let (mut vertices, mut faces) = (String::new(), String::new());
    for t in &mesh.triangles {
        let ids = t.vertices.map(|v| {
            let n = index.len();
            *index
                .entry(v.to_array().map(f64::to_bits))
                .or_insert_with(|| {
                    let _ = writeln!(vertices, "v {} {} {}", v.x, v.y, v.z);
                    n
                })
                + 1
        });
        let _ = writeln!(faces, "f {} {} {}", ids[0], ids[1], ids[2]);
    }
    std::fs::write(path, vertices + &faces)
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// A compiled scene.
#[derive(Debug, Clone)]
pub struct Compiled {
    /// The scene.
    pub spec: SceneSpec,
    /// The `.peel` file.
    pub peel: PathBuf,
    /// Its bytes.
    pub peel_bytes: Vec<u8>,
    /// The z-buffer's mesh file ([`peel_target_kit::mesh`]).
    pub mesh: PathBuf,
    /// Its bytes.
    pub mesh_bytes: Vec<u8>,
    /// The mesh with ids for colours ([`peel_target_kit::mesh::with_ids`]), for id images.
    pub ids_mesh_bytes: Vec<u8>,
    /// embedded-3dgfx's asset ([`peel_target_kit::gfx3d`]): the same mesh, scaled, with face
    /// normals, and for a smooth scene vertex normals (its corners' as the compiler shades
    /// them).
    pub gfx3d: PathBuf,
    /// Its bytes.
    pub gfx3d_bytes: Vec<u8>,
    /// Source triangles (`input_triangles` of `peel compile --stats-json`).
    pub triangles: u64,
    /// Compiled with the default sun's shadows (`--shadows`).
    pub shadows: bool,
    /// Compiled smooth (`--shading smooth`, the default crease).
    pub smooth: bool,
    /// A textured file (format 6, from an OBJ with `vt` and an MTL with `map_Kd`).
    pub textured: bool,
    /// Objects the frames pose (a file of parts, [`crate::objects`]); 0 for a plain scene.
    pub objects: u64,
    /// Its records are of the transparent scene (`"transparent": true`): set by the runner
    /// that compiles it ([`crate::transparent`]), which checks the file has transparent
    /// polygons.
    pub transparent: bool,
}

impl Compiled {
    /// The records' `shading`.
    pub fn shading(&self) -> &'static str {
        use peel_target_runner::results::{FLAT, SMOOTH, TEXTURED};
        match (self.textured, self.smooth) {
            (true, _) => TEXTURED,
            (false, true) => SMOOTH,
            (false, false) => FLAT,
        }
    }
}

/// Compile `spec` into `dir` with `peel compile --solid --shading faceted`, or smooth with a crease
/// in degrees (`--shading smooth --crease DEG`), and export its mesh.
pub fn compile(
    tools: &Tools,
    spec: &SceneSpec,
    shadows: bool,
    crease: Option<f64>,
    dir: &Path,
) -> Result<Compiled, String> {
    let smooth = crease.is_some();
    let mut stem = spec.name.replace(" (generated)", "-generated");
    if smooth {
        stem.push_str("-smooth");
    }
    let peel = dir.join(format!("{stem}.peel"));
    let stats = dir.join(format!("{stem}.json"));
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "compile".as_ref(),
        spec.obj.as_os_str(),
        "-o".as_ref(),
        peel.as_os_str(),
        "--stats-json".as_ref(),
        stats.as_os_str(),
        // Faces of closed parts seen from behind are skipped, as every peer here skips back
        // faces; open parts (the teapot's) stay two-sided.
        "--solid".as_ref(),
    ];
    if shadows {
        args.push("--shadows".as_ref());
    }
    let crease_arg = crease.map(|c| c.to_string());
    if let Some(c) = &crease_arg {
        args.extend::<[&std::ffi::OsStr; 4]>([
            "--shading".as_ref(),
            "smooth".as_ref(),
            "--crease".as_ref(),
            c.as_ref(),
        ]);
    } else {
        args.extend::<[&std::ffi::OsStr; 2]>(["--shading".as_ref(), "faceted".as_ref()]);
    }
    tools.peel(&args)?;
    let read =
        |p: &Path| std::fs::read(p).map_err(|e| format!("{}: cannot read: {e}", p.display()));
    let peel_bytes = read(&peel)?;
    let json: serde_json::Value =
        serde_json::from_slice(&read(&stats)?).map_err(|e| format!("{}: {e}", stats.display()))?;
    let triangles = json["input_triangles"]
        .as_u64()
        .ok_or_else(|| format!("{}: no input_triangles", stats.display()))?;
    let mesh_bytes = export_mesh(&spec.obj, &peel_bytes, &options(shadows, crease)?)?;
    let ids_mesh_bytes = peel_target_kit::mesh::with_ids(&mesh_bytes).ok_or_else(|| {
        format!(
            "{}: an id image holds fewer than 65,535 triangles",
            spec.obj.display()
        )
    })?;
    let textured = Scene::parse(&peel_bytes)
        .map_err(|e| format!("{}: {e}", peel.display()))?
        .has_textures();
    let gfx3d_bytes = {
        let parsed = peel_target_kit::mesh::Mesh::parse(&mesh_bytes)
            .map_err(|e| format!("{}: {e}", spec.obj.display()))?;
        let encoded = if textured {
            let (corners, colours, textures) = gfx3d_textures(&spec.obj, &peel_bytes)?;
            peel_target_kit::gfx3d::encode_textured(&parsed, &corners, &colours, &textures)
        } else if let Some(crease) = crease {
            let corners = gfx3d_corner_normals(&spec.obj, crease)?;
            peel_target_kit::gfx3d::encode_smooth(&parsed, &corners)
        } else {
            peel_target_kit::gfx3d::encode(&parsed)
        };
        encoded.ok_or_else(|| {
            format!(
                "{}: too large for embedded-3dgfx's asset",
                spec.obj.display()
            )
        })?
    };
    let mesh = dir.join(format!("{stem}.mesh"));
    let gfx3d = dir.join(format!("{stem}.gfx3d"));
    for (path, bytes) in [(&mesh, &mesh_bytes), (&gfx3d, &gfx3d_bytes)] {
        std::fs::write(path, bytes)
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    }
    Ok(Compiled {
        spec: spec.clone(),
        peel,
        peel_bytes,
        mesh,
        mesh_bytes,
        ids_mesh_bytes,
        gfx3d,
        gfx3d_bytes,
        triangles,
        shadows,
        smooth,
        textured,
        objects: 0,
        transparent: false,
    })
}

/// `peel compile`'s options, with `--shadows` or not (the default sun's shadows baked),
/// `--shading smooth --crease DEG` or `--shading faceted`.
pub fn options(shadows: bool, crease: Option<f64>) -> Result<CompileOptions, String> {
    let mut options = CompileOptions {
        surface: Surface::Faceted,
        solid: true,
        ..CompileOptions::default()
    };
    if shadows {
        options.build.shadows = options.shading.light();
    }
    if let Some(deg) = crease {
        options.surface = Surface::Smooth(crease_of(deg)?);
    }
    Ok(options)
}

fn crease_of(deg: f64) -> Result<Crease, String> {
    Crease::new(deg).map_err(|e| format!("crease {deg}: {e}"))
}

/// The unit normal of each corner of each triangle of `obj`, as the compiler shades a smooth
/// file with the crease `crease` in degrees ([`corner_normals`]), for embedded-3dgfx's Gouraud mode.
fn gfx3d_corner_normals(obj: &Path, crease: f64) -> Result<Vec<[[f32; 3]; 3]>, String> {
    let mesh = load_obj(obj).map_err(|e| format!("{}: {e}", obj.display()))?;
    Ok(corner_normals(&mesh.triangles, crease_of(crease)?)
        .into_iter()
        .map(|c| c.map(|n| n.as_vec3().to_array()))
        .collect())
}

/// embedded-3dgfx's textures of the textured `obj` compiled into `peel_bytes`: each source
/// triangle's texture and corners' coordinates (`None` untextured; `(u, 1 - v)` of the OBJ's
/// `vt`, the library's `v` running down the image), its material's colour in RGB565 (which
/// the library lights), and the file's textures. A triangle's texture is the file's with the
/// very texels of the mesh's (found by content: the writer may order them otherwise).
#[allow(clippy::type_complexity)]
fn gfx3d_textures<'a>(
    obj: &Path,
    peel_bytes: &'a [u8],
) -> Result<
    (
        Vec<Option<peel_target_kit::gfx3d::CornerTexture>>,
        Vec<u16>,
        Vec<peel_runtime::read::Texture<'a>>,
    ),
    String,
> {
    let fail = |e: String| format!("{}: {e}", obj.display());
    let mesh = load_obj(obj).map_err(|e| fail(e.to_string()))?;
    let scene = Scene::parse(peel_bytes).map_err(|e| fail(format!("its .peel file: {e}")))?;
    let textures: Vec<_> = (0..scene.texture_count())
        .filter_map(|k| scene.texture(k))
        .collect();
    let in_file = mesh
        .textures
        .iter()
        .map(|t| {
            textures
                .iter()
                .position(|f| {
                    (f.log2_width, f.log2_height) == (t.log2_width, t.log2_height)
                        && (0..t.height())
                            .all(|r| (0..t.width()).all(|c| f.texel(c, r) == t.texel(c, r)))
                })
                .map(|k| k as u32)
                .ok_or_else(|| fail(format!("{}: not in its .peel file", t.path.display())))
        })
        .collect::<Result<Vec<u32>, String>>()?;
    let corners = mesh
        .triangles
        .iter()
        .map(|t| {
            let c = t.texture?;
            Some(peel_target_kit::gfx3d::CornerTexture {
                texture: in_file[c.texture as usize],
                uv: c.uv.map(|uv| [uv.x as f32, (1.0 - uv.y) as f32]),
            })
        })
        .collect();
    let colours = (mesh.triangles.iter())
        .map(|t| {
            let [r, g, b] = t.colour;
            Colour::new(r, g, b).to_rgb565()
        })
        .collect();
    Ok((corners, colours, textures))
}

/// The source triangles of `obj` as the z-buffer's mesh, framed by the header of its `.peel`
/// file `peel_bytes`: vertices relative to its centre in `f32` (as the `.peel` file stores
/// them), each triangle in the colour the compiler baked into its polygons. The colours come
/// from compiling the OBJ again with the library (the same `options`), which must give the
/// very bytes `peel compile` wrote.
pub fn export_mesh(
    obj: &Path,
    peel_bytes: &[u8],
    options: &CompileOptions,
) -> Result<Vec<u8>, String> {
    let fail = |e: String| format!("{}: {e}", obj.display());
    let mesh = load_obj(obj).map_err(|e| fail(e.to_string()))?;
    let (tree, bytes) = compile_mesh(&mesh, options, &|_| {}).map_err(|e| fail(e.to_string()))?;
    if bytes != peel_bytes {
        return Err(fail(
            "compiling it with the library does not give the bytes `peel compile` wrote".into(),
        ));
    }
    let mut baked: Vec<Option<[u8; 3]>> = vec![None; mesh.triangles.len()];
    for p in &tree.polygons {
        let kd = mesh.triangles[p.source as usize].colour;
        baked[p.source as usize] = Some(
            options
                .shading
                .shade(kd, tree.planes[p.plane as usize].normal),
        );
    }
    let header = Scene::parse(peel_bytes)
        .map_err(|e| fail(format!("its .peel file: {e}")))?
        .header();
    let centre = DVec3::from_array(header.centre);
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    let mut vertices: Vec<Vec3> = Vec::new();
    let triangles: Vec<([u32; 3], u16)> = mesh
        .triangles
        .iter()
        .zip(&baked)
        .map(|(t, baked)| {
            let corners = t.vertices.map(|p| {
                let q = (p - centre).as_vec3();
                *index
                    .entry(q.to_array().map(f32::to_bits))
                    .or_insert_with(|| {
                        vertices.push(q);
                        (vertices.len() - 1) as u32
                    })
            });
            // A triangle the compiler dropped (degenerate) draws nothing; shade it anyway.
            let [a, b, c] = t.vertices;
            let normal = (b - a).cross(c - a).normalize_or_zero();
            let [r, g, b] = baked.unwrap_or_else(|| options.shading.shade(t.colour, normal));
            (corners, Colour::new(r, g, b).to_rgb565())
        })
        .collect();
    peel_target_kit::mesh::encode(&header, &vertices, &triangles).ok_or_else(|| {
        fail(format!(
            "{} vertices: the mesh format holds 65536",
            vertices.len()
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_obj_files_load_back_exactly() {
        let dir = std::env::temp_dir().join(format!("peel-target-scenes-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("sphere.obj");
        let mesh = scenes::sphere(5, 6);
        write_obj(&mesh, &path).unwrap();
        let back = load_obj(&path).unwrap();
        let corners = |m: &Mesh| m.triangles.iter().map(|t| t.vertices).collect::<Vec<_>>();
        assert_eq!(corners(&back), corners(&mesh));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn stand_ins_are_of_similar_size() {
        for ((name, generate), real) in MODELS.iter().zip([968usize, 6320, 5804]) {
            let n = generate().triangles.len();
            // Within a quarter: grids of boxes come in sizes of 12 k^3 triangles.
            assert!(
                n.abs_diff(real) * 4 <= real,
                "{name}: {n} triangles for {real}"
            );
        }
    }
}
