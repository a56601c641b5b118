//! The replay log: the simulator's sensor-event stream as a CSV file (and its compact binary
//! form for the QEMU firmware), so any scenario can be replayed through the flight code
//! elsewhere (`nav-sim replay`), and recorded data can be fed in. Full specification:
//! `docs/guide/replay-format.md`.
//!
//! ## CSV layout
//! One header line, then one row per sensor event in delivery order (non-decreasing
//! `arrival_time_s`; rows with equal arrival times keep their file order). Every row has all
//! [`COLUMNS`]; the `kind` column says which are filled, the others are empty:
//!
//! | column | imu | star | gnss |
//! |---|---|---|---|
//! | `kind` | `imu` | `star` | `gnss` |
//! | `arrival_time_s` | frame end | arrival | arrival (time of validity + latency) |
//! | `time_tag_s` | = arrival | time of validity | |
//! | `sequence` | frame counter (u64) | | |
//! | `interval_s` | sampling interval | | |
//! | `delta_angle_{x,y,z}_rad` | Δθ, body axes | | |
//! | `delta_velocity_{x,y,z}_mps` | Δv, body axes | | |
//! | `attitude_{w,x,y,z}` | | `q_gs`, sensor → GCRF (Hamilton, scalar first) | |
//! | `position_ecef_{x,y,z}_m` | | | ECEF (ITRF) WGS-84 position |
//! | `velocity_ecef_{x,y,z}_mps` | | | ECEF velocity (all three, or all three empty for a position-only receiver) |
//! | `gps_week` | | | time of validity: GPS week (full count) |
//! | `gps_seconds_of_week` | | | time of validity: GPS seconds of week |
//! | `star_head` | | the tracker head (0 = `[star_sensor]`, 1 = its first additional head; u8) | |
//!
//! Times other than the GNSS tags are navigation time (s since the launch epoch). A log of the
//! earlier layout (18 or 21 columns: star relative to launch-inertial, GNSS tagged in
//! navigation time) is refused with [`SensorLogError::OldLayout`]; a log of the 23 columns
//! before `star_head` is read with every star row of head 0.
//!
//! Floats are written in the shortest form that parses back to the same `f64` (ryu), so a
//! file round-trips bit for bit; NaN and infinity are refused on writing and on reading. The
//! reader never panics: every error names the line (the header is line 1) and the column.
//!
//! The binary form is nav-fsw's [`nav_fsw::log_record`]: a 16-byte header and one 80-byte
//! record per row, same order, same bits.
//!
//! ## Star-tracker heads
//! A log holds the star measurements of the heads a tracker port carries (nav-fsw
//! `MAX_STAR_HEADS`: head 0, `[star_sensor]`, and head 1, its first additional head), each row
//! naming its head, as nav-fsw's binary record does (word 6). A simulation's further heads are
//! held back by [`crate::logs::star_heads::FlightStarHeads`] and counted
//! ([`RecordedLog::withheld_star_measurements`]).

mod binary;
mod reader;
#[cfg(test)]
mod tests;
mod writer;

pub use binary::{convert_csv_to_binary, read_binary};
pub use reader::{read_events, SensorLogReader};
pub use writer::{record_simulation, RecordedLog, SensorLogWriter};

use nalgebra::{Quaternion, Vector3};
use nav_fsw::log_record::{GnssRecord, ImuRecord, LogRecord, LogRecordError, StarRecord};

use nav_fsw::sensor_frames::SensorFrames;

use crate::logs::star_heads::FlightStarHeads;
use crate::world::sensors::SensorEvent;
use crate::world::simulation::{Simulation, SimulationError};

/// The CSV header, in column order.
pub const COLUMNS: [&str; 24] = [
    "kind",
    "arrival_time_s",
    "time_tag_s",
    "sequence",
    "interval_s",
    "delta_angle_x_rad",
    "delta_angle_y_rad",
    "delta_angle_z_rad",
    "delta_velocity_x_mps",
    "delta_velocity_y_mps",
    "delta_velocity_z_mps",
    "attitude_w",
    "attitude_x",
    "attitude_y",
    "attitude_z",
    "position_ecef_x_m",
    "position_ecef_y_m",
    "position_ecef_z_m",
    "velocity_ecef_x_mps",
    "velocity_ecef_y_mps",
    "velocity_ecef_z_mps",
    "gps_week",
    "gps_seconds_of_week",
    "star_head",
];

/// Column count of the layout before the `star_head` column: read, its star rows head 0.
const ONE_HEAD_LAYOUT_COLUMNS: usize = 23;

/// Column counts of the earlier layouts (before the GPS-time columns; before the velocity).
const OLD_LAYOUT_COLUMNS: [usize; 2] = [18, 21];

