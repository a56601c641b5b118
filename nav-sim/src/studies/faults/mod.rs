//! The fault-injection campaign: one flight per fault class through the flight
//! software (nav-fsw), each with its injected fault, its expected reaction, the health
//! counters that must count it, and its pass criteria, checked here and printed as a table
//! (`nav-sim faults`, `tests-host/tests/fault_campaign.rs`).
//!
//! **Flights.** A row flies a prefix of the scenario: the first [`SHORT_FLIGHT_S`] (480 s of
//! the default one: 20 s coast, three 1800° rotations, 300 s coast, the +x burn, 62 s coast)
//! when its injection lasts at most [`SHORT_INJECTION_LIMIT_S`], else (the 600 s outages and
//! ramp) the first [`LONG_FLIGHT_S`] (800 s: also 319 s coast, the +y burn, 22 s coast). The
//! rows run in parallel (rayon).
//! **Injection** starts [`FAULT_START_S`] (100 s) after the scenario start, in the quiet coast
//! after the three rotations: the attitude, the gyro biases, the star installation error and
//! the gyro scale factors have been observed, the accelerometer errors wait for the burns
//! that follow the fault (so a fault that corrupted the filter would show in them).
//!
//! **Common criteria, checked for every row:**
//! * no panic (each flight runs under `catch_unwind`; a panic fails the row);
//! * from the fault start on, the error state, the covariance, the navigation solution and the
//!   calibration estimate are finite at every frame;
//! * the covariance is symmetric (`max |P − Pᵀ| ≤ 1e-12 max |P|`) and positive definite
//!   (Cholesky succeeds) at every frame of the first [`DENSE_CHECK_S`] of the count window
//!   (the injection and 1 s after; 10 s covers every short injection whole) and every
//!   [`SPD_CHECK_INTERVAL_S`] (every 50 frames at 500 Hz) otherwise, to keep the cost of the
//!   check below that of the flight;
//! * each named counter increased over the count window by exactly (or at least) the
//!   expected amount;
//! * no filter reset (no class's documented reaction is a reset; a reset would have to be
//!   exactly one) and each sensor declared faulty exactly as often as the row expects;
//! * at the end of the flight every one of the 15 calibration states is within 3σ of its
//!   truth (`|e_i| ≤ 3 √P_ii`, filter coordinates). Per axis, not the joint NEES: the rows
//!   share one seed and one truth, so they are one draw, not 15 × rows independent chances to
//!   fail; the no-fault control row shows the margin of that draw (its NEES is printed too).
//!
//! Rows whose honest reaction cannot meet a criterion say so in their reaction text and carry
//! the criterion they meet instead ([`Criterion`]).
//!
//! **Frames.** The rows give their injection times in seconds from the fault start; a
//! [`FrameSchedule`] turns them into frames at the scenario's IMU rate (`imu.rate_hz`), so the
//! faults fall at the same times whatever the rate. The files: `table/` (the rows, by
//! family), `injection.rs` (how a fault is injected into the frame ports), `monitor.rs` (what
//! is observed and asserted about the reaction), this one (the runner and its table).

mod injection;
mod monitor;
mod table;
#[cfg(test)]
mod tests;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicU64, Ordering};

use comfy_table::{presets::UTF8_FULL_CONDENSED, Cell, CellAlignment, ContentArrangement, Table};
use nalgebra::Vector3;
use nav_fsw::health::HealthCounters;
use rayon::prelude::*;

use crate::harness::flight::{fly_observed, FlightError, FlightOptions, FlightResult};
use crate::scenario::Scenario;
use crate::setup::fsw::fsw_config;

pub use injection::{FrameSchedule, Injector};
pub use monitor::{Counter, Criterion, Expected};
pub use table::{campaign, campaign_at, campaign_for};

use monitor::Monitor;

/// Flight length of a row whose injection lasts at most [`SHORT_INJECTION_LIMIT_S`] (s, from
/// the scenario start).
pub const SHORT_FLIGHT_S: f64 = 480.0;
/// Flight length of the other rows (s).
pub const LONG_FLIGHT_S: f64 = 800.0;
/// Longest injection flown on the short flight (s).
pub const SHORT_INJECTION_LIMIT_S: f64 = 100.0;
/// `P` is checked positive definite at every frame of the first this-many seconds of the
/// count window.
pub const DENSE_CHECK_S: f64 = 10.0;
/// Start of every injection, after the scenario start (s).
pub const FAULT_START_S: f64 = 100.0;
/// Outside the dense window, `P` is checked positive definite at this interval (s; in frames
/// of the scenario's IMU rate, at least every frame).
pub const SPD_CHECK_INTERVAL_S: f64 = 0.1;
/// The count window extends this long past the last injected frame (s): a measurement is
/// fused within a frame of its arrival, an outage counted 2 s into it.
pub const COUNT_MARGIN_S: f64 = 1.0;
/// Width of the printed table (characters; cells wrap).
pub const TABLE_WIDTH: u16 = 160;
/// Calibration criterion: every state within this many σ of its truth.
pub const CALIBRATION_SIGMA_BOUND: f64 = 3.0;

