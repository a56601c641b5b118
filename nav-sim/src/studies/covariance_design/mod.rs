//! Linear covariance analysis of a scenario's calibration: how well *can* the 24-state filter
//! estimate the sensor errors on this manoeuvre schedule with these sensors?
//!
//! The analysis flies the scenario's truth trajectory ([`crate::world::truth`]) and runs only the
//! covariance half of nav-core's filter along it, with the flight filter's own pieces:
//! the error model [`system_matrix`] / [`noise_input_matrix`] linearised at the truth, nav-core's
//! [`discretise`] at the scenario's order (paper: 3), [`ErrorStateFilter::predict`] and the
//! Joseph-form [`ErrorStateFilter::update`] with the Jacobians of nav-core's
//! [`measurement::star_sensor`], [`measurement::gnss_velocity`] and
//! [`measurement::gnss_position`] evaluated at the truth, at the scenario's measurement epochs.
//! For a linear(ised) system the Kalman covariance does not depend on the measured values, so
//! the result is the 1σ the filter reports after the flight, and, when the filter's model
//! matches the truth, the 1σ of its actual estimation error.
//!
//! What the flight filter models, the analysis models when the scenario asks for it:
//! * the receiver's velocity (`gnss.velocity_noise_mps > 0`), fused before the position of the
//!   same fix, as nav-fsw's scheduler orders them (star sample first when both are due);
//! * the correlated GNSS error states (`filter.gnss_correlated_sigma_m > 0`): the filter built
//!   by [`filter_config`] carries them, nav-core's `predict` propagates them and the position
//!   Jacobian's `h_ε = 1` includes them in the update;
//! * the white position noise the filter is told (`filter.gnss_noise_m`, default
//!   `gnss.noise_m`);
//! * a blind star tracker: no star sample while the frame's mean body rate exceeds
//!   `star_sensor.max_rate_deg_per_s`, nor for `reacquisition_s` after (the sensor model's
//!   rule), and no sample of either sensor inside its `outages`;
//! * the flight software's second-order attitude growth while the star sensor is unheard
//!   (`covariance.second_order_attitude`, nav-core `unmodelled`), with the scheduler's rule:
//!   grown after each propagation that no star update follows, restarted by a star update;
//!   while the sensor is unheard the covariance steps are single frames, as in flight;
//! * the flight software's allowance for the gravity field its model omits
//!   (`[filter.gravity]`), scaled with the omitted field's power at the truth's radius
//!   (`allowance.rs`).
//!
//! Simplifications (stated in `docs/guide/scenario-design.md`):
//! * the covariance is propagated over steps of [`DesignOptions::step_frames`] IMU frames
//!   (default 5 = 10 ms at 500 Hz) instead of every 2 ms frame; a step also ends at every
//!   measurement epoch and segment boundary, so no update is moved in time. The step's
//!   linearisation point is the mean body rate and specific force over the step (from the exact
//!   IMU increments) and the truth attitude and position at the step's middle frame;
//! * the error model is linearised along the truth trajectory with the noise-free sensor
//!   outputs `ω_m = (ω + b_g) ./ (1 − λ_g)`, `f_m = (f + b_a) ./ (1 − λ_a)` of the scenario's
//!   true sensor errors (open loop: `ω̂ = ω_m`; closed loop: `ω̂ = ω`); the sensor errors
//!   change the Jacobians only at relative order 1e-4, so the result barely depends on them;
//! * the updates of one epoch are fused at the epoch; the flight software fuses one
//!   measurement per 2 ms frame, so its velocity and position updates come one and two frames
//!   later, referred back by `H (I − A Δ)` (a change of order `|A| Δ` ≈ 1e-5);
//! * GNSS fixes are used at their time of validity (latency ignored), no lever arm; no gate
//!   rejections, no held IMU samples, no covariance floors (none binds on a nominal flight);
//! * [`DesignOptions::measurement_stride`] > 1 (a coarse search) fuses every n-th epoch with
//!   1/n of the noise variance (the mean of n epochs): the same information, fused less often.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
use nav_core::attitude::{exp_rotation_vector, rotation_matrix};
use nav_core::discretise::discretise;
use nav_core::error_model::{noise_input_matrix, system_matrix, LinearisationPoint, ProcessNoise};
use nav_core::filter::{ErrorState, ErrorStateFilter, FilterMode};
use nav_core::frames::{EarthRotation, LaunchFrame};
use nav_core::gravity::GravityModel;
use nav_core::imu_error::IMU_ERROR_DIMENSION;
use nav_core::measurement;
use nav_core::state::StateBlock;
use nav_core::unmodelled::{
    bilinear_attitude_rate_covariance, rate_error_correlation, CoherentGrowth,
};
use nav_core::NavError;
use nav_fsw::calibration_manager::CalibrationThresholds;

