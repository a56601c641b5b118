//! Structured (block-sparse) covariance propagation, measurement update and reset: the same
//! arithmetic as the dense reference ([`crate::discretise::discretise`] with
//! [`crate::filter::ErrorStateFilter::predict`], and the dense Joseph update), computed only
//! where the 3×3 blocks of `F`, `Γ`, `H` and the reset Jacobian are non-zero and
//! non-identity, upper triangle only, symmetric by construction. The flight path uses these;
//! the dense versions stay as the reference the tests compare against (relative 1e-12).
//!
//! ## Structure of the discrete model (derivation)
//! Order the state as `d = (ϑ, δp, δv)` (9 "dynamic" states) and `c` (the 15 calibration
//! states). [`crate::error_model::system_matrix`] has non-zero rows only in `d`:
//! `A = [[M, B], [0, 0]]` with, in 3×3 blocks,
//! `M = [[W, 0, 0], [0, 0, I], [V, N, 0]]` (`W = −[ω̂×]`, `V = −2Ĉ[f̂×]`, `N = ∂g/∂p`) and `B`
//! non-zero only in `B_{ϑ,bg} = −½I`, `B_{ϑ,λg} = −½ diag(ω_m)`, `B_{δv,ba} = −Ĉ`,
//! `B_{δv,λa} = −Ĉ diag(f_m)`. Hence `A^n = [[M^n, M^{n−1}B], [0, 0]]` for `n ≥ 1`, and the
//! series of [`crate::discretise`] become
//! * `F = Σ_{n=0..N} (AΔ)^n/n! = [[Φ, Ψ B Δ], [0, I]]`, `Φ = Σ_{n=0..N} (MΔ)^n/n!`,
//!   `Ψ = Σ_{n=1..N} (MΔ)^{n−1}/n!`;
//! * `S = Σ_{n=1..N} (AΔ)^{n−1}/n! = [[Ψ, Χ B Δ], [0, I]]`, `Χ = Σ_{n=2..N} (MΔ)^{n−2}/n!`,
//!   and `Γ = S G Δ`.
//!
//! With `a = WΔ`, `b = VΔ`, `g = NΔ`, `d = Δ`, the powers of `MΔ` have only the blocks
//! (ϑϑ, pϑ, pp, pv, vϑ, vp, vv) — rows `ϑ` never reach `δp`, `δv`:
//!
//! | n | ϑϑ  | pϑ            | pp    | pv   | vϑ          | vp    | vv    |
//! |---|-----|---------------|-------|------|-------------|-------|-------|
//! | 1 | a   | 0             | 0     | d I  | b           | g     | 0     |
//! | 2 | a²  | d b           | d g   | 0    | b a         | 0     | d g   |
//! | 3 | a³  | d b a         | 0     | d² g | b a² + d g b| d g²  | 0     |
//! | 4 | a⁴  | d b a² + d² g b | d² g² | 0  | b a³ + d g b a | 0  | d² g² |
//!
//! (each row is the previous one times `MΔ` on the right: `X_{rϑ} a + X_{rv} b`,
//! `X_{rv} g`, `X_{rp} d`). The calibration columns of `F` are
//! `E_g = −½Δ Ψ_{·ϑ}` (gyro bias), `E_g diag(ω_m)` (gyro scale factor),
//! `E_a = −Δ Ψ_{·v} Ĉ` (accelerometer bias, rows δp and δv) and `E_a diag(f_m)`
//! (accelerometer scale factor); the installation column is zero. The noise columns of
//! `Γ` are `E_g` (gyro noise), `E_a` (accelerometer noise), `[−½Δ² Χ_{·ϑ}; ΔI]` (gyro-bias
//! walk) and `[−Δ² Χ_{·v} Ĉ; ΔI]` (accelerometer-bias walk), and
//! `Qd = Σ_k (q_k/Δ) Γ_k Γ_kᵀ` over the noise blocks with a non-zero density.
//!
//! ## Propagation
//! With `P = [[P_dd, P_dc], [P_cd, P_cc]]`: `F P Fᵀ` keeps `P_cc`; `U = [Φ E] P` (9×24) is the
//! new `P_dc` in its calibration columns, and the new `P_dd = U [Φ E]ᵀ + Qd_dd` (upper block
//! triangle only, diagonal blocks mirrored). The scale-factor columns are folded into the
//! bias columns before multiplying: `E_g P_{bg,j} + E_g diag(ω_m) P_{λg,j} =
//! E_g (P_{bg,j} + diag(ω_m) P_{λg,j})`, likewise for the accelerometer.
//!
//! ## Update
//! For any gain `K` the Joseph form expands exactly (Bucy & Joseph 1968) to
//! `(I − KH) P (I − KH)ᵀ + K R Kᵀ = P − K Mᵀ − M Kᵀ + K S Kᵀ` with `M = P Hᵀ`,
//! `S = H P Hᵀ + R`; element-wise `P⁺_ij = P_ij − K_i·M_j + (K_i S − M_i)·K_j`, O(n²) with
//! 6 multiply-adds per element of the upper triangle. `M` is summed only over the non-zero
//! 3×3 blocks of `H` (found at run time, so a measurement referred to a later time with
//! `H (I − AΔ)` is handled with its extra bias/scale-factor/velocity columns).
//!
//! ## Reset
//! The reset Jacobian is the identity except the attitude and installation diagonal blocks,
//! so only the block rows and columns of those two blocks change.

use nalgebra::{Matrix3, SMatrix, Vector3};

use crate::discretise::{CovarianceMatrix, MAX_ORDER};
use crate::error_model::{LinearisationPoint, ProcessNoise};
use crate::filter::block_of;
use crate::state::{
    BlockMask, StateBlock, ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, GYRO_BIAS, GYRO_SCALE_FACTOR,
    POSITION, STAR_INSTALLATION, VELOCITY,
};
use crate::NavError;

/// Number of states the process noise can reach: attitude, position, velocity, gyro bias and
/// accelerometer bias (states 1-15; the installation error and scale factors have none).
pub const NOISE_DRIVEN_DIMENSION: usize = 15;
/// Number of dynamic states (attitude, position, velocity), the rows of `F` that differ from
/// the identity.
const DYNAMIC_DIMENSION: usize = 9;

/// `1/n!` for `n = 0..=MAX_ORDER + 2` (the `Χ` series reaches `1/(N)!` with `N ≤ 4`).
const INVERSE_FACTORIALS: [f64; 7] = [
    1.0,
    1.0,
    0.5,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
];

/// The seven 3×3 blocks over (ϑ, δp, δv) that a power of `MΔ` (and so `Φ`, `Ψ`, `Χ`) can
/// have non-zero (module docs table); ϑp and ϑv are always zero.
#[derive(Debug, Clone, Copy, PartialEq)]
struct DynamicBlocks {
    attitude_attitude: Matrix3<f64>,
    position_attitude: Matrix3<f64>,
    position_position: Matrix3<f64>,
    position_velocity: Matrix3<f64>,
    velocity_attitude: Matrix3<f64>,
    velocity_position: Matrix3<f64>,
    velocity_velocity: Matrix3<f64>,
}

