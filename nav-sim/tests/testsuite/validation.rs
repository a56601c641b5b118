//! Bad scenario input is refused before a run, with a message naming the key and the limit:
//! values that would make a run last days or produce nothing (duration, truth substeps),
//! lose the time resolution (start time), square to infinity or zero in the filter (every
//! 1σ and noise key), or exceed what the flight software can take (IMU rate, aiding rates,
//! GNSS latency). The flight software's own refusals name the scenario key too.

use nav_fsw::config::FswConfig;
use nav_fsw::{ConfigField, FswError};
use nav_sim::scenario::{
    max_imu_rate_hz, ScenarioError, DEFAULT_SCENARIO_TOML, SIGMA_RANGE, SIGMA_UNIT_MARGIN,
};
use nav_sim::setup::fsw::{configuration_error, fsw_config, scenario_key};
use nav_sim::Scenario;

/// The default scenario with the first `original` replaced by `replacement`: the refused key
/// and the whole message.
fn refusal(original: &str, replacement: &str) -> (String, String) {
    assert!(DEFAULT_SCENARIO_TOML.contains(original), "{original}");
    let text = DEFAULT_SCENARIO_TOML.replacen(original, replacement, 1);
    let error = Scenario::from_toml_str(&text).expect_err(replacement);
    let message = error.to_string();
    match error {
        ScenarioError::Invalid { key, .. } => (key, message),
        other => panic!("{replacement}: expected an Invalid error, got {other:?}"),
    }
}

/// `replacement` is refused naming `key`, and the message quotes every one of `quoted`.
fn assert_refused(original: &str, replacement: &str, key: &str, quoted: &[&str]) {
    let (refused_key, message) = refusal(original, replacement);
    assert_eq!(refused_key, key, "{message}");
    assert!(message.contains(key), "{message}");
    for text in quoted {
        assert!(
            message.contains(text),
            "{replacement}: {text} not in {message}"
        );
    }
}

fn accepted(original: &str, replacement: &str) -> Scenario {
    let text = DEFAULT_SCENARIO_TOML.replacen(original, replacement, 1);
    Scenario::from_toml_str(&text).unwrap()
}

#[test]
fn a_flight_longer_than_one_day_is_refused() {
    assert_refused(
        "duration_s = 20.0",
        "duration_s = 1e9",
        "manoeuvre[0].duration_s",
        &["= 1e9 s", "above the limit 86400 s", "one day of flight"],
    );
    // Each segment within the limit, the total (3077 − 739 + 86000 s) above it.
    assert_refused(
        "duration_s = 739.0",
        "duration_s = 86000.0",
        "manoeuvre[..].duration_s (total)",
        &["88338 s", "86400 s"],
    );
}

#[test]
fn truth_substeps_beyond_the_limit_or_the_step_budget_are_refused() {
    assert_refused(
        "truth_substeps_per_frame = 16",
        "truth_substeps_per_frame = 1000000000",
        "simulation.truth_substeps_per_frame",
        &["= 1e9 is above the limit 256"],
    );
    accepted(
        "truth_substeps_per_frame = 16",
        "truth_substeps_per_frame = 256",
    );
    // 256 substeps over a 9077 s flight at 500 Hz: 1.16e9 truth steps.
    let text = DEFAULT_SCENARIO_TOML
        .replacen(
            "truth_substeps_per_frame = 16",
            "truth_substeps_per_frame = 256",
            1,
        )
        .replacen("duration_s = 739.0", "duration_s = 6739.0", 1);
    let message = Scenario::from_toml_str(&text).unwrap_err().to_string();
    assert!(
        message.contains("simulation.truth_substeps_per_frame"),
        "{message}"
    );
    assert!(message.contains("above the limit 1e9"), "{message}");
}

#[test]
fn a_start_time_that_loses_the_frame_resolution_is_refused() {
    for start in ["1e12", "1e17"] {
        assert_refused(
            "start_time_s = 600.0",
            &format!("start_time_s = {start}"),
            "simulation.start_time_s",
            &[
                &format!("= {start} s"),
                "above the limit 1e7 s",
                "resolution",
            ],
        );
    }
    accepted("start_time_s = 600.0", "start_time_s = 1e7");
}

