//! The checks of the star sensor's optional truth terms: per-axis noise, the slowly varying
//! Gauss–Markov error and the periodic error (`[star_sensor]`).

use super::{Checker, ScenarioError};
use crate::scenario::{number, StarSensorSettings};

impl Checker<'_> {
    /// The per-axis noise (both keys or neither, each 0 or a 1σ, `noise_arcsec` equal to the
    /// larger), the slow error (each 1σ 0 or in range, τ > 0 when on) and the periodic error
    /// (each amplitude 0 or in range, period > 0 when on, phase finite).
    pub(super) fn star_sensor_truth(&self, star: &StarSensorSettings) -> Result<(), ScenarioError> {
        self.star_per_axis_noise(star)?;
        for (axis, sigma) in ["x", "y", "z"].iter().zip(star.slow_error_sigma_arcsec) {
            self.sigma(
                &format!("star_sensor.slow_error_sigma_arcsec ({axis})"),
                sigma,
                true,
            )?;
        }
        let key = "star_sensor.slow_error_correlation_time_s";
        if star.has_slow_error() {
            self.positive(key, star.slow_error_correlation_time_s)?;
        } else {
            self.non_negative(key, star.slow_error_correlation_time_s)?;
        }
        for (axis, amplitude) in ["x", "y", "z"]
            .iter()
            .zip(star.periodic_error_amplitude_arcsec)
        {
            let key = format!("star_sensor.periodic_error_amplitude_arcsec ({axis})");
            self.sigma(&key, amplitude, true)?;
        }
        let key = "star_sensor.periodic_error_period_s";
        if star.has_periodic_error() {
            self.positive(key, star.periodic_error_period_s)?;
        } else {
            self.non_negative(key, star.periodic_error_period_s)?;
        }
        self.finite(
            "star_sensor.periodic_error_phase_deg",
            star.periodic_error_phase_deg,
        )
    }

    /// `cross_boresight_noise_arcsec` and `roll_noise_arcsec`: both or neither, each 0 or a
    /// 1σ, and then `noise_arcsec` their larger value (the flight software is told the
    /// per-axis values; the single-noise studies take `noise_arcsec`).
    fn star_per_axis_noise(&self, star: &StarSensorSettings) -> Result<(), ScenarioError> {
        let (cross_key, roll_key) = (
            "star_sensor.cross_boresight_noise_arcsec",
            "star_sensor.roll_noise_arcsec",
        );
        let (cross, roll) = match (star.cross_boresight_noise_arcsec, star.roll_noise_arcsec) {
            (None, None) => return Ok(()),
            (Some(cross), Some(roll)) => (cross, roll),
            (Some(_), None) => {
                return Err(self.fail(roll_key, &format!("must be given with {cross_key}")))
            }
            (None, Some(_)) => {
                return Err(self.fail(cross_key, &format!("must be given with {roll_key}")))
            }
        };
        self.sigma(cross_key, cross, true)?;
        self.sigma(roll_key, roll, true)?;
        let largest = cross.max(roll);
        // Exactly equal (the dispersion scales both alike, which keeps them so).
        if star.noise_arcsec.partial_cmp(&largest) == Some(std::cmp::Ordering::Equal) {
            return Ok(());
        }
        Err(self.fail(
            "star_sensor.noise_arcsec",
            &format!(
                "= {} conflicts with the per-axis noise: with {cross_key} and {roll_key} given, \
                 noise_arcsec (the single-noise studies' 1σ) must equal the larger of them, {}",
                number(star.noise_arcsec),
                number(largest)
            ),
        ))
    }
}
