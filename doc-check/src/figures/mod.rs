//! The docs' measured figures, written from the committed results by a command and checked
//! against them in CI (`bash .ci/figures`), so that a figure has one source.
//!
//! Conventions, in `README.md`, `BENCHMARKS.md` and every `docs/**/*.md` (outside code
//! blocks):
//!
//! * A block: `<!-- figures: KIND key=value ... -->` on a line of its own, the generated
//!   lines, then `<!-- figures-end -->` on a line of its own. The generated text is the
//!   rendering followed by one empty line (so a table ends before the end marker).
//! * Within a line, for prose: `<!-- figures: KIND ... -->1.97x<!-- figures-end -->`; the
//!   text between the two comments is generated (GitHub shows only it).
//! * `cargo run --release -p peel-doc-check -- figures` rewrites every marked text from
//!   `results/*.json`; `... -- figures --check` rewrites nothing and fails naming the file
//!   and line of each marked text that differs.
//!
//! The results are copies of what the benchmark runs wrote, committed with the figures they
//! gave ([`sources::SOURCES`]): `results/target.json` (`bash .ci/target`),
//! `results/frames.json` (`peel bench --json`), `results/compile.json`
//! (`peel bench compile --json`) and `results/embedded-size.json` (`bash .ci/embedded-size`).
//! The kinds and their parameters are [`kinds::KINDS`]; every other `key=v1,v2` keeps the
//! records whose field `key` is one of the values, `key!=v1,v2` the others (`v*` for a
//! prefix, `a.b` for a nested field). A value with spaces is quoted: `scene="box grid 6^3"`.

pub mod kinds;
pub mod number;
pub mod sources;

use std::ops::Range;

use crate::docs::{Doc, Kind, Problem};
use kinds::Params;
use sources::Sources;

const OPEN: &str = "<!-- figures:";
const END: &str = "<!-- figures-end -->";

/// A marked text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Marker {
    /// The line of its opening comment.
    pub line: usize,
    /// What it renders.
    pub kind: String,
    /// Its parameters, in order.
    pub params: Vec<(String, String)>,
    /// The generated text's bytes in the document.
    pub content: Range<usize>,
    /// A block of lines (else within a line).
    pub block: bool,
}

/// The words of a marker: split at spaces outside double quotes, which are removed.
fn words(body: &str) -> Result<Vec<String>, String> {
    let (mut out, mut word, mut quoted, mut any) = (Vec::new(), String::new(), false, false);
    for c in body.chars() {
        match c {
            '"' => (quoted, any) = (!quoted, true),
            c if c.is_whitespace() && !quoted => {
                if any {
                    out.push(std::mem::take(&mut word));
                }
                any = false;
            }
            c => (word, any) = (word + &c.to_string(), true),
        }
    }
    if quoted {
        return Err("a quote is not closed".into());
    }
    if any {
        out.push(word);
    }
    Ok(out)
}

/// The kind and parameters of an opening comment's body.
fn parse_body(body: &str) -> Result<(String, Vec<(String, String)>), String> {
    let mut words = words(body)?.into_iter();
    let kind = words.next().ok_or("a figures marker without a kind")?;
    let params = words
        .map(|w| match w.split_once('=') {
            Some((k, v)) if !k.is_empty() && !v.is_empty() => Ok((k.to_string(), v.to_string())),
            _ => Err(format!("{w:?}: parameters are key=value")),
        })
        .collect::<Result<_, _>>()?;
    Ok((kind, params))
}

