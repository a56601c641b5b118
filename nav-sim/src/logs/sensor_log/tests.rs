//! Unit tests of the sensor-log formats: CSV round trips and errors, binary conversion.

use nav_fsw::log_record::{
    GnssRecord, ImuRecord, LogRecord, LogRecordError, StarRecord, HEADER_SIZE, RECORD_SIZE,
};

use super::*;
use crate::scenario::Scenario;
use proptest::prelude::*;

fn write_csv(records: &[LogRecord]) -> Vec<u8> {
    let mut log = SensorLogWriter::new(Vec::new()).unwrap();
    for record in records {
        log.write(record).unwrap();
    }
    log.finish().unwrap()
}

fn read_csv(bytes: &[u8]) -> Result<Vec<LogRecord>, SensorLogError> {
    SensorLogReader::new(bytes)?.collect()
}

/// Bit patterns of every field (the binary encoding is exactly that).
fn bits(records: &[LogRecord]) -> Vec<[u8; RECORD_SIZE]> {
    records
        .iter()
        .map(|record| record.encode().unwrap())
        .collect()
}

/// A record of any kind from nine arbitrary finite floats; arrival times are set by the
/// caller to keep the log in order.
fn record_from(kind: u8, sequence: u64, arrival_time_s: f64, values: [f64; 9]) -> LogRecord {
    let [a, b, c, d, e, f, g, h, i] = values;
    match kind % 4 {
        0 => LogRecord::Imu(ImuRecord {
            sequence,
            time_s: arrival_time_s,
            interval_s: a,
            delta_angle_rad: [b, c, d],
            delta_velocity_mps: [e, f, g],
        }),
        1 => LogRecord::Star(StarRecord {
            arrival_time_s,
            time_tag_s: a,
            attitude_wxyz: [b, c, d, e],
            head: 0,
        }),
        2 => LogRecord::Gnss(GnssRecord {
            arrival_time_s,
            gps_week: sequence as u32,
            gps_seconds_of_week: h,
            position_ecef_m: [i, a, b],
            velocity_ecef_mps: None,
        }),
        _ => LogRecord::Gnss(GnssRecord {
            arrival_time_s,
            gps_week: sequence as u32,
            gps_seconds_of_week: h,
            position_ecef_m: [i, a, b],
            velocity_ecef_mps: Some([c, d, e]),
        }),
    }
}

fn finite() -> impl Strategy<Value = f64> {
    any::<f64>().prop_filter("finite", |value| value.is_finite())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Any finite values (subnormals, ±0, extremes included) survive CSV and binary
    /// bit for bit.
    #[test]
    fn csv_and_binary_round_trip_bit_exactly(
        rows in proptest::collection::vec(
            (any::<u8>(), any::<u64>(), finite(), proptest::array::uniform9(finite())),
            0..40,
        )
    ) {
        let mut arrivals: Vec<f64> = rows.iter().map(|row| row.2).collect();
        arrivals.sort_by(f64::total_cmp);
        let records: Vec<LogRecord> = rows
            .iter()
            .zip(arrivals)
            .map(|(&(kind, sequence, _, values), arrival)| record_from(kind, sequence, arrival, values))
            .collect();
        let csv = write_csv(&records);
        let read = read_csv(&csv).unwrap();
        prop_assert_eq!(bits(&read), bits(&records));

        let mut binary = Vec::new();
        let count = convert_csv_to_binary(csv.as_slice(), &mut binary).unwrap();
        prop_assert_eq!(count, u64::try_from(records.len()).unwrap());
        prop_assert_eq!(binary.len(), HEADER_SIZE + RECORD_SIZE * records.len());
        prop_assert_eq!(bits(&read_binary(binary.as_slice()).unwrap()), bits(&records));
    }

    /// Arbitrary text never panics the reader.
    #[test]
    fn reader_never_panics_on_arbitrary_rows(body in "[a-z0-9.,eE+-]{0,200}(\n[a-z0-9.,eE+-]{0,200}){0,5}") {
        let text = format!("{}\n{body}", COLUMNS.join(","));
        let _ = read_csv(text.as_bytes());
    }
}

