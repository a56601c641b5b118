//! Health telemetry counters: every detected fault and every protective action is counted
//! here (saturating, so a counter never wraps back to a healthy-looking value).

/// Fault and action counters, reported in the health telemetry.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HealthCounters {
    /// IMU samples with NaN/Inf fields.
    pub imu_non_finite: u32,
    /// IMU samples beyond the saturation limits.
    pub imu_saturated: u32,
    /// Repeated IMU samples (same sequence number) and late, out-of-order ones.
    pub imu_duplicate: u32,
    /// IMU samples missing (sequence gaps and frames with no sample).
    pub imu_missing: u32,
    /// IMU time-tag jumps (zero, negative or wrong step).
    pub imu_time_jump: u32,
    /// Star measurements rejected as non-finite.
    pub star_non_finite: u32,
    /// Star quaternions rejected as not unit (zero included).
    pub star_not_unit: u32,
    /// Sign changes of the star quaternion between consecutive samples (q and −q are one
    /// attitude: undone, and harmless; a sensor that keeps w ≥ 0 changes sign twice per turn).
    pub star_sign_flip: u32,
    /// GNSS fixes rejected as non-finite.
    pub gnss_non_finite: u32,
    /// GNSS fixes rejected as jumps.
    pub gnss_jump: u32,
    /// Measurements older than the allowed latency, or older than the last fused one.
    pub measurement_stale: u32,
    /// Measurements time-tagged in the future.
    pub measurement_future: u32,
    /// Measurements dropped because their buffer was full.
    pub measurement_overflow: u32,
    /// Star updates rejected by the innovation gate.
    pub star_gate_rejections: u32,
    /// GNSS updates rejected by the innovation gate.
    pub gnss_gate_rejections: u32,
    /// GNSS velocity updates rejected by the innovation gate.
    pub gnss_velocity_gate_rejections: u32,
    /// Frames whose IMU sample was held (missing or refused), each adding the held sample's
    /// uncertainty to the covariance.
    pub imu_held_frames: u32,
    /// Covariance repairs (variance clamped to its floor or ceiling).
    pub covariance_clamps: u32,
    /// Filter resets after a non-finite state or covariance.
    pub filter_resets: u32,
    /// Frames whose work exceeded the frame budget.
    pub frame_overruns: u32,
    /// Times the star sensor was declared faulty (consecutive rejections).
    pub star_declared_faulty: u32,
    /// Times the GNSS receiver was declared faulty (consecutive rejections).
    pub gnss_declared_faulty: u32,
    /// Measurements discarded because their sensor is declared faulty.
    pub ignored_from_faulty_sensor: u32,
    /// Star-sensor outages: no measurement received for longer than
    /// `timing.outage_timeout_s` (counted once per outage, when the timeout elapses).
    pub star_outages: u32,
    /// GNSS outages, as [`HealthCounters::star_outages`].
    pub gnss_outages: u32,
    /// Filter operations refused by nav-core (measurement model or update errors).
    pub filter_errors: u32,
    /// Strapdown steps refused (the navigation state was held).
    pub strapdown_failures: u32,
    /// Episodes of serially correlated GNSS position innovations ([`WhitenessMonitor`]): the
    /// receiver's errors are correlated beyond what the filter models, so its covariance is
    /// no longer to be trusted.
    pub gnss_innovations_correlated: u32,
    /// Episodes of star innovations inconsistent with their covariance
    /// ([`crate::consistency::ConsistencyMonitor`]): counted when the aid starts failing
    /// the test.
    pub star_inconsistent: u32,
    /// Episodes of inconsistent GNSS position innovations, as
    /// [`HealthCounters::star_inconsistent`].
    pub gnss_inconsistent: u32,
    /// Episodes of inconsistent GNSS velocity innovations, as
    /// [`HealthCounters::star_inconsistent`].
    pub gnss_velocity_inconsistent: u32,
    /// Runs of `timing.rejections_to_declare_faulty` gate rejections blamed on the inertial
    /// solution, not on the aiding sensor: its innovations were already inconsistent when
    /// the run began, or the other sensor's are now. The sensor is kept, and the uncertainty
    /// of the states it observes is widened (`scheduler::aid`).
    pub inertial_suspect: u32,
    /// Episodes of a gravity model too coarse for its allowance: the RMS magnitude of the
    /// field it omits, at the vehicle's radius, above `√3 gravity.omitted_field_sigma_mps2`
    /// (`scheduler::gravity`). The filter's covariance does not cover that field. Not counted
    /// without an allowance, a configuration warning instead ([`ConfigurationWarnings`]).
    pub gravity_allowance_short: u32,
    /// Evaluations of the field beyond `J2` refused (non-finite position or result); the
    /// last value is held.
    pub gravity_field_errors: u32,
    /// Times the star noise began to follow the innovations (`star.noise_matching`,
    /// [`crate::noise_matching`]): the star innovations failed the consistency test, and the
    /// update weights the tracker by the noise they show until the filter is re-initialised.
    pub star_noise_matched: u32,
    /// Pairs of the two tracker heads' measurements rejected by the pair gate
    /// (`star.second_head.pair_gate_nis`; `scheduler::heads`).
    pub star_pair_rejections: u32,
    /// Times the pairs' residuals began to fail the consistency test: the heads' relative
    /// alignment moves (a slowly varying error, an uncorrected aberration) or their noise is
    /// larger than configured.
    pub star_heads_inconsistent: u32,
    /// Times the filter's installation block was handed over to the other tracker head.
    pub star_head_handovers: u32,
    /// Star measurements of a head the configuration does not have (ignored).
    pub star_unknown_head: u32,
    /// Times the star innovations began to follow the velocity aberration: left in by the
    /// tracker while the flight software is not told to correct it, or corrected twice or
    /// with the wrong sign while it is (nav-fsw `aberration_monitor`).
    pub star_aberration_suspected: u32,
}

