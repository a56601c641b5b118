//! The IMU's data sheet (gyro and accelerometer triads) and its conversions to the filter's
//! process noise, bias and scale-factor priors, bias instability and systematic error states.

use super::{PER_MILLION, SECONDS_PER_HOUR, SQRT_SECONDS_PER_SQRT_HOUR};
use crate::config::{FswConfig, Param};

/// Standard gravity (m/s² per g): the conventional `g` of data sheets (3rd CGPM, 1901).
pub const STANDARD_GRAVITY_MPS2: f64 = 9.80665;

/// The peak of a first-order Gauss–Markov process's Allan deviation per unit of its
/// stationary 1σ (0.6174 to four digits), reached at [`ALLAN_PEAK_TAU_PER_CORRELATION_TIME`]
/// times its correlation time ([`gauss_markov_from_allan_floor`]).
pub const ALLAN_PEAK_PER_SIGMA: f64 = 0.617_364;

/// The averaging time of that peak per unit of the correlation time (1.893 to four digits).
pub const ALLAN_PEAK_TAU_PER_CORRELATION_TIME: f64 = 1.892_78;

/// A rate in degrees per hour in rad/s: `x · π/180 / 3600` (also a density in
/// (°/h)/√Hz in rad/s/√Hz = rad/√s). nav-sim's gyro noise key uses it, so the two agree bit
/// for bit.
pub fn deg_per_h_to_rad_per_s(deg_per_h: f64) -> f64 {
    deg_per_h.to_radians() / SECONDS_PER_HOUR
}

/// A specific force in µg in m/s²: `x · g / 10⁶` with the standard `g`.
fn ug_to_mps2(ug: f64) -> f64 {
    ug * STANDARD_GRAVITY_MPS2 / PER_MILLION
}

/// The bias random-walk density the filter uses for a walk of density `walk` plus a
/// first-order Gauss–Markov bias of stationary 1σ `sigma` and correlation time `tau_s`:
/// `√(walk² + 2σ²/τ)`, the density of the white noise that drives the Gauss–Markov bias
/// (`ḃ = −b/τ + w`, stationary variance `qτ/2 = σ²`). With the prior of
/// [`bias_prior_with_instability`] the walk bounds the Gauss–Markov bias's covariance at
/// every set of times (docs/guide/model.md, "Bias instability in the filter"). With the
/// instability off the walk is returned unchanged (the paper's model keeps its bits).
pub fn bias_walk_with_instability(walk: f64, sigma: f64, tau_s: f64) -> f64 {
    if sigma > 0.0 && tau_s > 0.0 {
        nav_core::float::sqrt(walk * walk + 2.0 * sigma * sigma / tau_s)
    } else {
        walk
    }
}

/// The bias's prior 1σ for a constant part of 1σ `constant_sigma` and a Gauss–Markov part of
/// stationary 1σ `sigma`: `√(σ_c² + 2σ²)`. A walk driven by the Gauss–Markov bias's noise
/// and started with `2σ²` of variance is that bias plus an independent process (a copy of
/// `b(0) + (1/τ)∫₀ᵗ b du`, whose covariance is `σ²(2 − e^(−|t−s|/τ)) + (2σ²/τ) min(s, t)`),
/// so every combination of the bias at any times has at least its true variance; with less
/// than `2σ²` some has not (docs/guide/model.md, "Bias instability in the filter"). With the
/// instability off the 1σ is returned unchanged.
pub fn bias_prior_with_instability(constant_sigma: f64, sigma: f64, tau_s: f64) -> f64 {
    if sigma > 0.0 && tau_s > 0.0 {
        nav_core::float::sqrt(constant_sigma * constant_sigma + 2.0 * sigma * sigma)
    } else {
        constant_sigma
    }
}

