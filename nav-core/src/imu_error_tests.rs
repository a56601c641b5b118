//! Tests of the systematic IMU error model: layout, columns against the nonlinear strapdown
//! (second-order residual), the equivalent biases, correction, and the gauge map.

use super::*;
use crate::attitude::{exp_rotation_vector, rotation_matrix, skew};
use crate::error_model::system_matrix;
use crate::state::{ACCEL_BIAS, GYRO_BIAS, POSITION};
use nalgebra::SVector;

type Full = SVector<f64, STATE_DIMENSION>;
type Params = SVector<f64, IMU_ERROR_DIMENSION>;

#[test]
fn blocks_are_contiguous_after_the_24() {
    let mut next = STATE_DIMENSION;
    for block in ImuErrorBlock::ALL {
        assert_eq!(block.index(), next, "{}", block.name());
        for k in 0..block.dimension() {
            assert_ne!(block.component_name(k), "?");
        }
        assert_eq!(block.component_name(block.dimension()), "?");
        next += block.dimension();
    }
    assert_eq!(next, AUGMENTED_DIMENSION);
    assert_eq!(AUGMENTED_DIMENSION, 36);
}

#[test]
fn layout_names_and_offsets() {
    let names: Vec<String> = ImuErrorBlock::ALL
        .iter()
        .flat_map(|b| {
            (0..b.dimension()).map(move |k| format!("{}.{}", b.name(), b.component_name(k)))
        })
        .collect();
    assert_eq!(
        names,
        [
            "gyro_non_orthogonality.yx",
            "gyro_non_orthogonality.zx",
            "gyro_non_orthogonality.zy",
            "accel_misalignment.xy",
            "accel_misalignment.xz",
            "accel_misalignment.yx",
            "accel_misalignment.yz",
            "accel_misalignment.zx",
            "accel_misalignment.zy",
            "gyro_g_sensitivity.x",
            "gyro_g_sensitivity.y",
            "gyro_g_sensitivity.z",
        ]
    );
    let offsets = ImuErrorBlock::ALL.map(ImuErrorBlock::offset);
    assert_eq!(offsets, [0, 3, 9]);
    // Each term's name is its (row, column) in the matrix.
    let axis = ["x", "y", "z"];
    for (k, (row, column)) in GYRO_NON_ORTHOGONALITY_TERMS.iter().enumerate() {
        let name = format!("{}{}", axis[*row], axis[*column]);
        assert_eq!(ImuErrorBlock::GyroNonOrthogonality.component_name(k), name);
        assert!(row > column);
    }
    for (k, (row, column)) in ACCEL_MISALIGNMENT_TERMS.iter().enumerate() {
        let name = format!("{}{}", axis[*row], axis[*column]);
        assert_eq!(ImuErrorBlock::AccelMisalignment.component_name(k), name);
    }
}

#[test]
fn sensitivities_reproduce_the_matrices() {
    let e = ImuErrorEstimate {
        gyro_non_orthogonality_rad: Vector3::new(7.0, -8.0, 9.0) * 1e-4,
        accel_misalignment_rad: SVector::from([1.0, -2.0, 3.0, -4.0, 5.0, -6.0]) * 1e-4,
        gyro_g_sensitivity_rad_s_per_mps2: Vector3::zeros(),
    };
    let v = Vector3::new(0.3, -1.1, 2.7);
    let l = e.gyro_matrix();
    assert!(
        (l * v - gyro_non_orthogonality_sensitivity(&v) * e.gyro_non_orthogonality_rad).norm()
            < 1e-18
    );
    // Strictly lower triangular, every term placed.
    assert!(l.upper_triangle().norm() < 1e-300);
    assert!((l.lower_triangle().norm() - e.gyro_non_orthogonality_rad.norm()).abs() < 1e-18);
    let a = e.accel_matrix();
    assert!((a * v - accel_misalignment_sensitivity(&v) * e.accel_misalignment_rad).norm() < 1e-18);
    assert!(a.diagonal().norm() < 1e-300);
    assert!((a.norm() - e.accel_misalignment_rad.norm()).abs() < 1e-18);
}

