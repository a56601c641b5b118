//! Monte Carlo of the default flight with the IMU as it is (docs/imu-errors.md): a bias
//! instability the flight software is told of keeps it consistent (the average NEES of the 15
//! calibration states inside its two-sided 95 % χ² interval, no run's state beyond 4σ); the
//! errors it does not model (misalignment, g-sensitivity) are flagged by the consistency
//! monitor in every run, and no healthy sensor is declared faulty for them.
//!
//! `NAV_MC_RUNS` sets the runs (default 6, the test command's size; the docs' campaigns use
//! `nav-sim monte-carlo … --runs 20`); `NAV_MC_FIRST_RUN` offsets the seeds.

use crate::realistic_campaign::{fly, print, scenario, seeds};
use nav_sim::campaign::monte_carlo::fly_campaign;

/// Largest |error| / σ any run's calibration state may end at.
const WORST_SIGMA_BOUND: f64 = 4.0;

#[test]
fn a_bias_instability_the_filter_is_told_of_keeps_it_consistent() {
    let name = "imu_bias_instability";
    let campaign = fly(&scenario(name));
    print(name, &campaign);
    assert!(campaign.consistent, "{name}: {}", campaign.nees_line);
    assert!(
        campaign.worst_sigma <= WORST_SIGMA_BOUND,
        "{name}: a calibration state ended {:.2} sigma off (seed {})",
        campaign.worst_sigma,
        campaign.worst_seed
    );
}

/// With misalignment, g-sensitivity and bias instability drawn per run and the flight
/// software as it is (`imu_errors.toml`, four runs of the default flight;
/// `upper_stage_imu_errors.toml`, two of the upper stage; fewer if `NAV_MC_RUNS` says so):
/// every run raises a consistency counter, and neither sensor is declared faulty.
#[test]
fn unmodelled_imu_errors_are_flagged_in_every_run_and_no_sensor_is_blamed() {
    for (name, runs) in [("imu_errors", 4), ("upper_stage_imu_errors", 2)] {
        let scenario = scenario(name);
        let mut seeds = seeds(&scenario);
        seeds.truncate(runs);
        let outcomes = fly_campaign(&scenario, &seeds, &|| {}).unwrap();
        for outcome in &outcomes {
            let counter = |key: &str| outcome.health.get(key).copied().unwrap_or(0);
            println!("{name} seed {}: {:?}", outcome.seed, outcome.health);
            let flagged: u32 = [
                "star_inconsistent",
                "gnss_inconsistent",
                "gnss_velocity_inconsistent",
            ]
            .iter()
            .map(|key| counter(key))
            .sum();
            assert!(flagged >= 1, "{name} seed {}: not flagged", outcome.seed);
            assert_eq!(
                counter("star_declared_faulty"),
                0,
                "{name} seed {}",
                outcome.seed
            );
            assert_eq!(
                counter("gnss_declared_faulty"),
                0,
                "{name} seed {}",
                outcome.seed
            );
        }
    }
}
