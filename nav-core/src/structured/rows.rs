//! The row kernel of the covariance propagation, for targets with f64 SIMD (x86-64 SSE2,
//! AArch64 NEON): `U = [Φ E] P` as nine rows of 24, each a linear combination of rows of
//! `P` (`U_i = Σ_k F_ik P_k`: axpys over 24 contiguous values, which the compiler
//! vectorises), and the new `P_dd` a row at a time across its output columns.
//!
//! **Same bits as the block kernel** ([`StructuredModel::propagate_column`] and
//! `dynamic_pair`, the Cortex-M7's): every element is the same sequence of IEEE operations,
//! the first product and then each further product added in the same term order,
//! `((F_i0 P_0j + F_i1 P_1j) + F_i2 P_2j) + …` ([`crate::block`]); only the loops are nested
//! the other way, which changes no element's arithmetic. The rows of `P` are read as its
//! columns (nalgebra stores column-major): `P` is exactly symmetric whenever it is propagated
//! (every writer keeps it so: the updates and the reset write both triangles, and
//! [`crate::filter::ErrorStateFilter::set_covariance`] symmetrises), so column `k` is row `k`.

use super::{StructuredModel, A, BA, BG, P, SA, SG, V};
use crate::block::{Block, Row};
use crate::discretise::CovarianceMatrix;
use crate::state::STATE_DIMENSION;

/// A row over the 24 states.
type StateRow = [f64; STATE_DIMENSION];

/// The dynamic states (ϑ, δp, δv): the rows of `U`.
const DYNAMIC_DIMENSION: usize = 9;

/// `U = [Φ E] P`, rows ϑ, δp, δv; row `i`'s element `j` is `U_ij` (state `j`'s column).
pub(super) type ProjectedRows = [StateRow; DYNAMIC_DIMENSION];

/// Read where an index is out of range (constant indices never are).
const NAN_ROW: StateRow = [f64::NAN; STATE_DIMENSION];

/// Columns summed together: a chunk of a row whose sum stays in registers across all the
/// terms (four SSE2 or NEON registers of two).
const LANES: usize = 8;

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

/// `Σ_k c_k r_k` element-wise, summed left to right from the first product (the block
/// kernels' order). Inlined at each call: `N` and `W` are constants, so the sum of `W`
/// values stays in registers across the `N` terms.
#[inline(always)]
fn combination<const W: usize, const N: usize>(
    coefficients: &[f64; N],
    rows: &[&[f64; W]; N],
) -> [f64; W] {
    let mut terms = coefficients.iter().zip(rows);
    let Some((c0, r0)) = terms.next() else {
        return [0.0; W];
    };
    let mut sum = r0.map(|x| x * c0);
    for (c, r) in terms {
        for (s, x) in sum.iter_mut().zip(r.iter()) {
            *s += x * c;
        }
    }
    sum
}

