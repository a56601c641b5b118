//! Unit tests of the star tracker's heads: head 0 unchanged by the others, each head's
//! attitude, noise, outages and rate limit its own, and the relative-alignment truth.

use super::star_errors_tests::head_star_residuals;
use super::tests::{
    events_digest, every_frame_scenario, port_frames, run, statistics, truth_frame,
};
use super::*;
use nav_core::attitude::{canonical, exp_rotation_vector, log_rotation_vector};

const ARCSEC_RAD: f64 = 4.848_136_811_095_36e-6;

/// Head 1 of the two-head scenario files: boresight 90° from head 0's, its own installation
/// error of head 0's size, 5″ across the boresight and 35″ in roll.
fn second_head(scenario: &Scenario) -> crate::scenario::StarSensorSettings {
    let mut head = scenario.star_sensor.clone();
    head.mounting_rotation_vector_deg = [90.0, 0.0, 0.0];
    head.installation_error_rotation_vector_rad = [-3.0e-3, 1.0e-3, 2.0e-3];
    head.noise_arcsec = 35.0;
    head.cross_boresight_noise_arcsec = Some(5.0);
    head.roll_noise_arcsec = Some(35.0);
    head
}

fn with_heads(
    mut scenario: Scenario,
    heads: impl IntoIterator<Item = crate::scenario::StarSensorSettings>,
) -> Scenario {
    scenario.star_sensor.additional_heads.extend(heads);
    scenario
}

/// The events of head `head` (and every non-star event).
fn without_other_heads(events: &[SensorEvent], head: usize) -> Vec<SensorEvent> {
    events
        .iter()
        .filter(|event| !matches!(event, SensorEvent::Star { head: h, .. } if *h != head))
        .copied()
        .collect()
}

/// Head 0 with slow, periodic and aberration errors on: its events (and the IMU's and the
/// GNSS's) are the bits of the single tracker's whatever the other heads do, and its truth
/// too.
#[test]
fn head_zero_is_bit_identical_with_and_without_additional_heads() {
    let mut single = Scenario::default_scenario().unwrap();
    single.star_sensor.slow_error_sigma_arcsec = [3.0, 3.0, 1.0];
    single.star_sensor.slow_error_correlation_time_s = 100.0;
    single.star_sensor.aberration = crate::scenario::StarAberration::Uncorrected;
    let mut busy_head = second_head(&single);
    busy_head.outages = vec![[0.5, 1.0]];
    let several = with_heads(single.clone(), [second_head(&single), busy_head]);
    let (_, single_events) = run(&single, 2_000);
    let (_, several_events) = run(&several, 2_000);
    let head_0 = without_other_heads(&several_events, 0);
    println!(
        "events: single {}, three heads {}, head 0 of them {}",
        single_events.len(),
        several_events.len(),
        head_0.len()
    );
    assert_eq!(events_digest(&head_0), events_digest(&single_events));
    assert_eq!(head_0.len(), single_events.len());
    // 4 s at 10 Hz: 40 samples of head 1 and 30 of head 2 (0.5 s to 1.5 s out).
    assert_eq!(several_events.len(), single_events.len() + 40 + 30);
    let truth = |scenario: &Scenario| {
        let mut sensors = SensorSimulator::new(scenario).unwrap();
        let mut events = Vec::new();
        for frame_index in 0..200 {
            let period_s = scenario.imu.frame_period_s();
            let frame = truth_frame(frame_index, period_s);
            sensors.process_frame(&frame, &mut events).unwrap();
        }
        sensors.error_truth()
    };
    let (alone, together) = (truth(&single), truth(&several));
    assert_eq!(
        alone.star_installation_q_psi.coords.map(f64::to_bits),
        together.star_installation_q_psi.coords.map(f64::to_bits)
    );
}

