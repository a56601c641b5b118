//! The campaign's statistics of the systematic IMU error states, when the filter estimates
//! them (`[filter.imu_errors]`): per state the RMS error against the truth in the filter's
//! gauge (`harness::filter_gauge`), the mean filter 1σ and their ratio, the NEES test of the
//! twelve, and the largest |error|/1σ of any run.

use std::fmt::Write as _;

use comfy_table::{presets::UTF8_FULL_CONDENSED, Cell, CellAlignment, Table};
use nav_core::imu_error::{ImuErrorBlock, IMU_ERROR_DIMENSION};

use crate::campaign::monte_carlo::{self, MonteCarloError, MonteCarloSummary, RunOutcome};
use crate::campaign::runs::RunRecord;
use crate::harness::flight::FlightError;

/// The statistics of the twelve states over a campaign.
#[derive(Debug, Clone, PartialEq)]
pub struct ImuErrorCampaign {
    /// RMS error, mean 1σ and the NEES test of the twelve states.
    pub summary: MonteCarloSummary<IMU_ERROR_DIMENSION>,
    /// The largest |error|/1σ over every run and state, with its run and state.
    pub largest_error_over_sigma: (f64, u64, usize),
}

/// `block.component` of state `k` (nav-core's names).
pub fn state_name(k: usize) -> String {
    ImuErrorBlock::ALL
        .iter()
        .find(|block| (block.offset()..block.offset() + block.dimension()).contains(&k))
        .map_or_else(
            || "?".to_string(),
            |block| {
                format!(
                    "{}.{}",
                    block.name(),
                    block.component_name(k - block.offset())
                )
            },
        )
}

/// The unit of state `k`.
fn unit(k: usize) -> &'static str {
    if k >= ImuErrorBlock::GyroGSensitivity.offset() {
        "rad/s per m/s²"
    } else {
        "rad"
    }
}

impl ImuErrorCampaign {
    /// The statistics of `records`, or `None` when some run has no systematic states.
    ///
    /// # Errors
    /// [`MonteCarloError`] from the statistics (a covariance not positive definite, χ²
    /// quantiles refused).
    pub fn of(records: &[RunRecord]) -> Result<Option<Self>, MonteCarloError<FlightError>> {
        let outcomes: Option<Vec<RunOutcome<IMU_ERROR_DIMENSION>>> = records
            .iter()
            .map(|record| {
                let outcome = &record.outcome;
                outcome.imu_error.as_ref().map(|imu| RunOutcome {
                    seed: outcome.seed,
                    error: -imu.error,
                    covariance: imu.covariance,
                    star_nis: outcome.star_nis,
                    gnss_nis: outcome.gnss_nis,
                    position_error_m: outcome.position_error_m,
                    over_time: Vec::new(),
                    health: std::collections::BTreeMap::new(),
                    imu_error: None,
                })
            })
            .collect();
        let Some(outcomes) = outcomes.filter(|outcomes| !outcomes.is_empty()) else {
            return Ok(None);
        };
        let summary = monte_carlo::summarise::<IMU_ERROR_DIMENSION, FlightError>(&outcomes)?;
        let mut largest = (0.0, 0, 0);
        for (record, outcome) in records.iter().zip(&outcomes) {
            for state in 0..IMU_ERROR_DIMENSION {
                let ratio = outcome.error[state].abs() / outcome.covariance[(state, state)].sqrt();
                if ratio > largest.0 {
                    largest = (ratio, record.run, state);
                }
            }
        }
        Ok(Some(Self {
            summary,
            largest_error_over_sigma: largest,
        }))
    }

    /// The table (state, RMS error, mean 1σ, ratio), the NEES line and the largest
    /// |error|/1σ.
    pub fn text(&self) -> String {
        let mut table = Table::new();
        table.load_preset(UTF8_FULL_CONDENSED).set_header([
            "systematic IMU error (filter's gauge)",
            "RMS error",
            "mean filter 1σ",
            "RMS / 1σ",
        ]);
        let right = |text: String| Cell::new(text).set_alignment(CellAlignment::Right);
        for (k, state) in self.summary.states.iter().enumerate() {
            table.add_row([
                Cell::new(format!("{} ({})", state_name(k), unit(k))),
                right(format!("{:.3e}", state.rms_error)),
                right(format!("{:.3e}", state.mean_sigma)),
                right(format!("{:.2}", state.rms_error / state.mean_sigma)),
            ]);
        }
        let mut text = format!("{table}\n{}\n", self.summary.nees_line());
        let (ratio, run, state) = self.largest_error_over_sigma;
        let _ = writeln!(
            text,
            "largest |error|/1σ of a systematic state: {ratio:.2} (run {run}, {})",
            state_name(state)
        );
        text
    }

    /// The statistics as a JSON object: `{"nees_mean", "nees_interval_95", "states":
    /// [{"state", "rms_error", "mean_sigma"}], "largest_error_over_sigma": {"value", "run",
    /// "state"}}`.
    pub fn json_value(&self) -> serde_json::Value {
        let states: Vec<serde_json::Value> = self
            .summary
            .states
            .iter()
            .enumerate()
            .map(|(k, state)| {
                serde_json::json!({
                    "state": state_name(k),
                    "rms_error": state.rms_error,
                    "mean_sigma": state.mean_sigma,
                })
            })
            .collect();
        let (ratio, run, state) = self.largest_error_over_sigma;
        serde_json::json!({
            "nees_mean": self.summary.nees.average,
            "nees_interval_95": [self.summary.nees.lower_bound, self.summary.nees.upper_bound],
            "states": states,
            "largest_error_over_sigma": {"value": ratio, "run": run, "state": state_name(state)},
        })
    }
}
