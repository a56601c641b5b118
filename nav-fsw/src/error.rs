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
    /// `measurement.max_latency_s`
    MaxLatency,
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
