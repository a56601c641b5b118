//! Two (or more) star-tracker heads with one installation-error block in the filter.
//!
//! The filter carries the installation error `ψ` ([`crate::state::STAR_INSTALLATION`]) of
//! the head it fuses (the *active* head). The relative alignment of two heads is estimated
//! here, outside the filter, from simultaneous measurements of both ([`RelativeAlignment`]:
//! no IMU is involved), and when the active head goes blind and the other takes over, the
//! installation estimate and the filter's installation block are moved to the new head
//! ([`RelativeAlignment::hand_over`], [`new_head_installation`],
//! [`crate::filter::ErrorStateFilter::hand_over_installation`]).
//!
//! ## Model
//! Head `h` measures, as [`crate::measurement::star_sensor`] models it,
//! `q_gs_h = q_gi ⊗ q_ib ⊗ q_bs_h ⊗ q_ψ_h ⊗ exp(n_h)`: `q_bs_h` the nominal mounting,
//! `q_ψ_h` the installation error, `n_h` the noise rotation vector (rad) in sensor-`h` axes,
//! independent per axis with the 1σ `noise_angle_rad` of `star_sensor` (a rotation angle;
//! the vector part of `exp(n)` is `n/2`, whence that function's `R = (σ/2)²`).
//!
//! ## Relative alignment (derivation)
//! The heads' relative alignment is `q_ab = (q_bs_A ⊗ q_ψ_A)* ⊗ (q_bs_B ⊗ q_ψ_B)` (sensor B
//! to sensor A as they actually sit). For a pair of measurements with one time of validity
//! the attitude cancels:
//! `q_gs_A* ⊗ q_gs_B = exp(−n_A) ⊗ q_ab ⊗ exp(n_B)`.
//! The estimate `q̂_ab` has the right error `δ` (rotation vector, rad, sensor-B axes):
//! `q_ab = q̂_ab ⊗ exp(δ)`, covariance `P` (rad²). The residual of a pair is
//! `z = log(q̂_ab* ⊗ q_gs_A* ⊗ q_gs_B)` (the logarithm takes the sign with a non-negative
//! scalar part, so `q` and `−q` give the same `z`). Since `q* ⊗ exp(v) ⊗ q = exp(R(q)ᵀ v)`
//! (a quaternion sandwich rotates the vector part),
//! `z = log(exp(−Ĉ_abᵀ n_A) ⊗ exp(δ) ⊗ exp(n_B)) = δ + n_B − Ĉ_abᵀ n_A + O(2)`,
//! `Ĉ_ab = R(q̂_ab)`. Hence `H = I` and the pair's noise covariance, in B axes,
//! `R_pair = diag(σ_B²) + Ĉ_abᵀ diag(σ_A²) Ĉ_ab` (A's noise rotated into B axes by
//! `Ĉ_ba = Ĉ_abᵀ`). Tests prove the three Jacobians by finite differences of the exact
//! expression and `R_pair` by Monte Carlo.
//!
//! ## Update
//! `S = P + R_pair`, NIS `= zᵀ S⁻¹ z` (3×3 Cholesky of `S`); above the gate nothing
//! changes. Otherwise `K = P S⁻¹`, `δ̂ = K z`, `q̂_ab ← q̂_ab ⊗ exp(δ̂)` and the Joseph form
//! `P ← (I − K) P (I − K)ᵀ + K R_pair Kᵀ` (Bucy & Joseph 1968). The correction is then
//! folded into the estimate, as the filter's reset does: `exp(δ⁺) = exp(−δ̂) ⊗ exp(δ)`, so
//! `δ⁺ = δ − δ̂ − ½ δ̂ × δ + O(2)` (Solà 2017, §7.2) and `P ← J P Jᵀ`,
//! `J = I − ½[δ̂×]` (proven by a finite difference in the tests). `P` is symmetrised.
//!
//! ## Reversal
//! `q_ba = q_ab* = exp(−δ) ⊗ q̂_ab* = q̂_ba ⊗ exp(−Ĉ_ab δ)`, so the error of the reversed
//! estimate is `δ_ba = −Ĉ_ab δ` and its covariance `Ĉ_ab P Ĉ_abᵀ`
//! ([`RelativeAlignment::reversed`]).
//!
//! ## Hand-over from head A (old) to head B (new)
//! From the definition of `q_ab`: `q_ψ_B = q_bs_B* ⊗ q_bs_A ⊗ q_ψ_A ⊗ q_ab`, so the new
//! head's installation estimate is `q̂_ψ_B = q_bs_B* ⊗ q_bs_A ⊗ q̂_ψ_A ⊗ q̂_ab`
//! ([`new_head_installation`]). The filter's installation error is the right error
//! `q_ψ = q̂_ψ ⊗ δq_ψ` with the state `ψ = vec(δq_ψ)` (truth − estimate, half-angle;
//! [`crate::measurement`]). Substituting `q_ψ_A = q̂_ψ_A ⊗ δq_ψ_A` and
//! `q_ab = q̂_ab ⊗ exp(δ)`:
//! `δq_ψ_B = (q̂_ab* ⊗ δq_ψ_A ⊗ q̂_ab) ⊗ exp(δ)`, whose vector part is
//! `ψ_B = Ĉ_abᵀ ψ_A + δ/2 + O(2)` (the sandwich rotates `ψ_A` exactly; vector parts of small
//! quaternions add; `vec(exp(δ)) = δ/2 + O(|δ|³)`). With `T = Ĉ_abᵀ = C_new,old` the filter's
//! block maps as `x_ψ ← T x_ψ`, `P_ψψ ← T P_ψψ Tᵀ + P/4`, `P_jψ ← P_jψ Tᵀ` for every other
//! state `j` (border states included), treating `δ` as independent of the filter's errors.
//! That neglects one correlation: the pairs contain head A's noise, which the filter has
//! also fused when it used the same measurements.

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::attitude::{
    canonical, conjugate, exp_rotation_vector, log_rotation_vector, normalise, product,
    rotation_matrix, skew,
};
use crate::block;
use crate::structured::Cholesky3;
use crate::NavError;

