//! The row kernel of the covariance propagation, for targets with f64 SIMD (x86-64 SSE2,
//! AArch64 NEON): `U = [Φ E] P` as nine rows of 24, each a linear combination of rows of
//! `P` (`U_i = Σ_k F_ik P_k`: axpys over 24 contiguous values, which the compiler
//! vectorises), and the new `P_dd` a block row (three rows) at a time across its output
//! columns.
//!
//! **Same bits as the block kernel** (`super::columns` and
//! `dynamic_pair`, the Cortex-M7's): every element is the same sequence of IEEE operations,
//! the first product and then each further product added in the same term order,
//! `((F_i0 P_0j + F_i1 P_1j) + F_i2 P_2j) + …` ([`crate::block`]); only the loops are nested
//! the other way, which changes no element's arithmetic. The rows of `P` are read as its
//! columns (nalgebra stores column-major): `P` is exactly symmetric whenever it is propagated
//! (every writer keeps it so: the updates and the reset write both triangles, and
//! [`crate::filter::ErrorStateFilter::set_covariance`] symmetrises), so column `k` is row `k`.

use core::borrow::Borrow;

use super::{
    BorderBiasInputs, StructuredModel, ATT, BIAS_A, BIAS_G, F_ROW_TERMS, POS, SCALE_A, SCALE_G, VEL,
};
use crate::block::{Block, Row};
use crate::discretise::CovarianceMatrix;
use crate::state::{BLOCK_DIMENSION, CALIBRATION_DIMENSION, DYNAMIC_DIMENSION, STATE_DIMENSION};

/// Coefficients of one δp or δv row of `F` over the kernels' terms.
const F_ROW_LENGTH: usize = F_ROW_TERMS * BLOCK_DIMENSION;

/// A row over the 24 states.
type StateRow = [f64; STATE_DIMENSION];

/// `U = [Φ E] P`, rows ϑ, δp, δv (the dynamic states); row `i`'s element `j` is `U_ij` (state `j`'s column).
pub(super) type ProjectedRows = [StateRow; DYNAMIC_DIMENSION];

/// Read where an index is out of range (constant indices never are).
const NAN_ROW: StateRow = [f64::NAN; STATE_DIMENSION];

/// Columns summed together: a chunk of a row whose sums (three rows at once, see
/// [`combinations`]) stay in registers across all the terms. With AVX (16 registers of four):
/// 12 columns, 9 registers; otherwise (SSE2, 16 registers of two) 4 columns, 6 registers: 12
/// would need 18 and spill. Measured on the host replay (x86-64, median of five 300 s runs):
/// AVX2 1,097,000 frames/s with 12 against 1,050,000 with 8; SSE2 846,000 with 4 against
/// 820,000 with 8 and 785,000 with 12. Divides the 24 states.
const LANES: usize = if cfg!(target_feature = "avx") { 12 } else { 4 };

/// Chunks of [`LANES`] columns in a row (whole: checked at compile time).
const CHUNKS: usize = STATE_DIMENSION / LANES;
const _: () = assert!(CHUNKS * LANES == STATE_DIMENSION);

/// A chunk of [`LANES`] columns of a row.
type Chunk = [f64; LANES];

/// Read where a chunk is out of range (constant indices never are).
const NAN_CHUNK: Chunk = [f64::NAN; LANES];

/// Row `k` of a symmetric `P`: its column `k`.
#[inline(always)]
fn row(p: &CovarianceMatrix, k: usize) -> &StateRow {
    p.data.0.get(k).unwrap_or(&NAN_ROW)
}

/// Chunk `index` (columns `LANES·index ..`) of a row.
#[inline(always)]
fn chunk(row: &StateRow, index: usize) -> &Chunk {
    row.get(index * LANES..(index + 1) * LANES)
        .and_then(|values| <&Chunk>::try_from(values).ok())
        .unwrap_or(&NAN_CHUNK)
}

/// `Σ_k c_mk r_k` element-wise for `M` coefficient sets `c_m` over the same rows, each sum
/// left to right from the first product (the block kernels' order). The `M` sums are built
/// together: each row is read once for all of them, and their `M` chains of dependent
/// additions run side by side (one chain alone waits on each addition's latency). Inlined at
/// each call: `W`, `N` and `M` are constants, so the sums stay in registers across the `N`
/// terms. The rows are given by value or by reference.
#[inline(always)]
fn combinations<const W: usize, const N: usize, const M: usize, R: Borrow<[f64; W]>>(
    coefficients: &[[f64; N]; M],
    rows: &[R; N],
) -> [[f64; W]; M] {
    let mut terms = rows.iter().enumerate();
    let Some((_, r0)) = terms.next() else {
        return [[0.0; W]; M];
    };
    let mut sums = coefficients.map(|c| {
        let c0 = c.first().copied().unwrap_or(f64::NAN);
        r0.borrow().map(|x| x * c0)
    });
    for (k, r) in terms {
        for (sum, c) in sums.iter_mut().zip(coefficients) {
            let ck = c.get(k).copied().unwrap_or(f64::NAN);
            for (s, x) in sum.iter_mut().zip(r.borrow()) {
                *s += x * ck;
            }
        }
    }
    sums
}

