//! Monte Carlo statistics of the calibration states: runs a scenario over many seeds in
//! parallel and checks the filter's consistency, i.e. that its covariance describes its actual
//! errors (Bar-Shalom, Li & Kirubarajan, *Estimation with Applications to Tracking and
//! Navigation*, 2001, §5.4.2: the NEES test).
//!
//! For run `i` with final calibration error `eᵢ = x̂ᵢ − xᵢ` (n states) and filter covariance
//! `Pᵢ`, the normalised estimation error squared is `εᵢ = eᵢᵀ Pᵢ⁻¹ eᵢ`. If the filter is
//! consistent, `εᵢ ~ χ²(n)` and the average over N independent runs satisfies
//! `N·ε̄ ~ χ²(N n)`, so the two-sided 95% acceptance interval of `ε̄` is
//! `[χ²⁻¹(0.025; N n) / N, χ²⁻¹(0.975; N n) / N]` (statrs' χ² quantiles).
//!
//! Per state the statistics are the RMS error `√(mean eᵢ²)` and the mean filter 1σ
//! `mean √Pᵢ,jj`; for a consistent filter their ratio is near 1.
//!
//! The calibration states are nav-core's five calibration blocks (`nav_core::state::
//! StateBlock::CALIBRATION`), 5 × 3 = [`CALIBRATION_STATES`] = 15 states; the functions are generic
//! in the dimension `n` so any sub-state can be tested.

use comfy_table::{presets::UTF8_FULL_CONDENSED, Cell, CellAlignment, Table};
use nalgebra::{SMatrix, SVector};
use rayon::prelude::*;
use statrs::distribution::{ChiSquared, ContinuousCDF};

use crate::output::report::{Axis, Parameter};

/// Number of calibration states: gyro bias, accelerometer bias, star installation, gyro and
/// accelerometer scale factors, three axes each (nav-core's `StateBlock::CALIBRATION`).
pub const CALIBRATION_STATES: usize = 15;

const _: () = assert!(CALIBRATION_STATES == 3 * nav_core::state::StateBlock::CALIBRATION.len());

/// The (parameter, axis) of each calibration state, in nav-core's state order.
pub fn calibration_labels() -> [(Parameter, Axis); CALIBRATION_STATES] {
    let mut labels = [(Parameter::GyroBias, Axis::X); CALIBRATION_STATES];
    let all = Parameter::CALIBRATION
        .iter()
        .flat_map(|&parameter| Axis::ALL.map(|axis| (parameter, axis)));
    for (label, value) in labels.iter_mut().zip(all) {
        *label = value;
    }
    labels
}

/// What one run leaves for the statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutcome<const N: usize = CALIBRATION_STATES> {
    /// The run's seed.
    pub seed: u64,
    /// Final error `estimate − truth` of each state.
    pub error: SVector<f64, N>,
    /// Final filter covariance of the states.
    pub covariance: SMatrix<f64, N, N>,
    /// NIS of the star sensor's tested updates (zero sums when not recorded).
    pub star_nis: crate::harness::flight::NisSum,
    /// NIS of the GNSS fixes' tested updates.
    pub gnss_nis: crate::harness::flight::NisSum,
    /// Norm of the final navigation position error (m; NaN if the flight recorded no sample).
    pub position_error_m: f64,
    /// The run's consistency over time ([`over_time`]; empty when not recorded).
    pub over_time: Vec<OverTimeSample>,
    /// The systematic IMU error states' final error and covariance, when the filter
    /// estimates them (`[filter.imu_errors]`).
    pub imu_error: Option<crate::harness::optional_blocks::ImuErrorOutcome>,
    /// The correlated GNSS error states' final error and covariance, when the filter
    /// estimates them (`[filter] gnss_correlated_sigma_m`).
    pub gnss_error: Option<crate::harness::optional_blocks::GnssErrorOutcome>,
    /// The flight software's health counters at the end of the run, the non-zero ones by
    /// name (`nav_fsw::health::HealthCounters::named`).
    pub health: std::collections::BTreeMap<String, u32>,
}

/// The non-zero counters of `health`, by name.
pub fn non_zero_counters(
    health: &nav_fsw::health::HealthCounters,
) -> std::collections::BTreeMap<String, u32> {
    health
        .named()
        .iter()
        .filter(|(_, value)| *value != 0)
        .map(|(name, value)| ((*name).to_string(), *value))
        .collect()
}

