//! `nav-sim replay`: a recorded sensor log flown through the flight software, its
//! per-second navigation and calibration output written as CSV.

use std::path::PathBuf;

use nav_sim::output::OutputFile;

use super::{inputs, load, Failure};

/// The arguments of `nav-sim replay`.
#[derive(clap::Args)]
pub struct Args {
    /// The sensor log (CSV, docs/guide/replay-format.md).
    log: PathBuf,
    /// Scenario TOML giving the flight software's setup (launch site, mounting, noise,
    /// initial solution); default: the built-in one.
    #[arg(long)]
    scenario: Option<PathBuf>,
    /// Output CSV (not the log or the scenario).
    #[arg(long, default_value = "replay-output.csv")]
    out: PathBuf,
}

/// Replays the log and writes the output CSV.
pub fn run(args: Args) -> Result<(), Failure> {
    let log = args.log.as_path();
    let scenario_path = args.scenario.as_deref();
    let out = args.out.as_path();
    let mut input_paths = inputs(scenario_path);
    input_paths.push(log);
    let mut output = OutputFile::create_distinct(out, &input_paths)?;
    let scenario = load(scenario_path)?;
    let input = std::fs::File::open(log)
        .map_err(|error| format!("cannot open {}: {error}", log.display()))?;
    let summary = nav_sim::harness::log_replay::replay(input, &scenario, &mut output)
        .map_err(|error| format!("replaying {}: {error}", log.display()))?;
    output.commit()?;
    println!("replayed {}: {}", log.display(), summary.text());
    println!("output {}", out.display());
    Ok(())
}
