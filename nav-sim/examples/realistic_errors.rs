//! Studies of the realistic sensor errors whose output docs/guide/realistic-errors.md quotes:
//!
//! * `mis-specified`: the receiver's correlated error given to the filter three times too
//!   small or too large, in σ or τ (`NAV_MC_RUNS=20 cargo run --release -p nav-sim --example
//!   realistic_errors -- mis-specified`);
//! * `second-order`: a blind star tracker flown with the attitude kinematics' second-order
//!   term neglected and bounded (`NAV_MC_RUNS=100 NAV_MC_FIRST_RUN=200 cargo run --release -p
//!   nav-sim --example realistic_errors -- second-order`).
//!
//! `NAV_MC_RUNS` sets the runs (default 6), `NAV_MC_FIRST_RUN` offsets the seeds.

use std::process::ExitCode;

use nav_fsw::config::SecondOrderAttitude;
use nav_sim::campaign::monte_carlo::calibration_labels;
use nav_sim::harness::flight::{fly_with, FlightOptions};
use nav_sim::output::report::Parameter;
use nav_sim::setup::fsw::fsw_config;
use nav_sim::setup::prior::with_truth_drawn_from_prior;
use nav_sim::Scenario;

#[path = "../tests/testsuite/realistic_campaign.rs"]
mod realistic_campaign;

use realistic_campaign::{fly, print, scenario, seeds};

fn main() -> ExitCode {
    match std::env::args().nth(1).as_deref() {
        Some("mis-specified") => a_mis_specified_correlated_error_model(),
        Some("second-order") => the_second_order_attitude_term_with_a_blind_star_tracker(),
        _ => {
            eprintln!("usage: realistic_errors mis-specified | second-order");
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}

/// The receiver's σ or τ given to the filter wrong by a factor of 3 either way (scenario (a)
/// flown with a mis-specified filter): printed for docs/guide/realistic-errors.md.
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

/// Mean NEES of the three gyro scale factors and of the 15 calibration states over the runs
/// of `scenario` with `seeds` (truth drawn from the prior), flown with the attitude
/// kinematics' second-order term neglected or bounded.
fn second_order_campaign(
    scenario: &Scenario,
    treatment: SecondOrderAttitude,
    seeds: &[u64],
) -> (f64, f64) {
    let scale_factor_states: Vec<usize> = calibration_labels()
        .iter()
        .enumerate()
        .filter(|(_, (parameter, _))| *parameter == Parameter::GyroScaleFactor)
        .map(|(index, _)| index)
        .collect();
    let (mut scale_factor_nees, mut nees) = (0.0, 0.0);
    for seed in seeds {
        let drawn = with_truth_drawn_from_prior(scenario, *seed);
        let mut config = fsw_config(&drawn).unwrap();
        config.covariance.second_order_attitude = treatment;
        let options = FlightOptions {
            record_interval_s: 100.0,
        };
        let result = fly_with(&drawn, config, options, |_, _| {}, |_, _| {}).unwrap();
        let (error, covariance) = (result.calibration_error, result.calibration_covariance);
        scale_factor_nees += scale_factor_states
            .iter()
            .map(|&i| error[i] * error[i] / covariance[(i, i)])
            .sum::<f64>();
        nees += (error.transpose() * covariance.try_inverse().unwrap() * error)[(0, 0)];
    }
    let runs = seeds.len() as f64;
    (scale_factor_nees / runs, nees / runs)
}

/// Case (c) flown with the attitude kinematics' second-order term neglected (the paper's
/// linear model) and bounded (`covariance.second_order_attitude`, the default): printed for
/// docs/guide/realistic-errors.md. Two threads, one per treatment.
fn the_second_order_attitude_term_with_a_blind_star_tracker() {
    let flown = scenario("star_tracker_rate_limited");
    let seeds = seeds(&flown);
    let treatments = [SecondOrderAttitude::Neglected, SecondOrderAttitude::Bounded];
    std::thread::scope(|scope| {
        let handles = treatments.map(|treatment| {
            let (flown, seeds) = (&flown, &seeds);
            scope.spawn(move || (treatment, second_order_campaign(flown, treatment, seeds)))
        });
        for handle in handles {
            let (treatment, (scale_factor, all)) = handle.join().unwrap();
            println!(
                "{treatment:?}, {} runs: mean NEES of the gyro scale factors {scale_factor:.3} \
                 (of 3), of the 15 calibration states {all:.3} (of 15)",
                seeds.len()
            );
        }
    });
}
