//! The error-state Kalman filter: covariance prediction, gated Joseph-form updates, and the
//! open-loop (paper) or closed-loop (reset) handling of the error state.
//!
//! * Predict: `x ← F x` (open loop only; closed loop keeps `x = 0`), `P ← F P Fᵀ + Qd`.
//! * Update: `ν = z − H x`, `S = H P Hᵀ + R` (Cholesky; not positive definite ⇒ error),
//!   NIS `= νᵀ S⁻¹ ν`, `K = P Hᵀ S⁻¹`, `x ← x + K ν`,
//!   Joseph form `P ← (I − K H) P (I − K H)ᵀ + K R Kᵀ` (Bucy & Joseph 1968), then
//!   symmetrised. A measurement whose NIS exceeds the gate leaves `x` and `P` untouched.
//! * Closed-loop reset: the caller applies `x` to the navigation solution and the sensor
//!   estimates ([`apply_error_state`]), and the filter zeroes `x` and maps `P` through the
//!   reset Jacobian: after `q̂⁺ = q̂ ⊗ δq(ϑ̂)`, the new error is `δq⁺ = δq(ϑ̂)* ⊗ δq`, so
//!   `∂ϑ⁺/∂ϑ = I − [ϑ̂×]` to first order (Solà 2017, §7.2, with `ϑ = δθ/2`); likewise for the
//!   installation error. All other blocks reset with the identity.
//!
//! Every failure is a typed [`NavError`] and leaves the filter exactly as it was.

use nalgebra::{Cholesky, Matrix3, Quaternion, SMatrix, SVector, Vector3};

use crate::attitude::{self, skew};
use crate::block;
use crate::discretise::{CovarianceMatrix, DiscreteModel};
use crate::error_model::set_block;
use crate::gnss_error::{GnssErrorModel, GnssErrorStates};
use crate::measurement::LinearMeasurement;
use crate::state::{
    BlockMask, StateBlock, ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, BLOCKS, GYRO_BIAS,
    GYRO_SCALE_FACTOR, POSITION, STAR_INSTALLATION, STATE_DIMENSION, VELOCITY,
};
use crate::structured::{self, StructuredModel};
use crate::NavError;

/// The 24-element error-state vector.
pub type ErrorState = SVector<f64, STATE_DIMENSION>;

/// How the estimated errors are used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FilterMode {
    /// The paper's filter: the navigation solution is never corrected; `x` accumulates.
    OpenLoop,
    /// After each update the errors are fed back and `x` is zeroed (flight practice).
    ClosedLoop,
}

/// Initial 1σ per block (same value on each of the block's three axes).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct InitialUncertainty {
    /// Attitude error, as a rotation angle (rad); the state's 1σ is half of it.
    pub attitude_rad: f64,
    /// Position (m).
    pub position_m: f64,
    /// Velocity (m/s).
    pub velocity_mps: f64,
    /// Gyro bias (rad/s).
    pub gyro_bias_rad_s: f64,
    /// Accelerometer bias (m/s²).
    pub accel_bias_mps2: f64,
    /// Star-sensor installation error, as a rotation angle (rad); the state's 1σ is half.
    pub star_installation_rad: f64,
    /// Gyro scale factor (dimensionless).
    pub gyro_scale_factor: f64,
    /// Accelerometer scale factor (dimensionless).
    pub accel_scale_factor: f64,
}

/// Filter configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FilterConfig {
    /// Open or closed loop.
    pub mode: FilterMode,
    /// Discretisation order, 1 to 4 (paper: 3).
    pub discretisation_order: u8,
    /// Initial 1σ per block.
    pub initial: InitialUncertainty,
    /// The GNSS receiver's correlated position error ([`crate::gnss_error`]);
    /// [`GnssErrorModel::WHITE`] for the paper's 24 states.
    pub gnss_error: GnssErrorModel,
}

impl FilterConfig {
    /// Checks every value is finite and in range.
    ///
    /// # Errors
    /// [`NavError::InvalidDiscretisationOrder`], or [`NavError::InvalidConfiguration`] for a
    /// non-finite or non-positive initial 1σ or a bad [`GnssErrorModel`].
    pub fn validate(&self) -> Result<(), NavError> {
        if !(1..=crate::discretise::MAX_ORDER).contains(&self.discretisation_order) {
            return Err(NavError::InvalidDiscretisationOrder);
        }
        self.gnss_error.validate()?;
        let sigmas = self.initial_sigmas();
        if sigmas
            .iter()
            .all(|(_, sigma)| sigma.is_finite() && *sigma > 0.0)
        {
            Ok(())
        } else {
            Err(NavError::InvalidConfiguration)
        }
    }

    /// 1σ of each block's state (the attitude and installation states are half-angles).
    fn initial_sigmas(&self) -> [(StateBlock, f64); 8] {
        let i = &self.initial;
        [
            (ATTITUDE, 0.5 * i.attitude_rad),
            (POSITION, i.position_m),
            (VELOCITY, i.velocity_mps),
            (GYRO_BIAS, i.gyro_bias_rad_s),
            (ACCEL_BIAS, i.accel_bias_mps2),
            (STAR_INSTALLATION, 0.5 * i.star_installation_rad),
            (GYRO_SCALE_FACTOR, i.gyro_scale_factor),
            (ACCEL_SCALE_FACTOR, i.accel_scale_factor),
        ]
    }
}

/// What an update computed, for gating and telemetry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InnovationReport {
    /// Innovation `ν = z − H x`.
    pub innovation: Vector3<f64>,
    /// Innovation covariance `S = H P Hᵀ + R`.
    pub covariance: Matrix3<f64>,
    /// Normalised innovation squared `νᵀ S⁻¹ ν` (χ² with 3 degrees of freedom if consistent).
    pub normalised_innovation_squared: f64,
    /// Whether the update was applied (false: rejected by the gate, filter untouched).
    pub accepted: bool,
}

/// The sensor-error estimates the closed-loop filter feeds back into.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CalibrationEstimate {
    /// Gyro bias (rad/s).
    pub gyro_bias_rad_s: [f64; 3],
    /// Accelerometer bias (m/s²).
    pub accel_bias_mps2: [f64; 3],
    /// Star-sensor installation error `q̂_ψ`, `[w, x, y, z]`.
    pub star_installation_wxyz: [f64; 4],
    /// Gyro scale factor (dimensionless).
    pub gyro_scale_factor: [f64; 3],
    /// Accelerometer scale factor (dimensionless).
    pub accel_scale_factor: [f64; 3],
}

impl Default for CalibrationEstimate {
    fn default() -> Self {
        Self {
            gyro_bias_rad_s: [0.0; 3],
            accel_bias_mps2: [0.0; 3],
            star_installation_wxyz: [1.0, 0.0, 0.0, 0.0],
            gyro_scale_factor: [0.0; 3],
            accel_scale_factor: [0.0; 3],
        }
    }
}

/// Error state and covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorStateFilter {
    state: ErrorState,
    covariance: CovarianceMatrix,
    mode: FilterMode,
    /// The correlated GNSS error states (the border of a 27-state filter), inert under
    /// [`GnssErrorModel::WHITE`].
    gnss_error: GnssErrorStates,
}

/// The three states of `block` (NaN for an index outside the state, which the state layout
/// never produces: no panic path).
pub fn block_of(state: &ErrorState, block: StateBlock) -> Vector3<f64> {
    let component = |offset: usize| {
        block
            .index
            .checked_add(offset)
            .and_then(|index| state.get(index))
            .copied()
            .unwrap_or(f64::NAN)
    };
    Vector3::new(component(0), component(1), component(2))
}

