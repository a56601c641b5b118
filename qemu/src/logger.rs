//! defmt global logger writing encoded frames to semihosting stdout.
//!
//! Written here rather than taken from `defmt-semihosting` because that crate panics on a
//! re-entrant log call, and the flight build must contain no panic path at all. Here a
//! re-entrant call (a log from an exception handler while main is logging) drops that frame
//! and counts it in [`dropped_frames`]. Frames are buffered and written with few semihosting
//! calls. Only defmt frames ever go to this channel.

use core::cell::RefCell;
use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::interrupt::{self, CriticalSection, Mutex};
use cortex_m_semihosting::hio::{self, HostStream};

const BUFFER_BYTES: usize = 256;

/// Buffered semihosting stdout.
struct Sink {
    stream: Option<HostStream>,
    buffer: [u8; BUFFER_BYTES],
    used: usize,
}

impl Sink {
    fn flush(&mut self) {
        if self.stream.is_none() {
            self.stream = hio::hstdout().ok();
        }
        if let (Some(stream), Some(bytes)) = (self.stream.as_mut(), self.buffer.get(..self.used)) {
            // A failed host write cannot be reported anywhere else; the bytes are lost.
            let _ = stream.write_all(bytes);
        }
        self.used = 0;
    }

    fn push(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            if self.used >= BUFFER_BYTES {
                self.flush();
            }
            if let Some(slot) = self.buffer.get_mut(self.used) {
                *slot = byte;
                self.used += 1;
            }
        }
    }
}

struct LoggerState {
    encoder: defmt::Encoder,
    sink: Sink,
    /// A frame is being written (between acquire and release).
    active: bool,
    /// A re-entrant acquire is being ignored (its writes and release are dropped).
    nested: bool,
    /// Interrupts were enabled before acquire and must be re-enabled at release.
    restore_interrupts: bool,
}

static STATE: Mutex<RefCell<LoggerState>> = Mutex::new(RefCell::new(LoggerState {
    encoder: defmt::Encoder::new(),
    sink: Sink {
        stream: None,
        buffer: [0; BUFFER_BYTES],
        used: 0,
    },
    active: false,
    nested: false,
    restore_interrupts: false,
}));
static DROPPED_FRAMES: AtomicU32 = AtomicU32::new(0);

/// Number of log frames dropped because a log call re-entered the logger.
pub fn dropped_frames() -> u32 {
    DROPPED_FRAMES.load(Ordering::Relaxed)
}

fn with_state(action: impl FnOnce(&mut LoggerState)) {
    // SAFETY: only called between acquire() (which disabled interrupts) and release(), on a
    // single core, so no other context can hold the state.
    let cs = unsafe { CriticalSection::new() };
    if let Ok(mut state) = STATE.borrow(&cs).try_borrow_mut() {
        action(&mut state);
    };
}

#[defmt::global_logger]
struct SemihostingLogger;

// SAFETY: acquire/release bracket every frame with interrupts disabled (single core).
unsafe impl defmt::Logger for SemihostingLogger {
    fn acquire() {
        let interrupts_enabled = cortex_m::register::primask::read().is_active();
        interrupt::disable();
        with_state(|state| {
            if state.active {
                state.nested = true;
                DROPPED_FRAMES.fetch_add(1, Ordering::Relaxed);
                return;
            }
            state.active = true;
            state.restore_interrupts = interrupts_enabled;
            let LoggerState { encoder, sink, .. } = state;
            encoder.start_frame(|bytes| sink.push(bytes));
        });
    }

    unsafe fn flush() {
        with_state(|state| state.sink.flush());
    }

    unsafe fn release() {
        let mut enable = false;
        with_state(|state| {
            if state.nested {
                state.nested = false;
                return;
            }
            let LoggerState { encoder, sink, .. } = state;
            encoder.end_frame(|bytes| sink.push(bytes));
            sink.flush();
            state.active = false;
            enable = state.restore_interrupts;
        });
        if enable {
            // SAFETY: restores the interrupt state found at acquire().
            unsafe { interrupt::enable() };
        }
    }

    unsafe fn write(bytes: &[u8]) {
        with_state(|state| {
            if state.nested {
                return;
            }
            let LoggerState { encoder, sink, .. } = state;
            encoder.write(bytes, |encoded| sink.push(encoded));
        });
    }
}
