//! The default scenario replayed through nav-fsw on the host and, from the very same
//! input file, by the firmware on QEMU (500 Hz SysTick frames in virtual time); every output
//! word of every frame must agree bit for bit, and the painted stack must stay within its
//! budget. Prints the per-frame target cost (instructions) by frame type, the stack
//! high-water mark and the image's static memory, writes them to
//! `target/qemu/replay-report.txt` and compares them with the committed
//! `docs/results/qemu-replay-*.md` (`NAV_RESULTS_BLESS=1` rewrites those).
//!
//! Ignored by default (needs QEMU and the firmware): `scripts/test.sh` builds the firmware
//! and runs it with `NAV_QEMU_REPLAY_ELF` set; `NAV_REPLAY_SECONDS` (default 300) sets how
//! much of the scenario is replayed (scripts/test.sh: 300 s).

use std::path::PathBuf;

use nav_fsw::replay::OUTPUT_FIELD_NAMES;
use nav_sim::harness::target_replay::{
    replay_on_target, TargetReplayReport, FRAME_WORDS, STACK_BUDGET_BYTES,
    START_UP_STACK_BUDGET_BYTES,
};
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
    check_replay_results("default", &report);
    assert_eq!(report.frames, (seconds * 500).min(scenario.frame_count()));
    if let Some(difference) = &report.difference {
        panic!("host and target differ first at {difference:?}");
    }
    assert!(
        report.stack.high_water_bytes <= STACK_BUDGET_BYTES,
        "stack high-water mark {} bytes above the budget of {STACK_BUDGET_BYTES}",
        report.stack.high_water_bytes
    );
    assert!(
        report.stack.start_up_bytes <= START_UP_STACK_BUDGET_BYTES,
        "start-up stack {} bytes above the budget of {START_UP_STACK_BUDGET_BYTES}",
        report.stack.start_up_bytes
    );
    let worst = report.costs[0].1.worst;
    assert!(
        worst <= PAPER_FLIGHT_WORST_FRAME_BUDGET_INSTRUCTIONS,
        "worst frame {worst} instructions, budget {PAPER_FLIGHT_WORST_FRAME_BUDGET_INSTRUCTIONS}"
    );
    // The measurement is real: the flight path uses a stack, and the paint was found.
    assert!(report.stack.high_water_bytes > 1024);
    assert!(report.stack.high_water_bytes < report.stack.region_bytes);
    assert!(report.memory.flash_bytes > 0 && report.memory.static_ram_bytes > 0);
}

/// The realistic-sensor flight path on the target: the default flight with a receiver whose
/// errors are 6 m white + 8 m correlated (τ = 300 s) and that outputs velocity (0.05 m/s),
/// a star tracker blind above 3 °/s for 10 s after, and the filter given the receiver's
/// specification, in the real gravity field with the flight's 12 × 12 model and its allowance
/// (`nav-sim/scenarios/realistic_sensors.toml`): the correlated-error states, the velocity
/// update and the field's evaluation run on QEMU bit for bit with the host, every frame
/// within the worst-frame budget.
#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn realistic_sensor_scenario_replays_bit_for_bit_on_host_and_target() {
    let seconds: u64 = std::env::var("NAV_REPLAY_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    replay_within_budgets(
        REALISTIC_SCENARIO,
        seconds,
        "realistic",
        WORST_FRAME_BUDGET_INSTRUCTIONS,
    );
}

/// Every optional state block on: the upper-stage flight with the twelve systematic IMU
/// error states beside the correlated GNSS error states
/// (`nav-sim/scenarios/upper_stage_imu_errors_estimated.toml`), its first 60 s (burns,
/// star and GNSS updates, both borders' propagation and coupling) on QEMU bit for bit with
/// the host, within the 30,000-instruction frame budget and the stack budget.
#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn every_optional_state_block_replays_bit_for_bit_on_host_and_target() {
    replay_within_budgets(
        ALL_BLOCKS_SCENARIO,
        60,
        "all-blocks",
        ALL_BLOCKS_WORST_FRAME_BOUND_INSTRUCTIONS,
    );
}

