//! The example's PNG output, run as a user runs it, against the host renderer: the simulator's
//! frame must be `tools::raster`'s frame of the same orbit camera, pixel for pixel in RGB565,
//! in scan order and streamed, for the scene build.rs compiled and for a `.peel` file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use embedded_graphics_core::pixelcolor::raw::RawU16;
use embedded_graphics_core::pixelcolor::{Rgb565, Rgb888, RgbColor};
use peel_compiler::compile::{compile_obj, CompileOptions};
use peel_compiler::tools::raster::render_bytes;
use peel_compiler::tools::shot::Shot;
use peel_runtime::camera::{Orbit, DEFAULT_FOV_Y_DEG};
use peel_runtime::display::Colour;
use peel_runtime::read::Scene;

/// The scene the example embeds.
static BUILT_IN: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/scene.peel"));
/// The example's display, background and orbit elevation (its docs: docs/desktop.md).
const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;
const BACKGROUND: [u8; 3] = [24, 26, 32];
const ELEVATION_DEG: f64 = 20.0;

fn example() -> Command {
    Command::new(env!("CARGO_BIN_EXE_peel-desktop-example"))
}

/// Run the example with `args`; its output, with a message naming the command on failure.
fn run(args: &[&str]) -> Output {
    let out = example().args(args).output().expect("run the example");
    assert!(
        out.status.success(),
        "peel-desktop-example {}: {}\n{}",
        args.join(" "),
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The PNG's pixels, RGB888 as the simulator wrote them.
fn read_png(path: &Path) -> Vec<[u8; 3]> {
    let image = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8();
    assert_eq!(image.dimensions(), (WIDTH, HEIGHT), "{}", path.display());
    image.pixels().map(|p| p.0).collect()
}

/// The host renderer's frame of `bytes` at `azimuth_deg` on the example's orbit, each pixel
/// [`shown`] as the simulator would show it.
fn host_frame(bytes: &[u8], azimuth_deg: f64) -> Vec<[u8; 3]> {
    let header = Scene::parse(bytes).expect("a valid scene").header();
    let pose = Orbit {
        azimuth_deg,
        elevation_deg: ELEVATION_DEG,
        distance: Orbit::fitting_distance(DEFAULT_FOV_Y_DEG, WIDTH, HEIGHT),
    }
    .pose(&header);
    let shot = Shot {
        up: pose.up,
        ..Shot::new(pose.eye, pose.target, WIDTH, HEIGHT)
    };
    let frame = render_bytes(bytes, &shot, false, BACKGROUND).expect("the host renders");
    frame
        .pixels
        .iter()
        .map(|&p| shown(Colour::new((p >> 16) as u8, (p >> 8) as u8, p as u8)))
        .collect()
}

/// `colour` quantised to RGB565 as firmware sends it (the runtime's `Colour::to_rgb565`),
/// then shown as the simulator shows an RGB565 pixel (embedded-graphics' `Rgb565` to
/// `Rgb888`).
fn shown(colour: Colour) -> [u8; 3] {
    let c = Rgb888::from(Rgb565::from(RawU16::new(colour.to_rgb565())));
    [c.r(), c.g(), c.b()]
}

/// Pixels where `a` and `b` differ, with the first few named.
fn differences(a: &[[u8; 3]], b: &[[u8; 3]]) -> (usize, Vec<String>) {
    assert_eq!(a.len(), b.len());
    let differ: Vec<usize> = (0..a.len()).filter(|&i| a[i] != b[i]).collect();
    let first = differ
        .iter()
        .take(5)
        .map(|&i| {
            let (x, y) = (i as u32 % WIDTH, i as u32 / WIDTH);
            format!("({x}, {y}): {:?} against {:?}", a[i], b[i])
        })
        .collect();
    (differ.len(), first)
}

/// Write frames of `bytes` with the example (`extra` arguments: the scene, the order), the
/// last at `start + step * (frames - 1)`, and check the PNG against the host renderer's frame
/// at that azimuth. Also checks that the comparison can fail: the frame shows the scene (a
/// good part of it not background, in several colours) and differs from the host's frame a
/// few degrees on.
fn check(bytes: &[u8], extra: &[&str], start: f64, step: f64, frames: u32) {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let png = dir.path().join("frame.png");
    let (start_s, step_s, frames_s) = (start.to_string(), step.to_string(), frames.to_string());
    let mut args = vec!["--png", png.to_str().expect("a UTF-8 path")];
    args.extend([
        "--azimuth",
        &start_s,
        "--step",
        &step_s,
        "--frames",
        &frames_s,
    ]);
    args.extend(extra);
    run(&args);
    let simulator = read_png(&png);
    let azimuth = start + step * f64::from(frames - 1);
    let host = host_frame(bytes, azimuth);
    let (n, first) = differences(&simulator, &host);
    assert_eq!(
        n, 0,
        "{args:?}: {n} pixels differ from the host renderer's at azimuth {azimuth}, \
         first: {first:#?}"
    );

    let background = shown(Colour::new(BACKGROUND[0], BACKGROUND[1], BACKGROUND[2]));
    let covered = simulator.iter().filter(|&&p| p != background).count();
    let mut colours = simulator.clone();
    colours.sort_unstable();
    colours.dedup();
    assert!(
        covered * 20 > simulator.len() && colours.len() >= 3,
        "{args:?}: a frame of {covered} covered pixels in {} colours shows too little to compare",
        colours.len()
    );
    let (n, _) = differences(&simulator, &host_frame(bytes, azimuth + 5.0));
    assert!(n > 0, "{args:?}: the frame 5 degrees on is the same frame");
}

#[test]
fn scan_order_frames_are_the_host_renderers() {
    check(BUILT_IN, &[], 30.0, 1.0, 1);
    check(BUILT_IN, &[], 200.0, 2.5, 4);
}

#[test]
fn streamed_frames_are_the_host_renderers() {
    check(BUILT_IN, &["--order", "stream"], 75.0, 10.0, 3);
}

/// The window's orbit, a degree a frame, a whole turn: every frame fits the memory the sizes
/// file gives (the build script measured it at 15 degree steps), in both orders.
#[test]
fn a_whole_turn_fits_the_memory_of_the_sizes_file() {
    check(BUILT_IN, &[], 0.0, 1.0, 360);
    check(BUILT_IN, &["--order", "stream"], 0.0, 1.0, 360);
}

#[test]
fn a_peel_file_from_the_command_line() {
    let obj =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/interpenetrating_boxes.obj");
    let compiled = compile_obj(&obj, &CompileOptions::default(), &|_| {}).expect("compile");
    let dir = tempfile::tempdir().expect("a temporary folder");
    let file = dir.path().join("boxes.peel");
    std::fs::write(&file, &compiled.bytes).expect("write the scene");
    let file = file.to_str().expect("a UTF-8 path");
    check(&compiled.bytes, &["--scene", file], 40.0, 1.0, 1);
    check(
        &compiled.bytes,
        &["--scene", file, "--order", "stream"],
        300.0,
        1.0,
        2,
    );
}

/// Bad input: an error naming what is wrong, a failing exit status and no PNG.
#[test]
fn bad_input_is_refused_without_output() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let png = dir.path().join("frame.png");
    let png_arg = png.to_str().expect("a UTF-8 path");
    let garbage = dir.path().join("garbage.peel");
    std::fs::write(&garbage, b"not a scene at all").expect("write");
    let missing: PathBuf = dir.path().join("missing.peel");
    let nowhere = dir.path().join("no/such/folder/frame.png");
    let cases: [(Vec<&str>, &str); 6] = [
        (
            vec!["--scene", missing.to_str().unwrap(), "--png", png_arg],
            "missing.peel: cannot read",
        ),
        (
            vec!["--scene", garbage.to_str().unwrap(), "--png", png_arg],
            "garbage.peel: not a valid .peel file",
        ),
        (
            vec!["--png", png_arg, "--azimuth", "NaN"],
            "'NaN' is not a finite number",
        ),
        (vec!["--png", png_arg, "--frames", "0"], "--frames"),
        (vec!["--frames", "2"], "--png"),
        (
            vec!["--png", nowhere.to_str().unwrap()],
            "frame.png: cannot write the PNG",
        ),
    ];
    for (args, expected) in cases {
        let out = example().args(&args).output().expect("run the example");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(!png.exists() && !nowhere.exists(), "{args:?} left a PNG");
    }
}

/// Without the `window` feature, no `--png` is an error that says how to get a window.
#[cfg(not(feature = "window"))]
#[test]
fn without_the_window_feature_the_error_names_it() {
    let out = example().output().expect("run the example");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("--features window") && stderr.contains("libsdl2-dev"),
        "{stderr}"
    );
}
