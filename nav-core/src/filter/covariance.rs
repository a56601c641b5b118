//! Changes to the covariance from outside the filter's steps: process noise the discrete model
//! does not hold, its replacement, the variance floor and ceiling, and a block's widening.

use nalgebra::Matrix3;

use super::{check_block_covariance, symmetrised, ErrorState, ErrorStateFilter, FilterConfig};
use crate::discretise::CovarianceMatrix;
use crate::gnss_error::GnssErrorStates;
use crate::state::{StateBlock, DYNAMIC_DIMENSION, STATE_DIMENSION};
use crate::NavError;

impl ErrorStateFilter {
    /// Adds `variance · I` to the diagonal block of `block` (m², rad², … in the block's
    /// units): process noise the discrete model does not contain, such as the error of a
    /// held IMU sample. `P` stays symmetric positive definite. The isotropic case of
    /// [`ErrorStateFilter::add_block_covariance`], with a loop of its own over the diagonal:
    /// written through that function it costs more in the worst frame on the Cortex-M7
    /// (QEMU replay).
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a negative or non-finite variance; nothing changes
    /// then.
    ///
    /// # Examples
    /// ```
    /// use nav_core::filter::{ErrorStateFilter, FilterConfig, FilterMode, InitialUncertainty};
    /// use nav_core::gnss_error::GnssErrorModel;
    /// use nav_core::imu_error_states::ImuErrorModel;
    /// use nav_core::state::VELOCITY;
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig { mode: FilterMode::ClosedLoop, discretisation_order: 3,
    ///     initial, gnss_error: GnssErrorModel::WHITE, imu_error: ImuErrorModel::DISABLED };
    /// let mut filter = ErrorStateFilter::new(&config).unwrap();
    /// filter.add_block_variance(VELOCITY, 0.03).unwrap();
    /// assert!((filter.covariance()[(VELOCITY.index(), VELOCITY.index())] - 0.04).abs() < 1e-15);
    /// ```
    pub fn add_block_variance(&mut self, block: StateBlock, variance: f64) -> Result<(), NavError> {
        if !(variance.is_finite() && variance >= 0.0) {
            return Err(NavError::NonFiniteInput);
        }
        for index in block.index()..block.index().saturating_add(block.dimension()) {
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
    /// use nav_core::imu_error_states::ImuErrorModel;
    /// use nav_core::state::ATTITUDE;
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig { mode: FilterMode::ClosedLoop, discretisation_order: 3,
    ///     initial, gnss_error: GnssErrorModel::WHITE, imu_error: ImuErrorModel::DISABLED };
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
        check_block_covariance(covariance)?;
        self.add_symmetric_part(block, covariance);
        Ok(())
    }

    /// Adds the symmetric part of `covariance` to the diagonal block of `block` (checked by
    /// [`check_block_covariance`]).
    pub(super) fn add_symmetric_part(&mut self, block: StateBlock, covariance: &Matrix3<f64>) {
        let symmetric = (covariance + covariance.transpose()) * 0.5;
        for (row, values) in symmetric.row_iter().enumerate() {
            for (column, value) in values.iter().enumerate() {
                if let Some(entry) = self
                    .covariance
                    .data
                    .0
                    .get_mut(block.index().saturating_add(column))
                    .and_then(|entries| entries.get_mut(block.index().saturating_add(row)))
                {
                    *entry += value;
                }
            }
        }
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
        // iterators and checked 2-D indexing cost several times as much on the target).
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
            self.scale_state_uncertainty(index, crate::float::sqrt(ceiling / variance));
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

    /// Widens the uncertainty of `block` by `variance_factor`: `P' = S P S` with
    /// `S = diag(1, …, √f I₃, …, 1)` on the block's rows and columns (its cross-covariance
    /// with the receiver's correlated error included). Every correlation coefficient and
    /// positive definiteness are kept, and the block's variances grow by `f`: the reaction to
    /// innovations larger than the filter claims, when the error they show is the inertial
    /// solution's (nav-fsw's fault logic).
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a factor below 1 or non-finite; nothing changes then.
    ///
    /// # Examples
    /// ```
    /// use nav_core::filter::{ErrorStateFilter, FilterConfig, FilterMode, InitialUncertainty};
    /// use nav_core::gnss_error::GnssErrorModel;
    /// use nav_core::imu_error_states::ImuErrorModel;
    /// use nav_core::state::GYRO_BIAS;
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig { mode: FilterMode::ClosedLoop, discretisation_order: 3,
    ///     initial, gnss_error: GnssErrorModel::WHITE, imu_error: ImuErrorModel::DISABLED };
    /// let mut filter = ErrorStateFilter::new(&config).unwrap();
    /// filter.widen_block_uncertainty(GYRO_BIAS, 4.0).unwrap();
    /// let index = GYRO_BIAS.index();
    /// assert!((filter.covariance()[(index, index)] - 4e-6).abs() < 1e-18);
    /// assert!(filter.widen_block_uncertainty(GYRO_BIAS, 0.5).is_err());
    /// ```
    pub fn widen_block_uncertainty(
        &mut self,
        block: StateBlock,
        variance_factor: f64,
    ) -> Result<(), NavError> {
        if !(variance_factor.is_finite() && variance_factor >= 1.0) {
            return Err(NavError::NonFiniteInput);
        }
        let scale = crate::float::sqrt(variance_factor);
        for index in block.index()..block.index().saturating_add(block.dimension()) {
            self.scale_state_uncertainty(index, scale);
        }
        Ok(())
    }

    /// Multiplies row and column `index` of `P` (and the state's cross-covariance with the
    /// receiver's correlated error) by `scale`: `P' = S P S` for one state, so the variance
    /// takes `scale²`.
    pub(super) fn scale_state_uncertainty(&mut self, index: usize, scale: f64) {
        self.blocks.scale_cross_row(index, scale);
        for (column_index, column) in self.covariance.data.0.iter_mut().enumerate() {
            if column_index == index {
                column.iter_mut().for_each(|value| *value *= scale);
            }
            // The row's entry: in the state's own column this is the diagonal, scaled twice.
            if let Some(value) = column.get_mut(index) {
                *value *= scale;
            }
        }
    }

    /// Re-initialises the navigation states and the optional blocks to `config`'s prior and
    /// keeps the core calibration (a commanded reset after a navigation upset, when the
    /// sensors' calibration is still trusted): the navigation part of `x` becomes zero, `P`'s
    /// navigation rows and columns become the prior's (no correlation with the calibration),
    /// its calibration block and the calibration part of `x` are kept, and the optional
    /// blocks start again from their prior, as in [`Self::restart`]. Dropping the correlation
    /// between navigation and calibration is conservative: the navigation prior alone bounds
    /// the error it describes. The mode stays `config`'s.
    ///
    /// # Errors
    /// As [`Self::restart`]; nothing changes then.
    ///
    /// # Examples
    /// ```
    /// use nav_core::filter::{ErrorStateFilter, FilterConfig, FilterMode, InitialUncertainty};
    /// use nav_core::gnss_error::GnssErrorModel;
    /// use nav_core::imu_error_states::ImuErrorModel;
    /// use nav_core::state::{GYRO_BIAS, VELOCITY};
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig { mode: FilterMode::ClosedLoop, discretisation_order: 3,
    ///     initial, gnss_error: GnssErrorModel::WHITE, imu_error: ImuErrorModel::DISABLED };
    /// let mut filter = ErrorStateFilter::new(&config)?;
    /// filter.add_block_variance(VELOCITY, 0.03)?;
    /// filter.add_block_variance(GYRO_BIAS, 4e-6)?;
    /// filter.restart_keeping_calibration(&config)?;
    /// let prior = ErrorStateFilter::new(&config)?;
    /// assert_eq!(filter.covariance()[(6, 6)].to_bits(), prior.covariance()[(6, 6)].to_bits());
    /// assert!((filter.covariance()[(9, 9)] - (1e-6 + 4e-6)).abs() < 1e-18);
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn restart_keeping_calibration(&mut self, config: &FilterConfig) -> Result<(), NavError> {
        config.validate()?;
        let gnss_error = GnssErrorStates::new(config.gnss_error)?;
        for (column, entries) in self.covariance.data.0.iter_mut().enumerate() {
            for (row, entry) in entries.iter_mut().enumerate() {
                if row < DYNAMIC_DIMENSION || column < DYNAMIC_DIMENSION {
                    *entry = 0.0;
                }
            }
        }
        for value in self.state.iter_mut().take(DYNAMIC_DIMENSION) {
            *value = 0.0;
        }
        self.mode = config.mode;
        self.restart_optional_blocks(gnss_error, config);
        self.set_initial_navigation_covariance(config);
        Ok(())
    }
}
