//! The calibration kept across a reboot: a fixed-size, versioned record of the calibration a
//! flight has earned (the fed-back estimates of the core calibration blocks and of the
//! systematic IMU errors, and their covariance), with a CRC-32 and a
//! fingerprint of the configuration it was made under. The integrator stores its bytes
//! where it likes (a port like the sensors'); [`crate::scheduler::NavigationComputer`]
//! exports one and loads one as the prior of the next start.
//!
//! Layout (little-endian, [`CALIBRATION_RECORD_BYTES`] bytes): magic `NAVCALIB` (8), version
//! `u16`, two reserved bytes, configuration fingerprint `u32`, navigation time of the export
//! `f64`, the 16 estimate values of `CalibrationEstimate` (gyro bias, accelerometer bias,
//! installation `wxyz`, gyro and accelerometer scale factors), the 12 of `ImuErrorEstimate`
//! (gyro non-orthogonality, accelerometer misalignment, g-sensitivity), the 120 entries of
//! the calibration block's lower triangle row by row (nav-core
//! `ErrorStateFilter::calibration_covariance`), the 78 of the systematic IMU errors'
//! covariance's lower triangle and the 180 of their covariance with the core calibration
//! states, row by row (nav-core `ImuErrorCovariance`; zero when they are not flown), then
//! the CRC-32 (ISO-HDLC) of every byte before it.
//!
//! The fingerprint is the CRC-32 of the replay-setup words of every flight parameter that
//! gives the states their meaning: all but the launch's ground constants (`launch_site.*`,
//! `sensor_frames.*`, which change from launch to launch for the same vehicle) and the
//! monitors' thresholds (`calibration.*`, `consistency.*`).

use crc::{Crc, CRC_32_ISO_HDLC};
use nalgebra::{SVector, Vector3};
use nav_core::filter::{CalibrationEstimate, CALIBRATION_LOWER_TRIANGLE};
use nav_core::imu_error::ImuErrorEstimate;
use nav_core::imu_error::IMU_ERROR_DIMENSION;
use nav_core::imu_error_states::{ImuErrorCovariance, IMU_ERROR_LOWER_TRIANGLE};
use nav_core::state::CALIBRATION_DIMENSION;

use crate::config::{FswConfig, Param};

/// The record's format version; a record of another version is refused.
pub const CALIBRATION_RECORD_VERSION: u16 = 2;
/// The record's magic bytes.
const MAGIC: [u8; 8] = *b"NAVCALIB";
/// Values of the core calibration estimate (`CalibrationEstimate`).
const CORE_ESTIMATE_VALUES: usize = 16;
/// Values of the systematic IMU error estimate (`ImuErrorEstimate`).
const IMU_ERROR_VALUES: usize = 12;
/// Bytes before the `f64` values: magic, version, reserved, fingerprint, time.
const HEADER_BYTES: usize = 8 + 2 + 2 + 4 + 8;
/// The `f64` values after the header.
const VALUES: usize = CORE_ESTIMATE_VALUES
    + IMU_ERROR_VALUES
    + CALIBRATION_LOWER_TRIANGLE
    + IMU_ERROR_LOWER_TRIANGLE
    + CALIBRATION_DIMENSION * IMU_ERROR_DIMENSION;
/// Bytes of the record's CRC.
const CRC_BYTES: usize = 4;
/// Bytes of a record.
pub const CALIBRATION_RECORD_BYTES: usize = HEADER_BYTES + 8 * VALUES + CRC_BYTES;

const CRC32: Crc<u32> = Crc::<u32>::new(&CRC_32_ISO_HDLC);

/// Why a record is refused (the computer keeps its configured prior).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum RecordError {
    /// The bytes are not a calibration record (no `NAVCALIB` magic).
    NotARecord,
    /// The CRC over the record does not match its stored CRC: the bytes were changed.
    Crc {
        /// The CRC stored in the record.
        stored: u32,
        /// The CRC of the bytes as read.
        computed: u32,
    },
    /// A record of another format version.
    Version {
        /// The record's version.
        found: u16,
    },
    /// A record made under another configuration (its fingerprint differs).
    Configuration {
        /// The record's fingerprint.
        record: u32,
        /// The current configuration's.
        current: u32,
    },
    /// The record's covariance is not finite or not positive definite, or an estimate is not
    /// finite.
    Values,
    /// The computer runs the open-loop filter, whose calibration lives in the error state: a
    /// record is loaded only into the closed-loop filter.
    OpenLoop,
}

