//! The block kernel of `U = [Φ E] P` (the Cortex-M7's; module docs of [`super`]): one
//! column block of three states at a time, one block row of `U` (ϑ, δp or δv) per call.
//!
//! A call holds the nine sums of its output block in registers and streams the inputs:
//! per term and per `k`, three values of `P` (or of the folded calibration rows) and three
//! coefficients of `F`, nine multiply-adds. Nine sums, three inputs and one coefficient fit
//! the 16 double registers of the FPv5-D16 without spilling; the block rows are separate
//! calls so that the compiler cannot interleave two of them (which spills). Every element is
//! summed as the textbook product of [`crate::block`]: the first product, then each further
//! product added in the term order ϑ, δp, δv, bg, ba and `k` order, so the bits equal those
//! of `block::mul`/`block::mul_add` and of the row kernel (`super::rows`).
//!
//! With a border ([`BorderBiasInputs`]) the folded rows of each column gain its `M C_jᵀ`.
//!
//! The calibration columns of `U` (the new `P_dc`) are written straight into the lower
//! triangle of `P` (rows 9..24 of columns 0..9), whose old values, by symmetry a copy of the
//! upper triangle, no later column block reads (the dynamic column blocks, which read them,
//! come first): the upper triangle keeps the old `P_dc` as the roll-back copy.

use super::{BiasInput, BorderBiasInputs, StructuredModel, BIAS_A, BIAS_G, SCALE_A, SCALE_G};
use crate::block::{Block, FiniteCheck, Row};
use crate::state::{BLOCK_DIMENSION, CALIBRATION_DIMENSION, DYNAMIC_DIMENSION, STATE_DIMENSION};

/// Three columns of `P` (a column block): column `j` holds row `j` of `P` by symmetry, so
/// `X_t[k][j]` of term `t` is `columns[j][3t + k]` for the dynamic terms.
pub(super) type Columns = [[f64; STATE_DIMENSION]; 3];

/// The folded calibration rows of a column block, by column `j`:
/// `P_bg + diag(ω_m) P_λg` (values 0..3) and `P_ba + diag(f_m) P_λa` (values 3..6).
type Folded = [[f64; 6]; 3];

/// The blocks of `F`'s δp rows or δv rows over the terms ϑ, δp, δv, bg, ba.
pub(super) type FRow<'a> = [&'a Block; super::F_ROW_TERMS];

/// Input `X_t[k][j]` of term `t` (0..3: ϑ, δp, δv from `P`; 3, 4: the folded gyro and
/// accelerometer rows).
#[inline(always)]
fn input(columns: &Columns, folded: &Folded, t: usize, k: usize, j: usize) -> f64 {
    let value = if t < 3 {
        columns.get(j).and_then(|c| c.get(3 * t + k))
    } else {
        folded.get(j).and_then(|c| c.get(3 * (t - 3) + k))
    };
    value.copied().unwrap_or(f64::NAN)
}

/// The three inputs `X_t[0..3][j]` of term `t` in column `j`: contiguous in memory (one
/// multiple load on the target).
#[inline(always)]
fn input_column(columns: &Columns, folded: &Folded, t: usize, j: usize) -> Row {
    [0, 1, 2].map(|k| input(columns, folded, t, k, j))
}

/// `acc + F_t X_t` for term `T` (or `F_t X_t` if `FIRST`): element `(i, j)` gets
/// `F_t[i][k] X_t[k][j]` added for `k = 0, 1, 2` in turn (as `block::mul_add`, or from the
/// first product as `block::mul`; IEEE multiplication commutes). Row `i` of `F_t` and
/// column `j` of `X_t` are each three contiguous values, loaded together.
#[inline(always)]
fn add_term<const T: usize, const FIRST: bool>(
    acc: &mut Block,
    f: &Block,
    columns: &Columns,
    folded: &Folded,
) {
    for (acc_row, f_row) in acc.iter_mut().zip(f.iter()) {
        let [f0, f1, f2] = *f_row;
        for (j, sum) in acc_row.iter_mut().enumerate() {
            let [x0, x1, x2] = input_column(columns, folded, T, j);
            let first = if FIRST { x0 * f0 } else { *sum + x0 * f0 };
            *sum = first + x1 * f1 + x2 * f2;
        }
    }
}

/// Block row ϑ of `U` in a column block: `Φ_ϑϑ X_ϑ + E_gϑ G` (`Φ_ϑp = Φ_ϑv = 0`, `E_a` has
/// no attitude row).
#[inline(never)]
fn attitude_block(f: &[&Block; 2], columns: &Columns, folded: &Folded) -> Block {
    attitude_sum(f, columns, folded)
}

