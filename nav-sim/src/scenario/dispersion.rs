//! The scenario's optional `[dispersion]` table (`docs/guide/monte-carlo.md`, "Dispersions"): which
//! truth-side quantities a Monte Carlo run draws afresh, and from which distribution. The draws
//! themselves are the setup layer's ([`crate::setup::dispersion`]).

use schemars::JsonSchema;
use serde::Deserialize;

/// The entries' keys, in stream order (entry `i` draws from stream
/// `DISPERSION_STREAM_BASE` + `i`, the setup layer's dispersion streams).
pub const ENTRY_KEYS: [&str; 15] = [
    "initial_attitude_deg",
    "initial_position_m",
    "initial_velocity_mps",
    "gyro_noise_percent",
    "accelerometer_noise_percent",
    "star_noise_percent",
    "gnss_noise_percent",
    "star_mounting_deg",
    "gnss_correlated_sigma_percent",
    "gnss_correlation_time_percent",
    "gnss_latency_frames",
    "gyro_misalignment_rad",
    "accelerometer_misalignment_rad",
    "gyro_g_sensitivity_rad_s_per_mps2",
    "launch_longitude_deg",
];

/// Index in [`ENTRY_KEYS`] of `gnss_latency_frames` (its stream).
pub const GNSS_LATENCY_ENTRY: usize = 10;

/// Index in [`ENTRY_KEYS`] of `launch_longitude_deg` (its stream).
pub const LAUNCH_LONGITUDE_ENTRY: usize = 14;

/// Smallest factor a dispersed correlation time is scaled by: a first-order Gauss–Markov
/// error needs τ > 0, and a draw at or below −100 % would make it zero or negative.
pub const MIN_CORRELATION_TIME_FACTOR: f64 = 1.0e-3;

/// Distribution of one dispersed quantity, zero-mean, in the entry's units: TOML
/// `{ kind = "normal", sigma = 1.0 }` or `{ kind = "uniform", half_width = 1.0 }`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Distribution {
    /// Normal with standard deviation `sigma`, ≥ 0.
    Normal {
        /// 1σ, in the entry's units.
        sigma: f64,
    },
    /// Uniform on `[−half_width, half_width]`, `half_width` ≥ 0.
    Uniform {
        /// Half the interval's width, in the entry's units.
        half_width: f64,
    },
}

impl Distribution {
    /// The distribution's width parameter (σ or half-width).
    pub fn width(&self) -> f64 {
        match *self {
            Self::Normal { sigma } => sigma,
            Self::Uniform { half_width } => half_width,
        }
    }
}

/// The `[dispersion]` table: every entry optional, absent = not dispersed.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Dispersion {
    /// Rotation added per axis to the initial attitude error of the navigation solution
    /// (deg, body axes).
    pub initial_attitude_deg: Option<Distribution>,
    /// Offset added per axis to the initial position error (m, launch-inertial).
    pub initial_position_m: Option<Distribution>,
    /// Offset added per axis to the initial velocity error (m/s, launch-inertial).
    pub initial_velocity_mps: Option<Distribution>,
    /// Relative change of the true gyro rate-noise density (%).
    pub gyro_noise_percent: Option<Distribution>,
    /// Relative change of the true accelerometer noise (%).
    pub accelerometer_noise_percent: Option<Distribution>,
    /// Relative change of the true star-sensor noise (%).
    pub star_noise_percent: Option<Distribution>,
    /// Relative change of the true white GNSS position noise (%).
    pub gnss_noise_percent: Option<Distribution>,
    /// Rotation added per axis to the true star-sensor mounting rotation vector (deg), on top
    /// of the installation error; the flight software keeps the nominal mounting.
    pub star_mounting_deg: Option<Distribution>,
    /// Relative change of the receiver's true correlated error 1σ (%).
    pub gnss_correlated_sigma_percent: Option<Distribution>,
    /// Relative change of the receiver's true correlation time (%).
    pub gnss_correlation_time_percent: Option<Distribution>,
    /// Whole IMU frames added to the receiver's true latency, uniform in `0..=n`.
    pub gnss_latency_frames: Option<u32>,
    /// Added to each of the six off-diagonal terms of the true gyro misalignment (rad), drawn
    /// in the order `a01, a02, a10, a12, a20, a21`.
    pub gyro_misalignment_rad: Option<Distribution>,
    /// Added to each off-diagonal term of the true accelerometer misalignment (rad), same
    /// order.
    pub accelerometer_misalignment_rad: Option<Distribution>,
    /// Added per axis to the true gyro g-sensitivity (rad/s per m/s²).
    pub gyro_g_sensitivity_rad_s_per_mps2: Option<Distribution>,
    /// Turn of the whole flight about the Earth's axis (deg, east): the launch site's
    /// longitude and the orbit's node move together, so the flight in the launch frame is the
    /// same while its ground track, and the gravity field under it, is another. Unlike the
    /// other entries this draws another mission, not a mismatch: the flight software is
    /// configured for the turned flight ([`crate::setup::dispersion::mission_scenario`]).
    pub launch_longitude_deg: Option<Distribution>,
}
