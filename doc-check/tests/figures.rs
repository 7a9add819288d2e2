//! `peel-doc-check figures` on a scratch repository: it writes the marked figures from
//! `results/target.json`, `--check` passes on what it wrote and fails, naming the line, when
//! one digit of a marked text changes; a bad marker writes nothing.

use std::path::Path;
use std::process::{Command, Output};

use peel_target_runner::results::{self, Record};

fn record(scene: &str, method: &str, path: &str, instructions: u64, ram_bytes: u64) -> Record {
    Record {
        scene: scene.into(),
        method: method.into(),
        path: path.into(),
        shading: "flat".into(),
        core: "cortex-m4f".into(),
        width: 320,
        height: 240,
        triangles: 6320,
        instructions,
        ram_bytes,
        framebuffer_bytes: 0,
        flash_bytes: 436_064,
        text_bytes: 40_000,
        display_bytes: 153_611,
        display_writes: 2,
        differing_pixels: Some(0),
        robust_errors: Some(0),
        pending_peak: None,
        pending_records: None,
        pending_fallback: None,
        deterministic: true,
        objects: 0,
        transparent: false,
        fallback_rows: None,
        composite_peak: None,
        composite_runs: None,
    }
}

fn figures(root: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_peel-doc-check"))
        .arg("figures")
        .args(args)
        .arg("--root")
        .arg(root)
        .output()
        .unwrap()
}

const README: &str = "# Scratch\n\n<!-- figures: alternatives scene=teapot -->\n<!-- figures-end -->\n\n\
Peel takes <!-- figures: ratio scene=teapot core=cortex-m4f a=peel-front-to-back/stream \
b=embedded-3dgfx/framebuffer -->?<!-- figures-end --> embedded-3dgfx's instructions in \
<!-- figures: value field=ram_bytes method=peel-front-to-back unit=B -->?<!-- figures-end --> of RAM.\n";

fn scratch() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("results")).unwrap();
    let records = [
        record("teapot", "peel-front-to-back", "stream", 15_136_880, 24_920),
        record(
            "teapot",
            "embedded-3dgfx",
            "framebuffer",
            8_379_920,
            456_644,
        ),
        record("cow", "peel-front-to-back", "stream", 14_356_280, 21_080),
    ];
    std::fs::write(
        dir.path().join("results/target.json"),
        results::json(&records).unwrap(),
    )
    .unwrap();
    std::fs::write(dir.path().join("README.md"), README).unwrap();
    dir
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn written_figures_pass_the_check_and_one_changed_digit_fails_it() {
    let dir = scratch();
    let readme = dir.path().join("README.md");
    let o = figures(dir.path(), &["--check"]);
    assert!(
        !o.status.success(),
        "the placeholders differ from the results"
    );
    assert!(
        stderr(&o).contains("README.md:3: alternatives: the figures differ"),
        "{}",
        stderr(&o)
    );

    let o = figures(dir.path(), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let written = std::fs::read_to_string(&readme).unwrap();
    assert_eq!(
        written,
        "# Scratch\n\n<!-- figures: alternatives scene=teapot -->\n\
         | scene | core | method | path | instructions | RAM (bytes) | flash (bytes) | robust errors \
         | x Peel's instructions | x Peel's RAM |\n\
         |---|---|---|---|--:|--:|--:|--:|--:|--:|\n\
         | teapot | cortex-m4f | peel-front-to-back | stream | 15 136 880 | 24 920 | 436 064 | 0 | 1.00 | 1.00 |\n\
         | teapot | cortex-m4f | embedded-3dgfx | framebuffer | 8 379 920 | 456 644 | 436 064 | 0 | 0.55 | 18.32 |\n\
         \n<!-- figures-end -->\n\n\
         Peel takes <!-- figures: ratio scene=teapot core=cortex-m4f a=peel-front-to-back/stream \
         b=embedded-3dgfx/framebuffer -->1.81x<!-- figures-end --> embedded-3dgfx's instructions in \
         <!-- figures: value field=ram_bytes method=peel-front-to-back unit=B -->21,080-24,920 B\
         <!-- figures-end --> of RAM.\n"
    );
    let o = figures(dir.path(), &["--check"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Writing again changes nothing.
    assert!(figures(dir.path(), &[]).status.success());
    assert_eq!(std::fs::read_to_string(&readme).unwrap(), written);

    for (from, to, line) in [
        ("15 136 880", "15 136 881", 3),
        ("1.81x", "1.82x", 11),
        ("21,080-", "21,081-", 11),
    ] {
        std::fs::write(&readme, written.replacen(from, to, 1)).unwrap();
        let o = figures(dir.path(), &["--check"]);
        assert!(!o.status.success(), "{from} -> {to} passed");
        let e = stderr(&o);
        assert!(e.contains(&format!("README.md:{line}: ")), "{e}");
        assert!(e.contains(to) && e.contains(from), "{e}");
        assert!(e.contains("1 marked texts differ"), "{e}");
    }
}

#[test]
fn a_bad_marker_writes_nothing() {
    let dir = scratch();
    let readme = dir.path().join("README.md");
    let text = format!("{README}\n<!-- figures: ratio a=zbuffer-int b=peel-front-to-back/stream -->x<!-- figures-end -->\n");
    std::fs::write(&readme, &text).unwrap();
    let o = figures(dir.path(), &[]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("README.md:8: ratio: no scene/shading/transparent/core/width/height of results/target.json has both a=zbuffer-int"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read_to_string(&readme).unwrap(), text);
    // A missing results file names what writes it.
    std::fs::remove_file(dir.path().join("results/target.json")).unwrap();
    let o = figures(dir.path(), &["--check"]);
    assert!(
        stderr(&o).contains("results/target.json: cannot read"),
        "{}",
        stderr(&o)
    );
    assert!(stderr(&o).contains("bash .ci/target"), "{}", stderr(&o));
}
