//! Star-sensor noise matching: once the star innovations fail the consistency test, the
//! measurement noise `R` of each sensor axis follows the scatter the innovations show, never
//! below the configured noise. A tracker noisier than the flight software was told (a roll
//! noise left out of the configuration) is then weighted by its real noise, instead of pulling
//! the calibration by many σ and having its runs of gate rejections end in a fault declaration.
//!
//! **Estimate** (covariance matching: Mehra, "Approaches to adaptive filtering", IEEE Trans.
//! Automatic Control 17(5), 1972, §IV; Mohamed and Schwarz, "Adaptive Kalman filtering for
//! INS/GPS", Journal of Geodesy 73, 1999, eq. 26). For the innovation `ν = z − H x̂` of a filter
//! whose `P` is right, `cov ν = H P Hᵀ + R`, and consecutive innovations are uncorrelated. With
//! a true noise `R_t` per sensor axis `i` and `p = (H P Hᵀ)_ii = S_ii − R_i` (the `R` the update
//! used), `x_k = (ν_{k,i} − ν_{k−1,i})² / 2 − (p_k + p_{k−1}) / 2` therefore has mean `R_t`:
//! the innovations' scatter from one measurement to the next, less what the state error
//! explains. The difference takes out whatever the innovations share from one measurement to
//! the next (an offset, a drift). `x_k` has variance `(S_k + S_{k−1})² / 2`, so the estimate is
//! the average weighted by `w_k = 1/(S_k + S_{k−1})²`, fading with the consistency monitor's
//! time constant `N`: `R̂ = Σ λ^(n−k) w_k x_k / Σ λ^(n−k) w_k`, `λ = 1 − 1/N`. The weight keeps
//! out the measurements of a filter far from converged (after start-up or a widening of its
//! covariance, `S` a thousand times `R`), whose `x_k` are large and say nothing of the noise;
//! the fading keeps the last `N` measurements. The update then uses
//! `R_i = max(R_configured,i, R̂_i)`; the star residual is half the rotation angle, so the noise
//! angle is `σ_i = 2 √R_i`.
//!
//! **Scatter, not offset.** A faulty tracker (a step, a frozen output) and an inertial
//! solution drifting away give innovations that are offset, not scattered: the difference
//! takes the offset out of `R̂` (the step enters once), so neither widens the noise, and the
//! fault logic still declares the tracker faulty or blames the inertial solution. A
//! gate-rejected measurement enters scaled to the gate (`ν √(gate/NIS)`), as in the
//! consistency monitor. While `R` was too small `P` is
//! too small as well, so `p` is low and `R̂` high: the estimate errs on the cautious side.
//!
//! **When.** The averages take the measurements after the aid's acquisition (the first, under
//! the acquisition gate, tells the prior, not the noise), and are used from a measurement at
//! which the consistency monitor fails *and* the averages show the tracker noisier than
//! configured on some axis by more than [`NOISIER_THAN_CONFIGURED_RATIO`] (the evidence
//! points at the tracker: its scatter, not an offset or drift of the inertial solution, which
//! the differences take out; a g-sensitivity the filter is not told of fails the monitor in
//! every burn while the scatter stays the configured noise) until the filter is
//! re-initialised: once `R`
//! follows the innovations the monitor passes again, and letting go would bring the
//! inconsistency back. A consistent filter never engages it (the monitor's false-alarm rate),
//! so its bits are those of a filter without it. A non-finite innovation is not entered.

/// The matched noise (1σ) over the configured beyond which the tracker is noisier than the
/// flight software is told: the matched σ of a tracker as noisy as configured scatters by a
/// few per cent (a fading average of squared differences over some `N` = 256 measurements:
/// `√(2/(2N − 1))` = 6 % in variance, 3 % in σ), so 1.25 lies some eight of its σ beyond.
pub const NOISIER_THAN_CONFIGURED_RATIO: f64 = 1.25;

/// Averages of one aid's per-axis innovation statistics and whether they set its noise.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NoiseMatching {
    /// The last innovation entered (scaled to the gate if it was rejected).
    previous_innovation: [f64; 3],
    /// Its `S_ii` per sensor axis.
    previous_variance: [f64; 3],
    /// Its `(H P Hᵀ)_ii = S_ii − R_i` per sensor axis.
    previous_predicted: [f64; 3],
    /// `Σ λ^(n−k) w_k x_k` per sensor axis (module docs).
    weighted_excess: [f64; 3],
    /// `Σ λ^(n−k) w_k` per sensor axis.
    total_weight: [f64; 3],
    /// Whether a measurement has been entered.
    started: bool,
    /// Whether the averages set the noise (latched until [`NoiseMatching::clear`]).
    engaged: bool,
}

