//! Real logs through `nav-sim replay` (nav_sim::harness::log_replay) and nav-fsw's frame assembler:
//! dropped IMU samples, duplicated records, time jumps, logs at another rate or on another
//! time base, more measurements in a frame than its ports hold. Every sample is placed by
//! its own time tag, every measurement is fused or counted, and a log that does not match the
//! scenario is refused with both values named.

use crate::common;

use nav_fsw::log_record::LogRecord;
use nav_fsw::replay::FrameAssembler;
use nav_fsw::scheduler::NavigationComputer;
use nav_fsw::telemetry::FrameFusion;
use nav_sim::harness::log_replay::{self, ReplaySummary};
use nav_sim::logs::sensor_log::{self, SensorLogWriter};
use nav_sim::Scenario;
use proptest::prelude::*;

/// The short test flight with a 10 Hz star sensor and 10 Hz GNSS (many measurements to
/// account for).
fn scenario() -> Scenario {
    let mut scenario = common::short_scenario();
    scenario.star_sensor.rate_hz = 10.0;
    scenario.gnss.rate_hz = 10.0;
    scenario
}

/// The first `seconds` of `scenario`'s sensor log.
fn records(scenario: &Scenario, seconds: f64) -> Vec<LogRecord> {
    let frames = (seconds / scenario.imu.frame_period_s()).round() as u64;
    let records = sensor_log::simulated_records(scenario, frames).unwrap();
    assert!(records.iter().filter(|r| is_imu(r)).count() as u64 == frames);
    records
}

fn csv(records: &[LogRecord]) -> Vec<u8> {
    let mut writer = SensorLogWriter::new(Vec::new()).unwrap();
    for record in records {
        writer.write(record).unwrap();
    }
    writer.finish().unwrap()
}

/// `nav-sim replay` of `records`: the summary and the output CSV, or the error message.
fn replay(records: &[LogRecord], scenario: &Scenario) -> Result<(ReplaySummary, String), String> {
    let mut output = Vec::new();
    let summary = log_replay::replay(csv(records).as_slice(), scenario, &mut output)
        .map_err(|error| error.to_string())?;
    Ok((summary, String::from_utf8(output).unwrap()))
}

/// The value of `column` in the last row of a replay output.
fn last_value(output: &str, column: &str) -> f64 {
    let mut lines = output.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let index = header.iter().position(|name| *name == column).unwrap();
    let last: Vec<&str> = lines.last().unwrap().split(',').collect();
    last[index].parse().unwrap()
}

fn is_imu(record: &LogRecord) -> bool {
    matches!(record, LogRecord::Imu(_))
}

#[test]
fn a_missing_imu_row_is_a_held_frame_and_every_later_measurement_is_still_used() {
    let scenario = scenario();
    let intact = records(&scenario, 20.0);
    let mut gapped = intact.clone();
    let tenth_second = intact
        .iter()
        .position(|r| matches!(r, LogRecord::Imu(imu) if imu.sequence == 5_000))
        .unwrap();
    gapped.remove(tenth_second);
    let (reference, reference_output) = replay(&intact, &scenario).unwrap();
    let (summary, output) = replay(&gapped, &scenario).unwrap();
    assert_eq!(summary.frames, reference.frames);
    assert_eq!(summary.counts.frames_without_imu, 1);
    assert_eq!(summary.health.imu_missing, 1);
    assert_eq!(summary.health.measurement_future, 0);
    assert_eq!(
        summary.counts.measurements_delivered,
        reference.counts.measurements_delivered
    );
    // One held 2 ms sample in a coast costs far less than the GNSS noise.
    for axis in ["x", "y", "z"] {
        let column = format!("position_{axis}_m");
        let difference = last_value(&output, &column) - last_value(&reference_output, &column);
        assert!(difference.abs() < 0.5, "{column}: {difference} m");
    }
    assert_eq!(
        last_value(&output, "replay_frames_without_imu").to_bits(),
        1.0_f64.to_bits()
    );
}

#[test]
fn a_log_at_another_imu_rate_is_refused_naming_both_rates() {
    let scenario = scenario();
    let mut slow = scenario.clone();
    slow.imu.rate_hz = 100.0;
    slow.validate().unwrap();
    let error = replay(&records(&slow, 1.0), &scenario).unwrap_err();
    assert!(error.contains("0.01") && error.contains("0.002"), "{error}");
    assert!(error.contains("line 2"), "{error}");
}

