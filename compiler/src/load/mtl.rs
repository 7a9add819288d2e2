//! What tobj does not tell of an MTL file: the line of each material's `map_Kd` and its
//! options. tobj keeps the rest of the statement, options and all, as the image's name, and no
//! line; this reads the same lines the same way, so its materials pair with tobj's one for one.

use std::path::{Path, PathBuf};

/// A material's `map_Kd` statement: where it is, and what it says.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct MapKd {
    /// The MTL file.
    pub mtl: PathBuf,
    /// 1-based line of the statement.
    pub line: usize,
    /// The statement after `map_Kd`, as tobj keeps it (options, then the image's name).
    pub text: String,
}

/// A `map_Kd` statement read: the image and how it wraps.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Options {
    /// The image's name as written (relative to the MTL file's folder unless absolute).
    pub image: String,
    /// `-clamp on`: the edge texels continue past the edges (both axes); else the texture
    /// repeats.
    pub clamp: bool,
    /// Options that change nothing here (`-blendu`, `-bm`, `-o`, ...), as written: a warning
    /// names them.
    pub ignored: Vec<String>,
}

/// One material of an MTL file, in the order tobj lists them.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Material {
    /// Its name (`newmtl`).
    pub name: String,
    /// The MTL file it is in.
    pub mtl: PathBuf,
    /// Its last `map_Kd` statement (tobj keeps the last), if any.
    pub map_kd: Option<MapKd>,
    /// Its last `d` (dissolve: the opacity) and `Tr` (transparency, `1 - d`) statements:
    /// the line and the text after the keyword.
    pub dissolve: Option<(usize, String)>,
    pub transparency: Option<(usize, String)>,
}

/// Where a material's opacity was given: its MTL file and line.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct OpacityAt {
    /// The opacity, of 255 ([`super::OPAQUE`] without `d` or `Tr`).
    pub opacity: u8,
    /// The MTL file and the line of its `d` (else its `Tr`) statement, when given.
    pub at: Option<(PathBuf, usize)>,
}

impl Material {
    /// The opacity its `d` or `Tr` give (`round(255 d)`, `d = 1 - Tr`): an error names the
    /// MTL file `path` and the line of a value that is no number from 0 to 1, or of a `d` and
    /// a `Tr` that disagree by more than 1/255.
    pub(super) fn opacity(&self) -> Result<OpacityAt, crate::CompileError> {
        let path = &self.mtl;
        let value = |(line, text): &(usize, String), name: &str| {
            let v: Option<f64> = text.split_whitespace().next().and_then(|w| w.parse().ok());
            match v.filter(|v| (0.0..=1.0).contains(v)) {
                Some(v) => Ok((*line, v)),
                None => Err(crate::CompileError::Mtl {
                    path: path.to_path_buf(),
                    line: *line,
                    message: format!(
                        "material `{}`: `{name} {text}`: the value must be a number from 0 to 1",
                        self.name
                    ),
                }),
            }
        };
        let d = self.dissolve.as_ref().map(|s| value(s, "d")).transpose()?;
        let tr = (self.transparency.as_ref())
            .map(|s| value(s, "Tr"))
            .transpose()?;
        let (line, opacity) = match (d, tr) {
            (Some((line, d)), Some((_, tr))) if (d - (1.0 - tr)).abs() > 1.0 / 255.0 => {
                return Err(crate::CompileError::Mtl {
                    path: path.to_path_buf(),
                    line,
                    message: format!(
                        "material `{}`: `d {d}` and `Tr {tr}` disagree (`Tr` is `1 - d`)",
                        self.name
                    ),
                })
            }
            (Some((line, d)), _) => (line, d),
            (None, Some((line, tr))) => (line, 1.0 - tr),
            (None, None) => {
                return Ok(OpacityAt {
                    opacity: super::OPAQUE,
                    at: None,
                })
            }
        };
        Ok(OpacityAt {
            opacity: (opacity * 255.0).round() as u8,
            at: Some((path.to_path_buf(), line)),
        })
    }
}

/// The materials of the MTL file `path` whose text is `text`, as tobj reads them: a material
/// starts at each `newmtl` with a name, and statements before the first belong to none.
pub(super) fn materials(path: &Path, text: &str) -> Vec<Material> {
    let mut out = Vec::new();
    let mut current: Option<Material> = None;
    for (index, raw) in text.split('\n').enumerate() {
        // tobj trims each line, then takes the rest after the keyword's bytes.
        let line = raw.trim();
        match line.split_whitespace().next() {
            Some("newmtl") => {
                out.extend(current.take());
                let name = line.get(6..).unwrap_or_default().trim();
                current = (!name.is_empty()).then(|| Material {
                    name: name.to_owned(),
                    mtl: path.to_path_buf(),
                    map_kd: None,
                    dissolve: None,
                    transparency: None,
                });
            }
            Some("map_Kd") => {
                let rest = line.get(6..).unwrap_or_default().trim();
                if let Some(material) = current.as_mut().filter(|_| !rest.is_empty()) {
                    material.map_kd = Some(MapKd {
                        mtl: path.to_path_buf(),
                        line: index + 1,
                        text: rest.to_owned(),
                    });
                }
            }
            Some(keyword @ ("d" | "Tr")) => {
                let rest = line.get(keyword.len()..).unwrap_or_default().trim();
                if let Some(material) = current.as_mut() {
                    let statement = Some((index + 1, rest.to_owned()));
                    if keyword == "d" {
                        material.dissolve = statement;
                    } else {
                        material.transparency = statement;
                    }
                }
            }
            _ => {}
        }
    }
    out.extend(current);
    out
}

