//! The campaign's statistics of the filter's optional state blocks, each when the filter
//! estimates it: the systematic IMU errors (`[filter.imu_errors]`, against the truth in the
//! filter's gauge, `harness::filter_gauge`) and the correlated GNSS error (`[filter]
//! gnss_correlated_sigma_m`, against the receiver's correlated error,
//! `harness::optional_blocks`). Per state the RMS error, the mean filter 1σ and their ratio,
//! the NEES test of the block, and the largest |error|/1σ of any run: the core states'
//! statistics ([`monte_carlo::summarise`]) on the block's states.

use std::fmt::Write as _;

use comfy_table::{presets::UTF8_FULL_CONDENSED, Cell, CellAlignment, Table};
use nav_core::imu_error::{ImuErrorBlock, IMU_ERROR_DIMENSION};

use crate::campaign::monte_carlo::{self, MonteCarloError, MonteCarloSummary, RunOutcome};
use crate::campaign::runs::RunRecord;
use crate::harness::flight::FlightError;
use crate::harness::optional_blocks::BlockOutcome;

/// An optional state block, as a campaign reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReportedBlock {
    /// The twelve systematic IMU error states (filter's gauge).
    ImuError,
    /// The three correlated GNSS error states (launch-inertial axes).
    GnssError,
}

impl ReportedBlock {
    /// The first column's header of the block's table.
    fn table_header(self) -> &'static str {
        match self {
            Self::ImuError => "systematic IMU error (filter's gauge)",
            Self::GnssError => "correlated GNSS error (launch-inertial)",
        }
    }

    /// What one of the block's states is called in prose.
    fn state_noun(self) -> &'static str {
        match self {
            Self::ImuError => "systematic state",
            Self::GnssError => "correlated GNSS error state",
        }
    }

    /// What the block's states are called in prose (`--check`'s message).
    pub fn states_noun(self) -> &'static str {
        match self {
            Self::ImuError => "systematic IMU error states",
            Self::GnssError => "correlated GNSS error states",
        }
    }

    /// The block's key in the JSON report.
    pub fn json_key(self) -> &'static str {
        match self {
            Self::ImuError => "imu_error",
            Self::GnssError => "gnss_error",
        }
    }

    /// `block.component` of state `k` (nav-core's names; `gnss_error.x` …).
    pub fn state_name(self, k: usize) -> String {
        match self {
            Self::ImuError => imu_state_name(k),
            Self::GnssError => format!("gnss_error.{}", ["x", "y", "z"].get(k).unwrap_or(&"?")),
        }
    }

    /// The unit of state `k`.
    fn unit(self, k: usize) -> &'static str {
        match self {
            Self::ImuError if k >= ImuErrorBlock::GyroGSensitivity.offset() => "rad/s per m/s²",
            Self::ImuError => "rad",
            Self::GnssError => "m",
        }
    }
}

