//! What the on-line calibration buys: the navigation error through a long aiding outage after
//! the calibration flight, with the calibration and without it (`nav-sim benefit`).
//!
//! The outage flight is the scenario (the calibration flight) with a coast appended
//! ([`OutagePlan::coast_s`], no thrust and the small body rate of the scenarios' quiet coasts)
//! and, from the end of the calibration flight, a GNSS outage and a star-tracker outage
//! ([`outage_scenario`]). It is flown twice through the flight software on the same sensor data
//! (same scenario, same seed):
//!
//! * **calibrated**: the flight software as configured, its 24-state filter estimating the
//!   star-sensor installation error and the gyro and accelerometer scale factors;
//! * **uncalibrated**: the calibration switched off. The installation error and both scale
//!   factors start with a 1σ of [`SWITCHED_OFF_SIGMA`] (and the same covariance floor), so the
//!   filter never moves them: they are held at zero and the sensors are used uncorrected, as a
//!   plain 15-state INS/star/GNSS filter (attitude, position, velocity, gyro and accelerometer
//!   bias) uses them. The flight software is unchanged; only its configuration differs
//!   ([`uncalibrated_config`]). The truth keeps the sensors' scale-factor and installation
//!   errors, so this filter is overconfident by design: its health counters (gate rejections,
//!   sensors declared faulty) and its error / 1σ are reported beside its errors.
//!
//! The errors are the magnitudes of estimate − truth (position, velocity, and the attitude as
//! a rotation angle), recorded every second from the start of the outage. A Monte Carlo
//! ([`compare`] with several seeds) flies both filters per seed in parallel (rayon) and reports
//! the mean and the range over the runs ([`Spread`]).

use std::fmt::Write as _;
use std::path::Path;

use comfy_table::{presets::UTF8_FULL_CONDENSED, Cell, CellAlignment, Table};
use nalgebra::Vector3;
use nav_fsw::config::FswConfig;
use nav_fsw::health::HealthCounters;
use rayon::prelude::*;

use crate::harness::flight::{self, FlightError, FlightOptions, FlightSample};
use crate::output::report::ReportError;
use crate::scenario::{ManoeuvreSegment, Scenario, ScenarioError};

mod plot;

pub use plot::plot;

/// Initial 1σ and covariance floor of the switched-off calibration states (installation error
/// in rad, scale factors dimensionless): positive, as the flight software's configuration check
/// requires, and small enough that no update moves the states.
pub const SWITCHED_OFF_SIGMA: f64 = 1.0e-12;

/// Body rate of the outage coast (deg/s per axis): the quiet-coast rate of the scenarios'
/// coasts, so the coast commands the same phase.
pub const COAST_BODY_RATE_DEG_PER_S: [f64; 3] = [2.4e-4; 3];

/// Times into the outage at which the table reports the errors (s); those beyond the coast
/// are left out, and the coast's end is added when it is not among them.
pub const TABLE_TIMES_S: [f64; 6] = [0.0, 60.0, 300.0, 600.0, 1200.0, 1800.0];

/// Interval between the recorded error samples (s).
const RECORD_INTERVAL_S: f64 = 1.0;

/// Which filter a flight uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Filter {
    /// The flight software as configured (on-line calibration on).
    Calibrated,
    /// Installation error and scale factors held at zero (a 15-state filter).
    Uncalibrated,
}

impl Filter {
    /// Both, calibrated first.
    pub const BOTH: [Filter; 2] = [Filter::Calibrated, Filter::Uncalibrated];

    /// Name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Filter::Calibrated => "calibrated",
            Filter::Uncalibrated => "uncalibrated",
        }
    }
}

/// The outage after the calibration flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutagePlan {
    /// Length of the coast appended to the scenario (s), > 0, a whole number of IMU frames.
    pub coast_s: f64,
    /// GNSS outage from the end of the calibration flight (s), ≥ 0 (0 = none).
    pub gnss_outage_s: f64,
    /// Star-tracker outage from the end of the calibration flight (s), ≥ 0 (0 = none).
    pub star_outage_s: f64,
}

impl Default for OutagePlan {
    /// GNSS lost for 30 min and the star tracker for 10 min; the coast lasts as long as the
    /// GNSS outage.
    fn default() -> Self {
        Self {
            coast_s: 1800.0,
            gnss_outage_s: 1800.0,
            star_outage_s: 600.0,
        }
    }
}