/// Number of counters in [`HealthCounters`].
pub const HEALTH_COUNTER_COUNT: usize = 40;

/// Number of consistency flags ([`HealthCounters::CONSISTENCY_FLAGS`]).
pub const CONSISTENCY_FLAG_COUNT: usize = 11;

impl HealthCounters {
    /// The consistency flags: the counters that tell the operator a sensor or a model is
    /// suspected (not an input fault the checks refused, nor a protective action on every
    /// flight). Each has a false-alarm rate per clean flight measured in Monte Carlo
    /// (`nav-sim false-alarms`, docs/results/false-alarms-*.md).
    pub const CONSISTENCY_FLAGS: [&'static str; CONSISTENCY_FLAG_COUNT] = [
        "gnss_innovations_correlated",
        "star_inconsistent",
        "gnss_inconsistent",
        "gnss_velocity_inconsistent",
        "inertial_suspect",
        "gravity_allowance_short",
        "star_noise_matched",
        "star_heads_inconsistent",
        "star_aberration_suspected",
        "star_declared_faulty",
        "gnss_declared_faulty",
    ];

    /// Every counter with its name (the field's), in declaration order: for reports and
    /// ground tools.
    ///
    /// # Examples
    /// ```
    /// use nav_fsw::health::HealthCounters;
    /// let mut health = HealthCounters::default();
    /// health.imu_missing = 3;
    /// assert!(health.named().contains(&("imu_missing", 3)));
    /// ```
    pub const fn named(&self) -> [(&'static str, u32); HEALTH_COUNTER_COUNT] {
        [
            ("imu_non_finite", self.imu_non_finite),
            ("imu_saturated", self.imu_saturated),
            ("imu_duplicate", self.imu_duplicate),
            ("imu_missing", self.imu_missing),
            ("imu_time_jump", self.imu_time_jump),
            ("star_non_finite", self.star_non_finite),
            ("star_not_unit", self.star_not_unit),
            ("star_sign_flip", self.star_sign_flip),
            ("gnss_non_finite", self.gnss_non_finite),
            ("gnss_jump", self.gnss_jump),
            ("measurement_stale", self.measurement_stale),
            ("measurement_future", self.measurement_future),
            ("measurement_overflow", self.measurement_overflow),
            ("star_gate_rejections", self.star_gate_rejections),
            ("gnss_gate_rejections", self.gnss_gate_rejections),
            (
                "gnss_velocity_gate_rejections",
                self.gnss_velocity_gate_rejections,
            ),
            ("imu_held_frames", self.imu_held_frames),
            ("covariance_clamps", self.covariance_clamps),
            ("filter_resets", self.filter_resets),
            ("frame_overruns", self.frame_overruns),
            ("star_declared_faulty", self.star_declared_faulty),
            ("gnss_declared_faulty", self.gnss_declared_faulty),
            (
                "ignored_from_faulty_sensor",
                self.ignored_from_faulty_sensor,
            ),
            ("star_outages", self.star_outages),
            ("gnss_outages", self.gnss_outages),
            ("filter_errors", self.filter_errors),
            ("strapdown_failures", self.strapdown_failures),
            (
                "gnss_innovations_correlated",
                self.gnss_innovations_correlated,
            ),
            ("star_inconsistent", self.star_inconsistent),
            ("gnss_inconsistent", self.gnss_inconsistent),
            (
                "gnss_velocity_inconsistent",
                self.gnss_velocity_inconsistent,
            ),
            ("inertial_suspect", self.inertial_suspect),
            ("gravity_allowance_short", self.gravity_allowance_short),
            ("gravity_field_errors", self.gravity_field_errors),
            ("star_noise_matched", self.star_noise_matched),
            ("star_pair_rejections", self.star_pair_rejections),
            ("star_heads_inconsistent", self.star_heads_inconsistent),
            ("star_head_handovers", self.star_head_handovers),
            ("star_unknown_head", self.star_unknown_head),
            ("star_aberration_suspected", self.star_aberration_suspected),
        ]
    }
}

/// What the configuration itself says the flight will lack: reported once at start-up
/// ([`crate::scheduler::NavigationComputer::configuration_warnings`]), never counted as a flight
/// event, so the counters an operator watches move only for what the flight shows.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct ConfigurationWarnings {
    /// The gravity model has no allowance for the field it omits
    /// (`gravity.omitted_field_sigma_mps2` = 0, as the paper's configuration): the
    /// covariance never covers that field, by design, so `gravity_allowance_short`, which
    /// would restate it at every evaluation, is not counted.
    pub gravity_without_allowance: bool,
}

