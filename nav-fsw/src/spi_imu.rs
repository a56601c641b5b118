//! An IMU on an SPI bus with a data-ready line, as an [`ImuPort`]: the shape of a
//! navigation-grade IMU's interface (embedded-hal 1.0 [`SpiDevice`] and [`InputPin`], so any
//! HAL's bus works). The IMU raises data-ready when a new sample of integrated increments is
//! latched; the port then burst-reads one packet, checks it and hands the scheduler the sample.
//!
//! ## Example packet layout
//! A device with its own layout needs its own decoder with the same checks; this one is
//! documented so a sensor front-end (or an FPGA) can be built to it. The port writes the
//! burst-read command byte [`BURST_READ_COMMAND`] and reads [`PACKET_SIZE`] = 34 bytes, all
//! big-endian:
//!
//! | bytes | field | scale |
//! |---|---|---|
//! | 0..2 | sync word [`SYNC_WORD`] = `0xA55A` | |
//! | 2..6 | sample counter, u32 (wraps) | |
//! | 6..18 | Δθ x, y, z, i32 each | [`DELTA_ANGLE_LSB_RAD`] = 2⁻³¹ rad |
//! | 18..30 | Δv x, y, z, i32 each | [`DELTA_VELOCITY_LSB_MPS`] = 2⁻²⁶ m/s |
//! | 30..32 | status, u16: bit 0 gyro fault, bit 1 accelerometer fault, bit 2 saturated | |
//! | 32..34 | CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF) over bytes 0..32 | |
//!
//! The scales cover ±1 rad and ±32 m/s per sample (at 500 Hz: 28,000 °/s, 1,600 g), with
//! resolutions of 0.47 nrad and 15 nm/s, far below a navigation-grade IMU's quantisation.
//!
//! ## Time
//! The IMU's sample counter is the time base: sample `n` ends at
//! `first_sample_time_s + (n − first_counter)·period_s` (navigation time, the counter's
//! wrap handled), as for an IMU whose sampling is synchronised to the flight computer's frame.
//!
//! ## Faults
//! No data-ready: no sample this frame (the scheduler holds the last one and counts it). A bus
//! error, a wrong sync word, a CRC mismatch or a fault bit in the status: no sample, and the
//! port counts which ([`SpiImuCounters`]); a faulty sample never reaches the filter. A
//! saturated sample is delivered (the scheduler's own saturation check inflates its
//! uncertainty) and counted.

use crc::{Crc, CRC_16_IBM_3740};
use embedded_hal::digital::InputPin;
use embedded_hal::spi::{Operation, SpiDevice};

use crate::ports::{ImuPort, ImuSample};

/// Bytes of one packet.
pub const PACKET_SIZE: usize = 34;
/// The command byte that starts a burst read.
pub const BURST_READ_COMMAND: u8 = 0x3E;
/// First two bytes of every packet.
pub const SYNC_WORD: u16 = 0xA55A;
/// Δθ per count (rad): 2⁻³¹.
pub const DELTA_ANGLE_LSB_RAD: f64 = 1.0 / 2_147_483_648.0;
/// Δv per count (m/s): 2⁻²⁶.
pub const DELTA_VELOCITY_LSB_MPS: f64 = 1.0 / 67_108_864.0;
/// Status bit: the gyro reports a fault.
pub const STATUS_GYRO_FAULT: u16 = 1 << 0;
/// Status bit: the accelerometer reports a fault.
pub const STATUS_ACCELEROMETER_FAULT: u16 = 1 << 1;
/// Status bit: an increment saturated.
pub const STATUS_SATURATED: u16 = 1 << 2;

/// CRC-16/CCITT-FALSE (catalogued as CRC-16/IBM-3740: poly 0x1021, init 0xFFFF, no
/// reflection, no final XOR).
const PACKET_CRC: Crc<u16> = Crc::<u16>::new(&CRC_16_IBM_3740);

/// What the port has counted (telemetry).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SpiImuCounters {
    /// Samples delivered.
    pub samples: u32,
    /// Frames without data-ready.
    pub not_ready: u32,
    /// SPI or data-ready pin errors.
    pub bus_errors: u32,
    /// Packets whose sync word is wrong.
    pub sync_errors: u32,
    /// Packets whose CRC does not match.
    pub crc_errors: u32,
    /// Packets with a gyro or accelerometer fault bit set (not delivered).
    pub device_faults: u32,
    /// Delivered samples flagged as saturated.
    pub saturated: u32,
}

/// The time base of the IMU's sample counter.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SampleClock {
    /// The counter of a reference sample.
    pub first_counter: u32,
    /// When the reference sample ends (s, navigation time).
    pub first_sample_time_s: f64,
    /// The IMU's sampling period (s).
    pub period_s: f64,
}