use crate::scenario::{frames_in, in_outage, Scenario};
use crate::setup::fsw::{filter_config, scenario_process_noise};
use crate::setup::launch::Launch;
use crate::setup::SetupError;
use crate::world::sensors::{star_tracker_tracks, SensorErrorTruth, SensorSimulator};
use crate::world::truth::{TruthError, TruthFrame, TruthSimulator};

mod allowance;
mod augmented;
mod imu_errors;
mod orbit;

use allowance::GravityAllowance;
use augmented::AnalysedFilter;
use imu_errors::MultiplierTracker;
pub use imu_errors::{ImuErrorReport, ImuErrorRow};
use orbit::OrbitTracker;
pub use orbit::{initial_orbital_axes, perigee_apogee_radii_m};

/// Why the analysis could not run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// The truth trajectory could not be flown.
    #[error(transparent)]
    Truth(#[from] TruthError),
    /// A nav-core call refused its input.
    #[error("nav-core {operation} failed at t = {time_s} s: {error}")]
    Filter {
        /// What was being done (e.g. "discretise", "star update").
        operation: &'static str,
        /// Navigation time (s).
        time_s: f64,
        /// nav-core's reason.
        error: NavError,
    },
    /// The sensor models could not be built.
    #[error("sensor models: {0}")]
    Sensor(String),
    /// The run could not be set up from its scenario.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// A setting is unusable.
    #[error("covariance design setting {key} {requirement}")]
    Setting {
        /// The offending setting.
        key: &'static str,
        /// What it must satisfy.
        requirement: &'static str,
    },
}

/// How the analysis is run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DesignOptions {
    /// IMU frames per covariance step (≥ 1); a step also ends at measurement epochs and
    /// segment boundaries. 5 = 10 ms at 500 Hz.
    pub step_frames: u32,
    /// Truth RK4 substeps per IMU frame; `None` = the scenario's value. The linearisation point
    /// needs far less accuracy than the sensor simulation, so 1-2 is enough here.
    pub truth_substeps_per_frame: Option<u32>,
    /// Include the gravity gradient `∂g/∂p` (J2 model) in `A` (the paper drops it).
    pub gravity_gradient: bool,
    /// The filter's process noise; `None` = the scenario's true sensor noise
    /// ([`scenario_process_noise`]).
    pub process_noise: Option<ProcessNoise>,
    /// Fuse every n-th measurement epoch of each sensor (≥ 1) with 1/n of its noise
    /// variance: the information of n epochs in one update. 1 = every epoch (the flight's);
    /// larger values speed up a coarse search.
    pub measurement_stride: u32,
    /// Grow the attitude covariance for the second-order attitude term while the star sensor
    /// is unheard, as the flight software does (`covariance.second_order_attitude`).
    pub second_order_attitude: bool,
}

impl Default for DesignOptions {
    fn default() -> Self {
        Self {
            step_frames: 5,
            truth_substeps_per_frame: Some(2),
            gravity_gradient: true,
            process_noise: None,
            measurement_stride: 1,
            second_order_attitude: true,
        }
    }
}

