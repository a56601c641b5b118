//! The one place that chooses between the flight arithmetic of the filter's steps and the
//! dense reference: [`FilterArithmetic`]'s methods run one propagation, late-measurement
//! referral, update or reset with either. The flight path is the block-structured one
//! ([`crate::structured`]); the dense 24×24 reference exists only with the
//! `dense-reference` feature (comparisons, tests, benchmarks), so a flight build compiles
//! none of it.

use crate::error_model::{LinearisationPoint, ProcessNoise};
use crate::filter::{ErrorState, ErrorStateFilter, InnovationReport};
use crate::measurement::LinearMeasurement;
use crate::state::BlockMask;
use crate::structured::{refer_to_later_time_in_place, StructuredModel};
use crate::NavError;

/// Which implementation of the filter's matrix arithmetic runs each step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FilterArithmetic {
    /// The flight path: block-structured propagation, update, referral and reset
    /// ([`crate::structured`]).
    #[default]
    Structured,
    /// The dense 24×24 reference (`discretise`, the dense predict and Joseph update,
    /// `refer_to_later_time`, `reset_dense`): equal within round-off, for comparisons.
    #[cfg(any(test, feature = "dense-reference"))]
    DenseReference,
}

/// What one propagation discretises.
#[derive(Debug, Clone, Copy)]
pub struct Propagation<'a> {
    /// The linearisation point (the strapdown step's output).
    pub point: &'a LinearisationPoint,
    /// The sensors' noise densities.
    pub noise: &'a ProcessNoise,
    /// The interval (s).
    pub interval_s: f64,
    /// The order of the discretisation series (1 to 4).
    pub order: u8,
    /// The blocks without process noise (frozen by the calibration manager).
    pub frozen: &'a BlockMask,
}

impl FilterArithmetic {
    /// One time update: the model discretised at `step.point` (into `model`, the flight
    /// path's reusable buffer), the frozen blocks' process noise removed, and `P ← F P Fᵀ + Qd`.
    ///
    /// # Errors
    /// As [`StructuredModel::rebuild`] and [`ErrorStateFilter::predict_structured`]; the
    /// filter is unchanged on an error.
    #[inline(always)]
    pub fn predict(
        self,
        filter: &mut ErrorStateFilter,
        model: &mut StructuredModel,
        step: &Propagation,
    ) -> Result<(), NavError> {
        match self {
            Self::Structured => {
                model.rebuild(step.point, step.noise, step.interval_s, step.order)?;
                // Tested here, inline: most frames freeze nothing and skip the call.
                if !step.frozen.is_empty() {
                    model.remove_process_noise(step.frozen);
                }
                filter.predict_structured(model)
            }
            #[cfg(any(test, feature = "dense-reference"))]
            Self::DenseReference => dense::predict(filter, step),
        }
    }

    /// Refers a measurement `latency_s` old to the current error state, `H ← H (I − A Δ)`
    /// with `A` at `point`, in place; the measurement is unchanged on an error.
    ///
    /// # Errors
    /// As [`refer_to_later_time_in_place`].
    #[inline(always)]
    pub fn refer_to_later_time(
        self,
        measurement: &mut LinearMeasurement,
        point: &LinearisationPoint,
        latency_s: f64,
    ) -> Result<(), NavError> {
        match self {
            Self::Structured => refer_to_later_time_in_place(measurement, point, latency_s),
            #[cfg(any(test, feature = "dense-reference"))]
            Self::DenseReference => dense::refer(measurement, point, latency_s),
        }
    }

    /// The gated Joseph-form update with the `frozen` blocks' gain zero.
    ///
    /// # Errors
    /// As [`ErrorStateFilter::update_structured`]; the filter is unchanged on any error.
    #[inline(always)]
    pub fn update(
        self,
        filter: &mut ErrorStateFilter,
        measurement: &LinearMeasurement,
        gate_nis: f64,
        frozen: &BlockMask,
    ) -> Result<InnovationReport, NavError> {
        match self {
            Self::Structured => filter.update_structured(measurement, gate_nis, frozen),
            #[cfg(any(test, feature = "dense-reference"))]
            Self::DenseReference => dense::update(filter, measurement, gate_nis, frozen),
        }
    }

    /// The closed-loop reset; returns the error state to feed back.
    #[inline(always)]
    pub fn reset(self, filter: &mut ErrorStateFilter) -> ErrorState {
        match self {
            Self::Structured => filter.reset(),
            #[cfg(any(test, feature = "dense-reference"))]
            Self::DenseReference => dense::reset(filter),
        }
    }

    /// The closed-loop reset for a caller that has read the error state already
    /// ([`ErrorStateFilter::reset_in_place`]).
    #[inline(always)]
    pub fn reset_in_place(self, filter: &mut ErrorStateFilter) {
        match self {
            Self::Structured => filter.reset_in_place(),
            #[cfg(any(test, feature = "dense-reference"))]
            Self::DenseReference => {
                dense::reset(filter);
            }
        }
    }
}

/// The dense branches, each in its own never-inlined function: inlined, their 24×24
/// temporaries (many times the flight path's own stack in the propagation) would be reserved
/// in the flight path's stack frames even where the flight path never takes them.
#[cfg(any(test, feature = "dense-reference"))]
mod dense {
    use super::{ErrorState, ErrorStateFilter, InnovationReport, Propagation};
    use crate::discretise::discretise;
    use crate::error_model::{noise_input_matrix, system_matrix, LinearisationPoint};
    use crate::measurement::{refer_to_later_time, LinearMeasurement};
    use crate::state::BlockMask;
    use crate::NavError;

    /// The dense model (process noise of the frozen blocks removed) and the dense predict.
    #[inline(never)]
    pub(super) fn predict(
        filter: &mut ErrorStateFilter,
        step: &Propagation,
    ) -> Result<(), NavError> {
        let mut model = discretise(
            &system_matrix(step.point),
            &noise_input_matrix(step.point),
            &step.noise.spectral_density_diagonal(),
            step.interval_s,
            step.order,
        )?;
        model.remove_process_noise(step.frozen);
        filter.predict(&model)
    }

    /// The referral with the dense `A`.
    #[inline(never)]
    pub(super) fn refer(
        measurement: &mut LinearMeasurement,
        point: &LinearisationPoint,
        latency_s: f64,
    ) -> Result<(), NavError> {
        *measurement = refer_to_later_time(measurement, &system_matrix(point), latency_s)?;
        Ok(())
    }

    /// The dense Joseph update.
    #[inline(never)]
    pub(super) fn update(
        filter: &mut ErrorStateFilter,
        measurement: &LinearMeasurement,
        gate_nis: f64,
        frozen: &BlockMask,
    ) -> Result<InnovationReport, NavError> {
        filter.update_with_frozen_blocks(measurement, gate_nis, frozen)
    }

    /// The dense reset.
    #[inline(never)]
    pub(super) fn reset(filter: &mut ErrorStateFilter) -> ErrorState {
        filter.reset_dense()
    }
}
