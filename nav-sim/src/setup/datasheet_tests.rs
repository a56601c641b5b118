//! The data sheets of shipped scenarios' sensors configure the flight nav-sim builds for
//! those scenarios ([`super::fsw::fsw_config`]), field by field and bit for bit. Where the
//! data sheet's unit is not the scenario's (°/h, µg, per √h), the data-sheet value is the
//! scenario's SI value in that unit, to the last digit that converts back to its bits.

use nav_fsw::config::{FswConfig, Param};
use nav_fsw::datasheet::{
    AccelBiasInstability, AccelerometerDatasheet, Datasheets, GnssCorrelatedError, GnssDatasheet,
    GravityDatasheet, GyroBiasInstability, GyroDatasheet, HandOverDatasheet, ImuDatasheet,
    LowFrequencyError, StarTrackerDatasheet,
};

use crate::scenario::Scenario;
use crate::setup::fsw::fsw_config;
use crate::setup::launch::Launch;

/// The sensors of the default flight (default.toml: the paper's IMU and 10″ tracker with its
/// 10 mrad installation prior) with realistic_sensors.toml's receiver (6 m white, 8 m
/// correlated over 300 s, 0.05 m/s) and gravity (12 × 12 and its allowance).
fn realistic_sensors() -> Datasheets {
    Datasheets {
        imu: ImuDatasheet {
            output_rate_hz: 500.0,
            gyro: GyroDatasheet {
                // The paper's 0.2 (°/h)/√Hz as an angle random walk.
                angle_random_walk_deg_per_sqrt_h: 0.2 / 60.0,
                // The scenario's initial 1σ, 1e-3 rad/s, in °/h.
                bias_stability_deg_per_h: 206.264_806_247_096_37,
                bias_instability: None,
                rate_random_walk_deg_per_h_per_sqrt_h: None,
                scale_factor_ppm: 100.0,
                misalignment_urad: None,
                g_sensitivity_deg_per_h_per_g: None,
                range_deg_per_s: None,
            },
            accelerometer: AccelerometerDatasheet {
                // 1e-4 m/s² per 2 ms sample: 1e-4 √0.002 m/s²/√Hz, times 60 per √h.
                velocity_random_walk_m_per_s_per_sqrt_h: 2.683_281_572_999_747_7e-4,
                // The scenario's initial 1σ, 1e-2 m/s², in µg.
                bias_stability_ug: 1_019.716_212_977_928_3,
                bias_instability: None,
                bias_random_walk_ug_per_sqrt_h: None,
                scale_factor_ppm: 200.0,
                misalignment_urad: None,
                range_g: None,
            },
        },
        star_tracker: StarTrackerDatasheet {
            cross_boresight_noise_arcsec: 10.0,
            roll_noise_arcsec: 10.0,
            low_frequency_error: None,
            aberration_corrected: true,
            mounting_accuracy_mrad: 10.0,
            mounting_rotation_vector_deg: [0.0, -30.0, 0.0],
            second_head_mounting_rotation_vector_deg: None,
        },
        gnss: GnssDatasheet {
            position_noise_m: 6.0,
            correlated_error: Some(GnssCorrelatedError {
                sigma_m: 8.0,
                correlation_time_s: 300.0,
            }),
            velocity_noise_mps: Some(0.05),
            latency_s: 0.0,
            antenna_lever_arm_m: [0.0; 3],
        },
        gravity: GravityDatasheet {
            degree: 12,
            order: 12,
            terms_per_frame: 4,
            omitted_field_sigma_mps2: 1.9e-5,
            omitted_field_psd_m2_per_s3: 5.5e-8,
        },
        hand_over: HandOverDatasheet {
            attitude_mrad: 1.0,
            position_m: 10.0,
            velocity_mps: 0.1,
        },
    }
}

/// `file`'s flight as nav-sim builds it and as `sheets` configure it, at the scenario's
/// launch site and ground constants.
fn both_configurations(file: &str, sheets: &Datasheets) -> (FswConfig, FswConfig) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(file);
    let scenario = Scenario::load(&path).unwrap();
    let launch = Launch::new(&scenario).unwrap();
    let simulated = fsw_config(&scenario).unwrap();
    let sheets =
        FswConfig::from_datasheets(sheets, launch.site, launch.ground.sensor_frames).unwrap();
    (simulated, sheets)
}

/// Every parameter of the table bit for bit, then the whole configuration: the parts outside
/// the table (launch site, ground constants, strapdown, observability table) too.
fn assert_same_flight(file: &str, sheets: &Datasheets) {
    let (simulated, from_sheets) = both_configurations(file, sheets);
    for &param in Param::ALL {
        let (ours, theirs) = (param.value(&from_sheets), param.value(&simulated));
        assert_eq!(ours.to_bits(), theirs.to_bits(), "{file}: {}", param.path());
    }
    assert_eq!(from_sheets, simulated, "{file}");
}

#[test]
fn the_realistic_sensors_data_sheets_configure_nav_sims_flight() {
    assert_same_flight("realistic_sensors.toml", &realistic_sensors());
}

