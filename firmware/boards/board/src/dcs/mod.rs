//! A model of the boards' panel controllers (ST7789, ILI9341) fed the bytes a driver sends
//! them: the MIPI DCS commands that set the panel up and write its memory, decoded into the
//! 320x240 landscape picture the panel shows, so that a test can compare it with the host's
//! frame pixel for pixel.
//!
//! The controller's memory is 240 columns by 320 rows, the glass's portrait pixels. A write
//! (`RAMWR`) fills the window of `CASET` (columns) and `RASET` (rows) left to right, top to
//! bottom, through `MADCTL`'s address mapping: row/column exchange (`MV`), then column and row
//! mirrors (`MX`, `MY`) in the memory's own terms, as the controllers' data sheets and
//! mipidsi's `MemoryMapping` have it. The boards' panels are turned a quarter turn
//! anticlockwise into landscape: the memory's first row on the left, its first column at
//! the bottom. What the glass shows of a stored colour depends on the colour inversion
//! (`INVON`, `INVOFF`) against the glass's own (an IPS panel inverts), and on `MADCTL`'s BGR
//! bit against the order of the glass's subpixels (both taken as the panel shows its memory:
//! mipidsi sets them once, before any pixel).
//!
//! Anything the model does not understand is an error with a message, never skipped: a
//! command it does not know, parameters of the wrong length, pixels before a window or in
//! another format than 16-bit RGB565 (`COLMOD` 0x55), more pixels than the window, half a
//! pixel, a picture with a pixel never written or a display never switched on.

#[cfg(test)]
mod tests;

use crate::recorder::Write;

/// The controller memory's columns (the portrait width).
pub const COLUMNS: usize = 240;
/// The controller memory's rows (the portrait height).
pub const ROWS: usize = 320;
/// The picture's width: the panel turned to landscape.
pub const PICTURE_WIDTH: usize = ROWS;
/// The picture's height.
pub const PICTURE_HEIGHT: usize = COLUMNS;

/// Software reset: the power-on state back.
const SWRESET: u8 = 0x01;
/// Sleep out.
const SLPOUT: u8 = 0x11;
/// Normal display mode (not partial): no effect on the picture.
const NORON: u8 = 0x13;
/// Colour inversion off.
const INVOFF: u8 = 0x20;
/// Colour inversion on.
const INVON: u8 = 0x21;
/// Display on.
const DISPON: u8 = 0x29;
/// Column address set: the window's first and last column, 16-bit big-endian each.
const CASET: u8 = 0x2A;
/// Row (page) address set: the window's first and last row.
const RASET: u8 = 0x2B;
/// Memory write: pixels into the window from its first column and row.
const RAMWR: u8 = 0x2C;
/// Memory access control: address mapping and colour order.
const MADCTL: u8 = 0x36;
/// Interface pixel format.
const COLMOD: u8 = 0x3A;

/// `MADCTL`'s row address order (mirrors rows).
const MY: u8 = 0x80;
/// `MADCTL`'s column address order (mirrors columns).
const MX: u8 = 0x40;
/// `MADCTL`'s row/column exchange.
const MV: u8 = 0x20;
/// `MADCTL`'s BGR order.
const BGR: u8 = 0x08;
/// `COLMOD` for 16 bits a pixel on both the RGB and the control interface.
const RGB565: u8 = 0x55;

/// A panel module: what its glass does to the controller's colours, and the commands of its
/// controller beyond the DCS ones above that leave the picture alone.
#[derive(Debug, Clone, Copy)]
pub struct Glass {
    /// The glass shows colours inverted unless the controller inverts them (IPS panels).
    pub inverts: bool,
    /// The glass's subpixels are in BGR order.
    pub bgr: bool,
    /// Commands known to change nothing in the picture, with their parameter count.
    pub neutral: &'static [(u8, usize)],
}

/// The Pico's ST7789 module (Waveshare's Pico-LCD-2): an IPS glass in RGB order.
pub const ST7789_IPS: Glass = Glass {
    inverts: true,
    bgr: false,
    neutral: &[],
};

/// The Black Pill's ILI9341 module: BGR subpixels. Its controller's `INVCTR` (0xB4: line or
/// frame inversion of the liquid crystal's drive, one parameter) changes no colour.
pub const ILI9341_BGR: Glass = Glass {
    inverts: false,
    bgr: true,
    neutral: &[(0xB4, 1)],
};