#[test]
fn a_log_on_another_time_base_is_refused_naming_both_times() {
    let scenario = scenario();
    let later: Vec<LogRecord> = records(&scenario, 1.0)
        .iter()
        .map(|r| sensor_log::shifted(r, 0.5))
        .collect();
    let error = replay(&later, &scenario).unwrap_err();
    assert!(
        error.contains("600.502") && error.contains("600.002"),
        "{error}"
    );
}

#[test]
fn an_imu_interval_that_is_zero_negative_or_huge_is_refused() {
    let scenario = scenario();
    let log = records(&scenario, 1.0);
    for interval_s in [0.0, -0.002, 1e300] {
        let mut edited = log.clone();
        let Some(LogRecord::Imu(imu)) = edited.get_mut(20) else {
            panic!("record 20 is an IMU record in this log")
        };
        imu.interval_s = interval_s;
        let error = replay(&edited, &scenario).unwrap_err();
        assert!(
            error.contains("interval_s") && error.contains("0.002"),
            "{error}"
        );
    }
}

#[test]
fn a_log_without_imu_rows_is_refused() {
    let scenario = scenario();
    let measurements: Vec<LogRecord> = records(&scenario, 1.0)
        .into_iter()
        .filter(|r| !is_imu(r))
        .collect();
    assert!(!measurements.is_empty());
    let error = replay(&measurements, &scenario).unwrap_err();
    assert!(error.contains("no IMU record"), "{error}");
}

#[test]
fn fixes_beyond_a_frames_ports_are_counted_in_the_output() {
    let scenario = scenario();
    let mut log = records(&scenario, 2.0);
    let fix = log
        .iter()
        .position(|r| matches!(r, LogRecord::Gnss(_)))
        .unwrap();
    let copies = vec![log[fix]; 11];
    log.splice(fix + 1..fix + 1, copies); // 12 fixes in one frame; the ports hold 4
    let (summary, output) = replay(&log, &scenario).unwrap();
    assert_eq!(summary.counts.measurements_dropped, 8);
    assert_eq!(
        last_value(&output, "replay_measurements_dropped").to_bits(),
        8.0_f64.to_bits()
    );
}

#[test]
fn the_output_has_each_estimates_sigma_beside_it_and_a_row_per_second() {
    let scenario = scenario();
    let (summary, output) = replay(&records(&scenario, 3.0), &scenario).unwrap();
    assert_eq!(summary.frames, 1500);
    let header: Vec<&str> = output.lines().next().unwrap().split(',').collect();
    for name in [
        "position",
        "velocity",
        "gyro_bias",
        "accel_bias",
        "star_installation",
        "gyro_scale_factor",
        "accel_scale_factor",
    ] {
        let estimate = header
            .iter()
            .position(|c| c.starts_with(&format!("{name}_x")));
        let sigma = header
            .iter()
            .position(|c| c.starts_with(&format!("{name}_sigma_x")));
        assert_eq!(sigma.unwrap(), estimate.unwrap() + 3, "{name}");
        let sigma_column = header[sigma.unwrap()];
        let value = last_value(&output, sigma_column);
        assert!(value.is_finite() && value > 0.0, "{sigma_column} = {value}");
    }
    assert_eq!(output.lines().count(), 1 + 3); // header + one row per second
}

/// One edit of a log, at a position given as a fraction (per mille) of its length.
#[derive(Debug, Clone, Copy)]
enum Edit {
    /// The first IMU record at or after the position is lost.
    DropImu(usize),
    /// The record at the position is written twice.
    Duplicate(usize),
    /// Every record from the position on is later by this many frame periods.
    Jump(usize, u32),
}

fn edit_strategy() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (1..1000_usize).prop_map(Edit::DropImu),
        (1..1000_usize).prop_map(Edit::Duplicate),
        ((1..1000_usize), (1..200_u32)).prop_map(|(at, frames)| Edit::Jump(at, frames)),
    ]
}