/// The upper-stage flight as it is (`nav-sim/scenarios/upper_stage_as_it_is.toml`): every
/// effect nav-sim models at once and the flight software configured from the data sheets,
/// with every optional state block, the field beyond `J2`, the star slow error, aberration
/// correction and two heads, head 0 blind from 20 s to 30 s (both hand-overs). Its first 60 s
/// on QEMU bit for bit with the host, within [`AS_IT_IS_WORST_FRAME_BOUND_INSTRUCTIONS`] and
/// the stack budget; the results name the computer's size.
#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn the_upper_stage_as_it_is_replays_bit_for_bit_on_host_and_target() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut scenario = Scenario::load(&root.join(AS_IT_IS_SCENARIO)).unwrap();
    scenario.star_sensor.outages = vec![[20.0, 10.0]];
    let report = replay_scenario(&scenario, 60, "upper-stage-as-it-is");
    let word = |name: &str| {
        let index = OUTPUT_FIELD_NAMES.iter().position(|n| *n == name).unwrap();
        report.host_output[report.host_output.len() - FRAME_WORDS + index]
    };
    assert_eq!(word("star_head_handovers"), 2);
    let worst = report.costs[0].1.worst;
    assert!(
        worst <= AS_IT_IS_WORST_FRAME_BOUND_INSTRUCTIONS,
        "worst frame {worst} instructions"
    );
    assert!(report.stack.high_water_bytes <= STACK_BUDGET_BYTES);
    assert!(report.computer_bytes.is_some_and(|bytes| bytes > 26_000));
}

/// The flight's gravity field beyond `J2` (12 × 12, a share each frame that fuses nothing)
/// with its allowance, in the truth's 20 × 20 field
/// (`nav-sim/scenarios/gravity_field_modelled.toml`): its first 30 s (the rotations, star
/// and GNSS updates, 300 evaluations of the field) on QEMU bit for bit with the host, within
/// the paper flight's frame budget and the stack budget.
#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn the_flight_gravity_field_replays_bit_for_bit_on_host_and_target() {
    replay_within_budgets(
        GRAVITY_SCENARIO,
        30,
        "gravity",
        PAPER_FLIGHT_WORST_FRAME_BUDGET_INSTRUCTIONS,
    );
}

/// The star tracker's slow error walked in the installation states
/// (`nav-sim/scenarios/star_tracker_slow_error.toml`): its first 20 s (star and GNSS updates
/// with the walk added after every propagation) on QEMU bit for bit with the host, within
/// the paper flight's frame budget and the stack budget.
#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn the_star_slow_error_walk_replays_bit_for_bit_on_host_and_target() {
    replay_within_budgets(
        STAR_SLOW_ERROR_SCENARIO,
        20,
        "star-slow-error",
        PAPER_FLIGHT_WORST_FRAME_BUDGET_INSTRUCTIONS,
    );
}

/// A star tracker that leaves velocity aberration in, and the flight software removing it
/// (`nav-sim/scenarios/star_tracker_aberration.toml`): its first 30 s (every star update
/// corrected with the navigation velocity) on QEMU bit for bit with the host, within the
/// 30,000-instruction frame budget and the stack budget.
#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn the_star_aberration_correction_replays_bit_for_bit_on_host_and_target() {
    replay_within_budgets(
        ABERRATION_SCENARIO,
        30,
        "aberration",
        ALL_BLOCKS_WORST_FRAME_BOUND_INSTRUCTIONS,
    );
}

/// A star tracker noisier than the flight software is told
/// (`nav-sim/scenarios/star_tracker_roll_noise_unmodelled.toml`): the consistency monitor
/// fails within seconds and the star noise matching sets the update's noise from then on
/// (the square roots of its averages in every star frame); the first 10 s on QEMU bit for
/// bit with the host, within the 30,000-instruction frame budget and the stack budget, the
/// matching engaged and the matched roll noise above the configured 10″ by the end.
#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn the_star_noise_matching_replays_bit_for_bit_on_host_and_target() {
    let report = replay_scenario_file(NOISE_MATCHING_SCENARIO, 10, "noise-matching");
    assert!(report.costs[0].1.worst <= ALL_BLOCKS_WORST_FRAME_BOUND_INSTRUCTIONS);
    assert!(report.stack.high_water_bytes <= STACK_BUDGET_BYTES);
    let word = |name: &str| {
        let index = OUTPUT_FIELD_NAMES.iter().position(|n| *n == name).unwrap();
        report.host_output[report.host_output.len() - FRAME_WORDS + index]
    };
    assert_eq!(word("star_noise_matched"), 1);
    let roll_rad = f64::from_bits(word("star_noise_z_rad"));
    let configured_rad = 10.0 * std::f64::consts::PI / 180.0 / 3600.0;
    assert!(
        roll_rad > 1.5 * configured_rad,
        "matched roll noise {roll_rad} rad"
    );
}