/// The marked texts of `doc`.
pub fn markers(doc: &Doc) -> Result<Vec<Marker>, Vec<Problem>> {
    let (mut found, mut problems) = (Vec::new(), Vec::new());
    let problem = |line: usize, m: String| Problem::new(&doc.name, line, m);
    let lines = crate::docs::lines(&doc.text);
    // A block waiting for its end: the marker, its content's start.
    let mut open: Option<Marker> = None;
    for (k, line) in lines.iter().enumerate() {
        let next_start = lines.get(k + 1).map_or(doc.text.len(), |l| l.start);
        if let Some(m) = &mut open {
            // The generated lines are not markdown to look into; the end is on its own line.
            if line.text.trim() == END {
                m.content.end = line.start;
                found.extend(open.take());
            } else if line.text.contains(OPEN) {
                problems.push(problem(
                    line.number,
                    format!("a figures marker inside the block of line {}", m.line),
                ));
            }
            continue;
        }
        if line.kind != Kind::Prose {
            continue;
        }
        let mut at = 0;
        let text = line.text;
        // Markers in code spans are examples.
        let code = crate::docs::code_spans(text);
        let find = |from: usize, what: &str| {
            text[from..]
                .match_indices(what)
                .map(|(k, _)| from + k)
                .find(|k| !code.iter().any(|c| c.contains(k)))
                .map(|k| k - from)
        };
        loop {
            let (Some(o), e) = (find(at, OPEN), find(at, END)) else {
                if find(at, END).is_some() {
                    problems.push(problem(line.number, format!("{END} without a marker")));
                }
                break;
            };
            if e.is_some_and(|e| e < o) {
                problems.push(problem(line.number, format!("{END} without a marker")));
            }
            let body_start = at + o + OPEN.len();
            let Some(close) = text[body_start..].find("-->") else {
                problems.push(problem(
                    line.number,
                    "a figures marker without its `-->`".into(),
                ));
                break;
            };
            let (kind, params) = match parse_body(&text[body_start..body_start + close]) {
                Ok(p) => p,
                Err(e) => {
                    problems.push(problem(line.number, e));
                    break;
                }
            };
            let after = body_start + close + 3;
            if text[..at + o].trim().is_empty() && text[after..].trim().is_empty() {
                open = Some(Marker {
                    line: line.number,
                    kind,
                    params,
                    content: next_start..next_start,
                    block: true,
                });
                break;
            }
            let Some(end) = find(after, END) else {
                problems.push(problem(
                    line.number,
                    format!(
                        "a figures marker within a line needs its {END} on that line (a block: \
                         the marker and the end each on a line of their own)"
                    ),
                ));
                break;
            };
            found.push(Marker {
                line: line.number,
                kind,
                params,
                content: line.start + after..line.start + after + end,
                block: false,
            });
            at = after + end + END.len();
        }
    }
    if let Some(m) = open {
        problems.push(problem(
            m.line,
            format!("a figures block without its {END}"),
        ));
    }
    if problems.is_empty() {
        Ok(found)
    } else {
        Err(problems)
    }
}

/// The text a marker should hold.
fn expected(m: &Marker, sources: &mut Sources) -> Result<String, String> {
    let table = kinds::is_table(&m.kind);
    if table && !m.block {
        return Err(format!(
            "{} is a table: a block, its marker and end each on a line of their own",
            m.kind
        ));
    }
    let text = kinds::render(&m.kind, Params::new(m.params.clone()), sources)?;
    Ok(if m.block {
        format!("{}\n\n", text.trim_end_matches('\n'))
    } else {
        text
    })
}

/// Every document with its marked texts made from the results: the new texts (only of the
/// documents that change) and the marked texts that differ; or every problem found
/// (malformed markers, figures that cannot be made), and nothing to write.
pub fn update(
    docs: &[Doc],
    sources: &mut Sources,
) -> Result<(Vec<Doc>, Vec<Problem>), Vec<Problem>> {
    let (mut changed, mut stale, mut problems) = (Vec::new(), Vec::new(), Vec::new());
    for doc in docs {
        let marks = match markers(doc) {
            Ok(m) => m,
            Err(p) => {
                problems.extend(p);
                continue;
            }
        };
        let mut text = String::new();
        let mut at = 0;
        for m in &marks {
            let want = match expected(m, sources) {
                Ok(t) => t,
                Err(e) => {
                    problems.push(Problem::new(&doc.name, m.line, format!("{}: {e}", m.kind)));
                    continue;
                }
            };
            let have = &doc.text[m.content.clone()];
            if have != want {
                stale.push(Problem::new(
                    &doc.name,
                    m.line,
                    difference(&m.kind, have, &want),
                ));
            }
            text.push_str(&doc.text[at..m.content.start]);
            text.push_str(&want);
            at = m.content.end;
        }
        text.push_str(&doc.text[at..]);
        if text != doc.text {
            changed.push(Doc {
                name: doc.name.clone(),
                text,
            });
        }
    }
    if problems.is_empty() {
        Ok((changed, stale))
    } else {
        Err(problems)
    }
}

