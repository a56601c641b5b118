//! Unit tests of the misalignment, g-sensitivity and bias-instability models.

use super::imu_errors::BiasInstability;
use super::tests::statistics;
use super::*;

const PERIOD_S: f64 = 0.002;

/// The default scenario with every gyro and accelerometer error off (no noise, bias or
/// scale factor), so that the measured increments are the truth plus the term under test.
fn clean_scenario() -> Scenario {
    let mut scenario = Scenario::default_scenario().unwrap();
    let (gyro, accelerometer) = (&mut scenario.gyro, &mut scenario.accelerometer);
    gyro.rate_noise_density_deg_per_h_per_sqrt_hz = 0.0;
    gyro.bias_rad_per_s = [0.0; 3];
    gyro.scale_factor = [0.0; 3];
    accelerometer.noise_per_sample_mps2 = 0.0;
    accelerometer.bias_mps2 = [0.0; 3];
    accelerometer.scale_factor = [0.0; 3];
    scenario
}

fn frame(delta_angle_rad: Vector3<f64>, delta_velocity_mps: Vector3<f64>) -> TruthFrame {
    TruthFrame {
        frame_index: 0,
        start_time_s: 600.0,
        time_s: 600.0 + PERIOD_S,
        interval_s: PERIOD_S,
        attitude_q_ib: Quaternion::identity(),
        position_m: Vector3::new(1.0e5, 5.0e5, 2.0e5),
        velocity_mps: Vector3::new(7000.0, 0.0, 100.0),
        delta_angle_rad,
        delta_velocity_mps,
        segment_index: 0,
    }
}

/// The first frame's measured (Δθ, Δv) for `truth`.
fn measure(scenario: &Scenario, truth: &TruthFrame) -> (Vector3<f64>, Vector3<f64>) {
    scenario.validate().unwrap();
    let mut sensors = SensorSimulator::new(scenario).unwrap();
    let mut events = Vec::new();
    sensors.process_frame(truth, &mut events).unwrap();
    match events[0] {
        SensorEvent::Imu {
            delta_angle_rad,
            delta_velocity_mps,
            ..
        } => (delta_angle_rad, delta_velocity_mps),
        _ => panic!("the first event is the IMU's"),
    }
}

/// `a_ij`: axis `i` senses `a_ij` of the increment on body axis `j`, with its sign.
#[test]
fn misalignment_couples_the_increment_on_axis_j_into_axis_i() {
    let mut scenario = clean_scenario();
    scenario.gyro.misalignment_rad[0][1] = 2.0e-5;
    scenario.gyro.misalignment_rad[1][0] = -3.0e-5;
    scenario.gyro.misalignment_rad[2][0] = 5.0e-5;
    scenario.accelerometer.misalignment_rad[2][1] = -7.0e-4;

    // A pure rotation about body y: only a01 (x senses y) and a21 (z senses y, zero here).
    let y_rotation = 0.01;
    let (angle, _) = measure(
        &scenario,
        &frame(Vector3::new(0.0, y_rotation, 0.0), Vector3::zeros()),
    );
    assert_eq!(f64::to_bits(angle.y), f64::to_bits(y_rotation));
    assert!((angle.x - 2.0e-5 * y_rotation).abs() < 1e-20, "{angle:?}");
    assert_eq!(f64::to_bits(angle.z), f64::to_bits(0.0));

    // A pure rotation about body x: a10 into y (negative), a20 into z.
    let x_rotation = -0.02;
    let (angle, _) = measure(
        &scenario,
        &frame(Vector3::new(x_rotation, 0.0, 0.0), Vector3::zeros()),
    );
    assert_eq!(f64::to_bits(angle.x), f64::to_bits(x_rotation));
    assert!(
        (angle.y - (-3.0e-5 * x_rotation)).abs() < 1e-20,
        "{angle:?}"
    );
    assert!(angle.y > 0.0);
    assert!((angle.z - 5.0e-5 * x_rotation).abs() < 1e-20, "{angle:?}");

    // The accelerometer: a thrust along body y shows on z as a21 Δv_y.
    let (_, velocity) = measure(
        &scenario,
        &frame(Vector3::zeros(), Vector3::new(0.0, 0.1, 0.0)),
    );
    assert_eq!(f64::to_bits(velocity.x), f64::to_bits(0.0));
    assert_eq!(f64::to_bits(velocity.y), f64::to_bits(0.1));
    assert!((velocity.z - (-7.0e-4 * 0.1)).abs() < 1e-19, "{velocity:?}");
}

