//! Prints the linear covariance analysis of a scenario: final 1σ of every calibration state
//! against the paper's reported accuracy, the history per manoeuvre segment and the orbit check;
//! with `[filter.imu_errors]`, the same for the twelve systematic IMU error states.
//!
//! ```sh
//! cargo run --release -p nav-sim --example covariance_design -- [scenario.toml] [--step-frames N] [--measurement-stride N]
//! ```
//! Without a file: the built-in default scenario. `--help` lists the options.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use nav_core::error_model::ProcessNoise;
use nav_sim::studies::covariance_design::{analyse, DesignOptions};
use nav_sim::Scenario;

/// Linear covariance analysis of a calibration scenario.
#[derive(Parser)]
struct Arguments {
    /// Scenario file (default: the built-in default scenario).
    scenario: Option<PathBuf>,
    /// IMU frames per covariance step (5 = 10 ms at 500 Hz).
    #[arg(long, default_value_t = 5)]
    step_frames: u32,
    /// Leave the gravity gradient out of the error model (as the paper does).
    #[arg(long)]
    no_gravity_gradient: bool,
    /// Tune the filter with nav-core's `ProcessNoise::PAPER` instead of the scenario's noise.
    #[arg(long)]
    paper_process_noise: bool,
    /// Fuse every N-th measurement epoch with 1/N of the noise variance (coarse, faster).
    #[arg(long, default_value_t = 1)]
    measurement_stride: u32,
}

fn main() -> ExitCode {
    let arguments = Arguments::parse();
    let scenario = match &arguments.scenario {
        Some(path) => Scenario::load(path),
        None => Scenario::default_scenario(),
    };
    let scenario = match scenario {
        Ok(scenario) => scenario,
        Err(error) => {
            eprintln!("{error}");
            return ExitCode::FAILURE;
        }
    };
    let options = DesignOptions {
        step_frames: arguments.step_frames,
        gravity_gradient: !arguments.no_gravity_gradient,
        process_noise: arguments.paper_process_noise.then_some(ProcessNoise::PAPER),
        measurement_stride: arguments.measurement_stride,
        ..DesignOptions::default()
    };
    if let Ok([radial, along_track, normal]) =
        nav_sim::studies::covariance_design::initial_orbital_axes(&scenario)
    {
        println!(
            "launch-inertial axes at the start: radial {:?}, along-track {:?}, normal {:?}",
            radial.as_slice(),
            along_track.as_slice(),
            normal.as_slice()
        );
        let [x, y, z] = scenario.initial_attitude.rotation_vector_deg;
        let attitude =
            nav_core::attitude::rotation_matrix(&nav_core::attitude::exp_rotation_vector(
                &nalgebra::Vector3::new(x.to_radians(), y.to_radians(), z.to_radians()),
            ));
        for (axis, name) in ["x", "y", "z"].iter().enumerate() {
            let body_axis = attitude.column(axis);
            println!(
                "initial body {name} axis: radial {:+.3}, along-track {:+.3}, normal {:+.3}",
                body_axis.dot(&radial),
                body_axis.dot(&along_track),
                body_axis.dot(&normal)
            );
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
    if let (Some(history), Some(imu)) = (report.imu_error_history(), &report.imu_errors) {
        println!("\nsystematic IMU error states, sigma/prior at the end of each segment:");
        print!("{history}");
        println!("\nfinal (bias target: the paper's accuracy of the disturbed sensor's bias):");
        print!("{}", imu.table());
    }
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
