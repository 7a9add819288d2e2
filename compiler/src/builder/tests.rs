//! Builder tests: watched paths, the cache (key, hits, damaged and stale entries, MTL
//! changes, warnings), the sizes file and the default colour.

use super::cache::{self, Key, Miss};
use super::*;
use crate::compile::compile_obj;
use crate::shadow::Light;
use peel_runtime::read::Scene;
use std::fs;

/// A cube without materials (its faces get the default colour, without a warning: the file
/// names no material).
const CUBE: &str = include_str!("../../../fixtures/cube.obj");

/// The cube with a material library it uses for no face: its faces get the default colour,
/// with a warning.
const CUBE_WITH_LIBRARY: &str = concat!(
    "mtllib cube.mtl\n",
    include_str!("../../../fixtures/cube.obj")
);

/// Writes `CUBE_WITH_LIBRARY` and its library into `dir`; the OBJ's path.
fn cube_with_library(dir: &Path) -> PathBuf {
    write(dir, "cube.mtl", "newmtl unused\nKd 1 0 0\n");
    write(dir, "cube.obj", CUBE_WITH_LIBRARY)
}

/// A triangle with a material from `m.mtl`.
const RED_TRIANGLE: &str = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    fs::write(&path, text).unwrap();
    path
}

/// A builder writing into `dir/out` with its cache in `dir/cache`.
fn builder(dir: &Path, obj: &Path) -> Builder {
    Builder::new(obj).out_dir(dir).cache_dir(dir.join("cache"))
}

/// The cache's entry files.
fn entries(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = fs::read_dir(dir.join("cache"))
        .map(|d| d.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn missing_mtl_files_are_watched_through_their_nearest_folder() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(
        dir.path(),
        "scene.obj",
        "mtllib here.mtl\nmtllib gone.mtl\nmtllib sub/deeper/gone.mtl\n\
         v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n",
    );
    let here = write(dir.path(), "here.mtl", "newmtl red\nKd 1 0 0\n");
    let compiled = compile_obj(&obj, &CompileOptions::default(), &|_| {}).unwrap();
    assert_eq!(compiled.files, [obj.clone(), here.clone()]);
    assert_eq!(compiled.missing.len(), 2);
    // The folder holds the missing file; `sub/deeper` does not exist, so its nearest
    // existing ancestor (the same folder) is watched, once.
    assert_eq!(
        watched(&compiled.files[1..], &compiled.missing),
        [here.clone(), dir.path().to_path_buf()]
    );
    // The Builder writes the file and still succeeds (missing MTL files only warn), and a hit
    // watches the same paths.
    for from_cache in [false, true] {
        let done = builder(dir.path(), &obj)
            .cached_compile(fs::read(&obj).unwrap(), Vec::new(), Instant::now())
            .unwrap();
        assert_eq!(done.from_cache, from_cache);
        assert_eq!(
            watched(&done.mtl_files, &done.entry.missing),
            [here.clone(), dir.path().to_path_buf()]
        );
    }
    let out = builder(dir.path(), &obj).compile().unwrap();
    assert!(out.peel.exists() && out.sizes.exists() && out.from_cache);
}

#[test]
fn the_key_is_the_compiler_the_options_and_the_obj() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(dir.path(), "cube.obj", CUBE);
    let other = write(dir.path(), "other.obj", CUBE);
    let bytes = CUBE.as_bytes();
    let options = CompileOptions::default();
    let key =
        |obj: &Path, bytes: &[u8], options: &CompileOptions| Key::new(obj, bytes, options).unwrap();
    let base = key(&obj, bytes, &options);
    // Same inputs, same key and entry.
    assert_eq!(base, key(&obj, bytes, &options));
    assert_eq!(base.file_name(), key(&obj, bytes, &options).file_name());
    // Other bytes: another key, the same entry file (a new compile replaces the old one).
    let mut edited = bytes.to_vec();
    edited.extend_from_slice(b"\n");
    assert_ne!(base, key(&obj, &edited, &options));
    assert_eq!(base.file_name(), key(&obj, &edited, &options).file_name());
    // Every option and the path: another key and another entry.
    let mut variants = Vec::new();
    let mut o = options.clone();
    o.ids = true;
    variants.push(o);
    let mut o = options.clone();
    o.build.candidates += 1;
    variants.push(o);
    let mut o = options.clone();
    o.build.seed = 1;
    variants.push(o);
    let mut o = options.clone();
    o.build.max_polygon_vertices = 3;
    variants.push(o);
    let mut o = options.clone();
    o.build.watertight = false;
    variants.push(o);
    let mut o = options.clone();
    o.shading = Shading::Flat;
    variants.push(o);
    let mut o = options.clone();
    o.shading = Shading::Lambert(glam::DVec3::new(1.0, 2.0, 3.0));
    variants.push(o);
    let mut o = options.clone();
    o.load.default_colour = Some([1, 2, 3]);
    variants.push(o);
    let mut o = options.clone();
    o.load.max_texture = 64;
    variants.push(o);
    let mut o = options.clone();
    o.load.resample = false;
    variants.push(o);
    // The surface other than the default, and another crease.
    let smooth = Surface::smooth(60.0).unwrap();
    for surface in [
        if options.surface == Surface::Faceted {
            smooth
        } else {
            Surface::Faceted
        },
        Surface::smooth(30.0).unwrap(),
    ] {
        let mut o = options.clone();
        o.surface = surface;
        variants.push(o);
    }
    let mut keys = vec![base.clone(), key(&other, bytes, &options)];
    keys.extend(variants.iter().map(|o| key(&obj, bytes, o)));
    for (i, a) in keys.iter().enumerate() {
        for b in &keys[i + 1..] {
            assert_ne!(a, b);
            assert_ne!(a.file_name(), b.file_name());
        }
    }
}

