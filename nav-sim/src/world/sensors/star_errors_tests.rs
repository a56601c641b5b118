//! Unit tests of the star tracker's per-axis noise and slowly varying errors.

use super::imu_errors_tests::autocorrelation;
use super::star_errors::SlowGaussMarkov;
use super::tests::{events_digest, every_frame_scenario, port_frames, run, statistics};
use super::*;
use nav_core::attitude::{canonical, log_rotation_vector};

/// One arc-second (rad).
const ARCSEC_RAD: f64 = 4.848_136_811_095_36e-6;

/// The rotation vectors `log((q_ib q_bs q_ψ)* ⊗ q_m)` (rad, sensor axes) of head 0's star
/// samples of `frames` synthetic frames, and their time tags.
pub(super) fn star_residuals(scenario: &Scenario, frames: u64) -> Vec<(f64, Vector3<f64>)> {
    head_star_residuals(scenario, frames, 0)
}

/// [`star_residuals`] of head `head`, against its own `q_bs ⊗ q_ψ` (without slow errors).
pub(super) fn head_star_residuals(
    scenario: &Scenario,
    frames: u64,
    head: usize,
) -> Vec<(f64, Vector3<f64>)> {
    let (truths, events) = run(scenario, frames);
    let (_, q_ig) = port_frames(scenario);
    let period_s = scenario.imu.frame_period_s();
    let installed_q_bs = SensorSimulator::new(scenario)
        .unwrap()
        .star_head_alignment(head)
        .unwrap()
        .installed_q_bs();
    events
        .iter()
        .filter_map(|event| match event {
            SensorEvent::Star {
                head: event_head,
                time_tag_s,
                attitude_q_gs,
            } if *event_head == head => {
                let index = ((time_tag_s - truths[0].time_s) / period_s).round() as usize;
                let expected = truths[index].attitude_q_ib * installed_q_bs;
                let residual = expected.conjugate() * (q_ig * attitude_q_gs);
                Some((*time_tag_s, log_rotation_vector(&canonical(&residual))))
            }
            _ => None,
        })
        .collect()
}

/// The per-axis keys equal to `noise_arcsec` give the very bits of the isotropic noise, and
/// the default scenario's stream is unchanged by their existence.
#[test]
fn per_axis_noise_equal_to_the_isotropic_noise_gives_the_same_bits() {
    let default = Scenario::default_scenario().unwrap();
    assert!(!default.star_sensor.has_per_axis_noise());
    let mut per_axis = default.clone();
    per_axis.star_sensor.cross_boresight_noise_arcsec = Some(10.0);
    per_axis.star_sensor.roll_noise_arcsec = Some(10.0);
    per_axis.validate().unwrap();
    let (_, isotropic_events) = run(&default, 1_000);
    let (_, per_axis_events) = run(&per_axis, 1_000);
    assert_eq!(isotropic_events.len(), per_axis_events.len());
    assert_eq!(
        events_digest(&isotropic_events),
        events_digest(&per_axis_events)
    );
}

/// Roll (about the boresight, sensor z) and cross-boresight (sensor x, y) noise have their
/// own σ: 10,000 samples, the sample σ within 5 % (its standard error is 0.7 %).
#[test]
fn per_axis_noise_has_the_configured_sigma_about_each_sensor_axis() {
    let mut scenario = every_frame_scenario();
    let star = &mut scenario.star_sensor;
    (star.noise_arcsec, star.cross_boresight_noise_arcsec) = (35.0, Some(5.0));
    star.roll_noise_arcsec = Some(35.0);
    scenario.validate().unwrap();
    let residuals: Vec<Vector3<f64>> = star_residuals(&scenario, 10_000)
        .into_iter()
        .map(|(_, residual)| residual)
        .collect();
    assert_eq!(residuals.len(), 10_000);
    let (mean, deviation) = statistics(&residuals);
    let ratio = deviation.component_div(&Vector3::new(5.0, 5.0, 35.0)) / ARCSEC_RAD;
    println!(
        "sample σ / σ {ratio:.4?}, mean {:.3?} arcsec",
        mean / ARCSEC_RAD
    );
    assert!((ratio - Vector3::repeat(1.0)).amax() < 0.05, "{ratio:?}");
}

