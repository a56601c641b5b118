//! The 500 Hz cyclic executive: [`NavigationComputer::run_frame`] is one minor frame.
//!
//! Each frame, in this order (every loop bounded by a constant):
//! 1. IMU: read one sample, check it ([`crate::input_check`]), correct it with the current
//!    calibration (closed loop) and run one strapdown step (nav-core). A missing or rejected
//!    sample is replaced by the last good increment (zero-order hold), counted; navigation
//!    time always advances by one frame period.
//! 2. History: the navigation solution of the frame goes into a ring of
//!    [`HISTORY_CAPACITY`] frames, so a late measurement is fused against the solution at
//!    its own time of validity (interpolated between frames).
//! 3. Measurements: at most [`MAX_POLLS_PER_FRAME`] new measurements per port are checked and
//!    queued. A measurement is due once its time tag is no later than the covariance's
//!    time ([`NavigationComputer::covariance_time_s`], within the future tolerance).
//! 4. Fusion or propagation (`covariance.frame_load`, [`crate::config::FrameLoad`]). By
//!    default a frame does one of the two: **at most one** due measurement (the oldest) is
//!    fused against `P` at its last propagation, and the propagation, if due, waits one
//!    frame; a frame whose propagation has already waited propagates, and a due measurement
//!    waits instead. The propagation: every `propagation_interval_frames` frames (or the
//!    frame after, when it waited), the error model at the mean rates/forces of the
//!    interval, 3rd-order `F` and `P ← F P Fᵀ + Qd` by blocks, in place (nav-core
//!    `structured`; paper §1.3.3), then covariance protection (variance floors and
//!    ceilings, counted; only the diagonal is read unless a bound is crossed). The worst
//!    frame is therefore strapdown + the larger of one propagation and one update (+
//!    closed-loop reset), bounded by construction; with `PropagateThenFuse` it is
//!    strapdown + both.
//! 5. Calibration manager: table, convergence, frozen set.
//!
//! Delayed fusion: the innovation and `H` are formed with the navigation solution at the
//! measurement's time of validity and referred to the error state at the covariance's time
//! with `H (I − A Δ)` (nav-core `refer_to_later_time_in_place`, by blocks of `A`). In
//! closed loop the correction, estimated at the covariance's time, is applied to the
//! navigation solution of the frame, later by the frames not yet propagated (one in a
//! fusion frame, by default): the error state's change over them, `A Δ x̂`, is left out
//! (0.35 % of the correction per frame at 100 °/s; docs/guide/flight-software.md).
//!
//! `FilterArithmetic::DenseReference` runs the same frame with nav-core's dense 24×24
//! reference arithmetic (equal within round-off), for cost comparisons only.
//!
//! Closed loop (the default): after every accepted update the error state is fed back into
//! the navigation solution, the history (each snapshot corrected when it is read, with the
//! feedbacks since it was recorded) and the sensor corrections, and the filter is reset
//! (nav-core `reset`), so `x = 0` whenever the filter predicts. Open loop (the paper): the
//! navigation solution is never corrected; outputs apply `x` on the way out.

// The scheduler's files share these imports through `use super::*`.
use heapless::Deque;
use nalgebra::{Matrix3, Quaternion, Vector3};
use nav_core::arithmetic::Propagation;
use nav_core::attitude;
use nav_core::error_model::{LinearisationPoint, ProcessNoise};
use nav_core::filter::{
    apply_error_state, block_of, CalibrationEstimate, ErrorState, ErrorStateFilter, FilterConfig,
    FilterMode, OptionalVarianceBounds,
};
use nav_core::frames::LaunchFrame;
use nav_core::imu_error::ImuErrorEstimate;
use nav_core::measurement::{
    gnss_position, gnss_velocity, star_sensor, BodyRate, GnssVelocityFix, LinearMeasurement,
};
use nav_core::state::{
    BlockMask, OptionalBlock, StateBlock, ACCEL_BIAS, ATTITUDE, GYRO_BIAS, GYRO_SCALE_FACTOR,
    POSITION, STAR_INSTALLATION, VELOCITY,
};
use nav_core::strapdown::{
    ImuIncrement, NavigationState, SensorCorrections, StepOutput, Strapdown,
};
use nav_core::structured::StructuredModel;
use nav_core::unmodelled::{
    bilinear_attitude_rate_covariance, rate_error_correlation, CoherentGrowth,
};
use nav_core::NavError;

