//! Every estimated state in the outputs: a short flight of the default vehicle with the
//! twelve systematic IMU error states and the three correlated GNSS error states
//! (`imu_errors_estimated.toml` with the receiver's correlated error and the filter told of
//! it). The telemetry's estimates and 1σ are the filter's, the replay CSV and the output
//! record carry the same bits, and a Monte Carlo campaign reports each block's NEES and
//! RMS / 1σ; without the blocks nothing of theirs appears.

use crate::common::{segment, short_scenario};
use nav_fsw::replay::{GNSS_ERROR_BLOCK_BIT, IMU_ERROR_BLOCK_BIT, OUTPUT_FIELD_NAMES};
use nav_fsw::scheduler::NavigationComputer;
use nav_fsw::telemetry::{GNSS_ERROR_FIELD_NAMES, IMU_ERROR_FIELD_NAMES};
use nav_sim::campaign::{fly_runs, CampaignReport};
use nav_sim::harness::filter_gauge::imu_error_vector;
use nav_sim::harness::flight::{fly_observed, FlightOptions};
use nav_sim::harness::log_replay;
use nav_sim::harness::target_replay::{run_records_on_host, FRAME_WORDS};
use nav_sim::logs::sensor_log::{self, SensorLogWriter};
use nav_sim::output::scenario_label::ScenarioLabel;
use nav_sim::scenario::FilterMode;
use nav_sim::setup::fsw::{fsw_config, replay_setup};
use nav_sim::Scenario;

/// 44 s of `imu_errors_estimated.toml`: a 5 s coast, turns about x and y at 100 °/s, 10 s of
/// thrust along x at 50 m/s², a 5 s coast; a receiver with an 8 m correlated error (τ 300 s)
/// and a filter told of it.
fn both_blocks() -> Scenario {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join("imu_errors_estimated.toml");
    let mut scenario = Scenario::load(&path).unwrap();
    let quiet = [2.4e-4; 3];
    scenario.manoeuvres = vec![
        segment("coast", 5.0, 0.0, quiet, [0.0; 3]),
        segment("rotate x", 12.0, 1.0, [100.0, 0.0, 0.0], [0.0; 3]),
        segment("rotate y", 12.0, 1.0, [0.0, 100.0, 0.0], [0.0; 3]),
        segment("thrust +x", 10.0, 1.0, [0.0; 3], [50.0, 0.0, 0.0]),
        segment("coast", 5.0, 0.0, quiet, [0.0; 3]),
    ];
    scenario.gnss.correlated_noise_m = 8.0;
    scenario.gnss.correlation_time_s = 300.0;
    scenario.filter.gnss_correlated_sigma_m = 8.0;
    scenario.filter.gnss_correlation_time_s = 300.0;
    scenario.validate().unwrap();
    scenario
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|value| value.to_bits()).collect()
}

/// The telemetry's optional states against the filter's accessors, bit for bit.
fn assert_telemetry_is_the_filters(computer: &NavigationComputer) {
    let states = computer.optional_states();
    let filter = computer.filter();
    let gnss = states.gnss_error.expect("the GNSS error states are flown");
    let gnss_covariance = filter.gnss_error().covariance();
    assert_eq!(
        bits(&gnss.estimate_m),
        bits(filter.gnss_error().estimate_m().as_slice())
    );
    let gnss_sigma: Vec<f64> = (0..3).map(|k| gnss_covariance[(k, k)].sqrt()).collect();
    assert_eq!(bits(&gnss.sigma_m), bits(&gnss_sigma));
    let imu = states.imu_error.expect("the IMU error states are flown");
    let estimate = imu_error_vector(&computer.imu_error_estimate().unwrap());
    assert_eq!(bits(&imu.estimates()), bits(estimate.as_slice()));
    let imu_covariance = filter.imu_error().covariance();
    let imu_sigma: Vec<f64> = (0..12).map(|k| imu_covariance[(k, k)].sqrt()).collect();
    assert_eq!(bits(&imu.sigmas()), bits(&imu_sigma));
}

