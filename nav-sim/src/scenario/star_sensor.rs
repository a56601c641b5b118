//! The `[star_sensor]` table: the tracker's rate, noise, mounting, installation error, rate
//! limit and outages, and its optional truth terms (`docs/guide/model.md`, "Star sensor truth"):
//! per-axis noise (cross-boresight and roll), a slowly varying first-order Gauss–Markov error,
//! a periodic error and velocity aberration; and the tracker's further optical heads,
//! `[[star_sensor.additional_heads]]`, each described by the same keys (`[star_sensor]` is
//! head 0). The optional terms are left out of the `Debug` rendering while absent or zero, so
//! a scenario without them renders, and hashes (the campaign's `scenario_hash`), as it did
//! before they existed.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Star sensor head: `q_is,meas = q_ib ⊗ q_bs ⊗ q_ψ ⊗ exp(ε_slow) ⊗ δq_noise`. The
/// `[star_sensor]` table is head 0; each `[[star_sensor.additional_heads]]` table is one more
/// head with the same keys (and no `additional_heads` of its own).
#[derive(Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StarSensorSettings {
    /// Output rate (Hz), > 0; the IMU rate must be a whole multiple of it. The heads sample
    /// on the flight computer's clock together: an additional head's rate must equal head
    /// 0's, so the time tags of every head coincide.
    pub rate_hz: f64,
    /// Attitude noise, 1σ per sensor axis, as a small rotation (arcsec), ≥ 0: without the
    /// per-axis keys the truth's and the flight software's noise on every axis. With them it
    /// must equal the larger of them and is only the scalar that single-noise users take
    /// (the covariance design study); truth and flight software use the per-axis values.
    pub noise_arcsec: f64,
    /// Nominal body-to-sensor mounting `q_bs = exp(φ)` as a rotation vector (deg). Known to
    /// the flight code.
    pub mounting_rotation_vector_deg: [f64; 3],
    /// Installation error `q_ψ = exp(ψ)` as a rotation vector `ψ` (rad, the rotation angle, not
    /// the quaternion's vector part). Unknown to the flight code.
    pub installation_error_rotation_vector_rad: [f64; 3],
    /// No output while the body rate's magnitude exceeds this (deg/s); 0 (the default) = no
    /// limit.
    #[serde(default)]
    pub max_rate_deg_per_s: f64,
    /// No output for this long after the rate falls back below `max_rate_deg_per_s` (s), ≥ 0
    /// (re-acquisition).
    #[serde(default)]
    pub reacquisition_s: f64,
    /// Outages `[[start_s, duration_s], ...]`, seconds after the scenario start: no output
    /// during `[start, start + duration)`.
    #[serde(default)]
    pub outages: Vec<[f64; 2]>,
    /// Noise 1σ about sensor x and about sensor y, across the boresight (arcsec), ≥ 0; given
    /// together with `roll_noise_arcsec`, it replaces the isotropic `noise_arcsec` in the truth.
    #[serde(default)]
    pub cross_boresight_noise_arcsec: Option<f64>,
    /// Noise 1σ about sensor z, the boresight (arcsec), ≥ 0; with
    /// `cross_boresight_noise_arcsec`.
    #[serde(default)]
    pub roll_noise_arcsec: Option<f64>,
    /// Slowly varying error: stationary 1σ per sensor axis (x, y, z) of a first-order
    /// Gauss–Markov rotation (arcsec), each ≥ 0; zero (the default) = none.
    #[serde(default)]
    pub slow_error_sigma_arcsec: [f64; 3],
    /// Its correlation time τ (s), > 0 when any `slow_error_sigma_arcsec` is.
    #[serde(default)]
    pub slow_error_correlation_time_s: f64,
    /// Periodic error: amplitude per sensor axis (arcsec), each ≥ 0; zero (the default) =
    /// none.
    #[serde(default)]
    pub periodic_error_amplitude_arcsec: [f64; 3],
    /// Its period (s), > 0 when any amplitude is.
    #[serde(default)]
    pub periodic_error_period_s: f64,
    /// Its phase at the scenario start (deg), the same on every axis.
    #[serde(default)]
    pub periodic_error_phase_deg: f64,
    /// Velocity aberration of the measured attitude (`docs/guide/model.md`, "Star sensor truth");
    /// `"none"` (the default) = a tracker that corrects it itself.
    #[serde(default)]
    pub aberration: StarAberration,
    /// The tracker's further heads, 1, 2, … in file order (head 0 is this table), each a
    /// complete head with its own mounting, installation error, noise, errors, rate limit
    /// and outages, and its own random streams; at most [`MAX_STAR_HEADS`] heads in all.
    /// Empty (the default) = one head.
    #[serde(default)]
    pub additional_heads: Vec<StarSensorSettings>,
}

