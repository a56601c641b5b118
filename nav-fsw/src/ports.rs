//! Sensor ports: what the scheduler reads, as traits, so the same flight code runs on real
//! hardware, in the host simulator and in the QEMU firmware. nav-core does no I/O; only these
//! ports do. On hardware, [`crate::stream_ports`] adapts any `embedded_io` byte stream (a HAL's
//! UART) carrying the documented 80-byte records; a device with its own protocol needs its own
//! small decoder behind these traits. Navigation time is the frame count times the period:
//! the scheduler needs no clock port.
//!
//! The port structs are `#[non_exhaustive]` and built with their constructors
//! ([`ImuSample::new`], [`StarMeasurement::new`], [`GnssFix::new`]), so a field added later
//! (with a default) does not break an integrator's code.

use nalgebra::{Quaternion, Vector3};

/// One IMU output: the increments over one sampling period, as navigation IMUs deliver them.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct ImuSample {
    /// The IMU's own sample counter (wraps at `u32::MAX`); detects missing and repeated samples.
    pub sequence: u32,
    /// Time of the end of the sampling interval (s, navigation time).
    pub time_s: f64,
    /// Integrated body angular rate over the interval (rad).
    pub delta_angle_rad: [f64; 3],
    /// Integrated body specific force over the interval (m/s).
    pub delta_velocity_mps: [f64; 3],
}

/// One star-tracker attitude: `q_gs`, star-sensor frame to GCRF, as trackers output it
/// (their catalogue is ICRS/J2000; the J2000 ↔ GCRF frame bias, 0.02″, is far below the
/// tracker's noise). The flight code turns it into launch-inertial with the ground constant
/// of [`crate::sensor_frames::SensorFrames`].
///
/// The frame is in the field's name, so code written when this port took a launch-inertial
/// attitude (`attitude_wxyz`) no longer compiles:
/// ```compile_fail
/// let _ = nav_fsw::ports::StarMeasurement { time_tag_s: 600.0, attitude_wxyz: [1.0, 0.0, 0.0, 0.0], head: 0 };
/// ```
///
/// Outside nav-fsw it is built with [`StarMeasurement::new`], as a struct literal no longer
/// compiles (`#[non_exhaustive]`: a field added later does not break an integrator's code):
/// ```compile_fail
/// let _ = nav_fsw::ports::StarMeasurement {
///     time_tag_s: 600.0,
///     sensor_to_gcrf_wxyz: [1.0, 0.0, 0.0, 0.0],
///     head: 0,
/// };
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct StarMeasurement {
    /// Time of validity (s, navigation time: the tracker is synchronised by the flight
    /// computer, as its exposures are commanded on the flight computer's clock).
    pub time_tag_s: f64,
    /// Measured attitude quaternion `q_gs` `[w, x, y, z]` (Hamilton, scalar first), sensor
    /// frame → GCRF. The frame is in the name: the flight code turns it into the
    /// launch-inertial frame with the launch's ground constants (`SensorFrames`).
    pub sensor_to_gcrf_wxyz: [f64; 4],
    /// The tracker head that took it: 0 for the head of `star`, 1 for `star.second_head`
    /// (the heads share one port, as the optical heads of one tracker share its electronics).
    pub head: u8,
}

/// One GNSS fix: antenna position and, from receivers that output it, antenna velocity, in
/// ECEF (ITRF / WGS-84) axes, tagged in GPS time.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct GnssFix {
    /// Time of validity: GPS week (full count since 1980-01-06, not modulo 1024).
    pub gps_week: u32,
    /// Time of validity: GPS seconds of week (s), in `[0, 604800)`.
    pub gps_seconds_of_week: f64,
    /// Antenna position in ECEF, WGS-84 (m).
    pub position_ecef_m: [f64; 3],
    /// Antenna velocity relative to the rotating Earth, ECEF axes (m/s); `None` when the
    /// receiver outputs position only.
    pub velocity_ecef_mps: Option<[f64; 3]>,
}

impl ImuSample {
    /// A sample: the IMU's sequence counter, the end of its interval (s, navigation time) and
    /// the interval's angle (rad) and velocity (m/s) increments in body axes.
    ///
    /// ```
    /// let sample = nav_fsw::ports::ImuSample::new(5, 0.002, [1e-6, 0.0, 0.0], [0.0, 0.0, 0.02]);
    /// assert_eq!(sample.sequence, 5);
    /// assert_eq!(sample.delta_velocity_mps, [0.0, 0.0, 0.02]);
    /// ```
    #[must_use]
    pub const fn new(
        sequence: u32,
        time_s: f64,
        delta_angle_rad: [f64; 3],
        delta_velocity_mps: [f64; 3],
    ) -> Self {
        Self {
            sequence,
            time_s,
            delta_angle_rad,
            delta_velocity_mps,
        }
    }
}

impl StarMeasurement {
    /// A measurement: its time of validity (s, navigation time), the attitude `q_gs`
    /// `[w, x, y, z]` (sensor frame → GCRF) and the head that took it (0 or 1).
    ///
    /// ```
    /// let measurement = nav_fsw::ports::StarMeasurement::new(600.0, [1.0, 0.0, 0.0, 0.0], 1);
    /// assert_eq!(measurement.head, 1);
    /// assert_eq!(measurement.sensor_to_gcrf_wxyz, [1.0, 0.0, 0.0, 0.0]);
    /// ```
    #[must_use]
    pub const fn new(time_tag_s: f64, sensor_to_gcrf_wxyz: [f64; 4], head: u8) -> Self {
        Self {
            time_tag_s,
            sensor_to_gcrf_wxyz,
            head,
        }
    }
}

