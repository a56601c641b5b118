//! The aiding measurements and the sensors behind them: every setting, statistic and counter
//! that depends on the measurement is chosen here, by [`Aid`] or [`Sensor`], so fusion runs
//! one path for all of them.

use super::*;

/// The aiding sensors, each with one fault state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Sensor {
    /// The star sensor (attitude).
    Star,
    /// The GNSS receiver: its position and velocity share one fault state, since a receiver
    /// fault spoils both.
    Gnss,
}

impl Sensor {
    /// The sensor's position in per-sensor arrays.
    pub(super) const fn index(self) -> usize {
        match self {
            Sensor::Star => 0,
            Sensor::Gnss => 1,
        }
    }

    /// The other aiding sensor: the independent witness of the inertial solution.
    pub(super) const fn other(self) -> Sensor {
        match self {
            Sensor::Star => Sensor::Gnss,
            Sensor::Gnss => Sensor::Star,
        }
    }

    /// The error-state blocks the sensor observes directly and the inertial error that
    /// drives them: the states whose uncertainty is widened when its disagreement is blamed
    /// on the inertial solution. The star sensor sees the attitude, driven by the gyro bias
    /// (a g-sensitivity or a gyro misalignment acts as one); the receiver sees position and
    /// velocity, driven by the accelerometer bias (a non-orthogonal triad acts as one).
    pub(super) const fn inertial_blocks(self) -> &'static [StateBlock] {
        match self {
            Sensor::Star => &[ATTITUDE, GYRO_BIAS],
            Sensor::Gnss => &[POSITION, VELOCITY, ACCEL_BIAS],
        }
    }
}

/// The matched star noise over the configured noise beyond which a run of star rejections is
/// blamed on the filter's fit ([`NavigationComputer::star_noise_exceeds_configured`]): the
/// ratio at which the noise matching engages (nav-fsw `noise_matching`).
const NOISE_MATCHED_BLAME_RATIO: f64 = crate::noise_matching::NOISIER_THAN_CONFIGURED_RATIO;

/// The blocks beyond the attitude and gyro bias that the star updates fit: the installation
/// error and the gyro scale factor. When a run of star rejections grew, or the tracker proved
/// noisier than configured, the fit of these is as suspect as the attitude's (a gyro bias,
/// scale factor and installation fitted together in the first seconds with too small a noise
/// are each confidently wrong), so they are widened with it.
pub(super) const STAR_FITTED_BLOCKS: [StateBlock; 2] = [STAR_INSTALLATION, GYRO_SCALE_FACTOR];

/// The aiding measurements, one routine each for forming them and one shared path for
/// referral, update and fault handling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Aid {
    Star,
    GnssPosition,
    GnssVelocity,
}

impl Aid {
    /// Telemetry of an accepted or rejected measurement.
    pub(super) const fn fusion(self, accepted: bool) -> FrameFusion {
        match (self, accepted) {
            (Aid::Star, true) => FrameFusion::StarAccepted,
            (Aid::Star, false) => FrameFusion::StarRejected,
            (Aid::GnssPosition, true) => FrameFusion::GnssAccepted,
            (Aid::GnssPosition, false) => FrameFusion::GnssRejected,
            (Aid::GnssVelocity, true) => FrameFusion::GnssVelocityAccepted,
            (Aid::GnssVelocity, false) => FrameFusion::GnssVelocityRejected,
        }
    }

    /// The sensor the measurement comes from.
    pub(super) const fn sensor(self) -> Sensor {
        match self {
            Aid::Star => Sensor::Star,
            Aid::GnssPosition | Aid::GnssVelocity => Sensor::Gnss,
        }
    }

    /// Whether the measurement observes the attitude directly: an accepted one bounds the
    /// attitude error, so the second-order attitude growth starts again.
    pub(super) const fn measures_attitude(self) -> bool {
        matches!(self, Aid::Star)
    }
}