impl DynamicBlocks {
    fn zeros() -> Self {
        let zero = Matrix3::zeros();
        Self {
            attitude_attitude: zero,
            position_attitude: zero,
            position_position: zero,
            position_velocity: zero,
            velocity_attitude: zero,
            velocity_position: zero,
            velocity_velocity: zero,
        }
    }

    fn identity() -> Self {
        let identity = Matrix3::identity();
        Self {
            attitude_attitude: identity,
            position_position: identity,
            velocity_velocity: identity,
            ..Self::zeros()
        }
    }

    /// `self += factor · other`, block by block.
    fn add_scaled(&mut self, other: &Self, factor: f64) {
        self.attitude_attitude += other.attitude_attitude * factor;
        self.position_attitude += other.position_attitude * factor;
        self.position_position += other.position_position * factor;
        self.position_velocity += other.position_velocity * factor;
        self.velocity_attitude += other.velocity_attitude * factor;
        self.velocity_position += other.velocity_position * factor;
        self.velocity_velocity += other.velocity_velocity * factor;
    }

    /// The powers `(MΔ)^n`, `n = 0..=order` (closed forms of the module docs table); powers
    /// above `order` are left zero and never computed.
    fn powers(point: &LinearisationPoint, interval_s: f64, order: u8) -> [Self; 5] {
        let d = interval_s;
        let a = -crate::attitude::skew(&(point.corrected_rate_rad_s * d));
        let b = -2.0
            * d
            * point.body_to_inertial
            * crate::attitude::skew(&point.corrected_specific_force_mps2);
        let g = point.gravity_gradient_per_s2 * d;
        let zero = Self::zeros();
        let mut powers = [Self::identity(), zero, zero, zero, zero];
        let [_, first, second, third, fourth] = &mut powers;
        *first = Self {
            attitude_attitude: a,
            position_velocity: Matrix3::identity() * d,
            velocity_attitude: b,
            velocity_position: g,
            ..zero
        };
        if order < 2 {
            return powers;
        }
        let a2 = a * a;
        let ba = b * a;
        let dg = g * d;
        *second = Self {
            attitude_attitude: a2,
            position_attitude: b * d,
            position_position: dg,
            velocity_attitude: ba,
            velocity_velocity: dg,
            ..zero
        };
        if order < 3 {
            return powers;
        }
        let ba2 = ba * a;
        let gb = g * b;
        let g2 = g * g;
        *third = Self {
            attitude_attitude: a2 * a,
            position_attitude: ba * d,
            position_velocity: dg * d,
            velocity_attitude: ba2 + gb * d,
            velocity_position: g2 * d,
            ..zero
        };
        if order < 4 {
            return powers;
        }
        let d2g2 = g2 * (d * d);
        *fourth = Self {
            attitude_attitude: a2 * a2,
            position_attitude: ba2 * d + gb * (d * d),
            position_position: d2g2,
            velocity_attitude: ba2 * a + g * ba * d,
            velocity_velocity: d2g2,
            ..zero
        };
        powers
    }
}

/// Rows of `m` scaled by `scale` (`diag(scale) m`), without a full product.
fn scale_rows(m: &Matrix3<f64>, scale: &Vector3<f64>) -> Matrix3<f64> {
    let mut scaled = *m;
    for (mut row, factor) in scaled.row_iter_mut().zip(scale.iter()) {
        row *= *factor;
    }
    scaled
}

/// Columns of `m` scaled by `scale` (`m diag(scale)`), without a full product.
fn scale_columns(m: &Matrix3<f64>, scale: &Vector3<f64>) -> Matrix3<f64> {
    let mut scaled = *m;
    for (mut column, factor) in scaled.column_iter_mut().zip(scale.iter()) {
        column *= *factor;
    }
    scaled
}

/// Writes the 3×3 block (`row`, `column`) of a matrix.
fn set<const R: usize, const C: usize>(
    matrix: &mut SMatrix<f64, R, C>,
    row: StateBlock,
    column: StateBlock,
    value: &Matrix3<f64>,
) {
    matrix
        .fixed_view_mut::<3, 3>(row.index, column.index)
        .copy_from(value);
}

/// Writes block (`R`, `C`) and its mirror (`C`, `R`) = valueᵀ of a symmetric matrix; a
/// diagonal block is made symmetric from its upper triangle.
fn set_symmetric<const R: usize, const C: usize>(
    matrix: &mut CovarianceMatrix,
    value: &Matrix3<f64>,
) {
    if R == C {
        let mut mirrored = *value;
        mirrored.fill_lower_triangle_with_upper_triangle();
        matrix.fixed_view_mut::<3, 3>(R, C).copy_from(&mirrored);
    } else {
        matrix.fixed_view_mut::<3, 3>(R, C).copy_from(value);
        matrix.fixed_view_mut::<3, 3>(C, R).tr_copy_from(value);
    }
}

/// `U_B + U_S diag(scale)`: a scale-factor column block `S` of `U` folded into its bias
/// column block `B`.
fn fold<const B: usize, const S: usize>(
    u: &DynamicRows,
    scale: &Vector3<f64>,
) -> SMatrix<f64, DYNAMIC_DIMENSION, 3> {
    let mut folded = u.fixed_columns::<3>(S).into_owned();
    for (mut column, factor) in folded.column_iter_mut().zip(scale.iter()) {
        column *= *factor;
    }
    folded + u.fixed_columns::<3>(B)
}

/// The 9×24 block rows (ϑ, δp, δv) of a 24-column matrix.
type DynamicRows = SMatrix<f64, DYNAMIC_DIMENSION, 24>;
/// Number of calibration states (the rows of `F` equal to the identity).
const CALIBRATION_DIMENSION: usize = 15;

/// The discrete model of one interval in block form (module docs): the non-zero blocks of
/// `F` and the non-zero upper-left 15×15 part of `Qd`. Equal to
/// [`crate::discretise::discretise`] of `system_matrix`/`noise_input_matrix` at the same
/// point (proven by the tests within relative 1e-12).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StructuredModel {
    /// `Φ`: the (ϑ, δp, δv) × (ϑ, δp, δv) part of `F`.
    transition: DynamicBlocks,
    /// `E_g = −½Δ Ψ_{·ϑ}`: the gyro-bias column of `F`, rows ϑ, δp, δv.
    gyro_bias_column: [Matrix3<f64>; 3],
    /// `E_a = −Δ Ψ_{·v} Ĉ`: the accelerometer-bias column of `F`, rows δp, δv (row ϑ is 0).
    accel_bias_column: [Matrix3<f64>; 2],
    /// `ω_m`: the gyro scale-factor column of `F` is `E_g diag(ω_m)` (rad/s).
    measured_rate_rad_s: Vector3<f64>,
    /// `f_m`: the accelerometer scale-factor column is `E_a diag(f_m)` (m/s²).
    measured_specific_force_mps2: Vector3<f64>,
    /// `Qd` restricted to the noise-driven states 1-15 (zero elsewhere), symmetric.
    process_noise: SMatrix<f64, NOISE_DRIVEN_DIMENSION, NOISE_DRIVEN_DIMENSION>,
    /// Whether any bias random walk is non-zero (`Qd` reaches the bias rows).
    bias_walk: bool,
}

