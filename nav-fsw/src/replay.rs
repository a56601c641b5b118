//! Replay: a recorded sensor log fed to the flight software frame by frame, identically on
//! the host and on the target, with a fixed-layout output record per frame so the two can be
//! compared bit for bit.
//!
//! * [`FramePorts`]: the port contents of one frame (the IMU sample and the measurements
//!   delivered with it); the simulator fills them live, the replay from the log.
//! * [`FrameAssembler`]: places the log's records (`crate::log_record`, delivery order) in
//!   frames by their own times on the [`FrameGrid`] the setup defines: an IMU record in the
//!   frame it ends, a measurement in the frame it arrives by. A frame the log has no IMU
//!   record for runs without one (the flight software holds and counts it, as live), a second
//!   IMU record for a frame is dropped and counted, and a log at another IMU rate, on another
//!   time base or with a jump longer than [`FrameGrid::max_gap_s`] is refused.
//! * [`ReplaySetup`]: what a scenario decides about the flight software (launch site, initial
//!   navigation solution, filter, noise, gates), as 8-byte words, so the target builds the
//!   very configuration the host built ([`ReplaySetup::config`]).
//! * [`output_words`]: the frame's output record, [`OUTPUT_WORDS`] little-endian 8-byte
//!   words named by [`OUTPUT_FIELD_NAMES`] (floats as their bit patterns).

use heapless::Deque;
use nalgebra::{Quaternion, Vector3};
use nav_core::error_model::ProcessNoise;
use nav_core::filter::{FilterMode, InitialUncertainty};
use nav_core::frames::LaunchSite;
use nav_core::strapdown::NavigationState;

use crate::config::FswConfig;
use crate::error::{ConfigField, FswError};
use crate::log_record::LogRecord;
use crate::ports::{GnssFix, GnssPort, ImuPort, ImuSample, StarMeasurement, StarSensorPort};
use crate::scheduler::NavigationComputer;
use crate::sensor_frames::SensorFrames;
use crate::telemetry::{FrameFusion, FrameTelemetry};

/// Most star measurements one frame can carry (more are counted as dropped).
pub const FRAME_STAR_CAPACITY: usize = 8;
/// Most GNSS fixes one frame can carry.
pub const FRAME_GNSS_CAPACITY: usize = 4;

/// The IMU port of one frame.
#[derive(Debug, Clone, Default)]
pub struct FrameImu(pub Option<ImuSample>);

impl ImuPort for FrameImu {
    fn read(&mut self) -> Option<ImuSample> {
        self.0.take()
    }
}

/// The star-sensor port of one frame.
#[derive(Debug, Clone, Default)]
pub struct FrameStar(pub Deque<StarMeasurement, FRAME_STAR_CAPACITY>);

impl StarSensorPort for FrameStar {
    fn poll(&mut self) -> Option<StarMeasurement> {
        self.0.pop_front()
    }
}

/// The GNSS port of one frame.
#[derive(Debug, Clone, Default)]
pub struct FrameGnss(pub Deque<GnssFix, FRAME_GNSS_CAPACITY>);

impl GnssPort for FrameGnss {
    fn poll(&mut self) -> Option<GnssFix> {
        self.0.pop_front()
    }
}

/// What the ports hold for one frame.
#[derive(Debug, Clone, Default)]
pub struct FramePorts {
    /// The IMU sample.
    pub imu: FrameImu,
    /// Star measurements delivered in the frame.
    pub star: FrameStar,
    /// GNSS fixes delivered in the frame.
    pub gnss: FrameGnss,
    /// Measurements that did not fit the frame's capacity (lost, counted here).
    pub dropped: u32,
}

impl FramePorts {
    /// Adds a record's content to the frame (an IMU record replaces the sample).
    pub fn add(&mut self, record: &LogRecord) {
        let refused = match record {
            LogRecord::Imu(imu) => {
                self.imu.0 = Some(imu.to_imu_sample());
                false
            }
            LogRecord::Star(star) => self.star.0.push_back(star.to_star_measurement()).is_err(),
            LogRecord::Gnss(gnss) => self.gnss.0.push_back(gnss.to_gnss_fix()).is_err(),
        };
        if refused {
            self.dropped = self.dropped.saturating_add(1);
        }
    }