#[test]
fn zero_estimate_is_the_strapdown_correction_bit_for_bit() {
    let corrections = SensorCorrections {
        gyro_bias_rad_s: Vector3::new(1e-4, -2e-4, 3e-4),
        accel_bias_mps2: Vector3::new(2e-3, 1e-3, -3e-3),
        gyro_scale_factor: Vector3::new(3e-5, -2e-5, 1e-5),
        accel_scale_factor: Vector3::new(5e-5, -4e-5, 2e-5),
    };
    let raw = ImuIncrement::from_rates(
        &Vector3::new(0.3, -1.2, 1.7),
        &Vector3::new(4.0, 30.0, -12.0),
        0.002,
    );
    let out = correct_increment(&raw, &corrections, &ImuErrorEstimate::default()).unwrap();
    // The strapdown's step 1 (nav-core/src/strapdown.rs).
    let angle = raw.delta_angle_rad
        - corrections
            .gyro_scale_factor
            .component_mul(&raw.delta_angle_rad)
        - corrections.gyro_bias_rad_s * raw.interval_s;
    let velocity = raw.delta_velocity_mps
        - corrections
            .accel_scale_factor
            .component_mul(&raw.delta_velocity_mps)
        - corrections.accel_bias_mps2 * raw.interval_s;
    for (a, b) in out
        .delta_angle_rad
        .iter()
        .chain(out.delta_velocity_mps.iter())
        .zip(angle.iter().chain(velocity.iter()))
    {
        assert_eq!(a.to_bits(), b.to_bits());
    }
    let bad = ImuIncrement {
        interval_s: 0.0,
        ..raw
    };
    assert_eq!(
        correct_increment(&bad, &corrections, &ImuErrorEstimate::default()),
        Err(NavError::InvalidTimeStep)
    );
}

// ---- The columns against the nonlinear strapdown -------------------------------------------

const TRUE_RATE: Vector3<f64> = Vector3::new(0.3, -0.5, 0.4);
const TRUE_FORCE: Vector3<f64> = Vector3::new(25.0, 3.0, -4.0);
const HORIZON_S: f64 = 2.0;
const STEPS: usize = 400;

fn initial_attitude() -> Quaternion<f64> {
    exp_rotation_vector(&Vector3::new(0.3, -0.7, 1.1))
}

/// Truth parameters as an [`ImuErrorEstimate`] from the 12-vector.
fn estimate_of(p: &Params) -> ImuErrorEstimate {
    ImuErrorEstimate {
        gyro_non_orthogonality_rad: p.fixed_rows::<3>(0).into(),
        accel_misalignment_rad: p.fixed_rows::<6>(3).into(),
        gyro_g_sensitivity_rad_s_per_mps2: p.fixed_rows::<3>(9).into(),
    }
}

/// The simulator's sensor (`M = I + A` on the true rate and force, `g∘f` on the true force).
fn measured(p: &Params) -> (Vector3<f64>, Vector3<f64>) {
    let e = estimate_of(p);
    let rate = TRUE_RATE
        + e.gyro_matrix() * TRUE_RATE
        + e.gyro_g_sensitivity_rad_s_per_mps2
            .component_mul(&TRUE_FORCE);
    let force = TRUE_FORCE + e.accel_matrix() * TRUE_FORCE;
    (rate, force)
}

fn rk4<const N: usize>(
    y: &SVector<f64, N>,
    t: f64,
    h: f64,
    f: impl Fn(f64, &SVector<f64, N>) -> SVector<f64, N>,
) -> SVector<f64, N> {
    let k1 = f(t, y);
    let k2 = f(t + 0.5 * h, &(y + k1 * (0.5 * h)));
    let k3 = f(t + 0.5 * h, &(y + k2 * (0.5 * h)));
    let k4 = f(t + h, &(y + k3 * h));
    y + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0)
}

