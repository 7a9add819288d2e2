//! The documents both checks read, and their lines told apart: prose, or inside a fenced code
//! block (markers there are examples, not markers).

use std::fmt;
use std::path::{Path, PathBuf};

/// A problem in a document: where, and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// The file, relative to the repository root.
    pub file: String,
    /// 1-based line.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

impl Problem {
    /// A problem at `file:line`.
    pub fn new(file: &str, line: usize, message: impl Into<String>) -> Problem {
        Problem {
            file: file.to_string(),
            line,
            message: message.into(),
        }
    }
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.file, self.line, self.message)
    }
}

/// A document: its path relative to the root (with `/`) and its text.
#[derive(Debug, Clone)]
pub struct Doc {
    /// Relative path, e.g. `docs/host.md`.
    pub name: String,
    /// The whole text.
    pub text: String,
}

/// `README.md`, every `docs/**/*.md` (sorted) and, with `benchmarks`, `BENCHMARKS.md`; a file
/// that is not there is left out.
pub fn read(root: &Path, benchmarks: bool) -> Result<Vec<Doc>, String> {
    let mut paths = vec![PathBuf::from("README.md")];
    if benchmarks {
        paths.push(PathBuf::from("BENCHMARKS.md"));
    }
    let mut guides = Vec::new();
    markdown_under(root, Path::new("docs"), &mut guides)?;
    guides.sort();
    paths.extend(guides);
    let mut docs = Vec::new();
    for path in paths {
        let full = root.join(&path);
        if !full.is_file() {
            continue;
        }
        let text = std::fs::read_to_string(&full)
            .map_err(|e| format!("{}: cannot read: {e}", full.display()))?;
        let name = path
            .components()
            .map(|c| c.as_os_str().to_string_lossy())
            .collect::<Vec<_>>()
            .join("/");
        docs.push(Doc { name, text });
    }
    Ok(docs)
}

/// The `.md` files under `root/dir`, relative to `root`.
fn markdown_under(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), String> {
    let full = root.join(dir);
    if !full.is_dir() {
        return Ok(());
    }
    let entries =
        std::fs::read_dir(&full).map_err(|e| format!("{}: cannot list: {e}", full.display()))?;
    for entry in entries {
        let entry = entry.map_err(|e| format!("{}: cannot list: {e}", full.display()))?;
        let path = dir.join(entry.file_name());
        let kind = entry
            .file_type()
            .map_err(|e| format!("{}: {e}", root.join(&path).display()))?;
        if kind.is_dir() {
            markdown_under(root, &path, out)?;
        } else if path.extension().is_some_and(|e| e == "md") {
            out.push(path);
        }
    }
    Ok(())
}

/// What a line is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind<'a> {
    /// Outside fenced code blocks.
    Prose,
    /// The opening fence of a code block, with its info string (```` ```rust,no_run ```` gives
    /// `rust,no_run`).
    Open(&'a str),
    /// Inside a code block: the line without the opening fence's indentation.
    Code(&'a str),
    /// The closing fence (a block the file ends inside has none).
    Close,
}

/// A line of a document.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Line<'a> {
    /// 1-based.
    pub number: usize,
    /// Byte offset of its first character in the text.
    pub start: usize,
    /// The line without its line break.
    pub text: &'a str,
    /// What it is.
    pub kind: Kind<'a>,
}

/// A fence: at least three backticks or tildes after any indentation; the character, how many
/// and the indentation.
fn fence(line: &str) -> Option<(char, usize, usize, &str)> {
    let body = line.trim_start_matches([' ', '\t']);
    let indent = line.len() - body.len();
    let c = body.chars().next().filter(|c| *c == '`' || *c == '~')?;
    let count = body.chars().take_while(|&x| x == c).count();
    (count >= 3).then(|| (c, count, indent, body[count..].trim()))
}

/// The lines of `text`, each told apart as prose or code (CommonMark's fenced code blocks: a
/// block closes at a fence of the same character at least as long, with nothing after it).
pub fn lines(text: &str) -> Vec<Line<'_>> {
    let mut out = Vec::new();
    let mut open: Option<(char, usize, usize)> = None;
    let mut start = 0;
    for (k, raw) in text.split_inclusive('\n').enumerate() {
        let line = raw.strip_suffix('\n').unwrap_or(raw);
        let line = line.strip_suffix('\r').unwrap_or(line);
        let kind = match (open, fence(line)) {
            (None, Some((c, count, indent, info))) if !(c == '`' && info.contains('`')) => {
                open = Some((c, count, indent));
                Kind::Open(info)
            }
            (None, _) => Kind::Prose,
            (Some((c, count, _)), Some((c2, count2, _, ""))) if c2 == c && count2 >= count => {
                open = None;
                Kind::Close
            }
            (Some((_, _, indent)), _) => {
                let strip = line
                    .char_indices()
                    .take_while(|&(i, ch)| i < indent && ch == ' ')
                    .count();
                Kind::Code(&line[strip..])
            }
        };
        out.push(Line {
            number: k + 1,
            start,
            text: line,
            kind,
        });
        start += raw.len();
    }
    out
}

