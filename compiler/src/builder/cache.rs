//! The [`Builder`](super::Builder)'s compile cache: one compile per asset for every cargo
//! profile of a target directory.
//!
//! # Where
//!
//! `PEEL_CACHE_DIR` when set, else `peel-cache` in the cargo target directory, found from the
//! build script's `OUT_DIR` (see [`dir_from_out_dir`]). `cargo clean`, or deleting the folder,
//! clears it.
//!
//! # Key
//!
//! An entry is used only when everything a compile reads is the same, compared byte for byte
//! (no hash stands in for the inputs):
//! - the compiler: `peel-compiler`'s version, the `.peel` format version, and the sizes and
//!   modification times of the compiler crate's own source files (a path or git dependency
//!   changes its code without changing its version);
//! - every compile option ([`encode_options`] names each field);
//! - the OBJ's path as given (warnings and `cargo:rerun-if-changed` lines name it) and its
//!   absolute path;
//! - the OBJ's bytes;
//! - each object of a scene of parts: its name, its paths and its bytes, as the OBJ's;
//! - each MTL file and texture image read: its bytes now must be those the entry was compiled
//!   from; and each MTL file that was named but missing must still be missing.
//!
//! Entries are files named by a hash of the options and the OBJ's paths (one entry per asset
//! and option set: a changed asset replaces its entry, the folder does not grow with edits).
//! Each is written atomically and starts with a checksum of the rest; an entry that is
//! unreadable, truncated, fails its checksum, was made from other inputs, or whose `.peel`
//! bytes fail [`Scene::parse`] is ignored and rewritten by the compile.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use peel_runtime::read::layout::FORMAT_VERSION;
use peel_runtime::read::Scene;

use crate::compile::CompileOptions;
use crate::error::CompileError;
use crate::load::LoadOptions;
use crate::shade::{Shading, Surface};
use crate::shadow::Light;
use crate::tree::BuildOptions;

/// The environment variable that sets the cache folder.
pub const CACHE_DIR_ENV: &str = "PEEL_CACHE_DIR";

/// The first bytes of an entry, then its layout version.
const MAGIC: &[u8; 11] = b"peel-cache\n";
const ENTRY_VERSION: u32 = 1;

/// The cache folder for a build script whose `OUT_DIR` is `out_dir`, building for `target`
/// (cargo's `TARGET`): `<target dir>/peel-cache`.
///
/// Cargo puts a build script's output in `<base>/<profile>/build/<package>-<hash>/out`, where
/// `<base>` is the target directory, or `<target dir>/<triple>` when the build names a
/// `--target`. The folder is `<base>/peel-cache`, with `<base>` lifted to the target directory
/// when its name is the triple: so `dev`, `test`, `release` and any custom profile, with or
/// without `--target`, share one cache (the `.peel` bytes do not depend on the target).
/// `None` when `out_dir` does not have that shape.
pub fn dir_from_out_dir(out_dir: &Path, target: Option<&str>) -> Option<PathBuf> {
    let mut up = out_dir.ancestors();
    let out = up.next()?;
    let _package = up.next()?;
    let build = up.next()?;
    let _profile = up.next()?;
    let mut base = up.next()?;
    if out.file_name()? != "out" || build.file_name()? != "build" {
        return None;
    }
    if let (Some(target), Some(name), Some(parent)) = (target, base.file_name(), base.parent()) {
        if name == target && !parent.as_os_str().is_empty() {
            base = parent;
        }
    }
    Some(base.join("peel-cache"))
}

/// What identifies one compile before it runs: the compiler, the options and the OBJ (its
/// paths and bytes). Equal keys compile to equal bytes, given equal MTL files.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Key {
    /// Everything but the OBJ's bytes: names the entry.
    head: Vec<u8>,
    /// The OBJ's bytes.
    obj: Vec<u8>,
}

impl Key {
    /// The key of compiling `obj` (as given to the builder) with bytes `obj_bytes` and
    /// `options`, by this compiler. `None` when a path is not UTF-8 (such compiles are not
    /// cached).
    pub fn new(obj: &Path, obj_bytes: &[u8], options: &CompileOptions) -> Option<Key> {
        let absolute = fs::canonicalize(obj).unwrap_or_default();
        let mut head = Vec::new();
        put(&mut head, compiler_identity().as_bytes());
        let mut encoded = Vec::new();
        encode_options(options, &mut encoded);
        put(&mut head, &encoded);
        put(&mut head, obj.to_str()?.as_bytes());
        put(&mut head, absolute.to_str()?.as_bytes());
        Some(Key {
            head,
            obj: obj_bytes.to_vec(),
        })
    }

