//! The calibration record: a round trip through its bytes into a new computer carries the
//! calibration bit for bit; a record with one bit flipped anywhere, another version, another
//! configuration or bad values is refused, counted, and changes nothing.

use super::tests::{computer, initial_state, run_frame_with_turned_star};
use super::*;
use crate::calibration_record::{CalibrationRecord, RecordError, CALIBRATION_RECORD_BYTES};
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
    version[8] = 2;
    let crc = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC)
        .checksum(&version[..CALIBRATION_RECORD_BYTES - 4]);
    version[CALIBRATION_RECORD_BYTES - 4..].copy_from_slice(&crc.to_le_bytes());
    assert_eq!(
        refused(&mut new, &version),
        RecordError::Version { found: 2 }
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
