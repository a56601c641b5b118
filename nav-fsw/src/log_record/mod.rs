//! The binary replay log: the compact form of the sensor log (`docs/guide/replay-format.md`) that the
//! QEMU firmware streams from the host through semihosting. Fixed-size little-endian records,
//! so a reader needs one 80-byte buffer and no allocator; decoding checks everything and never
//! panics, whatever the bytes.
//!
//! ## File layout
//! A 16-byte header, then records of [`RECORD_SIZE`] = 80 bytes each, in delivery order
//! (non-decreasing arrival time; the host writer guarantees it, the flight input checks handle a
//! log that breaks it).
//!
//! | header bytes | content |
//! |---|---|
//! | 0..8 | magic [`MAGIC`] = `b"NAVLOG\0\0"` |
//! | 8..12 | format version, u32 LE = [`FORMAT_VERSION`] (2) |
//! | 12..16 | record size in bytes, u32 LE = 80 |
//!
//! ## Record layout
//! Byte 0 is the tag, bytes 1..8 are reserved (zero), then nine 8-byte little-endian words at
//! offsets 8, 16, …, 72. Floats are IEEE-754 binary64 bit patterns (`f64::to_le_bytes`), so the
//! record is bit-exact; every float must be finite. Unused words are zero.
//!
//! | offset | IMU (tag 1) | star (tag 2) | GNSS (tag 3) | GNSS with velocity (tag 4) |
//! |---|---|---|---|---|
//! | 8 | sequence (u64) | arrival time (s) | arrival time (s) | arrival time (s) |
//! | 16 | time tag = arrival (s) | time tag (s) | GPS seconds of week (s) | GPS seconds of week (s) |
//! | 24 | interval (s) | `q_gs` w | ECEF x (m) | ECEF x (m) |
//! | 32 | Δθ x (rad) | `q_gs` x | ECEF y (m) | ECEF y (m) |
//! | 40 | Δθ y (rad) | `q_gs` y | ECEF z (m) | ECEF z (m) |
//! | 48 | Δθ z (rad) | `q_gs` z | 0 | ECEF v x (m/s) |
//! | 56 | Δv x (m/s) | head (u64, ≤ 255; 0 = the first) | 0 | ECEF v y (m/s) |
//! | 64 | Δv y (m/s) | 0 | 0 | ECEF v z (m/s) |
//! | 72 | Δv z (m/s) | 0 | GPS week (u64, ≤ u32::MAX) | GPS week (u64, ≤ u32::MAX) |
//!
//! Times other than the GNSS tags are navigation time (s since the launch epoch); the star
//! attitude is sensor → GCRF, the GNSS fix ECEF (ITRF) tagged in GPS time, as the ports take
//! them ([`crate::ports`]). A position-only receiver's fixes are tag 3. Version 1 logs (star
//! relative to launch-inertial, GNSS tagged in navigation time) are refused with
//! [`LogRecordError::UnsupportedVersion`].
//!
//! Decoding accepts only this canonical form (known tag, zero reserved and unused bytes, finite
//! floats), so `encode(decode(bytes)) == bytes` for every accepted record.

use crate::ports::{GnssFix, ImuSample, StarMeasurement};

/// Size of one record (bytes).
pub const RECORD_SIZE: usize = 80;
/// Size of the file header (bytes).
pub const HEADER_SIZE: usize = 16;
/// The file's first eight bytes.
pub const MAGIC: [u8; 8] = *b"NAVLOG\0\0";
/// The layout version this module reads and writes.
pub const FORMAT_VERSION: u32 = 2;

/// Tag byte of an IMU record.
pub const TAG_IMU: u8 = 1;
/// Tag byte of a star-sensor record.
pub const TAG_STAR: u8 = 2;
/// Tag byte of a GNSS record (position only).
pub const TAG_GNSS: u8 = 3;
/// Tag byte of a GNSS record with the receiver's velocity.
pub const TAG_GNSS_VELOCITY: u8 = 4;

/// Number of 8-byte words after the tag word.
const WORDS: usize = 9;
/// Bytes per word.
const WORD: usize = 8;