    /// This key with the objects of a scene of parts added: each one's name, paths (as given
    /// and absolute) and bytes, in order. Without objects the key is unchanged. `None` when a
    /// path is not UTF-8.
    pub fn with_objects(mut self, objects: &[(String, PathBuf, Vec<u8>)]) -> Option<Key> {
        for (name, path, bytes) in objects {
            let absolute = fs::canonicalize(path).unwrap_or_default();
            put(&mut self.head, name.as_bytes());
            put(&mut self.head, path.to_str()?.as_bytes());
            put(&mut self.head, absolute.to_str()?.as_bytes());
            put(&mut self.obj, bytes);
        }
        Some(self)
    }

    /// The entry's file name: a hash of the options and the OBJ's paths, not of the compiler
    /// or the bytes, so a new compile of the same asset replaces the old entry.
    pub fn file_name(&self) -> String {
        // Skip the compiler identity, the first field.
        let rest = Reader::new(&self.head)
            .blob()
            .map_or(&self.head[..], |id| &self.head[8 + id.len()..]);
        format!("{:016x}.entry", checksum(rest))
    }
}

/// `peel-compiler`'s version, the format version and a fingerprint of the compiler crate's
/// source files (computed once per process).
fn compiler_identity() -> &'static str {
    static IDENTITY: OnceLock<String> = OnceLock::new();
    IDENTITY.get_or_init(|| {
        format!(
            "peel-compiler {}; format {FORMAT_VERSION}; sources {:016x}",
            env!("CARGO_PKG_VERSION"),
            sources_fingerprint(Path::new(env!("CARGO_MANIFEST_DIR")))
        )
    })
}

/// A hash of the relative path, size and modification time of `Cargo.toml` and every file
/// under `src/` in `dir` (0 if there is none): a release from a registry never changes, a path
/// dependency being edited does.
fn sources_fingerprint(dir: &Path) -> u64 {
    let mut files = Vec::new();
    let mut pending = vec![dir.join("src")];
    files.push(dir.join("Cargo.toml"));
    while let Some(d) = pending.pop() {
        let Ok(entries) = fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            match e.file_type() {
                Ok(t) if t.is_dir() => pending.push(e.path()),
                Ok(_) => files.push(e.path()),
                Err(_) => {}
            }
        }
    }
    files.sort();
    let mut record = Vec::new();
    for f in &files {
        let Ok(meta) = fs::metadata(f) else { continue };
        let modified = meta
            .modified()
            .ok()
            .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
            .map_or(0, |d| d.as_nanos());
        put(
            &mut record,
            f.strip_prefix(dir)
                .unwrap_or(f)
                .as_os_str()
                .as_encoded_bytes(),
        );
        record.extend_from_slice(&meta.len().to_le_bytes());
        record.extend_from_slice(&modified.to_le_bytes());
    }
    checksum(&record)
}