impl StructuredModel {
    /// Discretises the error model at `point` over `interval_s` with a series of `order`
    /// terms (as [`crate::discretise::discretise`], module docs for the block derivation).
    ///
    /// # Errors
    /// [`NavError::InvalidDiscretisationOrder`] for an order outside `1..=4`,
    /// [`NavError::InvalidTimeStep`] for a non-positive or non-finite interval,
    /// [`NavError::NonFiniteInput`] if the point or the noise densities hold NaN/Inf.
    pub fn new(
        point: &LinearisationPoint,
        noise: &ProcessNoise,
        interval_s: f64,
        order: u8,
    ) -> Result<Self, NavError> {
        if !(1..=MAX_ORDER).contains(&order) {
            return Err(NavError::InvalidDiscretisationOrder);
        }
        if !(interval_s.is_finite() && interval_s > 0.0) {
            return Err(NavError::InvalidTimeStep);
        }
        let densities = noise.spectral_density_diagonal();
        let all_finite = point.corrected_rate_rad_s.iter().all(|v| v.is_finite())
            && point
                .corrected_specific_force_mps2
                .iter()
                .all(|v| v.is_finite())
            && point.measured_rate_rad_s.iter().all(|v| v.is_finite())
            && point
                .measured_specific_force_mps2
                .iter()
                .all(|v| v.is_finite())
            && point.body_to_inertial.iter().all(|v| v.is_finite())
            && point.gravity_gradient_per_s2.iter().all(|v| v.is_finite())
            && densities.iter().all(|v| v.is_finite());
        if !all_finite {
            return Err(NavError::NonFiniteInput);
        }
        let powers = DynamicBlocks::powers(point, interval_s, order);
        // Φ += P_n/n! (n ≤ N), Ψ += P_n/(n+1)! (n+1 ≤ N), Χ += P_n/(n+2)! (n+2 ≤ N).
        let mut transition = DynamicBlocks::zeros();
        let mut psi = DynamicBlocks::zeros();
        let mut chi = DynamicBlocks::zeros();
        let order = usize::from(order);
        for (n, power) in powers.iter().enumerate() {
            let coefficient = |shift: usize| {
                if n + shift <= order {
                    INVERSE_FACTORIALS.get(n + shift).copied()
                } else {
                    None
                }
            };
            if let Some(c) = coefficient(0) {
                transition.add_scaled(power, c);
            }
            if let Some(c) = coefficient(1) {
                psi.add_scaled(power, c);
            }
            if let Some(c) = coefficient(2) {
                chi.add_scaled(power, c);
            }
        }
        let c = &point.body_to_inertial;
        let half_interval = 0.5 * interval_s;
        let gyro_bias_column = [
            psi.attitude_attitude * -half_interval,
            psi.position_attitude * -half_interval,
            psi.velocity_attitude * -half_interval,
        ];
        let accel_bias_column = [
            psi.position_velocity * c * -interval_s,
            psi.velocity_velocity * c * -interval_s,
        ];

        // Qd = Σ_k (q_k/Δ) Γ_k Γ_kᵀ (module docs) over the noise-driven states 1-15; each
        // Γ_k Γ_kᵀ is symmetric bit for bit (element (i, j) and (j, i) are the same sum).
        let density =
            |block: StateBlock| densities.get(block.index).copied().unwrap_or(0.0) / interval_s;
        let gyro_noise = density(crate::error_model::NOISE_GYRO);
        let accel_noise = density(crate::error_model::NOISE_ACCEL);
        let gyro_walk = density(crate::error_model::NOISE_GYRO_BIAS_WALK);
        let accel_walk = density(crate::error_model::NOISE_ACCEL_BIAS_WALK);
        let squared = interval_s * interval_s;
        let mut process_noise =
            SMatrix::<f64, NOISE_DRIVEN_DIMENSION, NOISE_DRIVEN_DIMENSION>::zeros();
        if gyro_noise > 0.0 {
            // Γ = E_g (rows ϑ, δp, δv).
            let mut gamma = SMatrix::<f64, DYNAMIC_DIMENSION, 3>::zeros();
            let [attitude, position, velocity] = &gyro_bias_column;
            gamma
                .fixed_rows_mut::<3>(ATTITUDE.index)
                .copy_from(attitude);
            gamma
                .fixed_rows_mut::<3>(POSITION.index)
                .copy_from(position);
            gamma
                .fixed_rows_mut::<3>(VELOCITY.index)
                .copy_from(velocity);
            let mut target =
                process_noise.fixed_view_mut::<DYNAMIC_DIMENSION, DYNAMIC_DIMENSION>(0, 0);
            target += gamma * gamma.transpose() * gyro_noise;
        }
        if accel_noise > 0.0 {
            // Γ = E_a (rows δp, δv; row ϑ is zero).
            let mut gamma = SMatrix::<f64, 6, 3>::zeros();
            let [position, velocity] = &accel_bias_column;
            gamma.fixed_rows_mut::<3>(0).copy_from(position);
            gamma.fixed_rows_mut::<3>(3).copy_from(velocity);
            let mut target = process_noise.fixed_view_mut::<6, 6>(POSITION.index, POSITION.index);
            target += gamma * gamma.transpose() * accel_noise;
        }
        if gyro_walk > 0.0 {
            // Γ = [−½Δ² Χ_{·ϑ}; ΔI] (rows ϑ, δp, δv, gyro bias).
            let mut gamma = SMatrix::<f64, NOISE_DRIVEN_DIMENSION, 3>::zeros();
            let factor = -0.5 * squared;
            gamma
                .fixed_rows_mut::<3>(ATTITUDE.index)
                .copy_from(&(chi.attitude_attitude * factor));
            gamma
                .fixed_rows_mut::<3>(POSITION.index)
                .copy_from(&(chi.position_attitude * factor));
            gamma
                .fixed_rows_mut::<3>(VELOCITY.index)
                .copy_from(&(chi.velocity_attitude * factor));
            gamma
                .fixed_rows_mut::<3>(GYRO_BIAS.index)
                .copy_from(&(Matrix3::identity() * interval_s));
            process_noise += gamma * gamma.transpose() * gyro_walk;
        }
        if accel_walk > 0.0 {
            // Γ = [−Δ² Χ_{·v} Ĉ; ΔI] (rows δp, δv, accelerometer bias; row ϑ is zero).
            let mut gamma = SMatrix::<f64, NOISE_DRIVEN_DIMENSION, 3>::zeros();
            gamma
                .fixed_rows_mut::<3>(POSITION.index)
                .copy_from(&(chi.position_velocity * c * -squared));
            gamma
                .fixed_rows_mut::<3>(VELOCITY.index)
                .copy_from(&(chi.velocity_velocity * c * -squared));
            gamma
                .fixed_rows_mut::<3>(ACCEL_BIAS.index)
                .copy_from(&(Matrix3::identity() * interval_s));
            process_noise += gamma * gamma.transpose() * accel_walk;
        }
        let [accel_position, accel_velocity] = accel_bias_column;
        Ok(Self {
            transition,
            gyro_bias_column,
            accel_bias_column: [accel_position, accel_velocity],
            measured_rate_rad_s: point.measured_rate_rad_s,
            measured_specific_force_mps2: point.measured_specific_force_mps2,
            process_noise,
            bias_walk: gyro_walk > 0.0 || accel_walk > 0.0,
        })
    }

