//! The `[filter]` table: what the flight software is told. Every key that sets a flight
//! parameter is checked by the flight software's own rule (nav-fsw's parameter table,
//! [`Param`]), never a copy of it: its range, the parameters that go together and the rules
//! between values ([`FswConfig::validate`]). Only `[filter.bias_instability]`, which nav-sim
//! turns into the flight's bias walk and prior, is checked here, with the flight's range of
//! every correlation time.

use nav_fsw::config::{FswConfig, Param, Range, CORRELATION_TIME_RANGE_S, CORRELATION_TIME_WHY};
use nav_fsw::{ConfigField, FswError};

use super::{Checker, ScenarioError};
use crate::scenario::number;
use crate::scenario::star_sensor::arcsec_to_rad;
use crate::scenario::FilterSettings;

/// How many `[filter]` keys set a flight parameter ([`FilterSettings::FLIGHT_KEYS`]).
const FLIGHT_KEY_COUNT: usize = 29;

impl FilterSettings {
    /// Each `[filter]` key that sets a flight parameter, with the parameter
    /// ([`FilterSettings::flight_numbers`] gives the values in this order).
    pub const FLIGHT_KEYS: [(&'static str, Param); FLIGHT_KEY_COUNT] = [
        (
            "filter.discretisation_order",
            Param::FilterDiscretisationOrder,
        ),
        ("filter.initial_sigma.attitude_rad", Param::InitialAttitude),
        ("filter.initial_sigma.position_m", Param::InitialPosition),
        ("filter.initial_sigma.velocity_mps", Param::InitialVelocity),
        (
            "filter.initial_sigma.gyro_bias_rad_per_s",
            Param::InitialGyroBias,
        ),
        (
            "filter.initial_sigma.accel_bias_mps2",
            Param::InitialAccelBias,
        ),
        (
            "filter.initial_sigma.star_installation_rad",
            Param::InitialStarInstallation,
        ),
        (
            "filter.initial_sigma.gyro_scale_factor",
            Param::InitialGyroScaleFactor,
        ),
        (
            "filter.initial_sigma.accel_scale_factor",
            Param::InitialAccelScaleFactor,
        ),
        ("filter.nis_gate.star_threshold", Param::StarGate),
        ("filter.nis_gate.gnss_threshold", Param::GnssGate),
        ("filter.gnss_correlated_sigma_m", Param::GnssCorrelatedSigma),
        ("filter.gnss_correlation_time_s", Param::GnssCorrelationTime),
        ("filter.gnss_noise_m", Param::GnssNoise),
        ("filter.star_noise_arcsec", Param::StarNoise),
        ("filter.star_noise_arcsec", Param::StarRollNoise),
        (
            "filter.imu_errors.gyro_misalignment_sigma_rad",
            Param::GyroMisalignmentSigma,
        ),
        (
            "filter.imu_errors.accel_misalignment_sigma_rad",
            Param::AccelMisalignmentSigma,
        ),
        (
            "filter.imu_errors.gyro_g_sensitivity_sigma_rad_s_per_mps2",
            Param::GyroGSensitivitySigma,
        ),
        (
            "filter.star_slow_error.sigma_arcsec[0]",
            Param::StarSlowErrorX,
        ),
        (
            "filter.star_slow_error.sigma_arcsec[1]",
            Param::StarSlowErrorY,
        ),
        (
            "filter.star_slow_error.sigma_arcsec[2]",
            Param::StarSlowErrorZ,
        ),
        (
            "filter.star_slow_error.correlation_time_s",
            Param::StarSlowErrorCorrelationTime,
        ),
        (
            "filter.star_pairs_before_hand_over",
            Param::HeadPairsBeforeHandOver,
        ),
        ("filter.gravity.degree", Param::GravityDegree),
        ("filter.gravity.order", Param::GravityOrder),
        (
            "filter.gravity.terms_per_frame",
            Param::GravityTermsPerFrame,
        ),
        (
            "filter.gravity.omitted_field_sigma_mps2",
            Param::OmittedFieldSigma,
        ),
        (
            "filter.gravity.omitted_field_psd_m2_per_s3",
            Param::OmittedFieldPsd,
        ),
    ];

    /// The values of [`Self::FLIGHT_KEYS`] in the flight's units (arcseconds as radians),
    /// `None` for a key left out that has no value of its own (`gnss_noise_m`,
    /// `star_noise_arcsec`).
    pub fn flight_numbers(&self) -> [Option<f64>; FLIGHT_KEY_COUNT] {
        let sigma = &self.initial_sigma;
        let errors = &self.imu_errors;
        let [slow_x, slow_y, slow_z] = self.star_slow_error.sigma_arcsec.map(arcsec_to_rad);
        let star_noise = self.star_noise_arcsec.map(arcsec_to_rad);
        let gravity = &self.gravity;
        [
            Some(f64::from(self.discretisation_order)),
            Some(sigma.attitude_rad),
            Some(sigma.position_m),
            Some(sigma.velocity_mps),
            Some(sigma.gyro_bias_rad_per_s),
            Some(sigma.accel_bias_mps2),
            Some(sigma.star_installation_rad),
            Some(sigma.gyro_scale_factor),
            Some(sigma.accel_scale_factor),
            Some(self.nis_gate.star_threshold),
            Some(self.nis_gate.gnss_threshold),
            Some(self.gnss_correlated_sigma_m),
            Some(self.gnss_correlation_time_s),
            self.gnss_noise_m,
            star_noise,
            star_noise,
            Some(errors.gyro_misalignment_sigma_rad),
            Some(errors.accel_misalignment_sigma_rad),
            Some(errors.gyro_g_sensitivity_sigma_rad_s_per_mps2),
            Some(slow_x),
            Some(slow_y),
            Some(slow_z),
            Some(self.star_slow_error.correlation_time_s),
            Some(f64::from(self.star_pairs_before_hand_over)),
            Some(f64::from(gravity.degree)),
            Some(f64::from(gravity.order)),
            Some(f64::from(gravity.terms_per_frame)),
            Some(gravity.omitted_field_sigma_mps2),
            Some(gravity.omitted_field_psd_m2_per_s3),
        ]
    }

    /// The `[filter]` key that sets `param`, if one does.
    pub fn flight_key(param: Param) -> Option<&'static str> {
        Self::FLIGHT_KEYS
            .iter()
            .find(|(_, keyed)| *keyed == param)
            .map(|(key, _)| *key)
    }
}

