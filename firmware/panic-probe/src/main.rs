//! Panic probe: calls the runtime's public render path (parse, camera, render back to front
//! and front to back into a framebuffer, with span and vertex memory, anti-aliased with
//! pending pixels, anti-aliased in scan order and read out; the trusted parse with
//! the `f32` view) on inputs the
//! optimiser cannot see through (`black_box`), so every panic the runtime could reach on some
//! input stays in the program.
//! The panic handler of `panic-never` references an undefined symbol: linking succeeds only
//! when no panic is reachable. Build: `cargo build --release --target thumbv7em-none-eabihf`.
#![no_std]
#![no_main]

use core::hint::black_box;

use glam::{DVec3, Vec3};
use panic_never as _;
use peel_runtime::camera::{Camera, LocalView, Pose};
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Colour, Framebuffer, Rgb565};
#[cfg(feature = "antialias")]
use peel_runtime::pending::{Pending, PendingPixel};
use peel_runtime::read::Scene;
use peel_runtime::render::{Renderer, Workspace};
#[cfg(feature = "antialias")]
use peel_runtime::scan::{ScanMemory, ScanNode};
use peel_runtime::vertices::{CachedVertex, VertexCache};

/// Image size of the probe (any size: the runtime checks it).
const W: u32 = 40;
const H: u32 = 30;
const PIXELS: usize = (W * H) as usize;

/// Stand-in for a `.peel` file in flash; its contents are opaque to the optimiser.
static FILE: [u8; 4096] = [0; 4096];

fn probe() {
    let len = black_box(FILE.len());
    let bytes = FILE.get(..len).unwrap_or(&[]);
    let bytes = black_box(bytes);
    let Ok(scene) = Scene::parse(bytes) else {
        return;
    };
    let eye = black_box(DVec3::new(3.0, 2.0, 5.0));
    let target = black_box(DVec3::ZERO);
    let (fov, width, height, near) = black_box((60.0, W, H, 1e-3));
    let Ok(camera) = Camera::look_at(Pose::new(eye, target), fov, width, height, near) else {
        return;
    };
    let mut pixels = [0u16; PIXELS];
    let Ok(mut fb) = Framebuffer::<Rgb565>::new(&mut pixels, W, H) else {
        return;
    };
    fb.clear(black_box(Colour::new(1, 2, 3)));
    let view = camera.view(scene.header().centre);
    let mut workspace: Workspace<64, 32> = Workspace::new();
    let mut painter = Renderer::new(&mut workspace);
    if black_box(false) {
        painter = painter.without_culling();
    }
    let _ = black_box(painter.draw(&scene, &view, &mut fb));
    let mut intervals = [(0u16, 0u16); 8 * H as usize];
    let mut counts = [0u16; H as usize];
    // Projected vertices: any length, the file's vertex count is opaque.
    let mut memory = [CachedVertex::EMPTY; 64];
    let vertices = VertexCache::new(memory.get_mut(..black_box(64)).unwrap_or_default());
    if let Ok(coverage) = Coverage::new(&mut intervals, &mut counts, W, H) {
        let mut renderer = Renderer::new(&mut workspace)
            .span_memory(coverage)
            .vertex_memory(vertices);
        if black_box(true) {
            renderer = renderer.ids();
        }
        if black_box(false) {
            renderer = renderer.back_to_front();
        }
        if black_box(true) {
            renderer = renderer.integer_vertices();
        }
        let _ = black_box(renderer.draw(&scene, &view, &mut fb));
    }
    // Anti-aliased, with pending pixels of any size.
    #[cfg(feature = "antialias")]
    antialiased(&scene, &view, &mut workspace, &mut fb);
    black_box(&pixels);
}

