//! The 500 Hz minor frame on the target: SysTick interrupts every 2 ms of QEMU's virtual time
//! (`-icount shift=0`: one instruction per nanosecond), the frame loop waits for the next
//! interrupt, and each frame's cost is read off the SysTick counter in instructions.

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;
use cortex_m_rt::exception;

use crate::cost::INSTRUCTIONS_PER_TICK;

/// SysTick ticks per 2 ms frame at the MPS2 system clock of 25 MHz.
pub const FRAME_TICKS: u32 = 50_000;
/// Frame budget in instructions (2 ms at one instruction per virtual nanosecond).
pub const FRAME_BUDGET_INSTRUCTIONS: u32 = 2_000_000;

/// Frame interrupts since the clock started.
static FRAME_TICKS_ELAPSED: AtomicU32 = AtomicU32::new(0);

#[exception]
fn SysTick() {
    FRAME_TICKS_ELAPSED.fetch_add(1, Ordering::Release);
}

/// The frame interrupt and the frames it has started.
pub struct FrameClock {
    _systick: SYST,
    frames_started: u32,
}

impl FrameClock {
    /// Starts the 500 Hz frame interrupt.
    pub fn start(mut systick: SYST) -> Self {
        systick.set_clock_source(SystClkSource::Core);
        systick.set_reload(FRAME_TICKS - 1);
        systick.clear_current();
        systick.enable_interrupt();
        systick.enable_counter();
        Self {
            _systick: systick,
            frames_started: FRAME_TICKS_ELAPSED.load(Ordering::Acquire),
        }
    }

    /// Waits for the next frame interrupt, runs `frame` and returns its result and its cost
    /// (instructions). A frame that runs into the next one skips the interrupts it overlapped.
    #[inline(always)]
    pub fn run_frame<T>(&mut self, frame: impl FnOnce() -> T) -> (T, u32) {
        while FRAME_TICKS_ELAPSED.load(Ordering::Acquire) <= self.frames_started {
            cortex_m::asm::wfi();
        }
        self.frames_started = FRAME_TICKS_ELAPSED.load(Ordering::Acquire);
        let start_current = SYST::get_current();
        let result = frame();
        let end_current = SYST::get_current();
        let ticks_passed = FRAME_TICKS_ELAPSED.load(Ordering::Acquire) - self.frames_started;
        // SysTick counts down to 0 (where it interrupts; read right after, it still shows 0)
        // and reloads FRAME_TICKS − 1 on the next tick: ticks into the period = (N − c) mod N.
        let into_period = |current: u32| (FRAME_TICKS - current) % FRAME_TICKS;
        let (start_position, end_position) = (into_period(start_current), into_period(end_current));
        let mut elapsed_ticks = ticks_passed * FRAME_TICKS + end_position;
        if elapsed_ticks < start_position {
            // Wrapped between the last read and the interrupt being taken.
            elapsed_ticks += FRAME_TICKS;
        }
        let elapsed_ticks = elapsed_ticks - start_position;
        self.frames_started += ticks_passed;
        let cost = elapsed_ticks.saturating_mul(INSTRUCTIONS_PER_TICK as u32);
        (result, cost)
    }
}
