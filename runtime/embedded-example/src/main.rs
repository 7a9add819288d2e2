//! Render frames of a scene compiled at build time into a static RGB565 framebuffer, front to
//! back with span memory. With the `full` feature (default) the paint (colours or ids) and the
//! order are chosen at run time, so every path of the runtime is linked; with `smallest` only
//! front to back with colours is.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use panic_halt as _;
use peel_runtime::camera::{Camera, Pose};
use peel_runtime::coverage::Coverage;
use peel_runtime::read::Scene;
use peel_runtime::render::{render_ordered, Paint, RenderOptions, Workspace};
use peel_runtime::target::{Colour, Rgb565Framebuffer};
use peel_runtime::traverse::Order;

/// The scene, compiled by build.rs.
static SCENE: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/scene.peel"));

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;
const PIXELS: usize = (WIDTH * HEIGHT) as usize;
/// Span memory: covered intervals per row.
const SLOTS: usize = 16;

/// How this frame is drawn.
fn options(frame: u32) -> RenderOptions {
    let mut options = RenderOptions::default();
    if cfg!(feature = "full") {
        // Opaque to the optimiser: both orders and both paints stay reachable.
        let k = core::hint::black_box(frame);
        if k % 3 == 1 {
            options.order = Order::BackToFront;
        }
        if k % 5 == 4 {
            options.paint = Paint::Ids;
        }
    }
    options
}

#[entry]
fn main() -> ! {
    // cortex-m-rt turns these `static mut` into safe `&'static mut` owned by `main`.
    static mut FRAME: [u16; PIXELS] = [0; PIXELS];
    static mut INTERVALS: [(u16, u16); SLOTS * HEIGHT as usize] = [(0, 0); SLOTS * HEIGHT as usize];
    static mut COUNTS: [u16; HEIGHT as usize] = [0; HEIGHT as usize];
    let frame: &'static mut [u16; PIXELS] = FRAME;
    let intervals: &'static mut [(u16, u16); SLOTS * HEIGHT as usize] = INTERVALS;
    let counts: &'static mut [u16; HEIGHT as usize] = COUNTS;
    let mut workspace: Workspace<64, 24> = Workspace::new();
    let mut angle = 0.0f64;
    let mut n = 0u32;
    loop {
        if let Ok(scene) = Scene::parse(SCENE) {
            let (s, c) = (libm::sin(angle), libm::cos(angle));
            let pose = Pose::new([8.0 * s, 4.0, 8.0 * c].into(), [0.0, 0.8, 0.0].into());
            if let (Ok(camera), Ok(mut coverage)) = (
                Camera::look_at(pose, 50.0, WIDTH, HEIGHT, 0.01),
                Coverage::new(&mut intervals[..], &mut counts[..], WIDTH, HEIGHT),
            ) {
                if let Ok(mut fb) = Rgb565Framebuffer::new(&mut frame[..], WIDTH, HEIGHT) {
                    fb.clear(Colour::new(24, 26, 32));
                    let _ = render_ordered(
                        &scene,
                        &camera,
                        &mut workspace,
                        options(n),
                        Some(&mut coverage),
                        &mut fb,
                    );
                }
            }
        }
        // Hand the frame to the "display": keeps the optimiser from dropping the drawing.
        core::hint::black_box(&*frame);
        angle += 0.05;
        n = n.wrapping_add(1);
    }
}
