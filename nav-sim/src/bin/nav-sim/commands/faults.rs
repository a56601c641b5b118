//! `nav-sim faults`: the fault-injection campaign, one flight per fault class, as a table.

use std::path::PathBuf;

use indicatif::ProgressBar;

use super::{load, Failure, ResultsArg};

/// The arguments of `nav-sim faults`.
#[derive(clap::Args)]
pub struct Args {
    /// Scenario TOML (default: the built-in one).
    scenario: Option<PathBuf>,
    #[command(flatten)]
    results: ResultsArg,
}

/// Flies every fault class, prints the table and fails if a row is not met.
pub fn run(args: Args) -> Result<(), Failure> {
    let scenario = load(args.scenario.as_deref())?;
    let total = nav_sim::studies::faults::campaign().len() as u64;
    let bar = ProgressBar::new(total);
    bar.set_message("fault classes");
    let result =
        nav_sim::studies::faults::run_campaign(&scenario, |done, _| bar.set_position(done))?;
    bar.finish_and_clear();
    println!("{}", result.table());
    println!("{}", result.summary_line());
    let measured = format!("{}\n{}\n", result.table(), result.measured_summary_line());
    args.results
        .write("faults", args.scenario.as_deref(), &measured)?;
    if result.all_met() {
        Ok(())
    } else {
        Err("fault campaign: a row is not met".into())
    }
}
