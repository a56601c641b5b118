//! Two star-tracker heads 90° apart, head 0 blind for the middle third of the flight
//! (docs/guide/sensor-errors.md, "Two heads"): told of the second head, the flight software aligns
//! it from simultaneous pairs, hands its installation block to it for the outage and back,
//! and stays consistent; configured with one head, it counts the second head's measurements
//! as from a head it lacks and blames no sensor. `NAV_MC_RUNS` runs, default 1 each here; the
//! docs' campaigns fly 20.

use crate::common::QUIET_COUNTERS;
use crate::common::{assert_run_within_bounds, counted, one_run_unless_told as campaign};
use crate::realistic_campaign::scenario;
use nav_sim::scenario::star_sensor::arcsec_to_rad;
use nav_sim::setup::fsw::{fsw_config, replay_setup};

/// The scenario's first additional head reaches the flight software's configuration and the
/// QEMU replay words; `[filter] star_second_head = false` leaves the flight software one head.
#[test]
fn the_second_head_reaches_the_flight_software_and_the_replay_words() {
    let told = scenario("star_tracker_two_heads");
    let config = fsw_config(&told).unwrap();
    let head = config.star.second_head.unwrap();
    assert_eq!(head.noise_rad.to_bits(), arcsec_to_rad(5.0).to_bits());
    assert_eq!(head.roll_noise_rad.to_bits(), arcsec_to_rad(35.0).to_bits());
    // Boresight (sensor z) along body +y: exp(−90° about body x).
    let [w, x, y, z] = head.mounting_wxyz;
    let half = std::f64::consts::FRAC_PI_4;
    assert!((w - half.cos()).abs() < 1e-15 && (x + half.sin()).abs() < 1e-15);
    assert!(y.abs() < 1e-15 && z.abs() < 1e-15);
    let prior = std::f64::consts::SQRT_2 * config.filter.initial.star_installation_rad;
    assert_eq!(head.alignment_prior_sigma_rad.to_bits(), prior.to_bits());
    let setup = replay_setup(&told).unwrap();
    let decoded = nav_fsw::replay::ReplaySetup::from_words(&setup.to_words()).unwrap();
    assert_eq!(decoded.config().star, config.star);
    let one_head = fsw_config(&scenario("star_tracker_two_heads_unmodelled")).unwrap();
    assert_eq!(one_head.star.second_head, None);
}

/// Told of the second head: every run within 4σ, its NEES below the χ²(15) 99.9 % point, the
/// installation handed to head 1 for head 0's outage and back, no monitor raised and no
/// sensor declared faulty.
#[test]
fn told_of_the_second_head_the_calibration_stays_consistent_through_the_outage() {
    for outcome in campaign("star_tracker_two_heads") {
        assert_run_within_bounds(&outcome);
        assert_eq!(counted(&outcome, "star_head_handovers"), 2);
        assert_eq!(counted(&outcome, "star_outages"), 1);
        for key in QUIET_COUNTERS {
            assert_eq!(counted(&outcome, key), 0, "seed {}: {key}", outcome.seed);
        }
    }
}

/// Configured with one head: the second head's measurements are counted as from a head the
/// flight software lacks (every one of them), and no sensor is declared faulty.
#[test]
fn configured_with_one_head_the_second_is_counted_and_no_sensor_blamed() {
    for outcome in campaign("star_tracker_two_heads_unmodelled") {
        println!("seed {}: {:?}", outcome.seed, outcome.health);
        // Head 1 delivers at 10 Hz over the whole 3077 s flight.
        assert_eq!(counted(&outcome, "star_unknown_head"), 30_770);
        assert_eq!(counted(&outcome, "star_head_handovers"), 0);
        assert_eq!(counted(&outcome, "star_declared_faulty"), 0);
        assert_eq!(counted(&outcome, "gnss_declared_faulty"), 0);
    }
}