    /// Removes the process noise of the `blocks` (their rows and columns of `Qd` set to zero),
    /// as the flight scheduler does for frozen calibration blocks.
    pub fn remove_process_noise(&mut self, blocks: &BlockMask) {
        if blocks.is_empty() {
            return;
        }
        // Column-major storage: element k is (k mod 15, k div 15).
        for (element, value) in self.process_noise.iter_mut().enumerate() {
            let (row, column) = (
                element % NOISE_DRIVEN_DIMENSION,
                element / NOISE_DRIVEN_DIMENSION,
            );
            if blocks.contains_state(row) || blocks.contains_state(column) {
                *value = 0.0;
            }
        }
    }

    /// The dense 24×24 `F` (for tests and reports; the flight path never forms it).
    pub fn transition_matrix(&self) -> CovarianceMatrix {
        let mut f = CovarianceMatrix::identity();
        let t = &self.transition;
        set(&mut f, ATTITUDE, ATTITUDE, &t.attitude_attitude);
        set(&mut f, POSITION, ATTITUDE, &t.position_attitude);
        set(&mut f, POSITION, POSITION, &t.position_position);
        set(&mut f, POSITION, VELOCITY, &t.position_velocity);
        set(&mut f, VELOCITY, ATTITUDE, &t.velocity_attitude);
        set(&mut f, VELOCITY, POSITION, &t.velocity_position);
        set(&mut f, VELOCITY, VELOCITY, &t.velocity_velocity);
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        let rate = &self.measured_rate_rad_s;
        let force = &self.measured_specific_force_mps2;
        for (row, gyro) in [
            (ATTITUDE, gyro_attitude),
            (POSITION, gyro_position),
            (VELOCITY, gyro_velocity),
        ] {
            set(&mut f, row, GYRO_BIAS, gyro);
            set(&mut f, row, GYRO_SCALE_FACTOR, &scale_columns(gyro, rate));
        }
        for (row, accel) in [(POSITION, accel_position), (VELOCITY, accel_velocity)] {
            set(&mut f, row, ACCEL_BIAS, accel);
            set(
                &mut f,
                row,
                ACCEL_SCALE_FACTOR,
                &scale_columns(accel, force),
            );
        }
        f
    }

    /// The dense 24×24 `Qd` (for tests and reports).
    pub fn process_noise_matrix(&self) -> CovarianceMatrix {
        let mut q = CovarianceMatrix::zeros();
        q.fixed_view_mut::<NOISE_DRIVEN_DIMENSION, NOISE_DRIVEN_DIMENSION>(0, 0)
            .copy_from(&self.process_noise);
        q
    }

    /// `x_d ← Φ x_d + E_g (x_bg + diag(ω_m) x_λg) + E_a (x_ba + diag(f_m) x_λa)`; the
    /// calibration states are unchanged (open-loop state propagation `x ← F x`).
    pub(crate) fn propagate_state(&self, state: &SMatrix<f64, 24, 1>) -> SMatrix<f64, 24, 1> {
        let part = |b: StateBlock| block_of(state, b);
        let gyro =
            part(GYRO_BIAS) + part(GYRO_SCALE_FACTOR).component_mul(&self.measured_rate_rad_s);
        let accel = part(ACCEL_BIAS)
            + part(ACCEL_SCALE_FACTOR).component_mul(&self.measured_specific_force_mps2);
        let t = &self.transition;
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        let (attitude, position, velocity) = (part(ATTITUDE), part(POSITION), part(VELOCITY));
        let mut propagated = *state;
        propagated
            .fixed_rows_mut::<3>(ATTITUDE.index)
            .copy_from(&(t.attitude_attitude * attitude + gyro_attitude * gyro));
        propagated.fixed_rows_mut::<3>(POSITION.index).copy_from(
            &(t.position_attitude * attitude
                + t.position_position * position
                + t.position_velocity * velocity
                + gyro_position * gyro
                + accel_position * accel),
        );
        propagated.fixed_rows_mut::<3>(VELOCITY.index).copy_from(
            &(t.velocity_attitude * attitude
                + t.velocity_position * position
                + t.velocity_velocity * velocity
                + gyro_velocity * gyro
                + accel_velocity * accel),
        );
        propagated
    }

    /// Column block `C` of `U = [Φ E] P` (rows ϑ, δp, δv), scale factors folded into the
    /// biases (module docs). Block indices are compile-time constants: no bounds check, no
    /// panic path.
    fn propagate_column<const C: usize>(&self, p: &CovarianceMatrix, u: &mut DynamicRows) {
        let t = &self.transition;
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        let attitude = p.fixed_view::<3, 3>(ATTITUDE.index, C).into_owned();
        let position = p.fixed_view::<3, 3>(POSITION.index, C).into_owned();
        let velocity = p.fixed_view::<3, 3>(VELOCITY.index, C).into_owned();
        let gyro = p.fixed_view::<3, 3>(GYRO_BIAS.index, C)
            + scale_rows(
                &p.fixed_view::<3, 3>(GYRO_SCALE_FACTOR.index, C)
                    .into_owned(),
                &self.measured_rate_rad_s,
            );
        let accel = p.fixed_view::<3, 3>(ACCEL_BIAS.index, C)
            + scale_rows(
                &p.fixed_view::<3, 3>(ACCEL_SCALE_FACTOR.index, C)
                    .into_owned(),
                &self.measured_specific_force_mps2,
            );
        u.fixed_view_mut::<3, 3>(ATTITUDE.index, C)
            .copy_from(&(t.attitude_attitude * attitude + gyro_attitude * gyro));
        u.fixed_view_mut::<3, 3>(POSITION.index, C).copy_from(
            &(t.position_attitude * attitude
                + t.position_position * position
                + t.position_velocity * velocity
                + gyro_position * gyro
                + accel_position * accel),
        );
        u.fixed_view_mut::<3, 3>(VELOCITY.index, C).copy_from(
            &(t.velocity_attitude * attitude
                + t.velocity_position * position
                + t.velocity_velocity * velocity
                + gyro_velocity * gyro
                + accel_velocity * accel),
        );
    }

