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
//!   [`SPD_CHECK_INTERVAL_FRAMES`] frames (10 Hz) otherwise, to keep the cost of the check
//!   below that of the flight;
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

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicU64, Ordering};

use comfy_table::{presets::UTF8_FULL_CONDENSED, Cell, CellAlignment, ContentArrangement, Table};
use nalgebra::Vector3;
use nav_core::attitude;
use nav_fsw::health::HealthCounters;
use nav_fsw::ports::{GnssFix, ImuSample, StarMeasurement};
use nav_fsw::replay::FramePorts;
use nav_fsw::scheduler::NavigationComputer;
use rayon::prelude::*;

use crate::harness::flight::{fly_observed, FlightError, FlightOptions, FlightResult};
use crate::scenario::{frames_in, ManoeuvreSegment, Scenario};
use crate::setup::fsw::fsw_config;

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
/// Outside the dense window, `P` is checked positive definite every this many frames.
pub const SPD_CHECK_INTERVAL_FRAMES: i64 = 50;
/// The count window extends this long past the last injected frame (s): a measurement is
/// fused within a frame of its arrival, an outage counted 2 s into it.
pub const COUNT_MARGIN_S: f64 = 1.0;
/// Width of the printed table (characters; cells wrap).
pub const TABLE_WIDTH: u16 = 160;
/// Calibration criterion: every state within this many σ of its truth.
pub const CALIBRATION_SIGMA_BOUND: f64 = 3.0;

/// Frames per second at the default 500 Hz (the rows are written in frames at that rate).
const HZ: i64 = 500;

/// The smallest positive subnormal, 4.9e-324.
const SUBNORMAL: f64 = 4.9e-324;
/// NaN, +Inf, −Inf: the non-finite values injected in every field.
const NON_FINITE: [f64; 3] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];

/// A health counter (or a sum of counters) by name.
#[derive(Clone, Copy)]
pub struct Counter {
    /// Name as in [`HealthCounters`] (`a + b` for a sum).
    pub name: &'static str,
    /// Its value.
    pub read: fn(&HealthCounters) -> u32,
}

macro_rules! counter {
    ($field:ident) => {
        Counter {
            name: stringify!($field),
            read: |h| h.$field,
        }
    };
    ($a:ident + $b:ident) => {
        Counter {
            name: concat!(stringify!($a), " + ", stringify!($b)),
            read: |h| h.$a.saturating_add(h.$b),
        }
    };
}

/// How a counter must have increased over the count window.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Expected {
    /// By exactly this much.
    Exactly(u32),
    /// By at least this much.
    AtLeast(u32),
}

impl Expected {
    fn met(self, observed: u32) -> bool {
        match self {
            Expected::Exactly(n) => observed == n,
            Expected::AtLeast(n) => observed >= n,
        }
    }

    fn text(self) -> String {
        match self {
            Expected::Exactly(n) => format!("{n}"),
            Expected::AtLeast(n) => format!("≥ {n}"),
        }
    }
}

/// The end-of-flight criterion of a row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Criterion {
    /// Every calibration state within [`CALIBRATION_SIGMA_BOUND`] σ of its truth.
    CalibrationWithinBound,
    /// For a departure from the filter's model that the flight software can only report:
    /// the counters and the common criteria are checked, the calibration is printed but not
    /// required within bound.
    CountedOnly,
    /// For a fault no check can see (a slow GNSS ramp, followed as truth): the calibration
    /// within bound as above, and the final position error (norm) within 1.5 × `ramp_m` (the
    /// ramp's final offset): the solution follows the ramp with the filter's lag and
    /// overshoot, but the fault is not amplified.
    CalibrationAndPositionWithinRamp {
        /// The offset the ramp reached (m).
        ramp_m: f64,
    },
}

/// An injector: `inject(frame − fault_frame, ports)` on every frame.
pub type Injector = Box<dyn FnMut(i64, &mut FramePorts)>;

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
    /// Builds the injector (a fresh one per flight).
    pub injector: fn() -> Injector,
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
// Injector building blocks.

fn imu(ports: &mut FramePorts) -> Option<&mut ImuSample> {
    ports.imu.0.as_mut()
}

/// Calls `corrupt(n, ports)` on each frame from the fault start that carries a star
/// measurement, `n` counting those frames from 0.
fn on_star(mut corrupt: impl FnMut(u32, &mut FramePorts) + 'static) -> Injector {
    let mut n = 0;
    Box::new(move |relative, ports| {
        if relative >= 0 && !ports.star.0.is_empty() {
            corrupt(n, ports);
            n += 1;
        }
    })
}

/// As [`on_star`] for GNSS fixes.
fn on_gnss(mut corrupt: impl FnMut(u32, &mut FramePorts) + 'static) -> Injector {
    let mut n = 0;
    Box::new(move |relative, ports| {
        if relative >= 0 && !ports.gnss.0.is_empty() {
            corrupt(n, ports);
            n += 1;
        }
    })
}

fn star(ports: &mut FramePorts) -> Option<&mut StarMeasurement> {
    ports.star.0.front_mut()
}

fn gnss(ports: &mut FramePorts) -> Option<&mut GnssFix> {
    ports.gnss.0.front_mut()
}

fn both(mut a: Injector, mut b: Injector) -> Injector {
    Box::new(move |relative, ports| {
        a(relative, ports);
        b(relative, ports);
    })
}

