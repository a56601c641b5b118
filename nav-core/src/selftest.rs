//! A fixed numerical workload run identically by the firmware on the Cortex-M7 and by the host
//! tests, whose results must agree bit for bit (`f64::to_bits`). It exercises what the filter
//! uses: 24×24 f64 products, libm transcendentals and quaternion integration.

use nalgebra::{Quaternion, SMatrix, Vector3};

use crate::attitude;
use crate::discretise::discretise;
use crate::error_model::{noise_input_matrix, system_matrix, LinearisationPoint, ProcessNoise};
use crate::filter::{
    apply_error_state, CalibrationEstimate, ErrorStateFilter, FilterConfig, FilterMode,
    InitialUncertainty,
};
use crate::frames::{LaunchFrame, LaunchSite};
use crate::measurement::{gnss_position, star_sensor};
use crate::observability::{
    full_update_measurement_matrix, PaperMotionState, RankTolerance, Scaling,
    StrippedObservability, SystemForm,
};
use crate::strapdown::{
    ImuIncrement, NavigationState, SensorCorrections, StepOutput, Strapdown, StrapdownConfig,
};
use crate::NavError;

/// Number of f64 results produced by [`reference_workload`].
pub const REFERENCE_RESULT_COUNT: usize = 8;

/// Runs the reference workload: builds a deterministic 24×24 matrix `M` from `sin`/`exp`,
/// forms `M Mᵀ` and `M M` and their traces, and integrates the attitude quaternion of a coning
/// motion for 500 steps of 2 ms with the exact rotation-vector exponential.
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
    let step_s = 0.002;
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
/// closed-loop reset with feedback into the navigation solution. Each step is a separate
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
}

impl FilterPathFixture {
    /// The fixture at its initial state (paper-like initial uncertainty, closed loop).
    ///
    /// # Errors
    /// Only if the built-in configuration were invalid.
    pub fn new() -> Result<Self, NavError> {
        let config = FilterConfig {
            mode: FilterMode::ClosedLoop,
            discretisation_order: 3,
            initial: InitialUncertainty {
                attitude_rad: 1e-3,
                position_m: 30.0,
                velocity_mps: 0.3,
                gyro_bias_rad_s: 5e-4,
                accel_bias_mps2: 5e-3,
                star_installation_rad: 5e-3,
                gyro_scale_factor: 1e-4,
                accel_scale_factor: 1e-4,
            },
        };
        let launch_frame = LaunchFrame::new(&LaunchSite {
            latitude_rad: 0.342,
            longitude_rad: 1.936,
            height_m: 20.0,
            azimuth_rad: 1.571,
            epoch_s: 0.0,
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
        })
    }

