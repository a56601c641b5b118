//! Unit tests of the scenario schema: the default scenario, parsing errors and validation.

use super::*;

fn invalid_key(text: &str) -> String {
    match Scenario::from_toml_str(text) {
        Err(ScenarioError::Invalid { key, .. }) => key,
        other => panic!("expected an Invalid error, got {other:?}"),
    }
}

/// Parsed decimal literals must equal the literal's f64 to the last bit (up to 1 ulp).
fn assert_same(parsed: &[f64], expected: &[f64]) {
    assert_eq!(parsed.len(), expected.len());
    for (value, wanted) in parsed.iter().zip(expected) {
        assert!(
            (value - wanted).abs() <= f64::EPSILON * wanted.abs(),
            "{parsed:?} != {expected:?}"
        );
    }
}

#[test]
fn default_scenario_parses_with_the_papers_values() {
    let scenario = Scenario::default_scenario().unwrap();
    assert_same(&[scenario.imu.rate_hz], &[500.0]);
    assert_same(&scenario.gyro.bias_rad_per_s, &[1.0e-4, 2.0e-4, 3.0e-4]);
    assert_same(&scenario.gyro.scale_factor, &[3.0e-5; 3]);
    assert_same(&[scenario.accelerometer.noise_per_sample_mps2], &[1.0e-4]);
    assert_same(
        &scenario.star_sensor.installation_error_rotation_vector_rad,
        &[1.0e-3, 2.0e-3, 3.0e-3],
    );
    assert_same(&[scenario.star_sensor.noise_arcsec], &[10.0]);
    assert_same(&[scenario.gnss.noise_m], &[10.0]);
    assert_eq!(scenario.filter.mode, FilterMode::ClosedLoop);
    // 20 + 3 x 19 + 6 x 41 + 300 + 4 x 319 + 739 + 439 s.
    assert!((scenario.duration_s() - 3077.0).abs() < 1e-9);
    assert_eq!(scenario.frame_count(), 1_538_500);
}

#[test]
fn noise_conversions_match_the_stated_interpretation() {
    let scenario = Scenario::default_scenario().unwrap();
    let period_s = scenario.imu.frame_period_s();
    // 0.2 (deg/h)/sqrt(Hz) * sqrt(0.002 s) = 4.3e-8 rad.
    let sigma_angle = scenario.gyro.delta_angle_noise_sigma_rad(period_s);
    assert!((sigma_angle - 4.3362e-8).abs() < 1e-11, "{sigma_angle}");
    // 1e-4 m/s^2 * 0.002 s = 2e-7 m/s.
    let sigma_velocity = scenario
        .accelerometer
        .delta_velocity_noise_sigma_mps(period_s);
    assert!((sigma_velocity - 2.0e-7).abs() < 1e-20);
    assert!((scenario.star_sensor.noise_rad() - 4.8481e-5).abs() < 1e-9);
}

#[test]
fn unknown_key_is_an_error_naming_it() {
    let text = DEFAULT_SCENARIO_TOML.replace("rate_hz = 500.0", "rate_hz = 500.0\nrate_hx = 1.0");
    let error = Scenario::from_toml_str(&text).unwrap_err();
    let message = error.to_string();
    assert!(message.contains("rate_hx"), "{message}");
}

#[test]
fn unknown_table_is_an_error_naming_it() {
    let text = format!("{DEFAULT_SCENARIO_TOML}\n[magnetometer]\nrate_hz = 10.0\n");
    let message = Scenario::from_toml_str(&text).unwrap_err().to_string();
    assert!(message.contains("magnetometer"), "{message}");
}

#[test]
fn missing_key_is_an_error_naming_it() {
    let text = DEFAULT_SCENARIO_TOML.replace("noise_m = 10.0\n", "");
    let message = Scenario::from_toml_str(&text).unwrap_err().to_string();
    assert!(message.contains("noise_m"), "{message}");
}

