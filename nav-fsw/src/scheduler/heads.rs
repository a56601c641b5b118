//! Two star-tracker heads (`star.second_head`): the filter fuses one head at a time, the
//! *active* one, and carries its installation error in its one installation block. The
//! other head's measurements, each paired with the active head's of the same time of
//! validity, estimate the two heads' relative alignment (nav-core `star_heads`: the vehicle's
//! attitude cancels in a pair, so no inertial information enters). When the active head falls
//! silent (an outage) or is declared faulty and the other head is aligned, the filter's
//! installation block is handed over to it (nav-core `hand_over_installation`: the block
//! rotated into the new head's axes, the alignment's covariance added); when the first head
//! pairs again, it is handed back. A head declared faulty is remembered: it takes the block
//! back only after `pairs_before_hand_over` pairs in a row agree with the head the filter
//! fuses, and an outage hands the block only to a head whose last pair agreed (a head that
//! disagrees with a healthy one is not trusted to carry it). The pairs' residuals feed their own consistency test
//! (`star_heads_inconsistent`): a relative alignment that moves shows a slowly varying error
//! or an uncorrected aberration that a single head hides in the attitude.
//! docs/guide/sensor-errors.md, "Two heads".

use super::*;
use nav_core::star_heads::RelativeAlignment;

/// Heads a tracker port may carry (`StarMeasurement::head` 0 and 1).
pub const MAX_STAR_HEADS: usize = 2;

/// The heads' state: the active head, each head's last measurement, the relative alignment.
#[derive(Debug, Clone, Copy)]
pub(super) struct StarHeads {
    /// The head the filter fuses (0 = `star`, 1 = `star.second_head`).
    pub(super) active: u8,
    /// Each head's last measurement: time of validity (s) and `q_ls` (launch-inertial).
    last: [Option<(f64, Quaternion<f64>)>; MAX_STAR_HEADS],
    /// Whether the two last measurements share a time of validity and wait to be paired.
    pair_pending: bool,
    /// Head 1's alignment to head 0, `q_s0s1`; `None` with one head.
    pub(super) alignment: Option<RelativeAlignment>,
    /// The pairs' consistency test (their NIS).
    pair_consistency: ConsistencyMonitor,
    /// The pairs' residual mean test ([`ResidualMean`]).
    pair_mean: ResidualMean,
    /// Time of validity of the last pair (s), for the slow error's walk of the alignment.
    last_pair_s: Option<f64>,
    /// Each head declared faulty while it was active and not since cleared by
    /// `pairs_before_hand_over` agreeing pairs.
    faulty: [bool; MAX_STAR_HEADS],
    /// Pairs accepted since the last rejected one.
    agreeing_pairs: u32,
}

/// Why the active head is lost ([`NavigationComputer::hand_over_from_lost_head`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum HeadLoss {
    /// It fell silent: its last pairs say whether the other head agreed with it.
    Outage,
    /// It was declared faulty: its last pairs disagree because of it.
    Fault,
}

/// A fading mean of a residual per axis, each axis normalised by its own σ (`√S_ii`), over
/// about `N` residuals: `m ← m + (u − m)/N`. Under the model the normalised residuals are
/// white with unit variance, so `m` has 1σ `√(1/(2N − 1))`; a relative alignment that moves
/// (each head's slowly varying error, an aberration the tracker leaves in) holds `m` away
/// from 0 by the motion over its σ however small the motion is against one residual's noise,
/// which the NIS does not see. An episode begins when `|m|` on some axis exceeds
/// [`RESIDUAL_MEAN_BOUND_SIGMA`] times that 1σ and ends below half of it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct ResidualMean {
    mean: [f64; 3],
    in_episode: bool,
}

/// The residual mean test's bound in its own σ: 5σ, for a false alarm per axis and
/// independent stretch of `N` residuals of 6e-7 (a few hundred stretches a flight).
const RESIDUAL_MEAN_BOUND_SIGMA: f64 = 5.0;

impl ResidualMean {
    /// Enters residual `z` with covariance diagonal `variances` over about `n` residuals;
    /// true when an episode has just begun. A non-finite or non-positive variance enters
    /// nothing.
    fn observe(&mut self, z: &[f64; 3], variances: &[f64; 3], n: u32) -> bool {
        let n = f64::from(n.max(1));
        let bound = RESIDUAL_MEAN_BOUND_SIGMA / nav_core::float::sqrt(2.0 * n - 1.0);
        let mut over = false;
        let mut under_half = true;
        for ((mean, residual), variance) in self.mean.iter_mut().zip(z).zip(variances) {
            if !(variance.is_finite() && *variance > 0.0 && residual.is_finite()) {
                return false;
            }
            let normalised = residual / nav_core::float::sqrt(*variance);
            *mean += (normalised - *mean) / n;
            over |= mean.abs() > bound;
            under_half &= mean.abs() < 0.5 * bound;
        }
        let began = over && !self.in_episode;
        if began {
            self.in_episode = true;
        } else if under_half {
            self.in_episode = false;
        }
        began
    }
}

