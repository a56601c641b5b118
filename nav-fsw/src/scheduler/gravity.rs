//! The gravity field beyond the strapdown's point mass + `J2`: a share of its evaluation each
//! frame (nav-core `gravity::harmonics`), its held value handed to the strapdown, the
//! allowance for what it omits in the process noise, and the check of that allowance.

use super::*;
use crate::health::ConfigurationWarnings;

/// The process noise before the field's first evaluation: the whole allowance.
pub(super) fn process_noise(config: &FswConfig) -> ProcessNoise {
    config
        .gravity
        .process_noise_at(&config.process_noise, f64::INFINITY)
}

impl NavigationComputer {
    /// This frame's share of the field's evaluation at the navigation solution (called in
    /// frames that fuse no measurement, so a share never adds to an update frame); when an
    /// evaluation completes, its value goes to the strapdown (a model beyond `J2` only) and
    /// its omitted RMS (of the magnitude) is checked against the allowance's `√3 σ` (above it
    /// begins an episode of `gravity_allowance_short`) and sets the allowance's share of the
    /// process noise ([`crate::config::GravityConfig::process_noise_at`]). A refused
    /// evaluation is counted and the held value kept.
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
        let omitted_rms_mps2 = field.omitted_rms_mps2();
        if !field.model().is_j2_only() {
            navigation
                .strapdown
                .set_field_beyond_j2(Some(*field.acceleration_launch_mps2()));
        }
        // The omitted RMS is of the vector's magnitude, as is the allowance's cover. Without
        // an allowance the check only restates the configuration: a start-up warning
        // (`ConfigurationWarnings`), not a flight event.
        let allowance = !ConfigurationWarnings::of(&self.config).gravity_without_allowance;
        let short = allowance && omitted_rms_mps2 > self.config.gravity.covered_rms_mps2();
        if short && !navigation.gravity_allowance_short {
            count(&mut self.health.counters.gravity_allowance_short);
        }
        navigation.gravity_allowance_short = short;
        if self.config.gravity.omitted_field_psd_m2_per_s3 > 0.0 {
            self.covariance.process_noise = self
                .config
                .gravity
                .process_noise_at(&self.config.process_noise, omitted_rms_mps2);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor_frames::SensorFrames;

    /// The allowance's share follows the omitted field's power up to `√3 σ` and stays whole
    /// above it (or for an RMS that is not a number); without an allowance the configured
    /// noise, bit for bit, at any RMS.
    #[test]
    fn the_allowance_scales_with_the_omitted_fields_power() {
        let process_noise_at = |config: &FswConfig, rms: f64| {
            config.gravity.process_noise_at(&config.process_noise, rms)
        };
        let mut config =
            FswConfig::paper_defaults(super::super::tests::site(), SensorFrames::ALIGNED);
        let configured = config.process_noise;
        for rms in [0.0, 1e-5, f64::INFINITY, f64::NAN] {
            assert_eq!(process_noise_at(&config, rms), configured);
        }
        let (sigma, q) = (2.0e-5, 1.2e-8);
        config.gravity.omitted_field_sigma_mps2 = sigma;
        config.gravity.omitted_field_psd_m2_per_s3 = q;
        let density = configured.accel_noise_density_mps2_per_sqrt_hz;
        let with_share =
            |rms: f64| process_noise_at(&config, rms).accel_noise_density_mps2_per_sqrt_hz;
        let covered = 3.0_f64.sqrt() * sigma;
        for (rms, share) in [
            (0.0, 0.0),
            (0.5 * covered, 0.25),
            (0.9 * covered, 0.81),
            (covered, 1.0),
            (2.0 * covered, 1.0),
            (f64::INFINITY, 1.0),
            (f64::NAN, 1.0),
        ] {
            let expected = (density * density + q * share).sqrt();
            let got = with_share(rms);
            assert!(
                (got - expected).abs() <= 1e-15 * expected,
                "{rms}: {got} vs {expected}"
            );
        }
        // Before the first evaluation: the whole allowance, as the configured density grown
        // by q.
        assert_eq!(
            process_noise(&config)
                .accel_noise_density_mps2_per_sqrt_hz
                .to_bits(),
            (density * density + q).sqrt().to_bits()
        );
        // Only the accelerometer's density changes.
        let scaled = process_noise_at(&config, 0.5 * covered);
        assert_eq!(
            scaled.gyro_noise_density_rad_s_per_sqrt_hz.to_bits(),
            configured.gyro_noise_density_rad_s_per_sqrt_hz.to_bits()
        );
    }

    /// Without the feature `gravity-field` the computer carries no table of the field: the
    /// paper's configuration flies with nothing to evaluate, and a field beyond `J2` is
    /// refused at start, naming the parameter (nav-core's stand-in refuses it too).
    #[cfg(not(feature = "gravity-field"))]
    #[test]
    fn without_the_gravity_field_the_computer_flies_j2_alone() {
        use nav_core::gravity::harmonics::{FieldModel, FieldRemainder};
        assert!(core::mem::size_of::<FieldRemainder>() <= core::mem::size_of::<FieldModel>());
        let mut field = FieldRemainder::EMPTY;
        let beyond = FieldModel {
            degree: 4,
            order: 4,
            terms_per_frame: 4,
        };
        assert_eq!(
            field.configure(beyond),
            Err(nav_core::NavError::InvalidConfiguration)
        );
        assert_eq!(field, FieldRemainder::EMPTY);
        let computer = super::super::tests::computer();
        let navigation = &computer.navigation;
        assert!(!navigation.gravity_field.is_due(f64::MAX));
        assert_eq!(navigation.gravity_field.model(), &FieldModel::J2_ONLY);
        let mut config =
            FswConfig::paper_defaults(super::super::tests::site(), SensorFrames::ALIGNED);
        config.gravity.field = beyond;
        let refused = NavigationComputer::new(config, super::super::tests::initial_state());
        assert_eq!(
            refused.err(),
            Some(FswError::InvalidConfiguration(ConfigField::Parameter(
                crate::config::Param::GravityDegree
            )))
        );
    }
}
