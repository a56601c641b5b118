//! `nav-sim merge`: the shard files of a sharded campaign read back and reported as
//! `nav-sim monte-carlo` reports the campaign flown in one process.

use std::path::{Path, PathBuf};

use nav_sim::campaign::{self, CampaignReport};

use super::monte_carlo::{campaign_plots, check_campaign, print_campaign, write_campaign_plots};
use super::{prepare_outputs, Failure, ResultsArg};

/// The arguments of `nav-sim merge`.
#[derive(clap::Args)]
pub struct Args {
    /// Shard files, or directories holding them (their shard-*-of-*.jsonl files).
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// Write the campaign's plots into this directory (as `monte-carlo --out`:
    /// `monte_carlo.png`, `nees_over_time.png`).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print the report as one JSON object (as `monte-carlo --json`).
    #[arg(long)]
    json: bool,
    /// Exit non-zero if the average NEES is outside its 95 % interval.
    #[arg(long)]
    check: bool,
    /// As `monte-carlo --results DIR`: the report as DIR/monte-carlo-<scenario>.md, headed by
    /// this merge's command line.
    #[command(flatten)]
    results: ResultsArg,
}

/// Merges the shard files and prints the campaign's report.
pub fn run(args: Args) -> Result<(), Failure> {
    let out = args.out.as_deref();
    if let Some(directory) = out {
        let inputs: Vec<&Path> = args.paths.iter().map(PathBuf::as_path).collect();
        prepare_outputs(directory, &campaign_plots(directory), &inputs)?;
    }
    let merged = campaign::merge(&args.paths)?;
    let report = CampaignReport::new(&merged.records, &merged.scenario)?;
    print_campaign(&report, args.json)?;
    args.results.write(
        "monte-carlo",
        merged.scenario.file.as_deref().map(Path::new),
        &report.text(),
    )?;
    if let Some(directory) = out {
        write_campaign_plots(&report, directory, args.json)?;
    }
    check_campaign(&report, args.check, "merge")
}
