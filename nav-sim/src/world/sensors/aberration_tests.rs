//! Unit tests of the star tracker's velocity aberration (`[star_sensor] aberration`): the
//! sign and size of the rotation against star directions displaced by the nonlinear
//! aberration formula, its place in the sample stream, and the flight code's correction.

use super::star_errors_tests::star_residuals;
use super::tests::{events_digest, every_frame_scenario, run};
use super::*;
use crate::scenario::StarAberration;
use nav_core::aberration::SPEED_OF_LIGHT_MPS;
use nav_core::attitude::{canonical, exp_rotation_vector, log_rotation_vector};

/// The attitude `q_is` a tracker fits to stars: the catalogue directions `catalogue`
/// (inertial), seen from a vehicle at `velocity_mps` at `u' = (u + β)/|u + β|` (the
/// aberration formula before any linearisation) in the true sensor frame `q_is`; the fit is
/// Wahba's problem solved by the SVD (Markley, "Attitude determination using vector
/// observations and the singular value decomposition", J. Astronaut. Sci. 36(3), 1988):
/// `B = Σ u_k s_kᵀ = U S Vᵀ`, `C_is = U diag(1, 1, det U det V) Vᵀ`.
fn fitted_tracker_attitude(
    q_is: &Quaternion<f64>,
    catalogue: &[Vector3<f64>],
    velocity_mps: &Vector3<f64>,
) -> Quaternion<f64> {
    let beta = velocity_mps / SPEED_OF_LIGHT_MPS;
    let true_frame = nalgebra::UnitQuaternion::from_quaternion(*q_is);
    let mut profile = Matrix3::zeros();
    for u in catalogue {
        let observed = true_frame.inverse_transform_vector(&(u + beta).normalize());
        profile += u * observed.transpose();
    }
    let svd = profile.svd(true, true);
    let (u, v_t) = (svd.u.unwrap(), svd.v_t.unwrap());
    let sign = u.determinant() * v_t.determinant();
    let c_is = u * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, sign)) * v_t;
    let rotation = nalgebra::Rotation3::from_matrix_unchecked(c_is);
    *nalgebra::UnitQuaternion::from_rotation_matrix(&rotation).quaternion()
}

/// Nine stars (inertial) in a field of 5° radius symmetric about the boresight of `q_is`.
fn symmetric_field(q_is: &Quaternion<f64>) -> Vec<Vector3<f64>> {
    let frame = nalgebra::UnitQuaternion::from_quaternion(*q_is);
    let off = 5.0_f64.to_radians();
    let mut stars = vec![frame * Vector3::z()];
    for k in 0..8 {
        let azimuth = std::f64::consts::FRAC_PI_4 * f64::from(k);
        let sensor = Vector3::new(
            off.sin() * azimuth.cos(),
            off.sin() * azimuth.sin(),
            off.cos(),
        );
        stars.push(frame * sensor);
    }
    stars
}

/// The sign and size: for several attitudes and velocities, the tracker's fitted frame is
/// the true one turned by `a_s = β_s × z` ([`aberration_rotation_rad`]) to 2e-4 of `|β|`,
/// the stars moving towards the velocity. Moving along sensor +x at 7.5 km/s the rotation
/// is `−β` about sensor y (5.16″).
#[test]
fn the_aberration_rotation_is_the_fitted_trackers_frame() {
    let velocities = [
        Vector3::new(7500.0, 0.0, 0.0),
        Vector3::new(-3000.0, 6500.0, 2500.0),
        Vector3::new(400.0, -11_000.0, 7000.0),
    ];
    for (attitude, velocity) in [
        Vector3::zeros(),
        Vector3::new(0.3, -1.1, 0.4),
        Vector3::new(-2.0, 0.5, 1.2),
    ]
    .iter()
    .flat_map(|a| velocities.iter().map(move |v| (a, v)))
    {
        let q_is = exp_rotation_vector(attitude);
        let fitted = fitted_tracker_attitude(&q_is, &symmetric_field(&q_is), velocity);
        let seen = log_rotation_vector(&canonical(&(q_is.conjugate() * fitted)));
        let model = aberration_rotation_rad(&q_is, velocity);
        let beta = velocity.norm() / SPEED_OF_LIGHT_MPS;
        assert!((seen - model).norm() < 2e-4 * beta, "{seen:?} {model:?}");
        assert!(model.norm() > 0.3 * beta, "{model:?}");
        assert_eq!(model.z.abs().to_bits(), 0, "{model:?}");
    }
    let along_x = aberration_rotation_rad(&Quaternion::identity(), &Vector3::new(7500.0, 0.0, 0.0));
    let arcsec = along_x / 4.848_136_811_095_36e-6;
    assert!(
        (arcsec - Vector3::new(0.0, -5.1602, 0.0)).norm() < 1e-3,
        "{arcsec:?}"
    );
}

/// In the stream: noise-free, each star sample is the installed attitude turned by the
/// rotation of the truth's attitude and velocity; nav-core's correction with that velocity
/// gives the installed attitude back to `|a_s| |β|` (its axes are the measured ones). Without the key the stream is the
/// default's (`"none"` is the default).
#[test]
fn aberration_enters_the_star_samples_and_the_flight_correction_removes_it() {
    let mut scenario = every_frame_scenario();
    scenario.star_sensor.noise_arcsec = 0.0;
    let plain = scenario.clone();
    scenario.star_sensor.aberration = StarAberration::Uncorrected;
    scenario.validate().unwrap();
    let (truths, _) = run(&scenario, 1);
    let errors = SensorSimulator::new(&scenario).unwrap().error_truth();
    let installed =
        truths[0].attitude_q_ib * errors.star_mounting_q_bs * errors.star_installation_q_psi;
    let expected = aberration_rotation_rad(&installed, &truths[0].velocity_mps);
    // 2.2″ here: the synthetic velocity (7 km/s) lies 25° from the boresight.
    assert!(expected.norm() > 2.0 * 4.848e-6, "{expected:?}");
    let residuals = star_residuals(&scenario, 50);
    assert_eq!(residuals.len(), 50);
    for (_, residual) in &residuals {
        assert!((residual - expected).amax() < 1e-12, "{residual:?}");
    }
    let measured = installed * exp_rotation_vector(&expected);
    let corrected = nav_core::aberration::correct(&measured, &truths[0].velocity_mps).unwrap();
    let left = log_rotation_vector(&canonical(&(installed.conjugate() * corrected)));
    // The correction takes `β_s` in the measured axes, turned by `a_s` from the true ones:
    // what is left is `|a_s| |β|`, 2.5e-10 rad here (5e-5″).
    let bound = expected.norm() * truths[0].velocity_mps.norm() / SPEED_OF_LIGHT_MPS;
    assert!(left.norm() < 1.01 * bound, "{left:?} {bound:e}");
    // Absent (or "none") the key stays out of the rendering, so the scenario hash is as before.
    assert!(!format!("{plain:?}").contains("aberration"));
    assert!(format!("{scenario:?}").contains("aberration: Uncorrected"));
    let (_, plain_events) = run(&plain, 100);
    let (_, aberrated_events) = run(&scenario, 100);
    assert_ne!(
        events_digest(&plain_events),
        events_digest(&aberrated_events)
    );
}
