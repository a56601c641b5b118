//! Covariance propagation at the interval's mean motion, the growth for a held IMU sample and
//! for the second-order attitude term, variance protection and the documented filter
//! recovery.

use super::*;

/// Rates and forces summed over the covariance-propagation interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct PropagationSums {
    pub(super) frames: u32,
    pub(super) corrected_rate: Vector3<f64>,
    pub(super) measured_rate: Vector3<f64>,
    pub(super) corrected_force: Vector3<f64>,
    pub(super) measured_force: Vector3<f64>,
}

impl PropagationSums {
    pub(super) const EMPTY: PropagationSums = PropagationSums {
        frames: 0,
        corrected_rate: Vector3::new(0.0, 0.0, 0.0),
        measured_rate: Vector3::new(0.0, 0.0, 0.0),
        corrected_force: Vector3::new(0.0, 0.0, 0.0),
        measured_force: Vector3::new(0.0, 0.0, 0.0),
    };

    pub(super) fn add(&mut self, step: &StepOutput) {
        self.frames = self.frames.saturating_add(1);
        self.corrected_rate += step.corrected_rate_rad_s;
        self.measured_rate += step.measured_rate_rad_s;
        self.corrected_force += step.corrected_specific_force_mps2;
        self.measured_force += step.measured_specific_force_mps2;
    }
}

impl NavigationComputer {
    pub(super) fn propagate_covariance(&mut self) {
        let sums = self.covariance.sums;
        self.covariance.sums = PropagationSums::EMPTY;
        // The covariance is at the navigation time from here on, propagated or, on a
        // failure, restarted.
        self.covariance.time_s = self.navigation.solution.time_s;
        let frames = f64::from(sums.frames.max(1));
        let interval_s = frames * self.config.imu.period_s;
        // Built in place (a local moved into `last_point` is a copy on the target).
        let point = self.covariance.last_point.insert(LinearisationPoint {
            corrected_rate_rad_s: sums.corrected_rate / frames,
            corrected_specific_force_mps2: sums.corrected_force / frames,
            measured_rate_rad_s: sums.measured_rate / frames,
            measured_specific_force_mps2: sums.measured_force / frames,
            body_to_inertial: attitude::rotation_matrix(&self.navigation.solution.attitude),
            gravity_gradient_per_s2: self
                .config
                .strapdown
                .gravity
                .gravity_gradient_launch(&self.launch_frame, &self.navigation.solution.position_m),
        });
        self.calibration.manager.observe_motion(
            &point.corrected_rate_rad_s,
            &point.corrected_specific_force_mps2,
        );
        // Block-structured discretisation and F P Fᵀ + Qd (nav-core `structured`); frozen
        // blocks get no process noise.
        let frozen = self.calibration.manager.frozen_blocks();
        let order = self.config.filter.discretisation_order;
        let step = Propagation {
            point,
            noise: &self.covariance.process_noise,
            interval_s,
            order,
            frozen: &frozen,
        };
        let result = self.arithmetic.predict(
            &mut self.covariance.filter,
            &mut self.covariance.model,
            &step,
        );
        match result {
            Ok(()) => {
                self.covariance.second_order_pending_s += interval_s;
                self.add_installation_walk(interval_s);
                self.protect_covariance();
            }
            Err(_) => self.recover_filter(),
        }
    }

    /// The installation states' random walk for the tracker's slowly varying error
    /// (`star.slow_error_sigma_rad`, [`crate::config::StarSensorConfig::installation_walk_rad2_per_s`]):
    /// `Qd = diag(q) Δ` on the installation block, nothing else. The installation error
    /// enters no dynamic state (its rows and columns of the system matrix are zero), so the
    /// walk has no cross terms. Added whether or not the block is frozen: a held estimate
    /// of a drifting alignment grows uncertain all the same.
    pub(super) fn add_installation_walk(&mut self, interval_s: f64) {
        let Some([x, y, z]) = self.covariance.installation_walk_rad2_per_s else {
            return;
        };
        let walk = Matrix3::from_diagonal(&Vector3::new(x, y, z)) * interval_s;
        if self
            .covariance
            .filter
            .add_block_covariance(STAR_INSTALLATION, &walk)
            .is_err()
        {
            count(&mut self.health.counters.filter_errors);
        }
    }

    /// The covariance grows for what a held IMU sample may be wrong by
    /// ([`HeldSampleUncertainty`]), coherently (nav-core `unmodelled`): the held error is the
    /// same all gap long, so the 1σ grows as the number of held frames. Attitude states are
    /// half-angles, so their σ is half the angle's.
    pub(super) fn inflate_for_held_sample(&mut self, held: Option<HeldSampleUncertainty>) {
        let Some(sigma) = held else {
            self.covariance.held_attitude.restart();
            self.covariance.held_velocity.restart();
            return;
        };
        count(&mut self.health.counters.imu_held_frames);
        let period_s = self.config.imu.period_s;
        let added = [
            (
                ATTITUDE,
                self.covariance
                    .held_attitude
                    .grow(HALF_ANGLE_PER_ANGLE * sigma.rate_rad_s * period_s),
            ),
            (
                VELOCITY,
                self.covariance
                    .held_velocity
                    .grow(sigma.specific_force_mps2 * period_s),
            ),
        ];
        for (block, variance) in added {
            if self
                .covariance
                .filter
                .add_block_variance(block, variance)
                .is_err()
            {
                count(&mut self.health.counters.filter_errors);
            }
        }
    }

