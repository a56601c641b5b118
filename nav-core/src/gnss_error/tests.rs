//! Tests of the correlated GNSS error states: the structured border against the dense
//! 27-state filter, its propagation, relaxation, reset and validation.

use super::*;
use crate::discretise::{discretise, CovarianceMatrix};
use crate::error_model::{noise_input_matrix, system_matrix};
use crate::filter::{ErrorStateFilter, FilterMode};
use crate::state::BlockMask;
use crate::structured::tests::{
    filter_with, random_covariance, random_mask, random_measurement, random_noise, random_point,
    random_vector,
};
use crate::structured::StructuredModel;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const RECEIVER: GnssErrorModel = GnssErrorModel {
    sigma_m: 8.0,
    correlation_time_s: 300.0,
};

/// A filter with the border in use, a random 27-state covariance (positive definite,
/// every state at a physical scale, ε correlated with everything) and a random state.
fn bordered_filter(rng: &mut ChaCha8Rng, mode: FilterMode) -> ErrorStateFilter {
    let p = random_covariance(rng);
    let mut filter = filter_with(mode, &p);
    *filter.gnss_error_mut() = GnssErrorStates::new(RECEIVER).unwrap();
    // C = P_xx^{1/2}-like correlations: C = P_xx W with small W keeps P positive definite
    // when P_εε dominates W' P_xx W (checked by the Cholesky below).
    let w = SMatrix::<f64, STATE_DIMENSION, 3>::from_fn(|j, _| {
        rng.random_range(-1.0..1.0) * 0.3 / crate::float::sqrt(p[(j, j)]) * RECEIVER.sigma_m
            / crate::float::sqrt(STATE_DIMENSION as f64)
    });
    let cross = p * w;
    let border = w.transpose() * p * w + Matrix3::identity() * RECEIVER.sigma_m.powi(2);
    let estimate = random_vector(rng, 5.0);
    filter.gnss_error_mut().set(&estimate, &border, &cross);
    filter
}

fn bits_equal(a: &GnssErrorStates, b: &GnssErrorStates) -> bool {
    let all = |s: &GnssErrorStates| {
        let mut v: std::vec::Vec<u64> = s.estimate.iter().map(|x| x.to_bits()).collect();
        v.extend(s.covariance.iter().flatten().map(|x| x.to_bits()));
        v.extend(s.rows().iter().flatten().map(|x| x.to_bits()));
        v
    };
    all(a) == all(b)
}

/// Largest difference of the border relative to the prior's scales
/// (`√(P_ii P_jj)` per element, `√P_εε` for `ε̂`).
fn border_difference(a: &GnssErrorStates, b: &GnssErrorStates, prior: &ErrorStateFilter) -> f64 {
    let sigma_x = |j: usize| crate::float::sqrt(prior.covariance()[(j, j)]);
    let sigma_e = |a: usize| crate::float::sqrt(prior.gnss_error().covariance()[(a, a)]);
    let mut worst = 0.0f64;
    for a_index in 0..3 {
        worst = worst.max((a.estimate[a_index] - b.estimate[a_index]).abs() / sigma_e(a_index));
        for b_index in 0..3 {
            let d = (a.covariance[a_index][b_index] - b.covariance[a_index][b_index]).abs();
            worst = worst.max(d / (sigma_e(a_index) * sigma_e(b_index)));
        }
        for j in 0..STATE_DIMENSION {
            let d = (a.rows()[j][a_index] - b.rows()[j][a_index]).abs();
            worst = worst.max(d / (sigma_x(j) * sigma_e(a_index)));
        }
    }
    worst
}

