//! The on-target benchmark's firmware. QEMU loads the scene (or the z-buffer's mesh) and a
//! config block into code memory ([`peel_target_kit::layout`]); for each camera of the block
//! the firmware computes the view, paints the stack, times one frame with SysTick (drawing it
//! and sending it to the mock display, nothing else), measures the stack's high-water mark and
//! reports over semihosting:
//!
//! ```text
//! peel-target variant=<variant> target=<target triple>
//! frame <k> ticks=<SysTick ticks> display_bytes=<bytes> display_writes=<writes> fallback=<0|1>
//! aa <k> antialiased=<0|1> pending_peak=<records> pending_records=<records>  (stream-aa, scan-aa)
//! composite <k> fallback_rows=<rows> composite_peak=<runs> composite_runs=<runs>  (transparency)
//! memory pool_used=<bytes> pool_capacity=<bytes> framebuffer=<bytes> stack_peak=<bytes>
//! gfx3d commands_peak=<commands> capacity=<commands>   (embedded-3dgfx only)
//! done
//! ```
//!
//! and, when the block asks, writes what the panel received to the host file
//! `frame-<k>.rgb565` (after the timed region). Any failure prints `error: ...` and exits with
//! a non-zero code; a panic or a fault does too.
#![no_std]
#![no_main]

mod clock;
mod display;
mod host;
mod method;
mod pool;
mod stack;

use core::fmt;

use cortex_m_rt::{entry, exception, ExceptionFrame};
use cortex_m_semihosting::{debug, hprintln};
use peel_target_kit::config::{Config, ConfigError, Variant, WRITE_FRAMES};

use display::Panel;
use pool::Pool;

/// `VARIANT`, this build's variant, from its one variant feature (two give two `VARIANT`s,
/// none a compile error): each feature named once, as `Variant::name` names it.
macro_rules! variant {
    ($($feature:literal => $variant:ident),*) => {
        $(
            #[cfg(feature = $feature)]
            const VARIANT: Variant = Variant::$variant;
        )*
        #[cfg(not(any($(feature = $feature),*)))]
        compile_error!("build with exactly one variant feature, e.g. --features ftb-framebuffer");
    };
}

// Objects are drawn by the streamed build alone (its panel sink).
#[cfg(all(feature = "objects", not(feature = "ftb-stream")))]
compile_error!("the objects feature goes with ftb-stream only");

// Textures are drawn by the streamed build (its panel sink) and by embedded-3dgfx alone.
#[cfg(all(
    feature = "textures",
    not(any(feature = "ftb-stream", feature = "embedded-3dgfx"))
))]
compile_error!("the textures feature goes with ftb-stream or embedded-3dgfx only");

// Transparent surfaces are drawn by the streamed build alone (its composite memory).
#[cfg(all(feature = "transparency", not(feature = "ftb-stream")))]
compile_error!("the transparency feature goes with ftb-stream only");

variant!(
    "ftb-framebuffer" => FtbFramebuffer,
    "ftb-stream" => FtbStream,
    "stream-aa" => StreamAa,
    "ftb-bands" => FtbBands,
    "scan-order" => ScanOrder,
    "scan-aa" => ScanAa,
    "b2f-framebuffer" => B2fFramebuffer,
    "b2f-bands" => B2fBands,
    "zbuffer" => Zbuffer,
    "scanline-zbuffer" => ScanlineZbuffer,
    "tiled-zbuffer" => TiledZbuffer,
    "embedded-3dgfx" => Gfx3d
);

/// The largest image the panel memory holds.
const MAX_PIXELS: usize = 320 * 240;
/// Words of memory handed out by size at boot: a framebuffer and a depth buffer at the largest
/// size, a framebuffer and span memory (up to 64 intervals per row), or the scanline
/// z-buffer's lists of the largest scene (the teapot's take about 330 kB). Only what a run
/// takes counts as its RAM.
const POOL_WORDS: usize = 192 * 1024;

