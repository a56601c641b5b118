//! The observability heat map: the degree of each state per case, as a PNG in Noto Sans.

use std::path::Path;

use nav_core::state::STATE_DIMENSION;

use super::{state_name, CaseReport, ObservabilityReport, ObservabilityReportError, StateReport};

/// Lower end of the heat map's colour scale, log10 of the degree.
const HEAT_MAP_LOG10_MIN: f64 = -12.0;
/// The family name the embedded font is registered under (plotters' ab_glyph backend).
const FONT_FAMILY: &str = "sans-serif";

/// Heat-map cell colour: viridis over log10(degree) in [−12, 0]; grey when the state fails the
/// null-space test; white when it passes but was assigned no singular value (degree 0).
fn cell_colour(state: &StateReport) -> plotters::style::RGBColor {
    use plotters::style::colors::colormaps::{ColorMap, ViridisRGB};
    if !state.observable {
        return plotters::style::RGBColor(200, 200, 200);
    }
    if state.degree <= 0.0 {
        // Observable, but the largest-component rule assigned it no singular value.
        return plotters::style::RGBColor(255, 255, 255);
    }
    let level = state.degree.log10().clamp(HEAT_MAP_LOG10_MIN, 0.0);
    ViridisRGB.get_color_normalized(level, HEAT_MAP_LOG10_MIN, 0.0)
}

/// Writes the heat map (PNG) of the degree per state (rows) per case (columns): left panel the
/// paper's states and the phases after the previous ones, right panel each phase alone.
///
/// # Errors
/// [`ObservabilityReportError::Plot`] if the font cannot be loaded or drawing/encoding fails.
pub fn write_heat_map(
    report: &ObservabilityReport,
    path: &Path,
) -> Result<(), ObservabilityReportError> {
    use plotters::prelude::*;
    let fail = |message: String| ObservabilityReportError::Plot {
        path: path.display().to_string(),
        message,
    };
    plotters::style::register_font(FONT_FAMILY, FontStyle::Normal, ttf_noto_sans::REGULAR)
        .map_err(|_| fail("the embedded Noto Sans font is not a valid font".to_string()))?;

    let mut left: Vec<(String, &CaseReport)> = report
        .paper_states
        .iter()
        .map(|c| (c.label.clone(), c))
        .collect();
    left.extend(
        report
            .phases
            .iter()
            .map(|p| (format!("1-{}", p.index), &p.after_previous)),
    );
    let right: Vec<(String, &CaseReport)> = report
        .phases
        .iter()
        .map(|p| (p.index.to_string(), &p.alone))
        .collect();

    let root = BitMapBackend::new(path, (1500, 820)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(e.to_string()))?;
    let (body, footer) = root.split_vertically(780);
    let (left_area, right_area) = body.split_horizontally(880);
    draw_panel(
        &left_area,
        "Degree σk/σmax: paper states I, II, III, I→II, I→III; phases 1..k",
        &left,
        true,
    )
    .map_err(fail)?;
    draw_panel(&right_area, "Each phase alone", &right, false).map_err(fail)?;
    footer
        .draw(&Text::new(
            "colour: log10(degree) from -12 (dark blue) to 0 (yellow), scaled continuous PWCS; grey: unobservable (null-space test); white: observable, no singular value assigned",
            (20, 10),
            (FONT_FAMILY, 16).into_font(),
        ))
        .map_err(|e| fail(e.to_string()))?;
    root.present().map_err(|e| fail(e.to_string()))?;
    Ok(())
}

/// One heat-map panel: 24 named rows, one column per case.
fn draw_panel<DB: plotters::prelude::DrawingBackend>(
    area: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    columns: &[(String, &CaseReport)],
    row_names: bool,
) -> Result<(), String> {
    use plotters::prelude::*;
    let column_count = u32::try_from(columns.len()).map_err(|e| e.to_string())?;
    let row_count = u32::try_from(STATE_DIMENSION).map_err(|e| e.to_string())?;
    let mut chart = ChartBuilder::on(area)
        .caption(title, (FONT_FAMILY, 18))
        .margin(8)
        .x_label_area_size(28)
        .y_label_area_size(if row_names { 170 } else { 10 })
        // plotters' integer ranges include their end: 0..n−1 gives n segments.
        .build_cartesian_2d(
            (0..column_count.saturating_sub(1)).into_segmented(),
            (0..row_count.saturating_sub(1)).into_segmented(),
        )
        .map_err(|e| e.to_string())?;
    let label_of = |value: &SegmentValue<u32>| match value {
        SegmentValue::CenterOf(i) | SegmentValue::Exact(i) => *i,
        SegmentValue::Last => u32::MAX,
    };
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(columns.len())
        .y_labels(STATE_DIMENSION)
        .x_label_formatter(&|value| {
            usize::try_from(label_of(value))
                .ok()
                .and_then(|i| columns.get(i))
                .map_or_else(String::new, |(name, _)| name.clone())
        })
        .y_label_formatter(&|value| {
            if !row_names {
                return String::new();
            }
            // Row 0 is at the bottom: the first state is drawn at the top.
            usize::try_from(label_of(value))
                .ok()
                .and_then(|row| STATE_DIMENSION.checked_sub(row + 1))
                .map_or_else(String::new, state_name)
        })
        .label_style((FONT_FAMILY, 13))
        .draw()
        .map_err(|e| e.to_string())?;
    let mut cells = Vec::new();
    for (column, (_, case)) in (0u32..).zip(columns) {
        for (row, state) in (0..row_count).rev().zip(&case.states) {
            cells.push(Rectangle::new(
                [
                    (SegmentValue::Exact(column), SegmentValue::Exact(row)),
                    (
                        SegmentValue::Exact(column + 1),
                        SegmentValue::Exact(row + 1),
                    ),
                ],
                cell_colour(state).filled(),
            ));
        }
    }
    chart.draw_series(cells).map_err(|e| e.to_string())?;
    Ok(())
}
