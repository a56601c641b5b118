//! The one error type of nav-fsw.

use nav_core::NavError;

/// A configuration field that failed validation (so the error names the key, never a bare
/// "invalid configuration").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ConfigField {
    /// `imu.period_s`
    ImuPeriod,
    /// `imu.period_tolerance`
    ImuPeriodTolerance,
    /// `imu.max_rate_rad_s`
    ImuMaxRate,
    /// `imu.max_specific_force_mps2`
    ImuMaxSpecificForce,
    /// `star.unit_norm_tolerance`
    StarNormTolerance,
    /// `gnss.max_jump_m`
    GnssMaxJump,
    /// `timing.max_latency_s`
    MaxLatency,
    /// `launch_site` (latitude, longitude, azimuth, height or epoch)
    LaunchSite,
    /// `filter.initial` or `filter.discretisation_order`
    FilterInitialUncertainty,
    /// `process_noise`
    ProcessNoise,
    /// `star.mounting_wxyz`
    StarMounting,
    /// `star.noise_rad`
    StarNoise,
    /// `star.gate_nis`
    StarGate,
    /// `gnss.lever_arm_body_m`
    GnssLeverArm,
    /// `gnss.noise_m`
    GnssNoise,
    /// `gnss.gate_nis`
    GnssGate,
    /// `gnss.velocity_noise_mps` or `gnss.velocity_gate_nis`.
    GnssVelocity,
    /// `gnss.whiteness_window_fixes` or `gnss.whiteness_threshold`.
    GnssWhiteness,
    /// `filter.gnss_error` (correlated GNSS error σ or correlation time).
    GnssCorrelatedError,
    /// `covariance.held_sample` (uncertainty of a held IMU sample).
    HeldSampleUncertainty,
    /// `timing.future_tolerance_s`
    FutureTolerance,
    /// `timing.outage_timeout_s`
    OutageTimeout,
    /// `timing.rejections_to_declare_faulty`
    RejectionsToDeclareFaulty,
    /// `covariance.propagation_interval_frames`
    PropagationInterval,
    /// `covariance.sigma_floor`
    SigmaFloor,
    /// `covariance.sigma_ceiling_factor`
    SigmaCeiling,
    /// `calibration.convergence_sigma`
    CalibrationThreshold,
    /// `calibration.stability_window_s`
    CalibrationWindow,
    /// `calibration.stability_fraction`
    CalibrationStability,
    /// `calibration.motion_rate_threshold_rad_s` or `calibration.motion_force_threshold_mps2`
    CalibrationMotionThreshold,
    /// `calibration.motion_observability` (an entry names a navigation block)
    CalibrationObservabilityTable,
    /// The initial navigation state (non-finite, or attitude not a unit quaternion).
    InitialNavigation,
}

/// Why a nav-fsw operation refused its input or could not complete.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FswError {
    /// A configuration value is out of its documented range.
    InvalidConfiguration(ConfigField),
    /// nav-core refused an operation.
    Navigation(NavError),
}

impl From<NavError> for FswError {
    fn from(error: NavError) -> Self {
        FswError::Navigation(error)
    }
}
