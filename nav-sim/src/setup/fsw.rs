//! The flight software's configuration for a scenario: what the scenario decides about it
//! (launch site, ground constants, filter settings, process noise, mounting, gates), the
//! initial navigation solution, and the scenario key behind each refused field.

use nalgebra::Vector3;
use nav_core::attitude;
use nav_core::error_model::ProcessNoise;
use nav_core::filter::{FilterConfig, FilterMode, InitialUncertainty};
use nav_core::strapdown::NavigationState;
use nav_fsw::config::{FswConfig, Param, StarHeadConfig};
use nav_fsw::datasheet;
use nav_fsw::replay::ReplaySetup;
use nav_fsw::{ConfigField, FswError};
use rand_distr::{Distribution, StandardNormal};

use crate::scenario::star_sensor::arcsec_to_rad;
use crate::scenario::{FilterMode as ScenarioFilterMode, Scenario};
use crate::setup::launch::{Launch, TruthState};
use crate::setup::streams::{self, Stream};
use crate::setup::{dispersion, SetupError};

/// The scenario key that sets a flight-software configuration field ([`replay_setup`]): a
/// `[filter]` key ([`crate::scenario::FilterSettings::FLIGHT_KEYS`]) or the truth's key the
/// flight is told of; `None` for a field the scenario leaves at the flight software's default.
pub fn scenario_key(field: ConfigField) -> Option<&'static str> {
    let param = match field {
        ConfigField::Parameter(param) | ConfigField::Companion(_, param) => param,
        ConfigField::MaxLatency => return Some("gnss.latency_s"),
        ConfigField::FutureTolerance => return Some("imu.rate_hz"),
        ConfigField::LaunchSite => return Some("launch_site"),
        ConfigField::SensorFrames => {
            return Some("launch_site.epoch_utc / launch_site.earth_orientation")
        }
        ConfigField::StarMounting => return Some("star_sensor.mounting_rotation_vector_deg"),
        ConfigField::StarSecondHead => return Some("star_sensor.additional_heads"),
        ConfigField::Gravity => return Some("filter.gravity.order"),
        ConfigField::InitialNavigation => return Some("initial_orbit / initial_attitude"),
        _ => return None,
    };
    crate::scenario::FilterSettings::flight_key(param).or_else(|| told_key(param))
}

/// The truth's key behind a flight parameter the scenario sets outside `[filter]`.
fn told_key(param: Param) -> Option<&'static str> {
    use Param as P;
    Some(match param {
        P::ImuPeriod => "imu.rate_hz",
        P::ImuMaxRate => "imu.max_rate_deg_per_s",
        P::ImuMaxSpecificForce => "imu.max_specific_force_mps2",
        P::MaxLatency => "gnss.latency_s",
        P::LaunchLatitude
        | P::LaunchLongitude
        | P::LaunchHeight
        | P::LaunchAzimuth
        | P::EarthAxisX
        | P::EarthAxisY
        | P::EarthAxisZ => "launch_site",
        P::LaunchEpochGpsWeek
        | P::LaunchEpochSecondsOfWeek
        | P::GcrfW
        | P::GcrfX
        | P::GcrfY
        | P::GcrfZ => "launch_site.epoch_utc / launch_site.earth_orientation",
        P::GyroNoiseDensity => "gyro.rate_noise_density_deg_per_h_per_sqrt_hz",
        P::AccelNoiseDensity => "accelerometer.noise_per_sample_mps2",
        P::GyroBiasWalk => {
            "gyro.bias_random_walk_rad_per_s_per_sqrt_s / filter.bias_instability.gyro_*"
        }
        P::AccelBiasWalk => {
            "accelerometer.bias_random_walk_mps2_per_sqrt_s / filter.bias_instability.accel_*"
        }
        P::StarMountingW | P::StarMountingX | P::StarMountingY | P::StarMountingZ => {
            "star_sensor.mounting_rotation_vector_deg"
        }
        P::StarNoise | P::StarRollNoise => {
            "filter.star_noise_arcsec (default star_sensor.noise_arcsec, or \
             cross_boresight_noise_arcsec / roll_noise_arcsec)"
        }
        P::GnssNoise => "filter.gnss_noise_m (default gnss.noise_m)",
        P::GnssVelocityNoise => "gnss.velocity_noise_mps",
        P::StarAberrationCorrection => "filter.star_aberration_correction",
        P::StarNoiseMatching => "filter.star_noise_matching",
        P::StarSecondHead => "filter.star_second_head",
        P::HeadMountingW
        | P::HeadMountingX
        | P::HeadMountingY
        | P::HeadMountingZ
        | P::HeadNoise
        | P::HeadRollNoise => "star_sensor.additional_heads",
        P::HeadAlignmentPrior => "filter.initial_sigma.star_installation_rad",
        P::HeadPairGate => "filter.nis_gate.star_threshold",
        P::FilterMode => "filter.mode",
        _ => return None,
    })
}

