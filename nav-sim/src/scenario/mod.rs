//! Scenarios: everything a simulation run needs, read from TOML.
//!
//! The built-in default is `scenarios/default.toml` (the paper's Section 3), embedded with
//! `include_str!` and parsed from that same text, so the printed file and the default can never
//! diverge ([`DEFAULT_SCENARIO_TOML`], [`Scenario::default_scenario`]).
//!
//! A scenario file may name a base and hold only what differs from it (`extends = "base.toml"`,
//! `remove = ["gravity"]`; [`overlay`]); `nav-sim scenario --resolved FILE` prints the result,
//! and the outputs name a scenario by its resolved SHA-256.
//!
//! Every table is `deny_unknown_fields`: a misspelt key is an error naming it. Every value is
//! checked by [`Scenario::validate`], whose errors name the key (`"imu.rate_hz must be > 0"`).
//! Units are SI unless a field name says otherwise (`_deg`, `_arcsec`, `_deg_per_h_...`).

use std::path::Path;

use nav_core::frames::LaunchSite;
use nav_fsw::config::FswConfig;
use schemars::JsonSchema;
use serde::Deserialize;

pub mod commands;
mod debug;
pub mod dispersion;
pub mod epoch;
pub mod gravity;
pub mod overlay;
#[cfg(test)]
mod overlay_tests;
pub mod star_sensor;
#[cfg(test)]
mod tests;
mod validate;

use epoch::{EarthOrientation, EpochError, LaunchEpoch};
pub use star_sensor::{StarAberration, StarSensorSettings};

/// The default scenario file, verbatim (what `nav-sim scenario` prints).
pub const DEFAULT_SCENARIO_TOML: &str = include_str!("../../scenarios/default.toml");

/// Largest accepted magnitude of a scale-factor error (dimensionless). The error model divides
/// by `1 − λ`, and any real sensor is far below this.
pub const MAX_SCALE_FACTOR_MAGNITUDE: f64 = 0.1;
/// Relative tolerance when checking that a duration is a whole number of IMU frames.
const WHOLE_FRAME_TOLERANCE: f64 = 1.0e-9;

/// Longest flight, the sum of the manoeuvre durations (s): one day. A calibration flight is
/// an upper stage's orbital phase of minutes to hours; run time and the recorded history grow
/// with the duration (one day at 500 Hz is 43.2 M frames, 28 default flights, and 345,600
/// recorded samples of about 0.5 kB).
pub const MAX_DURATION_S: f64 = 86_400.0;

/// Most truth integration substeps per IMU frame. RK4's local error falls as `h⁵`: the
/// default 16 (125 µs at 500 Hz) already puts the truth's integration error far below the
/// sensors' noise, and 256 is 16 times finer still; beyond it the truth costs more without
/// being more accurate (rounding dominates).
pub const MAX_TRUTH_SUBSTEPS_PER_FRAME: u32 = 256;

/// Most truth integration steps in one flight (frames × substeps): about 40 default flights
/// (2.46e7 steps each), minutes of run time in a release build; one day at 500 Hz with the
/// default 16 substeps is 6.9e8.
pub const MAX_TRUTH_STEPS: f64 = 1.0e9;

/// Largest `simulation.start_time_s` (s). Every time in a run is at most this plus
/// [`MAX_DURATION_S`], below 2²⁴ s, where the f64 resolution ulp(t) is 2⁻²⁹ s = 1.9e-9 s: a
/// millionth of the 2 ms frame, so frame times `t₀ + k T` and the sensors' time tags agree to
/// nanoseconds. At 1e12 s ulp(t) is 1.2e-4 s (6 % of a frame) and GNSS fixes miss their
/// frames; at 1e17 s it is 16 s. 1e7 s is 116 days after the launch epoch, longer than any
/// upper stage's mission.
pub const MAX_START_TIME_S: f64 = 1.0e7;

/// Range of every 1σ and noise key (in the key's units): its square stays far inside the
/// normal f64 range, neither infinite nor zero / subnormal in the filter's covariance. It is
/// the flight software's σ rule ([`nav_fsw::config::SIGMA_MIN`],
/// [`nav_fsw::config::SIGMA_MAX`], 1e∓150) narrowed by [`SIGMA_UNIT_MARGIN`] on each side, so
/// that the unit conversions between the keys and the flight software (1″ = 4.8e-6 rad,
/// 1 °/h = 4.8e-9 rad/s, a per-sample σ times `√T`) never take a valid key outside it.
/// Noise keys whose 0 switches the noise off also accept 0.
pub const SIGMA_RANGE: (f64, f64) = (1.0e-100, 1.0e100);