    /// Block (`R`, `S`), `R ≤ S` dynamic, of the new `P_dd = U [Φ E]ᵀ + Qd_dd`; `folded` is
    /// `U`'s calibration columns folded to (gyro, accelerometer) (9×6).
    fn propagate_dynamic_pair<const R: usize, const S: usize>(
        &self,
        u: &DynamicRows,
        folded: &SMatrix<f64, DYNAMIC_DIMENSION, 6>,
        updated: &mut CovarianceMatrix,
    ) {
        let t = &self.transition;
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        let u_attitude = u.fixed_view::<3, 3>(R, ATTITUDE.index);
        let u_gyro = folded.fixed_view::<3, 3>(R, 0);
        let value = if S == ATTITUDE.index {
            u_attitude * t.attitude_attitude.transpose() + u_gyro * gyro_attitude.transpose()
        } else {
            let (f_attitude, f_position, f_velocity, e_gyro, e_accel) = if S == POSITION.index {
                (
                    &t.position_attitude,
                    &t.position_position,
                    &t.position_velocity,
                    gyro_position,
                    accel_position,
                )
            } else {
                (
                    &t.velocity_attitude,
                    &t.velocity_position,
                    &t.velocity_velocity,
                    gyro_velocity,
                    accel_velocity,
                )
            };
            u_attitude * f_attitude.transpose()
                + u.fixed_view::<3, 3>(R, POSITION.index) * f_position.transpose()
                + u.fixed_view::<3, 3>(R, VELOCITY.index) * f_velocity.transpose()
                + u_gyro * e_gyro.transpose()
                + folded.fixed_view::<3, 3>(R, 3) * e_accel.transpose()
        };
        let value = value + self.process_noise.fixed_view::<3, 3>(R, S);
        set_symmetric::<R, S>(updated, &value);
    }

    /// `F P Fᵀ + Qd` by blocks (module docs), or `None` if the result is not finite.
    pub(crate) fn propagate_covariance(&self, p: &CovarianceMatrix) -> Option<CovarianceMatrix> {
        // U = [Φ E] P, rows ϑ, δp, δv (9×24), one column block at a time.
        let mut u = DynamicRows::zeros();
        self.propagate_column::<{ ATTITUDE.index }>(p, &mut u);
        self.propagate_column::<{ POSITION.index }>(p, &mut u);
        self.propagate_column::<{ VELOCITY.index }>(p, &mut u);
        self.propagate_column::<{ GYRO_BIAS.index }>(p, &mut u);
        self.propagate_column::<{ ACCEL_BIAS.index }>(p, &mut u);
        self.propagate_column::<{ STAR_INSTALLATION.index }>(p, &mut u);
        self.propagate_column::<{ GYRO_SCALE_FACTOR.index }>(p, &mut u);
        self.propagate_column::<{ ACCEL_SCALE_FACTOR.index }>(p, &mut u);
        // U's calibration columns folded: U_bg + U_λg diag(ω_m), U_ba + U_λa diag(f_m).
        let mut folded = SMatrix::<f64, DYNAMIC_DIMENSION, 6>::zeros();
        folded.fixed_columns_mut::<3>(0).copy_from(&fold::<
            { GYRO_BIAS.index },
            { GYRO_SCALE_FACTOR.index },
        >(&u, &self.measured_rate_rad_s));
        folded.fixed_columns_mut::<3>(3).copy_from(&fold::<
            { ACCEL_BIAS.index },
            { ACCEL_SCALE_FACTOR.index },
        >(
            &u, &self.measured_specific_force_mps2
        ));
        // New P_dd: upper blocks, mirrored.
        let mut updated = *p;
        self.propagate_dynamic_pair::<{ ATTITUDE.index }, { ATTITUDE.index }>(
            &u,
            &folded,
            &mut updated,
        );
        self.propagate_dynamic_pair::<{ ATTITUDE.index }, { POSITION.index }>(
            &u,
            &folded,
            &mut updated,
        );
        self.propagate_dynamic_pair::<{ ATTITUDE.index }, { VELOCITY.index }>(
            &u,
            &folded,
            &mut updated,
        );
        self.propagate_dynamic_pair::<{ POSITION.index }, { POSITION.index }>(
            &u,
            &folded,
            &mut updated,
        );
        self.propagate_dynamic_pair::<{ POSITION.index }, { VELOCITY.index }>(
            &u,
            &folded,
            &mut updated,
        );
        self.propagate_dynamic_pair::<{ VELOCITY.index }, { VELOCITY.index }>(
            &u,
            &folded,
            &mut updated,
        );
        // New P_dc = U's calibration columns, mirrored into P_cd.
        let calibration = u.fixed_columns::<CALIBRATION_DIMENSION>(DYNAMIC_DIMENSION);
        updated
            .fixed_view_mut::<DYNAMIC_DIMENSION, CALIBRATION_DIMENSION>(0, DYNAMIC_DIMENSION)
            .copy_from(&calibration);
        updated
            .fixed_view_mut::<CALIBRATION_DIMENSION, DYNAMIC_DIMENSION>(DYNAMIC_DIMENSION, 0)
            .tr_copy_from(&calibration);
        if self.bias_walk {
            // Qd outside P_dd: dynamic × bias and bias × bias blocks (symmetric).
            let mut noise = self.process_noise;
            noise
                .fixed_view_mut::<DYNAMIC_DIMENSION, DYNAMIC_DIMENSION>(0, 0)
                .fill(0.0);
            let mut top_left =
                updated.fixed_view_mut::<NOISE_DRIVEN_DIMENSION, NOISE_DRIVEN_DIMENSION>(0, 0);
            top_left += noise;
        }
        let finite = updated
            .fixed_rows::<DYNAMIC_DIMENSION>(0)
            .iter()
            .all(|v| v.is_finite())
            && (!self.bias_walk || updated.iter().all(|v| v.is_finite()));
        finite.then_some(updated)
    }
}

/// `product += H_K P_{K,·}` for the block `K` of `H` if it is not all zero (`K` a
/// compile-time constant: no bounds check, no panic path).
fn add_observed_block<const K: usize>(
    jacobian: &SMatrix<f64, 3, 24>,
    p: &CovarianceMatrix,
    product: &mut SMatrix<f64, 3, 24>,
) {
    let h = jacobian.fixed_columns::<3>(K);
    if h.iter().any(|v| *v != 0.0) {
        *product += h * p.fixed_rows::<3>(K);
    }
}

/// `H P` (3×24, = `Mᵀ`) summed over the non-zero 3×3 blocks of `H` only.
pub(crate) fn jacobian_times_covariance(
    jacobian: &SMatrix<f64, 3, 24>,
    p: &CovarianceMatrix,
) -> SMatrix<f64, 3, 24> {
    let mut product = SMatrix::<f64, 3, 24>::zeros();
    add_observed_block::<{ ATTITUDE.index }>(jacobian, p, &mut product);
    add_observed_block::<{ POSITION.index }>(jacobian, p, &mut product);
    add_observed_block::<{ VELOCITY.index }>(jacobian, p, &mut product);
    add_observed_block::<{ GYRO_BIAS.index }>(jacobian, p, &mut product);
    add_observed_block::<{ ACCEL_BIAS.index }>(jacobian, p, &mut product);
    add_observed_block::<{ STAR_INSTALLATION.index }>(jacobian, p, &mut product);
    add_observed_block::<{ GYRO_SCALE_FACTOR.index }>(jacobian, p, &mut product);
    add_observed_block::<{ ACCEL_SCALE_FACTOR.index }>(jacobian, p, &mut product);
    product
}

