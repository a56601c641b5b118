//! The calibration record: a round trip through its bytes into a new computer carries the
//! calibration bit for bit; a record with one bit flipped anywhere, another version, another
//! configuration or bad values is refused, counted, and changes nothing.

use super::tests::{computer, initial_state, run_frame_with_turned_star};
use super::*;
use crate::calibration_record::{CalibrationRecord, RecordError, CALIBRATION_RECORD_BYTES};
use crate::ports::CalibrationStoreFault;
use nav_core::state::{DYNAMIC_DIMENSION, STATE_DIMENSION};

fn calibrated() -> NavigationComputer {
    let mut computer = computer();
    for sequence in 1..=300_u32 {
        run_frame_with_turned_star(&mut computer, sequence);
    }
    assert_ne!(
        computer.calibration_estimate(),
        CalibrationEstimate::default()
    );
    computer
}

fn refused(
    computer: &mut NavigationComputer,
    bytes: &[u8; CALIBRATION_RECORD_BYTES],
) -> RecordError {
    let before = computer.clone();
    let error = computer.load_calibration(bytes).unwrap_err();
    assert_eq!(computer.filter(), before.filter());
    assert_eq!(
        computer.calibration_estimate(),
        before.calibration_estimate()
    );
    let commands = computer.operations.commands;
    assert_eq!(
        commands.calibration_records_refused,
        before.operations.commands.calibration_records_refused + 1
    );
    error
}

#[test]
fn a_record_carries_the_calibration_into_a_new_computer_bit_for_bit() {
    let old = calibrated();
    let record = old.export_calibration().unwrap();
    let bytes = record.to_bytes();
    assert_eq!(
        CalibrationRecord::from_bytes(&bytes, old.config()),
        Ok(record)
    );
    let mut new = computer();
    new.load_calibration(&bytes).unwrap();
    assert_eq!(new.calibration_estimate(), old.calibration_estimate());
    // The calibration block is the record's (the old filter's bound for a restart), its
    // correlation with navigation zero, the navigation block the prior.
    let loaded = new.filter().calibration_covariance();
    assert_eq!(
        loaded.map(f64::to_bits),
        record.covariance.map(f64::to_bits)
    );
    let prior = ErrorStateFilter::new(&new.config().filter).unwrap();
    for i in 0..STATE_DIMENSION {
        for j in 0..DYNAMIC_DIMENSION {
            let expected = if i < DYNAMIC_DIMENSION {
                prior.covariance()[(i, j)]
            } else {
                0.0
            };
            assert_eq!(
                new.filter().covariance()[(i, j)].to_bits(),
                expected.to_bits()
            );
        }
    }
    assert_eq!(new.operations.commands.calibration_records_loaded, 1);
}

#[test]
fn a_flipped_bit_another_version_or_configuration_is_refused_and_counted() {
    let old = calibrated();
    let record = old.export_calibration().unwrap();
    let bytes = record.to_bytes();
    let mut new = computer();
    // One bit flipped, in the header, an estimate, the covariance and the CRC itself.
    for (byte, bit) in [(9, 0), (30, 3), (600, 7), (CALIBRATION_RECORD_BYTES - 1, 5)] {
        let mut flipped = bytes;
        flipped[byte] ^= 1 << bit;
        let error = refused(&mut new, &flipped);
        assert!(
            matches!(error, RecordError::Crc { .. }),
            "byte {byte}: {error}"
        );
    }
    let mut not_a_record = bytes;
    not_a_record[0] = b'X';
    assert_eq!(refused(&mut new, &not_a_record), RecordError::NotARecord);
    // Another version, its CRC made valid: refused by the version.
    let mut version = bytes;
    version[8] = 3;
    let crc = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC)
        .checksum(&version[..CALIBRATION_RECORD_BYTES - 4]);
    version[CALIBRATION_RECORD_BYTES - 4..].copy_from_slice(&crc.to_le_bytes());
    assert_eq!(
        refused(&mut new, &version),
        RecordError::Version { found: 3 }
    );
    // Another configuration: a different star noise.
    let mut config = *new.config();
    config.star.noise_rad *= 2.0;
    let mut other = NavigationComputer::new(config, initial_state()).unwrap();
    assert!(matches!(
        refused(&mut other, &bytes),
        RecordError::Configuration { .. }
    ));
    // Values that are no covariance: a negative variance, written with a valid CRC.
    let mut bad = record;
    bad.covariance[0] = -1.0;
    assert_eq!(refused(&mut new, &bad.to_bytes()), RecordError::Values);
    // The launch's ground constants are not part of the fingerprint: another launch azimuth
    // loads the same vehicle's record.
    let mut config = *new.config();
    config.launch_site.azimuth_rad += 0.1;
    let mut relaunched = NavigationComputer::new(config, initial_state()).unwrap();
    relaunched.load_calibration(&bytes).unwrap();
    assert_eq!(new.operations.commands.calibration_records_refused, 7);
}

/// Non-volatile memory in RAM for the store commands; `writable: false` fails every write.
struct RamStore {
    record: Option<[u8; CALIBRATION_RECORD_BYTES]>,
    writable: bool,
}

impl crate::ports::CalibrationStorePort for RamStore {
    fn read_record(
        &mut self,
        record: &mut [u8; CALIBRATION_RECORD_BYTES],
    ) -> Result<(), CalibrationStoreFault> {
        *record = self.record.ok_or(CalibrationStoreFault::Empty)?;
        Ok(())
    }

