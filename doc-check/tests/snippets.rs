//! `peel-doc-check snippets` on a scratch repository: each snippet is made a crate and built,
//! one line each; a build error, or a rust block in no snippet, fails the run.

use std::path::Path;
use std::process::{Command, Output};

fn snippets(root: &Path, args: &[&str]) -> Output {
    // The crates are made in the temporary folder: the scratch repository's, so that the
    // failed ones kept for a look go with it.
    let tmp = root.join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    Command::new(env!("CARGO_BIN_EXE_peel-doc-check"))
        .env("TMPDIR", &tmp)
        .arg("snippets")
        .args(args)
        .arg("--root")
        .arg(root)
        .output()
        .unwrap()
}

const FINE: &str =
    "# Scratch\n\n<!-- snippet: fine -->\n\n```toml\n# Cargo.toml\n[dependencies]\n```\n\n\
```rust\n// src/main.rs\nfn main() {\n    println!(\"{}\", greeting::TEXT);\n}\n```\n\n\
```rust\n// src/greeting.rs\npub const TEXT: &str = \"hi\";\n```\n\n<!-- snippet-end -->\n";

const BROKEN: &str = "<!-- snippet: broken -->\n```rust\n// src/main.rs\nfn main() {\n    let _x: u32 = \"text\";\n}\n```\n";

fn out(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr)
}

#[test]
fn each_snippet_builds_as_a_crate() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    // `mod greeting;` is missing: the snippet fails until it is added.
    std::fs::write(root.join("README.md"), FINE).unwrap();
    let o = snippets(root, &[]);
    assert!(!o.status.success());
    assert!(
        out(&o).contains("FAILED  fine (README.md:3)"),
        "{}",
        out(&o)
    );
    assert!(out(&o).contains("error[E0433]"), "{}", out(&o));
    std::fs::write(
        root.join("README.md"),
        FINE.replace("fn main() {\n", "mod greeting;\n\nfn main() {\n"),
    )
    .unwrap();
    let o = snippets(root, &[]);
    assert!(o.status.success(), "{}", out(&o));
    assert!(
        out(&o).contains("ok      fine (README.md:3)"),
        "{}",
        out(&o)
    );
    assert!(root.join("target/snippets/debug/fine").is_file());
}

#[test]
fn a_failed_build_and_an_unclaimed_block_fail_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    std::fs::create_dir(root.join("docs")).unwrap();
    std::fs::write(root.join("README.md"), BROKEN).unwrap();
    std::fs::write(
        root.join("docs/guide.md"),
        "Text.\n\n```rust\nfn unclaimed() {}\n```\n\n<!-- snippet: none a fragment -->\n```toml\nx = 1\n```\n",
    )
    .unwrap();
    let o = snippets(root, &[]);
    assert!(!o.status.success());
    let text = out(&o);
    assert!(text.contains("FAILED  broken (README.md:1)"), "{text}");
    assert!(text.contains("error[E0308]: mismatched types"), "{text}");
    assert!(
        text.contains("docs/guide.md:3: a rust block in no snippet"),
        "{text}"
    );
    assert!(
        text.contains("snippets: 0 built, 1 failed, 1 blocks left out, 1 problems"),
        "{text}"
    );
    let o = snippets(root, &["--list"]);
    assert!(!o.status.success());
    let text = out(&o);
    assert!(text.contains("broken  README.md:1  src/main.rs"), "{text}");
    assert!(
        text.contains("left out: docs/guide.md:8  a fragment"),
        "{text}"
    );
    let o = snippets(root, &["--only", "other"]);
    assert!(
        out(&o).contains("--only: no snippet \"other\""),
        "{}",
        out(&o)
    );
}

#[test]
fn peel_crates_are_the_checkout() {
    // The dependency line a user writes, with Peel cloned beside the crate; refused as a
    // version (none is published).
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let doc = "<!-- snippet: user -->\n```toml\n# Cargo.toml\n[dependencies]\npeel-runtime = \"0.1\"\n```\n\
               ```rust\n// src/main.rs\nfn main() {}\n```\n";
    std::fs::write(root.join("README.md"), doc).unwrap();
    let o = snippets(root, &[]);
    assert!(!o.status.success());
    assert!(
        out(&o).contains(
            "README.md:5: peel-runtime: a path dependency on Peel cloned beside the crate"
        ),
        "{}",
        out(&o)
    );
}
