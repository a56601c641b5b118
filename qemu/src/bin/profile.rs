//! Instruction profiler support (`scripts/profile-target.sh`): runs the scheduler scenario
//! ([`nav_qemu::scenario`]) and brackets one frame of each kind (the last IMU-only frame
//! before the star frame, the star frame, the late-GNSS frame) between calls of the
//! never-inlined marker functions `profile_window_begin` and `profile_window_end`. QEMU's
//! execution trace (`-d exec,nochain`) between the markers, mapped to source lines with the
//! ELF's debug information, attributes every executed instruction of those frames.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use nav_fsw::scheduler::FilterArithmetic;
use nav_qemu::scenario::{SchedulerScenario, GNSS_FRAME, STAR_FRAME};
use nav_qemu::{exit_failure, exit_success};

/// Marks the start of a profiled frame (`frame` in r0, visible in the trace).
#[inline(never)]
#[no_mangle]
extern "C" fn profile_window_begin(frame: u32) {
    core::hint::black_box(frame);
}

/// Marks the end of a profiled frame.
#[inline(never)]
#[no_mangle]
extern "C" fn profile_window_end(frame: u32) {
    // A body different from the begin marker's, so the linker cannot fold the two.
    core::hint::black_box(!frame);
}

#[entry]
fn main() -> ! {
    let Some(mut scenario) = SchedulerScenario::new(FilterArithmetic::Structured) else {
        defmt::error!("profile: configuration rejected");
        exit_failure()
    };
    while let Some((frame, mut ports)) = scenario.next_frame() {
        let profiled = [STAR_FRAME - 1, STAR_FRAME, GNSS_FRAME].contains(&frame);
        if profiled {
            profile_window_begin(frame);
        }
        let telemetry = core::hint::black_box(ports.run(&mut scenario.computer));
        if profiled {
            profile_window_end(frame);
            defmt::println!("PROFILED frame {=u32}: {}", frame, telemetry.fusion);
        }
    }
    exit_success()
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    defmt::error!("panic on target");
    exit_failure()
}
