//! Scenario validation: every value checked against its documented range, the first
//! violation reported with its dotted key.

use nav_fsw::config::FswConfig;

use crate::scenario::epoch::EpochError;

use super::{
    dispersion, gnss_latency_violation, gravity, gravity::GravitySettings, max_imu_rate_hz, number,
    Scenario, ScenarioError, MAX_DURATION_S, MAX_G_SENSITIVITY_RAD_S_PER_MPS2,
    MAX_MISALIGNMENT_RAD, MAX_SCALE_FACTOR_MAGNITUDE, MAX_START_TIME_S, MAX_TRUTH_STEPS,
    MAX_TRUTH_SUBSTEPS_PER_FRAME, SIGMA_RANGE, SIGMA_UNIT_MARGIN, WHOLE_FRAME_TOLERANCE,
};

/// Collects the first violated rule while walking the scenario.
struct Checker<'a> {
    origin: &'a str,
}

impl Checker<'_> {
    fn fail(&self, key: &str, requirement: &str) -> ScenarioError {
        ScenarioError::Invalid {
            origin: self.origin.to_string(),
            key: key.to_string(),
            requirement: requirement.to_string(),
        }
    }

    /// `[[start_s, duration_s], ...]` with every start ≥ 0 and every duration > 0.
    fn outages(&self, key: &str, outages: &[[f64; 2]]) -> Result<(), ScenarioError> {
        for (index, [start_s, duration_s]) in outages.iter().enumerate() {
            self.non_negative(&format!("{key}[{index}][0] (start_s)"), *start_s)?;
            self.positive(&format!("{key}[{index}][1] (duration_s)"), *duration_s)?;
        }
        Ok(())
    }

    /// `value` (finite) at most `limit`; the message quotes both, with `unit` (" s", or ""
    /// for a count), and the limit's reason.
    fn at_most(
        &self,
        key: &str,
        value: f64,
        limit: f64,
        unit: &str,
        reason: &str,
    ) -> Result<(), ScenarioError> {
        let ok = value.is_finite() && value <= limit;
        self.limit(ok, key, value, ("is above", limit), unit, reason)
    }

    /// `Ok` if `ok`, else "`key` = value `relation` the limit L (reason)", e.g. "is above".
    fn limit(
        &self,
        ok: bool,
        key: &str,
        value: f64,
        (relation, limit): (&str, f64),
        unit: &str,
        reason: &str,
    ) -> Result<(), ScenarioError> {
        if ok {
            return Ok(());
        }
        let (value, limit) = (number(value), number(limit));
        Err(self.fail(
            key,
            &format!("= {value}{unit} {relation} the limit {limit}{unit} ({reason})"),
        ))
    }

    /// A 1σ or noise key: in [`SIGMA_RANGE`], or 0 where `zero_is_off`.
    fn sigma(&self, key: &str, value: f64, zero_is_off: bool) -> Result<(), ScenarioError> {
        let (low, high) = SIGMA_RANGE;
        if (zero_is_off && value == 0.0) || (low..=high).contains(&value) {
            return Ok(());
        }
        let off = if zero_is_off { "0 (off) or " } else { "" };
        Err(self.fail(
            key,
            &format!(
                "= {} must be {off}in [{low:e}, {high:e}] (its square must stay a normal f64 \
                 in the filter's covariance: the flight software's range [{:e}, {:e}] with \
                 {SIGMA_UNIT_MARGIN:e} to spare for unit conversions)",
                number(value),
                nav_fsw::config::SIGMA_MIN,
                nav_fsw::config::SIGMA_MAX,
            ),
        ))
    }

    fn finite(&self, key: &str, value: f64) -> Result<(), ScenarioError> {
        if value.is_finite() {
            Ok(())
        } else {
            Err(self.fail(key, "must be finite"))
        }
    }

    fn finite3(&self, key: &str, values: &[f64; 3]) -> Result<(), ScenarioError> {
        if values.iter().all(|value| value.is_finite()) {
            Ok(())
        } else {
            Err(self.fail(key, "must have three finite components"))
        }
    }

    /// A rotation vector (`one_turn`: 360 in degrees, 2π in radians): finite, with a norm of
    /// at most one turn. Beyond it the rotation is the same as a shorter vector's, and a norm
    /// whose square overflows has no direction at all.
    fn rotation_vector(
        &self,
        key: &str,
        values: &[f64; 3],
        one_turn: f64,
        unit: &str,
    ) -> Result<(), ScenarioError> {
        self.finite3(key, values)?;
        // A component beyond 1e150 turns is beyond one turn by itself; below, the squares of
        // the components in turns cannot overflow.
        let turns = values.map(|value| value / one_turn);
        let norm_turns = if turns.iter().all(|value| value.abs() <= 1.0e150) {
            turns.iter().map(|value| value * value).sum::<f64>().sqrt()
        } else {
            f64::INFINITY
        };
        if norm_turns <= 1.0 {
            return Ok(());
        }
        let size = if norm_turns.is_finite() {
            format!("a norm of {} {unit}", number(norm_turns * one_turn))
        } else {
            let largest = values.iter().map(|value| value.abs()).fold(0.0, f64::max);
            format!("a component of magnitude {} {unit}", number(largest))
        };
        Err(self.fail(
            key,
            &format!(
                "has {size}, more than one turn ({} {unit}): give the same rotation as a \
                 vector of norm at most one turn",
                number(one_turn)
            ),
        ))
    }

    fn positive(&self, key: &str, value: f64) -> Result<(), ScenarioError> {
        if value.is_finite() && value > 0.0 {
            Ok(())
        } else {
            Err(self.fail(key, "must be > 0"))
        }
    }

    fn non_negative(&self, key: &str, value: f64) -> Result<(), ScenarioError> {
        if value.is_finite() && value >= 0.0 {
            Ok(())
        } else {
            Err(self.fail(key, "must be >= 0"))
        }
    }

    /// `Ok` if `value` is in `[low, high]`, else "`key` must be in [low, high] unit (got …)".
    fn within(
        &self,
        key: &str,
        value: f64,
        (low, high): (f64, f64),
        unit: &str,
    ) -> Result<(), ScenarioError> {
        if value.is_finite() && (low..=high).contains(&value) {
            Ok(())
        } else {
            let value = number(value);
            Err(self.fail(
                key,
                &format!("must be in [{low}, {high}]{unit} (got {value}{unit})"),
            ))
        }
    }

    fn scale_factors(&self, key: &str, values: &[f64; 3]) -> Result<(), ScenarioError> {
        if values
            .iter()
            .all(|value| value.is_finite() && value.abs() <= MAX_SCALE_FACTOR_MAGNITUDE)
        {
            Ok(())
        } else {
            Err(self.fail(
                key,
                &format!(
                    "components must be finite with magnitude <= {MAX_SCALE_FACTOR_MAGNITUDE}"
                ),
            ))
        }
    }

    /// `duration_s` must be a whole number (≥ `minimum_frames`) of IMU frames of `period_s`.
    fn whole_frames(
        &self,
        key: &str,
        duration_s: f64,
        period_s: f64,
        minimum_frames: f64,
    ) -> Result<(), ScenarioError> {
        let frames = duration_s / period_s;
        let whole = frames.round();
        if frames.is_finite()
            && whole >= minimum_frames
            && (frames - whole).abs() <= WHOLE_FRAME_TOLERANCE * whole.max(1.0)
        {
            Ok(())
        } else {
            Err(self.fail(
                key,
                &format!("must be a whole number of IMU frames ({period_s} s), at least {minimum_frames}"),
            ))
        }
    }
}

