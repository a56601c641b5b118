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
//! The white gyro and accelerometer noise enter `Qd` as `q_g E_g E_gᵀ + q_a E_a E_aᵀ`
//! (their `Γ` columns are `E_g`, `E_a`); they are folded into the same sum rather than
//! formed: `P_dd` gets `(U_{d,bg} + q_g E_g) E_gᵀ`, which is `U_{d,bg} E_gᵀ + q_g E_g E_gᵀ`
//! (`U_{d,bg}` folded with the scale factor as above), likewise for the accelerometer. Only
//! the bias random walks' `Qd` is formed block by block.
//!
//! ## Update
//! For any gain `K` the Joseph form expands exactly (Bucy & Joseph 1968) to
//! `(I − KH) P (I − KH)ᵀ + K R Kᵀ = P − K Mᵀ − M Kᵀ + K S Kᵀ` with `M = P Hᵀ`,
//! `S = H P Hᵀ + R`; element-wise `P⁺_ij = (P_ij + (K_i S − M_i)·K_j) − K_i·M_j`, O(n²)
//! with 6 multiply-adds per element of the upper triangle. `M` is summed only over the non-zero
//! 3×3 blocks of `H` (found at run time, so a measurement referred to a later time with
//! `H (I − AΔ)` is handled with its extra bias/scale-factor/velocity columns).
//!
//! ## In place, without a copy
//! Propagation and update overwrite `P` where it lies (a 24×24 copy costs thousands of
//! instructions on the target). They write new values to the upper triangle only, so while
//! they run the lower triangle (and a saved diagonal) still holds the old `P`: it is read
//! where an old value is needed after its upper twin was overwritten, and it is the
//! roll-back copy if the result is not finite; on success the upper triangle is mirrored
//! into the lower. The arithmetic is done on plain 3×3 arrays (`crate::block`).
//!
//! ## Reset
//! The reset Jacobian is the identity except the attitude and installation diagonal blocks,
//! so only the block rows and columns of those two blocks change.

use nalgebra::{Matrix3, SMatrix, Vector3};

use crate::block::{
    self, add, add_scaled, add_scaled_columns, dot, mul, mul_add, mul_transpose, mul_transpose_add,
    mul_vector_add, read, row_add, row_scale, scale, scale_columns, transpose, write,
    write_diagonal_symmetric, write_symmetric, Block, FiniteCheck, Row, IDENTITY, ZERO,
};
use crate::discretise::{CovarianceMatrix, MAX_ORDER};
use crate::error_model::{LinearisationPoint, ProcessNoise};
use crate::measurement::{LinearMeasurement, MeasurementJacobian};
use crate::state::{
    BlockMask, StateBlock, ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, GYRO_BIAS, GYRO_SCALE_FACTOR,
    POSITION, STAR_INSTALLATION, STATE_DIMENSION, VELOCITY,
};
use crate::NavError;

#[cfg(any(test, not(target_arch = "arm")))]
mod rows;

/// Number of states the process noise can reach: attitude, position, velocity, gyro bias and
/// accelerometer bias (states 1-15; the installation error and scale factors have none).
pub const NOISE_DRIVEN_DIMENSION: usize = 15;

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

// Block offsets as constants (const generic arguments).
const A: usize = ATTITUDE.index;
const P: usize = POSITION.index;
const V: usize = VELOCITY.index;
const BG: usize = GYRO_BIAS.index;
const BA: usize = ACCEL_BIAS.index;
const PSI: usize = STAR_INSTALLATION.index;
const SG: usize = GYRO_SCALE_FACTOR.index;
const SA: usize = ACCEL_SCALE_FACTOR.index;

/// The seven 3×3 blocks over (ϑ, δp, δv) that a power of `MΔ` (and so `Φ`, `Ψ`, `Χ`) can
/// have non-zero (module docs table); ϑp and ϑv are always zero.
#[derive(Debug, Clone, Copy, PartialEq)]
struct DynamicBlocks {
    attitude_attitude: Block,
    position_attitude: Block,
    position_position: Block,
    position_velocity: Block,
    velocity_attitude: Block,
    velocity_position: Block,
    velocity_velocity: Block,
}

/// `out = factor · Σ_n T_n / (n + shift)!` over the terms `(n, T_n)` with
/// `n + shift ≤ order` (an absent power is simply not listed). A diagonal first term
/// (`DIAGONAL_FIRST`: the identity, or `ΔI`) adds only its scaled diagonal (the same
/// products, without the zero off-diagonal ones). Inlined at each call, so the term
/// array, the shift and the diagonal flag fold into constants (a called function builds
/// the arrays of `(n, &T_n)` in memory at every call, about 400 instructions per rebuild
/// on the target).
#[inline(always)]
fn series_into<const N: usize, const DIAGONAL_FIRST: bool>(
    out: &mut Block,
    terms: &[(usize, &Block); N],
    order: usize,
    shift: usize,
    factor: f64,
) {
    let mut sum = ZERO;
    for (index, (n, term)) in terms.iter().enumerate() {
        if n + shift <= order {
            if let Some(coefficient) = INVERSE_FACTORIALS.get(n + shift) {
                let scale = factor * coefficient;
                if DIAGONAL_FIRST && index == 0 {
                    for (i, (row, term_row)) in sum.iter_mut().zip(term.iter()).enumerate() {
                        if let (Some(value), Some(diagonal)) = (row.get_mut(i), term_row.get(i)) {
                            *value += diagonal * scale;
                        }
                    }
                } else {
                    sum = add_scaled(&sum, term, scale);
                }
            }
        }
    }
    *out = sum;
}

/// The non-zero blocks of the powers `(MΔ)^n`, `n ≤ order` (module docs table; the
/// powers the order does not reach are not computed, and the series never read them).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Powers {
    /// `MΔ`'s blocks: `a = WΔ`, `b = VΔ`, `g = NΔ` (and `d I`).
    a: Block,
    b: Block,
    g: Block,
    d_identity: Block,
    /// Table rows 2-4.
    a2: Block,
    a3: Block,
    a4: Block,
    d_b: Block,
    d_ba: Block,
    position_attitude_4: Block,
    dg: Block,
    d2_g2: Block,
    d2_g: Block,
    ba: Block,
    velocity_attitude_3: Block,
    velocity_attitude_4: Block,
    velocity_position_3: Block,
}

impl Powers {
    /// All blocks zero.
    const ZERO: Self = Powers {
        a: ZERO,
        b: ZERO,
        g: ZERO,
        d_identity: ZERO,
        a2: ZERO,
        a3: ZERO,
        a4: ZERO,
        d_b: ZERO,
        d_ba: ZERO,
        position_attitude_4: ZERO,
        dg: ZERO,
        d2_g2: ZERO,
        d2_g: ZERO,
        ba: ZERO,
        velocity_attitude_3: ZERO,
        velocity_attitude_4: ZERO,
        velocity_position_3: ZERO,
    };

    /// The powers at `point` over `d = Δ` (module docs: `a = WΔ`, `b = VΔ`, `g = NΔ`), in
    /// place: every block the order reaches is overwritten (a new struct, zero-filled and
    /// moved, cost ~900 instructions more on the target).
    #[inline(never)]
    fn update(&mut self, point: &LinearisationPoint, c: &Block, d: f64, order: usize) {
        let rate = block::from_vector(&point.corrected_rate_rad_s);
        let force = block::from_vector(&point.corrected_specific_force_mps2);
        self.a = block::skew(row_scale(rate, -d));
        self.b = scale(&mul(c, &block::skew(force)), -2.0 * d);
        self.g = scale(&block::from_matrix(&point.gravity_gradient_per_s2), d);
        self.d_identity = scale(&IDENTITY, d);
        self.d_b = scale(&self.b, d);
        self.dg = scale(&self.g, d);
        // The blocks beyond the order are left as they are: the series never read them
        // (`series_into` takes a term only if its power is within the order).
        if order >= 2 {
            self.a2 = mul(&self.a, &self.a);
            self.ba = mul(&self.b, &self.a);
        }
        if order >= 3 {
            let gb = mul(&self.g, &self.b);
            let ba2 = mul(&self.ba, &self.a);
            self.a3 = mul(&self.a2, &self.a);
            self.d_ba = scale(&self.ba, d);
            self.d2_g = scale(&self.dg, d);
            self.velocity_attitude_3 = add_scaled(&ba2, &gb, d);
            let g2 = mul(&self.g, &self.g);
            self.velocity_position_3 = scale(&g2, d);
            if order >= 4 {
                self.a4 = mul(&self.a2, &self.a2);
                self.position_attitude_4 = add_scaled(&scale(&ba2, d), &gb, d * d);
                self.d2_g2 = scale(&g2, d * d);
                self.velocity_attitude_4 =
                    add_scaled(&mul(&ba2, &self.a), &mul(&self.g, &self.ba), d);
            }
        }
    }
}

/// The non-zero blocks of `Qd` (upper block triangle; the diagonal blocks symmetric).
#[derive(Debug, Clone, Copy, PartialEq)]
struct NoiseBlocks {
    /// Over (ϑ, δp, δv): pairs ϑϑ, ϑp, ϑv, pp, pv, vv.
    dynamic: [Block; 6],
    /// Rows ϑ, δp, δv of the gyro-bias column (gyro-bias walk).
    dynamic_gyro_bias: [Block; 3],
    /// Rows ϑ (zero), δp, δv of the accelerometer-bias column (accelerometer-bias walk).
    dynamic_accel_bias: [Block; 3],
    /// Gyro bias × gyro bias.
    gyro_bias: Block,
    /// Accelerometer bias × accelerometer bias.
    accel_bias: Block,
}

/// The pairs of [`NoiseBlocks::dynamic`], in order.
const DYNAMIC_PAIRS: [(StateBlock, StateBlock); 6] = [
    (ATTITUDE, ATTITUDE),
    (ATTITUDE, POSITION),
    (ATTITUDE, VELOCITY),
    (POSITION, POSITION),
    (POSITION, VELOCITY),
    (VELOCITY, VELOCITY),
];
/// The row blocks of [`NoiseBlocks::dynamic_gyro_bias`] and `dynamic_accel_bias`.
const DYNAMIC_ROWS: [StateBlock; 3] = [ATTITUDE, POSITION, VELOCITY];

/// `dynamic = q Γ Γᵀ` (`ACCUMULATE` false: written, so the blocks need no zero fill first)
/// or `dynamic += q Γ Γᵀ` over the pairs of [`DYNAMIC_PAIRS`] for an input column
/// `Γ = [Γ_ϑ; Γ_p; Γ_v]`: `q Γ_R Γ_Sᵀ`, with `q` folded into the left factor.
fn noise_input<const ACCUMULATE: bool>(dynamic: &mut [Block; 6], q: f64, gamma: &[Block; 3]) {
    let [ga, gp, gv] = gamma;
    let scaled = [scale(ga, q), scale(gp, q), scale(gv, q)];
    let [qa, qp, qv] = &scaled;
    let products = [(qa, ga), (qa, gp), (qa, gv), (qp, gp), (qp, gv), (qv, gv)];
    for (slot, (left, right)) in dynamic.iter_mut().zip(products) {
        *slot = if ACCUMULATE {
            mul_transpose_add(slot, left, right)
        } else {
            mul_transpose(left, right)
        };
    }
}

