//! The twelve systematic IMU error states in the analysis' report: their final 1σ against
//! their prior, and the largest error each can still put into the navigation on this flight.
//!
//! Each state acts as a bias on one gyro or accelerometer axis, scaled by a measured rate or
//! force component `m_k` (nav-core `imu_error::equivalent_bias_terms`). Its 1σ times the
//! largest `|m_k|` of the flight is the largest equivalent sensor bias its remaining
//! uncertainty leaves; the report sets it against the paper's accuracy for that sensor's bias
//! (the calibration target of the gyro or accelerometer bias), the yardstick the 15
//! calibration states are held to. A state whose multiplier stays zero (no force along its
//! axis) keeps its prior and leaves no error on this flight.

use nav_core::error_model::LinearisationPoint;
use nav_core::imu_error::{equivalent_bias_terms, BiasSensor, IMU_ERROR_DIMENSION};
use nav_core::state::StateBlock;

use super::CALIBRATION_TARGETS;

/// The largest `|m_k|` per state over the covariance steps.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct MultiplierTracker {
    pub(super) largest: [f64; IMU_ERROR_DIMENSION],
}

impl MultiplierTracker {
    /// Takes in the multipliers at one step's linearisation point.
    pub(super) fn observe(&mut self, point: &LinearisationPoint) {
        let terms = equivalent_bias_terms(
            &point.measured_rate_rad_s,
            &point.measured_specific_force_mps2,
        );
        for (largest, term) in self.largest.iter_mut().zip(terms) {
            *largest = largest.max(term.multiplier.abs());
        }
    }
}

/// The twelve states' result (module docs), in nav-core `ImuErrorBlock` order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuErrorReport {
    /// Prior 1σ (the scenario's `[filter.imu_errors]`).
    pub prior: [f64; IMU_ERROR_DIMENSION],
    /// Final 1σ.
    pub sigma: [f64; IMU_ERROR_DIMENSION],
    /// Largest `|m_k|` over the flight: rad/s for the gyro non-orthogonality, m/s² for the
    /// others.
    pub largest_multiplier: [f64; IMU_ERROR_DIMENSION],
}

/// One state of an [`ImuErrorReport`].
#[derive(Debug, Clone, PartialEq)]
pub struct ImuErrorRow {
    /// `block.component`, e.g. `accel_misalignment.yx`.
    pub name: String,
    /// Prior 1σ (rad, or rad/s per m/s² for the g-sensitivity).
    pub prior: f64,
    /// Final 1σ, same unit.
    pub sigma: f64,
    /// Largest `|m_k|` over the flight (rad/s or m/s²).
    pub largest_multiplier: f64,
    /// The paper's accuracy for the bias of the sensor the state disturbs (rad/s or m/s²).
    pub bias_target: f64,
    /// Unit of the bias (`rad/s` or `m/s^2`).
    pub bias_unit: &'static str,
}

impl ImuErrorRow {
    /// `sigma / prior`: 1 = nothing learnt.
    pub fn remaining(&self) -> f64 {
        self.sigma / self.prior
    }

    /// `sigma · max|m_k|`: the largest equivalent sensor bias the remaining uncertainty leaves.
    pub fn equivalent_bias(&self) -> f64 {
        self.sigma * self.largest_multiplier
    }

    /// [`Self::equivalent_bias`] over the sensor's bias target.
    pub fn bias_ratio(&self) -> f64 {
        self.equivalent_bias() / self.bias_target
    }
}

/// The paper's bias accuracy for `block` (rad/s or m/s²).
fn bias_target(block: StateBlock) -> f64 {
    CALIBRATION_TARGETS
        .iter()
        .find(|target| target.block == block)
        .map_or(f64::NAN, |target| target.target)
}

/// `block.component` of state `k` (0-11), nav-core's names (the campaign report's).
pub use crate::campaign::optional_block_report::imu_state_name as state_name;

impl ImuErrorReport {
    /// One row per state.
    pub fn rows(&self) -> Vec<ImuErrorRow> {
        let sensors = equivalent_bias_terms(&Default::default(), &Default::default());
        (0..IMU_ERROR_DIMENSION)
            .map(|k| {
                let (block, bias_unit) = match sensors.get(k).map(|term| term.sensor) {
                    Some(BiasSensor::Accel) => (StateBlock::AccelBias, "m/s^2"),
                    _ => (StateBlock::GyroBias, "rad/s"),
                };
                let value = |values: &[f64; IMU_ERROR_DIMENSION]| {
                    values.get(k).copied().unwrap_or(f64::NAN)
                };
                ImuErrorRow {
                    name: state_name(k),
                    prior: value(&self.prior),
                    sigma: value(&self.sigma),
                    largest_multiplier: value(&self.largest_multiplier),
                    bias_target: bias_target(block),
                    bias_unit,
                }
            })
            .collect()
    }

    /// The final table as text.
    pub fn table(&self) -> String {
        let mut text = String::from(
            "IMU error state             final 1-sigma      prior  sigma/prior  largest |m_k|  \
             sigma*|m_k| / bias target\n",
        );
        for row in self.rows() {
            text.push_str(&format!(
                "{:<27} {:>13.3e}  {:>9.2e}  {:>11.3}  {:>13.3e}  {:>10.3e} {:<6} {:>8.3}\n",
                row.name,
                row.sigma,
                row.prior,
                row.remaining(),
                row.largest_multiplier,
                row.equivalent_bias(),
                row.bias_unit,
                row.bias_ratio(),
            ));
        }
        text
    }
}

/// Per segment end, `sigma / prior` of the twelve states (the manoeuvre that lowers a state's
/// ratio is the one that makes it observable), as text; empty without the states.
pub fn history(snapshots: &[super::SegmentSnapshot], prior: &[f64; IMU_ERROR_DIMENSION]) -> String {
    let mut text = String::from("segment end (s)  label                                   ");
    for k in 0..IMU_ERROR_DIMENSION {
        let name = state_name(k);
        let short = name
            .rsplit_once('.')
            .map_or("?", |(_, component)| component);
        let block = ["gn", "am", "gs"][usize::from(k >= 3) + usize::from(k >= 9)];
        text.push_str(&format!(" {:>5}", format!("{block}.{short}")));
    }
    text.push('\n');
    for snapshot in snapshots {
        let Some(sigmas) = &snapshot.imu_error_sigmas else {
            continue;
        };
        let label: String = snapshot.label.chars().take(38).collect();
        text.push_str(&format!("{:>15.1}  {:<38} ", snapshot.end_time_s, label));
        for (sigma, prior) in sigmas.iter().zip(prior) {
            text.push_str(&format!(" {:>5.2}", sigma / prior));
        }
        text.push('\n');
    }
    text
}