#[test]
fn every_sigma_key_whose_square_overflows_or_underflows_is_refused() {
    // (text in the default file, key) for every 1σ / noise key present there.
    let keys = [
        (
            "rate_noise_density_deg_per_h_per_sqrt_hz = 0.2",
            "gyro.rate_noise_density_deg_per_h_per_sqrt_hz",
        ),
        (
            "bias_random_walk_rad_per_s_per_sqrt_s = 0.0",
            "gyro.bias_random_walk_rad_per_s_per_sqrt_s",
        ),
        (
            "noise_per_sample_mps2 = 1.0e-4",
            "accelerometer.noise_per_sample_mps2",
        ),
        (
            "bias_random_walk_mps2_per_sqrt_s = 0.0",
            "accelerometer.bias_random_walk_mps2_per_sqrt_s",
        ),
        ("noise_arcsec = 10.0", "star_sensor.noise_arcsec"),
        ("noise_m = 10.0", "gnss.noise_m"),
        ("# correlated_noise_m = 0.0", "gnss.correlated_noise_m"),
        ("# velocity_noise_mps = 0.0", "gnss.velocity_noise_mps"),
    ];
    for (original, key) in keys {
        let name = original
            .trim_start_matches("# ")
            .split(" = ")
            .next()
            .unwrap();
        for bad in ["1e300", "1e-300"] {
            // A correlated error needs its correlation time to reach the σ check.
            let tau = match name {
                "correlated_noise_m" => "\ncorrelation_time_s = 300.0",
                _ => "",
            };
            assert_refused(
                original,
                &format!("{name} = {bad}{tau}"),
                key,
                &[&format!("= {bad} must be"), "[1e-100, 1e100]"],
            );
        }
    }
}

/// Every `[filter]` key is refused by the flight software's own rule (its parameter table):
/// the message names the scenario key, the flight key, its range and its unit.
#[test]
fn every_filter_key_beyond_the_flight_softwares_range_is_refused_by_its_rule() {
    let keys = [
        (
            "attitude_rad = 1.0e-3",
            "filter.initial_sigma.attitude_rad",
            "filter.initial.attitude_rad must be in [1e-9, 3.14",
        ),
        (
            "position_m = 10.0",
            "filter.initial_sigma.position_m",
            "filter.initial.position_m must be in [0.001, 1e7] m (",
        ),
        (
            "velocity_mps = 0.1",
            "filter.initial_sigma.velocity_mps",
            "[1e-6, 10000] m/s",
        ),
        (
            "gyro_bias_rad_per_s = 1.0e-3",
            "filter.initial_sigma.gyro_bias_rad_per_s",
            "[1e-12, 0.1] rad/s",
        ),
        (
            "accel_bias_mps2 = 1.0e-2",
            "filter.initial_sigma.accel_bias_mps2",
            "[1e-9, 10] m/s^2",
        ),
        (
            "star_installation_rad = 1.0e-2",
            "filter.initial_sigma.star_installation_rad",
            "filter.initial.star_installation_rad must be",
        ),
        (
            "gyro_scale_factor = 1.0e-4",
            "filter.initial_sigma.gyro_scale_factor",
            "[1e-12, 0.1] (",
        ),
        (
            "accel_scale_factor = 2.0e-4",
            "filter.initial_sigma.accel_scale_factor",
            "[1e-12, 0.1] (",
        ),
        (
            "# gnss_correlated_sigma_m = 0.0",
            "filter.gnss_correlated_sigma_m",
            "filter.gnss_error.sigma_m must be 0 (off) or in [0.001, 1000] m",
        ),
        (
            "# gnss_noise_m = 10.0",
            "filter.gnss_noise_m",
            "gnss.noise_m must be in [1e-6, 100000] m",
        ),
    ];
    for (original, key, rule) in keys {
        let name = original
            .trim_start_matches("# ")
            .split(" = ")
            .next()
            .unwrap();
        for bad in ["1e300", "1e-300"] {
            let tau = match name {
                "gnss_correlated_sigma_m" => "\ngnss_correlation_time_s = 300.0",
                _ => "",
            };
            assert_refused(
                original,
                &format!("{name} = {bad}{tau}"),
                key,
                &[&format!("= {bad} is refused by the flight software"), rule],
            );
        }
    }
}

