//! Measurement intake: polling the ports, checking and queueing, and choosing the one due
//! measurement to fuse.

use super::*;

/// A GNSS fix in the launch-inertial frame, queued until due.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct GnssQueued {
    pub(super) position_m: [f64; 3],
    /// The receiver's ECEF velocity turned into launch-inertial axes, without the Earth's
    /// rotation, which the fusion adds at the estimated antenna position (nav-core
    /// `measurement::gnss_velocity`). Valid when `has_velocity` (the receiver outputs velocity
    /// and velocity fusion is configured); plain words rather than an `Option` keep the
    /// queue's copies word-aligned.
    pub(super) turned_velocity_mps: [f64; 3],
    pub(super) has_velocity: bool,
}

/// Which queued measurement to fuse.
pub(super) enum Due {
    Star(f64, Quaternion<f64>),
    GnssPosition(f64, Vector3<f64>),
    /// The fix's velocity turned into launch-inertial axes (`GnssQueued::turned_velocity_mps`).
    GnssVelocity(f64, Vector3<f64>),
}

impl Due {
    pub(super) const fn aid(&self) -> Aid {
        match self {
            Due::Star(..) => Aid::Star,
            Due::GnssPosition(..) => Aid::GnssPosition,
            Due::GnssVelocity(..) => Aid::GnssVelocity,
        }
    }

    pub(super) const fn time_tag_s(&self) -> f64 {
        match self {
            Due::Star(tag, _) | Due::GnssPosition(tag, _) | Due::GnssVelocity(tag, _) => *tag,
        }
    }
}

impl NavigationComputer {
    pub(super) fn poll_measurements<S: StarSensorPort, G: GnssPort>(
        &mut self,
        star: &mut S,
        gnss: &mut G,
    ) {
        let now_s = self.navigation.solution.time_s;
        let timing = self.config.timing;
        let (mut star_heard, mut gnss_heard) = (false, false);
        for _ in 0..MAX_POLLS_PER_FRAME {
            let Some(measurement) = star.poll() else {
                break;
            };
            let head = usize::from(measurement.head);
            let Some(last_star) = self
                .aids
                .last_star
                .get(head)
                .filter(|_| head < self.head_count())
            else {
                count(&mut self.health.counters.star_unknown_head);
                continue;
            };
            // The outage monitor watches the head the filter fuses.
            let active = measurement.head == self.heads.active;
            star_heard |= active;
            match check_star(
                &measurement,
                last_star.as_ref(),
                self.config.star.unit_norm_tolerance,
            ) {
                Err(StarFault::NonFinite) => count(&mut self.health.counters.star_non_finite),
                Err(StarFault::NotUnit) => count(&mut self.health.counters.star_not_unit),
                Ok((quaternion, flipped)) => {
                    if flipped {
                        count(&mut self.health.counters.star_sign_flip);
                    }
                    // Remember the sensor's own sign, so that a sensor that changes its sign
                    // convention (e.g. keeps w ≥ 0 while the attitude turns) is counted once
                    // per change, not on every later sample.
                    if let Some(last) = self.aids.last_star.get_mut(head) {
                        *last = Some(if flipped { -quaternion } else { quaternion });
                    }
                    let launch_inertial = self
                        .config
                        .sensor_frames
                        .star_in_launch_inertial(&quaternion);
                    if self.config.star.second_head.is_some() {
                        let tag = measurement.time_tag_s;
                        let same_instant_s =
                            SAME_INSTANT_FRACTION_OF_PERIOD * self.config.imu.period_s;
                        self.heads.note(head, tag, launch_inertial, same_instant_s);
                    }
                    if !active {
                        continue;
                    }
                    if self.operations.disabled(Sensor::Star) {
                        count(&mut self.operations.commands.measurements_of_disabled_aid);
                        continue;
                    }
                    let pushed = self.aids.star_queue.push(
                        measurement.time_tag_s,
                        launch_inertial,
                        now_s,
                        timing.max_latency_s,
                        timing.future_tolerance_s,
                    );
                    if let Err(refusal) = pushed {
                        self.count_refusal(refusal, Sensor::Star);
                    }
                }
            }
        }
        for _ in 0..MAX_POLLS_PER_FRAME {
            let Some(fix) = gnss.poll() else {
                break;
            };
            gnss_heard = true;
            match self.gnss_in_launch_frame(&fix) {
                Err(_) => count(&mut self.health.counters.gnss_non_finite),
                Ok(_) if self.operations.disabled(Sensor::Gnss) => {
                    count(&mut self.operations.commands.measurements_of_disabled_aid);
                }
                Ok((time_tag_s, queued)) => {
                    let pushed = self.aids.gnss_queue.push(
                        time_tag_s,
                        queued,
                        now_s,
                        timing.max_latency_s,
                        timing.future_tolerance_s,
                    );
                    if let Err(refusal) = pushed {
                        self.count_refusal(refusal, Sensor::Gnss);
                    }
                }
            }
        }
        let timeout_s = timing.outage_timeout_s;
        // After an outage the state error has grown unseen: the aid is acquired again.
        if self.aids.star_outage.observe(now_s, star_heard, timeout_s) {
            count(&mut self.health.counters.star_outages);
            self.reacquire(Sensor::Star);
            self.hand_over_from_lost_head(heads::HeadLoss::Outage);
        }
        if self.aids.gnss_outage.observe(now_s, gnss_heard, timeout_s) {
            count(&mut self.health.counters.gnss_outages);
            self.reacquire(Sensor::Gnss);
        }
    }

