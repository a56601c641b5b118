//! Sensor ports over byte streams: the adapter that plugs a real sensor's serial line (any
//! [`embedded_io`] reader, e.g. a HAL's UART) into the scheduler's [`ImuPort`],
//! [`StarSensorPort`] and [`GnssPort`].
//!
//! The wire format is the replay log's fixed 80-byte record (`docs/guide/replay-format.md`,
//! [`crate::log_record`]), so a sensor front-end (or a recorder) that emits those records works
//! unchanged on hardware, in the host simulator and in the QEMU firmware. Reading is
//! non-blocking and bounded: a poll reads only the bytes the device reports ready
//! ([`embedded_io::ReadReady`]) and at most [`MAX_BYTES_PER_POLL`] of them, so a port never
//! stalls a frame. Records may arrive split across polls; after corrupt bytes (a record that
//! does not decode) the reader drops one byte at a time until records decode again (resync),
//! counting what it dropped. A record of another sensor's kind is dropped and counted.

use embedded_io::{Read, ReadReady};

use crate::log_record::{LogRecord, RECORD_SIZE};
use crate::ports::{GnssFix, GnssPort, ImuPort, ImuSample, StarMeasurement, StarSensorPort};

/// Most bytes one [`RecordReader::next_record`] reads (two records).
pub const MAX_BYTES_PER_POLL: usize = 2 * RECORD_SIZE;
/// Most records one port call looks at while skipping other sensors' records: with
/// [`MAX_BYTES_PER_POLL`], the bound on a port's work per call.
pub const MAX_RECORDS_PER_POLL: usize = 4;

/// What a stream port has counted (telemetry).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StreamCounters {
    /// Records decoded and delivered.
    pub records: u32,
    /// Bytes dropped to find the next record boundary after corrupt data.
    pub resync_bytes: u32,
    /// Well-formed records of another sensor's kind (dropped).
    pub wrong_kind: u32,
    /// Device read errors (the poll then delivers nothing).
    pub read_errors: u32,
}

/// Assembles [`LogRecord`]s from a byte stream.
#[derive(Debug)]
pub struct RecordReader<R> {
    device: R,
    buffer: [u8; RECORD_SIZE],
    filled: usize,
    counters: StreamCounters,
}

fn count(counter: &mut u32) {
    *counter = counter.saturating_add(1);
}

impl<R: Read + ReadReady> RecordReader<R> {
    /// A reader over `device`.
    pub fn new(device: R) -> Self {
        Self {
            device,
            buffer: [0; RECORD_SIZE],
            filled: 0,
            counters: StreamCounters::default(),
        }
    }

    /// The counters so far.
    pub fn counters(&self) -> StreamCounters {
        self.counters
    }

    /// The byte stream read from.
    pub fn device(&self) -> &R {
        &self.device
    }

    /// The next complete record, reading at most [`MAX_BYTES_PER_POLL`] bytes that the device
    /// has ready; `None` when no complete record is available now.
    pub fn next_record(&mut self) -> Option<LogRecord> {
        let mut budget = MAX_BYTES_PER_POLL;
        while budget > 0 {
            if self.filled == RECORD_SIZE {
                if let Some(record) = self.decode_or_drop_a_byte() {
                    return Some(record);
                }
                continue;
            }
            match self.device.read_ready() {
                Ok(true) => {}
                Ok(false) => return None,
                Err(_) => {
                    count(&mut self.counters.read_errors);
                    return None;
                }
            }
            let wanted = (RECORD_SIZE - self.filled).min(budget);
            let space = self.buffer.get_mut(self.filled..self.filled + wanted)?;
            match self.device.read(space) {
                Ok(0) => return None,
                Ok(read) => {
                    let read = read.min(wanted);
                    self.filled += read;
                    budget -= read;
                }
                Err(_) => {
                    count(&mut self.counters.read_errors);
                    return None;
                }
            }
        }
        if self.filled == RECORD_SIZE {
            return self.decode_or_drop_a_byte();
        }
        None
    }

