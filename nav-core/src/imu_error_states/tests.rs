//! The 36-state border against the dense 36-state reference: `F₃₆ = Σ (A₃₆Δ)ⁿ/n!` with
//! `A₃₆ = [[A, B_ε], [0, 0]]` (`B_ε` = [`crate::imu_error::system_columns`], whose signs
//! `imu_error`'s tests prove against the nonlinear sensor model), `Qd₃₆ = diag(Qd, 0)`, and
//! the dense Joseph update with `H₃₆ = [H 0]`.

use super::*;
use crate::discretise::discretise;
use crate::error_model::{noise_input_matrix, system_matrix, LinearisationPoint};
use crate::filter::{ErrorStateFilter, FilterConfig, FilterMode};
use crate::imu_error::system_columns;
use crate::measurement::LinearMeasurement;
use crate::state::BlockMask;
use crate::structured::tests::{
    filter_with, install_both_borders, random_covariance, random_mask, random_measurement,
    random_noise, random_point, whole_covariance, whole_state, Bordered, BORDERED,
};
use crate::structured::StructuredModel;
use nalgebra::{Cholesky, Matrix3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const N: usize = STATE_DIMENSION + IMU_ERROR_DIMENSION;
type Full = SMatrix<f64, N, N>;

/// Prior 1σ: 20 µrad misalignment, 0.5 °/h/g g-sensitivity.
const MODEL: ImuErrorModel = ImuErrorModel {
    gyro_misalignment_sigma_rad: 2e-5,
    accel_misalignment_sigma_rad: 2e-5,
    gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7,
};

/// A filter with the border in use: random 24-state `P`, `C = P W` and
/// `P_εε = Wᵀ P W + diag(σ²)` (positive definite by construction), a random `x` and `ε̂`.
fn bordered_filter(rng: &mut ChaCha8Rng, mode: FilterMode) -> ErrorStateFilter {
    let p = random_covariance(rng);
    let mut filter = filter_with(mode, &p);
    *filter.imu_error_mut() = ImuErrorStates::new(MODEL).unwrap();
    let sigmas = MODEL.state_sigmas();
    let w = SMatrix::<f64, STATE_DIMENSION, IMU_ERROR_DIMENSION>::from_fn(|j, a| {
        rng.random_range(-1.0..1.0) * 0.3 / p[(j, j)].sqrt() * sigmas[a]
            / (STATE_DIMENSION as f64).sqrt()
    });
    let cross = p * w;
    let border = w.transpose() * p * w
        + SMatrix::<f64, IMU_ERROR_DIMENSION, IMU_ERROR_DIMENSION>::from_diagonal(&SVector::from(
            sigmas.map(|s| s * s),
        ));
    // Exactly symmetric, as every writer keeps the flight filter's P_εε.
    let border = (border + border.transpose()) * 0.5;
    let estimate = SVector::<f64, IMU_ERROR_DIMENSION>::from_fn(|a, _| {
        sigmas[a] * rng.random_range(-1.0..1.0)
    });
    filter.imu_error_mut().set(&estimate, &border, &cross);
    if mode == FilterMode::OpenLoop {
        // A non-zero open-loop state, from an earlier update.
        let star = rng.random_bool(0.5);
        let earlier = random_measurement(rng, star, false);
        filter
            .update_structured(&earlier, f64::INFINITY, &BlockMask::NONE)
            .unwrap();
    }
    filter
}

fn full_covariance(filter: &ErrorStateFilter) -> Full {
    let (p, c, b) = (
        filter.covariance(),
        filter.imu_error().cross_covariance(),
        filter.imu_error().covariance(),
    );
    Full::from_fn(|i, j| match (i.checked_sub(24), j.checked_sub(24)) {
        (None, None) => p[(i, j)],
        (None, Some(a)) => c[(i, a)],
        (Some(a), None) => c[(j, a)],
        (Some(a), Some(b_)) => b[(a, b_)],
    })
}

fn full_state(filter: &ErrorStateFilter) -> SVector<f64, N> {
    let (x, e) = (filter.state(), filter.imu_error().estimate());
    SVector::from_fn(|i, _| if i < 24 { x[i] } else { e[i - 24] })
}

/// `max |A_ij − B_ij| / √(S_ii S_jj)`.
fn relative(a: &Full, b: &Full, scale: &Full) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..N {
        for j in 0..N {
            let s = (scale[(i, i)] * scale[(j, j)]).sqrt();
            worst = worst.max((a[(i, j)] - b[(i, j)]).abs() / s);
        }
    }
    worst
}

