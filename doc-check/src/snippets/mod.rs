//! The docs' snippets: each a whole crate, written out as a user would and built, so that an
//! example that drifts from the code fails CI (`bash .ci/snippets`).
//!
//! Conventions, in `README.md` and every `docs/**/*.md`:
//!
//! * `<!-- snippet: NAME [target=TRIPLE] [copy=DEST:SRC]... -->` on a line of its own starts a
//!   snippet: a crate made with `cargo new --bin --vcs none NAME` (the installed cargo's
//!   edition) and built with `cargo build` (`--target TRIPLE` with `target=`). `copy=` copies
//!   the repository's file `SRC` to `DEST` in the crate (an asset, say). NAME is a package
//!   name (`a-z`, digits, `-`, `_`, a letter first), unique across the docs.
//!   `extends=OTHER` starts from snippet OTHER's crate (its files, copies and target): a block
//!   of this snippet replaces OTHER's file of the same path (all of OTHER's `Cargo.toml`
//!   blocks when it has one), so a variant of an example shows only what differs.
//! * The snippet holds every fenced block after it up to the next snippet marker,
//!   `<!-- snippet-end -->` or the end of the file. A block names its file on its first line,
//!   in a comment: `# Cargo.toml`, `// src/main.rs`, `// build.rs: what it does`,
//!   `/* memory.x */`, `# .cargo/config.toml`. Its whole text, that line included, is the
//!   file; `Cargo.toml` blocks are appended to the manifest `cargo new` made (without its
//!   empty `[dependencies]`), and a block whose first line of TOML is not a table header is
//!   put under `[dependencies]`. A block of another language without a file comment (```` sh
//!   ````, ```` text ````) is left out.
//! * Peel's crates are path dependencies on a clone of Peel beside the user's crate:
//!   `peel-runtime = { path = "../peel/runtime", ... }`. The check points `../peel/DIR` at
//!   this checkout's `DIR`; a version requirement for a Peel crate is an error (none is
//!   published).
//! * Every ```` rust ```` and ```` toml ```` block belongs to a snippet, or follows
//!   `<!-- snippet: none [why] -->`, which leaves out the next block alone (for a fragment
//!   shown to explain, kept rare; `--list` lists them). Any other block is an error naming its
//!   file and line, so a new example cannot go unbuilt.
//!
//! A crate with tests, benches or examples (a file under `tests/`, `benches/` or `examples/`) is
//! built with `--all-targets`, so those compile too.
//!
//! Every snippet builds in one target directory, `target/snippets`, so Peel's crates compile
//! once per configuration; each crate resolves its own `Cargo.lock`.

pub mod crates;
pub mod manifest;

use std::path::Path;

use crate::docs::{Doc, Item, Problem};

/// A snippet: a crate of the docs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Snippet {
    /// The package name.
    pub name: String,
    /// The document.
    pub doc: String,
    /// The line of its marker.
    pub line: usize,
    /// `--target` for the build.
    pub target: Option<String>,
    /// Files of the repository copied into the crate: (in the crate, in the repository).
    pub copies: Vec<(String, String)>,
    /// The snippet it starts from (`extends=`), resolved by [`find`].
    pub extends: Option<String>,
    /// Its blocks, in order.
    pub files: Vec<SnippetFile>,
}

/// A block of a snippet and the file it is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SnippetFile {
    /// Path in the crate.
    pub path: String,
    /// The line of the block's opening fence.
    pub line: usize,
    /// The block's text.
    pub text: String,
}

/// A block left out with `<!-- snippet: none -->`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Exclusion {
    /// The document.
    pub doc: String,
    /// The line of the block's opening fence.
    pub line: usize,
    /// The marker's words after `none`.
    pub reason: String,
}

/// What the docs hold.
#[derive(Debug, Default)]
pub struct Found {
    /// Snippets, in the order of the documents.
    pub snippets: Vec<Snippet>,
    /// Blocks left out.
    pub exclusions: Vec<Exclusion>,
    /// Malformed markers and blocks, unclaimed blocks.
    pub problems: Vec<Problem>,
}