/// The nonlinear error (ϑ, δp, δv in a 24-vector) after [`HORIZON_S`] between the truth (the
/// true rate and force) and the strapdown fed with the measurements of truth `p` corrected
/// with a zero estimate (uniform gravity: it cancels in the difference).
fn nonlinear_error(p: &Params) -> Full {
    let (rate_m, force_m) = measured(p);
    let q0 = initial_attitude();
    let truth = |t: f64| product(&q0, &exp_rotation_vector(&(TRUE_RATE * t)));
    let estimate = |t: f64| product(&q0, &exp_rotation_vector(&(rate_m * t)));
    let h = HORIZON_S / STEPS as f64;
    // y = (δv, δp); δv̇ = C f − Ĉ f̂.
    let mut y = SVector::<f64, 6>::zeros();
    for step in 0..STEPS {
        let t = step as f64 * h;
        y = rk4(&y, t, h, |s, y| {
            let dv =
                rotation_matrix(&truth(s)) * TRUE_FORCE - rotation_matrix(&estimate(s)) * force_m;
            let mut d = SVector::<f64, 6>::zeros();
            d.fixed_rows_mut::<3>(0).copy_from(&dv);
            d.fixed_rows_mut::<3>(3).copy_from(&y.fixed_rows::<3>(0));
            d
        });
    }
    let delta_q = product(&conjugate(&estimate(HORIZON_S)), &truth(HORIZON_S));
    let mut error = Full::zeros();
    error
        .fixed_rows_mut::<3>(ATTITUDE.index())
        .copy_from(&delta_q.imag());
    error
        .fixed_rows_mut::<3>(VELOCITY.index())
        .copy_from(&y.fixed_rows::<3>(0));
    error
        .fixed_rows_mut::<3>(POSITION.index())
        .copy_from(&y.fixed_rows::<3>(3));
    error
}

/// The linear prediction `δẋ = A(t) δx + B(t) p` along the estimate (its measured rate and
/// force, its attitude), integrated with RK4;
/// `flip` negates one column of `B` (the sign-error check).
fn linear_error(p: &Params, flip: Option<usize>) -> Full {
    let (rate_m, force_m) = measured(p);
    let q0 = initial_attitude();
    let point = |t: f64| LinearisationPoint {
        corrected_rate_rad_s: rate_m,
        corrected_specific_force_mps2: force_m,
        measured_rate_rad_s: rate_m,
        measured_specific_force_mps2: force_m,
        body_to_inertial: rotation_matrix(&product(&q0, &exp_rotation_vector(&(rate_m * t)))),
        gravity_gradient_per_s2: Matrix3::zeros(),
    };
    let h = HORIZON_S / STEPS as f64;
    let mut x = Full::zeros();
    for step in 0..STEPS {
        let t = step as f64 * h;
        x = rk4(&x, t, h, |s, x| {
            let point = point(s);
            let mut b = system_columns(&point);
            if let Some(column) = flip {
                let negated = -b.column(column);
                b.set_column(column, &negated);
            }
            system_matrix(&point) * x + b * p
        });
    }
    x
}

/// The truth's IMU has the systematic errors `p` (and no others), the estimate corrects
/// none (`p̂ = 0`), so the error state is `δp = p` and the navigation error is driven by `p`
/// alone. Returns the nonlinear − linear mismatch at `p` and `p/2`, and the linear size:
/// second order means halving `p` quarters the mismatch.
fn mismatch_ratio(p: &Params, flip: Option<usize>) -> (f64, f64, f64) {
    let mut mismatch = [0.0; 2];
    let mut size = 0.0;
    for (slot, halving) in [1.0, 0.5].into_iter().enumerate() {
        let scaled = p * halving;
        let nonlinear = nonlinear_error(&scaled);
        let linear = linear_error(&scaled, flip);
        mismatch[slot] = (nonlinear - linear).amax();
        if slot == 0 {
            size = linear.amax();
        }
    }
    (mismatch[0], mismatch[1], size)
}

fn unit_parameter(k: usize) -> Params {
    let scale = if k >= ImuErrorBlock::GyroGSensitivity.offset() {
        1e-4
    } else {
        1e-3
    };
    let mut p = Params::zeros();
    p[k] = scale;
    p
}

#[test]
fn columns_predict_the_nonlinear_strapdown_to_second_order() {
    for k in 0..IMU_ERROR_DIMENSION {
        let (first, second, size) = mismatch_ratio(&unit_parameter(k), None);
        let ratio = first / second;
        println!(
            "state {k}: |linear| {size:.3e}, mismatch {first:.3e} / {second:.3e} ({ratio:.3})"
        );
        assert!(size > 1e-6, "state {k} has no effect");
        // One accelerometer term alone enters δv exactly linearly: it does not move the
        // attitude, and `f = (I + A)⁻¹ f_m = f_m − A f_m` when `A² = 0` (a single
        // off-diagonal term). Its mismatch is the integrator's round-off.
        let at_round_off = first <= 1e-9 * size;
        let accel = ImuErrorBlock::AccelMisalignment;
        assert!(
            !at_round_off || (accel.offset()..accel.offset() + accel.dimension()).contains(&k),
            "state {k}: a gyro term cannot be exactly linear"
        );
        assert!(
            at_round_off || (3.5..4.5).contains(&ratio),
            "state {k}: ratio {ratio}"
        );
        assert!(first < 0.05 * size, "state {k}: {first} vs {size}");
    }
}

