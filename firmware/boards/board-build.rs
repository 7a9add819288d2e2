// The build script of every board crate (each crate's `build.rs` includes this file, so the
// boards share one copy of it): compile the scene at build time, sized for the panel, and put
// `memory.x` where the linker finds it.
//
// The scene is the repository's demo (`fixtures/demo.obj`) unless `PEEL_BOARD_MESH` names
// another OBJ. A relative path is taken from this crate's folder: cargo runs build scripts
// there, and `cargo build` is run there too (its `.cargo/config.toml` picks the target), so
// it is the folder the command is typed in, e.g.
// `PEEL_BOARD_MESH=../../../fixtures/cube.obj cargo build --release`. An absolute path is used
// as it is. A path that cannot be read fails the build with a message naming the variable, the
// path as given and as resolved; an OBJ that does not compile, with the compiler's error.

use std::ffi::OsString;
use std::path::PathBuf;
use std::process::ExitCode;

/// The panel, in landscape: the size the span memory is measured at.
const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;

/// The variable that chooses the mesh.
const MESH_VAR: &str = "PEEL_BOARD_MESH";
/// The mesh without it, relative to this crate's folder.
const DEFAULT_MESH: &str = "../../../fixtures/demo.obj";

fn main() -> ExitCode {
    match build() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Cargo shows a failed build script's stderr: this line, without a panic's noise.
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn build() -> Result<(), String> {
    println!("cargo:rerun-if-env-changed={MESH_VAR}");
    let crate_dir = PathBuf::from(env("CARGO_MANIFEST_DIR")?);
    let out = PathBuf::from(env("OUT_DIR")?);
    // The path as given, and how the messages name it.
    let (given, mesh) = match std::env::var_os(MESH_VAR) {
        Some(value) if value.is_empty() => {
            return Err(format!(
                "{MESH_VAR} is set but empty: unset it for the demo, or name an OBJ file"
            ))
        }
        Some(value) => {
            let given = PathBuf::from(value);
            let mesh = format!("{MESH_VAR}={:?}", given.display());
            (given, mesh)
        }
        None => (
            PathBuf::from(DEFAULT_MESH),
            format!("the default mesh {DEFAULT_MESH:?} ({MESH_VAR} is unset)"),
        ),
    };
    // `join` keeps an absolute path as it is.
    let path = crate_dir.join(&given);
    let how = format!(
        "note: a relative {MESH_VAR} is taken from this board's folder, {}; an absolute one is \
         used as it is",
        crate_dir.display()
    );
    match std::fs::metadata(&path) {
        Ok(m) if m.is_file() => {}
        Ok(_) => return Err(format!("{mesh}: {} is not a file\n{how}", path.display())),
        Err(e) => {
            return Err(format!(
                "{mesh}: cannot read {}: {e}\n{how}",
                path.display()
            ))
        }
    }
    // Writes `$OUT_DIR/scene.peel` and its sizes, `$OUT_DIR/scene.rs` (`STACK`, `VERTS`,
    // `SPANS_PER_ROW` measured over an orbit at 320x240, ...), whatever the OBJ's name. The
    // path as given (cargo runs this in the crate's folder): the compile cache keys on it, so
    // both boards share the demo's compile, and the compiler's warnings name it as typed.
    peel_compiler::Builder::new(&given)
        .out_name("scene.peel")
        .image_size(WIDTH, HEIGHT)
        .compile()
        .map_err(|e| format!("{mesh}: {e}"))?;
    std::fs::copy("memory.x", out.join("memory.x"))
        .map_err(|e| format!("copy memory.x to {}: {e}", out.display()))?;
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    Ok(())
}

/// A variable cargo sets for build scripts.
fn env(name: &str) -> Result<OsString, String> {
    std::env::var_os(name).ok_or_else(|| format!("{name} is not set (not run by cargo?)"))
}
