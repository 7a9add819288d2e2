//! What each kind of marked block renders. The tables are those the benchmarks write
//! themselves (`peel_target_runner::results`, `peel_compiler::tools::bench_frames` and
//! `bench_compile`), made again from the committed records; `value` and `ratio` compute a
//! figure for prose.

use serde::de::DeserializeOwned;
use serde_json::Value;

use super::number::{self, Precision};
use super::sources::{field, select, text, Filter, Sources};

/// The kinds, each with its parameters (besides the filters, `key=v1,v2` or `key!=v1,v2` on
/// the records' fields), for the usage and error messages.
pub const KINDS: [(&str, &str); 7] = [
    (
        "target-table",
        "[columns=KEY,...] FILTERS: rows of results/target.json",
    ),
    (
        "target-antialiased",
        "FILTERS: the anti-aliased frames' table of results/target.json",
    ),
    (
        "alternatives",
        "[scene=teapot,cow]: the README's table of Peel and the alternatives",
    ),
    (
        "frames-table",
        "FILTERS: rows of results/frames.json (peel bench)",
    ),
    (
        "compile-table",
        "FILTERS: rows of results/compile.json (peel bench compile)",
    ),
    (
        "value",
        "field=KEY [source=target] [unit=U] [digits=N|sig=N] FILTERS: a figure, or the range \
         of the records'",
    ),
    (
        "ratio",
        "a=METHOD[/PATH] b=METHOD[/PATH] [field=instructions] [source=target] [digits=N|sig=N] \
         FILTERS: a's field over b's, per scene (and core and size), or their range",
    ),
];

/// Whether a kind renders a table (a block of lines) rather than a figure within a line.
pub fn is_table(kind: &str) -> bool {
    kind.ends_with("-table") || kind == "target-antialiased" || kind == "alternatives"
}

/// A marker's parameters, taken one by one; what is left are the filters.
pub struct Params(Vec<(String, String)>);

impl Params {
    /// The parameters of a marker, in order.
    pub fn new(params: Vec<(String, String)>) -> Params {
        Params(params)
    }

    /// The value of `key`, removed.
    fn take(&mut self, key: &str) -> Option<String> {
        let at = self.0.iter().position(|(k, _)| k == key)?;
        Some(self.0.remove(at).1)
    }

    /// The rest, as filters.
    fn filters(self) -> Vec<Filter> {
        self.0
            .into_iter()
            .map(|(key, values)| Filter::new(&key, &values))
            .collect()
    }

    /// `digits=` or `sig=`.
    fn precision(&mut self) -> Result<Precision, String> {
        let count = |key: &str, v: String| {
            v.parse::<usize>()
                .map_err(|_| format!("{key}={v}: not a count of digits"))
        };
        match (self.take("digits"), self.take("sig")) {
            (Some(_), Some(_)) => Err("digits= or sig=, not both".into()),
            (Some(d), None) => Ok(Precision::Decimals(count("digits", d)?)),
            (None, Some(s)) => Ok(Precision::Significant(count("sig", s)?)),
            (None, None) => Ok(Precision::Default),
        }
    }
}

/// The records of `source` that pass `filters`, as `T`.
fn typed<T: DeserializeOwned>(
    sources: &mut Sources,
    source: &str,
    filters: &[Filter],
) -> Result<(Vec<T>, Vec<T>), String> {
    let all = sources.get(source)?;
    let parse = |v: &Value| {
        serde_json::from_value::<T>(v.clone()).map_err(|e| format!("results/{source}.json: {e}"))
    };
    let kept = select(all, source, filters)?
        .into_iter()
        .map(parse)
        .collect::<Result<_, _>>()?;
    let every = all.iter().map(parse).collect::<Result<_, _>>()?;
    Ok((kept, every))
}