/// The flight software's refusal of the configuration made from `scenario`, as the user
/// reads it: the scenario key that sets the field ([`scenario_key`]), with its value and the
/// limit where the scenario determines them, and the flight software's rule.
pub fn configuration_error(scenario: &Scenario, error: FswError) -> SetupError {
    let period_s = scenario.imu.frame_period_s();
    let latency_s = scenario.gnss.latency_s;
    let message = match error {
        FswError::InvalidConfiguration(ConfigField::MaxLatency) => {
            crate::scenario::gnss_latency_violation(latency_s, period_s)
                .map(|requirement| format!("gnss.latency_s {requirement}"))
        }
        _ => None,
    };
    let message = message.unwrap_or_else(|| match error {
        FswError::InvalidConfiguration(field) => match scenario_key(field) {
            Some(key) => format!("{key} is refused: the flight software's {field}"),
            None => format!("the flight software's own setting {field} (not a scenario key)"),
        },
        FswError::Navigation(_) => error.to_string(),
    });
    SetupError::Configuration { error, message }
}

/// What the scenario decides about the flight software (its launch site, filter settings,
/// sensor noise as process-noise densities, star mounting, gates) and its initial navigation
/// solution: the truth at the start with errors drawn from the configured initial 1σ
/// (random stream [`Stream::InitialError`] of the scenario seed), so the initial
/// covariance is honest. The replay files carry exactly this.
///
/// # Errors
/// [`SetupError`] if the launch site or the initial state cannot be computed.
pub fn replay_setup(scenario: &Scenario) -> Result<ReplaySetup, SetupError> {
    replay_setup_for(scenario, &Launch::new(scenario)?)
}

/// [`replay_setup`] for a replay of a sensor log or on the target, which flies no ground
/// commands.
///
/// # Errors
/// [`SetupError::Setting`] naming `command` for a scenario that schedules commands (its
/// replay would silently differ from its flight); otherwise as [`replay_setup`].
pub fn replay_setup_without_commands(scenario: &Scenario) -> Result<ReplaySetup, SetupError> {
    if !scenario.commands.is_empty() {
        return Err(SetupError::Setting(format!(
            "command: the scenario schedules {} ground command(s), which a replay does not \
             fly; replay a scenario without [[command]]",
            scenario.commands.len()
        )));
    }
    replay_setup(scenario)
}