/// The structured bordered update (the flight path) equals the dense 27-state Joseph
/// update, for star, GNSS and referred GNSS measurements, with and without frozen blocks.
#[test]
fn structured_border_update_equals_the_dense_27_state_update() {
    let mut rng = ChaCha8Rng::seed_from_u64(16);
    let mut worst = 0.0f64;
    for case in 0..300 {
        let star = case % 3 == 0;
        let referred = case % 2 == 1;
        let prior = bordered_filter(&mut rng, FilterMode::OpenLoop);
        let mut measurement = random_measurement(&mut rng, star, referred);
        if !star && referred {
            measurement.border_coefficient =
                RECEIVER.position_coefficient(rng.random_range(0.0..0.1));
        }
        let frozen = if case % 4 == 0 {
            random_mask(&mut rng)
        } else {
            BlockMask::NONE
        };
        let (mut dense, mut structured) = (prior, prior);
        let dense_report = dense
            .update_with_frozen_blocks(&measurement, f64::INFINITY, &frozen)
            .unwrap();
        let structured_report = structured
            .update_structured(&measurement, f64::INFINITY, &frozen)
            .unwrap();
        let nis = dense_report.normalised_innovation_squared;
        assert!(
            (structured_report.normalised_innovation_squared - nis).abs() <= 1e-11 * nis,
            "case {case}: NIS"
        );
        let p_error = crate::structured::tests::relative_to(
            structured.covariance(),
            dense.covariance(),
            prior.covariance(),
        );
        let border_error = border_difference(structured.gnss_error(), dense.gnss_error(), &prior);
        let state_error = (0..STATE_DIMENSION)
            .map(|j| {
                (structured.state()[j] - dense.state()[j]).abs()
                    / crate::float::sqrt(prior.covariance()[(j, j)])
            })
            .fold(0.0f64, f64::max);
        worst = worst.max(p_error).max(border_error).max(state_error);
        assert!(p_error <= 1e-11, "case {case}: P_xx {p_error:e}");
        assert!(
            border_error <= 1e-11,
            "case {case}: border {border_error:e}"
        );
        assert!(state_error <= 1e-11, "case {case}: x {state_error:e}");
        crate::structured::tests::assert_frozen_blocks_unmoved(&structured, &prior, &frozen);
        // A star update moves ε̂ only through its correlation with the attitude.
        if star {
            assert!(structured.gnss_error().estimate_m() != prior.gnss_error().estimate_m());
        }
    }
    println!("structured vs dense 27-state update: worst {worst:.2e} prior σ");
}

/// `C ← φ F C`, `P_εε ← φ² P_εε + σ²(1 − φ²) I`, `ε̂ ← φ ε̂`, with the structured model
/// (flight path) and the dense `F` (reference): equal within round-off, and equal to
/// the formulas.
#[test]
fn border_propagation_equals_the_dense_transition() {
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    for case in 0..50 {
        let prior = bordered_filter(&mut rng, FilterMode::ClosedLoop);
        let point = random_point(&mut rng);
        let noise = random_noise(&mut rng, case % 2 == 0);
        let interval_s = rng.random_range(0.002..0.5);
        let model = StructuredModel::new(&point, &noise, interval_s, 3).unwrap();
        let dense_model = discretise(
            &system_matrix(&point),
            &noise_input_matrix(&point),
            &noise.spectral_density_diagonal(),
            interval_s,
            3,
        )
        .unwrap();
        let (mut structured, mut dense) = (prior, prior);
        structured.predict_structured(&model).unwrap();
        dense.predict(&dense_model).unwrap();
        assert!(
            border_difference(structured.gnss_error(), dense.gnss_error(), &prior) < 1e-12,
            "case {case}"
        );
        let phi = libm::exp(-interval_s / RECEIVER.correlation_time_s);
        let expected_cross = dense_model.transition * prior.gnss_error().cross_covariance() * phi;
        let cross = structured.gnss_error().cross_covariance();
        for j in 0..STATE_DIMENSION {
            for a in 0..3 {
                let scale = crate::float::sqrt(prior.covariance()[(j, j)]) * RECEIVER.sigma_m;
                assert!((cross[(j, a)] - expected_cross[(j, a)]).abs() < 1e-12 * scale);
            }
        }
        let expected_border = prior.gnss_error().covariance() * (phi * phi)
            + Matrix3::identity() * (RECEIVER.sigma_m.powi(2) * (1.0 - phi * phi));
        assert!((structured.gnss_error().covariance() - expected_border).amax() < 1e-12);
        let expected_estimate = prior.gnss_error().estimate_m() * phi;
        assert!((structured.gnss_error().estimate_m() - expected_estimate).amax() < 1e-12);
    }
}

