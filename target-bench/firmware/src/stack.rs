//! The stack's high-water mark: before a frame, every word from the end of the statics
//! (`__sheap`, after `.data`, `.bss` and `.uninit`) up to just below the current stack pointer
//! is painted with a pattern; after it, the lowest word whose paint is gone marks the deepest
//! the stack went (it starts at `_stack_start`, the top of RAM, and grows down towards the
//! statics). Paint gone down to the bottom means the stack reached the statics: a failure.

use core::ptr::{addr_of, read_volatile, write_volatile};

use crate::Failure;

/// The paint.
const PAINT: u32 = 0xA5C3_5A3C;
/// Bytes left unpainted below the stack pointer (this function's own calls).
const MARGIN: usize = 64;

extern "C" {
    /// End of the statics (cortex-m-rt's link.x).
    static __sheap: u32;
    /// Top of the stack (cortex-m-rt's link.x).
    static _stack_start: u32;
}

/// Only the symbols' addresses are taken (safe since Rust 1.82).
fn bottom() -> usize {
    addr_of!(__sheap) as usize
}

fn top() -> usize {
    addr_of!(_stack_start) as usize
}

/// Paint the free stack.
#[inline(never)]
pub fn paint() {
    let end = cortex_m::register::msp::read() as usize - MARGIN;
    let mut at = bottom();
    while at < end {
        // SAFETY: the words between the statics and the stack pointer belong to no one.
        unsafe { write_volatile(at as *mut u32, PAINT) };
        at += 4;
    }
}

/// Bytes of stack used since [`paint`] (the deepest point reached).
pub fn high_water() -> Result<usize, Failure> {
    let (bottom, top) = (bottom(), top());
    let mut at = bottom;
    // SAFETY: reads of RAM between the statics and the top of the stack.
    while at < top && unsafe { read_volatile(at as *const u32) } == PAINT {
        at += 4;
    }
    if at == bottom {
        return Err(Failure::StackOverflow);
    }
    Ok(top - at)
}
