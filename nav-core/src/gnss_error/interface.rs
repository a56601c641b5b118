//! The correlated GNSS error states as the measured border of `crate::block_interface`: the
//! filter's propagation, update, reset and protections reach them through
//! [`OptionalStates`] only.

#[cfg(feature = "gnss-error-states")]
use nalgebra::Vector3;

use super::{GnssErrorModel, GnssErrorStates};
#[cfg(feature = "gnss-error-states")]
use crate::block::{Block, Row};
#[cfg(feature = "gnss-error-states")]
use crate::block_interface::MeasuredBorder;
use crate::block_interface::{OptionalModel, OptionalStates};
#[cfg(feature = "gnss-error-states")]
use crate::measurement::MeasurementJacobian;
#[cfg(feature = "gnss-error-states")]
use crate::state::STATE_DIMENSION;
use crate::state::{OptionalBlock, BLOCK_DIMENSION};
#[cfg(feature = "gnss-error-states")]
use crate::structured::{StateRows, StructuredModel};
use crate::NavError;

impl OptionalModel for GnssErrorModel {
    const OFF: Self = Self::WHITE;

    fn in_use(&self) -> bool {
        self.is_enabled()
    }

    fn check(&self) -> Result<(), NavError> {
        self.validate()
    }

    fn write_prior_variances(&self, variances: &mut [f64]) {
        let variance = self.sigma_m * self.sigma_m;
        variances.iter_mut().for_each(|slot| *slot = variance);
    }
}

/// The measured border of [`crate::block_interface`].
#[cfg(feature = "gnss-error-states")]
impl OptionalStates for GnssErrorStates {
    type Model = GnssErrorModel;
    const FIRST_BLOCK: OptionalBlock = OptionalBlock::GnssError;
    const DIMENSION: usize = BLOCK_DIMENSION;
    const EMPTY: Self = Self::EMPTY;

    fn start(&mut self, model: GnssErrorModel) {
        GnssErrorStates::start(self, model);
    }

    fn in_use(&self) -> bool {
        self.is_enabled()
    }

    fn block_frozen(&self, _block: OptionalBlock) -> bool {
        self.frozen
    }

    fn freeze(&mut self, _block: OptionalBlock, frozen: bool) {
        self.frozen = frozen;
    }

    fn is_measured(&self) -> bool {
        self.is_enabled()
    }

    fn prepare_propagation(
        &mut self,
        model: &StructuredModel,
        _open_loop: bool,
        measured_inputs: Option<&[Block; 2]>,
    ) -> bool {
        GnssErrorStates::prepare_propagation(self, model, measured_inputs)
    }

    fn measured_decay(&self, interval_s: f64) -> Option<f64> {
        self.is_enabled().then(|| self.model.decay(interval_s))
    }

    fn commit_propagation(&mut self, _measured_decay: Option<f64>) {
        GnssErrorStates::commit_propagation(self);
    }

    fn measured_border(
        &self,
        jacobian: &MeasurementJacobian,
        observed: &[bool; STATE_DIMENSION / 3],
        coefficient: f64,
    ) -> Option<MeasuredBorder> {
        self.is_enabled()
            .then(|| self.border(jacobian, observed, coefficient))
    }

    fn measured_rows(&self) -> Option<&StateRows> {
        Some(self.rows())
    }

    fn predicted_residual(&self, coefficient: f64) -> Option<Vector3<f64>> {
        Some(GnssErrorStates::predicted_residual(self, coefficient))
    }

    #[inline(always)]
    fn prepare_update(
        &mut self,
        measured: Option<&MeasuredBorder>,
        inputs: &crate::block_interface::UpdateInputs<'_>,
    ) -> bool {
        let Some(border) = measured else {
            return true;
        };
        let solve = |row| inputs.solve(row);
        GnssErrorStates::prepare_update(self, border, inputs.core(), solve, inputs.innovation)
    }

    fn commit_update(&mut self) {
        GnssErrorStates::commit_update(self);
    }

    fn transform_cross_rows(&mut self, attitude: &Block, installation: &Block, _reset: bool) {
        // `ε̂` is a receiver error, never fed back: kept.
        self.reset(attitude, installation);
    }

    fn scale_cross_row(&mut self, index: usize, scale: f64) {
        GnssErrorStates::scale_cross_row(self, index, scale);
    }

    fn protect_variances(
        &mut self,
        floor: &[f64],
        ceiling: &[f64],
        _measured_scales: Option<&Row>,
    ) -> (bool, Option<Row>) {
        match (floor.first_chunk::<3>(), ceiling.first_chunk::<3>()) {
            (Some(floor), Some(ceiling)) => {
                GnssErrorStates::protect_variances(self, floor, ceiling)
            }
            _ => (false, None),
        }
    }

    #[cfg(any(test, feature = "dense-reference"))]
    fn has_dense_reference(&self) -> bool {
        true
    }

    #[cfg(any(test, feature = "dense-reference"))]
    fn propagate_dense<F>(&mut self, interval_s: f64, transition: &F) -> bool
    where
        F: Fn(&nalgebra::SVector<f64, STATE_DIMENSION>) -> nalgebra::SVector<f64, STATE_DIMENSION>,
    {
        self.propagate(interval_s, transition)
    }

    #[cfg(any(test, feature = "dense-reference"))]
    fn measured_dense(&self) -> Option<crate::block_interface::DenseBorder> {
        self.is_enabled()
            .then(|| crate::block_interface::DenseBorder {
                cross: self.cross_covariance(),
                covariance: self.covariance(),
                estimate: self.estimate_m(),
                frozen: self.frozen,
            })
    }

    #[cfg(any(test, feature = "dense-reference"))]
    fn set_measured_dense(&mut self, border: &crate::block_interface::DenseBorder) {
        self.set(&border.estimate, &border.covariance, &border.cross);
    }
}

/// Compiled out: never in use.
#[cfg(not(feature = "gnss-error-states"))]
impl OptionalStates for GnssErrorStates {
    type Model = GnssErrorModel;
    const FIRST_BLOCK: OptionalBlock = OptionalBlock::GnssError;
    const DIMENSION: usize = BLOCK_DIMENSION;
    const EMPTY: Self = Self;

    fn start(&mut self, _model: GnssErrorModel) {}

    fn in_use(&self) -> bool {
        false
    }
}
