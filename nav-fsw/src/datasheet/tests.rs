//! The data sheets' conversions with real numbers, and the configuration they make.

use super::*;
use crate::config::{Param, GATE_NIS};
use crate::ConfigField;

fn site() -> LaunchSite {
    LaunchSite {
        latitude_rad: 0.715,
        longitude_rad: 1.750,
        height_m: 1000.0,
        azimuth_rad: 3.316,
        earth_axis_ecef: [0.0, 0.0, 1.0],
    }
}

fn close(actual: f64, expected: f64, relative: f64) -> bool {
    (actual - expected).abs() <= relative * expected.abs()
}

/// A navigation-grade IMU, a two-head star tracker with an orbit-periodic error, a receiver
/// with a correlated error and velocity, and the 12 × 12 field with realistic_sensors.toml's
/// allowance.
fn navigation_grade() -> Datasheets {
    Datasheets {
        imu: ImuDatasheet {
            output_rate_hz: 500.0,
            gyro: GyroDatasheet {
                angle_random_walk_deg_per_sqrt_h: 0.002,
                bias_stability_deg_per_h: 0.01,
                bias_instability: Some(GyroBiasInstability {
                    sigma_deg_per_h: 0.003,
                    correlation_time_s: 600.0,
                }),
                rate_random_walk_deg_per_h_per_sqrt_h: None,
                scale_factor_ppm: 5.0,
                misalignment_urad: Some(20.0),
                g_sensitivity_deg_per_h_per_g: Some(0.5),
                range_deg_per_s: Some(400.0),
            },
            accelerometer: AccelerometerDatasheet {
                velocity_random_walk_m_per_s_per_sqrt_h: 0.03,
                bias_stability_ug: 25.0,
                bias_instability: Some(AccelBiasInstability {
                    sigma_ug: 2.0,
                    correlation_time_s: 600.0,
                }),
                bias_random_walk_ug_per_sqrt_h: None,
                scale_factor_ppm: 100.0,
                misalignment_urad: Some(20.0),
                range_g: Some(20.0),
            },
        },
        star_tracker: StarTrackerDatasheet {
            cross_boresight_noise_arcsec: 5.0,
            roll_noise_arcsec: 35.0,
            low_frequency_error: Some(LowFrequencyError {
                sigma_arcsec: [3.0, 3.0, 6.0],
                period_s: 5680.0,
            }),
            aberration_corrected: true,
            mounting_accuracy_mrad: 1.0,
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
            latency_s: 0.05,
            antenna_lever_arm_m: [1.5, 0.0, -0.4],
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

/// ARW 0.002 °/√h is 0.12 (°/h)/√Hz = 5.818e-7 rad/√s; the paper's 0.2 (°/h)/√Hz as an ARW
/// (0.2/60 °/√h) gives nav-sim's density bit for bit; a rate random walk of 0.01 °/h/√h is
/// 8.08e-10 rad/s per √s.
#[test]
fn gyro_random_walks_convert_per_square_root_hour() {
    let gyro = navigation_grade().imu.gyro;
    let density = gyro.noise_density_rad_s_per_sqrt_hz();
    assert!(close(
        density,
        0.12 * core::f64::consts::PI / 180.0 / 3600.0,
        1e-15
    ));
    assert!(close(density, 5.817_764e-7, 1e-6), "{density}");
    let paper = GyroDatasheet {
        angle_random_walk_deg_per_sqrt_h: 0.2 / 60.0,
        ..gyro
    };
    assert_eq!(
        paper.noise_density_rad_s_per_sqrt_hz().to_bits(),
        deg_per_h_to_rad_per_s(0.2).to_bits()
    );
    assert_eq!(
        gyro.bias_walk_rad_s2_per_sqrt_hz().to_bits(),
        0.0f64.to_bits()
    );
    let walking = GyroDatasheet {
        rate_random_walk_deg_per_h_per_sqrt_h: Some(0.01),
        ..gyro
    };
    let walk = walking.bias_walk_rad_s2_per_sqrt_hz();
    assert!(close(walk, 8.080_8e-10, 1e-4), "{walk}");
}

/// VRW 0.03 m/s/√h is 5e-4 m/s²/√Hz (51 µg/√Hz); 25 µg is 2.4517e-4 m/s²; 0.5 °/h/g is
/// 2.4718e-7 rad/s per m/s² (the upper-stage scenario's 2.47e-7).
#[test]
fn accelerometer_figures_and_g_sensitivity_convert_with_the_standard_g() {
    let sheets = navigation_grade();
    let accel = sheets.imu.accelerometer;
    assert!(close(accel.noise_density_mps2_per_sqrt_hz(), 5.0e-4, 1e-15));
    let config = FswConfig::from_datasheets(&sheets, site(), SensorFrames::ALIGNED).unwrap();
    let prior = config.filter.initial.accel_bias_mps2;
    // 25 µg with the instability's 2σ² of 2 µg: √(25² + 8) µg.
    let expected = (625.0_f64 + 8.0).sqrt() * 9.80665e-6;
    assert!(close(prior, expected, 1e-15), "{prior}");
    let g_sensitivity = sheets.imu.gyro.g_sensitivity_rad_s_per_mps2();
    assert!(close(g_sensitivity, 2.4718e-7, 1e-4), "{g_sensitivity}");
    assert!(close(config.imu.max_specific_force_mps2, 196.133, 1e-15));
    assert!(close(config.imu.max_rate_rad_s, 6.981_317, 1e-7));
}

/// Off, the walk keeps its bits; on, the density is `√(walk² + 2σ²/τ)`, and its variance
/// growth bounds the Gauss–Markov bias's change over every interval.
#[test]
fn bias_instability_adds_its_driving_noise_to_the_walk() {
    for walk in [0.0, 3.0e-9, 1.0e-7] {
        assert_eq!(
            bias_walk_with_instability(walk, 0.0, 600.0).to_bits(),
            walk.to_bits()
        );
        assert_eq!(
            bias_walk_with_instability(walk, 1.0e-6, 0.0).to_bits(),
            walk.to_bits()
        );
    }
    let (sigma, tau_s) = (1.0e-6, 600.0);
    let density = bias_walk_with_instability(0.0, sigma, tau_s);
    assert!((density - (2.0 * 1.0e-12 / 600.0_f64).sqrt()).abs() < 1e-22);
    let combined = bias_walk_with_instability(3.0e-8, sigma, tau_s);
    assert!((combined * combined - (9.0e-16 + 2.0e-12 / 600.0)).abs() < 1e-28);
    for t_s in [1.0, 60.0, 600.0, 6000.0] {
        let gauss_markov_change = 2.0 * sigma * sigma * (1.0 - libm::exp(-t_s / tau_s));
        assert!(density * density * t_s >= gauss_markov_change, "{t_s}");
    }
}

/// The walk with the prior of [`bias_prior_with_instability`] bounds the Gauss–Markov bias:
/// over any set of times (here 60, from 0 to 5τ, bunched near 0 where the bound is
/// tightest) the filter's covariance of the bias minus the truth's (a constant of the
/// prior's 1σ plus the stationary Gauss–Markov bias) is positive semi-definite. A prior
/// holding only the stationary `σ²` is not a bound.
#[test]
fn the_walk_and_its_prior_bound_the_gauss_markov_bias_at_every_set_of_times() {
    let (constant_sigma, sigma, tau_s) = (1.0e-3, 2.0e-5, 600.0);
    let q = bias_walk_with_instability(0.0, sigma, tau_s).powi(2);
    const TIMES: usize = 60;
    let times: [f64; TIMES] =
        core::array::from_fn(|k| 5.0 * tau_s * (k as f64 / (TIMES - 1) as f64).powi(3));
    let smallest_eigenvalue = |prior_variance: f64| {
        let difference = nalgebra::SMatrix::<f64, TIMES, TIMES>::from_fn(|i, j| {
            let (s, t) = (times[i], times[j]);
            let filter = prior_variance + q * s.min(t);
            let truth =
                constant_sigma * constant_sigma + sigma * sigma * libm::exp(-(t - s).abs() / tau_s);
            (filter - truth) / (sigma * sigma)
        });
        difference.symmetric_eigenvalues().min()
    };
    let prior = bias_prior_with_instability(constant_sigma, sigma, tau_s).powi(2);
    assert!((prior - (1.0e-6 + 8.0e-10)).abs() < 1e-18);
    assert!(
        smallest_eigenvalue(prior) > -1e-6,
        "{}",
        smallest_eigenvalue(prior)
    );
    let stationary_only = constant_sigma * constant_sigma + sigma * sigma;
    assert!(smallest_eigenvalue(stationary_only) < -0.1);
    assert_eq!(
        bias_prior_with_instability(constant_sigma, 0.0, tau_s).to_bits(),
        constant_sigma.to_bits()
    );
}

/// The Gauss–Markov bias's Allan deviation peaks at 0.6174 σ at 1.893 τ (a larger value
/// than at 0.9 and 1.1 times that averaging time); a floor of 0.003 °/h at 1000 s is a bias
/// of 1σ 0.00486 °/h and τ 528 s.
#[test]
fn an_allan_floor_is_the_peak_of_the_gauss_markov_bias() {
    let allan_deviation = |t_over_tau: f64| {
        let x = t_over_tau;
        let variance = (2.0 * x - 3.0 + 4.0 * libm::exp(-x) - libm::exp(-2.0 * x)) / (x * x);
        variance.sqrt()
    };
    let peak = allan_deviation(ALLAN_PEAK_TAU_PER_CORRELATION_TIME);
    assert!((peak - ALLAN_PEAK_PER_SIGMA).abs() < 1e-6, "{peak}");
    for factor in [0.9, 1.1] {
        assert!(allan_deviation(factor * ALLAN_PEAK_TAU_PER_CORRELATION_TIME) < peak - 1e-4);
    }
    let (sigma, tau_s) = gauss_markov_from_allan_floor(0.003, 1000.0);
    assert!(close(sigma, 0.004_859_3, 1e-4), "{sigma}");
    assert!(close(tau_s, 528.32, 1e-4), "{tau_s}");
}

/// 5″ is 2.424e-5 rad; an orbit of 5680 s is a correlation time of 1420 s; the mounting
/// 30° about −y is `[cos 15°, 0, −sin 15°, 0]`; the second head's prior is √2 times the
/// installation's, itself √(1 mrad² + 2 (6″)²).
#[test]
fn the_star_trackers_figures_convert_to_radians_and_its_heads_to_quaternions() {
    assert!(close(arcsec_to_rad(5.0), 2.424_068_4e-5, 1e-7));
    let sheets = navigation_grade();
    let lfe = sheets.star_tracker.low_frequency_error.unwrap();
    assert_eq!(lfe.correlation_time_s().to_bits(), 1420.0f64.to_bits());
    let [w, x, y, z] = mounting_wxyz_from_rotation_vector_deg([0.0, -30.0, 0.0]);
    assert!(close(w, 0.965_925_826, 1e-9) && close(y, -0.258_819_045, 1e-9));
    assert_eq!([x.to_bits(), z.to_bits()], [0.0f64.to_bits(); 2]);
    let config = FswConfig::from_datasheets(&sheets, site(), SensorFrames::ALIGNED).unwrap();
    let star = config.star;
    assert!(close(star.roll_noise_rad, 7.0 * star.noise_rad, 1e-15));
    assert!(close(
        star.slow_error_sigma_rad[2],
        arcsec_to_rad(6.0),
        1e-15
    ));
    let installation = config.filter.initial.star_installation_rad;
    let six_arcsec = arcsec_to_rad(6.0);
    assert!(close(
        installation,
        (1.0e-6 + 2.0 * six_arcsec * six_arcsec).sqrt(),
        1e-15
    ));
    let head = star.second_head.unwrap();
    assert!(close(
        head.alignment_prior_sigma_rad,
        2.0f64.sqrt() * installation,
        1e-15
    ));
    assert_eq!(head.pairs_before_hand_over, 100);
    assert_eq!(head.pair_gate_nis.to_bits(), GATE_NIS.to_bits());
    assert!(
        !star.aberration_correction,
        "the tracker corrects it itself"
    );
}

/// The data sheets turn on every optional block they call for; without the optional
/// figures every block is off and the gravity is `J2` alone.
#[test]
fn the_data_sheets_turn_on_the_blocks_they_call_for() {
    let sheets = navigation_grade();
    let config = FswConfig::from_datasheets(&sheets, site(), SensorFrames::ALIGNED).unwrap();
    assert!(config.filter.imu_error.is_enabled());
    assert!(config.filter.gnss_error.is_enabled());
    assert!(config.star.has_slow_error() && config.star.second_head.is_some());
    assert_eq!(config.gravity.field.degree, 12);
    assert_eq!(
        config.gnss.lever_arm_body_m.map(f64::to_bits),
        [1.5, 0.0, -0.4].map(f64::to_bits)
    );
    // The 50 ms latency fits the 0.1 s default window; 110 ms widens it by one frame.
    assert_eq!(config.timing.max_latency_s.to_bits(), 0.1f64.to_bits());
    assert!(close(latency_window_s(0.1, 0.11, 0.002), 0.112, 1e-15));
    let mut bare = sheets;
    bare.imu.gyro.misalignment_urad = None;
    bare.imu.accelerometer.misalignment_urad = None;
    bare.imu.gyro.g_sensitivity_deg_per_h_per_g = None;
    bare.gnss.correlated_error = None;
    bare.gnss.velocity_noise_mps = None;
    bare.star_tracker.low_frequency_error = None;
    bare.star_tracker.second_head_mounting_rotation_vector_deg = None;
    bare.star_tracker.aberration_corrected = false;
    bare.gravity = GravityDatasheet::J2_ONLY;
    let config = FswConfig::from_datasheets(&bare, site(), SensorFrames::ALIGNED).unwrap();
    assert!(!config.filter.imu_error.is_enabled());
    assert!(!config.filter.gnss_error.is_enabled());
    assert!(!config.star.has_slow_error() && config.star.second_head.is_none());
    assert!(
        config.star.aberration_correction,
        "the flight software corrects it"
    );
    assert_eq!(config.gnss.velocity_noise_mps.to_bits(), 0.0f64.to_bits());
    assert_eq!(config.gravity, crate::config::GravityConfig::J2_ONLY);
}

/// A gyro misalignment without the accelerometer's is refused (the IMU error states need
/// all three 1σ), naming the data-sheet field to fill; a zero star noise names its field.
#[test]
fn a_refusal_names_the_data_sheet_field() {
    let mut sheets = navigation_grade();
    sheets.imu.accelerometer.misalignment_urad = None;
    let error = FswConfig::from_datasheets(&sheets, site(), SensorFrames::ALIGNED).unwrap_err();
    let FswError::InvalidConfiguration(field) = error else {
        panic!("{error}");
    };
    assert_eq!(
        field,
        ConfigField::Companion(Param::GyroMisalignmentSigma, Param::AccelMisalignmentSigma)
    );
    assert_eq!(
        Datasheets::field_of(field),
        Some("imu.accelerometer.misalignment_urad")
    );
    let mut sheets = navigation_grade();
    sheets.star_tracker.cross_boresight_noise_arcsec = 0.0;
    let error = FswConfig::from_datasheets(&sheets, site(), SensorFrames::ALIGNED).unwrap_err();
    let FswError::InvalidConfiguration(field) = error else {
        panic!("{error}");
    };
    assert_eq!(
        Datasheets::field_of(field),
        Some("star_tracker.cross_boresight_noise_arcsec")
    );
    assert_eq!(Datasheets::field_of(ConfigField::LaunchSite), None);
}

/// Every parameter the data sheets set has a data-sheet field, and every such field names a
/// table of [`Datasheets`].
#[test]
fn every_parameter_the_data_sheets_set_names_its_field() {
    let sheets = navigation_grade();
    let defaults = FswConfig::paper_defaults(site(), SensorFrames::ALIGNED);
    let config = FswConfig::from_datasheets(&sheets, site(), SensorFrames::ALIGNED).unwrap();
    let tables = ["imu.", "star_tracker.", "gnss.", "gravity.", "hand_over."];
    for &param in Param::ALL {
        let differs = param.value(&config).to_bits() != param.value(&defaults).to_bits();
        let field = Datasheets::field_of(ConfigField::Parameter(param));
        if differs {
            assert!(field.is_some(), "{}", param.path());
        }
        if let Some(field) = field {
            assert!(tables.iter().any(|t| field.starts_with(t)), "{field}");
        }
    }
}

/// realistic_sensors.toml's allowance: the default flight's check figure 1.87e-5 m/s²
/// rounded up to 1.9e-5, and the density 5.24e-8 m²/s³ printed for it scaled by
/// (1.9/1.87)² to 5.41e-8, rounded up to the 5.5e-8 its data sheet gives.
#[test]
fn the_gravity_allowance_scales_with_the_omitted_fields_power() {
    let psd = GravityDatasheet::omitted_field_psd_for_sigma(5.24e-8, 1.87e-5, 1.9e-5);
    assert!(close(psd, 5.409_477e-8, 1e-6), "{psd}");
    assert!(psd < navigation_grade().gravity.omitted_field_psd_m2_per_s3);
}
