//! Fusion of one due measurement: forming it at its time of validity, referring it to now,
//! the gated update and its conclusion (statistics, fault state, feedback).

use super::*;

impl NavigationComputer {
    pub(super) fn installation_estimate(&self) -> Quaternion<f64> {
        ports::quaternion(&self.calibration.estimate.star_installation_wxyz)
    }

    pub(super) fn fuse_one_due_measurement(&mut self) -> FrameFusion {
        let Some(due) = self.next_due() else {
            return FrameFusion::None;
        };
        let (aid, tag) = (due.aid(), due.time_tag_s());
        if self.fault_state(aid.sensor()).faulty {
            count(&mut self.health.counters.ignored_from_faulty_sensor);
            return aid.fusion(false);
        }
        let Some(snapshot) = self.snapshot_at(tag) else {
            count(&mut self.health.counters.measurement_stale);
            return FrameFusion::None;
        };
        if self.is_gnss_jump(&due, &snapshot) {
            count(&mut self.health.counters.gnss_jump);
            self.note_rejection(aid);
            return aid.fusion(false);
        }
        // Formed where it lies: the large measurement is never copied.
        let mut measurement = self.form_measurement(&due, &snapshot);
        // A late measurement is referred to the error state at the covariance's time
        // (nav-core docs), in place: the measurement is never copied (every copy is a
        // `memcpy` on the target).
        let latency_s = self.covariance.time_s - tag;
        if let Ok(m) = &mut measurement {
            if let Err(error) = self.refer_to_now(m, aid, latency_s) {
                measurement = Err(error);
            }
        }
        let signature = match &due {
            Due::Star(_, measured) => self.aberration_signature(measured, &snapshot),
            _ => None,
        };
        let report = match &measurement {
            Ok(m) => self.update(m, aid),
            Err(error) => Err(*error),
        };
        if let (Some(signature), Ok(report)) = (signature, &report) {
            self.test_aberration(report, &signature);
        }
        self.conclude(aid, report)
    }

    /// The aberration rotation `a_s` (sensor axes) of the star measurement `measured`, with
    /// the navigation velocity at its time of validity (`snapshot`): what its innovations
    /// follow if the aberration is left in while the configuration does not correct it, or
    /// corrected twice or with the wrong sign while it does (`aberration_monitor`). Out of
    /// line, as [`Self::test_aberration`]: the GNSS frames, the dearest, pay a branch.
    #[inline(never)]
    fn aberration_signature(
        &self,
        measured: &Quaternion<f64>,
        snapshot: &Snapshot,
    ) -> Option<Vector3<f64>> {
        nav_core::aberration::rotation_rad(measured, &snapshot.velocity_mps).ok()
    }

    /// Feeds an accepted star innovation of an acquired tracker to the aberration test
    /// (nav-fsw `aberration_monitor`; counted per episode).
    #[inline(never)]
    fn test_aberration(
        &mut self,
        report: &nav_core::filter::InnovationReport,
        signature: &Vector3<f64>,
    ) {
        if !(report.accepted && self.aids.star.acquired) {
            return;
        }
        let n = self.config.consistency.time_constant_measurements;
        // A flight whose innovations have shown a larger unmodelled error (an aid failing its
        // NIS test, a run blamed on the inertial solution, the star noise matched) carries
        // something the aberration cannot be told from: it would project onto the signature
        // too. The aberration is what is left when those monitors are quiet.
        let counters = &self.health.counters;
        let quiet = counters.star_inconsistent == 0
            && counters.gnss_inconsistent == 0
            && counters.gnss_velocity_inconsistent == 0
            && counters.inertial_suspect == 0
            && !self.aids.star_noise.engaged();
        let claimable = quiet && !self.aids.star_consistency.failing();
        if self.star_aberration.observe(
            &report.innovation,
            &report.covariance,
            signature,
            n,
            claimable,
            self.config.star.aberration_correction,
        ) {
            count(&mut self.health.counters.star_aberration_suspected);
        }
    }

    /// Whether `due` is a GNSS fix farther than `gnss.max_jump_m` from the antenna position
    /// predicted at its time of validity (`snapshot`).
    pub(super) fn is_gnss_jump(&self, due: &Due, snapshot: &Snapshot) -> bool {
        let Due::GnssPosition(_, position) = due else {
            return false;
        };
        let lever_arm = ports::vector(&self.config.gnss.lever_arm_body_m);
        let predicted = snapshot.position_m + attitude::rotate(&snapshot.attitude, &lever_arm);
        // The fix is already converted: only its position is checked here.
        let fix = ports::GnssFix {
            gps_week: 0,
            gps_seconds_of_week: 0.0,
            position_ecef_m: array3(position),
            velocity_ecef_mps: None,
        };
        matches!(
            check_gnss(&fix, position, &predicted, self.config.gnss.max_jump_m),
            Err(GnssFault::Jump)
        )
    }