/// Largest asymmetry `|P_ij − P_ji|` of a covariance given as symmetric, relative to its
/// largest element: round-off of a symmetric computation stays far below it, a transposed
/// or mistyped matrix far above.
pub const SYMMETRY_TOLERANCE: f64 = 1.0e-9;

/// What a pair update computed, for gating and telemetry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairReport {
    /// Residual `z = log(q̂_ab* ⊗ q_gs_A* ⊗ q_gs_B)`, rotation vector in sensor-B axes (rad).
    pub residual_rad: Vector3<f64>,
    /// Innovation covariance `S = P + R_pair` (rad²).
    pub covariance_rad2: Matrix3<f64>,
    /// Normalised innovation squared `zᵀ S⁻¹ z` (χ² with 3 degrees of freedom if consistent).
    pub normalised_innovation_squared: f64,
    /// Whether the update was applied (false: rejected by the gate, estimator untouched).
    pub accepted: bool,
}

/// What the filter and the caller need to move the installation block to the new head
/// (module docs, "Hand-over").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandOver {
    /// The new head's installation estimate `q̂_ψ_B` (unit, canonical sign).
    pub installation_estimate: Quaternion<f64>,
    /// `T = Ĉ_abᵀ`: old-head sensor axes to new-head sensor axes.
    pub rotation_new_from_old: Matrix3<f64>,
    /// `P/4`: the relative alignment's covariance as a half-angle covariance (rad²), added to
    /// the installation block.
    pub added_covariance_half_angle: Matrix3<f64>,
}

/// The estimated relative alignment of two star-tracker heads A and B (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RelativeAlignment {
    /// `q̂_ab`: sensor-B frame to sensor-A frame (unit).
    estimate: Quaternion<f64>,
    /// Covariance of the right error `δ` (rad², sensor-B axes).
    covariance: Matrix3<f64>,
    /// Number of pairs the gate accepted.
    pairs_accepted: u32,
}