    /// Star measurements and GNSS fixes the frame's ports hold.
    pub fn measurements(&self) -> u32 {
        let held = self.star.0.len().saturating_add(self.gnss.0.len());
        u32::try_from(held).unwrap_or(u32::MAX)
    }

    /// Runs the frame on `computer`.
    pub fn run(&mut self, computer: &mut NavigationComputer) -> FrameTelemetry {
        computer.run_frame(&mut self.imu, &mut self.star, &mut self.gnss)
    }
}

/// Longest stretch of a log without records that the replay bridges with frames (s):
/// [`FrameGrid::max_gap_s`] of [`ReplaySetup::frame_grid`]. Ten seconds is 5,000 frames at
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

/// Number of words of a [`ReplaySetup`].
pub const SETUP_WORDS: usize = 54;
/// First word of an encoded setup (`"NAVSETUP"` little-endian).
pub const SETUP_MAGIC: u64 = u64::from_le_bytes(*b"NAVSETUP");

/// The scenario-dependent part of the flight software's configuration and its initial
/// navigation solution; everything else is [`FswConfig::paper_defaults`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplaySetup {
    /// Launch site.
    pub launch_site: LaunchSite,
    /// The sensors' frames and time scales (ground constants).
    pub sensor_frames: SensorFrames,
    /// Initial navigation solution.
    pub initial: NavigationState,
    /// Filter mode.
    pub mode: FilterMode,
    /// Discretisation order.
    pub discretisation_order: u8,
    /// Initial 1σ.
    pub initial_sigma: InitialUncertainty,
    /// Noise densities.
    pub process_noise: ProcessNoise,
    /// IMU period (s).
    pub imu_period_s: f64,
    /// Star mounting `q_bs` `[w, x, y, z]`.
    pub star_mounting_wxyz: [f64; 4],
    /// Star noise 1σ (rad).
    pub star_noise_rad: f64,
    /// Star NIS gate.
    pub star_gate_nis: f64,
    /// GNSS noise 1σ (m).
    pub gnss_noise_m: f64,
    /// GNSS NIS gate.
    pub gnss_gate_nis: f64,
    /// Largest measurement latency (s).
    pub max_latency_s: f64,
    /// The receiver's correlated position error (`filter.gnss_error`).
    pub gnss_error: nav_core::gnss_error::GnssErrorModel,
    /// GNSS velocity noise 1σ (m/s); 0 = velocities not fused.
    pub gnss_velocity_noise_mps: f64,
    /// The gyro's measurement range per axis (rad/s).
    pub imu_max_rate_rad_s: f64,
    /// The accelerometer's measurement range per axis (m/s²).
    pub imu_max_specific_force_mps2: f64,
}

impl ReplaySetup {
    /// The flight software configuration.
    pub fn config(&self) -> FswConfig {
        let mut config = FswConfig::paper_defaults(self.launch_site, self.sensor_frames);
        config.filter.mode = self.mode;
        config.filter.discretisation_order = self.discretisation_order;
        config.filter.initial = self.initial_sigma;
        config.process_noise = self.process_noise;
        config.imu.period_s = self.imu_period_s;
        config.star.mounting_wxyz = self.star_mounting_wxyz;
        config.star.noise_rad = self.star_noise_rad;
        config.star.gate_nis = self.star_gate_nis;
        config.gnss.noise_m = self.gnss_noise_m;
        config.gnss.gate_nis = self.gnss_gate_nis;
        config.timing.max_latency_s = self.max_latency_s;
        config.filter.gnss_error = self.gnss_error;
        config.gnss.velocity_noise_mps = self.gnss_velocity_noise_mps;
        config.imu.max_rate_rad_s = self.imu_max_rate_rad_s;
        config.imu.max_specific_force_mps2 = self.imu_max_specific_force_mps2;
        config
    }

    /// The frames a replay with this setup runs: from the initial solution's time at the IMU
    /// period, with the flight software's IMU period tolerance and [`DEFAULT_MAX_GAP_S`].
    pub fn frame_grid(&self) -> FrameGrid {
        FrameGrid {
            start_time_s: self.initial.time_s,
            period_s: self.imu_period_s,
            tolerance: self.config().imu.period_tolerance,
            max_gap_s: DEFAULT_MAX_GAP_S,
        }
    }