    /// The linearised measurement of `due` at its time of validity (`snapshot`).
    pub(super) fn form_measurement(
        &self,
        due: &Due,
        snapshot: &Snapshot,
    ) -> Result<LinearMeasurement, NavError> {
        let lever_arm = ports::vector(&self.config.gnss.lever_arm_body_m);
        match due {
            Due::Star(_, measured) => star_sensor(
                &snapshot.attitude,
                &self.head_mounting_and_noise(self.heads.active).0,
                &self.installation_estimate(),
                &self.star_without_aberration(measured, snapshot)?,
                &self.star_noise_rad(),
            ),
            // nav-core refuses a non-finite fix (the jump check passes NaN through).
            Due::GnssPosition(_, position) => gnss_position(
                &snapshot.attitude,
                &snapshot.position_m,
                &lever_arm,
                position,
                self.config.gnss.noise_m,
            ),
            Due::GnssVelocity(_, turned_velocity) => {
                // The lever-arm term's body rates: the mean of the last propagation interval.
                let rate = self.covariance.last_point.map_or(
                    BodyRate {
                        corrected_rad_s: Vector3::zeros(),
                        measured_rad_s: Vector3::zeros(),
                    },
                    |point| BodyRate {
                        corrected_rad_s: point.corrected_rate_rad_s,
                        measured_rad_s: point.measured_rate_rad_s,
                    },
                );
                let fix = GnssVelocityFix {
                    turned_velocity_mps: *turned_velocity,
                    earth: self.launch_frame.earth_rotation(),
                };
                gnss_velocity(
                    &snapshot.attitude,
                    &snapshot.position_m,
                    &snapshot.velocity_mps,
                    &lever_arm,
                    &rate,
                    &fix,
                    self.config.gnss.velocity_noise_mps,
                )
            }
        }
    }

    /// The star noise angles (1σ, sensor axes: cross-boresight about x and y, roll about z,
    /// the boresight) of the next update: the configured ones, or once the star consistency
    /// test has failed and `star.noise_matching` is on, the innovations' (nav-fsw
    /// `noise_matching`, never below the configured).
    pub fn star_noise_rad(&self) -> [f64; 3] {
        let (_, configured) = self.head_mounting_and_noise(self.heads.active);
        self.aids.star_noise.noise_rad(&configured)
    }

    /// Enters a tested star measurement in the noise matching (after the tracker's
    /// acquisition: `acquired_before`), and engages it when the star consistency test fails
    /// and the innovations' scatter shows the tracker noisier than configured (counted once:
    /// the matching stays on until the filter is re-initialised). Called before
    /// the consistency monitor sees the measurement's NIS.
    pub(super) fn match_star_noise(
        &mut self,
        report: &nav_core::filter::InnovationReport,
        acquired_before: bool,
    ) {
        if !self.config.star.noise_matching {
            return;
        }
        if acquired_before {
            let (innovation, variances) = per_axis(report);
            let used = self.star_noise_rad();
            let gate = self.gate_nis(Aid::Star);
            let time_constant = self.config.consistency.time_constant_measurements;
            let nis = report.normalised_innovation_squared;
            self.aids.star_noise.observe(
                &innovation,
                &variances,
                &used,
                nis,
                report.accepted,
                gate,
                time_constant,
            );
        }
        // Only when the scatter points at the tracker (nav-fsw `noise_matching`, "When").
        let (_, configured) = self.head_mounting_and_noise(self.heads.active);
        if self.aids.star_consistency.failing() && self.aids.star_noise.engage(&configured) {
            count(&mut self.health.counters.star_noise_matched);
        }
    }

    /// The measured `q_is` with the velocity aberration removed when the configuration says
    /// the tracker leaves it in (`star.aberration_correction`), with the navigation velocity
    /// at the measurement's time of validity (`snapshot`; nav-core `aberration`); else the
    /// measurement itself. A 1 m/s velocity error moves the correction by 7e-4″, so the
    /// residual's Jacobian needs no velocity term.
    ///
    /// # Errors
    /// As nav-core's `aberration::correct`: [`NavError::NonFiniteInput`] for a non-finite
    /// velocity or measurement, [`NavError::DegenerateQuaternion`] for one of (near) zero norm
    /// (the intake's unit-norm check refuses those before).
    pub(super) fn star_without_aberration(
        &self,
        measured: &Quaternion<f64>,
        snapshot: &Snapshot,
    ) -> Result<Quaternion<f64>, NavError> {
        if self.config.star.aberration_correction {
            nav_core::aberration::correct(measured, &snapshot.velocity_mps)
        } else {
            Ok(*measured)
        }
    }

