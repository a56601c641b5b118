//! Separate sensor streams back into one log: a flight computer hears each sensor on its own
//! line (UART), while the frame assembler ([`crate::replay::FrameAssembler`]) takes one
//! sequence in arrival order. [`ArrivalMerge`] holds the next record of each stream and hands
//! out the earliest; records that arrive at the same time come IMU first, then star, then
//! GNSS, the order the simulator writes a frame's records in. The assembler places records by
//! time, so the frames are the same as from the single log the streams were split from
//! (every stream keeps its own order, and records of one arrival time belong to one frame).
//!
//! The host and the QEMU firmware run this same code on the same bytes, so a replay over
//! UARTs is bit for bit the host's, corrupted streams included.

use embedded_io::{ErrorType, Read, ReadReady};

use crate::log_record::LogRecord;
use crate::stream_ports::{RecordReader, StreamCounters};

/// Polls a [`LineSource`] makes for its next record while its line has no byte ready, before
/// it takes the line as ended: with a UART polled in a tight loop, seconds of silence.
pub const MAX_IDLE_POLLS: u32 = 100_000_000;

/// One sensor's stream of records, in its own arrival order.
pub trait RecordSource {
    /// The stream's next record, waiting for it if the stream has not ended; `None` once the
    /// stream has ended.
    fn next_record(&mut self) -> Option<LogRecord>;
}

/// A byte stream that knows when it has delivered its last byte (a recorded line being
/// played back, whose length is known).
pub trait FiniteStream {
    /// Every byte has been read.
    fn exhausted(&self) -> bool;
}

/// A sensor line (a byte stream carrying the log's 80-byte records, corrupt bytes and all) as
/// a [`RecordSource`]: [`RecordReader`] finds the records and resynchronises after corrupt
/// bytes; the line has ended when its last byte is read and no record is left.
#[derive(Debug)]
pub struct LineSource<R>(pub RecordReader<R>);

impl<R: Read + ReadReady + FiniteStream> RecordSource for LineSource<R> {
    fn next_record(&mut self) -> Option<LogRecord> {
        for _ in 0..MAX_IDLE_POLLS {
            if let Some(record) = self.0.next_record() {
                return Some(record);
            }
            if self.0.device().exhausted() {
                return None;
            }
        }
        None
    }
}

impl<R: Read + ReadReady> LineSource<R> {
    /// What the line's reader counted: records, resynchronisation bytes, wrong kinds.
    pub fn counters(&self) -> StreamCounters {
        self.0.counters()
    }
}

/// A recorded line in memory: the bytes a sensor sent, played back at once.
#[derive(Debug, Clone, Copy)]
pub struct RecordedLine<'a>(pub &'a [u8]);

impl ErrorType for RecordedLine<'_> {
    type Error = core::convert::Infallible;
}

impl Read for RecordedLine<'_> {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        self.0.read(buf)
    }
}

impl ReadReady for RecordedLine<'_> {
    fn read_ready(&mut self) -> Result<bool, Self::Error> {
        Ok(!self.0.is_empty())
    }
}

impl FiniteStream for RecordedLine<'_> {
    fn exhausted(&self) -> bool {
        self.0.is_empty()
    }
}

/// Which stream a record of the merge came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SensorStream {
    /// The IMU's line.
    Imu,
    /// The star tracker's line.
    Star,
    /// The GNSS receiver's line.
    Gnss,
}

impl SensorStream {
    /// Every stream, in the order records of equal arrival time are handed out.
    pub const ALL: [Self; 3] = [Self::Imu, Self::Star, Self::Gnss];

    /// Position in [`Self::ALL`].
    pub const fn index(self) -> usize {
        match self {
            Self::Imu => 0,
            Self::Star => 1,
            Self::Gnss => 2,
        }
    }
}

/// The three sensor streams merged into arrival order.
///
/// # Examples
/// ```
/// use nav_fsw::log_record::{LogRecord, StarRecord};
/// use nav_fsw::stream_merge::{ArrivalMerge, RecordSource};
///
/// struct Listed(std::vec::IntoIter<LogRecord>);
/// impl RecordSource for Listed {
///     fn next_record(&mut self) -> Option<LogRecord> {
///         self.0.next()
///     }
/// }
/// let star = |arrival_time_s| LogRecord::Star(StarRecord {
///     arrival_time_s,
///     time_tag_s: arrival_time_s,
///     attitude_wxyz: [1.0, 0.0, 0.0, 0.0],
///     head: 0,
/// });
/// let none = || Listed(Vec::new().into_iter());
/// let stars = Listed(vec![star(0.1), star(0.3)].into_iter());
/// let mut merge = ArrivalMerge::new(none(), stars, none());
/// let times: Vec<f64> = core::iter::from_fn(|| merge.next_record())
///     .map(|record| record.arrival_time_s())
///     .collect();
/// assert_eq!(times.len(), 2);
/// assert!(times[0] < times[1]);
/// ```
#[derive(Debug)]
pub struct ArrivalMerge<I, S, G> {
    imu: I,
    star: S,
    gnss: G,
    /// The next record of each stream (indexed by [`SensorStream::index`]).
    pending: [Option<LogRecord>; 3],
    /// Streams that have ended.
    ended: [bool; 3],
}