/// The first-order Gauss–Markov bias `(σ, τ_s)` whose Allan deviation peaks at a data
/// sheet's bias-instability floor `floor` (any unit; `σ` in the same) reached at the
/// averaging time `averaging_time_s`. Such a bias has the Allan variance
/// `σ² (τ/t)² (2t/τ − 3 + 4e^(−t/τ) − e^(−2t/τ))` at averaging time `t` (the Markov-noise
/// term of IEEE Std 952-1997, Annex C, with the white driving density `2σ²/τ`), whose
/// maximum is [`ALLAN_PEAK_PER_SIGMA`]` · σ` at `t` = [`ALLAN_PEAK_TAU_PER_CORRELATION_TIME`]
/// `· τ`. A data sheet's "bias instability" is that floor (as IEEE Std 952's flicker-noise
/// floor, a multiple of the flicker coefficient, is read): the Gauss–Markov 1σ is 1.62
/// times it.
pub fn gauss_markov_from_allan_floor(floor: f64, averaging_time_s: f64) -> (f64, f64) {
    (
        floor / ALLAN_PEAK_PER_SIGMA,
        averaging_time_s / ALLAN_PEAK_TAU_PER_CORRELATION_TIME,
    )
}

/// A gyro's in-run bias instability as a first-order Gauss–Markov bias per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GyroBiasInstability {
    /// Stationary 1σ per axis (°/h); from an Allan plot's floor see
    /// [`gauss_markov_from_allan_floor`].
    pub sigma_deg_per_h: f64,
    /// Its correlation time (s), > 0.
    pub correlation_time_s: f64,
}

/// An accelerometer's in-run bias instability as a first-order Gauss–Markov bias per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccelBiasInstability {
    /// Stationary 1σ per axis (µg); from an Allan plot's floor see
    /// [`gauss_markov_from_allan_floor`].
    pub sigma_ug: f64,
    /// Its correlation time (s), > 0.
    pub correlation_time_s: f64,
}

/// The gyro triad's data sheet. Every figure is 1σ per axis (a data sheet's 3σ divided by
/// 3); an absent figure (`None`) is an effect the flight is not told of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GyroDatasheet {
    /// Angle random walk (°/√h): the white rate noise.
    pub angle_random_walk_deg_per_sqrt_h: f64,
    /// Bias stability (°/h): the 1σ of the bias the flight starts with (turn-on to turn-on,
    /// over storage and after the last calibration), which the filter calibrates.
    pub bias_stability_deg_per_h: f64,
    /// In-run bias instability.
    pub bias_instability: Option<GyroBiasInstability>,
    /// Rate random walk (°/h/√h): the bias's random walk.
    pub rate_random_walk_deg_per_h_per_sqrt_h: Option<f64>,
    /// Scale-factor error (ppm).
    pub scale_factor_ppm: f64,
    /// Misalignment and non-orthogonality, 1σ of every off-diagonal term (µrad).
    pub misalignment_urad: Option<f64>,
    /// g-sensitivity, 1σ per axis (°/h/g).
    pub g_sensitivity_deg_per_h_per_g: Option<f64>,
    /// Measurement range per axis (°/s); `None` = the flight software's default.
    pub range_deg_per_s: Option<f64>,
}

/// The accelerometer triad's data sheet, as [`GyroDatasheet`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccelerometerDatasheet {
    /// Velocity random walk (m/s/√h): the white specific-force noise.
    pub velocity_random_walk_m_per_s_per_sqrt_h: f64,
    /// Bias stability (µg), as the gyro's.
    pub bias_stability_ug: f64,
    /// In-run bias instability.
    pub bias_instability: Option<AccelBiasInstability>,
    /// Acceleration random walk (µg/√h): the bias's random walk.
    pub bias_random_walk_ug_per_sqrt_h: Option<f64>,
    /// Scale-factor error (ppm).
    pub scale_factor_ppm: f64,
    /// Misalignment and non-orthogonality, 1σ of every off-diagonal term (µrad).
    pub misalignment_urad: Option<f64>,
    /// Measurement range per axis (g); `None` = the flight software's default.
    pub range_g: Option<f64>,
}

