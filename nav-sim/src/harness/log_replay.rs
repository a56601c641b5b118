//! `nav-sim replay`: a recorded sensor log (CSV, `docs/guide/replay-format.md`) fed through the
//! flight software frame by frame by nav-fsw's `FrameAssembler` (the one the QEMU replay
//! firmware uses), which places every record by its own time: a missing IMU sample is a frame
//! without one, never a shift of navigation time. The output CSV has one row per second of
//! navigation time and one at the end: the estimates with their filter 1σ (those of the
//! optional state blocks the filter flies included), the flight software's health and
//! command counters and the assembler's counts, so nothing in the log goes unseen.

use std::io::{Read, Write};

use nav_core::state::{ATTITUDE, POSITION, VELOCITY};
use nav_fsw::replay::{output_words, AssemblyCounts, FrameAssembler, OUTPUT_WORDS};
use nav_fsw::scheduler::NavigationComputer;
use nav_fsw::telemetry::{FrameTelemetry, GNSS_ERROR_FIELD_NAMES, IMU_ERROR_FIELD_NAMES};

use crate::logs::sensor_log::SensorLogReader;
use crate::scenario::Scenario;

/// What a replay did.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplaySummary {
    /// Frames run.
    pub frames: u64,
    /// What the frame assembler did with the log's records.
    pub counts: AssemblyCounts,
    /// The flight software's health counters at the end.
    pub health: nav_fsw::health::HealthCounters,
}

impl ReplaySummary {
    /// One paragraph for people: frames, what the assembler dropped, the non-zero health
    /// counters.
    pub fn text(&self) -> String {
        let c = &self.counts;
        let counters: Vec<String> = self
            .health
            .named()
            .iter()
            .filter(|(_, value)| *value > 0)
            .map(|(name, value)| format!("{name} {value}"))
            .collect();
        format!(
            "{} frames ({} without an IMU sample); IMU records dropped (duplicate or late): {}; \
             measurements delivered {}, dropped (more than a frame's ports hold) {}\n\
             flight software counters: {}",
            self.frames,
            c.frames_without_imu,
            c.imu_records_dropped,
            c.measurements_delivered,
            c.measurements_dropped,
            if counters.is_empty() {
                "all zero".to_owned()
            } else {
                counters.join(", ")
            }
        )
    }
}

/// A replay failure.
pub type ReplayFailure = Box<dyn std::error::Error>;

const AXES: [&str; 3] = ["x", "y", "z"];

/// The output CSV's header.
pub fn output_columns(computer: &NavigationComputer) -> Vec<String> {
    let mut columns = vec!["time_s".to_owned()];
    columns.extend(["w", "x", "y", "z"].map(|c| format!("attitude_{c}")));
    columns.extend(AXES.map(|a| format!("attitude_sigma_{a}_rad")));
    for (name, unit) in [("position", "m"), ("velocity", "mps")] {
        columns.extend(AXES.map(|a| format!("{name}_{a}_{unit}")));
        columns.extend(AXES.map(|a| format!("{name}_sigma_{a}_{unit}")));
    }
    for (block, _) in computer.calibration_table().entries() {
        columns.extend(AXES.map(|a| format!("{}_{a}", block.name())));
        columns.extend(AXES.map(|a| format!("{}_sigma_{a}", block.name())));
    }
    // Only the blocks the filter flies: a flight without them has the columns it always had.
    let optional = computer.optional_states();
    if optional.gnss_error.is_some() {
        columns.extend(GNSS_ERROR_FIELD_NAMES.map(str::to_owned));
    }
    if optional.imu_error.is_some() {
        columns.extend(IMU_ERROR_FIELD_NAMES.map(str::to_owned));
    }
    columns.extend(computer.health().named().map(|(name, _)| name.to_owned()));
    let commands = nav_fsw::scheduler::CommandCounters::default();
    columns.extend(commands.named().map(|(name, _)| name.to_owned()));
    columns.extend(
        [
            "replay_frames_without_imu",
            "replay_imu_records_dropped",
            "replay_measurements_delivered",
            "replay_measurements_dropped",
        ]
        .map(str::to_owned),
    );
    columns
}

