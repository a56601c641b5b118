//! A fixed numerical workload run identically by the firmware on the Cortex-M7 and by the host
//! tests, whose results must agree bit for bit (`f64::to_bits`). It exercises what the filter
//! uses: 24×24 f64 products, libm transcendentals and quaternion integration.

use nalgebra::{Quaternion, SMatrix, Vector3};

use crate::arithmetic::{FilterArithmetic, Propagation};
use crate::attitude;
use crate::error_model::{system_matrix, LinearisationPoint, ProcessNoise};
use crate::filter::{
    apply_error_state, CalibrationEstimate, ErrorStateFilter, FilterConfig, FilterMode,
    InitialUncertainty,
};
use crate::frames::{LaunchFrame, LaunchSite};
use crate::measurement::{gnss_position, star_sensor, LinearMeasurement};
use crate::observability::{
    full_update_measurement_matrix, PaperMotionState, RankTolerance, Scaling,
    StrippedObservability, SystemForm,
};
use crate::state::BlockMask;
use crate::strapdown::{
    ImuIncrement, NavigationState, SensorCorrections, StepOutput, Strapdown, StrapdownConfig,
};
use crate::structured::StructuredModel;
use crate::NavError;

/// The fixture's IMU interval (s): the flight software's 500 Hz frame.
pub const STEP_S: f64 = 0.002;

/// Number of f64 results produced by [`reference_workload`].
pub const REFERENCE_RESULT_COUNT: usize = 8;

/// Runs the reference workload: builds a deterministic 24×24 matrix
/// `M_rc = sin(0.37 r + 1.13 c) · exp(−0.05 (r − c)²) + 0.01 r` (`r`, `c` = 0..23), forms
/// `M Mᵀ` and `M M` and their traces, and integrates the attitude quaternion of a coning
/// motion (body rate `(−a Ω sin Ωt, a Ω cos Ωt, 0.1)` rad/s, `a` = 0.02 rad, `Ω` = 2π·5 rad/s,
/// rate sampled at the start of each step) for 500 steps of 2 ms with the exact
/// rotation-vector exponential, `q ← q ⊗ exp(ω Δt)`.
///
/// Returns `[trace(M Mᵀ), trace(M M), (M Mᵀ)[(3,17)], q.w, q.x, q.y, q.z, |q| − 1]`.
pub fn reference_workload() -> [f64; REFERENCE_RESULT_COUNT] {
    let matrix = SMatrix::<f64, 24, 24>::from_fn(|row, column| {
        let r = f64::from(u32::try_from(row).unwrap_or(0));
        let c = f64::from(u32::try_from(column).unwrap_or(0));
        libm::sin(0.37 * r + 1.13 * c) * libm::exp(-0.05 * (r - c) * (r - c)) + 0.01 * r
    });
    let gram = matrix * matrix.transpose();
    let square = matrix * matrix;

    let mut attitude = Quaternion::new(1.0, 0.0, 0.0, 0.0);
    let step_s = STEP_S;
    let coning_rate_rad_s = 2.0 * core::f64::consts::PI * 5.0;
    let cone_half_angle_rad = 0.02;
    let mut time_s = 0.0;
    for _ in 0..500 {
        let rate = Vector3::new(
            -cone_half_angle_rad * coning_rate_rad_s * libm::sin(coning_rate_rad_s * time_s),
            cone_half_angle_rad * coning_rate_rad_s * libm::cos(coning_rate_rad_s * time_s),
            0.1,
        );
        attitude = attitude::product(&attitude, &attitude::exp_rotation_vector(&(rate * step_s)));
        time_s += step_s;
    }
    [
        gram.trace(),
        square.trace(),
        gram.get((3, 17)).copied().unwrap_or(f64::NAN),
        attitude.w,
        attitude.i,
        attitude.j,
        attitude.k,
        attitude.norm() - 1.0,
    ]
}

/// Number of f64 results of [`FilterPathFixture::results`].
pub const FILTER_PATH_RESULT_COUNT: usize = 16;