/// The most heads a star tracker may have (`[star_sensor]` and its additional heads): each
/// head's random streams have their own ids below the next block of stream ids
/// (`setup::streams`).
pub const MAX_STAR_HEADS: usize = 8;

/// Whether the tracker's attitude carries the velocity aberration of the vehicle's motion.
// `Serialize` gives the key's default to the reference (docs/reference/scenario-keys.md).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum StarAberration {
    /// The tracker corrects it: the geometric attitude (the truth before this key existed).
    #[default]
    None,
    /// The tracker does not correct it: the attitude is turned by `a_s = β_s × z`
    /// (nav-core `aberration`), `β_s` the inertial velocity over `c` in sensor axes.
    Uncorrected,
}

/// Arc-seconds to radians: the flight software's data-sheet conversion, so a scenario and a
/// data sheet that state one value give the same bits.
pub use nav_fsw::datasheet::arcsec_to_rad;

impl StarSensorSettings {
    /// A second head as the two-head scenario files have it (`star_tracker_two_heads.toml`):
    /// this head's keys with the boresight along body +y (mounting `exp(−90° about body x)`,
    /// 90° from the default head's), an installation error of the default head's size in
    /// another direction, no outages and no further heads. For the studies and tests that add
    /// a head to a one-head scenario.
    pub fn head_across(&self) -> StarSensorSettings {
        let mut head = self.clone();
        head.additional_heads.clear();
        head.outages.clear();
        head.mounting_rotation_vector_deg = [-90.0, 0.0, 0.0];
        head.installation_error_rotation_vector_rad = [-3.0e-3, 1.0e-3, 2.0e-3];
        head
    }

    /// Noise 1σ per axis (rad): the isotropic `noise_arcsec` (with per-axis keys, the larger
    /// of them; the flight software is told [`Self::noise_per_axis_rad`]).
    pub fn noise_rad(&self) -> f64 {
        arcsec_to_rad(self.noise_arcsec)
    }

    /// Whether the per-axis noise keys are given (both; validation refuses one alone).
    pub fn has_per_axis_noise(&self) -> bool {
        self.cross_boresight_noise_arcsec.is_some() || self.roll_noise_arcsec.is_some()
    }

    /// The noise 1σ about sensor x, y and z (rad), the truth's and the flight software's:
    /// cross-boresight, cross-boresight, roll with the per-axis keys, else `noise_arcsec` on
    /// every axis (the same bits).
    pub fn noise_per_axis_rad(&self) -> [f64; 3] {
        let isotropic = self.noise_rad();
        let cross = self
            .cross_boresight_noise_arcsec
            .map_or(isotropic, arcsec_to_rad);
        let roll = self.roll_noise_arcsec.map_or(isotropic, arcsec_to_rad);
        [cross, cross, roll]
    }

    /// Every head, head 0 (this table) first, then the additional heads in file order.
    pub fn heads(&self) -> impl Iterator<Item = &StarSensorSettings> {
        std::iter::once(self).chain(&self.additional_heads)
    }

    /// Whether the slowly varying Gauss–Markov error is on.
    pub fn has_slow_error(&self) -> bool {
        self.slow_error_sigma_arcsec
            .iter()
            .any(|sigma| *sigma != 0.0)
    }

    /// Whether the periodic error is on.
    pub fn has_periodic_error(&self) -> bool {
        self.periodic_error_amplitude_arcsec
            .iter()
            .any(|amplitude| *amplitude != 0.0)
    }

