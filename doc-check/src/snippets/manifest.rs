//! A snippet's `Cargo.toml`: its blocks appended to the manifest `cargo new` made, and Peel's
//! crates, written as path dependencies on a clone beside the crate (`../peel/runtime`),
//! pointed at this checkout.

use std::path::Path;

/// Where the docs say Peel is: cloned beside the user's crate.
const CLONE: &str = "../peel";

/// The key of a `key = value` line, unquoted (`None` for other lines).
fn key(line: &str) -> Option<&str> {
    let (k, _) = line.split_once('=')?;
    let k = k.trim().trim_matches('"');
    (!k.is_empty() && !k.starts_with('[') && !k.starts_with('#')).then_some(k)
}

/// A table header's name (`[build-dependencies]` gives `build-dependencies`).
fn header(line: &str) -> Option<&str> {
    let t = line.trim();
    let t = t.strip_prefix("[[").or_else(|| t.strip_prefix('['))?;
    let end = t.find(']')?;
    Some(t[..end].trim())
}

/// Whether a table holds dependencies (`dependencies`, `build-dependencies`,
/// `target.'cfg(...)'.dependencies`, ...).
fn dependency_table(name: &str) -> bool {
    name.rsplit('.')
        .next()
        .is_some_and(|last| last.ends_with("dependencies"))
}

/// The path a Peel crate's entry gives: `"../peel/runtime"` gives `runtime`.
fn clone_path(entry: &str) -> Option<&str> {
    let at = entry.find(&format!("\"{CLONE}/"))?;
    let rest = &entry[at + CLONE.len() + 2..];
    Some(&rest[..rest.find('"')?])
}

/// The problem with a Peel crate's entry, if any: it must be a path into the clone.
fn peel_entry(name: &str, entry: &str) -> Option<String> {
    let compact: String = entry.chars().filter(|c| !c.is_whitespace()).collect();
    if compact.contains(&format!("path=\"{CLONE}/")) {
        return None;
    }
    let dir = name.strip_prefix("peel-").unwrap_or(name);
    let why = if compact.contains("path=") {
        "its path is not in the clone"
    } else {
        "no version of Peel is published"
    };
    Some(format!(
        "{name}: a path dependency on Peel cloned beside the crate, \
         `{name} = {{ path = \"{CLONE}/{dir}\", ... }}` ({why})"
    ))
}

/// Check a `Cargo.toml` block and point its `../peel/DIR` paths at `root/DIR`; the problems
/// are (line in the block, 0-based; message).
pub fn rewrite(block: &str, root: &Path) -> Result<String, Vec<(usize, String)>> {
    let mut problems = Vec::new();
    let mut out = String::new();
    // A `[dependencies.peel-x]` table: its name and header line, and whether it has a path.
    let mut table: Option<String> = None;
    let mut peel_table: Option<(String, usize, String)> = None;
    let end_table = |peel: &mut Option<(String, usize, String)>,
                     problems: &mut Vec<(usize, String)>| {
        if let Some((name, line, entry)) = peel.take() {
            if let Some(p) = peel_entry(&name, &entry) {
                problems.push((line, p));
            }
        }
    };
    for (k, line) in block.lines().enumerate() {
        let code = line.split('#').next().unwrap_or("");
        if let Some(h) = header(code) {
            end_table(&mut peel_table, &mut problems);
            if let Some((deps, name)) = h.rsplit_once('.') {
                if dependency_table(deps) && name.trim_matches('"').starts_with("peel-") {
                    peel_table = Some((name.trim_matches('"').to_string(), k, String::new()));
                }
            }
            table = Some(h.to_string());
        } else if let Some((_, _, entry)) = &mut peel_table {
            entry.push_str(code);
            entry.push(' ');
        } else if let Some(name) = key(code) {
            // A line before any header goes under `[dependencies]` (see `manifest`).
            let deps = table.as_deref().is_none_or(dependency_table);
            if deps && name.starts_with("peel-") {
                if let Some(p) = peel_entry(name, code) {
                    problems.push((k, p));
                }
            }
        }
        let mut rest = line;
        while let Some(dir) = clone_path(rest) {
            let at = rest.find(&format!("\"{CLONE}/")).unwrap_or(0);
            let target = root.join(dir);
            if !target.join("Cargo.toml").is_file() {
                problems.push((
                    k,
                    format!("{CLONE}/{dir}: no crate there in Peel's repository"),
                ));
            }
            out.push_str(&rest[..at]);
            out.push_str(&toml_string(&target.to_string_lossy()));
            rest = &rest[at + CLONE.len() + 3 + dir.len()..];
        }
        out.push_str(rest);
        out.push('\n');
    }
    end_table(&mut peel_table, &mut problems);
    if problems.is_empty() {
        Ok(out)
    } else {
        Err(problems)
    }
}

