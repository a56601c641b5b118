//! The flight's gravity beyond point mass + `J2`: EGM2008 ([`super::egm2008`]) to a configured
//! degree `N ≤ 12` and order `M ≤ N`, evaluated a few terms per frame so that no frame pays
//! for a whole evaluation, and held between evaluations; with the RMS of what the model
//! leaves out, for the consistency check of the gravity allowance.
//!
//! **Recursion.** Cunningham's solid harmonics for fully normalised coefficients
//! (Montenbruck & Gill, *Satellite Orbits*, 2000, eqs. 3.29–3.33, times the ratios of the
//! normalisation `N_nm = √((2 − δ_m0)(2n + 1)(n − m)!/(n + m)!)`; Holmes & Featherstone,
//! *J. Geodesy* 76, 2002, eqs. 11–12 for `α`, `β`). With `ρ = a / r²`, `(x, y, z)` the
//! Earth-fixed position and `V̄_00 = a / r`, `W̄_00 = 0`:
//!
//! ```text
//! V̄_mm = f_m (xρ V̄_m−1,m−1 − yρ W̄_m−1,m−1),   W̄_mm = f_m (xρ W̄_m−1,m−1 + yρ V̄_m−1,m−1)
//! V̄_nm = α_nm zρ V̄_n−1,m − β_nm aρ V̄_n−2,m    (W̄ alike)
//! f_1 = √3, f_m = √((2m + 1)/(2m));  α_nm = √((2n + 1)(2n − 1)/((n − m)(n + m)))
//! β_nm = √((2n + 1)(n + m − 1)(n − m − 1)/((2n − 3)(n + m)(n − m)))
//! ```
//!
//! and the acceleration (M&G eq. 3.33), per coefficient, in units of `GM / a²`:
//!
//! ```text
//! m = 0: ẍ = −C̄ k₀ V̄_n+1,1,  ÿ = −C̄ k₀ W̄_n+1,1
//! m > 0: ẍ = ½ [k₁ (−C̄ V̄_n+1,m+1 − S̄ W̄_n+1,m+1) + k₂ (C̄ V̄_n+1,m−1 + S̄ W̄_n+1,m−1)]
//!        ÿ = ½ [k₁ (−C̄ W̄_n+1,m+1 + S̄ V̄_n+1,m+1) + k₂ (−C̄ W̄_n+1,m−1 + S̄ V̄_n+1,m−1)]
//! all m: z̈ = k₃ (−C̄ V̄_n+1,m − S̄ W̄_n+1,m)
//! k₀² = (2n+1)(n+1)(n+2)/(2(2n+3)),  k₁² = (2n+1)(n+m+1)(n+m+2)/(2n+3)
//! k₂² = (1 + δ_m1)(2n+1)(n−m+1)(n−m+2)/(2n+3),  k₃² = (2n+1)(n+m+1)(n−m+1)/(2n+3)
//! ```
//!
//! `C̄_00` and `C̄_20` are left out: point mass and `J2` are [`super::GravityModel`]'s, exact at
//! every step (what the model's own `GM`, `a` and `C̄_20` change against WGS-84's is below
//! 1.3e-8 m/s² in LEO).
//!
//! **Slices.** An evaluation is a fixed sequence of work items: one to start (the Earth-fixed
//! position at the node time `t_n`), one per solid harmonic `(n ≤ N + 1, m ≤ M + 1)`, one
//! per coefficient, one per [`OMITTED_DEGREES_PER_ITEM`] degrees of the omitted power, one to
//! finish (back to launch-inertial axes, `R(t_n)ᵀ`). [`FieldRemainder::advance`] does at most
//! `terms_per_frame` of them per frame and starts an evaluation at most every
//! [`MIN_REFRESH_PERIOD_S`] ([`OMITTED_ONLY_REFRESH_PERIOD_S`] for point mass + `J2`, which
//! evaluates only the omitted RMS), so the value is refreshed every
//! [`FieldModel::frames_per_evaluation`] frames or that period, and held in between:
//! the value used at `t` was evaluated where the vehicle was up to two refresh periods
//! earlier. What that hold costs is part of the omitted field the allowance covers
//! (docs/guide/gravity.md).
//!
//! **Omitted field.** The degree-`n` part of the potential has, over the sphere of radius
//! `r`, the mean square gradient `(GM/r²)² (a/r)^(2n) (n + 1)(2n + 1) Σ_m (C̄² + S̄²)` (radial
//! `(n + 1)²`, horizontal `n (n + 1)` times the mean square of the surface harmonic, which is
//! `Σ_m (C̄² + S̄²)` for 4π-normalised harmonics); degrees are orthogonal, so the RMS of the
//! terms the model leaves out, up to degree [`TAIL_MAX_DEGREE`], is the root of their sum.

use super::egm2008::{self, FLIGHT_MAX_DEGREE, TAIL_MAX_DEGREE};
use crate::error::NavError;

