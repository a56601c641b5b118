//! A scenario flown through the flight software exactly as it would fly: the simulated
//! sensor events of each 2 ms frame are handed to nav-fsw's [`NavigationComputer`] through
//! its ports, the manoeuvre phase is commanded from the schedule, and the estimates, their
//! 1σ and the truth are recorded for the reports.

use nalgebra::{Quaternion, SMatrix, SVector, Vector3};
use nav_core::attitude;
use nav_core::filter::CalibrationEstimate;
use nav_core::imu_error::ImuErrorEstimate;
use nav_core::state::StateBlock;
use nav_fsw::calibration_manager::{CalibrationTable, ManoeuvrePhase, CALIBRATION_BLOCK_COUNT};
use nav_fsw::calibration_record::CALIBRATION_RECORD_BYTES;
use nav_fsw::config::FswConfig;
use nav_fsw::health::HealthCounters;
use nav_fsw::ports::{CalibrationStoreFault, CalibrationStorePort};
use nav_fsw::replay::FramePorts;
use nav_fsw::scheduler::{Command, NavigationComputer};
use nav_fsw::telemetry::FrameFusion;

use crate::harness::filter_gauge::in_filter_gauge;
use crate::harness::optional_blocks::{
    gnss_error_outcome, imu_error_outcome, GnssErrorOutcome, ImuErrorOutcome,
};
use crate::logs::sensor_log;
use crate::logs::star_heads::FlightStarHeads;
use crate::output::report::{BlockSample, Parameter, TimeHistorySample};
use crate::scenario::commands::Scheduled;
use crate::scenario::{self, Scenario};
use crate::setup::fsw::{configuration_error, fsw_config, replay_setup_for};
use crate::setup::launch::Launch;
use crate::setup::SetupError;
use crate::world::sensors::SensorErrorTruth;
use crate::world::simulation::{Simulation, SimulationError};
use crate::world::truth::TruthFrame;

/// Number of calibration states (biases, installation error, scale factors).
pub const CALIBRATION_STATE_COUNT: usize = 3 * CALIBRATION_BLOCK_COUNT;

/// Why a flight could not run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FlightError {
    /// The simulation failed.
    #[error(transparent)]
    Simulation(#[from] SimulationError),
    /// The run could not be set up from its scenario (launch site, configuration).
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The truth's IMU errors could not be mapped into the filter's gauge, or the flight
    /// software's systematic estimate is not finite.
    #[error("the systematic IMU errors in the filter's gauge: {0}")]
    Gauge(nav_core::NavError),
    /// The receiver's correlated error could not be turned into launch-inertial axes (a
    /// non-finite value or time).
    #[error("the receiver's correlated error in launch-inertial axes: {0}")]
    GnssErrorTruth(nav_core::NavError),
}

/// Values of the five calibration blocks, per axis, in [`StateBlock::CALIBRATION`] order (gyro
/// bias rad/s, accelerometer bias m/s², installation rotation vector rad, gyro and
/// accelerometer scale factors).
pub type CalibrationValues = [[f64; 3]; CALIBRATION_BLOCK_COUNT];

/// One recorded instant of a flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlightSample {
    /// Navigation time (s).
    pub time_s: f64,
    /// Calibration estimates.
    pub estimate: CalibrationValues,
    /// Filter 1σ.
    pub sigma: CalibrationValues,
    /// Truth.
    pub truth: CalibrationValues,
    /// Position error, estimate − truth, launch-inertial (m).
    pub position_error_m: [f64; 3],
    /// Velocity error, estimate − truth (m/s).
    pub velocity_error_mps: [f64; 3],
    /// Attitude error, rotation vector of `q_true* ⊗ q̂`, body axes (rad).
    pub attitude_error_rad: [f64; 3],
    /// Position 1σ (m).
    pub position_sigma_m: [f64; 3],
    /// Velocity 1σ (m/s).
    pub velocity_sigma_mps: [f64; 3],
    /// Attitude 1σ as an angle (rad).
    pub attitude_sigma_rad: [f64; 3],
    /// NEES of the 15 calibration states with the filter's full covariance at this instant
    /// ([`calibration_nees`]; `None` if the covariance is not positive definite).
    pub calibration_nees: Option<f64>,
    /// NIS of the star-sensor measurements the gate tested since the previous sample.
    pub star_nis: NisSum,
    /// NIS of the GNSS fixes the gate tested since the previous sample.
    pub gnss_nis: NisSum,
}