/// The whole filter path on a fixed, deterministic input sequence: linearisation and
/// 3rd-order discretisation, covariance prediction, star-sensor and GNSS updates, and the
/// closed-loop reset with feedback into the navigation solution, with the flight (structured)
/// implementation; each step also exists with the dense reference for cost comparisons. Each step is a separate
/// method so the firmware can cost it; host and target run the same sequence and must agree
/// bit for bit.
#[derive(Debug, Clone, Copy)]
pub struct FilterPathFixture {
    filter: ErrorStateFilter,
    navigation: NavigationState,
    strapdown: Strapdown,
    launch_frame: LaunchFrame,
    last_step: StepOutput,
    calibration: CalibrationEstimate,
    step: u32,
    /// The structured model, refilled in place by every structured propagation.
    model: StructuredModel,
}

impl FilterPathFixture {
    /// The fixture at its initial state (paper-like initial uncertainty, closed loop).
    ///
    /// # Errors
    /// Only if the built-in configuration were invalid.
    pub fn new() -> Result<Self, NavError> {
        let config = FilterConfig::without_optional_blocks(
            FilterMode::ClosedLoop,
            3,
            InitialUncertainty {
                attitude_rad: 1e-3,
                position_m: 30.0,
                velocity_mps: 0.3,
                gyro_bias_rad_s: 5e-4,
                accel_bias_mps2: 5e-3,
                star_installation_rad: 5e-3,
                gyro_scale_factor: 1e-4,
                accel_scale_factor: 1e-4,
            },
        );
        let launch_frame = LaunchFrame::new(&LaunchSite {
            latitude_rad: 0.342,
            longitude_rad: 1.936,
            height_m: 20.0,
            azimuth_rad: 1.571,
            earth_axis_ecef: [0.0, 0.0, 1.0],
        })?;
        let zero = Vector3::zeros();
        Ok(Self {
            filter: ErrorStateFilter::new(&config)?,
            navigation: NavigationState {
                attitude: attitude::exp_rotation_vector(&Vector3::new(0.1, 0.2, 0.3)),
                position_m: Vector3::new(1.0e5, 5.0e5, 2.0e5),
                velocity_mps: Vector3::new(7.5e3, 10.0, -20.0),
                time_s: 0.0,
            },
            strapdown: Strapdown::new(StrapdownConfig::default()),
            launch_frame,
            last_step: StepOutput {
                corrected_rate_rad_s: zero,
                corrected_specific_force_mps2: zero,
                measured_rate_rad_s: zero,
                measured_specific_force_mps2: zero,
                gravity_mps2: zero,
            },
            calibration: CalibrationEstimate::default(),
            step: 0,
            model: StructuredModel::EMPTY,
        })
    }

    /// One 2 ms strapdown step (coning/sculling, J2 gravity) with a time-varying rotation
    /// and thrust, corrected by the current calibration estimate: at step `k` (phase
    /// `φ = 0.01 k`) body rate `(0.1 sin φ, 0.05, 1.7 cos φ)` rad/s and specific force
    /// `(0.5, 20 + sin 3φ, −0.3)` m/s².
    ///
    /// # Errors
    /// As [`Strapdown::step`].
    pub fn navigate(&mut self) -> Result<(), NavError> {
        let phase = 0.01 * f64::from(self.step);
        let rate = Vector3::new(0.1 * libm::sin(phase), 0.05, 1.7 * libm::cos(phase));
        let force = Vector3::new(0.5, 20.0 + libm::sin(3.0 * phase), -0.3);
        let increment = ImuIncrement::from_rates(&rate, &force, STEP_S);
        let c = &self.calibration;
        let corrections = SensorCorrections {
            gyro_bias_rad_s: Vector3::from(c.gyro_bias_rad_s),
            accel_bias_mps2: Vector3::from(c.accel_bias_mps2),
            gyro_scale_factor: Vector3::from(c.gyro_scale_factor),
            accel_scale_factor: Vector3::from(c.accel_scale_factor),
        };
        self.last_step = self.strapdown.step(
            &mut self.navigation,
            &increment,
            &corrections,
            &self.launch_frame,
        )?;
        self.step = self.step.wrapping_add(1);
        Ok(())
    }

