//! Tests of the parameter table: its defaults, ranges, companions, rules, words and messages.

use super::*;
use crate::error::{ConfigField, FswError};
use crate::replay::{INITIAL_NAVIGATION_WORDS, SETUP_WORDS};

pub(crate) fn site() -> LaunchSite {
    LaunchSite {
        latitude_rad: 0.715,
        longitude_rad: 1.750,
        height_m: 1000.0,
        azimuth_rad: 3.316,
        earth_axis_ecef: [0.0, 0.0, 1.0],
    }
}

fn defaults() -> FswConfig {
    FswConfig::paper_defaults(site(), SensorFrames::ALIGNED)
}

/// A valid second head, so the head's parameters apply.
fn with_head() -> FswConfig {
    let mut config = defaults();
    config.star.second_head = Some(StarHeadConfig {
        mounting_wxyz: [0.5, 0.5, 0.5, 0.5],
        noise_rad: 2.4e-5,
        roll_noise_rad: 1.7e-4,
        alignment_prior_sigma_rad: 1.4e-2,
        pair_gate_nis: GATE_NIS,
        pairs_before_hand_over: 100,
    });
    config
}

/// The field `corrupt` makes `validate` report, `None` if it validates.
fn refused(corrupt: impl Fn(&mut FswConfig)) -> Option<ConfigField> {
    let mut config = with_head();
    corrupt(&mut config);
    match config.validate() {
        Err(FswError::InvalidConfiguration(field)) => Some(field),
        _ => None,
    }
}

fn message(field: ConfigField) -> std::string::String {
    std::format!("{}", FswError::InvalidConfiguration(field))
}

#[test]
fn the_table_sets_every_value_of_the_defaults_and_they_validate() {
    let config = defaults();
    let text = std::format!("{config:?}");
    assert!(
        !text.contains("NaN"),
        "a value the table does not set: {text}"
    );
    assert_eq!(config.validate(), Ok(()));
    assert_eq!(with_head().validate(), Ok(()));
    for param in Param::ALL {
        if let Some(default) = param.default_value() {
            assert_eq!(
                default.to_bits(),
                param.value(&config).to_bits(),
                "{}",
                param.path()
            );
            assert!(param.range().contains(default), "{}", param.path());
        }
    }
    // The parts' defaults are the table's.
    assert_eq!(crate::input_check::ImuLimits::default(), config.imu);
    assert_eq!(
        crate::consistency::ConsistencyConfig::default(),
        config.consistency
    );
    assert_eq!(
        crate::calibration_manager::CalibrationManagerConfig::default(),
        config.calibration
    );
}

#[test]
fn paths_are_unique_and_the_words_fill_the_setup_once_each() {
    let mut owners = [0_usize; SETUP_WORDS];
    owners[0] += 1;
    for index in INITIAL_NAVIGATION_WORDS {
        owners[index] += 1;
    }
    for (index, param) in Param::ALL.iter().enumerate() {
        if let Some(word) = param.word() {
            owners[word] += 1;
        }
        let later = &Param::ALL[index + 1..];
        assert!(later.iter().all(|other| other.path() != param.path()));
    }
    assert_eq!(owners, [1; SETUP_WORDS]);
}

/// Each parameter's range where the table puts it: the ends accepted, just beyond them and
/// NaN refused, naming the parameter (through `Param::check`, whatever the other values).
#[test]
fn every_range_boundary_is_where_the_table_puts_it() {
    for param in Param::ALL {
        let range = param.range();
        let check = |value: f64| param.check(value);
        let refusal = Err(FswError::InvalidConfiguration(ConfigField::Parameter(
            *param,
        )));
        assert_eq!(check(range.high), Ok(()), "{}", param.path());
        assert_eq!(check(f64::NAN), refusal, "{}", param.path());
        let above = range.high + range.high.abs().max(1.0) * 1e-9;
        if !range.infinity_is_off {
            assert_eq!(check(above), refusal, "{}", param.path());
        }
        let below = range.low - range.low.abs().max(1e-300) * 1e-9;
        assert_eq!(check(below), refusal, "{}", param.path());
        let low = if range.low_open { refusal } else { Ok(()) };
        assert_eq!(check(range.low), low, "{}", param.path());
        assert_eq!(check(0.0).is_ok(), range.zero_is_off || range.contains(0.0));
    }
}

