//! The flight software's configuration: one struct, documented units, the paper's values as
//! defaults, validated once at start-up ([`FswConfig::validate`]) so that a bad value is a
//! typed error naming the field, never a panic or a silently wrong filter.

use nav_core::error_model::ProcessNoise;
use nav_core::filter::{FilterConfig, FilterMode, InitialUncertainty};
use nav_core::frames::LaunchSite;
use nav_core::strapdown::StrapdownConfig;

use crate::calibration_manager::CalibrationManagerConfig;
use crate::error::{ConfigField, FswError};
use crate::input_check::ImuLimits;
use crate::sensor_frames::SensorFrames;

/// Arc-seconds to radians.
pub const ARCSEC_TO_RAD: f64 = core::f64::consts::PI / (180.0 * 3600.0);

/// Capacity of the navigation-history ring (frames): bounds the measurement latency that can
/// be fused at its time of validity, `(capacity − 1) × frame period` = 126 ms at 500 Hz.
pub const HISTORY_CAPACITY: usize = 64;

/// Frames the navigation history reaches back, `HISTORY_CAPACITY − 1`: the measurement
/// latency limit in frames ([`max_latency_limit_s`]).
pub fn history_span_frames() -> u32 {
    u32::try_from(HISTORY_CAPACITY).map_or(0, |capacity| capacity.saturating_sub(1))
}

/// Largest accepted `timing.max_latency_s` for an IMU period: [`history_span_frames`] ×
/// `period_s` (126 ms at 500 Hz). An older measurement has no navigation snapshot left to
/// be fused against.
pub fn max_latency_limit_s(period_s: f64) -> f64 {
    f64::from(history_span_frames()) * period_s
}

/// Largest `covariance.propagation_interval_frames`: one second at 500 Hz, beyond which the
/// accumulated interval's mean rates no longer describe the motion.
pub const MAX_PROPAGATION_INTERVAL_FRAMES: u32 = 500;

/// Default acquisition gate of every aid: the χ²(3) point exceeded with probability 1e-6
/// (30.67; `Q(x) = erfc(√(x/2)) + √(2x/π) e^(−x/2)` for three degrees of freedom).
///
/// Until the filter has accepted a measurement of an aid, its innovation is the prior's
/// error, and that error does not change from one measurement to the next: a draw beyond the
/// steady gate ([`GATE_NIS`], exceeded with probability 1e-3) would be rejected every time, and
/// after `timing.rejections_to_declare_faulty` rejections a healthy sensor would be declared
/// faulty for the flight (one flight in a thousand from the prior alone). The first
/// acceptance is therefore gated at 1e-6; after it the innovations are fresh noise again and
/// the steady gate applies. A sensor whose error exceeds this gate is still rejected and
/// declared faulty.
pub const ACQUISITION_GATE_NIS: f64 = 30.67;

/// Default steady gate of every aid: the χ²(3) point exceeded with probability 1e-3 (16.27,
/// 99.9 %), by the same `Q(x)` as [`ACQUISITION_GATE_NIS`].
pub const GATE_NIS: f64 = 16.27;

/// Whether `value` is a valid χ² gate of a configuration: finite and > 0, or +∞ (no gate).
fn is_gate(value: f64) -> bool {
    (value.is_finite() && value > 0.0) || value == f64::INFINITY
}

/// Smallest 1σ or noise density accepted where the filter squares it ([`sigma_is_squarable`]).
pub const SIGMA_MIN: f64 = 1e-150;

/// Largest 1σ or noise density accepted where the filter squares it ([`sigma_is_squarable`]).
pub const SIGMA_MAX: f64 = 1e150;

/// The one rule for every 1σ and noise density the filter squares into `P`, `Q` or `R`:
/// `σ` in [[`SIGMA_MIN`], [`SIGMA_MAX`]], so `σ²` lies in [1e-300, 1e300], inside the normal
/// `f64` range [2.2e-308, 1.8e308]. The square then neither overflows to ∞ nor underflows to
/// 0 or a subnormal (an infinite or singular covariance), with eight decades left for the
/// factors the filter applies to it (the half-angle states' ½, the ceiling factor, frame
/// periods). NaN, 0 and negative values fail.
pub fn sigma_is_squarable(sigma: f64) -> bool {
    (SIGMA_MIN..=SIGMA_MAX).contains(&sigma)
}

/// [`sigma_is_squarable`], or exactly 0 for a value whose 0 switches its term off (process
/// noise densities, GNSS velocity noise, correlated GNSS error, held-sample uncertainty).
pub fn sigma_is_squarable_or_off(sigma: f64) -> bool {
    sigma == 0.0 || sigma_is_squarable(sigma)
}

/// The eight block values of an [`InitialUncertainty`] (initial 1σ or floor).
fn uncertainty_values(uncertainty: &InitialUncertainty) -> [f64; 8] {
    [
        uncertainty.attitude_rad,
        uncertainty.position_m,
        uncertainty.velocity_mps,
        uncertainty.gyro_bias_rad_s,
        uncertainty.accel_bias_mps2,
        uncertainty.star_installation_rad,
        uncertainty.gyro_scale_factor,
        uncertainty.accel_scale_factor,
    ]
}

/// Largest magnitude of the initial navigation time (s, since the launch epoch): about 32
/// years. Time must keep advancing by whole frames: at `|t|` = 1e9 s one ulp of an `f64` is
/// 1.2e-7 s, a sixteen-thousandth of the 2 ms frame; at 1e17 s it is 16 s and a frame no
/// longer moves the clock.
pub const MAX_INITIAL_TIME_S: f64 = 1.0e9;

/// Capacity of the star-sensor measurement queue.
pub const STAR_QUEUE_CAPACITY: usize = 8;

/// Capacity of the GNSS fix queue.
pub const GNSS_QUEUE_CAPACITY: usize = 4;

