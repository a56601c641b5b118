//! Innovation consistency monitor: tells whether an aid's recent innovations agree with the
//! covariance the filter claims for them, so that an error the filter does not model (an IMU
//! misalignment, a g-sensitivity, a bias instability) is seen, and said in telemetry, before
//! it is absorbed silently. It decides nothing about the navigation by itself; the fault logic
//! reads its verdict to tell an inertial error from a sensor fault (`scheduler::aid`).
//!
//! **Test** (Bar-Shalom, Li and Kirubarajan, *Estimation with Applications to Tracking and
//! Navigation*, 2001, §5.4.2, with a fading memory instead of a sliding window). Under a
//! consistent filter the NIS `ε_k = νᵀ S⁻¹ ν` of a 3-dimensional innovation is χ²(3), mean 3,
//! variance 6, and the NIS of different times are independent. The monitor keeps the fading
//! average `m_k = m_{k−1} + (ε_k − m_{k−1}) / N` (`m_0 = 3`, time constant `N` measurements)
//! and fails when `m_k > r`. For independent χ²(3) terms `m` has mean 3 and variance
//! `6 λ / (2 − λ)`, `λ = 1/N`; matching both moments to a scaled χ² (Patnaik's approximation)
//! gives `m ≈ (3/ν) χ²(ν)` with `ν = 3 (2N − 1)`, so `r = 3 χ²⁻¹(1 − α; ν) / ν` bounds the
//! probability that a consistent filter's `m` exceeds `r` at any one measurement by `α`.
//! The default `N` = 256 (25.6 s of a 10 Hz aid) and `α` = 1e-9 give `ν` = 1533 and
//! `r` = 3.70 ([`DEFAULT_MEAN_NIS_BOUND`]; nav-sim's tests check it against statrs). A flight
//! of 30 000 measurements per aid holds about 120 independent averages, so the chance of a
//! false alarm in a consistent flight stays far below one in a thousand; docs/guide/imu-errors.md
//! measures it in Monte Carlo, where the filter's NIS is slightly heavier-tailed than χ².
//!
//! The cost is one division and three additions per tested measurement, no window storage.
//! Every measurement is tested, from the first after a (re)start: `m` starts at 3, so early
//! on it has less variance than in steady state (`6λ² Σ_{j<n} (1 − λ)^{2j}` after `n`
//! measurements), and an NIS enters it at most at the gate it failed. To reach the bound a
//! consistent filter needs `(r − 3) N / (gate − 3)` = 14 gate-sized NIS in a row, which
//! χ²(3) (1.1 % above 11.3) does not give. An aid whose noise is larger than the filter is
//! told (a star tracker's roll) therefore fails within seconds of its first measurement, not
//! after `N`: before a run of gate rejections could have it declared faulty, which the fault
//! logic would otherwise do to a healthy sensor (`scheduler::aid`). A gate-rejected
//! measurement enters with its NIS capped at the gate it failed, so one outlier (a star
//! glitch) moves `m` by at most `gate / N`, while a run of rejections (the inertial solution
//! drifting away) drives `m` to the gate and fails the test. A non-finite NIS is not
//! entered.

/// Default time constant of the fading average (measurements).
pub const DEFAULT_TIME_CONSTANT_MEASUREMENTS: u32 = 256;

/// Largest time constant the configuration accepts (measurements): 1.8 h of a 10 Hz aid.
pub const MAX_TIME_CONSTANT_MEASUREMENTS: u32 = 65_536;

/// Default bound of the fading-average NIS of a 3-dimensional aid: `3 χ²⁻¹(1 − 1e-9; ν) / ν`,
/// `ν = 3 (2 N − 1)` = 1533 for [`DEFAULT_TIME_CONSTANT_MEASUREMENTS`] (module docs).
pub const DEFAULT_MEAN_NIS_BOUND: f64 = 3.70;

/// Mean of the NIS of a consistent 3-dimensional aid (χ²(3)): the fading average's start.
pub const CONSISTENT_MEAN_NIS: f64 = 3.0;

