//! The campaign's rows, one file per family in row order: the control and non-finite rows,
//! the IMU, star-sensor, GNSS and timing rows, the correlated GNSS drift, the manoeuvres,
//! the IMU errors the filter does not model and a tracker with two heads.
//! Each row gives its injection times in seconds from the fault start, turned into frames by
//! the [`FrameSchedule`] of the flight's IMU rate.

mod drift;
mod gnss;
mod imu;
mod imu_model;
mod manoeuvre;
mod non_finite;
mod star;
mod star_heads;
mod timing;

use nalgebra::Vector3;
use nav_fsw::ports::ImuSample;

use super::injection::{
    both, gnss, imu, imu_field_injector, insert_segments, on_gnss, on_star, rotate_star, slew,
    star, thrust, FrameSchedule, GaussMarkovDrift, DRIFT_CORRELATION_TIME_S, DRIFT_SIGMA_M,
    NON_FINITE, SUBNORMAL,
};
use super::monitor::{counter, Counter, Criterion, Expected};
use super::{FaultClass, COUNT_MARGIN_S, FAULT_START_S, LONG_FLIGHT_S};
use crate::scenario::Scenario;

/// The campaign's fault classes, in row order, at the default scenario's IMU rate (the rows,
/// their names and their order do not depend on the rate; [`campaign_for`] for a scenario).
///
/// # Panics
/// Only if the built-in default scenario is broken, which the crate's tests rule out.
pub fn campaign() -> Vec<FaultClass> {
    let scenario = Scenario::default_scenario().expect("the built-in default scenario");
    campaign_for(&scenario)
}

/// The campaign's fault classes, in row order, injected at the frames of `scenario`'s IMU
/// rate.
pub fn campaign_for(scenario: &Scenario) -> Vec<FaultClass> {
    campaign_at(FrameSchedule::of(scenario))
}

/// The campaign's fault classes, in row order, for the frames of `frames`.
pub fn campaign_at(frames: FrameSchedule) -> Vec<FaultClass> {
    [
        non_finite::rows,
        imu::rows,
        star::rows,
        gnss::rows,
        timing::rows,
        drift::rows,
        manoeuvre::rows,
        imu_model::rows,
        star_heads::rows,
    ]
    .into_iter()
    .flat_map(|rows| rows(frames))
    .collect()
}