/// `dynamic += q Γ Γᵀ` for an input with a zero attitude row, `Γ = [0; Γ_p; Γ_v]`: only
/// the pairs pp, pv, vv are reached.
fn add_accel_noise_input(dynamic: &mut [Block; 6], q: f64, gamma: &[Block; 2]) {
    let [gp, gv] = gamma;
    let qp = scale(gp, q);
    let [_, _, _, pp, pv, vv] = dynamic;
    *pp = mul_transpose_add(pp, &qp, gp);
    *pv = mul_transpose_add(pv, &qp, gv);
    *vv = mul_transpose_add(vv, &scale(gv, q), gv);
}

impl NoiseBlocks {
    /// Sets the dynamic and gyro-bias blocks to `q Γ Γᵀ` (module docs) of the gyro-bias
    /// walk, `q` = `q_k/Δ`, for its noise column `Γ = [Γ_ϑ; Γ_p; Γ_v; ΔI]` given by its
    /// dynamic rows `columns` (the first of the two walks: it writes, the other adds).
    fn set_gyro_walk(&mut self, q: f64, interval_s: f64, columns: &[Block; 3]) {
        noise_input::<false>(&mut self.dynamic, q, columns);
        // Γ_bias = ΔI: (X, bg) = q Γ_X Δ, (bg, bg) = q Δ² I.
        for (slot, gamma) in self.dynamic_gyro_bias.iter_mut().zip(columns) {
            *slot = scale(gamma, q * interval_s);
        }
        self.gyro_bias = scale(&IDENTITY, q * interval_s * interval_s);
    }

    /// No gyro-bias walk: the blocks [`NoiseBlocks::set_gyro_walk`] writes, zero.
    fn clear_gyro_walk(&mut self) {
        self.dynamic = [ZERO; 6];
        self.dynamic_gyro_bias = [ZERO; 3];
        self.gyro_bias = ZERO;
    }

    /// [`NoiseBlocks::set_gyro_walk`] for the accelerometer-bias walk, whose column has a
    /// zero attitude row: `columns` are its rows δp, δv. Adds to the dynamic blocks (after
    /// the gyro walk's), writes its own bias blocks.
    fn add_accel_walk(&mut self, q: f64, interval_s: f64, columns: &[Block; 2]) {
        add_accel_noise_input(&mut self.dynamic, q, columns);
        let [attitude, position, velocity] = &mut self.dynamic_accel_bias;
        let [walk_position, walk_velocity] = columns;
        *attitude = ZERO;
        *position = scale(walk_position, q * interval_s);
        *velocity = scale(walk_velocity, q * interval_s);
        self.accel_bias = scale(&IDENTITY, q * interval_s * interval_s);
    }

    /// No accelerometer-bias walk: its own bias blocks zero.
    fn clear_accel_walk(&mut self) {
        self.dynamic_accel_bias = [ZERO; 3];
        self.accel_bias = ZERO;
    }

    /// No noise.
    const ZERO: Self = NoiseBlocks {
        dynamic: [ZERO; 6],
        dynamic_gyro_bias: [ZERO; 3],
        dynamic_accel_bias: [ZERO; 3],
        gyro_bias: ZERO,
        accel_bias: ZERO,
    };

    /// Every block with its (row, column) state blocks.
    fn blocks_mut(&mut self) -> impl Iterator<Item = (StateBlock, StateBlock, &mut Block)> {
        let dynamic = self
            .dynamic
            .iter_mut()
            .zip(DYNAMIC_PAIRS)
            .map(|(block, (row, column))| (row, column, block));
        let gyro = self
            .dynamic_gyro_bias
            .iter_mut()
            .zip(DYNAMIC_ROWS)
            .map(|(block, row)| (row, GYRO_BIAS, block));
        let accel = self
            .dynamic_accel_bias
            .iter_mut()
            .zip(DYNAMIC_ROWS)
            .map(|(block, row)| (row, ACCEL_BIAS, block));
        dynamic.chain(gyro).chain(accel).chain([
            (GYRO_BIAS, GYRO_BIAS, &mut self.gyro_bias),
            (ACCEL_BIAS, ACCEL_BIAS, &mut self.accel_bias),
        ])
    }
}

