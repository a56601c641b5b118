//! Telemetry: the fixed-size record the flight software reports every frame (or every N
//! frames, as the caller chooses): navigation solution, health counters, sensor states and
//! the frame-cost monitor. A plain `Copy` struct always; `defmt::Format` with the `defmt`
//! feature.
//!
//! The optional state blocks' estimates with their 1σ ([`OptionalStateTelemetry`]) are read
//! when they are reported (`NavigationComputer::optional_states`), not built in every frame:
//! their fifteen square roots and the IMU block's covariance are paid only by the frames the
//! caller reports.

use crate::health::HealthCounters;

/// What happened to the measurements in one frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FrameFusion {
    /// No measurement was fused.
    #[default]
    None,
    /// A star-sensor update was accepted.
    StarAccepted,
    /// A star-sensor measurement was rejected (gate, jump or fault).
    StarRejected,
    /// A GNSS update was accepted.
    GnssAccepted,
    /// A GNSS fix was rejected (gate, jump or fault).
    GnssRejected,
    /// A GNSS velocity update was accepted.
    GnssVelocityAccepted,
    /// A GNSS velocity was rejected (gate or fault).
    GnssVelocityRejected,
}

/// One telemetry record.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FrameTelemetry {
    /// Minor-frame counter (wraps).
    pub frame: u32,
    /// Navigation time at the end of the frame (s).
    pub time_s: f64,
    /// Best attitude estimate `q_ib` `[w, x, y, z]`.
    pub attitude_wxyz: [f64; 4],
    /// Best position estimate, launch-inertial (m).
    pub position_m: [f64; 3],
    /// Best velocity estimate, launch-inertial (m/s).
    pub velocity_mps: [f64; 3],
    /// Measurement fused this frame.
    pub fusion: FrameFusion,
    /// NIS of the last star-sensor measurement tested.
    pub last_star_nis: f64,
    /// NIS of the last GNSS fix tested.
    pub last_gnss_nis: f64,
    /// NIS of the last GNSS velocity tested.
    pub last_gnss_velocity_nis: f64,
    /// The star sensor is declared faulty.
    pub star_faulty: bool,
    /// The GNSS receiver is declared faulty.
    pub gnss_faulty: bool,
    /// Whether the star consistency monitor's last window failed.
    pub star_inconsistent: bool,
    /// Whether the GNSS position consistency monitor's last window failed.
    pub gnss_inconsistent: bool,
    /// Whether the GNSS velocity consistency monitor's last window failed.
    pub gnss_velocity_inconsistent: bool,
    /// Calibration blocks converged so far.
    pub converged_blocks: u32,
    /// Blocks frozen now ([`nav_core::state::BlockMask`] bits).
    pub frozen_blocks: u8,
    /// Fault and action counters.
    pub health: HealthCounters,
    /// Commands executed and refused (`NavigationComputer::command`).
    pub commands: crate::scheduler::CommandCounters,
    /// Cost of the previous frame as reported by the platform (instructions or cycles).
    pub last_frame_cost: u32,
    /// Worst reported frame cost so far.
    pub worst_frame_cost: u32,
}

/// Names of the correlated GNSS error fields (estimates, then 1σ; launch-inertial axes), as
/// the output record and the replay CSV name them: [`GnssErrorTelemetry::values`] order.
pub const GNSS_ERROR_FIELD_NAMES: [&str; 6] = [
    "gnss_error_x_m",
    "gnss_error_y_m",
    "gnss_error_z_m",
    "gnss_error_sigma_x_m",
    "gnss_error_sigma_y_m",
    "gnss_error_sigma_z_m",
];

/// Names of the systematic IMU error fields (per block its estimates, then their 1σ; nav-core
/// `ImuErrorBlock` names and components), as the output record and the replay CSV name them:
/// [`ImuErrorTelemetry::values`] order.
pub const IMU_ERROR_FIELD_NAMES: [&str; 24] = [
    "gyro_non_orthogonality_yx_rad",
    "gyro_non_orthogonality_zx_rad",
    "gyro_non_orthogonality_zy_rad",
    "gyro_non_orthogonality_sigma_yx_rad",
    "gyro_non_orthogonality_sigma_zx_rad",
    "gyro_non_orthogonality_sigma_zy_rad",
    "accel_misalignment_xy_rad",
    "accel_misalignment_xz_rad",
    "accel_misalignment_yx_rad",
    "accel_misalignment_yz_rad",
    "accel_misalignment_zx_rad",
    "accel_misalignment_zy_rad",
    "accel_misalignment_sigma_xy_rad",
    "accel_misalignment_sigma_xz_rad",
    "accel_misalignment_sigma_yx_rad",
    "accel_misalignment_sigma_yz_rad",
    "accel_misalignment_sigma_zx_rad",
    "accel_misalignment_sigma_zy_rad",
    "gyro_g_sensitivity_x_rad_s_per_mps2",
    "gyro_g_sensitivity_y_rad_s_per_mps2",
    "gyro_g_sensitivity_z_rad_s_per_mps2",
    "gyro_g_sensitivity_sigma_x_rad_s_per_mps2",
    "gyro_g_sensitivity_sigma_y_rad_s_per_mps2",
    "gyro_g_sensitivity_sigma_z_rad_s_per_mps2",
];