/// Decades between [`SIGMA_RANGE`] and the flight software's σ rule, as a factor.
pub const SIGMA_UNIT_MARGIN: f64 = 1.0e50;

/// Largest `gnss.latency_s` the flight software can fuse at an IMU period (s): its navigation
/// history reaches [`nav_fsw::config::max_latency_limit_s`] back (63 frames), and the flight
/// is configured with `latency_s` plus one frame of hand-over margin
/// (the setup layer's `replay_setup`): 62 frames, 0.124 s at 500 Hz.
pub fn max_gnss_latency_s(period_s: f64) -> f64 {
    nav_fsw::config::max_latency_limit_s(period_s) - period_s
}

/// The requirement `gnss.latency_s` violates at IMU period `period_s`, if any: the message
/// of both [`Scenario::validate`] and the flight's configuration error.
pub fn gnss_latency_violation(latency_s: f64, period_s: f64) -> Option<String> {
    let limit_s = max_gnss_latency_s(period_s);
    (latency_s > limit_s).then(|| {
        format!(
            "= {} s is above the flight software's limit {} s (its measurement history, \
             nav_fsw::config::HISTORY_CAPACITY = {} frames, reaches {} frames of {} s back, \
             one of them the hand-over margin: {} frames of latency)",
            number(latency_s),
            number(limit_s),
            nav_fsw::config::HISTORY_CAPACITY,
            nav_fsw::config::history_span_frames(),
            number(period_s),
            nav_fsw::config::history_span_frames().saturating_sub(1),
        )
    })
}

/// A number as a message shows it: plain between 1e-4 and 1e7 (at most 9 decimals, no
/// trailing zeros), otherwise in exponent form (`1e9`, `1e-300`).
pub fn number(value: f64) -> String {
    if value == 0.0 || (1.0e-4..1.0e7).contains(&value.abs()) {
        let text = format!("{value:.9}");
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{value:e}")
    }
}

/// Why a scenario could not be loaded or is not valid.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    /// The scenario file could not be read.
    #[error("cannot read scenario file {path}: {source}")]
    Io {
        /// The file that was being read.
        path: String,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The text is not valid TOML for a scenario (syntax, unknown key, wrong type, missing key).
    /// The message comes from the TOML parser and names the key and the line.
    #[error("scenario {origin}: {message}")]
    Parse {
        /// Where the text came from (a file path, or `"<built-in default>"` / `"<string>"`).
        origin: String,
        /// The parser's description, naming the offending key.
        message: String,
    },
    /// A value is out of its documented range.
    #[error("scenario {origin}: {key} {requirement}")]
    Invalid {
        /// Where the text came from.
        origin: String,
        /// Dotted path of the offending key, e.g. `imu.rate_hz` or `manoeuvre[3].ramp_s`.
        key: String,
        /// What the value must satisfy, e.g. "must be > 0".
        requirement: String,
    },
    /// An overlay chain (`extends`, `remove`) cannot be resolved ([`overlay`]).
    #[error("scenario {file}: {error}")]
    Overlay {
        /// The file whose `extends` or `remove` is at fault.
        file: String,
        /// What is wrong.
        error: overlay::OverlayError,
    },
}

/// A complete simulation scenario (the TOML file's top level).
///
/// Its `Debug` rendering leaves out an absent `[dispersion]` or `[gravity]` table, so a
/// scenario without one renders (and hashes, the campaign's `scenario_hash`) as it did before
/// the table existed.
#[derive(Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Run control: seed, start time, truth integration.
    pub simulation: SimulationSettings,
    /// The launch site, which defines the launch-inertial frame.
    pub launch_site: LaunchSiteSettings,
    /// The orbit at the scenario start.
    pub initial_orbit: OrbitElements,
    /// The attitude at the scenario start.
    pub initial_attitude: InitialAttitude,
    /// IMU sampling.
    pub imu: ImuSettings,
    /// Gyro error model (paper eq. 1).
    pub gyro: GyroErrors,
    /// Accelerometer error model (paper eq. 3).
    pub accelerometer: AccelerometerErrors,
    /// Star sensor model.
    pub star_sensor: StarSensorSettings,
    /// GNSS receiver model.
    pub gnss: GnssSettings,
    /// The manoeuvre schedule, segments back to back (TOML `[[manoeuvre]]`).
    #[serde(rename = "manoeuvre")]
    pub manoeuvres: Vec<ManoeuvreSegment>,
    /// Filter settings (placeholders the filter reads).
    pub filter: FilterSettings,
    /// Truth-side quantities drawn afresh for every Monte Carlo run; absent = none
    /// ([`dispersion`]).
    #[serde(default)]
    pub dispersion: Option<dispersion::Dispersion>,
    /// The truth's gravity field; absent = the flight code's point mass + `J2` ([`gravity`]).
    #[serde(default)]
    pub gravity: Option<gravity::GravitySettings>,
    /// Ground commands given to the flight software during the flight (TOML `[[command]]`;
    /// [`commands`]); absent = none.
    #[serde(default, rename = "command")]
    pub commands: Vec<commands::ScheduledCommand>,
}