fn dense_transition(point: &LinearisationPoint, interval_s: f64, order: u8) -> Full {
    let mut a = Full::zeros();
    a.fixed_view_mut::<24, 24>(0, 0)
        .copy_from(&system_matrix(point));
    a.fixed_view_mut::<24, 12>(0, 24)
        .copy_from(&system_columns(point));
    let step = a * interval_s;
    let (mut term, mut sum) = (Full::identity(), Full::identity());
    for n in 1..=order {
        term = term * step / f64::from(n);
        sum += term;
    }
    sum
}

/// The structured propagation with the border (flight path) equals the dense 36-state
/// `F P Fᵀ + Qd` and, in open loop, `x ← F x`, for orders 1 to 4.
#[test]
fn border_propagation_equals_the_dense_36_state_transition() {
    let mut rng = ChaCha8Rng::seed_from_u64(36);
    let mut worst = 0.0f64;
    for case in 0..60 {
        let mode = if case % 2 == 0 {
            FilterMode::ClosedLoop
        } else {
            FilterMode::OpenLoop
        };
        let prior = bordered_filter(&mut rng, mode);
        let point = random_point(&mut rng);
        let noise = random_noise(&mut rng, case % 3 == 0);
        let interval_s = rng.random_range(0.002..0.5);
        let order = 1 + (case % 4) as u8;
        let model = StructuredModel::new(&point, &noise, interval_s, order).unwrap();
        let dense_24 = discretise(
            &system_matrix(&point),
            &noise_input_matrix(&point),
            &noise.spectral_density_diagonal(),
            interval_s,
            order,
        )
        .unwrap();
        let f = dense_transition(&point, interval_s, order);
        let mut q = Full::zeros();
        q.fixed_view_mut::<24, 24>(0, 0)
            .copy_from(&dense_24.process_noise);
        let p = full_covariance(&prior);
        let expected = f * p * f.transpose() + q;
        let mut structured = prior;
        structured.predict_structured(&model).unwrap();
        let got = full_covariance(&structured);
        let error = relative(&got, &expected, &p);
        worst = worst.max(error);
        assert!(error < 1e-12, "case {case}: {error:e}");
        // Exactly symmetric.
        let p_xx = structured.covariance();
        assert_eq!(p_xx, &p_xx.transpose(), "case {case}");
        if mode == FilterMode::OpenLoop {
            let x = f * full_state(&prior);
            let got = full_state(&structured);
            for i in 0..N {
                let sigma = p[(i, i)].sqrt();
                assert!((got[i] - x[i]).abs() < 1e-12 * sigma, "case {case}: x {i}");
            }
        }
    }
    println!("structured vs dense 36-state propagation: worst {worst:.2e}");
}