use crate::calibration_manager::{
    CalibrationManager, CalibrationTable, EstimationPolicy, ManoeuvrePhase, CALIBRATION_BLOCK_COUNT,
};
use crate::config::HeldSampleUncertainty;
use crate::config::{FswConfig, GNSS_QUEUE_CAPACITY, HISTORY_CAPACITY, STAR_QUEUE_CAPACITY};
use crate::consistency::{ConsistencyMonitor, CONSISTENT_MEAN_NIS};
use crate::error::{ConfigField, FswError};
use crate::health::{count, HealthCounters, OutageMonitor, WhitenessMonitor};
use crate::input_check::{check_gnss, check_star, GnssFault, ImuChecker, ImuFault, StarFault};
use crate::measurement_buffer::{BufferRefusal, MeasurementBuffer};
use crate::noise_matching::NoiseMatching;
use crate::ports::{self, GnssPort, ImuPort, StarSensorPort};
use crate::telemetry::{FrameCostMonitor, FrameFusion, FrameTelemetry};

mod aid;
mod calibration;
mod commands;
#[cfg(test)]
mod commands_tests;
mod covariance;
mod fusion;
mod gravity;
mod heads;
#[cfg(test)]
mod heads_tests;
mod history;
mod intake;
mod navigate;
mod outputs;
mod record;
#[cfg(test)]
mod record_tests;
mod start;
#[cfg(test)]
mod tests;

use aid::{Aid, AidingSensor, Sensor};
pub use commands::{AidingSensorId, Command, CommandCounters, CommandError, COMMAND_COUNTER_COUNT};
use covariance::PropagationSums;
use heads::StarHeads;
pub use heads::MAX_STAR_HEADS;
use history::{Correction, History, Snapshot};
use intake::{Due, GnssQueued};
/// Which implementation of the filter's matrix arithmetic the scheduler uses (nav-core's
/// one dispatch; the dense reference only with the `dense-reference` feature).
pub use nav_core::arithmetic::FilterArithmetic;

/// Two times closer than this fraction of the IMU period are the same instant: the round-off
/// of frame times accumulated over a flight stays far below it, and the nearest distinct
/// time (the next frame) is a million times farther.
const SAME_INSTANT_FRACTION_OF_PERIOD: f64 = 1e-6;

/// The attitude and star-installation error states are half-angles (the vector part of a
/// small rotation's quaternion, nav-core `state`): a rotation angle's 1σ is twice the
/// state's.
const HALF_ANGLE_PER_ANGLE: f64 = 0.5;
/// A rotation angle's variance per variance of its half-angle state.
const ANGLE_VARIANCE_PER_HALF_ANGLE_VARIANCE: f64 = 4.0;

/// Most measurements taken from one port in one frame (the rest wait in the port).
pub const MAX_POLLS_PER_FRAME: usize = 4;

