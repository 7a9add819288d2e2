//! Load: OBJ + MTL -> source triangles, with validation.
//!
//! `load_obj(path)` returns a [`Mesh`] whose triangle `i` is source triangle id `i` (ids follow
//! the order of the `f` lines; a polygon face contributes its triangles in the documented
//! order).
//!
//! How a file is read:
//! - The OBJ text is parsed by `tobj` with its triangulation off, after a light line check
//!   (`lines`) that validates what tobj does not (NaN/inf coordinates, index ranges, syntax)
//!   and reports the line. tobj groups faces into models (a new one at each `o`, `g` or
//!   material change) but keeps them in file order; the loader pairs each tobj face with its
//!   checked `f`/`l` line and fails with [`CompileError::Invariant`] if the two disagree, so
//!   source ids always follow the `f` lines.
//! - A face's colour is its material's diffuse `Kd`, clamped to [0, 1] and rounded to RGB888.
//!   A face without material, with an undefined material, with a material without `Kd`, or
//!   whose MTL file is missing gets [`DEFAULT_COLOUR`] (or [`LoadOptions::default_colour`])
//!   and a warning. Faces without any material give none where that is meant: in a file
//!   without `mtllib` and `usemtl` statements (a plain mesh), or with
//!   [`LoadOptions::default_colour`] set.
//! - A triangle face gives one triangle, its corners in file order. A face with more corners is
//!   triangulated in its own plane (`triangulate`): every triangle is written starting at
//!   its smallest corner index in the face, keeping the face's winding, and the triangles of
//!   the face are sorted by these index triples. Consecutive repeated corners are merged first
//!   (so a face can give fewer than n - 2 triangles). A polygon that is not simple (repeated
//!   vertex, crossing edges) gets a warning and the fan `[0, i, i + 1]` from its first corner;
//!   a collinear one gets the same fan silently (all zero-area, dropped later).
//! - `f` lines with fewer than three corners are skipped with a warning; `l` (polyline)
//!   statements are not surfaces and are skipped with a warning. A file that ends without a
//!   line end in the middle of a face (fewer than three corners, or a last corner cut short)
//!   is cut off: an error at that line.
//! - A face of a material with a texture (`map_Kd`, its options read by `mtl`) whose every corner
//!   names texture coordinates (`v/vt`, `v/vt/vn`) is textured ([`SourceTriangle::texture`]; a
//!   polygon's triangles take those of their corners); its colour is the material's `Kd`, or
//!   white without one (the texture as it is). Each image is read at the first face that uses
//!   it (`decode`: PNG or JPEG with the `textures` feature, brought to power-of-two sides) and
//!   joins [`Mesh::files`]. Faces of such a material without coordinates at every corner
//!   show its colour alone, with a warning.
//! - A face whose every corner names a normal (`v//vn`, `v/vt/vn`) keeps them, normalised, on
//!   its triangles' corners ([`SourceTriangle::normals`]; a polygon's triangles take those of
//!   their corners). A face that names them for some corners only, or whose normals are not
//!   finite or of no length, keeps none: smooth shading computes them.
//! - Degenerate triangles are kept: the compiler drops zero-area triangles after quantisation.
//! - Limits: the OBJ (and each MTL) may not exceed [`MAX_INPUT_BYTES`], the file may not have
//!   more than [`MAX_VERTEX_STATEMENTS`] `v`/`vt`/`vn` statements nor produce more than
//!   [`MAX_TRIANGLES`] triangles; otherwise [`CompileError::TooLarge`].

mod decode;
mod lines;
mod mtl;
pub mod texture;
mod triangulate;
mod warnings;

use glam::DVec3;
use std::cell::RefCell;
use std::path::{Path, PathBuf};

use crate::error::CompileError;
use warnings::{Notes, Tally};

/// Colour used for faces without a material (or when the MTL file is missing): mid grey.
pub const DEFAULT_COLOUR: [u8; 3] = [200, 200, 200];

/// Largest OBJ or MTL file accepted, in bytes (256 MiB).
pub const MAX_INPUT_BYTES: u64 = 256 << 20;

/// Largest number of `v`, `vt` and `vn` statements together in one OBJ.
pub const MAX_VERTEX_STATEMENTS: usize = 1 << 22;