/// Why a run stopped.
#[derive(Debug)]
pub enum Failure {
    /// The config block.
    Config(ConfigError),
    /// A block written for another build.
    WrongVariant(Variant),
    /// The scene.
    Read(peel_runtime::ReadError),
    /// A file of parts without a world.
    #[cfg(feature = "objects")]
    NoWorld,
    /// A file of parts with another number of objects than the scene's.
    #[cfg(feature = "objects")]
    Objects(usize),
    /// The z-buffer's mesh.
    Mesh(peel_target_kit::mesh::MeshError),
    /// The renderer.
    Render(peel_runtime::RenderError),
    /// A framebuffer.
    Framebuffer(peel_runtime::display::FramebufferError),
    /// The z-buffer.
    ZBuffer(peel_target_kit::zbuffer::ZError),
    /// A pool too small for what the block asks.
    OutOfMemory {
        /// What was asked for.
        what: pool::Use,
        /// Elements asked for.
        needed: usize,
        /// Elements left.
        free: usize,
    },
    /// The stack grew into the statics: its paint is gone down to its bottom.
    StackOverflow,
    /// A semihosting call failed.
    Host(&'static str),
    /// embedded-3dgfx: its scene, or the library itself.
    #[cfg(feature = "embedded-3dgfx")]
    Gfx3d(method::Gfx3dFailure),
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Config(e) => write!(f, "config block: {e}"),
            Failure::WrongVariant(v) => write!(
                f,
                "config block for {}, this build is {}",
                v.name(),
                VARIANT.name()
            ),
            Failure::Read(e) => write!(f, "scene: {e}"),
            #[cfg(feature = "objects")]
            Failure::NoWorld => write!(f, "scene: a file of parts without a world"),
            #[cfg(feature = "objects")]
            Failure::Objects(n) => write!(
                f,
                "scene: {n} objects, the scene with objects has {}",
                peel_target_kit::objects::OBJECTS
            ),
            Failure::Mesh(e) => write!(f, "mesh: {e}"),
            Failure::Render(e) => write!(f, "render: {e}"),
            Failure::Framebuffer(e) => write!(f, "framebuffer: {e}"),
            Failure::ZBuffer(e) => write!(f, "z-buffer: {e}"),
            Failure::OutOfMemory { what, needed, free } => {
                write!(
                    f,
                    "{what}: {needed} elements asked, {free} left in the pool"
                )
            }
            Failure::StackOverflow => write!(f, "stack overflow: the stack reached the statics"),
            Failure::Host(what) => write!(f, "semihosting: {what}"),
            #[cfg(feature = "embedded-3dgfx")]
            Failure::Gfx3d(e) => write!(f, "embedded-3dgfx: {e}"),
        }
    }
}

macro_rules! from {
    ($($variant:ident($error:ty)),*) => {
        $(impl From<$error> for Failure {
            fn from(e: $error) -> Self {
                Failure::$variant(e)
            }
        })*
    };
}

from!(
    Config(ConfigError),
    Read(peel_runtime::ReadError),
    Mesh(peel_target_kit::mesh::MeshError),
    Render(peel_runtime::RenderError),
    Framebuffer(peel_runtime::display::FramebufferError),
    ZBuffer(peel_target_kit::zbuffer::ZError)
);

/// The mock display's panel memory (its GRAM, see [`display`]): in its own memory region
/// (memory.x, not loaded or zeroed), outside the statics counted as the firmware's RAM.
#[link_section = ".panel"]
static mut PANEL: [u16; MAX_PIXELS] = [0; MAX_PIXELS];

#[entry]
fn main() -> ! {
    // cortex-m-rt turns these into `&'static mut` owned by `main`.
    static mut POOL: [u32; POOL_WORDS] = [0; POOL_WORDS];
    let pool = Pool::new(&mut POOL[..]);
    // SAFETY: `main` runs once and is the only user of the panel memory.
    let panel = unsafe { &mut *core::ptr::addr_of_mut!(PANEL) };
    let code = match run(&mut panel[..], pool) {
        Ok(()) => debug::EXIT_SUCCESS,
        Err(e) => {
            hprintln!("error: {}", e);
            debug::EXIT_FAILURE
        }
    };
    debug::exit(code);
    loop {
        cortex_m::asm::wfi();
    }
}