/// The dense 36-state Joseph update with `H₃₆ = [H 0]` and the frozen rows' gain zero.
/// A non-finite value anywhere in the border (`C`'s dynamic or calibration rows, `P_εε`)
/// makes the propagation refuse, in either mode, with nothing changed: the kernel's check
/// covers the new `C` and the bias inputs (`prepare_propagation`'s comment says why).
#[test]
fn a_non_finite_border_is_refused_by_the_propagation_and_changes_nothing() {
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    let mut refused = 0;
    for case in 0..24 {
        let mode = [FilterMode::ClosedLoop, FilterMode::OpenLoop][case % 2];
        let mut filter = bordered_filter(&mut rng, mode);
        let (estimate, mut border, mut cross) = (
            filter.imu_error().estimate(),
            filter.imu_error().covariance(),
            filter.imu_error().cross_covariance(),
        );
        let bad = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY][case % 3];
        let state = rng.random_range(0..IMU_ERROR_DIMENSION);
        match case % 4 {
            0 => cross[(rng.random_range(0..9), state)] = bad,
            1 => cross[(rng.random_range(9..STATE_DIMENSION), state)] = bad,
            _ => {
                let other = rng.random_range(0..IMU_ERROR_DIMENSION);
                border[(state, other)] = bad;
                border[(other, state)] = bad;
            }
        }
        filter.imu_error_mut().set(&estimate, &border, &cross);
        // What the filter reads (NaN prints alike; the spare buffers and scratch may change).
        let readable = |f: &ErrorStateFilter| {
            let imu = f.imu_error();
            format!(
                "{:?}",
                (
                    f.state(),
                    f.covariance(),
                    imu.estimate(),
                    imu.covariance(),
                    imu.cross_covariance(),
                    imu.gnss_cross_covariance(),
                )
            )
        };
        let before = readable(&filter);
        let model = StructuredModel::new(
            &random_point(&mut rng),
            &random_noise(&mut rng, case % 3 == 0),
            0.002,
            3,
        )
        .unwrap();
        assert_eq!(
            filter.predict_structured(&model),
            Err(NavError::NonFiniteState),
            "case {case}"
        );
        assert!(readable(&filter) == before, "case {case}: changed");
        refused += 1;
    }
    assert_eq!(refused, 24);
}

fn dense_update(
    prior: &ErrorStateFilter,
    measurement: &LinearMeasurement,
    frozen: &BlockMask,
) -> (SVector<f64, N>, Full) {
    let p = full_covariance(prior);
    let mut h = SMatrix::<f64, 3, N>::zeros();
    h.fixed_view_mut::<3, 24>(0, 0)
        .copy_from(&measurement.jacobian);
    let x = full_state(prior);
    let innovation = measurement.residual - h * x;
    let s = h * p * h.transpose() + measurement.noise_covariance;
    let cholesky = Cholesky::new(s).unwrap();
    let mut gain: SMatrix<f64, N, 3> = cholesky.solve(&(h * p)).transpose();
    for (i, mut row) in gain.row_iter_mut().enumerate() {
        if i < 24 && frozen.contains_state(i) {
            row.fill(0.0);
        }
    }
    let i_kh = Full::identity() - gain * h;
    let p = i_kh * p * i_kh.transpose() + gain * measurement.noise_covariance * gain.transpose();
    (x + gain * innovation, (p + p.transpose()) * 0.5)
}

/// The structured bordered update (flight path) equals the dense 36-state Joseph update, for
/// star, GNSS and referred GNSS measurements, with and without frozen blocks; a star update
/// moves `ε̂` through its correlation with the attitude.
#[test]
fn border_update_equals_the_dense_36_state_update() {
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    let mut worst = 0.0f64;
    for case in 0..200 {
        let star = case % 3 == 0;
        let referred = case % 2 == 1;
        let mode = if case % 5 == 0 {
            FilterMode::OpenLoop
        } else {
            FilterMode::ClosedLoop
        };
        let prior = bordered_filter(&mut rng, mode);
        let measurement = random_measurement(&mut rng, star, referred);
        let frozen = if case % 4 == 0 {
            random_mask(&mut rng)
        } else {
            BlockMask::NONE
        };
        let (x, p) = dense_update(&prior, &measurement, &frozen);
        let mut structured = prior;
        let report = structured
            .update_structured(&measurement, f64::INFINITY, &frozen)
            .unwrap();
        assert!(report.accepted);
        let scale = full_covariance(&prior);
        let error = relative(&full_covariance(&structured), &p, &scale);
        let got = full_state(&structured);
        let state_error = (0..N)
            .map(|i| (got[i] - x[i]).abs() / scale[(i, i)].sqrt())
            .fold(0.0f64, f64::max);
        worst = worst.max(error).max(state_error);
        assert!(error < 1e-11, "case {case}: P {error:e}");
        assert!(state_error < 1e-11, "case {case}: x {state_error:e}");
        let border = structured.imu_error().covariance();
        assert_eq!(
            border,
            border.transpose(),
            "case {case}: P_εε exactly symmetric"
        );
        assert!(
            structured.imu_error().estimate() != prior.imu_error().estimate(),
            "case {case}"
        );
    }
    println!("structured vs dense 36-state update: worst {worst:.2e}");
}