/// One IMU output: the increments over one sampling period.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ImuRecord {
    /// Frame counter of the log (the simulator's frame index); the IMU port's 32-bit sequence
    /// is its low 32 bits.
    pub sequence: u64,
    /// End of the sampling interval, which is also when the sample arrives (s).
    pub time_s: f64,
    /// Sampling interval (s).
    pub interval_s: f64,
    /// Measured delta angle (rad, body axes).
    pub delta_angle_rad: [f64; 3],
    /// Measured delta velocity (m/s, body axes).
    pub delta_velocity_mps: [f64; 3],
}

/// One star-sensor attitude measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StarRecord {
    /// When the measurement reaches the flight code (s).
    pub arrival_time_s: f64,
    /// Time of validity (s).
    pub time_tag_s: f64,
    /// Measured `q_gs` (sensor → GCRF), `[w, x, y, z]` (Hamilton, scalar first).
    pub attitude_wxyz: [f64; 4],
    /// The tracker head that took it (`StarMeasurement::head`; 0 = the first).
    pub head: u8,
}

/// One GNSS position fix.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GnssRecord {
    /// When the fix reaches the flight code (s, navigation time).
    pub arrival_time_s: f64,
    /// Time of validity: GPS week (full count).
    pub gps_week: u32,
    /// Time of validity: GPS seconds of week (s).
    pub gps_seconds_of_week: f64,
    /// Measured position in ECEF, WGS-84 (m).
    pub position_ecef_m: [f64; 3],
    /// Measured velocity relative to the rotating Earth, ECEF axes (m/s), if the receiver
    /// outputs it.
    pub velocity_ecef_mps: Option<[f64; 3]>,
}

/// One sensor event of the replay log.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LogRecord {
    /// IMU increments.
    Imu(ImuRecord),
    /// Star-sensor attitude.
    Star(StarRecord),
    /// GNSS position.
    Gnss(GnssRecord),
}

/// A field of a record (named in errors).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RecordField {
    /// IMU `time_s`.
    Time,
    /// IMU `interval_s`.
    Interval,
    /// IMU `delta_angle_rad`.
    DeltaAngle,
    /// IMU `delta_velocity_mps`.
    DeltaVelocity,
    /// Star/GNSS `arrival_time_s`.
    ArrivalTime,
    /// Star `time_tag_s`, GNSS `gps_seconds_of_week`.
    TimeTag,
    /// Star `attitude_wxyz`.
    Attitude,
    /// GNSS `position_ecef_m`.
    Position,
    /// GNSS `velocity_ecef_mps`.
    Velocity,
}

/// Why bytes are not a valid log header or record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LogRecordError {
    /// The header does not start with [`MAGIC`].
    BadMagic,
    /// The header's version is not [`FORMAT_VERSION`].
    UnsupportedVersion(u32),
    /// The header's record size is not [`RECORD_SIZE`].
    RecordSizeMismatch(u32),
    /// Fewer bytes than a whole record (or header) remain.
    Truncated {
        /// Bytes needed.
        needed: usize,
        /// Bytes available.
        available: usize,
    },
    /// The tag byte is not [`TAG_IMU`], [`TAG_STAR`], [`TAG_GNSS`] or
    /// [`TAG_GNSS_VELOCITY`].
    UnknownTag(u8),
    /// A reserved or unused byte is not zero.
    NonZeroPadding {
        /// Byte offset within the record.
        offset: usize,
    },
    /// A GNSS record's GPS week word does not fit a `u32`.
    GpsWeek(u64),
    /// A star record's head word does not fit a `u8`.
    StarHead(u64),
    /// A float is NaN or infinite.
    NonFinite {
        /// The field.
        field: RecordField,
        /// Byte offset of the offending component within the record.
        offset: usize,
    },
}

