//! The replay log: the simulator's sensor-event stream as a CSV file (and its compact binary
//! form for the QEMU firmware), so any scenario can be replayed through the flight code
//! elsewhere (`nav-sim replay`), and recorded data can be fed in. Full specification:
//! `docs/replay-format.md`.
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
//!
//! Times other than the GNSS tags are navigation time (s since the launch epoch). A log of the
//! earlier layout (18 or 21 columns: star relative to launch-inertial, GNSS tagged in
//! navigation time) is refused with [`SensorLogError::OldLayout`].
//!
//! Floats are written in the shortest form that parses back to the same `f64` (ryu), so a
//! file round-trips bit for bit; NaN and infinity are refused on writing and on reading. The
//! reader never panics: every error names the line (the header is line 1) and the column.
//!
//! The binary form is nav-fsw's [`nav_fsw::log_record`]: a 16-byte header and one 80-byte
//! record per row, same order, same bits.

use std::io::{Read, Write};

use nalgebra::{Quaternion, Vector3};
use nav_fsw::log_record::{
    self, GnssRecord, ImuRecord, LogRecord, LogRecordError, StarRecord, HEADER_SIZE, RECORD_SIZE,
};

use nav_fsw::sensor_frames::SensorFrames;

use crate::world::sensors::SensorEvent;
use crate::world::simulation::{Simulation, SimulationError};

/// The CSV header, in column order.
pub const COLUMNS: [&str; 23] = [
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
];

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
         (docs/replay-format.md): regenerate the log with `nav-sim log`"
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