/// A snippet marker.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Marker {
    /// `<!-- snippet: NAME options -->`.
    Start {
        name: String,
        target: Option<String>,
        copies: Vec<(String, String)>,
        extends: Option<String>,
    },
    /// `<!-- snippet: none ... -->`.
    None(String),
    /// `<!-- snippet-end -->`.
    End,
}

const FORM: &str =
    "expected `<!-- snippet: NAME [target=TRIPLE] [copy=DEST:SRC] [extends=OTHER] -->`, \
                    `<!-- snippet: none -->` or `<!-- snippet-end -->`";

/// The marker on `line`, `None` when it holds none.
fn marker(line: &str) -> Option<Result<Marker, String>> {
    let t = line.trim();
    if !t.starts_with("<!-- snippet") {
        return None;
    }
    if t == "<!-- snippet-end -->" {
        return Some(Ok(Marker::End));
    }
    let Some(body) = t
        .strip_prefix("<!-- snippet:")
        .and_then(|b| b.strip_suffix("-->"))
    else {
        return Some(Err(format!("malformed snippet marker: {FORM}")));
    };
    let mut words = body.split_whitespace();
    let Some(name) = words.next() else {
        return Some(Err(format!("a snippet marker without a name: {FORM}")));
    };
    if name == "none" {
        return Some(Ok(Marker::None(words.collect::<Vec<_>>().join(" "))));
    }
    Some(start(name, words))
}

/// A start marker's name and options.
fn start<'a>(name: &str, options: impl Iterator<Item = &'a str>) -> Result<Marker, String> {
    let mut chars = name.chars();
    let valid = chars.next().is_some_and(|c| c.is_ascii_lowercase())
        && chars.all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '_');
    if !valid {
        return Err(format!(
            "snippet name {name:?}: a package name is lowercase letters, digits, `-` and `_`, \
             a letter first"
        ));
    }
    let (mut target, mut copies, mut extends) = (None, Vec::new(), None);
    for option in options {
        if let Some(t) = option.strip_prefix("target=") {
            if t.is_empty() || target.is_some() {
                return Err(format!(
                    "snippet {name}: one `target=TRIPLE`, not {option:?}"
                ));
            }
            target = Some(t.to_string());
        } else if let Some(c) = option.strip_prefix("copy=") {
            let (dest, src) = c
                .split_once(':')
                .filter(|(d, s)| relative(d) && relative(s))
                .ok_or_else(|| {
                    format!(
                        "snippet {name}: {option:?}: `copy=DEST:SRC`, two relative paths \
                         without `..` (DEST in the crate, SRC in the repository)"
                    )
                })?;
            copies.push((dest.to_string(), src.to_string()));
        } else if let Some(other) = option.strip_prefix("extends=") {
            if other.is_empty() || extends.is_some() {
                return Err(format!(
                    "snippet {name}: one `extends=OTHER`, not {option:?}"
                ));
            }
            extends = Some(other.to_string());
        } else {
            return Err(format!(
                "snippet {name}: unknown option {option:?} (options: target=TRIPLE, copy=DEST:SRC, \
                 extends=OTHER)"
            ));
        }
    }
    Ok(Marker::Start {
        name: name.to_string(),
        target,
        copies,
        extends,
    })
}

/// A relative path inside its folder: no leading `/`, no `..`, no empty part.
fn relative(path: &str) -> bool {
    !path.is_empty()
        && !path.starts_with('/')
        && path
            .split('/')
            .all(|part| !part.is_empty() && part != "." && part != "..")
        && path
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "._-/".contains(c))
}