/// Why the comparison could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenefitError {
    /// The extended scenario is not valid.
    #[error("outage scenario: {0}")]
    Scenario(#[from] ScenarioError),
    /// An outage setting is out of range.
    #[error("{key} {requirement}")]
    Setting {
        /// The option.
        key: &'static str,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// A flight failed.
    #[error("{filter} flight with seed {seed}: {source}")]
    Flight {
        /// The filter flown.
        filter: &'static str,
        /// The run's seed.
        seed: u64,
        /// The flight's error.
        source: FlightError,
    },
    /// A flight recorded nothing from the outage's start on.
    #[error("the {0} flight recorded no sample in the outage")]
    NoOutageSamples(&'static str),
    /// No runs were asked for.
    #[error("no runs")]
    NoRuns,
    /// The plot could not be written.
    #[error(transparent)]
    Report(#[from] ReportError),
}

/// The scenario with the outage coast appended and the GNSS and star-tracker outages starting
/// at the end of its manoeuvres (after any outages the scenario has), validated.
///
/// # Errors
/// [`BenefitError::Setting`] for a coast that is not positive or a negative outage;
/// [`BenefitError::Scenario`] if the extended scenario is refused (e.g. the coast is not a
/// whole number of IMU frames, or the orbit decays below the minimum altitude).
pub fn outage_scenario(scenario: &Scenario, plan: &OutagePlan) -> Result<Scenario, BenefitError> {
    if !(plan.coast_s.is_finite() && plan.coast_s > 0.0) {
        return Err(BenefitError::Setting {
            key: "--coast-s",
            requirement: "must be > 0",
        });
    }
    for (key, value) in [
        ("--gnss-outage-s", plan.gnss_outage_s),
        ("--star-outage-s", plan.star_outage_s),
    ] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(BenefitError::Setting {
                key,
                requirement: "must be >= 0",
            });
        }
    }
    let calibration_end_s = scenario.duration_s();
    let mut extended = scenario.clone();
    extended.manoeuvres.push(ManoeuvreSegment {
        label: "outage coast".to_string(),
        duration_s: plan.coast_s,
        ramp_s: 0.0,
        body_rate_deg_per_s: COAST_BODY_RATE_DEG_PER_S,
        specific_force_mps2: [0.0; 3],
    });
    if plan.gnss_outage_s > 0.0 {
        extended
            .gnss
            .outages
            .push([calibration_end_s, plan.gnss_outage_s]);
    }
    if plan.star_outage_s > 0.0 {
        extended
            .star_sensor
            .outages
            .push([calibration_end_s, plan.star_outage_s]);
    }
    extended.validate()?;
    Ok(extended)
}

/// The flight-software configuration with the calibration switched off: the initial 1σ and the
/// covariance floor of the star-sensor installation error and of both scale factors set to
/// [`SWITCHED_OFF_SIGMA`], everything else as [`crate::setup::fsw::fsw_config`] gives it.
///
/// # Errors
/// As [`crate::setup::fsw::fsw_config`].
pub fn uncalibrated_config(scenario: &Scenario) -> Result<FswConfig, FlightError> {
    let mut config = crate::setup::fsw::fsw_config(scenario)?;
    for sigma in [
        &mut config.filter.initial,
        &mut config.covariance.sigma_floor,
    ] {
        sigma.star_installation_rad = SWITCHED_OFF_SIGMA;
        sigma.gyro_scale_factor = SWITCHED_OFF_SIGMA;
        sigma.accel_scale_factor = SWITCHED_OFF_SIGMA;
    }
    Ok(config)
}

/// The navigation error at one instant of the outage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutageSample {
    /// Time since the outage's start (s).
    pub time_into_outage_s: f64,
    /// |estimated − true position| (m).
    pub position_error_m: f64,
    /// |estimated − true velocity| (m/s).
    pub velocity_error_mps: f64,
    /// Attitude error as a rotation angle (rad).
    pub attitude_error_rad: f64,
    /// The filter's position 1σ, `√(tr P)` of the position block (m).
    pub position_sigma_m: f64,
    /// The filter's velocity 1σ, `√(tr P)` of the velocity block (m/s).
    pub velocity_sigma_mps: f64,
    /// The filter's attitude 1σ as an angle, root sum of squares over the axes (rad).
    pub attitude_sigma_rad: f64,
}

