//! The dense reference of the filter's steps: the 24×24 (or, with the measured border of the
//! optional blocks, `crate::block_interface`, 27×27) predict, Joseph update and reset, the arithmetic the structured flight path
//! ([`crate::structured`]) is compared against (equal within relative 1e-12). Compiled for
//! the `dense-reference` feature and the tests only.

use nalgebra::{Cholesky, Matrix3, SMatrix, SVector, Vector3};

use super::{
    check_update_inputs, innovation_report, reset_jacobian_block, symmetrised, ErrorState,
    ErrorStateFilter, FilterMode, InnovationReport,
};
use crate::block;
use crate::block_interface::DenseBorder;
use crate::discretise::{CovarianceMatrix, DiscreteModel};
use crate::error_model::set_block;
use crate::measurement::LinearMeasurement;
use crate::state::{BlockMask, StateBlock, ATTITUDE, STAR_INSTALLATION, STATE_DIMENSION};
use crate::NavError;

impl ErrorStateFilter {
    /// Time update with a discretised model.
    ///
    /// # Errors
    /// [`NavError::NonFiniteState`] if the result is not finite (filter unchanged);
    /// [`NavError::InvalidConfiguration`] with an optional block in use that has no dense
    /// reference here (a bias border: its dense reference is in its own tests).
    pub fn predict(&mut self, model: &DiscreteModel) -> Result<(), NavError> {
        if !self.blocks.has_dense_reference() {
            return Err(NavError::InvalidConfiguration);
        }
        let f = &model.transition;
        let covariance = symmetrised(&(f * self.covariance * f.transpose() + model.process_noise));
        let state = match self.mode {
            FilterMode::OpenLoop => f * self.state,
            FilterMode::ClosedLoop => self.state,
        };
        if !(covariance.iter().all(|v| v.is_finite()) && state.iter().all(|v| v.is_finite())) {
            return Err(NavError::NonFiniteState);
        }
        // Each block changes only when its result is finite.
        if !self
            .blocks
            .propagate_dense(model.interval_s, &|column: &ErrorState| f * column)
        {
            return Err(NavError::NonFiniteState);
        }
        self.covariance = covariance;
        self.state = state;
        Ok(())
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
    /// As [`ErrorStateFilter::update`]; [`NavError::InvalidConfiguration`] with an optional
    /// block in use that has no dense reference here.
    pub fn update_with_frozen_blocks(
        &mut self,
        measurement: &LinearMeasurement,
        gate_nis: f64,
        frozen: &BlockMask,
    ) -> Result<InnovationReport, NavError> {
        check_update_inputs(measurement, gate_nis)?;
        if !self.blocks.has_dense_reference() {
            return Err(NavError::InvalidConfiguration);
        }
        if let Some(border) = self.blocks.measured_dense() {
            return self.update_bordered_dense(&border, measurement, gate_nis, frozen);
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

    /// [`ErrorStateFilter::update_with_frozen_blocks`] with the measured `border`: the dense
    /// 27-state Joseph update of its model (the reference the structured border is tested
    /// against).
    fn update_bordered_dense(
        &mut self,
        border: &DenseBorder,
        measurement: &LinearMeasurement,
        gate_nis: f64,
        frozen: &BlockMask,
    ) -> Result<InnovationReport, NavError> {
        let (cross, border_covariance) = (&border.cross, &border.covariance);
        let estimate = border.estimate;
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
        let coefficient = measurement.border_coefficient;
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
        // A frozen border's gain rows are zero too (`set_optional_block_frozen`).
        let border_frozen = border.frozen;
        for (state_index, mut row) in gain.row_iter_mut().enumerate() {
            let core = state_index < STATE_DIMENSION;
            if (core && frozen.contains_state(state_index)) || (!core && border_frozen) {
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
        self.blocks.set_measured_dense(&DenseBorder {
            estimate: Vector3::from_fn(|a, _| x.get(n + a).copied().unwrap_or(f64::NAN)),
            covariance: Matrix3::from_fn(|a, b| at_augmented(&p, n + a, n + b)),
            cross: SMatrix::from_fn(|i, a| at_augmented(&p, i, n + a)),
            frozen: border.frozen,
        });
        report.accepted = true;
        Ok(report)
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
            block::from_matrix(
                &jacobian
                    .fixed_view::<3, 3>(block.index(), block.index())
                    .into(),
            )
        };
        self.blocks.transform_cross_rows(
            &block_of_jacobian(ATTITUDE),
            &block_of_jacobian(STAR_INSTALLATION),
            true,
        );
        self.state = ErrorState::zeros();
        error
    }
}

/// The paper's 24 states and the measured border's three (one per measured axis).
const AUGMENTED_DIMENSION: usize = STATE_DIMENSION + 3;

/// The 27-state covariance of the dense bordered reference.
type AugmentedCovariance = SMatrix<f64, AUGMENTED_DIMENSION, AUGMENTED_DIMENSION>;

/// Element `(i, j)` of a 27-state covariance (NaN outside, which callers never reach).
fn at_augmented(p: &AugmentedCovariance, i: usize, j: usize) -> f64 {
    p.get((i, j)).copied().unwrap_or(f64::NAN)
}
