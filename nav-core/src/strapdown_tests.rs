use super::*;
use crate::attitude::conjugate;
use crate::frames::{WGS84_GM_M3_S2, WGS84_SEMI_MAJOR_AXIS_M};
use core::f64::consts::PI;

use crate::frames::tests::wenchang_frame as frame;

fn at_rest() -> NavigationState {
    NavigationState {
        attitude: Quaternion::identity(),
        position_m: Vector3::zeros(),
        velocity_mps: Vector3::zeros(),
        time_s: 0.0,
    }
}

/// Rotation angle (rad) of `a* ⊗ b`.
fn angle_between(a: &Quaternion<f64>, b: &Quaternion<f64>) -> f64 {
    let d = product(&conjugate(a), b);
    2.0 * libm::atan2(d.imag().norm(), d.w.abs())
}

fn config(coning: bool, j2: bool) -> StrapdownConfig {
    StrapdownConfig {
        coning_compensation: coning,
        sculling_compensation: true,
        gravity: GravityModel { j2_enabled: j2 },
    }
}

#[test]
fn constant_rotation_matches_exact_exponential() {
    let f = frame();
    let mut sd = Strapdown::new(config(true, true));
    let mut nav = at_rest();
    let rate = Vector3::new(0.3, -0.7, 1.1);
    let t = 0.002;
    let raw = ImuIncrement::from_rates(&rate, &Vector3::zeros(), t);
    for _ in 0..1000 {
        sd.step(&mut nav, &raw, &SensorCorrections::default(), &f)
            .unwrap();
    }
    let exact = exp_rotation_vector(&(rate * (1000.0 * t)));
    let err = angle_between(&exact, &nav.attitude);
    println!("constant-rate attitude error after 1000 steps: {err:e} rad");
    assert!(err < 1e-12);
    assert!((nav.time_s - 2.0).abs() < 1e-12);
}

