//! Tests of the observability analysis: the paper's Table 1, ranks, scaling and errors.

use super::*;
use crate::attitude::{exp_rotation_vector, rotation_matrix};
use crate::discretise::discretise;
use crate::error_model::{noise_input_matrix, system_matrix, LinearisationPoint, ProcessNoise};

use nalgebra::{Quaternion, Vector3};

const DEG: f64 = core::f64::consts::PI / 180.0;
const STEP_S: f64 = 0.002;

fn attitude() -> Quaternion<f64> {
    exp_rotation_vector(&Vector3::new(0.2, 0.4, -0.1))
}

fn motion(rate_deg_s: Vector3<f64>, force_mps2: Vector3<f64>) -> LinearisationPoint {
    constant_motion(
        &(rate_deg_s * DEG),
        &force_mps2,
        &rotation_matrix(&attitude()),
    )
}

fn coast() -> LinearisationPoint {
    PaperMotionState::Coast.linearisation_point(&rotation_matrix(&attitude()))
}
fn ideal_coast() -> LinearisationPoint {
    motion(Vector3::zeros(), Vector3::zeros())
}
fn rotation(axis: usize) -> LinearisationPoint {
    let mut rate = Vector3::zeros();
    rate[axis] = 10.0;
    motion(rate, Vector3::zeros())
}
fn acceleration(axis: usize) -> LinearisationPoint {
    let mut force = Vector3::zeros();
    force[axis] = 20.0;
    motion(Vector3::zeros(), force)
}

/// H from the measurement module: star (generic mounting) and GNSS with zero lever arm
/// (the paper has none).
fn h() -> MeasurementMatrix {
    let mounting = exp_rotation_vector(&Vector3::new(0.4, -1.1, 0.25));
    full_update_measurement_matrix(&attitude(), &mounting).unwrap()
}

fn transition(point: &LinearisationPoint) -> SystemMatrix {
    discretise(
        &system_matrix(point),
        &noise_input_matrix(point),
        &ProcessNoise::PAPER.spectral_density_diagonal(),
        STEP_S,
        3,
    )
    .unwrap()
    .transition
}

fn analyse(
    segments: &[LinearisationPoint],
    form: SystemForm,
    scaling: Scaling,
) -> ObservabilityAnalysis {
    let mut som = StrippedObservability::new(scaling).unwrap();
    for point in segments {
        let system = match form {
            SystemForm::Continuous => system_matrix(point),
            SystemForm::Discrete => transition(point),
        };
        som.add_segment(&system, &h(), form).unwrap();
    }
    som.analyse(&RankTolerance::DEFAULT).unwrap()
}

fn continuous(segments: &[LinearisationPoint]) -> ObservabilityAnalysis {
    analyse(segments, SystemForm::Continuous, Scaling::typical())
}

fn state_name(k: usize) -> String {
    let block = StateBlock::ALL[k / 3];
    format!("{}.{}", block.name(), ["x", "y", "z"][k % 3])
}

fn unobservable(analysis: &ObservabilityAnalysis) -> Vec<String> {
    (0..STATE_DIMENSION)
        .filter(|k| !analysis.observable[*k])
        .map(state_name)
        .collect()
}

fn full_schedule() -> Vec<LinearisationPoint> {
    vec![
        coast(),
        rotation(0),
        rotation(1),
        rotation(2),
        acceleration(0),
        acceleration(1),
        acceleration(2),
    ]
}

