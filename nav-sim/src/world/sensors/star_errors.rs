//! The star tracker's slowly varying errors (`docs/guide/model.md`, "Star sensor truth"): a
//! first-order Gauss–Markov rotation per sensor axis and a periodic rotation, summed into one
//! small rotation vector `ε_slow` in sensor axes, applied between the installation error and
//! the white noise, `q_is,m = q_ib ⊗ q_bs ⊗ q_ψ ⊗ exp(ε_slow) ⊗ exp(n)`.
//!
//! The Gauss–Markov part `ε̇ = −ε/τ + w` is drawn from its stationary `N(0, σ²)` at the
//! first star sample and advanced exactly between samples `Δt` apart,
//! `ε ← φ ε + σ √(1 − φ²) w`, `φ = exp(−Δt/τ)` (the discrete-time equivalent of the
//! continuous model: Gelb, *Applied Optimal Estimation*, 1974, Chapter 3; Maybeck,
//! *Stochastic Models, Estimation and Control* I, 1979, Chapter 4), `w ~ N(0, I)` from its
//! own stream, created only when the error is on. The periodic part is
//! `a sin(2π (t − t₀)/P + φ₀)` per axis (`t₀` the scenario start). A tracker with neither has
//! no [`StarSlowErrors`], and its measurement is the model without them, bit for bit.

use nalgebra::Vector3;
use rand_chacha::ChaCha8Rng;

use super::normal3;
use crate::scenario::star_sensor::arcsec_to_rad;
use crate::scenario::StarSensorSettings;

/// A first-order Gauss–Markov rotation per sensor axis (rad), stationary 1σ `sigma_rad`.
#[derive(Debug, Clone)]
pub(super) struct SlowGaussMarkov {
    sigma_rad: Vector3<f64>,
    correlation_time_s: f64,
    /// The time and value of the last sample, `None` before the first.
    state: Option<(f64, Vector3<f64>)>,
    rng: ChaCha8Rng,
}

impl SlowGaussMarkov {
    /// The error with per-axis 1σ `sigma_rad` and correlation time `correlation_time_s`.
    pub(super) fn new(sigma_rad: Vector3<f64>, correlation_time_s: f64, rng: ChaCha8Rng) -> Self {
        Self {
            sigma_rad,
            correlation_time_s,
            state: None,
            rng,
        }
    }

    /// The error at `time_s` (not before the previous sample): the stationary draw first,
    /// then the exact transition from the previous sample.
    pub(super) fn at(&mut self, time_s: f64) -> Vector3<f64> {
        let value = match self.state {
            None => normal3(&mut self.rng).component_mul(&self.sigma_rad),
            Some((last_s, last)) => {
                let phi = (-(time_s - last_s).max(0.0) / self.correlation_time_s).exp();
                last * phi
                    + normal3(&mut self.rng).component_mul(&self.sigma_rad)
                        * (1.0 - phi * phi).sqrt()
            }
        };
        self.state = Some((time_s, value));
        value
    }
}

/// A sinusoidal rotation per sensor axis (rad).
#[derive(Debug, Clone, Copy)]
struct Periodic {
    amplitude_rad: Vector3<f64>,
    period_s: f64,
    phase_rad: f64,
    start_time_s: f64,
}

/// The star tracker's slowly varying errors; each `None` is off.
#[derive(Debug, Clone)]
pub(super) struct StarSlowErrors {
    gauss_markov: Option<SlowGaussMarkov>,
    periodic: Option<Periodic>,
    /// `ε_slow` at the last star sample (zero before the first).
    last: Vector3<f64>,
}

impl StarSlowErrors {
    /// The terms from the scenario's `[star_sensor]` keys, or `None` when both are off.
    /// `rng` is called (the stream created) only when the Gauss–Markov error is on.
    pub(super) fn new(
        star: &StarSensorSettings,
        start_time_s: f64,
        rng: impl FnOnce() -> ChaCha8Rng,
    ) -> Option<Self> {
        let gauss_markov = star.has_slow_error().then(|| {
            SlowGaussMarkov::new(
                Vector3::from(star.slow_error_sigma_arcsec.map(arcsec_to_rad)),
                star.slow_error_correlation_time_s,
                rng(),
            )
        });
        let periodic = star.has_periodic_error().then(|| Periodic {
            amplitude_rad: Vector3::from(star.periodic_error_amplitude_arcsec.map(arcsec_to_rad)),
            period_s: star.periodic_error_period_s,
            phase_rad: star.periodic_error_phase_deg.to_radians(),
            start_time_s,
        });
        (gauss_markov.is_some() || periodic.is_some()).then_some(Self {
            gauss_markov,
            periodic,
            last: Vector3::zeros(),
        })
    }

    /// `ε_slow` at the star sample `time_s` (rad, sensor axes); called once per sample, in
    /// time order, whether or not the sample is delivered.
    pub(super) fn at(&mut self, time_s: f64) -> Vector3<f64> {
        let mut error = Vector3::zeros();
        if let Some(gauss_markov) = &mut self.gauss_markov {
            error += gauss_markov.at(time_s);
        }
        if let Some(periodic) = &self.periodic {
            let angle_rad = std::f64::consts::TAU * (time_s - periodic.start_time_s)
                / periodic.period_s
                + periodic.phase_rad;
            error += periodic.amplitude_rad * angle_rad.sin();
        }
        self.last = error;
        error
    }

    /// `ε_slow` at the last star sample (rad, sensor axes; zero before the first).
    pub(super) fn last(&self) -> Vector3<f64> {
        self.last
    }
}
