//! The gravity field beyond the strapdown's point mass + `J2`: a share of its evaluation each
//! frame (nav-core `gravity::harmonics`), its held value handed to the strapdown, the
//! allowance for what it omits in the process noise, and the check of that allowance.

use super::*;

/// `√3`: the RMS magnitude of a vector of three independent axes of unit 1σ.
const SQRT_3: f64 = 1.732_050_807_568_877_2;

/// `config.process_noise` with the gravity allowance `q` (m²/s³, [`GravityConfig`]) added
/// to the accelerometer density squared: in launch-inertial axes the accelerometer's white
/// noise enters the velocity as `C (σ_a² I) Cᵀ = σ_a² I`, so an isotropic white velocity noise
/// of density `q` is the same as an accelerometer density `√(σ_a² + q)`. Without an
/// allowance the configured noise, bit for bit.
///
/// [`GravityConfig`]: crate::config::GravityConfig
pub(super) fn process_noise(config: &FswConfig) -> ProcessNoise {
    let mut noise = config.process_noise;
    let allowance = config.gravity.omitted_field_psd_m2_per_s3;
    if allowance > 0.0 {
        let density = noise.accel_noise_density_mps2_per_sqrt_hz;
        noise.accel_noise_density_mps2_per_sqrt_hz =
            nav_core::float::sqrt(density * density + allowance);
    }
    noise
}

impl NavigationComputer {
    /// This frame's share of the field's evaluation at the navigation solution (called in
    /// frames that fuse no measurement, so a share never adds to an update frame); when an
    /// evaluation completes, its value goes to the strapdown (a model beyond `J2` only) and
    /// its omitted RMS (of the magnitude) is checked against the allowance's `√3 σ`: above it
    /// begins an episode of
    /// `gravity_allowance_short`. A refused evaluation is counted and the held value kept.
    #[inline(never)]
    pub(super) fn advance_gravity_field(&mut self) {
        let navigation = &mut self.navigation;
        let field = &mut navigation.gravity_field;
        let solution = &navigation.solution;
        if !field.is_due(solution.time_s) {
            return;
        }
        let before = field.evaluations();
        if field
            .advance(&self.launch_frame, solution.time_s, &solution.position_m)
            .is_err()
        {
            count(&mut self.health.counters.gravity_field_errors);
        }
        if field.evaluations() == before {
            return;
        }
        if !field.model().is_j2_only() {
            navigation
                .strapdown
                .set_field_beyond_j2(Some(*field.acceleration_launch_mps2()));
        }
        // The omitted RMS is of the vector's magnitude; an allowance of σ per axis covers a
        // magnitude RMS of √3 σ.
        let covered_rms = SQRT_3 * self.config.gravity.omitted_field_sigma_mps2;
        let short = field.omitted_rms_mps2() > covered_rms;
        if short && !navigation.gravity_allowance_short {
            count(&mut self.health.counters.gravity_allowance_short);
        }
        navigation.gravity_allowance_short = short;
    }
}