/// Every parameter that a number can put out of range is reported by `validate`, before any
/// rule between values: a NaN for an `f64`, one beyond the range for a count.
#[test]
fn validate_names_every_parameter_out_of_range() {
    for param in Param::ALL {
        let range = param.range();
        if !range.choices.is_empty() {
            continue;
        }
        let mut config = with_head();
        if param.set_word(&mut config, f64::NAN.to_bits()).is_err() {
            // A count: the NaN's bits are no count.
            // One beyond the range; a range that is the whole type has no such count.
            let word = range.high as u64 + 1;
            if param.set_word(&mut config, word).is_err() {
                continue;
            }
        }
        assert_eq!(
            config.validate(),
            Err(FswError::InvalidConfiguration(ConfigField::Parameter(
                *param
            ))),
            "{}",
            param.path()
        );
    }
}

/// The inputs the table was made to refuse: each names its key, its range and its unit.
#[test]
fn the_absurd_inputs_are_refused_naming_key_range_and_unit() {
    use Param as P;
    let slow_tau = refused(|c| {
        c.star.slow_error_sigma_rad = [1e-5; 3];
        c.star.slow_error_correlation_time_s = 1e-300;
    });
    assert_eq!(
        slow_tau,
        Some(ConfigField::Parameter(P::StarSlowErrorCorrelationTime))
    );
    let gnss_tau = refused(|c| {
        c.filter.gnss_error.sigma_m = 8.0;
        c.filter.gnss_error.correlation_time_s = 1e-300;
    });
    assert_eq!(
        gnss_tau,
        Some(ConfigField::Parameter(P::GnssCorrelationTime))
    );
    assert_eq!(
        message(ConfigField::Parameter(P::GnssCorrelationTime)),
        "invalid configuration: filter.gnss_error.correlation_time_s must be 0 (off) or in \
         [1, 1e8] s (below 1 s (500 frames) the error is white noise to the filter, whose walk \
         2 sigma^2 / tau would swamp the covariance every frame; beyond 1e8 s (three years) it \
         is a constant over any flight: 0 (off) leaves it to the constant states)"
    );
    let prior = refused(|c| {
        c.filter.imu_error = nav_core::imu_error_states::ImuErrorModel {
            gyro_misalignment_sigma_rad: 1.0,
            accel_misalignment_sigma_rad: 2e-5,
            gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7,
        };
    });
    assert_eq!(
        prior,
        Some(ConfigField::Parameter(P::GyroMisalignmentSigma))
    );
    assert!(message(prior.unwrap()).contains(
        "filter.imu_error.gyro_misalignment_sigma_rad must be 0 (off) or in [1e-9, 0.01] rad"
    ));
    let terms = refused(|c| c.gravity.field.terms_per_frame = 255);
    assert_eq!(terms, Some(ConfigField::Parameter(P::GravityTermsPerFrame)));
    assert!(message(terms.unwrap())
        .contains("gravity.field.terms_per_frame must be in [1, 8] (the frame budget"));
    assert_eq!(refused(|c| c.gravity.field.terms_per_frame = 8), None);
    let pairs = refused(|c| {
        if let Some(head) = c.star.second_head.as_mut() {
            head.pairs_before_hand_over = 0;
        }
    });
    assert_eq!(
        pairs,
        Some(ConfigField::Parameter(P::HeadPairsBeforeHandOver))
    );
    assert!(message(pairs.unwrap())
        .contains("star.second_head.pairs_before_hand_over must be in [1, 100000] pairs"));
}