/// `q̂_ψ_B = q_bs_B* ⊗ q_bs_A ⊗ q̂_ψ_A ⊗ q̂_ab` (module docs, "Hand-over"): the installation
/// estimate of the new head B from the old head A's, the two nominal mountings and the
/// relative alignment `q̂_ab` (B to A). Normalised, canonical sign.
///
/// # Errors
/// [`NavError::NonFiniteInput`] for a non-finite input, [`NavError::DegenerateQuaternion`]
/// for a (near) zero quaternion.
///
/// # Examples
/// ```
/// use nalgebra::{Quaternion, Vector3};
/// use nav_core::attitude::exp_rotation_vector;
/// use nav_core::star_heads::new_head_installation;
/// let mounting_a = exp_rotation_vector(&Vector3::new(0.3, -0.2, 0.1));
/// let quarter_turn = exp_rotation_vector(&Vector3::new(1.5707963267948966, 0.0, 0.0));
/// let mounting_b = mounting_a * quarter_turn;
/// // Perfect installations: the relative alignment is the nominal one, and the new head's
/// // installation error is the identity too.
/// let identity = Quaternion::identity();
/// let installation_b = new_head_installation(&mounting_a, &mounting_b, &identity, &quarter_turn)?;
/// assert!((installation_b.w - 1.0).abs() < 1e-15);
/// # Ok::<(), nav_core::NavError>(())
/// ```
pub fn new_head_installation(
    mounting_old: &Quaternion<f64>,
    mounting_new: &Quaternion<f64>,
    installation_old: &Quaternion<f64>,
    alignment_old_from_new: &Quaternion<f64>,
) -> Result<Quaternion<f64>, NavError> {
    let [mounting_old, mounting_new, installation_old, alignment] = [
        mounting_old,
        mounting_new,
        installation_old,
        alignment_old_from_new,
    ]
    .map(normalise);
    let sensor_old_to_new = product(&conjugate(&mounting_new?), &mounting_old?);
    let installation = product(
        &product(&sensor_old_to_new, &installation_old?),
        &alignment?,
    );
    Ok(canonical(&normalise(&installation)?))
}

/// `R_pair = diag(σ_B²) + C_abᵀ diag(σ_A²) C_ab` (module docs), rad², sensor-B axes.
fn pair_noise_covariance(
    alignment: &Matrix3<f64>,
    noise_a_angle_rad: &[f64; 3],
    noise_b_angle_rad: &[f64; 3],
) -> Matrix3<f64> {
    let [variance_a, variance_b] =
        [noise_a_angle_rad, noise_b_angle_rad].map(|sigma| Vector3::from(sigma.map(|s| s * s)));
    let rotated_a = alignment.transpose() * Matrix3::from_diagonal(&variance_a) * alignment;
    symmetrised(&(Matrix3::from_diagonal(&variance_b) + rotated_a))
}

/// `J = I − ½[δ̂×]`, the Jacobian of the error after the correction `δ̂` is folded into
/// the estimate (module docs, "Update").
fn reset_jacobian(correction: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::identity() - skew(correction) * 0.5
}

fn symmetrised(matrix: &Matrix3<f64>) -> Matrix3<f64> {
    (matrix + matrix.transpose()) * 0.5
}

/// [`NavError::NonFiniteInput`] for a non-finite entry, [`NavError::InvalidConfiguration`]
/// for an asymmetry above [`SYMMETRY_TOLERANCE`] or a negative diagonal entry.
fn check_symmetric(covariance: &Matrix3<f64>) -> Result<(), NavError> {
    if !covariance.iter().all(|value| value.is_finite()) {
        return Err(NavError::NonFiniteInput);
    }
    let asymmetry = (covariance - covariance.transpose()).amax();
    let diagonal_non_negative = covariance.diagonal().iter().all(|value| *value >= 0.0);
    if asymmetry <= SYMMETRY_TOLERANCE * covariance.amax() && diagonal_non_negative {
        Ok(())
    } else {
        Err(NavError::InvalidConfiguration)
    }
}

fn noise_is_valid(sigmas: &[f64; 3]) -> bool {
    sigmas
        .iter()
        .all(|sigma| sigma.is_finite() && *sigma >= 0.0)
}

impl RelativeAlignment {
    /// The estimator at the nominal alignment `q̂_ab = q_bs_A* ⊗ q_bs_B` of the two heads'
    /// nominal mountings (sensor to body), with the prior covariance `prior_covariance_rad2`
    /// of its right error `δ` (rad², sensor-B axes). With independent installation errors
    /// of 1σ `σ_A`, `σ_B` (rotation angle per axis) the prior is
    /// `Ĉ_abᵀ diag(σ_A²) Ĉ_ab + diag(σ_B²)` (the pair model with `n` replaced by `ψ`).
    ///
    /// # Errors
    /// As [`RelativeAlignment::from_estimate`].
    ///
    /// # Examples
    /// ```
    /// use nalgebra::{Matrix3, Vector3};
    /// use nav_core::attitude::exp_rotation_vector;
    /// use nav_core::star_heads::RelativeAlignment;
    /// let mounting_a = exp_rotation_vector(&Vector3::new(0.3, -0.2, 0.1));
    /// let quarter_turn = exp_rotation_vector(&Vector3::new(1.5707963267948966, 0.0, 0.0));
    /// let mounting_b = mounting_a * quarter_turn;
    /// let prior = Matrix3::identity() * 1e-6;
    /// let alignment = RelativeAlignment::new(&mounting_a, &mounting_b, &prior)?;
    /// assert!((alignment.estimate().coords - quarter_turn.coords).amax() < 1e-15);
    /// assert_eq!(alignment.covariance(), &prior);
    /// assert_eq!(alignment.pairs_accepted(), 0);
    /// assert!(RelativeAlignment::new(&mounting_a, &mounting_b, &(-prior)).is_err());
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn new(
        mounting_a: &Quaternion<f64>,
        mounting_b: &Quaternion<f64>,
        prior_covariance_rad2: &Matrix3<f64>,
    ) -> Result<Self, NavError> {
        let [mounting_a, mounting_b] = [mounting_a, mounting_b].map(normalise);
        let nominal = product(&conjugate(&mounting_a?), &mounting_b?);
        Self::from_estimate(&nominal, prior_covariance_rad2)
    }