/// `n (n + 1) / 2 + m`: the position of `(n, m)` in a triangle stored degree by degree.
const fn triangle_index(degree: usize, order: usize) -> usize {
    degree * (degree + 1) / 2 + order
}

const COEFFICIENT_COUNT: usize = triangle_index(FLIGHT_MAX_DEGREE, FLIGHT_MAX_DEGREE) + 1;
const _: () =
    assert!(COEFFICIENT_COUNT == egm2008::C.len() && COEFFICIENT_COUNT == egm2008::S.len());
const _: () = assert!(egm2008::TAIL_DEGREE_POWER.len() == TAIL_MAX_DEGREE - FLIGHT_MAX_DEGREE);

/// Default work items per frame: 4 evaluate a 12 × 12 model in 50 frames (0.1 s at 500 Hz).
pub const DEFAULT_TERMS_PER_FRAME: u8 = 4;

/// Shortest time between the starts of two evaluations of a model beyond `J2` (s): a model
/// that takes fewer frames waits.
pub const MIN_REFRESH_PERIOD_S: f64 = 0.1;

/// Time between two evaluations of the omitted RMS alone, for point mass + `J2` (s): it
/// changes with the radius only, by 0.3 % per km, and 1 s is at most 8 km of altitude.
pub const OMITTED_ONLY_REFRESH_PERIOD_S: f64 = 1.0;

/// Degrees of the omitted power summed per work item.
pub const OMITTED_DEGREES_PER_ITEM: usize = 10;

/// Work items of the omitted power (degrees 2..=[`TAIL_MAX_DEGREE`]).
const OMITTED_ITEMS: usize = (TAIL_MAX_DEGREE - 1).div_ceil(OMITTED_DEGREES_PER_ITEM);

/// The flight model's fidelity: `degree` 2 and `order` 0 is point mass + `J2` alone (nothing
/// evaluated); `order` 0 with a higher degree the zonal terms `J3 … J_N`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FieldModel {
    /// Largest degree `N`, 2 to [`FLIGHT_MAX_DEGREE`].
    pub degree: u8,
    /// Largest order `M`, 0 to `degree`.
    pub order: u8,
    /// Work items per frame (module docs), at least 1.
    pub terms_per_frame: u8,
}

impl FieldModel {
    /// Point mass + `J2`: today's model, nothing beyond it evaluated.
    pub const J2_ONLY: Self = Self {
        degree: 2,
        order: 0,
        terms_per_frame: DEFAULT_TERMS_PER_FRAME,
    };

    /// Whether the model adds nothing to point mass + `J2`.
    pub fn is_j2_only(&self) -> bool {
        self.degree == 2 && self.order == 0
    }

    /// # Errors
    /// [`NavError::InvalidConfiguration`] for a degree outside 2..=[`FLIGHT_MAX_DEGREE`], an
    /// order above the degree, or no work per frame.
    ///
    /// ```
    /// use nav_core::gravity::harmonics::FieldModel;
    /// let model = FieldModel { degree: 8, order: 8, terms_per_frame: 4 };
    /// assert!(model.validate().is_ok());
    /// assert!(FieldModel { degree: 13, ..model }.validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<(), NavError> {
        let degree_in_range = (2..=FLIGHT_MAX_DEGREE).contains(&usize::from(self.degree));
        if degree_in_range && self.order <= self.degree && self.terms_per_frame >= 1 {
            Ok(())
        } else {
            Err(NavError::InvalidConfiguration)
        }
    }

    /// Largest column of solid harmonics the coefficients read.
    fn solid_order(&self) -> u8 {
        self.order
            .saturating_add(1)
            .min(self.degree.saturating_add(1))
    }

    /// Work items of one evaluation (module docs): start, solid harmonics, coefficients,
    /// omitted power, finish.
    pub fn work_items(&self) -> usize {
        if self.is_j2_only() {
            return 1 + OMITTED_ITEMS + 1;
        }
        let solid_degree = usize::from(self.degree) + 1;
        let solid: usize = (0..=usize::from(self.solid_order()))
            .map(|m| solid_degree + 1 - m)
            .sum();
        let coefficients: usize = (2..=usize::from(self.degree))
            .map(|n| n.min(usize::from(self.order)) + 1)
            .sum();
        // The start item computes V̄_00 itself.
        1 + (solid - 1) + coefficients + OMITTED_ITEMS + 1
    }

    /// Frames between two refreshes of the held value.
    pub fn frames_per_evaluation(&self) -> usize {
        self.work_items()
            .div_ceil(usize::from(self.terms_per_frame.max(1)))
    }
}

// The evaluation and its tables (feature `gravity-field`), or without it a stand-in of the
// same interface that holds no table and accepts point mass + `J2` alone.
#[cfg(feature = "gravity-field")]
#[path = "harmonics_remainder.rs"]
mod remainder;
#[cfg(not(feature = "gravity-field"))]
#[path = "harmonics_absent.rs"]
mod remainder;
pub use remainder::FieldRemainder;

#[cfg(all(test, feature = "gravity-field"))]
#[path = "harmonics_tests.rs"]
mod tests;
