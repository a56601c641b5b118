//! The checks of the filter's systematic IMU error states (`[filter.imu_errors]`).

use super::{Checker, ScenarioError};
use crate::scenario::FilterSettings;

impl Checker<'_> {
    /// `[filter.imu_errors]`: off (every 1σ 0) or every 1σ in `SIGMA_RANGE`.
    pub(super) fn filter_imu_errors(&self, filter: &FilterSettings) -> Result<(), ScenarioError> {
        let imu_errors = &filter.imu_errors;
        let on = imu_errors.is_on();
        for (name, value) in imu_errors.values() {
            self.sigma(&format!("filter.imu_errors.{name}"), value, !on)?;
        }
        Ok(())
    }
}