/// Settings of every aid's consistency monitor.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ConsistencyConfig {
    /// Time constant `N` of the fading average (measurements), 1 to
    /// [`MAX_TIME_CONSTANT_MEASUREMENTS`].
    pub time_constant_measurements: u32,
    /// Bound `r` of the fading-average NIS, above [`CONSISTENT_MEAN_NIS`]
    /// (`3 χ²⁻¹(1 − α; ν) / ν`, module docs).
    pub mean_nis_bound: f64,
}

/// The parameter table's defaults ([`crate::config::Param`]).
impl Default for ConsistencyConfig {
    fn default() -> Self {
        crate::config::FswConfig::table_defaults().consistency
    }
}

impl ConsistencyConfig {
    /// Whether the settings are within their ranges in the parameter table: a time constant
    /// in range and a bound above the consistent mean (a bound at or below 3 fails a
    /// consistent filter).
    pub fn is_valid(&self) -> bool {
        use crate::config::Param;
        Param::ConsistencyTimeConstant
            .check(f64::from(self.time_constant_measurements))
            .and(Param::ConsistencyMeanNisBound.check(self.mean_nis_bound))
            .is_ok()
    }
}

/// The fading-average NIS of one aid and its verdict; no allocation, O(1) per measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConsistencyMonitor {
    mean_nis: f64,
    failing: bool,
}

impl Default for ConsistencyMonitor {
    fn default() -> Self {
        Self {
            mean_nis: CONSISTENT_MEAN_NIS,
            failing: false,
        }
    }
}

impl ConsistencyMonitor {
    /// Enters one tested measurement's NIS (`accepted` = it passed the gate `gate_nis`);
    /// true when the aid has just started failing the test (one count per episode). An
    /// episode ends when the average falls back to the bound.
    ///
    /// # Examples
    /// ```
    /// use nav_fsw::consistency::{ConsistencyConfig, ConsistencyMonitor};
    /// let config = ConsistencyConfig::default();
    /// let mut monitor = ConsistencyMonitor::default();
    /// // Innovations twice as large as the filter claims: NIS 12 on average instead of 3.
    /// let began = (0..400).filter(|_| monitor.observe(12.0, true, 16.27, &config)).count();
    /// assert_eq!(began, 1);
    /// assert!(monitor.failing());
    /// ```
    pub fn observe(
        &mut self,
        nis: f64,
        accepted: bool,
        gate_nis: f64,
        config: &ConsistencyConfig,
    ) -> bool {
        if !nis.is_finite() {
            return false;
        }
        let entered = if accepted { nis } else { nis.min(gate_nis) };
        let time_constant = f64::from(config.time_constant_measurements.max(1));
        self.mean_nis += (entered - self.mean_nis) / time_constant;
        let over = self.mean_nis > config.mean_nis_bound;
        let began = over && !self.failing;
        self.failing = over;
        began
    }

    /// Whether the aid fails the test now (its current verdict).
    pub fn failing(&self) -> bool {
        self.failing
    }

    /// The fading-average NIS ([`CONSISTENT_MEAN_NIS`] before the first measurement).
    pub fn mean_nis(&self) -> f64 {
        self.mean_nis
    }

