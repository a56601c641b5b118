//! The star-head relations against their exact quaternion expressions (finite differences,
//! second-order mismatch ratios, Monte Carlo), the filter's hand-over against the dense
//! `T P Tᵀ + Q` with and without the border states, and the estimator's consistency.

use super::*;
use crate::attitude::from_vector_part;
use crate::filter::{ErrorStateFilter, FilterMode};
use crate::gnss_error::GnssErrorModel;
use crate::imu_error_states::ImuErrorModel;
use crate::state::{BlockMask, STAR_INSTALLATION};
use crate::structured::tests::{
    filter_with, install_both_borders, random_covariance, random_measurement, random_quaternion,
    random_vector, whole_covariance, whole_state, Bordered, BORDERED,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const ARCSEC: f64 = core::f64::consts::PI / 180.0 / 3600.0;
/// The trackers of the brief: 5″ across the boresight, 35″ about it (1σ).
const TRACKER_NOISE_RAD: [f64; 3] = [5.0 * ARCSEC, 5.0 * ARCSEC, 35.0 * ARCSEC];

fn standard_normal(rng: &mut ChaCha8Rng) -> f64 {
    // Box-Muller; 1 − u keeps the logarithm's argument in (0, 1].
    let u: f64 = 1.0 - rng.random::<f64>();
    let v: f64 = rng.random::<f64>();
    (-2.0 * u.ln()).sqrt() * (2.0 * core::f64::consts::PI * v).cos()
}

fn normal_rotation(rng: &mut ChaCha8Rng, sigmas: &[f64; 3]) -> Vector3<f64> {
    Vector3::from_fn(|axis, _| sigmas[axis] * standard_normal(rng))
}

/// The residual the estimator computes for a pair (a gate below zero rejects it, so nothing
/// changes).
fn residual_of(
    alignment: &RelativeAlignment,
    measured_a: &Quaternion<f64>,
    measured_b: &Quaternion<f64>,
) -> PairReport {
    let mut probe = *alignment;
    let report = probe
        .update(
            measured_a,
            measured_b,
            &TRACKER_NOISE_RAD,
            &TRACKER_NOISE_RAD,
            -1.0,
        )
        .unwrap();
    assert!(!report.accepted);
    assert_eq!(probe, *alignment);
    report
}

/// A pair's geometry: the sky attitude of head A's true frame and the true `q_ab`.
struct Pair {
    sensor_a: Quaternion<f64>,
    alignment_true: Quaternion<f64>,
}

impl Pair {
    /// The measurements with noise rotations `n_A`, `n_B` (sensor axes).
    fn measure(&self, noise_a: &Vector3<f64>, noise_b: &Vector3<f64>) -> [Quaternion<f64>; 2] {
        let a = self.sensor_a * exp_rotation_vector(noise_a);
        // Sign flipped: the residual must not care.
        let b = -(self.sensor_a * self.alignment_true * exp_rotation_vector(noise_b));
        [a, b]
    }
}

/// Central-difference Jacobian of `f` at zero, step `step`.
fn jacobian(step: f64, f: impl Fn(&Vector3<f64>) -> Vector3<f64>) -> Matrix3<f64> {
    let mut j = Matrix3::zeros();
    for axis in 0..3 {
        let e = Vector3::ith(axis, step);
        j.set_column(axis, &((f(&e) - f(&-e)) / (2.0 * step)));
    }
    j
}

/// `z = δ + n_B − Ĉ_abᵀ n_A`: the three Jacobians of the exact residual by central
/// differences; the untransposed `−Ĉ_ab` would miss by a rotation's worth.
#[test]
fn pair_residual_jacobians_match_finite_differences() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for _ in 0..20 {
        let estimate = random_quaternion(&mut rng, 3.1);
        let alignment =
            RelativeAlignment::from_estimate(&estimate, &(Matrix3::identity() * 1e-8)).unwrap();
        let sensor_a = random_quaternion(&mut rng, 3.1);
        let zero = Vector3::zeros();
        let residual = |error: &Vector3<f64>, noise_a: &Vector3<f64>, noise_b: &Vector3<f64>| {
            let pair = Pair {
                sensor_a,
                alignment_true: estimate * exp_rotation_vector(error),
            };
            let [a, b] = pair.measure(noise_a, noise_b);
            residual_of(&alignment, &a, &b).residual_rad
        };
        let step = 1e-6;
        let by_error = jacobian(step, |v| residual(v, &zero, &zero));
        let by_noise_a = jacobian(step, |v| residual(&zero, v, &zero));
        let by_noise_b = jacobian(step, |v| residual(&zero, &zero, v));
        let c_ab = rotation_matrix(&estimate);
        assert!((by_error - Matrix3::identity()).amax() < 1e-8, "{by_error}");
        assert!(
            (by_noise_b - Matrix3::identity()).amax() < 1e-8,
            "{by_noise_b}"
        );
        assert!(
            (by_noise_a + c_ab.transpose()).amax() < 1e-8,
            "{by_noise_a}"
        );
        assert!((by_noise_a + c_ab).amax() > 0.1 || (c_ab - c_ab.transpose()).amax() < 0.1);
    }
}

