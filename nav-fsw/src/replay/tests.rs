//! Tests of the replay: assembler, setup words and output record.

use super::*;
use crate::config::FswConfig;
use crate::log_record::test_records::{self, gnss, star};
use crate::sensor_frames::SensorFrames;
use nalgebra::{Quaternion, Vector3};
use nav_core::frames::LaunchSite;
use nav_core::strapdown::NavigationState;

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
    test_records::imu(sequence, time_s, PERIOD_S)
}

fn end_of(frame: u64) -> f64 {
    GRID.start_time_s + PERIOD_S * f64::from(u32::try_from(frame).unwrap())
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
    let mut config = config;
    config.star.slow_error_sigma_rad = [1.5e-5, 2.5e-5, 3.5e-5];
    config.star.slow_error_correlation_time_s = 1420.0;
    config.star.mounting_wxyz = [0.9659, 0.0, -0.2588, 0.0];
    config.star.noise_rad = 4.8e-5;
    config.filter.gnss_error = nav_core::gnss_error::GnssErrorModel {
        sigma_m: 8.0,
        correlation_time_s: 300.0,
    };
    // Not a configuration the flight software accepts (both borders): the words carry any
    // values, and every field must come back.
    config.filter.imu_error = nav_core::imu_error_states::ImuErrorModel {
        gyro_misalignment_sigma_rad: 2e-5,
        accel_misalignment_sigma_rad: 3e-5,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7,
    };
    config.gravity = crate::config::GravityConfig {
        field: nav_core::gravity::harmonics::FieldModel {
            degree: 8,
            order: 6,
            terms_per_frame: 3,
        },
        omitted_field_sigma_mps2: 4.5e-5,
        omitted_field_psd_m2_per_s3: 1.7e-8,
    };
    config.star.roll_noise_rad = 1.7e-4;
    config.star.aberration_correction = true;
    config.star.noise_matching = false;
    config.star.second_head = Some(crate::config::StarHeadConfig {
        mounting_wxyz: [0.5, 0.5, 0.5, 0.5],
        noise_rad: 2.4e-5,
        roll_noise_rad: 1.7e-4,
        alignment_prior_sigma_rad: 1.4e-2,
        pair_gate_nis: 16.27,
        pairs_before_hand_over: 100,
    });
    let initial = NavigationState {
        attitude: Quaternion::new(0.5, 0.5, -0.5, 0.5),
        position_m: Vector3::new(1.0, -2.0, 3.0),
        velocity_mps: Vector3::new(7.5e3, 0.1, -0.2),
        time_s: 600.0,
    };
    let setup = ReplaySetup::new(&config, initial);
    // Every parameter with a word comes back; the rest are the defaults.
    assert_eq!(setup.config(), config);
    // A parameter without a word does not travel.
    let mut untravelled = config;
    untravelled.gnss.max_jump_m = 5.0;
    assert_eq!(ReplaySetup::new(&untravelled, initial), setup);
    let words = setup.to_words();
    assert_eq!(ReplaySetup::from_words(&words), Ok(setup));
    let mut bad = words;
    bad[0] = 0;
    assert!(ReplaySetup::from_words(&bad).is_err());
    bad = words;
    bad[1] = 7;
    assert!(ReplaySetup::from_words(&bad).is_err());
    // The flags follow the floats, aberration correction, noise matching and the second
    // head, 0 or 1; the second head's pair count and its eight floats end the setup.
    let flags = SETUP_WORDS - 12;
    assert_eq!(words[flags..flags + 4], [1, 0, 1, 100]);
    bad = words;
    bad[flags] = 0;
    bad[flags + 1] = 1;
    let flipped = ReplaySetup::from_words(&bad).unwrap();
    let flipped = flipped.config().star;
    assert!(!flipped.aberration_correction && flipped.noise_matching);
    for slot in flags..flags + 3 {
        bad = words;
        bad[slot] = 2;
        assert!(ReplaySetup::from_words(&bad).is_err());
    }
    // Without a second head its words must be zero, the one encoding of that setup.
    bad = words;
    bad[flags + 2] = 0;
    assert!(ReplaySetup::from_words(&bad).is_err());
    for word in &mut bad[flags + 3..] {
        *word = 0;
    }
    let one_head = ReplaySetup::from_words(&bad).unwrap();
    assert_eq!(one_head.config().star.second_head, None);
    assert_eq!(one_head.to_words()[flags + 2..], [0; 10]);
    bad = one_head.to_words();
    bad[SETUP_WORDS - 1] = 1;
    assert!(ReplaySetup::from_words(&bad).is_err());
}

