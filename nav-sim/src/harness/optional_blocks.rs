//! The filter's optional state blocks at the end of a flight: per block the final error
//! (truth − estimate) and covariance, what the Monte Carlo report and `nav-sim calibrate`
//! test them with. The systematic IMU errors' truth is in the filter's gauge
//! ([`crate::harness::filter_gauge`]); the correlated GNSS error's is the receiver's correlated
//! position error at the covariance's time, in launch-inertial axes (the filter's `ε`: the
//! fix is the true position plus it).

use nalgebra::{SMatrix, SVector, Vector3};
use nav_core::imu_error::{ImuErrorEstimate, IMU_ERROR_DIMENSION};
use nav_core::NavError;
use nav_fsw::scheduler::NavigationComputer;

use crate::harness::filter_gauge::imu_error_vector;
use crate::world::simulation::Simulation;

/// The final error and covariance of one optional state block of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockOutcome<const N: usize> {
    /// Truth − estimate, in the block's state order.
    pub error: SVector<f64, N>,
    /// The filter's covariance of the block's states.
    pub covariance: SMatrix<f64, N, N>,
}

impl<const N: usize> BlockOutcome<N> {
    /// The NEES of the block ([`nees`]).
    pub fn nees(&self) -> Option<f64> {
        nees(&self.error, &self.covariance)
    }
}

/// The NEES `eᵀ P⁻¹ e` of an error and its covariance, or `None` if the covariance is not
/// positive definite.
pub fn nees<const N: usize>(
    error: &SVector<f64, N>,
    covariance: &SMatrix<f64, N, N>,
) -> Option<f64> {
    // eᵀ P⁻¹ e = |L⁻¹ e|² with P = L Lᵀ.
    let cholesky = covariance.cholesky()?;
    let whitened = cholesky.l().solve_lower_triangular(error)?;
    Some(whitened.norm_squared())
}

/// The twelve systematic IMU error states' outcome (truth in the filter's gauge − estimate,
/// nav-core `ImuErrorBlock` order).
pub type ImuErrorOutcome = BlockOutcome<IMU_ERROR_DIMENSION>;
/// The correlated GNSS error states' outcome (m, launch-inertial axes).
pub type GnssErrorOutcome = BlockOutcome<3>;

/// The systematic IMU error states' final error (truth in the filter's gauge − estimate) and
/// covariance, or `None` without a truth in the gauge (the states not flown).
///
/// # Errors
/// nav-core's error if the open-loop estimate is not finite.
pub fn imu_error_outcome(
    computer: &NavigationComputer,
    truth: Option<&ImuErrorEstimate>,
) -> Result<Option<ImuErrorOutcome>, NavError> {
    let Some(truth) = truth else {
        return Ok(None);
    };
    let estimate = computer.imu_error_estimate()?;
    Ok(Some(BlockOutcome {
        error: imu_error_vector(truth) - imu_error_vector(&estimate),
        covariance: computer.filter().imu_error().covariance(),
    }))
}

/// The correlated GNSS error states' final error (the receiver's correlated error at the
/// covariance's time, launch-inertial − estimate) and covariance, or `None` when the filter
/// does not fly them.
///
/// # Errors
/// nav-core's error for a non-finite truth or time.
pub fn gnss_error_outcome(
    computer: &NavigationComputer,
    simulation: &Simulation,
) -> Result<Option<GnssErrorOutcome>, NavError> {
    let states = computer.filter().gnss_error();
    if !states.is_enabled() {
        return Ok(None);
    }
    let time_s = computer.covariance_time_s();
    let truth_ecef_m = simulation.gnss_correlated_error_ecef_m(time_s);
    let truth_m = ecef_offset_to_launch_inertial(computer, &truth_ecef_m, time_s)?;
    Ok(Some(BlockOutcome {
        error: truth_m - states.estimate_m(),
        covariance: states.covariance(),
    }))
}

/// An ECEF offset (a difference of two positions) in launch-inertial axes at navigation time
/// `time_s`, by the flight software's own frame: the image of the offset minus the image of
/// the ECEF origin.
fn ecef_offset_to_launch_inertial(
    computer: &NavigationComputer,
    offset_ecef_m: &Vector3<f64>,
    time_s: f64,
) -> Result<Vector3<f64>, NavError> {
    let frame = computer.launch_frame();
    Ok(frame.ecef_to_launch_inertial(offset_ecef_m, time_s)?
        - frame.ecef_to_launch_inertial(&Vector3::zeros(), time_s)?)
}
