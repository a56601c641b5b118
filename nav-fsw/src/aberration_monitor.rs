//! A matched test for a velocity aberration the star tracker leaves in and the flight
//! software is not told of (`star.aberration_correction` off): a single head's aberration
//! hides in the attitude while the vehicle holds its attitude, but not while it turns, when the
//! aberration's rotation in sensor axes changes faster than the gyro lets the attitude wander.
//!
//! **Signature.** A tracker that leaves the aberration in reports `q_is ⊗ exp(a_s)`,
//! `a_s = β_s × z` (nav-core `aberration`, with the navigation velocity and the measured
//! attitude), so the star residual (half the rotation angle, sensor axes) carries `a_s / 2`
//! less what the filter has absorbed into the attitude and the installation.
//!
//! **Statistic** (the score of a linear-Gaussian model for an offset along a known signal;
//! Kay, *Fundamentals of Statistical Signal Processing, Vol. II: Detection Theory*, 1998,
//! §7.3, the generalised matched filter). With the innovation `ν_k ~ N(0, S_k)` of a
//! consistent filter and the signature `s_k = a_s,k / 2`, `u_k = s_kᵀ S_k⁻¹ ν_k` has variance
//! `w_k = s_kᵀ S_k⁻¹ s_k`, and the innovations are white, so the fading sums
//! `U = Σ λ^(n−k) u_k` and `W = Σ λ^(2(n−k)) w_k` (`λ = 1 − 1/N`, the consistency monitor's
//! `N`) give `z = U / √W ~ N(0, 1)` at every measurement. An uncorrected aberration holds `z`
//! at about `Σ λ^(n−k) w_k / √W`, growing with every measurement taken while the vehicle turns.
//! An episode begins when `|z|` exceeds [`ABERRATION_BOUND_SIGMA`] and ends below half of it.
//!
//! The test takes accepted measurements only (a rejected one is an outlier, not the model's)
//! after the aid's acquisition; a non-finite or singular input enters nothing.

use nalgebra::{Matrix3, Vector3};

/// The bound on `|z|` in its own σ: 5σ, for a false alarm per independent stretch of `N`
/// measurements of 6e-7 (a few hundred stretches a flight).
pub const ABERRATION_BOUND_SIGMA: f64 = 5.0;

/// The fading sums of the aberration test and whether an episode is under way.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AberrationMonitor {
    /// `U = Σ λ^(n−k) sᵀ S⁻¹ ν`.
    score: f64,
    /// `W = Σ λ^(2(n−k)) sᵀ S⁻¹ s`, the variance of `U` under the model.
    score_variance: f64,
    in_episode: bool,
}

impl AberrationMonitor {
    /// Enters one accepted star innovation `innovation` with covariance `covariance` and the
    /// aberration rotation `aberration_rad` (`a_s`, sensor axes) over about `n` measurements;
    /// true when an episode has just begun. A non-finite input or a covariance that cannot
    /// be inverted enters nothing.
    ///
    /// # Examples
    /// ```
    /// use nalgebra::{Matrix3, Vector3};
    /// use nav_fsw::aberration_monitor::AberrationMonitor;
    /// let mut monitor = AberrationMonitor::default();
    /// let covariance = Matrix3::identity() * 1e-10;
    /// // A 5″ aberration turning with the vehicle, left whole in the innovations.
    /// let began = (0..200)
    ///     .filter(|k| {
    ///         let angle = f64::from(*k) * 0.3;
    ///         let a = Vector3::new(angle.cos(), angle.sin(), 0.0) * 2.4e-5;
    ///         monitor.observe(&(a / 2.0), &covariance, &a, 256)
    ///     })
    ///     .count();
    /// assert_eq!(began, 1);
    /// assert!(monitor.statistic_sigma() > 5.0);
    /// ```
    pub fn observe(
        &mut self,
        innovation: &Vector3<f64>,
        covariance: &Matrix3<f64>,
        aberration_rad: &Vector3<f64>,
        n: u32,
    ) -> bool {
        let signature = aberration_rad * 0.5;
        let finite = innovation
            .iter()
            .chain(signature.iter())
            .all(|v| v.is_finite());
        let Some(weighted) = covariance.cholesky().map(|c| c.solve(&signature)) else {
            return false;
        };
        let (score, variance) = (weighted.dot(innovation), weighted.dot(&signature));
        if !(finite && score.is_finite() && variance.is_finite() && variance >= 0.0) {
            return false;
        }
        let fading = 1.0 - 1.0 / f64::from(n.max(1));
        self.score = fading * self.score + score;
        self.score_variance = fading * fading * self.score_variance + variance;
        let z = self.statistic_sigma();
        let began = z > ABERRATION_BOUND_SIGMA && !self.in_episode;
        if began {
            self.in_episode = true;
        } else if z < 0.5 * ABERRATION_BOUND_SIGMA {
            self.in_episode = false;
        }
        began
    }

    /// `|z|`, the test statistic in its own σ (0 before any signature was entered).
    pub fn statistic_sigma(&self) -> f64 {
        if self.score_variance > 0.0 {
            (self.score / nav_core::float::sqrt(self.score_variance)).abs()
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_random::normal_source;

    const COVARIANCE_SCALE: f64 = 1e-10;

    /// A signature turning with the vehicle (5″ across the boresight).
    fn turning(k: u32) -> Vector3<f64> {
        let angle = f64::from(k) * 0.3;
        Vector3::new(angle.cos(), angle.sin(), 0.0) * 2.4e-5
    }

    #[test]
    fn white_innovations_raise_nothing_and_z_has_unit_variance() {
        let mut normal = normal_source(20_170_415);
        let covariance = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 49.0)) * COVARIANCE_SCALE;
        let sigma = covariance.map(f64::sqrt).diagonal();
        let mut monitor = AberrationMonitor::default();
        let (mut sum_squares, mut count) = (0.0, 0.0);
        for k in 0..20_000 {
            let innovation = sigma.map(|s| s * normal());
            let began = monitor.observe(&innovation, &covariance, &turning(k), 256);
            assert!(!began, "measurement {k}: {}σ", monitor.statistic_sigma());
            if k % 256 == 255 {
                sum_squares += monitor.statistic_sigma().powi(2);
                count += 1.0;
            }
        }
        let variance = sum_squares / count;
        assert!((variance - 1.0).abs() < 0.4, "{variance}");
    }

    #[test]
    fn a_constant_offset_or_an_absorbed_signature_raises_nothing() {
        let covariance = Matrix3::identity() * COVARIANCE_SCALE;
        let mut monitor = AberrationMonitor::default();
        // An offset the turning signature averages out (a step is the fault logic's).
        for k in 0..2_000 {
            let offset = Vector3::new(3e-6, 0.0, 0.0);
            assert!(!monitor.observe(&offset, &covariance, &turning(k), 256));
        }
        assert!(
            monitor.statistic_sigma() < 2.0,
            "{}",
            monitor.statistic_sigma()
        );
    }

    #[test]
    fn bad_input_enters_nothing() {
        let mut monitor = AberrationMonitor::default();
        let good = Matrix3::identity() * COVARIANCE_SCALE;
        let signature = turning(1);
        assert!(!monitor.observe(&signature, &Matrix3::zeros(), &signature, 256));
        assert!(!monitor.observe(&Vector3::new(f64::NAN, 0.0, 0.0), &good, &signature, 256));
        assert!(!monitor.observe(&signature, &good, &Vector3::new(f64::INFINITY, 0.0, 0.0), 0));
        assert_eq!(monitor, AberrationMonitor::default());
    }
}
