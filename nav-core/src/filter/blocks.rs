//! The optional state blocks of the layout ([`crate::state::OptionalBlock`]) as the filter
//! holds them, beside the core states, and the one place that steps them around the core
//! kernels: a propagation or an update first prepares every block in use (their new values
//! into spare buffers, nothing changed), then the core kernel runs (with the blocks' inputs
//! to it), then every block commits. So the filter has one propagation path and one update
//! path whatever blocks are in use, and nothing changes when any step fails.
//!
//! A block whose cargo feature is off is a zero-sized placeholder here (its module keeps only
//! the public read accessors, all inert): no memory, no code.
//!
//! Adding a block: its module (states, prepare/commit of propagation and update, reset and
//! scaling of its cross-covariance rows), its line in the layout ([`crate::state`]), its field
//! and calls here.

use nalgebra::Vector3;

use super::optional::OptionalVarianceBounds;
use super::ErrorState;
use crate::block::{Block, Row};
use crate::gnss_error::{Border, GnssErrorStates};
use crate::imu_error_states::ImuErrorStates;
use crate::measurement::MeasurementJacobian;
use crate::state::{BlockMask, OptionalBlock, STATE_DIMENSION};
use crate::structured::{self, BorderBiasInputs, StateRows, StructuredModel};

/// Every optional block's states (a zero-sized placeholder for a block compiled out).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct OptionalBlocks {
    /// The correlated GNSS error states, inert under [`crate::gnss_error::GnssErrorModel::WHITE`].
    pub(super) gnss: GnssErrorStates,
    /// The systematic IMU error states, inert under
    /// [`crate::imu_error_states::ImuErrorModel::DISABLED`].
    pub(super) imu: ImuErrorStates,
}

// A build without the optional blocks' features carries none of their memory.
#[cfg(not(any(feature = "gnss-error-states", feature = "imu-error-states")))]
const _: () = assert!(core::mem::size_of::<OptionalBlocks>() == 0);

/// What an update hands to the blocks' preparation: the measurement's Jacobian and observed
/// blocks, the core gains `K_x`, `M_x` and the frozen blocks, `S`'s factor and the innovation.
pub(super) struct UpdateInputs<'a> {
    pub(super) jacobian: (&'a MeasurementJacobian, &'a [bool; STATE_DIMENSION / 3]),
    pub(super) gains: &'a StateRows,
    pub(super) products: &'a StateRows,
    pub(super) frozen: &'a BlockMask,
    pub(super) cholesky: &'a structured::Cholesky3,
    pub(super) innovation: Row,
}

impl OptionalBlocks {
    /// Whether any block is in use.
    #[inline]
    pub(super) fn any_enabled(&self) -> bool {
        self.gnss.is_enabled() || self.imu.is_enabled()
    }

    /// Propagation, first step: every block's new values from the model (nothing committed);
    /// `false` if one is not finite. Not inlined: its stack space is taken only when a block
    /// is in use.
    #[inline(never)]
    pub(super) fn prepare_propagation(&mut self, model: &StructuredModel, open_loop: bool) -> bool {
        #[cfg(feature = "gnss-error-states")]
        if self.gnss.is_enabled() {
            // With the IMU error states, `C_GNSS` also gains `Γ Bᵀ` (crate::imu_error_states).
            #[cfg(feature = "imu-error-states")]
            let inputs = self
                .imu
                .is_enabled()
                .then(|| self.imu.gnss_bias_inputs(model));
            #[cfg(not(feature = "imu-error-states"))]
            let inputs = None;
            if !self.gnss.prepare_propagation(model, inputs.as_ref()) {
                return false;
            }
        }
        #[cfg(feature = "imu-error-states")]
        if self.imu.is_enabled() && !self.imu.prepare_propagation(model, open_loop) {
            return false;
        }
        let _ = (model, open_loop);
        true
    }

    /// The bias inputs the core propagation kernel folds in (the IMU error states').
    #[inline]
    pub(super) fn kernel_inputs(&self) -> Option<&BorderBiasInputs> {
        #[cfg(feature = "imu-error-states")]
        if self.imu.is_enabled() {
            return Some(self.imu.propagation_inputs());
        }
        None
    }

