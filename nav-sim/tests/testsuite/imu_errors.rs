//! Monte Carlo of the default flight with the IMU as it is (docs/guide/imu-errors.md): a bias
//! instability the flight software is told of keeps it consistent (the average NEES of the 15
//! calibration states inside its two-sided 95 % χ² interval, no run's state beyond 4σ); the
//! errors it does not model (misalignment, g-sensitivity) are flagged by the consistency
//! monitor in every run, and no healthy sensor is declared faulty for them; a flight software
//! that estimates them stays consistent in every state it estimates.
//!
//! `NAV_MC_RUNS` sets the runs (default 4, the test command's size; the docs' campaigns use
//! `nav-sim monte-carlo … --runs 20`); `NAV_MC_FIRST_RUN` offsets the seeds.

use crate::common::QUIET_COUNTERS;
use crate::realistic_campaign::{fly, print, scenario, seeds, worst_sigma};
use nav_sim::campaign::monte_carlo::{fly_campaign, summarise, RunOutcome};

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
/// software as it is (`imu_errors.toml`, two runs of the default flight;
/// `upper_stage_imu_errors.toml`, one of the upper stage; fewer if `NAV_MC_RUNS` says so):
/// every run raises a consistency counter, and neither sensor is declared faulty.
#[test]
fn unmodelled_imu_errors_are_flagged_in_every_run_and_no_sensor_is_blamed() {
    for (name, runs) in [("imu_errors", 2), ("upper_stage_imu_errors", 1)] {
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

/// With the same errors and a flight software that estimates them (`imu_errors_estimated.toml`,
/// four runs of the default flight; `upper_stage_imu_errors_estimated.toml`, two of the upper
/// stage, where the states sit beside the receiver's correlated error states): the 15
/// calibration states (against the truth in the filter's gauge) and the 12 systematic states
/// each keep their average NEES inside the two-sided 95 % χ² interval, no state of any run
/// ends beyond 4σ, no consistency counter is raised and no sensor is declared faulty.
#[test]
fn estimated_imu_errors_keep_the_filter_consistent() {
    for (name, runs) in [
        ("imu_errors_estimated", 4),
        ("upper_stage_imu_errors_estimated", 2),
    ] {
        let scenario = scenario(name);
        let mut seeds = seeds(&scenario);
        seeds.truncate(runs);
        let outcomes = fly_campaign(&scenario, &seeds, &|| {}).unwrap();
        assert_estimated_consistent(name, &outcomes);
    }
}

/// The assertions of [`estimated_imu_errors_keep_the_filter_consistent`] on one campaign.
fn assert_estimated_consistent(name: &str, outcomes: &[RunOutcome]) {
    let calibration = summarise::<15, nav_sim::harness::flight::FlightError>(outcomes).unwrap();
    println!("{name}: {}", calibration.nees_line());
    assert!(calibration.nees.consistent(), "{}", calibration.nees_line());
    let systematic: Vec<RunOutcome<12>> = outcomes
        .iter()
        .map(|outcome| {
            let imu = outcome.imu_error.as_ref().expect("the states are on");
            RunOutcome {
                seed: outcome.seed,
                error: imu.error,
                covariance: imu.covariance,
                star_nis: outcome.star_nis,
                gnss_nis: outcome.gnss_nis,
                position_error_m: outcome.position_error_m,
                over_time: Vec::new(),
                health: Default::default(),
                imu_error: None,
                gnss_error: None,
            }
        })
        .collect();
    let summary = summarise::<12, nav_sim::harness::flight::FlightError>(&systematic).unwrap();
    println!("{name}, systematic states: {}", summary.nees_line());
    assert!(summary.nees.consistent(), "{}", summary.nees_line());
    for (outcome, imu) in outcomes.iter().zip(&systematic) {
        let worst = (0..12)
            .map(|k| imu.error[k].abs() / imu.covariance[(k, k)].sqrt())
            .fold(worst_sigma(outcome), f64::max);
        assert!(
            worst <= WORST_SIGMA_BOUND,
            "{name} seed {}: {worst:.2} sigma",
            outcome.seed
        );
        println!("{name} seed {}: {:?}", outcome.seed, outcome.health);
        for key in QUIET_COUNTERS.into_iter().chain(["inertial_suspect"]) {
            assert_eq!(
                outcome.health.get(key),
                None,
                "{name} seed {}: {key}",
                outcome.seed
            );
        }
    }
}
