//! Peel on a Raspberry Pi Pico (RP2040, Cortex-M0+ at 125 MHz, no FPU) with a 320x240 ST7789
//! panel: an orbit around the scene compiled by build.rs, drawn front to back frame after
//! frame and sent to the panel in scan order (no framebuffer: 150 KiB at this size).
//!
//! Wiring (as on Waveshare's Pico-LCD-2, an ST7789 of 240x320 turned to landscape): SPI1 with
//! SCK on GP10 and MOSI on GP11, chip select GP9, data/command GP8, reset GP12, backlight
//! GP13.
//!
//! The memory comes from the scene's sizes file: the traversal stack (`scene::STACK`), the
//! clip buffers (`scene::VERTS`) and the scan memory (`scene::SCAN_NODES`, measured by
//! build.rs over an orbit at 320x240), so another mesh (`PEEL_BOARD_MESH`) needs no edit here.
//! The camera is a [`LocalOrbit`]: `f32` alone, no `f64` and no libm.
#![no_std]
#![no_main]

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::pixelcolor::Rgb565;
use embedded_hal::digital::OutputPin;
use embedded_hal_bus::spi::ExclusiveDevice;
use mipidsi::interface::SpiInterface;
use mipidsi::models::ST7789;
use mipidsi::options::{ColorInversion, Orientation, Rotation};
use panic_halt as _;
use peel_runtime::camera::{Camera, LocalOrbit, LocalView, Orbit};
use peel_runtime::display::Colour;
use peel_runtime::read::{Header, Scene};
use peel_runtime::render::{Renderer, Workspace};
use peel_runtime::scan::{ScanMemory, ScanNode};
use peel_runtime::vertices::{CachedVertex, VertexCache};
use peel_runtime::RenderError;
use rp_pico::entry;
use rp_pico::hal::fugit::RateExtU32;
use rp_pico::hal::{self, gpio, pac, spi, Clock};

/// The scene, compiled by build.rs: an array of its own, so that its symbol's size in the ELF
/// is the scene's flash (`.ci/board-size` prints it).
static SCENE: [u8; scene::BYTES] = *include_bytes!(concat!(env!("OUT_DIR"), "/scene.peel"));

/// The scene's sizes, written beside it by build.rs.
mod scene {
    include!(concat!(env!("OUT_DIR"), "/scene.rs"));
}

/// The panel in landscape.
const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;
/// Vertex memory: every vertex of a small scene, 512 entries (4 KiB) of a larger one (the
/// vertices used close together in the walk, as in the target benchmark).
const VERTEX_MEMORY: usize = if scene::VERTEX_MEMORY < 512 {
    scene::VERTEX_MEMORY
} else {
    512
};
/// What no polygon covers.
const BACKGROUND: Colour = Colour::new(24, 26, 32);
/// Vertical field of view, degrees.
const FOV_Y_DEG: f32 = 60.0;
/// The orbit: its elevation (one of those build.rs measured the span memory at) and its
/// step per frame, degrees.
const ELEVATION_DEG: f32 = 20.0;
const STEP_DEG: f32 = 3.0;

/// What stopped the firmware, kept where a debugger finds it.
#[derive(Debug)]
#[allow(dead_code)] // Read by a debugger, not by the program.
enum Failure {
    Read(peel_runtime::ReadError),
    Render(RenderError),
    /// The hardware: the clocks did not start, a peripheral was taken twice, or the panel
    /// refused its set-up or a write (SPI or a pin).
    Hardware,
}

impl From<RenderError> for Failure {
    fn from(e: RenderError) -> Self {
        Failure::Render(e)
    }
}

/// Stop with `failure` (a real device might blink it, or reset).
fn fail(failure: Failure) -> ! {
    loop {
        core::hint::black_box(&failure);
    }
}

/// The view of the orbit's frame at `azimuth_deg`: in `f32` alone ([`LocalOrbit`], no `f64`
/// and no libm linked). With the feature `f64-orbit`, the same orbit through the `f64`
/// [`Orbit`] and [`Camera`] instead: only to measure the flash the `f32` one saves (README,
/// "On a board").
fn orbit_view(header: &Header, azimuth_deg: f32) -> Result<LocalView, RenderError> {
    if cfg!(feature = "f64-orbit") {
        let fov = f64::from(FOV_Y_DEG);
        let orbit = Orbit {
            azimuth_deg: f64::from(azimuth_deg),
            elevation_deg: f64::from(ELEVATION_DEG),
            distance: Orbit::fitting_distance(fov, WIDTH, HEIGHT),
        };
        let near = Camera::default_near(header.bounds_min, header.bounds_max);
        let camera = Camera::look_at(orbit.pose(header), fov, WIDTH, HEIGHT, near)?;
        Ok(camera.view(header.centre))
    } else {
        let focal = LocalOrbit::focal(FOV_Y_DEG, HEIGHT);
        let orbit = LocalOrbit {
            azimuth_deg,
            elevation_deg: ELEVATION_DEG,
            distance: LocalOrbit::fitting_distance(focal, WIDTH, HEIGHT),
        };
        orbit.view(
            header,
            focal,
            WIDTH,
            HEIGHT,
            LocalOrbit::default_near(header),
        )
    }
}

