//! The `Debug` renderings of the scenario, of the IMU triads' settings and of the filter's:
//! the optional tables, the optional misalignment, g-sensitivity and bias-instability terms
//! and an empty command schedule are left out, so a scenario without them renders, and
//! hashes (the campaign's `scenario_hash`), as it did before they existed.

use super::{AccelerometerErrors, FilterSettings, GyroErrors, Scenario};

/// Adds the optional IMU error terms to a triad's `Debug` rendering, each only when
/// non-zero (the misalignment matrix, the g-sensitivity, the bias instability's pair).
fn debug_optional_terms(
    debug: &mut std::fmt::DebugStruct<'_, '_>,
    misalignment_rad: &[[f64; 3]; 3],
    g_sensitivity: Option<(&str, &[f64; 3])>,
    (sigma_key, sigma): (&str, f64),
    correlation_time_s: f64,
) {
    if misalignment_rad.iter().flatten().any(|term| *term != 0.0) {
        debug.field("misalignment_rad", misalignment_rad);
    }
    if let Some((key, values)) = g_sensitivity {
        if values.iter().any(|value| *value != 0.0) {
            debug.field(key, values);
        }
    }
    if sigma != 0.0 || correlation_time_s != 0.0 {
        debug
            .field(sigma_key, &sigma)
            .field("bias_instability_correlation_time_s", &correlation_time_s);
    }
}

impl std::fmt::Debug for GyroErrors {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut debug = formatter.debug_struct("GyroErrors");
        debug
            .field(
                "rate_noise_density_deg_per_h_per_sqrt_hz",
                &self.rate_noise_density_deg_per_h_per_sqrt_hz,
            )
            .field("bias_rad_per_s", &self.bias_rad_per_s)
            .field("scale_factor", &self.scale_factor)
            .field(
                "bias_random_walk_rad_per_s_per_sqrt_s",
                &self.bias_random_walk_rad_per_s_per_sqrt_s,
            )
            .field("quantum_rad", &self.quantum_rad);
        debug_optional_terms(
            &mut debug,
            &self.misalignment_rad,
            Some((
                "g_sensitivity_rad_s_per_mps2",
                &self.g_sensitivity_rad_s_per_mps2,
            )),
            (
                "bias_instability_sigma_rad_per_s",
                self.bias_instability_sigma_rad_per_s,
            ),
            self.bias_instability_correlation_time_s,
        );
        debug.finish()
    }
}

impl std::fmt::Debug for AccelerometerErrors {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut debug = formatter.debug_struct("AccelerometerErrors");
        debug
            .field("noise_per_sample_mps2", &self.noise_per_sample_mps2)
            .field("bias_mps2", &self.bias_mps2)
            .field("scale_factor", &self.scale_factor)
            .field(
                "bias_random_walk_mps2_per_sqrt_s",
                &self.bias_random_walk_mps2_per_sqrt_s,
            )
            .field("quantum_mps", &self.quantum_mps);
        debug_optional_terms(
            &mut debug,
            &self.misalignment_rad,
            None,
            (
                "bias_instability_sigma_mps2",
                self.bias_instability_sigma_mps2,
            ),
            self.bias_instability_correlation_time_s,
        );
        debug.finish()
    }
}

impl AccelerometerErrors {
    /// 1σ of the delta-velocity noise per increment of length `interval_s` (m/s): the
    /// per-sample specific-force σ held over the sample, `σ_Δv = σ_f · T`.
    pub fn delta_velocity_noise_sigma_mps(&self, interval_s: f64) -> f64 {
        self.noise_per_sample_mps2 * interval_s
    }

    /// The same noise as a white specific-force density `σ_f · √T` ((m/s²)/√Hz) for a sampling
    /// interval `interval_s`, the form a continuous-time filter model uses.
    pub fn noise_density_mps2_per_sqrt_hz(&self, interval_s: f64) -> f64 {
        self.noise_per_sample_mps2 * interval_s.sqrt()
    }
}

impl std::fmt::Debug for FilterSettings {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut debug = formatter.debug_struct("FilterSettings");
        debug
            .field("mode", &self.mode)
            .field("discretisation_order", &self.discretisation_order)
            .field("initial_sigma", &self.initial_sigma)
            .field("nis_gate", &self.nis_gate)
            .field("gnss_correlated_sigma_m", &self.gnss_correlated_sigma_m)
            .field("gnss_correlation_time_s", &self.gnss_correlation_time_s)
            .field("gnss_noise_m", &self.gnss_noise_m);
        if let Some(noise_arcsec) = self.star_noise_arcsec {
            debug.field("star_noise_arcsec", &noise_arcsec);
        }
        if self.bias_instability.is_on() {
            debug.field("bias_instability", &self.bias_instability);
        }
        if self.imu_errors.is_on() {
            debug.field("imu_errors", &self.imu_errors);
        }
        if self.gravity.is_on() {
            debug.field("gravity", &self.gravity);
        }
        if self.star_slow_error.is_on() {
            debug.field("star_slow_error", &self.star_slow_error);
        }
        if self.star_aberration_correction {
            debug.field(
                "star_aberration_correction",
                &self.star_aberration_correction,
            );
        }
        if !self.star_noise_matching {
            debug.field("star_noise_matching", &self.star_noise_matching);
        }
        if !self.star_second_head {
            debug.field("star_second_head", &self.star_second_head);
        }
        if self.star_pairs_before_hand_over != super::DEFAULT_STAR_PAIRS_BEFORE_HAND_OVER {
            debug.field(
                "star_pairs_before_hand_over",
                &self.star_pairs_before_hand_over,
            );
        }
        debug.finish()
    }
}

impl std::fmt::Debug for Scenario {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut debug = formatter.debug_struct("Scenario");
        debug
            .field("simulation", &self.simulation)
            .field("launch_site", &self.launch_site)
            .field("initial_orbit", &self.initial_orbit)
            .field("initial_attitude", &self.initial_attitude)
            .field("imu", &self.imu)
            .field("gyro", &self.gyro)
            .field("accelerometer", &self.accelerometer)
            .field("star_sensor", &self.star_sensor)
            .field("gnss", &self.gnss)
            .field("manoeuvres", &self.manoeuvres)
            .field("filter", &self.filter);
        if let Some(dispersion) = &self.dispersion {
            debug.field("dispersion", dispersion);
        }
        if let Some(gravity) = &self.gravity {
            debug.field("gravity", gravity);
        }
        if !self.commands.is_empty() {
            debug.field("commands", &self.commands);
        }
        debug.finish()
    }
}