/// The discrete model of one interval in block form (module docs): the non-zero blocks of
/// `F` and of `Qd`. Equal to [`crate::discretise::discretise`] of
/// `system_matrix`/`noise_input_matrix` at the same point (proven by the tests within
/// relative 1e-12).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StructuredModel {
    /// `Φ`: the (ϑ, δp, δv) × (ϑ, δp, δv) part of `F`.
    transition: DynamicBlocks,
    /// `E_g = −½Δ Ψ_{·ϑ}`: the gyro-bias column of `F`, rows ϑ, δp, δv.
    gyro_bias_column: [Block; 3],
    /// `E_a = −Δ Ψ_{·v} Ĉ`: the accelerometer-bias column of `F`, rows δp, δv (row ϑ is 0).
    accel_bias_column: [Block; 2],
    /// `ω_m`: the gyro scale-factor column of `F` is `E_g diag(ω_m)` (rad/s).
    measured_rate_rad_s: Row,
    /// `f_m`: the accelerometer scale-factor column is `E_a diag(f_m)` (m/s²).
    measured_specific_force_mps2: Row,
    /// `q_g/Δ` and `q_a/Δ` of the white gyro and accelerometer noise: their part of `Qd`,
    /// `q E_g E_gᵀ + q E_a E_aᵀ` (the noise columns of `Γ` are `E_g`, `E_a`), is folded into
    /// the propagation ([`StructuredModel::propagate_covariance`]).
    input_noise: [f64; 2],
    /// The non-zero blocks of the rest of `Qd` (the bias random walks).
    noise: NoiseBlocks,
    /// Whether any bias random walk is non-zero (`Qd` reaches the bias rows).
    bias_walk: bool,
    /// Whether every block of [`StructuredModel::noise`] is zero (no walk, nothing
    /// unfolded): the rebuild then skips refilling them and the propagation adding them.
    noise_is_zero: bool,
    /// Scratch for [`StructuredModel::rebuild`]: the powers of `MΔ` (kept in the model so
    /// they are computed in place).
    powers: Powers,
    /// The interval `Δ` (s) the model discretises.
    interval_s: f64,
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
        let mut model = Self::EMPTY;
        model.rebuild(point, noise, interval_s, order)?;
        Ok(model)
    }

    /// A model with every block zero (no propagation), to be filled by
    /// [`StructuredModel::rebuild`].
    pub const EMPTY: Self = StructuredModel {
        transition: DynamicBlocks {
            attitude_attitude: ZERO,
            position_attitude: ZERO,
            position_position: ZERO,
            position_velocity: ZERO,
            velocity_attitude: ZERO,
            velocity_position: ZERO,
            velocity_velocity: ZERO,
        },
        gyro_bias_column: [ZERO; 3],
        accel_bias_column: [ZERO; 2],
        measured_rate_rad_s: [0.0; 3],
        measured_specific_force_mps2: [0.0; 3],
        input_noise: [0.0; 2],
        noise: NoiseBlocks::ZERO,
        bias_walk: false,
        noise_is_zero: true,
        powers: Powers::ZERO,
        interval_s: 0.0,
    };

    /// [`StructuredModel::new`] in place (the flight path keeps one model and refills it
    /// every propagation: no copy of the ~2 KB model). On error the model is unchanged.
    ///
    /// # Errors
    /// As [`StructuredModel::new`].
    pub fn rebuild(
        &mut self,
        point: &LinearisationPoint,
        noise: &ProcessNoise,
        interval_s: f64,
        order: u8,
    ) -> Result<(), NavError> {
        if !(1..=MAX_ORDER).contains(&order) {
            return Err(NavError::InvalidDiscretisationOrder);
        }
        if !(interval_s.is_finite() && interval_s > 0.0) {
            return Err(NavError::InvalidTimeStep);
        }
        let mut check = FiniteCheck::new();
        for vector in [
            &point.corrected_rate_rad_s,
            &point.corrected_specific_force_mps2,
            &point.measured_rate_rad_s,
            &point.measured_specific_force_mps2,
        ] {
            for value in block::from_vector(vector) {
                check.value(value);
            }
        }
        check.block(&block::from_matrix(&point.body_to_inertial));
        check.block(&block::from_matrix(&point.gravity_gradient_per_s2));
        let density = |value: f64| value * value / interval_s;
        let gyro_noise = density(noise.gyro_noise_density_rad_s_per_sqrt_hz);
        let accel_noise = density(noise.accel_noise_density_mps2_per_sqrt_hz);
        let gyro_walk = density(noise.gyro_bias_walk_rad_s2_per_sqrt_hz);
        let accel_walk = density(noise.accel_bias_walk_mps3_per_sqrt_hz);
        for value in [gyro_noise, accel_noise, gyro_walk, accel_walk] {
            check.value(value);
        }
        if !check.all_finite() {
            return Err(NavError::NonFiniteInput);
        }
        let order = usize::from(order);
        let d = interval_s;
        self.interval_s = interval_s;
        let c = block::from_matrix(&point.body_to_inertial);
        self.powers.update(point, &c, d, order);
        let w = &self.powers;
        let attitude_attitude: [(usize, &Block); 5] = [
            (0, &IDENTITY),
            (1, &w.a),
            (2, &w.a2),
            (3, &w.a3),
            (4, &w.a4),
        ];
        let position_attitude: [(usize, &Block); 3] =
            [(2, &w.d_b), (3, &w.d_ba), (4, &w.position_attitude_4)];
        let position_position: [(usize, &Block); 3] = [(0, &IDENTITY), (2, &w.dg), (4, &w.d2_g2)];
        let position_velocity: [(usize, &Block); 2] = [(1, &w.d_identity), (3, &w.d2_g)];
        let velocity_attitude: [(usize, &Block); 4] = [
            (1, &w.b),
            (2, &w.ba),
            (3, &w.velocity_attitude_3),
            (4, &w.velocity_attitude_4),
        ];
        let velocity_position: [(usize, &Block); 2] = [(1, &w.g), (3, &w.velocity_position_3)];
        let velocity_velocity = position_position;
        // Φ = Σ (MΔ)^n/n!.
        let t = &mut self.transition;
        series_into::<_, true>(&mut t.attitude_attitude, &attitude_attitude, order, 0, 1.0);
        series_into::<_, false>(&mut t.position_attitude, &position_attitude, order, 0, 1.0);
        series_into::<_, true>(&mut t.position_position, &position_position, order, 0, 1.0);
        series_into::<_, true>(&mut t.position_velocity, &position_velocity, order, 0, 1.0);
        series_into::<_, false>(&mut t.velocity_attitude, &velocity_attitude, order, 0, 1.0);
        series_into::<_, false>(&mut t.velocity_position, &velocity_position, order, 0, 1.0);
        series_into::<_, true>(&mut t.velocity_velocity, &velocity_velocity, order, 0, 1.0);
        // E_g = −½Δ Ψ_{·ϑ}, E_a = −Δ Ψ_{·v} Ĉ (Ψ: shift 1).
        let [gyro_a, gyro_p, gyro_v] = &mut self.gyro_bias_column;
        series_into::<_, true>(gyro_a, &attitude_attitude, order, 1, -0.5 * d);
        series_into::<_, false>(gyro_p, &position_attitude, order, 1, -0.5 * d);
        series_into::<_, false>(gyro_v, &velocity_attitude, order, 1, -0.5 * d);
        let mut psi = ZERO;
        let [accel_p, accel_v] = &mut self.accel_bias_column;
        series_into::<_, true>(&mut psi, &position_velocity, order, 1, -d);
        *accel_p = mul(&psi, &c);
        series_into::<_, true>(&mut psi, &velocity_velocity, order, 1, -d);
        *accel_v = mul(&psi, &c);
        self.measured_rate_rad_s = block::from_vector(&point.measured_rate_rad_s);
        self.measured_specific_force_mps2 = block::from_vector(&point.measured_specific_force_mps2);
        self.input_noise = [gyro_noise, accel_noise];
        // The walks' noise columns of Γ (module docs): [−½Δ² Χ_{·ϑ}; ΔI] and
        // [−Δ² Χ_{·v} Ĉ; ΔI] (Χ: shift 2).
        // Every noise block written once (no zero fill of the 1 kB first): the gyro walk
        // sets the dynamic blocks (or zeroes them), the accelerometer walk adds to them.
        // Without any walk the blocks are zeroed only if something made them non-zero.
        let noise = &mut self.noise;
        let squared = d * d;
        if gyro_walk > 0.0 || accel_walk > 0.0 {
            if gyro_walk > 0.0 {
                let mut columns = [ZERO; 3];
                let [walk_a, walk_p, walk_v] = &mut columns;
                series_into::<_, true>(walk_a, &attitude_attitude, order, 2, -0.5 * squared);
                series_into::<_, false>(walk_p, &position_attitude, order, 2, -0.5 * squared);
                series_into::<_, false>(walk_v, &velocity_attitude, order, 2, -0.5 * squared);
                noise.set_gyro_walk(gyro_walk, d, &columns);
            } else {
                noise.clear_gyro_walk();
            }
            if accel_walk > 0.0 {
                let mut columns = [ZERO; 2];
                let [walk_p, walk_v] = &mut columns;
                series_into::<_, true>(&mut psi, &position_velocity, order, 2, -squared);
                *walk_p = mul(&psi, &c);
                series_into::<_, true>(&mut psi, &velocity_velocity, order, 2, -squared);
                *walk_v = mul(&psi, &c);
                noise.add_accel_walk(accel_walk, d, &columns);
            } else {
                noise.clear_accel_walk();
            }
            self.noise_is_zero = false;
        } else if !self.noise_is_zero {
            *noise = NoiseBlocks::ZERO;
            self.noise_is_zero = true;
        }
        self.bias_walk = gyro_walk > 0.0 || accel_walk > 0.0;
        Ok(())
    }

    /// Adds the folded white-noise part of `Qd` (`q E_g E_gᵀ + q E_a E_aᵀ`, see
    /// [`StructuredModel::input_noise`]) to the explicit blocks, and clears the folded
    /// intensities: the model is unchanged, only its noise is held in the blocks.
    fn unfold_input_noise(&mut self) {
        let [gyro_noise, accel_noise] = self.input_noise;
        if gyro_noise > 0.0 || accel_noise > 0.0 {
            self.noise_is_zero = false;
        }
        if gyro_noise > 0.0 {
            noise_input::<true>(&mut self.noise.dynamic, gyro_noise, &self.gyro_bias_column);
        }
        if accel_noise > 0.0 {
            add_accel_noise_input(
                &mut self.noise.dynamic,
                accel_noise,
                &self.accel_bias_column,
            );
        }
        self.input_noise = [0.0; 2];
    }

    /// Removes the process noise of the `blocks` (their rows and columns of `Qd` set to zero),
    /// as the flight scheduler does for frozen calibration blocks.
    pub fn remove_process_noise(&mut self, blocks: &BlockMask) {
        if blocks.is_empty() {
            return;
        }
        if DYNAMIC_ROWS.iter().any(|block| blocks.contains(*block)) {
            // The folded white noise reaches every dynamic row: hold it in the blocks.
            self.unfold_input_noise();
        }
        for (row, column, value) in self.noise.blocks_mut() {
            if blocks.contains(row) || blocks.contains(column) {
                *value = ZERO;
            }
        }
    }

    /// The dense 24×24 `F` (for tests and reports; the flight path never forms it).
    pub fn transition_matrix(&self) -> CovarianceMatrix {
        let mut f = CovarianceMatrix::identity();
        let t = &self.transition;
        write::<A, A>(&mut f, &t.attitude_attitude);
        write::<P, A>(&mut f, &t.position_attitude);
        write::<P, P>(&mut f, &t.position_position);
        write::<P, V>(&mut f, &t.position_velocity);
        write::<V, A>(&mut f, &t.velocity_attitude);
        write::<V, P>(&mut f, &t.velocity_position);
        write::<V, V>(&mut f, &t.velocity_velocity);
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        let rate = self.measured_rate_rad_s;
        let force = self.measured_specific_force_mps2;
        write::<A, BG>(&mut f, gyro_attitude);
        write::<P, BG>(&mut f, gyro_position);
        write::<V, BG>(&mut f, gyro_velocity);
        write::<A, SG>(&mut f, &scale_columns(gyro_attitude, rate));
        write::<P, SG>(&mut f, &scale_columns(gyro_position, rate));
        write::<V, SG>(&mut f, &scale_columns(gyro_velocity, rate));
        write::<P, BA>(&mut f, accel_position);
        write::<V, BA>(&mut f, accel_velocity);
        write::<P, SA>(&mut f, &scale_columns(accel_position, force));
        write::<V, SA>(&mut f, &scale_columns(accel_velocity, force));
        f
    }

    /// The dense 24×24 `Qd` (for tests and reports).
    pub fn process_noise_matrix(&self) -> CovarianceMatrix {
        let mut q = CovarianceMatrix::zeros();
        let mut unfolded = *self;
        unfolded.unfold_input_noise();
        let n = &unfolded.noise;
        let [aa, ap, av, pp, pv, vv] = &n.dynamic;
        write_diagonal_symmetric::<A>(&mut q, aa);
        write_symmetric::<A, P>(&mut q, ap);
        write_symmetric::<A, V>(&mut q, av);
        write_diagonal_symmetric::<P>(&mut q, pp);
        write_symmetric::<P, V>(&mut q, pv);
        write_diagonal_symmetric::<V>(&mut q, vv);
        let [ga, gp, gv] = &n.dynamic_gyro_bias;
        write_symmetric::<A, BG>(&mut q, ga);
        write_symmetric::<P, BG>(&mut q, gp);
        write_symmetric::<V, BG>(&mut q, gv);
        let [ba_attitude, ba_position, ba_velocity] = &n.dynamic_accel_bias;
        write_symmetric::<A, BA>(&mut q, ba_attitude);
        write_symmetric::<P, BA>(&mut q, ba_position);
        write_symmetric::<V, BA>(&mut q, ba_velocity);
        write_diagonal_symmetric::<BG>(&mut q, &n.gyro_bias);
        write_diagonal_symmetric::<BA>(&mut q, &n.accel_bias);
        q
    }

    /// The interval `Δ` (s) the model discretises (0 for [`StructuredModel::EMPTY`]).
    pub fn interval_s(&self) -> f64 {
        self.interval_s
    }

    /// `x_d ← Φ x_d + E_g (x_bg + diag(ω_m) x_λg) + E_a (x_ba + diag(f_m) x_λa)`; the
    /// calibration states are unchanged (open-loop state propagation `x ← F x`).
    pub(crate) fn propagate_state(&self, state: &SMatrix<f64, 24, 1>) -> SMatrix<f64, 24, 1> {
        let part =
            |index: usize| [0, 1, 2].map(|i| state.get(index + i).copied().unwrap_or(f64::NAN));
        let multiply = |x: Row, scale: Row| {
            let ([x0, x1, x2], [s0, s1, s2]) = (x, scale);
            [x0 * s0, x1 * s1, x2 * s2]
        };
        let gyro = row_add(part(BG), multiply(part(SG), self.measured_rate_rad_s));
        let accel = row_add(
            part(BA),
            multiply(part(SA), self.measured_specific_force_mps2),
        );
        let t = &self.transition;
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        let (attitude, position, velocity) = (part(A), part(P), part(V));
        let zero = [0.0; 3];
        let new_attitude = mul_vector_add(
            mul_vector_add(zero, &t.attitude_attitude, attitude),
            gyro_attitude,
            gyro,
        );
        let new_position = [
            (&t.position_attitude, attitude),
            (&t.position_position, position),
            (&t.position_velocity, velocity),
            (gyro_position, gyro),
            (accel_position, accel),
        ]
        .iter()
        .fold(zero, |sum, (m, x)| mul_vector_add(sum, m, *x));
        let new_velocity = [
            (&t.velocity_attitude, attitude),
            (&t.velocity_position, position),
            (&t.velocity_velocity, velocity),
            (gyro_velocity, gyro),
            (accel_velocity, accel),
        ]
        .iter()
        .fold(zero, |sum, (m, x)| mul_vector_add(sum, m, *x));
        let mut propagated = *state;
        for (offset, values) in [(A, new_attitude), (P, new_position), (V, new_velocity)] {
            for (i, value) in values.iter().enumerate() {
                if let Some(slot) = propagated.get_mut(offset + i) {
                    *slot = *value;
                }
            }
        }
        propagated
    }

    /// Rows (ϑ, δp, δv) of `F C` for a 24×3 matrix `C` given by its rows (the calibration
    /// rows of `F C` are those of `C`): `Φ C_d + E_g (C_bg + diag(ω_m) C_λg) + E_a (C_ba +
    /// diag(f_m) C_λa)`, [`StructuredModel::propagate_state`] for three columns at once, by
    /// blocks (the correlated-error border's cross-covariance, [`crate::gnss_error`]).
    pub(crate) fn propagate_rows(&self, rows: &StateRows) -> [Block; 3] {
        let block = |offset: usize| -> Block {
            [0, 1, 2].map(|i| rows.get(offset + i).copied().unwrap_or([f64::NAN; 3]))
        };
        let gyro = block::add_scaled_rows(&block(BG), &block(SG), self.measured_rate_rad_s);
        let accel =
            block::add_scaled_rows(&block(BA), &block(SA), self.measured_specific_force_mps2);
        let (attitude, position, velocity) = (block(A), block(P), block(V));
        let t = &self.transition;
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        let new_attitude = mul_add(&mul(&t.attitude_attitude, &attitude), gyro_attitude, &gyro);
        let new_position = [
            (&t.position_position, &position),
            (&t.position_velocity, &velocity),
            (gyro_position, &gyro),
            (accel_position, &accel),
        ]
        .iter()
        .fold(mul(&t.position_attitude, &attitude), |sum, (m, x)| {
            mul_add(&sum, m, x)
        });
        let new_velocity = [
            (&t.velocity_position, &position),
            (&t.velocity_velocity, &velocity),
            (gyro_velocity, &gyro),
            (accel_velocity, &accel),
        ]
        .iter()
        .fold(mul(&t.velocity_attitude, &attitude), |sum, (m, x)| {
            mul_add(&sum, m, x)
        });
        [new_attitude, new_position, new_velocity]
    }

    /// Rows (ϑ, δp, δv) of `U = [Φ E] P` in one column block, given as its three columns of
    /// `P`; scale factors folded into the biases (module docs). Not inlined: one compact
    /// body called per column block keeps the working set in the registers and the
    /// addresses within load offsets on the target.
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(never)]
    fn propagate_column(&self, columns: [&[f64; 24]; 3]) -> [Block; 3] {
        use crate::block::add_scaled_rows;
        let rows = |offset: usize| -> Block {
            [0, 1, 2].map(|i| columns.map(|c| c.get(offset + i).copied().unwrap_or(f64::NAN)))
        };
        let attitude = rows(A);
        let position = rows(P);
        let velocity = rows(V);
        let gyro = add_scaled_rows(&rows(BG), &rows(SG), self.measured_rate_rad_s);
        let accel = add_scaled_rows(&rows(BA), &rows(SA), self.measured_specific_force_mps2);
        let t = &self.transition;
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        let sum = |terms: [(&Block, &Block); 5]| {
            let [(f0, x0), rest @ ..] = terms;
            rest.iter()
                .fold(mul(f0, x0), |acc, (f, x)| mul_add(&acc, f, x))
        };
        [
            mul_add(&mul(&t.attitude_attitude, &attitude), gyro_attitude, &gyro),
            sum([
                (&t.position_attitude, &attitude),
                (&t.position_position, &position),
                (&t.position_velocity, &velocity),
                (gyro_position, &gyro),
                (accel_position, &accel),
            ]),
            sum([
                (&t.velocity_attitude, &attitude),
                (&t.velocity_position, &position),
                (&t.velocity_velocity, &velocity),
                (gyro_velocity, &gyro),
                (accel_velocity, &accel),
            ]),
        ]
    }

    /// Block (`R`, `S`), `S` = δp or δv, of the new `P_dd = U_d [Φ E]_Sᵀ` (without the
    /// walks' `Qd`): `row` is `(U_Rϑ, U_Rp, U_Rv)`, `folded` row `R` of `U`'s folded
    /// calibration columns (with the white noise folded in), `transition` row `S` of `Φ` and
    /// `bias_columns` row `S` of `E_g`, `E_a` (multiplied transposed: `X Yᵀ`).
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(never)]
    fn dynamic_pair(
        row: [&Block; 3],
        folded: [&Block; 2],
        transition: [&Block; 3],
        bias_columns: [&Block; 2],
    ) -> Block {
        let [u_attitude, u_position, u_velocity] = row;
        let [f_attitude, f_position, f_velocity] = transition;
        let [gyro, accel] = folded;
        let [e_gyro, e_accel] = bias_columns;
        let mut value = mul_transpose(u_attitude, f_attitude);
        value = mul_transpose_add(&value, u_position, f_position);
        value = mul_transpose_add(&value, u_velocity, f_velocity);
        value = mul_transpose_add(&value, gyro, e_gyro);
        mul_transpose_add(&value, accel, e_accel)
    }

    /// Block (`R`, ϑ) of the new `P_dd`: `Φ_ϑp = Φ_ϑv = 0` and `E_a` has no attitude row.
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(never)]
    fn attitude_pair(&self, u_attitude: &Block, gyro: &Block) -> Block {
        let [gyro_attitude, _, _] = &self.gyro_bias_column;
        mul_transpose_add(
            &mul_transpose(u_attitude, &self.transition.attitude_attitude),
            gyro,
            gyro_attitude,
        )
    }

    /// `P ← F P Fᵀ + Qd` in place, by blocks (module docs); `false` (and `P` unchanged) if
    /// the result is not finite. Every new block is computed from the old `P` into locals
    /// first (`U` is 9×24, the new `P_dd` six blocks), checked, then written with its mirror.
    ///
    /// Two kernels compute `U` and the new `P_dd`, chosen by the target: 3×3 blocks with the
    /// accumulators in registers on a scalar double-precision FPU (32-bit ARM: the
    /// Cortex-M7 has no f64 SIMD), 24-wide rows that the compiler vectorises elsewhere
    /// (x86-64 SSE2, AArch64 NEON; [`rows`]). Both sum every element with the same
    /// operations in the same order, so they give the same bits (tested on the host, and by
    /// the host/target comparisons). The folding of the scale-factor columns, the noise of
    /// `P_dd`, the walk diagonal, the finite check of `P_dd` and its writes are shared; the
    /// new `P_dc` stays in blocks in one tail and in the rows of `U` in the other.
    pub(crate) fn propagate_covariance(&self, p: &mut CovarianceMatrix) -> bool {
        #[cfg(target_arch = "arm")]
        return self.propagate_covariance_by_blocks(p);
        #[cfg(not(target_arch = "arm"))]
        return self.propagate_covariance_by_rows(p);
    }

    /// [`StructuredModel::propagate_covariance`] with the 3×3 block kernel (the target's).
    #[cfg(any(test, target_arch = "arm"))]
    fn propagate_covariance_by_blocks(&self, p: &mut CovarianceMatrix) -> bool {
        let [c0, c1, c2, c3, c4, c5, c6, c7, c8, c9, c10, c11, c12, c13, c14, c15, c16, c17, c18, c19, c20, c21, c22, c23] =
            &p.data.0;
        // U = [Φ E] P by column blocks; U's calibration columns are the new P_dc.
        // Bound whole and split by reference: destructuring by value copies each block.
        let u_attitude_columns = self.propagate_column([c0, c1, c2]);
        let u_position_columns = self.propagate_column([c3, c4, c5]);
        let u_velocity_columns = self.propagate_column([c6, c7, c8]);
        let mut gyro_bias = self.propagate_column([c9, c10, c11]);
        let mut accel_bias = self.propagate_column([c12, c13, c14]);
        let installation = self.propagate_column([c15, c16, c17]);
        let gyro_scale = self.propagate_column([c18, c19, c20]);
        let accel_scale = self.propagate_column([c21, c22, c23]);
        let (folded_gyro, folded_accel) =
            self.fold_calibration_columns(&gyro_bias, &gyro_scale, &accel_bias, &accel_scale);
        let [u_aa, u_pa, u_va] = &u_attitude_columns;
        let [u_ap, u_pp, u_vp] = &u_position_columns;
        let [u_av, u_pv, u_vv] = &u_velocity_columns;
        let [fg_a, fg_p, fg_v] = &folded_gyro;
        let [fa_a, fa_p, fa_v] = &folded_accel;
        let t = &self.transition;
        let [_, e_gyro_p, e_gyro_v] = &self.gyro_bias_column;
        let [e_accel_p, e_accel_v] = &self.accel_bias_column;
        let position_row = [
            &t.position_attitude,
            &t.position_position,
            &t.position_velocity,
        ];
        let velocity_row = [
            &t.velocity_attitude,
            &t.velocity_position,
            &t.velocity_velocity,
        ];
        let position_columns = [e_gyro_p, e_accel_p];
        let velocity_columns = [e_gyro_v, e_accel_v];
        // Rows of U_dd by reference (an array of blocks would be copied, 72 bytes each).
        let row_a = [u_aa, u_ap, u_av];
        let row_p = [u_pa, u_pp, u_pv];
        let row_v = [u_va, u_vp, u_vv];
        let mut dynamic = [
            self.attitude_pair(u_aa, fg_a),
            Self::dynamic_pair(row_a, [fg_a, fa_a], position_row, position_columns),
            Self::dynamic_pair(row_a, [fg_a, fa_a], velocity_row, velocity_columns),
            Self::dynamic_pair(row_p, [fg_p, fa_p], position_row, position_columns),
            Self::dynamic_pair(row_p, [fg_p, fa_p], velocity_row, velocity_columns),
            Self::dynamic_pair(row_v, [fg_v, fa_v], velocity_row, velocity_columns),
        ];
        self.write_propagated(
            p,
            [&mut gyro_bias, &mut accel_bias],
            [&installation, &gyro_scale, &accel_scale],
            &mut dynamic,
        )
    }

    /// [`StructuredModel::propagate_covariance`] with the row kernel ([`rows`]; the host's).
    #[cfg(any(test, not(target_arch = "arm")))]
    fn propagate_covariance_by_rows(&self, p: &mut CovarianceMatrix) -> bool {
        // Every element is written by `projected_rows` (the zeros are never read).
        let mut u = [[0.0; STATE_DIMENSION]; rows::DYNAMIC_DIMENSION];
        rows::projected_rows(self, p, &mut u);
        let (folded_gyro, folded_accel) = self.fold_calibration_columns(
            &rows::column_block(&u, BG),
            &rows::column_block(&u, SG),
            &rows::column_block(&u, BA),
            &rows::column_block(&u, SA),
        );
        let mut dynamic = rows::dynamic_blocks(self, &u, &folded_gyro, &folded_accel);
        self.write_propagated_rows(p, &mut u, &mut dynamic)
    }

    /// `U`'s calibration columns folded (module docs), rows ϑ, δp, δv: the gyro's
    /// `U_bg + U_λg diag(ω_m) + q_g E_g` and the accelerometer's
    /// `U_ba + U_λa diag(f_m) + q_a E_a` (white noise folded in; `E_a` has no attitude row).
    #[inline(always)]
    fn fold_calibration_columns(
        &self,
        gyro_bias: &[Block; 3],
        gyro_scale: &[Block; 3],
        accel_bias: &[Block; 3],
        accel_scale: &[Block; 3],
    ) -> ([Block; 3], [Block; 3]) {
        let rate = self.measured_rate_rad_s;
        let force = self.measured_specific_force_mps2;
        let [gyro_a, gyro_p, gyro_v] = gyro_bias;
        let [accel_a, accel_p, accel_v] = accel_bias;
        let [scale_gyro_a, scale_gyro_p, scale_gyro_v] = gyro_scale;
        let [scale_accel_a, scale_accel_p, scale_accel_v] = accel_scale;
        let [gyro_noise, accel_noise] = self.input_noise;
        let [e_gyro_a, e_gyro_p, e_gyro_v] = &self.gyro_bias_column;
        let [e_accel_p, e_accel_v] = &self.accel_bias_column;
        let fold = |bias, scale_factor, input, column, noise| {
            add_scaled(
                &add_scaled_columns(bias, scale_factor, input),
                column,
                noise,
            )
        };
        (
            [
                fold(gyro_a, scale_gyro_a, rate, e_gyro_a, gyro_noise),
                fold(gyro_p, scale_gyro_p, rate, e_gyro_p, gyro_noise),
                fold(gyro_v, scale_gyro_v, rate, e_gyro_v, gyro_noise),
            ],
            [
                add_scaled_columns(accel_a, scale_accel_a, force),
                fold(accel_p, scale_accel_p, force, e_accel_p, accel_noise),
                fold(accel_v, scale_accel_v, force, e_accel_v, accel_noise),
            ],
        )
    }

    /// The block kernel's tail of the propagation: the walks' `Qd` added to the new `P_dd`
    /// (`dynamic`, pairs ϑϑ, ϑp, ϑv, pp, pv, vv without noise) and to the bias columns, the
    /// finite check of everything new, then the writes with their mirrors. `bias` are `U`'s
    /// gyro- and accelerometer-bias columns, `other` its installation and scale-factor
    /// columns (rows ϑ, δp, δv each). `false`, with `P` unchanged, if anything is not finite.
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(always)]
    fn write_propagated(
        &self,
        p: &mut CovarianceMatrix,
        bias: [&mut [Block; 3]; 2],
        other: [&[Block; 3]; 3],
        dynamic: &mut [Block; 6],
    ) -> bool {
        self.add_dynamic_noise(dynamic);
        let [gyro_bias, accel_bias] = bias;
        // Bias walks: Qd in the bias columns of the dynamic rows and on the bias diagonal.
        if self.bias_walk {
            // In place (new arrays of blocks would be copies).
            let with = |column: &mut [Block; 3], noise: &[Block; 3]| {
                for (value, q) in column.iter_mut().zip(noise) {
                    *value = add(value, q);
                }
            };
            with(gyro_bias, &self.noise.dynamic_gyro_bias);
            with(accel_bias, &self.noise.dynamic_accel_bias);
        }
        let walk_diagonal = self.walk_diagonal(p);
        let [installation, gyro_scale, accel_scale] = other;
        let mut check = FiniteCheck::new();
        for blocks in [
            &*gyro_bias,
            &*accel_bias,
            installation,
            gyro_scale,
            accel_scale,
        ] {
            for value in blocks {
                check.block(value);
            }
        }
        Self::check_dynamic(&mut check, dynamic, &walk_diagonal);
        if !check.all_finite() {
            return false;
        }
        let [gyro_a, gyro_p, gyro_v] = &*gyro_bias;
        write_symmetric::<A, BG>(p, gyro_a);
        write_symmetric::<P, BG>(p, gyro_p);
        write_symmetric::<V, BG>(p, gyro_v);
        let [accel_a, accel_p, accel_v] = &*accel_bias;
        write_symmetric::<A, BA>(p, accel_a);
        write_symmetric::<P, BA>(p, accel_p);
        write_symmetric::<V, BA>(p, accel_v);
        let [installation_a, installation_p, installation_v] = installation;
        write_symmetric::<A, PSI>(p, installation_a);
        write_symmetric::<P, PSI>(p, installation_p);
        write_symmetric::<V, PSI>(p, installation_v);
        let [scale_gyro_a, scale_gyro_p, scale_gyro_v] = gyro_scale;
        write_symmetric::<A, SG>(p, scale_gyro_a);
        write_symmetric::<P, SG>(p, scale_gyro_p);
        write_symmetric::<V, SG>(p, scale_gyro_v);
        let [scale_accel_a, scale_accel_p, scale_accel_v] = accel_scale;
        write_symmetric::<A, SA>(p, scale_accel_a);
        write_symmetric::<P, SA>(p, scale_accel_p);
        write_symmetric::<V, SA>(p, scale_accel_v);
        Self::write_dynamic(p, dynamic, &walk_diagonal);
        true
    }

    /// The row kernel's tail: as [`StructuredModel::write_propagated`], with `U`'s
    /// calibration columns (the new `P_dc`) kept in the rows of `u`: the walks' `Qd` added
    /// there, checked there, and written from there (each row into its column of `P`, and
    /// mirrored).
    #[cfg(any(test, not(target_arch = "arm")))]
    #[inline(always)]
    fn write_propagated_rows(
        &self,
        p: &mut CovarianceMatrix,
        u: &mut rows::ProjectedRows,
        dynamic: &mut [Block; 6],
    ) -> bool {
        self.add_dynamic_noise(dynamic);
        if self.bias_walk {
            rows::add_to_column(u, BG, &self.noise.dynamic_gyro_bias);
            rows::add_to_column(u, BA, &self.noise.dynamic_accel_bias);
        }
        let walk_diagonal = self.walk_diagonal(p);
        let mut check = FiniteCheck::new();
        Self::check_dynamic(&mut check, dynamic, &walk_diagonal);
        if !(check.all_finite() && rows::calibration_finite(u)) {
            return false;
        }
        rows::write_calibration_columns(p, u);
        Self::write_dynamic(p, dynamic, &walk_diagonal);
        true
    }

    /// The walks' `Qd` added to the new `P_dd` (zero noise blocks, no walk, are not added).
    #[inline(always)]
    fn add_dynamic_noise(&self, dynamic: &mut [Block; 6]) {
        if !self.noise_is_zero {
            for (value, q) in dynamic.iter_mut().zip(&self.noise.dynamic) {
                *value = add(value, q);
            }
        }
    }

    /// The new bias diagonal blocks under bias walks, `P_bg,bg + Qd` and `P_ba,ba + Qd`
    /// (read from the old `P`); `None` without walks (the blocks keep their values).
    #[inline(always)]
    fn walk_diagonal(&self, p: &CovarianceMatrix) -> Option<[Block; 2]> {
        if self.bias_walk {
            Some([
                add(&read::<BG, BG, 24, 24>(p), &self.noise.gyro_bias),
                add(&read::<BA, BA, 24, 24>(p), &self.noise.accel_bias),
            ])
        } else {
            None
        }
    }

    /// Adds the new `P_dd` and bias diagonal blocks to a finite check.
    #[inline(always)]
    fn check_dynamic(
        check: &mut FiniteCheck,
        dynamic: &[Block; 6],
        walk_diagonal: &Option<[Block; 2]>,
    ) {
        for value in dynamic.iter() {
            check.block(value);
        }
        if let Some(blocks) = walk_diagonal {
            for value in blocks {
                check.block(value);
            }
        }
    }

    /// Writes the new `P_dd` (upper block triangle, mirrored) and bias diagonal blocks.
    #[inline(always)]
    fn write_dynamic(
        p: &mut CovarianceMatrix,
        dynamic: &[Block; 6],
        walk_diagonal: &Option<[Block; 2]>,
    ) {
        let [new_aa, new_ap, new_av, new_pp, new_pv, new_vv] = dynamic;
        write_diagonal_symmetric::<A>(p, new_aa);
        write_symmetric::<A, P>(p, new_ap);
        write_symmetric::<A, V>(p, new_av);
        write_diagonal_symmetric::<P>(p, new_pp);
        write_symmetric::<P, V>(p, new_pv);
        write_diagonal_symmetric::<V>(p, new_vv);
        if let Some([gyro, accel]) = walk_diagonal {
            write_diagonal_symmetric::<BG>(p, gyro);
            write_diagonal_symmetric::<BA>(p, accel);
        }
    }
}