impl RunOutcome {
    /// The outcome of the flight of seed `seed`: its final calibration error and covariance,
    /// NIS sums, final position error and consistency over time.
    pub fn of_flight(seed: u64, result: &crate::harness::flight::FlightResult) -> Self {
        Self {
            seed,
            error: -result.calibration_error,
            covariance: result.calibration_covariance,
            star_nis: result.star_nis,
            gnss_nis: result.gnss_nis,
            position_error_m: result.samples.last().map_or(f64::NAN, |sample| {
                nalgebra::Vector3::from(sample.position_error_m).norm()
            }),
            over_time: over_time(&result.samples),
            health: non_zero_counters(&result.health),
            imu_error: result.imu_error.clone(),
            gnss_error: result.gnss_error.clone(),
        }
    }
}

/// One instant of a run's consistency over time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OverTimeSample {
    /// Navigation time (s).
    pub time_s: f64,
    /// NEES of the calibration states at this instant (`None` if the covariance is not
    /// positive definite).
    pub nees: Option<f64>,
    /// NIS of the star sensor's tested updates since the previous instant.
    pub star_nis: crate::harness::flight::NisSum,
    /// NIS of the GNSS fixes' tested updates since the previous instant.
    pub gnss_nis: crate::harness::flight::NisSum,
}

/// At most this many instants (and the last) of a run enter its consistency over time, so a
/// campaign's memory stays small whatever the recording interval.
pub const OVER_TIME_POINTS: usize = 100;

/// A flight's consistency over time: every `k`-th recorded sample from the first, and the
/// last, with `k` the smallest stride that keeps at most [`OVER_TIME_POINTS`] (+ 1) instants;
/// each instant carries the NIS of all samples since the previous instant, so the interval
/// sums add up to the flight's totals.
pub fn over_time(samples: &[crate::harness::flight::FlightSample]) -> Vec<OverTimeSample> {
    let stride = samples.len().div_ceil(OVER_TIME_POINTS).max(1);
    let mut points = Vec::with_capacity(OVER_TIME_POINTS + 1);
    let mut star_nis = crate::harness::flight::NisSum::default();
    let mut gnss_nis = crate::harness::flight::NisSum::default();
    for (index, sample) in samples.iter().enumerate() {
        star_nis.sum += sample.star_nis.sum;
        star_nis.updates += sample.star_nis.updates;
        gnss_nis.sum += sample.gnss_nis.sum;
        gnss_nis.updates += sample.gnss_nis.updates;
        if index % stride == 0 || index + 1 == samples.len() {
            points.push(OverTimeSample {
                time_s: sample.time_s,
                nees: sample.calibration_nees,
                star_nis: std::mem::take(&mut star_nis),
                gnss_nis: std::mem::take(&mut gnss_nis),
            });
        }
    }
    points
}

/// Flies `scenario` once per seed in parallel, each run's sensor-error truth drawn from the
/// filter's prior ([`crate::setup::prior::with_truth_drawn_from_prior`]): the campaign of
/// `nav-sim monte-carlo` and of the consistency tests. `progress` is called once per finished
/// run, from the rayon workers (`&|| {}` for none).
///
/// # Errors
/// [`MonteCarloError::Run`] with the seed of a failed flight.
pub fn fly_campaign(
    scenario: &crate::scenario::Scenario,
    seeds: &[u64],
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<RunOutcome>, MonteCarloError<crate::harness::flight::FlightError>> {
    run_parallel(
        seeds,
        |seed| {
            // The run's mission (a turned ground track when drawn), then its sensor errors.
            let mission = crate::setup::dispersion::mission_scenario(scenario, seed);
            let seeded = crate::setup::prior::with_truth_drawn_from_prior(&mission, seed);
            // The flight software is configured from the mission undispersed otherwise: the
            // other entries change only the truth ([`crate::setup::dispersion::truth_scenario`]).
            let truth = crate::setup::dispersion::truth_scenario(&seeded, seed);
            let flight_config = crate::setup::fsw::run_config(&seeded, &truth)?;
            let run_options = crate::harness::flight::FlightOptions::default();
            crate::harness::flight::fly_with(
                &truth,
                flight_config,
                run_options,
                |_, _| {},
                |_, _| {},
            )
            .map(|result| RunOutcome::of_flight(seed, &result))
        },
        progress,
    )
}

/// Why the Monte Carlo statistics or a run failed.
#[derive(Debug, thiserror::Error)]
pub enum MonteCarloError<E: std::error::Error + 'static> {
    /// A run failed.
    #[error("run with seed {seed}: {source}")]
    Run {
        /// The run's seed.
        seed: u64,
        /// The run's error.
        source: E,
    },
    /// A run's covariance is not symmetric positive definite (its NEES is undefined).
    #[error("run with seed {seed}: the covariance is not positive definite")]
    CovarianceNotPositiveDefinite {
        /// The run's seed.
        seed: u64,
    },
    /// No runs.
    #[error("no runs")]
    NoRuns,
    /// statrs refused the χ² degrees of freedom.
    #[error("χ² distribution with {degrees_of_freedom} degrees of freedom: {message}")]
    ChiSquared {
        /// Degrees of freedom.
        degrees_of_freedom: f64,
        /// statrs' message.
        message: String,
    },
}

