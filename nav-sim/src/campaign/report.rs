//! The report of a campaign, flown in one process or merged from shards: the Monte Carlo
//! summary, percentiles of the final errors, the runs outside 3σ with their re-run commands
//! and the health counters the runs raised, as text and as JSON; the optional state blocks'
//! statistics beside them when the filter estimates a block (none otherwise: the report of a
//! campaign without one is as it was).

use std::fmt::Write as _;

use comfy_table::{presets::UTF8_FULL_CONDENSED, Cell, CellAlignment, Table};
use statrs::distribution::{ChiSquared, ContinuousCDF};

use crate::campaign::consistency_checks::ConsistencyChecks;
use crate::campaign::monte_carlo::{
    self, MonteCarloError, MonteCarloSummary, RunOutcome, CALIBRATION_STATES,
};
use crate::campaign::optional_block_report::{GnssErrorCampaign, ImuErrorCampaign};
use crate::campaign::runs::RunRecord;
use crate::harness::flight::FlightError;
use crate::output::scenario_label::ScenarioLabel;

/// Probability below the NEES bound that marks a run as an outlier: the χ²(15) 99.9 % point.
pub const OUTLIER_NEES_PROBABILITY: f64 = 0.999;

/// A state's |error| beyond this many filter σ marks its run as an outlier.
pub const OUTLIER_SIGMAS: f64 = 3.0;
/// The 50th, 95th and 99th percentiles of a set of values (nearest rank: the smallest value
/// with at least p % of the values at or below it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Percentiles {
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// 99th percentile.
    pub p99: f64,
}

impl Percentiles {
    /// The percentiles of `values` (NaN for none).
    pub fn of(mut values: Vec<f64>) -> Self {
        values.sort_by(f64::total_cmp);
        let rank = |percent: usize| {
            // Nearest rank ⌈p n / 100⌉, from 1.
            let rank = (percent * values.len()).div_ceil(100).max(1);
            values.get(rank - 1).copied().unwrap_or(f64::NAN)
        };
        Self {
            p50: rank(50),
            p95: rank(95),
            p99: rank(99),
        }
    }

    fn json(&self, scale: f64) -> serde_json::Value {
        serde_json::json!({
            "p50": scale * self.p50,
            "p95": scale * self.p95,
            "p99": scale * self.p99,
        })
    }
}

/// A run outside 3σ: a state's |error| above [`OUTLIER_SIGMAS`] filter σ, or a NEES above the
/// χ²(15) [`OUTLIER_NEES_PROBABILITY`] point.
#[derive(Debug, Clone, PartialEq)]
pub struct Outlier {
    /// The run index.
    pub run: u64,
    /// Its seed.
    pub seed: u64,
    /// Its NEES.
    pub nees: f64,
    /// The states beyond 3σ: (state index, |error| / σ).
    pub states: Vec<(usize, f64)>,
    /// The command that re-runs it alone.
    pub command: String,
}

/// One health counter over a campaign's runs (only counters non-zero in some run).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CounterOverRuns {
    /// The counter's name (`nav_fsw::health::HealthCounters::named`).
    pub counter: String,
    /// The runs that ended with it non-zero.
    pub runs: usize,
    /// Its largest final value over the runs.
    pub max: u32,
    /// The sum of its final values over the runs (saturating).
    pub total: u64,
}

/// The health counters non-zero in some run of `outcomes`, by name.
pub fn counters_over_runs(outcomes: &[RunOutcome]) -> Vec<CounterOverRuns> {
    let mut counters: std::collections::BTreeMap<&str, CounterOverRuns> = Default::default();
    for (name, &value) in outcomes.iter().flat_map(|outcome| &outcome.health) {
        let entry = counters.entry(name).or_insert_with(|| CounterOverRuns {
            counter: name.clone(),
            runs: 0,
            max: 0,
            total: 0,
        });
        entry.runs += usize::from(value != 0);
        entry.max = entry.max.max(value);
        entry.total = entry.total.saturating_add(u64::from(value));
    }
    counters
        .into_values()
        .filter(|entry| entry.runs > 0)
        .collect()
}