/// One 3-vector per state: row `j` of a 24×3 matrix such as `P Hᵀ` or `K`.
pub(crate) type StateRows = [Row; STATE_DIMENSION];

/// `P Hᵀ` and `H P Hᵀ` of a measurement, summed over the non-zero 3×3 blocks of `H` only
/// (module docs).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ObservedCovariance {
    /// `M = P Hᵀ`, row `j` for state `j`.
    products: StateRows,
    /// `H P Hᵀ` (without `R`).
    projected: Block,
}

impl ObservedCovariance {
    /// `M = P Hᵀ` and `H P Hᵀ` over the blocks of `H` that are not all zero: for each
    /// observed block `K`, `M_j += H_K P_{K,j}` over the 24 columns `j` (the symmetric `P`
    /// read by columns), then `H P Hᵀ = Σ_K H_K P_{K,·} H_Kᵀ`'s sum `Σ_K (M_K)ᵀ H_Kᵀ`.
    pub(crate) fn new(
        jacobian: &MeasurementJacobian,
        p: &CovarianceMatrix,
        border: Option<(&StateRows, &crate::gnss_error::Border)>,
    ) -> Self {
        // Built in its final place (a local array moved into `Self` would be copied).
        let mut observed = Self {
            products: [[0.0; 3]; STATE_DIMENSION],
            projected: ZERO,
        };
        let blocks = [
            (A, read::<0, A, 3, 24>(jacobian)),
            (P, read::<0, P, 3, 24>(jacobian)),
            (V, read::<0, V, 3, 24>(jacobian)),
            (BG, read::<0, BG, 3, 24>(jacobian)),
            (BA, read::<0, BA, 3, 24>(jacobian)),
            (PSI, read::<0, PSI, 3, 24>(jacobian)),
            (SG, read::<0, SG, 3, 24>(jacobian)),
            (SA, read::<0, SA, 3, 24>(jacobian)),
        ];
        let observed_blocks = || {
            blocks
                .iter()
                .filter(|(_, h)| !h.iter().flatten().all(|v| *v == 0.0))
        };
        for (offset, h) in observed_blocks() {
            add_observed_block(&mut observed.products, p, *offset, h);
        }
        // H P Hᵀ = Σ_K (H P)_{·,K} H_Kᵀ, with (H P)_{·,K} = [M_K, M_K+1, M_K+2] as columns.
        for (offset, h) in observed_blocks() {
            if let Some([m0, m1, m2]) = observed.products.get(*offset..*offset + 3) {
                observed.projected =
                    mul_transpose_add(&observed.projected, &transpose(&[*m0, *m1, *m2]), h);
            }
        }
        if let Some((cross, border)) = border {
            observed.add_border(cross, border);
        }
        observed
    }