/// Two tracker heads (`nav-sim/scenarios/star_tracker_two_heads.toml`) with head 0 blind from
/// 12 s to 18 s after the start: the pairs align head 1 in the first 12 s, the outage hands the
/// installation block to head 1, head 0's return hands it back. The first 25 s on QEMU bit for
/// bit with the host, within the frame and stack budgets, with both hand-overs.
#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn two_star_heads_hand_over_bit_for_bit_on_host_and_target() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut scenario = Scenario::load(&root.join(TWO_HEADS_SCENARIO)).unwrap();
    scenario.star_sensor.outages = vec![[12.0, 6.0]];
    let report = replay_scenario(&scenario, 25, "two-heads");
    assert!(report.costs[0].1.worst <= PAPER_FLIGHT_WORST_FRAME_BUDGET_INSTRUCTIONS);
    assert!(report.stack.high_water_bytes <= STACK_BUDGET_BYTES);
    assert_eq!(report.withheld_star_measurements, 0);
    let word = |name: &str| {
        let index = OUTPUT_FIELD_NAMES.iter().position(|n| *n == name).unwrap();
        report.host_output[report.host_output.len() - FRAME_WORDS + index]
    };
    assert_eq!(word("star_head_handovers"), 2);
    assert_eq!(word("star_active_head"), 0);
    assert_eq!(word("star_declared_faulty"), 0);
}

/// [`replay_scenario_file`], and its worst frame within `worst_frame_bound` instructions and
/// its frame-loop stack within [`STACK_BUDGET_BYTES`].
fn replay_within_budgets(path: &str, seconds: u64, name: &str, worst_frame_bound: u64) {
    let report = replay_scenario_file(path, seconds, name);
    let worst = report.costs[0].1.worst;
    assert!(
        worst <= worst_frame_bound,
        "{path}: worst frame {worst} instructions, bound {worst_frame_bound}"
    );
    assert!(report.stack.high_water_bytes <= STACK_BUDGET_BYTES);
}

/// Replays the first `seconds` of the scenario file `path` (from the repository root) on
/// the host and on QEMU, prints and saves the report as `target/qemu/replay-{name}*`, and
/// asserts the frame count and bit-for-bit agreement.
fn replay_scenario_file(path: &str, seconds: u64, name: &str) -> TargetReplayReport {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    replay_scenario(&Scenario::load(&root.join(path)).unwrap(), seconds, name)
}

/// [`replay_scenario_file`] for a scenario already loaded (and edited).
fn replay_scenario(scenario: &Scenario, seconds: u64, name: &str) -> TargetReplayReport {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let elf = root.join(
        std::env::var("NAV_QEMU_REPLAY_ELF").expect("NAV_QEMU_REPLAY_ELF: the replay firmware"),
    );
    let report = replay_on_target(
        scenario,
        seconds,
        &elf,
        &root.join("qemu/run.sh"),
        &root.join(format!("target/qemu/replay-{name}")),
    )
    .unwrap();
    let text = report.text();
    print!("{text}");
    std::fs::write(
        root.join(format!("target/qemu/replay-{name}-report.txt")),
        &text,
    )
    .unwrap();
    assert_eq!(report.frames, (seconds * 500).min(scenario.frame_count()));
    if let Some(difference) = &report.difference {
        panic!("{name}: host and target differ first at {difference:?}");
    }
    check_replay_results(name, &report);
    report
}

/// Compares the measured cost, stack and memory of the replay `name` with the committed
/// `docs/results/qemu-replay-{name}.md` (`-icount` makes them deterministic for one
/// firmware binary), unless `NAV_REPLAY_SECONDS` shortened the replays.
fn check_replay_results(name: &str, report: &TargetReplayReport) {
    let full = std::env::var("NAV_REPLAY_SECONDS").map_or(true, |seconds| seconds == "300");
    if !full {
        println!("NAV_REPLAY_SECONDS set: the results of {name} are not compared");
        return;
    }
    tests_host::docs::check_results(
        &format!("qemu-replay-{name}.md"),
        "scripts/results.sh qemu",
        &report.measured_text(),
    );
}

