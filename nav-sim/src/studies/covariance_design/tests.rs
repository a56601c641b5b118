//! Unit tests of the covariance design study.

use super::*;
use nav_core::frames::WGS84_GM_M3_S2;
use nav_core::state::ACCEL_SCALE_FACTOR;

/// The second shipped scenario: the default schedule with different true sensor errors.
const MADE_UP_ERRORS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/made_up_errors.toml");

/// Coarse but exact enough for the tests: a covariance step is at most 50 frames (0.1 s,
/// and the 10 Hz measurements end a step every 0.1 s anyway); one truth substep.
fn test_options() -> DesignOptions {
    DesignOptions {
        step_frames: 50,
        truth_substeps_per_frame: Some(1),
        ..DesignOptions::default()
    }
}

fn assert_meets_half_the_targets(report: &DesignReport) {
    print!("{}", report.table());
    for row in &report.rows {
        assert!(
            row.ratio() <= 0.5,
            "{} axis {}: sigma {:.3e} > target/2 ({:.3e})",
            row.target.block.name(),
            row.axis,
            row.sigma,
            row.target.target
        );
    }
}

#[test]
fn default_schedule_calibrates_every_state_to_half_the_papers_accuracy() {
    let scenario = Scenario::default_scenario().unwrap();
    let report = analyse(&scenario, &test_options()).unwrap();
    assert_meets_half_the_targets(&report);
    // Design goal (docs/guide/scenario-design.md): every sigma <= target/3. Measured worst
    // 0.293 (accelerometer scale factor y).
    assert!(
        report.worst_ratio() <= 1.0 / 3.0,
        "{}",
        report.worst_ratio()
    );
    assert_eq!(report.rows.len(), 15);
    assert_eq!((report.star_updates, report.gnss_updates), (30_770, 30_770));
    // Orbit safety with the truth simulator: lowest altitude 440 km, final perigee 640 km,
    // the thrust pulses cancel.
    let orbit = &report.orbit;
    println!("{orbit:?}");
    assert!(orbit.minimum_altitude_m > 200.0e3, "{orbit:?}");
    assert!(orbit.final_perigee_altitude_m > 200.0e3, "{orbit:?}");
    assert!(orbit.net_delta_v_mps < 1.0, "{orbit:?}");
    assert!(
        (orbit.total_delta_v_mps - 12_000.0).abs() < 1.0,
        "{orbit:?}"
    );
}

#[test]
fn made_up_errors_are_calibrated_as_well_as_the_papers() {
    let made_up = Scenario::load(std::path::Path::new(MADE_UP_ERRORS)).unwrap();
    let default = Scenario::default_scenario().unwrap();
    // Every true error component differs from the default's (signs and magnitudes).
    let differ =
        |a: &[f64; 3], b: &[f64; 3], by: f64| a.iter().zip(b).all(|(x, y)| (x - y).abs() > by);
    assert!(differ(
        &made_up.gyro.bias_rad_per_s,
        &default.gyro.bias_rad_per_s,
        1e-5
    ));
    assert!(differ(
        &made_up.gyro.scale_factor,
        &default.gyro.scale_factor,
        1e-5
    ));
    assert!(differ(
        &made_up.accelerometer.bias_mps2,
        &default.accelerometer.bias_mps2,
        1e-4
    ));
    assert!(differ(
        &made_up.accelerometer.scale_factor,
        &default.accelerometer.scale_factor,
        1e-5
    ));
    assert!(differ(
        &made_up.star_sensor.installation_error_rotation_vector_rad,
        &default.star_sensor.installation_error_rotation_vector_rad,
        1e-4
    ));
    // The schedule is the default's.
    assert_eq!(made_up.manoeuvres, default.manoeuvres);
    let report = analyse(&made_up, &test_options()).unwrap();
    assert_meets_half_the_targets(&report);
    assert!(
        report.worst_ratio() <= 1.0 / 3.0,
        "{}",
        report.worst_ratio()
    );
}

#[test]
fn without_thrust_the_accelerometer_scale_factor_stays_at_its_prior() {
    // The analysis can fail: a scenario that never thrusts cannot see the accelerometer
    // scale factor, whose sigma must stay at the initial 2e-4 (ratio 100).
    let mut scenario = Scenario::default_scenario().unwrap();
    scenario.manoeuvres.truncate(4);
    let report = analyse(&scenario, &test_options()).unwrap();
    let accel_scale: Vec<f64> = report
        .rows
        .iter()
        .filter(|row| row.target.block == ACCEL_SCALE_FACTOR)
        .map(SigmaRow::ratio)
        .collect();
    assert_eq!(accel_scale.len(), 3);
    assert!(
        accel_scale.iter().all(|ratio| *ratio > 99.0),
        "{accel_scale:?}"
    );
    assert!(report.orbit.total_delta_v_mps < 1e-9);
}

