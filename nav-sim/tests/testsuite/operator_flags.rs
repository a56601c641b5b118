//! Flags an operator can act on: an error of the inertial solution is blamed on the
//! inertial solution, never on the healthy star tracker. Two default flights (the false-alarm
//! rates on clean flights: `nav-sim false-alarms`, docs/results/false-alarms-*.md).

use nav_sim::campaign::monte_carlo::{fly_campaign, RunOutcome};
use nav_sim::harness::flight::{fly_observed, FlightOptions};
use nav_sim::setup::fsw::fsw_config;
use nav_sim::Scenario;

use crate::common::counted;

/// 0.7 °/h/g in rad/s per m/s² (1 °/h/g = 4.848e-6 / 9.80665 = 4.94e-7).
const G_SENSITIVITY_RAD_S_PER_MPS2: f64 = 0.7 * 4.943_8e-7;

/// The most star measurements the gate may refuse on the flight with the g-sensitivity, as a
/// multiple of the clean flight's: its burns move the attitude faster than the filter's
/// process noise allows, so its innovations are larger than their covariance says while the
/// burns last and exceed the gate more often than the clean flight's 0.1 %.
const REJECTIONS_OVER_CLEAN: u32 = 5;

/// The default flight's first run.
fn first_run(scenario: &Scenario) -> RunOutcome {
    let outcomes = fly_campaign(scenario, &[scenario.simulation.seed], &|| {}).unwrap();
    outcomes.into_iter().next().unwrap()
}

/// A gyro g-sensitivity of 0.7 °/h/g the flight software is not told of, on the default
/// flight: the inertial solution is suspected (`inertial_suspect`), the star tracker is never
/// deweighted (the noise in use is the configured noise in every frame, the matching never
/// engaged) nor declared faulty, and the gate refuses at most [`REJECTIONS_OVER_CLEAN`]
/// times the clean flight's star measurements.
#[test]
fn an_unmodelled_g_sensitivity_is_blamed_on_the_inertial_solution_not_the_tracker() {
    let clean = Scenario::default_scenario().unwrap();
    let clean_rejections = counted(&first_run(&clean), "star_gate_rejections");
    let mut scenario = clean.clone();
    scenario.gyro.g_sensitivity_rad_s_per_mps2 = [G_SENSITIVITY_RAD_S_PER_MPS2; 3];
    let config = fsw_config(&scenario).unwrap();
    let configured = [
        config.star.noise_rad,
        config.star.noise_rad,
        config.star.roll_noise_rad,
    ];
    let mut deweighted_frames = 0_u64;
    let result = fly_observed(
        &scenario,
        config,
        FlightOptions::default(),
        |_, _| {},
        |_, _| {},
        |_, computer| {
            let used = computer.star_noise_rad();
            if used
                .iter()
                .zip(&configured)
                .any(|(u, c)| u.to_bits() != c.to_bits())
            {
                deweighted_frames += 1;
            }
        },
    )
    .unwrap();
    let health = result.health;
    println!("clean star rejections {clean_rejections}; with the g-sensitivity {health:?}");
    assert!(health.inertial_suspect > 0);
    assert_eq!(deweighted_frames, 0, "the tracker's noise was widened");
    assert_eq!(health.star_noise_matched, 0);
    assert_eq!(health.star_declared_faulty, 0);
    assert_eq!(health.gnss_declared_faulty, 0);
    assert!(
        health.star_gate_rejections <= REJECTIONS_OVER_CLEAN * clean_rejections,
        "{} star rejections against {clean_rejections} on the clean flight",
        health.star_gate_rejections
    );
}