/// The inputs the flight software's ranges were made for: a correlation time of 1e-300 s,
/// an IMU error prior of 1 rad, 255 gravity terms a frame, a hand-over after no pair.
#[test]
fn the_absurd_filter_inputs_are_refused_naming_key_range_and_unit() {
    assert_refused(
        "[filter.nis_gate]",
        "[filter.bias_instability]\ngyro_sigma_rad_per_s = 1.0e-6\n\
         gyro_correlation_time_s = 1e-300\n\n[filter.nis_gate]",
        "filter.bias_instability.gyro_correlation_time_s",
        &["= 1e-300 must be 0 (off) or in [1, 1e8] s (below 1 s"],
    );
    assert_refused(
        "[filter.nis_gate]",
        "[filter.bias_instability]\naccel_sigma_mps2 = 2.0e-5\n\n[filter.nis_gate]",
        "filter.bias_instability.accel_correlation_time_s",
        &["must not be 0 while filter.bias_instability.accel_sigma_mps2 is on"],
    );
    assert_refused(
        "[filter.nis_gate]",
        "[filter.imu_errors]\ngyro_misalignment_sigma_rad = 1.0\n\
         accel_misalignment_sigma_rad = 2.0e-5\n\
         gyro_g_sensitivity_sigma_rad_s_per_mps2 = 2.5e-7\n\n[filter.nis_gate]",
        "filter.imu_errors.gyro_misalignment_sigma_rad",
        &[
            "= 1 is refused by the flight software",
            "filter.imu_error.gyro_misalignment_sigma_rad must be 0 (off) or in [1e-9, 0.01] rad",
        ],
    );
    assert_refused(
        "[filter.nis_gate]",
        "[filter.imu_errors]\ngyro_misalignment_sigma_rad = 2.0e-5\n\n[filter.nis_gate]",
        "filter.imu_errors.accel_misalignment_sigma_rad",
        &["and not 0 while filter.imu_error.gyro_misalignment_sigma_rad is on"],
    );
    assert_refused(
        "[filter.nis_gate]",
        "[filter.gravity]\nterms_per_frame = 255\n\n[filter.nis_gate]",
        "filter.gravity.terms_per_frame",
        &["gravity.field.terms_per_frame must be in [1, 8] (the frame budget"],
    );
    assert_refused(
        "[filter.nis_gate]",
        "[filter.gravity]\ndegree = 4\norder = 5\n\n[filter.nis_gate]",
        "filter.gravity.order",
        &["gravity.field.order must be at most gravity.field.degree"],
    );
    assert_refused(
        "discretisation_order = 3",
        "discretisation_order = 3\nstar_pairs_before_hand_over = 0",
        "filter.star_pairs_before_hand_over",
        &["star.second_head.pairs_before_hand_over must be in [1, 100000] pairs"],
    );
    accepted(
        "discretisation_order = 3",
        "discretisation_order = 3\nstar_pairs_before_hand_over = 1",
    );
}

#[test]
fn the_scenarios_sigma_range_is_the_flight_softwares_with_room_for_unit_conversions() {
    let (low, high) = SIGMA_RANGE;
    let relative = |a: f64, b: f64| ((a - b) / b).abs();
    assert!(relative(low / SIGMA_UNIT_MARGIN, nav_fsw::config::SIGMA_MIN) < 1e-12);
    assert!(relative(high * SIGMA_UNIT_MARGIN, nav_fsw::config::SIGMA_MAX) < 1e-12);
}

#[test]
fn a_gnss_latency_beyond_the_flight_softwares_history_is_refused_with_the_limit() {
    assert_refused(
        "latency_s = 0.0",
        "latency_s = 0.3",
        "gnss.latency_s",
        &[
            "= 0.3 s is above the flight software's limit 0.124 s",
            "HISTORY_CAPACITY = 64 frames",
            "62 frames of latency",
        ],
    );
    assert_refused(
        "latency_s = 0.0",
        "latency_s = 0.126",
        "gnss.latency_s",
        &["0.124 s"],
    );
    accepted("latency_s = 0.0", "latency_s = 0.124");
}