#[test]
fn circular_orbit_has_equal_perigee_and_apogee() {
    let radius_m = 6_878_137.0;
    let speed_mps = (WGS84_GM_M3_S2 / radius_m).sqrt();
    let (perigee_m, apogee_m) = perigee_apogee_radii_m(
        &Vector3::new(radius_m, 0.0, 0.0),
        &Vector3::new(0.0, speed_mps, 0.0),
    );
    assert!((perigee_m - radius_m).abs() < 1e-6 && (apogee_m - radius_m).abs() < 1e-6);
    // A prograde burn to v_p = sqrt(mu (2/r - 1/a)) for a = r + 1000 km puts the apogee at
    // 2a - r, the perigee stays at r (vis-viva).
    let semi_major_axis_m = radius_m + 1.0e6;
    let burnt_mps = (WGS84_GM_M3_S2 * (2.0 / radius_m - 1.0 / semi_major_axis_m)).sqrt();
    let (perigee_m, apogee_m) = perigee_apogee_radii_m(
        &Vector3::new(radius_m, 0.0, 0.0),
        &Vector3::new(0.0, burnt_mps, 0.0),
    );
    assert!((perigee_m - radius_m).abs() < 1e-6, "{perigee_m}");
    assert!(
        (apogee_m - (2.0 * semi_major_axis_m - radius_m)).abs() < 1e-5,
        "{apogee_m}"
    );
}

#[test]
fn zero_step_is_a_setting_error() {
    let scenario = Scenario::default_scenario().unwrap();
    let options = DesignOptions {
        step_frames: 0,
        ..DesignOptions::default()
    };
    assert!(matches!(
        analyse(&scenario, &options),
        Err(DesignError::Setting {
            key: "step_frames",
            ..
        })
    ));
}

/// The augmented transition's coupling `E M` to first order is nav-core's continuous
/// columns of the twelve states (`imu_error::system_columns`, derived from the
/// sensitivities, not from the equivalent biases) times the interval.
#[test]
fn the_imu_error_coupling_is_nav_cores_system_columns() {
    use nav_core::imu_error::system_columns;
    use nav_core::observability::constant_motion;
    let point = LinearisationPoint {
        measured_rate_rad_s: Vector3::new(0.03, -0.02, 0.05),
        measured_specific_force_mps2: Vector3::new(9.0, -0.7, 0.4),
        ..constant_motion(
            &Vector3::new(0.03, -0.02, 0.05),
            &Vector3::new(9.0, -0.7, 0.4),
            &rotation_matrix(&exp_rotation_vector(&Vector3::new(0.3, -0.5, 1.1))),
        )
    };
    let noise = scenario_process_noise(&Scenario::default_scenario().unwrap());
    let interval_s = 1e-3;
    let model = discretise(
        &system_matrix(&point),
        &noise_input_matrix(&point),
        &noise.spectral_density_diagonal(),
        interval_s,
        1,
    )
    .unwrap();
    let coupling =
        augmented::bias_columns(&model.transition) * augmented::equivalent_bias_map(&point);
    let expected = system_columns(&point) * interval_s;
    let scale = expected.amax();
    assert!(scale > 1e-6, "{scale}");
    for row in 0..24 {
        for column in 0..IMU_ERROR_DIMENSION {
            let (got, want) = (coupling[(row, column)], expected[(row, column)]);
            assert!(
                (got - want).abs() <= 1e-12 * scale,
                "row {row} column {column}: {got:e} against {want:e}"
            );
        }
    }
}

/// With the twelve states on but a negligible prior, the host-side augmented covariance
/// reproduces nav-core's dense filter on a flight with receiver velocity and the correlated
/// GNSS error states (the upper stage's initial coast and its slews about +x and -x).
#[test]
fn with_negligible_imu_error_priors_the_augmented_analysis_is_nav_cores() {
    let mut scenario =
        Scenario::from_toml_str(include_str!("../../../scenarios/upper_stage.toml")).unwrap();
    scenario.manoeuvres.truncate(4);
    let reference = analyse(&scenario, &test_options()).unwrap();
    scenario.filter.imu_errors = crate::scenario::FilterImuErrors {
        gyro_misalignment_sigma_rad: 1e-15,
        accel_misalignment_sigma_rad: 1e-15,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: 1e-18,
    };
    let augmented = analyse(&scenario, &test_options()).unwrap();
    assert!(reference.imu_errors.is_none());
    let imu = augmented.imu_errors.unwrap();
    assert!(imu
        .sigma
        .iter()
        .zip(imu.prior)
        .all(|(s, p)| *s <= p && *s > 0.0));
    for (k, (a, b)) in augmented
        .final_sigma
        .iter()
        .zip(reference.final_sigma.iter())
        .enumerate()
    {
        assert!((a / b - 1.0).abs() < 1e-9, "state {k}: {a:e} against {b:e}");
    }
}