/// [`combination`] of whole rows, a chunk of [`LANES`] columns at a time.
#[inline(always)]
fn combination_of_rows<const N: usize>(coefficients: &[f64; N], rows: &[&StateRow; N]) -> StateRow {
    let mut out = [0.0; STATE_DIMENSION];
    for (index, out) in out.chunks_exact_mut(LANES).enumerate() {
        let chunks = rows.map(|r| chunk(r, index));
        out.copy_from_slice(&combination(coefficients, &chunks));
    }
    out
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

/// Three coefficient rows `(c_0 | c_1 | …)` of blocks side by side: the coefficients of
/// one row of `F` over the blocks' columns.
#[inline(always)]
fn concatenated<const N: usize>(blocks: [&Row; N]) -> [f64; 15] {
    let mut out = [0.0; 15];
    for (slot, value) in out.iter_mut().zip(blocks.iter().flat_map(|row| row.iter())) {
        *slot = *value;
    }
    out
}

/// `U = [Φ E] P` (module docs of [`super`]): attitude rows `Φ_ϑϑ P_ϑ + E_gϑ G`, position
/// and velocity rows over `P_ϑ, P_p, P_v, G, A` (`G`, `A` the folded gyro and
/// accelerometer rows), in the block kernel's term order.
#[inline(never)]
pub(super) fn projected_rows(model: &StructuredModel, p: &CovarianceMatrix) -> ProjectedRows {
    let [g0, g1, g2] = folded_rows(p, BG, SG, model.measured_rate_rad_s);
    let [a0, a1, a2] = folded_rows(p, BA, SA, model.measured_specific_force_mps2);
    let (t0, t1, t2) = (row(p, A), row(p, A + 1), row(p, A + 2));
    let dynamic_rows = [
        t0,
        t1,
        t2,
        row(p, P),
        row(p, P + 1),
        row(p, P + 2),
        row(p, V),
        row(p, V + 1),
        row(p, V + 2),
        &g0,
        &g1,
        &g2,
        &a0,
        &a1,
        &a2,
    ];
    let attitude_rows = [t0, t1, t2, &g0, &g1, &g2];
    let t = &model.transition;
    let [gyro_attitude, gyro_position, gyro_velocity] = &model.gyro_bias_column;
    let [accel_position, accel_velocity] = &model.accel_bias_column;
    let mut u = [[0.0; STATE_DIMENSION]; DYNAMIC_DIMENSION];
    let (attitude, rest) = u.split_at_mut(3);
    let (position, velocity) = rest.split_at_mut(3);
    for (out, (f, e)) in attitude
        .iter_mut()
        .zip(t.attitude_attitude.iter().zip(gyro_attitude))
    {
        let [f0, f1, f2] = *f;
        let [e0, e1, e2] = *e;
        *out = combination_of_rows(&[f0, f1, f2, e0, e1, e2], &attitude_rows);
    }
    for (out, blocks) in [
        (
            position,
            [
                &t.position_attitude,
                &t.position_position,
                &t.position_velocity,
                gyro_position,
                accel_position,
            ],
        ),
        (
            velocity,
            [
                &t.velocity_attitude,
                &t.velocity_position,
                &t.velocity_velocity,
                gyro_velocity,
                accel_velocity,
            ],
        ),
    ] {
        let [fa, fp, fv, eg, ea] = blocks;
        for (i, out) in out.iter_mut().enumerate() {
            let pick = |block: &Block| block.get(i).copied().unwrap_or([f64::NAN; 3]);
            let (fa, fp, fv, eg, ea) = (pick(fa), pick(fp), pick(fv), pick(eg), pick(ea));
            let coefficients = concatenated([&fa, &fp, &fv, &eg, &ea]);
            *out = combination_of_rows(&coefficients, &dynamic_rows);
        }
    }
    u
}

/// `U`'s column block at state `column` (its rows ϑ, δp, δv as three blocks).
#[inline(always)]
pub(super) fn column_block(u: &ProjectedRows, column: usize) -> [Block; 3] {
    let entry = |r: usize, c: usize| {
        u.get(r)
            .and_then(|values| values.get(c))
            .copied()
            .unwrap_or(f64::NAN)
    };
    [A, P, V].map(|r| [0, 1, 2].map(|i| [0, 1, 2].map(|j| entry(r + i, column + j))))
}

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
    let t = &model.transition;
    let [gyro_attitude, gyro_position, gyro_velocity] = &model.gyro_bias_column;
    let [accel_position, accel_velocity] = &model.accel_bias_column;
    // Fᵀ over the δp and δv rows of F (columns s = 0..6), 15 terms k: ϑ, p, v, bg, ba.
    let mut transposed = [[0.0; 6]; 15];
    let rows_of_f: [[&Block; 5]; 2] = [
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
    ];
    for (block_row, blocks) in rows_of_f.iter().enumerate() {
        for (term_block, block) in blocks.iter().enumerate() {
            for (i, coefficients) in block.iter().enumerate() {
                for (j, coefficient) in coefficients.iter().enumerate() {
                    let slot = transposed
                        .get_mut(3 * term_block + j)
                        .and_then(|row| row.get_mut(3 * block_row + i));
                    if let Some(slot) = slot {
                        *slot = *coefficient;
                    }
                }
            }
        }
    }
    // Fᵀ over the ϑ rows (columns s = 0..3), 6 terms k: ϑ, bg.
    let mut transposed_attitude = [[0.0; 3]; 6];
    for (term_block, block) in [&t.attitude_attitude, gyro_attitude].iter().enumerate() {
        for (i, coefficients) in block.iter().enumerate() {
            for (j, coefficient) in coefficients.iter().enumerate() {
                let slot = transposed_attitude
                    .get_mut(3 * term_block + j)
                    .and_then(|row| row.get_mut(i));
                if let Some(slot) = slot {
                    *slot = *coefficient;
                }
            }
        }
    }
    // y_r for each row of U, and the products across the output columns.
    let transposed = transposed.each_ref();
    let transposed_attitude = transposed_attitude.each_ref();
    let mut products = [[0.0; 6]; DYNAMIC_DIMENSION];
    let mut attitude_products = [[0.0; 3]; 3];
    let block_rows = folded_gyro.iter().zip(folded_accel);
    for (block_index, (gyro, accel)) in block_rows.enumerate() {
        for (i, (gyro_row, accel_row)) in gyro.iter().zip(accel).enumerate() {
            let r = 3 * block_index + i;
            let (Some(u_row), Some(out)) = (u.get(r), products.get_mut(r)) else {
                continue;
            };
            let mut y = [0.0; 15];
            let values = u_row.iter().take(DYNAMIC_DIMENSION);
            for (slot, value) in y.iter_mut().zip(values.chain(gyro_row).chain(accel_row)) {
                *slot = *value;
            }
            *out = combination(&y, &transposed);
            if let Some(out) = attitude_products.get_mut(r) {
                let [y0, y1, y2, ..] = y;
                let [g0, g1, g2] = *gyro_row;
                *out = combination(&[y0, y1, y2, g0, g1, g2], &transposed_attitude);
            }
        }
    }
    let block_of = |first_row: usize, first_column: usize| -> Block {
        [0, 1, 2].map(|i| {
            [0, 1, 2].map(|j| {
                products
                    .get(first_row + i)
                    .and_then(|row| row.get(first_column + j))
                    .copied()
                    .unwrap_or(f64::NAN)
            })
        })
    };
    [
        attitude_products,
        block_of(A, 0),
        block_of(A, 3),
        block_of(P, 0),
        block_of(P, 3),
        block_of(V, 3),
    ]
}

#[cfg(test)]
mod tests {
    // The row kernel against the block kernel, bit for bit: in
    // `super::super::tests::the_row_kernel_equals_the_block_kernel_bit_for_bit`, beside the
    // random covariances and models it shares with the other equality tests.
}
