//! Long-run covariance conditioning through the whole flight code. One simulated hour
//! at 500 Hz (the default calibration scenario, every rotation and burn, followed by a coast to
//! 3600 s) with precise aiding (star sensor 1″, GNSS 0.1 m: ten and a hundred times better
//! than the paper's, so the updates remove as much variance as they can): once per simulated
//! second `P` is checked for symmetry (‖P − Pᵀ‖_F / ‖P‖_F < 1e-12), for positive
//! definiteness (Cholesky), and the smallest eigenvalue of its correlation matrix
//! `D^{-1/2} P D^{-1/2}` (scale-free: P's own eigenvalues span 1e-22 to 1e2 because the
//! states have different units) is tracked and must stay above 1e-12. Measured: asymmetry
//! exactly 0 (symmetric by construction), smallest correlation eigenvalue 4.3e-7, no covariance
//! clamp, no filter reset, 36 / 41 star / GNSS gate rejections in 1.8 M frames.

use nalgebra::SymmetricEigen;
use nav_sim::harness::flight::{fly_observed, FlightOptions};
use nav_sim::scenario::ManoeuvreSegment;
use nav_sim::setup::fsw::fsw_config;
use nav_sim::Scenario;

const ONE_HOUR_S: f64 = 3600.0;
/// Floor for the smallest eigenvalue of the correlation matrix.
const CORRELATION_EIGENVALUE_FLOOR: f64 = 1e-12;

#[test]
fn one_hour_at_500_hz_keeps_the_covariance_symmetric_and_positive_definite() {
    let mut scenario = Scenario::default_scenario().unwrap();
    let flown_s: f64 = scenario.manoeuvres.iter().map(|s| s.duration_s).sum();
    assert!(flown_s < ONE_HOUR_S);
    scenario.manoeuvres.push(ManoeuvreSegment {
        label: "coast to one hour".into(),
        duration_s: ONE_HOUR_S - flown_s,
        ramp_s: 0.0,
        body_rate_deg_per_s: [0.0; 3],
        specific_force_mps2: [0.0; 3],
    });
    scenario.star_sensor.noise_arcsec = 1.0;
    scenario.gnss.noise_m = 0.1;
    scenario.validate().unwrap();
    let mut worst_asymmetry = 0.0_f64;
    let mut smallest_eigenvalue = f64::INFINITY;
    let mut checks = 0_u32;
    let mut failures = Vec::new();
    let result = fly_observed(
        &scenario,
        fsw_config(&scenario).unwrap(),
        FlightOptions {
            record_interval_s: 60.0,
        },
        |_, _| {},
        |_, _| {},
        |frame, computer| {
            if frame % 500 != 0 {
                return;
            }
            checks += 1;
            let p = computer.filter().covariance();
            let asymmetry = (p - p.transpose()).norm() / p.norm();
            worst_asymmetry = worst_asymmetry.max(asymmetry);
            if p.cholesky().is_none() {
                failures.push(format!("frame {frame}: Cholesky failed"));
            }
            let scale = p.diagonal().map(|v| 1.0 / v.sqrt());
            let correlation = p.component_mul(&(scale * scale.transpose()));
            let eigen = SymmetricEigen::new(correlation);
            smallest_eigenvalue = smallest_eigenvalue.min(eigen.eigenvalues.min());
        },
    )
    .unwrap();
    let health = result.health;
    println!(
        "{} frames, {checks} checks: worst ‖P − Pᵀ‖/‖P‖ {worst_asymmetry:.2e}, smallest \
         correlation eigenvalue {smallest_eigenvalue:.2e}; gate rejections star {} GNSS {}, \
         declared faulty star {} GNSS {}, ignored {}, covariance clamps {}, filter resets {}",
        result.frames,
        health.star_gate_rejections,
        health.gnss_gate_rejections,
        health.star_declared_faulty,
        health.gnss_declared_faulty,
        health.ignored_from_faulty_sensor,
        health.covariance_clamps,
        health.filter_resets
    );
    assert_eq!(result.frames, 1_800_000);
    assert!(failures.is_empty(), "{failures:?}");
    assert!(worst_asymmetry < 1e-12, "{worst_asymmetry:e}");
    assert!(
        smallest_eigenvalue > CORRELATION_EIGENVALUE_FLOOR,
        "{smallest_eigenvalue:e}"
    );
    assert_eq!(health.filter_resets, 0);
    // The aiding was really used all hour (about 36,000 updates per sensor at 10 Hz).
    assert_eq!(health.star_declared_faulty + health.gnss_declared_faulty, 0);
    assert_eq!(health.ignored_from_faulty_sensor, 0);
}