/// Star-sensor settings.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StarSensorConfig {
    /// Nominal body-to-sensor mounting `q_bs` `[w, x, y, z]` (unit), known from the drawings.
    pub mounting_wxyz: [f64; 4],
    /// Attitude noise across the boresight, 1σ about sensor `x` and about sensor `y` (rad);
    /// the paper's 10″.
    pub noise_rad: f64,
    /// Attitude noise about the boresight, 1σ about sensor `z` (rad); the paper's 10″ (it
    /// has one value for every axis). A real tracker's is 5–10× its cross-boresight noise.
    pub roll_noise_rad: f64,
    /// NIS gate, χ²(3) ([`GATE_NIS`] by default).
    pub gate_nis: f64,
    /// NIS gate, χ²(3), until the filter has accepted a star measurement: after start-up,
    /// an outage, a filter re-initialisation or a cleared fault ([`ACQUISITION_GATE_NIS`]);
    /// the larger of it and `gate_nis` applies.
    pub acquisition_gate_nis: f64,
    /// Largest accepted `| |q| − 1 |` of a measured quaternion.
    pub unit_norm_tolerance: f64,
    /// The tracker's slowly varying error (thermo-elastic, focal plane): stationary 1σ per
    /// sensor axis `[x, y, z]` of a first-order Gauss–Markov rotation (rad); all 0 (the
    /// paper's model) = a constant installation error. The installation states carry it as
    /// a random walk (`scheduler::covariance`, docs/sensor-errors.md).
    pub slow_error_sigma_rad: [f64; 3],
    /// Its correlation time `τ` (s), finite and > 0 when any `slow_error_sigma_rad` is.
    pub slow_error_correlation_time_s: f64,
    /// Whether the flight software removes the velocity aberration from the measured
    /// attitude (the tracker does not), with the navigation velocity at the measurement's
    /// time of validity (nav-core `aberration`); `false` (the default) for a tracker that
    /// corrects it itself.
    pub aberration_correction: bool,
    /// Whether the star noise follows the innovations once they fail the consistency test
    /// (per sensor axis, never below `noise_rad` and `roll_noise_rad`; [`crate::noise_matching`]);
    /// `true` by default. Off, a tracker noisier than configured keeps its configured weight.
    pub noise_matching: bool,
    /// A second tracker head on the same port (`StarMeasurement::head` 1); `None` (the
    /// default) = one head. The filter fuses one head at a time and carries its installation
    /// error; the other head's measurements estimate the heads' relative alignment
    /// (`scheduler::heads`, docs/sensor-errors.md).
    pub second_head: Option<StarHeadConfig>,
}

/// The second tracker head: what differs from the first (`star`); its gates, rate and slow
/// error are the first head's.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StarHeadConfig {
    /// Nominal body-to-sensor mounting `q_bs` `[w, x, y, z]` (unit) of this head.
    pub mounting_wxyz: [f64; 4],
    /// Attitude noise across the boresight, 1σ about sensor `x` and `y` (rad).
    pub noise_rad: f64,
    /// Attitude noise about the boresight, 1σ about sensor `z` (rad).
    pub roll_noise_rad: f64,
    /// 1σ per axis of the two heads' relative alignment before the first pair (rotation
    /// angle, rad): both heads' installation errors, `√2` times their 1σ when equal.
    pub alignment_prior_sigma_rad: f64,
    /// χ²(3) gate of a pair's residual ([`GATE_NIS`] by default).
    pub pair_gate_nis: f64,
    /// Pairs accepted before the filter may hand its installation block over to this head
    /// (or back): the alignment is known to a fraction of the noise by then.
    pub pairs_before_hand_over: u32,
}

impl StarHeadConfig {
    /// The head's noise 1σ about sensor `x`, `y`, `z` (rad).
    pub const fn noise_per_axis_rad(&self) -> [f64; 3] {
        [self.noise_rad, self.noise_rad, self.roll_noise_rad]
    }

    /// Whether every value is valid (a unit mounting, squarable noises and prior, a gate).
    fn is_valid(&self) -> bool {
        is_unit_quaternion(&self.mounting_wxyz)
            && [
                self.noise_rad,
                self.roll_noise_rad,
                self.alignment_prior_sigma_rad,
            ]
            .iter()
            .all(|sigma| sigma_is_squarable(*sigma))
            && is_gate(self.pair_gate_nis)
    }
}

/// Whether `[w, x, y, z]` is a unit quaternion within nav-core's unit-norm tolerance (a
/// mounting).
fn is_unit_quaternion(wxyz: &[f64; 4]) -> bool {
    let [w, x, y, z] = *wxyz;
    let norm = nav_core::float::sqrt(w * w + x * x + y * y + z * z);
    norm.is_finite() && nav_core::attitude::is_unit_norm(norm)
}

impl StarSensorConfig {
    /// The first head's noise 1σ about sensor `x`, `y`, `z` (rad).
    pub const fn noise_per_axis_rad(&self) -> [f64; 3] {
        [self.noise_rad, self.noise_rad, self.roll_noise_rad]
    }
    /// Whether the slowly varying error is configured (any 1σ non-zero).
    pub fn has_slow_error(&self) -> bool {
        self.slow_error_sigma_rad.iter().any(|sigma| *sigma != 0.0)
    }

    /// The variance per second the slow error adds to each installation state (the vector
    /// part, a half-angle), `[x, y, z]`: `¼ · 2σ²/τ = σ²/(2τ)` (rad²/s). `2σ²/τ` is the
    /// density of the white noise that drives a Gauss–Markov rotation of stationary 1σ `σ`
    /// (`ε̇ = −ε/τ + w`, stationary variance `qτ/2`); the walk with it bounds the
    /// Gauss–Markov error at every set of times when the prior also holds `2σ²`
    /// (docs/model.md, "Bias instability in the filter", the same argument). Zero when off.
    ///
    /// # Examples
    /// ```
    /// use nav_fsw::config::FswConfig;
    /// use nav_fsw::nav_core::frames::LaunchSite;
    /// use nav_fsw::sensor_frames::SensorFrames;
    /// let site = LaunchSite {
    ///     latitude_rad: 0.715, longitude_rad: 1.750, height_m: 1000.0, azimuth_rad: 3.316,
    ///     earth_axis_ecef: [0.0, 0.0, 1.0],
    /// };
    /// let mut config = FswConfig::paper_defaults(site, SensorFrames::ALIGNED);
    /// assert_eq!(config.star.installation_walk_rad2_per_s(), [0.0; 3]);
    /// config.star.slow_error_sigma_rad = [2e-5, 2e-5, 4e-5];
    /// config.star.slow_error_correlation_time_s = 1000.0;
    /// let walk = config.star.installation_walk_rad2_per_s();
    /// assert!((walk[2] - 8e-13).abs() < 1e-27);
    /// ```
    pub fn installation_walk_rad2_per_s(&self) -> [f64; 3] {
        if !self.has_slow_error() {
            return [0.0; 3];
        }
        let tau_s = self.slow_error_correlation_time_s;
        self.slow_error_sigma_rad
            .map(|sigma| sigma * sigma / (2.0 * tau_s))
    }
}

/// GNSS receiver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GnssConfig {
    /// Antenna position relative to the IMU, body axes (m).
    pub lever_arm_body_m: [f64; 3],
    /// Position noise, 1σ per axis (m); the paper's 10 m.
    pub noise_m: f64,
    /// NIS gate, χ²(3).
    pub gate_nis: f64,
    /// NIS gate, χ²(3), of the positions until the filter has accepted one (as
    /// [`StarSensorConfig::acquisition_gate_nis`]; the larger of it and `gate_nis` applies).
    pub acquisition_gate_nis: f64,
    /// A fix farther than this from the predicted antenna position is a jump (m).
    pub max_jump_m: f64,
    /// Velocity noise, 1σ per axis (m/s) of a receiver that outputs velocity (used when a
    /// fix carries one); 0 = velocities are not fused.
    pub velocity_noise_mps: f64,
    /// NIS gate of the velocity update, χ²(3).
    pub velocity_gate_nis: f64,
    /// NIS gate, χ²(3), of the velocities until the filter has accepted one (the larger of it
    /// and `velocity_gate_nis` applies).
    pub velocity_acquisition_gate_nis: f64,
    /// Window (position fixes) of the innovation whiteness monitor
    /// ([`crate::health::WhitenessMonitor`]).
    pub whiteness_window_fixes: f64,
    /// Weighted lag-one correlation of the normalised position innovations above which
    /// `gnss_innovations_correlated` counts an episode.
    pub whiteness_threshold: f64,
}