/// The command being received.
#[derive(Debug)]
enum Command {
    /// A command and the parameters so far.
    Parameters { code: u8, bytes: Vec<u8> },
    /// `RAMWR`: the next pixel's window address, and the first byte of a pixel if half of
    /// one came.
    Pixels {
        x: usize,
        y: usize,
        high: Option<u8>,
    },
}

/// The controller's state: its memory, its settings and the command being received.
#[derive(Debug)]
pub struct Panel {
    glass: Glass,
    /// Row by row, `None` where nothing was written (power-on memory is undefined).
    memory: Vec<Option<u16>>,
    madctl: u8,
    /// `None` until `COLMOD` 0x55: the power-on format is not 16-bit.
    colmod: Option<u8>,
    inverted: bool,
    asleep: bool,
    on: bool,
    /// The window: first and last column, first and last row, in the mapped addresses.
    columns: Option<(usize, usize)>,
    rows: Option<(usize, usize)>,
    command: Option<Command>,
}

impl Panel {
    /// A controller just powered on behind `glass`.
    pub fn new(glass: Glass) -> Panel {
        Panel {
            glass,
            memory: vec![None; COLUMNS * ROWS],
            madctl: 0,
            colmod: None,
            inverted: false,
            asleep: true,
            on: false,
            columns: None,
            rows: None,
            command: None,
        }
    }

    /// Receive `writes`, in order.
    pub fn feed(&mut self, writes: &[Write]) -> Result<(), String> {
        for w in writes {
            if w.data {
                self.data(&w.bytes)?;
            } else {
                for &code in &w.bytes {
                    self.start(code)?;
                }
            }
        }
        Ok(())
    }

    /// The picture the panel shows after what it received: [`PICTURE_WIDTH`] x
    /// [`PICTURE_HEIGHT`] RGB565 colours, row by row.
    pub fn picture(mut self) -> Result<Vec<u16>, String> {
        self.end()?;
        if self.asleep {
            return Err("the panel never left sleep (no SLPOUT)".into());
        }
        if !self.on {
            return Err("the display was never switched on (no DISPON)".into());
        }
        let mut picture = Vec::with_capacity(PICTURE_WIDTH * PICTURE_HEIGHT);
        for y in 0..PICTURE_HEIGHT {
            for x in 0..PICTURE_WIDTH {
                // A quarter turn anticlockwise: memory row `x` from the left, memory column
                // `COLUMNS - 1 - y` from the top.
                let (column, row) = (COLUMNS - 1 - y, x);
                let Some(stored) = self.memory[row * COLUMNS + column] else {
                    return Err(format!(
                        "picture pixel ({x}, {y}) (memory column {column}, row {row}) was never \
                         written"
                    ));
                };
                picture.push(self.shown(stored));
            }
        }
        Ok(picture)
    }

    /// The colour the glass shows for `stored`.
    fn shown(&self, stored: u16) -> u16 {
        let mut c = stored;
        if (self.madctl & BGR != 0) != self.glass.bgr {
            c = (c & 0x07E0) | (c >> 11) | ((c & 0x1F) << 11);
        }
        if self.inverted != self.glass.inverts {
            c = !c;
        }
        c
    }

    /// A command byte: the previous command ends and `code` starts.
    fn start(&mut self, code: u8) -> Result<(), String> {
        self.end()?;
        self.command = Some(if code == RAMWR {
            let (Some((x0, x1)), Some((y0, y1))) = (self.columns, self.rows) else {
                return Err("RAMWR without a window (CASET and RASET first)".into());
            };
            if self.colmod != Some(RGB565) {
                return Err("RAMWR before COLMOD set 16-bit pixels (0x55)".into());
            }
            // The mapped addresses: exchanged, the columns run along the memory's rows.
            let (width, height) = if self.madctl & MV != 0 {
                (ROWS, COLUMNS)
            } else {
                (COLUMNS, ROWS)
            };
            if x1 >= width || y1 >= height {
                return Err(format!(
                    "RAMWR window columns {x0}..={x1}, rows {y0}..={y1} outside the \
                     {width}x{height} addresses of MADCTL {:#04x}",
                    self.madctl
                ));
            }
            Command::Pixels {
                x: x0,
                y: y0,
                high: None,
            }
        } else if parameters(code, self.glass).is_some() {
            Command::Parameters {
                code,
                bytes: Vec::new(),
            }
        } else {
            return Err(format!(
                "command {code:#04x} is not one the panel model knows"
            ));
        });
        Ok(())
    }