/// Classic coning motion `q(t) = [cos(a/2), sin(a/2) cosΩt, sin(a/2) sinΩt, 0]`.
/// Body rate `ω = 2 vec(q* ⊗ q̇) = [−Ω sin a sinΩt, Ω sin a cosΩt, −2Ω sin²(a/2)]`,
/// integrated exactly: `Δθ = [sin a (cosΩt₂ − cosΩt₁), sin a (sinΩt₂ − sinΩt₁),
/// −2Ω sin²(a/2) (t₂ − t₁)]` (cross-checked against 64-interval Simpson quadrature).
#[test]
fn coning_compensation_reduces_coning_error() {
    let f = frame();
    let a = 1.0_f64.to_radians();
    let omega = 2.0 * PI * 10.0;
    let t = 0.002;
    let steps = 5000;
    let exact_q = |time: f64| {
        let (s, c) = ((a / 2.0).sin(), (a / 2.0).cos());
        Quaternion::new(c, s * (omega * time).cos(), s * (omega * time).sin(), 0.0)
    };
    let rate = |time: f64| {
        // ω = 2 vec(q* ⊗ q̇), q̇ by its closed form.
        let s = (a / 2.0).sin();
        let qdot = Quaternion::new(
            0.0,
            -s * omega * (omega * time).sin(),
            s * omega * (omega * time).cos(),
            0.0,
        );
        product(&conjugate(&exact_q(time)), &qdot).imag() * 2.0
    };
    let delta = |t1: f64, t2: f64| {
        Vector3::new(
            a.sin() * ((omega * t2).cos() - (omega * t1).cos()),
            a.sin() * ((omega * t2).sin() - (omega * t1).sin()),
            -2.0 * omega * (a / 2.0).sin().powi(2) * (t2 - t1),
        )
    };
    // Cross-check the closed form against 64-interval composite Simpson quadrature.
    let (t1, t2) = (0.0123, 0.0143);
    let n = 64;
    let h = (t2 - t1) / n as f64;
    let mut simpson = rate(t1) + rate(t2);
    for i in 1..n {
        simpson += rate(t1 + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    simpson *= h / 3.0;
    let quad_err = (simpson - delta(t1, t2)).norm();
    println!("closed-form Δθ vs Simpson-64: {quad_err:e} rad");
    assert!(quad_err < 1e-13);

    let mut errors = [0.0; 2];
    for (slot, coning) in [(0, true), (1, false)] {
        let mut sd = Strapdown::new(config(coning, false));
        let mut nav = at_rest();
        nav.attitude = exact_q(0.0);
        for k in 0..steps {
            let raw = ImuIncrement {
                delta_angle_rad: delta(k as f64 * t, (k + 1) as f64 * t),
                delta_velocity_mps: Vector3::zeros(),
                interval_s: t,
            };
            sd.step(&mut nav, &raw, &SensorCorrections::default(), &f)
                .unwrap();
        }
        errors[slot] = angle_between(&exact_q(steps as f64 * t), &nav.attitude);
    }
    let ratio = errors[1] / errors[0];
    println!(
        "coning 10 s: error with compensation {:e} rad, without {:e} rad, ratio {ratio:.1}",
        errors[0], errors[1]
    );
    assert!(ratio >= 100.0);
    // Measured 8.44e-7 rad with compensation; assert within 2x of that.
    assert!(errors[0] < 1.7e-6);
}

/// `J1(x) = Σ_m (−1)^m (x/2)^{2m+1} / (m! (m+1)!)` (Abramowitz & Stegun 9.1.10), eight
/// terms: truncation below 1e-30 for `|x| ≤ 0.1`.
fn bessel_j1(x: f64) -> f64 {
    let mut term = x / 2.0;
    let mut sum = term;
    for m in 1..8 {
        term *= -(x / 2.0) * (x / 2.0) / (f64::from(m) * f64::from(m + 1));
        sum += term;
    }
    sum
}

/// Classic sculling: angular oscillation `θ(t) = α sinΩt` about body `x` (attitude
/// `exp(θ x̂)`, starting at identity) in phase with specific force `f_b = A sinΩt ŷ`.
/// Exact increments: `Δθ = α (sinΩt₂ − sinΩt₁) x̂`, `Δv = A (cosΩt₁ − cosΩt₂)/Ω ŷ`.
/// In inertial axes `f = A sinΩt [0, cos θ, sin θ]`, whose mean over a period is
/// `[0, 0, A J1(α)]` (Bessel generating function), so after whole periods the exact
/// velocity change is `[0, 0, A J1(α) t]`: the rectified sculling acceleration. The vehicle
/// is placed 1e13 m from the Earth centre so gravitation (4e-12 m/s², 4e-11 m/s over the
/// run) is negligible against the velocity errors compared. Run at Ω = 2π·20 Hz and
/// 2π·10 Hz (ΩT = 0.25 and 0.13 rad at 500 Hz), α = 0.02 rad, A = 10 m/s², 10 s.
#[test]
fn sculling_compensation_reduces_sculling_error() {
    let f = frame();
    let (alpha, accel, omega) = (0.02, 10.0, 2.0 * PI * 20.0);
    let t = 0.002;
    let steps = 5000; // 10 s = 200 periods
                      // Cross-check the Bessel mean with 2000-interval Simpson quadrature over one period.
    let period = 2.0 * PI / omega;
    let integrand = |time: f64| (omega * time).sin() * (alpha * (omega * time).sin()).sin();
    let n = 2000;
    let h = period / f64::from(n);
    let mut simpson = integrand(0.0) + integrand(period);
    for i in 1..n {
        let weight = if i % 2 == 1 { 4.0 } else { 2.0 };
        simpson += weight * integrand(f64::from(i) * h);
    }
    let mean = simpson * h / 3.0 / period;
    println!("J1(α) {} vs Simpson mean {mean}", bessel_j1(alpha));
    assert!((mean - bessel_j1(alpha)).abs() < 1e-15);

    let duration = f64::from(steps) * t;
    let exact_velocity = Vector3::new(0.0, 0.0, accel * bessel_j1(alpha) * duration);
    let far = *f.earth_centre_launch_m() + Vector3::new(0.0, 1.0e13, 0.0);
    let run = |omega: f64, sculling: bool| {
        let mut sd = Strapdown::new(StrapdownConfig {
            coning_compensation: true,
            sculling_compensation: sculling,
            gravity: GravityModel { j2_enabled: false },
        });
        let mut nav = NavigationState {
            position_m: far,
            ..at_rest()
        };
        for k in 0..steps {
            let (t1, t2) = (f64::from(k) * t, f64::from(k + 1) * t);
            let raw = ImuIncrement {
                delta_angle_rad: Vector3::new(
                    alpha * ((omega * t2).sin() - (omega * t1).sin()),
                    0.0,
                    0.0,
                ),
                delta_velocity_mps: Vector3::new(
                    0.0,
                    accel * ((omega * t1).cos() - (omega * t2).cos()) / omega,
                    0.0,
                ),
                interval_s: t,
            };
            sd.step(&mut nav, &raw, &SensorCorrections::default(), &f)
                .unwrap();
        }
        // Attitude returns to identity after whole periods (fixed-axis rotation).
        assert!(angle_between(&Quaternion::identity(), &nav.attitude) < 1e-12);
        (nav.velocity_mps - exact_velocity).norm()
    };
    let (with_20, without_20) = (run(omega, true), run(omega, false));
    let (with_10, without_10) = (run(omega / 2.0, true), run(omega / 2.0, false));
    println!(
        "sculling 10 s, rectified Δv {:.6} m/s; 20 Hz: error with compensation {with_20:e} \
         m/s, without {without_20:e} m/s (ratio {:.1}); 10 Hz: with {with_10:e} m/s, \
         without {without_10:e} m/s (ratio {:.1})",
        exact_velocity.z,
        without_20 / with_20,
        without_10 / with_10
    );
    // Measured: 20 Hz 1.33e-4 vs 1.05e-2 m/s (ratio 79), 10 Hz 8.56e-6 vs 2.63e-3 m/s
    // (ratio 307). Halving ΩT divides the compensated error by 15.5 (fourth order, the
    // two-sample algorithm's residual) and the uncompensated one by 3.99 (second order).
    assert!(without_10 / with_10 >= 100.0);
    assert!(with_10 < 1.7e-5);
    let (order_with, order_without) = (with_20 / with_10, without_20 / without_10);
    assert!((14.0..18.0).contains(&order_with), "{order_with}");
    assert!((3.8..4.2).contains(&order_without), "{order_without}");
}

#[test]
fn circular_orbit_closes_after_one_period() {
    let f = frame();
    let radius = WGS84_SEMI_MAJOR_AXIS_M + 500.0e3;
    let n = (WGS84_GM_M3_S2 / (radius * radius * radius)).sqrt();
    let period = 2.0 * PI / n;
    let steps = (period * 500.0).ceil() as usize;
    let t = period / steps as f64;
    // Orbit plane: an arbitrary inclined plane in launch-inertial axes.
    let u1 = Vector3::new(1.0, 0.2, -0.3).normalize();
    let u2 = {
        let w = Vector3::new(0.1, 1.0, 0.5);
        (w - u1 * u1.dot(&w)).normalize()
    };
    let centre = *f.earth_centre_launch_m();
    let exact = |time: f64| {
        (
            centre + (u1 * (n * time).cos() + u2 * (n * time).sin()) * radius,
            (-u1 * (n * time).sin() + u2 * (n * time).cos()) * (radius * n),
        )
    };
    let (p0, v0) = exact(0.0);
    let mut nav = NavigationState {
        attitude: Quaternion::identity(),
        position_m: p0,
        velocity_mps: v0,
        time_s: 0.0,
    };
    let mut sd = Strapdown::new(config(true, false));
    let raw = ImuIncrement::from_rates(&Vector3::zeros(), &Vector3::zeros(), t);
    for _ in 0..steps {
        sd.step(&mut nav, &raw, &SensorCorrections::default(), &f)
            .unwrap();
    }
    let (p1, v1) = exact(period);
    let pos_err = (nav.position_m - p1).norm();
    let vel_err = (nav.velocity_mps - v1).norm();
    println!(
        "Kepler 500 km, {steps} steps of {t} s: position error {pos_err:e} m, velocity error {vel_err:e} m/s"
    );
    // Measured 6.2e-5 m (2,838,490 steps); assert within 2x of that.
    assert!(pos_err < 1.3e-4);
    assert!(vel_err < 1.4e-7);
}

#[test]
fn corrections_and_outputs() {
    let f = frame();
    let mut sd = Strapdown::new(config(false, true));
    let mut nav = at_rest();
    let t = 0.01;
    let raw = ImuIncrement::from_rates(
        &Vector3::new(0.01, 0.02, 0.03),
        &Vector3::new(1.0, 2.0, 3.0),
        t,
    );
    let corr = SensorCorrections {
        gyro_bias_rad_s: Vector3::new(0.001, 0.0, 0.0),
        accel_bias_mps2: Vector3::new(0.0, 0.5, 0.0),
        gyro_scale_factor: Vector3::new(0.0, 0.5, 0.0),
        accel_scale_factor: Vector3::new(0.0, 0.0, 0.1),
    };
    let out = sd.step(&mut nav, &raw, &corr, &f).unwrap();
    assert!((out.measured_rate_rad_s - Vector3::new(0.01, 0.02, 0.03)).norm() < 1e-15);
    assert!((out.corrected_rate_rad_s - Vector3::new(0.009, 0.01, 0.03)).norm() < 1e-15);
    assert!((out.corrected_specific_force_mps2 - Vector3::new(1.0, 1.5, 2.7)).norm() < 1e-14);
    assert!((out.gravity_mps2.norm() - 9.816).abs() < 1e-3);
}

/// A 2 ms increment turning about all three axes under a 9.8 m/s² specific force.
fn turning_increment() -> ImuIncrement {
    ImuIncrement::from_rates(
        &Vector3::new(0.1, 0.2, 0.3),
        &Vector3::new(0.0, 9.8, 0.0),
        0.002,
    )
}

#[test]
fn errors_leave_state_untouched() {
    let f = frame();
    let mut sd = Strapdown::new(StrapdownConfig::default());
    let mut nav = at_rest();
    let good = turning_increment();
    sd.step(&mut nav, &good, &SensorCorrections::default(), &f)
        .unwrap();
    let (nav_before, sd_before) = (nav, sd);
    let mut bad = good;
    bad.interval_s = 0.0;
    assert_eq!(
        sd.step(&mut nav, &bad, &SensorCorrections::default(), &f),
        Err(NavError::InvalidTimeStep)
    );
    bad.interval_s = f64::NAN;
    assert_eq!(
        sd.step(&mut nav, &bad, &SensorCorrections::default(), &f),
        Err(NavError::InvalidTimeStep)
    );
    bad = good;
    bad.delta_angle_rad.y = f64::INFINITY;
    assert_eq!(
        sd.step(&mut nav, &bad, &SensorCorrections::default(), &f),
        Err(NavError::NonFiniteInput)
    );
    let corr = SensorCorrections {
        accel_bias_mps2: Vector3::new(f64::NAN, 0.0, 0.0),
        ..SensorCorrections::default()
    };
    assert_eq!(
        sd.step(&mut nav, &good, &corr, &f),
        Err(NavError::NonFiniteInput)
    );
    // Position at the Earth centre: gravity is non-finite, refused.
    let mut centre = nav;
    centre.position_m = *f.earth_centre_launch_m();
    centre.velocity_mps = Vector3::zeros();
    let centre_before = centre;
    assert_eq!(
        sd.step(&mut centre, &good, &SensorCorrections::default(), &f),
        Err(NavError::NonFiniteState)
    );
    assert_eq!(centre, centre_before);
    assert_eq!(nav, nav_before);
    assert_eq!(sd, sd_before);
}

/// Each input check refuses its own fault with its own error: a non-finite velocity
/// increment alone, or a non-finite attitude vector part alone, is caught up front (not
/// later by a side effect), and a negative interval is an invalid time step.
#[test]
fn each_input_fault_is_refused_with_its_error() {
    let f = frame();
    let mut sd = Strapdown::new(StrapdownConfig::default());
    let mut nav = at_rest();
    let good = turning_increment();
    let none = SensorCorrections::default();
    let mut bad = good;
    bad.delta_velocity_mps.z = f64::NAN;
    assert_eq!(
        sd.step(&mut nav, &bad, &none, &f),
        Err(NavError::NonFiniteInput)
    );
    bad = good;
    bad.interval_s = -0.002;
    assert_eq!(
        sd.step(&mut nav, &bad, &none, &f),
        Err(NavError::InvalidTimeStep)
    );
    for component in 0..3 {
        let mut broken = at_rest();
        broken.attitude.coords[component] = f64::NAN;
        assert_eq!(
            sd.step(&mut broken, &good, &none, &f),
            Err(NavError::NonFiniteState),
            "{component}"
        );
    }
    assert_eq!(nav, at_rest());
}

/// After `reset_history` a step is exactly the step of a fresh integrator (no coning or
/// sculling term from the previous increments), while without it the history matters.
#[test]
fn reset_history_forgets_the_previous_increments() {
    let f = frame();
    let first = ImuIncrement::from_rates(
        &Vector3::new(0.5, -0.2, 0.3),
        &Vector3::new(1.0, 9.8, -2.0),
        0.002,
    );
    let second = ImuIncrement::from_rates(
        &Vector3::new(-0.4, 0.6, 0.1),
        &Vector3::new(-3.0, 9.0, 4.0),
        0.002,
    );
    let none = SensorCorrections::default();
    let mut sd = Strapdown::new(config(true, true));
    let mut nav = at_rest();
    sd.step(&mut nav, &first, &none, &f).unwrap();
    let after_first = nav;
    let mut with_history = sd;
    let mut nav_with_history = after_first;
    with_history
        .step(&mut nav_with_history, &second, &none, &f)
        .unwrap();
    sd.reset_history();
    assert_eq!(sd, Strapdown::new(config(true, true)));
    let mut nav_reset = after_first;
    sd.step(&mut nav_reset, &second, &none, &f).unwrap();
    let mut fresh = Strapdown::new(config(true, true));
    let mut nav_fresh = after_first;
    fresh.step(&mut nav_fresh, &second, &none, &f).unwrap();
    assert_eq!(nav_reset, nav_fresh);
    assert!(angle_between(&nav_reset.attitude, &nav_with_history.attitude) > 1e-8);
    assert!((nav_reset.velocity_mps - nav_with_history.velocity_mps).norm() > 1e-8);
}

/// Rotation compensation, step 3's `½ Δθ × Δv`: one step from rest (no history) with a
/// constant rate ω about body z and a constant specific force f along body x. The exact
/// inertial velocity change is `∫₀ᵀ R_z(ωt) f dt = (f/ω) [sin ωT, 1 − cos ωT, 0]`, i.e.
/// `f T [1 − (ωT)²/6, ωT/2 − (ωT)³/24, 0]`; the two-sample form gives `f T [1, ωT/2, 0]`,
/// so it must agree to `f T (ωT)²/6` (1.7e-6 m/s here) — the `ωT/2` term is 5e-4 m/s.
/// Gravity is removed with the step's own `g T`; measured outputs are `Δ/T`.
#[test]
fn rotation_compensation_matches_the_exact_velocity_increment() {
    let f = frame();
    let mut sd = Strapdown::new(config(true, true));
    let mut nav = at_rest();
    let (rate, force, interval) = (1.0, 10.0, 0.01);
    let raw = ImuIncrement::from_rates(
        &Vector3::new(0.0, 0.0, rate),
        &Vector3::new(force, 0.0, 0.0),
        interval,
    );
    let out = sd
        .step(&mut nav, &raw, &SensorCorrections::default(), &f)
        .unwrap();
    let angle = rate * interval;
    let exact = Vector3::new(angle.sin(), 1.0 - angle.cos(), 0.0) * (force / rate);
    let from_force = nav.velocity_mps - out.gravity_mps2 * interval;
    let error = (from_force - exact).norm();
    assert!(error < 2e-6, "{from_force:?} vs {exact:?}");
    assert!((from_force.y - 0.5 * force * interval * angle).abs() < 1e-7);
    assert!((out.measured_rate_rad_s - Vector3::new(0.0, 0.0, rate)).norm() < 1e-15);
    assert!((out.measured_specific_force_mps2 - Vector3::new(force, 0.0, 0.0)).norm() < 1e-14);
}

/// Every result is checked for overflow, each on its own: a position that overflows while
/// the velocity stays finite, a time that overflows alone, and each of the four output
/// rates overflowing alone (a subnormal interval; scale-factor corrections make the
/// corrected and raw increments differ). All are refused and leave `nav` unchanged.
#[test]
fn an_overflowing_position_or_time_is_refused() {
    let f = frame();
    let none = SensorCorrections::default();
    let no_j2 = config(true, false);
    // Position: p = 1.5e308, Δv = 1e308 over 1 s → v = 1e308 (finite), p + v/2 = ∞.
    let mut far = at_rest();
    far.position_m = Vector3::new(1.5e308, 0.0, 0.0);
    let push = ImuIncrement {
        delta_angle_rad: Vector3::zeros(),
        delta_velocity_mps: Vector3::new(1.0e308, 0.0, 0.0),
        interval_s: 1.0,
    };
    let before = far;
    assert_eq!(
        Strapdown::new(no_j2).step(&mut far, &push, &none, &f),
        Err(NavError::NonFiniteState)
    );
    assert_eq!(far, before);
    // Time: t = f64::MAX plus one ulp of it; 1e150 m out gravity is 0, so nothing else
    // overflows.
    let mut late = at_rest();
    late.position_m = Vector3::new(1.0e150, 0.0, 0.0);
    late.time_s = f64::MAX;
    let idle = ImuIncrement {
        delta_angle_rad: Vector3::zeros(),
        delta_velocity_mps: Vector3::zeros(),
        interval_s: libm::exp2(971.0),
    };
    let before = late;
    assert_eq!(
        Strapdown::new(no_j2).step(&mut late, &idle, &none, &f),
        Err(NavError::NonFiniteState)
    );
    assert_eq!(late, before);
}

#[test]
fn an_overflowing_output_rate_is_refused() {
    let f = frame();
    // Output rates over a subnormal interval of 1e-310 s.
    let tiny = 1.0e-310;
    let x = Vector3::x();
    let cases = [
        // Corrected rate ∞ (0.101 / 1e-310), raw rate 1e307.
        (
            x * 1e-3,
            Vector3::zeros(),
            Vector3::new(-100.0, 0.0, 0.0),
            Vector3::zeros(),
        ),
        // Corrected specific force ∞, raw 1e307.
        (
            Vector3::zeros(),
            x * 1e-3,
            Vector3::zeros(),
            Vector3::new(-100.0, 0.0, 0.0),
        ),
        // Raw rate ∞ (0.1 / 1e-310), corrected 1e306.
        (
            x * 0.1,
            Vector3::zeros(),
            Vector3::new(0.999, 0.0, 0.0),
            Vector3::zeros(),
        ),
        // Raw specific force ∞, corrected 1e306.
        (
            Vector3::zeros(),
            x * 0.1,
            Vector3::zeros(),
            Vector3::new(0.999, 0.0, 0.0),
        ),
    ];
    for (index, (delta_angle, delta_velocity, gyro_scale, accel_scale)) in
        cases.into_iter().enumerate()
    {
        let raw = ImuIncrement {
            delta_angle_rad: delta_angle,
            delta_velocity_mps: delta_velocity,
            interval_s: tiny,
        };
        let corrections = SensorCorrections {
            gyro_scale_factor: gyro_scale,
            accel_scale_factor: accel_scale,
            ..SensorCorrections::default()
        };
        let mut nav = at_rest();
        assert_eq!(
            Strapdown::new(config(true, true)).step(&mut nav, &raw, &corrections, &f),
            Err(NavError::NonFiniteState),
            "case {index}"
        );
        assert_eq!(nav, at_rest());
    }
}