impl Checker<'_> {
    /// A triad's misalignment matrix: zero diagonal, off-diagonal terms finite and at most
    /// [`MAX_MISALIGNMENT_RAD`] in magnitude.
    fn misalignment(&self, key: &str, matrix: &[[f64; 3]; 3]) -> Result<(), ScenarioError> {
        for (row, terms) in matrix.iter().enumerate() {
            for (column, term) in terms.iter().enumerate() {
                let key = format!("{key}[{row}][{column}]");
                if row == column {
                    if *term != 0.0 {
                        return Err(self.fail(
                            &key,
                            &format!(
                                "= {} must be 0 (the diagonal is the triad's scale_factor)",
                                number(*term)
                            ),
                        ));
                    }
                } else {
                    self.magnitude(
                        &key,
                        *term,
                        MAX_MISALIGNMENT_RAD,
                        " rad",
                        MISALIGNMENT_REASON,
                    )?;
                }
            }
        }
        Ok(())
    }

    /// `|value|` (finite) at most `limit`.
    fn magnitude(
        &self,
        key: &str,
        value: f64,
        limit: f64,
        unit: &str,
        reason: &str,
    ) -> Result<(), ScenarioError> {
        let ok = value.is_finite() && value.abs() <= limit;
        self.limit(
            ok,
            key,
            value.abs(),
            ("in magnitude is above", limit),
            unit,
            reason,
        )
    }

    /// A bias instability: the 1σ 0 (off) or in [`SIGMA_RANGE`], and a positive correlation
    /// time when it is on.
    fn bias_instability(
        &self,
        (sigma_key, sigma): (&str, f64),
        (time_key, correlation_time_s): (&str, f64),
    ) -> Result<(), ScenarioError> {
        self.sigma(sigma_key, sigma, true)?;
        self.non_negative(time_key, correlation_time_s)?;
        if sigma > 0.0 {
            self.positive(time_key, correlation_time_s)?;
        }
        Ok(())
    }
}