impl SampleClock {
    /// When sample `counter` ends (s): counters after the reference, modulo 2³².
    pub fn time_s(&self, counter: u32) -> f64 {
        let samples_after = counter.wrapping_sub(self.first_counter);
        self.first_sample_time_s + f64::from(samples_after) * self.period_s
    }
}

/// Why a packet was not delivered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PacketError {
    /// The first two bytes are not [`SYNC_WORD`].
    Sync,
    /// The CRC does not match the packet.
    Crc,
    /// The status reports a gyro or accelerometer fault.
    DeviceFault,
}

impl core::fmt::Display for PacketError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::Sync => "IMU packet: wrong sync word",
            Self::Crc => "IMU packet: CRC mismatch",
            Self::DeviceFault => "IMU packet: the device reports a sensor fault",
        })
    }
}

impl core::error::Error for PacketError {}

/// One decoded packet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuPacket {
    /// The IMU's sample counter.
    pub counter: u32,
    /// Δθ (rad).
    pub delta_angle_rad: [f64; 3],
    /// Δv (m/s).
    pub delta_velocity_mps: [f64; 3],
    /// The status word.
    pub status: u16,
}

fn be_u16(bytes: &[u8; PACKET_SIZE], at: usize) -> u16 {
    let pair = [0, 1].map(|k| bytes.get(at + k).copied().unwrap_or(0));
    u16::from_be_bytes(pair)
}

fn be_u32(bytes: &[u8; PACKET_SIZE], at: usize) -> u32 {
    let quad = [0, 1, 2, 3].map(|k| bytes.get(at + k).copied().unwrap_or(0));
    u32::from_be_bytes(quad)
}

fn scaled_triple(bytes: &[u8; PACKET_SIZE], at: usize, lsb: f64) -> [f64; 3] {
    [0, 1, 2].map(|axis| {
        let quad = [0, 1, 2, 3].map(|k| bytes.get(at + 4 * axis + k).copied().unwrap_or(0));
        f64::from(i32::from_be_bytes(quad)) * lsb
    })
}

/// `value / lsb` rounded to the nearest count, saturating at the i32 range (NaN gives 0).
#[expect(
    clippy::as_conversions,
    reason = "a float-to-integer `as` saturates and maps NaN to 0: the intended rounding"
)]
fn counts(value: f64, lsb: f64) -> i32 {
    libm::round(value / lsb) as i32
}

impl ImuPacket {
    /// Checks and decodes a packet.
    ///
    /// # Errors
    /// [`PacketError`]: wrong sync word, CRC mismatch, or a fault bit in the status.
    ///
    /// # Examples
    /// ```
    /// use nav_fsw::spi_imu::{ImuPacket, PacketError};
    /// let packet = ImuPacket {
    ///     counter: 7,
    ///     delta_angle_rad: [1e-4, 0.0, -2e-4],
    ///     delta_velocity_mps: [0.0, 0.0196, 0.0],
    ///     status: 0,
    /// };
    /// let mut bytes = packet.encode();
    /// assert_eq!(ImuPacket::decode(&bytes)?.counter, 7);
    /// bytes[10] ^= 0x01;
    /// assert_eq!(ImuPacket::decode(&bytes), Err(PacketError::Crc));
    /// # Ok::<(), PacketError>(())
    /// ```
    pub fn decode(bytes: &[u8; PACKET_SIZE]) -> Result<Self, PacketError> {
        if be_u16(bytes, 0) != SYNC_WORD {
            return Err(PacketError::Sync);
        }
        let (covered, _) = bytes.split_at(PACKET_SIZE - 2);
        if PACKET_CRC.checksum(covered) != be_u16(bytes, PACKET_SIZE - 2) {
            return Err(PacketError::Crc);
        }
        let status = be_u16(bytes, 30);
        if status & (STATUS_GYRO_FAULT | STATUS_ACCELEROMETER_FAULT) != 0 {
            return Err(PacketError::DeviceFault);
        }
        Ok(Self {
            counter: be_u32(bytes, 2),
            delta_angle_rad: scaled_triple(bytes, 6, DELTA_ANGLE_LSB_RAD),
            delta_velocity_mps: scaled_triple(bytes, 18, DELTA_VELOCITY_LSB_MPS),
            status,
        })
    }

