//! Unit tests of the campaign statistics: χ² bounds, the NEES test, the parallel runner.

use super::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use std::path::Path;

type Never = std::convert::Infallible;

/// A fixed symmetric positive definite 15×15 covariance with correlations and scales from
/// 1e-12 to 1 (like the calibration states').
fn known_covariance() -> SMatrix<f64, CALIBRATION_STATES, CALIBRATION_STATES> {
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    let mixing = SMatrix::<f64, CALIBRATION_STATES, CALIBRATION_STATES>::from_fn(|_, _| {
        StandardNormal.sample(&mut rng)
    });
    let correlation = mixing * mixing.transpose()
        + SMatrix::<f64, CALIBRATION_STATES, CALIBRATION_STATES>::identity();
    let scale = SVector::<f64, CALIBRATION_STATES>::from_fn(|index, _| {
        10_f64.powi(-(i32::try_from(index).unwrap() % 7) * 2)
    });
    SMatrix::from_diagonal(&scale) * correlation * SMatrix::from_diagonal(&scale)
}

/// `runs` outcomes whose errors are drawn from `N(0, true_scale · P)` while the filter
/// reports `P`.
fn synthetic_runs(
    runs: usize,
    true_scale: f64,
    first_seed: u64,
) -> Vec<RunOutcome<CALIBRATION_STATES>> {
    let covariance = known_covariance();
    let factor = covariance.cholesky().unwrap().l() * true_scale.sqrt();
    (first_seed..)
        .take(runs)
        .map(|seed| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let white =
                SVector::<f64, CALIBRATION_STATES>::from_fn(|_, _| StandardNormal.sample(&mut rng));
            RunOutcome {
                seed,
                error: factor * white,
                covariance,
                star_nis: crate::harness::flight::NisSum::default(),
                gnss_nis: crate::harness::flight::NisSum::default(),
                position_error_m: 0.0,
                over_time: Vec::new(),
                health: std::collections::BTreeMap::new(),
                imu_error: None,
                gnss_error: None,
            }
        })
        .collect()
}

#[test]
fn wilson_hilferty_matches_the_exact_quantiles_where_both_exist_and_stays_finite_beyond() {
    let k = WILSON_HILFERTY_ABOVE_DOF;
    let exact = ChiSquared::new(k).unwrap();
    let normal = statrs::distribution::Normal::standard();
    let spread = (2.0 / (9.0 * k)).sqrt();
    for p in [0.025, 0.975] {
        let approximate = k * (1.0 - spread * spread + normal.inverse_cdf(p) * spread).powi(3);
        let relative = (approximate / exact.inverse_cdf(p) - 1.0).abs();
        assert!(relative < 1e-5, "p {p}: {relative:e}");
    }
    // The 100-run NIS campaign: 3,077,000 updates of 3 components.
    let (lower, upper) = average_interval::<Never>(3_077_000, 3).unwrap();
    assert!(
        (lower - 2.99726).abs() < 1e-4 && (upper - 3.00274).abs() < 1e-4,
        "{lower} {upper}"
    );
}

#[test]
fn chi_square_bounds_match_the_tables() {
    // Reference quantiles from the regularised incomplete gamma function (mpmath, 30
    // digits, bisection): χ²⁻¹(0.025; 15) = 6.262137795, χ²⁻¹(0.975; 15) = 27.48839286;
    // χ²⁻¹(0.025; 750) / 50 = 13.52005229, χ²⁻¹(0.975; 750) / 50 = 16.55570541.
    let (lower, upper) = nees_bounds::<Never>(1, 15).unwrap();
    assert!((lower - 6.262_137_795).abs() < 1e-7, "{lower}");
    assert!((upper - 27.488_392_86).abs() < 1e-7, "{upper}");
    let (lower, upper) = nees_bounds::<Never>(50, 15).unwrap();
    assert!((lower - 13.520_052_29).abs() < 1e-7, "{lower}");
    assert!((upper - 16.555_705_41).abs() < 1e-7, "{upper}");
    assert!(matches!(
        nees_bounds::<Never>(0, 15),
        Err(MonteCarloError::NoRuns)
    ));
}

#[test]
fn consistent_errors_pass_and_scaled_errors_fail() {
    let consistent = summarise::<_, Never>(&synthetic_runs(50, 1.0, 1000)).unwrap();
    let too_large = summarise::<_, Never>(&synthetic_runs(50, 4.0, 1000)).unwrap();
    let too_small = summarise::<_, Never>(&synthetic_runs(50, 0.25, 1000)).unwrap();
    println!("{}", consistent.nees_line());
    println!("{}", too_large.nees_line());
    println!("{}", too_small.nees_line());
    assert!(consistent.nees.consistent());
    assert!((consistent.nees.average - 15.0).abs() < 2.0);
    // Errors twice as large as the filter claims: NEES ≈ 4 × 15.
    assert!(!too_large.nees.consistent());
    assert!((too_large.nees.average / consistent.nees.average - 4.0).abs() < 1e-9);
    assert!(too_large.nees.average > too_large.nees.upper_bound);
    assert!(too_small.nees.average < too_small.nees.lower_bound);
}