/// With the scale factor on, the misalignment enters before `(I − Λ)⁻¹`:
/// `Δθ_m = (I − Λ)⁻¹ (M Δθ + b T)`.
#[test]
fn misalignment_enters_before_the_scale_factor_and_bias() {
    let mut scenario = clean_scenario();
    scenario.gyro.scale_factor = [1.0e-3, -2.0e-3, 0.0];
    scenario.gyro.bias_rad_per_s = [1.0e-4, 0.0, 0.0];
    scenario.gyro.misalignment_rad = [[0.0, 1.0e-3, 0.0], [0.0; 3], [0.0; 3]];
    let truth = Vector3::new(0.01, -0.02, 0.005);
    let (angle, _) = measure(&scenario, &frame(truth, Vector3::zeros()));
    let expected_x = (0.01 + 1.0e-3 * -0.02 + 1.0e-4 * PERIOD_S) / (1.0 - 1.0e-3);
    assert!((angle.x - expected_x).abs() < 1e-17, "{angle:?}");
    assert!((angle.y - (-0.02 / (1.0 + 2.0e-3))).abs() < 1e-17);
}

/// The rate error on axis i is `g_i f_i`: over the frame `g_i Δv_i` of delta angle; the
/// accelerometer is unaffected.
#[test]
fn g_sensitivity_adds_the_rate_error_of_the_specific_force() {
    let mut scenario = clean_scenario();
    let g = [1.0e-5, -2.0e-5, 4.0e-6];
    scenario.gyro.g_sensitivity_rad_s_per_mps2 = g;
    // 30 m/s² along x, 5 m/s² along -z, held over the frame.
    let force = Vector3::new(30.0, 0.0, -5.0);
    let truth_angle = Vector3::new(1.0e-3, 0.0, 0.0);
    let (angle, velocity) = measure(&scenario, &frame(truth_angle, force * PERIOD_S));
    let rate_error = (angle - truth_angle) / PERIOD_S;
    let expected = Vector3::new(g[0] * 30.0, 0.0, g[2] * -5.0);
    assert!((rate_error - expected).norm() < 1e-15, "{rate_error:?}");
    // 3e-4 rad/s on x: 61.9 °/h under 3.06 g.
    assert!((rate_error.x - 3.0e-4).abs() < 1e-15);
    assert_eq!(velocity, force * PERIOD_S);
}

/// Lag-`lag` sample autocorrelation of one axis.
pub(super) fn autocorrelation(samples: &[f64], lag: usize) -> f64 {
    let count = samples.len() as f64;
    let mean = samples.iter().sum::<f64>() / count;
    let variance = samples.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / count;
    let covariance = samples
        .iter()
        .zip(&samples[lag..])
        .map(|(a, b)| (a - mean) * (b - mean))
        .sum::<f64>()
        / (count - lag as f64);
    covariance / variance
}