/// The scenario with every optional state block on.
const ALL_BLOCKS_SCENARIO: &str = "nav-sim/scenarios/upper_stage_imu_errors_estimated.toml";
/// The upper stage as it is: every modelled effect, configured from the data sheets.
const AS_IT_IS_SCENARIO: &str = "nav-sim/scenarios/upper_stage_as_it_is.toml";
/// Its worst frame may take this many instructions: the budget with every optional block on
/// (the dearest frame is a late GNSS velocity update with both borders, docs/guide/performance.md).
const ALL_BLOCKS_WORST_FRAME_BOUND_INSTRUCTIONS: u64 = 30_000;
/// The upper stage as it is holds its worst frame under this bound, above the 30,000 target
/// of [`ALL_BLOCKS_WORST_FRAME_BOUND_INSTRUCTIONS`]: its dearest frames are propagation frames
/// at the GNSS fixes' rate that carry more than the others (the figures:
/// docs/results/qemu-replay-upper-stage-as-it-is.md). Until that work leaves the propagation
/// frames, this bound keeps the flight from growing.
const AS_IT_IS_WORST_FRAME_BOUND_INSTRUCTIONS: u64 = 31_000;

/// The default flight with a tracker that leaves velocity aberration in, corrected by the
/// flight software.
const ABERRATION_SCENARIO: &str = "nav-sim/scenarios/star_tracker_aberration.toml";

/// The default flight with the flight's 12 × 12 gravity field and its allowance.
const GRAVITY_SCENARIO: &str = "nav-sim/scenarios/gravity_field_modelled.toml";

/// The default flight with a tracker noisier about its boresight than the flight software is
/// told.
const NOISE_MATCHING_SCENARIO: &str = "nav-sim/scenarios/star_tracker_roll_noise_unmodelled.toml";

/// The default flight with two tracker heads, head 0 blind for the middle third.
const TWO_HEADS_SCENARIO: &str = "nav-sim/scenarios/star_tracker_two_heads.toml";

/// The default flight with a star tracker slow error the flight software is told of.
const STAR_SLOW_ERROR_SCENARIO: &str = "nav-sim/scenarios/star_tracker_slow_error.toml";

/// The realistic-sensor scenario of the replay test.
const REALISTIC_SCENARIO: &str = "nav-sim/scenarios/realistic_sensors.toml";
/// Worst frame the flight path may take on the Cortex-M7 (instructions) with the
/// correlated-GNSS-error states and the velocity update (the dearest frame is a GNSS velocity
/// update referred by one frame, in a frame that fuses and does not propagate; measured in
/// docs/guide/performance.md).
const WORST_FRAME_BUDGET_INSTRUCTIONS: u64 = 23_000;
/// Worst frame of the paper's flight (white GNSS errors, no error states) on the Cortex-M7
/// (instructions; measured in docs/guide/performance.md).
const PAPER_FLIGHT_WORST_FRAME_BUDGET_INSTRUCTIONS: u64 = 20_000;

