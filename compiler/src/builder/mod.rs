//! Builder: compile OBJ assets from a build script, as `prost-build` and `cc` do.
//!
//! Besides the `.peel` file it writes a sizes file ([`sizes`]) and keeps a compile cache
//! ([`cache`]) that every cargo profile of a target directory shares.

pub mod cache;
pub mod sizes;
pub mod spans;

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::compile::{compile_obj_bytes, compile_parts_bytes, CompileOptions};
use crate::error::CompileError;
use crate::shade::{Shading, Surface};

/// Compiles an OBJ (and its MTL) into `OUT_DIR` from a `build.rs`, writes a sizes file beside
/// it, and tells cargo to rerun the build script when any of the files read changes, or an MTL
/// file the OBJ names but that is missing appears.
///
/// Compiles are cached (see [`Builder::cache`] and [`Builder::cache_location`]): `cargo build`,
/// `cargo test` and `cargo build --release` compile each asset once between them.
///
/// In `build.rs`:
///
/// ```no_run
/// let out = peel_compiler::Builder::new("assets/scene.obj")
///     .compile()
///     .expect("compile assets/scene.obj");
/// // $OUT_DIR/scene.peel; the firmware embeds it with
/// // include_bytes!(concat!(env!("OUT_DIR"), "/scene.peel"))
/// assert!(out.peel.ends_with("scene.peel"));
/// // $OUT_DIR/scene.rs: the sizes, for
/// // mod scene { include!(concat!(env!("OUT_DIR"), "/scene.rs")); }
/// assert!(out.sizes.ends_with("scene.rs"));
/// ```
#[derive(Debug, Clone)]
pub struct Builder {
    obj: PathBuf,
    /// The objects of a scene of parts ([`Builder::object`]): name and OBJ file.
    objects: Vec<(String, PathBuf)>,
    out_dir: Option<PathBuf>,
    out_name: Option<String>,
    options: CompileOptions,
    /// Shadows cast from the shading's light ([`Builder::shadows`]).
    shadows: bool,
    cache: bool,
    cache_dir: Option<PathBuf>,
    /// The image size span memory is measured at, if any.
    image_size: Option<(u32, u32)>,
}

/// A compile, from the cache or not.
struct Done {
    entry: cache::Entry,
    /// The MTL files read (readable or not).
    mtl_files: Vec<PathBuf>,
    /// What happened, for the builder's plain line.
    note: String,
    from_cache: bool,
}

/// What [`Builder::compile`] wrote. Its [`AsRef<Path>`] is the `.peel` file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Output {
    /// The `.peel` file.
    pub peel: PathBuf,
    /// The sizes file: `<stem>.rs` beside the `.peel` file, the constants firmware sizes its
    /// buffers from and the checks that they suffice.
    pub sizes: PathBuf,
    /// Whether the bytes came from the cache (no compile ran).
    pub from_cache: bool,
}

impl AsRef<Path> for Output {
    fn as_ref(&self) -> &Path {
        &self.peel
    }
}

impl Builder {
    /// Compile `obj` with the default options.
    pub fn new(obj: impl AsRef<Path>) -> Self {
        Builder {
            obj: obj.as_ref().to_path_buf(),
            objects: Vec::new(),
            out_dir: None,
            out_name: None,
            options: CompileOptions::default(),
            shadows: false,
            cache: true,
            cache_dir: None,
            image_size: None,
        }
    }

    /// Add an object `name` compiled from `obj` in its own frame, with the same options:
    /// the output becomes a file of parts (format 5; `formats/peel.md`), the OBJ given to
    /// [`Builder::new`] its world, then the objects in the order added. Names have 1 to
    /// `MAX_NAME` bytes and are distinct ([`CompileError::PartName`]). The sizes file then
    /// gives the largest of each figure over the parts, so that one workspace draws every
    /// part; its `CENTRE` and bounds are the world's.
    pub fn object(mut self, name: impl Into<String>, obj: impl AsRef<Path>) -> Self {
        self.objects.push((name.into(), obj.as_ref().to_path_buf()));
        self
    }

    /// Write into `dir` instead of `$OUT_DIR`.
    pub fn out_dir(mut self, dir: impl AsRef<Path>) -> Self {
        self.out_dir = Some(dir.as_ref().to_path_buf());
        self
    }

    /// Output file name (default: the OBJ's stem + `.peel`). The sizes file is named after its
    /// stem: `<stem>.rs`.
    pub fn out_name(mut self, name: impl Into<String>) -> Self {
        self.out_name = Some(name.into());
        self
    }

