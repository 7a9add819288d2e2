//! One pending pixel's record, [`PendingPixel`]: its mask and the sums of its samples'
//! colours in one accumulator, so that adding a polygon's samples is one addition; and a
//! polygon's colour placed as one sample's increment ([`SampleColour`]).

use super::NONE;
use crate::display::Colour;
use crate::fill::samples::{Mask, FULL_MASK, SAMPLES};

/// One pending pixel: its column, its row list's next record, its covered samples and the sums
/// of their colours. 12 bytes: the mask and the sums share one 64-bit accumulator
/// ([`SAMPLES`] bits of mask, then 13 per channel, red lowest), kept as two words so
/// that the record stays 4-byte aligned. Adding a polygon's new samples is then one addition.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PendingPixel {
    pub(super) x: u16,
    pub(super) next: u16,
    pub(super) acc: [u32; 2],
}

/// Bits of a colour sum: at most [`SAMPLES`] x 255 per channel.
pub(super) const SUM_BITS: u32 = 13;
const _: () = assert!(SAMPLES * 255 < 1 << SUM_BITS && SAMPLES + 3 * SUM_BITS <= 64);

impl Default for PendingPixel {
    fn default() -> Self {
        PendingPixel {
            x: 0,
            next: NONE,
            acc: [0; 2],
        }
    }
}

impl PendingPixel {
    /// A record for caller memory before [`super::Pending::new`]: all zeros, so that a static
    /// array of them takes no flash (`.bss`); a record is written whole when it is taken.
    pub const EMPTY: PendingPixel = PendingPixel {
        x: 0,
        next: 0,
        acc: [0; 2],
    };

    pub(super) fn acc(&self) -> u64 {
        u64::from(self.acc[0]) | u64::from(self.acc[1]) << 32
    }

    pub(super) fn mask(&self) -> Mask {
        self.acc[0] & FULL_MASK
    }

    /// Add the samples of `mask` the record lacks, each of colour `sample` ([`packed`]): their
    /// bits and colours in one addition, no carry crossing a field.
    pub(super) fn add(&mut self, mask: Mask, sample: u64) {
        let new = mask & !self.mask();
        let acc = self.acc() + u64::from(new) + u64::from(new.count_ones()) * sample;
        self.acc = [acc as u32, (acc >> 32) as u32];
    }
}

/// A polygon's colour, and its channels placed as a [`PendingPixel`]'s sums (the accumulator's
/// increment for one sample), placed once per polygon.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SampleColour {
    pub(super) colour: Colour,
    pub(super) sample: u64,
}

impl SampleColour {
    /// `colour`, placed.
    pub fn new(colour: Colour) -> Self {
        SampleColour {
            colour,
            sample: packed(colour),
        }
    }
}

/// `colour`'s channels placed as a [`PendingPixel`]'s sums: the accumulator's increment for one
/// sample.
pub(super) fn packed(colour: Colour) -> u64 {
    (u64::from(colour.r) | u64::from(colour.g) << SUM_BITS | u64::from(colour.b) << (2 * SUM_BITS))
        << SAMPLES
}