/// A rejected measurement leaves the border untouched, bit for bit.
#[test]
fn a_gated_measurement_changes_nothing() {
    let mut rng = ChaCha8Rng::seed_from_u64(38);
    let prior = bordered_filter(&mut rng, FilterMode::ClosedLoop);
    let measurement = random_measurement(&mut rng, true, false);
    let mut filter = prior;
    let report = filter
        .update_structured(&measurement, 0.0, &BlockMask::NONE)
        .unwrap();
    assert!(!report.accepted);
    assert_eq!(filter, prior);
}

/// The reset maps `C`'s attitude and installation rows through `J` (as the dense `J P Jᵀ`
/// of the 36 states), keeps its other rows and `P_εε`, and zeroes `ε̂` (fed back by the
/// caller).
#[test]
fn reset_maps_the_cross_covariance_and_zeroes_the_estimate() {
    let mut rng = ChaCha8Rng::seed_from_u64(39);
    let mut prior = bordered_filter(&mut rng, FilterMode::ClosedLoop);
    let measurement = random_measurement(&mut rng, true, false);
    prior
        .update_structured(&measurement, f64::INFINITY, &BlockMask::NONE)
        .unwrap();
    let mut jacobian = Full::identity();
    for offset in [ATTITUDE.index(), STAR_INSTALLATION.index()] {
        let v = prior.state().fixed_rows::<3>(offset).into_owned();
        let block = Matrix3::identity() - crate::attitude::skew(&v);
        jacobian
            .fixed_view_mut::<3, 3>(offset, offset)
            .copy_from(&block);
    }
    let expected = jacobian * full_covariance(&prior) * jacobian.transpose();
    let mut filter = prior;
    filter.reset_in_place();
    let got = full_covariance(&filter);
    let error = relative(&got, &expected, &full_covariance(&prior));
    assert!(error < 1e-14, "{error:e}");
    assert_eq!(
        filter.imu_error().estimate(),
        SVector::<f64, IMU_ERROR_DIMENSION>::zeros()
    );
    assert_eq!(
        filter.imu_error().covariance(),
        prior.imu_error().covariance()
    );
    let (before, after) = (
        prior.imu_error().cross_covariance(),
        filter.imu_error().cross_covariance(),
    );
    for j in 3..15 {
        assert_eq!(before.row(j), after.row(j), "row {j}");
    }
}

/// Widening a block's uncertainty scales its rows of `C` with it (`P' = S P S` over 36).
#[test]
fn widening_scales_the_cross_covariance() {
    let mut rng = ChaCha8Rng::seed_from_u64(40);
    let prior = bordered_filter(&mut rng, FilterMode::ClosedLoop);
    let mut filter = prior;
    filter
        .widen_block_uncertainty(crate::state::GYRO_BIAS, 4.0)
        .unwrap();
    let mut s = Full::identity();
    for k in 9..12 {
        s[(k, k)] = 2.0;
    }
    let expected = s * full_covariance(&prior) * s;
    let error = relative(
        &full_covariance(&filter),
        &expected,
        &full_covariance(&prior),
    );
    assert!(error < 1e-15, "{error:e}");
}