/// Per-state statistics over the runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateStatistics {
    /// RMS of the final errors over the runs.
    pub rms_error: f64,
    /// Mean of the filter's final 1σ over the runs.
    pub mean_sigma: f64,
}

/// The NEES consistency test.
#[derive(Debug, Clone, PartialEq)]
pub struct NeesTest {
    /// NEES of each run, in run order.
    pub per_run: Vec<f64>,
    /// Average NEES `ε̄`.
    pub average: f64,
    /// Lower bound of the 95% interval, `χ²⁻¹(0.025; N n) / N`.
    pub lower_bound: f64,
    /// Upper bound, `χ²⁻¹(0.975; N n) / N`.
    pub upper_bound: f64,
    /// Degrees of freedom of one run, `n`.
    pub states: usize,
}

impl NeesTest {
    /// Whether the average lies inside the 95% interval.
    pub fn consistent(&self) -> bool {
        self.lower_bound <= self.average && self.average <= self.upper_bound
    }
}

/// Statistics of a Monte Carlo campaign.
#[derive(Debug, Clone, PartialEq)]
pub struct MonteCarloSummary<const N: usize = CALIBRATION_STATES> {
    /// Number of runs.
    pub runs: usize,
    /// Per state, in state order.
    pub states: [StateStatistics; N],
    /// The NEES test.
    pub nees: NeesTest,
    /// The star sensor's NIS test (3 components), when the runs recorded NIS.
    pub star_nis: Option<NisTest>,
    /// The GNSS receiver's NIS test (3 components), when the runs recorded NIS.
    pub gnss_nis: Option<NisTest>,
    /// The consistency at each instant the runs recorded ([`OverTimeSample`]); empty when
    /// the runs carry no time series.
    pub over_time: Vec<OverTimeStatistics>,
}

/// The campaign's consistency at one instant.
#[derive(Debug, Clone, PartialEq)]
pub struct OverTimeStatistics {
    /// Navigation time (s).
    pub time_s: f64,
    /// Average NEES over the runs (NaN if a run's covariance is not positive definite).
    pub nees_average: f64,
    /// Lower bound of the 95 % interval of the average NEES ([`nees_bounds`]).
    pub nees_lower_bound: f64,
    /// Upper bound of the 95 % interval of the average NEES.
    pub nees_upper_bound: f64,
    /// The star sensor's NIS test over the interval ending here (`None` without updates).
    pub star_nis: Option<NisTest>,
    /// The GNSS receiver's NIS test over the interval ending here (`None` without updates).
    pub gnss_nis: Option<NisTest>,
}

impl OverTimeStatistics {
    /// Whether the average NEES lies inside its 95 % interval.
    pub fn nees_consistent(&self) -> bool {
        self.nees_lower_bound <= self.nees_average && self.nees_average <= self.nees_upper_bound
    }
}

