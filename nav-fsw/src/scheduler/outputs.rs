//! The navigation solution and the frame telemetry on the way out.

use super::*;

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
            last_frame_cost: self.health.cost.last,
            worst_frame_cost: self.health.cost.worst,
        }
    }
}
