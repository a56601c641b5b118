//! A Monte Carlo run's sensor-error truth drawn from the filter's prior.

use rand_distr::{Distribution, StandardNormal};

use crate::scenario::Scenario;
use crate::setup::streams::{self, Stream};

/// The scenario with its sensor-error truth (gyro and accelerometer bias and scale factor,
/// star installation error of every head, head 0's first) drawn from the filter's initial
/// 1σ with `seed` (random
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
    // Each further head's installation error from the same 1σ, independently: the relative
    // alignment's prior (√2 σ_ψ, setup `fsw`) is that of two such draws.
    for head in &mut drawn.star_sensor.additional_heads {
        head.installation_error_rotation_vector_rad = draw(sigma.star_installation_rad);
    }
    drawn
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default scenario with a second head.
    fn two_heads() -> Scenario {
        let mut scenario = Scenario::default_scenario().unwrap();
        scenario.star_sensor.additional_heads = vec![scenario.star_sensor.head_across()];
        scenario
    }

    #[test]
    fn every_heads_installation_is_drawn_and_head_zero_keeps_its_draw() {
        let one = Scenario::default_scenario().unwrap();
        let two = two_heads();
        let sigma = one.filter.initial_sigma.star_installation_rad;
        let mut spread = 0.0;
        for seed in 0..50 {
            let one = with_truth_drawn_from_prior(&one, seed);
            let two = with_truth_drawn_from_prior(&two, seed);
            let first = two.star_sensor.installation_error_rotation_vector_rad;
            assert_eq!(
                first.map(f64::to_bits),
                one.star_sensor
                    .installation_error_rotation_vector_rad
                    .map(f64::to_bits)
            );
            assert_eq!(
                two.gyro.bias_rad_per_s.map(f64::to_bits),
                one.gyro.bias_rad_per_s.map(f64::to_bits)
            );
            let second = two.star_sensor.additional_heads[0].installation_error_rotation_vector_rad;
            assert_ne!(second.map(f64::to_bits), first.map(f64::to_bits));
            spread += second.iter().map(|x| x * x).sum::<f64>();
        }
        // 150 draws of σ²: their mean within 30 % of it.
        let variance = spread / 150.0;
        assert!((variance / (sigma * sigma) - 1.0).abs() < 0.3, "{variance}");
    }
}
