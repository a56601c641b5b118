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
//! The paper's reported accuracies (Section 3; `docs/model.md`) are met when
//! `|error| < accuracy` ("better than", strictly).
//!
//! Plots are drawn with plotters' bitmap backend and an embedded DejaVu Sans font (no system
//! font library needed).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use comfy_table::{presets::UTF8_FULL_CONDENSED, Cell, CellAlignment, Table};
use nav_core::state::{self, StateBlock};
use plotters::prelude::*;
use serde::Serialize;

use crate::output::{OutputError, OutputFile};

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

/// A row as JSON: exactly the keys `parameter, axis, truth, estimate, error, sigma,
/// paper_accuracy, met` (`paper_accuracy` and `met` are `null` without a paper figure).
#[derive(Debug, Serialize)]
struct JsonRow {
    parameter: &'static str,
    axis: &'static str,
    truth: f64,
    estimate: f64,
    error: f64,
    sigma: f64,
    paper_accuracy: Option<f64>,
    met: Option<bool>,
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

/// Scientific notation with four significant digits (table cells).
fn scientific(value: f64) -> String {
    format!("{value:.3e}")
}

impl CalibrationResult {
    /// The rows of the blocks of one time-history sample (e.g. the last one), in the order of
    /// `parameters`, axes x, y, z.
    pub fn from_sample(sample: &TimeHistorySample, parameters: &[Parameter]) -> Self {
        let rows = parameters
            .iter()
            .flat_map(|&parameter| {
                let block = sample.block(parameter);
                Axis::ALL.map(|axis| CalibrationRow {
                    parameter,
                    axis,
                    truth: block.truth[axis.index()],
                    estimate: block.estimate[axis.index()],
                    sigma: block.sigma[axis.index()],
                })
            })
            .collect();
        Self { rows }
    }

    /// Whether every row with a paper figure meets it.
    pub fn all_met(&self) -> bool {
        self.rows.iter().all(|row| row.met() != Some(false))
    }

    /// The text table: parameter (unit), axis, truth, estimate, error, 1σ, paper accuracy, met.
    pub fn table(&self) -> Table {
        let mut table = Table::new();
        table.load_preset(UTF8_FULL_CONDENSED).set_header([
            "parameter",
            "axis",
            "truth",
            "estimate",
            "error",
            "sigma (1σ)",
            "paper accuracy",
            "met",
        ]);
        for row in &self.rows {
            let right = |text: String| Cell::new(text).set_alignment(CellAlignment::Right);
            table.add_row([
                Cell::new(format!(
                    "{} ({})",
                    row.parameter.name(),
                    row.parameter.unit()
                )),
                Cell::new(row.axis.name()),
                right(scientific(row.truth)),
                right(scientific(row.estimate)),
                right(scientific(row.error())),
                right(scientific(row.sigma)),
                right(
                    row.parameter
                        .paper_accuracy()
                        .map_or_else(|| "-".to_string(), |accuracy| format!("< {accuracy:.3e}")),
                ),
                Cell::new(match row.met() {
                    Some(true) => "yes",
                    Some(false) => "no",
                    None => "-",
                }),
            ]);
        }
        table
    }

    /// The table as a JSON array, one object per row with exactly the keys `parameter`,
    /// `axis`, `truth`, `estimate`, `error`, `sigma`, `paper_accuracy`, `met`.
    ///
    /// # Errors
    /// [`ReportError::Json`] (not expected: every value is a number, a string or null).
    pub fn json(&self) -> Result<String, ReportError> {
        let rows: Vec<JsonRow> = self
            .rows
            .iter()
            .map(|row| JsonRow {
                parameter: row.parameter.name(),
                axis: row.axis.name(),
                truth: row.truth,
                estimate: row.estimate,
                error: row.error(),
                sigma: row.sigma,
                paper_accuracy: row.parameter.paper_accuracy(),
                met: row.met(),
            })
            .collect();
        Ok(serde_json::to_string_pretty(&rows)?)
    }