#[test]
fn a_flipped_column_sign_is_caught() {
    for k in [0, 3, 9] {
        let (first, _, size) = mismatch_ratio(&unit_parameter(k), Some(k));
        assert!(first > 0.5 * size, "state {k}: {first} vs {size}");
    }
}

// ---- The gauge map -----------------------------------------------------------------------

fn truth() -> ImuTruth {
    ImuTruth {
        gyro_misalignment_rad: Matrix3::new(0.0, 3e-4, -2e-4, 1e-4, 0.0, 4e-4, -5e-4, 2e-4, 0.0),
        accel_misalignment_rad: Matrix3::new(0.0, -4e-4, 1e-4, 2e-4, 0.0, -3e-4, 5e-4, 1e-4, 0.0),
        gyro_g_sensitivity_rad_s_per_mps2: Vector3::new(2e-6, -1e-6, 3e-6),
        gyro_bias_rad_s: Vector3::new(1e-4, 2e-4, 3e-4),
        accel_bias_mps2: Vector3::new(2e-3, -1e-3, 3e-3),
        gyro_scale_factor: Vector3::new(3e-5, -2e-5, 1e-5),
        accel_scale_factor: Vector3::new(5e-5, -4e-5, 2e-5),
        star_mounting: exp_rotation_vector(&Vector3::new(0.2, 1.3, -0.4)),
        star_installation: exp_rotation_vector(&Vector3::new(2e-3, 4e-3, 6e-3)),
    }
}

/// The simulator's measured rates for a true body rate and specific force.
fn simulator_measurement(
    truth: &ImuTruth,
    rate: &Vector3<f64>,
    force: &Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let identity = Matrix3::<f64>::identity();
    let gyro = (identity + truth.gyro_misalignment_rad) * rate
        + truth.gyro_g_sensitivity_rad_s_per_mps2.component_mul(force)
        + truth.gyro_bias_rad_s;
    let accel = (identity + truth.accel_misalignment_rad) * force + truth.accel_bias_mps2;
    let unscale =
        |v: Vector3<f64>, lambda: &Vector3<f64>| v.component_div(&(Vector3::repeat(1.0) - lambda));
    (
        unscale(gyro, &truth.gyro_scale_factor),
        unscale(accel, &truth.accel_scale_factor),
    )
}

#[test]
fn gauge_map_leaves_the_corrected_measurements_invariant_up_to_the_frame_rotation() {
    let truth = truth();
    let gauge = to_filter_gauge(&truth).unwrap();
    // R = C_b'b.
    let r = rotation_matrix(&gauge.body_rotation).transpose();
    assert!((r * r.transpose() - Matrix3::identity()).amax() < 1e-15);
    let corrections = SensorCorrections {
        gyro_bias_rad_s: gauge.gyro_bias_rad_s,
        accel_bias_mps2: gauge.accel_bias_mps2,
        gyro_scale_factor: gauge.gyro_scale_factor,
        accel_scale_factor: gauge.accel_scale_factor,
    };
    let unmodelled = gauge.unmodelled_g_sensitivity.amax();
    assert!(unmodelled < 1e-8 && unmodelled > 0.0, "{unmodelled:e}");
    for (rate, force) in [
        (Vector3::new(0.1, -0.2, 0.3), Vector3::new(30.0, 1.0, -2.0)),
        (Vector3::new(-1.5, 0.7, 0.0), Vector3::new(0.0, 0.0, 0.0)),
        (Vector3::new(0.0, 0.0, 2.0), Vector3::new(-3.0, 9.8, 12.0)),
    ] {
        let (rate_m, force_m) = simulator_measurement(&truth, &rate, &force);
        let (rate_hat, force_hat) = correct_rates(&rate_m, &force_m, &corrections, &gauge.imu);
        let force_error = (force_hat - r * force).amax();
        assert!(force_error < 1e-13, "{force_error:e}");
        // The model holds diag(N) of the g-sensitivity map; its off-diagonal is left out:
        // ω̂ − R ω = offdiag(N) f_m.
        let rate_error = rate_hat - gauge.unmodelled_g_sensitivity * force_m - r * rate;
        assert!(rate_error.amax() < 1e-15, "{:e}", rate_error.amax());
    }
    // The star measurement is the same in either frame.
    let attitude = exp_rotation_vector(&Vector3::new(0.3, -0.7, 1.1));
    let star = |q_ib: &Quaternion<f64>, q_psi: &Quaternion<f64>| {
        crate::attitude::canonical(&product(&product(q_ib, &truth.star_mounting), q_psi))
    };
    let original = star(&attitude, &truth.star_installation);
    let in_gauge = star(&gauge.attitude(&attitude), &gauge.star_installation);
    assert!((original.coords - in_gauge.coords).amax() < 1e-15);
}