/// The simulator's own stream (first 3 s of the default scenario: IMU, star, GNSS)
/// survives the CSV log exactly.
#[test]
fn simulator_events_round_trip() {
    let scenario = Scenario::default_scenario().unwrap();
    let mut simulation = Simulation::new(&scenario).unwrap();
    let mut events = Vec::new();
    for _ in 0..1500 {
        simulation.step(&mut events).unwrap();
    }
    let count = |wanted: fn(&SensorEvent) -> bool| events.iter().filter(|e| wanted(e)).count();
    assert_eq!(count(|e| matches!(e, SensorEvent::Imu { .. })), 1500);
    assert!(count(|e| matches!(e, SensorEvent::Star { .. })) >= 10);
    assert!(count(|e| matches!(e, SensorEvent::Gnss { .. })) >= 2);

    let mut log = SensorLogWriter::new(Vec::new()).unwrap();
    for event in &events {
        log.write_event(event).unwrap();
    }
    let csv = log.finish().unwrap();
    let frames = crate::setup::launch::scenario_ground_constants(&scenario)
        .unwrap()
        .sensor_frames;
    let read = read_events(csv.as_slice(), &frames).unwrap();
    // Bit for bit in the log's own terms (a GNSS event's navigation time is re-derived from
    // its GPS tag, exact to the rounding of the seconds of week, ~1e-11 s).
    assert_eq!(read.len(), events.len());
    let event_bits =
        |events: &[SensorEvent]| bits(&events.iter().map(record_of).collect::<Vec<_>>());
    assert_eq!(event_bits(&read), event_bits(&events));

    let text = String::from_utf8(csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), COLUMNS.join(","));
    let first = lines.next().unwrap();
    assert!(first.starts_with("imu,600.002,600.002,0,0.002,"), "{first}");
}

/// The default mission's first two phases, streamed to CSV, read back as the simulator's
/// stream.
#[test]
fn recorded_mission_reads_back_as_the_event_stream() {
    let mut scenario = Scenario::default_scenario().unwrap();
    scenario.manoeuvres.truncate(2);
    let mut csv = Vec::new();
    let recorded = record_simulation(Simulation::new(&scenario).unwrap(), &mut csv).unwrap();
    assert_eq!(recorded.withheld_star_measurements, 0);
    let rows = recorded.rows;
    let expected = Simulation::new(&scenario).unwrap().event_stream().unwrap();
    assert_eq!(rows, u64::try_from(expected.len()).unwrap());
    let imu_rows = expected
        .iter()
        .filter(|event| matches!(event, SensorEvent::Imu { .. }))
        .count();
    assert_eq!(u64::try_from(imu_rows).unwrap(), scenario.frame_count());
    let frames = crate::setup::launch::scenario_ground_constants(&scenario)
        .unwrap()
        .sensor_frames;
    let read = read_events(csv.as_slice(), &frames).unwrap();
    assert_eq!(read.len(), expected.len());
    assert!(read
        .iter()
        .zip(&expected)
        .all(|(read, expected)| record_of(read).encode() == record_of(expected).encode()));
    println!(
        "default mission log: {rows} rows, {} bytes of CSV",
        csv.len()
    );
}

/// A row of 18 or 23 fields (an IMU row's, a GNSS row's) padded to [`COLUMNS`]; any other
/// row as it is (too short: the CSV error of unequal lengths).
fn padded(row: &str) -> String {
    let commas = row.matches(',').count();
    if commas == 17 || commas == 22 {
        format!("{row}{}", ",".repeat(COLUMNS.len() - 1 - commas))
    } else {
        row.to_string()
    }
}

/// Expected error for a log whose only data row is `row` (line 2), padded.
fn error_of(row: &str) -> SensorLogError {
    let text = format!("{}\n{}\n", COLUMNS.join(","), padded(row));
    read_csv(text.as_bytes()).unwrap_err()
}

/// GNSS velocity columns: all three filled or all three empty; the earlier 18- and
/// 21-column layouts are refused, saying why; a velocity round-trips bit for bit.
#[test]
fn gnss_velocity_columns() {
    let header = COLUMNS.join(",");
    let row = padded("gnss,2,,,,,,,,,,,,,,1,2,3,0.5,-0.25,7500,2300,2");
    let records = read_csv(format!("{header}\n{row}\n").as_bytes()).unwrap();
    let LogRecord::Gnss(gnss) = records[0] else {
        panic!("not a GNSS record")
    };
    assert_eq!(gnss.velocity_ecef_mps, Some([0.5, -0.25, 7500.0]));
    let position_only = padded("gnss,2,,,,,,,,,,,,,,1,2,3,,,,2300,2");
    let records = read_csv(format!("{header}\n{position_only}\n").as_bytes()).unwrap();
    assert!(matches!(
        records[0],
        LogRecord::Gnss(GnssRecord {
            velocity_ecef_mps: None,
            ..
        })
    ));
    let partial = padded("gnss,2,,,,,,,,,,,,,,1,2,3,0.5,,7500,2300,2");
    assert_eq!(
        read_csv(format!("{header}\n{partial}\n").as_bytes())
            .unwrap_err()
            .to_string(),
        "line 2, column `velocity_ecef_y_mps`: missing value (needed in `gnss` rows)"
    );
    for columns in [18, 21] {
        let legacy = COLUMNS[..columns].join(",");
        let error =
            read_csv(format!("{legacy}\ngnss,2,2,,,,,,,,,,,,,1,2,3\n").as_bytes()).unwrap_err();
        assert!(matches!(error, SensorLogError::OldLayout { columns: c } if c == columns));
        assert!(error.to_string().contains("GPS week"), "{error}");
    }
    let records = read_csv(format!("{header}\n{position_only}\n").as_bytes()).unwrap();
    let mut log = SensorLogWriter::new(Vec::new()).unwrap();
    log.write(&records[0]).unwrap();
    let with_velocity = LogRecord::Gnss(GnssRecord {
        velocity_ecef_mps: Some([0.1, f64::MIN_POSITIVE, -7.6e3]),
        ..match records[0] {
            LogRecord::Gnss(gnss) => gnss,
            _ => unreachable!(),
        }
    });
    log.write(&with_velocity).unwrap();
    let written = log.finish().unwrap();
    assert_eq!(
        bits(&read_csv(&written).unwrap()),
        bits(&[records[0], with_velocity])
    );
}