    /// The calibration report as one JSON object: `{"rows": [...as json()...], "met": n,
    /// "nees": x, "health": {counter: value, ...}}` (`met` counts the rows that meet the
    /// paper's figure; `nees` is `null` without a positive definite covariance).
    ///
    /// # Errors
    /// [`ReportError::Json`] if serialisation fails.
    pub fn report_json(
        &self,
        nees: Option<f64>,
        health: &nav_fsw::health::HealthCounters,
    ) -> Result<String, ReportError> {
        let rows: serde_json::Value = serde_json::from_str(&self.json()?)?;
        let met = self
            .rows
            .iter()
            .filter(|row| row.met() == Some(true))
            .count();
        let health: serde_json::Map<String, serde_json::Value> = health
            .named()
            .iter()
            .map(|(name, value)| ((*name).to_string(), (*value).into()))
            .collect();
        let report = serde_json::json!({
            "rows": rows,
            "met": met,
            "nees": nees,
            "health": health,
        });
        Ok(serde_json::to_string_pretty(&report)?)
    }
}

/// Header of a block's time-history CSV.
fn history_header() -> Vec<String> {
    let mut header = vec!["time_s".to_string()];
    for quantity in ["estimate", "sigma", "truth", "error"] {
        for axis in Axis::ALL {
            header.push(format!("{quantity}_{}", axis.name()));
        }
    }
    header
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

/// Writes one CSV per block into `directory` (`<block name>.csv`: `time_s`, `estimate_{x,y,z}`,
/// `sigma_{x,y,z}`, `truth_{x,y,z}`, `error_{x,y,z}`; floats in shortest round-trip form).
/// Each file is written whole or not at all ([`OutputFile`]). Returns the files written.
///
/// # Errors
/// [`ReportError::Output`] / [`ReportError::Csv`] naming the file.
pub fn write_time_histories(
    directory: &Path,
    history: &[TimeHistorySample],
) -> Result<Vec<PathBuf>, ReportError> {
    let mut buffer = ryu::Buffer::new();
    Parameter::ALL
        .iter()
        .map(|&parameter| {
            let path = time_history_file(directory, parameter);
            let csv_error = |line, source| ReportError::Csv {
                path: path.clone(),
                line,
                source,
            };
            let mut writer = csv::Writer::from_writer(OutputFile::create(&path)?);
            writer
                .write_record(history_header())
                .map_err(|source| csv_error(1, source))?;
            for (line, sample) in (2_u64..).zip(history) {
                let block = sample.block(parameter);
                let values = std::iter::once(sample.time_s)
                    .chain(block.estimate)
                    .chain(block.sigma)
                    .chain(block.truth)
                    .chain(block.error());
                // NaN/inf are written as Rust prints them (`NaN`, `inf`) and read back as such.
                let row: Vec<String> = values
                    .map(|value| {
                        if value.is_finite() {
                            buffer.format_finite(value).to_string()
                        } else {
                            value.to_string()
                        }
                    })
                    .collect();
                writer
                    .write_record(&row)
                    .map_err(|source| csv_error(line, source))?;
            }
            let output = writer.into_inner().map_err(|error| ReportError::Io {
                path: path.clone(),
                source: error.into_error(),
            })?;
            output.commit()?;
            Ok(path)
        })
        .collect()
}

/// Reads the time histories written by [`write_time_histories`] back.
///
/// # Errors
/// [`ReportError`] naming the file, line and column.
pub fn read_time_histories(directory: &Path) -> Result<Vec<TimeHistorySample>, ReportError> {
    let header = history_header();
    let mut history: Vec<TimeHistorySample> = Vec::new();
    for (file_number, parameter) in Parameter::ALL.into_iter().enumerate() {
        let path = directory.join(format!("{}.csv", parameter.name()));
        let csv_error = |line, source| ReportError::Csv {
            path: path.clone(),
            line,
            source,
        };
        let mut reader = csv::Reader::from_path(&path).map_err(|source| csv_error(1, source))?;
        let found = reader.headers().map_err(|source| csv_error(1, source))?;
        if found.iter().ne(header.iter().map(String::as_str)) {
            return Err(ReportError::Header {
                path: path.clone(),
                expected: header.join(","),
                found: found.iter().collect::<Vec<_>>().join(","),
            });
        }
        for (index, row) in reader.records().enumerate() {
            let row = row.map_err(|source| {
                let line = source.position().map_or(0, csv::Position::line);
                csv_error(line, source)
            })?;
            let line = row.position().map_or(0, csv::Position::line);
            let mut values = [0.0; 13];
            for (column, (value, text)) in values.iter_mut().zip(row.iter()).enumerate() {
                *value = text.parse().map_err(|_| ReportError::Invalid {
                    path: path.clone(),
                    line,
                    column: header[column].clone(),
                    value: text.to_string(),
                })?;
            }
            let [time_s, ex, ey, ez, sx, sy, sz, tx, ty, tz, ..] = values;
            if file_number == 0 {
                history.push(TimeHistorySample {
                    time_s,
                    ..TimeHistorySample::default()
                });
            }
            let sample = history
                .get_mut(index)
                .filter(|sample| sample.time_s.to_bits() == time_s.to_bits());
            let Some(sample) = sample else {
                return Err(ReportError::TimeMismatch {
                    path: path.clone(),
                    line,
                    found: time_s,
                    expected: history.get(index).map_or(f64::NAN, |sample| sample.time_s),
                });
            };
            sample.blocks[parameter.index()] = BlockSample {
                estimate: [ex, ey, ez],
                sigma: [sx, sy, sz],
                truth: [tx, ty, tz],
            };
        }
    }
    Ok(history)
}

/// One panel of a plot: curves against a common x axis.
pub(crate) struct Panel {
    pub(crate) caption: String,
    pub(crate) y_label: String,
    /// y range `(low, high)`; points beyond are clamped to the edge.
    pub(crate) y_range: (f64, f64),
    pub(crate) curves: Vec<Curve>,
}

/// One labelled line of a panel.
pub(crate) struct Curve {
    pub(crate) label: String,
    pub(crate) color: RGBColor,
    pub(crate) points: Vec<(f64, f64)>,
}

/// A symmetric y range `±limit` (±1 if the limit is zero or not finite).
fn symmetric(limit: f64) -> (f64, f64) {
    if limit.is_finite() && limit > 0.0 {
        (-limit, limit)
    } else {
        (-1.0, 1.0)
    }
}

/// Plot size (pixels).
const PLOT_SIZE: (u32, u32) = (1200, 1000);

/// Registers the embedded font with plotters once (its text rendering has no default font
/// without the system-font features).
fn register_font() -> Result<(), ReportError> {
    static REGISTERED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let registered = REGISTERED.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .is_ok()
    });
    if *registered {
        Ok(())
    } else {
        Err(ReportError::Font)
    }
}

