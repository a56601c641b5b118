//! `nav-sim calibrate` (also `nav-sim` alone): one flight of the calibration scenario through
//! the flight software, its calibration table, NEES and health (and each optional state
//! block's final errors and NEES when the filter flies it), and `--check`.

use std::path::PathBuf;

use nav_sim::campaign::monte_carlo;
use nav_sim::campaign::optional_block_report::{flight_json, flight_text, ReportedBlock};
use nav_sim::harness::flight::{self, FlightOptions, FlightResult};
use nav_sim::output::report::{self, CalibrationResult, Parameter, TimeHistorySample};
use nav_sim::output::scenario_label::ScenarioLabel;
use statrs::distribution::{ChiSquared, ContinuousCDF};

use super::{frame_bar, inputs, load_labelled, prepare_outputs, Failure, ResultsArg};

/// The arguments of `nav-sim calibrate`.
#[derive(clap::Args, Default)]
pub struct Args {
    /// Scenario TOML (default: the built-in one; `nav-sim scenario` prints it).
    scenario: Option<PathBuf>,
    /// Write time-history CSVs and PNG plots into this directory.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print one JSON object: `{"scenario": {"file", "sha256"}, "rows": [...], "met": n,
    /// "nees": x, "health": {...}}`, with `imu_error` and `gnss_error` (`{"nees", "states"}`)
    /// when the filter flies them.
    #[arg(long)]
    json: bool,
    /// Exit non-zero if a parameter axis misses the paper's accuracy or the NEES of the
    /// calibration states is above its χ² 95 % bound.
    #[arg(long)]
    check: bool,
    #[command(flatten)]
    results: ResultsArg,
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

/// The JSON report: the calibration table's, with the optional state blocks the filter flies
/// (a flight without them prints the table's report untouched).
fn json_report(
    table: &CalibrationResult,
    nees: Option<f64>,
    result: &FlightResult,
    label: &ScenarioLabel,
) -> Result<String, Failure> {
    let text = table.report_json(nees, &result.health, label)?;
    if result.imu_error.is_none() && result.gnss_error.is_none() {
        return Ok(text);
    }
    let mut report: serde_json::Value = serde_json::from_str(&text)?;
    if let Some(object) = report.as_object_mut() {
        if let Some(imu_error) = &result.imu_error {
            let block = ReportedBlock::ImuError;
            object.insert(block.json_key().into(), flight_json(block, imu_error));
        }
        if let Some(gnss_error) = &result.gnss_error {
            let block = ReportedBlock::GnssError;
            object.insert(block.json_key().into(), flight_json(block, gnss_error));
        }
    }
    Ok(serde_json::to_string_pretty(&report)?)
}

/// The calibration table, the NEES of the calibration states and the health counters as
/// `calibrate` prints them (everything but the run time).
fn measured_text(
    table: &CalibrationResult,
    nees: Option<f64>,
    nees_bound: f64,
    result: &FlightResult,
) -> String {
    let mut text = format!("{}\n", report::summary(table));
    if let Some(nees) = nees {
        text += &format!(
            "NEES of the 15 calibration states at the end: {nees:.1} (χ²(15): mean 15, 95 % below {nees_bound:.1})\n"
        );
    }
    if let Some(imu_error) = &result.imu_error {
        text += &format!("{}\n", flight_text(ReportedBlock::ImuError, imu_error));
    }
    if let Some(gnss_error) = &result.gnss_error {
        text += &format!("{}\n", flight_text(ReportedBlock::GnssError, gnss_error));
    }
    text += &format!("{}\n", report::health_table(&result.health));
    if result.withheld_star_measurements > 0 {
        text += &format!(
            "star measurements of the additional star-tracker heads not handed to the \
             flight software (it fuses head 0, [star_sensor], only): {}\n",
            result.withheld_star_measurements
        );
    }
    text
}

/// Flies the scenario, prints the calibration (text or JSON), writes the time histories and
/// plots if asked, and fails under `--check` if the calibration misses.
pub fn run(args: Args) -> Result<(), Failure> {
    let scenario_path = args.scenario.as_deref();
    let out = args.out.as_deref();
    let json = args.json;
    let (scenario, label) = load_labelled(scenario_path)?;
    nav_sim::setup::fsw::check_flight_star_heads(&scenario)?;
    if let Some(directory) = out {
        prepare_outputs(
            directory,
            &report::output_files(directory),
            &inputs(scenario_path),
        )?;
    }
    let nees_bound = calibration_nees_bound()?;
    let bar = frame_bar(scenario.frame_count(), "calibrate");
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
    let measured = measured_text(&table, nees, nees_bound, &result);
    if json {
        println!("{}", json_report(&table, nees, &result, &label)?);
    } else {
        println!("{}", label.line());
        println!(
            "{} frames ({:.0} s of flight) through nav-fsw in {:.2?}",
            result.frames,
            result.frames as f64 * scenario.imu.frame_period_s(),
            started.elapsed()
        );
        print!("{measured}");
    }
    args.results.write("calibrate", scenario_path, &measured)?;
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
    if args.check {
        if let Some(failures) = calibration_failures(&table, nees, nees_bound) {
            return Err(format!("calibrate --check: {failures}").into());
        }
    }
    Ok(())
}
