//! The systematic IMU error states kept across a restart: their part of the calibration
//! covariance (`P_εε` and their covariance `P_cε` with the core calibration states), bounded
//! for a restart as the core calibration block is
//! ([`ErrorStateFilter::calibration_covariance_for_restart`]), read for a calibration record
//! and set from one.

use nalgebra::SMatrix;

use crate::filter::covariance::{calibration_block_from_lower, CalibrationCovariance, CrossBlock};
use crate::filter::{ErrorStateFilter, FilterConfig, CALIBRATION_LOWER_TRIANGLE};
use crate::imu_error::IMU_ERROR_DIMENSION;
use crate::state::{CALIBRATION_DIMENSION, DYNAMIC_DIMENSION, STATE_DIMENSION};
use crate::NavError;

/// Entries of `P_εε`'s lower triangle (diagonal included).
pub const IMU_ERROR_LOWER_TRIANGLE: usize = IMU_ERROR_DIMENSION * (IMU_ERROR_DIMENSION + 1) / 2;

/// The systematic IMU error states' part of the calibration covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuErrorCovariance {
    /// `P_εε`, lower triangle row by row (`(0,0), (1,0), (1,1), …`; `crate::imu_error`
    /// block order).
    pub imu_error_lower: [f64; IMU_ERROR_LOWER_TRIANGLE],
    /// `P_cε`: row `i` the core calibration state `DYNAMIC_DIMENSION + i`, column `a` the
    /// IMU error state `a`.
    pub with_calibration: [[f64; IMU_ERROR_DIMENSION]; CALIBRATION_DIMENSION],
}

impl ImuErrorCovariance {
    /// All zero: the value a record carries when the states are not flown.
    pub const ZERO: Self = Self {
        imu_error_lower: [0.0; IMU_ERROR_LOWER_TRIANGLE],
        with_calibration: [[0.0; IMU_ERROR_DIMENSION]; CALIBRATION_DIMENSION],
    };

    fn imu_error_block(&self) -> ImuErrorBlock {
        ImuErrorBlock::from_fn(|row, column| {
            let (high, low) = (row.max(column), row.min(column));
            self.imu_error_lower
                .get(high * (high + 1) / 2 + low)
                .copied()
                .unwrap_or(f64::NAN)
        })
    }

    fn calibration_cross(&self) -> CalibrationImuCross {
        CalibrationImuCross::from_fn(|i, a| {
            self.with_calibration
                .get(i)
                .and_then(|row| row.get(a))
                .copied()
                .unwrap_or(f64::NAN)
        })
    }

    fn from_blocks(imu_error: &ImuErrorBlock, cross: &CalibrationImuCross) -> Self {
        let mut value = Self::ZERO;
        let mut slots = value.imu_error_lower.iter_mut();
        for row in 0..IMU_ERROR_DIMENSION {
            for column in 0..=row {
                if let (Some(slot), Some(entry)) = (slots.next(), imu_error.get((row, column))) {
                    *slot = *entry;
                }
            }
        }
        for (i, row) in value.with_calibration.iter_mut().enumerate() {
            for (a, slot) in row.iter_mut().enumerate() {
                *slot = cross.get((i, a)).copied().unwrap_or(f64::NAN);
            }
        }
        value
    }

    fn is_finite(&self) -> bool {
        self.imu_error_lower.iter().all(|value| value.is_finite())
            && self
                .with_calibration
                .iter()
                .flatten()
                .all(|v| v.is_finite())
    }
}

type ImuErrorBlock = SMatrix<f64, IMU_ERROR_DIMENSION, IMU_ERROR_DIMENSION>;
type CalibrationImuCross = SMatrix<f64, CALIBRATION_DIMENSION, IMU_ERROR_DIMENSION>;
type NavigationImuCross = SMatrix<f64, DYNAMIC_DIMENSION, IMU_ERROR_DIMENSION>;

