//! The flight software's configuration: one struct ([`FswConfig`]) with documented units,
//! whose every parameter is declared once in the parameter table ([`Param`]: path, unit,
//! default, range and why, replay-setup word). The defaults and the start-up validation
//! ([`FswConfig::validate`]) come from that table, so a bad value is a typed error naming the
//! key, the accepted range and the unit, never a panic or a silently wrong filter.

use nav_core::error_model::ProcessNoise;
use nav_core::filter::{FilterConfig, FilterMode, InitialUncertainty};
use nav_core::frames::LaunchSite;
use nav_core::state::OptionalBlock;
use nav_core::strapdown::StrapdownConfig;

use crate::calibration_manager::CalibrationManagerConfig;
use crate::input_check::ImuLimits;
use crate::sensor_frames::SensorFrames;

mod gravity;
mod parameters;
mod range;
mod shared_ranges;
mod table;
#[cfg(test)]
mod tests;
mod validate;

pub use gravity::GravityConfig;
pub use parameters::Param;
pub use range::{Interval, Number, ParamValue, Range};
pub use shared_ranges::{CORRELATION_TIME_RANGE_S, CORRELATION_TIME_WHY};
pub use validate::COMPANIONS;

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

/// Smallest 1σ or noise density accepted where the filter squares it ([`sigma_is_squarable`]).
pub const SIGMA_MIN: f64 = 1e-150;

/// Largest 1σ or noise density accepted where the filter squares it ([`sigma_is_squarable`]).
pub const SIGMA_MAX: f64 = 1e150;

/// The numerical bound of every 1σ and noise density the filter squares into `P`, `Q` or
/// `R`, which every such range of the parameter table lies within (a test holds them to it):
/// `σ` in [[`SIGMA_MIN`], [`SIGMA_MAX`]], so `σ²` lies in [1e-300, 1e300], inside the normal
/// `f64` range [2.2e-308, 1.8e308]. The square then neither overflows to ∞ nor underflows to
/// 0 or a subnormal (an infinite or singular covariance), with eight decades left for the
/// factors the filter applies to it (the half-angle states' ½, the ceiling factor, frame
/// periods). NaN, 0 and negative values fail.
pub fn sigma_is_squarable(sigma: f64) -> bool {
    (SIGMA_MIN..=SIGMA_MAX).contains(&sigma)
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
    /// a random walk (`scheduler::covariance`, docs/guide/sensor-errors.md).
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
    /// (`scheduler::heads`, docs/guide/sensor-errors.md).
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

    /// Every value 0: the head the replay setup's `star.second_head` word creates before its
    /// values are read.
    pub const ZERO: Self = Self {
        mounting_wxyz: [0.0; 4],
        noise_rad: 0.0,
        roll_noise_rad: 0.0,
        alignment_prior_sigma_rad: 0.0,
        pair_gate_nis: 0.0,
        pairs_before_hand_over: 0,
    };
}

/// Whether `[w, x, y, z]` is a unit quaternion within nav-core's unit-norm tolerance (a
/// mounting).
pub(crate) fn is_unit_quaternion(wxyz: &[f64; 4]) -> bool {
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
    /// (docs/guide/model.md, "Bias instability in the filter", the same argument). Zero when off.
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
    /// Floor of the 1σ of every optional state block in use (nav-core `OptionalBlock`), per
    /// block, as [`Self::sigma_floor`] for the core's.
    pub optional_sigma_floor: OptionalSigmaFloor,
    /// Ceiling of every 1σ, the optional blocks' included, as a multiple of its initial 1σ
    /// (an optional state's: its prior's); a larger variance is scaled back with its row and
    /// column (correlations kept), counted.
    pub sigma_ceiling_factor: f64,
    /// What a held IMU sample may be wrong by ([`HeldSampleUncertainty`]).
    pub held_sample: HeldSampleUncertainty,
    /// Whether the attitude covariance grows for the kinematics' second-order term while the
    /// star sensor is unheard ([`SecondOrderAttitude`]).
    pub second_order_attitude: SecondOrderAttitude,
}