fn add3(target: &mut [f64; 3], delta: &Vector3<f64>) {
    let [x, y, z] = target;
    *x += delta.x;
    *y += delta.y;
    *z += delta.z;
}

/// Applies an error state to a navigation solution and calibration estimate (closed-loop
/// feedback): `q̂ ← q̂ ⊗ δq(ϑ)`, `p̂ += δp`, `v̂ += δv`, `b̂ += δb`, `λ̂ += δλ`,
/// `q̂_ψ ← q̂_ψ ⊗ δq(ψ)`. Nothing is changed on error.
///
/// # Errors
/// [`NavError::NonFiniteState`] if `x` is not finite, [`NavError::DegenerateQuaternion`] if
/// an attitude correction is not a valid quaternion vector part (|ϑ| ≥ 1).
pub fn apply_error_state(
    error: &ErrorState,
    attitude: &mut Quaternion<f64>,
    position_m: &mut Vector3<f64>,
    velocity_mps: &mut Vector3<f64>,
    calibration: &mut CalibrationEstimate,
) -> Result<(), NavError> {
    if !block::all_finite(error.as_slice()) {
        return Err(NavError::NonFiniteState);
    }
    let attitude_correction = attitude::from_vector_part(&block_of(error, ATTITUDE))?;
    let installation_correction = attitude::from_vector_part(&block_of(error, STAR_INSTALLATION))?;
    let [w, x, y, z] = calibration.star_installation_wxyz;
    let installation = attitude::normalise(&attitude::product(
        &Quaternion::new(w, x, y, z),
        &installation_correction,
    ))?;
    let new_attitude = attitude::normalise(&attitude::product(attitude, &attitude_correction))?;
    *attitude = new_attitude;
    calibration.star_installation_wxyz = [
        installation.w,
        installation.i,
        installation.j,
        installation.k,
    ];
    *position_m += block_of(error, POSITION);
    *velocity_mps += block_of(error, VELOCITY);
    add3(
        &mut calibration.gyro_bias_rad_s,
        &block_of(error, GYRO_BIAS),
    );
    add3(
        &mut calibration.accel_bias_mps2,
        &block_of(error, ACCEL_BIAS),
    );
    add3(
        &mut calibration.gyro_scale_factor,
        &block_of(error, GYRO_SCALE_FACTOR),
    );
    add3(
        &mut calibration.accel_scale_factor,
        &block_of(error, ACCEL_SCALE_FACTOR),
    );
    Ok(())
}

impl ErrorStateFilter {
    /// A filter with `x = 0` and `P = diag(σ²)` from the configuration.
    ///
    /// # Errors
    /// As [`FilterConfig::validate`].
    pub fn new(config: &FilterConfig) -> Result<Self, NavError> {
        config.validate()?;
        let mut covariance = CovarianceMatrix::zeros();
        for (block, sigma) in config.initial_sigmas() {
            set_block(
                &mut covariance,
                block,
                block,
                &(Matrix3::identity() * (sigma * sigma)),
            );
        }
        Ok(Self {
            state: ErrorState::zeros(),
            covariance,
            mode: config.mode,
            gnss_error: GnssErrorStates::new(config.gnss_error)?,
        })
    }

    /// The correlated GNSS error states ([`crate::gnss_error`]).
    pub fn gnss_error(&self) -> &GnssErrorStates {
        &self.gnss_error
    }

    /// The correlated GNSS error states, for the crate's tests.
    #[cfg(test)]
    pub(crate) fn gnss_error_mut(&mut self) -> &mut GnssErrorStates {
        &mut self.gnss_error
    }

    /// The error-state estimate `x`.
    pub fn state(&self) -> &ErrorState {
        &self.state
    }

    /// The covariance `P`.
    pub fn covariance(&self) -> &CovarianceMatrix {
        &self.covariance
    }

    /// The mode.
    pub fn mode(&self) -> FilterMode {
        self.mode
    }

    /// 1σ of every state (square roots of the diagonal of `P`).
    pub fn standard_deviations(&self) -> ErrorState {
        self.covariance
            .diagonal()
            .map(|variance| libm::sqrt(variance.max(0.0)))
    }