/// One fault class of the campaign.
pub struct FaultClass {
    /// Short name.
    pub name: &'static str,
    /// What is injected, when (relative to [`FAULT_START_S`]).
    pub injected: &'static str,
    /// The documented reaction (README's fault table).
    pub reaction: &'static str,
    /// Counters that must count it over the count window.
    pub counts: Vec<(Counter, Expected)>,
    /// Injection length (s from the fault start); the count window adds [`COUNT_MARGIN_S`].
    pub injection_s: f64,
    /// Times the star sensor and the GNSS receiver must be declared faulty (whole flight).
    pub declared_faulty: [u32; 2],
    /// End-of-flight criterion.
    pub criterion: Criterion,
    /// A change to the row's flight (an inserted manoeuvre, a filter setting), applied to
    /// the scenario prefix before the flight; `None` flies the prefix as it is.
    pub scenario_change: Option<fn(&mut Scenario)>,
    /// Builds the injector (a fresh one per flight) for the frames of the flight's IMU rate.
    pub injector: fn(FrameSchedule) -> Injector,
}

/// What a row's flight showed.
#[derive(Debug, Clone)]
pub struct RowOutcome {
    /// The class's name.
    pub name: &'static str,
    /// Observed increase of each expected counter over the count window.
    pub observed: Vec<u32>,
    /// Worst `|e_i| / σ_i` over the 15 calibration states at the end.
    pub worst_calibration_sigma: f64,
    /// NEES of the 15 calibration states at the end (None if `P` not positive definite).
    pub calibration_nees: Option<f64>,
    /// Final position error per axis, estimate − truth (m).
    pub position_error_m: [f64; 3],
    /// Health counters at the end of the flight.
    pub health: HealthCounters,
    /// Frames on which `P` was checked positive definite.
    pub definiteness_checks: u64,
    /// Every failed criterion, in words (empty: the row is met).
    pub failures: Vec<String>,
}

impl RowOutcome {
    /// All criteria met.
    pub fn met(&self) -> bool {
        self.failures.is_empty()
    }
}

/// The campaign's result.
pub struct CampaignResult {
    /// The classes, in row order.
    pub classes: Vec<FaultClass>,
    /// One outcome per class.
    pub outcomes: Vec<RowOutcome>,
    /// Wall time (s).
    pub wall_time_s: f64,
}

// ---------------------------------------------------------------------------------------
// Running a row.

/// The first `prefix_s` of `scenario` (cut in a constant segment, or at the end of the
/// ramped segment that contains the cut).
pub fn scenario_prefix(scenario: &Scenario, prefix_s: f64) -> Scenario {
    let mut prefix = scenario.clone();
    let mut elapsed_s = 0.0;
    let mut kept = Vec::new();
    for segment in &scenario.manoeuvres {
        if elapsed_s >= prefix_s - 1e-9 {
            break;
        }
        let mut segment = segment.clone();
        let remaining_s = prefix_s - elapsed_s;
        if segment.duration_s > remaining_s && segment.ramp_s == 0.0 {
            segment.duration_s = remaining_s;
        }
        elapsed_s += segment.duration_s;
        kept.push(segment);
    }
    prefix.manoeuvres = kept;
    prefix
}

/// Flies one row on the (prefix) scenario and checks every criterion.
pub fn run_row(scenario: &Scenario, class: &FaultClass) -> Result<RowOutcome, FlightError> {
    let mut changed = scenario.clone();
    if let Some(change) = class.scenario_change {
        change(&mut changed);
    }
    let scenario = &changed;
    let frames = FrameSchedule::of(scenario);
    let fault_frame = frames.frames(FAULT_START_S);
    let window_end = frames.frames(class.injection_s + COUNT_MARGIN_S);
    let dense_end = window_end.min(frames.frames(DENSE_CHECK_S));
    let check_interval = frames.frames(SPD_CHECK_INTERVAL_S).max(1);
    let config = fsw_config(scenario)?;
    let mut monitor = Monitor::default();
    let mut inject = (class.injector)(frames);
    let flown = catch_unwind(AssertUnwindSafe(|| {
        fly_observed(
            scenario,
            config,
            FlightOptions {
                record_interval_s: 10.0,
            },
            |_, _| {},
            |frame, ports| inject(frame as i64 - fault_frame, ports),
            |frame, computer| {
                monitor.observe(
                    frame as i64 - fault_frame,
                    (window_end, dense_end, check_interval),
                    computer,
                )
            },
        )
    }));
    let mut failures = std::mem::take(&mut monitor.failures);
    let result: Option<FlightResult> = match flown {
        Ok(result) => Some(result?),
        Err(panic) => {
            let message = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            failures.insert(0, format!("panicked: {message}"));
            None
        }
    };
    let Some(result) = result else {
        return Ok(RowOutcome {
            name: class.name,
            observed: vec![0; class.counts.len()],
            worst_calibration_sigma: f64::NAN,
            calibration_nees: None,
            position_error_m: [f64::NAN; 3],
            health: HealthCounters::default(),
            definiteness_checks: monitor.definiteness_checks,
            failures,
        });
    };
    Ok(monitor.verdict(class, &result, failures))
}

