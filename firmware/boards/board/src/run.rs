//! A board's firmware after its hardware set-up: the scene read once, the renderer made once,
//! then the orbit frame after frame.

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::pixelcolor::Rgb565;
use embedded_hal::delay::DelayNs;
use embedded_hal::digital::OutputPin;
use mipidsi::interface::{Interface, InterfacePixelFormat};
use mipidsi::models::Model;
use mipidsi::{Builder, NoResetPin};
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

/// What a board's `main` hands its hardware set-up ([`crate::main!`]): the scene its build
/// script compiled and its frame memory `M` (a [`Memory`]), for [`Firmware::start`] once the
/// panel is wired.
pub struct Firmware<'a, M> {
    scene: &'a [u8],
    memory: &'a mut M,
}

impl<'a, M> Firmware<'a, M> {
    /// `scene` drawn in `memory`.
    pub fn new(scene: &'a [u8], memory: &'a mut M) -> Self {
        Firmware { scene, memory }
    }
}

impl<
        const STACK: usize,
        const VERTS: usize,
        const NODES: usize,
        const VERTICES: usize,
        const RECORDS: usize,
    > Firmware<'_, Memory<STACK, VERTS, NODES, VERTICES, RECORDS>>
{
    /// Set up the panel `panel` describes (one of [`crate::panel`]'s settings over the board's
    /// SPI) with its reset pin, turn its backlight on, and [`run`] the orbit on it with
    /// `core`'s switches; stops with [`fail`] if the panel refuses its set-up or a pin fails.
    #[inline(always)]
    pub fn start<DI, M>(
        self,
        panel: Builder<DI, M, NoResetPin>,
        reset: impl OutputPin,
        mut backlight: impl OutputPin,
        delay: &mut impl DelayNs,
        core: Core,
    ) -> !
    where
        DI: Interface,
        M: Model<ColorFormat = Rgb565>,
        Rgb565: InterfacePixelFormat<DI::Word>,
    {
        let mut panel = panel
            .reset_pin(reset)
            .init(delay)
            .unwrap_or_else(|_| fail(Failure::Hardware));
        if backlight.set_high().is_err() {
            fail(Failure::Hardware)
        }
        run(self.scene, self.memory, core, &mut panel)
    }
}