#[test]
fn the_model_is_validated_and_combines_with_the_gnss_border() {
    assert_eq!(ImuErrorModel::DISABLED.validate(), Ok(()));
    assert_eq!(MODEL.validate(), Ok(()));
    for bad in [
        ImuErrorModel {
            gyro_misalignment_sigma_rad: 0.0,
            ..MODEL
        },
        ImuErrorModel {
            accel_misalignment_sigma_rad: -1e-5,
            ..MODEL
        },
        ImuErrorModel {
            gyro_g_sensitivity_sigma_rad_s_per_mps2: f64::NAN,
            ..MODEL
        },
        ImuErrorModel {
            accel_misalignment_sigma_rad: f64::INFINITY,
            ..MODEL
        },
    ] {
        assert_eq!(bad.validate(), Err(NavError::InvalidConfiguration));
        assert!(ImuErrorStates::new(bad).is_err());
    }
    let config = FilterConfig {
        mode: FilterMode::ClosedLoop,
        discretisation_order: 3,
        initial: crate::filter::InitialUncertainty {
            attitude_rad: 1e-3,
            position_m: 10.0,
            velocity_mps: 0.1,
            gyro_bias_rad_s: 1e-6,
            accel_bias_mps2: 1e-4,
            star_installation_rad: 1e-4,
            gyro_scale_factor: 1e-4,
            accel_scale_factor: 1e-4,
        },
        gnss_error: crate::gnss_error::GnssErrorModel::WHITE,
        imu_error: MODEL,
    };
    assert!(ErrorStateFilter::new(&config).is_ok());
    let both = FilterConfig {
        gnss_error: RECEIVER,
        ..config
    };
    assert!(ErrorStateFilter::new(&both).is_ok());
}

/// The written-out equivalent-bias rows of the propagation equal the ones the
/// equivalent-bias maps (`imu_error::equivalent_bias_terms`) give, for random `C` and
/// motion: the layout and the maps cannot drift apart.
#[test]
fn explicit_projection_equals_the_maps() {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    for _ in 0..20 {
        let point = random_point(&mut rng);
        let noise = random_noise(&mut rng, false);
        let model = StructuredModel::new(&point, &noise, 0.01, 3).unwrap();
        let cross: CrossCovariance = core::array::from_fn(|_| {
            core::array::from_fn(|_| core::array::from_fn(|_| rng.random_range(-1.0..1.0)))
        });
        let maps = propagate::group_maps(&model);
        let motion = (model.measured_rate(), model.measured_force());
        for j in 0..STATE_DIMENSION {
            let explicit = propagate::equivalent_row(&cross, motion, j);
            let mut generic = [0.0; 6];
            for (group, map) in cross.iter().zip(&maps) {
                for (k, value) in group[j].iter().enumerate() {
                    generic[3 * map.sensor + map.axes[k]] += map.multipliers[k] * value;
                }
            }
            for (a, b) in explicit.iter().zip(&generic) {
                assert!((a - b).abs() <= 1e-15 * (1.0 + b.abs()), "row {j}");
            }
        }
    }
}

/// Both borders: 24 + 3 correlated GNSS error states + 12 systematic IMU error states.
const M: usize = BORDERED;
type Both = Bordered;

const RECEIVER: crate::gnss_error::GnssErrorModel = crate::gnss_error::GnssErrorModel {
    sigma_m: 8.0,
    correlation_time_s: 300.0,
};

/// A filter with both borders and a random positive-definite 39-state covariance
/// (`structured::tests::install_both_borders`) and random estimates.
fn filter_with_both_borders(rng: &mut ChaCha8Rng, mode: FilterMode) -> ErrorStateFilter {
    let mut filter = filter_with(mode, &random_covariance(rng));
    install_both_borders(&mut filter, rng, RECEIVER, MODEL);
    filter
}

fn relative_both(a: &Both, b: &Both, scale: &Both) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..M {
        for j in 0..M {
            let s = (scale[(i, i)] * scale[(j, j)]).sqrt();
            worst = worst.max((a[(i, j)] - b[(i, j)]).abs() / s);
        }
    }
    worst
}

