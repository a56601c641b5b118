//! Innovation bias monitor: tells whether an aid's innovations have kept a mean that the
//! filter does not predict, the signature of a slowly varying sensor error the filter models
//! as constant (a star tracker's thermo-elastic error absorbed into its installation state).
//! The NIS test of [`crate::consistency`] cannot see it: a bias of a fraction of the noise
//! raises the average NIS by that fraction squared, while the mean of many innovations shows
//! it at many times its own 1σ.
//!
//! **Test.** Under a consistent filter the innovations `ν_k` are white, zero-mean, with
//! covariance `S_k` (the innovation property: Bar-Shalom, Li and Kirubarajan, *Estimation
//! with Applications to Tracking and Navigation*, 2001, §5.2.5). Each component is normalised
//! by its own claimed 1σ, `u_{k,i} = ν_{k,i} / √S_{k,ii}`, N(0, 1) whatever the correlation
//! between axes and however `S` changes over the flight (converging, rotating, after an
//! outage). The monitor keeps the fading mean `m_k = m_{k−1} + λ (u_k − m_{k−1})`,
//! `λ = 1/N` (time constant `N` measurements, `m_0 = 0`); for white `u`,
//! `m = λ Σ_j (1 − λ)^j u_{k−j}` has variance `λ² Σ_j (1 − λ)^{2j} = λ / (2 − λ)` per
//! component. The monitor fails when some `|m_i| > k √(λ/(2−λ))`, tested squared. With
//! `N` = 1,000 (100 s of a 10 Hz aid) a flight of 3,000 s holds about 30 independent means
//! per axis; with `k` = 6 each fails with probability 2e-9, so a consistent flight raises a
//! false alarm about once in ten million flights (measured in Monte Carlo in
//! docs/sensor-errors.md). A bias of `b` is seen when `b > k σ_ν / √(2N)`: 0.34″ on the
//! 2.5″ (half-angle) innovations of a 5″ tracker axis.
//!
//! Only accepted measurements enter (a gate-rejected one is an outlier the gate handled);
//! the first `N` after a (re)start are not tested, while `m` still carries its start value.
//! The cost is three square roots and divisions, and a few multiplications per measurement.

/// Default time constant of the fading mean (measurements): 100 s of a 10 Hz aid, long
/// beside the filter's settling of a bias (a few seconds) and short beside a
/// thermo-elastic error's correlation time (a quarter orbit, about 1,400 s).
pub const DEFAULT_TIME_CONSTANT_MEASUREMENTS: f64 = 1000.0;

/// Default bound on `|z_i|` (standard deviations of the fading mean): 6σ (module docs).
pub const DEFAULT_BOUND_SIGMA: f64 = 6.0;

/// Settings of an innovation bias monitor.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct InnovationBiasConfig {
    /// Time constant `N` of the fading mean (measurements), ≥ 1; also the measurements
    /// after a (re)start that are not tested.
    pub time_constant_measurements: f64,
    /// Bound `k` on each component of the normalised mean (standard deviations), > 0.
    pub bound_sigma: f64,
}

impl Default for InnovationBiasConfig {
    fn default() -> Self {
        Self {
            time_constant_measurements: DEFAULT_TIME_CONSTANT_MEASUREMENTS,
            bound_sigma: DEFAULT_BOUND_SIGMA,
        }
    }
}

impl InnovationBiasConfig {
    /// Whether the settings are usable: a finite time constant of at least one measurement
    /// and a finite positive bound.
    pub fn is_valid(&self) -> bool {
        self.time_constant_measurements.is_finite()
            && self.time_constant_measurements >= 1.0
            && self.bound_sigma.is_finite()
            && self.bound_sigma > 0.0
    }
}

/// The fading mean of one aid's innovations and its verdict; O(1), no allocation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct InnovationBiasMonitor {
    mean: [f64; 3],
    entered: f64,
    failing: bool,
}

