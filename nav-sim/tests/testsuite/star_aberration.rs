//! The star tracker's velocity aberration (docs/guide/sensor-errors.md, "Velocity aberration"):
//! the scenario keys reach the truth and the flight software (and the replay words); a short
//! Monte Carlo of the default flight with a tracker that leaves the aberration in shows the
//! flight software's correction consistent, and the flight software without it biased in the
//! installation error and flagged by the aberration test (`star_aberration_suspected`), no
//! healthy sensor blamed.
//!
//! One run of each (the docs' campaigns fly 20: `nav-sim monte-carlo
//! nav-sim/scenarios/star_tracker_aberration.toml --runs 20`).

use crate::common::QUIET_COUNTERS;
use crate::realistic_campaign::{scenario, worst_sigma};
use nav_sim::campaign::monte_carlo::{fly_campaign, RunOutcome};
use nav_sim::scenario::StarAberration;
use nav_sim::setup::fsw::{fsw_config, replay_setup};
use nav_sim::Scenario;

/// Runs of each case in the test command.
const RUNS: u64 = 1;

/// The installation-error state (vector part) of sensor axis x in the 15 calibration states.
const INSTALLATION_X: usize = 6;

#[test]
fn the_aberration_keys_reach_the_truth_the_flight_software_and_the_replay_words() {
    let corrected = scenario("star_tracker_aberration");
    let uncorrected = scenario("star_tracker_aberration_uncorrected");
    for (scenario, correction) in [(&corrected, true), (&uncorrected, false)] {
        assert_eq!(scenario.star_sensor.aberration, StarAberration::Uncorrected);
        assert_eq!(
            fsw_config(scenario).unwrap().star.aberration_correction,
            correction
        );
        let setup = replay_setup(scenario).unwrap();
        let decoded = nav_fsw::replay::ReplaySetup::from_words(&setup.to_words()).unwrap();
        assert_eq!(decoded.config().star.aberration_correction, correction);
    }
    // Value for value the default scenario but for the two keys.
    let mut default = Scenario::default_scenario().unwrap();
    default.star_sensor.aberration = StarAberration::Uncorrected;
    assert_eq!(format!("{default:?}"), format!("{uncorrected:?}"));
    default.filter.star_aberration_correction = true;
    assert_eq!(format!("{default:?}"), format!("{corrected:?}"));
    assert!(
        !fsw_config(&Scenario::default_scenario().unwrap())
            .unwrap()
            .star
            .aberration_correction
    );
}

/// The first [`RUNS`] seeds of `name`, flown.
fn outcomes(name: &str) -> Vec<RunOutcome> {
    let scenario = scenario(name);
    let seeds: Vec<u64> = (0..RUNS)
        .map(|run| scenario.simulation.seed.wrapping_add(run))
        .collect();
    fly_campaign(&scenario, &seeds, &|| {}).unwrap()
}

/// The installation error about sensor x in σ of the filter, signed.
fn installation_x_sigma(outcome: &RunOutcome) -> f64 {
    outcome.error[INSTALLATION_X] / outcome.covariance[(INSTALLATION_X, INSTALLATION_X)].sqrt()
}

/// Corrected (the flight software removes the aberration): every calibration state of every
/// run within 4σ, the star NIS near 3, no consistency counter, no sensor declared faulty.
/// Not corrected (the flight software as it was): the installation error about sensor x
/// ends beyond 5σ in every run (8.98–12.18σ over the docs' 20 runs), the aberration taken for
/// installation error; the aberration test says so (`star_aberration_suspected`), no other
/// consistency counter moves and no sensor is declared faulty (docs/guide/sensor-errors.md).
#[test]
fn the_corrected_aberration_keeps_the_filter_consistent_and_the_uncorrected_one_biases_it() {
    for (name, corrected) in [
        ("star_tracker_aberration", true),
        ("star_tracker_aberration_uncorrected", false),
    ] {
        for outcome in outcomes(name) {
            let counter = |key: &str| outcome.health.get(key).copied().unwrap_or(0);
            let (worst, installation) = (worst_sigma(&outcome), installation_x_sigma(&outcome));
            println!(
                "{name} seed {}: worst {worst:.2} sigma, installation x {installation:.2} sigma, \
                 star NIS {:.3}, {:?}",
                outcome.seed,
                outcome.star_nis.average(),
                outcome.health
            );
            if corrected {
                assert!(
                    worst <= 4.0,
                    "{name} seed {}: {worst:.2} sigma",
                    outcome.seed
                );
            } else {
                assert!(
                    installation.abs() > 5.0,
                    "{name} seed {}: {installation:.2}",
                    outcome.seed
                );
            }
            let star_nis = outcome.star_nis.average();
            assert!(
                (star_nis - 3.0).abs() < 0.1,
                "{name} seed {}: {star_nis}",
                outcome.seed
            );
            let flagged = counter("star_aberration_suspected");
            assert_eq!(flagged > 0, !corrected, "{name} seed {}", outcome.seed);
            for key in QUIET_COUNTERS
                .into_iter()
                .filter(|key| *key != "star_aberration_suspected")
            {
                assert_eq!(counter(key), 0, "{name} seed {}: {key}", outcome.seed);
            }
        }
    }
}
