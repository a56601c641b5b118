//! The star tracker's data sheet (noise per sensor axis, low-frequency error, aberration,
//! heads and their mountings) and its conversions to the flight software's star settings.

use nalgebra::Vector3;

use super::imu::bias_prior_with_instability;
use super::PER_THOUSAND;
use crate::config::{FswConfig, Param, StarHeadConfig};

/// Pairs of the two heads accepted before the flight software may hand its installation
/// block to the second head, and agreeing pairs in a row before a head declared faulty takes
/// it back: 100 pairs (10 s at 10 Hz) know the heads' alignment to a tenth of the noise about
/// the axes they share (nav-core `star_heads`: `σ/√n` per axis with `n` pairs).
pub const PAIRS_BEFORE_HAND_OVER: u32 = 100;

/// Arc-seconds per degree.
const ARCSEC_PER_DEG: f64 = 3600.0;

/// A quarter: the lag, as a fraction of its period, at which a periodic error is no longer
/// correlated with itself ([`LowFrequencyError`]).
const CORRELATION_TIME_PER_PERIOD: f64 = 0.25;

/// Arc-seconds to radians: `(x / 3600)` degrees in radians. nav-sim's scenario keys use it,
/// so a scenario and a data sheet that state one value give the same bits.
pub fn arcsec_to_rad(arcsec: f64) -> f64 {
    (arcsec / ARCSEC_PER_DEG).to_radians()
}

/// A head's nominal body-to-sensor mounting `q_bs = exp(φ)` `[w, x, y, z]` from the rotation
/// vector `φ` in degrees the drawings give (each component in radians, then nav-core's exact
/// exponential).
pub fn mounting_wxyz_from_rotation_vector_deg(rotation_vector_deg: [f64; 3]) -> [f64; 4] {
    let [x, y, z] = rotation_vector_deg;
    let mounting = nav_core::attitude::exp_rotation_vector(&Vector3::new(
        x.to_radians(),
        y.to_radians(),
        z.to_radians(),
    ));
    [mounting.w, mounting.i, mounting.j, mounting.k]
}

/// The prior 1σ per axis of two heads' relative alignment, each installed with the filter's
/// installation 1σ `installation_sigma_rad` independently: the difference of two independent
/// errors of 1σ `σ` has `√2 σ`.
pub fn second_head_alignment_prior_rad(installation_sigma_rad: f64) -> f64 {
    core::f64::consts::SQRT_2 * installation_sigma_rad
}

/// A tracker's low-frequency error (thermo-elastic, focal-plane), which the flight carries
/// as a first-order Gauss–Markov rotation per sensor axis: its 1σ as given, its correlation
/// time a quarter of the period (`τ = P/4`): at the lag `P/4` a periodic error of period `P`
/// is uncorrelated with itself (`cos(2π t/P) = 0`), and a Gauss–Markov error's correlation
/// has fallen to `1/e` at `τ`. An orbit-periodic thermal error of a 500 km orbit
/// (`P` = 5680 s) is `τ` = 1420 s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LowFrequencyError {
    /// 1σ per sensor axis `[x, y, z]` (arcsec).
    pub sigma_arcsec: [f64; 3],
    /// Its period (s), > 0: the orbit's, for a thermal error.
    pub period_s: f64,
}

impl LowFrequencyError {
    /// The Gauss–Markov correlation time (s): `P/4`.
    pub fn correlation_time_s(&self) -> f64 {
        self.period_s * CORRELATION_TIME_PER_PERIOD
    }
}

/// The star tracker's data sheet: every head shares its noise and errors; each head has a
/// mounting from the drawings. Noise figures are 1σ per axis (a data sheet's 3σ divided by 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StarTrackerDatasheet {
    /// White noise across the boresight, 1σ about sensor `x` and `y` (arcsec).
    pub cross_boresight_noise_arcsec: f64,
    /// White noise about the boresight (roll), 1σ about sensor `z` (arcsec).
    pub roll_noise_arcsec: f64,
    /// The low-frequency error; `None` = a constant installation error (none).
    pub low_frequency_error: Option<LowFrequencyError>,
    /// Whether the tracker removes the velocity aberration from its attitude itself; `false`
    /// turns on the flight software's correction (never both: it would be removed twice).
    pub aberration_corrected: bool,
    /// Each head's installation error about its nominal mounting, 1σ per axis (mrad): the
    /// alignment's accuracy.
    pub mounting_accuracy_mrad: f64,
    /// Head 0's nominal mounting `q_bs = exp(φ)` as the rotation vector `φ` (deg).
    pub mounting_rotation_vector_deg: [f64; 3],
    /// Head 1's nominal mounting, as head 0's; `None` = one head.
    pub second_head_mounting_rotation_vector_deg: Option<[f64; 3]>,
}