/// Head 1's samples are `q_ib ⊗ q_bs,1 ⊗ q_ψ,1 ⊗ exp(n)` with `n` of its own per-axis σ
/// (5″, 5″, 35″): over 10,000 samples the residual's mean is within 5 standard errors of 0
/// and its sample σ within 5 % of the configured σ on each sensor axis. Against head 0's
/// alignment the residual is the 90° between the boresights.
#[test]
fn a_second_heads_attitude_is_its_mounting_and_installation_within_its_noise() {
    let scenario = every_frame_scenario();
    let scenario = with_heads(scenario.clone(), [second_head(&scenario)]);
    let residuals: Vec<Vector3<f64>> = head_star_residuals(&scenario, 10_000, 1)
        .into_iter()
        .map(|(_, residual)| residual)
        .collect();
    assert_eq!(residuals.len(), 10_000);
    let (mean, deviation) = statistics(&residuals);
    let sigma = Vector3::new(5.0, 5.0, 35.0) * ARCSEC_RAD;
    let ratio = deviation.component_div(&sigma);
    let mean_in_standard_errors = mean.component_div(&(sigma / 100.0));
    println!("head 1: sample σ / σ = {ratio:.4?}, mean / (σ/√N) = {mean_in_standard_errors:.3?}");
    for axis in 0..3 {
        assert!((ratio[axis] - 1.0).abs() < 0.05, "axis {axis}: {ratio:?}");
        assert!(mean_in_standard_errors[axis].abs() < 5.0, "{mean:?}");
    }
    let against_head_0: Vec<(f64, Vector3<f64>)> = {
        let (truths, events) = run(&scenario, 10);
        let (_, q_ig) = port_frames(&scenario);
        let head_0 = SensorSimulator::new(&scenario).unwrap().error_truth();
        events
            .iter()
            .filter_map(|event| match event {
                SensorEvent::Star {
                    head: 1,
                    time_tag_s,
                    attitude_q_gs,
                } => {
                    let truth = truths
                        .iter()
                        .find(|t| t.time_s.to_bits() == time_tag_s.to_bits())?;
                    let expected = truth.attitude_q_ib
                        * head_0.star_mounting_q_bs
                        * head_0.star_installation_q_psi;
                    let residual = canonical(&(expected.conjugate() * (q_ig * attitude_q_gs)));
                    Some((*time_tag_s, log_rotation_vector(&residual)))
                }
                _ => None,
            })
            .collect()
    };
    assert_eq!(against_head_0.len(), 10);
    let angle_deg = against_head_0[0].1.norm().to_degrees();
    assert!((80.0..100.0).contains(&angle_deg), "{angle_deg}");
}

/// Pearson correlation of two equally long series.
fn correlation(first: &[f64], second: &[f64]) -> f64 {
    let count = first.len() as f64;
    let mean = |values: &[f64]| values.iter().sum::<f64>() / count;
    let (mean_first, mean_second) = (mean(first), mean(second));
    let (mut covariance, mut variance_first, mut variance_second) = (0.0, 0.0, 0.0);
    for (a, b) in first.iter().zip(second) {
        covariance += (a - mean_first) * (b - mean_second);
        variance_first += (a - mean_first).powi(2);
        variance_second += (b - mean_second).powi(2);
    }
    covariance / (variance_first * variance_second).sqrt()
}

/// Two heads with identical settings draw independent noise: over 10,000 common samples the
/// correlation of their residuals per sensor axis is within 4/√N = 0.04 of 0 (it is 1 for a
/// shared stream).
#[test]
fn heads_draw_independent_noise() {
    let scenario = every_frame_scenario();
    let twin = scenario.star_sensor.clone();
    let scenario = with_heads(scenario, [twin]);
    let head_0 = head_star_residuals(&scenario, 10_000, 0);
    let head_1 = head_star_residuals(&scenario, 10_000, 1);
    assert_eq!(head_0.len(), head_1.len());
    assert!(head_0
        .iter()
        .zip(&head_1)
        .all(|(a, b)| a.0.to_bits() == b.0.to_bits()));
    for axis in 0..3 {
        let series = |residuals: &[(f64, Vector3<f64>)]| -> Vec<f64> {
            residuals.iter().map(|(_, r)| r[axis]).collect()
        };
        let rho = correlation(&series(&head_0), &series(&head_1));
        println!("axis {axis}: correlation of head 0 and head 1 noise {rho:+.4}");
        assert!(rho.abs() < 0.04, "axis {axis}: {rho}");
    }
}

/// Head 1 blind above 100 deg/s with 0.1 s re-acquisition, head 2 in an outage from 1 s to
/// 3 s after the start, head 0 without either; the synthetic frames turn at 656 deg/s from
/// 2 s to 2.2 s, and at 14 deg/s otherwise. Each head loses exactly its own samples, and the
/// heads of one frame come in head order.
#[test]
fn outages_and_rate_limits_are_per_head() {
    let scenario = every_frame_scenario();
    let mut rate_limited = scenario.star_sensor.clone();
    rate_limited.max_rate_deg_per_s = 100.0;
    rate_limited.reacquisition_s = 0.1;
    let mut out = scenario.star_sensor.clone();
    out.outages = vec![[1.0, 2.0]];
    let scenario = with_heads(scenario, [rate_limited, out]);
    let period_s = scenario.imu.frame_period_s();
    let mut sensors = SensorSimulator::new(&scenario).unwrap();
    let mut events = Vec::new();
    let mut delivered = [0_usize; 3];
    for frame_index in 0..2_500_u64 {
        let mut frame = truth_frame(frame_index, period_s);
        // Frames 1000..1099 end between 2.002 s and 2.2 s after the start.
        if !(1_000..1_100).contains(&frame_index) {
            frame.delta_angle_rad /= 50.0;
        }
        events.clear();
        sensors.process_frame(&frame, &mut events).unwrap();
        let heads: Vec<usize> = events
            .iter()
            .filter_map(|event| match event {
                SensorEvent::Star { head, .. } => Some(*head),
                _ => None,
            })
            .collect();
        assert!(heads.windows(2).all(|pair| pair[0] < pair[1]), "{heads:?}");
        for head in heads {
            delivered[head] += 1;
        }
    }
    println!("star samples delivered per head: {delivered:?}");
    // Head 1: 100 frames above the limit, then 0.1 s = 50 frames re-acquiring (whether the
    // frame ending at the end of the re-acquisition tracks is up to the rounding of the times).
    assert_eq!(delivered[0], 2_500);
    assert!(
        (2_500 - 150..=2_500 - 149).contains(&delivered[1]),
        "{delivered:?}"
    );
    // Head 2: the 1000 samples of [1 s, 3 s) (give or take the rounding at the edges).
    assert!(
        (2_500 - 1_001..=2_500 - 999).contains(&delivered[2]),
        "{delivered:?}"
    );
}