/// The consistency over time of `outcomes`: one entry per instant that every run recorded,
/// at the first run's times (the runs of one scenario share their sample times).
///
/// # Errors
/// [`MonteCarloError::NoRuns`] or [`MonteCarloError::ChiSquared`] from the NEES interval.
fn summarise_over_time<const N: usize, E: std::error::Error>(
    outcomes: &[RunOutcome<N>],
) -> Result<Vec<OverTimeStatistics>, MonteCarloError<E>> {
    let (nees_lower_bound, nees_upper_bound) = nees_bounds(outcomes.len(), N)?;
    let instants = outcomes
        .iter()
        .map(|outcome| outcome.over_time.len())
        .min()
        .unwrap_or(0);
    let runs_f64 = outcomes.len() as f64;
    Ok((0..instants)
        .map(|instant| {
            let points: Vec<&OverTimeSample> = outcomes
                .iter()
                .filter_map(|outcome| outcome.over_time.get(instant))
                .collect();
            let nees_average = points
                .iter()
                .map(|point| point.nees.unwrap_or(f64::NAN))
                .sum::<f64>()
                / runs_f64;
            let nis = |sums: Vec<crate::harness::flight::NisSum>| NisTest::new::<E>(&sums, 3).ok();
            OverTimeStatistics {
                time_s: points.first().map_or(f64::NAN, |point| point.time_s),
                nees_average,
                nees_lower_bound,
                nees_upper_bound,
                star_nis: nis(points.iter().map(|point| point.star_nis).collect()),
                gnss_nis: nis(points.iter().map(|point| point.gnss_nis).collect()),
            }
        })
        .collect())
}

/// The two-sided 95% interval of the average NEES of `runs` runs of `states` states.
///
/// # Errors
/// [`MonteCarloError::NoRuns`], or [`MonteCarloError::ChiSquared`] if statrs refuses the
/// degrees of freedom.
pub fn nees_bounds<E: std::error::Error>(
    runs: usize,
    states: usize,
) -> Result<(f64, f64), MonteCarloError<E>> {
    average_interval(runs as u64, states)
}

/// The two-sided 95 % interval of the average of `count` independent χ²(`dimension`)
/// variables: `[χ²⁻¹(0.025; count·dimension), χ²⁻¹(0.975; count·dimension)] / count`.
fn average_interval<E: std::error::Error>(
    count: u64,
    dimension: usize,
) -> Result<(f64, f64), MonteCarloError<E>> {
    if count == 0 || dimension == 0 {
        return Err(MonteCarloError::NoRuns);
    }
    // Counts and dimensions are far below 2⁵³: exact in f64.
    let count = count as f64;
    let degrees_of_freedom = count * dimension as f64;
    let (lower, upper) = chi_square_quantiles(degrees_of_freedom)?;
    Ok((lower / count, upper / count))
}

/// Above this many degrees of freedom the χ² quantiles come from the Wilson–Hilferty cube
/// approximation (statrs' inverse CDF returns NaN for millions of degrees of freedom, the NIS
/// of a 100-run campaign has 9 million).
const WILSON_HILFERTY_ABOVE_DOF: f64 = 1.0e5;

/// The 2.5 % and 97.5 % quantiles of χ²(k). Exact (statrs) up to
/// [`WILSON_HILFERTY_ABOVE_DOF`]; above, Wilson and Hilferty (1931): `(χ²/k)^(1/3)` is nearly
/// normal with mean `1 − 2/(9k)` and variance `2/(9k)`, so
/// `χ²_p ≈ k (1 − 2/(9k) + z_p √(2/(9k)))³`, relative difference from the exact quantile below 1e-5 at 1e5 degrees of freedom
/// (test) and falling with k.
fn chi_square_quantiles<E: std::error::Error>(
    degrees_of_freedom: f64,
) -> Result<(f64, f64), MonteCarloError<E>> {
    let refused = |message: String| MonteCarloError::ChiSquared {
        degrees_of_freedom,
        message,
    };
    if degrees_of_freedom > WILSON_HILFERTY_ABOVE_DOF {
        let normal = statrs::distribution::Normal::standard();
        let spread = (2.0 / (9.0 * degrees_of_freedom)).sqrt();
        let quantile = |p: f64| {
            let z = normal.inverse_cdf(p);
            degrees_of_freedom * (1.0 - spread * spread + z * spread).powi(3)
        };
        return Ok((quantile(0.025), quantile(0.975)));
    }
    let distribution =
        ChiSquared::new(degrees_of_freedom).map_err(|error| refused(error.to_string()))?;
    let (lower, upper) = (
        distribution.inverse_cdf(0.025),
        distribution.inverse_cdf(0.975),
    );
    if lower.is_finite() && upper.is_finite() {
        Ok((lower, upper))
    } else {
        Err(refused("the inverse CDF is not finite".into()))
    }
}

