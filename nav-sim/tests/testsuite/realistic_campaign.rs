//! The realistic-error campaigns shared by the tests (`realistic_errors.rs`) and the studies
//! for the docs (`examples/realistic_errors.rs`, which includes this file): runs with the
//! sensor-error truth drawn from the prior, their NEES test, the worst state of any run and
//! the accuracy against the paper's figures.
//!
//! `NAV_MC_FIRST_RUN` offsets the seeds (default 0: the scenario's seed, +1, ...).
//! `NAV_MC_RUNS` sets the runs per scenario (default 4, the test command's size).

use std::path::PathBuf;

use nav_sim::campaign::monte_carlo::{calibration_labels, fly_campaign, summarise, RunOutcome};
use nav_sim::output::report::Parameter;
use nav_sim::Scenario;

pub fn scenario(name: &str) -> Scenario {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(format!("{name}.toml"));
    Scenario::load(&path).unwrap()
}

pub fn runs() -> u64 {
    std::env::var("NAV_MC_RUNS")
        .ok()
        .and_then(|text| text.parse().ok())
        .unwrap_or(DEFAULT_RUNS)
}

/// Runs per scenario in the test command (the docs' campaigns fly 20 to 50).
const DEFAULT_RUNS: u64 = 4;

/// Worst |e_i| / σ_i over the 15 calibration states of one run.
pub fn worst_sigma(outcome: &RunOutcome) -> f64 {
    (0..15)
        .map(|i| outcome.error[i].abs() / outcome.covariance[(i, i)].sqrt())
        .fold(0.0, f64::max)
}

/// What a campaign showed: the NEES test, the worst state of any run, and per state the RMS
/// error over the paper's figure (installation error as an angle, twice the state).
pub struct Campaign {
    pub nees_line: String,
    pub consistent: bool,
    pub worst_sigma: f64,
    pub worst_seed: u64,
    pub accuracy: Vec<(String, f64, f64)>,
}

/// The campaign's seeds: `NAV_MC_RUNS` of them from the scenario's seed plus
/// `NAV_MC_FIRST_RUN`.
pub fn seeds(scenario: &Scenario) -> Vec<u64> {
    let first: u64 = std::env::var("NAV_MC_FIRST_RUN")
        .ok()
        .and_then(|text| text.parse().ok())
        .unwrap_or(0);
    (first..first + runs())
        .map(|run| scenario.simulation.seed.wrapping_add(run))
        .collect()
}

pub fn fly(scenario: &Scenario) -> Campaign {
    let outcomes = fly_campaign(scenario, &seeds(scenario), &|| {}).unwrap();
    let summary = summarise::<15, nav_sim::harness::flight::FlightError>(&outcomes).unwrap();
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

pub fn print(name: &str, campaign: &Campaign) {
    println!(
        "== {name}: {} ({})",
        campaign.nees_line,
        if campaign.consistent {
            "consistent"
        } else {
            "not consistent"
        }
    );
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
