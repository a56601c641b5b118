//! What leaving each Earth orientation parameter out of the ground constants costs the
//! default flight: the sensors are simulated with the day's values, the flight software is
//! configured from a scenario with UT1 − UTC or polar motion zeroed (and, to show the scale,
//! with UT1 − UTC wrong by 0.5 s). Prints the final attitude and position errors, the NEES of
//! the calibration states and the gate rejections; checks that the day's values fly.
//! A measurement for docs/guide/frames-and-time.md, about 10 s a flight in release:
//! `cargo run --release -p nav-sim --example earth_orientation_cost`.

use nalgebra::Vector3;
use nav_sim::harness::flight::{fly_with, FlightOptions};
use nav_sim::scenario::epoch::EarthOrientation;
use nav_sim::setup::fsw::fsw_config;
use nav_sim::Scenario;

/// Radians per arcsecond.
const ARCSEC: f64 = 1.0 / 206_264.806_247_096_36;

fn main() {
    let scenario = Scenario::default_scenario().unwrap();
    type Change = fn(&mut EarthOrientation);
    let cases: [(&str, Change); 7] = [
        ("the day's values", |_| {}),
        ("UT1 - UTC left out", |e| e.ut1_minus_utc_s = 0.0),
        ("polar motion left out", |e| {
            e.polar_motion_x_arcsec = 0.0;
            e.polar_motion_y_arcsec = 0.0;
        }),
        ("UT1 - UTC wrong by 0.02 s", |e| e.ut1_minus_utc_s += 0.02),
        ("UT1 - UTC wrong by 0.05 s", |e| e.ut1_minus_utc_s += 0.05),
        ("UT1 - UTC wrong by 0.1 s", |e| e.ut1_minus_utc_s += 0.1),
        ("UT1 - UTC wrong by 0.5 s", |e| e.ut1_minus_utc_s += 0.5),
    ];
    for (name, change) in cases {
        let mut configured = scenario.clone();
        change(&mut configured.launch_site.earth_orientation);
        let config = fsw_config(&configured).unwrap();
        let result = fly_with(
            &scenario,
            config,
            FlightOptions::default(),
            |_, _| {},
            |_, _| {},
        )
        .unwrap();
        let last = result.samples.last().unwrap();
        let norm = |v: [f64; 3]| Vector3::from(v).norm();
        println!(
            "{name}: attitude error {:.2}\", position error {:.2} m, calibration NEES {:.1}, \
             gate rejections star {} GNSS {}",
            norm(last.attitude_error_rad) / ARCSEC,
            norm(last.position_error_m),
            result.calibration_nees().unwrap_or(f64::NAN),
            result.health.star_gate_rejections,
            result.health.gnss_gate_rejections
        );
        if name == "the day's values" {
            assert!(result.calibration_nees().unwrap() < 25.0);
        }
    }
}