/// `mᵀ` of a small matrix given as rows.
#[inline(always)]
fn transposed<const R: usize, const C: usize>(m: &[[f64; C]; R]) -> [[f64; R]; C] {
    core::array::from_fn(|k| {
        core::array::from_fn(|s| {
            m.get(s)
                .and_then(|row| row.get(k))
                .copied()
                .unwrap_or(f64::NAN)
        })
    })
}

/// [`combinations`] of whole rows into `out`, a chunk of [`LANES`] columns at a time.
#[inline(always)]
fn combinations_of_rows<const N: usize, const M: usize>(
    out: &mut [StateRow],
    coefficients: &[[f64; N]; M],
    rows: &[&StateRow; N],
) {
    for index in 0..CHUNKS {
        let chunks = rows.map(|r| chunk(r, index));
        let sums = combinations(coefficients, &chunks);
        for (out, sum) in out.iter_mut().zip(&sums) {
            if let Some(target) = out.get_mut(index * LANES..(index + 1) * LANES) {
                target.copy_from_slice(sum);
            }
        }
    }
}

/// The rows `bias + diag(input) scale` over three states: the scale factors folded into
/// the biases (`P_{bg,j} + ω_m P_{λg,j}`, module docs of [`super`]).
#[inline(always)]
fn folded_rows(p: &CovarianceMatrix, bias: usize, scale: usize, input: Row) -> [StateRow; 3] {
    let mut rows = [*row(p, bias), *row(p, bias + 1), *row(p, bias + 2)];
    for (offset, (folded, factor)) in rows.iter_mut().zip(input).enumerate() {
        for (value, x) in folded.iter_mut().zip(row(p, scale + offset)) {
            *value += x * factor;
        }
    }
    rows
}

/// The blocks of `F`'s δp rows and of its δv rows over the terms ϑ, p, v, bg, ba (the
/// block kernel's term order; the scale factors are folded into the biases).
#[inline(always)]
fn dynamic_rows_of_f(model: &StructuredModel) -> [[&Block; F_ROW_TERMS]; 2] {
    let t = &model.transition;
    let [_, gyro_position, gyro_velocity] = &model.gyro_bias_column;
    let [accel_position, accel_velocity] = &model.accel_bias_column;
    [
        [
            &t.position_attitude,
            &t.position_position,
            &t.position_velocity,
            gyro_position,
            accel_position,
        ],
        [
            &t.velocity_attitude,
            &t.velocity_position,
            &t.velocity_velocity,
            gyro_velocity,
            accel_velocity,
        ],
    ]
}

/// Row `i` of one of those block rows: its coefficients side by side.
#[inline(always)]
fn row_of_f(blocks: [&Block; F_ROW_TERMS], i: usize) -> [f64; F_ROW_LENGTH] {
    let mut out = [0.0; F_ROW_LENGTH];
    let rows = blocks.map(|block| crate::block::row_at(block, i));
    for (slot, value) in out.iter_mut().zip(rows.iter().flatten()) {
        *slot = *value;
    }
    out
}

/// Row `i` of `F`'s ϑ rows over their non-zero blocks, `Φ_ϑϑ` and `E_gϑ` (its ϑp, ϑv and
/// accelerometer blocks are zero): 6 coefficients.
#[inline(always)]
fn attitude_row_of_f(model: &StructuredModel, i: usize) -> [f64; 6] {
    let [gyro_attitude, _, _] = &model.gyro_bias_column;
    let ([f0, f1, f2], [e0, e1, e2]) = (
        crate::block::row_at(&model.transition.attitude_attitude, i),
        crate::block::row_at(gyro_attitude, i),
    );
    [f0, f1, f2, e0, e1, e2]
}

/// The border's `M C_jᵀ` added to the folded rows: gyro row `k` of column `j` gains
/// value `k` of state `j`'s bias input, accelerometer row `k` value `3 + k` (the block
/// kernel adds them after folding, in the same order).
#[inline(always)]
fn add_border(gyro: &mut [StateRow; 3], accel: &mut [StateRow; 3], border: &BorderBiasInputs) {
    for (j, input) in border.state_columns.iter().enumerate() {
        let [g0, g1, g2, a0, a1, a2] = *input;
        for (rows, values) in [(&mut *gyro, [g0, g1, g2]), (&mut *accel, [a0, a1, a2])] {
            for (row, value) in rows.iter_mut().zip(values) {
                if let Some(slot) = row.get_mut(j) {
                    *slot += value;
                }
            }
        }
    }
}

