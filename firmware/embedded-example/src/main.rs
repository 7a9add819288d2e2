//! Render frames of a scene compiled at build time into a static RGB565 framebuffer, front to
//! back with span memory: the scene is read once, each frame's renderer borrows the same
//! static memory (making one costs a few stores), and every error stops the program with the
//! error at hand (where firmware would show it). With the `full` feature (default) the paint (colours or ids) and the order are
//! chosen at run time, so every path of the runtime is linked; with `smallest` only front to
//! back with colours is, with the camera computed in `f32`: a Cortex-M4F has no `f64`
//! hardware.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use glam::{DVec3, Vec3};
use panic_halt as _;
use peel_runtime::camera::{Camera, LocalView, Pose};
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Colour, Rgb565Framebuffer};
use peel_runtime::read::Scene;
use peel_runtime::render::{Renderer, Workspace};

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

/// What went wrong, kept where a debugger (or a display) finds it.
#[derive(Debug)]
#[allow(dead_code)] // Read by a debugger, not by the program.
enum Failure {
    Read(peel_runtime::ReadError),
    Render(peel_runtime::RenderError),
    Framebuffer(peel_runtime::display::FramebufferError),
}

/// Stop with `failure` (a real device would show it, or reset).
fn fail(failure: Failure) -> ! {
    loop {
        core::hint::black_box(&failure);
    }
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

/// `|target - eye|`, the same on the whole orbit: `sqrt(RADIUS^2 + (EYE_Y - TARGET_Y)^2)`.
const DISTANCE: f32 = 8.616_264;

/// The camera of the frame whose orbit angle has sine `s` and cosine `c`, looking from
/// `eye = (RADIUS s, EYE_Y, RADIUS c)` at `(0, TARGET_Y, 0)` (scene coordinates, relative to
/// the centre). With `full` the `f64` [`Camera`] (world coordinates) is linked too.
/// Otherwise the view is built in `f32` with its basis written out, since the orbit fixes it
/// (`forward = (target - eye) / DISTANCE`, `right = (c, 0, -s)`): the binary then holds
/// neither `f64` arithmetic nor a square root, which a Cortex-M4F would run in software
/// (libm's): [`LocalView::from_basis`] takes it as it is, where [`LocalView::look_at`] computes it
/// for any eye.
fn view(scene: &Scene<'_>, s: f32, c: f32) -> Result<LocalView, peel_runtime::RenderError> {
    let eye = Vec3::new(RADIUS * s, EYE_Y, RADIUS * c);
    let target = Vec3::new(0.0, TARGET_Y, 0.0);
    if cfg!(feature = "full") {
        let centre = scene.header().centre;
        let c = DVec3::from_array(centre);
        let pose = Pose::new(eye.as_dvec3() + c, target.as_dvec3() + c);
        let camera = Camera::look_at(pose, FOV_Y_DEG, WIDTH, HEIGHT, f64::from(NEAR))?;
        Ok(camera.view(centre))
    } else {
        let forward = (target - eye) * (1.0 / DISTANCE);
        let right = Vec3::new(c, 0.0, -s);
        Ok(LocalView::from_basis(
            eye, right, forward, FOCAL, WIDTH, HEIGHT, NEAR,
        ))
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

/// A frame's renderer over the static memory: span memory (front to back, each pixel once).
/// With `full`, a setting opaque to the optimiser may ask for back to front or ids (the build
/// script compiles the scene with ids), so those paths stay linked. Made per frame rather
/// than once: the same pixels, and the smallest configuration's code stays under 8 KiB (the
/// per-frame clear of span memory known to be word-aligned is cheaper).
#[inline(always)]
fn renderer<'m>(
    workspace: &'m mut Workspace<STACK, VERTS>,
    coverage: Coverage<'m>,
) -> Renderer<'m> {
    let mut renderer = Renderer::new(workspace).span_memory(coverage);
    if cfg!(feature = "full") {
        let setting = core::hint::black_box(0u32);
        if setting & 1 != 0 {
            renderer = renderer.back_to_front();
        }
        if setting & 2 != 0 {
            renderer = renderer.ids();
        }
    }
    renderer
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
    let scene = parse().unwrap_or_else(|e| fail(Failure::Read(e)));
    // The orbit angle as its sine and cosine, turned by a fixed rotation each frame (no
    // trigonometry on the device) and pulled back to the unit circle so rounding cannot drift.
    let (mut s, mut c) = (0.0f32, 1.0f32);
    loop {
        let view = view(&scene, s, c).unwrap_or_else(|e| fail(Failure::Render(e)));
        let mut fb = Rgb565Framebuffer::new(&mut frame[..], WIDTH, HEIGHT)
            .unwrap_or_else(|e| fail(Failure::Framebuffer(e)));
        fb.clear(Colour::new(24, 26, 32));
        let coverage = Coverage::new(&mut intervals[..], &mut counts[..], WIDTH, HEIGHT)
            .unwrap_or_else(|e| fail(Failure::Render(e)));
        let mut renderer = renderer(workspace, coverage);
        if let Err(e) = renderer.draw(&scene, &view, &mut fb) {
            fail(Failure::Render(e));
        }
        // Hand the frame to the "display": keeps the optimiser from dropping the drawing.
        core::hint::black_box(&*frame);
        (s, c) = (s * STEP_COS + c * STEP_SIN, c * STEP_COS - s * STEP_SIN);
        let k = 1.5 - 0.5 * (s * s + c * c);
        (s, c) = (s * k, c * k);
    }
}
