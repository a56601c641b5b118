//! The `[dispersion]` table: absent, a campaign flies the same bits as the undispersed path;
//! present, each run's truth carries its own draws while the flight software keeps the
//! scenario's configuration, and run k alone equals run k of a campaign; a bad entry is
//! refused naming its key.

use nav_core::attitude;
use nav_sim::campaign::monte_carlo::{fly_campaign, RunOutcome};
use nav_sim::harness::flight::{fly, FlightOptions};
use nav_sim::scenario::dispersion::{Dispersion, Distribution, ENTRY_KEYS};
use nav_sim::scenario::{ScenarioError, DEFAULT_SCENARIO_TOML};
use nav_sim::setup::dispersion::{draw, truth_scenario};
use nav_sim::setup::fsw::{fsw_config, replay_setup};
use nav_sim::setup::prior::with_truth_drawn_from_prior;
use nav_sim::Scenario;

use crate::common;

const SEEDS: [u64; 2] = [4242, 4243];

fn bits(outcome: &RunOutcome) -> Vec<u64> {
    outcome
        .error
        .iter()
        .chain(outcome.covariance.iter())
        .map(|value| value.to_bits())
        .chain([outcome.position_error_m.to_bits()])
        .collect()
}

fn dispersed() -> Scenario {
    let mut scenario = common::short_scenario();
    scenario.dispersion = Some(Dispersion {
        initial_attitude_deg: Some(Distribution::Normal { sigma: 0.01 }),
        initial_position_m: Some(Distribution::Uniform { half_width: 5.0 }),
        star_noise_percent: Some(Distribution::Uniform { half_width: 20.0 }),
        gyro_noise_percent: Some(Distribution::Normal { sigma: 10.0 }),
        star_mounting_deg: Some(Distribution::Normal { sigma: 0.005 }),
        gnss_latency_frames: Some(3),
        ..Dispersion::default()
    });
    scenario.validate().unwrap();
    scenario
}

#[test]
fn without_a_dispersion_table_a_campaign_flies_the_undispersed_bits() {
    let scenario = common::short_scenario();
    assert!(!format!("{scenario:?}").contains("dispersion"));
    let outcomes = fly_campaign(&scenario, &SEEDS, &|| {}).unwrap();
    for (outcome, seed) in outcomes.iter().zip(SEEDS) {
        let seeded = with_truth_drawn_from_prior(&scenario, seed);
        assert_eq!(truth_scenario(&seeded, seed), seeded);
        let result = fly(&seeded, FlightOptions::default(), |_, _| {}).unwrap();
        let expected = RunOutcome::of_flight(seed, &result);
        assert_eq!(bits(outcome), bits(&expected), "seed {seed}");
    }
}

#[test]
fn each_run_draws_its_own_truth_and_keeps_the_filters_configuration() {
    let scenario = dispersed();
    let Some(dispersion) = scenario.dispersion.clone() else {
        panic!("the scenario has a dispersion table");
    };
    let undispersed = Scenario {
        dispersion: None,
        ..scenario.clone()
    };
    let mut mountings = Vec::new();
    for seed in SEEDS {
        let draw = draw(&dispersion, seed);
        let seeded = with_truth_drawn_from_prior(&scenario, seed);
        let truth = truth_scenario(&seeded, seed);
        let expected_noise =
            scenario.star_sensor.noise_arcsec * (1.0 + draw.star_noise_percent / 100.0);
        assert_eq!(
            truth.star_sensor.noise_arcsec.to_bits(),
            expected_noise.to_bits()
        );
        assert!(draw.star_noise_percent.abs() <= 20.0);
        assert!(draw.gnss_latency_frames <= 3);
        for axis in 0..3 {
            let expected = scenario.star_sensor.mounting_rotation_vector_deg[axis]
                + draw.star_mounting_deg[axis];
            assert_eq!(
                truth.star_sensor.mounting_rotation_vector_deg[axis].to_bits(),
                expected.to_bits()
            );
        }
        mountings.push(
            truth
                .star_sensor
                .mounting_rotation_vector_deg
                .map(f64::to_bits),
        );
        // The flight software's configuration is the undispersed scenario's.
        let config = nav_sim::setup::fsw::run_config(&seeded, &truth).unwrap();
        let nominal = fsw_config(&with_truth_drawn_from_prior(&undispersed, seed)).unwrap();
        assert_eq!(
            config.star.noise_rad.to_bits(),
            nominal.star.noise_rad.to_bits()
        );
        assert_eq!(
            config.star.mounting_wxyz.map(f64::to_bits),
            nominal.star.mounting_wxyz.map(f64::to_bits)
        );
        assert_eq!(config.process_noise, nominal.process_noise);

        // The initial navigation error is the σ draw plus the dispersion's offset.
        let frame = nav_sim::setup::launch::launch_frame(&seeded).unwrap();
        let start = nav_sim::setup::launch::initial_state(&seeded, &frame).unwrap();
        let error = |scenario: &Scenario| {
            let initial = replay_setup(scenario).unwrap().initial;
            let attitude = attitude::log_rotation_vector(&attitude::product(
                &attitude::conjugate(&start.attitude_q_ib),
                &initial.attitude,
            ));
            (attitude, initial.position_m - start.position_m)
        };
        let undispersed_seeded = with_truth_drawn_from_prior(&undispersed, seed);
        let (attitude, position) = error(&seeded);
        let (base_attitude, base_position) = error(&undispersed_seeded);
        for axis in 0..3 {
            let added_rad = attitude[axis] - base_attitude[axis];
            let drawn_rad = draw.initial_attitude_deg[axis].to_radians();
            assert!(
                (added_rad - drawn_rad).abs() < 1e-12,
                "{added_rad} vs {drawn_rad}"
            );
            let added_m = position[axis] - base_position[axis];
            assert!((added_m - draw.initial_position_m[axis]).abs() < 1e-6);
            assert!(draw.initial_position_m[axis].abs() <= 5.0);
        }
    }
    // Runs differ by their draws.
    assert_ne!(mountings[0], mountings[1]);
}