/// With both borders the structured propagation equals the dense 39-state
/// `F P Fᵀ + Qd` (`F = [[F, 0, Γ], [0, φI, 0], [0, 0, I]]`, the GNSS states' noise
/// `σ²(1 − φ²) I`), and the structured update the dense 39-state Joseph update with
/// `H = [H, h I, 0]`, for star, GNSS and referred GNSS measurements, with frozen blocks.
#[test]
fn with_both_borders_propagation_and_update_equal_the_dense_39_state_filter() {
    let mut rng = ChaCha8Rng::seed_from_u64(43);
    let mut worst = 0.0f64;
    for case in 0..80 {
        let mode = if case % 3 == 0 {
            FilterMode::OpenLoop
        } else {
            FilterMode::ClosedLoop
        };
        let prior = filter_with_both_borders(&mut rng, mode);
        let scale = whole_covariance(&prior);
        // Propagation.
        let point = random_point(&mut rng);
        let noise = random_noise(&mut rng, case % 2 == 0);
        let interval_s = rng.random_range(0.002..0.5);
        let model = StructuredModel::new(&point, &noise, interval_s, 3).unwrap();
        let dense_24 = discretise(
            &system_matrix(&point),
            &noise_input_matrix(&point),
            &noise.spectral_density_diagonal(),
            interval_s,
            3,
        )
        .unwrap();
        let f36 = dense_transition(&point, interval_s, 3);
        let phi = RECEIVER.decay(interval_s);
        let mut f = Both::zeros();
        f.fixed_view_mut::<24, 24>(0, 0)
            .copy_from(&f36.fixed_view::<24, 24>(0, 0));
        f.fixed_view_mut::<24, 12>(0, 27)
            .copy_from(&f36.fixed_view::<24, 12>(0, 24));
        for k in 24..27 {
            f[(k, k)] = phi;
        }
        for k in 27..M {
            f[(k, k)] = 1.0;
        }
        let mut q = Both::zeros();
        q.fixed_view_mut::<24, 24>(0, 0)
            .copy_from(&dense_24.process_noise);
        for k in 24..27 {
            q[(k, k)] = RECEIVER.sigma_m.powi(2) * (1.0 - phi * phi);
        }
        let expected = f * scale * f.transpose() + q;
        let mut propagated = prior;
        propagated.predict_structured(&model).unwrap();
        let error = relative_both(&whole_covariance(&propagated), &expected, &scale);
        assert!(error < 1e-12, "case {case}: propagation {error:e}");
        if mode == FilterMode::OpenLoop {
            let x = f * whole_state(&prior);
            let got = whole_state(&propagated);
            for i in 0..M {
                assert!(
                    (got[i] - x[i]).abs() < 1e-12 * scale[(i, i)].sqrt(),
                    "case {case}: x {i}"
                );
            }
        }
        worst = worst.max(error);
        // Update.
        let star = case % 3 == 1;
        let mut measurement = random_measurement(&mut rng, star, case % 2 == 1);
        if !star {
            measurement.border_coefficient =
                RECEIVER.position_coefficient(rng.random_range(0.0..0.1));
        }
        let frozen = if case % 4 == 0 {
            random_mask(&mut rng)
        } else {
            BlockMask::NONE
        };
        let mut h = SMatrix::<f64, 3, M>::zeros();
        h.fixed_view_mut::<3, 24>(0, 0)
            .copy_from(&measurement.jacobian);
        for k in 0..3 {
            h[(k, 24 + k)] = measurement.border_coefficient;
        }
        let x = whole_state(&prior);
        let innovation = measurement.residual - h * x;
        let s = h * scale * h.transpose() + measurement.noise_covariance;
        let mut gain: SMatrix<f64, M, 3> =
            Cholesky::new(s).unwrap().solve(&(h * scale)).transpose();
        for (i, mut row) in gain.row_iter_mut().enumerate() {
            if i < 24 && frozen.contains_state(i) {
                row.fill(0.0);
            }
        }
        let i_kh = Both::identity() - gain * h;
        let p = i_kh * scale * i_kh.transpose()
            + gain * measurement.noise_covariance * gain.transpose();
        let p = (p + p.transpose()) * 0.5;
        let x = x + gain * innovation;
        let mut updated = prior;
        updated
            .update_structured(&measurement, f64::INFINITY, &frozen)
            .unwrap();
        let error = relative_both(&whole_covariance(&updated), &p, &scale);
        assert!(error < 1e-11, "case {case}: update {error:e}");
        let got = whole_state(&updated);
        for i in 0..M {
            assert!(
                (got[i] - x[i]).abs() < 1e-11 * scale[(i, i)].sqrt(),
                "case {case}: x {i}"
            );
        }
        worst = worst.max(error);
    }
    println!("structured vs dense 39-state filter: worst {worst:.2e}");
}