    /// Keep source triangle ids (for id images).
    pub fn ids(mut self, ids: bool) -> Self {
        self.options.ids = ids;
        self
    }

    /// Store vertices as `f32` instead of 16-bit steps on the scene's bounds (see
    /// [`crate::compile::CompileOptions::wide_vertices`]).
    pub fn wide_vertices(mut self, wide: bool) -> Self {
        self.options.wide_vertices = wide;
        self
    }

    /// Mark the faces of closed parts that face out, hidden from behind (see
    /// [`crate::compile::CompileOptions::solid`]).
    pub fn solid(mut self, solid: bool) -> Self {
        self.options.solid = solid;
        self
    }

    /// Candidate planes costed per split node of more than 2048 fragments (smaller nodes cost
    /// every plane).
    pub fn candidates(mut self, k: usize) -> Self {
        self.options.build.candidates = k;
        self
    }

    /// Largest output polygon.
    pub fn max_polygon_vertices(mut self, n: usize) -> Self {
        self.options.build.max_polygon_vertices = n;
        self
    }

    /// The light colours are baked with ([`Shading::Flat`]: unlit).
    pub fn shading(mut self, shading: Shading) -> Self {
        self.options.shading = shading;
        let on = self.shadows;
        self.shadows(on)
    }

    /// Faceted or smooth shading, with its crease angle (`peel compile --shading smooth
    /// --crease DEG`; default [`crate::shade::DEFAULT_SURFACE`]), e.g.
    /// `.surface(Surface::smooth(45.0)?)`.
    pub fn surface(mut self, surface: Surface) -> Self {
        self.options.surface = surface;
        self
    }

    /// Cast shadows from the shading's light, a sun or a point light (`peel compile
    /// --shadows`): polygons are cut along the shadows and the parts in shadow get the ambient
    /// colour. Nothing to cast with [`Shading::Flat`].
    pub fn shadows(mut self, on: bool) -> Self {
        self.shadows = on;
        self.options.build.shadows = self.options.shading.light().filter(|_| on);
        self
    }

    /// The colour of faces the files give no colour (instead of the grey
    /// [`crate::load::DEFAULT_COLOUR`]). It says faces without a material are meant: the
    /// warning about them is no longer printed. Undefined materials, materials without `Kd`
    /// and missing MTL files still warn (see [`crate::load::LoadOptions`]).
    pub fn default_colour(mut self, rgb: [u8; 3]) -> Self {
        self.options.load.default_colour = Some(rgb);
        self
    }

    /// The largest side of a stored texture, in texels: a power of two from 1 to 1024
    /// (`peel compile --max-texture N`; default [`crate::load::DEFAULT_MAX_TEXTURE`]). Larger
    /// images are resampled to it (see [`crate::load::LoadOptions::max_texture`]).
    pub fn max_texture(mut self, texels: u32) -> Self {
        self.options.load.max_texture = texels;
        self
    }

    /// Resample textures whose sides are not powers of two within the limit (default: on);
    /// off (`peel compile --no-resample`), such a texture is an error.
    pub fn resample(mut self, on: bool) -> Self {
        self.options.load.resample = on;
        self
    }

    /// Use the compile cache (default: on). Off, every run compiles.
    pub fn cache(mut self, on: bool) -> Self {
        self.cache = on;
        self
    }

    /// Keep the compile cache in `dir` (default: `PEEL_CACHE_DIR` if set, else `peel-cache` in
    /// the cargo target directory; see [`Builder::cache_location`]).
    pub fn cache_dir(mut self, dir: impl AsRef<Path>) -> Self {
        self.cache_dir = Some(dir.as_ref().to_path_buf());
        self
    }

    /// The cache folder this builder uses, if any: [`Builder::cache_dir`], else
    /// `PEEL_CACHE_DIR`, else the target directory's `peel-cache` found from `OUT_DIR`.
    pub fn cache_location(&self) -> Option<PathBuf> {
        if !self.cache {
            return None;
        }
        if let Some(dir) = &self.cache_dir {
            return Some(dir.clone());
        }
        if let Some(dir) = std::env::var_os(cache::CACHE_DIR_ENV).filter(|d| !d.is_empty()) {
            return Some(PathBuf::from(dir));
        }
        let out_dir = PathBuf::from(std::env::var_os("OUT_DIR")?);
        let target = std::env::var("TARGET").ok();
        cache::dir_from_out_dir(&out_dir, target.as_deref())
    }