impl ConfigurationWarnings {
    /// The warnings of `config`.
    pub fn of(config: &crate::config::FswConfig) -> Self {
        let sigma = config.gravity.omitted_field_sigma_mps2;
        Self {
            gravity_without_allowance: sigma.is_nan() || sigma <= 0.0,
        }
    }

    /// One bit per warning (bit 0: [`Self::gravity_without_allowance`]), for telemetry.
    pub const fn bits(&self) -> u32 {
        if self.gravity_without_allowance {
            1
        } else {
            0
        }
    }
}

/// Adds one to a counter without wrapping.
#[inline]
pub fn count(counter: &mut u32) {
    *counter = counter.saturating_add(1);
}

/// Detects an aiding-sensor outage: the sensor silent for longer than a timeout. Reports each
/// outage once, when the timeout elapses; a message ends it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct OutageMonitor {
    last_heard_s: Option<f64>,
    in_outage: bool,
}

impl OutageMonitor {
    /// Called once a frame with the navigation time and whether the sensor delivered anything
    /// (valid or not) in the frame; true when a new outage has just begun. The first call
    /// starts the clock (a sensor that never speaks is an outage too).
    pub fn observe(&mut self, now_s: f64, heard: bool, timeout_s: f64) -> bool {
        let last = *self.last_heard_s.get_or_insert(now_s);
        if heard {
            self.last_heard_s = Some(now_s);
            self.in_outage = false;
            return false;
        }
        let began = !self.in_outage && now_s - last > timeout_s;
        self.in_outage |= began;
        began
    }
}

