//! [`ErrorStateFilter::restart_keeping_calibration`] against its definition written densely:
//! the navigation rows and columns of the 24×24 `P` and of `x` are the prior's, the
//! calibration block and the calibration part of `x` are kept bit for bit, the optional blocks
//! are back at their prior, and `P` stays positive definite.

use nalgebra::{Cholesky, SMatrix};

use crate::discretise::CovarianceMatrix;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::{ErrorStateFilter, FilterConfig, FilterMode, InitialUncertainty};
use crate::gnss_error::GnssErrorModel;
use crate::imu_error_states::ImuErrorModel;
use crate::state::{DYNAMIC_DIMENSION, STATE_DIMENSION};
use crate::structured::tests::{
    filter_with, install_both_borders, random_covariance, random_state,
};

const RECEIVER: GnssErrorModel = GnssErrorModel {
    sigma_m: 8.0,
    correlation_time_s: 300.0,
};

const IMU: ImuErrorModel = ImuErrorModel {
    gyro_misalignment_sigma_rad: 2e-5,
    accel_misalignment_sigma_rad: 2e-5,
    gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7,
};

/// A configuration whose prior differs from `filter_with`'s (unit σ everywhere), so a kept
/// entry cannot pass for a restarted one; its navigation prior is wider than any random
/// covariance's navigation block.
fn config(mode: FilterMode) -> FilterConfig {
    FilterConfig {
        mode,
        discretisation_order: 3,
        initial: InitialUncertainty {
            attitude_rad: 1e3,
            position_m: 1e3,
            velocity_mps: 1e3,
            gyro_bias_rad_s: 1e-5,
            accel_bias_mps2: 1e-3,
            star_installation_rad: 1e-3,
            gyro_scale_factor: 1e-4,
            accel_scale_factor: 1e-4,
        },
        gnss_error: RECEIVER,
        imu_error: IMU,
    }
}

/// `P_cc + P_cn (P⁰_nn − P_nn)⁻¹ P_nc`, written densely (nav-core
/// `calibration_covariance_for_restart`).
fn bound(p: &CovarianceMatrix, prior: &CovarianceMatrix) -> SMatrix<f64, 15, 15> {
    let n = DYNAMIC_DIMENSION;
    let margin = prior.fixed_view::<9, 9>(0, 0) - p.fixed_view::<9, 9>(0, 0);
    let cross = p.fixed_view::<9, 15>(0, n).into_owned();
    let inverse = margin.try_inverse().unwrap();
    p.fixed_view::<15, 15>(n, n) + cross.transpose() * inverse * cross
}

#[test]
fn navigation_restarts_and_calibration_is_bounded_for_the_dropped_correlation() {
    for (seed, mode) in [(1, FilterMode::ClosedLoop), (2, FilterMode::OpenLoop)] {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut filter = filter_with(mode, &random_covariance(&mut rng));
        install_both_borders(&mut filter, &mut rng, RECEIVER, IMU);
        filter.state = random_state(&mut rng);
        let (before_p, before_x) = (*filter.covariance(), *filter.state());
        let config = config(mode);
        filter.restart_keeping_calibration(&config).unwrap();
        let prior = ErrorStateFilter::new(&config).unwrap();
        let expected_block = bound(&before_p, prior.covariance());
        let (p, x) = (filter.covariance(), filter.state());
        for i in 0..STATE_DIMENSION {
            let kept = i >= DYNAMIC_DIMENSION;
            let expected_x = if kept { before_x[i] } else { 0.0 };
            assert_eq!(x[i].to_bits(), expected_x.to_bits(), "x[{i}]");
            for j in 0..STATE_DIMENSION {
                if kept && j >= DYNAMIC_DIMENSION {
                    let expected = expected_block[(i - 9, j - 9)];
                    let scale = (p[(i, i)] * p[(j, j)]).sqrt();
                    assert!((p[(i, j)] - expected).abs() <= 1e-12 * scale, "P[{i},{j}]");
                    // Never below what was known: the bound only adds.
                    assert!(p[(i, i)] >= before_p[(i, i)], "P[{i},{i}]");
                } else {
                    let expected = prior.covariance()[(i, j)];
                    assert_eq!(p[(i, j)].to_bits(), expected.to_bits(), "P[{i},{j}]");
                }
            }
        }
        // The restarted filter claims no less than the errors' covariance: Q − P ⪰ 0.
        let difference = p - before_p;
        let smallest = difference.symmetric_eigenvalues().min();
        assert!(smallest > -1e-9 * p.norm(), "{smallest}");
        assert!(Cholesky::new(*p).is_some(), "P not positive definite");
        assert_eq!(filter.gnss_error(), prior.gnss_error());
        assert_eq!(filter.mode(), mode);
    }
}