/// Measurement timing.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MeasurementTiming {
    /// Oldest accepted time of validity behind the navigation time (s); at most
    /// `(HISTORY_CAPACITY − 1) × frame period`.
    pub max_latency_s: f64,
    /// A time tag later than navigation time by more than this is refused as future (s).
    pub future_tolerance_s: f64,
    /// An aiding sensor silent for longer than this is in an outage (counted once in
    /// `star_outages` / `gnss_outages`) (s); longer than the slowest nominal message interval.
    pub outage_timeout_s: f64,
    /// Consecutive gate rejections after which a sensor is declared faulty (its
    /// measurements are then ignored until [`crate::scheduler::Command::ClearSensorFaults`]).
    pub rejections_to_declare_faulty: u32,
}

/// Covariance propagation and protection.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CovarianceConfig {
    /// Propagate `P` every this many frames (1 = every frame, the default), over the
    /// accumulated interval with the mean rates and forces of the interval.
    pub propagation_interval_frames: u32,
    /// Whether one frame may both propagate `P` and fuse a measurement ([`FrameLoad`]).
    pub frame_load: FrameLoad,
    /// Floor of every 1σ, per block (same units as the initial uncertainty); a variance
    /// below its floor² is raised to it (counted).
    pub sigma_floor: InitialUncertainty,
    /// Ceiling of every 1σ as a multiple of its initial 1σ; a larger variance is scaled back
    /// with its row and column (correlations kept), counted.
    pub sigma_ceiling_factor: f64,
    /// What a held IMU sample may be wrong by ([`HeldSampleUncertainty`]).
    pub held_sample: HeldSampleUncertainty,
    /// Whether the attitude covariance grows for the kinematics' second-order term while the
    /// star sensor is unheard ([`SecondOrderAttitude`]).
    pub second_order_attitude: SecondOrderAttitude,
}

/// How the covariance propagation and the fusion of a measurement share the frames: the
/// worst frame's cost.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FrameLoad {
    /// A frame whose propagation is due propagates `P` to the navigation time, then fuses
    /// the oldest due measurement: the worst frame carries both.
    PropagateThenFuse,
    /// A frame fuses a measurement or propagates `P`, never both (the default): a frame
    /// with a due measurement fuses it against `P` at its last propagation (the
    /// measurement referred to that time, [`crate::scheduler`]) and the propagation waits
    /// one frame, then covers both frames; it waits no longer, so a measurement due in
    /// that frame waits instead. The worst frame carries the larger of the two.
    FuseOrPropagate,
}

impl FrameLoad {
    /// Whether a frame that fuses a measurement lets a due propagation wait.
    pub const fn defers_propagation(self) -> bool {
        matches!(self, FrameLoad::FuseOrPropagate)
    }
}

/// The attitude-error kinematics' second-order term `½ ϑ × δω`, which the paper's linear
/// model (eq. 7) drops (nav-core `unmodelled`). It matters when the star sensor is blind
/// through a fast rotation: the attitude error then grows with the gyro scale-factor error
/// times the angle turned, and the term biases the scale factors the filter infers when the
/// sensor re-acquires.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SecondOrderAttitude {
    /// The paper's linear model: no covariance for the term.
    Neglected,
    /// The attitude covariance grows, from the last accepted star-sensor update on, in the
    /// direction of the term's covariance and by its 1σ accumulated coherently while the
    /// gyro rate error stays the same (the default).
    Bounded,
}

impl SecondOrderAttitude {
    /// Whether the covariance grows for the term.
    pub const fn is_bounded(self) -> bool {
        matches!(self, SecondOrderAttitude::Bounded)
    }
}

/// 1σ per axis of the difference between the true motion and a held IMU increment (the last
/// good one, replacing a missing or refused sample), as a rate and a specific force. The
/// error of consecutive held samples is taken as fully correlated (a held sample is wrong
/// the same way for the whole gap), so after `k` held frames the attitude and velocity
/// errors have 1σ `k σ Δt` (angle) and `k σ Δt`: the `k`-th adds `(2k − 1) (σ Δt)²`.
/// A sample refused as saturated uses at least the IMU's range as its σ: the true motion is
/// beyond it by an unknown amount.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HeldSampleUncertainty {
    /// Body-rate error of a held sample (rad/s, 1σ per axis).
    pub rate_rad_s: f64,
    /// Specific-force error of a held sample (m/s², 1σ per axis).
    pub specific_force_mps2: f64,
}

/// Everything the flight software needs, in one place.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FswConfig {
    /// Launch site and Earth rotation axis, defining the launch-inertial navigation frame.
    pub launch_site: LaunchSite,
    /// The star tracker's and GNSS receiver's frames and time scales (ground constants).
    pub sensor_frames: SensorFrames,
    /// Strapdown options (coning, sculling, gravity model).
    pub strapdown: StrapdownConfig,
    /// The 24-state filter: mode, discretisation order (paper: 3), initial 1σ.
    pub filter: FilterConfig,
    /// Sensor noise spectral densities for `Q`.
    pub process_noise: ProcessNoise,
    /// IMU period and saturation limits.
    pub imu: ImuLimits,
    /// Star sensor.
    pub star: StarSensorConfig,
    /// GNSS.
    pub gnss: GnssConfig,
    /// Measurement latency and fault declaration.
    pub timing: MeasurementTiming,
    /// Covariance propagation rate and protection.
    pub covariance: CovarianceConfig,
    /// The calibration manager.
    pub calibration: CalibrationManagerConfig,
    /// The innovation consistency monitor of every aid
    /// ([`crate::consistency::ConsistencyMonitor`]).
    pub consistency: crate::consistency::ConsistencyConfig,
    /// The gravity field beyond point mass + `J2` and the allowance for what it omits.
    pub gravity: GravityConfig,
}