/// Serial correlation of a measurement's innovations, the filter's own consistency check
/// when no truth is at hand: an optimal filter's innovations are white, so consecutive
/// whitened innovations `u_k = L_k⁻¹ ν_k` (`S_k = L_k L_kᵀ`, Cholesky: `u_k ~ N(0, I)`) are
/// uncorrelated. The monitor keeps an exponentially weighted mean `c` of
/// `x_k = (u_k · u_{k−1}) / 3` over about `W` = `window` measurements:
/// `c ← c + (x_k − c) / W`. An episode begins when `c` rises above `threshold` and ends when it
/// falls below half of it.
///
/// **Threshold** (Bar-Shalom, Li and Kirubarajan 2001, §5.4.2, the whiteness test of the
/// innovations, with a fading memory). Under whiteness `x_k` is a martingale difference of
/// variance 1/3 (`E[(u · u')²] = 3` for independent `u, u' ~ N(0, I₃)`), so with `λ = 1/W`
/// `c` has mean 0 and variance `(1/3) λ / (2 − λ) = 1 / (3 (2W − 1))`: 1σ = 0.0512 for
/// `W` = 64. A flight tests `c` at every fix: the upper stage's 1.9 h at 10 Hz, `n` = 68 400
/// fixes, the longest shipped. For a false-alarm rate per flight below `α_f` the union bound
/// over the fixes asks `P(c > r) ≤ α_f / n` at each; with `α_f` = 1e-3 (a tenth of the 1 %
/// an operator can act on, the rest for what the Gaussian approximation leaves out: `c` is a
/// sum of some `2W − 1` products of normals, whose tail is heavier than the normal's) that is
/// 1.5e-8, 5.5σ. The default
/// `r` = 0.30 is 5.86σ: 2.3e-9 per fix, 1.6e-4 per flight before the tail's excess.
/// Errors correlated beyond the model's keep `c` near their lag-one correlation (0.4–0.6 for
/// 8 m of a 10 m receiver error with τ = 300 s), above `r`. Measured false alarms:
/// `nav-sim false-alarms` (docs/results/false-alarms-*.md).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WhitenessMonitor {
    previous: Option<[f64; 3]>,
    correlation: f64,
    in_episode: bool,
}

impl WhitenessMonitor {
    /// Takes one innovation `ν` with its covariance `S`; true when a new episode of correlated
    /// innovations has just begun. A non-finite innovation or an `S` that is not positive
    /// definite restarts the pairing.
    pub fn observe(
        &mut self,
        innovation: &nalgebra::Vector3<f64>,
        covariance: &nalgebra::Matrix3<f64>,
        window: f64,
        threshold: f64,
    ) -> bool {
        let whitened = covariance
            .cholesky()
            .and_then(|factor| factor.l().solve_lower_triangular(innovation));
        let Some(whitened) = whitened.filter(|u| u.iter().all(|v| v.is_finite())) else {
            self.previous = None;
            return false;
        };
        let normalised = [whitened.x, whitened.y, whitened.z];
        let Some(previous) = self.previous.replace(normalised) else {
            return false;
        };
        let [a0, a1, a2] = normalised;
        let [b0, b1, b2] = previous;
        let product = (a0 * b0 + a1 * b1 + a2 * b2) / 3.0;
        self.correlation += (product - self.correlation) / window;
        let began = !self.in_episode && self.correlation > threshold;
        if began {
            self.in_episode = true;
        } else if self.correlation < 0.5 * threshold {
            self.in_episode = false;
        }
        began
    }

    /// The current weighted lag-one correlation `c`.
    pub fn correlation(&self) -> f64 {
        self.correlation
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Vector3};