#[test]
fn the_second_compile_comes_from_the_cache_with_the_same_bytes_and_warnings() {
    let dir = tempfile::tempdir().unwrap();
    let obj = cube_with_library(dir.path());
    let b = builder(dir.path(), &obj);
    let first = b
        .cached_compile(CUBE_WITH_LIBRARY.into(), Vec::new(), Instant::now())
        .unwrap();
    let second = b
        .cached_compile(CUBE_WITH_LIBRARY.into(), Vec::new(), Instant::now())
        .unwrap();
    assert!(!first.from_cache && second.from_cache, "{}", second.note);
    assert_eq!(first.entry, second.entry);
    assert!(first.entry.warnings[0].contains("no material"));
    assert_eq!(entries(dir.path()).len(), 1);
    // The files written are the same either way.
    let out = b.compile().unwrap();
    assert!(out.from_cache);
    assert_eq!(fs::read(&out.peel).unwrap(), first.entry.peel);
    let uncached = Builder::new(&obj)
        .out_dir(dir.path().join("uncached"))
        .cache(false);
    fs::create_dir(dir.path().join("uncached")).unwrap();
    let plain = uncached.compile().unwrap();
    assert!(!plain.from_cache);
    assert_eq!(fs::read(&plain.peel).unwrap(), first.entry.peel);
    assert_eq!(
        fs::read(&plain.sizes).unwrap(),
        fs::read(&out.sizes).unwrap()
    );
}

#[test]
fn a_damaged_entry_is_compiled_again_and_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(dir.path(), "cube.obj", CUBE);
    let b = builder(dir.path(), &obj);
    let good = b
        .cached_compile(CUBE.into(), Vec::new(), Instant::now())
        .unwrap()
        .entry;
    let [entry] = &entries(dir.path())[..] else {
        panic!("one entry expected");
    };
    let stored = fs::read(entry).unwrap();
    let key = Key::new(&obj, CUBE.as_bytes(), &b.options).unwrap();
    let dir_cache = dir.path().join("cache");
    let mut flipped = stored.clone();
    let last = flipped.len() - 1;
    flipped[last] ^= 1;
    let damages: Vec<(&str, Vec<u8>, Miss)> = vec![
        ("empty", Vec::new(), Miss::Corrupt),
        (
            "truncated",
            stored[..stored.len() / 2].to_vec(),
            Miss::Corrupt,
        ),
        ("one bit", flipped, Miss::Corrupt),
        ("garbage", vec![7; 4096], Miss::Corrupt),
    ];
    for (what, bytes, miss) in damages {
        fs::write(entry, &bytes).unwrap();
        assert_eq!(cache::lookup(&dir_cache, &key), Err(miss), "{what}");
        let done = b
            .cached_compile(CUBE.into(), Vec::new(), Instant::now())
            .unwrap();
        assert!(!done.from_cache, "{what}");
        assert_eq!(done.entry, good, "{what}");
        assert_eq!(
            fs::read(entry).unwrap(),
            stored,
            "{what}: the entry is rewritten"
        );
        assert!(
            b.cached_compile(CUBE.into(), Vec::new(), Instant::now())
                .unwrap()
                .from_cache
        );
    }
    // A checksum that matches damaged `.peel` bytes (a bad writer): the full validation
    // refuses them.
    let mut bad = good.clone();
    bad.peel.truncate(40);
    cache::store(&dir_cache, &key, &bad).unwrap();
    assert_eq!(cache::lookup(&dir_cache, &key), Err(Miss::Corrupt));
    let done = b
        .cached_compile(CUBE.into(), Vec::new(), Instant::now())
        .unwrap();
    assert!(!done.from_cache);
    assert!(Scene::parse(&fs::read(entry).unwrap()).is_err());
    assert_eq!(cache::lookup(&dir_cache, &key), Ok(good));
}