/// A recorded log with what real logs have: IMU samples missing (one, then five in a row), a
/// duplicated IMU record, a duplicated star record and a time jump of 40 ms. The firmware's
/// frame builder places every record by its own time exactly as the host's: bit for bit, the
/// missing samples are frames without one (counted), the duplicate is dropped (counted), and
/// no later measurement is refused as from the future.
#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn an_edited_log_replays_bit_for_bit_with_every_gap_counted() {
    use nav_fsw::log_record::LogRecord;
    use nav_fsw::replay::OUTPUT_FIELD_NAMES;
    use nav_sim::harness::target_replay::{replay_records_on_target, FRAME_WORDS};

    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let elf = root.join(
        std::env::var("NAV_QEMU_REPLAY_ELF").expect("NAV_QEMU_REPLAY_ELF: the replay firmware"),
    );
    let scenario = Scenario::default_scenario().unwrap();
    let mut log = nav_sim::logs::sensor_log::simulated_records(&scenario, 10_000).unwrap();
    let imu_index = |log: &[LogRecord], sequence: u64| {
        log.iter()
            .position(|r| matches!(r, LogRecord::Imu(imu) if imu.sequence == sequence))
            .unwrap()
    };
    let missing = imu_index(&log, 1_000);
    log.remove(missing);
    for sequence in 3_000..3_005 {
        let index = imu_index(&log, sequence);
        log.remove(index);
    }
    let duplicate = imu_index(&log, 4_000);
    log.insert(duplicate + 1, log[duplicate]);
    let star = log
        .iter()
        .position(|r| matches!(r, LogRecord::Star(_)))
        .unwrap();
    log.insert(star + 1, log[star]);
    // Twelve fixes in one frame: its ports hold four, the other eight are counted.
    let fix = log
        .iter()
        .position(|r| matches!(r, LogRecord::Gnss(_)))
        .unwrap();
    let copies = vec![log[fix]; 11];
    log.splice(fix + 1..fix + 1, copies);
    let jump = imu_index(&log, 6_000);
    for record in &mut log[jump..] {
        *record = nav_sim::logs::sensor_log::shifted(record, 0.04);
    }
    let report = replay_records_on_target(
        &scenario,
        &log,
        &elf,
        &root.join("qemu/run.sh"),
        &root.join("target/qemu/replay-edited"),
    )
    .unwrap();
    print!("{}", report.text());
    if let Some(difference) = &report.difference {
        panic!("host and target differ first at {difference:?}");
    }
    // 10,000 frames, 6 without a sample, and 20 more bridging the 40 ms jump.
    assert_eq!(report.frames, 10_020);
    let last = report.host_output.chunks_exact(FRAME_WORDS).last().unwrap();
    let word = |name: &str| last[OUTPUT_FIELD_NAMES.iter().position(|n| *n == name).unwrap()];
    assert_eq!(word("imu_missing"), 6 + 20);
    assert_eq!(word("imu_records_dropped"), 1);
    assert_eq!(word("measurement_future"), 0);
    assert_eq!(word("imu_time_jump"), 1);
    assert_eq!(word("dropped_measurements"), 8);
}

/// The firmware refuses what the host refuses: a log on another time base (shifted by
/// 0.5 s), a log at another IMU rate (100 Hz against the scenario's 500 Hz) and a log without
/// IMU records each end the firmware's replay with a failure, and the host's run of the same
/// input returns an error.
#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn the_firmware_refuses_a_log_on_another_time_base_or_rate_or_without_imu() {
    use nav_fsw::log_record::LogRecord;
    use nav_sim::harness::target_replay::replay_records_on_target;

    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let elf = root.join(
        std::env::var("NAV_QEMU_REPLAY_ELF").expect("NAV_QEMU_REPLAY_ELF: the replay firmware"),
    );
    let records = |scenario: &Scenario| -> Vec<LogRecord> {
        nav_sim::logs::sensor_log::simulated_records(scenario, 200).unwrap()
    };
    let scenario = Scenario::default_scenario().unwrap();
    let shifted: Vec<LogRecord> = records(&scenario)
        .iter()
        .map(|record| nav_sim::logs::sensor_log::shifted(record, 0.5))
        .collect();
    let mut slow = scenario.clone();
    slow.imu.rate_hz = 100.0;
    let without_imu: Vec<LogRecord> = records(&scenario)
        .into_iter()
        .filter(|r| !matches!(r, LogRecord::Imu(_)))
        .collect();
    for (case, log) in [
        ("time base", shifted),
        ("IMU rate", records(&slow)),
        ("no IMU", without_imu),
    ] {
        let outcome = replay_records_on_target(
            &scenario,
            &log,
            &elf,
            &root.join("qemu/run.sh"),
            &root.join("target/qemu/replay-refused"),
        );
        let error = outcome.expect_err(case).to_string();
        assert!(error.contains("firmware replay failed"), "{case}: {error}");
        let input = nav_sim::harness::target_replay::records_input(&scenario, &log).unwrap();
        let host = nav_sim::harness::target_replay::run_on_host(&input);
        assert!(
            host.as_ref().is_err() || host.as_ref().is_ok_and(|words| words.is_empty()),
            "{case}: the host accepts it"
        );
    }
}
