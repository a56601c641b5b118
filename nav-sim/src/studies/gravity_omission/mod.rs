//! The gravity the flight software leaves out, as the process noise that covers it
//! (`nav-sim gravity-omission`, `docs/guide/gravity.md`, "The omitted field as process noise").
//!
//! The truth flies a published field (EGM2008 to the scenario's `[gravity]` degree and order);
//! a flight model keeps its terms only to a lower degree `N` and order `M`, refreshed every
//! `refresh_s` and held in between. This study flies the scenario's truth once, samples the
//! difference `d(t)` of the two fields along it and derives the white velocity process-noise
//! density `q` (m²/s³ per axis) whose covariance dominates that of `d`.
//!
//! ## The difference
//! `d(t) = δg_truth(t, p(t)) − δg_flight(t)` (m/s², launch-inertial axes), with `δg` the
//! remainder beyond point mass + `J2` ([`RotatingRemainder`]): `δg_truth` to the truth's degree
//! and order, evaluated in full at the truth position `p(t)`; `δg_flight` to `N`, `M` as the
//! flight holds it: the value computed at a refresh time `t_r` at `p(t_r)`, where `t_r` is the
//! last refresh `t_0 + refresh·⌊(t − t_0)/refresh⌋` less [`FlightGravityModel::latency_refreshes`]
//! refresh periods (the evaluation's latency; refreshes before the scenario start `t_0` are
//! taken at `t_0`, where the flight computes its first value). `N = 2`, `M = 0` is the flight's
//! `J2` alone: `δg_flight = 0`.
//!
//! ## Why white noise of PSD `q` covers it, and which `q`
//! For a linear filter with fixed gains the estimation error is a linear functional of the
//! process noise, so its covariance is monotone in the noise's covariance operator: a noise
//! whose covariance operator dominates another's gives the larger error covariance in every
//! direction. White noise of PSD `q` has the covariance operator `q·I·δ(τ)`; a stationary
//! process with cross-spectral density matrix `S(f)` is dominated by it iff
//! `q·I ⪰ S(f)` for every `f` (both operators are diagonal in frequency). Hence
//!
//! `q = sup_f λ_max(S(f))`,
//!
//! estimated from the sampled `d_k = d(t_0 + kΔ)`, `k = 0..K−1`, in two ways:
//!
//! 1. **Gershgorin bound.** The raw cross second moments (mean *not* removed: the filter sees
//!    the mean of `d` too) `R_ij(m) = (1/K) Σ_k d_i(k) d_j(k+m)`, lag `τ = mΔ`, give
//!    `S_ij(f) = Σ_m R_ij(m) e^{−i2πfmΔ} Δ`, so `|S_ij(f)| ≤ Σ_m |R_ij(m)| Δ` and, by
//!    Gershgorin's circle theorem, `λ_max(S(f)) ≤ max_i Σ_j |S_ij(f)|`:
//!    `q_bound = max_i Σ_j Σ_{|m|Δ ≤ L} |R_ij(m)| Δ`, the lags truncated at `L` (`max_lag_s`).
//!    It bounds every lag-window (Blackman–Tukey) spectrum estimate with window `|w| ≤ 1` and
//!    support `L`, and grows with `L` while `d` stays correlated (a mean `μ` alone adds
//!    `≈ 2Lμ²`): a slowly varying `d` is covered by white noise only over a horizon.
//! 2. **Averaged periodogram** (Welch): Hann-windowed segments of `2L` (at most the record),
//!    overlapping by half, `S(f) = Δ/(Σ_k w_k²) · mean over segments of X(f) X(f)ᴴ`,
//!    `X(f) = Σ_k w_k d_k e^{−i2πfkΔ}`; `q_periodogram = max_f λ_max(S(f))`. It estimates the
//!    same supremum more tightly; it is not a bound and should lie below `q_bound`.
//! 3. **At zero frequency** (`q at f = 0`): `tr S(0) / 3`, the allowance the calibration
//!    states need. A constant state's estimate takes from `d` its weighted mean over the
//!    flight, of covariance `S(0)/T` for a long flight `T`; white noise `q I` gives it
//!    `q I / T`. `S(0)` is nearly of rank one along one ground track (the mean of `d` over
//!    the flight is one vector), in another direction on each track; the isotropic `q I` with
//!    the same expected total power, `E tr(q I) = E tr S(0)`, leaves the expected NEES of the
//!    states it feeds at their dimension, while `λ_max(S(0))` on every axis over-covers the
//!    two others on each track (the supremum: up to three times the power in all).
//!
//! Both are two-sided densities (white noise of PSD `q` has `E[w(t) w(t+τ)ᵀ] = q I δ(τ)`), as
//! the filter's continuous process noise `Q = q I` is; `√q` is the velocity random walk
//! (m/s/√s).
//!
//! Also reported: the RMS of `d` per axis and of `|d|`, the largest `|d|`, the mean, and the
//! correlation time of `|d|`: the first lag where its autocorrelation (mean removed, so that
//! a positive signal can decorrelate) falls below `1/e`.

