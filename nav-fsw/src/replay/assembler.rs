//! Records placed in frames by their own times: the frame grid and the assembler.

use super::FramePorts;
use crate::log_record::LogRecord;

/// Longest stretch of a log without records that the replay bridges with frames (s):
/// [`FrameGrid::max_gap_s`] of [`super::ReplaySetup::frame_grid`]. Ten seconds is 5,000 frames at
/// 500 Hz, longer than any IMU dropout a flight computer rides through by holding its last
/// sample; a longer silence in a log is a clock fault or a spliced recording, refused.
pub const DEFAULT_MAX_GAP_S: f64 = 10.0;

/// Most frames a [`FrameGrid::max_gap_s`] may span (1,000 s at 500 Hz): bounds the frames
/// one record can release, and so the caller's loop over [`FrameAssembler::next_frame`].
pub const MAX_GAP_FRAMES: u32 = 500_000;

/// Where the frames of a replay fall in navigation time. Frame `n` (1-based) runs from
/// `start_time_s + (n − 1)·period_s` to `start_time_s + n·period_s`, as the flight software
/// advances its navigation time one period per frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameGrid {
    /// Navigation time at the start of the first frame: the initial solution's time (s).
    pub start_time_s: f64,
    /// Frame period, the IMU's sampling period (s).
    pub period_s: f64,
    /// Accepted deviation, as a fraction of the period, of an IMU record's `interval_s` from
    /// the period and of a measurement's arrival past the end of a frame (the flight
    /// software's `imu.period_tolerance`). In `(0, 0.5)`.
    pub tolerance: f64,
    /// Longest stretch without records bridged by frames (s); a longer one is refused.
    pub max_gap_s: f64,
}

impl FrameGrid {
    /// End time of frame `frame` (1-based) (s).
    fn frame_end_s(&self, frame: u32) -> f64 {
        self.start_time_s + f64::from(frame) * self.period_s
    }

    fn validate(&self) -> Result<(), FrameAssemblyError> {
        let valid = self.start_time_s.is_finite()
            && self.period_s.is_finite()
            && self.period_s > 0.0
            && self.tolerance > 0.0
            && self.tolerance < 0.5
            && self.max_gap_s >= 0.0
            && self.max_gap_s <= self.period_s * f64::from(MAX_GAP_FRAMES);
        if valid {
            Ok(())
        } else {
            Err(FrameAssemblyError::InvalidGrid)
        }
    }
}

/// Why the frame assembler refused a record (the assembler is unchanged).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FrameAssemblyError {
    /// The [`FrameGrid`] is not usable (non-finite, non-positive period, tolerance outside
    /// `(0, 0.5)`, a gap negative or longer than [`MAX_GAP_FRAMES`] periods).
    InvalidGrid,
    /// A record's time is NaN or infinite.
    NonFiniteTime,
    /// An IMU record's sampling interval differs from the frame period by more than the
    /// tolerance: the log was recorded at another rate.
    ImuInterval {
        /// The record's `interval_s` (s).
        interval_s: f64,
        /// The frame period (s).
        period_s: f64,
    },
    /// The first IMU record does not end the first frame: the log's time base differs from
    /// the initial solution's.
    TimeBase {
        /// The first IMU record's time tag (s).
        first_imu_time_s: f64,
        /// End of the first frame (s).
        first_frame_end_s: f64,
    },
    /// A record lies farther past the frame being assembled than [`FrameGrid::max_gap_s`].
    Gap {
        /// End of the frame being assembled (s).
        from_s: f64,
        /// The record's time (s).
        to_s: f64,
        /// The limit (s).
        max_gap_s: f64,
    },
    /// [`FrameAssembler::push`] was called before [`FrameAssembler::next_frame`] returned
    /// `None`.
    NotDrained,
    /// A record was pushed after [`FrameAssembler::finish`], or the frame counter is full.
    Finished,
}

