//! The flight's gravity model and the allowance for the field it omits, as the gravity
//! analysis of the mission gives them (docs/guide/gravity.md).

use crate::config::{FswConfig, GravityConfig, Param};

/// The gravity model the flight carries beyond point mass + `J2` (EGM2008 to `degree` and
/// `order`; 2 and 0: `J2` alone) and the allowance derived for it on the ground: `nav-sim
/// gravity-omission --flight-degree N` on the mission's trajectory over the ground tracks it
/// may fly prints the flight software's own omitted RMS at the lowest altitude and the
/// omitted field's spectral density at zero frequency (docs/guide/gravity.md, "The allowance with
/// the altitude: the shipped allowance"). `omitted_field_sigma_mps2` is that RMS over `√3` (per axis), rounded up;
/// `omitted_field_psd_m2_per_s3` the density scaled by `(σ / RMS-per-axis)²`, rounded up.
/// Without an allowance (both 0) the flight reports a configuration warning at start-up
/// (`health::ConfigurationWarnings`) and never checks the omitted field against it.
///
/// The density is the mean over ground tracks of `tr S(0) / 3`, `S(0)` the omitted field's
/// 3 × 3 spectral matrix at zero frequency (the printed `q at f = 0, scaled`). Derivation: a
/// constant calibration state's estimate takes from the omitted field `d` its weighted mean
/// over the flight, of covariance `S(0)/T` for a flight of length `T`, while the allowance,
/// white velocity noise `q I`, gives the filter `q I / T`. Along one track `S(0)` is nearly
/// of rank one (the field's mean over the flight is one vector), in a direction that changes
/// with the track; an isotropic `q` matches its expected total power when
/// `3 q = E tr S(0)`, which keeps the expected NEES of the states it feeds at their
/// dimension. The largest eigenvalue of `S(0)` on every axis (the supremum) gives up to
/// three times that power: an honest filter would read as conservative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GravityDatasheet {
    /// Largest degree of the flight's model, 2..=12.
    pub degree: u8,
    /// Largest order, 0..=degree.
    pub order: u8,
    /// Work items of the evaluation per frame (nav-core `gravity::harmonics`).
    pub terms_per_frame: u8,
    /// 1σ per axis of the field the model omits at the lowest altitude (m/s²); 0 = none.
    pub omitted_field_sigma_mps2: f64,
    /// Spectral density of the white velocity noise that covers it (m²/s³); 0 = none.
    pub omitted_field_psd_m2_per_s3: f64,
}

impl GravityDatasheet {
    /// Point mass + `J2` without an allowance: the paper's model.
    pub const J2_ONLY: Self = Self {
        degree: 2,
        order: 0,
        terms_per_frame: nav_core::gravity::harmonics::DEFAULT_TERMS_PER_FRAME,
        omitted_field_sigma_mps2: 0.0,
        omitted_field_psd_m2_per_s3: 0.0,
    };

    /// The allowance's density for a 1σ `sigma_mps2` per axis, from the density
    /// `psd_at_check_m2_per_s3` that `nav-sim gravity-omission` prints for the omitted field
    /// scaled to the flight software's check figure `check_sigma_mps2` (per axis): the
    /// density of a field scales with its power, `q · (σ / σ_check)²`. The data sheet's
    /// `omitted_field_psd_m2_per_s3` is this, rounded up.
    pub fn omitted_field_psd_for_sigma(
        psd_at_check_m2_per_s3: f64,
        check_sigma_mps2: f64,
        sigma_mps2: f64,
    ) -> f64 {
        let ratio = sigma_mps2 / check_sigma_mps2;
        psd_at_check_m2_per_s3 * ratio * ratio
    }

    /// The flight's gravity settings, as given.
    pub(super) fn apply(&self, config: &mut FswConfig) {
        config.gravity = GravityConfig {
            field: nav_core::gravity::harmonics::FieldModel {
                degree: self.degree,
                order: self.order,
                terms_per_frame: self.terms_per_frame,
            },
            omitted_field_sigma_mps2: self.omitted_field_sigma_mps2,
            omitted_field_psd_m2_per_s3: self.omitted_field_psd_m2_per_s3,
        };
    }
}

/// The gravity data-sheet field behind a flight parameter.
pub(super) fn field_of(param: Param) -> Option<&'static str> {
    use Param as P;
    Some(match param {
        P::GravityDegree => "gravity.degree",
        P::GravityOrder => "gravity.order",
        P::GravityTermsPerFrame => "gravity.terms_per_frame",
        P::OmittedFieldSigma => "gravity.omitted_field_sigma_mps2",
        P::OmittedFieldPsd => "gravity.omitted_field_psd_m2_per_s3",
        _ => return None,
    })
}