impl StarHeads {
    /// Head 0 active, nothing heard; the alignment at its nominal value and prior when a
    /// second head is configured.
    ///
    /// # Errors
    /// As nav-core's `RelativeAlignment::new` (the configuration's validation refuses what
    /// it refuses).
    pub(super) fn new(star: &crate::config::StarSensorConfig) -> Result<Self, NavError> {
        let alignment = match &star.second_head {
            None => None,
            Some(head) => {
                let variance = head.alignment_prior_sigma_rad * head.alignment_prior_sigma_rad;
                Some(RelativeAlignment::new(
                    &ports::quaternion(&star.mounting_wxyz),
                    &ports::quaternion(&head.mounting_wxyz),
                    &(Matrix3::identity() * variance),
                )?)
            }
        };
        Ok(Self {
            active: 0,
            last: [None; MAX_STAR_HEADS],
            pair_pending: false,
            alignment,
            pair_consistency: ConsistencyMonitor::default(),
            pair_mean: ResidualMean::default(),
            last_pair_s: None,
            faulty: [false; MAX_STAR_HEADS],
            agreeing_pairs: 0,
        })
    }

    /// Notes head `head`'s measurement `q_ls` of time `time_tag_s`: a pair is pending when
    /// the other head's last measurement has the same time of validity (closer than
    /// `same_instant_s`: the heads are commanded on the flight computer's clock, so their tags
    /// differ only by round-off).
    pub(super) fn note(
        &mut self,
        head: usize,
        time_tag_s: f64,
        measured: Quaternion<f64>,
        same_instant_s: f64,
    ) {
        let Some(slot) = self.last.get_mut(head) else {
            return;
        };
        *slot = Some((time_tag_s, measured));
        if let [Some((first_s, _)), Some((second_s, _))] = self.last {
            self.pair_pending = (first_s - second_s).abs() <= same_instant_s;
        }
    }

    /// The pairs accepted so far (0 with one head).
    pub(super) fn pairs_accepted(&self) -> u32 {
        self.alignment
            .map_or(0, |alignment| alignment.pairs_accepted())
    }

    /// The head the filter does not fuse.
    fn other(&self) -> u8 {
        if self.active == 0 {
            1
        } else {
            0
        }
    }

    /// Whether head `head` may carry the installation block: aligned by at least
    /// `pairs_to_align` pairs and not declared faulty.
    fn may_carry(&self, head: u8, pairs_to_align: u32) -> bool {
        let faulty = self.faulty.get(usize::from(head)).copied().unwrap_or(true);
        !faulty && self.pairs_accepted() >= pairs_to_align
    }

    /// Whether head `head` was heard within `timeout_s` before `now_s`.
    fn heard_since(&self, head: usize, now_s: f64, timeout_s: f64) -> bool {
        matches!(self.last.get(head), Some(Some((time_s, _))) if now_s - time_s <= timeout_s)
    }
}

impl NavigationComputer {
    /// The configured mounting `q_bs` and noise 1σ per sensor axis of head `head` (the
    /// first head's for any head but 1).
    pub(super) fn head_mounting_and_noise(&self, head: u8) -> (Quaternion<f64>, [f64; 3]) {
        let star = &self.config.star;
        match (head, &star.second_head) {
            (1, Some(second)) => (
                ports::quaternion(&second.mounting_wxyz),
                second.noise_per_axis_rad(),
            ),
            _ => (
                ports::quaternion(&star.mounting_wxyz),
                star.noise_per_axis_rad(),
            ),
        }
    }

    /// Number of heads the configuration has.
    pub(super) fn head_count(&self) -> usize {
        if self.config.star.second_head.is_some() {
            MAX_STAR_HEADS
        } else {
            1
        }
    }

