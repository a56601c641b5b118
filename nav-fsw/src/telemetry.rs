//! Telemetry: the fixed-size record the flight software reports every frame (or every N
//! frames, as the caller chooses): navigation solution, health counters, sensor states and
//! the frame-cost monitor. A plain `Copy` struct always; `defmt::Format` with the `defmt`
//! feature.

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
    /// Cost of the previous frame as reported by the platform (instructions or cycles).
    pub last_frame_cost: u32,
    /// Worst reported frame cost so far.
    pub worst_frame_cost: u32,
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
