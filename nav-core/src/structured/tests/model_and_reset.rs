//! The structured kernels' edge cases, rebuild and reset against the dense reference.

use super::*;

/// The Joseph update's roll-back: when its products overflow (finite gains and `P Hᵀ`
/// whose products exceed the f64 range), it reports `false` and `P` is bit-identical to
/// before, both triangles and the diagonal.
#[test]
fn an_overflowing_joseph_update_leaves_p_unchanged() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut p = random_covariance(&mut rng);
    let before = p;
    let observed = ObservedCovariance {
        products: &[[1e200, 0.0, 0.0]; STATE_DIMENSION],
        projected: IDENTITY,
    };
    let gains: StateRows = [[1e200, 0.0, 0.0]; STATE_DIMENSION];
    assert!(!joseph_update(
        &mut p,
        &gains,
        &observed,
        &Matrix3::identity()
    ));
    assert_eq!(p.map(f64::to_bits), before.map(f64::to_bits));
}

/// The Joseph update's finite check sums the new values: when finite values are large
/// enough for the sum to overflow, the exact check accepts them (no false roll-back). Zero
/// gains and `P Hᵀ` leave `P` as it was, bit for bit, even at `1e308` per element.
#[test]
fn a_joseph_update_of_large_finite_values_is_accepted() {
    let mut p = CovarianceMatrix::from_element(1e308);
    let before = p;
    let observed = ObservedCovariance {
        products: &[[0.0; 3]; STATE_DIMENSION],
        projected: IDENTITY,
    };
    let gains: StateRows = [[0.0; 3]; STATE_DIMENSION];
    assert!(joseph_update(
        &mut p,
        &gains,
        &observed,
        &Matrix3::identity()
    ));
    assert_eq!(p.map(f64::to_bits), before.map(f64::to_bits));
}

/// With a strong gravity gradient and a long step (so the 4th-order terms are large) the
/// structured transition still equals the dense series: every power's coefficient and
/// factor of `Δ` shows.
#[test]
fn fourth_order_terms_match_the_dense_series_under_a_strong_gradient() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut point = random_point(&mut rng);
    point.gravity_gradient_per_s2 = Matrix3::new(3.0, 0.5, 0.2, 0.5, -1.0, 0.1, 0.2, 0.1, 2.0);
    let noise = random_noise(&mut rng, true);
    let interval_s = 0.5;
    let dense = dense_model(&point, &noise, interval_s, 4, &BlockMask::NONE);
    let model = StructuredModel::new(&point, &noise, interval_s, 4).unwrap();
    let difference = relative_difference(&model.transition_matrix(), &dense.transition);
    assert!(difference < 1e-12, "{difference:e}");
}

/// From a zero covariance one propagation gives exactly `Qd`: the structured model adds the
/// same process noise as the dense one, relative to `Qd` itself (the equality tests on a
/// full `P` cannot see an error of the size of `Qd`), with and without bias walks, with
/// dynamic and calibration blocks' noise removed, and after a rebuild that drops the walks.
#[test]
fn the_process_noise_added_equals_the_dense_qd() {
    use crate::state::{StateBlock, ACCEL_SCALE_FACTOR, ATTITUDE, GYRO_BIAS, VELOCITY};
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mask = |blocks: &[StateBlock]| {
        let mut mask = BlockMask::NONE;
        for block in blocks {
            mask.insert(*block);
        }
        mask
    };
    let masks = [
        BlockMask::NONE,
        mask(&[ATTITUDE]),
        mask(&[VELOCITY, GYRO_BIAS]),
        mask(&[ACCEL_SCALE_FACTOR]),
    ];
    for case in 0..32 {
        let point = random_point(&mut rng);
        let with_walk = case % 2 == 0;
        let mut noise = random_noise(&mut rng, with_walk);
        // Every combination of the two walks (both, gyro only, accelerometer only) and of
        // the two white noises (one of them absent).
        match case % 8 {
            2 => noise.accel_bias_walk_mps3_per_sqrt_hz = 0.0,
            4 => noise.gyro_bias_walk_rad_s2_per_sqrt_hz = 0.0,
            5 => noise.gyro_noise_density_rad_s_per_sqrt_hz = 0.0,
            7 => noise.accel_noise_density_mps2_per_sqrt_hz = 0.0,
            _ => {}
        }
        let frozen = masks[(case / 8) % 4];
        let dense_model = dense_model(&point, &noise, 0.01, 3, &frozen);
        // Built with the other walk setting first, then rebuilt in place.
        let mut model =
            StructuredModel::new(&point, &random_noise(&mut rng, !with_walk), 0.01, 3).unwrap();
        model.rebuild(&point, &noise, 0.01, 3).unwrap();
        model.remove_process_noise(&frozen);
        let mut structured = filter_with(FilterMode::ClosedLoop, &CovarianceMatrix::zeros());
        structured.predict_structured(&model).unwrap();
        let q = &dense_model.process_noise;
        let difference = (structured.covariance() - q).norm() / q.norm();
        assert!(difference < 1e-12, "case {case}: {difference:e}");
    }
}

