//! [`ErrorStateFilter::restart_keeping_calibration`] against its definition written densely:
//! the navigation rows and columns of the 24×24 `P` and of `x` are the prior's, the
//! calibration block and the calibration part of `x` are kept bit for bit, the optional blocks
//! are back at their prior, and `P` stays positive definite.

use nalgebra::Cholesky;
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
/// entry cannot pass for a restarted one.
fn config(mode: FilterMode) -> FilterConfig {
    FilterConfig {
        mode,
        discretisation_order: 3,
        initial: InitialUncertainty {
            attitude_rad: 1e-3,
            position_m: 10.0,
            velocity_mps: 0.1,
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

#[test]
fn navigation_restarts_and_calibration_is_kept_bit_for_bit() {
    for (seed, mode) in [(1, FilterMode::ClosedLoop), (2, FilterMode::OpenLoop)] {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut filter = filter_with(mode, &random_covariance(&mut rng));
        install_both_borders(&mut filter, &mut rng, RECEIVER, IMU);
        filter.state = random_state(&mut rng);
        let (before_p, before_x) = (*filter.covariance(), *filter.state());
        let config = config(mode);
        filter.restart_keeping_calibration(&config).unwrap();
        let prior = ErrorStateFilter::new(&config).unwrap();
        let (p, x) = (filter.covariance(), filter.state());
        for i in 0..STATE_DIMENSION {
            let kept = i >= DYNAMIC_DIMENSION;
            let expected_x = if kept { before_x[i] } else { 0.0 };
            assert_eq!(x[i].to_bits(), expected_x.to_bits(), "x[{i}]");
            for j in 0..STATE_DIMENSION {
                let expected = if kept && j >= DYNAMIC_DIMENSION {
                    before_p[(i, j)]
                } else {
                    prior.covariance()[(i, j)]
                };
                assert_eq!(p[(i, j)].to_bits(), expected.to_bits(), "P[{i},{j}]");
            }
        }
        assert!(Cholesky::new(*p).is_some(), "P not positive definite");
        // The optional blocks: the prior's, with no cross-covariance to the core.
        assert_eq!(filter.gnss_error(), prior.gnss_error());
        assert_eq!(filter.imu_error(), prior.imu_error());
        assert_eq!(filter.mode(), mode);
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