/// The options a `map_Kd` statement may give before the image's name, and how many values
/// each takes (at least, at most).
const OPTIONS: [(&str, usize, usize); 12] = [
    ("-blendu", 1, 1),
    ("-blendv", 1, 1),
    ("-bm", 1, 1),
    ("-boost", 1, 1),
    ("-cc", 1, 1),
    ("-clamp", 1, 1),
    ("-imfchan", 1, 1),
    ("-mm", 2, 2),
    ("-o", 1, 3),
    ("-s", 1, 3),
    ("-t", 1, 3),
    ("-texres", 1, 1),
];

/// Reads a `map_Kd` statement's `text` (after the keyword): its options, then the image's name
/// (the rest of the text, spaces and all). An unknown option, an option without its values, a
/// `-clamp` other than `on` or `off`, or no image is an error, worded for the MTL file's line.
pub(super) fn options(text: &str) -> Result<Options, String> {
    let mut out = Options {
        image: String::new(),
        clamp: false,
        ignored: Vec::new(),
    };
    let mut rest = text.trim_start();
    loop {
        let word = rest.split_whitespace().next().unwrap_or_default();
        if !word.starts_with('-') {
            break;
        }
        let Some(&(name, least, most)) = OPTIONS.iter().find(|o| o.0 == word) else {
            return Err(format!(
                "`map_Kd`: unknown option `{word}` (the options are {})",
                OPTIONS.map(|o| o.0).join(", ")
            ));
        };
        rest = rest[word.len()..].trim_start();
        let mut values = Vec::new();
        while values.len() < most {
            let value = rest.split_whitespace().next().unwrap_or_default();
            // Beyond the values an option must have, only numbers are its own (`-s 2 2
            // image.png`), and never the last word: the image's name follows.
            let optional = value.parse::<f64>().is_ok() && rest.len() > value.len();
            let taken = !value.is_empty() && (values.len() < least || optional);
            if !taken {
                break;
            }
            values.push(value);
            rest = rest[value.len()..].trim_start();
        }
        if values.len() < least {
            return Err(format!(
                "`map_Kd`: option `{name}` needs {least} value{} before the image's name",
                if least == 1 { "" } else { "s" }
            ));
        }
        if name == "-clamp" {
            out.clamp = match values[0] {
                "on" => true,
                "off" => false,
                other => {
                    return Err(format!(
                        "`map_Kd`: `-clamp {other}`: the value is `on` or `off`"
                    ))
                }
            };
        } else {
            out.ignored.push(format!("{name} {}", values.join(" ")));
        }
    }
    if rest.is_empty() {
        return Err("`map_Kd` names no image after its options".into());
    }
    out.image = rest.trim_end().to_owned();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn materials_pair_with_tobjs_and_keep_their_map_kd_line() {
        let text = "map_Kd stray.png\nnewmtl a\nKd 1 1 1\nmap_Kd  -clamp on  a b.png \r\n\
                    newmtl b\n  map_Kd first.png\nmap_Kd second.jpg\nnewmtl c\n";
        let got = materials(Path::new("m.mtl"), text);
        let (parsed, _) = tobj::load_mtl_buf(&mut std::io::Cursor::new(text)).unwrap();
        let names: Vec<&str> = got.iter().map(|m| m.name.as_str()).collect();
        let theirs: Vec<&str> = parsed.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, theirs);
        assert_eq!(names, ["a", "b", "c"]);
        for (mine, theirs) in got.iter().zip(&parsed) {
            assert_eq!(
                mine.map_kd.as_ref().map(|m| m.text.as_str()),
                theirs.diffuse_texture.as_deref()
            );
        }
        let lines: Vec<Option<usize>> = got
            .iter()
            .map(|m| m.map_kd.as_ref().map(|m| m.line))
            .collect();
        assert_eq!(lines, [Some(4), Some(7), None]);
        assert_eq!(got[0].map_kd.as_ref().unwrap().mtl, Path::new("m.mtl"));
    }

    #[test]
    fn options_come_before_the_image_whose_name_may_hold_spaces() {
        let o = options("-clamp on a b.png").unwrap();
        assert_eq!((o.image.as_str(), o.clamp), ("a b.png", true));
        assert!(o.ignored.is_empty());
        let o = options("-s 2 2 1 -clamp off -bm 0.5 wall.jpg").unwrap();
        assert_eq!((o.image.as_str(), o.clamp), ("wall.jpg", false));
        assert_eq!(o.ignored, ["-s 2 2 1", "-bm 0.5"]);
        // A number is an option's value only while it may take more: `-o 1 2.png`'s image is
        // `2.png`, and the last word is always the image.
        let o = options("-o 1 2.png").unwrap();
        assert_eq!(
            (o.image.as_str(), o.ignored.as_slice()),
            ("2.png", &["-o 1".to_owned()][..])
        );
        let o = options("-o 1 2").unwrap();
        assert_eq!(o.image, "2");
        assert_eq!(options("plain.png").unwrap().image, "plain.png");
    }

    #[test]
    fn a_bad_option_is_refused_with_its_reason() {
        for (text, says) in [
            (
                "-clamp yes a.png",
                "`-clamp yes`: the value is `on` or `off`",
            ),
            ("-wrap on a.png", "unknown option `-wrap`"),
            ("-clamp on", "names no image"),
            ("-mm 1", "option `-mm` needs 2 values"),
        ] {
            let e = options(text).unwrap_err();
            assert!(e.contains(says), "{text}: {e}");
        }
    }
}
