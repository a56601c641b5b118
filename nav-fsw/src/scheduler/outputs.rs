//! The navigation solution, the frame telemetry and the optional state blocks' estimates on
//! the way out.

use super::*;
use crate::telemetry::{GnssErrorTelemetry, ImuErrorTelemetry, OptionalStateTelemetry};

/// 1σ of a variance (a negative variance, which the filter's floors prevent, reads as 0).
fn sigma_of(variance: f64) -> f64 {
    nav_core::float::sqrt(variance.max(0.0))
}

impl NavigationComputer {
    /// The best navigation solution (open loop: `x` applied on the way out).
    pub fn navigation(&self) -> NavigationState {
        let mut navigation = self.navigation.solution;
        if self.covariance.filter.mode() == FilterMode::OpenLoop {
            let mut calibration = self.calibration.estimate;
            let mut corrected = navigation;
            if apply_error_state(
                self.covariance.filter.state(),
                &mut corrected.attitude,
                &mut corrected.position_m,
                &mut corrected.velocity_mps,
                &mut calibration,
            )
            .is_ok()
            {
                navigation = corrected;
            }
        }
        navigation
    }

    pub(super) fn telemetry(&self, fusion: FrameFusion) -> FrameTelemetry {
        let navigation = self.navigation();
        let q = navigation.attitude;
        FrameTelemetry {
            frame: self.frame,
            time_s: navigation.time_s,
            attitude_wxyz: [q.w, q.i, q.j, q.k],
            position_m: array3(&navigation.position_m),
            velocity_mps: array3(&navigation.velocity_mps),
            fusion,
            last_star_nis: self.aids.star.last_nis,
            last_gnss_nis: self.aids.gnss.last_nis,
            last_gnss_velocity_nis: self.aids.gnss_velocity.last_nis,
            star_faulty: self.aids.star.faulty,
            gnss_faulty: self.aids.gnss.faulty,
            star_inconsistent: self.aids.star_consistency.failing(),
            gnss_inconsistent: self.aids.gnss_consistency.failing(),
            gnss_velocity_inconsistent: self.aids.gnss_velocity_consistency.failing(),
            converged_blocks: self.calibration.manager.table().converged_count(),
            frozen_blocks: self.calibration.manager.frozen_blocks().bits(),
            health: self.health.counters,
            commands: self.operations.commands,
            last_frame_cost: self.health.cost.last,
            worst_frame_cost: self.health.cost.worst,
        }
    }

    /// The estimates of the optional state blocks the filter flies, with their filter 1σ
    /// (square roots of the covariance diagonal); `None` for a block it does not fly. Read
    /// when they are reported, not in every frame (module docs of `crate::telemetry`). The
    /// systematic IMU errors are [`Self::imu_error_estimate`]'s (the fed-back corrections if
    /// the open-loop sum is not finite, as [`Self::calibration_estimate`] keeps them). Not
    /// inlined: the IMU block's covariance would take its place in the caller's stack frame,
    /// the frame loop's on the Cortex-M7.
    #[inline(never)]
    pub fn optional_states(&self) -> OptionalStateTelemetry {
        let filter = &self.covariance.filter;
        let gnss = filter.gnss_error();
        let gnss_error = gnss.is_enabled().then(|| {
            let variances = gnss.covariance().diagonal();
            GnssErrorTelemetry {
                estimate_m: array3(&gnss.estimate_m()),
                sigma_m: array3(&variances.map(sigma_of)),
            }
        });
        let imu = filter.imu_error();
        let imu_error = imu.is_enabled().then(|| {
            let estimate = self
                .imu_error_estimate()
                .unwrap_or(self.calibration.imu_errors);
            let sigma: [f64; 12] = imu.covariance().diagonal().map(sigma_of).into();
            let [g0, g1, g2, a0, a1, a2, a3, a4, a5, s0, s1, s2] = sigma;
            ImuErrorTelemetry {
                gyro_non_orthogonality_rad: estimate.gyro_non_orthogonality_rad.into(),
                gyro_non_orthogonality_sigma_rad: [g0, g1, g2],
                accel_misalignment_rad: estimate.accel_misalignment_rad.into(),
                accel_misalignment_sigma_rad: [a0, a1, a2, a3, a4, a5],
                gyro_g_sensitivity_rad_s_per_mps2: estimate
                    .gyro_g_sensitivity_rad_s_per_mps2
                    .into(),
                gyro_g_sensitivity_sigma_rad_s_per_mps2: [s0, s1, s2],
            }
        });
        OptionalStateTelemetry {
            gnss_error,
            imu_error,
        }
    }
}