#[test]
fn parameters_that_go_together_are_refused_alone() {
    use Param as P;
    let imu_error = nav_core::imu_error_states::ImuErrorModel {
        gyro_misalignment_sigma_rad: 2e-5,
        accel_misalignment_sigma_rad: 2e-5,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7,
    };
    assert_eq!(refused(|c| c.filter.imu_error = imu_error), None);
    assert_eq!(
        refused(|c| {
            c.filter.imu_error = imu_error;
            c.filter.imu_error.accel_misalignment_sigma_rad = 0.0;
        }),
        Some(ConfigField::Companion(
            P::GyroMisalignmentSigma,
            P::AccelMisalignmentSigma
        ))
    );
    let alone = refused(|c| c.filter.gnss_error.sigma_m = 8.0);
    assert_eq!(
        alone,
        Some(ConfigField::Companion(
            P::GnssCorrelatedSigma,
            P::GnssCorrelationTime
        ))
    );
    assert!(message(alone.unwrap()).contains(
        "filter.gnss_error.correlation_time_s must be 0 (off) or in [1, 1e8] s and not 0 while \
         filter.gnss_error.sigma_m is on"
    ));
    // Without the feature `gravity-field` there is no allowance: its range refuses it first.
    let allowance_alone = if cfg!(feature = "gravity-field") {
        ConfigField::Companion(P::OmittedFieldPsd, P::OmittedFieldSigma)
    } else {
        ConfigField::Parameter(P::OmittedFieldPsd)
    };
    assert_eq!(
        refused(|c| c.gravity.omitted_field_psd_m2_per_s3 = 1e-7),
        Some(allowance_alone)
    );
    assert_eq!(
        refused(|c| c.star.slow_error_sigma_rad[2] = 1e-5),
        Some(ConfigField::Companion(
            P::StarSlowErrorZ,
            P::StarSlowErrorCorrelationTime
        ))
    );
}

#[test]
fn the_rules_between_values_name_their_key() {
    let half = core::f64::consts::FRAC_1_SQRT_2;
    for mounting in [[0.5, 0.5, -0.5, 0.5], [0.0, half, 0.0, half]] {
        assert_eq!(refused(|c| c.star.mounting_wxyz = mounting), None);
    }
    assert_eq!(
        refused(|c| c.star.mounting_wxyz = [0.0, 0.0, 0.0, 1.0 - 2e-9]),
        Some(ConfigField::StarMounting)
    );
    assert_eq!(
        refused(|c| {
            if let Some(head) = c.star.second_head.as_mut() {
                head.mounting_wxyz = [0.0, 0.6, 0.6, 0.6];
            }
        }),
        Some(ConfigField::StarSecondHead)
    );
    // The latency may span the whole history, (64 − 1) frames, and no more.
    let period = defaults().imu.period_s;
    assert_eq!(refused(|c| c.timing.max_latency_s = 63.0 * period), None);
    assert_eq!(
        refused(|c| c.timing.max_latency_s = 63.0 * period * (1.0 + 1e-12)),
        Some(ConfigField::MaxLatency)
    );
    assert_eq!(
        refused(|c| c.timing.future_tolerance_s = period),
        Some(ConfigField::FutureTolerance)
    );
    assert_eq!(
        refused(|c| c.timing.future_tolerance_s = 0.999 * period),
        None
    );
    // Without the feature `gravity-field` the order's range (0 alone) refuses it first.
    let order_above_degree = if cfg!(feature = "gravity-field") {
        ConfigField::Gravity
    } else {
        ConfigField::Parameter(Param::GravityOrder)
    };
    assert_eq!(
        refused(|c| c.gravity.field.order = 3),
        Some(order_above_degree)
    );
    assert_eq!(
        refused(|c| c.launch_site.earth_axis_ecef = [0.0, 0.01, 0.99995]),
        Some(ConfigField::LaunchSite)
    );
}

#[test]
fn the_rule_texts_quote_the_limits_the_checks_use() {
    let text = |field: ConfigField| std::format!("{field}");
    assert!(text(ConfigField::MaxLatency).starts_with("timing.max_latency_s must be"));
    let span = std::format!("{} IMU periods", history_span_frames());
    assert!(text(ConfigField::MaxLatency).contains(&span));
    let span_ms = std::format!("{:.0} ms", 1e3 * max_latency_limit_s(0.002));
    assert!(
        text(ConfigField::MaxLatency).contains(&span_ms),
        "{span_ms}"
    );
    let tolerance = std::format!("{:e}", nav_core::attitude::UNIT_NORM_TOLERANCE);
    for field in [ConfigField::StarMounting, ConfigField::SensorFrames] {
        assert!(field.rule().contains(&tolerance), "{field}");
    }
    let interval = std::format!("[1, {MAX_PROPAGATION_INTERVAL_FRAMES}] frames");
    assert!(text(ConfigField::Parameter(Param::PropagationInterval)).contains(&interval));
    let (low, high) = nav_core::frames::SITE_HEIGHT_RANGE_M;
    let height = std::format!("[{low}, {high}] m");
    assert!(text(ConfigField::Parameter(Param::LaunchHeight)).contains(&height));
    let order = std::format!("in [1, {}] (", nav_core::discretise::MAX_ORDER);
    assert!(text(ConfigField::Parameter(Param::FilterDiscretisationOrder)).contains(&order));
    assert_eq!(
        text(ConfigField::Parameter(Param::FilterMode)),
        "filter.mode must be one of open_loop, closed_loop (the two filter modes)"
    );
    assert!(text(ConfigField::Parameter(Param::StarGate))
        .starts_with("star.gate_nis must be in [1, 1e6] or +inf (no gate) ("));
}

