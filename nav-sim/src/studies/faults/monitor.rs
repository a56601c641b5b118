//! What a row observes and asserts about the reaction: the health counters and their expected
//! increase, the end-of-flight criterion, the per-frame checks of the filter during the
//! flight, and the verdict on a flown row.

use nalgebra::Vector3;
use nav_fsw::health::HealthCounters;
use nav_fsw::scheduler::NavigationComputer;

use super::{FaultClass, RowOutcome, CALIBRATION_SIGMA_BOUND};
use crate::harness::flight::FlightResult;

/// A health counter (or a sum of counters) by name.
#[derive(Clone, Copy)]
pub struct Counter {
    /// Name as in [`HealthCounters`] (`a + b` for a sum).
    pub name: &'static str,
    /// Its value.
    pub read: fn(&HealthCounters) -> u32,
}

macro_rules! counter {
    ($field:ident) => {
        Counter {
            name: stringify!($field),
            read: |h| h.$field,
        }
    };
    ($a:ident + $b:ident) => {
        Counter {
            name: concat!(stringify!($a), " + ", stringify!($b)),
            read: |h| h.$a.saturating_add(h.$b),
        }
    };
}
pub(super) use counter;

/// How a counter must have increased over the count window.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Expected {
    /// By exactly this much.
    Exactly(u32),
    /// By at least this much.
    AtLeast(u32),
}

impl Expected {
    pub(super) fn met(self, observed: u32) -> bool {
        match self {
            Expected::Exactly(n) => observed == n,
            Expected::AtLeast(n) => observed >= n,
        }
    }

    pub(super) fn text(self) -> String {
        match self {
            Expected::Exactly(n) => format!("{n}"),
            Expected::AtLeast(n) => format!("≥ {n}"),
        }
    }
}

/// The end-of-flight criterion of a row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Criterion {
    /// Every calibration state within [`CALIBRATION_SIGMA_BOUND`] σ of its truth.
    CalibrationWithinBound,
    /// For a departure from the filter's model that the flight software can only report:
    /// the counters and the common criteria are checked, the calibration is printed but not
    /// required within bound.
    CountedOnly,
    /// For a fault no check can see (a slow GNSS ramp, followed as truth): the calibration
    /// within bound as above, and the final position error (norm) within 1.5 × `ramp_m` (the
    /// ramp's final offset): the solution follows the ramp with the filter's lag and
    /// overshoot, but the fault is not amplified.
    CalibrationAndPositionWithinRamp {
        /// The offset the ramp reached (m).
        ramp_m: f64,
    },
}

/// The observations of one row's flight: the health counters at the count window's ends, the
/// failed per-frame checks and the number of frames `P` was checked positive definite on.
#[derive(Default)]
pub(super) struct Monitor {
    before: Option<HealthCounters>,
    after: Option<HealthCounters>,
    pub(super) failures: Vec<String>,
    pub(super) definiteness_checks: u64,
}

impl Monitor {
    pub(super) fn fail(&mut self, failure: String) {
        // The first few are enough to diagnose; a fault that persists would repeat them.
        if self.failures.len() < 4 {
            self.failures.push(failure);
        }
    }