/// `U = [Φ E] P` (module docs of [`super`]): attitude rows `Φ_ϑϑ P_ϑ + E_gϑ G`, position
/// and velocity rows over `P_ϑ, P_p, P_v, G, A` (`G`, `A` the folded gyro and
/// accelerometer rows, with the border's `M Cᵀ` when there is one), in the block kernel's
/// term order.
#[inline(never)]
pub(super) fn projected_rows(
    model: &StructuredModel,
    p: &CovarianceMatrix,
    u: &mut ProjectedRows,
    border: Option<&BorderBiasInputs>,
) {
    let mut gyro = folded_rows(p, BIAS_G, SCALE_G, model.measured_rate_rad_s);
    let mut accel = folded_rows(p, BIAS_A, SCALE_A, model.measured_specific_force_mps2);
    if let Some(border) = border {
        add_border(&mut gyro, &mut accel, border);
    }
    let [g0, g1, g2] = gyro;
    let [a0, a1, a2] = accel;
    let (t0, t1, t2) = (row(p, ATT), row(p, ATT + 1), row(p, ATT + 2));
    let dynamic_rows = [
        t0,
        t1,
        t2,
        row(p, POS),
        row(p, POS + 1),
        row(p, POS + 2),
        row(p, VEL),
        row(p, VEL + 1),
        row(p, VEL + 2),
        &g0,
        &g1,
        &g2,
        &a0,
        &a1,
        &a2,
    ];
    let attitude_rows = [t0, t1, t2, &g0, &g1, &g2];
    let (attitude, rest) = u.split_at_mut(3);
    let (position, velocity) = rest.split_at_mut(3);
    let attitude_coefficients = [0, 1, 2].map(|i| attitude_row_of_f(model, i));
    combinations_of_rows(attitude, &attitude_coefficients, &attitude_rows);
    let [position_blocks, velocity_blocks] = dynamic_rows_of_f(model);
    for (out, blocks) in [(position, position_blocks), (velocity, velocity_blocks)] {
        let coefficients = [0, 1, 2].map(|i| row_of_f(blocks, i));
        combinations_of_rows(out, &coefficients, &dynamic_rows);
    }
}

/// `U`'s column block at state `column` (its rows ϑ, δp, δv as three blocks).
#[inline(always)]
pub(super) fn column_block(u: &ProjectedRows, column: usize) -> [Block; 3] {
    let part = |r: usize| -> Row {
        u.get(r)
            .and_then(|values| values.get(column..column + 3))
            .and_then(|values| <[f64; 3]>::try_from(values).ok())
            .unwrap_or([f64::NAN; 3])
    };
    [
        [part(ATT), part(ATT + 1), part(ATT + 2)],
        [part(POS), part(POS + 1), part(POS + 2)],
        [part(VEL), part(VEL + 1), part(VEL + 2)],
    ]
}

/// Adds `blocks` (rows ϑ, δp, δv) to `U`'s column block at state `column`, element by
/// element as the block kernel's `add` (a zero block is added too: `−0 + 0` is `+0`).
#[inline(always)]
pub(super) fn add_to_column(u: &mut ProjectedRows, column: usize, blocks: &[Block; 3]) {
    for (u_row, q_row) in u.iter_mut().zip(blocks.iter().flatten()) {
        let part = u_row.get_mut(column..column + 3).into_iter().flatten();
        for (value, q) in part.zip(q_row) {
            *value += q;
        }
    }
}

/// Whether `U`'s calibration columns (the new `P_dc`) are finite: `x · 0` summed per column
/// ([`crate::block::FiniteCheck`]'s test) across the rows, so the sums are independent and
/// vectorised (one running sum would be a chain of 135 dependent additions).
#[inline(always)]
pub(super) fn calibration_finite(u: &ProjectedRows) -> bool {
    let mut sums = [0.0; CALIBRATION_DIMENSION];
    for row in u {
        let values = row.get(DYNAMIC_DIMENSION..).unwrap_or(&[f64::NAN]);
        for (sum, x) in sums.iter_mut().zip(values) {
            *sum += x * 0.0;
        }
    }
    crate::block::all_finite(&sums)
}

/// Writes `U`'s calibration columns as the new `P_dc`: row `r` into column `r` of `P`
/// (rows 9..24, contiguous) and mirrored into row `r` of columns 9..24.
#[inline(always)]
pub(super) fn write_calibration_columns(p: &mut CovarianceMatrix, u: &ProjectedRows) {
    let (dynamic_columns, calibration_columns) = p.data.0.split_at_mut(DYNAMIC_DIMENSION);
    for (column, u_row) in dynamic_columns.iter_mut().zip(u) {
        let targets = column.iter_mut().skip(DYNAMIC_DIMENSION);
        for (target, value) in targets.zip(u_row.iter().skip(DYNAMIC_DIMENSION)) {
            *target = *value;
        }
    }
    for (offset, column) in calibration_columns.iter_mut().enumerate() {
        for (target, u_row) in column.iter_mut().zip(u) {
            if let Some(value) = u_row.get(DYNAMIC_DIMENSION + offset) {
                *target = *value;
            }
        }
    }
}

