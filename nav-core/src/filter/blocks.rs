//! The registration of the optional state blocks ([`crate::state::OptionalBlock`]): one line
//! per block in `optional_blocks!` below gives the block's model its field in
//! [`FilterConfig`], its states their field in the filter and their read accessor, and puts
//! the block into every step the filter takes. Every step goes through the block interface
//! ([`crate::block_interface::OptionalStates`]) and calls the blocks in registration order: a
//! propagation or an update first prepares every block in use (their new values into spare
//! buffers, nothing changed), then the core kernel runs (with the blocks' inputs to it), then
//! every block commits. So the filter has one propagation path and one update path whatever
//! blocks are in use, and nothing changes when any step fails.
//!
//! A block whose cargo feature is off is a zero-sized placeholder (its module keeps only the
//! public read accessors, all inert): no memory, and every step on it folds away.

use nalgebra::Vector3;

use super::optional::OptionalVarianceBounds;
use super::{ErrorState, ErrorStateFilter, FilterMode, InitialUncertainty};
use crate::block::{Block, Row};
use crate::block_interface::{
    layout_states, owns, MeasuredBorder, OptionalModel, OptionalStates, UpdateInputs,
};
use crate::measurement::MeasurementJacobian;
use crate::state::{OptionalBlock, OPTIONAL_DIMENSION, STATE_DIMENSION};
use crate::structured::{BorderBiasInputs, StateRows, StructuredModel};
use crate::NavError;