/// Why a misalignment term is at most [`MAX_MISALIGNMENT_RAD`] (the message's wording).
const MISALIGNMENT_REASON: &str = "the model is the small-angle I + A; navigation-grade \
                                   triads are 5-20 urad, tactical ones 100 urad and more";

impl Checker<'_> {
    /// Every `[dispersion]` entry: a finite, non-negative width, and the latency within the
    /// flight software's limit together with `gnss.latency_s`.
    fn dispersion(
        &self,
        dispersion: &dispersion::Dispersion,
        scenario: &Scenario,
    ) -> Result<(), ScenarioError> {
        // The largest width of each entry, with why: beyond it a draw no longer disperses
        // the flight but replaces it (a different orbit, a sensor of another kind).
        let (noise, angle) = (
            MAX_DISPERSION_PERCENT,
            "a rotation of 180° per axis covers every attitude",
        );
        let noise_reason = "a factor of 11 on a specification is another sensor";
        let entries = [
            (
                "initial_attitude_deg",
                dispersion.initial_attitude_deg,
                180.0,
                angle,
            ),
            (
                "initial_position_m",
                dispersion.initial_position_m,
                1.0e6,
                "1000 km off is another orbit, not a navigation error",
            ),
            (
                "initial_velocity_mps",
                dispersion.initial_velocity_mps,
                1.0e3,
                "1 km/s off is another orbit, not a navigation error",
            ),
            (
                "gyro_noise_percent",
                dispersion.gyro_noise_percent,
                noise,
                noise_reason,
            ),
            (
                "accelerometer_noise_percent",
                dispersion.accelerometer_noise_percent,
                noise,
                noise_reason,
            ),
            (
                "star_noise_percent",
                dispersion.star_noise_percent,
                noise,
                noise_reason,
            ),
            (
                "gnss_noise_percent",
                dispersion.gnss_noise_percent,
                noise,
                noise_reason,
            ),
            (
                "star_mounting_deg",
                dispersion.star_mounting_deg,
                180.0,
                angle,
            ),
            (
                "gnss_correlated_sigma_percent",
                dispersion.gnss_correlated_sigma_percent,
                noise,
                noise_reason,
            ),
            (
                "gnss_correlation_time_percent",
                dispersion.gnss_correlation_time_percent,
                noise,
                noise_reason,
            ),
            (
                "gyro_misalignment_rad",
                dispersion.gyro_misalignment_rad,
                MAX_MISALIGNMENT_RAD,
                "the misalignment key's own limit",
            ),
            (
                "accelerometer_misalignment_rad",
                dispersion.accelerometer_misalignment_rad,
                MAX_MISALIGNMENT_RAD,
                "the misalignment key's own limit",
            ),
            (
                "gyro_g_sensitivity_rad_s_per_mps2",
                dispersion.gyro_g_sensitivity_rad_s_per_mps2,
                MAX_G_SENSITIVITY_RAD_S_PER_MPS2,
                "the g-sensitivity key's own limit",
            ),
            (
                "launch_longitude_deg",
                dispersion.launch_longitude_deg,
                180.0,
                "a turn of 180° either way reaches every longitude",
            ),
        ];
        for (name, distribution, max, reason) in entries {
            let Some(distribution) = distribution else {
                continue;
            };
            let field = match distribution {
                dispersion::Distribution::Normal { .. } => "sigma",
                dispersion::Distribution::Uniform { .. } => "half_width",
            };
            let key = format!("dispersion.{name}.{field}");
            let width = distribution.width();
            self.non_negative(&key, width)?;
            if width > max {
                return Err(self.fail(
                    &key,
                    &format!(
                        "= {} must be at most {} ({reason})",
                        number(width),
                        number(max)
                    ),
                ));
            }
        }
        if let Some(frames) = dispersion.gnss_latency_frames {
            let period_s = scenario.imu.frame_period_s();
            let latency_s = scenario.gnss.latency_s + f64::from(frames) * period_s;
            if let Some(requirement) = gnss_latency_violation(latency_s, period_s) {
                return Err(self.fail(
                    "dispersion.gnss_latency_frames",
                    &format!("= {frames} frames: gnss.latency_s plus them {requirement}"),
                ));
            }
        }
        Ok(())
    }
}

