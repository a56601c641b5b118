//! Proof that a stack overflow faults instead of corrupting memory: installs the MPU guard at
//! the bottom of the stack ([`nav_qemu::stack::install_guard`], as the replay firmware does)
//! and then recurses with 4 KiB frames until the stack runs into it. The run must end in
//! failure (HardFault exit, or the runner's timeout if the core locks up); `scripts/test.sh`
//! requires that, and that the deepest frame reached was close to the guard (the whole stack
//! region was usable, and nothing below it was touched).
#![no_std]
#![no_main]

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m_rt::entry;
use nav_qemu::{exit_failure, exit_success};

/// Deepest recursion level reached (reported by the fault path through defmt).
static DEPTH: AtomicU32 = AtomicU32::new(0);

/// Recursion on purpose: each level holds a 4 KiB frame the optimiser cannot remove.
#[inline(never)]
fn descend(level: u32) -> u32 {
    let mut frame = [0_u8; 4096];
    frame[0] = level as u8;
    let frame = core::hint::black_box(frame);
    DEPTH.store(level, Ordering::Relaxed);
    if level.is_multiple_of(256) {
        defmt::println!("STACK depth {=u32} KiB", level * 4);
    }
    if level >= 1 << 20 {
        // 4 GiB of frames: never reached on a 4 MiB RAM.
        return level;
    }
    let below = descend(core::hint::black_box(level + 1));
    below.wrapping_add(u32::from(frame[4095]))
}

#[entry]
fn main() -> ! {
    let Some(mut peripherals) = cortex_m::Peripherals::take() else {
        exit_failure()
    };
    nav_qemu::stack::install_guard(&mut peripherals.MPU);
    defmt::println!("STACK guard installed; recursing until the stack overflows");
    let result = descend(1);
    // Unreachable unless the guard failed to fault.
    defmt::error!("STACK overflow not caught (result {=u32})", result);
    exit_success()
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    exit_failure()
}
