//! Structured (block-sparse) covariance propagation, measurement update and reset: the same
//! arithmetic as the dense reference (`crate::discretise::discretise` with
//! `crate::filter::ErrorStateFilter::predict`, and the dense Joseph update), computed only
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
//! States beside the 24 whose transition columns are `E M` (a bias border of the optional
//! blocks, [`crate::state::OptionalBlock`]: `ε`, cross-covariance `C = P_xε`) fold in the
//! same way. In
//! the bordered product `[F, E M] [[P, C], [Cᵀ, P_εε]]` the 24 columns are
//! `U = [Φ E] P + E M Cᵀ`: column `j`'s folded bias rows gain `M C_jᵀ`; the border's columns
//! are the new `C⁺_d`; and the new `P_dd = U [Φ E]ᵀ + C⁺_d Mᵀ E_dᵀ + Qd_dd`: row `r` of `U`'s
//! folded bias columns gains `M C⁺_rᵀ` (`BorderBiasInputs`). Without such states nothing
//! is added (the same operations as before, the same bits).
//!
//! ## Update
//! For any gain `K` the Joseph form expands exactly (Bucy & Joseph 1968) to
//! `(I − KH) P (I − KH)ᵀ + K R Kᵀ = P − K Mᵀ − M Kᵀ + K S Kᵀ` with `M = P Hᵀ`,
//! `S = H P Hᵀ + R`; element-wise `P⁺_ij = (P_ij + (K_i S − M_i)·K_j) − K_i·M_j`, O(n²)
//! with 6 multiply-adds per element of the upper triangle. `M` is summed only over the non-zero
//! 3×3 blocks of `H` (found at run time, so a measurement referred to a later time with
//! `H (I − AΔ)` is handled with its extra bias/scale-factor/velocity columns). The six
//! multiply-adds of an element are done in one pass over `P` (each element loaded and stored
//! once), a few rows at a time: two on the Cortex-M7 (their twelve coefficients fill its
//! sixteen double registers), four on the host (one 256-bit vector per column); each
//! element's operations are the same either way, so are its bits.
//!
//! ## In place, without a copy
//! Propagation and update overwrite `P` where it lies (a 24×24 copy costs thousands of
//! instructions on the target). They write new values to one triangle only, so while they
//! run the other (and a saved diagonal) still holds the old `P`: it is read where an old
//! value is needed after its twin was overwritten, and it is the roll-back copy if the result
//! is not finite; on success the new triangle is mirrored into the other. The updates write
//! the upper triangle; the target's propagation writes the new `P_dc` into the lower one
//! (rows 9..24 of columns 0..9, which no later step of it reads) and copies it up after the
//! check (`columns`). The arithmetic is done on plain 3×3 arrays (`crate::block`).
//!
//! ## Reset
//! The reset Jacobian is the identity except the attitude and installation diagonal blocks,
//! so only the block rows and columns of those two blocks change.
//!
//! ## Files
//! `model` rebuilds the model, `propagate` propagates the state and covariance (the 3×3
//! block kernel of the target, whose product `U = [Φ E] P` is in `columns`), `rows` is the
//! host's row kernel, `update` the measurement
//! update, `reset` the covariance reset and `referral` refers a measurement to a later time.

use crate::block::{Block, Row};
use crate::state::{
    StateBlock, ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, DYNAMIC_DIMENSION, GYRO_BIAS,
    GYRO_SCALE_FACTOR, POSITION, STAR_INSTALLATION, STATE_DIMENSION, VELOCITY,
};

#[cfg(any(test, not(target_arch = "arm")))]
mod rows;

/// Terms of a δp or δv row of `F` in the kernels: the blocks ϑ, δp, δv, bg, ba (the
/// scale-factor columns folded into the bias ones, the installation column zero).
const F_ROW_TERMS: usize = 5;

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

// Block offsets (first state index of each block) as constants, for const generic arguments.
// Named by block, never by a single letter: `P` is the covariance throughout.
const ATT: usize = ATTITUDE.index();
const POS: usize = POSITION.index();
const VEL: usize = VELOCITY.index();
const BIAS_G: usize = GYRO_BIAS.index();
const BIAS_A: usize = ACCEL_BIAS.index();
const INSTALL: usize = STAR_INSTALLATION.index();
const SCALE_G: usize = GYRO_SCALE_FACTOR.index();
const SCALE_A: usize = ACCEL_SCALE_FACTOR.index();

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

/// The discrete model of one interval in block form (module docs): the non-zero blocks of
/// `F` and of `Qd`. Equal to `crate::discretise::discretise` of
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

/// One 3-vector per state: row `j` of a 24×3 matrix such as `P Hᵀ` or `K`.
pub(crate) type StateRows = [Row; STATE_DIMENSION];

/// An equivalent-bias 6-vector: gyro axes x, y, z (values 0..3), then accelerometer axes
/// (values 3..6).
pub(crate) type BiasInput = [f64; 6];

/// What states beside the 24 whose transition columns are `E M` (bias columns of `F` times a
/// map `M`: a bias border of the optional blocks, [`crate::state::OptionalBlock`]) add to the
/// propagation (module docs, "Propagation"): with `C` their cross-covariance and `C⁺` its
/// propagated value, `U` gains `E M Cᵀ` and the new `P_dd` gains `C⁺_d Mᵀ E_dᵀ`. Both are
/// additions to the folded bias inputs the kernels already multiply by `E`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BorderBiasInputs {
    /// `M C_jᵀ` for each state `j` (the old `C`): added to column `j`'s folded bias rows.
    pub(crate) state_columns: [BiasInput; STATE_DIMENSION],
    /// `M C⁺_rᵀ` for each dynamic row `r` (the new `C`): added to row `r` of `U`'s folded
    /// bias columns.
    pub(crate) dynamic_rows: [BiasInput; DYNAMIC_DIMENSION],
}

impl BorderBiasInputs {
    /// All zero.
    pub(crate) const ZERO: Self = Self {
        state_columns: [[0.0; 6]; STATE_DIMENSION],
        dynamic_rows: [[0.0; 6]; DYNAMIC_DIMENSION],
    };
}

/// `P Hᵀ` and `H P Hᵀ` of a measurement, summed over the non-zero 3×3 blocks of `H` only
/// (module docs).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ObservedCovariance<'a> {
    /// `M = P Hᵀ`, row `j` for state `j`.
    products: &'a StateRows,
    /// `H P Hᵀ` (without `R`).
    projected: Block,
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

#[cfg(any(test, target_arch = "arm"))]
mod columns;
#[cfg(any(test, feature = "dense-reference"))]
mod dense;
mod model;
mod propagate;
mod referral;
mod reset;
#[cfg(test)]
pub(crate) mod tests;
mod update;

pub use referral::{refer_to_later_time_at, refer_to_later_time_in_place};
pub(crate) use reset::reset_covariance;
pub(crate) use update::{
    add_gain_times, corrected_state_is_finite, joseph_update, observed_blocks,
};