/// 200,000 samples 0.1 s apart with τ = 1 s, φ = 0.905 (as the IMU bias instability's
/// test): the sample σ within 3 % (relative standard error √((1 + φ²)/(1 − φ²)/(2N)) =
/// 0.5 %), the lag-1 correlation within 0.005 of φ (standard error √((1 − φ²)/N) = 0.001),
/// lag 10 within 0.04 of φ¹⁰ (0.007); and stationary from the start: the first draws of
/// 4,000 seeds have σ within 5 % (standard error 1.1 % per axis).
#[test]
fn slow_error_has_the_stationary_sigma_and_correlation() {
    let sigma = Vector3::new(3.0, 3.0, 10.0) * ARCSEC_RAD;
    let (interval_s, tau_s) = (0.1, 1.0);
    let mut error = SlowGaussMarkov::new(sigma, tau_s, streams::rng(7, Stream::StarSlowError));
    let samples: Vec<Vector3<f64>> = (0..200_000)
        .map(|k| error.at(600.0 + f64::from(k) * interval_s))
        .collect();
    let phi = (-interval_s / tau_s).exp();
    let (_, deviation) = statistics(&samples);
    let ratio = deviation.component_div(&sigma);
    for axis in 0..3 {
        let axis_samples: Vec<f64> = samples.iter().map(|v| v[axis]).collect();
        let (lag1, lag10) = (
            autocorrelation(&axis_samples, 1),
            autocorrelation(&axis_samples, 10),
        );
        println!(
            "axis {axis}: σ ratio {:.4}, lag 1 {lag1:.4} (φ {phi:.4})",
            ratio[axis]
        );
        assert!((ratio[axis] - 1.0).abs() < 0.03, "{ratio:?}");
        assert!((lag1 - phi).abs() < 0.005, "{lag1}");
        assert!((lag10 - phi.powi(10)).abs() < 0.04, "{lag10}");
    }
    let first: Vec<Vector3<f64>> = (0..4_000)
        .map(|seed| SlowGaussMarkov::new(sigma, tau_s, streams::rng(seed, Stream::StarSlowError)))
        .map(|mut error| error.at(600.0))
        .collect();
    let (_, deviation) = statistics(&first);
    let ratio = deviation.component_div(&sigma);
    assert!((ratio - Vector3::repeat(1.0)).amax() < 0.05, "{ratio:?}");
}

/// The slow errors enter the star samples as a rotation in sensor axes: noise-free, the
/// periodic error alone is `a sin(2π (t − t₀)/P + φ₀)`; with the Gauss–Markov error on, the
/// IMU and GNSS events keep their bits (the error has its own stream).
#[test]
fn slow_errors_enter_the_star_samples_and_leave_the_other_streams_alone() {
    let mut scenario = every_frame_scenario();
    scenario.star_sensor.noise_arcsec = 0.0;
    let star = &mut scenario.star_sensor;
    star.periodic_error_amplitude_arcsec = [2.0, 0.0, 6.0];
    (star.periodic_error_period_s, star.periodic_error_phase_deg) = (0.5, 30.0);
    scenario.validate().unwrap();
    let start_s = scenario.simulation.start_time_s;
    for (time_s, residual) in star_residuals(&scenario, 400) {
        let sine = (std::f64::consts::TAU * (time_s - start_s) / 0.5 + 30_f64.to_radians()).sin();
        let expected = Vector3::new(2.0, 0.0, 6.0) * (ARCSEC_RAD * sine);
        assert!((residual - expected).amax() < 1e-12, "{residual:?}");
    }

    let plain = Scenario::default_scenario().unwrap();
    let mut slow = plain.clone();
    slow.star_sensor.slow_error_sigma_arcsec = [3.0, 3.0, 3.0];
    slow.star_sensor.slow_error_correlation_time_s = 1_420.0;
    slow.validate().unwrap();
    let (_, plain_events) = run(&plain, 500);
    let (_, slow_events) = run(&slow, 500);
    let not_star = |events: &[SensorEvent]| -> Vec<SensorEvent> {
        let kept = events
            .iter()
            .filter(|event| !matches!(event, SensorEvent::Star { .. }));
        kept.copied().collect()
    };
    assert_eq!(
        events_digest(&not_star(&plain_events)),
        events_digest(&not_star(&slow_events))
    );
    assert_ne!(events_digest(&plain_events), events_digest(&slow_events));
}

/// The installation truth the calibration is scored against is the alignment the tracker's
/// measurement sees at its last sample, `q_ψ ⊗ exp(ε_slow)`: noise-free, every sample is
/// `q_ib ⊗ q_bs` times that truth exactly; before the first sample it is `q_ψ`.
#[test]
fn the_installation_truth_carries_the_slow_error_of_the_last_sample() {
    let mut scenario = every_frame_scenario();
    scenario.star_sensor.noise_arcsec = 0.0;
    scenario.star_sensor.slow_error_sigma_arcsec = [3.0, 2.0, 5.0];
    scenario.star_sensor.slow_error_correlation_time_s = 1_420.0;
    scenario.validate().unwrap();
    let period_s = scenario.imu.frame_period_s();
    let (_, q_ig) = port_frames(&scenario);
    let mut sensors = SensorSimulator::new(&scenario).unwrap();
    let constant = sensors.error_truth().star_installation_q_psi;
    let mut events = Vec::new();
    let mut largest_slow_rad: f64 = 0.0;
    for k in 0..300 {
        let truth = super::tests::truth_frame(k, period_s);
        events.clear();
        sensors.process_frame(&truth, &mut events).unwrap();
        let errors = sensors.error_truth();
        for event in &events {
            if let SensorEvent::Star { attitude_q_gs, .. } = event {
                let expected = truth.attitude_q_ib
                    * errors.star_mounting_q_bs
                    * errors.star_installation_q_psi;
                let residual = expected.conjugate() * (q_ig * attitude_q_gs);
                let angle = log_rotation_vector(&canonical(&residual)).amax();
                assert!(angle < 1e-13, "frame {k}: {angle}");
            }
        }
        let slow = constant.conjugate() * errors.star_installation_q_psi;
        largest_slow_rad = largest_slow_rad.max(log_rotation_vector(&canonical(&slow)).amax());
    }
    assert!(largest_slow_rad > 0.5 * ARCSEC_RAD, "{largest_slow_rad}");
}