/// What a flight produced.
#[derive(Debug, Clone)]
pub struct FlightResult {
    /// Recorded samples (every `record_interval_s`, and the last frame).
    pub samples: Vec<FlightSample>,
    /// The flight software's calibration table at the end.
    pub table: CalibrationTable,
    /// Health counters at the end.
    pub health: HealthCounters,
    /// Final error of the 15 calibration states in the filter's state coordinates
    /// (truth − estimate; installation as the quaternion vector part).
    pub calibration_error: SVector<f64, CALIBRATION_STATE_COUNT>,
    /// Final filter covariance of the 15 calibration states.
    pub calibration_covariance: SMatrix<f64, CALIBRATION_STATE_COUNT, CALIBRATION_STATE_COUNT>,
    /// Frames flown.
    pub frames: u64,
    /// Measurements lost because a frame's port capacity was exceeded.
    pub dropped_measurements: u32,
    /// Star measurements of the additional star-tracker heads not handed to the flight
    /// software, which takes head 0, and head 1 when configured with it ([`FlightStarHeads`]).
    pub withheld_star_measurements: u64,
    /// NIS of every star-sensor measurement the gate tested (accepted or rejected).
    pub star_nis: NisSum,
    /// NIS of every GNSS fix the gate tested.
    pub gnss_nis: NisSum,
    /// The systematic IMU error states' final error and covariance (`[filter.imu_errors]`
    /// on; the calibration error is then in the filter's gauge too, [`crate::harness::filter_gauge`]).
    pub imu_error: Option<ImuErrorOutcome>,
    /// The correlated GNSS error states' final error and covariance (`[filter]`
    /// `gnss_correlated_sigma_m` above zero; [`crate::harness::optional_blocks`]).
    pub gnss_error: Option<GnssErrorOutcome>,
}

/// The sensor errors as the filter sees them: in its gauge when it estimates the systematic
/// IMU errors ([`crate::harness::filter_gauge`]), as they are otherwise.
fn filter_view(
    computer: &NavigationComputer,
    errors: &SensorErrorTruth,
) -> Result<(SensorErrorTruth, Option<ImuErrorEstimate>), FlightError> {
    if computer.filter().imu_error().is_enabled() {
        let (mapped, imu) = in_filter_gauge(errors).map_err(FlightError::Gauge)?;
        Ok((mapped, Some(imu)))
    } else {
        Ok((*errors, None))
    }
}

/// Sum of the normalised innovation squared over the updates of one sensor (the gate's
/// statistic, recorded for accepted and gate-rejected measurements alike, so the average is
/// not truncated by the gate).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NisSum {
    /// Σ NIS.
    pub sum: f64,
    /// Number of updates tested.
    pub updates: u64,
}

impl NisSum {
    fn add(&mut self, nis: f64) {
        self.sum += nis;
        self.updates += 1;
    }

    /// Average NIS (NaN without updates).
    pub fn average(&self) -> f64 {
        self.sum / self.updates as f64
    }
}

impl FlightSample {
    /// The sample in the report's form: calibration blocks with estimate, 1σ and truth;
    /// navigation blocks as errors (estimate − truth, truth 0) with their 1σ.
    pub fn time_history(&self) -> TimeHistorySample {
        let mut sample = TimeHistorySample {
            time_s: self.time_s,
            ..TimeHistorySample::default()
        };
        let navigation = [
            (
                Parameter::Attitude,
                self.attitude_error_rad,
                self.attitude_sigma_rad,
            ),
            (
                Parameter::Position,
                self.position_error_m,
                self.position_sigma_m,
            ),
            (
                Parameter::Velocity,
                self.velocity_error_mps,
                self.velocity_sigma_mps,
            ),
        ];
        for (parameter, error, sigma) in navigation {
            sample.blocks[parameter.index()] = BlockSample {
                estimate: error,
                sigma,
                truth: [0.0; 3],
            };
        }
        for (index, parameter) in Parameter::CALIBRATION.iter().enumerate() {
            sample.blocks[parameter.index()] = BlockSample {
                estimate: self.estimate[index],
                sigma: self.sigma[index],
                truth: self.truth[index],
            };
        }
        sample
    }
}

