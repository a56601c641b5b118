//! Unit tests of the truth trajectory.

use super::*;

use crate::scenario::Scenario;
use crate::setup::launch::{initial_state, launch_frame, orbit_state_from_elements};
use nav_core::attitude::exp_rotation_vector;
use nav_core::frames::{WGS84_GM_M3_S2, WGS84_J2, WGS84_SEMI_MAJOR_AXIS_M};

const MU_M3_PER_S2: f64 = WGS84_GM_M3_S2;

/// The potential whose gradient is nav-core's point mass + J2 field:
/// `U = −μ/r [1 − J2 (a/r)² P2(s/r)]`, `s = k·r` (k the Earth axis), `P2(x) = (3x² − 1)/2`.
fn j2_potential(gravity: &FlightGravity, position_launch_m: &Vector3<f64>) -> f64 {
    let geocentric = gravity.frame.geocentric_position_launch(position_launch_m);
    let r = geocentric.norm();
    let sin_latitude = gravity.frame.earth_axis_launch().dot(&geocentric) / r;
    let p2 = 0.5 * (3.0 * sin_latitude * sin_latitude - 1.0);
    -MU_M3_PER_S2 / r * (1.0 - WGS84_J2 * (WGS84_SEMI_MAJOR_AXIS_M / r).powi(2) * p2)
}

fn segment(duration_s: f64, ramp_s: f64, rate: [f64; 3], force: [f64; 3]) -> ManoeuvreSegment {
    ManoeuvreSegment {
        label: "test".to_string(),
        duration_s,
        ramp_s,
        body_rate_deg_per_s: rate,
        specific_force_mps2: force,
    }
}

fn profile(segments: &[ManoeuvreSegment], start_time_s: f64) -> CommandProfile {
    let mut start = start_time_s;
    CommandProfile {
        segments: segments
            .iter()
            .map(|manoeuvre| {
                let command = CommandSegment::from_manoeuvre(manoeuvre, start);
                start = command.end_time_s();
                command
            })
            .collect(),
    }
}

fn no_gravity(_: &Vector3<f64>) -> Vector3<f64> {
    Vector3::zeros()
}

#[test]
fn raised_cosine_integral_matches_quadrature_and_closed_total() {
    let (duration_s, ramp_s) = (10.0, 1.5);
    // Midpoint quadrature with 1e5 cells: error ~ h² s''/24 ~ 1e-10.
    let cells = 100_000;
    let h = duration_s / f64::from(cells);
    let mut sum = 0.0;
    for cell in 0..cells {
        let tau = (f64::from(cell) + 0.5) * h;
        sum += raised_cosine_shape(tau, duration_s, ramp_s) * h;
        if cell % 9_973 == 0 {
            let partial = raised_cosine_integral(tau + 0.5 * h, duration_s, ramp_s);
            assert!((partial - sum).abs() < 1e-8, "{tau}: {partial} vs {sum}");
        }
    }
    assert!((sum - (duration_s - ramp_s)).abs() < 1e-8);
    let total = raised_cosine_integral(duration_s, duration_s, ramp_s);
    assert!((total - 8.5).abs() < 1e-14);
    assert!((raised_cosine_shape(0.75, duration_s, ramp_s) - 0.5).abs() < 1e-15);
    assert!(raised_cosine_shape(-0.1, duration_s, ramp_s).abs() < 1e-300);
}

