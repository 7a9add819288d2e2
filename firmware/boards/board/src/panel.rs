//! The boards' panels as mipidsi drives them, in landscape (320x240): the settings of each
//! module, in one place for the board and for the host test that decodes what it is sent
//! (`on_panel.rs`). A board adds its reset pin and runs `init`.

use embedded_hal::digital::OutputPin;
use embedded_hal::spi::SpiDevice;
use mipidsi::interface::SpiInterface;
use mipidsi::models::{ILI9341Rgb565, ST7789};
use mipidsi::options::{ColorInversion, ColorOrder, Orientation, Rotation};
use mipidsi::{Builder, NoResetPin};

/// The Pico's ST7789 (as on Waveshare's Pico-LCD-2: a 240x320 IPS panel turned to landscape),
/// on the SPI device `spi` with data/command pin `dc`; mipidsi sends pixels in bursts of
/// `buffer`'s length. An IPS panel shows its colours inverted unless told to invert them.
pub fn st7789<SPI: SpiDevice, DC: OutputPin>(
    spi: SPI,
    dc: DC,
    buffer: &mut [u8],
) -> Builder<SpiInterface<'_, SPI, DC>, ST7789, NoResetPin> {
    Builder::new(ST7789, SpiInterface::new(spi, dc, buffer))
        .display_size(240, 320)
        .orientation(Orientation::new().rotate(Rotation::Deg90))
        .invert_colors(ColorInversion::Inverted)
}

/// The Black Pill's ILI9341 (240x320, turned to landscape), as [`st7789`]. Most ILI9341
/// modules take their colours in BGR order.
pub fn ili9341<SPI: SpiDevice, DC: OutputPin>(
    spi: SPI,
    dc: DC,
    buffer: &mut [u8],
) -> Builder<SpiInterface<'_, SPI, DC>, ILI9341Rgb565, NoResetPin> {
    Builder::new(ILI9341Rgb565, SpiInterface::new(spi, dc, buffer))
        .display_size(240, 320)
        .orientation(Orientation::new().rotate(Rotation::Deg90))
        .color_order(ColorOrder::Bgr)
}
