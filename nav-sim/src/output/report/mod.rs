//! Calibration report: the final table against the paper's accuracy figures (text and JSON),
//! CSV time histories of every estimated block, and PNG plots of estimate − truth with its
//! ±3σ envelope (the analogues of the paper's Figs. 1-5) beside |estimate − truth| and 1σ on a
//! log scale, plus the navigation errors.
//!
//! The report knows nothing about the filter: the caller fills plain structs (truth, estimate,
//! filter 1σ per block and axis) in the units of nav-core's error state
//! (`nav_core::state`). For every block, `error = estimate − truth`. For the navigation blocks
//! (attitude, position, velocity) the caller chooses what estimate and truth mean (e.g. the
//! filter's estimate of the navigation error and the true navigation error); they have no paper
//! figure.
//!
//! The paper's reported accuracies (Section 3; `docs/guide/model.md`) are met when
//! `|error| < accuracy` ("better than", strictly).
//!
//! Plots are drawn with plotters' bitmap backend and an embedded DejaVu Sans font (no system
//! font library needed).

mod history;
mod plot;
mod table;
#[cfg(test)]
mod tests;

use std::path::{Path, PathBuf};

use nav_core::state::{self, StateBlock};

use crate::output::OutputError;

pub use history::{read_time_histories, write_time_histories};
pub(crate) use plot::{draw_linear_and_log_panels, draw_panels, Curve, Panel};
pub use plot::{plot_block, plot_navigation_errors, write_plots};
pub use table::{health_table, summary};

/// One block of the error state (nav-core's layout, paper eq. 15).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Parameter {
    /// Attitude error.
    Attitude,
    /// Position error.
    Position,
    /// Velocity error.
    Velocity,
    /// Gyro bias (rad/s).
    GyroBias,
    /// Accelerometer bias (m/s²).
    AccelerometerBias,
    /// Star-sensor installation error (rad).
    StarInstallation,
    /// Gyro scale factor (dimensionless).
    GyroScaleFactor,
    /// Accelerometer scale factor (dimensionless).
    AccelerometerScaleFactor,
}

impl Parameter {
    /// Every block, in the state's order ([`StateBlock::ALL`]).
    pub const ALL: [Parameter; 8] = Self::of_blocks(StateBlock::ALL);

    /// The calibration blocks (those with a paper accuracy), in the state's order
    /// ([`StateBlock::CALIBRATION`]).
    pub const CALIBRATION: [Parameter; 5] = Self::of_blocks(StateBlock::CALIBRATION);

    /// The navigation blocks ([`StateBlock::NAVIGATION`]).
    pub const NAVIGATION: [Parameter; 3] = Self::of_blocks(StateBlock::NAVIGATION);

    /// The parameter of nav-core's state block.
    pub const fn of(block: StateBlock) -> Self {
        match block {
            StateBlock::Attitude => Self::Attitude,
            StateBlock::Position => Self::Position,
            StateBlock::Velocity => Self::Velocity,
            StateBlock::GyroBias => Self::GyroBias,
            StateBlock::AccelBias => Self::AccelerometerBias,
            StateBlock::StarInstallation => Self::StarInstallation,
            StateBlock::GyroScaleFactor => Self::GyroScaleFactor,
            StateBlock::AccelScaleFactor => Self::AccelerometerScaleFactor,
        }
    }

    /// [`Parameter::of`] for each block of a list.
    const fn of_blocks<const N: usize>(blocks: [StateBlock; N]) -> [Parameter; N] {
        let mut parameters = [Self::Attitude; N];
        let mut k = 0;
        while k < N {
            parameters[k] = Self::of(blocks[k]);
            k += 1;
        }
        parameters
    }

    /// nav-core's state block.
    pub fn state_block(self) -> StateBlock {
        match self {
            Self::Attitude => state::ATTITUDE,
            Self::Position => state::POSITION,
            Self::Velocity => state::VELOCITY,
            Self::GyroBias => state::GYRO_BIAS,
            Self::AccelerometerBias => state::ACCEL_BIAS,
            Self::StarInstallation => state::STAR_INSTALLATION,
            Self::GyroScaleFactor => state::GYRO_SCALE_FACTOR,
            Self::AccelerometerScaleFactor => state::ACCEL_SCALE_FACTOR,
        }
    }

    /// Name in tables, JSON and file names (nav-core's block name).
    pub fn name(self) -> &'static str {
        self.state_block().name()
    }

    /// Position in [`Parameter::ALL`] (and in a [`TimeHistorySample`]).
    pub fn index(self) -> usize {
        self.state_block().position()
    }

    /// Factor from the filter's state to the reported value: 2 for the star installation
    /// error (the state is the quaternion's vector part, about half the angle; reports give
    /// the angle, as the calibration table does), 1 otherwise.
    pub fn state_to_report_scale(self) -> f64 {
        match self {
            Self::StarInstallation | Self::Attitude => 2.0,
            _ => 1.0,
        }
    }

    /// Unit of the block's values.
    pub fn unit(self) -> &'static str {
        match self {
            Self::Attitude | Self::StarInstallation => "rad",
            Self::Position => "m",
            Self::Velocity => "m/s",
            Self::GyroBias => "rad/s",
            Self::AccelerometerBias => "m/s²",
            Self::GyroScaleFactor | Self::AccelerometerScaleFactor => "-",
        }
    }

    /// The accuracy the paper reports after convergence (Section 3), per axis; `None` for the
    /// navigation blocks. Defined once, in nav-fsw's
    /// [`CalibrationThresholds::PAPER_ACCURACY`](nav_fsw::calibration_manager::CalibrationThresholds::PAPER_ACCURACY).
    pub fn paper_accuracy(self) -> Option<f64> {
        let paper = nav_fsw::calibration_manager::CalibrationThresholds::PAPER_ACCURACY;
        match self {
            Self::GyroScaleFactor => Some(paper.gyro_scale_factor),
            Self::AccelerometerScaleFactor => Some(paper.accel_scale_factor),
            Self::StarInstallation => Some(paper.star_installation_rad),
            Self::GyroBias => Some(paper.gyro_bias_rad_s),
            Self::AccelerometerBias => Some(paper.accel_bias_mps2),
            Self::Attitude | Self::Position | Self::Velocity => None,
        }
    }
}

