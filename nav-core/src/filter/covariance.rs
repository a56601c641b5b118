//! Changes to the covariance from outside the filter's steps: process noise the discrete model
//! does not hold, its replacement, the variance floor and ceiling, and a block's widening.

use nalgebra::Matrix3;

use super::{check_block_covariance, symmetrised, ErrorState, ErrorStateFilter, FilterConfig};
use crate::discretise::CovarianceMatrix;
use crate::state::{StateBlock, CALIBRATION_DIMENSION, DYNAMIC_DIMENSION, STATE_DIMENSION};
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
    /// use nav_core::state::VELOCITY;
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig::without_optional_blocks(FilterMode::ClosedLoop, 3, initial);
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
    /// use nav_core::state::ATTITUDE;
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig::without_optional_blocks(FilterMode::ClosedLoop, 3, initial);
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
    /// use nav_core::state::GYRO_BIAS;
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig::without_optional_blocks(FilterMode::ClosedLoop, 3, initial);
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
    /// the calibration part of `x` is kept, its block of `P` becomes
    /// [`Self::calibration_covariance_for_restart`]'s. An optional block that is calibration
    /// keeps its estimate and its covariance bounded in the same way (`filter/blocks.rs`,
    /// `optional_calibration_for_restart`); the others start again from their prior, as in
    /// [`Self::restart`]. The mode stays `config`'s.
    ///
    /// # Errors
    /// As [`Self::restart`], and as [`Self::calibration_covariance_for_restart`]; nothing
    /// changes then.
    ///
    /// # Examples
    /// ```
    /// use nav_core::filter::{ErrorStateFilter, FilterConfig, FilterMode, InitialUncertainty};
    /// use nav_core::state::{GYRO_BIAS, VELOCITY};
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig::without_optional_blocks(FilterMode::ClosedLoop, 3, initial);
    /// let mut filter = ErrorStateFilter::new(&config)?;
    /// filter.add_block_variance(VELOCITY, 0.03)?;
    /// filter.add_block_variance(GYRO_BIAS, 4e-6)?;
    /// filter.restart_keeping_calibration(&config)?;
    /// let prior = ErrorStateFilter::new(&config)?;
    /// assert_eq!(filter.covariance()[(6, 6)].to_bits(), prior.covariance()[(6, 6)].to_bits());
    /// // The gyro bias was not correlated with the navigation states: its variance is kept.
    /// assert!((filter.covariance()[(9, 9)] - (1e-6 + 4e-6)).abs() < 1e-18);
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn restart_keeping_calibration(&mut self, config: &FilterConfig) -> Result<(), NavError> {
        config.validate()?;
        let calibration = self.calibration_block_for_restart(config)?;
        let kept = self.optional_calibration_for_restart(config)?;
        for (column, entries) in self.covariance.data.0.iter_mut().enumerate() {
            for (row, entry) in entries.iter_mut().enumerate() {
                let at = (
                    row.checked_sub(DYNAMIC_DIMENSION),
                    column.checked_sub(DYNAMIC_DIMENSION),
                );
                *entry = match at {
                    (Some(i), Some(j)) => calibration.get((i, j)).copied().unwrap_or(f64::NAN),
                    _ => 0.0,
                };
            }
        }
        for value in self.state.iter_mut().take(DYNAMIC_DIMENSION) {
            *value = 0.0;
        }
        self.mode = config.mode;
        self.restart_optional_blocks(config);
        self.keep_optional_calibration(&kept);
        self.set_initial_navigation_covariance(config);
        Ok(())
    }

    /// Replaces the calibration block of `P` (states `DYNAMIC_DIMENSION..`, the
    /// calibration blocks in layout order) by the symmetric matrix whose lower triangle
    /// `lower` holds row by row (`(0,0), (1,0), (1,1), (2,0), …`), and zeroes its correlation
    /// with the navigation states: a calibration loaded as the prior (nav-fsw
    /// `calibration_record`), which says nothing about the navigation error now.
    ///
    /// # Errors
    /// [`NavError::NonFiniteState`] for a non-finite entry, [`NavError::InvalidConfiguration`]
    /// for a matrix that is not positive definite; nothing changes then.
    pub fn set_calibration_covariance(
        &mut self,
        lower: &[f64; CALIBRATION_LOWER_TRIANGLE],
    ) -> Result<(), NavError> {
        let block = calibration_block_from_lower(lower)?;
        self.write_calibration_block(&block);
        Ok(())
    }

    /// `block` as the calibration block of `P`, its correlation with navigation zero.
    pub(crate) fn write_calibration_block(&mut self, block: &CalibrationCovariance) {
        for (column, entries) in self.covariance.data.0.iter_mut().enumerate() {
            for (row, entry) in entries.iter_mut().enumerate() {
                let calibration = (
                    row.checked_sub(DYNAMIC_DIMENSION),
                    column.checked_sub(DYNAMIC_DIMENSION),
                );
                *entry = match calibration {
                    (Some(i), Some(j)) => block.get((i, j)).copied().unwrap_or(0.0),
                    (None, None) => *entry,
                    _ => 0.0,
                };
            }
        }
    }

    /// The calibration block of `P` as [`Self::set_calibration_covariance`] takes it (lower
    /// triangle, row by row).
    pub fn calibration_covariance(&self) -> [f64; CALIBRATION_LOWER_TRIANGLE] {
        lower_triangle(|row, column| {
            let at = (DYNAMIC_DIMENSION + row, DYNAMIC_DIMENSION + column);
            self.covariance.get(at).copied()
        })
    }
}

