//! The plots of a Monte Carlo campaign: NEES per run and RMS / 1σ per state, and the
//! consistency (NEES and NIS) over time, drawn through the output toolkit's panels.

use std::path::Path;

use crate::campaign::monte_carlo::{MonteCarloSummary, NisTest, OverTimeStatistics};
use crate::output::report::{self, Curve, Panel, ReportError};

impl<const N: usize> MonteCarloSummary<N> {
    /// The plot: NEES per run with the average and its 95% interval, and RMS error / mean 1σ
    /// per state (1 for a consistent filter).
    ///
    /// # Errors
    /// [`ReportError`] from the plotting.
    pub fn plot(&self, path: &Path) -> Result<(), ReportError> {
        let nees = &self.nees;
        let runs: Vec<f64> = (1..=self.runs).map(|run| run as f64).collect();
        let constant = |value: f64| runs.iter().map(|&run| (run, value)).collect::<Vec<_>>();
        let highest_nees = nees
            .per_run
            .iter()
            .copied()
            .fold(nees.upper_bound, f64::max);
        let ratios: Vec<(f64, f64)> = self
            .states
            .iter()
            .enumerate()
            .map(|(index, state)| ((index + 1) as f64, state.rms_error / state.mean_sigma))
            .collect();
        let highest_ratio = ratios.iter().map(|(_, ratio)| *ratio).fold(2.0, f64::max);
        let panels = [
            Panel {
                caption: format!("NEES per run ({} states)", nees.states),
                y_label: "NEES".to_string(),
                y_range: (0.0, 1.1 * highest_nees),
                curves: vec![
                    Curve {
                        label: "run".to_string(),
                        color: plotters::style::BLUE,
                        points: runs.iter().copied().zip(nees.per_run.clone()).collect(),
                    },
                    Curve {
                        label: "average".to_string(),
                        color: plotters::style::BLACK,
                        points: constant(nees.average),
                    },
                    Curve {
                        label: "95% interval of the average".to_string(),
                        color: plotters::style::RED,
                        points: constant(nees.lower_bound),
                    },
                    Curve {
                        label: String::new(),
                        color: plotters::style::RED,
                        points: constant(nees.upper_bound),
                    },
                ],
            },
            Panel {
                caption: "RMS error / mean filter 1σ per state (state number)".to_string(),
                y_label: "ratio".to_string(),
                y_range: (0.0, 1.1 * highest_ratio),
                curves: vec![
                    Curve {
                        label: "RMS / 1σ".to_string(),
                        color: plotters::style::BLUE,
                        points: ratios.clone(),
                    },
                    Curve {
                        label: "1".to_string(),
                        color: plotters::style::BLACK,
                        points: ratios.iter().map(|(index, _)| (*index, 1.0)).collect(),
                    },
                ],
            },
        ];
        report::draw_panels(
            path,
            "Monte Carlo consistency",
            "run (top) / state number (bottom)",
            &panels,
        )
    }

    /// The consistency over time: the average NEES over the runs at each recorded instant
    /// with its 95 % interval (top), and the average NIS of the star sensor and of the GNSS
    /// over the interval ending at each instant with their 95 % intervals (bottom; 3 for a
    /// consistent filter). Instants without a defined value are left out.
    ///
    /// # Errors
    /// [`ReportError::Empty`] if the runs carry no time series, or [`ReportError`] from the
    /// plotting.
    pub fn plot_over_time(&self, path: &Path) -> Result<(), ReportError> {
        if self.over_time.is_empty() {
            return Err(ReportError::Empty);
        }
        let series = |value: &dyn Fn(&OverTimeStatistics) -> Option<f64>| -> Vec<(f64, f64)> {
            self.over_time
                .iter()
                .filter_map(|point| Some((point.time_s, value(point)?)))
                .filter(|(time_s, value)| time_s.is_finite() && value.is_finite())
                .collect()
        };
        let highest = |curves: &[Curve], floor: f64| {
            curves
                .iter()
                .flat_map(|curve| curve.points.iter().map(|(_, value)| *value))
                .fold(floor, f64::max)
        };
        let nees_curves = vec![
            Curve {
                label: format!("average NEES over {} runs", self.runs),
                color: plotters::style::BLUE,
                points: series(&|point| Some(point.nees_average)),
            },
            Curve {
                label: "95% interval".to_string(),
                color: plotters::style::RED,
                points: series(&|point| Some(point.nees_lower_bound)),
            },
            Curve {
                label: String::new(),
                color: plotters::style::RED,
                points: series(&|point| Some(point.nees_upper_bound)),
            },
        ];
        // Each sensor's average, and its band in a lighter shade of the same colour.
        let sensor_curves =
            |sensor: &str,
             color: plotters::style::RGBColor,
             band: plotters::style::RGBColor,
             test: &dyn Fn(&OverTimeStatistics) -> Option<&NisTest>| {
                vec![
                    Curve {
                        label: format!("{sensor} NIS"),
                        color,
                        points: series(&|point| test(point).map(|test| test.average)),
                    },
                    Curve {
                        label: format!("{sensor} 95% interval"),
                        color: band,
                        points: series(&|point| test(point).map(|test| test.lower_bound)),
                    },
                    Curve {
                        label: String::new(),
                        color: band,
                        points: series(&|point| test(point).map(|test| test.upper_bound)),
                    },
                ]
            };
        let mut nis_curves = sensor_curves(
            "star sensor",
            plotters::style::BLUE,
            plotters::style::RGBColor(130, 170, 255),
            &|point| point.star_nis.as_ref(),
        );
        nis_curves.extend(sensor_curves(
            "GNSS",
            plotters::style::RGBColor(0, 150, 0),
            plotters::style::RGBColor(130, 210, 130),
            &|point| point.gnss_nis.as_ref(),
        ));
        let panels = [
            Panel {
                caption: format!("average NEES of {} states over time", self.nees.states),
                y_label: "NEES".to_string(),
                y_range: (0.0, 1.1 * highest(&nees_curves, 0.0)),
                curves: nees_curves,
            },
            Panel {
                caption: "average NIS per sensor over each interval (3 components)".to_string(),
                y_label: "NIS".to_string(),
                y_range: (0.0, 1.1 * highest(&nis_curves, 6.0)),
                curves: nis_curves,
            },
        ];
        report::draw_panels(
            path,
            "Monte Carlo consistency over time",
            "time (s)",
            &panels,
        )
    }
}