#[test]
fn an_edited_obj_or_mtl_or_a_new_mtl_is_compiled_again() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(dir.path(), "t.obj", RED_TRIANGLE);
    let b = builder(dir.path(), &obj);
    let run = |bytes: &str| {
        b.cached_compile(bytes.into(), Vec::new(), Instant::now())
            .unwrap()
    };
    // The MTL is missing: default colour and a warning; its appearance invalidates.
    let missing = run(RED_TRIANGLE);
    assert!(!missing.from_cache && !missing.entry.warnings.is_empty());
    assert!(run(RED_TRIANGLE).from_cache);
    write(dir.path(), "m.mtl", "newmtl red\nKd 1 0 0\n");
    let red = run(RED_TRIANGLE);
    assert!(!red.from_cache, "{}", red.note);
    assert!(red.note.contains("MTL"), "{}", red.note);
    assert_ne!(red.entry.peel, missing.entry.peel);
    assert!(run(RED_TRIANGLE).from_cache);
    // An edited MTL.
    write(dir.path(), "m.mtl", "newmtl red\nKd 0 0 1\n");
    let blue = run(RED_TRIANGLE);
    assert!(!blue.from_cache);
    assert_ne!(blue.entry.peel, red.entry.peel);
    assert!(run(RED_TRIANGLE).from_cache);
    // Edited OBJ bytes (the builder passes what it read).
    let edited = format!("{RED_TRIANGLE}v 0 0 1\nf 1 2 4\n");
    let more = run(&edited);
    assert!(
        !more.from_cache && more.note.contains("other OBJ bytes"),
        "{}",
        more.note
    );
    assert!(run(&edited).from_cache);
    // Each change replaced the asset's one entry.
    assert_eq!(entries(dir.path()).len(), 1);
}

/// A texture image is one of the files a compile read: watched, and an edit of it compiles
/// again.
#[cfg(feature = "textures")]
#[test]
fn an_edited_texture_is_compiled_again() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(
        dir.path(),
        "t.obj",
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl tex\n\
         f 1/1 2/2 3/3\n",
    );
    write(dir.path(), "m.mtl", "newmtl tex\nmap_Kd t.png\n");
    let image = dir.path().join("t.png");
    let png = |rgb: [u8; 3]| {
        image::RgbImage::from_pixel(2, 2, image::Rgb(rgb))
            .save(&image)
            .unwrap()
    };
    png([255, 0, 0]);
    let b = builder(dir.path(), &obj);
    let bytes = fs::read(&obj).unwrap();
    let run = || {
        b.cached_compile(bytes.clone(), Vec::new(), Instant::now())
            .unwrap()
    };
    let red = run();
    assert!(!red.from_cache);
    assert!(red.mtl_files.contains(&image), "{:?}", red.mtl_files);
    assert!(watched(&red.mtl_files, &[]).contains(&image));
    assert!(run().from_cache);
    png([0, 0, 255]);
    let blue = run();
    assert!(
        !blue.from_cache && blue.note.contains("texture"),
        "{}",
        blue.note
    );
    assert_ne!(blue.entry.peel, red.entry.peel);
    assert!(run().from_cache);
}

