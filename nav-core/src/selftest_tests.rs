use super::*;
use crate::measurement::refer_to_later_time;

#[test]
fn filter_path_sequence_runs_and_moves_the_solution_by_the_measured_offsets() {
    let mut fixture = FilterPathFixture::new().unwrap();
    let before = fixture.results();
    fixture.run_sequence().unwrap();
    let after = fixture.results();
    assert!(after.iter().all(|v| v.is_finite()));
    // Each of the two GNSS updates sees a fix 12 m further in x than the current position
    // and moves by gain × 12 m: ≈ 0.9 × 12 (prior 30 m vs 10 m noise), then ≈ 0.5 × 12.
    // Compared with the same strapdown run without any update:
    let mut free_running = FilterPathFixture::new().unwrap();
    for _ in 0..100 {
        free_running.navigate().unwrap();
    }
    let moved_x = after[4] - free_running.results()[4];
    assert!(
        after[4] - before[4] > 1000.0,
        "the strapdown moved the vehicle"
    );
    assert!(moved_x > 14.0 && moved_x < 19.0, "{moved_x}");
    // Updates shrink the attitude variance below its prior.
    assert!(after[14] < (0.5e-3f64).powi(2), "{}", after[14]);
}

#[test]
fn structured_and_dense_sequences_agree() {
    let mut structured = FilterPathFixture::new().unwrap();
    structured
        .run_sequence_with(FilterArithmetic::Structured)
        .unwrap();
    let mut dense = FilterPathFixture::new().unwrap();
    dense
        .run_sequence_with(FilterArithmetic::DenseReference)
        .unwrap();
    let (s, d) = (structured.results(), dense.results());
    // Attitude (unit quaternion), position (1e5-1e6 m), velocity (7.5e3 m/s), gyro bias,
    // P entries: relative to each quantity's own scale.
    let scales = [
        1.0, 1.0, 1.0, 1.0, 1e6, 1e6, 1e6, 1e4, 1e4, 1e4, 5e-4, 5e-4, 5e-4,
    ];
    for (index, scale) in scales.iter().enumerate() {
        let difference = (s[index] - d[index]).abs() / scale;
        assert!(
            difference < 1e-12,
            "result {index}: {} vs {}",
            s[index],
            d[index]
        );
    }
    for index in 13..FILTER_PATH_RESULT_COUNT {
        let difference = (s[index] - d[index]).abs() / d[13];
        assert!(
            difference < 1e-12,
            "result {index}: {} vs {}",
            s[index],
            d[index]
        );
    }
    // Another latency path: a late GNSS fix, structured vs dense, in one worst frame.
    let mut late_structured = structured;
    let mut late_dense = structured;
    late_structured
        .worst_frame_with(FilterArithmetic::Structured)
        .unwrap();
    late_dense
        .worst_frame_with(FilterArithmetic::DenseReference)
        .unwrap();
    let (s, d) = (late_structured.results(), late_dense.results());
    assert!((s[4] - d[4]).abs() < 1e-9, "{} vs {}", s[4], d[4]);
    assert!((s[13] - d[13]).abs() < 1e-12 * d[13]);
}

#[test]
fn reference_workload_is_finite_and_keeps_the_quaternion_unit() {
    let results = reference_workload();
    assert!(results.iter().all(|value| value.is_finite()));
    assert!(results[0] > 0.0, "trace of a Gram matrix is positive");
    assert!(results[7].abs() < 1e-12);
}

#[test]
fn observability_workload_gives_rank_15_for_each_paper_state_alone() {
    let results = observability_workload().unwrap();
    // Three states (I, II, III), each 24 singular values and a rank.
    assert_eq!(results.len(), 75);
    assert_eq!(
        results.chunks_exact(SINGULAR_VALUES_PER_STATE + 1).count(),
        3
    );
    for chunk in results.chunks_exact(SINGULAR_VALUES_PER_STATE + 1) {
        let (singular_values, rank) = chunk.split_at(SINGULAR_VALUES_PER_STATE);
        assert!((rank[0] - 15.0).abs() < 1e-12, "{rank:?}");
        assert!(singular_values.windows(2).all(|pair| pair[0] >= pair[1]));
        // 15 clearly non-zero, 9 numerically zero (relative 1e-12).
        assert!(singular_values[14] > 1e-8 * singular_values[0]);
        assert!(singular_values[15] <= 1e-12 * singular_values[0]);
    }
}