/// A navigation block less certain than the prior it would restart to: the prior stands in
/// for the margin, `P_cc + P_cn (P⁰_nn)⁻¹ P_nc`.
#[test]
fn a_restart_to_a_narrower_navigation_prior_pays_for_the_correlation_at_the_prior_s_scale() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut filter = filter_with(FilterMode::ClosedLoop, &random_covariance(&mut rng));
    let before = *filter.covariance();
    let mut narrow = config(FilterMode::ClosedLoop);
    narrow.initial.attitude_rad = 1e-3;
    filter.restart_keeping_calibration(&narrow).unwrap();
    let prior = ErrorStateFilter::new(&narrow).unwrap();
    let n = DYNAMIC_DIMENSION;
    let cross = before.fixed_view::<9, 15>(0, n).into_owned();
    let inverse = prior
        .covariance()
        .fixed_view::<9, 9>(0, 0)
        .try_inverse()
        .unwrap();
    let expected = before.fixed_view::<15, 15>(n, n) + cross.transpose() * inverse * cross;
    for i in 0..15 {
        for j in 0..15 {
            let got = filter.covariance()[(n + i, n + j)];
            let scale = (expected[(i, i)] * expected[(j, j)]).sqrt();
            assert!(
                (got - expected[(i, j)]).abs() <= 1e-12 * scale,
                "P[{i},{j}]"
            );
        }
    }
}

#[test]
fn a_refused_configuration_changes_nothing() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut filter = filter_with(FilterMode::ClosedLoop, &random_covariance(&mut rng));
    filter.state = random_state(&mut rng);
    let before = filter;
    let mut config = config(FilterMode::ClosedLoop);
    config.initial.velocity_mps = -1.0;
    assert!(filter.restart_keeping_calibration(&config).is_err());
    assert_eq!(filter, before);
}

/// The calibration covariance read out and written back is the same block, bit for bit, its
/// correlation with navigation zeroed and the navigation block kept; a matrix that is not
/// positive definite or not finite is refused and changes nothing.
#[test]
fn the_calibration_covariance_round_trips_and_a_bad_one_is_refused() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut filter = filter_with(FilterMode::ClosedLoop, &random_covariance(&mut rng));
    let before = *filter.covariance();
    let lower = filter.calibration_covariance();
    filter.set_calibration_covariance(&lower).unwrap();
    let after = filter.covariance();
    for i in 0..STATE_DIMENSION {
        for j in 0..STATE_DIMENSION {
            let navigation = (i < DYNAMIC_DIMENSION) == (j < DYNAMIC_DIMENSION);
            let expected = if navigation { before[(i, j)] } else { 0.0 };
            assert_eq!(after[(i, j)].to_bits(), expected.to_bits(), "P[{i},{j}]");
        }
    }
    let unchanged = filter;
    let mut indefinite = lower;
    indefinite[0] = -1.0;
    assert_eq!(
        filter.set_calibration_covariance(&indefinite),
        Err(crate::NavError::InvalidConfiguration)
    );
    let mut not_finite = lower;
    not_finite[7] = f64::NAN;
    assert_eq!(
        filter.set_calibration_covariance(&not_finite),
        Err(crate::NavError::NonFiniteState)
    );
    assert_eq!(filter, unchanged);
}