/// Draws a PNG of `size` at `path`: a white canvas titled `title`, its area below the title
/// filled by `draw`. The file is written whole or not at all ([`OutputFile`]).
fn draw_png(
    path: &Path,
    size: (u32, u32),
    title: &str,
    draw: impl FnOnce(
        &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    ) -> Result<(), ReportError>,
) -> Result<(), ReportError> {
    register_font()?;
    let output = OutputFile::create(path)?;
    {
        let root = BitMapBackend::new(output.staging_path(), size).into_drawing_area();
        root.fill(&WHITE)
            .map_err(|error| plot_error(path, &error))?;
        let root = root
            .titled(title, ("sans-serif", 28))
            .map_err(|error| plot_error(path, &error))?;
        draw(&root)?;
        root.present().map_err(|error| plot_error(path, &error))?;
    }
    output.commit()?;
    Ok(())
}

/// Draws panels stacked vertically into a PNG, all with the x axis `x_label`.
pub(crate) fn draw_panels(
    path: &Path,
    title: &str,
    x_label: &str,
    panels: &[Panel],
) -> Result<(), ReportError> {
    let x_ranges = panels
        .iter()
        .map(panel_x_range)
        .collect::<Result<Vec<_>, _>>()?;
    draw_png(path, PLOT_SIZE, title, |root| {
        for ((area, panel), x_range) in root
            .split_evenly((panels.len(), 1))
            .iter()
            .zip(panels)
            .zip(x_ranges)
        {
            draw_linear_panel(path, area, panel, x_range, x_label)?;
        }
        Ok(())
    })
}

/// A plotting failure on the file `path`.
fn plot_error(path: &Path, error: &dyn std::fmt::Display) -> ReportError {
    ReportError::Plot {
        path: path.to_path_buf(),
        message: error.to_string(),
    }
}

/// The x range spanned by a panel's points (each panel spans its own).
fn panel_x_range(panel: &Panel) -> Result<(f64, f64), ReportError> {
    let (start, end) = panel
        .curves
        .iter()
        .flat_map(|curve| &curve.points)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(low, high), (x, _)| {
            (low.min(*x), high.max(*x))
        });
    if !(start.is_finite() && end.is_finite()) {
        return Err(ReportError::Empty);
    }
    Ok((start, if end > start { end } else { start + 1.0 }))
}

