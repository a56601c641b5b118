//! Dispersions: the scenario's optional `[dispersion]` table, truth-side quantities drawn
//! afresh for every Monte Carlo run (`docs/monte-carlo.md`, "Dispersions").
//!
//! Every entry changes what the simulated vehicle and sensors do, never what the flight
//! software is configured with, so a dispersion is a model mismatch the campaign measures.
//! Each entry draws from its own ChaCha8 stream of the run's seed
//! ([`DISPERSION_STREAM_BASE`] + the entry's index in [`ENTRY_KEYS`]): a run's draws depend
//! only on its seed and the table, so run k alone reproduces run k of a campaign, and adding
//! or removing one entry leaves the others' draws unchanged.

use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution as _, StandardNormal};
use serde::Deserialize;

use crate::scenario::Scenario;

/// First ChaCha8 stream of the dispersion draws (the sensors use 0..=4, the initial
/// navigation error 100 and the sensor-error truth 101).
pub const DISPERSION_STREAM_BASE: u64 = 200;

/// The entries' keys, in stream order (entry `i` draws from stream
/// [`DISPERSION_STREAM_BASE`] + `i`).
pub const ENTRY_KEYS: [&str; 11] = [
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
];

/// Smallest factor a dispersed correlation time is scaled by: a first-order Gauss–Markov
/// error needs τ > 0, and a draw at or below −100 % would make it zero or negative.
pub const MIN_CORRELATION_TIME_FACTOR: f64 = 1.0e-3;

/// Distribution of one dispersed quantity, zero-mean, in the entry's units: TOML
/// `{ kind = "normal", sigma = 1.0 }` or `{ kind = "uniform", half_width = 1.0 }`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
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

    fn sample(&self, rng: &mut ChaCha8Rng) -> f64 {
        match *self {
            Self::Normal { sigma } => {
                let normal: f64 = StandardNormal.sample(rng);
                normal * sigma
            }
            Self::Uniform { half_width } => {
                let unit: f64 = rng.random_range(-1.0..=1.0);
                unit * half_width
            }
        }
    }
}

/// The `[dispersion]` table: every entry optional, absent = not dispersed.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
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
}

/// The values one run draws, in the entries' units (zero for an absent entry).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Draw {
    /// Added initial attitude error (deg).
    pub initial_attitude_deg: [f64; 3],
    /// Added initial position error (m).
    pub initial_position_m: [f64; 3],
    /// Added initial velocity error (m/s).
    pub initial_velocity_mps: [f64; 3],
    /// Gyro noise change (%).
    pub gyro_noise_percent: f64,
    /// Accelerometer noise change (%).
    pub accelerometer_noise_percent: f64,
    /// Star-sensor noise change (%).
    pub star_noise_percent: f64,
    /// GNSS white noise change (%).
    pub gnss_noise_percent: f64,
    /// Added star mounting rotation (deg).
    pub star_mounting_deg: [f64; 3],
    /// GNSS correlated 1σ change (%).
    pub gnss_correlated_sigma_percent: f64,
    /// GNSS correlation time change (%).
    pub gnss_correlation_time_percent: f64,
    /// Added GNSS latency (IMU frames).
    pub gnss_latency_frames: u32,
}

fn stream(seed: u64, entry: usize) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // Entry indices are below ENTRY_KEYS.len(), far inside u64.
    rng.set_stream(DISPERSION_STREAM_BASE + entry as u64);
    rng
}

fn draw3(distribution: Option<&Distribution>, seed: u64, entry: usize) -> [f64; 3] {
    distribution.map_or([0.0; 3], |distribution| {
        let mut rng = stream(seed, entry);
        [0; 3].map(|_| distribution.sample(&mut rng))
    })
}

fn draw1(distribution: Option<&Distribution>, seed: u64, entry: usize) -> f64 {
    distribution.map_or(0.0, |distribution| {
        distribution.sample(&mut stream(seed, entry))
    })
}

