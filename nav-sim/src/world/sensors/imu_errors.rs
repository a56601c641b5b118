//! The optional IMU error terms of a triad (`docs/guide/model.md`, "IMU misalignment,
//! g-sensitivity and bias instability"): misalignment and non-orthogonality `M = I + A`,
//! gyro g-sensitivity `G = diag(g)`, and a first-order Gauss–Markov bias `b_GM`. With them the
//! increment before the paper's bias, noise and scale factor is
//!
//! ```text
//! Δ_s = Δ + A Δ + G Δv + b_GM,k T      (G Δv for the gyro only)
//! Δ_m = (I − Λ)⁻¹ (Δ_s + b T + n)
//! ```
//!
//! `A` has a zero diagonal (`a_ij`, `i ≠ j`: axis `i` senses `a_ij` of the increment on body
//! axis `j`); `G Δv = ∫ G f dt` is exact because the truth's `Δv` is the frame integral of
//! the body specific force `f`. The bias instability advances once per frame with the exact
//! discretisation `b_GM,k+1 = φ b_GM,k + σ √(1 − φ²) w_k`, `φ = exp(−T/τ)`, from an initial
//! draw `N(0, σ²)`. A triad with every term off has no [`TriadExtras`] at all, so its
//! arithmetic and random draws are the model's without them, bit for bit.

use nalgebra::{Matrix3, Vector3};
use rand_chacha::ChaCha8Rng;

use super::normal3;

/// A first-order Gauss–Markov bias per axis, stationary 1σ `sigma`, advanced per frame.
#[derive(Debug, Clone)]
pub(super) struct BiasInstability {
    sigma: f64,
    correlation_time_s: f64,
    /// The bias of the current frame (units of the rate or specific force).
    pub(super) value: Vector3<f64>,
    rng: ChaCha8Rng,
}

impl BiasInstability {
    /// The bias with its stationary initial draw from `rng`, or `None` (no draw) when
    /// `sigma` is 0.
    pub(super) fn new(sigma: f64, correlation_time_s: f64, mut rng: ChaCha8Rng) -> Option<Self> {
        (sigma > 0.0).then(|| Self {
            sigma,
            correlation_time_s,
            value: normal3(&mut rng) * sigma,
            rng,
        })
    }

    /// Advances the bias over a frame of `interval_s`: `b ← φ b + σ √(1 − φ²) w`.
    pub(super) fn advance(&mut self, interval_s: f64) {
        let phi = (-interval_s / self.correlation_time_s).exp();
        self.value =
            self.value * phi + normal3(&mut self.rng) * (self.sigma * (1.0 - phi * phi).sqrt());
    }
}

/// The optional terms of one triad; each `None` is off.
#[derive(Debug, Clone)]
pub(super) struct TriadExtras {
    /// `A`, the off-diagonal part of `M = I + A`.
    misalignment: Option<Matrix3<f64>>,
    /// The diagonal of `G` (gyro only).
    g_sensitivity: Option<Vector3<f64>>,
    /// The Gauss–Markov bias.
    pub(super) instability: Option<BiasInstability>,
}

impl TriadExtras {
    /// The terms from the scenario's keys, or `None` when all are off. `instability_rng` is
    /// called (the stream created) only when the bias instability is on.
    pub(super) fn new(
        misalignment_rad: &[[f64; 3]; 3],
        g_sensitivity: &[f64; 3],
        (sigma, correlation_time_s): (f64, f64),
        instability_rng: impl FnOnce() -> ChaCha8Rng,
    ) -> Option<Self> {
        let misalignment = misalignment_rad
            .iter()
            .flatten()
            .any(|term| *term != 0.0)
            .then(|| Matrix3::from_fn(|row, column| misalignment_rad[row][column]));
        let g_sensitivity = g_sensitivity
            .iter()
            .any(|value| *value != 0.0)
            .then(|| Vector3::from(*g_sensitivity));
        let instability = (sigma > 0.0)
            .then(|| BiasInstability::new(sigma, correlation_time_s, instability_rng()))
            .flatten();
        (misalignment.is_some() || g_sensitivity.is_some() || instability.is_some()).then_some(
            Self {
                misalignment,
                g_sensitivity,
                instability,
            },
        )
    }

    /// `Δ_s = Δ + A Δ + G Δv + b_GM T` for the true increment `increment` and the true
    /// velocity increment `specific_force_increment` over `interval_s`.
    pub(super) fn sensed(
        &self,
        increment: &Vector3<f64>,
        specific_force_increment: &Vector3<f64>,
        interval_s: f64,
    ) -> Vector3<f64> {
        let mut sensed = *increment;
        if let Some(misalignment) = &self.misalignment {
            sensed += misalignment * increment;
        }
        if let Some(g_sensitivity) = &self.g_sensitivity {
            sensed += g_sensitivity.component_mul(specific_force_increment);
        }
        if let Some(instability) = &self.instability {
            sensed += instability.value * interval_s;
        }
        sensed
    }

    /// Advances the Gauss–Markov bias (if on) to the next frame.
    pub(super) fn advance(&mut self, interval_s: f64) {
        if let Some(instability) = &mut self.instability {
            instability.advance(interval_s);
        }
    }

    /// `A` (zero when off).
    pub(super) fn misalignment(&self) -> Matrix3<f64> {
        self.misalignment.unwrap_or_else(Matrix3::zeros)
    }

    /// The diagonal of `G` (zero when off).
    pub(super) fn g_sensitivity(&self) -> Vector3<f64> {
        self.g_sensitivity.unwrap_or_else(Vector3::zeros)
    }

    /// The Gauss–Markov bias of the current frame, if on.
    pub(super) fn instability_bias(&self) -> Option<Vector3<f64>> {
        self.instability
            .as_ref()
            .map(|instability| instability.value)
    }
}