    /// The linearisation point of the last strapdown step (with the J2 gravity gradient).
    fn linearisation_point(&self) -> LinearisationPoint {
        let step = &self.last_step;
        LinearisationPoint {
            corrected_rate_rad_s: step.corrected_rate_rad_s,
            corrected_specific_force_mps2: step.corrected_specific_force_mps2,
            measured_rate_rad_s: step.measured_rate_rad_s,
            measured_specific_force_mps2: step.measured_specific_force_mps2,
            body_to_inertial: attitude::rotation_matrix(&self.navigation.attitude),
            gravity_gradient_per_s2: self
                .strapdown
                .config()
                .gravity
                .gravity_gradient_launch(&self.launch_frame, &self.navigation.position_m),
        }
    }

    /// The parts of [`FilterPathFixture::propagate`] for the cost breakdown: `0` the
    /// linearisation point (rotation matrix and gravity gradient), `1` that and the
    /// structured model, `2` everything (as `propagate`).
    ///
    /// # Errors
    /// As [`FilterPathFixture::propagate_with`].
    pub fn propagate_part(&mut self, part: u8) -> Result<(), NavError> {
        let point = core::hint::black_box(self.linearisation_point());
        if part == 0 {
            return Ok(());
        }
        self.model
            .rebuild(&point, &ProcessNoise::PAPER, STEP_S, 3)?;
        if part == 1 {
            return Ok(());
        }
        self.filter.predict_structured(&self.model)
    }

    /// One 2 ms covariance propagation about the last strapdown step with the flight
    /// (structured) implementation.
    ///
    /// # Errors
    /// As [`FilterPathFixture::propagate_with`].
    pub fn propagate(&mut self) -> Result<(), NavError> {
        self.propagate_with(FilterArithmetic::Structured)
    }

    /// One 2 ms covariance propagation about the last strapdown step (order 3): structured
    /// ([`StructuredModel`], [`ErrorStateFilter::predict_structured`]) or dense (`A` and `G`,
    /// `discretise`, [`ErrorStateFilter::predict`]).
    ///
    /// # Errors
    /// As [`StructuredModel::new`]/`discretise` and the predict.
    pub fn propagate_with(&mut self, implementation: FilterArithmetic) -> Result<(), NavError> {
        let point = self.linearisation_point();
        let step = Propagation {
            point: &point,
            noise: &ProcessNoise::PAPER,
            interval_s: STEP_S,
            order: 3,
            frozen: &BlockMask::NONE,
        };
        implementation.predict(&mut self.filter, &mut self.model, &step)
    }

    /// Applies `measurement` with the chosen update implementation (no gate, nothing frozen).
    fn apply(
        &mut self,
        measurement: &LinearMeasurement,
        implementation: FilterArithmetic,
    ) -> Result<(), NavError> {
        implementation
            .update(
                &mut self.filter,
                measurement,
                f64::INFINITY,
                &BlockMask::NONE,
            )
            .map(|_| ())
    }

    /// A star-sensor update with a fixed small attitude offset (10″-class noise model), with
    /// the flight (structured) update.
    ///
    /// # Errors
    /// As [`FilterPathFixture::star_update_with`].
    pub fn star_update(&mut self) -> Result<(), NavError> {
        self.star_update_with(FilterArithmetic::Structured)
    }

    /// [`FilterPathFixture::star_update`] with the chosen implementation.
    ///
    /// # Errors
    /// As [`star_sensor`] and the update.
    pub fn star_update_with(&mut self, implementation: FilterArithmetic) -> Result<(), NavError> {
        let mounting = attitude::exp_rotation_vector(&Vector3::new(0.0, 0.5, 0.0));
        let truth_offset = attitude::exp_rotation_vector(&Vector3::new(2e-4, -1e-4, 3e-4));
        let measured = attitude::product(
            &attitude::product(&self.navigation.attitude, &truth_offset),
            &mounting,
        );
        let [w, x, y, z] = self.calibration.star_installation_wxyz;
        // Used where it lies, as the flight scheduler does: moving the measurement out of
        // the `Result` (`?`) copies it twice on the target, through a misaligned temporary.
        let measurement = star_sensor(
            &self.navigation.attitude,
            &mounting,
            &Quaternion::new(w, x, y, z),
            &measured,
            &[10.0 / 206_264.806_247_096_36; 3],
        );
        match &measurement {
            Ok(measurement) => self.apply(measurement, implementation),
            Err(error) => Err(*error),
        }
    }

