//! Covariance growth for errors the linear error model does not contain: an error that stays
//! the same over an interval (a held IMU sample), and the attitude-error kinematics'
//! second-order term while the attitude goes unmeasured.
//!
//! **Coherent growth.** An unmodelled error whose rate has 1σ `σ̇` and keeps its sign over
//! the interval grows as `s(t) = ∫ σ̇ dt` in 1σ, not as `√t`: one step adds `δ = σ̇ Δt` to
//! `s` and `(s + δ)² − s² = (2s + δ) δ` to the variance ([`CoherentGrowth`]). For a constant
//! `σ̇` the `k`-th step adds `(2k − 1) δ²`. This is the exact variance when the error's rate
//! is the same random value for the whole interval, and an upper bound otherwise
//! (Minkowski: the 1σ of a sum is at most the sum of the 1σ).
//!
//! **The second-order attitude term.** The exact kinematics of the body-frame attitude error
//! (`docs/guide/model.md`, nav-core [`crate::error_model`] with the second-order terms kept) are
//! `ϑ̇ = −[ω̂×]ϑ + ½ s δω + ½ ϑ × δω`, `s = √(1 − |ϑ|²)`; the filter's linear model (paper
//! eq. 7) keeps `−[ω̂×]ϑ + ½ δω`. In closed loop both `ϑ` and `δω` are reset to their
//! posterior size at every star-sensor update, and `½ ϑ × δω` is negligible. While the star
//! sensor is blind (a slew faster than it tracks) `ϑ` grows with the gyro scale-factor error
//! times the angle turned, and `ϑ` is only known up to the installation error before the
//! first rotation is seen; then `½ ϑ × δω` biases the gyro scale factors the filter infers
//! from the attitude seen at re-acquisition. [`bilinear_attitude_rate_covariance`] gives
//! its covariance from `P`; the caller grows the attitude covariance in that direction,
//! coherently over the outage.

use nalgebra::{Matrix3, Vector3};

use crate::block::{
    add_scaled_columns, add_scaled_rows, from_vector, read, to_matrix, transpose, Block, Row,
};
use crate::discretise::CovarianceMatrix;
use crate::state::{ATTITUDE, GYRO_BIAS, GYRO_SCALE_FACTOR, STATE_DIMENSION};

/// Coherent growth of one unmodelled error's 1σ (module docs): the 1σ accumulated since the
/// error began, in the unit of the state it is added to.
///
/// # Examples
/// ```
/// use nav_core::unmodelled::CoherentGrowth;
/// let mut growth = CoherentGrowth::default();
/// let added: f64 = (0..3).map(|_| growth.grow(0.5)).sum();
/// // Three steps of 0.5 in 1σ: (3 × 0.5)² in variance.
/// assert!((added - 2.25).abs() < 1e-15);
/// assert!((growth.accumulated_sigma() - 1.5).abs() < 1e-15);
/// growth.restart();
/// assert_eq!(growth.grow(0.5), 0.25);
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CoherentGrowth {
    accumulated_sigma: f64,
}

impl CoherentGrowth {
    /// Adds `step_sigma` (≥ 0; a negative or non-finite step counts as 0) to the accumulated
    /// 1σ and returns the variance this adds, `(2s + δ) δ`.
    pub fn grow(&mut self, step_sigma: f64) -> f64 {
        let step = if step_sigma.is_finite() && step_sigma > 0.0 {
            step_sigma
        } else {
            0.0
        };
        let added = (2.0 * self.accumulated_sigma + step) * step;
        self.accumulated_sigma += step;
        added
    }