    /// Adds the correlated-GNSS-error border ([`crate::gnss_error`]): `h_ε C_j` to each
    /// `M_j` and the border's terms to `H P Hᵀ`.
    fn add_border(&mut self, cross: &StateRows, border: &crate::gnss_error::Border) {
        for (product, c) in self.products.iter_mut().zip(cross) {
            *product = block::row_add_scaled(*product, *c, border.coefficient);
        }
        self.projected = add(&self.projected, &border.projected);
    }

    /// `M = P Hᵀ`, row `j` for state `j`.
    pub(crate) fn products(&self) -> &StateRows {
        &self.products
    }

    /// `H P Hᵀ`.
    pub(crate) fn projected(&self) -> Matrix3<f64> {
        block::to_matrix(&self.projected)
    }

    /// The gain `K = P Hᵀ S⁻¹`, row `j` = `S⁻¹ M_j`, the rows of the `frozen` blocks zero.
    pub(crate) fn gain(&self, cholesky: &Cholesky3, frozen: &BlockMask) -> StateRows {
        // Built element by element (no zero-fill of the 576-byte array first).
        core::array::from_fn(|state_index| match self.products.get(state_index) {
            Some(product) if !frozen.contains_state(state_index) => cholesky.solve(*product),
            _ => [0.0; 3],
        })
    }
}

