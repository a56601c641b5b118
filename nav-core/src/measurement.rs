//! Measurement residuals and their Jacobians (paper Section 1.3.2, re-derived for the
//! body-frame attitude error; see `docs/guide/model.md` on why the paper's `−C` block
//! becomes a constant here). Each sensor gives a 3-row block so it can update alone.
//!
//! ## Star sensor
//! The sensor measures `q_is = q_ib ⊗ q_bs ⊗ q_ψ ⊗ δq_noise` (paper: `q̂_s = q_s ⊗ q_ψ`),
//! `q_bs` the nominal mounting (sensor to body), `q_ψ` the installation error. The estimate
//! keeps `q̂_ψ`, and the installation-error state `ψ` is the vector part of `δq_ψ` in
//! `q_ψ = q̂_ψ ⊗ δq_ψ` (in open loop `q̂_ψ = 1`, so `ψ = vec(q_ψ)`, the paper's state).
//! Predicted `q̂_is = q̂_ib ⊗ M`, `M = q_bs ⊗ q̂_ψ`. Residual
//! `z = vec(canonical(q̂_is* ⊗ q_is))`. With `q_ib = q̂_ib ⊗ δq`:
//! `q̂_is* ⊗ q_is = (M* ⊗ δq ⊗ M) ⊗ δq_ψ ⊗ δq_noise`, whose vector part is, to first order,
//! `R(M)ᵀ ϑ + ψ + ν/2` (a quaternion sandwich rotates the vector part; small quaternions'
//! vector parts add). So `H_attitude = R(M)ᵀ = C_sb` and `H_installation = I`, both constant
//! for a body-fixed sensor, and the noise of the vector part is half the angle noise:
//! a small rotation by angle `α` has vector part `sin(α/2) ≈ α/2` per axis, so a 1σ of
//! `σ_angle` (10″ in the paper) gives `σ_z = σ_angle/2` and `R = (σ_angle/2)² I`.
//! `ν` is the sensor's own error rotation, so its vector part is in sensor axes and a
//! sensor noisier about its boresight (sensor `z`) than across it has the diagonal
//! `R = diag((σ_x/2)², (σ_y/2)², (σ_z/2)²)` in the same axes as the residual.
//!
//! **Departure from the paper.** The paper prints `H = [I … −C' …]`, a time-varying
//! installation block. That form belongs to an attitude error expressed in the inertial frame
//! (left error `q = δq ⊗ q̂`), where moving a body-fixed misalignment to the left of `q̂_ib`
//! rotates it by the current attitude. The paper's own attitude dynamics (eq. 7, the
//! `−[ω×]δq` term) are those of a body-frame (right) error, which this crate uses
//! consistently; with it both the attitude and the installation errors sit to the right of
//! `q̂_ib`, and the installation block is the constant `I` (attitude block the constant
//! `C_sb`). Attitude and installation error are then separated by the dynamics, not by `H`:
//! rotation makes `−[ω̂×]ϑ` act on `ϑ` only, acceleration couples `ϑ` into `δv` via
//! `−2Ĉ[f̂×]` (see `docs/guide/model.md`). The tests prove `H` against the nonlinear
//! residual, which the paper's `−C` would fail.
//!
//! ## GNSS
//! The antenna is at `p + C ℓ` (`ℓ` lever arm in body axes). Residual
//! `z = p_gnss − p̂ − Ĉ ℓ = δp + (C − Ĉ) ℓ = δp + 2 Ĉ [ϑ×] ℓ = δp − 2 Ĉ [ℓ×] ϑ`, so
//! `H_position = I`, `H_attitude = −2 Ĉ [ℓ×]`.
//!
//! ## GNSS velocity
//! The antenna moves at `v + C (ω × ℓ)` (`ω` the true body rate). The receiver's ECEF
//! velocity `v_e` becomes launch-inertial as `C R_k(θ) v_e + Ω × (p_a − c)`
//! ([`crate::frames::EarthRotation`]), the Earth-rotation term at the antenna's position
//! `p_a`. The fix's own position would carry its correlated error `ε` (8 m for a 10 m
//! receiver) into the velocity as `Ω × ε`, 6e-4 m/s correlated over minutes, which the
//! white Doppler noise model does not cover; over a long flight it makes the accelerometer
//! states overconfident (`docs/guide/upper-stage.md`). The term takes the estimated antenna
//! position `p̂_a = p̂ + Ĉ ℓ` instead, whose error `p_a − p̂_a = δp − 2 Ĉ [ℓ×] ϑ` is in the
//! state. With `u = ω̂ × ℓ`, residual
//! `z = C R_k(θ) v_e + Ω × (p̂_a − c) − v̂ − Ĉ u
//!    = δv + (C − Ĉ) u + Ĉ (δω × ℓ) − Ω × (δp − 2 Ĉ [ℓ×] ϑ)` to first order, where
//! `(C − Ĉ) u = −2 Ĉ [u×] ϑ` as above and `δω = ω − ω̂ = −δb_g − diag(ω_m) δλ_g`
//! (`ω = ω_m − diag(ω_m) λ_g − b_g`, [`crate::error_model`]), so
//! `Ĉ (δω × ℓ) = Ĉ [ℓ×] (δb_g + diag(ω_m) δλ_g)`:
//! `H_velocity = I`, `H_position = −[Ω×]`, `H_attitude = −2 Ĉ [u×] + 2 [Ω×] Ĉ [ℓ×]`,
//! `H_gyro_bias = Ĉ [ℓ×]`, `H_gyro_scale = Ĉ [ℓ×] diag(ω_m)`. The receiver's velocity
//! error is white (Doppler).

