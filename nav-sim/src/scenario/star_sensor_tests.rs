//! Unit tests of the `[star_sensor]` table's optional truth keys: parsing, the `Debug`
//! rendering (the scenario hash) and validation.

use crate::scenario::{Scenario, ScenarioError, DEFAULT_SCENARIO_TOML};

/// The default scenario with `lines` added to `[star_sensor]`.
fn with_star_lines(lines: &str) -> String {
    DEFAULT_SCENARIO_TOML.replacen(
        "noise_arcsec = 10.0\n",
        &format!("noise_arcsec = 10.0\n{lines}\n"),
        1,
    )
}

/// The key and message of the validation error of `text`.
fn refusal(text: &str) -> (String, String) {
    match Scenario::from_toml_str(text) {
        Err(error @ ScenarioError::Invalid { .. }) => {
            let message = error.to_string();
            let ScenarioError::Invalid { key, .. } = error else {
                unreachable!()
            };
            (key, message)
        }
        other => panic!("expected an Invalid error, got {other:?}"),
    }
}

#[test]
fn absent_keys_are_off_and_leave_the_rendering_as_it_was() {
    let default = Scenario::default_scenario().unwrap();
    let star = &default.star_sensor;
    assert!(!star.has_per_axis_noise() && !star.has_slow_error() && !star.has_periodic_error());
    assert_eq!(
        star.noise_per_axis_rad().map(f64::to_bits),
        [star.noise_rad().to_bits(); 3]
    );
    // The derived rendering before the keys existed, verbatim.
    assert!(format!("{default:?}").contains(
        "star_sensor: StarSensorSettings { rate_hz: 10.0, noise_arcsec: 10.0, \
         mounting_rotation_vector_deg: [0.0, -30.0, 0.0], \
         installation_error_rotation_vector_rad: [0.001, 0.002, 0.003], \
         max_rate_deg_per_s: 0.0, reacquisition_s: 0.0, outages: [] }"
    ));
    let text = with_star_lines(
        "cross_boresight_noise_arcsec = 5.0\nroll_noise_arcsec = 10.0\n\
         slow_error_sigma_arcsec = [3.0, 3.0, 1.0]\nslow_error_correlation_time_s = 1420.0\n\
         periodic_error_amplitude_arcsec = [1.0, 0.0, 0.0]\nperiodic_error_period_s = 5700.0",
    );
    let scenario = Scenario::from_toml_str(&text).unwrap();
    let rendering = format!("{scenario:?}");
    for key in [
        "cross_boresight",
        "roll_noise",
        "slow_error",
        "periodic_error",
    ] {
        assert!(rendering.contains(key), "{key}");
    }
    let star = &scenario.star_sensor;
    assert!(star.has_per_axis_noise() && star.has_slow_error() && star.has_periodic_error());
    let [x, y, z] = star.noise_per_axis_rad();
    assert_eq!(x.to_bits(), y.to_bits());
    assert_eq!(z.to_bits(), star.noise_rad().to_bits());
    assert!((z / x - 2.0).abs() < 1e-15, "{x} {z}");
}

#[test]
fn bad_star_truth_keys_are_refused_naming_the_key() {
    for (lines, key, words) in [
        (
            "cross_boresight_noise_arcsec = 5.0",
            "star_sensor.roll_noise_arcsec",
            "must be given with star_sensor.cross_boresight_noise_arcsec",
        ),
        (
            "roll_noise_arcsec = 5.0",
            "star_sensor.cross_boresight_noise_arcsec",
            "must be given with",
        ),
        (
            "cross_boresight_noise_arcsec = 5.0\nroll_noise_arcsec = 35.0",
            "star_sensor.noise_arcsec",
            "must equal the larger of them, 35",
        ),
        (
            "cross_boresight_noise_arcsec = -5.0\nroll_noise_arcsec = 10.0",
            "star_sensor.cross_boresight_noise_arcsec",
            "must be 0 (off) or in",
        ),
        (
            "slow_error_sigma_arcsec = [3.0, -1.0, 3.0]\nslow_error_correlation_time_s = 9.0",
            "star_sensor.slow_error_sigma_arcsec (y)",
            "must be 0 (off) or in",
        ),
        (
            "slow_error_sigma_arcsec = [3.0, 3.0, 3.0]",
            "star_sensor.slow_error_correlation_time_s",
            "must be > 0",
        ),
        (
            "slow_error_correlation_time_s = -1.0",
            "star_sensor.slow_error_correlation_time_s",
            "must be >= 0",
        ),
        (
            "periodic_error_amplitude_arcsec = [0.0, 0.0, 2.0]\nperiodic_error_period_s = inf",
            "star_sensor.periodic_error_period_s",
            "must be > 0",
        ),
        (
            "periodic_error_amplitude_arcsec = [nan, 0.0, 2.0]\nperiodic_error_period_s = 9.0",
            "star_sensor.periodic_error_amplitude_arcsec (x)",
            "must be 0 (off) or in",
        ),
        (
            "periodic_error_phase_deg = inf",
            "star_sensor.periodic_error_phase_deg",
            "must be finite",
        ),
    ] {
        let (refused_key, message) = refusal(&with_star_lines(lines));
        assert_eq!(refused_key, key, "{lines}");
        assert!(message.contains(words), "{message}");
    }
    // The per-axis keys with noise_arcsec their larger value are accepted.
    let text = with_star_lines("cross_boresight_noise_arcsec = 10.0\nroll_noise_arcsec = 2.0");
    assert!(Scenario::from_toml_str(&text).is_ok());
}

