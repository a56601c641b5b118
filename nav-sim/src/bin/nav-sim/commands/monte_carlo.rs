//! `nav-sim monte-carlo`: a campaign over seeds flown in one process, in shards
//! (`--shard K/M`, for `nav-sim merge`) or one run alone (`--run K`), and the campaign
//! report's printing, plots and `--check` that `nav-sim merge` shares.

use std::path::{Path, PathBuf};

use nav_sim::campaign::{self, CampaignReport, Shard};

use super::{campaign_bar, inputs, load_labelled, prepare_outputs, Failure, ResultsArg};

/// Runs flown without `--runs`.
const DEFAULT_RUNS: u64 = 50;

/// The arguments of `nav-sim monte-carlo`.
#[derive(clap::Args)]
pub struct Args {
    /// Scenario TOML (default: the built-in one).
    scenario: Option<PathBuf>,
    /// Number of runs, 1 to 100000 (run k has the seed: the scenario's seed + k); default 50.
    // Negative numbers reach the parser, which names the flag and the accepted range,
    // rather than being taken for an unknown flag. No clap default: `--run K` checks K
    // against `--runs` only when the user gave it.
    #[arg(long, allow_negative_numbers = true, value_parser = super::parse_runs)]
    runs: Option<u64>,
    /// Fly only shard K of M (runs k with k mod M = K) and write OUT/shard-K-of-M.jsonl,
    /// one JSON line per run, for `nav-sim merge`.
    #[arg(long, value_name = "K/M", requires = "out", conflicts_with_all = ["json", "check"])]
    shard: Option<Shard>,
    /// Fly run K alone and print its JSON line (as in a shard file).
    #[arg(long, value_name = "K", conflicts_with_all = ["shard", "out", "json", "check"])]
    run: Option<u64>,
    /// Write the NEES / RMS plot OUT/monte_carlo.png and the NEES and NIS over time with
    /// their 95 % intervals OUT/nees_over_time.png into this directory (with --shard: the
    /// shard file OUT/shard-K-of-M.jsonl).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print one JSON object: `{"scenario", "runs", "nees_mean", "nees_interval_95",
    /// "states", ...}`.
    #[arg(long)]
    json: bool,
    /// Exit non-zero if the average NEES is outside its 95 % interval.
    #[arg(long)]
    check: bool,
    #[command(flatten)]
    results: ResultsArg,
}

/// A progress bar over the runs of a campaign, hidden unless `show`.
fn runs_bar(count: usize, show: bool) -> indicatif::ProgressBar {
    campaign_bar(count, "Monte Carlo", "runs", show)
}

/// Flies the campaign (or its shard, or one run) and prints its report or its lines.
pub fn run(args: Args) -> Result<(), Failure> {
    let scenario_path = args.scenario.as_deref();
    if let (Some(run), Some(runs)) = (args.run, args.runs) {
        if run >= runs {
            return Err(format!(
                "--run {run} is not a run of --runs {runs}: the runs are numbered 0 to {}",
                runs - 1
            )
            .into());
        }
    }
    let runs_count = args.runs.unwrap_or(DEFAULT_RUNS);
    let (scenario, label) = load_labelled(scenario_path)?;
    nav_sim::setup::fsw::check_flight_star_heads(&scenario)?;
    if let Some(run) = args.run {
        for record in campaign::fly_runs(&scenario, &[run], &|| {})? {
            println!("{}", record.json_line()?);
        }
        return Ok(());
    }
    if let (Some(shard), Some(directory)) = (args.shard, args.out.as_deref()) {
        let bar = runs_bar(shard.runs(runs_count).len(), true);
        let written = campaign::write_shard(
            &scenario,
            scenario_path,
            label.sha256.as_deref().unwrap_or_default(),
            runs_count,
            shard,
            directory,
            &|| bar.inc(1),
        );
        bar.finish();
        let (path, runs) = written?;
        println!("wrote {runs} runs to {}", path.display());
        return Ok(());
    }
    if let Some(directory) = args.out.as_deref() {
        prepare_outputs(
            directory,
            &campaign_plots(directory),
            &inputs(scenario_path),
        )?;
    }
    let runs: Vec<u64> = (0..runs_count).collect();
    let bar = runs_bar(runs.len(), !args.json);
    let records = campaign::fly_runs(&scenario, &runs, &|| bar.inc(1));
    bar.finish();
    let records = records?;
    let report = CampaignReport::new(&records, &label)?;
    print_campaign(&report, args.json)?;
    args.results
        .write("monte-carlo", scenario_path, &report.text())?;
    if let Some(directory) = args.out.as_deref() {
        write_campaign_plots(&report, directory, args.json)?;
    }
    check_campaign(&report, args.check, "monte-carlo")
}

/// The plots `monte-carlo --out DIR` and `merge --out DIR` write: the NEES / RMS per run and
/// the consistency over time.
pub fn campaign_plots(directory: &Path) -> [PathBuf; 2] {
    [
        directory.join("monte_carlo.png"),
        directory.join("nees_over_time.png"),
    ]
}

/// Writes the campaign's plots into `directory` and says so unless `json`.
pub fn write_campaign_plots(
    report: &CampaignReport,
    directory: &Path,
    json: bool,
) -> Result<(), Failure> {
    let [per_run, over_time] = campaign_plots(directory);
    report.summary.plot(&per_run)?;
    report.summary.plot_over_time(&over_time)?;
    if !json {
        println!("wrote {} and {}", per_run.display(), over_time.display());
    }
    Ok(())
}

/// Prints the campaign's report, as text or as one JSON object.
pub fn print_campaign(report: &CampaignReport, json: bool) -> Result<(), Failure> {
    if json {
        println!("{}", report.json()?);
    } else {
        print!("{}", report.text());
    }
    Ok(())
}

/// `--check`: fails, naming `command`, if the average NEES is outside its 95 % interval.
pub fn check_campaign(report: &CampaignReport, check: bool, command: &str) -> Result<(), Failure> {
    match report.check_failure() {
        Some(failure) if check => Err(format!("{command} --check: {failure}").into()),
        _ => Ok(()),
    }
}