/// The flight's gravity beyond the strapdown's point mass + `J2` (nav-core
/// `gravity::harmonics`), and the allowance for the field it leaves out: white velocity noise
/// of spectral density `omitted_field_psd_m2_per_s3` (isotropic, per axis) added to the
/// filter's process noise where the omitted field is `omitted_field_sigma_mps2` per axis, and
/// scaled with the omitted field's power at the vehicle's radius below that: the omitted
/// field's spectral density at zero frequency, scaled to that σ and averaged over ground
/// tracks, is what the constant calibration states see (docs/gravity.md, "The allowance with
/// the altitude"; `nav-sim gravity-omission`). Each evaluation compares the RMS magnitude of
/// the omitted field at the vehicle's radius with `√3 σ`; above it (a model too coarse for
/// its allowance, a flight lower than designed for, or no allowance at all),
/// `gravity_allowance_short` counts an episode.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GravityConfig {
    /// Degree, order and work per frame of the field beyond `J2`.
    pub field: nav_core::gravity::harmonics::FieldModel,
    /// 1σ per axis of the omitted field the allowance is for (m/s²); 0: no allowance.
    pub omitted_field_sigma_mps2: f64,
    /// Spectral density of the white velocity noise that covers a field of that 1σ (m²/s³),
    /// scaled down with the field's power where it is weaker; 0: none.
    pub omitted_field_psd_m2_per_s3: f64,
}

/// `√3`: the RMS magnitude of a vector of three independent axes of unit 1σ.
const SQRT_3: f64 = 1.732_050_807_568_877_2;

impl GravityConfig {
    /// Point mass + `J2` and no allowance: the paper's model.
    pub const J2_ONLY: Self = Self {
        field: nav_core::gravity::harmonics::FieldModel::J2_ONLY,
        omitted_field_sigma_mps2: 0.0,
        omitted_field_psd_m2_per_s3: 0.0,
    };

    /// Whether the field model is valid and the allowance is off (both 0) or on (both
    /// positive: σ squarable, the density at most 1 m²/s³).
    pub fn is_valid(&self) -> bool {
        let (sigma, psd) = (
            self.omitted_field_sigma_mps2,
            self.omitted_field_psd_m2_per_s3,
        );
        let off = sigma == 0.0 && psd == 0.0;
        let on = sigma_is_squarable(sigma) && psd > 0.0 && psd <= 1.0;
        self.field.validate().is_ok() && (off || on)
    }

    /// The RMS magnitude of the omitted field the allowance covers (m/s²): `σ` per axis is
    /// `√3 σ` in magnitude, the figure the flight software's omitted RMS is checked against.
    pub fn covered_rms_mps2(&self) -> f64 {
        SQRT_3 * self.omitted_field_sigma_mps2
    }

    /// `base` with the allowance added where the omitted field has the RMS magnitude
    /// `omitted_rms_mps2`: the allowance `q` (m²/s³) is for a field of `σ` per axis (RMS
    /// magnitude `√3 σ`), and its density scales with the field's power,
    /// `q_r = q · min(1, (rms / √3 σ)²)`: the omitted degrees' field falls with the radius as
    /// `(a/r)^(n+2)`, and a flight that climbs from its parking orbit leaves the field behind
    /// (docs/gravity.md, "The allowance with the altitude"). Above `√3 σ` the allowance stays
    /// `q`; an RMS that is not a number counts as above. In launch-inertial axes the
    /// accelerometer's white noise enters the velocity as `C (σ_a² I) Cᵀ = σ_a² I`, so an
    /// isotropic white velocity noise of density `q_r` is the same as an accelerometer
    /// density `√(σ_a² + q_r)`. Without an allowance `base`, bit for bit.
    ///
    /// # Examples
    /// ```
    /// use nav_core::error_model::ProcessNoise;
    /// use nav_fsw::config::GravityConfig;
    /// let gravity = GravityConfig {
    ///     omitted_field_sigma_mps2: 2.0e-5,
    ///     omitted_field_psd_m2_per_s3: 1.0e-7,
    ///     ..GravityConfig::J2_ONLY
    /// };
    /// let base = ProcessNoise::PAPER;
    /// // Half the covered RMS: a quarter of the allowance.
    /// let half = gravity.process_noise_at(&base, 0.5 * gravity.covered_rms_mps2());
    /// let density = base.accel_noise_density_mps2_per_sqrt_hz;
    /// let expected = (density * density + 0.25e-7).sqrt();
    /// assert!((half.accel_noise_density_mps2_per_sqrt_hz - expected).abs() < 1e-18);
    /// assert_eq!(GravityConfig::J2_ONLY.process_noise_at(&base, 1.0), base);
    /// ```
    pub fn process_noise_at(&self, base: &ProcessNoise, omitted_rms_mps2: f64) -> ProcessNoise {
        let mut noise = *base;
        let allowance = self.omitted_field_psd_m2_per_s3;
        if allowance > 0.0 {
            // σ > 0 whenever an allowance is configured (`is_valid`).
            let ratio = omitted_rms_mps2 / self.covered_rms_mps2();
            let share = if ratio < 1.0 { ratio * ratio } else { 1.0 };
            let density = noise.accel_noise_density_mps2_per_sqrt_hz;
            noise.accel_noise_density_mps2_per_sqrt_hz =
                nav_core::float::sqrt(density * density + allowance * share);
        }
        noise
    }
}

impl FswConfig {
    /// The paper's values where it gives them (Section 3: 500 Hz, 10″ star sensor, 10 m
    /// GNSS, 3rd-order discretisation, its noise densities) and documented choices
    /// elsewhere, for a launch site given by the mission.
    pub fn paper_defaults(launch_site: LaunchSite, sensor_frames: SensorFrames) -> Self {
        Self {
            launch_site,
            sensor_frames,
            strapdown: StrapdownConfig::default(),
            filter: FilterConfig {
                mode: FilterMode::ClosedLoop,
                discretisation_order: 3,
                initial: InitialUncertainty {
                    attitude_rad: 1e-3,
                    position_m: 10.0,
                    velocity_mps: 0.1,
                    gyro_bias_rad_s: 1e-3,
                    accel_bias_mps2: 1e-2,
                    star_installation_rad: 1e-2,
                    gyro_scale_factor: 1e-4,
                    accel_scale_factor: 2e-4,
                },
                gnss_error: nav_core::gnss_error::GnssErrorModel::WHITE,
                imu_error: nav_core::imu_error_states::ImuErrorModel::DISABLED,
            },
            process_noise: ProcessNoise::PAPER,
            imu: ImuLimits::default(),
            star: StarSensorConfig {
                mounting_wxyz: [1.0, 0.0, 0.0, 0.0],
                noise_rad: 10.0 * ARCSEC_TO_RAD,
                roll_noise_rad: 10.0 * ARCSEC_TO_RAD,
                gate_nis: GATE_NIS,
                acquisition_gate_nis: ACQUISITION_GATE_NIS,
                unit_norm_tolerance: 1e-3,
                slow_error_sigma_rad: [0.0; 3],
                slow_error_correlation_time_s: 0.0,
                aberration_correction: false,
                noise_matching: true,
                second_head: None,
            },
            gnss: GnssConfig {
                lever_arm_body_m: [0.0; 3],
                noise_m: 10.0,
                gate_nis: GATE_NIS,
                acquisition_gate_nis: ACQUISITION_GATE_NIS,
                max_jump_m: 1000.0,
                velocity_noise_mps: 0.05,
                velocity_gate_nis: GATE_NIS,
                velocity_acquisition_gate_nis: ACQUISITION_GATE_NIS,
                // [chosen] 64 fixes: 1σ of the statistic 0.051 when the innovations are
                // white; 0.25 is about 5σ, and well below the 0.4-0.6 of an unmodelled
                // correlated error of the receiver's size.
                whiteness_window_fixes: 64.0,
                whiteness_threshold: 0.25,
            },
            timing: MeasurementTiming {
                max_latency_s: 0.1,
                future_tolerance_s: 0.001,
                outage_timeout_s: 2.0,
                rejections_to_declare_faulty: 20,
            },
            covariance: CovarianceConfig {
                propagation_interval_frames: 1,
                frame_load: FrameLoad::FuseOrPropagate,
                sigma_floor: InitialUncertainty {
                    attitude_rad: 1e-9,
                    position_m: 1e-4,
                    velocity_mps: 1e-7,
                    gyro_bias_rad_s: 1e-10,
                    accel_bias_mps2: 1e-8,
                    star_installation_rad: 1e-9,
                    gyro_scale_factor: 1e-10,
                    accel_scale_factor: 1e-10,
                },
                sigma_ceiling_factor: 1e3,
                // [chosen] the change of rate and specific force an upper stage makes over a
                // short gap: 0.1 rad/s (5.7°/s) and 1 m/s².
                held_sample: HeldSampleUncertainty {
                    rate_rad_s: 0.1,
                    specific_force_mps2: 1.0,
                },
                second_order_attitude: SecondOrderAttitude::Bounded,
            },
            calibration: CalibrationManagerConfig::default(),
            consistency: crate::consistency::ConsistencyConfig::default(),
            gravity: GravityConfig::J2_ONLY,
        }
    }

