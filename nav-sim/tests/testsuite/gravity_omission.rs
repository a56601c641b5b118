//! The omitted-field study (`nav-sim gravity-omission`, `docs/guide/gravity.md`, "The omitted field
//! as process noise") on a short flight in the 20×20 field: a flight field equal to the
//! truth's leaves only its hold error, bounded by the field's rate of change; the omitted field
//! and its process noise fall as the flight's degree rises; the periodogram stays below the
//! bound; bad input is a clear error.
//!
//! The flight is `nav-sim/scenarios/gravity_field.toml` with its manoeuvres replaced by
//! 300 s of its quiet coast, so each test flies a short truth.

use std::process::Command;

use nav_sim::setup::launch::Launch;
use nav_sim::studies::gravity_omission::{
    omitted_field, omitted_fields, FlightGravityModel, OmissionError, OmissionOptions,
    OmissionReport,
};
use nav_sim::world::gravity::{RotatingRemainder, EGM2008_GFC};
use nav_sim::world::truth::TruthSimulator;
use nav_sim::Scenario;

/// Length of the short flight's coast (s).
const COAST_S: f64 = 300.0;

/// `gravity_field.toml` (truth 20×20) with one quiet coast of [`COAST_S`].
fn short_flight() -> Scenario {
    let mut scenario = crate::realistic_campaign::scenario("gravity_field");
    let mut coast = scenario.manoeuvres[0].clone();
    assert_eq!(coast.label, "initial coast");
    coast.duration_s = COAST_S;
    scenario.manoeuvres = vec![coast];
    scenario
}

fn options(sample_s: f64) -> OmissionOptions {
    OmissionOptions {
        sample_s,
        max_lag_s: 100.0,
        report_lags_s: vec![10.0, 100.0, 1000.0],
    }
}

/// The largest `|dδg/dt|` (m/s³) of the 20×20 remainder along the short flight: `G v + ġ`
/// from the field's gradient and its rate at a fixed inertial position (the truth's Taylor
/// node), every 0.02 s. Derivatives, not the differences the study takes.
fn largest_field_rate_mps3(scenario: &Scenario) -> f64 {
    let launch = Launch::new(scenario).unwrap();
    let remainder = RotatingRemainder::new(EGM2008_GFC, 20, 20, launch.frame).unwrap();
    let mut largest: f64 = 0.0;
    for frame in TruthSimulator::from_launch(scenario, &launch).unwrap() {
        let frame = frame.unwrap();
        if frame.frame_index % 10 == 9 {
            let node = remainder
                .linearise(frame.time_s, &frame.position_m)
                .unwrap();
            let rate = node.gradient_per_s2 * frame.velocity_mps + node.rate_mps3;
            largest = largest.max(rate.norm());
        }
    }
    largest
}

/// (a) A flight field equal to the truth's (20×20), refreshed every 0.1 s and one refresh
/// late, leaves only the hold error: `d(t) = δg(t) − δg(t_r)` with `t − t_r` between 0.1 and
/// 0.2 s, so `|d| ≤ max |dδg/dt| · 2 · refresh`; and it reaches beyond `max |dδg/dt| ·
/// refresh` (the latency is modelled), where the same field without latency stays below it.
#[test]
fn a_flight_field_equal_to_the_truth_leaves_only_the_hold_error() {
    let scenario = short_flight();
    let refresh_s = 0.1;
    let late = FlightGravityModel {
        refresh_s,
        ..FlightGravityModel::new(20, 20)
    };
    let current = FlightGravityModel {
        latency_refreshes: 0,
        ..late
    };
    let j2 = FlightGravityModel::new(2, 0);
    let reports = omitted_fields(&scenario, &[late, current, j2], &options(0.02)).unwrap();
    let rate_mps3 = largest_field_rate_mps3(&scenario);
    let (late, current, j2) = (&reports[0], &reports[1], &reports[2]);
    println!(
        "max |dδg/dt| {rate_mps3:.3e} m/s³; max |d| {:.3e} (one refresh late), {:.3e} (current), \
         RMS {:.3e} vs {:.3e} m/s² with J2 only",
        late.statistics.max_mps2,
        current.statistics.max_mps2,
        late.statistics.rms_mps2,
        j2.statistics.rms_mps2
    );
    // The field changes at about |δg| · 2π n / T_orbit ~ 1e-6 m/s³ in low orbit.
    assert!((1e-7..1e-5).contains(&rate_mps3), "{rate_mps3:e}");
    assert!(late.statistics.max_mps2 <= 1.01 * rate_mps3 * 2.0 * refresh_s);
    assert!(late.statistics.max_mps2 > rate_mps3 * refresh_s);
    assert!(current.statistics.max_mps2 <= 1.01 * rate_mps3 * refresh_s);
    assert!(current.statistics.max_mps2 > 0.5 * rate_mps3 * refresh_s);
    assert!(late.statistics.rms_mps2 < 1e-2 * j2.statistics.rms_mps2);
}