/// Column indices into [`COLUMNS`].
mod column {
    pub const KIND: usize = 0;
    pub const ARRIVAL_TIME: usize = 1;
    pub const TIME_TAG: usize = 2;
    pub const SEQUENCE: usize = 3;
    pub const INTERVAL: usize = 4;
    pub const DELTA_ANGLE: usize = 5;
    pub const DELTA_VELOCITY: usize = 8;
    pub const ATTITUDE: usize = 11;
    pub const POSITION: usize = 15;
    pub const VELOCITY: usize = 18;
    pub const GPS_WEEK: usize = 21;
    pub const GPS_SECONDS: usize = 22;
    pub const STAR_HEAD: usize = 23;
}

/// Float columns of an IMU row, in the order of [`float_values`].
const IMU_FLOAT_COLUMNS: [usize; 9] = [
    column::ARRIVAL_TIME,
    column::TIME_TAG,
    column::INTERVAL,
    column::DELTA_ANGLE,
    column::DELTA_ANGLE + 1,
    column::DELTA_ANGLE + 2,
    column::DELTA_VELOCITY,
    column::DELTA_VELOCITY + 1,
    column::DELTA_VELOCITY + 2,
];
/// Float columns of a star row.
const STAR_FLOAT_COLUMNS: [usize; 6] = [
    column::ARRIVAL_TIME,
    column::TIME_TAG,
    column::ATTITUDE,
    column::ATTITUDE + 1,
    column::ATTITUDE + 2,
    column::ATTITUDE + 3,
];
/// Float columns of a GNSS row.
const GNSS_FLOAT_COLUMNS: [usize; 5] = [
    column::ARRIVAL_TIME,
    column::GPS_SECONDS,
    column::POSITION,
    column::POSITION + 1,
    column::POSITION + 2,
];

/// The three kinds of row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Imu,
    Star,
    Gnss,
}

impl Kind {
    fn of(record: &LogRecord) -> Self {
        match record {
            LogRecord::Imu(_) => Self::Imu,
            LogRecord::Star(_) => Self::Star,
            LogRecord::Gnss(_) => Self::Gnss,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Self::Imu => "imu",
            Self::Star => "star",
            Self::Gnss => "gnss",
        }
    }

    fn parse(text: &str) -> Option<Self> {
        [Self::Imu, Self::Star, Self::Gnss]
            .into_iter()
            .find(|kind| kind.name() == text)
    }

    fn float_columns(self) -> &'static [usize] {
        match self {
            Self::Imu => &IMU_FLOAT_COLUMNS,
            Self::Star => &STAR_FLOAT_COLUMNS,
            Self::Gnss => &GNSS_FLOAT_COLUMNS,
        }
    }

    /// Whether a column is filled in this kind's rows.
    fn uses(self, column: usize) -> bool {
        column == column::KIND
            || (self == Self::Imu && column == column::SEQUENCE)
            || (self == Self::Gnss && column == column::GPS_WEEK)
            || (self == Self::Star && column == column::STAR_HEAD)
            || (self == Self::Gnss && (column::VELOCITY..column::VELOCITY + 3).contains(&column))
            || self.float_columns().contains(&column)
    }
}

/// A record's float values in the order of its kind's float columns.
fn float_values(record: &LogRecord) -> Vec<f64> {
    match record {
        LogRecord::Imu(imu) => [imu.time_s, imu.time_s, imu.interval_s]
            .into_iter()
            .chain(imu.delta_angle_rad)
            .chain(imu.delta_velocity_mps)
            .collect(),
        LogRecord::Star(star) => [star.arrival_time_s, star.time_tag_s]
            .into_iter()
            .chain(star.attitude_wxyz)
            .collect(),
        LogRecord::Gnss(gnss) => [gnss.arrival_time_s, gnss.gps_seconds_of_week]
            .into_iter()
            .chain(gnss.position_ecef_m)
            .collect(),
    }
}

