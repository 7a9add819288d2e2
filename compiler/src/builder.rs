//! Builder: the library API for build scripts (owned by the integrator).

/// Compiles an OBJ into `OUT_DIR` from a build script.
#[derive(Debug, Clone, Default)]
pub struct Builder {}