/// Floor of the 1σ of each optional state block (units of the block), read only while the
/// block is in use: a variance below its floor² is raised to it (counted).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct OptionalSigmaFloor {
    /// The receiver's correlated position error (m).
    pub gnss_error_m: f64,
    /// Gyro non-orthogonality (rad).
    pub gyro_non_orthogonality_rad: f64,
    /// Accelerometer misalignment (rad).
    pub accel_misalignment_rad: f64,
    /// Gyro g-sensitivity (rad/s per m/s²).
    pub gyro_g_sensitivity_rad_s_per_mps2: f64,
}

impl OptionalSigmaFloor {
    /// The floors in [`OptionalBlock::ALL`] order.
    pub fn by_block(&self) -> [f64; OptionalBlock::ALL.len()] {
        OptionalBlock::ALL.map(|block| match block {
            OptionalBlock::GnssError => self.gnss_error_m,
            OptionalBlock::GyroNonOrthogonality => self.gyro_non_orthogonality_rad,
            OptionalBlock::AccelMisalignment => self.accel_misalignment_rad,
            OptionalBlock::GyroGSensitivity => self.gyro_g_sensitivity_rad_s_per_mps2,
        })
    }
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

/// A launch site of zeros on the ECEF `z` axis: the defaults' site where the mission's does
/// not matter (the parts' defaults, the replay setup before its words are read).
pub(crate) const ZERO_SITE: LaunchSite = LaunchSite {
    latitude_rad: 0.0,
    longitude_rad: 0.0,
    height_m: 0.0,
    azimuth_rad: 0.0,
    earth_axis_ecef: nav_core::frames::ECEF_Z_AXIS,
};

impl FswConfig {
    /// The paper's values where it gives them (Section 3: 500 Hz, 10″ star sensor, 10 m
    /// GNSS, 3rd-order discretisation, its noise densities) and documented choices
    /// elsewhere, for a launch site given by the mission: every parameter's default of the
    /// parameter table ([`Param`]). For the paper's experiment and as the base the other
    /// configurations change: it is the paper's idealised filter (point mass + `J2` without
    /// an allowance, no IMU error states, no star slow error), not a vehicle's. A flight is
    /// configured from its sensors' data sheets ([`FswConfig::from_datasheets`]).
    pub fn paper_defaults(launch_site: LaunchSite, sensor_frames: SensorFrames) -> Self {
        let mut config = Self::blank(launch_site, sensor_frames);
        for param in Param::ALL {
            param.set_default(&mut config);
        }
        config
    }

    /// The table's defaults at a launch site of zeros: the defaults of the configuration's
    /// parts (`ImuLimits::default`, ...).
    pub(crate) fn table_defaults() -> Self {
        Self::paper_defaults(ZERO_SITE, SensorFrames::ALIGNED)
    }