/// The flight software: strapdown, filter, input checks, fault handling and calibration.
///
/// Its state is in six parts, each kept by the files of its job: `Navigation` (`navigate.rs`,
/// `history.rs`), `Covariance` (`covariance.rs`), `Aids` (`intake.rs`, `aid.rs`), `Health`,
/// `Calibration` (`calibration.rs`) and the tracker heads (`heads.rs`); `fusion.rs` joins them
/// for one update.
// Laid out in the order written (`repr(C)`, here and in the parts): the small members that
// every frame reads first, the large arrays (model, filter, history) after them, and last the
// configuration, whose values each frame reads a few of, and the heads, so that most members
// lie within the reach of a load's offset from the computer's address on the target (the
// compiler's own order puts some behind the large arrays; docs/guide/performance.md).
#[derive(Debug, Clone)]
#[repr(C)]
pub struct NavigationComputer {
    /// Frames run since start-up (wrapping).
    frame: u32,
    arithmetic: FilterArithmetic,
    health: Health,
    calibration: Calibration,
    aids: Aids,
    launch_frame: LaunchFrame,
    covariance: Covariance,
    navigation: Navigation,
    config: FswConfig,
    /// The tracker heads (`heads.rs`).
    heads: StarHeads,
    /// The matched test for an aberration the tracker leaves in and the configuration does
    /// not correct (`star.aberration_correction` off). Last, with the other small members
    /// the update frames do not read, so that it moves none of theirs out of a load's reach.
    star_aberration: crate::aberration_monitor::AberrationMonitor,
    /// The optional state blocks' variance floor and ceiling (`covariance.rs`), read by the
    /// propagation frames only while a block is in use: after every member the other frames
    /// read, so that it moves none of them.
    optional_variance_bounds: OptionalVarianceBounds,
    /// The aids disabled by command and the commands' counters: last, read by no frame's
    /// arithmetic, so that they move no other member out of a load's reach.
    operations: Operations,
}

/// The navigation solution and what produces it: the IMU step's state and the history of the
/// solution for delayed fusion.
#[derive(Debug, Clone)]
#[repr(C)]
struct Navigation {
    solution: NavigationState,
    frames_without_sample: u32,
    /// The last good IMU increment, held when a sample is missing or refused.
    last_increment: Option<ImuIncrement>,
    imu_checker: ImuChecker,
    strapdown: Strapdown,
    history: History,
    /// The field beyond `J2`, a few terms a frame (`gravity.rs`).
    gravity_field: nav_core::gravity::harmonics::FieldRemainder,
    /// Whether the last evaluation found the omitted field above the allowance.
    gravity_allowance_short: bool,
}

/// The error-state filter and its propagation: the discrete model, the motion of the interval,
/// the protection's bounds and the growth for what the model leaves out.
#[derive(Debug, Clone)]
#[repr(C)]
struct Covariance {
    /// Navigation time (s) of `P`: the time of its last propagation, or of the start. The
    /// filter's error state refers to it; a measurement is due once its time tag is no
    /// later (within `timing.future_tolerance_s`) and is referred to it.
    time_s: f64,
    sums: PropagationSums,
    /// Attitude (half-angle) and velocity 1σ accumulated over the current run of held IMU
    /// samples.
    held_attitude: CoherentGrowth,
    held_velocity: CoherentGrowth,
    /// Attitude 1σ (half-angle) of the second-order kinematics term accumulated since the
    /// last accepted star-sensor update.
    second_order_attitude: CoherentGrowth,
    /// Body rate of the previous growth step: the term grows coherently only while the gyro
    /// rate error stays the same random variable.
    second_order_rate_rad_s: Vector3<f64>,
    /// Propagation time (s) the second-order growth has not yet covered.
    second_order_pending_s: f64,
    /// Motion of the last covariance propagation (for referring late measurements).
    last_point: Option<LinearisationPoint>,
    variance_floor: ErrorState,
    variance_ceiling: ErrorState,
    /// The structured discrete model, refilled in place by every propagation (a large
    /// struct: building it in place avoids copying it).
    model: StructuredModel,
    filter: ErrorStateFilter,
    /// The process noise in use: `process_noise` with the gravity allowance's density added
    /// to the accelerometer's density squared (`gravity.rs`).
    process_noise: ProcessNoise,
    /// The installation states' walk for the tracker's slow error (rad²/s per sensor axis,
    /// `StarSensorConfig::installation_walk_rad2_per_s`), derived once; `None` when off.
    installation_walk_rad2_per_s: Option<[f64; 3]>,
}

