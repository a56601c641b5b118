//! Ground commands scheduled by a scenario (`[[command]]`), flown through the flight
//! software's command interface: a campaign that resets the filter mid-flight (keeping the
//! calibration, or dropping it), reboots it with its calibration carried over in a record,
//! or flies without GNSS for a while, stays consistent
//! (average NEES of the 15 calibration states inside its two-sided 95 % χ² interval over 40
//! runs of the short scenario, truth drawn from the filter's prior, as `consistency.rs`
//! checks the same flight without commands); a schedule that cannot fly is refused naming
//! its key.

use nav_sim::campaign::monte_carlo::{fly_campaign, summarise};
use nav_sim::scenario::commands::{AidName, CommandKind, ScheduledCommand};
use nav_sim::Scenario;

use crate::common;

fn command(at_s: f64, command: CommandKind) -> ScheduledCommand {
    ScheduledCommand {
        at_s,
        command,
        block: None,
        aid: None,
        head: None,
    }
}

fn nees_over_forty_runs_is_consistent(scenario: &Scenario) {
    scenario.validate().unwrap();
    let seeds: Vec<u64> = (0..40).map(|run| 1000 + run).collect();
    let outcomes = fly_campaign(scenario, &seeds, &|| {}).unwrap();
    let summary = summarise::<15, nav_sim::harness::flight::FlightError>(&outcomes).unwrap();
    println!("{}", summary.nees_line());
    assert!(summary.nees.consistent(), "{}", summary.nees_line());
}

#[test]
fn a_campaign_that_resets_keeping_the_calibration_and_loses_gnss_stays_consistent() {
    let mut scenario = common::short_scenario();
    scenario.commands = vec![
        ScheduledCommand {
            aid: Some(AidName::Gnss),
            ..command(5.0, CommandKind::DisableAid)
        },
        ScheduledCommand {
            aid: Some(AidName::Gnss),
            ..command(15.0, CommandKind::EnableAid)
        },
        command(25.0, CommandKind::ResetFilterKeepingCalibration),
    ];
    nees_over_forty_runs_is_consistent(&scenario);
}

#[test]
fn a_campaign_that_resets_dropping_the_calibration_stays_consistent() {
    let mut scenario = common::short_scenario();
    scenario.commands = vec![command(5.0, CommandKind::ResetFilterDroppingCalibration)];
    nees_over_forty_runs_is_consistent(&scenario);
}

#[test]
fn a_schedule_that_cannot_fly_is_refused_naming_its_key() {
    let mut scenario = common::short_scenario();
    scenario.commands = vec![command(100.0, CommandKind::ClearSensorFaults)];
    let error = scenario.validate().unwrap_err().to_string();
    assert!(
        error.contains("command[0].at_s must be in [0, 42]"),
        "{error}"
    );
    scenario.commands = vec![
        command(1.0, CommandKind::ClearSensorFaults),
        command(2.0, CommandKind::FreezeBlock),
    ];
    let error = scenario.validate().unwrap_err().to_string();
    assert!(error.contains("command[1].block is required"), "{error}");
    // A command the flight software refuses ends the flight with its reason.
    scenario.commands = vec![ScheduledCommand {
        head: Some(1),
        ..command(2.0, CommandKind::SelectStarHead)
    }];
    let options = nav_sim::harness::flight::FlightOptions::default();
    let error = nav_sim::harness::flight::fly(&scenario, options, |_, _| {})
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("command[0]") && error.contains("head 1"),
        "{error}"
    );
}

/// `save_calibration` and `load_calibration` go through the vehicle's memory: a load with
/// nothing saved is refused naming the empty store; saved first, the load flies, and the
/// flight ends with the calibration of a filter reset keeping the calibration, bit for bit
/// (the load restarts the navigation from its prior with the reset's covariance bound; the
/// convergence tests it also restarts have passed no block by then).
#[test]
fn a_scheduled_load_needs_a_saved_record_and_then_flies_as_a_reset_keeping_the_calibration() {
    let options = nav_sim::harness::flight::FlightOptions::default;
    let mut scenario = common::short_scenario();
    scenario.commands = vec![command(5.0, CommandKind::LoadCalibration)];
    let error = nav_sim::harness::flight::fly(&scenario, options(), |_, _| {})
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("command[0]") && error.contains("holds no record"),
        "{error}"
    );
    scenario.commands = vec![
        command(10.0, CommandKind::SaveCalibration),
        command(10.0, CommandKind::LoadCalibration),
    ];
    let loaded = nav_sim::harness::flight::fly(&scenario, options(), |_, _| {}).unwrap();
    scenario.commands = vec![command(10.0, CommandKind::ResetFilterKeepingCalibration)];
    let reset = nav_sim::harness::flight::fly(&scenario, options(), |_, _| {}).unwrap();
    let bits = |result: &nav_sim::harness::flight::FlightResult| {
        result.calibration_error.map(f64::to_bits)
    };
    assert_eq!(bits(&loaded), bits(&reset));
    assert_eq!(
        loaded.calibration_covariance.map(f64::to_bits),
        reset.calibration_covariance.map(f64::to_bits)
    );
}

/// A flight rebooted half way (mid-rotation, the hardest moment: the calibration is most
/// correlated with the attitude), its calibration carried over in a record: consistent over
/// 40 runs, and every calibration state ends within 1σ of the uninterrupted flight's
/// estimate (RMS over the runs of the difference over the rebooted flight's own σ).
#[test]
fn a_flight_rebooted_half_way_ends_within_one_sigma_of_the_uninterrupted_flight() {
    let uninterrupted = common::short_scenario();
    let mut rebooted = uninterrupted.clone();
    rebooted.commands = vec![command(21.0, CommandKind::RebootKeepingCalibration)];
    nees_over_forty_runs_is_consistent(&rebooted);
    let seeds: Vec<u64> = (0..40).map(|run| 1000 + run).collect();
    let plain = fly_campaign(&uninterrupted, &seeds, &|| {}).unwrap();
    let interrupted = fly_campaign(&rebooted, &seeds, &|| {}).unwrap();
    for state in 0..15 {
        let mean_square = plain
            .iter()
            .zip(&interrupted)
            .map(|(a, b)| {
                let difference = a.error[state] - b.error[state];
                difference * difference / b.covariance[(state, state)]
            })
            .sum::<f64>()
            / seeds.len() as f64;
        println!(
            "state {state}: RMS difference / σ = {:.3}",
            mean_square.sqrt()
        );
        assert!(mean_square.sqrt() < 1.0, "state {state}");
    }
}