    /// The image size the firmware draws at: the sizes file's `SPANS_PER_ROW` is then the span
    /// memory an orbit of the scene needs at that size ([`spans::spans_per_row`]: the fewest
    /// intervals per row with which no frame of it falls back to back-to-front painting),
    /// instead of the host's 64. It is measured on every build, not cached (about a second
    /// for the teapot at 320x240 in an optimised build script: 12 intervals a row where 64
    /// would take 61,440 bytes).
    pub fn image_size(mut self, width: u32, height: u32) -> Self {
        self.image_size = Some((width, height));
        self
    }

    /// Compile (or take the compile from the cache), print `cargo:rerun-if-changed` for every
    /// file read and `cargo:warning` for every loader warning (the same lines either way),
    /// write the `.peel` file and its sizes file atomically, and return their paths.
    ///
    /// It also prints a plain line (cargo ignores it; `cargo build -vv` shows it) saying
    /// whether it compiled or used the cache: `peel: <obj>: compiled in <s> s (...)` or
    /// `peel: <obj>: cache hit (...)`.
    pub fn compile(&self) -> Result<Output, CompileError> {
        let out_dir =
            match &self.out_dir {
                Some(d) => d.clone(),
                None => PathBuf::from(std::env::var_os("OUT_DIR").ok_or_else(|| {
                    CompileError::Write {
                        path: PathBuf::from("$OUT_DIR"),
                        source: std::io::Error::other(
                            "OUT_DIR is not set (not in a build script?)",
                        ),
                    }
                })?),
            };
        let name = self.out_name.clone().unwrap_or_else(|| {
            let stem = self
                .obj
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned());
            format!("{}.peel", stem.unwrap_or_else(|| "scene".into()))
        });
        let sizes_name = sizes::sizes_name(&name);
        if sizes_name == name {
            return Err(CompileError::Write {
                path: out_dir.join(&name),
                source: std::io::Error::other("the .peel file cannot be named like its sizes file"),
            });
        }
        let names: Vec<&str> = self.objects.iter().map(|(n, _)| n.as_str()).collect();
        crate::write::parts::check_parts(true, &names)?;
        // Rerun on the OBJ files even if loading fails, so fixing them triggers a rebuild.
        println!("cargo:rerun-if-changed={}", self.obj.display());
        for (_, obj) in &self.objects {
            println!("cargo:rerun-if-changed={}", obj.display());
        }
        let start = Instant::now();
        let obj_bytes = crate::load::read_obj(&self.obj)?;
        let objects = (self.objects.iter())
            .map(|(name, obj)| Ok((name.clone(), obj.clone(), crate::load::read_obj(obj)?)))
            .collect::<Result<Vec<_>, CompileError>>()?;
        let Done {
            entry: result,
            mtl_files,
            note,
            from_cache,
        } = self.cached_compile(obj_bytes, objects, start)?;
        for f in watched(&mtl_files, &result.missing) {
            println!("cargo:rerun-if-changed={}", f.display());
        }
        for w in &result.warnings {
            println!("cargo:warning={w}");
        }
        println!("peel: {}: {note}", self.obj.display());
        let failed = |e: String| {
            CompileError::Invariant(format!("the compiled scene fails validation: {e}"))
        };
        let trees: Vec<&[u8]> = if self.objects.is_empty() {
            vec![&result.peel]
        } else {
            let parts = crate::write::parts::read_parts(&result.peel).map_err(failed)?;
            parts.into_iter().map(|p| p.tree).collect()
        };
        let mut headers = Vec::with_capacity(trees.len());
        let mut measured: Vec<sizes::MeasuredSpans> = Vec::new();
        for tree in &trees {
            let scene =
                peel_runtime::read::Scene::parse(tree).map_err(|e| failed(e.to_string()))?;
            headers.push(scene.header());
            if let Some((width, height)) = self.image_size {
                measured
                    .push(spans::measure(tree, width, height).map_err(CompileError::Invariant)?);
            }
        }
        let spans = measured.into_iter().reduce(sizes::MeasuredSpans::max);
        let text = sizes::sizes_file(
            &sizes::largest(&headers),
            result.peel.len(),
            &name,
            &self.obj.display().to_string(),
            spans,
            self.objects.len(),
        );
        let out = out_dir.join(&name);
        let sizes = out_dir.join(&sizes_name);
        crate::write::write_atomic(&out, &result.peel)?;
        crate::write::write_atomic(&sizes, text.as_bytes())?;
        Ok(Output {
            peel: out,
            sizes,
            from_cache,
        })
    }

    /// The compile of `obj_bytes`, from the cache when it holds it, else compiled (and stored).
    /// `objects` are the objects' names, paths and bytes.
    fn cached_compile(
        &self,
        obj_bytes: Vec<u8>,
        objects: Vec<(String, PathBuf, Vec<u8>)>,
        start: Instant,
    ) -> Result<Done, CompileError> {
        let Some(dir) = self.cache_location() else {
            return self.compile_now(obj_bytes, objects, start, |_| "cache off".into());
        };
        let key = cache::Key::new(&self.obj, &obj_bytes, &self.options)
            .and_then(|key| key.with_objects(&objects));
        let Some(key) = key else {
            return self.compile_now(obj_bytes, objects, start, |_| {
                "not cached: a path is not UTF-8".into()
            });
        };
        let miss = match cache::lookup(&dir, &key) {
            Ok(entry) => {
                let note = format!(
                    "cache hit in {:.3} s ({})",
                    start.elapsed().as_secs_f64(),
                    dir.join(key.file_name()).display()
                );
                return Ok(Done {
                    mtl_files: entry.mtl.iter().map(|(p, _)| p.clone()).collect(),
                    entry,
                    note,
                    from_cache: true,
                });
            }
            Err(miss) => miss,
        };
        self.compile_now(obj_bytes, objects, start, |done| {
            let stored = if done.entry.mtl.len() < done.mtl_files.len() {
                "not cached: an MTL file could not be read".to_string()
            } else {
                match cache::store(&dir, &key, &done.entry) {
                    Ok(Some(p)) => format!("cached in {}", p.display()),
                    Ok(None) => "not cached: a path is not UTF-8".into(),
                    Err(e) => format!("not cached: {e}"),
                }
            };
            format!("{}; {stored}", miss.describe())
        })
    }

    /// Compile now; `then` says (and does) what follows, for the note.
    fn compile_now(
        &self,
        obj_bytes: Vec<u8>,
        objects: Vec<(String, PathBuf, Vec<u8>)>,
        start: Instant,
        then: impl FnOnce(&Done) -> String,
    ) -> Result<Done, CompileError> {
        let (parts, peel, seconds) = if objects.is_empty() {
            let compiled = compile_obj_bytes(&self.obj, obj_bytes, &self.options, &|_| {}, start)?;
            let (peel, seconds) = (compiled.bytes.clone(), compiled.seconds);
            (vec![compiled], peel, seconds)
        } else {
            let objs = (objects.iter())
                .map(|(name, path, bytes)| (name.clone(), path.as_path(), bytes.clone()))
                .collect();
            let compiled = compile_parts_bytes(
                Some((&self.obj, obj_bytes)),
                objs,
                &self.options,
                &|_| {},
                start,
            )?;
            let parts = compiled.parts.into_iter().map(|(_, c)| c).collect();
            (parts, compiled.bytes, compiled.seconds)
        };
        let objs: Vec<&PathBuf> = std::iter::once(&self.obj)
            .chain(objects.iter().map(|(_, path, _)| path))
            .collect();
        let mut entry = cache::Entry {
            mtl: Vec::new(),
            missing: Vec::new(),
            warnings: Vec::new(),
            peel,
        };
        let mut mtl_files = Vec::new();
        for part in parts {
            mtl_files.extend(part.files.into_iter().filter(|f| !objs.contains(&f)));
            entry.mtl.extend(part.mtl_bytes);
            entry.missing.extend(part.missing);
            entry.warnings.extend(part.warnings);
        }
        let mut done = Done {
            mtl_files,
            entry,
            note: String::new(),
            from_cache: false,
        };
        done.note = format!("compiled in {seconds:.2} s ({})", then(&done));
        Ok(done)
    }
}

/// The paths besides the OBJ whose changes must rerun the build script: the MTL files read, and
/// for each MTL file named but missing, the nearest folder on its path that exists (creating
/// the file, or a folder towards it, changes that folder; the missing path itself would make
/// cargo rerun the script on every build).
fn watched(mtl_files: &[PathBuf], missing: &[PathBuf]) -> Vec<PathBuf> {
    let mut out = mtl_files.to_vec();
    for m in missing {
        let dir = m
            .ancestors()
            .skip(1)
            .find(|d| d.as_os_str().is_empty() || d.is_dir())
            .filter(|d| !d.as_os_str().is_empty())
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        if !out.contains(&dir) {
            out.push(dir);
        }
    }
    out
}

#[cfg(test)]
mod tests;