#[test]
fn givens_factor_reproduces_the_gram_matrix_and_singular_values() {
    let scaling = Scaling::typical();
    let segments = [coast(), rotation(2), acceleration(1)];
    let mut som = StrippedObservability::new(scaling).unwrap();
    let mut gram = SystemMatrix::zeros();
    for point in &segments {
        let a = system_matrix(point);
        som.add_segment(&a, &h(), SystemForm::Continuous).unwrap();
        let q = segment_observability_matrix(&a, &h(), SystemForm::Continuous, &scaling).unwrap();
        gram += q.transpose() * q;
    }
    let r = som.factor();
    // Upper triangular.
    for i in 0..STATE_DIMENSION {
        for j in 0..i {
            assert_eq!(r[(i, j)].abs().to_bits(), 0.0_f64.to_bits());
        }
    }
    let difference = (r.transpose() * r - gram).norm() / gram.norm();
    assert!(difference < 1e-13, "{difference}");
    // Singular values of one segment's Q_j equal those of its R.
    let a = system_matrix(&rotation(2));
    let q = segment_observability_matrix(&a, &h(), SystemForm::Continuous, &scaling).unwrap();
    let mut single = StrippedObservability::new(scaling).unwrap();
    single
        .add_segment(&a, &h(), SystemForm::Continuous)
        .unwrap();
    let from_r = single
        .analyse(&RankTolerance::DEFAULT)
        .unwrap()
        .singular_values;
    let from_gram = (q.transpose() * q).symmetric_eigen().eigenvalues;
    let mut eig: Vec<f64> = from_gram.iter().map(|e| e.max(0.0).sqrt()).collect();
    eig.sort_by(|a, b| b.partial_cmp(a).unwrap());
    for (k, (s, e)) in from_r.iter().zip(eig.iter()).enumerate().take(12) {
        assert!((s - e).abs() <= 1e-9 * from_r[0], "{k}: {s} vs {e}");
    }
}