impl core::fmt::Display for LogRecordError {
    fn fmt(&self, formatter: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::BadMagic => write!(formatter, "not a replay log (bad magic)"),
            Self::UnsupportedVersion(1) => write!(
                formatter,
                "format version 1 (expected {FORMAT_VERSION}): its star attitudes are relative \
                 to the launch-inertial frame and its GNSS fixes tagged in navigation time; \
                 regenerate the log (star sensor to GCRF, GNSS in GPS time)"
            ),
            Self::UnsupportedVersion(version) => {
                write!(
                    formatter,
                    "format version {version} (expected {FORMAT_VERSION})"
                )
            }
            Self::GpsWeek(week) => write!(formatter, "GPS week {week} does not fit 32 bits"),
            Self::StarHead(head) => write!(formatter, "star head {head} does not fit 8 bits"),
            Self::RecordSizeMismatch(size) => {
                write!(formatter, "record size {size} (expected {RECORD_SIZE})")
            }
            Self::Truncated { needed, available } => {
                write!(formatter, "truncated: {available} of {needed} bytes")
            }
            Self::UnknownTag(tag) => write!(formatter, "unknown tag {tag}"),
            Self::NonZeroPadding { offset } => {
                write!(formatter, "reserved/unused byte {offset} is not zero")
            }
            Self::NonFinite { field, offset } => {
                write!(formatter, "{field:?} at byte {offset} is not finite")
            }
        }
    }
}

impl core::error::Error for LogRecordError {}

/// The file header.
pub fn encode_header() -> [u8; HEADER_SIZE] {
    let mut header = [0_u8; HEADER_SIZE];
    let version = FORMAT_VERSION.to_le_bytes();
    let record_size = RECORD_SIZE_U32.to_le_bytes();
    let source = MAGIC.iter().chain(version.iter()).chain(record_size.iter());
    for (destination, byte) in header.iter_mut().zip(source) {
        *destination = *byte;
    }
    header
}

/// [`RECORD_SIZE`] as written in the header.
const RECORD_SIZE_U32: u32 = 80;

// The layout constants agree: a tag word plus the payload words make a record.
const _: () = assert!(RECORD_SIZE == WORD * (WORDS + 1));
const _: () = assert!(RECORD_SIZE_U32 == 80 && RECORD_SIZE == 80);
const _: () = assert!(HEADER_SIZE == MAGIC.len() + 4 + 4);

/// Checks a file header.
///
/// # Errors
/// [`LogRecordError::BadMagic`], [`LogRecordError::UnsupportedVersion`] or
/// [`LogRecordError::RecordSizeMismatch`].
pub fn decode_header(header: &[u8; HEADER_SIZE]) -> Result<(), LogRecordError> {
    let (magic, rest) = split_word(header);
    let mut version = [0_u8; 4];
    let mut record_size = [0_u8; 4];
    for (destination, byte) in version
        .iter_mut()
        .chain(record_size.iter_mut())
        .zip(rest.iter())
    {
        *destination = *byte;
    }
    if magic != MAGIC {
        return Err(LogRecordError::BadMagic);
    }
    let version = u32::from_le_bytes(version);
    if version != FORMAT_VERSION {
        return Err(LogRecordError::UnsupportedVersion(version));
    }
    let record_size = u32::from_le_bytes(record_size);
    if record_size != RECORD_SIZE_U32 {
        return Err(LogRecordError::RecordSizeMismatch(record_size));
    }
    Ok(())
}

/// The first [`WORD`] bytes of a slice as a word (zero-filled if shorter) and the rest.
fn split_word(bytes: &[u8]) -> ([u8; WORD], &[u8]) {
    let mut word = [0_u8; WORD];
    for (destination, byte) in word.iter_mut().zip(bytes.iter()) {
        *destination = *byte;
    }
    (word, bytes.get(WORD..).unwrap_or(&[]))
}

/// Byte offset of payload word `index` (0-based) within a record.
const fn offset_of(index: usize) -> usize {
    WORD + WORD * index
}

impl LogRecord {
    /// When the event reaches the flight code (s): the IMU time tag, the measurement's arrival.
    pub fn arrival_time_s(&self) -> f64 {
        match self {
            Self::Imu(imu) => imu.time_s,
            Self::Star(star) => star.arrival_time_s,
            Self::Gnss(gnss) => gnss.arrival_time_s,
        }
    }