impl NoiseMatching {
    /// Enters one tested measurement: its innovation `ν` and the diagonal of its covariance
    /// `S` per axis, the noise angles `noise_rad` (1σ) its update used, its NIS, whether it
    /// passed the gate `gate_nis`, and the time constant `N` (measurements).
    ///
    /// # Examples
    /// ```
    /// use nav_fsw::noise_matching::NoiseMatching;
    /// let configured = [5e-5, 5e-5, 5e-5];
    /// // R = (σ/2)² = 6.25e-10 per axis, S = 7e-10; innovations ±√(1e-9) about z, which
    /// // differ by 2√(1e-9) from one to the next: (ν_k − ν_{k−1})² / 2 = 2e-9.
    /// let mut matching = NoiseMatching::default();
    /// for k in 0..2000 {
    ///     let z = if k % 2 == 0 { 1e-9_f64.sqrt() } else { -(1e-9_f64.sqrt()) };
    ///     let nis = z * z / 7e-10;
    ///     matching.observe(&[0.0, 0.0, z], &[7e-10; 3], &configured, nis, true, 16.27, 256);
    /// }
    /// assert!(matching.engage(&configured));
    /// let used = matching.noise_rad(&configured);
    /// assert_eq!(used[0].to_bits(), configured[0].to_bits());
    /// assert!((used[2] - 2.0 * (2e-9_f64 - 7.5e-11).sqrt()).abs() < 1e-9);
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn observe(
        &mut self,
        innovation: &[f64; 3],
        innovation_variance: &[f64; 3],
        noise_rad: &[f64; 3],
        nis: f64,
        accepted: bool,
        gate_nis: f64,
        time_constant_measurements: u32,
    ) {
        let finite = innovation
            .iter()
            .chain(innovation_variance)
            .all(|x| x.is_finite());
        if !finite || !nis.is_finite() {
            return;
        }
        // A rejected innovation enters scaled to the gate (module docs).
        let scale = if accepted || nis <= gate_nis {
            1.0
        } else {
            nav_core::float::sqrt(gate_nis / nis)
        };
        let entered = innovation.map(|nu| nu * scale);
        let predicted: [f64; 3] = core::array::from_fn(|axis| {
            let half_noise = 0.5 * noise_rad.get(axis).copied().unwrap_or(0.0);
            innovation_variance.get(axis).copied().unwrap_or(f64::NAN) - half_noise * half_noise
        });
        let previous = core::mem::replace(&mut self.previous_innovation, entered);
        let previous_variance =
            core::mem::replace(&mut self.previous_variance, *innovation_variance);
        let previous_predicted = core::mem::replace(&mut self.previous_predicted, predicted);
        let first = !self.started;
        self.started = true;
        if first {
            return;
        }
        let fading = 1.0 - 1.0 / f64::from(time_constant_measurements.max(1));
        let sums = self.weighted_excess.iter_mut().zip(&mut self.total_weight);
        let now = entered.iter().zip(innovation_variance).zip(&predicted);
        let before = previous
            .iter()
            .zip(&previous_variance)
            .zip(&previous_predicted);
        for ((excess, weight), (((nu, s), p), ((nu_before, s_before), p_before))) in
            sums.zip(now.zip(before))
        {
            let difference = nu - nu_before;
            let x = 0.5 * difference * difference - 0.5 * (p + p_before);
            let sum_variance = s + s_before;
            let w = 1.0 / (sum_variance * sum_variance);
            if x.is_finite() && w.is_finite() {
                *excess = fading * *excess + w * x;
                *weight = fading * *weight + w;
            }
        }
    }

    /// Lets the averages set the noise from now on if they show the tracker noisier than
    /// `configured` ([`Self::noisier_than`]); true when they did not before (one count per
    /// engagement). Refused (false, nothing changes) before the first measurement and while
    /// the scatter is the configured noise's.
    pub fn engage(&mut self, configured: &[f64; 3]) -> bool {
        let began = self.started && !self.engaged && self.noisier_than(configured);
        self.engaged |= began;
        began
    }

    /// Whether the averages put some axis's noise above [`NOISIER_THAN_CONFIGURED_RATIO`]
    /// times its `configured` noise (engaged or not).
    pub fn noisier_than(&self, configured: &[f64; 3]) -> bool {
        self.matched_noise_rad(configured)
            .iter()
            .zip(configured)
            .any(|(matched, configured)| *matched > NOISIER_THAN_CONFIGURED_RATIO * configured)
    }

