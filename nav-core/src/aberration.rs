//! Velocity aberration of a star tracker's attitude: the apparent displacement of the stars
//! by the vehicle's own inertial velocity, and its removal from a measured attitude.
//!
//! ## Model
//! An observer moving at `v` relative to the solar-system barycentre sees a star of
//! catalogue direction `u` at `u' = (u + β) / |u + β|`, `β = v/c`, to first order in `β`
//! (stellar aberration, the classical first-order form: Seidelmann (ed.), *Explanatory
//! Supplement to the Astronomical Almanac*, 1992, Chapter 3, "aberration"; the relativistic
//! form differs by `O(β²)`, 6e-10 rad in low orbit), that is
//!
//! ```text
//! u' = u + (I − u uᵀ) β + O(β²)
//! ```
//!
//! the star moves towards the velocity by `|β| sin(angle between u and v)`: 5″ at the
//! 7.6 km/s of a low orbit. Only the vehicle's velocity about the Earth is handled here, in
//! the launch-inertial frame (whose origin is fixed in inertial space, so this is the
//! geocentric inertial velocity); the Earth's orbital (annual) aberration, 20″, is the same
//! for every vehicle and is removed by the tracker's own catalogue or software, as most do.
//!
//! ## The attitude it displaces
//! Near the boresight `b` (unit, inertial axes), a star `u = b + ρ e` (`e ⟂ b`, `ρ` the
//! off-boresight angle) moves by `(I − b bᵀ)β − ρ ((e·β) b + (b·β) e) + O(ρ², β²)`. The
//! small rotation `δ = b × β` moves it by `δ × u = (I − b bᵀ)β − ρ (e·β) b`
//! (`(b × β) × b = β − (b·β) b`, `(b × β) × e = −(e·β) b`): the same to first order but for
//! `−ρ (b·β) e`, a contraction of the field about the boresight, which no rotation fits
//! and a field symmetric about the boresight averages out (it shifts the stars' centroid
//! `c` by `−(b·β) c`, a rotation of at most `|c| |β|`, 0.09″ per degree of centroid offset at
//! 5″). A tracker fitting catalogue directions `u_k` to the observed `s_k = C_si u'_k =
//! C_si exp(δ) u_k` therefore reports `Ĉ_si = C_si exp(δ)`, i.e. `Ĉ_is = exp(−δ) C_is`,
//! or, moving the rotation into sensor axes (`δ_s = C_si δ = z × β_s`, `z` the boresight,
//! `β_s = C_si β`),
//!
//! ```text
//! q_is,m = q_is ⊗ exp(a_s),   a_s = β_s × z = (β_s,y, −β_s,x, 0)
//! ```
//!
//! a rotation across the boresight, none about it. Sign: moving along sensor `+x`, the
//! star seen on the boresight is one catalogued at `z − β x`, so the tracker's boresight is
//! turned away from the velocity: a rotation about `y` by `−β`, which is `a_s`. nav-sim's
//! truth applies this rotation; its test fits a tracker's attitude to displaced star
//! directions (the nonlinear formula above) and finds it, sign and size. [`correct`] removes
//! it with the navigation velocity: `q_is = q_is,m ⊗ exp(−a_s)`. `a_s` is taken with the
//! measured attitude's own axes: the measured and the true sensor axes differ by the noise,
//! the slow error and the aberration itself, under a minute of arc, which changes `a_s` by
//! `|β|` times that angle, under 1.5e-3″; a 1 m/s velocity error changes it by `1/c` rad,
//! 7e-4″.

use nalgebra::{Quaternion, Vector3};

use crate::attitude::{all_finite3, exp_rotation_vector, normalise, product, rotation_matrix};
use crate::NavError;

/// Speed of light in vacuum (m/s), exact by the SI definition of the metre.
pub const SPEED_OF_LIGHT_MPS: f64 = 299_792_458.0;