impl FlightResult {
    /// The last sample.
    pub fn last(&self) -> Option<&FlightSample> {
        self.samples.last()
    }

    /// Normalised estimation error squared of the calibration states, `eᵀ P⁻¹ e`
    /// (`None` if `P` is not positive definite).
    pub fn calibration_nees(&self) -> Option<f64> {
        calibration_nees(&self.calibration_error, &self.calibration_covariance)
    }
}

/// Normalised estimation error squared `eᵀ P⁻¹ e` of calibration error `error` with
/// covariance `covariance` (`None` if `P` is not positive definite).
pub fn calibration_nees(
    error: &SVector<f64, CALIBRATION_STATE_COUNT>,
    covariance: &SMatrix<f64, CALIBRATION_STATE_COUNT, CALIBRATION_STATE_COUNT>,
) -> Option<f64> {
    let cholesky = covariance.cholesky()?;
    Some(error.dot(&cholesky.solve(error)))
}

/// The filter's covariance of the 15 calibration states.
fn calibration_covariance(
    computer: &NavigationComputer,
) -> SMatrix<f64, CALIBRATION_STATE_COUNT, CALIBRATION_STATE_COUNT> {
    let first = StateBlock::CALIBRATION.first().map_or(9, |b| b.index());
    computer
        .filter()
        .covariance()
        .fixed_view::<CALIBRATION_STATE_COUNT, CALIBRATION_STATE_COUNT>(first, first)
        .into_owned()
}

/// How to record a flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlightOptions {
    /// Interval between recorded samples (s).
    pub record_interval_s: f64,
}

impl Default for FlightOptions {
    fn default() -> Self {
        Self {
            record_interval_s: 0.25,
        }
    }
}

/// The phase the flight plan commands during a manoeuvre segment.
pub fn phase_of(segment: &scenario::ManoeuvreSegment) -> ManoeuvrePhase {
    let rate_deg_s = Vector3::from(segment.body_rate_deg_per_s).norm();
    let force_mps2 = Vector3::from(segment.specific_force_mps2).norm();
    if force_mps2 > 1.0 {
        ManoeuvrePhase::Acceleration
    } else if rate_deg_s > 1.0 {
        ManoeuvrePhase::Rotation
    } else {
        ManoeuvrePhase::Coast
    }
}

fn array3(vector: &Vector3<f64>) -> [f64; 3] {
    [vector.x, vector.y, vector.z]
}

/// Truth values in table units.
pub fn calibration_truth(errors: &SensorErrorTruth) -> CalibrationValues {
    [
        array3(&errors.gyro_bias_rad_per_s),
        array3(&errors.accel_bias_mps2),
        array3(&attitude::log_rotation_vector(
            &errors.star_installation_q_psi,
        )),
        array3(&errors.gyro_scale_factor),
        array3(&errors.accel_scale_factor),
    ]
}

fn table_values(table: &CalibrationTable) -> (CalibrationValues, CalibrationValues) {
    let mut values = [[0.0; 3]; CALIBRATION_BLOCK_COUNT];
    let mut sigmas = [[0.0; 3]; CALIBRATION_BLOCK_COUNT];
    for ((value, sigma), (_, entry)) in values
        .iter_mut()
        .zip(sigmas.iter_mut())
        .zip(table.entries())
    {
        *value = entry.value;
        *sigma = entry.sigma();
    }
    (values, sigmas)
}