/// Gate statistics and fault state of one aiding sensor (or, for `acquired` and `last_nis`,
/// of one aid).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct AidingSensor {
    pub(super) consecutive_rejections: u32,
    pub(super) faulty: bool,
    pub(super) last_nis: f64,
    /// Whether the sensor's innovations were already failing the consistency test when its
    /// current run of gate rejections began (a gradual onset: the inertial solution drifting
    /// away, not a step in the sensor).
    pub(super) run_began_inconsistent: bool,
    /// The aid's first rejected innovation in its sensor's current run of gate rejections.
    pub(super) run_start_innovation: Option<[f64; 3]>,
    /// Whether a later rejected innovation of the run differs from the first by more than
    /// two measurements' noise can explain ([`NavigationComputer::note_run_innovation`]):
    /// the innovations grow, as from an inertial solution drifting away.
    pub(super) run_innovation_grew: bool,
    /// Whether a run of the sensor's rejections has been blamed on the inertial solution
    /// since start-up, the filter's last re-initialisation or the last cleared fault: from
    /// then on the evidence points at the inertial solution, and each rejection widens its
    /// uncertainty at once ([`NavigationComputer::note_rejection`]).
    pub(super) inertial_blamed: bool,
    /// Whether the filter has accepted a measurement of the aid since start-up, the aid's
    /// last outage, the filter's last re-initialisation or its sensor's last cleared fault:
    /// until then its gate is the acquisition gate ([`crate::config::ACQUISITION_GATE_NIS`]).
    pub(super) acquired: bool,
}

impl Aids {
    /// Forgets every fault declaration and gate statistic: each aid is used, and acquired,
    /// again.
    pub(super) fn clear_faults(&mut self) {
        self.star = AidingSensor::default();
        self.gnss = AidingSensor::default();
        self.gnss_velocity = AidingSensor::default();
    }
}

impl NavigationComputer {
    /// The χ² gate (normalised innovation squared) of `aid`: the larger of its gate and its
    /// acquisition gate until the filter has accepted one of its measurements
    /// ([`AidingSensor::acquired`]), its gate after.
    pub(super) fn gate_nis(&self, aid: Aid) -> f64 {
        let (star, gnss) = (&self.config.star, &self.config.gnss);
        let (statistics, gate, acquisition_gate) = match aid {
            Aid::Star => (&self.aids.star, star.gate_nis, star.acquisition_gate_nis),
            Aid::GnssPosition => (&self.aids.gnss, gnss.gate_nis, gnss.acquisition_gate_nis),
            Aid::GnssVelocity => (
                &self.aids.gnss_velocity,
                gnss.velocity_gate_nis,
                gnss.velocity_acquisition_gate_nis,
            ),
        };
        if statistics.acquired {
            gate
        } else {
            gate.max(acquisition_gate)
        }
    }

    /// The aids of `sensor` are to be acquired again (an outage, a re-initialised filter, a
    /// cleared fault): their next acceptance is gated by the acquisition gate.
    pub(super) fn reacquire(&mut self, sensor: Sensor) {
        match sensor {
            Sensor::Star => self.aids.star.acquired = false,
            Sensor::Gnss => {
                self.aids.gnss.acquired = false;
                self.aids.gnss_velocity.acquired = false;
            }
        }
    }

    /// The gate statistics of `aid` (the GNSS velocity keeps its own NIS).
    pub(super) fn statistics(&mut self, aid: Aid) -> &mut AidingSensor {
        match aid {
            Aid::Star => &mut self.aids.star,
            Aid::GnssPosition => &mut self.aids.gnss,
            Aid::GnssVelocity => &mut self.aids.gnss_velocity,
        }
    }

    /// The gate-rejection counter of `aid`.
    pub(super) fn gate_rejections(&mut self, aid: Aid) -> &mut u32 {
        match aid {
            Aid::Star => &mut self.health.counters.star_gate_rejections,
            Aid::GnssPosition => &mut self.health.counters.gnss_gate_rejections,
            Aid::GnssVelocity => &mut self.health.counters.gnss_velocity_gate_rejections,
        }
    }