/// The relative-alignment truth is `(q_bs,0 q_ψ,0)⁻¹ ⊗ (q_bs,h q_ψ,h)` with each head's slow
/// error at its last sample: (1) without noise it is the two heads' measured attitudes
/// composed, `q_is,0⁻¹ ⊗ q_is,h`, at every sample; (2) without slow errors it is the product
/// of the configured rotations; (3) head 1's boresight in head 0's axes is 90° from head 0's.
#[test]
fn the_relative_alignment_truth_is_the_direct_computation() {
    let mut scenario = every_frame_scenario();
    scenario.star_sensor.noise_arcsec = 0.0;
    scenario.star_sensor.slow_error_sigma_arcsec = [20.0, 10.0, 5.0];
    scenario.star_sensor.slow_error_correlation_time_s = 1.0;
    let mut head = second_head(&scenario);
    head.noise_arcsec = 0.0;
    head.cross_boresight_noise_arcsec = None;
    head.roll_noise_arcsec = None;
    head.periodic_error_amplitude_arcsec = [30.0, 0.0, 10.0];
    head.periodic_error_period_s = 0.37;
    let scenario = with_heads(scenario, [head.clone()]);
    let period_s = scenario.imu.frame_period_s();
    let mut sensors = SensorSimulator::new(&scenario).unwrap();
    let mut events = Vec::new();
    let mut worst_rad = 0.0_f64;
    let mut slow_seen_rad = 0.0_f64;
    let static_relative = sensors.star_relative_alignment_q(1).unwrap();
    for frame_index in 0..300 {
        events.clear();
        sensors
            .process_frame(&truth_frame(frame_index, period_s), &mut events)
            .unwrap();
        let stars: Vec<Quaternion<f64>> = events
            .iter()
            .filter_map(|event| match event {
                SensorEvent::Star { attitude_q_gs, .. } => Some(*attitude_q_gs),
                _ => None,
            })
            .collect();
        assert_eq!(stars.len(), 2);
        let measured = canonical(&(stars[0].conjugate() * stars[1]));
        let truth = sensors.star_relative_alignment_q(1).unwrap();
        worst_rad = worst_rad.max(2.0 * (truth.conjugate() * measured).imag().norm());
        slow_seen_rad =
            slow_seen_rad.max(2.0 * (static_relative.conjugate() * truth).imag().norm());
    }
    println!(
        "relative alignment truth vs measured heads: worst {worst_rad:.2e} rad; the slow \
         errors move it by up to {:.1} arcsec",
        slow_seen_rad / ARCSEC_RAD
    );
    assert!(worst_rad < 1e-13, "{worst_rad}");
    assert!(slow_seen_rad > 20.0 * ARCSEC_RAD, "{slow_seen_rad}");
    assert!(sensors.star_relative_alignment_q(2).is_none());
    assert_eq!(sensors.star_head_count(), 2);
    let head_0 = sensors.star_head_alignment(0).unwrap();
    let truth = sensors.error_truth();
    assert_eq!(
        head_0.installation_q_psi.coords.map(f64::to_bits),
        truth.star_installation_q_psi.coords.map(f64::to_bits)
    );

    // (2) Before any sample the slow errors are zero: the configured rotations.
    let installed = |settings: &crate::scenario::StarSensorSettings| {
        exp_rotation_vector(&Vector3::from(
            settings.mounting_rotation_vector_deg.map(f64::to_radians),
        )) * exp_rotation_vector(&Vector3::from(
            settings.installation_error_rotation_vector_rad,
        ))
    };
    let direct = canonical(&(installed(&scenario.star_sensor).conjugate() * installed(&head)));
    assert!((static_relative - direct).norm() < 1e-15);
    // (3) The boresights are 90° apart give or take the installation errors (≤ 4e-3 rad).
    let boresight_1_in_0 = nalgebra::UnitQuaternion::from_quaternion(direct) * Vector3::z();
    let angle_deg = boresight_1_in_0.dot(&Vector3::z()).acos().to_degrees();
    assert!((angle_deg - 90.0).abs() < 0.25, "{angle_deg}");
}