/// The report of a campaign: the Monte Carlo summary, percentiles of the final errors and the
/// runs outside 3σ.
#[derive(Debug, Clone, PartialEq)]
pub struct CampaignReport {
    /// The scenario flown: its file and resolved SHA-256.
    pub scenario: ScenarioLabel,
    /// RMS error, mean 1σ, NEES and NIS tests.
    pub summary: MonteCarloSummary,
    /// Per calibration state, percentiles of the final |error| (state units).
    pub error_percentiles: [Percentiles; CALIBRATION_STATES],
    /// Percentiles of the norm of the final navigation position error (m).
    pub position_error_percentiles: Percentiles,
    /// The NEES above which a run is an outlier.
    pub outlier_nees_bound: f64,
    /// The systematic IMU error states' statistics, when the filter estimates them.
    pub imu_error: Option<ImuErrorCampaign>,
    /// The correlated GNSS error states' statistics, when the filter estimates them.
    pub gnss_error: Option<GnssErrorCampaign>,
    /// The runs outside 3σ, in run order.
    pub outliers: Vec<Outlier>,
    /// Every state's RMS |error|/1σ against its interval, and the runs beyond 4σ.
    pub checks: ConsistencyChecks,
    /// The health counters non-zero in some run, by name: how many runs raised each.
    pub health: Vec<CounterOverRuns>,
}