impl ErrorStateFilter {
    /// The systematic IMU error states' part of the calibration covariance a restart to the
    /// navigation prior needs, `None` when they are not flown. With `ε` counted among the
    /// calibration states `c`, the bound of
    /// [`Self::calibration_covariance_for_restart`] (`P'_cc = P_cc + P_cn D⁻¹ P_nc`, its
    /// derivation there) gives `P'_εε = P_εε + P_εn D⁻¹ P_nε` and
    /// `P'_cε = P_cε + P_cn D⁻¹ P_nε`, with the same `D`.
    ///
    /// # Errors
    /// As [`Self::calibration_covariance_for_restart`].
    pub fn imu_error_covariance_for_restart(
        &self,
        config: &FilterConfig,
    ) -> Result<Option<ImuErrorCovariance>, NavError> {
        let states = self.imu_error();
        if !states.is_enabled() {
            return Ok(None);
        }
        let cross = states.cross_covariance();
        let at = |j: usize, a: usize| cross.get((j, a)).copied().unwrap_or(f64::NAN);
        let navigation = NavigationImuCross::from_fn(at);
        let kept_cross = CalibrationImuCross::from_fn(|i, a| at(DYNAMIC_DIMENSION + i, a));
        let mut imu_error = states.covariance();
        let mut with_calibration = kept_cross;
        let calibration: CrossBlock = self.navigation_calibration_cross();
        let correlated = |values: &[f64]| values.iter().any(|value| *value != 0.0);
        if correlated(navigation.as_slice()) {
            let solved = self.restart_margin(config)?.solve(&navigation);
            let added = navigation.transpose() * solved;
            imu_error += (added + added.transpose()) * 0.5;
            with_calibration += calibration.transpose() * solved;
        }
        let value = ImuErrorCovariance::from_blocks(&imu_error, &with_calibration);
        if value.is_finite() {
            Ok(Some(value))
        } else {
            Err(NavError::NonFiniteState)
        }
    }

    /// The systematic IMU error states' part of the calibration covariance
    /// ([`Self::imu_error_covariance_for_restart`] reads it), their correlation with the
    /// navigation states and the correlated GNSS error states zeroed: a calibration loaded
    /// as the prior, which says nothing about the navigation error now. Their estimate is
    /// kept.
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] when the states are not flown or when the whole
    /// calibration block (the core block of `P` now, and `value`) is not positive definite;
    /// [`NavError::NonFiniteState`] for a non-finite entry. Nothing changes then.
    pub fn set_imu_error_covariance(&mut self, value: &ImuErrorCovariance) -> Result<(), NavError> {
        let estimate = self.imu_error().estimate();
        self.install_imu_error(&estimate, value)
    }

    /// The calibration block of `P` and the systematic IMU error states' part of it at once
    /// (a calibration record loaded as the prior): [`Self::set_calibration_covariance`] with
    /// `lower`, then [`Self::set_imu_error_covariance`] with `imu_error`, checked together
    /// before anything is written.
    ///
    /// # Errors
    /// As those two; nothing changes then.
    pub fn set_calibration_and_imu_error_covariance(
        &mut self,
        lower: &[f64; CALIBRATION_LOWER_TRIANGLE],
        imu_error: &ImuErrorCovariance,
    ) -> Result<(), NavError> {
        let block = calibration_block_from_lower(lower)?;
        let cross = self.checked_imu_error(&block, imu_error)?;
        self.write_calibration_block(&block);
        let estimate = self.imu_error().estimate();
        self.imu_error_mut()
            .set(&estimate, &imu_error.imu_error_block(), &cross);
        Ok(())
    }

    /// [`Self::set_imu_error_covariance`] with the estimate `ε̂ = estimate`.
    pub(crate) fn install_imu_error(
        &mut self,
        estimate: &nalgebra::SVector<f64, IMU_ERROR_DIMENSION>,
        value: &ImuErrorCovariance,
    ) -> Result<(), NavError> {
        let p = self.covariance();
        let calibration = CalibrationCovariance::from_fn(|i, j| {
            p.get((DYNAMIC_DIMENSION + i, DYNAMIC_DIMENSION + j))
                .copied()
                .unwrap_or(f64::NAN)
        });
        let cross = self.checked_imu_error(&calibration, value)?;
        self.imu_error_mut()
            .set(estimate, &value.imu_error_block(), &cross);
        Ok(())
    }

    /// `C` (24×12) for `value` with the core calibration block `calibration`, checked: the
    /// states flown, every value finite, the whole calibration block positive definite.
    fn checked_imu_error(
        &self,
        calibration: &CalibrationCovariance,
        value: &ImuErrorCovariance,
    ) -> Result<SMatrix<f64, STATE_DIMENSION, IMU_ERROR_DIMENSION>, NavError> {
        if !self.imu_error().is_enabled() {
            return Err(NavError::InvalidConfiguration);
        }
        if !value.is_finite() {
            return Err(NavError::NonFiniteState);
        }
        let (imu_error, with_calibration) = (value.imu_error_block(), value.calibration_cross());
        // Positive definite as a whole when `P_cc` is and so is its Schur complement
        // `P_εε − P_εc P_cc⁻¹ P_cε`.
        let factor = nalgebra::Cholesky::new(*calibration).ok_or(NavError::InvalidConfiguration)?;
        let complement = imu_error - with_calibration.transpose() * factor.solve(&with_calibration);
        if nalgebra::Cholesky::new(complement).is_none() {
            return Err(NavError::InvalidConfiguration);
        }
        Ok(SMatrix::from_fn(|j, a| {
            j.checked_sub(DYNAMIC_DIMENSION)
                .and_then(|i| with_calibration.get((i, a)).copied())
                .unwrap_or(0.0)
        }))
    }
}