/// The rotation `a_s = β_s × z` (rad, sensor axes) by which velocity aberration turns a
/// star tracker's measured frame (module docs for the derivation and the sign), for the
/// sensor-to-inertial attitude `attitude_q_is` and the inertial velocity `velocity_mps`
/// (m/s, the same inertial axes). `attitude_q_is` need not be exactly unit: it is normalised.
///
/// # Errors
/// [`NavError::NonFiniteInput`] for NaN/Inf in either input;
/// [`NavError::DegenerateQuaternion`] for an attitude of (near) zero norm.
pub fn rotation_rad(
    attitude_q_is: &Quaternion<f64>,
    velocity_mps: &Vector3<f64>,
) -> Result<Vector3<f64>, NavError> {
    let finite = attitude_q_is.coords.iter().all(|c| c.is_finite());
    if !(finite && all_finite3(velocity_mps)) {
        return Err(NavError::NonFiniteInput);
    }
    let unit = normalise(attitude_q_is)?;
    // β_s = C_si β = C_isᵀ v / c.
    let beta_sensor = rotation_matrix(&unit).transpose() * (velocity_mps / SPEED_OF_LIGHT_MPS);
    // β_s × z = (β_y, −β_x, 0).
    Ok(Vector3::new(beta_sensor.y, -beta_sensor.x, 0.0))
}

