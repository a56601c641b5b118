//! Tests of the binary log: round trips, canonical form, typed errors.

use super::*;
use proptest::prelude::*;

#[test]
fn arrival_time_and_time_of_validity_come_from_the_right_fields() {
    let imu = LogRecord::Imu(ImuRecord {
        sequence: 7,
        time_s: 12.5,
        interval_s: 0.002,
        delta_angle_rad: [0.0; 3],
        delta_velocity_mps: [0.0; 3],
    });
    let star = LogRecord::Star(StarRecord {
        arrival_time_s: 20.25,
        time_tag_s: 20.125,
        attitude_wxyz: [1.0, 0.0, 0.0, 0.0],
        head: 0,
    });
    let gnss = LogRecord::Gnss(GnssRecord {
        arrival_time_s: 30.5,
        gps_week: 2300,
        gps_seconds_of_week: 30.375,
        position_ecef_m: [0.0; 3],
        velocity_ecef_mps: None,
    });
    let times = [imu, star, gnss].map(|r| (r.arrival_time_s(), r.time_tag_s()));
    assert_eq!(
        times,
        [(12.5, Some(12.5)), (20.25, Some(20.125)), (30.5, None)]
    );
}

#[test]
fn errors_explain_themselves() {
    let text = |error: LogRecordError| {
        let mut buffer = heapless::String::<96>::new();
        core::fmt::write(&mut buffer, format_args!("{error}")).unwrap();
        buffer
    };
    assert_eq!(
        text(LogRecordError::BadMagic),
        "not a replay log (bad magic)"
    );
    let mut expected = heapless::String::<96>::new();
    core::fmt::write(
        &mut expected,
        format_args!("record size 3 (expected {RECORD_SIZE})"),
    )
    .unwrap();
    assert_eq!(text(LogRecordError::RecordSizeMismatch(3)), expected);
}

/// The record's fields as bit patterns, for bitwise equality (`-0.0 != 0.0`).
fn field_bits(record: &LogRecord) -> (u8, [u64; WORDS]) {
    (record.tag(), record.words().map(|(bits, _)| bits))
}

fn finite() -> impl Strategy<Value = f64> {
    any::<f64>().prop_filter("finite", |value| value.is_finite())
}

fn record() -> impl Strategy<Value = LogRecord> {
    let imu = (
        any::<u64>(),
        finite(),
        finite(),
        proptest::array::uniform3(finite()),
        proptest::array::uniform3(finite()),
    )
        .prop_map(|(sequence, time_s, interval_s, angle, velocity)| {
            LogRecord::Imu(ImuRecord {
                sequence,
                time_s,
                interval_s,
                delta_angle_rad: angle,
                delta_velocity_mps: velocity,
            })
        });
    let star = (
        finite(),
        finite(),
        proptest::array::uniform4(finite()),
        any::<u8>(),
    )
        .prop_map(|(arrival_time_s, time_tag_s, attitude_wxyz, head)| {
            LogRecord::Star(StarRecord {
                arrival_time_s,
                time_tag_s,
                attitude_wxyz,
                head,
            })
        });
    let velocity = proptest::option::of(proptest::array::uniform3(finite()));
    let gnss = (
        (finite(), any::<u32>()),
        finite(),
        proptest::array::uniform3(finite()),
        velocity,
    )
        .prop_map(
            |(
                (arrival_time_s, gps_week),
                gps_seconds_of_week,
                position_ecef_m,
                velocity_ecef_mps,
            )| {
                LogRecord::Gnss(GnssRecord {
                    arrival_time_s,
                    gps_week,
                    gps_seconds_of_week,
                    position_ecef_m,
                    velocity_ecef_mps,
                })
            },
        );
    prop_oneof![imu, star, gnss]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn decode_inverts_encode_bitwise(record in record()) {
        let bytes = record.encode().unwrap();
        let decoded = LogRecord::decode(&bytes).unwrap();
        prop_assert_eq!(field_bits(&decoded), field_bits(&record));
        prop_assert_eq!(decoded.encode().unwrap(), bytes);
    }

    /// Whatever the bytes: no panic, and what is accepted is canonical.
    #[test]
    fn decoding_arbitrary_bytes_never_panics(bytes in proptest::array::uniform::<_, 80>(any::<u8>())) {
        if let Ok(record) = LogRecord::decode(&bytes) {
            prop_assert_eq!(record.encode().unwrap(), bytes);
        }
    }

    /// A valid tag and zero reserved bytes, then words mixing finite floats, NaN, infinity,
    /// zero and arbitrary bits: every rejection is the typed error of the first bad word.
    #[test]
    fn rejections_name_the_first_bad_word(
        tag in 1_u8..=4,
        words in proptest::array::uniform9(prop_oneof![
            any::<u64>(),
            finite().prop_map(f64::to_bits),
            Just(0_u64),
            Just(f64::NAN.to_bits()),
            Just(f64::NEG_INFINITY.to_bits()),
        ]),
    ) {
        let mut bytes = [0_u8; RECORD_SIZE];
        bytes[0] = tag;
        for (index, word) in words.iter().enumerate() {
            bytes[offset_of(index)..offset_of(index) + WORD].copy_from_slice(&word.to_le_bytes());
        }
        // Words carrying floats, and the unused words, per tag (module-doc table); GNSS
        // records carry the GPS week in the last word, star records the head after the
        // quaternion.
        let (float_words, unused) = match tag {
            TAG_IMU => (1..9, 9..WORDS),
            TAG_STAR => (0..6, 7..WORDS),
            TAG_GNSS_VELOCITY => (0..8, 8..8),
            _ => (0..5, 5..8),
        };
        let first_non_finite = float_words
            .clone()
            .find(|index| !f64::from_bits(words[*index]).is_finite());
        let first_padding = unused.clone().find(|index| words[*index] != 0);
        let gnss = tag == TAG_GNSS || tag == TAG_GNSS_VELOCITY;
        let wide_week = gnss && u32::try_from(words[8]).is_err();
        let wide_head = tag == TAG_STAR && u8::try_from(words[6]).is_err();
        match LogRecord::decode(&bytes) {
            Ok(record) => {
                prop_assert!(
                    first_non_finite.is_none() && first_padding.is_none() && !wide_week && !wide_head
                );
                prop_assert_eq!(record.encode().unwrap(), bytes);
            }
            Err(LogRecordError::GpsWeek(week)) => {
                prop_assert!(first_non_finite.is_none() && first_padding.is_none());
                prop_assert_eq!(week, words[8]);
            }
            Err(LogRecordError::StarHead(head)) => {
                prop_assert!(first_non_finite.is_none() && wide_head);
                prop_assert_eq!(head, words[6]);
            }
            Err(LogRecordError::NonFinite { offset, .. }) => {
                prop_assert_eq!(Some(offset), first_non_finite.map(offset_of));
            }
            Err(LogRecordError::NonZeroPadding { offset }) => {
                prop_assert!(first_non_finite.is_none());
                let index = first_padding.unwrap();
                prop_assert!(offset >= offset_of(index) && offset < offset_of(index) + WORD);
                prop_assert_ne!(bytes[offset], 0);
            }
            Err(other) => prop_assert!(false, "unexpected {:?}", other),
        }
    }
}