#[test]
fn pure_orbit_conserves_energy_over_one_orbit() {
    // The default scenario's 500 km orbit with nav-core's J2 gravity, no manoeuvre, for one
    // Keplerian period: ½v² + U(r) is an exact invariant (the field is static and
    // axisymmetric in the inertial frame).
    let mut scenario = Scenario::default_scenario().unwrap();
    let semi_major_axis_m = scenario.initial_orbit.semi_major_axis_m;
    let period_s = 2.0 * std::f64::consts::PI * (semi_major_axis_m.powi(3) / MU_M3_PER_S2).sqrt();
    let frame_period_s = scenario.imu.frame_period_s();
    scenario.manoeuvres = vec![segment(
        (period_s / frame_period_s).ceil() * frame_period_s,
        0.0,
        [0.0; 3],
        [0.0; 3],
    )];
    let mut truth = TruthSimulator::from_scenario(&scenario).unwrap();
    let gravity = truth.gravity.flight;
    let initial = *truth.state();
    let energy = |state: &TruthState| {
        0.5 * state.velocity_mps.norm_squared() + j2_potential(&gravity, &state.position_m)
    };
    let initial_energy = energy(&initial);
    let mut worst_relative = 0.0_f64;
    let mut last = initial;
    for frame in truth.by_ref() {
        let frame = frame.unwrap();
        if frame.frame_index % 1000 == 0 {
            let drift = ((energy(&frame.state()) - initial_energy) / initial_energy).abs();
            worst_relative = worst_relative.max(drift);
        }
        last = frame.state();
    }
    let final_relative = ((energy(&last) - initial_energy) / initial_energy).abs();
    println!("energy: worst relative drift {worst_relative:.3e}, final {final_relative:.3e}");
    // Measured: 1.0e-12 worst, 6.5e-13 final (RK4, 125 µs steps; round-off dominated).
    assert!(worst_relative.max(final_relative) < 1e-11);
    // After one Keplerian period the J2-perturbed orbit is back near its start: J2 shifts
    // the node and the period by some tens of km along a 43,000 km circumference.
    let closure_m = (last.position_m - initial.position_m).norm();
    println!("orbit closure after one Keplerian period: {closure_m:.0} m");
    assert!(closure_m < 100_000.0, "{closure_m}");
}

#[test]
fn default_initial_state_is_the_stated_orbit_over_the_launch_site() {
    let scenario = Scenario::default_scenario().unwrap();
    let frame = launch_frame(&scenario).unwrap();
    let state = initial_state(&scenario, &frame).unwrap();
    let geocentric = frame.geocentric_position_launch(&state.position_m);
    // r = a (1 − e²) / (1 + e cos ν), ν = 160°.
    let expected_radius_m =
        6_878_137.0 * (1.0 - 0.001 * 0.001) / (1.0 + 0.001 * 160.0_f64.to_radians().cos());
    assert!((geocentric.norm() - expected_radius_m).abs() < 1e-6);
    // Inclination: the orbit normal makes 97.4° with the ECEF z axis at the epoch (the
    // elements' reference; the rotation axis of the day is 0.26″ from it).
    let normal = geocentric.cross(&state.velocity_mps).normalize();
    let z_launch = frame.launch_from_ecef() * Vector3::z();
    let inclination_deg = normal.dot(&z_launch).acos().to_degrees();
    assert!((inclination_deg - 97.4).abs() < 1e-9, "{inclination_deg}");
    // The orbit plane contains the launch site direction (within the 0.19° geodetic vs
    // geocentric latitude difference of the node placement).
    let site_direction = (-frame.earth_centre_launch_m()).normalize();
    let out_of_plane_deg = normal.dot(&site_direction).asin().to_degrees();
    assert!(out_of_plane_deg.abs() < 0.5, "{out_of_plane_deg}");
    // The vehicle is 21.4° of arc downrange of the site's pass.
    let arc_deg = geocentric
        .normalize()
        .dot(&site_direction)
        .acos()
        .to_degrees();
    assert!((arc_deg - 21.4).abs() < 0.5, "{arc_deg}");
    assert!((state.attitude_q_ib.norm() - 1.0).abs() < 1e-15);
}

#[test]
fn orbit_elements_give_the_right_radius_energy_and_plane() {
    let (a, e, i, raan, perigee, nu) = (7.0e6, 0.1, 0.9, 2.0, 0.4, 1.1);
    let (position, velocity) = orbit_state_from_elements(a, e, i, raan, perigee, nu, MU_M3_PER_S2);
    let expected_radius = a * (1.0 - e * e) / (1.0 + e * nu.cos());
    assert!((position.norm() - expected_radius).abs() < 1e-6);
    // Vis-viva: ½v² − μ/r = −μ/(2a).
    let energy = 0.5 * velocity.norm_squared() - MU_M3_PER_S2 / position.norm();
    assert!((energy + MU_M3_PER_S2 / (2.0 * a)).abs() < 1e-6 * MU_M3_PER_S2 / a);
    // Orbit normal = R3(Ω) R1(i) z = [sin i sin Ω, −sin i cos Ω, cos i].
    let normal = position.cross(&velocity).normalize();
    let expected_normal = Vector3::new(i.sin() * raan.sin(), -i.sin() * raan.cos(), i.cos());
    assert!((normal - expected_normal).norm() < 1e-12);
    // Argument of latitude u = ω + ν: z = r sin i sin u.
    assert!((position.z - expected_radius * i.sin() * (perigee + nu).sin()).abs() < 1e-6);
}