impl core::fmt::Display for FrameAssemblyError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::InvalidGrid => write!(f, "invalid frame grid (period, tolerance or gap)"),
            Self::NonFiniteTime => write!(f, "a record's time is not finite"),
            Self::ImuInterval {
                interval_s,
                period_s,
            } => write!(
                f,
                "IMU interval_s {interval_s} s does not match the IMU period {period_s} s of the setup"
            ),
            Self::TimeBase {
                first_imu_time_s,
                first_frame_end_s,
            } => write!(
                f,
                "the first IMU sample ends at {first_imu_time_s} s, but the first frame after the \
                 initial solution ends at {first_frame_end_s} s"
            ),
            Self::Gap {
                from_s,
                to_s,
                max_gap_s,
            } => write!(
                f,
                "a jump from {from_s} s to {to_s} s is longer than the replay bridges ({max_gap_s} s)"
            ),
            Self::NotDrained => write!(f, "a record was pushed before the ready frames were taken"),
            Self::Finished => write!(f, "a record was pushed after the end of the log"),
        }
    }
}

impl core::error::Error for FrameAssemblyError {}

/// What the assembler did with the log's records, cumulative.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AssemblyCounts {
    /// Frames assembled.
    pub frames: u32,
    /// Frames without an IMU record (the flight software holds its last sample).
    pub frames_without_imu: u32,
    /// IMU records dropped: a second record for a frame that already has one (a duplicated
    /// record) or a record for a frame already assembled (out of order).
    pub imu_records_dropped: u32,
    /// Measurements delivered in their frame's ports.
    pub measurements_delivered: u32,
    /// Measurements dropped because their frame's ports were full.
    pub measurements_dropped: u32,
}

/// Builds frames from the log's records, each record placed in navigation time by its own
/// time (module docs): an IMU record in the frame it ends (nearest frame end), a measurement
/// in the first frame that ends at or after its arrival (within the tolerance). Frames the log
/// has no IMU record for are assembled without one, as a live IMU port that delivered nothing.
///
/// Use: [`Self::push`] each record, then take frames with [`Self::next_frame`] until `None`;
/// at the end of the log [`Self::finish`] and take the last frames.
///
/// # Examples
/// ```
/// use nav_fsw::log_record::{ImuRecord, LogRecord};
/// use nav_fsw::replay::{FrameAssembler, FrameGrid};
///
/// let grid = FrameGrid { start_time_s: 0.0, period_s: 0.002, tolerance: 0.1, max_gap_s: 10.0 };
/// let mut assembler = FrameAssembler::new(grid)?;
/// let imu = |sequence: u64, time_s: f64| LogRecord::Imu(ImuRecord {
///     sequence,
///     time_s,
///     interval_s: 0.002,
///     delta_angle_rad: [0.0; 3],
///     delta_velocity_mps: [0.0; 3],
/// });
/// // Sample 2 (ending at 6 ms) is missing from the log.
/// let mut frames = Vec::new();
/// for record in [imu(0, 0.002), imu(1, 0.004), imu(3, 0.008)] {
///     assembler.push(&record)?;
///     while let Some(frame) = assembler.next_frame() {
///         frames.push(frame);
///     }
/// }
/// assembler.finish();
/// while let Some(frame) = assembler.next_frame() {
///     frames.push(frame);
/// }
/// let sequences: Vec<_> = frames.iter().map(|f| f.imu.0.map(|s| s.sequence)).collect();
/// assert_eq!(sequences, [Some(0), Some(1), None, Some(3)]);
/// assert_eq!(assembler.counts().frames_without_imu, 1);
/// # Ok::<(), nav_fsw::replay::FrameAssemblyError>(())
/// ```
#[derive(Debug, Clone)]
pub struct FrameAssembler {
    grid: FrameGrid,
    /// The frame being assembled (1-based).
    frame: u32,
    pending: FramePorts,
    /// A record that belongs to a later frame than the one being assembled.
    ahead: Option<LogRecord>,
    imu_seen: bool,
    ended: bool,
    counts: AssemblyCounts,
}

impl FrameAssembler {
    /// An assembler for `grid`.
    ///
    /// # Errors
    /// [`FrameAssemblyError::InvalidGrid`].
    pub fn new(grid: FrameGrid) -> Result<Self, FrameAssemblyError> {
        grid.validate()?;
        Ok(Self {
            grid,
            frame: 1,
            pending: FramePorts::default(),
            ahead: None,
            imu_seen: false,
            ended: false,
            counts: AssemblyCounts::default(),
        })
    }