    /// Every value the parameter table sets NaN, 0, `false` or a first choice (the table's
    /// defaults overwrite them, a test checks no NaN is left), the rest as given.
    fn blank(launch_site: LaunchSite, sensor_frames: SensorFrames) -> Self {
        const NAN: f64 = f64::NAN;
        let uncertainty = InitialUncertainty {
            attitude_rad: NAN,
            position_m: NAN,
            velocity_mps: NAN,
            gyro_bias_rad_s: NAN,
            accel_bias_mps2: NAN,
            star_installation_rad: NAN,
            gyro_scale_factor: NAN,
            accel_scale_factor: NAN,
        };
        Self {
            launch_site,
            sensor_frames,
            strapdown: StrapdownConfig::default(),
            filter: FilterConfig {
                mode: FilterMode::OpenLoop,
                discretisation_order: 0,
                initial: uncertainty,
                gnss_error: nav_core::gnss_error::GnssErrorModel {
                    sigma_m: NAN,
                    correlation_time_s: NAN,
                },
                imu_error: nav_core::imu_error_states::ImuErrorModel {
                    gyro_misalignment_sigma_rad: NAN,
                    accel_misalignment_sigma_rad: NAN,
                    gyro_g_sensitivity_sigma_rad_s_per_mps2: NAN,
                },
            },
            process_noise: ProcessNoise {
                gyro_noise_density_rad_s_per_sqrt_hz: NAN,
                accel_noise_density_mps2_per_sqrt_hz: NAN,
                gyro_bias_walk_rad_s2_per_sqrt_hz: NAN,
                accel_bias_walk_mps3_per_sqrt_hz: NAN,
            },
            imu: ImuLimits {
                period_s: NAN,
                period_tolerance: NAN,
                max_rate_rad_s: NAN,
                max_specific_force_mps2: NAN,
            },
            star: StarSensorConfig {
                mounting_wxyz: [NAN; 4],
                noise_rad: NAN,
                roll_noise_rad: NAN,
                gate_nis: NAN,
                acquisition_gate_nis: NAN,
                unit_norm_tolerance: NAN,
                slow_error_sigma_rad: [NAN; 3],
                slow_error_correlation_time_s: NAN,
                aberration_correction: false,
                noise_matching: false,
                second_head: None,
            },
            gnss: GnssConfig {
                lever_arm_body_m: [NAN; 3],
                noise_m: NAN,
                gate_nis: NAN,
                acquisition_gate_nis: NAN,
                max_jump_m: NAN,
                velocity_noise_mps: NAN,
                velocity_gate_nis: NAN,
                velocity_acquisition_gate_nis: NAN,
                whiteness_window_fixes: NAN,
                whiteness_threshold: NAN,
            },
            timing: MeasurementTiming {
                max_latency_s: NAN,
                future_tolerance_s: NAN,
                outage_timeout_s: NAN,
                rejections_to_declare_faulty: 0,
            },
            covariance: CovarianceConfig {
                propagation_interval_frames: 0,
                frame_load: FrameLoad::PropagateThenFuse,
                sigma_floor: uncertainty,
                optional_sigma_floor: OptionalSigmaFloor {
                    gnss_error_m: NAN,
                    gyro_non_orthogonality_rad: NAN,
                    accel_misalignment_rad: NAN,
                    gyro_g_sensitivity_rad_s_per_mps2: NAN,
                },
                sigma_ceiling_factor: NAN,
                held_sample: HeldSampleUncertainty {
                    rate_rad_s: NAN,
                    specific_force_mps2: NAN,
                },
                second_order_attitude: SecondOrderAttitude::Neglected,
            },
            calibration: CalibrationManagerConfig {
                convergence_sigma: crate::calibration_manager::CalibrationThresholds {
                    gyro_bias_rad_s: NAN,
                    accel_bias_mps2: NAN,
                    star_installation_rad: NAN,
                    gyro_scale_factor: NAN,
                    accel_scale_factor: NAN,
                },
                stability_window_s: NAN,
                stability_fraction: NAN,
                freeze_converged: false,
                policy: crate::calibration_manager::EstimationPolicy::AllBlocks,
                motion_rate_threshold_rad_s: NAN,
                motion_force_threshold_mps2: NAN,
                motion_observability:
                    crate::motion_observability::MotionObservabilityTable::structural(),
            },
            consistency: crate::consistency::ConsistencyConfig {
                time_constant_measurements: 0,
                mean_nis_bound: NAN,
            },
            gravity: GravityConfig {
                field: nav_core::gravity::harmonics::FieldModel {
                    degree: 0,
                    order: 0,
                    terms_per_frame: 0,
                },
                omitted_field_sigma_mps2: NAN,
                omitted_field_psd_m2_per_s3: NAN,
            },
        }
    }
}