/// A calibration block with the paper's reported accuracy (the target of the design).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CalibrationTarget {
    /// The error-state block.
    pub block: StateBlock,
    /// Reported accuracy (absolute estimate error) in `unit`.
    pub target: f64,
    /// Factor from the state's units to `unit` (2 for the installation error: the state is
    /// the quaternion vector part, ≈ half the rotation angle the target is stated in).
    pub state_to_unit: f64,
    /// Unit of `target`.
    pub unit: &'static str,
}

/// The paper's figures, defined once in nav-fsw.
const PAPER: CalibrationThresholds = CalibrationThresholds::PAPER_ACCURACY;

/// The paper's reported accuracies after convergence (Section 3, `docs/guide/model.md`), one per
/// calibration block in [`StateBlock::CALIBRATION`] order.
pub const CALIBRATION_TARGETS: [CalibrationTarget; 5] = calibration_targets();

/// [`CALIBRATION_TARGETS`] from the state layout's calibration blocks and the paper's figures
/// (both in the same order).
const fn calibration_targets() -> [CalibrationTarget; 5] {
    let values = PAPER.values();
    let mut targets = [CalibrationTarget {
        block: StateBlock::GyroBias,
        target: 0.0,
        state_to_unit: 1.0,
        unit: "",
    }; 5];
    let mut k = 0;
    while k < targets.len() {
        let block = StateBlock::CALIBRATION[k];
        let (state_to_unit, unit) = match block {
            StateBlock::StarInstallation => (2.0, "rad (angle)"),
            StateBlock::GyroBias => (1.0, "rad/s"),
            StateBlock::AccelBias => (1.0, "m/s^2"),
            _ => (1.0, "-"),
        };
        targets[k] = CalibrationTarget {
            block,
            target: values[k],
            state_to_unit,
            unit,
        };
        k += 1;
    }
    targets
}

/// Final 1σ of one calibration state against its target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SigmaRow {
    /// The block and its target.
    pub target: CalibrationTarget,
    /// Body axis, 0 = x.
    pub axis: usize,
    /// Final 1σ in the target's unit.
    pub sigma: f64,
}

impl SigmaRow {
    /// `sigma / target` (the design goal is ≤ 1/3).
    pub fn ratio(&self) -> f64 {
        self.sigma / self.target.target
    }
}

/// The calibration 1σ (in target units) at the end of one manoeuvre segment.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentSnapshot {
    /// The segment's label.
    pub label: String,
    /// Navigation time at its end (s).
    pub end_time_s: f64,
    /// 1σ per calibration state, in [`CALIBRATION_TARGETS`] order, x/y/z per block.
    pub sigmas: [f64; 15],
    /// 1σ of the twelve systematic IMU error states (nav-core `ImuErrorBlock` order), when
    /// the scenario carries them (`[filter.imu_errors]`).
    pub imu_error_sigmas: Option<[f64; IMU_ERROR_DIMENSION]>,
}

/// The orbit along the truth trajectory, for the safety check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitSummary {
    /// Lowest geocentric radius minus the WGS-84 equatorial radius over the flight (m).
    pub minimum_altitude_m: f64,
    /// Lowest osculating-perigee altitude over the flight (m): the perigee the vehicle would
    /// be left with if the engine stopped at any instant.
    pub minimum_perigee_altitude_m: f64,
    /// Osculating perigee altitude at the end (m).
    pub final_perigee_altitude_m: f64,
    /// Osculating apogee altitude at the end (m); infinite if the orbit is open.
    pub final_apogee_altitude_m: f64,
    /// `|∫ C f dt|`: the net inertial velocity change of all thrust (m/s).
    pub net_delta_v_mps: f64,
    /// `∫ |f| dt`: the velocity change the propulsion delivers in total (m/s).
    pub total_delta_v_mps: f64,
}