    /// Checks every value; the first bad one is reported by name.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] naming the field.
    pub fn validate(&self) -> Result<(), FswError> {
        let invalid = |field| Err(FswError::InvalidConfiguration(field));
        if self.launch_site.validate().is_err() {
            return invalid(ConfigField::LaunchSite);
        }
        self.sensor_frames.validate()?;
        self.validate_squared_sigmas()?;
        if self.filter.gnss_error.validate().is_err() {
            return invalid(ConfigField::GnssCorrelatedError);
        }
        if self.filter.imu_error.validate().is_err() {
            return invalid(ConfigField::ImuSystematicError);
        }
        if self.filter.validate().is_err() {
            return invalid(ConfigField::FilterInitialUncertainty);
        }
        self.imu.validate()?;
        self.validate_sensors()?;
        self.validate_acquisition_gates()?;
        self.validate_timing()?;
        self.validate_covariance()?;
        self.calibration.validate()
    }

    /// Every 1σ and noise density the filter squares, by [`sigma_is_squarable`] (or 0 where 0
    /// switches the term off).
    fn validate_squared_sigmas(&self) -> Result<(), FswError> {
        let noise = &self.process_noise;
        let held = &self.covariance.held_sample;
        let required: [(&[f64], ConfigField); 5] = [
            (
                &uncertainty_values(&self.filter.initial),
                ConfigField::FilterInitialUncertainty,
            ),
            (
                &uncertainty_values(&self.covariance.sigma_floor),
                ConfigField::SigmaFloor,
            ),
            (
                &[self.star.noise_rad, self.star.roll_noise_rad],
                ConfigField::StarNoise,
            ),
            (&[self.gnss.noise_m], ConfigField::GnssNoise),
            (
                &self.calibration.convergence_sigma.values(),
                ConfigField::CalibrationThreshold,
            ),
        ];
        let optional: [(&[f64], ConfigField); 4] = [
            (
                &[
                    noise.gyro_noise_density_rad_s_per_sqrt_hz,
                    noise.accel_noise_density_mps2_per_sqrt_hz,
                    noise.gyro_bias_walk_rad_s2_per_sqrt_hz,
                    noise.accel_bias_walk_mps3_per_sqrt_hz,
                ],
                ConfigField::ProcessNoise,
            ),
            (&[self.gnss.velocity_noise_mps], ConfigField::GnssVelocity),
            (
                &[self.filter.gnss_error.sigma_m],
                ConfigField::GnssCorrelatedError,
            ),
            (
                &[held.rate_rad_s, held.specific_force_mps2],
                ConfigField::HeldSampleUncertainty,
            ),
        ];
        let failing = |(values, field): &(&[f64], ConfigField), rule: fn(f64) -> bool| {
            (!values.iter().all(|value| rule(*value))).then_some(*field)
        };
        let first = required
            .iter()
            .find_map(|entry| failing(entry, sigma_is_squarable))
            .or_else(|| {
                optional
                    .iter()
                    .find_map(|entry| failing(entry, sigma_is_squarable_or_off))
            });
        first.map_or(Ok(()), |field| Err(FswError::InvalidConfiguration(field)))
    }

    /// The star sensor's and the GNSS receiver's settings other than their noise.
    fn validate_sensors(&self) -> Result<(), FswError> {
        let invalid = |field| Err(FswError::InvalidConfiguration(field));
        let positive = |value: f64| value.is_finite() && value > 0.0;
        if !is_unit_quaternion(&self.star.mounting_wxyz) {
            return invalid(ConfigField::StarMounting);
        }
        if !is_gate(self.star.gate_nis) {
            return invalid(ConfigField::StarGate);
        }
        if !(positive(self.star.unit_norm_tolerance) && self.star.unit_norm_tolerance < 0.5) {
            return invalid(ConfigField::StarNormTolerance);
        }
        let slow_sigmas_ok = self
            .star
            .slow_error_sigma_rad
            .iter()
            .all(|sigma| sigma_is_squarable_or_off(*sigma));
        if !(slow_sigmas_ok
            && (!self.star.has_slow_error() || positive(self.star.slow_error_correlation_time_s))
            && self
                .star
                .installation_walk_rad2_per_s()
                .iter()
                .all(|walk| walk.is_finite()))
        {
            return invalid(ConfigField::StarSlowError);
        }
        if !self.star.second_head.is_none_or(|head| head.is_valid()) {
            return invalid(ConfigField::StarSecondHead);
        }
        if !self.gnss.lever_arm_body_m.iter().all(|v| v.is_finite()) {
            return invalid(ConfigField::GnssLeverArm);
        }
        if !is_gate(self.gnss.gate_nis) {
            return invalid(ConfigField::GnssGate);
        }
        if !positive(self.gnss.max_jump_m) {
            return invalid(ConfigField::GnssMaxJump);
        }
        if !is_gate(self.gnss.velocity_gate_nis) {
            return invalid(ConfigField::GnssVelocity);
        }
        if !(self.gnss.whiteness_window_fixes.is_finite()
            && self.gnss.whiteness_window_fixes >= 1.0
            && positive(self.gnss.whiteness_threshold))
        {
            return invalid(ConfigField::GnssWhiteness);
        }
        Ok(())
    }

