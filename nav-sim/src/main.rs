//! `nav-sim`: the host simulator. Runs the paper's on-line calibration experiment (Section 3)
//! through the flight code (nav-fsw), Monte Carlo campaigns over seeds, replays of recorded
//! sensor logs, and prints or writes the scenarios and logs they use.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use nav_sim::campaign::monte_carlo;
use nav_sim::harness::flight::{self, FlightOptions, FlightResult};
use nav_sim::output::report::{self, CalibrationResult, Parameter, TimeHistorySample};
use nav_sim::output::{self, OutputFile};
use nav_sim::Scenario;
use statrs::distribution::{ChiSquared, ContinuousCDF};

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
    Calibrate {
        /// Scenario TOML (default: the built-in one; `nav-sim scenario` prints it).
        scenario: Option<PathBuf>,
        /// Write time-history CSVs and PNG plots into this directory.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print one JSON object: `{"rows": [...], "met": n, "nees": x, "health": {...}}`.
        #[arg(long)]
        json: bool,
        /// Exit non-zero if a parameter axis misses the paper's accuracy or the NEES of the
        /// calibration states is above its χ² 95 % bound.
        #[arg(long)]
        check: bool,
    },
    /// Monte Carlo over seeds (each run's sensor-error truth drawn from the filter's prior):
    /// RMS error, mean filter 1σ, |error| percentiles, the NEES consistency test and the runs
    /// outside 3σ (docs/monte-carlo.md).
    MonteCarlo {
        /// Scenario TOML (default: the built-in one).
        scenario: Option<PathBuf>,
        /// Number of runs, 1 or more (run k has the seed: the scenario's seed + k).
        // Negative numbers reach the parser, which names the flag and the accepted range,
        // rather than being taken for an unknown flag.
        #[arg(long, default_value_t = 50, allow_negative_numbers = true, value_parser = parse_runs)]
        runs: u64,
        /// Fly only shard K of M (runs k with k mod M = K) and write OUT/shard-K-of-M.jsonl,
        /// one JSON line per run, for `nav-sim merge`.
        #[arg(long, value_name = "K/M", requires = "out", conflicts_with_all = ["json", "check"])]
        shard: Option<nav_sim::campaign::Shard>,
        /// Fly run K alone and print its JSON line (as in a shard file).
        #[arg(long, value_name = "K", conflicts_with_all = ["shard", "out", "json", "check"])]
        run: Option<u64>,
        /// Write the NEES / RMS plot OUT/monte_carlo.png and the NEES and NIS over time with
        /// their 95 % intervals OUT/nees_over_time.png into this directory (with --shard: the
        /// shard file OUT/shard-K-of-M.jsonl).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print one JSON object: `{"runs", "nees_mean", "nees_interval_95", "states", ...}`.
        #[arg(long)]
        json: bool,
        /// Exit non-zero if the average NEES is outside its 95 % interval.
        #[arg(long)]
        check: bool,
    },
    /// Merge the shard files of a sharded Monte Carlo campaign (`monte-carlo --shard`) and
    /// print the report of the whole campaign, as `monte-carlo` prints it.
    Merge {
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
    },
    /// Write a scenario's sensor log as CSV (the replay format, docs/replay-format.md).
    Log {
        /// Scenario TOML (default: the built-in one).
        scenario: Option<PathBuf>,
        /// The CSV file to write (not the scenario).
        #[arg(long)]
        out: PathBuf,
    },
    /// Replay a recorded sensor log (CSV) through the flight software and write its
    /// per-second navigation and calibration output as CSV.
    Replay {
        /// The sensor log (CSV, docs/replay-format.md).
        log: PathBuf,
        /// Scenario TOML giving the flight software's setup (launch site, mounting, noise,
        /// initial solution); default: the built-in one.
        #[arg(long)]
        scenario: Option<PathBuf>,
        /// Output CSV (not the log or the scenario).
        #[arg(long, default_value = "replay-output.csv")]
        out: PathBuf,
    },
    /// Print the built-in default scenario (TOML) to standard output.
    Scenario,
    /// Fault-injection campaign: one flight per fault class through the flight software,
    /// printed as a table (fault, expected reaction, counters, calibration, met); exits
    /// non-zero if a row is not met.
    Faults {
        /// Scenario TOML (default: the built-in one).
        scenario: Option<PathBuf>,
    },
    /// Observability analysis (the paper's Table 1) of its motion states and the scenario's
    /// manoeuvre schedule.
    Observability(nav_sim::studies::observability::ObservabilityArgs),
    /// Search a manoeuvre schedule with the covariance analysis under a vehicle's limits
    /// (default: the upper stage's), print its predicted accuracy and write it as a scenario.
    Design(nav_sim::studies::manoeuvre_design::DesignArgs),
    /// Target benchmark: replay the scenario's first SECONDS on the Cortex-M7 firmware under
    /// QEMU and on the host, compare every output bit for bit, and print the per-frame cost
    /// (min / median / worst by frame type), the stack high-water mark and the image's flash
    /// and static RAM (`scripts/bench-target.sh` builds the firmware and runs this).
    TargetBench {
        /// Scenario TOML (default: the built-in one).
        scenario: Option<PathBuf>,
        /// The replay firmware ELF (qemu/target/thumbv7em-none-eabihf/release/replay).
        #[arg(long)]
        elf: PathBuf,
        /// Scenario seconds to replay (500 frames each).
        #[arg(long, default_value_t = 60)]
        seconds: u64,
        /// QEMU runner script.
        #[arg(long, default_value = "qemu/run.sh")]
        runner: PathBuf,
        /// Working directory for the replay files; the report is written there too.
        #[arg(long, default_value = "target/qemu/bench")]
        out: PathBuf,
    },
    /// What calibration buys: fly the scenario, then a coast with GNSS and star tracker lost,
    /// with the on-line calibration and with it switched off (same sensor data), and print the
    /// position, velocity and attitude error growth side by side (`--runs N`: over seeds).
    Benefit(nav_sim::studies::benefit::BenefitArgs),
}

