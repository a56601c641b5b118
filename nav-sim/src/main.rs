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
    /// Observability analysis (the paper's Table 1) of its motion states and the scenario's
    /// manoeuvre schedule.
    Observability(nav_sim::observability_report::ObservabilityArgs),
}

fn main() {
    let cli = Cli::parse();
    match cli.command.unwrap_or(Command::Calibrate) {
        Command::Calibrate => {
            let results = nav_core::selftest::reference_workload();
            println!("nav-sim: scenario engine not built yet (placeholder run).");
            println!("nav-core reference workload: {results:?}");
        }
        Command::Scenario => print!("{}", nav_sim::scenario::DEFAULT_SCENARIO_TOML),
        Command::Observability(arguments) => {
            if let Err(error) = arguments.run() {
                eprintln!("nav-sim observability: {error}");
                std::process::exit(1);
            }
        }
    }
}