/// The error states' dimensions as the restart's bound splits them.
type NavigationBlock = nalgebra::SMatrix<f64, DYNAMIC_DIMENSION, DYNAMIC_DIMENSION>;
pub(crate) type CrossBlock = nalgebra::SMatrix<f64, DYNAMIC_DIMENSION, CALIBRATION_DIMENSION>;

impl ErrorStateFilter {
    /// The calibration block of `P` for a restart that puts the navigation states back at
    /// `config`'s prior `P⁰_nn` and drops their correlation with the calibration:
    /// `P'_cc = P_cc + P_cn (P⁰_nn − P_nn)⁻¹ P_nc`.
    ///
    /// Derivation: the restarted filter claims `Q = diag(P⁰_nn, P'_cc)` for errors whose
    /// covariance is still `P` (the navigation solution is the one before the restart). `Q`
    /// bounds `P` when `Q − P = [[P⁰_nn − P_nn, −P_nc], [−P_cn, P'_cc − P_cc]] ⪰ 0`; with
    /// `D = P⁰_nn − P_nn ≻ 0`, the Schur complement of `D` is
    /// `P'_cc − P_cc − P_cn D⁻¹ P_nc`, which the formula makes zero: the smallest `P'_cc` of
    /// that form that keeps the restarted filter from claiming more than it knows. Keeping
    /// `P_cc` unchanged claims more (the navigation error the calibration explained is
    /// forgotten), and the flights that reset or reboot mid-manoeuvre end overconfident.
    /// When `D` is not positive definite (the navigation already less certain than its prior
    /// in some direction, as after a long flight without GNSS) no `P'_cc` bounds `P`, and
    /// `D = P⁰_nn` stands in: the correlation is still paid for, at the prior's scale.
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] for a prior that is not positive definite
    /// (refused by the configuration's validation first); [`NavError::NonFiniteState`] for a
    /// non-finite result.
    pub fn calibration_covariance_for_restart(
        &self,
        config: &FilterConfig,
    ) -> Result<[f64; CALIBRATION_LOWER_TRIANGLE], NavError> {
        let block = self.calibration_block_for_restart(config)?;
        Ok(lower_triangle(|row, column| {
            block.get((row, column)).copied()
        }))
    }

    fn calibration_block_for_restart(
        &self,
        config: &FilterConfig,
    ) -> Result<CalibrationCovariance, NavError> {
        let p = &self.covariance;
        let entry = |i: usize, j: usize| p.get((i, j)).copied().unwrap_or(f64::NAN);
        let cross = self.navigation_calibration_cross();
        let kept = CalibrationCovariance::from_fn(|i, j| {
            entry(DYNAMIC_DIMENSION + i, DYNAMIC_DIMENSION + j)
        });
        if cross.iter().all(|value| *value == 0.0) {
            // Nothing to forget (a calibration just loaded, or never correlated).
            return Ok(kept);
        }
        let cholesky = self.restart_margin(config)?;
        let added = cross.transpose() * cholesky.solve(&cross);
        let block = kept + (added + added.transpose()) * 0.5;
        if block.iter().all(|value| value.is_finite()) {
            Ok(block)
        } else {
            Err(NavError::NonFiniteState)
        }
    }
}