#[test]
fn the_telemetry_carries_the_filters_optional_estimates_and_their_sigma() {
    let scenario = both_blocks();
    let mut checked = 0;
    let result = fly_observed(
        &scenario,
        fsw_config(&scenario).unwrap(),
        FlightOptions::default(),
        |_, _| {},
        |_, _| {},
        |frame, computer| {
            if frame % 997 == 0 {
                assert_telemetry_is_the_filters(computer);
                checked += 1;
            }
        },
    )
    .unwrap();
    assert_eq!(checked, 23);
    // The turn moved states from their prior: some 1σ shrank.
    let imu = result.imu_error.as_ref().unwrap();
    let settings = scenario.filter.imu_errors;
    let prior = nav_core::imu_error_states::ImuErrorModel {
        gyro_misalignment_sigma_rad: settings.gyro_misalignment_sigma_rad,
        accel_misalignment_sigma_rad: settings.accel_misalignment_sigma_rad,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: settings.gyro_g_sensitivity_sigma_rad_s_per_mps2,
    }
    .state_sigmas();
    let moved = (0..12)
        .filter(|&k| imu.covariance[(k, k)].sqrt() < 0.9 * prior[k])
        .count();
    let ratios: Vec<f64> = (0..12)
        .map(|k| imu.covariance[(k, k)].sqrt() / prior[k])
        .collect();
    assert!(moved >= 1, "{ratios:?}");
    let gnss = result.gnss_error.as_ref().unwrap();
    assert!(gnss.covariance[(0, 0)].sqrt() < 8.0);
    assert!(gnss.nees().unwrap() > 0.0);

    // Open loop: nothing is fed back, so the telemetry's IMU errors are the filter's `ε̂`.
    let mut open_loop = both_blocks();
    open_loop.filter.mode = FilterMode::OpenLoop;
    open_loop.manoeuvres.truncate(2);
    let mut moved = false;
    fly_observed(
        &open_loop,
        fsw_config(&open_loop).unwrap(),
        FlightOptions::default(),
        |_, _| {},
        |_, _| {},
        |frame, computer| {
            if frame % 1_009 == 0 {
                assert_telemetry_is_the_filters(computer);
                let imu = computer.optional_states().imu_error.unwrap();
                let estimate = computer.filter().imu_error().estimate();
                assert_eq!(bits(&imu.estimates()), bits(estimate.as_slice()));
                moved |= estimate.amax() > 0.0;
            }
        },
    )
    .unwrap();
    assert!(moved);
}

#[test]
fn the_replay_csv_and_the_output_record_carry_the_optional_estimates() {
    let scenario = both_blocks();
    let records = sensor_log::simulated_records(&scenario, 3_000).unwrap();
    let mut writer = SensorLogWriter::new(Vec::new()).unwrap();
    for record in &records {
        writer.write(record).unwrap();
    }
    let log = writer.finish().unwrap();
    let mut csv = Vec::new();
    log_replay::replay(log.as_slice(), &scenario, &mut csv).unwrap();
    let csv = String::from_utf8(csv).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let last: Vec<&str> = lines.last().unwrap().split(',').collect();
    let words = run_records_on_host(&replay_setup(&scenario).unwrap(), records).unwrap();
    let frame = &words[words.len() - FRAME_WORDS..];
    let word = |name: &str| frame[OUTPUT_FIELD_NAMES.iter().position(|n| *n == name).unwrap()];
    assert_eq!(
        word("optional_blocks"),
        GNSS_ERROR_BLOCK_BIT | IMU_ERROR_BLOCK_BIT
    );
    let names = GNSS_ERROR_FIELD_NAMES.iter().chain(&IMU_ERROR_FIELD_NAMES);
    for name in names {
        let column = header.iter().position(|c| c == name).unwrap();
        let value: f64 = last[column].parse().unwrap();
        assert_eq!(value.to_bits(), word(name), "{name}");
        let is_sigma = name.contains("_sigma_");
        assert!(
            value.is_finite() && (!is_sigma || value > 0.0),
            "{name} {value}"
        );
    }
    // The per-block order: a block's estimates, then their 1σ.
    let position = |name: &str| header.iter().position(|c| *c == name).unwrap();
    assert_eq!(
        position("accel_misalignment_sigma_xy_rad"),
        position("accel_misalignment_xy_rad") + 6
    );

    // Without the blocks: no columns of theirs, and NaN in their words.
    let plain = short_scenario();
    let records = sensor_log::simulated_records(&plain, 500).unwrap();
    let mut writer = SensorLogWriter::new(Vec::new()).unwrap();
    for record in &records {
        writer.write(record).unwrap();
    }
    let mut csv = Vec::new();
    log_replay::replay(writer.finish().unwrap().as_slice(), &plain, &mut csv).unwrap();
    let header = String::from_utf8(csv).unwrap();
    let header = header.lines().next().unwrap();
    assert!(!header.contains("gnss_error") && !header.contains("misalignment"));
    let words = run_records_on_host(&replay_setup(&plain).unwrap(), records).unwrap();
    let frame = &words[words.len() - FRAME_WORDS..];
    let first = OUTPUT_FIELD_NAMES
        .iter()
        .position(|n| *n == "optional_blocks")
        .unwrap();
    assert_eq!(frame[first], 0);
    assert!(frame[first + 1..FRAME_WORDS - 1]
        .iter()
        .all(|word| f64::from_bits(*word).is_nan()));
}

