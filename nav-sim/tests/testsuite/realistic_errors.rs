//! Monte Carlo of the default flight under realistic sensor errors (docs/guide/realistic-errors.md):
//! (a) GNSS 6 m white + 8 m Gauss–Markov, τ = 300 s; (b) the same with τ = 30 s; (c) a star
//! tracker blind above 3 °/s and for 10 s after; (d) (a) with GNSS velocity at 0.05 m/s. The
//! filter is given each receiver's specification. In each: the average NEES of the 15
//! calibration states inside its two-sided 95 % χ² interval, and no run's calibration state
//! beyond 4σ of its truth; the accuracy against the paper's figures is printed.
//!
//! `NAV_MC_RUNS` sets the runs per scenario (default 4, the test command's size; the docs'
//! campaign uses 50: `NAV_MC_RUNS=50 cargo test --release -p nav-sim --test testsuite
//! realistic_errors -- --nocapture --test-threads 1`); `NAV_MC_FIRST_RUN` offsets the seeds.
//! The studies for the docs are `examples/realistic_errors.rs`.

use crate::realistic_campaign::{fly, print, scenario};
use nav_sim::campaign::monte_carlo::{calibration_labels, fly_campaign, summarise};
use nav_sim::output::report::Parameter;
use nav_sim::Scenario;

/// Largest |error| / σ any run's calibration state may end at.
const WORST_SIGMA_BOUND: f64 = 4.0;

