//! The study's input checks and the held field's refresh arithmetic (the flights themselves
//! are tested in `nav-sim/tests/testsuite/gravity_omission.rs`).

use super::trajectory::HeldField;
use super::*;

#[test]
fn flight_models_above_the_truth_are_refused() {
    let truth = (20, 20);
    assert!(check_flight(&FlightGravityModel::new(20, 20), truth).is_ok());
    assert!(check_flight(&FlightGravityModel::new(2, 0), (2, 0)).is_ok());
    for (degree, order) in [(21, 0), (1, 0), (8, 9)] {
        let error = check_flight(&FlightGravityModel::new(degree, order), truth).unwrap_err();
        assert!(matches!(error, OmissionError::Setting { .. }), "{error}");
    }
    let error = check_flight(&FlightGravityModel::new(8, 8), (20, 4)).unwrap_err();
    assert!(error.to_string().contains("truth's order (4)"), "{error}");
}

#[test]
fn intervals_must_be_whole_frames() {
    assert_eq!(whole_frames("sample_s", 0.1, 0.002).unwrap(), 50);
    assert_eq!(whole_frames("sample_s", 0.002, 0.002).unwrap(), 1);
    for bad in [0.0, -0.1, 0.003, f64::NAN, f64::INFINITY, 0.0005] {
        let error = whole_frames("sample_s", bad, 0.002).unwrap_err();
        assert!(error.to_string().starts_with("sample_s = "), "{error}");
    }
}

#[test]
fn held_value_comes_from_the_refresh_before_the_last() {
    let held = HeldField {
        remainder: None,
        refresh_frames: 50,
        latency_refreshes: 1,
    };
    // Boundary 149 lies after the refresh at 100: the value in use is the one of 50.
    assert_eq!(held.source(149), 50);
    assert_eq!(held.source(150), 100);
    // Before the second refresh, the first (at the start).
    assert_eq!(held.source(99), 0);
    let current = HeldField {
        latency_refreshes: 0,
        ..held
    };
    assert_eq!(current.source(149), 100);
    assert_eq!(gcd(50, 20), 10);
    assert_eq!(gcd(7, 0), 7);
}

/// Scaled to the lowest altitude, a sample there keeps its value and a sample 500 km higher
/// grows by the omitted field's fall with the radius: the 12 × 12 model omits degrees 13–60,
/// each falling as `(a/r)^(n+2)`, so the factor lies between `(r_h/r_l)^15` and
/// `(r_h/r_l)^62`; a model beyond the flight software's 12 × 12 has no figure.
#[test]
fn the_difference_scaled_to_the_lowest_altitude_follows_the_omitted_degrees() {
    let scenario = crate::Scenario::load(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenarios/gravity_field_modelled.toml"),
    )
    .unwrap();
    let launch = Launch::new(&scenario).unwrap();
    let flight = FlightGravityModel::new(12, 12);
    let (low_m, high_m) = (6_800_000.0, 7_300_000.0);
    let low_sigma = flight_check_sigma(&flight, &launch, low_m).unwrap();
    let sample = Vector3::new(1e-5, -2e-5, 3e-5);
    let scaled = scaled_to_lowest(
        &flight,
        &launch,
        &[sample, sample],
        &[low_m, high_m],
        low_sigma,
    )
    .unwrap();
    assert!(
        (scaled[0] - sample).norm() <= 1e-12 * sample.norm(),
        "{scaled:?}"
    );
    let factor = scaled[1].norm() / sample.norm();
    let ratio: f64 = high_m / low_m;
    assert!(
        (ratio.powi(15)..ratio.powi(62)).contains(&factor),
        "{factor} outside [{}, {}]",
        ratio.powi(15),
        ratio.powi(62)
    );
    // The direction is kept.
    assert!(scaled[1].normalize().dot(&sample.normalize()) > 1.0 - 1e-12);
    let beyond = flight_check_sigma(&FlightGravityModel::new(16, 16), &launch, low_m).unwrap();
    assert!(beyond.is_nan());
}