    /// The estimator at a given alignment `q̂_ab` (B to A; e.g. a stored calibration) with
    /// the covariance `prior_covariance_rad2` of its right error (rad², sensor-B axes).
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a non-finite input,
    /// [`NavError::DegenerateQuaternion`] for a (near) zero quaternion,
    /// [`NavError::InvalidConfiguration`] for a covariance that is not symmetric (within
    /// [`SYMMETRY_TOLERANCE`]) positive definite.
    ///
    /// # Examples
    /// ```
    /// use nalgebra::{Matrix3, Quaternion};
    /// use nav_core::star_heads::RelativeAlignment;
    /// use nav_core::NavError;
    /// let prior = Matrix3::identity() * 1e-8;
    /// let alignment = RelativeAlignment::from_estimate(&Quaternion::identity(), &prior)?;
    /// assert_eq!(alignment.estimate(), &Quaternion::identity());
    /// let not_symmetric = Matrix3::new(1e-8, 1e-9, 0.0, 0.0, 1e-8, 0.0, 0.0, 0.0, 1e-8);
    /// assert_eq!(
    ///     RelativeAlignment::from_estimate(&Quaternion::identity(), &not_symmetric),
    ///     Err(NavError::InvalidConfiguration)
    /// );
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn from_estimate(
        estimate: &Quaternion<f64>,
        prior_covariance_rad2: &Matrix3<f64>,
    ) -> Result<Self, NavError> {
        let estimate = normalise(estimate)?;
        check_symmetric(prior_covariance_rad2)?;
        let covariance = symmetrised(prior_covariance_rad2);
        Cholesky3::new(&covariance).ok_or(NavError::InvalidConfiguration)?;
        Ok(Self {
            estimate,
            covariance,
            pairs_accepted: 0,
        })
    }

    /// The estimate `q̂_ab` (sensor B to sensor A, unit).
    pub fn estimate(&self) -> &Quaternion<f64> {
        &self.estimate
    }

    /// The covariance of the estimate's right error `δ` (rad², sensor-B axes).
    pub fn covariance(&self) -> &Matrix3<f64> {
        &self.covariance
    }

    /// The number of pairs the gate accepted (saturating).
    pub fn pairs_accepted(&self) -> u32 {
        self.pairs_accepted
    }

