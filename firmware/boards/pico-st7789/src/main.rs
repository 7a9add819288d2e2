//! Peel on a Raspberry Pi Pico (RP2040, Cortex-M0+ at 125 MHz, no FPU) with a 320x240 ST7789
//! panel: an orbit around the scene compiled by build.rs, drawn front to back frame after
//! frame and sent to the panel in scan order (no framebuffer: 150 KiB at this size). This file
//! is the hardware; the frames are `peel_board`'s, which the boards share.
//!
//! Wiring (as on Waveshare's Pico-LCD-2, an ST7789 of 240x320 turned to landscape): SPI1 with
//! SCK on GP10 and MOSI on GP11, chip select GP9, data/command GP8, reset GP12, backlight
//! GP13.
//!
//! The memory comes from the scene's sizes file (`Memory`, see `peel_board::include_scene!`),
//! so another mesh (`PEEL_BOARD_MESH`) needs no edit here.
#![no_std]
#![no_main]

use embedded_hal_bus::spi::ExclusiveDevice;
use panic_halt as _;
use peel_board::{fail, Core, Failure};
use rp_pico::hal::fugit::RateExtU32;
use rp_pico::hal::{self, gpio, pac, spi, Clock};

peel_board::main!(rp_pico::entry, hardware);

/// The Pico's clocks, pins and SPI, then its panel and the orbit.
// Inlined into `main`, its one caller, with the HAL's set-up (out of line: about 2 KB
// more flash).
#[inline(always)]
fn hardware(firmware: Firmware, buffer: &'static mut [u8; 512]) -> ! {
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
    let Ok(device) = ExclusiveDevice::new_no_delay(bus, pins.gpio9.into_push_pull_output());
    let panel = peel_board::panel::st7789(device, pins.gpio8.into_push_pull_output(), buffer);
    let reset = pins.gpio12.into_push_pull_output();
    let backlight = pins.gpio13.into_push_pull_output();
    firmware.start(panel, reset, backlight, &mut delay, Core::WithoutFpu)
}