    /// Adds `variance · I` to the diagonal block of `block` (m², rad², … in the block's
    /// units): process noise the discrete model does not contain, such as the error of a
    /// held IMU sample. `P` stays symmetric positive definite. The isotropic case of
    /// [`ErrorStateFilter::add_block_covariance`], with a loop of its own over the diagonal:
    /// written through that function it costs 80 instructions more in the worst frame on the
    /// Cortex-M7 (QEMU replay).
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a negative or non-finite variance; nothing changes
    /// then.
    ///
    /// # Examples
    /// ```
    /// use nav_core::filter::{ErrorStateFilter, FilterConfig, FilterMode, InitialUncertainty};
    /// use nav_core::gnss_error::GnssErrorModel;
    /// use nav_core::state::VELOCITY;
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig { mode: FilterMode::ClosedLoop, discretisation_order: 3,
    ///     initial, gnss_error: GnssErrorModel::WHITE };
    /// let mut filter = ErrorStateFilter::new(&config).unwrap();
    /// filter.add_block_variance(VELOCITY, 0.03).unwrap();
    /// assert!((filter.covariance()[(VELOCITY.index, VELOCITY.index)] - 0.04).abs() < 1e-15);
    /// ```
    pub fn add_block_variance(&mut self, block: StateBlock, variance: f64) -> Result<(), NavError> {
        if !(variance.is_finite() && variance >= 0.0) {
            return Err(NavError::NonFiniteInput);
        }
        for index in block.index..block.index.saturating_add(block.dimension) {
            if let Some(entry) = self
                .covariance
                .data
                .0
                .get_mut(index)
                .and_then(|column| column.get_mut(index))
            {
                *entry += variance;
            }
        }
        Ok(())
    }

    /// Adds the symmetric part of `covariance` (a 3×3 covariance in the block's units) to the
    /// diagonal block of `block`: process noise with a direction, such as the attitude
    /// kinematics' second-order term (nav-core [`crate::unmodelled`]).
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a non-finite entry or a negative diagonal entry;
    /// nothing changes then.
    ///
    /// # Examples
    /// ```
    /// use nalgebra::Matrix3;
    /// use nav_core::filter::{ErrorStateFilter, FilterConfig, FilterMode, InitialUncertainty};
    /// use nav_core::gnss_error::GnssErrorModel;
    /// use nav_core::state::ATTITUDE;
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig { mode: FilterMode::ClosedLoop, discretisation_order: 3,
    ///     initial, gnss_error: GnssErrorModel::WHITE };
    /// let mut filter = ErrorStateFilter::new(&config).unwrap();
    /// let along_x_and_y = Matrix3::new(1e-8, 1e-8, 0.0, 1e-8, 1e-8, 0.0, 0.0, 0.0, 0.0);
    /// filter.add_block_covariance(ATTITUDE, &along_x_and_y).unwrap();
    /// assert!((filter.covariance()[(0, 1)] - 1e-8).abs() < 1e-22);
    /// assert!(filter.add_block_covariance(ATTITUDE, &(-along_x_and_y)).is_err());
    /// ```
    pub fn add_block_covariance(
        &mut self,
        block: StateBlock,
        covariance: &Matrix3<f64>,
    ) -> Result<(), NavError> {
        let finite = covariance.iter().all(|value| value.is_finite());
        let diagonal_positive = covariance.diagonal().iter().all(|value| *value >= 0.0);
        if !(finite && diagonal_positive) {
            return Err(NavError::NonFiniteInput);
        }
        let symmetric = (covariance + covariance.transpose()) * 0.5;
        for (row, values) in symmetric.row_iter().enumerate() {
            for (column, value) in values.iter().enumerate() {
                if let Some(entry) = self
                    .covariance
                    .data
                    .0
                    .get_mut(block.index.saturating_add(column))
                    .and_then(|entries| entries.get_mut(block.index.saturating_add(row)))
                {
                    *entry += value;
                }
            }
        }
        Ok(())
    }

    /// Replaces `P` (for covariance protection by the caller).
    ///
    /// # Errors
    /// [`NavError::NonFiniteState`] if `covariance` has NaN/Inf; nothing changes then.
    pub fn set_covariance(&mut self, covariance: &CovarianceMatrix) -> Result<(), NavError> {
        if !covariance.iter().all(|v| v.is_finite()) {
            return Err(NavError::NonFiniteState);
        }
        self.covariance = symmetrised(covariance);
        Ok(())
    }

    /// Covariance protection in place: each variance below its `floor` is raised to it; each
    /// variance above its `ceiling` becomes the ceiling, with the rest of its row and column
    /// multiplied by `s = √(ceiling/variance)`: `P' = S P S`, `S = diag(1, …, s, …, 1)`, which
    /// keeps every correlation coefficient and positive definiteness. Returns whether anything
    /// was changed. Only the diagonal is read unless a bound is crossed.
    pub fn protect_variances(&mut self, floor: &ErrorState, ceiling: &ErrorState) -> bool {
        // The diagonal is read through the column arrays with one index (nalgebra's strided
        // iterators and checked 2-D indexing cost ~45 instructions per state on the target).
        let ([floor], [ceiling]) = (&floor.data.0, &ceiling.data.0);
        let columns = &mut self.covariance.data.0;
        let mut crossed = [false; STATE_DIMENSION];
        let mut clamped = false;
        for index in 0..STATE_DIMENSION {
            let (Some(column), Some(floor), Some(ceiling), Some(crossing)) = (
                columns.get_mut(index),
                floor.get(index),
                ceiling.get(index),
                crossed.get_mut(index),
            ) else {
                continue;
            };
            let Some(variance) = column.get_mut(index) else {
                continue;
            };
            if *variance < *floor {
                *variance = *floor;
                clamped = true;
            } else if *variance > *ceiling {
                *crossing = true;
                clamped = true;
            }
        }
        if !clamped {
            return false;
        }
        // Rare: a variance above its ceiling (in state order, as the scaling of one state
        // changes the off-diagonal entries the next one scales).
        for (index, (crossing, ceiling)) in crossed.iter().zip(ceiling).enumerate() {
            let (true, Some(variance)) = (
                *crossing,
                self.covariance.data.0.get(index).and_then(|c| c.get(index)),
            ) else {
                continue;
            };
            let scale = libm::sqrt(ceiling / variance);
            self.gnss_error.scale_cross_row(index, scale);
            for (column_index, column) in self.covariance.data.0.iter_mut().enumerate() {
                if column_index == index {
                    column.iter_mut().for_each(|value| *value *= scale);
                } else if let Some(value) = column.get_mut(index) {
                    *value *= scale;
                }
            }
            // The diagonal takes s² (row and column): exactly the ceiling.
            if let Some(entry) = self
                .covariance
                .data
                .0
                .get_mut(index)
                .and_then(|c| c.get_mut(index))
            {
                *entry = *ceiling;
            }
        }
        clamped
    }

    /// Time update with a discretised model.
    ///
    /// # Errors
    /// [`NavError::NonFiniteState`] if the result is not finite (filter unchanged).
    pub fn predict(&mut self, model: &DiscreteModel) -> Result<(), NavError> {
        let f = &model.transition;
        let covariance = symmetrised(&(f * self.covariance * f.transpose() + model.process_noise));
        let state = match self.mode {
            FilterMode::OpenLoop => f * self.state,
            FilterMode::ClosedLoop => self.state,
        };
        let mut gnss_error = self.gnss_error;
        let border_finite = gnss_error.propagate(model.interval_s, |column| f * column);
        if !(covariance.iter().all(|v| v.is_finite())
            && state.iter().all(|v| v.is_finite())
            && border_finite)
        {
            return Err(NavError::NonFiniteState);
        }
        self.covariance = covariance;
        self.state = state;
        self.gnss_error = gnss_error;
        Ok(())
    }

    /// Innovation, its covariance and NIS for `measurement`, without changing the filter.
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for NaN/Inf in the measurement,
    /// [`NavError::NonPositiveInnovationCovariance`] if `S` is not positive definite.
    pub fn innovation(
        &self,
        measurement: &LinearMeasurement,
    ) -> Result<InnovationReport, NavError> {
        check_measurement(measurement)?;
        let h = &measurement.jacobian;
        innovation_report(
            measurement.residual - h * self.state,
            &(h * self.covariance * h.transpose() + measurement.noise_covariance),
        )
    }

    /// Measurement update in Joseph form, gated: if the NIS exceeds `gate_nis` (a χ²(3)
    /// threshold, e.g. 11.34 for 1 % false rejection; `f64::INFINITY` disables the gate) the
    /// filter is left untouched and the report says `accepted: false`.
    ///
    /// # Errors
    /// As [`ErrorStateFilter::innovation`], plus [`NavError::NonFiniteInput`] for a NaN gate
    /// and [`NavError::NonFiniteState`] if the result is not finite; the filter is unchanged
    /// on any error.
    pub fn update(
        &mut self,
        measurement: &LinearMeasurement,
        gate_nis: f64,
    ) -> Result<InnovationReport, NavError> {
        self.update_with_frozen_blocks(measurement, gate_nis, &BlockMask::NONE)
    }

    /// [`ErrorStateFilter::update`] with the gain rows of the `frozen` blocks set to zero:
    /// their estimate does not move and, the Joseph form being valid for any gain, `P` stays
    /// the exact covariance of the suboptimal update (a "consider" update; Simon 2006,
    /// §7.5). The calibration manager freezes converged blocks this way.
    ///
    /// # Errors
    /// As [`ErrorStateFilter::update`].
    pub fn update_with_frozen_blocks(
        &mut self,
        measurement: &LinearMeasurement,
        gate_nis: f64,
        frozen: &BlockMask,
    ) -> Result<InnovationReport, NavError> {
        if gate_nis.is_nan() {
            // A NaN gate would silently accept everything (`nis > NaN` is false).
            return Err(NavError::NonFiniteInput);
        }
        if self.gnss_error.is_enabled() {
            return self.update_bordered_dense(measurement, gate_nis, frozen);
        }
        let mut report = self.innovation(measurement)?;
        if report.normalised_innovation_squared > gate_nis {
            return Ok(report);
        }
        let cholesky =
            Cholesky::new(report.covariance).ok_or(NavError::NonPositiveInnovationCovariance)?;
        let h = &measurement.jacobian;
        // K = P Hᵀ S⁻¹, computed as (S⁻¹ H P)ᵀ since S and P are symmetric.
        let mut gain: SMatrix<f64, STATE_DIMENSION, 3> =
            cholesky.solve(&(h * self.covariance)).transpose();
        if !frozen.is_empty() {
            for (state_index, mut row) in gain.row_iter_mut().enumerate() {
                if frozen.contains_state(state_index) {
                    row.fill(0.0);
                }
            }
        }
        let state = self.state + gain * report.innovation;
        let i_minus_kh = CovarianceMatrix::identity() - gain * h;
        let covariance = symmetrised(
            &(i_minus_kh * self.covariance * i_minus_kh.transpose()
                + gain * measurement.noise_covariance * gain.transpose()),
        );
        if !(covariance.iter().all(|v| v.is_finite()) && state.iter().all(|v| v.is_finite())) {
            return Err(NavError::NonFiniteState);
        }
        self.state = state;
        self.covariance = covariance;
        report.accepted = true;
        Ok(report)
    }

    /// [`ErrorStateFilter::update_with_frozen_blocks`] with the correlated GNSS error states:
    /// the dense 27-state Joseph update of [`crate::gnss_error`]'s model (the reference the
    /// structured border is tested against).
    fn update_bordered_dense(
        &mut self,
        measurement: &LinearMeasurement,
        gate_nis: f64,
        frozen: &BlockMask,
    ) -> Result<InnovationReport, NavError> {
        check_measurement(measurement)?;
        let border = &self.gnss_error;
        let (cross, border_covariance) = (border.cross_covariance(), border.covariance());
        let estimate = border.estimate_m();
        let at = |m: &CovarianceMatrix, i: usize, j: usize| m.get((i, j)).copied();
        let p = AugmentedCovariance::from_fn(|i, j| {
            let (n, value) = (STATE_DIMENSION, f64::NAN);
            match (i.checked_sub(n), j.checked_sub(n)) {
                (None, None) => at(&self.covariance, i, j),
                (None, Some(b)) => cross.get((i, b)).copied(),
                (Some(a), None) => cross.get((j, a)).copied(),
                (Some(a), Some(b)) => border_covariance.get((a, b)).copied(),
            }
            .unwrap_or(value)
        });
        let coefficient = measurement.gnss_error_coefficient;
        let h = SMatrix::<f64, 3, AUGMENTED_DIMENSION>::from_fn(|r, j| {
            match j.checked_sub(STATE_DIMENSION) {
                None => measurement
                    .jacobian
                    .get((r, j))
                    .copied()
                    .unwrap_or(f64::NAN),
                Some(a) if a == r => coefficient,
                Some(_) => 0.0,
            }
        });
        let x = SVector::<f64, AUGMENTED_DIMENSION>::from_fn(|i, _| {
            match i.checked_sub(STATE_DIMENSION) {
                None => self.state.get(i).copied(),
                Some(a) => estimate.get(a).copied(),
            }
            .unwrap_or(f64::NAN)
        });
        let mut report = innovation_report(
            measurement.residual - h * x,
            &(h * p * h.transpose() + measurement.noise_covariance),
        )?;
        if report.normalised_innovation_squared > gate_nis {
            return Ok(report);
        }
        let cholesky =
            Cholesky::new(report.covariance).ok_or(NavError::NonPositiveInnovationCovariance)?;
        let mut gain: SMatrix<f64, AUGMENTED_DIMENSION, 3> = cholesky.solve(&(h * p)).transpose();
        for (state_index, mut row) in gain.row_iter_mut().enumerate() {
            if state_index < STATE_DIMENSION && frozen.contains_state(state_index) {
                row.fill(0.0);
            }
        }
        let x = x + gain * report.innovation;
        let i_minus_kh = AugmentedCovariance::identity() - gain * h;
        let p = i_minus_kh * p * i_minus_kh.transpose()
            + gain * measurement.noise_covariance * gain.transpose();
        let p = (p + p.transpose()) * 0.5;
        if !(block::all_finite(p.as_slice()) && block::all_finite(x.as_slice())) {
            return Err(NavError::NonFiniteState);
        }
        let n = STATE_DIMENSION;
        self.covariance = CovarianceMatrix::from_fn(|i, j| at_augmented(&p, i, j));
        self.state = ErrorState::from_fn(|i, _| x.get(i).copied().unwrap_or(f64::NAN));
        self.gnss_error.set(
            &Vector3::from_fn(|a, _| x.get(n + a).copied().unwrap_or(f64::NAN)),
            &Matrix3::from_fn(|a, b| at_augmented(&p, n + a, n + b)),
            &SMatrix::from_fn(|i, a| at_augmented(&p, i, n + a)),
        );
        report.accepted = true;
        Ok(report)
    }

    /// Structured time update (the flight path): `P ← F P Fᵀ + Qd` and, in open loop,
    /// `x ← F x`, computed by blocks from a [`StructuredModel`] (derivation in
    /// [`crate::structured`]); equal to [`ErrorStateFilter::predict`] with the dense model
    /// of the same point within relative 1e-12.
    ///
    /// # Errors
    /// [`NavError::NonFiniteState`] if the result is not finite (filter unchanged).
    pub fn predict_structured(&mut self, model: &StructuredModel) -> Result<(), NavError> {
        let state = match self.mode {
            FilterMode::OpenLoop => {
                let state = model.propagate_state(&self.state);
                if !block::all_finite(state.as_slice()) {
                    return Err(NavError::NonFiniteState);
                }
                Some(state)
            }
            // Closed loop: x = 0 stays 0.
            FilterMode::ClosedLoop => None,
        };
        if self.gnss_error.is_enabled() {
            return self.predict_structured_bordered(model, state);
        }
        if !model.propagate_covariance(&mut self.covariance) {
            return Err(NavError::NonFiniteState);
        }
        if let Some(state) = state {
            self.state = state;
        }
        Ok(())
    }

    /// [`ErrorStateFilter::predict_structured`] with the correlated GNSS error states: the
    /// border's new values are computed first, so nothing changes on an error. Not inlined:
    /// their stack space is taken only when the states are in use.
    #[inline(never)]
    fn predict_structured_bordered(
        &mut self,
        model: &StructuredModel,
        state: Option<ErrorState>,
    ) -> Result<(), NavError> {
        let dynamic = model.propagate_rows(self.gnss_error.cross_rows());
        let propagated = self
            .gnss_error
            .propagated(model.interval_s(), &dynamic)
            .ok_or(NavError::NonFiniteState)?;
        if !model.propagate_covariance(&mut self.covariance) {
            return Err(NavError::NonFiniteState);
        }
        if let Some(state) = state {
            self.state = state;
        }
        self.gnss_error.commit_propagation(&propagated);
        Ok(())
    }

    /// Structured measurement update (the flight path): the same gated, frozen-block
    /// Joseph-form update as [`ErrorStateFilter::update_with_frozen_blocks`], with `P Hᵀ`
    /// summed over the non-zero 3×3 blocks of `H` only, a 3×3 Cholesky of `S`, and the Joseph
    /// form expanded to O(n²) in place (derivation in [`crate::structured`]); equal to the
    /// dense update within relative 1e-12.
    ///
    /// # Errors
    /// As [`ErrorStateFilter::update_with_frozen_blocks`]; the filter is unchanged on any
    /// error.
    pub fn update_structured(
        &mut self,
        measurement: &LinearMeasurement,
        gate_nis: f64,
        frozen: &BlockMask,
    ) -> Result<InnovationReport, NavError> {
        if gate_nis.is_nan() {
            return Err(NavError::NonFiniteInput);
        }
        check_measurement(measurement)?;
        let h = &measurement.jacobian;
        // H P = Mᵀ and H P Hᵀ, over the non-zero blocks of H.
        // The correlated GNSS error states' border (crate::gnss_error), when in use.
        let coefficient = measurement.gnss_error_coefficient;
        let border = self
            .gnss_error
            .is_enabled()
            .then(|| self.gnss_error.border(h, coefficient));
        let observed = structured::ObservedCovariance::new(
            h,
            &self.covariance,
            border
                .as_ref()
                .map(|border| (self.gnss_error.cross_rows(), border)),
        );
        let mut innovation = measurement.residual - h * self.state;
        if border.is_some() {
            innovation -= self.gnss_error.predicted_residual(coefficient);
        }
        let covariance = symmetrised3(&(observed.projected() + measurement.noise_covariance));
        let cholesky = structured::Cholesky3::new(&covariance)
            .ok_or(NavError::NonPositiveInnovationCovariance)?;
        // NIS = νᵀ S⁻¹ ν = |L⁻¹ ν|².
        let whitened = Vector3::from(cholesky.whiten([innovation.x, innovation.y, innovation.z]));
        let nis = whitened.norm_squared();
        if !nis.is_finite() {
            return Err(NavError::NonPositiveInnovationCovariance);
        }
        let mut report = InnovationReport {
            innovation,
            covariance,
            normalised_innovation_squared: nis,
            accepted: false,
        };
        if nis > gate_nis {
            return Ok(report);
        }
        // K = P Hᵀ S⁻¹ by state blocks, frozen blocks' gain zero.
        let gains = observed.gain(&cholesky, frozen);
        let mut state = self.state;
        structured::add_gain_times(&mut state, &gains, &innovation);
        if !block::all_finite(state.as_slice()) {
            return Err(NavError::NonFiniteState);
        }
        if let Some(border) = &border {
            let solved = (&cholesky, &covariance);
            self.update_border_and_covariance(border, &gains, &observed, solved, &innovation)?;
        } else if !structured::joseph_update(&mut self.covariance, &gains, &observed, &covariance) {
            return Err(NavError::NonFiniteState);
        }
        self.state = state;
        report.accepted = true;
        Ok(report)
    }

    /// The covariance part of [`ErrorStateFilter::update_structured`] with the correlated
    /// GNSS error states: the border's new values first (its new `C` into its spare buffer),
    /// then the 24-state Joseph kernel with the bordered `M` and `S`, then the border
    /// committed; nothing changes on an error.
    ///
    /// # Errors
    /// [`NavError::NonFiniteState`] if a result is not finite.
    #[inline(never)]
    fn update_border_and_covariance(
        &mut self,
        border: &crate::gnss_error::Border,
        gains: &structured::StateRows,
        observed: &structured::ObservedCovariance,
        (cholesky, s): (&structured::Cholesky3, &Matrix3<f64>),
        innovation: &Vector3<f64>,
    ) -> Result<(), NavError> {
        let (estimate, border_covariance) = self
            .gnss_error
            .updated(
                border,
                (gains, observed.products()),
                |row| cholesky.solve(row),
                block::from_vector(innovation),
            )
            .ok_or(NavError::NonFiniteState)?;
        if !structured::joseph_update(&mut self.covariance, gains, observed, s) {
            return Err(NavError::NonFiniteState);
        }
        self.gnss_error.commit(estimate, &border_covariance);
        Ok(())
    }

    /// Closed-loop reset: returns the error state to feed back (see [`apply_error_state`]),
    /// zeroes `x` and applies the reset Jacobian to `P` (module docs), by blocks and in
    /// place: only the attitude and installation block rows and columns change
    /// ([`crate::structured`]).
    pub fn reset(&mut self) -> ErrorState {
        let error = self.state;
        let [attitude, installation] =
            [ATTITUDE, STAR_INSTALLATION].map(|block| reset_jacobian_block(&error, block));
        structured::reset_covariance(&mut self.covariance, &attitude, &installation);
        if self.gnss_error.is_enabled() {
            self.gnss_error.reset(
                &block::from_matrix(&attitude),
                &block::from_matrix(&installation),
            );
        }
        self.state = ErrorState::zeros();
        error
    }

    /// [`ErrorStateFilter::reset`] with the dense 24×24 `J P Jᵀ` (the reference for tests and
    /// benchmarks).
    pub fn reset_dense(&mut self) -> ErrorState {
        let error = self.state;
        let mut jacobian = CovarianceMatrix::identity();
        for block in [ATTITUDE, STAR_INSTALLATION] {
            set_block(
                &mut jacobian,
                block,
                block,
                &reset_jacobian_block(&error, block),
            );
        }
        self.covariance = symmetrised(&(jacobian * self.covariance * jacobian.transpose()));
        let block_of_jacobian = |block: StateBlock| {
            block::from_matrix(&jacobian.fixed_view::<3, 3>(block.index, block.index).into())
        };
        self.gnss_error.reset(
            &block_of_jacobian(ATTITUDE),
            &block_of_jacobian(STAR_INSTALLATION),
        );
        self.state = ErrorState::zeros();
        error
    }

    /// In open loop, the current estimate of the error of one block (for reporting).
    pub fn block(&self, block: StateBlock) -> Vector3<f64> {
        block_of(&self.state, block)
    }

    /// Indices of the blocks, for reports (re-export of the state layout).
    pub fn blocks() -> &'static [StateBlock; 8] {
        &BLOCKS
    }
}

/// The paper's 24 states and the three correlated GNSS error states ([`crate::gnss_error`]).
const AUGMENTED_DIMENSION: usize = STATE_DIMENSION + 3;

/// The 27-state covariance of the dense bordered reference.
type AugmentedCovariance = SMatrix<f64, AUGMENTED_DIMENSION, AUGMENTED_DIMENSION>;

/// Element `(i, j)` of a 27-state covariance (NaN outside, which callers never reach).
fn at_augmented(p: &AugmentedCovariance, i: usize, j: usize) -> f64 {
    p.get((i, j)).copied().unwrap_or(f64::NAN)
}

/// [`NavError::NonFiniteInput`] for NaN/Inf in a measurement's residual, `H` or `R`.
fn check_measurement(measurement: &LinearMeasurement) -> Result<(), NavError> {
    // One multiply-add per value ([`block::all_finite`]): the 84 values cost ~250
    // instructions on the target instead of ~1,100 with `is_finite` per value.
    let finite = block::all_finite(measurement.residual.as_slice())
        && block::all_finite(measurement.jacobian.as_slice())
        && block::all_finite(measurement.noise_covariance.as_slice());
    if finite {
        Ok(())
    } else {
        Err(NavError::NonFiniteInput)
    }
}

/// The report for innovation `ν` and `S` (symmetrised here): NIS `νᵀ S⁻¹ ν` by Cholesky.
fn innovation_report(
    innovation: Vector3<f64>,
    covariance: &Matrix3<f64>,
) -> Result<InnovationReport, NavError> {
    let covariance = symmetrised3(covariance);
    let cholesky = Cholesky::new(covariance).ok_or(NavError::NonPositiveInnovationCovariance)?;
    let whitened = cholesky.solve(&innovation);
    let nis = innovation.dot(&whitened);
    if !(nis.is_finite() && nis >= 0.0) {
        return Err(NavError::NonPositiveInnovationCovariance);
    }
    Ok(InnovationReport {
        innovation,
        covariance,
        normalised_innovation_squared: nis,
        accepted: false,
    })
}

/// The reset Jacobian's diagonal block `I − [x̂×]` of an attitude-like `block` (module docs).
fn reset_jacobian_block(error: &ErrorState, block: StateBlock) -> Matrix3<f64> {
    Matrix3::identity() - skew(&block_of(error, block))
}

fn symmetrised(matrix: &CovarianceMatrix) -> CovarianceMatrix {
    (matrix + matrix.transpose()) * 0.5
}

fn symmetrised3(matrix: &Matrix3<f64>) -> Matrix3<f64> {
    (matrix + matrix.transpose()) * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measurement::MeasurementJacobian;

    fn config(mode: FilterMode) -> FilterConfig {
        FilterConfig {
            mode,
            discretisation_order: 3,
            initial: InitialUncertainty {
                attitude_rad: 1e-2,
                position_m: 100.0,
                velocity_mps: 1.0,
                gyro_bias_rad_s: 1e-3,
                accel_bias_mps2: 1e-2,
                star_installation_rad: 1e-2,
                gyro_scale_factor: 1e-4,
                accel_scale_factor: 1e-4,
            },
            gnss_error: crate::gnss_error::GnssErrorModel::WHITE,
        }
    }

    fn position_measurement(residual: Vector3<f64>, sigma: f64) -> LinearMeasurement {
        let mut jacobian = MeasurementJacobian::zeros();
        jacobian
            .fixed_view_mut::<3, 3>(0, POSITION.index)
            .fill_with_identity();
        LinearMeasurement {
            residual,
            jacobian,
            noise_covariance: Matrix3::identity() * sigma * sigma,
            gnss_error_coefficient: 1.0,
        }
    }

    #[test]
    fn scalar_update_matches_the_closed_form_posterior() {
        let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
        let report = filter
            .update(
                &position_measurement(Vector3::new(30.0, -10.0, 5.0), 10.0),
                f64::INFINITY,
            )
            .unwrap();
        assert!(report.accepted);
        // prior σ² = 1e4, R = 1e2: posterior mean z·σ²/(σ²+R), variance σ²R/(σ²+R).
        let gain = 1e4 / (1e4 + 1e2);
        assert!((filter.state()[POSITION.index] - 30.0 * gain).abs() < 1e-12);
        assert!(
            (filter.covariance()[(POSITION.index, POSITION.index)] - 1e4 * 1e2 / (1e4 + 1e2)).abs()
                < 1e-9
        );
        let expected_nis = (30.0f64.powi(2) + 10.0f64.powi(2) + 5.0f64.powi(2)) / (1e4 + 1e2);
        assert!((report.normalised_innovation_squared - expected_nis).abs() < 1e-12);
        // Unobserved blocks keep their prior.
        assert_eq!(
            filter.covariance()[(VELOCITY.index, VELOCITY.index)].to_bits(),
            1.0f64.to_bits()
        );
        assert_eq!(filter.covariance(), &filter.covariance().transpose());
        assert!(Cholesky::new(*filter.covariance()).is_some());
    }

    /// Every initial 1σ must be finite and strictly positive: zero, negative and non-finite
    /// values are refused, each for every state block.
    #[test]
    fn initial_sigmas_must_be_finite_and_positive() {
        assert_eq!(config(FilterMode::ClosedLoop).validate(), Ok(()));
        let setters: [fn(&mut InitialUncertainty, f64); 8] = [
            |u, v| u.attitude_rad = v,
            |u, v| u.position_m = v,
            |u, v| u.velocity_mps = v,
            |u, v| u.gyro_bias_rad_s = v,
            |u, v| u.accel_bias_mps2 = v,
            |u, v| u.star_installation_rad = v,
            |u, v| u.gyro_scale_factor = v,
            |u, v| u.accel_scale_factor = v,
        ];
        for set in setters {
            for bad in [0.0, -1e-3, f64::INFINITY, f64::NAN] {
                let mut bad_config = config(FilterMode::ClosedLoop);
                set(&mut bad_config.initial, bad);
                assert_eq!(bad_config.validate(), Err(NavError::InvalidConfiguration));
            }
        }
    }

    #[test]
    fn a_gated_measurement_leaves_the_filter_bit_identical() {
        let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
        let before = filter;
        let report = filter
            .update(
                &position_measurement(Vector3::new(5000.0, 0.0, 0.0), 10.0),
                11.34,
            )
            .unwrap();
        assert!(!report.accepted);
        assert!(report.normalised_innovation_squared > 11.34);
        assert_eq!(filter, before);
    }

    #[test]
    fn bad_measurements_are_typed_errors_and_change_nothing() {
        let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
        let before = filter;
        let nan = position_measurement(Vector3::new(f64::NAN, 0.0, 0.0), 10.0);
        assert_eq!(
            filter.update(&nan, f64::INFINITY),
            Err(NavError::NonFiniteInput)
        );
        let mut negative = position_measurement(Vector3::zeros(), 10.0);
        negative.noise_covariance = Matrix3::identity() * -2e4;
        assert_eq!(
            filter.update(&negative, f64::INFINITY),
            Err(NavError::NonPositiveInnovationCovariance)
        );
        assert_eq!(filter, before);
        let mut bad = config(FilterMode::OpenLoop);
        bad.initial.gyro_bias_rad_s = f64::NAN;
        assert_eq!(
            ErrorStateFilter::new(&bad),
            Err(NavError::InvalidConfiguration)
        );
        bad = config(FilterMode::OpenLoop);
        bad.discretisation_order = 7;
        assert_eq!(
            ErrorStateFilter::new(&bad),
            Err(NavError::InvalidDiscretisationOrder)
        );
    }

    #[test]
    fn closed_loop_reset_zeroes_the_state_and_applies_the_reset_jacobian() {
        let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
        let mut jacobian = MeasurementJacobian::zeros();
        jacobian
            .fixed_view_mut::<3, 3>(0, ATTITUDE.index)
            .fill_with_identity();
        let measurement = LinearMeasurement {
            residual: Vector3::new(2e-3, -1e-3, 3e-3),
            jacobian,
            noise_covariance: Matrix3::identity() * 1e-10,
            gnss_error_coefficient: 0.0,
        };
        filter.update(&measurement, f64::INFINITY).unwrap();
        let covariance_before = *filter.covariance();
        let error = filter.reset();
        assert_eq!(filter.state(), &ErrorState::zeros());
        let theta = error.fixed_rows::<3>(ATTITUDE.index).into_owned();
        let g = Matrix3::identity() - skew(&theta);
        let expected = g * covariance_before.fixed_view::<3, 3>(0, 0) * g.transpose();
        assert!((filter.covariance().fixed_view::<3, 3>(0, 0) - expected).amax() < 1e-20);

        let mut attitude = Quaternion::new(1.0, 0.0, 0.0, 0.0);
        let mut position = Vector3::zeros();
        let mut velocity = Vector3::zeros();
        let mut calibration = CalibrationEstimate::default();
        apply_error_state(
            &error,
            &mut attitude,
            &mut position,
            &mut velocity,
            &mut calibration,
        )
        .unwrap();
        assert!(
            (attitude.imag() - theta).amax() < 1e-12,
            "{attitude:?} vs {theta:?}"
        );
    }

    #[test]
    fn a_frozen_block_keeps_its_estimate_and_the_covariance_stays_exact() {
        // Correlate position with the accelerometer scale factor, then observe position with
        // that block frozen: the frozen estimate must not move, the unfrozen one must, and P
        // must equal the Joseph-form covariance (I − K H) P (I − K H)ᵀ + K R Kᵀ of the
        // zero-row gain, computed here independently.
        let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
        let mut covariance = *filter.covariance();
        let cross = 0.5 * libm::sqrt(1e4 * 1e-8);
        for axis in 0..3 {
            covariance[(POSITION.index + axis, ACCEL_SCALE_FACTOR.index + axis)] = cross;
            covariance[(ACCEL_SCALE_FACTOR.index + axis, POSITION.index + axis)] = cross;
        }
        filter.set_covariance(&covariance).unwrap();
        let prior = *filter.covariance();
        let measurement = position_measurement(Vector3::new(30.0, -10.0, 5.0), 10.0);
        let mut frozen = BlockMask::NONE;
        frozen.insert(ACCEL_SCALE_FACTOR);
        let mut free = filter;
        free.update(&measurement, f64::INFINITY).unwrap();
        assert!(free.block(ACCEL_SCALE_FACTOR).norm() > 1e-6);
        filter
            .update_with_frozen_blocks(&measurement, f64::INFINITY, &frozen)
            .unwrap();
        assert_eq!(filter.block(ACCEL_SCALE_FACTOR), Vector3::zeros());
        assert!((filter.block(POSITION) - free.block(POSITION)).norm() < 1e-12);
        let h = measurement.jacobian;
        let s = h * prior * h.transpose() + measurement.noise_covariance;
        let mut gain = prior * h.transpose() * s.try_inverse().unwrap();
        gain.fixed_rows_mut::<3>(ACCEL_SCALE_FACTOR.index).fill(0.0);
        let i_kh = CovarianceMatrix::identity() - gain * h;
        let expected = i_kh * prior * i_kh.transpose()
            + gain * measurement.noise_covariance * gain.transpose();
        assert!((filter.covariance() - expected).amax() < 1e-9 * expected.amax());
        // Freezing costs information: the frozen block keeps its prior variance.
        let variance = filter.covariance()[(ACCEL_SCALE_FACTOR.index, ACCEL_SCALE_FACTOR.index)];
        assert!((variance - 1e-8).abs() < 1e-20);
    }

    #[test]
    fn a_nan_gate_is_an_error_not_an_open_gate() {
        let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
        let before = filter;
        assert_eq!(
            filter.update(&position_measurement(Vector3::zeros(), 10.0), f64::NAN),
            Err(NavError::NonFiniteInput)
        );
        assert_eq!(filter, before);
    }

    /// Vector part of `q̂* ⊗ q` (the body-frame error of `q̂` with respect to `q`).
    fn body_error(estimate: &Quaternion<f64>, truth: &Quaternion<f64>) -> Vector3<f64> {
        attitude::canonical(&attitude::product(&attitude::conjugate(estimate), truth)).imag()
    }

    #[test]
    fn reset_jacobian_matches_the_nonlinear_reset() {
        // The filter estimates ϑ̂; the true error is ϑ = ϑ̂ + e (e the estimation error, the
        // random variable P describes). After q̂⁺ = q̂ ⊗ δq(ϑ̂) the new error is
        // ϑ⁺ = vec(q̂⁺* ⊗ q) ≈ (I − [ϑ̂×]) e. Checked through apply_error_state for both the
        // attitude and the installation blocks: the mismatch is O(|ϑ̂|²|e| + |e|²), far below
        // the O(|ϑ̂||e|) error of a plain identity reset.
        let estimated = Vector3::new(2e-3, -1.5e-3, 3e-3);
        let attitude_estimate = attitude::exp_rotation_vector(&Vector3::new(0.3, -0.7, 1.1));
        let installation_estimate = attitude::exp_rotation_vector(&Vector3::new(1e-3, 2e-3, -1e-3));
        let g = Matrix3::identity() - skew(&estimated);
        for block in [ATTITUDE, STAR_INSTALLATION] {
            let mut state = ErrorState::zeros();
            state.fixed_rows_mut::<3>(block.index).copy_from(&estimated);
            for e_scale in [1e-4, 0.5e-4] {
                let e = Vector3::new(0.7, 1.0, -0.4) * e_scale;
                let true_error = attitude::from_vector_part(&(estimated + e)).unwrap();
                let mut attitude_now = attitude_estimate;
                let mut calibration = CalibrationEstimate::default();
                let [w, x, y, z] = [
                    installation_estimate.w,
                    installation_estimate.i,
                    installation_estimate.j,
                    installation_estimate.k,
                ];
                calibration.star_installation_wxyz = [w, x, y, z];
                let base = if block == ATTITUDE {
                    attitude_estimate
                } else {
                    installation_estimate
                };
                let truth = attitude::product(&base, &true_error);
                apply_error_state(
                    &state,
                    &mut attitude_now,
                    &mut Vector3::zeros(),
                    &mut Vector3::zeros(),
                    &mut calibration,
                )
                .unwrap();
                let corrected = if block == ATTITUDE {
                    attitude_now
                } else {
                    let [w, x, y, z] = calibration.star_installation_wxyz;
                    Quaternion::new(w, x, y, z)
                };
                let new_error = body_error(&corrected, &truth);
                let with_jacobian = (new_error - g * e).amax();
                let with_identity = (new_error - e).amax();
                let bound = 3.0 * (estimated.norm_squared() * e.norm() + e.norm_squared());
                println!(
                    "{} reset, |e| = {:.1e}: mismatch with I − [ϑ̂×] {with_jacobian:.3e}, with I {with_identity:.3e}",
                    block.name,
                    e.norm()
                );
                assert!(
                    with_jacobian < bound,
                    "{}: {with_jacobian:e} vs {bound:e}",
                    block.name
                );
                assert!(with_jacobian < 0.01 * with_identity, "{}", block.name);
            }
        }
    }

    #[test]
    fn joseph_form_keeps_p_symmetric_and_positive_definite_under_precise_measurements() {
        use crate::discretise::discretise;
        use crate::error_model::{
            noise_input_matrix, system_matrix, LinearisationPoint, ProcessNoise,
        };
        use crate::measurement::{gnss_position, star_sensor};
        // Paper motion state II plus an acceleration, 2 ms steps, star and GNSS updates far
        // more precise than the prior (R/HPHᵀ down to 1e-14), the ill-conditioned regime
        // the Joseph form is chosen for.
        let q_ib = attitude::exp_rotation_vector(&Vector3::new(0.2, 0.4, -0.1));
        let point = LinearisationPoint {
            corrected_rate_rad_s: Vector3::new(0.0, 0.0, 10.0f64.to_radians()),
            corrected_specific_force_mps2: Vector3::new(0.0, 20.0, 0.0),
            measured_rate_rad_s: Vector3::new(0.0, 0.0, 10.0f64.to_radians()),
            measured_specific_force_mps2: Vector3::new(0.0, 20.0, 0.0),
            body_to_inertial: attitude::rotation_matrix(&q_ib),
            gravity_gradient_per_s2: Matrix3::zeros(),
        };
        let model = discretise(
            &system_matrix(&point),
            &noise_input_matrix(&point),
            &ProcessNoise::PAPER.spectral_density_diagonal(),
            0.002,
            3,
        )
        .unwrap();
        let mounting = attitude::exp_rotation_vector(&Vector3::new(0.4, -1.1, 0.25));
        let identity = Quaternion::new(1.0, 0.0, 0.0, 0.0);
        let star = star_sensor(&q_ib, &mounting, &identity, &q_ib, 1e-9).unwrap();
        let gnss = gnss_position(
            &q_ib,
            &Vector3::zeros(),
            &Vector3::new(1.5, -0.4, 2.0),
            &Vector3::new(0.1, 0.0, 0.0),
            1e-4,
        )
        .unwrap();
        let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
        let mut smallest_pivot = f64::INFINITY;
        for step in 0..300 {
            filter.predict(&model).unwrap();
            if step % 10 == 0 {
                filter.update(&star, f64::INFINITY).unwrap();
                filter.update(&gnss, f64::INFINITY).unwrap();
                let p = filter.covariance();
                assert_eq!(p, &p.transpose(), "step {step}");
                let cholesky = Cholesky::new(*p).expect("P positive definite");
                let pivot = cholesky.l().diagonal().min();
                smallest_pivot = smallest_pivot.min(pivot);
                assert!(pivot > 0.0, "step {step}");
                // What GNSS observes (antenna position δp − 2Ĉ[ℓ×]ϑ; δp alone stays as
                // uncertain as attitude × lever arm, since the star sensor only sees ϑ
                // together with the installation error) collapses to its 1e-4 m precision.
                let h = &gnss.jacobian;
                let observed = (h * p * h.transpose()).diagonal().max();
                assert!(observed < 1.01e-8, "step {step}: {observed}");
            }
        }
        println!("smallest Cholesky pivot of P over 30 precise update pairs: {smallest_pivot:.3e}");
    }

    #[test]
    fn open_loop_prediction_propagates_the_state() {
        let mut filter = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
        filter
            .update(
                &position_measurement(Vector3::new(30.0, 0.0, 0.0), 10.0),
                f64::INFINITY,
            )
            .unwrap();
        let mut transition = CovarianceMatrix::identity() * 2.0;
        transition[(0, 0)] = 1.0;
        let model = DiscreteModel {
            transition,
            process_noise: CovarianceMatrix::zeros(),
            interval_s: 0.1,
        };
        let before = filter.state()[POSITION.index];
        filter.predict(&model).unwrap();
        assert_eq!(
            filter.state()[POSITION.index].to_bits(),
            (2.0 * before).to_bits()
        );
    }

    #[test]
    fn protection_puts_a_variance_at_its_ceiling_and_keeps_correlations() {
        let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
        let mut covariance = CovarianceMatrix::identity();
        covariance[(0, 0)] = 4.0;
        covariance[(0, 1)] = 1.0;
        covariance[(1, 0)] = 1.0;
        filter.set_covariance(&covariance).unwrap();
        let correlation = |p: &CovarianceMatrix| p[(0, 1)] / (p[(0, 0)] * p[(1, 1)]).sqrt();
        let before = correlation(filter.covariance());
        let floor = ErrorState::repeat(0.5);
        let mut ceiling = ErrorState::repeat(10.0);
        ceiling[0] = 1.0;
        assert!(filter.protect_variances(&floor, &ceiling));
        let p = filter.covariance();
        assert_eq!(p[(0, 0)].to_bits(), 1.0_f64.to_bits());
        assert!((correlation(p) - before).abs() < 1e-15);
        assert_eq!(p[(0, 1)].to_bits(), p[(1, 0)].to_bits());
        assert!(p.cholesky().is_some());
        // Within the bounds: nothing changes.
        assert!(!filter.protect_variances(&floor, &ceiling));
    }

    /// A variance below its floor is raised to it (only the diagonal changes); one exactly
    /// at its floor or ceiling is inside the bounds and reported as unchanged.
    #[test]
    fn protection_raises_a_variance_to_its_floor_and_leaves_the_bounds_alone() {
        let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
        let mut covariance = CovarianceMatrix::identity();
        covariance[(3, 3)] = 0.25;
        covariance[(3, 4)] = 0.1;
        covariance[(4, 3)] = 0.1;
        filter.set_covariance(&covariance).unwrap();
        let floor = ErrorState::repeat(0.5);
        let ceiling = ErrorState::repeat(1.0);
        assert!(filter.protect_variances(&floor, &ceiling));
        let p = *filter.covariance();
        assert_eq!(p[(3, 3)].to_bits(), 0.5_f64.to_bits());
        assert_eq!(p[(3, 4)].to_bits(), 0.1_f64.to_bits());
        // Every variance now at a bound (0.5 or 1.0): inside, nothing to do.
        assert!(!filter.protect_variances(&floor, &ceiling));
        assert_eq!(filter.covariance().map(f64::to_bits), p.map(f64::to_bits));
    }

    /// 1σ is the square root of each variance.
    #[test]
    fn standard_deviations_are_the_roots_of_the_variances() {
        let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
        let covariance = CovarianceMatrix::from_diagonal(&ErrorState::from_fn(|i, _| {
            ((i + 1) * (i + 1)) as f64
        }));
        filter.set_covariance(&covariance).unwrap();
        let sigmas = filter.standard_deviations();
        for (index, sigma) in sigmas.iter().enumerate() {
            assert_eq!(sigma.to_bits(), ((index + 1) as f64).to_bits());
        }
    }

    /// A measurement whose NIS equals the gate exactly is accepted (the gate refuses only
    /// what lies beyond it), by the dense and the structured update alike; a hair above it
    /// is refused.
    #[test]
    fn the_gate_refuses_only_beyond_its_value() {
        let measurement = position_measurement(Vector3::new(30.0, -10.0, 5.0), 10.0);
        let none = BlockMask::NONE;
        let fresh = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
        type Update = fn(
            &mut ErrorStateFilter,
            &LinearMeasurement,
            f64,
            &BlockMask,
        ) -> Result<InnovationReport, NavError>;
        let updates: [Update; 2] = [
            ErrorStateFilter::update_with_frozen_blocks,
            ErrorStateFilter::update_structured,
        ];
        for update in updates {
            // This implementation's own NIS (its round-off), then the gate exactly there.
            let nis = update(&mut { fresh }, &measurement, f64::INFINITY, &none)
                .unwrap()
                .normalised_innovation_squared;
            for (gate, accepted) in [(nis, true), (nis * (1.0 - 1e-12), false)] {
                let report = update(&mut { fresh }, &measurement, gate, &none).unwrap();
                assert_eq!(report.accepted, accepted);
            }
        }
    }

    /// A dense prediction whose covariance overflows is refused and changes nothing, even
    /// though the (zero, closed-loop) state stays finite.
    #[test]
    fn an_overflowing_dense_prediction_changes_nothing() {
        let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
        filter
            .set_covariance(&CovarianceMatrix::from_element(f64::MAX))
            .unwrap();
        let before = filter;
        let model = DiscreteModel {
            transition: CovarianceMatrix::identity() * 2.0,
            process_noise: CovarianceMatrix::zeros(),
            interval_s: 0.1,
        };
        assert_eq!(filter.predict(&model), Err(NavError::NonFiniteState));
        assert_eq!(
            filter.covariance().map(f64::to_bits),
            before.covariance().map(f64::to_bits)
        );
    }

    /// The structured prediction in open loop propagates the state as the dense one does.
    #[test]
    fn open_loop_structured_prediction_propagates_the_state() {
        use crate::error_model::{LinearisationPoint, ProcessNoise};
        let mut structured = ErrorStateFilter::new(&config(FilterMode::OpenLoop)).unwrap();
        structured
            .update(
                &position_measurement(Vector3::new(30.0, -10.0, 5.0), 10.0),
                f64::INFINITY,
            )
            .unwrap();
        let mut dense = structured;
        let point = LinearisationPoint {
            corrected_rate_rad_s: Vector3::new(0.01, -0.02, 0.03),
            corrected_specific_force_mps2: Vector3::new(1.0, 0.5, -9.0),
            measured_rate_rad_s: Vector3::new(0.01, -0.02, 0.03),
            measured_specific_force_mps2: Vector3::new(1.0, 0.5, -9.0),
            body_to_inertial: Matrix3::identity(),
            gravity_gradient_per_s2: Matrix3::identity() * -1.5e-6,
        };
        let model = StructuredModel::new(&point, &ProcessNoise::PAPER, 0.002, 3).unwrap();
        structured.predict_structured(&model).unwrap();
        let dense_model = crate::discretise::discretise(
            &crate::error_model::system_matrix(&point),
            &crate::error_model::noise_input_matrix(&point),
            &ProcessNoise::PAPER.spectral_density_diagonal(),
            0.002,
            3,
        )
        .unwrap();
        dense.predict(&dense_model).unwrap();
        let difference = (structured.state() - dense.state()).norm();
        assert!(difference <= 1e-12 * dense.state().norm(), "{difference:e}");
        assert!(structured.state()[VELOCITY.index].abs() > 0.0);
    }

    /// A finite innovation whose NIS overflows is an error, not a report with an infinite
    /// NIS (dense path).
    #[test]
    fn an_overflowing_nis_is_an_error() {
        let mut filter = ErrorStateFilter::new(&config(FilterMode::ClosedLoop)).unwrap();
        let measurement = position_measurement(Vector3::new(1e200, 0.0, 0.0), 10.0);
        assert_eq!(
            filter.innovation(&measurement).map(|r| r.accepted),
            Err(NavError::NonPositiveInnovationCovariance)
        );
        assert_eq!(
            filter.update(&measurement, 16.0).map(|r| r.accepted),
            Err(NavError::NonPositiveInnovationCovariance)
        );
    }
}