/// The file a block's first line names in a comment (`# Cargo.toml`, `// src/main.rs: ...`,
/// `/* memory.x */`), if it names one: a relative path whose last part has an extension.
pub fn file_comment(block: &str) -> Option<&str> {
    let first = block.lines().next()?.trim();
    let inner = if let Some(rest) = first.strip_prefix("/*") {
        rest.strip_suffix("*/")?
    } else {
        first
            .strip_prefix("//")
            .or_else(|| first.strip_prefix('#'))?
    };
    let path = inner
        .trim()
        .split(|c: char| c.is_whitespace() || c == ':')
        .next()?;
    let last = path.rsplit('/').next()?;
    let named = last
        .rsplit_once('.')
        .is_some_and(|(_, ext)| !ext.is_empty() && ext.chars().all(|c| c.is_ascii_alphanumeric()));
    (relative(path) && named).then_some(path)
}

/// Whether a block of this language must belong to a snippet.
fn must_build(lang: &str) -> bool {
    matches!(lang, "rust" | "toml")
}

/// The snippets, exclusions and problems of `docs`; `root` is the repository (for `copy=`).
pub fn find(docs: &[Doc], root: &Path) -> Found {
    let mut found = Found::default();
    for doc in docs {
        scan(doc, root, &mut found);
    }
    let mut seen: Vec<&Snippet> = Vec::new();
    let mut duplicates = Vec::new();
    for s in &found.snippets {
        if let Some(first) = seen.iter().find(|f| f.name == s.name) {
            duplicates.push(Problem::new(
                &s.doc,
                s.line,
                format!(
                    "snippet {} is also at {}:{}: names are package names, one each",
                    s.name, first.doc, first.line
                ),
            ));
        } else {
            seen.push(s);
        }
    }
    found.problems.extend(duplicates);
    resolve_extends(&mut found);
    // A manifest that names Peel otherwise than as the clone beside the crate is not built.
    let mut bad = Vec::new();
    for s in &found.snippets {
        for f in s.files.iter().filter(|f| f.path == "Cargo.toml") {
            if let Err(problems) = manifest::rewrite(&f.text, root) {
                bad.push(s.name.clone());
                found.problems.extend(
                    problems
                        .into_iter()
                        .map(|(k, p)| Problem::new(&s.doc, f.line + 1 + k, p)),
                );
            }
        }
    }
    found.snippets.retain(|s| !bad.contains(&s.name));
    found
}

/// Each `extends=OTHER` snippet given OTHER's files (those it does not replace), copies and
/// target; an unknown or extended OTHER is a problem.
fn resolve_extends(found: &mut Found) {
    let bases = found.snippets.clone();
    for s in &mut found.snippets {
        let Some(other) = s.extends.clone() else {
            continue;
        };
        let Some(base) = bases.iter().find(|b| b.name == other) else {
            found.problems.push(Problem::new(
                &s.doc,
                s.line,
                format!("snippet {}: extends {other}, which no snippet is", s.name),
            ));
            continue;
        };
        if base.extends.is_some() {
            found.problems.push(Problem::new(
                &s.doc,
                s.line,
                format!(
                    "snippet {}: extends {other}, which extends another (one level only)",
                    s.name
                ),
            ));
            continue;
        }
        let own: Vec<String> = s.files.iter().map(|f| f.path.clone()).collect();
        let inherited = base
            .files
            .iter()
            .filter(|f| !own.contains(&f.path))
            .cloned();
        s.files = inherited.chain(s.files.drain(..)).collect();
        let own_copies = std::mem::take(&mut s.copies);
        let mut copies: Vec<(String, String)> = base
            .copies
            .iter()
            .filter(|(dest, _)| !own_copies.iter().any(|(d, _)| d == dest))
            .cloned()
            .collect();
        copies.extend(own_copies);
        s.copies = copies;
        if s.target.is_none() {
            s.target = base.target.clone();
        }
    }
}