type Failure = Box<dyn std::error::Error>;

/// `--runs`: a whole number of runs, 1 or more (clap names the flag and the value).
fn parse_runs(text: &str) -> Result<u64, String> {
    text.parse::<u64>()
        .ok()
        .filter(|&runs| runs >= 1)
        .ok_or_else(|| "expected a whole number of runs, 1 or more".to_string())
}

fn load(scenario: Option<&Path>) -> Result<Scenario, Failure> {
    Ok(match scenario {
        Some(path) => Scenario::load(path)?,
        None => Scenario::default_scenario()?,
    })
}

fn progress_bar(total: u64, message: &'static str) -> ProgressBar {
    let bar = ProgressBar::new(total);
    if let Ok(style) =
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} frames ({eta} left)")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(message);
    bar
}

fn history(result: &FlightResult) -> Vec<TimeHistorySample> {
    result.samples.iter().map(|s| s.time_history()).collect()
}

/// The probability below the bound of the single-flight NEES test of `calibrate --check`.
const NEES_BOUND_PROBABILITY: f64 = 0.95;

/// The bound that the NEES of the calibration states stays below with probability
/// [`NEES_BOUND_PROBABILITY`] for a consistent filter: the χ²(15) quantile.
fn calibration_nees_bound() -> Result<f64, Failure> {
    let distribution = ChiSquared::new(monte_carlo::CALIBRATION_STATES as f64)?;
    Ok(distribution.inverse_cdf(NEES_BOUND_PROBABILITY))
}

/// The scenario file as the input list of a command (the built-in one has none).
fn inputs(scenario: Option<&Path>) -> Vec<&Path> {
    scenario.into_iter().collect()
}

/// Checks an output directory and the files a command writes into it before the run, so a
/// bad `--out` fails at once rather than after the flight.
fn prepare_outputs(directory: &Path, files: &[PathBuf], inputs: &[&Path]) -> Result<(), Failure> {
    for file in files {
        output::refuse_inputs(file, inputs)?;
    }
    output::prepare_directory(directory)?;
    Ok(())
}

/// What `calibrate --check` finds wrong with a calibration: the axes that miss the paper's
/// accuracy and a NEES above its bound (`None` if nothing).
fn calibration_failures(
    table: &CalibrationResult,
    nees: Option<f64>,
    bound: f64,
) -> Option<String> {
    let mut failures = Vec::new();
    let missed: Vec<String> = table
        .rows
        .iter()
        .filter(|row| row.met() != Some(true))
        .map(|row| format!("{} {}", row.parameter.name(), row.axis.name()))
        .collect();
    if !missed.is_empty() {
        failures.push(format!(
            "{} of {} parameter axes do not meet the paper's accuracy ({})",
            missed.len(),
            table.rows.len(),
            missed.join(", ")
        ));
    }
    match nees {
        Some(nees) if nees <= bound => {}
        Some(nees) => failures.push(format!(
            "the NEES of the calibration states, {nees:.1}, is above its χ²({}) 95 % bound {bound:.1}",
            monte_carlo::CALIBRATION_STATES
        )),
        None => failures.push(
            "the NEES of the calibration states is undefined (covariance not positive definite)"
                .to_string(),
        ),
    }
    (!failures.is_empty()).then(|| failures.join("; "))
}

