//! The flight software's allowance for the gravity field its model omits
//! (`[filter.gravity]`), as the covariance analysis applies it: nav-fsw's own
//! [`GravityConfig::process_noise_at`], the allowance scaled with the omitted field's power at
//! the vehicle's radius (docs/guide/gravity.md). The flight takes the omitted RMS from its own
//! evaluation at the navigation solution every 0.1 s; the analysis takes the same evaluation
//! at the truth's radius, once per 100 m of radius (`gravity_omission`'s radius bins, across
//! which the RMS changes by under 0.1 %).

use nalgebra::Vector3;
use nav_core::error_model::ProcessNoise;
use nav_fsw::config::GravityConfig;

use super::DesignError;
use crate::scenario::Scenario;
use crate::setup::launch::Launch;
use crate::studies::gravity_omission::{CheckSigmaByRadius, FlightGravityModel};

/// The allowance of one flight and its flight model's omitted RMS by radius.
pub(super) struct GravityAllowance {
    base: ProcessNoise,
    gravity: GravityConfig,
    check: CheckSigmaByRadius,
}

impl GravityAllowance {
    /// The allowance of `scenario`'s flight software on top of `base`; `None` without one.
    pub(super) fn new(scenario: &Scenario, base: ProcessNoise) -> Option<Self> {
        let settings = &scenario.filter.gravity;
        (settings.omitted_field_psd_m2_per_s3 > 0.0).then(|| Self {
            base,
            gravity: settings.config(),
            check: CheckSigmaByRadius::new(FlightGravityModel::new(
                usize::from(settings.degree),
                usize::from(settings.order),
            )),
        })
    }

    /// The process noise at launch-inertial position `position_m` (m).
    ///
    /// # Errors
    /// [`DesignError::Sensor`] if the flight model's evaluation fails.
    pub(super) fn noise_at(
        &mut self,
        launch: &Launch,
        position_m: &Vector3<f64>,
    ) -> Result<ProcessNoise, DesignError> {
        let radius_m = launch.frame.geocentric_position_launch(position_m).norm();
        let per_axis_mps2 = self
            .check
            .at(launch, radius_m)
            .map_err(|error| DesignError::Sensor(error.to_string()))?;
        // The flight's figure is the RMS magnitude, √3 times the per-axis one.
        let omitted_rms_mps2 = per_axis_mps2 * 3.0_f64.sqrt();
        Ok(self.gravity.process_noise_at(&self.base, omitted_rms_mps2))
    }
}