    /// Pairs the two heads' last measurements if a pair is pending: the alignment's gated
    /// update, its rejections and consistency counted; then, with head 1 active, the
    /// installation is handed back to head 0, which has just been heard. Run in a frame that
    /// fuses nothing, so that no update frame pays for it; under the default frame load in a
    /// frame of its own, without the covariance propagation (`fuse_or_propagate`).
    pub(super) fn pair_star_heads(&mut self) {
        if !core::mem::take(&mut self.heads.pair_pending) {
            return;
        }
        let (Some(second), [Some((time_s, first_q)), Some((_, second_q))]) =
            (self.config.star.second_head, self.heads.last)
        else {
            return;
        };
        let Some((first_q, second_q)) = self.comparable_pair(time_s, &first_q, &second_q) else {
            count(&mut self.health.counters.measurement_stale);
            return;
        };
        self.walk_alignment_to(time_s);
        let first_noise = self.config.star.noise_per_axis_rad();
        let gate = second.pair_gate_nis;
        let Some(alignment) = self.heads.alignment.as_mut() else {
            return;
        };
        let Ok(report) = alignment.update(
            &first_q,
            &second_q,
            &first_noise,
            &second.noise_per_axis_rad(),
            gate,
        ) else {
            count(&mut self.health.counters.filter_errors);
            return;
        };
        self.test_pair(&report, gate, second.pairs_before_hand_over);
        // The other head, heard now, takes the block when the active head was declared
        // faulty, and head 0 takes it back at an agreeing pair; either only if it may carry
        // it (a head declared faulty is cleared by `test_pair` after enough agreeing pairs).
        let heads = &self.heads;
        let other = heads.other();
        let wanted = self.aids.star.faulty || (heads.active == 1 && report.accepted);
        if wanted && heads.may_carry(other, second.pairs_before_hand_over) {
            // A refused hand-over is counted in `filter_errors`; the active head stays.
            let _ = self.hand_over_to_head(other);
        }
    }

    /// The pair as the flight software compares it: a tracker that leaves the aberration in
    /// turns each head by its own rotation, so both are corrected, as a fused measurement is,
    /// when the flight software makes the correction; `None` when that fails (no navigation
    /// solution at their time).
    fn comparable_pair(
        &self,
        time_s: f64,
        first: &Quaternion<f64>,
        second: &Quaternion<f64>,
    ) -> Option<(Quaternion<f64>, Quaternion<f64>)> {
        if !self.config.star.aberration_correction {
            return Some((*first, *second));
        }
        let snapshot = self.snapshot_at(time_s)?;
        let first = self.star_without_aberration(first, &snapshot).ok()?;
        let second = self.star_without_aberration(second, &snapshot).ok()?;
        Some((first, second))
    }

    /// Walks the alignment to the pair at `time_s` for the heads' slow error: each head's moves
    /// it by a walk of `2σ²/τ` per axis (the bound of
    /// `StarSensorConfig::installation_walk_rad2_per_s`, as an angle), both heads told the same σ.
    fn walk_alignment_to(&mut self, time_s: f64) {
        let heads = &mut self.heads;
        let elapsed_s = heads
            .last_pair_s
            .map_or(0.0, |last| (time_s - last).max(0.0));
        heads.last_pair_s = Some(time_s);
        let star = &self.config.star;
        let Some(alignment) = heads.alignment.as_mut() else {
            return;
        };
        if !(star.has_slow_error() && elapsed_s > 0.0) {
            return;
        }
        let [x, y, z] = star
            .slow_error_sigma_rad
            .map(|sigma| 4.0 * sigma * sigma / star.slow_error_correlation_time_s * elapsed_s);
        let walk = Matrix3::from_diagonal(&Vector3::new(x, y, z));
        if alignment.add_process_noise(&walk).is_err() {
            count(&mut self.health.counters.filter_errors);
        }
    }

    /// Whether the two heads' last measurements wait to be paired.
    pub(super) fn star_pair_is_pending(&self) -> bool {
        self.heads.pair_pending
    }

    /// Counts a rejected pair and feeds the pairs' NIS and residual mean tests (one
    /// `star_heads_inconsistent` per episode of either).
    ///
    /// A head declared faulty is cleared once `pairs_to_clear` pairs in a row agree with
    /// the active head, itself not declared faulty.
    fn test_pair(
        &mut self,
        report: &nav_core::star_heads::PairReport,
        gate: f64,
        pairs_to_clear: u32,
    ) {
        let heads = &mut self.heads;
        if report.accepted {
            heads.agreeing_pairs = heads.agreeing_pairs.saturating_add(1);
        } else {
            heads.agreeing_pairs = 0;
            count(&mut self.health.counters.star_pair_rejections);
        }
        if heads.agreeing_pairs >= pairs_to_clear && !self.aids.star.faulty {
            let other = usize::from(heads.other());
            if let Some(faulty) = heads.faulty.get_mut(other) {
                *faulty = false;
            }
        }
        let config = self.config.consistency;
        let nis = report.normalised_innovation_squared;
        let nis_began = heads
            .pair_consistency
            .observe(nis, report.accepted, gate, &config);
        let residual = &report.residual_rad;
        let covariance = &report.covariance_rad2;
        let variances = [0, 1, 2].map(|i| covariance.get((i, i)).copied().unwrap_or(f64::NAN));
        let mean_began = report.accepted
            && heads.pair_mean.observe(
                &[residual.x, residual.y, residual.z],
                &variances,
                config.time_constant_measurements,
            );
        if nis_began || mean_began {
            count(&mut self.health.counters.star_heads_inconsistent);
        }
    }