/// Joseph form expanded (module docs): `P⁺_ij = P_ij − K_i·M_j + (K_i S − M_i)·K_j` on the
/// upper triangle, mirrored; `gain_t = Kᵀ`, `hp = H P = Mᵀ`, `s` symmetric. `None` if not
/// finite.
pub(crate) fn joseph_update(
    p: &CovarianceMatrix,
    gain_t: &SMatrix<f64, 3, 24>,
    hp: &SMatrix<f64, 3, 24>,
    s: &Matrix3<f64>,
) -> Option<CovarianceMatrix> {
    let excess_t = s * gain_t - hp;
    let mut updated = *p;
    let mut finite = true;
    for (column_number, ((mut column, k_j), m_j)) in updated
        .column_iter_mut()
        .zip(gain_t.column_iter())
        .zip(hp.column_iter())
        .enumerate()
    {
        for (value, (k_i, n_i)) in column
            .iter_mut()
            .zip(gain_t.column_iter().zip(excess_t.column_iter()))
            .take(column_number + 1)
        {
            *value += n_i.dot(&k_j) - k_i.dot(&m_j);
            finite &= value.is_finite();
        }
    }
    updated.fill_lower_triangle_with_upper_triangle();
    finite.then_some(updated)
}

/// Block (`R`, `C`) of `J P Jᵀ` with `J_R = left` and `J_C = right` (`None`: identity).
fn reset_pair<const R: usize, const C: usize>(
    p: &CovarianceMatrix,
    updated: &mut CovarianceMatrix,
    left: Option<&Matrix3<f64>>,
    right: Option<&Matrix3<f64>>,
) {
    let block = p.fixed_view::<3, 3>(R, C);
    let value = match (left, right) {
        (Some(l), Some(r)) => l * block * r.transpose(),
        (Some(l), None) => l * block,
        (None, Some(r)) => block * r.transpose(),
        (None, None) => block.into_owned(),
    };
    set_symmetric::<R, C>(updated, &value);
}

