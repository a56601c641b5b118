//! The flight software's allowance for the gravity field its model omits
//! (`[filter.gravity]`), as the covariance analysis applies it: the white velocity noise the
//! flight adds to the accelerometer's, `√(σ_a² + q·s)`, with the share
//! `s = min(1, (rms / √3 σ)²)` of the omitted field's RMS at the vehicle's radius (nav-fsw
//! `scheduler::gravity::process_noise_at`, docs/gravity.md). The flight takes the RMS from
//! its own evaluation at the navigation solution every 0.1 s; the analysis takes the same
//! evaluation at the truth's radius, once per 100 m of radius (`gravity_omission`'s radius
//! bins, across which the RMS changes by under 0.1 %).

use nalgebra::Vector3;
use nav_core::error_model::ProcessNoise;

use super::DesignError;
use crate::scenario::Scenario;
use crate::setup::launch::Launch;
use crate::studies::gravity_omission::{CheckSigmaByRadius, FlightGravityModel};

/// The allowance of one flight and its flight model's omitted RMS by radius.
pub(super) struct GravityAllowance {
    base: ProcessNoise,
    psd_m2_per_s3: f64,
    sigma_mps2: f64,
    check: CheckSigmaByRadius,
}

impl GravityAllowance {
    /// The allowance of `scenario`'s flight software on top of `base`; `None` without one.
    pub(super) fn new(scenario: &Scenario, base: ProcessNoise) -> Option<Self> {
        let gravity = &scenario.filter.gravity;
        (gravity.omitted_field_psd_m2_per_s3 > 0.0).then(|| Self {
            base,
            psd_m2_per_s3: gravity.omitted_field_psd_m2_per_s3,
            sigma_mps2: gravity.omitted_field_sigma_mps2,
            check: CheckSigmaByRadius::new(FlightGravityModel::new(
                usize::from(gravity.degree),
                usize::from(gravity.order),
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
        // The flight's ratio rms / (√3 σ) with the per-axis figure: rms = √3 · per axis. A
        // figure that is not a number counts as above, as in flight.
        let ratio = per_axis_mps2 / self.sigma_mps2;
        let share = if ratio < 1.0 { ratio * ratio } else { 1.0 };
        let density = self.base.accel_noise_density_mps2_per_sqrt_hz;
        Ok(ProcessNoise {
            accel_noise_density_mps2_per_sqrt_hz: (density * density + self.psd_m2_per_s3 * share)
                .sqrt(),
            ..self.base
        })
    }
}