/// Declares the registered blocks. Each line: the block's field in the filter, its states'
/// type, its model's field in [`FilterConfig`] (also the filter's read accessor) and its
/// model's type. The measured border comes before any bias border
/// ([`crate::block_interface`]).
macro_rules! optional_blocks {
    ($( $(#[$doc:meta])* $field:ident: $states:ty, $config:ident: $model:ty; )*) => {
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
            $( $(#[$doc])* pub $config: $model, )*
        }

        impl FilterConfig {
            /// The paper's 24 states: every optional block's model off.
            ///
            /// # Examples
            /// ```
            /// use nav_core::filter::{FilterConfig, FilterMode, InitialUncertainty};
            /// let initial = InitialUncertainty {
            ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
            ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
            ///     accel_scale_factor: 1e-4,
            /// };
            /// let config = FilterConfig::without_optional_blocks(FilterMode::ClosedLoop, 3, initial);
            /// assert_eq!(config.validate(), Ok(()));
            /// ```
            pub const fn without_optional_blocks(
                mode: FilterMode,
                discretisation_order: u8,
                initial: InitialUncertainty,
            ) -> Self {
                Self {
                    mode,
                    discretisation_order,
                    initial,
                    $( $config: <$model as OptionalModel>::OFF, )*
                }
            }

            /// Every optional block's model checked, in registration order.
            pub(super) fn check_optional_models(&self) -> Result<(), NavError> {
                $( OptionalModel::check(&self.$config)?; )*
                Ok(())
            }

            /// Whether the model of the block `block` belongs to asks for it.
            pub(super) fn optional_block_in_use(&self, block: OptionalBlock) -> bool {
                false $( || (owns::<$states>(block) && OptionalModel::in_use(&self.$config)) )*
            }

            /// Every optional state's prior variance, in layout order after the core's
            /// (zero for a block whose model is off).
            pub(super) fn optional_prior_variances(&self) -> [f64; OPTIONAL_DIMENSION] {
                let mut variances = [0.0; OPTIONAL_DIMENSION];
                $(
                    let states = layout_states::<$states>();
                    let states = states.start - STATE_DIMENSION..states.end - STATE_DIMENSION;
                    if let Some(slots) = variances.get_mut(states) {
                        OptionalModel::write_prior_variances(&self.$config, slots);
                    }
                )*
                variances
            }
        }

        /// Every optional block's states (a zero-sized placeholder for a block compiled out).
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub(crate) struct OptionalBlocks {
            $( $(#[$doc])* pub(super) $field: $states, )*
        }

        impl ErrorStateFilter {
            $(
                $(#[$doc])*
                pub fn $config(&self) -> &$states {
                    &self.blocks.$field
                }
            )*
        }

        impl OptionalBlocks {
            /// Every block empty, its model off.
            pub(super) const EMPTY: Self = Self {
                $( $field: <$states as OptionalStates>::EMPTY, )*
            };

            /// On [`Self::EMPTY`] blocks, in place: every block's model and prior from
            /// `config` (checked by the caller).
            pub(super) fn start(&mut self, config: &FilterConfig) {
                $( OptionalStates::start(&mut self.$field, config.$config); )*
            }

            /// Whether any block is in use.
            #[inline]
            pub(super) fn any_enabled(&self) -> bool {
                false $( || OptionalStates::in_use(&self.$field) )*
            }

            /// Whether a measured border is in use.
            fn any_measured(&self) -> bool {
                false $( || OptionalStates::is_measured(&self.$field) )*
            }

            /// Whether a bias border is in use.
            fn any_coupled(&self) -> bool {
                false $( || OptionalStates::couples_to_measured(&self.$field) )*
            }

            /// Propagation, first step: every block's new values from the model (nothing
            /// committed); `false` if one is not finite. Not inlined: its stack space is
            /// taken only when a block is in use.
            #[inline(never)]
            pub(super) fn prepare_propagation(
                &mut self,
                model: &StructuredModel,
                open_loop: bool,
            ) -> bool {
                // A bias border's `M Bᵀ`, for the measured border's `C ← φ (F C + Γ Bᵀ)`.
                let mut measured_inputs = None;
                if self.any_measured() {
                    $(
                        if measured_inputs.is_none() {
                            measured_inputs = OptionalStates::measured_cross_inputs(&self.$field, model);
                        }
                    )*
                }
                $(
                    if OptionalStates::in_use(&self.$field)
                        && !OptionalStates::prepare_propagation(
                            &mut self.$field,
                            model,
                            open_loop,
                            measured_inputs.as_ref(),
                        )
                    {
                        return false;
                    }
                )*
                true
            }

            /// The bias inputs the core propagation kernel folds in.
            #[inline]
            pub(super) fn kernel_inputs(&self) -> Option<&BorderBiasInputs> {
                None $( .or_else(|| OptionalStates::kernel_inputs(&self.$field)) )*
            }

            /// Open loop: the blocks' part of the propagated core state (`x_d += E M ε̂`).
            pub(super) fn add_state_increment(&self, state: &mut ErrorState) {
                $( OptionalStates::add_state_increment(&self.$field, state); )*
            }

            /// Propagation, last step: every prepared block made current.
            pub(super) fn commit_propagation(&mut self, model: &StructuredModel) {
                let mut decay = None;
                if self.any_coupled() {
                    $(
                        if decay.is_none() {
                            decay = OptionalStates::measured_decay(&self.$field, model.interval_s());
                        }
                    )*
                }
                $(
                    if OptionalStates::in_use(&self.$field) {
                        OptionalStates::commit_propagation(&mut self.$field, decay);
                    }
                )*
            }

            /// The measured border's part of an update (`H_ε ≠ 0`), found once per update;
            /// `None` if there is none.
            pub(super) fn measured_border(
                &self,
                (jacobian, observed): (&MeasurementJacobian, &[bool; STATE_DIMENSION / 3]),
                coefficient: f64,
            ) -> Option<MeasuredBorder> {
                $(
                    let border =
                        OptionalStates::measured_border(&self.$field, jacobian, observed, coefficient);
                    if border.is_some() {
                        return border;
                    }
                )*
                None
            }

            /// The cross-covariance rows `C_j` of the measured border (added to `M_x`).
            pub(super) fn measured_rows<'a>(
                &'a self,
                border: Option<&'a MeasuredBorder>,
            ) -> Option<(&'a StateRows, &'a MeasuredBorder)> {
                let border = border?;
                let rows = None $( .or_else(|| OptionalStates::measured_rows(&self.$field)) )*;
                rows.map(|rows| (rows, border))
            }

            /// `h_ε ε̂`, subtracted from the innovation.
            pub(super) fn predicted_residual(&self, border: &MeasuredBorder) -> Vector3<f64> {
                $(
                    if OptionalStates::is_measured(&self.$field) {
                        if let Some(residual) =
                            OptionalStates::predicted_residual(&self.$field, border.coefficient)
                        {
                            return residual;
                        }
                    }
                )*
                Vector3::zeros()
            }

            /// Update, first step: every block's new values (into its spare buffers); `false`
            /// if one is not finite (nothing committed).
            pub(super) fn prepare_update(
                &mut self,
                border: Option<&MeasuredBorder>,
                inputs: &UpdateInputs<'_>,
            ) -> bool {
                // Each block decides from `border` or its own use whether it takes part.
                $(
                    if !OptionalStates::prepare_update(&mut self.$field, border, inputs) {
                        return false;
                    }
                )*
                true
            }

            /// Update, last step: every prepared block made current.
            pub(super) fn commit_update(&mut self) {
                $(
                    if OptionalStates::in_use(&self.$field) {
                        OptionalStates::commit_update(&mut self.$field);
                    }
                )*
            }

            /// `C ← J C` for every block's cross-covariance, `J` the identity but
            /// `J_ϑϑ = attitude` and `J_ψψ = installation` (the closed-loop reset with
            /// `reset_estimate`, which also zeroes the fed-back estimates; the star-head
            /// hand-over without).
            pub(super) fn transform_cross_rows(
                &mut self,
                attitude: &Block,
                installation: &Block,
                reset_estimate: bool,
            ) {
                $(
                    if OptionalStates::in_use(&self.$field) {
                        OptionalStates::transform_cross_rows(
                            &mut self.$field,
                            attitude,
                            installation,
                            reset_estimate,
                        );
                    }
                )*
            }

            /// Every block in use under its variance floor and ceiling
            /// ([`super::ErrorStateFilter::protect_optional_variances`]); whether anything
            /// changed. Not inlined: the frames of a flight without optional blocks do not
            /// carry it.
            #[inline(never)]
            // The last block's scales are not read.
            #[allow(unused_assignments)]
            pub(super) fn protect_variances(&mut self, bounds: &OptionalVarianceBounds) -> bool {
                let mut changed = false;
                let mut measured_scales: Option<Row> = None;
                $(
                    if OptionalStates::in_use(&self.$field) {
                        let states = optional_states::<$states>();
                        let (clamped, scales) = match (
                            bounds.floor.get(states.clone()),
                            bounds.ceiling.get(states),
                        ) {
                            (Some(floor), Some(ceiling)) => OptionalStates::protect_variances(
                                &mut self.$field,
                                floor,
                                ceiling,
                                measured_scales.as_ref(),
                            ),
                            _ => (false, None),
                        };
                        changed |= clamped;
                        measured_scales = measured_scales.or(scales);
                    }
                )*
                changed
            }

            /// Whether `block` is frozen (never, for a block compiled out).
            pub(super) fn is_frozen(&self, block: OptionalBlock) -> bool {
                false $( || (owns::<$states>(block) && OptionalStates::block_frozen(&self.$field, block)) )*
            }

            /// Freezes `block` or releases it (the caller has checked that it is in use).
            pub(super) fn set_frozen(&mut self, block: OptionalBlock, frozen: bool) {
                $(
                    if owns::<$states>(block) {
                        OptionalStates::freeze(&mut self.$field, block, frozen);
                    }
                )*
            }

            /// Whether `block` is in use.
            pub(super) fn is_enabled(&self, block: OptionalBlock) -> bool {
                false $( || (owns::<$states>(block) && OptionalStates::in_use(&self.$field)) )*
            }

            /// Row `index` of every block's cross-covariance times `scale` (that core state's
            /// uncertainty was scaled).
            pub(super) fn scale_cross_row(&mut self, index: usize, scale: f64) {
                $( OptionalStates::scale_cross_row(&mut self.$field, index, scale); )*
            }

            /// Whether the dense reference covers every block as it is.
            #[cfg(any(test, feature = "dense-reference"))]
            pub(super) fn has_dense_reference(&self) -> bool {
                true $( && OptionalStates::has_dense_reference(&self.$field) )*
            }

            /// The dense propagation of every block with `transition(c) = F c`; `false` if
            /// not finite (a block is changed only when its result is finite).
            #[cfg(any(test, feature = "dense-reference"))]
            pub(super) fn propagate_dense<F>(&mut self, interval_s: f64, transition: &F) -> bool
            where
                F: Fn(&nalgebra::SVector<f64, STATE_DIMENSION>)
                    -> nalgebra::SVector<f64, STATE_DIMENSION>,
            {
                true $( && OptionalStates::propagate_dense(&mut self.$field, interval_s, transition) )*
            }

            /// The measured border as the dense reference reads it.
            #[cfg(any(test, feature = "dense-reference"))]
            pub(super) fn measured_dense(&self) -> Option<crate::block_interface::DenseBorder> {
                None $( .or_else(|| OptionalStates::measured_dense(&self.$field)) )*
            }

            /// The dense reference's result written into the measured border.
            #[cfg(any(test, feature = "dense-reference"))]
            pub(super) fn set_measured_dense(&mut self, border: &crate::block_interface::DenseBorder) {
                $(
                    if OptionalStates::is_measured(&self.$field) {
                        OptionalStates::set_measured_dense(&mut self.$field, border);
                    }
                )*
            }
        }
    };
}

optional_blocks! {
    /// The GNSS receiver's correlated position error ([`crate::gnss_error`]); off for the
    /// paper's 24 states.
    gnss: crate::gnss_error::GnssErrorStates, gnss_error: crate::gnss_error::GnssErrorModel;
    /// The systematic IMU error states ([`crate::imu_error_states`]); off for the paper's 24
    /// states. In closed loop, read `ε̂` before [`ErrorStateFilter::reset`] to feed it into the
    /// sensor corrections.
    imu: crate::imu_error_states::ImuErrorStates, imu_error: crate::imu_error_states::ImuErrorModel;
}

// A build without the optional blocks' features carries none of their memory.
#[cfg(not(any(feature = "gnss-error-states", feature = "imu-error-states")))]
const _: () = assert!(core::mem::size_of::<OptionalBlocks>() == 0);

/// The states of `T` in the optional-state bounds (layout order after the core's).
fn optional_states<T: OptionalStates>() -> core::ops::Range<usize> {
    let states = layout_states::<T>();
    states.start.saturating_sub(STATE_DIMENSION)..states.end.saturating_sub(STATE_DIMENSION)
}

/// What the optional blocks that are calibration keep across a restart that keeps the
/// calibration: the systematic IMU errors' estimate and their covariance bounded for the
/// dropped correlation with navigation (`None` when they are not flown).
pub(super) struct KeptOptionalCalibration {
    imu: Option<(
        nalgebra::SVector<f64, { crate::imu_error::IMU_ERROR_DIMENSION }>,
        crate::imu_error_states::ImuErrorCovariance,
    )>,
}

impl ErrorStateFilter {
    /// The systematic IMU error states, written by their restart and record code.
    pub(crate) fn imu_error_mut(&mut self) -> &mut crate::imu_error_states::ImuErrorStates {
        &mut self.blocks.imu
    }

    /// What [`Self::keep_optional_calibration`] puts back after a restart.
    ///
    /// # Errors
    /// As [`ErrorStateFilter::imu_error_covariance_for_restart`]; nothing changes.
    pub(super) fn optional_calibration_for_restart(
        &self,
        config: &FilterConfig,
    ) -> Result<KeptOptionalCalibration, NavError> {
        let imu = self
            .imu_error_covariance_for_restart(config)?
            .map(|covariance| (self.blocks.imu.estimate(), covariance));
        Ok(KeptOptionalCalibration { imu })
    }

    /// The kept calibration blocks installed on restarted blocks.
    pub(super) fn keep_optional_calibration(&mut self, kept: &KeptOptionalCalibration) {
        if let Some((estimate, covariance)) = &kept.imu {
            // The bound keeps the whole calibration block positive definite, so the check
            // cannot fail (were it to, the states would stay at their prior: conservative).
            let _ = self.install_imu_error(estimate, covariance);
        }
    }
}

#[cfg(test)]
impl ErrorStateFilter {
    /// The correlated GNSS error states, for the crate's tests.
    pub(crate) fn gnss_error_mut(&mut self) -> &mut crate::gnss_error::GnssErrorStates {
        &mut self.blocks.gnss
    }
}