/// The aiding measurements: their queues, the gate statistics and fault state of each aid and
/// sensor, and the outage and whiteness monitors.
#[derive(Debug, Clone)]
struct Aids {
    /// Each star head's last quaternion, in its own sign convention.
    last_star: [Option<Quaternion<f64>>; MAX_STAR_HEADS],
    star_queue: MeasurementBuffer<Quaternion<f64>, STAR_QUEUE_CAPACITY>,
    gnss_queue: MeasurementBuffer<GnssQueued, GNSS_QUEUE_CAPACITY>,
    /// The position of the GNSS fix whose velocity was fused last frame (one update per
    /// frame: it is fused in the next). The velocity goes first: fused in its own frame it
    /// needs no referral, while a position referred by one frame gains only a velocity block
    /// in `H` (a velocity referred gains five).
    pending_gnss_position: Option<(f64, Vector3<f64>)>,
    star: AidingSensor,
    gnss: AidingSensor,
    /// Gate statistics of the GNSS velocity (its fault state is the receiver's, `gnss`).
    gnss_velocity: AidingSensor,
    star_outage: OutageMonitor,
    gnss_outage: OutageMonitor,
    gnss_whiteness: WhitenessMonitor,
    star_consistency: ConsistencyMonitor,
    /// The star noise per sensor axis as the innovations show it, used once the star
    /// consistency test has failed (`star.noise_matching`).
    star_noise: NoiseMatching,
    gnss_consistency: ConsistencyMonitor,
    gnss_velocity_consistency: ConsistencyMonitor,
}

/// What the computer reports about itself: the health counters and the frame cost.
#[derive(Debug, Clone)]
struct Health {
    counters: HealthCounters,
    cost: FrameCostMonitor,
}

/// What operations set and count (`commands.rs`): the aids disabled by command and the
/// commands' counters. Read only when a measurement arrives or the telemetry is written.
#[derive(Debug, Clone)]
struct Operations {
    /// Each sensor disabled by command ([`Command::SetAidEnabled`]; star, GNSS).
    disabled: [bool; 2],
    commands: CommandCounters,
}

/// The calibration: the sensor corrections fed back (closed loop) and the manager's table.
#[derive(Debug, Clone)]
struct Calibration {
    estimate: CalibrationEstimate,
    /// The systematic IMU errors fed back (closed loop, `filter.imu_error` in use).
    imu_errors: ImuErrorEstimate,
    manager: CalibrationManager,
}

fn array3(vector: &Vector3<f64>) -> [f64; 3] {
    [vector.x, vector.y, vector.z]
}

impl NavigationComputer {
    /// Selects the filter arithmetic (default: structured, the flight path); the dense
    /// reference is for cost and equality comparisons.
    pub fn set_arithmetic(&mut self, arithmetic: FilterArithmetic) {
        self.arithmetic = arithmetic;
    }

    /// Sets the frame budget for overrun counting (unit of [`Self::report_frame_cost`]).
    pub fn set_frame_budget(&mut self, budget: u32) {
        self.health.cost.budget = budget;
    }

    /// The platform reports the cost of the frame just run (instructions or cycles).
    pub fn report_frame_cost(&mut self, cost: u32) {
        if self.health.cost.record(cost) {
            count(&mut self.health.counters.frame_overruns);
        }
    }

    /// Worst frame cost reported by the platform so far.
    pub fn worst_frame_cost(&self) -> u32 {
        self.health.cost.worst
    }

    /// One minor frame (module docs). Never fails: every fault is handled, counted and
    /// reported in the returned telemetry.
    pub fn run_frame<I, S, G>(&mut self, imu: &mut I, star: &mut S, gnss: &mut G) -> FrameTelemetry
    where
        I: ImuPort,
        S: StarSensorPort,
        G: GnssPort,
    {
        self.frame = self.frame.wrapping_add(1);
        self.navigate(imu.read());
        self.record_snapshot();
        let (fusion, paired) = if self.config.covariance.frame_load.defers_propagation() {
            self.poll_measurements(star, gnss);
            self.fuse_or_propagate()
        } else {
            if self.propagation_is_due() {
                self.propagate_covariance();
            }
            self.poll_measurements(star, gnss);
            (self.fuse_one_due_measurement(), false)
        };
        if fusion == FrameFusion::None && !paired {
            self.inflate_for_second_order_attitude();
            self.pair_star_heads();
            // Only in frames that fuse nothing: a measurement update, the dearest frame, never
            // carries the gravity field's share (`gravity.rs`).
            self.advance_gravity_field();
        }
        self.evaluate_calibration();
        self.telemetry(fusion)
    }

