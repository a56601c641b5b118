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
//! 3. Covariance: every `propagation_interval_frames` frames, the error model at the mean
//!    rates/forces of the interval, 3rd-order `F` and `P ← F P Fᵀ + Qd` by blocks, in place
//!    (nav-core `structured`; paper §1.3.3), then covariance protection (variance floors
//!    and ceilings, counted; only the diagonal is read unless a bound is crossed).
//! 4. Measurements: at most [`MAX_POLLS_PER_FRAME`] new measurements per port are checked and
//!    queued; then **at most one** due measurement (the oldest) is fused. A second due
//!    measurement waits for the next frame: the worst frame is therefore strapdown + one
//!    propagation + one update (+ closed-loop reset), bounded by construction.
//! 5. Calibration manager: table, convergence, frozen set.
//!
//! Delayed fusion: the innovation and `H` are formed with the navigation solution at the
//! measurement's time of validity and referred to the current error state with
//! `H (I − A Δ)` (nav-core `refer_to_later_time_in_place`, by blocks of `A`).
//!
//! [`FilterArithmetic::DenseReference`] runs the same frame with nav-core's dense 24×24
//! reference arithmetic (equal within round-off), for cost comparisons only.
//!
//! Closed loop (the default): after every accepted update the error state is fed back into
//! the navigation solution, the history (each snapshot corrected when it is read, with the
//! feedbacks since it was recorded) and the sensor corrections, and the filter is reset
//! (nav-core `reset`), so `x = 0` whenever the filter predicts. Open loop (the paper): the
//! navigation solution is never corrected; outputs apply `x` on the way out.

use heapless::Deque;
use nalgebra::{Quaternion, Vector3};
use nav_core::attitude;
use nav_core::discretise::{discretise, DiscreteModel};
use nav_core::error_model::{noise_input_matrix, system_matrix, LinearisationPoint};
use nav_core::filter::{
    apply_error_state, block_of, CalibrationEstimate, ErrorState, ErrorStateFilter, FilterConfig,
    FilterMode,
};
use nav_core::frames::LaunchFrame;
use nav_core::measurement::{
    gnss_position, gnss_velocity, refer_to_later_time, star_sensor, BodyRate, LinearMeasurement,
};
use nav_core::state::{
    BlockMask, StateBlock, ACCEL_BIAS, ATTITUDE, CALIBRATION_BLOCKS, GYRO_BIAS, GYRO_SCALE_FACTOR,
    POSITION, STAR_INSTALLATION, VELOCITY,
};
use nav_core::strapdown::{
    ImuIncrement, NavigationState, SensorCorrections, StepOutput, Strapdown,
};
use nav_core::structured::{refer_to_later_time_in_place, StructuredModel};
use nav_core::unmodelled::{
    bilinear_attitude_rate_covariance, rate_error_correlation, CoherentGrowth,
};
use nav_core::NavError;

use crate::calibration_manager::{
    CalibrationManager, CalibrationTable, EstimationPolicy, ManoeuvrePhase, CALIBRATION_BLOCK_COUNT,
};
use crate::config::HeldSampleUncertainty;
use crate::config::{FswConfig, GNSS_QUEUE_CAPACITY, HISTORY_CAPACITY, STAR_QUEUE_CAPACITY};
use crate::error::{ConfigField, FswError};
use crate::health::{count, HealthCounters, OutageMonitor, WhitenessMonitor};
use crate::input_check::{check_gnss, check_star, GnssFault, ImuChecker, ImuFault, StarFault};
use crate::measurement_buffer::{BufferRefusal, MeasurementBuffer};
use crate::ports::{self, GnssPort, ImuPort, StarSensorPort};
use crate::telemetry::{FrameCostMonitor, FrameFusion, FrameTelemetry};

/// Most measurements taken from one port in one frame (the rest wait in the port).
pub const MAX_POLLS_PER_FRAME: usize = 4;

/// Ground or flight-plan commands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Command {
    /// The manoeuvre phase: drives the calibration manager under
    /// [`EstimationPolicy::PaperSchedule`]; refused under a policy that does not read it
    /// ([`EstimationPolicy::uses_phase`]).
    SetPhase(ManoeuvrePhase),
    /// Forget the fault declarations: both sensors are used again.
    ClearSensorFaults,
    /// Forget calibration convergence (unfreeze every block).
    RestartCalibration,
}

/// Why a [`Command`] was refused (the computer is unchanged).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CommandError {
    /// `SetPhase` under a policy that does not read the manoeuvre phase.
    PhaseNotUsed(EstimationPolicy),
}

impl core::fmt::Display for CommandError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::PhaseNotUsed(policy) => write!(
                f,
                "SetPhase refused: the calibration policy {policy:?} does not use the manoeuvre \
                 phase (only PaperSchedule does)"
            ),
        }
    }
}

impl core::error::Error for CommandError {}

/// Which implementation of the filter's matrix arithmetic the scheduler uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FilterArithmetic {
    /// The flight path: block-structured propagation, update, referral and reset
    /// (nav-core `structured`).
    #[default]
    Structured,
    /// The dense 24×24 reference (nav-core `discretise`, `predict`, Joseph update,
    /// `refer_to_later_time`, `reset_dense`): equal within round-off, for cost comparisons.
    DenseReference,
}

// The dense reference paths (cost comparisons only) live in their own never-inlined
// functions: inlined, their 24×24 temporaries (84 KB in `propagate_covariance`) would be
// reserved in the flight path's stack frames even though flight never takes these branches.

/// Dense reference propagation ([`FilterArithmetic::DenseReference`]).
#[inline(never)]
fn dense_predict(
    filter: &mut ErrorStateFilter,
    point: &LinearisationPoint,
    noise: &nav_core::error_model::ProcessNoise,
    interval_s: f64,
    order: u8,
    frozen: &BlockMask,
) -> Result<(), NavError> {
    dense_model(point, noise, interval_s, order, frozen).and_then(|model| filter.predict(&model))
}

/// Dense reference late-measurement referral.
#[inline(never)]
fn dense_referral(
    measurement: &mut LinearMeasurement,
    point: &LinearisationPoint,
    latency_s: f64,
) -> Result<(), NavError> {
    *measurement = refer_to_later_time(measurement, &system_matrix(point), latency_s)?;
    Ok(())
}

/// Dense reference Joseph update.
#[inline(never)]
fn dense_update(
    filter: &mut ErrorStateFilter,
    measurement: &LinearMeasurement,
    gate: f64,
    frozen: &BlockMask,
) -> Result<nav_core::filter::InnovationReport, NavError> {
    filter.update_with_frozen_blocks(measurement, gate, frozen)
}

/// Dense reference reset.
#[inline(never)]
fn dense_reset(filter: &mut ErrorStateFilter) -> nav_core::filter::ErrorState {
    filter.reset_dense()
}

/// The dense reference discrete model with the process noise of the `frozen` blocks removed
/// (as [`StructuredModel::remove_process_noise`]).
fn dense_model(
    point: &LinearisationPoint,
    noise: &nav_core::error_model::ProcessNoise,
    interval_s: f64,
    order: u8,
    frozen: &BlockMask,
) -> Result<DiscreteModel, NavError> {
    let mut model = discretise(
        &system_matrix(point),
        &noise_input_matrix(point),
        &noise.spectral_density_diagonal(),
        interval_s,
        order,
    )?;
    model.remove_process_noise(frozen);
    Ok(model)
}