/// The measured sensor-to-inertial attitude `measured_q_is` with the velocity aberration of
/// a vehicle moving at `velocity_mps` (inertial, m/s) removed: `q_is,m ⊗ exp(−a_s)`, `a_s`
/// from [`rotation_rad`]. The norm and the sign of `measured_q_is` are kept.
///
/// # Errors
/// As [`rotation_rad`].
///
/// # Examples
/// ```
/// use nalgebra::{Quaternion, Vector3};
/// use nav_core::aberration::{correct, SPEED_OF_LIGHT_MPS};
/// // Boresight along inertial z, moving along inertial x at 7.5 km/s: the tracker's frame
/// // is turned about y by −v/c (5.2″); the correction turns it back (to (v/c)², from
/// // taking the measured axes).
/// let measured = nav_core::attitude::exp_rotation_vector(&Vector3::new(
///     0.0,
///     -7500.0 / SPEED_OF_LIGHT_MPS,
///     0.0,
/// ));
/// let corrected = correct(&measured, &Vector3::new(7500.0, 0.0, 0.0)).unwrap();
/// assert!(corrected.imag().norm() < 1e-9);
/// assert!(correct(&measured, &Vector3::new(f64::NAN, 0.0, 0.0)).is_err());
/// ```
pub fn correct(
    measured_q_is: &Quaternion<f64>,
    velocity_mps: &Vector3<f64>,
) -> Result<Quaternion<f64>, NavError> {
    let rotation = rotation_rad(measured_q_is, velocity_mps)?;
    Ok(product(measured_q_is, &exp_rotation_vector(&-rotation)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::{conjugate, log_rotation_vector, rotate};

    /// Unit direction from spherical angles about the sensor boresight `z`: `off` from it,
    /// `azimuth` about it (rad).
    fn sensor_direction(off: f64, azimuth: f64) -> Vector3<f64> {
        Vector3::new(
            off.sin() * azimuth.cos(),
            off.sin() * azimuth.sin(),
            off.cos(),
        )
    }

    /// A tracker's frame fitted to observed stars: the rotation `r` (sensor axes, small)
    /// minimising `Σ |u_k − C_is exp(r) s_k|²` to first order, with `u_k` the catalogue
    /// directions and `s_k` the observed ones (sensor axes): `Σ [s_k×]ᵀ[s_k×] r = Σ s_k × d_k`,
    /// `d_k = C_si u_k − s_k`. One Gauss–Newton step from the true frame, exact to O(β²).
    fn fitted_rotation(
        q_is: &Quaternion<f64>,
        catalogue: &[Vector3<f64>],
        beta: &Vector3<f64>,
    ) -> Vector3<f64> {
        let q_si = conjugate(q_is);
        let mut normal = nalgebra::Matrix3::zeros();
        let mut right = Vector3::zeros();
        for u in catalogue {
            let apparent = (u + beta).normalize();
            let observed = rotate(&q_si, &apparent);
            let difference = rotate(&q_si, u) - observed;
            let cross = crate::attitude::skew(&observed);
            normal += cross.transpose() * cross;
            right += observed.cross(&difference);
        }
        normal.try_inverse().unwrap() * right
    }

    /// The nonlinear check of the sign and size: stars in a 10° field, symmetric about the
    /// boresight, displaced by the exact (non-linearised) aberration formula, give a fitted
    /// tracker frame turned by [`rotation_rad`] to within 2e-4 of `|β|`; [`correct`] then
    /// returns the true attitude.
    #[test]
    fn the_fitted_tracker_frame_is_turned_by_the_aberration_rotation() {
        let q_is = exp_rotation_vector(&Vector3::new(0.4, -1.1, 2.0));
        for velocity in [
            Vector3::new(7500.0, 0.0, 0.0),
            Vector3::new(-3000.0, 6500.0, 2500.0),
            Vector3::new(0.0, 0.0, 11_000.0),
            Vector3::new(1200.0, -7000.0, -900.0),
        ] {
            let beta = velocity / SPEED_OF_LIGHT_MPS;
            let mut catalogue = [Vector3::zeros(); 9];
            catalogue[0] = rotate(&q_is, &Vector3::z());
            for (k, star) in catalogue.iter_mut().enumerate().skip(1) {
                let azimuth = core::f64::consts::PI * 0.25 * (k as f64);
                *star = rotate(&q_is, &sensor_direction(5.0_f64.to_radians(), azimuth));
            }
            let fitted = fitted_rotation(&q_is, &catalogue, &beta);
            let model = rotation_rad(&q_is, &velocity).unwrap();
            assert!(
                (fitted - model).norm() < 2e-4 * beta.norm(),
                "{fitted:?} {model:?}"
            );
            // The rotation is across the boresight and nonzero unless v is along it.
            assert_eq!(model.z.to_bits(), 0.0_f64.to_bits());
            let measured = product(&q_is, &exp_rotation_vector(&fitted));
            let corrected = correct(&measured, &velocity).unwrap();
            let left = log_rotation_vector(&product(&conjugate(&q_is), &corrected));
            assert!(left.norm() < 2e-4 * beta.norm() + 1e-15, "{left:?}");
            // Uncorrected, the error is the aberration itself.
            let uncorrected = log_rotation_vector(&product(&conjugate(&q_is), &measured));
            assert!((uncorrected.norm() - model.norm()).abs() < 2e-4 * beta.norm());
        }
    }

    /// A field whose stars' centroid lies `ρ_c` off the boresight is turned by the model's
    /// rotation to within `ρ_c |β|` (module docs): here 3° off, a 0.053 fraction of `|β|`.
    #[test]
    fn an_asymmetric_field_departs_by_at_most_its_centroid_offset() {
        let q_is = exp_rotation_vector(&Vector3::new(-0.3, 0.2, 0.9));
        let velocity = Vector3::new(5000.0, -4000.0, 3000.0);
        let beta = velocity / SPEED_OF_LIGHT_MPS;
        let catalogue = [(3.0, 0.0), (5.0, 0.3), (4.0, -0.4), (0.5, 2.0)]
            .map(|(off, azimuth)| rotate(&q_is, &sensor_direction(f64::to_radians(off), azimuth)));
        let fitted = fitted_rotation(&q_is, &catalogue, &beta);
        let model = rotation_rad(&q_is, &velocity).unwrap();
        let departure = (fitted - model).norm();
        assert!(
            departure < 3.0_f64.to_radians() * beta.norm(),
            "{departure}"
        );
        // The model is still far better than nothing.
        assert!(departure < 0.1 * model.norm());
    }

    #[test]
    fn bad_inputs_are_refused() {
        let q = Quaternion::identity();
        let v = Vector3::new(7000.0, 0.0, 0.0);
        assert_eq!(
            correct(&q, &Vector3::new(f64::INFINITY, 0.0, 0.0)),
            Err(NavError::NonFiniteInput)
        );
        assert_eq!(
            correct(&Quaternion::new(f64::NAN, 0.0, 0.0, 0.0), &v),
            Err(NavError::NonFiniteInput)
        );
        assert_eq!(
            correct(&Quaternion::new(0.0, 0.0, 0.0, 0.0), &v),
            Err(NavError::DegenerateQuaternion)
        );
        // At rest nothing changes, bit for bit; the sign is kept.
        let measured = -exp_rotation_vector(&Vector3::new(0.1, 0.2, 0.3));
        assert_eq!(correct(&measured, &Vector3::zeros()).unwrap(), measured);
    }
}