/// `R_pair = diag(σ_B²) + Ĉ_abᵀ diag(σ_A²) Ĉ_ab` against the sample covariance of the exact
/// residual at `δ = 0` over 40,000 noise draws (relative standard error of a variance
/// `√(2/N)` = 0.7 %), at random relative alignments; `Ĉ_ab diag(σ_A²) Ĉ_abᵀ` would fail.
#[test]
fn pair_noise_covariance_matches_monte_carlo() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let draws = 40_000;
    for _ in 0..3 {
        let estimate = random_quaternion(&mut rng, 3.1);
        let alignment =
            RelativeAlignment::from_estimate(&estimate, &(Matrix3::identity() * 1e-30)).unwrap();
        let pair = Pair {
            sensor_a: random_quaternion(&mut rng, 3.1),
            alignment_true: estimate,
        };
        let mut sum = Matrix3::zeros();
        for _ in 0..draws {
            let noise_a = normal_rotation(&mut rng, &TRACKER_NOISE_RAD);
            let noise_b = normal_rotation(&mut rng, &TRACKER_NOISE_RAD);
            let [a, b] = pair.measure(&noise_a, &noise_b);
            let z = residual_of(&alignment, &a, &b).residual_rad;
            sum += z * z.transpose();
        }
        let sample = sum / draws as f64;
        let c_ab = rotation_matrix(&estimate);
        let expected = pair_noise_covariance(&c_ab, &TRACKER_NOISE_RAD, &TRACKER_NOISE_RAD);
        let variance = Matrix3::from_diagonal(&Vector3::from(TRACKER_NOISE_RAD.map(|s| s * s)));
        let wrong = variance + c_ab * variance * c_ab.transpose();
        let relative = |m: &Matrix3<f64>| {
            Matrix3::from_fn(|i, j| {
                (sample[(i, j)] - m[(i, j)]).abs() / (m[(i, i)] * m[(j, j)]).sqrt()
            })
            .amax()
        };
        println!(
            "R_pair vs sample: {:.4}, transposed form: {:.4}",
            relative(&expected),
            relative(&wrong)
        );
        assert!(relative(&expected) < 0.03);
        assert!(relative(&wrong) > 0.2);
        // The report's S is P + R_pair.
        let [a, b] = pair.measure(&Vector3::zeros(), &Vector3::zeros());
        let report = residual_of(&alignment, &a, &b);
        assert!((report.covariance_rad2 - expected).amax() < 1e-14 * expected.amax());
    }
}

/// `δ⁺ = log(exp(−δ̂) ⊗ exp(δ))` has the Jacobian `I − ½[δ̂×]` at `δ = δ̂` (to `O(|δ̂|²)`);
/// the other sign misses by `|δ̂|`.
#[test]
fn reset_jacobian_matches_finite_difference() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for _ in 0..20 {
        let correction = random_vector(&mut rng, 1e-3) + Vector3::new(2e-4, 0.0, 0.0);
        let fd = jacobian(1e-7, |v| {
            log_rotation_vector(
                &(exp_rotation_vector(&-correction) * exp_rotation_vector(&(correction + v))),
            )
        });
        let reset = reset_jacobian(&correction);
        let flipped = Matrix3::identity() + skew(&correction) * 0.5;
        assert!(
            (fd - reset).amax() < 0.05 * correction.norm(),
            "{fd} {reset}"
        );
        assert!((fd - flipped).amax() > 0.5 * correction.amax());
    }
}