/// [`replay_setup`] for the scenario's `launch`, already computed.
///
/// # Errors
/// [`SetupError::Setting`] if the filter settings are refused.
pub fn replay_setup_for(scenario: &Scenario, launch: &Launch) -> Result<ReplaySetup, SetupError> {
    let settings = &scenario.filter;
    let filter = filter_config(scenario)?;
    let period_s = scenario.imu.frame_period_s();
    let (max_rate_rad_s, max_force_mps2) = scenario.imu.ranges_si();
    // The truth's white noise per sensor axis: cross-boresight (x, y) and roll (z) with the
    // per-axis keys, else `noise_arcsec` on every axis (the same bits as before).
    // `filter.star_noise_arcsec`, when given, on every axis instead.
    let [cross_rad, _, roll_rad] = settings.star_noise_arcsec.map_or_else(
        || scenario.star_sensor.noise_per_axis_rad(),
        |noise_arcsec| [arcsec_to_rad(noise_arcsec); 3],
    );
    let mut config = FswConfig::paper_defaults(launch.site, launch.ground.sensor_frames);
    config.filter = filter;
    config.process_noise = scenario_process_noise(scenario);
    config.imu.period_s = period_s;
    config.imu.max_rate_rad_s = max_rate_rad_s;
    config.imu.max_specific_force_mps2 = max_force_mps2;
    let star = &mut config.star;
    star.mounting_wxyz = datasheet::mounting_wxyz_from_rotation_vector_deg(
        scenario.star_sensor.mounting_rotation_vector_deg,
    );
    // A zero-noise sensor (a test setting) still needs a positive R. The flight software is
    // told the white noise per sensor axis; the slow errors are not modelled in its R.
    star.noise_rad = cross_rad.max(1e-12);
    star.roll_noise_rad = roll_rad.max(1e-12);
    star.gate_nis = settings.nis_gate.star_threshold;
    star.slow_error_sigma_rad = settings.star_slow_error.sigma_rad();
    star.slow_error_correlation_time_s = settings.star_slow_error.correlation_time_s;
    star.aberration_correction = settings.star_aberration_correction;
    star.noise_matching = settings.star_noise_matching;
    star.second_head = second_head(scenario, &filter);
    let gnss = &mut config.gnss;
    gnss.noise_m = settings
        .gnss_noise_m
        .unwrap_or(scenario.gnss.noise_m)
        .max(1e-6);
    gnss.gate_nis = settings.nis_gate.gnss_threshold;
    // The receiver's specification: 0 (no velocity output) turns velocity fusion off.
    gnss.velocity_noise_mps = scenario.gnss.velocity_noise_mps;
    config.timing.max_latency_s = datasheet::latency_window_s(
        config.timing.max_latency_s,
        scenario.gnss.latency_s,
        period_s,
    );
    config.gravity = settings.gravity.config();
    let initial = initial_navigation(scenario, &launch.truth_start);
    Ok(ReplaySetup::new(&config, initial))
}

/// Checks that the flight software takes every star head of `scenario` (`[star_sensor]` and its
/// `[[star_sensor.additional_heads]]`; nav-fsw `MAX_STAR_HEADS`): the commands that fly the
/// flight software on a campaign (`calibrate`, `monte-carlo`) refuse a tracker with more heads
/// rather than drop the further heads' measurements unseen. The simulator itself flies up to
/// [`crate::scenario::star_sensor::MAX_STAR_HEADS`] heads.
///
/// # Errors
/// [`SetupError::Setting`] naming `star_sensor.additional_heads`, the head count and the limit.
pub fn check_flight_star_heads(scenario: &Scenario) -> Result<(), SetupError> {
    let heads = 1 + scenario.star_sensor.additional_heads.len();
    let limit = nav_fsw::scheduler::MAX_STAR_HEADS;
    if heads > limit {
        return Err(SetupError::Setting(format!(
            "star_sensor.additional_heads gives {heads} star heads with [star_sensor], more \
             than the {limit} heads the flight software takes (nav-fsw MAX_STAR_HEADS): the \
             further heads' measurements would never reach it; give at most {} \
             [[star_sensor.additional_heads]] tables",
            limit - 1
        )));
    }
    Ok(())
}