/// `M_j += H_K P_{K,j}` for all 24 columns `j` (`offset` = `K`'s first state). Not inlined:
/// `H_K` stays in nine registers over the loop.
#[inline(never)]
fn add_observed_block(products: &mut StateRows, p: &CovarianceMatrix, offset: usize, h: &Block) {
    let [h0, h1, h2] = *h;
    for (product, column) in products.iter_mut().zip(p.data.0.iter()) {
        if let Some(&[x0, x1, x2]) = column.get(offset..offset + 3) {
            let x = [x0, x1, x2];
            let [r0, r1, r2] = *product;
            *product = [r0 + dot(h0, x), r1 + dot(h1, x), r2 + dot(h2, x)];
        }
    }
}

/// `x += K ν` (the state correction) from the gain rows, in place.
pub(crate) fn add_gain_times(
    state: &mut SMatrix<f64, 24, 1>,
    gains: &StateRows,
    innovation: &Vector3<f64>,
) {
    let nu = block::from_vector(innovation);
    let [values] = &mut state.data.0;
    for (value, row) in values.iter_mut().zip(gains) {
        *value += dot(*row, nu);
    }
}

/// Cholesky factor `L` (lower, `S = L Lᵀ`) of a symmetric 3×3, with the reciprocals of its
/// diagonal (Golub & Van Loan, *Matrix Computations*, 4th ed., Alg. 4.2.1).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Cholesky3 {
    l10: f64,
    l20: f64,
    l21: f64,
    inverse_diagonal: Row,
}

impl Cholesky3 {
    /// `None` if `s` is not positive definite (or not finite).
    pub(crate) fn new(s: &Matrix3<f64>) -> Option<Self> {
        let [[s00, _, _], [s10, s11, _], [s20, s21, s22]] = block::from_matrix(s);
        let pivot = |value: f64| (value.is_finite() && value > 0.0).then(|| libm::sqrt(value));
        let l00 = pivot(s00)?;
        let i00 = 1.0 / l00;
        let l10 = s10 * i00;
        let l20 = s20 * i00;
        let l11 = pivot(s11 - l10 * l10)?;
        let i11 = 1.0 / l11;
        let l21 = (s21 - l20 * l10) * i11;
        let l22 = pivot(s22 - l20 * l20 - l21 * l21)?;
        Some(Self {
            l10,
            l20,
            l21,
            inverse_diagonal: [i00, i11, 1.0 / l22],
        })
    }

    /// `y = L⁻¹ b` (forward substitution).
    #[inline(always)]
    pub(crate) fn whiten(&self, b: Row) -> Row {
        let ([b0, b1, b2], [i0, i1, i2]) = (b, self.inverse_diagonal);
        let y0 = b0 * i0;
        let y1 = (b1 - self.l10 * y0) * i1;
        let y2 = (b2 - self.l20 * y0 - self.l21 * y1) * i2;
        [y0, y1, y2]
    }

    /// `x = S⁻¹ b = L⁻ᵀ L⁻¹ b`.
    #[inline(always)]
    pub(crate) fn solve(&self, b: Row) -> Row {
        let [y0, y1, y2] = self.whiten(b);
        let [i0, i1, i2] = self.inverse_diagonal;
        let x2 = y2 * i2;
        let x1 = (y1 - self.l21 * x2) * i1;
        let x0 = (y0 - self.l10 * x1 - self.l20 * x2) * i0;
        [x0, x1, x2]
    }
}

/// One rank-3 pass of the expanded Joseph update over rows `row..row + 3`, upper triangle:
/// `P_ij ← ((P_ij ± l_i0 r_j0) ± l_i1 r_j1) ± l_i2 r_j2` (`+` unless `SUBTRACT`), with the
/// rows' vectors `left` and the columns' vectors `right`. The nine row coefficients stay in
/// registers while the columns stream past; each column's three rows (contiguous in the
/// column-major `P`) and its `r_j` are loaded once. Column `row` reaches only row `row`,
/// column `row + 1` rows `row` and `row + 1`. The subtracting pass also checks every new
/// value (the returned check; a local accumulator stays in a register).
#[inline(never)]
fn joseph_pass<const SUBTRACT: bool>(
    columns: &mut [[f64; STATE_DIMENSION]; STATE_DIMENSION],
    row: usize,
    left: &[Row; 3],
    right: &StateRows,
) -> FiniteCheck {
    let mut check = FiniteCheck::new();
    let [l0, l1, l2] = *left;
    let term = |value: f64, [a0, a1, a2]: Row, [b0, b1, b2]: Row| {
        if SUBTRACT {
            value - a0 * b0 - a1 * b1 - a2 * b2
        } else {
            value + a0 * b0 + a1 * b1 + a2 * b2
        }
    };
    let mut update = |value: &mut f64, l: Row, r: Row| {
        *value = term(*value, l, r);
        if SUBTRACT {
            check.value(*value);
        }
    };
    if let (Some(column), Some(r)) = (columns.get_mut(row), right.get(row)) {
        if let Some(p0) = column.get_mut(row) {
            update(p0, l0, *r);
        }
    }
    if let (Some(column), Some(r)) = (columns.get_mut(row + 1), right.get(row + 1)) {
        if let Some([p0, p1]) = column.get_mut(row..row + 2) {
            update(p0, l0, *r);
            update(p1, l1, *r);
        }
    }
    // Plain slice zips (no iterator state kept in memory across iterations).
    let (Some(full_columns), Some(full_right)) = (columns.get_mut(row + 2..), right.get(row + 2..))
    else {
        return check;
    };
    for (column, r) in full_columns.iter_mut().zip(full_right) {
        if let Some([p0, p1, p2]) = column.get_mut(row..row + 3) {
            update(p0, l0, *r);
            update(p1, l1, *r);
            update(p2, l2, *r);
        }
    }
    check
}

/// Joseph form expanded (module docs), in place: `P⁺_ij = (P_ij + N_i·K_j) − K_i·M_j` with
/// `N = K S − M` on the upper triangle (6 multiply-adds per element, in two rank-3 passes
/// per triple of rows, [`joseph_pass`]), mirrored; `gains` are the rows `K_i`, `observed`
/// holds `M = P Hᵀ`, `s` is symmetric. `false` (and `P` unchanged) if the result is not
/// finite: new values go to the upper triangle only, so the untouched lower triangle and a
/// saved diagonal are the roll-back copy.
pub(crate) fn joseph_update(
    p: &mut CovarianceMatrix,
    gains: &StateRows,
    observed: &ObservedCovariance,
    s: &Matrix3<f64>,
) -> bool {
    let s = block::from_matrix(s);
    // N_i = K_i S − M_i (built element by element: no zero-fill first).
    let n_rows: StateRows = core::array::from_fn(|i| {
        let gain = gains.get(i).copied().unwrap_or([0.0; 3]);
        let product = observed.products.get(i).copied().unwrap_or([0.0; 3]);
        block::row_sub(mul_vector_add([0.0; 3], &s, gain), product)
    });
    let diagonal: [f64; STATE_DIMENSION] = core::array::from_fn(|i| block::entry(p, i, i));
    let mut check = FiniteCheck::new();
    let triples = n_rows
        .chunks_exact(3)
        .zip(gains.chunks_exact(3))
        .enumerate();
    for (triple, (n, k)) in triples {
        let row = 3 * triple;
        if let ([n0, n1, n2], [k0, k1, k2]) = (n, k) {
            joseph_pass::<false>(&mut p.data.0, row, &[*n0, *n1, *n2], gains);
            let products = &observed.products;
            check.merge(joseph_pass::<true>(
                &mut p.data.0,
                row,
                &[*k0, *k1, *k2],
                products,
            ));
        }
    }
    if check.all_finite() {
        block::mirror_upper_to_lower(p, STATE_DIMENSION);
        true
    } else {
        block::mirror_lower_to_upper(p, STATE_DIMENSION);
        for (index, value) in diagonal.iter().enumerate() {
            block::set_entry(p, index, index, *value);
        }
        false
    }
}

/// Block (`R`, `C`), `R < C`, of `J P Jᵀ` in place, with `J_R = left` and `J_C = right`
/// (`None`: identity), and its mirror.
#[inline(always)]
fn reset_pair<const R: usize, const C: usize>(
    p: &mut CovarianceMatrix,
    left: Option<&Block>,
    right: Option<&Block>,
) {
    let old = read::<R, C, 24, 24>(p);
    let value = match (left, right) {
        (Some(l), Some(r)) => mul_transpose(&mul(l, &old), r),
        (Some(l), None) => mul(l, &old),
        (None, Some(r)) => mul_transpose(&old, r),
        (None, None) => old,
    };
    write_symmetric::<R, C>(p, &value);
}

/// Diagonal block `D` of `J P Jᵀ` in place: `J_D P_DD J_Dᵀ`, upper triangle mirrored.
#[inline(always)]
fn reset_diagonal<const D: usize>(p: &mut CovarianceMatrix, jacobian: &Block) {
    let old = read::<D, D, 24, 24>(p);
    write_diagonal_symmetric::<D>(p, &mul_transpose(&mul(jacobian, &old), jacobian));
}

