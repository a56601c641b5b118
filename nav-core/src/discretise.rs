//! Discretisation of the error model exactly as the paper's Section 1.3.3:
//! `F = Σ_{n=0..N} (AΔ)^n / n!`, `Γ = (Σ_{n=1..N} (AΔ)^{n−1} / n!) G Δ`, and
//! `Qd = Γ (Q/Δ) Γᵀ`, with the order `N` a parameter (1 to 4; the paper uses 3).
//!
//! `Q/Δ`: the paper's discrete model `X_k = F X_{k−1} + Γ W_{k−1}` holds the noise sample
//! `W_{k−1}` constant over the interval, so a continuous white noise of power spectral density
//! `Q` becomes a sequence of covariance `Q/Δ` (then `Qd ≈ G Q Gᵀ Δ` to first order, the
//! standard result).

use nalgebra::SMatrix;

#[cfg(any(test, feature = "dense-reference"))]
use crate::error_model::{NoiseInputMatrix, SystemMatrix, NOISE_DIMENSION};
#[cfg(any(test, feature = "dense-reference"))]
use crate::state::BlockMask;
use crate::state::STATE_DIMENSION;
#[cfg(any(test, feature = "dense-reference"))]
use crate::NavError;

/// Discrete process-noise covariance and transition matrices are 24×24.
pub type CovarianceMatrix = SMatrix<f64, STATE_DIMENSION, STATE_DIMENSION>;

/// Highest supported discretisation order.
pub const MAX_ORDER: u8 = 4;

/// Transition matrix `F` and discrete process noise `Qd` of one interval.
#[cfg(any(test, feature = "dense-reference"))]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscreteModel {
    /// State transition matrix `F_{k,k−1}`.
    pub transition: SystemMatrix,
    /// Process-noise covariance `Qd = Γ (Q/Δ) Γᵀ` (symmetric by construction).
    pub process_noise: CovarianceMatrix,
    /// The interval `Δ` (s).
    pub interval_s: f64,
}

#[cfg(any(test, feature = "dense-reference"))]
impl DiscreteModel {
    /// Removes the process noise of the `frozen` blocks (their rows and columns of `Qd`), as
    /// the calibration manager's freezing requires; the dense twin of
    /// [`crate::structured::StructuredModel::remove_process_noise`].
    pub fn remove_process_noise(&mut self, frozen: &BlockMask) {
        if frozen.is_empty() {
            return;
        }
        for (element, value) in self.process_noise.iter_mut().enumerate() {
            let (row, column) = (element % STATE_DIMENSION, element / STATE_DIMENSION);
            if frozen.contains_state(row) || frozen.contains_state(column) {
                *value = 0.0;
            }
        }
    }
}