use nalgebra::{ArrayStorage, Matrix3, Quaternion, SMatrix, Vector3};

use crate::attitude::{all_finite3, canonical, conjugate, product, rotation_matrix, skew};
use crate::error_model::set_block;
use crate::frames::EarthRotation;
use crate::state::{
    ATTITUDE, GYRO_BIAS, GYRO_SCALE_FACTOR, POSITION, STAR_INSTALLATION, STATE_DIMENSION, VELOCITY,
};
use crate::NavError;

/// The three rows of a 3-component measurement (for block writes into `H`).
const MEASUREMENT_ROWS: usize = 0;

/// A 3×24 measurement Jacobian block.
pub type MeasurementJacobian = SMatrix<f64, 3, STATE_DIMENSION>;

/// A linearised 3-component measurement: residual (measured − predicted), `H` and `R`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearMeasurement {
    /// Residual `z` (measured minus predicted), in the measurement's units.
    pub residual: Vector3<f64>,
    /// Jacobian `H` of the residual with respect to the error state.
    pub jacobian: MeasurementJacobian,
    /// Measurement noise covariance `R`.
    pub noise_covariance: Matrix3<f64>,
    /// `h_ε`, the residual's coefficient of the optional block a measurement sees directly
    /// (the measured border: the receiver's correlated position error): 1 for a GNSS
    /// position fix, 0 for every other measurement (read only when the filter carries that
    /// block).
    pub border_coefficient: f64,
}

fn quaternion_is_finite(q: &Quaternion<f64>) -> bool {
    q.coords.iter().all(|c| c.is_finite())
}