impl core::fmt::Display for RecordError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::NotARecord => f.write_str("calibration record refused: no NAVCALIB magic"),
            Self::Crc { stored, computed } => write!(
                f,
                "calibration record refused: CRC {computed:#010x} of its bytes, {stored:#010x} stored"
            ),
            Self::Version { found } => write!(
                f,
                "calibration record refused: version {found}, this software reads version \
                 {CALIBRATION_RECORD_VERSION}"
            ),
            Self::Configuration { record, current } => write!(
                f,
                "calibration record refused: made under configuration {record:#010x}, the \
                 current one is {current:#010x}"
            ),
            Self::Values => f.write_str(
                "calibration record refused: a value is not finite or its covariance is not \
                 positive definite",
            ),
            Self::OpenLoop => f.write_str(
                "calibration record refused: the open-loop filter keeps its calibration in \
                 the error state",
            ),
        }
    }
}

impl core::error::Error for RecordError {}

/// A decoded calibration record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CalibrationRecord {
    /// The configuration fingerprint it was made under ([`configuration_fingerprint`]).
    pub fingerprint: u32,
    /// Navigation time of the export (s).
    pub time_s: f64,
    /// The core calibration blocks' estimates.
    pub estimate: CalibrationEstimate,
    /// The systematic IMU errors' estimate (zero when they are not flown).
    pub imu_errors: ImuErrorEstimate,
    /// The calibration block of `P`, lower triangle row by row.
    pub covariance: [f64; CALIBRATION_LOWER_TRIANGLE],
    /// The systematic IMU errors' covariance and their covariance with the core calibration
    /// states ([`ImuErrorCovariance::ZERO`] when they are not flown).
    pub imu_error_covariance: ImuErrorCovariance,
}

/// Whether `param` enters the configuration fingerprint (module docs).
fn fingerprinted(param: Param) -> bool {
    let path = param.path();
    ![
        "launch_site.",
        "sensor_frames.",
        "calibration.",
        "consistency.",
    ]
    .iter()
    .any(|prefix| path.starts_with(prefix))
}

/// The fingerprint of `config` (module docs).
///
/// # Examples
/// ```
/// use nav_fsw::calibration_record::configuration_fingerprint;
/// # let config = nav_fsw::config::FswConfig::paper_defaults(
/// #     nav_core::frames::LaunchSite { latitude_rad: 0.7, longitude_rad: 1.7, height_m: 0.0,
/// #         azimuth_rad: 3.3, earth_axis_ecef: [0.0, 0.0, 1.0] },
/// #     nav_fsw::sensor_frames::SensorFrames::ALIGNED);
/// let mut other = config;
/// other.star.noise_rad *= 2.0;
/// assert_ne!(configuration_fingerprint(&config), configuration_fingerprint(&other));
/// ```
pub fn configuration_fingerprint(config: &FswConfig) -> u32 {
    let mut digest = CRC32.digest();
    for param in Param::ALL.iter().filter(|param| fingerprinted(**param)) {
        digest.update(&param.to_word(config).to_le_bytes());
    }
    digest.finalize()
}

impl CalibrationRecord {
    /// The record's bytes (module docs).
    pub fn to_bytes(&self) -> [u8; CALIBRATION_RECORD_BYTES] {
        let mut bytes = [0u8; CALIBRATION_RECORD_BYTES];
        let (body, crc) = bytes.split_at_mut(CALIBRATION_RECORD_BYTES - CRC_BYTES);
        let mut writer = body.iter_mut();
        // The chunk drives the zip: it is asked first, so its end takes no slot.
        let mut put = |chunk: &[u8]| {
            for (byte, slot) in chunk.iter().zip(writer.by_ref()) {
                *slot = *byte;
            }
        };
        put(&MAGIC);
        put(&CALIBRATION_RECORD_VERSION.to_le_bytes());
        put(&[0, 0]);
        put(&self.fingerprint.to_le_bytes());
        put(&self.time_s.to_le_bytes());
        for value in self.values() {
            put(&value.to_le_bytes());
        }
        let checksum = CRC32.checksum(body);
        for (slot, byte) in crc.iter_mut().zip(checksum.to_le_bytes()) {
            *slot = byte;
        }
        bytes
    }