/// Whether the snippet's crate has targets besides its binary (built with `--all-targets`).
pub fn has_other_targets(s: &Snippet) -> bool {
    s.files.iter().any(|f| {
        ["tests/", "benches/", "examples/"]
            .iter()
            .any(|dir| f.path.starts_with(dir))
    })
}

/// One document's snippets into `found`.
fn scan(doc: &Doc, root: &Path, found: &mut Found) {
    let name = doc.name.as_str();
    let mut open: Option<Snippet> = None;
    // `<!-- snippet: none -->` waiting for its block: (line, reason).
    let mut exclude: Option<(usize, String)> = None;
    let close = |open: &mut Option<Snippet>, found: &mut Found| {
        if let Some(s) = open.take() {
            if s.files.is_empty() {
                found.problems.push(Problem::new(
                    name,
                    s.line,
                    format!("snippet {} holds no block naming its file", s.name),
                ));
            } else {
                found.snippets.push(s);
            }
        }
    };
    let unused = |exclude: &mut Option<(usize, String)>, found: &mut Found| {
        if let Some((line, _)) = exclude.take() {
            found.problems.push(Problem::new(
                name,
                line,
                "`<!-- snippet: none -->` with no code block after it",
            ));
        }
    };
    for item in crate::docs::items(&doc.text) {
        match item {
            Item::Prose(line) => {
                let Some(m) = marker(line.text) else { continue };
                close(&mut open, found);
                unused(&mut exclude, found);
                match m {
                    Err(e) => found.problems.push(Problem::new(name, line.number, e)),
                    Ok(Marker::End) => {}
                    Ok(Marker::None(reason)) => exclude = Some((line.number, reason)),
                    Ok(Marker::Start {
                        name: snippet,
                        target,
                        copies,
                        extends,
                    }) => {
                        for (_, src) in &copies {
                            if !root.join(src).is_file() {
                                found.problems.push(Problem::new(
                                    name,
                                    line.number,
                                    format!(
                                        "snippet {snippet}: copy: no file {src} in the repository"
                                    ),
                                ));
                            }
                        }
                        open = Some(Snippet {
                            name: snippet,
                            doc: name.to_string(),
                            line: line.number,
                            target,
                            copies,
                            extends,
                            files: Vec::new(),
                        });
                    }
                }
            }
            Item::Block(block) => {
                if let Some((_, reason)) = exclude.take() {
                    found.exclusions.push(Exclusion {
                        doc: name.to_string(),
                        line: block.line,
                        reason,
                    });
                    continue;
                }
                let file = file_comment(&block.text);
                match (&mut open, file) {
                    (Some(s), Some(path)) => {
                        if path != "Cargo.toml" && s.files.iter().any(|f| f.path == path) {
                            found.problems.push(Problem::new(
                                name,
                                block.line,
                                format!("snippet {}: a second block for {path}", s.name),
                            ));
                        }
                        s.files.push(SnippetFile {
                            path: path.to_string(),
                            line: block.line,
                            text: block.text,
                        });
                    }
                    (Some(s), None) if must_build(&block.lang) => {
                        found.problems.push(Problem::new(
                            name,
                            block.line,
                            format!(
                                "a {} block of snippet {} names no file: its first line is a \
                                 comment with the file's path (`// src/main.rs`, `# Cargo.toml`)",
                                block.lang, s.name
                            ),
                        ));
                    }
                    (None, _) if must_build(&block.lang) => {
                        found.problems.push(Problem::new(
                            name,
                            block.line,
                            format!(
                                "a {} block in no snippet: put `<!-- snippet: NAME -->` before it \
                                 (or `<!-- snippet: none -->` for a fragment)",
                                block.lang
                            ),
                        ));
                    }
                    _ => {}
                }
            }
        }
    }
    close(&mut open, found);
    unused(&mut exclude, found);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn found(text: &str) -> Found {
        let doc = Doc {
            name: "README.md".into(),
            text: text.into(),
        };
        find(
            &[doc],
            Path::new(env!("CARGO_MANIFEST_DIR")).join("..").as_path(),
        )
    }

    #[test]
    fn markers() {
        assert_eq!(marker("text"), None);
        assert_eq!(marker("<!-- snippet-end -->"), Some(Ok(Marker::End)));
        assert_eq!(
            marker("  <!-- snippet: none a fragment -->"),
            Some(Ok(Marker::None("a fragment".into())))
        );
        assert_eq!(
            marker("<!-- snippet: fw target=thumbv7em-none-eabihf copy=assets/a.obj:fixtures/demo.obj -->"),
            Some(Ok(Marker::Start {
                name: "fw".into(),
                target: Some("thumbv7em-none-eabihf".into()),
                copies: vec![("assets/a.obj".into(), "fixtures/demo.obj".into())],
                extends: None,
            }))
        );
        for (bad, says) in [
            ("<!-- snippet fw -->", "malformed"),
            ("<!-- snippet: -->", "without a name"),
            ("<!-- snippet: Fw -->", "package name"),
            (
                "<!-- snippet: fw tagret=x -->",
                "unknown option \"tagret=x\"",
            ),
            ("<!-- snippet: fw copy=a -->", "copy=DEST:SRC"),
            ("<!-- snippet: fw copy=../a:b -->", "without `..`"),
            (
                "<!-- snippet: fw target=a target=b -->",
                "one `target=TRIPLE`",
            ),
        ] {
            let e = marker(bad).unwrap().unwrap_err();
            assert!(e.contains(says), "{bad}: {e}");
        }
    }

    #[test]
    fn file_comments() {
        assert_eq!(
            file_comment("# Cargo.toml\n[dependencies]"),
            Some("Cargo.toml")
        );
        assert_eq!(
            file_comment("// src/main.rs\nfn main() {}"),
            Some("src/main.rs")
        );
        assert_eq!(
            file_comment("// build.rs: writes the scene\n"),
            Some("build.rs")
        );
        assert_eq!(file_comment("/* memory.x */\nMEMORY"), Some("memory.x"));
        assert_eq!(
            file_comment("# .cargo/config.toml\n"),
            Some(".cargo/config.toml")
        );
        for none in [
            "# peel: build-time setup",
            "// firmware",
            "#[derive(Debug)]",
            "//! The crate",
            "// e.g. this",
            "// ../src/main.rs",
            "// /etc/passwd.rs",
            "fn main() {}",
            "",
        ] {
            assert_eq!(file_comment(none), None, "{none}");
        }
    }

    #[test]
    fn snippets_hold_the_blocks_up_to_the_next_marker() {
        let f = found(
            "# Title\n\n<!-- snippet: one target=thumbv6m-none-eabi -->\n\n```toml\n# Cargo.toml\n[dependencies]\n```\n\n\
             ```sh\ncargo build\n```\n\n```rust,no_run\n// src/main.rs\nfn main() {}\n```\n\
             <!-- snippet: two -->\n```rust\n// src/lib.rs\n```\n<!-- snippet-end -->\n\
             <!-- snippet: none shown for its shape -->\n```rust,ignore\nlet x = 1;\n```\n```text\nnot Rust\n```\n",
        );
        assert_eq!(f.problems, []);
        assert_eq!(f.snippets.len(), 2);
        let one = &f.snippets[0];
        assert_eq!((one.name.as_str(), one.line), ("one", 3));
        assert_eq!(one.target.as_deref(), Some("thumbv6m-none-eabi"));
        let files: Vec<(&str, usize)> = one
            .files
            .iter()
            .map(|f| (f.path.as_str(), f.line))
            .collect();
        assert_eq!(files, [("Cargo.toml", 5), ("src/main.rs", 14)]);
        assert_eq!(one.files[1].text, "// src/main.rs\nfn main() {}\n");
        assert_eq!(f.snippets[1].files[0].path, "src/lib.rs");
        assert_eq!(
            f.exclusions,
            [Exclusion {
                doc: "README.md".into(),
                line: 24,
                reason: "shown for its shape".into()
            }]
        );
    }

    #[test]
    fn every_rust_and_toml_block_is_claimed() {
        let f = found(
            "```rust\nfn main() {}\n```\n```toml\n[dependencies]\n```\n```sh\nls\n```\n\
             <!-- snippet: a -->\n```rust\nfn main() {}\n```\n<!-- snippet: b -->\n\
             <!-- snippet: none -->\n<!-- snippet: a -->\n```rust\n// src/main.rs\n```\n\
             ```rust\n// src/main.rs\n```\n<!-- snippet: c copy=x:no/such.file -->\n```toml\n# Cargo.toml\n```\n\
             <!-- snippet: c -->\n```toml\n# Cargo.toml\n```\n",
        );
        let problems: Vec<String> = f.problems.iter().map(|p| p.to_string()).collect();
        let expect = [
            "README.md:1: a rust block in no snippet",
            "README.md:4: a toml block in no snippet",
            "README.md:11: a rust block of snippet a names no file",
            "README.md:10: snippet a holds no block",
            "README.md:14: snippet b holds no block",
            "README.md:15: `<!-- snippet: none -->` with no code block",
            "README.md:20: snippet a: a second block for src/main.rs",
            "README.md:23: snippet c: copy: no file no/such.file",
            "README.md:27: snippet c is also at README.md:23",
        ];
        assert_eq!(problems.len(), expect.len(), "{problems:#?}");
        for (p, e) in problems.iter().zip(expect) {
            assert!(p.starts_with(e), "{p}\n  expected: {e}");
        }
    }
    #[test]
    fn a_snippet_that_extends_another_replaces_its_files_of_the_same_path() {
        let f = found(
            "<!-- snippet: base target=thumbv7em-none-eabihf copy=assets/a.obj:fixtures/demo.obj -->\n\
             ```toml\n# Cargo.toml\n[dependencies]\na = \"1\"\n```\n```toml\n# Cargo.toml\n[profile.dev]\n```\n\
             ```rust\n// build.rs\nfn main() {}\n```\n```rust\n// src/main.rs\nfn main() {}\n```\n\
             <!-- snippet: variant extends=base -->\n```toml\n# Cargo.toml\n[dependencies]\nb = \"1\"\n```\n\
             ```rust\n// src/main.rs\nfn main() { let _ = 1; }\n```\n\
             <!-- snippet: lost extends=nothing -->\n```rust\n// src/main.rs\n```\n\
             <!-- snippet: deep extends=variant -->\n```rust\n// src/main.rs\n```\n\
             <!-- snippet: tested -->\n```rust\n// tests/a.rs\n```\n",
        );
        let problems: Vec<String> = f.problems.iter().map(|p| p.to_string()).collect();
        assert_eq!(problems.len(), 2, "{problems:#?}");
        assert!(problems[0].contains("snippet lost: extends nothing, which no snippet is"));
        assert!(problems[1].contains("snippet deep: extends variant, which extends another"));
        let variant = &f.snippets[1];
        let files: Vec<(&str, &str)> = variant
            .files
            .iter()
            .map(|f| (f.path.as_str(), f.text.as_str()))
            .collect();
        assert_eq!(
            files,
            [
                ("build.rs", "// build.rs\nfn main() {}\n"),
                ("Cargo.toml", "# Cargo.toml\n[dependencies]\nb = \"1\"\n"),
                ("src/main.rs", "// src/main.rs\nfn main() { let _ = 1; }\n"),
            ]
        );
        assert_eq!(variant.target.as_deref(), Some("thumbv7em-none-eabihf"));
        assert_eq!(
            variant.copies,
            [("assets/a.obj".to_string(), "fixtures/demo.obj".to_string())]
        );
        assert!(!has_other_targets(variant));
        assert!(has_other_targets(&f.snippets[4]));
    }
}
