//! `nav-sim benefit`: what the calibration buys, the calibrated and the uncalibrated filter
//! flown through the same aiding outage.

use std::path::PathBuf;

use nav_sim::output;
use nav_sim::studies::benefit::{self, BenefitOptions, OutagePlan};

use super::{campaign_bar, load, Failure, ResultsArg};

/// The arguments of `nav-sim benefit`.
#[derive(clap::Args)]
pub struct Args {
    /// Scenario TOML: the calibration flight (default: the built-in one).
    scenario: Option<PathBuf>,
    /// Length of the coast after the calibration flight (s).
    #[arg(long, default_value_t = OutagePlan::default().coast_s)]
    coast_s: f64,
    /// GNSS outage from the end of the calibration flight (s); 0 = none.
    #[arg(long, default_value_t = OutagePlan::default().gnss_outage_s)]
    gnss_outage_s: f64,
    /// Star-tracker outage from the end of the calibration flight (s); 0 = none.
    #[arg(long, default_value_t = OutagePlan::default().star_outage_s)]
    star_outage_s: f64,
    /// Number of runs, 1 to 100000 (seeds: the scenario's seed, +1, +2, ...).
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = super::parse_runs)]
    runs: u64,
    /// Draw each run's sensor-error truth from the filter's prior (as `monte-carlo` does)
    /// instead of keeping the scenario's sensor errors.
    #[arg(long)]
    draw_truth: bool,
    /// Fly both filters with the innovation gates open and no sensor ever declared faulty, so
    /// the uncalibrated filter keeps its aiding sensors however overconfident it is.
    #[arg(long)]
    open_gates: bool,
    /// Write the error-growth plot (benefit.png) into this directory.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    #[command(flatten)]
    results: ResultsArg,
}

impl Args {
    /// The comparison's options.
    fn options(&self) -> BenefitOptions {
        BenefitOptions {
            plan: OutagePlan {
                coast_s: self.coast_s,
                gnss_outage_s: self.gnss_outage_s,
                star_outage_s: self.star_outage_s,
            },
            runs: self.runs,
            draw_truth: self.draw_truth,
            open_gates: self.open_gates,
        }
    }
}

/// Flies both filters and prints the comparison (and writes its plot if asked).
pub fn run(args: Args) -> Result<(), Failure> {
    let scenario = load(args.scenario.as_deref())?;
    // A bad --out fails now, not after the flights.
    if let Some(directory) = args.out.as_deref() {
        output::prepare_directory(directory)?;
    }
    let options = args.options();
    // Two flights per run (calibrated, uncalibrated); a count of 0 runs is refused by the
    // comparison itself.
    let flights = usize::try_from(options.runs)
        .unwrap_or(usize::MAX)
        .saturating_mul(2);
    let bar = campaign_bar(flights, "benefit", "flights", true);
    let report = benefit::run(&scenario, &options, args.out.as_deref(), &|| bar.inc(1));
    bar.finish_and_clear();
    let printed = report?.to_string();
    print!("{printed}");
    // The run time is the machine's, not a measurement of the flight.
    let measured: String = printed
        .lines()
        .filter(|line| !line.contains(" frames through nav-fsw in "))
        .map(|line| format!("{line}\n"))
        .collect();
    args.results
        .write("benefit", args.scenario.as_deref(), &measured)?;
    Ok(())
}