/// The reference workload against an independent evaluation of its documented formulas
/// (Python 3 with the C library's `sin`/`exp`/`cos`, double precision): traces and one
/// element of `M Mᵀ` to 1e-13 relative, the coning attitude to 1e-14. The host/target
/// comparison alone cannot see a wrong formula (both sides run the same code).
#[test]
fn reference_workload_matches_an_independent_evaluation() {
    let results = reference_workload();
    let independent: [f64; 7] = [
        73.710_713_977_101_49,
        25.961_100_458_878_73,
        0.183_797_414_086_148_8,
        0.998_588_918_490_162_3,
        3.325_459_334_804_181e-5,
        0.001_058_178_318_167_892_8,
        0.053_094_736_287_282_895,
    ];
    for (index, (value, expected)) in results.iter().zip(independent.iter()).enumerate() {
        let tolerance = if index < 3 {
            1e-13 * expected.abs()
        } else {
            1e-14
        };
        assert!(
            (value - expected).abs() <= tolerance,
            "result {index}: {value:e} vs {expected:e}"
        );
    }
    // |q| − 1: round-off of 500 products only.
    assert!(results[7].abs() < 1e-14, "{:e}", results[7]);
}

/// The fixture's IMU profile is the documented one: raw rate and specific force of the
/// last step (`Δθ/T`, `Δv/T`) at step k = 37 (φ = 0.37).
#[test]
fn fixture_navigate_uses_the_documented_motion() {
    let mut fixture = FilterPathFixture::new().unwrap();
    for _ in 0..38 {
        fixture.navigate().unwrap();
    }
    let phase: f64 = 0.37;
    let rate = Vector3::new(0.1 * phase.sin(), 0.05, 1.7 * phase.cos());
    let force = Vector3::new(0.5, 20.0 + (3.0 * phase).sin(), -0.3);
    let step = fixture.last_step;
    assert!((step.measured_rate_rad_s - rate).norm() < 1e-14, "{step:?}");
    assert!(
        (step.measured_specific_force_mps2 - force).norm() < 1e-13,
        "{step:?}"
    );
    // No calibration yet: corrected = measured.
    assert!((step.corrected_rate_rad_s - rate).norm() < 1e-14);
}

/// `propagate`, `propagate_with(Structured)` and `propagate_part(2)` are the same
/// operation (bit for bit); parts 0 and 1 leave `P` alone; the dense propagation agrees
/// to round-off; and a propagation adds process noise (the trace of `P` grows).
#[test]
fn fixture_propagation_variants_agree_and_grow_the_covariance() {
    let mut base = FilterPathFixture::new().unwrap();
    base.navigate().unwrap();
    let before = *base.filter.covariance();
    let run = |action: &dyn Fn(&mut FilterPathFixture)| {
        let mut fixture = base;
        action(&mut fixture);
        *fixture.filter.covariance()
    };
    let flight = run(&|f| f.propagate().unwrap());
    let with = run(&|f| f.propagate_with(FilterArithmetic::Structured).unwrap());
    let part = run(&|f| f.propagate_part(2).unwrap());
    let dense = run(&|f| f.propagate_with(FilterArithmetic::DenseReference).unwrap());
    assert_eq!(flight, with);
    assert_eq!(flight, part);
    for partial in [0, 1] {
        assert_eq!(run(&|f| f.propagate_part(partial).unwrap()), before);
    }
    assert!(flight.trace() > before.trace());
    assert!((flight - before).amax() > 1e-12 * before.amax());
    assert!((dense - flight).amax() <= 1e-12 * before.amax());
}

