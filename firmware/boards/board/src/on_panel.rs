//! The boards' frames as their panels show them: each board's panel set up with its own
//! settings ([`crate::panel`]) and sent a frame by the boards' own code ([`Memory`],
//! [`draw_frame`]) through mipidsi over a recorded SPI bus, the bytes decoded as the panel
//! would store and show them ([`crate::dcs`]), and the picture compared pixel for pixel with
//! the host's frame of the same scene and camera (the runtime's framebuffer path), plain and
//! anti-aliased.

use std::sync::OnceLock;

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::pixelcolor::Rgb565;
use mipidsi::interface::SpiInterface;
use mipidsi::models::Model;
use mipidsi::{Builder, NoResetPin};
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{self, Framebuffer};
use peel_runtime::pending::{Pending, PendingPixel};
use peel_runtime::read::Scene;
use peel_runtime::render::{Renderer, Workspace};
use peel_runtime::stats::FrameStats;

use crate::dcs::{self, Glass, ILI9341_BGR, ST7789_IPS};
use crate::recorder::{DcPin, NoDelay, Recorder, RecordingSpi, Write};
use crate::{draw_frame, orbit_view, panel, Core, Memory, BACKGROUND, HEIGHT, WIDTH};

/// The test's frame memory, ample for the demo scene (a frame that runs short fails its
/// draw, or, anti-aliased, comes out plain, which the tests check).
const STACK: usize = 128;
const VERTS: usize = 32;
const NODES: usize = 16_384;
const VERTICES: usize = 512;
const RECORDS: usize = 8_192;

/// A frame of the boards' orbit, 11 steps in.
const AZIMUTH_DEG: f32 = 33.0;

/// The repository's demo scene, compiled once as the boards' build scripts compile it.
fn demo() -> &'static [u8] {
    static BYTES: OnceLock<Vec<u8>> = OnceLock::new();
    BYTES.get_or_init(|| {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let obj = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../fixtures/demo.obj");
        let out = peel_compiler::Builder::new(obj)
            .out_dir(dir.path())
            .cache(false)
            .compile()
            .expect("the demo compiles");
        std::fs::read(out.peel).expect("the compiled demo")
    })
}

/// Panels built with a board's settings, over a recorded bus.
type PanelBuilder<'b, M> = Builder<SpiInterface<'b, RecordingSpi, DcPin>, M, NoResetPin>;

/// A board's panel: its settings, the module's glass and the board's core.
struct Board {
    name: &'static str,
    glass: Glass,
    core: Core,
}

const PICO: Board = Board {
    name: "pico-st7789",
    glass: ST7789_IPS,
    core: Core::WithoutFpu,
};

const BLACKPILL: Board = Board {
    name: "blackpill-ili9341",
    glass: ILI9341_BGR,
    core: Core::WithFpu,
};

/// What `board`'s panel receives from its set-up and one frame (anti-aliased if
/// `antialiased`), made by `settings` from [`crate::panel`], and what the walk reported.
fn recorded<M>(
    board: &Board,
    antialiased: bool,
    settings: impl FnOnce(RecordingSpi, DcPin, &mut [u8]) -> PanelBuilder<'_, M>,
) -> (Vec<Write>, FrameStats)
where
    M: Model<ColorFormat = Rgb565>,
{
    let recorder = Recorder::default();
    let mut buffer = [0; 512];
    let mut display = settings(recorder.spi(), recorder.dc(), &mut buffer)
        .init(&mut NoDelay)
        .expect("the panel's set-up");
    let stats = board_frame(board.core, antialiased, &mut display);
    (recorder.take(), stats)
}

/// The board's frame at [`AZIMUTH_DEG`], sent to `panel` by the boards' code.
fn board_frame<D: DrawTarget<Color = Rgb565>>(
    core: Core,
    antialiased: bool,
    panel: &mut D,
) -> FrameStats {
    if antialiased {
        let mut memory = Box::new(Memory::<STACK, VERTS, NODES, VERTICES, RECORDS>::new());
        frame_in(&mut memory, core, panel)
    } else {
        let mut memory = Box::new(Memory::<STACK, VERTS, NODES, VERTICES, 0>::new());
        frame_in(&mut memory, core, panel)
    }
}

/// [`board_frame`] in `memory` (anti-aliased when it holds pending-pixel records).
fn frame_in<D: DrawTarget<Color = Rgb565>, const R: usize>(
    memory: &mut Memory<STACK, VERTS, NODES, VERTICES, R>,
    core: Core,
    panel: &mut D,
) -> FrameStats {
    let scene = Scene::parse(demo()).expect("the demo parses");
    let mut renderer = memory.renderer(core).expect("a renderer");
    let view = orbit_view(&scene.header(), AZIMUTH_DEG).expect("a view");
    match draw_frame(&mut renderer, &scene, &view, panel) {
        Ok(stats) => stats,
        Err(e) => panic!("the board's frame: {e:?}"),
    }
}