/// Mismatch ratio of a linear prediction at two scales: second order gives ≈ 4; a map that
/// is exact leaves round-off only.
fn assert_second_order(mismatch: [f64; 2], linear_size: f64) {
    let ratio = mismatch[0] / mismatch[1];
    let at_round_off = mismatch[0] <= 1e-12 * linear_size;
    assert!(
        at_round_off || (3.5..4.5).contains(&ratio),
        "{mismatch:?} ratio {ratio}"
    );
    assert!(
        mismatch[0] < 0.01 * linear_size,
        "{mismatch:?} vs {linear_size}"
    );
}

/// The reversed estimate's error is `−Ĉ_ab δ` (exactly: `q̂_ab ⊗ exp(−δ) ⊗ q̂_ab*` is
/// `exp(−Ĉ_ab δ)`), its covariance `Ĉ P Ĉᵀ`; `+Ĉ_ab δ` or `−Ĉ_abᵀ δ` would miss.
#[test]
fn reversal_matches_the_inverse_rotation() {
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    for _ in 0..20 {
        let estimate = random_quaternion(&mut rng, 3.1);
        let prior = random_spd(&mut rng, 1e-6);
        let alignment = RelativeAlignment::from_estimate(&estimate, &prior).unwrap();
        let reversed = alignment.reversed();
        let direction = random_vector(&mut rng, 1.0).normalize();
        let c_ab = rotation_matrix(&estimate);
        let mut mismatch = [0.0; 2];
        for (slot, scale) in [1e-2, 5e-3].into_iter().enumerate() {
            let error = direction * scale;
            let truth_ba = conjugate(&(estimate * exp_rotation_vector(&error)));
            let exact = log_rotation_vector(&(conjugate(reversed.estimate()) * truth_ba));
            mismatch[slot] = (exact - (-c_ab * error)).amax();
            assert!((exact - c_ab * error).amax() > 0.5 * scale);
            let transposed = -c_ab.transpose() * error;
            assert!(
                (exact - transposed).amax() > 0.01 * scale
                    || (c_ab - c_ab.transpose()).amax() < 0.01
            );
        }
        assert_second_order(mismatch, 5e-3);
        let expected = c_ab * prior * c_ab.transpose();
        assert!((reversed.covariance() - expected).amax() < 1e-20);
        assert_eq!(reversed.pairs_accepted(), alignment.pairs_accepted());
    }
}

