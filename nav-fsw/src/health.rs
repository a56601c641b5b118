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
    /// Repeated IMU samples (same sequence number) and late, out-of-order ones.
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
    /// GNSS velocity updates rejected by the innovation gate.
    pub gnss_velocity_gate_rejections: u32,
    /// Frames whose IMU sample was held (missing or refused), each adding the held sample's
    /// uncertainty to the covariance.
    pub imu_held_frames: u32,
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
    /// Star-sensor outages: no measurement received for longer than
    /// `timing.outage_timeout_s` (counted once per outage, when the timeout elapses).
    pub star_outages: u32,
    /// GNSS outages, as [`HealthCounters::star_outages`].
    pub gnss_outages: u32,
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

/// Detects an aiding-sensor outage: the sensor silent for longer than a timeout. Reports each
/// outage once, when the timeout elapses; a message ends it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct OutageMonitor {
    last_heard_s: Option<f64>,
    in_outage: bool,
}

impl OutageMonitor {
    /// Called once a frame with the navigation time and whether the sensor delivered anything
    /// (valid or not) in the frame; true when a new outage has just begun. The first call
    /// starts the clock (a sensor that never speaks is an outage too).
    pub fn observe(&mut self, now_s: f64, heard: bool, timeout_s: f64) -> bool {
        let last = *self.last_heard_s.get_or_insert(now_s);
        if heard {
            self.last_heard_s = Some(now_s);
            self.in_outage = false;
            return false;
        }
        let began = !self.in_outage && now_s - last > timeout_s;
        self.in_outage |= began;
        began
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_outage_is_reported_once_when_its_timeout_elapses() {
        let mut monitor = OutageMonitor::default();
        let reports: usize = (0..100)
            .map(|frame| {
                let now_s = f64::from(frame) * 0.1;
                // Heard every frame, then silent from 1.0 s to 5.0 s, then heard again.
                let heard = !(10..50).contains(&frame);
                usize::from(monitor.observe(now_s, heard, 2.0))
            })
            .sum();
        assert_eq!(reports, 1);
        let mut short = OutageMonitor::default();
        let reports: usize = (0..100)
            .map(|frame| {
                let heard = !(10..25).contains(&frame); // 1.6 s of silence: within 2 s
                usize::from(short.observe(f64::from(frame) * 0.1, heard, 2.0))
            })
            .sum();
        assert_eq!(reports, 0);
    }

    /// Mutation-testing boundaries: counters saturate, and silence of exactly the timeout is
    /// not yet an outage.
    #[test]
    fn counters_saturate_and_an_outage_needs_more_than_the_timeout() {
        let mut counter = u32::MAX - 1;
        count(&mut counter);
        assert_eq!(counter, u32::MAX);
        count(&mut counter);
        assert_eq!(counter, u32::MAX);
        let mut monitor = OutageMonitor::default();
        assert!(!monitor.observe(0.0, true, 2.0));
        assert!(!monitor.observe(2.0, false, 2.0));
        assert!(monitor.observe(2.5, false, 2.0));
    }
}