fn flight_fields(fields: &[(usize, usize)]) -> Vec<OmissionReport> {
    let flights: Vec<FlightGravityModel> = fields
        .iter()
        .map(|&(degree, order)| FlightGravityModel::new(degree, order))
        .collect();
    omitted_fields(&short_flight(), &flights, &options(0.1)).unwrap()
}

/// (b) and (c): the omitted field, its bound and its periodogram fall as the flight's degree
/// rises (J2 only > 8×8 > 16×16), each periodogram lies below its bound and above the level
/// its own power implies (Parseval: the spectrum's integral over `±1/(2Δ)` is the mean square,
/// so its largest eigenvalue is at least `RMS² Δ / 3`, less the window's taper at the
/// record's ends), and the bound grows with the largest lag.
#[test]
fn omitted_field_and_its_process_noise_fall_as_the_flight_degree_rises() {
    let reports = flight_fields(&[(2, 0), (8, 8), (16, 16)]);
    for report in &reports {
        let statistics = &report.statistics;
        println!(
            "{}×{}: RMS {:.3e} m/s², max {:.3e} m/s², q_bound {:.3e}, q_periodogram {:.3e} \
             m²/s³ at {:.2e} Hz, correlation time {:?} s",
            report.flight.degree,
            report.flight.order,
            statistics.rms_mps2,
            statistics.max_mps2,
            statistics.q_bound_m2_s3,
            statistics.q_periodogram_m2_s3,
            statistics.periodogram_peak_hz,
            statistics.correlation_time_s
        );
        assert_eq!(report.samples, 3001);
        assert!(statistics.q_periodogram_m2_s3 <= statistics.q_bound_m2_s3);
        let parseval = statistics.rms_mps2.powi(2) * report.sample_s / 3.0;
        assert!(statistics.q_periodogram_m2_s3 > 0.25 * parseval);
        let bounds: Vec<f64> = statistics
            .bounds_by_lag
            .iter()
            .map(|bound| bound.q_bound_m2_s3)
            .collect();
        assert!(bounds[0] < bounds[1] && bounds[1] < bounds[2], "{bounds:?}");
        // L = 100 s is both the option and a reported lag: the same sum, bit for bit.
        assert_eq!(
            statistics.bounds_by_lag[1].q_bound_m2_s3.to_bits(),
            statistics.q_bound_m2_s3.to_bits()
        );
        // 1000 s is beyond the 300 s record: its longest lag is used.
        assert!((statistics.bounds_by_lag[2].used_lag_s - COAST_S).abs() < 1e-9);
    }
    // In low orbit the terms of degree 3..=20 are of order 1e-4 m/s² (docs/guide/model.md).
    assert!((3e-5..1e-3).contains(&reports[0].statistics.rms_mps2));
    for pair in reports.windows(2) {
        let (lower, higher) = (&pair[0].statistics, &pair[1].statistics);
        assert!(higher.rms_mps2 < 0.5 * lower.rms_mps2);
        assert!(higher.max_mps2 < lower.max_mps2);
        assert!(higher.q_bound_m2_s3 < 0.25 * lower.q_bound_m2_s3);
        assert!(higher.q_periodogram_m2_s3 < lower.q_periodogram_m2_s3);
    }
}

fn refused(flight: FlightGravityModel, options: &OmissionOptions) -> String {
    match omitted_field(&short_flight(), flight, options) {
        Err(error @ OmissionError::Setting { .. }) => error.to_string(),
        other => panic!("expected a setting error, got {other:?}"),
    }
}

