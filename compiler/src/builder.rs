//! Builder: compile OBJ assets from a build script, as `prost-build` and `cc` do.

use std::path::{Path, PathBuf};

use crate::compile::{compile_obj, CompileOptions, Compiled};
use crate::error::CompileError;
use crate::shade::Shading;

/// Compiles an OBJ (and its MTL) into `OUT_DIR` from a `build.rs`, and tells cargo to rerun
/// the build script when any of the files read changes, or an MTL file the OBJ names but that
/// is missing appears.
///
/// In `build.rs`:
///
/// ```no_run
/// let peel = peel_compiler::Builder::new("assets/scene.obj")
///     .compile()
///     .expect("compile assets/scene.obj");
/// // peel == $OUT_DIR/scene.peel; the firmware embeds it with
/// // include_bytes!(concat!(env!("OUT_DIR"), "/scene.peel"))
/// assert!(peel.ends_with("scene.peel"));
/// ```
#[derive(Debug, Clone)]
pub struct Builder {
    obj: PathBuf,
    out_dir: Option<PathBuf>,
    out_name: Option<String>,
    options: CompileOptions,
}

impl Builder {
    /// Compile `obj` with the default options.
    pub fn new(obj: impl AsRef<Path>) -> Self {
        Builder {
            obj: obj.as_ref().to_path_buf(),
            out_dir: None,
            out_name: None,
            options: CompileOptions::default(),
        }
    }

    /// Write into `dir` instead of `$OUT_DIR`.
    pub fn out_dir(mut self, dir: impl AsRef<Path>) -> Self {
        self.out_dir = Some(dir.as_ref().to_path_buf());
        self
    }

    /// Output file name (default: the OBJ's stem + `.peel`).
    pub fn out_name(mut self, name: impl Into<String>) -> Self {
        self.out_name = Some(name.into());
        self
    }

    /// Keep source triangle ids (for id images).
    pub fn ids(mut self, ids: bool) -> Self {
        self.options.ids = ids;
        self
    }

    /// Candidate planes costed per split node.
    pub fn candidates(mut self, k: usize) -> Self {
        self.options.build.candidates = k;
        self
    }

    /// Largest output polygon.
    pub fn max_polygon_vertices(mut self, n: usize) -> Self {
        self.options.build.max_polygon_vertices = n;
        self
    }

    /// How colours are baked.
    pub fn shading(mut self, shading: Shading) -> Self {
        self.options.shading = shading;
        self
    }

    /// Compile, write atomically, print `cargo:rerun-if-changed` for every file read, and
    /// return the path of the `.peel` file.
    pub fn compile(&self) -> Result<PathBuf, CompileError> {
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
        // Rerun on the OBJ even if loading fails, so fixing it triggers a rebuild.
        println!("cargo:rerun-if-changed={}", self.obj.display());
        let compiled = compile_obj(&self.obj, &self.options, &|_| {})?;
        for f in watched(&self.obj, &compiled) {
            println!("cargo:rerun-if-changed={}", f.display());
        }
        for w in &compiled.warnings {
            println!("cargo:warning={w}");
        }
        let out = out_dir.join(name);
        crate::write::write_atomic(&out, &compiled.bytes)?;
        Ok(out)
    }
}

/// The paths besides `obj` whose changes must rerun the build script: the MTL files read, and
/// for each MTL file named but missing, the nearest folder on its path that exists (creating
/// the file, or a folder towards it, changes that folder; the missing path itself would make
/// cargo rerun the script on every build).
fn watched(obj: &Path, compiled: &Compiled) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = compiled
        .files
        .iter()
        .filter(|f| *f != obj)
        .cloned()
        .collect();
    for m in &compiled.missing {
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
mod tests {
    use super::*;

    #[test]
    fn missing_mtl_files_are_watched_through_their_nearest_folder() {
        let dir = tempfile::tempdir().unwrap();
        let obj = dir.path().join("scene.obj");
        std::fs::write(
            &obj,
            "mtllib here.mtl\nmtllib gone.mtl\nmtllib sub/deeper/gone.mtl\n\
             v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n",
        )
        .unwrap();
        let here = dir.path().join("here.mtl");
        std::fs::write(&here, "newmtl red\nKd 1 0 0\n").unwrap();
        let compiled = compile_obj(&obj, &CompileOptions::default(), &|_| {}).unwrap();
        assert_eq!(compiled.files, [obj.clone(), here.clone()]);
        assert_eq!(compiled.missing.len(), 2);
        // The folder holds the missing file; `sub/deeper` does not exist, so its nearest
        // existing ancestor (the same folder) is watched, once.
        assert_eq!(watched(&obj, &compiled), [here, dir.path().to_path_buf()]);
        // The Builder writes the file and still succeeds (missing MTL files only warn).
        let out = Builder::new(&obj).out_dir(dir.path()).compile().unwrap();
        assert!(out.exists());
    }
}