/// Every compile option, field by field. The destructuring names every field: a new option
/// does not compile until it is part of the key.
pub fn encode_options(options: &CompileOptions, out: &mut Vec<u8>) {
    let CompileOptions {
        load:
            LoadOptions {
                default_colour,
                max_texture,
                resample,
            },
        build:
            BuildOptions {
                candidates,
                seed,
                max_polygon_vertices,
                watertight,
                shadows,
            },
        ids,
        id_offset,
        wide_vertices,
        shading,
        surface,
        solid,
    } = options;
    match default_colour {
        None => out.push(0),
        Some(c) => {
            out.push(1);
            out.extend_from_slice(c);
        }
    }
    out.extend_from_slice(&max_texture.to_le_bytes());
    out.push(u8::from(*resample));
    out.extend_from_slice(&(*candidates as u64).to_le_bytes());
    out.extend_from_slice(&seed.to_le_bytes());
    out.extend_from_slice(&(*max_polygon_vertices as u64).to_le_bytes());
    out.push(u8::from(*watertight));
    out.push(u8::from(*ids));
    out.extend_from_slice(&id_offset.to_le_bytes());
    out.push(u8::from(*wide_vertices));
    out.push(u8::from(*solid));
    let direction = |out: &mut Vec<u8>, d: &glam::DVec3| {
        for c in d.to_array() {
            out.extend_from_slice(&c.to_bits().to_le_bytes());
        }
    };
    match shading {
        Shading::Flat => out.push(0),
        Shading::Lambert(light) => {
            out.push(1);
            direction(out, light);
        }
        Shading::Point(at) => {
            out.push(2);
            direction(out, at);
        }
    }
    match surface {
        Surface::Faceted => out.push(0),
        Surface::Smooth(crease) => {
            out.push(1);
            out.extend_from_slice(&crease.degrees().to_bits().to_le_bytes());
        }
    }
    match shadows {
        None => out.push(0),
        Some(Light::Sun(sun)) => {
            out.push(1);
            direction(out, sun);
        }
        Some(Light::Point(at)) => {
            out.push(2);
            direction(out, at);
        }
    }
}

/// A compile, as the cache keeps it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Entry {
    /// The MTL files and texture images read, and their bytes.
    pub mtl: Vec<(PathBuf, Vec<u8>)>,
    /// MTL files named but missing.
    pub missing: Vec<PathBuf>,
    /// The compile's warnings.
    pub warnings: Vec<String>,
    /// The `.peel` bytes.
    pub peel: Vec<u8>,
}

/// Why an entry was not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Miss {
    /// No entry for this asset and option set.
    Absent,
    /// The entry could not be read.
    Unreadable,
    /// The entry is truncated, fails its checksum, or its `.peel` bytes are invalid.
    Corrupt,
    /// The entry was made by another compiler, or from other OBJ bytes.
    Stale,
    /// An MTL file or texture image changed, appeared or can no longer be read.
    MtlChanged,
}

impl Miss {
    /// For the builder's note.
    pub fn describe(self) -> &'static str {
        match self {
            Miss::Absent => "no entry",
            Miss::Unreadable => "entry unreadable",
            Miss::Corrupt => "entry corrupt, replaced",
            Miss::Stale => "entry from another compiler or other OBJ bytes, replaced",
            Miss::MtlChanged => "an MTL file or texture changed, entry replaced",
        }
    }
}

/// The entry for `key` in `dir`, if it is valid for the files as they are now.
pub fn lookup(dir: &Path, key: &Key) -> Result<Entry, Miss> {
    let bytes = match fs::read(dir.join(key.file_name())) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(Miss::Absent),
        Err(_) => return Err(Miss::Unreadable),
    };
    let (head, obj, entry) = decode(&bytes).ok_or(Miss::Corrupt)?;
    if head != key.head || obj != key.obj {
        return Err(Miss::Stale);
    }
    for (path, bytes) in &entry.mtl {
        if fs::read(path).ok().as_ref() != Some(bytes) {
            return Err(Miss::MtlChanged);
        }
    }
    if entry.missing.iter().any(|m| m.is_file()) {
        return Err(Miss::MtlChanged);
    }
    // The checksum says the bytes are those stored; the full validation says what was stored
    // is a scene this runtime reads.
    let valid = if crate::write::parts::is_parts_file(&entry.peel) {
        crate::write::parts::read_parts(&entry.peel).is_ok()
    } else {
        Scene::parse(&entry.peel).is_ok()
    };
    if !valid {
        return Err(Miss::Corrupt);
    }
    Ok(entry)
}

/// Write `entry` for `key` into `dir` (created if needed), atomically. Returns the entry's
/// path, or `None` when a path is not UTF-8 (nothing is written).
pub fn store(dir: &Path, key: &Key, entry: &Entry) -> Result<Option<PathBuf>, CompileError> {
    let Some(bytes) = encode(key, entry) else {
        return Ok(None);
    };
    fs::create_dir_all(dir).map_err(|source| CompileError::Write {
        path: dir.to_path_buf(),
        source,
    })?;
    let path = dir.join(key.file_name());
    crate::write::write_atomic(&path, &bytes)?;
    Ok(Some(path))
}