/// `q_ψ_B = q_bs_B* ⊗ q_bs_A ⊗ q_ψ_A ⊗ q_ab` with the true `q_ab` from its definition, at
/// large random rotations.
#[test]
fn hand_over_quaternion_matches_the_exact_composition() {
    let mut rng = ChaCha8Rng::seed_from_u64(19);
    for _ in 0..50 {
        let [mounting_a, mounting_b] = [0; 2].map(|_| random_quaternion(&mut rng, 3.1));
        let [installation_a, installation_b] = [0; 2].map(|_| random_quaternion(&mut rng, 0.5));
        let alignment = conjugate(&(mounting_a * installation_a)) * (mounting_b * installation_b);
        let new =
            new_head_installation(&mounting_a, &mounting_b, &installation_a, &alignment).unwrap();
        let difference = canonical(&(conjugate(&installation_b) * new));
        assert!(difference.imag().amax() < 1e-15, "{difference}");
        assert!(new.w >= 0.0);
        // Head B's sensor attitude is the same through either head's chain.
        let through_b = mounting_b * new;
        let through_a = mounting_a * installation_a * alignment;
        assert!(
            canonical(&(conjugate(&through_a) * through_b))
                .imag()
                .amax()
                < 1e-15
        );
    }
    let nan = Quaternion::new(f64::NAN, 0.0, 0.0, 0.0);
    let one = Quaternion::identity();
    assert_eq!(
        new_head_installation(&one, &one, &nan, &one),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(
        new_head_installation(&one, &Quaternion::new(0.0, 0.0, 0.0, 0.0), &one, &one),
        Err(NavError::DegenerateQuaternion)
    );
}

/// `ψ_B = Ĉ_abᵀ ψ_A + δ/2` against the exact new error `vec(q̂_ψ_B* ⊗ q_ψ_B)` with
/// `q_ψ_A = q̂_ψ_A ⊗ δq(ψ_A)`, `q_ab = q̂_ab ⊗ exp(δ)`: mismatch second order; `Ĉ_ab ψ_A`
/// (untransposed) or `δ` without the half would miss at first order.
#[test]
fn hand_over_error_is_rotated_plus_half_delta_to_second_order() {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    for _ in 0..20 {
        let [mounting_a, mounting_b] = [0; 2].map(|_| random_quaternion(&mut rng, 3.1));
        let installation_a = random_quaternion(&mut rng, 0.05);
        let estimate = random_quaternion(&mut rng, 3.1);
        let alignment =
            RelativeAlignment::from_estimate(&estimate, &(Matrix3::identity() * 1e-8)).unwrap();
        let hand_over = alignment
            .hand_over(&mounting_a, &mounting_b, &installation_a)
            .unwrap();
        let [psi_direction, delta_direction] =
            [0; 2].map(|_| random_vector(&mut rng, 1.0).normalize());
        let t = hand_over.rotation_new_from_old;
        let predict = |scale: f64| {
            let (psi_a, delta) = (psi_direction * scale, delta_direction * scale);
            let true_a = installation_a * from_vector_part(&psi_a).unwrap();
            let true_ab = estimate * exp_rotation_vector(&delta);
            let true_b = conjugate(&mounting_b) * mounting_a * true_a * true_ab;
            let exact = canonical(&(conjugate(&hand_over.installation_estimate) * true_b)).imag();
            (exact, psi_a, delta)
        };
        let mut mismatch = [0.0; 2];
        for (slot, scale) in [2e-3, 1e-3].into_iter().enumerate() {
            let (exact, psi_a, delta) = predict(scale);
            mismatch[slot] = (exact - (t * psi_a + delta * 0.5)).amax();
        }
        assert_second_order(mismatch, 1e-3);
        let (exact, psi_a, delta) = predict(1e-3);
        let untransposed = t.transpose() * psi_a + delta * 0.5;
        let whole_delta = t * psi_a + delta;
        assert!((exact - whole_delta).amax() > 0.1e-3);
        assert!((exact - untransposed).amax() > 0.1e-3 || (t - t.transpose()).amax() < 0.1);
        assert!(
            (hand_over.added_covariance_half_angle * 4.0 - alignment.covariance()).amax() < 1e-24
        );
    }
}

/// A random symmetric positive-definite 3×3 with entries of order `scale`.
fn random_spd(rng: &mut ChaCha8Rng, scale: f64) -> Matrix3<f64> {
    let b = Matrix3::from_fn(|_, _| rng.random_range(-1.0..1.0));
    let p = (b * b.transpose() + Matrix3::identity() * 0.1) * scale;
    (p + p.transpose()) * 0.5
}

const RECEIVER: GnssErrorModel = GnssErrorModel {
    sigma_m: 8.0,
    correlation_time_s: 300.0,
};
const IMU_MODEL: ImuErrorModel = ImuErrorModel {
    gyro_misalignment_sigma_rad: 2e-5,
    accel_misalignment_sigma_rad: 2e-5,
    gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7,
};

/// An open-loop filter with a random `P`, a non-zero `x` (from one update) and, if asked,
/// the border states with a random positive-definite 39-state covariance and estimates.
fn random_filter(rng: &mut ChaCha8Rng, borders: bool) -> ErrorStateFilter {
    let p24 = random_covariance(rng);
    let mut filter = filter_with(FilterMode::OpenLoop, &p24);
    let earlier = random_measurement(rng, true, false);
    filter
        .update_structured(&earlier, f64::INFINITY, &BlockMask::NONE)
        .unwrap();
    if !borders {
        return filter;
    }
    install_both_borders(&mut filter, rng, RECEIVER, IMU_MODEL);
    filter
}

/// The hand-over equals the dense `T_full P T_fullᵀ + E Q Eᵀ` and `x ← T_full x`
/// (`T_full` the identity but `T` on the installation block, `E` the installation block's
/// columns), over the 24 states and over 39 with both border states; `P` stays exactly
/// symmetric.
#[test]
fn hand_over_equals_the_dense_transform() {
    let mut rng = ChaCha8Rng::seed_from_u64(29);
    let mut worst = 0.0f64;
    for trial in 0..40 {
        let borders = trial % 2 == 1;
        let mut filter = random_filter(&mut rng, borders);
        let (p, x) = (whole_covariance(&filter), whole_state(&filter));
        let t = rotation_matrix(&random_quaternion(&mut rng, 3.1)).transpose();
        let q = random_spd(&mut rng, 1e-9);
        filter.hand_over_installation(&t, &q).unwrap();
        let i = STAR_INSTALLATION.index();
        let mut t_full = Bordered::identity();
        t_full.fixed_view_mut::<3, 3>(i, i).copy_from(&t);
        let mut expected = t_full * p * t_full.transpose();
        let mut block = expected.fixed_view_mut::<3, 3>(i, i);
        block += q;
        let got = whole_covariance(&filter);
        for r in 0..BORDERED {
            for c in 0..BORDERED {
                let scale = (expected[(r, r)] * expected[(c, c)]).sqrt().max(1e-300);
                worst = worst.max((got[(r, c)] - expected[(r, c)]).abs() / scale);
            }
        }
        assert_eq!(filter.covariance(), &filter.covariance().transpose());
        let expected_x = t_full * x;
        assert!((whole_state(&filter) - expected_x).amax() <= 1e-15 * x.amax());
        assert_eq!(filter.gnss_error().is_enabled(), borders);
        assert_eq!(filter.imu_error().is_enabled(), borders);
    }
    println!("hand-over vs dense: worst relative {worst:.2e}");
    assert!(worst < 1e-14, "{worst}");
}

/// Every refused input leaves the filter exactly as it was.
#[test]
fn a_refused_hand_over_changes_nothing() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let mut filter = random_filter(&mut rng, true);
    let before = filter;
    let t = rotation_matrix(&random_quaternion(&mut rng, 3.1));
    let q = random_spd(&mut rng, 1e-9);
    let mut nan_t = t;
    nan_t[(1, 2)] = f64::NAN;
    let mut nan_q = q;
    nan_q[(0, 1)] = f64::INFINITY;
    let mut negative_q = q;
    negative_q[(2, 2)] = -1e-12;
    let cases = [
        (nan_t, q, NavError::NonFiniteInput),
        (t * 1.001, q, NavError::InvalidConfiguration),
        (-t, q, NavError::InvalidConfiguration),
        (t, nan_q, NavError::NonFiniteInput),
        (t, negative_q, NavError::NonFiniteInput),
    ];
    for (t, q, error) in cases {
        assert_eq!(filter.hand_over_installation(&t, &q), Err(error));
        assert_eq!(filter, before);
    }
    // A rotation within round-off is accepted.
    filter.hand_over_installation(&t, &q).unwrap();
    assert_ne!(filter, before);
}