/// Why a sensor log could not be written, read or converted.
#[derive(Debug, thiserror::Error)]
pub enum SensorLogError {
    /// The underlying file or stream failed.
    #[error("sensor log I/O: {0}")]
    Io(#[from] std::io::Error),
    /// The CSV itself is malformed (e.g. a row with the wrong number of fields).
    #[error("line {line}: {source}")]
    Csv {
        /// Line of the error (1 = header; 0 if unknown).
        line: u64,
        /// The csv crate's error.
        source: csv::Error,
    },
    /// The header is not [`COLUMNS`].
    #[error("line 1, column {position}: header is `{found}`, expected `{expected}`")]
    Header {
        /// 1-based column position.
        position: usize,
        /// The expected column name.
        expected: &'static str,
        /// What the file has there (empty if the header is short).
        found: String,
    },
    /// The header is an earlier layout's.
    #[error(
        "line 1: a log of the earlier {columns}-column layout (star attitude relative to the \
         launch-inertial frame, GNSS tagged in navigation time); this layout has the star \
         tracker relative to GCRF and GNSS tagged in GPS week and seconds of week \
         (docs/guide/replay-format.md): regenerate the log with `nav-sim log`"
    )]
    OldLayout {
        /// The old file's column count.
        columns: usize,
    },
    /// The `kind` column is not `imu`, `star` or `gnss`.
    #[error("line {line}, column `kind`: unknown kind `{value}` (expected imu, star or gnss)")]
    UnknownKind {
        /// Line number.
        line: u64,
        /// The cell.
        value: String,
    },
    /// A column this row's kind needs is empty.
    #[error("line {line}, column `{column}`: missing value (needed in `{kind}` rows)")]
    Missing {
        /// Line number.
        line: u64,
        /// Column name.
        column: &'static str,
        /// Row kind.
        kind: &'static str,
    },
    /// A column this row's kind does not use is filled.
    #[error("line {line}, column `{column}`: `{value}` must be empty in `{kind}` rows")]
    NotApplicable {
        /// Line number.
        line: u64,
        /// Column name.
        column: &'static str,
        /// Row kind.
        kind: &'static str,
        /// The cell.
        value: String,
    },
    /// A cell does not parse as its column's type.
    #[error("line {line}, column `{column}`: `{value}` is not {expected}")]
    Invalid {
        /// Line number.
        line: u64,
        /// Column name.
        column: &'static str,
        /// The cell.
        value: String,
        /// What was expected ("a number", "an unsigned 64-bit integer").
        expected: &'static str,
    },
    /// A float is NaN or infinite (reading or writing).
    #[error("line {line}, column `{column}`: {value} is not finite")]
    NonFinite {
        /// Line number (as it is or would be in the file).
        line: u64,
        /// Column name.
        column: &'static str,
        /// The value.
        value: f64,
    },
    /// An IMU row whose `time_tag_s` differs from its `arrival_time_s`.
    #[error(
        "line {line}, column `time_tag_s`: an imu row's time tag must equal its arrival time \
         ({arrival_time_s} s), found {time_tag_s} s"
    )]
    ImuTimeMismatch {
        /// Line number.
        line: u64,
        /// The row's arrival time (s).
        arrival_time_s: f64,
        /// The row's time tag (s).
        time_tag_s: f64,
    },
    /// A row arrives before the previous one (reading or writing).
    #[error(
        "line {line}, column `arrival_time_s`: {arrival_time_s} s is earlier than the previous \
         row's {previous_s} s (rows must be in delivery order)"
    )]
    OutOfOrder {
        /// Line number.
        line: u64,
        /// The row's arrival time (s).
        arrival_time_s: f64,
        /// The previous row's arrival time (s).
        previous_s: f64,
    },
    /// A star row arrives later than its time tag, which [`SensorEvent::Star`] cannot express.
    #[error(
        "line {line}: star arrival {arrival_time_s} s differs from its time tag {time_tag_s} s; \
         the simulator's events have no star latency (read it as LogRecord instead)"
    )]
    StarLatency {
        /// Line number.
        line: u64,
        /// Arrival time (s).
        arrival_time_s: f64,
        /// Time tag (s).
        time_tag_s: f64,
    },
    /// A binary record (0-based index; `None`: the file header) is invalid.
    #[error("binary log {}: {error}", match record { Some(index) => format!("record {index}"), None => "header".to_string() })]
    Binary {
        /// Index of the record, `None` for the header.
        record: Option<u64>,
        /// nav-fsw's decoding error.
        error: LogRecordError,
    },
    /// The simulation producing the events failed.
    #[error(transparent)]
    Simulation(#[from] SimulationError),
}

/// The log record of a simulator event (exact: every field is copied bit for bit), a star
/// event's head with it.
pub fn record_of(event: &SensorEvent) -> LogRecord {
    match event {
        SensorEvent::Imu {
            frame_index,
            time_s,
            interval_s,
            delta_angle_rad,
            delta_velocity_mps,
        } => LogRecord::Imu(ImuRecord {
            sequence: *frame_index,
            time_s: *time_s,
            interval_s: *interval_s,
            delta_angle_rad: (*delta_angle_rad).into(),
            delta_velocity_mps: (*delta_velocity_mps).into(),
        }),
        SensorEvent::Star {
            time_tag_s,
            attitude_q_gs,
            head,
        } => LogRecord::Star(StarRecord {
            arrival_time_s: *time_tag_s,
            time_tag_s: *time_tag_s,
            attitude_wxyz: [
                attitude_q_gs.w,
                attitude_q_gs.i,
                attitude_q_gs.j,
                attitude_q_gs.k,
            ],
            // The scenario's validation bounds the heads far below 256.
            head: u8::try_from(*head).unwrap_or(u8::MAX),
        }),
        SensorEvent::Gnss {
            gps_week,
            gps_seconds_of_week,
            delivery_time_s,
            position_ecef_m,
            velocity_ecef_mps,
            ..
        } => LogRecord::Gnss(GnssRecord {
            arrival_time_s: *delivery_time_s,
            gps_week: *gps_week,
            gps_seconds_of_week: *gps_seconds_of_week,
            position_ecef_m: (*position_ecef_m).into(),
            velocity_ecef_mps: velocity_ecef_mps.map(Into::into),
        }),
    }
}