impl InnovationBiasMonitor {
    /// Enters one accepted measurement's innovation `ν` with the diagonal of its covariance
    /// `S`; true when the aid has just started failing the test (one count per episode,
    /// which ends when every component is back within the bound). A non-finite value or a
    /// non-positive variance is not entered (false).
    ///
    /// # Examples
    /// ```
    /// use nav_fsw::innovation_bias::{InnovationBiasConfig, InnovationBiasMonitor};
    /// let config = InnovationBiasConfig::default();
    /// let mut monitor = InnovationBiasMonitor::default();
    /// // Innovations of 1σ = 1 with a steady mean of 0.3 on the first axis.
    /// let began = (0..3000)
    ///     .map(|k| if k % 2 == 0 { 1.3 } else { -0.7 })
    ///     .filter(|nu| monitor.observe(&[*nu, 0.0, 0.0], &[1.0; 3], &config))
    ///     .count();
    /// assert_eq!(began, 1);
    /// assert!(monitor.failing());
    /// ```
    pub fn observe(
        &mut self,
        innovation: &[f64; 3],
        variances: &[f64; 3],
        config: &InnovationBiasConfig,
    ) -> bool {
        let usable = innovation.iter().all(|nu| nu.is_finite())
            && variances.iter().all(|s| s.is_finite() && *s > 0.0);
        if !usable {
            return false;
        }
        let time_constant = config.time_constant_measurements.max(1.0);
        let lambda = 1.0 / time_constant;
        for ((mean, nu), variance) in self.mean.iter_mut().zip(innovation).zip(variances) {
            let normalised = nu / nav_core::float::sqrt(*variance);
            *mean += (normalised - *mean) * lambda;
        }
        self.entered += 1.0;
        // Var(m_i) = λ / (2 − λ) (module docs).
        let bound = config.bound_sigma * config.bound_sigma * lambda / (2.0 - lambda);
        let tested = self.entered >= time_constant;
        let over = tested && self.mean.iter().any(|mean| mean * mean > bound);
        let began = over && !self.failing;
        self.failing = over;
        began
    }

    /// Whether the aid fails the test now.
    pub fn failing(&self) -> bool {
        self.failing
    }

    /// The fading mean of the normalised innovations `ν_i / √S_ii` (zero before the first
    /// measurement).
    pub fn mean(&self) -> [f64; 3] {
        self.mean
    }

    /// Starts afresh (a re-initialised filter): the next `N` measurements are not tested.
    pub fn clear(&mut self) {
        *self = Self::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic pseudo-random N(0, 1) source (xorshift + Box–Muller).
    fn normal_source(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        move || {
            let mut uniform = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64 + 1e-18
            };
            let (u, v) = (uniform(), uniform());
            nav_core::float::sqrt(-2.0 * libm::log(u)) * libm::cos(2.0 * core::f64::consts::PI * v)
        }
    }

    /// The normalised fading mean has unit variance on white innovations (the λ/(2 − λ)
    /// factor): with `k` = 2 and `N` = 50 the fraction of failing measurements is the
    /// two-sided N(0, 1) tail at 2 on any of three independent axes,
    /// `1 − (1 − 0.0455)³` = 0.130, within the Monte Carlo error of 600 000 draws.
    #[test]
    fn the_failing_fraction_matches_the_normal_tail() {
        let config = InnovationBiasConfig {
            time_constant_measurements: 50.0,
            bound_sigma: 2.0,
        };
        let mut normal = normal_source(0x9e37_79b9_7f4a_7c15);
        let mut monitor = InnovationBiasMonitor::default();
        let variances = [4.0, 1.0, 0.25];
        let (measurements, mut failing) = (600_000u32, 0u32);
        for _ in 0..measurements {
            let nu = [2.0 * normal(), normal(), 0.5 * normal()];
            monitor.observe(&nu, &variances, &config);
            failing += u32::from(monitor.failing());
        }
        let fraction = f64::from(failing) / f64::from(measurements);
        assert!((0.115..0.145).contains(&fraction), "fraction {fraction}");
    }

    /// The default settings: 300 000 white innovations (ten flights of a 10 Hz aid) start
    /// no episode; a steady bias of 0.3σ on one axis is caught within two time constants;
    /// a non-finite innovation or a zero variance is not entered.
    #[test]
    fn white_innovations_pass_and_a_biased_axis_fails() {
        let config = InnovationBiasConfig::default();
        let mut normal = normal_source(0x2545_f491_4f6c_dd1d);
        let mut monitor = InnovationBiasMonitor::default();
        let episodes = (0..300_000)
            .filter(|_| monitor.observe(&[normal(), normal(), normal()], &[1.0; 3], &config))
            .count();
        assert_eq!(episodes, 0);
        let mut biased = InnovationBiasMonitor::default();
        let first = (0..2000)
            .find(|_| biased.observe(&[normal(), 0.3 + normal(), normal()], &[1.0; 3], &config));
        assert!(first.is_some_and(|k| k < 2000), "first failure {first:?}");
        let before = biased;
        assert!(!biased.observe(&[f64::NAN, 0.0, 0.0], &[1.0; 3], &config));
        assert!(!biased.observe(&[0.0; 3], &[1.0, 0.0, 1.0], &config));
        assert_eq!(biased, before);
        biased.clear();
        assert!(!biased.failing());
    }

    #[test]
    fn settings_are_checked() {
        assert!(InnovationBiasConfig::default().is_valid());
        for (time_constant_measurements, bound_sigma) in [
            (0.5, 6.0),
            (f64::NAN, 6.0),
            (1000.0, 0.0),
            (1000.0, f64::INFINITY),
        ] {
            let config = InnovationBiasConfig {
                time_constant_measurements,
                bound_sigma,
            };
            assert!(!config.is_valid());
        }
    }
}