/// The analysis result.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignReport {
    /// Final 1σ of all 24 states, in the filter's units (vector-part attitude/installation).
    pub final_sigma: ErrorState,
    /// The 15 calibration rows with their targets.
    pub rows: Vec<SigmaRow>,
    /// Calibration 1σ at the end of each segment.
    pub snapshots: Vec<SegmentSnapshot>,
    /// Orbit safety figures.
    pub orbit: OrbitSummary,
    /// Flight duration (s).
    pub duration_s: f64,
    /// Number of star-sensor updates.
    pub star_updates: u64,
    /// Number of GNSS updates.
    pub gnss_updates: u64,
    /// The twelve systematic IMU error states, when the scenario carries them.
    pub imu_errors: Option<ImuErrorReport>,
}

impl DesignReport {
    /// The largest `sigma / target` over the calibration states.
    pub fn worst_ratio(&self) -> f64 {
        self.rows.iter().map(SigmaRow::ratio).fold(0.0, f64::max)
    }

    /// The final table (one line per calibration state) as text.
    pub fn table(&self) -> String {
        let mut text = String::from(
            "state                  axis   final 1-sigma       target    sigma/target\n",
        );
        for row in &self.rows {
            text.push_str(&format!(
                "{:<22} {:>4}   {:>13.3e}   {:>10.2e}   {:>8.3}   {}\n",
                row.target.block.name(),
                ["x", "y", "z"].get(row.axis).copied().unwrap_or("?"),
                row.sigma,
                row.target.target,
                row.ratio(),
                row.target.unit,
            ));
        }
        text
    }

    /// The per-segment history of the twelve systematic IMU error states (`sigma / prior`)
    /// as text; `None` without them.
    pub fn imu_error_history(&self) -> Option<String> {
        self.imu_errors
            .as_ref()
            .map(|imu| imu_errors::history(&self.snapshots, &imu.prior))
    }

    /// The per-segment history (ratio to target, per calibration state) as text.
    pub fn history(&self) -> String {
        let mut text = String::from("segment end (s)  label                       ");
        for target in CALIBRATION_TARGETS {
            text.push_str(&format!(" {:>17}", target.block.name()));
        }
        text.push('\n');
        for snapshot in &self.snapshots {
            text.push_str(&format!(
                "{:>15.1}  {:<27} ",
                snapshot.end_time_s, snapshot.label
            ));
            for (chunk, target) in snapshot.sigmas.chunks(3).zip(CALIBRATION_TARGETS) {
                let ratios: Vec<String> = chunk
                    .iter()
                    .map(|sigma| format!("{:5.2}", sigma / target.target))
                    .collect();
                text.push_str(&format!(" {:>17}", ratios.join(" ")));
            }
            text.push('\n');
        }
        text
    }
}

/// The frames of one covariance step, reduced to what the linearisation needs.
struct StepAccumulator {
    frames: Vec<TruthFrame>,
    errors: SensorErrorTruth,
    mode: FilterMode,
}