/// Adds a curve's legend entry (an unlabelled curve has none).
fn label_series<DB: DrawingBackend>(
    series: &mut plotters::chart::SeriesAnno<'_, DB>,
    curve: &Curve,
) {
    if !curve.label.is_empty() {
        let color = curve.color;
        series
            .label(&curve.label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color));
    }
}

/// Draws one panel with a linear y axis into `area`; points beyond the y range are clamped to
/// its edge.
fn draw_linear_panel(
    path: &Path,
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    panel: &Panel,
    (x_start, x_end): (f64, f64),
    x_label: &str,
) -> Result<(), ReportError> {
    let (low, high) = panel.y_range;
    let (low, high) = if low.is_finite() && high.is_finite() && high > low {
        (low, high)
    } else {
        (-1.0, 1.0)
    };
    let span = high - low;
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.caption, ("sans-serif", 20))
        .margin(8)
        .margin_right(30)
        .x_label_area_size(35)
        .y_label_area_size(90)
        .build_cartesian_2d(x_start..x_end, low..high)
        .map_err(|error| plot_error(path, &error))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(&panel.y_label)
        // Tick values are computed by stepping, so zero comes out as ±1e-21 or so.
        .y_label_formatter(&|value| {
            if value.abs() < 1e-9 * span {
                "0".to_string()
            } else {
                format!("{value:.1e}")
            }
        })
        .draw()
        .map_err(|error| plot_error(path, &error))?;
    for curve in &panel.curves {
        let points = curve
            .points
            .iter()
            .filter(|(_, value)| !value.is_nan())
            .map(|&(x, value)| (x, value.clamp(low, high)));
        let series = chart
            .draw_series(LineSeries::new(points, curve.color.stroke_width(2)))
            .map_err(|error| plot_error(path, &error))?;
        label_series(series, curve);
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|error| plot_error(path, &error))?;
    Ok(())
}

/// Draws one panel with a logarithmic y axis into `area`. `panel.y_range` must be positive;
/// values below its bottom (zero crossings of an |error|) are drawn at the bottom edge, values
/// above its top at the top edge.
fn draw_log_panel(
    path: &Path,
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    panel: &Panel,
    (x_start, x_end): (f64, f64),
    x_label: &str,
) -> Result<(), ReportError> {
    let (low, high) = panel.y_range;
    let (low, high) = if low.is_finite() && high.is_finite() && low > 0.0 && high > low {
        (low, high)
    } else {
        (1e-3, 1.0)
    };
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.caption, ("sans-serif", 20))
        .margin(8)
        .margin_right(30)
        .x_label_area_size(35)
        .y_label_area_size(90)
        .build_cartesian_2d(x_start..x_end, (low..high).log_scale())
        .map_err(|error| plot_error(path, &error))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(&panel.y_label)
        .y_label_formatter(&|value| format!("{value:.0e}"))
        .draw()
        .map_err(|error| plot_error(path, &error))?;
    for curve in &panel.curves {
        let points = curve
            .points
            .iter()
            .filter(|(_, value)| !value.is_nan())
            .map(|&(x, value)| (x, value.clamp(low, high)));
        let series = chart
            .draw_series(LineSeries::new(points, curve.color.stroke_width(2)))
            .map_err(|error| plot_error(path, &error))?;
        label_series(series, curve);
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|error| plot_error(path, &error))?;
    Ok(())
}

/// Size of a block plot (pixels): two columns of panels.
const BLOCK_PLOT_SIZE: (u32, u32) = (1800, 1000);

/// Draws rows of panel pairs into a PNG: the left panel of each row with a linear y axis, the
/// right one with a logarithmic y axis; all with the x axis `x_label`.
pub(crate) fn draw_linear_and_log_panels(
    path: &Path,
    title: &str,
    x_label: &str,
    rows: &[(Panel, Panel)],
) -> Result<(), ReportError> {
    draw_png(path, BLOCK_PLOT_SIZE, title, |root| {
        let areas = root.split_evenly((rows.len(), 2));
        for ((linear, log), areas) in rows.iter().zip(areas.chunks(2)) {
            if let [linear_area, log_area] = areas {
                draw_linear_panel(path, linear_area, linear, panel_x_range(linear)?, x_label)?;
                draw_log_panel(path, log_area, log, panel_x_range(log)?, x_label)?;
            }
        }
        Ok(())
    })
}