#[test]
fn constant_rate_about_z_gives_the_analytic_attitude() {
    let rate_deg_per_s = 100.0;
    let duration_s = 3.0;
    let initial_attitude = exp_rotation_vector(&Vector3::new(0.3, -0.2, 0.1));
    let initial = TruthState {
        time_s: 10.0,
        attitude_q_ib: initial_attitude,
        position_m: Vector3::zeros(),
        velocity_mps: Vector3::zeros(),
    };
    let commands = profile(
        &[segment(
            duration_s,
            0.0,
            [0.0, 0.0, rate_deg_per_s],
            [0.0; 3],
        )],
        10.0,
    );
    let truth = TruthSimulator::new(initial, commands, no_gravity, 0.002, 16).unwrap();
    let mut worst_error = 0.0_f64;
    let mut frames = 0;
    for frame in truth {
        let frame = frame.unwrap();
        frames += 1;
        let elapsed_s = frame.time_s - 10.0;
        let expected = initial_attitude
            * exp_rotation_vector(&Vector3::new(
                0.0,
                0.0,
                rate_deg_per_s.to_radians() * elapsed_s,
            ));
        let error = (frame.attitude_q_ib - expected).norm();
        worst_error = worst_error.max(error);
        let expected_increment = rate_deg_per_s.to_radians() * 0.002;
        // Frame times are t0 + kT with t0 = 10 s: their rounding (~2e-15 s) limits Δθ.
        let increment_error =
            (frame.delta_angle_rad - Vector3::new(0.0, 0.0, expected_increment)).norm();
        assert!(increment_error < 1e-14, "{increment_error}");
    }
    println!("attitude: worst quaternion error {worst_error:.3e} over {frames} frames");
    assert_eq!(frames, 1500);
    assert!(worst_error < 1e-12);
}

#[test]
fn thrust_phase_changes_velocity_by_the_analytic_amount() {
    // 50 m/s² along body y with 1 s raised-cosine ramps over 5 s: Δv = 50 (5 − 1) = 200 m/s
    // along C(q) y, position change = ∫∫ f = 50 (∫₀^5 S(τ) dτ).
    let attitude = exp_rotation_vector(&Vector3::new(0.4, 0.2, -0.9));
    let initial = TruthState {
        time_s: 0.0,
        attitude_q_ib: attitude,
        position_m: Vector3::new(1.0, 2.0, 3.0),
        velocity_mps: Vector3::new(10.0, 0.0, 0.0),
    };
    let commands = profile(&[segment(5.0, 1.0, [0.0; 3], [0.0, 50.0, 0.0])], 0.0);
    let mut truth = TruthSimulator::new(initial, commands, no_gravity, 0.002, 8).unwrap();
    let mut body_delta_velocity = Vector3::zeros();
    let mut last = initial;
    while let Some(frame) = truth.next_frame().unwrap() {
        body_delta_velocity += frame.delta_velocity_mps;
        last = frame.state();
    }
    let direction = nav_core::attitude::rotate(&attitude, &Vector3::y());
    let velocity_change = last.velocity_mps - initial.velocity_mps;
    assert!(
        (velocity_change - direction * 200.0).norm() < 1e-10,
        "{velocity_change:?}"
    );
    assert!((body_delta_velocity - Vector3::new(0.0, 200.0, 0.0)).norm() < 1e-10);
    // ∫₀^5 S: the pulse is symmetric, so ∫₀^D S(τ)dτ = (D − ramp) · D / 2.
    let expected_displacement = initial.velocity_mps * 5.0 + direction * 50.0 * 4.0 * 2.5;
    let displacement = last.position_m - initial.position_m;
    assert!(
        (displacement - expected_displacement).norm() < 1e-9,
        "{displacement:?}"
    );
    // The attitude did not move.
    assert!((last.attitude_q_ib - attitude).norm() < 1e-15);
}