/// `aberration = "none"` is the absent key (same rendering, so the same scenario hash);
/// `"uncorrected"` renders; anything else is refused by the parser.
#[test]
fn the_aberration_key_parses_and_renders_only_when_on() {
    let default = Scenario::default_scenario().unwrap();
    let none = Scenario::from_toml_str(&with_star_lines("aberration = \"none\"")).unwrap();
    assert_eq!(format!("{none:?}"), format!("{default:?}"));
    let on = Scenario::from_toml_str(&with_star_lines("aberration = \"uncorrected\"")).unwrap();
    assert_eq!(
        on.star_sensor.aberration,
        crate::scenario::StarAberration::Uncorrected
    );
    assert!(format!("{on:?}").contains("aberration: Uncorrected"));
    assert!(Scenario::from_toml_str(&with_star_lines("aberration = \"corrected\"")).is_err());
}

/// The default scenario with one `[[star_sensor.additional_heads]]` table of `lines` (each a
/// complete head), placed after `[star_sensor]`'s keys.
fn with_heads(heads: &[&str]) -> String {
    let tables: String = heads
        .iter()
        .map(|lines| format!("[[star_sensor.additional_heads]]\n{lines}\n\n"))
        .collect();
    DEFAULT_SCENARIO_TOML.replacen("\n[gnss]\n", &format!("\n{tables}[gnss]\n"), 1)
}

/// A complete head 90° from head 0 (about body x), rate `rate_hz`.
fn head(rate_hz: f64) -> String {
    format!(
        "rate_hz = {rate_hz:?}\nnoise_arcsec = 10.0\nmounting_rotation_vector_deg = [90.0, 0.0, 0.0]\n\
         installation_error_rotation_vector_rad = [-3.0e-3, 1.0e-3, 2.0e-3]"
    )
}

#[test]
fn additional_heads_parse_render_and_keep_head_zero() {
    let default = Scenario::default_scenario().unwrap();
    assert!(default.star_sensor.additional_heads.is_empty());
    assert!(!format!("{default:?}").contains("additional_heads"));
    let two = Scenario::from_toml_str(&with_heads(&[&head(10.0), &head(10.0)])).unwrap();
    let star = &two.star_sensor;
    assert_eq!(star.heads().count(), 3);
    assert_eq!(
        star.additional_heads[1]
            .mounting_rotation_vector_deg
            .map(f64::to_bits),
        [90.0, 0.0, 0.0].map(f64::to_bits)
    );
    assert_eq!(star.additional_heads[0].outages, Vec::<[f64; 2]>::new());
    let mut without = star.clone();
    without.additional_heads.clear();
    assert_eq!(without, default.star_sensor);
    assert!(format!("{two:?}").contains("additional_heads: [StarSensorSettings { rate_hz: 10.0"));
}

#[test]
fn bad_additional_heads_are_refused_naming_the_head_and_the_key() {
    let other_rate = &head(5.0);
    let negative_noise = &head(10.0).replace("noise_arcsec = 10.0", "noise_arcsec = -1.0");
    let lone_roll = &format!("{}\nroll_noise_arcsec = 35.0", head(10.0));
    let bad_outage = &format!("{}\noutages = [[100.0, 0.0]]", head(10.0));
    let nested = &format!(
        "{}\n[[star_sensor.additional_heads.additional_heads]]\n{}",
        head(10.0),
        head(10.0)
    );
    for (heads, key, words) in [
        (
            vec![other_rate.as_str()],
            "star_sensor.additional_heads[0].rate_hz",
            "= 5 Hz differs from star_sensor.rate_hz = 10 Hz",
        ),
        (
            vec![&head(10.0), negative_noise],
            "star_sensor.additional_heads[1].noise_arcsec",
            "(star-tracker head 2)",
        ),
        (
            vec![lone_roll.as_str()],
            "star_sensor.additional_heads[0].cross_boresight_noise_arcsec",
            "must be given with star_sensor.additional_heads[0].roll_noise_arcsec",
        ),
        (
            vec![bad_outage.as_str()],
            "star_sensor.additional_heads[0].outages[0][1] (duration_s)",
            "(star-tracker head 1)",
        ),
        (
            vec![nested.as_str()],
            "star_sensor.additional_heads[0].additional_heads",
            "is not allowed in a head",
        ),
    ] {
        let (refused_key, message) = refusal(&with_heads(&heads));
        assert_eq!(refused_key, key, "{message}");
        assert!(message.contains(words), "{message}");
    }
    let eight = vec![head(10.0); 8];
    let eight: Vec<&str> = eight.iter().map(String::as_str).collect();
    let (key, message) = refusal(&with_heads(&eight));
    assert_eq!(key, "star_sensor.additional_heads");
    assert!(message.contains("9 heads"), "{message}");
    // An unknown or missing key in a head is the parser's error, naming it.
    let unknown =
        Scenario::from_toml_str(&with_heads(&[&format!("{}\nboresight = 1.0", head(10.0))]))
            .unwrap_err()
            .to_string();
    assert!(unknown.contains("boresight"), "{unknown}");
    let missing = Scenario::from_toml_str(&with_heads(&["rate_hz = 10.0\nnoise_arcsec = 10.0"]))
        .unwrap_err()
        .to_string();
    assert!(
        missing.contains("mounting_rotation_vector_deg"),
        "{missing}"
    );
}