#[test]
fn gauge_frame_is_the_gyro_s() {
    let truth = truth();
    let gauge = to_filter_gauge(&truth).unwrap();
    let r = rotation_matrix(&gauge.body_rotation).transpose();
    // x' along the gyro x sensing axis, z' normal to the x and y sensing axes.
    let sensing = Matrix3::identity() + truth.gyro_misalignment_rad;
    let s_x: Vector3<f64> = sensing.row(0).transpose();
    let s_y: Vector3<f64> = sensing.row(1).transpose();
    let x: Vector3<f64> = r.row(0).transpose();
    let z: Vector3<f64> = r.row(2).transpose();
    assert!(x.cross(&s_x).norm() < 1e-15);
    assert!(z.dot(&s_x).abs() < 1e-15 && z.dot(&s_y).abs() < 1e-15);
    assert!(r.determinant() > 0.0);
    // So R (I + A_g)⁻¹ is lower triangular: the gyro's correction needs no upper term.
    let k_g = r * sensing.try_inverse().unwrap();
    let strictly_upper = (k_g - Matrix3::from_diagonal(&k_g.diagonal())).upper_triangle();
    assert!(strictly_upper.amax() < 1e-15, "{strictly_upper}");
    assert!(k_g.lower_triangle().amax() > 1e-5);
    // The accelerometer's is full: with the truth's misalignments every term is non-zero.
    assert!(gauge
        .imu
        .accel_misalignment_rad
        .iter()
        .all(|a| a.abs() > 1e-5));
}

#[test]
fn gauge_map_to_first_order() {
    // Small terms: R ≈ I − [ρ×] with ρ = (a_yz, −a_xz, a_xy) of the gyro (the rotation that
    // zeroes its upper terms), so the gyro keeps twice its symmetric lower part and the
    // accelerometer gains the frame rotation: A'_a = A_a + [ρ×].
    let mut truth = truth();
    truth.gyro_misalignment_rad *= 0.05;
    truth.accel_misalignment_rad *= 0.05;
    let gauge = to_filter_gauge(&truth).unwrap();
    let a = truth.gyro_misalignment_rad;
    let expected_gyro = Vector3::new(a.m21 + a.m12, a.m31 + a.m13, a.m32 + a.m23);
    let rho = Vector3::new(a.m23, -a.m13, a.m12);
    let expected_accel = truth.accel_misalignment_rad + skew(&rho);
    let second_order = 1e-8;
    // The first-order terms are 1e-5 in size: the tolerance separates them.
    assert!(expected_gyro.amax() > 1e-5 && rho.amax() > 1e-5);
    assert!((gauge.imu.gyro_non_orthogonality_rad - expected_gyro).amax() < second_order);
    assert!((gauge.imu.accel_matrix() - expected_accel).amax() < second_order);
    // The installation error rotates by the frame rotation, in sensor axes.
    let rotated = (gauge.star_installation * conjugate(&truth.star_installation)).imag();
    let in_sensor = rotation_matrix(&truth.star_mounting).transpose() * rho * -0.5;
    assert!((rotated - in_sensor).amax() < second_order);
}

#[test]
fn gauge_map_without_misalignment_is_the_identity() {
    let mut truth = truth();
    truth.gyro_misalignment_rad = Matrix3::zeros();
    truth.accel_misalignment_rad = Matrix3::zeros();
    truth.gyro_g_sensitivity_rad_s_per_mps2 = Vector3::zeros();
    let gauge = to_filter_gauge(&truth).unwrap();
    assert!((gauge.body_rotation.coords - Quaternion::identity().coords).amax() < 1e-300);
    assert!((gauge.gyro_scale_factor - truth.gyro_scale_factor).amax() < 1e-15);
    assert!((gauge.accel_bias_mps2 - truth.accel_bias_mps2).amax() < 1e-18);
    assert!((gauge.star_installation.coords - truth.star_installation.coords).amax() < 1e-15);
    assert!(gauge.imu.gyro_non_orthogonality_rad.amax() < 1e-300);
    assert!(gauge.imu.accel_misalignment_rad.amax() < 1e-300);
}

