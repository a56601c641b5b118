//! The plot of `nav-sim benefit`: the error growth of the calibrated and the uncalibrated
//! filter through the aiding outage, linear and logarithmic.

use std::path::{Path, PathBuf};

use plotters::style::RGBColor;

use super::{BenefitError, Comparison, Filter, Quantity, Spread};
use crate::output::report::{self, Curve, Panel};

/// Colours of the filters' curves (calibrated, uncalibrated): mean, then the largest run.
const CURVE_COLOURS: [[RGBColor; 2]; 2] = [
    [RGBColor(0, 0, 255), RGBColor(120, 160, 255)],
    [RGBColor(220, 0, 0), RGBColor(255, 150, 150)],
];

/// Writes the error growth of both filters as a PNG: a row per quantity, linear on the left,
/// logarithmic on the right, each filter's mean over the runs (and, for several runs, its
/// largest run) against the time into the outage.
///
/// # Errors
/// [`BenefitError::NoRuns`] without comparisons; [`BenefitError::Report`] if drawing fails.
pub fn plot(path: &Path, comparisons: &[Comparison]) -> Result<PathBuf, BenefitError> {
    let first = comparisons.first().ok_or(BenefitError::NoRuns)?;
    let runs = comparisons.len();
    let rows: Vec<(Panel, Panel)> = Quantity::ALL
        .iter()
        .map(|&quantity| {
            let scale = quantity.report_scale();
            let mut curves = Vec::new();
            for (filter, [mean_colour, max_colour]) in Filter::BOTH.into_iter().zip(CURVE_COLOURS) {
                let series = |pick: fn(&Spread) -> f64| -> Vec<(f64, f64)> {
                    first
                        .run(filter)
                        .samples
                        .iter()
                        .enumerate()
                        .map(|(i, sample)| {
                            let spread = Spread::of(comparisons.iter().filter_map(|c| {
                                c.run(filter).samples.get(i).map(|s| s.error(quantity))
                            }));
                            (sample.time_into_outage_s, scale * pick(&spread))
                        })
                        .collect()
                };
                let label = if runs > 1 {
                    format!("{} (mean of {runs})", filter.name())
                } else {
                    filter.name().to_string()
                };
                curves.push(Curve {
                    label,
                    color: mean_colour,
                    points: series(|spread| spread.mean),
                });
                if runs > 1 {
                    curves.push(Curve {
                        label: format!("{} (largest)", filter.name()),
                        color: max_colour,
                        points: series(|spread| spread.max),
                    });
                }
            }
            let largest = curves
                .iter()
                .flat_map(|curve| curve.points.iter().map(|(_, value)| *value))
                .filter(|value| value.is_finite())
                .fold(0.0, f64::max);
            let smallest = curves
                .iter()
                .flat_map(|curve| curve.points.iter().map(|(_, value)| *value))
                .filter(|value| value.is_finite() && *value > 0.0)
                .fold(f64::INFINITY, f64::min);
            let linear = Panel {
                caption: quantity.label().to_string(),
                y_label: quantity.label().to_string(),
                y_range: (0.0, 1.05 * largest),
                curves,
            };
            let log = Panel {
                caption: format!("{} (log scale)", quantity.label()),
                y_label: quantity.label().to_string(),
                y_range: (0.5 * smallest, 2.0 * largest),
                curves: linear
                    .curves
                    .iter()
                    .map(|curve| Curve {
                        label: curve.label.clone(),
                        color: curve.color,
                        points: curve.points.clone(),
                    })
                    .collect(),
            };
            (linear, log)
        })
        .collect();
    report::draw_linear_and_log_panels(
        path,
        "navigation error through the aiding outage: calibrated vs calibration switched off",
        "time into the outage (s)",
        &rows,
    )?;
    Ok(path.to_path_buf())
}