/// The byte ranges of a line's code spans (`` `x` ``, ``` ``x`` ```): a run of backticks up to
/// the next run of as many (an unmatched run is text).
pub fn code_spans(line: &str) -> Vec<std::ops::Range<usize>> {
    let bytes = line.as_bytes();
    let run = |at: usize| bytes[at..].iter().take_while(|&&b| b == b'`').count();
    let (mut spans, mut at) = (Vec::new(), 0);
    while at < bytes.len() {
        if bytes[at] != b'`' {
            at += 1;
            continue;
        }
        let n = run(at);
        let mut k = at + n;
        let close = loop {
            if k >= bytes.len() {
                break None;
            }
            if bytes[k] == b'`' {
                let m = run(k);
                if m == n {
                    break Some(k + m);
                }
                k += m;
            } else {
                k += 1;
            }
        };
        match close {
            Some(end) => {
                spans.push(at..end);
                at = end;
            }
            None => at += n,
        }
    }
    spans
}

/// A fenced code block.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Block {
    /// The line of its opening fence.
    pub line: usize,
    /// The language: the info string's first word (`rust` for `rust,no_run`).
    pub lang: String,
    /// Its lines, each with a line break.
    pub text: String,
}

/// A prose line or a whole fenced block, in the order of the text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Item<'a> {
    /// A line outside code blocks.
    Prose(Line<'a>),
    /// A fenced code block.
    Block(Block),
}

/// The prose lines and fenced blocks of `text`.
pub fn items(text: &str) -> Vec<Item<'_>> {
    let mut out = Vec::new();
    let mut block: Option<Block> = None;
    for line in lines(text) {
        match line.kind {
            Kind::Prose => out.push(Item::Prose(line)),
            Kind::Open(info) => {
                block = Some(Block {
                    line: line.number,
                    lang: lang(info),
                    text: String::new(),
                })
            }
            Kind::Code(code) => {
                if let Some(b) = &mut block {
                    b.text.push_str(code);
                    b.text.push('\n');
                }
            }
            Kind::Close => out.extend(block.take().map(Item::Block)),
        }
    }
    out.extend(block.map(Item::Block));
    out
}

/// The language of an info string: its first word, up to a comma or space.
pub fn lang(info: &str) -> String {
    info.split([',', ' ', '\t', '{'])
        .next()
        .unwrap_or("")
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fences_and_prose() {
        let text =
            "a\n```rust,no_run\nfn main() {}\n```\n  ~~~~\n  x\n ~~~\n~~~~\nb\n````\n```\n````";
        let kinds: Vec<Kind> = lines(text).iter().map(|l| l.kind).collect();
        assert_eq!(
            kinds,
            [
                Kind::Prose,
                Kind::Open("rust,no_run"),
                Kind::Code("fn main() {}"),
                Kind::Close,
                Kind::Open(""),
                Kind::Code("x"),
                // Too short to close a fence of four.
                Kind::Code("~~~"),
                Kind::Close,
                Kind::Prose,
                Kind::Open(""),
                Kind::Code("```"),
                Kind::Close,
            ]
        );
        let l = lines(text);
        assert_eq!(
            &text[l[2].start..l[2].start + l[2].text.len()],
            "fn main() {}"
        );
        assert_eq!(l[8].number, 9);
        assert_eq!(lang("rust,no_run"), "rust");
        assert_eq!(lang("toml"), "toml");
        assert_eq!(lang(""), "");
        let items = items(text);
        assert_eq!(items.len(), 5);
        assert_eq!(
            items[1],
            Item::Block(Block {
                line: 2,
                lang: "rust".into(),
                text: "fn main() {}\n".into()
            })
        );
        assert!(matches!(&items[4], Item::Block(b) if b.text == "```\n"));
    }

    #[test]
    fn code_spans_of_a_line() {
        let line = "a `b` ``c ` d`` `` e `f";
        let spans: Vec<&str> = code_spans(line).into_iter().map(|r| &line[r]).collect();
        assert_eq!(spans, ["`b`", "``c ` d``"]);
        assert_eq!(code_spans("no code"), []);
    }

    #[test]
    fn the_documents_in_order() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        std::fs::create_dir_all(root.join("docs/b")).unwrap();
        for f in [
            "README.md",
            "BENCHMARKS.md",
            "docs/z.md",
            "docs/b/a.md",
            "docs/x.png",
        ] {
            std::fs::write(root.join(f), f).unwrap();
        }
        let names =
            |b| -> Vec<String> { read(root, b).unwrap().into_iter().map(|d| d.name).collect() };
        assert_eq!(names(false), ["README.md", "docs/b/a.md", "docs/z.md"]);
        assert_eq!(
            names(true),
            ["README.md", "BENCHMARKS.md", "docs/b/a.md", "docs/z.md"]
        );
    }
}