/// The star measurement rotated by `angle_deg` about sensor axis `axis`.
fn rotate_star(measurement: &mut StarMeasurement, axis: usize, angle_deg: f64) {
    let q = nav_fsw::ports::quaternion(&measurement.attitude_wxyz);
    let mut rotation = Vector3::zeros();
    rotation[axis % 3] = angle_deg.to_radians();
    let r = attitude::product(&q, &attitude::exp_rotation_vector(&rotation));
    measurement.attitude_wxyz = [r.w, r.i, r.j, r.k];
}

/// Non-finite values in IMU field `field` (0: Δθ, 1: Δv): NaN, +Inf, −Inf in x, y, z on
/// frames 0..9, then the smallest subnormal in x, y, z on frames 20..23.
fn imu_field_injector(field: usize) -> Injector {
    Box::new(move |relative, ports| {
        let Some(sample) = imu(ports) else { return };
        let vector = if field == 0 {
            &mut sample.delta_angle_rad
        } else {
            &mut sample.delta_velocity_mps
        };
        match relative {
            0..9 => vector[(relative % 3) as usize] = NON_FINITE[(relative / 3) as usize],
            20..23 => *vector = [SUBNORMAL; 3],
            _ => {}
        }
    })
}

// ---------------------------------------------------------------------------------------
// The rows.