/// Truth − estimate of the calibration states in the filter's coordinates.
fn calibration_state_error(
    estimate: &CalibrationEstimate,
    errors: &SensorErrorTruth,
) -> SVector<f64, CALIBRATION_STATE_COUNT> {
    let [w, x, y, z] = estimate.star_installation_wxyz;
    let installation_error = attitude::canonical(&attitude::product(
        &attitude::conjugate(&Quaternion::new(w, x, y, z)),
        &errors.star_installation_q_psi,
    ))
    .imag();
    let blocks = [
        errors.gyro_bias_rad_per_s - Vector3::from(estimate.gyro_bias_rad_s),
        errors.accel_bias_mps2 - Vector3::from(estimate.accel_bias_mps2),
        installation_error,
        errors.gyro_scale_factor - Vector3::from(estimate.gyro_scale_factor),
        errors.accel_scale_factor - Vector3::from(estimate.accel_scale_factor),
    ];
    SVector::from_iterator(blocks.iter().flat_map(|b| b.iter().copied()))
}

/// The sample of `frame`; `star_nis` and `gnss_nis` are the NIS sums since the previous one.
fn record(
    computer: &NavigationComputer,
    frame: &TruthFrame,
    errors: &SensorErrorTruth,
    (star_nis, gnss_nis): (NisSum, NisSum),
) -> FlightSample {
    let (estimate, sigma) = table_values(computer.calibration_table());
    let navigation = computer.navigation();
    let attitude_error = attitude::log_rotation_vector(&attitude::product(
        &attitude::conjugate(&frame.attitude_q_ib),
        &navigation.attitude,
    ));
    let sigmas = computer.filter().standard_deviations();
    let position_sigma: Vector3<f64> = sigmas.fixed_rows::<3>(3).into_owned();
    let velocity_sigma: Vector3<f64> = sigmas.fixed_rows::<3>(6).into_owned();
    let attitude_sigma: Vector3<f64> = sigmas.fixed_rows::<3>(0).into_owned() * 2.0;
    FlightSample {
        time_s: frame.time_s,
        estimate,
        sigma,
        truth: calibration_truth(errors),
        position_error_m: array3(&(navigation.position_m - frame.position_m)),
        velocity_error_mps: array3(&(navigation.velocity_mps - frame.velocity_mps)),
        attitude_error_rad: array3(&attitude_error),
        position_sigma_m: array3(&position_sigma),
        velocity_sigma_mps: array3(&velocity_sigma),
        attitude_sigma_rad: array3(&attitude_sigma),
        calibration_nees: calibration_nees(
            &calibration_state_error(&computer.calibration_estimate(), errors),
            &calibration_covariance(computer),
        ),
        star_nis,
        gnss_nis,
    }
}

/// Flies `scenario` through nav-fsw; `progress(frames_done, frames_total)` is called every
/// 500 frames.
///
/// # Errors
/// [`FlightError`] if the simulation or the flight software cannot be set up.
pub fn fly(
    scenario: &Scenario,
    options: FlightOptions,
    progress: impl FnMut(u64, u64),
) -> Result<FlightResult, FlightError> {
    fly_with(
        scenario,
        fsw_config(scenario)?,
        options,
        progress,
        |_, _| {},
    )
}

/// [`fly`] with an explicit flight-software configuration and a fault injector
/// `inject(frame_index, ports)` called on every frame's port contents before the flight
/// software reads them.
///
/// # Errors
/// As [`fly`].
pub fn fly_with(
    scenario: &Scenario,
    config: FswConfig,
    options: FlightOptions,
    progress: impl FnMut(u64, u64),
    inject: impl FnMut(u64, &mut FramePorts),
) -> Result<FlightResult, FlightError> {
    fly_observed(scenario, config, options, progress, inject, |_, _| {})
}

/// The scenario's `[[command]]` schedule as (frame, what, index in the schedule).
fn scheduled_commands(scenario: &Scenario) -> Result<Vec<(u64, Scheduled, usize)>, SetupError> {
    let period_s = scenario.imu.frame_period_s();
    scenario
        .commands
        .iter()
        .enumerate()
        .map(|(index, scheduled)| {
            let what = scheduled.to_command().map_err(|(key, requirement)| {
                SetupError::Setting(format!("command[{index}].{key} {requirement}"))
            })?;
            Ok((scenario::frames_in(scheduled.at_s, period_s), what, index))
        })
        .collect()
}