/// The optional state blocks' words follow the record's other words: their names are the
/// telemetry's field names (the systematic IMU errors' from nav-core's block and component
/// names), a block not flown has its bit clear and NaN in its words, and a flown block's
/// fields land bit for bit in its words.
#[test]
fn the_optional_state_words_carry_each_flown_block_and_nan_for_the_others() {
    use crate::telemetry::{
        GnssErrorTelemetry, ImuErrorTelemetry, OptionalStateTelemetry, GNSS_ERROR_FIELD_NAMES,
        IMU_ERROR_FIELD_NAMES,
    };
    use nav_core::imu_error::ImuErrorBlock;
    let first = OUTPUT_WORDS - OPTIONAL_STATE_WORDS;
    assert_eq!(OUTPUT_FIELD_NAMES[first], "optional_blocks");
    let names: Vec<&str> = GNSS_ERROR_FIELD_NAMES
        .iter()
        .chain(&IMU_ERROR_FIELD_NAMES)
        .copied()
        .collect();
    assert_eq!(OUTPUT_FIELD_NAMES[first + 1..], names[..]);
    let mut nav_core_names = Vec::new();
    for block in ImuErrorBlock::ALL {
        let unit = match block {
            ImuErrorBlock::GyroGSensitivity => "rad_s_per_mps2",
            _ => "rad",
        };
        for sigma in ["", "sigma_"] {
            for k in 0..block.dimension() {
                let component = block.component_name(k);
                nav_core_names.push(format!("{}_{sigma}{component}_{unit}", block.name()));
            }
        }
    }
    assert_eq!(
        IMU_ERROR_FIELD_NAMES.map(str::to_owned).to_vec(),
        nav_core_names
    );

    let none = optional_state_words(&OptionalStateTelemetry::default());
    assert_eq!(none[0], 0);
    assert!(none[1..].iter().all(|word| *word == f64::NAN.to_bits()));

    let gnss = GnssErrorTelemetry {
        estimate_m: [1.5, -2.25, 3.0],
        sigma_m: [7.5, 7.75, 8.0],
    };
    fn ramp<const N: usize>(offset: f64) -> [f64; N] {
        core::array::from_fn(|k| offset + k as f64 / 8.0)
    }
    let imu = ImuErrorTelemetry {
        gyro_non_orthogonality_rad: ramp(1.0),
        gyro_non_orthogonality_sigma_rad: ramp(2.0),
        accel_misalignment_rad: ramp(3.0),
        accel_misalignment_sigma_rad: ramp(4.0),
        gyro_g_sensitivity_rad_s_per_mps2: ramp(5.0),
        gyro_g_sensitivity_sigma_rad_s_per_mps2: ramp(6.0),
    };
    let bits = |values: &[f64]| values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&imu.estimates()[3..5]), bits(&[3.0, 3.125]));
    assert_eq!(bits(&imu.sigmas()[9..]), bits(&[6.0, 6.125, 6.25]));
    let word = |words: &[u64], name: &str| {
        let index = OUTPUT_FIELD_NAMES.iter().position(|n| *n == name).unwrap();
        words[index - first]
    };
    let both = optional_state_words(&OptionalStateTelemetry {
        gnss_error: Some(gnss),
        imu_error: Some(imu),
    });
    assert_eq!(both[0], GNSS_ERROR_BLOCK_BIT | IMU_ERROR_BLOCK_BIT);
    assert_eq!(word(&both, "gnss_error_y_m"), f64::to_bits(-2.25));
    assert_eq!(word(&both, "gnss_error_sigma_z_m"), f64::to_bits(8.0));
    assert_eq!(
        word(&both, "gyro_non_orthogonality_sigma_zx_rad"),
        f64::to_bits(2.125)
    );
    assert_eq!(
        word(&both, "accel_misalignment_zy_rad"),
        f64::to_bits(3.625)
    );
    assert_eq!(
        word(&both, "gyro_g_sensitivity_sigma_z_rad_s_per_mps2"),
        f64::to_bits(6.25)
    );
    let imu_only = optional_state_words(&OptionalStateTelemetry {
        gnss_error: None,
        imu_error: Some(imu),
    });
    assert_eq!(imu_only[0], IMU_ERROR_BLOCK_BIT);
    assert!(f64::from_bits(word(&imu_only, "gnss_error_x_m")).is_nan());
    assert_eq!(
        word(&imu_only, "accel_misalignment_sigma_xy_rad"),
        f64::to_bits(4.0)
    );
}