/// Largest finite absolute value (0 if none).
fn largest_magnitude(values: impl Iterator<Item = f64>) -> f64 {
    values
        .filter(|value| value.is_finite())
        .fold(0.0, |largest, value| largest.max(value.abs()))
}

/// The first sample of the converged window of a run of `len` samples: its second half, long
/// after the calibration manoeuvres of the paper's flight have made every state observable.
fn converged_window_start(len: usize) -> usize {
    len / 2
}

/// The plot of one block, a row per axis with two panels:
/// - left, the paper's view (its Figs. 1-5): `estimate − truth` and `±3σ` over the whole run,
///   on a linear scale of ±1.2 × the largest |error| and 3σ of the run's second half (the
///   converged window), so the band the estimate settles in is readable; the larger transient
///   before it is clipped at the panel edge;
/// - right, the converged accuracy: `|estimate − truth|`, `1σ` and the paper's accuracy figure
///   (where it has one) on a logarithmic scale, so the error after convergence, which is orders
///   of magnitude below the prior, stays readable.
///
/// # Errors
/// [`ReportError::Empty`], [`ReportError::Plot`], [`ReportError::Font`] or
/// [`ReportError::Output`] (the file cannot be created or replaced).
pub fn plot_block(
    path: &Path,
    history: &[TimeHistorySample],
    parameter: Parameter,
) -> Result<(), ReportError> {
    if history.is_empty() {
        return Err(ReportError::Empty);
    }
    let accuracy = parameter.paper_accuracy();
    let rows: Vec<(Panel, Panel)> = Axis::ALL
        .iter()
        .map(|&axis| {
            let axis_index = axis.index();
            let series = |value: &dyn Fn(&BlockSample) -> f64| -> Vec<(f64, f64)> {
                history
                    .iter()
                    .map(|sample| (sample.time_s, value(sample.block(parameter))))
                    .collect()
            };
            let error = series(&|block| block.error()[axis_index]);
            let sigma = series(&|block| block.sigma[axis_index]);
            // The y scale of the converged window: the largest |error| and 3σ of its samples.
            let window = converged_window_start(history.len());
            let limit = 1.2
                * largest_magnitude(error[window..].iter().map(|(_, value)| *value))
                    .max(3.0 * largest_magnitude(sigma[window..].iter().map(|(_, value)| *value)));
            let caption = format!("{} {}", parameter.name(), axis.name());
            let linear = Panel {
                caption: format!("{caption}: y scaled to the run's second half"),
                y_label: format!("estimate − truth ({})", parameter.unit()),
                y_range: symmetric(limit),
                curves: vec![
                    Curve {
                        label: "estimate − truth".to_string(),
                        color: BLUE,
                        points: error.clone(),
                    },
                    Curve {
                        label: "+3σ".to_string(),
                        color: RED,
                        points: sigma.iter().map(|&(t, value)| (t, 3.0 * value)).collect(),
                    },
                    Curve {
                        label: "−3σ".to_string(),
                        color: RED,
                        points: sigma.iter().map(|&(t, value)| (t, -3.0 * value)).collect(),
                    },
                ],
            };
            let magnitude: Vec<(f64, f64)> =
                error.iter().map(|&(t, value)| (t, value.abs())).collect();
            let mut log_curves = vec![
                Curve {
                    label: "|estimate − truth|".to_string(),
                    color: BLUE,
                    points: magnitude,
                },
                Curve {
                    label: "1σ".to_string(),
                    color: RED,
                    points: sigma.clone(),
                },
            ];
            if let Some(accuracy) = accuracy {
                log_curves.push(Curve {
                    label: "paper's accuracy".to_string(),
                    color: BLACK,
                    points: sigma.iter().map(|&(t, _)| (t, accuracy)).collect(),
                });
            }
            let log = Panel {
                caption: format!("{caption}: |error| and 1σ"),
                y_label: format!("|estimate − truth| ({})", parameter.unit()),
                y_range: log_range(&log_curves),
                curves: log_curves,
            };
            (linear, log)
        })
        .collect();
    draw_linear_and_log_panels(
        path,
        &format!(
            "{}: estimate − truth and ±3σ (left), |estimate − truth| and 1σ on a log scale (right)",
            parameter.name()
        ),
        "time (s)",
        &rows,
    )
}