    fn write_record(
        &mut self,
        record: &[u8; CALIBRATION_RECORD_BYTES],
    ) -> Result<(), CalibrationStoreFault> {
        if !self.writable {
            return Err(CalibrationStoreFault::WriteFailed);
        }
        self.record = Some(*record);
        Ok(())
    }
}

/// A store command refused: the reason, the count, and nothing else changed.
fn store_command_refused(
    computer: &mut NavigationComputer,
    command: Command,
    store: &mut RamStore,
    reason: CommandError,
) {
    let before = computer.clone();
    assert_eq!(computer.command_with_store(command, store), Err(reason));
    assert_eq!(computer.filter(), before.filter());
    assert_eq!(
        computer.calibration_estimate(),
        before.calibration_estimate()
    );
    let commands = computer.operations.commands;
    assert_eq!(commands.refused, before.operations.commands.refused + 1);
    assert_eq!(commands.accepted, before.operations.commands.accepted);
}

#[test]
fn save_and_load_commands_carry_the_calibration_through_the_store() {
    let old = calibrated();
    let mut store = RamStore {
        record: None,
        writable: true,
    };
    let mut old_copy = old.clone();
    old_copy
        .command_with_store(Command::SaveCalibration, &mut store)
        .unwrap();
    assert_eq!(old_copy.filter(), old.filter(), "saving changes nothing");
    let saved = store.record.unwrap();
    assert_eq!(saved, old.export_calibration().unwrap().to_bytes());

    let mut new = computer();
    new.command_with_store(Command::LoadCalibration, &mut store)
        .unwrap();
    let mut direct = computer();
    direct.load_calibration(&saved).unwrap();
    assert_eq!(new.filter(), direct.filter());
    assert_eq!(new.calibration_estimate(), old.calibration_estimate());
    let commands = new.operations.commands;
    assert_eq!((commands.accepted, commands.refused), (1, 0));
    assert_eq!(commands.calibration_records_loaded, 1);
}

#[test]
fn store_commands_without_a_store_a_record_or_a_good_record_are_refused() {
    let mut computer = calibrated();
    let no_store = CommandError::CalibrationStore(CalibrationStoreFault::NoStore);
    for command in [Command::SaveCalibration, Command::LoadCalibration] {
        let refused_before = computer.operations.commands.refused;
        assert_eq!(computer.command(command), Err(no_store));
        assert_eq!(computer.operations.commands.refused, refused_before + 1);
    }
    let mut empty = RamStore {
        record: None,
        writable: false,
    };
    store_command_refused(
        &mut computer,
        Command::LoadCalibration,
        &mut empty,
        CommandError::CalibrationStore(CalibrationStoreFault::Empty),
    );
    store_command_refused(
        &mut computer,
        Command::SaveCalibration,
        &mut empty,
        CommandError::CalibrationStore(CalibrationStoreFault::WriteFailed),
    );
    let mut corrupted = computer.export_calibration().unwrap().to_bytes();
    corrupted[100] ^= 1;
    let mut store = RamStore {
        record: Some(corrupted),
        writable: true,
    };
    let records_refused = computer.operations.commands.calibration_records_refused;
    let before = computer.clone();
    let error = computer
        .command_with_store(Command::LoadCalibration, &mut store)
        .unwrap_err();
    assert!(
        matches!(
            error,
            CommandError::CalibrationRecord(RecordError::Crc { .. })
        ),
        "{error}"
    );
    assert_eq!(computer.filter(), before.filter());
    assert_eq!(
        computer.operations.commands.calibration_records_refused,
        records_refused + 1
    );
}

/// With the systematic IMU error states flown, the record carries their covariance and its
/// covariance with the core calibration into the new computer bit for bit (below the prior
/// where the flight has observed them, so not restarted from it), and their correlation with
/// navigation is zero there.
#[test]
fn a_record_carries_the_imu_error_covariance_into_a_new_computer() {
    let mut config = *computer().config();
    config.filter.imu_error = nav_core::imu_error_states::ImuErrorModel {
        gyro_misalignment_sigma_rad: 1e-3,
        accel_misalignment_sigma_rad: 1e-3,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: 1e-5,
    };
    let mut old = NavigationComputer::new(config, initial_state()).unwrap();
    let prior = old.filter().imu_error().covariance();
    for sequence in 1..=300_u32 {
        run_frame_with_turned_star(&mut old, sequence);
    }
    let record = old.export_calibration().unwrap();
    let expected = old
        .filter()
        .imu_error_covariance_for_restart(&config.filter)
        .unwrap()
        .unwrap();
    assert_eq!(record.imu_error_covariance, expected);
    let mut new = NavigationComputer::new(config, initial_state()).unwrap();
    new.load_calibration(&record.to_bytes()).unwrap();
    let loaded = new
        .filter()
        .imu_error_covariance_for_restart(&config.filter)
        .unwrap()
        .unwrap();
    assert_eq!(loaded, expected);
    let covariance = new.filter().imu_error().covariance();
    assert!((0..12).any(|a| covariance[(a, a)] < (1.0 - 1e-6) * prior[(a, a)]));
    let cross = new.filter().imu_error().cross_covariance();
    assert!((0..DYNAMIC_DIMENSION).all(|n| (0..12).all(|a| cross[(n, a)] == 0.0)));
    assert!((DYNAMIC_DIMENSION..STATE_DIMENSION).any(|j| (0..12).any(|a| cross[(j, a)] != 0.0)));
}