    /// The fault state of `sensor`.
    pub(super) fn fault_state(&mut self, sensor: Sensor) -> &mut AidingSensor {
        match sensor {
            Sensor::Star => &mut self.aids.star,
            Sensor::Gnss => &mut self.aids.gnss,
        }
    }

    /// One more rejection of `aid`'s sensor. After `timing.rejections_to_declare_faulty` in
    /// a row the run is blamed ([`NavigationComputer::blames_inertial_solution`]): on the
    /// inertial solution, the sensor is kept and the uncertainty of the states it observes
    /// widened ([`NavigationComputer::widen_inertial_uncertainty`], counted in
    /// `inertial_suspect`), and a new run begins; on the sensor, it is declared faulty
    /// (counted once per declaration).
    ///
    /// Once a run of the sensor has been blamed on the inertial solution
    /// ([`AidingSensor::inertial_blamed`]), the first rejection of each later run, and every
    /// rejection of a run that began while the sensor's innovations failed their consistency
    /// test, widens the inertial uncertainty at once by its own NIS over 3, capped at the gate
    /// ([`NavigationComputer::widen_inertial_blocks`]), not after a run: the evidence has
    /// pointed at the inertial solution, whose error (a g-sensitivity in each burn) would
    /// otherwise have the healthy sensor's measurements refused a run at a time. A step in the
    /// sensor while its innovations are consistent widens once (its first rejection) and
    /// goes on counting, so it is still declared faulty after
    /// `timing.rejections_to_declare_faulty`.
    pub(super) fn note_rejection(&mut self, aid: Aid) {
        let limit = self.config.timing.rejections_to_declare_faulty;
        let sensor = aid.sensor();
        let inconsistent = self.inconsistent(sensor);
        let state = self.fault_state(sensor);
        let first = state.consecutive_rejections == 0;
        if first {
            state.run_began_inconsistent = inconsistent;
        }
        state.consecutive_rejections = state.consecutive_rejections.saturating_add(1);
        if state.faulty {
            return;
        }
        if state.inertial_blamed && (first || state.run_began_inconsistent) {
            let nis = self.statistics(aid).last_nis.min(self.gate_nis(aid));
            self.widen_inertial_blocks(sensor, nis, &[]);
        }
        if self.fault_state(sensor).consecutive_rejections < limit {
            return;
        }
        if self.blames_inertial_solution(sensor) {
            let state = self.fault_state(sensor);
            state.consecutive_rejections = 0;
            state.inertial_blamed = true;
            count(&mut self.health.counters.inertial_suspect);
            self.widen_inertial_uncertainty(sensor);
            self.clear_runs(sensor);
        } else {
            self.fault_state(sensor).faulty = true;
            count(match sensor {
                Sensor::Star => &mut self.health.counters.star_declared_faulty,
                Sensor::Gnss => &mut self.health.counters.gnss_declared_faulty,
            });
            if sensor == Sensor::Star {
                // A faulty head leaves its fault state behind when the other takes over.
                self.hand_over_from_lost_head(heads::HeadLoss::Fault);
            }
        }
    }

    /// Whether `sensor`'s run of rejections is the inertial solution's doing: a sensor fault
    /// (a step, a frozen output) starts while its innovations are consistent and leaves the
    /// other sensor consistent; an inertial error unmodelled by the filter (an IMU
    /// misalignment, a g-sensitivity) grows, so the sensor's innovations fail the
    /// consistency test before they fail the gate, or the other sensor's fail it too.
    pub(super) fn blames_inertial_solution(&mut self, sensor: Sensor) -> bool {
        self.fault_state(sensor).run_began_inconsistent
            || self.run_innovation_grew(sensor)
            || self.inconsistent(sensor.other())
    }