/// Discretises `(A, G, Q)` over `interval_s` with a series of `order` terms.
///
/// # Errors
/// [`NavError::InvalidDiscretisationOrder`] for an order outside `1..=4`,
/// [`NavError::InvalidTimeStep`] for a non-positive or non-finite interval,
/// [`NavError::NonFiniteInput`] if `A`, `G` or `Q` hold NaN/Inf.
#[cfg(any(test, feature = "dense-reference"))]
pub fn discretise(
    system: &SystemMatrix,
    noise_input: &NoiseInputMatrix,
    noise_spectral_density: &SMatrix<f64, NOISE_DIMENSION, 1>,
    interval_s: f64,
    order: u8,
) -> Result<DiscreteModel, NavError> {
    if !(1..=MAX_ORDER).contains(&order) {
        return Err(NavError::InvalidDiscretisationOrder);
    }
    if !(interval_s.is_finite() && interval_s > 0.0) {
        return Err(NavError::InvalidTimeStep);
    }
    let all_finite = system.iter().all(|v| v.is_finite())
        && noise_input.iter().all(|v| v.is_finite())
        && noise_spectral_density.iter().all(|v| v.is_finite());
    if !all_finite {
        return Err(NavError::NonFiniteInput);
    }
    let scaled = system * interval_s;
    // term_n = (AΔ)^n / n!; F accumulates term_0..term_N, the Γ series term_{n−1}/n.
    let mut term = SystemMatrix::identity();
    let mut transition = SystemMatrix::identity();
    let mut gamma_series = SystemMatrix::zeros();
    let mut n = 1.0_f64;
    for _ in 0..order {
        // (AΔ)^{n−1}/n! = term_{n−1} / n
        gamma_series += term / n;
        term = term * scaled / n;
        transition += term;
        n += 1.0;
    }
    let gamma = gamma_series * noise_input * interval_s;
    let mut process_noise = CovarianceMatrix::zeros();
    for (column, density) in noise_spectral_density.iter().enumerate() {
        if *density > 0.0 {
            let gamma_column = gamma.column(column);
            process_noise += gamma_column * gamma_column.transpose() * (density / interval_s);
        }
    }
    Ok(DiscreteModel {
        transition,
        process_noise,
        interval_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error_model::{noise_input_matrix, system_matrix, LinearisationPoint, ProcessNoise};
    use nalgebra::{Matrix3, Vector3};

    /// High-accuracy exp(M) by scaling and squaring with a 20-term Taylor series.
    fn reference_exponential(matrix: &SystemMatrix) -> SystemMatrix {
        let squarings = 10;
        let scaled = matrix / f64::from(1u32 << squarings);
        let mut term = SystemMatrix::identity();
        let mut sum = SystemMatrix::identity();
        for k in 1..=20 {
            term = term * scaled / f64::from(k);
            sum += term;
        }
        for _ in 0..squarings {
            sum = sum * sum;
        }
        sum
    }

    fn motion_state(rate_deg_s: Vector3<f64>, force_mps2: Vector3<f64>) -> LinearisationPoint {
        let rate = rate_deg_s * core::f64::consts::PI / 180.0;
        LinearisationPoint {
            corrected_rate_rad_s: rate,
            corrected_specific_force_mps2: force_mps2,
            measured_rate_rad_s: rate,
            measured_specific_force_mps2: force_mps2,
            body_to_inertial: crate::attitude::rotation_matrix(
                &crate::attitude::exp_rotation_vector(&Vector3::new(0.2, 0.4, -0.1)),
            ),
            gravity_gradient_per_s2: Matrix3::zeros(),
        }
    }

    #[test]
    fn third_order_series_matches_the_exponential_to_fourth_order_truncation() {
        // At the filter's 2 ms the truncation is below round-off; at 1 s it dominates, and
        // must then equal the first omitted term (AΔ)^4/4! to within its own higher terms.
        let paper_motion_states = [
            ("I coast", Vector3::repeat(2.4e-4), Vector3::zeros()),
            (
                "II rotation",
                Vector3::new(0.0, 0.0, 10.0),
                Vector3::zeros(),
            ),
            (
                "III acceleration",
                Vector3::zeros(),
                Vector3::new(0.0, 20.0, 0.0),
            ),
        ];
        for (name, rate, force) in paper_motion_states {
            for interval_s in [0.002, 1.0] {
                let point = motion_state(rate, force);
                let a = system_matrix(&point);
                let g = noise_input_matrix(&point);
                let q = ProcessNoise::PAPER.spectral_density_diagonal();
                let exact = reference_exponential(&(a * interval_s));
                // Round-off of the 10 squarings in the reference, relative to |F|.
                let round_off = 1e-12 * exact.amax();
                let scaled = a * interval_s;
                let omitted_term = (scaled * scaled * scaled * scaled / 24.0).amax();
                let third = discretise(&a, &g, &q, interval_s, 3).unwrap().transition;
                let fourth = discretise(&a, &g, &q, interval_s, 4).unwrap().transition;
                let error3 = (third - exact).amax();
                let error4 = (fourth - exact).amax();
                println!("{name}, Δ = {interval_s} s: |F3 - expm| = {error3:.3e}, |F4 - expm| = {error4:.3e}, |(AΔ)^4/4!| = {omitted_term:.3e}");
                assert!(
                    error3 <= 1.05 * omitted_term + round_off,
                    "{name}: order 3 error {error3:e}"
                );
                assert!(
                    error4 <= error3 + round_off,
                    "{name}: order 4 {error4:e} worse than 3 {error3:e}"
                );
                if omitted_term > 1e3 * round_off {
                    assert!(
                        error3 >= 0.8 * omitted_term,
                        "{name}: {error3:e} vs {omitted_term:e}"
                    );
                    assert!(error4 < 0.5 * error3, "{name}: order 4 does not improve");
                }
            }
        }
    }

    #[test]
    fn process_noise_is_symmetric_and_first_order_consistent() {
        let point = motion_state(Vector3::new(0.0, 0.0, 10.0), Vector3::new(0.0, 20.0, 0.0));
        let a = system_matrix(&point);
        let g = noise_input_matrix(&point);
        let q = ProcessNoise::PAPER.spectral_density_diagonal();
        let model = discretise(&a, &g, &q, 0.002, 3).unwrap();
        assert_eq!(model.process_noise, model.process_noise.transpose());
        let first_order = g * SMatrix::<f64, 12, 12>::from_diagonal(&q) * g.transpose() * 0.002;
        let relative = (model.process_noise - first_order).amax() / first_order.amax();
        assert!(relative < 0.01, "{relative}");
    }

    #[test]
    fn bad_arguments_are_typed_errors() {
        let point = motion_state(Vector3::zeros(), Vector3::zeros());
        let a = system_matrix(&point);
        let g = noise_input_matrix(&point);
        let q = ProcessNoise::PAPER.spectral_density_diagonal();
        assert_eq!(
            discretise(&a, &g, &q, 0.002, 0),
            Err(NavError::InvalidDiscretisationOrder)
        );
        assert_eq!(
            discretise(&a, &g, &q, 0.002, 5),
            Err(NavError::InvalidDiscretisationOrder)
        );
        assert_eq!(
            discretise(&a, &g, &q, 0.0, 3),
            Err(NavError::InvalidTimeStep)
        );
        let mut bad = a;
        bad[(0, 0)] = f64::NAN;
        assert_eq!(
            discretise(&bad, &g, &q, 0.002, 3),
            Err(NavError::NonFiniteInput)
        );
    }
}
