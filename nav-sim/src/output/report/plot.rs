//! The PNG plots: panels of estimate − truth with its ±3σ envelope beside |estimate − truth|
//! and 1σ on a log scale, per block and for the navigation errors.

use std::path::{Path, PathBuf};

use plotters::prelude::*;

use super::{
    navigation_plot_file, plot_file, Axis, BlockSample, Parameter, ReportError, TimeHistorySample,
};
use crate::output::OutputFile;

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
pub(super) const PLOT_SIZE: (u32, u32) = (1200, 1000);

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
pub(super) const BLOCK_PLOT_SIZE: (u32, u32) = (1800, 1000);

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
pub(super) fn converged_window_start(len: usize) -> usize {
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
pub(super) fn log_range(curves: &[Curve]) -> (f64, f64) {
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
