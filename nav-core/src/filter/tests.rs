//! Tests of the filter: closed forms, gates, errors, resets, and structured against dense.

use super::*;
use crate::discretise::DiscreteModel;
use crate::error_model::set_block;
use crate::measurement::MeasurementJacobian;

pub(super) fn config(mode: FilterMode) -> FilterConfig {
    FilterConfig {
        mode,
        discretisation_order: 3,
        initial: InitialUncertainty {
            attitude_rad: 1e-2,
            position_m: 100.0,
            velocity_mps: 1.0,
            gyro_bias_rad_s: 1e-3,
            accel_bias_mps2: 1e-2,
            star_installation_rad: 1e-2,
            gyro_scale_factor: 1e-4,
            accel_scale_factor: 1e-4,
        },
        gnss_error: crate::gnss_error::GnssErrorModel::WHITE,
        imu_error: crate::imu_error_states::ImuErrorModel::DISABLED,
    }
}

fn position_measurement(residual: Vector3<f64>, sigma: f64) -> LinearMeasurement {
    let mut jacobian = MeasurementJacobian::zeros();
    jacobian
        .fixed_view_mut::<3, 3>(0, POSITION.index())
        .fill_with_identity();
    LinearMeasurement {
        residual,
        jacobian,
        noise_covariance: Matrix3::identity() * sigma * sigma,
        border_coefficient: 1.0,
    }
}

#[test]
fn scalar_update_matches_the_closed_form_posterior() {
    let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
    let report = filter
        .update(
            &position_measurement(Vector3::new(30.0, -10.0, 5.0), 10.0),
            f64::INFINITY,
        )
        .unwrap();
    assert!(report.accepted);
    // prior σ² = 1e4, R = 1e2: posterior mean z·σ²/(σ²+R), variance σ²R/(σ²+R).
    let gain = 1e4 / (1e4 + 1e2);
    assert!((filter.state()[POSITION.index()] - 30.0 * gain).abs() < 1e-12);
    assert!(
        (filter.covariance()[(POSITION.index(), POSITION.index())] - 1e4 * 1e2 / (1e4 + 1e2)).abs()
            < 1e-9
    );
    let expected_nis = (30.0f64.powi(2) + 10.0f64.powi(2) + 5.0f64.powi(2)) / (1e4 + 1e2);
    assert!((report.normalised_innovation_squared - expected_nis).abs() < 1e-12);
    // Unobserved blocks keep their prior.
    assert_eq!(
        filter.covariance()[(VELOCITY.index(), VELOCITY.index())].to_bits(),
        1.0f64.to_bits()
    );
    assert_eq!(filter.covariance(), &filter.covariance().transpose());
    assert!(Cholesky::new(*filter.covariance()).is_some());
}

/// Every initial 1σ must be finite and strictly positive: zero, negative and non-finite
/// values are refused, each for every state block.
#[test]
fn initial_sigmas_must_be_finite_and_positive() {
    assert_eq!(config(FilterMode::ClosedLoop).validate(), Ok(()));
    let setters: [fn(&mut InitialUncertainty, f64); 8] = [
        |u, v| u.attitude_rad = v,
        |u, v| u.position_m = v,
        |u, v| u.velocity_mps = v,
        |u, v| u.gyro_bias_rad_s = v,
        |u, v| u.accel_bias_mps2 = v,
        |u, v| u.star_installation_rad = v,
        |u, v| u.gyro_scale_factor = v,
        |u, v| u.accel_scale_factor = v,
    ];
    for set in setters {
        for bad in [0.0, -1e-3, f64::INFINITY, f64::NAN] {
            let mut bad_config = config(FilterMode::ClosedLoop);
            set(&mut bad_config.initial, bad);
            assert_eq!(bad_config.validate(), Err(NavError::InvalidConfiguration));
        }
    }
}

#[test]
fn a_gated_measurement_leaves_the_filter_bit_identical() {
    let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
    let before = filter;
    let report = filter
        .update(
            &position_measurement(Vector3::new(5000.0, 0.0, 0.0), 10.0),
            11.34,
        )
        .unwrap();
    assert!(!report.accepted);
    assert!(report.normalised_innovation_squared > 11.34);
    assert_eq!(filter, before);
}

