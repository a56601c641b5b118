//! The default scenario replayed through nav-fsw on the host and, from the very same
//! input file, by the firmware on QEMU (500 Hz SysTick frames in virtual time); every output
//! word of every frame must agree bit for bit, and the painted stack must stay within its
//! budget. Prints the per-frame target cost (instructions) by frame type, the stack
//! high-water mark and the image's static memory, and writes them to
//! `target/qemu/replay-report.txt`.
//!
//! Ignored by default (needs QEMU and the firmware): `scripts/test.sh` builds the firmware
//! and runs it with `NAV_QEMU_REPLAY_ELF` set; `NAV_REPLAY_SECONDS` (default 300) sets how
//! much of the scenario is replayed (scripts/test.sh: 300 s).

use std::path::PathBuf;

use nav_sim::target_replay::{replay_on_target, STACK_BUDGET_BYTES};
use nav_sim::Scenario;

#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn default_scenario_replays_bit_for_bit_on_host_and_target() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    // Relative paths are relative to the workspace root.
    let elf = root.join(
        std::env::var("NAV_QEMU_REPLAY_ELF").expect("NAV_QEMU_REPLAY_ELF: the replay firmware"),
    );
    let seconds: u64 = std::env::var("NAV_REPLAY_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    let scenario = Scenario::default_scenario().unwrap();
    let report = replay_on_target(
        &scenario,
        seconds,
        &elf,
        &root.join("qemu/run.sh"),
        &root.join("target/qemu/replay"),
    )
    .unwrap();
    let text = report.text();
    print!("{text}");
    std::fs::write(root.join("target/qemu/replay-report.txt"), &text).unwrap();
    assert_eq!(report.frames, (seconds * 500).min(scenario.frame_count()));
    if let Some(difference) = &report.difference {
        panic!("host and target differ first at {difference:?}");
    }
    assert!(
        report.stack.high_water_bytes <= STACK_BUDGET_BYTES,
        "stack high-water mark {} bytes above the budget of {STACK_BUDGET_BYTES}",
        report.stack.high_water_bytes
    );
    // The measurement is real: the flight path uses a stack, and the paint was found.
    assert!(report.stack.high_water_bytes > 1024);
    assert!(report.stack.high_water_bytes < report.stack.region_bytes);
    assert!(report.memory.flash_bytes > 0 && report.memory.static_ram_bytes > 0);
}

/// The realistic-sensor flight path on the target: the default flight with a receiver whose
/// errors are 6 m white + 8 m correlated (τ = 300 s) and that outputs velocity (0.05 m/s),
/// a star tracker blind above 3 °/s for 10 s after, and the filter given the receiver's
/// specification (`nav-sim/scenarios/realistic_sensors.toml`): the correlated-error states
/// and the velocity update run on QEMU bit for bit with the host, every frame within the
/// worst-frame budget.
#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn realistic_sensor_scenario_replays_bit_for_bit_on_host_and_target() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let elf = root.join(
        std::env::var("NAV_QEMU_REPLAY_ELF").expect("NAV_QEMU_REPLAY_ELF: the replay firmware"),
    );
    let seconds: u64 = std::env::var("NAV_REPLAY_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    let scenario = Scenario::load(&root.join(REALISTIC_SCENARIO)).unwrap();
    let report = replay_on_target(
        &scenario,
        seconds,
        &elf,
        &root.join("qemu/run.sh"),
        &root.join("target/qemu/replay-realistic"),
    )
    .unwrap();
    let text = report.text();
    print!("{text}");
    std::fs::write(root.join("target/qemu/replay-realistic-report.txt"), &text).unwrap();
    assert_eq!(report.frames, (seconds * 500).min(scenario.frame_count()));
    if let Some(difference) = &report.difference {
        panic!("host and target differ first at {difference:?}");
    }
    let worst = report.costs[0].1.worst;
    assert!(
        worst <= WORST_FRAME_BUDGET_INSTRUCTIONS,
        "worst frame {worst} instructions, budget {WORST_FRAME_BUDGET_INSTRUCTIONS}"
    );
    assert!(report.stack.high_water_bytes <= STACK_BUDGET_BYTES);
}

/// The realistic-sensor scenario of the replay test.
const REALISTIC_SCENARIO: &str = "nav-sim/scenarios/realistic_sensors.toml";
/// Worst frame the flight path may take on the Cortex-M7 (instructions).
const WORST_FRAME_BUDGET_INSTRUCTIONS: u64 = 40_000;