/// The estimator refuses bad inputs and a gated pair without changing.
#[test]
fn a_refused_or_gated_pair_changes_nothing() {
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    let mut alignment = RelativeAlignment::from_estimate(
        &random_quaternion(&mut rng, 3.1),
        &(Matrix3::identity() * 1e-8),
    )
    .unwrap();
    let before = alignment;
    let a = random_quaternion(&mut rng, 3.1);
    let b = a * *alignment.estimate() * exp_rotation_vector(&Vector3::new(1e-3, 0.0, 0.0));
    let noise = TRACKER_NOISE_RAD;
    let nan = Quaternion::new(f64::NAN, 0.0, 0.0, 0.0);
    let zero = Quaternion::new(0.0, 0.0, 0.0, 0.0);
    let negative = [5.0 * ARCSEC, -1e-9, 0.0];
    assert_eq!(
        alignment.update(&nan, &b, &noise, &noise, 16.0),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(
        alignment.update(&a, &zero, &noise, &noise, 16.0),
        Err(NavError::DegenerateQuaternion)
    );
    assert_eq!(
        alignment.update(&a, &b, &negative, &noise, 16.0),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(
        alignment.update(&a, &b, &noise, &[f64::NAN; 3], 16.0),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(
        alignment.update(&a, &b, &noise, &noise, f64::NAN),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(alignment, before);
    // 1 mrad against a 100 µrad prior: far outside a 16 gate.
    let report = alignment.update(&a, &b, &noise, &noise, 16.0).unwrap();
    assert!(!report.accepted && report.normalised_innovation_squared > 16.0);
    assert_eq!(alignment, before);
    // A zero prior with zero noise has no positive-definite S.
    assert_eq!(
        RelativeAlignment::from_estimate(&a, &Matrix3::zeros()),
        Err(NavError::InvalidConfiguration)
    );
    assert_eq!(
        RelativeAlignment::from_estimate(&a, &(Matrix3::identity() * f64::NAN)),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(
        alignment.add_process_noise(&(Matrix3::identity() * -1e-12)),
        Err(NavError::InvalidConfiguration)
    );
    assert_eq!(alignment, before);
    // Accepted: the count moves, P shrinks and stays exactly symmetric.
    let report = alignment
        .update(&a, &b, &noise, &noise, f64::INFINITY)
        .unwrap();
    assert!(report.accepted);
    assert_eq!(alignment.pairs_accepted(), 1);
    assert!(alignment.covariance().trace() < before.covariance().trace());
    assert_eq!(alignment.covariance(), &alignment.covariance().transpose());
}

/// Monte Carlo of the estimator (brief's case): heads 90° apart, 5″/5″/35″ noise on both,
/// installation errors of 60″ per axis, 100 pairs per trial at random sky attitudes, 300
/// trials. The final error's NEES `eᵀ P⁻¹ e` averages 3 within the 99.9 % band of
/// `χ²(3·300)/300` (±3.29 √(6/300)), the NIS over all pairs likewise (±3.29 √(6/30000)).
#[test]
fn the_estimator_is_consistent_over_many_trials() {
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    let (trials, pairs) = (300, 100);
    let installation_sigma = [60.0 * ARCSEC; 3];
    let quarter_turn = exp_rotation_vector(&Vector3::new(core::f64::consts::FRAC_PI_2, 0.0, 0.0));
    let (mut nees_sum, mut nis_sum, mut nis_count, mut rejected) = (0.0, 0.0, 0usize, 0usize);
    let mut final_sigma_arcsec = Vector3::zeros();
    for _ in 0..trials {
        let mounting_a = random_quaternion(&mut rng, 3.1);
        let mounting_b = mounting_a * quarter_turn;
        let [installation_a, installation_b] =
            [0; 2].map(|_| exp_rotation_vector(&normal_rotation(&mut rng, &installation_sigma)));
        let truth = conjugate(&(mounting_a * installation_a)) * (mounting_b * installation_b);
        // Prior: the pair model with n replaced by ψ (isotropic here: 2σ² I).
        let nominal = conjugate(&mounting_a) * mounting_b;
        let variance = Matrix3::from_diagonal(&Vector3::from(installation_sigma.map(|s| s * s)));
        let c = rotation_matrix(&nominal);
        let prior = variance + c.transpose() * variance * c;
        let mut alignment = RelativeAlignment::new(&mounting_a, &mounting_b, &prior).unwrap();
        for _ in 0..pairs {
            let pair = Pair {
                sensor_a: random_quaternion(&mut rng, 3.1) * mounting_a * installation_a,
                alignment_true: truth,
            };
            let [a, b] = pair.measure(
                &normal_rotation(&mut rng, &TRACKER_NOISE_RAD),
                &normal_rotation(&mut rng, &TRACKER_NOISE_RAD),
            );
            let report = alignment
                .update(&a, &b, &TRACKER_NOISE_RAD, &TRACKER_NOISE_RAD, 21.1)
                .unwrap();
            nis_sum += report.normalised_innovation_squared;
            nis_count += 1;
            rejected += usize::from(!report.accepted);
        }
        let error = log_rotation_vector(&(conjugate(alignment.estimate()) * truth));
        let p = alignment.covariance();
        nees_sum += error.dot(&(p.try_inverse().unwrap() * error));
        final_sigma_arcsec += p.diagonal().map(|v| v.sqrt() / ARCSEC) / trials as f64;
    }
    let nees = nees_sum / trials as f64;
    let nis = nis_sum / nis_count as f64;
    println!(
        "NEES mean {nees:.3}, NIS mean {nis:.4}, rejected {rejected} of {nis_count}, \
         final 1σ (″, mean) {:.2} {:.2} {:.2}",
        final_sigma_arcsec.x, final_sigma_arcsec.y, final_sigma_arcsec.z
    );
    assert!(
        (nees - 3.0).abs() < 3.29 * (6.0 / trials as f64).sqrt(),
        "{nees}"
    );
    assert!(
        (nis - 3.0).abs() < 3.29 * (6.0 / nis_count as f64).sqrt(),
        "{nis}"
    );
    assert!(rejected < nis_count / 1000 + 5, "{rejected}");
    // 100 pairs: each axis is seen by at least one head's cross-boresight noise.
    assert!(final_sigma_arcsec.amax() < 5.0, "{final_sigma_arcsec}");
}