    /// A fix's navigation time and the fix converted to the launch-inertial frame; its
    /// velocity only when velocity fusion is configured (`gnss.velocity_noise_mps > 0`).
    pub(super) fn gnss_in_launch_frame(
        &self,
        fix: &ports::GnssFix,
    ) -> Result<(f64, GnssQueued), NavError> {
        let time_tag_s = self
            .config
            .sensor_frames
            .navigation_time_s(fix.gps_week, fix.gps_seconds_of_week)
            .map_err(|_| NavError::NonFiniteInput)?;
        let position_ecef = ports::vector(&fix.position_ecef_m);
        let position_m = self
            .launch_frame
            .ecef_to_launch_inertial(&position_ecef, time_tag_s)?;
        let turned_velocity_mps = match fix.velocity_ecef_mps {
            Some(velocity) if self.config.gnss.velocity_noise_mps > 0.0 => Some(
                self.launch_frame
                    .ecef_velocity_to_launch_axes(&ports::vector(&velocity), time_tag_s)?,
            ),
            _ => None,
        };
        Ok((
            time_tag_s,
            GnssQueued {
                position_m: array3(&position_m),
                turned_velocity_mps: turned_velocity_mps.as_ref().map_or([0.0; 3], array3),
                has_velocity: turned_velocity_mps.is_some(),
            },
        ))
    }

    /// Measurements tagged up to this time (s) are due: the covariance's time, within
    /// `timing.future_tolerance_s`.
    fn due_before_s(&self) -> f64 {
        self.covariance.time_s + self.config.timing.future_tolerance_s
    }

    /// The time tags of the oldest star measurement and the oldest GNSS fix, each if due.
    fn due_tags(&self) -> (Option<f64>, Option<f64>) {
        let due_before_s = self.due_before_s();
        let due = |tag: Option<f64>| tag.filter(|t| *t <= due_before_s);
        (
            due(self.aids.star_queue.oldest_time_tag()),
            due(self.aids.gnss_queue.oldest_time_tag()),
        )
    }

    /// Whether [`Self::next_due`] has a measurement (and takes nothing).
    pub(super) fn measurement_is_due(&self) -> bool {
        let (star_tag, gnss_tag) = self.due_tags();
        self.aids.pending_gnss_position.is_some() || star_tag.is_some() || gnss_tag.is_some()
    }

    /// The oldest due measurement, taken from its queue (a GNSS fix with velocity gives its
    /// velocity, and its position next time).
    pub(super) fn next_due(&mut self) -> Option<Due> {
        if let Some((tag, position)) = self.aids.pending_gnss_position.take() {
            return Some(Due::GnssPosition(tag, position));
        }
        let due_before_s = self.due_before_s();
        let (star_tag, gnss_tag) = self.due_tags();
        let star_first = match (star_tag, gnss_tag) {
            (Some(s), Some(g)) => s <= g,
            (Some(_), None) => true,
            (None, Some(_)) => false,
            (None, None) => return None,
        };
        if star_first {
            self.aids
                .star_queue
                .pop_due(due_before_s)
                .map(|(tag, q)| Due::Star(tag, q))
        } else {
            let (tag, fix) = self.aids.gnss_queue.pop_due(due_before_s)?;
            let position = ports::vector(&fix.position_m);
            if fix.has_velocity {
                self.aids.pending_gnss_position = Some((tag, position));
                Some(Due::GnssVelocity(
                    tag,
                    ports::vector(&fix.turned_velocity_mps),
                ))
            } else {
                Some(Due::GnssPosition(tag, position))
            }
        }
    }
}