/// A star update shrinks the attitude variance as the scalar Kalman update of `ϑ` seen
/// through `ϑ + ψ` predicts; `star_update` is the structured variant.
#[test]
fn fixture_star_update_follows_the_scalar_kalman_update() {
    let mut base = FilterPathFixture::new().unwrap();
    base.navigate().unwrap();
    base.propagate().unwrap();
    let prior = base.filter.covariance()[(0, 0)];
    let mut flight = base;
    flight.star_update().unwrap();
    let mut structured = base;
    structured
        .star_update_with(FilterArithmetic::Structured)
        .unwrap();
    assert_eq!(flight.filter.covariance(), structured.filter.covariance());
    // The star sees `C ϑ + ψ + v` with isotropic priors a (attitude), b (installation) and
    // noise r = (10″/2)²: the scalar update a' = a (b + r) / (a + b + r) per axis.
    let installation = crate::state::STAR_INSTALLATION.index();
    let b = base.filter.covariance()[(installation, installation)];
    let r = (0.5 * 10.0 / 206_264.806_247_096_36_f64).powi(2);
    let expected = prior * (b + r) / (prior + b + r);
    let posterior = flight.filter.covariance()[(0, 0)];
    assert!(
        (posterior - expected).abs() < 1e-6 * expected,
        "{posterior:e} vs {expected:e} (prior {prior:e})"
    );
    assert!(posterior < prior - 9e-9);
}

/// The GNSS update is the documented fix (lever arm `(0.5, 1, −0.2)` m, offset
/// `(12, −5, 3)` m, 10 m), referred to the current state by `H (I − AΔ)` only for a
/// positive latency: the error state after each implementation's update equals a plain
/// dense update with the measurement built here, per component to 1e-9 relative.
#[test]
fn fixture_gnss_update_is_the_documented_fix() {
    let mut base = FilterPathFixture::new().unwrap();
    base.navigate().unwrap();
    base.propagate().unwrap();
    let navigation = base.navigation;
    let lever_arm = Vector3::new(0.5, 1.0, -0.2);
    let offset = Vector3::new(12.0, -5.0, 3.0);
    let antenna =
        navigation.position_m + attitude::rotate(&navigation.attitude, &lever_arm) + offset;
    let measurement = gnss_position(
        &navigation.attitude,
        &navigation.position_m,
        &lever_arm,
        &antenna,
        10.0,
    )
    .unwrap();
    assert!((measurement.residual - offset).norm() < 1e-8);
    let mut flight = base;
    flight.gnss_update().unwrap();
    let mut structured = base;
    structured
        .gnss_update_with(FilterArithmetic::Structured, 0.0)
        .unwrap();
    assert_eq!(flight.filter.state(), structured.filter.state());
    assert_eq!(flight.filter.covariance(), structured.filter.covariance());
    for latency in [0.0, 0.01] {
        let referred = if latency > 0.0 {
            let system = system_matrix(&base.linearisation_point());
            refer_to_later_time(&measurement, &system, latency).unwrap()
        } else {
            measurement
        };
        let mut expected = base;
        expected.filter.update(&referred, f64::INFINITY).unwrap();
        let expected_state = *expected.filter.state();
        // The referral adds a velocity column: the velocity correction differs.
        for implementation in [
            FilterArithmetic::Structured,
            FilterArithmetic::DenseReference,
        ] {
            let mut fixture = base;
            fixture.gnss_update_with(implementation, latency).unwrap();
            for (k, (value, wanted)) in fixture
                .filter
                .state()
                .iter()
                .zip(expected_state.iter())
                .enumerate()
            {
                assert!(
                    (value - wanted).abs() <= 1e-9 * wanted.abs(),
                    "{implementation:?} latency {latency}, state {k}: {value:e} vs {wanted:e}"
                );
            }
        }
    }
}