    /// Starts afresh (a re-initialised filter): the average back at 3.
    pub fn clear(&mut self) {
        *self = Self::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_random::normal_source;

    /// A χ²(3) draw scaled by `variance_ratio` (innovations `√ratio` times the claimed σ).
    fn nis_draw(normal: &mut impl FnMut() -> f64, variance_ratio: f64) -> f64 {
        (0..3).map(|_| normal().powi(2)).sum::<f64>() * variance_ratio
    }

    /// The fraction of measurements at which a consistent stream's average exceeds the
    /// bound matches the `α` the bound was made for. With `N` = 16, `ν` = 93 and
    /// `r = 3 χ²⁻¹(0.99; 93) / 93` = 3 × 127.63 / 93 = 4.117 (`α` = 0.01); over 400 000
    /// measurements (25 000 time constants) the fraction is 0.01 within the moment-matching
    /// approximation's accuracy and the Monte Carlo error.
    #[test]
    fn the_false_alarm_fraction_matches_the_bounds_probability() {
        let config = ConsistencyConfig {
            time_constant_measurements: 16,
            mean_nis_bound: 3.0 * 127.63 / 93.0,
        };
        let mut normal = normal_source(0x9e37_79b9_7f4a_7c15);
        let mut monitor = ConsistencyMonitor::default();
        let (measurements, mut failing) = (400_000u32, 0u32);
        for _ in 0..measurements {
            let nis = nis_draw(&mut normal, 1.0);
            monitor.observe(nis, nis < 16.27, 16.27, &config);
            failing += u32::from(monitor.failing());
        }
        let fraction = f64::from(failing) / f64::from(measurements);
        assert!((0.007..0.014).contains(&fraction), "fraction {fraction}");
    }

    /// The default settings on a consistent stream of 300 000 measurements (ten flights of
    /// a 10 Hz aid): no episode. Innovations 1.3 times larger than claimed (average NIS
    /// 5.07) are detected within two time constants.
    #[test]
    fn a_consistent_stream_passes_and_a_larger_one_fails() {
        let config = ConsistencyConfig::default();
        let mut normal = normal_source(0x2545_f491_4f6c_dd1d);
        let mut monitor = ConsistencyMonitor::default();
        let mut episodes = 0;
        for _ in 0..300_000 {
            let nis = nis_draw(&mut normal, 1.0);
            episodes += usize::from(monitor.observe(nis, nis < 16.27, 16.27, &config));
        }
        assert_eq!(episodes, 0);
        assert!(
            (monitor.mean_nis() - 3.0).abs() < 0.5,
            "{}",
            monitor.mean_nis()
        );
        let mut larger = ConsistencyMonitor::default();
        let first = (0..2000).find(|_| {
            let nis = nis_draw(&mut normal, 1.3 * 1.3);
            larger.observe(nis, nis < 16.27, 16.27, &config)
        });
        assert!(first.is_some_and(|k| k < 512), "detected at {first:?}");
    }

    /// One rejected outlier moves the average by at most `gate / N`; a run of rejections
    /// fails the test, from the first measurement on (14 gate-sized NIS after a start, not
    /// 13); a non-finite NIS is ignored; `clear` starts afresh.
    #[test]
    fn one_outlier_is_tolerated_and_a_run_of_rejections_is_not() {
        let config = ConsistencyConfig::default();
        let mut monitor = ConsistencyMonitor::default();
        // Rejections from the start: capped at the gate, they fail the test at the 14th.
        for _ in 0..13 {
            assert!(!monitor.observe(1e6, false, 16.27, &config));
        }
        assert!(!monitor.failing());
        assert!(monitor.observe(1e6, false, 16.27, &config));
        assert!(monitor.failing());
        monitor.clear();
        for _ in 0..300 {
            assert!(!monitor.observe(3.0, true, 16.27, &config));
        }
        assert!(!monitor.observe(1e6, false, 16.27, &config));
        assert!((monitor.mean_nis() - (3.0 + (16.27 - 3.0) / 256.0)).abs() < 1e-12);
        assert!(!monitor.failing());
        assert!(!monitor.observe(f64::NAN, true, 16.27, &config));
        let began = (0..100)
            .filter(|_| monitor.observe(1e3, false, 16.27, &config))
            .count();
        assert_eq!(began, 1);
        assert!(monitor.failing());
        monitor.clear();
        assert!(!monitor.failing());
        assert_eq!(monitor.mean_nis().to_bits(), 3.0f64.to_bits());
    }

    /// The configuration's checks: the default is valid; a zero or too long time constant,
    /// a bound at the consistent mean, and a non-finite bound are not.
    #[test]
    fn invalid_settings_are_refused() {
        let valid = ConsistencyConfig::default();
        assert!(valid.is_valid());
        for invalid in [
            ConsistencyConfig {
                time_constant_measurements: 0,
                ..valid
            },
            ConsistencyConfig {
                time_constant_measurements: MAX_TIME_CONSTANT_MEASUREMENTS + 1,
                ..valid
            },
            ConsistencyConfig {
                mean_nis_bound: 3.0,
                ..valid
            },
            ConsistencyConfig {
                mean_nis_bound: f64::INFINITY,
                ..valid
            },
            ConsistencyConfig {
                mean_nis_bound: f64::NAN,
                ..valid
            },
        ] {
            assert!(!invalid.is_valid(), "{invalid:?}");
        }
    }
}
