//! The GNSS receiver's data sheet (white and correlated position error, velocity, latency)
//! and the antenna's lever arm, and their conversions to the flight software's settings.

use crate::config::{FswConfig, Param};

/// The measurement history's latency window for a receiver of latency `latency_s` at the
/// IMU period `period_s`: the configured window `window_s`, widened to the latency plus one
/// frame (the fix is handed over in the frame after it arrives). The window is a buffer
/// length, not a model the filter assumes; a fix older than it would be dropped rather than
/// fused late.
pub fn latency_window_s(window_s: f64, latency_s: f64, period_s: f64) -> f64 {
    window_s.max(latency_s + period_s)
}

/// A receiver's correlated position error, which the flight carries in three first-order
/// Gauss–Markov error states.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GnssCorrelatedError {
    /// Stationary 1σ per ECEF axis (m).
    pub sigma_m: f64,
    /// Its correlation time (s), > 0.
    pub correlation_time_s: f64,
}

/// The GNSS receiver's data sheet. Figures are 1σ per ECEF axis: a data sheet's 3-D RMS
/// is `√3` times it, a spherical error probable (SEP, 50 %) 1.538 times it (the median of a
/// χ with three degrees of freedom).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GnssDatasheet {
    /// White position noise, 1σ per axis (m).
    pub position_noise_m: f64,
    /// The slowly varying part of the position error (ephemeris, ionosphere, multipath);
    /// `None` = white errors only.
    pub correlated_error: Option<GnssCorrelatedError>,
    /// White velocity noise, 1σ per axis (m/s); `None` = the receiver outputs no velocity.
    pub velocity_noise_mps: Option<f64>,
    /// Delivery latency: a fix valid at `t` reaches the flight computer at `t + latency_s`.
    pub latency_s: f64,
    /// The antenna's phase centre from the IMU, body axes (m), from the drawings.
    pub antenna_lever_arm_m: [f64; 3],
}

impl GnssDatasheet {
    /// The receiver's settings: white noise, velocity noise (0 without: no velocity
    /// fusion), lever arm, the correlated-error states when a correlated error is given,
    /// and the latency window ([`latency_window_s`]) at the IMU's period (the IMU's table
    /// is applied first).
    pub(super) fn apply(&self, config: &mut FswConfig) {
        let gnss = &mut config.gnss;
        gnss.noise_m = self.position_noise_m;
        gnss.velocity_noise_mps = self.velocity_noise_mps.unwrap_or(0.0);
        gnss.lever_arm_body_m = self.antenna_lever_arm_m;
        let error = &mut config.filter.gnss_error;
        (error.sigma_m, error.correlation_time_s) = self
            .correlated_error
            .map_or((0.0, 0.0), |gm| (gm.sigma_m, gm.correlation_time_s));
        config.timing.max_latency_s = latency_window_s(
            config.timing.max_latency_s,
            self.latency_s,
            config.imu.period_s,
        );
    }
}

/// The GNSS data-sheet field behind a flight parameter.
pub(super) fn field_of(param: Param) -> Option<&'static str> {
    use Param as P;
    Some(match param {
        P::GnssNoise => "gnss.position_noise_m",
        P::GnssVelocityNoise => "gnss.velocity_noise_mps",
        P::GnssCorrelatedSigma => "gnss.correlated_error.sigma_m",
        P::GnssCorrelationTime => "gnss.correlated_error.correlation_time_s",
        P::MaxLatency => "gnss.latency_s",
        P::GnssLeverArmX | P::GnssLeverArmY | P::GnssLeverArmZ => "gnss.antenna_lever_arm_m",
        _ => return None,
    })
}
