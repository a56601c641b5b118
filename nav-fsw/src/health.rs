//! Health telemetry counters: every detected fault and every protective action is counted
//! here (saturating, so a counter never wraps back to a healthy-looking value).

/// Fault and action counters, reported in the health telemetry.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HealthCounters {
    /// IMU samples with NaN/Inf fields.
    pub imu_non_finite: u32,
    /// IMU samples beyond the saturation limits.
    pub imu_saturated: u32,
    /// Repeated IMU samples (same sequence number).
    pub imu_duplicate: u32,
    /// IMU samples missing (sequence gaps and frames with no sample).
    pub imu_missing: u32,
    /// IMU time-tag jumps (zero, negative or wrong step).
    pub imu_time_jump: u32,
    /// Star measurements rejected as non-finite.
    pub star_non_finite: u32,
    /// Star quaternions rejected as not unit (zero included).
    pub star_not_unit: u32,
    /// Sign changes of the star quaternion between consecutive samples (q and −q are one
    /// attitude: undone, and harmless; a sensor that keeps w ≥ 0 changes sign twice per turn).
    pub star_sign_flip: u32,
    /// GNSS fixes rejected as non-finite.
    pub gnss_non_finite: u32,
    /// GNSS fixes rejected as jumps.
    pub gnss_jump: u32,
    /// Measurements older than the allowed latency, or older than the last fused one.
    pub measurement_stale: u32,
    /// Measurements time-tagged in the future.
    pub measurement_future: u32,
    /// Measurements dropped because their buffer was full.
    pub measurement_overflow: u32,
    /// Star updates rejected by the innovation gate.
    pub star_gate_rejections: u32,
    /// GNSS updates rejected by the innovation gate.
    pub gnss_gate_rejections: u32,
    /// Covariance repairs (variance clamped to its floor or ceiling).
    pub covariance_clamps: u32,
    /// Filter resets after a non-finite state or covariance.
    pub filter_resets: u32,
    /// Frames whose work exceeded the frame budget.
    pub frame_overruns: u32,
    /// Times the star sensor was declared faulty (consecutive rejections).
    pub star_declared_faulty: u32,
    /// Times the GNSS receiver was declared faulty (consecutive rejections).
    pub gnss_declared_faulty: u32,
    /// Measurements discarded because their sensor is declared faulty.
    pub ignored_from_faulty_sensor: u32,
    /// Filter operations refused by nav-core (measurement model or update errors).
    pub filter_errors: u32,
    /// Strapdown steps refused (the navigation state was held).
    pub strapdown_failures: u32,
}

/// Adds one to a counter without wrapping.
#[inline]
pub fn count(counter: &mut u32) {
    *counter = counter.saturating_add(1);
}