/// The vehicle's non-volatile memory: the one calibration record a flight keeps.
#[derive(Default)]
struct VehicleMemory(Option<[u8; CALIBRATION_RECORD_BYTES]>);

impl CalibrationStorePort for VehicleMemory {
    fn read_record(
        &mut self,
        record: &mut [u8; CALIBRATION_RECORD_BYTES],
    ) -> Result<(), CalibrationStoreFault> {
        *record = self.0.ok_or(CalibrationStoreFault::Empty)?;
        Ok(())
    }

    fn write_record(
        &mut self,
        record: &[u8; CALIBRATION_RECORD_BYTES],
    ) -> Result<(), CalibrationStoreFault> {
        self.0 = Some(*record);
        Ok(())
    }
}

/// Gives the flight software the commands due before frame `frame_index`, in schedule
/// order (a reboot: [`reboot_keeping_calibration`]); a refused one ends the flight with its
/// reason.
fn give_due_commands(
    commands: &[(u64, Scheduled, usize)],
    frame_index: u64,
    computer: &mut NavigationComputer,
    memory: &mut VehicleMemory,
) -> Result<(), SetupError> {
    for (_, what, index) in commands.iter().filter(|(f, ..)| *f == frame_index) {
        let refused = |reason: String| {
            SetupError::Setting(format!("command[{index}] at frame {frame_index}: {reason}"))
        };
        match what {
            Scheduled::Command(command) => computer
                .command_with_store(*command, memory)
                .map_err(|e| refused(e.to_string()))?,
            Scheduled::RebootKeepingCalibration => {
                *computer = reboot_keeping_calibration(computer, memory).map_err(refused)?
            }
        }
    }
    Ok(())
}

/// A new computer with `computer`'s configuration, started from its navigation solution at
/// the configured prior, with its calibration carried over through the vehicle's memory
/// (`SaveCalibration` before, `LoadCalibration` after).
fn reboot_keeping_calibration(
    computer: &mut NavigationComputer,
    memory: &mut VehicleMemory,
) -> Result<NavigationComputer, String> {
    computer
        .command_with_store(Command::SaveCalibration, memory)
        .map_err(|error| error.to_string())?;
    let mut rebooted = NavigationComputer::new(*computer.config(), computer.navigation())
        .map_err(|error| error.to_string())?;
    rebooted
        .command_with_store(Command::LoadCalibration, memory)
        .map_err(|error| error.to_string())?;
    Ok(rebooted)
}

