//! Quaternion helpers in the crate's one convention (Hamilton, scalar first, `q_ab` maps
//! frame-`b` vectors into frame `a`; see the crate docs).
//!
//! Everything here is closed-form, branch-bounded and uses `libm` for transcendentals.

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::NavError;

/// Quaternion norms below this are treated as degenerate (cannot be normalised).
pub const MIN_QUATERNION_NORM: f64 = 1.0e-12;

/// Largest distance from 1 of the norm of a quaternion or direction that a configuration or
/// an initial state gives as unit (dimensionless; the bound itself is accepted,
/// [`is_unit_norm`]): the round-off of a normalised value stays far below it, a wrong
/// convention or a value never normalised far above.
pub const UNIT_NORM_TOLERANCE: f64 = 1.0e-9;

/// Whether `norm` is within [`UNIT_NORM_TOLERANCE`] of 1, the bound included (false for NaN).
#[inline]
pub fn is_unit_norm(norm: f64) -> bool {
    (norm - 1.0).abs() <= UNIT_NORM_TOLERANCE
}

/// Hamilton product `a ⊗ b` (rotation `b` first, then `a`, when both map into their left frame:
/// `q_ac = q_ab ⊗ q_bc`).
#[inline]
pub fn product(a: &Quaternion<f64>, b: &Quaternion<f64>) -> Quaternion<f64> {
    a * b
}

/// Conjugate `q*` (the inverse of a unit quaternion): `q_ba = q_ab*`.
#[inline]
pub fn conjugate(q: &Quaternion<f64>) -> Quaternion<f64> {
    q.conjugate()
}

/// Direction-cosine matrix `C_ab = R(q_ab)` of a unit quaternion, so `v_a = C_ab v_b`.
///
/// Standard Hamilton formula (e.g. Solà, "Quaternion kinematics for the error-state Kalman
/// filter", 2017, eq. 115).
pub fn rotation_matrix(q: &Quaternion<f64>) -> Matrix3<f64> {
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    Matrix3::new(
        w * w + x * x - y * y - z * z,
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        w * w - x * x + y * y - z * z,
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        w * w - x * x - y * y + z * z,
    )
}

/// Rotates `v` (expressed in frame `b`) into frame `a` with `q_ab`: `C_ab v`.
#[inline]
pub fn rotate(q: &Quaternion<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    rotation_matrix(q) * v
}

/// Below this angle (rad) [`exp_rotation_vector`] uses its Taylor series: the truncation
/// error there is below 1e-22, while `sin(|φ|/2)/|φ|` loses relative precision as `|φ| → 0`.
pub const SERIES_ANGLE_RAD: f64 = 1.0e-4;

/// Exact exponential of a rotation vector `φ` (rad): the unit quaternion
/// `[cos(|φ|/2), sin(|φ|/2) φ/|φ|]`. For `|φ| <` [`SERIES_ANGLE_RAD`] the Taylor series
/// `[1 − |φ|²/8 + |φ|⁴/384, φ/2 (1 − |φ|²/24 + |φ|⁴/1920)]` is used (truncation < 1e-22).
pub fn exp_rotation_vector(phi: &Vector3<f64>) -> Quaternion<f64> {
    let angle_squared = phi.dot(phi);
    let angle = crate::float::sqrt(angle_squared);
    if angle < SERIES_ANGLE_RAD {
        let scalar = 1.0 - angle_squared / 8.0 + angle_squared * angle_squared / 384.0;
        let vector_gain =
            0.5 * (1.0 - angle_squared / 24.0 + angle_squared * angle_squared / 1920.0);
        Quaternion::new(
            scalar,
            vector_gain * phi.x,
            vector_gain * phi.y,
            vector_gain * phi.z,
        )
    } else {
        let half = 0.5 * angle;
        let vector_gain = libm::sin(half) / angle;
        Quaternion::new(
            libm::cos(half),
            vector_gain * phi.x,
            vector_gain * phi.y,
            vector_gain * phi.z,
        )
    }
}

/// Rotation vector (rad) of a unit quaternion, the inverse of [`exp_rotation_vector`] on
/// the canonical sign: `φ = 2 atan2(|v|, w) v/|v|`, with `φ ≈ 2 v / w` for `|v| < 1e-8`
/// (relative truncation below 1e-16).
pub fn log_rotation_vector(q: &Quaternion<f64>) -> Vector3<f64> {
    let q = canonical(q);
    let vector = q.imag();
    let sine = crate::float::sqrt(vector.dot(&vector));
    if sine < 1.0e-8 {
        vector * (2.0 / q.w)
    } else {
        vector * (2.0 * libm::atan2(sine, q.w) / sine)
    }
}