/// The estimates of the optional state blocks with their filter 1σ; a block the filter does
/// not fly is `None`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct OptionalStateTelemetry {
    /// The correlated GNSS error states (nav-core `gnss_error`).
    pub gnss_error: Option<GnssErrorTelemetry>,
    /// The systematic IMU error states (nav-core `imu_error_states`).
    pub imu_error: Option<ImuErrorTelemetry>,
}

/// The correlated GNSS position error: the estimate `ε̂` and its 1σ (launch-inertial axes).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GnssErrorTelemetry {
    /// Estimate (m).
    pub estimate_m: [f64; 3],
    /// Filter 1σ (m).
    pub sigma_m: [f64; 3],
}

impl GnssErrorTelemetry {
    /// The fields in [`GNSS_ERROR_FIELD_NAMES`] order.
    pub fn values(&self) -> [f64; 6] {
        let [x, y, z] = self.estimate_m;
        let [sx, sy, sz] = self.sigma_m;
        [x, y, z, sx, sy, sz]
    }
}

/// The systematic IMU errors in the filter's gauge (nav-core `imu_error`; the fed-back
/// corrections in closed loop, with the filter's current estimate in open loop) and their
/// filter 1σ. Components in nav-core's order: gyro non-orthogonality `yx, zx, zy`,
/// accelerometer misalignment `xy, xz, yx, yz, zx, zy`, g-sensitivity `x, y, z`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ImuErrorTelemetry {
    /// Gyro non-orthogonality (rad).
    pub gyro_non_orthogonality_rad: [f64; 3],
    /// Its filter 1σ (rad).
    pub gyro_non_orthogonality_sigma_rad: [f64; 3],
    /// Accelerometer misalignment (rad).
    pub accel_misalignment_rad: [f64; 6],
    /// Its filter 1σ (rad).
    pub accel_misalignment_sigma_rad: [f64; 6],
    /// Gyro g-sensitivity (rad/s per m/s²).
    pub gyro_g_sensitivity_rad_s_per_mps2: [f64; 3],
    /// Its filter 1σ (rad/s per m/s²).
    pub gyro_g_sensitivity_sigma_rad_s_per_mps2: [f64; 3],
}

impl ImuErrorTelemetry {
    /// The fields in [`IMU_ERROR_FIELD_NAMES`] order.
    pub fn values(&self) -> [f64; 24] {
        let mut values = [0.0; 24];
        let fields = [
            self.gyro_non_orthogonality_rad.as_slice(),
            &self.gyro_non_orthogonality_sigma_rad,
            &self.accel_misalignment_rad,
            &self.accel_misalignment_sigma_rad,
            &self.gyro_g_sensitivity_rad_s_per_mps2,
            &self.gyro_g_sensitivity_sigma_rad_s_per_mps2,
        ];
        for (slot, value) in values.iter_mut().zip(fields.into_iter().flatten()) {
            *slot = *value;
        }
        values
    }

    /// The twelve estimates in nav-core's state order (`ImuErrorBlock` order).
    pub fn estimates(&self) -> [f64; 12] {
        self.in_state_order(false)
    }

    /// The twelve 1σ in nav-core's state order.
    pub fn sigmas(&self) -> [f64; 12] {
        self.in_state_order(true)
    }

    fn in_state_order(&self, sigma: bool) -> [f64; 12] {
        let values = self.values();
        // Per block: its estimates, then its 1σ (block sizes 3, 6, 3).
        let blocks = [(0, 3), (6, 6), (18, 3)];
        let mut states = [0.0; 12];
        let picked = blocks.iter().flat_map(|&(start, size)| {
            let first = if sigma { start + size } else { start };
            values.iter().skip(first).take(size)
        });
        for (slot, value) in states.iter_mut().zip(picked) {
            *slot = *value;
        }
        states
    }
}

/// Frame-cost monitor: the platform measures each frame (SysTick, cycle counter) and reports
/// it; frames over the budget are counted as overruns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FrameCostMonitor {
    /// Budget per frame (same unit as the reports).
    pub budget: u32,
    /// Last reported cost.
    pub last: u32,
    /// Worst reported cost.
    pub worst: u32,
    /// Frames over the budget.
    pub overruns: u32,
}

impl FrameCostMonitor {
    /// A monitor with a budget per frame.
    pub const fn new(budget: u32) -> Self {
        Self {
            budget,
            last: 0,
            worst: 0,
            overruns: 0,
        }
    }

    /// Records one frame's cost; returns true if it overran the budget.
    pub fn record(&mut self, cost: u32) -> bool {
        self.last = cost;
        self.worst = self.worst.max(cost);
        let overrun = cost > self.budget;
        if overrun {
            self.overruns = self.overruns.saturating_add(1);
        }
        overrun
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_monitor_keeps_the_worst_and_counts_overruns() {
        let mut monitor = FrameCostMonitor::new(100);
        assert!(!monitor.record(40));
        assert!(monitor.record(120));
        assert!(!monitor.record(100));
        assert_eq!(
            (monitor.last, monitor.worst, monitor.overruns),
            (100, 120, 1)
        );
    }
}