/// Run control.
#[derive(Debug, Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SimulationSettings {
    /// Seed of the deterministic random streams.
    pub seed: u64,
    /// Scenario start, seconds after the launch epoch (navigation time of the first sample).
    pub start_time_s: f64,
    /// Truth integration substeps per IMU frame (RK4), at least 1.
    pub truth_substeps_per_frame: u32,
    /// Lowest altitude the truth trajectory may reach (m above the WGS-84 ellipsoid, along
    /// the geocentric radius), ≥ 0; a flight that goes below it is refused, naming the
    /// segment and the time. Default 150 km (below it the atmosphere the simulator does not
    /// model decays the orbit within hours).
    #[serde(default = "default_min_altitude_m")]
    pub min_altitude_m: f64,
}

/// [`SimulationSettings::min_altitude_m`]'s default (m).
pub const DEFAULT_MIN_ALTITUDE_M: f64 = 150_000.0;

fn default_min_altitude_m() -> f64 {
    DEFAULT_MIN_ALTITUDE_M
}

fn default_true() -> bool {
    true
}

/// The launch site: origin and orientation of the launch-inertial frame.
#[derive(Debug, Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LaunchSiteSettings {
    /// Geodetic latitude (deg, WGS-84), in [−90, 90].
    pub latitude_deg: f64,
    /// Longitude (deg, east positive), in [−180, 360].
    pub longitude_deg: f64,
    /// Height above the WGS-84 ellipsoid (m).
    pub height_m: f64,
    /// Launch azimuth, clockwise from north (deg), in [−360, 360].
    pub azimuth_deg: f64,
    /// Launch epoch (ISO 8601, UTC): fixes the GCRF → launch-inertial rotation and the GPS
    /// time of the launch ([`epoch`]).
    pub epoch_utc: String,
    /// Earth orientation parameters of the launch day (IERS Bulletin A).
    pub earth_orientation: EarthOrientation,
}

impl LaunchSiteSettings {
    /// The launch epoch (`epoch_utc`, `earth_orientation`).
    ///
    /// # Errors
    /// As [`LaunchEpoch::new`].
    pub fn epoch(&self) -> Result<LaunchEpoch, EpochError> {
        LaunchEpoch::new(&self.epoch_utc, self.earth_orientation)
    }

    /// nav-core's [`LaunchSite`] for this site, rotating about the Earth axis (CIP) of its
    /// epoch ([`LaunchEpoch::earth_axis_ecef`]; the ECEF `z` axis for an epoch that does not
    /// parse, which scenario validation refuses).
    pub fn nav_site(&self) -> LaunchSite {
        LaunchSite {
            latitude_rad: self.latitude_deg.to_radians(),
            longitude_rad: self.longitude_deg.to_radians(),
            height_m: self.height_m,
            azimuth_rad: self.azimuth_deg.to_radians(),
            earth_axis_ecef: self.epoch().map_or(nav_core::frames::ECEF_Z_AXIS, |epoch| {
                epoch.earth_axis_ecef()
            }),
        }
    }
}

/// Keplerian elements at the scenario start, in the Earth-centred inertial frame that coincides
/// with ECEF at the launch epoch.
#[derive(Debug, Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OrbitElements {
    /// Semi-major axis (m); perigee must be above the Earth's equatorial radius.
    pub semi_major_axis_m: f64,
    /// Eccentricity, in [0, 1).
    pub eccentricity: f64,
    /// Inclination (deg), in [0, 180].
    pub inclination_deg: f64,
    /// Right ascension of the ascending node, from the launch-epoch Greenwich meridian (deg).
    pub right_ascension_of_node_deg: f64,
    /// Argument of perigee (deg).
    pub argument_of_perigee_deg: f64,
    /// True anomaly at the scenario start (deg).
    pub true_anomaly_deg: f64,
}

/// The truth attitude at the scenario start.
#[derive(Debug, Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct InitialAttitude {
    /// `q_ib = exp(φ)` (body to launch-inertial) as a rotation vector `φ` (deg).
    pub rotation_vector_deg: [f64; 3],
}