    /// The `f64` values in record order.
    fn values(&self) -> impl Iterator<Item = f64> + '_ {
        let e = &self.estimate;
        let i = &self.imu_errors;
        let core = [
            e.gyro_bias_rad_s.as_slice(),
            &e.accel_bias_mps2,
            &e.star_installation_wxyz,
            &e.gyro_scale_factor,
            &e.accel_scale_factor,
        ];
        let imu = [
            i.gyro_non_orthogonality_rad.as_slice(),
            i.accel_misalignment_rad.as_slice(),
            i.gyro_g_sensitivity_rad_s_per_mps2.as_slice(),
        ];
        let imu_covariance = &self.imu_error_covariance;
        let covariance = [
            self.covariance.as_slice(),
            imu_covariance.imu_error_lower.as_slice(),
        ];
        core.into_iter()
            .chain(imu)
            .chain(covariance)
            .chain(
                imu_covariance
                    .with_calibration
                    .iter()
                    .map(|row| row.as_slice()),
            )
            .flatten()
            .copied()
    }

    /// Decodes `bytes`, checking magic, CRC, version and that `config` is the configuration
    /// the record was made under.
    ///
    /// # Errors
    /// The [`RecordError`] of the first check that fails, in that order.
    pub fn from_bytes(
        bytes: &[u8; CALIBRATION_RECORD_BYTES],
        config: &FswConfig,
    ) -> Result<Self, RecordError> {
        let (body, crc) = bytes.split_at(CALIBRATION_RECORD_BYTES - CRC_BYTES);
        let mut reader = Reader { rest: body };
        if reader.array::<8>() != MAGIC {
            return Err(RecordError::NotARecord);
        }
        let stored = u32::from_le_bytes(Reader { rest: crc }.array());
        let computed = CRC32.checksum(body);
        if stored != computed {
            return Err(RecordError::Crc { stored, computed });
        }
        let found = u16::from_le_bytes(reader.array());
        if found != CALIBRATION_RECORD_VERSION {
            return Err(RecordError::Version { found });
        }
        let _reserved: [u8; 2] = reader.array();
        let record = u32::from_le_bytes(reader.array());
        let current = configuration_fingerprint(config);
        if record != current {
            return Err(RecordError::Configuration { record, current });
        }
        let time_s = reader.f64();
        Ok(Self {
            fingerprint: record,
            time_s,
            estimate: CalibrationEstimate {
                gyro_bias_rad_s: reader.f64s(),
                accel_bias_mps2: reader.f64s(),
                star_installation_wxyz: reader.f64s(),
                gyro_scale_factor: reader.f64s(),
                accel_scale_factor: reader.f64s(),
            },
            imu_errors: ImuErrorEstimate {
                gyro_non_orthogonality_rad: Vector3::from(reader.f64s::<3>()),
                accel_misalignment_rad: SVector::from(reader.f64s::<6>()),
                gyro_g_sensitivity_rad_s_per_mps2: Vector3::from(reader.f64s::<3>()),
            },
            covariance: reader.f64s(),
            imu_error_covariance: ImuErrorCovariance {
                imu_error_lower: reader.f64s(),
                with_calibration: core::array::from_fn(|_| reader.f64s()),
            },
        })
    }
}

/// Reads little-endian values from the front of a byte slice (zeros past its end: the
/// record's length is fixed, so that never happens).
struct Reader<'a> {
    rest: &'a [u8],
}

impl Reader<'_> {
    fn array<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0u8; N];
        let (head, rest) = self.rest.split_at(N.min(self.rest.len()));
        for (slot, byte) in out.iter_mut().zip(head) {
            *slot = *byte;
        }
        self.rest = rest;
        out
    }

    fn f64(&mut self) -> f64 {
        f64::from_le_bytes(self.array())
    }

    fn f64s<const N: usize>(&mut self) -> [f64; N] {
        let mut out = [0.0; N];
        for value in out.iter_mut() {
            *value = self.f64();
        }
        out
    }
}
