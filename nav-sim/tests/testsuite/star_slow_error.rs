//! The star tracker's slowly varying error (docs/guide/sensor-errors.md, "The
//! slowly varying error in the flight filter"): told of it (`[filter.star_slow_error]`), the
//! flight software walks its installation states and stays consistent; configured as the
//! paper's (a constant installation error), it is many σ wrong and blames no sensor. No
//! innovation monitor of a single tracker can say so: the attitude absorbs the slow error
//! (docs/guide/sensor-errors.md). `NAV_MC_RUNS` runs, default 1 each here; the docs' campaigns fly
//! 20.

use crate::common::{assert_run_within_bounds, counted, nees, one_run_unless_told as campaign};
use crate::realistic_campaign::{scenario, worst_sigma};
use nav_sim::scenario::star_sensor::arcsec_to_rad;
use nav_sim::setup::fsw::{fsw_config, replay_setup};
use nav_sim::Scenario;

/// The scenario key reaches the flight software and the QEMU replay words; without it the
/// configuration is the paper's and the scenario renders (and hashes) as before the key.
#[test]
fn the_slow_error_the_flight_software_is_told_reaches_its_configuration() {
    let told = scenario("star_tracker_slow_error");
    let config = fsw_config(&told).unwrap();
    assert_eq!(
        config.star.slow_error_sigma_rad.map(f64::to_bits),
        [arcsec_to_rad(3.0).to_bits(); 3]
    );
    assert_eq!(
        config.star.slow_error_correlation_time_s.to_bits(),
        1420.0_f64.to_bits()
    );
    let setup = replay_setup(&told).unwrap();
    let decoded = nav_fsw::replay::ReplaySetup::from_words(&setup.to_words()).unwrap();
    assert_eq!(decoded.config().star, config.star);
    // The installation prior holds the walk's 2σ² beside the constant part's.
    let constant = told.filter.initial_sigma.star_installation_rad;
    let expected = (constant * constant + 2.0 * arcsec_to_rad(3.0).powi(2)).sqrt();
    assert_eq!(
        config.filter.initial.star_installation_rad.to_bits(),
        expected.to_bits()
    );
    let unmodelled = scenario("star_tracker_slow_error_unmodelled");
    let paper = fsw_config(&unmodelled).unwrap();
    assert_eq!(paper.star.slow_error_sigma_rad.map(f64::to_bits), [0; 3]);
    assert_eq!(
        paper.filter.initial.star_installation_rad.to_bits(),
        constant.to_bits()
    );
    assert!(!format!("{:?}", Scenario::default_scenario().unwrap()).contains("star_slow_error"));
    let mut refused = told;
    refused.filter.star_slow_error.correlation_time_s = 0.0;
    let message = refused.validate().unwrap_err().to_string();
    assert!(
        message.contains("filter.star_slow_error.correlation_time_s"),
        "{message}"
    );
}

/// Told of the slow error: every run within 4σ, its NEES below the χ²(15) 99.9 % point, no
/// sensor declared faulty.
#[test]
fn told_of_the_slow_error_the_calibration_stays_consistent() {
    for outcome in campaign("star_tracker_slow_error") {
        assert_run_within_bounds(&outcome);
        assert_eq!(counted(&outcome, "star_declared_faulty"), 0);
        assert_eq!(counted(&outcome, "gnss_declared_faulty"), 0);
    }
}

/// Configured as the paper's: the installation estimate is many σ from the alignment the
/// tracker has (the key matters), and the healthy tracker is not declared faulty.
#[test]
fn a_slow_error_the_flight_software_is_not_told_of_leaves_it_overconfident_and_no_sensor_blamed() {
    for outcome in campaign("star_tracker_slow_error_unmodelled") {
        let worst = worst_sigma(&outcome);
        println!(
            "seed {}: worst {worst:.2} sigma, NEES {:.1}, {:?}",
            outcome.seed,
            nees(&outcome),
            outcome.health
        );
        assert!(worst > 4.0, "seed {}: {worst:.2} sigma", outcome.seed);
        assert_eq!(counted(&outcome, "star_declared_faulty"), 0);
        assert_eq!(counted(&outcome, "gnss_declared_faulty"), 0);
    }
}
