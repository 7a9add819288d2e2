//! A board's firmware after its hardware set-up: the scene read once, the renderer made once,
//! then the orbit frame after frame.

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::pixelcolor::Rgb565;
use peel_runtime::read::Scene;

use crate::{draw_frame, fail, next_azimuth, orbit_view, Core, Failure, Memory};

/// Validate `scene` (once, at boot), make the renderer over `memory` for `core`, and draw the
/// orbit around the scene to `panel` forever; stops with [`fail`] on the first error.
///
/// Always inlined into the board's `main`, its one caller: called out of line, LLVM no longer
/// inlined the HAL's set-up into `main` either, and the Black Pill's clock set-up stayed
/// generic (2 KB more flash).
#[inline(always)]
pub fn run<
    D,
    const STACK: usize,
    const VERTS: usize,
    const NODES: usize,
    const VERTICES: usize,
    const RECORDS: usize,
>(
    scene: &[u8],
    memory: &mut Memory<STACK, VERTS, NODES, VERTICES, RECORDS>,
    core: Core,
    panel: &mut D,
) -> !
where
    D: DrawTarget<Color = Rgb565>,
{
    let scene = Scene::parse(scene).unwrap_or_else(|e| fail(Failure::Read(e)));
    let mut renderer = memory
        .renderer(core)
        .unwrap_or_else(|e| fail(Failure::Render(e)));
    let header = scene.header();
    let mut azimuth_deg = 0.0;
    loop {
        let view = orbit_view(&header, azimuth_deg).unwrap_or_else(|e| fail(Failure::Render(e)));
        if let Err(e) = draw_frame(&mut renderer, &scene, &view, panel) {
            fail(e)
        }
        azimuth_deg = next_azimuth(azimuth_deg);
    }
}