/// How far below the smallest 1σ or accuracy value a log panel reaches (a decade), so an
/// |error| well inside its 1σ stays visible.
const LOG_FLOOR_FACTOR: f64 = 10.0;

/// A logarithmic y range for `curves` (the |error| first, then 1σ and the accuracy): from
/// [`LOG_FLOOR_FACTOR`] below the smallest positive value of the curves after the first (the
/// |error|'s zero crossings have no floor) to twice the largest value of all.
fn log_range(curves: &[Curve]) -> (f64, f64) {
    let values = |curves: &[Curve]| -> Vec<f64> {
        curves
            .iter()
            .flat_map(|curve| curve.points.iter().map(|(_, value)| *value))
            .filter(|value| value.is_finite() && *value > 0.0)
            .collect()
    };
    let high = 2.0 * values(curves).into_iter().fold(0.0, f64::max);
    let floor = values(curves.get(1..).unwrap_or_default())
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    (floor / LOG_FLOOR_FACTOR, high)
}

/// The navigation-error plot: a panel per navigation block (attitude, position, velocity) with
/// `estimate − truth` on each axis.
///
/// # Errors
/// As [`plot_block`].
pub fn plot_navigation_errors(
    path: &Path,
    history: &[TimeHistorySample],
) -> Result<(), ReportError> {
    if history.is_empty() {
        return Err(ReportError::Empty);
    }
    let colors = [RED, GREEN, BLUE];
    let panels: Vec<Panel> = Parameter::NAVIGATION
        .iter()
        .map(|&parameter| {
            let curves: Vec<Curve> = Axis::ALL
                .iter()
                .zip(colors)
                .map(|(&axis, color)| Curve {
                    label: axis.name().to_string(),
                    color,
                    points: history
                        .iter()
                        .map(|sample| {
                            (sample.time_s, sample.block(parameter).error()[axis.index()])
                        })
                        .collect(),
                })
                .collect();
            let limit = 1.2
                * largest_magnitude(
                    curves
                        .iter()
                        .flat_map(|curve| curve.points.iter().map(|(_, value)| *value)),
                );
            Panel {
                caption: parameter.name().to_string(),
                y_label: format!("error ({})", parameter.unit()),
                y_range: symmetric(limit),
                curves,
            }
        })
        .collect();
    draw_panels(
        path,
        "navigation errors (estimate − truth)",
        "time (s)",
        &panels,
    )
}

/// Writes every plot into `directory`: `<block name>.png` for each block and
/// `navigation_errors.png`. Returns the files written.
///
/// # Errors
/// As [`plot_block`].
pub fn write_plots(
    directory: &Path,
    history: &[TimeHistorySample],
) -> Result<Vec<PathBuf>, ReportError> {
    let mut written = Vec::new();
    for parameter in Parameter::ALL {
        let path = plot_file(directory, parameter);
        plot_block(&path, history, parameter)?;
        written.push(path);
    }
    let path = navigation_plot_file(directory);
    plot_navigation_errors(&path, history)?;
    written.push(path);
    Ok(written)
}