    /// The packet as the IMU sends it (increments rounded to counts, saturating at the
    /// i32 range): for simulators, front-ends and tests.
    pub fn encode(&self) -> [u8; PACKET_SIZE] {
        let mut words = [0_u8; PACKET_SIZE];
        fn put_into(words: &mut [u8; PACKET_SIZE], at: usize, bytes: &[u8]) {
            if let Some(slot) = words.get_mut(at..at + bytes.len()) {
                slot.copy_from_slice(bytes);
            }
        }
        let mut put = |at: usize, bytes: &[u8]| put_into(&mut words, at, bytes);
        put(0, &SYNC_WORD.to_be_bytes());
        put(2, &self.counter.to_be_bytes());
        for axis in 0..3 {
            let angle = self.delta_angle_rad.get(axis).copied().unwrap_or(0.0);
            let velocity = self.delta_velocity_mps.get(axis).copied().unwrap_or(0.0);
            put(
                6 + 4 * axis,
                &counts(angle, DELTA_ANGLE_LSB_RAD).to_be_bytes(),
            );
            put(
                18 + 4 * axis,
                &counts(velocity, DELTA_VELOCITY_LSB_MPS).to_be_bytes(),
            );
        }
        put(30, &self.status.to_be_bytes());
        let checksum = PACKET_CRC.checksum(words.get(..PACKET_SIZE - 2).unwrap_or(&[]));
        put_into(&mut words, PACKET_SIZE - 2, &checksum.to_be_bytes());
        words
    }
}

/// An IMU on `spi` with its data-ready line on `data_ready`, as an [`ImuPort`].
#[derive(Debug)]
pub struct SpiImu<S, P> {
    spi: S,
    data_ready: P,
    clock: SampleClock,
    counters: SpiImuCounters,
}

fn count(counter: &mut u32) {
    *counter = counter.saturating_add(1);
}

impl<S: SpiDevice, P: InputPin> SpiImu<S, P> {
    /// The port for the IMU on `spi`, its data-ready pin, and its counter's time base.
    pub fn new(spi: S, data_ready: P, clock: SampleClock) -> Self {
        Self {
            spi,
            data_ready,
            clock,
            counters: SpiImuCounters::default(),
        }
    }

    /// What the port has counted.
    pub fn counters(&self) -> SpiImuCounters {
        self.counters
    }

    /// Reads one packet if data-ready is raised.
    fn read_packet(&mut self) -> Option<[u8; PACKET_SIZE]> {
        match self.data_ready.is_high() {
            Ok(true) => {}
            Ok(false) => {
                count(&mut self.counters.not_ready);
                return None;
            }
            Err(_) => {
                count(&mut self.counters.bus_errors);
                return None;
            }
        }
        let mut packet = [0_u8; PACKET_SIZE];
        let burst = self.spi.transaction(&mut [
            Operation::Write(&[BURST_READ_COMMAND]),
            Operation::Read(&mut packet),
        ]);
        if burst.is_err() {
            count(&mut self.counters.bus_errors);
            return None;
        }
        Some(packet)
    }
}

