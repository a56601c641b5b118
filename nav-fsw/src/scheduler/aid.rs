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

    /// One more rejection of `aid`'s sensor; after `timing.rejections_to_declare_faulty` in a
    /// row the sensor is declared faulty (counted once per declaration).
    pub(super) fn note_rejection(&mut self, aid: Aid) {
        let limit = self.config.timing.rejections_to_declare_faulty;
        let (sensor, declarations) = match aid.sensor() {
            Sensor::Star => (
                &mut self.aids.star,
                &mut self.health.counters.star_declared_faulty,
            ),
            Sensor::Gnss => (
                &mut self.aids.gnss,
                &mut self.health.counters.gnss_declared_faulty,
            ),
        };
        sensor.consecutive_rejections = sensor.consecutive_rejections.saturating_add(1);
        if !sensor.faulty && sensor.consecutive_rejections >= limit {
            sensor.faulty = true;
            count(declarations);
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
