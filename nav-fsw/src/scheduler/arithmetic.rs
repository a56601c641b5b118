//! The choice of filter arithmetic: the block-structured flight path or the dense reference.

use super::*;

/// Which implementation of the filter's matrix arithmetic the scheduler uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FilterArithmetic {
    /// The flight path: block-structured propagation, update, referral and reset
    /// (nav-core `structured`).
    #[default]
    Structured,
    /// The dense 24×24 reference (nav-core `discretise`, `predict`, Joseph update,
    /// `refer_to_later_time`, `reset_dense`): equal within round-off, for cost comparisons.
    DenseReference,
}

// The dense reference paths (cost comparisons only) live in their own never-inlined
// functions: inlined, their 24×24 temporaries (84 KB in `propagate_covariance`) would be
// reserved in the flight path's stack frames even though flight never takes these branches.

/// Dense reference propagation ([`FilterArithmetic::DenseReference`]).
#[inline(never)]
pub(super) fn dense_predict(
    filter: &mut ErrorStateFilter,
    point: &LinearisationPoint,
    noise: &nav_core::error_model::ProcessNoise,
    interval_s: f64,
    order: u8,
    frozen: &BlockMask,
) -> Result<(), NavError> {
    dense_model(point, noise, interval_s, order, frozen).and_then(|model| filter.predict(&model))
}

/// Dense reference late-measurement referral.
#[inline(never)]
pub(super) fn dense_referral(
    measurement: &mut LinearMeasurement,
    point: &LinearisationPoint,
    latency_s: f64,
) -> Result<(), NavError> {
    *measurement = refer_to_later_time(measurement, &system_matrix(point), latency_s)?;
    Ok(())
}

/// Dense reference Joseph update.
#[inline(never)]
pub(super) fn dense_update(
    filter: &mut ErrorStateFilter,
    measurement: &LinearMeasurement,
    gate: f64,
    frozen: &BlockMask,
) -> Result<nav_core::filter::InnovationReport, NavError> {
    filter.update_with_frozen_blocks(measurement, gate, frozen)
}

/// Dense reference reset.
#[inline(never)]
pub(super) fn dense_reset(filter: &mut ErrorStateFilter) -> nav_core::filter::ErrorState {
    filter.reset_dense()
}

/// The dense reference discrete model with the process noise of the `frozen` blocks removed
/// (as [`StructuredModel::remove_process_noise`]).
pub(super) fn dense_model(
    point: &LinearisationPoint,
    noise: &nav_core::error_model::ProcessNoise,
    interval_s: f64,
    order: u8,
    frozen: &BlockMask,
) -> Result<DiscreteModel, NavError> {
    let mut model = discretise(
        &system_matrix(point),
        &noise_input_matrix(point),
        &noise.spectral_density_diagonal(),
        interval_s,
        order,
    )?;
    model.remove_process_noise(frozen);
    Ok(model)
}
