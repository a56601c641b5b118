//! A matched test for a velocity aberration the flight software handles wrongly: left in by
//! the tracker while the flight software is not told of it (`star.aberration_correction`
//! off), or, with the correction on, corrected twice (a tracker that corrects its own) or with
//! the wrong sign (a tracker whose correction adds it). A single head's aberration hides in
//! the attitude while the vehicle holds its attitude, but not while it turns, when the
//! aberration's rotation in sensor axes changes faster than the gyro lets the attitude wander.
//!
//! **Signature.** A tracker that leaves the aberration in reports `q_is ⊗ exp(a_s)`,
//! `a_s = β_s × z` (nav-core `aberration`, with the navigation velocity and the measured
//! attitude), so the star residual (half the rotation angle, sensor axes) carries `a_s / 2`
//! less what the filter has absorbed into the attitude and the installation. With the
//! correction on, a tracker that corrects its own leaves `−a_s / 2` (subtracted twice) and one
//! that adds it `+a_s / 2`, so the test is then two-sided.
//!
//! **Statistic** (the score of a linear-Gaussian model for an offset along a known signal;
//! Kay, *Fundamentals of Statistical Signal Processing, Vol. II: Detection Theory*, 1998,
//! §7.3, the generalised matched filter). With the innovation `ν_k ~ N(0, S_k)` of a
//! consistent filter and the signature `s_k = a_s,k / 2`, `u_k = s_kᵀ S_k⁻¹ ν_k` has variance
//! `w_k = s_kᵀ S_k⁻¹ s_k`, and the innovations are white, so the fading sums
//! `U = Σ λ^(n−k) u_k` and `W = Σ λ^(2(n−k)) w_k` (`λ = 1 − 1/N`, the consistency monitor's
//! `N`) give `z = U / √W ~ N(0, 1)` at every measurement. An uncorrected aberration holds `z`
//! at about `Σ λ^(n−k) w_k / √W`, growing with every measurement taken while the vehicle turns.
//! An episode begins when `z` exceeds [`ABERRATION_BOUND_SIGMA`] (one-sided without the
//! correction: the aberration adds `+s`; `|z|` with it) while the amplitude along the
//! signature, `U / Σ λ^(n−k) w_k`, is at most [`MAX_ABERRATION_FRACTION`] of the aberration
//! in size (a larger error that projects onto it is not
//! the aberration) and the same statistic along the twin signature, `s` turned 90° about the
//! boresight, stays within [`TWIN_BOUND_SIGMA`] (an aberration puts nothing there; an error of
//! another origin, an IMU misalignment turning the attitude in the same rotations, does), and
//! ends when `z` (`|z|`) falls below half the bound. The bound's false-alarm rate, 5σ one-sided
//! (2.9e-7; twice that two-sided) per independent stretch of `N` measurements, some 270 a
//! flight of the upper stage at 10 Hz, is below 2e-4 per flight (Bonferroni).
//!
//! The test takes accepted measurements only (a rejected one is an outlier, not the model's)
//! after the aid's acquisition; a non-finite or singular input enters nothing.

use nalgebra::{Matrix3, Vector3};

/// The bound on `z` in its own σ: 5σ, for a false alarm per independent stretch of `N`
/// measurements of 3e-7 (a few hundred stretches a flight).
pub const ABERRATION_BOUND_SIGMA: f64 = 5.0;

/// The largest fraction of the aberration an episode may claim: an aberration left in puts
/// at most all of `a_s / 2` in the innovations (less what the filter absorbs), so a score
/// beyond 1.5 times that is some larger error that happens to project onto the signature
/// (an IMU misalignment turning the attitude in the same rotations), not the aberration.
pub const MAX_ABERRATION_FRACTION: f64 = 1.5;

/// The largest `|z|` of the twin signature (the aberration's turned 90° about the
/// boresight) an episode allows: an aberration puts nothing along its twin, so the twin's
/// statistic stays N(0, 1) (3σ: a claim lost in 0.3 % of the stretches); an error of another
/// origin that projects onto the signature projects onto its twin as well.
pub const TWIN_BOUND_SIGMA: f64 = 3.0;

