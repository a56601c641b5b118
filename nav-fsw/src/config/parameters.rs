//! The parameter table: one declaration per flight parameter with its path in
//! [`FswConfig`], unit, default, accepted range and the reason for it, and its replay-setup
//! word. [`FswConfig::paper_defaults`], [`FswConfig::validate`], the replay setup's words, the
//! configuration errors ([`crate::ConfigField::Parameter`]), nav-sim's `[filter]` checks and
//! docs/reference/flight-parameters.md all come from it. Adding a parameter is one
//! declaration here (and a replay word if a scenario sets it).
//!
//! Ranges are physical (what a sensor, a vehicle or an orbit can be) or follow the frame
//! budget (docs/guide/performance.md); every 1σ range keeps its square a normal `f64`.

use core::f64::consts::{FRAC_PI_2, PI};

use nav_core::filter::FilterMode;

use super::gravity::ranges as gravity;
use super::range::{ParamValue, Range};
use super::shared_ranges::*;
use super::table::flight_parameters;
use super::{FrameLoad, FswConfig, SecondOrderAttitude, ARCSEC_TO_RAD, GATE_NIS};
use super::{ACQUISITION_GATE_NIS, MAX_PROPAGATION_INTERVAL_FRAMES};
use crate::calibration_manager::{CalibrationThresholds as Thresholds, EstimationPolicy};
use crate::consistency::{DEFAULT_MEAN_NIS_BOUND, MAX_TIME_CONSTANT_MEASUREMENTS};
use crate::error::{ConfigField, FswError};

