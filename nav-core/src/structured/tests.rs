//! Structured-versus-dense equivalence tests and the shared random cases.

use super::*;
use nalgebra::{Matrix3, SMatrix};

use crate::attitude::{exp_rotation_vector, rotation_matrix};
use crate::block::IDENTITY;
use crate::discretise::discretise;
use crate::discretise::{CovarianceMatrix, MAX_ORDER};
use crate::error_model::{noise_input_matrix, system_matrix};
use crate::error_model::{LinearisationPoint, ProcessNoise};
use crate::filter::{ErrorState, ErrorStateFilter, FilterConfig, FilterMode, InitialUncertainty};
use crate::measurement::{gnss_position, refer_to_later_time, star_sensor, LinearMeasurement};
use crate::state::{
    BlockMask, StateBlock, GYRO_BIAS, STAR_INSTALLATION, STATE_DIMENSION, VELOCITY,
};
use crate::NavError;

/// The 3×3 block (`row`, `column`) of a matrix.
fn block<const R: usize, const C: usize>(
    matrix: &SMatrix<f64, R, C>,
    row: StateBlock,
    column: StateBlock,
) -> Matrix3<f64> {
    matrix
        .fixed_view::<3, 3>(row.index(), column.index())
        .into_owned()
}

use nalgebra::{Quaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Largest element-wise difference of two covariances in correlation units,
/// `max |A_ij − B_ij| / √(B_ii B_jj)` (a zero-variance pair must match exactly).
fn relative_difference(a: &CovarianceMatrix, b: &CovarianceMatrix) -> f64 {
    relative_to(a, b, b)
}

/// `max |A_ij − B_ij| / √(S_ii S_jj)`: the difference in units of the scale `S`.
pub(crate) fn relative_to(
    a: &CovarianceMatrix,
    b: &CovarianceMatrix,
    scale: &CovarianceMatrix,
) -> f64 {
    let b_scale = scale;
    let mut worst = 0.0f64;
    for i in 0..24 {
        for j in 0..24 {
            let scale = (b_scale[(i, i)] * b_scale[(j, j)]).sqrt();
            let difference = (a[(i, j)] - b[(i, j)]).abs();
            let relative = if scale > 0.0 {
                difference / scale
            } else if difference > 0.0 {
                f64::INFINITY
            } else {
                0.0
            };
            worst = worst.max(relative);
        }
    }
    worst
}

/// Largest difference of two error states in units of the 1σ of `p`.
fn state_difference(a: &ErrorState, b: &ErrorState, p: &CovarianceMatrix) -> f64 {
    (0..24)
        .map(|i| (a[i] - b[i]).abs() / p[(i, i)].sqrt())
        .fold(0.0, f64::max)
}

pub(crate) fn random_vector(rng: &mut ChaCha8Rng, largest_norm: f64) -> Vector3<f64> {
    let direction = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
    direction.normalize() * rng.random_range(0.0..largest_norm)
}

/// Physical 1σ scale of each block (attitude rad, m, m/s, rad/s, m/s², rad, -, -).
const BLOCK_SCALES: [f64; 8] = [1e-3, 30.0, 0.3, 5e-4, 5e-3, 2e-3, 1e-4, 1e-4];

/// A random symmetric positive-definite P with physical block scales and strong
/// correlations: `D (B Bᵀ/24 + 0.05 I) D`.
pub(crate) fn random_covariance(rng: &mut ChaCha8Rng) -> CovarianceMatrix {
    let b = CovarianceMatrix::from_fn(|_, _| rng.random_range(-1.0..1.0));
    let d = CovarianceMatrix::from_diagonal(&SMatrix::<f64, 24, 1>::from_fn(|i, _| {
        BLOCK_SCALES[i / 3] * rng.random_range(0.5..2.0)
    }));
    let p = d * (b * b.transpose() / 24.0 + CovarianceMatrix::identity() * 0.05) * d;
    (p + p.transpose()) * 0.5
}

pub(crate) fn random_state(rng: &mut ChaCha8Rng) -> ErrorState {
    ErrorState::from_fn(|i, _| BLOCK_SCALES[i / 3] * rng.random_range(-1.0..1.0))
}

/// Random motion: rates up to 2 rad/s, specific forces up to 50 m/s², random attitude,
/// point-mass gravity gradient at a random position 6,400-7,000 km from the centre.
pub(crate) fn random_point(rng: &mut ChaCha8Rng) -> LinearisationPoint {
    let rate = random_vector(rng, 2.0);
    let force = random_vector(rng, 50.0);
    let radius = rng.random_range(6.4e6..7.0e6);
    let position = random_vector(rng, 1.0).normalize() * radius;
    LinearisationPoint {
        corrected_rate_rad_s: rate,
        corrected_specific_force_mps2: force,
        measured_rate_rad_s: rate + random_vector(rng, 1e-3),
        measured_specific_force_mps2: force + random_vector(rng, 1e-2),
        body_to_inertial: rotation_matrix(&exp_rotation_vector(&random_vector(rng, 3.1))),
        gravity_gradient_per_s2: crate::error_model::tests::point_mass_gradient(&position),
    }
}

pub(crate) fn random_noise(rng: &mut ChaCha8Rng, with_bias_walk: bool) -> ProcessNoise {
    let walk = if with_bias_walk { 1.0 } else { 0.0 };
    ProcessNoise {
        gyro_noise_density_rad_s_per_sqrt_hz: rng.random_range(1e-7..1e-5),
        accel_noise_density_mps2_per_sqrt_hz: rng.random_range(1e-5..1e-3),
        gyro_bias_walk_rad_s2_per_sqrt_hz: walk * rng.random_range(1e-9..1e-7),
        accel_bias_walk_mps3_per_sqrt_hz: walk * rng.random_range(1e-7..1e-5),
    }
}

pub(crate) fn random_mask(rng: &mut ChaCha8Rng) -> BlockMask {
    let mut mask = BlockMask::NONE;
    for block in StateBlock::ALL {
        if rng.random_bool(0.3) {
            mask.insert(block);
        }
    }
    mask
}

pub(crate) fn filter_with(mode: FilterMode, p: &CovarianceMatrix) -> ErrorStateFilter {
    let mut filter = ErrorStateFilter::new(&FilterConfig {
        mode,
        discretisation_order: 3,
        initial: InitialUncertainty {
            attitude_rad: 1.0,
            position_m: 1.0,
            velocity_mps: 1.0,
            gyro_bias_rad_s: 1.0,
            accel_bias_mps2: 1.0,
            star_installation_rad: 1.0,
            gyro_scale_factor: 1.0,
            accel_scale_factor: 1.0,
        },
        gnss_error: crate::gnss_error::GnssErrorModel::WHITE,
        imu_error: crate::imu_error_states::ImuErrorModel::DISABLED,
    })
    .unwrap();
    filter.set_covariance(p).unwrap();
    filter
}

/// Dense reference `F`, `Qd` with the frozen blocks' noise removed as the scheduler does.
fn dense_model(
    point: &LinearisationPoint,
    noise: &ProcessNoise,
    interval_s: f64,
    order: u8,
    frozen: &BlockMask,
) -> crate::discretise::DiscreteModel {
    let mut model = discretise(
        &system_matrix(point),
        &noise_input_matrix(point),
        &noise.spectral_density_diagonal(),
        interval_s,
        order,
    )
    .unwrap();
    model.remove_process_noise(frozen);
    model
}

#[test]
fn structured_model_blocks_equal_the_dense_series_for_every_order() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for order in 1..=MAX_ORDER {
        for case in 0..100 {
            let point = random_point(&mut rng);
            let noise = random_noise(&mut rng, case % 2 == 0);
            let interval_s = [0.002, 0.02, 0.1][case % 3];
            let dense = dense_model(&point, &noise, interval_s, order, &BlockMask::NONE);
            let model = StructuredModel::new(&point, &noise, interval_s, order).unwrap();
            let f = model.transition_matrix();
            let q = model.process_noise_matrix();
            for row in StateBlock::ALL {
                for column in StateBlock::ALL {
                    for (structured, reference, name) in [
                        (&f, &dense.transition, "F"),
                        (&q, &dense.process_noise, "Qd"),
                    ] {
                        let s = block(structured, row, column);
                        let r = block(reference, row, column);
                        let bound = 1e-12 * r.amax();
                        assert!(
                            (s - r).amax() <= bound,
                            "order {order} case {case} {name}[{}, {}]: {:e} vs {:e}",
                            row.name(),
                            column.name(),
                            (s - r).amax(),
                            r.amax()
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn structured_propagation_equals_the_dense_reference_for_every_order() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut worst = [0.0f64; 4];
    for order in 1..=MAX_ORDER {
        for case in 0..200 {
            let point = random_point(&mut rng);
            let noise = random_noise(&mut rng, case % 2 == 1);
            let interval_s = [0.002, 0.004, 0.02, 0.1][case % 4];
            let frozen = if case % 3 == 0 {
                random_mask(&mut rng)
            } else {
                BlockMask::NONE
            };
            let p = random_covariance(&mut rng);
            let dense_model = dense_model(&point, &noise, interval_s, order, &frozen);
            let mut model = StructuredModel::new(&point, &noise, interval_s, order).unwrap();
            model.remove_process_noise(&frozen);
            let mut dense = filter_with(FilterMode::ClosedLoop, &p);
            let mut structured = dense;
            dense.predict(&dense_model).unwrap();
            structured.predict_structured(&model).unwrap();
            let p_dense = dense.covariance();
            let p_structured = structured.covariance();
            assert_eq!(
                p_structured,
                &p_structured.transpose(),
                "symmetric by construction"
            );
            let difference = relative_difference(p_structured, p_dense);
            let slot = &mut worst[usize::from(order - 1)];
            *slot = slot.max(difference);
            assert!(
                difference <= 1e-12,
                "order {order} case {case}: {difference:e}"
            );
            // The untouched calibration block is bit-identical.
            assert_eq!(
                p_structured.fixed_view::<15, 15>(9, 9),
                p.fixed_view::<15, 15>(9, 9).map(|v| v)
                    + model.process_noise_matrix().fixed_view::<15, 15>(9, 9),
            );
            // Open loop: x ← F x.
            let x = random_state(&mut rng);
            let structured_x = model.propagate_state(&x);
            let dense_x = dense_model.transition * x;
            let state_error = state_difference(&structured_x, &dense_x, p_dense);
            assert!(
                state_error <= 1e-12,
                "order {order} case {case}: x {state_error:e}"
            );
        }
    }
    println!(
        "largest |structured − dense| / √(P_ii P_jj) per order 1..4: {:.2e} {:.2e} {:.2e} {:.2e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}

/// The row kernel (the host's) and the block kernel (the Cortex-M7's) give the same
/// bits: random SPD `P`, a diagonal `P` (the initial covariance: many products are
/// signed zeros), random motion, every order, with and without walks and frozen noise;
/// and both refuse an overflow leaving `P` unchanged.
#[test]
fn the_row_kernel_equals_the_block_kernel_bit_for_bit() {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let bits = |p: &CovarianceMatrix| p.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    let mut compared = 0;
    for order in 1..=MAX_ORDER {
        for case in 0..120 {
            let point = random_point(&mut rng);
            let noise = random_noise(&mut rng, case % 2 == 1);
            let interval_s = [0.002, 0.004, 0.02, 0.1][case % 4];
            let mut model = StructuredModel::new(&point, &noise, interval_s, order).unwrap();
            if case % 3 == 0 {
                model.remove_process_noise(&random_mask(&mut rng));
            }
            let p = if case % 5 == 0 {
                CovarianceMatrix::from_diagonal(&random_covariance(&mut rng).diagonal())
            } else {
                random_covariance(&mut rng)
            };
            // Half the cases with a border's bias inputs (crate::imu_error_states).
            let border = (case % 2 == 0).then(|| random_border(&mut rng));
            let (mut by_blocks, mut by_rows) = (p, p);
            assert!(model.propagate_covariance_by_blocks(&mut by_blocks, border.as_ref()));
            assert!(model.propagate_covariance_by_rows(&mut by_rows, border.as_ref()));
            assert_eq!(
                bits(&by_rows),
                bits(&by_blocks),
                "order {order} case {case}"
            );
            assert_ne!(bits(&by_rows), bits(&p), "the propagation changed P");
            compared += 1;
        }
    }
    assert_eq!(compared, 480);
    // A non-finite value that only the new P_dc reads (P_bg,ψ: the installation columns
    // of U), or only the new P_dd reads (P_vv): both kernels refuse, P unchanged.
    let noise = random_noise(&mut rng, true);
    let model = StructuredModel::new(&random_point(&mut rng), &noise, 0.02, 3).unwrap();
    for (row, column) in [
        (GYRO_BIAS.index(), STAR_INSTALLATION.index()),
        (VELOCITY.index(), VELOCITY.index()),
    ] {
        let mut p = random_covariance(&mut rng);
        p[(row, column)] = f64::INFINITY;
        p[(column, row)] = f64::INFINITY;
        let (mut by_blocks, mut by_rows) = (p, p);
        assert!(!model.propagate_covariance_by_blocks(&mut by_blocks, None));
        assert!(!model.propagate_covariance_by_rows(&mut by_rows, None));
        assert_eq!(bits(&by_blocks), bits(&p));
        assert_eq!(bits(&by_rows), bits(&p));
    }
    // An overflowing propagation: both kernels refuse it and leave P as it was.
    let noise = random_noise(&mut rng, true);
    let model = StructuredModel::new(&random_point(&mut rng), &noise, 0.1, 3).unwrap();
    let p = CovarianceMatrix::from_element(f64::MAX);
    let (mut by_blocks, mut by_rows) = (p, p);
    assert!(!model.propagate_covariance_by_blocks(&mut by_blocks, None));
    assert!(!model.propagate_covariance_by_rows(&mut by_rows, None));
    assert_eq!(bits(&by_blocks), bits(&p));
    assert_eq!(bits(&by_rows), bits(&p));
}

/// Random bias inputs of a border ([`super::BorderBiasInputs`]), of the size a 24×12
/// cross-covariance times a measured rate or force gives.
fn random_border(rng: &mut ChaCha8Rng) -> super::BorderBiasInputs {
    let mut value = || rng.random_range(-1e-3..1e-3);
    super::BorderBiasInputs {
        state_columns: core::array::from_fn(|_| core::array::from_fn(|_| value())),
        dynamic_rows: core::array::from_fn(|_| core::array::from_fn(|_| value())),
    }
}

pub(crate) fn random_quaternion(rng: &mut ChaCha8Rng, largest_angle_rad: f64) -> Quaternion<f64> {
    exp_rotation_vector(&random_vector(rng, largest_angle_rad))
}

/// A star (`star = true`) or GNSS measurement at a random geometry, optionally referred
/// to a later time with `H (I − AΔ)` (extra bias, scale-factor and velocity columns).
pub(crate) fn random_measurement(
    rng: &mut ChaCha8Rng,
    star: bool,
    referred: bool,
) -> LinearMeasurement {
    let attitude = random_quaternion(rng, 3.1);
    let measurement = if star {
        let mounting = random_quaternion(rng, 3.1);
        let installation = random_quaternion(rng, 5e-3);
        let offset = random_quaternion(rng, 1e-3);
        let measured = crate::attitude::product(
            &crate::attitude::product(&attitude, &offset),
            &crate::attitude::product(&mounting, &installation),
        );
        star_sensor(
            &attitude,
            &mounting,
            &installation,
            &measured,
            &[10.0 / 206_264.8; 3],
        )
        .unwrap()
    } else {
        let position = random_vector(rng, 7e6);
        let lever_arm = random_vector(rng, 3.0);
        let fix =
            position + crate::attitude::rotate(&attitude, &lever_arm) + random_vector(rng, 50.0);
        gnss_position(
            &attitude,
            &position,
            &lever_arm,
            &fix,
            rng.random_range(0.1..10.0),
        )
        .unwrap()
    };
    if referred {
        let point = random_point(rng);
        refer_to_later_time(
            &measurement,
            &system_matrix(&point),
            rng.random_range(0.0..0.1),
        )
        .unwrap()
    } else {
        measurement
    }
}

#[test]
fn structured_update_equals_the_dense_joseph_update() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut worst_covariance = 0.0f64;
    let mut worst_posterior = 0.0f64;
    let mut worst_state = 0.0f64;
    for case in 0..400 {
        let star = case % 2 == 0;
        let referred = case % 4 >= 2;
        let mut prior = filter_with(FilterMode::OpenLoop, &random_covariance(&mut rng));
        // A non-zero open-loop state, from an earlier (dense) update.
        let earlier = random_measurement(&mut rng, !star, false);
        prior.update(&earlier, f64::INFINITY).unwrap();
        let frozen = if case % 3 == 0 {
            random_mask(&mut rng)
        } else {
            BlockMask::NONE
        };
        let measurement = random_measurement(&mut rng, star, referred);
        let mut dense = prior;
        let mut structured = prior;
        let dense_report = dense
            .update_with_frozen_blocks(&measurement, f64::INFINITY, &frozen)
            .unwrap();
        let structured_report = structured
            .update_structured(&measurement, f64::INFINITY, &frozen)
            .unwrap();
        assert!(dense_report.accepted && structured_report.accepted);
        let nis = dense_report.normalised_innovation_squared;
        assert!(
            (structured_report.normalised_innovation_squared - nis).abs() <= 1e-12 * nis,
            "case {case}: NIS"
        );
        let p = structured.covariance();
        assert_eq!(p, &p.transpose(), "symmetric by construction");
        // Both updates compute P⁺ = P⁻ − (…) and carry a rounding error of order ε·P⁻,
        // so the difference is measured in units of the prior; in units of a posterior
        // collapsed by a precise measurement it would measure the measurement's
        // conditioning, not the implementation (printed for information).
        let covariance_error = relative_to(p, dense.covariance(), prior.covariance());
        worst_posterior = worst_posterior.max(relative_difference(p, dense.covariance()));
        let state_error = state_difference(structured.state(), dense.state(), prior.covariance());
        worst_covariance = worst_covariance.max(covariance_error);
        worst_state = worst_state.max(state_error);
        assert!(
            covariance_error <= 1e-12,
            "case {case}: P {covariance_error:e}"
        );
        assert!(state_error <= 1e-12, "case {case}: x {state_error:e}");
        // Frozen blocks: the estimate does not move (bit for bit), as in the dense update.
        assert_frozen_blocks_unmoved(&structured, &prior, &frozen);
    }
    println!(
        "structured vs dense update: P {worst_covariance:.2e} (prior correlation units; \
         {worst_posterior:.2e} in posterior units), x {worst_state:.2e} prior σ"
    );
}

#[test]
fn a_gated_structured_update_leaves_the_filter_bit_identical() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut filter = filter_with(FilterMode::OpenLoop, &random_covariance(&mut rng));
    let measurement = random_measurement(&mut rng, false, true);
    let before = filter;
    let report = filter
        .update_structured(&measurement, 1e-12, &BlockMask::NONE)
        .unwrap();
    assert!(!report.accepted);
    assert!(report.normalised_innovation_squared > 1e-12);
    assert_eq!(filter, before);
    let mut nan = measurement;
    nan.residual.x = f64::NAN;
    assert_eq!(
        filter.update_structured(&nan, f64::INFINITY, &BlockMask::NONE),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(
        filter.update_structured(&measurement, f64::NAN, &BlockMask::NONE),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(filter, before);
}

#[test]
fn referring_by_blocks_equals_the_dense_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for case in 0..200 {
        let measurement = random_measurement(&mut rng, case % 2 == 0, false);
        let point = random_point(&mut rng);
        let latency_s = rng.random_range(0.0..0.126);
        let dense = refer_to_later_time(&measurement, &system_matrix(&point), latency_s).unwrap();
        let structured = refer_to_later_time_at(&measurement, &point, latency_s).unwrap();
        assert_eq!(structured.residual, dense.residual);
        assert_eq!(structured.noise_covariance, dense.noise_covariance);
        let scale = dense.jacobian.amax();
        let difference = (structured.jacobian - dense.jacobian).amax();
        assert!(
            difference <= 1e-15 * scale,
            "case {case}: {difference:e} of {scale:e}"
        );
        // The columns A never reaches (installation) are untouched bit for bit.
        assert_eq!(
            structured
                .jacobian
                .fixed_columns::<3>(STAR_INSTALLATION.index()),
            measurement
                .jacobian
                .fixed_columns::<3>(STAR_INSTALLATION.index())
        );
    }
    // A measurement already referred once (its `H` has velocity, bias and scale-factor
    // columns, so every block of `H A` is reached, `H_v V` and `−H_v Ĉ` included).
    for case in 0..100 {
        let measurement = random_measurement(&mut rng, case % 2 == 0, true);
        let point = random_point(&mut rng);
        let latency_s = rng.random_range(0.0..0.126);
        let dense = refer_to_later_time(&measurement, &system_matrix(&point), latency_s).unwrap();
        let structured = refer_to_later_time_at(&measurement, &point, latency_s).unwrap();
        let scale = dense.jacobian.amax();
        let difference = (structured.jacobian - dense.jacobian).amax();
        assert!(
            difference <= 1e-15 * scale,
            "referred case {case}: {difference:e} of {scale:e}"
        );
    }
    let measurement = random_measurement(&mut rng, false, false);
    let point = random_point(&mut rng);
    assert_eq!(
        refer_to_later_time_at(&measurement, &point, -1.0),
        Err(NavError::InvalidTimeStep)
    );
    let mut bad = point;
    bad.gravity_gradient_per_s2[(0, 0)] = f64::NAN;
    assert_eq!(
        refer_to_later_time_at(&measurement, &bad, 0.01),
        Err(NavError::NonFiniteInput)
    );
}

/// The estimate of every `frozen` block of `filter` is bit for bit that of `prior`.
pub(crate) fn assert_frozen_blocks_unmoved(
    filter: &ErrorStateFilter,
    prior: &ErrorStateFilter,
    frozen: &BlockMask,
) {
    for block in StateBlock::ALL {
        if frozen.contains(block) {
            assert_eq!(filter.block(block), prior.block(block), "{}", block.name());
        }
    }
}

/// Every state with both border blocks: 24 + 3 correlated GNSS error states + 12 systematic
/// IMU error states.
pub(crate) const BORDERED: usize = STATE_DIMENSION + 3 + crate::imu_error::IMU_ERROR_DIMENSION;
/// A matrix over [`BORDERED`] states.
pub(crate) type Bordered = SMatrix<f64, BORDERED, BORDERED>;

/// Gives `filter` both border blocks (`receiver`, `imu`) with a random positive-definite
/// 39-state covariance `D (R Rᵀ/39 + 0.05 I) D` at physical scales around its 24-state `P`
/// (whose diagonal sets `D` there; the borders' prior 1σ elsewhere), and random estimates.
pub(crate) fn install_both_borders(
    filter: &mut ErrorStateFilter,
    rng: &mut ChaCha8Rng,
    receiver: crate::gnss_error::GnssErrorModel,
    imu: crate::imu_error_states::ImuErrorModel,
) {
    let p24 = *filter.covariance();
    let sigmas = imu.state_sigmas();
    let scale = nalgebra::SVector::<f64, BORDERED>::from_fn(|i, _| match i {
        0..24 => p24[(i, i)].sqrt(),
        24..27 => receiver.sigma_m,
        _ => sigmas[i - 27],
    });
    let r = Bordered::from_fn(|_, _| rng.random_range(-1.0..1.0));
    let d = Bordered::from_diagonal(&scale);
    let p = d * (r * r.transpose() / (BORDERED as f64) + Bordered::identity() * 0.05) * d;
    let p = (p + p.transpose()) * 0.5;
    filter
        .set_covariance(&p.fixed_view::<24, 24>(0, 0).into_owned())
        .unwrap();
    *filter.gnss_error_mut() = crate::gnss_error::GnssErrorStates::new(receiver).unwrap();
    *filter.imu_error_mut() = crate::imu_error_states::ImuErrorStates::new(imu).unwrap();
    let gnss_estimate = Vector3::from_fn(|_, _| rng.random_range(-5.0..5.0));
    filter.gnss_error_mut().set(
        &gnss_estimate,
        &p.fixed_view::<3, 3>(24, 24).into_owned(),
        &p.fixed_view::<24, 3>(0, 24).into_owned(),
    );
    let imu_estimate =
        nalgebra::SVector::<f64, { crate::imu_error::IMU_ERROR_DIMENSION }>::from_fn(|a, _| {
            sigmas[a] * rng.random_range(-1.0..1.0)
        });
    filter.imu_error_mut().set(
        &imu_estimate,
        &p.fixed_view::<12, 12>(27, 27).into_owned(),
        &p.fixed_view::<24, 12>(0, 27).into_owned(),
    );
    filter
        .imu_error_mut()
        .set_gnss_cross(&p.fixed_view::<3, 12>(24, 27).into_owned());
}

/// The filter's whole covariance over [`BORDERED`] states (the border entries zero for a
/// border not in use).
pub(crate) fn whole_covariance(filter: &ErrorStateFilter) -> Bordered {
    let mut p = Bordered::zeros();
    p.fixed_view_mut::<24, 24>(0, 0)
        .copy_from(filter.covariance());
    if filter.gnss_error().is_enabled() {
        let c = filter.gnss_error().cross_covariance();
        p.fixed_view_mut::<24, 3>(0, 24).copy_from(&c);
        p.fixed_view_mut::<3, 24>(24, 0).copy_from(&c.transpose());
        p.fixed_view_mut::<3, 3>(24, 24)
            .copy_from(&filter.gnss_error().covariance());
    }
    if filter.imu_error().is_enabled() {
        let imu = filter.imu_error();
        let (c, b) = (imu.cross_covariance(), imu.gnss_cross_covariance());
        p.fixed_view_mut::<24, 12>(0, 27).copy_from(&c);
        p.fixed_view_mut::<12, 24>(27, 0).copy_from(&c.transpose());
        p.fixed_view_mut::<12, 12>(27, 27)
            .copy_from(&imu.covariance());
        p.fixed_view_mut::<3, 12>(24, 27).copy_from(&b);
        p.fixed_view_mut::<12, 3>(27, 24).copy_from(&b.transpose());
    }
    p
}

/// The filter's whole error state over [`BORDERED`] states.
pub(crate) fn whole_state(filter: &ErrorStateFilter) -> nalgebra::SVector<f64, BORDERED> {
    let (x, g, e) = (
        filter.state(),
        filter.gnss_error().estimate_m(),
        filter.imu_error().estimate(),
    );
    nalgebra::SVector::from_fn(|i, _| match i {
        0..24 => x[i],
        24..27 => g[i - 24],
        _ => e[i - 27],
    })
}

/// The Joseph update's overflow guards, the model's rebuild and high-order terms, and the
/// reset, against the dense reference.
mod model_and_reset;