/// The IMU's data sheet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuDatasheet {
    /// Output rate of the increments (Hz): one per frame.
    pub output_rate_hz: f64,
    /// The gyro triad.
    pub gyro: GyroDatasheet,
    /// The accelerometer triad.
    pub accelerometer: AccelerometerDatasheet,
}

impl GyroDatasheet {
    /// The white rate-noise density (rad/s/√Hz): `60 · ARW` in (°/h)/√Hz, since a random
    /// walk `σ(t) = N √t` has `N` per `√h` 60 times `N` per `√s`
    /// ([`deg_per_h_to_rad_per_s`] then gives rad/√s).
    pub fn noise_density_rad_s_per_sqrt_hz(&self) -> f64 {
        deg_per_h_to_rad_per_s(self.angle_random_walk_deg_per_sqrt_h * SQRT_SECONDS_PER_SQRT_HOUR)
    }

    /// The bias random-walk density (rad/s²/√Hz = rad/s per √s): the rate random walk per
    /// `√h` over 60 is per `√s`; 0 without one.
    pub fn bias_walk_rad_s2_per_sqrt_hz(&self) -> f64 {
        self.rate_random_walk_deg_per_h_per_sqrt_h
            .map_or(0.0, |walk| {
                deg_per_h_to_rad_per_s(walk) / SQRT_SECONDS_PER_SQRT_HOUR
            })
    }

    /// The g-sensitivity 1σ (rad/s per m/s²): °/h in rad/s over the standard `g`; 0 without.
    pub fn g_sensitivity_rad_s_per_mps2(&self) -> f64 {
        self.g_sensitivity_deg_per_h_per_g
            .map_or(0.0, |g| deg_per_h_to_rad_per_s(g) / STANDARD_GRAVITY_MPS2)
    }

    /// `(σ, τ)` of the bias instability (rad/s, s); `(0, 0)` without.
    fn instability(&self) -> (f64, f64) {
        self.bias_instability.map_or((0.0, 0.0), |gm| {
            (
                deg_per_h_to_rad_per_s(gm.sigma_deg_per_h),
                gm.correlation_time_s,
            )
        })
    }
}

impl AccelerometerDatasheet {
    /// The white specific-force noise density (m/s²/√Hz): the velocity random walk per `√h`
    /// over 60.
    pub fn noise_density_mps2_per_sqrt_hz(&self) -> f64 {
        self.velocity_random_walk_m_per_s_per_sqrt_h / SQRT_SECONDS_PER_SQRT_HOUR
    }

    /// The bias random-walk density (m/s³/√Hz): µg/√h in m/s² over 60; 0 without one.
    pub fn bias_walk_mps3_per_sqrt_hz(&self) -> f64 {
        self.bias_random_walk_ug_per_sqrt_h
            .map_or(0.0, |walk| ug_to_mps2(walk) / SQRT_SECONDS_PER_SQRT_HOUR)
    }

    /// `(σ, τ)` of the bias instability (m/s², s); `(0, 0)` without.
    fn instability(&self) -> (f64, f64) {
        self.bias_instability.map_or((0.0, 0.0), |gm| {
            (ug_to_mps2(gm.sigma_ug), gm.correlation_time_s)
        })
    }
}

/// µrad or ppm (1σ, optional) as a fraction; 0 without.
fn per_million(value: Option<f64>) -> f64 {
    value.map_or(0.0, |value| value / PER_MILLION)
}

