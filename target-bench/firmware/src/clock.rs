//! Frame timing with SysTick. QEMU does not emulate the DWT cycle counter; with `-icount
//! shift=0` every instruction takes 1 ns of virtual time and SysTick, on the 25 MHz core clock
//! of the MPS2 machines, advances one tick per 40 instructions, identically from run to run.
//! The runner turns ticks into instructions (x 40): instructions, not cycles.

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;
use cortex_m_rt::exception;

/// The counter's reload value: the longest period (2^24 ticks).
const RELOAD: u32 = 0x00FF_FFFF;

/// Periods completed; only the SysTick exception writes it (load and store are atomic on
/// every Cortex-M, read-modify-write is not on ARMv6-M, and is not needed).
static WRAPS: AtomicU32 = AtomicU32::new(0);

#[exception]
fn SysTick() {
    WRAPS.store(
        WRAPS.load(Ordering::Relaxed).wrapping_add(1),
        Ordering::Relaxed,
    );
}

/// SysTick counting down from [`RELOAD`] on the core clock, its wraps counted.
pub struct Clock {
    _syst: SYST,
}

impl Clock {
    /// Start the counter.
    pub fn start(mut syst: SYST) -> Clock {
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(RELOAD);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        Clock { _syst: syst }
    }

    /// Ticks since [`Clock::start`]. The wrap count is read before and after the counter:
    /// when they differ the counter wrapped in between and the read is taken again.
    pub fn ticks(&self) -> u64 {
        loop {
            let wraps = WRAPS.load(Ordering::Relaxed);
            let current = SYST::get_current();
            if WRAPS.load(Ordering::Relaxed) == wraps {
                return (u64::from(wraps) << 24) + u64::from(RELOAD - current);
            }
        }
    }
}