/// The flight software's second tracker head: the scenario's first
/// `[[star_sensor.additional_heads]]` (its mounting and white noise per sensor axis), with
/// the relative alignment's prior from both heads' installation 1σ (the filter's,
/// `√2 σ_ψ`), the star gate for the pairs and `[filter] star_pairs_before_hand_over`; `None` without
/// additional heads or with `[filter] star_second_head = false`.
fn second_head(scenario: &Scenario, filter: &FilterConfig) -> Option<StarHeadConfig> {
    let head = scenario
        .star_sensor
        .additional_heads
        .first()
        .filter(|_| scenario.filter.star_second_head)?;
    let [cross_rad, _, roll_rad] = head.noise_per_axis_rad();
    Some(StarHeadConfig {
        mounting_wxyz: datasheet::mounting_wxyz_from_rotation_vector_deg(
            head.mounting_rotation_vector_deg,
        ),
        noise_rad: cross_rad.max(1e-12),
        roll_noise_rad: roll_rad.max(1e-12),
        alignment_prior_sigma_rad: datasheet::second_head_alignment_prior_rad(
            filter.initial.star_installation_rad,
        ),
        pair_gate_nis: scenario.filter.nis_gate.star_threshold,
        pairs_before_hand_over: scenario.filter.star_pairs_before_hand_over,
    })
}

/// The flight software configuration for a scenario ([`replay_setup`]).
///
/// # Errors
/// As [`replay_setup`].
pub fn fsw_config(scenario: &Scenario) -> Result<FswConfig, SetupError> {
    Ok(replay_setup(scenario)?.config())
}

/// The truth at the start with errors drawn from the scenario's initial 1σ.
fn initial_navigation(scenario: &Scenario, truth_start: &TruthState) -> NavigationState {
    let mut rng = streams::rng(scenario.simulation.seed, Stream::InitialError);
    let sigma = &scenario.filter.initial_sigma;
    let mut draw = |scale: f64| -> Vector3<f64> {
        Vector3::from_fn(|_, _| {
            let normal: f64 = StandardNormal.sample(&mut rng);
            normal * scale
        })
    };
    // A `[dispersion]` table's initial-state entries add to the error the σ describes, so the
    // filter starts with an error its initial covariance does not expect.
    let (attitude_offset, position_offset, velocity_offset) =
        dispersion::initial_error_offsets(scenario);
    let attitude_error = draw(sigma.attitude_rad) + attitude_offset;
    let position_error = draw(sigma.position_m) + position_offset;
    let velocity_error = draw(sigma.velocity_mps) + velocity_offset;
    NavigationState {
        attitude: attitude::product(
            &truth_start.attitude_q_ib,
            &attitude::exp_rotation_vector(&attitude_error),
        ),
        position_m: truth_start.position_m + position_error,
        velocity_mps: truth_start.velocity_mps + velocity_error,
        time_s: truth_start.time_s,
    }
}

/// The filter's process noise matching the scenario's sensors: the gyro's white rate-noise
/// density, the accelerometer's per-sample σ as a density `σ_f √T` (the same noise, see
/// [`crate::scenario::AccelerometerErrors::noise_density_mps2_per_sqrt_hz`]), and the bias
/// random walks.
pub fn scenario_process_noise(scenario: &Scenario) -> ProcessNoise {
    let instability = &scenario.filter.bias_instability;
    ProcessNoise {
        gyro_noise_density_rad_s_per_sqrt_hz: scenario.gyro.rate_noise_density_rad_per_sqrt_s(),
        accel_noise_density_mps2_per_sqrt_hz: scenario
            .accelerometer
            .noise_density_mps2_per_sqrt_hz(scenario.imu.frame_period_s()),
        gyro_bias_walk_rad_s2_per_sqrt_hz: datasheet::bias_walk_with_instability(
            scenario.gyro.bias_random_walk_rad_per_s_per_sqrt_s,
            instability.gyro_sigma_rad_per_s,
            instability.gyro_correlation_time_s,
        ),
        accel_bias_walk_mps3_per_sqrt_hz: datasheet::bias_walk_with_instability(
            scenario.accelerometer.bias_random_walk_mps2_per_sqrt_s,
            instability.accel_sigma_mps2,
            instability.accel_correlation_time_s,
        ),
    }
}