/// Draw the frame `view` sees and send it to `panel` in scan order: the walk keeps every
/// covered interval with its colour in scan memory, then the frame goes out row by row, top to
/// bottom, in one address window (one `fill_contiguous`: mipidsi sets the window once and
/// streams the pixels), so the panel never shows two frames mixed beyond the row being
/// written. The one place that decides how a frame reaches the panel.
fn draw_frame<D>(
    renderer: &mut Renderer<'_>,
    scene: &Scene<'_>,
    view: &LocalView,
    panel: &mut D,
) -> Result<(), Failure>
where
    D: DrawTarget<Color = Rgb565>,
{
    let frame = renderer.draw_scan(scene, view)?;
    frame.draw_to(panel).map_err(|_| Failure::Hardware)
}

#[entry]
fn main() -> ! {
    // cortex-m-rt turns these `static mut` into `&'static mut` owned by `main`: zeros, in
    // `.bss`, no code to set them up.
    static mut WORKSPACE: Workspace<{ scene::STACK }, { scene::VERTS }> = Workspace::new();
    static mut NODES: [ScanNode; scene::SCAN_NODES] = [ScanNode::EMPTY; scene::SCAN_NODES];
    static mut HEADS: [u16; HEIGHT as usize] = [0; HEIGHT as usize];
    static mut VERTICES: [CachedVertex; VERTEX_MEMORY] = [CachedVertex::EMPTY; VERTEX_MEMORY];
    // mipidsi's transfer buffer: pixels of one fill go out in bursts of this many bytes.
    static mut SPI_BUFFER: [u8; 512] = [0; 512];

    let Some(mut pac) = pac::Peripherals::take() else {
        fail(Failure::Hardware)
    };
    let mut watchdog = hal::Watchdog::new(pac.WATCHDOG);
    let Ok(clocks) = hal::clocks::init_clocks_and_plls(
        rp_pico::XOSC_CRYSTAL_FREQ,
        pac.XOSC,
        pac.CLOCKS,
        pac.PLL_SYS,
        pac.PLL_USB,
        &mut pac.RESETS,
        &mut watchdog,
    ) else {
        fail(Failure::Hardware)
    };
    let sio = hal::Sio::new(pac.SIO);
    let pins = rp_pico::Pins::new(
        pac.IO_BANK0,
        pac.PADS_BANK0,
        sio.gpio_bank0,
        &mut pac.RESETS,
    );
    let mut delay = hal::Timer::new(pac.TIMER, &mut pac.RESETS, &clocks);

    // The panel: SPI1 at 62.5 MHz (the peripheral clock halved, the RP2040's fastest).
    let sck: gpio::Pin<_, gpio::FunctionSpi, gpio::PullNone> = pins.gpio10.reconfigure();
    let mosi: gpio::Pin<_, gpio::FunctionSpi, gpio::PullNone> = pins.gpio11.reconfigure();
    let bus = spi::Spi::<_, _, _, 8>::new(pac.SPI1, (mosi, sck)).init(
        &mut pac.RESETS,
        clocks.peripheral_clock.freq(),
        62_500_000u32.Hz(),
        embedded_hal::spi::MODE_0,
    );
    let cs = pins.gpio9.into_push_pull_output();
    let dc = pins.gpio8.into_push_pull_output();
    let reset = pins.gpio12.into_push_pull_output();
    let mut backlight = pins.gpio13.into_push_pull_output();
    let Ok(device) = ExclusiveDevice::new_no_delay(bus, cs);
    let interface = SpiInterface::new(device, dc, SPI_BUFFER);
    let mut panel = mipidsi::Builder::new(ST7789, interface)
        .display_size(240, 320)
        .orientation(Orientation::new().rotate(Rotation::Deg90))
        .invert_colors(ColorInversion::Inverted)
        .reset_pin(reset)
        .init(&mut delay)
        .unwrap_or_else(|_| fail(Failure::Hardware));
    let Ok(()) = backlight.set_high();

    // The scene, validated once at boot; the renderer over the static memory, made once.
    let scene = Scene::parse(&SCENE).unwrap_or_else(|e| fail(Failure::Read(e)));
    let memory =
        ScanMemory::new(NODES, HEADS, WIDTH, HEIGHT).unwrap_or_else(|e| fail(Failure::Render(e)));
    // Without an FPU, vertices are projected in integers and a subtree's box test costs more
    // than the subtrees it skips (BENCHMARKS.md, "On the target").
    let mut renderer = Renderer::new(WORKSPACE)
        .scan_memory(memory)
        .vertex_memory(VertexCache::new(VERTICES))
        .background(BACKGROUND)
        .integer_vertices()
        .without_subtree_culling();

    let header = scene.header();
    let mut azimuth_deg = 0.0;
    loop {
        let view = orbit_view(&header, azimuth_deg).unwrap_or_else(|e| fail(Failure::Render(e)));
        // A frame needing more scan memory than build.rs measured for this orbit is an error
        // (`RenderError::ScanMemoryFull`), sent nowhere: never a frame with overdraw.
        draw_frame(&mut renderer, &scene, &view, &mut panel).unwrap_or_else(|e| fail(e));
        azimuth_deg += STEP_DEG;
        if azimuth_deg >= 360.0 {
            azimuth_deg -= 360.0;
        }
    }
}
