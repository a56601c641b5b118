//! The flight's gravity beyond `J2` and its allowance for the field it omits
//! (`[filter.gravity]`, docs/guide/gravity.md), in the truth's 20 × 20 field: a flight software
//! configured as the paper's (point mass + `J2`, no allowance) is a configuration warning at
//! start-up and blames no sensor; configured with the 12 × 12 model and its derived allowance
//! it warns of nothing, and the default flight's calibration stays
//! consistent (`NAV_MC_RUNS` runs, default 2 here; the docs' campaigns fly 20).

use crate::common::first_seconds;
use crate::realistic_campaign::{scenario, seeds, worst_sigma};
use nav_sim::campaign::monte_carlo::{fly_campaign, summarise};
use nav_sim::harness::flight::{fly, FlightOptions};

fn counter(health: &nav_fsw::health::HealthCounters, key: &str) -> u32 {
    health
        .named()
        .iter()
        .find(|(name, _)| *name == key)
        .map_or(0, |(_, count)| *count)
}

/// A model with no allowance is a configuration warning at start-up
/// (`ConfigurationWarnings::gravity_without_allowance`), never a flight event: neither it nor
/// the modelled configuration counts `gravity_allowance_short`, the modelled configuration
/// warns of nothing, and no sensor is declared faulty either way. The modelled configuration
/// in the J2 truth (a flight model beyond the truth's field) is refused before it flies.
#[test]
fn a_gravity_model_without_its_allowance_is_a_configuration_warning_and_no_sensor_blamed() {
    let modelled = scenario("gravity_field_modelled");
    let mut modelled_in_j2_truth = modelled.clone();
    modelled_in_j2_truth.gravity = None;
    let refused = modelled_in_j2_truth.validate().unwrap_err().to_string();
    assert!(refused.contains("filter.gravity.degree = 12"), "{refused}");
    for (name, scenario, warned) in [
        (
            "gravity_field (J2, no allowance)",
            scenario("gravity_field"),
            true,
        ),
        ("gravity_field_modelled", modelled, false),
    ] {
        let config = nav_sim::setup::fsw::fsw_config(&scenario).unwrap();
        let warnings = nav_fsw::health::ConfigurationWarnings::of(&config);
        assert_eq!(warnings.gravity_without_allowance, warned, "{name}");
        let flight = fly(
            &first_seconds(scenario, 400.0),
            FlightOptions::default(),
            |_, _| {},
        )
        .unwrap();
        let health = &flight.health;
        println!("{name}: {:?}", health.named());
        assert_eq!(counter(health, "gravity_allowance_short"), 0, "{name}");
        assert_eq!(counter(health, "gravity_field_errors"), 0, "{name}");
        assert_eq!(counter(health, "star_declared_faulty"), 0, "{name}");
        assert_eq!(counter(health, "gnss_declared_faulty"), 0, "{name}");
    }
}

/// The default flight in the 20 × 20 field with the 12 × 12 model and its allowance: every
/// run's calibration within 4σ and its NEES below the χ²(15) 99.9 % point, and the average
/// NEES inside its 95 % interval when the campaign has the docs' size.
#[test]
fn the_modelled_field_keeps_the_calibration_consistent() {
    let scenario = scenario("gravity_field_modelled");
    let mut seeds = seeds(&scenario);
    if std::env::var_os("NAV_MC_RUNS").is_none() {
        seeds.truncate(2);
    }
    let outcomes = fly_campaign(&scenario, &seeds, &|| {}).unwrap();
    let summary = summarise::<15, nav_sim::harness::flight::FlightError>(&outcomes).unwrap();
    println!("{}", summary.nees_line());
    for outcome in &outcomes {
        let worst = worst_sigma(outcome);
        let nees = crate::common::nees(outcome);
        let counted = |key: &str| outcome.health.get(key).copied().unwrap_or(0);
        assert_eq!(
            counted("gravity_allowance_short"),
            0,
            "seed {}",
            outcome.seed
        );
        assert_eq!(counted("star_declared_faulty"), 0, "seed {}", outcome.seed);
        assert_eq!(counted("gnss_declared_faulty"), 0, "seed {}", outcome.seed);
        println!(
            "seed {}: worst {worst:.2} sigma, NEES {nees:.1}",
            outcome.seed
        );
        assert!(worst <= 4.0, "seed {}: {worst:.2} sigma", outcome.seed);
        assert!(nees < 37.70, "seed {}: NEES {nees:.1}", outcome.seed);
    }
    if outcomes.len() >= 20 {
        assert!(summary.nees.consistent(), "{}", summary.nees_line());
    }
}