#[test]
fn the_cache_folder_is_in_the_target_directory_for_every_profile_and_target() {
    let target = Path::new("/work/project/target");
    for profile in ["debug", "release", "custom"] {
        let out = target.join(profile).join("build/app-0123abcd/out");
        assert_eq!(
            cache::dir_from_out_dir(&out, Some("x86_64-unknown-linux-gnu")),
            Some(target.join("peel-cache"))
        );
        let cross = target
            .join("thumbv7em-none-eabihf")
            .join(profile)
            .join("build/app-0123abcd/out");
        assert_eq!(
            cache::dir_from_out_dir(&cross, Some("thumbv7em-none-eabihf")),
            Some(target.join("peel-cache"))
        );
    }
    assert_eq!(cache::dir_from_out_dir(Path::new("/tmp/out"), None), None);
    assert_eq!(
        cache::dir_from_out_dir(Path::new("/a/b/debug/deps/x/out"), None),
        None
    );
    // Off, or explicit.
    let b = Builder::new("x.obj").cache(false).cache_dir("/somewhere");
    assert_eq!(b.cache_location(), None);
    let b = Builder::new("x.obj").cache_dir("/somewhere");
    assert_eq!(b.cache_location(), Some(PathBuf::from("/somewhere")));
}

#[test]
fn the_sizes_file_has_the_header_s_figures() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(dir.path(), "cube.obj", CUBE);
    let out = builder(dir.path(), &obj)
        .out_name("box.peel")
        .compile()
        .unwrap();
    assert_eq!(out.sizes, dir.path().join("box.rs"));
    let bytes = fs::read(&out.peel).unwrap();
    let h = Scene::parse(&bytes).unwrap().header();
    let text = fs::read_to_string(&out.sizes).unwrap();
    let has = |line: String| assert!(text.contains(&line), "{line} not in\n{text}");
    has(format!("pub const STACK: usize = {};", h.max_depth));
    has(format!("pub const MAX_DEPTH: usize = {};", h.max_depth));
    has(format!(
        "pub const VERTS: usize = {};",
        h.max_polygon_vertices as usize + peel_runtime::clip::CLIP_PLANES
    ));
    has(format!(
        "pub const MAX_POLYGON_VERTICES: usize = {};",
        h.max_polygon_vertices
    ));
    has(format!("pub const VERTICES: usize = {};", h.vertex_count));
    has(format!(
        "pub const VERTEX_MEMORY: usize = {};",
        (h.vertex_count as usize).next_power_of_two()
    ));
    has(format!("pub const POLYGONS: usize = {};", h.polygon_count));
    has(format!("pub const NODES: usize = {};", h.node_count));
    has(format!("pub const BYTES: usize = {};", bytes.len()));
    has(format!(
        "pub const CENTRE: [f64; 3] = [{:?}, {:?}, {:?}];",
        h.centre[0], h.centre[1], h.centre[2]
    ));
    has(format!(
        "pub const BOUNDS_MIN: [f32; 3] = [{:?}, {:?}, {:?}];",
        h.bounds_min.x, h.bounds_min.y, h.bounds_min.z
    ));
    has(format!(
        "pub const SPANS_PER_ROW: usize = {};",
        crate::tools::raster::HOST_SPANS_PER_ROW
    ));
    has("pub const fn check_workspace(stack: usize, verts: usize)".into());
    // Every item may go unused in the firmware.
    let items = text.lines().filter(|l| l.starts_with("pub ")).count();
    let allowed = text
        .lines()
        .filter(|l| l.starts_with("#[allow(dead_code"))
        .count();
    assert_eq!(items, allowed);
    // A name that would be its own sizes file is refused.
    assert!(builder(dir.path(), &obj)
        .out_name("box.rs")
        .compile()
        .is_err());
}