    /// Like [`CoherentGrowth::grow`] for an error whose rate is correlated with the rate so
    /// far by `correlation` (clamped to [0, 1]; 1 is [`CoherentGrowth::grow`]): the part of
    /// the accumulated 1σ the new step adds coherently to shrinks by that factor,
    /// `s ← ρ s`, before the step. Successive stretches with uncorrelated rates then add
    /// their variances, as independent errors do.
    ///
    /// # Examples
    /// ```
    /// use nav_core::unmodelled::CoherentGrowth;
    /// let mut growth = CoherentGrowth::default();
    /// let first = growth.grow_correlated(1.0, 1.0) + growth.grow_correlated(1.0, 1.0);
    /// let second = growth.grow_correlated(1.0, 0.0) + growth.grow_correlated(1.0, 1.0);
    /// // Two stretches of 2 in 1σ, uncorrelated: 4 + 4 in variance, not (2 + 2)².
    /// assert_eq!((first, second), (4.0, 4.0));
    /// ```
    pub fn grow_correlated(&mut self, step_sigma: f64, correlation: f64) -> f64 {
        let kept = if correlation.is_finite() {
            correlation.clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.accumulated_sigma *= kept;
        self.grow(step_sigma)
    }

    /// The error is observed or gone: the next step starts from zero.
    pub fn restart(&mut self) {
        self.accumulated_sigma = 0.0;
    }

    /// The 1σ accumulated since the last restart.
    pub fn accumulated_sigma(&self) -> f64 {
        self.accumulated_sigma
    }
}

/// Covariance `E[b bᵀ]` (body axes, 1/s²) of the attitude-error kinematics' second-order
/// term `b = ½ ϑ × δω` (`ϑ` the vector-part attitude error), from the covariance `P` and the
/// measured body rate `ω_m` (rad/s).
///
/// Derivation. With `u = δbg + diag(ω_m) δλg` (`δω = −u` up to the gyro noise, paper eq. 2;
/// the sign cancels in every product below) and `ϑ`, `u` zero-mean jointly Gaussian (the
/// closed loop resets the error state's mean to zero), write `A = P_ϑ`,
/// `U = E[u uᵀ] = P_bb + P_bλ D + D P_λb + D P_λλ D`, `C = E[ϑ uᵀ] = P_ϑb + P_ϑλ D`,
/// `D = diag(ω_m)`. Isserlis' theorem on `(ϑ × u)_i = ε_ijk ϑ_j u_k` and the expansion of
/// `ε_ijk ε_lmn` in Kronecker deltas give, with `a_i = ε_ijk C_jk`,
///
/// ```text
/// E[(ϑ × u)(ϑ × u)ᵀ] = a aᵀ + (tr A tr U − tr AU) I − tr U A − tr A U + AU + UA
///                    + (‖C‖² − (tr C)²) I − C Cᵀ − Cᵀ C + tr C (C + Cᵀ).
/// ```
///
/// Its trace is `E[|ϑ|²|u|²] − E[(ϑ·u)²]`: the parts of `ϑ` and `u` along the same axis (a
/// rotation about one axis with that axis' scale-factor error) cancel, as in the cross
/// product.
///
/// # Examples
/// ```
/// use nalgebra::Vector3;
/// use nav_core::discretise::CovarianceMatrix;
/// use nav_core::state::{ATTITUDE, GYRO_SCALE_FACTOR};
/// use nav_core::unmodelled::bilinear_attitude_rate_covariance;
/// // Attitude error 1σ 1e-3 on x only, gyro scale factor 1σ 1e-4 on y only, turning at
/// // 2 rad/s about y: b = ½ ϑx λy ωy along z, 1σ ½ · 1e-3 · 1e-4 · 2 = 1e-7 rad/s.
/// let mut p = CovarianceMatrix::zeros();
/// p[(ATTITUDE.index(), ATTITUDE.index())] = 1e-6;
/// p[(GYRO_SCALE_FACTOR.index() + 1, GYRO_SCALE_FACTOR.index() + 1)] = 1e-8;
/// let b = bilinear_attitude_rate_covariance(&p, &Vector3::new(0.0, 2.0, 0.0));
/// assert!((b[(2, 2)].sqrt() - 1e-7).abs() < 1e-20);
/// assert_eq!(b[(0, 0)] + b[(1, 1)], 0.0);
/// // The same scale-factor error turning about x, the attitude error's own axis: no term.
/// p[(GYRO_SCALE_FACTOR.index() + 1, GYRO_SCALE_FACTOR.index() + 1)] = 0.0;
/// p[(GYRO_SCALE_FACTOR.index(), GYRO_SCALE_FACTOR.index())] = 1e-8;
/// assert_eq!(bilinear_attitude_rate_covariance(&p, &Vector3::new(2.0, 0.0, 0.0)).trace(), 0.0);
/// ```
pub fn bilinear_attitude_rate_covariance(
    covariance: &CovarianceMatrix,
    measured_rate_rad_s: &Vector3<f64>,
) -> Matrix3<f64> {
    const A: usize = ATTITUDE.index();
    const B: usize = GYRO_BIAS.index();
    const L: usize = GYRO_SCALE_FACTOR.index();
    const N: usize = STATE_DIMENSION;
    let rate = from_vector(measured_rate_rad_s);
    let bias_scale = read::<B, L, N, N>(covariance);
    let attitude = to_matrix(&read::<A, A, N, N>(covariance));
    let cross = to_matrix(&add_scaled_columns(
        &read::<A, B, N, N>(covariance),
        &read::<A, L, N, N>(covariance),
        rate,
    ));
    let rate_error = to_matrix(&add_scaled_rows(
        &add_scaled_columns(&read::<B, B, N, N>(covariance), &bias_scale, rate),
        &add_scaled_columns(
            &transpose(&bias_scale),
            &read::<L, L, N, N>(covariance),
            rate,
        ),
        rate,
    ));
    let axial = Vector3::new(
        cross.m23 - cross.m32,
        cross.m31 - cross.m13,
        cross.m12 - cross.m21,
    );
    let (trace_a, trace_u, trace_c) = (attitude.trace(), rate_error.trace(), cross.trace());
    let product = attitude * rate_error;
    let cross_product = cross * cross.transpose();
    let isotropic = trace_a * trace_u - product.trace() + cross_product.trace() - trace_c * trace_c;
    let expectation = axial * axial.transpose() + Matrix3::from_diagonal_element(isotropic)
        - attitude * trace_u
        - rate_error * trace_a
        + product
        + product.transpose()
        - cross_product
        - cross.transpose() * cross
        + (cross + cross.transpose()) * trace_c;
    expectation * 0.25
}

/// Correlation coefficient of the gyro rate errors `u = δbg + diag(ω) δλg` at two body rates
/// `ω_a`, `ω_b` (rad/s), from `P`: `E[u_a · u_b] / √(E|u_a|² E|u_b|²)`, with
/// `E[u_a · u_b] = Σ_k P(bg_k, bg_k) + (ω_a,k + ω_b,k) P(bg_k, λg_k) + ω_a,k ω_b,k P(λg_k, λg_k)`.
/// A rotation about another axis, or a stop, makes the scale-factor part of the rate error a
/// different random variable (`ρ ≈ 0`); the same rotation keeps it (`ρ = 1`). Returns 0 when
/// either rate error has no variance.
///
/// # Examples
/// ```
/// use nalgebra::Vector3;
/// use nav_core::discretise::CovarianceMatrix;
/// use nav_core::state::GYRO_SCALE_FACTOR;
/// use nav_core::unmodelled::rate_error_correlation;
/// let mut p = CovarianceMatrix::zeros();
/// for k in 0..3 {
///     p[(GYRO_SCALE_FACTOR.index() + k, GYRO_SCALE_FACTOR.index() + k)] = 1e-8;
/// }
/// let (about_x, about_y) = (Vector3::new(1.7, 0.0, 0.0), Vector3::new(0.0, 1.7, 0.0));
/// assert_eq!(rate_error_correlation(&p, &about_x, &(about_x * 0.5)), 1.0);
/// assert_eq!(rate_error_correlation(&p, &about_x, &about_y), 0.0);
/// ```
pub fn rate_error_correlation(
    covariance: &CovarianceMatrix,
    rate_a_rad_s: &Vector3<f64>,
    rate_b_rad_s: &Vector3<f64>,
) -> f64 {
    const B: usize = GYRO_BIAS.index();
    const L: usize = GYRO_SCALE_FACTOR.index();
    const N: usize = STATE_DIMENSION;
    // The diagonals of the three blocks, read once (each sum below takes them in the order
    // of the formula, axis by axis).
    let diagonal = |block: Block| {
        let [[d0, _, _], [_, d1, _], [_, _, d2]] = block;
        [d0, d1, d2]
    };
    let bias = diagonal(read::<B, B, N, N>(covariance));
    let bias_scale = diagonal(read::<B, L, N, N>(covariance));
    let scale = diagonal(read::<L, L, N, N>(covariance));
    let inner = |a: &Row, b: &Row| {
        let mut sum = 0.0;
        for ((((wa, wb), p_bb), p_bl), p_ll) in a.iter().zip(b).zip(bias).zip(bias_scale).zip(scale)
        {
            sum += p_bb + (wa + wb) * p_bl + wa * wb * p_ll;
        }
        sum
    };
    let (rate_a, rate_b) = (from_vector(rate_a_rad_s), from_vector(rate_b_rad_s));
    let norm = inner(&rate_a, &rate_a) * inner(&rate_b, &rate_b);
    let correlation = inner(&rate_a, &rate_b) / crate::float::sqrt(norm);
    if norm > 0.0 && correlation.is_finite() {
        correlation.clamp(-1.0, 1.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::SMatrix;

    /// Deterministic uniform numbers in [0, 1) (64-bit LCG; the test needs no crate).
    struct Lcg(u64);
    impl Lcg {
        fn uniform(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((self.0 >> 11) as f64) / ((1_u64 << 53) as f64)
        }
        fn gaussian(&mut self) -> f64 {
            let (u1, u2) = (self.uniform().max(1e-300), self.uniform());
            crate::float::sqrt(-2.0 * libm::log(u1)) * libm::cos(2.0 * core::f64::consts::PI * u2)
        }
    }

    /// A random covariance whose attitude, gyro-bias and gyro-scale-factor blocks are
    /// correlated (`P = G Gᵀ`).
    fn correlated_covariance(rng: &mut Lcg) -> CovarianceMatrix {
        let mut g = SMatrix::<f64, STATE_DIMENSION, STATE_DIMENSION>::zeros();
        let scales = [
            (ATTITUDE.index(), 1e-3),
            (GYRO_BIAS.index(), 1e-6),
            (GYRO_SCALE_FACTOR.index(), 1e-4),
        ];
        for (index, scale) in scales {
            for i in index..index + 3 {
                for (other, _) in scales {
                    for j in other..other + 3 {
                        g[(i, j)] = scale * rng.gaussian();
                    }
                }
            }
        }
        // The other states are unit variances, uncorrelated, so that `P` has a Cholesky root.
        for i in 0..STATE_DIMENSION {
            if g.row(i).iter().all(|x| *x == 0.0) {
                g[(i, i)] = 1.0;
            }
        }
        g * g.transpose()
    }

    /// The covariance equals the sampled mean of (½ ϑ × δω)(½ ϑ × δω)ᵀ for correlated `ϑ`,
    /// `δbg`, `δλg` drawn from `P` and `δω` formed as the filter's gyro model does (paper
    /// eq. 2).
    #[test]
    fn the_covariance_equals_the_sampled_second_order_term() {
        let mut rng = Lcg(7);
        for case in 0..5 {
            let p = correlated_covariance(&mut rng);
            let rate = Vector3::new(1.7, -0.4, 0.9) * (case as f64);
            let expected = bilinear_attitude_rate_covariance(&p, &rate);
            let root = p.cholesky().unwrap().l();
            let samples = 40_000;
            let mut sampled = Matrix3::zeros();
            for _ in 0..samples {
                let white = SMatrix::<f64, STATE_DIMENSION, 1>::from_fn(|_, _| rng.gaussian());
                let x = root * white;
                let theta = x.fixed_rows::<3>(ATTITUDE.index()).into_owned();
                let bias = x.fixed_rows::<3>(GYRO_BIAS.index()).into_owned();
                let scale = x.fixed_rows::<3>(GYRO_SCALE_FACTOR.index()).into_owned();
                let rate_error = -(bias + rate.component_mul(&scale));
                let term = 0.5 * theta.cross(&rate_error);
                sampled += term * term.transpose();
            }
            sampled /= samples as f64;
            // 40,000 samples of products of Gaussians: within a few per cent of the trace.
            let difference = (sampled - expected).abs().max();
            assert!(
                difference < 0.03 * expected.trace(),
                "case {case}: {expected} vs sampled {sampled}"
            );
        }
    }

    #[test]
    fn a_non_finite_growth_step_adds_nothing() {
        let mut growth = CoherentGrowth::default();
        assert_eq!(growth.grow(f64::INFINITY).to_bits(), 0);
        assert_eq!(growth.grow(-1.0).to_bits(), 0);
        assert_eq!(growth.accumulated_sigma().to_bits(), 0);
    }
}
