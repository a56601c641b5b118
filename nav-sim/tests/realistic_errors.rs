//! Monte Carlo of the default flight under realistic sensor errors (docs/realistic-errors.md):
//! (a) GNSS 6 m white + 8 m Gauss–Markov, τ = 300 s; (b) the same with τ = 30 s; (c) a star
//! tracker blind above 3 °/s and for 10 s after; (d) (a) with GNSS velocity at 0.05 m/s. The
//! filter is given each receiver's specification. In each: the average NEES of the 15
//! calibration states inside its two-sided 95 % χ² interval, and no run's calibration state
//! beyond 4σ of its truth; the accuracy against the paper's figures is printed.
//!
//! `NAV_MC_FIRST_RUN` offsets the seeds (default 0: the scenario's seed, +1, ...).
//! `NAV_MC_RUNS` sets the runs per scenario (default 6, the test command's size; the docs'
//! campaign uses 50: `NAV_MC_RUNS=50 cargo test --release -p nav-sim --test realistic_errors
//! -- --nocapture --test-threads 1`). The factor-of-3 mismatch study is ignored by default.

use std::path::PathBuf;

use nav_sim::monte_carlo::{calibration_labels, fly_campaign, summarise, RunOutcome};
use nav_sim::report::Parameter;
use nav_sim::Scenario;

/// Largest |error| / σ any run's calibration state may end at.
const WORST_SIGMA_BOUND: f64 = 4.0;

fn scenario(name: &str) -> Scenario {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(format!("{name}.toml"));
    Scenario::load(&path).unwrap()
}

fn runs() -> u64 {
    std::env::var("NAV_MC_RUNS")
        .ok()
        .and_then(|text| text.parse().ok())
        .unwrap_or(DEFAULT_RUNS)
}

/// Runs per scenario in the test command (about 45 s for the four on two cores).
const DEFAULT_RUNS: u64 = 6;

/// Worst |e_i| / σ_i over the 15 calibration states of one run.
fn worst_sigma(outcome: &RunOutcome) -> f64 {
    (0..15)
        .map(|i| outcome.error[i].abs() / outcome.covariance[(i, i)].sqrt())
        .fold(0.0, f64::max)
}

/// What a campaign showed: the NEES test, the worst state of any run, and per state the RMS
/// error over the paper's figure (installation error as an angle, twice the state).
struct Campaign {
    nees_line: String,
    consistent: bool,
    worst_sigma: f64,
    worst_seed: u64,
    accuracy: Vec<(String, f64, f64)>,
}

fn fly(scenario: &Scenario) -> Campaign {
    let first: u64 = std::env::var("NAV_MC_FIRST_RUN")
        .ok()
        .and_then(|text| text.parse().ok())
        .unwrap_or(0);
    let seeds: Vec<u64> = (first..first + runs())
        .map(|run| scenario.simulation.seed.wrapping_add(run))
        .collect();
    let outcomes = fly_campaign(scenario, &seeds, false).unwrap();
    let summary = summarise::<15, nav_sim::flight::FlightError>(&outcomes).unwrap();
    let (worst_sigma, worst_seed) = outcomes
        .iter()
        .map(|outcome| (worst_sigma(outcome), outcome.seed))
        .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
    let accuracy = calibration_labels()
        .iter()
        .zip(summary.states.iter())
        .map(|((parameter, axis), state)| {
            let angle = if *parameter == Parameter::StarInstallation {
                2.0
            } else {
                1.0
            };
            let paper = parameter.paper_accuracy().unwrap_or(f64::NAN);
            (
                format!("{} {}", parameter.name(), axis.name()),
                angle * state.rms_error / paper,
                angle * state.mean_sigma / paper,
            )
        })
        .collect();
    Campaign {
        nees_line: summary.nees_line(),
        consistent: summary.nees.consistent(),
        worst_sigma,
        worst_seed,
        accuracy,
    }
}

