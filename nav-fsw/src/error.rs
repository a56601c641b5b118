//! The one error type of nav-fsw.

use nav_core::NavError;

use crate::config::Param;

/// What failed a configuration's validation, naming the key (never a bare "invalid
/// configuration"): a parameter outside its declared range (the parameter table,
/// [`Param`]), two parameters that go together with one of them off, or a rule between
/// several values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ConfigField {
    /// The parameter is outside its range ([`Param::range`]).
    Parameter(Param),
    /// The first parameter is on (not 0) and the second, which must go with it, is 0
    /// ([`crate::config::COMPANIONS`]).
    Companion(Param, Param),
    /// `launch_site`: the Earth axis is not a unit vector within 1e-4 rad of ECEF `z`.
    LaunchSite,
    /// `sensor_frames`: the GCRF → launch-inertial rotation is not a unit quaternion, or the
    /// epoch's seconds of week reach the next week.
    SensorFrames,
    /// `star.mounting_wxyz` is not a unit quaternion.
    StarMounting,
    /// `star.second_head`: its mounting is not a unit quaternion.
    StarSecondHead,
    /// `timing.max_latency_s` reaches beyond the navigation history at `imu.period_s`.
    MaxLatency,
    /// `timing.future_tolerance_s` is not below `imu.period_s`.
    FutureTolerance,
    /// `gravity.field`: the order is above the degree.
    Gravity,
    /// `calibration.motion_observability` names a navigation block.
    CalibrationObservabilityTable,
    /// The initial navigation state (non-finite, or attitude not a unit quaternion).
    InitialNavigation,
}

impl ConfigField {
    /// The key in [`crate::config::FswConfig`], e.g. `timing.max_latency_s` (for a companion,
    /// the parameter that is off).
    pub const fn key(self) -> &'static str {
        match self {
            ConfigField::Parameter(param) | ConfigField::Companion(_, param) => param.path(),
            ConfigField::LaunchSite => "launch_site.earth_axis_ecef",
            ConfigField::SensorFrames => "sensor_frames",
            ConfigField::StarMounting => "star.mounting_wxyz",
            ConfigField::StarSecondHead => "star.second_head.mounting_wxyz",
            ConfigField::MaxLatency => "timing.max_latency_s",
            ConfigField::FutureTolerance => "timing.future_tolerance_s",
            ConfigField::Gravity => "gravity.field.order",
            ConfigField::CalibrationObservabilityTable => "calibration.motion_observability",
            ConfigField::InitialNavigation => "initial navigation state",
        }
    }

    /// The rule of a field that is not one parameter's range, as a phrase that follows the
    /// key ("must be ..."); `""` for [`ConfigField::Parameter`] and
    /// [`ConfigField::Companion`], whose Display gives the range and unit.
    pub const fn rule(self) -> &'static str {
        match self {
            ConfigField::Parameter(_) | ConfigField::Companion(..) => "",
            ConfigField::LaunchSite => {
                "must be a unit vector (norm within 1e-9 of 1) within 1e-4 rad of ECEF z"
            }
            ConfigField::SensorFrames => {
                "must have a unit GCRF-to-launch-inertial quaternion (norm within 1e-9 of 1) and \
                 seconds of week in [0, 604800) s"
            }
            ConfigField::StarMounting | ConfigField::StarSecondHead => {
                "must be a unit quaternion (norm within 1e-9 of 1)"
            }
            ConfigField::MaxLatency => {
                "must be at most (HISTORY_CAPACITY - 1) = 63 IMU periods (126 ms at 500 Hz): \
                 the navigation history holds no older snapshot"
            }
            ConfigField::FutureTolerance => "must be below one IMU period (imu.period_s)",
            ConfigField::Gravity => "must be at most gravity.field.degree",
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

/// `key must be RANGE UNIT (why)` for a parameter, `key must be on ... when other is on` for a
/// companion, `key rule` otherwise; e.g. "gnss.noise_m must be in [1e-6, 100000] m (...)".
impl core::fmt::Display for ConfigField {
    fn fmt(&self, formatter: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            ConfigField::Parameter(param) => {
                write!(formatter, "{} must be ", param.path())?;
                write_range(formatter, param)?;
                write!(formatter, " ({})", param.why())
            }
            ConfigField::Companion(on, off) => {
                write!(formatter, "{} must be ", off.path())?;
                write_range(formatter, off)?;
                write!(formatter, " and not 0 while {} is on", on.path())
            }
            _ => write!(formatter, "{} {}", self.key(), self.rule()),
        }
    }
}

/// `in RANGE UNIT`, or `one of A, B` for a choice.
fn write_range(formatter: &mut core::fmt::Formatter<'_>, param: Param) -> core::fmt::Result {
    let range = param.range();
    if !range.choices.is_empty() {
        return write!(formatter, "one of {range}");
    }
    if range.zero_is_off {
        formatter.write_str("0 (off) or ")?;
    }
    write!(formatter, "in {}", crate::config::Interval(range))?;
    match param.unit() {
        "" => Ok(()),
        unit => write!(formatter, " {unit}"),
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