/// IMU sampling.
#[derive(Debug, Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ImuSettings {
    /// Output rate of the increments (Hz), > 0.
    pub rate_hz: f64,
    /// Gyro measurement range per axis (deg/s), > 0; absent = the flight software's
    /// default (401 °/s, 7 rad/s). A manoeuvre at or beyond it is refused.
    #[serde(default)]
    pub max_rate_deg_per_s: Option<f64>,
    /// Accelerometer measurement range per axis (m/s²), > 0; absent = the flight software's
    /// default (200 m/s²). A manoeuvre at or beyond it is refused.
    #[serde(default)]
    pub max_specific_force_mps2: Option<f64>,
}

impl ImuSettings {
    /// The IMU frame (increment) period `T = 1 / rate` (s).
    pub fn frame_period_s(&self) -> f64 {
        1.0 / self.rate_hz
    }

    /// The measurement ranges in the flight software's units (rad/s, m/s²): the keys, or the
    /// flight software's defaults exactly.
    pub fn ranges_si(&self) -> (f64, f64) {
        let defaults = nav_fsw::input_check::ImuLimits::default();
        (
            self.max_rate_deg_per_s
                .map_or(defaults.max_rate_rad_s, f64::to_radians),
            self.max_specific_force_mps2
                .unwrap_or(defaults.max_specific_force_mps2),
        )
    }

    /// The measurement ranges (deg/s, m/s²): the keys, or the flight software's defaults.
    pub fn ranges(&self) -> (f64, f64) {
        let defaults = nav_fsw::input_check::ImuLimits::default();
        (
            self.max_rate_deg_per_s
                .unwrap_or(defaults.max_rate_rad_s.to_degrees()),
            self.max_specific_force_mps2
                .unwrap_or(defaults.max_specific_force_mps2),
        )
    }
}

/// Gyro errors, paper eq. (1): `ω_meas = ω + Λg ω_meas + b_g + η_g`, extended by the
/// misalignment, g-sensitivity and bias-instability terms of `docs/guide/model.md` ("IMU
/// misalignment, g-sensitivity and bias instability"), all optional (0 = off).
///
/// Its `Debug` rendering leaves out those optional terms while they are zero, so a scenario
/// without them renders (and hashes) as it did before they existed.
#[derive(Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GyroErrors {
    /// White rate-noise spectral density ((deg/h)/√Hz), ≥ 0. The paper's "0.2 °/h".
    pub rate_noise_density_deg_per_h_per_sqrt_hz: f64,
    /// Constant bias `b_g` (rad/s), body axes.
    pub bias_rad_per_s: [f64; 3],
    /// Scale-factor errors, the diagonal of `Λg` (dimensionless), `|λ| ≤ 0.1`.
    pub scale_factor: [f64; 3],
    /// Bias random-walk intensity ((rad/s)/√s), ≥ 0; 0 = constant bias.
    pub bias_random_walk_rad_per_s_per_sqrt_s: f64,
    /// Output quantum of the delta angle (rad), ≥ 0; 0 = no quantisation.
    pub quantum_rad: f64,
    /// Misalignment and non-orthogonality of the triad (rad): the off-diagonal terms `a_ij`
    /// of `M = I + A`, the increment sensed on axis `i` gains `a_ij Δθ_j` (body axes). The
    /// diagonal must be 0 (it is `scale_factor`); `|a_ij| ≤` [`MAX_MISALIGNMENT_RAD`].
    /// Default all 0 (off).
    #[serde(default)]
    pub misalignment_rad: [[f64; 3]; 3],
    /// g-sensitivity per axis (rad/s per m/s²): the rate error on axis `i` is `g_i f_i`, `f`
    /// the true body specific force; `|g_i| ≤` [`MAX_G_SENSITIVITY_RAD_S_PER_MPS2`].
    /// Default 0 (off).
    #[serde(default)]
    pub g_sensitivity_rad_s_per_mps2: [f64; 3],
    /// Bias instability: stationary 1σ per axis (rad/s) of a first-order Gauss–Markov bias
    /// added to `bias_rad_per_s`; 0 (the default) = off.
    #[serde(default)]
    pub bias_instability_sigma_rad_per_s: f64,
    /// Its correlation time τ (s), > 0 when `bias_instability_sigma_rad_per_s` > 0.
    #[serde(default)]
    pub bias_instability_correlation_time_s: f64,
}

