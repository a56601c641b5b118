//! Support for the Cortex-M7 firmware run on QEMU's MPS2-AN500:
//!
//! * a defmt global logger over semihosting stdout with no panic path (frames only: nothing
//!   else is ever printed on that channel, so `defmt-print` decodes the whole stream);
//! * semihosting exit codes, and a HardFault handler that exits QEMU with failure;
//! * the instruction-count harness ([`cost`]), based on SysTick under `-icount shift=0`;
//! * the 500 Hz SysTick frame ([`frame_clock`]) and the serial lines ([`cmsdk_uart`]);
//! * the flight software built in its static slot ([`flight_start`]);
//! * the stack high-water mark ([`stack`]) from cortex-m-rt's stack painting;
//! * the short scheduler scenario the cost checks and the profiler share ([`scenario`]).
#![no_std]
#![deny(missing_docs)]

pub mod cmsdk_uart;
pub mod cost;
pub mod flight_start;
pub mod frame_clock;
pub mod host_file;
pub mod logger;
pub mod scenario;
pub mod stack;

use cortex_m_rt::{exception, ExceptionFrame};
use cortex_m_semihosting::debug;

/// Ends the QEMU run with success (exit status 0).
pub fn exit_success() -> ! {
    debug::exit(debug::EXIT_SUCCESS);
    halt()
}

/// Ends the QEMU run with failure (exit status 1).
pub fn exit_failure() -> ! {
    debug::exit(debug::EXIT_FAILURE);
    halt()
}

/// Parks the core (only reached if the host ignored the exit request).
fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    defmt::error!("HardFault at pc={=u32:#010x}", frame.pc());
    exit_failure()
}

#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    defmt::error!("unexpected exception {=i16}", irqn);
    exit_failure()
}