    /// Updates the estimate with a pair of measurements of the two heads with one time of
    /// validity (module docs, "Update"): `measured_a` `q_gs_A`, `measured_b` `q_gs_B` (any
    /// sign and any common reference frame `g`), their 1σ noise angles about the sensor axes
    /// `[x, y, z]` (rad, as [`crate::measurement::star_sensor`]'s `noise_angle_rad`), and the
    /// NIS gate (`f64::INFINITY` accepts every pair).
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a non-finite quaternion, a NaN gate or a negative
    /// or non-finite noise; [`NavError::DegenerateQuaternion`] for a (near) zero quaternion;
    /// [`NavError::NonPositiveInnovationCovariance`] if `S` is not positive definite;
    /// [`NavError::NonFiniteState`] if the result is not finite. The estimator is unchanged
    /// on any error.
    ///
    /// # Examples
    /// ```
    /// use nalgebra::{Matrix3, Quaternion, Vector3};
    /// use nav_core::attitude::exp_rotation_vector;
    /// use nav_core::star_heads::RelativeAlignment;
    /// let arcsec = core::f64::consts::PI / 180.0 / 3600.0;
    /// let noise = [5.0 * arcsec, 5.0 * arcsec, 35.0 * arcsec];
    /// let mut alignment =
    ///     RelativeAlignment::from_estimate(&Quaternion::identity(), &(Matrix3::identity() * 1e-6))?;
    /// // Both heads see the same frame, head B turned by 100″ about its x axis against A.
    /// let sky = exp_rotation_vector(&Vector3::new(0.4, 1.0, -2.0));
    /// let offset = exp_rotation_vector(&Vector3::new(100.0 * arcsec, 0.0, 0.0));
    /// let report = alignment.update(&sky, &(sky * offset), &noise, &noise, 16.0)?;
    /// assert!(report.accepted);
    /// assert!((report.residual_rad.x - 100.0 * arcsec).abs() < 1e-12);
    /// assert_eq!(alignment.pairs_accepted(), 1);
    /// // The estimate moved most of the way to the offset.
    /// let moved = 2.0 * alignment.estimate().i;
    /// assert!((moved - 100.0 * arcsec).abs() < 1.0 * arcsec);
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn update(
        &mut self,
        measured_a: &Quaternion<f64>,
        measured_b: &Quaternion<f64>,
        noise_a_angle_rad: &[f64; 3],
        noise_b_angle_rad: &[f64; 3],
        gate_nis: f64,
    ) -> Result<PairReport, NavError> {
        if gate_nis.is_nan() || !noise_is_valid(noise_a_angle_rad) {
            return Err(NavError::NonFiniteInput);
        }
        if !noise_is_valid(noise_b_angle_rad) {
            return Err(NavError::NonFiniteInput);
        }
        let [measured_a, measured_b] = [measured_a, measured_b].map(normalise);
        let measured_ab = product(&conjugate(&measured_a?), &measured_b?);
        let residual = log_rotation_vector(&product(&conjugate(&self.estimate), &measured_ab));
        let alignment = rotation_matrix(&self.estimate);
        let noise = pair_noise_covariance(&alignment, noise_a_angle_rad, noise_b_angle_rad);
        let covariance = symmetrised(&(self.covariance + noise));
        let cholesky =
            Cholesky3::new(&covariance).ok_or(NavError::NonPositiveInnovationCovariance)?;
        let whitened = Vector3::from(cholesky.whiten(block::from_vector(&residual)));
        let nis = whitened.norm_squared();
        if !nis.is_finite() {
            return Err(NavError::NonPositiveInnovationCovariance);
        }
        let accepted = nis <= gate_nis;
        if accepted {
            self.apply(&cholesky, &residual, &noise)?;
        }
        Ok(PairReport {
            residual_rad: residual,
            covariance_rad2: covariance,
            normalised_innovation_squared: nis,
            accepted,
        })
    }

    /// The accepted update's state and covariance (module docs, "Update"), written only if
    /// every value is finite.
    fn apply(
        &mut self,
        cholesky: &Cholesky3,
        residual: &Vector3<f64>,
        noise: &Matrix3<f64>,
    ) -> Result<(), NavError> {
        // K = P S⁻¹: row i of K is (S⁻¹ P_i)ᵀ, P and S symmetric.
        let gain =
            block::to_matrix(&block::from_matrix(&self.covariance).map(|row| cholesky.solve(row)));
        let correction = gain * residual;
        let estimate = normalise(&product(&self.estimate, &exp_rotation_vector(&correction)))
            .map_err(|_| NavError::NonFiniteState)?;
        let complement = Matrix3::identity() - gain;
        let joseph =
            complement * self.covariance * complement.transpose() + gain * noise * gain.transpose();
        let reset = reset_jacobian(&correction);
        let covariance = symmetrised(&(reset * joseph * reset.transpose()));
        if !covariance.iter().all(|value| value.is_finite()) {
            return Err(NavError::NonFiniteState);
        }
        self.estimate = estimate;
        self.covariance = covariance;
        self.pairs_accepted = self.pairs_accepted.saturating_add(1);
        Ok(())
    }