    /// After the active head's outage began or its fault was declared (`loss`; a fault is
    /// remembered against the head): the installation is handed over to the other head if
    /// that head was heard within the outage timeout, is aligned and not itself declared
    /// faulty ([`StarHeads::may_carry`]), and, after an outage, agreed with the lost head at
    /// their last pair.
    pub(super) fn hand_over_from_lost_head(&mut self, loss: HeadLoss) {
        let Some(second) = self.config.star.second_head else {
            return;
        };
        let heads = &mut self.heads;
        if loss == HeadLoss::Fault {
            if let Some(faulty) = heads.faulty.get_mut(usize::from(heads.active)) {
                *faulty = true;
            }
        }
        let other = heads.other();
        let now_s = self.navigation.solution.time_s;
        let timeout_s = self.config.timing.outage_timeout_s;
        let agreed = loss == HeadLoss::Fault || heads.agreeing_pairs > 0;
        if heads.heard_since(usize::from(other), now_s, timeout_s)
            && heads.may_carry(other, second.pairs_before_hand_over)
            && agreed
        {
            // A refused hand-over is counted in `filter_errors`; the active head stays.
            let _ = self.hand_over_to_head(other);
        }
    }

    /// [`Command::SelectStarHead`]: the checks an automatic hand-over makes
    /// ([`Self::hand_over_from_lost_head`]), then the hand-over.
    pub(super) fn select_star_head(&mut self, head: u8) -> Result<(), CommandError> {
        let Some(second) = self.config.star.second_head else {
            return Err(CommandError::StarHeadNotConfigured(head));
        };
        if usize::from(head) >= MAX_STAR_HEADS {
            return Err(CommandError::StarHeadNotConfigured(head));
        }
        if head == self.heads.active {
            return Ok(());
        }
        if !self.heads.may_carry(head, second.pairs_before_hand_over) {
            return Err(CommandError::StarHeadNotAligned(head));
        }
        let now_s = self.navigation.solution.time_s;
        let timeout_s = self.config.timing.outage_timeout_s;
        if !self.heads.heard_since(usize::from(head), now_s, timeout_s) {
            return Err(CommandError::StarHeadSilent(head));
        }
        self.hand_over_to_head(head).map_err(CommandError::Filter)
    }

    /// Hands the filter's installation block over to head `new` (nav-core `star_heads`): the
    /// installation estimate and its covariance become the new head's, the star queue (the
    /// old head's measurements) is emptied, the aid is acquired afresh with the star noise
    /// matching and fault state cleared (they were the old head's). Counted in
    /// `star_head_handovers`; a refused hand-over changes nothing, counts a filter error and
    /// returns nav-core's error ([`NavError::InvalidConfiguration`] with one head).
    fn hand_over_to_head(&mut self, new: u8) -> Result<(), NavError> {
        let Some(alignment) = self.heads.alignment else {
            return Err(NavError::InvalidConfiguration);
        };
        let old = self.heads.active;
        let (old_mounting, _) = self.head_mounting_and_noise(old);
        let (new_mounting, _) = self.head_mounting_and_noise(new);
        // The alignment is head 1's to head 0: from head 1 back to head 0 it is reversed.
        let oriented = if new == 1 {
            alignment
        } else {
            alignment.reversed()
        };
        let installation = self.installation_estimate();
        let handed = oriented
            .hand_over(&old_mounting, &new_mounting, &installation)
            .and_then(|hand_over| {
                self.covariance.filter.hand_over_installation(
                    &hand_over.rotation_new_from_old,
                    &hand_over.added_covariance_half_angle,
                )?;
                Ok(hand_over.installation_estimate)
            });
        let estimate = match handed {
            Ok(estimate) => estimate,
            Err(error) => {
                count(&mut self.health.counters.filter_errors);
                return Err(error);
            }
        };
        self.calibration.estimate.star_installation_wxyz =
            [estimate.w, estimate.i, estimate.j, estimate.k];
        self.heads.active = new;
        for _ in 0..STAR_QUEUE_CAPACITY {
            if self.aids.star_queue.pop_due(f64::INFINITY).is_none() {
                break;
            }
            count(&mut self.health.counters.measurement_stale);
        }
        // The default state is also not yet acquired: the new head's first measurement is
        // gated by the acquisition gate.
        self.aids.star = AidingSensor::default();
        self.aids.star_noise.clear();
        count(&mut self.health.counters.star_head_handovers);
        Ok(())
    }
}