    /// The attitude covariance grows for the kinematics' second-order term `½ ϑ × δω`
    /// (`covariance.second_order_attitude`, nav-core `unmodelled`): in the direction of the
    /// term's covariance, by its 1σ accumulated since the last accepted star-sensor update,
    /// coherently while the gyro rate error stays correlated with the previous step's.
    /// It runs in frames that fuse no measurement, which have time to spare (aiding comes at
    /// 10 Hz, the IMU at 500 Hz), over the propagation time since it last ran, at the last
    /// propagation's rate.
    pub(super) fn inflate_for_second_order_attitude(&mut self) {
        let (Some(point), true) = (
            self.covariance.last_point,
            self.config.covariance.second_order_attitude.is_bounded(),
        ) else {
            return;
        };
        let (measured_rate_rad_s, interval_s) = (
            &point.measured_rate_rad_s,
            self.covariance.second_order_pending_s,
        );
        self.covariance.second_order_pending_s = 0.0;
        let rate_covariance = bilinear_attitude_rate_covariance(
            self.covariance.filter.covariance(),
            measured_rate_rad_s,
        );
        let rate_variance = rate_covariance.trace();
        if !(rate_variance.is_finite() && rate_variance > 0.0) {
            return;
        }
        let correlation = rate_error_correlation(
            self.covariance.filter.covariance(),
            measured_rate_rad_s,
            &self.covariance.second_order_rate_rad_s,
        );
        self.covariance.second_order_rate_rad_s = *measured_rate_rad_s;
        let added = self.covariance.second_order_attitude.grow_correlated(
            nav_core::float::sqrt(rate_variance) * interval_s,
            correlation,
        );
        let direction = rate_covariance / rate_variance;
        if self
            .covariance
            .filter
            .add_block_covariance(ATTITUDE, &(direction * added))
            .is_err()
        {
            count(&mut self.health.counters.filter_errors);
        }
    }

    /// The attitude is measured (or the filter starts afresh): the second-order growth starts
    /// again from zero.
    pub(super) fn restart_second_order_attitude(&mut self) {
        self.covariance.second_order_attitude.restart();
        self.covariance.second_order_pending_s = 0.0;
    }

    /// Documented recovery from a filter that nav-core refuses to propagate (non-finite
    /// result): `x = 0`, `P` re-initialised from the configured 1σ, calibration convergence
    /// forgotten; the navigation solution and the sensor corrections fed back so far are
    /// kept. Counted in `filter_resets`.
    pub(super) fn recover_filter(&mut self) {
        count(&mut self.health.counters.filter_resets);
        // A refused configuration (checked at start-up, so never here) keeps the filter.
        let _ = self.covariance.filter.restart(&self.config.filter);
        self.calibration.manager.restart();
        self.restart_after_filter_reset();
    }

    /// After the filter was restarted (recovery or command): everything that follows its
    /// state starts again.
    pub(super) fn restart_after_filter_reset(&mut self) {
        self.restart_second_order_attitude();
        // The filter is back at its prior: each aid's first acceptance is an acquisition.
        self.reacquire(Sensor::Star);
        self.reacquire(Sensor::Gnss);
        // Its innovations are tested afresh.
        self.aids.star_consistency.clear();
        self.aids.star_noise.clear();
        // The blame on the inertial solution was the old filter's.
        self.aids.star.inertial_blamed = false;
        self.aids.gnss.inertial_blamed = false;
        self.aids.gnss_consistency.clear();
        self.aids.gnss_velocity_consistency.clear();
        self.star_aberration = crate::aberration_monitor::AberrationMonitor::default();
    }

    /// Variance floors and ceilings (module docs), the core's and the optional blocks' in
    /// use, in place: only the diagonal is read unless a bound is crossed (nav-core
    /// `protect_variances`, `protect_optional_variances`); symmetry is kept by construction.
    pub(super) fn protect_covariance(&mut self) {
        let core = self.covariance.filter.protect_variances(
            &self.covariance.variance_floor,
            &self.covariance.variance_ceiling,
        );
        let optional = self
            .covariance
            .filter
            .protect_optional_variances(&self.optional_variance_bounds);
        if core || optional {
            count(&mut self.health.counters.covariance_clamps);
            if !self
                .covariance
                .filter
                .covariance()
                .iter()
                .all(|v| v.is_finite())
            {
                self.recover_filter();
            }
        }
    }
}