    /// Decodes the full buffer; on failure drops its first byte (resync) and returns `None`.
    fn decode_or_drop_a_byte(&mut self) -> Option<LogRecord> {
        match LogRecord::decode(&self.buffer) {
            Ok(record) => {
                self.filled = 0;
                count(&mut self.counters.records);
                Some(record)
            }
            Err(_) => {
                self.buffer.copy_within(1.., 0);
                self.filled = RECORD_SIZE - 1;
                count(&mut self.counters.resync_bytes);
                None
            }
        }
    }
}

/// The next record `pick` accepts, skipping (and counting) at most
/// [`MAX_RECORDS_PER_POLL`] records of other kinds.
fn next_matching<R: Read + ReadReady, T>(
    reader: &mut RecordReader<R>,
    pick: impl Fn(&LogRecord) -> Option<T>,
) -> Option<T> {
    for _ in 0..MAX_RECORDS_PER_POLL {
        let record = reader.next_record()?;
        match pick(&record) {
            Some(value) => return Some(value),
            None => count(&mut reader.counters.wrong_kind),
        }
    }
    None
}

/// An IMU on a byte stream ([`ImuPort`]): the next IMU record is the frame's sample.
#[derive(Debug)]
#[non_exhaustive]
pub struct StreamImu<R>(pub RecordReader<R>);

impl<R: Read + ReadReady> StreamImu<R> {
    /// The port over `device`'s byte stream.
    ///
    /// ```
    /// use nav_fsw::ports::ImuPort;
    /// use nav_fsw::stream_merge::RecordedLine;
    /// let mut port = nav_fsw::stream_ports::StreamImu::new(RecordedLine(&[]));
    /// assert!(port.read().is_none());
    /// assert_eq!(port.0.counters().records, 0);
    /// ```
    pub fn new(device: R) -> Self {
        Self(RecordReader::new(device))
    }
}

impl<R: Read + ReadReady> ImuPort for StreamImu<R> {
    fn read(&mut self) -> Option<ImuSample> {
        next_matching(&mut self.0, |record| match record {
            LogRecord::Imu(imu) => Some(imu.to_imu_sample()),
            LogRecord::Star(_) | LogRecord::Gnss(_) => None,
        })
    }
}

/// A star sensor on a byte stream ([`StarSensorPort`]).
#[derive(Debug)]
#[non_exhaustive]
pub struct StreamStarSensor<R>(pub RecordReader<R>);

impl<R: Read + ReadReady> StreamStarSensor<R> {
    /// The port over `device`'s byte stream.
    ///
    /// ```
    /// use nav_fsw::ports::StarSensorPort;
    /// use nav_fsw::stream_merge::RecordedLine;
    /// let mut port = nav_fsw::stream_ports::StreamStarSensor::new(RecordedLine(&[]));
    /// assert!(port.poll().is_none());
    /// assert_eq!(port.0.counters().records, 0);
    /// ```
    pub fn new(device: R) -> Self {
        Self(RecordReader::new(device))
    }
}

impl<R: Read + ReadReady> StarSensorPort for StreamStarSensor<R> {
    fn poll(&mut self) -> Option<StarMeasurement> {
        next_matching(&mut self.0, |record| match record {
            LogRecord::Star(star) => Some(star.to_star_measurement()),
            LogRecord::Imu(_) | LogRecord::Gnss(_) => None,
        })
    }
}

/// A GNSS receiver on a byte stream ([`GnssPort`]).
#[derive(Debug)]
#[non_exhaustive]
pub struct StreamGnss<R>(pub RecordReader<R>);

impl<R: Read + ReadReady> StreamGnss<R> {
    /// The port over `device`'s byte stream.
    ///
    /// ```
    /// use nav_fsw::ports::GnssPort;
    /// use nav_fsw::stream_merge::RecordedLine;
    /// let mut port = nav_fsw::stream_ports::StreamGnss::new(RecordedLine(&[]));
    /// assert!(port.poll().is_none());
    /// assert_eq!(port.0.counters().records, 0);
    /// ```
    pub fn new(device: R) -> Self {
        Self(RecordReader::new(device))
    }
}