/// `P ← J P Jᵀ` in place for the reset Jacobian `J` = identity except `J_ϑϑ = I − [ϑ̂×]` and
/// `J_ψψ = I − [ψ̂×]`: only the attitude and installation block rows and columns change;
/// each new block depends only on the same old block, so they are overwritten one by one.
pub(crate) fn reset_covariance(
    p: &mut CovarianceMatrix,
    attitude: &Matrix3<f64>,
    installation: &Matrix3<f64>,
) {
    let (attitude, installation) = (
        block::from_matrix(attitude),
        block::from_matrix(installation),
    );
    let (a, i) = (Some(&attitude), Some(&installation));
    reset_diagonal::<A>(p, &attitude);
    reset_pair::<A, P>(p, a, None);
    reset_pair::<A, V>(p, a, None);
    reset_pair::<A, BG>(p, a, None);
    reset_pair::<A, BA>(p, a, None);
    reset_pair::<A, PSI>(p, a, i);
    reset_pair::<A, SG>(p, a, None);
    reset_pair::<A, SA>(p, a, None);
    reset_pair::<P, PSI>(p, None, i);
    reset_pair::<V, PSI>(p, None, i);
    reset_pair::<BG, PSI>(p, None, i);
    reset_pair::<BA, PSI>(p, None, i);
    reset_diagonal::<PSI>(p, &installation);
    reset_pair::<PSI, SG>(p, i, None);
    reset_pair::<PSI, SA>(p, i, None);
}

/// [`crate::measurement::refer_to_later_time`] without forming `A`: `H' = H − (H A) Δ`
/// computed from the blocks of `A` at `point` (only its attitude, position and velocity rows
/// are non-zero, [`crate::error_model`]):
/// `(H A)_ϑ = H_ϑ W + H_v V`, `(H A)_p = H_v N`, `(H A)_v = H_p`, `(H A)_bg = −½ H_ϑ`,
/// `(H A)_ba = −H_v Ĉ`, `(H A)_λg = −½ H_ϑ diag(ω_m)`, `(H A)_λa = −H_v Ĉ diag(f_m)`,
/// `(H A)_ψ = 0`, with `W = −[ω̂×]`, `V = −2Ĉ[f̂×]`, `N = ∂g/∂p`. Equal to the dense
/// version (proven by the tests).
///
/// # Errors
/// [`NavError::InvalidTimeStep`] for a negative or non-finite latency,
/// [`NavError::NonFiniteInput`] for a non-finite point.
pub fn refer_to_later_time_at(
    measurement: &LinearMeasurement,
    point: &LinearisationPoint,
    latency_s: f64,
) -> Result<LinearMeasurement, NavError> {
    let mut referred = *measurement;
    refer_to_later_time_in_place(&mut referred, point, latency_s)?;
    Ok(referred)
}