/// The prior in the filter's gauge is the triads' specification pushed through the
/// nonlinear gauge map: `J diag(σ_g², σ_a²) Jᵀ`, `J` the finite-difference Jacobian of
/// `to_filter_gauge` with respect to the twelve off-diagonal truth terms at zero.
#[test]
fn the_prior_is_the_specification_through_the_gauge_map() {
    use crate::imu_error::{to_filter_gauge, ImuTruth};
    let model = ImuErrorModel {
        gyro_misalignment_sigma_rad: 2e-5,
        accel_misalignment_sigma_rad: 3e-5,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7,
    };
    let zero = ImuTruth {
        gyro_misalignment_rad: Matrix3::zeros(),
        accel_misalignment_rad: Matrix3::zeros(),
        gyro_g_sensitivity_rad_s_per_mps2: Vector3::zeros(),
        gyro_bias_rad_s: Vector3::zeros(),
        accel_bias_mps2: Vector3::zeros(),
        gyro_scale_factor: Vector3::zeros(),
        accel_scale_factor: Vector3::zeros(),
        star_mounting: nalgebra::Quaternion::identity(),
        star_installation: nalgebra::Quaternion::identity(),
    };
    let states = |truth: &ImuTruth| {
        let imu = to_filter_gauge(truth).unwrap().imu;
        SVector::<f64, IMU_ERROR_DIMENSION>::from_iterator(
            imu.gyro_non_orthogonality_rad
                .iter()
                .chain(imu.accel_misalignment_rad.iter())
                .chain(imu.gyro_g_sensitivity_rad_s_per_mps2.iter())
                .copied(),
        )
    };
    let off_diagonal: Vec<(usize, usize)> = (0..3)
        .flat_map(|i| (0..3).map(move |j| (i, j)))
        .filter(|(i, j)| i != j)
        .collect();
    let step = 1e-7;
    let mut jacobian = SMatrix::<f64, IMU_ERROR_DIMENSION, 12>::zeros();
    let mut spec = SMatrix::<f64, 12, 12>::zeros();
    for (column, &(i, j)) in off_diagonal.iter().chain(&off_diagonal).enumerate() {
        let mut truth = zero;
        let (matrix, sigma) = if column < 6 {
            (
                &mut truth.gyro_misalignment_rad,
                model.gyro_misalignment_sigma_rad,
            )
        } else {
            (
                &mut truth.accel_misalignment_rad,
                model.accel_misalignment_sigma_rad,
            )
        };
        matrix[(i, j)] = step;
        jacobian.set_column(column, &(states(&truth) / step));
        spec[(column, column)] = sigma * sigma;
    }
    let expected = jacobian * spec * jacobian.transpose();
    let prior = model.prior_covariance();
    let misalignment = 9;
    let error = (prior.fixed_view::<9, 9>(0, 0) - expected.fixed_view::<9, 9>(0, 0)).amax();
    assert!(error < 1e-6 * 9e-10, "{error:e}\n{prior}\n{expected}");
    // Off-diagonal terms exist (a diagonal prior would fail the comparison above).
    let correlated = expected.iter().filter(|v| v.abs() > 1e-12).count();
    assert!(correlated > misalignment, "{correlated}");
    for k in misalignment..IMU_ERROR_DIMENSION {
        assert!((prior[(k, k)] - 6.25e-14).abs() < 1e-28);
        assert_eq!(prior.row(k).iter().filter(|v| **v != 0.0).count(), 1);
    }
    assert!(prior.cholesky().is_some());
    let sigmas = model.state_sigmas();
    for (k, sigma) in sigmas.iter().enumerate() {
        assert!((sigma * sigma - prior[(k, k)]).abs() < 1e-24);
    }
}