impl OutageSample {
    fn new(sample: &FlightSample, outage_start_s: f64) -> Self {
        let norm = |values: [f64; 3]| Vector3::from(values).norm();
        Self {
            time_into_outage_s: sample.time_s - outage_start_s,
            position_error_m: norm(sample.position_error_m),
            velocity_error_mps: norm(sample.velocity_error_mps),
            attitude_error_rad: norm(sample.attitude_error_rad),
            position_sigma_m: norm(sample.position_sigma_m),
            velocity_sigma_mps: norm(sample.velocity_sigma_mps),
            attitude_sigma_rad: norm(sample.attitude_sigma_rad),
        }
    }

    /// The value of one quantity.
    pub fn error(&self, quantity: Quantity) -> f64 {
        match quantity {
            Quantity::Position => self.position_error_m,
            Quantity::Velocity => self.velocity_error_mps,
            Quantity::Attitude => self.attitude_error_rad,
        }
    }

    /// The filter's 1σ of one quantity.
    pub fn sigma(&self, quantity: Quantity) -> f64 {
        match quantity {
            Quantity::Position => self.position_sigma_m,
            Quantity::Velocity => self.velocity_sigma_mps,
            Quantity::Attitude => self.attitude_sigma_rad,
        }
    }
}

/// The navigation quantities compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// Position error (m).
    Position,
    /// Velocity error (m/s).
    Velocity,
    /// Attitude error (rad; reported in mrad).
    Attitude,
}

impl Quantity {
    /// All three, in report order.
    pub const ALL: [Quantity; 3] = [Quantity::Position, Quantity::Velocity, Quantity::Attitude];

    /// Name and unit in reports.
    pub fn label(self) -> &'static str {
        match self {
            Quantity::Position => "position error (m)",
            Quantity::Velocity => "velocity error (m/s)",
            Quantity::Attitude => "attitude error (mrad)",
        }
    }

    /// Factor from the SI value to the reported unit.
    pub fn report_scale(self) -> f64 {
        match self {
            Quantity::Attitude => 1.0e3,
            Quantity::Position | Quantity::Velocity => 1.0,
        }
    }
}

/// One filter's flight through the outage.
#[derive(Debug, Clone)]
pub struct OutageRun {
    /// The run's seed.
    pub seed: u64,
    /// The filter flown.
    pub filter: Filter,
    /// Errors every second from the outage's start to the end of the coast.
    pub samples: Vec<OutageSample>,
    /// Health counters at the end of the flight.
    pub health: HealthCounters,
    /// Frames flown (calibration flight and coast).
    pub frames: u64,
}

impl OutageRun {
    /// The sample nearest to `time_into_outage_s` (`None` if the time is more than one record
    /// interval beyond the recorded samples).
    pub fn at(&self, time_into_outage_s: f64) -> Option<&OutageSample> {
        let last = self.samples.last()?;
        if time_into_outage_s > last.time_into_outage_s + RECORD_INTERVAL_S {
            return None;
        }
        self.samples.iter().min_by(|a, b| {
            let distance = |s: &OutageSample| (s.time_into_outage_s - time_into_outage_s).abs();
            distance(a).total_cmp(&distance(b))
        })
    }

    /// The largest error of `quantity` over the outage (0 without samples).
    pub fn max(&self, quantity: Quantity) -> f64 {
        self.samples
            .iter()
            .map(|sample| sample.error(quantity))
            .fold(0.0, f64::max)
    }
}

/// The configuration with the innovation gates open and no sensor ever declared faulty: every
/// measurement is fused, so an overconfident filter keeps its aiding sensors.
pub fn with_open_gates(mut config: FswConfig) -> FswConfig {
    config.star.gate_nis = f64::INFINITY;
    config.gnss.gate_nis = f64::INFINITY;
    config.gnss.velocity_gate_nis = f64::INFINITY;
    config.timing.rejections_to_declare_faulty = u32::MAX;
    config
}