    /// Refers a measurement `latency_s` old to the current error state: `H (I − A Δ)` and,
    /// for a GNSS position, the correlated error's `h_ε = exp(Δ/τ)` (nav-core `gnss_error`).
    /// On an error the measurement is unchanged.
    pub(super) fn refer_to_now(
        &self,
        measurement: &mut LinearMeasurement,
        aid: Aid,
        latency_s: f64,
    ) -> Result<(), NavError> {
        let Some(point) = self.covariance.last_point else {
            return Ok(());
        };
        if latency_s <= SAME_INSTANT_FRACTION_OF_PERIOD * self.config.imu.period_s {
            return Ok(());
        }
        self.arithmetic
            .refer_to_later_time(measurement, &point, latency_s)?;
        if aid == Aid::GnssPosition {
            measurement.border_coefficient = self
                .config
                .filter
                .gnss_error
                .position_coefficient(latency_s);
        }
        Ok(())
    }

    /// The gated update of one aiding measurement (frozen blocks held).
    pub(super) fn update(
        &mut self,
        measurement: &LinearMeasurement,
        aid: Aid,
    ) -> Result<nav_core::filter::InnovationReport, NavError> {
        let gate = self.gate_nis(aid);
        let frozen = self.calibration.manager.frozen_blocks();
        self.arithmetic
            .update(&mut self.covariance.filter, measurement, gate, &frozen)
    }

    /// Gate statistics, counters, fault state and closed-loop feedback after an update.
    pub(super) fn conclude(
        &mut self,
        aid: Aid,
        report: Result<nav_core::filter::InnovationReport, NavError>,
    ) -> FrameFusion {
        let report = match report {
            Err(_) => {
                count(&mut self.health.counters.filter_errors);
                self.note_rejection(aid);
                return aid.fusion(false);
            }
            Ok(report) => report,
        };
        self.statistics(aid).last_nis = report.normalised_innovation_squared;
        if aid == Aid::Star {
            // Before the acquisition below: the acquisition measurement is not entered.
            let acquired_before = self.aids.star.acquired;
            self.match_star_noise(&report, acquired_before);
        }
        if aid == Aid::GnssPosition {
            self.observe_whiteness(&report);
        }
        if report.accepted {
            let state = self.fault_state(aid.sensor());
            // A run's first innovations are kept only while a run lasts.
            if core::mem::take(&mut state.consecutive_rejections) != 0 {
                self.clear_runs(aid.sensor());
            }
            self.statistics(aid).acquired = true;
            if aid.measures_attitude() {
                self.restart_second_order_attitude();
            }
            if self.covariance.filter.mode() == FilterMode::ClosedLoop {
                self.feed_back();
            }
        } else {
            count(self.gate_rejections(aid));
            self.note_run_innovation(aid, &report);
            self.note_rejection(aid);
        }
        // After the fault logic, which reads the verdict the run of rejections began under.
        self.observe_consistency(aid, &report);
        aid.fusion(report.accepted)
    }

    /// Feeds a tested measurement's NIS to its aid's consistency monitor (counted per
    /// episode).
    pub(super) fn observe_consistency(
        &mut self,
        aid: Aid,
        report: &nav_core::filter::InnovationReport,
    ) {
        let gate = self.gate_nis(aid);
        let config = self.config.consistency;
        let (monitor, counter) = match aid {
            Aid::Star => (
                &mut self.aids.star_consistency,
                &mut self.health.counters.star_inconsistent,
            ),
            Aid::GnssPosition => (
                &mut self.aids.gnss_consistency,
                &mut self.health.counters.gnss_inconsistent,
            ),
            Aid::GnssVelocity => (
                &mut self.aids.gnss_velocity_consistency,
                &mut self.health.counters.gnss_velocity_inconsistent,
            ),
        };
        let nis = report.normalised_innovation_squared;
        if monitor.observe(nis, report.accepted, gate, &config) {
            count(counter);
        }
    }

    /// Feeds a GNSS position innovation to the whiteness monitor (counted per episode).
    pub(super) fn observe_whiteness(&mut self, report: &nav_core::filter::InnovationReport) {
        let began = self.aids.gnss_whiteness.observe(
            &report.innovation,
            &report.covariance,
            self.config.gnss.whiteness_window_fixes,
            self.config.gnss.whiteness_threshold,
        );
        if began {
            count(&mut self.health.counters.gnss_innovations_correlated);
        }
    }
}

/// A measurement's innovation and the diagonal of its covariance `S`, per axis (a non-finite
/// `S_ii` where the matrix has none, which every user refuses).
pub(super) fn per_axis(report: &nav_core::filter::InnovationReport) -> ([f64; 3], [f64; 3]) {
    let (nu, s) = (&report.innovation, &report.covariance);
    let variances = [0, 1, 2].map(|i| s.get((i, i)).copied().unwrap_or(f64::NAN));
    ([nu.x, nu.y, nu.z], variances)
}
