//! A light line check of the OBJ text, run before tobj.
//!
//! tobj reports neither line numbers nor NaN/inf coordinates, so this check validates every
//! statement tobj would look at (same tokenisation, same index rules) and reports errors with
//! their line. A file that ends without a line end in the middle of a face (cut off) is an
//! error at that line. A file that passes the check cannot make tobj fail on vertex or face data. The
//! check also records every `f`/`l` statement in file order: tobj emits exactly one face per
//! statement, which lets the loader pair each tobj face with its line and check that the two
//! parsers agree.

use crate::hash::FastMap;
use std::path::Path;

use crate::error::CompileError;

/// One `f` or `l` statement.
#[derive(Debug, Clone, Copy)]
pub(super) struct Statement {
    /// 1-based line.
    pub line: usize,
    /// Number of corners.
    pub arity: usize,
    /// `true` for `f`, `false` for `l` (a polyline, not a surface).
    pub is_face: bool,
    /// Index into [`Lines::material_names`] of the last `usemtl` before it.
    pub material: Option<u32>,
    /// Every corner names a normal (`v//vn` or `v/vt/vn`): the face's corners take the file's
    /// normals. A face that names them for some corners only takes none.
    pub normals: bool,
    /// Every corner names texture coordinates (`v/vt` or `v/vt/vn`): with a textured material
    /// the face is textured. A face that names them for some corners only is not.
    pub uvs: bool,
}

/// What the line check learnt about the file.
#[derive(Debug, Default)]
pub(super) struct Lines {
    /// Every `f` and `l` statement, in file order.
    pub statements: Vec<Statement>,
    /// Material names as tobj reads them from `usemtl` lines.
    pub material_names: Vec<String>,
    /// 1-based line of each `mtllib` statement, in file order.
    pub mtllib_lines: Vec<usize>,
    /// Number of `f` statements with at least three corners.
    pub polygon_faces: usize,
}

/// Limits checked line by line.
#[derive(Debug, Clone, Copy)]
pub(super) struct Limits {
    /// Maximum number of `v`, `vt` and `vn` statements together.
    pub vertices: usize,
    /// Maximum number of triangles (a polygon of n corners counts n - 2; `l` and short faces 1).
    pub triangles: usize,
}

/// Vertex, texture-coordinate and normal counts so far (OBJ indices refer to earlier lines).
#[derive(Debug, Default)]
struct Counts {
    v: usize,
    vt: usize,
    vn: usize,
}

/// Checks `text` (the content of `path`).
pub(super) fn check(path: &Path, text: &str, limits: Limits) -> Result<Lines, CompileError> {
    let parse_error = |line: usize, message: String| CompileError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut out = Lines::default();
    let mut names: FastMap<String, u32> = FastMap::default();
    let mut counts = Counts::default();
    let mut material: Option<u32> = None;
    let mut coloured: Option<bool> = None;
    let mut triangles = 0usize;

    let mut lines = text.split('\n').enumerate().peekable();
    while let Some((index, raw)) = lines.next() {
        let line = index + 1;
        // The text after the last line end: a file that does not end with one.
        let unterminated = lines.peek().is_none();
        let mut words = raw.split_whitespace();
        match words.next() {
            Some("v") => {
                let tokens: Vec<&str> = words.by_ref().take(7).collect();
                check_vertex(path, line, &tokens, &mut coloured)?;
                counts.v += 1;
            }
            Some("vt") => {
                check_floats(&mut words, 2)
                    .map_err(|m| parse_error(line, format!("texture coordinate: {m}")))?;
                counts.vt += 1;
            }
            Some("vn") => {
                check_floats(&mut words, 3)
                    .map_err(|m| parse_error(line, format!("normal: {m}")))?;
                counts.vn += 1;
            }
            Some(keyword @ ("f" | "l")) => {
                let mut arity = 0;
                let (mut first, mut last) = ("", "");
                let (mut normals, mut uvs) = (true, true);
                for corner in words {
                    check_corner(path, line, corner, &counts)?;
                    normals &= corner.split('/').nth(2).is_some_and(|vn| !vn.is_empty());
                    uvs &= corner.split('/').nth(1).is_some_and(|vt| !vt.is_empty());
                    if arity == 0 {
                        first = corner;
                    }
                    last = corner;
                    arity += 1;
                }
                let is_face = keyword == "f";
                if is_face && unterminated {
                    check_complete_face(raw, arity, first, last)
                        .map_err(|m| parse_error(line, m))?;
                }
                triangles += if is_face && arity >= 3 { arity - 2 } else { 1 };
                if triangles > limits.triangles {
                    return Err(CompileError::TooLarge {
                        path: path.to_path_buf(),
                        message: format!(
                            "more than {} triangles (reached at line {line})",
                            limits.triangles
                        ),
                    });
                }
                if is_face && arity >= 3 {
                    out.polygon_faces += 1;
                }
                out.statements.push(Statement {
                    line,
                    arity,
                    is_face,
                    material,
                    normals: normals && arity > 0,
                    uvs: uvs && arity > 0,
                });
            }
            Some("usemtl") => {
                // Same extraction as tobj, so the names match the ones it looks up.
                let name = raw.split_once(' ').unwrap_or_default().1.trim();
                if name.is_empty() {
                    return Err(parse_error(line, "`usemtl` needs a material name".into()));
                }
                let next = out.material_names.len() as u32;
                let id = *names.entry(name.to_owned()).or_insert(next);
                if id == next {
                    out.material_names.push(name.to_owned());
                }
                material = Some(id);
            }
            Some("mtllib") => out.mtllib_lines.push(line),
            _ => {}
        }
        if counts.v + counts.vt + counts.vn > limits.vertices {
            return Err(CompileError::TooLarge {
                path: path.to_path_buf(),
                message: format!(
                    "more than {} vertex statements (`v`, `vt`, `vn`; reached at line {line})",
                    limits.vertices
                ),
            });
        }
    }
    Ok(out)
}