/// The NIS consistency test of one aiding sensor over a campaign (Bar-Shalom, Li and
/// Kirubarajan, *Estimation with Applications to Tracking and Navigation*, §5.4.2): the average
/// NIS over all `M` tested updates of all runs, `ε̄_ν = Σ ν ᵀ S⁻¹ ν / M`, is `χ²(M m) / M`
/// distributed for an `m`-dimensional measurement of a consistent filter; its two-sided 95 %
/// interval is `[χ²⁻¹(0.025; M m), χ²⁻¹(0.975; M m)] / M`.
#[derive(Debug, Clone, PartialEq)]
pub struct NisTest {
    /// Average NIS over every tested update.
    pub average: f64,
    /// Lower bound of the 95 % interval.
    pub lower_bound: f64,
    /// Upper bound of the 95 % interval.
    pub upper_bound: f64,
    /// Updates tested, `M`.
    pub updates: u64,
    /// Measurement dimension, `m`.
    pub dimension: usize,
}

impl NisTest {
    /// The test over the per-run sums of one sensor.
    ///
    /// # Errors
    /// [`MonteCarloError::NoRuns`] without updates, [`MonteCarloError::ChiSquared`] if statrs
    /// refuses the degrees of freedom.
    pub fn new<E: std::error::Error>(
        runs: &[crate::harness::flight::NisSum],
        dimension: usize,
    ) -> Result<Self, MonteCarloError<E>> {
        let updates: u64 = runs.iter().map(|run| run.updates).sum();
        let sum: f64 = runs.iter().map(|run| run.sum).sum();
        let (lower_bound, upper_bound) = average_interval(updates, dimension)?;
        Ok(Self {
            // Update counts are far below 2⁵³: exact in f64.
            average: sum / updates as f64,
            lower_bound,
            upper_bound,
            updates,
            dimension,
        })
    }

    /// Whether the average lies inside the 95 % interval.
    pub fn consistent(&self) -> bool {
        self.lower_bound <= self.average && self.average <= self.upper_bound
    }

    /// One line for reports: `NIS <sensor> over M updates: average …, 95% interval […]: …`.
    pub fn line(&self, sensor: &str) -> String {
        format!(
            "NIS of the {sensor} ({} components) over {} updates: average {:.4}, 95% interval \
             [{:.4}, {:.4}]: {}",
            self.dimension,
            self.updates,
            self.average,
            self.lower_bound,
            self.upper_bound,
            if self.consistent() {
                "consistent"
            } else {
                "NOT consistent"
            }
        )
    }
}

/// The NEES of one run, `eᵀ P⁻¹ e`, or `None` if its covariance is not positive definite.
pub fn run_nees<const N: usize>(outcome: &RunOutcome<N>) -> Option<f64> {
    crate::harness::optional_blocks::nees(&outcome.error, &outcome.covariance)
}

/// Computes the per-state statistics and the NEES test of the runs.
///
/// # Errors
/// [`MonteCarloError::NoRuns`], [`MonteCarloError::CovarianceNotPositiveDefinite`] naming the
/// run's seed, or [`MonteCarloError::ChiSquared`].
pub fn summarise<const N: usize, E: std::error::Error>(
    outcomes: &[RunOutcome<N>],
) -> Result<MonteCarloSummary<N>, MonteCarloError<E>> {
    let (lower_bound, upper_bound) = nees_bounds(outcomes.len(), N)?;
    let per_run = outcomes
        .iter()
        .map(|outcome| {
            run_nees(outcome)
                .ok_or(MonteCarloError::CovarianceNotPositiveDefinite { seed: outcome.seed })
        })
        .collect::<Result<Vec<f64>, _>>()?;
    let runs_f64 = outcomes.len() as f64;
    let average = per_run.iter().sum::<f64>() / runs_f64;
    let states = std::array::from_fn(|state| StateStatistics {
        rms_error: (outcomes
            .iter()
            .map(|outcome| outcome.error[state].powi(2))
            .sum::<f64>()
            / runs_f64)
            .sqrt(),
        mean_sigma: outcomes
            .iter()
            .map(|outcome| outcome.covariance[(state, state)].sqrt())
            .sum::<f64>()
            / runs_f64,
    });
    let nis = |sums: Vec<crate::harness::flight::NisSum>| NisTest::new::<E>(&sums, 3).ok();
    Ok(MonteCarloSummary {
        runs: outcomes.len(),
        star_nis: nis(outcomes.iter().map(|outcome| outcome.star_nis).collect()),
        gnss_nis: nis(outcomes.iter().map(|outcome| outcome.gnss_nis).collect()),
        over_time: summarise_over_time(outcomes)?,
        states,
        nees: NeesTest {
            per_run,
            average,
            lower_bound,
            upper_bound,
            states: N,
        },
    })
}