    /// Takes the next record of the log (delivery order).
    ///
    /// # Errors
    /// [`FrameAssemblyError`]: the record is refused and the assembler is unchanged.
    pub fn push(&mut self, record: &LogRecord) -> Result<(), FrameAssemblyError> {
        if self.ended || self.frame == u32::MAX {
            return Err(FrameAssemblyError::Finished);
        }
        if self.ahead.is_some() {
            return Err(FrameAssemblyError::NotDrained);
        }
        let time_s = record_time_s(record);
        if !time_s.is_finite() {
            return Err(FrameAssemblyError::NonFiniteTime);
        }
        self.check_interval(record)?;
        let frame_end_s = self.grid.frame_end_s(self.frame);
        if !self.imu_seen {
            return self.push_before_first_imu(record, time_s, frame_end_s);
        }
        if time_s > frame_end_s + self.grid.max_gap_s + self.tolerance_s() {
            return Err(FrameAssemblyError::Gap {
                from_s: frame_end_s,
                to_s: time_s,
                max_gap_s: self.grid.max_gap_s,
            });
        }
        if self.belongs_to_frame(record, time_s, frame_end_s) {
            self.place(record, time_s, frame_end_s);
        } else {
            self.ahead = Some(*record);
        }
        Ok(())
    }

    /// The end of the log: the frame being assembled is complete. A log without an IMU
    /// record has no frame: its measurements are counted as dropped.
    pub fn finish(&mut self) {
        self.ended = true;
        if !self.imu_seen {
            let pending = core::mem::take(&mut self.pending);
            let dropped = pending.dropped.saturating_add(pending.measurements());
            self.counts.measurements_dropped =
                self.counts.measurements_dropped.saturating_add(dropped);
        }
    }

    /// The next complete frame, if any.
    pub fn next_frame(&mut self) -> Option<FramePorts> {
        let has_content = self.pending.imu.0.is_some()
            || self.pending.measurements() > 0
            || self.pending.dropped > 0;
        let complete = self.ahead.is_some() || (self.ended && has_content);
        if !complete {
            return None;
        }
        let frame = core::mem::take(&mut self.pending);
        self.count_frame(&frame);
        self.frame = self.frame.saturating_add(1);
        if self.frame == u32::MAX {
            // The frame counter is full (99 days at 500 Hz): the log ends here.
            if let Some(record) = self.ahead.take() {
                self.count_dropped(&record);
            }
            self.ended = true;
        }
        if let Some(record) = self.ahead {
            let time_s = record_time_s(&record);
            let frame_end_s = self.grid.frame_end_s(self.frame);
            if self.belongs_to_frame(&record, time_s, frame_end_s) {
                self.ahead = None;
                self.place(&record, time_s, frame_end_s);
            }
        }
        Some(frame)
    }

    /// The next complete frame, taking records from `source` (delivery order; `None` at its
    /// end, after which the assembler finishes and `source` is not called again) until one
    /// is ready; `Ok(None)` once every frame has been taken. Each pass of the loop consumes
    /// one record, so it ends with the source.
    ///
    /// # Errors
    /// [`FrameAssemblyError`] for a refused record ([`FrameAssembler::push`]); the records
    /// taken before it stay in the assembler.
    ///
    /// # Examples
    /// ```
    /// use nav_fsw::log_record::{ImuRecord, LogRecord};
    /// use nav_fsw::replay::{FrameAssembler, FrameGrid};
    ///
    /// let grid = FrameGrid { start_time_s: 0.0, period_s: 0.002, tolerance: 0.1, max_gap_s: 10.0 };
    /// let mut assembler = FrameAssembler::new(grid)?;
    /// let imu = |sequence: u64, time_s: f64| LogRecord::Imu(ImuRecord {
    ///     sequence,
    ///     time_s,
    ///     interval_s: 0.002,
    ///     delta_angle_rad: [0.0; 3],
    ///     delta_velocity_mps: [0.0; 3],
    /// });
    /// // Sample 2 (ending at 6 ms) is missing from the log.
    /// let mut log = [imu(0, 0.002), imu(1, 0.004), imu(3, 0.008)].into_iter();
    /// let mut sequences = Vec::new();
    /// while let Some(frame) = assembler.next_frame_from(|| log.next())? {
    ///     sequences.push(frame.imu.0.map(|s| s.sequence));
    /// }
    /// assert_eq!(sequences, [Some(0), Some(1), None, Some(3)]);
    /// # Ok::<(), nav_fsw::replay::FrameAssemblyError>(())
    /// ```
    pub fn next_frame_from(
        &mut self,
        mut source: impl FnMut() -> Option<LogRecord>,
    ) -> Result<Option<FramePorts>, FrameAssemblyError> {
        let mut next = self.next_frame();
        while next.is_none() && !self.ended {
            match source() {
                Some(record) => self.push(&record)?,
                None => self.finish(),
            }
            next = self.next_frame();
        }
        Ok(next)
    }