/// The host's frame of the same scene and camera: `Renderer::draw` into an RGB565
/// framebuffer, front to back with span memory that never runs out, the same switches.
fn host_frame(core: Core, antialiased: bool) -> (Vec<u16>, FrameStats) {
    let scene = Scene::parse(demo()).expect("the demo parses");
    let (w, h) = (WIDTH as usize, HEIGHT as usize);
    let mut workspace = Box::new(Workspace::<STACK, VERTS>::new());
    let (mut spans, mut counts) = (vec![(0, 0); w.div_ceil(2) * h], vec![0; h]);
    let (mut records, mut heads) = (vec![PendingPixel::default(); RECORDS], vec![0; h]);
    let coverage = Coverage::new(&mut spans, &mut counts, WIDTH, HEIGHT).expect("span memory");
    let mut renderer = Renderer::new(&mut workspace)
        .span_memory(coverage)
        .background(BACKGROUND);
    if antialiased {
        let pending = Pending::new(&mut records, &mut heads, HEIGHT).expect("pending memory");
        renderer = renderer.antialias(pending);
    }
    let mut renderer = core.configure(renderer);
    let view = orbit_view(&scene.header(), AZIMUTH_DEG).expect("a view");
    let mut pixels = vec![0; w * h];
    let mut fb = Framebuffer::<display::Rgb565>::new(&mut pixels, WIDTH, HEIGHT).expect("a frame");
    let stats = renderer
        .draw(&scene, &view, &mut fb)
        .expect("the host's frame");
    (pixels, stats)
}

/// Whether `writes` show `expected` on `glass`: the decoder's error, or how many pixels
/// differ and the first of them.
fn check(glass: Glass, writes: &[Write], expected: &[u16]) -> Result<(), String> {
    let picture = dcs::decode(glass, writes)?;
    let differ: Vec<usize> = (0..expected.len())
        .filter(|&i| picture[i] != expected[i])
        .collect();
    match differ.first() {
        None => Ok(()),
        Some(&i) => Err(format!(
            "{} pixels differ, the first at ({}, {}): {:#06x} shown, {:#06x} on the host",
            differ.len(),
            i % WIDTH as usize,
            i / WIDTH as usize,
            picture[i],
            expected[i]
        )),
    }
}

/// `board`'s frames, plain and anti-aliased, as its panel shows them, against the host's.
fn shows_the_hosts_frames<M>(
    board: &Board,
    settings: impl Fn(RecordingSpi, DcPin, &mut [u8]) -> PanelBuilder<'_, M>,
) where
    M: Model<ColorFormat = Rgb565>,
{
    // Anti-aliased frames with the feature `antialias` (the crate's default).
    for antialiased in [false, cfg!(feature = "antialias")] {
        let (writes, stats) = recorded(board, antialiased, &settings);
        let (expected, host) = host_frame(board.core, antialiased);
        assert_eq!(stats.antialiased, antialiased, "{}", board.name);
        assert_eq!(host.antialiased, antialiased, "{}", board.name);
        if let Err(e) = check(board.glass, &writes, &expected) {
            panic!("{} (antialiased: {antialiased}): {e}", board.name);
        }
    }
}

#[test]
fn the_picos_st7789_shows_the_hosts_frames() {
    shows_the_hosts_frames(&PICO, panel::st7789);
}

#[test]
fn the_black_pills_ili9341_shows_the_hosts_frames() {
    shows_the_hosts_frames(&BLACKPILL, panel::ili9341);
}

#[test]
fn the_frames_are_not_one_colour() {
    // A check of a blank frame would prove little: the demo covers part of the picture.
    let (pixels, _) = host_frame(Core::WithFpu, true);
    let background = BACKGROUND.to_rgb565();
    let covered = pixels.iter().filter(|&&p| p != background).count();
    assert!(covered > pixels.len() / 20, "{covered} pixels covered");
    assert!(covered < pixels.len(), "{covered} pixels covered");
}

/// The index of the first write after the last command `code`.
fn after_last(writes: &[Write], code: u8) -> usize {
    let i = writes
        .iter()
        .rposition(|w| !w.data && w.bytes == [code])
        .expect("the command was sent");
    i + 1
}

#[test]
fn a_changed_byte_fails_the_check() {
    let (writes, _) = recorded(&BLACKPILL, false, panel::ili9341);
    let (expected, _) = host_frame(BLACKPILL.core, false);
    check(BLACKPILL.glass, &writes, &expected).expect("the frame as recorded");

    // One byte of one pixel in the middle of the frame.
    let mut changed = writes.clone();
    let first = after_last(&changed, 0x2C);
    let burst = first + (changed.len() - first) / 2;
    changed[burst].bytes[101] ^= 0x10;
    let e = check(BLACKPILL.glass, &changed, &expected).unwrap_err();
    assert!(e.starts_with("1 pixels differ"), "{e}");

    // The frame's window one column narrower: its pixels overrun it.
    let mut changed = writes;
    let caset = after_last(&changed, 0x2A);
    assert_eq!(changed[caset].bytes, [0, 0, 0x01, 0x3F]);
    changed[caset].bytes[3] = 0x3E;
    let e = check(BLACKPILL.glass, &changed, &expected).unwrap_err();
    assert!(e.contains("past the end of its window"), "{e}");
}