#[test]
fn an_image_size_measures_the_span_memory_of_an_orbit() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(dir.path(), "cube.obj", CUBE);
    let out = builder(dir.path(), &obj)
        .image_size(160, 120)
        .compile()
        .unwrap();
    let bytes = fs::read(&out.peel).unwrap();
    let want = spans::spans_per_row(&bytes, 160, 120).unwrap();
    // A convex cube: a face or two beside another before they touch.
    assert!((1..=3).contains(&want), "{want}");
    let text = fs::read_to_string(&out.sizes).unwrap();
    assert!(text.contains(&format!("pub const SPANS_PER_ROW: usize = {want};")));
    assert!(text.contains("pub const SPANS_MEASURED_AT: (u32, u32) = (160, 120);"));
    assert!(text.contains("no frame of an orbit"));
    let aa = spans::scan_nodes_antialiased(&bytes, 160, 120).unwrap();
    assert!(text.contains(&format!("pub const SCAN_NODES_AA: usize = {aa};")));
    assert!(text.contains("SCAN_NODES_AA * 6 + PENDING_PIXELS * 12 + 4 * height as usize"));
    // From the cache, the same measurement.
    let again = builder(dir.path(), &obj)
        .image_size(160, 120)
        .compile()
        .unwrap();
    assert!(again.from_cache);
    assert_eq!(fs::read_to_string(&again.sizes).unwrap(), text);
}

/// The value of `pub const NAME: usize = value;` in a sizes file.
fn constant(text: &str, name: &str) -> usize {
    let prefix = format!("pub const {name}: usize = ");
    text.lines()
        .find_map(|l| l.strip_prefix(&prefix)?.strip_suffix(';'))
        .unwrap_or_else(|| panic!("no {name} in\n{text}"))
        .parse()
        .unwrap()
}

#[test]
fn inspect_gives_the_frame_memory_of_the_sizes_file() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(
        dir.path(),
        "demo.obj",
        include_str!("../../../fixtures/demo.obj"),
    );
    for size in [None, Some((96, 64))] {
        let mut b = builder(dir.path(), &obj);
        if let Some((w, h)) = size {
            b = b.image_size(w, h);
        }
        let out = b.compile().unwrap();
        let text = fs::read_to_string(&out.sizes).unwrap();
        let bytes = fs::read(&out.peel).unwrap();
        let info = match size {
            None => crate::dump::inspect(&bytes).unwrap(),
            Some((w, h)) => crate::dump::inspect_at(&bytes, w, h).unwrap(),
        };
        let m = info.frame_memory;
        assert_eq!(m.measured_at, size);
        for (name, value) in [
            ("STACK", m.stack),
            ("VERTS", m.verts),
            ("VERTEX_MEMORY", m.vertex_memory),
            ("SPANS_PER_ROW", m.spans_per_row),
            ("SCAN_NODES", m.scan_nodes),
            ("SCAN_NODES_AA", m.scan_nodes_aa),
            ("PENDING_PIXELS", m.pending_pixels),
        ] {
            assert_eq!(constant(&text, name), value, "{name} at {size:?}");
        }
        let printed = crate::dump::inspect_text(&info);
        assert!(
            printed.contains(&format!("\n  stack: {}\n", m.stack))
                && printed.contains(&format!("\n  scan_nodes: {} (", m.scan_nodes)),
            "{printed}"
        );
    }
}

#[test]
fn a_default_colour_silences_the_warning_about_faces_without_material() {
    let dir = tempfile::tempdir().unwrap();
    let obj = cube_with_library(dir.path());
    let grey = builder(dir.path(), &obj)
        .cached_compile(CUBE_WITH_LIBRARY.into(), Vec::new(), Instant::now())
        .unwrap();
    assert_eq!(grey.entry.warnings.len(), 1, "{:?}", grey.entry.warnings);
    assert!(grey.entry.warnings[0].contains("--default-colour"));
    let b = builder(dir.path(), &obj)
        .default_colour([10, 20, 30])
        .shading(Shading::Flat);
    for from_cache in [false, true] {
        let done = b
            .cached_compile(CUBE_WITH_LIBRARY.into(), Vec::new(), Instant::now())
            .unwrap();
        assert_eq!(done.from_cache, from_cache);
        assert!(done.entry.warnings.is_empty(), "{:?}", done.entry.warnings);
        let scene = Scene::parse(&done.entry.peel).unwrap();
        let p = scene.polygon(0);
        assert_eq!(
            (p.colour.r, p.colour.g, p.colour.b),
            (10, 20, 30),
            "the faces get the colour"
        );
    }
}