    /// What the assembler did so far.
    pub fn counts(&self) -> AssemblyCounts {
        self.counts
    }

    fn tolerance_s(&self) -> f64 {
        self.grid.tolerance * self.grid.period_s
    }

    fn check_interval(&self, record: &LogRecord) -> Result<(), FrameAssemblyError> {
        let LogRecord::Imu(imu) = record else {
            return Ok(());
        };
        // Written so that NaN fails too.
        if (imu.interval_s - self.grid.period_s).abs() <= self.tolerance_s() {
            Ok(())
        } else {
            Err(FrameAssemblyError::ImuInterval {
                interval_s: imu.interval_s,
                period_s: self.grid.period_s,
            })
        }
    }

    /// Until the first IMU record every measurement joins the first frame, whose IMU record
    /// must be the log's first (the time base check).
    fn push_before_first_imu(
        &mut self,
        record: &LogRecord,
        time_s: f64,
        frame_end_s: f64,
    ) -> Result<(), FrameAssemblyError> {
        if let LogRecord::Imu(_) = record {
            if (time_s - frame_end_s).abs() > self.tolerance_s() {
                return Err(FrameAssemblyError::TimeBase {
                    first_imu_time_s: time_s,
                    first_frame_end_s: frame_end_s,
                });
            }
            self.imu_seen = true;
        }
        self.place(record, time_s, frame_end_s);
        Ok(())
    }

    /// An IMU record belongs to the frame whose end is nearest its time tag; a measurement to
    /// the first frame that ends at or after its arrival (within the tolerance).
    fn belongs_to_frame(&self, record: &LogRecord, time_s: f64, frame_end_s: f64) -> bool {
        let reach_s = match record {
            LogRecord::Imu(_) => 0.5 * self.grid.period_s,
            LogRecord::Star(_) | LogRecord::Gnss(_) => self.tolerance_s(),
        };
        time_s <= frame_end_s + reach_s
    }

    fn place(&mut self, record: &LogRecord, time_s: f64, frame_end_s: f64) {
        let late = time_s <= frame_end_s - 0.5 * self.grid.period_s;
        match record {
            LogRecord::Imu(_) if late || self.pending.imu.0.is_some() => {
                self.count_dropped(record);
            }
            _ => self.pending.add(record),
        }
    }

    fn count_dropped(&mut self, record: &LogRecord) {
        let counter = match record {
            LogRecord::Imu(_) => &mut self.counts.imu_records_dropped,
            LogRecord::Star(_) | LogRecord::Gnss(_) => &mut self.counts.measurements_dropped,
        };
        *counter = counter.saturating_add(1);
    }

    fn count_frame(&mut self, frame: &FramePorts) {
        let c = &mut self.counts;
        c.frames = c.frames.saturating_add(1);
        if frame.imu.0.is_none() {
            c.frames_without_imu = c.frames_without_imu.saturating_add(1);
        }
        c.measurements_delivered = c
            .measurements_delivered
            .saturating_add(frame.measurements());
        c.measurements_dropped = c.measurements_dropped.saturating_add(frame.dropped);
    }
}

/// The time a record is placed by: an IMU record's time tag (the end of its interval), a
/// measurement's arrival.
fn record_time_s(record: &LogRecord) -> f64 {
    match record {
        LogRecord::Imu(imu) => imu.time_s,
        LogRecord::Star(star) => star.arrival_time_s,
        LogRecord::Gnss(gnss) => gnss.arrival_time_s,
    }
}