/// `J P Jᵀ` for the reset Jacobian `J` = identity except `J_ϑϑ = I − [ϑ̂×]` and
/// `J_ψψ = I − [ψ̂×]`: only the attitude and installation block rows and columns change
/// (upper blocks computed, mirrored).
pub(crate) fn reset_covariance(
    p: &CovarianceMatrix,
    attitude: &Matrix3<f64>,
    installation: &Matrix3<f64>,
) -> CovarianceMatrix {
    const A: usize = ATTITUDE.index;
    const I: usize = STAR_INSTALLATION.index;
    let mut u = *p;
    let (a, i) = (Some(attitude), Some(installation));
    reset_pair::<A, A>(p, &mut u, a, a);
    reset_pair::<A, { POSITION.index }>(p, &mut u, a, None);
    reset_pair::<A, { VELOCITY.index }>(p, &mut u, a, None);
    reset_pair::<A, { GYRO_BIAS.index }>(p, &mut u, a, None);
    reset_pair::<A, { ACCEL_BIAS.index }>(p, &mut u, a, None);
    reset_pair::<A, I>(p, &mut u, a, i);
    reset_pair::<A, { GYRO_SCALE_FACTOR.index }>(p, &mut u, a, None);
    reset_pair::<A, { ACCEL_SCALE_FACTOR.index }>(p, &mut u, a, None);
    reset_pair::<{ POSITION.index }, I>(p, &mut u, None, i);
    reset_pair::<{ VELOCITY.index }, I>(p, &mut u, None, i);
    reset_pair::<{ GYRO_BIAS.index }, I>(p, &mut u, None, i);
    reset_pair::<{ ACCEL_BIAS.index }, I>(p, &mut u, None, i);
    reset_pair::<I, I>(p, &mut u, i, i);
    reset_pair::<I, { GYRO_SCALE_FACTOR.index }>(p, &mut u, i, None);
    reset_pair::<I, { ACCEL_SCALE_FACTOR.index }>(p, &mut u, i, None);
    u
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::{exp_rotation_vector, rotation_matrix};
    use crate::discretise::discretise;
    use crate::error_model::{noise_input_matrix, system_matrix};
    use crate::filter::{
        ErrorState, ErrorStateFilter, FilterConfig, FilterMode, InitialUncertainty,
    };
    use crate::measurement::{gnss_position, refer_to_later_time, star_sensor, LinearMeasurement};
    use crate::state::BLOCKS;

    /// The 3×3 block (`row`, `column`) of a matrix.
    fn block<const R: usize, const C: usize>(
        matrix: &SMatrix<f64, R, C>,
        row: StateBlock,
        column: StateBlock,
    ) -> Matrix3<f64> {
        matrix
            .fixed_view::<3, 3>(row.index, column.index)
            .into_owned()
    }

    use nalgebra::Quaternion;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Largest element-wise difference of two covariances in correlation units,
    /// `max |A_ij − B_ij| / √(B_ii B_jj)` (a zero-variance pair must match exactly).
    fn relative_difference(a: &CovarianceMatrix, b: &CovarianceMatrix) -> f64 {
        relative_to(a, b, b)
    }

    /// `max |A_ij − B_ij| / √(S_ii S_jj)`: the difference in units of the scale `S`.
    fn relative_to(a: &CovarianceMatrix, b: &CovarianceMatrix, scale: &CovarianceMatrix) -> f64 {
        let b_scale = scale;
        let mut worst = 0.0f64;
        for i in 0..24 {
            for j in 0..24 {
                let scale = (b_scale[(i, i)] * b_scale[(j, j)]).sqrt();
                let difference = (a[(i, j)] - b[(i, j)]).abs();
                let relative = if scale > 0.0 {
                    difference / scale
                } else if difference > 0.0 {
                    f64::INFINITY
                } else {
                    0.0
                };
                worst = worst.max(relative);
            }
        }
        worst
    }

    /// Largest difference of two error states in units of the 1σ of `p`.
    fn state_difference(a: &ErrorState, b: &ErrorState, p: &CovarianceMatrix) -> f64 {
        (0..24)
            .map(|i| (a[i] - b[i]).abs() / p[(i, i)].sqrt())
            .fold(0.0, f64::max)
    }

    fn random_vector(rng: &mut ChaCha8Rng, largest_norm: f64) -> Vector3<f64> {
        let direction = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        direction.normalize() * rng.random_range(0.0..largest_norm)
    }

    /// Physical 1σ scale of each block (attitude rad, m, m/s, rad/s, m/s², rad, -, -).
    const BLOCK_SCALES: [f64; 8] = [1e-3, 30.0, 0.3, 5e-4, 5e-3, 2e-3, 1e-4, 1e-4];

    /// A random symmetric positive-definite P with physical block scales and strong
    /// correlations: `D (B Bᵀ/24 + 0.05 I) D`.
    fn random_covariance(rng: &mut ChaCha8Rng) -> CovarianceMatrix {
        let b = CovarianceMatrix::from_fn(|_, _| rng.random_range(-1.0..1.0));
        let d = CovarianceMatrix::from_diagonal(&SMatrix::<f64, 24, 1>::from_fn(|i, _| {
            BLOCK_SCALES[i / 3] * rng.random_range(0.5..2.0)
        }));
        let p = d * (b * b.transpose() / 24.0 + CovarianceMatrix::identity() * 0.05) * d;
        (p + p.transpose()) * 0.5
    }

    fn random_state(rng: &mut ChaCha8Rng) -> ErrorState {
        ErrorState::from_fn(|i, _| BLOCK_SCALES[i / 3] * rng.random_range(-1.0..1.0))
    }

    /// Random motion: rates up to 2 rad/s, specific forces up to 50 m/s², random attitude,
    /// point-mass gravity gradient at a random position 6,400-7,000 km from the centre.
    fn random_point(rng: &mut ChaCha8Rng) -> LinearisationPoint {
        let rate = random_vector(rng, 2.0);
        let force = random_vector(rng, 50.0);
        let radius = rng.random_range(6.4e6..7.0e6);
        let position = random_vector(rng, 1.0).normalize() * radius;
        LinearisationPoint {
            corrected_rate_rad_s: rate,
            corrected_specific_force_mps2: force,
            measured_rate_rad_s: rate + random_vector(rng, 1e-3),
            measured_specific_force_mps2: force + random_vector(rng, 1e-2),
            body_to_inertial: rotation_matrix(&exp_rotation_vector(&random_vector(rng, 3.1))),
            gravity_gradient_per_s2: crate::error_model::tests::point_mass_gradient(&position),
        }
    }

    fn random_noise(rng: &mut ChaCha8Rng, with_bias_walk: bool) -> ProcessNoise {
        let walk = if with_bias_walk { 1.0 } else { 0.0 };
        ProcessNoise {
            gyro_noise_density_rad_s_per_sqrt_hz: rng.random_range(1e-7..1e-5),
            accel_noise_density_mps2_per_sqrt_hz: rng.random_range(1e-5..1e-3),
            gyro_bias_walk_rad_s2_per_sqrt_hz: walk * rng.random_range(1e-9..1e-7),
            accel_bias_walk_mps3_per_sqrt_hz: walk * rng.random_range(1e-7..1e-5),
        }
    }

    fn random_mask(rng: &mut ChaCha8Rng) -> BlockMask {
        let mut mask = BlockMask::NONE;
        for block in BLOCKS {
            if rng.random_bool(0.3) {
                mask.insert(block);
            }
        }
        mask
    }

    fn filter_with(mode: FilterMode, p: &CovarianceMatrix) -> ErrorStateFilter {
        let mut filter = ErrorStateFilter::new(&FilterConfig {
            mode,
            discretisation_order: 3,
            initial: InitialUncertainty {
                attitude_rad: 1.0,
                position_m: 1.0,
                velocity_mps: 1.0,
                gyro_bias_rad_s: 1.0,
                accel_bias_mps2: 1.0,
                star_installation_rad: 1.0,
                gyro_scale_factor: 1.0,
                accel_scale_factor: 1.0,
            },
        })
        .unwrap();
        filter.set_covariance(p).unwrap();
        filter
    }

    /// Dense reference `F`, `Qd` with the frozen blocks' noise removed as the scheduler does.
    fn dense_model(
        point: &LinearisationPoint,
        noise: &ProcessNoise,
        interval_s: f64,
        order: u8,
        frozen: &BlockMask,
    ) -> crate::discretise::DiscreteModel {
        let mut model = discretise(
            &system_matrix(point),
            &noise_input_matrix(point),
            &noise.spectral_density_diagonal(),
            interval_s,
            order,
        )
        .unwrap();
        for block in BLOCKS {
            if frozen.contains(block) {
                model
                    .process_noise
                    .fixed_rows_mut::<3>(block.index)
                    .fill(0.0);
                model
                    .process_noise
                    .fixed_columns_mut::<3>(block.index)
                    .fill(0.0);
            }
        }
        model
    }

    #[test]
    fn structured_model_blocks_equal_the_dense_series_for_every_order() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for order in 1..=MAX_ORDER {
            for case in 0..100 {
                let point = random_point(&mut rng);
                let noise = random_noise(&mut rng, case % 2 == 0);
                let interval_s = [0.002, 0.02, 0.1][case % 3];
                let dense = dense_model(&point, &noise, interval_s, order, &BlockMask::NONE);
                let model = StructuredModel::new(&point, &noise, interval_s, order).unwrap();
                let f = model.transition_matrix();
                let q = model.process_noise_matrix();
                for row in BLOCKS {
                    for column in BLOCKS {
                        for (structured, reference, name) in [
                            (&f, &dense.transition, "F"),
                            (&q, &dense.process_noise, "Qd"),
                        ] {
                            let s = block(structured, row, column);
                            let r = block(reference, row, column);
                            let bound = 1e-12 * r.amax();
                            assert!(
                                (s - r).amax() <= bound,
                                "order {order} case {case} {name}[{}, {}]: {:e} vs {:e}",
                                row.name,
                                column.name,
                                (s - r).amax(),
                                r.amax()
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn structured_propagation_equals_the_dense_reference_for_every_order() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut worst = [0.0f64; 4];
        for order in 1..=MAX_ORDER {
            for case in 0..200 {
                let point = random_point(&mut rng);
                let noise = random_noise(&mut rng, case % 2 == 1);
                let interval_s = [0.002, 0.004, 0.02, 0.1][case % 4];
                let frozen = if case % 3 == 0 {
                    random_mask(&mut rng)
                } else {
                    BlockMask::NONE
                };
                let p = random_covariance(&mut rng);
                let dense_model = dense_model(&point, &noise, interval_s, order, &frozen);
                let mut model = StructuredModel::new(&point, &noise, interval_s, order).unwrap();
                model.remove_process_noise(&frozen);
                let mut dense = filter_with(FilterMode::ClosedLoop, &p);
                let mut structured = dense;
                dense.predict(&dense_model).unwrap();
                structured.predict_structured(&model).unwrap();
                let p_dense = dense.covariance();
                let p_structured = structured.covariance();
                assert_eq!(
                    p_structured,
                    &p_structured.transpose(),
                    "symmetric by construction"
                );
                let difference = relative_difference(p_structured, p_dense);
                let slot = &mut worst[usize::from(order - 1)];
                *slot = slot.max(difference);
                assert!(
                    difference <= 1e-12,
                    "order {order} case {case}: {difference:e}"
                );
                // The untouched calibration block is bit-identical.
                assert_eq!(
                    p_structured.fixed_view::<15, 15>(9, 9),
                    p.fixed_view::<15, 15>(9, 9).map(|v| v)
                        + model.process_noise_matrix().fixed_view::<15, 15>(9, 9),
                );
                // Open loop: x ← F x.
                let x = random_state(&mut rng);
                let structured_x = model.propagate_state(&x);
                let dense_x = dense_model.transition * x;
                let state_error = state_difference(&structured_x, &dense_x, p_dense);
                assert!(
                    state_error <= 1e-12,
                    "order {order} case {case}: x {state_error:e}"
                );
            }
        }
        println!(
            "largest |structured − dense| / √(P_ii P_jj) per order 1..4: {:.2e} {:.2e} {:.2e} {:.2e}",
            worst[0], worst[1], worst[2], worst[3]
        );
    }

    fn random_quaternion(rng: &mut ChaCha8Rng, largest_angle_rad: f64) -> Quaternion<f64> {
        exp_rotation_vector(&random_vector(rng, largest_angle_rad))
    }

    /// A star (`star = true`) or GNSS measurement at a random geometry, optionally referred
    /// to a later time with `H (I − AΔ)` (extra bias, scale-factor and velocity columns).
    fn random_measurement(rng: &mut ChaCha8Rng, star: bool, referred: bool) -> LinearMeasurement {
        let attitude = random_quaternion(rng, 3.1);
        let measurement = if star {
            let mounting = random_quaternion(rng, 3.1);
            let installation = random_quaternion(rng, 5e-3);
            let offset = random_quaternion(rng, 1e-3);
            let measured = crate::attitude::product(
                &crate::attitude::product(&attitude, &offset),
                &crate::attitude::product(&mounting, &installation),
            );
            star_sensor(
                &attitude,
                &mounting,
                &installation,
                &measured,
                10.0 / 206_264.8,
            )
            .unwrap()
        } else {
            let position = random_vector(rng, 7e6);
            let lever_arm = random_vector(rng, 3.0);
            let fix = position
                + crate::attitude::rotate(&attitude, &lever_arm)
                + random_vector(rng, 50.0);
            gnss_position(
                &attitude,
                &position,
                &lever_arm,
                &fix,
                rng.random_range(0.1..10.0),
            )
            .unwrap()
        };
        if referred {
            let point = random_point(rng);
            refer_to_later_time(
                &measurement,
                &system_matrix(&point),
                rng.random_range(0.0..0.1),
            )
            .unwrap()
        } else {
            measurement
        }
    }

    #[test]
    fn structured_update_equals_the_dense_joseph_update() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut worst_covariance = 0.0f64;
        let mut worst_posterior = 0.0f64;
        let mut worst_state = 0.0f64;
        for case in 0..400 {
            let star = case % 2 == 0;
            let referred = case % 4 >= 2;
            let mut prior = filter_with(FilterMode::OpenLoop, &random_covariance(&mut rng));
            // A non-zero open-loop state, from an earlier (dense) update.
            let earlier = random_measurement(&mut rng, !star, false);
            prior.update(&earlier, f64::INFINITY).unwrap();
            let frozen = if case % 3 == 0 {
                random_mask(&mut rng)
            } else {
                BlockMask::NONE
            };
            let measurement = random_measurement(&mut rng, star, referred);
            let mut dense = prior;
            let mut structured = prior;
            let dense_report = dense
                .update_with_frozen_blocks(&measurement, f64::INFINITY, &frozen)
                .unwrap();
            let structured_report = structured
                .update_structured(&measurement, f64::INFINITY, &frozen)
                .unwrap();
            assert!(dense_report.accepted && structured_report.accepted);
            let nis = dense_report.normalised_innovation_squared;
            assert!(
                (structured_report.normalised_innovation_squared - nis).abs() <= 1e-12 * nis,
                "case {case}: NIS"
            );
            let p = structured.covariance();
            assert_eq!(p, &p.transpose(), "symmetric by construction");
            // Both updates compute P⁺ = P⁻ − (…) and carry a rounding error of order ε·P⁻,
            // so the difference is measured in units of the prior; in units of a posterior
            // collapsed by a precise measurement it would measure the measurement's
            // conditioning, not the implementation (printed for information).
            let covariance_error = relative_to(p, dense.covariance(), prior.covariance());
            worst_posterior = worst_posterior.max(relative_difference(p, dense.covariance()));
            let state_error =
                state_difference(structured.state(), dense.state(), prior.covariance());
            worst_covariance = worst_covariance.max(covariance_error);
            worst_state = worst_state.max(state_error);
            assert!(
                covariance_error <= 1e-12,
                "case {case}: P {covariance_error:e}"
            );
            assert!(state_error <= 1e-12, "case {case}: x {state_error:e}");
            // Frozen blocks: the estimate does not move (bit for bit), as in the dense update.
            for block in BLOCKS {
                if frozen.contains(block) {
                    assert_eq!(
                        structured.block(block),
                        prior.block(block),
                        "{}",
                        block.name
                    );
                }
            }
        }
        println!(
            "structured vs dense update: P {worst_covariance:.2e} (prior correlation units; \
             {worst_posterior:.2e} in posterior units), x {worst_state:.2e} prior σ"
        );
    }

    #[test]
    fn a_gated_structured_update_leaves_the_filter_bit_identical() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut filter = filter_with(FilterMode::OpenLoop, &random_covariance(&mut rng));
        let measurement = random_measurement(&mut rng, false, true);
        let before = filter;
        let report = filter
            .update_structured(&measurement, 1e-12, &BlockMask::NONE)
            .unwrap();
        assert!(!report.accepted);
        assert!(report.normalised_innovation_squared > 1e-12);
        assert_eq!(filter, before);
        let mut nan = measurement;
        nan.residual.x = f64::NAN;
        assert_eq!(
            filter.update_structured(&nan, f64::INFINITY, &BlockMask::NONE),
            Err(NavError::NonFiniteInput)
        );
        assert_eq!(
            filter.update_structured(&measurement, f64::NAN, &BlockMask::NONE),
            Err(NavError::NonFiniteInput)
        );
        assert_eq!(filter, before);
    }

    #[test]
    fn structured_reset_equals_the_dense_reset() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        for case in 0..100 {
            let mut filter = filter_with(FilterMode::ClosedLoop, &random_covariance(&mut rng));
            filter
                .update(
                    &random_measurement(&mut rng, case % 2 == 0, false),
                    f64::INFINITY,
                )
                .unwrap();
            let mut dense = filter;
            let error = filter.reset();
            assert_eq!(error, dense.reset_dense());
            assert_eq!(filter.state(), dense.state());
            let p = filter.covariance();
            assert_eq!(p, &p.transpose());
            let difference = relative_difference(p, dense.covariance());
            assert!(difference <= 1e-12, "case {case}: {difference:e}");
        }
    }
}
