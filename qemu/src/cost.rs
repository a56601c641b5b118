//! Instruction-count harness: measures what a closure costs on the target, in instructions.
//!
//! QEMU runs with `-icount shift=0`, so every executed instruction advances virtual time by
//! exactly 1 ns. SysTick, clocked from the processor clock (CLKSOURCE = 1), runs at the MPS2
//! system clock of 25 MHz, so one SysTick tick is 40 ns = [`INSTRUCTIONS_PER_TICK`]
//! instructions. The `checks` firmware verifies that factor against a loop of known length on
//! every run (and fails if it is off by more than 1 %). Resolution: one tick, 40 instructions.
//! Span: 2^24 ticks (671 M instructions); a longer measurement is reported as an overflow.

use cortex_m::peripheral::{syst::SystClkSource, SYST};

/// Instructions per SysTick tick under `-icount shift=0` on MPS2 (1 GHz virtual / 25 MHz).
pub const INSTRUCTIONS_PER_TICK: u64 = 40;
/// SysTick reload value: the full 24-bit range.
const RELOAD: u32 = 0x00FF_FFFF;

/// SysTick-based instruction counter. Owns SYST so nothing else reprograms it meanwhile.
pub struct InstructionCounter {
    systick: SYST,
    /// Cost of an empty measurement (ticks), subtracted from every result.
    overhead_ticks: u32,
}

/// Why a measurement could not be made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, defmt::Format)]
pub enum CostError {
    /// The measured code ran longer than the 24-bit SysTick span.
    Overflow,
}

impl InstructionCounter {
    /// Takes SysTick, runs it free at the processor clock without interrupts, and calibrates
    /// the measurement overhead.
    pub fn new(mut systick: SYST) -> Self {
        systick.disable_interrupt();
        systick.set_clock_source(SystClkSource::Core);
        systick.set_reload(RELOAD);
        systick.clear_current();
        systick.enable_counter();
        let mut counter = Self {
            systick,
            overhead_ticks: 0,
        };
        counter.overhead_ticks = counter.measure_ticks(|| ()).map(|(_, t)| t).unwrap_or(0);
        counter
    }

    /// Runs `work` once and returns its result and its cost in SysTick ticks (overhead
    /// removed).
    pub fn measure_ticks<R>(&mut self, work: impl FnOnce() -> R) -> Result<(R, u32), CostError> {
        // Reading CSR clears COUNTFLAG, so a set flag afterwards means the counter wrapped.
        let _ = self.systick.has_wrapped();
        let start = SYST::get_current();
        let result = core::hint::black_box(work());
        let end = SYST::get_current();
        if self.systick.has_wrapped() && end >= start {
            return Err(CostError::Overflow);
        }
        // SysTick counts down and reloads from RELOAD after 0.
        let elapsed = if start >= end {
            start - end
        } else {
            start + (RELOAD + 1 - end)
        };
        Ok((result, elapsed.saturating_sub(self.overhead_ticks)))
    }

    /// Runs `work` once and returns its result and its cost in instructions
    /// (ticks × [`INSTRUCTIONS_PER_TICK`]).
    pub fn measure<R>(&mut self, work: impl FnOnce() -> R) -> Result<(R, u64), CostError> {
        self.measure_ticks(work)
            .map(|(result, ticks)| (result, u64::from(ticks) * INSTRUCTIONS_PER_TICK))
    }

    /// The calibrated overhead of an empty measurement, in ticks.
    pub fn overhead_ticks(&self) -> u32 {
        self.overhead_ticks
    }
}

/// Executes exactly `2 × iterations` instructions (`subs` + `bne` per iteration) plus a
/// constant few: the known-length workload for checking [`INSTRUCTIONS_PER_TICK`].
#[inline(never)]
pub fn known_length_loop(iterations: u32) {
    if iterations == 0 {
        return;
    }
    // SAFETY: register-only loop, no memory access.
    unsafe {
        core::arch::asm!(
            "2:",
            "subs {n}, {n}, #1",
            "bne 2b",
            n = inout(reg) iterations => _,
            options(nomem, nostack),
        );
    }
}
