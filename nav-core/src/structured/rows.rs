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

use core::borrow::Borrow;

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
/// terms (six SSE2 or NEON registers of two, three AVX2 registers of four). Measured on the
/// host replay (x86-64): 12 beats 4, 8 and 24 with SSE2 and with AVX2.
const LANES: usize = 12;

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
/// values stays in registers across the `N` terms. The rows are given by value or by
/// reference.
#[inline(always)]
fn combination<const W: usize, const N: usize, R: Borrow<[f64; W]>>(
    coefficients: &[f64; N],
    rows: &[R; N],
) -> [f64; W] {
    let mut terms = coefficients.iter().zip(rows);
    let Some((c0, r0)) = terms.next() else {
        return [0.0; W];
    };
    let mut sum = r0.borrow().map(|x| x * c0);
    for (c, r) in terms {
        for (s, x) in sum.iter_mut().zip(r.borrow()) {
            *s += x * c;
        }
    }
    sum
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

/// [`combination`] of whole rows, a chunk of [`LANES`] columns at a time.
#[inline(always)]
fn combination_of_rows<const N: usize>(
    out: &mut StateRow,
    coefficients: &[f64; N],
    rows: &[&StateRow; N],
) {
    for (index, out) in out.chunks_exact_mut(LANES).enumerate() {
        let chunks = rows.map(|r| chunk(r, index));
        out.copy_from_slice(&combination(coefficients, &chunks));
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
pub(super) fn projected_rows(model: &StructuredModel, p: &CovarianceMatrix, u: &mut ProjectedRows) {
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
    let (attitude, rest) = u.split_at_mut(3);
    let (position, velocity) = rest.split_at_mut(3);
    for (out, (f, e)) in attitude
        .iter_mut()
        .zip(t.attitude_attitude.iter().zip(gyro_attitude))
    {
        let [f0, f1, f2] = *f;
        let [e0, e1, e2] = *e;
        combination_of_rows(out, &[f0, f1, f2, e0, e1, e2], &attitude_rows);
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
            combination_of_rows(out, &coefficients, &dynamic_rows);
        }
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
        [part(A), part(A + 1), part(A + 2)],
        [part(P), part(P + 1), part(P + 2)],
        [part(V), part(V + 1), part(V + 2)],
    ]
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
    // Rows δp, δv of F over (ϑ, p, v, bg, ba), transposed: 15 terms k of 6 columns s.
    let rows_of_f = |blocks: [&Block; 5], i: usize| {
        let pick = |block: &Block| block.get(i).copied().unwrap_or([f64::NAN; 3]);
        let [fa, fp, fv, eg, ea] = blocks.map(pick);
        concatenated([&fa, &fp, &fv, &eg, &ea])
    };
    let position_blocks = [
        &t.position_attitude,
        &t.position_position,
        &t.position_velocity,
        gyro_position,
        accel_position,
    ];
    let velocity_blocks = [
        &t.velocity_attitude,
        &t.velocity_position,
        &t.velocity_velocity,
        gyro_velocity,
        accel_velocity,
    ];
    let f_transposed = transposed(&[
        rows_of_f(position_blocks, 0),
        rows_of_f(position_blocks, 1),
        rows_of_f(position_blocks, 2),
        rows_of_f(velocity_blocks, 0),
        rows_of_f(velocity_blocks, 1),
        rows_of_f(velocity_blocks, 2),
    ]);
    // Rows ϑ of F over (ϑ, bg), transposed: 6 terms of 3 columns.
    let attitude_row = |i: usize| {
        let pick = |block: &Block| block.get(i).copied().unwrap_or([f64::NAN; 3]);
        let ([f0, f1, f2], [e0, e1, e2]) = (pick(&t.attitude_attitude), pick(gyro_attitude));
        [f0, f1, f2, e0, e1, e2]
    };
    let attitude_transposed = transposed(&[attitude_row(0), attitude_row(1), attitude_row(2)]);
    // Row r of U with its folded columns: y_r, then the products across the columns.
    let mut products = [[0.0; 6]; DYNAMIC_DIMENSION];
    let mut attitude_products = [[0.0; 3]; 3];
    let folded_rows = folded_gyro
        .iter()
        .flatten()
        .zip(folded_accel.iter().flatten());
    for (r, (u_row, (gyro_row, accel_row))) in u.iter().zip(folded_rows).enumerate() {
        let [u0, u1, u2, u3, u4, u5, u6, u7, u8, ..] = *u_row;
        let [g0, g1, g2] = *gyro_row;
        let [a0, a1, a2] = *accel_row;
        let y = [u0, u1, u2, u3, u4, u5, u6, u7, u8, g0, g1, g2, a0, a1, a2];
        if let Some(out) = products.get_mut(r) {
            *out = combination(&y, &f_transposed);
        }
        if let Some(out) = attitude_products.get_mut(r) {
            *out = combination(&[u0, u1, u2, g0, g1, g2], &attitude_transposed);
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