#[test]
fn known_layout() {
    let record = LogRecord::Gnss(GnssRecord {
        arrival_time_s: 1.5,
        gps_week: 2_391,
        gps_seconds_of_week: 1.0,
        position_ecef_m: [-2.0, 0.25, 6.4e6],
        velocity_ecef_mps: None,
    });
    let bytes = record.encode().unwrap();
    assert_eq!(bytes[0], TAG_GNSS);
    assert_eq!(bytes[8..16], 1.5_f64.to_le_bytes());
    assert_eq!(bytes[16..24], 1.0_f64.to_le_bytes());
    assert_eq!(bytes[24..32], (-2.0_f64).to_le_bytes());
    assert_eq!(bytes[40..48], 6.4e6_f64.to_le_bytes());
    assert!(bytes[48..72].iter().all(|byte| *byte == 0));
    assert_eq!(bytes[72..80], 2_391_u64.to_le_bytes());
    assert_eq!(LogRecord::decode(&bytes), Ok(record));
    let mut wide = bytes;
    wide[76] = 1;
    assert_eq!(
        LogRecord::decode(&wide),
        Err(LogRecordError::GpsWeek((1 << 32) + 2_391))
    );

    // With the receiver's velocity: tag 4, velocity in the words at 48, 56, 64.
    let with_velocity = LogRecord::Gnss(GnssRecord {
        arrival_time_s: 1.5,
        gps_week: 2_391,
        gps_seconds_of_week: 1.0,
        position_ecef_m: [-2.0, 0.25, 6.4e6],
        velocity_ecef_mps: Some([7.5e3, -0.5, 3.0]),
    });
    let bytes = with_velocity.encode().unwrap();
    assert_eq!(bytes[0], TAG_GNSS_VELOCITY);
    assert_eq!(bytes[48..56], 7.5e3_f64.to_le_bytes());
    assert_eq!(bytes[64..72], 3.0_f64.to_le_bytes());
    assert_eq!(bytes[72..80], 2_391_u64.to_le_bytes());
    assert_eq!(LogRecord::decode(&bytes), Ok(with_velocity));
    let mut bad = bytes;
    bad[56..64].copy_from_slice(&f64::NAN.to_le_bytes());
    assert_eq!(
        LogRecord::decode(&bad),
        Err(LogRecordError::NonFinite {
            field: RecordField::Velocity,
            offset: 56
        })
    );

    let imu = LogRecord::Imu(ImuRecord {
        sequence: 0x0000_0001_0000_0005,
        time_s: 0.004,
        interval_s: 0.002,
        delta_angle_rad: [1e-6, 0.0, -0.0],
        delta_velocity_mps: [0.0, 0.0, -0.0196],
    });
    let bytes = imu.encode().unwrap();
    assert_eq!(bytes[0], TAG_IMU);
    assert_eq!(bytes[8..16], 0x0000_0001_0000_0005_u64.to_le_bytes());
    assert_eq!(bytes[48..56], (-0.0_f64).to_le_bytes());
    assert_eq!(bytes[72..80], (-0.0196_f64).to_le_bytes());
    let LogRecord::Imu(decoded) = LogRecord::decode(&bytes).unwrap() else {
        panic!("not an IMU record");
    };
    // The port's 32-bit counter is the low half of the log's 64-bit counter.
    assert_eq!(decoded.to_imu_sample().sequence, 5);
}