/// The largest width of a `[dispersion]` entry in percent (a factor of 11 on the value).
pub const MAX_DISPERSION_PERCENT: f64 = 1000.0;

/// Why a flight is at most [`MAX_DURATION_S`] long (the error message's wording).
const DURATION_REASON: &str = "one day of flight: an upper stage's orbital phase lasts \
                               minutes to hours, and run time and recorded history grow with it";

/// WGS-84 equatorial radius (m): the lowest acceptable perigee radius of the initial orbit.
const EARTH_EQUATORIAL_RADIUS_M: f64 = 6_378_137.0;

impl Scenario {
    /// Checks every value against its documented range.
    ///
    /// # Errors
    /// [`ScenarioError::Invalid`] naming the first offending key.
    pub fn validate(&self) -> Result<(), ScenarioError> {
        self.validate_from("<in memory>")
    }

    pub(super) fn validate_from(&self, origin: &str) -> Result<(), ScenarioError> {
        let check = Checker { origin };
        let simulation = &self.simulation;
        check.non_negative("simulation.start_time_s", simulation.start_time_s)?;
        check.at_most(
            "simulation.start_time_s",
            simulation.start_time_s,
            MAX_START_TIME_S,
            " s",
            "the f64 time resolution stays 1.9e-9 s, a millionth of a 2 ms frame; \
             at 1e12 s it is 1.2e-4 s and time tags miss their frames",
        )?;
        check.non_negative("simulation.min_altitude_m", simulation.min_altitude_m)?;
        if simulation.truth_substeps_per_frame == 0 {
            return Err(check.fail("simulation.truth_substeps_per_frame", "must be >= 1"));
        }
        check.at_most(
            "simulation.truth_substeps_per_frame",
            f64::from(simulation.truth_substeps_per_frame),
            f64::from(MAX_TRUTH_SUBSTEPS_PER_FRAME),
            "",
            "RK4 at the default 16 is already far below the sensor noise; \
             more substeps only cost run time",
        )?;

        let site = &self.launch_site;
        check.within(
            "launch_site.latitude_deg",
            site.latitude_deg,
            (-90.0, 90.0),
            " deg",
        )?;
        let longitude = site.longitude_deg;
        check.within(
            "launch_site.longitude_deg",
            longitude,
            (-180.0, 360.0),
            " deg",
        )?;
        check.within(
            "launch_site.height_m",
            site.height_m,
            (-500.0, 10_000.0),
            " m",
        )?;
        check.within(
            "launch_site.azimuth_deg",
            site.azimuth_deg,
            (-360.0, 360.0),
            " deg",
        )?;
        if let Err(EpochError::EarthOrientation {
            key,
            value,
            limit,
            unit,
            reason,
        }) = site.earth_orientation.check()
        {
            let key = format!("launch_site.earth_orientation.{key}");
            let relation = ("has a magnitude above", limit);
            check.limit(false, &key, value, relation, &format!(" {unit}"), reason)?;
        }
        self.launch_site
            .epoch()
            .and_then(|epoch| epoch.gps_week_and_seconds())
            .map_err(|error| check.fail("launch_site.epoch_utc", &error.to_string()))?;

        let orbit = &self.initial_orbit;
        check.positive("initial_orbit.semi_major_axis_m", orbit.semi_major_axis_m)?;
        if !(orbit.eccentricity.is_finite() && (0.0..1.0).contains(&orbit.eccentricity)) {
            return Err(check.fail("initial_orbit.eccentricity", "must be in [0, 1)"));
        }
        if orbit.semi_major_axis_m * (1.0 - orbit.eccentricity) <= EARTH_EQUATORIAL_RADIUS_M {
            return Err(check.fail(
                "initial_orbit.semi_major_axis_m",
                "must put the perigee (a (1 - e)) above the Earth's equatorial radius 6378137 m",
            ));
        }
        let inclination = orbit.inclination_deg;
        check.within(
            "initial_orbit.inclination_deg",
            inclination,
            (0.0, 180.0),
            " deg",
        )?;
        check.finite(
            "initial_orbit.right_ascension_of_node_deg",
            orbit.right_ascension_of_node_deg,
        )?;
        check.finite(
            "initial_orbit.argument_of_perigee_deg",
            orbit.argument_of_perigee_deg,
        )?;
        check.finite("initial_orbit.true_anomaly_deg", orbit.true_anomaly_deg)?;
        check.rotation_vector(
            "initial_attitude.rotation_vector_deg",
            &self.initial_attitude.rotation_vector_deg,
            360.0,
            "deg",
        )?;

        check.positive("imu.rate_hz", self.imu.rate_hz)?;
        let period_s = self.imu.frame_period_s();
        let fsw = FswConfig::paper_defaults(
            self.launch_site.nav_site(),
            nav_fsw::sensor_frames::SensorFrames::ALIGNED,
        );
        let span_frames = nav_fsw::config::history_span_frames();
        check.at_most(
            "imu.rate_hz",
            self.imu.rate_hz,
            max_imu_rate_hz(&fsw),
            " Hz",
            &format!(
                "the flight software's navigation history of {span_frames} frames must span \
                 its latency window timing.max_latency_s = {} s",
                number(fsw.timing.max_latency_s)
            ),
        )?;
        let min_aiding_rate_hz = 1.0 / fsw.timing.outage_timeout_s;
        let outage_reason = format!(
            "a sensor silent for longer than the flight software's timing.outage_timeout_s = \
             {} s is in an outage",
            number(fsw.timing.outage_timeout_s)
        );

        let gyro = &self.gyro;
        check.sigma(
            "gyro.rate_noise_density_deg_per_h_per_sqrt_hz",
            gyro.rate_noise_density_deg_per_h_per_sqrt_hz,
            true,
        )?;
        check.finite3("gyro.bias_rad_per_s", &gyro.bias_rad_per_s)?;
        check.scale_factors("gyro.scale_factor", &gyro.scale_factor)?;
        check.sigma(
            "gyro.bias_random_walk_rad_per_s_per_sqrt_s",
            gyro.bias_random_walk_rad_per_s_per_sqrt_s,
            true,
        )?;
        check.non_negative("gyro.quantum_rad", gyro.quantum_rad)?;
        check.misalignment("gyro.misalignment_rad", &gyro.misalignment_rad)?;
        for (axis, value) in gyro.g_sensitivity_rad_s_per_mps2.iter().enumerate() {
            check.magnitude(
                &format!("gyro.g_sensitivity_rad_s_per_mps2[{axis}]"),
                *value,
                MAX_G_SENSITIVITY_RAD_S_PER_MPS2,
                " rad/s per m/s^2",
                "about 2000 deg/h/g; navigation-grade gyros have 0.1-10 deg/h/g",
            )?;
        }
        check.bias_instability(
            (
                "gyro.bias_instability_sigma_rad_per_s",
                gyro.bias_instability_sigma_rad_per_s,
            ),
            (
                "gyro.bias_instability_correlation_time_s",
                gyro.bias_instability_correlation_time_s,
            ),
        )?;

        let accelerometer = &self.accelerometer;
        check.sigma(
            "accelerometer.noise_per_sample_mps2",
            accelerometer.noise_per_sample_mps2,
            true,
        )?;
        check.finite3("accelerometer.bias_mps2", &accelerometer.bias_mps2)?;
        check.scale_factors("accelerometer.scale_factor", &accelerometer.scale_factor)?;
        check.sigma(
            "accelerometer.bias_random_walk_mps2_per_sqrt_s",
            accelerometer.bias_random_walk_mps2_per_sqrt_s,
            true,
        )?;
        check.non_negative("accelerometer.quantum_mps", accelerometer.quantum_mps)?;
        check.misalignment(
            "accelerometer.misalignment_rad",
            &accelerometer.misalignment_rad,
        )?;
        check.bias_instability(
            (
                "accelerometer.bias_instability_sigma_mps2",
                accelerometer.bias_instability_sigma_mps2,
            ),
            (
                "accelerometer.bias_instability_correlation_time_s",
                accelerometer.bias_instability_correlation_time_s,
            ),
        )?;

        check.star_sensor(
            &self.star_sensor,
            period_s,
            (min_aiding_rate_hz, &outage_reason),
        )?;

        let gnss = &self.gnss;
        check.positive("gnss.rate_hz", gnss.rate_hz)?;
        check.limit(
            gnss.rate_hz > min_aiding_rate_hz,
            "gnss.rate_hz",
            gnss.rate_hz,
            ("is not above", min_aiding_rate_hz),
            " Hz",
            &outage_reason,
        )?;
        check.whole_frames("gnss.rate_hz", 1.0 / gnss.rate_hz, period_s, 1.0)?;
        check.sigma("gnss.noise_m", gnss.noise_m, true)?;
        check.non_negative("gnss.latency_s", gnss.latency_s)?;
        check.whole_frames("gnss.latency_s", gnss.latency_s, period_s, 0.0)?;
        if let Some(requirement) = gnss_latency_violation(gnss.latency_s, period_s) {
            return Err(check.fail("gnss.latency_s", &requirement));
        }
        check.sigma("gnss.correlated_noise_m", gnss.correlated_noise_m, true)?;
        if gnss.correlated_noise_m > 0.0 {
            check.positive("gnss.correlation_time_s", gnss.correlation_time_s)?;
        }
        check.sigma("gnss.velocity_noise_mps", gnss.velocity_noise_mps, true)?;
        check.outages("gnss.outages", &gnss.outages)?;
        let (max_rate_deg_per_s, max_force_mps2) = self.imu.ranges();
        check.positive("imu.max_rate_deg_per_s", max_rate_deg_per_s)?;
        check.positive("imu.max_specific_force_mps2", max_force_mps2)?;

        if self.manoeuvres.is_empty() {
            return Err(check.fail("manoeuvre", "must list at least one segment"));
        }
        for (index, segment) in self.manoeuvres.iter().enumerate() {
            let key = |field: &str| format!("manoeuvre[{index}].{field}");
            check.positive(&key("duration_s"), segment.duration_s)?;
            check.at_most(
                &key("duration_s"),
                segment.duration_s,
                MAX_DURATION_S,
                " s",
                DURATION_REASON,
            )?;
            check.whole_frames(&key("duration_s"), segment.duration_s, period_s, 1.0)?;
            check.non_negative(&key("ramp_s"), segment.ramp_s)?;
            if 2.0 * segment.ramp_s > segment.duration_s {
                return Err(check.fail(&key("ramp_s"), "must be at most half of duration_s"));
            }
            check.finite3(&key("body_rate_deg_per_s"), &segment.body_rate_deg_per_s)?;
            check.finite3(&key("specific_force_mps2"), &segment.specific_force_mps2)?;
            let beyond = |peaks: &[f64; 3], range: f64| peaks.iter().any(|v| v.abs() >= range);
            if beyond(&segment.body_rate_deg_per_s, max_rate_deg_per_s) {
                return Err(check.fail(
                    &key("body_rate_deg_per_s"),
                    &format!(
                        "(segment \"{}\") must stay below the gyro's range \
                         imu.max_rate_deg_per_s = {max_rate_deg_per_s} on every axis",
                        segment.label
                    ),
                ));
            }
            if beyond(&segment.specific_force_mps2, max_force_mps2) {
                return Err(check.fail(
                    &key("specific_force_mps2"),
                    &format!(
                        "(segment \"{}\") must stay below the accelerometer's range \
                         imu.max_specific_force_mps2 = {max_force_mps2} on every axis",
                        segment.label
                    ),
                ));
            }
        }

        check.at_most(
            "manoeuvre[..].duration_s (total)",
            self.duration_s(),
            MAX_DURATION_S,
            " s",
            DURATION_REASON,
        )?;
        let truth_steps =
            self.frame_count() as f64 * f64::from(simulation.truth_substeps_per_frame);
        if truth_steps > MAX_TRUTH_STEPS {
            return Err(check.fail(
                "simulation.truth_substeps_per_frame",
                &format!(
                    "= {} gives {} truth integration steps (flight duration x imu.rate_hz x \
                     substeps), above the limit {} (about 40 default flights of run time)",
                    simulation.truth_substeps_per_frame,
                    number(truth_steps),
                    number(MAX_TRUTH_STEPS)
                ),
            ));
        }

        check.filter(&self.filter, fsw)?;
        if let Some(dispersion) = &self.dispersion {
            check.dispersion(dispersion, self)?;
        }
        for (index, scheduled) in self.commands.iter().enumerate() {
            let key = |name: &str| format!("command[{index}].{name}");
            check.within(&key("at_s"), scheduled.at_s, (0.0, self.duration_s()), " s")?;
            scheduled
                .to_command()
                .map_err(|(name, requirement)| check.fail(&key(name), &requirement))?;
        }
        let truth = self.gravity.as_ref();
        let gravity = truth.and_then(GravitySettings::violation);
        let flight = || gravity::flight_above_truth(&self.filter.gravity, truth);
        gravity
            .or_else(flight)
            .map_or(Ok(()), |(key, rule)| Err(check.fail(key, &rule)))
    }
}

/// The checks of `[filter]`: the flight software's own.
#[path = "validate_filter.rs"]
mod filter;
/// The checks of the star sensor's optional truth terms.
#[path = "validate_star.rs"]
mod star;