/// One output row (the columns of [`output_columns`]).
fn output_row(
    telemetry: &FrameTelemetry,
    computer: &NavigationComputer,
    counts: &AssemblyCounts,
) -> String {
    let sigma = computer.filter().standard_deviations();
    let block_sigma = |index: usize, scale: f64| -> Vec<f64> {
        (0..3).map(|axis| scale * sigma[index + axis]).collect()
    };
    let mut values: Vec<String> = vec![telemetry.time_s.to_string()];
    let mut put = |numbers: &[f64]| values.extend(numbers.iter().map(f64::to_string));
    put(&telemetry.attitude_wxyz);
    // The attitude states are half-angles: the rotation's 1σ is twice theirs.
    put(&block_sigma(ATTITUDE.index(), 2.0));
    put(&telemetry.position_m);
    put(&block_sigma(POSITION.index(), 1.0));
    put(&telemetry.velocity_mps);
    put(&block_sigma(VELOCITY.index(), 1.0));
    for (_, entry) in computer.calibration_table().entries() {
        put(&entry.value);
        put(&entry.sigma());
    }
    let optional = computer.optional_states();
    if let Some(gnss_error) = optional.gnss_error {
        put(&gnss_error.values());
    }
    if let Some(imu_error) = optional.imu_error {
        put(&imu_error.values());
    }
    let counters = computer.health().named().map(|(_, value)| value);
    let commands = telemetry.commands.named().map(|(_, value)| value);
    let replay = [
        counts.frames_without_imu,
        counts.imu_records_dropped,
        counts.measurements_delivered,
        counts.measurements_dropped,
    ];
    let all_counters = counters.iter().chain(&commands).chain(&replay);
    values.extend(all_counters.map(u32::to_string));
    values.join(",")
}

/// How many of the log's first GNSS fixes [`EpochCheck`] looks at.
const EPOCH_CHECK_FIXES: usize = 10;

/// Whether the log's GNSS time tags agree with the scenario's launch epoch: a fix's time of
/// validity (GPS week and seconds, turned into navigation time with the scenario's epoch)
/// lies at most `timing.max_latency_s` before its arrival and at most
/// `timing.future_tolerance_s` after it. A log recorded with another epoch has every fix off
/// by the same amount, and the flight software would drop each one as stale or from the
/// future: if none of the first [`EPOCH_CHECK_FIXES`] fixes agrees, the replay is refused.
/// One glitch among them is the receiver's, not the epoch's.
struct EpochCheck {
    sensor_frames: nav_fsw::sensor_frames::SensorFrames,
    window_s: (f64, f64),
    /// The first disagreeing fix: its log line and arrival − validity (s); `None` when none
    /// disagreed or a fix agreed.
    first_disagreement: Option<(u64, f64)>,
    fixes_seen: usize,
    settled: bool,
}

impl EpochCheck {
    fn new(config: &nav_fsw::config::FswConfig) -> Self {
        Self {
            sensor_frames: config.sensor_frames,
            window_s: (
                -config.timing.future_tolerance_s,
                config.timing.max_latency_s,
            ),
            first_disagreement: None,
            fixes_seen: 0,
            settled: false,
        }
    }

    /// Looks at one record (GNSS fixes only, until one agrees or the count is reached).
    fn observe(
        &mut self,
        record: &nav_fsw::log_record::LogRecord,
        line: u64,
    ) -> Result<(), ReplayFailure> {
        let nav_fsw::log_record::LogRecord::Gnss(fix) = record else {
            return Ok(());
        };
        if self.settled {
            return Ok(());
        }
        let validity_s = self
            .sensor_frames
            .navigation_time_s(fix.gps_week, fix.gps_seconds_of_week)
            .unwrap_or(f64::NAN);
        let age_s = fix.arrival_time_s - validity_s;
        if age_s >= self.window_s.0 && age_s <= self.window_s.1 {
            self.settled = true;
            self.first_disagreement = None;
            return Ok(());
        }
        self.first_disagreement.get_or_insert((line, age_s));
        self.fixes_seen += 1;
        if self.fixes_seen >= EPOCH_CHECK_FIXES {
            return self.verdict();
        }
        Ok(())
    }

    /// The refusal, if every fix seen disagreed.
    fn verdict(&mut self) -> Result<(), ReplayFailure> {
        self.settled = true;
        let Some((line, age_s)) = self.first_disagreement else {
            return Ok(());
        };
        Err(format!(
            "line {line}: the GNSS fix arrives {age_s:.3} s after its time of validity by the \
             scenario's launch epoch (allowed: {:.3} to {:.3} s), as does every one of the \
             log's first {} fixes: the log was recorded with another launch epoch (replay it \
             with its scenario, --scenario FILE, whose [launch_site] epoch is the recording's)",
            self.window_s.0, self.window_s.1, self.fixes_seen
        )
        .into())
    }
}

/// Whether the log carries the star heads the scenario's flight software takes: with a
/// second head configured (`[[star_sensor.additional_heads]]`, `[filter] star_second_head`),
/// a log without the `star_head` column (every star row read as head 0's) and a log with
/// star rows of head 0 only are refused, rather than replayed with the second head's
/// measurements missing or taken for the first's.
struct HeadCheck {
    /// The flight software takes a second head.
    two_heads: bool,
    /// Star rows per head (0, 1 and any other).
    star_rows: [u64; 3],
}