/// nav-core's filter configuration from the scenario's `[filter]` table.
///
/// # Errors
/// [`SetupError::Setting`] if the discretisation order does not fit nav-core's `u8`.
pub fn filter_config(scenario: &Scenario) -> Result<FilterConfig, SetupError> {
    let settings = &scenario.filter;
    let sigma = &settings.initial_sigma;
    let instability = &settings.bias_instability;
    let discretisation_order = u8::try_from(settings.discretisation_order).map_err(|_| {
        SetupError::Setting("filter.discretisation_order must be in 1..=4".to_string())
    })?;
    Ok(FilterConfig {
        mode: match settings.mode {
            ScenarioFilterMode::OpenLoop => FilterMode::OpenLoop,
            ScenarioFilterMode::ClosedLoop => FilterMode::ClosedLoop,
        },
        discretisation_order,
        initial: InitialUncertainty {
            attitude_rad: sigma.attitude_rad,
            position_m: sigma.position_m,
            velocity_mps: sigma.velocity_mps,
            gyro_bias_rad_s: datasheet::bias_prior_with_instability(
                sigma.gyro_bias_rad_per_s,
                instability.gyro_sigma_rad_per_s,
                instability.gyro_correlation_time_s,
            ),
            accel_bias_mps2: datasheet::bias_prior_with_instability(
                sigma.accel_bias_mps2,
                instability.accel_sigma_mps2,
                instability.accel_correlation_time_s,
            ),
            star_installation_rad: datasheet::bias_prior_with_instability(
                sigma.star_installation_rad,
                settings.star_slow_error.largest_sigma_rad(),
                settings.star_slow_error.correlation_time_s,
            ),
            gyro_scale_factor: sigma.gyro_scale_factor,
            accel_scale_factor: sigma.accel_scale_factor,
        },
        gnss_error: nav_core::gnss_error::GnssErrorModel {
            sigma_m: settings.gnss_correlated_sigma_m,
            correlation_time_s: settings.gnss_correlation_time_s,
        },
        imu_error: nav_core::imu_error_states::ImuErrorModel {
            gyro_misalignment_sigma_rad: settings.imu_errors.gyro_misalignment_sigma_rad,
            accel_misalignment_sigma_rad: settings.imu_errors.accel_misalignment_sigma_rad,
            gyro_g_sensitivity_sigma_rad_s_per_mps2: settings
                .imu_errors
                .gyro_g_sensitivity_sigma_rad_s_per_mps2,
        },
    })
}