/// The ranges written as numbers are nav-core's limits.
#[test]
fn the_count_ranges_are_nav_cores_limits() {
    let high = |param: Param| param.range().high;
    let order = f64::from(nav_core::discretise::MAX_ORDER);
    assert_eq!(
        high(Param::FilterDiscretisationOrder).to_bits(),
        order.to_bits()
    );
    let degree = u32::try_from(nav_core::gravity::egm2008::FLIGHT_MAX_DEGREE).unwrap();
    // Without the feature `gravity-field` the build flies point mass + `J2` alone.
    let (degree, order) = if cfg!(feature = "gravity-field") {
        (degree, degree)
    } else {
        (2, 0)
    };
    assert_eq!(
        high(Param::GravityDegree).to_bits(),
        f64::from(degree).to_bits()
    );
    assert_eq!(
        high(Param::GravityOrder).to_bits(),
        f64::from(order).to_bits()
    );
}

/// Every 1σ and noise range keeps its square a normal `f64` ([`sigma_is_squarable`]).
#[test]
fn every_range_squares_inside_the_normal_f64_range() {
    for param in Param::ALL {
        let range = param.range();
        if range.choices.is_empty() && range.low > 0.0 {
            assert!(sigma_is_squarable(range.low), "{}", param.path());
            assert!(sigma_is_squarable(range.high), "{}", param.path());
        }
    }
}

#[test]
fn the_unit_conversions_and_the_default_star_noise_have_their_values() {
    // 1″ = π / 648,000 rad; the paper's star sensor is 10″ (1σ).
    assert!((ARCSEC_TO_RAD - 4.848_136_811_095_36e-6).abs() < 1e-20);
    let star = defaults().star;
    assert!((star.noise_rad - 4.848_136_811_095_36e-5).abs() < 1e-19);
    assert_eq!(star.roll_noise_rad.to_bits(), star.noise_rad.to_bits());
    for gate in [
        star.gate_nis,
        defaults().gnss.gate_nis,
        defaults().gnss.velocity_gate_nis,
    ] {
        assert_eq!(gate.to_bits(), GATE_NIS.to_bits());
    }
}

/// Without the feature `gravity-field` the build flies point mass + `J2` alone: the paper's
/// configuration validates, and one that asks for the field beyond `J2` or for an allowance
/// for the omitted field is refused, naming the parameter and the feature.
#[cfg(not(feature = "gravity-field"))]
#[test]
fn without_the_gravity_field_a_configuration_beyond_j2_is_refused() {
    use Param as P;
    assert_eq!(defaults().validate(), Ok(()));
    assert_eq!(refused(|c| c.gravity.field.terms_per_frame = 8), None);
    type Corrupt = fn(&mut FswConfig);
    let cases: [(Corrupt, Param); 5] = [
        (|c| c.gravity.field.degree = 3, P::GravityDegree),
        (|c| c.gravity.field.order = 1, P::GravityOrder),
        (
            |c| {
                c.gravity.field.degree = 12;
                c.gravity.field.order = 12;
            },
            P::GravityDegree,
        ),
        (
            |c| {
                c.gravity.omitted_field_sigma_mps2 = 2.0e-5;
                c.gravity.omitted_field_psd_m2_per_s3 = 1.0e-8;
            },
            P::OmittedFieldSigma,
        ),
        (
            |c| c.gravity.omitted_field_psd_m2_per_s3 = 1.0e-8,
            P::OmittedFieldPsd,
        ),
    ];
    for (corrupt, param) in cases {
        let field = refused(corrupt);
        assert_eq!(field, Some(ConfigField::Parameter(param)));
        let text = message(ConfigField::Parameter(param));
        assert!(text.contains(param.path()), "{text}");
        assert!(text.contains("feature gravity-field off"), "{text}");
    }
}