/// A body (or frame) axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Axis {
    /// x
    X,
    /// y
    Y,
    /// z
    Z,
}

impl Axis {
    /// The three axes in order.
    pub const ALL: [Axis; 3] = [Self::X, Self::Y, Self::Z];

    /// `"x"`, `"y"` or `"z"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::X => "x",
            Self::Y => "y",
            Self::Z => "z",
        }
    }

    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        match self {
            Self::X => 0,
            Self::Y => 1,
            Self::Z => 2,
        }
    }
}

/// One parameter and axis of the final calibration result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CalibrationRow {
    /// The block.
    pub parameter: Parameter,
    /// The axis.
    pub axis: Axis,
    /// True value.
    pub truth: f64,
    /// Filter estimate.
    pub estimate: f64,
    /// Filter 1σ.
    pub sigma: f64,
}

impl CalibrationRow {
    /// `estimate − truth`.
    pub fn error(&self) -> f64 {
        self.estimate - self.truth
    }

    /// Whether `|error|` is strictly below the paper's accuracy (`None`: no paper figure; a
    /// non-finite error is not met).
    pub fn met(&self) -> Option<bool> {
        self.parameter
            .paper_accuracy()
            .map(|accuracy| self.error().abs() < accuracy)
    }
}

/// One block's three axes at one time.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BlockSample {
    /// Estimate per axis.
    pub estimate: [f64; 3],
    /// Filter 1σ per axis.
    pub sigma: [f64; 3],
    /// Truth per axis.
    pub truth: [f64; 3],
}

impl BlockSample {
    /// `estimate − truth` per axis.
    pub fn error(&self) -> [f64; 3] {
        [0, 1, 2].map(|axis| self.estimate[axis] - self.truth[axis])
    }
}

/// Every block at one time.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TimeHistorySample {
    /// Time (s).
    pub time_s: f64,
    /// Per block, indexed by [`Parameter::index`].
    pub blocks: [BlockSample; 8],
}

impl TimeHistorySample {
    /// The sample of one block.
    pub fn block(&self, parameter: Parameter) -> &BlockSample {
        &self.blocks[parameter.index()]
    }
}

/// The final calibration result, one row per parameter and axis.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CalibrationResult {
    /// The rows, in table order.
    pub rows: Vec<CalibrationRow>,
}
/// Why a report could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A file could not be created, written or read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A CSV file is malformed.
    #[error("{}, line {line}: {source}", path.display())]
    Csv {
        /// The file.
        path: PathBuf,
        /// Line number (1 = header; 0 if unknown).
        line: u64,
        /// The csv crate's error.
        source: csv::Error,
    },
    /// A CSV file's header is not the expected one.
    #[error("{}, line 1: header is `{found}`, expected `{expected}`", path.display())]
    Header {
        /// The file.
        path: PathBuf,
        /// The expected header.
        expected: String,
        /// The file's header.
        found: String,
    },
    /// A CSV cell is not a number.
    #[error("{}, line {line}, column `{column}`: `{value}` is not a number", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// Line number.
        line: u64,
        /// Column name.
        column: String,
        /// The cell.
        value: String,
    },
    /// The time histories of the blocks do not have the same times.
    #[error("{}: line {line} has time {found} s, the other blocks have {expected} s", path.display())]
    TimeMismatch {
        /// The file.
        path: PathBuf,
        /// Line number.
        line: u64,
        /// The time in this file (s).
        found: f64,
        /// The time in the files read before (s).
        expected: f64,
    },
    /// Nothing to plot or write.
    #[error("the time history is empty")]
    Empty,
    /// The embedded font was refused by the plotting library.
    #[error("the embedded DejaVu Sans font could not be registered")]
    Font,
    /// Drawing a plot failed.
    #[error("{}: plotting failed: {message}", path.display())]
    Plot {
        /// The PNG file.
        path: PathBuf,
        /// The plotting library's message.
        message: String,
    },
    /// JSON serialisation failed.
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// An output file could not be created or committed.
    #[error(transparent)]
    Output(#[from] OutputError),
}
/// The time-history CSV of `parameter` in `directory`.
fn time_history_file(directory: &Path, parameter: Parameter) -> PathBuf {
    directory.join(format!("{}.csv", parameter.name()))
}

/// The plot of `parameter` in `directory`.
fn plot_file(directory: &Path, parameter: Parameter) -> PathBuf {
    directory.join(format!("{}.png", parameter.name()))
}

/// The navigation-error plot in `directory`.
fn navigation_plot_file(directory: &Path) -> PathBuf {
    directory.join("navigation_errors.png")
}

/// The files [`write_time_histories`] and [`write_plots`] write into `directory`, so a caller
/// can check them before a run.
pub fn output_files(directory: &Path) -> Vec<PathBuf> {
    Parameter::ALL
        .iter()
        .map(|&parameter| time_history_file(directory, parameter))
        .chain(
            Parameter::ALL
                .iter()
                .map(|&parameter| plot_file(directory, parameter)),
        )
        .chain(std::iter::once(navigation_plot_file(directory)))
        .collect()
}