/// The entry's bytes: magic, version, checksum of the rest, then the rest.
fn encode(key: &Key, entry: &Entry) -> Option<Vec<u8>> {
    let mut rest = Vec::new();
    put(&mut rest, &key.head);
    put(&mut rest, &key.obj);
    put_count(&mut rest, entry.mtl.len());
    for (path, bytes) in &entry.mtl {
        put(&mut rest, path.to_str()?.as_bytes());
        put(&mut rest, bytes);
    }
    put_count(&mut rest, entry.missing.len());
    for path in &entry.missing {
        put(&mut rest, path.to_str()?.as_bytes());
    }
    put_count(&mut rest, entry.warnings.len());
    for w in &entry.warnings {
        put(&mut rest, w.as_bytes());
    }
    put(&mut rest, &entry.peel);
    let mut out = Vec::with_capacity(rest.len() + 32);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&ENTRY_VERSION.to_le_bytes());
    out.extend_from_slice(&checksum(&rest).to_le_bytes());
    out.extend_from_slice(&rest);
    Some(out)
}

/// The key head, OBJ bytes and entry of an entry's bytes, or `None` if they are damaged.
fn decode(bytes: &[u8]) -> Option<(&[u8], &[u8], Entry)> {
    let rest = bytes.strip_prefix(MAGIC)?;
    let (version, rest) = rest.split_first_chunk::<4>()?;
    let (sum, rest) = rest.split_first_chunk::<8>()?;
    if u32::from_le_bytes(*version) != ENTRY_VERSION || u64::from_le_bytes(*sum) != checksum(rest) {
        return None;
    }
    let mut r = Reader::new(rest);
    let head = r.blob()?;
    let obj = r.blob()?;
    let text = |b: &[u8]| std::str::from_utf8(b).ok().map(str::to_owned);
    let mut mtl = Vec::new();
    for _ in 0..r.count()? {
        mtl.push((PathBuf::from(text(r.blob()?)?), r.blob()?.to_vec()));
    }
    let mut missing = Vec::new();
    for _ in 0..r.count()? {
        missing.push(PathBuf::from(text(r.blob()?)?));
    }
    let mut warnings = Vec::new();
    for _ in 0..r.count()? {
        warnings.push(text(r.blob()?)?);
    }
    let peel = r.blob()?.to_vec();
    if !r.rest.is_empty() {
        return None;
    }
    let entry = Entry {
        mtl,
        missing,
        warnings,
        peel,
    };
    Some((head, obj, entry))
}

/// Append `bytes` with its length (`u64`, little-endian).
fn put(out: &mut Vec<u8>, bytes: &[u8]) {
    out.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    out.extend_from_slice(bytes);
}

fn put_count(out: &mut Vec<u8>, n: usize) {
    out.extend_from_slice(&(n as u64).to_le_bytes());
}

/// Reads what [`put`] and [`put_count`] wrote; `None` past the end.
struct Reader<'a> {
    rest: &'a [u8],
}

impl<'a> Reader<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Reader { rest: bytes }
    }

    fn count(&mut self) -> Option<u64> {
        let (n, rest) = self.rest.split_first_chunk::<8>()?;
        self.rest = rest;
        Some(u64::from_le_bytes(*n))
    }

    fn blob(&mut self) -> Option<&'a [u8]> {
        let n = usize::try_from(self.count()?).ok()?;
        if n > self.rest.len() {
            return None;
        }
        let (blob, rest) = self.rest.split_at(n);
        self.rest = rest;
        Some(blob)
    }
}

/// A 64-bit checksum (a multiply-rotate chain over 8-byte words, then the length): it detects
/// damage, it does not stand in for the inputs (those are compared whole). Each step is a
/// bijection of the state for a fixed word and of the word for a fixed state, so any change
/// confined to one word always changes the result.
fn checksum(bytes: &[u8]) -> u64 {
    let step = |h: u64, w: u64| (h ^ w).wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(29);
    let mut chunks = bytes.chunks_exact(8);
    let mut h = 0x243F_6A88_85A3_08D3;
    for c in &mut chunks {
        h = step(h, u64::from_le_bytes(c.try_into().unwrap_or([0; 8])));
    }
    let mut tail = [0u8; 8];
    tail[..chunks.remainder().len()].copy_from_slice(chunks.remainder());
    h = step(h, u64::from_le_bytes(tail));
    step(h, bytes.len() as u64)
}