fn run(panel: &'static mut [u16], mut pool: Pool) -> Result<(), Failure> {
    let config = Config::decode(host::config_block())?;
    if config.variant != VARIANT {
        return Err(Failure::WrongVariant(config.variant));
    }
    let (width, height) = (config.width, config.height);
    let pixel_count = width as usize * height as usize;
    let free = panel.len();
    let panel = panel.get_mut(..pixel_count).ok_or(Failure::OutOfMemory {
        what: pool::Use::PanelMemory,
        needed: pixel_count,
        free,
    })?;
    let mut display = Panel::new(panel, width, height);
    let mut method = method::Method::new(host::asset(config.asset_len), &config, &mut pool)?;
    let header = method.header();
    let peripherals = cortex_m::Peripherals::take().ok_or(Failure::Host("no peripherals"))?;
    let clock = clock::Clock::start(peripherals.SYST);
    hprintln!(
        "peel-target variant={} target={}",
        VARIANT.name(),
        env!("FIRMWARE_TARGET")
    );
    let mut stack_peak = 0;
    for (k, &angles) in config.cameras().iter().enumerate() {
        // A scene with objects poses them for each camera, and its posed header frames them.
        #[cfg(feature = "objects")]
        let header = method.pose(k).unwrap_or(header);
        // The camera (f64 maths) is set up before the timed region.
        let view = peel_target_kit::orbit_view(&header, angles, config.fov_y_deg, width, height)?;
        display.start_frame();
        stack::paint();
        let start = clock.ticks();
        let fallback = frame(&mut method, &view, &mut display)?;
        let ticks = clock.ticks() - start;
        stack_peak = stack_peak.max(stack::high_water()?);
        hprintln!(
            "frame {} ticks={} display_bytes={} display_writes={} fallback={}",
            k,
            ticks,
            display.bytes(),
            display.writes(),
            u8::from(fallback)
        );
        // Anti-aliased: whether the frame was, and its pending pixels against the records.
        #[cfg(feature = "aa")]
        {
            let (antialiased, peak, records) = method.antialiasing();
            hprintln!(
                "aa {} antialiased={} pending_peak={} pending_records={}",
                k,
                u8::from(antialiased),
                peak,
                records
            );
        }
        // Transparency: the rows that fell back to screen-door transparency, and the most
        // composite runs the frame held at once against the runs there are.
        #[cfg(feature = "transparency")]
        {
            let (fallback_rows, peak, runs) = method.transparency();
            hprintln!(
                "composite {} fallback_rows={} composite_peak={} composite_runs={}",
                k,
                fallback_rows,
                peak,
                runs
            );
        }
        if config.flags & WRITE_FRAMES != 0 {
            host::write_frame(k, display.pixels())?;
        }
    }
    let (used, capacity) = (pool.used_bytes(), pool.capacity_bytes());
    hprintln!(
        "memory pool_used={} pool_capacity={} framebuffer={} stack_peak={}",
        used,
        capacity,
        method.framebuffer_bytes(),
        stack_peak
    );
    // The runner sizes embedded-3dgfx's command buffer from this line.
    #[cfg(feature = "embedded-3dgfx")]
    {
        let (peak, capacity) = method.commands();
        hprintln!("gfx3d commands_peak={} capacity={}", peak, capacity);
    }
    hprintln!("done");
    Ok(())
}

/// One frame of `method`, drawn and sent to `panel`: the timed region, in a function of its
/// own so that its code does not change with the untimed code of `main` around it (inlined
/// there, edits to the camera loop and the reports moved the counts of the loops inside it:
/// BENCHMARKS.md, "The display charged fairly").
#[inline(never)]
fn frame(
    method: &mut method::Method,
    view: &peel_runtime::camera::LocalView,
    panel: &mut Panel,
) -> Result<bool, Failure> {
    method.frame(view, panel)
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    hprintln!("error: panic: {}", info);
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}

#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    hprintln!("error: hard fault at pc {:#010x}", frame.pc());
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}
