//! `nav-sim gravity-omission`: the gravity a flight field of degree `N` and order `M` leaves
//! out along the scenario's truth, and the white velocity process noise that covers it
//! (`docs/guide/gravity.md`, "The omitted field as process noise").

use std::fmt::Write as _;
use std::path::PathBuf;

use comfy_table::{presets::UTF8_FULL_CONDENSED, Cell, CellAlignment, Table};
use nav_sim::studies::gravity_omission::{
    omitted_fields, truth_field, FlightGravityModel, OmissionOptions, OmissionReport,
    DEFAULT_FLIGHT_FIELDS, DEFAULT_MAX_LAG_S, DEFAULT_REFRESH_S, DEFAULT_REPORT_LAGS_S,
    DEFAULT_SAMPLE_S,
};
use nav_sim::Scenario;

use super::Failure;

/// The arguments of `nav-sim gravity-omission`.
#[derive(clap::Args)]
pub struct Args {
    /// Scenario file (TOML); its `[gravity]` table is the truth's field.
    scenario: PathBuf,
    /// Degree N of the flight field (2: J2 only); without it, a table over J2, zonal to J4,
    /// 4×4, 6×6, 8×8, 12×12 and 16×16 (those within the truth's field).
    #[arg(long)]
    flight_degree: Option<usize>,
    /// Order M of the flight field (default: the degree, a square field).
    #[arg(long, requires = "flight_degree")]
    flight_order: Option<usize>,
    /// Time between two refreshes of the flight field (s), a whole number of IMU frames.
    #[arg(long, default_value_t = DEFAULT_REFRESH_S, allow_negative_numbers = true)]
    flight_refresh_s: f64,
    /// How many refreshes old the flight's value is (1: its evaluation latency).
    #[arg(long, default_value_t = 1)]
    flight_latency_refreshes: u32,
    /// Sampling interval of the difference (s), a whole number of IMU frames.
    #[arg(long, default_value_t = DEFAULT_SAMPLE_S, allow_negative_numbers = true)]
    sample_s: f64,
    /// Largest lag L of the bound (s); the periodogram's segments are 2L long.
    #[arg(long, default_value_t = DEFAULT_MAX_LAG_S, allow_negative_numbers = true)]
    max_lag_s: f64,
    /// Turn the whole flight east about the Earth's axis by this angle (deg, -180..=180): the
    /// same flight over another ground track, as the `[dispersion] launch_longitude_deg`
    /// entry draws it.
    #[arg(long, allow_negative_numbers = true)]
    turn_deg: Option<f64>,
}

impl Args {
    /// The flight models asked for: the one given, or the default list within the truth's
    /// field.
    fn flights(&self, truth: (usize, usize)) -> Vec<FlightGravityModel> {
        let with_refresh = |(degree, order)| FlightGravityModel {
            degree,
            order,
            refresh_s: self.flight_refresh_s,
            latency_refreshes: self.flight_latency_refreshes,
        };
        match self.flight_degree {
            Some(degree) => vec![with_refresh((degree, self.flight_order.unwrap_or(degree)))],
            None => DEFAULT_FLIGHT_FIELDS
                .into_iter()
                .filter(|&(degree, order)| degree <= truth.0 && order <= truth.1)
                .map(with_refresh)
                .collect(),
        }
    }

    fn options(&self) -> OmissionOptions {
        let mut report_lags_s = DEFAULT_REPORT_LAGS_S.to_vec();
        if !report_lags_s.contains(&self.max_lag_s) {
            report_lags_s.push(self.max_lag_s);
            report_lags_s.sort_by(f64::total_cmp);
        }
        OmissionOptions {
            sample_s: self.sample_s,
            max_lag_s: self.max_lag_s,
            report_lags_s,
        }
    }
}

/// Flies the scenario's truth once and prints the omitted field of each flight model.
pub fn run(args: Args) -> Result<(), Failure> {
    let mut scenario = Scenario::load(&args.scenario)?;
    if let Some(turn_deg) = args.turn_deg {
        if !(turn_deg.is_finite() && (-180.0..=180.0).contains(&turn_deg)) {
            return Err(
                format!("--turn-deg {turn_deg} must be a number of degrees in -180..=180").into(),
            );
        }
        scenario = nav_sim::setup::dispersion::turned(&scenario, turn_deg);
    }
    let truth = truth_field(&scenario);
    let flights = args.flights(truth);
    eprintln!(
        "flying the truth of {} ({} s) ...",
        args.scenario.display(),
        scenario.duration_s()
    );
    let reports = omitted_fields(&scenario, &flights, &args.options())?;
    print!("{}", text(&args, truth, &reports));
    Ok(())
}

/// Three significant digits in scientific notation.
fn scientific(value: f64) -> String {
    format!("{value:.2e}")
}