mod spectrum;
mod trajectory;

use nalgebra::Vector3;

use crate::scenario::gravity::GravityModelName;
use crate::scenario::Scenario;
use crate::setup::launch::Launch;
use crate::setup::SetupError;
use crate::world::gravity::gfc::GfcError;
use crate::world::gravity::{RotatingRemainder, EGM2008_GFC};
use crate::world::truth::TruthError;

pub use spectrum::{LagBound, Statistics};

/// The flight models of the table `nav-sim gravity-omission` prints by default, as
/// `(degree, order)`: `J2` only, zonal to `J4`, and square fields 4 to 16.
pub const DEFAULT_FLIGHT_FIELDS: [(usize, usize); 7] =
    [(2, 0), (4, 0), (4, 4), (6, 6), (8, 8), (12, 12), (16, 16)];

/// Default time between two refreshes of the flight's field (s).
pub const DEFAULT_REFRESH_S: f64 = 0.1;

/// Default sampling interval of `d` (s).
pub const DEFAULT_SAMPLE_S: f64 = 0.1;

/// Default largest lag `L` of the Gershgorin bound, half the Welch segment (s).
pub const DEFAULT_MAX_LAG_S: f64 = 1000.0;

/// Default lags at which the bound is also reported, to show how it grows with `L` (s).
pub const DEFAULT_REPORT_LAGS_S: [f64; 5] = [100.0, 300.0, 1000.0, 3000.0, 10000.0];

/// A flight gravity model: the remainder beyond point mass + `J2` to `degree` and `order`,
/// refreshed every `refresh_s` and held, its value `latency_refreshes` refreshes old.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlightGravityModel {
    /// Largest degree `N`, 2 (`J2` only) up to the truth's.
    pub degree: usize,
    /// Largest order `M`, at most `degree` and the truth's order.
    pub order: usize,
    /// Time between refreshes (s): positive, a whole number of IMU frames.
    pub refresh_s: f64,
    /// How many refresh periods old the value in use is (1: computed at the refresh before
    /// the last one, the flight's evaluation latency; 0: at the last one).
    pub latency_refreshes: u32,
}

impl FlightGravityModel {
    /// The model to `degree` and `order` with the default refresh and one refresh of latency.
    pub fn new(degree: usize, order: usize) -> Self {
        Self {
            degree,
            order,
            refresh_s: DEFAULT_REFRESH_S,
            latency_refreshes: 1,
        }
    }
}

/// How `d` is sampled and analysed.
#[derive(Debug, Clone, PartialEq)]
pub struct OmissionOptions {
    /// Sampling interval `Δ` of `d` (s): positive, a whole number of IMU frames.
    pub sample_s: f64,
    /// Largest lag `L` of the bound, half the periodogram's segment (s): at least `sample_s`.
    pub max_lag_s: f64,
    /// Lags at which the bound is also reported (s), each at least `sample_s`.
    pub report_lags_s: Vec<f64>,
}