/// (d) A flight field above the truth's, an order above the degree, a non-positive or
/// fractional-frame sample or refresh interval and a lag below the sample are clear errors,
/// before any flight.
#[test]
fn bad_input_is_a_clear_error() {
    let good = options(0.1);
    let cases = [
        (
            FlightGravityModel::new(21, 0),
            good.clone(),
            "flight degree = 21 must be in 2..=20",
        ),
        (
            FlightGravityModel::new(8, 9),
            good.clone(),
            "flight order = 9 must be in 0..=flight degree (8)",
        ),
        (
            FlightGravityModel::new(1, 0),
            good.clone(),
            "flight degree = 1 must be in 2..=20",
        ),
        (
            FlightGravityModel::new(8, 8),
            options(0.0),
            "sample_s = 0 must be positive",
        ),
        (
            FlightGravityModel::new(8, 8),
            options(-0.1),
            "sample_s = -0.1 must be positive",
        ),
        (
            FlightGravityModel::new(8, 8),
            options(0.003),
            "whole number of IMU frames (0.002 s)",
        ),
        (
            FlightGravityModel {
                refresh_s: 0.0,
                ..FlightGravityModel::new(8, 8)
            },
            good.clone(),
            "flight refresh_s = 0 must be positive",
        ),
        (
            FlightGravityModel {
                refresh_s: -0.1,
                ..FlightGravityModel::new(8, 8)
            },
            good.clone(),
            "flight refresh_s = -0.1 must be positive",
        ),
        (
            FlightGravityModel::new(8, 8),
            OmissionOptions {
                max_lag_s: 0.05,
                ..good.clone()
            },
            "max_lag_s = 0.05 must be finite and at least sample_s (0.1 s)",
        ),
    ];
    for (flight, options, expected) in cases {
        let message = refused(flight, &options);
        assert!(message.contains(expected), "{message:?} lacks {expected:?}");
    }
    // Without a published model the truth is J2: nothing beyond it to leave out.
    let mut j2_truth = short_flight();
    j2_truth.gravity = None;
    let error = omitted_field(&j2_truth, FlightGravityModel::new(4, 4), &good).unwrap_err();
    assert!(error.to_string().contains("must be in 2..=2"), "{error}");
    let zero = omitted_field(&j2_truth, FlightGravityModel::new(2, 0), &good).unwrap();
    assert!(zero.statistics.max_mps2 == 0.0, "{zero:?}");
    assert!(zero.statistics.q_bound_m2_s3 == 0.0, "{zero:?}");
}

/// The command prints its tables for the default flight models within the truth's field, and
/// refuses a flight degree above the truth's with the study's message.
#[test]
fn command_prints_the_table_and_refuses_a_field_above_the_truth() {
    let directory = tempfile::tempdir().unwrap();
    let path = directory.path().join("short_gravity_field.toml");
    // An overlay of the shipped file: its truth field lowered, one short coast.
    let base = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/gravity_field.toml");
    let text = format!(
        "extends = '{base}'\n[gravity]\ndegree = 8\norder = 8\n\
         [[manoeuvre]]\nlabel = \"coast\"\nduration_s = 60.0\nramp_s = 0.0\n\
         body_rate_deg_per_s = [0.0, 0.0, 0.0]\nspecific_force_mps2 = [0.0, 0.0, 0.0]\n"
    );
    std::fs::write(&path, text).unwrap();
    let run = |arguments: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_nav-sim"))
            .arg("gravity-omission")
            .arg(&path)
            .args(arguments)
            .output()
            .unwrap()
    };
    let output = run(&["--max-lag-s", "10"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{output:?}");
    assert!(
        stdout.contains("truth field 8×8, 601 samples every 0.1 s"),
        "{stdout}"
    );
    for row in ["J2 only (2, 0)", "zonal to J4 (4, 0)", "4×4", "6×6", "8×8"] {
        assert!(stdout.contains(row), "{row} missing:\n{stdout}");
    }
    assert!(!stdout.contains("12×12"), "{stdout}");
    let output = run(&["--flight-degree", "12"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("nav-sim: flight degree = 12 must be in 2..=8"),
        "{stderr}"
    );
    // Turned a quarter of the way round, the same flight crosses another field.
    let turned = run(&["--max-lag-s", "10", "--turn-deg", "90"]);
    let turned_stdout = String::from_utf8_lossy(&turned.stdout);
    assert!(turned.status.success(), "{turned:?}");
    assert!(turned_stdout.contains("601 samples"), "{turned_stdout}");
    assert_ne!(turned_stdout, stdout);
    let refused = run(&["--turn-deg", "200"]);
    assert!(!refused.status.success());
    assert!(
        String::from_utf8_lossy(&refused.stderr)
            .contains("--turn-deg 200 must be a number of degrees in -180..=180"),
        "{refused:?}"
    );
}