/// `Φ_ϑϑ X_ϑ + E_gϑ G`, the terms in order.
#[inline(always)]
fn attitude_sum(f: &[&Block; 2], columns: &Columns, folded: &Folded) -> Block {
    let [f_attitude, e_gyro] = *f;
    let mut acc = [[0.0; 3]; 3];
    add_term::<0, true>(&mut acc, f_attitude, columns, folded);
    add_term::<3, false>(&mut acc, e_gyro, columns, folded);
    acc
}

/// `F_Rϑ X_ϑ + F_Rp X_p + F_Rv X_v + E_gR G + E_aR A`, the terms in order.
#[inline(always)]
fn dynamic_sum(f: &FRow, columns: &Columns, folded: &Folded) -> Block {
    let [f_attitude, f_position, f_velocity, e_gyro, e_accel] = *f;
    let mut acc = [[0.0; 3]; 3];
    add_term::<0, true>(&mut acc, f_attitude, columns, folded);
    add_term::<1, false>(&mut acc, f_position, columns, folded);
    add_term::<2, false>(&mut acc, f_velocity, columns, folded);
    add_term::<3, false>(&mut acc, e_gyro, columns, folded);
    add_term::<4, false>(&mut acc, e_accel, columns, folded);
    acc
}

/// Block row δp or δv of `U` in a column block: `F_R X` over its five terms.
#[inline(never)]
fn dynamic_block(f: &FRow, columns: &Columns, folded: &Folded) -> Block {
    dynamic_sum(f, columns, folded)
}

/// Writes `value` into `out` (element `(i, j)` into `out[i][column + j]`) and returns its
/// finite check.
#[inline(always)]
fn store(value: &Block, out: &mut Columns, column: usize) -> FiniteCheck {
    let mut check = FiniteCheck::new();
    for (target, row) in out.iter_mut().zip(value) {
        let Some(target) = target.get_mut(column..column + 3) else {
            check.value(f64::NAN);
            continue;
        };
        target.copy_from_slice(row);
    }
    check.block(value);
    check
}

/// [`attitude_block`] written into `out` (three rows of the output, from `column` on), with
/// its finite check.
#[inline(never)]
fn attitude_into(
    f: &[&Block; 2],
    columns: &Columns,
    folded: &Folded,
    out: &mut Columns,
    column: usize,
) -> FiniteCheck {
    store(&attitude_sum(f, columns, folded), out, column)
}

/// [`dynamic_block`] written into `out`, with its finite check.
#[inline(never)]
fn dynamic_into(
    f: &FRow,
    columns: &Columns,
    folded: &Folded,
    out: &mut Columns,
    column: usize,
) -> FiniteCheck {
    store(&dynamic_sum(f, columns, folded), out, column)
}

/// The coefficients of `F` the kernel reads: the attitude rows' `Φ_ϑϑ`, `E_gϑ`, and the δp
/// and δv rows' five blocks.
pub(super) struct KernelRows<'a> {
    attitude: [&'a Block; 2],
    position: FRow<'a>,
    velocity: FRow<'a>,
}