/// Star-sensor attitude measurement (module docs for the derivation).
///
/// * `attitude`: estimated `q̂_ib`; `mounting`: nominal `q_bs`; `installation_estimate`: `q̂_ψ`;
/// * `measured`: the sensor's `q_is` (unit, any sign);
/// * `noise_angle_rad`: 1σ angle noise about each sensor axis `[x, y, z]`, `z` the
///   boresight (10″ on every axis in the paper);
///   `R = diag((σ_x/2)², (σ_y/2)², (σ_z/2)²)` in sensor axes, the residual's axes.
///
/// # Errors
/// [`NavError::NonFiniteInput`] for NaN/Inf in any input or a negative noise.
pub fn star_sensor(
    attitude: &Quaternion<f64>,
    mounting: &Quaternion<f64>,
    installation_estimate: &Quaternion<f64>,
    measured: &Quaternion<f64>,
    noise_angle_rad: &[f64; 3],
) -> Result<LinearMeasurement, NavError> {
    let inputs_finite = [attitude, mounting, installation_estimate, measured]
        .iter()
        .all(|q| quaternion_is_finite(q));
    let noise_valid = noise_angle_rad
        .iter()
        .all(|sigma| sigma.is_finite() && *sigma >= 0.0);
    if !(inputs_finite && noise_valid) {
        return Err(NavError::NonFiniteInput);
    }
    let sensor_to_body = product(mounting, installation_estimate);
    let predicted = product(attitude, &sensor_to_body);
    let difference = canonical(&product(&conjugate(&predicted), measured));
    let mut jacobian = MeasurementJacobian::zeros();
    set_block(
        &mut jacobian,
        MEASUREMENT_ROWS,
        ATTITUDE,
        &rotation_matrix(&sensor_to_body).transpose(),
    );
    set_block(
        &mut jacobian,
        MEASUREMENT_ROWS,
        STAR_INSTALLATION,
        &Matrix3::identity(),
    );
    // Per element the arithmetic of the former `I · (σ/2)²`: the diagonal is `(0.5 σ)²`,
    // the rest exact zeros, so equal sigmas give the isotropic bits.
    let half_sigma = noise_angle_rad.map(|sigma| 0.5 * sigma);
    let variance = half_sigma.map(|half| half * half);
    Ok(LinearMeasurement {
        residual: difference.imag(),
        jacobian,
        noise_covariance: Matrix3::from_diagonal(&Vector3::from(variance)),
        border_coefficient: 0.0,
    })
}

/// GNSS position measurement in the launch-inertial frame (module docs for the derivation).
///
/// * `attitude` `q̂_ib`, `position_m` `p̂` (IMU position), `lever_arm_body_m` `ℓ`;
/// * `measured_position_m`: the fix converted to the launch-inertial frame (`frames`);
/// * `noise_m`: 1σ per axis (10 m in the paper); `R = σ² I`.
///
/// # Errors
/// [`NavError::NonFiniteInput`] for NaN/Inf in any input or a negative noise.
pub fn gnss_position(
    attitude: &Quaternion<f64>,
    position_m: &Vector3<f64>,
    lever_arm_body_m: &Vector3<f64>,
    measured_position_m: &Vector3<f64>,
    noise_m: f64,
) -> Result<LinearMeasurement, NavError> {
    let inputs_finite = quaternion_is_finite(attitude)
        && all_finite3(position_m)
        && all_finite3(lever_arm_body_m)
        && all_finite3(measured_position_m);
    if !(inputs_finite && noise_m.is_finite() && noise_m >= 0.0) {
        return Err(NavError::NonFiniteInput);
    }
    let body_to_inertial = rotation_matrix(attitude);
    let predicted = position_m + body_to_inertial * lever_arm_body_m;
    let row = MEASUREMENT_ROWS;
    let mut jacobian = MeasurementJacobian::zeros();
    set_block(&mut jacobian, row, POSITION, &Matrix3::identity());
    set_block(
        &mut jacobian,
        row,
        ATTITUDE,
        &(-2.0 * body_to_inertial * skew(lever_arm_body_m)),
    );
    Ok(LinearMeasurement {
        residual: measured_position_m - predicted,
        jacobian,
        noise_covariance: Matrix3::identity() * (noise_m * noise_m),
        border_coefficient: 1.0,
    })
}

/// The body motion a GNSS velocity measurement needs for its lever-arm term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyRate {
    /// Corrected body rate `ω̂` (rad/s).
    pub corrected_rad_s: Vector3<f64>,
    /// Measured body rate `ω_m` (rad/s), which the gyro scale factor multiplies.
    pub measured_rad_s: Vector3<f64>,
}