/// The upper stage's IMU as it is (upper_stage_imu_errors_estimated.toml): bias instability
/// 1e-6 rad/s and 2e-5 m/s² over 600 s, 20 µrad misalignments and 2.47e-7 rad/s per m/s² of
/// g-sensitivity, with the upper stage's mounting and gravity (J2 alone: the file removes
/// the field).
#[test]
fn the_upper_stages_imu_data_sheet_configures_its_error_states() {
    let mut sheets = realistic_sensors();
    sheets.gravity = GravityDatasheet::J2_ONLY;
    sheets.star_tracker.mounting_rotation_vector_deg = [-8.160548, -179.633363, 0.015173];
    let gyro = &mut sheets.imu.gyro;
    gyro.bias_instability = Some(GyroBiasInstability {
        // 1e-6 rad/s in °/h.
        sigma_deg_per_h: 0.206_264_806_247_096_34,
        correlation_time_s: 600.0,
    });
    gyro.misalignment_urad = Some(20.0);
    // 2.47e-7 rad/s per m/s² in °/h/g.
    gyro.g_sensitivity_deg_per_h_per_g = Some(0.499_623_390_259_222_5);
    let accel = &mut sheets.imu.accelerometer;
    accel.bias_instability = Some(AccelBiasInstability {
        // 2e-5 m/s² in µg.
        sigma_ug: 2.039_432_425_955_856_5,
        correlation_time_s: 600.0,
    });
    accel.misalignment_urad = Some(20.0);
    assert_same_flight("upper_stage_imu_errors_estimated.toml", &sheets);
}

/// The two-head tracker with roll noise (star_tracker_two_heads.toml: 5″ across, 35″ in
/// roll, head 1 at −90° about body x) and the orbit-periodic low-frequency error
/// (star_tracker_slow_error.toml: 3″ per axis, a quarter of the 5680 s orbit).
#[test]
fn the_star_trackers_data_sheet_configures_its_heads_and_slow_error() {
    let mut sheets = realistic_sensors();
    sheets.gnss.position_noise_m = 10.0;
    sheets.gnss.correlated_error = None;
    sheets.gnss.velocity_noise_mps = None;
    sheets.gravity = GravityDatasheet::J2_ONLY;
    let mut two_heads = sheets;
    two_heads.star_tracker.cross_boresight_noise_arcsec = 5.0;
    two_heads.star_tracker.roll_noise_arcsec = 35.0;
    two_heads
        .star_tracker
        .second_head_mounting_rotation_vector_deg = Some([-90.0, 0.0, 0.0]);
    assert_same_flight("star_tracker_two_heads.toml", &two_heads);
    let mut slow = sheets;
    slow.star_tracker.low_frequency_error = Some(LowFrequencyError {
        sigma_arcsec: [3.0; 3],
        period_s: 5680.0,
    });
    assert_same_flight("star_tracker_slow_error.toml", &slow);
}

/// The data sheets of the vehicle as it is on the default flight (as_it_is.toml): the IMU of
/// upper_stage_imu_errors_estimated.toml (bias instability, 20 µrad misalignments, 0.5 °/h/g
/// g-sensitivity), a two-head tracker of 5″ across and 35″ in roll with a 3″ low-frequency
/// error over the 5680 s orbit that leaves the aberration in, a receiver of
/// realistic_sensors.toml's with 50 ms latency, and realistic_sensors.toml's gravity.
fn as_it_is() -> Datasheets {
    let mut sheets = realistic_sensors();
    let gyro = &mut sheets.imu.gyro;
    gyro.bias_instability = Some(GyroBiasInstability {
        // 1e-6 rad/s in °/h.
        sigma_deg_per_h: 0.206_264_806_247_096_34,
        correlation_time_s: 600.0,
    });
    gyro.misalignment_urad = Some(20.0);
    // 2.47e-7 rad/s per m/s² in °/h/g.
    gyro.g_sensitivity_deg_per_h_per_g = Some(0.499_623_390_259_222_5);
    let accel = &mut sheets.imu.accelerometer;
    accel.bias_instability = Some(AccelBiasInstability {
        // 2e-5 m/s² in µg.
        sigma_ug: 2.039_432_425_955_856_5,
        correlation_time_s: 600.0,
    });
    accel.misalignment_urad = Some(20.0);
    let star = &mut sheets.star_tracker;
    star.cross_boresight_noise_arcsec = 5.0;
    star.roll_noise_arcsec = 35.0;
    star.low_frequency_error = Some(LowFrequencyError {
        sigma_arcsec: [3.0; 3],
        period_s: 5680.0,
    });
    star.aberration_corrected = false;
    star.second_head_mounting_rotation_vector_deg = Some([-90.0, 0.0, 0.0]);
    sheets.gnss.latency_s = 0.05;
    sheets
}

#[test]
fn the_as_it_is_data_sheets_configure_nav_sims_flight() {
    assert_same_flight("as_it_is.toml", &as_it_is());
}

/// The same sensors on the upper stage (upper_stage_as_it_is.toml): its mountings, the
/// 5432 s parking orbit's low-frequency error and upper_stage.toml's gravity allowance.
#[test]
fn the_upper_stage_as_it_is_data_sheets_configure_nav_sims_flight() {
    let mut sheets = as_it_is();
    let star = &mut sheets.star_tracker;
    star.mounting_rotation_vector_deg = [-8.160548, -179.633363, 0.015173];
    star.second_head_mounting_rotation_vector_deg = Some([-5.459872, -124.51749, 124.538527]);
    star.low_frequency_error = Some(LowFrequencyError {
        sigma_arcsec: [3.0; 3],
        period_s: 5432.0,
    });
    sheets.gravity.omitted_field_sigma_mps2 = 3.2e-5;
    sheets.gravity.omitted_field_psd_m2_per_s3 = 1.3e-7;
    assert_same_flight("upper_stage_as_it_is.toml", &sheets);
}