/// The flight field's name: `J2 only`, `zonal to J4`, `8×8`, `12×4`.
fn field_name(flight: &FlightGravityModel) -> String {
    match (flight.degree, flight.order) {
        (2, 0) => "J2 only (2, 0)".to_string(),
        (degree, 0) => format!("zonal to J{degree} ({degree}, 0)"),
        (degree, order) => format!("{degree}×{order}"),
    }
}

/// The heading line, the table of the omitted field and the table of the bound against `L`.
fn text(args: &Args, truth: (usize, usize), reports: &[OmissionReport]) -> String {
    let mut text = String::new();
    let Some(first) = reports.first() else {
        return text;
    };
    let _ = writeln!(
        text,
        "{}: truth field {}×{}, {} samples every {} s, flight field refreshed every {} s and \
         {} refresh(es) old; L = {} s, periodogram: {} Hann segments of {} s",
        args.scenario.display(),
        truth.0,
        truth.1,
        first.samples,
        first.sample_s,
        args.flight_refresh_s,
        args.flight_latency_refreshes,
        first.statistics.max_lag_s,
        first.statistics.segments,
        first.statistics.segment_s,
    );
    let right = |text: String| Cell::new(text).set_alignment(CellAlignment::Right);
    let mut table = Table::new();
    table.load_preset(UTF8_FULL_CONDENSED).set_header([
        "flight field",
        "RMS |d| (m/s²)",
        "max |d| (m/s²)",
        "corr. time (s)",
        "q_bound (m²/s³)",
        "q_periodogram (m²/s³) @ f (Hz)",
        "q at f = 0 (m²/s³)",
        "q at f = 0, scaled (m²/s³)",
        "√q_bound (m/s/√s)",
        "flight check σ (m/s²)",
    ]);
    for report in reports {
        let statistics = &report.statistics;
        table.add_row([
            Cell::new(field_name(&report.flight)),
            right(scientific(statistics.rms_mps2)),
            right(scientific(statistics.max_mps2)),
            right(
                statistics
                    .correlation_time_s
                    .map_or("-".to_string(), |time_s| format!("{time_s:.1}")),
            ),
            right(scientific(statistics.q_bound_m2_s3)),
            right(format!(
                "{} @ {:.2e}",
                scientific(statistics.q_periodogram_m2_s3),
                statistics.periodogram_peak_hz
            )),
            right(scientific(statistics.q_zero_frequency_m2_s3)),
            right(if report.q_zero_frequency_scaled_m2_s3.is_nan() {
                "-".to_string()
            } else {
                scientific(report.q_zero_frequency_scaled_m2_s3)
            }),
            right(scientific(report.velocity_random_walk_mps_per_sqrt_s())),
            right(if report.flight_check_sigma_mps2.is_nan() {
                "-".to_string()
            } else {
                scientific(report.flight_check_sigma_mps2)
            }),
        ]);
    }
    let _ = writeln!(text, "{table}");
    let _ = writeln!(
        text,
        "flight check σ: the omitted field's RMS per axis at the lowest altitude ({:.0} km), \
         as the flight software checks its allowance (filter.gravity.omitted_field_sigma_mps2 \
         at least this); - beyond the flight's degree and order 12; q at f = 0: the \
         periodogram's zero-frequency bin, the density the constant calibration states see; \
         scaled: of d scaled to the field at the lowest altitude, the allowance the flight \
         software scales with the omitted field's power",
        first.lowest_altitude_m / 1e3
    );
    let _ = writeln!(text, "q_bound (m²/s³) against the largest lag L:");
    let _ = writeln!(text, "{}", lag_table(reports));
    text
}

/// `q_bound` at each reported `L` (columns), per flight field (rows).
fn lag_table(reports: &[OmissionReport]) -> Table {
    let right = |text: String| Cell::new(text).set_alignment(CellAlignment::Right);
    let mut table = Table::new();
    let mut header = vec!["flight field".to_string()];
    if let Some(first) = reports.first() {
        header.extend(first.statistics.bounds_by_lag.iter().map(|bound| {
            if (bound.used_lag_s - bound.max_lag_s).abs() > 1e-9 * bound.max_lag_s {
                format!("L = {} s (record: {} s)", bound.max_lag_s, bound.used_lag_s)
            } else {
                format!("L = {} s", bound.max_lag_s)
            }
        }));
    }
    table.load_preset(UTF8_FULL_CONDENSED).set_header(header);
    for report in reports {
        let mut row = vec![Cell::new(field_name(&report.flight))];
        row.extend(
            report
                .statistics
                .bounds_by_lag
                .iter()
                .map(|bound| right(scientific(bound.q_bound_m2_s3))),
        );
        table.add_row(row);
    }
    table
}