/// Flies the outage scenario (from [`outage_scenario`]) with one filter (its gates open if
/// `open_gates`, [`with_open_gates`]) and keeps the errors from the start of the outage,
/// `calibration_duration_s` after the scenario start.
///
/// # Errors
/// [`BenefitError::Flight`] if the flight fails, [`BenefitError::NoOutageSamples`] if it
/// recorded nothing in the outage.
pub fn fly_outage(
    outage: &Scenario,
    calibration_duration_s: f64,
    filter: Filter,
    open_gates: bool,
    progress: impl FnMut(u64, u64),
) -> Result<OutageRun, BenefitError> {
    let seed = outage.simulation.seed;
    let failed = |source| BenefitError::Flight {
        filter: filter.name(),
        seed,
        source,
    };
    let config = match filter {
        Filter::Calibrated => crate::setup::fsw::fsw_config(outage).map_err(FlightError::from),
        Filter::Uncalibrated => uncalibrated_config(outage),
    }
    .map_err(failed)?;
    let config = if open_gates {
        with_open_gates(config)
    } else {
        config
    };
    let options = FlightOptions {
        record_interval_s: RECORD_INTERVAL_S,
    };
    let result = flight::fly_with(outage, config, options, progress, |_, _| {}).map_err(failed)?;
    let outage_start_s = outage.simulation.start_time_s + calibration_duration_s;
    let samples: Vec<OutageSample> = result
        .samples
        .iter()
        .filter(|sample| sample.time_s >= outage_start_s - 0.5 * RECORD_INTERVAL_S)
        .map(|sample| OutageSample::new(sample, outage_start_s))
        .collect();
    if samples.is_empty() {
        return Err(BenefitError::NoOutageSamples(filter.name()));
    }
    Ok(OutageRun {
        seed,
        filter,
        samples,
        health: result.health,
        frames: result.frames,
    })
}

/// Both filters on one seed's sensor data.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// With the on-line calibration.
    pub calibrated: OutageRun,
    /// Without it.
    pub uncalibrated: OutageRun,
}

impl Comparison {
    /// The run of `filter`.
    pub fn run(&self, filter: Filter) -> &OutageRun {
        match filter {
            Filter::Calibrated => &self.calibrated,
            Filter::Uncalibrated => &self.uncalibrated,
        }
    }

    /// Calibrated / uncalibrated ratio of the largest error of `quantity` over the outage.
    pub fn max_ratio(&self, quantity: Quantity) -> f64 {
        self.calibrated.max(quantity) / self.uncalibrated.max(quantity)
    }
}

/// How a comparison is run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BenefitOptions {
    /// The outage.
    pub plan: OutagePlan,
    /// Number of runs (seeds: the scenario's seed, +1, +2, ...), ≥ 1.
    pub runs: u64,
    /// Draw each run's sensor-error truth from the filter's prior
    /// ([`crate::setup::prior::with_truth_drawn_from_prior`]) instead of keeping the scenario's.
    pub draw_truth: bool,
    /// Fly both filters with their innovation gates open and no sensor declared faulty
    /// ([`with_open_gates`]).
    pub open_gates: bool,
}

/// Flies both filters for every seed, in parallel (rayon, one task per seed and filter),
/// calling `progress` once per finished flight (from the rayon workers; `&|| {}` for none).
/// Comparisons come in seed order.
///
/// # Errors
/// [`BenefitError::NoRuns`], any error of [`outage_scenario`], or the first failed flight
/// ([`fly_outage`]) in seed order.
pub fn compare(
    scenario: &Scenario,
    options: &BenefitOptions,
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<Comparison>, BenefitError> {
    if options.runs == 0 {
        return Err(BenefitError::NoRuns);
    }
    let calibration_duration_s = scenario.duration_s();
    let outage = outage_scenario(scenario, &options.plan)?;
    let jobs: Vec<(u64, Filter)> = (0..options.runs)
        .map(|run| scenario.simulation.seed.wrapping_add(run))
        .flat_map(|seed| Filter::BOTH.map(|filter| (seed, filter)))
        .collect();
    let runs: Vec<Result<OutageRun, BenefitError>> = jobs
        .par_iter()
        .map(|&(seed, filter)| {
            let seeded = if options.draw_truth {
                crate::setup::prior::with_truth_drawn_from_prior(&outage, seed)
            } else {
                let mut seeded = outage.clone();
                seeded.simulation.seed = seed;
                seeded
            };
            let run = fly_outage(
                &seeded,
                calibration_duration_s,
                filter,
                options.open_gates,
                |_, _| {},
            );
            progress();
            run
        })
        .collect();
    let mut runs = runs.into_iter();
    let mut comparisons = Vec::new();
    while let (Some(calibrated), Some(uncalibrated)) = (runs.next(), runs.next()) {
        comparisons.push(Comparison {
            calibrated: calibrated?,
            uncalibrated: uncalibrated?,
        });
    }
    Ok(comparisons)
}

/// Mean and range of a value over the runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    /// Mean.
    pub mean: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
}