impl Dispersion {
    /// The values the run with `seed` draws.
    pub fn draw(&self, seed: u64) -> Draw {
        let latency_entry = ENTRY_KEYS.len() - 1;
        Draw {
            initial_attitude_deg: draw3(self.initial_attitude_deg.as_ref(), seed, 0),
            initial_position_m: draw3(self.initial_position_m.as_ref(), seed, 1),
            initial_velocity_mps: draw3(self.initial_velocity_mps.as_ref(), seed, 2),
            gyro_noise_percent: draw1(self.gyro_noise_percent.as_ref(), seed, 3),
            accelerometer_noise_percent: draw1(self.accelerometer_noise_percent.as_ref(), seed, 4),
            star_noise_percent: draw1(self.star_noise_percent.as_ref(), seed, 5),
            gnss_noise_percent: draw1(self.gnss_noise_percent.as_ref(), seed, 6),
            star_mounting_deg: draw3(self.star_mounting_deg.as_ref(), seed, 7),
            gnss_correlated_sigma_percent: draw1(
                self.gnss_correlated_sigma_percent.as_ref(),
                seed,
                8,
            ),
            gnss_correlation_time_percent: draw1(
                self.gnss_correlation_time_percent.as_ref(),
                seed,
                9,
            ),
            gnss_latency_frames: self.gnss_latency_frames.map_or(0, |frames| {
                stream(seed, latency_entry).random_range(0..=frames)
            }),
        }
    }
}

/// `1 + percent / 100`, at least `floor`: a noise level cannot fall below zero.
fn factor(percent: f64, floor: f64) -> f64 {
    (1.0 + percent / 100.0).max(floor)
}

/// The truth side of the run with `seed`: `scenario` (already seeded for the run) with the
/// drawn noise levels, star mounting, correlated GNSS error and latency. The flight software's
/// configuration is made from the undispersed scenario, so these are model mismatches. Without
/// a `[dispersion]` table the scenario is returned unchanged.
pub fn truth_scenario(scenario: &Scenario, seed: u64) -> Scenario {
    let mut truth = scenario.clone();
    let Some(dispersion) = &scenario.dispersion else {
        return truth;
    };
    let draw = dispersion.draw(seed);
    truth.gyro.rate_noise_density_deg_per_h_per_sqrt_hz *= factor(draw.gyro_noise_percent, 0.0);
    truth.accelerometer.noise_per_sample_mps2 *= factor(draw.accelerometer_noise_percent, 0.0);
    truth.star_sensor.noise_arcsec *= factor(draw.star_noise_percent, 0.0);
    truth.gnss.noise_m *= factor(draw.gnss_noise_percent, 0.0);
    for (mounting, added) in truth
        .star_sensor
        .mounting_rotation_vector_deg
        .iter_mut()
        .zip(draw.star_mounting_deg)
    {
        *mounting += added;
    }
    truth.gnss.correlated_noise_m *= factor(draw.gnss_correlated_sigma_percent, 0.0);
    truth.gnss.correlation_time_s *= factor(
        draw.gnss_correlation_time_percent,
        MIN_CORRELATION_TIME_FACTOR,
    );
    truth.gnss.latency_s += f64::from(draw.gnss_latency_frames) * scenario.imu.frame_period_s();
    truth
}

/// The initial navigation error a flight of `scenario` adds to the one drawn from the filter's
/// initial 1σ, drawn with the scenario's seed (a campaign run's seed,
/// [`crate::flight::with_truth_drawn_from_prior`]): (attitude rotation vector rad, position m,
/// velocity m/s), zero without a `[dispersion]` table.
pub fn initial_error_offsets(scenario: &Scenario) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let Some(dispersion) = &scenario.dispersion else {
        return (Vector3::zeros(), Vector3::zeros(), Vector3::zeros());
    };
    let draw = dispersion.draw(scenario.simulation.seed);
    (
        Vector3::from(draw.initial_attitude_deg.map(f64::to_radians)),
        Vector3::from(draw.initial_position_m),
        Vector3::from(draw.initial_velocity_mps),
    )
}

/// The flight software's configuration for a run: made from the undispersed `scenario`
/// ([`crate::flight::fsw_config`]), with the measurement history's latency window widened to
/// the `truth`'s dispersed GNSS latency plus the hand-over frame, as the scenario's own
/// `gnss.latency_s` widens it: the window is a buffer length, not a model the filter assumes,
/// and a fix older than it would be dropped rather than fused late.
///
/// # Errors
/// As [`crate::flight::fsw_config`].
pub fn flight_config(
    scenario: &Scenario,
    truth: &Scenario,
) -> Result<nav_fsw::config::FswConfig, crate::flight::FlightError> {
    let mut config = crate::flight::fsw_config(scenario)?;
    if truth.gnss.latency_s > scenario.gnss.latency_s {
        let window_s = truth.gnss.latency_s + scenario.imu.frame_period_s();
        config.timing.max_latency_s = config.timing.max_latency_s.max(window_s);
    }
    Ok(config)
}