/// Checks the face on the last line of a file that does not end with a line end, `raw`, of
/// `arity` corners, the first `first` and the last `last`: a file cut off in the middle of a
/// face leaves one with fewer than three corners or a last corner cut short (`3/`, or fewer
/// indices than the first corner has). Elsewhere such a face is a mistake of its own, skipped
/// with a warning; here the rest of the file is missing.
fn check_complete_face(raw: &str, arity: usize, first: &str, last: &str) -> Result<(), String> {
    let statement = excerpt(raw.trim());
    let why = if arity < 3 {
        format!(
            "`{statement}` has {arity} corner{}",
            if arity == 1 { "" } else { "s" }
        )
    } else if last.ends_with('/') || last.split('/').count() < first.split('/').count() {
        format!("the last corner of `{statement}`, `{last}`, is incomplete")
    } else {
        return Ok(());
    };
    Err(format!(
        "the file ends in the middle of a face: {why}, and no line end follows (is the file cut \
         off?)"
    ))
}

/// `text`, shortened to its first 40 characters and an ellipsis when longer.
fn excerpt(text: &str) -> String {
    match text.char_indices().nth(40) {
        Some((at, _)) => format!("{}...", text[..at].trim_end()),
        None => text.to_owned(),
    }
}

/// Checks a `v` statement the way tobj reads it: x y z, then nothing, a weight w, or an RGB
/// colour. Coordinates (after dividing by w) must be finite.
fn check_vertex(
    path: &Path,
    line: usize,
    tokens: &[&str],
    coloured: &mut Option<bool>,
) -> Result<(), CompileError> {
    let parse_error = |message: String| CompileError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let non_finite = |value: String| CompileError::NonFinite {
        path: path.to_path_buf(),
        line,
        value,
    };
    if tokens.len() < 3 {
        return Err(parse_error(format!(
            "a vertex needs three coordinates, found {}",
            tokens.len()
        )));
    }
    let mut xyz = [0.0f64; 3];
    for (c, token) in xyz.iter_mut().zip(tokens) {
        *c = number(token).map_err(|m| parse_error(format!("vertex coordinate: {m}")))?;
        if !c.is_finite() {
            return Err(non_finite((*token).to_owned()));
        }
    }
    let has_colour = match tokens.len() {
        3 => false,
        4 => {
            let w = number(tokens[3]).map_err(|m| parse_error(format!("vertex weight: {m}")))?;
            if !w.is_finite() {
                return Err(non_finite(tokens[3].to_owned()));
            }
            if w == 0.0 {
                return Err(parse_error("the vertex weight w is zero".into()));
            }
            for (c, token) in xyz.iter().zip(tokens) {
                if !(c / w).is_finite() {
                    return Err(non_finite(format!("{token} / {}", tokens[3])));
                }
            }
            false
        }
        6 => {
            for token in &tokens[3..] {
                number(token).map_err(|m| parse_error(format!("vertex colour: {m}")))?;
            }
            true
        }
        n => {
            return Err(parse_error(format!(
                "a vertex is x y z, optionally followed by a weight w or an RGB colour; found {}{} numbers",
                if n > 6 { "more than " } else { "" },
                n.min(6)
            )))
        }
    };
    match *coloured {
        None => *coloured = Some(has_colour),
        Some(c) if c != has_colour => {
            return Err(parse_error(
                "some vertices have an RGB colour and others do not".into(),
            ))
        }
        Some(_) => {}
    }
    Ok(())
}