/// The log record of a simulator event (exact: every field is copied bit for bit).
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
        } => LogRecord::Star(StarRecord {
            arrival_time_s: *time_tag_s,
            time_tag_s: *time_tag_s,
            attitude_wxyz: [
                attitude_q_gs.w,
                attitude_q_gs.i,
                attitude_q_gs.j,
                attitude_q_gs.k,
            ],
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
/// scenario ends first), in delivery order.
///
/// # Errors
/// [`SimulationError`] from the simulation.
pub fn simulated_records(
    scenario: &crate::scenario::Scenario,
    frames: u64,
) -> Result<Vec<LogRecord>, SimulationError> {
    let mut simulation = Simulation::new(scenario)?;
    let mut events = Vec::new();
    for _ in 0..frames {
        if simulation.step(&mut events)?.is_none() {
            break;
        }
    }
    Ok(events.iter().map(record_of).collect())
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
/// `frames`), or `None` for a star record whose arrival differs from its time tag (the
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

/// Keeps the delivery-order invariant shared by writer and reader.
#[derive(Debug, Default)]
struct OrderCheck {
    previous_s: Option<f64>,
}

impl OrderCheck {
    fn check(&mut self, line: u64, arrival_time_s: f64) -> Result<(), SensorLogError> {
        if let Some(previous_s) = self.previous_s {
            if arrival_time_s < previous_s {
                return Err(SensorLogError::OutOfOrder {
                    line,
                    arrival_time_s,
                    previous_s,
                });
            }
        }
        self.previous_s = Some(arrival_time_s);
        Ok(())
    }
}

/// Writes a CSV sensor log row by row.
pub struct SensorLogWriter<W: Write> {
    csv: csv::Writer<W>,
    /// Line number of the next row (the header is line 1).
    next_line: u64,
    order: OrderCheck,
    float_buffer: ryu::Buffer,
}

impl<W: Write> SensorLogWriter<W> {
    /// Starts a log: writes the header.
    ///
    /// # Errors
    /// [`SensorLogError::Csv`] if the header cannot be written.
    pub fn new(writer: W) -> Result<Self, SensorLogError> {
        let mut csv = csv::Writer::from_writer(writer);
        csv.write_record(COLUMNS)
            .map_err(|source| SensorLogError::Csv { line: 1, source })?;
        Ok(Self {
            csv,
            next_line: 2,
            order: OrderCheck::default(),
            float_buffer: ryu::Buffer::new(),
        })
    }

    /// Appends one record.
    ///
    /// # Errors
    /// [`SensorLogError::NonFinite`] for a NaN/infinite field, [`SensorLogError::OutOfOrder`]
    /// if it arrives before the previous row, [`SensorLogError::Csv`] if writing fails. The
    /// line number is the one the row would have had.
    pub fn write(&mut self, record: &LogRecord) -> Result<(), SensorLogError> {
        let line = self.next_line;
        let kind = Kind::of(record);
        let mut row: [String; COLUMNS.len()] = Default::default();
        kind.name().clone_into(&mut row[column::KIND]);
        if let LogRecord::Imu(imu) = record {
            row[column::SEQUENCE] = imu.sequence.to_string();
        }
        if let LogRecord::Gnss(gnss) = record {
            row[column::GPS_WEEK] = gnss.gps_week.to_string();
        }
        for (&index, value) in kind.float_columns().iter().zip(float_values(record)) {
            if !value.is_finite() {
                return Err(SensorLogError::NonFinite {
                    line,
                    column: COLUMNS[index],
                    value,
                });
            }
            self.float_buffer
                .format_finite(value)
                .clone_into(&mut row[index]);
        }
        if let LogRecord::Gnss(GnssRecord {
            velocity_ecef_mps: Some(velocity),
            ..
        }) = record
        {
            for (offset, value) in velocity.iter().enumerate() {
                let index = column::VELOCITY + offset;
                if !value.is_finite() {
                    return Err(SensorLogError::NonFinite {
                        line,
                        column: COLUMNS[index],
                        value: *value,
                    });
                }
                self.float_buffer
                    .format_finite(*value)
                    .clone_into(&mut row[index]);
            }
        }
        self.order.check(line, record.arrival_time_s())?;
        self.csv
            .write_record(&row)
            .map_err(|source| SensorLogError::Csv { line, source })?;
        self.next_line += 1;
        Ok(())
    }

    /// Appends one simulator event.
    ///
    /// # Errors
    /// As [`SensorLogWriter::write`].
    pub fn write_event(&mut self, event: &SensorEvent) -> Result<(), SensorLogError> {
        self.write(&record_of(event))
    }

    /// Flushes and returns the underlying writer.
    ///
    /// # Errors
    /// [`SensorLogError::Io`] if flushing fails.
    pub fn finish(self) -> Result<W, SensorLogError> {
        self.csv
            .into_inner()
            .map_err(|error| SensorLogError::Io(error.into_error()))
    }
}

/// Runs a simulation to its end, streaming every sensor event into a CSV log (memory does not
/// grow with the mission length). Returns the number of rows written.
///
/// # Errors
/// [`SensorLogError::Simulation`] or a writing error.
pub fn record_simulation<W: Write>(
    mut simulation: Simulation,
    writer: W,
) -> Result<u64, SensorLogError> {
    let mut log = SensorLogWriter::new(writer)?;
    let mut events = Vec::new();
    let mut rows = 0_u64;
    while simulation.step(&mut events)?.is_some() {
        for event in events.drain(..) {
            log.write_event(&event)?;
            rows += 1;
        }
    }
    log.finish()?.flush()?;
    Ok(rows)
}

/// Reads a CSV sensor log row by row (an iterator of records; stops at the first error).
pub struct SensorLogReader<R: Read> {
    records: csv::StringRecordsIntoIter<R>,
    order: OrderCheck,
    failed: bool,
    /// Line of the last row read (1 before the first).
    line: u64,
}

impl<R: Read> SensorLogReader<R> {
    /// Opens a log and checks its header.
    ///
    /// # Errors
    /// [`SensorLogError::Header`] naming the first wrong column, or [`SensorLogError::Csv`].
    pub fn new(reader: R) -> Result<Self, SensorLogError> {
        let mut csv = csv::ReaderBuilder::new()
            .has_headers(true)
            .from_reader(reader);
        let header = csv
            .headers()
            .map_err(|source| SensorLogError::Csv { line: 1, source })?;
        // A log of an earlier layout has a prefix of this header.
        let old = OLD_LAYOUT_COLUMNS.contains(&header.len())
            && header
                .iter()
                .zip(COLUMNS)
                .all(|(found, expected)| found == expected);
        if old {
            return Err(SensorLogError::OldLayout {
                columns: header.len(),
            });
        }
        let expected_columns = COLUMNS.len();
        let mismatch = (0..expected_columns.max(header.len())).find_map(|index| {
            let found = header.get(index).unwrap_or("");
            let expected = COLUMNS
                .get(index)
                .filter(|_| index < expected_columns)
                .copied()
                .unwrap_or("");
            (found != expected).then(|| SensorLogError::Header {
                position: index + 1,
                expected,
                found: found.to_string(),
            })
        });
        if let Some(error) = mismatch {
            return Err(error);
        }
        Ok(Self {
            records: csv.into_records(),
            order: OrderCheck::default(),
            failed: false,
            line: 1,
        })
    }

    /// Line of the last row read (1, the header, before the first).
    pub fn line(&self) -> u64 {
        self.line
    }

    fn parse(&mut self, row: &csv::StringRecord) -> Result<LogRecord, SensorLogError> {
        let line = row.position().map_or(0, csv::Position::line);
        let cell = |index: usize| row.get(index).unwrap_or("");
        let kind = Kind::parse(cell(column::KIND)).ok_or_else(|| SensorLogError::UnknownKind {
            line,
            value: cell(column::KIND).to_string(),
        })?;
        if let Some(index) =
            (0..COLUMNS.len()).find(|&index| !kind.uses(index) && !cell(index).is_empty())
        {
            return Err(SensorLogError::NotApplicable {
                line,
                column: COLUMNS[index],
                kind: kind.name(),
                value: cell(index).to_string(),
            });
        }
        let required = |index: usize| -> Result<&str, SensorLogError> {
            let text = cell(index);
            if text.is_empty() {
                Err(SensorLogError::Missing {
                    line,
                    column: COLUMNS[index],
                    kind: kind.name(),
                })
            } else {
                Ok(text)
            }
        };
        let float = |index: usize| -> Result<f64, SensorLogError> {
            let text = required(index)?;
            let value: f64 = text.parse().map_err(|_| SensorLogError::Invalid {
                line,
                column: COLUMNS[index],
                value: text.to_string(),
                expected: "a number",
            })?;
            if value.is_finite() {
                Ok(value)
            } else {
                Err(SensorLogError::NonFinite {
                    line,
                    column: COLUMNS[index],
                    value,
                })
            }
        };
        let record = match kind {
            Kind::Imu => {
                let [arrival_time_s, time_tag_s, interval_s, ax, ay, az, vx, vy, vz] =
                    parse_floats(IMU_FLOAT_COLUMNS, &float)?;
                if arrival_time_s.to_bits() != time_tag_s.to_bits() {
                    return Err(SensorLogError::ImuTimeMismatch {
                        line,
                        arrival_time_s,
                        time_tag_s,
                    });
                }
                let text = required(column::SEQUENCE)?;
                let sequence = text.parse().map_err(|_| SensorLogError::Invalid {
                    line,
                    column: COLUMNS[column::SEQUENCE],
                    value: text.to_string(),
                    expected: "an unsigned 64-bit integer",
                })?;
                LogRecord::Imu(ImuRecord {
                    sequence,
                    time_s: arrival_time_s,
                    interval_s,
                    delta_angle_rad: [ax, ay, az],
                    delta_velocity_mps: [vx, vy, vz],
                })
            }
            Kind::Star => {
                let [arrival_time_s, time_tag_s, w, x, y, z] =
                    parse_floats(STAR_FLOAT_COLUMNS, &float)?;
                LogRecord::Star(StarRecord {
                    arrival_time_s,
                    time_tag_s,
                    attitude_wxyz: [w, x, y, z],
                })
            }
            Kind::Gnss => {
                let [arrival_time_s, gps_seconds_of_week, x, y, z] =
                    parse_floats(GNSS_FLOAT_COLUMNS, &float)?;
                let text = required(column::GPS_WEEK)?;
                let gps_week = text.parse().map_err(|_| SensorLogError::Invalid {
                    line,
                    column: COLUMNS[column::GPS_WEEK],
                    value: text.to_string(),
                    expected: "an unsigned 32-bit integer",
                })?;
                let velocity_columns = [0, 1, 2].map(|offset| column::VELOCITY + offset);
                // All three empty: a position-only receiver; else all three are required.
                let velocity_ecef_mps = if velocity_columns.iter().all(|i| cell(*i).is_empty()) {
                    None
                } else {
                    Some(parse_floats(velocity_columns, &float)?)
                };
                LogRecord::Gnss(GnssRecord {
                    arrival_time_s,
                    gps_week,
                    gps_seconds_of_week,
                    position_ecef_m: [x, y, z],
                    velocity_ecef_mps,
                })
            }
        };
        self.order.check(line, record.arrival_time_s())?;
        Ok(record)
    }
}

/// Parses the given columns of a row, in order.
fn parse_floats<const N: usize>(
    columns: [usize; N],
    float: &dyn Fn(usize) -> Result<f64, SensorLogError>,
) -> Result<[f64; N], SensorLogError> {
    let mut values = [0.0; N];
    for (value, index) in values.iter_mut().zip(columns) {
        *value = float(index)?;
    }
    Ok(values)
}

impl<R: Read> Iterator for SensorLogReader<R> {
    type Item = Result<LogRecord, SensorLogError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        let result = match self.records.next()? {
            Ok(row) => {
                self.line = row.position().map_or(0, csv::Position::line);
                self.parse(&row)
            }
            Err(source) => Err(SensorLogError::Csv {
                line: source.position().map_or(0, csv::Position::line),
                source,
            }),
        };
        self.failed = result.is_err();
        Some(result)
    }
}

/// Reads a whole CSV log into simulator events.
///
/// # Errors
/// Any reading error, or [`SensorLogError::StarLatency`] for a star row the simulator's events
/// cannot express.
pub fn read_events<R: Read>(
    reader: R,
    frames: &SensorFrames,
) -> Result<Vec<SensorEvent>, SensorLogError> {
    let mut log = SensorLogReader::new(reader)?;
    let mut events = Vec::new();
    while let Some(record) = log.next() {
        let record = record?;
        let event = event_of(&record, frames).ok_or_else(|| SensorLogError::StarLatency {
            line: log.line(),
            arrival_time_s: record.arrival_time_s(),
            time_tag_s: record.time_tag_s().unwrap_or(f64::NAN),
        })?;
        events.push(event);
    }
    Ok(events)
}

/// Converts a CSV log into the binary form (header, then one record per row). Returns the
/// number of records written.
///
/// # Errors
/// Any CSV reading error (naming line and column), or an I/O error writing.
pub fn convert_csv_to_binary<R: Read, W: Write>(
    csv: R,
    mut binary: W,
) -> Result<u64, SensorLogError> {
    binary.write_all(&log_record::encode_header())?;
    let mut count = 0_u64;
    for record in SensorLogReader::new(csv)? {
        let bytes = record?.encode().map_err(|error| SensorLogError::Binary {
            record: Some(count),
            error,
        })?;
        binary.write_all(&bytes)?;
        count += 1;
    }
    binary.flush()?;
    Ok(count)
}

/// Reads a binary log (the host side of what the firmware streams).
///
/// # Errors
/// [`SensorLogError::Binary`] naming the header or the record index (a trailing partial record
/// is [`LogRecordError::Truncated`]), or [`SensorLogError::Io`].
pub fn read_binary<R: Read>(mut reader: R) -> Result<Vec<LogRecord>, SensorLogError> {
    let mut header = [0_u8; HEADER_SIZE];
    let available = read_up_to(&mut reader, &mut header)?;
    if available < HEADER_SIZE {
        return Err(SensorLogError::Binary {
            record: None,
            error: LogRecordError::Truncated {
                needed: HEADER_SIZE,
                available,
            },
        });
    }
    log_record::decode_header(&header).map_err(|error| SensorLogError::Binary {
        record: None,
        error,
    })?;
    let mut records = Vec::new();
    let mut buffer = [0_u8; RECORD_SIZE];
    loop {
        let index = u64::try_from(records.len()).unwrap_or(u64::MAX);
        let binary_error = |error| SensorLogError::Binary {
            record: Some(index),
            error,
        };
        match read_up_to(&mut reader, &mut buffer)? {
            0 => return Ok(records),
            RECORD_SIZE => records.push(LogRecord::decode(&buffer).map_err(binary_error)?),
            available => {
                return Err(binary_error(LogRecordError::Truncated {
                    needed: RECORD_SIZE,
                    available,
                }))
            }
        }
    }
}

/// Reads until `buffer` is full or the stream ends; returns the bytes read.
fn read_up_to<R: Read>(reader: &mut R, buffer: &mut [u8]) -> std::io::Result<usize> {
    let mut filled = 0;
    while filled < buffer.len() {
        match reader.read(&mut buffer[filled..]) {
            Ok(0) => break,
            Ok(count) => filled += count,
            Err(error) if error.kind() == std::io::ErrorKind::Interrupted => {}
            Err(error) => return Err(error),
        }
    }
    Ok(filled)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Scenario;
    use proptest::prelude::*;

    fn write_csv(records: &[LogRecord]) -> Vec<u8> {
        let mut log = SensorLogWriter::new(Vec::new()).unwrap();
        for record in records {
            log.write(record).unwrap();
        }
        log.finish().unwrap()
    }

    fn read_csv(bytes: &[u8]) -> Result<Vec<LogRecord>, SensorLogError> {
        SensorLogReader::new(bytes)?.collect()
    }

    /// Bit patterns of every field (the binary encoding is exactly that).
    fn bits(records: &[LogRecord]) -> Vec<[u8; RECORD_SIZE]> {
        records
            .iter()
            .map(|record| record.encode().unwrap())
            .collect()
    }

    /// A record of any kind from nine arbitrary finite floats; arrival times are set by the
    /// caller to keep the log in order.
    fn record_from(kind: u8, sequence: u64, arrival_time_s: f64, values: [f64; 9]) -> LogRecord {
        let [a, b, c, d, e, f, g, h, i] = values;
        match kind % 4 {
            0 => LogRecord::Imu(ImuRecord {
                sequence,
                time_s: arrival_time_s,
                interval_s: a,
                delta_angle_rad: [b, c, d],
                delta_velocity_mps: [e, f, g],
            }),
            1 => LogRecord::Star(StarRecord {
                arrival_time_s,
                time_tag_s: a,
                attitude_wxyz: [b, c, d, e],
            }),
            2 => LogRecord::Gnss(GnssRecord {
                arrival_time_s,
                gps_week: sequence as u32,
                gps_seconds_of_week: h,
                position_ecef_m: [i, a, b],
                velocity_ecef_mps: None,
            }),
            _ => LogRecord::Gnss(GnssRecord {
                arrival_time_s,
                gps_week: sequence as u32,
                gps_seconds_of_week: h,
                position_ecef_m: [i, a, b],
                velocity_ecef_mps: Some([c, d, e]),
            }),
        }
    }

    fn finite() -> impl Strategy<Value = f64> {
        any::<f64>().prop_filter("finite", |value| value.is_finite())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// Any finite values (subnormals, ±0, extremes included) survive CSV and binary
        /// bit for bit.
        #[test]
        fn csv_and_binary_round_trip_bit_exactly(
            rows in proptest::collection::vec(
                (any::<u8>(), any::<u64>(), finite(), proptest::array::uniform9(finite())),
                0..40,
            )
        ) {
            let mut arrivals: Vec<f64> = rows.iter().map(|row| row.2).collect();
            arrivals.sort_by(f64::total_cmp);
            let records: Vec<LogRecord> = rows
                .iter()
                .zip(arrivals)
                .map(|(&(kind, sequence, _, values), arrival)| record_from(kind, sequence, arrival, values))
                .collect();
            let csv = write_csv(&records);
            let read = read_csv(&csv).unwrap();
            prop_assert_eq!(bits(&read), bits(&records));

            let mut binary = Vec::new();
            let count = convert_csv_to_binary(csv.as_slice(), &mut binary).unwrap();
            prop_assert_eq!(count, u64::try_from(records.len()).unwrap());
            prop_assert_eq!(binary.len(), HEADER_SIZE + RECORD_SIZE * records.len());
            prop_assert_eq!(bits(&read_binary(binary.as_slice()).unwrap()), bits(&records));
        }

        /// Arbitrary text never panics the reader.
        #[test]
        fn reader_never_panics_on_arbitrary_rows(body in "[a-z0-9.,eE+-]{0,200}(\n[a-z0-9.,eE+-]{0,200}){0,5}") {
            let text = format!("{}\n{body}", COLUMNS.join(","));
            let _ = read_csv(text.as_bytes());
        }
    }

    /// The simulator's own stream (first 3 s of the default scenario: IMU, star, GNSS)
    /// survives the CSV log exactly.
    #[test]
    fn simulator_events_round_trip() {
        let scenario = Scenario::default_scenario().unwrap();
        let mut simulation = Simulation::new(&scenario).unwrap();
        let mut events = Vec::new();
        for _ in 0..1500 {
            simulation.step(&mut events).unwrap();
        }
        let count = |wanted: fn(&SensorEvent) -> bool| events.iter().filter(|e| wanted(e)).count();
        assert_eq!(count(|e| matches!(e, SensorEvent::Imu { .. })), 1500);
        assert!(count(|e| matches!(e, SensorEvent::Star { .. })) >= 10);
        assert!(count(|e| matches!(e, SensorEvent::Gnss { .. })) >= 2);

        let mut log = SensorLogWriter::new(Vec::new()).unwrap();
        for event in &events {
            log.write_event(event).unwrap();
        }
        let csv = log.finish().unwrap();
        let frames = crate::setup::launch::scenario_ground_constants(&scenario)
            .unwrap()
            .sensor_frames;
        let read = read_events(csv.as_slice(), &frames).unwrap();
        // Bit for bit in the log's own terms (a GNSS event's navigation time is re-derived from
        // its GPS tag, exact to the rounding of the seconds of week, ~1e-11 s).
        assert_eq!(read.len(), events.len());
        let event_bits =
            |events: &[SensorEvent]| bits(&events.iter().map(record_of).collect::<Vec<_>>());
        assert_eq!(event_bits(&read), event_bits(&events));

        let text = String::from_utf8(csv).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next().unwrap(), COLUMNS.join(","));
        let first = lines.next().unwrap();
        assert!(first.starts_with("imu,600.002,600.002,0,0.002,"), "{first}");
    }

    /// The default mission's first two phases, streamed to CSV, read back as the simulator's
    /// stream.
    #[test]
    fn recorded_mission_reads_back_as_the_event_stream() {
        let mut scenario = Scenario::default_scenario().unwrap();
        scenario.manoeuvres.truncate(2);
        let mut csv = Vec::new();
        let rows = record_simulation(Simulation::new(&scenario).unwrap(), &mut csv).unwrap();
        let expected = Simulation::new(&scenario).unwrap().event_stream().unwrap();
        assert_eq!(rows, u64::try_from(expected.len()).unwrap());
        let imu_rows = expected
            .iter()
            .filter(|event| matches!(event, SensorEvent::Imu { .. }))
            .count();
        assert_eq!(u64::try_from(imu_rows).unwrap(), scenario.frame_count());
        let frames = crate::setup::launch::scenario_ground_constants(&scenario)
            .unwrap()
            .sensor_frames;
        let read = read_events(csv.as_slice(), &frames).unwrap();
        assert_eq!(read.len(), expected.len());
        assert!(read
            .iter()
            .zip(&expected)
            .all(|(read, expected)| record_of(read).encode() == record_of(expected).encode()));
        println!(
            "default mission log: {rows} rows, {} bytes of CSV",
            csv.len()
        );
    }

    /// `row` of the first 18 columns with the 5 columns after them empty (other rows as they
    /// are).
    fn padded(row: &str) -> String {
        if row.matches(',').count() == 17 {
            format!("{row},,,,,")
        } else {
            row.to_string()
        }
    }

    /// Expected error for a log whose only data row is `row` (line 2), padded.
    fn error_of(row: &str) -> SensorLogError {
        let text = format!("{}\n{}\n", COLUMNS.join(","), padded(row));
        read_csv(text.as_bytes()).unwrap_err()
    }

    /// GNSS velocity columns: all three filled or all three empty; the earlier 18- and
    /// 21-column layouts are refused, saying why; a velocity round-trips bit for bit.
    #[test]
    fn gnss_velocity_columns() {
        let header = COLUMNS.join(",");
        let row = "gnss,2,,,,,,,,,,,,,,1,2,3,0.5,-0.25,7500,2300,2";
        let records = read_csv(format!("{header}\n{row}\n").as_bytes()).unwrap();
        let LogRecord::Gnss(gnss) = records[0] else {
            panic!("not a GNSS record")
        };
        assert_eq!(gnss.velocity_ecef_mps, Some([0.5, -0.25, 7500.0]));
        let position_only = "gnss,2,,,,,,,,,,,,,,1,2,3,,,,2300,2";
        let records = read_csv(format!("{header}\n{position_only}\n").as_bytes()).unwrap();
        assert!(matches!(
            records[0],
            LogRecord::Gnss(GnssRecord {
                velocity_ecef_mps: None,
                ..
            })
        ));
        let partial = "gnss,2,,,,,,,,,,,,,,1,2,3,0.5,,7500,2300,2";
        assert_eq!(
            read_csv(format!("{header}\n{partial}\n").as_bytes())
                .unwrap_err()
                .to_string(),
            "line 2, column `velocity_ecef_y_mps`: missing value (needed in `gnss` rows)"
        );
        for columns in [18, 21] {
            let legacy = COLUMNS[..columns].join(",");
            let error =
                read_csv(format!("{legacy}\ngnss,2,2,,,,,,,,,,,,,1,2,3\n").as_bytes()).unwrap_err();
            assert!(matches!(error, SensorLogError::OldLayout { columns: c } if c == columns));
            assert!(error.to_string().contains("GPS week"), "{error}");
        }
        let records = read_csv(format!("{header}\n{position_only}\n").as_bytes()).unwrap();
        let mut log = SensorLogWriter::new(Vec::new()).unwrap();
        log.write(&records[0]).unwrap();
        let with_velocity = LogRecord::Gnss(GnssRecord {
            velocity_ecef_mps: Some([0.1, f64::MIN_POSITIVE, -7.6e3]),
            ..match records[0] {
                LogRecord::Gnss(gnss) => gnss,
                _ => unreachable!(),
            }
        });
        log.write(&with_velocity).unwrap();
        let written = log.finish().unwrap();
        assert_eq!(
            bits(&read_csv(&written).unwrap()),
            bits(&[records[0], with_velocity])
        );
    }

    const IMU_ROW: &str = "imu,1.5,1.5,7,0.002,1e-6,0,0,0,0,-0.02,,,,,,,";

    #[test]
    fn reader_errors_name_line_and_column() {
        let good =
            read_csv(format!("{}\n{}\n", COLUMNS.join(","), padded(IMU_ROW)).as_bytes()).unwrap();
        assert_eq!(good.len(), 1);

        let message = |error: SensorLogError| error.to_string();
        assert_eq!(
            message(error_of(&IMU_ROW.replacen("imu", "lidar", 1))),
            "line 2, column `kind`: unknown kind `lidar` (expected imu, star or gnss)"
        );
        assert_eq!(
            message(error_of(&IMU_ROW.replacen(",7,", ",,", 1))),
            "line 2, column `sequence`: missing value (needed in `imu` rows)"
        );
        assert!(matches!(
            error_of(&IMU_ROW.replacen(",7,", ",-7,", 1)),
            SensorLogError::Invalid {
                line: 2,
                column: "sequence",
                ..
            }
        ));
        assert!(matches!(
            error_of(&IMU_ROW.replacen("1e-6", "1e-6x", 1)),
            SensorLogError::Invalid {
                line: 2,
                column: "delta_angle_x_rad",
                ..
            }
        ));
        assert!(matches!(
            error_of(&IMU_ROW.replacen("-0.02", "NaN", 1)),
            SensorLogError::NonFinite {
                line: 2,
                column: "delta_velocity_z_mps",
                ..
            }
        ));
        assert!(matches!(
            error_of(&format!("{IMU_ROW}1")),
            SensorLogError::NotApplicable {
                line: 2,
                column: "position_ecef_z_m",
                kind: "imu",
                ..
            }
        ));
        assert!(matches!(
            error_of(&IMU_ROW.replacen("1.5,1.5", "1.5,1.25", 1)),
            SensorLogError::ImuTimeMismatch { line: 2, .. }
        ));
        assert!(matches!(
            error_of("star,1,1,,,,,,,,,1,0,0"),
            SensorLogError::Csv { line: 2, .. }
        ));
        assert!(matches!(
            error_of("gnss,1,,,,,,,,,,,,,,1,2,,,,,2300,5"),
            SensorLogError::Missing {
                line: 2,
                column: "position_ecef_z_m",
                kind: "gnss"
            }
        ));

        let out_of_order = format!(
            "{}\n{}\n{}\n",
            COLUMNS.join(","),
            padded(IMU_ROW),
            padded("star,1.25,1.25,,,,,,,,,1,0,0,0,,,")
        );
        assert!(matches!(
            read_csv(out_of_order.as_bytes()).unwrap_err(),
            SensorLogError::OutOfOrder { line: 3, .. }
        ));

        let header = COLUMNS.join(",").replace("attitude_x", "attitude_i");
        match SensorLogReader::new(header.as_bytes()).err().unwrap() {
            SensorLogError::Header {
                position,
                expected,
                found,
            } => {
                assert_eq!(
                    (position, expected, found.as_str()),
                    (13, "attitude_x", "attitude_i")
                );
            }
            other => panic!("{other}"),
        }
        let short_header = COLUMNS[..17].join(",");
        assert!(matches!(
            SensorLogReader::new(short_header.as_bytes()).err().unwrap(),
            SensorLogError::Header { position: 18, found, .. } if found.is_empty()
        ));

        let latency = format!(
            "{}\n{}\n",
            COLUMNS.join(","),
            padded("star,1.25,1,,,,,,,,,1,0,0,0,,,")
        );
        assert!(read_csv(latency.as_bytes()).is_ok());
        assert!(matches!(
            read_events(latency.as_bytes(), &SensorFrames::ALIGNED).unwrap_err(),
            SensorLogError::StarLatency { line: 2, .. }
        ));
    }

    #[test]
    fn writer_refuses_what_the_reader_would_refuse() {
        let mut log = SensorLogWriter::new(Vec::new()).unwrap();
        let gnss = |arrival_time_s: f64, x: f64| {
            LogRecord::Gnss(GnssRecord {
                arrival_time_s,
                gps_week: 2_300,
                gps_seconds_of_week: arrival_time_s,
                position_ecef_m: [x, 0.0, 0.0],
                velocity_ecef_mps: None,
            })
        };
        log.write(&gnss(2.0, 1.0)).unwrap();
        assert!(matches!(
            log.write(&gnss(3.0, f64::INFINITY)).unwrap_err(),
            SensorLogError::NonFinite {
                line: 3,
                column: "position_ecef_x_m",
                ..
            }
        ));
        assert!(matches!(
            log.write(&gnss(1.0, 1.0)).unwrap_err(),
            SensorLogError::OutOfOrder { line: 3, .. }
        ));
    }

    #[test]
    fn binary_errors_name_the_record() {
        let records = [
            record_from(1, 0, 1.0, [1.0; 9]),
            record_from(2, 0, 2.0, [3.0; 9]),
        ];
        let mut binary = Vec::new();
        convert_csv_to_binary(write_csv(&records).as_slice(), &mut binary).unwrap();
        assert_eq!(
            bits(&read_binary(binary.as_slice()).unwrap()),
            bits(&records)
        );

        let mut bad_tag = binary.clone();
        bad_tag[HEADER_SIZE + RECORD_SIZE] = 9;
        assert_eq!(
            read_binary(bad_tag.as_slice()).unwrap_err().to_string(),
            "binary log record 1: unknown tag 9"
        );
        let truncated = &binary[..binary.len() - 1];
        assert!(matches!(
            read_binary(truncated).unwrap_err(),
            SensorLogError::Binary {
                record: Some(1),
                error: LogRecordError::Truncated {
                    needed: 80,
                    available: 79
                }
            }
        ));
        assert!(matches!(
            read_binary(&binary[..5]).unwrap_err(),
            SensorLogError::Binary {
                record: None,
                error: LogRecordError::Truncated { .. }
            }
        ));
        let mut bad_magic = binary;
        bad_magic[0] = b'X';
        assert!(matches!(
            read_binary(bad_magic.as_slice()).unwrap_err(),
            SensorLogError::Binary {
                record: None,
                error: LogRecordError::BadMagic
            }
        ));
    }
}