flight_parameters! {
    FilterMode: FilterMode {
        path: "filter.mode", unit: "", default: Some(FilterMode::ClosedLoop), word: Some(1),
        range: Range::choice(&["open_loop", "closed_loop"]), why: "the two filter modes",
        get: |c| c.filter.mode, set: |c, v| c.filter.mode = v,
    }
    FilterDiscretisationOrder: u8 {
        path: "filter.discretisation_order", unit: "", default: Some(3), word: Some(2),
        range: Range::new(1.0, 4.0),
        why: "nav-core's truncated transition series: 1 is Euler, 4 the longest it has",
        get: |c| c.filter.discretisation_order, set: |c, v| c.filter.discretisation_order = v,
    }
    LaunchEpochGpsWeek: u32 {
        path: "sensor_frames.launch_epoch_gps_week", unit: "week", default: None, word: Some(3),
        range: Range::new(0.0, 9999.0), why: "a four-digit GPS week (until 2171)",
        get: |c| c.sensor_frames.launch_epoch_gps_week,
        set: |c, v| c.sensor_frames.launch_epoch_gps_week = v,
    }
    GravityDegree: u8 {
        path: "gravity.field.degree", unit: "", default: Some(2), word: Some(4),
        range: gravity::DEGREE, why: gravity::DEGREE_WHY,
        get: |c| c.gravity.field.degree, set: |c, v| c.gravity.field.degree = v,
    }
    GravityOrder: u8 {
        path: "gravity.field.order", unit: "", default: Some(0), word: Some(5),
        range: gravity::ORDER, why: gravity::ORDER_WHY,
        get: |c| c.gravity.field.order, set: |c, v| c.gravity.field.order = v,
    }
    GravityTermsPerFrame: u8 {
        path: "gravity.field.terms_per_frame", unit: "",
        default: Some(nav_core::gravity::harmonics::DEFAULT_TERMS_PER_FRAME), word: Some(6),
        range: Range::new(1.0, 8.0),
        why: "the frame budget: each work item adds up to one coefficient's work to a frame \
              that fuses nothing (docs/guide/gravity.md, its cost table); twice the default keeps \
              that frame inside 30,000 instructions with every state block, 255 would not",
        get: |c| c.gravity.field.terms_per_frame, set: |c, v| c.gravity.field.terms_per_frame = v,
    }
    LaunchLatitude: f64 {
        path: "launch_site.latitude_rad", unit: "rad", default: None, word: Some(7),
        range: Range::new(-FRAC_PI_2, FRAC_PI_2), why: "a geodetic latitude",
        get: |c| c.launch_site.latitude_rad, set: |c, v| c.launch_site.latitude_rad = v,
    }
    LaunchLongitude: f64 {
        path: "launch_site.longitude_rad", unit: "rad", default: None, word: Some(8),
        range: Range::new(-2.0 * PI, 2.0 * PI), why: "a longitude, one turn either way",
        get: |c| c.launch_site.longitude_rad, set: |c, v| c.launch_site.longitude_rad = v,
    }
    LaunchHeight: f64 {
        path: "launch_site.height_m", unit: "m", default: None, word: Some(9),
        range: Range::new(nav_core::frames::SITE_HEIGHT_RANGE_M.0, nav_core::frames::SITE_HEIGHT_RANGE_M.1),
        why: "above the ellipsoid: below the lowest land to above any launch site",
        get: |c| c.launch_site.height_m, set: |c, v| c.launch_site.height_m = v,
    }
    LaunchAzimuth: f64 {
        path: "launch_site.azimuth_rad", unit: "rad", default: None, word: Some(10),
        range: Range::new(-2.0 * PI, 2.0 * PI), why: "an azimuth, one turn either way",
        get: |c| c.launch_site.azimuth_rad, set: |c, v| c.launch_site.azimuth_rad = v,
    }
    EarthAxisX: f64 {
        path: "launch_site.earth_axis_ecef[0]", unit: "", default: None, word: Some(11),
        range: UNIT,
        why: "a component of the unit Earth axis (within 1e-4 rad of ECEF z, checked with the whole axis)",
        get: |c| c.launch_site.earth_axis_ecef[0], set: |c, v| c.launch_site.earth_axis_ecef[0] = v,
    }
    EarthAxisY: f64 {
        path: "launch_site.earth_axis_ecef[1]", unit: "", default: None, word: Some(12),
        range: UNIT, why: "as earth_axis_ecef[0]",
        get: |c| c.launch_site.earth_axis_ecef[1], set: |c, v| c.launch_site.earth_axis_ecef[1] = v,
    }
    EarthAxisZ: f64 {
        path: "launch_site.earth_axis_ecef[2]", unit: "", default: None, word: Some(13),
        range: UNIT, why: "as earth_axis_ecef[0]",
        get: |c| c.launch_site.earth_axis_ecef[2], set: |c, v| c.launch_site.earth_axis_ecef[2] = v,
    }
    GcrfW: f64 {
        path: "sensor_frames.gcrf_to_launch_inertial_wxyz[0]", unit: "",
        default: None, word: Some(14),
        range: UNIT, why: UNIT_WHY,
        get: |c| c.sensor_frames.gcrf_to_launch_inertial_wxyz[0],
        set: |c, v| c.sensor_frames.gcrf_to_launch_inertial_wxyz[0] = v,
    }
    GcrfX: f64 {
        path: "sensor_frames.gcrf_to_launch_inertial_wxyz[1]", unit: "",
        default: None, word: Some(15),
        range: UNIT, why: UNIT_WHY,
        get: |c| c.sensor_frames.gcrf_to_launch_inertial_wxyz[1],
        set: |c, v| c.sensor_frames.gcrf_to_launch_inertial_wxyz[1] = v,
    }
    GcrfY: f64 {
        path: "sensor_frames.gcrf_to_launch_inertial_wxyz[2]", unit: "",
        default: None, word: Some(16),
        range: UNIT, why: UNIT_WHY,
        get: |c| c.sensor_frames.gcrf_to_launch_inertial_wxyz[2],
        set: |c, v| c.sensor_frames.gcrf_to_launch_inertial_wxyz[2] = v,
    }
    GcrfZ: f64 {
        path: "sensor_frames.gcrf_to_launch_inertial_wxyz[3]", unit: "",
        default: None, word: Some(17),
        range: UNIT, why: UNIT_WHY,
        get: |c| c.sensor_frames.gcrf_to_launch_inertial_wxyz[3],
        set: |c, v| c.sensor_frames.gcrf_to_launch_inertial_wxyz[3] = v,
    }
    LaunchEpochSecondsOfWeek: f64 {
        path: "sensor_frames.launch_epoch_gps_seconds_of_week", unit: "s",
        default: None, word: Some(18),
        range: Range::new(0.0, 604_800.0),
        why: "within one GPS week (604800 itself is the next week's 0, checked with the frames)",
        get: |c| c.sensor_frames.launch_epoch_gps_seconds_of_week,
        set: |c, v| c.sensor_frames.launch_epoch_gps_seconds_of_week = v,
    }
    InitialAttitude: f64 {
        path: "filter.initial.attitude_rad", unit: "rad", default: Some(1e-3), word: Some(30),
        range: ATTITUDE_SIGMA, why: ATTITUDE_WHY,
        get: |c| c.filter.initial.attitude_rad, set: |c, v| c.filter.initial.attitude_rad = v,
    }
    InitialPosition: f64 {
        path: "filter.initial.position_m", unit: "m", default: Some(10.0), word: Some(31),
        range: Range::new(1.0e-3, 1.0e7),
        why: "a millimetre is below any position fix; 1e7 m is the size of the Earth",
        get: |c| c.filter.initial.position_m, set: |c, v| c.filter.initial.position_m = v,
    }
    InitialVelocity: f64 {
        path: "filter.initial.velocity_mps", unit: "m/s", default: Some(0.1), word: Some(32),
        range: Range::new(1.0e-6, 1.0e4),
        why: "a micrometre per second is below any velocity fix; 1e4 m/s exceeds orbital speed",
        get: |c| c.filter.initial.velocity_mps, set: |c, v| c.filter.initial.velocity_mps = v,
    }
    InitialGyroBias: f64 {
        path: "filter.initial.gyro_bias_rad_s", unit: "rad/s", default: Some(1e-3), word: Some(33),
        range: GYRO_BIAS_SIGMA, why: GYRO_BIAS_WHY,
        get: |c| c.filter.initial.gyro_bias_rad_s, set: |c, v| c.filter.initial.gyro_bias_rad_s = v,
    }
    InitialAccelBias: f64 {
        path: "filter.initial.accel_bias_mps2", unit: "m/s^2", default: Some(1e-2), word: Some(34),
        range: ACCEL_BIAS_SIGMA, why: ACCEL_BIAS_WHY,
        get: |c| c.filter.initial.accel_bias_mps2, set: |c, v| c.filter.initial.accel_bias_mps2 = v,
    }
    InitialStarInstallation: f64 {
        path: "filter.initial.star_installation_rad", unit: "rad",
        default: Some(1e-2), word: Some(35),
        range: INSTALLATION_SIGMA, why: INSTALLATION_WHY,
        get: |c| c.filter.initial.star_installation_rad,
        set: |c, v| c.filter.initial.star_installation_rad = v,
    }
    InitialGyroScaleFactor: f64 {
        path: "filter.initial.gyro_scale_factor", unit: "", default: Some(1e-4), word: Some(36),
        range: SCALE_SIGMA, why: SCALE_WHY,
        get: |c| c.filter.initial.gyro_scale_factor,
        set: |c, v| c.filter.initial.gyro_scale_factor = v,
    }
    InitialAccelScaleFactor: f64 {
        path: "filter.initial.accel_scale_factor", unit: "", default: Some(2e-4), word: Some(37),
        range: SCALE_SIGMA, why: SCALE_WHY,
        get: |c| c.filter.initial.accel_scale_factor,
        set: |c, v| c.filter.initial.accel_scale_factor = v,
    }
    GyroNoiseDensity: f64 {
        path: "process_noise.gyro_noise_density_rad_s_per_sqrt_hz", unit: "rad/s/sqrt(Hz)",
        default: Some(nav_core::error_model::ProcessNoise::PAPER.gyro_noise_density_rad_s_per_sqrt_hz), word: Some(38),
        range: Range::new(1.0e-12, 1.0e-1).or_off(), why: GYRO_NOISE_WHY,
        get: |c| c.process_noise.gyro_noise_density_rad_s_per_sqrt_hz,
        set: |c, v| c.process_noise.gyro_noise_density_rad_s_per_sqrt_hz = v,
    }
    AccelNoiseDensity: f64 {
        path: "process_noise.accel_noise_density_mps2_per_sqrt_hz", unit: "m/s^2/sqrt(Hz)",
        default: Some(nav_core::error_model::ProcessNoise::PAPER.accel_noise_density_mps2_per_sqrt_hz), word: Some(39),
        range: Range::new(1.0e-12, 10.0).or_off(), why: ACCEL_NOISE_WHY,
        get: |c| c.process_noise.accel_noise_density_mps2_per_sqrt_hz,
        set: |c, v| c.process_noise.accel_noise_density_mps2_per_sqrt_hz = v,
    }
    GyroBiasWalk: f64 {
        path: "process_noise.gyro_bias_walk_rad_s2_per_sqrt_hz", unit: "rad/s^2/sqrt(Hz)",
        default: Some(nav_core::error_model::ProcessNoise::PAPER.gyro_bias_walk_rad_s2_per_sqrt_hz), word: Some(40),
        range: Range::new(1.0e-18, 1.0).or_off(), why: WALK_WHY,
        get: |c| c.process_noise.gyro_bias_walk_rad_s2_per_sqrt_hz,
        set: |c, v| c.process_noise.gyro_bias_walk_rad_s2_per_sqrt_hz = v,
    }
    AccelBiasWalk: f64 {
        path: "process_noise.accel_bias_walk_mps3_per_sqrt_hz", unit: "m/s^3/sqrt(Hz)",
        default: Some(nav_core::error_model::ProcessNoise::PAPER.accel_bias_walk_mps3_per_sqrt_hz), word: Some(41),
        range: Range::new(1.0e-15, 100.0).or_off(), why: WALK_WHY,
        get: |c| c.process_noise.accel_bias_walk_mps3_per_sqrt_hz,
        set: |c, v| c.process_noise.accel_bias_walk_mps3_per_sqrt_hz = v,
    }
    ImuPeriod: f64 {
        path: "imu.period_s", unit: "s", default: Some(crate::MINOR_FRAME_PERIOD_S), word: Some(42),
        range: Range::new(1.0e-4, 0.1),
        why: "10 kHz to 10 Hz: the two-sample coning and sculling terms need many samples per \
              manoeuvre, and a faster frame leaves no room in the budget",
        get: |c| c.imu.period_s, set: |c, v| c.imu.period_s = v,
    }
    StarMountingW: f64 {
        path: "star.mounting_wxyz[0]", unit: "", default: Some(1.0), word: Some(43),
        range: UNIT, why: UNIT_WHY,
        get: |c| c.star.mounting_wxyz[0], set: |c, v| c.star.mounting_wxyz[0] = v,
    }
    StarMountingX: f64 {
        path: "star.mounting_wxyz[1]", unit: "", default: Some(0.0), word: Some(44),
        range: UNIT, why: UNIT_WHY,
        get: |c| c.star.mounting_wxyz[1], set: |c, v| c.star.mounting_wxyz[1] = v,
    }
    StarMountingY: f64 {
        path: "star.mounting_wxyz[2]", unit: "", default: Some(0.0), word: Some(45),
        range: UNIT, why: UNIT_WHY,
        get: |c| c.star.mounting_wxyz[2], set: |c, v| c.star.mounting_wxyz[2] = v,
    }
    StarMountingZ: f64 {
        path: "star.mounting_wxyz[3]", unit: "", default: Some(0.0), word: Some(46),
        range: UNIT, why: UNIT_WHY,
        get: |c| c.star.mounting_wxyz[3], set: |c, v| c.star.mounting_wxyz[3] = v,
    }
    StarNoise: f64 {
        path: "star.noise_rad", unit: "rad", default: Some(10.0 * ARCSEC_TO_RAD), word: Some(47),
        range: STAR_NOISE, why: STAR_NOISE_WHY,
        get: |c| c.star.noise_rad, set: |c, v| c.star.noise_rad = v,
    }
    StarGate: f64 {
        path: "star.gate_nis", unit: "", default: Some(GATE_NIS), word: Some(48),
        range: GATE, why: GATE_WHY,
        get: |c| c.star.gate_nis, set: |c, v| c.star.gate_nis = v,
    }
    GnssNoise: f64 {
        path: "gnss.noise_m", unit: "m", default: Some(10.0), word: Some(49),
        range: Range::new(1.0e-6, 1.0e5),
        why: "1e-6 m is the floor nav-sim gives a noiseless test receiver; 1e5 m is no fix",
        get: |c| c.gnss.noise_m, set: |c, v| c.gnss.noise_m = v,
    }
    GnssGate: f64 {
        path: "gnss.gate_nis", unit: "", default: Some(GATE_NIS), word: Some(50),
        range: GATE, why: GATE_WHY,
        get: |c| c.gnss.gate_nis, set: |c, v| c.gnss.gate_nis = v,
    }
    MaxLatency: f64 {
        path: "timing.max_latency_s", unit: "s", default: Some(0.1), word: Some(51),
        range: Range::new(0.0, 1.0),
        why: "at most the navigation history's span, (HISTORY_CAPACITY - 1) IMU periods \
              (checked with imu.period_s)",
        get: |c| c.timing.max_latency_s, set: |c, v| c.timing.max_latency_s = v,
    }
    GnssCorrelatedSigma: f64 {
        path: "filter.gnss_error.sigma_m", unit: "m", default: Some(0.0), word: Some(52),
        range: Range::new(1.0e-3, 1.0e3).or_off(),
        why: "a receiver's slowly varying error: ionosphere and orbit errors are metres, 1 km is \
              no fix",
        get: |c| c.filter.gnss_error.sigma_m, set: |c, v| c.filter.gnss_error.sigma_m = v,
    }
    GnssCorrelationTime: f64 {
        path: "filter.gnss_error.correlation_time_s", unit: "s", default: Some(0.0), word: Some(53),
        range: CORRELATION_TIME_RANGE_S, why: CORRELATION_TIME_WHY,
        get: |c| c.filter.gnss_error.correlation_time_s,
        set: |c, v| c.filter.gnss_error.correlation_time_s = v,
    }
    GnssVelocityNoise: f64 {
        path: "gnss.velocity_noise_mps", unit: "m/s", default: Some(0.05), word: Some(54),
        range: Range::new(1.0e-6, 1.0e3).or_off(),
        why: "0 turns velocity fusion off; a receiver's velocity is centimetres per second, \
              1 km/s is none",
        get: |c| c.gnss.velocity_noise_mps, set: |c, v| c.gnss.velocity_noise_mps = v,
    }
    ImuMaxRate: f64 {
        path: "imu.max_rate_rad_s", unit: "rad/s", default: Some(7.0), word: Some(55),
        range: Range::new(1.0e-2, 1.0e3),
        why: "a gyro's measurement span: 0.6 deg/s to 57,000 deg/s",
        get: |c| c.imu.max_rate_rad_s, set: |c, v| c.imu.max_rate_rad_s = v,
    }
    ImuMaxSpecificForce: f64 {
        path: "imu.max_specific_force_mps2", unit: "m/s^2", default: Some(200.0), word: Some(56),
        range: Range::new(1.0, 1.0e5),
        why: "an accelerometer's measurement span: 0.1 g to 10,000 g",
        get: |c| c.imu.max_specific_force_mps2, set: |c, v| c.imu.max_specific_force_mps2 = v,
    }
    GyroMisalignmentSigma: f64 {
        path: "filter.imu_error.gyro_misalignment_sigma_rad", unit: "rad",
        default: Some(0.0), word: Some(57),
        range: MISALIGNMENT_SIGMA, why: MISALIGNMENT_WHY,
        get: |c| c.filter.imu_error.gyro_misalignment_sigma_rad,
        set: |c, v| c.filter.imu_error.gyro_misalignment_sigma_rad = v,
    }
    AccelMisalignmentSigma: f64 {
        path: "filter.imu_error.accel_misalignment_sigma_rad", unit: "rad",
        default: Some(0.0), word: Some(58),
        range: MISALIGNMENT_SIGMA, why: MISALIGNMENT_WHY,
        get: |c| c.filter.imu_error.accel_misalignment_sigma_rad,
        set: |c, v| c.filter.imu_error.accel_misalignment_sigma_rad = v,
    }
    GyroGSensitivitySigma: f64 {
        path: "filter.imu_error.gyro_g_sensitivity_sigma_rad_s_per_mps2", unit: "rad/s per m/s^2",
        default: Some(0.0), word: Some(59),
        range: Range::new(1.0e-12, 1.0e-3).or_off(),
        why: "navigation-grade gyros have 0.1-10 deg/h/g; 1e-3 is 2000 deg/h/g",
        get: |c| c.filter.imu_error.gyro_g_sensitivity_sigma_rad_s_per_mps2,
        set: |c, v| c.filter.imu_error.gyro_g_sensitivity_sigma_rad_s_per_mps2 = v,
    }
    OmittedFieldSigma: f64 {
        path: "gravity.omitted_field_sigma_mps2", unit: "m/s^2", default: Some(0.0), word: Some(60),
        range: gravity::OMITTED_SIGMA, why: gravity::OMITTED_SIGMA_WHY,
        get: |c| c.gravity.omitted_field_sigma_mps2,
        set: |c, v| c.gravity.omitted_field_sigma_mps2 = v,
    }
    OmittedFieldPsd: f64 {
        path: "gravity.omitted_field_psd_m2_per_s3", unit: "m^2/s^3",
        default: Some(0.0), word: Some(61),
        range: gravity::OMITTED_PSD, why: gravity::OMITTED_PSD_WHY,
        get: |c| c.gravity.omitted_field_psd_m2_per_s3,
        set: |c, v| c.gravity.omitted_field_psd_m2_per_s3 = v,
    }
    StarRollNoise: f64 {
        path: "star.roll_noise_rad", unit: "rad",
        default: Some(10.0 * ARCSEC_TO_RAD), word: Some(62),
        range: STAR_NOISE, why: STAR_NOISE_WHY,
        get: |c| c.star.roll_noise_rad, set: |c, v| c.star.roll_noise_rad = v,
    }
    StarSlowErrorX: f64 {
        path: "star.slow_error_sigma_rad[0]", unit: "rad", default: Some(0.0), word: Some(63),
        range: SLOW_ERROR_SIGMA, why: SLOW_ERROR_WHY,
        get: |c| c.star.slow_error_sigma_rad[0], set: |c, v| c.star.slow_error_sigma_rad[0] = v,
    }
    StarSlowErrorY: f64 {
        path: "star.slow_error_sigma_rad[1]", unit: "rad", default: Some(0.0), word: Some(64),
        range: SLOW_ERROR_SIGMA, why: SLOW_ERROR_WHY,
        get: |c| c.star.slow_error_sigma_rad[1], set: |c, v| c.star.slow_error_sigma_rad[1] = v,
    }
    StarSlowErrorZ: f64 {
        path: "star.slow_error_sigma_rad[2]", unit: "rad", default: Some(0.0), word: Some(65),
        range: SLOW_ERROR_SIGMA, why: SLOW_ERROR_WHY,
        get: |c| c.star.slow_error_sigma_rad[2], set: |c, v| c.star.slow_error_sigma_rad[2] = v,
    }
    StarSlowErrorCorrelationTime: f64 {
        path: "star.slow_error_correlation_time_s", unit: "s", default: Some(0.0), word: Some(66),
        range: CORRELATION_TIME_RANGE_S, why: CORRELATION_TIME_WHY,
        get: |c| c.star.slow_error_correlation_time_s,
        set: |c, v| c.star.slow_error_correlation_time_s = v,
    }
    StarAberrationCorrection: bool {
        path: "star.aberration_correction", unit: "", default: Some(false), word: Some(67),
        range: Range::FLAG, why: "on or off",
        get: |c| c.star.aberration_correction, set: |c, v| c.star.aberration_correction = v,
    }
    StarNoiseMatching: bool {
        path: "star.noise_matching", unit: "", default: Some(true), word: Some(68),
        range: Range::FLAG, why: "on or off",
        get: |c| c.star.noise_matching, set: |c, v| c.star.noise_matching = v,
    }
    StarSecondHead: bool {
        path: "star.second_head", unit: "", default: Some(false), word: Some(69),
        range: Range::FLAG, why: "one tracker head or two; the head's values follow",
        get: |c| c.star.second_head.is_some(),
        set: |c, v| c.star.second_head = v.then_some(super::StarHeadConfig::ZERO),
    }
    HeadPairsBeforeHandOver: u32 {
        path: "star.second_head.pairs_before_hand_over", unit: "pairs",
        default: None, word: Some(70),
        range: Range::new(1.0, 1.0e5),
        why: "at 0 the filter hands over to a head whose alignment no pair has measured; \
              1e5 pairs (hours at 10 Hz) is never",
        get: |c| c.star.second_head.map_or(0, |h| h.pairs_before_hand_over),
        set: |c, v| if let Some(h) = c.star.second_head.as_mut() { h.pairs_before_hand_over = v },
        when: StarSecondHead,
    }
    HeadMountingW: f64 {
        path: "star.second_head.mounting_wxyz[0]", unit: "", default: None, word: Some(71),
        range: UNIT, why: UNIT_WHY,
        get: |c| c.star.second_head.map_or(0.0, |h| h.mounting_wxyz[0]),
        set: |c, v| if let Some(h) = c.star.second_head.as_mut() { h.mounting_wxyz[0] = v },
        when: StarSecondHead,
    }
    HeadMountingX: f64 {
        path: "star.second_head.mounting_wxyz[1]", unit: "", default: None, word: Some(72),
        range: UNIT, why: UNIT_WHY,
        get: |c| c.star.second_head.map_or(0.0, |h| h.mounting_wxyz[1]),
        set: |c, v| if let Some(h) = c.star.second_head.as_mut() { h.mounting_wxyz[1] = v },
        when: StarSecondHead,
    }
    HeadMountingY: f64 {
        path: "star.second_head.mounting_wxyz[2]", unit: "", default: None, word: Some(73),
        range: UNIT, why: UNIT_WHY,
        get: |c| c.star.second_head.map_or(0.0, |h| h.mounting_wxyz[2]),
        set: |c, v| if let Some(h) = c.star.second_head.as_mut() { h.mounting_wxyz[2] = v },
        when: StarSecondHead,
    }
    HeadMountingZ: f64 {
        path: "star.second_head.mounting_wxyz[3]", unit: "", default: None, word: Some(74),
        range: UNIT, why: UNIT_WHY,
        get: |c| c.star.second_head.map_or(0.0, |h| h.mounting_wxyz[3]),
        set: |c, v| if let Some(h) = c.star.second_head.as_mut() { h.mounting_wxyz[3] = v },
        when: StarSecondHead,
    }
    HeadNoise: f64 {
        path: "star.second_head.noise_rad", unit: "rad", default: None, word: Some(75),
        range: STAR_NOISE, why: STAR_NOISE_WHY,
        get: |c| c.star.second_head.map_or(0.0, |h| h.noise_rad),
        set: |c, v| if let Some(h) = c.star.second_head.as_mut() { h.noise_rad = v },
        when: StarSecondHead,
    }
    HeadRollNoise: f64 {
        path: "star.second_head.roll_noise_rad", unit: "rad", default: None, word: Some(76),
        range: STAR_NOISE, why: STAR_NOISE_WHY,
        get: |c| c.star.second_head.map_or(0.0, |h| h.roll_noise_rad),
        set: |c, v| if let Some(h) = c.star.second_head.as_mut() { h.roll_noise_rad = v },
        when: StarSecondHead,
    }
    HeadAlignmentPrior: f64 {
        path: "star.second_head.alignment_prior_sigma_rad", unit: "rad",
        default: None, word: Some(77),
        range: ATTITUDE_SIGMA, why: ATTITUDE_WHY,
        get: |c| c.star.second_head.map_or(0.0, |h| h.alignment_prior_sigma_rad),
        set: |c, v| if let Some(h) = c.star.second_head.as_mut() { h.alignment_prior_sigma_rad = v },
        when: StarSecondHead,
    }
    HeadPairGate: f64 {
        path: "star.second_head.pair_gate_nis", unit: "", default: None, word: Some(78),
        range: GATE, why: GATE_WHY,
        get: |c| c.star.second_head.map_or(0.0, |h| h.pair_gate_nis),
        set: |c, v| if let Some(h) = c.star.second_head.as_mut() { h.pair_gate_nis = v },
        when: StarSecondHead,
    }
    ImuPeriodTolerance: f64 {
        path: "imu.period_tolerance", unit: "", default: Some(0.1), word: None,
        range: Range::new(1.0e-6, 0.5),
        why: "a sample's relative step error: a clock within 1e-6 is a quartz; beyond a half \
              two samples could share a frame",
        get: |c| c.imu.period_tolerance, set: |c, v| c.imu.period_tolerance = v,
    }
    StarAcquisitionGate: f64 {
        path: "star.acquisition_gate_nis", unit: "",
        default: Some(ACQUISITION_GATE_NIS), word: None,
        range: GATE, why: GATE_WHY,
        get: |c| c.star.acquisition_gate_nis, set: |c, v| c.star.acquisition_gate_nis = v,
    }
    StarNormTolerance: f64 {
        path: "star.unit_norm_tolerance", unit: "", default: Some(1e-3), word: None,
        range: Range::new(1.0e-12, 0.1),
        why: "a measured quaternion's norm error: 1e-12 is the rounding of its components; \
              beyond 0.1 it is no attitude",
        get: |c| c.star.unit_norm_tolerance, set: |c, v| c.star.unit_norm_tolerance = v,
    }
    GnssLeverArmX: f64 {
        path: "gnss.lever_arm_body_m[0]", unit: "m", default: Some(0.0), word: None,
        range: Range::new(-100.0, 100.0), why: "within the vehicle",
        get: |c| c.gnss.lever_arm_body_m[0], set: |c, v| c.gnss.lever_arm_body_m[0] = v,
    }
    GnssLeverArmY: f64 {
        path: "gnss.lever_arm_body_m[1]", unit: "m", default: Some(0.0), word: None,
        range: Range::new(-100.0, 100.0), why: "within the vehicle",
        get: |c| c.gnss.lever_arm_body_m[1], set: |c, v| c.gnss.lever_arm_body_m[1] = v,
    }
    GnssLeverArmZ: f64 {
        path: "gnss.lever_arm_body_m[2]", unit: "m", default: Some(0.0), word: None,
        range: Range::new(-100.0, 100.0), why: "within the vehicle",
        get: |c| c.gnss.lever_arm_body_m[2], set: |c, v| c.gnss.lever_arm_body_m[2] = v,
    }
    GnssAcquisitionGate: f64 {
        path: "gnss.acquisition_gate_nis", unit: "",
        default: Some(ACQUISITION_GATE_NIS), word: None,
        range: GATE, why: GATE_WHY,
        get: |c| c.gnss.acquisition_gate_nis, set: |c, v| c.gnss.acquisition_gate_nis = v,
    }
    GnssMaxJump: f64 {
        path: "gnss.max_jump_m", unit: "m", default: Some(1000.0), word: None,
        range: Range::new(1.0, 1.0e7),
        why: "a jump is beyond the receiver's noise (metres) and within the Earth's size",
        get: |c| c.gnss.max_jump_m, set: |c, v| c.gnss.max_jump_m = v,
    }
    GnssVelocityGate: f64 {
        path: "gnss.velocity_gate_nis", unit: "", default: Some(GATE_NIS), word: None,
        range: GATE, why: GATE_WHY,
        get: |c| c.gnss.velocity_gate_nis, set: |c, v| c.gnss.velocity_gate_nis = v,
    }
    GnssVelocityAcquisitionGate: f64 {
        path: "gnss.velocity_acquisition_gate_nis", unit: "",
        default: Some(ACQUISITION_GATE_NIS), word: None,
        range: GATE, why: GATE_WHY,
        get: |c| c.gnss.velocity_acquisition_gate_nis,
        set: |c, v| c.gnss.velocity_acquisition_gate_nis = v,
    }
    GnssWhitenessWindow: f64 {
        path: "gnss.whiteness_window_fixes", unit: "fixes", default: Some(64.0), word: None,
        range: Range::new(1.0, 1.0e6),
        why: "at least one fix; 1e6 fixes (days at 10 Hz) never forgets",
        get: |c| c.gnss.whiteness_window_fixes, set: |c, v| c.gnss.whiteness_window_fixes = v,
    }
    GnssWhitenessThreshold: f64 {
        path: "gnss.whiteness_threshold", unit: "", default: Some(0.30), word: None,
        range: Range::above(0.0, 1.0),
        why: "a correlation coefficient; the default: WhitenessMonitor docs",
        get: |c| c.gnss.whiteness_threshold, set: |c, v| c.gnss.whiteness_threshold = v,
    }
    FutureTolerance: f64 {
        path: "timing.future_tolerance_s", unit: "s", default: Some(0.001), word: None,
        range: Range::new(0.0, 0.1),
        why: "below one IMU period (checked with imu.period_s): a later tag is a future frame's",
        get: |c| c.timing.future_tolerance_s, set: |c, v| c.timing.future_tolerance_s = v,
    }
    OutageTimeout: f64 {
        path: "timing.outage_timeout_s", unit: "s", default: Some(2.0), word: None,
        range: Range::new(1.0e-3, 3600.0),
        why: "longer than a sensor's message interval; beyond an hour no outage is noticed",
        get: |c| c.timing.outage_timeout_s, set: |c, v| c.timing.outage_timeout_s = v,
    }
    RejectionsToDeclareFaulty: u32 {
        path: "timing.rejections_to_declare_faulty", unit: "rejections",
        default: Some(20), word: None,
        range: Range::counts(1, u32::MAX),
        why: "at least one; u32::MAX never declares a sensor faulty (a study of the flight without \
              fault declaration)",
        get: |c| c.timing.rejections_to_declare_faulty,
        set: |c, v| c.timing.rejections_to_declare_faulty = v,
    }
    PropagationInterval: u32 {
        path: "covariance.propagation_interval_frames", unit: "frames",
        default: Some(1), word: None,
        range: Range::counts(1, MAX_PROPAGATION_INTERVAL_FRAMES),
        why: "one second at 500 Hz at most: longer, the interval's mean rates no longer describe \
              the motion",
        get: |c| c.covariance.propagation_interval_frames,
        set: |c, v| c.covariance.propagation_interval_frames = v,
    }
    FrameLoad: FrameLoad {
        path: "covariance.frame_load", unit: "",
        default: Some(FrameLoad::FuseOrPropagate), word: None,
        range: Range::choice(&["propagate_then_fuse", "fuse_or_propagate"]),
        why: "the two schedules",
        get: |c| c.covariance.frame_load, set: |c, v| c.covariance.frame_load = v,
    }
    FloorAttitude: f64 {
        path: "covariance.sigma_floor.attitude_rad", unit: "rad", default: Some(1e-9), word: None,
        range: Range::new(1.0e-15, PI), why: FLOOR_WHY,
        get: |c| c.covariance.sigma_floor.attitude_rad,
        set: |c, v| c.covariance.sigma_floor.attitude_rad = v,
    }
    FloorPosition: f64 {
        path: "covariance.sigma_floor.position_m", unit: "m", default: Some(1e-4), word: None,
        range: Range::new(1.0e-9, 1.0e7), why: FLOOR_WHY,
        get: |c| c.covariance.sigma_floor.position_m,
        set: |c, v| c.covariance.sigma_floor.position_m = v,
    }
    FloorVelocity: f64 {
        path: "covariance.sigma_floor.velocity_mps", unit: "m/s", default: Some(1e-7), word: None,
        range: Range::new(1.0e-12, 1.0e4), why: FLOOR_WHY,
        get: |c| c.covariance.sigma_floor.velocity_mps,
        set: |c, v| c.covariance.sigma_floor.velocity_mps = v,
    }
    FloorGyroBias: f64 {
        path: "covariance.sigma_floor.gyro_bias_rad_s", unit: "rad/s",
        default: Some(1e-10), word: None,
        range: Range::new(1.0e-18, 1.0e-1), why: FLOOR_WHY,
        get: |c| c.covariance.sigma_floor.gyro_bias_rad_s,
        set: |c, v| c.covariance.sigma_floor.gyro_bias_rad_s = v,
    }
    FloorAccelBias: f64 {
        path: "covariance.sigma_floor.accel_bias_mps2", unit: "m/s^2",
        default: Some(1e-8), word: None,
        range: Range::new(1.0e-15, 10.0), why: FLOOR_WHY,
        get: |c| c.covariance.sigma_floor.accel_bias_mps2,
        set: |c, v| c.covariance.sigma_floor.accel_bias_mps2 = v,
    }
    FloorStarInstallation: f64 {
        path: "covariance.sigma_floor.star_installation_rad", unit: "rad",
        default: Some(1e-9), word: None,
        range: Range::new(1.0e-15, PI), why: FLOOR_WHY,
        get: |c| c.covariance.sigma_floor.star_installation_rad,
        set: |c, v| c.covariance.sigma_floor.star_installation_rad = v,
    }
    FloorGyroScaleFactor: f64 {
        path: "covariance.sigma_floor.gyro_scale_factor", unit: "",
        default: Some(1e-10), word: None,
        range: Range::new(1.0e-15, 0.1), why: FLOOR_WHY,
        get: |c| c.covariance.sigma_floor.gyro_scale_factor,
        set: |c, v| c.covariance.sigma_floor.gyro_scale_factor = v,
    }
    FloorAccelScaleFactor: f64 {
        path: "covariance.sigma_floor.accel_scale_factor", unit: "",
        default: Some(1e-10), word: None,
        range: Range::new(1.0e-15, 0.1), why: FLOOR_WHY,
        get: |c| c.covariance.sigma_floor.accel_scale_factor,
        set: |c, v| c.covariance.sigma_floor.accel_scale_factor = v,
    }
    FloorGnssError: f64 {
        path: "covariance.optional_sigma_floor.gnss_error_m", unit: "m",
        default: Some(1e-4), word: None,
        range: Range::new(1.0e-9, 1.0e3), why: FLOOR_WHY,
        get: |c| c.covariance.optional_sigma_floor.gnss_error_m,
        set: |c, v| c.covariance.optional_sigma_floor.gnss_error_m = v,
    }
    FloorGyroNonOrthogonality: f64 {
        path: "covariance.optional_sigma_floor.gyro_non_orthogonality_rad", unit: "rad",
        default: Some(1e-12), word: None,
        range: Range::new(1.0e-15, 1.0e-2), why: FLOOR_WHY,
        get: |c| c.covariance.optional_sigma_floor.gyro_non_orthogonality_rad,
        set: |c, v| c.covariance.optional_sigma_floor.gyro_non_orthogonality_rad = v,
    }
    FloorAccelMisalignment: f64 {
        path: "covariance.optional_sigma_floor.accel_misalignment_rad", unit: "rad",
        default: Some(1e-12), word: None,
        range: Range::new(1.0e-15, 1.0e-2), why: FLOOR_WHY,
        get: |c| c.covariance.optional_sigma_floor.accel_misalignment_rad,
        set: |c, v| c.covariance.optional_sigma_floor.accel_misalignment_rad = v,
    }
    FloorGyroGSensitivity: f64 {
        path: "covariance.optional_sigma_floor.gyro_g_sensitivity_rad_s_per_mps2",
        unit: "rad/s per m/s^2", default: Some(1e-15), word: None,
        range: Range::new(1.0e-18, 1.0e-3), why: FLOOR_WHY,
        get: |c| c.covariance.optional_sigma_floor.gyro_g_sensitivity_rad_s_per_mps2,
        set: |c, v| c.covariance.optional_sigma_floor.gyro_g_sensitivity_rad_s_per_mps2 = v,
    }
    SigmaCeilingFactor: f64 {
        path: "covariance.sigma_ceiling_factor", unit: "", default: Some(1e3), word: None,
        range: Range::new(1.0, 1.0e6),
        why: "a multiple of the initial 1-sigma: below 1 the prior itself is clamped; beyond 1e6 \
              the square of a large prior leaves the normal f64 range",
        get: |c| c.covariance.sigma_ceiling_factor,
        set: |c, v| c.covariance.sigma_ceiling_factor = v,
    }
    HeldSampleRate: f64 {
        path: "covariance.held_sample.rate_rad_s", unit: "rad/s", default: Some(0.1), word: None,
        range: Range::new(1.0e-6, 1.0e3).or_off(), why: "within a gyro's measurement range",
        get: |c| c.covariance.held_sample.rate_rad_s,
        set: |c, v| c.covariance.held_sample.rate_rad_s = v,
    }
    HeldSampleSpecificForce: f64 {
        path: "covariance.held_sample.specific_force_mps2", unit: "m/s^2",
        default: Some(1.0), word: None,
        range: Range::new(1.0e-6, 1.0e5).or_off(),
        why: "within an accelerometer's measurement range",
        get: |c| c.covariance.held_sample.specific_force_mps2,
        set: |c, v| c.covariance.held_sample.specific_force_mps2 = v,
    }
    SecondOrderAttitude: SecondOrderAttitude {
        path: "covariance.second_order_attitude", unit: "",
        default: Some(SecondOrderAttitude::Bounded), word: None,
        range: Range::choice(&["neglected", "bounded"]), why: "the two models",
        get: |c| c.covariance.second_order_attitude,
        set: |c, v| c.covariance.second_order_attitude = v,
    }
    ThresholdGyroBias: f64 {
        path: "calibration.convergence_sigma.gyro_bias_rad_s", unit: "rad/s",
        default: Some(Thresholds::PAPER_ACCURACY.gyro_bias_rad_s / 3.0), word: None,
        range: GYRO_BIAS_SIGMA, why: THRESHOLD_WHY,
        get: |c| c.calibration.convergence_sigma.gyro_bias_rad_s,
        set: |c, v| c.calibration.convergence_sigma.gyro_bias_rad_s = v,
    }
    ThresholdAccelBias: f64 {
        path: "calibration.convergence_sigma.accel_bias_mps2", unit: "m/s^2",
        default: Some(Thresholds::PAPER_ACCURACY.accel_bias_mps2 / 3.0), word: None,
        range: ACCEL_BIAS_SIGMA, why: THRESHOLD_WHY,
        get: |c| c.calibration.convergence_sigma.accel_bias_mps2,
        set: |c, v| c.calibration.convergence_sigma.accel_bias_mps2 = v,
    }
    ThresholdStarInstallation: f64 {
        path: "calibration.convergence_sigma.star_installation_rad", unit: "rad",
        default: Some(Thresholds::PAPER_ACCURACY.star_installation_rad / 3.0), word: None,
        range: ATTITUDE_SIGMA, why: THRESHOLD_WHY,
        get: |c| c.calibration.convergence_sigma.star_installation_rad,
        set: |c, v| c.calibration.convergence_sigma.star_installation_rad = v,
    }
    ThresholdGyroScaleFactor: f64 {
        path: "calibration.convergence_sigma.gyro_scale_factor", unit: "",
        default: Some(Thresholds::PAPER_ACCURACY.gyro_scale_factor / 3.0), word: None,
        range: SCALE_SIGMA, why: THRESHOLD_WHY,
        get: |c| c.calibration.convergence_sigma.gyro_scale_factor,
        set: |c, v| c.calibration.convergence_sigma.gyro_scale_factor = v,
    }
    ThresholdAccelScaleFactor: f64 {
        path: "calibration.convergence_sigma.accel_scale_factor", unit: "",
        default: Some(Thresholds::PAPER_ACCURACY.accel_scale_factor / 3.0), word: None,
        range: SCALE_SIGMA, why: THRESHOLD_WHY,
        get: |c| c.calibration.convergence_sigma.accel_scale_factor,
        set: |c, v| c.calibration.convergence_sigma.accel_scale_factor = v,
    }
    StabilityWindow: f64 {
        path: "calibration.stability_window_s", unit: "s", default: Some(10.0), word: None,
        range: Range::new(0.0, 86_400.0), why: "0 (converged at once) to one day of flight",
        get: |c| c.calibration.stability_window_s, set: |c, v| c.calibration.stability_window_s = v,
    }
    StabilityFraction: f64 {
        path: "calibration.stability_fraction", unit: "", default: Some(1.0), word: None,
        range: Range::new(1.0e-3, 1.0e3), why: "a fraction of the block's threshold",
        get: |c| c.calibration.stability_fraction, set: |c, v| c.calibration.stability_fraction = v,
    }
    FreezeConverged: bool {
        path: "calibration.freeze_converged", unit: "", default: Some(false), word: None,
        range: Range::FLAG, why: "on or off",
        get: |c| c.calibration.freeze_converged, set: |c, v| c.calibration.freeze_converged = v,
    }
    EstimationPolicy: EstimationPolicy {
        path: "calibration.policy", unit: "",
        default: Some(EstimationPolicy::AllBlocks), word: None,
        range: Range::choice(&["all_blocks", "paper_schedule", "motion_observability"]),
        why: "the three policies",
        get: |c| c.calibration.policy, set: |c, v| c.calibration.policy = v,
    }
    MotionRateThreshold: f64 {
        path: "calibration.motion_rate_threshold_rad_s", unit: "rad/s",
        default: Some(0.5 * PI / 180.0), word: None,
        range: Range::new(1.0e-6, 1.0),
        why: "above an orbital coast's rate and the gyro noise, below a calibration rotation",
        get: |c| c.calibration.motion_rate_threshold_rad_s,
        set: |c, v| c.calibration.motion_rate_threshold_rad_s = v,
    }
    MotionForceThreshold: f64 {
        path: "calibration.motion_force_threshold_mps2", unit: "m/s^2",
        default: Some(0.5), word: None,
        range: Range::new(1.0e-4, 100.0),
        why: "above a coast's drag and accelerometer noise, below a calibration burn",
        get: |c| c.calibration.motion_force_threshold_mps2,
        set: |c, v| c.calibration.motion_force_threshold_mps2 = v,
    }
    ConsistencyTimeConstant: u32 {
        path: "consistency.time_constant_measurements", unit: "measurements",
        default: Some(crate::consistency::DEFAULT_TIME_CONSTANT_MEASUREMENTS), word: None,
        range: Range::counts(1, MAX_TIME_CONSTANT_MEASUREMENTS),
        why: "the fading average's memory: one measurement to the monitor's largest",
        get: |c| c.consistency.time_constant_measurements,
        set: |c, v| c.consistency.time_constant_measurements = v,
    }
    ConsistencyMeanNisBound: f64 {
        path: "consistency.mean_nis_bound", unit: "",
        default: Some(DEFAULT_MEAN_NIS_BOUND), word: None,
        range: Range::above(crate::consistency::CONSISTENT_MEAN_NIS, 100.0),
        why: "above 3, a consistent filter's mean NIS; beyond 100 nothing is flagged",
        get: |c| c.consistency.mean_nis_bound, set: |c, v| c.consistency.mean_nis_bound = v,
    }
    ConingCompensation: bool {
        path: "strapdown.coning_compensation", unit: "", default: Some(true), word: None,
        range: Range::FLAG, why: "on or off",
        get: |c| c.strapdown.coning_compensation, set: |c, v| c.strapdown.coning_compensation = v,
    }
    ScullingCompensation: bool {
        path: "strapdown.sculling_compensation", unit: "", default: Some(true), word: None,
        range: Range::FLAG, why: "on or off",
        get: |c| c.strapdown.sculling_compensation,
        set: |c, v| c.strapdown.sculling_compensation = v,
    }
    StrapdownJ2: bool {
        path: "strapdown.gravity.j2_enabled", unit: "", default: Some(true), word: None,
        range: Range::FLAG, why: "on or off",
        get: |c| c.strapdown.gravity.j2_enabled, set: |c, v| c.strapdown.gravity.j2_enabled = v,
    }
}