/// The flight software's configuration for a run: made from the undispersed `scenario`
/// ([`fsw_config`]), with the measurement history's latency window widened to
/// the `truth`'s dispersed GNSS latency plus the hand-over frame, as the scenario's own
/// `gnss.latency_s` widens it: the window is a buffer length, not a model the filter assumes,
/// and a fix older than it would be dropped rather than fused late.
///
/// # Errors
/// As [`fsw_config`].
pub fn run_config(scenario: &Scenario, truth: &Scenario) -> Result<FswConfig, SetupError> {
    let mut config = fsw_config(scenario)?;
    if truth.gnss.latency_s > scenario.gnss.latency_s {
        let window_s = truth.gnss.latency_s + scenario.imu.frame_period_s();
        config.timing.max_latency_s = config.timing.max_latency_s.max(window_s);
    }
    Ok(config)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scenario's `[filter.imu_errors]` reaches the filter (and the replay setup, so the
    /// target flies the same filter); absent, the filter has no systematic states.
    #[test]
    fn the_filters_imu_error_states_reach_the_flight_software() {
        let default = Scenario::default_scenario().unwrap();
        assert!(!filter_config(&default).unwrap().imu_error.is_enabled());
        let mut scenario = default.clone();
        scenario.filter.imu_errors = crate::scenario::FilterImuErrors {
            gyro_misalignment_sigma_rad: 2.0e-5,
            accel_misalignment_sigma_rad: 3.0e-5,
            gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.47e-7,
        };
        let config = filter_config(&scenario).unwrap();
        assert_eq!(
            [
                config.imu_error.gyro_misalignment_sigma_rad,
                config.imu_error.accel_misalignment_sigma_rad,
                config.imu_error.gyro_g_sensitivity_sigma_rad_s_per_mps2,
            ]
            .map(f64::to_bits),
            [2.0e-5, 3.0e-5, 2.47e-7].map(f64::to_bits)
        );
        let launch = crate::setup::launch::Launch::new(&scenario).unwrap();
        let setup = replay_setup_for(&scenario, &launch).unwrap();
        assert_eq!(setup.config().filter.imu_error, config.imu_error);
        assert_eq!(setup.config().filter.imu_error, config.imu_error);
    }

    /// The scenario's `[filter.bias_instability]` reaches the filter's process noise and its
    /// bias prior; the default scenario's process noise is the truth's random walks (0)
    /// unchanged.
    #[test]
    fn the_scenarios_bias_instability_reaches_the_process_noise() {
        let default = Scenario::default_scenario().unwrap();
        let noise = scenario_process_noise(&default);
        assert_eq!(
            noise.gyro_bias_walk_rad_s2_per_sqrt_hz.to_bits(),
            0.0f64.to_bits()
        );
        let mut scenario = default.clone();
        scenario.filter.bias_instability.accel_sigma_mps2 = 2.0e-5;
        scenario.filter.bias_instability.accel_correlation_time_s = 300.0;
        let noise = scenario_process_noise(&scenario);
        let expected = (2.0 * 4.0e-10 / 300.0_f64).sqrt();
        assert!((noise.accel_bias_walk_mps3_per_sqrt_hz - expected).abs() < 1e-15 * expected);
        let initial = filter_config(&scenario).unwrap().initial;
        let constant = default.filter.initial_sigma.accel_bias_mps2;
        let expected = (constant * constant + 8.0e-10).sqrt();
        assert!((initial.accel_bias_mps2 - expected).abs() < 1e-15 * expected);
        let default_initial = filter_config(&default).unwrap().initial;
        assert_eq!(
            initial.gyro_bias_rad_s.to_bits(),
            default_initial.gyro_bias_rad_s.to_bits()
        );
        assert_eq!(
            noise.gyro_bias_walk_rad_s2_per_sqrt_hz.to_bits(),
            0.0f64.to_bits()
        );
    }

    #[test]
    fn the_flight_softwares_second_head_follows_the_filter_keys() {
        let one_head = crate::scenario::DEFAULT_SCENARIO_TOML.replacen(
            "\n[gnss]\n",
            "\n[[star_sensor.additional_heads]]\nrate_hz = 10.0\nnoise_arcsec = 10.0\n\
         mounting_rotation_vector_deg = [90.0, 0.0, 0.0]\n\
         installation_error_rotation_vector_rad = [-3.0e-3, 1.0e-3, 2.0e-3]\n\n[gnss]\n",
            1,
        );
        let told = crate::scenario::Scenario::from_toml_str(&one_head).unwrap();
        assert!(!format!("{told:?}").contains("star_pairs_before_hand_over"));
        let config = fsw_config(&told).unwrap();
        let second = config.star.second_head.unwrap();
        assert_eq!(second.pairs_before_hand_over, 100);
        assert_eq!(
            second.pairs_before_hand_over,
            crate::scenario::DEFAULT_STAR_PAIRS_BEFORE_HAND_OVER
        );
        let keyed = one_head.replacen(
            "[filter]\n",
            "[filter]\nstar_pairs_before_hand_over = 7\n",
            1,
        );
        let keyed = crate::scenario::Scenario::from_toml_str(&keyed).unwrap();
        assert!(format!("{keyed:?}").contains("star_pairs_before_hand_over: 7"));
        let config = fsw_config(&keyed).unwrap();
        assert_eq!(config.star.second_head.unwrap().pairs_before_hand_over, 7);
        let untold = one_head.replacen("[filter]\n", "[filter]\nstar_second_head = false\n", 1);
        let untold = crate::scenario::Scenario::from_toml_str(&untold).unwrap();
        assert!(fsw_config(&untold).unwrap().star.second_head.is_none());
    }
}