/// Largest accepted magnitude of a misalignment term (rad, 10 mrad = 0.57°): far above a
/// navigation-grade (5–20 µrad) or tactical (≥ 100 µrad) triad, and small enough that the
/// model's small-angle form `I + A` stays meaningful.
pub const MAX_MISALIGNMENT_RAD: f64 = 1.0e-2;

/// Largest accepted magnitude of a gyro g-sensitivity (rad/s per m/s², ≈ 2000 °/h/g):
/// navigation-grade gyros have 0.1–10 °/h/g, MEMS gyros up to a few hundred.
pub const MAX_G_SENSITIVITY_RAD_S_PER_MPS2: f64 = 1.0e-3;

impl GyroErrors {
    /// Rate-noise density in SI units (rad/s/√Hz = rad/√s).
    pub fn rate_noise_density_rad_per_sqrt_s(&self) -> f64 {
        nav_fsw::datasheet::deg_per_h_to_rad_per_s(self.rate_noise_density_deg_per_h_per_sqrt_hz)
    }

    /// 1σ of the delta-angle noise per increment of length `interval_s`:
    /// white rate noise integrated over the interval, `σ_Δθ = density · √T` (rad).
    pub fn delta_angle_noise_sigma_rad(&self, interval_s: f64) -> f64 {
        self.rate_noise_density_rad_per_sqrt_s() * interval_s.sqrt()
    }
}

/// Accelerometer errors, paper eq. (3): `f_meas = f + Λa f_meas + b_a + η_a`, extended by
/// the optional misalignment and bias-instability terms (0 = off; `Debug` leaves them out
/// while zero, as [`GyroErrors`]'s does).
#[derive(Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AccelerometerErrors {
    /// 1σ of the specific-force noise per IMU sample (m/s²), ≥ 0. The paper's "1e-4 m/s²".
    pub noise_per_sample_mps2: f64,
    /// Constant bias `b_a` (m/s²), body axes.
    pub bias_mps2: [f64; 3],
    /// Scale-factor errors, the diagonal of `Λa` (dimensionless), `|λ| ≤ 0.1`.
    pub scale_factor: [f64; 3],
    /// Bias random-walk intensity ((m/s²)/√s), ≥ 0; 0 = constant bias.
    pub bias_random_walk_mps2_per_sqrt_s: f64,
    /// Output quantum of the delta velocity (m/s), ≥ 0; 0 = no quantisation.
    pub quantum_mps: f64,
    /// Misalignment and non-orthogonality of the triad (rad), as
    /// [`GyroErrors::misalignment_rad`]: the increment sensed on axis `i` gains `a_ij Δv_j`.
    /// Default all 0 (off).
    #[serde(default)]
    pub misalignment_rad: [[f64; 3]; 3],
    /// Bias instability: stationary 1σ per axis (m/s²) of a first-order Gauss–Markov bias
    /// added to `bias_mps2`; 0 (the default) = off.
    #[serde(default)]
    pub bias_instability_sigma_mps2: f64,
    /// Its correlation time τ (s), > 0 when `bias_instability_sigma_mps2` > 0.
    #[serde(default)]
    pub bias_instability_correlation_time_s: f64,
}

/// GNSS receiver: ECEF position fixes.
#[derive(Debug, Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GnssSettings {
    /// Fix rate (Hz), > 0; the IMU rate must be a whole multiple of it.
    pub rate_hz: f64,
    /// Position noise, 1σ per ECEF axis (m), ≥ 0.
    pub noise_m: f64,
    /// Delivery latency (s), ≥ 0, a whole number of IMU frames.
    pub latency_s: f64,
    /// Correlated position error: 1σ per ECEF axis (m) of a first-order Gauss–Markov error
    /// added to the white `noise_m`, ≥ 0; 0 (the default) = none.
    #[serde(default)]
    pub correlated_noise_m: f64,
    /// Its correlation time τ (s), > 0 when `correlated_noise_m` > 0.
    #[serde(default)]
    pub correlation_time_s: f64,
    /// Velocity noise, 1σ per ECEF axis (m/s), ≥ 0: 0 (the default) = the receiver outputs
    /// no velocity; > 0 = it also outputs ECEF velocity with this white noise.
    #[serde(default)]
    pub velocity_noise_mps: f64,
    /// Outages `[[start_s, duration_s], ...]`, seconds after the scenario start: no fix is
    /// valid during `[start, start + duration)`.
    #[serde(default)]
    pub outages: Vec<[f64; 2]>,
}

/// Whether `elapsed_s` (seconds after the scenario start) falls in one of `outages`.
pub fn in_outage(outages: &[[f64; 2]], elapsed_s: f64) -> bool {
    outages
        .iter()
        .any(|[start_s, duration_s]| (*start_s..start_s + duration_s).contains(&elapsed_s))
}