fn assert_consistent(name: &str) {
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

#[test]
fn a_correlated_gnss_error_with_tau_300_s_keeps_the_filter_consistent() {
    assert_consistent("gnss_correlated");
}

#[test]
fn a_correlated_gnss_error_with_tau_30_s_keeps_the_filter_consistent() {
    assert_consistent("gnss_correlated_fast");
}

#[test]
fn a_rate_limited_star_tracker_keeps_the_filter_consistent() {
    assert_consistent("star_tracker_rate_limited");
}

#[test]
fn gnss_velocity_keeps_the_filter_consistent() {
    assert_consistent("gnss_correlated_velocity");
}

/// The filter's correlated-error keys are checked, and a refusal names the key.
#[test]
fn the_filter_keys_are_validated_by_name() {
    let default = nav_sim::scenario::DEFAULT_SCENARIO_TOML;
    let with = |keys: &str| {
        default.replace(
            "discretisation_order = 3\n",
            &format!("discretisation_order = 3\n{keys}\n"),
        )
    };
    for (keys, named) in [
        (
            "gnss_correlated_sigma_m = -1.0",
            "filter.gnss_correlated_sigma_m",
        ),
        (
            "gnss_correlated_sigma_m = 8.0\ngnss_correlation_time_s = 0.0",
            "filter.gnss_correlation_time_s",
        ),
        ("gnss_noise_m = 0.0", "filter.gnss_noise_m"),
    ] {
        let error = Scenario::from_toml_str(&with(keys))
            .unwrap_err()
            .to_string();
        assert!(error.contains(named), "{keys}: {error}");
    }
    let told = Scenario::from_toml_str(&with(
        "gnss_correlated_sigma_m = 8.0\ngnss_correlation_time_s = 300.0\ngnss_noise_m = 6.0",
    ))
    .unwrap();
    let config = nav_sim::setup::fsw::fsw_config(&told).unwrap();
    assert_eq!(config.filter.gnss_error.sigma_m.to_bits(), 8.0f64.to_bits());
    assert_eq!(
        config.filter.gnss_error.correlation_time_s.to_bits(),
        300.0f64.to_bits()
    );
    assert_eq!(config.gnss.noise_m.to_bits(), 6.0f64.to_bits());
}

// ---------------------------------------------------------------------------------------
// The simulator's realistic error models.

use nav_sim::logs::sensor_log::record_of;
use nav_sim::studies::faults::scenario_prefix;
use nav_sim::{SensorEvent, Simulation};

/// FNV-1a of the encoded events of a scenario's first `seconds`.
fn event_digest(scenario: &Scenario, seconds: f64) -> u64 {
    let events = Simulation::new(&scenario_prefix(scenario, seconds))
        .unwrap()
        .event_stream()
        .unwrap();
    events
        .iter()
        .fold(0xcbf2_9ce4_8422_2325_u64, |hash, event| {
            record_of(event)
                .encode()
                .unwrap()
                .iter()
                .fold(hash, |h, byte| {
                    (h ^ u64::from(*byte)).wrapping_mul(0x100_0000_01b3)
                })
        })
}

/// A scenario without the realistic-error keys produces exactly the sensor data of the
/// simulator's ideal models (digest of the first 30 s: star tracker in GCRF, GNSS in ITRF
/// tagged in GPS time).
#[test]
fn a_scenario_without_the_new_keys_gives_the_same_bits() {
    let scenario = Scenario::default_scenario().unwrap();
    assert_eq!(event_digest(&scenario, 30.0), DEFAULT_FIRST_30_S_DIGEST);
}

/// [`a_scenario_without_the_new_keys_gives_the_same_bits`]'s digest.
const DEFAULT_FIRST_30_S_DIGEST: u64 = 0x33dc_0a12_f4ba_ff58;

/// The GNSS fixes of a scenario with a correlated error minus those of the same scenario
/// without it (the white noise draws are the same): per axis.
fn correlated_error_samples(sigma_m: f64, tau_s: f64, seconds: f64) -> Vec<[f64; 3]> {
    let mut base = scenario_prefix(&Scenario::default_scenario().unwrap(), seconds);
    base.simulation.truth_substeps_per_frame = 1;
    let mut correlated = base.clone();
    correlated.gnss.correlated_noise_m = sigma_m;
    correlated.gnss.correlation_time_s = tau_s;
    let fixes = |scenario: &Scenario| -> Vec<[f64; 3]> {
        Simulation::new(scenario)
            .unwrap()
            .event_stream()
            .unwrap()
            .into_iter()
            .filter_map(|event| match event {
                SensorEvent::Gnss {
                    position_ecef_m, ..
                } => Some(position_ecef_m.into()),
                _ => None,
            })
            .collect()
    };
    fixes(&correlated)
        .iter()
        .zip(fixes(&base))
        .map(|(a, b)| [a[0] - b[0], a[1] - b[1], a[2] - b[2]])
        .collect()
}

/// The correlated GNSS error has the σ and the lag-one correlation `exp(−Δt/τ)` of its
/// model (τ = 1 s at 10 Hz over 600 s: 300 correlation times per axis).
#[test]
fn the_correlated_gnss_error_has_its_model_statistics() {
    let samples = correlated_error_samples(8.0, 1.0, 600.0);
    assert_eq!(samples.len(), 6000);
    for axis in 0..3 {
        let x: Vec<f64> = samples.iter().map(|s| s[axis]).collect();
        let n = x.len() as f64;
        let variance = x.iter().map(|v| v * v).sum::<f64>() / n;
        let lag_one = x.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / (n - 1.0) / variance;
        let sigma = variance.sqrt();
        assert!((sigma - 8.0).abs() < 0.8, "axis {axis}: sigma {sigma}");
        let expected = (-0.1_f64).exp();
        assert!(
            (lag_one - expected).abs() < 0.02,
            "axis {axis}: lag one {lag_one}"
        );
    }
}

/// The star tracker delivers nothing above `max_rate_deg_per_s` and for
/// `reacquisition_s` after; outages silence a sensor for their interval.
#[test]
fn blind_rates_and_outages_silence_the_sensors() {
    let mut scenario = scenario_prefix(&Scenario::default_scenario().unwrap(), 120.0);
    scenario.simulation.truth_substeps_per_frame = 1;
    scenario.star_sensor.max_rate_deg_per_s = 3.0;
    scenario.star_sensor.reacquisition_s = 10.0;
    scenario.gnss.outages = vec![[10.0, 5.0]];
    scenario.star_sensor.outages = vec![[100.0, 2.0]];
    let start = scenario.simulation.start_time_s;
    let events = Simulation::new(&scenario).unwrap().event_stream().unwrap();
    let star: Vec<f64> = events
        .iter()
        .filter_map(|e| match e {
            SensorEvent::Star { time_tag_s, .. } => Some(time_tag_s - start),
            _ => None,
        })
        .collect();
    let gnss: Vec<f64> = events
        .iter()
        .filter_map(|e| match e {
            SensorEvent::Gnss { time_tag_s, .. } => Some(time_tag_s - start),
            _ => None,
        })
        .collect();
    // The rotations run from 20 s to 77 s (rate above 3 °/s from 0.11 s into the first
    // ramp to 0.11 s before the last ramp ends): blind from there to 10 s after.
    assert!(star.iter().any(|t| (19.0..20.2).contains(t)));
    assert!(!star.iter().any(|t| (20.2..86.8).contains(t)), "{star:?}");
    assert!(star.iter().any(|t| (86.8..88.0).contains(t)));
    assert!(!star.iter().any(|t| (100.0..102.0).contains(t)));
    assert!(!gnss.iter().any(|t| (10.0..15.0).contains(t)));
    assert_eq!(gnss.len(), 1200 - 50);
}

/// The receiver's velocity is the truth's ITRF velocity (noise off) through the full IAU
/// 2006/2000A chain, within its round-off; nav-core's flight conversion agrees to 1e-3 m/s
/// (its frozen precession–nutation and WGS-84 rate, docs/guide/frames-and-time.md).
#[test]
fn the_gnss_velocity_is_the_true_ecef_velocity() {
    let mut scenario = scenario_prefix(&Scenario::default_scenario().unwrap(), 5.0);
    scenario.simulation.truth_substeps_per_frame = 1;
    scenario.gnss.velocity_noise_mps = 1e-300;
    let frame = nav_sim::setup::launch::launch_frame(&scenario).unwrap();
    let epoch = nav_sim::setup::launch::scenario_epoch(&scenario).unwrap();
    let itrf = nav_sim::scenario::epoch::ItrfFromLaunchInertial::new(&epoch, &frame);
    let mut simulation = Simulation::new(&scenario).unwrap();
    let mut events = Vec::new();
    let mut checked = 0;
    while let Some(truth) = simulation.step(&mut events).unwrap() {
        for event in events.drain(..) {
            if let SensorEvent::Gnss {
                velocity_ecef_mps, ..
            } = event
            {
                let (_, expected) =
                    itrf.convert(&truth.position_m, Some(&truth.velocity_mps), truth.time_s);
                let expected = expected.unwrap();
                let measured = velocity_ecef_mps.unwrap();
                assert!((measured - expected).norm() < 1e-9, "{measured} {expected}");
                let flight = frame
                    .launch_inertial_velocity_to_ecef(
                        &truth.position_m,
                        &truth.velocity_mps,
                        truth.time_s,
                    )
                    .unwrap();
                assert!((measured - flight).norm() < 1e-3, "{measured} {flight}");
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 50);
}

/// A trajectory below `simulation.min_altitude_m` is refused with the segment and the
/// time; a manoeuvre at or beyond the IMU's range is refused by name.
#[test]
fn unflyable_scenarios_are_refused_by_name() {
    let mut scenario = scenario_prefix(&Scenario::default_scenario().unwrap(), 5.0);
    scenario.simulation.min_altitude_m = 2_000_000.0;
    let Err(error) = Simulation::new(&scenario).unwrap().event_stream() else {
        panic!("a flight below its minimum altitude was accepted");
    };
    let message = error.to_string();
    assert!(
        message.contains("simulation.min_altitude_m = 2000000")
            && message.contains("manoeuvre[0] \"initial coast\"")
            && message.contains("t = 600.002 s"),
        "{message}"
    );
    let default = nav_sim::scenario::DEFAULT_SCENARIO_TOML;
    for (from, to, named) in [
        (
            "body_rate_deg_per_s = [100.0, 0.0, 0.0]",
            "body_rate_deg_per_s = [450.0, 0.0, 0.0]",
            "manoeuvre[1].body_rate_deg_per_s (segment \"rotate about body x\") must stay below \
             the gyro's range imu.max_rate_deg_per_s",
        ),
        (
            "specific_force_mps2 = [50.0, 0.0, 0.0]",
            "specific_force_mps2 = [250.0, 0.0, 0.0]",
            "must stay below the accelerometer's range imu.max_specific_force_mps2 = 200",
        ),
    ] {
        let error = Scenario::from_toml_str(&default.replacen(from, to, 1))
            .unwrap_err()
            .to_string();
        assert!(error.contains(named), "{error}");
    }
}

/// `calibrate --json` and `monte-carlo --json`: one object each with exactly the documented
/// keys, the installation error in the calibration table's unit (an angle, twice the state).
#[test]
fn json_reports_have_the_documented_shape() {
    let mut scenario = scenario_prefix(&Scenario::default_scenario().unwrap(), 30.0);
    scenario.simulation.truth_substeps_per_frame = 1;
    let result = nav_sim::harness::flight::fly(
        &scenario,
        nav_sim::harness::flight::FlightOptions::default(),
        |_, _| {},
    )
    .unwrap();
    let last = result.samples.last().unwrap().time_history();
    let table =
        nav_sim::output::report::CalibrationResult::from_sample(&last, &Parameter::CALIBRATION);
    let (_, resolved) = Scenario::default_resolved().unwrap();
    let label = nav_sim::output::scenario_label::ScenarioLabel {
        file: None,
        sha256: Some(resolved.sha256("default").unwrap()),
    };
    let report: serde_json::Value = serde_json::from_str(
        &table
            .report_json(result.calibration_nees(), &result.health, &label)
            .unwrap(),
    )
    .unwrap();
    let mut keys: Vec<&String> = report.as_object().unwrap().keys().collect();
    keys.sort();
    assert_eq!(keys, ["health", "met", "nees", "rows", "scenario"]);
    assert_eq!(report["scenario"]["file"], serde_json::Value::Null);
    assert_eq!(
        report["scenario"]["sha256"].as_str(),
        Some(resolved.sha256("default").unwrap().as_str())
    );
    assert_eq!(report["rows"].as_array().unwrap().len(), 15);
    let met = report["rows"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|row| row["met"] == serde_json::Value::Bool(true))
        .count();
    assert_eq!(report["met"].as_u64().unwrap(), met as u64);
    assert!((report["nees"].as_f64().unwrap() - result.calibration_nees().unwrap()).abs() < 1e-9);
    let health = report["health"].as_object().unwrap();
    assert_eq!(health.len(), nav_fsw::health::HEALTH_COUNTER_COUNT);
    assert_eq!(
        health["imu_missing"].as_u64().unwrap(),
        u64::from(result.health.imu_missing)
    );

    let seeds = [scenario.simulation.seed, scenario.simulation.seed + 1];
    let outcomes = fly_campaign(&scenario, &seeds, &|| {}).unwrap();
    let summary = summarise::<15, nav_sim::harness::flight::FlightError>(&outcomes).unwrap();
    let campaign: serde_json::Value =
        serde_json::from_str(&summary.json(&calibration_labels()).unwrap()).unwrap();
    let mut keys: Vec<&String> = campaign.as_object().unwrap().keys().collect();
    keys.sort();
    assert_eq!(keys, ["nees_interval_95", "nees_mean", "runs", "states"]);
    assert_eq!(campaign["runs"].as_u64().unwrap(), 2);
    let interval = campaign["nees_interval_95"].as_array().unwrap();
    assert!(interval[0].as_f64().unwrap() < 15.0 && interval[1].as_f64().unwrap() > 15.0);
    let states = campaign["states"].as_array().unwrap();
    assert_eq!(states.len(), 15);
    let installation_x = &states[6];
    assert_eq!(installation_x["parameter"], "star_installation");
    assert_eq!(installation_x["axis"], "x");
    let state_rms = summary.states[6].rms_error;
    assert!((installation_x["rms_error"].as_f64().unwrap() - 2.0 * state_rms).abs() < 1e-18);
}