/// Navigation solution of one frame, kept for delayed fusion, as it was when recorded: the
/// closed-loop corrections fed back since then are applied when it is read
/// ([`NavigationComputer::corrected`]).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Snapshot {
    /// Frame counter when recorded.
    frame: u32,
    time_s: f64,
    attitude: Quaternion<f64>,
    position_m: Vector3<f64>,
    velocity_mps: Vector3<f64>,
}

/// One closed-loop correction of the navigation solution (attitude `q ← q ⊗ δq`, position
/// `p ← p + δp`, velocity `v ← v + δv`), kept for the snapshots recorded up to its frame.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Correction {
    /// Frame counter of the feedback.
    frame: u32,
    attitude: Quaternion<f64>,
    position_m: Vector3<f64>,
    velocity_mps: Vector3<f64>,
}

/// A GNSS fix in the launch-inertial frame, queued until due.
#[derive(Debug, Clone, Copy, PartialEq)]
struct GnssQueued {
    position_m: [f64; 3],
    /// Valid when `has_velocity` (the receiver outputs velocity and velocity fusion is
    /// configured); plain words rather than an `Option` keep the queue's copies word-aligned.
    velocity_mps: [f64; 3],
    has_velocity: bool,
}

/// Gate statistics and fault state of one aiding sensor.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct AidingSensor {
    consecutive_rejections: u32,
    faulty: bool,
    last_nis: f64,
}

/// Rates and forces summed over the covariance-propagation interval.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PropagationSums {
    frames: u32,
    corrected_rate: Vector3<f64>,
    measured_rate: Vector3<f64>,
    corrected_force: Vector3<f64>,
    measured_force: Vector3<f64>,
}

impl PropagationSums {
    const EMPTY: PropagationSums = PropagationSums {
        frames: 0,
        corrected_rate: Vector3::new(0.0, 0.0, 0.0),
        measured_rate: Vector3::new(0.0, 0.0, 0.0),
        corrected_force: Vector3::new(0.0, 0.0, 0.0),
        measured_force: Vector3::new(0.0, 0.0, 0.0),
    };

    fn add(&mut self, step: &StepOutput) {
        self.frames = self.frames.saturating_add(1);
        self.corrected_rate += step.corrected_rate_rad_s;
        self.measured_rate += step.measured_rate_rad_s;
        self.corrected_force += step.corrected_specific_force_mps2;
        self.measured_force += step.measured_specific_force_mps2;
    }
}

/// The aiding measurements, one routine each for forming them and one shared path for
/// referral, update and fault handling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Aid {
    Star,
    GnssPosition,
    GnssVelocity,
}

impl Aid {
    /// Telemetry of an accepted or rejected measurement.
    const fn fusion(self, accepted: bool) -> FrameFusion {
        match (self, accepted) {
            (Aid::Star, true) => FrameFusion::StarAccepted,
            (Aid::Star, false) => FrameFusion::StarRejected,
            (Aid::GnssPosition, true) => FrameFusion::GnssAccepted,
            (Aid::GnssPosition, false) => FrameFusion::GnssRejected,
            (Aid::GnssVelocity, true) => FrameFusion::GnssVelocityAccepted,
            (Aid::GnssVelocity, false) => FrameFusion::GnssVelocityRejected,
        }
    }

    /// Whether the measurement comes from the star sensor (else the GNSS receiver, whose
    /// position and velocity share one fault state).
    const fn is_star(self) -> bool {
        matches!(self, Aid::Star)
    }
}

/// Which queued measurement to fuse.
enum Due {
    Star(f64, Quaternion<f64>),
    GnssPosition(f64, Vector3<f64>),
    GnssVelocity(f64, Vector3<f64>),
}

impl Due {
    const fn aid(&self) -> Aid {
        match self {
            Due::Star(..) => Aid::Star,
            Due::GnssPosition(..) => Aid::GnssPosition,
            Due::GnssVelocity(..) => Aid::GnssVelocity,
        }
    }

    const fn time_tag_s(&self) -> f64 {
        match self {
            Due::Star(tag, _) | Due::GnssPosition(tag, _) | Due::GnssVelocity(tag, _) => *tag,
        }
    }
}

/// The flight software: strapdown, filter, input checks, fault handling and calibration.
#[derive(Debug, Clone)]
pub struct NavigationComputer {
    config: FswConfig,
    launch_frame: LaunchFrame,
    strapdown: Strapdown,
    navigation: NavigationState,
    filter: ErrorStateFilter,
    calibration: CalibrationEstimate,
    manager: CalibrationManager,
    imu_checker: ImuChecker,
    last_increment: Option<ImuIncrement>,
    frames_without_sample: u32,
    history: Deque<Snapshot, HISTORY_CAPACITY>,
    /// The feedbacks of the last [`HISTORY_CAPACITY`] frames (at most one per frame), applied
    /// to a snapshot when it is read: correcting all 64 snapshots at every feedback cost
    /// ~2,000 instructions on the target.
    corrections: Deque<Correction, HISTORY_CAPACITY>,
    star_queue: MeasurementBuffer<Quaternion<f64>, STAR_QUEUE_CAPACITY>,
    gnss_queue: MeasurementBuffer<GnssQueued, GNSS_QUEUE_CAPACITY>,
    /// The position of the GNSS fix whose velocity was fused last frame (one update per
    /// frame: it is fused in the next). The velocity goes first: fused in its own frame it
    /// needs no referral, while a position referred by one frame gains only a velocity block
    /// in `H` (a velocity referred gains five).
    pending_gnss_position: Option<(f64, Vector3<f64>)>,
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
    last_star: Option<Quaternion<f64>>,
    star: AidingSensor,
    gnss: AidingSensor,
    /// Gate statistics of the GNSS velocity (its fault state is the receiver's, `gnss`).
    gnss_velocity: AidingSensor,
    star_outage: OutageMonitor,
    gnss_outage: OutageMonitor,
    gnss_whiteness: WhitenessMonitor,
    sums: PropagationSums,
    /// Motion of the last covariance propagation (for referring late measurements).
    last_point: Option<LinearisationPoint>,
    /// The structured discrete model, refilled in place by every propagation (a ~2 KB
    /// struct: building it in place avoids copies that cost thousands of instructions).
    model: StructuredModel,
    variance_floor: ErrorState,
    variance_ceiling: ErrorState,
    health: HealthCounters,
    cost: FrameCostMonitor,
    frame: u32,
    arithmetic: FilterArithmetic,
}

fn sensor_corrections(calibration: &CalibrationEstimate) -> SensorCorrections {
    SensorCorrections {
        gyro_bias_rad_s: Vector3::from(calibration.gyro_bias_rad_s),
        accel_bias_mps2: Vector3::from(calibration.accel_bias_mps2),
        gyro_scale_factor: Vector3::from(calibration.gyro_scale_factor),
        accel_scale_factor: Vector3::from(calibration.accel_scale_factor),
    }
}

fn array3(vector: &Vector3<f64>) -> [f64; 3] {
    [vector.x, vector.y, vector.z]
}

/// `q0 ⊗ exp(s · log(q0* ⊗ q1))`: constant-rate interpolation between two attitudes.
fn interpolate_attitude(q0: &Quaternion<f64>, q1: &Quaternion<f64>, s: f64) -> Quaternion<f64> {
    let relative = attitude::log_rotation_vector(&attitude::product(&attitude::conjugate(q0), q1));
    attitude::product(q0, &attitude::exp_rotation_vector(&(relative * s)))
}