    /// The acquisition gates, each a gate as the steady ones ([`is_gate`]).
    fn validate_acquisition_gates(&self) -> Result<(), FswError> {
        if !is_gate(self.star.acquisition_gate_nis) {
            return Err(FswError::InvalidConfiguration(
                ConfigField::StarAcquisitionGate,
            ));
        }
        if !(is_gate(self.gnss.acquisition_gate_nis)
            && is_gate(self.gnss.velocity_acquisition_gate_nis))
        {
            return Err(FswError::InvalidConfiguration(
                ConfigField::GnssAcquisitionGate,
            ));
        }
        Ok(())
    }

    /// Measurement latency, future tolerance, outage timeout and fault declaration.
    fn validate_timing(&self) -> Result<(), FswError> {
        let invalid = |field| Err(FswError::InvalidConfiguration(field));
        let latency = self.timing.max_latency_s;
        if !(latency.is_finite()
            && latency >= 0.0
            && latency <= max_latency_limit_s(self.imu.period_s))
        {
            return invalid(ConfigField::MaxLatency);
        }
        let future = self.timing.future_tolerance_s;
        if !(future.is_finite() && future >= 0.0 && future < self.imu.period_s) {
            return invalid(ConfigField::FutureTolerance);
        }
        if !(self.timing.outage_timeout_s.is_finite() && self.timing.outage_timeout_s > 0.0) {
            return invalid(ConfigField::OutageTimeout);
        }
        if self.timing.rejections_to_declare_faulty == 0 {
            return invalid(ConfigField::RejectionsToDeclareFaulty);
        }
        if !self.consistency.is_valid() {
            return invalid(ConfigField::Consistency);
        }
        if !self.gravity.is_valid() {
            return invalid(ConfigField::Gravity);
        }
        Ok(())
    }

