//! The campaign's consistency checks, each with its interval and verdict: for every
//! estimated state the report covers (the 15 calibration states and each optional block's),
//! the RMS of its normalised final error against its 99 % interval for the number of runs;
//! the mean of those over the states against [`MEAN_RATIO_INTERVAL`]; and the runs with some
//! state beyond [`FAR_OUT_SIGMAS`]. The NEES of each block against its 95 % interval is the
//! report's NEES lines (docs/guide/monte-carlo.md, "Consistency checks").

use std::fmt::Write as _;

use statrs::distribution::{ChiSquared, ContinuousCDF};

use crate::campaign::monte_carlo::{self, MonteCarloError};
use crate::campaign::optional_block_report::ReportedBlock;
use crate::campaign::runs::RunRecord;
use crate::harness::flight::FlightError;
use crate::harness::optional_blocks::BlockOutcome;
use nav_core::imu_error::IMU_ERROR_DIMENSION;

/// Two-sided probability of a state's interval of RMS(e/σ).
pub const STATE_RATIO_PROBABILITY: f64 = 0.99;

/// The interval of the mean of RMS(e/σ) over the states: a filter whose σ are 10 % too large
/// or too small on average fails it.
pub const MEAN_RATIO_INTERVAL: (f64, f64) = (0.9, 1.1);

/// A state's |error| beyond this many filter σ in a run fails the campaign: a consistent
/// filter has one in about 16,000 state-runs.
pub const FAR_OUT_SIGMAS: f64 = 4.0;

/// One state's normalised final errors over the runs.
#[derive(Debug, Clone, PartialEq)]
pub struct StateRatio {
    /// The state's name (`gyro_bias.x`, `imu_error.…`, `gnss_error.x`).
    pub name: String,
    /// `√(mean over runs of (e/σ)²)`, σ each run's own final filter 1σ.
    pub rms_error_over_sigma: f64,
}

/// A run with some state beyond [`FAR_OUT_SIGMAS`]: its largest.
#[derive(Debug, Clone, PartialEq)]
pub struct FarOutRun {
    /// The run index.
    pub run: u64,
    /// The state furthest out.
    pub state: String,
    /// Its |error| / σ.
    pub error_over_sigma: f64,
}

/// The checks of one campaign.
#[derive(Debug, Clone, PartialEq)]
pub struct ConsistencyChecks {
    /// Runs.
    pub runs: usize,
    /// The 99 % interval of one state's RMS(e/σ) for `runs` runs.
    pub ratio_interval: (f64, f64),
    /// Every state, calibration states first, then each optional block's.
    pub states: Vec<StateRatio>,
    /// The runs with some state beyond [`FAR_OUT_SIGMAS`], in run order.
    pub far_out_runs: Vec<FarOutRun>,
}

/// The 99 % interval of `√(χ²(n)/n)`: for a consistent filter each run's `e/σ` is a standard
/// normal draw, independent over the runs, so `n · RMS(e/σ)² ~ χ²(n)`
/// (Bar-Shalom, Li and Kirubarajan, §5.4.2, one state at a time).
///
/// # Errors
/// [`MonteCarloError::NoRuns`] or [`MonteCarloError::ChiSquared`] if statrs refuses `n`.
pub fn ratio_interval(runs: usize) -> Result<(f64, f64), MonteCarloError<FlightError>> {
    if runs == 0 {
        return Err(MonteCarloError::NoRuns);
    }
    // Run counts are far below 2⁵³: exact in f64.
    let count = runs as f64;
    let distribution = ChiSquared::new(count).map_err(|error| MonteCarloError::ChiSquared {
        degrees_of_freedom: count,
        message: error.to_string(),
    })?;
    let tail = (1.0 - STATE_RATIO_PROBABILITY) / 2.0;
    Ok((
        (distribution.inverse_cdf(tail) / count).sqrt(),
        (distribution.inverse_cdf(1.0 - tail) / count).sqrt(),
    ))
}

/// `e_k/σ_k` of every state of a block (`error`, `covariance`): appended to `ratios`.
fn push_ratios<const N: usize>(ratios: &mut Vec<f64>, states: &BlockOutcome<N>) {
    ratios.extend((0..N).map(|k| states.error[k] / states.covariance[(k, k)].sqrt()));
}

/// Each run's `e/σ` of every state, calibration states first, then the optional blocks
/// every run has, with the states' names.
fn normalised_errors(records: &[RunRecord]) -> (Vec<String>, Vec<Vec<f64>>) {
    let labels = monte_carlo::calibration_labels();
    let mut names: Vec<String> = labels
        .iter()
        .map(|(parameter, axis)| format!("{}.{}", parameter.name(), axis.name()))
        .collect();
    let imu = records
        .iter()
        .all(|record| record.outcome.imu_error.is_some());
    let gnss = records
        .iter()
        .all(|record| record.outcome.gnss_error.is_some());
    if imu {
        names.extend((0..IMU_ERROR_DIMENSION).map(|k| ReportedBlock::ImuError.state_name(k)));
    }
    if gnss {
        names.extend((0..3).map(|k| ReportedBlock::GnssError.state_name(k)));
    }
    let per_run = records
        .iter()
        .map(|record| {
            let outcome = &record.outcome;
            let mut ratios: Vec<f64> = (0..outcome.error.len())
                .map(|k| outcome.error[k] / outcome.covariance[(k, k)].sqrt())
                .collect();
            if let Some(states) = outcome.imu_error.as_ref().filter(|_| imu) {
                push_ratios(&mut ratios, states);
            }
            if let Some(states) = outcome.gnss_error.as_ref().filter(|_| gnss) {
                push_ratios(&mut ratios, states);
            }
            ratios
        })
        .collect();
    (names, per_run)
}