impl ImuDatasheet {
    /// The IMU's part of the configuration: frame period `1 / rate`, ranges, process noise
    /// (white noise and bias walk with the instability's driving noise), bias priors (the
    /// bias stability with the instability's `2σ²`), scale-factor priors (ppm / 10⁶) and the
    /// systematic error states (µrad / 10⁶, g-sensitivity), on when any of them is given.
    pub(super) fn apply(&self, config: &mut FswConfig) {
        let (gyro, accel) = (&self.gyro, &self.accelerometer);
        config.imu.period_s = 1.0 / self.output_rate_hz;
        if let Some(range) = gyro.range_deg_per_s {
            config.imu.max_rate_rad_s = range.to_radians();
        }
        if let Some(range) = accel.range_g {
            config.imu.max_specific_force_mps2 = range * STANDARD_GRAVITY_MPS2;
        }
        let (gyro_sigma, gyro_tau_s) = gyro.instability();
        let (accel_sigma, accel_tau_s) = accel.instability();
        let noise = &mut config.process_noise;
        noise.gyro_noise_density_rad_s_per_sqrt_hz = gyro.noise_density_rad_s_per_sqrt_hz();
        noise.accel_noise_density_mps2_per_sqrt_hz = accel.noise_density_mps2_per_sqrt_hz();
        noise.gyro_bias_walk_rad_s2_per_sqrt_hz =
            bias_walk_with_instability(gyro.bias_walk_rad_s2_per_sqrt_hz(), gyro_sigma, gyro_tau_s);
        noise.accel_bias_walk_mps3_per_sqrt_hz = bias_walk_with_instability(
            accel.bias_walk_mps3_per_sqrt_hz(),
            accel_sigma,
            accel_tau_s,
        );
        let initial = &mut config.filter.initial;
        initial.gyro_bias_rad_s = bias_prior_with_instability(
            deg_per_h_to_rad_per_s(gyro.bias_stability_deg_per_h),
            gyro_sigma,
            gyro_tau_s,
        );
        initial.accel_bias_mps2 = bias_prior_with_instability(
            ug_to_mps2(accel.bias_stability_ug),
            accel_sigma,
            accel_tau_s,
        );
        initial.gyro_scale_factor = gyro.scale_factor_ppm / PER_MILLION;
        initial.accel_scale_factor = accel.scale_factor_ppm / PER_MILLION;
        let errors = &mut config.filter.imu_error;
        errors.gyro_misalignment_sigma_rad = per_million(gyro.misalignment_urad);
        errors.accel_misalignment_sigma_rad = per_million(accel.misalignment_urad);
        errors.gyro_g_sensitivity_sigma_rad_s_per_mps2 = gyro.g_sensitivity_rad_s_per_mps2();
    }
}

/// The IMU data-sheet field behind a flight parameter.
pub(super) fn field_of(param: Param) -> Option<&'static str> {
    use Param as P;
    Some(match param {
        P::ImuPeriod => "imu.output_rate_hz",
        P::ImuMaxRate => "imu.gyro.range_deg_per_s",
        P::ImuMaxSpecificForce => "imu.accelerometer.range_g",
        P::GyroNoiseDensity => "imu.gyro.angle_random_walk_deg_per_sqrt_h",
        P::AccelNoiseDensity => "imu.accelerometer.velocity_random_walk_m_per_s_per_sqrt_h",
        P::GyroBiasWalk => "imu.gyro.rate_random_walk_deg_per_h_per_sqrt_h / bias_instability",
        P::AccelBiasWalk => "imu.accelerometer.bias_random_walk_ug_per_sqrt_h / bias_instability",
        P::InitialGyroBias => "imu.gyro.bias_stability_deg_per_h",
        P::InitialAccelBias => "imu.accelerometer.bias_stability_ug",
        P::InitialGyroScaleFactor => "imu.gyro.scale_factor_ppm",
        P::InitialAccelScaleFactor => "imu.accelerometer.scale_factor_ppm",
        P::GyroMisalignmentSigma => "imu.gyro.misalignment_urad",
        P::AccelMisalignmentSigma => "imu.accelerometer.misalignment_urad",
        P::GyroGSensitivitySigma => "imu.gyro.g_sensitivity_deg_per_h_per_g",
        _ => return None,
    })
}