impl ErrorStateFilter {
    /// `P_nc`: the navigation states' covariance with the core calibration states.
    pub(crate) fn navigation_calibration_cross(&self) -> CrossBlock {
        let p = &self.covariance;
        CrossBlock::from_fn(|i, j| {
            p.get((i, DYNAMIC_DIMENSION + j))
                .copied()
                .unwrap_or(f64::NAN)
        })
    }

    /// The factor of the restart's margin `D = P⁰_nn − P_nn`
    /// ([`Self::calibration_covariance_for_restart`]), or of `P⁰_nn` when `D` is not positive
    /// definite.
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] for a prior that is not positive definite.
    pub(crate) fn restart_margin(
        &self,
        config: &FilterConfig,
    ) -> Result<nalgebra::Cholesky<f64, nalgebra::Const<DYNAMIC_DIMENSION>>, NavError> {
        let prior = config.initial_variances()?;
        let p = &self.covariance;
        let entry = |i: usize, j: usize| p.get((i, j)).copied().unwrap_or(f64::NAN);
        let prior_block = NavigationBlock::from_fn(|i, j| {
            if i == j {
                prior.get(i).copied().unwrap_or(f64::NAN)
            } else {
                0.0
            }
        });
        let margin = NavigationBlock::from_fn(|i, j| {
            prior_block.get((i, j)).copied().unwrap_or(f64::NAN) - entry(i, j)
        });
        // A navigation block already wider than the prior in some direction (a long flight
        // without GNSS): no calibration block makes the restart bound it; the prior alone
        // then stands for the navigation error the calibration explained.
        nalgebra::Cholesky::new(margin)
            .or_else(|| nalgebra::Cholesky::new(prior_block))
            .ok_or(NavError::InvalidConfiguration)
    }
}

/// The symmetric calibration block whose lower triangle `lower` holds row by row
/// ([`ErrorStateFilter::set_calibration_covariance`]).
///
/// # Errors
/// [`NavError::NonFiniteState`] for a non-finite entry, [`NavError::InvalidConfiguration`]
/// for a matrix that is not positive definite.
pub(crate) fn calibration_block_from_lower(
    lower: &[f64; CALIBRATION_LOWER_TRIANGLE],
) -> Result<CalibrationCovariance, NavError> {
    if !lower.iter().all(|value| value.is_finite()) {
        return Err(NavError::NonFiniteState);
    }
    let block = CalibrationCovariance::from_fn(|row, column| {
        let (high, low) = if row >= column {
            (row, column)
        } else {
            (column, row)
        };
        lower
            .get(high * (high + 1) / 2 + low)
            .copied()
            .unwrap_or(f64::NAN)
    });
    if nalgebra::Cholesky::new(block).is_none() {
        return Err(NavError::InvalidConfiguration);
    }
    Ok(block)
}

/// The lower triangle (diagonal included) of the calibration block whose entry `(row,
/// column)` is `entry(row, column)`, row by row.
fn lower_triangle(
    entry: impl Fn(usize, usize) -> Option<f64>,
) -> [f64; CALIBRATION_LOWER_TRIANGLE] {
    let mut lower = [0.0; CALIBRATION_LOWER_TRIANGLE];
    let mut slots = lower.iter_mut();
    for row in 0..CALIBRATION_DIMENSION {
        for column in 0..=row {
            if let (Some(slot), Some(value)) = (slots.next(), entry(row, column)) {
                *slot = value;
            }
        }
    }
    lower
}

/// The calibration block of `P` (15×15).
pub(crate) type CalibrationCovariance =
    nalgebra::SMatrix<f64, CALIBRATION_DIMENSION, CALIBRATION_DIMENSION>;

/// Entries of the calibration block's lower triangle (diagonal included).
pub const CALIBRATION_LOWER_TRIANGLE: usize =
    CALIBRATION_DIMENSION * (CALIBRATION_DIMENSION + 1) / 2;