impl<I: RecordSource, S: RecordSource, G: RecordSource> ArrivalMerge<I, S, G> {
    /// A merge of the IMU, star-tracker and GNSS streams.
    pub fn new(imu: I, star: S, gnss: G) -> Self {
        Self {
            imu,
            star,
            gnss,
            pending: [None; 3],
            ended: [false; 3],
        }
    }

    /// The sources, to read their counters.
    pub fn sources(&self) -> (&I, &S, &G) {
        (&self.imu, &self.star, &self.gnss)
    }

    /// The earliest-arriving record of all streams (waiting for every stream that has not
    /// ended to offer one); `None` once every stream has ended.
    pub fn next_record(&mut self) -> Option<LogRecord> {
        for stream in SensorStream::ALL {
            self.refill(stream);
        }
        let mut earliest: Option<(usize, f64)> = None;
        for (index, record) in self.pending.iter().enumerate() {
            let Some(record) = record else {
                continue;
            };
            let arrival_s = record.arrival_time_s();
            // Strictly earlier only: of equal arrival times, the first stream in ALL wins.
            if earliest.is_none_or(|(_, best_s)| arrival_s < best_s) {
                earliest = Some((index, arrival_s));
            }
        }
        let (index, _) = earliest?;
        self.pending.get_mut(index).and_then(Option::take)
    }

    fn refill(&mut self, stream: SensorStream) {
        let index = stream.index();
        let (Some(slot), Some(ended)) = (self.pending.get_mut(index), self.ended.get_mut(index))
        else {
            return;
        };
        if slot.is_some() || *ended {
            return;
        }
        *slot = match stream {
            SensorStream::Imu => self.imu.next_record(),
            SensorStream::Star => self.star.next_record(),
            SensorStream::Gnss => self.gnss.next_record(),
        };
        *ended = slot.is_none();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Listed(std::vec::IntoIter<LogRecord>);

    impl RecordSource for Listed {
        fn next_record(&mut self) -> Option<LogRecord> {
            self.0.next()
        }
    }

    use crate::log_record::test_records::{gnss, star};

    fn imu(time_s: f64) -> LogRecord {
        crate::log_record::test_records::imu(0, time_s, 0.002)
    }

    fn listed(records: Vec<LogRecord>) -> Listed {
        Listed(records.into_iter())
    }

    /// A log in delivery order, split by kind and merged, comes back as it was.
    #[test]
    fn split_streams_merge_back_into_the_log_s_order() {
        let log = vec![
            imu(0.002),
            star(0.002),
            gnss(0.002),
            imu(0.004),
            gnss(0.005),
            imu(0.006),
            star(0.007),
            imu(0.008),
        ];
        let of_kind = |tag: u8| {
            listed(
                log.iter()
                    .copied()
                    .filter(|record| record.tag() == tag)
                    .collect(),
            )
        };
        let mut merge = ArrivalMerge::new(of_kind(1), of_kind(2), of_kind(3));
        let merged: Vec<LogRecord> = core::iter::from_fn(|| merge.next_record()).collect();
        assert_eq!(merged, log);
    }

    /// Bytes of noise between two records of a line are dropped and counted; every record
    /// still arrives, in order.
    #[test]
    fn a_line_with_noise_between_records_still_delivers_every_record() {
        let records = [star(0.1), star(0.2), star(0.3)];
        let mut bytes = Vec::new();
        for (index, record) in records.iter().enumerate() {
            bytes.extend_from_slice(&record.encode().unwrap());
            if index == 0 {
                bytes.extend_from_slice(&[0xFF, 0x02, 0x00]);
            }
        }
        let mut line = LineSource(RecordReader::new(RecordedLine(&bytes)));
        let read: Vec<LogRecord> = core::iter::from_fn(|| line.next_record()).collect();
        assert_eq!(read, records);
        assert_eq!(line.counters().resync_bytes, 3);
        assert_eq!(line.counters().records, 3);
    }

    /// Of records arriving together the IMU's comes first, then the star tracker's, then the
    /// receiver's, whichever stream offers its record first.
    #[test]
    fn equal_arrival_times_come_imu_star_gnss() {
        let mut merge = ArrivalMerge::new(
            listed(vec![imu(0.004)]),
            listed(vec![star(0.004)]),
            listed(vec![gnss(0.002), gnss(0.004)]),
        );
        let tags: Vec<u8> = core::iter::from_fn(|| merge.next_record())
            .map(|record| record.tag())
            .collect();
        assert_eq!(tags, [3, 1, 2, 3]);
    }
}