impl StructuredModel {
    /// The blocks of `F` by row for the kernel.
    #[inline(always)]
    pub(super) fn kernel_rows(&self) -> KernelRows<'_> {
        let t = &self.transition;
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        KernelRows {
            attitude: [&t.attitude_attitude, gyro_attitude],
            position: [
                &t.position_attitude,
                &t.position_position,
                &t.position_velocity,
                gyro_position,
                accel_position,
            ],
            velocity: [
                &t.velocity_attitude,
                &t.velocity_position,
                &t.velocity_velocity,
                gyro_velocity,
                accel_velocity,
            ],
        }
    }

    /// The folded calibration rows of a column block (module docs of [`super`]):
    /// `P_bg,j + ω_k P_λg,j` and `P_ba,j + f_k P_λa,j` (as `block::add_scaled_rows`), plus
    /// the border's `M C_jᵀ` when there is one (then added, as the row kernel does). Not
    /// inlined: its result goes straight into the caller's frame (inlined, the compiler
    /// keeps the values in registers across the kernel calls and then copies them).
    #[inline(never)]
    fn fold_inputs(&self, columns: &Columns, border: Option<&[BiasInput; 3]>) -> Folded {
        let (rate, force) = (self.measured_rate_rad_s, self.measured_specific_force_mps2);
        let mut folded = columns.each_ref().map(|column| {
            let at = |index: usize| column.get(index).copied().unwrap_or(f64::NAN);
            let [g0, g1, g2] =
                [0, 1, 2].map(|k| at(BIAS_G + k) + at(SCALE_G + k) * element(rate, k));
            let [a0, a1, a2] =
                [0, 1, 2].map(|k| at(BIAS_A + k) + at(SCALE_A + k) * element(force, k));
            [g0, g1, g2, a0, a1, a2]
        });
        if let Some(border) = border {
            for (values, extra) in folded.iter_mut().zip(border) {
                for (value, x) in values.iter_mut().zip(extra) {
                    *value += x;
                }
            }
        }
        folded
    }

    /// `U`'s dynamic column block at `C` (ϑ, δp or δv): its blocks `(ϑ, C)`, `(δp, C)`,
    /// `(δv, C)`.
    #[inline(always)]
    pub(super) fn dynamic_column_block<const C: usize>(
        &self,
        rows: &KernelRows,
        p: &[[f64; STATE_DIMENSION]; STATE_DIMENSION],
        border: Option<&BorderBiasInputs>,
    ) -> [Block; 3] {
        let Some(columns) = column_block::<C>(p) else {
            return [[[f64::NAN; 3]; 3]; 3];
        };
        let folded = self.fold_inputs(columns, border_block::<C>(border));
        [
            attitude_block(&rows.attitude, columns, &folded),
            dynamic_block(&rows.position, columns, &folded),
            dynamic_block(&rows.velocity, columns, &folded),
        ]
    }

    /// `U`'s calibration column block at `C` written into the lower triangle of `P`
    /// (`dynamic` its columns 0..9, `calibration` its columns 9..24; module docs), with the
    /// finite check of the values written.
    #[inline(always)]
    pub(super) fn calibration_column_block<const C: usize>(
        &self,
        rows: &KernelRows,
        dynamic: &mut [[f64; STATE_DIMENSION]; DYNAMIC_DIMENSION],
        calibration: &[[f64; STATE_DIMENSION]; CALIBRATION_DIMENSION],
        border: Option<&BorderBiasInputs>,
    ) -> FiniteCheck {
        let mut check = FiniteCheck::new();
        let Some(columns) = calibration
            .get(C - DYNAMIC_DIMENSION..C - DYNAMIC_DIMENSION + BLOCK_DIMENSION)
            .and_then(|c| <&Columns>::try_from(c).ok())
        else {
            check.value(f64::NAN);
            return check;
        };
        let folded = self.fold_inputs(columns, border_block::<C>(border));
        let (attitude, rest) = dynamic.split_at_mut(3);
        let (position, velocity) = rest.split_at_mut(3);
        let (Ok(attitude), Ok(position), Ok(velocity)) = (
            <&mut Columns>::try_from(attitude),
            <&mut Columns>::try_from(position),
            <&mut Columns>::try_from(velocity),
        ) else {
            check.value(f64::NAN);
            return check;
        };
        check.merge(attitude_into(&rows.attitude, columns, &folded, attitude, C));
        check.merge(dynamic_into(&rows.position, columns, &folded, position, C));
        check.merge(dynamic_into(&rows.velocity, columns, &folded, velocity, C));
        check
    }
}

/// Element `k` of a row (NaN outside).
#[inline(always)]
fn element(row: Row, k: usize) -> f64 {
    row.get(k).copied().unwrap_or(f64::NAN)
}

/// The three columns at `C` of `P`'s columns.
#[inline(always)]
fn column_block<const C: usize>(p: &[[f64; STATE_DIMENSION]; STATE_DIMENSION]) -> Option<&Columns> {
    p.get(C..C + 3).and_then(|c| <&Columns>::try_from(c).ok())
}

/// The border's `M C_jᵀ` for the column block at `C` (`None` without a border; a NaN block
/// if out of range, which constant `C` never is).
#[inline(always)]
fn border_block<const C: usize>(border: Option<&BorderBiasInputs>) -> Option<&[BiasInput; 3]> {
    const NAN_BLOCK: [BiasInput; 3] = [[f64::NAN; 6]; 3];
    border.map(|b| {
        b.state_columns
            .get(C..C + 3)
            .and_then(|values| <&[BiasInput; 3]>::try_from(values).ok())
            .unwrap_or(&NAN_BLOCK)
    })
}