#[test]
fn invalid_values_are_rejected_naming_the_key() {
    let cases = [
        ("rate_hz = 500.0", "rate_hz = 0.0", "imu.rate_hz"),
        // The first "rate_hz = 10.0" is the star sensor's (GNSS comes after it).
        ("rate_hz = 10.0", "rate_hz = 3.0", "star_sensor.rate_hz"),
        ("noise_m = 10.0", "noise_m = -1.0", "gnss.noise_m"),
        ("latency_s = 0.0", "latency_s = 0.0031", "gnss.latency_s"),
        (
            "eccentricity = 0.001",
            "eccentricity = 1.5",
            "initial_orbit.eccentricity",
        ),
        (
            "semi_major_axis_m = 6878137.0",
            "semi_major_axis_m = 6000000.0",
            "initial_orbit.semi_major_axis_m",
        ),
        (
            "scale_factor = [3.0e-5, 3.0e-5, 3.0e-5]",
            "scale_factor = [3.0e-5, 1.5, 3.0e-5]",
            "gyro.scale_factor",
        ),
        (
            "discretisation_order = 3",
            "discretisation_order = 7",
            "filter.discretisation_order",
        ),
        (
            "position_m = 10.0",
            "position_m = 0.0",
            "filter.initial_sigma.position_m",
        ),
        (
            "truth_substeps_per_frame = 16",
            "truth_substeps_per_frame = 0",
            "simulation.truth_substeps_per_frame",
        ),
    ];
    for (original, replacement, key) in cases {
        assert!(DEFAULT_SCENARIO_TOML.contains(original), "{original}");
        let text = DEFAULT_SCENARIO_TOML.replacen(original, replacement, 1);
        assert_eq!(invalid_key(&text), key);
    }
}

#[test]
fn manoeuvre_errors_name_the_segment() {
    // The second segment (index 1) is "rotate about body x", 19 s, ramp 1 s.
    let text = DEFAULT_SCENARIO_TOML.replacen(
        "duration_s = 19.0\nramp_s = 1.0",
        "duration_s = 19.0\nramp_s = 10.0",
        1,
    );
    assert_eq!(invalid_key(&text), "manoeuvre[1].ramp_s");
    let text = DEFAULT_SCENARIO_TOML.replacen("duration_s = 19.0", "duration_s = 19.0001", 1);
    assert_eq!(invalid_key(&text), "manoeuvre[1].duration_s");
    let message = Scenario::from_toml_str(&text).unwrap_err().to_string();
    assert!(message.contains("whole number of IMU frames"), "{message}");
}

