//! A snippet made into a crate, as a user would make it, and built.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::{manifest, Snippet};

/// Where the snippets are made and built.
pub struct Workshop {
    /// The repository (Peel's clone, for the crates' paths and `copy=`).
    pub root: PathBuf,
    /// The folder the crates are made in (outside the repository's workspace).
    pub crates: PathBuf,
    /// The target directory every snippet shares.
    pub target_dir: PathBuf,
    /// The cargo to run.
    pub cargo: PathBuf,
}

/// Lines of cargo's output kept for a failed build.
const EXCERPT_LINES: usize = 30;

impl Workshop {
    /// `cargo` as the environment names it (as `cargo run` sets `CARGO`), run from `root`.
    pub fn new(root: &Path, crates: PathBuf) -> Workshop {
        Workshop {
            root: root.to_path_buf(),
            crates,
            target_dir: root.join("target").join("snippets"),
            cargo: std::env::var_os("CARGO").map_or_else(|| "cargo".into(), PathBuf::from),
        }
    }

    /// A cargo command in `dir`, without the variables `cargo run` set for this tool.
    fn cargo(&self, dir: &Path) -> Command {
        let mut c = Command::new(&self.cargo);
        c.current_dir(dir)
            .env("CARGO_TARGET_DIR", &self.target_dir)
            .env("CARGO_TERM_COLOR", "never");
        for (name, _) in std::env::vars_os() {
            let n = name.to_string_lossy();
            if n.starts_with("CARGO_PKG_")
                || [
                    "CARGO_MANIFEST_DIR",
                    "CARGO_MANIFEST_PATH",
                    "CARGO_CRATE_NAME",
                ]
                .contains(&n.as_ref())
                || n.starts_with("CARGO_BIN_")
                || n == "CARGO_PRIMARY_PACKAGE"
            {
                c.env_remove(&name);
            }
        }
        c
    }

    /// Make the snippet's crate (a fresh one) and build it; `Err` holds what went wrong
    /// (cargo's first error and what follows it).
    pub fn build(&self, s: &Snippet) -> Result<(), String> {
        let dir = self.make(s)?;
        let mut build = self.cargo(&dir);
        build.arg("build");
        if super::has_other_targets(s) {
            build.arg("--all-targets");
        }
        if let Some(t) = &s.target {
            build.args(["--target", t]);
        }
        run(&mut build, "cargo build")
    }

    /// The snippet's crate, made with `cargo new` and its files.
    pub fn make(&self, s: &Snippet) -> Result<PathBuf, String> {
        let dir = self.crates.join(&s.name);
        if dir.exists() {
            std::fs::remove_dir_all(&dir)
                .map_err(|e| format!("{}: cannot remove: {e}", dir.display()))?;
        }
        std::fs::create_dir_all(&self.crates)
            .map_err(|e| format!("{}: cannot create: {e}", self.crates.display()))?;
        run(
            self.cargo(&self.crates)
                .args(["new", "--bin", "--vcs", "none", "--quiet"])
                .arg(&s.name),
            "cargo new",
        )?;
        let toml = dir.join("Cargo.toml");
        let generated = std::fs::read_to_string(&toml)
            .map_err(|e| format!("{}: cannot read: {e}", toml.display()))?;
        let mut blocks = Vec::new();
        for f in s.files.iter().filter(|f| f.path == "Cargo.toml") {
            blocks.push(manifest::rewrite(&f.text, &self.root).map_err(|problems| {
                problems
                    .iter()
                    .map(|(k, p)| format!("{}:{}: {p}", s.doc, f.line + 1 + k))
                    .collect::<Vec<_>>()
                    .join("\n")
            })?);
        }
        write(&toml, &manifest::manifest(&generated, &blocks))?;
        for f in s.files.iter().filter(|f| f.path != "Cargo.toml") {
            write(&dir.join(&f.path), &f.text)?;
        }
        for (dest, src) in &s.copies {
            let (from, to) = (self.root.join(src), dir.join(dest));
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent)
                    .map_err(|e| format!("{}: cannot create: {e}", parent.display()))?;
            }
            std::fs::copy(&from, &to)
                .map_err(|e| format!("copy {} to {}: {e}", from.display(), to.display()))?;
        }
        Ok(dir)
    }
}

/// Write `text` to `path`, making its folders.
fn write(path: &Path, text: &str) -> Result<(), String> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)
            .map_err(|e| format!("{}: cannot create: {e}", parent.display()))?;
    }
    std::fs::write(path, text).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// Run `command`; on failure, what it said from its first error on.
fn run(command: &mut Command, what: &str) -> Result<(), String> {
    let out = command
        .output()
        .map_err(|e| format!("{what}: cannot run: {e}"))?;
    if out.status.success() {
        return Ok(());
    }
    let text =
        String::from_utf8_lossy(&out.stderr).to_string() + &String::from_utf8_lossy(&out.stdout);
    Err(format!("{what} failed:\n{}", excerpt(&text)))
}

/// From the first `error` line on, at most [`EXCERPT_LINES`] lines (the last ones when no line
/// says `error`).
pub fn excerpt(output: &str) -> String {
    let lines: Vec<&str> = output.lines().collect();
    let first = lines
        .iter()
        .position(|l| l.starts_with("error"))
        .unwrap_or(lines.len().saturating_sub(EXCERPT_LINES));
    lines[first..]
        .iter()
        .take(EXCERPT_LINES)
        .copied()
        .collect::<Vec<_>>()
        .join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn excerpts_start_at_the_first_error() {
        let out = "   Compiling a v0.1.0\nwarning: unused\nerror[E0425]: cannot find value `x`\n --> src/main.rs:1:1\n";
        assert_eq!(
            excerpt(out),
            "error[E0425]: cannot find value `x`\n --> src/main.rs:1:1"
        );
        let long: String = (0..100).map(|k| format!("line {k}\n")).collect();
        let e = excerpt(&long);
        assert_eq!(e.lines().count(), EXCERPT_LINES);
        assert!(e.ends_with("line 99"));
    }
}