/// Largest number of triangles (a polygon of n corners counts n - 2; every `l` statement and
/// every face with fewer than three corners counts one, as they cost memory too).
pub const MAX_TRIANGLES: usize = 1 << 22;

/// One input triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SourceTriangle {
    /// Corners in file order (the winding gives the front side).
    pub vertices: [DVec3; 3],
    /// Material diffuse colour (`Kd`), RGB888.
    pub colour: [u8; 3],
    /// The file's normals at the corners (`vn`, unit length), in the order of `vertices`;
    /// `None` where the face gives none, and smooth shading computes them
    /// ([`crate::shade::normals`]).
    pub normals: Option<[DVec3; 3]>,
    /// The texture and the corners' texture coordinates, where the material has a `map_Kd`
    /// and the face gives `vt` at every corner; else `None`.
    pub texture: Option<texture::CornerUvs>,
    /// Its material's opacity (MTL `d`, or `1 - Tr`), of 255: [`OPAQUE`] for an opaque one
    /// (no `d` or `Tr`, or no material), below it for a transparent one.
    pub opacity: u8,
}

/// The opacity of an opaque triangle ([`SourceTriangle::opacity`]).
pub const OPAQUE: u8 = u8::MAX;

/// The default largest side of a texture, in texels ([`LoadOptions::max_texture`]).
pub const DEFAULT_MAX_TEXTURE: u32 = 256;

/// How a file is loaded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LoadOptions {
    /// The colour of faces whose colour the files do not give (no material, an undefined
    /// material, a material without `Kd`, a missing MTL file); `None` is [`DEFAULT_COLOUR`].
    /// When set, faces without any material (no `usemtl` before them) are taken as meant:
    /// they give no warning (nor do they in a file that names no material at all). The other
    /// cases still warn (they are mistakes in the files).
    pub default_colour: Option<[u8; 3]>,
    /// The largest side of a stored texture, in texels: a power of two from 1 to 1024
    /// (`2^MAX_TEXTURE_LOG2`), [`DEFAULT_MAX_TEXTURE`] by default. A texture costs its target
    /// two bytes a texel (one with a palette), in flash.
    pub max_texture: u32,
    /// Resample a texture whose side is not a power of two, or is larger than
    /// [`LoadOptions::max_texture`], to the nearest power of two within the limit (Lanczos);
    /// without it such a texture is an error ([`CompileError::TextureSize`]).
    pub resample: bool,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            default_colour: None,
            max_texture: DEFAULT_MAX_TEXTURE,
            resample: true,
        }
    }
}

impl LoadOptions {
    /// Refuses a [`LoadOptions::max_texture`] that is not a power of two from 1 to 1024
    /// ([`CompileError::MaxTexture`]).
    pub fn check(&self) -> Result<(), CompileError> {
        let largest = 1u32 << peel_runtime::read::layout::MAX_TEXTURE_LOG2;
        if !self.max_texture.is_power_of_two() || self.max_texture > largest {
            return Err(CompileError::MaxTexture {
                max: self.max_texture,
                largest,
            });
        }
        Ok(())
    }
}

/// A loaded scene.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Triangles; the index is the source triangle id.
    pub triangles: Vec<SourceTriangle>,
    /// The faces the triangles come from (`f` lines of three corners or more), for messages;
    /// 0 for a mesh not read from a file.
    pub faces: usize,
    /// Non-fatal problems (missing MTL, face without material, ...), already worded for people.
    pub warnings: Vec<String>,
    /// Every file read (the OBJ, its MTL files and the texture images its faces use), for
    /// `cargo:rerun-if-changed`.
    pub files: Vec<PathBuf>,
    /// The bytes of each MTL file and texture image read, as the loader parsed them, in the
    /// order of `files` (a build cache keys on exactly what was compiled). A file that could
    /// not be read has no entry.
    pub mtl_bytes: Vec<(PathBuf, Vec<u8>)>,
    /// MTL files the OBJ names but that do not exist: a build script watches these paths'
    /// folders (a missing file itself would make cargo rerun it on every build), so adding
    /// the file triggers a rebuild.
    pub missing: Vec<PathBuf>,
    /// The textures the triangles name ([`SourceTriangle::texture`]), each read once.
    pub textures: Vec<texture::Texture>,
}