/// The two-head scenario files: head 0 is the roll-noise file's tracker value for value but for
/// an outage over the middle third of the flight; head 1 has head 0's rate and noise, a
/// boresight 90° from head 0's and an installation error of head 0's size.
#[test]
fn the_two_head_scenario_files_are_their_single_head_files_plus_head_one() {
    let directory = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    for (two_heads, roll_noise) in [
        ("star_tracker_two_heads", "star_tracker_roll_noise"),
        (
            "upper_stage_star_tracker_two_heads",
            "upper_stage_star_tracker_roll_noise",
        ),
    ] {
        let load = |name: &str| Scenario::load(&directory.join(format!("{name}.toml"))).unwrap();
        let (two_heads, mut single) = (load(two_heads), load(roll_noise));
        let star = &two_heads.star_sensor;
        let [head_1] = star.additional_heads.as_slice() else {
            panic!("one additional head expected")
        };
        single.star_sensor.additional_heads = vec![head_1.clone()];
        single.star_sensor.outages = star.outages.clone();
        assert!(head_1.outages.is_empty());
        assert_eq!(format!("{single:?}"), format!("{two_heads:?}"));
        assert_eq!(head_1.rate_hz.to_bits(), star.rate_hz.to_bits());
        assert_eq!(
            head_1.noise_per_axis_rad().map(f64::to_bits),
            star.noise_per_axis_rad().map(f64::to_bits)
        );
        let boresight = |settings: &crate::scenario::StarSensorSettings| {
            let vector =
                nalgebra::Vector3::from(settings.mounting_rotation_vector_deg).map(f64::to_radians);
            nalgebra::UnitQuaternion::from_scaled_axis(vector) * nalgebra::Vector3::z()
        };
        let angle_deg = boresight(star).angle(&boresight(head_1)).to_degrees();
        assert!((angle_deg - 90.0).abs() < 1e-5, "{angle_deg}");
        let size = |psi: [f64; 3]| nalgebra::Vector3::from(psi).norm();
        let (size_0, size_1) = (
            size(star.installation_error_rotation_vector_rad),
            size(head_1.installation_error_rotation_vector_rad),
        );
        assert!((size_0 - size_1).abs() < 1e-15, "{size_0} {size_1}");
        assert_ne!(
            star.installation_error_rotation_vector_rad
                .map(f64::to_bits),
            head_1
                .installation_error_rotation_vector_rad
                .map(f64::to_bits)
        );
        let duration_s: f64 = two_heads.manoeuvres.iter().map(|m| m.duration_s).sum();
        let [[start_s, out_s]] = star.outages.as_slice() else {
            panic!("one outage expected")
        };
        assert!(
            (start_s - duration_s / 3.0).abs() < 1e-3,
            "{start_s} {duration_s}"
        );
        assert!(
            (out_s - duration_s / 3.0).abs() < 1e-3,
            "{out_s} {duration_s}"
        );
    }
}

/// The noise dispersion scales every head's noise by the one factor, per-axis keys included.
#[test]
fn the_noise_dispersion_scales_every_head() {
    let mut tracker = Scenario::default_scenario().unwrap().star_sensor;
    tracker.noise_arcsec = 10.0;
    tracker.roll_noise_arcsec = Some(10.0);
    tracker.cross_boresight_noise_arcsec = Some(4.0);
    let mut second = tracker.head_across();
    second.noise_arcsec = 20.0;
    tracker.additional_heads.push(second);
    tracker.scale_noise(1.5);
    let bits = |value: Option<f64>| value.map(f64::to_bits);
    assert_eq!(tracker.noise_arcsec.to_bits(), 15.0_f64.to_bits());
    assert_eq!(bits(tracker.roll_noise_arcsec), bits(Some(15.0)));
    assert_eq!(bits(tracker.cross_boresight_noise_arcsec), bits(Some(6.0)));
    assert_eq!(
        tracker.additional_heads[0].noise_arcsec.to_bits(),
        30.0_f64.to_bits()
    );
    assert!(tracker.additional_heads[0].additional_heads.is_empty());
}