#[test]
fn gauge_map_refuses_non_finite_input() {
    let mut truth = truth();
    truth.accel_misalignment_rad.m12 = f64::NAN;
    assert!(to_filter_gauge(&truth).is_err());
    let mut truth = self::truth();
    truth.gyro_misalignment_rad.m21 = f64::NAN;
    assert!(to_filter_gauge(&truth).is_err());
}

// ---- The equivalent biases -----------------------------------------------------------------

/// A deterministic pseudo-random value in (−1, 1) (xorshift; the tests need no crate).
fn pseudo_random(state: &mut u64) -> f64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    (*state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

#[test]
fn equivalent_biases_reproduce_the_sensor_model_and_the_columns() {
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    for _ in 0..20 {
        let draw =
            |seed: &mut u64, scale: f64| Vector3::from_fn(|_, _| pseudo_random(seed) * scale);
        let rate = draw(&mut seed, 0.5);
        let force = draw(&mut seed, 30.0);
        let epsilon = Params::from_fn(|_, _| pseudo_random(&mut seed) * 1e-3);
        let e = estimate_of(&epsilon);
        let terms = equivalent_bias_terms(&rate, &force);
        let mut gyro = Vector3::zeros();
        let mut accel = Vector3::zeros();
        for (term, value) in terms.iter().zip(epsilon.iter()) {
            match term.sensor {
                BiasSensor::Gyro => gyro[term.axis] += term.multiplier * value,
                BiasSensor::Accel => accel[term.axis] += term.multiplier * value,
            }
        }
        let expected_gyro =
            e.gyro_matrix() * rate + e.gyro_g_sensitivity_rad_s_per_mps2.component_mul(&force);
        let expected_accel = e.accel_matrix() * force;
        assert!(expected_gyro.amax() > 1e-5 && expected_accel.amax() > 1e-3);
        assert!(
            (gyro - expected_gyro).amax() < 1e-15,
            "{gyro} {expected_gyro}"
        );
        assert!(
            (accel - expected_accel).amax() < 1e-13,
            "{accel} {expected_accel}"
        );

        // Column k of B is the bias column of A times m_k.
        let point = LinearisationPoint {
            corrected_rate_rad_s: rate * 0.9,
            corrected_specific_force_mps2: force * 1.1,
            measured_rate_rad_s: rate,
            measured_specific_force_mps2: force,
            body_to_inertial: rotation_matrix(&exp_rotation_vector(&draw(&mut seed, 2.0))),
            gravity_gradient_per_s2: Matrix3::identity() * 1e-6,
        };
        let a = system_matrix(&point);
        let b = system_columns(&point);
        for (k, term) in terms.iter().enumerate() {
            let block = match term.sensor {
                BiasSensor::Gyro => GYRO_BIAS,
                BiasSensor::Accel => ACCEL_BIAS,
            };
            let expected = a.column(block.index() + term.axis) * term.multiplier;
            assert!(expected.amax() > 0.0, "state {k}");
            let column = b.column(k);
            assert!((column - expected).amax() < 1e-15, "state {k}");
        }
    }
    // Pure x rate and x force: only the terms that multiply x survive.
    let terms = equivalent_bias_terms(&Vector3::new(0.2, 0.0, 0.0), &Vector3::new(20.0, 0.0, 0.0));
    let live: Vec<(BiasSensor, usize, f64)> = terms
        .iter()
        .filter(|t| t.multiplier != 0.0)
        .map(|t| (t.sensor, t.axis, t.multiplier))
        .collect();
    assert_eq!(
        live,
        [
            (BiasSensor::Gyro, 1, 0.2),   // non-orthogonality yx
            (BiasSensor::Gyro, 2, 0.2),   // non-orthogonality zx
            (BiasSensor::Accel, 1, 20.0), // misalignment yx
            (BiasSensor::Accel, 2, 20.0), // misalignment zx
            (BiasSensor::Gyro, 0, 20.0),  // g-sensitivity x
        ]
    );
}