/// Runs `run` for every seed in parallel (rayon), calling `progress` once per finished run
/// (from the rayon workers). Outcomes are returned in seed order whatever the scheduling.
///
/// # Errors
/// [`MonteCarloError::Run`] with the seed of a failed run (the first in seed order).
pub fn run_parallel<const N: usize, E, F>(
    seeds: &[u64],
    run: F,
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<RunOutcome<N>>, MonteCarloError<E>>
where
    E: std::error::Error + Send + 'static,
    F: Fn(u64) -> Result<RunOutcome<N>, E> + Sync,
{
    seeds
        .par_iter()
        .map(|&seed| {
            let outcome = run(seed).map_err(|source| MonteCarloError::Run { seed, source });
            progress();
            outcome
        })
        .collect()
}

impl<const N: usize> MonteCarloSummary<N> {
    /// The table: one row per state (parameter, axis, RMS error, mean 1σ, their ratio), then
    /// the NEES test. `labels` names the states in order (e.g. [`calibration_labels`]).
    pub fn table(&self, labels: &[(Parameter, Axis); N]) -> Table {
        let mut table = Table::new();
        table.load_preset(UTF8_FULL_CONDENSED).set_header([
            "parameter",
            "axis",
            "RMS error",
            "mean filter 1σ",
            "RMS / 1σ",
        ]);
        let right = |text: String| Cell::new(text).set_alignment(CellAlignment::Right);
        for ((parameter, axis), state) in labels.iter().zip(&self.states) {
            // In the calibration table's units (the installation error as an angle).
            let scale = parameter.state_to_report_scale();
            table.add_row([
                Cell::new(format!("{} ({})", parameter.name(), parameter.unit())),
                Cell::new(axis.name()),
                right(format!("{:.3e}", scale * state.rms_error)),
                right(format!("{:.3e}", scale * state.mean_sigma)),
                right(format!("{:.2}", state.rms_error / state.mean_sigma)),
            ]);
        }
        table
    }

    /// The campaign as one JSON object: `{"runs": n, "nees_mean": x, "nees_interval_95":
    /// [lo, hi], "states": [{"parameter", "axis", "rms_error", "mean_sigma"}, ...]}`, the
    /// states in the calibration table's units (the installation error as an angle).
    ///
    /// # Errors
    /// A serialisation error (none for finite numbers).
    pub fn json(&self, labels: &[(Parameter, Axis); N]) -> Result<String, serde_json::Error> {
        serde_json::to_string_pretty(&self.json_value(labels))
    }

    /// The object that [`json`](Self::json) prints, for reports that add to it.
    pub fn json_value(&self, labels: &[(Parameter, Axis); N]) -> serde_json::Value {
        let states: Vec<serde_json::Value> = labels
            .iter()
            .zip(&self.states)
            .map(|((parameter, axis), state)| {
                let scale = parameter.state_to_report_scale();
                serde_json::json!({
                    "parameter": parameter.name(),
                    "axis": axis.name(),
                    "rms_error": scale * state.rms_error,
                    "mean_sigma": scale * state.mean_sigma,
                })
            })
            .collect();
        serde_json::json!({
            "runs": self.runs,
            "nees_mean": self.nees.average,
            "nees_interval_95": [self.nees.lower_bound, self.nees.upper_bound],
            "states": states,
        })
    }

    /// One line on the NEES test.
    pub fn nees_line(&self) -> String {
        let nees = &self.nees;
        format!(
            "NEES of {} states over {} runs: average {:.3}, 95% interval [{:.3}, {:.3}]: {}",
            nees.states,
            self.runs,
            nees.average,
            nees.lower_bound,
            nees.upper_bound,
            if nees.consistent() {
                "consistent"
            } else {
                "NOT consistent"
            }
        )
    }
}

#[cfg(test)]
mod tests;