/// The table as plain text with a summary line (for terminals and logs).
pub fn summary(result: &CalibrationResult) -> String {
    let mut text = result.table().to_string();
    let with_figure = result.rows.iter().filter(|row| row.met().is_some()).count();
    let met = result
        .rows
        .iter()
        .filter(|row| row.met() == Some(true))
        .count();
    let _ = write!(
        text,
        "\n{met} of {with_figure} parameter axes meet the paper's accuracy"
    );
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(
        parameter: Parameter,
        axis: Axis,
        truth: f64,
        estimate: f64,
        sigma: f64,
    ) -> CalibrationRow {
        CalibrationRow {
            parameter,
            axis,
            truth,
            estimate,
            sigma,
        }
    }

    fn known_result() -> CalibrationResult {
        CalibrationResult {
            rows: vec![
                // Error 2e-7 < 1e-6: met.
                row(Parameter::GyroScaleFactor, Axis::X, 3e-5, 3.02e-5, 1e-7),
                // Error exactly the paper's 1e-6: "better than" is strict, so not met.
                row(Parameter::GyroScaleFactor, Axis::Y, 0.0, 1e-6, 1e-7),
                // Error −3e-4, |error| > 2.75e-4: not met.
                row(Parameter::AccelerometerBias, Axis::Z, 1e-3, 7e-4, 5e-5),
                // No paper figure.
                row(Parameter::Position, Axis::X, 0.0, 2.5, 3.0),
            ],
        }
    }

    #[test]
    fn met_is_strictly_better_than_the_paper() {
        let result = known_result();
        let met: Vec<Option<bool>> = result.rows.iter().map(CalibrationRow::met).collect();
        assert_eq!(met, [Some(true), Some(false), Some(false), None]);
        assert!(!result.all_met());
        let just_inside = row(
            Parameter::GyroScaleFactor,
            Axis::Y,
            0.0,
            1e-6 * (1.0 - 1e-15),
            1e-7,
        );
        assert_eq!(just_inside.met(), Some(true));
        let nan = row(Parameter::GyroBias, Axis::X, 0.0, f64::NAN, 1e-7);
        assert_eq!(nan.met(), Some(false));
        assert!(CalibrationResult {
            rows: vec![result.rows[0], result.rows[3]]
        }
        .all_met());
    }

    #[test]
    fn table_shows_every_column() {
        let text = summary(&known_result());
        println!("{text}");
        let lines: Vec<&str> = text.lines().collect();
        let header = lines
            .iter()
            .find(|line| line.contains("parameter"))
            .unwrap();
        for column in [
            "axis",
            "truth",
            "estimate",
            "error",
            "sigma",
            "paper accuracy",
            "met",
        ] {
            assert!(header.contains(column), "{column}");
        }
        let gyro_x = lines
            .iter()
            .find(|line| line.contains("gyro_scale_factor (-)") && line.contains(" x "))
            .unwrap();
        for cell in [
            "3.000e-5",
            "3.020e-5",
            "2.000e-7",
            "1.000e-7",
            "< 1.000e-6",
            "yes",
        ] {
            assert!(gyro_x.contains(cell), "{cell} in {gyro_x}");
        }
        let accel = lines
            .iter()
            .find(|line| line.contains("accel_bias (m/s²)"))
            .unwrap();
        assert!(
            accel.contains("-3.000e-4") && accel.contains("< 2.750e-4") && accel.contains(" no "),
            "{accel}"
        );
        let position = lines
            .iter()
            .find(|line| line.contains("position (m)"))
            .unwrap();
        assert!(position.contains(" - "), "{position}");
        assert!(text.ends_with("1 of 3 parameter axes meet the paper's accuracy"));
    }

    #[test]
    fn json_has_exactly_the_documented_keys() {
        let json: serde_json::Value =
            serde_json::from_str(&known_result().json().unwrap()).unwrap();
        let rows = json.as_array().unwrap();
        assert_eq!(rows.len(), 4);
        for row in rows {
            let mut keys: Vec<&str> = row
                .as_object()
                .unwrap()
                .keys()
                .map(String::as_str)
                .collect();
            keys.sort_unstable();
            assert_eq!(
                keys,
                [
                    "axis",
                    "error",
                    "estimate",
                    "met",
                    "paper_accuracy",
                    "parameter",
                    "sigma",
                    "truth"
                ]
            );
        }
        assert_eq!(rows[0]["parameter"], "gyro_scale_factor");
        assert_eq!(rows[0]["axis"], "x");
        assert!((rows[0]["error"].as_f64().unwrap() - 2e-7).abs() < 1e-20);
        assert_eq!(
            rows[0]["paper_accuracy"].as_f64().unwrap().to_bits(),
            1e-6_f64.to_bits()
        );
        assert_eq!(rows[0]["met"], true);
        assert_eq!(rows[1]["met"], false);
        assert_eq!(rows[2]["axis"], "z");
        assert_eq!(rows[2]["met"], false);
        assert!(rows[3]["paper_accuracy"].is_null() && rows[3]["met"].is_null());
    }

    /// A synthetic run: every block converges from −truth towards the truth with a shrinking σ.
    fn synthetic_history() -> Vec<TimeHistorySample> {
        (0..=400)
            .map(|step| {
                let time_s = 600.0 + 0.5 * f64::from(step);
                let decay = (-(time_s - 600.0) / 40.0).exp();
                let mut sample = TimeHistorySample {
                    time_s,
                    ..TimeHistorySample::default()
                };
                for parameter in Parameter::ALL {
                    let scale = parameter.paper_accuracy().unwrap_or(1.0);
                    let truth = [10.0, 20.0, -30.0].map(|value| value * scale);
                    sample.blocks[parameter.index()] = BlockSample {
                        truth,
                        estimate: truth.map(|value| {
                            value * (1.0 - decay) + 0.1 * scale * (time_s / 7.0).sin()
                        }),
                        sigma: [1.0, 2.0, 3.0].map(|value| value * scale * (0.05 + 20.0 * decay)),
                    };
                }
                sample
            })
            .collect()
    }

    #[test]
    fn time_histories_round_trip_through_csv() {
        let directory = tempfile::tempdir().unwrap();
        let history = synthetic_history();
        let files = write_time_histories(directory.path(), &history).unwrap();
        assert_eq!(files.len(), 8);
        assert!(files[3].ends_with("gyro_bias.csv"));
        let read = read_time_histories(directory.path()).unwrap();
        assert_eq!(read.len(), history.len());
        let bits = |history: &[TimeHistorySample]| -> Vec<u64> {
            history
                .iter()
                .flat_map(|sample| {
                    std::iter::once(sample.time_s).chain(sample.blocks.iter().flat_map(|block| {
                        block
                            .estimate
                            .into_iter()
                            .chain(block.sigma)
                            .chain(block.truth)
                    }))
                })
                .map(f64::to_bits)
                .collect()
        };
        assert_eq!(bits(&read), bits(&history));

        let text = std::fs::read_to_string(directory.path().join("position.csv")).unwrap();
        assert!(text.starts_with("time_s,estimate_x,estimate_y,estimate_z,sigma_x,"));

        // A damaged cell is named by file, line and column.
        let damaged = text.replacen("600.5,", "600.5x,", 1);
        std::fs::write(directory.path().join("position.csv"), damaged).unwrap();
        let message = read_time_histories(directory.path())
            .unwrap_err()
            .to_string();
        assert!(
            message.ends_with("position.csv, line 3, column `time_s`: `600.5x` is not a number"),
            "{message}"
        );
    }

    #[test]
    fn log_range_spans_a_decade_below_the_sigma_to_twice_the_largest_value() {
        let curve = |points: Vec<(f64, f64)>| Curve {
            label: String::new(),
            color: BLUE,
            points,
        };
        let curves = [
            // |error|: a zero crossing (no floor) and the largest value.
            curve(vec![(0.0, 4e-3), (1.0, 0.0), (2.0, 1e-12)]),
            // 1σ falling to 2e-6, and an accuracy line above it.
            curve(vec![(0.0, 1e-3), (1.0, 1e-5), (2.0, 2e-6)]),
            curve(vec![(0.0, 5e-6), (2.0, 5e-6)]),
        ];
        let (low, high) = log_range(&curves);
        assert!((low - 2e-7).abs() < 1e-20, "{low}");
        assert!((high - 8e-3).abs() < 1e-15, "{high}");
        assert_eq!(converged_window_start(401), 200);
    }

    #[test]
    fn plots_are_written() {
        let directory = tempfile::tempdir().unwrap();
        let files = write_plots(directory.path(), &synthetic_history()).unwrap();
        assert_eq!(files.len(), 9);
        for file in &files {
            let bytes = std::fs::read(file).unwrap();
            // A PNG signature and more than a blank image's worth of data.
            assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{}", file.display());
            assert!(
                bytes.len() > 20_000,
                "{}: {} bytes",
                file.display(),
                bytes.len()
            );
        }
        // Block plots are two columns wide (linear and log panels), the navigation plot one.
        let size = |file: &Path| -> (u32, u32) {
            let bytes = std::fs::read(file).unwrap();
            let word = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
            (word(16), word(20))
        };
        assert_eq!(size(&files[0]), BLOCK_PLOT_SIZE);
        assert_eq!(size(files.last().unwrap()), PLOT_SIZE);
        assert!(matches!(
            plot_block(
                &directory.path().join("empty.png"),
                &[],
                Parameter::GyroBias
            ),
            Err(ReportError::Empty)
        ));
        if let Ok(keep) = std::env::var("NAV_SIM_KEEP_PLOTS") {
            for file in &files {
                std::fs::copy(file, Path::new(&keep).join(file.file_name().unwrap())).unwrap();
            }
        }
    }
}