/// The Gauss–Markov bias: stationary σ from its first draw on, and correlation `φ^lag`,
/// `φ = exp(−T/τ)`. τ = 10 T and 200,000 steps: the lag-1 correlation φ = 0.905 makes the
/// relative standard error of the sample σ √((1 + φ²)/(1 − φ²)/(2N)) = 0.5 %, and of the
/// lag-1 correlation √((1 − φ²)/N) = 0.001; the bounds are about 5 of them (lag 10's,
/// √((1 + φ²)/(1 − φ²)/N) ≈ 0.007, also about 5).
#[test]
fn bias_instability_has_the_stationary_sigma_and_correlation() {
    let (sigma, tau_s) = (3.0e-6, 10.0 * PERIOD_S);
    let steps = 200_000;
    let mut bias =
        BiasInstability::new(sigma, tau_s, streams::rng(7, Stream::GyroBiasInstability)).unwrap();
    let mut axes = [Vec::new(), Vec::new(), Vec::new()];
    for _ in 0..steps {
        for (axis, samples) in axes.iter_mut().enumerate() {
            samples.push(bias.value[axis]);
        }
        bias.advance(PERIOD_S);
    }
    let phi = (-PERIOD_S / tau_s).exp();
    for samples in &axes {
        let (_, deviation) = statistics(
            &samples
                .iter()
                .map(|v| Vector3::new(*v, 0.0, 0.0))
                .collect::<Vec<_>>(),
        );
        let ratio = deviation.x / sigma;
        let lag1 = autocorrelation(samples, 1);
        let lag10 = autocorrelation(samples, 10);
        println!("σ ratio {ratio:.4}, lag 1 {lag1:.4} (φ {phi:.4}), lag 10 {lag10:.4}");
        assert!((ratio - 1.0).abs() < 0.03, "{ratio}");
        assert!((lag1 - phi).abs() < 0.005, "{lag1}");
        assert!((lag10 - phi.powi(10)).abs() < 0.04, "{lag10}");
    }
    // Stationary from the start: the first draws of many seeds have σ too.
    let first: Vec<Vector3<f64>> = (0..4_000)
        .map(|seed| {
            BiasInstability::new(
                sigma,
                tau_s,
                streams::rng(seed, Stream::GyroBiasInstability),
            )
            .unwrap()
            .value
        })
        .collect();
    let (_, deviation) = statistics(&first);
    // 12,000 draws: the sample σ's relative standard error is 0.65 % per axis of 4,000.
    assert!(
        ((deviation / sigma) - Vector3::repeat(1.0)).amax() < 0.05,
        "{deviation:?}"
    );
}

/// In the sensor stream the bias instability is the measured-minus-true increment over `T`,
/// reported in the error truth, and the white noise of the other streams is untouched.
#[test]
fn bias_instability_enters_the_increments_and_the_error_truth() {
    let mut scenario = clean_scenario();
    scenario.gyro.bias_instability_sigma_rad_per_s = 1.0e-5;
    scenario.gyro.bias_instability_correlation_time_s = 100.0;
    scenario.accelerometer.bias_instability_sigma_mps2 = 1.0e-3;
    scenario.accelerometer.bias_instability_correlation_time_s = 300.0;
    scenario.validate().unwrap();
    let mut sensors = SensorSimulator::new(&scenario).unwrap();
    let truth = frame(Vector3::new(0.01, 0.0, 0.0), Vector3::new(0.0, 0.02, 0.0));
    for _ in 0..5 {
        let errors = sensors.error_truth();
        assert!(errors.gyro_bias_rad_per_s.norm() > 0.0);
        let mut events = Vec::new();
        sensors.process_frame(&truth, &mut events).unwrap();
        let SensorEvent::Imu {
            delta_angle_rad,
            delta_velocity_mps,
            ..
        } = events[0]
        else {
            panic!("the first event is the IMU's");
        };
        let gyro = (delta_angle_rad - truth.delta_angle_rad) / PERIOD_S;
        let accel = (delta_velocity_mps - truth.delta_velocity_mps) / PERIOD_S;
        assert!(
            (gyro - errors.gyro_bias_rad_per_s).norm() < 1e-12,
            "{gyro:?}"
        );
        assert!((accel - errors.accel_bias_mps2).norm() < 1e-12, "{accel:?}");
    }
    // The other streams are the scenario's without the model.
    let mut star_only = Scenario::default_scenario().unwrap();
    let mut with_model = star_only.clone();
    with_model.gyro.bias_instability_sigma_rad_per_s = 1.0e-5;
    with_model.gyro.bias_instability_correlation_time_s = 100.0;
    star_only.star_sensor.rate_hz = star_only.imu.rate_hz;
    with_model.star_sensor.rate_hz = with_model.imu.rate_hz;
    let (_, without) = super::tests::run(&star_only, 50);
    let (_, with) = super::tests::run(&with_model, 50);
    let stars = |events: &[SensorEvent]| -> Vec<SensorEvent> {
        events
            .iter()
            .filter(|event| matches!(event, SensorEvent::Star { .. } | SensorEvent::Gnss { .. }))
            .copied()
            .collect()
    };
    assert_eq!(stars(&without), stars(&with));
    let accel = |events: &[SensorEvent]| -> Vec<Vector3<f64>> {
        events
            .iter()
            .filter_map(|event| match event {
                SensorEvent::Imu {
                    delta_velocity_mps, ..
                } => Some(*delta_velocity_mps),
                _ => None,
            })
            .collect()
    };
    assert_eq!(accel(&without), accel(&with));
}