    /// One 2 ms strapdown step (coning/sculling, J2 gravity) with a time-varying rotation
    /// and thrust, corrected by the current calibration estimate.
    ///
    /// # Errors
    /// As [`Strapdown::step`].
    pub fn navigate(&mut self) -> Result<(), NavError> {
        let phase = 0.01 * f64::from(self.step);
        let rate = Vector3::new(0.1 * libm::sin(phase), 0.05, 1.7 * libm::cos(phase));
        let force = Vector3::new(0.5, 20.0 + libm::sin(3.0 * phase), -0.3);
        let increment = ImuIncrement::from_rates(&rate, &force, 0.002);
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

    /// One 2 ms covariance propagation about the last strapdown step: builds `A` (with the
    /// J2 gravity gradient) and `G`, discretises (order 3) and predicts.
    ///
    /// # Errors
    /// As [`discretise`] and [`ErrorStateFilter::predict`].
    pub fn propagate(&mut self) -> Result<(), NavError> {
        let step = &self.last_step;
        let point = LinearisationPoint {
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
        };
        let model = discretise(
            &system_matrix(&point),
            &noise_input_matrix(&point),
            &ProcessNoise::PAPER.spectral_density_diagonal(),
            0.002,
            3,
        )?;
        self.filter.predict(&model)
    }

    /// A star-sensor update with a fixed small attitude offset (10″-class noise model).
    ///
    /// # Errors
    /// As [`star_sensor`] and [`ErrorStateFilter::update`].
    pub fn star_update(&mut self) -> Result<(), NavError> {
        let mounting = attitude::exp_rotation_vector(&Vector3::new(0.0, 0.5, 0.0));
        let truth_offset = attitude::exp_rotation_vector(&Vector3::new(2e-4, -1e-4, 3e-4));
        let measured = attitude::product(
            &attitude::product(&self.navigation.attitude, &truth_offset),
            &mounting,
        );
        let [w, x, y, z] = self.calibration.star_installation_wxyz;
        let measurement = star_sensor(
            &self.navigation.attitude,
            &mounting,
            &Quaternion::new(w, x, y, z),
            &measured,
            10.0 / 206_264.806_247_096_36,
        )?;
        self.filter.update(&measurement, f64::INFINITY).map(|_| ())
    }

    /// A GNSS update 12 m away from the predicted antenna position.
    ///
    /// # Errors
    /// As [`gnss_position`] and [`ErrorStateFilter::update`].
    pub fn gnss_update(&mut self) -> Result<(), NavError> {
        let lever_arm = Vector3::new(0.5, 1.0, -0.2);
        let antenna = self.navigation.position_m
            + attitude::rotate(&self.navigation.attitude, &lever_arm)
            + Vector3::new(12.0, -5.0, 3.0);
        let measurement = gnss_position(
            &self.navigation.attitude,
            &self.navigation.position_m,
            &lever_arm,
            &antenna,
            10.0,
        )?;
        self.filter.update(&measurement, f64::INFINITY).map(|_| ())
    }

    /// Closed-loop reset and feedback into the navigation solution and calibration.
    ///
    /// # Errors
    /// As [`apply_error_state`].
    pub fn reset(&mut self) -> Result<(), NavError> {
        let error = self.filter.reset();
        apply_error_state(
            &error,
            &mut self.navigation.attitude,
            &mut self.navigation.position_m,
            &mut self.navigation.velocity_mps,
            &mut self.calibration,
        )
    }

    /// Runs the reference sequence: 100 strapdown steps each followed by a propagation, a star update every 25, a GNSS update
    /// every 50, a reset after every update.
    ///
    /// # Errors
    /// The first error of any step.
    pub fn run_sequence(&mut self) -> Result<(), NavError> {
        for frame in 1..=100u32 {
            self.navigate()?;
            self.propagate()?;
            if frame % 25 == 0 {
                self.star_update()?;
                self.reset()?;
            }
            if frame % 50 == 0 {
                self.gnss_update()?;
                self.reset()?;
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
mod tests {
    use super::*;

    #[test]
    fn filter_path_sequence_runs_and_moves_the_solution_by_the_measured_offsets() {
        let mut fixture = FilterPathFixture::new().unwrap();
        let before = fixture.results();
        fixture.run_sequence().unwrap();
        let after = fixture.results();
        assert!(after.iter().all(|v| v.is_finite()));
        // Each of the two GNSS updates sees a fix 12 m further in x than the current position
        // and moves by gain × 12 m: ≈ 0.9 × 12 (prior 30 m vs 10 m noise), then ≈ 0.5 × 12.
        // Compared with the same strapdown run without any update:
        let mut free_running = FilterPathFixture::new().unwrap();
        for _ in 0..100 {
            free_running.navigate().unwrap();
        }
        let moved_x = after[4] - free_running.results()[4];
        assert!(
            after[4] - before[4] > 1000.0,
            "the strapdown moved the vehicle"
        );
        assert!(moved_x > 14.0 && moved_x < 19.0, "{moved_x}");
        // Updates shrink the attitude variance below its prior.
        assert!(after[14] < (0.5e-3f64).powi(2), "{}", after[14]);
    }

    #[test]
    fn reference_workload_is_finite_and_keeps_the_quaternion_unit() {
        let results = reference_workload();
        assert!(results.iter().all(|value| value.is_finite()));
        assert!(results[0] > 0.0, "trace of a Gram matrix is positive");
        assert!(results[7].abs() < 1e-12);
    }

    #[test]
    fn observability_workload_gives_rank_15_for_each_paper_state_alone() {
        let results = observability_workload().unwrap();
        for chunk in results.chunks_exact(SINGULAR_VALUES_PER_STATE + 1) {
            let (singular_values, rank) = chunk.split_at(SINGULAR_VALUES_PER_STATE);
            assert!((rank[0] - 15.0).abs() < 1e-12, "{rank:?}");
            assert!(singular_values.windows(2).all(|pair| pair[0] >= pair[1]));
            // 15 clearly non-zero, 9 numerically zero (relative 1e-12).
            assert!(singular_values[14] > 1e-8 * singular_values[0]);
            assert!(singular_values[15] <= 1e-12 * singular_values[0]);
        }
    }
}
