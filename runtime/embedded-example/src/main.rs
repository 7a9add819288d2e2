//! Render one frame of a scene compiled at build time into a static RGB565 framebuffer.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use panic_halt as _;
use peel_runtime::camera::{Camera, Pose};
use peel_runtime::read::Scene;
use peel_runtime::render::{render, Paint, Workspace};
use peel_runtime::target::{Colour, Rgb565Framebuffer};

/// The scene, compiled by build.rs.
static SCENE: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/scene.peel"));

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;
const PIXELS: usize = (WIDTH * HEIGHT) as usize;

#[entry]
fn main() -> ! {
    // cortex-m-rt turns this `static mut` into a safe `&'static mut` owned by `main`.
    static mut FRAME: [u16; PIXELS] = [0; PIXELS];
    let frame: &'static mut [u16; PIXELS] = FRAME;
    let mut workspace: Workspace<64, 24> = Workspace::new();
    let mut angle = 0.0f64;
    loop {
        if let Ok(scene) = Scene::parse(SCENE) {
            let (s, c) = (libm::sin(angle), libm::cos(angle));
            let pose = Pose::new([8.0 * s, 4.0, 8.0 * c].into(), [0.0, 0.8, 0.0].into());
            if let Ok(camera) = Camera::look_at(pose, 50.0, WIDTH, HEIGHT, 0.01) {
                if let Ok(mut fb) = Rgb565Framebuffer::new(&mut frame[..], WIDTH, HEIGHT) {
                    fb.clear(Colour::new(24, 26, 32));
                    let _ = render(&scene, &camera, &mut workspace, Paint::Colours, &mut fb);
                }
            }
        }
        // Hand the frame to the "display": keeps the optimiser from dropping the drawing.
        core::hint::black_box(&*frame);
        angle += 0.05;
    }
}