impl HeadCheck {
    fn new<R: Read>(
        config: &nav_fsw::config::FswConfig,
        reader: &SensorLogReader<R>,
    ) -> Result<Self, ReplayFailure> {
        let two_heads = config.star.second_head.is_some();
        if two_heads && !reader.has_head_column() {
            return Err(
                "line 1: the log has no `star_head` column, so every star row would be \
                 read as head 0's, but the scenario flies two star heads \
                 ([[star_sensor.additional_heads]] with [filter] star_second_head = true): \
                 add the `star_head` column (docs/guide/replay-format.md) or replay with a one-head \
                 scenario"
                    .into(),
            );
        }
        Ok(Self {
            two_heads,
            star_rows: [0; 3],
        })
    }

    fn observe(&mut self, record: &nav_fsw::log_record::LogRecord) {
        if let nav_fsw::log_record::LogRecord::Star(star) = record {
            let slot = usize::from(star.head).min(2);
            self.star_rows[slot] += 1;
        }
    }

    /// The refusal of a one-head log on a two-head scenario.
    fn verdict(&self) -> Result<(), ReplayFailure> {
        let [head_0, head_1, _] = self.star_rows;
        if self.two_heads && head_0 > 0 && head_1 == 0 {
            return Err(format!(
                "the log has {head_0} star rows, all of head 0 (`star_head` = 0), but the \
                 scenario flies two star heads ([[star_sensor.additional_heads]] with [filter] \
                 star_second_head = true): replay a one-head log with a one-head scenario \
                 (or [filter] star_second_head = false)"
            )
            .into());
        }
        Ok(())
    }
}

/// Replays `log` through the flight software set up by `scenario` and writes the output CSV
/// (module docs) to `output`.
///
/// # Errors
/// A log error naming its line (including a log at another IMU rate, on another time base or
/// with a jump the replay does not bridge, `nav_fsw::replay::FrameAssemblyError`, and a log
/// whose GNSS time tags disagree with the scenario's launch epoch: none of its first 10 fixes
/// within the latency window, and a log without the star heads the scenario flies, `HeadCheck`),
/// a refused configuration, or an I/O error of `output`.
pub fn replay<R: Read, W: Write>(
    log: R,
    scenario: &Scenario,
    output: W,
) -> Result<ReplaySummary, ReplayFailure> {
    replay_with_records(log, scenario, output, None)
}

/// What receives each frame's output record (nav-fsw `replay::output_words`).
pub type RecordSink<'a> = &'a mut dyn FnMut(&[u64; OUTPUT_WORDS]) -> Result<(), ReplayFailure>;

/// [`replay`], handing every frame's output record to `records` as well (the telemetry
/// packets and the output-record CSV of `nav-sim replay --packets`, `--records`).
///
/// # Errors
/// As [`replay`], and an error of `records`.
pub fn replay_with_records<R: Read, W: Write>(
    log: R,
    scenario: &Scenario,
    output: W,
    mut records: Option<RecordSink<'_>>,
) -> Result<ReplaySummary, ReplayFailure> {
    let setup = crate::setup::fsw::replay_setup_without_commands(scenario)?;
    let mut computer = NavigationComputer::new(setup.config(), setup.initial)
        .map_err(|error| format!("flight software configuration refused: {error}"))?;
    let mut assembler = FrameAssembler::new(setup.frame_grid())?;
    let mut reader = SensorLogReader::new(log)?;
    let mut heads = HeadCheck::new(&setup.config(), &reader)?;
    let mut output = std::io::BufWriter::new(output);
    writeln!(output, "{}", output_columns(&computer).join(","))?;
    let frames_per_row = (1.0 / setup.config().imu.period_s).round().max(1.0) as u64;
    let mut frames = 0_u64;
    let mut last_row: Option<String> = None;
    let mut run_ready =
        |assembler: &mut FrameAssembler, output: &mut dyn Write| -> Result<(), ReplayFailure> {
            while let Some(mut ports) = assembler.next_frame() {
                let telemetry = ports.run(&mut computer);
                frames += 1;
                if let Some(records) = records.as_mut() {
                    records(&output_words(&telemetry, &computer, &assembler.counts()))?;
                }
                let row = output_row(&telemetry, &computer, &assembler.counts());
                if frames % frames_per_row == 0 {
                    writeln!(output, "{row}")?;
                    last_row = None;
                } else {
                    last_row = Some(row);
                }
            }
            Ok(())
        };
    let mut epoch = EpochCheck::new(&setup.config());
    while let Some(record) = reader.next() {
        let line = reader.line();
        let record = record?;
        epoch.observe(&record, line)?;
        heads.observe(&record);
        assembler
            .push(&record)
            .map_err(|error| format!("line {line}: {error}"))?;
        run_ready(&mut assembler, &mut output)?;
    }
    epoch.verdict()?;
    heads.verdict()?;
    assembler.finish();
    run_ready(&mut assembler, &mut output)?;
    if let Some(row) = last_row {
        writeln!(output, "{row}")?;
    }
    output.flush()?;
    if frames == 0 {
        return Err("the log has no IMU record: nothing to replay".into());
    }
    Ok(ReplaySummary {
        frames,
        counts: assembler.counts(),
        health: *computer.health(),
    })
}