impl Default for OmissionOptions {
    fn default() -> Self {
        Self {
            sample_s: DEFAULT_SAMPLE_S,
            max_lag_s: DEFAULT_MAX_LAG_S,
            report_lags_s: DEFAULT_REPORT_LAGS_S.to_vec(),
        }
    }
}

/// Why the study could not run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OmissionError {
    /// An option or a flight model is out of range.
    #[error("{key} = {value} {requirement}")]
    Setting {
        /// The option.
        key: &'static str,
        /// Its value, as given.
        value: String,
        /// What it must satisfy.
        requirement: String,
    },
    /// The launch or the initial state could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The truth flight failed.
    #[error(transparent)]
    Truth(#[from] TruthError),
    /// The model file could not be read to the degree asked.
    #[error(transparent)]
    GravityModel(#[from] GfcError),
    /// A field evaluation failed (e.g. a position at the Earth's centre).
    #[error("gravity field at t = {time_s} s: {reason}")]
    Field {
        /// Navigation time of the evaluation (s).
        time_s: f64,
        /// The field's reason.
        reason: String,
    },
}

/// The omitted field of one flight model along the scenario's truth.
#[derive(Debug, Clone, PartialEq)]
pub struct OmissionReport {
    /// The flight model.
    pub flight: FlightGravityModel,
    /// The truth's degree and order (2, 0 without a published model).
    pub truth_field: (usize, usize),
    /// Number of samples `K`.
    pub samples: usize,
    /// Their interval `Δ` (s).
    pub sample_s: f64,
    /// The statistics of `d` (module docs).
    pub statistics: Statistics,
    /// Lowest altitude of the flight above a sphere of the model's radius (m).
    pub lowest_altitude_m: f64,
    /// What the flight software checks its allowance against there: the RMS magnitude over
    /// the sphere of the field its model omits (to degree 60, nav-core
    /// `gravity::harmonics`), divided by `√3` to a 1σ per axis (m/s²). A
    /// `filter.gravity.omitted_field_sigma_mps2` at least this raises no
    /// `gravity_allowance_short` on this flight. NaN for a model beyond the flight's 12 × 12.
    pub flight_check_sigma_mps2: f64,
    /// `tr S(0) / 3` of `d` scaled to the field at the lowest altitude, `d_k · rms(r_low) /
    /// rms(r_k)` with `rms(r)` the flight software's omitted RMS at radius `r` (m²/s³): the
    /// allowance the flight software scales down with the omitted field's power where the
    /// vehicle is higher (docs/guide/gravity.md, "The allowance with the altitude"). NaN where the
    /// check σ is.
    pub q_zero_frequency_scaled_m2_s3: f64,
}

impl OmissionReport {
    /// `√q_bound`: the velocity random walk density of the allowance (m/s/√s).
    pub fn velocity_random_walk_mps_per_sqrt_s(&self) -> f64 {
        self.statistics.q_bound_m2_s3.sqrt()
    }
}

/// The truth's field of `scenario`: its degree and order, 2 and 0 for point mass + `J2`.
pub fn truth_field(scenario: &Scenario) -> (usize, usize) {
    match &scenario.gravity {
        Some(settings) if settings.model == GravityModelName::Egm2008 => (
            settings.degree.unwrap_or(2) as usize,
            settings.order.unwrap_or(0) as usize,
        ),
        _ => (2, 0),
    }
}

/// The omitted field of `flight` along the scenario's truth (module docs).
///
/// # Errors
/// As [`omitted_fields`].
pub fn omitted_field(
    scenario: &Scenario,
    flight: FlightGravityModel,
    options: &OmissionOptions,
) -> Result<OmissionReport, OmissionError> {
    let mut reports = omitted_fields(scenario, &[flight], options)?;
    reports.pop().ok_or_else(|| OmissionError::Setting {
        key: "flight models",
        value: "none".to_string(),
        requirement: "must name at least one model".to_string(),
    })
}

/// The omitted field of each of `flights` along the scenario's truth, flown once.
///
/// # Errors
/// [`OmissionError::Setting`] for an option out of range or a flight model above the truth's
/// field (checked before the flight); the others if the truth or a field evaluation fails.
pub fn omitted_fields(
    scenario: &Scenario,
    flights: &[FlightGravityModel],
    options: &OmissionOptions,
) -> Result<Vec<OmissionReport>, OmissionError> {
    let frame_period_s = scenario.imu.frame_period_s();
    let sample_frames = whole_frames("sample_s", options.sample_s, frame_period_s)?;
    check_lags(options)?;
    let truth = truth_field(scenario);
    let mut refresh_frames = Vec::with_capacity(flights.len());
    for flight in flights {
        check_flight(flight, truth)?;
        refresh_frames.push(whole_frames(
            "flight refresh_s",
            flight.refresh_s,
            frame_period_s,
        )?);
    }
    let launch = Launch::new(scenario)?;
    let truth_remainder =
        RotatingRemainder::from_settings(scenario.gravity.as_ref(), launch.frame)?;
    let stride = refresh_frames
        .iter()
        .fold(sample_frames, |stride, frames| gcd(stride, *frames));
    let path = trajectory::fly(scenario, &launch, stride)?;
    let truth_values = trajectory::truth_remainder(&path, sample_frames, truth_remainder.as_ref())?;
    check_samples(truth_values.len(), scenario, options)?;
    let radii_m = path.sample_radii_m(sample_frames, &launch);
    let lowest_radius_m = path.lowest_radius_m(&launch);
    let mut reports = Vec::with_capacity(flights.len());
    for (flight, refresh) in flights.iter().zip(refresh_frames) {
        let flight_remainder = flight_remainder(flight, launch.frame)?;
        let held = trajectory::HeldField {
            remainder: flight_remainder.as_ref(),
            refresh_frames: refresh,
            latency_refreshes: u64::from(flight.latency_refreshes),
        };
        let flight_values = trajectory::flight_remainder(&path, sample_frames, &held)?;
        let difference: Vec<Vector3<f64>> = truth_values
            .iter()
            .zip(&flight_values)
            .map(|(truth, flight)| truth - flight)
            .collect();
        let flight_check_sigma_mps2 = flight_check_sigma(flight, &launch, lowest_radius_m)?;
        let q_zero_frequency_scaled_m2_s3 = zero_frequency_scaled(
            flight,
            &launch,
            flight_check_sigma_mps2,
            &difference,
            &radii_m,
            options,
        )?;
        reports.push(OmissionReport {
            flight: *flight,
            truth_field: truth,
            samples: difference.len(),
            sample_s: options.sample_s,
            statistics: spectrum::statistics(&difference, options),
            lowest_altitude_m: lowest_radius_m - nav_core::gravity::egm2008::RADIUS_M,
            flight_check_sigma_mps2,
            q_zero_frequency_scaled_m2_s3,
        });
    }
    Ok(reports)
}

/// A record of at least two samples, or a setting error naming `sample_s`.
fn check_samples(
    samples: usize,
    scenario: &Scenario,
    options: &OmissionOptions,
) -> Result<(), OmissionError> {
    if samples >= 2 {
        return Ok(());
    }
    Err(OmissionError::Setting {
        key: "sample_s",
        value: options.sample_s.to_string(),
        requirement: format!(
            "must leave at least two samples in the flight ({} s)",
            scenario.duration_s()
        ),
    })
}

/// `tr S(0) / 3` of the difference scaled to the field at the lowest altitude
/// ([`scaled_to_lowest`], `lowest_sigma_mps2` the flight's check σ there), or NaN where that
/// σ is (a model beyond the flight software's 12 × 12).
fn zero_frequency_scaled(
    flight: &FlightGravityModel,
    launch: &Launch,
    lowest_sigma_mps2: f64,
    difference: &[Vector3<f64>],
    radii_m: &[f64],
    options: &OmissionOptions,
) -> Result<f64, OmissionError> {
    if lowest_sigma_mps2.is_nan() {
        return Ok(f64::NAN);
    }
    let scaled = scaled_to_lowest(flight, launch, difference, radii_m, lowest_sigma_mps2)?;
    Ok(spectrum::statistics(&scaled, options).q_zero_frequency_m2_s3)
}

/// Radii are grouped in bins of this width (m) for the omitted RMS, which changes by less
/// than 0.1 % over one bin in low orbit (each degree as `(a/r)^(n+2)`, so by at most
/// `(n + 2) Δr / r` = 62 · 100 / 6.6e6 for `n` ≤ 60).
const RADIUS_BIN_M: f64 = 100.0;

/// The flight software's omitted RMS per axis by radius ([`flight_check_sigma`]), evaluated
/// once per [`RADIUS_BIN_M`] bin and kept.
pub(crate) struct CheckSigmaByRadius {
    flight: FlightGravityModel,
    sigma_by_bin: std::collections::HashMap<i64, f64>,
}

impl CheckSigmaByRadius {
    /// For the flight model `flight`, nothing evaluated yet.
    pub(crate) fn new(flight: FlightGravityModel) -> Self {
        Self {
            flight,
            sigma_by_bin: std::collections::HashMap::new(),
        }
    }

    /// The omitted RMS per axis (m/s²) at the centre of `radius_m`'s bin.
    ///
    /// # Errors
    /// [`OmissionError::Setting`] if the flight model's evaluation fails.
    pub(crate) fn at(&mut self, launch: &Launch, radius_m: f64) -> Result<f64, OmissionError> {
        // Radii of a flight are far below 2^63 bins; the cast saturates otherwise.
        let bin = (radius_m / RADIUS_BIN_M).round() as i64;
        if let Some(&sigma) = self.sigma_by_bin.get(&bin) {
            return Ok(sigma);
        }
        let sigma = flight_check_sigma(&self.flight, launch, bin as f64 * RADIUS_BIN_M)?;
        self.sigma_by_bin.insert(bin, sigma);
        Ok(sigma)
    }
}

/// `d_k · σ_low / σ(r_k)`: the difference scaled to the field at the lowest altitude, `σ(r)`
/// the flight software's omitted RMS per axis at `r` ([`CheckSigmaByRadius`]).
fn scaled_to_lowest(
    flight: &FlightGravityModel,
    launch: &Launch,
    difference: &[Vector3<f64>],
    radii_m: &[f64],
    lowest_sigma_mps2: f64,
) -> Result<Vec<Vector3<f64>>, OmissionError> {
    let mut check = CheckSigmaByRadius::new(*flight);
    difference
        .iter()
        .zip(radii_m)
        .map(|(d, &radius_m)| Ok(d * (lowest_sigma_mps2 / check.at(launch, radius_m)?)))
        .collect()
}

/// The flight software's own omitted RMS at `radius_m` (one whole evaluation of nav-core's
/// `FieldRemainder` at a point of that radius: the figure depends on the radius only), per
/// axis.
fn flight_check_sigma(
    flight: &FlightGravityModel,
    launch: &Launch,
    radius_m: f64,
) -> Result<f64, OmissionError> {
    use nav_core::gravity::harmonics::{FieldModel, FieldRemainder};
    let setting = |reason: String| OmissionError::Setting {
        key: "flight model",
        value: format!("{} x {}", flight.degree, flight.order),
        requirement: reason,
    };
    let (Ok(degree), Ok(order)) = (u8::try_from(flight.degree), u8::try_from(flight.order)) else {
        return Ok(f64::NAN);
    };
    let model = FieldModel {
        degree,
        order,
        terms_per_frame: u8::MAX,
    };
    let mut field = Box::new(FieldRemainder::EMPTY);
    if field.configure(model).is_err() {
        // Beyond the flight's coefficients: no flight software flies it.
        return Ok(f64::NAN);
    }
    let position = launch.frame.earth_centre_launch_m() + Vector3::new(0.0, radius_m, 0.0);
    // An evaluation may need more than one frame's share even at u8::MAX items a frame.
    for _ in 0..=model.frames_per_evaluation() {
        if field.evaluations() > 0 {
            break;
        }
        field
            .advance(&launch.frame, 0.0, &position)
            .map_err(|error| setting(error.to_string()))?;
    }
    Ok(field.omitted_rms_mps2() / 3.0_f64.sqrt())
}

/// The flight's remainder, `None` for `J2` alone (degree 2, order 0: nothing beyond `J2`).
fn flight_remainder(
    flight: &FlightGravityModel,
    frame: nav_core::frames::LaunchFrame,
) -> Result<Option<RotatingRemainder>, OmissionError> {
    if flight.degree == 2 && flight.order == 0 {
        return Ok(None);
    }
    Ok(Some(RotatingRemainder::new(
        EGM2008_GFC,
        flight.degree,
        flight.order,
        frame,
    )?))
}

/// A flight model within the truth's field: `2 ≤ degree ≤` the truth's degree,
/// `order ≤ degree` and `order ≤` the truth's order (terms the truth lacks would be an error
/// of the flight's own making, not an omission).
fn check_flight(
    flight: &FlightGravityModel,
    (truth_degree, truth_order): (usize, usize),
) -> Result<(), OmissionError> {
    let setting = |key, value: usize, requirement: String| OmissionError::Setting {
        key,
        value: value.to_string(),
        requirement,
    };
    if !(2..=truth_degree).contains(&flight.degree) {
        return Err(setting(
            "flight degree",
            flight.degree,
            format!(
                "must be in 2..={truth_degree}, the truth's degree (a flight field above the \
                 truth's has no omitted part to measure; raise the scenario's [gravity] degree)"
            ),
        ));
    }
    if flight.order > flight.degree {
        return Err(setting(
            "flight order",
            flight.order,
            format!("must be in 0..=flight degree ({})", flight.degree),
        ));
    }
    if flight.order > truth_order {
        return Err(setting(
            "flight order",
            flight.order,
            format!("must be at most the truth's order ({truth_order})"),
        ));
    }
    Ok(())
}

/// `value_s` as a whole number of IMU frames of `frame_period_s`, at least one (to a
/// millionth of a frame, so a decimal interval's rounding is accepted).
fn whole_frames(
    key: &'static str,
    value_s: f64,
    frame_period_s: f64,
) -> Result<u64, OmissionError> {
    let frames = (value_s / frame_period_s).round();
    let whole = value_s.is_finite()
        && frames >= 1.0
        && (frames * frame_period_s - value_s).abs() <= 1.0e-6 * frame_period_s;
    if whole {
        // A finite count of at least one frame; the cast saturates far beyond any flight.
        Ok(frames as u64)
    } else {
        Err(OmissionError::Setting {
            key,
            value: value_s.to_string(),
            requirement: format!(
                "must be positive and a whole number of IMU frames ({frame_period_s} s)"
            ),
        })
    }
}

/// `max_lag_s` and every reported lag finite and at least `sample_s`.
fn check_lags(options: &OmissionOptions) -> Result<(), OmissionError> {
    let lags = std::iter::once(("max_lag_s", options.max_lag_s)).chain(
        options
            .report_lags_s
            .iter()
            .map(|lag_s| ("report lag", *lag_s)),
    );
    for (key, lag_s) in lags {
        if !(lag_s.is_finite() && lag_s >= options.sample_s) {
            return Err(OmissionError::Setting {
                key,
                value: lag_s.to_string(),
                requirement: format!(
                    "must be finite and at least sample_s ({} s)",
                    options.sample_s
                ),
            });
        }
    }
    Ok(())
}

/// Greatest common divisor (Euclid).
fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

#[cfg(test)]
mod tests;