#[test]
fn shadows_are_cast_from_the_shading_light_whatever_the_order() {
    let sun = glam::DVec3::new(0.3, 1.0, -0.2);
    let light = Shading::Lambert(sun);
    let a = Builder::new("x.obj").shadows(true).shading(light);
    let b = Builder::new("x.obj").shading(light).shadows(true);
    assert_eq!(a.options.build.shadows, Some(Light::Sun(sun)));
    assert_eq!(b.options.build.shadows, Some(Light::Sun(sun)));
    let point = b.clone().shading(Shading::Point(sun));
    assert_eq!(point.options.build.shadows, Some(Light::Point(sun)));
    let flat = Builder::new("x.obj").shadows(true).shading(Shading::Flat);
    assert_eq!(flat.options.build.shadows, None, "nothing to cast");
    let off = b.shadows(false);
    assert_eq!(off.options.build.shadows, None);
    // The option is part of the cache key: the builder does not take a lit compile for one
    // with shadows.
    let dir = tempfile::tempdir().unwrap();
    let obj = write(dir.path(), "cube.obj", CUBE);
    let bytes = fs::read(&obj).unwrap();
    let lit = Key::new(&obj, &bytes, &builder(dir.path(), &obj).options).unwrap();
    let cast = builder(dir.path(), &obj).shadows(true);
    assert_ne!(lit, Key::new(&obj, &bytes, &cast.options).unwrap());
}

/// A world and two objects: a file of parts whose sizes file gives the largest of each figure
/// over the parts; the second compile comes from the cache, an edited object misses it, and a
/// repeated name is refused before anything is written.
#[test]
fn objects_make_a_file_of_parts_sized_for_every_part() {
    let dir = tempfile::tempdir().unwrap();
    let world = write(dir.path(), "cube.obj", CUBE);
    let demo = write(
        dir.path(),
        "demo.obj",
        include_str!("../../../fixtures/demo.obj"),
    );
    let tri = write(
        dir.path(),
        "tri.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let b = builder(dir.path(), &world)
        .object("demo", &demo)
        .object("tri", &tri);
    let out = b.compile().unwrap();
    assert!(!out.from_cache);
    let bytes = fs::read(&out.peel).unwrap();
    let parts = crate::write::parts::read_parts(&bytes).unwrap();
    let names: Vec<&str> = parts.iter().map(|p| p.name).collect();
    assert_eq!(names, ["", "demo", "tri"]);
    let headers: Vec<_> = (parts.iter())
        .map(|p| Scene::parse(p.tree).unwrap().header())
        .collect();
    let text = fs::read_to_string(&out.sizes).unwrap();
    let most =
        |f: fn(&peel_runtime::read::Header) -> u32| headers.iter().map(f).max().unwrap() as usize;
    assert_eq!(constant(&text, "STACK"), most(|h| h.max_depth));
    assert_eq!(constant(&text, "VERTICES"), most(|h| h.vertex_count));
    assert_eq!(constant(&text, "POLYGONS"), most(|h| h.polygon_count));
    // Room for the cuts of posed objects, two vertices a plane.
    assert_eq!(
        constant(&text, "VERTS"),
        most(|h| h.max_polygon_vertices)
            + peel_runtime::clip::CLIP_PLANES
            + 2 * super::sizes::OBJECT_PLANES
    );
    assert_eq!(constant(&text, "OBJECTS"), 2);
    assert_eq!(
        constant(&text, "OBJECT_STEPS"),
        3 * super::sizes::STEPS_PER_OBJECT
    );
    assert_eq!(constant(&text, "BYTES"), bytes.len());
    // The demo is the largest part: the figures are not all the world's.
    assert!(headers[1].polygon_count > headers[0].polygon_count);
    assert!(text.contains(&format!(
        "pub const FORMAT_VERSION: u16 = {};",
        peel_runtime::read::layout::PARTS_VERSION
    )));

    let again = b.compile().unwrap();
    assert!(again.from_cache);
    assert_eq!(fs::read(&again.peel).unwrap(), bytes);
    assert_eq!(fs::read_to_string(&again.sizes).unwrap(), text);
    write(
        dir.path(),
        "tri.obj",
        "v 0 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    assert!(!b.compile().unwrap().from_cache);

    let e = builder(dir.path(), &world)
        .out_name("twice.peel")
        .object("a", &tri)
        .object("a", &tri)
        .compile()
        .unwrap_err();
    assert!(matches!(e, CompileError::PartName { .. }), "{e:?}");
    assert!(!dir.path().join("twice.peel").exists());
}