    /// A GNSS update 12 m away from the predicted antenna position (lever arm
    /// `(0.5, 1.0, −0.2)` m in body axes, fix = predicted antenna + `(12, −5, 3)` m, 1σ 10 m),
    /// with the flight (structured) update.
    ///
    /// # Errors
    /// As [`FilterPathFixture::gnss_update_with`].
    pub fn gnss_update(&mut self) -> Result<(), NavError> {
        self.gnss_update_with(FilterArithmetic::Structured, 0.0)
    }

    /// [`FilterPathFixture::gnss_update`] with the chosen implementation; a positive
    /// `latency_s` refers the fix to the current error state with `H (I − AΔ)` (as the
    /// flight scheduler does for a late fix: by blocks, or with the dense `A`), which adds
    /// the velocity, gyro-bias and gyro-scale-factor columns to `H`.
    ///
    /// # Errors
    /// As [`gnss_position`], `measurement::refer_to_later_time` and the update.
    pub fn gnss_update_with(
        &mut self,
        implementation: FilterArithmetic,
        latency_s: f64,
    ) -> Result<(), NavError> {
        let lever_arm = Vector3::new(0.5, 1.0, -0.2);
        let antenna = self.navigation.position_m
            + attitude::rotate(&self.navigation.attitude, &lever_arm)
            + Vector3::new(12.0, -5.0, 3.0);
        // Used where it lies, as the flight scheduler does (no copy of the measurement out
        // of the `Result`, see `star_update_with`).
        let mut measurement = gnss_position(
            &self.navigation.attitude,
            &self.navigation.position_m,
            &lever_arm,
            &antenna,
            10.0,
        );
        let Ok(linear) = &mut measurement else {
            return measurement.map(|_| ());
        };
        if latency_s > 0.0 {
            let point = self.linearisation_point();
            // In place, as the flight scheduler does (no copy of the measurement).
            implementation.refer_to_later_time(linear, &point, latency_s)?;
        }
        self.apply(linear, implementation)
    }

    /// Closed-loop reset and feedback into the navigation solution and calibration (the
    /// flight, block-wise reset).
    ///
    /// # Errors
    /// As [`FilterPathFixture::reset_with`].
    pub fn reset(&mut self) -> Result<(), NavError> {
        self.reset_with(FilterArithmetic::Structured)
    }

    /// [`FilterPathFixture::reset`] with the chosen implementation of `J P Jᵀ`.
    ///
    /// # Errors
    /// As [`apply_error_state`].
    pub fn reset_with(&mut self, implementation: FilterArithmetic) -> Result<(), NavError> {
        let error = implementation.reset(&mut self.filter);
        apply_error_state(
            &error,
            &mut self.navigation.attitude,
            &mut self.navigation.position_m,
            &mut self.navigation.velocity_mps,
            &mut self.calibration,
        )
    }

    /// The filter path of the worst 2 ms frame of a scheduler that propagates and fuses in
    /// one frame (nav-fsw's `FrameLoad::PropagateThenFuse`): a strapdown step, a covariance
    /// propagation, one measurement update (the costliest: a GNSS fix 10 ms late, referred
    /// to the current state) and the closed-loop reset.
    ///
    /// # Errors
    /// The first error of any step.
    pub fn worst_frame_with(&mut self, implementation: FilterArithmetic) -> Result<(), NavError> {
        self.navigate()?;
        self.propagate_with(implementation)?;
        self.gnss_update_with(implementation, 0.01)?;
        self.reset_with(implementation)
    }

    /// Runs the reference sequence with the flight (structured) implementation: 100
    /// strapdown steps each followed by a propagation, a star update every 25, a GNSS update
    /// every 50, a reset after every update.
    ///
    /// # Errors
    /// The first error of any step.
    pub fn run_sequence(&mut self) -> Result<(), NavError> {
        self.run_sequence_with(FilterArithmetic::Structured)
    }