impl StepAccumulator {
    /// The linearisation point of the step (module docs) and its length (s).
    fn point(
        &self,
        frame: &LaunchFrame,
        gravity: Option<&GravityModel>,
    ) -> Option<(LinearisationPoint, f64, f64)> {
        let middle = self.frames.get(self.frames.len() / 2)?;
        let first = self.frames.first()?;
        let last = self.frames.last()?;
        let interval_s = last.time_s - first.start_time_s;
        let (delta_angle, delta_velocity) = self.frames.iter().fold(
            (Vector3::zeros(), Vector3::zeros()),
            |(angle, velocity), truth| {
                (
                    angle + truth.delta_angle_rad,
                    velocity + truth.delta_velocity_mps,
                )
            },
        );
        let rate = delta_angle / interval_s;
        let force = delta_velocity / interval_s;
        // What the sensors output (paper eqs. 1, 3 solved for the measurement):
        // ω_m = (ω + b_g) ./ (1 − λ_g), likewise f_m; open loop uses them uncorrected.
        let measured_rate = (rate + self.errors.gyro_bias_rad_per_s)
            .component_div(&self.errors.gyro_scale_factor.map(|lambda| 1.0 - lambda));
        let measured_force = (force + self.errors.accel_bias_mps2)
            .component_div(&self.errors.accel_scale_factor.map(|lambda| 1.0 - lambda));
        let (corrected_rate, corrected_force) = match self.mode {
            FilterMode::OpenLoop => (measured_rate, measured_force),
            FilterMode::ClosedLoop => (rate, force),
        };
        let gradient = gravity.map_or_else(Matrix3::zeros, |model| {
            model.gravity_gradient_launch(frame, &middle.position_m)
        });
        Some((
            LinearisationPoint {
                corrected_rate_rad_s: corrected_rate,
                corrected_specific_force_mps2: corrected_force,
                measured_rate_rad_s: measured_rate,
                measured_specific_force_mps2: measured_force,
                body_to_inertial: rotation_matrix(&middle.attitude_q_ib),
                gravity_gradient_per_s2: gradient,
            },
            interval_s,
            last.time_s,
        ))
    }
}

/// The aiding sensors as the flight software sees them: which samples arrive (the star
/// tracker's rate limit), their Jacobians at the truth and the flight filter's noise, and the
/// second-order attitude growth while the star sensor is unheard.
struct Aiding {
    mounting: Quaternion<f64>,
    /// Open loop: the installation estimate stays the identity; closed loop: the update's
    /// Jacobian does not depend on it to first order.
    installation_estimate: Quaternion<f64>,
    star_noise_rad: f64,
    gnss_noise_m: f64,
    /// 0 = the receiver outputs no velocity (no velocity update).
    gnss_velocity_noise_mps: f64,
    /// The Earth's rotation, whose velocity term couples the velocity update to position.
    earth: EarthRotation,
    star_max_rate_rad_s: f64,
    star_reacquisition_s: f64,
    star_blind_until_s: f64,
    second_order: Option<CoherentGrowth>,
    second_order_rate_rad_s: Vector3<f64>,
}

impl Aiding {
    fn new(
        scenario: &Scenario,
        options: &DesignOptions,
        earth: EarthRotation,
    ) -> Result<Self, DesignError> {
        let [x, y, z] = scenario.star_sensor.mounting_rotation_vector_deg;
        // One update stands for the mean of n epochs: 1/n of the variance.
        let stride_sigma = 1.0 / f64::from(options.measurement_stride.max(1)).sqrt();
        let gnss_noise_m = scenario
            .filter
            .gnss_noise_m
            .unwrap_or(scenario.gnss.noise_m);
        let star = &scenario.star_sensor;
        if !(star.max_rate_deg_per_s.is_finite() && star.reacquisition_s.is_finite()) {
            return Err(DesignError::Setting {
                key: "star_sensor.max_rate_deg_per_s / reacquisition_s",
                requirement: "must be finite",
            });
        }
        Ok(Self {
            mounting: exp_rotation_vector(&Vector3::new(
                x.to_radians(),
                y.to_radians(),
                z.to_radians(),
            )),
            installation_estimate: *UnitQuaternion::identity().quaternion(),
            // The flight configuration's floors: a zero-noise sensor still has a positive R.
            star_noise_rad: star.noise_rad().max(1e-12) * stride_sigma,
            gnss_noise_m: gnss_noise_m.max(1e-6) * stride_sigma,
            gnss_velocity_noise_mps: scenario.gnss.velocity_noise_mps * stride_sigma,
            earth,
            star_max_rate_rad_s: star.max_rate_deg_per_s.to_radians(),
            star_reacquisition_s: star.reacquisition_s,
            star_blind_until_s: f64::NEG_INFINITY,
            second_order: options.second_order_attitude.then(CoherentGrowth::default),
            second_order_rate_rad_s: Vector3::zeros(),
        })
    }