    /// Bytes sent with the data/command line high: the current command's parameters or
    /// pixels.
    fn data(&mut self, bytes: &[u8]) -> Result<(), String> {
        match &mut self.command {
            None if bytes.is_empty() => Ok(()),
            None => Err(format!("{} data bytes before any command", bytes.len())),
            Some(Command::Parameters { code, bytes: got }) => {
                got.extend_from_slice(bytes);
                let want = parameters(*code, self.glass).unwrap_or(0);
                if got.len() > want {
                    return Err(format!(
                        "command {code:#04x} takes {want} parameter bytes, got {}",
                        got.len()
                    ));
                }
                Ok(())
            }
            Some(Command::Pixels { .. }) => {
                for &b in bytes {
                    self.pixel_byte(b)?;
                }
                Ok(())
            }
        }
    }

    /// One byte of `RAMWR`'s pixels: a pixel is two, big-endian.
    fn pixel_byte(&mut self, byte: u8) -> Result<(), String> {
        let (Some(Command::Pixels { x, y, high }), Some((x0, x1)), Some((_, y1))) =
            (&mut self.command, self.columns, self.rows)
        else {
            unreachable!("pixels come only inside RAMWR, which has a window");
        };
        let Some(first) = high.take() else {
            *high = Some(byte);
            return Ok(());
        };
        if *y > y1 {
            return Err(format!(
                "RAMWR past the end of its window (columns {x0}..={x1}, last row {y1})"
            ));
        }
        let colour = u16::from_be_bytes([first, byte]);
        let (mut column, mut row) = if self.madctl & MV != 0 {
            (*y, *x)
        } else {
            (*x, *y)
        };
        if self.madctl & MX != 0 {
            column = COLUMNS - 1 - column;
        }
        if self.madctl & MY != 0 {
            row = ROWS - 1 - row;
        }
        self.memory[row * COLUMNS + column] = Some(colour);
        *x += 1;
        if *x > x1 {
            *x = x0;
            *y += 1;
        }
        Ok(())
    }

    /// The current command ends (a new command byte, or the end of the stream): apply it.
    fn end(&mut self) -> Result<(), String> {
        match self.command.take() {
            None => Ok(()),
            Some(Command::Pixels { high: Some(_), .. }) => {
                Err("RAMWR ended in the middle of a pixel (an odd byte count)".into())
            }
            Some(Command::Pixels { .. }) => Ok(()),
            Some(Command::Parameters { code, bytes }) => {
                let want = parameters(code, self.glass).unwrap_or(0);
                if bytes.len() != want {
                    return Err(format!(
                        "command {code:#04x} takes {want} parameter bytes, got {}",
                        bytes.len()
                    ));
                }
                self.apply(code, &bytes)
            }
        }
    }

    /// Command `code` with all its parameters `p`.
    fn apply(&mut self, code: u8, p: &[u8]) -> Result<(), String> {
        let range = |p: &[u8]| {
            let (first, last) = (
                usize::from(u16::from_be_bytes([p[0], p[1]])),
                usize::from(u16::from_be_bytes([p[2], p[3]])),
            );
            if first > last {
                return Err(format!(
                    "command {code:#04x}: first address {first} after the last, {last}"
                ));
            }
            Ok(Some((first, last)))
        };
        match code {
            SWRESET => *self = Panel::new(self.glass),
            SLPOUT => self.asleep = false,
            INVOFF => self.inverted = false,
            INVON => self.inverted = true,
            DISPON => self.on = true,
            CASET => self.columns = range(p)?,
            RASET => self.rows = range(p)?,
            MADCTL => self.madctl = p[0],
            COLMOD if p[0] == RGB565 => self.colmod = Some(RGB565),
            COLMOD => {
                return Err(format!(
                    "COLMOD {:#04x}: the panel model takes 16-bit pixels only (0x55)",
                    p[0]
                ))
            }
            // NORON and the glass's neutral commands.
            _ => {}
        }
        Ok(())
    }
}

/// The parameter bytes of command `code`, if the model knows it (RAMWR's pixels aside).
fn parameters(code: u8, glass: Glass) -> Option<usize> {
    match code {
        SWRESET | SLPOUT | NORON | INVOFF | INVON | DISPON => Some(0),
        CASET | RASET => Some(4),
        MADCTL | COLMOD => Some(1),
        _ => glass
            .neutral
            .iter()
            .find(|(c, _)| *c == code)
            .map(|&(_, n)| n),
    }
}

/// The picture `glass` shows after `writes`.
pub fn decode(glass: Glass, writes: &[Write]) -> Result<Vec<u16>, String> {
    let mut panel = Panel::new(glass);
    panel.feed(writes)?;
    panel.picture()
}
