//! The calibration table: its text (comfy-table) and JSON forms and the summary line.

use std::fmt::Write as _;

use comfy_table::{presets::UTF8_FULL_CONDENSED, Cell, CellAlignment, Table};
use serde::Serialize;

use super::{Axis, CalibrationResult, CalibrationRow, Parameter, ReportError, TimeHistorySample};

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

    /// The calibration report as one JSON object: `{"scenario": {"file", "sha256"}, "rows":
    /// [...as json()...], "met": n, "nees": x, "health": {counter: value, ...}}` (`met` counts
    /// the rows that meet the paper's figure; `nees` is `null` without a positive definite
    /// covariance).
    ///
    /// # Errors
    /// [`ReportError::Json`] if serialisation fails.
    pub fn report_json(
        &self,
        nees: Option<f64>,
        health: &nav_fsw::health::HealthCounters,
        scenario: &crate::output::scenario_label::ScenarioLabel,
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
            "scenario": scenario.json(),
            "rows": rows,
            "met": met,
            "nees": nees,
            "health": health,
        });
        Ok(serde_json::to_string_pretty(&report)?)
    }
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

/// The flight software's health counters as a table of the non-zero ones (counter, value), or
/// a line saying all are zero.
///
/// # Examples
/// ```
/// let mut health = nav_fsw::health::HealthCounters::default();
/// assert_eq!(nav_sim::output::report::health_table(&health), "health counters: all zero");
/// health.star_gate_rejections = 31;
/// let text = nav_sim::output::report::health_table(&health);
/// assert!(text.contains("star_gate_rejections") && text.contains("31"));
/// assert!(!text.contains("imu_missing"));
/// ```
pub fn health_table(health: &nav_fsw::health::HealthCounters) -> String {
    let raised: Vec<(&str, u32)> = health
        .named()
        .into_iter()
        .filter(|(_, value)| *value != 0)
        .collect();
    if raised.is_empty() {
        return "health counters: all zero".to_string();
    }
    let mut table = Table::new();
    table
        .load_preset(UTF8_FULL_CONDENSED)
        .set_header(["health counter", "count"]);
    for (name, value) in raised {
        table.add_row([
            Cell::new(name),
            Cell::new(value).set_alignment(CellAlignment::Right),
        ]);
    }
    format!("health counters (the non-zero ones):\n{table}")
}