impl Spread {
    /// The spread of `values` (NaN fields without values).
    pub fn of(values: impl IntoIterator<Item = f64>) -> Self {
        let (count, sum, min, max) = values.into_iter().fold(
            (0u32, 0.0, f64::INFINITY, f64::NEG_INFINITY),
            |(count, sum, min, max), value| {
                (count + 1, sum + value, min.min(value), max.max(value))
            },
        );
        if count == 0 {
            return Self {
                mean: f64::NAN,
                min: f64::NAN,
                max: f64::NAN,
            };
        }
        Self {
            mean: sum / f64::from(count),
            min,
            max,
        }
    }

    /// `mean` alone for one run, `mean [min, max]` for several, each times `scale`.
    fn cell(&self, scale: f64, runs: usize) -> String {
        if runs <= 1 {
            significant(scale * self.mean)
        } else {
            format!(
                "{} [{}, {}]",
                significant(scale * self.mean),
                significant(scale * self.min),
                significant(scale * self.max)
            )
        }
    }
}

/// Three significant digits, in scientific notation outside [0.01, 10⁵).
fn significant(value: f64) -> String {
    let magnitude = value.abs();
    if magnitude == 0.0 || (1e-2..1e5).contains(&magnitude) {
        let decimals = if magnitude >= 100.0 {
            0
        } else if magnitude >= 10.0 {
            1
        } else if magnitude >= 1.0 {
            2
        } else {
            3
        };
        format!("{value:.decimals$}")
    } else {
        format!("{value:.2e}")
    }
}

/// The table's times: [`TABLE_TIMES_S`] within the coast, and the coast's end.
pub fn table_times_s(coast_s: f64) -> Vec<f64> {
    let mut times: Vec<f64> = TABLE_TIMES_S
        .iter()
        .copied()
        .filter(|time_s| *time_s <= coast_s + 1e-9)
        .collect();
    if times
        .last()
        .is_none_or(|last| (coast_s - last).abs() > RECORD_INTERVAL_S)
    {
        times.push(coast_s);
    }
    times
}

/// Row of a quantity's table: where (a time into the outage, or the maximum) and the spread of
/// each filter's error there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// Time into the outage (s); `None` for the maximum over the outage.
    pub time_into_outage_s: Option<f64>,
    /// Calibrated filter's error over the runs (SI units).
    pub calibrated: Spread,
    /// Uncalibrated filter's error over the runs.
    pub uncalibrated: Spread,
}

impl Row {
    /// Ratio of the mean errors, calibrated / uncalibrated.
    pub fn ratio(&self) -> f64 {
        self.calibrated.mean / self.uncalibrated.mean
    }
}

/// The rows of one quantity: one per table time, then the maximum over the outage.
pub fn rows(comparisons: &[Comparison], quantity: Quantity, coast_s: f64) -> Vec<Row> {
    let spread_at = |filter: Filter, time_s: f64| {
        Spread::of(comparisons.iter().filter_map(|comparison| {
            comparison
                .run(filter)
                .at(time_s)
                .map(|sample| sample.error(quantity))
        }))
    };
    let spread_max = |filter: Filter| {
        Spread::of(
            comparisons
                .iter()
                .map(|comparison| comparison.run(filter).max(quantity)),
        )
    };
    let mut rows: Vec<Row> = table_times_s(coast_s)
        .into_iter()
        .map(|time_s| Row {
            time_into_outage_s: Some(time_s),
            calibrated: spread_at(Filter::Calibrated, time_s),
            uncalibrated: spread_at(Filter::Uncalibrated, time_s),
        })
        .collect();
    rows.push(Row {
        time_into_outage_s: None,
        calibrated: spread_max(Filter::Calibrated),
        uncalibrated: spread_max(Filter::Uncalibrated),
    });
    rows
}

