//! The IMU step of a frame: input check, zero-order hold, closed-loop sensor corrections and
//! one strapdown step (the covariance's growth for a held sample is `covariance.rs`'s).

use super::*;

pub(super) fn sensor_corrections(calibration: &CalibrationEstimate) -> SensorCorrections {
    SensorCorrections {
        gyro_bias_rad_s: Vector3::from(calibration.gyro_bias_rad_s),
        accel_bias_mps2: Vector3::from(calibration.accel_bias_mps2),
        gyro_scale_factor: Vector3::from(calibration.gyro_scale_factor),
        accel_scale_factor: Vector3::from(calibration.accel_scale_factor),
    }
}

impl NavigationComputer {
    /// One strapdown step with the frame's IMU sample, or with the last good increment held
    /// when the sample is missing or refused (the covariance grows for the held error).
    pub(super) fn navigate(&mut self, sample: Option<ports::ImuSample>) {
        let period_s = self.config.imu.period_s;
        let checked = self.check_sample(sample);
        self.inflate_for_held_sample(checked.err());
        let increment = match checked {
            Ok(sample) => {
                self.navigation.frames_without_sample = 0;
                let increment = ImuIncrement {
                    delta_angle_rad: ports::vector(&sample.delta_angle_rad),
                    delta_velocity_mps: ports::vector(&sample.delta_velocity_mps),
                    interval_s: period_s,
                };
                self.navigation.last_increment = Some(increment);
                increment
            }
            Err(_) => self.navigation.last_increment.unwrap_or(ImuIncrement {
                delta_angle_rad: Vector3::zeros(),
                delta_velocity_mps: Vector3::zeros(),
                interval_s: period_s,
            }),
        };
        let closed_loop = self.covariance.filter.mode() == FilterMode::ClosedLoop;
        let corrections = if closed_loop {
            sensor_corrections(&self.calibration.estimate)
        } else {
            SensorCorrections::default()
        };
        let increment = if closed_loop && self.covariance.filter.imu_error().is_enabled() {
            self.compensate_systematic(&increment)
        } else {
            increment
        };
        match self.navigation.strapdown.step(
            &mut self.navigation.solution,
            &increment,
            &corrections,
            &self.launch_frame,
        ) {
            Ok(step) => self.covariance.sums.add(&step),
            Err(_) => {
                // nav-core left the solution untouched; time still advances with the frame.
                count(&mut self.health.counters.strapdown_failures);
                self.navigation.solution.time_s += period_s;
            }
        }
    }

    /// The increment with the fed-back systematic IMU errors removed (nav-core
    /// `imu_error::correct_increment` with no bias or scale factor): `Δθ − L̂_g Δθ − ĝ∘Δv`,
    /// `Δv − Â_a Δv`, before the strapdown's bias and scale-factor corrections. The filter's
    /// model applies both to the raw increment; the difference, `λ̂∘(L̂_g Δθ)` and the like,
    /// is second order (1e-4 × 2e-5 of the increment). A non-finite result keeps the raw
    /// increment (the corrections are finite by construction, so only a raw value can be).
    #[inline(never)]
    fn compensate_systematic(&self, raw: &ImuIncrement) -> ImuIncrement {
        nav_core::imu_error::correct_increment(
            raw,
            &SensorCorrections::default(),
            &self.calibration.imu_errors,
        )
        .unwrap_or(*raw)
    }

    /// The frame's sample after its input check (counted by fault): `Ok` to use it, `Err`
    /// with what the held increment may be wrong by when it is missing or refused.
    fn check_sample(
        &mut self,
        sample: Option<ports::ImuSample>,
    ) -> Result<ports::ImuSample, HeldSampleUncertainty> {
        let held = self.config.covariance.held_sample;
        let Some(sample) = sample else {
            count(&mut self.health.counters.imu_missing);
            self.navigation.frames_without_sample =
                self.navigation.frames_without_sample.saturating_add(1);
            return Err(held);
        };
        match self.navigation.imu_checker.check(&sample) {
            Ok(continuity) => {
                // Gaps already counted frame by frame are not counted twice.
                let unseen = continuity
                    .missing_samples
                    .saturating_sub(self.navigation.frames_without_sample);
                self.health.counters.imu_missing =
                    self.health.counters.imu_missing.saturating_add(unseen);
                Ok(sample)
            }
            Err(ImuFault::TimeJump) => {
                // The increments are sound; only the time tag is wrong. Navigation time is
                // frame-driven, so the sample is used.
                count(&mut self.health.counters.imu_time_jump);
                Ok(sample)
            }
            Err(ImuFault::NonFinite) => {
                count(&mut self.health.counters.imu_non_finite);
                Err(held)
            }
            Err(ImuFault::Saturated) => {
                count(&mut self.health.counters.imu_saturated);
                Err(self.saturation_sigma(&sample))
            }
            Err(ImuFault::Duplicate) => {
                count(&mut self.health.counters.imu_duplicate);
                Err(held)
            }
        }
    }

    /// A saturated sample's error, channel by channel: at least the IMU's range on a channel
    /// at or beyond full scale (the truth is beyond it by an unknown amount), the held-sample
    /// σ on the other.
    pub(super) fn saturation_sigma(&self, sample: &ports::ImuSample) -> HeldSampleUncertainty {
        let (held, limits) = (self.config.covariance.held_sample, self.config.imu);
        let at_full_scale = |values: &[f64; 3], range: f64| {
            values
                .iter()
                .any(|value| value.abs() >= range * limits.period_s)
        };
        let gyro = at_full_scale(&sample.delta_angle_rad, limits.max_rate_rad_s);
        let accelerometer =
            at_full_scale(&sample.delta_velocity_mps, limits.max_specific_force_mps2);
        HeldSampleUncertainty {
            rate_rad_s: if gyro {
                held.rate_rad_s.max(limits.max_rate_rad_s)
            } else {
                held.rate_rad_s
            },
            specific_force_mps2: if accelerometer {
                held.specific_force_mps2.max(limits.max_specific_force_mps2)
            } else {
                held.specific_force_mps2
            },
        }
    }
}