#[test]
fn invalid_inputs_are_typed_errors() {
    let mut bad = Scaling::typical();
    bad.time_unit_s = 0.0;
    assert_eq!(
        StrippedObservability::new(bad),
        Err(NavError::InvalidConfiguration)
    );
    let mut som = StrippedObservability::new(Scaling::typical()).unwrap();
    let mut a = system_matrix(&coast());
    a[(0, 0)] = f64::NAN;
    assert_eq!(
        som.add_segment(&a, &h(), SystemForm::Continuous),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(som.segments(), 0);
    assert_eq!(
        InformationAccumulator::new(&StateVector::zeros()),
        Err(NavError::InvalidConfiguration)
    );
}

#[test]
fn observability_coast_alone_rank_15() {
    let analysis = continuous(&[coast()]);
    println!("I alone: σ = {:.3e}", analysis.singular_values.transpose());
    assert_eq!(analysis.rank, 15, "{:?}", analysis.singular_values);
    // All six scale factors and the installation error (not separable from attitude)
    // have a null-space component; so do attitude and (through b_g + ω λ_g) gyro bias.
    for block in [
        GYRO_SCALE_FACTOR,
        ACCEL_SCALE_FACTOR,
        STAR_INSTALLATION,
        ATTITUDE,
    ] {
        assert_eq!(
            analysis.block_observable(block),
            [false; 3],
            "{}",
            block.name()
        );
    }
    for block in [POSITION, VELOCITY, ACCEL_BIAS] {
        assert_eq!(
            analysis.block_observable(block),
            [true; 3],
            "{}",
            block.name()
        );
    }
    // Accelerometer scale factors: zero columns (f = 0), the null vector is e_k itself.
    for k in ACCEL_SCALE_FACTOR.index()..ACCEL_SCALE_FACTOR.index() + 3 {
        assert!((analysis.null_space_projection[k] - 1.0).abs() < 1e-9);
    }
}

#[test]
fn observability_rotation_alone_cannot_separate_z_scale_factor_from_z_bias() {
    let analysis = continuous(&[rotation(2)]);
    assert_eq!(analysis.rank, 15, "{:?}", analysis.singular_values);
    // Constant ω: diag(ω) λ_g and b_g enter identically, the z pair is one direction.
    let z = GYRO_SCALE_FACTOR.index() + 2;
    let bz = GYRO_BIAS.index() + 2;
    assert!(!analysis.observable[z]);
    assert!(!analysis.observable[bz]);
    // The null vector pairs them with weights (b_gz, λ_gz) ∝ (−ω_z, 1) in physical units.
    let scaling = Scaling::typical();
    let null_pair: Vec<_> = analysis
        .right_singular_vectors
        .column_iter()
        .zip(analysis.singular_values.iter())
        .filter(|(_, s)| **s <= analysis.zero_threshold)
        .map(|(v, _)| {
            (
                v[bz] * scaling.state_magnitudes[bz],
                v[z] * scaling.state_magnitudes[z],
            )
        })
        .filter(|(b, l)| b.abs() + l.abs() > 1e-12)
        .collect();
    assert!(!null_pair.is_empty());
    for (b, l) in null_pair {
        assert!((b / l + 10.0 * DEG).abs() < 1e-9 * 10.0 * DEG, "{b} {l}");
    }
}

#[test]
fn observability_coast_then_rotation_z_separates_z_gyro_scale_factor() {
    let analysis = continuous(&[coast(), rotation(2)]);
    assert_eq!(analysis.rank, 18);
    let degree = |block: StateBlock, axis: usize| analysis.degree[block.index() + axis];
    let z = GYRO_SCALE_FACTOR.index() + 2;
    assert!(analysis.observable[z]);
    assert!(
        degree(GYRO_SCALE_FACTOR, 2) > 1e-4,
        "{}",
        degree(GYRO_SCALE_FACTOR, 2)
    );
    // x, y: observable only through the coast's 4e-6 rad/s rates: practically not.
    for axis in 0..2 {
        let d = analysis.null_space_projection[GYRO_SCALE_FACTOR.index() + axis];
        let sigma = analysis.assigned_singular_value[GYRO_SCALE_FACTOR.index() + axis];
        println!("I+II: λg axis {axis}: null projection {d:.2e}, σ {sigma:.2e}");
    }
    // With an ideal coast (ω = 0) x, y are exactly unobservable.
    let ideal = continuous(&[ideal_coast(), rotation(2)]);
    assert_eq!(
        ideal.block_observable(GYRO_SCALE_FACTOR),
        [false, false, true]
    );
    // Rotation about z separates the installation error's components ⊥ z (body) from
    // attitude; the z component stays tied to attitude.
    println!("ideal I+II unobservable: {:?}", unobservable(&ideal));
}

#[test]
fn observability_coast_then_acceleration_y_separates_y_accel_scale_factor() {
    let analysis = continuous(&[coast(), acceleration(1)]);
    assert_eq!(analysis.rank, 21);
    assert_eq!(
        analysis.block_observable(ACCEL_SCALE_FACTOR),
        [false, true, false]
    );
    println!("I+III unobservable: {:?}", unobservable(&analysis));
    let alone = continuous(&[acceleration(1)]);
    assert!(!alone.observable[ACCEL_SCALE_FACTOR.index() + 1]);
}

#[test]
fn observability_full_schedule_rank_24() {
    let analysis = continuous(&full_schedule());
    println!("full: σ = {:.3e}", analysis.singular_values.transpose());
    assert_eq!(analysis.rank, STATE_DIMENSION);
    assert_eq!(analysis.observable_count(), STATE_DIMENSION);
    let discrete = analyse(&full_schedule(), SystemForm::Discrete, Scaling::typical());
    assert_eq!(discrete.rank, STATE_DIMENSION);
}

#[test]
fn observable_directions_count_combinations_inside_a_block() {
    // Rotation about body x after a coast, generic star mounting: the installation error
    // about body x (a mix of all three sensor axes) stays glued to the attitude error, so
    // no single installation state passes the per-state test, yet two directions do; the
    // gyro scale factor has exactly one observable direction (x).
    let mounting = exp_rotation_vector(&Vector3::new(0.3, -0.2, 0.5));
    let h = full_update_measurement_matrix(&attitude(), &mounting).unwrap();
    let analysis =
        motion_observability_analysis(&rotation(0), &h, &RankTolerance::DEFAULT).unwrap();
    assert_eq!(analysis.block_observable(STAR_INSTALLATION), [false; 3]);
    let count = |block| {
        analysis
            .observable_directions(block, &RankTolerance::DEFAULT)
            .unwrap()
    };
    assert_eq!(count(STAR_INSTALLATION), 2);
    assert_eq!(count(GYRO_SCALE_FACTOR), 1);
    assert_eq!(count(ACCEL_SCALE_FACTOR), 0);
    assert_eq!(count(GYRO_BIAS), 3);
    assert_eq!(count(ATTITUDE), 2);
}

#[test]
fn observability_covariance_ratios_agree_with_the_pattern() {
    let mut prior = StateVector::zeros();
    for (block, sigma) in [
        (ATTITUDE, 1e-3),
        (POSITION, 10.0),
        (VELOCITY, 1.0),
        (GYRO_BIAS, 1e-3),
        (ACCEL_BIAS, 1e-2),
        (STAR_INSTALLATION, 1e-2),
        (GYRO_SCALE_FACTOR, 1e-4),
        (ACCEL_SCALE_FACTOR, 1e-4),
    ] {
        prior.fixed_rows_mut::<3>(block.index()).fill(sigma);
    }
    let noise = Scaling::typical().measurement_magnitudes;
    let run = |segments: &[LinearisationPoint]| {
        let mut info = InformationAccumulator::new(&prior).unwrap();
        for point in segments {
            // Measurements every 0.1 s for 20 s per segment.
            let step = transition(point);
            let mut f = SystemMatrix::identity();
            for _ in 0..50 {
                f = step * f;
            }
            info.add_segment(&f, &h(), &noise, 200).unwrap();
        }
        info.variance_ratios().unwrap()
    };
    let coast_only = run(&[coast()]);
    let full = run(&full_schedule());
    println!("ratio prior/posterior variance (coast | full schedule):");
    for k in 0..STATE_DIMENSION {
        println!(
            "  {:24} {:10.3e} {:10.3e}",
            state_name(k),
            coast_only[k],
            full[k]
        );
    }
    for k in 0..3 {
        assert!(coast_only[ACCEL_SCALE_FACTOR.index() + k] < 1.0 + 1e-9);
        // Weak: 20 s at 20 m/s² with λa = 1e-4 moves the position ≈ 0.4 m against a
        // 10 m GNSS: learned, but only a little (≈ 1.03-1.23 with this prior).
        assert!(full[ACCEL_SCALE_FACTOR.index() + k] > 1.02);
        assert!(full[GYRO_SCALE_FACTOR.index() + k] > 100.0);
        assert!(full[STAR_INSTALLATION.index() + k] > 100.0);
    }
}

#[test]
fn observability_table_1() {
    let cases: Vec<(&str, Vec<LinearisationPoint>)> = vec![
        ("I", vec![coast()]),
        ("II", vec![rotation(2)]),
        ("III", vec![acceleration(1)]),
        ("I+II", vec![coast(), rotation(2)]),
        ("I+III", vec![coast(), acceleration(1)]),
        ("full", full_schedule()),
    ];
    let scaled: Vec<_> = cases.iter().map(|(_, s)| continuous(s)).collect();
    let raw: Vec<_> = cases
        .iter()
        .map(|(_, s)| analyse(s, SystemForm::Discrete, Scaling::unscaled()))
        .collect();
    println!("Observability degree σ_k/σ_max (continuous, scaled; '*' = null-space test fails)");
    print!("{:22}", "state");
    for (name, _) in &cases {
        print!("{name:>11}");
    }
    println!();
    for k in 0..STATE_DIMENSION {
        print!("{:22}", state_name(k));
        for a in &scaled {
            let mark = if a.observable[k] { ' ' } else { '*' };
            print!("{:>10.1e}{mark}", a.degree[k]);
        }
        println!();
    }
    print!("{:22}", "rank (rel 1e-12)");
    for a in &scaled {
        print!("{:>11}", a.rank);
    }
    println!();
    println!("Paper-like: discrete Δ = 2 ms, unscaled, assigned σ (paper threshold 5e-8)");
    for k in 0..STATE_DIMENSION {
        print!("{:22}", state_name(k));
        for a in &raw {
            print!("{:>11.1e}", a.assigned_singular_value[k]);
        }
        println!();
    }
    print!("{:22}", "count σ ≥ 5e-8");
    for a in &raw {
        print!("{:>11}", a.rank_absolute);
    }
    println!();
    print!("{:22}", "rank (rel 1e-12)");
    for a in &raw {
        print!("{:>11}", a.rank);
    }
    println!();
}

/// The flight helper on the paper's three states (after the reference ideal coast).
#[test]
fn motion_observability_of_the_paper_states() {
    let attitude_matrix = rotation_matrix(&attitude());
    let result = |state: PaperMotionState| {
        motion_observability(
            &state.linearisation_point(&attitude_matrix),
            &h(),
            &RankTolerance::DEFAULT,
        )
        .unwrap()
    };
    let all = [true; 3];
    let none = [false; 3];
    // I: position, velocity, both biases; attitude and installation only as their sum
    // (the star sees C_sb ϑ + ψ), no scale factor (ω ≈ 0, f = 0).
    let coast = result(PaperMotionState::Coast);
    for (block, expected) in [
        (ATTITUDE, none),
        (POSITION, all),
        (VELOCITY, all),
        (GYRO_BIAS, all),
        (ACCEL_BIAS, all),
        (STAR_INSTALLATION, none),
        (GYRO_SCALE_FACTOR, none),
        (ACCEL_SCALE_FACTOR, none),
    ] {
        assert_eq!(coast.block(block), expected, "I {}", block.name());
    }
    assert_eq!(coast.observable_count(), 12);
    // II: rotation about z separates attitude x, y from the installation and makes the
    // z gyro scale factor observable.
    let rotation = result(PaperMotionState::Rotation);
    assert_eq!(rotation.block(ATTITUDE), [true, true, false]);
    assert_eq!(rotation.block(GYRO_SCALE_FACTOR), [false, false, true]);
    assert_eq!(rotation.block(STAR_INSTALLATION), none);
    assert_eq!(rotation.block(ACCEL_SCALE_FACTOR), none);
    assert!(rotation.fully_observable(GYRO_BIAS));
    assert_eq!(rotation.observable_count(), 15);
    // III: acceleration along y makes attitude ⊥ y visible in the velocity and the y
    // accelerometer scale factor observable.
    let acceleration = result(PaperMotionState::Acceleration);
    assert_eq!(acceleration.block(ATTITUDE), [true, false, true]);
    assert_eq!(acceleration.block(ACCEL_SCALE_FACTOR), [false, true, false]);
    assert_eq!(acceleration.block(GYRO_SCALE_FACTOR), none);
    assert_eq!(acceleration.block(STAR_INSTALLATION), none);
    assert!(acceleration.fully_observable(ACCEL_BIAS));
    assert_eq!(acceleration.observable_count(), 15);
    // Bad input is a typed error.
    let mut bad = PaperMotionState::Coast.linearisation_point(&attitude_matrix);
    bad.corrected_rate_rad_s.x = f64::NAN;
    assert_eq!(
        motion_observability(&bad, &h(), &RankTolerance::DEFAULT),
        Err(NavError::NonFiniteInput)
    );
}

/// The documented scaling values: star rows 5″ (10″/2) in radians, `unscaled` all ones
/// with `τ` = 1 s, `typical` the per-block magnitudes.
#[test]
fn scaling_constructors_hold_the_documented_values() {
    // 5″ = 5 / 3600 · π / 180 rad.
    assert!((Scaling::STAR_ROW_MAGNITUDE - 2.424_068_405_547_68e-5).abs() < 1e-19);
    let unscaled = Scaling::unscaled();
    assert_eq!(unscaled.state_magnitudes, StateVector::repeat(1.0));
    assert_eq!(
        unscaled.measurement_magnitudes,
        MeasurementVector::repeat(1.0)
    );
    assert_eq!(unscaled.time_unit_s.to_bits(), 1.0_f64.to_bits());
    let typical = Scaling::typical();
    assert_eq!(typical, Scaling::default());
    for (block, magnitude) in Scaling::TYPICAL_STATE_MAGNITUDES {
        for k in block.index()..block.index() + 3 {
            assert_eq!(typical.state_magnitudes[k].to_bits(), magnitude.to_bits());
        }
    }
    let custom = Scaling::from_blocks(&Scaling::TYPICAL_STATE_MAGNITUDES, 3.0, 7.0, 0.5);
    assert_eq!(
        custom.measurement_magnitudes,
        MeasurementVector::new(3.0, 3.0, 3.0, 7.0, 7.0, 7.0)
    );
    assert_eq!(custom.time_unit_s.to_bits(), 0.5_f64.to_bits());
}

/// Unscaled rows with `τ` = 2 s are `H (2A)^k` exactly as written in the module docs
/// (checked for k = 0, 1, 2 against products formed here); NaN in `H` or `A` is refused.
#[test]
fn segment_matrix_rows_are_h_times_powers_of_a_tau() {
    let scaling = Scaling {
        time_unit_s: 2.0,
        ..Scaling::unscaled()
    };
    let a = system_matrix(&rotation(2));
    let q = segment_observability_matrix(&a, &h(), SystemForm::Continuous, &scaling).unwrap();
    let mut expected = h();
    for power in 0..3 {
        let rows = q.fixed_rows::<MEASUREMENT_DIMENSION>(power * MEASUREMENT_DIMENSION);
        let error = (rows - expected).amax();
        assert!(error <= 1e-14 * expected.amax(), "power {power}: {error:e}");
        expected *= a * 2.0;
    }
    // Discrete form ignores τ: rows H F^k.
    let discrete = segment_observability_matrix(&a, &h(), SystemForm::Discrete, &scaling)
        .unwrap()
        .fixed_rows::<MEASUREMENT_DIMENSION>(MEASUREMENT_DIMENSION)
        .into_owned();
    assert!((discrete - h() * a).amax() <= 1e-14 * (h() * a).amax());
    let mut bad_h = h();
    bad_h[(4, 2)] = f64::NAN;
    assert_eq!(
        segment_observability_matrix(&a, &bad_h, SystemForm::Continuous, &scaling),
        Err(NavError::NonFiniteInput)
    );
    let mut bad_a = a;
    bad_a[(1, 7)] = f64::INFINITY;
    assert_eq!(
        segment_observability_matrix(&bad_a, &h(), SystemForm::Continuous, &scaling),
        Err(NavError::NonFiniteInput)
    );
}

#[test]
fn stripped_observability_counts_its_segments() {
    let mut som = StrippedObservability::new(Scaling::typical()).unwrap();
    assert_eq!(som.segments(), 0);
    for expected in 1..=3 {
        som.add_segment(&system_matrix(&coast()), &h(), SystemForm::Continuous)
            .unwrap();
        assert_eq!(som.segments(), expected);
    }
}

/// A diagonal factor has its diagonal as singular values (exactly) and the unit vectors as
/// singular vectors, so every reported number is known: threshold `1e-12 · σ_max`, a
/// value exactly at the threshold is zero (`σ ≤ threshold`), a value exactly at the
/// paper's `5e-8` counts (`σ ≥ 5e-8`), degree `σ_k / σ_max`.
#[test]
fn analyse_factor_of_a_diagonal_factor() {
    let tolerance = RankTolerance::DEFAULT;
    let sigma_max = 1.0e6;
    let at_threshold = tolerance.relative * sigma_max;
    let mut diagonal = StateVector::zeros();
    for (k, value) in diagonal.iter_mut().enumerate() {
        *value = 0.5 * (k as f64 + 1.0);
    }
    diagonal[3] = sigma_max;
    diagonal[7] = at_threshold;
    diagonal[9] = tolerance.absolute;
    diagonal[11] = 0.0;
    let analysis = analyse_factor(&TriangularFactor::from_diagonal(&diagonal), &tolerance).unwrap();
    assert_eq!(analysis.zero_threshold.to_bits(), at_threshold.to_bits());
    assert!((analysis.zero_threshold - 1.0e-6).abs() < 1e-21);
    // 24 values minus the one at the threshold, 5e-8 and 0.
    assert_eq!(analysis.rank, 21);
    // Only the zero is below 5e-8.
    assert_eq!(analysis.rank_absolute, 23);
    for k in 0..STATE_DIMENSION {
        assert_eq!(
            analysis.assigned_singular_value[k].to_bits(),
            diagonal[k].to_bits()
        );
        assert!((analysis.degree[k] - diagonal[k] / sigma_max).abs() <= 1e-16 * diagonal[k]);
        let unobservable = [7, 9, 11].contains(&k);
        assert_eq!(analysis.observable[k], !unobservable, "state {k}");
        let projection = if unobservable { 1.0 } else { 0.0 };
        assert!((analysis.null_space_projection[k] - projection).abs() < 1e-15);
    }
    assert!((analysis.degree[3] - 1.0).abs() < 1e-16);
    assert!((analysis.degree[23] - 12.0e-6).abs() < 1e-21);
}

/// `R = [[2, 2], [0, 0]]` (plus `3 I` elsewhere): right singular vectors `(1, ±1)/√2`
/// with `σ = 2√2` and 0, an exact tie between states 0 and 1. The first state wins the
/// tie, so state 0 gets `2√2` (and keeps it over the 0) and state 1 gets nothing.
#[test]
fn analyse_factor_breaks_ties_towards_the_first_state() {
    let mut factor = TriangularFactor::identity() * 3.0;
    factor[(0, 0)] = 2.0;
    factor[(0, 1)] = 2.0;
    factor[(1, 1)] = 0.0;
    let analysis = analyse_factor(&factor, &RankTolerance::DEFAULT).unwrap();
    assert!((analysis.assigned_singular_value[0] - 2.0 * 2.0_f64.sqrt()).abs() < 1e-14);
    assert_eq!(
        analysis.assigned_singular_value[1].to_bits(),
        0.0_f64.to_bits()
    );
    assert_eq!(analysis.degree[1].to_bits(), 0.0_f64.to_bits());
    // The null vector (1, −1)/√2 makes both unobservable.
    assert!(!analysis.observable[0] && !analysis.observable[1]);
    assert!((analysis.null_space_projection[0] - 0.5_f64.sqrt()).abs() < 1e-14);
}

/// Degenerate factors: all zero gives rank 0 and degree 0 (not 0/0 = NaN); a factor whose
/// singular value overflows is a typed error, not an analysis with an infinite σ.
#[test]
fn analyse_factor_of_zero_and_of_an_overflowing_factor() {
    let zero = analyse_factor(&TriangularFactor::zeros(), &RankTolerance::DEFAULT).unwrap();
    assert_eq!(zero.rank, 0);
    assert_eq!(zero.rank_absolute, 0);
    assert_eq!(zero.degree, StateVector::zeros());
    assert_eq!(zero.observable_count(), 0);
    let mut overflowing = TriangularFactor::identity();
    overflowing[(2, 2)] = f64::MAX;
    overflowing[(2, 5)] = f64::MAX;
    assert_eq!(
        analyse_factor(&overflowing, &RankTolerance::DEFAULT),
        Err(NavError::NonFiniteState)
    );
}

/// One null vector `v = 1e-4 e₀ + √(1 − 1e-8) e₂₃` (factor `I − v vᵀ`): the attitude
/// block's projection `P_b = diag(1e-8, 0, 0)` has one eigenvalue 1e-8 > 1e-6² , so only
/// two attitude directions are observable; the state test agrees (‖Nᵀe₀‖ = 1e-4 > 1e-6).
#[test]
fn observable_directions_uses_the_squared_projection_threshold() {
    let mut v = StateVector::zeros();
    v[0] = 1.0e-4;
    v[23] = crate::float::sqrt(1.0 - 1.0e-8);
    let factor = TriangularFactor::identity() - v * v.transpose();
    let analysis = analyse_factor(&factor, &RankTolerance::DEFAULT).unwrap();
    assert_eq!(analysis.rank, 23);
    assert!((analysis.null_space_projection[0] - 1.0e-4).abs() < 1e-12);
    assert!(!analysis.observable[0]);
    assert!(analysis.observable[1] && analysis.observable[2]);
    let directions = analysis
        .observable_directions(ATTITUDE, &RankTolerance::DEFAULT)
        .unwrap();
    assert_eq!(directions, 2);
    assert_eq!(
        analysis
            .observable_directions(POSITION, &RankTolerance::DEFAULT)
            .unwrap(),
        3
    );
}

/// One epoch-invariant scalar case in closed form: `H` observes position x (row 3) and
/// velocity y (row 4) with noise `m`, transition `I`, `n` epochs: the information on a
/// state with prior σ₀ is `1/σ₀² + n/m²`, so `prior/posterior = 1 + n σ₀²/m²`; unobserved
/// states keep 1.
#[test]
fn information_ratios_in_closed_form() {
    let mut prior = StateVector::repeat(1.0);
    prior[POSITION.index()] = 10.0;
    prior[VELOCITY.index() + 1] = 2.0;
    let mut h = MeasurementMatrix::zeros();
    h[(3, POSITION.index())] = 1.0;
    h[(4, VELOCITY.index() + 1)] = 1.0;
    let noise = MeasurementVector::new(1.0, 1.0, 1.0, 5.0, 0.5, 1.0);
    let mut info = InformationAccumulator::new(&prior).unwrap();
    info.add_segment(&SystemMatrix::identity(), &h, &noise, 4)
        .unwrap();
    let ratios = info.variance_ratios().unwrap();
    let expected_position = 1.0 + 4.0 * 100.0 / 25.0;
    let expected_velocity = 1.0 + 4.0 * 4.0 / 0.25;
    assert!((ratios[POSITION.index()] - expected_position).abs() < 1e-12);
    assert!((ratios[VELOCITY.index() + 1] - expected_velocity).abs() < 1e-12);
    for k in 0..STATE_DIMENSION {
        if k != POSITION.index() && k != VELOCITY.index() + 1 {
            assert!((ratios[k] - 1.0).abs() < 1e-15, "{k}: {}", ratios[k]);
        }
    }
}

/// The input checks in their documented order: epoch count (≤ 1e6, exactly 1e6 allowed),
/// then sigmas (finite and > 0), then finiteness of `transition` and `h` (even with zero
/// epochs, when neither is used); a refused call leaves the accumulator unchanged.
#[test]
fn information_accumulator_input_checks() {
    let mut info = InformationAccumulator::new(&StateVector::repeat(1.0)).unwrap();
    let before = info;
    let sigma = MeasurementVector::repeat(1.0);
    let identity = SystemMatrix::identity();
    let mut nan_transition = identity;
    nan_transition[(0, 0)] = f64::NAN;
    // The count check comes first: just above the limit it is a configuration error
    // even with a NaN transition; exactly at the limit the NaN is what is refused.
    assert_eq!(
        info.add_segment(
            &nan_transition,
            &h(),
            &sigma,
            MAX_MEASUREMENTS_PER_SEGMENT + 1
        ),
        Err(NavError::InvalidConfiguration)
    );
    assert_eq!(
        info.add_segment(&nan_transition, &h(), &sigma, MAX_MEASUREMENTS_PER_SEGMENT),
        Err(NavError::NonFiniteInput)
    );
    for bad in [0.0, -1.0, f64::INFINITY, f64::NAN] {
        let mut bad_sigma = sigma;
        bad_sigma[4] = bad;
        assert_eq!(
            info.add_segment(&identity, &h(), &bad_sigma, 1),
            Err(NavError::InvalidConfiguration),
            "{bad}"
        );
    }
    let mut nan_h = h();
    nan_h[(2, 2)] = f64::NAN;
    assert_eq!(
        info.add_segment(&identity, &nan_h, &sigma, 0),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(
        info.add_segment(&nan_transition, &h(), &sigma, 0),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(info, before);
    assert_eq!(info.add_segment(&identity, &h(), &sigma, 0), Ok(()));
}

/// A factor whose inverse overflows (a diagonal of 1e-200: posterior variance 1e400) or
/// underflows is reported as singular instead of a ratio of 1/∞ = 0. Not reachable through
/// `add_segment` (its diagonals only grow from 1) except by round-off, hence set directly.
#[test]
fn variance_ratios_refuse_an_overflowing_posterior() {
    let mut info = InformationAccumulator::new(&StateVector::repeat(1.0)).unwrap();
    info.factor_transposed[(5, 5)] = 1.0e-200;
    assert_eq!(info.variance_ratios(), Err(NavError::SingularMatrix));
    // An underflowing one (1e200 diagonal: posterior 1e-400 → 0) likewise, not ∞.
    info.factor_transposed[(5, 5)] = 1.0e200;
    assert_eq!(info.variance_ratios(), Err(NavError::SingularMatrix));
    info.factor_transposed[(5, 5)] = 0.5;
    let ratios = info.variance_ratios().unwrap();
    assert!((ratios[5] - 0.25).abs() < 1e-15);
}

/// Table 1's column labels, and `fully_observable` is false as soon as one axis fails
/// (rotation about z: attitude x, y observable, z not) and for a block with no axis.
#[test]
fn paper_labels_and_fully_observable() {
    let labels: Vec<&str> = PaperMotionState::ALL.iter().map(|s| s.label()).collect();
    assert_eq!(labels, ["I", "II", "III"]);
    let rotation = motion_observability(
        &PaperMotionState::Rotation.linearisation_point(&rotation_matrix(&attitude())),
        &h(),
        &RankTolerance::DEFAULT,
    )
    .unwrap();
    assert_eq!(rotation.block(ATTITUDE), [true, true, false]);
    assert!(!rotation.fully_observable(ATTITUDE));
    assert!(!rotation.fully_observable(ACCEL_SCALE_FACTOR));
    assert!(rotation.fully_observable(POSITION));
}