impl StarTrackerDatasheet {
    /// The star settings: mounting, noise per axis in radians ([`arcsec_to_rad`]), the
    /// low-frequency error's 1σ and `τ`, the installation prior (the mounting accuracy with
    /// `2σ²` of the largest low-frequency 1σ, as a bias's instability,
    /// [`bias_prior_with_instability`]), the flight software's aberration correction when the
    /// tracker does not make it, and the second head with the pair gate of the first.
    pub(super) fn apply(&self, config: &mut FswConfig) {
        let cross_rad = arcsec_to_rad(self.cross_boresight_noise_arcsec);
        let roll_rad = arcsec_to_rad(self.roll_noise_arcsec);
        let (slow_sigma_rad, tau_s) = self.low_frequency_error.map_or(([0.0; 3], 0.0), |lfe| {
            (
                lfe.sigma_arcsec.map(arcsec_to_rad),
                lfe.correlation_time_s(),
            )
        });
        let largest_slow_rad = slow_sigma_rad.into_iter().fold(0.0, f64::max);
        let installation_rad = bias_prior_with_instability(
            self.mounting_accuracy_mrad / PER_THOUSAND,
            largest_slow_rad,
            tau_s,
        );
        config.filter.initial.star_installation_rad = installation_rad;
        let star = &mut config.star;
        star.mounting_wxyz =
            mounting_wxyz_from_rotation_vector_deg(self.mounting_rotation_vector_deg);
        star.noise_rad = cross_rad;
        star.roll_noise_rad = roll_rad;
        star.slow_error_sigma_rad = slow_sigma_rad;
        star.slow_error_correlation_time_s = tau_s;
        star.aberration_correction = !self.aberration_corrected;
        let pair_gate_nis = star.gate_nis;
        star.second_head =
            self.second_head_mounting_rotation_vector_deg
                .map(|rotation_vector_deg| StarHeadConfig {
                    mounting_wxyz: mounting_wxyz_from_rotation_vector_deg(rotation_vector_deg),
                    noise_rad: cross_rad,
                    roll_noise_rad: roll_rad,
                    alignment_prior_sigma_rad: second_head_alignment_prior_rad(installation_rad),
                    pair_gate_nis,
                    pairs_before_hand_over: PAIRS_BEFORE_HAND_OVER,
                });
    }
}

/// The star-tracker data-sheet field behind a flight parameter.
pub(super) fn field_of(param: Param) -> Option<&'static str> {
    use Param as P;
    Some(match param {
        P::StarMountingW | P::StarMountingX | P::StarMountingY | P::StarMountingZ => {
            "star_tracker.mounting_rotation_vector_deg"
        }
        P::StarNoise | P::HeadNoise => "star_tracker.cross_boresight_noise_arcsec",
        P::StarRollNoise | P::HeadRollNoise => "star_tracker.roll_noise_arcsec",
        P::StarSlowErrorX | P::StarSlowErrorY | P::StarSlowErrorZ => {
            "star_tracker.low_frequency_error.sigma_arcsec"
        }
        P::StarSlowErrorCorrelationTime => "star_tracker.low_frequency_error.period_s",
        P::InitialStarInstallation | P::HeadAlignmentPrior => {
            "star_tracker.mounting_accuracy_mrad / low_frequency_error"
        }
        P::StarAberrationCorrection => "star_tracker.aberration_corrected",
        P::StarSecondHead
        | P::HeadPairsBeforeHandOver
        | P::HeadPairGate
        | P::HeadMountingW
        | P::HeadMountingX
        | P::HeadMountingY
        | P::HeadMountingZ => "star_tracker.second_head_mounting_rotation_vector_deg",
        _ => return None,
    })
}