#[test]
fn imu_and_aiding_rates_beyond_the_flight_softwares_limits_are_refused() {
    assert_refused(
        "rate_hz = 500.0",
        "rate_hz = 1000.0",
        "imu.rate_hz",
        &["= 1000 Hz is above the limit 630 Hz", "63 frames"],
    );
    // The first "rate_hz = 10.0" is the star sensor's, the second the receiver's.
    assert_refused(
        "rate_hz = 10.0",
        "rate_hz = 0.4",
        "star_sensor.rate_hz",
        &[
            "= 0.4 Hz is not above the limit 0.5 Hz",
            "outage_timeout_s = 2 s",
        ],
    );
    let text = DEFAULT_SCENARIO_TOML.replacen(
        "rate_hz = 10.0\n# ECEF position noise",
        "rate_hz = 0.5\n# ECEF position noise",
        1,
    );
    let message = Scenario::from_toml_str(&text).unwrap_err().to_string();
    assert!(message.contains("gnss.rate_hz = 0.5 Hz"), "{message}");
    assert!(message.contains("limit 0.5 Hz"), "{message}");
    // The history limit also keeps the IMU period above the future tolerance.
    let defaults = Scenario::default_scenario().unwrap();
    let fsw = fsw_config(&defaults).unwrap();
    assert!(max_imu_rate_hz(&fsw) < 1.0 / fsw.timing.future_tolerance_s);
}

#[test]
fn the_flight_softwares_refusals_name_the_scenario_key_and_the_limit() {
    // Set in memory, past Scenario::validate: the flight software's own check refuses them.
    let mut scenario = Scenario::default_scenario().unwrap();
    scenario.gnss.latency_s = 0.3;
    let config = fsw_config(&scenario).unwrap();
    let error = config.validate().unwrap_err();
    assert_eq!(
        error,
        FswError::InvalidConfiguration(ConfigField::MaxLatency)
    );
    let message = configuration_error(&scenario, error).to_string();
    assert!(
        message.contains("gnss.latency_s = 0.3 s is above the flight software's limit 0.124 s"),
        "{message}"
    );

    let mut scenario = Scenario::default_scenario().unwrap();
    scenario.filter.initial_sigma.position_m = 1e300;
    let error = fsw_config(&scenario).unwrap().validate().unwrap_err();
    let message = configuration_error(&scenario, error).to_string();
    assert!(message.contains("filter.initial_sigma"), "{message}");
    assert!(
        message.contains("filter.initial.position_m must be in [0.001, 1e7] m"),
        "{message}"
    );

    // A field the scenario does not set is named as the flight software's own.
    let mut config = FswConfig::paper_defaults(config.launch_site, config.sensor_frames);
    config.covariance.sigma_ceiling_factor = 0.5;
    let error = config.validate().unwrap_err();
    let ceiling = ConfigField::Parameter(nav_fsw::config::Param::SigmaCeilingFactor);
    assert_eq!(error, FswError::InvalidConfiguration(ceiling));
    assert_eq!(scenario_key(ceiling), None);
    let message = configuration_error(&scenario, error).to_string();
    assert!(
        message.contains("own setting covariance.sigma_ceiling_factor must be in [1, 1e6] ("),
        "{message}"
    );
}

#[test]
fn every_shipped_scenario_is_within_the_limits() {
    let directory = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let mut count = 0;
    for entry in std::fs::read_dir(directory).unwrap() {
        let path = entry.unwrap().path();
        if path
            .extension()
            .is_some_and(|extension| extension == "toml")
        {
            // Loaded, and the flight software accepts the configuration made from it.
            let scenario = Scenario::load(&path).unwrap();
            let config = fsw_config(&scenario).unwrap();
            assert_eq!(config.validate(), Ok(()), "{}", path.display());
            count += 1;
        }
    }
    assert!(count >= 7, "{count} scenarios");
}