impl<R: Read + ReadReady> GnssPort for StreamGnss<R> {
    fn poll(&mut self) -> Option<GnssFix> {
        next_matching(&mut self.0, |record| match record {
            LogRecord::Gnss(gnss) => Some(gnss.to_gnss_fix()),
            LogRecord::Imu(_) | LogRecord::Star(_) => None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::log_record::{GnssRecord, ImuRecord, StarRecord};
    use proptest::prelude::*;

    /// A serial line that makes `chunks[k]` bytes ready at poll `k` (then 0).
    struct ChunkedLine {
        bytes: Vec<u8>,
        position: usize,
        ready: usize,
    }

    #[derive(Debug)]
    struct LineError;
    impl embedded_io::Error for LineError {
        fn kind(&self) -> embedded_io::ErrorKind {
            embedded_io::ErrorKind::Other
        }
    }
    impl embedded_io::ErrorType for ChunkedLine {
        type Error = LineError;
    }
    impl ReadReady for ChunkedLine {
        fn read_ready(&mut self) -> Result<bool, LineError> {
            Ok(self.ready > 0 && self.position < self.bytes.len())
        }
    }
    impl Read for ChunkedLine {
        fn read(&mut self, buffer: &mut [u8]) -> Result<usize, LineError> {
            let available = self.ready.min(self.bytes.len() - self.position);
            let count = available.min(buffer.len());
            buffer[..count].copy_from_slice(&self.bytes[self.position..self.position + count]);
            self.position += count;
            self.ready -= count;
            Ok(count)
        }
    }

    fn star(k: u32) -> LogRecord {
        let t = f64::from(k);
        LogRecord::Star(StarRecord {
            arrival_time_s: t,
            time_tag_s: t,
            attitude_wxyz: [0.5, 0.5, -0.5, 0.5],
            head: 0,
        })
    }

    fn gnss(k: u32) -> LogRecord {
        let t = f64::from(k);
        LogRecord::Gnss(GnssRecord {
            arrival_time_s: t,
            gps_week: 2_000,
            gps_seconds_of_week: t,
            position_ecef_m: [7e6, t, -t],
            velocity_ecef_mps: None,
        })
    }

    proptest! {
        /// Records split at arbitrary points across polls, with garbage bytes between some of
        /// them and records of the other sensor mixed in, come out complete, in order, with
        /// the garbage counted as resync bytes and the foreign records as wrong kind.
        #[test]
        fn split_corrupted_and_mixed_streams_deliver_every_record(
            layout in proptest::collection::vec((any::<bool>(), 0_usize..5), 1..12),
            chunks in proptest::collection::vec(1_usize..200, 1..400),
        ) {
            let mut bytes = Vec::new();
            let mut expected = Vec::new();
            let mut foreign = 0_u32;
            let mut garbage = 0_u32;
            for (k, (is_star, noise)) in (0_u32..).zip(layout.iter()) {
                // Garbage that never decodes: bytes equal to 0xFF are not a valid tag.
                bytes.extend(std::iter::repeat_n(0xFF_u8, *noise));
                garbage += u32::try_from(*noise).unwrap();
                if *is_star {
                    bytes.extend(star(k).encode().unwrap());
                    expected.push(k);
                } else {
                    bytes.extend(gnss(k).encode().unwrap());
                    foreign += 1;
                }
            }
            let line = ChunkedLine { bytes, position: 0, ready: 0 };
            let mut port = StreamStarSensor(RecordReader::new(line));
            let mut received = Vec::new();
            for chunk in chunks {
                port.0.device.ready += chunk;
                for _ in 0..4 {
                    if let Some(measurement) = port.poll() {
                        received.push(measurement.time_tag_s);
                    }
                }
            }
            // Drain what is left.
            port.0.device.ready = usize::MAX / 2;
            for _ in 0..200 {
                if let Some(measurement) = port.poll() {
                    received.push(measurement.time_tag_s);
                }
            }
            let expected: Vec<f64> = expected.into_iter().map(f64::from).collect();
            prop_assert_eq!(received.iter().map(|t| t.to_bits()).collect::<Vec<_>>(),
                            expected.iter().map(|t| t.to_bits()).collect::<Vec<_>>());
            let counters = port.0.counters();
            prop_assert_eq!(counters.resync_bytes, garbage);
            prop_assert_eq!(counters.wrong_kind, foreign);
            prop_assert_eq!(counters.read_errors, 0);
        }
    }

    #[test]
    fn a_poll_reads_no_more_than_its_bound() {
        let mut bytes = Vec::new();
        for k in 0..10 {
            bytes.extend(gnss(k).encode().unwrap());
        }
        let line = ChunkedLine {
            bytes,
            position: 0,
            ready: usize::MAX / 2,
        };
        // A star port on a GNSS-only line: each call looks at no more than
        // MAX_RECORDS_PER_POLL records and returns nothing.
        let mut port = StreamStarSensor(RecordReader::new(line));
        assert!(port.poll().is_none());
        assert_eq!(port.0.counters().wrong_kind, 4);
        assert_eq!(port.0.device.position, 4 * RECORD_SIZE);
        assert!(port.poll().is_none());
        assert_eq!(port.0.counters().wrong_kind, 8);
    }

    /// Mutation-testing boundaries: one `next_record` call reads at most
    /// [`MAX_BYTES_PER_POLL`] bytes, and that is enough to skip a record's worth of garbage and
    /// deliver the record behind it (the last byte read completes it).
    #[test]
    fn one_call_reads_at_most_two_records_of_bytes_and_uses_all_of_them() {
        let line = |garbage: usize| {
            let mut bytes = vec![0xFF_u8; garbage];
            bytes.extend(star(7).encode().unwrap());
            ChunkedLine {
                bytes,
                position: 0,
                ready: usize::MAX / 2,
            }
        };
        let mut reader = RecordReader::new(line(RECORD_SIZE));
        assert_eq!(reader.next_record(), Some(star(7)));
        assert_eq!(reader.device.position, MAX_BYTES_PER_POLL);
        assert_eq!(reader.counters().resync_bytes, 80);
        let mut reader = RecordReader::new(line(300));
        assert_eq!(reader.next_record(), None);
        assert_eq!(reader.device.position, MAX_BYTES_PER_POLL);
    }

    /// Each port takes its own kind from a shared line and counts the others.
    #[test]
    fn imu_and_gnss_ports_deliver_their_records() {
        let imu = LogRecord::Imu(ImuRecord {
            sequence: 42,
            time_s: 1.0,
            interval_s: 0.002,
            delta_angle_rad: [1e-4, 0.0, -1e-4],
            delta_velocity_mps: [0.0, 2e-3, 0.0],
        });
        let mut bytes = Vec::new();
        for record in [star(1), imu, gnss(2)] {
            bytes.extend(record.encode().unwrap());
        }
        let line = || ChunkedLine {
            bytes: bytes.clone(),
            position: 0,
            ready: usize::MAX / 2,
        };
        let mut imu_port = StreamImu(RecordReader::new(line()));
        let sample = imu_port.read().unwrap();
        assert_eq!(sample.sequence, 42);
        assert_eq!(sample.delta_velocity_mps[1].to_bits(), 2e-3_f64.to_bits());
        assert_eq!(imu_port.0.counters().wrong_kind, 1);
        let mut gnss_port = StreamGnss(RecordReader::new(line()));
        let fix = gnss_port.poll().unwrap();
        assert_eq!(
            fix.position_ecef_m.map(f64::to_bits),
            [7e6, 2.0, -2.0].map(f64::to_bits)
        );
        assert_eq!(gnss_port.0.counters().wrong_kind, 2);
    }
}
