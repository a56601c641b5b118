//! `nav-sim calibrate` on the default scenario meets every accuracy figure
//! the paper reports, on every axis, through the flight code; a scenario with made-up truth
//! errors (not the paper's: `scenarios/made_up_errors.toml`) is estimated just as well; and a
//! small Monte Carlo of the default scenario (the 50-run campaign is
//! `nav-sim monte-carlo --runs 50`, README) has its calibration NEES inside the two-sided 95 %
//! χ² interval. Each flight is the whole 3077 s scenario (1.5 M frames).

use nav_sim::campaign::monte_carlo::{fly_campaign, summarise};
use nav_sim::harness::flight::{fly, FlightOptions, FlightResult};
use nav_sim::output::report::{CalibrationResult, Parameter};
use nav_sim::Scenario;

/// χ²(15) 99.9 % point: the bound on one run's NEES of the 15 calibration states.
const CALIBRATION_NEES_BOUND: f64 = 37.70;

fn fly_whole(scenario: &Scenario) -> FlightResult {
    fly(
        scenario,
        FlightOptions {
            record_interval_s: 60.0,
        },
        |_, _| {},
    )
    .unwrap()
}

/// Every axis of every block within the paper's figure, the run consistent, neither aiding
/// sensor declared faulty.
fn assert_paper_accuracy(result: &FlightResult, case: &str) {
    let last = result.last().unwrap().time_history();
    let table = CalibrationResult::from_sample(&last, &Parameter::CALIBRATION);
    println!("{case}:\n{}", table.table());
    for row in &table.rows {
        assert_eq!(
            row.met(),
            Some(true),
            "{case}: {} {:?} error {:.3e}",
            row.parameter.name(),
            row.axis,
            row.error()
        );
    }
    let nees = result.calibration_nees().unwrap();
    println!("{case}: NEES {nees:.1}, health {:?}", result.health);
    assert!(nees < CALIBRATION_NEES_BOUND, "{case}: NEES {nees:.1}");
    assert_eq!(result.health.star_declared_faulty, 0, "{case}");
    assert_eq!(result.health.gnss_declared_faulty, 0, "{case}");
    // White receiver errors, as the filter assumes: the innovations stay white.
    assert_eq!(result.health.gnss_innovations_correlated, 0, "{case}");
    // The model is the truth's: the consistency monitor stays quiet, nothing is blamed.
    let health = &result.health;
    let quiet = [
        health.star_inconsistent,
        health.gnss_inconsistent,
        health.gnss_velocity_inconsistent,
        health.inertial_suspect,
    ];
    assert_eq!(quiet, [0; 4], "{case}");
}

#[test]
fn the_default_scenario_meets_every_accuracy_the_paper_reports() {
    let scenario = Scenario::default_scenario().unwrap();
    assert_paper_accuracy(&fly_whole(&scenario), "default scenario");
}

#[test]
fn made_up_truth_errors_are_estimated_just_as_well() {
    let made_up = crate::realistic_campaign::scenario("made_up_errors");
    let default = Scenario::default_scenario().unwrap();
    // Really different truths (every component at least 1e-5 relative away from the paper's),
    // same manoeuvres and sensors.
    let differs = |a: &[f64; 3], b: &[f64; 3]| {
        a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() > 1e-5 * y.abs().max(1e-12))
    };
    assert!(differs(
        &made_up.gyro.bias_rad_per_s,
        &default.gyro.bias_rad_per_s
    ));
    assert!(differs(
        &made_up.accelerometer.scale_factor,
        &default.accelerometer.scale_factor
    ));
    assert_eq!(made_up.manoeuvres, default.manoeuvres);
    assert_paper_accuracy(&fly_whole(&made_up), "made-up errors");
}

/// The campaign's NEES of the 15 calibration states and the NIS of both sensors (over every
/// update the gate tested, accepted or not) inside their two-sided 95 % χ² intervals.
fn assert_campaign_consistent(runs: u64) {
    let scenario = Scenario::default_scenario().unwrap();
    // The CLI's seeds: the scenario's seed, +1, +2, ... (each run's truth drawn from the prior).
    let seeds: Vec<u64> = (0..runs)
        .map(|run| scenario.simulation.seed.wrapping_add(run))
        .collect();
    let outcomes = fly_campaign(&scenario, &seeds, &|| {}).unwrap();
    let summary = summarise::<15, nav_sim::harness::flight::FlightError>(&outcomes).unwrap();
    println!("{}", summary.nees_line());
    let star = summary.star_nis.clone().unwrap();
    let gnss = summary.gnss_nis.clone().unwrap();
    println!("{}\n{}", star.line("star sensor"), gnss.line("GNSS"));
    assert!(summary.nees.consistent(), "{}", summary.nees_line());
    assert!(star.consistent(), "{}", star.line("star sensor"));
    assert!(gnss.consistent(), "{}", gnss.line("GNSS"));
}

#[test]
fn a_small_monte_carlo_of_the_default_scenario_is_consistent() {
    assert_campaign_consistent(4);
}
