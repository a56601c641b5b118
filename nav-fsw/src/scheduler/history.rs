//! The navigation-solution history for delayed fusion: one snapshot per frame and the
//! closed-loop corrections fed back since, applied when a snapshot is read.

use super::*;

/// Navigation solution of one frame, kept for delayed fusion, as it was when recorded: the
/// closed-loop corrections fed back since then are applied when it is read
/// ([`History::corrected`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Snapshot {
    /// Frame counter when recorded.
    pub(super) frame: u32,
    pub(super) time_s: f64,
    pub(super) attitude: Quaternion<f64>,
    pub(super) position_m: Vector3<f64>,
    pub(super) velocity_mps: Vector3<f64>,
}

/// One closed-loop correction of the navigation solution (attitude `q ← q ⊗ δq`, position
/// `p ← p + δp`, velocity `v ← v + δv`), kept for the snapshots recorded up to its frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Correction {
    /// Frame counter of the feedback.
    pub(super) frame: u32,
    pub(super) attitude: Quaternion<f64>,
    pub(super) position_m: Vector3<f64>,
    pub(super) velocity_mps: Vector3<f64>,
}

/// `q0 ⊗ exp(s · log(q0* ⊗ q1))`: constant-rate interpolation between two attitudes.
pub(super) fn interpolate_attitude(
    q0: &Quaternion<f64>,
    q1: &Quaternion<f64>,
    s: f64,
) -> Quaternion<f64> {
    let relative = attitude::log_rotation_vector(&attitude::product(&attitude::conjugate(q0), q1));
    attitude::product(q0, &attitude::exp_rotation_vector(&(relative * s)))
}

/// The navigation solutions of the last [`HISTORY_CAPACITY`] frames and the closed-loop
/// feedbacks of the same frames (at most one per frame). A feedback is applied to a snapshot
/// when the snapshot is read: correcting every snapshot at every feedback would cost far more
/// on the target than the few snapshots a fusion reads.
#[derive(Debug, Clone)]
pub(super) struct History {
    snapshots: Deque<Snapshot, HISTORY_CAPACITY>,
    corrections: Deque<Correction, HISTORY_CAPACITY>,
}

impl History {
    /// No snapshot and no correction.
    pub(super) const fn new() -> Self {
        Self {
            snapshots: Deque::new(),
            corrections: Deque::new(),
        }
    }

    /// Records the navigation solution of frame `frame`, in place of the oldest when full.
    pub(super) fn record(&mut self, frame: u32, navigation: &NavigationState) {
        if self.snapshots.is_full() {
            self.snapshots.pop_front();
        }
        // Cannot fail after the pop above; a refusal would only lose the oldest entry.
        let _ = self.snapshots.push_back(Snapshot {
            frame,
            time_s: navigation.time_s,
            attitude: navigation.attitude,
            position_m: navigation.position_m,
            velocity_mps: navigation.velocity_mps,
        });
    }

    /// Keeps a feedback for the snapshots recorded up to its frame. One older than every
    /// snapshot is no longer needed, so dropping the oldest when full never loses one that is.
    pub(super) fn record_correction(&mut self, correction: Correction) {
        if self.corrections.is_full() {
            self.corrections.pop_front();
        }
        let _ = self.corrections.push_back(correction);
    }

    /// `snapshot` with every correction fed back since it was recorded (in its frame or
    /// later, `now` being the current frame), in feedback order: the same arithmetic as
    /// correcting the whole history at each feedback. Frame counters are compared by age
    /// (wrapping). The corrections are in feedback order, so those to apply are the newest
    /// ones: counted from the back, then applied oldest first (a measurement of the current
    /// frame needs none).
    pub(super) fn corrected(&self, now: u32, snapshot: &Snapshot) -> Snapshot {
        let snapshot_age = now.wrapping_sub(snapshot.frame);
        let applies = |correction: &Correction| now.wrapping_sub(correction.frame) <= snapshot_age;
        let newer = self
            .corrections
            .iter()
            .rev()
            .take_while(|correction| applies(correction))
            .count();
        let (older_half, newer_half) = self.corrections.as_slices();
        let first = self.corrections.len().saturating_sub(newer);
        let (from_older, from_newer) = match first.checked_sub(older_half.len()) {
            None => (older_half.get(first..).unwrap_or(&[]), newer_half),
            Some(offset) => (&[][..], newer_half.get(offset..).unwrap_or(&[])),
        };
        let mut corrected = *snapshot;
        for correction in from_older.iter().chain(from_newer) {
            corrected.attitude = attitude::product(&corrected.attitude, &correction.attitude);
            corrected.position_m += correction.position_m;
            corrected.velocity_mps += correction.velocity_mps;
        }
        corrected
    }

    /// The navigation solution at `time_s` (`now` being the current frame), interpolated
    /// between the two bracketing frames (both corrected first); a frame within
    /// `tolerance_s` of `time_s` is taken as it is, and a time up to `future_tolerance_s`
    /// after the newest frame takes the newest; `None` outside the history. Searched from the
    /// newest frame, where most measurements fall (the frame times increase, so the match or
    /// the bracketing pair is the one a search from the oldest would find).
    pub(super) fn at(
        &self,
        now: u32,
        time_s: f64,
        tolerance_s: f64,
        future_tolerance_s: f64,
    ) -> Option<Snapshot> {
        let mut later: Option<&Snapshot> = None;
        for snapshot in self.snapshots.iter().rev() {
            if (snapshot.time_s - time_s).abs() <= tolerance_s {
                return Some(self.corrected(now, snapshot));
            }
            if snapshot.time_s < time_s {
                let Some(after) = later else {
                    // A tag a little after the newest frame (within the future tolerance,
                    // e.g. clock rounding) uses the newest frame.
                    let future_s = time_s - snapshot.time_s;
                    return (future_s <= future_tolerance_s).then(|| self.corrected(now, snapshot));
                };
                // `after` is later than `time_s`: it was neither a match nor earlier.
                let (before, after) = (self.corrected(now, snapshot), self.corrected(now, after));
                let s = (time_s - before.time_s) / (after.time_s - before.time_s);
                return Some(Snapshot {
                    frame: after.frame,
                    time_s,
                    attitude: interpolate_attitude(&before.attitude, &after.attitude, s),
                    position_m: before.position_m + (after.position_m - before.position_m) * s,
                    velocity_mps: before.velocity_mps
                        + (after.velocity_mps - before.velocity_mps) * s,
                });
            }
            later = Some(snapshot);
        }
        None
    }
}

impl NavigationComputer {
    /// Records the current navigation solution in the history.
    pub(super) fn record_snapshot(&mut self) {
        self.navigation
            .history
            .record(self.frame, &self.navigation.solution);
    }

    /// The navigation solution at `time_s` from the history ([`History::at`]): frames closer
    /// than [`SAME_INSTANT_FRACTION_OF_PERIOD`] of the IMU period are the same instant.
    pub(super) fn snapshot_at(&self, time_s: f64) -> Option<Snapshot> {
        self.navigation.history.at(
            self.frame,
            time_s,
            SAME_INSTANT_FRACTION_OF_PERIOD * self.config.imu.period_s,
            self.config.timing.future_tolerance_s,
        )
    }
}
