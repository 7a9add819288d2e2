//! A recording SPI device and data/command pin (embedded-hal 1): every byte a panel driver
//! sends, with the level of the data/command line it was sent at, as the panel receives them.

use std::cell::RefCell;
use std::convert::Infallible;
use std::rc::Rc;

use embedded_hal::delay::DelayNs;
use embedded_hal::digital::{self, OutputPin};
use embedded_hal::spi::{self, Operation, SpiDevice};

/// One SPI write: its bytes, sent with the data/command line high (`data`: parameters or
/// pixels) or low (commands).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Write {
    pub data: bool,
    pub bytes: Vec<u8>,
}

/// The line as the panel sees it: the data/command level and the writes so far.
#[derive(Debug, Default)]
struct Line {
    data: bool,
    writes: Vec<Write>,
}

/// The recording that an SPI device and a pin made of it share.
#[derive(Debug, Clone, Default)]
pub struct Recorder(Rc<RefCell<Line>>);

impl Recorder {
    /// An SPI device whose writes are recorded.
    pub fn spi(&self) -> RecordingSpi {
        RecordingSpi(self.clone())
    }

    /// A data/command pin whose level goes with the writes.
    pub fn dc(&self) -> DcPin {
        DcPin(self.clone())
    }

    /// The writes so far (and forget them).
    pub fn take(&self) -> Vec<Write> {
        std::mem::take(&mut self.0.borrow_mut().writes)
    }
}

/// See [`Recorder::spi`].
#[derive(Debug)]
pub struct RecordingSpi(Recorder);

impl spi::ErrorType for RecordingSpi {
    type Error = Infallible;
}

impl SpiDevice for RecordingSpi {
    fn transaction(&mut self, operations: &mut [Operation<'_, u8>]) -> Result<(), Infallible> {
        let mut line = self.0 .0.borrow_mut();
        for op in operations {
            match op {
                Operation::Write(bytes) => {
                    let data = line.data;
                    line.writes.push(Write {
                        data,
                        bytes: bytes.to_vec(),
                    });
                }
                Operation::DelayNs(_) => {}
                // A panel on a write-only bus (no MISO) answers nothing.
                other => panic!("the panel's bus only writes, got {other:?}"),
            }
        }
        Ok(())
    }
}

/// See [`Recorder::dc`].
#[derive(Debug)]
pub struct DcPin(Recorder);

impl digital::ErrorType for DcPin {
    type Error = Infallible;
}

impl OutputPin for DcPin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.0 .0.borrow_mut().data = false;
        Ok(())
    }

    fn set_high(&mut self) -> Result<(), Infallible> {
        self.0 .0.borrow_mut().data = true;
        Ok(())
    }
}

/// A delay that takes no time: the recording needs the bytes, not the pauses between them.
#[derive(Debug)]
pub struct NoDelay;

impl DelayNs for NoDelay {
    fn delay_ns(&mut self, _ns: u32) {}
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_write_keeps_the_level_of_the_data_command_line() {
        let recorder = Recorder::default();
        let (mut spi, mut dc) = (recorder.spi(), recorder.dc());
        dc.set_low().unwrap();
        spi.write(&[0x2A]).unwrap();
        dc.set_high().unwrap();
        spi.write(&[0, 1, 0, 2]).unwrap();
        let expected = vec![
            Write {
                data: false,
                bytes: vec![0x2A],
            },
            Write {
                data: true,
                bytes: vec![0, 1, 0, 2],
            },
        ];
        assert_eq!(recorder.take(), expected);
        assert!(recorder.take().is_empty());
    }
}