/// The records of the first `frames` frames of `scenario`'s sensor-event stream (fewer if the
/// scenario ends first), in delivery order, with the star measurements of the heads a tracker
/// port carries ([`simulated_log`] also counts the others').
///
/// # Errors
/// [`SimulationError`] from the simulation.
pub fn simulated_records(
    scenario: &crate::scenario::Scenario,
    frames: u64,
) -> Result<Vec<LogRecord>, SimulationError> {
    simulated_log(scenario, frames).map(|(records, _)| records)
}

/// [`simulated_records`] and the number of star measurements of the other heads held back
/// ([`FlightStarHeads`]).
///
/// # Errors
/// [`SimulationError`] from the simulation.
pub fn simulated_log(
    scenario: &crate::scenario::Scenario,
    frames: u64,
) -> Result<(Vec<LogRecord>, u64), SimulationError> {
    let mut simulation = Simulation::new(scenario)?;
    let mut events = Vec::new();
    for _ in 0..frames {
        if simulation.step(&mut events)?.is_none() {
            break;
        }
    }
    let mut heads = FlightStarHeads::port();
    let records = events
        .iter()
        .filter(|event| heads.hands_over(event))
        .map(record_of)
        .collect();
    Ok((records, heads.withheld()))
}

/// `record` with its arrival time and time tag moved by `by_s`: a log whose clock is offset
/// or jumps.
pub fn shifted(record: &LogRecord, by_s: f64) -> LogRecord {
    let mut record = *record;
    match &mut record {
        LogRecord::Imu(imu) => imu.time_s += by_s,
        LogRecord::Star(star) => {
            star.arrival_time_s += by_s;
            star.time_tag_s += by_s;
        }
        LogRecord::Gnss(gnss) => {
            gnss.arrival_time_s += by_s;
            // GPS time `by_s` later: the week and seconds with the carry.
            let at_tag = SensorFrames {
                gcrf_to_launch_inertial_wxyz: [1.0, 0.0, 0.0, 0.0],
                launch_epoch_gps_week: gnss.gps_week,
                launch_epoch_gps_seconds_of_week: gnss.gps_seconds_of_week,
            };
            if let Some((week, seconds)) = at_tag.gps_time(by_s) {
                gnss.gps_week = week;
                gnss.gps_seconds_of_week = seconds;
            }
        }
    }
    record
}

/// The simulator event of a log record (GNSS navigation time from its GPS tag with
/// `frames`; a star record is head 0's), or `None` for a star record whose arrival differs from its time tag (the
/// simulator has no star latency) or a GNSS tag outside the GPS ranges.
pub fn event_of(record: &LogRecord, frames: &SensorFrames) -> Option<SensorEvent> {
    match record {
        LogRecord::Imu(imu) => Some(SensorEvent::Imu {
            frame_index: imu.sequence,
            time_s: imu.time_s,
            interval_s: imu.interval_s,
            delta_angle_rad: Vector3::from(imu.delta_angle_rad),
            delta_velocity_mps: Vector3::from(imu.delta_velocity_mps),
        }),
        LogRecord::Star(star) => {
            let [w, x, y, z] = star.attitude_wxyz;
            (star.arrival_time_s.to_bits() == star.time_tag_s.to_bits()).then_some(
                SensorEvent::Star {
                    head: usize::from(star.head),
                    time_tag_s: star.time_tag_s,
                    attitude_q_gs: Quaternion::new(w, x, y, z),
                },
            )
        }
        LogRecord::Gnss(gnss) => Some(SensorEvent::Gnss {
            time_tag_s: frames
                .navigation_time_s(gnss.gps_week, gnss.gps_seconds_of_week)
                .ok()?,
            gps_week: gnss.gps_week,
            gps_seconds_of_week: gnss.gps_seconds_of_week,
            delivery_time_s: gnss.arrival_time_s,
            position_ecef_m: Vector3::from(gnss.position_ecef_m),
            velocity_ecef_mps: gnss.velocity_ecef_mps.map(Vector3::from),
        }),
    }
}