/// The fading sums of the aberration test and whether an episode is under way.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AberrationMonitor {
    /// `U = Σ λ^(n−k) sᵀ S⁻¹ ν`.
    score: f64,
    /// `W = Σ λ^(2(n−k)) sᵀ S⁻¹ s`, the variance of `U` under the model.
    score_variance: f64,
    /// `Σ λ^(n−k) sᵀ S⁻¹ s`: `U` over it is the fraction of the aberration the innovations
    /// carry.
    signature_weight: f64,
    /// `U` and `W` of the twin signature (the signature turned 90° about the boresight).
    twin_score: f64,
    twin_variance: f64,
    in_episode: bool,
}

impl AberrationMonitor {
    /// Enters one accepted star innovation `innovation` with covariance `covariance` and the
    /// aberration rotation `aberration_rad` (`a_s`, sensor axes) over about `n` measurements;
    /// true when an episode has just begun, which it may only while `claimable` (the caller's
    /// word that no larger error is in the innovations: the aberration is 5″ against the
    /// noise, so a star stream failing its NIS test carries something else, which would
    /// project onto the signature too); `correcting`: the flight software subtracts the
    /// aberration, so an episode begins on either sign (module docs). A non-finite input or a
    /// covariance that cannot be inverted enters nothing.
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
    ///         monitor.observe(&(a / 2.0), &covariance, &a, 256, true, false)
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
        claimable: bool,
        correcting: bool,
    ) -> bool {
        let signature = aberration_rad * 0.5;
        // The twin: the signature turned 90° about the boresight (sensor z), the
        // cross-boresight velocity direction itself, which an aberration does not produce.
        let twin = Vector3::new(-signature.y, signature.x, 0.0);
        let finite = innovation
            .iter()
            .chain(signature.iter())
            .all(|v| v.is_finite());
        let Some(cholesky) = covariance.cholesky() else {
            return false;
        };
        let (weighted, weighted_twin) = (cholesky.solve(&signature), cholesky.solve(&twin));
        let (score, variance) = (weighted.dot(innovation), weighted.dot(&signature));
        let (twin_score, twin_variance) = (weighted_twin.dot(innovation), weighted_twin.dot(&twin));
        let sums = [score, variance, twin_score, twin_variance];
        if !(finite && sums.iter().all(|v| v.is_finite()) && variance >= 0.0) {
            return false;
        }
        let fading = 1.0 - 1.0 / f64::from(n.max(1));
        self.score = fading * self.score + score;
        self.score_variance = fading * fading * self.score_variance + variance;
        self.signature_weight = fading * self.signature_weight + variance;
        self.twin_score = fading * self.twin_score + twin_score;
        self.twin_variance = fading * fading * self.twin_variance + twin_variance;
        // Without the correction only the aberration's own sign; with it either sign.
        let (z, fraction) = if correcting {
            (self.statistic_sigma().abs(), self.fraction().abs())
        } else {
            (self.statistic_sigma(), self.fraction())
        };
        let explained =
            fraction <= MAX_ABERRATION_FRACTION && self.twin_sigma().abs() <= TWIN_BOUND_SIGMA;
        let began = z > ABERRATION_BOUND_SIGMA && explained && claimable && !self.in_episode;
        if began {
            self.in_episode = true;
        } else if z < 0.5 * ABERRATION_BOUND_SIGMA {
            self.in_episode = false;
        }
        began
    }

    /// The twin statistic in its own σ: the innovations' score along the signature turned
    /// 90° about the boresight (0 before any was entered).
    pub fn twin_sigma(&self) -> f64 {
        in_own_sigma(self.twin_score, self.twin_variance)
    }

    /// `z`, the test statistic in its own σ, positive when the innovations follow the
    /// aberration (0 before any signature was entered).
    pub fn statistic_sigma(&self) -> f64 {
        in_own_sigma(self.score, self.score_variance)
    }

    /// The fraction of the aberration the innovations carry, `U / Σ λ^(n−k) sᵀ S⁻¹ s` (the
    /// weighted least-squares amplitude along the signature; 0 before any was entered).
    pub fn fraction(&self) -> f64 {
        if self.signature_weight > 0.0 {
            self.score / self.signature_weight
        } else {
            0.0
        }
    }
}