/// One case per error variant, as a table: longer than a function usually is, since
/// splitting it would scatter the table.
#[test]
fn typed_errors() {
    let star = LogRecord::Star(StarRecord {
        arrival_time_s: 2.0,
        time_tag_s: 2.0,
        attitude_wxyz: [1.0, 0.0, 0.0, 0.0],
        head: 0,
    });
    let good = star.encode().unwrap();

    let mut bytes = good;
    bytes[0] = 0;
    assert_eq!(
        LogRecord::decode(&bytes),
        Err(LogRecordError::UnknownTag(0))
    );
    bytes[0] = 5;
    assert_eq!(
        LogRecord::decode(&bytes),
        Err(LogRecordError::UnknownTag(5))
    );

    let mut bytes = good;
    bytes[3] = 1;
    assert_eq!(
        LogRecord::decode(&bytes),
        Err(LogRecordError::NonZeroPadding { offset: 3 })
    );
    let mut bytes = good;
    bytes[69] = 0x80;
    assert_eq!(
        LogRecord::decode(&bytes),
        Err(LogRecordError::NonZeroPadding { offset: 69 })
    );
    let mut bytes = good;
    bytes[57] = 0x01;
    assert_eq!(
        LogRecord::decode(&bytes),
        Err(LogRecordError::StarHead(0x100))
    );

    let mut bytes = good;
    bytes[40..48].copy_from_slice(&f64::NAN.to_le_bytes());
    assert_eq!(
        LogRecord::decode(&bytes),
        Err(LogRecordError::NonFinite {
            field: RecordField::Attitude,
            offset: 40
        })
    );
    let mut bytes = good;
    bytes[16..24].copy_from_slice(&f64::NEG_INFINITY.to_le_bytes());
    assert_eq!(
        LogRecord::decode(&bytes),
        Err(LogRecordError::NonFinite {
            field: RecordField::TimeTag,
            offset: 16
        })
    );

    let infinite = LogRecord::Imu(ImuRecord {
        sequence: 0,
        time_s: 0.0,
        interval_s: 0.002,
        delta_angle_rad: [0.0; 3],
        delta_velocity_mps: [0.0, f64::INFINITY, 0.0],
    });
    assert_eq!(
        infinite.encode(),
        Err(LogRecordError::NonFinite {
            field: RecordField::DeltaVelocity,
            offset: 64
        })
    );

    assert_eq!(
        LogRecord::decode_prefix(&good[..79]),
        Err(LogRecordError::Truncated {
            needed: 80,
            available: 79
        })
    );
    let mut two = [0_u8; 160];
    two[..80].copy_from_slice(&good);
    two[80..].copy_from_slice(&good);
    let (first, rest) = LogRecord::decode_prefix(&two).unwrap();
    assert_eq!(first, star);
    assert_eq!(rest.len(), 80);
}

#[test]
fn header() {
    let header = encode_header();
    assert_eq!(&header[..8], b"NAVLOG\0\0");
    assert_eq!(decode_header(&header), Ok(()));
    let mut bad = header;
    bad[0] = b'X';
    assert_eq!(decode_header(&bad), Err(LogRecordError::BadMagic));
    let mut bad = header;
    bad[8] = 3;
    assert_eq!(
        decode_header(&bad),
        Err(LogRecordError::UnsupportedVersion(3))
    );
    // A version-1 log (launch-inertial star, navigation-time GNSS) is refused, saying why.
    bad[8] = 1;
    let error = decode_header(&bad).unwrap_err();
    assert_eq!(error, LogRecordError::UnsupportedVersion(1));
    let mut text = heapless::String::<256>::new();
    core::fmt::write(&mut text, format_args!("{error}")).unwrap();
    assert!(
        text.contains("launch-inertial") && text.contains("GPS time"),
        "{text}"
    );
    let mut bad = header;
    bad[12] = 81;
    assert_eq!(
        decode_header(&bad),
        Err(LogRecordError::RecordSizeMismatch(81))
    );
}