    /// Open loop: the blocks' part of the propagated core state (`x_d += E M ε̂`).
    pub(super) fn add_state_increment(&self, state: &mut ErrorState) {
        #[cfg(feature = "imu-error-states")]
        if self.imu.is_enabled() {
            for (value, delta) in state.iter_mut().zip(self.imu.state_increment()) {
                *value += delta;
            }
        }
        let _ = state;
    }

    /// Propagation, last step: every prepared block made current.
    pub(super) fn commit_propagation(&mut self, model: &StructuredModel) {
        #[cfg(feature = "imu-error-states")]
        if self.imu.is_enabled() {
            // `B = cov(ε_GNSS, ε)` decays with the GNSS error.
            let gnss_decay = self
                .gnss
                .is_enabled()
                .then(|| self.gnss.model().decay(model.interval_s()));
            self.imu.commit_propagation(gnss_decay);
        }
        #[cfg(feature = "gnss-error-states")]
        if self.gnss.is_enabled() {
            self.gnss.commit_propagation();
        }
        let _ = model;
    }

    /// The part of an update of the blocks a measurement sees directly (`H_ε ≠ 0`: the GNSS
    /// error states, coefficient `h_ε`), found once per update; `None` if there is none.
    pub(super) fn measured_border(
        &self,
        jacobian: (&MeasurementJacobian, &[bool; STATE_DIMENSION / 3]),
        coefficient: f64,
    ) -> Option<Border> {
        #[cfg(feature = "gnss-error-states")]
        if self.gnss.is_enabled() {
            return Some(self.gnss.border(jacobian.0, jacobian.1, coefficient));
        }
        let _ = (jacobian, coefficient);
        None
    }

