//! Reading a CSV sensor log: the reader (an iterator of records, every error naming its line
//! and column) and the events of a log.

use std::io::Read;

use nav_fsw::log_record::{GnssRecord, ImuRecord, LogRecord, StarRecord};
use nav_fsw::sensor_frames::SensorFrames;

use super::writer::OrderCheck;
use super::{
    column, event_of, Kind, SensorLogError, COLUMNS, GNSS_FLOAT_COLUMNS, IMU_FLOAT_COLUMNS,
    OLD_LAYOUT_COLUMNS, ONE_HEAD_LAYOUT_COLUMNS, STAR_FLOAT_COLUMNS,
};
use crate::world::sensors::SensorEvent;

/// Reads a CSV sensor log row by row (an iterator of records; stops at the first error).
pub struct SensorLogReader<R: Read> {
    records: csv::StringRecordsIntoIter<R>,
    order: OrderCheck,
    failed: bool,
    /// Line of the last row read (1 before the first).
    line: u64,
    /// Whether the log has the `star_head` column (else every star row is head 0's).
    has_head_column: bool,
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
        // The layout before the head column is this header without its last column.
        let expected_columns = if header.len() == ONE_HEAD_LAYOUT_COLUMNS {
            ONE_HEAD_LAYOUT_COLUMNS
        } else {
            COLUMNS.len()
        };
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
            has_head_column: expected_columns == COLUMNS.len(),
        })
    }

    /// Whether the log has the `star_head` column (a log without it has every star row
    /// head 0's).
    pub fn has_head_column(&self) -> bool {
        self.has_head_column
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
                let head = if self.has_head_column {
                    let text = required(column::STAR_HEAD)?;
                    text.parse().map_err(|_| SensorLogError::Invalid {
                        line,
                        column: COLUMNS[column::STAR_HEAD],
                        value: text.to_string(),
                        expected: "an unsigned 8-bit integer",
                    })?
                } else {
                    0
                };
                LogRecord::Star(StarRecord {
                    arrival_time_s,
                    time_tag_s,
                    attitude_wxyz: [w, x, y, z],
                    head,
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