    /// Propagation interval and variance ceiling (the floors are checked with the sigmas).
    fn validate_covariance(&self) -> Result<(), FswError> {
        let invalid = |field| Err(FswError::InvalidConfiguration(field));
        let interval = self.covariance.propagation_interval_frames;
        if !(1..=MAX_PROPAGATION_INTERVAL_FRAMES).contains(&interval) {
            return invalid(ConfigField::PropagationInterval);
        }
        let ceiling = self.covariance.sigma_ceiling_factor;
        if !(ceiling.is_finite() && ceiling >= 1.0) {
            return invalid(ConfigField::SigmaCeiling);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn site() -> LaunchSite {
        LaunchSite {
            latitude_rad: 0.715,
            longitude_rad: 1.750,
            height_m: 1000.0,
            azimuth_rad: 3.316,
            earth_axis_ecef: [0.0, 0.0, 1.0],
        }
    }

    /// The rules' text states the tolerance and the gates the code applies.
    #[test]
    fn the_rules_and_defaults_state_the_named_constants() {
        let tolerance = format!("{:e}", nav_core::attitude::UNIT_NORM_TOLERANCE);
        assert_eq!(tolerance, "1e-9");
        for field in [ConfigField::StarMounting, ConfigField::SensorFrames] {
            assert!(field.rule().contains(&tolerance), "{field}");
        }
        let defaults = FswConfig::paper_defaults(site(), SensorFrames::ALIGNED);
        for gate in [
            defaults.star.gate_nis,
            defaults.gnss.gate_nis,
            defaults.gnss.velocity_gate_nis,
        ] {
            assert_eq!(gate.to_bits(), GATE_NIS.to_bits());
        }
    }

    #[test]
    fn defaults_are_valid_and_each_bad_value_names_its_field() {
        let good = FswConfig::paper_defaults(site(), SensorFrames::ALIGNED);
        assert_eq!(good.validate(), Ok(()));
        type Corruption = (fn(&mut FswConfig), ConfigField);
        let cases: [Corruption; 16] = [
            (
                |c| c.star.mounting_wxyz = [0.9, 0.0, 0.0, 0.0],
                ConfigField::StarMounting,
            ),
            (
                |c| c.consistency.mean_nis_bound = 2.9,
                ConfigField::Consistency,
            ),
            (
                |c| c.consistency.time_constant_measurements = 0,
                ConfigField::Consistency,
            ),
            (|c| c.gravity.field.degree = 13, ConfigField::Gravity),
            (|c| c.gravity.field.order = 3, ConfigField::Gravity),
            (
                |c| c.gravity.omitted_field_sigma_mps2 = 1e-4,
                ConfigField::Gravity,
            ),
            (
                |c| {
                    c.gravity.omitted_field_sigma_mps2 = 1e-4;
                    c.gravity.omitted_field_psd_m2_per_s3 = f64::INFINITY;
                },
                ConfigField::Gravity,
            ),
            (|c| c.star.noise_rad = f64::NAN, ConfigField::StarNoise),
            (|c| c.star.roll_noise_rad = -1e-5, ConfigField::StarNoise),
            (|c| c.star.roll_noise_rad = f64::NAN, ConfigField::StarNoise),
            (|c| c.gnss.gate_nis = -1.0, ConfigField::GnssGate),
            (|c| c.timing.max_latency_s = 1.0, ConfigField::MaxLatency),
            (
                |c| c.covariance.propagation_interval_frames = 0,
                ConfigField::PropagationInterval,
            ),
            (
                |c| c.covariance.sigma_floor.position_m = 0.0,
                ConfigField::SigmaFloor,
            ),
            (
                |c| c.filter.initial.gyro_scale_factor = -1.0,
                ConfigField::FilterInitialUncertainty,
            ),
            (
                |c| c.calibration.stability_window_s = -1.0,
                ConfigField::CalibrationWindow,
            ),
        ];
        for (corrupt, field) in cases {
            let mut config = good;
            corrupt(&mut config);
            assert_eq!(
                config.validate(),
                Err(FswError::InvalidConfiguration(field))
            );
        }
    }

    fn refused(corrupt: impl Fn(&mut FswConfig)) -> Option<ConfigField> {
        let mut config = FswConfig::paper_defaults(site(), SensorFrames::ALIGNED);
        corrupt(&mut config);
        match config.validate() {
            Err(FswError::InvalidConfiguration(field)) => Some(field),
            _ => None,
        }
    }

    #[test]
    fn the_unit_conversions_and_the_default_star_noise_have_their_values() {
        // 1″ = π / 648,000 rad; the paper's star sensor is 10″ (1σ).
        assert!((ARCSEC_TO_RAD - 4.848_136_811_095_36e-6).abs() < 1e-20);
        let star = FswConfig::paper_defaults(site(), SensorFrames::ALIGNED).star;
        assert!((star.noise_rad - 4.848_136_811_095_36e-5).abs() < 1e-19);
        assert_eq!(star.roll_noise_rad.to_bits(), star.noise_rad.to_bits());
    }

    /// One case per documented limit, as a table: longer than a function usually is, since
    /// splitting it would scatter the table.
    #[test]
    fn every_validation_boundary_is_where_its_documentation_puts_it() {
        use ConfigField as F;
        // A zero noise is not positive.
        assert_eq!(refused(|c| c.star.noise_rad = 0.0), Some(F::StarNoise));
        assert_eq!(refused(|c| c.star.roll_noise_rad = 0.0), Some(F::StarNoise));
        // Any unit mounting is accepted, whatever its axis; a norm 2e-9 off is refused.
        let half = core::f64::consts::FRAC_1_SQRT_2;
        for mounting in [
            [0.5, 0.5, -0.5, 0.5],
            [0.0, half, 0.0, half],
            [0.0, 0.0, 1.0, 0.0],
        ] {
            assert_eq!(refused(|c| c.star.mounting_wxyz = mounting), None);
        }
        assert_eq!(
            refused(|c| c.star.mounting_wxyz = [0.0, 0.0, 0.0, 1.0 + 2e-9]),
            Some(F::StarMounting)
        );
        assert_eq!(
            refused(|c| c.star.mounting_wxyz = [0.0, 0.6, 0.6, 0.6]),
            Some(F::StarMounting)
        );
        // An infinite gate means "never gate" and is valid; a NaN gate is not.
        assert_eq!(refused(|c| c.star.gate_nis = f64::INFINITY), None);
        assert_eq!(refused(|c| c.star.gate_nis = f64::NAN), Some(F::StarGate));
        assert_eq!(refused(|c| c.gnss.gate_nis = f64::INFINITY), None);
        assert_eq!(refused(|c| c.gnss.gate_nis = 0.0), Some(F::GnssGate));
        // The acquisition gates follow the same rule, whatever the gates are.
        assert_eq!(refused(|c| c.star.acquisition_gate_nis = 1.0), None);
        assert_eq!(
            refused(|c| c.star.acquisition_gate_nis = f64::INFINITY),
            None
        );
        assert_eq!(
            refused(|c| c.star.acquisition_gate_nis = f64::NAN),
            Some(F::StarAcquisitionGate)
        );
        assert_eq!(
            refused(|c| c.gnss.acquisition_gate_nis = 0.0),
            Some(F::GnssAcquisitionGate)
        );
        assert_eq!(
            refused(|c| c.gnss.velocity_acquisition_gate_nis = -1.0),
            Some(F::GnssAcquisitionGate)
        );
        // The unit-norm tolerance must be positive and below 0.5.
        assert_eq!(
            refused(|c| c.star.unit_norm_tolerance = 0.5),
            Some(F::StarNormTolerance)
        );
        assert_eq!(refused(|c| c.star.unit_norm_tolerance = 0.499), None);
        assert_eq!(
            refused(|c| c.star.unit_norm_tolerance = f64::NAN),
            Some(F::StarNormTolerance)
        );
        // The latency may span the whole history, (64 − 1) frames, and no more.
        let period = FswConfig::paper_defaults(site(), SensorFrames::ALIGNED)
            .imu
            .period_s;
        assert_eq!(refused(|c| c.timing.max_latency_s = 63.0 * period), None);
        assert_eq!(
            refused(|c| c.timing.max_latency_s = 63.0 * period * (1.0 + 1e-12)),
            Some(F::MaxLatency)
        );
        assert_eq!(
            refused(|c| c.timing.max_latency_s = -1e-9),
            Some(F::MaxLatency)
        );
        assert_eq!(
            refused(|c| c.timing.max_latency_s = f64::NAN),
            Some(F::MaxLatency)
        );
        // The future tolerance is below one frame period, not negative.
        assert_eq!(
            refused(|c| c.timing.future_tolerance_s = period),
            Some(F::FutureTolerance)
        );
        assert_eq!(
            refused(|c| c.timing.future_tolerance_s = 0.999 * period),
            None
        );
        assert_eq!(
            refused(|c| c.timing.future_tolerance_s = -1e-9),
            Some(F::FutureTolerance)
        );
        assert_eq!(
            refused(|c| c.timing.future_tolerance_s = f64::INFINITY),
            Some(F::FutureTolerance)
        );
        // The propagation interval is 1..=500 frames.
        assert_eq!(
            refused(|c| c.covariance.propagation_interval_frames = 500),
            None
        );
        assert_eq!(
            refused(|c| c.covariance.propagation_interval_frames = 501),
            Some(F::PropagationInterval)
        );
        // Velocity noise 0 turns velocity fusion off; negative or NaN is refused, as is a
        // non-positive gate. Correlated-error σ and τ, and held-sample σ, likewise.
        assert_eq!(refused(|c| c.gnss.velocity_noise_mps = 0.0), None);
        assert_eq!(
            refused(|c| c.gnss.velocity_noise_mps = -1e-9),
            Some(F::GnssVelocity)
        );
        assert_eq!(
            refused(|c| c.gnss.velocity_gate_nis = 0.0),
            Some(F::GnssVelocity)
        );
        assert_eq!(
            refused(
                |c| c.filter.gnss_error = nav_core::gnss_error::GnssErrorModel {
                    sigma_m: 8.0,
                    correlation_time_s: 0.0
                }
            ),
            Some(F::GnssCorrelatedError)
        );
        // The systematic IMU error states: all 1σ zero or all positive; with the correlated
        // GNSS error states too.
        let imu_error = nav_core::imu_error_states::ImuErrorModel {
            gyro_misalignment_sigma_rad: 2e-5,
            accel_misalignment_sigma_rad: 2e-5,
            gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7,
        };
        assert_eq!(refused(|c| c.filter.imu_error = imu_error), None);
        assert_eq!(
            refused(|c| {
                c.filter.imu_error = imu_error;
                c.filter.imu_error.accel_misalignment_sigma_rad = 0.0;
            }),
            Some(F::ImuSystematicError)
        );
        assert_eq!(
            refused(|c| {
                c.filter.imu_error = imu_error;
                c.filter.gnss_error = nav_core::gnss_error::GnssErrorModel {
                    sigma_m: 8.0,
                    correlation_time_s: 300.0,
                };
            }),
            None
        );
        assert_eq!(
            refused(|c| c.covariance.held_sample.rate_rad_s = f64::NAN),
            Some(F::HeldSampleUncertainty)
        );
        assert_eq!(
            refused(|c| c.covariance.held_sample.specific_force_mps2 = -1.0),
            Some(F::HeldSampleUncertainty)
        );
        // The ceiling factor is at least 1 (and finite).
        assert_eq!(refused(|c| c.covariance.sigma_ceiling_factor = 1.0), None);
        assert_eq!(
            refused(|c| c.covariance.sigma_ceiling_factor = 0.999),
            Some(F::SigmaCeiling)
        );
        assert_eq!(
            refused(|c| c.covariance.sigma_ceiling_factor = f64::INFINITY),
            Some(F::SigmaCeiling)
        );
    }

    /// Every σ and noise density the filter squares, with the field that reports it.
    type SigmaField = (fn(&mut FswConfig, f64), ConfigField);

    const SQUARED_SIGMAS: [SigmaField; 32] = {
        use ConfigField as F;
        [
            (
                |c, v| c.filter.initial.attitude_rad = v,
                F::FilterInitialUncertainty,
            ),
            (
                |c, v| c.filter.initial.position_m = v,
                F::FilterInitialUncertainty,
            ),
            (
                |c, v| c.filter.initial.velocity_mps = v,
                F::FilterInitialUncertainty,
            ),
            (
                |c, v| c.filter.initial.gyro_bias_rad_s = v,
                F::FilterInitialUncertainty,
            ),
            (
                |c, v| c.filter.initial.accel_bias_mps2 = v,
                F::FilterInitialUncertainty,
            ),
            (
                |c, v| c.filter.initial.star_installation_rad = v,
                F::FilterInitialUncertainty,
            ),
            (
                |c, v| c.filter.initial.gyro_scale_factor = v,
                F::FilterInitialUncertainty,
            ),
            (
                |c, v| c.filter.initial.accel_scale_factor = v,
                F::FilterInitialUncertainty,
            ),
            (
                |c, v| c.covariance.sigma_floor.attitude_rad = v,
                F::SigmaFloor,
            ),
            (
                |c, v| c.covariance.sigma_floor.position_m = v,
                F::SigmaFloor,
            ),
            (
                |c, v| c.covariance.sigma_floor.velocity_mps = v,
                F::SigmaFloor,
            ),
            (
                |c, v| c.covariance.sigma_floor.gyro_bias_rad_s = v,
                F::SigmaFloor,
            ),
            (
                |c, v| c.covariance.sigma_floor.accel_bias_mps2 = v,
                F::SigmaFloor,
            ),
            (
                |c, v| c.covariance.sigma_floor.star_installation_rad = v,
                F::SigmaFloor,
            ),
            (
                |c, v| c.covariance.sigma_floor.gyro_scale_factor = v,
                F::SigmaFloor,
            ),
            (
                |c, v| c.covariance.sigma_floor.accel_scale_factor = v,
                F::SigmaFloor,
            ),
            (|c, v| c.star.noise_rad = v, F::StarNoise),
            (|c, v| c.star.roll_noise_rad = v, F::StarNoise),
            (|c, v| c.gnss.noise_m = v, F::GnssNoise),
            (
                |c, v| c.calibration.convergence_sigma.gyro_bias_rad_s = v,
                F::CalibrationThreshold,
            ),
            (
                |c, v| c.calibration.convergence_sigma.accel_bias_mps2 = v,
                F::CalibrationThreshold,
            ),
            (
                |c, v| c.calibration.convergence_sigma.star_installation_rad = v,
                F::CalibrationThreshold,
            ),
            (
                |c, v| c.calibration.convergence_sigma.gyro_scale_factor = v,
                F::CalibrationThreshold,
            ),
            (
                |c, v| c.calibration.convergence_sigma.accel_scale_factor = v,
                F::CalibrationThreshold,
            ),
            (
                |c, v| c.process_noise.gyro_noise_density_rad_s_per_sqrt_hz = v,
                F::ProcessNoise,
            ),
            (
                |c, v| c.process_noise.accel_noise_density_mps2_per_sqrt_hz = v,
                F::ProcessNoise,
            ),
            (
                |c, v| c.process_noise.gyro_bias_walk_rad_s2_per_sqrt_hz = v,
                F::ProcessNoise,
            ),
            (
                |c, v| c.process_noise.accel_bias_walk_mps3_per_sqrt_hz = v,
                F::ProcessNoise,
            ),
            (|c, v| c.gnss.velocity_noise_mps = v, F::GnssVelocity),
            (
                |c, v| {
                    c.filter.gnss_error = nav_core::gnss_error::GnssErrorModel {
                        sigma_m: v,
                        correlation_time_s: 300.0,
                    }
                },
                F::GnssCorrelatedError,
            ),
            (
                |c, v| c.covariance.held_sample.rate_rad_s = v,
                F::HeldSampleUncertainty,
            ),
            (
                |c, v| c.covariance.held_sample.specific_force_mps2 = v,
                F::HeldSampleUncertainty,
            ),
        ]
    };

    #[test]
    fn every_squared_sigma_whose_square_overflows_or_underflows_is_refused() {
        for (index, (set, field)) in SQUARED_SIGMAS.iter().enumerate() {
            // σ² = inf (1e300) or 0 (1e-300), and the first values outside the rule.
            for bad in [1e300, 1e-300, SIGMA_MAX * 1.000_001, SIGMA_MIN * 0.999_999] {
                assert_eq!(
                    refused(|c| set(c, bad)),
                    Some(*field),
                    "row {index}, {bad:e}"
                );
            }
            // The rule's ends are accepted.
            for good in [SIGMA_MIN, SIGMA_MAX] {
                assert_eq!(refused(|c| set(c, good)), None, "row {index}, {good:e}");
            }
        }
    }

    #[test]
    fn the_rule_texts_quote_the_limits_the_checks_use() {
        use ConfigField as F;
        let text = |field: F| std::format!("{field}");
        assert!(text(F::MaxLatency).starts_with("timing.max_latency_s must be"));
        let span = std::format!("{} IMU periods", history_span_frames());
        assert!(text(F::MaxLatency).contains(&span));
        let span_ms = std::format!("{:.0} ms", 1e3 * max_latency_limit_s(0.002));
        assert!(text(F::MaxLatency).contains(&span_ms), "{span_ms}");
        let interval = std::format!("1..={MAX_PROPAGATION_INTERVAL_FRAMES}");
        assert!(text(F::PropagationInterval).contains(&interval));
        let range = std::format!("[{SIGMA_MIN:e}, {SIGMA_MAX:e}]");
        for field in [
            F::FilterInitialUncertainty,
            F::StarNoise,
            F::ProcessNoise,
            F::SigmaFloor,
        ] {
            assert!(text(field).contains(&range), "{}", text(field));
        }
        let (low, high) = nav_core::frames::SITE_HEIGHT_RANGE_M;
        let height = std::format!("[{low}, {high}] m");
        assert!(text(F::LaunchSite).contains(&height));
        let order = std::format!("1..={}", nav_core::discretise::MAX_ORDER);
        assert!(text(F::FilterInitialUncertainty).contains(&order));
        let message = std::format!("{}", FswError::InvalidConfiguration(F::StarNoise));
        assert!(
            message.contains("star.noise_rad / star.roll_noise_rad must be in [1e-150, 1e150]"),
            "{message}"
        );
    }
}