/// A non-positive or non-finite interval is refused, and the model is left as it was.
#[test]
fn a_rebuild_refuses_a_bad_interval() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let point = random_point(&mut rng);
    let noise = random_noise(&mut rng, true);
    let mut model = StructuredModel::new(&point, &noise, 0.002, 3).unwrap();
    let before = model.transition_matrix();
    for interval_s in [-0.002, 0.0, f64::NAN, f64::INFINITY] {
        assert_eq!(
            model.rebuild(&point, &noise, interval_s, 3),
            Err(NavError::InvalidTimeStep)
        );
    }
    assert_eq!(
        model.transition_matrix().map(f64::to_bits),
        before.map(f64::to_bits)
    );
}

/// Rebuilding a model in place with fewer noise sources leaves no trace of the earlier
/// ones: the same `Qd` as a model built afresh (accelerometer walk only; no walk).
#[test]
fn a_rebuilt_model_forgets_the_previous_walks() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let point = random_point(&mut rng);
    let both = random_noise(&mut rng, true);
    let accel_only = ProcessNoise {
        gyro_bias_walk_rad_s2_per_sqrt_hz: 0.0,
        ..both
    };
    let gyro_only = ProcessNoise {
        accel_bias_walk_mps3_per_sqrt_hz: 0.0,
        ..both
    };
    let none = random_noise(&mut rng, false);
    for noise in [accel_only, gyro_only, none] {
        let mut model = StructuredModel::new(&point, &both, 0.002, 3).unwrap();
        model.rebuild(&point, &noise, 0.002, 3).unwrap();
        let fresh = StructuredModel::new(&point, &noise, 0.002, 3).unwrap();
        assert_eq!(
            model.process_noise_matrix().map(f64::to_bits),
            fresh.process_noise_matrix().map(f64::to_bits)
        );
    }
}

/// The table of `1/n!`: each entry times `n!` is 1 (the high orders' terms are too small
/// for the model-equality tests to see a wrong coefficient).
#[test]
fn inverse_factorials_are_the_reciprocals_of_the_factorials() {
    let mut factorial = 1.0_f64;
    for (n, inverse) in INVERSE_FACTORIALS.iter().enumerate() {
        if n > 0 {
            factorial *= n as f64;
        }
        assert!((inverse * factorial - 1.0).abs() < 1e-15, "1/{n}!");
    }
}

#[test]
fn structured_reset_equals_the_dense_reset() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for case in 0..100 {
        let mut filter = filter_with(FilterMode::ClosedLoop, &random_covariance(&mut rng));
        filter
            .update(
                &random_measurement(&mut rng, case % 2 == 0, false),
                f64::INFINITY,
            )
            .unwrap();
        let mut dense = filter;
        let error = filter.reset();
        assert_eq!(error, dense.reset_dense());
        assert_eq!(filter.state(), dense.state());
        let p = filter.covariance();
        assert_eq!(p, &p.transpose());
        let difference = relative_difference(p, dense.covariance());
        assert!(difference <= 1e-12, "case {case}: {difference:e}");
    }
}