    /// Adds the symmetric part of `covariance_rad2` (rad², sensor-B axes) to `P`: the walk
    /// of a relative alignment that drifts (thermal), added by the caller per pair interval.
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a non-finite entry, [`NavError::InvalidConfiguration`]
    /// for an asymmetry above [`SYMMETRY_TOLERANCE`] or a negative diagonal entry; the
    /// estimator is unchanged then.
    ///
    /// # Examples
    /// ```
    /// use nalgebra::{Matrix3, Quaternion};
    /// use nav_core::star_heads::RelativeAlignment;
    /// let mut alignment =
    ///     RelativeAlignment::from_estimate(&Quaternion::identity(), &(Matrix3::identity() * 1e-8))?;
    /// alignment.add_process_noise(&(Matrix3::identity() * 1e-10))?;
    /// assert!((alignment.covariance()[(2, 2)] - 1.01e-8).abs() < 1e-22);
    /// assert!(alignment.add_process_noise(&(Matrix3::identity() * f64::NAN)).is_err());
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn add_process_noise(&mut self, covariance_rad2: &Matrix3<f64>) -> Result<(), NavError> {
        check_symmetric(covariance_rad2)?;
        self.covariance = symmetrised(&(self.covariance + covariance_rad2));
        Ok(())
    }

    /// The same alignment seen from the other head: `q̂_ba = q̂_ab*`, covariance
    /// `Ĉ_ab P Ĉ_abᵀ` in sensor-A axes (module docs, "Reversal"); for a hand-over from B to
    /// A. The pair count is kept.
    ///
    /// # Examples
    /// ```
    /// use nalgebra::{Matrix3, Vector3};
    /// use nav_core::attitude::exp_rotation_vector;
    /// use nav_core::star_heads::RelativeAlignment;
    /// let turn = exp_rotation_vector(&Vector3::new(0.0, 0.0, 1.5707963267948966));
    /// let prior = Matrix3::from_diagonal(&Vector3::new(1e-8, 4e-8, 9e-8));
    /// let alignment = RelativeAlignment::from_estimate(&turn, &prior)?;
    /// let reversed = alignment.reversed();
    /// // A quarter turn about z swaps the x and y variances.
    /// assert!((reversed.covariance()[(0, 0)] - 4e-8).abs() < 1e-22);
    /// assert!((reversed.covariance()[(1, 1)] - 1e-8).abs() < 1e-22);
    /// assert!((reversed.estimate().k + turn.k).abs() < 1e-16);
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn reversed(&self) -> Self {
        let alignment = rotation_matrix(&self.estimate);
        Self {
            estimate: conjugate(&self.estimate),
            covariance: symmetrised(&(alignment * self.covariance * alignment.transpose())),
            pairs_accepted: self.pairs_accepted,
        }
    }

    /// Everything to move the installation block from head A (old, the filter's active
    /// head) to head B (new): the new head's installation estimate
    /// ([`new_head_installation`] with this estimate), `T = Ĉ_abᵀ` and `P/4` (module docs,
    /// "Hand-over"); give the last two to
    /// [`crate::filter::ErrorStateFilter::hand_over_installation`]. For a hand-over from B
    /// to A use [`RelativeAlignment::reversed`] first.
    ///
    /// # Errors
    /// As [`new_head_installation`].
    ///
    /// # Examples
    /// ```
    /// use nalgebra::{Matrix3, Quaternion, Vector3};
    /// use nav_core::attitude::{exp_rotation_vector, rotation_matrix};
    /// use nav_core::star_heads::RelativeAlignment;
    /// let mounting_a = exp_rotation_vector(&Vector3::new(0.3, -0.2, 0.1));
    /// let quarter_turn = exp_rotation_vector(&Vector3::new(1.5707963267948966, 0.0, 0.0));
    /// let mounting_b = mounting_a * quarter_turn;
    /// let prior = Matrix3::identity() * 4e-8;
    /// let alignment = RelativeAlignment::new(&mounting_a, &mounting_b, &prior)?;
    /// let hand_over = alignment.hand_over(&mounting_a, &mounting_b, &Quaternion::identity())?;
    /// assert!((hand_over.installation_estimate.w - 1.0).abs() < 1e-15);
    /// let expected = rotation_matrix(&quarter_turn).transpose();
    /// assert!((hand_over.rotation_new_from_old - expected).amax() < 1e-15);
    /// assert!((hand_over.added_covariance_half_angle[(0, 0)] - 1e-8).abs() < 1e-22);
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn hand_over(
        &self,
        mounting_a: &Quaternion<f64>,
        mounting_b: &Quaternion<f64>,
        installation_a: &Quaternion<f64>,
    ) -> Result<HandOver, NavError> {
        let installation_estimate =
            new_head_installation(mounting_a, mounting_b, installation_a, &self.estimate)?;
        Ok(HandOver {
            installation_estimate,
            rotation_new_from_old: rotation_matrix(&self.estimate).transpose(),
            added_covariance_half_angle: self.covariance * 0.25,
        })
    }
}

#[cfg(test)]
#[path = "star_heads_tests.rs"]
mod tests;