    /// Whether the star tracker tracks during `truth`'s frame: the sensor model's rule
    /// ([`star_tracker_tracks`]).
    fn star_tracking(&mut self, truth: &TruthFrame) -> bool {
        let (limit_rad_s, reacquisition_s) = (self.star_max_rate_rad_s, self.star_reacquisition_s);
        star_tracker_tracks(
            truth,
            limit_rad_s,
            reacquisition_s,
            &mut self.star_blind_until_s,
        )
    }

    fn star_update(
        &mut self,
        filter: &mut AnalysedFilter,
        truth: &TruthFrame,
    ) -> Result<bool, DesignError> {
        let attitude: Quaternion<f64> = truth.attitude_q_ib;
        let predicted = attitude * self.mounting * self.installation_estimate;
        let accepted = measurement::star_sensor(
            &attitude,
            &self.mounting,
            &self.installation_estimate,
            &predicted,
            &[self.star_noise_rad; 3],
        )
        .and_then(|linear| filter.update(&linear))
        .map_err(|error| DesignError::Filter {
            operation: "star update",
            time_s: truth.time_s,
            error,
        })?;
        if accepted {
            if let Some(growth) = &mut self.second_order {
                growth.restart();
            }
        }
        Ok(accepted)
    }

    /// Velocity (when the receiver outputs it), then position of one fix; whether the
    /// position update was accepted.
    fn gnss_update(
        &self,
        filter: &mut AnalysedFilter,
        truth: &TruthFrame,
    ) -> Result<bool, DesignError> {
        let failed = |operation| {
            move |error| DesignError::Filter {
                operation,
                time_s: truth.time_s,
                error,
            }
        };
        if self.gnss_velocity_noise_mps > 0.0 {
            // No lever arm: the body rates do not enter the Jacobian.
            let rate = measurement::BodyRate {
                corrected_rad_s: Vector3::zeros(),
                measured_rad_s: Vector3::zeros(),
            };
            let fix = measurement::GnssVelocityFix {
                turned_velocity_mps: truth.velocity_mps - self.earth.velocity_at(&truth.position_m),
                earth: self.earth,
            };
            measurement::gnss_velocity(
                &truth.attitude_q_ib,
                &truth.position_m,
                &truth.velocity_mps,
                &Vector3::zeros(),
                &rate,
                &fix,
                self.gnss_velocity_noise_mps,
            )
            .and_then(|linear| filter.update(&linear))
            .map_err(failed("GNSS velocity update"))?;
        }
        let accepted = measurement::gnss_position(
            &truth.attitude_q_ib,
            &truth.position_m,
            &Vector3::zeros(),
            &truth.position_m,
            self.gnss_noise_m,
        )
        .and_then(|linear| filter.update(&linear))
        .map_err(failed("GNSS update"))?;
        Ok(accepted)
    }

    /// The scheduler's second-order attitude growth (nav-fsw
    /// `inflate_for_second_order_attitude`) over one propagation of `interval_s` at the
    /// measured rate `measured_rate_rad_s`.
    fn grow_second_order_attitude(
        &mut self,
        filter: &mut AnalysedFilter,
        measured_rate_rad_s: &Vector3<f64>,
        interval_s: f64,
        time_s: f64,
    ) -> Result<(), DesignError> {
        let Some(growth) = &mut self.second_order else {
            return Ok(());
        };
        let covariance = filter.covariance();
        let rate_covariance = bilinear_attitude_rate_covariance(&covariance, measured_rate_rad_s);
        let rate_variance = rate_covariance.trace();
        if !(rate_variance.is_finite() && rate_variance > 0.0) {
            return Ok(());
        }
        let correlation = rate_error_correlation(
            &covariance,
            measured_rate_rad_s,
            &self.second_order_rate_rad_s,
        );
        self.second_order_rate_rad_s = *measured_rate_rad_s;
        let added = growth.grow_correlated(rate_variance.sqrt() * interval_s, correlation);
        filter
            .add_attitude_covariance(&(rate_covariance * (added / rate_variance)))
            .map_err(|error| DesignError::Filter {
                operation: "second-order attitude growth",
                time_s,
                error,
            })
    }
}