    /// The setup as words.
    pub fn to_words(&self) -> [u64; SETUP_WORDS] {
        let site = &self.launch_site;
        let [kx, ky, kz] = site.earth_axis_ecef;
        let frames = &self.sensor_frames;
        let [gw, gx, gy, gz] = frames.gcrf_to_launch_inertial_wxyz;
        let q = &self.initial.attitude;
        let p = &self.initial.position_m;
        let v = &self.initial.velocity_mps;
        let s = &self.initial_sigma;
        let n = &self.process_noise;
        let [mw, mx, my, mz] = self.star_mounting_wxyz;
        let mode = match self.mode {
            FilterMode::OpenLoop => 0,
            FilterMode::ClosedLoop => 1,
        };
        let floats = [
            site.latitude_rad,
            site.longitude_rad,
            site.height_m,
            site.azimuth_rad,
            kx,
            ky,
            kz,
            gw,
            gx,
            gy,
            gz,
            frames.launch_epoch_gps_seconds_of_week,
            q.w,
            q.i,
            q.j,
            q.k,
            p.x,
            p.y,
            p.z,
            v.x,
            v.y,
            v.z,
            self.initial.time_s,
            s.attitude_rad,
            s.position_m,
            s.velocity_mps,
            s.gyro_bias_rad_s,
            s.accel_bias_mps2,
            s.star_installation_rad,
            s.gyro_scale_factor,
            s.accel_scale_factor,
            n.gyro_noise_density_rad_s_per_sqrt_hz,
            n.accel_noise_density_mps2_per_sqrt_hz,
            n.gyro_bias_walk_rad_s2_per_sqrt_hz,
            n.accel_bias_walk_mps3_per_sqrt_hz,
            self.imu_period_s,
            mw,
            mx,
            my,
            mz,
            self.star_noise_rad,
            self.star_gate_nis,
            self.gnss_noise_m,
            self.gnss_gate_nis,
            self.max_latency_s,
            self.gnss_error.sigma_m,
            self.gnss_error.correlation_time_s,
            self.gnss_velocity_noise_mps,
            self.imu_max_rate_rad_s,
            self.imu_max_specific_force_mps2,
        ];
        let mut words = [0_u64; SETUP_WORDS];
        let mut slots = words.iter_mut();
        let header = [
            SETUP_MAGIC,
            mode,
            u64::from(self.discretisation_order),
            u64::from(frames.launch_epoch_gps_week),
        ];
        // `header` first: zip polls its first iterator first, so no slot is skipped.
        for (value, slot) in header.into_iter().zip(&mut slots) {
            *slot = value;
        }
        for (slot, value) in slots.zip(floats) {
            *slot = value.to_bits();
        }
        words
    }