impl NavigationComputer {
    /// The flight software at start: the given navigation solution, `x = 0`, `P` from the
    /// configured initial 1σ, no calibration (zero corrections).
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] for a bad configuration (named field) or a
    /// non-finite / non-unit initial navigation state.
    pub fn new(config: FswConfig, initial: NavigationState) -> Result<Self, FswError> {
        config.validate()?;
        let attitude_norm = initial.attitude.norm();
        let finite = attitude::all_finite3(&initial.position_m)
            && attitude::all_finite3(&initial.velocity_mps)
            && initial.time_s.is_finite();
        if !(finite && attitude_norm.is_finite() && (attitude_norm - 1.0).abs() < 1e-9) {
            return Err(FswError::InvalidConfiguration(
                ConfigField::InitialNavigation,
            ));
        }
        let floors = ErrorStateFilter::new(&FilterConfig {
            initial: config.covariance.sigma_floor,
            ..config.filter
        })?;
        let initial_filter = ErrorStateFilter::new(&config.filter)?;
        let ceiling_factor = config.covariance.sigma_ceiling_factor;
        let launch_frame = LaunchFrame::new(&config.launch_site)
            .map_err(|_| FswError::InvalidConfiguration(ConfigField::LaunchSite))?;
        let mut computer = Self {
            config,
            launch_frame,
            strapdown: Strapdown::new(config.strapdown),
            navigation: initial,
            filter: initial_filter,
            calibration: CalibrationEstimate::default(),
            manager: CalibrationManager::new(config.calibration)?,
            imu_checker: ImuChecker::new(config.imu)?,
            last_increment: None,
            frames_without_sample: 0,
            history: Deque::new(),
            corrections: Deque::new(),
            star_queue: MeasurementBuffer::new(),
            gnss_queue: MeasurementBuffer::new(),
            pending_gnss_position: None,
            held_attitude: CoherentGrowth::default(),
            held_velocity: CoherentGrowth::default(),
            second_order_attitude: CoherentGrowth::default(),
            second_order_rate_rad_s: Vector3::zeros(),
            second_order_pending_s: 0.0,
            last_star: None,
            star: AidingSensor::default(),
            gnss: AidingSensor::default(),
            gnss_velocity: AidingSensor::default(),
            star_outage: OutageMonitor::default(),
            gnss_outage: OutageMonitor::default(),
            gnss_whiteness: WhitenessMonitor::default(),
            sums: PropagationSums::EMPTY,
            last_point: None,
            model: StructuredModel::EMPTY,
            variance_floor: floors.covariance().diagonal(),
            variance_ceiling: initial_filter.covariance().diagonal()
                * (ceiling_factor * ceiling_factor),
            health: HealthCounters::default(),
            cost: FrameCostMonitor::new(u32::MAX),
            frame: 0,
            arithmetic: FilterArithmetic::Structured,
        };
        computer.record_snapshot();
        Ok(computer)
    }

    /// Selects the filter arithmetic (default: structured, the flight path); the dense
    /// reference is for cost and equality comparisons.
    pub fn set_arithmetic(&mut self, arithmetic: FilterArithmetic) {
        self.arithmetic = arithmetic;
    }

    /// Sets the frame budget for overrun counting (unit of [`Self::report_frame_cost`]).
    pub fn set_frame_budget(&mut self, budget: u32) {
        self.cost.budget = budget;
    }

    /// The platform reports the cost of the frame just run (instructions or cycles).
    pub fn report_frame_cost(&mut self, cost: u32) {
        if self.cost.record(cost) {
            count(&mut self.health.frame_overruns);
        }
    }

    /// Worst frame cost reported by the platform so far.
    pub fn worst_frame_cost(&self) -> u32 {
        self.cost.worst
    }

    /// Executes a command.
    ///
    /// # Errors
    /// [`CommandError::PhaseNotUsed`] for `SetPhase` under a policy that does not read the
    /// phase; the computer is unchanged.
    pub fn command(&mut self, command: Command) -> Result<(), CommandError> {
        match command {
            Command::SetPhase(phase) => {
                let policy = self.config.calibration.policy;
                if !policy.uses_phase() {
                    return Err(CommandError::PhaseNotUsed(policy));
                }
                self.manager.set_phase(phase);
            }
            Command::ClearSensorFaults => {
                self.star = AidingSensor::default();
                self.gnss = AidingSensor::default();
                self.gnss_velocity = AidingSensor::default();
            }
            Command::RestartCalibration => self.manager.restart(),
        }
        Ok(())
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
        if self.sums.frames >= self.config.covariance.propagation_interval_frames {
            self.propagate_covariance();
        }
        self.poll_measurements(star, gnss);
        let fusion = self.fuse_one_due_measurement();
        if fusion == FrameFusion::None {
            self.inflate_for_second_order_attitude();
        }
        self.evaluate_calibration();
        self.telemetry(fusion)
    }

    fn navigate(&mut self, sample: Option<ports::ImuSample>) {
        let period_s = self.config.imu.period_s;
        let mut saturated = false;
        let checked = match sample {
            None => {
                count(&mut self.health.imu_missing);
                self.frames_without_sample = self.frames_without_sample.saturating_add(1);
                None
            }
            Some(sample) => {
                let result = self.imu_checker.check(&sample);
                match result {
                    Ok(continuity) => {
                        // Gaps already counted frame by frame are not counted twice.
                        let unseen = continuity
                            .missing_samples
                            .saturating_sub(self.frames_without_sample);
                        self.health.imu_missing = self.health.imu_missing.saturating_add(unseen);
                        Some(sample)
                    }
                    Err(ImuFault::TimeJump) => {
                        // The increments are sound; only the time tag is wrong. Navigation
                        // time is frame-driven, so the sample is used.
                        count(&mut self.health.imu_time_jump);
                        Some(sample)
                    }
                    Err(ImuFault::NonFinite) => {
                        count(&mut self.health.imu_non_finite);
                        None
                    }
                    Err(ImuFault::Saturated) => {
                        count(&mut self.health.imu_saturated);
                        saturated = true;
                        None
                    }
                    Err(ImuFault::Duplicate) => {
                        count(&mut self.health.imu_duplicate);
                        None
                    }
                }
            }
        };
        let held = match (&checked, &sample) {
            (Some(_), _) => None,
            (None, Some(raw)) if saturated => Some(self.saturation_sigma(raw)),
            (None, _) => Some(self.config.covariance.held_sample),
        };
        self.inflate_for_held_sample(held);
        let increment = match checked {
            Some(sample) => {
                self.frames_without_sample = 0;
                let increment = ImuIncrement {
                    delta_angle_rad: ports::vector(&sample.delta_angle_rad),
                    delta_velocity_mps: ports::vector(&sample.delta_velocity_mps),
                    interval_s: period_s,
                };
                self.last_increment = Some(increment);
                increment
            }
            None => self.last_increment.unwrap_or(ImuIncrement {
                delta_angle_rad: Vector3::zeros(),
                delta_velocity_mps: Vector3::zeros(),
                interval_s: period_s,
            }),
        };
        let corrections = match self.filter.mode() {
            FilterMode::ClosedLoop => sensor_corrections(&self.calibration),
            FilterMode::OpenLoop => SensorCorrections::default(),
        };
        match self.strapdown.step(
            &mut self.navigation,
            &increment,
            &corrections,
            &self.launch_frame,
        ) {
            Ok(step) => self.sums.add(&step),
            Err(_) => {
                // nav-core left the solution untouched; time still advances with the frame.
                count(&mut self.health.strapdown_failures);
                self.navigation.time_s += period_s;
            }
        }
    }

    /// A saturated sample's error, channel by channel: at least the IMU's range on a channel
    /// at or beyond full scale (the truth is beyond it by an unknown amount), the held-sample
    /// σ on the other.
    fn saturation_sigma(&self, sample: &ports::ImuSample) -> HeldSampleUncertainty {
        let (held, limits) = (self.config.covariance.held_sample, self.config.imu);
        let at_full_scale = |values: &[f64; 3], range: f64| {
            values
                .iter()
                .any(|value| value.abs() >= range * limits.period_s)
        };
        let gyro = at_full_scale(&sample.delta_angle_rad, limits.max_rate_rad_s);
        let accelerometer =
            at_full_scale(&sample.delta_velocity_mps, limits.max_specific_force_mps2);
        HeldSampleUncertainty {
            rate_rad_s: if gyro {
                held.rate_rad_s.max(limits.max_rate_rad_s)
            } else {
                held.rate_rad_s
            },
            specific_force_mps2: if accelerometer {
                held.specific_force_mps2.max(limits.max_specific_force_mps2)
            } else {
                held.specific_force_mps2
            },
        }
    }

    /// The covariance grows for what a held IMU sample may be wrong by
    /// ([`HeldSampleUncertainty`]), coherently (nav-core `unmodelled`): the held error is the
    /// same all gap long, so the 1σ grows as the number of held frames. Attitude states are
    /// half-angles, so their σ is half the angle's.
    fn inflate_for_held_sample(&mut self, held: Option<HeldSampleUncertainty>) {
        let Some(sigma) = held else {
            self.held_attitude.restart();
            self.held_velocity.restart();
            return;
        };
        count(&mut self.health.imu_held_frames);
        let period_s = self.config.imu.period_s;
        let added = [
            (
                ATTITUDE,
                self.held_attitude.grow(0.5 * sigma.rate_rad_s * period_s),
            ),
            (
                VELOCITY,
                self.held_velocity
                    .grow(sigma.specific_force_mps2 * period_s),
            ),
        ];
        for (block, variance) in added {
            if self.filter.add_block_variance(block, variance).is_err() {
                count(&mut self.health.filter_errors);
            }
        }
    }

    fn record_snapshot(&mut self) {
        if self.history.is_full() {
            self.history.pop_front();
        }
        // Cannot fail after the pop above; a refusal would only lose the oldest entry.
        let _ = self.history.push_back(Snapshot {
            frame: self.frame,
            time_s: self.navigation.time_s,
            attitude: self.navigation.attitude,
            position_m: self.navigation.position_m,
            velocity_mps: self.navigation.velocity_mps,
        });
    }

    /// `snapshot` with every correction fed back since it was recorded (in its frame or
    /// later), in feedback order: the same arithmetic as correcting the whole history at
    /// each feedback. Frame counters are compared by age (wrapping). The corrections are in
    /// feedback order, so those to apply are the newest ones: counted from the back, then
    /// applied oldest first (a measurement of the current frame needs none).
    fn corrected(&self, snapshot: &Snapshot) -> Snapshot {
        let snapshot_age = self.frame.wrapping_sub(snapshot.frame);
        let applies =
            |correction: &Correction| self.frame.wrapping_sub(correction.frame) <= snapshot_age;
        let newer = self
            .corrections
            .iter()
            .rev()
            .take_while(|correction| applies(correction))
            .count();
        let (older_half, newer_half) = self.corrections.as_slices();
        let first = self.corrections.len().saturating_sub(newer);
        let (from_older, from_newer) = match first.checked_sub(older_half.len()) {
            None => (older_half.get(first..).unwrap_or(&[]), newer_half),
            Some(offset) => (&[][..], newer_half.get(offset..).unwrap_or(&[])),
        };
        let mut corrected = *snapshot;
        for correction in from_older.iter().chain(from_newer) {
            corrected.attitude = attitude::product(&corrected.attitude, &correction.attitude);
            corrected.position_m += correction.position_m;
            corrected.velocity_mps += correction.velocity_mps;
        }
        corrected
    }

    /// The navigation solution at `time_s`, interpolated between the two bracketing frames
    /// of the history (both corrected first); `None` outside the history. Searched from the
    /// newest frame, where most measurements fall (the frame times increase, so the match
    /// or the bracketing pair is the one a search from the oldest would find).
    fn snapshot_at(&self, time_s: f64) -> Option<Snapshot> {
        let tolerance = 1e-6 * self.config.imu.period_s;
        let mut later: Option<&Snapshot> = None;
        for snapshot in self.history.iter().rev() {
            if (snapshot.time_s - time_s).abs() <= tolerance {
                return Some(self.corrected(snapshot));
            }
            if snapshot.time_s < time_s {
                let Some(after) = later else {
                    // A tag a little after the newest frame (within the future tolerance,
                    // e.g. clock rounding) uses the newest frame.
                    let future_s = time_s - snapshot.time_s;
                    return (future_s <= self.config.timing.future_tolerance_s)
                        .then(|| self.corrected(snapshot));
                };
                // `after` is later than `time_s`: it was neither a match nor earlier.
                let (before, after) = (self.corrected(snapshot), self.corrected(after));
                let s = (time_s - before.time_s) / (after.time_s - before.time_s);
                return Some(Snapshot {
                    frame: after.frame,
                    time_s,
                    attitude: interpolate_attitude(&before.attitude, &after.attitude, s),
                    position_m: before.position_m + (after.position_m - before.position_m) * s,
                    velocity_mps: before.velocity_mps
                        + (after.velocity_mps - before.velocity_mps) * s,
                });
            }
            later = Some(snapshot);
        }
        None
    }

    fn propagate_covariance(&mut self) {
        let sums = self.sums;
        self.sums = PropagationSums::EMPTY;
        let frames = f64::from(sums.frames.max(1));
        let interval_s = frames * self.config.imu.period_s;
        let point = LinearisationPoint {
            corrected_rate_rad_s: sums.corrected_rate / frames,
            corrected_specific_force_mps2: sums.corrected_force / frames,
            measured_rate_rad_s: sums.measured_rate / frames,
            measured_specific_force_mps2: sums.measured_force / frames,
            body_to_inertial: attitude::rotation_matrix(&self.navigation.attitude),
            gravity_gradient_per_s2: self
                .config
                .strapdown
                .gravity
                .gravity_gradient_launch(&self.launch_frame, &self.navigation.position_m),
        };
        self.last_point = Some(point);
        self.manager.observe_motion(
            &point.corrected_rate_rad_s,
            &point.corrected_specific_force_mps2,
        );
        // Block-structured discretisation and F P Fᵀ + Qd (nav-core `structured`); frozen
        // blocks get no process noise.
        let frozen = self.manager.frozen_blocks();
        let order = self.config.filter.discretisation_order;
        let result = match self.arithmetic {
            FilterArithmetic::Structured => {
                match self
                    .model
                    .rebuild(&point, &self.config.process_noise, interval_s, order)
                {
                    Ok(()) => {
                        self.model.remove_process_noise(&frozen);
                        self.filter.predict_structured(&self.model)
                    }
                    Err(error) => Err(error),
                }
            }
            FilterArithmetic::DenseReference => dense_predict(
                &mut self.filter,
                &point,
                &self.config.process_noise,
                interval_s,
                order,
                &frozen,
            ),
        };
        match result {
            Ok(()) => {
                self.second_order_pending_s += interval_s;
                self.protect_covariance();
            }
            Err(_) => self.recover_filter(),
        }
    }

    /// The attitude covariance grows for the kinematics' second-order term `½ ϑ × δω`
    /// (`covariance.second_order_attitude`, nav-core `unmodelled`): in the direction of the
    /// term's covariance, by its 1σ accumulated since the last accepted star-sensor update,
    /// coherently while the gyro rate error stays correlated with the previous step's.
    /// It runs in frames that fuse no measurement, which have time to spare (aiding comes at
    /// 10 Hz, the IMU at 500 Hz), over the propagation time since it last ran, at the last
    /// propagation's rate.
    fn inflate_for_second_order_attitude(&mut self) {
        let (Some(point), true) = (
            self.last_point,
            self.config.covariance.second_order_attitude.is_bounded(),
        ) else {
            return;
        };
        let (measured_rate_rad_s, interval_s) =
            (&point.measured_rate_rad_s, self.second_order_pending_s);
        self.second_order_pending_s = 0.0;
        let rate_covariance =
            bilinear_attitude_rate_covariance(self.filter.covariance(), measured_rate_rad_s);
        let rate_variance = rate_covariance.trace();
        if !(rate_variance.is_finite() && rate_variance > 0.0) {
            return;
        }
        let correlation = rate_error_correlation(
            self.filter.covariance(),
            measured_rate_rad_s,
            &self.second_order_rate_rad_s,
        );
        self.second_order_rate_rad_s = *measured_rate_rad_s;
        let added = self
            .second_order_attitude
            .grow_correlated(libm::sqrt(rate_variance) * interval_s, correlation);
        let direction = rate_covariance / rate_variance;
        if self
            .filter
            .add_block_covariance(ATTITUDE, &(direction * added))
            .is_err()
        {
            count(&mut self.health.filter_errors);
        }
    }

    /// The attitude is measured (or the filter starts afresh): the second-order growth starts
    /// again from zero.
    fn restart_second_order_attitude(&mut self) {
        self.second_order_attitude.restart();
        self.second_order_pending_s = 0.0;
    }

    /// Documented recovery from a filter that nav-core refuses to propagate (non-finite
    /// result): `x = 0`, `P` re-initialised from the configured 1σ, calibration convergence
    /// forgotten; the navigation solution and the sensor corrections fed back so far are
    /// kept. Counted in `filter_resets`.
    fn recover_filter(&mut self) {
        count(&mut self.health.filter_resets);
        if let Ok(filter) = ErrorStateFilter::new(&self.config.filter) {
            self.filter = filter;
        }
        self.restart_second_order_attitude();
        self.manager.restart();
    }

    /// Variance floors and ceilings (module docs), in place: only the diagonal is read unless
    /// a bound is crossed (nav-core `protect_variances`); symmetry is kept by construction.
    fn protect_covariance(&mut self) {
        if self
            .filter
            .protect_variances(&self.variance_floor, &self.variance_ceiling)
        {
            count(&mut self.health.covariance_clamps);
            if !self.filter.covariance().iter().all(|v| v.is_finite()) {
                self.recover_filter();
            }
        }
    }

    fn poll_measurements<S: StarSensorPort, G: GnssPort>(&mut self, star: &mut S, gnss: &mut G) {
        let now_s = self.navigation.time_s;
        let timing = self.config.timing;
        let (mut star_heard, mut gnss_heard) = (false, false);
        for _ in 0..MAX_POLLS_PER_FRAME {
            let Some(measurement) = star.poll() else {
                break;
            };
            star_heard = true;
            match check_star(
                &measurement,
                self.last_star.as_ref(),
                self.config.star.unit_norm_tolerance,
            ) {
                Err(StarFault::NonFinite) => count(&mut self.health.star_non_finite),
                Err(StarFault::NotUnit) => count(&mut self.health.star_not_unit),
                Ok((quaternion, flipped)) => {
                    if flipped {
                        count(&mut self.health.star_sign_flip);
                    }
                    // Remember the sensor's own sign, so that a sensor that changes its sign
                    // convention (e.g. keeps w ≥ 0 while the attitude turns) is counted once
                    // per change, not on every later sample.
                    self.last_star = Some(if flipped { -quaternion } else { quaternion });
                    let pushed = self.star_queue.push(
                        measurement.time_tag_s,
                        quaternion,
                        now_s,
                        timing.max_latency_s,
                        timing.future_tolerance_s,
                    );
                    if let Err(refusal) = pushed {
                        self.count_refusal(refusal, true);
                    }
                }
            }
        }
        for _ in 0..MAX_POLLS_PER_FRAME {
            let Some(fix) = gnss.poll() else {
                break;
            };
            gnss_heard = true;
            match self.gnss_in_launch_frame(&fix) {
                Err(_) => count(&mut self.health.gnss_non_finite),
                Ok(queued) => {
                    let pushed = self.gnss_queue.push(
                        fix.time_tag_s,
                        queued,
                        now_s,
                        timing.max_latency_s,
                        timing.future_tolerance_s,
                    );
                    if let Err(refusal) = pushed {
                        self.count_refusal(refusal, false);
                    }
                }
            }
        }
        let timeout_s = timing.outage_timeout_s;
        if self.star_outage.observe(now_s, star_heard, timeout_s) {
            count(&mut self.health.star_outages);
        }
        if self.gnss_outage.observe(now_s, gnss_heard, timeout_s) {
            count(&mut self.health.gnss_outages);
        }
    }

    /// A fix converted to the launch-inertial frame; its velocity only when velocity fusion
    /// is configured (`gnss.velocity_noise_mps > 0`).
    fn gnss_in_launch_frame(&self, fix: &ports::GnssFix) -> Result<GnssQueued, NavError> {
        let position_ecef = ports::vector(&fix.position_ecef_m);
        let position_m = self
            .launch_frame
            .ecef_to_launch_inertial(&position_ecef, fix.time_tag_s)?;
        let velocity_mps = match fix.velocity_ecef_mps {
            Some(velocity) if self.config.gnss.velocity_noise_mps > 0.0 => {
                Some(self.launch_frame.ecef_velocity_to_launch_inertial(
                    &position_ecef,
                    &ports::vector(&velocity),
                    fix.time_tag_s,
                )?)
            }
            _ => None,
        };
        Ok(GnssQueued {
            position_m: array3(&position_m),
            velocity_mps: velocity_mps.as_ref().map_or([0.0; 3], array3),
            has_velocity: velocity_mps.is_some(),
        })
    }

    fn count_refusal(&mut self, refusal: BufferRefusal, is_star: bool) {
        let counter = match (refusal, is_star) {
            (BufferRefusal::Stale, _) => &mut self.health.measurement_stale,
            (BufferRefusal::Future, _) => &mut self.health.measurement_future,
            (BufferRefusal::Overflow, _) => &mut self.health.measurement_overflow,
            (BufferRefusal::NonFinite, true) => &mut self.health.star_non_finite,
            (BufferRefusal::NonFinite, false) => &mut self.health.gnss_non_finite,
        };
        count(counter);
    }

    fn next_due(&mut self) -> Option<Due> {
        if let Some((tag, position)) = self.pending_gnss_position.take() {
            return Some(Due::GnssPosition(tag, position));
        }
        let due_before_s = self.navigation.time_s + self.config.timing.future_tolerance_s;
        let star_tag = self
            .star_queue
            .oldest_time_tag()
            .filter(|t| *t <= due_before_s);
        let gnss_tag = self
            .gnss_queue
            .oldest_time_tag()
            .filter(|t| *t <= due_before_s);
        let star_first = match (star_tag, gnss_tag) {
            (Some(s), Some(g)) => s <= g,
            (Some(_), None) => true,
            (None, Some(_)) => false,
            (None, None) => return None,
        };
        if star_first {
            self.star_queue
                .pop_due(due_before_s)
                .map(|(tag, q)| Due::Star(tag, q))
        } else {
            let (tag, fix) = self.gnss_queue.pop_due(due_before_s)?;
            let position = ports::vector(&fix.position_m);
            if fix.has_velocity {
                self.pending_gnss_position = Some((tag, position));
                Some(Due::GnssVelocity(tag, ports::vector(&fix.velocity_mps)))
            } else {
                Some(Due::GnssPosition(tag, position))
            }
        }
    }

    fn installation_estimate(&self) -> Quaternion<f64> {
        ports::quaternion(&self.calibration.star_installation_wxyz)
    }

    fn fuse_one_due_measurement(&mut self) -> FrameFusion {
        let Some(due) = self.next_due() else {
            return FrameFusion::None;
        };
        let (aid, tag) = (due.aid(), due.time_tag_s());
        if self.fault_state(aid).faulty {
            count(&mut self.health.ignored_from_faulty_sensor);
            return aid.fusion(false);
        }
        let Some(snapshot) = self.snapshot_at(tag) else {
            count(&mut self.health.measurement_stale);
            return FrameFusion::None;
        };
        if self.is_gnss_jump(&due, &snapshot) {
            count(&mut self.health.gnss_jump);
            self.note_rejection(aid);
            return aid.fusion(false);
        }
        // Formed where it lies: the 672-byte measurement is never copied.
        let mut measurement = self.form_measurement(&due, &snapshot);
        // A late measurement is referred to the current error state (nav-core docs), in
        // place: the 672-byte measurement is never copied (each copy is ~540 instructions
        // on the target).
        let latency_s = self.navigation.time_s - tag;
        if let Ok(m) = &mut measurement {
            if let Err(error) = self.refer_to_now(m, aid, latency_s) {
                measurement = Err(error);
            }
        }
        let report = match &measurement {
            Ok(m) => self.update(m, aid),
            Err(error) => Err(*error),
        };
        self.conclude(aid, report)
    }

    /// Whether `due` is a GNSS fix farther than `gnss.max_jump_m` from the antenna position
    /// predicted at its time of validity (`snapshot`).
    fn is_gnss_jump(&self, due: &Due, snapshot: &Snapshot) -> bool {
        let Due::GnssPosition(tag, position) = due else {
            return false;
        };
        let lever_arm = ports::vector(&self.config.gnss.lever_arm_body_m);
        let predicted = snapshot.position_m + attitude::rotate(&snapshot.attitude, &lever_arm);
        let fix = ports::GnssFix {
            time_tag_s: *tag,
            position_ecef_m: array3(position),
            velocity_ecef_mps: None,
        };
        matches!(
            check_gnss(&fix, position, &predicted, self.config.gnss.max_jump_m),
            Err(GnssFault::Jump)
        )
    }

    /// The linearised measurement of `due` at its time of validity (`snapshot`).
    fn form_measurement(
        &self,
        due: &Due,
        snapshot: &Snapshot,
    ) -> Result<LinearMeasurement, NavError> {
        let lever_arm = ports::vector(&self.config.gnss.lever_arm_body_m);
        match due {
            Due::Star(_, measured) => star_sensor(
                &snapshot.attitude,
                &ports::quaternion(&self.config.star.mounting_wxyz),
                &self.installation_estimate(),
                measured,
                self.config.star.noise_rad,
            ),
            // nav-core refuses a non-finite fix (the jump check passes NaN through).
            Due::GnssPosition(_, position) => gnss_position(
                &snapshot.attitude,
                &snapshot.position_m,
                &lever_arm,
                position,
                self.config.gnss.noise_m,
            ),
            Due::GnssVelocity(_, velocity) => {
                // The lever-arm term's body rates: the mean of the last propagation interval.
                let rate = self.last_point.map_or(
                    BodyRate {
                        corrected_rad_s: Vector3::zeros(),
                        measured_rad_s: Vector3::zeros(),
                    },
                    |point| BodyRate {
                        corrected_rad_s: point.corrected_rate_rad_s,
                        measured_rad_s: point.measured_rate_rad_s,
                    },
                );
                gnss_velocity(
                    &snapshot.attitude,
                    &snapshot.velocity_mps,
                    &lever_arm,
                    &rate,
                    velocity,
                    self.config.gnss.velocity_noise_mps,
                )
            }
        }
    }

    /// Refers a measurement `latency_s` old to the current error state: `H (I − A Δ)` and,
    /// for a GNSS position, the correlated error's `h_ε = exp(Δ/τ)` (nav-core `gnss_error`).
    /// On an error the measurement is unchanged.
    fn refer_to_now(
        &self,
        measurement: &mut LinearMeasurement,
        aid: Aid,
        latency_s: f64,
    ) -> Result<(), NavError> {
        let Some(point) = self.last_point else {
            return Ok(());
        };
        if latency_s <= 1e-6 * self.config.imu.period_s {
            return Ok(());
        }
        match self.arithmetic {
            FilterArithmetic::Structured => {
                refer_to_later_time_in_place(measurement, &point, latency_s)?
            }
            FilterArithmetic::DenseReference => dense_referral(measurement, &point, latency_s)?,
        }
        if aid == Aid::GnssPosition {
            measurement.gnss_error_coefficient = self
                .config
                .filter
                .gnss_error
                .position_coefficient(latency_s);
        }
        Ok(())
    }

    /// The gated update of one aiding measurement (frozen blocks held).
    fn update(
        &mut self,
        measurement: &LinearMeasurement,
        aid: Aid,
    ) -> Result<nav_core::filter::InnovationReport, NavError> {
        let gate = match aid {
            Aid::Star => self.config.star.gate_nis,
            Aid::GnssPosition => self.config.gnss.gate_nis,
            Aid::GnssVelocity => self.config.gnss.velocity_gate_nis,
        };
        let frozen = self.manager.frozen_blocks();
        match self.arithmetic {
            FilterArithmetic::Structured => {
                self.filter.update_structured(measurement, gate, &frozen)
            }
            FilterArithmetic::DenseReference => {
                dense_update(&mut self.filter, measurement, gate, &frozen)
            }
        }
    }

    /// Gate statistics, counters, fault state and closed-loop feedback after an update.
    fn conclude(
        &mut self,
        aid: Aid,
        report: Result<nav_core::filter::InnovationReport, NavError>,
    ) -> FrameFusion {
        let report = match report {
            Err(_) => {
                count(&mut self.health.filter_errors);
                self.note_rejection(aid);
                return aid.fusion(false);
            }
            Ok(report) => report,
        };
        let statistics = match aid {
            Aid::Star => &mut self.star,
            Aid::GnssPosition => &mut self.gnss,
            Aid::GnssVelocity => &mut self.gnss_velocity,
        };
        statistics.last_nis = report.normalised_innovation_squared;
        if aid == Aid::GnssPosition {
            self.observe_whiteness(&report);
        }
        if report.accepted {
            self.fault_state(aid).consecutive_rejections = 0;
            if aid.is_star() {
                self.restart_second_order_attitude();
            }
            if self.filter.mode() == FilterMode::ClosedLoop {
                self.feed_back();
            }
        } else {
            let counter = match aid {
                Aid::Star => &mut self.health.star_gate_rejections,
                Aid::GnssPosition => &mut self.health.gnss_gate_rejections,
                Aid::GnssVelocity => &mut self.health.gnss_velocity_gate_rejections,
            };
            count(counter);
            self.note_rejection(aid);
        }
        aid.fusion(report.accepted)
    }

    /// Feeds a GNSS position innovation to the whiteness monitor (counted per episode).
    fn observe_whiteness(&mut self, report: &nav_core::filter::InnovationReport) {
        let (nu, s) = (&report.innovation, &report.covariance);
        let variances = [0, 1, 2].map(|i| s.get((i, i)).copied().unwrap_or(f64::NAN));
        let began = self.gnss_whiteness.observe(
            &[nu.x, nu.y, nu.z],
            &variances,
            self.config.gnss.whiteness_window_fixes,
            self.config.gnss.whiteness_threshold,
        );
        if began {
            count(&mut self.health.gnss_innovations_correlated);
        }
    }

    /// The fault state of the sensor behind `aid` (GNSS position and velocity share the
    /// receiver's).
    fn fault_state(&mut self, aid: Aid) -> &mut AidingSensor {
        if aid.is_star() {
            &mut self.star
        } else {
            &mut self.gnss
        }
    }

    fn note_rejection(&mut self, aid: Aid) {
        let limit = self.config.timing.rejections_to_declare_faulty;
        let (sensor, declarations) = if aid.is_star() {
            (&mut self.star, &mut self.health.star_declared_faulty)
        } else {
            (&mut self.gnss, &mut self.health.gnss_declared_faulty)
        };
        sensor.consecutive_rejections = sensor.consecutive_rejections.saturating_add(1);
        if !sensor.faulty && sensor.consecutive_rejections >= limit {
            sensor.faulty = true;
            count(declarations);
        }
    }

    /// Closed-loop feedback of the error state into the navigation solution, the history and
    /// the sensor corrections, then the filter reset (module docs).
    fn feed_back(&mut self) {
        // The correction is applied to copies of the (small) navigation solution and
        // calibration first; the filter (4.8 kB) is reset in place only once it succeeded.
        let error = *self.filter.state();
        let mut navigation = self.navigation;
        let mut calibration = self.calibration;
        let applied = apply_error_state(
            &error,
            &mut navigation.attitude,
            &mut navigation.position_m,
            &mut navigation.velocity_mps,
            &mut calibration,
        );
        if applied.is_err() {
            // A correction nav-core cannot apply (|ϑ| ≥ 1 or non-finite): keep everything
            // as it was and re-initialise the filter (documented recovery).
            self.recover_filter();
            return;
        }
        match self.arithmetic {
            FilterArithmetic::Structured => self.filter.reset(),
            FilterArithmetic::DenseReference => dense_reset(&mut self.filter),
        };
        let attitude_correction = attitude::from_vector_part(&block_of(&error, ATTITUDE));
        let position_correction = block_of(&error, POSITION);
        let velocity_correction = block_of(&error, VELOCITY);
        if let Ok(correction) = attitude_correction {
            // Snapshots are corrected when read ([`Self::corrected`]); a correction older
            // than every snapshot is no longer needed, so the ring never loses one that is.
            if self.corrections.is_full() {
                self.corrections.pop_front();
            }
            let _ = self.corrections.push_back(Correction {
                frame: self.frame,
                attitude: correction,
                position_m: position_correction,
                velocity_mps: velocity_correction,
            });
        }
        self.navigation = navigation;
        self.calibration = calibration;
    }

    /// Current estimate and variance of one calibration block in table units (the
    /// installation error as a rotation vector: twice the quaternion vector part, so four
    /// times its variance).
    fn block_estimate(
        block: StateBlock,
        estimate: &CalibrationEstimate,
        variances: &ErrorState,
    ) -> ([f64; 3], [f64; 3]) {
        let variance = block_of(variances, block);
        let c = estimate;
        match block {
            b if b == STAR_INSTALLATION => {
                let [w, x, y, z] = c.star_installation_wxyz;
                let vector = attitude::log_rotation_vector(&Quaternion::new(w, x, y, z));
                (array3(&vector), array3(&(variance * 4.0)))
            }
            b if b == GYRO_BIAS => (c.gyro_bias_rad_s, array3(&variance)),
            b if b == ACCEL_BIAS => (c.accel_bias_mps2, array3(&variance)),
            b if b == GYRO_SCALE_FACTOR => (c.gyro_scale_factor, array3(&variance)),
            _ => (c.accel_scale_factor, array3(&variance)),
        }
    }

    fn evaluate_calibration(&mut self) {
        let mut values = [[0.0; 3]; CALIBRATION_BLOCK_COUNT];
        let mut variances = [[0.0; 3]; CALIBRATION_BLOCK_COUNT];
        // Once per frame (not per block): the estimate and the variance of every state.
        let estimate = self.calibration_estimate();
        let state_variances = self.filter.covariance().diagonal();
        for ((value, variance), block) in values
            .iter_mut()
            .zip(variances.iter_mut())
            .zip(CALIBRATION_BLOCKS.iter())
        {
            (*value, *variance) = Self::block_estimate(*block, &estimate, &state_variances);
        }
        self.manager
            .evaluate(self.navigation.time_s, &values, &variances);
    }

    /// The sensor-error estimate: in closed loop the fed-back corrections; in open loop the
    /// filter's current error state applied to them.
    pub fn calibration_estimate(&self) -> CalibrationEstimate {
        let mut calibration = self.calibration;
        if self.filter.mode() == FilterMode::OpenLoop {
            let mut scratch = self.navigation;
            // Errors only for a non-finite or degenerate x; the fed-back value stands then.
            let _ = apply_error_state(
                self.filter.state(),
                &mut scratch.attitude,
                &mut scratch.position_m,
                &mut scratch.velocity_mps,
                &mut calibration,
            );
        }
        calibration
    }

    /// The best navigation solution (open loop: `x` applied on the way out).
    pub fn navigation(&self) -> NavigationState {
        let mut navigation = self.navigation;
        if self.filter.mode() == FilterMode::OpenLoop {
            let mut calibration = self.calibration;
            let mut corrected = navigation;
            if apply_error_state(
                self.filter.state(),
                &mut corrected.attitude,
                &mut corrected.position_m,
                &mut corrected.velocity_mps,
                &mut calibration,
            )
            .is_ok()
            {
                navigation = corrected;
            }
        }
        navigation
    }

    /// The filter (error state and covariance).
    pub fn filter(&self) -> &ErrorStateFilter {
        &self.filter
    }

    /// The calibration table.
    pub fn calibration_table(&self) -> &CalibrationTable {
        self.manager.table()
    }

    /// The blocks frozen now.
    pub fn frozen_blocks(&self) -> BlockMask {
        self.manager.frozen_blocks()
    }

    /// The health counters.
    pub fn health(&self) -> &HealthCounters {
        &self.health
    }

    /// Measurements received and waiting to be fused (star and GNSS queues; a GNSS fix whose
    /// velocity is fused and whose position waits counts once): with the fusions and the
    /// health counters, every measurement received is accounted for.
    pub fn queued_measurements(&self) -> usize {
        self.star_queue
            .len()
            .saturating_add(self.gnss_queue.len())
            .saturating_add(usize::from(self.pending_gnss_position.is_some()))
    }

    /// The launch-inertial frame in use.
    pub fn launch_frame(&self) -> &LaunchFrame {
        &self.launch_frame
    }

    /// The configuration in use.
    pub fn config(&self) -> &FswConfig {
        &self.config
    }

    fn telemetry(&self, fusion: FrameFusion) -> FrameTelemetry {
        let navigation = self.navigation();
        let q = navigation.attitude;
        FrameTelemetry {
            frame: self.frame,
            time_s: navigation.time_s,
            attitude_wxyz: [q.w, q.i, q.j, q.k],
            position_m: array3(&navigation.position_m),
            velocity_mps: array3(&navigation.velocity_mps),
            fusion,
            last_star_nis: self.star.last_nis,
            last_gnss_nis: self.gnss.last_nis,
            last_gnss_velocity_nis: self.gnss_velocity.last_nis,
            star_faulty: self.star.faulty,
            gnss_faulty: self.gnss.faulty,
            converged_blocks: self.manager.table().converged_count(),
            frozen_blocks: self.manager.frozen_blocks().bits(),
            health: self.health,
            last_frame_cost: self.cost.last,
            worst_frame_cost: self.cost.worst,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nav_core::frames::LaunchSite;

    fn computer() -> NavigationComputer {
        let site = LaunchSite {
            latitude_rad: 0.715,
            longitude_rad: 1.750,
            height_m: 1000.0,
            azimuth_rad: 3.316,
            epoch_s: 0.0,
        };
        let initial = NavigationState {
            attitude: Quaternion::new(1.0, 0.0, 0.0, 0.0),
            position_m: Vector3::new(1.0e5, 5.0e5, 2.0e5),
            velocity_mps: Vector3::new(7.5e3, 10.0, -20.0),
            time_s: 600.0,
        };
        NavigationComputer::new(FswConfig::paper_defaults(site), initial).unwrap()
    }

    /// A snapshot read back equals the eager correction of the history: every correction
    /// fed back in its frame or later, in feedback order (rotations that do not commute),
    /// none from before it, across the frame counter's wrap.
    #[test]
    fn a_snapshot_takes_the_corrections_since_its_frame_in_order() {
        let mut computer = computer();
        let recorded = u32::MAX - 1;
        let snapshot = Snapshot {
            frame: recorded,
            time_s: 1.0,
            attitude: attitude::exp_rotation_vector(&Vector3::new(0.0, 0.0, 0.3)),
            position_m: Vector3::new(10.0, 20.0, 30.0),
            velocity_mps: Vector3::new(1.0, 2.0, 3.0),
        };
        let rotation = |x: f64, y: f64| attitude::exp_rotation_vector(&Vector3::new(x, y, 0.0));
        let corrections = [
            // (frame, attitude, position): before the snapshot, in its frame, after the wrap.
            (
                recorded.wrapping_sub(1),
                rotation(0.5, 0.0),
                Vector3::new(100.0, 0.0, 0.0),
            ),
            (recorded, rotation(0.1, 0.0), Vector3::new(1.0, 0.0, 0.0)),
            (
                recorded.wrapping_add(3),
                rotation(0.0, 0.2),
                Vector3::new(0.0, 2.0, 0.0),
            ),
        ];
        for (frame, attitude, position_m) in corrections {
            computer
                .corrections
                .push_back(Correction {
                    frame,
                    attitude,
                    velocity_mps: position_m * 0.5,
                    position_m,
                })
                .unwrap();
        }
        computer.frame = recorded.wrapping_add(4);
        let corrected = computer.corrected(&snapshot);
        let mut eager = snapshot;
        for (_, attitude, position_m) in &corrections[1..] {
            eager.attitude = attitude::product(&eager.attitude, attitude);
            eager.position_m += position_m;
            eager.velocity_mps += position_m * 0.5;
        }
        assert_eq!(
            corrected.attitude.coords.map(f64::to_bits),
            eager.attitude.coords.map(f64::to_bits)
        );
        assert_eq!(
            corrected.position_m.map(f64::to_bits),
            eager.position_m.map(f64::to_bits)
        );
        // The order matters: the opposite order gives a different attitude.
        let reversed = attitude::product(
            &attitude::product(&snapshot.attitude, &corrections[2].1),
            &corrections[1].1,
        );
        assert!((reversed.coords - corrected.attitude.coords).norm() > 1e-3);
    }

    /// The documented recovery: a covariance nav-core refuses to propagate (its products
    /// overflow) re-initialises the filter from the configured 1σ, once, counted; the
    /// navigation solution is kept.
    #[test]
    fn a_filter_that_cannot_be_propagated_is_reinitialised_once() {
        use crate::replay::FramePorts;
        let mut computer = computer();
        let fresh = *computer.filter.covariance();
        let huge = nav_core::discretise::CovarianceMatrix::from_element(f64::MAX);
        computer.filter.set_covariance(&huge).unwrap();
        let before = computer.navigation();
        let mut ports = FramePorts::default();
        ports.imu.0 = Some(crate::ports::ImuSample {
            sequence: 1,
            time_s: 600.002,
            delta_angle_rad: [0.0; 3],
            delta_velocity_mps: [0.0; 3],
        });
        ports.run(&mut computer);
        assert_eq!(computer.health().filter_resets, 1);
        assert_eq!(
            computer.filter.covariance().map(f64::to_bits),
            fresh.map(f64::to_bits)
        );
        assert!((computer.navigation().position_m - before.position_m).norm() < 100.0);
    }

    fn one_frame(computer: &mut NavigationComputer, sequence: u32) {
        let mut ports = crate::replay::FramePorts::default();
        ports.imu.0 = Some(crate::ports::ImuSample {
            sequence,
            time_s: 600.0 + 0.002 * f64::from(sequence),
            delta_angle_rad: [0.0; 3],
            delta_velocity_mps: [0.0; 3],
        });
        ports.run(computer);
    }

    /// A strapdown step nav-core refuses (the solution at the Earth's centre, where gravity
    /// is not finite) is counted and leaves the solution as it was, except that navigation
    /// time still advances by one frame.
    #[test]
    fn a_refused_strapdown_step_still_advances_time_by_one_frame() {
        let mut computer = computer();
        computer.navigation.position_m = *computer.launch_frame.earth_centre_launch_m();
        computer.navigation.velocity_mps = Vector3::zeros();
        let before = computer.navigation;
        one_frame(&mut computer, 1);
        assert_eq!(computer.health().strapdown_failures, 1);
        let period = computer.config.imu.period_s;
        assert_eq!(
            computer.navigation.time_s.to_bits(),
            (before.time_s + period).to_bits()
        );
        assert_eq!(
            computer.navigation.position_m.map(f64::to_bits),
            before.position_m.map(f64::to_bits)
        );
    }

    /// Under the paper's schedule, a coast freezes every calibration block but the biases,
    /// and the computer reports exactly the set its telemetry carries.
    #[test]
    fn the_frozen_set_is_the_policy_s_for_the_phase() {
        use crate::calibration_manager::{EstimationPolicy, ManoeuvrePhase};
        use nav_core::state::{ACCEL_BIAS, GYRO_BIAS, GYRO_SCALE_FACTOR, STAR_INSTALLATION};
        let mut config = computer().config;
        config.calibration.policy = EstimationPolicy::PaperSchedule;
        let initial = computer().navigation;
        let mut computer = NavigationComputer::new(config, initial).unwrap();
        computer
            .command(Command::SetPhase(ManoeuvrePhase::Coast))
            .unwrap();
        one_frame(&mut computer, 1);
        let frozen = computer.frozen_blocks();
        assert!(!frozen.contains(GYRO_BIAS) && !frozen.contains(ACCEL_BIAS));
        assert!(frozen.contains(GYRO_SCALE_FACTOR) && frozen.contains(STAR_INSTALLATION));
        assert_eq!(
            frozen.bits(),
            computer.telemetry(FrameFusion::None).frozen_blocks
        );
    }
}