/// The campaign's fault classes, in row order.
pub fn campaign() -> Vec<FaultClass> {
    let none = [0, 0];
    let calibration = Criterion::CalibrationWithinBound;
    vec![
        FaultClass {
            name: "control: no fault",
            injected: "nothing",
            reaction: "nothing counted",
            counts: vec![
                (counter!(imu_missing), Expected::Exactly(0)),
                (counter!(star_outages + gnss_outages), Expected::Exactly(0)),
            ],
            injection_s: 10.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || Box::new(|_, _| {}),
        },
        FaultClass {
            name: "IMU Δθ NaN/±Inf/subnormal",
            injected: "Δθ x, y, z = NaN, +Inf, −Inf (9 samples); all = 4.9e-324 (3 samples)",
            reaction: "non-finite: sample dropped, last good increment held, counted also as \
                       missing; subnormal: a valid near-zero reading, used",
            counts: vec![
                (counter!(imu_non_finite), Expected::Exactly(9)),
                (counter!(imu_missing), Expected::Exactly(9)),
            ],
            injection_s: 0.05,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || imu_field_injector(0),
        },
        FaultClass {
            name: "IMU Δv NaN/±Inf/subnormal",
            injected: "Δv x, y, z = NaN, +Inf, −Inf (9 samples); all = 4.9e-324 (3 samples)",
            reaction: "as Δθ",
            counts: vec![
                (counter!(imu_non_finite), Expected::Exactly(9)),
                (counter!(imu_missing), Expected::Exactly(9)),
            ],
            injection_s: 0.05,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || imu_field_injector(1),
        },
        FaultClass {
            name: "IMU time tag NaN/±Inf/subnormal",
            injected: "time = NaN, +Inf, −Inf (3 samples); time = 4.9e-324 (1 sample)",
            reaction: "non-finite: dropped, held, counted as missing; subnormal: a time jump \
                       (the sample and the next one), increments used",
            counts: vec![
                (counter!(imu_non_finite), Expected::Exactly(3)),
                (counter!(imu_missing), Expected::Exactly(3)),
                (counter!(imu_time_jump), Expected::Exactly(2)),
            ],
            injection_s: 0.05,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                Box::new(|relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    match relative {
                        0..3 => sample.time_s = NON_FINITE[relative as usize],
                        10 => sample.time_s = SUBNORMAL,
                        _ => {}
                    }
                })
            },
        },
        FaultClass {
            name: "star quaternion NaN/±Inf/subnormal",
            injected: "w, x, y, z = NaN, +Inf, −Inf (12 measurements); w, x, y, z = 4.9e-324 \
                       in turn (4), all four = 4.9e-324 (1)",
            reaction: "non-finite: dropped; subnormal: not unit, dropped, or (a small \
                       component zeroed) a wrong attitude, gated",
            counts: vec![
                (counter!(star_non_finite), Expected::Exactly(12)),
                (
                    counter!(star_not_unit + star_gate_rejections),
                    Expected::Exactly(5),
                ),
            ],
            injection_s: 1.7,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                on_star(|n, ports| {
                    let Some(m) = star(ports) else { return };
                    match n {
                        0..12 => m.attitude_wxyz[(n % 4) as usize] = NON_FINITE[(n / 4) as usize],
                        12..16 => m.attitude_wxyz[(n - 12) as usize] = SUBNORMAL,
                        16 => m.attitude_wxyz = [SUBNORMAL; 4],
                        _ => {}
                    }
                })
            },
        },
        FaultClass {
            name: "star time tag NaN/±Inf/subnormal",
            injected: "time tag = NaN, +Inf, −Inf (3 measurements); 4.9e-324 (1)",
            reaction: "non-finite: dropped; subnormal: stale, dropped",
            counts: vec![
                (counter!(star_non_finite), Expected::Exactly(3)),
                (counter!(measurement_stale), Expected::Exactly(1)),
            ],
            injection_s: 0.4,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                on_star(|n, ports| {
                    let Some(m) = star(ports) else { return };
                    match n {
                        0..3 => m.time_tag_s = NON_FINITE[n as usize],
                        3 => m.time_tag_s = SUBNORMAL,
                        _ => {}
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS position NaN/±Inf/subnormal",
            injected: "x, y, z = NaN, +Inf, −Inf (9 fixes); x, y, z = 4.9e-324 in turn (3)",
            reaction: "non-finite: dropped; subnormal: a jump of thousands of km, dropped \
                       (a rejection)",
            counts: vec![
                (counter!(gnss_non_finite), Expected::Exactly(9)),
                (
                    counter!(gnss_jump + gnss_gate_rejections),
                    Expected::Exactly(3),
                ),
            ],
            injection_s: 1.2,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                on_gnss(|n, ports| {
                    let Some(fix) = gnss(ports) else { return };
                    match n {
                        0..9 => {
                            fix.position_ecef_m[(n % 3) as usize] = NON_FINITE[(n / 3) as usize]
                        }
                        9..12 => fix.position_ecef_m[(n - 9) as usize] = SUBNORMAL,
                        _ => {}
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS time tag NaN/±Inf/subnormal",
            injected: "time tag = NaN, +Inf, −Inf (3 fixes); 4.9e-324 (1)",
            reaction: "non-finite: dropped; subnormal: stale, dropped",
            counts: vec![
                (counter!(gnss_non_finite), Expected::Exactly(3)),
                (counter!(measurement_stale), Expected::Exactly(1)),
            ],
            injection_s: 0.4,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                on_gnss(|n, ports| {
                    let Some(fix) = gnss(ports) else { return };
                    match n {
                        0..3 => fix.gps_seconds_of_week = NON_FINITE[n as usize],
                        3 => fix.gps_seconds_of_week = SUBNORMAL,
                        _ => {}
                    }
                })
            },
        },
        FaultClass {
            name: "IMU dropouts 1-500 frames",
            injected: "no sample for 1, 10, 100 and 500 frames (at 0, 1, 2, 4 s)",
            reaction: "last good increment held, time advances",
            counts: vec![(counter!(imu_missing), Expected::Exactly(611))],
            injection_s: 5.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                Box::new(|relative, ports| {
                    let dropped = [(0, 1), (HZ, 10), (2 * HZ, 100), (4 * HZ, 500)]
                        .iter()
                        .any(|(start, length)| (*start..start + length).contains(&relative));
                    if dropped {
                        ports.imu.0 = None;
                    }
                })
            },
        },
        FaultClass {
            name: "IMU spikes",
            injected: "10 single-sample spikes every 0.5 s: Δθ ±0.1 rad (50 rad/s) and Δv \
                       ±2 m/s (1000 m/s²) on x, y, z in turn",
            reaction: "beyond the saturation limits: dropped, held, counted also as missing",
            counts: vec![
                (counter!(imu_saturated), Expected::Exactly(10)),
                (counter!(imu_missing), Expected::Exactly(10)),
            ],
            injection_s: 5.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                Box::new(|relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    if relative < 0 || relative % (HZ / 2) != 0 || relative >= 5 * HZ {
                        return;
                    }
                    let spike = relative / (HZ / 2);
                    let sign = if spike % 2 == 0 { 1.0 } else { -1.0 };
                    let axis = (spike % 3) as usize;
                    if spike % 4 < 2 {
                        sample.delta_angle_rad[axis] = 0.1 * sign;
                    } else {
                        sample.delta_velocity_mps[axis] = 2.0 * sign;
                    }
                })
            },
        },
        FaultClass {
            name: "IMU saturation held 1 s",
            injected: "Δθ z = 0.021 rad (10.5 rad/s, 1.5 × the limit) for 1 s, then Δv x = \
                       0.6 m/s (300 m/s²) for 1 s",
            reaction: "each sample beyond the limits dropped, last good increment held, \
                       counted also as missing",
            counts: vec![
                (counter!(imu_saturated), Expected::Exactly(1000)),
                (counter!(imu_missing), Expected::Exactly(1000)),
            ],
            injection_s: 3.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                Box::new(|relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    if (0..HZ).contains(&relative) {
                        sample.delta_angle_rad[2] = 0.021;
                    } else if (2 * HZ..3 * HZ).contains(&relative) {
                        sample.delta_velocity_mps[0] = 0.6;
                    }
                })
            },
        },
        FaultClass {
            name: "IMU channel frozen 10 s",
            injected: "gyro x repeats the bits of its first sample for 10 s (5000 samples)",
            reaction: "a repeated value is a valid reading: no input check sees it; the \
                       attitude drift it causes is below the star gate",
            counts: vec![
                (
                    counter!(imu_non_finite + imu_saturated),
                    Expected::Exactly(0),
                ),
                (counter!(star_gate_rejections), Expected::Exactly(0)),
            ],
            injection_s: 10.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                let mut frozen = None;
                Box::new(move |relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    if (0..10 * HZ).contains(&relative) {
                        let value = *frozen.get_or_insert(sample.delta_angle_rad[0]);
                        sample.delta_angle_rad[0] = value;
                    }
                })
            },
        },
        FaultClass {
            name: "star outages 0.5 s, 5 s, 60 s",
            injected: "no star measurement for 0.5 s (at 0 s), 5 s (at 2 s), 60 s (at 10 s)",
            reaction: "navigation on IMU + GNSS; an outage longer than the 2 s timeout \
                       counted once",
            counts: vec![(counter!(star_outages), Expected::Exactly(2))],
            injection_s: 70.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                Box::new(|relative, ports| {
                    let silent = [(0, HZ / 2), (2 * HZ, 5 * HZ), (10 * HZ, 60 * HZ)]
                        .iter()
                        .any(|(start, length)| (*start..start + length).contains(&relative));
                    if silent {
                        ports.star.0.clear();
                    }
                })
            },
        },
        FaultClass {
            name: "star outage 600 s",
            injected: "no star measurement for 600 s (across the +x burn)",
            reaction: "navigation on IMU + GNSS; the outage counted once",
            counts: vec![(counter!(star_outages), Expected::Exactly(1))],
            injection_s: 600.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                Box::new(|relative, ports| {
                    if (0..600 * HZ).contains(&relative) {
                        ports.star.0.clear();
                    }
                })
            },
        },
        FaultClass {
            name: "star quaternion sign flips",
            injected: "q → −q on every other measurement, 10 measurements",
            reaction: "undone (q and −q are one attitude), each change of sign counted",
            counts: vec![(counter!(star_sign_flip), Expected::Exactly(10))],
            injection_s: 1.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                on_star(|n, ports| {
                    if n < 10 && n % 2 == 0 {
                        if let Some(m) = star(ports) {
                            m.attitude_wxyz.iter_mut().for_each(|c| *c = -*c);
                        }
                    }
                })
            },
        },
        FaultClass {
            name: "star quaternion non-unit and zero",
            injected: "|q| = 1.1, 0.9, 1.002 and 0 (4 measurements, every other one); |q| = \
                       1.0005 (within the 1e-3 tolerance)",
            reaction: "|q| − 1 beyond the tolerance: dropped; within: normalised and used",
            counts: vec![(counter!(star_not_unit), Expected::Exactly(4))],
            injection_s: 1.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                on_star(|n, ports| {
                    let Some(m) = star(ports) else { return };
                    let scale = match n {
                        0 => 1.1,
                        2 => 0.9,
                        4 => 1.002,
                        6 => 0.0,
                        8 => 1.0005,
                        _ => return,
                    };
                    m.attitude_wxyz.iter_mut().for_each(|c| *c *= scale);
                })
            },
        },
        FaultClass {
            name: "star outliers 5°",
            injected: "3 measurements rotated 5° about x, y, z (1 s apart)",
            reaction: "rejected by the innovation gate (NIS ≫ 16.27)",
            counts: vec![(counter!(star_gate_rejections), Expected::Exactly(3))],
            injection_s: 2.1,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                on_star(|n, ports| {
                    if n % 10 == 0 && n < 30 {
                        if let Some(m) = star(ports) {
                            rotate_star(m, (n / 10) as usize, 5.0);
                        }
                    }
                })
            },
        },
        FaultClass {
            name: "star outliers 180°",
            injected: "3 measurements rotated 180° about x, y, z (1 s apart)",
            reaction: "rejected by the innovation gate",
            counts: vec![(counter!(star_gate_rejections), Expected::Exactly(3))],
            injection_s: 2.1,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                on_star(|n, ports| {
                    if n % 10 == 0 && n < 30 {
                        if let Some(m) = star(ports) {
                            rotate_star(m, (n / 10) as usize, 180.0);
                        }
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS steps 100 m-10 km (1 s)",
            injected: "10 fixes offset by 100 m (x), 500 m (y), 2 km (z), 10 km (x); 10 good \
                       fixes between steps",
            reaction: "below the 1 km jump limit: gated; beyond: dropped as jumps; no \
                       declaration (the receiver recovers between steps)",
            counts: vec![
                (counter!(gnss_gate_rejections), Expected::Exactly(20)),
                (counter!(gnss_jump), Expected::Exactly(20)),
            ],
            injection_s: 7.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                on_gnss(|n, ports| {
                    let steps = [100.0, 500.0, 2_000.0, 10_000.0];
                    let (step, within) = ((n / 20) as usize, n % 20 < 10);
                    if let (Some(offset), true, Some(fix)) = (steps.get(step), within, gnss(ports))
                    {
                        fix.position_ecef_m[step % 3] += offset;
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS step 100 m held",
            injected: "every fix from the fault on offset by 100 m (x)",
            reaction: "gated; after 20 rejections in a row the receiver is declared faulty \
                       (once) and ignored; navigation continues on the star sensor",
            counts: vec![
                (counter!(gnss_gate_rejections), Expected::Exactly(20)),
                (counter!(gnss_declared_faulty), Expected::Exactly(1)),
                (counter!(ignored_from_faulty_sensor), Expected::AtLeast(1)),
            ],
            injection_s: 3.0,
            declared_faulty: [0, 1],
            criterion: calibration,
            scenario_change: None,
            injector: || {
                on_gnss(|_, ports| {
                    if let Some(fix) = gnss(ports) {
                        fix.position_ecef_m[0] += 100.0;
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS step 10 km held",
            injected: "every fix from the fault on offset by 10 km (y)",
            reaction: "dropped as jumps (each a rejection); after 20 the receiver is declared \
                       faulty (once) and ignored",
            counts: vec![
                (counter!(gnss_jump), Expected::Exactly(20)),
                (counter!(gnss_declared_faulty), Expected::Exactly(1)),
                (counter!(ignored_from_faulty_sensor), Expected::AtLeast(1)),
            ],
            injection_s: 3.0,
            declared_faulty: [0, 1],
            criterion: calibration,
            scenario_change: None,
            injector: || {
                on_gnss(|_, ports| {
                    if let Some(fix) = gnss(ports) {
                        fix.position_ecef_m[1] += 10_000.0;
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS slow ramp below the gate",
            injected: "fixes drift 0.05 m/s along ECEF x for 600 s (30 m), then held",
            reaction: "indistinguishable from truth, followed: no check or gate can see it, \
                       so not counted (gate rejections at the natural 0.1 % rate); the \
                       position error follows the ramp, bounded by it",
            counts: vec![
                (counter!(gnss_jump), Expected::Exactly(0)),
                (counter!(gnss_declared_faulty), Expected::Exactly(0)),
            ],
            injection_s: 600.0,
            declared_faulty: none,
            criterion: Criterion::CalibrationAndPositionWithinRamp { ramp_m: 30.0 },
            scenario_change: None,
            injector: || {
                Box::new(|relative, ports| {
                    if relative < 0 {
                        return;
                    }
                    let elapsed_s = (relative.min(600 * HZ) as f64) / HZ as f64;
                    if let Some(fix) = gnss(ports) {
                        fix.position_ecef_m[0] += 0.05 * elapsed_s;
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS outage 10 min",
            injected: "no fix for 600 s (across the +x burn)",
            reaction: "navigation on IMU + star sensor; the outage counted once; fixes \
                       accepted again after it",
            counts: vec![(counter!(gnss_outages), Expected::Exactly(1))],
            injection_s: 600.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                Box::new(|relative, ports| {
                    if (0..600 * HZ).contains(&relative) {
                        ports.gnss.0.clear();
                    }
                })
            },
        },
        FaultClass {
            name: "stale time tags",
            injected: "one star measurement and one fix time-tagged 1 s late",
            reaction: "older than the latency limit: dropped",
            counts: vec![(counter!(measurement_stale), Expected::Exactly(2))],
            injection_s: 0.2,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                both(
                    on_star(|n, ports| {
                        if let (0, Some(m)) = (n, star(ports)) {
                            m.time_tag_s -= 1.0;
                        }
                    }),
                    on_gnss(|n, ports| {
                        if let (0, Some(fix)) = (n, gnss(ports)) {
                            fix.gps_seconds_of_week -= 1.0;
                        }
                    }),
                )
            },
        },
        FaultClass {
            name: "duplicated samples",
            injected: "one star measurement and one fix delivered twice; one IMU sample \
                       repeated (replacing the next)",
            reaction: "measurement not newer than the last: dropped; IMU: dropped, held, the \
                       replaced sample counted missing",
            counts: vec![
                (counter!(measurement_stale), Expected::Exactly(2)),
                (counter!(imu_duplicate), Expected::Exactly(1)),
                (counter!(imu_missing), Expected::Exactly(1)),
            ],
            injection_s: 0.2,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                let mut previous = None;
                both(
                    Box::new(move |relative, ports| {
                        if relative == 0 {
                            ports.imu.0 = previous;
                        }
                        previous = ports.imu.0;
                    }),
                    both(
                        on_star(|n, ports| {
                            if let (0, Some(m)) = (n, ports.star.0.front().copied()) {
                                let _ = ports.star.0.push_back(m);
                            }
                        }),
                        on_gnss(|n, ports| {
                            if let (0, Some(fix)) = (n, ports.gnss.0.front().copied()) {
                                let _ = ports.gnss.0.push_back(fix);
                            }
                        }),
                    ),
                )
            },
        },
        FaultClass {
            name: "out-of-order samples",
            injected: "a star measurement and a fix followed by one 20 ms older; IMU sample \
                       k−2 delivered after k−1, in place of k",
            reaction: "measurement older than the last fused: dropped; IMU: the late sample \
                       dropped (out of order), held; the lost sample k counted missing",
            counts: vec![
                (counter!(measurement_stale), Expected::Exactly(2)),
                (counter!(imu_duplicate), Expected::Exactly(1)),
                (counter!(imu_missing), Expected::Exactly(1)),
            ],
            injection_s: 0.2,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                let mut history: [Option<ImuSample>; 2] = [None; 2];
                both(
                    Box::new(move |relative, ports| {
                        let current = ports.imu.0;
                        if relative == 0 {
                            // Sample k−2 arrives late, after k−1, in place of sample k.
                            ports.imu.0 = history[0];
                        }
                        history = [history[1], current];
                    }),
                    both(
                        on_star(|n, ports| {
                            if let (0, Some(mut m)) = (n, ports.star.0.front().copied()) {
                                m.time_tag_s -= 0.02;
                                let _ = ports.star.0.push_back(m);
                            }
                        }),
                        on_gnss(|n, ports| {
                            if let (0, Some(mut fix)) = (n, ports.gnss.0.front().copied()) {
                                fix.gps_seconds_of_week -= 0.02;
                                let _ = ports.gnss.0.push_back(fix);
                            }
                        }),
                    ),
                )
            },
        },
        FaultClass {
            name: "future time tags",
            injected: "one star measurement and one fix time-tagged 1 s ahead",
            reaction: "beyond the future tolerance: dropped",
            counts: vec![(counter!(measurement_future), Expected::Exactly(2))],
            injection_s: 0.2,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                both(
                    on_star(|n, ports| {
                        if let (0, Some(m)) = (n, star(ports)) {
                            m.time_tag_s += 1.0;
                        }
                    }),
                    on_gnss(|n, ports| {
                        if let (0, Some(fix)) = (n, gnss(ports)) {
                            fix.gps_seconds_of_week += 1.0;
                        }
                    }),
                )
            },
        },
        FaultClass {
            name: "IMU clock jumps",
            injected: "time step 0 (at 0 s), −1 period (1 s), +10 periods (2 s); 32-bit µs \
                       clock wrap, −4294.967296 s from 3 s on",
            reaction: "time jump counted (the sample and the next one; the wrap once, the \
                       time base re-anchored); increments used, time frame-driven",
            counts: vec![(counter!(imu_time_jump), Expected::Exactly(7))],
            injection_s: 3.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                Box::new(|relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    let period = 1.0 / HZ as f64;
                    match relative {
                        0 => sample.time_s -= period,
                        r if r == HZ => sample.time_s -= 2.0 * period,
                        r if r == 2 * HZ => sample.time_s += 9.0 * period,
                        r if r >= 3 * HZ => sample.time_s -= 4_294.967_296,
                        _ => {}
                    }
                })
            },
        },
        FaultClass {
            name: "IMU sequence counter wrap",
            injected: "sequence numbers offset so the counter wraps u32::MAX → 0 at 10 ms",
            reaction: "continuous through the wrap: nothing missing, nothing repeated",
            counts: vec![
                (counter!(imu_missing), Expected::Exactly(0)),
                (
                    counter!(imu_duplicate + imu_time_jump),
                    Expected::Exactly(0),
                ),
            ],
            injection_s: 1.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: || {
                let mut offset = None;
                Box::new(move |relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    // Sequence u32::MAX − 4 at the fault start: 0 five frames later.
                    let offset = *offset.get_or_insert_with(|| {
                        (u32::MAX - 4)
                            .wrapping_add(relative as u32)
                            .wrapping_sub(sample.sequence)
                    });
                    sample.sequence = sample.sequence.wrapping_add(offset);
                })
            },
        },
        FaultClass {
            name: "GNSS correlated drift",
            injected: "a Gauss–Markov position error on every fix for 600 s: 8 m per ECEF axis, \
                       τ = 300 s (on top of the white noise); the filter is given the receiver's \
                       specification (filter.gnss_correlated_sigma_m = 8, \
                       gnss_correlation_time_s = 300)",
            reaction: "followed by the three correlated-error states; nothing refused, the \
                       innovations stay white",
            counts: vec![
                (counter!(filter_errors), Expected::Exactly(0)),
                (counter!(gnss_innovations_correlated), Expected::Exactly(0)),
            ],
            injection_s: 600.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: Some(|scenario| {
                scenario.filter.gnss_correlated_sigma_m = DRIFT_SIGMA_M;
                scenario.filter.gnss_correlation_time_s = DRIFT_CORRELATION_TIME_S;
            }),
            injector: || {
                let mut drift = GaussMarkovDrift::new(DRIFT_SIGMA_M, DRIFT_CORRELATION_TIME_S);
                Box::new(move |relative, ports| {
                    if !(0..600 * HZ).contains(&relative) {
                        return;
                    }
                    for fix in ports.gnss.0.iter_mut() {
                        let error = drift.at(fix.gps_seconds_of_week);
                        for (value, e) in fix.position_ecef_m.iter_mut().zip(error) {
                            *value += e;
                        }
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS correlated drift, not modelled",
            injected: "the drift of the row above with the filter left at white errors (the \
                       paper's model)",
            reaction: "the filter cannot stay consistent; the serially correlated innovations \
                       are counted, so the overconfidence is not silent",
            counts: vec![(counter!(gnss_innovations_correlated), Expected::AtLeast(1))],
            injection_s: 600.0,
            declared_faulty: none,
            criterion: Criterion::CountedOnly,
            scenario_change: None,
            injector: || {
                let mut drift = GaussMarkovDrift::new(DRIFT_SIGMA_M, DRIFT_CORRELATION_TIME_S);
                Box::new(move |relative, ports| {
                    if !(0..600 * HZ).contains(&relative) {
                        return;
                    }
                    for fix in ports.gnss.0.iter_mut() {
                        let error = drift.at(fix.gps_seconds_of_week);
                        for (value, e) in fix.position_ecef_m.iter_mut().zip(error) {
                            *value += e;
                        }
                    }
                })
            },
        },
        FaultClass {
            name: "star tracker loses track in a slew",
            injected: "a 10 °/s slew (9 s, 80°) at 0 s; the tracker delivers nothing while \
                       the body rate exceeds 3 °/s and for 10 s after (re-acquisition)",
            reaction: "navigation on IMU + GNSS through the blind slew; the outage counted once",
            counts: vec![(counter!(star_outages), Expected::Exactly(1))],
            injection_s: 30.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: Some(|scenario| {
                insert_segments(scenario, FAULT_START_S, &[slew(9.0, [0.0, 10.0, 0.0])]);
            }),
            injector: || {
                let mut blind_until = i64::MIN;
                Box::new(move |relative, ports| {
                    if relative < 0 {
                        return;
                    }
                    let rate_deg_s = ports.imu.0.as_ref().map_or(0.0, |sample| {
                        Vector3::from(sample.delta_angle_rad).norm().to_degrees() * HZ as f64
                    });
                    if rate_deg_s > 3.0 {
                        blind_until = relative + 10 * HZ;
                    }
                    if relative < blind_until {
                        ports.star.0.clear();
                    }
                })
            },
        },
        FaultClass {
            name: "manoeuvre beyond the IMU range",
            injected: "450 °/s about z for 2 s at 0 s, then 250 m/s² along x for 2 s at 7 s \
                       (ranges 401 °/s, 200 m/s²): the IMU outputs its full scale",
            reaction: "each full-scale sample refused as saturated and the last good one held; \
                       the covariance grows by the range per held frame, so the star sensor \
                       and GNSS pull the solution back and neither is declared faulty",
            // Frames at or beyond full scale: the raised-cosine ramps (0.5 s) pass 401/450 of
            // the peak rate 0.107 s before the plateau ends, 250/200 of the force 0.148 s:
            // (1 + 2 × 0.107) s + (1 + 2 × 0.148) s at 500 Hz ≈ 607 + 648 frames.
            counts: vec![(counter!(imu_saturated), Expected::Exactly(1254))],
            injection_s: 10.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: Some(|scenario| {
                insert_segments(
                    scenario,
                    FAULT_START_S,
                    &[
                        slew(2.0, [0.0, 0.0, 450.0]),
                        slew(5.0, [0.0; 3]),
                        thrust(2.0, [250.0, 0.0, 0.0]),
                    ],
                );
            }),
            injector: || {
                Box::new(|relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    if relative < 0 {
                        return;
                    }
                    // The default limits (nav-fsw ImuLimits): 7 rad/s and 200 m/s².
                    let period_s = 1.0 / HZ as f64;
                    let clip = |value: &mut f64, range: f64| *value = value.clamp(-range, range);
                    for value in sample.delta_angle_rad.iter_mut() {
                        clip(value, 7.0 * period_s);
                    }
                    for value in sample.delta_velocity_mps.iter_mut() {
                        clip(value, 200.0 * period_s);
                    }
                })
            },
        },
    ]
}

/// 1σ per axis of the injected GNSS drift (m).
const DRIFT_SIGMA_M: f64 = 8.0;
/// Correlation time of the injected GNSS drift (s).
const DRIFT_CORRELATION_TIME_S: f64 = 300.0;

/// A first-order Gauss–Markov error per axis, stationary from its first sample, advanced
/// exactly between the time tags it is asked for (seeded: every flight draws the same drift).
struct GaussMarkovDrift {
    sigma_m: f64,
    correlation_time_s: f64,
    rng: rand_chacha::ChaCha8Rng,
    last: Option<(f64, [f64; 3])>,
}

impl GaussMarkovDrift {
    fn new(sigma_m: f64, correlation_time_s: f64) -> Self {
        use rand::SeedableRng;
        Self {
            sigma_m,
            correlation_time_s,
            rng: rand_chacha::ChaCha8Rng::seed_from_u64(0x6e55),
            last: None,
        }
    }

    fn normal(&mut self) -> f64 {
        use rand_distr::Distribution;
        rand_distr::StandardNormal.sample(&mut self.rng)
    }

    /// The error at `time_s` (not before the previous time asked).
    fn at(&mut self, time_s: f64) -> [f64; 3] {
        let error = match self.last {
            None => [0; 3].map(|_| self.sigma_m * self.normal()),
            Some((last_s, last)) => {
                let phi = (-(time_s - last_s).max(0.0) / self.correlation_time_s).exp();
                let walk = self.sigma_m * (1.0 - phi * phi).sqrt();
                last.map(|value| phi * value + walk * self.normal())
            }
        };
        self.last = Some((time_s, error));
        error
    }
}

/// A raised-cosine rotation (0.5 s ramps) at `rate_deg_s` for `duration_s`, no thrust.
fn slew(duration_s: f64, rate_deg_s: [f64; 3]) -> ManoeuvreSegment {
    ManoeuvreSegment {
        label: "fault: slew".to_string(),
        duration_s,
        ramp_s: 0.5,
        body_rate_deg_per_s: rate_deg_s,
        specific_force_mps2: [0.0; 3],
    }
}

/// A raised-cosine thrust (0.5 s ramps) of `force_mps2` for `duration_s`, no rotation.
fn thrust(duration_s: f64, force_mps2: [f64; 3]) -> ManoeuvreSegment {
    ManoeuvreSegment {
        label: "fault: thrust".to_string(),
        duration_s,
        ramp_s: 0.5,
        body_rate_deg_per_s: [0.0; 3],
        specific_force_mps2: force_mps2,
    }
}

/// Splits the constant segment running at `at_s` (from the scenario start) and inserts
/// `inserted` there; the flight grows by their length. A ramped segment at `at_s` is left
/// whole and the insertion follows it.
fn insert_segments(scenario: &mut Scenario, at_s: f64, inserted: &[ManoeuvreSegment]) {
    let mut elapsed_s = 0.0;
    for index in 0..scenario.manoeuvres.len() {
        let segment = scenario.manoeuvres[index].clone();
        let end_s = elapsed_s + segment.duration_s;
        if end_s > at_s {
            let mut position = index + 1;
            if segment.ramp_s == 0.0 && at_s > elapsed_s {
                let mut first = segment.clone();
                first.duration_s = at_s - elapsed_s;
                let mut rest = segment;
                rest.duration_s = end_s - at_s;
                scenario.manoeuvres[index] = first;
                scenario.manoeuvres.insert(index + 1, rest);
            } else if segment.ramp_s == 0.0 {
                position = index;
            }
            for (offset, new) in inserted.iter().enumerate() {
                scenario.manoeuvres.insert(position + offset, new.clone());
            }
            return;
        }
        elapsed_s = end_s;
    }
    scenario.manoeuvres.extend_from_slice(inserted);
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

#[derive(Default)]
struct Monitor {
    before: Option<HealthCounters>,
    after: Option<HealthCounters>,
    failures: Vec<String>,
    definiteness_checks: u64,
}

impl Monitor {
    fn fail(&mut self, failure: String) {
        // The first few are enough to diagnose; a fault that persists would repeat them.
        if self.failures.len() < 4 {
            self.failures.push(failure);
        }
    }

    fn observe(
        &mut self,
        relative: i64,
        (window_end, dense_end): (i64, i64),
        computer: &NavigationComputer,
    ) {
        if relative == -1 {
            self.before = Some(*computer.health());
        }
        if relative == window_end {
            self.after = Some(*computer.health());
        }
        if relative < 0 {
            return;
        }
        let filter = computer.filter();
        let navigation = computer.navigation();
        let calibration = computer.calibration_estimate();
        let finite = filter.state().iter().all(|v| v.is_finite())
            && filter.covariance().iter().all(|v| v.is_finite())
            && navigation.attitude.coords.iter().all(|v| v.is_finite())
            && navigation.position_m.iter().all(|v| v.is_finite())
            && navigation.velocity_mps.iter().all(|v| v.is_finite())
            && navigation.time_s.is_finite()
            && [
                calibration.gyro_bias_rad_s.as_slice(),
                &calibration.accel_bias_mps2,
                &calibration.star_installation_wxyz,
                &calibration.gyro_scale_factor,
                &calibration.accel_scale_factor,
            ]
            .iter()
            .all(|block| block.iter().all(|v| v.is_finite()));
        if !finite {
            self.fail(format!(
                "non-finite state or covariance at frame {relative}"
            ));
            return;
        }
        if relative <= dense_end || relative % SPD_CHECK_INTERVAL_FRAMES == 0 {
            self.definiteness_checks += 1;
            let p = filter.covariance();
            let scale = p.amax();
            let asymmetry = (p - p.transpose()).amax();
            if asymmetry > 1e-12 * scale {
                self.fail(format!(
                    "P asymmetric at frame {relative}: {:.1e} of its largest entry",
                    asymmetry / scale
                ));
            }
            if p.cholesky().is_none() {
                self.fail(format!("P not positive definite at frame {relative}"));
            }
        }
    }
}

/// Flies one row on the (prefix) scenario and checks every criterion.
pub fn run_row(scenario: &Scenario, class: &FaultClass) -> Result<RowOutcome, FlightError> {
    let mut changed = scenario.clone();
    if let Some(change) = class.scenario_change {
        change(&mut changed);
    }
    let scenario = &changed;
    let period_s = scenario.imu.frame_period_s();
    let fault_frame = frames_in(FAULT_START_S, period_s) as i64;
    let window_end = frames_in(class.injection_s + COUNT_MARGIN_S, period_s) as i64;
    let dense_end = window_end.min(frames_in(DENSE_CHECK_S, period_s) as i64);
    let config = fsw_config(scenario)?;
    let mut monitor = Monitor::default();
    let mut inject = (class.injector)();
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
                    (window_end, dense_end),
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
    let (before, after) = match (monitor.before, monitor.after) {
        (Some(before), Some(after)) => (before, after),
        _ => {
            failures.push("the flight ended before the count window closed".to_string());
            (HealthCounters::default(), result.health)
        }
    };
    let mut observed = Vec::new();
    for (counter, expected) in &class.counts {
        let increase = (counter.read)(&after).saturating_sub((counter.read)(&before));
        observed.push(increase);
        if !expected.met(increase) {
            failures.push(format!(
                "{}: counted {increase}, expected {}",
                counter.name,
                expected.text()
            ));
        }
    }
    let health = result.health;
    if health.filter_resets != 0 {
        failures.push(format!("{} filter resets", health.filter_resets));
    }
    let declared = [health.star_declared_faulty, health.gnss_declared_faulty];
    if declared != class.declared_faulty {
        failures.push(format!(
            "declared faulty (star, GNSS) {declared:?}, expected {:?}",
            class.declared_faulty
        ));
    }
    let worst = (0..result.calibration_error.len())
        .map(|i| result.calibration_error[i].abs() / result.calibration_covariance[(i, i)].sqrt())
        // NaN-propagating maximum: a NaN ratio fails the row.
        .fold(0.0_f64, |worst, ratio| {
            if ratio.is_nan() || worst.is_nan() {
                f64::NAN
            } else {
                worst.max(ratio)
            }
        });
    let calibration_required = class.criterion != Criterion::CountedOnly;
    if calibration_required && (worst.is_nan() || worst > CALIBRATION_SIGMA_BOUND) {
        failures.push(format!(
            "calibration: worst state {worst:.2}σ from its truth"
        ));
    }
    let last = result.last().copied();
    let position_error_m = last.map_or([f64::NAN; 3], |s| s.position_error_m);
    if let (Criterion::CalibrationAndPositionWithinRamp { ramp_m }, Some(last)) =
        (class.criterion, last)
    {
        let error_m = Vector3::from(last.position_error_m).norm();
        if error_m.is_nan() || error_m > 1.5 * ramp_m {
            failures.push(format!(
                "position error {error_m:.1} m beyond 1.5 × the {ramp_m} m ramp"
            ));
        }
    }
    Ok(RowOutcome {
        name: class.name,
        observed,
        worst_calibration_sigma: worst,
        calibration_nees: result.calibration_nees(),
        position_error_m,
        health,
        definiteness_checks: monitor.definiteness_checks,
        failures,
    })
}

/// Runs every row of [`campaign`] on its prefix of `scenario` (module docs), in parallel;
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
    let classes: Vec<FaultClass> = campaign().into_iter().filter(|c| select(c)).collect();
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
        let met = self.outcomes.iter().filter(|o| o.met()).count();
        let checks: u64 = self.outcomes.iter().map(|o| o.definiteness_checks).sum();
        format!(
            "{met} of {} rows met; flights of {SHORT_FLIGHT_S:.0} s ({LONG_FLIGHT_S:.0} s for \
             injections over {SHORT_INJECTION_LIMIT_S:.0} s), faults from {FAULT_START_S:.0} s; \
             no panic; state and P finite at every frame after the fault; P symmetric positive \
             definite at all {checks} checked frames; {:.1} s wall time",
            self.outcomes.len(),
            self.wall_time_s
        )
    }
}