    /// Whether the averages set the noise.
    pub fn engaged(&self) -> bool {
        self.engaged
    }

    /// The noise angles (1σ per sensor axis) the next update uses: `configured` until
    /// engaged, then per axis the larger of `configured` and `2 √R̂` (module docs).
    pub fn noise_rad(&self, configured: &[f64; 3]) -> [f64; 3] {
        if !self.engaged {
            return *configured;
        }
        self.matched_noise_rad(configured)
    }

    /// Per axis the larger of `configured` and `2 √R̂`, engaged or not.
    fn matched_noise_rad(&self, configured: &[f64; 3]) -> [f64; 3] {
        let mut used = *configured;
        let sums = self.weighted_excess.iter().zip(&self.total_weight);
        for (noise, (excess, weight)) in used.iter_mut().zip(sums) {
            if *weight > 0.0 {
                let matched_variance = excess / weight;
                let half_noise = 0.5 * *noise;
                if matched_variance > half_noise * half_noise {
                    *noise = 2.0 * nav_core::float::sqrt(matched_variance);
                }
            }
        }
        used
    }

    /// Starts afresh (a re-initialised filter): no history, the configured noise.
    pub fn clear(&mut self) {
        *self = Self::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_random::normal_source;

    const ARCSEC: f64 = core::f64::consts::PI / 180.0 / 3600.0;
    const GATE: f64 = 16.27;

    /// Feeds `count` measurements whose innovations are `offset + noise` per axis (the true
    /// noise angle `true_noise`, residual = half of it) to `matching`, gated as the filter
    /// gates them with the noise the matching sets; engages it from the first. Returns the
    /// number accepted.
    fn feed(
        matching: &mut NoiseMatching,
        configured: &[f64; 3],
        true_noise: &[f64; 3],
        offset: &[f64; 3],
        count: u32,
        normal: &mut impl FnMut() -> f64,
    ) -> u32 {
        let predicted = 0.2 * (5.0 * ARCSEC) * (5.0 * ARCSEC); // H P Hᵀ per axis
        let mut accepted = 0;
        for _ in 0..count {
            let used = matching.noise_rad(configured);
            let variance = used.map(|n| predicted + 0.25 * n * n);
            let innovation: [f64; 3] = core::array::from_fn(|i| {
                offset[i]
                    + normal()
                        * nav_core::float::sqrt(predicted + 0.25 * true_noise[i] * true_noise[i])
            });
            let nis: f64 = (0..3)
                .map(|i| innovation[i] * innovation[i] / variance[i])
                .sum();
            matching.observe(&innovation, &variance, &used, nis, nis < GATE, GATE, 256);
            matching.engage(configured);
            accepted += u32::from(nis < GATE);
        }
        accepted
    }

    /// A filter told 10″ per axis whose tracker has 35″ about the boresight: the matched roll
    /// noise converges to the tracker's within the averages' scatter (`√(2/(2N − 1))` = 6 %
    /// in variance for `N` = 256) and the gate's truncation, and the cross axes, whose
    /// innovations agree with the configuration, keep the configured noise.
    #[test]
    fn the_matched_noise_converges_to_the_trackers_and_never_falls_below_the_configured() {
        let configured = [10.0 * ARCSEC; 3];
        let true_noise = [10.0 * ARCSEC, 10.0 * ARCSEC, 35.0 * ARCSEC];
        let mut normal = normal_source(0x5eed_1234_abcd_0001);
        let mut matching = NoiseMatching::default();
        // Within 30 measurements (3 s at 10 Hz) most measurements pass the gate again.
        let early = feed(
            &mut matching,
            &configured,
            &true_noise,
            &[0.0; 3],
            30,
            &mut normal,
        );
        let later = feed(
            &mut matching,
            &configured,
            &true_noise,
            &[0.0; 3],
            30,
            &mut normal,
        );
        assert!(later >= 27, "{early} then {later} of 30 accepted");
        feed(
            &mut matching,
            &configured,
            &true_noise,
            &[0.0; 3],
            8_000,
            &mut normal,
        );
        let used = matching.noise_rad(&configured);
        assert!(
            (used[2] / true_noise[2] - 1.0).abs() < 0.1,
            "roll {}",
            used[2] / ARCSEC
        );
        for axis in 0..2 {
            assert!(used[axis] >= configured[axis]);
            assert!(
                used[axis] < 1.15 * configured[axis],
                "{}",
                used[axis] / ARCSEC
            );
        }
    }

    /// A tracker whose output steps by 120″ about x after 300 good measurements (a fault): its
    /// innovations are offset, not scattered, so the matched noise stays within 1.5 times the
    /// configured and the step is still rejected, measurement after measurement.
    #[test]
    fn a_step_is_not_taken_for_noise() {
        let configured = [10.0 * ARCSEC; 3];
        let mut normal = normal_source(0x0dd_ba11_cafe_f00d);
        let mut matching = NoiseMatching::default();
        feed(
            &mut matching,
            &configured,
            &configured,
            &[0.0; 3],
            300,
            &mut normal,
        );
        let step = [0.5 * 120.0 * ARCSEC, 0.0, 0.0];
        let accepted = feed(
            &mut matching,
            &configured,
            &configured,
            &step,
            100,
            &mut normal,
        );
        assert_eq!(accepted, 0);
        let used = matching.noise_rad(&configured);
        assert!(used[0] < 1.5 * configured[0], "{}", used[0] / ARCSEC);
    }

    /// Innovations that wander (an inertial solution pulled away by an error the filter does
    /// not model and pulled back by the updates: an offset of 15″ amplitude over 30 s) over a
    /// tracker as noisy as configured: the scatter is the configured noise, so the matching
    /// does not engage, and the tracker keeps its weight.
    #[test]
    fn a_drifting_inertial_solution_does_not_engage_it() {
        let configured = [10.0 * ARCSEC; 3];
        let mut normal = normal_source(0x5eed_0000_d1f7_0001);
        let mut matching = NoiseMatching::default();
        let variance =
            [0.2 * (5.0 * ARCSEC) * (5.0 * ARCSEC) + 0.25 * configured[0] * configured[0]; 3];
        for k in 0..3_000 {
            let phase = 2.0 * core::f64::consts::PI * f64::from(k) / 300.0;
            let offset = 15.0 * ARCSEC * libm::sin(phase);
            let innovation: [f64; 3] = core::array::from_fn(|i| {
                let wander = if i == 0 { offset } else { 0.0 };
                wander + normal() * nav_core::float::sqrt(variance[i])
            });
            let nis: f64 = (0..3)
                .map(|i| innovation[i] * innovation[i] / variance[i])
                .sum();
            matching.observe(
                &innovation,
                &variance,
                &configured,
                nis,
                nis < GATE,
                GATE,
                256,
            );
            // The consistency monitor fails on such a stream after some tens of measurements.
            if k >= 256 {
                assert!(!matching.engage(&configured), "measurement {k}");
            }
        }
        assert!(!matching.engaged());
    }

    /// Before it is engaged the averages change nothing; a non-finite innovation is not
    /// entered; `clear` forgets everything.
    #[test]
    fn unengaged_matching_keeps_the_configured_noise() {
        let configured = [1e-4; 3];
        let variance = [5e-9; 3];
        let mut matching = NoiseMatching::default();
        assert!(
            !matching.engage(&configured),
            "no engagement before a measurement"
        );
        let before = matching;
        matching.observe(
            &[f64::NAN, 0.0, 0.0],
            &variance,
            &configured,
            1.0,
            true,
            GATE,
            16,
        );
        assert_eq!(matching, before);
        let large = [nav_core::float::sqrt(4.0 * 5e-9), 0.0, 0.0];
        for k in 0..64 {
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            matching.observe(
                &large.map(|x| sign * x),
                &variance,
                &configured,
                4.0,
                true,
                GATE,
                16,
            );
        }
        assert_eq!(
            matching.noise_rad(&configured).map(f64::to_bits),
            configured.map(f64::to_bits)
        );
        assert!(matching.engage(&configured) && !matching.engage(&configured));
        // Differences of 2 √(2e-8): R̂ = 4e-8 − 2.5e-9 (p = S − R = 5e-9 − 2.5e-9), σ = 2 √R̂.
        let used = matching.noise_rad(&configured);
        assert!(
            (used[0] - 2.0 * nav_core::float::sqrt(3.75e-8)).abs() < 1e-12,
            "{used:?}"
        );
        assert_eq!(
            used.map(f64::to_bits)[1..],
            configured.map(f64::to_bits)[1..]
        );
        matching.clear();
        assert!(!matching.engaged());
        assert_eq!(
            matching.noise_rad(&configured).map(f64::to_bits),
            configured.map(f64::to_bits)
        );
    }
}