/// [`probe`]'s frame anti-aliased.
#[cfg(feature = "antialias")]
fn antialiased(
    scene: &Scene<'_>,
    view: &LocalView,
    workspace: &mut Workspace<64, 32>,
    fb: &mut Framebuffer<'_, Rgb565>,
) {
    let mut intervals = [(0u16, 0u16); 8 * H as usize];
    let mut counts = [0u16; H as usize];
    let mut records = [PendingPixel::default(); 32];
    let mut heads = [0u16; H as usize];
    let records = records.get_mut(..black_box(32)).unwrap_or_default();
    if let (Ok(coverage), Ok(pending)) = (
        Coverage::new(&mut intervals, &mut counts, W, H),
        Pending::new(records, &mut heads, H),
    ) {
        let mut renderer = Renderer::new(workspace)
            .span_memory(coverage)
            .antialias(pending)
            .background(black_box(Colour::new(4, 5, 6)));
        let _ = black_box(renderer.draw(scene, view, fb));
    }
    scan_antialiased(scene, view, workspace);
}

/// [`probe`]'s frame anti-aliased in scan order, read out as one run and row by row. (Out of
/// line: inlined, it changed what LLVM proved of the framebuffer's `clear` in `probe`.)
#[cfg(feature = "antialias")]
#[inline(never)]
fn scan_antialiased(scene: &Scene<'_>, view: &LocalView, workspace: &mut Workspace<64, 32>) {
    let mut nodes = [ScanNode::EMPTY; 64];
    let mut scan_heads = [0u16; H as usize];
    let mut records = [PendingPixel::default(); 32];
    let mut heads = [0u16; H as usize];
    let nodes = nodes.get_mut(..black_box(64)).unwrap_or_default();
    let records = records.get_mut(..black_box(32)).unwrap_or_default();
    if let (Ok(memory), Ok(pending)) = (
        ScanMemory::new(nodes, &mut scan_heads, W, H),
        Pending::new(records, &mut heads, H),
    ) {
        let mut renderer = Renderer::new(workspace)
            .scan_memory(memory)
            .antialias(pending)
            .background(black_box(Colour::new(7, 8, 9)));
        if let Ok(frame) = renderer.draw_scan(scene, view) {
            let mut sum = 0u16;
            for p in frame.pixels() {
                sum = sum.wrapping_add(p);
            }
            let mut line = [0u16; W as usize];
            frame.row_into(black_box(3), &mut line);
            black_box((sum, line));
        }
    }
}

/// The smallest firmware's path: a file read with `parse_trusted` (any bytes past a valid
/// layout), an `f32` view from opaque values, front to back with span memory.
fn probe_trusted() {
    let len = black_box(FILE.len());
    let bytes = black_box(FILE.get(..len).unwrap_or(&[]));
    let Ok(scene) = Scene::parse_trusted(bytes) else {
        return;
    };
    let (eye, target, up) = black_box((Vec3::new(3.0, 2.0, 5.0), Vec3::ZERO, Vec3::Y));
    let (focal, width, height, near) = black_box((50.0, W, H, 1e-3));
    // Any view, even one `look_at` would refuse: `Renderer::draw` checks it.
    let view = black_box(
        LocalView::look_at(eye, target, up, focal, width, height, near)
            .unwrap_or_else(|_| black_box(view_from_nothing())),
    );
    let mut pixels = [0u16; PIXELS];
    let Ok(mut fb) = Framebuffer::<Rgb565>::new(&mut pixels, W, H) else {
        return;
    };
    let mut workspace: Workspace<64, 32> = Workspace::new();
    let mut intervals = [(0u16, 0u16); 8 * H as usize];
    let mut counts = [0u16; H as usize];
    if let Ok(coverage) = Coverage::new(&mut intervals, &mut counts, W, H) {
        let mut renderer = Renderer::new(&mut workspace).span_memory(coverage);
        let _ = black_box(renderer.draw(&scene, &view, &mut fb));
    }
    black_box(&pixels);
}

/// A view with every field opaque to the optimiser.
fn view_from_nothing() -> LocalView {
    LocalView {
        eye: black_box(Vec3::ZERO),
        right: black_box(Vec3::X),
        up: black_box(Vec3::Y),
        forward: black_box(Vec3::Z),
        fx: black_box(1.0),
        fy: black_box(1.0),
        cx: black_box(0.0),
        cy: black_box(0.0),
        width: black_box(W),
        height: black_box(H),
        near: black_box(1.0),
    }
}

/// Entry point (no runtime crate: the probe is linked, never run).
#[no_mangle]
pub extern "C" fn _start() -> ! {
    probe();
    probe_trusted();
    #[allow(clippy::empty_loop)]
    loop {}
}
