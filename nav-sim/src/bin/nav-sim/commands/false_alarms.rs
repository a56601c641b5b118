//! `nav-sim false-alarms`: a clean flight's campaign (flown here, or merged from the shard
//! files of `monte-carlo --shard`) and the consistency flags it raised, per flag the runs
//! raised and the rate's 95 % interval (nav-sim `campaign::false_alarms`).

use std::path::PathBuf;

use nav_sim::campaign::{self, false_alarms};

use super::{campaign_bar, load_labelled, Failure, ResultsArg};

/// The arguments of `nav-sim false-alarms`.
#[derive(clap::Args)]
pub struct Args {
    /// Scenario TOML of a clean flight (default: the built-in one).
    #[arg(conflicts_with = "merge")]
    scenario: Option<PathBuf>,
    /// Number of runs, 1 to 100000 (run k has the seed: the scenario's seed + k).
    #[arg(long, allow_negative_numbers = true, value_parser = super::parse_runs,
          required_unless_present = "merge", conflicts_with = "merge")]
    runs: Option<u64>,
    /// Read the runs from these shard files or directories (`monte-carlo --shard`) instead
    /// of flying them.
    #[arg(long, num_args = 1..)]
    merge: Vec<PathBuf>,
    #[command(flatten)]
    results: ResultsArg,
}

/// Flies (or merges) the campaign and prints its false-alarm table.
pub fn run(args: Args) -> Result<(), Failure> {
    let (label, records, scenario_path) = if args.merge.is_empty() {
        let scenario_path = args.scenario.as_deref();
        let (scenario, label) = load_labelled(scenario_path)?;
        nav_sim::setup::fsw::check_flight_star_heads(&scenario)?;
        let runs: Vec<u64> = (0..args.runs.unwrap_or(1)).collect();
        let bar = campaign_bar(runs.len(), "False alarms", "runs", true);
        let records = campaign::fly_runs(&scenario, &runs, &|| bar.inc(1));
        bar.finish();
        (label, records?, args.scenario.clone())
    } else {
        let merged = campaign::merge(&args.merge)?;
        let path = merged.scenario.file.clone().map(PathBuf::from);
        (merged.scenario, merged.records, path)
    };
    let text = false_alarms::false_alarm_text(&label, &records);
    print!("{text}");
    args.results
        .write("false-alarms", scenario_path.as_deref(), &text)
}