/// One manoeuvre segment: a raised-cosine pulse of body rate and body specific force.
///
/// The command is `peak · s(τ)` for `τ ∈ [0, duration_s]`, with `s` rising from 0 to 1 as
/// `½(1 − cos(π τ / ramp_s))` over `ramp_s`, holding 1, and falling symmetrically over the last
/// `ramp_s`; `∫ s dτ = duration_s − ramp_s`. `ramp_s = 0` is a constant command.
#[derive(Debug, Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ManoeuvreSegment {
    /// Free-text name (for reports).
    pub label: String,
    /// Segment length including both ramps (s), > 0, a whole number of IMU frames.
    pub duration_s: f64,
    /// Rise time and fall time (s), `0 ≤ 2 ramp_s ≤ duration_s`.
    pub ramp_s: f64,
    /// Peak body angular rate `ω_ib^b` (deg/s), body axes.
    pub body_rate_deg_per_s: [f64; 3],
    /// Peak body specific force (non-gravitational acceleration, m/s²), body axes.
    pub specific_force_mps2: [f64; 3],
}

/// The filter's mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum FilterMode {
    /// The paper's filter: errors estimated, the navigation solution not corrected. Its linear
    /// model holds only while the uncorrected navigation errors stay small (the default
    /// scenario's comment on `mode` gives the numbers); kept for comparison with the paper.
    OpenLoop,
    /// Feedback: navigation solution and sensor corrections reset after each update.
    ClosedLoop,
}

/// Filter settings (placeholders for the 24-state filter).
///
/// `Debug` is written out in `debug.rs`: `bias_instability` renders only when it is on, so a
/// scenario without it hashes as before the table existed.
#[derive(Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FilterSettings {
    /// Open- or closed-loop.
    pub mode: FilterMode,
    /// Order of the truncated transition-matrix series, 1..=4 (paper: 3).
    pub discretisation_order: u32,
    /// Initial 1σ per error-state block.
    pub initial_sigma: InitialSigma,
    /// Innovation gates.
    pub nis_gate: NisGate,
    /// The correlated GNSS error the filter assumes: 1σ per axis (m) of a first-order
    /// Gauss–Markov position error, ≥ 0; 0 (the default) = white errors only, the paper's
    /// 24-state model.
    #[serde(default)]
    pub gnss_correlated_sigma_m: f64,
    /// Its correlation time τ (s), > 0 when `gnss_correlated_sigma_m` > 0.
    #[serde(default)]
    pub gnss_correlation_time_s: f64,
    /// The white GNSS position noise the filter assumes, 1σ per axis (m); absent = the
    /// simulated receiver's `[gnss] noise_m` (a study of a mis-specified filter sets it).
    #[serde(default)]
    pub gnss_noise_m: Option<f64>,
    /// The white star-tracker noise the filter assumes, 1σ about every sensor axis (arcsec);
    /// absent = the simulated tracker's per-axis noise (`[star_sensor]`). A study of a
    /// flight software told the paper's isotropic 10″ sets it.
    #[serde(default)]
    pub star_noise_arcsec: Option<f64>,
    /// The IMU bias instability the filter assumes (`[filter.bias_instability]`); absent =
    /// constant biases (beside any configured random walk), the paper's model.
    #[serde(default)]
    pub bias_instability: FilterBiasInstability,
    /// The systematic IMU error states the filter estimates (`[filter.imu_errors]`); absent
    /// = none, the paper's 24 states.
    #[serde(default)]
    pub imu_errors: FilterImuErrors,
    /// The flight's gravity beyond `J2` and its allowance (`[filter.gravity]`); absent =
    /// point mass + `J2`, no allowance.
    #[serde(default)]
    pub gravity: gravity::FilterGravity,
    /// The star tracker's slowly varying error the filter accounts for
    /// (`[filter.star_slow_error]`); absent = a constant installation error, the paper's
    /// model.
    #[serde(default)]
    pub star_slow_error: star_sensor::FilterStarSlowError,
    /// Whether the flight software removes the star tracker's velocity aberration with its
    /// navigation velocity (`star.aberration_correction`), for a tracker that leaves it in
    /// (`[star_sensor] aberration = "uncorrected"`); false (the default) = it does not.
    #[serde(default)]
    pub star_aberration_correction: bool,
    /// Whether the flight software's star noise follows the innovations once they fail the
    /// consistency test (`star.noise_matching`, nav-fsw `noise_matching`); true (the default)
    /// = it does, false = the configured noise throughout.
    #[serde(default = "default_true")]
    pub star_noise_matching: bool,
    /// Whether the flight software is told of the tracker's second head (the first
    /// `[[star_sensor.additional_heads]]`, as `star.second_head`); true (the default) = it
    /// is, false = it is configured with one head, and the second head's measurements reach
    /// its port as from a head it does not have (counted in `star_unknown_head`).
    #[serde(default = "default_true")]
    pub star_second_head: bool,
    /// Pairs of the two heads accepted before the flight software may hand its installation
    /// block to the second head, and agreeing pairs in a row before a head declared faulty
    /// takes it back (`star.second_head.pairs_before_hand_over`); default
    /// [`DEFAULT_STAR_PAIRS_BEFORE_HAND_OVER`].
    #[serde(default = "default_star_pairs_before_hand_over")]
    pub star_pairs_before_hand_over: u32,
}