#[test]
fn bad_measurements_are_typed_errors_and_change_nothing() {
    let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
    let before = filter;
    let nan = position_measurement(Vector3::new(f64::NAN, 0.0, 0.0), 10.0);
    assert_eq!(
        filter.update(&nan, f64::INFINITY),
        Err(NavError::NonFiniteInput)
    );
    let mut negative = position_measurement(Vector3::zeros(), 10.0);
    negative.noise_covariance = Matrix3::identity() * -2e4;
    assert_eq!(
        filter.update(&negative, f64::INFINITY),
        Err(NavError::NonPositiveInnovationCovariance)
    );
    assert_eq!(filter, before);
    let mut bad = config(FilterMode::OpenLoop);
    bad.initial.gyro_bias_rad_s = f64::NAN;
    assert_eq!(
        ErrorStateFilter::new(&bad),
        Err(NavError::InvalidConfiguration)
    );
    bad = config(FilterMode::OpenLoop);
    bad.discretisation_order = 7;
    assert_eq!(
        ErrorStateFilter::new(&bad),
        Err(NavError::InvalidDiscretisationOrder)
    );
}

#[test]
fn closed_loop_reset_zeroes_the_state_and_applies_the_reset_jacobian() {
    let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
    let mut jacobian = MeasurementJacobian::zeros();
    jacobian
        .fixed_view_mut::<3, 3>(0, ATTITUDE.index())
        .fill_with_identity();
    let measurement = LinearMeasurement {
        residual: Vector3::new(2e-3, -1e-3, 3e-3),
        jacobian,
        noise_covariance: Matrix3::identity() * 1e-10,
        border_coefficient: 0.0,
    };
    filter.update(&measurement, f64::INFINITY).unwrap();
    let covariance_before = *filter.covariance();
    let error = filter.reset();
    assert_eq!(filter.state(), &ErrorState::zeros());
    let theta = error.fixed_rows::<3>(ATTITUDE.index()).into_owned();
    let g = Matrix3::identity() - skew(&theta);
    let expected = g * covariance_before.fixed_view::<3, 3>(0, 0) * g.transpose();
    assert!((filter.covariance().fixed_view::<3, 3>(0, 0) - expected).amax() < 1e-20);

    let mut attitude = Quaternion::new(1.0, 0.0, 0.0, 0.0);
    let mut position = Vector3::zeros();
    let mut velocity = Vector3::zeros();
    let mut calibration = CalibrationEstimate::default();
    apply_error_state(
        &error,
        &mut attitude,
        &mut position,
        &mut velocity,
        &mut calibration,
    )
    .unwrap();
    assert!(
        (attitude.imag() - theta).amax() < 1e-12,
        "{attitude:?} vs {theta:?}"
    );
}

#[test]
fn a_frozen_block_keeps_its_estimate_and_the_covariance_stays_exact() {
    // Correlate position with the accelerometer scale factor, then observe position with
    // that block frozen: the frozen estimate must not move, the unfrozen one must, and P
    // must equal the Joseph-form covariance (I − K H) P (I − K H)ᵀ + K R Kᵀ of the
    // zero-row gain, computed here independently.
    let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
    let mut covariance = *filter.covariance();
    let cross = 0.5 * crate::float::sqrt(1e4 * 1e-8);
    for axis in 0..3 {
        covariance[(POSITION.index() + axis, ACCEL_SCALE_FACTOR.index() + axis)] = cross;
        covariance[(ACCEL_SCALE_FACTOR.index() + axis, POSITION.index() + axis)] = cross;
    }
    filter.set_covariance(&covariance).unwrap();
    let prior = *filter.covariance();
    let measurement = position_measurement(Vector3::new(30.0, -10.0, 5.0), 10.0);
    let mut frozen = BlockMask::NONE;
    frozen.insert(ACCEL_SCALE_FACTOR);
    let mut free = filter;
    free.update(&measurement, f64::INFINITY).unwrap();
    assert!(free.block(ACCEL_SCALE_FACTOR).norm() > 1e-6);
    filter
        .update_with_frozen_blocks(&measurement, f64::INFINITY, &frozen)
        .unwrap();
    assert_eq!(filter.block(ACCEL_SCALE_FACTOR), Vector3::zeros());
    assert!((filter.block(POSITION) - free.block(POSITION)).norm() < 1e-12);
    let h = measurement.jacobian;
    let s = h * prior * h.transpose() + measurement.noise_covariance;
    let mut gain = prior * h.transpose() * s.try_inverse().unwrap();
    gain.fixed_rows_mut::<3>(ACCEL_SCALE_FACTOR.index())
        .fill(0.0);
    let i_kh = CovarianceMatrix::identity() - gain * h;
    let expected =
        i_kh * prior * i_kh.transpose() + gain * measurement.noise_covariance * gain.transpose();
    assert!((filter.covariance() - expected).amax() < 1e-9 * expected.amax());
    // Freezing costs information: the frozen block keeps its prior variance.
    let variance = filter.covariance()[(ACCEL_SCALE_FACTOR.index(), ACCEL_SCALE_FACTOR.index())];
    assert!((variance - 1e-8).abs() < 1e-20);
}