impl ConsistencyChecks {
    /// The checks of `records`.
    ///
    /// # Errors
    /// As [`ratio_interval`].
    pub fn new(records: &[RunRecord]) -> Result<Self, MonteCarloError<FlightError>> {
        let ratio_interval = ratio_interval(records.len())?;
        let (names, per_run) = normalised_errors(records);
        let count = records.len() as f64;
        let states = names
            .iter()
            .enumerate()
            .map(|(k, name)| StateRatio {
                name: name.clone(),
                rms_error_over_sigma: (per_run
                    .iter()
                    .map(|ratios| ratios.get(k).map_or(f64::NAN, |r| r * r))
                    .sum::<f64>()
                    / count)
                    .sqrt(),
            })
            .collect();
        let far_out_runs =
            records
                .iter()
                .zip(&per_run)
                .filter_map(|(record, ratios)| {
                    let (k, largest) = ratios.iter().map(|r| r.abs()).enumerate().fold(
                        (0, 0.0),
                        |best, (k, r)| if r > best.1 { (k, r) } else { best },
                    );
                    (largest > FAR_OUT_SIGMAS).then(|| FarOutRun {
                        run: record.run,
                        state: names.get(k).cloned().unwrap_or_default(),
                        error_over_sigma: largest,
                    })
                })
                .collect();
        Ok(Self {
            runs: records.len(),
            ratio_interval,
            states,
            far_out_runs,
        })
    }

    /// The mean of the states' RMS(e/σ).
    pub fn mean_ratio(&self) -> f64 {
        self.states
            .iter()
            .map(|state| state.rms_error_over_sigma)
            .sum::<f64>()
            / self.states.len().max(1) as f64
    }

    /// The states whose RMS(e/σ) is outside its interval.
    pub fn states_outside(&self) -> Vec<&StateRatio> {
        let (lower, upper) = self.ratio_interval;
        self.states
            .iter()
            .filter(|state| !(lower..=upper).contains(&state.rms_error_over_sigma))
            .collect()
    }

    /// Whether the mean ratio is inside [`MEAN_RATIO_INTERVAL`].
    pub fn mean_consistent(&self) -> bool {
        let (lower, upper) = MEAN_RATIO_INTERVAL;
        (lower..=upper).contains(&self.mean_ratio())
    }

    /// The checks as text: per state its ratio and verdict, then the mean and the 4σ line.
    pub fn text(&self) -> String {
        let verdict = |ok: bool| if ok { "consistent" } else { "INCONSISTENT" };
        let (lower, upper) = self.ratio_interval;
        let mut text = format!(
            "consistency checks over {} runs: RMS of |error|/1σ (each run's own σ) per state, \
             99 % interval [{lower:.3}, {upper:.3}]\n",
            self.runs
        );
        for state in &self.states {
            let ratio = state.rms_error_over_sigma;
            let _ = writeln!(
                text,
                "  {:<40} {ratio:>6.3}  {}",
                state.name,
                verdict((lower..=upper).contains(&ratio))
            );
        }
        let outside = self.states_outside();
        let _ = writeln!(
            text,
            "states outside their 99 % interval: {} of {}",
            outside.len(),
            self.states.len()
        );
        let (mean_lower, mean_upper) = MEAN_RATIO_INTERVAL;
        let _ = writeln!(
            text,
            "mean RMS |error|/1σ over the {} states: {:.3}, interval [{mean_lower}, \
             {mean_upper}]: {}",
            self.states.len(),
            self.mean_ratio(),
            verdict(self.mean_consistent())
        );
        let _ = writeln!(
            text,
            "runs with a state beyond {FAR_OUT_SIGMAS}σ: {} of {}: {}",
            self.far_out_runs.len(),
            self.runs,
            verdict(self.far_out_runs.is_empty())
        );
        for far in &self.far_out_runs {
            let _ = writeln!(
                text,
                "  run {}: {} {:.2}σ",
                far.run, far.state, far.error_over_sigma
            );
        }
        text
    }

    /// The checks as JSON: `{"ratio_interval_99", "states": [{"state",
    /// "rms_error_over_sigma"}], "mean_ratio", "mean_ratio_interval", "far_out_sigmas",
    /// "far_out_runs": [{"run", "state", "error_over_sigma"}]}`.
    pub fn json_value(&self) -> serde_json::Value {
        let states: Vec<serde_json::Value> = self
            .states
            .iter()
            .map(|state| {
                serde_json::json!({
                    "state": state.name,
                    "rms_error_over_sigma": state.rms_error_over_sigma,
                })
            })
            .collect();
        let far: Vec<serde_json::Value> = self
            .far_out_runs
            .iter()
            .map(|far| {
                serde_json::json!({
                    "run": far.run,
                    "state": far.state,
                    "error_over_sigma": far.error_over_sigma,
                })
            })
            .collect();
        serde_json::json!({
            "ratio_interval_99": [self.ratio_interval.0, self.ratio_interval.1],
            "states": states,
            "mean_ratio": self.mean_ratio(),
            "mean_ratio_interval": [MEAN_RATIO_INTERVAL.0, MEAN_RATIO_INTERVAL.1],
            "far_out_sigmas": FAR_OUT_SIGMAS,
            "far_out_runs": far,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ratio_interval_for_40_runs_is_the_chi_square_one() {
        let (lower, upper) = ratio_interval(40).unwrap();
        // χ²(40): 0.5 % point 20.707, 99.5 % point 66.766.
        assert!(
            (lower - (20.7065_f64 / 40.0).sqrt()).abs() < 1e-4,
            "{lower}"
        );
        assert!(
            (upper - (66.7659_f64 / 40.0).sqrt()).abs() < 1e-4,
            "{upper}"
        );
    }
}