fn apply(log: &mut Vec<LogRecord>, edit: Edit, period_s: f64) {
    let at = |per_mille: usize, length: usize| (per_mille * length / 1000).max(1);
    match edit {
        Edit::DropImu(position) => {
            let from = at(position, log.len());
            if let Some(offset) = log[from..].iter().position(is_imu) {
                log.remove(from + offset);
            }
        }
        Edit::Duplicate(position) => {
            let index = at(position, log.len()).min(log.len() - 1);
            log.insert(index + 1, log[index]);
        }
        Edit::Jump(position, frames) => {
            let from = at(position, log.len());
            for record in &mut log[from..] {
                *record = sensor_log::shifted(record, f64::from(frames) * period_s);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Whatever the gaps, duplicates and jumps: navigation time at every frame with an IMU
    /// sample is that sample's time tag; every IMU record is run or counted as dropped; every
    /// measurement is fused, counted by the flight software, still queued, or counted as
    /// dropped by the assembler.
    #[test]
    fn every_sample_is_placed_by_its_time_tag_and_every_measurement_accounted_for(
        edits in prop::collection::vec(edit_strategy(), 0..8)
    ) {
        let scenario = scenario();
        let period_s = scenario.imu.frame_period_s();
        let mut log = records(&scenario, 4.0);
        for edit in &edits {
            apply(&mut log, *edit, period_s);
        }
        let setup = nav_sim::setup::fsw::replay_setup(&scenario).unwrap();
        let mut computer = NavigationComputer::new(setup.config(), setup.initial).unwrap();
        let mut assembler = FrameAssembler::new(setup.frame_grid()).unwrap();
        let mut frames_with_imu = 0_u32;
        let mut fusions = 0_u32;
        let mut run_ready = |assembler: &mut FrameAssembler| -> Result<(), TestCaseError> {
            while let Some(mut ports) = assembler.next_frame() {
                let imu_time_s = ports.imu.0.map(|sample| sample.time_s);
                let telemetry = ports.run(&mut computer);
                if let Some(time_s) = imu_time_s {
                    frames_with_imu += 1;
                    prop_assert!(
                        (telemetry.time_s - time_s).abs() < 1e-6,
                        "navigation time {} s, IMU time tag {} s", telemetry.time_s, time_s
                    );
                }
                fusions += u32::from(matches!(
                    telemetry.fusion,
                    FrameFusion::StarAccepted
                        | FrameFusion::StarRejected
                        | FrameFusion::GnssAccepted
                        | FrameFusion::GnssRejected
                ));
            }
            Ok(())
        };
        for record in &log {
            assembler.push(record).unwrap();
            run_ready(&mut assembler)?;
        }
        assembler.finish();
        run_ready(&mut assembler)?;
        let counts = assembler.counts();
        let imu_records = u32::try_from(log.iter().filter(|r| is_imu(r)).count()).unwrap();
        let measurements = u32::try_from(log.len()).unwrap() - imu_records;
        prop_assert_eq!(frames_with_imu + counts.imu_records_dropped, imu_records);
        prop_assert_eq!(counts.frames, frames_with_imu + counts.frames_without_imu);
        prop_assert_eq!(
            counts.measurements_delivered + counts.measurements_dropped,
            measurements
        );
        let h = computer.health();
        let counted = h.measurement_stale
            + h.measurement_future
            + h.measurement_overflow
            + h.star_non_finite
            + h.star_not_unit
            + h.gnss_non_finite;
        let queued = u32::try_from(computer.queued_measurements()).unwrap();
        prop_assert_eq!(fusions + counted + queued, counts.measurements_delivered, "{:?}", h);
    }
}

/// A log replayed with a scenario whose launch epoch is an hour off has every GNSS fix an
/// hour from its arrival: refused naming the line and the offset, instead of every fix
/// dropped and the replay "succeeding". One bad time tag among the first fixes is the
/// receiver's and is replayed (dropped by the flight software as it would be in flight).
#[test]
fn a_log_from_another_launch_epoch_is_refused_and_one_bad_tag_is_not() {
    let scenario = scenario();
    let log = records(&scenario, 2.0);
    let mut hour_later = scenario.clone();
    hour_later.launch_site.epoch_utc = "2024-02-26T05:00:00Z".to_string();
    hour_later.validate().unwrap();
    let error = replay(&log, &hour_later).unwrap_err();
    assert!(error.contains("another launch epoch"), "{error}");
    assert!(error.contains("3600.0"), "{error}");
    let first_fix = log
        .iter()
        .position(|r| matches!(r, LogRecord::Gnss(_)))
        .unwrap();
    assert!(
        error.contains(&format!("line {}", first_fix + 2)),
        "{error}"
    );

    let mut glitch = log.clone();
    if let Some(LogRecord::Gnss(fix)) = glitch.get_mut(first_fix) {
        fix.gps_week += 1;
    }
    let (summary, _) = replay(&glitch, &scenario).unwrap();
    assert_eq!(summary.health.measurement_future, 1, "{}", summary.text());
}

/// A two-head flight's log holds both heads' measurements, each naming its head, and replays
/// through the flight software as the flight did: head 0 blind from 15 s to 25 s, its
/// installation block handed to head 1 and back, nothing counted as an unknown head.
#[test]
fn a_two_head_log_replays_both_heads_and_their_hand_overs() {
    let mut scenario = scenario();
    scenario.star_sensor.additional_heads = vec![scenario.star_sensor.head_across()];
    scenario.star_sensor.outages = vec![[15.0, 10.0]];
    scenario.filter.star_pairs_before_hand_over = 20;
    scenario.validate().unwrap();
    let records = records(&scenario, 40.0);
    let heads = |head: u8| {
        records
            .iter()
            .filter(|r| matches!(r, LogRecord::Star(star) if star.head == head))
            .count()
    };
    // 10 Hz for 40 s, head 0 silent for 10 of them.
    assert_eq!((heads(0), heads(1)), (300, 400));
    let read: Vec<LogRecord> = sensor_log::SensorLogReader::new(csv(&records).as_slice())
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    assert_eq!(read.len(), records.len());
    assert!(read
        .iter()
        .zip(&records)
        .all(|(a, b)| a.encode() == b.encode()));
    let (summary, _) = replay(&records, &scenario).unwrap();
    let health = summary.health;
    assert_eq!(health.star_head_handovers, 2, "{}", summary.text());
    assert_eq!(health.star_unknown_head, 0);
    assert_eq!(health.star_outages, 1);
    assert_eq!(health.star_declared_faulty, 0);
}

/// The short test flight with a second head (the flight software takes two heads).
fn two_head_scenario() -> Scenario {
    let mut two_heads = scenario();
    two_heads.star_sensor.additional_heads = vec![two_heads.star_sensor.head_across()];
    two_heads.validate().unwrap();
    two_heads
}

/// A one-head log (every star row head 0's) on a two-head scenario is refused, not replayed
/// with the second head missing; on its own scenario it replays.
#[test]
fn a_one_head_log_on_a_two_head_scenario_is_refused() {
    let one_head = scenario();
    let one_head_log = records(&one_head, 2.0);
    let star_rows = one_head_log
        .iter()
        .filter(|r| matches!(r, LogRecord::Star(_)))
        .count();
    // 10 Hz for 2 s.
    assert!((19..=21).contains(&star_rows), "{star_rows}");
    let error = replay(&one_head_log, &two_head_scenario()).unwrap_err();
    let expected = format!("the log has {star_rows} star rows, all of head 0 (`star_head` = 0)");
    assert!(error.contains(&expected), "{error}");
    assert!(error.contains("two star heads"), "{error}");
    replay(&one_head_log, &one_head).unwrap();
}

/// A two-head log without its `star_head` column (which would read every star row as head
/// 0's) is refused on a two-head scenario, the message naming the column; a one-head scenario
/// still replays it (the layout before the column).
#[test]
fn a_two_head_log_without_its_head_column_is_refused() {
    let two_heads = two_head_scenario();
    let two_head_log = csv(&records(&two_heads, 2.0));
    let without_column: String = String::from_utf8(two_head_log)
        .unwrap()
        .lines()
        .map(|line| line.rsplit_once(',').unwrap().0.to_string() + "\n")
        .collect();
    let mut output = Vec::new();
    let error = log_replay::replay(without_column.as_bytes(), &two_heads, &mut output)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("line 1: the log has no `star_head` column"),
        "{error}"
    );
    log_replay::replay(without_column.as_bytes(), &scenario(), &mut Vec::new()).unwrap();
}
