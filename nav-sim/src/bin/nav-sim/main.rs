//! `nav-sim`: the host simulator. Runs the paper's on-line calibration experiment (Section 3)
//! through the flight code (nav-fsw), Monte Carlo campaigns over seeds, replays of recorded
//! sensor logs, and prints or writes the scenarios and logs they use.
//!
//! This file only parses the command line and dispatches: each subcommand's arguments and
//! run are in `commands/<subcommand>.rs`.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod commands;

use commands::{
    benefit, calibrate, design, false_alarms, faults, gravity_omission, ground_constants, log,
    merge, monte_carlo, observability, replay, scenario, target_bench, telemetry,
};

/// Host simulator for the INS/CNS/GNSS navigation and on-line calibration flight software.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Fly the calibration scenario through the flight software and report the calibration
    /// (default: the paper's Section 3 scenario).
    Calibrate(calibrate::Args),
    /// Monte Carlo over seeds (each run's sensor-error truth drawn from the filter's prior):
    /// RMS error, mean filter 1σ, |error| percentiles, the NEES consistency test and the runs
    /// outside 3σ (docs/guide/monte-carlo.md).
    MonteCarlo(monte_carlo::Args),
    /// Merge the shard files of a sharded Monte Carlo campaign (`monte-carlo --shard`) and
    /// print the report of the whole campaign, as `monte-carlo` prints it.
    Merge(merge::Args),
    /// The consistency flags' false alarms on a clean flight: a campaign (or the shard files
    /// of one) and, per flag, the runs that raised it, with the rate's 95 % interval.
    FalseAlarms(false_alarms::Args),
    /// Write a scenario's sensor log as CSV (the replay format, docs/guide/replay-format.md).
    Log(log::Args),
    /// Replay a recorded sensor log (CSV) through the flight software and write its
    /// per-second navigation and calibration output as CSV (`--packets`: also its telemetry
    /// packets; `--records`: every frame's output record).
    Replay(replay::Args),
    /// Print the built-in default scenario (TOML) to standard output, or with `--resolved FILE`
    /// a scenario file resolved (its `extends` chain merged, `remove` applied).
    Scenario(scenario::Args),
    /// Print the flight configuration's ground constants (launch site with the day's Earth
    /// axis, GCRF → launch-inertial rotation, launch epoch in GPS time) for a launch, as TOML,
    /// JSON or Rust constants.
    GroundConstants(ground_constants::Args),
    /// Fault-injection campaign: one flight per fault class through the flight software,
    /// printed as a table (fault, expected reaction, counters, calibration, met); exits
    /// non-zero if a row is not met.
    Faults(faults::Args),
    /// Observability analysis (the paper's Table 1) of its motion states and the scenario's
    /// manoeuvre schedule.
    Observability(observability::Args),
    /// Search a manoeuvre schedule with the covariance analysis under a vehicle's limits
    /// (default: the upper stage's), print its predicted accuracy and write it as a scenario.
    Design(design::Args),
    /// Target benchmark: replay the scenario's first SECONDS on the Cortex-M7 firmware under
    /// QEMU and on the host, compare every output bit for bit, and print the per-frame cost
    /// (min / median / worst by frame type), the stack high-water mark and the image's flash
    /// and static RAM (`scripts/bench-target.sh` builds the firmware and runs this).
    TargetBench(target_bench::Args),
    /// What calibration buys: fly the scenario, then a coast with GNSS and star tracker lost,
    /// with the on-line calibration and with it switched off (same sensor data), and print the
    /// position, velocity and attitude error growth side by side (`--runs N`: over seeds).
    Benefit(benefit::Args),
    /// The gravity a flight field of degree N and order M leaves out along the scenario's
    /// truth (its `[gravity]` field), and the white velocity process noise q that covers it:
    /// RMS, maximum and correlation time of the difference, q from a Gershgorin bound on its
    /// second moments and from its averaged periodogram (docs/guide/gravity.md).
    GravityOmission(gravity_omission::Args),
    /// The flight's telemetry packets (CCSDS space packets, docs/reference/telemetry-packets.md):
    /// `telemetry decode` turns a packet stream into the output-record CSV.
    Telemetry(telemetry::Args),
}

/// The exit status of a command ended by SIGINT or SIGTERM (128 + SIGINT, as a shell reports
/// an interrupted command).
const INTERRUPTED_EXIT_CODE: i32 = 130;

fn main() -> ExitCode {
    // An interrupted command leaves no temporary output behind: the handler removes every
    // output not yet committed (their targets stay as they were) and ends the process.
    if let Err(error) = ctrlc::set_handler(|| {
        nav_sim::output::remove_staged_files();
        eprintln!("nav-sim: interrupted; the outputs not yet complete were removed");
        std::process::exit(INTERRUPTED_EXIT_CODE);
    }) {
        eprintln!("nav-sim: warning: cannot handle interruptions ({error})");
    }
    let cli = Cli::parse();
    let outcome = match cli.command {
        None => calibrate::run(calibrate::Args::default()),
        Some(Command::Calibrate(args)) => calibrate::run(args),
        Some(Command::MonteCarlo(args)) => monte_carlo::run(args),
        Some(Command::Merge(args)) => merge::run(args),
        Some(Command::FalseAlarms(args)) => false_alarms::run(args),
        Some(Command::Log(args)) => log::run(args),
        Some(Command::Replay(args)) => replay::run(args),
        Some(Command::Scenario(args)) => scenario::run(args),
        Some(Command::GroundConstants(args)) => ground_constants::run(args),
        Some(Command::Faults(args)) => faults::run(args),
        Some(Command::Observability(args)) => observability::run(args),
        Some(Command::Design(args)) => design::run(args),
        Some(Command::TargetBench(args)) => target_bench::run(args),
        Some(Command::Benefit(args)) => benefit::run(args),
        Some(Command::GravityOmission(args)) => gravity_omission::run(args),
        Some(Command::Telemetry(args)) => telemetry::run(args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("nav-sim: {error}");
            ExitCode::FAILURE
        }
    }
}