/// A receiver velocity in the two parts of its conversion to the launch-inertial frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GnssVelocityFix {
    /// The ECEF velocity turned into launch-inertial axes, `C R_k(θ) v_e` (m/s,
    /// [`crate::frames::LaunchFrame::ecef_velocity_to_launch_axes`]).
    pub turned_velocity_mps: Vector3<f64>,
    /// The Earth's rotation, whose velocity term [`gnss_velocity`] adds at the estimated
    /// antenna position.
    pub earth: EarthRotation,
}

/// GNSS velocity measurement in the launch-inertial frame (module docs for the derivation).
///
/// * `attitude` `q̂_ib`, `position_m` `p̂` and `velocity_mps` `v̂` (IMU), `lever_arm_body_m`
///   `ℓ`, `rate` the body rates;
/// * `fix`: the receiver's velocity, turned into launch-inertial axes;
/// * `noise_mps`: 1σ per axis; `R = σ² I`.
///
/// # Errors
/// [`NavError::NonFiniteInput`] for NaN/Inf in any input or a negative noise.
///
/// # Examples
/// ```
/// use nalgebra::{Quaternion, Vector3};
/// use nav_core::frames::EarthRotation;
/// use nav_core::measurement::{gnss_velocity, BodyRate, GnssVelocityFix};
/// let earth = EarthRotation {
///     rate_launch_rad_s: Vector3::new(0.0, 7.292115e-5, 0.0),
///     centre_launch_m: Vector3::new(0.0, -6.4e6, 0.0),
/// };
/// let (position, velocity) = (Vector3::new(0.0, 5.0e5, 0.0), Vector3::new(7600.0, 0.0, 0.0));
/// // A receiver that sees the estimated motion: its ECEF velocity, turned into launch
/// // axes, is the inertial velocity less the Earth's rotation at the antenna.
/// let turned_velocity_mps = velocity - earth.velocity_at(&position);
/// let fix = GnssVelocityFix { turned_velocity_mps, earth };
/// let rate = BodyRate { corrected_rad_s: Vector3::zeros(), measured_rad_s: Vector3::zeros() };
/// let (attitude, no_lever_arm) = (Quaternion::identity(), Vector3::zeros());
/// let m = gnss_velocity(&attitude, &position, &velocity, &no_lever_arm, &rate, &fix, 0.05)
///     .unwrap();
/// assert!(m.residual.norm() < 1e-9);
/// // The position error moves the Earth-rotation term: H_position = −[Ω×].
/// assert!((m.jacobian[(2, 3)] - 7.292115e-5).abs() < 1e-15);
/// ```
#[inline(never)]
pub fn gnss_velocity(
    attitude: &Quaternion<f64>,
    position_m: &Vector3<f64>,
    velocity_mps: &Vector3<f64>,
    lever_arm_body_m: &Vector3<f64>,
    rate: &BodyRate,
    fix: &GnssVelocityFix,
    noise_mps: f64,
) -> Result<LinearMeasurement, NavError> {
    let inputs_finite = quaternion_is_finite(attitude)
        && all_finite3(position_m)
        && all_finite3(velocity_mps)
        && all_finite3(lever_arm_body_m)
        && all_finite3(&rate.corrected_rad_s)
        && all_finite3(&rate.measured_rad_s)
        && all_finite3(&fix.turned_velocity_mps)
        && all_finite3(&fix.earth.rate_launch_rad_s)
        && all_finite3(&fix.earth.centre_launch_m);
    if !(inputs_finite && noise_mps.is_finite() && noise_mps >= 0.0) {
        return Err(NavError::NonFiniteInput);
    }
    let body_to_inertial = rotation_matrix(attitude);
    let antenna_position = position_m + body_to_inertial * lever_arm_body_m;
    let measured = fix.turned_velocity_mps + fix.earth.velocity_at(&antenna_position);
    let lever_velocity = rate.corrected_rad_s.cross(lever_arm_body_m);
    let predicted = velocity_mps + body_to_inertial * lever_velocity;
    let lever = body_to_inertial * skew(lever_arm_body_m);
    let earth_rate = skew(&fix.earth.rate_launch_rad_s);
    let attitude_block = (earth_rate * lever - body_to_inertial * skew(&lever_velocity)) * 2.0;
    let scale_block = lever * Matrix3::from_diagonal(&rate.measured_rad_s);
    Ok(LinearMeasurement {
        residual: measured - predicted,
        jacobian: velocity_jacobian(&attitude_block, &-earth_rate, &lever, &scale_block),
        noise_covariance: Matrix3::identity() * (noise_mps * noise_mps),
        border_coefficient: 0.0,
    })
}

