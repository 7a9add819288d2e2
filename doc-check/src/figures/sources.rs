//! The committed results the figures come from, `results/<source>.json` (each an array of
//! records), and the filters that pick records.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

/// The sources, each `results/<name>.json`, and what writes it.
pub const SOURCES: [(&str, &str); 4] = [
    (
        "target",
        "`bash .ci/target` (target/peel-target/results.json)",
    ),
    ("frames", "`peel bench --json FILE`"),
    ("compile", "`peel bench compile --json FILE`"),
    (
        "embedded-size",
        "`bash .ci/embedded-size` (target/embedded-size.json)",
    ),
];

/// The results files, each read once, when a figure first needs it.
pub struct Sources {
    dir: PathBuf,
    loaded: BTreeMap<String, Vec<Value>>,
}

impl Sources {
    /// The sources in `root/results`.
    pub fn new(root: &Path) -> Sources {
        Sources {
            dir: root.join("results"),
            loaded: BTreeMap::new(),
        }
    }

    /// The records of source `name`.
    pub fn get(&mut self, name: &str) -> Result<&[Value], String> {
        if !SOURCES.iter().any(|(n, _)| *n == name) {
            let names: Vec<&str> = SOURCES.iter().map(|(n, _)| *n).collect();
            return Err(format!(
                "no source {name:?} (sources: {})",
                names.join(", ")
            ));
        }
        if !self.loaded.contains_key(name) {
            let records = self.read(name)?;
            self.loaded.insert(name.to_string(), records);
        }
        Ok(&self.loaded[name])
    }

    fn read(&self, name: &str) -> Result<Vec<Value>, String> {
        let path = self.dir.join(format!("{name}.json"));
        let file = format!("results/{name}.json");
        let text = std::fs::read_to_string(&path).map_err(|e| {
            let from = SOURCES
                .iter()
                .find(|(n, _)| *n == name)
                .map_or("", |(_, w)| w);
            format!("{file}: cannot read ({e}); it is a copy of what {from} writes")
        })?;
        match serde_json::from_str(&text) {
            Ok(Value::Array(records)) if records.iter().all(Value::is_object) => Ok(records),
            Ok(_) => Err(format!("{file}: not an array of records")),
            Err(e) => Err(format!("{file}: {e}")),
        }
    }
}

/// The field `key` of `record`; a dotted key reaches into objects (`naive_bsp.ratio`).
pub fn field<'v>(record: &'v Value, key: &str) -> Option<&'v Value> {
    key.split('.').try_fold(record, |v, part| v.get(part))
}

/// A field as filters and tables see it: a string as it is, anything else as JSON.
pub fn text(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// `key=v1,v2`: records whose field `key` is one of the values; `key!=v1,v2`: the others. A
/// value ending in `*` stands for every value that starts with the rest (`path=bands-*`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Filter {
    /// The field.
    pub key: String,
    /// The values.
    pub values: Vec<String>,
    /// Keep the records whose field is none of the values.
    pub negate: bool,
}

impl Filter {
    /// The filter of a marker's `key=values` (`key!=values` when `key` ends in `!`).
    pub fn new(key: &str, values: &str) -> Filter {
        let (key, negate) = key.strip_suffix('!').map_or((key, false), |k| (k, true));
        Filter {
            key: key.to_string(),
            values: values.split(',').map(str::to_string).collect(),
            negate,
        }
    }

    /// Whether `record` passes.
    pub fn keeps(&self, record: &Value) -> bool {
        let one_of = field(record, &self.key).is_some_and(|v| {
            let t = text(v);
            self.values.iter().any(|want| match want.strip_suffix('*') {
                Some(prefix) => t.starts_with(prefix),
                None => t == *want,
            })
        });
        one_of != self.negate
    }
}

/// The records of source `name` that pass every filter, in the file's order: an error when a
/// filter names a field no record has, or when none passes.
pub fn select<'v>(
    records: &'v [Value],
    name: &str,
    filters: &[Filter],
) -> Result<Vec<&'v Value>, String> {
    for f in filters {
        if !records.iter().any(|r| field(r, &f.key).is_some()) {
            let keys: Vec<&String> = records
                .first()
                .and_then(Value::as_object)
                .map(|o| o.keys().collect())
                .unwrap_or_default();
            let keys: Vec<&str> = keys.iter().map(|k| k.as_str()).collect();
            return Err(format!(
                "no field {:?} in results/{name}.json (its fields: {})",
                f.key,
                keys.join(", ")
            ));
        }
    }
    let kept: Vec<&Value> = records
        .iter()
        .filter(|r| filters.iter().all(|f| f.keeps(r)))
        .collect();
    if kept.is_empty() {
        let said: Vec<String> = filters
            .iter()
            .map(|f| {
                let not = if f.negate { "!" } else { "" };
                format!("{}{not}={}", f.key, f.values.join(","))
            })
            .collect();
        return Err(format!(
            "no record of results/{name}.json has {}",
            said.join(" ")
        ));
    }
    Ok(kept)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn filters_pick_records() {
        let records = vec![
            json!({"scene": "teapot", "width": 320, "path": "bands-17", "naive_bsp": {"ratio": 5.1}}),
            json!({"scene": "cow", "width": 160, "path": "stream", "naive_bsp": null}),
        ];
        let f = |key: &str, values: &[&str]| Filter::new(key, &values.join(","));
        let pick = |filters: &[Filter]| -> Result<Vec<String>, String> {
            Ok(select(&records, "target", filters)?
                .iter()
                .map(|r| text(&r["scene"]))
                .collect())
        };
        assert_eq!(pick(&[]).unwrap(), ["teapot", "cow"]);
        assert_eq!(pick(&[f("width", &["320"])]).unwrap(), ["teapot"]);
        assert_eq!(pick(&[f("path", &["bands-*"])]).unwrap(), ["teapot"]);
        assert_eq!(
            pick(&[f("scene", &["cow", "teapot"])]).unwrap(),
            ["teapot", "cow"]
        );
        assert_eq!(pick(&[f("naive_bsp.ratio", &["5.1"])]).unwrap(), ["teapot"]);
        assert_eq!(pick(&[f("path!", &["bands-*"])]).unwrap(), ["cow"]);
        assert_eq!(
            pick(&[f("scene!", &["cow", "teapot"])]).unwrap_err(),
            "no record of results/target.json has scene!=cow,teapot"
        );
        let e = pick(&[f("scen", &["cow"])]).unwrap_err();
        assert!(
            e.contains("no field \"scen\" in results/target.json (its fields: "),
            "{e}"
        );
        let e = pick(&[f("scene", &["bunny"]), f("width", &["320"])]).unwrap_err();
        assert_eq!(
            e,
            "no record of results/target.json has scene=bunny width=320"
        );
    }

    #[test]
    fn sources_are_read_when_needed() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("results")).unwrap();
        std::fs::write(
            dir.path().join("results/frames.json"),
            "[{\"scene\": \"demo\"}]",
        )
        .unwrap();
        std::fs::write(
            dir.path().join("results/compile.json"),
            "{\"scene\": \"demo\"}",
        )
        .unwrap();
        let mut s = Sources::new(dir.path());
        assert_eq!(s.get("frames").unwrap().len(), 1);
        assert!(s
            .get("target")
            .unwrap_err()
            .contains("results/target.json: cannot read"));
        assert_eq!(
            s.get("compile").unwrap_err(),
            "results/compile.json: not an array of records"
        );
        assert!(s
            .get("targets")
            .unwrap_err()
            .starts_with("no source \"targets\""));
    }
}
