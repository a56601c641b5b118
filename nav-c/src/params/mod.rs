//! The flight parameters for C: [`NavConfig`] (one field per parameter of nav-fsw's
//! parameter table but the ground constants') and [`NavParam`] (every parameter's
//! identifier). Generated from the table (`nav-fsw/src/config/parameters.rs`) by
//! `NAV_BLESS=1 cargo test -p nav-c --test params`; the test fails when this file differs from the table. Do not edit it by
//! hand.

mod config;

pub use config::NavConfig;
pub(crate) use config::CONFIG_PARAMS;

/// Parameters in `NavConfig`, in the order of its fields.
pub const NAV_CONFIG_PARAMS: usize = 103;

/// Parameters in the table (`NavParam` counts them from 1).
pub const NAV_PARAMS: usize = 116;

/// Every flight parameter, numbered from 1 in the table's order (0 is none);
/// `nav_param_path` gives its path in the flight software's configuration.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NavParam {
    /// No parameter.
    None = 0,
    /// `filter.mode`
    FilterMode = 1,
    /// `filter.discretisation_order`
    FilterDiscretisationOrder = 2,
    /// `sensor_frames.launch_epoch_gps_week`
    LaunchEpochGpsWeek = 3,
    /// `gravity.field.degree`
    GravityDegree = 4,
    /// `gravity.field.order`
    GravityOrder = 5,
    /// `gravity.field.terms_per_frame`
    GravityTermsPerFrame = 6,
    /// `launch_site.latitude_rad`
    LaunchLatitude = 7,
    /// `launch_site.longitude_rad`
    LaunchLongitude = 8,
    /// `launch_site.height_m`
    LaunchHeight = 9,
    /// `launch_site.azimuth_rad`
    LaunchAzimuth = 10,
    /// `launch_site.earth_axis_ecef[0]`
    EarthAxisX = 11,
    /// `launch_site.earth_axis_ecef[1]`
    EarthAxisY = 12,
    /// `launch_site.earth_axis_ecef[2]`
    EarthAxisZ = 13,
    /// `sensor_frames.gcrf_to_launch_inertial_wxyz[0]`
    GcrfW = 14,
    /// `sensor_frames.gcrf_to_launch_inertial_wxyz[1]`
    GcrfX = 15,
    /// `sensor_frames.gcrf_to_launch_inertial_wxyz[2]`
    GcrfY = 16,
    /// `sensor_frames.gcrf_to_launch_inertial_wxyz[3]`
    GcrfZ = 17,
    /// `sensor_frames.launch_epoch_gps_seconds_of_week`
    LaunchEpochSecondsOfWeek = 18,
    /// `filter.initial.attitude_rad`
    InitialAttitude = 19,
    /// `filter.initial.position_m`
    InitialPosition = 20,
    /// `filter.initial.velocity_mps`
    InitialVelocity = 21,
    /// `filter.initial.gyro_bias_rad_s`
    InitialGyroBias = 22,
    /// `filter.initial.accel_bias_mps2`
    InitialAccelBias = 23,
    /// `filter.initial.star_installation_rad`
    InitialStarInstallation = 24,
    /// `filter.initial.gyro_scale_factor`
    InitialGyroScaleFactor = 25,
    /// `filter.initial.accel_scale_factor`
    InitialAccelScaleFactor = 26,
    /// `process_noise.gyro_noise_density_rad_s_per_sqrt_hz`
    GyroNoiseDensity = 27,
    /// `process_noise.accel_noise_density_mps2_per_sqrt_hz`
    AccelNoiseDensity = 28,
    /// `process_noise.gyro_bias_walk_rad_s2_per_sqrt_hz`
    GyroBiasWalk = 29,
    /// `process_noise.accel_bias_walk_mps3_per_sqrt_hz`
    AccelBiasWalk = 30,
    /// `imu.period_s`
    ImuPeriod = 31,
    /// `star.mounting_wxyz[0]`
    StarMountingW = 32,
    /// `star.mounting_wxyz[1]`
    StarMountingX = 33,
    /// `star.mounting_wxyz[2]`
    StarMountingY = 34,
    /// `star.mounting_wxyz[3]`
    StarMountingZ = 35,
    /// `star.noise_rad`
    StarNoise = 36,
    /// `star.gate_nis`
    StarGate = 37,
    /// `gnss.noise_m`
    GnssNoise = 38,
    /// `gnss.gate_nis`
    GnssGate = 39,
    /// `timing.max_latency_s`
    MaxLatency = 40,
    /// `filter.gnss_error.sigma_m`
    GnssCorrelatedSigma = 41,
    /// `filter.gnss_error.correlation_time_s`
    GnssCorrelationTime = 42,
    /// `gnss.velocity_noise_mps`
    GnssVelocityNoise = 43,
    /// `imu.max_rate_rad_s`
    ImuMaxRate = 44,
    /// `imu.max_specific_force_mps2`
    ImuMaxSpecificForce = 45,
    /// `filter.imu_error.gyro_misalignment_sigma_rad`
    GyroMisalignmentSigma = 46,
    /// `filter.imu_error.accel_misalignment_sigma_rad`
    AccelMisalignmentSigma = 47,
    /// `filter.imu_error.gyro_g_sensitivity_sigma_rad_s_per_mps2`
    GyroGSensitivitySigma = 48,
    /// `gravity.omitted_field_sigma_mps2`
    OmittedFieldSigma = 49,
    /// `gravity.omitted_field_psd_m2_per_s3`
    OmittedFieldPsd = 50,
    /// `star.roll_noise_rad`
    StarRollNoise = 51,
    /// `star.slow_error_sigma_rad[0]`
    StarSlowErrorX = 52,
    /// `star.slow_error_sigma_rad[1]`
    StarSlowErrorY = 53,
    /// `star.slow_error_sigma_rad[2]`
    StarSlowErrorZ = 54,
    /// `star.slow_error_correlation_time_s`
    StarSlowErrorCorrelationTime = 55,
    /// `star.aberration_correction`
    StarAberrationCorrection = 56,
    /// `star.noise_matching`
    StarNoiseMatching = 57,
    /// `star.second_head`
    StarSecondHead = 58,
    /// `star.second_head.pairs_before_hand_over`
    HeadPairsBeforeHandOver = 59,
    /// `star.second_head.mounting_wxyz[0]`
    HeadMountingW = 60,
    /// `star.second_head.mounting_wxyz[1]`
    HeadMountingX = 61,
    /// `star.second_head.mounting_wxyz[2]`
    HeadMountingY = 62,
    /// `star.second_head.mounting_wxyz[3]`
    HeadMountingZ = 63,
    /// `star.second_head.noise_rad`
    HeadNoise = 64,
    /// `star.second_head.roll_noise_rad`
    HeadRollNoise = 65,
    /// `star.second_head.alignment_prior_sigma_rad`
    HeadAlignmentPrior = 66,
    /// `star.second_head.pair_gate_nis`
    HeadPairGate = 67,
    /// `imu.period_tolerance`
    ImuPeriodTolerance = 68,
    /// `star.acquisition_gate_nis`
    StarAcquisitionGate = 69,
    /// `star.unit_norm_tolerance`
    StarNormTolerance = 70,
    /// `gnss.lever_arm_body_m[0]`
    GnssLeverArmX = 71,
    /// `gnss.lever_arm_body_m[1]`
    GnssLeverArmY = 72,
    /// `gnss.lever_arm_body_m[2]`
    GnssLeverArmZ = 73,
    /// `gnss.acquisition_gate_nis`
    GnssAcquisitionGate = 74,
    /// `gnss.max_jump_m`
    GnssMaxJump = 75,
    /// `gnss.velocity_gate_nis`
    GnssVelocityGate = 76,
    /// `gnss.velocity_acquisition_gate_nis`
    GnssVelocityAcquisitionGate = 77,
    /// `gnss.whiteness_window_fixes`
    GnssWhitenessWindow = 78,
    /// `gnss.whiteness_threshold`
    GnssWhitenessThreshold = 79,
    /// `timing.future_tolerance_s`
    FutureTolerance = 80,
    /// `timing.outage_timeout_s`
    OutageTimeout = 81,
    /// `timing.rejections_to_declare_faulty`
    RejectionsToDeclareFaulty = 82,
    /// `covariance.propagation_interval_frames`
    PropagationInterval = 83,
    /// `covariance.frame_load`
    FrameLoad = 84,
    /// `covariance.sigma_floor.attitude_rad`
    FloorAttitude = 85,
    /// `covariance.sigma_floor.position_m`
    FloorPosition = 86,
    /// `covariance.sigma_floor.velocity_mps`
    FloorVelocity = 87,
    /// `covariance.sigma_floor.gyro_bias_rad_s`
    FloorGyroBias = 88,
    /// `covariance.sigma_floor.accel_bias_mps2`
    FloorAccelBias = 89,
    /// `covariance.sigma_floor.star_installation_rad`
    FloorStarInstallation = 90,
    /// `covariance.sigma_floor.gyro_scale_factor`
    FloorGyroScaleFactor = 91,
    /// `covariance.sigma_floor.accel_scale_factor`
    FloorAccelScaleFactor = 92,
    /// `covariance.optional_sigma_floor.gnss_error_m`
    FloorGnssError = 93,
    /// `covariance.optional_sigma_floor.gyro_non_orthogonality_rad`
    FloorGyroNonOrthogonality = 94,
    /// `covariance.optional_sigma_floor.accel_misalignment_rad`
    FloorAccelMisalignment = 95,
    /// `covariance.optional_sigma_floor.gyro_g_sensitivity_rad_s_per_mps2`
    FloorGyroGSensitivity = 96,
    /// `covariance.sigma_ceiling_factor`
    SigmaCeilingFactor = 97,
    /// `covariance.held_sample.rate_rad_s`
    HeldSampleRate = 98,
    /// `covariance.held_sample.specific_force_mps2`
    HeldSampleSpecificForce = 99,
    /// `covariance.second_order_attitude`
    SecondOrderAttitude = 100,
    /// `calibration.convergence_sigma.gyro_bias_rad_s`
    ThresholdGyroBias = 101,
    /// `calibration.convergence_sigma.accel_bias_mps2`
    ThresholdAccelBias = 102,
    /// `calibration.convergence_sigma.star_installation_rad`
    ThresholdStarInstallation = 103,
    /// `calibration.convergence_sigma.gyro_scale_factor`
    ThresholdGyroScaleFactor = 104,
    /// `calibration.convergence_sigma.accel_scale_factor`
    ThresholdAccelScaleFactor = 105,
    /// `calibration.stability_window_s`
    StabilityWindow = 106,
    /// `calibration.stability_fraction`
    StabilityFraction = 107,
    /// `calibration.freeze_converged`
    FreezeConverged = 108,
    /// `calibration.policy`
    EstimationPolicy = 109,
    /// `calibration.motion_rate_threshold_rad_s`
    MotionRateThreshold = 110,
    /// `calibration.motion_force_threshold_mps2`
    MotionForceThreshold = 111,
    /// `consistency.time_constant_measurements`
    ConsistencyTimeConstant = 112,
    /// `consistency.mean_nis_bound`
    ConsistencyMeanNisBound = 113,
    /// `strapdown.coning_compensation`
    ConingCompensation = 114,
    /// `strapdown.sculling_compensation`
    ScullingCompensation = 115,
    /// `strapdown.gravity.j2_enabled`
    StrapdownJ2 = 116,
}