/// [`refer_to_later_time_at`] in place (the flight path: a [`LinearMeasurement`] is 672
/// bytes, and each copy costs ~540 instructions on the Cortex-M7 target). On an error the
/// measurement is unchanged.
///
/// # Errors
/// As [`refer_to_later_time_at`].
pub fn refer_to_later_time_in_place(
    measurement: &mut LinearMeasurement,
    point: &LinearisationPoint,
    latency_s: f64,
) -> Result<(), NavError> {
    if !(latency_s.is_finite() && latency_s >= 0.0) {
        return Err(NavError::InvalidTimeStep);
    }
    let rate = block::from_vector(&point.corrected_rate_rad_s);
    let force = block::from_vector(&point.corrected_specific_force_mps2);
    let measured_rate = block::from_vector(&point.measured_rate_rad_s);
    let measured_force = block::from_vector(&point.measured_specific_force_mps2);
    let c = block::from_matrix(&point.body_to_inertial);
    let gradient = block::from_matrix(&point.gravity_gradient_per_s2);
    let mut check = FiniteCheck::new();
    for value in rate
        .iter()
        .chain(&force)
        .chain(&measured_rate)
        .chain(&measured_force)
    {
        check.value(*value);
    }
    check.block(&c);
    check.block(&gradient);
    if !check.all_finite() {
        return Err(NavError::NonFiniteInput);
    }
    let h = &measurement.jacobian;
    // The blocks of H that (H A) reads, copied before H is changed.
    let (h_attitude, h_position, h_velocity) = (
        read::<0, A, 3, 24>(h),
        read::<0, P, 3, 24>(h),
        read::<0, V, 3, 24>(h),
    );
    let w = scale(&block::skew(rate), -1.0);
    let v = mul(&scale(&c, -2.0), &block::skew(force));
    let negative_c = scale(&c, -1.0);
    let accel = mul(&h_velocity, &negative_c);
    let half_attitude = scale(&h_attitude, -0.5);
    let jacobian = &mut measurement.jacobian;
    let mut subtract = |offset: usize, product: &Block| {
        for (i, row) in product.iter().enumerate() {
            for (j, value) in row.iter().enumerate() {
                if let Some(entry) = jacobian.get_mut((i, offset + j)) {
                    *entry -= value * latency_s;
                }
            }
        }
    };
    subtract(A, &mul_add(&mul(&h_attitude, &w), &h_velocity, &v));
    subtract(P, &mul(&h_velocity, &gradient));
    subtract(V, &h_position);
    subtract(BG, &half_attitude);
    subtract(BA, &accel);
    subtract(SG, &scale_columns(&half_attitude, measured_rate));
    subtract(SA, &scale_columns(&accel, measured_force));
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests {
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

    use nalgebra::{Quaternion, Vector3};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Largest element-wise difference of two covariances in correlation units,
    /// `max |A_ij − B_ij| / √(B_ii B_jj)` (a zero-variance pair must match exactly).
    fn relative_difference(a: &CovarianceMatrix, b: &CovarianceMatrix) -> f64 {
        relative_to(a, b, b)
    }

    /// `max |A_ij − B_ij| / √(S_ii S_jj)`: the difference in units of the scale `S`.
    pub(crate) fn relative_to(
        a: &CovarianceMatrix,
        b: &CovarianceMatrix,
        scale: &CovarianceMatrix,
    ) -> f64 {
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

    pub(crate) fn random_vector(rng: &mut ChaCha8Rng, largest_norm: f64) -> Vector3<f64> {
        let direction = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        direction.normalize() * rng.random_range(0.0..largest_norm)
    }

    /// Physical 1σ scale of each block (attitude rad, m, m/s, rad/s, m/s², rad, -, -).
    const BLOCK_SCALES: [f64; 8] = [1e-3, 30.0, 0.3, 5e-4, 5e-3, 2e-3, 1e-4, 1e-4];

    /// A random symmetric positive-definite P with physical block scales and strong
    /// correlations: `D (B Bᵀ/24 + 0.05 I) D`.
    pub(crate) fn random_covariance(rng: &mut ChaCha8Rng) -> CovarianceMatrix {
        let b = CovarianceMatrix::from_fn(|_, _| rng.random_range(-1.0..1.0));
        let d = CovarianceMatrix::from_diagonal(&SMatrix::<f64, 24, 1>::from_fn(|i, _| {
            BLOCK_SCALES[i / 3] * rng.random_range(0.5..2.0)
        }));
        let p = d * (b * b.transpose() / 24.0 + CovarianceMatrix::identity() * 0.05) * d;
        (p + p.transpose()) * 0.5
    }

    pub(crate) fn random_state(rng: &mut ChaCha8Rng) -> ErrorState {
        ErrorState::from_fn(|i, _| BLOCK_SCALES[i / 3] * rng.random_range(-1.0..1.0))
    }

    /// Random motion: rates up to 2 rad/s, specific forces up to 50 m/s², random attitude,
    /// point-mass gravity gradient at a random position 6,400-7,000 km from the centre.
    pub(crate) fn random_point(rng: &mut ChaCha8Rng) -> LinearisationPoint {
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

    pub(crate) fn random_noise(rng: &mut ChaCha8Rng, with_bias_walk: bool) -> ProcessNoise {
        let walk = if with_bias_walk { 1.0 } else { 0.0 };
        ProcessNoise {
            gyro_noise_density_rad_s_per_sqrt_hz: rng.random_range(1e-7..1e-5),
            accel_noise_density_mps2_per_sqrt_hz: rng.random_range(1e-5..1e-3),
            gyro_bias_walk_rad_s2_per_sqrt_hz: walk * rng.random_range(1e-9..1e-7),
            accel_bias_walk_mps3_per_sqrt_hz: walk * rng.random_range(1e-7..1e-5),
        }
    }

    pub(crate) fn random_mask(rng: &mut ChaCha8Rng) -> BlockMask {
        let mut mask = BlockMask::NONE;
        for block in BLOCKS {
            if rng.random_bool(0.3) {
                mask.insert(block);
            }
        }
        mask
    }

    pub(crate) fn filter_with(mode: FilterMode, p: &CovarianceMatrix) -> ErrorStateFilter {
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
            gnss_error: crate::gnss_error::GnssErrorModel::WHITE,
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
        model.remove_process_noise(frozen);
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

    /// The row kernel (the host's) and the block kernel (the Cortex-M7's) give the same
    /// bits: random SPD `P`, a diagonal `P` (the initial covariance: many products are
    /// signed zeros), random motion, every order, with and without walks and frozen noise;
    /// and both refuse an overflow leaving `P` unchanged.
    #[test]
    fn the_row_kernel_equals_the_block_kernel_bit_for_bit() {
        let mut rng = ChaCha8Rng::seed_from_u64(23);
        let bits = |p: &CovarianceMatrix| p.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        let mut compared = 0;
        for order in 1..=MAX_ORDER {
            for case in 0..120 {
                let point = random_point(&mut rng);
                let noise = random_noise(&mut rng, case % 2 == 1);
                let interval_s = [0.002, 0.004, 0.02, 0.1][case % 4];
                let mut model = StructuredModel::new(&point, &noise, interval_s, order).unwrap();
                if case % 3 == 0 {
                    model.remove_process_noise(&random_mask(&mut rng));
                }
                let p = if case % 5 == 0 {
                    CovarianceMatrix::from_diagonal(&random_covariance(&mut rng).diagonal())
                } else {
                    random_covariance(&mut rng)
                };
                let (mut by_blocks, mut by_rows) = (p, p);
                assert!(model.propagate_covariance_by_blocks(&mut by_blocks));
                assert!(model.propagate_covariance_by_rows(&mut by_rows));
                assert_eq!(
                    bits(&by_rows),
                    bits(&by_blocks),
                    "order {order} case {case}"
                );
                assert_ne!(bits(&by_rows), bits(&p), "the propagation changed P");
                compared += 1;
            }
        }
        assert_eq!(compared, 480);
        // A non-finite value that only the new P_dc reads (P_bg,ψ: the installation columns
        // of U), or only the new P_dd reads (P_vv): both kernels refuse, P unchanged.
        let noise = random_noise(&mut rng, true);
        let model = StructuredModel::new(&random_point(&mut rng), &noise, 0.02, 3).unwrap();
        for (row, column) in [
            (GYRO_BIAS.index, STAR_INSTALLATION.index),
            (VELOCITY.index, VELOCITY.index),
        ] {
            let mut p = random_covariance(&mut rng);
            p[(row, column)] = f64::INFINITY;
            p[(column, row)] = f64::INFINITY;
            let (mut by_blocks, mut by_rows) = (p, p);
            assert!(!model.propagate_covariance_by_blocks(&mut by_blocks));
            assert!(!model.propagate_covariance_by_rows(&mut by_rows));
            assert_eq!(bits(&by_blocks), bits(&p));
            assert_eq!(bits(&by_rows), bits(&p));
        }
        // An overflowing propagation: both kernels refuse it and leave P as it was.
        let noise = random_noise(&mut rng, true);
        let model = StructuredModel::new(&random_point(&mut rng), &noise, 0.1, 3).unwrap();
        let p = CovarianceMatrix::from_element(f64::MAX);
        let (mut by_blocks, mut by_rows) = (p, p);
        assert!(!model.propagate_covariance_by_blocks(&mut by_blocks));
        assert!(!model.propagate_covariance_by_rows(&mut by_rows));
        assert_eq!(bits(&by_blocks), bits(&p));
        assert_eq!(bits(&by_rows), bits(&p));
    }

    pub(crate) fn random_quaternion(
        rng: &mut ChaCha8Rng,
        largest_angle_rad: f64,
    ) -> Quaternion<f64> {
        exp_rotation_vector(&random_vector(rng, largest_angle_rad))
    }

    /// A star (`star = true`) or GNSS measurement at a random geometry, optionally referred
    /// to a later time with `H (I − AΔ)` (extra bias, scale-factor and velocity columns).
    pub(crate) fn random_measurement(
        rng: &mut ChaCha8Rng,
        star: bool,
        referred: bool,
    ) -> LinearMeasurement {
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
    fn referring_by_blocks_equals_the_dense_reference() {
        let mut rng = ChaCha8Rng::seed_from_u64(13);
        for case in 0..200 {
            let measurement = random_measurement(&mut rng, case % 2 == 0, false);
            let point = random_point(&mut rng);
            let latency_s = rng.random_range(0.0..0.126);
            let dense =
                refer_to_later_time(&measurement, &system_matrix(&point), latency_s).unwrap();
            let structured = refer_to_later_time_at(&measurement, &point, latency_s).unwrap();
            assert_eq!(structured.residual, dense.residual);
            assert_eq!(structured.noise_covariance, dense.noise_covariance);
            let scale = dense.jacobian.amax();
            let difference = (structured.jacobian - dense.jacobian).amax();
            assert!(
                difference <= 1e-15 * scale,
                "case {case}: {difference:e} of {scale:e}"
            );
            // The columns A never reaches (installation) are untouched bit for bit.
            assert_eq!(
                structured
                    .jacobian
                    .fixed_columns::<3>(STAR_INSTALLATION.index),
                measurement
                    .jacobian
                    .fixed_columns::<3>(STAR_INSTALLATION.index)
            );
        }
        // A measurement already referred once (its `H` has velocity, bias and scale-factor
        // columns, so every block of `H A` is reached, `H_v V` and `−H_v Ĉ` included).
        for case in 0..100 {
            let measurement = random_measurement(&mut rng, case % 2 == 0, true);
            let point = random_point(&mut rng);
            let latency_s = rng.random_range(0.0..0.126);
            let dense =
                refer_to_later_time(&measurement, &system_matrix(&point), latency_s).unwrap();
            let structured = refer_to_later_time_at(&measurement, &point, latency_s).unwrap();
            let scale = dense.jacobian.amax();
            let difference = (structured.jacobian - dense.jacobian).amax();
            assert!(
                difference <= 1e-15 * scale,
                "referred case {case}: {difference:e} of {scale:e}"
            );
        }
        let measurement = random_measurement(&mut rng, false, false);
        let point = random_point(&mut rng);
        assert_eq!(
            refer_to_later_time_at(&measurement, &point, -1.0),
            Err(NavError::InvalidTimeStep)
        );
        let mut bad = point;
        bad.gravity_gradient_per_s2[(0, 0)] = f64::NAN;
        assert_eq!(
            refer_to_later_time_at(&measurement, &bad, 0.01),
            Err(NavError::NonFiniteInput)
        );
    }

    /// The Joseph update's roll-back: when its products overflow (finite gains and `P Hᵀ`
    /// whose products exceed the f64 range), it reports `false` and `P` is bit-identical to
    /// before, both triangles and the diagonal.
    #[test]
    fn an_overflowing_joseph_update_leaves_p_unchanged() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut p = random_covariance(&mut rng);
        let before = p;
        let observed = ObservedCovariance {
            products: [[1e200, 0.0, 0.0]; STATE_DIMENSION],
            projected: IDENTITY,
        };
        let gains: StateRows = [[1e200, 0.0, 0.0]; STATE_DIMENSION];
        assert!(!joseph_update(
            &mut p,
            &gains,
            &observed,
            &Matrix3::identity()
        ));
        assert_eq!(p.map(f64::to_bits), before.map(f64::to_bits));
    }

    /// With a strong gravity gradient and a long step (so the 4th-order terms are large) the
    /// structured transition still equals the dense series: every power's coefficient and
    /// factor of `Δ` shows.
    #[test]
    fn fourth_order_terms_match_the_dense_series_under_a_strong_gradient() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut point = random_point(&mut rng);
        point.gravity_gradient_per_s2 = Matrix3::new(3.0, 0.5, 0.2, 0.5, -1.0, 0.1, 0.2, 0.1, 2.0);
        let noise = random_noise(&mut rng, true);
        let interval_s = 0.5;
        let dense = dense_model(&point, &noise, interval_s, 4, &BlockMask::NONE);
        let model = StructuredModel::new(&point, &noise, interval_s, 4).unwrap();
        let difference = relative_difference(&model.transition_matrix(), &dense.transition);
        assert!(difference < 1e-12, "{difference:e}");
    }

    /// From a zero covariance one propagation gives exactly `Qd`: the structured model adds the
    /// same process noise as the dense one, relative to `Qd` itself (the equality tests on a
    /// full `P` cannot see an error of the size of `Qd`), with and without bias walks, with
    /// dynamic and calibration blocks' noise removed, and after a rebuild that drops the walks.
    #[test]
    fn the_process_noise_added_equals_the_dense_qd() {
        use crate::state::{ACCEL_SCALE_FACTOR, ATTITUDE, GYRO_BIAS, VELOCITY};
        let mut rng = ChaCha8Rng::seed_from_u64(21);
        let mask = |blocks: &[StateBlock]| {
            let mut mask = BlockMask::NONE;
            for block in blocks {
                mask.insert(*block);
            }
            mask
        };
        let masks = [
            BlockMask::NONE,
            mask(&[ATTITUDE]),
            mask(&[VELOCITY, GYRO_BIAS]),
            mask(&[ACCEL_SCALE_FACTOR]),
        ];
        for case in 0..32 {
            let point = random_point(&mut rng);
            let with_walk = case % 2 == 0;
            let mut noise = random_noise(&mut rng, with_walk);
            // Every combination of the two walks (both, gyro only, accelerometer only) and of
            // the two white noises (one of them absent).
            match case % 8 {
                2 => noise.accel_bias_walk_mps3_per_sqrt_hz = 0.0,
                4 => noise.gyro_bias_walk_rad_s2_per_sqrt_hz = 0.0,
                5 => noise.gyro_noise_density_rad_s_per_sqrt_hz = 0.0,
                7 => noise.accel_noise_density_mps2_per_sqrt_hz = 0.0,
                _ => {}
            }
            let frozen = masks[(case / 8) % 4];
            let dense_model = dense_model(&point, &noise, 0.01, 3, &frozen);
            // Built with the other walk setting first, then rebuilt in place.
            let mut model =
                StructuredModel::new(&point, &random_noise(&mut rng, !with_walk), 0.01, 3).unwrap();
            model.rebuild(&point, &noise, 0.01, 3).unwrap();
            model.remove_process_noise(&frozen);
            let mut structured = filter_with(FilterMode::ClosedLoop, &CovarianceMatrix::zeros());
            structured.predict_structured(&model).unwrap();
            let q = &dense_model.process_noise;
            let difference = (structured.covariance() - q).norm() / q.norm();
            assert!(difference < 1e-12, "case {case}: {difference:e}");
        }
    }

    /// A non-positive or non-finite interval is refused, and the model is left as it was.
    #[test]
    fn a_rebuild_refuses_a_bad_interval() {
        let mut rng = ChaCha8Rng::seed_from_u64(13);
        let point = random_point(&mut rng);
        let noise = random_noise(&mut rng, true);
        let mut model = StructuredModel::new(&point, &noise, 0.002, 3).unwrap();
        let before = model.transition_matrix();
        for interval_s in [-0.002, 0.0, f64::NAN, f64::INFINITY] {
            assert_eq!(
                model.rebuild(&point, &noise, interval_s, 3),
                Err(NavError::InvalidTimeStep)
            );
        }
        assert_eq!(
            model.transition_matrix().map(f64::to_bits),
            before.map(f64::to_bits)
        );
    }

    /// Rebuilding a model in place with fewer noise sources leaves no trace of the earlier
    /// ones: the same `Qd` as a model built afresh (accelerometer walk only; no walk).
    #[test]
    fn a_rebuilt_model_forgets_the_previous_walks() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let point = random_point(&mut rng);
        let both = random_noise(&mut rng, true);
        let accel_only = ProcessNoise {
            gyro_bias_walk_rad_s2_per_sqrt_hz: 0.0,
            ..both
        };
        let gyro_only = ProcessNoise {
            accel_bias_walk_mps3_per_sqrt_hz: 0.0,
            ..both
        };
        let none = random_noise(&mut rng, false);
        for noise in [accel_only, gyro_only, none] {
            let mut model = StructuredModel::new(&point, &both, 0.002, 3).unwrap();
            model.rebuild(&point, &noise, 0.002, 3).unwrap();
            let fresh = StructuredModel::new(&point, &noise, 0.002, 3).unwrap();
            assert_eq!(
                model.process_noise_matrix().map(f64::to_bits),
                fresh.process_noise_matrix().map(f64::to_bits)
            );
        }
    }

    /// The table of `1/n!`: each entry times `n!` is 1 (the high orders' terms are too small
    /// for the model-equality tests to see a wrong coefficient).
    #[test]
    fn inverse_factorials_are_the_reciprocals_of_the_factorials() {
        let mut factorial = 1.0_f64;
        for (n, inverse) in INVERSE_FACTORIALS.iter().enumerate() {
            if n > 0 {
                factorial *= n as f64;
            }
            assert!((inverse * factorial - 1.0).abs() < 1e-15, "1/{n}!");
        }
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
