//! The data sheets of the vehicle this example flies, copied into nav-fsw's tables in the
//! units each data sheet prints (docs/guide/flight-software.md, "Configuring it from the data
//! sheets"). The vehicle as it is: a navigation-grade IMU with its misalignments,
//! g-sensitivity and bias instability (the values nav-sim's IMU-error scenarios fly), a
//! two-head star tracker noisier in roll than across its boresight with an orbit-periodic
//! low-frequency error, a receiver with a correlated error and velocity, and the flight's
//! 12 × 12 field with the allowance nav-sim/scenarios/realistic_sensors.toml derives for
//! the default flight's lowest altitude. A flight image carries its own sensors' sheets.

use nav_fsw::datasheet::{
    AccelBiasInstability, AccelerometerDatasheet, Datasheets, GnssCorrelatedError, GnssDatasheet,
    GravityDatasheet, GyroBiasInstability, GyroDatasheet, HandOverDatasheet, ImuDatasheet,
    LowFrequencyError, StarTrackerDatasheet,
};

/// Every data sheet of the vehicle.
pub const DATASHEETS: Datasheets = Datasheets {
    imu: ImuDatasheet {
        output_rate_hz: 500.0,
        gyro: GyroDatasheet {
            angle_random_walk_deg_per_sqrt_h: 0.0033,
            bias_stability_deg_per_h: 200.0,
            bias_instability: Some(GyroBiasInstability {
                sigma_deg_per_h: 0.2,
                correlation_time_s: 600.0,
            }),
            rate_random_walk_deg_per_h_per_sqrt_h: None,
            scale_factor_ppm: 100.0,
            misalignment_urad: Some(20.0),
            g_sensitivity_deg_per_h_per_g: Some(0.5),
            range_deg_per_s: Some(400.0),
        },
        accelerometer: AccelerometerDatasheet {
            velocity_random_walk_m_per_s_per_sqrt_h: 2.7e-4,
            bias_stability_ug: 1000.0,
            bias_instability: Some(AccelBiasInstability {
                sigma_ug: 2.0,
                correlation_time_s: 600.0,
            }),
            bias_random_walk_ug_per_sqrt_h: None,
            scale_factor_ppm: 200.0,
            misalignment_urad: Some(20.0),
            range_g: Some(20.0),
        },
    },
    star_tracker: StarTrackerDatasheet {
        cross_boresight_noise_arcsec: 5.0,
        roll_noise_arcsec: 35.0,
        low_frequency_error: Some(LowFrequencyError {
            sigma_arcsec: [3.0, 3.0, 3.0],
            period_s: 5680.0,
        }),
        aberration_corrected: true,
        mounting_accuracy_mrad: 10.0,
        mounting_rotation_vector_deg: [0.0, -30.0, 0.0],
        second_head_mounting_rotation_vector_deg: Some([-90.0, 0.0, 0.0]),
    },
    gnss: GnssDatasheet {
        position_noise_m: 6.0,
        correlated_error: Some(GnssCorrelatedError {
            sigma_m: 8.0,
            correlation_time_s: 300.0,
        }),
        velocity_noise_mps: Some(0.05),
        latency_s: 0.0,
        antenna_lever_arm_m: [0.0, 0.0, 0.0],
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
};