/// The text of a block of `kind` with `params`.
pub fn render(kind: &str, mut params: Params, sources: &mut Sources) -> Result<String, String> {
    use peel_compiler::tools::{bench_compile, bench_frames};
    use peel_target_runner::results::{self, Record};
    match kind {
        "target-table" => {
            let columns = params.take("columns");
            let (rows, _) = typed::<Record>(sources, "target", &params.filters())?;
            let keys: Vec<&str> = match &columns {
                Some(c) => c.split(',').collect(),
                None => results::RESULTS_MD.to_vec(),
            };
            Ok(results::table(&rows, &results::columns_of(&keys)?))
        }
        "target-antialiased" => {
            let (rows, _) = typed::<Record>(sources, "target", &params.filters())?;
            let table = results::antialiased_table(&rows);
            if table.is_empty() {
                return Err("no anti-aliased record (method peel-front-to-back-aa) there".into());
            }
            Ok(table)
        }
        "alternatives" => {
            let scenes = params.take("scene");
            let rest = params.filters();
            if let Some(f) = rest.first() {
                return Err(format!("alternatives takes scene= alone, not {}=", f.key));
            }
            let (all, _) = typed::<Record>(sources, "target", &[])?;
            let scenes: Vec<&str> = match &scenes {
                Some(s) => s.split(',').collect(),
                None => results::alternatives_scenes(&all),
            };
            if scenes.is_empty() {
                return Err(
                    "results/target.json has neither the teapot nor the cow: name the \
                            scenes with scene=NAME,..."
                        .into(),
                );
            }
            for s in &scenes {
                if !all.iter().any(|r| r.scene == *s) {
                    return Err(format!("no scene {s:?} in results/target.json"));
                }
            }
            Ok(results::alternatives(&all, &scenes))
        }
        "frames-table" => {
            let (rows, all) =
                typed::<bench_frames::FrameRecord>(sources, "frames", &params.filters())?;
            Ok(bench_frames::markdown_of(&rows, &all))
        }
        "compile-table" => {
            let (rows, _) =
                typed::<bench_compile::BenchRow>(sources, "compile", &params.filters())?;
            Ok(bench_compile::markdown(&rows))
        }
        "value" => value(params, sources),
        "ratio" => ratio(params, sources),
        other => {
            let names: Vec<&str> = KINDS.iter().map(|(k, _)| *k).collect();
            Err(format!("no kind {other:?} (kinds: {})", names.join(", ")))
        }
    }
}

/// The number in `record`'s field `key`.
fn number_of(record: &Value, key: &str, source: &str) -> Result<f64, String> {
    let v = field(record, key)
        .ok_or_else(|| format!("no field {key:?} in a record of results/{source}.json"))?;
    v.as_f64().ok_or_else(|| {
        format!(
            "field {key:?} is {} in a record of results/{source}.json, not a number",
            text(v)
        )
    })
}

/// `value`: a field of the records, one figure or the range of them; text fields give their
/// distinct values.
fn value(mut params: Params, sources: &mut Sources) -> Result<String, String> {
    let source = params.take("source").unwrap_or_else(|| "target".into());
    let key = params.take("field").ok_or("value needs field=KEY")?;
    let unit = number::unit(&params.take("unit").unwrap_or_default())?;
    let precision = params.precision()?;
    let records = sources.get(&source)?;
    let kept = select(records, &source, &params.filters())?;
    if kept
        .iter()
        .all(|r| field(r, &key).is_some_and(Value::is_string))
    {
        let mut texts: Vec<String> = Vec::new();
        for r in &kept {
            let t = field(r, &key).map(text).unwrap_or_default();
            if !texts.contains(&t) {
                texts.push(t);
            }
        }
        return Ok(texts.join(", "));
    }
    let values = kept
        .iter()
        .map(|r| number_of(r, &key, &source))
        .collect::<Result<Vec<f64>, String>>()?;
    Ok(number::range(&values, unit, precision))
}

/// The fields that tell apart the records a ratio compares, besides the method (and path).
fn identity(source: &str) -> Result<&'static [&'static str], String> {
    match source {
        "target" => Ok(&["scene", "shading", "transparent", "core", "width", "height"]),
        "frames" => Ok(&["scene"]),
        _ => Err(format!(
            "ratio compares methods: results/{source}.json has none"
        )),
    }
}

/// A group's name in a message: its fields' values, those absent (an opaque record's
/// `transparent`) left out.
fn named(g: &[String]) -> String {
    let present: Vec<&str> = g
        .iter()
        .map(String::as_str)
        .filter(|v| !v.is_empty())
        .collect();
    present.join(" ")
}

