//! Peel on an STM32F411 "Black Pill" (Cortex-M4F at 100 MHz, 512 KiB flash, 128 KiB RAM)
//! with a 320x240 ILI9341 panel: an orbit around the scene compiled by build.rs, drawn front
//! to back frame after frame and sent to the panel in scan order (no framebuffer: 150 KiB
//! at this size, more than the part's RAM). This file is the hardware; the frames are
//! `peel_board`'s, which the boards share.
//!
//! Wiring: SPI1 with SCK on PA5 and MOSI on PA7, chip select PA4, data/command PB1, reset PB0,
//! backlight PB10 (or the module's LED pin to 3.3 V). The board's 25 MHz crystal clocks it.
//!
//! The memory comes from the scene's sizes file (`Memory`, see `peel_board::include_scene!`),
//! so another mesh (`PEEL_BOARD_MESH`) needs no edit here. The camera is `f32` alone, no
//! `f64` and no libm (the FPU does `f32` only; `f64` would be software).
#![no_std]
#![no_main]

use embedded_hal_bus::spi::ExclusiveDevice;
use panic_halt as _;
use peel_board::{fail, Core, Failure};
use stm32f4xx_hal::gpio::Speed;
use stm32f4xx_hal::pac::{self, SPI1};
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::rcc::Config;
use stm32f4xx_hal::spi::{Mode, Phase, Polarity, Spi};

peel_board::main!(cortex_m_rt::entry, hardware);

/// The Black Pill's clocks, pins and SPI, then its panel and the orbit.
// Inlined into `main`, its one caller, with the HAL's set-up (out of line: about 2 KB
// more flash).
#[inline(always)]
fn hardware(firmware: Firmware, buffer: &'static mut [u8; 512]) -> ! {
    let Some(dp) = pac::Peripherals::take() else {
        fail(Failure::Hardware)
    };
    let mut rcc = dp.RCC.freeze(Config::hse(25.MHz()).sysclk(100.MHz()));
    let gpioa = dp.GPIOA.split(&mut rcc);
    let gpiob = dp.GPIOB.split(&mut rcc);
    let mut delay = dp.TIM5.delay_us(&mut rcc);

    // The panel: SPI1 at 50 MHz (its APB2 clock of 100 MHz halved, the fastest).
    let sck = gpioa.pa5.into_alternate().speed(Speed::VeryHigh);
    let mosi = gpioa.pa7.into_alternate().speed(Speed::VeryHigh);
    let mode = Mode {
        polarity: Polarity::IdleLow,
        phase: Phase::CaptureOnFirstTransition,
    };
    let bus = Spi::new(
        dp.SPI1,
        (Some(sck), SPI1::NoMiso, Some(mosi)),
        mode,
        50.MHz(),
        &mut rcc,
    );
    let Ok(device) = ExclusiveDevice::new_no_delay(bus, gpioa.pa4.into_push_pull_output());
    let panel = peel_board::panel::ili9341(device, gpiob.pb1.into_push_pull_output(), buffer);
    let (reset, backlight) = (
        gpiob.pb0.into_push_pull_output(),
        gpiob.pb10.into_push_pull_output(),
    );
    firmware.start(panel, reset, backlight, &mut delay, Core::WithFpu)
}