/// [`fly_with`] with an observer `observe(frame_index, computer)` called after every frame,
/// for tests that look inside the flight software (covariance conditioning, frozen blocks).
///
/// # Errors
/// As [`fly`].
pub fn fly_observed(
    scenario: &Scenario,
    config: FswConfig,
    options: FlightOptions,
    mut progress: impl FnMut(u64, u64),
    mut inject: impl FnMut(u64, &mut FramePorts),
    mut observe: impl FnMut(u64, &NavigationComputer),
) -> Result<FlightResult, FlightError> {
    // The truth, the sensors and the flight software's initial solution share one launch.
    let launch = Launch::new(scenario)?;
    let mut simulation = Simulation::with_launch(scenario, &launch)?;
    let start = *simulation.truth().state();
    let initial = replay_setup_for(scenario, &launch)?.initial;
    let mut computer = NavigationComputer::new(config, initial)
        .map_err(|error| configuration_error(scenario, error))?;
    let total_frames = scenario.frame_count();
    let segment_frames: Vec<(u64, ManoeuvrePhase)> = {
        let period_s = scenario.imu.frame_period_s();
        let mut first_frame = 0;
        scenario
            .manoeuvres
            .iter()
            .map(|segment| {
                let entry = (first_frame, phase_of(segment));
                first_frame += scenario::frames_in(segment.duration_s, period_s);
                entry
            })
            .collect()
    };
    let mut dropped = 0u32;
    // The tracker's port carries its first two heads, whether or not the flight software
    // is configured with the second.
    let mut star_heads = FlightStarHeads::for_scenario(scenario);
    let mut events = Vec::new();
    let mut samples = Vec::new();
    let mut next_record_s = start.time_s;
    let mut frames = 0u64;
    let mut last = None;
    let mut star_nis = NisSum::default();
    let mut gnss_nis = NisSum::default();
    // NIS since the previous sample, for the consistency over time.
    let mut interval_nis = (NisSum::default(), NisSum::default());
    // The flight plan tells the phase only to a policy that reads it.
    let uses_phase = computer.config().calibration.policy.uses_phase();
    let commands = scheduled_commands(scenario)?;
    let mut memory = VehicleMemory::default();
    while let Some(frame) = simulation.step(&mut events)? {
        give_due_commands(&commands, frame.frame_index, &mut computer, &mut memory)?;
        let phase_due = segment_frames.iter().find(|(f, _)| *f == frame.frame_index);
        if let (Some((_, phase)), true) = (phase_due, uses_phase) {
            computer
                .command(Command::SetPhase(*phase))
                .map_err(|error| SetupError::Setting(error.to_string()))?;
        }
        let mut ports = FramePorts::default();
        for event in events
            .drain(..)
            .filter(|event| star_heads.hands_over(event))
        {
            ports.add(&sensor_log::record_of(&event));
        }
        inject(frame.frame_index, &mut ports);
        dropped = dropped.saturating_add(ports.dropped);
        let gate_rejections_before = (
            computer.health().star_gate_rejections,
            computer.health().gnss_gate_rejections,
        );
        let telemetry = ports.run(&mut computer);
        let health = computer.health();
        let tested = match telemetry.fusion {
            FrameFusion::StarAccepted => Some((true, telemetry.last_star_nis)),
            FrameFusion::GnssAccepted => Some((false, telemetry.last_gnss_nis)),
            FrameFusion::StarRejected if health.star_gate_rejections > gate_rejections_before.0 => {
                Some((true, telemetry.last_star_nis))
            }
            FrameFusion::GnssRejected if health.gnss_gate_rejections > gate_rejections_before.1 => {
                Some((false, telemetry.last_gnss_nis))
            }
            _ => None,
        };
        match tested {
            Some((true, nis)) => {
                star_nis.add(nis);
                interval_nis.0.add(nis);
            }
            Some((false, nis)) => {
                gnss_nis.add(nis);
                interval_nis.1.add(nis);
            }
            None => {}
        }
        observe(frame.frame_index, &computer);
        frames += 1;
        let errors = simulation.error_truth();
        if frame.time_s >= next_record_s - 1e-9 {
            let (seen, _) = filter_view(&computer, &errors)?;
            samples.push(record(
                &computer,
                &frame,
                &seen,
                std::mem::take(&mut interval_nis),
            ));
            next_record_s += options.record_interval_s;
        }
        if frames % 500 == 0 {
            progress(frames, total_frames);
        }
        last = Some((frame, errors));
    }
    if let Some((frame, errors)) = last {
        let (seen, _) = filter_view(&computer, &errors)?;
        let final_sample = record(&computer, &frame, &seen, interval_nis);
        if samples.last().map(|s| s.time_s) != Some(final_sample.time_s) {
            samples.push(final_sample);
        }
    }
    progress(frames, total_frames);
    let (errors, imu_truth) = filter_view(&computer, &simulation.error_truth())?;
    let imu_error = imu_error_outcome(&computer, imu_truth.as_ref()).map_err(FlightError::Gauge)?;
    let gnss_error =
        gnss_error_outcome(&computer, &simulation).map_err(FlightError::GnssErrorTruth)?;
    Ok(FlightResult {
        samples,
        table: *computer.calibration_table(),
        health: *computer.health(),
        calibration_error: calibration_state_error(&computer.calibration_estimate(), &errors),
        calibration_covariance: calibration_covariance(&computer),
        frames,
        dropped_measurements: dropped,
        withheld_star_measurements: star_heads.withheld(),
        star_nis,
        gnss_nis,
        imu_error,
        gnss_error,
    })
}