/// Quaternion from a small-error vector part `ϑ` (the filter's attitude-error convention
/// `δq ≈ [1, ϑ]`), made exactly unit: `[sqrt(1 − |ϑ|²), ϑ]`.
///
/// # Errors
/// [`NavError::NonFiniteInput`] for a non-finite `ϑ`, [`NavError::DegenerateQuaternion`] when
/// `|ϑ| ≥ 1` (not a valid vector part of a unit quaternion).
pub fn from_vector_part(vector_part: &Vector3<f64>) -> Result<Quaternion<f64>, NavError> {
    if !all_finite3(vector_part) {
        return Err(NavError::NonFiniteInput);
    }
    let squared = vector_part.dot(vector_part);
    if squared >= 1.0 {
        return Err(NavError::DegenerateQuaternion);
    }
    Ok(Quaternion::new(
        crate::float::sqrt(1.0 - squared),
        vector_part.x,
        vector_part.y,
        vector_part.z,
    ))
}

/// Normalises `q` to unit norm.
///
/// # Errors
/// [`NavError::NonFiniteInput`] if any component is not finite,
/// [`NavError::DegenerateQuaternion`] if the norm is below [`MIN_QUATERNION_NORM`].
pub fn normalise(q: &Quaternion<f64>) -> Result<Quaternion<f64>, NavError> {
    if !(q.w.is_finite() && q.i.is_finite() && q.j.is_finite() && q.k.is_finite()) {
        return Err(NavError::NonFiniteInput);
    }
    let norm = crate::float::sqrt(q.w * q.w + q.i * q.i + q.j * q.j + q.k * q.k);
    if norm < MIN_QUATERNION_NORM {
        return Err(NavError::DegenerateQuaternion);
    }
    Ok(Quaternion::new(
        q.w / norm,
        q.i / norm,
        q.j / norm,
        q.k / norm,
    ))
}

/// Sign canonicalisation: returns `q` or `−q` (the same rotation) with a non-negative scalar
/// part, so residuals built from quaternion differences never see the `q`/`−q` ambiguity as a
/// 360° error.
#[inline]
pub fn canonical(q: &Quaternion<f64>) -> Quaternion<f64> {
    if q.w < 0.0 {
        -q
    } else {
        *q
    }
}