const IMU_ROW: &str = "imu,1.5,1.5,7,0.002,1e-6,0,0,0,0,-0.02,,,,,,,";

#[test]
fn reader_errors_name_line_and_column() {
    let good =
        read_csv(format!("{}\n{}\n", COLUMNS.join(","), padded(IMU_ROW)).as_bytes()).unwrap();
    assert_eq!(good.len(), 1);

    let message = |error: SensorLogError| error.to_string();
    assert_eq!(
        message(error_of(&IMU_ROW.replacen("imu", "lidar", 1))),
        "line 2, column `kind`: unknown kind `lidar` (expected imu, star or gnss)"
    );
    assert_eq!(
        message(error_of(&IMU_ROW.replacen(",7,", ",,", 1))),
        "line 2, column `sequence`: missing value (needed in `imu` rows)"
    );
    assert!(matches!(
        error_of(&IMU_ROW.replacen(",7,", ",-7,", 1)),
        SensorLogError::Invalid {
            line: 2,
            column: "sequence",
            ..
        }
    ));
    assert!(matches!(
        error_of(&IMU_ROW.replacen("1e-6", "1e-6x", 1)),
        SensorLogError::Invalid {
            line: 2,
            column: "delta_angle_x_rad",
            ..
        }
    ));
    assert!(matches!(
        error_of(&IMU_ROW.replacen("-0.02", "NaN", 1)),
        SensorLogError::NonFinite {
            line: 2,
            column: "delta_velocity_z_mps",
            ..
        }
    ));
    assert!(matches!(
        error_of(&format!("{IMU_ROW}1")),
        SensorLogError::NotApplicable {
            line: 2,
            column: "position_ecef_z_m",
            kind: "imu",
            ..
        }
    ));
    assert!(matches!(
        error_of(&IMU_ROW.replacen("1.5,1.5", "1.5,1.25", 1)),
        SensorLogError::ImuTimeMismatch { line: 2, .. }
    ));
    assert!(matches!(
        error_of("star,1,1,,,,,,,,,1,0,0"),
        SensorLogError::Csv { line: 2, .. }
    ));
    assert!(matches!(
        error_of("gnss,1,,,,,,,,,,,,,,1,2,,,,,2300,5"),
        SensorLogError::Missing {
            line: 2,
            column: "position_ecef_z_m",
            kind: "gnss"
        }
    ));

    let out_of_order = format!(
        "{}\n{}\n{}\n",
        COLUMNS.join(","),
        padded(IMU_ROW),
        "star,1.25,1.25,,,,,,,,,1,0,0,0,,,,,,,,,0"
    );
    assert!(matches!(
        read_csv(out_of_order.as_bytes()).unwrap_err(),
        SensorLogError::OutOfOrder { line: 3, .. }
    ));

    let header = COLUMNS.join(",").replace("attitude_x", "attitude_i");
    match SensorLogReader::new(header.as_bytes()).err().unwrap() {
        SensorLogError::Header {
            position,
            expected,
            found,
        } => {
            assert_eq!(
                (position, expected, found.as_str()),
                (13, "attitude_x", "attitude_i")
            );
        }
        other => panic!("{other}"),
    }
    let short_header = COLUMNS[..17].join(",");
    assert!(matches!(
        SensorLogReader::new(short_header.as_bytes()).err().unwrap(),
        SensorLogError::Header { position: 18, found, .. } if found.is_empty()
    ));

    let latency = format!(
        "{}\n{}\n",
        COLUMNS.join(","),
        "star,1.25,1,,,,,,,,,1,0,0,0,,,,,,,,,0"
    );
    assert!(read_csv(latency.as_bytes()).is_ok());
    assert!(matches!(
        read_events(latency.as_bytes(), &SensorFrames::ALIGNED).unwrap_err(),
        SensorLogError::StarLatency { line: 2, .. }
    ));
}