#[test]
fn run_k_alone_equals_run_k_of_the_campaign() {
    let scenario = dispersed();
    let campaign = fly_campaign(&scenario, &SEEDS, &|| {}).unwrap();
    let alone = fly_campaign(&scenario, &SEEDS[1..], &|| {}).unwrap();
    assert_eq!(bits(&campaign[1]), bits(&alone[0]));
    let undispersed = Scenario {
        dispersion: None,
        ..scenario
    };
    let plain = fly_campaign(&undispersed, &SEEDS[1..], &|| {}).unwrap();
    assert_ne!(bits(&campaign[1]), bits(&plain[0]));
}

fn invalid_key(table: &str) -> String {
    let text = format!("{DEFAULT_SCENARIO_TOML}\n[dispersion]\n{table}\n");
    match Scenario::from_toml_str(&text) {
        Err(ScenarioError::Invalid { key, .. }) => key,
        other => panic!("expected an Invalid error, got {other:?}"),
    }
}

#[test]
fn a_bad_entry_is_refused_naming_its_key() {
    assert_eq!(
        invalid_key("star_noise_percent = { kind = \"normal\", sigma = -1.0 }"),
        "dispersion.star_noise_percent.sigma"
    );
    assert_eq!(
        invalid_key("initial_position_m = { kind = \"uniform\", half_width = nan }"),
        "dispersion.initial_position_m.half_width"
    );
    assert_eq!(
        invalid_key("gnss_latency_frames = 1000"),
        "dispersion.gnss_latency_frames"
    );
    let text = format!(
        "{DEFAULT_SCENARIO_TOML}\n[dispersion]\ngyro_noise_percent = {{ kind = \"cauchy\", sigma = 1.0 }}\n"
    );
    let message = Scenario::from_toml_str(&text).unwrap_err().to_string();
    assert!(message.contains("cauchy"), "{message}");
    let text = format!("{DEFAULT_SCENARIO_TOML}\n[dispersion]\ngyro_noise_pct = 1\n");
    let message = Scenario::from_toml_str(&text).unwrap_err().to_string();
    assert!(message.contains("gyro_noise_pct"), "{message}");
    let text = format!(
        "{DEFAULT_SCENARIO_TOML}\n[dispersion]\ngnss_latency_frames = 3\n\
         star_mounting_deg = {{ kind = \"uniform\", half_width = 0.01 }}\n"
    );
    assert!(Scenario::from_toml_str(&text).unwrap().dispersion.is_some());
}

/// Every width has an upper bound, named with its reason: σ = 1e300 on the initial position
/// would give an infinite initial error, and a campaign that fuses nothing.
#[test]
fn a_width_beyond_its_bound_is_refused_naming_the_key_and_the_bound() {
    for (table, key, bound) in [
        (
            "initial_position_m = { kind = \"normal\", sigma = 1.0e300 }",
            "dispersion.initial_position_m.sigma",
            "at most 1000000 (1000 km off is another orbit",
        ),
        (
            "initial_velocity_mps = { kind = \"uniform\", half_width = 1.0e4 }",
            "dispersion.initial_velocity_mps.half_width",
            "at most 1000 (",
        ),
        (
            "initial_attitude_deg = { kind = \"normal\", sigma = 200.0 }",
            "dispersion.initial_attitude_deg.sigma",
            "at most 180 (",
        ),
        (
            "gnss_noise_percent = { kind = \"normal\", sigma = 1.0e5 }",
            "dispersion.gnss_noise_percent.sigma",
            "at most 1000 (a factor of 11",
        ),
        (
            "gyro_misalignment_rad = { kind = \"normal\", sigma = 0.1 }",
            "dispersion.gyro_misalignment_rad.sigma",
            "at most 0.01 (",
        ),
    ] {
        assert_eq!(invalid_key(table), key, "{table}");
        let text = format!("{DEFAULT_SCENARIO_TOML}\n[dispersion]\n{table}\n");
        let message = Scenario::from_toml_str(&text).unwrap_err().to_string();
        assert!(message.contains(bound), "{message}");
    }
    // At the bound it is accepted.
    let text = format!(
        "{DEFAULT_SCENARIO_TOML}\n[dispersion]\n\
         initial_position_m = {{ kind = \"normal\", sigma = 1.0e6 }}\n"
    );
    assert!(Scenario::from_toml_str(&text).is_ok());
}

#[test]
fn the_default_scenarios_commented_example_parses_when_uncommented() {
    let start = DEFAULT_SCENARIO_TOML.find("# [dispersion]").unwrap();
    let (flight, example) = DEFAULT_SCENARIO_TOML.split_at(start);
    let uncommented: String = example
        .lines()
        .filter_map(|line| line.strip_prefix("# "))
        .filter(|line| {
            *line == "[dispersion]"
                || ENTRY_KEYS.contains(&line.split(' ').next().unwrap_or_default())
        })
        .map(|line| format!("{line}\n"))
        .collect();
    let scenario = Scenario::from_toml_str(&format!("{flight}{uncommented}")).unwrap();
    let Some(dispersion) = scenario.dispersion else {
        panic!("the uncommented example has a dispersion table");
    };
    assert_eq!(dispersion.gnss_latency_frames, Some(5));
    assert!(dispersion.gnss_correlation_time_percent.is_some());
    assert!(dispersion.initial_attitude_deg.is_some());
}