/// `block.component` of systematic IMU error state `k` (nav-core's names).
pub fn imu_state_name(k: usize) -> String {
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

/// The statistics of one optional block's `N` states over a campaign.
#[derive(Debug, Clone, PartialEq)]
pub struct OptionalBlockCampaign<const N: usize> {
    /// Which block.
    pub block: ReportedBlock,
    /// RMS error, mean 1σ and the NEES test of the block's states.
    pub summary: MonteCarloSummary<N>,
    /// The largest |error|/1σ over every run and state, with its run and state.
    pub largest_error_over_sigma: (f64, u64, usize),
}

/// The systematic IMU error states' statistics.
pub type ImuErrorCampaign = OptionalBlockCampaign<IMU_ERROR_DIMENSION>;
/// The correlated GNSS error states' statistics.
pub type GnssErrorCampaign = OptionalBlockCampaign<3>;

impl ImuErrorCampaign {
    /// The systematic IMU error states' statistics of `records`, or `None` when some run
    /// has no such states.
    ///
    /// # Errors
    /// As [`OptionalBlockCampaign::of_block`].
    pub fn of(records: &[RunRecord]) -> Result<Option<Self>, MonteCarloError<FlightError>> {
        Self::of_block(ReportedBlock::ImuError, records, |outcome| {
            outcome.imu_error.as_ref()
        })
    }
}

impl GnssErrorCampaign {
    /// The correlated GNSS error states' statistics of `records`, or `None` when some run
    /// has no such states.
    ///
    /// # Errors
    /// As [`OptionalBlockCampaign::of_block`].
    pub fn of(records: &[RunRecord]) -> Result<Option<Self>, MonteCarloError<FlightError>> {
        Self::of_block(ReportedBlock::GnssError, records, |outcome| {
            outcome.gnss_error.as_ref()
        })
    }
}

impl<const N: usize> OptionalBlockCampaign<N> {
    /// The statistics of `block` over `records`, its outcome in each run by `outcome_of`, or
    /// `None` when some run has none.
    ///
    /// # Errors
    /// [`MonteCarloError`] from the statistics (a covariance not positive definite, χ²
    /// quantiles refused).
    pub fn of_block(
        block: ReportedBlock,
        records: &[RunRecord],
        outcome_of: impl Fn(&RunOutcome) -> Option<&BlockOutcome<N>>,
    ) -> Result<Option<Self>, MonteCarloError<FlightError>> {
        let outcomes: Option<Vec<RunOutcome<N>>> = records
            .iter()
            .map(|record| {
                let outcome = &record.outcome;
                outcome_of(outcome).map(|states| RunOutcome {
                    seed: outcome.seed,
                    error: -states.error,
                    covariance: states.covariance,
                    star_nis: outcome.star_nis,
                    gnss_nis: outcome.gnss_nis,
                    position_error_m: outcome.position_error_m,
                    over_time: Vec::new(),
                    health: std::collections::BTreeMap::new(),
                    imu_error: None,
                    gnss_error: None,
                })
            })
            .collect();
        let Some(outcomes) = outcomes.filter(|outcomes| !outcomes.is_empty()) else {
            return Ok(None);
        };
        let summary = monte_carlo::summarise::<N, FlightError>(&outcomes)?;
        let mut largest = (0.0, 0, 0);
        for (record, outcome) in records.iter().zip(&outcomes) {
            for state in 0..N {
                let ratio = outcome.error[state].abs() / outcome.covariance[(state, state)].sqrt();
                if ratio > largest.0 {
                    largest = (ratio, record.run, state);
                }
            }
        }
        Ok(Some(Self {
            block,
            summary,
            largest_error_over_sigma: largest,
        }))
    }

    /// The table (state, RMS error, mean 1σ, ratio), the NEES line and the largest
    /// |error|/1σ.
    pub fn text(&self) -> String {
        let block = self.block;
        let mut table = Table::new();
        table.load_preset(UTF8_FULL_CONDENSED).set_header([
            block.table_header(),
            "RMS error",
            "mean filter 1σ",
            "RMS / 1σ",
        ]);
        let right = |text: String| Cell::new(text).set_alignment(CellAlignment::Right);
        for (k, state) in self.summary.states.iter().enumerate() {
            table.add_row([
                Cell::new(format!("{} ({})", block.state_name(k), block.unit(k))),
                right(format!("{:.3e}", state.rms_error)),
                right(format!("{:.3e}", state.mean_sigma)),
                right(format!("{:.2}", state.rms_error / state.mean_sigma)),
            ]);
        }
        let mut text = format!("{table}\n{}\n", self.summary.nees_line());
        let (ratio, run, state) = self.largest_error_over_sigma;
        let _ = writeln!(
            text,
            "largest |error|/1σ of a {}: {ratio:.2} (run {run}, {})",
            block.state_noun(),
            block.state_name(state)
        );
        text
    }

    /// The statistics as a JSON object: `{"nees_mean", "nees_interval_95", "states":
    /// [{"state", "rms_error", "mean_sigma"}], "largest_error_over_sigma": {"value", "run",
    /// "state"}}`.
    pub fn json_value(&self) -> serde_json::Value {
        let block = self.block;
        let states: Vec<serde_json::Value> = self
            .summary
            .states
            .iter()
            .enumerate()
            .map(|(k, state)| {
                serde_json::json!({
                    "state": block.state_name(k),
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
            "largest_error_over_sigma": {
                "value": ratio,
                "run": run,
                "state": block.state_name(state),
            },
        })
    }
}

/// One flight's block at its end (`nav-sim calibrate`): the NEES line against its χ²(N)
/// 95 % bound, then per state the error (truth − estimate), the filter 1σ and their ratio.
pub fn flight_text<const N: usize>(block: ReportedBlock, outcome: &BlockOutcome<N>) -> String {
    let bound = statrs::distribution::ChiSquared::new(N as f64)
        .map(|distribution| {
            statrs::distribution::ContinuousCDF::inverse_cdf(&distribution, FLIGHT_NEES_PROBABILITY)
        })
        .unwrap_or(f64::NAN);
    let nees = outcome
        .nees()
        .map_or_else(|| "undefined".to_owned(), |nees| format!("{nees:.1}"));
    let mut table = Table::new();
    table.load_preset(UTF8_FULL_CONDENSED).set_header([
        block.table_header(),
        "error (truth − estimate)",
        "filter 1σ",
        "|error| / 1σ",
    ]);
    let right = |text: String| Cell::new(text).set_alignment(CellAlignment::Right);
    for k in 0..N {
        let (error, sigma) = (outcome.error[k], outcome.covariance[(k, k)].sqrt());
        table.add_row([
            Cell::new(format!("{} ({})", block.state_name(k), block.unit(k))),
            right(format!("{error:.3e}")),
            right(format!("{sigma:.3e}")),
            right(format!("{:.2}", error.abs() / sigma)),
        ]);
    }
    format!(
        "NEES of the {N} {} at the end: {nees} (χ²({N}): mean {N}, 95 % below {bound:.1})\n{table}",
        block.states_noun()
    )
}

/// The probability below the bound of [`flight_text`]'s NEES line.
const FLIGHT_NEES_PROBABILITY: f64 = 0.95;

/// One flight's block at its end as JSON: `{"nees", "states": [{"state", "error", "sigma"}]}`
/// (error truth − estimate; `nees` null if the covariance is not positive definite).
pub fn flight_json<const N: usize>(
    block: ReportedBlock,
    outcome: &BlockOutcome<N>,
) -> serde_json::Value {
    let states: Vec<serde_json::Value> = (0..N)
        .map(|k| {
            serde_json::json!({
                "state": block.state_name(k),
                "error": outcome.error[k],
                "sigma": outcome.covariance[(k, k)].sqrt(),
            })
        })
        .collect();
    serde_json::json!({"nees": outcome.nees(), "states": states})
}
