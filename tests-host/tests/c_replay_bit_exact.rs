//! The C firmware (qemu/c-firmware: C code built with arm-none-eabi-gcc against nav-c's static
//! library) replays the default and the realistic-sensor scenarios on QEMU from the very input
//! files the Rust firmware reads; every output word of every frame must agree bit for bit with
//! the host's replay (and so with the Rust firmware's, `replay_bit_exact`). Its frame cost is
//! measured as the Rust firmware's (the SysTick frame clock around the frame call), and the
//! interface's share of the worst frame is compared with the Rust firmware's committed worst
//! frame (docs/results/qemu-replay-*.md): at most 2 %. The figures are written to
//! `docs/results/qemu-c-replay-*.md` (`NAV_RESULTS_BLESS=1` rewrites them).
//!
//! Ignored by default (needs QEMU, arm-none-eabi-gcc and the firmware): `scripts/test.sh`
//! builds it and runs this with `NAV_QEMU_C_REPLAY_ELF` set; `NAV_REPLAY_SECONDS` (default
//! 300) sets how much of each scenario is replayed.

use std::path::PathBuf;

use nav_sim::harness::target_replay::{replay_on_target, TargetReplayReport};
use nav_sim::Scenario;

/// Largest share of the Rust firmware's worst frame the C interface may add (per cent).
const INTERFACE_SHARE_BOUND_PERCENT: f64 = 2.0;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn seconds() -> u64 {
    std::env::var("NAV_REPLAY_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300)
}

/// The worst frame of all frames in the Rust firmware's committed results of `name`.
fn rust_worst_frame(name: &str) -> u64 {
    let path = root().join(format!("docs/results/qemu-replay-{name}.md"));
    let text = std::fs::read_to_string(&path).unwrap();
    let line = text
        .lines()
        .find(|line| line.trim_start().starts_with("all frames"))
        .unwrap_or_else(|| panic!("{}: no line of all frames", path.display()));
    let words: Vec<&str> = line.split_whitespace().collect();
    let position = words.iter().position(|word| *word == "worst").unwrap();
    words[position + 1].parse().unwrap()
}

/// Replays `scenario` on QEMU with the C firmware and checks it against the host.
fn c_replay(scenario: &Scenario, name: &str) -> TargetReplayReport {
    let root = root();
    let elf = root.join(
        std::env::var("NAV_QEMU_C_REPLAY_ELF").expect("NAV_QEMU_C_REPLAY_ELF: the C firmware"),
    );
    let seconds = seconds();
    let report = replay_on_target(
        scenario,
        seconds,
        &elf,
        &root.join("qemu/c-firmware/run.sh"),
        &root.join(format!("target/qemu/c-replay-{name}")),
    )
    .unwrap();
    print!("{}", report.text());
    assert_eq!(report.frames, (seconds * 500).min(scenario.frame_count()));
    if let Some(difference) = &report.difference {
        panic!("host and C firmware differ first at {difference:?}");
    }
    // The measurement is real: every frame costs something, and the stack was used.
    assert!(report.costs[0].1.minimum > 0);
    assert!(report.stack.high_water_bytes > 1024);
    report
}

/// Compares the C firmware's worst frame with the Rust firmware's and writes the figures.
fn check_interface_cost(name: &str, report: &TargetReplayReport) {
    let c_worst = report.costs[0].1.worst;
    let rust_worst = rust_worst_frame(name);
    // Frame costs are far below 2⁵³: exact in f64.
    let share_percent = 100.0 * (c_worst as f64 - rust_worst as f64) / rust_worst as f64;
    let text = format!(
        "{}The C firmware's worst frame {c_worst} instructions, the Rust firmware's {rust_worst} \
         (qemu-replay-{name}.md): the C interface adds {share_percent:.2} % (bound \
         {INTERFACE_SHARE_BOUND_PERCENT} %).\n",
        report.measured_text()
    );
    println!("{text}");
    if seconds() == 300 {
        tests_host::docs::check_results(
            &format!("qemu-c-replay-{name}.md"),
            "scripts/results.sh qemu",
            &text,
        );
    }
    assert!(
        share_percent <= INTERFACE_SHARE_BOUND_PERCENT,
        "the C interface adds {share_percent:.2} % to the worst frame ({c_worst} vs {rust_worst})"
    );
}

#[test]
#[ignore = "needs qemu-system-arm, arm-none-eabi-gcc and the C firmware; run by scripts/test.sh"]
fn the_c_firmware_replays_the_default_scenario_bit_for_bit() {
    let scenario = Scenario::default_scenario().unwrap();
    let report = c_replay(&scenario, "default");
    check_interface_cost("default", &report);
}

#[test]
#[ignore = "needs qemu-system-arm, arm-none-eabi-gcc and the C firmware; run by scripts/test.sh"]
fn the_c_firmware_replays_the_realistic_sensor_scenario_bit_for_bit() {
    let path = root().join("nav-sim/scenarios/realistic_sensors.toml");
    let scenario = Scenario::load(&path).unwrap();
    let report = c_replay(&scenario, "realistic");
    check_interface_cost("realistic", &report);
}