    /// The setup from words.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] (`InitialNavigation`) for a bad magic or mode; the
    /// values themselves are checked by [`NavigationComputer::new`].
    pub fn from_words(words: &[u64; SETUP_WORDS]) -> Result<Self, FswError> {
        let bad = FswError::InvalidConfiguration(ConfigField::InitialNavigation);
        let [magic, mode, order, week, floats @ ..] = words;
        if *magic != SETUP_MAGIC {
            return Err(bad);
        }
        let mode = match mode {
            0 => FilterMode::OpenLoop,
            1 => FilterMode::ClosedLoop,
            _ => return Err(bad),
        };
        let order = u8::try_from(*order).map_err(|_| bad)?;
        let week = u32::try_from(*week).map_err(|_| bad)?;
        let f = floats.map(f64::from_bits);
        let [lat, lon, height, azimuth, kx, ky, kz, gw, gx, gy, gz, seconds_of_week, qw, qx, qy, qz, px, py, pz, vx, vy, vz, time, s_att, s_pos, s_vel, s_gb, s_ab, s_inst, s_gsf, s_asf, n_g, n_a, n_gw, n_aw, period, mw, mx, my, mz, star_noise, star_gate, gnss_noise, gnss_gate, latency, correlated_sigma, correlation_time, velocity_noise, max_rate, max_force] =
            f;
        Ok(Self {
            launch_site: LaunchSite {
                latitude_rad: lat,
                longitude_rad: lon,
                height_m: height,
                azimuth_rad: azimuth,
                earth_axis_ecef: [kx, ky, kz],
            },
            sensor_frames: SensorFrames {
                gcrf_to_launch_inertial_wxyz: [gw, gx, gy, gz],
                launch_epoch_gps_week: week,
                launch_epoch_gps_seconds_of_week: seconds_of_week,
            },
            initial: NavigationState {
                attitude: Quaternion::new(qw, qx, qy, qz),
                position_m: Vector3::new(px, py, pz),
                velocity_mps: Vector3::new(vx, vy, vz),
                time_s: time,
            },
            mode,
            discretisation_order: order,
            initial_sigma: InitialUncertainty {
                attitude_rad: s_att,
                position_m: s_pos,
                velocity_mps: s_vel,
                gyro_bias_rad_s: s_gb,
                accel_bias_mps2: s_ab,
                star_installation_rad: s_inst,
                gyro_scale_factor: s_gsf,
                accel_scale_factor: s_asf,
            },
            process_noise: ProcessNoise {
                gyro_noise_density_rad_s_per_sqrt_hz: n_g,
                accel_noise_density_mps2_per_sqrt_hz: n_a,
                gyro_bias_walk_rad_s2_per_sqrt_hz: n_gw,
                accel_bias_walk_mps3_per_sqrt_hz: n_aw,
            },
            imu_period_s: period,
            star_mounting_wxyz: [mw, mx, my, mz],
            star_noise_rad: star_noise,
            star_gate_nis: star_gate,
            gnss_noise_m: gnss_noise,
            gnss_gate_nis: gnss_gate,
            max_latency_s: latency,
            gnss_error: nav_core::gnss_error::GnssErrorModel {
                sigma_m: correlated_sigma,
                correlation_time_s: correlation_time,
            },
            gnss_velocity_noise_mps: velocity_noise,
            imu_max_rate_rad_s: max_rate,
            imu_max_specific_force_mps2: max_force,
        })
    }
}

/// Number of words of a frame's output record.
pub const OUTPUT_WORDS: usize = 77;

/// Names of the output words, in order.
pub const OUTPUT_FIELD_NAMES: [&str; OUTPUT_WORDS] = [
    "frame",
    "time_s",
    "attitude_w",
    "attitude_x",
    "attitude_y",
    "attitude_z",
    "position_x_m",
    "position_y_m",
    "position_z_m",
    "velocity_x_mps",
    "velocity_y_mps",
    "velocity_z_mps",
    "fusion",
    "last_star_nis",
    "last_gnss_nis",
    "star_faulty",
    "gnss_faulty",
    "converged_blocks",
    "frozen_blocks",
    "gyro_bias_x",
    "gyro_bias_y",
    "gyro_bias_z",
    "accel_bias_x",
    "accel_bias_y",
    "accel_bias_z",
    "star_installation_x",
    "star_installation_y",
    "star_installation_z",
    "gyro_scale_factor_x",
    "gyro_scale_factor_y",
    "gyro_scale_factor_z",
    "accel_scale_factor_x",
    "accel_scale_factor_y",
    "accel_scale_factor_z",
    "gyro_bias_sigma_x",
    "gyro_bias_sigma_y",
    "gyro_bias_sigma_z",
    "accel_bias_sigma_x",
    "accel_bias_sigma_y",
    "accel_bias_sigma_z",
    "star_installation_sigma_x",
    "star_installation_sigma_y",
    "star_installation_sigma_z",
    "gyro_scale_factor_sigma_x",
    "gyro_scale_factor_sigma_y",
    "gyro_scale_factor_sigma_z",
    "accel_scale_factor_sigma_x",
    "accel_scale_factor_sigma_y",
    "accel_scale_factor_sigma_z",
    "imu_non_finite",
    "imu_saturated",
    "imu_duplicate",
    "imu_missing",
    "imu_time_jump",
    "star_non_finite",
    "star_not_unit",
    "star_sign_flip",
    "gnss_non_finite",
    "gnss_jump",
    "measurement_stale",
    "measurement_future",
    "measurement_overflow",
    "star_gate_rejections",
    "gnss_gate_rejections",
    "covariance_clamps",
    "filter_resets",
    "star_declared_faulty",
    "gnss_declared_faulty",
    "ignored_from_faulty_sensor",
    "filter_errors",
    "strapdown_failures",
    "dropped_measurements",
    "last_gnss_velocity_nis",
    "gnss_velocity_gate_rejections",
    "imu_held_frames",
    "gnss_innovations_correlated",
    "imu_records_dropped",
];