    /// The cross-covariance rows `C_j` of the measured border (added to `M_x`).
    pub(super) fn measured_rows<'a>(
        &'a self,
        border: Option<&'a Border>,
    ) -> Option<(&'a StateRows, &'a Border)> {
        #[cfg(feature = "gnss-error-states")]
        return border.map(|border| (self.gnss.cross_rows(), border));
        #[cfg(not(feature = "gnss-error-states"))]
        border.and(None)
    }

    /// `h_ε ε̂`, subtracted from the innovation.
    pub(super) fn predicted_residual(&self, border: &Border) -> Vector3<f64> {
        #[cfg(feature = "gnss-error-states")]
        return self.gnss.predicted_residual(border.coefficient);
        #[cfg(not(feature = "gnss-error-states"))]
        {
            let _ = border;
            Vector3::zeros()
        }
    }

    /// Update, first step: every block's new values (into its spare buffers); `false` if one
    /// is not finite (nothing committed).
    pub(super) fn prepare_update(
        &mut self,
        border: Option<&Border>,
        inputs: &UpdateInputs<'_>,
    ) -> bool {
        let solve = |row| inputs.cholesky.solve(row);
        #[cfg(feature = "imu-error-states")]
        let gnss_frozen = self.gnss.is_frozen();
        #[cfg(feature = "gnss-error-states")]
        if let Some(border) = border {
            let core = (inputs.gains, inputs.products, inputs.frozen);
            if !self
                .gnss
                .prepare_update(border, core, solve, inputs.innovation)
            {
                return false;
            }
        }
        #[cfg(feature = "imu-error-states")]
        if self.imu.is_enabled()
            && !self.imu.prepare_update(
                inputs.jacobian,
                (inputs.gains, inputs.products, inputs.frozen),
                solve,
                inputs.innovation,
                border.map(|border| (border.coefficient, &border.products, gnss_frozen)),
            )
        {
            return false;
        }
        let _ = (border, solve);
        true
    }

    /// Update, last step: every prepared block made current.
    pub(super) fn commit_update(&mut self, border: Option<&Border>) {
        #[cfg(feature = "gnss-error-states")]
        if border.is_some() {
            self.gnss.commit_update();
        }
        #[cfg(feature = "imu-error-states")]
        if self.imu.is_enabled() {
            self.imu.commit_update();
        }
        let _ = border;
    }

    /// `C ← J C` for every block's cross-covariance, `J` the identity but `J_ϑϑ = attitude`
    /// and `J_ψψ = installation` (the closed-loop reset with `reset_estimate`, which also
    /// zeroes the fed-back estimates; the star-head hand-over without).
    pub(super) fn transform_cross_rows(
        &mut self,
        attitude: &Block,
        installation: &Block,
        reset_estimate: bool,
    ) {
        #[cfg(feature = "gnss-error-states")]
        if self.gnss.is_enabled() {
            // `ε̂` is a receiver error, never fed back: kept.
            self.gnss.reset(attitude, installation);
        }
        #[cfg(feature = "imu-error-states")]
        if self.imu.is_enabled() {
            if reset_estimate {
                self.imu.reset(attitude, installation);
            } else {
                self.imu.transform_cross_rows(attitude, installation);
            }
        }
        let _ = (attitude, installation, reset_estimate);
    }

    /// Every block in use under its variance floor and ceiling
    /// ([`super::ErrorStateFilter::protect_optional_variances`]); whether anything changed.
    /// Not inlined: the frames of a flight without optional blocks do not carry it.
    #[inline(never)]
    pub(super) fn protect_variances(&mut self, bounds: &OptionalVarianceBounds) -> bool {
        // Written only by the blocks compiled in.
        #[cfg_attr(
            not(any(feature = "gnss-error-states", feature = "imu-error-states")),
            allow(unused_mut)
        )]
        let mut changed = false;
        // The GNSS states first in the bounds, the IMU states after them (the layout's order).
        const _: () = assert!(
            OptionalBlock::GnssError.index() == STATE_DIMENSION
                && OptionalBlock::GyroNonOrthogonality.index() == STATE_DIMENSION + 3
        );
        let split = split_bounds;
        let (Some((gnss_floor, imu_floor)), Some((gnss_ceiling, imu_ceiling))) =
            (split(&bounds.floor), split(&bounds.ceiling))
        else {
            return false;
        };
        #[cfg(feature = "gnss-error-states")]
        if self.gnss.is_enabled() {
            let (clamped, scales) = self.gnss.protect_variances(gnss_floor, gnss_ceiling);
            // `cov(ε_GNSS, ε)` takes the GNSS states' scaling on its rows.
            #[cfg(feature = "imu-error-states")]
            if let Some(scales) = &scales {
                self.imu.scale_gnss_rows(scales);
            }
            let _ = scales;
            changed |= clamped;
        }
        #[cfg(feature = "imu-error-states")]
        if self.imu.is_enabled() {
            changed |= self.imu.protect_variances(imu_floor, imu_ceiling);
        }
        let _ = (gnss_floor, gnss_ceiling, imu_floor, imu_ceiling);
        changed
    }

    /// Whether `block` is frozen (never, for a block compiled out).
    pub(super) fn is_frozen(&self, block: OptionalBlock) -> bool {
        match block {
            OptionalBlock::GnssError => self.gnss.is_frozen(),
            _ => self.imu.is_frozen(block),
        }
    }

    /// Freezes `block` or releases it (the caller has checked that it is in use).
    pub(super) fn set_frozen(&mut self, block: OptionalBlock, frozen: bool) {
        #[cfg(feature = "gnss-error-states")]
        if block == OptionalBlock::GnssError {
            self.gnss.set_frozen(frozen);
        }
        #[cfg(feature = "imu-error-states")]
        self.imu.set_frozen(block, frozen);
        let _ = (block, frozen);
    }

    /// Whether `block` is in use.
    pub(super) fn is_enabled(&self, block: OptionalBlock) -> bool {
        match block {
            OptionalBlock::GnssError => self.gnss.is_enabled(),
            _ => self.imu.is_enabled(),
        }
    }

    /// Row `index` of every block's cross-covariance times `scale` (that core state's
    /// uncertainty was scaled).
    pub(super) fn scale_cross_row(&mut self, index: usize, scale: f64) {
        #[cfg(feature = "gnss-error-states")]
        self.gnss.scale_cross_row(index, scale);
        #[cfg(feature = "imu-error-states")]
        self.imu.scale_cross_row(index, scale);
        let _ = (index, scale);
    }
}

/// The GNSS border's states and the IMU border's in optional-state bounds (the layout's
/// order, checked in `OptionalBlocks::protect_variances`).
type SplitBounds<'a> = (
    &'a [f64; 3],
    &'a [f64; crate::imu_error::IMU_ERROR_DIMENSION],
);

/// `bounds` split into the GNSS border's states and the IMU border's.
fn split_bounds(bounds: &[f64; crate::state::OPTIONAL_DIMENSION]) -> Option<SplitBounds<'_>> {
    let (gnss, rest) = bounds.split_first_chunk::<3>()?;
    Some((gnss, rest.first_chunk()?))
}