    /// White innovations (of an anisotropic, correlated `S`) keep the monitor quiet; a first-order Gauss–Markov sequence with a
    /// lag-one correlation of 0.9 starts one episode; a non-finite variance restarts the
    /// pairing without counting.
    #[test]
    fn correlated_innovations_start_one_episode_and_white_ones_none() {
        // A deterministic pseudo-random N(0, 1) source (xorshift + Box–Muller).
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 + 1e-18
        };
        let mut normal = move || {
            let (u, v) = (uniform(), uniform());
            nav_core::float::sqrt(-2.0 * libm::log(u)) * libm::cos(2.0 * core::f64::consts::PI * v)
        };
        let mut white = WhitenessMonitor::default();
        let mut episodes = 0;
        let mut largest = 0.0f64;
        // An anisotropic, correlated S: whitened by its Cholesky factor.
        let covariance = Matrix3::new(4.0, 1.0, 0.0, 1.0, 2.0, 0.5, 0.0, 0.5, 1.0);
        let factor = covariance.cholesky().map(|c| c.l()).unwrap_or_default();
        for _ in 0..5000 {
            let nu = factor * Vector3::new(normal(), normal(), normal());
            episodes += usize::from(white.observe(&nu, &covariance, 64.0, 0.30));
            largest = largest.max(white.correlation());
        }
        assert_eq!(episodes, 0, "largest c {largest}");
        let mut correlated = WhitenessMonitor::default();
        let mut error = [0.0; 3];
        let mut episodes = 0;
        for _ in 0..2000 {
            for e in error.iter_mut() {
                *e = 0.9 * *e + nav_core::float::sqrt(1.0 - 0.81) * normal();
            }
            let nu = Vector3::from(error);
            episodes += usize::from(correlated.observe(&nu, &Matrix3::identity(), 64.0, 0.30));
        }
        assert_eq!(episodes, 1);
        assert!(
            correlated.correlation() > 0.7,
            "{}",
            correlated.correlation()
        );
        let bad = Matrix3::from_diagonal(&Vector3::new(f64::NAN, 1.0, 1.0));
        assert!(!correlated.observe(&Vector3::repeat(1.0), &bad, 64.0, 0.30));
        assert!(correlated.previous.is_none());
        assert!(!correlated.observe(&Vector3::repeat(1.0), &Matrix3::zeros(), 64.0, 0.30));
    }

    /// The paper's configuration has no gravity allowance: a warning (bit 0), and a
    /// configuration with one has none.
    #[test]
    fn a_configuration_without_a_gravity_allowance_warns() {
        use crate::config::FswConfig;
        use crate::sensor_frames::SensorFrames;
        let site = nav_core::frames::LaunchSite {
            latitude_rad: 0.715,
            longitude_rad: 1.750,
            height_m: 1000.0,
            azimuth_rad: 3.316,
            earth_axis_ecef: [0.0, 0.0, 1.0],
        };
        let mut config = FswConfig::paper_defaults(site, SensorFrames::ALIGNED);
        let warnings = ConfigurationWarnings::of(&config);
        assert!(warnings.gravity_without_allowance);
        assert_eq!(warnings.bits(), 1);
        config.gravity.omitted_field_sigma_mps2 = 2.0e-5;
        assert_eq!(ConfigurationWarnings::of(&config).bits(), 0);
    }

    /// Every consistency flag names a counter.
    #[test]
    fn every_consistency_flag_is_a_counter() {
        let named = HealthCounters::default().named();
        for flag in HealthCounters::CONSISTENCY_FLAGS {
            assert!(named.iter().any(|(name, _)| *name == flag), "{flag}");
        }
    }

    #[test]
    fn an_outage_is_reported_once_when_its_timeout_elapses() {
        let mut monitor = OutageMonitor::default();
        let reports: usize = (0..100)
            .map(|frame| {
                let now_s = f64::from(frame) * 0.1;
                // Heard every frame, then silent from 1.0 s to 5.0 s, then heard again.
                let heard = !(10..50).contains(&frame);
                usize::from(monitor.observe(now_s, heard, 2.0))
            })
            .sum();
        assert_eq!(reports, 1);
        let mut short = OutageMonitor::default();
        let reports: usize = (0..100)
            .map(|frame| {
                let heard = !(10..25).contains(&frame); // 1.6 s of silence: within 2 s
                usize::from(short.observe(f64::from(frame) * 0.1, heard, 2.0))
            })
            .sum();
        assert_eq!(reports, 0);
    }

    /// Mutation-testing boundaries: counters saturate, and silence of exactly the timeout is
    /// not yet an outage.
    #[test]
    fn counters_saturate_and_an_outage_needs_more_than_the_timeout() {
        let mut counter = u32::MAX - 1;
        count(&mut counter);
        assert_eq!(counter, u32::MAX);
        count(&mut counter);
        assert_eq!(counter, u32::MAX);
        let mut monitor = OutageMonitor::default();
        assert!(!monitor.observe(0.0, true, 2.0));
        assert!(!monitor.observe(2.0, false, 2.0));
        assert!(monitor.observe(2.5, false, 2.0));
    }
}
