//! The navigation-solution history for delayed fusion: one snapshot per frame and the
//! closed-loop corrections fed back since, applied when a snapshot is read.

use super::*;

/// Navigation solution of one frame, kept for delayed fusion, as it was when recorded: the
/// closed-loop corrections fed back since then are applied when it is read
/// ([`NavigationComputer::corrected`]).
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

impl NavigationComputer {
    pub(super) fn record_snapshot(&mut self) {
        if self.history.is_full() {
            self.history.pop_front();
        }
        // Cannot fail after the pop above; a refusal would only lose the oldest entry.
        let _ = self.history.push_back(Snapshot {
            frame: self.frame,
            time_s: self.navigation.time_s,
            attitude: self.navigation.attitude,
            position_m: self.navigation.position_m,
            velocity_mps: self.navigation.velocity_mps,
        });
    }

    /// `snapshot` with every correction fed back since it was recorded (in its frame or
    /// later), in feedback order: the same arithmetic as correcting the whole history at
    /// each feedback. Frame counters are compared by age (wrapping). The corrections are in
    /// feedback order, so those to apply are the newest ones: counted from the back, then
    /// applied oldest first (a measurement of the current frame needs none).
    pub(super) fn corrected(&self, snapshot: &Snapshot) -> Snapshot {
        let snapshot_age = self.frame.wrapping_sub(snapshot.frame);
        let applies =
            |correction: &Correction| self.frame.wrapping_sub(correction.frame) <= snapshot_age;
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

    /// The navigation solution at `time_s`, interpolated between the two bracketing frames
    /// of the history (both corrected first); `None` outside the history. Searched from the
    /// newest frame, where most measurements fall (the frame times increase, so the match
    /// or the bracketing pair is the one a search from the oldest would find).
    pub(super) fn snapshot_at(&self, time_s: f64) -> Option<Snapshot> {
        let tolerance = SAME_INSTANT_FRACTION_OF_PERIOD * self.config.imu.period_s;
        let mut later: Option<&Snapshot> = None;
        for snapshot in self.history.iter().rev() {
            if (snapshot.time_s - time_s).abs() <= tolerance {
                return Some(self.corrected(snapshot));
            }
            if snapshot.time_s < time_s {
                let Some(after) = later else {
                    // A tag a little after the newest frame (within the future tolerance,
                    // e.g. clock rounding) uses the newest frame.
                    let future_s = time_s - snapshot.time_s;
                    return (future_s <= self.config.timing.future_tolerance_s)
                        .then(|| self.corrected(snapshot));
                };
                // `after` is later than `time_s`: it was neither a match nor earlier.
                let (before, after) = (self.corrected(snapshot), self.corrected(after));
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