fn print(name: &str, campaign: &Campaign) {
    println!("== {name}: {}", campaign.nees_line);
    println!(
        "   worst calibration state of any run: {:.2} sigma (seed {})",
        campaign.worst_sigma, campaign.worst_seed
    );
    let met = campaign
        .accuracy
        .iter()
        .filter(|(_, rms, _)| *rms <= 1.0)
        .count();
    println!("   RMS error / paper's figure ({met} of 15 within):");
    for (label, rms, sigma) in &campaign.accuracy {
        println!("     {label:<22} rms {rms:>7.2}  mean sigma {sigma:>7.2}");
    }
}

fn assert_consistent(name: &str) {
    let campaign = fly(&scenario(name));
    print(name, &campaign);
    assert!(campaign.consistent, "{name}: {}", campaign.nees_line);
    assert!(
        campaign.worst_sigma <= WORST_SIGMA_BOUND,
        "{name}: a calibration state ended {:.2} sigma off (seed {})",
        campaign.worst_sigma,
        campaign.worst_seed
    );
}

#[test]
fn a_correlated_gnss_error_with_tau_300_s_keeps_the_filter_consistent() {
    assert_consistent("gnss_correlated");
}

#[test]
fn a_correlated_gnss_error_with_tau_30_s_keeps_the_filter_consistent() {
    assert_consistent("gnss_correlated_fast");
}

#[test]
fn a_rate_limited_star_tracker_keeps_the_filter_consistent() {
    assert_consistent("star_tracker_rate_limited");
}

#[test]
fn gnss_velocity_keeps_the_filter_consistent() {
    assert_consistent("gnss_correlated_velocity");
}

/// The receiver's σ or τ given to the filter wrong by a factor of 3 either way (scenario (a)
/// flown with a mis-specified filter): printed for docs/realistic-errors.md, not asserted.
#[test]
#[ignore = "a study for the docs: NAV_MC_RUNS=20 ... -- --ignored --nocapture"]
fn a_mis_specified_correlated_error_model() {
    let truth = scenario("gnss_correlated");
    let cases: [(&str, f64, f64); 4] = [
        ("sigma / 3", 8.0 / 3.0, 300.0),
        ("sigma x 3", 24.0, 300.0),
        ("tau / 3", 8.0, 100.0),
        ("tau x 3", 8.0, 900.0),
    ];
    for (name, sigma_m, tau_s) in cases {
        let mut flown = truth.clone();
        flown.filter.gnss_correlated_sigma_m = sigma_m;
        flown.filter.gnss_correlation_time_s = tau_s;
        print(name, &fly(&flown));
    }
}

/// The filter's correlated-error keys are checked, and a refusal names the key.
#[test]
fn the_filter_keys_are_validated_by_name() {
    let default = nav_sim::scenario::DEFAULT_SCENARIO_TOML;
    let with = |keys: &str| {
        default.replace(
            "discretisation_order = 3\n",
            &format!("discretisation_order = 3\n{keys}\n"),
        )
    };
    for (keys, named) in [
        (
            "gnss_correlated_sigma_m = -1.0",
            "filter.gnss_correlated_sigma_m",
        ),
        (
            "gnss_correlated_sigma_m = 8.0\ngnss_correlation_time_s = 0.0",
            "filter.gnss_correlation_time_s",
        ),
        ("gnss_noise_m = 0.0", "filter.gnss_noise_m"),
    ] {
        let error = Scenario::from_toml_str(&with(keys))
            .unwrap_err()
            .to_string();
        assert!(error.contains(named), "{keys}: {error}");
    }
    let told = Scenario::from_toml_str(&with(
        "gnss_correlated_sigma_m = 8.0\ngnss_correlation_time_s = 300.0\ngnss_noise_m = 6.0",
    ))
    .unwrap();
    let config = nav_sim::flight::fsw_config(&told).unwrap();
    assert_eq!(config.filter.gnss_error.sigma_m.to_bits(), 8.0f64.to_bits());
    assert_eq!(
        config.filter.gnss_error.correlation_time_s.to_bits(),
        300.0f64.to_bits()
    );
    assert_eq!(config.gnss.noise_m.to_bits(), 6.0f64.to_bits());
}