    /// Whether the star noise the innovations show exceeds the configured noise on some axis
    /// by more than [`NOISE_MATCHED_BLAME_RATIO`] (nav-fsw `noise_matching`, engaged): the
    /// tracker is noisier than the filter was told, so the states the filter fitted with the
    /// smaller noise are overconfident, and a run of rejections that follows is the fit's
    /// doing, not a fault of the tracker.
    pub(super) fn star_noise_exceeds_configured(&self) -> bool {
        let (_, configured) = self.head_mounting_and_noise(self.heads.active);
        self.star_noise_rad()
            .iter()
            .zip(&configured)
            .any(|(matched, configured)| *matched > NOISE_MATCHED_BLAME_RATIO * configured)
    }

    /// Whether the rejected innovations of any aid of `sensor` grew during the current run,
    /// or (star) the tracker's noise proved larger than configured.
    fn run_innovation_grew(&self, sensor: Sensor) -> bool {
        match sensor {
            Sensor::Star => {
                self.aids.star.run_innovation_grew || self.star_noise_exceeds_configured()
            }
            Sensor::Gnss => {
                self.aids.gnss.run_innovation_grew || self.aids.gnss_velocity.run_innovation_grew
            }
        }
    }

    /// Enters a gate-rejected innovation `ν` (covariance `S`) of `aid` in its sensor's run:
    /// the first is kept; a later one marks the run as grown when
    /// `Σ_i (ν_i − ν_first,i)² / (2 S_ii)` exceeds the aid's gate. A sensor fault (a step, a
    /// frozen output) repeats its innovation, so the difference of two is the noise of two
    /// measurements, `2 S`, and the sum is χ²(3) below the gate but for the gate's own false
    /// alarm; an inertial error the filter does not model (a gyro bias its first updates got
    /// wrong, a g-sensitivity in a burn) drives the innovations away from where the run began.
    pub(super) fn note_run_innovation(
        &mut self,
        aid: Aid,
        report: &nav_core::filter::InnovationReport,
    ) {
        let gate = self.gate_nis(aid);
        let (innovation, variances) = super::fusion::per_axis(report);
        let statistics = self.statistics(aid);
        let Some(start) = statistics.run_start_innovation else {
            statistics.run_start_innovation = Some(innovation);
            statistics.run_innovation_grew = false;
            return;
        };
        let change: f64 = innovation
            .iter()
            .zip(&start)
            .zip(&variances)
            .map(|((now, first), variance)| (now - first) * (now - first) / (2.0 * variance))
            .sum();
        // A NaN change (a non-finite S) marks nothing.
        statistics.run_innovation_grew |= change > gate;
    }

    /// Forgets the runs' first innovations of `sensor`'s aids: a new run begins.
    pub(super) fn clear_runs(&mut self, sensor: Sensor) {
        let aids: &mut [&mut AidingSensor] = match sensor {
            Sensor::Star => &mut [&mut self.aids.star],
            Sensor::Gnss => &mut [&mut self.aids.gnss, &mut self.aids.gnss_velocity],
        };
        for aid in aids.iter_mut() {
            aid.run_start_innovation = None;
            aid.run_innovation_grew = false;
        }
    }

    /// Whether any aid of `sensor` fails its consistency test now.
    pub(super) fn inconsistent(&self, sensor: Sensor) -> bool {
        match sensor {
            Sensor::Star => self.aids.star_consistency.failing(),
            Sensor::Gnss => {
                self.aids.gnss_consistency.failing()
                    || self.aids.gnss_velocity_consistency.failing()
            }
        }
    }

