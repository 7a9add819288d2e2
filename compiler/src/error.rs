//! The compiler's errors: each names the file (and line or byte offset where it can) and what is wrong.

use std::path::PathBuf;

/// Everything that can stop a compile.
#[derive(Debug, thiserror::Error)]
pub enum CompileError {
    /// The file could not be read at all.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the OS said.
        source: std::io::Error,
    },
    /// The OBJ text is malformed (bad number, bad index syntax, ...).
    #[error("{path}:{line}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("{path}:{line}: vertex coordinate is not finite ({value})")]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// 1-based line of the `v` statement.
        line: usize,
        /// The offending value as written.
        value: String,
    },
    /// A face refers to a vertex that does not exist.
    #[error("{path}:{line}: vertex index {index} out of range ({count} vertices are defined before this line)")]
    IndexOutOfRange {
        /// The file.
        path: PathBuf,
        /// 1-based line of the `f` statement.
        line: usize,
        /// The index as written (1-based or negative, OBJ style).
        index: i64,
        /// How many vertices were defined before the `f` line (OBJ indices refer backwards).
        count: usize,
    },
    /// The OBJ parser (tobj) failed where the line check found nothing wrong; no line is known.
    #[error("{path}: cannot parse: {message}")]
    Obj {
        /// The file.
        path: PathBuf,
        /// What tobj said.
        message: String,
    },
    /// The scene holds no face to draw.
    #[error("{path}: the scene has no faces")]
    NoFaces {
        /// The file.
        path: PathBuf,
    },
    /// Every face of the scene has zero area (repeated or collinear corners, at the
    /// compiler's precision): the compiled scene would hold nothing to draw.
    #[error("{path}: {}: there is nothing to draw", all_degenerate(*faces))]
    AllDegenerate {
        /// The file.
        path: PathBuf,
        /// How many faces it has.
        faces: usize,
    },
    /// The input is larger than the compiler accepts.
    #[error("{path}: {message}")]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Which limit was exceeded.
        message: String,
    },
    /// A statement of an MTL file that a used material needs is malformed (a `map_Kd` option).
    #[error("{path}:{line}: {message}")]
    Mtl {
        /// The MTL file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A texture image (MTL `map_Kd`) could not be read: missing, or not a file.
    #[error("{mtl}:{line}: texture {image}: cannot read: {source}")]
    TextureFile {
        /// The image file.
        image: PathBuf,
        /// The MTL file of the `map_Kd` statement.
        mtl: PathBuf,
        /// 1-based line of the `map_Kd` statement.
        line: usize,
        /// What the OS said.
        source: std::io::Error,
    },
    /// A texture image could not be decoded (not a PNG or JPEG, damaged, too large to decode).
    #[error("{mtl}:{line}: texture {image}: cannot decode: {message}")]
    TextureImage {
        /// The image file.
        image: PathBuf,
        /// The MTL file of the `map_Kd` statement.
        mtl: PathBuf,
        /// 1-based line of the `map_Kd` statement.
        line: usize,
        /// What the decoder said.
        message: String,
    },
    /// Without resampling, a texture whose side is not a power of two or is over the limit.
    #[error(
        "{mtl}:{line}: texture {image} is {width}x{height}: without resampling (--no-resample) \
         each side must be a power of two of at most {max} texels (--max-texture)"
    )]
    TextureSize {
        /// The image file.
        image: PathBuf,
        /// The MTL file of the `map_Kd` statement.
        mtl: PathBuf,
        /// 1-based line of the `map_Kd` statement.
        line: usize,
        /// The image's width in pixels.
        width: u32,
        /// The image's height in pixels.
        height: u32,
        /// The largest side allowed.
        max: u32,
    },
    /// A textured face in a compiler built without the `textures` feature, which decodes images.
    #[error(
        "{mtl}:{line}: texture {image}: this compiler was built without the `textures` feature \
         (enable it on peel-compiler to compile textured materials)"
    )]
    TexturesOff {
        /// The image file.
        image: PathBuf,
        /// The MTL file of the `map_Kd` statement.
        mtl: PathBuf,
        /// 1-based line of the `map_Kd` statement.
        line: usize,
    },
    /// More textures than a file holds (`MAX_TEXTURES`).
    #[error("{path}: the faces use {count} textures: a file holds at most {max}")]
    TooManyTextures {
        /// The OBJ file.
        path: PathBuf,
        /// The textures used (counted up to one past the limit).
        count: usize,
        /// The most a file holds.
        max: u32,
    },
    /// A texture size limit that is not a power of two from 1 to 1024.
    #[error(
        "invalid texture size limit {max} (--max-texture): a power of two from 1 to {largest}"
    )]
    MaxTexture {
        /// The limit given.
        max: u32,
        /// The largest limit (`2^MAX_TEXTURE_LOG2`).
        largest: u32,
    },
    /// A light the compiler cannot shade with or cast shadows from (a direction of no length, a
    /// position that is not finite, a point light too far for exact shadows).
    #[error("{0}")]
    Light(String),
    /// A crease angle of smooth shading that is not a number of degrees from 0 to 180.
    #[error(
        "invalid crease angle {degrees} (--crease): it is the angle in degrees, from 0 to 180, \
         above which two faces meet at a sharp edge"
    )]
    Crease {
        /// The angle given.
        degrees: f64,
    },
    /// An internal invariant of the display tree was violated: a bug, reported instead of a hang.
    #[error("internal invariant violated: {0}")]
    Invariant(String),
    /// Writing the output failed.
    #[error("{path}: cannot write: {source}")]
    Write {
        /// The output file.
        path: PathBuf,
        /// What the OS said.
        source: std::io::Error,
    },
    /// Encoding the tree failed.
    #[error("cannot encode the tree: {0}")]
    Encode(String),
    /// An object of a scene of parts whose name a file of parts cannot hold: empty, longer
    /// than `MAX_NAME` bytes, or another object's (the renderer finds objects by name).
    #[error("object name `{name}`: {problem}")]
    PartName {
        /// The name given.
        name: String,
        /// What is wrong with it.
        problem: String,
    },
    /// A scene of parts with no part, or more than a file of parts holds.
    #[error("{parts} parts (the world and the objects): a file of parts holds 1 to {max}")]
    PartCount {
        /// The parts given.
        parts: usize,
        /// The most a file holds (`MAX_PARTS`).
        max: u32,
    },
    /// A compiled file is not valid (for `inspect`, `dump`, `render`).
    #[error("{path}: invalid .peel file: {message}")]
    BadPeel {
        /// The file.
        path: PathBuf,
        /// What the reader found wrong.
        message: String,
    },
}

/// "all 3 faces are degenerate (...)", "the only face is degenerate (...)".
fn all_degenerate(faces: usize) -> String {
    let what = "(zero area: repeated or collinear corners, at the compiler's precision)";
    match faces {
        1 => format!("the only face is degenerate {what}"),
        n => format!("all {n} faces are degenerate {what}"),
    }
}