/// Load an OBJ file (and its MTL files).
pub fn load_obj(path: &Path) -> Result<Mesh, CompileError> {
    load_obj_with(path, &LoadOptions::default())
}

/// [`load_obj`] with options.
pub fn load_obj_with(path: &Path, options: &LoadOptions) -> Result<Mesh, CompileError> {
    load_obj_bytes(path, read_obj(path)?, options)
}

/// The bytes of the OBJ file at `path`, refusing a file over [`MAX_INPUT_BYTES`] before
/// reading it.
pub fn read_obj(path: &Path) -> Result<Vec<u8>, CompileError> {
    let io = |source| CompileError::Io {
        path: path.to_path_buf(),
        source,
    };
    let size = std::fs::metadata(path).map_err(io)?.len();
    check_size(path, size)?;
    let bytes = std::fs::read(path).map_err(io)?;
    check_size(path, bytes.len() as u64)?;
    Ok(bytes)
}

/// Load an OBJ file whose bytes were read already ([`read_obj`]); `path` names it in messages
/// and locates its MTL files.
pub fn load_obj_bytes(
    path: &Path,
    bytes: Vec<u8>,
    options: &LoadOptions,
) -> Result<Mesh, CompileError> {
    check_size(path, bytes.len() as u64)?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        CompileError::Parse {
            path: path.to_path_buf(),
            line: valid.iter().filter(|&&b| b == b'\n').count() + 1,
            message: "the file is not valid UTF-8 text".into(),
        }
    })?;
    load_obj_text_with(path, &text, options)
}

fn check_size(path: &Path, size: u64) -> Result<(), CompileError> {
    if size > MAX_INPUT_BYTES {
        return Err(CompileError::TooLarge {
            path: path.to_path_buf(),
            message: format!("the file has {size} bytes, more than the limit of {MAX_INPUT_BYTES}"),
        });
    }
    Ok(())
}

/// What happened to one `mtllib` statement (with the bytes read, when the file was read).
#[derive(Debug)]
enum MtlOutcome {
    Loaded(Vec<u8>),
    Malformed(Vec<u8>, String),
    Missing,
    Unreadable(String),
    TooLarge(u64),
}

/// Load OBJ text already in memory; `path` names it in messages and locates its MTL files
/// (relative `mtllib` paths are resolved next to it). Used by fuzzing and in-memory callers.
pub fn load_obj_text(path: &Path, text: &str) -> Result<Mesh, CompileError> {
    load_obj_text_with(path, text, &LoadOptions::default())
}