    /// A frame under [`crate::config::FrameLoad::FuseOrPropagate`]: the oldest due
    /// measurement fused, with the propagation waiting one frame (no longer: a measurement
    /// due when the propagation has waited a frame waits instead), or else the propagation
    /// if it is due. Not inlined: inlined into the frame loop, its two paths' locals would
    /// both be reserved in the frame loop's stack frame on the Cortex-M7
    /// (docs/guide/performance.md).
    ///
    /// A pair of the two star heads' measurements is such work too (the relative alignment's
    /// update, `heads.rs`): with no measurement due it takes the frame, and the propagation
    /// waits one frame as it does for a measurement, so a propagation frame, the dearest
    /// with every optional block, never carries it. Returns the fusion and whether the frame
    /// paired.
    #[inline(never)]
    fn fuse_or_propagate(&mut self) -> (FrameFusion, bool) {
        let interval = self.config.covariance.propagation_interval_frames;
        let waited = self.covariance.sums.frames > interval;
        if !waited && self.measurement_is_due() {
            return (self.fuse_one_due_measurement(), false);
        }
        if !waited && self.star_pair_is_pending() {
            self.pair_star_heads();
            return (FrameFusion::None, true);
        }
        if self.propagation_is_due() {
            self.propagate_covariance();
        }
        (FrameFusion::None, false)
    }

    /// Whether `covariance.propagation_interval_frames` frames have passed since the last
    /// propagation.
    fn propagation_is_due(&self) -> bool {
        self.covariance.sums.frames >= self.config.covariance.propagation_interval_frames
    }

    /// Navigation time (s) of the covariance: of its last propagation, or of the start. A
    /// fusion refers its measurement to this time.
    pub fn covariance_time_s(&self) -> f64 {
        self.covariance.time_s
    }

    /// The filter (error state and covariance).
    pub fn filter(&self) -> &ErrorStateFilter {
        &self.covariance.filter
    }

    /// The calibration table.
    pub fn calibration_table(&self) -> &CalibrationTable {
        self.calibration.manager.table()
    }

    /// The blocks frozen now.
    pub fn frozen_blocks(&self) -> BlockMask {
        self.calibration.manager.frozen_blocks()
    }

    /// What the configuration says the flight will lack (`health::ConfigurationWarnings`):
    /// constant for a flight, to be reported once at start-up; the counters leave it out.
    pub fn configuration_warnings(&self) -> crate::health::ConfigurationWarnings {
        crate::health::ConfigurationWarnings::of(&self.config)
    }

    /// The velocity aberration test's state (its statistic, fraction and twin in their own
    /// σ; nav-fsw `aberration_monitor`).
    pub fn aberration_monitor(&self) -> &crate::aberration_monitor::AberrationMonitor {
        &self.star_aberration
    }

    /// The health counters.
    pub fn health(&self) -> &HealthCounters {
        &self.health.counters
    }

    /// Measurements received and waiting to be fused (star and GNSS queues; a GNSS fix whose
    /// velocity is fused and whose position waits counts once): with the fusions and the
    /// health counters, every measurement received is accounted for.
    pub fn queued_measurements(&self) -> usize {
        self.aids
            .star_queue
            .len()
            .saturating_add(self.aids.gnss_queue.len())
            .saturating_add(usize::from(self.aids.pending_gnss_position.is_some()))
    }

    /// The star tracker head the filter fuses and whose installation error it carries (0, or
    /// 1 after a hand-over to `star.second_head`; `scheduler::heads`).
    pub fn active_star_head(&self) -> u8 {
        self.heads.active
    }

    /// The launch-inertial frame in use.
    pub fn launch_frame(&self) -> &LaunchFrame {
        &self.launch_frame
    }

    /// The configuration in use.
    pub fn config(&self) -> &FswConfig {
        &self.config
    }
}
