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
    /// `star.slow_error_sigma_rad` or `star.slow_error_correlation_time_s`
    StarSlowError,
    /// `star.second_head` (mounting, noise, alignment prior, pair gate)
    StarSecondHead,
    /// `gnss.max_jump_m`
    GnssMaxJump,
    /// `timing.max_latency_s`
    MaxLatency,
    /// `launch_site` (latitude, longitude, azimuth, height or epoch)
    LaunchSite,
    /// `sensor_frames` (GCRF → launch-inertial rotation, launch epoch in GPS time)
    SensorFrames,
    /// `filter.initial` or `filter.discretisation_order`
    FilterInitialUncertainty,
    /// `process_noise`
    ProcessNoise,
    /// `star.mounting_wxyz`
    StarMounting,
    /// `star.noise_rad` or `star.roll_noise_rad`
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
    /// `star.acquisition_gate_nis`
    StarAcquisitionGate,
    /// `gnss.acquisition_gate_nis` or `gnss.velocity_acquisition_gate_nis`
    GnssAcquisitionGate,
    /// `gnss.whiteness_window_fixes` or `gnss.whiteness_threshold`.
    GnssWhiteness,
    /// `filter.gnss_error` (correlated GNSS error σ or correlation time).
    GnssCorrelatedError,
    /// `filter.imu_error` (the systematic IMU error states' prior 1σ).
    ImuSystematicError,
    /// `covariance.held_sample` (uncertainty of a held IMU sample).
    HeldSampleUncertainty,
    /// `timing.future_tolerance_s`
    FutureTolerance,
    /// `timing.outage_timeout_s`
    OutageTimeout,
    /// `timing.rejections_to_declare_faulty`
    RejectionsToDeclareFaulty,
    /// `consistency.time_constant_measurements` / `consistency.mean_nis_bound`
    Consistency,
    /// `gravity` (the field model beyond `J2`, or the allowance for what it omits)
    Gravity,
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