fn calibrate(
    scenario_path: Option<&Path>,
    out: Option<&Path>,
    json: bool,
    check: bool,
) -> Result<(), Failure> {
    let scenario = load(scenario_path)?;
    if let Some(directory) = out {
        prepare_outputs(
            directory,
            &report::output_files(directory),
            &inputs(scenario_path),
        )?;
    }
    let nees_bound = calibration_nees_bound()?;
    let bar = progress_bar(scenario.frame_count(), "calibrate");
    if json {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let started = std::time::Instant::now();
    let result = flight::fly(&scenario, FlightOptions::default(), |done, _| {
        bar.set_position(done)
    })?;
    bar.finish_and_clear();
    let history = history(&result);
    let last = history.last().ok_or("the scenario has no frames")?;
    let table = CalibrationResult::from_sample(last, &Parameter::CALIBRATION);
    let nees = result.calibration_nees();
    if json {
        println!("{}", table.report_json(nees, &result.health)?);
    } else {
        println!(
            "{} frames ({:.0} s of flight) through nav-fsw in {:.2?}",
            result.frames,
            result.frames as f64 * scenario.imu.frame_period_s(),
            started.elapsed()
        );
        println!("{}", report::summary(&table));
        if let Some(nees) = nees {
            println!(
                "NEES of the 15 calibration states at the end: {nees:.1} (χ²(15): mean 15, 95 % below {nees_bound:.1})"
            );
        }
        println!("health: {:?}", result.health);
    }
    if let Some(directory) = out {
        let csv = report::write_time_histories(directory, &history)?;
        let png = report::write_plots(directory, &history)?;
        if !json {
            println!(
                "wrote {} CSV files and {} plots into {}",
                csv.len(),
                png.len(),
                directory.display()
            );
        }
    }
    if check {
        if let Some(failures) = calibration_failures(&table, nees, nees_bound) {
            return Err(format!("calibrate --check: {failures}").into());
        }
    }
    Ok(())
}

/// The arguments of `nav-sim monte-carlo`.
struct MonteCarloArgs<'a> {
    scenario_path: Option<&'a Path>,
    runs: u64,
    shard: Option<nav_sim::campaign::Shard>,
    run: Option<u64>,
    out: Option<&'a Path>,
    json: bool,
    check: bool,
}

fn monte_carlo(arguments: MonteCarloArgs<'_>) -> Result<(), Failure> {
    use nav_sim::campaign;
    let scenario_path = arguments.scenario_path;
    let scenario = load(scenario_path)?;
    if let Some(run) = arguments.run {
        let records = campaign::fly_runs(&scenario, &[run], false)?;
        for record in records {
            println!("{}", record.json_line()?);
        }
        return Ok(());
    }
    if let (Some(shard), Some(directory)) = (arguments.shard, arguments.out) {
        let (path, runs) = campaign::write_shard(
            &scenario,
            scenario_path,
            arguments.runs,
            shard,
            directory,
            true,
        )?;
        println!("wrote {runs} runs to {}", path.display());
        return Ok(());
    }
    if let Some(directory) = arguments.out {
        prepare_outputs(
            directory,
            &campaign_plots(directory),
            &inputs(scenario_path),
        )?;
    }
    let runs: Vec<u64> = (0..arguments.runs).collect();
    let records = campaign::fly_runs(&scenario, &runs, !arguments.json)?;
    let label = scenario_path.map(|path| path.display().to_string());
    let report = campaign::CampaignReport::new(&records, label.as_deref())?;
    print_campaign(&report, arguments.json)?;
    if let Some(directory) = arguments.out {
        write_campaign_plots(&report, directory, arguments.json)?;
    }
    check_campaign(&report, arguments.check, "monte-carlo")
}

/// The plots `monte-carlo --out DIR` and `merge --out DIR` write: the NEES / RMS per run and
/// the consistency over time.
fn campaign_plots(directory: &Path) -> [PathBuf; 2] {
    [
        directory.join("monte_carlo.png"),
        directory.join("nees_over_time.png"),
    ]
}