/// The output record of a frame (module docs): telemetry (without the platform's frame cost,
/// which only the target measures), the calibration table and the assembler's counts (a live
/// run, without an assembler, passes its ports' dropped measurements in
/// [`AssemblyCounts::measurements_dropped`]).
pub fn output_words(
    telemetry: &FrameTelemetry,
    computer: &NavigationComputer,
    counts: &AssemblyCounts,
) -> [u64; OUTPUT_WORDS] {
    let t = telemetry;
    let h = &t.health;
    let fusion = match t.fusion {
        FrameFusion::None => 0,
        FrameFusion::StarAccepted => 1,
        FrameFusion::StarRejected => 2,
        FrameFusion::GnssAccepted => 3,
        FrameFusion::GnssRejected => 4,
        FrameFusion::GnssVelocityAccepted => 5,
        FrameFusion::GnssVelocityRejected => 6,
    };
    let mut words = [0_u64; OUTPUT_WORDS];
    let mut slots = words.iter_mut();
    let mut put = |value: u64| {
        if let Some(slot) = slots.next() {
            *slot = value;
        }
    };
    put(u64::from(t.frame));
    put(t.time_s.to_bits());
    for value in t.attitude_wxyz {
        put(value.to_bits());
    }
    for value in t.position_m.iter().chain(t.velocity_mps.iter()) {
        put(value.to_bits());
    }
    put(fusion);
    put(t.last_star_nis.to_bits());
    put(t.last_gnss_nis.to_bits());
    put(u64::from(t.star_faulty));
    put(u64::from(t.gnss_faulty));
    put(u64::from(t.converged_blocks));
    put(u64::from(t.frozen_blocks));
    let table = computer.calibration_table().entries();
    for (_, entry) in table {
        for value in entry.value {
            put(value.to_bits());
        }
    }
    for (_, entry) in table {
        for value in entry.sigma() {
            put(value.to_bits());
        }
    }
    let counters = [
        h.imu_non_finite,
        h.imu_saturated,
        h.imu_duplicate,
        h.imu_missing,
        h.imu_time_jump,
        h.star_non_finite,
        h.star_not_unit,
        h.star_sign_flip,
        h.gnss_non_finite,
        h.gnss_jump,
        h.measurement_stale,
        h.measurement_future,
        h.measurement_overflow,
        h.star_gate_rejections,
        h.gnss_gate_rejections,
        h.covariance_clamps,
        h.filter_resets,
        h.star_declared_faulty,
        h.gnss_declared_faulty,
        h.ignored_from_faulty_sensor,
        h.filter_errors,
        h.strapdown_failures,
        counts.measurements_dropped,
    ];
    for counter in counters {
        put(u64::from(counter));
    }
    put(t.last_gnss_velocity_nis.to_bits());
    put(u64::from(h.gnss_velocity_gate_rejections));
    put(u64::from(h.imu_held_frames));
    put(u64::from(h.gnss_innovations_correlated));
    put(u64::from(counts.imu_records_dropped));
    words
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::log_record::{GnssRecord, ImuRecord, StarRecord};

    const PERIOD_S: f64 = 0.002;
    const GRID: FrameGrid = FrameGrid {
        start_time_s: 100.0,
        period_s: PERIOD_S,
        tolerance: 0.1,
        max_gap_s: 1.0,
    };

    /// IMU sample `sequence`, ending frame `sequence + 1`.
    fn imu(sequence: u64) -> LogRecord {
        imu_at(sequence, end_of(sequence + 1))
    }

    fn imu_at(sequence: u64, time_s: f64) -> LogRecord {
        LogRecord::Imu(ImuRecord {
            sequence,
            time_s,
            interval_s: PERIOD_S,
            delta_angle_rad: [0.0; 3],
            delta_velocity_mps: [0.0; 3],
        })
    }

    fn end_of(frame: u64) -> f64 {
        GRID.start_time_s + PERIOD_S * f64::from(u32::try_from(frame).unwrap())
    }

    fn star(arrival_time_s: f64) -> LogRecord {
        LogRecord::Star(StarRecord {
            arrival_time_s,
            time_tag_s: arrival_time_s,
            attitude_wxyz: [1.0, 0.0, 0.0, 0.0],
        })
    }

    fn gnss(arrival_time_s: f64) -> LogRecord {
        LogRecord::Gnss(GnssRecord {
            arrival_time_s,
            gps_week: 2_000,
            gps_seconds_of_week: arrival_time_s,
            position_ecef_m: [7e6, 0.0, 0.0],
            velocity_ecef_mps: None,
        })
    }

    type FrameSummary = (Option<u32>, usize, usize);

    /// The frames of `records` as (IMU sequence, star count, GNSS count), and the counts.
    fn assemble(records: &[LogRecord]) -> (Vec<FrameSummary>, AssemblyCounts) {
        let mut assembler = FrameAssembler::new(GRID).unwrap();
        let mut frames = Vec::new();
        let mut take = |assembler: &mut FrameAssembler| {
            while let Some(frame) = assembler.next_frame() {
                let imu = frame.imu.0.map(|sample| sample.sequence);
                frames.push((imu, frame.star.0.len(), frame.gnss.0.len()));
            }
        };
        for record in records {
            assembler.push(record).unwrap();
            take(&mut assembler);
        }
        assembler.finish();
        take(&mut assembler);
        (frames, assembler.counts())
    }

    #[test]
    fn measurements_join_the_frame_they_arrive_by() {
        let records = [
            star(end_of(0)), // before the first IMU record: joins frame 1
            imu(0),
            gnss(end_of(1)),
            star(end_of(1) + 0.000_3), // after frame 1 ended (beyond 10 % of a period)
            imu(1),
            gnss(end_of(2) + 1e-12), // rounding of time tag + latency
        ];
        let (frames, counts) = assemble(&records);
        assert_eq!(frames, [(Some(0), 1, 1), (Some(1), 1, 1)]);
        assert_eq!(counts.measurements_delivered, 4);
        assert_eq!(counts.frames_without_imu, 0);
    }

    #[test]
    fn a_missing_imu_record_is_a_frame_without_a_sample_not_a_shift_of_time() {
        // Samples 1 and 2 are missing; a star measurement arrives in frame 3, in the gap.
        let records = [imu(0), star(end_of(3)), imu(3), gnss(end_of(4)), imu(4)];
        let (frames, counts) = assemble(&records);
        assert_eq!(
            frames,
            [
                (Some(0), 0, 0),
                (None, 0, 0),
                (None, 1, 0),
                (Some(3), 0, 1),
                (Some(4), 0, 0)
            ]
        );
        assert_eq!((counts.frames, counts.frames_without_imu), (5, 2));
    }

    #[test]
    fn duplicated_and_late_imu_records_are_dropped_and_counted() {
        let records = [imu(0), imu(0), imu(1), imu_at(7, end_of(1)), imu(2)];
        let (frames, counts) = assemble(&records);
        assert_eq!(frames, [(Some(0), 0, 0), (Some(1), 0, 0), (Some(2), 0, 0)]);
        assert_eq!(counts.imu_records_dropped, 2);
    }

    #[test]
    fn measurements_beyond_a_frames_ports_are_counted() {
        let mut records = vec![imu(0)];
        records.extend((0..12).map(|_| gnss(end_of(1))));
        let (frames, counts) = assemble(&records);
        assert_eq!(frames, [(Some(0), 0, FRAME_GNSS_CAPACITY)]);
        assert_eq!(counts.measurements_delivered, 4);
        assert_eq!(counts.measurements_dropped, 8);
    }

    #[test]
    fn a_log_without_imu_records_has_no_frame() {
        let (frames, counts) = assemble(&[star(end_of(1)), gnss(end_of(2))]);
        assert!(frames.is_empty());
        assert_eq!(counts.measurements_dropped, 2);
    }

    #[test]
    fn a_log_at_another_rate_or_time_base_or_with_a_long_jump_is_refused_unchanged() {
        let mut assembler = FrameAssembler::new(GRID).unwrap();
        for interval_s in [0.01, 0.0, -0.002, 1e300, f64::NAN] {
            let LogRecord::Imu(mut record) = imu(0) else {
                unreachable!()
            };
            record.interval_s = interval_s;
            let refused = assembler.push(&LogRecord::Imu(record)).unwrap_err();
            assert!(
                matches!(refused, FrameAssemblyError::ImuInterval { period_s, .. }
                    if period_s.to_bits() == PERIOD_S.to_bits()),
                "{refused}"
            );
        }
        // A log shifted by 10 ms against the setup's initial time.
        assert_eq!(
            assembler.push(&imu_at(0, end_of(6))),
            Err(FrameAssemblyError::TimeBase {
                first_imu_time_s: end_of(6),
                first_frame_end_s: end_of(1)
            })
        );
        assembler.push(&imu(0)).unwrap();
        assert!(assembler.next_frame().is_none());
        let jump = assembler.push(&imu_at(1, end_of(1) + 2.0)).unwrap_err();
        assert!(matches!(jump, FrameAssemblyError::Gap { .. }), "{jump}");
        assembler.push(&imu(1)).unwrap();
        assert_eq!(assembler.push(&imu(2)), Err(FrameAssemblyError::NotDrained));
        assert_eq!(assembler.next_frame().unwrap().imu.0.unwrap().sequence, 0);
        assert!(assembler.next_frame().is_none());
        assembler.finish();
        assert_eq!(assembler.next_frame().unwrap().imu.0.unwrap().sequence, 1);
        assert_eq!(assembler.push(&imu(2)), Err(FrameAssemblyError::Finished));
        let bad_grids = [
            FrameGrid {
                period_s: 0.0,
                ..GRID
            },
            FrameGrid {
                tolerance: 0.5,
                ..GRID
            },
            FrameGrid {
                max_gap_s: f64::INFINITY,
                ..GRID
            },
            FrameGrid {
                max_gap_s: 1001.0,
                ..GRID
            },
            FrameGrid {
                start_time_s: f64::NAN,
                ..GRID
            },
        ];
        for grid in bad_grids {
            assert!(FrameAssembler::new(grid).is_err(), "{grid:?}");
        }
    }

    #[test]
    fn the_setup_round_trips_bit_for_bit_and_rejects_a_bad_magic() {
        let config = FswConfig::paper_defaults(
            LaunchSite {
                latitude_rad: 0.7,
                longitude_rad: 1.7,
                height_m: 1000.0,
                azimuth_rad: 3.3,
                earth_axis_ecef: [1e-6, -2e-6, 0.999_999_999_997_5],
            },
            SensorFrames {
                gcrf_to_launch_inertial_wxyz: [0.5, -0.5, 0.5, 0.5],
                launch_epoch_gps_week: 2_391,
                launch_epoch_gps_seconds_of_week: 302_418.25,
            },
        );
        let setup = ReplaySetup {
            launch_site: config.launch_site,
            sensor_frames: config.sensor_frames,
            initial: NavigationState {
                attitude: Quaternion::new(0.5, 0.5, -0.5, 0.5),
                position_m: Vector3::new(1.0, -2.0, 3.0),
                velocity_mps: Vector3::new(7.5e3, 0.1, -0.2),
                time_s: 600.0,
            },
            mode: FilterMode::ClosedLoop,
            discretisation_order: 3,
            initial_sigma: config.filter.initial,
            process_noise: config.process_noise,
            imu_period_s: 0.002,
            star_mounting_wxyz: [0.9659, 0.0, -0.2588, 0.0],
            star_noise_rad: 4.8e-5,
            star_gate_nis: 16.27,
            gnss_noise_m: 10.0,
            gnss_gate_nis: 16.27,
            max_latency_s: 0.1,
            gnss_error: nav_core::gnss_error::GnssErrorModel {
                sigma_m: 8.0,
                correlation_time_s: 300.0,
            },
            gnss_velocity_noise_mps: 0.05,
            imu_max_rate_rad_s: 7.0,
            imu_max_specific_force_mps2: 200.0,
        };
        let words = setup.to_words();
        assert_eq!(ReplaySetup::from_words(&words), Ok(setup));
        let mut bad = words;
        bad[0] = 0;
        assert!(ReplaySetup::from_words(&bad).is_err());
        bad = words;
        bad[1] = 7;
        assert!(ReplaySetup::from_words(&bad).is_err());
    }
}