    pub(super) fn observe(
        &mut self,
        relative: i64,
        (window_end, dense_end, check_interval): (i64, i64, i64),
        computer: &NavigationComputer,
    ) {
        if relative == -1 {
            self.before = Some(*computer.health());
        }
        if relative == window_end {
            self.after = Some(*computer.health());
        }
        if relative < 0 {
            return;
        }
        let filter = computer.filter();
        let navigation = computer.navigation();
        let calibration = computer.calibration_estimate();
        let finite = filter.state().iter().all(|v| v.is_finite())
            && filter.covariance().iter().all(|v| v.is_finite())
            && navigation.attitude.coords.iter().all(|v| v.is_finite())
            && navigation.position_m.iter().all(|v| v.is_finite())
            && navigation.velocity_mps.iter().all(|v| v.is_finite())
            && navigation.time_s.is_finite()
            && [
                calibration.gyro_bias_rad_s.as_slice(),
                &calibration.accel_bias_mps2,
                &calibration.star_installation_wxyz,
                &calibration.gyro_scale_factor,
                &calibration.accel_scale_factor,
            ]
            .iter()
            .all(|block| block.iter().all(|v| v.is_finite()));
        if !finite {
            self.fail(format!(
                "non-finite state or covariance at frame {relative}"
            ));
            return;
        }
        if relative <= dense_end || relative % check_interval == 0 {
            self.definiteness_checks += 1;
            let p = filter.covariance();
            let scale = p.amax();
            let asymmetry = (p - p.transpose()).amax();
            if asymmetry > 1e-12 * scale {
                self.fail(format!(
                    "P asymmetric at frame {relative}: {:.1e} of its largest entry",
                    asymmetry / scale
                ));
            }
            if p.cholesky().is_none() {
                self.fail(format!("P not positive definite at frame {relative}"));
            }
        }
    }

    /// The verdict on a flown row: the counters' increase over the count window, the filter
    /// resets and sensor declarations, and the end-of-flight criterion, added to `failures`
    /// (those of the flight).
    pub(super) fn verdict(
        self,
        class: &FaultClass,
        result: &FlightResult,
        mut failures: Vec<String>,
    ) -> RowOutcome {
        let (before, after) = match (self.before, self.after) {
            (Some(before), Some(after)) => (before, after),
            _ => {
                failures.push("the flight ended before the count window closed".to_string());
                (HealthCounters::default(), result.health)
            }
        };
        let mut observed = Vec::new();
        for (counter, expected) in &class.counts {
            let increase = (counter.read)(&after).saturating_sub((counter.read)(&before));
            observed.push(increase);
            if !expected.met(increase) {
                failures.push(format!(
                    "{}: counted {increase}, expected {}",
                    counter.name,
                    expected.text()
                ));
            }
        }
        let health = result.health;
        if health.filter_resets != 0 {
            failures.push(format!("{} filter resets", health.filter_resets));
        }
        let declared = [health.star_declared_faulty, health.gnss_declared_faulty];
        if declared != class.declared_faulty {
            failures.push(format!(
                "declared faulty (star, GNSS) {declared:?}, expected {:?}",
                class.declared_faulty
            ));
        }
        let worst = (0..result.calibration_error.len())
            .map(|i| {
                result.calibration_error[i].abs() / result.calibration_covariance[(i, i)].sqrt()
            })
            // NaN-propagating maximum: a NaN ratio fails the row.
            .fold(0.0_f64, |worst, ratio| {
                if ratio.is_nan() || worst.is_nan() {
                    f64::NAN
                } else {
                    worst.max(ratio)
                }
            });
        let calibration_required = class.criterion != Criterion::CountedOnly;
        if calibration_required && (worst.is_nan() || worst > CALIBRATION_SIGMA_BOUND) {
            failures.push(format!(
                "calibration: worst state {worst:.2}σ from its truth"
            ));
        }
        let last = result.last().copied();
        let position_error_m = last.map_or([f64::NAN; 3], |s| s.position_error_m);
        if let (Criterion::CalibrationAndPositionWithinRamp { ramp_m }, Some(last)) =
            (class.criterion, last)
        {
            let error_m = Vector3::from(last.position_error_m).norm();
            if error_m.is_nan() || error_m > 1.5 * ramp_m {
                failures.push(format!(
                    "position error {error_m:.1} m beyond 1.5 × the {ramp_m} m ramp"
                ));
            }
        }
        RowOutcome {
            name: class.name,
            observed,
            worst_calibration_sigma: worst,
            calibration_nees: result.calibration_nees(),
            position_error_m,
            health,
            definiteness_checks: self.definiteness_checks,
            failures,
        }
    }
}
