//! The ranges several flight parameters share, each with its reason (the parameter table,
//! `parameters.rs`, uses them).

use core::f64::consts::PI;

use super::range::Range;

/// The correlation time of every first-order Gauss–Markov error the filter is told of (s):
/// the GNSS receiver's correlated error, the star tracker's slow error, and nav-sim's
/// `[filter.bias_instability]`.
pub const CORRELATION_TIME_RANGE_S: Range = Range::new(1.0, 1.0e8).or_off();

/// Why [`CORRELATION_TIME_RANGE_S`]: the filter carries the error as a walk of density
/// `2σ²/τ`, so a τ of 1e-300 s makes that walk 1e300 times the variance per second and the
/// covariance is clamped every frame.
pub const CORRELATION_TIME_WHY: &str = "below 1 s (500 frames) the error is white noise to \
     the filter, whose walk 2 sigma^2 / tau would swamp the covariance every frame; beyond 1e8 s \
     (three years) it is a constant over any flight: 0 (off) leaves it to the constant states";

/// Every χ²(3) innovation gate.
pub(super) const GATE: Range = Range::new(1.0, 1.0e6).or_no_gate();
pub(super) const GATE_WHY: &str = "a chi-square(3) point: below 1 it rejects four consistent \
     measurements in five; above 1e6 it gates nothing a sensor can produce, say +inf";

/// A component of a unit quaternion (the norm is checked with the whole quaternion).
pub(super) const UNIT: Range = Range::new(-1.0, 1.0);
pub(super) const UNIT_WHY: &str =
    "a component of a unit quaternion (norm within 1e-9 of 1, checked \
     with the whole quaternion)";

/// A white noise 1σ the filter squares into `R`: never 0 (a singular innovation covariance).
pub(super) const STAR_NOISE: Range = Range::new(1.0e-12, 1.0e-1);
pub(super) const STAR_NOISE_WHY: &str =
    "1e-12 rad is the floor nav-sim gives a noiseless test tracker; \
     1e-1 rad (6 deg) is no star tracker";

pub(super) const ATTITUDE_SIGMA: Range = Range::new(1.0e-9, PI);
pub(super) const ATTITUDE_WHY: &str =
    "a rotation angle: below 1 nrad no sensor resolves it, beyond pi it \
     wraps";
pub(super) const GYRO_BIAS_SIGMA: Range = Range::new(1.0e-12, 1.0e-1);
pub(super) const GYRO_BIAS_WHY: &str = "1e-12 rad/s is far below the best gyro; 1e-1 rad/s \
     (20,000 deg/h) far beyond any";
pub(super) const ACCEL_BIAS_SIGMA: Range = Range::new(1.0e-9, 10.0);
pub(super) const ACCEL_BIAS_WHY: &str =
    "1e-9 m/s^2 is far below the best accelerometer; 10 m/s^2 is 1 g";
pub(super) const SCALE_SIGMA: Range = Range::new(1.0e-12, 0.1);
pub(super) const SCALE_WHY: &str =
    "a relative error: down to 1e-12, a prior so small that no update moves the state \
     (the calibration switched off, as nav-sim's benefit study flies it); 0.1 is nav-sim's \
     largest truth scale factor and beyond the linear model";
/// The star-sensor installation prior: a rotation angle, or a prior so small that the
/// calibration of the installation is switched off.
pub(super) const INSTALLATION_SIGMA: Range = Range::new(1.0e-12, PI);
pub(super) const INSTALLATION_WHY: &str =
    "a rotation angle: down to 1e-12 rad, a prior so small that no update moves the state \
     (the calibration switched off, as nav-sim's benefit study flies it); beyond pi it wraps";
pub(super) const FLOOR_WHY: &str =
    "from a numerical guard far below every sensor's accuracy to the \
     block's largest initial 1-sigma";
pub(super) const THRESHOLD_WHY: &str =
    "a calibration accuracy, within the block's initial 1-sigma range";

/// Gyro and accelerometer noise densities (0: the noise is not modelled).
pub(super) const GYRO_NOISE_WHY: &str = "1e-12 rad/s/sqrt(Hz) is far below the best gyro, 1e-1 \
     (20,000 deg/h/sqrt(Hz)) no gyro";
pub(super) const ACCEL_NOISE_WHY: &str =
    "1e-12 m/s^2/sqrt(Hz) is far below the best accelerometer, 10 is \
     no accelerometer";
pub(super) const WALK_WHY: &str =
    "a bias random walk, with nav-sim's bias instability 2 sigma^2 / tau \
     added: the largest instability 1-sigma over the shortest correlation time stays inside";

pub(super) const MISALIGNMENT_SIGMA: Range = Range::new(1.0e-9, 1.0e-2).or_off();
pub(super) const MISALIGNMENT_WHY: &str =
    "the model is the small-angle I + A: navigation-grade triads are \
     5-20 urad, tactical ones 100 urad and more; 1 rad is no small angle";
pub(super) const SLOW_ERROR_SIGMA: Range = Range::new(1.0e-9, 1.0e-2).or_off();
pub(super) const SLOW_ERROR_WHY: &str = "a tracker's thermo-elastic error is arcseconds: 1e-2 rad \
     (34 arcmin) is no tracker";