fn calibration_sigmas(filter: &AnalysedFilter) -> [f64; 15] {
    let sigma = filter.standard_deviations();
    let mut values = [0.0; 15];
    for (slots, target) in values.chunks_mut(3).zip(CALIBRATION_TARGETS) {
        for (axis, slot) in slots.iter_mut().enumerate() {
            *slot = sigma
                .get(target.block.index() + axis)
                .copied()
                .unwrap_or(0.0)
                * target.state_to_unit;
        }
    }
    values
}

/// Runs the covariance analysis of `scenario` (module docs).
///
/// # Errors
/// [`DesignError`] if the truth cannot be flown, a setting is unusable, or nav-core refuses a
/// step (which would mean a non-finite or non-positive-definite covariance).
pub fn analyse(scenario: &Scenario, options: &DesignOptions) -> Result<DesignReport, DesignError> {
    if options.step_frames == 0 {
        return Err(DesignError::Setting {
            key: "step_frames",
            requirement: "must be >= 1",
        });
    }
    let mut flown = scenario.clone();
    if let Some(substeps) = options.truth_substeps_per_frame {
        flown.simulation.truth_substeps_per_frame = substeps;
    }
    let launch = Launch::new(&flown)?;
    let frame = launch.frame;
    let mut truth = TruthSimulator::from_launch(&flown, &launch)?;
    let config = filter_config(scenario)?;
    let start_time_s = scenario.simulation.start_time_s;
    let mut filter = AnalysedFilter::new(ErrorStateFilter::new(&config).map_err(|error| {
        DesignError::Filter {
            operation: "filter initialisation",
            time_s: start_time_s,
            error,
        }
    })?);
    let base_noise = options
        .process_noise
        .unwrap_or_else(|| scenario_process_noise(scenario));
    let mut allowance = GravityAllowance::new(scenario, base_noise);
    let noise = base_noise.spectral_density_diagonal();
    let gravity = GravityModel { j2_enabled: true };
    let gravity_for_gradient = options.gravity_gradient.then_some(&gravity);

    let period_s = scenario.imu.frame_period_s();
    let stride = u64::from(options.measurement_stride.max(1));
    let star_frames = frames_in(1.0 / scenario.star_sensor.rate_hz, period_s).max(1) * stride;
    let gnss_frames = frames_in(1.0 / scenario.gnss.rate_hz, period_s).max(1) * stride;
    let mut aiding = Aiding::new(scenario, options, frame.earth_rotation())?;
    let step_frames = usize::try_from(options.step_frames).unwrap_or(usize::MAX);

    let mut orbit = OrbitTracker {
        frame,
        summary: OrbitSummary {
            minimum_altitude_m: f64::INFINITY,
            minimum_perigee_altitude_m: f64::INFINITY,
            final_perigee_altitude_m: f64::NAN,
            final_apogee_altitude_m: f64::NAN,
            net_delta_v_mps: 0.0,
            total_delta_v_mps: 0.0,
        },
        net_delta_v: Vector3::zeros(),
    };
    let mut step = StepAccumulator {
        frames: Vec::with_capacity(step_frames),
        errors: SensorSimulator::new(scenario)
            .map_err(|error| DesignError::Sensor(error.to_string()))?
            .error_truth(),
        mode: config.mode,
    };
    let mut snapshots = Vec::new();
    let mut multipliers = MultiplierTracker::default();
    let imu_error_prior = config.imu_error.state_sigmas();
    let (mut star_updates, mut gnss_updates) = (0_u64, 0_u64);
    let frame_count = truth.frame_count();
    let segment_labels: Vec<String> = truth
        .profile()
        .segments
        .iter()
        .map(|segment| segment.label.clone())
        .collect();

    while let Some(current) = truth.next_frame()? {
        orbit.observe(&current);
        let tracking = aiding.star_tracking(&current);
        step.frames.push(current);
        let frames_elapsed = current.frame_index + 1;
        let elapsed_s = current.time_s - start_time_s;
        let star_heard = tracking && !in_outage(&scenario.star_sensor.outages, elapsed_s);
        let star_due = frames_elapsed % star_frames == 0 && star_heard;
        // While the star sensor is unheard, the second-order growth is evaluated every frame,
        // as the flight software does: it depends on the covariance it feeds, and coarser
        // steps under-grow it (0.1 s steps: gyro scale factors 6-12 % low behind a blind
        // tracker).
        let frame_steps = !star_heard && options.second_order_attitude;
        let gnss_due =
            frames_elapsed % gnss_frames == 0 && !in_outage(&scenario.gnss.outages, elapsed_s);
        let last_frame = frames_elapsed >= frame_count;
        let segment_ends = last_frame
            || truth
                .profile()
                .segments
                .get(current.segment_index)
                .is_some_and(|segment| current.time_s >= segment.end_time_s() - 0.5 * period_s);
        if !(step.frames.len() >= step_frames
            || frame_steps
            || star_due
            || gnss_due
            || segment_ends)
        {
            continue;
        }
        let mut measured_rate = None;
        if let Some((point, interval_s, time_s)) = step.point(&frame, gravity_for_gradient) {
            let step_noise = match &mut allowance {
                Some(allowance) => allowance
                    .noise_at(&launch, &current.position_m)?
                    .spectral_density_diagonal(),
                None => noise,
            };
            let model = discretise(
                &system_matrix(&point),
                &noise_input_matrix(&point),
                &step_noise,
                interval_s,
                config.discretisation_order,
            )
            .map_err(|error| DesignError::Filter {
                operation: "discretise",
                time_s,
                error,
            })?;
            filter
                .predict(&model, &point)
                .map_err(|error| DesignError::Filter {
                    operation: "predict",
                    time_s,
                    error,
                })?;
            multipliers.observe(&point);
            measured_rate = Some((point.measured_rate_rad_s, interval_s));
        }
        step.frames.clear();
        if star_due {
            star_updates += u64::from(aiding.star_update(&mut filter, &current)?);
        } else if let Some((rate, interval_s)) = measured_rate {
            aiding.grow_second_order_attitude(&mut filter, &rate, interval_s, current.time_s)?;
        }
        if gnss_due {
            gnss_updates += u64::from(aiding.gnss_update(&mut filter, &current)?);
        }
        if segment_ends {
            snapshots.push(SegmentSnapshot {
                label: segment_labels
                    .get(current.segment_index)
                    .cloned()
                    .unwrap_or_default(),
                end_time_s: current.time_s,
                sigmas: calibration_sigmas(&filter),
                imu_error_sigmas: filter.imu_error_sigmas(),
            });
        }
    }

    let final_sigma = filter.standard_deviations();
    let rows = CALIBRATION_TARGETS
        .iter()
        .flat_map(|target| {
            (0..3).map(move |axis| SigmaRow {
                target: *target,
                axis,
                sigma: final_sigma
                    .get(target.block.index() + axis)
                    .copied()
                    .unwrap_or(0.0)
                    * target.state_to_unit,
            })
        })
        .collect();
    Ok(DesignReport {
        final_sigma,
        rows,
        snapshots,
        orbit: orbit.summary,
        duration_s: scenario.duration_s(),
        star_updates,
        gnss_updates,
        imu_errors: filter.imu_error_sigmas().map(|sigma| ImuErrorReport {
            prior: imu_error_prior,
            sigma,
            largest_multiplier: multipliers.largest,
        }),
    })
}

#[cfg(test)]
mod tests;