impl ConfigField {
    /// The field's path in [`crate::config::FswConfig`], e.g. `timing.max_latency_s`.
    pub const fn key(self) -> &'static str {
        match self {
            ConfigField::ImuPeriod => "imu.period_s",
            ConfigField::ImuPeriodTolerance => "imu.period_tolerance",
            ConfigField::ImuMaxRate => "imu.max_rate_rad_s",
            ConfigField::ImuMaxSpecificForce => "imu.max_specific_force_mps2",
            ConfigField::StarNormTolerance => "star.unit_norm_tolerance",
            ConfigField::StarSlowError => {
                "star.slow_error_sigma_rad / star.slow_error_correlation_time_s"
            }
            ConfigField::StarSecondHead => "star.second_head",
            ConfigField::GnssMaxJump => "gnss.max_jump_m",
            ConfigField::MaxLatency => "timing.max_latency_s",
            ConfigField::LaunchSite => "launch_site",
            ConfigField::SensorFrames => "sensor_frames",
            ConfigField::FilterInitialUncertainty => "filter.initial",
            ConfigField::ProcessNoise => "process_noise",
            ConfigField::StarMounting => "star.mounting_wxyz",
            ConfigField::StarNoise => "star.noise_rad / star.roll_noise_rad",
            ConfigField::StarGate => "star.gate_nis",
            ConfigField::GnssLeverArm => "gnss.lever_arm_body_m",
            ConfigField::GnssNoise => "gnss.noise_m",
            ConfigField::GnssGate => "gnss.gate_nis",
            ConfigField::GnssVelocity => "gnss.velocity_noise_mps / gnss.velocity_gate_nis",
            ConfigField::StarAcquisitionGate => "star.acquisition_gate_nis",
            ConfigField::GnssAcquisitionGate => {
                "gnss.acquisition_gate_nis / gnss.velocity_acquisition_gate_nis"
            }
            ConfigField::GnssWhiteness => "gnss.whiteness_window_fixes / gnss.whiteness_threshold",
            ConfigField::GnssCorrelatedError => "filter.gnss_error",
            ConfigField::ImuSystematicError => "filter.imu_error",
            ConfigField::HeldSampleUncertainty => "covariance.held_sample",
            ConfigField::FutureTolerance => "timing.future_tolerance_s",
            ConfigField::OutageTimeout => "timing.outage_timeout_s",
            ConfigField::RejectionsToDeclareFaulty => "timing.rejections_to_declare_faulty",
            ConfigField::Consistency => {
                "consistency.time_constant_measurements / consistency.mean_nis_bound"
            }
            ConfigField::Gravity => "gravity",
            ConfigField::PropagationInterval => "covariance.propagation_interval_frames",
            ConfigField::SigmaFloor => "covariance.sigma_floor",
            ConfigField::SigmaCeiling => "covariance.sigma_ceiling_factor",
            ConfigField::CalibrationThreshold => "calibration.convergence_sigma",
            ConfigField::CalibrationWindow => "calibration.stability_window_s",
            ConfigField::CalibrationStability => "calibration.stability_fraction",
            ConfigField::CalibrationMotionThreshold => "calibration.motion_*_threshold",
            ConfigField::CalibrationObservabilityTable => "calibration.motion_observability",
            ConfigField::InitialNavigation => "initial navigation state",
        }
    }

    /// The rule [`crate::config::FswConfig::validate`] applies to the field, as a phrase that
    /// follows the key ("must be ..."). `σ-rule` is [`crate::config::sigma_is_squarable`].
    pub const fn rule(self) -> &'static str {
        match self {
            ConfigField::ImuPeriod
            | ConfigField::ImuMaxRate
            | ConfigField::ImuMaxSpecificForce
            | ConfigField::GnssMaxJump
            | ConfigField::OutageTimeout
            | ConfigField::CalibrationStability
            | ConfigField::CalibrationMotionThreshold => "must be finite and > 0",
            ConfigField::ImuPeriodTolerance => "must be finite, > 0 and < 1",
            ConfigField::StarNormTolerance => "must be finite, > 0 and < 0.5",
            ConfigField::MaxLatency => {
                "must be finite, >= 0 and at most (HISTORY_CAPACITY - 1) = 63 IMU periods \
                 (126 ms at 500 Hz): the navigation history holds no older snapshot"
            }
            ConfigField::LaunchSite => {
                "must be finite, latitude within +-90 deg, longitude and azimuth within \
                 +-360 deg, height within [-1000, 10000] m, Earth axis a unit vector within \
                 1e-4 rad of ECEF z"
            }
            ConfigField::SensorFrames => {
                "must have a unit GCRF-to-launch-inertial quaternion (norm within 1e-9 of 1) and \
                 a launch epoch with GPS week <= 9999 and seconds of week in [0, 604800)"
            }
            ConfigField::FilterInitialUncertainty => {
                "must have every 1-sigma in [1e-150, 1e150] (its square inside the normal f64 \
                 range) and a discretisation order in 1..=4"
            }
            ConfigField::SigmaFloor | ConfigField::CalibrationThreshold => {
                "must have every 1-sigma in [1e-150, 1e150] (its square inside the normal f64 range)"
            }
            ConfigField::StarNoise | ConfigField::GnssNoise => {
                "must be in [1e-150, 1e150] (its square inside the normal f64 range)"
            }
            ConfigField::ProcessNoise | ConfigField::HeldSampleUncertainty => {
                "must have every value 0 or in [1e-150, 1e150] (its square inside the normal \
                 f64 range)"
            }
            ConfigField::StarMounting => "must be a unit quaternion (norm within 1e-9 of 1)",
            ConfigField::StarGate | ConfigField::GnssGate => "must be > 0 (or +infinity: no gate)",
            ConfigField::GnssLeverArm => "must be finite",
            ConfigField::GnssVelocity => {
                "must have a noise 0 (off) or in [1e-150, 1e150] and a gate > 0 (or +infinity)"
            }
            ConfigField::StarAcquisitionGate | ConfigField::GnssAcquisitionGate => {
                "must be > 0 (or +infinity: no gate until acquired)"
            }
            ConfigField::GnssWhiteness => "must have a window >= 1 fix and a threshold > 0",
            ConfigField::StarSlowError => {
                "must have every 1-sigma 0 (off) or in [1e-150, 1e150], and a correlation time \
                 finite and > 0 (with a finite walk) when any 1-sigma is > 0"
            }
            ConfigField::StarSecondHead => {
                "must have a unit mounting quaternion, noises and an alignment prior 1-sigma in \
                 [1e-150, 1e150] and a pair gate > 0"
            }
            ConfigField::GnssCorrelatedError => {
                "must have a 1-sigma 0 (off) or in [1e-150, 1e150], and a correlation time \
                 finite and > 0 when the 1-sigma is > 0"
            }
            ConfigField::ImuSystematicError => {
                "must have every 1-sigma 0 (off) or every one finite and > 0"
            }
            ConfigField::FutureTolerance => "must be finite, >= 0 and below one IMU period",
            ConfigField::RejectionsToDeclareFaulty => "must be >= 1",
            ConfigField::Consistency => {
                "must have a time constant in 1..=65536 measurements and a mean-NIS bound finite and > 3"
            }
            ConfigField::Gravity => {
                "must have a degree in 2..=12, an order <= degree, >= 1 term per frame, and an \
                 omitted-field 1-sigma and density both 0 or both > 0 (density <= 1 m^2/s^3)"
            }
            ConfigField::PropagationInterval => "must be in 1..=500 frames",
            ConfigField::SigmaCeiling => "must be finite and >= 1",
            ConfigField::CalibrationWindow => "must be finite and >= 0",
            ConfigField::CalibrationObservabilityTable => {
                "must name calibration blocks only (no attitude, position or velocity)"
            }
            ConfigField::InitialNavigation => {
                "must be finite, with a unit attitude quaternion and |time_s| <= 1e9 s \
                 (MAX_INITIAL_TIME_S)"
            }
        }
    }
}

/// `key rule`, e.g. "timing.max_latency_s must be finite, >= 0 and at most ...".
impl core::fmt::Display for ConfigField {
    fn fmt(&self, formatter: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(formatter, "{} {}", self.key(), self.rule())
    }
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

/// `invalid configuration: ` and the field with its rule, or the nav-core error.
impl core::fmt::Display for FswError {
    fn fmt(&self, formatter: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            FswError::InvalidConfiguration(field) => {
                write!(formatter, "invalid configuration: {field}")
            }
            FswError::Navigation(error) => write!(formatter, "navigation error: {error}"),
        }
    }
}

impl core::error::Error for FswError {}

impl From<NavError> for FswError {
    fn from(error: NavError) -> Self {
        FswError::Navigation(error)
    }
}