    /// The time of validity in navigation time (s): the IMU time tag, the star time tag;
    /// `None` for a GNSS fix, tagged in GPS time.
    pub fn time_tag_s(&self) -> Option<f64> {
        match self {
            Self::Imu(imu) => Some(imu.time_s),
            Self::Star(star) => Some(star.time_tag_s),
            Self::Gnss(_) => None,
        }
    }

    /// The tag byte of this kind of record.
    pub fn tag(&self) -> u8 {
        match self {
            Self::Imu(_) => TAG_IMU,
            Self::Star(_) => TAG_STAR,
            Self::Gnss(GnssRecord {
                velocity_ecef_mps: Some(_),
                ..
            }) => TAG_GNSS_VELOCITY,
            Self::Gnss(_) => TAG_GNSS,
        }
    }

    /// The payload words and the field each float word belongs to (`None`: not a float).
    fn words(&self) -> [(u64, Option<RecordField>); WORDS] {
        let float = |value: f64, field| (value.to_bits(), Some(field));
        let zero = (0, None);
        match self {
            Self::Imu(imu) => {
                let [angle_x, angle_y, angle_z] = imu.delta_angle_rad;
                let [velocity_x, velocity_y, velocity_z] = imu.delta_velocity_mps;
                [
                    (imu.sequence, None),
                    float(imu.time_s, RecordField::Time),
                    float(imu.interval_s, RecordField::Interval),
                    float(angle_x, RecordField::DeltaAngle),
                    float(angle_y, RecordField::DeltaAngle),
                    float(angle_z, RecordField::DeltaAngle),
                    float(velocity_x, RecordField::DeltaVelocity),
                    float(velocity_y, RecordField::DeltaVelocity),
                    float(velocity_z, RecordField::DeltaVelocity),
                ]
            }
            Self::Star(star) => {
                let [w, x, y, z] = star.attitude_wxyz;
                [
                    float(star.arrival_time_s, RecordField::ArrivalTime),
                    float(star.time_tag_s, RecordField::TimeTag),
                    float(w, RecordField::Attitude),
                    float(x, RecordField::Attitude),
                    float(y, RecordField::Attitude),
                    float(z, RecordField::Attitude),
                    (u64::from(star.head), None),
                    zero,
                    zero,
                ]
            }
            Self::Gnss(gnss) => {
                let [x, y, z] = gnss.position_ecef_m;
                let [vx, vy, vz] = gnss.velocity_ecef_mps.map_or([zero; 3], |velocity| {
                    velocity.map(|v| float(v, RecordField::Velocity))
                });
                [
                    float(gnss.arrival_time_s, RecordField::ArrivalTime),
                    float(gnss.gps_seconds_of_week, RecordField::TimeTag),
                    float(x, RecordField::Position),
                    float(y, RecordField::Position),
                    float(z, RecordField::Position),
                    vx,
                    vy,
                    vz,
                    (u64::from(gnss.gps_week), None),
                ]
            }
        }
    }

    /// Encodes the record (layout in the module docs).
    ///
    /// # Errors
    /// [`LogRecordError::NonFinite`] if a float is NaN or infinite (the decoder would refuse it).
    pub fn encode(&self) -> Result<[u8; RECORD_SIZE], LogRecordError> {
        let words = self.words();
        for (index, (bits, field)) in words.iter().enumerate() {
            if let Some(field) = field {
                if !f64::from_bits(*bits).is_finite() {
                    return Err(LogRecordError::NonFinite {
                        field: *field,
                        offset: offset_of(index),
                    });
                }
            }
        }
        let mut record = [0_u8; RECORD_SIZE];
        let head = [self.tag(), 0, 0, 0, 0, 0, 0, 0];
        let bytes = head
            .into_iter()
            .chain(words.into_iter().flat_map(|(bits, _)| bits.to_le_bytes()));
        for (destination, byte) in record.iter_mut().zip(bytes) {
            *destination = byte;
        }
        Ok(record)
    }