    /// [`FilterPathFixture::run_sequence`] with the chosen implementation.
    ///
    /// # Errors
    /// The first error of any step.
    pub fn run_sequence_with(&mut self, implementation: FilterArithmetic) -> Result<(), NavError> {
        for frame in 1..=100u32 {
            self.navigate()?;
            self.propagate_with(implementation)?;
            if frame % 25 == 0 {
                self.star_update_with(implementation)?;
                self.reset_with(implementation)?;
            }
            if frame % 50 == 0 {
                self.gnss_update_with(implementation, 0.0)?;
                self.reset_with(implementation)?;
            }
        }
        Ok(())
    }

    /// Results compared bit for bit: attitude (4), position (3), velocity (3), gyro bias (3),
    /// trace of P, P(attitude x, attitude x), P(position x, velocity x).
    pub fn results(&self) -> [f64; FILTER_PATH_RESULT_COUNT] {
        let p = self.filter.covariance();
        let element = |row: usize, column: usize| p.get((row, column)).copied().unwrap_or(f64::NAN);
        let [bx, by, bz] = self.calibration.gyro_bias_rad_s;
        [
            self.navigation.attitude.w,
            self.navigation.attitude.i,
            self.navigation.attitude.j,
            self.navigation.attitude.k,
            self.navigation.position_m.x,
            self.navigation.position_m.y,
            self.navigation.position_m.z,
            self.navigation.velocity_mps.x,
            self.navigation.velocity_mps.y,
            self.navigation.velocity_mps.z,
            bx,
            by,
            bz,
            p.trace(),
            element(0, 0),
            element(3, 6),
        ]
    }
}

/// Singular values per paper state in [`observability_workload`] (one per error state).
const SINGULAR_VALUES_PER_STATE: usize = 24;
/// Number of f64 results of [`observability_workload`]: for each of the paper's motion states
/// I, II, III its 24 singular values (descending) and its rank.
pub const OBSERVABILITY_RESULT_COUNT: usize = 3 * (SINGULAR_VALUES_PER_STATE + 1);

/// The Table 1 analysis on a fixed geometry: for each of the paper's motion states
/// ([`PaperMotionState::ALL`]) alone, the SVD of its scaled continuous observability matrix
/// (Givens-accumulated factor, [`Scaling::typical`], [`RankTolerance::DEFAULT`]) at the
/// attitude `exp([0.2, 0.4, −0.1])` with the star-sensor mounting `exp([0.4, −1.1, 0.25])`.
///
/// Returns, per state, its 24 singular values then its rank (as f64, 15 for each state).
///
/// # Errors
/// As [`StrippedObservability::add_segment`] and [`StrippedObservability::analyse`] (none for
/// this fixed input).
pub fn observability_workload() -> Result<[f64; OBSERVABILITY_RESULT_COUNT], NavError> {
    let attitude = attitude::exp_rotation_vector(&Vector3::new(0.2, 0.4, -0.1));
    let mounting = attitude::exp_rotation_vector(&Vector3::new(0.4, -1.1, 0.25));
    let body_to_inertial = attitude::rotation_matrix(&attitude);
    let h = full_update_measurement_matrix(&attitude, &mounting)?;
    let mut results = [0.0; OBSERVABILITY_RESULT_COUNT];
    for (state, chunk) in PaperMotionState::ALL
        .iter()
        .zip(results.chunks_exact_mut(SINGULAR_VALUES_PER_STATE + 1))
    {
        let mut stripped = StrippedObservability::new(Scaling::typical())?;
        stripped.add_segment(
            &system_matrix(&state.linearisation_point(&body_to_inertial)),
            &h,
            SystemForm::Continuous,
        )?;
        let analysis = stripped.analyse(&RankTolerance::DEFAULT)?;
        let rank = u32::try_from(analysis.rank).map_err(|_| NavError::NonFiniteState)?;
        for (slot, value) in chunk.iter_mut().zip(
            analysis
                .singular_values
                .iter()
                .chain([f64::from(rank)].iter()),
        ) {
            *slot = *value;
        }
    }
    Ok(results)
}

#[cfg(test)]
#[path = "selftest_tests.rs"]
mod tests;
