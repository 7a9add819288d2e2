//! What the CLI tests share: running `peel`, the fixtures, and a refusal's checks.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn peel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_peel"))
        .args(args)
        .output()
        .expect("run peel")
}

pub fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

pub fn fixture(name: &str) -> String {
    fixtures().join(name).to_string_lossy().into_owned()
}

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `peel args` expecting a failure whose message contains every one of `says`, and no
/// file in `dir` afterwards (nothing written, no temporary file left).
pub fn refused(dir: &Path, args: &[&str], says: &[&str]) {
    let o = peel(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{args:?} succeeded");
    for s in says {
        assert!(err.contains(s), "{args:?}: no `{s}` in: {err}");
    }
    let left: Vec<_> = std::fs::read_dir(dir).unwrap().collect();
    assert!(left.is_empty(), "{args:?} left {left:?}");
}
