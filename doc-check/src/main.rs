//! The docs' two checks: every snippet builds as a user's crate (`snippets`, see
//! [`snippets`]), and every marked figure is the one the committed results give (`figures`,
//! see [`figures`]). CI runs them as `bash .ci/snippets` and `bash .ci/figures`.

mod docs;
mod figures;
mod snippets;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

const USAGE: &str = "\
usage: peel-doc-check snippets [--list] [--only NAME,...] [--root DIR]
       peel-doc-check figures [--check] [--root DIR]

snippets   build every snippet of README.md and docs/**/*.md as a fresh crate (one line each)
  --list   list the snippets, their files and the blocks left out; build nothing
  --only   build only these snippets
figures    rewrite the marked figures of README.md, BENCHMARKS.md and docs/**/*.md from
           results/*.json
  --check  rewrite nothing: fail naming each marked text that differs from the results
--root DIR the repository (default: the one this tool was built in)";

/// The command line.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Command {
    /// `snippets`.
    Snippets {
        list: bool,
        only: Option<Vec<String>>,
    },
    /// `figures`.
    Figures { check: bool },
}

/// The command and the repository root, `Ok(None)` for `--help`.
fn parse_args(args: &[String]) -> Result<Option<(Command, Option<PathBuf>)>, String> {
    let mut args = args.iter();
    let mut command = match args.next().map(String::as_str) {
        Some("snippets") => Command::Snippets {
            list: false,
            only: None,
        },
        Some("figures") => Command::Figures { check: false },
        Some("-h" | "--help") => return Ok(None),
        Some(other) => return Err(format!("unknown command {other:?}")),
        None => return Err("a command: snippets or figures".into()),
    };
    let mut root = None;
    while let Some(arg) = args.next() {
        let mut value = |name: &str| {
            args.next()
                .cloned()
                .ok_or_else(|| format!("{name} needs a value"))
        };
        match (&mut command, arg.as_str()) {
            (_, "-h" | "--help") => return Ok(None),
            (_, "--root") => root = Some(PathBuf::from(value("--root")?)),
            (Command::Snippets { list, .. }, "--list") => *list = true,
            (Command::Snippets { only, .. }, "--only") => {
                *only = Some(value("--only")?.split(',').map(str::to_string).collect())
            }
            (Command::Figures { check }, "--check") => *check = true,
            _ => return Err(format!("unknown argument {arg:?}")),
        }
    }
    Ok(Some((command, root)))
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (command, root) = match parse_args(&args) {
        Ok(Some(parsed)) => parsed,
        Ok(None) => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            eprintln!("peel-doc-check: {e}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    let root = root.unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join(".."));
    let outcome = match &command {
        Command::Snippets { list, only } => run_snippets(&root, *list, only.as_deref()),
        Command::Figures { check } => run_figures(&root, *check),
    };
    match outcome {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("peel-doc-check: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `snippets`: whether every snippet (of `only`) built and the docs have no problem.
fn run_snippets(root: &Path, list: bool, only: Option<&[String]>) -> Result<bool, String> {
    let root = root
        .canonicalize()
        .map_err(|e| format!("{}: {e}", root.display()))?;
    let docs = docs::read(&root, false)?;
    let found = snippets::find(&docs, &root);
    if let Some(names) = only {
        for n in names {
            if !found.snippets.iter().any(|s| s.name == *n) {
                return Err(format!("--only: no snippet {n:?}"));
            }
        }
    }
    let chosen: Vec<&snippets::Snippet> = found
        .snippets
        .iter()
        .filter(|s| only.is_none_or(|o| o.contains(&s.name)))
        .collect();
    if list {
        for s in &chosen {
            let files: Vec<&str> = s.files.iter().map(|f| f.path.as_str()).collect();
            let mut line = format!("{}  {}:{}  {}", s.name, s.doc, s.line, files.join(", "));
            if let Some(t) = &s.target {
                line += &format!("  --target {t}");
            }
            for (dest, src) in &s.copies {
                line += &format!("  {dest} <- {src}");
            }
            println!("{line}");
        }
        for e in &found.exclusions {
            println!("left out: {}:{}  {}", e.doc, e.line, e.reason);
        }
    }
    for p in &found.problems {
        eprintln!("{p}");
    }
    if list {
        return Ok(found.problems.is_empty());
    }
    let work = std::env::temp_dir().join(format!("peel-snippets-{}", std::process::id()));
    let workshop = snippets::crates::Workshop::new(&root, work.clone());
    let mut failed = 0;
    for s in &chosen {
        let at = format!("{} ({}:{})", s.name, s.doc, s.line);
        match workshop.build(s) {
            Ok(()) => println!("ok      {at}"),
            Err(e) => {
                failed += 1;
                println!("FAILED  {at}\n{}", indent(&e));
            }
        }
    }
    println!(
        "snippets: {} built, {failed} failed, {} blocks left out, {} problems",
        chosen.len() - failed,
        found.exclusions.len(),
        found.problems.len()
    );
    if failed > 0 {
        println!("the failed crates are in {}", work.display());
    } else {
        let _ = std::fs::remove_dir_all(&work);
    }
    Ok(failed == 0 && found.problems.is_empty())
}

/// `text` indented by 8 spaces.
fn indent(text: &str) -> String {
    text.lines()
        .map(|l| format!("        {l}"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// `figures`: whether the marked figures match the results (after writing them, without
/// `check`).
fn run_figures(root: &Path, check: bool) -> Result<bool, String> {
    let docs = docs::read(root, true)?;
    let mut sources = figures::sources::Sources::new(root);
    let (changed, stale) = match figures::update(&docs, &mut sources) {
        Ok(done) => done,
        Err(problems) => {
            for p in &problems {
                eprintln!("{p}");
            }
            eprintln!("figures: {} problems, nothing written", problems.len());
            return Ok(false);
        }
    };
    if check {
        for p in &stale {
            eprintln!("{p}");
        }
        if !stale.is_empty() {
            eprintln!(
                "figures: {} marked texts differ from results/*.json; \
                 `cargo run --release -p peel-doc-check -- figures` rewrites them",
                stale.len()
            );
            return Ok(false);
        }
        println!("figures: every marked figure is the results'");
        return Ok(true);
    }
    for doc in &changed {
        let path = root.join(&doc.name);
        let temp = path.with_extension("md.figures");
        std::fs::write(&temp, &doc.text)
            .and_then(|()| std::fs::rename(&temp, &path))
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
        println!("rewrote {}", doc.name);
    }
    println!(
        "figures: {} marked texts rewritten in {} files",
        stale.len(),
        changed.len()
    );
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(args: &[&str]) -> Result<Option<(Command, Option<PathBuf>)>, String> {
        parse_args(&args.iter().map(|s| s.to_string()).collect::<Vec<_>>())
    }

    #[test]
    fn arguments() {
        assert_eq!(
            parse(&["snippets", "--only", "a,b"]).unwrap(),
            Some((
                Command::Snippets {
                    list: false,
                    only: Some(vec!["a".into(), "b".into()])
                },
                None
            ))
        );
        assert_eq!(
            parse(&["figures", "--check", "--root", "r"]).unwrap(),
            Some((Command::Figures { check: true }, Some(PathBuf::from("r"))))
        );
        assert_eq!(parse(&["--help"]).unwrap(), None);
        assert!(parse(&["figures", "--list"])
            .unwrap_err()
            .contains("--list"));
        assert!(parse(&["snippets", "--only"])
            .unwrap_err()
            .contains("needs a value"));
        assert!(parse(&["build"]).unwrap_err().contains("build"));
        assert!(parse(&[]).is_err());
    }
}