impl GnssFix {
    /// A position fix at GPS week and seconds of week, antenna position in ECEF (m), without
    /// a velocity ([`GnssFix::with_velocity_ecef_mps`] adds one).
    ///
    /// ```
    /// use nav_fsw::ports::GnssFix;
    /// let fix = GnssFix::new(2303, 100_818.5, [-1.0e6, 5.0e6, 3.0e6]);
    /// assert_eq!(fix.velocity_ecef_mps, None);
    /// let fix = fix.with_velocity_ecef_mps(Some([10.0, 0.0, -2.0]));
    /// assert_eq!(fix.velocity_ecef_mps, Some([10.0, 0.0, -2.0]));
    /// ```
    #[must_use]
    pub const fn new(gps_week: u32, gps_seconds_of_week: f64, position_ecef_m: [f64; 3]) -> Self {
        Self {
            gps_week,
            gps_seconds_of_week,
            position_ecef_m,
            velocity_ecef_mps: None,
        }
    }

    /// The fix with the antenna velocity relative to the rotating Earth, ECEF axes (m/s), or
    /// without one (`None`: a receiver that outputs position only).
    #[must_use]
    pub const fn with_velocity_ecef_mps(mut self, velocity_ecef_mps: Option<[f64; 3]>) -> Self {
        self.velocity_ecef_mps = velocity_ecef_mps;
        self
    }
}

/// Source of IMU samples (one per minor frame).
pub trait ImuPort {
    /// The sample of the current frame, or `None` if the IMU delivered nothing.
    fn read(&mut self) -> Option<ImuSample>;
}

/// Source of star-sensor measurements (asynchronous, at the sensor's rate).
pub trait StarSensorPort {
    /// A measurement that arrived since the last poll, if any.
    fn poll(&mut self) -> Option<StarMeasurement>;
}

/// Source of GNSS fixes (asynchronous, at the receiver's rate).
pub trait GnssPort {
    /// A fix that arrived since the last poll, if any.
    fn poll(&mut self) -> Option<GnssFix>;
}

/// Where the calibration record lives between flights (non-volatile memory, a file, the
/// vehicle computer): the integrator's, as the sensors are. [`crate::scheduler::Command`]'s
/// `SaveCalibration` writes the record through it and `LoadCalibration` reads it back
/// ([`crate::calibration_record`] holds the layout).
pub trait CalibrationStorePort {
    /// Fills `record` with the stored record's bytes.
    ///
    /// # Errors
    /// [`CalibrationStoreFault`] when nothing is stored or the storage cannot be read.
    fn read_record(
        &mut self,
        record: &mut [u8; crate::calibration_record::CALIBRATION_RECORD_BYTES],
    ) -> Result<(), CalibrationStoreFault>;

    /// Stores `record`, replacing what was stored.
    ///
    /// # Errors
    /// [`CalibrationStoreFault::WriteFailed`] when the storage cannot be written.
    fn write_record(
        &mut self,
        record: &[u8; crate::calibration_record::CALIBRATION_RECORD_BYTES],
    ) -> Result<(), CalibrationStoreFault>;
}

/// Why a [`CalibrationStorePort`] could not read or write the record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum CalibrationStoreFault {
    /// The computer was given no store (`NavigationComputer::command` without one).
    NoStore,
    /// The store holds no record.
    Empty,
    /// The storage could not be read.
    ReadFailed,
    /// The storage could not be written.
    WriteFailed,
}

impl core::fmt::Display for CalibrationStoreFault {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::NoStore => "no calibration store was given to the command",
            Self::Empty => "the calibration store holds no record",
            Self::ReadFailed => "the calibration store could not be read",
            Self::WriteFailed => "the calibration store could not be written",
        })
    }
}

impl core::error::Error for CalibrationStoreFault {}

/// The store of a computer given none: every read and write fails with
/// [`CalibrationStoreFault::NoStore`].
#[derive(Debug, Clone, Copy, Default)]
pub struct NoCalibrationStore;

impl CalibrationStorePort for NoCalibrationStore {
    fn read_record(
        &mut self,
        _record: &mut [u8; crate::calibration_record::CALIBRATION_RECORD_BYTES],
    ) -> Result<(), CalibrationStoreFault> {
        Err(CalibrationStoreFault::NoStore)
    }

    fn write_record(
        &mut self,
        _record: &[u8; crate::calibration_record::CALIBRATION_RECORD_BYTES],
    ) -> Result<(), CalibrationStoreFault> {
        Err(CalibrationStoreFault::NoStore)
    }
}

/// `[x, y, z]` as a vector.
#[inline]
pub fn vector(components: &[f64; 3]) -> Vector3<f64> {
    Vector3::new(components[0], components[1], components[2])
}

/// `[w, x, y, z]` as a quaternion.
#[inline]
pub fn quaternion(components: &[f64; 4]) -> Quaternion<f64> {
    Quaternion::new(components[0], components[1], components[2], components[3])
}