    /// The inertial solution is blamed for `sensor`'s rejections: the uncertainty of the
    /// states it observes ([`Sensor::inertial_blocks`]) is widened by the ratio of its
    /// innovations' NIS to the consistent 3 (`f = m / 3`, at least 1), so the filter's σ grows
    /// to the size of the error its innovations show (nav-core `widen_block_uncertainty`,
    /// `P' = S P S`, correlations kept). The NIS is the fading average `m` of the consistency
    /// monitor, or, when the run's innovations grew ([`AidingSensor::run_innovation_grew`]),
    /// the larger of it and the run's last NIS capped at the gate: the error now, which the
    /// average (a time constant of 256 measurements) would show only after many runs, the
    /// error growing all the while. A star run that grew, or that follows the tracker proving
    /// noisier than configured, widens the installation and gyro scale factor too
    /// ([`STAR_FITTED_BLOCKS`]).
    pub(super) fn widen_inertial_uncertainty(&mut self, sensor: Sensor) {
        // The run's last NIS counts up to the gate: beyond it the widening would let the next
        // measurement in whole, the sensor's error with it.
        let gate = self.gate_nis(match sensor {
            Sensor::Star => Aid::Star,
            Sensor::Gnss => Aid::GnssPosition,
        });
        let grown = |aid: &AidingSensor, noise_exceeds: bool| {
            if aid.run_innovation_grew || noise_exceeds {
                aid.last_nis.min(gate)
            } else {
                0.0
            }
        };
        let nis = match sensor {
            Sensor::Star => self
                .aids
                .star_consistency
                .mean_nis()
                .max(grown(&self.aids.star, self.star_noise_exceeds_configured())),
            Sensor::Gnss => self
                .aids
                .gnss_consistency
                .mean_nis()
                .max(self.aids.gnss_velocity_consistency.mean_nis())
                .max(grown(&self.aids.gnss, false))
                .max(grown(&self.aids.gnss_velocity, false)),
        };
        let refit: &[StateBlock] = match sensor {
            Sensor::Star if self.run_innovation_grew(Sensor::Star) => &STAR_FITTED_BLOCKS,
            _ => &[],
        };
        self.widen_inertial_blocks(sensor, nis, refit);
    }

    /// Widens the uncertainty of `sensor`'s inertial blocks ([`Sensor::inertial_blocks`]) and
    /// of `refit` by `f = nis / 3`, at least 1 (`P' = S P S`, correlations kept; nav-core
    /// `widen_block_uncertainty`); a refusal is counted in `filter_errors`.
    pub(super) fn widen_inertial_blocks(&mut self, sensor: Sensor, nis: f64, refit: &[StateBlock]) {
        let factor = (nis / CONSISTENT_MEAN_NIS).max(1.0);
        for block in sensor.inertial_blocks().iter().chain(refit) {
            if self
                .covariance
                .filter
                .widen_block_uncertainty(*block, factor)
                .is_err()
            {
                count(&mut self.health.counters.filter_errors);
            }
        }
    }

    /// Counts a measurement the queue of `sensor` refused.
    pub(super) fn count_refusal(&mut self, refusal: BufferRefusal, sensor: Sensor) {
        let counter = match (refusal, sensor) {
            (BufferRefusal::Stale, _) => &mut self.health.counters.measurement_stale,
            (BufferRefusal::Future, _) => &mut self.health.counters.measurement_future,
            (BufferRefusal::Overflow, _) => &mut self.health.counters.measurement_overflow,
            (BufferRefusal::NonFinite, Sensor::Star) => &mut self.health.counters.star_non_finite,
            (BufferRefusal::NonFinite, Sensor::Gnss) => &mut self.health.counters.gnss_non_finite,
        };
        count(counter);
    }
}

impl Operations {
    /// Whether `sensor` is disabled by command ([`Command::SetAidEnabled`]).
    pub(super) fn disabled(&self, sensor: Sensor) -> bool {
        self.disabled.get(sensor.index()).copied().unwrap_or(false)
    }

    /// Disables (`true`) or enables `sensor`.
    pub(super) fn set_disabled(&mut self, sensor: Sensor, disabled: bool) {
        if let Some(flag) = self.disabled.get_mut(sensor.index()) {
            *flag = disabled;
        }
    }
}