impl<S: SpiDevice, P: InputPin> ImuPort for SpiImu<S, P> {
    fn read(&mut self) -> Option<ImuSample> {
        let bytes = self.read_packet()?;
        let packet = match ImuPacket::decode(&bytes) {
            Ok(packet) => packet,
            Err(error) => {
                count(match error {
                    PacketError::Sync => &mut self.counters.sync_errors,
                    PacketError::Crc => &mut self.counters.crc_errors,
                    PacketError::DeviceFault => &mut self.counters.device_faults,
                });
                return None;
            }
        };
        if packet.status & STATUS_SATURATED != 0 {
            count(&mut self.counters.saturated);
        }
        count(&mut self.counters.samples);
        Some(ImuSample {
            sequence: packet.counter,
            time_s: self.clock.time_s(packet.counter),
            delta_angle_rad: packet.delta_angle_rad,
            delta_velocity_mps: packet.delta_velocity_mps,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::convert::Infallible;
    use embedded_hal::spi::{ErrorKind, ErrorType};

    /// A bus that answers every burst read with the next queued packet.
    struct Bus {
        packets: std::vec::Vec<[u8; PACKET_SIZE]>,
        fail: bool,
    }

    #[derive(Debug)]
    struct BusFault;

    impl embedded_hal::spi::Error for BusFault {
        fn kind(&self) -> ErrorKind {
            ErrorKind::Other
        }
    }

    impl ErrorType for Bus {
        type Error = BusFault;
    }

    impl SpiDevice for Bus {
        fn transaction(&mut self, operations: &mut [Operation<'_, u8>]) -> Result<(), BusFault> {
            if self.fail {
                return Err(BusFault);
            }
            let [Operation::Write(command), Operation::Read(read)] = operations else {
                panic!("not a burst read");
            };
            assert_eq!(*command, [BURST_READ_COMMAND]);
            read.copy_from_slice(&self.packets.remove(0));
            Ok(())
        }
    }

    struct DataReady(bool);

    impl embedded_hal::digital::ErrorType for DataReady {
        type Error = Infallible;
    }

    impl InputPin for DataReady {
        fn is_high(&mut self) -> Result<bool, Infallible> {
            Ok(self.0)
        }
        fn is_low(&mut self) -> Result<bool, Infallible> {
            Ok(!self.0)
        }
    }

    const CLOCK: SampleClock = SampleClock {
        first_counter: 100,
        first_sample_time_s: 600.002,
        period_s: 0.002,
    };

    fn packet(counter: u32, status: u16) -> ImuPacket {
        ImuPacket {
            counter,
            delta_angle_rad: [1.0e-4, -2.5e-5, 3.0e-6],
            delta_velocity_mps: [0.0196, -1.0e-3, 2.0e-2],
            status,
        }
    }

    fn port(packets: &[[u8; PACKET_SIZE]]) -> SpiImu<Bus, DataReady> {
        let bus = Bus {
            packets: packets.to_vec(),
            fail: false,
        };
        SpiImu::new(bus, DataReady(true), CLOCK)
    }

    /// The check value of CRC-16/CCITT-FALSE for the nine ASCII digits "123456789" is
    /// 0x29B1 (Greg Cook's CRC catalogue, CRC-16/IBM-3740).
    #[test]
    fn the_packet_crc_is_ccitt_false() {
        assert_eq!(PACKET_CRC.checksum(b"123456789"), 0x29B1);
    }

    /// A packet read over the bus arrives as the sample it encodes: increments within half a
    /// count, time from the counter.
    #[test]
    fn a_packet_becomes_the_sample_it_encodes() {
        let sent = packet(105, 0);
        let mut imu = port(&[sent.encode()]);
        let sample = imu.read().unwrap();
        assert_eq!(sample.sequence, 105);
        assert!((sample.time_s - (600.002 + 5.0 * 0.002)).abs() < 1e-12);
        for axis in 0..3 {
            let angle_error = sample.delta_angle_rad[axis] - sent.delta_angle_rad[axis];
            let velocity_error = sample.delta_velocity_mps[axis] - sent.delta_velocity_mps[axis];
            assert!(angle_error.abs() <= DELTA_ANGLE_LSB_RAD / 2.0);
            assert!(velocity_error.abs() <= DELTA_VELOCITY_LSB_MPS / 2.0);
        }
        assert_eq!(imu.counters().samples, 1);
    }

    /// The counter's wrap does not move time backwards.
    #[test]
    fn time_runs_on_across_the_counter_wrap() {
        let clock = SampleClock {
            first_counter: u32::MAX,
            ..CLOCK
        };
        assert!((clock.time_s(0) - (600.002 + 0.002)).abs() < 1e-12);
        assert!((clock.time_s(9) - (600.002 + 0.020)).abs() < 1e-12);
    }

    /// Each fault costs the sample and is counted by its kind; a saturated sample still
    /// arrives, counted.
    #[test]
    fn every_fault_is_counted_and_no_faulty_sample_is_delivered() {
        let mut crc_hit = packet(1, 0).encode();
        crc_hit[20] ^= 0x10;
        let mut sync_hit = packet(2, 0).encode();
        sync_hit[0] = 0x00;
        let packets = [
            crc_hit,
            sync_hit,
            packet(3, STATUS_GYRO_FAULT).encode(),
            packet(4, STATUS_ACCELEROMETER_FAULT).encode(),
            packet(5, STATUS_SATURATED).encode(),
        ];
        let mut imu = port(&packets);
        let delivered: std::vec::Vec<u32> = (0..5)
            .filter_map(|_| imu.read())
            .map(|s| s.sequence)
            .collect();
        assert_eq!(delivered, [5]);
        let counters = imu.counters();
        assert_eq!(
            (
                counters.crc_errors,
                counters.sync_errors,
                counters.device_faults
            ),
            (1, 1, 2)
        );
        assert_eq!((counters.saturated, counters.samples), (1, 1));
    }

    /// Without data-ready nothing is read; a failing bus is counted.
    #[test]
    fn no_data_ready_and_bus_errors_deliver_nothing() {
        let mut imu = port(&[packet(1, 0).encode()]);
        imu.data_ready.0 = false;
        assert!(imu.read().is_none());
        assert_eq!(imu.counters().not_ready, 1);
        imu.data_ready.0 = true;
        imu.spi.fail = true;
        assert!(imu.read().is_none());
        assert_eq!(imu.counters().bus_errors, 1);
    }
}