    /// Decodes one record, accepting only the canonical form (module docs).
    ///
    /// # Errors
    /// [`LogRecordError::UnknownTag`], [`LogRecordError::NonZeroPadding`] or
    /// [`LogRecordError::NonFinite`], naming the byte offset.
    pub fn decode(record: &[u8; RECORD_SIZE]) -> Result<Self, LogRecordError> {
        let (head, mut rest) = split_word(record);
        let [tag, reserved @ ..] = head;
        if let Some(position) = reserved.iter().position(|byte| *byte != 0) {
            return Err(LogRecordError::NonZeroPadding {
                offset: position.saturating_add(1),
            });
        }
        let mut words = RecordWords([0_u64; WORDS]);
        for word in words.0.iter_mut() {
            let (bytes, tail) = split_word(rest);
            *word = u64::from_le_bytes(bytes);
            rest = tail;
        }
        match tag {
            TAG_IMU => words.imu().map(Self::Imu),
            TAG_STAR => words.star().map(Self::Star),
            TAG_GNSS | TAG_GNSS_VELOCITY => words.gnss(tag == TAG_GNSS_VELOCITY).map(Self::Gnss),
            unknown => Err(LogRecordError::UnknownTag(unknown)),
        }
    }

    /// Decodes the record at the start of `bytes` and returns it with the bytes after it (for
    /// a buffer holding several records).
    ///
    /// # Errors
    /// [`LogRecordError::Truncated`] if fewer than [`RECORD_SIZE`] bytes remain, else as
    /// [`LogRecord::decode`].
    pub fn decode_prefix(bytes: &[u8]) -> Result<(Self, &[u8]), LogRecordError> {
        let (record, rest) =
            bytes
                .split_first_chunk::<RECORD_SIZE>()
                .ok_or(LogRecordError::Truncated {
                    needed: RECORD_SIZE,
                    available: bytes.len(),
                })?;
        Ok((Self::decode(record)?, rest))
    }
}

impl ImuRecord {
    /// The IMU port's sample: the sequence is the low 32 bits of the log's frame counter (a
    /// real IMU's counter wraps).
    pub fn to_imu_sample(&self) -> ImuSample {
        let [b0, b1, b2, b3, ..] = self.sequence.to_le_bytes();
        ImuSample {
            sequence: u32::from_le_bytes([b0, b1, b2, b3]),
            time_s: self.time_s,
            delta_angle_rad: self.delta_angle_rad,
            delta_velocity_mps: self.delta_velocity_mps,
        }
    }
}

impl StarRecord {
    /// The star-sensor port's measurement.
    pub fn to_star_measurement(&self) -> StarMeasurement {
        StarMeasurement {
            time_tag_s: self.time_tag_s,
            sensor_to_gcrf_wxyz: self.attitude_wxyz,
            head: self.head,
        }
    }
}

impl GnssRecord {
    /// The GNSS port's fix.
    pub fn to_gnss_fix(&self) -> GnssFix {
        GnssFix {
            gps_week: self.gps_week,
            gps_seconds_of_week: self.gps_seconds_of_week,
            position_ecef_m: self.position_ecef_m,
            velocity_ecef_mps: self.velocity_ecef_mps,
        }
    }
}

/// A record's payload words, decoded field by field in word order, so an error names the
/// first bad word.
struct RecordWords([u64; WORDS]);

impl RecordWords {
    /// Word `index` as a finite float.
    fn float(&self, index: usize, field: RecordField) -> Result<f64, LogRecordError> {
        let value = f64::from_bits(self.0.get(index).copied().unwrap_or(0));
        if value.is_finite() {
            Ok(value)
        } else {
            Err(LogRecordError::NonFinite {
                field,
                offset: offset_of(index),
            })
        }
    }

    /// Words `index..index + N` as finite floats.
    fn floats<const N: usize>(
        &self,
        index: usize,
        field: RecordField,
    ) -> Result<[f64; N], LogRecordError> {
        let mut values = [0.0; N];
        for (offset, value) in values.iter_mut().enumerate() {
            *value = self.float(index + offset, field)?;
        }
        Ok(values)
    }