fn write_campaign_plots(
    report: &nav_sim::campaign::CampaignReport,
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

fn print_campaign(report: &nav_sim::campaign::CampaignReport, json: bool) -> Result<(), Failure> {
    if json {
        println!("{}", report.json()?);
    } else {
        print!("{}", report.text());
    }
    Ok(())
}

fn check_campaign(
    report: &nav_sim::campaign::CampaignReport,
    check: bool,
    command: &str,
) -> Result<(), Failure> {
    match report.check_failure() {
        Some(failure) if check => Err(format!("{command} --check: {failure}").into()),
        _ => Ok(()),
    }
}

fn merge(paths: &[PathBuf], out: Option<&Path>, json: bool, check: bool) -> Result<(), Failure> {
    if let Some(directory) = out {
        let inputs: Vec<&Path> = paths.iter().map(PathBuf::as_path).collect();
        prepare_outputs(directory, &campaign_plots(directory), &inputs)?;
    }
    let merged = nav_sim::campaign::merge(paths)?;
    let report =
        nav_sim::campaign::CampaignReport::new(&merged.records, merged.scenario.as_deref())?;
    print_campaign(&report, json)?;
    if let Some(directory) = out {
        write_campaign_plots(&report, directory, json)?;
    }
    check_campaign(&report, check, "merge")
}

fn write_log(scenario_path: Option<&Path>, out: &Path) -> Result<(), Failure> {
    let mut file = OutputFile::create_distinct(out, &inputs(scenario_path))?;
    let scenario = load(scenario_path)?;
    let rows = nav_sim::logs::sensor_log::record_simulation(
        nav_sim::Simulation::new(&scenario)?,
        &mut file,
    )?;
    file.commit()?;
    println!("wrote {rows} sensor events to {}", out.display());
    Ok(())
}

fn replay(log: &Path, scenario_path: Option<&Path>, out: &Path) -> Result<(), Failure> {
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

fn faults(scenario: Option<&Path>) -> Result<(), Failure> {
    let scenario = load(scenario)?;
    let total = nav_sim::studies::faults::campaign().len() as u64;
    let bar = ProgressBar::new(total);
    bar.set_message("fault classes");
    let result =
        nav_sim::studies::faults::run_campaign(&scenario, |done, _| bar.set_position(done))?;
    bar.finish_and_clear();
    println!("{}", result.table());
    println!("{}", result.summary_line());
    if result.all_met() {
        Ok(())
    } else {
        Err("fault campaign: a row is not met".into())
    }
}

fn target_bench(
    scenario: Option<&Path>,
    elf: &Path,
    seconds: u64,
    runner: &Path,
    out: &Path,
) -> Result<(), Failure> {
    let scenario = load(scenario)?;
    let report =
        nav_sim::harness::target_replay::replay_on_target(&scenario, seconds, elf, runner, out)?;
    let text = report.text();
    print!("{text}");
    let path = out.join("target-bench-report.txt");
    let mut file = OutputFile::create(&path)?;
    file.write_all(text.as_bytes())?;
    file.commit()?;
    println!("report written to {}", path.display());
    if let Some(difference) = report.difference {
        return Err(format!("host and target differ first at {difference:?}").into());
    }
    Ok(())
}

fn benefit(arguments: &nav_sim::studies::benefit::BenefitArgs) -> Result<(), Failure> {
    let scenario = load(arguments.scenario.as_deref())?;
    // A bad --out fails now, not after the flights.
    if let Some(directory) = arguments.out.as_deref() {
        output::prepare_directory(directory)?;
    }
    let options = arguments.options();
    print!(
        "{}",
        nav_sim::studies::benefit::run(&scenario, &options, arguments.out.as_deref(), true)?
    );
    Ok(())
}

fn design(arguments: &nav_sim::studies::manoeuvre_design::DesignArgs) -> Result<(), Failure> {
    arguments.run().map_err(Failure::from)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command.unwrap_or(Command::Calibrate {
        scenario: None,
        out: None,
        json: false,
        check: false,
    }) {
        Command::Calibrate {
            scenario,
            out,
            json,
            check,
        } => calibrate(scenario.as_deref(), out.as_deref(), json, check),
        Command::MonteCarlo {
            scenario,
            runs,
            shard,
            run,
            out,
            json,
            check,
        } => monte_carlo(MonteCarloArgs {
            scenario_path: scenario.as_deref(),
            runs,
            shard,
            run,
            out: out.as_deref(),
            json,
            check,
        }),
        Command::Merge {
            paths,
            out,
            json,
            check,
        } => merge(&paths, out.as_deref(), json, check),
        Command::Log { scenario, out } => write_log(scenario.as_deref(), &out),
        Command::Replay { log, scenario, out } => replay(&log, scenario.as_deref(), &out),
        Command::Scenario => {
            print!("{}", nav_sim::scenario::DEFAULT_SCENARIO_TOML);
            Ok(())
        }
        Command::Faults { scenario } => faults(scenario.as_deref()),
        Command::Observability(arguments) => arguments.run().map_err(Failure::from),
        Command::Design(arguments) => design(&arguments),
        Command::TargetBench {
            scenario,
            elf,
            seconds,
            runner,
            out,
        } => target_bench(scenario.as_deref(), &elf, seconds, &runner, &out),
        Command::Benefit(arguments) => benefit(&arguments),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("nav-sim: {error}");
            ExitCode::FAILURE
        }
    }
}