/// The GNSS velocity's `H` (module docs) from its blocks `H_attitude`, `H_position`,
/// `H_gyro_bias` and `H_gyro_scale` (`H_velocity = I`), as one expression of its 24 columns
/// (nalgebra stores columns), in [`gnss_velocity`], which is not inlined: LLVM then writes
/// most of it into the caller's result directly, where a zero-filled `H` written by blocks,
/// or this one inlined into the scheduler, is assembled in a temporary and copied.
#[inline(always)]
fn velocity_jacobian(
    attitude: &Matrix3<f64>,
    position: &Matrix3<f64>,
    gyro_bias: &Matrix3<f64>,
    gyro_scale: &Matrix3<f64>,
) -> MeasurementJacobian {
    // The column positions below are those of the state layout.
    const _: () = assert!(
        ATTITUDE.index() == 0
            && POSITION.index() == 3
            && VELOCITY.index() == 6
            && GYRO_BIAS.index() == 9
            && GYRO_SCALE_FACTOR.index() == 18
            && STATE_DIMENSION == 24
    );
    let [a0, a1, a2] = attitude.data.0;
    let [p0, p1, p2] = position.data.0;
    let [b0, b1, b2] = gyro_bias.data.0;
    let [s0, s1, s2] = gyro_scale.data.0;
    let z = [0.0; 3];
    let [v0, v1, v2] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    MeasurementJacobian::from_data(ArrayStorage([
        a0, a1, a2, p0, p1, p2, v0, v1, v2, b0, b1, b2, z, z, z, z, z, z, s0, s1, s2, z, z, z,
    ]))
}