#[test]
fn rotation_and_thrust_together_rotate_the_velocity_increment() {
    // Constant rate ω about z with constant body force f along x from t = 0: in inertial
    // axes the force direction rotates, v(T) = C0 (f/ω) [sin ωT, 1 − cos ωT, 0].
    // (The sculling/rotation-compensation content a strapdown must reproduce.)
    let rate_rad_per_s = 2.0_f64.to_radians() * 50.0;
    let force_mps2 = 20.0;
    let duration_s = 2.0;
    let attitude = exp_rotation_vector(&Vector3::new(-0.1, 0.7, 0.2));
    let initial = TruthState {
        time_s: 0.0,
        attitude_q_ib: attitude,
        position_m: Vector3::zeros(),
        velocity_mps: Vector3::zeros(),
    };
    let commands = profile(
        &[segment(
            duration_s,
            0.0,
            [0.0, 0.0, rate_rad_per_s.to_degrees()],
            [force_mps2, 0.0, 0.0],
        )],
        0.0,
    );
    let mut truth = TruthSimulator::new(initial, commands, no_gravity, 0.002, 16).unwrap();
    let mut last = initial;
    while let Some(frame) = truth.next_frame().unwrap() {
        last = frame.state();
    }
    let angle = rate_rad_per_s * duration_s;
    let expected = nav_core::attitude::rotate(
        &attitude,
        &(Vector3::new(angle.sin(), 1.0 - angle.cos(), 0.0) * (force_mps2 / rate_rad_per_s)),
    );
    assert!(
        (last.velocity_mps - expected).norm() < 1e-11,
        "{:?}",
        last.velocity_mps - expected
    );
}

#[test]
fn segments_are_found_and_frames_never_straddle_them() {
    let commands = profile(
        &[
            segment(1.0, 0.0, [0.0; 3], [0.0; 3]),
            segment(2.0, 0.5, [10.0, 0.0, 0.0], [0.0; 3]),
        ],
        100.0,
    );
    assert!((commands.segment_at(100.999).unwrap().duration_s - 1.0).abs() < 1e-15);
    assert!((commands.segment_at(101.0).unwrap().duration_s - 2.0).abs() < 1e-15);
    assert!(commands.segment_at(103.0).is_some());
    assert!(commands.segment_at(103.001).is_none());
    let initial = TruthState {
        time_s: 100.0,
        attitude_q_ib: Quaternion::identity(),
        position_m: Vector3::zeros(),
        velocity_mps: Vector3::zeros(),
    };
    let truth = TruthSimulator::new(initial, commands, no_gravity, 0.01, 4).unwrap();
    assert_eq!(truth.frame_count(), 300);
    let frames: Vec<TruthFrame> = truth.map(Result::unwrap).collect();
    assert_eq!(frames.len(), 300);
    assert_eq!(frames[99].segment_index, 0);
    assert_eq!(frames[100].segment_index, 1);
    let total_angle: f64 = frames.iter().map(|frame| frame.delta_angle_rad.x).sum();
    assert!((total_angle - 10.0_f64.to_radians() * 1.5).abs() < 1e-14);
}

#[test]
fn bad_settings_are_errors() {
    let initial = TruthState {
        time_s: 0.0,
        attitude_q_ib: Quaternion::identity(),
        position_m: Vector3::zeros(),
        velocity_mps: Vector3::zeros(),
    };
    let commands = profile(&[segment(1.0, 0.0, [0.0; 3], [0.0; 3])], 0.0);
    assert!(TruthSimulator::new(initial, commands.clone(), no_gravity, 0.0, 4).is_err());
    assert!(TruthSimulator::new(initial, commands, no_gravity, 0.002, 0).is_err());
}