/// A fading score over its σ under the model, `U / √W` (0 while `W` is not positive).
fn in_own_sigma(score: f64, variance: f64) -> f64 {
    if variance > 0.0 {
        score / nav_core::float::sqrt(variance)
    } else {
        0.0
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
            let began = monitor.observe(&innovation, &covariance, &turning(k), 256, true, false);
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
            assert!(!monitor.observe(&offset, &covariance, &turning(k), 256, true, false));
        }
        assert!(
            monitor.statistic_sigma().abs() < 2.0,
            "{}",
            monitor.statistic_sigma()
        );
    }

    #[test]
    fn an_error_larger_than_the_aberration_or_opposite_to_it_is_not_claimed() {
        let covariance = Matrix3::identity() * COVARIANCE_SCALE;
        for scale in [3.0, -1.0] {
            let mut monitor = AberrationMonitor::default();
            for k in 0..2_000 {
                let innovation = turning(k) * (0.5 * scale);
                assert!(!monitor.observe(&innovation, &covariance, &turning(k), 256, true, false));
            }
            assert!(
                (monitor.fraction() - scale).abs() < 1e-9,
                "{}",
                monitor.fraction()
            );
        }
        // Half the aberration (the rest absorbed): claimed, its fraction 0.5.
        let mut monitor = AberrationMonitor::default();
        let began = (0..2_000)
            .filter(|k| {
                monitor.observe(
                    &(turning(*k) * 0.25),
                    &covariance,
                    &turning(*k),
                    256,
                    true,
                    false,
                )
            })
            .count();
        assert_eq!(began, 1);
        assert!((monitor.fraction() - 0.5).abs() < 1e-9);
        // Half the aberration plus as much along its twin (an error of another origin that
        // projects onto both): not claimed.
        let mut monitor = AberrationMonitor::default();
        assert!(!(0..2_000).any(|k| {
            let a = turning(k);
            let twin = Vector3::new(-a.y, a.x, 0.0);
            monitor.observe(&((a + twin) * 0.25), &covariance, &a, 256, true, false)
        }));
        assert!(monitor.twin_sigma() > 5.0, "{}", monitor.twin_sigma());
        // The same while the caller says the stream carries a larger error: not claimed.
        let mut monitor = AberrationMonitor::default();
        assert!(!(0..2_000).any(|k| monitor.observe(
            &(turning(k) * 0.25),
            &covariance,
            &turning(k),
            256,
            false,
            false
        )));
    }

    /// With the correction on, an aberration corrected twice (`−a_s / 2` in the innovations)
    /// is claimed, as one corrected with the wrong sign (`+a_s / 2`); without it, the
    /// negative one is not (no aberration left in gives it).
    #[test]
    fn with_the_correction_on_either_sign_is_claimed() {
        let covariance = Matrix3::identity() * COVARIANCE_SCALE;
        for (scale, correcting, claimed) in [
            (-0.5, true, true),
            (0.5, true, true),
            (-0.5, false, false),
            (-2.0, true, false),
        ] {
            let mut monitor = AberrationMonitor::default();
            let began = (0..2_000)
                .filter(|k| {
                    let a = turning(*k);
                    monitor.observe(&(a * scale), &covariance, &a, 256, true, correcting)
                })
                .count();
            assert_eq!(began, usize::from(claimed), "{scale} {correcting}");
        }
    }

    #[test]
    fn bad_input_enters_nothing() {
        let mut monitor = AberrationMonitor::default();
        let good = Matrix3::identity() * COVARIANCE_SCALE;
        let signature = turning(1);
        assert!(!monitor.observe(&signature, &Matrix3::zeros(), &signature, 256, true, false));
        assert!(!monitor.observe(
            &Vector3::new(f64::NAN, 0.0, 0.0),
            &good,
            &signature,
            256,
            true,
            false
        ));
        assert!(!monitor.observe(
            &signature,
            &good,
            &Vector3::new(f64::INFINITY, 0.0, 0.0),
            0,
            true,
            false
        ));
        assert_eq!(monitor, AberrationMonitor::default());
    }
}