#[test]
fn writer_refuses_what_the_reader_would_refuse() {
    let mut log = SensorLogWriter::new(Vec::new()).unwrap();
    let gnss = |arrival_time_s: f64, x: f64| {
        LogRecord::Gnss(GnssRecord {
            arrival_time_s,
            gps_week: 2_300,
            gps_seconds_of_week: arrival_time_s,
            position_ecef_m: [x, 0.0, 0.0],
            velocity_ecef_mps: None,
        })
    };
    log.write(&gnss(2.0, 1.0)).unwrap();
    assert!(matches!(
        log.write(&gnss(3.0, f64::INFINITY)).unwrap_err(),
        SensorLogError::NonFinite {
            line: 3,
            column: "position_ecef_x_m",
            ..
        }
    ));
    assert!(matches!(
        log.write(&gnss(1.0, 1.0)).unwrap_err(),
        SensorLogError::OutOfOrder { line: 3, .. }
    ));
}

#[test]
fn binary_errors_name_the_record() {
    let records = [
        record_from(1, 0, 1.0, [1.0; 9]),
        record_from(2, 0, 2.0, [3.0; 9]),
    ];
    let mut binary = Vec::new();
    convert_csv_to_binary(write_csv(&records).as_slice(), &mut binary).unwrap();
    assert_eq!(
        bits(&read_binary(binary.as_slice()).unwrap()),
        bits(&records)
    );

    let mut bad_tag = binary.clone();
    bad_tag[HEADER_SIZE + RECORD_SIZE] = 9;
    assert_eq!(
        read_binary(bad_tag.as_slice()).unwrap_err().to_string(),
        "binary log record 1: unknown tag 9"
    );
    let truncated = &binary[..binary.len() - 1];
    assert!(matches!(
        read_binary(truncated).unwrap_err(),
        SensorLogError::Binary {
            record: Some(1),
            error: LogRecordError::Truncated {
                needed: 80,
                available: 79
            }
        }
    ));
    assert!(matches!(
        read_binary(&binary[..5]).unwrap_err(),
        SensorLogError::Binary {
            record: None,
            error: LogRecordError::Truncated { .. }
        }
    ));
    let mut bad_magic = binary;
    bad_magic[0] = b'X';
    assert!(matches!(
        read_binary(bad_magic.as_slice()).unwrap_err(),
        SensorLogError::Binary {
            record: None,
            error: LogRecordError::BadMagic
        }
    ));
}

/// The `star_head` column: written and read for every head, required in a star row, a u8;
/// a log of the layout before it (23 columns) reads its star rows as head 0's.
#[test]
fn star_rows_carry_their_head() {
    let star = |head: u8| {
        LogRecord::Star(StarRecord {
            arrival_time_s: 1.5,
            time_tag_s: 1.5,
            attitude_wxyz: [0.5, 0.5, -0.5, 0.5],
            head,
        })
    };
    let mut log = SensorLogWriter::new(Vec::new()).unwrap();
    log.write(&star(0)).unwrap();
    log.write(&star(1)).unwrap();
    let written = log.finish().unwrap();
    let text = String::from_utf8(written.clone()).unwrap();
    assert!(text.lines().nth(2).unwrap().ends_with(",1"), "{text}");
    let read = read_csv(&written).unwrap();
    assert_eq!(read.len(), 2);
    assert!(matches!(
        read[1],
        LogRecord::Star(StarRecord { head: 1, .. })
    ));
    assert_eq!(read[1].encode(), star(1).encode());

    let header = COLUMNS.join(",");
    let body = "star,1.5,1.5,,,,,,,,,0.5,0.5,-0.5,0.5,,,,,,,,";
    let missing = read_csv(format!("{header}\n{body},\n").as_bytes()).unwrap_err();
    assert_eq!(
        missing.to_string(),
        "line 2, column `star_head`: missing value (needed in `star` rows)"
    );
    let wide = read_csv(format!("{header}\n{body},256\n").as_bytes()).unwrap_err();
    assert!(matches!(
        wide,
        SensorLogError::Invalid {
            column: "star_head",
            ..
        }
    ));
    let one_head = COLUMNS[..COLUMNS.len() - 1].join(",");
    let read = read_csv(format!("{one_head}\n{body}\n").as_bytes()).unwrap();
    assert_eq!(read[0].encode(), star(0).encode());
}
