//! The checks of the star tracker (`[star_sensor]`, head 0, and every
//! `[[star_sensor.additional_heads]]`): rate, noise, mounting, installation error, rate limit,
//! outages and the optional truth terms (per-axis noise, the slowly varying Gauss–Markov error
//! and the periodic error). An additional head is checked key for key as head 0 is, its keys
//! named `star_sensor.additional_heads[i].…` and its messages naming its head number `i + 1`.

use super::{Checker, ScenarioError};
use crate::scenario::star_sensor::MAX_STAR_HEADS;
use crate::scenario::{number, StarSensorSettings};

/// The table of head 0.
const HEAD_0: &str = "star_sensor";

impl Checker<'_> {
    /// Every head of the tracker: head 0 against the IMU frame `period_s` and the flight
    /// software's outage timeout (`aiding`: the lowest aiding rate and the reason), then the
    /// additional heads, each with head 0's rate (the heads share the flight computer's clock,
    /// so their time tags coincide) and no heads of its own.
    pub(super) fn star_sensor(
        &self,
        star: &StarSensorSettings,
        period_s: f64,
        aiding: (f64, &str),
    ) -> Result<(), ScenarioError> {
        self.star_head(HEAD_0, star, period_s, aiding)?;
        let heads = star.heads().count();
        if heads > MAX_STAR_HEADS {
            return Err(self.fail(
                "star_sensor.additional_heads",
                &format!(
                    "gives {heads} heads with [star_sensor], more than the limit {MAX_STAR_HEADS} \
                     (each head has its own random streams, and the stream ids are laid out \
                     for at most {MAX_STAR_HEADS})"
                ),
            ));
        }
        for (index, head) in star.additional_heads.iter().enumerate() {
            let head_number = index + 1;
            let prefix = format!("{HEAD_0}.additional_heads[{index}]");
            self.additional_star_head(&prefix, head, star, period_s, aiding)
                .map_err(|error| name_the_head(error, head_number))?;
        }
        Ok(())
    }

    /// An additional head at `prefix`: head 0's rate exactly, no nested heads, then the checks
    /// of any head.
    fn additional_star_head(
        &self,
        prefix: &str,
        head: &StarSensorSettings,
        head_0: &StarSensorSettings,
        period_s: f64,
        aiding: (f64, &str),
    ) -> Result<(), ScenarioError> {
        // Exactly equal: the heads sample at the same frames.
        if head.rate_hz.partial_cmp(&head_0.rate_hz) != Some(std::cmp::Ordering::Equal) {
            return Err(self.fail(
                &format!("{prefix}.rate_hz"),
                &format!(
                    "= {} Hz differs from star_sensor.rate_hz = {} Hz: every head samples on \
                     the flight computer's clock at head 0's rate, so their time tags coincide",
                    number(head.rate_hz),
                    number(head_0.rate_hz)
                ),
            ));
        }
        if !head.additional_heads.is_empty() {
            return Err(self.fail(
                &format!("{prefix}.additional_heads"),
                "is not allowed in a head: give every head as its own \
                 [[star_sensor.additional_heads]] table",
            ));
        }
        self.star_head(prefix, head, period_s, aiding)
    }

    /// The keys of one head, named under `prefix`.
    fn star_head(
        &self,
        prefix: &str,
        star: &StarSensorSettings,
        period_s: f64,
        (min_aiding_rate_hz, outage_reason): (f64, &str),
    ) -> Result<(), ScenarioError> {
        let key = |name: &str| format!("{prefix}.{name}");
        self.positive(&key("rate_hz"), star.rate_hz)?;
        self.limit(
            star.rate_hz > min_aiding_rate_hz,
            &key("rate_hz"),
            star.rate_hz,
            ("is not above", min_aiding_rate_hz),
            " Hz",
            outage_reason,
        )?;
        self.whole_frames(&key("rate_hz"), 1.0 / star.rate_hz, period_s, 1.0)?;
        self.sigma(&key("noise_arcsec"), star.noise_arcsec, true)?;
        self.rotation_vector(
            &key("mounting_rotation_vector_deg"),
            &star.mounting_rotation_vector_deg,
            360.0,
            "deg",
        )?;
        self.rotation_vector(
            &key("installation_error_rotation_vector_rad"),
            &star.installation_error_rotation_vector_rad,
            std::f64::consts::TAU,
            "rad",
        )?;
        self.non_negative(&key("max_rate_deg_per_s"), star.max_rate_deg_per_s)?;
        self.non_negative(&key("reacquisition_s"), star.reacquisition_s)?;
        self.outages(&key("outages"), &star.outages)?;
        self.star_sensor_truth(prefix, star)
    }

    /// The per-axis noise (both keys or neither, each 0 or a 1σ, `noise_arcsec` equal to the
    /// larger), the slow error (each 1σ 0 or in range, τ > 0 when on) and the periodic error
    /// (each amplitude 0 or in range, period > 0 when on, phase finite) of the head at
    /// `prefix`.
    fn star_sensor_truth(
        &self,
        prefix: &str,
        star: &StarSensorSettings,
    ) -> Result<(), ScenarioError> {
        self.star_per_axis_noise(prefix, star)?;
        for (axis, sigma) in ["x", "y", "z"].iter().zip(star.slow_error_sigma_arcsec) {
            self.sigma(
                &format!("{prefix}.slow_error_sigma_arcsec ({axis})"),
                sigma,
                true,
            )?;
        }
        let key = format!("{prefix}.slow_error_correlation_time_s");
        if star.has_slow_error() {
            self.positive(&key, star.slow_error_correlation_time_s)?;
        } else {
            self.non_negative(&key, star.slow_error_correlation_time_s)?;
        }
        for (axis, amplitude) in ["x", "y", "z"]
            .iter()
            .zip(star.periodic_error_amplitude_arcsec)
        {
            let key = format!("{prefix}.periodic_error_amplitude_arcsec ({axis})");
            self.sigma(&key, amplitude, true)?;
        }
        let key = format!("{prefix}.periodic_error_period_s");
        if star.has_periodic_error() {
            self.positive(&key, star.periodic_error_period_s)?;
        } else {
            self.non_negative(&key, star.periodic_error_period_s)?;
        }
        self.finite(
            &format!("{prefix}.periodic_error_phase_deg"),
            star.periodic_error_phase_deg,
        )
    }

    /// `cross_boresight_noise_arcsec` and `roll_noise_arcsec`: both or neither, each 0 or a
    /// 1σ, and then `noise_arcsec` their larger value (the flight software is told the
    /// per-axis values; the single-noise studies take `noise_arcsec`).
    fn star_per_axis_noise(
        &self,
        prefix: &str,
        star: &StarSensorSettings,
    ) -> Result<(), ScenarioError> {
        let (cross_key, roll_key) = (
            format!("{prefix}.cross_boresight_noise_arcsec"),
            format!("{prefix}.roll_noise_arcsec"),
        );
        let (cross, roll) = match (star.cross_boresight_noise_arcsec, star.roll_noise_arcsec) {
            (None, None) => return Ok(()),
            (Some(cross), Some(roll)) => (cross, roll),
            (Some(_), None) => {
                return Err(self.fail(&roll_key, &format!("must be given with {cross_key}")))
            }
            (None, Some(_)) => {
                return Err(self.fail(&cross_key, &format!("must be given with {roll_key}")))
            }
        };
        self.sigma(&cross_key, cross, true)?;
        self.sigma(&roll_key, roll, true)?;
        let largest = cross.max(roll);
        // Exactly equal (the dispersion scales both alike, which keeps them so).
        if star.noise_arcsec.partial_cmp(&largest) == Some(std::cmp::Ordering::Equal) {
            return Ok(());
        }
        Err(self.fail(
            &format!("{prefix}.noise_arcsec"),
            &format!(
                "= {} conflicts with the per-axis noise: with {cross_key} and {roll_key} given, \
                 noise_arcsec (the single-noise studies' 1σ) must equal the larger of them, {}",
                number(star.noise_arcsec),
                number(largest)
            ),
        ))
    }
}

/// `error` with the requirement saying which head it is about (`head_number` ≥ 1).
fn name_the_head(error: ScenarioError, head_number: usize) -> ScenarioError {
    match error {
        ScenarioError::Invalid {
            origin,
            key,
            requirement,
        } => ScenarioError::Invalid {
            origin,
            key,
            requirement: format!("{requirement} (star-tracker head {head_number})"),
        },
        other => other,
    }
}
