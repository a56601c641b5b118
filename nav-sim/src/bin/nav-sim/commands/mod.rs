//! The subcommands of `nav-sim`, one file each (its `Args` and `run`), and what they share:
//! the [`Failure`] type, loading a scenario, checking outputs before a run and the progress
//! bars on standard error.

use std::path::{Path, PathBuf};

use indicatif::{ProgressBar, ProgressStyle};
use nav_sim::output;
use nav_sim::output::scenario_label::ScenarioLabel;
use nav_sim::Scenario;

pub mod benefit;
pub mod calibrate;
pub mod design;
pub mod false_alarms;
pub mod faults;
pub mod gravity_omission;
pub mod ground_constants;
pub mod log;
pub mod merge;
pub mod monte_carlo;
pub mod observability;
pub mod replay;
pub mod scenario;
pub mod target_bench;
pub mod telemetry;

/// Why a subcommand failed; `main` prints it with `Display` after `nav-sim: `.
pub type Failure = Box<dyn std::error::Error>;

/// `--runs` of `monte-carlo` and `benefit`: a whole number of runs in
/// 1..=[`nav_sim::campaign::MAX_RUNS`] (clap names the flag and the value).
pub fn parse_runs(text: &str) -> Result<u64, String> {
    let max = nav_sim::campaign::MAX_RUNS;
    text.parse::<u64>()
        .ok()
        .filter(|runs| (1..=max).contains(runs))
        .ok_or_else(|| format!("expected a whole number of runs in 1..={max}"))
}

/// The scenario at `scenario`, or the built-in one.
pub fn load(scenario: Option<&Path>) -> Result<Scenario, Failure> {
    Ok(match scenario {
        Some(path) => Scenario::load(path)?,
        None => Scenario::default_scenario()?,
    })
}

/// The scenario at `scenario`, or the built-in one, and the label the outputs name it by
/// (the file and its resolved SHA-256).
pub fn load_labelled(scenario: Option<&Path>) -> Result<(Scenario, ScenarioLabel), Failure> {
    let (loaded, resolved) = match scenario {
        Some(path) => Scenario::load_resolved(path)?,
        None => Scenario::default_resolved()?,
    };
    let file = scenario.map(|path| path.display().to_string());
    let origin = file
        .as_deref()
        .unwrap_or(nav_sim::scenario::overlay::DEFAULT_ORIGIN);
    let sha256 = Some(resolved.sha256(origin)?);
    Ok((loaded, ScenarioLabel { file, sha256 }))
}

/// The scenario file as the input list of a command (the built-in one has none).
pub fn inputs(scenario: Option<&Path>) -> Vec<&Path> {
    scenario.into_iter().collect()
}

/// `--results DIR` of the measuring commands: the measured tables to write as a results file
/// (`docs/results/` holds the committed ones, which the documentation includes).
#[derive(clap::Args, Default)]
pub struct ResultsArg {
    /// Also write the measured table (without timings) as the results file
    /// DIR/<command>-<scenario>.md, headed by the command line that wrote it.
    #[arg(long, value_name = "DIR")]
    results: Option<PathBuf>,
}

impl ResultsArg {
    /// Writes `body` as the results file of `command` flown on `scenario` (the built-in one:
    /// `default`) if `--results` was given, and says where.
    pub fn write(&self, command: &str, scenario: Option<&Path>, body: &str) -> Result<(), Failure> {
        let Some(directory) = self.results.as_deref() else {
            return Ok(());
        };
        let stem = scenario
            .and_then(Path::file_stem)
            .map_or_else(|| "default".into(), |stem| stem.to_string_lossy());
        let name = format!("{command}-{stem}.md");
        let written = output::results::write(directory, &name, &command_line(), body)?;
        eprintln!("results written to {}", written.display());
        Ok(())
    }
}

/// This process's command line without `--results DIR`, as a results file's header names it.
fn command_line() -> String {
    let mut words = vec!["nav-sim".to_string()];
    let mut arguments = std::env::args().skip(1);
    while let Some(argument) = arguments.next() {
        if argument == "--results" {
            arguments.next();
        } else if !argument.starts_with("--results=") {
            words.push(argument);
        }
    }
    words.join(" ")
}

/// Checks an output directory and the files a command writes into it before the run, so a
/// bad `--out` fails at once rather than after the flight.
pub fn prepare_outputs(
    directory: &Path,
    files: &[PathBuf],
    inputs: &[&Path],
) -> Result<(), Failure> {
    for file in files {
        output::refuse_inputs(file, inputs)?;
    }
    output::prepare_directory(directory)?;
    Ok(())
}

/// A progress bar over the `total` frames of one flight: `{message} [bar] done/total frames
/// (eta left)`.
pub fn frame_bar(total: u64, message: &'static str) -> ProgressBar {
    let bar = ProgressBar::new(total);
    if let Ok(style) =
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} frames ({eta} left)")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(message);
    bar
}

/// A progress bar over `count` items of a parallel campaign (`{message} [elapsed] bar
/// done/count {unit}`), hidden unless `show`; the campaign advances it through its progress
/// callback (`&|| bar.inc(1)`).
pub fn campaign_bar(count: usize, message: &'static str, unit: &str, show: bool) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(u64::try_from(count).unwrap_or(u64::MAX));
    let template = format!("{{msg}} [{{elapsed_precise}}] {{wide_bar}} {{pos}}/{{len}} {unit}");
    if let Ok(style) = ProgressStyle::with_template(&template) {
        bar.set_style(style);
    }
    bar.set_message(message);
    bar
}
