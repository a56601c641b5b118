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