/// The report of a comparison as text: one table per quantity (position, velocity, attitude),
/// the per-run ratios of the maxima, the health counters and the error / 1σ at the end.
pub fn text(comparisons: &[Comparison], plan: &OutagePlan) -> String {
    let runs = comparisons.len();
    let right = |text: String| Cell::new(text).set_alignment(CellAlignment::Right);
    let spread_heading = if runs > 1 {
        format!(" (mean [min, max] over {runs} runs)")
    } else {
        String::new()
    };
    let mut text = String::new();
    for quantity in Quantity::ALL {
        let mut table = Table::new();
        table.load_preset(UTF8_FULL_CONDENSED).set_header([
            "time into outage (s)".to_string(),
            format!("calibrated{spread_heading}"),
            format!("uncalibrated{spread_heading}"),
            "ratio cal/uncal".to_string(),
        ]);
        for row in rows(comparisons, quantity, plan.coast_s) {
            let scale = quantity.report_scale();
            table.add_row([
                right(
                    row.time_into_outage_s
                        .map_or("max".to_string(), |t| format!("{t:.0}")),
                ),
                right(row.calibrated.cell(scale, runs)),
                right(row.uncalibrated.cell(scale, runs)),
                right(significant(row.ratio())),
            ]);
        }
        let _ = writeln!(text, "{}\n{table}\n", quantity.label());
    }
    if runs > 1 {
        for quantity in Quantity::ALL {
            let ratios = Spread::of(comparisons.iter().map(|c| c.max_ratio(quantity)));
            let _ = writeln!(
                text,
                "per-run ratio of the maximum {}, calibrated / uncalibrated: mean {}, \
                 range [{}, {}]",
                quantity.label(),
                significant(ratios.mean),
                significant(ratios.min),
                significant(ratios.max)
            );
        }
    }
    for filter in Filter::BOTH {
        let health = |field: fn(&HealthCounters) -> u32| {
            let spread = Spread::of(
                comparisons
                    .iter()
                    .map(|c| f64::from(field(&c.run(filter).health))),
            );
            if runs <= 1 {
                format!("{:.0}", spread.mean)
            } else {
                format!("{:.1} [{:.0}, {:.0}]", spread.mean, spread.min, spread.max)
            }
        };
        let _ = writeln!(
            text,
            "{} health: star gate rejections {}, GNSS gate rejections {}, star declared \
             faulty {}, GNSS declared faulty {}, covariance clamps {}",
            filter.name(),
            health(|h| h.star_gate_rejections),
            health(|h| h.gnss_gate_rejections),
            health(|h| h.star_declared_faulty),
            health(|h| h.gnss_declared_faulty),
            health(|h| h.covariance_clamps),
        );
        let normalised = |quantity: Quantity| {
            Spread::of(comparisons.iter().filter_map(|c| {
                c.run(filter)
                    .samples
                    .last()
                    .map(|s| s.error(quantity) / s.sigma(quantity))
            }))
            .cell(1.0, runs)
        };
        let _ = writeln!(
            text,
            "{} error / filter 1σ at the outage's end: position {}, velocity {}, attitude {}",
            filter.name(),
            normalised(Quantity::Position),
            normalised(Quantity::Velocity),
            normalised(Quantity::Attitude),
        );
    }
    text
}

/// Runs the comparison and returns its report (a heading, [`text`], and the plot's path when
/// `out` is given, whose directory is created); `progress` is called once per finished flight
/// (two per run, from the rayon workers).
///
/// # Errors
/// Any error of [`compare`] or [`plot`]; [`BenefitError::Report`] if the directory cannot be
/// created.
pub fn run(
    scenario: &Scenario,
    options: &BenefitOptions,
    out: Option<&Path>,
    progress: &(dyn Fn() + Sync),
) -> Result<String, BenefitError> {
    let started = std::time::Instant::now();
    let comparisons = compare(scenario, options, progress)?;
    let plan = &options.plan;
    let frames: u64 = comparisons
        .iter()
        .map(|c| c.calibrated.frames + c.uncalibrated.frames)
        .sum();
    let mut report = format!(
        "calibration flight {:.0} s, then a {:.0} s coast with GNSS lost for {:.0} s and the \
         star tracker for {:.0} s from its start; {} run(s) from seed {}{}{}\n\
         calibrated: the 24-state filter; uncalibrated: star installation error and scale \
         factors held at zero (1σ {SWITCHED_OFF_SIGMA:e}), a 15-state filter on the same \
         sensor data\n{} flights, {frames} frames through nav-fsw in {:.1?}\n\n",
        scenario.duration_s(),
        plan.coast_s,
        plan.gnss_outage_s,
        plan.star_outage_s,
        comparisons.len(),
        scenario.simulation.seed,
        if options.draw_truth {
            ", sensor-error truth drawn from the prior"
        } else {
            ""
        },
        if options.open_gates {
            "; gates open, no sensor declared faulty"
        } else {
            ""
        },
        2 * comparisons.len(),
        started.elapsed(),
    );
    report.push_str(&text(&comparisons, plan));
    if let Some(directory) = out {
        std::fs::create_dir_all(directory).map_err(|source| ReportError::Io {
            path: directory.to_path_buf(),
            source,
        })?;
        let path = plot(&directory.join("benefit.png"), &comparisons)?;
        let _ = writeln!(report, "wrote {}", path.display());
    }
    Ok(report)
}