/// The interval is a 95% interval: over 400 independent campaigns of 50 consistent runs,
/// about 95% pass (binomial σ ≈ 1.1%).
#[test]
fn the_interval_covers_95_percent_of_consistent_campaigns() {
    let campaigns = 400_u32;
    let passed = (0..campaigns)
        .filter(|campaign| {
            let runs = synthetic_runs(50, 1.0, 10_000 + u64::from(*campaign) * 50);
            summarise::<_, Never>(&runs).unwrap().nees.consistent()
        })
        .count();
    let fraction = f64::from(u32::try_from(passed).unwrap()) / f64::from(campaigns);
    println!("coverage of the 95% interval: {fraction:.3}");
    assert!((0.915..=0.985).contains(&fraction), "{fraction}");
}

#[test]
fn rms_error_and_mean_sigma_agree_for_a_consistent_filter() {
    let summary = summarise::<_, Never>(&synthetic_runs(4000, 1.0, 1)).unwrap();
    let covariance = known_covariance();
    for (state, statistics) in summary.states.iter().enumerate() {
        let sigma = covariance[(state, state)].sqrt();
        assert!((statistics.mean_sigma / sigma - 1.0).abs() < 1e-12);
        // RMS of 4000 normal draws: relative σ ≈ 1/√8000 = 1.1%.
        let ratio = statistics.rms_error / sigma;
        assert!((ratio - 1.0).abs() < 0.05, "state {state}: {ratio}");
    }
}

#[test]
fn bad_covariance_is_named_by_seed() {
    let mut runs = synthetic_runs(3, 1.0, 40);
    runs[1].covariance[(4, 4)] = -1.0;
    assert!(matches!(
        summarise::<_, Never>(&runs),
        Err(MonteCarloError::CovarianceNotPositiveDefinite { seed: 41 })
    ));
    assert!(matches!(
        summarise::<CALIBRATION_STATES, Never>(&[]),
        Err(MonteCarloError::NoRuns)
    ));
}

#[derive(Debug, thiserror::Error)]
#[error("diverged")]
struct Diverged;

#[test]
fn parallel_runner_keeps_seed_order_and_reports_the_failed_seed() {
    let seeds: Vec<u64> = (100..164).collect();
    let run =
        |seed: u64| -> Result<RunOutcome, Diverged> { Ok(synthetic_runs(1, 1.0, seed).remove(0)) };
    let outcomes = run_parallel(&seeds, run, &|| {}).unwrap();
    assert_eq!(
        outcomes
            .iter()
            .map(|outcome| outcome.seed)
            .collect::<Vec<_>>(),
        seeds
    );
    assert_eq!(outcomes, synthetic_runs(64, 1.0, 100));

    let failing = |seed: u64| -> Result<RunOutcome, Diverged> {
        if seed % 20 == 7 {
            Err(Diverged)
        } else {
            run(seed)
        }
    };
    let error = run_parallel(&seeds, failing, &|| {}).unwrap_err();
    assert_eq!(error.to_string(), "run with seed 107: diverged");
}

#[test]
fn table_and_plot() {
    let summary = summarise::<_, Never>(&synthetic_runs(50, 1.0, 1000)).unwrap();
    let text = summary.table(&calibration_labels()).to_string();
    println!("{text}\n{}", summary.nees_line());
    assert_eq!(
        text.lines()
            .filter(|line| line.contains("gyro_bias"))
            .count(),
        3
    );
    assert!(text.contains("accel_scale_factor (-)"));
    assert!(summary.nees_line().ends_with(": consistent"));
    let directory = tempfile::tempdir().unwrap();
    let path = directory.path().join("monte_carlo.png");
    summary.plot(&path).unwrap();
    assert!(std::fs::metadata(&path).unwrap().len() > 20_000);
    if let Ok(keep) = std::env::var("NAV_SIM_KEEP_PLOTS") {
        std::fs::copy(&path, Path::new(&keep).join("monte_carlo.png")).unwrap();
    }
}

/// The consistency monitor's default bound is `3 χ²⁻¹(1 − 1e-9; ν) / ν`, `ν = 3 (2N − 1)`,
/// for the default time constant `N` (nav-fsw `consistency`, Patnaik's moment match of the
/// fading average), to the 3 digits it is given; and the bound of nav-fsw's false-alarm test
/// is `χ²⁻¹(0.99; 93)`.
#[test]
fn the_consistency_monitors_default_bound_is_the_chi_square_quantile() {
    use nav_fsw::consistency::{DEFAULT_MEAN_NIS_BOUND, DEFAULT_TIME_CONSTANT_MEASUREMENTS};
    let degrees = 3.0 * (2.0 * f64::from(DEFAULT_TIME_CONSTANT_MEASUREMENTS) - 1.0);
    let exact = 3.0 * ChiSquared::new(degrees).unwrap().inverse_cdf(1.0 - 1e-9) / degrees;
    assert!(
        (exact - DEFAULT_MEAN_NIS_BOUND).abs() < 5e-3,
        "{exact} vs {DEFAULT_MEAN_NIS_BOUND}"
    );
    let test_bound = ChiSquared::new(93.0).unwrap().inverse_cdf(0.99);
    assert!((test_bound - 127.63).abs() < 5e-3, "{test_bound}");
}