#[test]
fn load_names_the_file() {
    let missing = Path::new("/nonexistent/scenario.toml");
    let message = Scenario::load(missing).unwrap_err().to_string();
    assert!(message.contains("/nonexistent/scenario.toml"), "{message}");

    let directory = std::env::temp_dir().join(format!("nav-sim-test-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    let path = directory.join("bad.toml");
    std::fs::write(
        &path,
        DEFAULT_SCENARIO_TOML.replace(
            "rate_hz = 10.0\n# ECEF position noise",
            "rate_hz = -1.0\n# ECEF position noise",
        ),
    )
    .unwrap();
    let message = Scenario::load(&path).unwrap_err().to_string();
    assert!(message.contains("bad.toml"), "{message}");
    assert!(message.contains("gnss.rate_hz must be > 0"), "{message}");
    let good = directory.join("good.toml");
    std::fs::write(&good, DEFAULT_SCENARIO_TOML).unwrap();
    assert_eq!(
        Scenario::load(&good).unwrap(),
        Scenario::default_scenario().unwrap()
    );
    std::fs::remove_dir_all(&directory).unwrap();
}

/// The default scenario with `extra` appended after the `key = value` line `after`.
fn with_lines(after: &str, extra: &str) -> String {
    assert_eq!(DEFAULT_SCENARIO_TOML.matches(after).count(), 1, "{after}");
    DEFAULT_SCENARIO_TOML.replace(after, &format!("{after}\n{extra}"))
}

#[test]
fn imu_misalignment_g_sensitivity_and_bias_instability_keys_parse_and_default_to_off() {
    let default = Scenario::default_scenario().unwrap();
    assert_eq!(default.gyro.misalignment_rad, [[0.0; 3]; 3]);
    assert_eq!(
        default.gyro.g_sensitivity_rad_s_per_mps2.map(f64::to_bits),
        [0.0; 3].map(f64::to_bits)
    );
    assert_eq!(
        f64::to_bits(default.gyro.bias_instability_sigma_rad_per_s),
        f64::to_bits(0.0)
    );
    assert_eq!(default.accelerometer.misalignment_rad, [[0.0; 3]; 3]);
    assert_eq!(
        f64::to_bits(default.accelerometer.bias_instability_sigma_mps2),
        f64::to_bits(0.0)
    );
    // Absent (or zero) keys leave the Debug rendering, the campaign's scenario hash, as it was.
    let rendering = format!("{default:?}");
    for key in ["misalignment", "g_sensitivity", "bias_instability"] {
        assert!(!rendering.contains(key), "{key}");
    }
    assert!(rendering.contains(
        "GyroErrors { rate_noise_density_deg_per_h_per_sqrt_hz: 0.2, bias_rad_per_s: \
         [0.0001, 0.0002, 0.0003], scale_factor: [3e-5, 3e-5, 3e-5], \
         bias_random_walk_rad_per_s_per_sqrt_s: 0.0, quantum_rad: 0.0 }"
    ));
    assert!(rendering.contains(
        "AccelerometerErrors { noise_per_sample_mps2: 0.0001, bias_mps2: [0.003, -0.002, \
         0.001], scale_factor: [5e-5, -4e-5, 6e-5], bias_random_walk_mps2_per_sqrt_s: 0.0, \
         quantum_mps: 0.0 }"
    ));
    let text = with_lines(
        "quantum_rad = 0.0",
        "misalignment_rad = [[0.0, 1.0e-5, -2.0e-5], [3.0e-5, 0.0, 0.0], [0.0, 0.0, 0.0]]\n\
         g_sensitivity_rad_s_per_mps2 = [1.0e-6, 0.0, -2.0e-6]\n\
         bias_instability_sigma_rad_per_s = 5.0e-8\n\
         bias_instability_correlation_time_s = 600.0",
    );
    let text = text.replace(
        "quantum_mps = 0.0",
        "quantum_mps = 0.0\nmisalignment_rad = [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0e-4], \
         [0.0, 0.0, 0.0]]\nbias_instability_sigma_mps2 = 1.0e-5\n\
         bias_instability_correlation_time_s = 300.0",
    );
    let scenario = Scenario::from_toml_str(&text).unwrap();
    assert_eq!(
        f64::to_bits(scenario.gyro.misalignment_rad[0][2]),
        f64::to_bits(-2.0e-5)
    );
    assert_eq!(
        f64::to_bits(scenario.gyro.misalignment_rad[1][0]),
        f64::to_bits(3.0e-5)
    );
    assert_eq!(
        f64::to_bits(scenario.gyro.g_sensitivity_rad_s_per_mps2[2]),
        f64::to_bits(-2.0e-6)
    );
    assert_eq!(
        f64::to_bits(scenario.gyro.bias_instability_correlation_time_s),
        f64::to_bits(600.0)
    );
    assert_eq!(
        f64::to_bits(scenario.accelerometer.misalignment_rad[1][2]),
        f64::to_bits(1.0e-4)
    );
    assert_eq!(
        f64::to_bits(scenario.accelerometer.bias_instability_sigma_mps2),
        f64::to_bits(1.0e-5)
    );
    let rendering = format!("{scenario:?}");
    for key in [
        "misalignment_rad: [[0.0, 1e-5, -2e-5]",
        "g_sensitivity_rad_s_per_mps2: [1e-6, 0.0, -2e-6]",
        "bias_instability_sigma_rad_per_s: 5e-8, bias_instability_correlation_time_s: 600.0",
        "bias_instability_sigma_mps2: 1e-5, bias_instability_correlation_time_s: 300.0",
    ] {
        assert!(rendering.contains(key), "{key}: {rendering}");
    }
}

#[test]
fn out_of_range_imu_error_terms_are_refused_naming_the_key() {
    let gyro = |extra: &str| invalid_key(&with_lines("quantum_rad = 0.0", extra));
    let accelerometer = |extra: &str| invalid_key(&with_lines("quantum_mps = 0.0", extra));
    assert_eq!(
        gyro("misalignment_rad = [[0.0, 0.0, 0.0], [0.0, 1.0e-5, 0.0], [0.0, 0.0, 0.0]]"),
        "gyro.misalignment_rad[1][1]"
    );
    assert_eq!(
        gyro("misalignment_rad = [[0.0, 0.0, 0.02], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]"),
        "gyro.misalignment_rad[0][2]"
    );
    assert_eq!(
        accelerometer("misalignment_rad = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [nan, 0.0, 0.0]]"),
        "accelerometer.misalignment_rad[2][0]"
    );
    assert_eq!(
        gyro("g_sensitivity_rad_s_per_mps2 = [0.0, -2.0e-3, 0.0]"),
        "gyro.g_sensitivity_rad_s_per_mps2[1]"
    );
    assert_eq!(
        gyro("bias_instability_sigma_rad_per_s = -1.0e-6"),
        "gyro.bias_instability_sigma_rad_per_s"
    );
    assert_eq!(
        gyro("bias_instability_sigma_rad_per_s = 1.0e-6"),
        "gyro.bias_instability_correlation_time_s"
    );
    assert_eq!(
        accelerometer("bias_instability_sigma_mps2 = 1.0e200"),
        "accelerometer.bias_instability_sigma_mps2"
    );
    assert_eq!(
        accelerometer(
            "bias_instability_sigma_mps2 = 1.0e-5\nbias_instability_correlation_time_s = -3.0"
        ),
        "accelerometer.bias_instability_correlation_time_s"
    );
    let text = with_lines(
        "quantum_rad = 0.0",
        "misalignment_rad = [[0.0, 0.0, 0.02], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]",
    );
    let message = Scenario::from_toml_str(&text).unwrap_err().to_string();
    assert!(
        message.contains("= 0.02 rad in magnitude is above the limit 0.01 rad"),
        "{message}"
    );
    // The dispersion entries' widths.
    let text = format!(
        "{DEFAULT_SCENARIO_TOML}\n[dispersion]\n\
         gyro_g_sensitivity_rad_s_per_mps2 = {{ kind = \"normal\", sigma = -1.0e-6 }}\n"
    );
    assert_eq!(
        invalid_key(&text),
        "dispersion.gyro_g_sensitivity_rad_s_per_mps2.sigma"
    );
    let text = format!(
        "{DEFAULT_SCENARIO_TOML}\n[dispersion]\n\
         accelerometer_misalignment_rad = {{ kind = \"uniform\", half_width = nan }}\n"
    );
    assert_eq!(
        invalid_key(&text),
        "dispersion.accelerometer_misalignment_rad.half_width"
    );
}

#[test]
fn the_filters_bias_instability_parses_renders_only_when_on_and_is_validated() {
    let default = Scenario::default_scenario().unwrap();
    assert!(!default.filter.bias_instability.is_on());
    assert!(!format!("{default:?}").contains("bias_instability:"));
    let table =
        |lines: &str| format!("{DEFAULT_SCENARIO_TOML}\n[filter.bias_instability]\n{lines}");
    let scenario = Scenario::from_toml_str(&table(
        "gyro_sigma_rad_per_s = 1.0e-6\ngyro_correlation_time_s = 600.0",
    ))
    .unwrap();
    let instability = scenario.filter.bias_instability;
    assert!(instability.is_on());
    assert_eq!(
        [
            instability.gyro_sigma_rad_per_s,
            instability.gyro_correlation_time_s,
            instability.accel_sigma_mps2,
        ]
        .map(f64::to_bits),
        [1.0e-6, 600.0, 0.0].map(f64::to_bits)
    );
    assert!(format!("{scenario:?}").contains(
        "bias_instability: FilterBiasInstability { gyro_sigma_rad_per_s: 1e-6, \
         gyro_correlation_time_s: 600.0"
    ));
    for (lines, key) in [
        (
            "gyro_sigma_rad_per_s = 1.0e-6",
            "filter.bias_instability.gyro_correlation_time_s",
        ),
        (
            "accel_sigma_mps2 = -1.0e-5\naccel_correlation_time_s = 60.0",
            "filter.bias_instability.accel_sigma_mps2",
        ),
        (
            "accel_correlation_time_s = -60.0",
            "filter.bias_instability.accel_correlation_time_s",
        ),
        (
            "gyro_sigma_rad_per_s = 1.0e200\ngyro_correlation_time_s = 60.0",
            "filter.bias_instability.gyro_sigma_rad_per_s",
        ),
    ] {
        assert_eq!(invalid_key(&table(lines)), key, "{lines}");
    }
}

/// `[filter.imu_errors]`: absent is off (and absent from `Debug`, so the scenario hash is
/// unchanged); a partial table or a bad value is refused naming the key; beside the
/// correlated GNSS error states it is accepted.
#[test]
fn the_filters_imu_error_states_parse_render_only_when_on_and_are_validated() {
    let default = Scenario::default_scenario().unwrap();
    assert!(!default.filter.imu_errors.is_on());
    assert!(!format!("{default:?}").contains("imu_errors"));
    let table = |lines: &str| format!("{DEFAULT_SCENARIO_TOML}\n[filter.imu_errors]\n{lines}");
    let on = "gyro_misalignment_sigma_rad = 2.0e-5\naccel_misalignment_sigma_rad = 2.0e-5\n\
              gyro_g_sensitivity_sigma_rad_s_per_mps2 = 2.47e-7";
    let scenario = Scenario::from_toml_str(&table(on)).unwrap();
    assert!(scenario.filter.imu_errors.is_on());
    assert!(format!("{scenario:?}").contains("imu_errors: FilterImuErrors"));
    for (lines, key) in [
        (
            "gyro_misalignment_sigma_rad = 2.0e-5",
            "filter.imu_errors.accel_misalignment_sigma_rad",
        ),
        (
            "gyro_misalignment_sigma_rad = 2.0e-5\naccel_misalignment_sigma_rad = -1e-5\n\
             gyro_g_sensitivity_sigma_rad_s_per_mps2 = 2.47e-7",
            "filter.imu_errors.accel_misalignment_sigma_rad",
        ),
    ] {
        assert_eq!(invalid_key(&table(lines)), key, "{lines}");
    }
    let with_gnss = table(on).replace(
        "# gnss_correlated_sigma_m = 0.0",
        "gnss_correlated_sigma_m = 8.0\ngnss_correlation_time_s = 300.0",
    );
    // With the correlated GNSS error states too.
    assert!(Scenario::from_toml_str(&with_gnss)
        .unwrap()
        .filter
        .imu_errors
        .is_on());
}

/// A rotation vector is refused beyond one turn, naming its key and size; one turn is
/// accepted.
#[test]
fn rotation_vectors_beyond_one_turn_are_refused_naming_the_key() {
    let attitude = "rotation_vector_deg = [10.0, -20.0, 30.0]";
    for (original, replacement, key, size) in [
        (
            attitude,
            "rotation_vector_deg = [1.0e300, -20.0, 30.0]",
            "initial_attitude.rotation_vector_deg",
            "a component of magnitude 1e300 deg",
        ),
        (
            attitude,
            "rotation_vector_deg = [300.0, 0.0, 400.0]",
            "initial_attitude.rotation_vector_deg",
            "a norm of 500 deg",
        ),
        (
            "installation_error_rotation_vector_rad = [1.0e-3",
            "installation_error_rotation_vector_rad = [7.0",
            "star_sensor.installation_error_rotation_vector_rad",
            "more than one turn (6.283185307 rad)",
        ),
    ] {
        let text = DEFAULT_SCENARIO_TOML.replacen(original, replacement, 1);
        assert_eq!(invalid_key(&text), key, "{replacement}");
        let message = Scenario::from_toml_str(&text).unwrap_err().to_string();
        assert!(message.contains(size), "{message}");
    }
    let one_turn =
        DEFAULT_SCENARIO_TOML.replacen(attitude, "rotation_vector_deg = [0.0, 360.0, 0.0]", 1);
    assert!(Scenario::from_toml_str(&one_turn).is_ok());
}