/// A path for a shell command line: as is if it needs no quoting, else in single quotes.
fn shell_word(text: &str) -> String {
    let plain = !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "/._-+=:,@".contains(c));
    if plain {
        text.to_string()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

/// The command that re-runs run `run` of a campaign of `scenario` alone.
pub fn rerun_command(scenario: Option<&str>, run: u64) -> String {
    match scenario {
        Some(path) => format!("nav-sim monte-carlo {} --run {run}", shell_word(path)),
        None => format!("nav-sim monte-carlo --run {run}"),
    }
}

impl CampaignReport {
    /// The report of `records` (in run order) of `scenario` (its file as given names it in
    /// the re-run commands).
    ///
    /// # Errors
    /// [`MonteCarloError`] from the statistics (no runs, a covariance not positive definite,
    /// χ² quantiles refused).
    pub fn new(
        records: &[RunRecord],
        scenario: &ScenarioLabel,
    ) -> Result<Self, MonteCarloError<FlightError>> {
        let outcomes: Vec<RunOutcome> = records
            .iter()
            .map(|record| record.outcome.clone())
            .collect();
        let summary = monte_carlo::summarise::<CALIBRATION_STATES, FlightError>(&outcomes)?;
        let dof = CALIBRATION_STATES as f64;
        let outlier_nees_bound = ChiSquared::new(dof)
            .map_err(|error| MonteCarloError::ChiSquared {
                degrees_of_freedom: dof,
                message: error.to_string(),
            })?
            .inverse_cdf(OUTLIER_NEES_PROBABILITY);
        let error_percentiles = std::array::from_fn(|state| {
            Percentiles::of(
                outcomes
                    .iter()
                    .map(|outcome| outcome.error[state].abs())
                    .collect(),
            )
        });
        let position_error_percentiles = Percentiles::of(
            outcomes
                .iter()
                .map(|outcome| outcome.position_error_m)
                .collect(),
        );
        let outliers = records
            .iter()
            .zip(&summary.nees.per_run)
            .filter_map(|(record, &nees)| {
                let outcome = &record.outcome;
                let states: Vec<(usize, f64)> = (0..CALIBRATION_STATES)
                    .map(|state| {
                        let sigma = outcome.covariance[(state, state)].sqrt();
                        (state, outcome.error[state].abs() / sigma)
                    })
                    .filter(|(_, ratio)| *ratio > OUTLIER_SIGMAS)
                    .collect();
                (nees > outlier_nees_bound || !states.is_empty()).then(|| Outlier {
                    run: record.run,
                    seed: outcome.seed,
                    nees,
                    states,
                    command: rerun_command(scenario.file.as_deref(), record.run),
                })
            })
            .collect();
        Ok(Self {
            scenario: scenario.clone(),
            imu_error: ImuErrorCampaign::of(records)?,
            checks: ConsistencyChecks::new(records)?,
            gnss_error: GnssErrorCampaign::of(records)?,
            summary,
            error_percentiles,
            position_error_percentiles,
            outlier_nees_bound,
            outliers,
            health: counters_over_runs(&outcomes),
        })
    }

    /// The text report: the RMS / 1σ table, the percentile table, the NEES and NIS lines and
    /// the runs outside 3σ with their re-run commands.
    pub fn text(&self) -> String {
        let labels = monte_carlo::calibration_labels();
        let mut text = format!(
            "{}\n{}\n",
            self.scenario.line(),
            self.summary.table(&labels)
        );
        let mut table = Table::new();
        table.load_preset(UTF8_FULL_CONDENSED).set_header([
            "parameter",
            "axis",
            "|error| p50",
            "p95",
            "p99",
        ]);
        let right =
            |value: f64| Cell::new(format!("{value:.3e}")).set_alignment(CellAlignment::Right);
        for ((parameter, axis), percentiles) in labels.iter().zip(&self.error_percentiles) {
            let scale = parameter.state_to_report_scale();
            table.add_row([
                Cell::new(format!("{} ({})", parameter.name(), parameter.unit())),
                Cell::new(axis.name()),
                right(scale * percentiles.p50),
                right(scale * percentiles.p95),
                right(scale * percentiles.p99),
            ]);
        }
        let position = &self.position_error_percentiles;
        table.add_row([
            Cell::new("navigation position (m)"),
            Cell::new("norm"),
            right(position.p50),
            right(position.p95),
            right(position.p99),
        ]);
        let _ = writeln!(
            text,
            "final |error| percentiles over {} runs (nearest rank):\n{table}",
            self.summary.runs
        );
        let _ = writeln!(text, "{}", self.summary.nees_line());
        for (sensor, test) in [
            ("star sensor", &self.summary.star_nis),
            ("GNSS", &self.summary.gnss_nis),
        ] {
            if let Some(test) = test {
                let _ = writeln!(text, "{}", test.line(sensor));
            }
        }
        let _ = writeln!(
            text,
            "runs outside 3σ (a state's |error| > {OUTLIER_SIGMAS}σ or NEES > {:.2}, the χ²({}) \
             {} % point): {} of {}",
            self.outlier_nees_bound,
            CALIBRATION_STATES,
            OUTLIER_NEES_PROBABILITY * 100.0,
            self.outliers.len(),
            self.summary.runs
        );
        for outlier in &self.outliers {
            let states: Vec<String> = outlier
                .states
                .iter()
                .map(|&(state, ratio)| {
                    let (parameter, axis) = labels[state];
                    format!("{} {} {ratio:.2}σ", parameter.name(), axis.name())
                })
                .collect();
            let _ = writeln!(
                text,
                "  run {} (seed {}): NEES {:.2}{}; re-run: {}",
                outlier.run,
                outlier.seed,
                outlier.nees,
                if states.is_empty() {
                    String::new()
                } else {
                    format!(", {}", states.join(", "))
                },
                outlier.command
            );
        }
        if let Some(imu_error) = &self.imu_error {
            let _ = write!(text, "{}", imu_error.text());
        }
        if let Some(gnss_error) = &self.gnss_error {
            let _ = write!(text, "{}", gnss_error.text());
        }
        let _ = write!(text, "{}", self.checks.text());
        let _ = writeln!(text, "{}", self.health_text());
        text
    }

    /// The health counters over the runs as a table (counter, runs that raised it, largest
    /// and total final value), or a line saying none was raised.
    fn health_text(&self) -> String {
        let runs = self.summary.runs;
        if self.health.is_empty() {
            return format!("health counters: none raised in {runs} runs");
        }
        let mut table = Table::new();
        table
            .load_preset(UTF8_FULL_CONDENSED)
            .set_header(["counter", "runs", "max", "total"]);
        let right = |value: String| Cell::new(value).set_alignment(CellAlignment::Right);
        for entry in &self.health {
            table.add_row([
                Cell::new(&entry.counter),
                right(format!("{} of {runs}", entry.runs)),
                right(entry.max.to_string()),
                right(entry.total.to_string()),
            ]);
        }
        format!("health counters raised (final values over {runs} runs):\n{table}")
    }

    /// The report as one JSON object: `scenario` (`{file, sha256}`), the summary's (`runs`,
    /// `nees_mean`,
    /// `nees_interval_95`, `states` with `rms_error` and `mean_sigma`), each state with
    /// `abs_error_percentiles` `{p50, p95, p99}` (report units), `position_error_m_percentiles`,
    /// `star_nis` and `gnss_nis` (`{average, interval_95, updates}` or null),
    /// `outlier_nees_bound`, `outliers` (`[{run, seed, nees, states: [{parameter, axis,
    /// error_over_sigma}], command}]`) and `health` (`[{counter, runs, max, total}]`, the
    /// counters non-zero in some run), `consistency_checks`
    /// ([`ConsistencyChecks::json_value`]), and per optional state block estimated its statistics
    /// (`imu_error`, `gnss_error`: [`crate::campaign::OptionalBlockCampaign::json_value`]).
    ///
    /// # Errors
    /// A serialisation error (none expected).
    pub fn json(&self) -> Result<String, serde_json::Error> {
        let labels = monte_carlo::calibration_labels();
        let mut value = self.summary.json_value(&labels);
        if let Some(states) = value
            .get_mut("states")
            .and_then(serde_json::Value::as_array_mut)
        {
            for ((state, percentiles), (parameter, _)) in
                states.iter_mut().zip(&self.error_percentiles).zip(&labels)
            {
                if let Some(object) = state.as_object_mut() {
                    object.insert(
                        "abs_error_percentiles".into(),
                        percentiles.json(parameter.state_to_report_scale()),
                    );
                }
            }
        }
        let nis = |test: &Option<monte_carlo::NisTest>| {
            test.as_ref().map(|test| {
                serde_json::json!({
                    "average": test.average,
                    "interval_95": [test.lower_bound, test.upper_bound],
                    "updates": test.updates,
                })
            })
        };
        let outliers: Vec<serde_json::Value> = self
            .outliers
            .iter()
            .map(|outlier| {
                let states: Vec<serde_json::Value> = outlier
                    .states
                    .iter()
                    .map(|&(state, ratio)| {
                        let (parameter, axis) = labels[state];
                        serde_json::json!({
                            "parameter": parameter.name(),
                            "axis": axis.name(),
                            "error_over_sigma": ratio,
                        })
                    })
                    .collect();
                serde_json::json!({
                    "run": outlier.run,
                    "seed": outlier.seed,
                    "nees": outlier.nees,
                    "states": states,
                    "command": outlier.command,
                })
            })
            .collect();
        if let Some(object) = value.as_object_mut() {
            object.insert("scenario".into(), self.scenario.json());
            object.insert(
                "position_error_m_percentiles".into(),
                self.position_error_percentiles.json(1.0),
            );
            object.insert("star_nis".into(), nis(&self.summary.star_nis).into());
            object.insert("gnss_nis".into(), nis(&self.summary.gnss_nis).into());
            object.insert("outlier_nees_bound".into(), self.outlier_nees_bound.into());
            object.insert("outliers".into(), outliers.into());
            let health: Vec<serde_json::Value> = self
                .health
                .iter()
                .map(|entry| {
                    serde_json::json!({
                        "counter": entry.counter,
                        "runs": entry.runs,
                        "max": entry.max,
                        "total": entry.total,
                    })
                })
                .collect();
            object.insert("health".into(), health.into());
            object.insert("consistency_checks".into(), self.checks.json_value());
            if let Some(imu_error) = &self.imu_error {
                object.insert(imu_error.block.json_key().into(), imu_error.json_value());
            }
            if let Some(gnss_error) = &self.gnss_error {
                object.insert(gnss_error.block.json_key().into(), gnss_error.json_value());
            }
        }
        serde_json::to_string_pretty(&value)
    }

    /// What `--check` refuses: the average NEES (of the calibration states, and of each
    /// optional state block estimated) outside its 95 % interval (`None` if inside).
    pub fn check_failure(&self) -> Option<String> {
        let outside = |nees: &monte_carlo::NeesTest, what: &str| {
            (!nees.consistent()).then(|| {
                format!(
                    "the average NEES {:.3} of the {what} over {} runs is outside its 95 % \
                     interval [{:.3}, {:.3}]",
                    nees.average, self.summary.runs, nees.lower_bound, nees.upper_bound
                )
            })
        };
        let imu_error = self
            .imu_error
            .as_ref()
            .map(|imu| (&imu.summary.nees, imu.block));
        let gnss_error = self
            .gnss_error
            .as_ref()
            .map(|gnss| (&gnss.summary.nees, gnss.block));
        outside(&self.summary.nees, "calibration states").or_else(|| {
            imu_error
                .into_iter()
                .chain(gnss_error)
                .find_map(|(nees, block)| outside(nees, block.states_noun()))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_are_nearest_rank() {
        let values: Vec<f64> = (1..=200).map(f64::from).rev().collect();
        let percentiles = Percentiles::of(values);
        assert_eq!(percentiles.p50.to_bits(), 100.0_f64.to_bits());
        assert_eq!(percentiles.p95.to_bits(), 190.0_f64.to_bits());
        assert_eq!(percentiles.p99.to_bits(), 198.0_f64.to_bits());
        let one = Percentiles::of(vec![2.5]);
        assert_eq!(one.p99.to_bits(), 2.5_f64.to_bits());
        assert!(Percentiles::of(Vec::new()).p50.is_nan());
    }

    #[test]
    fn counters_over_runs_count_the_runs_that_raised_each() {
        let outcome = |counters: &[(&str, u32)]| {
            let mut outcome = crate::campaign::shards::tests::record(0).outcome;
            outcome.health = counters
                .iter()
                .map(|(name, value)| ((*name).to_string(), *value))
                .collect();
            outcome
        };
        let outcomes = [
            outcome(&[("star_declared_faulty", 1), ("star_gate_rejections", 30)]),
            outcome(&[]),
            outcome(&[("star_gate_rejections", 12), ("gnss_jump", 0)]),
        ];
        let counters = counters_over_runs(&outcomes);
        assert_eq!(
            counters,
            [
                CounterOverRuns {
                    counter: "star_declared_faulty".into(),
                    runs: 1,
                    max: 1,
                    total: 1
                },
                CounterOverRuns {
                    counter: "star_gate_rejections".into(),
                    runs: 2,
                    max: 30,
                    total: 42
                },
            ]
        );
    }
}
