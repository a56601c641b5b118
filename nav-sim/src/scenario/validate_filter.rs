//! The checks of the filter's systematic IMU error states (`[filter.imu_errors]`) and of the
//! star tracker's noise and slow error it is told (`[filter] star_noise_arcsec`,
//! `[filter.star_slow_error]`).

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

    /// `[filter] star_noise_arcsec` in `SIGMA_RANGE` when given; `[filter.star_slow_error]`:
    /// each 1σ 0 or in `SIGMA_RANGE`, the correlation time > 0 when any 1σ is, else ≥ 0.
    pub(super) fn filter_star(&self, filter: &FilterSettings) -> Result<(), ScenarioError> {
        if let Some(noise_arcsec) = filter.star_noise_arcsec {
            self.sigma("filter.star_noise_arcsec", noise_arcsec, false)?;
        }
        let slow = &filter.star_slow_error;
        for sigma in slow.sigma_arcsec {
            self.sigma("filter.star_slow_error.sigma_arcsec", sigma, true)?;
        }
        let key = "filter.star_slow_error.correlation_time_s";
        if slow.sigma_arcsec.iter().any(|sigma| *sigma > 0.0) {
            self.positive(key, slow.correlation_time_s)
        } else {
            self.non_negative(key, slow.correlation_time_s)
        }
    }
}