/// Runs every row of [`campaign_for`] `scenario` on its prefix of `scenario` (module docs), in parallel;
/// `progress(rows_done, rows_total)` after each row.
///
/// # Errors
/// [`FlightError`] if a flight could not be set up (the first failing row).
pub fn run_campaign(
    scenario: &Scenario,
    progress: impl Fn(u64, u64) + Sync,
) -> Result<CampaignResult, FlightError> {
    run_campaign_rows(scenario, |_| true, progress)
}

/// [`run_campaign`] for the rows `select` keeps (e.g. one row while working on it).
///
/// # Errors
/// As [`run_campaign`].
pub fn run_campaign_rows(
    scenario: &Scenario,
    select: impl Fn(&FaultClass) -> bool,
    progress: impl Fn(u64, u64) + Sync,
) -> Result<CampaignResult, FlightError> {
    let started = std::time::Instant::now();
    let short = scenario_prefix(scenario, SHORT_FLIGHT_S);
    let long = scenario_prefix(scenario, LONG_FLIGHT_S);
    let classes: Vec<FaultClass> = campaign_for(scenario)
        .into_iter()
        .filter(|c| select(c))
        .collect();
    let total = classes.len() as u64;
    let done = AtomicU64::new(0);
    let outcomes = classes
        .par_iter()
        .map(|class| {
            let flight = if class.injection_s <= SHORT_INJECTION_LIMIT_S {
                &short
            } else {
                &long
            };
            let outcome = run_row(flight, class);
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            outcome
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(CampaignResult {
        classes,
        outcomes,
        wall_time_s: started.elapsed().as_secs_f64(),
    })
}

impl CampaignResult {
    /// Every row met.
    pub fn all_met(&self) -> bool {
        self.outcomes.iter().all(RowOutcome::met)
    }

    /// The table: row, fault, expected reaction, counters, expected and observed counts,
    /// calibration criterion value, met.
    pub fn table(&self) -> Table {
        let mut table = Table::new();
        table.load_preset(UTF8_FULL_CONDENSED).set_header([
            "row",
            "fault injected",
            "expected reaction",
            "counter",
            "expected",
            "observed",
            "calibration (worst |e|/σ, NEES)",
            "met",
        ]);
        table
            .set_content_arrangement(ContentArrangement::Dynamic)
            .set_width(TABLE_WIDTH);
        for (index, (class, outcome)) in self.classes.iter().zip(&self.outcomes).enumerate() {
            let counters: Vec<&str> = class.counts.iter().map(|(c, _)| c.name).collect();
            let expected: Vec<String> = class.counts.iter().map(|(_, e)| e.text()).collect();
            let observed: Vec<String> = outcome.observed.iter().map(u32::to_string).collect();
            let mut calibration = format!(
                "{:.2}σ, {}",
                outcome.worst_calibration_sigma,
                outcome
                    .calibration_nees
                    .map_or_else(|| "-".to_string(), |n| format!("{n:.1}"))
            );
            if let Criterion::CalibrationAndPositionWithinRamp { ramp_m } = class.criterion {
                let error_m = Vector3::from(outcome.position_error_m).norm();
                calibration += &format!("; position error {error_m:.1} m (ramp {ramp_m} m)");
            }
            let met = if outcome.met() {
                "yes".to_string()
            } else {
                format!("NO: {}", outcome.failures.join("; "))
            };
            let right = |text: String| Cell::new(text).set_alignment(CellAlignment::Right);
            table.add_row([
                right(format!("{}", index + 1)),
                Cell::new(format!("{}: {}", class.name, class.injected)),
                Cell::new(class.reaction),
                Cell::new(counters.join("\n")),
                right(expected.join("\n")),
                right(observed.join("\n")),
                right(calibration),
                Cell::new(met),
            ]);
        }
        table
    }

    /// One line: rows met, flights, wall time, and the common criteria.
    pub fn summary_line(&self) -> String {
        format!(
            "{}; {:.1} s wall time",
            self.measured_summary_line(),
            self.wall_time_s
        )
    }

    /// [`Self::summary_line`] without the wall time, the machine's rather than the
    /// campaign's: what a results file holds.
    pub fn measured_summary_line(&self) -> String {
        let met = self.outcomes.iter().filter(|o| o.met()).count();
        let checks: u64 = self.outcomes.iter().map(|o| o.definiteness_checks).sum();
        format!(
            "{met} of {} rows met; flights of {SHORT_FLIGHT_S:.0} s ({LONG_FLIGHT_S:.0} s for \
             injections over {SHORT_INJECTION_LIMIT_S:.0} s), faults from {FAULT_START_S:.0} s; \
             no panic; state and P finite at every frame after the fault; P symmetric positive \
             definite at all {checks} checked frames",
            self.outcomes.len(),
        )
    }
}
