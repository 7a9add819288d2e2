//! Render frames of a scene compiled at build time into a static RGB565 framebuffer, front to
//! back with span memory. With the `full` feature (default) the paint (colours or ids) and the
//! order are chosen at run time, so every path of the runtime is linked; with `smallest` only
//! front to back with colours is, with the camera computed in `f32` ([`View::look_at`]): a
//! Cortex-M4F has no `f64` hardware.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use glam::{DVec3, Vec3};
use panic_halt as _;
use peel_runtime::camera::{Camera, Pose, View};
use peel_runtime::coverage::Coverage;
use peel_runtime::read::Scene;
use peel_runtime::render::{render_view, FrameMemory, Paint, RenderOptions, Workspace};
use peel_runtime::target::{Colour, Rgb565Framebuffer};
use peel_runtime::traverse::Order;

/// The scene, compiled by build.rs.
static SCENE: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/scene.peel"));

/// The scene's sizes, written beside it by build.rs.
mod scene {
    include!(concat!(env!("OUT_DIR"), "/scene.rs"));
}

/// The workspace: a traversal stack of `STACK` entries and clip buffers of `VERTS` vertices,
/// checked against the scene when this program compiles.
const STACK: usize = 64;
const VERTS: usize = 24;
const _: () = scene::check_workspace(STACK, VERTS);

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

/// Vertical field of view of the `full` configuration's `f64` camera, in degrees.
const FOV_Y_DEG: f64 = 50.0;
/// The same field of view as a focal length in pixels, `(HEIGHT / 2) / tan(FOV_Y_DEG / 2)`,
/// for the `f32` view: no `tan` on the device.
const FOCAL: f32 = 128.670_42;
/// Near distance.
const NEAR: f32 = 0.01;
/// The orbit: radius, eye height and target height, relative to the scene centre (the demo's
/// centre is `0,1,0`, so the eye circles at height 4 around the point `0,0.8,0`).
const RADIUS: f32 = 8.0;
const EYE_Y: f32 = 3.0;
const TARGET_Y: f32 = -0.2;
/// `sin` and `cos` of the orbit's step of 0.05 rad per frame.
const STEP_SIN: f32 = 0.049_979_17;
const STEP_COS: f32 = 0.998_750_26;

/// The camera of a frame, looking from `eye` at `target` (scene coordinates, relative to the
/// centre). With `full` the `f64` [`Camera`] (world coordinates) is linked too; otherwise the
/// view is built in `f32`, and the binary holds no `f64` arithmetic.
fn view(scene: &Scene<'_>, eye: Vec3, target: Vec3) -> Option<View> {
    if cfg!(feature = "full") {
        let centre = scene.header().centre;
        let c = DVec3::from_array(centre);
        let pose = Pose::new(eye.as_dvec3() + c, target.as_dvec3() + c);
        let camera = Camera::look_at(pose, FOV_Y_DEG, WIDTH, HEIGHT, f64::from(NEAR)).ok()?;
        Some(camera.view(centre))
    } else {
        View::look_at(eye, target, Vec3::Y, FOCAL, WIDTH, HEIGHT, NEAR).ok()
    }
}

/// The embedded scene. build.rs ran the full validation ([`Scene::parse`]) on these very
/// bytes, so the smallest configuration only checks the header and layout
/// ([`Scene::parse_trusted`]); `full` validates again at run time.
fn parse() -> Result<Scene<'static>, peel_runtime::ReadError> {
    if cfg!(feature = "full") {
        Scene::parse(SCENE)
    } else {
        Scene::parse_trusted(SCENE)
    }
}

#[entry]
fn main() -> ! {
    // cortex-m-rt turns these `static mut` into safe `&'static mut` owned by `main`.
    static mut FRAME: [u16; PIXELS] = [0; PIXELS];
    static mut INTERVALS: [(u16, u16); SLOTS * HEIGHT as usize] = [(0, 0); SLOTS * HEIGHT as usize];
    static mut COUNTS: [u16; HEIGHT as usize] = [0; HEIGHT as usize];
    // Traversal stack and clip/fill buffers: zero bytes, in `.bss`, no code to set them up.
    static mut WORKSPACE: Workspace<STACK, VERTS> = Workspace::new();
    let frame: &'static mut [u16; PIXELS] = FRAME;
    let intervals: &'static mut [(u16, u16); SLOTS * HEIGHT as usize] = INTERVALS;
    let counts: &'static mut [u16; HEIGHT as usize] = COUNTS;
    let workspace: &'static mut Workspace<STACK, VERTS> = WORKSPACE;
    // The orbit angle as its sine and cosine, turned by a fixed rotation each frame (no
    // trigonometry on the device) and pulled back to the unit circle so rounding cannot drift.
    let (mut s, mut c) = (0.0f32, 1.0f32);
    let mut n = 0u32;
    loop {
        if let Ok(scene) = parse() {
            let eye = Vec3::new(RADIUS * s, EYE_Y, RADIUS * c);
            let target = Vec3::new(0.0, TARGET_Y, 0.0);
            if let (Some(view), Ok(mut coverage)) = (
                view(&scene, eye, target),
                Coverage::new(&mut intervals[..], &mut counts[..], WIDTH, HEIGHT),
            ) {
                if let Ok(mut fb) = Rgb565Framebuffer::new(&mut frame[..], WIDTH, HEIGHT) {
                    fb.clear(Colour::new(24, 26, 32));
                    let _ = render_view(
                        &scene,
                        &view,
                        workspace,
                        options(n),
                        FrameMemory::from(&mut coverage),
                        &mut fb,
                    );
                }
            }
        }
        // Hand the frame to the "display": keeps the optimiser from dropping the drawing.
        core::hint::black_box(&*frame);
        (s, c) = (s * STEP_COS + c * STEP_SIN, c * STEP_COS - s * STEP_SIN);
        let k = 1.5 - 0.5 * (s * s + c * c);
        (s, c) = (s * k, c * k);
        n = n.wrapping_add(1);
    }
}
