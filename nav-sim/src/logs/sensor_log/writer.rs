//! Writing a CSV sensor log: the writer, its delivery-order check, and a simulation recorded
//! to a log.

use std::io::Write;

use nav_fsw::log_record::{GnssRecord, LogRecord};

use super::{column, float_values, record_of, Kind, SensorLogError, COLUMNS};
use crate::logs::star_heads::FlightStarHeads;
use crate::world::sensors::SensorEvent;
use crate::world::simulation::Simulation;

/// Keeps the delivery-order invariant shared by writer and reader.
#[derive(Debug, Default)]
pub(super) struct OrderCheck {
    previous_s: Option<f64>,
}

impl OrderCheck {
    pub(super) fn check(&mut self, line: u64, arrival_time_s: f64) -> Result<(), SensorLogError> {
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
        if let LogRecord::Star(star) = record {
            row[column::STAR_HEAD] = star.head.to_string();
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

/// What [`record_simulation`] wrote.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RecordedLog {
    /// Rows written.
    pub rows: u64,
    /// Star measurements of heads beyond those a tracker port carries, not written
    /// ([`FlightStarHeads::port`]).
    pub withheld_star_measurements: u64,
}

/// Runs a simulation to its end, streaming every sensor event a flight computer's ports carry
/// ([`FlightStarHeads::port`]) into a CSV log (memory does not grow with the mission length).
///
/// # Errors
/// [`SensorLogError::Simulation`] or a writing error.
pub fn record_simulation<W: Write>(
    mut simulation: Simulation,
    writer: W,
) -> Result<RecordedLog, SensorLogError> {
    let mut log = SensorLogWriter::new(writer)?;
    let mut events = Vec::new();
    let mut heads = FlightStarHeads::port();
    let mut rows = 0_u64;
    while simulation.step(&mut events)?.is_some() {
        for event in events.drain(..).filter(|event| heads.hands_over(event)) {
            log.write_event(&event)?;
            rows += 1;
        }
    }
    log.finish()?.flush()?;
    Ok(RecordedLog {
        rows,
        withheld_star_measurements: heads.withheld(),
    })
}
