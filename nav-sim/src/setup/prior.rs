//! A Monte Carlo run's sensor-error truth drawn from the filter's prior.

use rand_distr::{Distribution, StandardNormal};

use crate::scenario::Scenario;
use crate::setup::streams::{self, Stream};

/// The scenario with its sensor-error truth (gyro and accelerometer bias and scale factor,
/// star installation error) drawn from the filter's initial 1σ with `seed` (random
/// stream [`Stream::TruthDraw`]) and the simulation seed set to `seed`: what a Monte Carlo
/// needs so that the NEES tests the filter's covariance, prior included (with one fixed truth
/// a weakly observed state would sit far inside its prior every run).
pub fn with_truth_drawn_from_prior(scenario: &Scenario, seed: u64) -> Scenario {
    let mut drawn = scenario.clone();
    drawn.simulation.seed = seed;
    let mut rng = streams::rng(seed, Stream::TruthDraw);
    let sigma = scenario.filter.initial_sigma.clone();
    let mut draw = |scale: f64| -> [f64; 3] {
        [0; 3].map(|_| {
            let normal: f64 = StandardNormal.sample(&mut rng);
            normal * scale
        })
    };
    drawn.gyro.bias_rad_per_s = draw(sigma.gyro_bias_rad_per_s);
    drawn.gyro.scale_factor = draw(sigma.gyro_scale_factor);
    drawn.accelerometer.bias_mps2 = draw(sigma.accel_bias_mps2);
    drawn.accelerometer.scale_factor = draw(sigma.accel_scale_factor);
    drawn.star_sensor.installation_error_rotation_vector_rad = draw(sigma.star_installation_rad);
    drawn
}