/// Default of `[filter] star_pairs_before_hand_over`: the data-sheet configuration's
/// ([`nav_fsw::datasheet::PAIRS_BEFORE_HAND_OVER`], 100 pairs, 10 s at 10 Hz).
pub const DEFAULT_STAR_PAIRS_BEFORE_HAND_OVER: u32 = nav_fsw::datasheet::PAIRS_BEFORE_HAND_OVER;

fn default_star_pairs_before_hand_over() -> u32 {
    DEFAULT_STAR_PAIRS_BEFORE_HAND_OVER
}

/// The triads' specification behind the filter's systematic IMU error states (nav-core
/// `imu_error_states`, docs/guide/imu-errors.md): the 1σ of every off-diagonal misalignment term
/// of each triad in body axes and of the gyro g-sensitivity per axis. nav-core derives the
/// prior of its twelve states in its gyro-defined gauge from them. All 0 (the default) =
/// off; when on, every 1σ is > 0.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FilterImuErrors {
    /// Gyro triad misalignment and non-orthogonality, 1σ per off-diagonal term (rad).
    #[serde(default)]
    pub gyro_misalignment_sigma_rad: f64,
    /// Accelerometer triad misalignment and non-orthogonality, 1σ per off-diagonal term (rad).
    #[serde(default)]
    pub accel_misalignment_sigma_rad: f64,
    /// Gyro g-sensitivity, 1σ per axis (rad/s per m/s²).
    #[serde(default)]
    pub gyro_g_sensitivity_sigma_rad_s_per_mps2: f64,
}

impl FilterImuErrors {
    /// Whether any 1σ is set (the table renders in `Debug` only then).
    pub fn is_on(&self) -> bool {
        self.values().iter().any(|(_, value)| *value != 0.0)
    }

    /// `(key, value)` of each 1σ, the key under `filter.imu_errors`.
    pub fn values(&self) -> [(&'static str, f64); 3] {
        [
            (
                "gyro_misalignment_sigma_rad",
                self.gyro_misalignment_sigma_rad,
            ),
            (
                "accel_misalignment_sigma_rad",
                self.accel_misalignment_sigma_rad,
            ),
            (
                "gyro_g_sensitivity_sigma_rad_s_per_mps2",
                self.gyro_g_sensitivity_sigma_rad_s_per_mps2,
            ),
        ]
    }
}

/// The bias instability the filter accounts for in its process noise: a first-order
/// Gauss–Markov bias per axis of stationary 1σ `σ` and correlation time `τ`, whose driving
/// noise density `√(2σ²/τ)` is added to the bias random walk (`setup::fsw`, docs/guide/model.md,
/// "Bias instability in the filter"). Every key defaults to 0 (off).
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FilterBiasInstability {
    /// Gyro bias instability, stationary 1σ per axis (rad/s); 0 = off.
    #[serde(default)]
    pub gyro_sigma_rad_per_s: f64,
    /// Its correlation time τ (s), > 0 when the 1σ is on.
    #[serde(default)]
    pub gyro_correlation_time_s: f64,
    /// Accelerometer bias instability, stationary 1σ per axis (m/s²); 0 = off.
    #[serde(default)]
    pub accel_sigma_mps2: f64,
    /// Its correlation time τ (s), > 0 when the 1σ is on.
    #[serde(default)]
    pub accel_correlation_time_s: f64,
}

impl FilterBiasInstability {
    /// Whether any term is set (the table renders in `Debug` only then).
    pub fn is_on(&self) -> bool {
        [
            self.gyro_sigma_rad_per_s,
            self.gyro_correlation_time_s,
            self.accel_sigma_mps2,
            self.accel_correlation_time_s,
        ]
        .iter()
        .any(|value| *value != 0.0)
    }
}

/// Initial 1σ of each error-state block (paper eq. 15 order). All must be > 0.
#[derive(Debug, Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct InitialSigma {
    /// Attitude error as a small rotation angle (rad); the vector-part state's σ is half.
    pub attitude_rad: f64,
    /// Position (m).
    pub position_m: f64,
    /// Velocity (m/s).
    pub velocity_mps: f64,
    /// Gyro bias (rad/s).
    pub gyro_bias_rad_per_s: f64,
    /// Accelerometer bias (m/s²).
    pub accel_bias_mps2: f64,
    /// Star-sensor installation error as a small rotation angle (rad); the state's σ is half.
    pub star_installation_rad: f64,
    /// Gyro scale factor (dimensionless).
    pub gyro_scale_factor: f64,
    /// Accelerometer scale factor (dimensionless).
    pub accel_scale_factor: f64,
}