/// Skew-symmetric cross-product matrix `[v×]`, so `[v×] u = v × u`.
#[inline]
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// True when every component of `v` is finite.
#[inline]
pub fn all_finite3(v: &Vector3<f64>) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &Matrix3<f64>, b: &Matrix3<f64>, tol: f64) -> bool {
        (a - b).abs().max() < tol
    }

    /// The one unit-norm rule: accepted within the tolerance on either side of 1, refused a
    /// tenth of it beyond, and NaN, infinity and zero refused.
    #[test]
    fn a_unit_norm_is_within_the_tolerance_of_one() {
        for norm in [
            1.0,
            1.0 + 0.9 * UNIT_NORM_TOLERANCE,
            1.0 - 0.9 * UNIT_NORM_TOLERANCE,
        ] {
            assert!(is_unit_norm(norm), "{norm}");
        }
        for norm in [
            1.0 + 1.1 * UNIT_NORM_TOLERANCE,
            1.0 - 1.1 * UNIT_NORM_TOLERANCE,
            f64::NAN,
            f64::INFINITY,
            0.0,
        ] {
            assert!(!is_unit_norm(norm), "{norm}");
        }
    }

    #[test]
    fn rotation_matrix_of_90deg_about_z_maps_x_to_y() {
        let q = exp_rotation_vector(&Vector3::new(0.0, 0.0, core::f64::consts::FRAC_PI_2));
        let v = rotate(&q, &Vector3::x());
        assert!((v - Vector3::y()).norm() < 1e-15, "{v:?}");
    }

    #[test]
    fn rotation_matrix_matches_quaternion_sandwich_and_composes() {
        let a = exp_rotation_vector(&Vector3::new(0.3, -1.2, 0.7));
        let b = exp_rotation_vector(&Vector3::new(-0.5, 0.1, 2.0));
        let v = Vector3::new(1.0, 2.0, -3.0);
        let sandwich = product(&product(&a, &Quaternion::from_imag(v)), &conjugate(&a));
        assert!((sandwich.imag() - rotate(&a, &v)).norm() < 1e-14);
        let composed = rotation_matrix(&product(&a, &b));
        assert!(close(
            &composed,
            &(rotation_matrix(&a) * rotation_matrix(&b)),
            1e-14
        ));
    }

    #[test]
    fn small_angle_branch_is_continuous_with_exact_branch() {
        let axis = Vector3::new(0.6, -0.48, 0.64);
        let below = exp_rotation_vector(&(axis * 0.999_999e-4));
        let above = exp_rotation_vector(&(axis * 1.000_001e-4));
        assert!((below.coords - above.coords).norm() < 1e-9);
        let q = exp_rotation_vector(&(axis * 0.5e-4));
        assert!((q.norm() - 1.0).abs() < 1e-16);
    }

    #[test]
    fn body_error_convention_gives_c_true_equal_c_hat_times_i_plus_two_skew() {
        // q_true = q̂ ⊗ δq with δq = [sqrt(1-|ϑ|²), ϑ]  =>  C_true = Ĉ (I + 2[ϑ×]) + O(ϑ²)
        let q_hat = exp_rotation_vector(&Vector3::new(0.4, 0.2, -0.9));
        for scale in [1e-3, 0.5e-3] {
            let theta = Vector3::new(1.0, -2.0, 0.5) * scale;
            let q_true = product(&q_hat, &from_vector_part(&theta).unwrap());
            let linear = rotation_matrix(&q_hat) * (Matrix3::identity() + 2.0 * skew(&theta));
            let mismatch = (rotation_matrix(&q_true) - linear).abs().max();
            assert!(mismatch < 10.0 * scale * scale, "{mismatch}");
        }
    }

    #[test]
    fn log_inverts_exp_on_both_branches_and_either_sign() {
        for phi in [
            Vector3::new(0.3, -1.2, 2.0),
            Vector3::new(1e-9, 2e-9, -3e-9),
            Vector3::zeros(),
        ] {
            let q = exp_rotation_vector(&phi);
            assert!((log_rotation_vector(&q) - phi).norm() < 1e-15 * (1.0 + phi.norm()));
            assert!((log_rotation_vector(&-q) - phi).norm() < 1e-15 * (1.0 + phi.norm()));
        }
    }

    /// At `φ = (3·2⁻¹⁵, 0, 0)` rad (|φ| ≈ 9.2e-5, the small-angle branch) every quantity is
    /// a short dyadic: `|φ|² = 9·2⁻³⁰`, so `cos(|φ|/2) = 1 − 9·2⁻³³ + |φ|⁴/384 − …` and
    /// `sin(|φ|/2) = (|φ|/2)(1 − 3·2⁻³³ + |φ|⁴/1920 − …)`, whose leading parts are exact
    /// doubles and whose remainders (≤ 2e-19 relative) are far below half an ulp (5.6e-17): the
    /// correctly rounded results are the leading parts, exactly. A `|φ|⁴` term mis-weighted by
    /// more than about half an ulp, or a wrong `|φ|²` coefficient, changes these bits.
    #[test]
    fn small_angle_branch_is_correctly_rounded_at_a_dyadic_angle() {
        let angle = 3.0 * libm::exp2(-15.0);
        let q = exp_rotation_vector(&Vector3::new(angle, 0.0, 0.0));
        let expected_cos = 1.0 - 9.0 * libm::exp2(-33.0);
        let expected_sin = 0.5 * angle * (1.0 - 3.0 * libm::exp2(-33.0));
        assert_eq!(
            q.w.to_bits(),
            expected_cos.to_bits(),
            "{:e}",
            q.w - expected_cos
        );
        assert_eq!(
            q.i.to_bits(),
            expected_sin.to_bits(),
            "{:e}",
            q.i - expected_sin
        );
        assert_eq!((q.j, q.k), (0.0, 0.0));
        // The same point through the exact branch's formulas (libm), to within one ulp.
        assert!((libm::cos(0.5 * angle) - expected_cos).abs() <= f64::EPSILON);
        assert!((libm::sin(0.5 * angle) - expected_sin).abs() <= expected_sin * f64::EPSILON);
    }

    /// The small-angle vector gain `sin(|φ|/2)/|φ|` against the exact formula over the whole
    /// small-angle range (relative 1e-15: a wrong `|φ|²` or `|φ|⁴` coefficient is ≥ 1e-13).
    #[test]
    fn small_angle_vector_gain_matches_the_exact_formula() {
        let axis = Vector3::new(0.6, -0.48, 0.64);
        for angle in [1.0e-6, 2.0e-5, 6.0e-5, 9.9e-5] {
            let q = exp_rotation_vector(&(axis * angle));
            let exact_gain = libm::sin(0.5 * angle) / angle;
            let gain = q.imag().norm() / angle;
            assert!(
                (gain / exact_gain - 1.0).abs() < 1e-15,
                "{angle}: {:e}",
                gain / exact_gain - 1.0
            );
            assert!((q.w - libm::cos(0.5 * angle)).abs() <= f64::EPSILON);
        }
    }

    /// The rotation vector depends only on the quaternion's direction: `2 atan2(|v|, w) v/|v|`
    /// and its small-angle form `2 v / w` are both invariant under `q → k q` (`k > 0`), so a
    /// slightly non-unit quaternion (drift before renormalisation) gives the same vector.
    #[test]
    fn log_is_invariant_under_positive_scaling_on_both_branches() {
        for phi in [
            Vector3::new(0.3, -1.2, 2.0),
            Vector3::new(1e-9, 2e-9, -3e-9),
        ] {
            let q = exp_rotation_vector(&phi);
            for scale in [0.5, 2.0, 1.0 + 1e-6] {
                let scaled = log_rotation_vector(&(q * scale));
                assert!(
                    (scaled - phi).norm() < 1e-15 * (1.0 + phi.norm()),
                    "{scale}: {scaled:?} vs {phi:?}"
                );
            }
        }
    }

    /// A norm exactly at [`MIN_QUATERNION_NORM`] is still normalised (only norms below it are
    /// degenerate); `sqrt(x²) = |x|` exactly in IEEE arithmetic, so the norm is the threshold.
    #[test]
    fn normalise_accepts_a_norm_exactly_at_the_threshold() {
        let q = Quaternion::new(MIN_QUATERNION_NORM, 0.0, 0.0, 0.0);
        assert_eq!(normalise(&q), Ok(Quaternion::new(1.0, 0.0, 0.0, 0.0)));
        let below = Quaternion::new(0.5 * MIN_QUATERNION_NORM, 0.0, 0.0, 0.0);
        assert_eq!(normalise(&below), Err(NavError::DegenerateQuaternion));
    }

    /// Canonicalisation is idempotent, also for a 180° rotation (`w = 0`), which already has a
    /// non-negative scalar part and must be returned unchanged (flipping it would make
    /// `canonical(canonical(q)) ≠ canonical(q)`).
    #[test]
    fn canonical_is_idempotent_and_keeps_a_zero_scalar_part() {
        for q in [
            Quaternion::new(0.0, 0.6, 0.0, -0.8),
            Quaternion::new(-0.5, 0.5, 0.5, 0.5),
            Quaternion::new(0.5, -0.5, 0.5, 0.5),
        ] {
            let once = canonical(&q);
            assert_eq!(canonical(&once), once);
            assert!(once.w >= 0.0);
        }
        let half_turn = Quaternion::new(0.0, 0.6, 0.0, -0.8);
        assert_eq!(canonical(&half_turn), half_turn);
        assert_eq!(canonical(&half_turn).i.to_bits(), 0.6_f64.to_bits());
    }

    #[test]
    fn bad_quaternions_are_errors_not_panics() {
        assert_eq!(
            normalise(&Quaternion::new(0.0, 0.0, 0.0, 0.0)),
            Err(NavError::DegenerateQuaternion)
        );
        assert_eq!(
            normalise(&Quaternion::new(f64::NAN, 0.0, 0.0, 1.0)),
            Err(NavError::NonFiniteInput)
        );
        assert_eq!(
            from_vector_part(&Vector3::new(1.0, 0.0, 0.0)),
            Err(NavError::DegenerateQuaternion)
        );
        let flipped = canonical(&Quaternion::new(-0.5, 0.5, 0.5, 0.5));
        assert!(flipped.w > 0.0);
    }
}