/// Without measurements the border tends to the stationary prior: after 10 τ the
/// cross-covariance and estimate have decayed by e⁻¹⁰ and `P_εε` is σ² I.
#[test]
fn the_border_relaxes_to_the_stationary_prior() {
    let mut rng = ChaCha8Rng::seed_from_u64(18);
    let mut filter = bordered_filter(&mut rng, FilterMode::ClosedLoop);
    let prior = filter;
    let point = random_point(&mut rng);
    let noise = random_noise(&mut rng, false);
    let model = StructuredModel::new(&point, &noise, 30.0, 1).unwrap();
    // The border's decay does not depend on F's size for ε̂ and P_εε.
    for _ in 0..100 {
        assert!(filter
            .gnss_error_mut()
            .propagate(model.interval_s(), |c| *c));
    }
    let sigma2 = RECEIVER.sigma_m.powi(2);
    assert!(
        (filter.gnss_error().covariance() - Matrix3::identity() * sigma2).amax() < 1e-9 * sigma2
    );
    let decay = libm::exp(-10.0);
    assert!(
        (filter.gnss_error().estimate_m() - prior.gnss_error().estimate_m() * decay).amax() < 1e-12
    );
}

/// The reset maps `C`'s attitude and installation rows through `J`, keeps the rest and
/// `ε̂`; structured and dense resets agree.
#[test]
fn reset_maps_the_cross_covariance() {
    let mut rng = ChaCha8Rng::seed_from_u64(19);
    let mut prior = bordered_filter(&mut rng, FilterMode::ClosedLoop);
    let measurement = random_measurement(&mut rng, true, false);
    prior.update(&measurement, f64::INFINITY).unwrap();
    let (mut structured, mut dense) = (prior, prior);
    structured.reset();
    dense.reset_dense();
    assert!(border_difference(structured.gnss_error(), dense.gnss_error(), &prior) < 1e-14);
    assert!(bits_equal(
        &{
            let mut e = *structured.gnss_error();
            e.estimate = prior.gnss_error().estimate;
            e
        },
        structured.gnss_error()
    ));
    let (before, after) = (
        prior.gnss_error().cross_covariance(),
        structured.gnss_error().cross_covariance(),
    );
    for j in 3..15 {
        assert_eq!(before.row(j), after.row(j), "row {j} is not reset");
    }
    assert!((before.fixed_rows::<3>(0) - after.fixed_rows::<3>(0)).amax() > 0.0);
}

#[test]
fn the_model_is_validated() {
    assert_eq!(GnssErrorModel::WHITE.validate(), Ok(()));
    assert_eq!(RECEIVER.validate(), Ok(()));
    for (sigma_m, correlation_time_s) in [
        (-1.0, 300.0),
        (f64::NAN, 300.0),
        (f64::INFINITY, 300.0),
        (8.0, 0.0),
        (8.0, -5.0),
        (8.0, f64::INFINITY),
        (8.0, f64::NAN),
    ] {
        let model = GnssErrorModel {
            sigma_m,
            correlation_time_s,
        };
        assert_eq!(model.validate(), Err(NavError::InvalidConfiguration));
        assert!(GnssErrorStates::new(model).is_err());
    }
    // A white model ignores its correlation time.
    let white = GnssErrorModel {
        sigma_m: 0.0,
        correlation_time_s: -1.0,
    };
    assert_eq!(white.validate(), Ok(()));
    assert_eq!(RECEIVER.decay(300.0).to_bits(), libm::exp(-1.0).to_bits());
    assert_eq!(
        GnssErrorModel::WHITE.decay(300.0).to_bits(),
        1.0f64.to_bits()
    );
    assert_eq!(
        RECEIVER.position_coefficient(30.0).to_bits(),
        libm::exp(0.1).to_bits()
    );
    let _ = CovarianceMatrix::zeros();
}