fn number(token: &str) -> Result<f64, String> {
    token
        .parse::<f64>()
        .map_err(|_| format!("`{token}` is not a number"))
}

/// Checks that the next `n` words are numbers (extra words are ignored, as tobj does).
fn check_floats<'a>(words: &mut impl Iterator<Item = &'a str>, n: usize) -> Result<(), String> {
    let mut found = 0;
    for token in words.take(n) {
        number(token)?;
        found += 1;
    }
    if found < n {
        return Err(format!("expected {n} numbers, found {found}"));
    }
    Ok(())
}

/// Checks one face corner `v`, `v/vt`, `v//vn` or `v/vt/vn` against what is defined so far.
fn check_corner(
    path: &Path,
    line: usize,
    corner: &str,
    counts: &Counts,
) -> Result<(), CompileError> {
    let parse_error = |message: String| CompileError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let parts: Vec<&str> = corner.split('/').collect();
    if parts.len() > 3 {
        return Err(parse_error(format!(
            "face corner `{corner}` has more than three indices"
        )));
    }
    if parts[0].is_empty() {
        return Err(parse_error(format!(
            "face corner `{corner}` has no vertex index"
        )));
    }
    for (slot, part) in parts.iter().enumerate() {
        if part.is_empty() {
            continue;
        }
        let index: i64 = part.parse().map_err(|_| {
            parse_error(format!("face corner `{corner}`: `{part}` is not an index"))
        })?;
        let count = [counts.v, counts.vt, counts.vn][slot];
        if resolve(index, count).is_none() {
            return Err(match slot {
                0 => CompileError::IndexOutOfRange {
                    path: path.to_path_buf(),
                    line,
                    index,
                    count,
                },
                1 => parse_error(format!(
                    "texture coordinate index {index} out of range ({count} defined before this line)"
                )),
                _ => parse_error(format!(
                    "normal index {index} out of range ({count} defined before this line)"
                )),
            });
        }
    }
    Ok(())
}