/// Output columns of the new `P_dd` summed together in [`dynamic_blocks`]: the δp and δv
/// columns, 6, padded to whole vector registers (8 with AVX's four lanes; 6 are three of
/// SSE2's two, which need no padding). The padding's sums are not read.
const PAIR_COLUMNS: usize = if cfg!(target_feature = "avx") { 8 } else { 6 };

/// The new `P_dd` without noise, pairs ϑϑ, ϑp, ϑv, pp, pv, vv: element `(r, s)` is
/// `Σ_k y_rk F_sk` over `y_r = (U_r,ϑpv, G_r, A_r)` (`U`'s dynamic columns, then its folded
/// gyro and accelerometer columns `folded_gyro`, `folded_accel`), computed across the output
/// columns `s` at once: `Σ_k y_rk (Fᵀ)_k`. The ϑ columns skip the zero blocks of `F`'s
/// attitude rows (as `attitude_pair` does), so only `Φ_ϑϑ` and `E_gϑ` are summed there.
#[inline(never)]
pub(super) fn dynamic_blocks(
    model: &StructuredModel,
    u: &ProjectedRows,
    folded_gyro: &[Block; 3],
    folded_accel: &[Block; 3],
) -> [Block; 6] {
    // Rows δp, δv of F over (ϑ, p, v, bg, ba), transposed: the terms k of 6 columns s,
    // padded to [`PAIR_COLUMNS`] with zero columns (their sums are not read).
    let [position_blocks, velocity_blocks] = dynamic_rows_of_f(model);
    let f_rows: [[f64; F_ROW_LENGTH]; PAIR_COLUMNS] = core::array::from_fn(|s| {
        let blocks = if s < 3 {
            position_blocks
        } else {
            velocity_blocks
        };
        if s < 6 {
            row_of_f(blocks, s % 3)
        } else {
            [0.0; F_ROW_LENGTH]
        }
    });
    let f_transposed = transposed(&f_rows);
    // Rows ϑ of F over (ϑ, bg), transposed: 6 terms of 3 columns, padded to 4 (not read).
    let attitude_row = |i: usize| attitude_row_of_f(model, i);
    let attitude_transposed =
        transposed(&[attitude_row(0), attitude_row(1), attitude_row(2), [0.0; 6]]);
    // y_r for the three rows of each block row of U, and their products across the
    // columns, the three rows together.
    let folded = folded_gyro.iter().zip(folded_accel);
    let mut products = [[[0.0; PAIR_COLUMNS]; 3]; 3];
    let mut attitude_products = [[0.0; 4]; 3];
    for (block_row, (out, (gyro, accel))) in products.iter_mut().zip(folded).enumerate() {
        let y = [0, 1, 2].map(|i| {
            let u_row = u.get(3 * block_row + i).unwrap_or(&NAN_ROW);
            let [u0, u1, u2, u3, u4, u5, u6, u7, u8, ..] = *u_row;
            let [g0, g1, g2] = crate::block::row_at(gyro, i);
            let [a0, a1, a2] = crate::block::row_at(accel, i);
            [u0, u1, u2, u3, u4, u5, u6, u7, u8, g0, g1, g2, a0, a1, a2]
        });
        *out = combinations(&y, &f_transposed);
        if block_row == 0 {
            let y_attitude =
                y.map(|[u0, u1, u2, _, _, _, _, _, _, g0, g1, g2, ..]| [u0, u1, u2, g0, g1, g2]);
            attitude_products = combinations(&y_attitude, &attitude_transposed);
        }
    }
    let [attitude_rows, position_rows, velocity_rows] = products;
    let left = |rows: [[f64; PAIR_COLUMNS]; 3]| rows.map(|[x, y, z, ..]| [x, y, z]);
    let right = |rows: [[f64; PAIR_COLUMNS]; 3]| rows.map(|[_, _, _, x, y, z, ..]| [x, y, z]);
    [
        attitude_products.map(|[x, y, z, _]| [x, y, z]),
        left(attitude_rows),
        right(attitude_rows),
        left(position_rows),
        right(position_rows),
        right(velocity_rows),
    ]
}

#[cfg(test)]
mod tests {
    // The row kernel against the block kernel, bit for bit: in
    // `super::super::tests::the_row_kernel_equals_the_block_kernel_bit_for_bit`, beside the
    // random covariances and models it shares with the other equality tests.
}