/// `s` as a TOML basic string.
fn toml_string(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// The manifest of a snippet: `generated` (what `cargo new` wrote) without its empty
/// `[dependencies]` table, then each block; a block whose first line of TOML is not a table
/// header goes under `[dependencies]`.
pub fn manifest(generated: &str, blocks: &[String]) -> String {
    let mut out = generated.trim_end().to_string();
    if let Some(rest) = out.strip_suffix("[dependencies]") {
        out = rest.trim_end().to_string();
    }
    out.push('\n');
    for block in blocks {
        out.push('\n');
        let first = block
            .lines()
            .map(str::trim)
            .find(|l| !l.is_empty() && !l.starts_with('#'));
        if first.is_some_and(|l| !l.starts_with('[')) {
            out.push_str("[dependencies]\n");
        }
        out.push_str(block);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn root() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
    }

    #[test]
    fn peel_paths_point_at_the_checkout() {
        let block = "# Cargo.toml\n[dependencies]\npeel-runtime = { path = \"../peel/runtime\", default-features = false }\n\
                     [build-dependencies.peel-compiler]\npath = \"../peel/compiler\"\ndefault-features = false\n";
        let out = rewrite(block, &root()).unwrap();
        let runtime = root().join("runtime");
        assert!(
            out.contains(&format!(
                "peel-runtime = {{ path = \"{}\", default",
                runtime.display()
            )),
            "{out}"
        );
        assert!(out.contains(&format!(
            "path = \"{}\"\n",
            root().join("compiler").display()
        )));
        assert_eq!(out.lines().count(), block.lines().count());
    }

    #[test]
    fn peel_crates_without_the_clone_are_refused() {
        let block =
            "[dependencies]\npeel-runtime = { version = \"0.1\" }\npeel-compiler = \"0.1\"\n\
                     glam = \"0.34\"\n[dev-dependencies.peel-compiler]\nversion = \"0.1\"\n\
                     [build-dependencies]\npeel-compiler = { path = \"../peel/compilr\" }\n\
                     peel-runtime = { path = \"../runtime\" }\n[package.metadata]\npeel-x = 1\n";
        let problems = rewrite(block, &root()).unwrap_err();
        let lines: Vec<usize> = problems.iter().map(|(l, _)| *l).collect();
        assert_eq!(lines, [1, 2, 4, 7, 8], "{problems:#?}");
        assert!(problems[0].1.contains(
            "peel-runtime: a path dependency on Peel cloned beside the crate, \
             `peel-runtime = { path = \"../peel/runtime\", ... }` (no version of Peel is published)"
        ));
        assert!(problems[2]
            .1
            .contains("peel-compiler = { path = \"../peel/compiler\""));
        assert!(problems[3].1.contains("../peel/compilr: no crate there"));
        assert!(problems[4].1.contains("its path is not in the clone"));
        // A bare line (under `[dependencies]` once appended) is checked too.
        assert_eq!(
            rewrite("peel-runtime = \"0.1\"\n", &root()).unwrap_err()[0].0,
            0
        );
    }

    #[test]
    fn blocks_append_to_the_generated_manifest() {
        let generated =
            "[package]\nname = \"a\"\nversion = \"0.1.0\"\nedition = \"2024\"\n\n[dependencies]\n";
        let m = manifest(
            generated,
            &[
                "# Cargo.toml\n[dependencies]\nx = \"1\"\n".into(),
                "# more\ny = \"2\"\n".into(),
            ],
        );
        assert_eq!(
            m,
            "[package]\nname = \"a\"\nversion = \"0.1.0\"\nedition = \"2024\"\n\n\
             # Cargo.toml\n[dependencies]\nx = \"1\"\n\n[dependencies]\n# more\ny = \"2\"\n"
        );
        // A generated manifest with dependencies keeps them.
        let kept = manifest("[package]\n[dependencies]\nz = \"1\"\n", &[]);
        assert_eq!(kept, "[package]\n[dependencies]\nz = \"1\"\n");
    }
}