/// Every parameter's path, NUL-terminated, in the table's order.
pub(crate) const PARAM_PATHS: [&str; NAV_PARAMS] = [
    "filter.mode\0",
    "filter.discretisation_order\0",
    "sensor_frames.launch_epoch_gps_week\0",
    "gravity.field.degree\0",
    "gravity.field.order\0",
    "gravity.field.terms_per_frame\0",
    "launch_site.latitude_rad\0",
    "launch_site.longitude_rad\0",
    "launch_site.height_m\0",
    "launch_site.azimuth_rad\0",
    "launch_site.earth_axis_ecef[0]\0",
    "launch_site.earth_axis_ecef[1]\0",
    "launch_site.earth_axis_ecef[2]\0",
    "sensor_frames.gcrf_to_launch_inertial_wxyz[0]\0",
    "sensor_frames.gcrf_to_launch_inertial_wxyz[1]\0",
    "sensor_frames.gcrf_to_launch_inertial_wxyz[2]\0",
    "sensor_frames.gcrf_to_launch_inertial_wxyz[3]\0",
    "sensor_frames.launch_epoch_gps_seconds_of_week\0",
    "filter.initial.attitude_rad\0",
    "filter.initial.position_m\0",
    "filter.initial.velocity_mps\0",
    "filter.initial.gyro_bias_rad_s\0",
    "filter.initial.accel_bias_mps2\0",
    "filter.initial.star_installation_rad\0",
    "filter.initial.gyro_scale_factor\0",
    "filter.initial.accel_scale_factor\0",
    "process_noise.gyro_noise_density_rad_s_per_sqrt_hz\0",
    "process_noise.accel_noise_density_mps2_per_sqrt_hz\0",
    "process_noise.gyro_bias_walk_rad_s2_per_sqrt_hz\0",
    "process_noise.accel_bias_walk_mps3_per_sqrt_hz\0",
    "imu.period_s\0",
    "star.mounting_wxyz[0]\0",
    "star.mounting_wxyz[1]\0",
    "star.mounting_wxyz[2]\0",
    "star.mounting_wxyz[3]\0",
    "star.noise_rad\0",
    "star.gate_nis\0",
    "gnss.noise_m\0",
    "gnss.gate_nis\0",
    "timing.max_latency_s\0",
    "filter.gnss_error.sigma_m\0",
    "filter.gnss_error.correlation_time_s\0",
    "gnss.velocity_noise_mps\0",
    "imu.max_rate_rad_s\0",
    "imu.max_specific_force_mps2\0",
    "filter.imu_error.gyro_misalignment_sigma_rad\0",
    "filter.imu_error.accel_misalignment_sigma_rad\0",
    "filter.imu_error.gyro_g_sensitivity_sigma_rad_s_per_mps2\0",
    "gravity.omitted_field_sigma_mps2\0",
    "gravity.omitted_field_psd_m2_per_s3\0",
    "star.roll_noise_rad\0",
    "star.slow_error_sigma_rad[0]\0",
    "star.slow_error_sigma_rad[1]\0",
    "star.slow_error_sigma_rad[2]\0",
    "star.slow_error_correlation_time_s\0",
    "star.aberration_correction\0",
    "star.noise_matching\0",
    "star.second_head\0",
    "star.second_head.pairs_before_hand_over\0",
    "star.second_head.mounting_wxyz[0]\0",
    "star.second_head.mounting_wxyz[1]\0",
    "star.second_head.mounting_wxyz[2]\0",
    "star.second_head.mounting_wxyz[3]\0",
    "star.second_head.noise_rad\0",
    "star.second_head.roll_noise_rad\0",
    "star.second_head.alignment_prior_sigma_rad\0",
    "star.second_head.pair_gate_nis\0",
    "imu.period_tolerance\0",
    "star.acquisition_gate_nis\0",
    "star.unit_norm_tolerance\0",
    "gnss.lever_arm_body_m[0]\0",
    "gnss.lever_arm_body_m[1]\0",
    "gnss.lever_arm_body_m[2]\0",
    "gnss.acquisition_gate_nis\0",
    "gnss.max_jump_m\0",
    "gnss.velocity_gate_nis\0",
    "gnss.velocity_acquisition_gate_nis\0",
    "gnss.whiteness_window_fixes\0",
    "gnss.whiteness_threshold\0",
    "timing.future_tolerance_s\0",
    "timing.outage_timeout_s\0",
    "timing.rejections_to_declare_faulty\0",
    "covariance.propagation_interval_frames\0",
    "covariance.frame_load\0",
    "covariance.sigma_floor.attitude_rad\0",
    "covariance.sigma_floor.position_m\0",
    "covariance.sigma_floor.velocity_mps\0",
    "covariance.sigma_floor.gyro_bias_rad_s\0",
    "covariance.sigma_floor.accel_bias_mps2\0",
    "covariance.sigma_floor.star_installation_rad\0",
    "covariance.sigma_floor.gyro_scale_factor\0",
    "covariance.sigma_floor.accel_scale_factor\0",
    "covariance.optional_sigma_floor.gnss_error_m\0",
    "covariance.optional_sigma_floor.gyro_non_orthogonality_rad\0",
    "covariance.optional_sigma_floor.accel_misalignment_rad\0",
    "covariance.optional_sigma_floor.gyro_g_sensitivity_rad_s_per_mps2\0",
    "covariance.sigma_ceiling_factor\0",
    "covariance.held_sample.rate_rad_s\0",
    "covariance.held_sample.specific_force_mps2\0",
    "covariance.second_order_attitude\0",
    "calibration.convergence_sigma.gyro_bias_rad_s\0",
    "calibration.convergence_sigma.accel_bias_mps2\0",
    "calibration.convergence_sigma.star_installation_rad\0",
    "calibration.convergence_sigma.gyro_scale_factor\0",
    "calibration.convergence_sigma.accel_scale_factor\0",
    "calibration.stability_window_s\0",
    "calibration.stability_fraction\0",
    "calibration.freeze_converged\0",
    "calibration.policy\0",
    "calibration.motion_rate_threshold_rad_s\0",
    "calibration.motion_force_threshold_mps2\0",
    "consistency.time_constant_measurements\0",
    "consistency.mean_nis_bound\0",
    "strapdown.coning_compensation\0",
    "strapdown.sculling_compensation\0",
    "strapdown.gravity.j2_enabled\0",
];