impl Checker<'_> {
    /// `[filter]`: each key by its flight parameter's range, then, set on the flight
    /// software's defaults at this launch site, the pairs that go together and the rules
    /// between values; then `[filter.bias_instability]`.
    pub(super) fn filter(
        &self,
        filter: &FilterSettings,
        mut config: FswConfig,
    ) -> Result<(), ScenarioError> {
        let numbers = filter.flight_numbers();
        for ((key, param), number) in FilterSettings::FLIGHT_KEYS.iter().zip(numbers) {
            let Some(value) = number else { continue };
            let refused = param
                .check(value)
                .and_then(|()| param.set_number(&mut config, value));
            if let Err(error) = refused {
                return Err(self.refused_by_flight(key, value, error));
            }
        }
        if let Err(error) = config.validate() {
            let key = match error {
                FswError::InvalidConfiguration(
                    ConfigField::Parameter(param) | ConfigField::Companion(_, param),
                ) => FilterSettings::flight_key(param),
                FswError::InvalidConfiguration(ConfigField::Gravity) => {
                    Some("filter.gravity.order")
                }
                _ => None,
            };
            let key = key.unwrap_or("filter");
            return Err(self.fail(key, &format!("is refused by the flight software: {error}")));
        }
        self.bias_instability_told(filter)
    }

    /// "`key` = value is refused by the flight software: RULE".
    fn refused_by_flight(&self, key: &str, value: f64, error: FswError) -> ScenarioError {
        let unit = if key.ends_with("_arcsec") || key.contains("_arcsec[") {
            format!(" ({} arcsec in rad)", number(value / arcsec_to_rad(1.0)))
        } else {
            String::new()
        };
        self.fail(
            key,
            &format!(
                "= {}{unit} is refused by the flight software: {error}",
                number(value)
            ),
        )
    }

    /// `[filter.bias_instability]`: each 1σ 0 (off) or in the flight's range of that bias's
    /// 1σ, each correlation time in the flight's range of every correlation time, and on
    /// with its 1σ.
    fn bias_instability_told(&self, filter: &FilterSettings) -> Result<(), ScenarioError> {
        let instability = &filter.bias_instability;
        for (sensor, unit, sigma, tau_s, bias) in [
            (
                "gyro",
                "rad_per_s",
                instability.gyro_sigma_rad_per_s,
                instability.gyro_correlation_time_s,
                Param::InitialGyroBias,
            ),
            (
                "accel",
                "mps2",
                instability.accel_sigma_mps2,
                instability.accel_correlation_time_s,
                Param::InitialAccelBias,
            ),
        ] {
            let sigma_key = format!("filter.bias_instability.{sensor}_sigma_{unit}");
            let why = format!("the flight's range of {}", bias.path());
            let range = bias.range().or_off();
            self.in_range(&sigma_key, sigma, range, bias.unit(), &why)?;
            let key = format!("filter.bias_instability.{sensor}_correlation_time_s");
            self.in_range(
                &key,
                tau_s,
                CORRELATION_TIME_RANGE_S,
                "s",
                CORRELATION_TIME_WHY,
            )?;
            if sigma > 0.0 && tau_s == 0.0 {
                return Err(self.fail(&key, &format!("must not be 0 while {sigma_key} is on")));
            }
        }
        Ok(())
    }

    /// "`key` = value must be in RANGE UNIT (why)".
    fn in_range(
        &self,
        key: &str,
        value: f64,
        range: Range,
        unit: &str,
        why: &str,
    ) -> Result<(), ScenarioError> {
        if range.contains(value) {
            return Ok(());
        }
        let off = if range.zero_is_off { "0 (off) or " } else { "" };
        let interval = nav_fsw::config::Interval(range);
        Err(self.fail(
            key,
            &format!(
                "= {} must be {off}in {interval} {unit} ({why})",
                number(value)
            ),
        ))
    }
}
