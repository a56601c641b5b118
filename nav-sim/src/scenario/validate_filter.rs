//! The checks of the filter's systematic IMU error states (`[filter.imu_errors]`).

use super::{Checker, ScenarioError};
use crate::scenario::FilterSettings;

impl Checker<'_> {
    /// `[filter.imu_errors]`: off (every 1σ 0) or every 1σ in [`SIGMA_RANGE`], and then no
    /// correlated GNSS error states (the flight software does not combine the two yet).
    pub(super) fn filter_imu_errors(&self, filter: &FilterSettings) -> Result<(), ScenarioError> {
        let imu_errors = &filter.imu_errors;
        let on = imu_errors.is_on();
        for (name, value) in imu_errors.values() {
            self.sigma(&format!("filter.imu_errors.{name}"), value, !on)?;
        }
        if on && filter.gnss_correlated_sigma_m > 0.0 {
            return Err(self.fail(
                "filter.imu_errors",
                "cannot be on with filter.gnss_correlated_sigma_m > 0 (the flight software \
                 does not combine the two state blocks yet)",
            ));
        }
        Ok(())
    }
}