/// Resolves a 1-based or negative (relative) OBJ index to a 0-based one, if it is in range.
fn resolve(index: i64, count: usize) -> Option<usize> {
    let count = i64::try_from(count).ok()?;
    let zero_based = if index < 0 { count + index } else { index - 1 };
    (0..count)
        .contains(&zero_based)
        .then_some(zero_based as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: Limits = Limits {
        vertices: 1000,
        triangles: 1000,
    };

    fn run(text: &str) -> Result<Lines, CompileError> {
        check(Path::new("t.obj"), text, LIMITS)
    }

    #[test]
    fn resolve_follows_obj_rules() {
        assert_eq!(resolve(1, 3), Some(0));
        assert_eq!(resolve(3, 3), Some(2));
        assert_eq!(resolve(4, 3), None);
        assert_eq!(resolve(0, 3), None);
        assert_eq!(resolve(-1, 3), Some(2));
        assert_eq!(resolve(-3, 3), Some(0));
        assert_eq!(resolve(-4, 3), None);
    }

    #[test]
    fn records_statements_and_materials_in_order() {
        let s = run("v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\nl 1 2\nusemtl b\nf 1 2 3 1\nusemtl a\nf -3 -2 -1\n")
            .unwrap();
        let lines: Vec<_> = s
            .statements
            .iter()
            .map(|s| (s.line, s.arity, s.is_face, s.material))
            .collect();
        assert_eq!(
            lines,
            [
                (5, 3, true, Some(0)),
                (6, 2, false, Some(0)),
                (8, 4, true, Some(1)),
                (10, 3, true, Some(0))
            ]
        );
        assert_eq!(s.material_names, ["a", "b"]);
        assert_eq!(s.polygon_faces, 3);
    }

    #[test]
    fn a_face_has_normals_when_every_corner_names_one() {
        let s = run("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n\
                     f 1//1 2//1 3//1\nf 1/1/1 2/1/1 3/1/1\nf 1//1 2 3//1\nf 1/1/ 2//1 3//1\n\
                     f 1 2 3\nl 1//1 2//1\n")
        .unwrap();
        let normals: Vec<bool> = s.statements.iter().map(|s| s.normals).collect();
        assert_eq!(normals, [true, true, false, false, false, true]);
    }

    #[test]
    fn a_face_has_texture_coordinates_when_every_corner_names_them() {
        let s = run("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n\
                     f 1/1 2/1 3/1\nf 1/1/1 2/1/1 3/1/1\nf 1//1 2//1 3//1\nf 1/1 2 3/1\n\
                     f 1/1/1 2//1 3/1/1\nf 1 2 3\n")
        .unwrap();
        let uvs: Vec<bool> = s.statements.iter().map(|s| s.uvs).collect();
        assert_eq!(uvs, [true, true, false, false, false, false]);
    }

    #[test]
    fn weight_that_overflows_is_non_finite() {
        let e = run("v 1e300 0 0 1e-300\n").unwrap_err();
        assert!(matches!(e, CompileError::NonFinite { line: 1, .. }), "{e}");
    }

    #[test]
    fn mixed_vertex_colours_are_rejected() {
        let e = run("v 0 0 0 1 0 0\nv 1 0 0\n").unwrap_err();
        assert!(matches!(e, CompileError::Parse { line: 2, .. }), "{e}");
    }

    #[test]
    fn texture_index_out_of_range_is_reported() {
        let e = run("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n").unwrap_err();
        assert!(matches!(e, CompileError::Parse { line: 5, .. }), "{e}");
        assert!(
            e.to_string().starts_with(
                "t.obj:5: texture coordinate index 2 out of range (1 defined before this line)"
            ),
            "{e}"
        );
        // Negative indices count back from the line; a `vt` after the face is not before it.
        let e = run("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-2 2/1 3/1\nvt 1 1\n").unwrap_err();
        assert!(matches!(e, CompileError::Parse { line: 5, .. }), "{e}");
        assert!(run("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-1 2/1 3/1\n").is_ok());
    }

    #[test]
    fn a_file_cut_off_in_a_face_is_an_error_at_its_last_line() {
        let head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1 2 3\n";
        for (tail, says) in [
            ("f 1 2", "`f 1 2` has 2 corners"),
            ("f", "`f` has 0 corners"),
            ("f 1/", "`f 1/` has 1 corner,"),
            (
                "f 1 2 3/",
                "the last corner of `f 1 2 3/`, `3/`, is incomplete",
            ),
            (
                "f 1/1 2/1 3",
                "the last corner of `f 1/1 2/1 3`, `3`, is incomplete",
            ),
            ("f 1//  ", "`f 1//` has 1 corner"),
        ] {
            let e = run(&format!("{head}{tail}")).unwrap_err();
            let shown = e.to_string();
            assert!(
                matches!(e, CompileError::Parse { line: 6, .. }),
                "{tail}: {shown}"
            );
            assert!(
                shown.starts_with("t.obj:6: the file ends in the middle of a face: ")
                    && shown.contains(says)
                    && shown.contains("cut off"),
                "{tail}: {shown}"
            );
        }
        // A whole face without a line end is a face; a short face with one is skipped later
        // (with a warning), as anywhere in a file.
        for text in [
            format!("{head}f 3 2 1"),
            format!("{head}f 1/1 2/1 3/1"),
            format!("{head}f 1 2\n"),
            format!("{head}f 1 2\r\n"),
            format!("{head}# f 1 2"),
            format!("{head}l 1"),
        ] {
            assert!(run(&text).is_ok(), "{text:?}");
        }
        // A long line is quoted in part.
        let long = format!("{head}f {}2/", "1 ".repeat(30));
        let shown = run(&long).unwrap_err().to_string();
        assert!(
            shown.contains(&format!("`f {}1...`, `2/`", "1 ".repeat(18))),
            "{shown}"
        );
    }

    #[test]
    fn limits_give_too_large() {
        let many_vertices = "v 0 0 0\n".repeat(1001);
        assert!(matches!(
            run(&many_vertices),
            Err(CompileError::TooLarge { .. })
        ));
        let mut many_faces = "v 0 0 0\nv 1 0 0\nv 0 1 0\n".to_owned();
        many_faces.push_str(&"f 1 2 3\n".repeat(1001));
        assert!(matches!(
            run(&many_faces),
            Err(CompileError::TooLarge { .. })
        ));
        let big_polygon = format!("v 0 0 0\nf {}\n", "1 ".repeat(1003));
        assert!(matches!(
            run(&big_polygon),
            Err(CompileError::TooLarge { .. })
        ));
    }
}