/// `P` with the systematic IMU error states appended (36×36; the correlated GNSS error
/// states, restarted to their prior, left out).
fn with_imu_errors(filter: &ErrorStateFilter) -> SMatrix<f64, 36, 36> {
    let (p, states) = (filter.covariance(), filter.imu_error());
    let (cross, own) = (states.cross_covariance(), states.covariance());
    SMatrix::from_fn(|i, j| match (i < 24, j < 24) {
        (true, true) => p[(i, j)],
        (true, false) => cross[(i, j - 24)],
        (false, true) => cross[(j, i - 24)],
        (false, false) => own[(i - 24, j - 24)],
    })
}

/// The systematic IMU error states kept across the restart, as calibration: their estimate
/// bit for bit, their covariance and their covariance with the core calibration bounded
/// for the dropped correlation with navigation (dense: `Q − P ⪰ 0` over the 36 states),
/// their correlation with navigation zero; read back, the bound is what was set, bit for
/// bit.
#[test]
fn the_imu_error_states_are_kept_and_bounded_as_calibration() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let mut filter = filter_with(FilterMode::ClosedLoop, &random_covariance(&mut rng));
    install_both_borders(&mut filter, &mut rng, RECEIVER, IMU);
    let before = with_imu_errors(&filter);
    let estimate = filter.imu_error().estimate();
    let config = config(FilterMode::ClosedLoop);
    let bound = filter.imu_error_covariance_for_restart(&config).unwrap();
    filter.restart_keeping_calibration(&config).unwrap();
    assert_eq!(
        filter.imu_error().estimate().map(f64::to_bits),
        estimate.map(f64::to_bits)
    );
    let after = with_imu_errors(&filter);
    let smallest = (after - before).symmetric_eigenvalues().min();
    assert!(smallest > -1e-9 * after.norm(), "{smallest}");
    for a in 0..12 {
        assert!(
            after[(24 + a, 24 + a)] >= before[(24 + a, 24 + a)],
            "P_εε[{a}]"
        );
        assert!(after[(24 + a, 24 + a)] < IMU.state_sigmas()[a].powi(2) * 10.0);
        for n in 0..DYNAMIC_DIMENSION {
            assert_eq!(after[(n, 24 + a)].to_bits(), 0.0f64.to_bits(), "C[{n},{a}]");
        }
    }
    let read = filter.imu_error_covariance_for_restart(&config).unwrap();
    assert_eq!(read, bound);
    assert!(Cholesky::new(after).is_some(), "P not positive definite");
}

/// A covariance that makes the whole calibration block indefinite, or is not finite, or a
/// filter without the states: refused, nothing changed.
#[test]
fn a_bad_imu_error_covariance_is_refused_and_changes_nothing() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut filter = filter_with(FilterMode::ClosedLoop, &random_covariance(&mut rng));
    install_both_borders(&mut filter, &mut rng, RECEIVER, IMU);
    let config = config(FilterMode::ClosedLoop);
    let good = filter
        .imu_error_covariance_for_restart(&config)
        .unwrap()
        .unwrap();
    let unchanged = filter;
    let mut strong = good;
    // A covariance with the gyro bias far beyond what both variances allow.
    strong.with_calibration[0][0] = 1e3;
    assert_eq!(
        filter.set_imu_error_covariance(&strong),
        Err(crate::NavError::InvalidConfiguration)
    );
    let mut not_finite = good;
    not_finite.imu_error_lower[5] = f64::INFINITY;
    assert_eq!(
        filter.set_imu_error_covariance(&not_finite),
        Err(crate::NavError::NonFiniteState)
    );
    assert_eq!(filter, unchanged);
    let mut without = filter_with(FilterMode::ClosedLoop, &random_covariance(&mut rng));
    assert_eq!(without.imu_error_covariance_for_restart(&config), Ok(None));
    assert_eq!(
        without.set_imu_error_covariance(&good),
        Err(crate::NavError::InvalidConfiguration)
    );
}