/// The closed-loop reset feeds the estimated error into the solution (`p̂ += δp`,
/// `v̂ += δv`, gyro bias `b̂ += δb`) and zeroes the filter's error state; `reset` is the
/// structured variant, and the worst frame is exactly its four documented steps.
#[test]
fn fixture_reset_feeds_back_and_worst_frame_is_its_four_steps() {
    use crate::state::{GYRO_BIAS, POSITION, VELOCITY};
    let mut base = FilterPathFixture::new().unwrap();
    base.navigate().unwrap();
    base.propagate().unwrap();
    base.gnss_update().unwrap();
    let error = *base.filter.state();
    assert!(
        error.fixed_rows::<3>(POSITION.index()).norm() > 5.0,
        "{error:?}"
    );
    let mut flight = base;
    flight.reset().unwrap();
    let mut structured = base;
    structured.reset_with(FilterArithmetic::Structured).unwrap();
    assert_eq!(
        flight.results().map(f64::to_bits),
        structured.results().map(f64::to_bits)
    );
    assert_eq!(*flight.filter.state(), crate::filter::ErrorState::zeros());
    let moved = flight.navigation.position_m - base.navigation.position_m;
    assert!(
        (moved - error.fixed_rows::<3>(POSITION.index())).norm() < 1e-9,
        "{moved:?}"
    );
    let velocity = flight.navigation.velocity_mps - base.navigation.velocity_mps;
    assert!((velocity - error.fixed_rows::<3>(VELOCITY.index())).norm() < 1e-12);
    let bias = Vector3::from(flight.calibration.gyro_bias_rad_s);
    assert!((bias - error.fixed_rows::<3>(GYRO_BIAS.index())).norm() < 1e-18);

    for implementation in [
        FilterArithmetic::Structured,
        FilterArithmetic::DenseReference,
    ] {
        let mut frame = FilterPathFixture::new().unwrap();
        frame.worst_frame_with(implementation).unwrap();
        let mut steps = FilterPathFixture::new().unwrap();
        steps.navigate().unwrap();
        steps.propagate_with(implementation).unwrap();
        steps.gnss_update_with(implementation, 0.01).unwrap();
        steps.reset_with(implementation).unwrap();
        assert_eq!(frame.step, 1);
        let (a, b) = (frame.results(), steps.results());
        assert!(a
            .iter()
            .zip(b.iter())
            .all(|(x, y)| x.to_bits() == y.to_bits()));
    }
}

/// The observability workload is the documented geometry: attitude `exp([0.2, 0.4, −0.1])`
/// and mounting `exp([0.4, −1.1, 0.25])`, each paper state alone, scaled continuous
/// segment; its singular values equal those of that analysis built here (1e-12 relative).
#[test]
fn observability_workload_is_the_documented_geometry() {
    let results = observability_workload().unwrap();
    let attitude = attitude::exp_rotation_vector(&Vector3::new(0.2, 0.4, -0.1));
    let mounting = attitude::exp_rotation_vector(&Vector3::new(0.4, -1.1, 0.25));
    let h = full_update_measurement_matrix(&attitude, &mounting).unwrap();
    for (state, chunk) in PaperMotionState::ALL
        .iter()
        .zip(results.chunks_exact(SINGULAR_VALUES_PER_STATE + 1))
    {
        let point = state.linearisation_point(&attitude::rotation_matrix(&attitude));
        let mut stripped = StrippedObservability::new(Scaling::typical()).unwrap();
        stripped
            .add_segment(&system_matrix(&point), &h, SystemForm::Continuous)
            .unwrap();
        let analysis = stripped.analyse(&RankTolerance::DEFAULT).unwrap();
        for (k, (value, expected)) in chunk
            .iter()
            .zip(analysis.singular_values.iter())
            .enumerate()
            .take(15)
        {
            assert!(
                (value - expected).abs() <= 1e-12 * expected,
                "{} σ{k}: {value:e} vs {expected:e}",
                state.label()
            );
        }
    }
}