/// Normalised-innovation-squared gates.
#[derive(Debug, Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NisGate {
    /// Star-sensor update rejected when its NIS exceeds this (3 dof), > 0.
    pub star_threshold: f64,
    /// GNSS update rejected when its NIS exceeds this (3 dof), > 0.
    pub gnss_threshold: f64,
}

/// Largest IMU rate the flight software's measurement history supports (Hz): the history's
/// [`nav_fsw::config::history_span_frames`] frames must span the latency window
/// `timing.max_latency_s` of `fsw` (630 Hz with the defaults, 63 frames and 0.1 s).
pub fn max_imu_rate_hz(fsw: &FswConfig) -> f64 {
    f64::from(nav_fsw::config::history_span_frames()) / fsw.timing.max_latency_s
}

impl Scenario {
    /// The built-in default scenario (the paper's Section 3), parsed from
    /// [`DEFAULT_SCENARIO_TOML`].
    ///
    /// # Errors
    /// Only if the embedded file is broken, which the crate's tests rule out.
    pub fn default_scenario() -> Result<Self, ScenarioError> {
        Self::parse(DEFAULT_SCENARIO_TOML, overlay::DEFAULT_ORIGIN)
    }

    /// Parses and validates a scenario from TOML text.
    ///
    /// # Errors
    /// [`ScenarioError::Parse`] for bad TOML, unknown or missing keys and wrong types (the
    /// message names the key); [`ScenarioError::Invalid`] for out-of-range values.
    pub fn from_toml_str(text: &str) -> Result<Self, ScenarioError> {
        Self::parse(text, "<string>")
    }

    /// Reads, resolves ([`overlay`]: `extends`, `remove`), parses and validates a scenario
    /// file.
    ///
    /// # Errors
    /// [`ScenarioError::Io`] if a file cannot be read, [`ScenarioError::Overlay`] if its
    /// chain cannot be resolved; otherwise as [`Scenario::from_toml_str`], with the file's
    /// path in the message.
    pub fn load(path: &Path) -> Result<Self, ScenarioError> {
        Self::load_resolved(path).map(|(scenario, _)| scenario)
    }

    fn parse(text: &str, origin: &str) -> Result<Self, ScenarioError> {
        let scenario: Scenario = toml::from_str(text).map_err(|error| {
            // Text with `extends` has no file to find its base from: say so, not "unknown key".
            match overlay::resolve_str(text, origin) {
                Err(overlay_error @ ScenarioError::Overlay { .. }) => overlay_error,
                _ => ScenarioError::Parse {
                    origin: origin.to_string(),
                    message: error.to_string(),
                },
            }
        })?;
        scenario.validate_from(origin)?;
        Ok(scenario)
    }

    /// Total scenario length: the sum of the manoeuvre segments (s).
    pub fn duration_s(&self) -> f64 {
        self.manoeuvres
            .iter()
            .map(|segment| segment.duration_s)
            .sum()
    }

    /// Number of IMU frames in the scenario (the duration in whole frames).
    pub fn frame_count(&self) -> u64 {
        frames_in(self.duration_s(), self.imu.frame_period_s())
    }
}

/// `duration_s / period_s` rounded to the nearest whole number of frames (durations are
/// validated to be whole numbers of frames, so the rounding only removes float noise).
pub fn frames_in(duration_s: f64, period_s: f64) -> u64 {
    let frames = (duration_s / period_s).round();
    if frames.is_finite() && frames > 0.0 {
        // The value is a finite, non-negative whole number; the cast is exact below 2^53.
        frames as u64
    } else {
        0
    }
}