    /// Words `first..end` must be zero; the error names the first non-zero byte.
    fn unused(&self, first: usize, end: usize) -> Result<(), LogRecordError> {
        let nonzero = self
            .0
            .iter()
            .enumerate()
            .take(end)
            .skip(first)
            .find(|(_, word)| **word != 0);
        match nonzero {
            Some((index, word)) => Err(LogRecordError::NonZeroPadding {
                offset: offset_of(index).saturating_add(
                    word.to_le_bytes()
                        .iter()
                        .position(|byte| *byte != 0)
                        .unwrap_or(0),
                ),
            }),
            None => Ok(()),
        }
    }

    fn imu(&self) -> Result<ImuRecord, LogRecordError> {
        Ok(ImuRecord {
            sequence: self.0.first().copied().unwrap_or(0),
            time_s: self.float(1, RecordField::Time)?,
            interval_s: self.float(2, RecordField::Interval)?,
            delta_angle_rad: self.floats(3, RecordField::DeltaAngle)?,
            delta_velocity_mps: self.floats(6, RecordField::DeltaVelocity)?,
        })
    }

    fn star(&self) -> Result<StarRecord, LogRecordError> {
        let star = StarRecord {
            arrival_time_s: self.float(0, RecordField::ArrivalTime)?,
            time_tag_s: self.float(1, RecordField::TimeTag)?,
            attitude_wxyz: self.floats(2, RecordField::Attitude)?,
            head: {
                let word = self.0.get(6).copied().unwrap_or(0);
                u8::try_from(word).map_err(|_| LogRecordError::StarHead(word))?
            },
        };
        self.unused(7, WORDS)?;
        Ok(star)
    }

    fn gnss(&self, with_velocity: bool) -> Result<GnssRecord, LogRecordError> {
        let arrival_time_s = self.float(0, RecordField::ArrivalTime)?;
        let gps_seconds_of_week = self.float(1, RecordField::TimeTag)?;
        let position_ecef_m = self.floats(2, RecordField::Position)?;
        let velocity_ecef_mps = if with_velocity {
            Some(self.floats(5, RecordField::Velocity)?)
        } else {
            self.unused(5, 8)?;
            None
        };
        let week = self.0.get(8).copied().unwrap_or(0);
        let gps_week = u32::try_from(week).map_err(|_| LogRecordError::GpsWeek(week))?;
        Ok(GnssRecord {
            arrival_time_s,
            gps_week,
            gps_seconds_of_week,
            position_ecef_m,
            velocity_ecef_mps,
        })
    }
}

#[cfg(test)]
mod tests;

/// Minimal records for the crate's tests: zero increments, identity attitude, a fix on the
/// equator at GPS week 2,000.
#[cfg(test)]
pub(crate) mod test_records {
    use super::{GnssRecord, ImuRecord, LogRecord, StarRecord};

    /// An IMU record ending at `time_s` over `interval_s`.
    pub(crate) fn imu(sequence: u64, time_s: f64, interval_s: f64) -> LogRecord {
        LogRecord::Imu(ImuRecord {
            sequence,
            time_s,
            interval_s,
            delta_angle_rad: [0.0; 3],
            delta_velocity_mps: [0.0; 3],
        })
    }

    /// A star record valid at its arrival.
    pub(crate) fn star(arrival_time_s: f64) -> LogRecord {
        LogRecord::Star(StarRecord {
            arrival_time_s,
            time_tag_s: arrival_time_s,
            attitude_wxyz: [1.0, 0.0, 0.0, 0.0],
            head: 0,
        })
    }

    /// A position-only fix arriving at `arrival_time_s`.
    pub(crate) fn gnss(arrival_time_s: f64) -> LogRecord {
        LogRecord::Gnss(GnssRecord {
            arrival_time_s,
            gps_week: 2_000,
            gps_seconds_of_week: arrival_time_s,
            position_ecef_m: [7e6, 0.0, 0.0],
            velocity_ecef_mps: None,
        })
    }
}
