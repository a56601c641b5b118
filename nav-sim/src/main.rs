//! `nav-sim`: the host simulator. Runs the paper's on-line calibration experiment through the
//! flight code. (The closed-loop experiment lands with the simulator issue; until then
//! `calibrate` runs nav-core's reference workload.)

use clap::{Parser, Subcommand};

/// Host simulator for the INS/CNS/GNSS navigation and on-line calibration flight software.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Run the calibration scenario (default: the paper's Section 3).
    Calibrate,
    /// Print the built-in default scenario (TOML) to standard output.
    Scenario,
}

fn main() {
    let cli = Cli::parse();
    match cli.command.unwrap_or(Command::Calibrate) {
        Command::Calibrate => {
            let scenario = nav_sim::Scenario::default_scenario().expect("default scenario");
            let started = std::time::Instant::now();
            let result = nav_sim::flight::fly(&scenario, Default::default(), |_, _| {})
                .expect("flight");
            println!("{} frames in {:.2?}", result.frames, started.elapsed());
            let last = result.last().expect("samples");
            let names = ["gyro bias", "accel bias", "installation", "gyro SF", "accel SF"];
            for (i, name) in names.iter().enumerate() {
                for axis in 0..3 {
                    println!(
                        "{name:>12} {axis} truth {:+.4e} est {:+.4e} err {:+.3e} sigma {:.3e}",
                        last.truth[i][axis],
                        last.estimate[i][axis],
                        last.estimate[i][axis] - last.truth[i][axis],
                        last.sigma[i][axis]
                    );
                }
            }
            println!("pos err {:?} att err {:?}", last.position_error_m, last.attitude_error_rad);
            println!("NEES {:?}", result.calibration_nees());
            println!("{:#?}", result.health);
        }
        Command::Scenario => print!("{}", nav_sim::scenario::DEFAULT_SCENARIO_TOML),
    }
}