#[test]
fn a_nan_gate_is_an_error_not_an_open_gate() {
    let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
    let before = filter;
    assert_eq!(
        filter.update(&position_measurement(Vector3::zeros(), 10.0), f64::NAN),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(filter, before);
}

/// Vector part of `q̂* ⊗ q` (the body-frame error of `q̂` with respect to `q`).
fn body_error(estimate: &Quaternion<f64>, truth: &Quaternion<f64>) -> Vector3<f64> {
    attitude::canonical(&attitude::product(&attitude::conjugate(estimate), truth)).imag()
}

#[test]
fn reset_jacobian_matches_the_nonlinear_reset() {
    // The filter estimates ϑ̂; the true error is ϑ = ϑ̂ + e (e the estimation error, the
    // random variable P describes). After q̂⁺ = q̂ ⊗ δq(ϑ̂) the new error is
    // ϑ⁺ = vec(q̂⁺* ⊗ q) ≈ (I − [ϑ̂×]) e. Checked through apply_error_state for both the
    // attitude and the installation blocks: the mismatch is O(|ϑ̂|²|e| + |e|²), far below
    // the O(|ϑ̂||e|) error of a plain identity reset.
    let estimated = Vector3::new(2e-3, -1.5e-3, 3e-3);
    let attitude_estimate = attitude::exp_rotation_vector(&Vector3::new(0.3, -0.7, 1.1));
    let installation_estimate = attitude::exp_rotation_vector(&Vector3::new(1e-3, 2e-3, -1e-3));
    let g = Matrix3::identity() - skew(&estimated);
    for block in [ATTITUDE, STAR_INSTALLATION] {
        let mut state = ErrorState::zeros();
        state
            .fixed_rows_mut::<3>(block.index())
            .copy_from(&estimated);
        for e_scale in [1e-4, 0.5e-4] {
            let e = Vector3::new(0.7, 1.0, -0.4) * e_scale;
            let true_error = attitude::from_vector_part(&(estimated + e)).unwrap();
            let mut attitude_now = attitude_estimate;
            let mut calibration = CalibrationEstimate::default();
            let [w, x, y, z] = [
                installation_estimate.w,
                installation_estimate.i,
                installation_estimate.j,
                installation_estimate.k,
            ];
            calibration.star_installation_wxyz = [w, x, y, z];
            let base = if block == ATTITUDE {
                attitude_estimate
            } else {
                installation_estimate
            };
            let truth = attitude::product(&base, &true_error);
            apply_error_state(
                &state,
                &mut attitude_now,
                &mut Vector3::zeros(),
                &mut Vector3::zeros(),
                &mut calibration,
            )
            .unwrap();
            let corrected = if block == ATTITUDE {
                attitude_now
            } else {
                let [w, x, y, z] = calibration.star_installation_wxyz;
                Quaternion::new(w, x, y, z)
            };
            let new_error = body_error(&corrected, &truth);
            let with_jacobian = (new_error - g * e).amax();
            let with_identity = (new_error - e).amax();
            let bound = 3.0 * (estimated.norm_squared() * e.norm() + e.norm_squared());
            println!(
                "{} reset, |e| = {:.1e}: mismatch with I − [ϑ̂×] {with_jacobian:.3e}, with I {with_identity:.3e}",
                block.name(),
                e.norm()
            );
            assert!(
                with_jacobian < bound,
                "{}: {with_jacobian:e} vs {bound:e}",
                block.name()
            );
            assert!(with_jacobian < 0.01 * with_identity, "{}", block.name());
        }
    }
}

#[test]
fn joseph_form_keeps_p_symmetric_and_positive_definite_under_precise_measurements() {
    use crate::discretise::discretise;
    use crate::error_model::{noise_input_matrix, system_matrix, LinearisationPoint, ProcessNoise};
    use crate::measurement::{gnss_position, star_sensor};
    // Paper motion state II plus an acceleration, 2 ms steps, star and GNSS updates far
    // more precise than the prior (R/HPHᵀ down to 1e-14), the ill-conditioned regime
    // the Joseph form is chosen for.
    let q_ib = attitude::exp_rotation_vector(&Vector3::new(0.2, 0.4, -0.1));
    let point = LinearisationPoint {
        corrected_rate_rad_s: Vector3::new(0.0, 0.0, 10.0f64.to_radians()),
        corrected_specific_force_mps2: Vector3::new(0.0, 20.0, 0.0),
        measured_rate_rad_s: Vector3::new(0.0, 0.0, 10.0f64.to_radians()),
        measured_specific_force_mps2: Vector3::new(0.0, 20.0, 0.0),
        body_to_inertial: attitude::rotation_matrix(&q_ib),
        gravity_gradient_per_s2: Matrix3::zeros(),
    };
    let model = discretise(
        &system_matrix(&point),
        &noise_input_matrix(&point),
        &ProcessNoise::PAPER.spectral_density_diagonal(),
        0.002,
        3,
    )
    .unwrap();
    let mounting = attitude::exp_rotation_vector(&Vector3::new(0.4, -1.1, 0.25));
    let identity = Quaternion::new(1.0, 0.0, 0.0, 0.0);
    let star = star_sensor(&q_ib, &mounting, &identity, &q_ib, &[1e-9; 3]).unwrap();
    let gnss = gnss_position(
        &q_ib,
        &Vector3::zeros(),
        &Vector3::new(1.5, -0.4, 2.0),
        &Vector3::new(0.1, 0.0, 0.0),
        1e-4,
    )
    .unwrap();
    let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
    let mut smallest_pivot = f64::INFINITY;
    for step in 0..300 {
        filter.predict(&model).unwrap();
        if step % 10 == 0 {
            filter.update(&star, f64::INFINITY).unwrap();
            filter.update(&gnss, f64::INFINITY).unwrap();
            let p = filter.covariance();
            assert_eq!(p, &p.transpose(), "step {step}");
            let cholesky = Cholesky::new(*p).expect("P positive definite");
            let pivot = cholesky.l().diagonal().min();
            smallest_pivot = smallest_pivot.min(pivot);
            assert!(pivot > 0.0, "step {step}");
            // What GNSS observes (antenna position δp − 2Ĉ[ℓ×]ϑ; δp alone stays as
            // uncertain as attitude × lever arm, since the star sensor only sees ϑ
            // together with the installation error) collapses to its 1e-4 m precision.
            let h = &gnss.jacobian;
            let observed = (h * p * h.transpose()).diagonal().max();
            assert!(observed < 1.01e-8, "step {step}: {observed}");
        }
    }
    println!("smallest Cholesky pivot of P over 30 precise update pairs: {smallest_pivot:.3e}");
}

#[test]
fn open_loop_prediction_propagates_the_state() {
    let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
    filter
        .update(
            &position_measurement(Vector3::new(30.0, 0.0, 0.0), 10.0),
            f64::INFINITY,
        )
        .unwrap();
    let mut transition = CovarianceMatrix::identity() * 2.0;
    transition[(0, 0)] = 1.0;
    let model = DiscreteModel {
        transition,
        process_noise: CovarianceMatrix::zeros(),
        interval_s: 0.1,
    };
    let before = filter.state()[POSITION.index()];
    filter.predict(&model).unwrap();
    assert_eq!(
        filter.state()[POSITION.index()].to_bits(),
        (2.0 * before).to_bits()
    );
}

#[test]
fn protection_puts_a_variance_at_its_ceiling_and_keeps_correlations() {
    let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
    let mut covariance = CovarianceMatrix::identity();
    covariance[(0, 0)] = 4.0;
    covariance[(0, 1)] = 1.0;
    covariance[(1, 0)] = 1.0;
    filter.set_covariance(&covariance).unwrap();
    let correlation = |p: &CovarianceMatrix| p[(0, 1)] / (p[(0, 0)] * p[(1, 1)]).sqrt();
    let before = correlation(filter.covariance());
    let floor = ErrorState::repeat(0.5);
    let mut ceiling = ErrorState::repeat(10.0);
    ceiling[0] = 1.0;
    assert!(filter.protect_variances(&floor, &ceiling));
    let p = filter.covariance();
    assert_eq!(p[(0, 0)].to_bits(), 1.0_f64.to_bits());
    assert!((correlation(p) - before).abs() < 1e-15);
    assert_eq!(p[(0, 1)].to_bits(), p[(1, 0)].to_bits());
    assert!(p.cholesky().is_some());
    // Within the bounds: nothing changes.
    assert!(!filter.protect_variances(&floor, &ceiling));
}

/// Widening a block is `P' = S P S` with `S = √f` on the block: compared with the product
/// formed densely, on a full covariance; a factor below 1 or non-finite changes nothing.
#[test]
fn widening_a_block_is_the_congruence_with_the_block_scaled() {
    let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
    let mixing = CovarianceMatrix::from_fn(|row, column| {
        let (row, column) = (row as f64, column as f64);
        libm::sin(1.0 + 0.37 * row + 0.11 * column * column)
    });
    let covariance = mixing * mixing.transpose() + CovarianceMatrix::identity();
    filter.set_covariance(&covariance).unwrap();
    let factor = 6.25;
    filter.widen_block_uncertainty(GYRO_BIAS, factor).unwrap();
    let scaling = CovarianceMatrix::from_fn(|row, column| {
        let in_block = (GYRO_BIAS.index()..GYRO_BIAS.index() + 3).contains(&row);
        match (row == column, in_block) {
            (false, _) => 0.0,
            (true, true) => 2.5,
            (true, false) => 1.0,
        }
    });
    let expected = scaling * covariance * scaling;
    let p = filter.covariance();
    let worst = (p - expected).abs().max();
    assert!(worst <= 1e-15 * expected.abs().max(), "{worst}");
    let index = GYRO_BIAS.index();
    assert!((p[(index, index)] / covariance[(index, index)] - factor).abs() < 1e-14);
    let widened = *p;
    for refused in [0.99, f64::NAN, f64::INFINITY] {
        assert!(filter.widen_block_uncertainty(ATTITUDE, refused).is_err());
        assert_eq!(filter.covariance(), &widened);
    }
}

/// A variance below its floor is raised to it (only the diagonal changes); one exactly
/// at its floor or ceiling is inside the bounds and reported as unchanged.
#[test]
fn protection_raises_a_variance_to_its_floor_and_leaves_the_bounds_alone() {
    let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
    let mut covariance = CovarianceMatrix::identity();
    covariance[(3, 3)] = 0.25;
    covariance[(3, 4)] = 0.1;
    covariance[(4, 3)] = 0.1;
    filter.set_covariance(&covariance).unwrap();
    let floor = ErrorState::repeat(0.5);
    let ceiling = ErrorState::repeat(1.0);
    assert!(filter.protect_variances(&floor, &ceiling));
    let p = *filter.covariance();
    assert_eq!(p[(3, 3)].to_bits(), 0.5_f64.to_bits());
    assert_eq!(p[(3, 4)].to_bits(), 0.1_f64.to_bits());
    // Every variance now at a bound (0.5 or 1.0): inside, nothing to do.
    assert!(!filter.protect_variances(&floor, &ceiling));
    assert_eq!(filter.covariance().map(f64::to_bits), p.map(f64::to_bits));
}

/// 1σ is the square root of each variance.
#[test]
fn standard_deviations_are_the_roots_of_the_variances() {
    let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
    let covariance =
        CovarianceMatrix::from_diagonal(&ErrorState::from_fn(|i, _| ((i + 1) * (i + 1)) as f64));
    filter.set_covariance(&covariance).unwrap();
    let sigmas = filter.standard_deviations();
    for (index, sigma) in sigmas.iter().enumerate() {
        assert_eq!(sigma.to_bits(), ((index + 1) as f64).to_bits());
    }
}

/// A measurement whose NIS equals the gate exactly is accepted (the gate refuses only
/// what lies beyond it), by the dense and the structured update alike; a hair above it
/// is refused.
#[test]
fn the_gate_refuses_only_beyond_its_value() {
    let measurement = position_measurement(Vector3::new(30.0, -10.0, 5.0), 10.0);
    let none = BlockMask::NONE;
    let fresh = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
    type Update = fn(
        &mut ErrorStateFilter,
        &LinearMeasurement,
        f64,
        &BlockMask,
    ) -> Result<InnovationReport, NavError>;
    let updates: [Update; 2] = [
        ErrorStateFilter::update_with_frozen_blocks,
        ErrorStateFilter::update_structured,
    ];
    for update in updates {
        // This implementation's own NIS (its round-off), then the gate exactly there.
        let nis = update(&mut { fresh }, &measurement, f64::INFINITY, &none)
            .unwrap()
            .normalised_innovation_squared;
        for (gate, accepted) in [(nis, true), (nis * (1.0 - 1e-12), false)] {
            let report = update(&mut { fresh }, &measurement, gate, &none).unwrap();
            assert_eq!(report.accepted, accepted);
        }
    }
}

/// A dense prediction whose covariance overflows is refused and changes nothing, even
/// though the (zero, closed-loop) state stays finite.
#[test]
fn an_overflowing_dense_prediction_changes_nothing() {
    let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
    filter
        .set_covariance(&CovarianceMatrix::from_element(f64::MAX))
        .unwrap();
    let before = filter;
    let model = DiscreteModel {
        transition: CovarianceMatrix::identity() * 2.0,
        process_noise: CovarianceMatrix::zeros(),
        interval_s: 0.1,
    };
    assert_eq!(filter.predict(&model), Err(NavError::NonFiniteState));
    assert_eq!(
        filter.covariance().map(f64::to_bits),
        before.covariance().map(f64::to_bits)
    );
}

/// The structured prediction in open loop propagates the state as the dense one does.
#[test]
fn open_loop_structured_prediction_propagates_the_state() {
    use crate::error_model::{LinearisationPoint, ProcessNoise};
    let mut structured = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
    structured
        .update(
            &position_measurement(Vector3::new(30.0, -10.0, 5.0), 10.0),
            f64::INFINITY,
        )
        .unwrap();
    let mut dense = structured;
    let point = LinearisationPoint {
        corrected_rate_rad_s: Vector3::new(0.01, -0.02, 0.03),
        corrected_specific_force_mps2: Vector3::new(1.0, 0.5, -9.0),
        measured_rate_rad_s: Vector3::new(0.01, -0.02, 0.03),
        measured_specific_force_mps2: Vector3::new(1.0, 0.5, -9.0),
        body_to_inertial: Matrix3::identity(),
        gravity_gradient_per_s2: Matrix3::identity() * -1.5e-6,
    };
    let model = StructuredModel::new(&point, &ProcessNoise::PAPER, 0.002, 3).unwrap();
    structured.predict_structured(&model).unwrap();
    let dense_model = crate::discretise::discretise(
        &crate::error_model::system_matrix(&point),
        &crate::error_model::noise_input_matrix(&point),
        &ProcessNoise::PAPER.spectral_density_diagonal(),
        0.002,
        3,
    )
    .unwrap();
    dense.predict(&dense_model).unwrap();
    let difference = (structured.state() - dense.state()).norm();
    assert!(difference <= 1e-12 * dense.state().norm(), "{difference:e}");
    assert!(structured.state()[VELOCITY.index()].abs() > 0.0);
}

/// A finite innovation whose NIS overflows is an error, not a report with an infinite
/// NIS (dense path).
#[test]
fn an_overflowing_nis_is_an_error() {
    let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
    let measurement = position_measurement(Vector3::new(1e200, 0.0, 0.0), 10.0);
    assert_eq!(
        filter.innovation(&measurement).map(|r| r.accepted),
        Err(NavError::NonPositiveInnovationCovariance)
    );
    assert_eq!(
        filter.update(&measurement, 16.0).map(|r| r.accepted),
        Err(NavError::NonPositiveInnovationCovariance)
    );
}

/// `apply_error_state` changes nothing when it fails (the scheduler's feedback applies it
/// to its navigation solution and calibration in place): a non-finite error, an attitude
/// correction with |ϑ| ≥ 1, and an installation correction with |ψ| ≥ 1 after a valid
/// attitude correction.
#[test]
fn a_failed_feedback_changes_nothing() {
    let mut valid = ErrorState::zeros();
    for (index, value) in valid.iter_mut().enumerate() {
        *value = 1e-3 * (index as f64 + 1.0);
    }
    let cases = [
        (ATTITUDE.index(), f64::NAN),
        (ATTITUDE.index(), 1.5),
        (STAR_INSTALLATION.index(), 1.5),
    ];
    for (index, value) in cases {
        let mut error = valid;
        error[index] = value;
        let attitude_before = Quaternion::new(0.5, 0.5, -0.5, 0.5);
        let position_before = Vector3::new(1.0e5, 2.0e5, 3.0e5);
        let velocity_before = Vector3::new(7.5e3, 10.0, -20.0);
        let calibration_before = CalibrationEstimate {
            gyro_bias_rad_s: [1e-5, 2e-5, 3e-5],
            ..CalibrationEstimate::default()
        };
        let (mut attitude, mut position, mut velocity, mut calibration) = (
            attitude_before,
            position_before,
            velocity_before,
            calibration_before,
        );
        assert!(apply_error_state(
            &error,
            &mut attitude,
            &mut position,
            &mut velocity,
            &mut calibration
        )
        .is_err());
        assert_eq!(attitude, attitude_before, "case {index} {value}");
        assert_eq!(position, position_before);
        assert_eq!(velocity, velocity_before);
        assert_eq!(calibration, calibration_before);
    }
}

/// The paper's white GNSS errors and a correlated-error model with its border states.
const WITH_AND_WITHOUT_GNSS_ERROR_STATES: [crate::gnss_error::GnssErrorModel; 2] = [
    crate::gnss_error::GnssErrorModel::WHITE,
    crate::gnss_error::GnssErrorModel {
        sigma_m: 8.0,
        correlation_time_s: 300.0,
    },
];

/// `reset_in_place` is `reset` without the returned error state: the same filter, bit for
/// bit, with and without the correlated GNSS error states.
#[test]
fn reset_in_place_equals_reset() {
    for gnss_error in WITH_AND_WITHOUT_GNSS_ERROR_STATES {
        let mut filter = ErrorStateFilter::new(&FilterConfig {
            gnss_error,
            ..config(FilterMode::ClosedLoop)
        })
        .unwrap();
        let mut jacobian = MeasurementJacobian::zeros();
        set_block(&mut jacobian, 0, ATTITUDE, &Matrix3::identity());
        set_block(&mut jacobian, 0, STAR_INSTALLATION, &Matrix3::identity());
        let measurement = LinearMeasurement {
            residual: Vector3::new(2e-3, -1e-3, 3e-3),
            jacobian,
            noise_covariance: Matrix3::identity() * 1e-8,
            border_coefficient: 0.0,
        };
        filter.update(&measurement, f64::INFINITY).unwrap();
        let (mut returned, mut in_place) = (filter, filter);
        let error = returned.reset();
        in_place.reset_in_place();
        assert_eq!(&error, filter.state());
        assert_eq!(returned, in_place);
        assert_eq!(in_place.state(), &ErrorState::zeros());
    }
}

/// `init_in_place` builds the filter `new` builds, bit for bit, with and without the
/// correlated GNSS error states, and refuses what `new` refuses; `initial_variances` is the
/// filter's diagonal.
#[test]
fn init_in_place_equals_new_and_refuses_what_new_refuses() {
    for gnss_error in WITH_AND_WITHOUT_GNSS_ERROR_STATES {
        let config = FilterConfig {
            gnss_error,
            ..config(FilterMode::ClosedLoop)
        };
        let built = ErrorStateFilter::new(&config).unwrap();
        let mut slot = core::mem::MaybeUninit::uninit();
        let in_place = *ErrorStateFilter::init_in_place(&mut slot, &config).unwrap();
        assert_eq!(in_place, built);
        let diagonal = built.covariance().diagonal();
        let variances = config.initial_variances().unwrap();
        assert_eq!(variances.map(f64::to_bits), diagonal.map(f64::to_bits));
        let mut refused = config;
        refused.initial.velocity_mps = f64::NAN;
        let mut unused = core::mem::MaybeUninit::uninit();
        assert_eq!(
            ErrorStateFilter::init_in_place(&mut unused, &refused).err(),
            Some(NavError::InvalidConfiguration)
        );
        assert_eq!(
            refused.initial_variances(),
            Err(NavError::InvalidConfiguration)
        );
    }
}