/// Refers a measurement whose time of validity `t_m` lies `latency_s` before the filter's
/// time `t` to the filter's current error state.
///
/// The measurement relates to the error at its own time, `z = H x(t_m) + v`. Over the
/// latency the error evolves as `ẋ = A x + G w`, so `x(t_m) = Φ(t_m, t) x(t) + (noise)` with
/// `Φ(t_m, t) = Φ(t, t_m)⁻¹ = I − A Δ + O(Δ²)` (`Δ = t − t_m`, `A` = nav-core's
/// [`crate::error_model::system_matrix`] at the current motion), hence `H' = H (I − A Δ)`.
/// The neglected `O(Δ²)` terms are `(A Δ)²/2`: at 100 °/s and Δ = 0.1 s, 1.5e-2 relative on
/// the attitude-error rotation; the process noise over the latency is neglected likewise
/// (it is below 1e-9 rad for the paper's gyro). Without this, a 50 ms-late star measurement
/// during a 100 °/s rotation compares the attitude error of a body frame 5° away from the
/// current one and biases the installation estimate (measured: 5.8σ).
///
/// # Errors
/// [`NavError::InvalidTimeStep`] for a negative or non-finite latency,
/// [`NavError::NonFiniteInput`] for a non-finite `A`.
#[cfg(any(test, feature = "dense-reference"))]
pub fn refer_to_later_time(
    measurement: &LinearMeasurement,
    system: &crate::error_model::SystemMatrix,
    latency_s: f64,
) -> Result<LinearMeasurement, NavError> {
    if !(latency_s.is_finite() && latency_s >= 0.0) {
        return Err(NavError::InvalidTimeStep);
    }
    if !system.iter().all(|v| v.is_finite()) {
        return Err(NavError::NonFiniteInput);
    }
    let jacobian = measurement.jacobian - (measurement.jacobian * system) * latency_s;
    Ok(LinearMeasurement {
        jacobian,
        ..*measurement
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::{exp_rotation_vector, from_vector_part};
    use crate::error_model::tests::{assert_second_order, estimate, perturbed};
    use crate::state::StateBlock;
    use nalgebra::SVector;

    fn mounting() -> Quaternion<f64> {
        exp_rotation_vector(&Vector3::new(0.4, -1.1, 0.25))
    }
    fn installation_estimate() -> Quaternion<f64> {
        exp_rotation_vector(&Vector3::new(2e-3, -1e-3, 3e-3))
    }
    const LEVER_ARM: Vector3<f64> = Vector3::new(1.5, -0.4, 2.0);

    /// The measurement a perfect sensor would give for the truth `estimate ⊕ error`.
    fn star_truth(error: &SVector<f64, 24>) -> Quaternion<f64> {
        let truth = perturbed(&estimate(), error);
        let psi: Vector3<f64> = error.fixed_rows::<3>(STAR_INSTALLATION.index()).into();
        let installation = product(&installation_estimate(), &from_vector_part(&psi).unwrap());
        // Sign deliberately flipped: the residual must not care.
        -product(&product(&truth.attitude, &mounting()), &installation)
    }

    fn scale(block: crate::state::StateBlock) -> f64 {
        if block == POSITION {
            10.0
        } else {
            1e-3
        }
    }

    #[test]
    fn star_jacobian_predicts_the_nonlinear_residual_to_second_order() {
        let est = estimate();
        for block in [ATTITUDE, STAR_INSTALLATION] {
            assert_second_order(block, scale(block), |error| {
                let m = star_sensor(
                    &est.attitude,
                    &mounting(),
                    &installation_estimate(),
                    &star_truth(error),
                    &[0.0; 3],
                )
                .unwrap();
                (m.residual, m.jacobian * error)
            });
        }
        // Blocks outside attitude and installation do not move the star residual.
        let m = star_sensor(
            &est.attitude,
            &mounting(),
            &installation_estimate(),
            &star_truth(&SVector::zeros()),
            &[0.0; 3],
        )
        .unwrap();
        assert!(m.residual.amax() < 1e-15);
        for block in StateBlock::ALL {
            if block != ATTITUDE && block != STAR_INSTALLATION {
                assert_eq!(
                    m.jacobian
                        .fixed_columns::<3>(block.index())
                        .amax()
                        .to_bits(),
                    0.0f64.to_bits()
                );
            }
        }
    }

    #[test]
    fn gnss_jacobian_predicts_the_nonlinear_residual_to_second_order() {
        let est = estimate();
        for block in [ATTITUDE, POSITION] {
            assert_second_order(block, scale(block), |error| {
                let truth = perturbed(&est, error);
                let antenna = truth.position + rotation_matrix(&truth.attitude) * LEVER_ARM;
                let m = gnss_position(&est.attitude, &est.position, &LEVER_ARM, &antenna, 10.0)
                    .unwrap();
                (m.residual, m.jacobian * error)
            });
        }
    }

    /// An Earth turning far faster than the real one (rad/s), so that its terms weigh in
    /// the test as much as the lever arm's, with its centre 2 km from the estimate so that
    /// the Earth-rotation velocity stays small enough for round-off not to hide them.
    fn earth() -> EarthRotation {
        EarthRotation {
            rate_launch_rad_s: Vector3::new(0.02, -0.05, 0.03),
            centre_launch_m: estimate().position + Vector3::new(100.0, -2.0e3, 300.0),
        }
    }

    /// The receiver's velocity for the truth `estimate ⊕ error`, turned into launch-inertial
    /// axes: the antenna's inertial velocity less the Earth's rotation at its true position.
    fn turned_velocity(
        error: &SVector<f64, 24>,
        true_rate: impl Fn(&crate::error_model::tests::Hypothesis) -> Vector3<f64>,
    ) -> GnssVelocityFix {
        let truth = perturbed(&estimate(), error);
        let body_to_inertial = rotation_matrix(&truth.attitude);
        let antenna_velocity =
            truth.velocity + body_to_inertial * true_rate(&truth).cross(&LEVER_ARM);
        let antenna_position = truth.position + body_to_inertial * LEVER_ARM;
        GnssVelocityFix {
            turned_velocity_mps: antenna_velocity - earth().velocity_at(&antenna_position),
            earth: earth(),
        }
    }

    #[test]
    fn gnss_velocity_jacobian_predicts_the_nonlinear_residual_to_second_order() {
        use crate::error_model::tests::MEASURED_RATE;
        let est = estimate();
        let true_rate = |h: &crate::error_model::tests::Hypothesis| {
            MEASURED_RATE - MEASURED_RATE.component_mul(&h.gyro_scale) - h.gyro_bias
        };
        let rate = BodyRate {
            corrected_rad_s: true_rate(&est),
            measured_rad_s: MEASURED_RATE,
        };
        let measure = |fix: &GnssVelocityFix, noise_mps: f64| {
            gnss_velocity(
                &est.attitude,
                &est.position,
                &est.velocity,
                &LEVER_ARM,
                &rate,
                fix,
                noise_mps,
            )
        };
        for block in [ATTITUDE, POSITION, VELOCITY, GYRO_BIAS, GYRO_SCALE_FACTOR] {
            assert_second_order(block, scale(block), |error| {
                let m = measure(&turned_velocity(error, true_rate), 0.05).unwrap();
                (m.residual, m.jacobian * error)
            });
        }
        let exact = turned_velocity(&SVector::zeros(), true_rate);
        let m = measure(&exact, 0.05).unwrap();
        assert!(m.residual.amax() < 1e-9, "{}", m.residual.amax());
        assert!((m.noise_covariance[(0, 0)] - 0.0025).abs() < 1e-15);
        assert_eq!(m.border_coefficient.to_bits(), 0.0f64.to_bits());
        assert_eq!(
            m.jacobian
                .fixed_columns::<3>(STAR_INSTALLATION.index())
                .amax()
                .to_bits(),
            0.0f64.to_bits()
        );
        let bad = Vector3::new(f64::NAN, 0.0, 0.0);
        for fix in [
            GnssVelocityFix {
                turned_velocity_mps: bad,
                ..exact
            },
            GnssVelocityFix {
                earth: EarthRotation {
                    rate_launch_rad_s: bad,
                    ..earth()
                },
                ..exact
            },
        ] {
            assert_eq!(measure(&fix, 0.05), Err(NavError::NonFiniteInput));
        }
        assert_eq!(measure(&exact, -1.0), Err(NavError::NonFiniteInput));
    }

    /// The star measurement of a sensor that sees exactly the estimated attitude.
    fn star_at_estimate(noise_rad: f64) -> LinearMeasurement {
        let est = estimate();
        star_sensor(
            &est.attitude,
            &mounting(),
            &installation_estimate(),
            &est.attitude,
            &[noise_rad; 3],
        )
        .unwrap()
    }

    #[test]
    fn noise_covariances_and_bad_inputs() {
        let est = estimate();
        let arcsec = core::f64::consts::PI / 180.0 / 3600.0;
        let m = star_at_estimate(10.0 * arcsec);
        assert!((m.noise_covariance[(0, 0)] - (5.0 * arcsec).powi(2)).abs() < 1e-25);
        let nan = Quaternion::new(f64::NAN, 0.0, 0.0, 0.0);
        assert_eq!(
            star_sensor(
                &nan,
                &mounting(),
                &installation_estimate(),
                &est.attitude,
                &[1e-5; 3]
            ),
            Err(NavError::NonFiniteInput)
        );
        for bad in [-1e-5, f64::NAN, f64::INFINITY] {
            assert_eq!(
                star_sensor(
                    &est.attitude,
                    &mounting(),
                    &installation_estimate(),
                    &est.attitude,
                    &[1e-5, 1e-5, bad]
                ),
                Err(NavError::NonFiniteInput),
                "{bad}"
            );
        }
        assert_eq!(
            gnss_position(
                &est.attitude,
                &est.position,
                &LEVER_ARM,
                &Vector3::new(f64::INFINITY, 0.0, 0.0),
                10.0
            ),
            Err(NavError::NonFiniteInput)
        );
    }

    /// The residual is in sensor axes: a small rotation of the measured attitude about
    /// sensor `z` (the boresight) lands, as the half angle, in residual component `z` alone
    /// (and likewise for `x`, `y`), so `R = diag((σ_x/2)², (σ_y/2)², (σ_z/2)²)` weights the
    /// axis each sigma is for; equal sigmas give the former `I · (σ/2)²` bit for bit.
    #[test]
    fn star_noise_is_per_sensor_axis() {
        let est = estimate();
        let arcsec = core::f64::consts::PI / 180.0 / 3600.0;
        let sensor_to_body = product(&mounting(), &installation_estimate());
        let sensor_attitude = product(&est.attitude, &sensor_to_body);
        let sigmas = [5.0 * arcsec, 7.0 * arcsec, 35.0 * arcsec];
        let angle_rad = 1e-6;
        for axis in 0..3 {
            let rotation = exp_rotation_vector(&Vector3::ith(axis, angle_rad));
            let measured = product(&sensor_attitude, &rotation);
            let m = star_sensor(
                &est.attitude,
                &mounting(),
                &installation_estimate(),
                &measured,
                &sigmas,
            )
            .unwrap();
            let expected = Vector3::ith(axis, 0.5 * angle_rad);
            assert!((m.residual - expected).amax() < 1e-15, "{axis}: {m:?}");
            let half = 0.5 * sigmas[axis];
            assert_eq!(
                m.noise_covariance[(axis, axis)].to_bits(),
                (half * half).to_bits()
            );
        }
        let m = star_at_estimate(35.0 * arcsec);
        let anisotropic = star_sensor(
            &est.attitude,
            &mounting(),
            &installation_estimate(),
            &est.attitude,
            &sigmas,
        )
        .unwrap();
        assert_eq!(
            anisotropic.noise_covariance
                - Matrix3::from_diagonal(&anisotropic.noise_covariance.diagonal()),
            Matrix3::zeros()
        );
        for sigma in [0.0, 1e-9, 10.0 * arcsec, 35.0 * arcsec, 0.3] {
            let half_sigma = 0.5 * sigma;
            let isotropic: Matrix3<f64> = Matrix3::identity() * (half_sigma * half_sigma);
            let per_axis = star_at_estimate(sigma).noise_covariance;
            for (a, b) in per_axis.iter().zip(isotropic.iter()) {
                assert_eq!(a.to_bits(), b.to_bits(), "{sigma}");
            }
        }
        assert_eq!(m.residual, anisotropic.residual);
    }

    /// `H' = H (I − A Δ)`: zero latency leaves `H` unchanged, a positive latency subtracts
    /// `H A Δ` exactly; a negative or non-finite latency and a non-finite `A` are refused.
    #[test]
    fn refer_to_later_time_formula_and_refusals() {
        let est = estimate();
        let arcsec = core::f64::consts::PI / 180.0 / 3600.0;
        let m = star_at_estimate(10.0 * arcsec);
        let system =
            crate::error_model::system_matrix(&crate::error_model::tests::linearisation(&est));
        let same = refer_to_later_time(&m, &system, 0.0).unwrap();
        assert_eq!(same.jacobian, m.jacobian);
        let latency = 0.05;
        let later = refer_to_later_time(&m, &system, latency).unwrap();
        let expected = m.jacobian - m.jacobian * system * latency;
        assert!((later.jacobian - expected).amax() <= 1e-15 * expected.amax());
        assert!((later.jacobian - m.jacobian).amax() > 0.0);
        assert_eq!(later.residual, m.residual);
        assert_eq!(later.noise_covariance, m.noise_covariance);
        for bad in [-1.0e-3, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(
                refer_to_later_time(&m, &system, bad),
                Err(NavError::InvalidTimeStep),
                "{bad}"
            );
        }
        let mut non_finite = system;
        non_finite[(3, 5)] = f64::NAN;
        assert_eq!(
            refer_to_later_time(&m, &non_finite, latency),
            Err(NavError::NonFiniteInput)
        );
    }
}
