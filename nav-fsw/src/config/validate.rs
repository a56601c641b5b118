//! [`FswConfig::validate`]: every parameter against its declared range, the parameters that go
//! together, then the few rules between several values (a unit quaternion, a latency within
//! the history at the IMU period, a gravity order within its degree).

use super::{is_unit_quaternion, max_latency_limit_s, FswConfig, Param};
use crate::error::{ConfigField, FswError};

impl FswConfig {
    /// Checks every value; the first bad one is reported by name: first each parameter of
    /// the table in table order ([`ConfigField::Parameter`]), then the pairs that go together
    /// ([`ConfigField::Companion`]), then the rules between values.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] naming the key.
    pub fn validate(&self) -> Result<(), FswError> {
        for param in Param::ALL {
            if param.applies(self) {
                param.check(param.value(self))?;
            }
        }
        self.validate_companions()?;
        self.validate_rules()
    }

    /// Every pair of [`COMPANIONS`]: the second on (not 0) whenever the first is.
    fn validate_companions(&self) -> Result<(), FswError> {
        let broken = COMPANIONS
            .iter()
            .find(|(on, off)| on.value(self) != 0.0 && off.value(self) == 0.0);
        broken.map_or(Ok(()), |(on, off)| {
            Err(FswError::InvalidConfiguration(ConfigField::Companion(
                *on, *off,
            )))
        })
    }

    /// The rules between several values.
    fn validate_rules(&self) -> Result<(), FswError> {
        let invalid = |field| Err(FswError::InvalidConfiguration(field));
        if self.launch_site.validate().is_err() {
            return invalid(ConfigField::LaunchSite);
        }
        self.sensor_frames.validate()?;
        if !is_unit_quaternion(&self.star.mounting_wxyz) {
            return invalid(ConfigField::StarMounting);
        }
        if !self
            .star
            .second_head
            .is_none_or(|head| is_unit_quaternion(&head.mounting_wxyz))
        {
            return invalid(ConfigField::StarSecondHead);
        }
        if self.timing.max_latency_s > max_latency_limit_s(self.imu.period_s) {
            return invalid(ConfigField::MaxLatency);
        }
        if self.timing.future_tolerance_s >= self.imu.period_s {
            return invalid(ConfigField::FutureTolerance);
        }
        if self.gravity.field.order > self.gravity.field.degree {
            return invalid(ConfigField::Gravity);
        }
        if !self.calibration.motion_observability.is_valid() {
            return invalid(ConfigField::CalibrationObservabilityTable);
        }
        Ok(())
    }
}

/// Pairs `(a, b)`: when `a` is on (not 0), `b` must be on too. A correlated error needs its
/// correlation time; the three IMU error 1σ are all on or all off (a cycle); the gravity
/// allowance and the field it is for go together.
pub const COMPANIONS: [(Param, Param); 9] = [
    (Param::GnssCorrelatedSigma, Param::GnssCorrelationTime),
    (Param::StarSlowErrorX, Param::StarSlowErrorCorrelationTime),
    (Param::StarSlowErrorY, Param::StarSlowErrorCorrelationTime),
    (Param::StarSlowErrorZ, Param::StarSlowErrorCorrelationTime),
    (Param::GyroMisalignmentSigma, Param::AccelMisalignmentSigma),
    (Param::AccelMisalignmentSigma, Param::GyroGSensitivitySigma),
    (Param::GyroGSensitivitySigma, Param::GyroMisalignmentSigma),
    (Param::OmittedFieldSigma, Param::OmittedFieldPsd),
    (Param::OmittedFieldPsd, Param::OmittedFieldSigma),
];

impl Param {
    /// Checks `value` against the parameter's range.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] ([`ConfigField::Parameter`]) outside the range.
    pub fn check(self, value: f64) -> Result<(), FswError> {
        if self.range().contains(value) {
            Ok(())
        } else {
            Err(FswError::InvalidConfiguration(ConfigField::Parameter(self)))
        }
    }
}