    /// The dispersed noise of every head: `noise_arcsec` and the per-axis keys scaled by
    /// `factor` (the larger per-axis value stays equal to `noise_arcsec`, as multiplication is
    /// monotonic). One factor for the tracker: its heads share one specification.
    pub fn scale_noise(&mut self, factor: f64) {
        self.scale_head_noise(factor);
        for head in &mut self.additional_heads {
            head.scale_head_noise(factor);
        }
    }

    /// This head's noise keys scaled by `factor`.
    fn scale_head_noise(&mut self, factor: f64) {
        self.noise_arcsec *= factor;
        for value in [
            &mut self.cross_boresight_noise_arcsec,
            &mut self.roll_noise_arcsec,
        ]
        .into_iter()
        .flatten()
        {
            *value *= factor;
        }
    }
}

impl std::fmt::Debug for StarSensorSettings {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut debug = formatter.debug_struct("StarSensorSettings");
        debug
            .field("rate_hz", &self.rate_hz)
            .field("noise_arcsec", &self.noise_arcsec)
            .field(
                "mounting_rotation_vector_deg",
                &self.mounting_rotation_vector_deg,
            )
            .field(
                "installation_error_rotation_vector_rad",
                &self.installation_error_rotation_vector_rad,
            )
            .field("max_rate_deg_per_s", &self.max_rate_deg_per_s)
            .field("reacquisition_s", &self.reacquisition_s)
            .field("outages", &self.outages);
        if self.has_per_axis_noise() {
            debug
                .field(
                    "cross_boresight_noise_arcsec",
                    &self.cross_boresight_noise_arcsec,
                )
                .field("roll_noise_arcsec", &self.roll_noise_arcsec);
        }
        if self.has_slow_error() || self.slow_error_correlation_time_s != 0.0 {
            debug
                .field("slow_error_sigma_arcsec", &self.slow_error_sigma_arcsec)
                .field(
                    "slow_error_correlation_time_s",
                    &self.slow_error_correlation_time_s,
                );
        }
        if self.has_periodic_error()
            || self.periodic_error_period_s != 0.0
            || self.periodic_error_phase_deg != 0.0
        {
            debug
                .field(
                    "periodic_error_amplitude_arcsec",
                    &self.periodic_error_amplitude_arcsec,
                )
                .field("periodic_error_period_s", &self.periodic_error_period_s)
                .field("periodic_error_phase_deg", &self.periodic_error_phase_deg);
        }
        if self.aberration != StarAberration::None {
            debug.field("aberration", &self.aberration);
        }
        if !self.additional_heads.is_empty() {
            debug.field("additional_heads", &self.additional_heads);
        }
        debug.finish()
    }
}

/// The tracker's slowly varying error as the flight software is told it
/// (`[filter.star_slow_error]`): a first-order Gauss–Markov rotation per sensor axis of
/// stationary 1σ and correlation time τ, which the filter carries as a random walk of its
/// installation states with the driving noise `2σ²/τ` and `2σ²` more prior variance
/// (nav-fsw `StarSensorConfig::installation_walk_rad2_per_s`, docs/guide/sensor-errors.md). Every
/// key defaults to 0 (off).
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FilterStarSlowError {
    /// Stationary 1σ per sensor axis `[x, y, z]` (arcsec), each ≥ 0; all 0 = off.
    #[serde(default)]
    pub sigma_arcsec: [f64; 3],
    /// Its correlation time τ (s), > 0 when any 1σ is.
    #[serde(default)]
    pub correlation_time_s: f64,
}

impl FilterStarSlowError {
    /// Whether any key is set (the table renders in `Debug` only then).
    pub fn is_on(&self) -> bool {
        self.sigma_arcsec.iter().any(|sigma| *sigma != 0.0) || self.correlation_time_s != 0.0
    }

    /// The 1σ per sensor axis (rad).
    pub fn sigma_rad(&self) -> [f64; 3] {
        self.sigma_arcsec.map(arcsec_to_rad)
    }

    /// The largest 1σ over the axes (rad): the installation prior is one 1σ for the three
    /// axes, so it takes the largest `2σ²`.
    pub fn largest_sigma_rad(&self) -> f64 {
        self.sigma_rad().into_iter().fold(0.0, f64::max)
    }
}

#[cfg(test)]
#[path = "star_sensor_tests.rs"]
mod tests;