#[test]
fn the_monte_carlo_report_tests_each_optional_block_and_only_those_flown() {
    let mut scenario = both_blocks();
    scenario.manoeuvres.truncate(2);
    let records = fly_runs(&scenario, &[0, 1, 2], &|| {}).unwrap();
    let report = CampaignReport::new(&records, &ScenarioLabel::default()).unwrap();
    let imu = report.imu_error.as_ref().expect("IMU error statistics");
    let gnss = report.gnss_error.as_ref().expect("GNSS error statistics");
    assert_eq!((imu.summary.runs, gnss.summary.runs), (3, 3));
    // The NEES of each block is the mean of its runs' NEES, each from the run's own block.
    let nees: Vec<f64> = records
        .iter()
        .map(|record| record.outcome.gnss_error.as_ref().unwrap().nees().unwrap())
        .collect();
    assert_eq!(gnss.summary.nees.per_run, nees);
    assert_eq!(gnss.summary.nees.states, 3);
    for state in &gnss.summary.states {
        let ratio = state.rms_error / state.mean_sigma;
        assert!(ratio > 0.0 && ratio < 4.0, "{ratio}");
        assert!(state.mean_sigma > 0.5 && state.mean_sigma < 8.0);
    }
    let text = report.text();
    assert!(
        text.contains("correlated GNSS error (launch-inertial)"),
        "{text}"
    );
    assert!(text.contains("gnss_error.z (m)"), "{text}");
    assert!(text.contains("NEES of 3 states over 3 runs"), "{text}");
    assert!(text.contains("NEES of 12 states over 3 runs"), "{text}");
    let json: serde_json::Value = serde_json::from_str(&report.json().unwrap()).unwrap();
    assert_eq!(json["gnss_error"]["states"].as_array().unwrap().len(), 3);
    assert_eq!(json["imu_error"]["states"].as_array().unwrap().len(), 12);
    assert_eq!(
        json["gnss_error"]["nees_mean"].as_f64().unwrap().to_bits(),
        gnss.summary.nees.average.to_bits()
    );

    // A campaign without optional blocks reports none of theirs.
    let mut plain = short_scenario();
    plain.manoeuvres.truncate(1);
    let records = fly_runs(&plain, &[0, 1], &|| {}).unwrap();
    let report = CampaignReport::new(&records, &ScenarioLabel::default()).unwrap();
    assert!(report.imu_error.is_none() && report.gnss_error.is_none());
    let text = report.text();
    assert!(!text.contains("systematic") && !text.contains("correlated GNSS"));
    let json = report.json().unwrap();
    assert!(!json.contains("imu_error") && !json.contains("gnss_error"));
}