/// What differs: the first line that does.
fn difference(kind: &str, have: &str, want: &str) -> String {
    let (h, w): (Vec<&str>, Vec<&str>) = (have.lines().collect(), want.lines().collect());
    let k = (0..h.len().max(w.len()))
        .find(|&k| h.get(k) != w.get(k))
        .unwrap_or(0);
    format!(
        "{kind}: the figures differ from the results: `{}` where they give `{}`",
        h.get(k).unwrap_or(&"(nothing)"),
        w.get(k).unwrap_or(&"(nothing)")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc(text: &str) -> Doc {
        Doc {
            name: "README.md".into(),
            text: text.into(),
        }
    }

    #[test]
    fn marker_words() {
        assert_eq!(
            words(" ratio scene=\"box grid 6^3\"  a=x ").unwrap(),
            ["ratio", "scene=box grid 6^3", "a=x"]
        );
        assert_eq!(words("a=\"\"").unwrap(), ["a="]);
        assert!(words("a=\"b").is_err());
        assert!(parse_body("value field").unwrap_err().contains("key=value"));
        assert!(parse_body("  ").unwrap_err().contains("without a kind"));
    }

    #[test]
    fn blocks_and_inline_markers() {
        let text = "# T\n\n<!-- figures: target-table scene=teapot -->\n| a |\n\n<!-- figures-end -->\n\
                    Peel takes <!-- figures: ratio a=x b=y -->1.9x<!-- figures-end --> and \
                    <!-- figures: value field=ram_bytes unit=kB -->25 kB<!-- figures-end -->.\n\
                    ```md\n<!-- figures: ignored -->\n```\nIn code: `<!-- figures: value -->x<!-- figures-end -->`.\n";
        let d = doc(text);
        let m = markers(&d).unwrap();
        assert_eq!(m.len(), 3);
        assert_eq!(
            (m[0].line, m[0].kind.as_str(), m[0].block),
            (3, "target-table", true)
        );
        assert_eq!(m[0].params, [("scene".to_string(), "teapot".to_string())]);
        assert_eq!(&text[m[0].content.clone()], "| a |\n\n");
        assert_eq!((m[1].line, m[1].block), (7, false));
        assert_eq!(&text[m[1].content.clone()], "1.9x");
        assert_eq!(&text[m[2].content.clone()], "25 kB");
    }

    #[test]
    fn malformed_markers() {
        for (text, says) in [
            (
                "<!-- figures: ratio -->\ntext\n",
                "README.md:1: a figures block without",
            ),
            (
                "x <!-- figures: ratio -->1x\n",
                "a figures marker within a line needs",
            ),
            ("x <!-- figures-end -->\n", "without a marker"),
            (
                "<!-- figures: a -->\n<!-- figures: b -->\n<!-- figures-end -->\n",
                "inside the block of line 1",
            ),
            ("x <!-- figures: ratio a=\"b -->\n", "quote is not closed"),
            ("x <!-- figures: ratio\n", "without its `-->`"),
        ] {
            let p = markers(&doc(text)).unwrap_err();
            let all: Vec<String> = p.iter().map(|p| p.to_string()).collect();
            assert!(all.iter().any(|p| p.contains(says)), "{text}: {all:?}");
        }
    }
}