/// [`load_obj_text`] with options.
pub fn load_obj_text_with(
    path: &Path,
    text: &str,
    options: &LoadOptions,
) -> Result<Mesh, CompileError> {
    options.check()?;
    let limits = lines::Limits {
        vertices: MAX_VERTEX_STATEMENTS,
        triangles: MAX_TRIANGLES,
    };
    // The line check (our validation, with line numbers) and tobj's parse read the same text
    // independently: they run side by side, and the check's verdict is taken first.
    let (checked, parsed) = rayon::join(
        || lines::check(path, text, limits),
        || {
            // tobj's loader callback is `Fn`: the record needs interior mutability.
            let libraries: RefCell<Vec<(PathBuf, MtlOutcome)>> = RefCell::new(Vec::new());
            let options = tobj::LoadOptions {
                triangulate: false,
                // One index list per attribute: `normal_indices` has an entry per corner (with
                // a single index, a corner without a normal puts the normals out of step with
                // the positions).
                single_index: false,
                // Points and lines stay in, so tobj emits one face per `f`/`l` line (see above).
                ..Default::default()
            };
            let parsed = tobj::load_obj_buf(
                &mut std::io::Cursor::new(text.as_bytes()),
                &options,
                |name| {
                    let full = match path.parent() {
                        Some(dir) => dir.join(name),
                        None => name.to_path_buf(),
                    };
                    let (outcome, result) = read_mtl(&full);
                    libraries.borrow_mut().push((full, outcome));
                    result
                },
            );
            (parsed, libraries.into_inner())
        },
    );
    let checked = checked?;
    if checked.polygon_faces == 0 {
        return Err(CompileError::NoFaces {
            path: path.to_path_buf(),
        });
    }
    let (parsed, libraries) = parsed;
    let (models, materials) = parsed.map_err(|e| CompileError::Obj {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    // tobj reports an error here only when no library loaded; our record says why.
    let materials = materials.unwrap_or_default();

    let mut mesh = Mesh {
        files: vec![path.to_path_buf()],
        ..Mesh::default()
    };
    let mut notes = Notes::default();
    for ((full, outcome), &line) in libraries.iter().zip(&checked.mtllib_lines) {
        let at = format!("{}:{line}", path.display());
        match outcome {
            MtlOutcome::Loaded(_) => {}
            MtlOutcome::Malformed(_, why) => mesh.warnings.push(format!(
                "{at}: material library {} cannot be read ({why}); faces using its materials get the default colour",
                full.display()
            )),
            MtlOutcome::Missing => mesh.warnings.push(format!(
                "{at}: material library {} not found; faces using its materials get the default colour",
                full.display()
            )),
            MtlOutcome::Unreadable(why) => mesh.warnings.push(format!(
                "{at}: material library {} cannot be read ({why}); faces using its materials get the default colour",
                full.display()
            )),
            MtlOutcome::TooLarge(size) => {
                return Err(CompileError::TooLarge {
                    path: full.clone(),
                    message: format!(
                        "the file has {size} bytes, more than the limit of {MAX_INPUT_BYTES}"
                    ),
                })
            }
        }
        let list = if matches!(outcome, MtlOutcome::Missing) {
            &mut mesh.missing
        } else {
            &mut mesh.files
        };
        if !list.contains(full) {
            list.push(full.clone());
            if let MtlOutcome::Loaded(bytes) | MtlOutcome::Malformed(bytes, _) = outcome {
                mesh.mtl_bytes.push((full.clone(), bytes.clone()));
            }
        }
    }
    let mine = mtl_materials(&libraries, &materials)?;
    // Each material's opacity and where it was given (an error names a bad value's line).
    let opacities = (mine.iter())
        .map(mtl::Material::opacity)
        .collect::<Result<Vec<_>, _>>()?;
    let mut textures = texture::Table::new(
        mine.into_iter().map(|m| m.map_kd).collect(),
        options.max_texture,
        options.resample,
    );
    let default_colour = options.default_colour.unwrap_or(DEFAULT_COLOUR);
    let colours: Vec<Option<[u8; 3]>> = materials
        .iter()
        .map(|m| m.diffuse.and_then(kd_to_rgb))
        .collect();

    let mut statements = checked.statements.iter();
    for model in &models {
        let m = &model.mesh;
        let arities: Box<dyn Iterator<Item = usize>> = if m.face_arities.is_empty() {
            Box::new((0..m.indices.len() / 3).map(|_| 3))
        } else {
            Box::new(m.face_arities.iter().map(|&a| a as usize))
        };
        let mut next = 0;
        for arity in arities {
            let statement = statements.next().ok_or_else(|| {
                CompileError::Invariant(format!(
                    "{}: tobj returned more faces than the file has `f`/`l` lines",
                    path.display()
                ))
            })?;
            if statement.arity != arity || next + arity > m.indices.len() {
                return Err(CompileError::Invariant(format!(
                    "{}:{}: tobj read {arity} corners where the line check read {}",
                    path.display(),
                    statement.line,
                    statement.arity
                )));
            }
            let indices = &m.indices[next..next + arity];
            let normal_indices = m.normal_indices.get(next..next + arity);
            let uv_indices = m.texcoord_indices.get(next..next + arity);
            next += arity;
            if !statement.is_face {
                notes.polylines.add(statement.line);
                continue;
            }
            if arity < 3 {
                notes.short_faces.add(statement.line);
                continue;
            }
            let uvs = match m.material_id.filter(|&id| textures.textured(id)) {
                Some(id) => {
                    let uvs = uv_indices
                        .filter(|_| statement.uvs)
                        .and_then(|indices| face_uvs(&m.texcoords, indices));
                    match uvs {
                        Some(uvs) => textures.texture(id)?.map(|k| (k, uvs)),
                        None => {
                            notes.no_uvs.entry(id).or_default().add(statement.line);
                            None
                        }
                    }
                }
                None => None,
            };
            // A textured material without `Kd` shows its texture as it is.
            let white = uvs.is_some() && m.material_id.is_some_and(|id| colours[id].is_none());
            let colour = if white {
                [255; 3]
            } else {
                face_colour(
                    m.material_id,
                    &colours,
                    statement,
                    default_colour,
                    &mut notes,
                )
            };
            let corners: Vec<DVec3> = indices
                .iter()
                .map(|&i| {
                    let i = 3 * i as usize;
                    DVec3::new(m.positions[i], m.positions[i + 1], m.positions[i + 2])
                })
                .collect();
            let normals = if statement.normals {
                let indices = normal_indices.ok_or_else(|| {
                    CompileError::Invariant(format!(
                        "{}:{}: tobj returned no normals for a face that has them",
                        path.display(),
                        statement.line
                    ))
                })?;
                face_normals(&m.normals, indices)
            } else {
                None
            };
            let triangles = match triangulate::triangulate_polygon(&corners) {
                Ok(t) => t,
                Err(triangulate::NotSimple::ZeroArea) => triangulate::fan(arity),
                Err(why) => {
                    notes
                        .not_simple
                        .entry(why.to_string())
                        .or_default()
                        .add(statement.line);
                    triangulate::fan(arity)
                }
            };
            let opacity = m.material_id.and_then(|id| opacities.get(id));
            if let (Some(o), Some(_)) = (opacity.filter(|o| o.opacity < OPAQUE), &uvs) {
                let (mtl, line) = o.at.clone().unwrap_or_default();
                return Err(CompileError::Mtl {
                    path: mtl,
                    line,
                    message: format!(
                        "a transparent material cannot be textured (a face with `vt` uses it at \
                         {}:{}): make it opaque or drop its `map_Kd`",
                        path.display(),
                        statement.line
                    ),
                });
            }
            let opacity = opacity.map_or(OPAQUE, |o| o.opacity);
            mesh.faces += 1;
            mesh.triangles
                .extend(triangles.iter().map(|t| SourceTriangle {
                    vertices: t.map(|i| corners[i]),
                    colour,
                    normals: normals.as_ref().map(|n| t.map(|i| n[i])),
                    texture: uvs.as_ref().map(|(k, uv)| texture::CornerUvs {
                        texture: *k,
                        uv: t.map(|i| uv[i]),
                    }),
                    opacity,
                }));
        }
    }
    if let Some(statement) = statements.next() {
        return Err(CompileError::Invariant(format!(
            "{}:{}: tobj returned no face for this line",
            path.display(),
            statement.line
        )));
    }
    if mesh.triangles.is_empty() {
        return Err(CompileError::NoFaces {
            path: path.to_path_buf(),
        });
    }
    if textures.textures.len() > peel_runtime::read::layout::MAX_TEXTURES as usize {
        return Err(CompileError::TooManyTextures {
            path: path.to_path_buf(),
            count: textures.textures.len(),
            max: peel_runtime::read::layout::MAX_TEXTURES,
        });
    }
    for (image, bytes) in textures.files {
        mesh.files.push(image.clone());
        mesh.mtl_bytes.push((image, bytes));
    }
    mesh.textures = textures.textures;
    mesh.warnings.extend(textures.warnings);
    let plain = checked.mtllib_lines.is_empty() && checked.material_names.is_empty();
    if options.default_colour.is_some() || plain {
        // Faces without a material were meant to get the caller's colour, or the file names
        // no material at all.
        notes.no_material = Tally::default();
    }
    notes.into_warnings(path, &checked, &materials, &mut mesh.warnings);
    Ok(mesh)
}

/// Reads one MTL file for tobj, recording what happened and the bytes parsed.
fn read_mtl(full: &Path) -> (MtlOutcome, tobj::MTLLoadResult) {
    let failed = Err(tobj::LoadError::OpenFileFailed);
    let size = match std::fs::metadata(full) {
        Ok(meta) if meta.is_file() => meta.len(),
        Ok(_) => return (MtlOutcome::Missing, failed),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return (MtlOutcome::Missing, failed),
        Err(e) => return (MtlOutcome::Unreadable(e.to_string()), failed),
    };
    if size > MAX_INPUT_BYTES {
        return (MtlOutcome::TooLarge(size), failed);
    }
    let bytes = match std::fs::read(full) {
        Ok(bytes) => bytes,
        Err(e) => return (MtlOutcome::Unreadable(e.to_string()), failed),
    };
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return (MtlOutcome::TooLarge(bytes.len() as u64), failed);
    }
    match tobj::load_mtl_buf(&mut std::io::Cursor::new(&bytes)) {
        Ok(result) => (MtlOutcome::Loaded(bytes), Ok(result)),
        Err(e) => (MtlOutcome::Malformed(bytes, e.to_string()), Err(e)),
    }
}

/// Each tobj material as the MTL files tobj merged say it (`libraries`, in order, those
/// loaded: its `map_Kd`, `d` and `Tr` statements with their lines), paired with `materials`
/// one for one.
fn mtl_materials(
    libraries: &[(PathBuf, MtlOutcome)],
    materials: &[tobj::Material],
) -> Result<Vec<mtl::Material>, CompileError> {
    let mine: Vec<mtl::Material> = (libraries.iter())
        .filter_map(|(path, outcome)| match outcome {
            MtlOutcome::Loaded(bytes) => {
                Some(mtl::materials(path, &String::from_utf8_lossy(bytes)))
            }
            _ => None,
        })
        .flatten()
        .collect();
    let paired = mine.len() == materials.len()
        && mine.iter().zip(materials).all(|(a, b)| {
            a.name == b.name
                && a.map_kd.as_ref().map(|m| m.text.as_str()) == b.diffuse_texture.as_deref()
        });
    if !paired {
        return Err(CompileError::Invariant(format!(
            "the MTL files read give {} materials where tobj read {}, or other ones",
            mine.len(),
            materials.len()
        )));
    }
    Ok(mine)
}

/// A face's corner texture coordinates `(u, v)` from tobj's `texcoords` at `indices`; `None`
/// when one is not finite.
fn face_uvs(texcoords: &[f64], indices: &[u32]) -> Option<Vec<glam::DVec2>> {
    indices
        .iter()
        .map(|&i| {
            let i = 2 * i as usize;
            let uv = glam::DVec2::new(*texcoords.get(i)?, *texcoords.get(i + 1)?);
            uv.is_finite().then_some(uv)
        })
        .collect()
}

/// A face's corner normals from tobj's `normals` at `indices`, each of unit length; `None`
/// when one is not finite or has no length (smooth shading then computes them all).
fn face_normals(normals: &[f64], indices: &[u32]) -> Option<Vec<DVec3>> {
    indices
        .iter()
        .map(|&i| {
            let i = 3 * i as usize;
            let n = DVec3::new(*normals.get(i)?, *normals.get(i + 1)?, *normals.get(i + 2)?);
            n.try_normalize()
        })
        .collect()
}

/// `Kd` -> RGB888: each channel clamped to [0, 1] and rounded; `None` if a channel is NaN.
fn kd_to_rgb(kd: [f64; 3]) -> Option<[u8; 3]> {
    if kd.iter().any(|c| c.is_nan()) {
        return None;
    }
    Some(kd.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8))
}

/// The colour of one face, noting why it falls back to `default` ([`DEFAULT_COLOUR`] unless
/// the caller chose one).
fn face_colour(
    material_id: Option<usize>,
    colours: &[Option<[u8; 3]>],
    statement: &lines::Statement,
    default: [u8; 3],
    notes: &mut Notes,
) -> [u8; 3] {
    match (material_id, statement.material) {
        (Some(id), _) => match colours.get(id).copied().flatten() {
            Some(colour) => colour,
            None => {
                notes.no_kd.entry(id).or_default().add(statement.line);
                default
            }
        },
        (None, Some(name)) => {
            notes.undefined.entry(name).or_default().add(statement.line);
            default
        }
        (None, None) => {
            notes.no_material.add(statement.line);
            default
        }
    }
}

#[cfg(test)]
mod tests;