/// `ratio`: `a`'s field over `b`'s for each scene (and core and size) that has both, one
/// figure or their range.
fn ratio(mut params: Params, sources: &mut Sources) -> Result<String, String> {
    let source = params.take("source").unwrap_or_else(|| "target".into());
    let key = match params.take("field") {
        Some(k) => k,
        None if source == "target" => "instructions".into(),
        None => return Err(format!("ratio of results/{source}.json needs field=KEY")),
    };
    let (a, b) = (
        params.take("a").ok_or("ratio needs a=METHOD[/PATH]")?,
        params.take("b").ok_or("ratio needs b=METHOD[/PATH]")?,
    );
    let precision = params.precision()?;
    let identity = identity(&source)?;
    let records = sources.get(&source)?;
    let kept = select(records, &source, &params.filters())?;
    // `method/path` where records have paths; frames' methods hold a `/` of their own.
    let has_path = kept.iter().any(|r| field(r, "path").is_some());
    let picks = |side: &str, r: &Value| {
        let (method, path) = match side.split_once('/') {
            Some((m, p)) if has_path => (m, Some(p)),
            _ => (side, None),
        };
        field(r, "method").map(text).as_deref() == Some(method)
            && path.is_none_or(|p| field(r, "path").map(text).as_deref() == Some(p))
    };
    // A target record written before smooth ones existed is flat.
    let group = |r: &Value| -> Vec<String> {
        identity
            .iter()
            .map(|&k| match field(r, k) {
                Some(v) => text(v),
                None if k == "shading" => "flat".into(),
                None => String::new(),
            })
            .collect()
    };
    let mut ratios = Vec::new();
    let mut groups: Vec<Vec<String>> = kept.iter().map(|r| group(r)).collect();
    groups.sort();
    groups.dedup();
    for g in groups {
        let mine: Vec<&Value> = kept.iter().copied().filter(|r| group(r) == g).collect();
        let one = |side: &str| -> Result<Option<&Value>, String> {
            let found: Vec<&Value> = mine.iter().copied().filter(|r| picks(side, r)).collect();
            match found.as_slice() {
                [] => Ok(None),
                [r] => Ok(Some(r)),
                _ => Err(format!(
                    "{side} is {} records for {}: name the path (METHOD/PATH) or filter",
                    found.len(),
                    named(&g)
                )),
            }
        };
        if let (Some(x), Some(y)) = (one(&a)?, one(&b)?) {
            let (x, y) = (number_of(x, &key, &source)?, number_of(y, &key, &source)?);
            if y == 0.0 {
                return Err(format!("{b}'s {key} is 0 for {}", named(&g)));
            }
            ratios.push(x / y);
        }
    }
    if ratios.is_empty() {
        return Err(format!(
            "no {} of results/{source}.json has both a={a} and b={b}",
            identity.join("/")
        ));
    }
    Ok(number::range(&ratios, number::unit("x")?, precision))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// Sources in a temporary folder: target records of two scenes and cores, and frames.
    fn sources() -> (tempfile::TempDir, Sources) {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("results")).unwrap();
        let target = |scene: &str, method: &str, path: &str, core: &str, instructions: u64| {
            json!({"scene": scene, "method": method, "path": path, "core": core, "width": 320,
                   "height": 240, "instructions": instructions, "ram_bytes": 1000})
        };
        let records = json!([
            target("teapot", "peel-front-to-back", "stream", "cortex-m4f", 300),
            target(
                "teapot",
                "peel-front-to-back",
                "framebuffer",
                "cortex-m4f",
                250
            ),
            target("teapot", "zbuffer-int", "framebuffer", "cortex-m4f", 200),
            target("cow", "peel-front-to-back", "stream", "cortex-m4f", 390),
            target("cow", "zbuffer-int", "framebuffer", "cortex-m4f", 300),
            target("cow", "zbuffer-int", "framebuffer", "cortex-m0plus", 900),
        ]);
        let frames = json!([
            {"scene": "demo", "method": "zbuffer-int", "median_frame_ms": 0.081},
            {"scene": "demo", "method": "peel-front-to-back/sub0", "median_frame_ms": 0.065},
        ]);
        for (name, v) in [("target", records), ("frames", frames)] {
            std::fs::write(
                dir.path().join(format!("results/{name}.json")),
                v.to_string(),
            )
            .unwrap();
        }
        let s = Sources::new(dir.path());
        (dir, s)
    }

    fn render_marker(words: &str, sources: &mut Sources) -> Result<String, String> {
        let mut w = words.split_whitespace();
        let kind = w.next().unwrap();
        let params = w
            .map(|p| {
                let (k, v) = p.split_once('=').unwrap();
                (k.to_string(), v.to_string())
            })
            .collect();
        render(kind, Params::new(params), sources)
    }

    /// A smooth record is not its flat twin's: a ratio pairs records of one shading, the
    /// records without one being flat.
    #[test]
    fn ratios_pair_records_of_one_shading() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("results")).unwrap();
        let records = json!([
            {"scene": "cow", "method": "peel-front-to-back", "path": "stream", "core": "cortex-m4f",
             "width": 320, "height": 240, "instructions": 390},
            {"scene": "cow", "method": "peel-front-to-back", "path": "stream", "shading": "smooth",
             "core": "cortex-m4f", "width": 320, "height": 240, "instructions": 500},
            {"scene": "cow", "method": "zbuffer-int", "path": "framebuffer", "shading": "flat",
             "core": "cortex-m4f", "width": 320, "height": 240, "instructions": 300},
        ]);
        std::fs::write(dir.path().join("results/target.json"), records.to_string()).unwrap();
        let mut s = Sources::new(dir.path());
        assert_eq!(
            render_marker("ratio a=peel-front-to-back/stream b=zbuffer-int", &mut s).unwrap(),
            "1.30x"
        );
    }

    #[test]
    fn ratios_pair_the_records_of_each_scene_and_core() {
        let (_dir, mut s) = sources();
        let mut r = |w: &str| render_marker(w, &mut s);
        assert_eq!(
            r("ratio a=peel-front-to-back/stream b=zbuffer-int").unwrap(),
            "1.30-1.50x"
        );
        assert_eq!(
            r("ratio scene=cow a=peel-front-to-back/stream b=zbuffer-int").unwrap(),
            "1.30x"
        );
        assert_eq!(
            r("ratio a=peel-front-to-back/stream b=zbuffer-int sig=1").unwrap(),
            "1-2x"
        );
        let e = r("ratio scene=teapot a=peel-front-to-back b=zbuffer-int").unwrap_err();
        assert!(
            e.contains("peel-front-to-back is 2 records for teapot flat cortex-m4f 320 240"),
            "{e}"
        );
        let e = r("ratio a=zbuffer-int b=peel-front-to-back/scan-order").unwrap_err();
        assert!(
            e.contains("has both a=zbuffer-int and b=peel-front-to-back/scan-order"),
            "{e}"
        );
        assert!(r("ratio a=x").unwrap_err().contains("b=METHOD"));

        assert!(r("ratio source=frames a=x b=y")
            .unwrap_err()
            .contains("needs field=KEY"));
        // The frames' methods hold a `/` of their own.
        assert_eq!(
            r("ratio source=frames field=median_frame_ms a=zbuffer-int b=peel-front-to-back/sub0")
                .unwrap(),
            "1.25x"
        );
    }

    #[test]
    fn values_and_tables() {
        let (_dir, mut s) = sources();
        let mut r = |w: &str| render_marker(w, &mut s);
        assert_eq!(r("value field=instructions scene=cow").unwrap(), "300-900");
        assert_eq!(
            r("value field=instructions core!=cortex-m0plus unit=B").unwrap(),
            "200-390 B"
        );
        assert_eq!(
            r("value field=path method=zbuffer-int").unwrap(),
            "framebuffer"
        );
        assert_eq!(
            r("value field=path scene=teapot").unwrap(),
            "stream, framebuffer"
        );
        assert!(r("value scene=cow").unwrap_err().contains("field=KEY"));
        assert!(r("value field=ram unit=B")
            .unwrap_err()
            .contains("no field \"ram\""));
        assert!(r("value field=ram_bytes digits=2 sig=1")
            .unwrap_err()
            .contains("not both"));
        assert!(r("nothing")
            .unwrap_err()
            .starts_with("no kind \"nothing\" (kinds: target-table,"));
        // Tables need whole records: these are not.
        assert!(r("target-table").unwrap_err().contains("missing field"));
        let e = r("alternatives").unwrap_err();
        assert!(e.contains("missing field"), "{e}");
    }
}
