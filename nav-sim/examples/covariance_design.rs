//! Prints the linear covariance analysis of a scenario: final 1σ of every calibration state
//! against the paper's reported accuracy, the history per manoeuvre segment and the orbit check.
//!
//! ```sh
//! cargo run --release -p nav-sim --example covariance_design -- [scenario.toml] [step_frames]
//! ```
//! Without a file: the built-in default scenario. `step_frames`: IMU frames per covariance
//! step (default 5 = 10 ms at 500 Hz).

use std::path::Path;
use std::process::ExitCode;

use nav_sim::covariance_design::{analyse, DesignOptions};
use nav_sim::Scenario;

fn main() -> ExitCode {
    let arguments: Vec<String> = std::env::args().skip(1).collect();
    let scenario = match arguments.first() {
        Some(path) => Scenario::load(Path::new(path)),
        None => Scenario::default_scenario(),
    };
    let scenario = match scenario {
        Ok(scenario) => scenario,
        Err(error) => {
            eprintln!("{error}");
            return ExitCode::FAILURE;
        }
    };
    let mut options = DesignOptions::default();
    if let Some(text) = arguments.get(1) {
        match text.parse::<u32>() {
            Ok(frames) => options.step_frames = frames,
            Err(error) => {
                eprintln!("step_frames {text:?} is not a whole number: {error}");
                return ExitCode::FAILURE;
            }
        }
    }
    let started = std::time::Instant::now();
    let report = match analyse(&scenario, &options) {
        Ok(report) => report,
        Err(error) => {
            eprintln!("{error}");
            return ExitCode::FAILURE;
        }
    };
    println!(
        "covariance analysis: {:.0} s flight, {} star and {} GNSS updates, step {} frames ({:.1} s host)",
        report.duration_s,
        report.star_updates,
        report.gnss_updates,
        options.step_frames,
        started.elapsed().as_secs_f64()
    );
    println!("\nsigma/target at the end of each segment (x y z per block):");
    print!("{}", report.history());
    println!("\nfinal:");
    print!("{}", report.table());
    println!("worst sigma/target: {:.3}", report.worst_ratio());
    let orbit = &report.orbit;
    println!(
        "\norbit: minimum altitude {:.1} km, minimum osculating perigee {:.1} km, final perigee {:.1} km, \
         final apogee {:.1} km, net delta-v {:.1} m/s, total delta-v {:.1} m/s",
        orbit.minimum_altitude_m / 1e3,
        orbit.minimum_perigee_altitude_m / 1e3,
        orbit.final_perigee_altitude_m / 1e3,
        orbit.final_apogee_altitude_m / 1e3,
        orbit.net_delta_v_mps,
        orbit.total_delta_v_mps,
    );
    ExitCode::SUCCESS
}
